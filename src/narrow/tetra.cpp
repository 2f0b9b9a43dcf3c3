// The tetrahedron path's one-pair test in two-lane vectors (SSE2, NEON; with
// GCC on x86-64 also compiled for AVX), its exact path, and the dispatch to
// the AVX2 kernels (tetra_avx2.cpp, tetra_batch_avx2.cpp).
#include "narrow/tetra.hpp"

#include <array>

#include "common/ieee.hpp"

namespace hgcd {
namespace tet {

namespace {

// The scaled local vertices l = fl(s m), one per lane, shared by the axis
// test and the world transform.
struct TetLocal {
    f64x2 x[2], y[2], z[2];
};

HGCD_TET_INLINE void tet_local(const BodyPose &b, TetLocal &l) {
    const double s = b.scale, *m = b.mesh->tetra_local;
    for (int h = 0; h < 2; ++h) {
        f64x2 mx, my, mz;
        std::memcpy(&mx, m + 2 * h, sizeof mx);
        std::memcpy(&my, m + 4 + 2 * h, sizeof my);
        std::memcpy(&mz, m + 8 + 2 * h, sizeof mz);
        l.x[h] = s * mx;
        l.y[h] = s * my;
        l.z[h] = s * mz;
    }
}

// max_i la_i . da + max_j lb_j . db, da in lane 0 of d, db in lane 1 (each
// dot product evaluated left to right).
HGCD_TET_INLINE double tet_supports(const TetLocal &la, const TetLocal &lb, const f64x2 *d) {
    const f64x2 a0 = lane<0>(d[0]), a1 = lane<0>(d[1]), a2 = lane<0>(d[2]);
    const f64x2 b0 = lane<1>(d[0]), b1 = lane<1>(d[1]), b2 = lane<1>(d[2]);
    const f64x2 pa = vmax((la.x[0] * a0 + la.y[0] * a1) + la.z[0] * a2, (la.x[1] * a0 + la.y[1] * a1) + la.z[1] * a2);
    const f64x2 pb = vmax((lb.x[0] * b0 + lb.y[0] * b1) + lb.z[0] * b2, (lb.x[1] * b0 + lb.y[1] * b1) + lb.z[1] * b2);
    const f64x2 h = vmax(__builtin_shufflevector(pa, pb, 0, 2), __builtin_shufflevector(pa, pb, 1, 3));
    return h[0] + h[1];
}

// World vertices of the body in lane L of r (tet_rotations), l = tet_local(b).
template <int L>
HGCD_TET_INLINE void tet_world(const BodyPose &b, const TetRotations &r, const TetLocal &l, TetWorld &w) {
    const double *c = b.position;
    f64x2 m[9];
    for (int k = 0; k < 9; ++k) m[k] = lane<L>(r.m[k]);
    for (int h = 0; h < 2; ++h) {
        // transform_point's operations in its order, one vertex per lane.
        const f64x2 lx = l.x[h], ly = l.y[h], lz = l.z[h];
        w.x[h] = c[0] + ((m[0] * lx + m[1] * ly) + m[2] * lz);
        w.y[h] = c[1] + ((m[3] * lx + m[4] * ly) + m[5] * lz);
        w.z[h] = c[2] + ((m[6] * lx + m[7] * ly) + m[8] * lz);
    }
    tet_box(w);
}

inline void plane_pair(TetPlanes &p, int h, f64x2 t0x, f64x2 t0y, f64x2 t0z, f64x2 t1x, f64x2 t1y, f64x2 t1z, f64x2 t2x,
                       f64x2 t2y, f64x2 t2z) {
    const f64x2 e1x = t1x - t0x, e1y = t1y - t0y, e1z = t1z - t0z;
    const f64x2 e2x = t2x - t0x, e2y = t2y - t0y, e2z = t2z - t0z;
    const f64x2 a = e1y * e2z, b = e1z * e2y, c = e1z * e2x, d = e1x * e2z, e = e1x * e2y, f = e1y * e2x;
    p.t0x[h] = t0x;
    p.t0y[h] = t0y;
    p.t0z[h] = t0z;
    p.nx[h] = a - b;
    p.ny[h] = c - d;
    p.nz[h] = e - f;
}

// Face planes of w, with the certifying bound (tet_plane_bound of a box
// holding both bodies).
HGCD_TET_INLINE void tet_planes(const TetWorld &w, double bound, TetPlanes &p) {
    p.bound = bound;
    const f64x2 *x = w.x, *y = w.y, *z = w.z;
#define HGCD_SH(v, i, j) __builtin_shufflevector(v[0], v[1], i, j)
    // faces 0 = (1 2 3), 1 = (0 3 2)
    plane_pair(p, 0, HGCD_SH(x, 1, 0), HGCD_SH(y, 1, 0), HGCD_SH(z, 1, 0), x[1], y[1], z[1],
               HGCD_SH(x, 3, 2), HGCD_SH(y, 3, 2), HGCD_SH(z, 3, 2));
    // faces 2 = (0 1 3), 3 = (0 2 1)
    plane_pair(p, 1, HGCD_SH(x, 0, 0), HGCD_SH(y, 0, 0), HGCD_SH(z, 0, 0), HGCD_SH(x, 1, 2),
               HGCD_SH(y, 1, 2), HGCD_SH(z, 1, 2), HGCD_SH(x, 3, 1), HGCD_SH(y, 3, 1),
               HGCD_SH(z, 3, 1));
#undef HGCD_SH
}

// Face F against the four vertices of o (two per vector).
template <int F>
HGCD_TET_INLINE void tet_face(const TetPlanes &p, const TetWorld &o, TetSides &s) {
    constexpr int h = F / 2, l = F % 2;
    const f64x2 t0x = lane<l>(p.t0x[h]), t0y = lane<l>(p.t0y[h]), t0z = lane<l>(p.t0z[h]);
    const f64x2 nx = lane<l>(p.nx[h]), ny = lane<l>(p.ny[h]), nz = lane<l>(p.nz[h]);
    const f64x2 bound = f64x2{} + p.bound, minus = -bound;
    const f64x2 d0 = ((o.x[0] - t0x) * nx + (o.y[0] - t0y) * ny) + (o.z[0] - t0z) * nz;
    const f64x2 d1 = ((o.x[1] - t0x) * nx + (o.y[1] - t0y) * ny) + (o.z[1] - t0z) * nz;
    s.pos[F] = less_bits(d0, minus) | less_bits(d1, minus) << 2;  // d = -orient3d
    s.neg[F] = less_bits(bound, d0) | less_bits(bound, d1) << 2;
}

// Signs of the other body's vertices against the faces of w; true (and the
// signs left incomplete) as soon as a face separates the bodies.
HGCD_TET_INLINE bool tet_sides_separate(const TetWorld &w, const TetPlanes &p, const TetWorld &o, TetSides &s) {
    s.inner = tet_inner_sign(w, p);
    const TetOuter outer(s.inner);
    tet_face<0>(p, o, s);
    if (outer.separates(s, 0)) return true;
    tet_face<1>(p, o, s);
    if (outer.separates(s, 1)) return true;
    tet_face<2>(p, o, s);
    if (outer.separates(s, 2)) return true;
    tet_face<3>(p, o, s);
    return outer.separates(s, 3);
}

inline bool tet_separated(const TetSides &s) {
    return tet_face_separates(s, 0) || tet_face_separates(s, 1) || tet_face_separates(s, 2) ||
           tet_face_separates(s, 3);
}

// Makes every sign of s exact: an undecided one is computed exactly (and
// stays in neither set when it is 0). True if there was one.
inline bool tet_resolve(const double (*t)[3], const double (*o)[3], TetSides &s) {
    bool any = false;
    for (int f = 0; f < 4; ++f) {
        unsigned open = ~(s.pos[f] | s.neg[f]) & 0xF;
        while (open) {
            const int v = __builtin_ctz(open);
            open &= open - 1;
            const int sign = orient3d(t[kFace[f][0]], t[kFace[f][1]], t[kFace[f][2]], o[v]);
            if (sign > 0) s.pos[f] |= 1u << v;
            if (sign < 0) s.neg[f] |= 1u << v;
            any = true;
        }
    }
    return any;
}

inline int sign_of(const TetSides &s, int f, int v) {
    return int((s.pos[f] >> v) & 1) - int((s.neg[f] >> v) & 1);
}

}  // namespace

// (The caller took the decisions on the certified signs already: the same
// ones on exact signs first.)
__attribute__((noinline)) HGCD_TET_CLONES Contact tet_exact_rows(const double (*wa)[3], const double (*wb)[3],
                                                                TetSides &sab, TetSides &sba,
                                                                NarrowScratch &scratch) {
    const bool any_ab = tet_resolve(wa, wb, sab), any_ba = tet_resolve(wb, wa, sba);  // (both resolved)
    if (any_ab || any_ba) {
        if (tet_separated(sab) || tet_separated(sba)) return Contact::None;
        const Verdict va = tet_verdict(sab), vb = tet_verdict(sba);
        if (va == Verdict::Surface || vb == Verdict::Surface) return Contact::Surface;
        if (va == Verdict::Containment || vb == Verdict::Containment) return Contact::Containment;
    }
    // Face pairs (f, g) with one triangle strictly on one side of the other's
    // plane are skipped. kHolds[S]: the faces whose 3 vertices all lie in the
    // vertex set S (face g misses vertex g).
    static constexpr unsigned kHolds[16] = {0, 0, 0, 0, 0, 0, 0, 8, 0, 0, 0, 4, 0, 2, 1, 15};
    const unsigned apart[4] = {kHolds[sba.pos[0]] | kHolds[sba.neg[0]], kHolds[sba.pos[1]] | kHolds[sba.neg[1]],
                               kHolds[sba.pos[2]] | kHolds[sba.neg[2]], kHolds[sba.pos[3]] | kHolds[sba.neg[3]]};
    for (int f = 0; f < 4; ++f) {  // apart[g]: bit f; kHolds[sab.*[f]]: bit g
        unsigned pending = ~(kHolds[sab.pos[f]] | kHolds[sab.neg[f]]) & 0xF;
        const double *p[3] = {wa[kFace[f][0]], wa[kFace[f][1]], wa[kFace[f][2]]};
        while (pending) {
            const int g = __builtin_ctz(pending);
            pending &= pending - 1;
            if ((apart[g] >> f) & 1) continue;
            const double *q[3] = {wb[kFace[g][0]], wb[kFace[g][1]], wb[kFace[g][2]]};
            const int sp[3] = {sign_of(sba, g, kFace[f][0]), sign_of(sba, g, kFace[f][1]),
                               sign_of(sba, g, kFace[f][2])};
            const int sq[3] = {sign_of(sab, f, kFace[g][0]), sign_of(sab, f, kFace[g][1]),
                               sign_of(sab, f, kFace[g][2])};
            ++scratch.triangle_tests;
            if (tri_tri_intersect_signed(p, q, sp, sq)) return Contact::Surface;
        }
    }
    // Surfaces apart: a solid holding the other's surface holds all its
    // vertices strictly inside, which the exact verdicts above would have
    // reported.
    return Contact::None;
}

namespace {

// The edge axis (EdgeAxis) in two-lane vectors, out of line as the AVX2 one
// (inlined, it slowed the whole pair test).
__attribute__((noinline)) HGCD_TET_CLONES bool tet_edges_separate_two_lane(const TetWorld &u, const TetWorld &v,
                                                                    const double *cu, const double *cv,
                                                                    double ex, double ey, double ez) {
    auto dist2 = [](const TetWorld &w, const double *c) {
        std::array<double, 4> d;
        for (int h = 0; h < 2; ++h) {
            const f64x2 dx = w.x[h] - c[0], dy = w.y[h] - c[1], dz = w.z[h] - c[2];
            const f64x2 dd = (dx * dx + dy * dy) + dz * dz;
            d[2 * h] = dd[0];
            d[2 * h + 1] = dd[1];
        }
        return d;
    };
    const EdgeAxis ax(u, v, dist2(u, cv), dist2(v, cu));
    auto project = [&](const TetWorld &w, double &lo, double &hi) {
        f64x2 p[2];
        for (int h = 0; h < 2; ++h)
            p[h] = ((w.x[h] - ax.c[0]) * ax.n[0] + (w.y[h] - ax.c[1]) * ax.n[1]) + (w.z[h] - ax.c[2]) * ax.n[2];
        lo = hmin(p[0], p[1]);
        hi = hmax(p[0], p[1]);
    };
    double amin, amax, bmin, bmax;
    project(u, amin, amax);
    project(v, bmin, bmax);
    return ax.apart(amin, amax, bmin, bmax, ex, ey, ez);
}

struct TwoLaneKernels {
    typedef TetLocal Local;
    static HGCD_TET_INLINE void local(const BodyPose &b, Local &l) { tet_local(b, l); }
    static HGCD_TET_INLINE double supports(const Local &la, const Local &lb, const f64x2 *d) {
        return tet_supports(la, lb, d);
    }
    template <int L>
    static HGCD_TET_INLINE void world(const BodyPose &b, const TetRotations &r, const Local &l, TetWorld &w) {
        tet_world<L>(b, r, l, w);
    }
    static HGCD_TET_INLINE void planes(const TetWorld &w, double bound, TetPlanes &p) {
        tet_planes(w, bound, p);
    }
    static HGCD_TET_INLINE bool sides_separate(const TetWorld &w, const TetPlanes &p, const TetWorld &o,
                                               TetSides &s) {
        return tet_sides_separate(w, p, o, s);
    }
    static HGCD_TET_INLINE bool edges_separate(const TetWorld &u, const TetWorld &v, const double *cu,
                                               const double *cv, double ex, double ey, double ez) {
        return tet_edges_separate_two_lane(u, v, cu, cv, ex, ey, ez);
    }
};

}  // namespace

HGCD_TET_CLONES Contact collide_tetra_two_lane(const BodyPose &a, const BodyPose &b, NarrowScratch &scratch) {
    return collide_tetra_with<TwoLaneKernels>(a, b, scratch);
}

}  // namespace tet

void collide_tetra_batch(const TetraPair *pairs, size_t n, Contact *out, NarrowScratch &scratch) {
#if HGCD_AVX2
    if (use_avx2()) return tet::collide_tetra_batch_avx2(pairs, n, out, scratch);
#endif
    for (size_t k = 0; k < n; ++k) {
        if (k + 8 < n) {  // (the placements of a later pair: see world/detect.cpp)
            __builtin_prefetch(pairs[k + 8].a);
            __builtin_prefetch(pairs[k + 8].b);
        }
        const TetraPair &p = pairs[k];
        out[k] = tet::collide_tetra(pose_of(p.mesh_a, *p.a), pose_of(p.mesh_b, *p.b), scratch);
    }
}

}  // namespace hgcd
