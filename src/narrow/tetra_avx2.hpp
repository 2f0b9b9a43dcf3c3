// AVX2 helpers of the tetrahedron path's four- and eight-lane kernels
// (tetra_avx2.cpp, tetra_batch_avx2.cpp). Each is compiled for the AVX2
// target, so only functions of that target, picked at run time
// (common/cpu.hpp), expand them.
#pragma once
#include "common/cpu.hpp"

#if HGCD_AVX2
#include <immintrin.h>

#include <cstdint>

#include "common/simd.hpp"

namespace hgcd {
namespace tet {

#pragma GCC push_options
#pragma GCC target("avx2")

// Bit i set when a[i] < b[i].
static inline unsigned less_avx2(const f64x4 &a, const f64x4 &b) {
    return unsigned(_mm256_movemask_pd(_mm256_cmp_pd((__m256d)a, (__m256d)b, _CMP_LT_OQ)));
}
// (An out-parameter: the one-pair kernels that call it have no target of
// their own, and a vector return would change the ABI there; the batch's
// helpers below, all of the AVX2 target, return theirs.)
static inline void max_avx2(f64x4 &out, const f64x4 &a, const f64x4 &b) {
    out = (f64x4)_mm256_max_pd((__m256d)a, (__m256d)b);
}
static inline double hmax_avx2(const f64x4 &a) {
    const __m256d m = _mm256_max_pd((__m256d)a, _mm256_permute2f128_pd((__m256d)a, (__m256d)a, 1));
    return _mm_cvtsd_f64(_mm256_castpd256_pd128(_mm256_max_pd(m, _mm256_permute_pd(m, 5))));
}
static inline double hmin_avx2(const f64x4 &a) {
    const __m256d m = _mm256_min_pd((__m256d)a, _mm256_permute2f128_pd((__m256d)a, (__m256d)a, 1));
    return _mm_cvtsd_f64(_mm256_castpd256_pd128(_mm256_min_pd(m, _mm256_permute_pd(m, 5))));
}

static inline void transpose4(f64x4 &r0, f64x4 &r1, f64x4 &r2, f64x4 &r3) {
    const __m256d t0 = _mm256_unpacklo_pd((__m256d)r0, (__m256d)r1);
    const __m256d t1 = _mm256_unpackhi_pd((__m256d)r0, (__m256d)r1);
    const __m256d t2 = _mm256_unpacklo_pd((__m256d)r2, (__m256d)r3);
    const __m256d t3 = _mm256_unpackhi_pd((__m256d)r2, (__m256d)r3);
    r0 = (f64x4)_mm256_permute2f128_pd(t0, t2, 0x20);
    r1 = (f64x4)_mm256_permute2f128_pd(t1, t3, 0x20);
    r2 = (f64x4)_mm256_permute2f128_pd(t0, t2, 0x31);
    r3 = (f64x4)_mm256_permute2f128_pd(t1, t3, 0x31);
}
// The lanes of a comparison's mask as bits.
static inline unsigned lanes_of(const i64x4 &m) { return unsigned(_mm256_movemask_pd((__m256d)m)); }
static inline unsigned lanes_of(const i32x8 &m) { return unsigned(_mm256_movemask_ps((__m256)m)); }
static inline f64x4 min4(const f64x4 &a, const f64x4 &b) { return (f64x4)_mm256_min_pd((__m256d)a, (__m256d)b); }
static inline f64x4 max4(const f64x4 &a, const f64x4 &b) { return (f64x4)_mm256_max_pd((__m256d)a, (__m256d)b); }
static inline f64x4 abs4(const f64x4 &a) { return (f64x4)((i64x4)a & (i64x4{} + INT64_MAX)); }
// b where take_b, else a.
static inline f64x4 pick4(const i64x4 &take_b, const f64x4 &a, const f64x4 &b) {
    return (f64x4)_mm256_blendv_pd((__m256d)a, (__m256d)b, (__m256d)take_b);
}
// Two groups' four doubles as eight floats (group 0 in lanes 0-3).
static inline f32x8 join8(const f64x4 &g0, const f64x4 &g1) {
    return (f32x8)_mm256_set_m128(_mm256_cvtpd_ps((__m256d)g1), _mm256_cvtpd_ps((__m256d)g0));
}

#pragma GCC pop_options

}  // namespace tet
}  // namespace hgcd

#endif  // HGCD_AVX2
