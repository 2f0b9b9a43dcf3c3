// The one world-space transform of hgcd (documented in hgcd.h): every place
// that needs world vertices calls these, so the bits agree everywhere.
#pragma once
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>

#if defined(__SSE2__)
#include <immintrin.h>
#endif

namespace hgcd {

struct Rotation {
    double m[9];  // row-major
};

// Rotation matrix of quaternion (x, y, z, w), each entry evaluated as written
// in docs/scenes.md. The build uses -ffp-contract=off so no FMA changes the bits.
// T is double, or a vector of doubles with one quaternion per lane (the same
// operations lane by lane, so the same bits).
template <class T>
inline void rotation_entries(const T &x, const T &y, const T &z, const T &w, T *m) {
    m[0] = 1.0 - 2.0 * (y * y + z * z);
    m[1] = 2.0 * (x * y - z * w);
    m[2] = 2.0 * (x * z + y * w);
    m[3] = 2.0 * (x * y + z * w);
    m[4] = 1.0 - 2.0 * (x * x + z * z);
    m[5] = 2.0 * (y * z - x * w);
    m[6] = 2.0 * (x * z - y * w);
    m[7] = 2.0 * (y * z + x * w);
    m[8] = 1.0 - 2.0 * (x * x + y * y);
}

inline Rotation rotation_of(const double *q) {
    Rotation r;
    rotation_entries(q[0], q[1], q[2], q[3], r.m);
    return r;
}

// A bound on ||R^T R - I||_inf (max row sum) for R = rotation_of(q), from
// the quaternion's norm alone; infinity unless |fl(|q|^2) - 1| <= 1e-6. In
// exact arithmetic on x, y, z, w with n = |q|^2, R = n R_u + (1 - n) I (R_u
// a rotation), so R^T R - I = n (n - 1) (2 I - R_u - R_u^T), whose max row
// sum is at most |n (n - 1)| (2 + 2 sqrt(3)) (a rotation's rows have 1-norm
// at most sqrt(3)). The computed entries are within 5.1u (diagonal: two
// squares, a sum and a subtraction, |y^2 + z^2| <= n) or 2u (the others) of
// those, E with ||E||_inf < 2e-15, and ||R^T E + E^T R + E^T E||_inf <= 2
// 1.74 ||E||_inf + tiny < 7e-15. fl(n) is within g_4 n < 4.6e-16 of n, so
// the bound is 5.47 (|fl(n) - 1| + 4.6e-16) + 7e-15 <= 5.5 |fl(n) - 1| +
// 1e-14 (5.47 >= (2 + 2 sqrt(3)) n; fl(n) - 1 is exact near 1; 1 + 1e-12
// covers the rest).
inline double rotation_defect(const double *q) {
    const double d = std::fabs((((q[0] * q[0] + q[1] * q[1]) + q[2] * q[2]) + q[3] * q[3]) - 1);
    return d <= 1e-6 ? (5.5 * d + 1e-14) * (1 + 1e-12) : INFINITY;
}

// World vertex of mesh vertex m for a body at c, rotation r, scale s.
inline void transform_point(const Rotation &r, const double *c, double s,
                            const double *m, double *out) {
    const double lx = s * m[0], ly = s * m[1], lz = s * m[2];
    out[0] = c[0] + ((r.m[0] * lx + r.m[1] * ly) + r.m[2] * lz);
    out[1] = c[1] + ((r.m[3] * lx + r.m[4] * ly) + r.m[5] * lz);
    out[2] = c[2] + ((r.m[6] * lx + r.m[7] * ly) + r.m[8] * lz);
}

// The box [lo, hi] of the offsets 0 + R (s v) of the points v (count, x y z
// each) from a body's position, each by transform_point's operations with a
// zero position, with std::min / std::max's choices (no offset is -0: 0 + -0
// is +0): what the grid's box of a body is made of.
inline void offset_box_scalar(const Rotation &r, double s, const double *v, size_t count, double *lo, double *hi) {
    const double zero[3] = {0, 0, 0};
    for (int k = 0; k < 3; ++k) {
        lo[k] = INFINITY;
        hi[k] = -INFINITY;
    }
    for (size_t k = 0; k < count; ++k, v += 3) {
        double d[3];
        transform_point(r, zero, s, v, d);
        for (int a = 0; a < 3; ++a) {
            lo[a] = std::min(lo[a], d[a]);
            hi[a] = std::max(hi[a], d[a]);
        }
    }
}

// The same, with SSE2: the x and y offsets of a point share a vector and z
// has one of its own, lane by lane the same operations (minpd and maxpd
// choose as std::min and std::max do), so the same bits.
inline void offset_box(const Rotation &r, double s, const double *v, size_t count, double *lo, double *hi) {
#if defined(__SSE2__)
    const __m128d r03 = _mm_set_pd(r.m[3], r.m[0]), r14 = _mm_set_pd(r.m[4], r.m[1]), r25 = _mm_set_pd(r.m[5], r.m[2]);
    const __m128d r6 = _mm_set1_pd(r.m[6]), r7 = _mm_set1_pd(r.m[7]), r8 = _mm_set1_pd(r.m[8]);
    const __m128d zero = _mm_setzero_pd();
    __m128d lo01 = _mm_set1_pd(INFINITY), hi01 = _mm_set1_pd(-INFINITY), lo2 = lo01, hi2 = hi01;
    for (size_t k = 0; k < count; ++k, v += 3) {
        const __m128d lx = _mm_set1_pd(s * v[0]), ly = _mm_set1_pd(s * v[1]), lz = _mm_set1_pd(s * v[2]);
        const __m128d d01 =
            _mm_add_pd(zero, _mm_add_pd(_mm_add_pd(_mm_mul_pd(r03, lx), _mm_mul_pd(r14, ly)), _mm_mul_pd(r25, lz)));
        const __m128d d2 =
            _mm_add_pd(zero, _mm_add_pd(_mm_add_pd(_mm_mul_pd(r6, lx), _mm_mul_pd(r7, ly)), _mm_mul_pd(r8, lz)));
        lo01 = _mm_min_pd(d01, lo01);  // (d < lo ? d : lo, as std::min(lo, d))
        hi01 = _mm_max_pd(d01, hi01);
        lo2 = _mm_min_pd(d2, lo2);
        hi2 = _mm_max_pd(d2, hi2);
    }
    _mm_storeu_pd(lo, lo01);
    _mm_storeu_pd(hi, hi01);
    _mm_store_sd(lo + 2, lo2);
    _mm_store_sd(hi + 2, hi2);
#else
    offset_box_scalar(r, s, v, count, lo, hi);
#endif
}

// Upper bound on |R v| / |v| for the matrix of a quaternion of squared norm
// n2: R = n2 * Rhat + (1 - n2) * I, so the stretch is at most n2 + |1 - n2|.
inline double rotation_stretch(const double *q) {
    const double n2 = q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3];
    return n2 + std::fabs(1.0 - n2);
}

}  // namespace hgcd
