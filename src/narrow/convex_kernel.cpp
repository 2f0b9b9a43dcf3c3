// The convex path's first kernel (narrow/convex.hpp): a pair of small convex
// meshes decided from the meshes' vertex runs and planes (SatData) and the
// two poses alone, without world vertices, four vertices per vector.
#include "common/ieee.hpp"
#include "narrow/convex.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>

#include "common/cpu.hpp"
#include "common/simd.hpp"
#include "narrow/convex_inside.hpp"
#include "narrow/convex_vec.hpp"
#include "narrow/tetra.hpp"

// Every vector function here, and in convex_vec.hpp and convex_inside.hpp
// (its helpers and its certificates that a point is inside a body, which
// only this file includes), is inlined into its kernel and lives in an
// anonymous namespace: no vector crosses a call boundary, so GCC's note that
// a 32-byte vector return would change the ABI without AVX does not apply.
#pragma GCC diagnostic ignored "-Wpsabi"

namespace hgcd {

namespace {

// The smallest and largest of fl(s v) . d over the vertices v of mesh d:
// the local vertices l = fl(s v) as transform_point rounds them, projected
// as (lx dx + ly dy) + lz dz. For a symmetric mesh (SatData::half_padded)
// -h and h, h the largest magnitude over the half run: the same values (up
// to the sign of a zero, which no comparison sees).
HGCD_CK_INLINE void range(const SatData &m, double s, const double *d, double &lo, double &hi) {
    const f64x4 dx = splat(d[0]), dy = splat(d[1]), dz = splat(d[2]), sv = splat(s);
    if (m.half_padded) {
        const double *x = m.half_soa(), *y = x + m.half_padded, *z = y + m.half_padded;
        f64x4 mx = splat(0);
        for (uint32_t i = 0; i < m.half_padded; i += SatData::kLanes) {
            const f64x4 p = ((sv * load4(x + i)) * dx + (sv * load4(y + i)) * dy) + (sv * load4(z + i)) * dz;
            mx = vmax4(mx, vabs(p));
        }
        hi = hmax4(mx);
        lo = -hi;
        return;
    }
    const double *x = m.soa(), *y = x + m.padded, *z = y + m.padded;
    f64x4 mx = splat(-INFINITY), mn = splat(INFINITY);
    for (uint32_t i = 0; i < m.padded; i += SatData::kLanes) {
        const f64x4 p = ((sv * load4(x + i)) * dx + (sv * load4(y + i)) * dy) + (sv * load4(z + i)) * dz;
        mx = vmax4(mx, p);
        mn = vmin4(mn, p);
    }
    lo = hmin4(mn);
    hi = hmax4(mx);
}

// range, and a vertex where the largest is reached (for a symmetric mesh
// the half run's vertex of largest magnitude, or its negation when its
// value is negative).
HGCD_CK_INLINE void range_arg(const SatData &m, double s, const double *d, double &lo, double &hi, uint32_t &arg) {
    const f64x4 dx = splat(d[0]), dy = splat(d[1]), dz = splat(d[2]), sv = splat(s), step = splat(SatData::kLanes);
    if (m.half_padded) {
        const double *x = m.half_soa(), *y = x + m.half_padded, *z = y + m.half_padded;
        f64x4 mx = splat(-1), at = {0, 1, 2, 3}, best = at, sign = splat(0);
        for (uint32_t i = 0; i < m.half_padded; i += SatData::kLanes, at += step) {
            const f64x4 p = ((sv * load4(x + i)) * dx + (sv * load4(y + i)) * dy) + (sv * load4(z + i)) * dz;
            const f64x4 a = vabs(p);
            const auto more = a > mx;
            best = more ? at : best;
            sign = more ? p : sign;
            mx = vmax4(mx, a);
        }
        hi = hmax4(mx);
        lo = -hi;
        const int k = mx[0] == hi ? 0 : mx[1] == hi ? 1 : mx[2] == hi ? 2 : 3;
        const double b = k == 0 ? best[0] : k == 1 ? best[1] : k == 2 ? best[2] : best[3];
        const double sg = k == 0 ? sign[0] : k == 1 ? sign[1] : k == 2 ? sign[2] : sign[3];
        arg = m.half_arg()[2 * uint32_t(b) + (sg < 0)];
        return;
    }
    const double *x = m.soa(), *y = x + m.padded, *z = y + m.padded;
    f64x4 mx = splat(-INFINITY), mn = splat(INFINITY), at = {0, 1, 2, 3}, best = at;
    for (uint32_t i = 0; i < m.padded; i += SatData::kLanes, at += step) {
        const f64x4 p = ((sv * load4(x + i)) * dx + (sv * load4(y + i)) * dy) + (sv * load4(z + i)) * dz;
        best = p > mx ? at : best;
        mx = vmax4(mx, p);
        mn = vmin4(mn, p);
    }
    lo = hmin4(mn);
    hi = hmax4(mx);
    // (Lanes by constant index: a variable one sends the vectors through the
    // stack.)
    arg = uint32_t(mx[0] == hi ? best[0] : mx[1] == hi ? best[1] : mx[2] == hi ? best[2] : best[3]);
}

// A separating axis N (any double vector, world frame) for the pair: each
// solid lies in the hull of its rounded world vertices w = fl(c + fl(R l)),
// so it suffices that the projections of the two vertex sets are strictly
// apart. Computed: o = fl(u . N) for u = fl(c_b - c_a), and each body's
// range of fl(l . d) with d = fl(R^T N). With P = |c_a|_inf + |c_b|_inf,
// L = s reach >= |l|_1 (up to a factor 1 + eps) and |R_kj| < 2 (quaternions
// unit within 1e-6), against the exact (w - c_a) . N and (w_b - c_a) . N:
//  - d misses R^T N by 6 eps |N|_1 per axis, so l . d misses l . R^T N by
//    6 eps L |N|_1, and its evaluation rounds by another 6 eps L |N|_1;
//  - w - (c + R l) is at most eps |c|_inf + 8 eps L per axis: eps P |N|_1
//    + 8 eps L |N|_1 on the projection;
//  - o misses (c_b - c_a) . N by 6 eps P |N|_1 (u's rounding, then the dot);
//  - the final sums of o and the two bounds round by 2 eps (P + 2 L_a +
//    2 L_b) |N|_1 and a little.
// All together below 12 eps P + 30 eps (L_a + L_b) times |N|_1 (first
// order), which kAxisMargin = 2^-44 = 512 eps of (P + L_a + L_b) |N|_1
// covers many times over; 2^-960 covers underflowed products (|l|, |N| <
// 2^52, so each is wrong by less than 2^-1074).
constexpr double kAxisMargin = 0x1p-44;

struct PairView {
    const BodyPose &a, &b;
    const SatData &sa, &sb;
    Rotation ra, rb;
    double u[3];
    double scale;   // P + L_a + L_b
    double c[9];    // fl(R_b^T R_a), row-major
    double dq[2];   // |1 - fl(|q|^2)| + 2^-50 of a and b
    // (The rest is filled in by decide before use: zeroing it first cost a
    // `rep stos` per pair.)
    PairView(const BodyPose &pa, const BodyPose &pb, const ConvexCentres &c)
        : a(pa), b(pb), sa(*c.sa), sb(*c.sb), ra(c.ra), rb(c.rb) {}
};

// A face axis n of mesh a (frame a), for the real world axis N = R_a n
// (any real vector separates as well as a double one). Computed: a's range
// fl(s fl(v . n)) from the mesh's face_range, b's range of fl(l . fl(C n))
// with C = fl(R_b^T R_a), and o = fl(da . n) for da = fl(R_a^T u), u =
// fl(c_b - c_a). Against the exact projections of the world vertices on N
// relative to c_a, to first order, with P, L as for apart_on:
//  - a: (w - c_a) . N = l . (R_a^T R_a n) + e . N; R_a^T R_a is within
//    5 |delta_a| + 40 eps of I entrywise (strictly_inside), |N|_1 <= 3 |n|_1,
//    and s fl(v . n) is within 5 eps L |n|_1 of l . n: at most
//    (5 |delta_a| + 70 eps) L_a |n|_1 + 3 eps P |n|_1;
//  - b: o misses (c_b - c_a) . N by 20 eps P |n|_1, fl(C n) misses
//    R_b^T R_a n by 20 eps |n|_1 (C's entries by 12 eps), so with the
//    range's rounding and e_b . N at most 60 eps L_b |n|_1 + 25 eps P |n|_1;
//  - the final sums, 20 eps (P + L_a + L_b) |n|_1.
// kFaceMargin (convex.hpp) = 2^-42 = 2048 eps of (P + L_a + L_b) |n|_1 and
// 8 dq_a L_a |n|_1 (dq >= |delta| + 24 eps) cover that many times over.

HGCD_CK_INLINE void mul3(const double *m, const double *v, double *out) {  // m v
    for (int j = 0; j < 3; ++j) out[j] = (m[3 * j] * v[0] + m[3 * j + 1] * v[1]) + m[3 * j + 2] * v[2];
}
HGCD_CK_INLINE void mul3_t(const double *m, const double *v, double *out) {  // m^T v
    for (int j = 0; j < 3; ++j) out[j] = (m[j] * v[0] + m[3 + j] * v[1]) + m[6 + j] * v[2];
}

// Face axis k of `own` (body index side: 0 a, 1 b) against the other body.
// For b's faces the roles swap: N = R_b n, the other's direction C^T n, o =
// fl(ub . n) with ub = fl(R_b^T u) seen from c_b (so the signs flip), the
// same bound with a and b exchanged.
HGCD_CK_INLINE bool face_apart(const PairView &p, int side, uint32_t k, const double *toward) {
    const SatData &own = side ? p.sb : p.sa, &other = side ? p.sa : p.sb;
    const double s_own = side ? p.b.scale : p.a.scale, s_other = side ? p.a.scale : p.b.scale;
    const double *n = &own.axes()[3 * k];
    double d[3], olo, ohi;
    if (side) mul3_t(p.c, n, d);
    else mul3(p.c, n, d);
    range(other, s_other, d, olo, ohi);
    const double alo = s_own * own.face_range()[2 * k], ahi = s_own * own.face_range()[2 * k + 1];
    const double o = (toward[0] * n[0] + toward[1] * n[1]) + toward[2] * n[2];
    const double margin =
        (kFaceMargin * p.scale + 8 * p.dq[side] * (s_own * own.reach)) * norm1(n) + tet::kUnderflowFloor;
    return ((o + olo) - ahi > margin) | (alo - (o + ohi) > margin);
}

HGCD_CK_INLINE bool apart_on(const PairView &p, const double *N) {
    double da[3], db[3], alo, ahi, blo, bhi;
    rotate_t(p.ra, N, da);
    rotate_t(p.rb, N, db);
    range(p.sa, p.a.scale, da, alo, ahi);
    range(p.sb, p.b.scale, db, blo, bhi);
    const double o = (p.u[0] * N[0] + p.u[1] * N[1]) + p.u[2] * N[2];
    const double margin = kAxisMargin * (p.scale * norm1(N)) + tet::kUnderflowFloor;
    return ((o + blo) - ahi > margin) | (alo - (o + bhi) > margin);
}

// The face axes of m worth trying first: those most nearly along d (the
// direction to the other body in m's frame), at most kFaceAxes of them,
// nearest first.
HGCD_CK_INLINE int pick_faces(const SatData &m, const double *d, uint32_t *out) {
    const uint32_t n = m.faces;
    double score[kFaceAxes];
    int count = 0;
    for (uint32_t k = 0; k < n; ++k) {
        const double *x = &m.axes()[3 * k];
        const double s = std::fabs((x[0] * d[0] + x[1] * d[1]) + x[2] * d[2]);
        if (count == kFaceAxes && s <= score[count - 1]) continue;
        int at = count < kFaceAxes ? count++ : count - 1;
        for (; at > 0 && score[at - 1] < s; --at) {
            score[at] = score[at - 1];
            out[at] = out[at - 1];
        }
        score[at] = s;
        out[at] = k;
    }
    return count;
}

// Separating axes after the line of centres: face normals of both meshes
// (those nearest that line first).
HGCD_CK_INLINE bool face_axes_apart(const PairView &p, const double *da, const double *ub) {
    uint32_t fa[kFaceAxes], fb[kFaceAxes];
    const int na = pick_faces(p.sa, da, fa), nb = pick_faces(p.sb, ub, fb);
    // (ub = R_b^T u points from b's position away from a: b's faces take
    // a's offset along -ub.)
    const double to_a[3] = {-ub[0], -ub[1], -ub[2]};
    for (int k = 0; k < std::max(na, nb); ++k) {
        if (k < na && face_apart(p, 0, fa[k], da)) return true;
        if (k < nb && face_apart(p, 1, fb[k], to_a)) return true;
    }
    return false;
}

// Then edge against edge, when the meshes have at most kEdgeAxisPairs pairs
// of edge directions.
HGCD_CK_INLINE bool edge_axes_apart(const PairView &p) {
    double N[3];
    const uint64_t pairs = uint64_t(p.sa.edges) * p.sb.edges;
    if (pairs == 0 || pairs > kEdgeAxisPairs) return false;
    double ea[kEdgeAxisPairs][3];
    for (uint32_t i = 0; i < p.sa.edges; ++i) rotate(p.ra, &p.sa.axes()[3 * (p.sa.faces + i)], ea[i]);
    for (uint32_t j = 0; j < p.sb.edges; ++j) {
        double eb[3];
        rotate(p.rb, &p.sb.axes()[3 * (p.sb.faces + j)], eb);
        for (uint32_t i = 0; i < p.sa.edges; ++i) {
            const double *x = ea[i];
            N[0] = x[1] * eb[2] - x[2] * eb[1];
            N[1] = x[2] * eb[0] - x[0] * eb[2];
            N[2] = x[0] * eb[1] - x[1] * eb[0];
            if (apart_on(p, N)) return true;
        }
    }
    return false;
}

// Last, for meshes with more than kEdgeAxisPairs pairs of edge directions
// (whose edge axes edge_axes_apart skips), the cross products of the edges at
// each body's vertex reaching furthest towards the other (va, vb): where
// two such bodies nearly touch without a face axis between them, their
// nearest features are mostly edges there. (A local edge vector turned
// into the world frame is as good an axis as any: apart_on's margin covers
// any vector.)
constexpr uint32_t kSupportEdges = 8;
HGCD_CK_INLINE uint32_t support_edges(const SatData &m, const Rotation &r, uint32_t v, double (*out)[3]) {
    double x[3];
    vertex_of(m, v, x);
    uint32_t n = 0;
    for (uint32_t e = m.vertex_edge_start()[v]; e < m.vertex_edge_start()[v + 1] && n < kSupportEdges; ++e, ++n) {
        double y[3];
        vertex_of(m, m.vertex_edges()[e], y);
        const double d[3] = {y[0] - x[0], y[1] - x[1], y[2] - x[2]};
        rotate(r, d, out[n]);
    }
    return n;
}
HGCD_CK_INLINE bool support_edges_apart(const PairView &p, uint32_t va, uint32_t vb) {
    if (uint64_t(p.sa.edges) * p.sb.edges <= kEdgeAxisPairs) return false;  // (all tried already)
    double ea[kSupportEdges][3], eb[kSupportEdges][3];
    const uint32_t na = support_edges(p.sa, p.ra, va, ea), nb = support_edges(p.sb, p.rb, vb, eb);
    for (uint32_t i = 0; i < na; ++i)
        for (uint32_t j = 0; j < nb; ++j) {
            const double *x = ea[i], *y = eb[j];
            const double N[3] = {x[1] * y[2] - x[2] * y[1], x[2] * y[0] - x[0] * y[2], x[0] * y[1] - x[1] * y[0]};
            if (apart_on(p, N)) return true;
        }
    return false;
}

// The line of centres: tet_axis_separates's test and margin (tetra.hpp),
// whose argument holds for any number of vertices (the world vertices are
// fl(c + fl(R l)) with l = fl(s v) here too, and reach bounds |v|_1 of every
// vertex), with the projections' other ends for the poke tests of rest().
// True when it separates.
HGCD_CK_INLINE bool centres(const BodyPose &a, const BodyPose &b, ConvexCentres &c) {
    c.sa = a.mesh->sat.get();
    c.sb = b.mesh->sat.get();
    const SatData &sa = *c.sa, &sb = *c.sb;
    c.ra = rotation_of(a.orientation);
    c.rb = rotation_of(b.orientation);
    const double *ca = a.position, *cb = b.position;
    for (int k = 0; k < 3; ++k) c.u[k] = cb[k] - ca[k];
    rotate_t(c.ra, c.u, c.da);
    rotate_t(c.rb, c.u, c.ub);
    for (int j = 0; j < 3; ++j) c.db[j] = -1.0 * c.ub[j];
    range_arg(sa, a.scale, c.da, c.alo, c.ahi, c.a_toward);
    range_arg(sb, b.scale, c.db, c.blo, c.bhi, c.b_toward);
    c.uu = (c.u[0] * c.u[0] + c.u[1] * c.u[1]) + c.u[2] * c.u[2];
    const double gap = c.uu - (c.ahi + c.bhi);
    const double reach = 2 * (a.scale * sa.reach + b.scale * sb.reach);
    const double cu = ((std::fabs(ca[0]) + std::fabs(cb[0]) + reach) * std::fabs(c.u[0]) +
                       (std::fabs(ca[1]) + std::fabs(cb[1]) + reach) * std::fabs(c.u[1])) +
                      (std::fabs(ca[2]) + std::fabs(cb[2]) + reach) * std::fabs(c.u[2]);
    c.cmargin = tet::kCentresMargin * (c.uu + cu) + tet::kUnderflowFloor;
    return gap > 0 && gap > c.cmargin;
}

// Everything after the line of centres, for a pair it does not separate.
HGCD_CK_INLINE ConvexVerdict rest(const BodyPose &a, const BodyPose &b, const ConvexCentres &c) {
    // Grazing on the line of centres (projections meeting within the
    // margin: faces, edges or corners exactly on each other, as cubes on an
    // integer grid): no certificate here can succeed (each needs a point
    // strictly inside a body, or a gap), so the exact steps take the pair
    // at once (collide_convex_after, flat.cpp).
    if (grazing(c.uu, c.ahi, c.bhi, c.cmargin)) return ConvexVerdict::Open;
    PairView p(a, b, c);
    const SatData &sa = p.sa, &sb = p.sb;
    const double *ca = a.position, *cb = b.position;
    for (int k = 0; k < 3; ++k) p.u[k] = c.u[k];
    const double *da = c.da, *db = c.db, *ub = c.ub;
    const double alo = c.alo, ahi = c.ahi, blo = c.blo, bhi = c.bhi, uu = c.uu, cmargin = c.cmargin;
    const uint32_t a_toward = c.a_toward, b_toward = c.b_toward;
    const double reach_ab = ahi + bhi;
    // On that line, relative to c_a, a's vertices project to [alo, ahi] and
    // b's to [uu - bhi, uu - blo] (b's range is taken along -R_b^T u): the
    // same sums as the gap above with other ends of the ranges, so the same
    // argument and margin make each comparison below certain.
    const bool b_out = (uu - blo) - ahi > cmargin;  // a vertex of b beyond a's far end
    const bool a_out = (uu - bhi) - alo > cmargin;  // a vertex of a before b's near end
    const bool deep = reach_ab > kDeep * uu;
    // The certificates that the surfaces cross: a vertex poking into the
    // other body (cheap, and it fails fast on pairs apart) first, the point
    // inside both first only for deep pairs.
    const bool inside = sa.inside_test && sb.inside_test;
    if (inside && !c.pokes_tried &&
        ((b_out && vertex_poke(a, p.ra, sa, b, p.rb, sb, b_toward)) ||
         (a_out && vertex_poke(b, p.rb, sb, a, p.ra, sa, a_toward))))
        return ConvexVerdict::Surface;
    const bool both_out = inside && a_out && b_out;
    if (deep && both_out && point_inside_both(a, sa, b, sb, p.u, da, db)) return ConvexVerdict::Surface;
    p.scale = ((norm_inf(ca) + norm_inf(cb)) + a.scale * sa.reach) + b.scale * sb.reach;
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j)
            p.c[3 * i + j] = (p.rb.m[i] * p.ra.m[j] + p.rb.m[3 + i] * p.ra.m[3 + j]) + p.rb.m[6 + i] * p.ra.m[6 + j];
    const double *qa = a.orientation, *qb = b.orientation;
    p.dq[0] = std::fabs(1.0 - (((qa[0] * qa[0] + qa[1] * qa[1]) + qa[2] * qa[2]) + qa[3] * qa[3])) + 0x1p-50;
    p.dq[1] = std::fabs(1.0 - (((qb[0] * qb[0] + qb[1] * qb[1]) + qb[2] * qb[2]) + qb[3] * qb[3])) + 0x1p-50;
    // One body's stretch of the line of centres inside the other's: try
    // whether it holds the whole body (before the axes, which cannot
    // separate such a pair).
    if (inside) {
        if (uu - bhi > alo && uu - blo < ahi && holds_all(a, p.ra, sa, b, p.rb, sb)) return ConvexVerdict::AHoldsB;
        if (uu - bhi < alo && uu - blo > ahi && holds_all(b, p.rb, sb, a, p.ra, sa)) return ConvexVerdict::BHoldsA;
    }
    // The edge crossing test (step cross_at): before the axes for deep pairs,
    // between the face and the edge axes for middling ones, last for the
    // others. (One call site: it is inlined.)
    const int cross_at = deep ? 0 : reach_ab > kMiddling * uu ? 1 : 2;
    for (int step = 0; step < 3; ++step) {
        if (step == cross_at && inside &&
            (edge_poke(a, p.ra, sa, b, p.rb, sb, b_out) || edge_poke(b, p.rb, sb, a, p.ra, sa, a_out)))
            return ConvexVerdict::Surface;
        if (step == 0 && !c.faces_tried && face_axes_apart(p, da, ub)) return ConvexVerdict::Apart;
        if (step == 1) {
            if (edge_axes_apart(p)) return ConvexVerdict::Apart;
            if (!deep && both_out && point_inside_both(a, sa, b, sb, p.u, da, db)) return ConvexVerdict::Surface;
            if (support_edges_apart(p, a_toward, b_toward)) return ConvexVerdict::Apart;
        }
    }
    return ConvexVerdict::Open;
}

HGCD_CK_INLINE ConvexVerdict decide(const BodyPose &a, const BodyPose &b) {
    ConvexCentres c;
    if (centres(a, b, c)) return ConvexVerdict::ApartOnCentres;
    return rest(a, b, c);
}

#if HGCD_AVX2
__attribute__((target("avx2"))) ConvexVerdict decide_avx2(const BodyPose &a, const BodyPose &b) {
    return decide(a, b);
}
__attribute__((target("avx2"))) ConvexVerdict rest_avx2(const BodyPose &a, const BodyPose &b,
                                                        const ConvexCentres &c) {
    return rest(a, b, c);
}
#endif
ConvexVerdict decide_base(const BodyPose &a, const BodyPose &b) { return decide(a, b); }
ConvexVerdict rest_base(const BodyPose &a, const BodyPose &b, const ConvexCentres &c) { return rest(a, b, c); }

}  // namespace

ConvexVerdict convex_decide(const BodyPose &a, const BodyPose &b) {
#if HGCD_AVX2
    if (use_avx2()) return decide_avx2(a, b);
#endif
    return decide_base(a, b);
}

ConvexVerdict convex_decide_past_centres(const BodyPose &a, const BodyPose &b, const ConvexCentres &c) {
#if HGCD_AVX2
    if (use_avx2()) return rest_avx2(a, b, c);
#endif
    return rest_base(a, b, c);
}

}  // namespace hgcd
