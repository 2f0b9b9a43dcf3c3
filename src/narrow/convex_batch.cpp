// The convex path's batch (collide_convex_batch, narrow.hpp): many pairs of
// small convex meshes, the kernel's first step (the separating axis along
// the line of centres, with the projections the later steps use) four pairs
// at a time, one per lane, then the kernel's later steps and the one-pair
// test's (collide_convex_after) on those values for the pairs it leaves.
#include "common/ieee.hpp"
#include "narrow/convex.hpp"

#include <algorithm>
#include <cstring>

#include "common/cpu.hpp"
#include "common/simd.hpp"
#include "narrow/tetra.hpp"

// Every vector function here is inlined into its kernel (no vector crosses
// a call boundary), as in convex_kernel.cpp.
#pragma GCC diagnostic ignored "-Wpsabi"

namespace hgcd {

namespace {

#define HGCD_CB_INLINE inline __attribute__((always_inline))

HGCD_CB_INLINE f64x4 lanes(double x0, double x1, double x2, double x3) {
    const double x[4] = {x0, x1, x2, x3};
    f64x4 v;
    std::memcpy(&v, x, sizeof v);
    return v;
}
HGCD_CB_INLINE f64x4 vmax4(f64x4 a, f64x4 b) { return a > b ? a : b; }
HGCD_CB_INLINE f64x4 vabs4(f64x4 a) { return (f64x4)((i64x4)a & (i64x4{} + INT64_MAX)); }

// One side (a or b) of four pairs, a pair per lane.
struct Side {
    const SatData *sat[4];
    f64x4 c[3], m[9], scale;
};

HGCD_CB_INLINE void load_side(const Placement *const *p, const Mesh *const *mesh, Side &s) {
    f64x4 q[4];
    for (int j = 0; j < 3; ++j) s.c[j] = lanes(p[0]->position[j], p[1]->position[j], p[2]->position[j], p[3]->position[j]);
    for (int j = 0; j < 4; ++j)
        q[j] = lanes(p[0]->orientation[j], p[1]->orientation[j], p[2]->orientation[j], p[3]->orientation[j]);
    s.scale = lanes(p[0]->scale, p[1]->scale, p[2]->scale, p[3]->scale);
    rotation_entries(q[0], q[1], q[2], q[3], s.m);  // (rotation_of's operations lane by lane)
    for (int k = 0; k < 4; ++k) s.sat[k] = mesh[k]->sat.get();
}

HGCD_CB_INLINE f64x4 vmin4(f64x4 a, f64x4 b) { return a < b ? a : b; }

// Per lane, the smallest and largest fl(l . d) over the vertices l = fl(s v)
// of the lane's mesh, by convex_kernel.cpp's range_arg operations on each
// vertex (the least and largest of the same values: the same bits), and a
// vertex where the largest is reached, by range_arg's choice among ties: it
// takes vertex i in lane i % 4 and the first of the lane's largest, then the
// first lane; so the vertices are visited here lane by lane, keeping the
// first of the largest. The padded runs repeat vertex 0, so a lane whose
// run is shorter reads vertex 0 past its end (never kept: it came first).
HGCD_CB_INLINE void range4(const Side &s, const f64x4 *d, f64x4 &lo, f64x4 &hi, i64x4 &arg) {
    f64x4 mx = f64x4{} - INFINITY, mn = f64x4{} + INFINITY;
    i64x4 best = i64x4{};
    const SatData *const *m = s.sat;
    const double *x[4], *y[4], *z[4];
    uint32_t padded[4], most = 0;
    for (int k = 0; k < 4; ++k) {
        padded[k] = m[k]->padded;
        most = std::max(most, padded[k]);
        x[k] = m[k]->soa.data();
        y[k] = x[k] + padded[k];
        z[k] = y[k] + padded[k];
    }
    const bool shared = m[1] == m[0] && m[2] == m[0] && m[3] == m[0];
    for (uint32_t lane = 0; lane < SatData::kLanes; ++lane)
        for (uint32_t i = lane; i < most; i += SatData::kLanes) {
            f64x4 vx, vy, vz;
            i64x4 at;
            if (shared) {  // (one shared mesh: the usual case)
                vx = f64x4{} + x[0][i];
                vy = f64x4{} + y[0][i];
                vz = f64x4{} + z[0][i];
                at = i64x4{} + int64_t(i);
            } else {
                const uint32_t j[4] = {i < padded[0] ? i : 0, i < padded[1] ? i : 0, i < padded[2] ? i : 0,
                                       i < padded[3] ? i : 0};
                vx = lanes(x[0][j[0]], x[1][j[1]], x[2][j[2]], x[3][j[3]]);
                vy = lanes(y[0][j[0]], y[1][j[1]], y[2][j[2]], y[3][j[3]]);
                vz = lanes(z[0][j[0]], z[1][j[1]], z[2][j[2]], z[3][j[3]]);
                at = i64x4{int64_t(j[0]), int64_t(j[1]), int64_t(j[2]), int64_t(j[3])};
            }
            const f64x4 p = ((s.scale * vx) * d[0] + (s.scale * vy) * d[1]) + (s.scale * vz) * d[2];
            best = p > mx ? at : best;
            mx = vmax4(mx, p);
            mn = vmin4(mn, p);
        }
    lo = mn;
    hi = mx;
    arg = best;
}

// The line of centres of four pairs, convex_decide's first step lane by
// lane in its operations (so the same values; the axis and its margin are
// argued there and in tetra.hpp). Returns the lanes it separates.
struct Centres4 {
    f64x4 u[3], da[3], ub[3], db[3], alo, ahi, blo, bhi, uu, cmargin;
    i64x4 a_toward, b_toward;
};
HGCD_CB_INLINE unsigned centres4(const Side &A, const Side &B, Centres4 &c) {
    for (int j = 0; j < 3; ++j) c.u[j] = B.c[j] - A.c[j];
    const f64x4 *u = c.u;
    for (int j = 0; j < 3; ++j) {
        c.da[j] = (A.m[j] * u[0] + A.m[3 + j] * u[1]) + A.m[6 + j] * u[2];
        c.ub[j] = (B.m[j] * u[0] + B.m[3 + j] * u[1]) + B.m[6 + j] * u[2];
        c.db[j] = -1.0 * c.ub[j];
    }
    range4(A, c.da, c.alo, c.ahi, c.a_toward);
    range4(B, c.db, c.blo, c.bhi, c.b_toward);
    c.uu = (u[0] * u[0] + u[1] * u[1]) + u[2] * u[2];
    const f64x4 gap = c.uu - (c.ahi + c.bhi);
    const f64x4 la = lanes(A.sat[0]->reach, A.sat[1]->reach, A.sat[2]->reach, A.sat[3]->reach);
    const f64x4 lb = lanes(B.sat[0]->reach, B.sat[1]->reach, B.sat[2]->reach, B.sat[3]->reach);
    const f64x4 reach = 2.0 * (A.scale * la + B.scale * lb);
    const f64x4 cu = ((vabs4(A.c[0]) + vabs4(B.c[0]) + reach) * vabs4(u[0]) +
                      (vabs4(A.c[1]) + vabs4(B.c[1]) + reach) * vabs4(u[1])) +
                     (vabs4(A.c[2]) + vabs4(B.c[2]) + reach) * vabs4(u[2]);
    c.cmargin = tet::kCentresMargin * (c.uu + cu) + tet::kUnderflowFloor;
    const i64x4 apart = (gap > 0.0) & (gap > c.cmargin);
    return unsigned(apart[0] & 1) | unsigned(apart[1] & 1) << 1 | unsigned(apart[2] & 1) << 2 |
           unsigned(apart[3] & 1) << 3;
}

// Lane k of the four pairs' values, as the one-pair kernel's.
HGCD_CB_INLINE void lane_of(const Side &A, const Side &B, const Centres4 &c, int k, ConvexCentres &out) {
    for (int j = 0; j < 9; ++j) {
        out.ra.m[j] = A.m[j][k];
        out.rb.m[j] = B.m[j][k];
    }
    for (int j = 0; j < 3; ++j) {
        out.u[j] = c.u[j][k];
        out.da[j] = c.da[j][k];
        out.ub[j] = c.ub[j][k];
        out.db[j] = c.db[j][k];
    }
    out.alo = c.alo[k];
    out.ahi = c.ahi[k];
    out.blo = c.blo[k];
    out.bhi = c.bhi[k];
    out.uu = c.uu[k];
    out.cmargin = c.cmargin[k];
    out.a_toward = uint32_t(c.a_toward[k]);
    out.b_toward = uint32_t(c.b_toward[k]);
}

HGCD_CB_INLINE void batch(const ConvexPair *pairs, size_t n, Contact *out, NarrowScratch &scratch) {
    for (size_t k = 0; k < n; k += 4) {
        if (k + 20 <= n)  // (the placements four groups ahead, as the tetra batch)
            for (size_t l = 0; l < 4; ++l) {
                __builtin_prefetch(pairs[k + 16 + l].a);
                __builtin_prefetch(pairs[k + 16 + l].b);
            }
        const Placement *pa[4], *pb[4];
        const Mesh *ma[4], *mb[4];
        for (size_t l = 0; l < 4; ++l) {
            const ConvexPair &p = pairs[k + l < n ? k + l : k];
            pa[l] = p.a;
            pb[l] = p.b;
            ma[l] = p.mesh_a;
            mb[l] = p.mesh_b;
        }
        Side A, B;
        load_side(pa, ma, A);
        load_side(pb, mb, B);
        Centres4 c;
        const unsigned apart = centres4(A, B, c);
        for (size_t l = 0; l < 4 && k + l < n; ++l) {
            out[k + l] = Contact::None;
            if (apart >> l & 1) continue;
            ConvexCentres one;
            lane_of(A, B, c, int(l), one);
            const BodyPose a = pose_of(ma[l], *pa[l]), b = pose_of(mb[l], *pb[l]);
            out[k + l] = collide_convex_after(a, b, scratch, nullptr, convex_decide_past_centres(a, b, one));
        }
    }
}

#if HGCD_AVX2
__attribute__((target("avx2"))) void batch_avx2(const ConvexPair *pairs, size_t n, Contact *out,
                                                NarrowScratch &scratch) {
    batch(pairs, n, out, scratch);
}
#endif
void batch_base(const ConvexPair *pairs, size_t n, Contact *out, NarrowScratch &scratch) {
    batch(pairs, n, out, scratch);
}

}  // namespace

void collide_convex_batch(const ConvexPair *pairs, size_t n, Contact *out, NarrowScratch &scratch) {
#if HGCD_AVX2
    if (use_avx2()) return batch_avx2(pairs, n, out, scratch);
#endif
    batch_base(pairs, n, out, scratch);
}

}  // namespace hgcd
