// The tetrahedron path's one-pair test four lanes wide for CPUs with AVX2
// (collide_tetra_avx2), picked at run time (common/cpu.hpp).
#include "common/ieee.hpp"
#include "narrow/tetra.hpp"
#include "narrow/tetra_avx2.hpp"

#if HGCD_AVX2

namespace hgcd {
namespace tet {

namespace {

// The one-pair test's kernels four lanes wide (vpermpd for the face
// shuffles). Each lane does the operations of the two-lane kernels
// (tetra.cpp) in the same order, without FMA: the same bits, the same signs.
// The kernels have no target of their own: they are only ever expanded
// inside collide_tetra_avx2, whose target allows the AVX builtins.

__attribute__((target("avx2"), noinline)) bool tet_edges_separate_avx2(const TetWorld &u, const TetWorld &v,
                                                                      const double *cu, const double *cv,
                                                                      double ex, double ey, double ez) {
    f64x4 ux, uy, uz, vx, vy, vz;
    std::memcpy(&ux, u.x, sizeof ux);
    std::memcpy(&uy, u.y, sizeof uy);
    std::memcpy(&uz, u.z, sizeof uz);
    std::memcpy(&vx, v.x, sizeof vx);
    std::memcpy(&vy, v.y, sizeof vy);
    std::memcpy(&vz, v.z, sizeof vz);
    // (Written out: a lambda would not inherit the AVX2 target.)
    const f64x4 dux = ux - cv[0], duy = uy - cv[1], duz = uz - cv[2];
    const f64x4 dvx = vx - cu[0], dvy = vy - cu[1], dvz = vz - cu[2];
    const f64x4 du = (dux * dux + duy * duy) + duz * duz, dv = (dvx * dvx + dvy * dvy) + dvz * dvz;
    const EdgeAxis ax(u, v, du, dv);
    const f64x4 pu = ((ux - ax.c[0]) * ax.n[0] + (uy - ax.c[1]) * ax.n[1]) + (uz - ax.c[2]) * ax.n[2];
    const f64x4 pv = ((vx - ax.c[0]) * ax.n[0] + (vy - ax.c[1]) * ax.n[1]) + (vz - ax.c[2]) * ax.n[2];
    return ax.apart(hmin_avx2(pu), hmax_avx2(pu), hmin_avx2(pv), hmax_avx2(pv), ex, ey, ez);
}

struct FourLaneKernels {
    static HGCD_TET_INLINE void load(f64x4 &v, const void *p) { std::memcpy(&v, p, sizeof v); }
    static HGCD_TET_INLINE void store(void *p, const f64x4 &v) { std::memcpy(p, &v, sizeof v); }
#define HGCD_SPLAT4(v) (f64x4{(v), (v), (v), (v)})
    static HGCD_TET_INLINE unsigned less(const f64x4 &a, const f64x4 &b) {  // bit i: a[i] < b[i]
        return less_avx2(a, b);
    }
    struct Local {
        f64x4 x, y, z;
    };
    static HGCD_TET_INLINE void local(const BodyPose &b, Local &l) {
        const double s = b.scale, *m = b.mesh->tetra_local;
        f64x4 mx, my, mz;
        load(mx, m);
        load(my, m + 4);
        load(mz, m + 8);
        l.x = s * mx;
        l.y = s * my;
        l.z = s * mz;
    }
    static HGCD_TET_INLINE double supports(const Local &la, const Local &lb, const f64x2 *d) {
        const f64x4 pa = (la.x * d[0][0] + la.y * d[1][0]) + la.z * d[2][0];
        const f64x4 pb = (lb.x * d[0][1] + lb.y * d[1][1]) + lb.z * d[2][1];
        // Lanes (a0 a1 b0 b1) against (a2 a3 b2 b3), then the two halves.
        f64x4 m, h;
        max_avx2(m, __builtin_shufflevector(pa, pb, 0, 1, 4, 5), __builtin_shufflevector(pa, pb, 2, 3, 6, 7));
        max_avx2(h, m, __builtin_shufflevector(m, m, 1, 0, 3, 2));
        return h[0] + h[2];
    }
    template <int L>
    static HGCD_TET_INLINE void world(const BodyPose &b, const TetRotations &rot, const Local &l, TetWorld &w) {
        const double *c = b.position;
        // Splats of lane L in registers: read back from memory as scalars,
        // GCC merges them into 32-byte loads of 16-byte stores (a store
        // forwarding stall).
        f64x4 r[9];
        for (int k = 0; k < 9; ++k) r[k] = __builtin_shufflevector(rot.m[k], rot.m[k], L, L, L, L);
        const f64x4 lx = l.x, ly = l.y, lz = l.z;
        store(w.x, c[0] + ((r[0] * lx + r[1] * ly) + r[2] * lz));
        store(w.y, c[1] + ((r[3] * lx + r[4] * ly) + r[5] * lz));
        store(w.z, c[2] + ((r[6] * lx + r[7] * ly) + r[8] * lz));
        tet_box(w);
    }
    static HGCD_TET_INLINE void planes(const TetWorld &w, double bound, TetPlanes &p) {
        p.bound = bound;
        f64x4 x, y, z;
        load(x, w.x);
        load(y, w.y);
        load(z, w.z);
        // Faces 0..3 = (1 2 3), (0 3 2), (0 1 3), (0 2 1), one per lane.
        const f64x4 t0x = __builtin_shufflevector(x, x, 1, 0, 0, 0), t0y = __builtin_shufflevector(y, y, 1, 0, 0, 0),
                 t0z = __builtin_shufflevector(z, z, 1, 0, 0, 0);
        const f64x4 e1x = __builtin_shufflevector(x, x, 2, 3, 1, 2) - t0x,
                 e1y = __builtin_shufflevector(y, y, 2, 3, 1, 2) - t0y,
                 e1z = __builtin_shufflevector(z, z, 2, 3, 1, 2) - t0z;
        const f64x4 e2x = __builtin_shufflevector(x, x, 3, 2, 3, 1) - t0x,
                 e2y = __builtin_shufflevector(y, y, 3, 2, 3, 1) - t0y,
                 e2z = __builtin_shufflevector(z, z, 3, 2, 3, 1) - t0z;
        const f64x4 a = e1y * e2z, b = e1z * e2y, c = e1z * e2x, d = e1x * e2z, e = e1x * e2y, f = e1y * e2x;
        store(p.t0x, t0x);
        store(p.t0y, t0y);
        store(p.t0z, t0z);
        store(p.nx, a - b);
        store(p.ny, c - d);
        store(p.nz, e - f);
    }
    template <int F>
    static HGCD_TET_INLINE void face(const TetPlanes &p, const f64x4 &x, const f64x4 &y, const f64x4 &z, TetSides &s) {
        constexpr int h = F / 2, l = F % 2;
        const f64x4 tx = HGCD_SPLAT4(p.t0x[h][l]), ty = HGCD_SPLAT4(p.t0y[h][l]), tz = HGCD_SPLAT4(p.t0z[h][l]);
        const f64x4 nx = HGCD_SPLAT4(p.nx[h][l]), ny = HGCD_SPLAT4(p.ny[h][l]), nz = HGCD_SPLAT4(p.nz[h][l]);
        const f64x4 bound = HGCD_SPLAT4(p.bound), minus = -bound;
        const f64x4 d = ((x - tx) * nx + (y - ty) * ny) + (z - tz) * nz;  // -orient3d
        s.pos[F] = less(d, minus);
        s.neg[F] = less(bound, d);
    }
    static HGCD_TET_INLINE bool sides_separate(const TetWorld &w, const TetPlanes &p, const TetWorld &o,
                                               TetSides &s) {
        f64x4 x, y, z, tx, ty, tz, nx, ny, nz;
        const f64x4 bound = HGCD_SPLAT4(p.bound);
        load(x, w.x);
        load(y, w.y);
        load(z, w.z);
        load(tx, p.t0x);
        load(ty, p.t0y);
        load(tz, p.t0z);
        load(nx, p.nx);
        load(ny, p.ny);
        load(nz, p.nz);
        // Face f at its own vertex f: the tetrahedron's sign (tet_inner_sign).
        const f64x4 d = ((x - tx) * nx + (y - ty) * ny) + (z - tz) * nz;
        s.inner = less(d, -bound) ? 1 : less(bound, d) ? -1 : tet_inner_sign(w, p);
        load(x, o.x);
        load(y, o.y);
        load(z, o.z);
        const TetOuter outer(s.inner);
        face<0>(p, x, y, z, s);
        if (outer.separates(s, 0)) return true;
        face<1>(p, x, y, z, s);
        if (outer.separates(s, 1)) return true;
        face<2>(p, x, y, z, s);
        if (outer.separates(s, 2)) return true;
        face<3>(p, x, y, z, s);
        return outer.separates(s, 3);
    }
    static HGCD_TET_INLINE bool edges_separate(const TetWorld &u, const TetWorld &v, const double *cu,
                                               const double *cv, double ex, double ey, double ez) {
        return tet_edges_separate_avx2(u, v, cu, cv, ex, ey, ez);
    }
};

#undef HGCD_SPLAT4

}  // namespace

__attribute__((target("avx2"))) Contact collide_tetra_avx2(const BodyPose &a, const BodyPose &b,
                                                           NarrowScratch &scratch) {
    return collide_tetra_with<FourLaneKernels>(a, b, scratch);
}

}  // namespace tet
}  // namespace hgcd

#endif  // HGCD_AVX2
