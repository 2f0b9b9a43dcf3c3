// The exact orientation predicates: the evaluation behind the filters of
// predicates.hpp, and the public orient3d, orient2d and collinear3d.
//
// Every test of src/exact decides with the signs of orient3d / orient2d,
// which are computed exactly:
//   1. a floating-point filter: the determinant is evaluated in plain double
//      arithmetic and its sign is accepted when |det| exceeds a rigorous bound
//      on the rounding error (derived in predicates.hpp);
//   2. otherwise an exact evaluation with floating-point expansions (sums of
//      non-overlapping doubles; Shewchuk, "Adaptive Precision Floating-Point
//      Arithmetic and Fast Robust Geometric Predicates", 1997: Two-Sum,
//      Two-Product, Fast-Expansion-Sum and Scale-Expansion with zero
//      elimination), after scaling the input by a power of two so that no
//      intermediate value can underflow or overflow;
//   3. if the inputs span too many binades for that scaling (for instance a
//      coordinate of 1e-300 next to one of 1e15), an exact fixed-size
//      big-integer evaluation.
// Nothing here allocates; all buffers are fixed-size stack arrays whose sizes
// follow from the bounds given next to them.
//
// The code assumes IEEE-754 binary64 with round-to-nearest-even, evaluated in
// double precision (SSE2 or AArch64, never x87 extended precision) and no
// -ffast-math. Fused multiply-add contraction of the filters is harmless (it
// only removes roundings); the exact parts use std::fma explicitly when the
// target has a hardware FMA and Dekker's splitting otherwise (targets without
// FMA cannot contract).
#include "exact/predicates.hpp"

#include <cmath>
#include <cstddef>
#include <cstdint>

#include "common/ieee.hpp"
#include "exact/big.hpp"
#include "exact/geometry.hpp"

#if defined(__FMA__) || defined(__ARM_FEATURE_FMA) || defined(__aarch64__)
#define HGCD_GEOM_HAVE_FMA 1
#else
#define HGCD_GEOM_HAVE_FMA 0
#endif

namespace hgcd {
namespace predicates {
namespace {

// ---------------------------------------------------------------------------
// Error-free transformations
// ---------------------------------------------------------------------------

inline void two_sum(double a, double b, double &x, double &y) {
    x = a + b;
    double bv = x - a;
    double av = x - bv;
    double br = b - bv;
    double ar = a - av;
    y = ar + br;
}

inline void two_diff(double a, double b, double &x, double &y) {
    x = a - b;
    double bv = a - x;
    double av = x + bv;
    double br = bv - b;
    double ar = a - av;
    y = ar + br;
}

#if !HGCD_GEOM_HAVE_FMA
inline void split(double a, double &hi, double &lo) {
    // Dekker: a = hi + lo, each with at most 26 significant bits.
    double c = 134217729.0 * a;  // 2^27 + 1
    double big = c - a;
    hi = c - big;
    lo = a - hi;
}
#endif

inline void two_prod(double a, double b, double &x, double &y) {
    x = a * b;
#if HGCD_GEOM_HAVE_FMA
    y = std::fma(a, b, -x);
#else
    double ahi, alo, bhi, blo;
    split(a, ahi, alo);
    split(b, bhi, blo);
    double err1 = x - ahi * bhi;
    double err2 = err1 - alo * bhi;
    double err3 = err2 - ahi * blo;
    y = alo * blo - err3;
#endif
}

// ---------------------------------------------------------------------------
// Expansions: arrays of non-zero, non-overlapping doubles in increasing order
// of magnitude; the value is their exact sum and the sign is the sign of the
// last (largest) component. Length 0 is zero.
// ---------------------------------------------------------------------------

// h = e + f; h has room for elen + flen components.
int expansion_sum(int elen, const double *e, int flen, const double *f,
                  double *h) {
    if (elen == 0) {
        for (int i = 0; i < flen; ++i) h[i] = f[i];
        return flen;
    }
    if (flen == 0) {
        for (int i = 0; i < elen; ++i) h[i] = e[i];
        return elen;
    }
    // Merge the two inputs by increasing magnitude and sweep with Two-Sum,
    // emitting the non-zero round-off terms (Fast-Expansion-Sum with
    // zero elimination).
    int i = 0, j = 0, n = 0;
    double q;
    if (std::fabs(e[0]) < std::fabs(f[0])) {
        q = e[i++];
    } else {
        q = f[j++];
    }
    while (i < elen || j < flen) {
        double g;
        if (j >= flen || (i < elen && std::fabs(e[i]) < std::fabs(f[j]))) {
            g = e[i++];
        } else {
            g = f[j++];
        }
        double s, err;
        two_sum(q, g, s, err);
        if (err != 0) h[n++] = err;
        q = s;
    }
    if (q != 0) h[n++] = q;
    return n;
}

// h = b * e; h has room for 2 * elen components.
int scale_expansion(int elen, const double *e, double b, double *h) {
    if (elen == 0 || b == 0) return 0;
    int n = 0;
    double q, hh;
    two_prod(e[0], b, q, hh);
    if (hh != 0) h[n++] = hh;
    for (int i = 1; i < elen; ++i) {
        double p1, p0, s;
        two_prod(e[i], b, p1, p0);
        two_sum(q, p0, s, hh);
        if (hh != 0) h[n++] = hh;
        two_sum(p1, s, q, hh);
        if (hh != 0) h[n++] = hh;
    }
    if (q != 0) h[n++] = q;
    return n;
}

inline int expansion_sign(int n, const double *e) {
    return n == 0 ? 0 : sgn(e[n - 1]);
}

inline void negate(int n, double *e) {
    for (int i = 0; i < n; ++i) e[i] = -e[i];
}

// Exact difference a - b as an expansion of at most 2 components.
inline int diff_expansion(double a, double b, double *h) {
    double x, y;
    two_diff(a, b, x, y);
    int n = 0;
    if (y != 0) h[n++] = y;
    if (x != 0) h[n++] = x;
    return n;
}

// h = e * f for elen <= 2 or flen <= 2 (all our uses: one factor is always
// a difference of two doubles) and the other of at most 16 components; h has
// room for 2 * elen * flen components (at most 64).
int expansion_mul_small(int elen, const double *e, int flen, const double *f,
                        double *h) {
    if (elen > flen) {  // scale the longer one by the shorter one's parts
        const double *t = e;
        e = f;
        f = t;
        int tn = elen;
        elen = flen;
        flen = tn;
    }
    if (elen == 0) return 0;
    if (elen == 1) return scale_expansion(flen, f, e[0], h);
    double p0[32], p1[32];  // elen == 2, flen <= 16
    int n0 = scale_expansion(flen, f, e[0], p0);
    int n1 = scale_expansion(flen, f, e[1], p1);
    return expansion_sum(n0, p0, n1, p1, h);
}

// The exact orient3d of the big points c[0..2] (a), c[3..5] (b), c[6..8]
// (c), c[9..11] (d) into acc.
void orient3d_big_value(const Big *c, Big &acc) {
    Big ad[3], bd[3], cd[3];
    for (int k = 0; k < 3; ++k) {
        big_add(c[k], c[9 + k], 1, ad[k]);
        big_add(c[3 + k], c[9 + k], 1, bd[k]);
        big_add(c[6 + k], c[9 + k], 1, cd[k]);
    }
    // det = adx (bdy cdz - bdz cdy) + ady (bdz cdx - bdx cdz)
    //     + adz (bdx cdy - bdy cdx)
    Big t1, t2, minor, term, tmp;
    big_zero(acc);
    for (int k = 0; k < 3; ++k) {
        int i1 = (k + 1) % 3, i2 = (k + 2) % 3;
        big_mul(bd[i1], cd[i2], t1);
        big_mul(bd[i2], cd[i1], t2);
        big_add(t1, t2, 1, minor);
        big_mul(ad[k], minor, term);
        big_add(acc, term, 0, tmp);
        acc = tmp;
    }
}

int orient3d_big(const double *x /*12: a b c d*/) {
    Big c[12], acc;
    big_from_doubles(x, 12, c);
    orient3d_big_value(c, acc);
    return big_sign(acc);
}

// |orient3d(t, o)| and |orient3d(t, e)| of two triangles (t1: x[0..8],
// t2: x[9..17]; o: x[18..20], e: x[21..23]) as big integers on one scale.
void crossing_values_big(const double *x, Big *ao, Big *ae, int triangles) {
    Big c[24], pts[12];
    big_from_doubles(x, 24, c);
    for (int k = 0; k < triangles; ++k) {
        for (int i = 0; i < 9; ++i) pts[i] = c[9 * k + i];
        for (int end = 0; end < 2; ++end) {
            for (int i = 0; i < 3; ++i) pts[9 + i] = c[18 + 3 * end + i];
            Big &r = end == 0 ? ao[k] : ae[k];
            orient3d_big_value(pts, r);
            r.neg = 0;
        }
    }
}

void crossing_points(const double *o, const double *e, const double *const *t1, const double *const *t2,
                     double *x) {
    for (int i = 0; i < 3; ++i)
        for (int k = 0; k < 3; ++k) {
            x[3 * i + k] = t1[i][k];
            x[9 + 3 * i + k] = t2[i][k];
        }
    for (int k = 0; k < 3; ++k) {
        x[18 + k] = o[k];
        x[21 + k] = e[k];
    }
}

// An approximation of a big magnitude: value = mant * 2^(32 * shift), mant
// the top three limbs (relative truncation error below 2^-64) rounded to
// double (3 more roundings).
double big_top(const Big &a, int *shift) {
    if (a.n == 0) {
        *shift = 0;
        return 0;
    }
    const int top = a.n - 1;
    double m = double(a.d[top]);
    for (int i = 1; i < 3; ++i) m = m * 4294967296.0 + (top - i >= 0 ? double(a.d[top - i]) : 0.0);
    *shift = top - 2;
    return m;
}

int orient2d_big(const double *x /*6: a b c*/) {
    Big c[6];
    big_from_doubles(x, 6, c);
    Big acx, acy, bcx, bcy, t1, t2, r;
    big_add(c[0], c[4], 1, acx);
    big_add(c[1], c[5], 1, acy);
    big_add(c[2], c[4], 1, bcx);
    big_add(c[3], c[5], 1, bcy);
    big_mul(acx, bcy, t1);
    big_mul(acy, bcx, t2);
    big_add(t1, t2, 1, r);
    return big_sign(r);
}

// ---------------------------------------------------------------------------
// Range handling for the expansion path. The expansion arithmetic is exact as
// long as no product underflows or overflows. If every non-zero input lies in
// [2^-250, 2^251) then: differences are exact 2-component expansions whose
// components are multiples of 2^-302 (the lsb of the smallest input) and
// below 2^252; products of three such numbers (and all partial products and
// Dekker halves) are multiples of 2^-906 > 2^-1074 and below 2^790, so every
// Two-Product is exact. Inputs outside that range are multiplied by a common
// power of two (exact) if their binades span at most 480; otherwise the
// big-integer path decides.
// ---------------------------------------------------------------------------

enum class Range { kDirect, kScaled, kBig, kZero };

Range classify(const double *x, int count, int &scale_exp) {
    double mx = 0, mn = INFINITY;
    for (int i = 0; i < count; ++i) {
        double a = std::fabs(x[i]);
        if (a > mx) mx = a;
        if (a != 0 && a < mn) mn = a;
    }
    if (mx == 0) return Range::kZero;
    if (mx < 0x1p251 && mn >= 0x1p-250) {
        scale_exp = 0;
        return Range::kDirect;
    }
    int emax = std::ilogb(mx), emin = std::ilogb(mn);
    if (emax <= 250 && emin >= -250) {
        scale_exp = 0;
        return Range::kDirect;
    }
    if (emax - emin <= 480) {
        scale_exp = 240 - emax;
        return Range::kScaled;
    }
    return Range::kBig;
}

int orient3d_expansion(const double *x /*12*/) {
    double ad[3][2], bd[3][2], cd[3][2];
    int adn[3], bdn[3], cdn[3];
    for (int k = 0; k < 3; ++k) {
        adn[k] = diff_expansion(x[k], x[9 + k], ad[k]);
        bdn[k] = diff_expansion(x[3 + k], x[9 + k], bd[k]);
        cdn[k] = diff_expansion(x[6 + k], x[9 + k], cd[k]);
    }
    // Sizes: products of two differences <= 8, minors <= 16, terms <= 64,
    // sum of three terms <= 192. When every difference is exact (a single
    // component, the usual case for coplanar data on a grid) the sizes are
    // 2, 4, 8 and 24.
    double term[3][64];
    int tn[3];
    for (int k = 0; k < 3; ++k) {
        int i1 = (k + 1) % 3, i2 = (k + 2) % 3;
        double m1[8], m2[8], minor[16];
        int n1 = expansion_mul_small(bdn[i1], bd[i1], cdn[i2], cd[i2], m1);
        int n2 = expansion_mul_small(bdn[i2], bd[i2], cdn[i1], cd[i1], m2);
        negate(n2, m2);
        int nm = expansion_sum(n1, m1, n2, m2, minor);
        tn[k] = expansion_mul_small(adn[k], ad[k], nm, minor, term[k]);
    }
    double t01[128], all[192];
    int n01 = expansion_sum(tn[0], term[0], tn[1], term[1], t01);
    int n = expansion_sum(n01, t01, tn[2], term[2], all);
    return expansion_sign(n, all);
}

int orient2d_expansion(const double *x /*6*/) {
    double acx[2], acy[2], bcx[2], bcy[2];
    int nacx = diff_expansion(x[0], x[4], acx);
    int nacy = diff_expansion(x[1], x[5], acy);
    int nbcx = diff_expansion(x[2], x[4], bcx);
    int nbcy = diff_expansion(x[3], x[5], bcy);
    double m1[8], m2[8], r[16];
    int n1 = expansion_mul_small(nacx, acx, nbcy, bcy, m1);
    int n2 = expansion_mul_small(nacy, acy, nbcx, bcx, m2);
    negate(n2, m2);
    int n = expansion_sum(n1, m1, n2, m2, r);
    return expansion_sign(n, r);
}

// The sign of a determinant of the count coordinates x, exact: expansions
// when the inputs lie in their safe range or scale into it, big integers
// otherwise (see classify). Scales x in place.
int exact_sign(double *x, int count, int (*expansion)(const double *), int (*big)(const double *)) {
    int se = 0;
    switch (classify(x, count, se)) {
    case Range::kZero:
        return 0;
    case Range::kDirect:
        return expansion(x);
    case Range::kScaled:
        for (int i = 0; i < count; ++i) x[i] = std::ldexp(x[i], se);
        return expansion(x);
    case Range::kBig:
        break;
    }
    return big(x);
}

}  // namespace

HGCD_NOINLINE int orient3d_exact(const double *a, const double *b,
                                 const double *c, const double *d) {
    double x[12];
    for (int k = 0; k < 3; ++k) {
        x[k] = a[k];
        x[3 + k] = b[k];
        x[6 + k] = c[k];
        x[9 + k] = d[k];
    }
    return exact_sign(x, 12, orient3d_expansion, orient3d_big);
}

HGCD_NOINLINE int orient2d_exact(double ax, double ay, double bx, double by,
                                 double cx, double cy) {
    double x[6] = {ax, ay, bx, by, cx, cy};
    return exact_sign(x, 6, orient2d_expansion, orient2d_big);
}

HGCD_NOINLINE int crossing_order_exact(const double *o, const double *e, const double *const *t1,
                                       const double *const *t2) {
    double x[24];
    crossing_points(o, e, t1, t2, x);
    Big ao[2], ae[2], p, q, r;
    crossing_values_big(x, ao, ae, 2);
    big_mul(ao[0], ae[1], p);
    big_mul(ao[1], ae[0], q);
    big_add(p, q, 1, r);
    return big_sign(r);
}

HGCD_NOINLINE double crossing_parameter_exact(const double *o, const double *e, const double *const *t) {
    double x[24];
    crossing_points(o, e, t, t, x);
    Big ao[2], ae[2], s;
    crossing_values_big(x, ao, ae, 1);
    big_add(ao[0], ae[0], 0, s);  // (both magnitudes)
    int sa, ss;
    const double ma = big_top(ao[0], &sa), ms = big_top(s, &ss);
    if (ms == 0) return 0;
    return std::ldexp(ma / ms, 32 * (sa - ss));
}

}  // namespace predicates

int orient3d(const double *a, const double *b, const double *c, const double *d) {
    return predicates::orient3d_filtered(a, b, c, d);
}

int orient2d(const double *a, const double *b, const double *c) {
    return predicates::orient2d_filtered(a[0], a[1], b[0], b[1], c[0], c[1]);
}

bool collinear3d(const double *a, const double *b, const double *c) {
    return predicates::is_collinear(a, b, c);
}

}  // namespace hgcd
