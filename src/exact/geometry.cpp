// Exact geometric predicates and the exact narrow-phase tests built on them.
//
// Everything here decides with the signs of orient3d / orient2d, which are
// computed exactly:
//   1. a floating-point filter: the determinant is evaluated in plain double
//      arithmetic and its sign is accepted when |det| exceeds a rigorous bound
//      on the rounding error (derived below);
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
#include "exact/geometry.hpp"
#include "common/ieee.hpp"

#include <cmath>
#include <cstdint>
#include <cstddef>

#if defined(__FMA__) || defined(__ARM_FEATURE_FMA) || defined(__aarch64__)
#define HGCD_GEOM_HAVE_FMA 1
#else
#define HGCD_GEOM_HAVE_FMA 0
#endif

namespace hgcd {
namespace {

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

// ---------------------------------------------------------------------------
// Exact big-integer fallback for inputs spanning more binades than the
// expansion path can scale into its safe range. Sign-magnitude, 32-bit limbs.
// A finite double is m * 2^e with |m| < 2^53 and -1074 <= e <= 971; relative
// to the smallest exponent E of the inputs every coordinate is an integer of
// at most 53 + 971 + 1074 = 2098 bits (66 limbs); differences 2099 bits,
// products of three 6297 bits (197 limbs, 66 + 132 + 2 allocated before
// trimming), sums of six 6300 bits: 212 limbs leave room.
// ---------------------------------------------------------------------------

constexpr int kBigLimbs = 212;

struct Big {
    int n;    // used limbs (no leading zero limbs); 0 means zero
    int neg;  // 1 if negative
    uint32_t d[kBigLimbs];
};

void big_zero(Big &r) {
    r.n = 0;
    r.neg = 0;
}

void big_trim(Big &r) {
    while (r.n > 0 && r.d[r.n - 1] == 0) --r.n;
    if (r.n == 0) r.neg = 0;
}

// r = m * 2^shift, |m| < 2^53, 0 <= shift.
void big_from_scaled(Big &r, int64_t m, int shift) {
    big_zero(r);
    if (m == 0) return;
    r.neg = m < 0;
    uint64_t mag = m < 0 ? uint64_t(-m) : uint64_t(m);
    int limb = shift / 32, bit = shift % 32;
    for (int i = 0; i < limb + 4 && i < kBigLimbs; ++i) r.d[i] = 0;
    // mag << bit spans at most 53 + 31 = 84 bits: 3 limbs.
    uint64_t lo = mag << bit;  // low 64 bits
    uint64_t hi = bit == 0 ? 0 : (mag >> (64 - bit));
    r.d[limb] = uint32_t(lo);
    r.d[limb + 1] = uint32_t(lo >> 32);
    r.d[limb + 2] = uint32_t(hi);
    r.n = limb + 3;
    big_trim(r);
}

int mag_cmp(const Big &a, const Big &b) {
    if (a.n != b.n) return a.n < b.n ? -1 : 1;
    for (int i = a.n - 1; i >= 0; --i) {
        if (a.d[i] != b.d[i]) return a.d[i] < b.d[i] ? -1 : 1;
    }
    return 0;
}

// r = |a| + |b| (r may alias neither).
void mag_add(const Big &a, const Big &b, Big &r) {
    int n = a.n > b.n ? a.n : b.n;
    uint64_t carry = 0;
    for (int i = 0; i < n; ++i) {
        uint64_t s = carry;
        if (i < a.n) s += a.d[i];
        if (i < b.n) s += b.d[i];
        r.d[i] = uint32_t(s);
        carry = s >> 32;
    }
    r.n = n;
    if (carry) r.d[r.n++] = uint32_t(carry);
}

// r = |a| - |b|, requires |a| >= |b|.
void mag_sub(const Big &a, const Big &b, Big &r) {
    int64_t borrow = 0;
    for (int i = 0; i < a.n; ++i) {
        int64_t s = int64_t(a.d[i]) - borrow - (i < b.n ? int64_t(b.d[i]) : 0);
        borrow = s < 0;
        r.d[i] = uint32_t(s + (borrow << 32));
    }
    r.n = a.n;
}

// r = a + (negb ? -b : b)
void big_add(const Big &a, const Big &b, int negb, Big &r) {
    int bneg = b.n == 0 ? 0 : (b.neg ^ negb);
    if (a.neg == bneg) {
        mag_add(a, b, r);
        r.neg = a.neg;
    } else if (mag_cmp(a, b) >= 0) {
        mag_sub(a, b, r);
        r.neg = a.neg;
    } else {
        mag_sub(b, a, r);
        r.neg = bneg;
    }
    big_trim(r);
}

void big_mul(const Big &a, const Big &b, Big &r) {
    big_zero(r);
    if (a.n == 0 || b.n == 0) return;
    int n = a.n + b.n;
    for (int i = 0; i < n; ++i) r.d[i] = 0;
    for (int i = 0; i < a.n; ++i) {
        uint64_t carry = 0;
        for (int j = 0; j < b.n; ++j) {
            uint64_t t = uint64_t(a.d[i]) * b.d[j] + r.d[i + j] + carry;
            r.d[i + j] = uint32_t(t);
            carry = t >> 32;
        }
        r.d[i + b.n] = uint32_t(carry);
    }
    r.n = n;
    r.neg = a.neg ^ b.neg;
    big_trim(r);
}

int big_sign(const Big &a) { return a.n == 0 ? 0 : (a.neg ? -1 : 1); }

// Converts count doubles to big integers relative to their smallest exponent.
void big_from_doubles(const double *x, int count, Big *out) {
    int64_t m[12];
    int e[12];
    int emin = 1 << 30;
    for (int i = 0; i < count; ++i) {
        if (x[i] == 0) {
            m[i] = 0;
            e[i] = 0;
            continue;
        }
        int ex;
        double f = std::frexp(x[i], &ex);  // x = f 2^ex, 0.5 <= |f| < 1
        m[i] = int64_t(std::ldexp(f, 53));
        e[i] = ex - 53;
        while ((m[i] & 1) == 0) {  // strip trailing zeros: e >= -1074
            m[i] /= 2;
            ++e[i];
        }
        if (e[i] < emin) emin = e[i];
    }
    for (int i = 0; i < count; ++i) {
        big_from_scaled(out[i], m[i], m[i] == 0 ? 0 : e[i] - emin);
    }
}

int orient3d_big(const double *x /*12: a b c d*/) {
    Big c[12];
    big_from_doubles(x, 12, c);
    Big ad[3], bd[3], cd[3];
    for (int k = 0; k < 3; ++k) {
        big_add(c[k], c[9 + k], 1, ad[k]);
        big_add(c[3 + k], c[9 + k], 1, bd[k]);
        big_add(c[6 + k], c[9 + k], 1, cd[k]);
    }
    // det = adx (bdy cdz - bdz cdy) + ady (bdz cdx - bdx cdz)
    //     + adz (bdx cdy - bdy cdx)
    Big t1, t2, minor, term, acc, tmp;
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
    return big_sign(acc);
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

#if defined(__GNUC__)
#define HGCD_NOINLINE __attribute__((noinline))
#else
#define HGCD_NOINLINE
#endif

HGCD_NOINLINE int orient3d_exact(const double *a, const double *b,
                                 const double *c, const double *d) {
    double x[12];
    for (int k = 0; k < 3; ++k) {
        x[k] = a[k];
        x[3 + k] = b[k];
        x[6 + k] = c[k];
        x[9 + k] = d[k];
    }
    int se = 0;
    switch (classify(x, 12, se)) {
    case Range::kZero:
        return 0;
    case Range::kDirect:
        return orient3d_expansion(x);
    case Range::kScaled:
        for (double &v : x) v = std::ldexp(v, se);
        return orient3d_expansion(x);
    case Range::kBig:
        break;
    }
    return orient3d_big(x);
}

HGCD_NOINLINE int orient2d_exact_v(double ax, double ay, double bx, double by,
                                   double cx, double cy) {
    double x[6] = {ax, ay, bx, by, cx, cy};
    int se = 0;
    switch (classify(x, 6, se)) {
    case Range::kZero:
        return 0;
    case Range::kDirect:
        return orient2d_expansion(x);
    case Range::kScaled:
        for (double &v : x) v = std::ldexp(v, se);
        return orient2d_expansion(x);
    case Range::kBig:
        break;
    }
    return orient2d_big(x);
}

// Filtered orient2d on explicit coordinates.
inline int orient2d_v(double ax, double ay, double bx, double by, double cx,
                      double cy) {
    double acx = ax - cx, acy = ay - cy, bcx = bx - cx, bcy = by - cy;
    double l = acx * bcy, r = acy * bcx;
    double det = l - r;
    double perm = std::fabs(l) + std::fabs(r);
    double bound = kO2dBound * perm + kSlack;
    if (det > bound) return 1;
    if (-det > bound) return -1;
    return orient2d_exact_v(ax, ay, bx, by, cx, cy);
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
    // Same error analysis as the header comment: every monomial carries at
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
    return orient2d_v(a[i], a[j], b[i], b[j], c[i], c[j]);
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

// Closed segments [a0,a1] and [b0,b1] (each possibly a point) meet in
// projection k.
bool seg_seg_proj(int k, const double *a0, const double *a1, const double *b0,
                  const double *b1) {
    int o1 = orient2d_proj(k, a0, a1, b0);
    int o2 = orient2d_proj(k, a0, a1, b1);
    if (o1 != 0 && o1 == o2) return false;
    int o3 = orient2d_proj(k, b0, b1, a0);
    int o4 = orient2d_proj(k, b0, b1, a1);
    if (o3 != 0 && o3 == o4) return false;
    if (o1 * o2 < 0 && o3 * o4 < 0) return true;  // proper crossing
    // Otherwise they meet iff an endpoint lies on the other segment.
    if (o1 == 0 && in_box_proj(k, a0, a1, b0)) return true;
    if (o2 == 0 && in_box_proj(k, a0, a1, b1)) return true;
    if (o3 == 0 && in_box_proj(k, b0, b1, a0)) return true;
    if (o4 == 0 && in_box_proj(k, b0, b1, a1)) return true;
    return false;
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
int choose_projection(const double *const *t, int *o) {
    for (int k = 2; k >= 0; --k) {
        int s = orient2d_proj(k, t[0], t[1], t[2]);
        if (s != 0) {
            *o = s;
            return k;
        }
    }
    return -1;
}

// Segment [e0, e1] lying in the plane of the non-degenerate triangle t.
bool coplanar_seg_tri(const double *e0, const double *e1,
                      const double *const *t) {
    int o = 0;
    int k = choose_projection(t, &o);
    if (k < 0) return false;  // unreachable for non-degenerate t
    if (point_in_tri_proj(k, e0, t, o)) return true;
    for (int i = 0; i < 3; ++i) {
        if (seg_seg_proj(k, e0, e1, t[i], t[(i + 1) % 3])) return true;
    }
    return false;
}

// Segment vs non-degenerate triangle, closed, exact.
bool seg_tri_nondegenerate(const double *e0, const double *e1,
                           const double *const *t) {
    int s0 = orient3d_filtered(t[0], t[1], t[2], e0);
    int s1 = orient3d_filtered(t[0], t[1], t[2], e1);
    if (s0 != 0 && s0 == s1) return false;
    if (s0 == 0 && s1 == 0) return coplanar_seg_tri(e0, e1, t);
    // The segment meets the plane in exactly one point X (e0 != e1 here);
    // X is in the closed triangle iff the line e0e1 passes on the same side
    // (or on) each directed edge.
    bool pos = false, neg = false;
    for (int i = 0; i < 3; ++i) {
        int s = orient3d_filtered(e0, e1, t[i], t[(i + 1) % 3]);
        pos |= s > 0;
        neg |= s < 0;
        if (pos && neg) return false;
    }
    return true;
}

// Closed 3D segments (each possibly a point). Coplanar segments meet iff they
// meet in all three coordinate projections (necessary; and one projection is
// injective on the line or plane they span, which makes it sufficient).
bool seg_seg_3d(const double *a0, const double *a1, const double *b0,
                const double *b1) {
    for (int i = 0; i < 3; ++i) {
        double alo = a0[i] < a1[i] ? a0[i] : a1[i];
        double ahi = a0[i] < a1[i] ? a1[i] : a0[i];
        double blo = b0[i] < b1[i] ? b0[i] : b1[i];
        double bhi = b0[i] < b1[i] ? b1[i] : b0[i];
        if (ahi < blo || bhi < alo) return false;
    }
    if (orient3d_filtered(a0, a1, b0, b1) != 0) return false;
    for (int k = 0; k < 3; ++k) {
        if (!seg_seg_proj(k, a0, a1, b0, b1)) return false;
    }
    return true;
}

bool is_collinear(const double *a, const double *b, const double *c) {
    const double *t[3] = {a, b, c};
    int o;
    return choose_projection(t, &o) < 0;
}

// Two coplanar non-degenerate triangles.
bool coplanar_tri_tri(const double *const *p, const double *const *q) {
    int o = 0;
    int k = choose_projection(p, &o);
    if (k < 0) return false;  // unreachable
    for (int i = 0; i < 3; ++i) {
        for (int j = 0; j < 3; ++j) {
            if (seg_seg_proj(k, p[i], p[(i + 1) % 3], q[j], q[(j + 1) % 3]))
                return true;
        }
    }
    // No boundary contact: one contains the other or they are disjoint.
    if (point_in_tri_proj(k, p[0], q, orient2d_proj(k, q[0], q[1], q[2])))
        return true;
    if (point_in_tri_proj(k, q[0], p, o)) return true;
    return false;
}

// Slow general path: coplanar triangles or at least one zero-area triangle.
// Two closed triangles meet iff an edge of one meets the other triangle; a
// zero-area triangle is the union of its edges.
HGCD_NOINLINE bool tri_tri_general(const double *const *p,
                                   const double *const *q) {
    bool dp = is_collinear(p[0], p[1], p[2]);
    bool dq = is_collinear(q[0], q[1], q[2]);
    if (!dp && !dq) return coplanar_tri_tri(p, q);
    if (dp && dq) {
        for (int i = 0; i < 3; ++i) {
            for (int j = 0; j < 3; ++j) {
                if (seg_seg_3d(p[i], p[(i + 1) % 3], q[j], q[(j + 1) % 3]))
                    return true;
            }
        }
        return false;
    }
    if (dq) {
        const double *const *t = p;
        p = q;
        q = t;
    }
    // p is degenerate, q is not.
    for (int i = 0; i < 3; ++i) {
        if (seg_tri_nondegenerate(p[i], p[(i + 1) % 3], q)) return true;
    }
    return false;
}

// For a sign pattern of a triangle's vertices against the other triangle's
// plane (not all equal and non-zero, not all zero), the "apex" vertex a and
// flip f such that f*s[a] >= 0 >= f*s[b], f*s[c] (b, c the next vertices
// in cyclic order) and the edges a-b and a-c each have an endpoint off the
// plane. Encoded as a + 3 * (f > 0); index (s0+1)*9 + (s1+1)*3 + (s2+1).
struct ApexTable {
    unsigned char v[27];
    constexpr ApexTable() : v() {
        for (int i = 0; i < 27; ++i) {
            int s[3] = {i / 9 - 1, (i / 3) % 3 - 1, i % 3 - 1};
            int np = 0, nn = 0, nz = 0, ip = 0, in = 0, iz = 0;
            for (int k = 0; k < 3; ++k) {
                if (s[k] > 0) { ++np; ip = k; }
                else if (s[k] < 0) { ++nn; in = k; }
                else { ++nz; iz = k; }
            }
            int a = 0, f = 1;
            if (np == 1 && nn + nz == 2) { a = ip; f = 1; }
            else if (nn == 1 && np + nz == 2) { a = in; f = -1; }
            else if (nz == 1 && np == 2) { a = iz; f = -1; }
            else if (nz == 1 && nn == 2) { a = iz; f = 1; }
            v[i] = (unsigned char)(a + (f > 0 ? 3 : 0));
        }
    }
};
constexpr ApexTable kApex;

}  // namespace

// ---------------------------------------------------------------------------
// Public predicates
// ---------------------------------------------------------------------------

int orient3d(const double *a, const double *b, const double *c,
             const double *d) {
    return orient3d_filtered(a, b, c, d);
}

int orient2d(const double *a, const double *b, const double *c) {
    return orient2d_v(a[0], a[1], b[0], b[1], c[0], c[1]);
}

bool collinear3d(const double *a, const double *b, const double *c) {
    return is_collinear(a, b, c);
}

bool segment_triangle_intersect(const double *e0, const double *e1,
                                const double *t0, const double *t1,
                                const double *t2) {
    const double *t[3] = {t0, t1, t2};
    if (is_collinear(t0, t1, t2)) {
        for (int i = 0; i < 3; ++i) {
            if (seg_seg_3d(e0, e1, t[i], t[(i + 1) % 3])) return true;
        }
        return false;
    }
    return seg_tri_nondegenerate(e0, e1, t);
}

// Triangle-triangle test.
//
// 1. Plane-side rejection: if the three vertices of one triangle are strictly
//    on one side of the other's plane there is no contact.
// 2. If all vertices of one triangle lie on the other's plane, the triangles
//    are coplanar or one of them has zero area: general exact path.
// 3. Otherwise both triangles are proper and their planes cross in a line L.
//    Each triangle meets L in a segment (possibly a point): S_P = [X_ab, X_ac]
//    where a is P's apex vertex (alone on its side of Q's plane, after
//    flipping) and X_ab is where edge a-b meets Q's plane; likewise S_Q. The
//    triangles meet iff S_P and S_Q overlap. Ordering along L needs no
//    constructed points: with P's apex on the positive side of Q's plane (after
//    the flip f) and Q's apex on the positive side of P's plane (flip g),
//    sign orient3d(p_a, p_x, q_a, q_y) = sign of (Y_y - X_x) along one fixed
//    direction of L (X_x on edge a-x of P, Y_y on edge a-y of Q). [Proof: an
//    orientation-preserving affine map sends P's plane to z=0, Q's to y=0,
//    with the apex sides to y>0 and z>0; writing p_a = X + l u,
//    p_x = X - m u (u = (u1, u2, 0), u2 > 0), q_a = Y + r w, q_y = Y - s w
//    (w = (w1, 0, w3), w3 > 0), the determinant expands to
//    (l+m)(r+s) u2 w3 (Y_1 - X_1).] In those coordinates, the order of the
//    two crossing points of each triangle follows from its orientation:
//    X_ab <= X_ac iff g = -1, and Y_ab >= Y_ac iff f = -1. With (lo, hi) the
//    endpoints so ordered, the segments overlap iff X_lo <= Y_hi and
//    Y_lo <= X_hi: two more orientation tests (the Guigue-Devillers idea).
namespace {

inline double min2(double a, double b) { return b < a ? b : a; }
inline double max2(double a, double b) { return a < b ? b : a; }

// Boxes of the two triangles are disjoint (exact comparisons).
inline bool boxes_disjoint(const double *const *p, const double *const *q) {
    bool apart = false;
    for (int k = 0; k < 3; ++k) {
        double plo = min2(min2(p[0][k], p[1][k]), p[2][k]);
        double phi = max2(max2(p[0][k], p[1][k]), p[2][k]);
        double qlo = min2(min2(q[0][k], q[1][k]), q[2][k]);
        double qhi = max2(max2(q[0][k], q[1][k]), q[2][k]);
        apart |= (phi < qlo) | (qhi < plo);
    }
    return apart;
}

// Steps 2-3 of tri_tri_intersect, given both sign triples (neither all
// equal and non-zero).
inline bool tri_tri_finish(const double *const *p, const double *const *q,
                           const int *sp, const int *sq) {
    if ((sp[0] == 0 && sp[1] == 0 && sp[2] == 0) ||
        (sq[0] == 0 && sq[1] == 0 && sq[2] == 0)) {
        return tri_tri_general(p, q);
    }
    int ap = kApex.v[(sp[0] + 1) * 9 + (sp[1] + 1) * 3 + (sp[2] + 1)];
    int aq = kApex.v[(sq[0] + 1) * 9 + (sq[1] + 1) * 3 + (sq[2] + 1)];
    int a = ap % 3, f = ap >= 3 ? 1 : -1;
    int b = aq % 3, g = aq >= 3 ? 1 : -1;
    const double *pa = p[a], *pb = p[(a + 1) % 3], *pc = p[(a + 2) % 3];
    const double *qa = q[b], *qb = q[(b + 1) % 3], *qc = q[(b + 2) % 3];
    const double *plo = g < 0 ? pb : pc, *phi = g < 0 ? pc : pb;
    const double *qlo = f < 0 ? qc : qb, *qhi = f < 0 ? qb : qc;
    if (orient3d_filtered(pa, plo, qa, qhi) < 0) return false;
    return orient3d_filtered(pa, phi, qa, qlo) <= 0;
}

inline bool all_same_nonzero(const int *s) {
    return (s[0] == s[1]) & (s[1] == s[2]) & (s[0] != 0);
}

}  // namespace

// Triangle-triangle test.
//
// 0. Disjoint bounding boxes: no contact (exact, cheap, rejects about half of
//    the triangle pairs of box-overlapping tetrahedra).
// 1. Plane-side rejection: if the three vertices of one triangle are strictly
//    on one side of the other's plane there is no contact.
// 2. If all vertices of one triangle lie on the other's plane, the triangles
//    are coplanar or one of them has zero area: general exact path.
// 3. Otherwise both triangles are proper and their planes cross in a line L.
//    Each triangle meets L in a segment (possibly a point): S_P = [X_ab, X_ac]
//    where a is P's apex vertex (alone on its side of Q's plane, after
//    flipping) and X_ab is where edge a-b meets Q's plane; likewise S_Q. The
//    triangles meet iff S_P and S_Q overlap. Ordering along L needs no
//    constructed points: with P's apex on the positive side of Q's plane (after
//    the flip f) and Q's apex on the positive side of P's plane (flip g),
//    sign orient3d(p_a, p_x, q_a, q_y) = sign of (Y_y - X_x) along one fixed
//    direction of L (X_x on edge a-x of P, Y_y on edge a-y of Q). [Proof: an
//    orientation-preserving affine map sends P's plane to z=0, Q's to y=0,
//    with the apex sides to y>0 and z>0; writing p_a = X + l u,
//    p_x = X - m u (u = (u1, u2, 0), u2 > 0), q_a = Y + r w, q_y = Y - s w
//    (w = (w1, 0, w3), w3 > 0), the determinant expands to
//    (l+m)(r+s) u2 w3 (Y_1 - X_1).] In those coordinates, the order of the
//    two crossing points of each triangle follows from its orientation:
//    X_ab <= X_ac iff g = -1, and Y_ab >= Y_ac iff f = -1. With (lo, hi) the
//    endpoints so ordered, the segments overlap iff X_lo <= Y_hi and
//    Y_lo <= X_hi: two more orientation tests (the Guigue-Devillers idea).
bool tri_tri_intersect(const double *p0, const double *p1, const double *p2,
                       const double *q0, const double *q1, const double *q2) {
    const double *p[3] = {p0, p1, p2};
    const double *q[3] = {q0, q1, q2};
    if (boxes_disjoint(p, q)) return false;

    PlaneFilter pq;
    plane_prepare(pq, q0, q1, q2);
    int sp[3];
    plane_sides3(pq, p0, p1, p2, sp);
    if (all_same_nonzero(sp)) return false;
    // P in Q's plane (or Q of zero area): coplanar or degenerate, and the
    // signs of Q against P's plane are not needed.
    if ((sp[0] == 0) & (sp[1] == 0) & (sp[2] == 0)) return tri_tri_general(p, q);

    PlaneFilter pp;
    plane_prepare(pp, p0, p1, p2);
    int sq[3];
    plane_sides3(pp, q0, q1, q2, sq);
    if (all_same_nonzero(sq)) return false;

    return tri_tri_finish(p, q, sp, sq);
}

bool tri_tri_intersect_signed(const double *const *p, const double *const *q,
                              const int *sp, const int *sq) {
    if (all_same_nonzero(sp) || all_same_nonzero(sq)) return false;
    return tri_tri_finish(p, q, sp, sq);
}

void prepare_triangle(PreparedTriangle &t, const double *v0, const double *v1,
                      const double *v2) {
    t.v[0] = v0;
    t.v[1] = v1;
    t.v[2] = v2;
    PlaneFilter pf;
    plane_prepare(pf, v0, v1, v2);
    for (int k = 0; k < 3; ++k) {
        t.n[k] = pf.n[k];
        t.an[k] = pf.an[k];
        t.lo[k] = min2(min2(v0[k], v1[k]), v2[k]);
        t.hi[k] = max2(max2(v0[k], v1[k]), v2[k]);
    }
}

bool tri_tri_intersect(const PreparedTriangle &p, const PreparedTriangle &q) {
    bool apart = false;
    for (int k = 0; k < 3; ++k) {
        apart |= (p.hi[k] < q.lo[k]) | (q.hi[k] < p.lo[k]);
    }
    if (apart) return false;
    PlaneFilter pq;
    pq.t0 = q.v[0];
    pq.t1 = q.v[1];
    pq.t2 = q.v[2];
    for (int k = 0; k < 3; ++k) {
        pq.n[k] = q.n[k];
        pq.an[k] = q.an[k];
    }
    int sp[3];
    plane_sides3(pq, p.v[0], p.v[1], p.v[2], sp);
    if (all_same_nonzero(sp)) return false;
    if ((sp[0] == 0) & (sp[1] == 0) & (sp[2] == 0)) return tri_tri_general(p.v, q.v);
    PlaneFilter pp;
    pp.t0 = p.v[0];
    pp.t1 = p.v[1];
    pp.t2 = p.v[2];
    for (int k = 0; k < 3; ++k) {
        pp.n[k] = p.n[k];
        pp.an[k] = p.an[k];
    }
    int sq[3];
    plane_sides3(pp, q.v[0], q.v[1], q.v[2], sq);
    if (all_same_nonzero(sq)) return false;
    return tri_tri_finish(p.v, q.v, sp, sq);
}

// ---------------------------------------------------------------------------
// Point in closed mesh
// ---------------------------------------------------------------------------

namespace {

// Fixed "generic" directions (random, full-precision components; one
// component is exactly +-1 so the segment provably leaves the box).
constexpr double kDirections[32][3] = {
    {1.0, 0.0935817916500935, -0.016930054247476733},
    {0.2007225393078308, 1.0, -0.4946207010107702},
    {0.44788822782939064, -0.6906693700061936, 1.0},
    {-1.0, 0.1695679353745877, 0.2821414776144783},
    {0.77382813823161, -1.0, 0.6854467277224109},
    {-0.3644828074192151, 0.100268934525365, 1.0},
    {1.0, -0.8596645014289273, -0.6506934030106357},
    {0.7034952300920198, 1.0, 0.0008216490721728587},
    {-0.016129958063424876, -0.3820996535285678, 1.0},
    {-1.0, -0.10336276040369208, 0.6440068499368016},
    {0.025260738424357942, -1.0, 0.5520275040223425},
    {-0.0626699102152436, -0.08465666527411231, -1.0},
    {-1.0, 0.30231348175180484, 0.012551726506148553},
    {-0.09048269460159863, 1.0, 0.4324322612823911},
    {0.8584192512310963, -0.04981394072274192, 1.0},
    {-1.0, -0.036161502419769787, 0.4850034309062593},
    {-0.22568896426358886, -1.0, -0.29218964873154973},
    {0.9046758003457708, -0.06930679101000203, -1.0},
    {1.0, -0.28839389032120344, -0.5511162360112578},
    {0.7548708209579681, -1.0, 0.7648675152211665},
    {-0.5289879543057623, 0.35849831185096936, 1.0},
    {-1.0, 0.6877990603376621, 0.9218769929293337},
    {-0.4924911870771004, -1.0, 0.8636427140596873},
    {0.09808070213706166, -0.21881296273158135, -1.0},
    {1.0, -0.6014918066435995, -0.6121608564333201},
    {-0.4539766533257843, 1.0, -0.4593933956215954},
    {0.20546452648160496, -0.5754435138711405, -1.0},
    {-1.0, 0.8706553307849888, -0.9074941015587997},
    {0.349334839723178, -1.0, 0.9231535222195858},
    {-0.23055428686955315, 0.5063698813531022, -1.0},
    {1.0, -0.404309839944094, -0.4377207190964512},
    {0.4110444609739782, 1.0, -0.9022506586077742},
};
constexpr int kDirectionCount = 32;

}  // namespace

// Counts the triangles the segment p -> q crosses; a crossing counts only
// when it is strictly decisive: p and q strictly on opposite sides of the
// triangle's plane and the segment's line strictly inside all three edges. A
// segment through an edge or a vertex, or lying in a triangle's plane and
// meeting it, makes the attempt degenerate and another direction is tried.
// Zero-area triangles are skipped: a generic segment cannot cross them (and
// a segment through one passes through an edge of the adjacent faces, which
// is caught as degenerate there). If all 32 directions are degenerate
// (practically impossible: the segment would have to pass exactly through a
// mesh edge for every one of them) the parity of the strict crossings of the
// last attempt is returned.
bool point_in_closed_mesh(const double *p, const double *verts,
                          const uint32_t *tris, uint32_t tri_count,
                          const double *box_min, const double *box_max) {
    for (int k = 0; k < 3; ++k) {
        if (!(p[k] >= box_min[k] && p[k] <= box_max[k])) return false;
    }
    double ext = 0;
    for (int k = 0; k < 3; ++k) {
        double e = box_max[k] - box_min[k];
        if (e > ext) ext = e;
    }
    bool parity = false;
    for (int attempt = 0; attempt < kDirectionCount; ++attempt) {
        const double *dir = kDirections[attempt];
        double len = 2.0 * ext + 1.0;
        double q[3];
        for (;;) {
            for (int k = 0; k < 3; ++k) q[k] = p[k] + len * dir[k];
            bool outside = false;
            for (int k = 0; k < 3; ++k) {
                outside |= q[k] < box_min[k] || q[k] > box_max[k];
            }
            if (outside) break;
            len *= 2.0;
        }
        double smin[3], smax[3];
        for (int k = 0; k < 3; ++k) {
            smin[k] = p[k] < q[k] ? p[k] : q[k];
            smax[k] = p[k] < q[k] ? q[k] : p[k];
        }
        parity = false;
        bool degenerate = false;
        // On a degenerate attempt keep counting (the last attempt's strict
        // crossings are the documented fallback answer).
        for (uint32_t t = 0; t < tri_count; ++t) {
            const double *v[3] = {verts + 3 * std::size_t(tris[3 * t]),
                                  verts + 3 * std::size_t(tris[3 * t + 1]),
                                  verts + 3 * std::size_t(tris[3 * t + 2])};
            bool away = false;
            for (int k = 0; k < 3 && !away; ++k) {
                double lo = v[0][k], hi = v[0][k];
                for (int i = 1; i < 3; ++i) {
                    if (v[i][k] < lo) lo = v[i][k];
                    if (v[i][k] > hi) hi = v[i][k];
                }
                away = hi < smin[k] || lo > smax[k];
            }
            if (away) continue;
            int sp = orient3d_filtered(v[0], v[1], v[2], p);
            int sq = orient3d_filtered(v[0], v[1], v[2], q);
            if (sp != 0 && sp == sq) continue;
            if (sp == 0 && sq == 0) {
                // In the plane (or a zero-area triangle).
                if (is_collinear(v[0], v[1], v[2])) continue;
                if (coplanar_seg_tri(p, q, v)) degenerate = true;
                continue;
            }
            if (sp == 0 || sq == 0) {
                // Touches the plane only at p (not on the surface by the
                // precondition) or at q (outside the box): but check, so
                // that a violated precondition is treated as degenerate.
                if (is_collinear(v[0], v[1], v[2])) continue;
                const double *x = sp == 0 ? p : q;
                int o = 0;
                int k = choose_projection(v, &o);
                if (point_in_tri_proj(k, x, v, o)) degenerate = true;
                continue;
            }
            int s0 = orient3d_filtered(p, q, v[0], v[1]);
            int s1 = orient3d_filtered(p, q, v[1], v[2]);
            int s2 = orient3d_filtered(p, q, v[2], v[0]);
            if (s0 == s1 && s1 == s2 && s0 != 0) {
                parity = !parity;
            } else if (!((s0 > 0 || s1 > 0 || s2 > 0) &&
                         (s0 < 0 || s1 < 0 || s2 < 0))) {
                degenerate = true;  // through an edge or a vertex
            }
        }
        if (!degenerate) return parity;
    }
    return parity;
}

bool point_in_convex_closed_mesh(const double *p, const double *verts,
                                 const uint32_t *tris, uint32_t tri_count,
                                 int inward_sign) {
    for (uint32_t t = 0; t < tri_count; ++t) {
        int s = orient3d_filtered(verts + 3 * std::size_t(tris[3 * t]),
                                  verts + 3 * std::size_t(tris[3 * t + 1]),
                                  verts + 3 * std::size_t(tris[3 * t + 2]), p);
        if (s == -inward_sign) return false;
    }
    return true;
}

}  // namespace hgcd
