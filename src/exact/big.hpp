// Exact fixed-size big integers for the exact fallbacks of src/exact
// (predicates.cpp, distance.cpp): inputs that the expansion arithmetic
// cannot hold, or polynomials of higher degree than it is written for.
// Internal to src/exact.
#pragma once
#include <cmath>
#include <cstdint>

namespace hgcd {
namespace predicates {

// ---------------------------------------------------------------------------
// Exact big-integer fallback for inputs spanning more binades than the
// expansion path can scale into its safe range. Sign-magnitude, 32-bit limbs.
// A finite double is m * 2^e with |m| < 2^53 and -1074 <= e <= 971; relative
// to the smallest exponent E of the inputs every coordinate is an integer of
// at most 53 + 971 + 1074 = 2098 bits (66 limbs); differences 2099 bits,
// products of three 6297 bits (197 limbs, 66 + 132 + 2 allocated before
// trimming), sums of six 6300 bits (197 limbs). The ray order of
// crossing.cpp multiplies two such determinants: 12600 bits, and big_mul
// allocates a.n + b.n <= 2 * 212 limbs before trimming: 430 limbs leave room.
// ---------------------------------------------------------------------------

constexpr int kBigLimbs = 430;

struct Big {
    int n;    // used limbs (no leading zero limbs); 0 means zero
    int neg;  // 1 if negative
    uint32_t d[kBigLimbs];
};

inline void big_zero(Big &r) {
    r.n = 0;
    r.neg = 0;
}

inline void big_trim(Big &r) {
    while (r.n > 0 && r.d[r.n - 1] == 0) --r.n;
    if (r.n == 0) r.neg = 0;
}

// r = m * 2^shift, |m| < 2^53, 0 <= shift.
inline void big_from_scaled(Big &r, int64_t m, int shift) {
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

inline int mag_cmp(const Big &a, const Big &b) {
    if (a.n != b.n) return a.n < b.n ? -1 : 1;
    for (int i = a.n - 1; i >= 0; --i) {
        if (a.d[i] != b.d[i]) return a.d[i] < b.d[i] ? -1 : 1;
    }
    return 0;
}

// r = |a| + |b| (r may alias neither).
inline void mag_add(const Big &a, const Big &b, Big &r) {
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
inline void mag_sub(const Big &a, const Big &b, Big &r) {
    int64_t borrow = 0;
    for (int i = 0; i < a.n; ++i) {
        int64_t s = int64_t(a.d[i]) - borrow - (i < b.n ? int64_t(b.d[i]) : 0);
        borrow = s < 0;
        r.d[i] = uint32_t(s + (borrow << 32));
    }
    r.n = a.n;
}

// r = a + (negb ? -b : b)
inline void big_add(const Big &a, const Big &b, int negb, Big &r) {
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

inline void big_mul(const Big &a, const Big &b, Big &r) {
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

inline int big_sign(const Big &a) { return a.n == 0 ? 0 : (a.neg ? -1 : 1); }

// Converts count doubles to big integers relative to their smallest exponent.
inline void big_from_doubles(const double *x, int count, Big *out) {
    int64_t m[24];  // (count <= 24)
    int e[24];
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

}  // namespace predicates
}  // namespace hgcd
