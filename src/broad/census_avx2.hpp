// The census's usual case four bodies at a time (AVX2, picked at run time):
// included by census.cpp alone.
#pragma once
#include <immintrin.h>

#include <cstddef>
#include <cstdint>

#include "broad/cells.hpp"

namespace hgcd {
namespace broad {

// Whether nothing changes for the bodies in slots s to s + 3: each is live
// with the generation last seen, its level exponent at most max_exponent
// and not oversize, on the level of the last update, and its cell there on
// both axes the one kept. The same tests as the census's own, on the same
// values: the oversize sum in its order, and x * 2^-e (exact) whose floor,
// below 2^51 in magnitude, is read from the bits of floor + 1.5 * 2^52.
// inv[l]: 2^-(exponent + row shift) of level l, 0 where that leaves the
// normal range (those bodies take the census's own path). e: the four
// exponents when true.
__attribute__((target("avx2"))) inline bool bodies_unchanged4(size_t s, const double *point,
                                                               const uint32_t *live_gen, const uint32_t *gen,
                                                               const int16_t *exponent, const float *slack,
                                                               const int16_t *level, const int64_t *cell,
                                                               const int16_t *level_of, const double *inv,
                                                               int max_exponent, int *e) {
    const __m128i live = _mm_loadu_si128(reinterpret_cast<const __m128i *>(live_gen + s));
    const __m128i seen = _mm_loadu_si128(reinterpret_cast<const __m128i *>(gen + s));
    if (_mm_movemask_epi8(_mm_or_si128(_mm_cmpeq_epi32(live, _mm_setzero_si128()),
                                       _mm_xor_si128(_mm_cmpeq_epi32(live, seen), _mm_set1_epi32(-1)))))
        return false;
    double scale[4];
    for (int k = 0; k < 4; ++k) {
        e[k] = exponent[s + k];
        if (e[k] > max_exponent) return false;
        const int16_t li = level_of[e[k] + kExponentBias];
        if (li < 0 || li != level[s + k] || inv[li] == 0) return false;
        scale[k] = inv[li];
    }
    // Points (x y z) of the four as rows, to columns x, y, z.
    const double *p = point + 3 * s;
    const __m256d r0 = _mm256_loadu_pd(p), r1 = _mm256_loadu_pd(p + 4), r2 = _mm256_loadu_pd(p + 8);
    // r0 = x0 y0 z0 x1, r1 = y1 z1 x2 y2, r2 = z2 x3 y3 z3
    const __m256d x = _mm256_setr_pd(r0[0], r0[3], r1[2], r2[1]), y = _mm256_setr_pd(r0[1], r1[0], r1[3], r2[2]),
                  z = _mm256_setr_pd(r0[2], r1[1], r2[0], r2[3]);
    const __m256d sign = _mm256_set1_pd(-0.0);
    const __m256d sum = _mm256_add_pd(_mm256_add_pd(_mm256_andnot_pd(sign, x), _mm256_andnot_pd(sign, y)),
                                      _mm256_andnot_pd(sign, z));
    const __m256d room = _mm256_cvtps_pd(_mm_loadu_ps(slack + s));
    if (_mm256_movemask_pd(_mm256_cmp_pd(_mm256_mul_pd(_mm256_set1_pd(kOversizeFactor), sum), room, _CMP_GT_OQ)))
        return false;
    // (The scales from registers: a vector load of the four stores stalled
    // on store forwarding.)
    const __m256d inv4 = _mm256_setr_pd(scale[0], scale[1], scale[2], scale[3]);
    const __m256d vy = _mm256_mul_pd(y, inv4), vz = _mm256_mul_pd(z, inv4);
    const __m256d limit = _mm256_set1_pd(0x1p51);
    if (_mm256_movemask_pd(_mm256_or_pd(_mm256_cmp_pd(_mm256_andnot_pd(sign, vy), limit, _CMP_NLT_UQ),
                                        _mm256_cmp_pd(_mm256_andnot_pd(sign, vz), limit, _CMP_NLT_UQ))))
        return false;
    const __m256d magic = _mm256_set1_pd(0x1.8p52);
    const __m256i cy = _mm256_sub_epi64(_mm256_castpd_si256(_mm256_add_pd(_mm256_floor_pd(vy), magic)),
                                        _mm256_castpd_si256(magic));
    const __m256i cz = _mm256_sub_epi64(_mm256_castpd_si256(_mm256_add_pd(_mm256_floor_pd(vz), magic)),
                                        _mm256_castpd_si256(magic));
    // Kept cells: y0 z0 y1 z1 | y2 z2 y3 z3.
    const __m256i k0 = _mm256_loadu_si256(reinterpret_cast<const __m256i *>(cell + 2 * s));
    const __m256i k1 = _mm256_loadu_si256(reinterpret_cast<const __m256i *>(cell + 2 * s + 4));
    const __m256i ky = _mm256_permute4x64_epi64(_mm256_unpacklo_epi64(k0, k1), 0xD8);
    const __m256i kz = _mm256_permute4x64_epi64(_mm256_unpackhi_epi64(k0, k1), 0xD8);
    const __m256i same = _mm256_and_si256(_mm256_cmpeq_epi64(cy, ky), _mm256_cmpeq_epi64(cz, kz));
    return _mm256_movemask_pd(_mm256_castsi256_pd(same)) == 0xF;
}

}  // namespace broad
}  // namespace hgcd
