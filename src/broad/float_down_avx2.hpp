// float_box's rounding to float of four doubles at a time (AVX2): the gather's
// kernel (float_box_avx2.cpp) and the pose's (world/pose_box.cpp).
#pragma once
#include <cfloat>

#include "common/cpu.hpp"

#if HGCD_AVX2
#include <immintrin.h>

namespace hgcd {
namespace broad {

// float_box's rounding down of four doubles (the 64-bit compare masks
// narrowed to 32 bits by one permute, tiny's in the odd halves).
#pragma GCC push_options
#pragma GCC target("avx2")
inline __m128 float_down4(__m256d x) {
    const __m128 f = _mm256_cvtpd_ps(x);
    const __m256d above = _mm256_cmp_pd(_mm256_cvtps_pd(f), x, _CMP_GT_OQ);
    const __m256d tiny = _mm256_cmp_pd(_mm256_andnot_pd(_mm256_set1_pd(-0.0), x), _mm256_set1_pd(FLT_MIN), _CMP_LT_OQ);
    const __m256i both = _mm256_permutevar8x32_epi32(
        _mm256_blend_epi32(_mm256_castpd_si256(above), _mm256_castpd_si256(tiny), 0xAA),
        _mm256_setr_epi32(0, 2, 4, 6, 1, 3, 5, 7));
    const __m128i up = _mm256_castsi256_si128(both), small = _mm256_extracti128_si256(both, 1);
    const __m128i bits = _mm_castps_si128(f), negative = _mm_srai_epi32(bits, 31);  // (f has x's sign)
    const __m128i down = _mm_sub_epi32(bits, _mm_and_si128(_mm_or_si128(negative, _mm_set1_epi32(1)), up));
    const __m128i floor = _mm_and_si128(negative, _mm_castps_si128(_mm_set1_ps(-FLT_MIN)));
    return _mm_castsi128_ps(_mm_or_si128(_mm_andnot_si128(small, down), _mm_and_si128(small, floor)));
}
#pragma GCC pop_options

}  // namespace broad
}  // namespace hgcd
#endif
