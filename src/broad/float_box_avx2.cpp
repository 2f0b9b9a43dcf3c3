// The gather's box rounding four bodies at a time (AVX2, picked at run
// time): float_box's sums and rounding on four boxes per instruction.
#include "broad/float_box.hpp"

#include "common/ieee.hpp"

#if HGCD_AVX2
#include <immintrin.h>

namespace hgcd {
namespace broad {

namespace {

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

// float_box for the bodies S[0..3], written to out[a][0..3].
__attribute__((target("avx2"))) inline void float_boxes4(const Boxes &boxes, const uint32_t *S, float *const *out) {
    const __m256i xyz = _mm256_setr_epi64x(-1, -1, -1, 0);
    __m256d lo[4], hi[4];
    for (int i = 0; i < 4; ++i) {
        const double *p = boxes.point(S[i]);
        const float *o = boxes.off + 6 * size_t(S[i]);
        const __m256d c = _mm256_maskload_pd(p, xyz);                  // x y z 0
        const __m128 ol = _mm_loadu_ps(o), oh = _mm_loadu_ps(o + 2);  // (lx ly lz hx), (lz hx hy hz)
        lo[i] = _mm256_add_pd(c, _mm256_cvtps_pd(ol));
        hi[i] = _mm256_add_pd(c, _mm256_cvtps_pd(_mm_shuffle_ps(oh, oh, _MM_SHUFFLE(3, 3, 2, 1))));
    }
    const __m256d sign = _mm256_set1_pd(-0.0);
    for (int h = 0; h < 2; ++h) {
        __m256d *r = h ? hi : lo;
        const __m256d t0 = _mm256_unpacklo_pd(r[0], r[1]), t1 = _mm256_unpackhi_pd(r[0], r[1]);
        const __m256d t2 = _mm256_unpacklo_pd(r[2], r[3]), t3 = _mm256_unpackhi_pd(r[2], r[3]);
        const __m256d axis[3] = {_mm256_permute2f128_pd(t0, t2, 0x20), _mm256_permute2f128_pd(t1, t3, 0x20),
                                 _mm256_permute2f128_pd(t0, t2, 0x31)};
        for (int a = 0; a < 3; ++a) {
            if (h == 0)
                _mm_storeu_ps(out[2 * a], float_down4(axis[a]));
            else  // (float_at_least: the low bound of the negated value, negated)
                _mm_storeu_ps(out[2 * a + 1],
                              _mm_xor_ps(float_down4(_mm256_xor_pd(axis[a], sign)), _mm_set1_ps(-0.0f)));
        }
    }
}

}  // namespace

__attribute__((target("avx2"))) size_t float_boxes_avx2(const Boxes &boxes, const uint32_t *S, size_t k, size_t e,
                                                        size_t end, float *const *arrays) {
    for (; k + 4 <= e; k += 4) {
        for (size_t a = k + kAhead; a < k + kAhead + 4 && a < end; ++a) {
            __builtin_prefetch(boxes.point(S[a]));
            __builtin_prefetch(boxes.off + 6 * size_t(S[a]));
        }
        float *const at[6] = {arrays[0] + k, arrays[1] + k, arrays[2] + k, arrays[3] + k, arrays[4] + k, arrays[5] + k};
        float_boxes4(boxes, S + k, at);
    }
    return k;
}

}  // namespace broad
}  // namespace hgcd
#endif
