// The gather's box rounding four bodies at a time (AVX2, picked at run
// time): float_box's sums and rounding on four boxes per instruction.
#include "broad/float_box.hpp"
#include "broad/float_down_avx2.hpp"

#include "common/ieee.hpp"

#if HGCD_AVX2
#include <immintrin.h>

namespace hgcd {
namespace broad {

namespace {

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
