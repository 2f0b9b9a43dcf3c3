// The boxes as the grid's lists hold them: each bound rounded outward to
// float, as float_at_most and float_at_least do (grid.hpp), half the bytes
// of doubles and twice the boxes to a vector compare.
#pragma once
#include <cfloat>
#include <cstddef>
#include <cstdint>

#include "broad/grid.hpp"
#include "common/cpu.hpp"

#if defined(__SSE2__)
#include <immintrin.h>
#endif

namespace hgcd {
namespace broad {

// The box [dlo, dhi] rounded outward to float: lo[k] = float_at_most(dlo[k]),
// hi[k] = float_at_least(dhi[k]), the same bits, without a branch. SSE2
// converts two at a time in whole registers: scalar cvtsd2ss keeps the rest
// of its destination register, which chained every conversion of a gather.
// Rounded down as integers: a float's bits step down by 1 when it is
// positive and up by 1 when negative, so the highs are rounded down negated;
// magnitudes below FLT_MIN (tested on the double, which reads a subnormal as
// 0 under DAZ: still below) go to 0 or, by the sign bit, -FLT_MIN.
inline void round_outward(const double *dlo, const double *dhi, float *lo, float *hi) {
#if defined(__SSE2__)
    auto down2 = [](__m128d x) {
        const __m128 f = _mm_cvtpd_ps(x);
        const __m128i above =
            _mm_shuffle_epi32(_mm_castpd_si128(_mm_cmpgt_pd(_mm_cvtps_pd(f), x)), _MM_SHUFFLE(3, 3, 2, 0));
        const __m128i bits = _mm_castps_si128(f);
        const __m128i step = _mm_and_si128(_mm_or_si128(_mm_srai_epi32(bits, 31), _mm_set1_epi32(1)), above);
        const __m128i down = _mm_sub_epi32(bits, step);
        const __m128d magnitude = _mm_andnot_pd(_mm_set1_pd(-0.0), x);
        const __m128i tiny = _mm_shuffle_epi32(_mm_castpd_si128(_mm_cmplt_pd(magnitude, _mm_set1_pd(FLT_MIN))),
                                               _MM_SHUFFLE(3, 3, 2, 0));
        const __m128i negative = _mm_shuffle_epi32(_mm_srai_epi32(_mm_castpd_si128(x), 31), _MM_SHUFFLE(3, 3, 3, 1));
        const __m128i floor = _mm_and_si128(negative, _mm_castps_si128(_mm_set1_ps(-FLT_MIN)));
        return _mm_castsi128_ps(_mm_or_si128(_mm_andnot_si128(tiny, down), _mm_and_si128(tiny, floor)));
    };
    alignas(16) float t[12];
    _mm_store_ps(t, down2(_mm_set_pd(dlo[1], dlo[0])));
    _mm_store_ps(t + 4, down2(_mm_set_pd(-dhi[0], dlo[2])));
    _mm_store_ps(t + 8, down2(_mm_set_pd(-dhi[2], -dhi[1])));
    lo[0] = t[0], lo[1] = t[1], lo[2] = t[4];
    hi[0] = -t[5], hi[1] = -t[8], hi[2] = -t[9];
#else
    for (int k = 0; k < 3; ++k) {
        lo[k] = float_at_most(dlo[k]);
        hi[k] = float_at_least(dhi[k]);
    }
#endif
}

// Body s's box [fl(p + low), fl(p + high)] rounded outward to float.
inline void float_box(const Boxes &boxes, uint32_t s, float *lo, float *hi) {
    double dlo[3], dhi[3];
    boxes.at(s, dlo, dhi);
    round_outward(dlo, dhi, lo, hi);
}

// float_box's low x alone (float_at_most of the same double), where only
// that one is needed.
inline float float_low_x(const Boxes &boxes, uint32_t s) {
    return float_at_most(boxes.point(s)[0] + double(boxes.off[6 * size_t(s)]));
}

// How many entries ahead the gather asks for the boxes it will read (the
// bodies' storage drifts from the sweep order between renumberings).
constexpr size_t kAhead = 48;

#if HGCD_AVX2
// float_box for the bodies S[k..e) four at a time (float_box_avx2.cpp),
// written to arrays[a][k..] (a: low x, high x, low y, high y, low z, high z):
// the same sums and the same bits. Returns where it stopped (those left at
// the end are for float_box). end: how far ahead the prefetches may look.
size_t float_boxes_avx2(const Boxes &boxes, const uint32_t *S, size_t k, size_t e, size_t end,
                        float *const *arrays);
#endif

}  // namespace broad
}  // namespace hgcd
