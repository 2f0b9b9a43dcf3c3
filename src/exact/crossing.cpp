// Where a segment crosses triangles, and in which order, exactly: what the
// ray queries (src/query) decide their closest hits with.
//
// A crossing of the segment [o, e] with a triangle t is transversal: o and e
// are not strictly on one side of t's plane and not both in it, and the one
// point where the segment meets the plane lies in the closed triangle. Its
// parameter along the segment is t = |A| / (|A| + |E|) with A = orient3d(t,
// o), E = orient3d(t, e) (A and E have opposite signs, or one is 0; A - E is
// the determinant of the plane and the segment's direction). Two crossings
// are ordered by the sign of |A1| |E2| - |A2| |E1| (cross-multiplied: both
// denominators are positive), a polynomial of degree 6 in the coordinates:
// a float filter certifies it from the determinants' error bounds, and big
// integers decide what it cannot (predicates.cpp).
#include <cmath>

#include "common/ieee.hpp"
#include "exact/geometry.hpp"
#include "exact/predicates.hpp"

namespace hgcd {

using namespace predicates;

namespace {

// orient3d(a, b, c, d) in double as orient3d_filtered computes it, and a
// bound on its error. predicates.hpp shows the computed value D~ within
// g7 P of the rounded sum S~ with D~ = (1 + t) S~, so |D~ - D| <= u |S~| +
// g7 P <= (8u + O(u^2)) P <= 2^-50 (1 + O(u)) P~ (P <= P~ / (1 - u)^8), plus
// under 2^-1008 for underflow: 2^-49 P~ + 2^-959 bounds it (the rounding of
// the bound's own sum is far inside the factor 2).
inline double o3d_value(const double *a, const double *b, const double *c, const double *d, double *err) {
    const double adx = a[0] - d[0], ady = a[1] - d[1], adz = a[2] - d[2];
    const double bdx = b[0] - d[0], bdy = b[1] - d[1], bdz = b[2] - d[2];
    const double cdx = c[0] - d[0], cdy = c[1] - d[1], cdz = c[2] - d[2];
    const double bdxcdy = bdx * cdy, cdxbdy = cdx * bdy;
    const double cdxady = cdx * ady, adxcdy = adx * cdy;
    const double adxbdy = adx * bdy, bdxady = bdx * ady;
    const double det = adz * (bdxcdy - cdxbdy) + bdz * (cdxady - adxcdy) + cdz * (adxbdy - bdxady);
    const double perm = (std::fabs(bdxcdy) + std::fabs(cdxbdy)) * std::fabs(adz) +
                        (std::fabs(cdxady) + std::fabs(adxcdy)) * std::fabs(bdz) +
                        (std::fabs(adxbdy) + std::fabs(bdxady)) * std::fabs(cdz);
    *err = 0x1p-49 * perm + 0x1p-959;
    return det;
}

inline int certified_sign(double det, double err, const double *a, const double *b, const double *c,
                          const double *d) {
    // (err exceeds the sign filter's bound 2^-50 P~ + 2^-960.)
    if (det > err) return 1;
    if (-det > err) return -1;
    return orient3d_exact(a, b, c, d);
}

constexpr double kU = 0x1p-53;

}  // namespace

bool segment_crosses(const double *o, const double *e, const double *const *v, RayCrossing *c) {
    // A = orient3d(v0, v1, v2, o) = -orient3d(o, v1, v2, v0) (a and d
    // swapped): computed from the differences to v0, so that the error bound
    // grows with the triangle's size times o's distance, not with the cube of
    // that distance (o3d_value's differences to its fourth point): a far
    // origin keeps the filters certain and the parameters narrow.
    double ea, ee;
    const double A = -o3d_value(o, v[1], v[2], v[0], &ea);
    const double E = -o3d_value(e, v[1], v[2], v[0], &ee);
    // Strictly on one side: no crossing (the common case, two filters).
    if ((A > ea && E > ee) || (A < -ea && E < -ee)) return false;
    const int sa = certified_sign(A, ea, v[0], v[1], v[2], o);
    const int se = certified_sign(E, ee, v[0], v[1], v[2], e);
    if (sa == se) return false;  // one side, or both in the plane (also every zero-area triangle)
    const int s0 = orient3d_filtered(o, e, v[0], v[1]);
    const int s1 = orient3d_filtered(o, e, v[1], v[2]);
    const int s2 = orient3d_filtered(o, e, v[2], v[0]);
    // The line is not in the plane, so it meets the closed triangle exactly
    // when the three signs are not mixed (Pluecker: zero on an edge's line).
    if ((s0 > 0 || s1 > 0 || s2 > 0) && (s0 < 0 || s1 < 0 || s2 < 0)) return false;
    c->a = std::fabs(A);
    c->b = std::fabs(E);
    c->ea = ea;
    c->eb = ee;
    c->a_zero = sa == 0;
    c->b_zero = se == 0;
    return true;
}

// t = a / (a + b) is increasing in a and decreasing in b; with a in
// [a~ - ea, a~ + ea] and b likewise (both >= 0 exactly), t lies in
// [a_lo / (a_lo + b_hi), a_hi / (a_hi + b_lo)]; each bound is computed with
// three roundings (relative 4u at most), which the factors absorb.
double crossing_upper(const RayCrossing &c) {
    if (c.a_zero) return 0;
    if (c.b_zero) return 1;
    const double ah = (c.a + c.ea) * (1 + 4 * kU);
    const double bl = std::fmax(c.b - c.eb, 0.0) * (1 - 4 * kU);
    const double t = ah / (ah + bl) * (1 + 4 * kU);
    return std::fmin(t, 1.0);
}

double crossing_lower(const RayCrossing &c) {
    if (c.a_zero) return 0;
    if (c.b_zero) return 1;
    const double al = std::fmax(c.a - c.ea, 0.0) * (1 - 4 * kU);
    const double bh = (c.b + c.eb) * (1 + 4 * kU);
    const double s = al + bh;
    return s > 0 ? al / s * (1 - 4 * kU) : 0.0;
}

double crossing_parameter(const double *o, const double *e, const double *const *v, const RayCrossing &c) {
    if (c.a_zero) return 0;
    if (c.b_zero) return 1;
    const double lo = crossing_lower(c), hi = crossing_upper(c);
    // The filter's value lies in [lo, hi]; when that is narrow enough, it is
    // the answer (relative error below 2^-42 + 2^-52 of lo); otherwise the
    // determinants are computed exactly.
    const double t = c.a / (c.a + c.b);
    if (hi - lo <= 0x1p-42 * lo) return t;
    return crossing_parameter_exact(o, e, v);
}

int compare_crossings(const double *o, const double *e, const double *const *v1, const RayCrossing &c1,
                      const double *const *v2, const RayCrossing &c2) {
    // Exact ends first: t = 0 when A = 0, t = 1 when E = 0.
    if (c1.a_zero || c2.a_zero) return c1.a_zero == c2.a_zero ? 0 : (c1.a_zero ? -1 : 1);
    if (c1.b_zero || c2.b_zero) return c1.b_zero == c2.b_zero ? 0 : (c1.b_zero ? 1 : -1);
    // sign(a1 b2 - a2 b1) by intervals: |x~ y~ - x y| <= ex |y~| + ey |x~| +
    // ex ey for |x - x~| <= ex, |y - y~| <= ey; the products, the bound's
    // own arithmetic and the final difference round by relative u each,
    // absorbed by the factor (1 + 2^-40) and the u |p| terms; 2^-1020 covers
    // products that underflow.
    const double p = c1.a * c2.b, q = c2.a * c1.b;
    const double ep = c1.ea * c2.b + c2.eb * c1.a + c1.ea * c2.eb;
    const double eq = c2.ea * c1.b + c1.eb * c2.a + c2.ea * c1.eb;
    const double bound = ((ep + eq) + 2 * kU * (p + q)) * (1 + 0x1p-40) + 0x1p-1020;
    const double x = p - q;
    if (x > bound) return 1;
    if (-x > bound) return -1;
    return crossing_order_exact(o, e, v1, v2);
}

}  // namespace hgcd
