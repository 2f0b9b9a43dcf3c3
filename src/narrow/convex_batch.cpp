// The convex path's batch (collide_convex_batch, narrow.hpp): many pairs of
// small convex meshes, the separating axis along the line of centres four
// pairs at a time (one per lane), then the one-pair test (collide_convex)
// for the pairs it leaves.
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

// Per lane, the largest fl(l . d) over the vertices l = fl(s v) of the
// lane's mesh, by convex_kernel.cpp's range operations on each vertex (the
// largest of the same values: the same bits). The padded runs repeat vertex
// 0, so a lane whose run is shorter reads vertex 0 past its end.
HGCD_CB_INLINE f64x4 reach_along(const Side &s, const f64x4 *d) {
    f64x4 mx = f64x4{} - INFINITY;
    const SatData *const *m = s.sat;
    if (m[1] == m[0] && m[2] == m[0] && m[3] == m[0]) {  // (one shared mesh: the usual case)
        const double *x = m[0]->soa.data(), *y = x + m[0]->padded, *z = y + m[0]->padded;
        for (uint32_t i = 0; i < m[0]->padded; ++i) {
            const f64x4 p = ((s.scale * x[i]) * d[0] + (s.scale * y[i]) * d[1]) + (s.scale * z[i]) * d[2];
            mx = vmax4(mx, p);
        }
        return mx;
    }
    const double *x[4], *y[4], *z[4];
    uint32_t padded[4], most = 0;
    for (int k = 0; k < 4; ++k) {
        padded[k] = m[k]->padded;
        most = std::max(most, padded[k]);
        x[k] = m[k]->soa.data();
        y[k] = x[k] + padded[k];
        z[k] = y[k] + padded[k];
    }
    for (uint32_t i = 0; i < most; ++i) {
        const uint32_t at[4] = {i < padded[0] ? i : 0, i < padded[1] ? i : 0, i < padded[2] ? i : 0,
                                i < padded[3] ? i : 0};
        const f64x4 vx = lanes(x[0][at[0]], x[1][at[1]], x[2][at[2]], x[3][at[3]]);
        const f64x4 vy = lanes(y[0][at[0]], y[1][at[1]], y[2][at[2]], y[3][at[3]]);
        const f64x4 vz = lanes(z[0][at[0]], z[1][at[1]], z[2][at[2]], z[3][at[3]]);
        const f64x4 p = ((s.scale * vx) * d[0] + (s.scale * vy) * d[1]) + (s.scale * vz) * d[2];
        mx = vmax4(mx, p);
    }
    return mx;
}

// The lanes that convex_decide's separating axis along the line of centres
// rejects, by its operations lane by lane (so the same verdicts: the axis
// and its margin are argued there and in tetra.hpp).
HGCD_CB_INLINE unsigned apart_on_centres4(const Side &A, const Side &B) {
    const f64x4 u[3] = {B.c[0] - A.c[0], B.c[1] - A.c[1], B.c[2] - A.c[2]};
    f64x4 da[3], db[3];
    for (int j = 0; j < 3; ++j) {
        da[j] = (A.m[j] * u[0] + A.m[3 + j] * u[1]) + A.m[6 + j] * u[2];
        db[j] = -1.0 * ((B.m[j] * u[0] + B.m[3 + j] * u[1]) + B.m[6 + j] * u[2]);
    }
    const f64x4 ahi = reach_along(A, da), bhi = reach_along(B, db);
    const f64x4 uu = (u[0] * u[0] + u[1] * u[1]) + u[2] * u[2];
    const f64x4 gap = uu - (ahi + bhi);
    const f64x4 la = lanes(A.sat[0]->reach, A.sat[1]->reach, A.sat[2]->reach, A.sat[3]->reach);
    const f64x4 lb = lanes(B.sat[0]->reach, B.sat[1]->reach, B.sat[2]->reach, B.sat[3]->reach);
    const f64x4 reach = 2.0 * (A.scale * la + B.scale * lb);
    const f64x4 cu = ((vabs4(A.c[0]) + vabs4(B.c[0]) + reach) * vabs4(u[0]) +
                      (vabs4(A.c[1]) + vabs4(B.c[1]) + reach) * vabs4(u[1])) +
                     (vabs4(A.c[2]) + vabs4(B.c[2]) + reach) * vabs4(u[2]);
    const f64x4 margin = tet::kCentresMargin * (uu + cu) + tet::kUnderflowFloor;
    const i64x4 apart = (gap > 0.0) & (gap > margin);
    return unsigned(apart[0] & 1) | unsigned(apart[1] & 1) << 1 | unsigned(apart[2] & 1) << 2 |
           unsigned(apart[3] & 1) << 3;
}

HGCD_CB_INLINE void batch(const ConvexPair *pairs, size_t n, Contact *out, NarrowScratch &scratch) {
    constexpr size_t kStage = 256;  // pairs per round of the two stages
    uint32_t left[kStage];
    for (size_t begin = 0; begin < n; begin += kStage) {
        const size_t end = std::min(n, begin + kStage);
        size_t kept = 0;
        for (size_t k = begin; k < end; k += 4) {
            if (k + 20 <= n)  // (the placements four groups ahead, as the tetra batch)
                for (size_t l = 0; l < 4; ++l) {
                    __builtin_prefetch(pairs[k + 16 + l].a);
                    __builtin_prefetch(pairs[k + 16 + l].b);
                }
            const Placement *pa[4], *pb[4];
            const Mesh *ma[4], *mb[4];
            for (size_t l = 0; l < 4; ++l) {
                const ConvexPair &p = pairs[k + l < end ? k + l : k];
                pa[l] = p.a;
                pb[l] = p.b;
                ma[l] = p.mesh_a;
                mb[l] = p.mesh_b;
            }
            Side A, B;
            load_side(pa, ma, A);
            load_side(pb, mb, B);
            const unsigned apart = apart_on_centres4(A, B);
            for (size_t l = 0; l < 4 && k + l < end; ++l) {
                out[k + l] = Contact::None;
                left[kept] = uint32_t(k + l);
                kept += ~apart >> l & 1;
            }
        }
        for (size_t i = 0; i < kept; ++i) {
            const ConvexPair &p = pairs[left[i]];
            out[left[i]] = collide_convex(pose_of(p.mesh_a, *p.a), pose_of(p.mesh_b, *p.b), scratch, nullptr);
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
