// The convex path's batch (collide_convex_batch, narrow.hpp): many pairs of
// small convex meshes, the kernel's first step (the separating axis along
// the line of centres, with the projections the later steps use) and, when
// each side of four pairs shares one mesh, its vertex pokes and, for the
// pairs not deep (kDeep), its face axes four pairs at a time, one per lane,
// then the kernel's later steps and the one-pair test's
// (collide_convex_after) on those values for the pairs it leaves.
#include "common/ieee.hpp"
#include "narrow/convex.hpp"

#include <algorithm>
#include <cstring>
#if defined(__SSE2__)
#include <emmintrin.h>
#endif

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
// The lanes of a comparison's result (each all ones or zero) as bits. (By
// the SSE2 sign masks of its halves where there are: baseline x86-64, so
// inlined into the AVX2 kernel too; lane by lane, it cost 12% of that
// kernel's time.)
HGCD_CB_INLINE unsigned mask_of(i64x4 m) {
#if defined(__SSE2__)
    __m128d lo, hi;
    std::memcpy(&lo, &m, sizeof lo);
    std::memcpy(&hi, reinterpret_cast<const char *>(&m) + sizeof lo, sizeof hi);
    return unsigned(_mm_movemask_pd(lo)) | unsigned(_mm_movemask_pd(hi)) << 2;
#else
    return unsigned(m[0] & 1) | unsigned(m[1] & 1) << 1 | unsigned(m[2] & 1) << 2 | unsigned(m[3] & 1) << 3;
#endif
}

// One side (a or b) of four pairs, a pair per lane.
struct Side {
    const SatData *sat[4];
    f64x4 c[3], m[9], scale, n2;  // n2 = fl(|q|^2), as strictly_inside sums it
};

HGCD_CB_INLINE void load_side(const Placement *const *p, const SatData *const *sat, Side &s) {
    f64x4 q[4];
    for (int j = 0; j < 3; ++j) s.c[j] = lanes(p[0]->position[j], p[1]->position[j], p[2]->position[j], p[3]->position[j]);
    for (int j = 0; j < 4; ++j)
        q[j] = lanes(p[0]->orientation[j], p[1]->orientation[j], p[2]->orientation[j], p[3]->orientation[j]);
    s.scale = lanes(p[0]->scale, p[1]->scale, p[2]->scale, p[3]->scale);
    rotation_entries(q[0], q[1], q[2], q[3], s.m);  // (rotation_of's operations lane by lane)
    s.n2 = ((q[0] * q[0] + q[1] * q[1]) + q[2] * q[2]) + q[3] * q[3];
    for (int k = 0; k < 4; ++k) s.sat[k] = sat[k];
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
// For four lanes of one symmetric mesh (SatData::half_padded), the same
// values from its half run: the largest magnitude h, -h (range's argument),
// and range_arg's vertex (the half run's first of the largest magnitude in
// that order, or its negation when its value is negative).
HGCD_CB_INLINE void range4_half(const Side &s, const f64x4 *d, f64x4 &lo, f64x4 &hi, i64x4 &arg) {
    const SatData &m = *s.sat[0];
    const uint32_t n = m.half_padded;
    const double *x = m.half_soa(), *y = x + n, *z = y + n;
    f64x4 mx = f64x4{} - 1.0, sign = f64x4{};
    i64x4 best = i64x4{};
    for (uint32_t lane = 0; lane < SatData::kLanes; ++lane)
        for (uint32_t i = lane; i < n; i += SatData::kLanes) {
            const f64x4 p = ((s.scale * x[i]) * d[0] + (s.scale * y[i]) * d[1]) + (s.scale * z[i]) * d[2];
            const f64x4 a = vabs4(p);
            const i64x4 more = a > mx;
            best = more ? i64x4{} + int64_t(i) : best;
            sign = more ? p : sign;
            mx = vmax4(mx, a);
        }
    hi = mx;
    lo = -1.0 * mx;
    const i64x4 at = 2 * best - (sign < 0.0);  // (a true lane is -1)
    for (int k = 0; k < 4; ++k) arg[k] = m.half_arg()[size_t(at[k])];
}

HGCD_CB_INLINE void range4(const Side &s, const f64x4 *d, f64x4 &lo, f64x4 &hi, i64x4 &arg) {
    f64x4 mx = f64x4{} - INFINITY, mn = f64x4{} + INFINITY;
    i64x4 best = i64x4{};
    const SatData *const *m = s.sat;
    if (m[1] == m[0] && m[2] == m[0] && m[3] == m[0] && m[0]->half_padded) return range4_half(s, d, lo, hi, arg);
    const double *x[4], *y[4], *z[4];
    uint32_t padded[4], most = 0;
    for (int k = 0; k < 4; ++k) {
        padded[k] = m[k]->padded;
        most = std::max(most, padded[k]);
        x[k] = m[k]->soa();
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
// Its values other than the two ranges: u, da, ub, db, uu and the margin.
HGCD_CB_INLINE void lines4(const Side &A, const Side &B, Centres4 &c) {
    for (int j = 0; j < 3; ++j) c.u[j] = B.c[j] - A.c[j];
    const f64x4 *u = c.u;
    for (int j = 0; j < 3; ++j) {
        c.da[j] = (A.m[j] * u[0] + A.m[3 + j] * u[1]) + A.m[6 + j] * u[2];
        c.ub[j] = (B.m[j] * u[0] + B.m[3 + j] * u[1]) + B.m[6 + j] * u[2];
        c.db[j] = -1.0 * c.ub[j];
    }
    c.uu = (u[0] * u[0] + u[1] * u[1]) + u[2] * u[2];
    const f64x4 la = lanes(A.sat[0]->reach, A.sat[1]->reach, A.sat[2]->reach, A.sat[3]->reach);
    const f64x4 lb = lanes(B.sat[0]->reach, B.sat[1]->reach, B.sat[2]->reach, B.sat[3]->reach);
    const f64x4 reach = 2.0 * (A.scale * la + B.scale * lb);
    const f64x4 cu = ((vabs4(A.c[0]) + vabs4(B.c[0]) + reach) * vabs4(u[0]) +
                      (vabs4(A.c[1]) + vabs4(B.c[1]) + reach) * vabs4(u[1])) +
                     (vabs4(A.c[2]) + vabs4(B.c[2]) + reach) * vabs4(u[2]);
    c.cmargin = tet::kCentresMargin * (c.uu + cu) + tet::kUnderflowFloor;
}
HGCD_CB_INLINE unsigned centres4(const Side &A, const Side &B, Centres4 &c) {
    lines4(A, B, c);
    range4(A, c.da, c.alo, c.ahi, c.a_toward);
    range4(B, c.db, c.blo, c.bhi, c.b_toward);
    const f64x4 gap = c.uu - (c.ahi + c.bhi);
    return mask_of((gap > 0.0) & (gap > c.cmargin));
}

HGCD_CB_INLINE f64x4 vnorm1(const f64x4 *v) { return (vabs4(v[0]) + vabs4(v[1])) + vabs4(v[2]); }

// The kernel's vertex poke (convex_kernel.cpp: vertex_poke, vertex_inside,
// strictly_inside) lane by lane, by its operations on the same values, so
// its argument holds in each lane: is vertex v[l] of body `out`'s mesh,
// lane l, strictly inside body `in`? For four pairs whose sides each share
// one SatData (the planes of `in` then splat, and the vertices of `out` are
// read from its runs: the same values as the meshes', which share it only
// when their arrays are the same); the lanes where it is, among the lanes
// `want` (the others may be left undecided: the planes stop when every lane
// wanted is outside one).
HGCD_CB_INLINE unsigned pokes4(const Side &in, const Side &out, const i64x4 &v, unsigned want) {
    const SatData &m = *in.sat[0];
    const uint32_t n = out.sat[0]->padded;
    const double *x = out.sat[0]->soa();
    f64x4 l[3], w[3], D[3], z[3];
    for (int j = 0; j < 3; ++j, x += n)
        l[j] = out.scale * lanes(x[v[0]], x[v[1]], x[v[2]], x[v[3]]);
    for (int j = 0; j < 3; ++j) w[j] = out.c[j] + ((out.m[3 * j] * l[0] + out.m[3 * j + 1] * l[1]) + out.m[3 * j + 2] * l[2]);
    for (int j = 0; j < 3; ++j) D[j] = w[j] - in.c[j];
    for (int j = 0; j < 3; ++j) z[j] = (in.m[j] * D[0] + in.m[3 + j] * D[1]) + in.m[6 + j] * D[2];
    const f64x4 dz = vnorm1(D), z1 = vnorm1(z);
    const f64x4 dq = vabs4(1.0 - in.n2) + 0x1p-50;
    const f64x4 L = in.scale * m.reach;
    const f64x4 cinf = vmax4(vmax4(vabs4(in.c[0]), vabs4(in.c[1])), vabs4(in.c[2]));
    const f64x4 margin =
        0x1p-40 * (((cinf + L) + z1) + dz) + 12 * dq * L + 2 * m.theta * (z1 + L) + tet::kUnderflowFloor;
    const f64x4 t = (in.scale * m.inner) * (1 - 0x1p-48) - margin;
    const f64x4 zz2 = (z[0] * z[0] + z[1] * z[1]) + z[2] * z[2];
    const i64x4 ball = (t > 0.0) & (zz2 * (1 + 0x1p-46) < (t * t) * (1 - 0x1p-48));
    const double *nx = m.planes(), *ny = nx + m.planes_padded, *nz = ny + m.planes_padded,
                 *k = nz + m.planes_padded;
    const unsigned in_ball = mask_of(ball) & want;
    if (in_ball == want) return in_ball;
    const f64x4 lim = -margin;
    i64x4 outside = i64x4{};
    for (uint32_t i = 0; i < m.plane_count; ++i) {
        const f64x4 g = ((nx[i] * z[0] + ny[i] * z[1]) + nz[i] * z[2]) - in.scale * k[i];
        outside |= g >= lim;
        if ((i & 3) == 3 && (mask_of(outside) & want) == want) return in_ball;
    }
    return (in_ball | ~mask_of(outside)) & want;
}

// Per lane, the smallest and largest fl(l . d) over the vertices l =
// fl(s v) of the lanes' one mesh m, by range's operations (convex_kernel.cpp:
// the same values, also from the half run of a symmetric mesh).
HGCD_CB_INLINE void shared_range4(const SatData &m, f64x4 scale, const f64x4 *d, f64x4 &lo, f64x4 &hi) {
    if (m.half_padded) {
        const uint32_t n = m.half_padded;
        const double *x = m.half_soa(), *y = x + n, *z = y + n;
        f64x4 mx = f64x4{};
        for (uint32_t i = 0; i < n; ++i)
            mx = vmax4(mx, vabs4(((scale * x[i]) * d[0] + (scale * y[i]) * d[1]) + (scale * z[i]) * d[2]));
        hi = mx;
        lo = -1.0 * mx;
        return;
    }
    const uint32_t n = m.padded;
    const double *x = m.soa(), *y = x + n, *z = y + n;
    f64x4 mx = f64x4{} - INFINITY, mn = f64x4{} + INFINITY;
    for (uint32_t i = 0; i < n; ++i) {
        const f64x4 p = ((scale * x[i]) * d[0] + (scale * y[i]) * d[1]) + (scale * z[i]) * d[2];
        mx = vmax4(mx, p);
        mn = vmin4(mn, p);
    }
    lo = mn;
    hi = mx;
}

// The kernel's face axes (convex_kernel.cpp: face_axes_apart, face_apart)
// four pairs at a time, for pairs whose sides each share one mesh of at
// most kFaceAxes face axes (all of them tried, a's first): lane by lane
// face_apart's operations on the same values, so its argument and margin
// hold in each lane. The lanes a face axis separates, among `want` (the
// axes stop once all of those are).
HGCD_CB_INLINE unsigned faces4(const Side &A, const Side &B, const Centres4 &c, unsigned want) {
    const SatData &sa = *A.sat[0], &sb = *B.sat[0];
    f64x4 C[9];  // fl(R_b^T R_a), row-major
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) C[3 * i + j] = (B.m[i] * A.m[j] + B.m[3 + i] * A.m[3 + j]) + B.m[6 + i] * A.m[6 + j];
    const f64x4 ninf_a = vmax4(vmax4(vabs4(A.c[0]), vabs4(A.c[1])), vabs4(A.c[2]));
    const f64x4 ninf_b = vmax4(vmax4(vabs4(B.c[0]), vabs4(B.c[1])), vabs4(B.c[2]));
    const f64x4 La = A.scale * sa.reach, Lb = B.scale * sb.reach;
    const f64x4 P = ((ninf_a + ninf_b) + La) + Lb;
    const f64x4 dqa = vabs4(1.0 - A.n2) + 0x1p-50, dqb = vabs4(1.0 - B.n2) + 0x1p-50;
    const f64x4 ma = kFaceMargin * P + 8 * dqa * La, mb = kFaceMargin * P + 8 * dqb * Lb;
    unsigned apart = 0;
    const uint32_t most = std::max(sa.faces, sb.faces);
    for (uint32_t k = 0; k < most && (apart & want) != want; ++k)
        for (int side = 0; side < 2; ++side) {
            const SatData &own = side ? sb : sa, &other = side ? sa : sb;
            if (k >= own.faces) continue;
            const double *n = &own.axes()[3 * k];
            f64x4 d[3], olo, ohi;
            for (int j = 0; j < 3; ++j)
                d[j] = side ? (C[j] * n[0] + C[3 + j] * n[1]) + C[6 + j] * n[2]
                            : (C[3 * j] * n[0] + C[3 * j + 1] * n[1]) + C[3 * j + 2] * n[2];
            const f64x4 s_own = side ? B.scale : A.scale;
            shared_range4(other, side ? A.scale : B.scale, d, olo, ohi);
            const f64x4 alo = s_own * own.face_range()[2 * k], ahi = s_own * own.face_range()[2 * k + 1];
            // (b's faces take a's offset along -ub = db)
            const f64x4 *t = side ? c.db : c.da;
            const f64x4 o = (t[0] * n[0] + t[1] * n[1]) + t[2] * n[2];
            const double n1 = (std::fabs(n[0]) + std::fabs(n[1])) + std::fabs(n[2]);
            const f64x4 margin = (side ? mb : ma) * n1 + tet::kUnderflowFloor;
            apart |= mask_of(((o + olo) - ahi > margin) | (alo - (o + ohi) > margin));
        }
    return apart & want;
}

// Lane k of the four pairs' values, as the one-pair kernel's.
HGCD_CB_INLINE void lane_of(const Side &A, const Side &B, const Centres4 &c, int k, ConvexCentres &out) {
    out.sa = A.sat[k];
    out.sb = B.sat[k];
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

// The steps after the line of centres for the lanes `open` of four pairs
// whose sides each share one SatData with planes (inside_test), pair
// index[l] in lane l: the kernel's first certificates, a vertex of one body
// poking into the other, four pairs at a time; then the face axes, for the
// pairs the kernel would try them on first (not deep: kDeep) when both
// meshes have at most kFaceAxes; then the one-pair steps for the pairs
// left.
HGCD_CB_INLINE void later4(const ConvexPair *pairs, const uint32_t *index, const Side &A, const Side &B,
                           const Centres4 &c, unsigned open, Contact *out, NarrowScratch &scratch) {
    // (a vertex of b beyond a's far end, of a before b's near end: the
    // kernel's b_out and a_out)
    const unsigned bo = mask_of((c.uu - c.blo) - c.ahi > c.cmargin);
    const unsigned ao = mask_of((c.uu - c.bhi) - c.alo > c.cmargin);
    unsigned surface = 0, faces = 0, face_apart = 0;
    // (Grazing lanes go to the exact steps: rest, the kernel's, says why.)
    const f64x4 gap = c.uu - (c.ahi + c.bhi);  // (grazing, in four lanes)
    const unsigned try_lanes = open & ~mask_of((gap <= c.cmargin) & (gap >= -c.cmargin));
    if (try_lanes & bo) surface = pokes4(A, B, c.b_toward, try_lanes & bo);
    if (try_lanes & ~surface & ao) surface |= pokes4(B, A, c.a_toward, try_lanes & ~surface & ao);
    if (A.sat[0]->faces <= uint32_t(kFaceAxes) && B.sat[0]->faces <= uint32_t(kFaceAxes)) {
        faces = try_lanes & ~surface & ~mask_of(c.ahi + c.bhi > kDeep * c.uu);
        if (faces) face_apart = faces4(A, B, c, faces);
    }
    // (What collide_convex_after does for those two verdicts without a
    // witness, in place: a count and the verdict.)
    scratch.exact_tests += unsigned(__builtin_popcount((surface | face_apart) & open));
    for (int l = 0; l < 4; ++l) {
        if (!(open >> l & 1)) continue;
        Contact &o = out[index[l]];
        if (surface >> l & 1) {
            o = Contact::Surface;
        } else if (face_apart >> l & 1) {
            o = Contact::None;
        } else {
            const ConvexPair &p = pairs[index[l]];
            const BodyPose a = pose_of(p.mesh_a, *p.a), b = pose_of(p.mesh_b, *p.b);
            ConvexCentres one;
            lane_of(A, B, c, l, one);
            one.pokes_tried = true;
            one.faces_tried = faces >> l & 1;
            o = collide_convex_after(a, b, scratch, nullptr, convex_decide_past_centres(a, b, one));
        }
    }
}

// Open pairs of groups whose sides do not each share one SatData (mixed
// worlds: a group holds pairs of several combinations of meshes), queued by
// combination until four fill later4's lanes: a pair's index and the values
// of its line of centres that cost a pass over the vertices; the others,
// cheap, are computed again from the poses by lines4, the same operations on
// the same values, so the same bits.
struct Queue {
    const SatData *sa = nullptr, *sb = nullptr;
    uint32_t count = 0;
    uint32_t index[4];
    double alo[4], ahi[4], blo[4], bhi[4];
    int64_t a_toward[4], b_toward[4];
};
// (Enough for worlds of a few convex shapes; pairs of other combinations
// take the one-pair steps.)
constexpr int kQueues = 4;

HGCD_CB_INLINE void run_queue(const ConvexPair *pairs, Queue &q, Contact *out, NarrowScratch &scratch) {
    const Placement *pa[4], *pb[4];
    const SatData *ma[4], *mb[4];
    double v[4][4];
    int64_t t[2][4];
    for (uint32_t l = 0; l < 4; ++l) {
        const uint32_t k = l < q.count ? l : 0;  // (lanes past count repeat lane 0)
        const ConvexPair &p = pairs[q.index[k]];
        pa[l] = p.a;
        pb[l] = p.b;
        ma[l] = p.sat_a;
        mb[l] = p.sat_b;
        v[0][l] = q.alo[k];
        v[1][l] = q.ahi[k];
        v[2][l] = q.blo[k];
        v[3][l] = q.bhi[k];
        t[0][l] = q.a_toward[k];
        t[1][l] = q.b_toward[k];
    }
    Side A, B;
    load_side(pa, ma, A);
    load_side(pb, mb, B);
    Centres4 c;
    lines4(A, B, c);
    std::memcpy(&c.alo, v[0], sizeof c.alo);
    std::memcpy(&c.ahi, v[1], sizeof c.ahi);
    std::memcpy(&c.blo, v[2], sizeof c.blo);
    std::memcpy(&c.bhi, v[3], sizeof c.bhi);
    std::memcpy(&c.a_toward, t[0], sizeof c.a_toward);
    std::memcpy(&c.b_toward, t[1], sizeof c.b_toward);
    later4(pairs, q.index, A, B, c, (1u << q.count) - 1, out, scratch);
    q.count = 0;
}

// Lane l of four pairs (pair `index`) into the queue of its combination of
// meshes (taking a free queue for a new one); false when it has none.
HGCD_CB_INLINE bool enqueue(const ConvexPair *pairs, Queue *queues, const Side &A, const Side &B,
                            const Centres4 &c, int l, uint32_t index, Contact *out, NarrowScratch &scratch) {
    const SatData *sa = A.sat[l], *sb = B.sat[l];
    if (!sa->inside_test || !sb->inside_test) return false;
    for (int k = 0; k < kQueues; ++k) {
        Queue &q = queues[k];
        if (q.sa != sa || q.sb != sb) {
            if (q.sa) continue;
            q.sa = sa;
            q.sb = sb;
        }
        const uint32_t i = q.count++;
        q.index[i] = index;
        q.alo[i] = c.alo[l];
        q.ahi[i] = c.ahi[l];
        q.blo[i] = c.blo[l];
        q.bhi[i] = c.bhi[l];
        q.a_toward[i] = c.a_toward[l];
        q.b_toward[i] = c.b_toward[l];
        if (q.count == 4) run_queue(pairs, q, out, scratch);
        return true;
    }
    return false;
}

// Bodies with meshes of their own (a mesh or a shape per body): their
// convex data lie anywhere in memory. So they are asked for in two stages
// ahead of the group at k: the headers eight groups ahead, the rest of the
// block the kernel reads (SatData::hot_bytes, read from the header) four
// groups ahead.
HGCD_CB_INLINE void prefetch_meshes(const ConvexPair *pairs, size_t n, size_t k) {
    if (k + 36 <= n)
        for (size_t l = 32; l < 36; ++l) {
            __builtin_prefetch(pairs[k + l].sat_a);
            __builtin_prefetch(pairs[k + l].sat_b);
        }
    if (k + 20 <= n)
        for (size_t l = 16; l < 20; ++l)
            for (int side = 0; side < 2; ++side) {
                const SatData *d = side ? pairs[k + l].sat_b : pairs[k + l].sat_a;
                const char *at = reinterpret_cast<const char *>(d);
                for (size_t b = 64; b < d->hot_bytes; b += 64) __builtin_prefetch(at + b);
            }
}

HGCD_CB_INLINE void batch(const ConvexPair *pairs, size_t n, Contact *out, NarrowScratch &scratch) {
    Queue queues[kQueues];
    // (Meshes of their own: their pairs' meshes differ. Only speed depends
    // on this guess.)
    const bool spread = n > 1 && (pairs[0].sat_a != pairs[n - 1].sat_a || pairs[0].sat_b != pairs[n - 1].sat_b ||
                                  pairs[0].sat_a != pairs[n / 2].sat_b);
    for (size_t k = 0; k < n; k += 4) {
        if (k + 20 <= n)  // (the placements four groups ahead, as the tetra batch)
            for (size_t l = 0; l < 4; ++l) {
                __builtin_prefetch(pairs[k + 16 + l].a);
                __builtin_prefetch(pairs[k + 16 + l].b);
            }
        if (spread) prefetch_meshes(pairs, n, k);
        const Placement *pa[4], *pb[4];
        const SatData *ma[4], *mb[4];
        for (size_t l = 0; l < 4; ++l) {
            const ConvexPair &p = pairs[k + l < n ? k + l : k];
            pa[l] = p.a;
            pb[l] = p.b;
            ma[l] = p.sat_a;
            mb[l] = p.sat_b;
        }
        Side A, B;
        load_side(pa, ma, A);
        load_side(pb, mb, B);
        Centres4 c;
        const unsigned apart = centres4(A, B, c);
        const unsigned open = ~apart & ((1u << std::min<size_t>(4, n - k)) - 1);
        for (size_t l = 0; l < 4 && k + l < n; ++l) out[k + l] = Contact::None;
        if (!open) continue;
        const SatData *const *sa = A.sat, *const *sb = B.sat;
        if (sa[1] == sa[0] && sa[2] == sa[0] && sa[3] == sa[0] && sb[1] == sb[0] && sb[2] == sb[0] &&
            sb[3] == sb[0] && sa[0]->inside_test && sb[0]->inside_test) {
            // (each side shares one mesh: the usual case, the lanes in place)
            const uint32_t index[4] = {uint32_t(k), uint32_t(k + 1), uint32_t(k + 2), uint32_t(k + 3)};
            later4(pairs, index, A, B, c, open, out, scratch);
            continue;
        }
        for (int l = 0; l < 4; ++l) {
            if (!(open >> l & 1) || enqueue(pairs, queues, A, B, c, l, uint32_t(k + l), out, scratch)) continue;
            const ConvexPair &p = pairs[k + l];
            const BodyPose a = pose_of(p.mesh_a, *p.a), b = pose_of(p.mesh_b, *p.b);
            ConvexCentres one;
            lane_of(A, B, c, l, one);
            out[k + l] = collide_convex_after(a, b, scratch, nullptr, convex_decide_past_centres(a, b, one));
        }
    }
    for (Queue &q : queues)
        if (q.count) run_queue(pairs, q, out, scratch);
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
