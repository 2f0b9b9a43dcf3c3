// The filtered orientation predicates of src/exact, inline so that the tests
// built on them (tri_tri.cpp, point_in_mesh.cpp) decide the common case
// without a call; the exact fallbacks behind the filters are in
// predicates.cpp. Internal to src/exact: callers elsewhere use geometry.hpp.
#pragma once
#include <cmath>

#include "common/ieee.hpp"

#if defined(__GNUC__)
#define HGCD_NOINLINE __attribute__((noinline))
#else
#define HGCD_NOINLINE
#endif

namespace hgcd {
namespace predicates {

// ---------------------------------------------------------------------------
// Filter error bounds
// ---------------------------------------------------------------------------
//
// Let d = 2^-53 (unit roundoff). Without underflow every operation returns
// fl(x op y) = (x op y)(1 + t), |t| <= d.
//
// orient3d, written as det = -(x - a) . ((b - a) x (c - a)) (the same value as
// det[a-x; b-x; c-x]). Each of the six monomials, e.g. (x-a)_x (b-a)_y (c-a)_z,
// goes through at most 7 roundings before the final addition: three
// differences, the inner product, the inner subtraction, the outer product and
// the first of the two additions. The final addition multiplies the whole sum
// by (1 + t_f). So the computed value is D~ = (1 + t_f) S~ with
// |S~ - D| <= g7 * P, g7 = 7d/(1-7d), D the exact determinant and P the
// permanent (sum of |monomials| with exact differences). The permanent is
// computed as P~ = |x-a|.(|(b-a)_y (c-a)_z| + |(b-a)_z (c-a)_y|, ...) from
// the same rounded differences; every monomial of P~ carries at most 8
// roundings, all terms are non-negative, so P <= P~ / (1-d)^8. Hence
//     |D~| > (1+d) g7 P~ / (1-d)^8 = 7d (1 + 16d + O(d^2)) P~
// implies |S~| > g7 P, so sign(D) = sign(S~) = sign(D~). We test
//     |D~| > 8d P~ + slack
// with 8d = 2^-50 (so 8d*P~ is exact), which exceeds 7d(1+20d)/(1-d) P~ and
// thus also absorbs the rounding of the addition of the slack.
//
// Underflow: a product that underflows adds an absolute error <= 2^-1075
// (sums and differences of doubles that land in the subnormal range are
// exact). With |coordinates| <= 2^60 (the contract is 1e15 < 2^50) every such
// error is multiplied by at most 2^62 afterwards, and there are at most 12
// products, so the total absolute error is < 2^-1008. The slack 2^-960 covers
// it with a huge margin.
//
// orient2d, det = (a-c)_x (b-c)_y - (a-c)_y (b-c)_x: each monomial carries 3
// roundings before the final subtraction (two differences, one product), the
// permanent |(a-c)_x (b-c)_y| + |(a-c)_y (b-c)_x| at most 4. So
// |D~| > (1+d) g3 P~/(1-d)^4 = 3d(1 + 8d + O(d^2)) P~ suffices and we test
// |D~| > 4d P~ + slack, 4d = 2^-51.
//
// If the inputs overflow the filter (only possible far outside the 1e15
// contract) D~ or P~ is inf/NaN, the comparison fails and the exact path,
// which rescales, decides.
constexpr double kO3dBound = 0x1p-50;
constexpr double kO2dBound = 0x1p-51;
constexpr double kSlack = 0x1p-960;

inline int sgn(double v) { return (v > 0) - (v < 0); }

// The exact evaluations (predicates.cpp), for inputs the filters cannot
// decide: out of line, so that the filters' callers stay small.
int orient3d_exact(const double *a, const double *b, const double *c, const double *d);
int orient2d_exact(double ax, double ay, double bx, double by, double cx, double cy);
// For crossing.cpp, on big integers: the sign of
// |A1| |E2| - |A2| |E1| with Ai = orient3d(ti, o), Ei = orient3d(ti, e)
// (the order of two crossings along [o, e]), and |A| / (|A| + |E|) of one
// triangle to within a relative 2^-50 (its parameter).
int crossing_order_exact(const double *o, const double *e, const double *const *t1, const double *const *t2);
double crossing_parameter_exact(const double *o, const double *e, const double *const *t);

// Filtered orient2d on explicit coordinates.
inline int orient2d_filtered(double ax, double ay, double bx, double by, double cx,
                             double cy) {
    double acx = ax - cx, acy = ay - cy, bcx = bx - cx, bcy = by - cy;
    double l = acx * bcy, r = acy * bcx;
    double det = l - r;
    double perm = std::fabs(l) + std::fabs(r);
    double bound = kO2dBound * perm + kSlack;
    if (det > bound) return 1;
    if (-det > bound) return -1;
    return orient2d_exact(ax, ay, bx, by, cx, cy);
}

inline int orient3d_filtered(const double *a, const double *b, const double *c,
                             const double *d) {
    double adx = a[0] - d[0], ady = a[1] - d[1], adz = a[2] - d[2];
    double bdx = b[0] - d[0], bdy = b[1] - d[1], bdz = b[2] - d[2];
    double cdx = c[0] - d[0], cdy = c[1] - d[1], cdz = c[2] - d[2];
    double bdxcdy = bdx * cdy, cdxbdy = cdx * bdy;
    double cdxady = cdx * ady, adxcdy = adx * cdy;
    double adxbdy = adx * bdy, bdxady = bdx * ady;
    double det = adz * (bdxcdy - cdxbdy) + bdz * (cdxady - adxcdy) +
                 cdz * (adxbdy - bdxady);
    double perm = (std::fabs(bdxcdy) + std::fabs(cdxbdy)) * std::fabs(adz) +
                  (std::fabs(cdxady) + std::fabs(adxcdy)) * std::fabs(bdz) +
                  (std::fabs(adxbdy) + std::fabs(bdxady)) * std::fabs(cdz);
    // The error analysis above: every monomial carries at
    // most 7 roundings before the final addition, the permanent at most 8.
    double bound = kO3dBound * perm + kSlack;
    if (det > bound) return 1;
    if (-det > bound) return -1;
    return orient3d_exact(a, b, c, d);
}

// ---------------------------------------------------------------------------
// Plane of a triangle, prepared once for several orient3d queries.
// sign(orient3d(t0, t1, t2, x)) = sign(-(x - t0) . n), n = (t1-t0) x (t2-t0).
// ---------------------------------------------------------------------------
struct PlaneFilter {
    const double *t0, *t1, *t2;
    double n[3];   // rounded normal
    double an[3];  // |e1_y e2_z| + |e1_z e2_y|, ...
};

inline void plane_prepare(PlaneFilter &pf, const double *t0, const double *t1,
                          const double *t2) {
    pf.t0 = t0;
    pf.t1 = t1;
    pf.t2 = t2;
    double e1x = t1[0] - t0[0], e1y = t1[1] - t0[1], e1z = t1[2] - t0[2];
    double e2x = t2[0] - t0[0], e2y = t2[1] - t0[1], e2z = t2[2] - t0[2];
    double a = e1y * e2z, b = e1z * e2y;
    double c = e1z * e2x, d = e1x * e2z;
    double e = e1x * e2y, f = e1y * e2x;
    pf.n[0] = a - b;
    pf.n[1] = c - d;
    pf.n[2] = e - f;
    pf.an[0] = std::fabs(a) + std::fabs(b);
    pf.an[1] = std::fabs(c) + std::fabs(d);
    pf.an[2] = std::fabs(e) + std::fabs(f);
}

// Exact sign of orient3d(t0, t1, t2, x) (the filter of plane_sides3).
inline int plane_side(const PlaneFilter &pf, const double *x) {
    double dx = x[0] - pf.t0[0], dy = x[1] - pf.t0[1], dz = x[2] - pf.t0[2];
    double det = -((dx * pf.n[0] + dy * pf.n[1]) + dz * pf.n[2]);
    double perm = (std::fabs(dx) * pf.an[0] + std::fabs(dy) * pf.an[1]) + std::fabs(dz) * pf.an[2];
    double bound = kO3dBound * perm + kSlack;
    if (std::fabs(det) > bound) return sgn(det);
    return orient3d_exact(pf.t0, pf.t1, pf.t2, x);
}

// Exact signs of orient3d(t0, t1, t2, x_i) for three points. The three
// filters are evaluated together with one combined (non-short-circuit)
// certainty test, so the common case has a single well-predicted branch.
inline void plane_sides3(const PlaneFilter &pf, const double *x0,
                         const double *x1, const double *x2, int *s) {
    const double *x[3] = {x0, x1, x2};
    double det[3], bound[3];
    for (int i = 0; i < 3; ++i) {
        double dx = x[i][0] - pf.t0[0], dy = x[i][1] - pf.t0[1],
               dz = x[i][2] - pf.t0[2];
        det[i] = -((dx * pf.n[0] + dy * pf.n[1]) + dz * pf.n[2]);
        double perm = (std::fabs(dx) * pf.an[0] + std::fabs(dy) * pf.an[1]) +
                      std::fabs(dz) * pf.an[2];
        bound[i] = kO3dBound * perm + kSlack;
    }
    bool sure = (std::fabs(det[0]) > bound[0]) &
                (std::fabs(det[1]) > bound[1]) &
                (std::fabs(det[2]) > bound[2]);
    if (sure) {
        s[0] = sgn(det[0]);
        s[1] = sgn(det[1]);
        s[2] = sgn(det[2]);
        return;
    }
    for (int i = 0; i < 3; ++i) {
        s[i] = std::fabs(det[i]) > bound[i]
                   ? sgn(det[i])
                   : orient3d_exact(pf.t0, pf.t1, pf.t2, x[i]);
    }
}

// ---------------------------------------------------------------------------
// 2D helpers on a coordinate-plane projection. Projection k drops axis k and
// keeps axes (k+1)%3, (k+2)%3.
// ---------------------------------------------------------------------------

inline int orient2d_proj(int k, const double *a, const double *b,
                         const double *c) {
    int i = k == 2 ? 0 : k + 1, j = k == 0 ? 2 : k - 1;
    // (i, j) = ((k+1)%3, (k+2)%3)
    return orient2d_filtered(a[i], a[j], b[i], b[j], c[i], c[j]);
}

// x (collinear with a, b in projection k) lies in the closed box of a, b.
inline bool in_box_proj(int k, const double *a, const double *b,
                        const double *x) {
    int i = k == 2 ? 0 : k + 1, j = k == 0 ? 2 : k - 1;
    double lo = a[i] < b[i] ? a[i] : b[i], hi = a[i] < b[i] ? b[i] : a[i];
    if (x[i] < lo || x[i] > hi) return false;
    lo = a[j] < b[j] ? a[j] : b[j];
    hi = a[j] < b[j] ? b[j] : a[j];
    return x[j] >= lo && x[j] <= hi;
}

// x in the closed triangle t (non-degenerate in projection k, orientation o).
inline bool point_in_tri_proj(int k, const double *x, const double *const *t,
                              int o) {
    for (int i = 0; i < 3; ++i) {
        int s = orient2d_proj(k, t[i], t[(i + 1) % 3], x);
        if (s == -o) return false;
    }
    return true;
}

// Projection in which the (non-degenerate) triangle t projects to a
// non-degenerate triangle; returns its orientation there in *o. -1 if t is
// degenerate (collinear) in every projection, i.e. degenerate in 3D.
inline int choose_projection(const double *const *t, int *o) {
    for (int k = 2; k >= 0; --k) {
        int s = orient2d_proj(k, t[0], t[1], t[2]);
        if (s != 0) {
            *o = s;
            return k;
        }
    }
    return -1;
}

inline bool is_collinear(const double *a, const double *b, const double *c) {
    const double *t[3] = {a, b, c};
    int o;
    return choose_projection(t, &o) < 0;
}

// Segment [e0, e1] lying in the plane of the non-degenerate triangle t
// (tri_tri.cpp).
bool coplanar_seg_tri(const double *e0, const double *e1, const double *const *t);

}  // namespace predicates
}  // namespace hgcd
