// The tetrahedron path of the narrow phase (tetra.cpp, tetra_avx2.cpp,
// tetra_batch_avx2.cpp): what its one-pair test and its four-lane and batched
// kernels share. Internal to src/narrow.
#pragma once
#include <algorithm>
#include <cmath>
#include <cstring>
#if defined(__SSE2__)
#include <immintrin.h>
#endif

#include "common/cpu.hpp"
#include "common/simd.hpp"
#include "common/transform.hpp"
#include "exact/geometry.hpp"
#include "narrow/narrow.hpp"

namespace hgcd {
namespace tet {

// Tetra path: both meshes are tetrahedra (Mesh::tetra: 4 vertices, the 4
// distinct vertex triples as triangles), the `tetra` scene's only shape.
//
// For such a mesh the closed solid in any pose is the hull of its 4 rounded
// world vertices: the triangles cover the hull's boundary (or the whole hull
// when the points are coplanar), a ray from a point off the surface crosses
// that boundary an odd number of times exactly when it starts in the open
// interior, and a flat hull has no interior (each of its points is covered by
// two triangles). So the answer depends only on the two point sets, the
// triangles can be taken in a fixed order, and with exact signs
//   - a vertex of B is in A's solid off its surface iff it is strictly on the
//     inner side of all four face planes of A (barycentric signs);
//   - it is outside A's solid if it is strictly on the outer side of one face
//     plane (for a flat A: strictly off its plane).
// Face f of a tetrahedron misses vertex f; its triangle is kFace[f], and with
// these orders orient3d(face f, vertex f) has the sign of -orient3d(v0, v1,
// v2, v3) for every f (each is an odd permutation of 0 1 2 3): one inner sign
// per tetrahedron, 0 when it is flat.
//
// Every sign is exact: a face plane is evaluated at two points per vector
// with the arithmetic and error bound of exact/predicates.hpp's plane_sides3
// (|det| > 2^-50 perm + 2^-960 certifies the sign), except that the
// permanent is replaced by a bound of it, the same for every face of both
// bodies (tet_plane_bound): each factor |fl(x - t0)| is at most the extent
// fl(hi - lo) of the box holding both bodies on its axis (x and t0 lie in
// that box and rounding is monotone), so each of the permanent's six terms is
// at most ex ey ez and their sum at most 6 ex ey ez, which 8 fl(fl(ex ey) ez)
// exceeds past its rounding. (Should fl(ex ey) underflow, this bound and the
// permanent's both round to the floor 2^-960: extents are below 2^52 by the
// coordinate limit of 1e15, so 2^-50 * 8 ex ey ez < 2^-1013 then.) One bound
// for all faces is larger than each face's own (about five times on scene
// tetra) but saves 15 operations a face; it can only leave more signs
// uncertain, and uncertain signs stay undecided until a step needs them,
// then the exact orient3d computes them.
//
// Before any world vertex is computed, a separating axis along the line of
// centres rejects most pairs that are apart (tet_axis_separates), then the
// exact vertex boxes. Decisions, in order, first with the faces of A (the
// larger box) and the vertices of B, then the other way round: a face plane
// of A with all of B strictly on its outer side: no contact. A vertex of B
// strictly inside A and one strictly outside: B's surface (connected,
// containing the edge between them) crosses A's boundary: Surface. All of B
// strictly inside A: Containment (B's hull in A's open interior, surfaces
// apart). Either verdict makes B's faces needless. Anything else (edge crossings,
// touching, undecided filters) makes every sign exact, takes the same
// decisions, then runs the exact triangle test on the face pairs with those
// signs; if no pair meets, there is no contact (a solid holding the other's
// surface would hold all its vertices strictly inside, which the exact
// decisions catch).

// Certifying factors of the filters, one set for every kernel that uses them
// (each argued where the one-pair code first uses it): the floor added for
// underflowed products; the face planes' sign bound (above), the separating
// axis along the line of centres (tet_axis_margin) and the axis across two
// edges (EdgeAxis).
constexpr double kUnderflowFloor = 0x1p-960;
constexpr double kPlaneBound = 0x1p-50, kCentresMargin = 0x1p-48, kEdgeMargin = 0x1p-46;

// The face planes' certifying bound for points in a box of extent (ex, ey,
// ez) that holds both bodies (see above), one for every face.
inline double tet_plane_bound(double ex, double ey, double ez) {
    return kPlaneBound * (8.0 * ((ex * ey) * ez)) + kUnderflowFloor;
}

// The size of a box (lo, hi: 3 values each) that picks which body's faces
// the tetra test tries first: the same sums in the one-pair test and the
// batch, so both try them in the same order. T is double or a vector of
// doubles (an out-parameter: a vector return would change the ABI where no
// AVX target is on).
template <class T>
inline void tet_box_size(T &size, const T *lo, const T *hi) {
    size = ((hi[0] - lo[0]) + (hi[1] - lo[1])) + (hi[2] - lo[2]);
}

// With GCC on x86-64 the two-lane pair test is also compiled for AVX
// (target_clones: the same operations VEX-encoded, without SSE2's register
// copies) and a four-lane version for AVX2 (tetra_avx2.cpp), picked at run
// time; neither uses FMA, so every lane has the same bits. Clang and other
// targets (NEON) use the two-lane kernels as written.
#if HGCD_AVX2
#define HGCD_TET_CLONES __attribute__((target_clones("avx", "default")))
#define HGCD_TET_INLINE inline __attribute__((always_inline))
#else
#define HGCD_TET_CLONES
#define HGCD_TET_INLINE inline
#endif

// Two doubles per vector (f64x2: SSE2 or NEON registers as they are; the lanes
// do IEEE double operations, so every value has the bits of the scalar code).

inline f64x2 vmin(f64x2 a, f64x2 b) {
#if defined(__SSE2__)
    return _mm_min_pd(a, b);
#else
    return a < b ? a : b;
#endif
}
inline f64x2 vmax(f64x2 a, f64x2 b) {
#if defined(__SSE2__)
    return _mm_max_pd(a, b);
#else
    return a > b ? a : b;
#endif
}
// Bit i set when a[i] < b[i].
inline unsigned less_bits(f64x2 a, f64x2 b) {
#if defined(__SSE2__)
    return unsigned(_mm_movemask_pd(_mm_cmplt_pd(a, b)));
#else
    const i64x2 m = a < b;
    return unsigned((m[0] & 1) | (m[1] & 2));
#endif
}
template <int L> inline f64x2 lane(f64x2 a) { return __builtin_shufflevector(a, a, L, L); }

// Face f misses vertex f. The faces go in pairs (0, 1) and (2, 3), one per
// lane, chosen so that each face vertex vector is one shuffle of the vertex
// pairs (0, 1) and (2, 3).
constexpr int kFace[4][3] = {{1, 2, 3}, {0, 3, 2}, {0, 1, 3}, {0, 2, 1}};

struct TetWorld {
    f64x2 x[2], y[2], z[2];  // world vertices: lanes (0, 1) in [0], (2, 3) in [1]
    double lo[3], hi[3];
};

inline double hmin(f64x2 a, f64x2 b) {
    const f64x2 m = vmin(a, b);
    return std::min(m[0], m[1]);
}
inline double hmax(f64x2 a, f64x2 b) {
    const f64x2 m = vmax(a, b);
    return std::max(m[0], m[1]);
}

// The box of w's four vertices (after they are set).
HGCD_TET_INLINE void tet_box(TetWorld &w) {
    w.lo[0] = hmin(w.x[0], w.x[1]);
    w.lo[1] = hmin(w.y[0], w.y[1]);
    w.lo[2] = hmin(w.z[0], w.z[1]);
    w.hi[0] = hmax(w.x[0], w.x[1]);
    w.hi[1] = hmax(w.y[0], w.y[1]);
    w.hi[2] = hmax(w.z[0], w.z[1]);
}

// Both bodies' rotations at once: body a in lane 0, b in lane 1.
struct TetRotations {
    f64x2 m[9];
};

HGCD_TET_INLINE void tet_rotations(const BodyPose &a, const BodyPose &b, TetRotations &r) {
    f64x2 a01, a23, b01, b23;
    std::memcpy(&a01, a.orientation, sizeof a01);
    std::memcpy(&a23, a.orientation + 2, sizeof a23);
    std::memcpy(&b01, b.orientation, sizeof b01);
    std::memcpy(&b23, b.orientation + 2, sizeof b23);
    rotation_entries(__builtin_shufflevector(a01, b01, 0, 2), __builtin_shufflevector(a01, b01, 1, 3),
                     __builtin_shufflevector(a23, b23, 0, 2), __builtin_shufflevector(a23, b23, 1, 3), r.m);
}

struct TetPlanes {  // faces (0, 1) in [0], (2, 3) in [1]
    f64x2 t0x[2], t0y[2], t0z[2], nx[2], ny[2], nz[2];
    double bound;  // certifies every face's signs (tet_plane_bound)
};

// -orient3d(face, point) for the faces of pair h, points per lane.
inline f64x2 plane_eval(const TetPlanes &p, int h, f64x2 px, f64x2 py, f64x2 pz) {
    return ((px - p.t0x[h]) * p.nx[h] + (py - p.t0y[h]) * p.ny[h]) + (pz - p.t0z[h]) * p.nz[h];
}

// Certified signs of the four vertices of one body against the four faces of
// the other: bit v of pos[f] / neg[f] when orient3d(face f, vertex v) is
// surely positive / negative; in neither, undecided.
struct TetSides {
    unsigned pos[4], neg[4];
    int inner;  // sign of orient3d(face f, vertex f) of the faces' own tetrahedron
};

// Sign of orient3d(face f, vertex f), the same for every f: from any
// certified lane, else exactly.
HGCD_TET_INLINE int tet_inner_sign(const TetWorld &w, const TetPlanes &p) {
    const f64x2 bound = f64x2{} + p.bound;
    const f64x2 d0 = plane_eval(p, 0, w.x[0], w.y[0], w.z[0]);  // faces 0, 1 at vertices 0, 1
    if (less_bits(d0, -bound)) return 1;
    if (less_bits(bound, d0)) return -1;
    const f64x2 d1 = plane_eval(p, 1, w.x[1], w.y[1], w.z[1]);  // faces 2, 3 at vertices 2, 3
    if (less_bits(d1, -bound)) return 1;
    if (less_bits(bound, d1)) return -1;
    const double v0[3] = {w.x[0][0], w.y[0][0], w.z[0][0]}, v1[3] = {w.x[0][1], w.y[0][1], w.z[0][1]},
                 v2[3] = {w.x[1][0], w.y[1][0], w.z[1][0]}, v3[3] = {w.x[1][1], w.y[1][1], w.z[1][1]};
    return orient3d(v1, v2, v3, v0);  // face 0 and vertex 0
}

// Face f has every vertex of the other body certainly strictly on its outer
// side (on either side when the tetrahedron is flat: it lies in the plane).
// The outer sets: all four vertices (0xF), or 0x10, which no set equals.
struct TetOuter {
    unsigned pos, neg;
    explicit TetOuter(int inner) : pos(inner <= 0 ? 0xFu : 0x10u), neg(inner >= 0 ? 0xFu : 0x10u) {}
    bool separates(const TetSides &s, int f) const { return (s.pos[f] == pos) | (s.neg[f] == neg); }
};
inline bool tet_face_separates(const TetSides &s, int f) { return TetOuter(s.inner).separates(s, f); }

// What the signs of one body's vertices against the other's faces decide.
enum class Verdict {
    Undecided,
    Containment,  // every vertex strictly inside
    Surface,      // a vertex strictly inside, one strictly outside
};

HGCD_TET_INLINE Verdict tet_verdict(const TetSides &s) {
    if (s.inner == 0) return Verdict::Undecided;
    const unsigned *inner = s.inner > 0 ? s.pos : s.neg, *outer = s.inner > 0 ? s.neg : s.pos;
    const unsigned in = inner[0] & inner[1] & inner[2] & inner[3];
    if (in == 0xF) return Verdict::Containment;
    return in && (outer[0] | outer[1] | outer[2] | outer[3]) ? Verdict::Surface : Verdict::Undecided;
}

// The world vertices of w as rows (x, y, z).
inline void tet_rows(const TetWorld &w, double (*v)[3]) {
    for (int i = 0; i < 4; ++i) {
        v[i][0] = w.x[i / 2][i % 2];
        v[i][1] = w.y[i / 2][i % 2];
        v[i][2] = w.z[i / 2][i % 2];
    }
}

// The exact path (tetra.cpp): everything the certified signs sab (b's
// vertices against a's faces) and sba left open, decided on exact signs,
// then by the exact triangle test on the face pairs whose planes do not
// already keep them apart. wa[i] = (x, y, z) of vertex i.
Contact tet_exact_rows(const double (*wa)[3], const double (*wb)[3], TetSides &sab, TetSides &sba,
                       NarrowScratch &scratch);

inline Contact tet_exact(const TetWorld &ta, const TetWorld &tb, TetSides &sab, TetSides &sba,
                         NarrowScratch &scratch) {
    double wa[4][3], wb[4][3];
    tet_rows(ta, wa);
    tet_rows(tb, wb);
    return tet_exact_rows(wa, wb, sab, sba, scratch);
}

// A separating axis across an edge of each tetrahedron, tried on the pairs
// that no face plane keeps apart and no certified sign decides, before the
// exact path. Two disjoint convex hulls with no separating face plane have
// a separating plane parallel to an edge of each, and the exact path would
// test up to 16 triangle pairs each. Of the 36 edge pairs one is tried: the
// edge joining the two vertices of each tetrahedron nearest the other's
// position (its centre); on scene tetra it finds an axis for most such
// pairs (some pair of the 36 would for all of them). The choice is a guess and any axis proves disjointness, so
// nothing needs to be exact but the final test.
//
// Why that test is certain. On an axis n (any double vector) the
// projections (x - c) . n of the world vertices, c a vertex of u, are
// evaluated within 5 eps S, S = e . |n| and e the extent of the box holding
// both bodies (which bounds |x - c| per coordinate): eps for x - c, gamma_3
// for the dot product. When the computed gap between the two sets of
// projections passes 2^-46 S + 2^-960 (128 eps S, and underflowed
// products), the real projections of the two hulls are strictly apart.
struct EdgeAxis {
    double n[3], c[3];  // the axis, and the vertex of u the projections are taken from
    // du, dv: the squared distances of u's and v's vertices to the other's
    // centre (any 4-lane type indexed by []).
    template <class D>
    EdgeAxis(const TetWorld &u, const TetWorld &v, const D &du, const D &dv) {
        double ux[4], uy[4], uz[4], vx[4], vy[4], vz[4];
        std::memcpy(ux, u.x, sizeof ux);
        std::memcpy(uy, u.y, sizeof uy);
        std::memcpy(uz, u.z, sizeof uz);
        std::memcpy(vx, v.x, sizeof vx);
        std::memcpy(vy, v.y, sizeof vy);
        std::memcpy(vz, v.z, sizeof vz);
        int a0, a1, b0, b1;
        nearest(du, a0, a1);
        nearest(dv, b0, b1);
        const double ax = ux[a1] - ux[a0], ay = uy[a1] - uy[a0], az = uz[a1] - uz[a0];
        const double bx = vx[b1] - vx[b0], by = vy[b1] - vy[b0], bz = vz[b1] - vz[b0];
        n[0] = ay * bz - az * by;
        n[1] = az * bx - ax * bz;
        n[2] = ax * by - ay * bx;
        c[0] = ux[a0];
        c[1] = uy[a0];
        c[2] = uz[a0];
    }
    // The two smallest of d[0..3] (selects, not branches).
    template <class D>
    static void nearest(const D &d, int &k0, int &k1) {
        int a = d[1] < d[0] ? 1 : 0, b = 1 - a;
        for (int i = 2; i < 4; ++i) {
            const bool below_a = d[i] < d[a], below_b = d[i] < d[b];
            b = below_a ? a : below_b ? i : b;
            a = below_a ? i : a;
        }
        k0 = a;
        k1 = b;
    }
    // u's projections in [amin, amax], v's in [bmin, bmax]: certainly apart?
    bool apart(double amin, double amax, double bmin, double bmax, double ex, double ey, double ez) const {
        const double margin =
            kEdgeMargin * ((ex * std::fabs(n[0]) + ey * std::fabs(n[1])) + ez * std::fabs(n[2])) + kUnderflowFloor;
        return (bmin - amax > margin) | (amin - bmax > margin);
    }
};

// Separating axis along the line of centres (the bodies' positions), tested
// before any world vertex is computed: on scene tetra it rejects about half
// of the broad phase's box candidates (the exact vertex boxes after it almost
// none: the broad phase's boxes are the same, rounded outward to float). Any
// axis u proves the hulls of two point sets disjoint when their projections
// on it are strictly apart, so u = fl(c_b - c_a) need not be exact, and
// touching sets are never rejected.
// The projection of a world vertex w = fl(c + fl(R l)) (tet_world) is u.c +
// l.(R^T u), exactly for R as rounded, plus its rounding: at most eps |c|.|u| +
// 4 eps |l|.(|R|^T |u|) (eps = 2^-53; this bound and those below to first order
// in eps, which the slack covers). Here d = fl(R^T u) and h = max_i fl(l_i . d)
// miss max_i l_i.(R^T u) by at most 2 gamma_3 |l|.(|R|^T |u|), and
// (c_b - c_a).u is fl(u.u) within 5 eps u.u. Accepted quaternions are unit
// within 1e-6 (hgcd.h), so |R_kj| <= 1 + 3e-6 < 2 and |l|.(|R|^T |u|) <
// 2 s reach |u|_1; with the rounding of u.u - (h_a + h_b) itself every error
// stays below
//   6 eps u.u + eps (|c_a| + |c_b|).|u| + 24 eps (s_a reach_a + s_b reach_b) |u|_1,
// which tet_axis_margin (2^-48 = 32 eps, reach terms doubled) covers more
// than twice. Underflowed products add less than 2^-1000 (|l|, |u| < 2^52).
HGCD_TET_INLINE double tet_axis_margin(const BodyPose &a, const BodyPose &b, const double *u, double uu) {
    const double *ca = a.position, *cb = b.position;
    const double au[3] = {std::fabs(u[0]), std::fabs(u[1]), std::fabs(u[2])};
    const double reach = 2 * (a.scale * a.mesh->tetra_reach + b.scale * b.mesh->tetra_reach);
    const double cu = ((std::fabs(ca[0]) + std::fabs(cb[0]) + reach) * au[0] +
                       (std::fabs(ca[1]) + std::fabs(cb[1]) + reach) * au[1]) +
                      (std::fabs(ca[2]) + std::fabs(cb[2]) + reach) * au[2];
    return kCentresMargin * (uu + cu) + kUnderflowFloor;
}

// The projections of a reach u.c_a + h_a, those of b go down to u.c_b - h_b,
// with h_a = max_i la_i . (R_a^T u) and h_b = max_j lb_j . (-R_b^T u).
template <class K>
HGCD_TET_INLINE bool tet_axis_separates(const BodyPose &a, const BodyPose &b, const TetRotations &r,
                                        const typename K::Local &la, const typename K::Local &lb) {
    const double *ca = a.position, *cb = b.position;
    const double u[3] = {cb[0] - ca[0], cb[1] - ca[1], cb[2] - ca[2]};
    f64x2 d[3];  // R_a^T u in lane 0, -R_b^T u in lane 1
    for (int j = 0; j < 3; ++j) d[j] = f64x2{1, -1} * ((r.m[j] * u[0] + r.m[3 + j] * u[1]) + r.m[6 + j] * u[2]);
    const double uu = (u[0] * u[0] + u[1] * u[1]) + u[2] * u[2];
    const double gap = uu - K::supports(la, lb, d);
    return gap > 0 && gap > tet_axis_margin(a, b, u, uu);  // the margin only when it can matter
}

// The pair test over a set of kernels K (local, supports, world, planes,
// sides_separate, edges_separate).
template <class K>
HGCD_TET_INLINE Contact collide_tetra_with(const BodyPose &a, const BodyPose &b, NarrowScratch &scratch) {
    // One rotation and one set of scaled vertices per body, for the axis
    // test and the world vertices alike.
    TetRotations r;
    tet_rotations(a, b, r);
    typename K::Local la, lb;
    K::local(a, la);
    K::local(b, lb);
    if (tet_axis_separates<K>(a, b, r, la, lb)) return Contact::None;
    TetWorld ta, tb;
    K::template world<0>(a, r, la, ta);
    K::template world<1>(b, r, lb, tb);
    // Exact prefilter: the solids lie inside these boxes. (Behind the broad
    // phase's boxes it only catches pairs within a float step of touching;
    // the boxes are needed below anyway.)
    if (ta.hi[0] < tb.lo[0] || tb.hi[0] < ta.lo[0] || ta.hi[1] < tb.lo[1] || tb.hi[1] < ta.lo[1] ||
        ta.hi[2] < tb.lo[2] || tb.hi[2] < ta.lo[2])
        return Contact::None;
    ++scratch.exact_tests;
    // Extent of a box holding both bodies (bounds |fl(x - t0)| for the filters).
    const double ex = std::max(ta.hi[0], tb.hi[0]) - std::min(ta.lo[0], tb.lo[0]);
    const double ey = std::max(ta.hi[1], tb.hi[1]) - std::min(ta.lo[1], tb.lo[1]);
    const double ez = std::max(ta.hi[2], tb.hi[2]) - std::min(ta.lo[2], tb.lo[2]);
    // The larger body's faces first: they separate more often (on scene
    // tetra, 19% fewer pairs need the second body's faces).
    const TetWorld *u = &ta, *v = &tb;
    const double *cu = a.position, *cv = b.position;
    double size_a, size_b;
    tet_box_size(size_a, ta.lo, ta.hi);
    tet_box_size(size_b, tb.lo, tb.hi);
    const double bound = tet_plane_bound(ex, ey, ez);
    if (size_b > size_a) {
        std::swap(u, v);
        std::swap(cu, cv);
    }
    TetPlanes pu, pv;
    TetSides suv, svu;  // v's vertices against u's faces, and u's against v's
    K::planes(*u, bound, pu);
    if (K::sides_separate(*u, pu, *v, suv)) return Contact::None;
    // A vertex of v strictly inside u is a common point: no face of v can
    // separate them, and v's verdict cannot differ (v wholly inside u's
    // interior leaves no vertex of u inside v).
    const Verdict vu = tet_verdict(suv);
    if (vu == Verdict::Surface) return Contact::Surface;
    if (vu == Verdict::Containment) return Contact::Containment;
    K::planes(*v, bound, pv);
    if (K::sides_separate(*v, pv, *u, svu)) return Contact::None;
    const Verdict vv = tet_verdict(svu);
    if (vv == Verdict::Surface) return Contact::Surface;
    if (vv == Verdict::Containment) return Contact::Containment;
    if (K::edges_separate(*u, *v, cu, cv, ex, ey, ez)) return Contact::None;
    return tet_exact(*u, *v, suv, svu, scratch);
}

// The one-pair test over each set of kernels (tetra.cpp, tetra_avx2.cpp), the
// batch with AVX2 (tetra_batch_avx2.cpp).
Contact collide_tetra_two_lane(const BodyPose &a, const BodyPose &b, NarrowScratch &scratch);
#if HGCD_AVX2
Contact collide_tetra_avx2(const BodyPose &a, const BodyPose &b, NarrowScratch &scratch);
void collide_tetra_batch_avx2(const TetraPair *pairs, size_t n, Contact *out, NarrowScratch &scratch);
#endif

// collide() of two tetrahedra.
inline Contact collide_tetra(const BodyPose &a, const BodyPose &b, NarrowScratch &scratch) {
#if HGCD_AVX2
    if (use_avx2()) return collide_tetra_avx2(a, b, scratch);
#endif
    return collide_tetra_two_lane(a, b, scratch);
}

}  // namespace tet
}  // namespace hgcd
