// The sweep's box test eight boxes at a time (AVX2, picked at run time):
// included by sweep.cpp alone, whose sweeps instantiated with Lanes8 inside
// functions of the AVX2 target inline these helpers. (Vectors pass by
// reference: a default-target function may not take them by value.)
#pragma once
#include <immintrin.h>

#include <cstddef>
#include <cstdint>

#include "broad/grid.hpp"

namespace hgcd {
namespace broad {

struct Lanes8;
#pragma GCC push_options
#pragma GCC target("avx2")
static inline void splat8(Lanes8 &lanes, const Grid::BoxArrays &A, size_t i);
static inline unsigned test8(const Lanes8 &lanes, const Grid::BoxArrays &B, size_t j);
static inline unsigned below8(const float *p, float v);
static inline size_t write8(uint64_t *to, uint64_t a, const uint32_t *slot, unsigned hits);
#pragma GCC pop_options

// Box i of a list in every lane (lx..hz: its low x, high x, low y, ...),
// against eight boxes of a row at a time (see Lanes4 in sweep.cpp).
struct Lanes8 {
    static constexpr int kBlock = 8;
    __m256 lx, hx, ly, hy, lz, hz;
    inline __attribute__((always_inline)) Lanes8(const Grid::BoxArrays &A, size_t i) { splat8(*this, A, i); }
    inline __attribute__((always_inline)) unsigned test(const Grid::BoxArrays &B, size_t j) const {
        return test8(*this, B, j);
    }
    inline __attribute__((always_inline)) static unsigned below(const float *p, float v) { return below8(p, v); }
    inline __attribute__((always_inline)) static size_t write(uint64_t *to, uint64_t a, const uint32_t *slot,
                                                              unsigned hits) {
        return write8(to, a, slot, hits);
    }
};

// For each 8-bit set of hits, the lanes of its bits in order (the rest 0):
// the permutation that packs a block's hits to the front.
struct PackTable {
    alignas(32) uint32_t lanes[256][8];
    constexpr PackTable() : lanes() {
        for (unsigned m = 0; m < 256; ++m) {
            unsigned n = 0;
            for (unsigned k = 0; k < 8; ++k)
                if (m >> k & 1) lanes[m][n++] = k;
        }
    }
};
constexpr PackTable kPack;

#pragma GCC push_options
#pragma GCC target("avx2")
static inline void splat8(Lanes8 &lanes, const Grid::BoxArrays &A, size_t i) {
    lanes.lx = _mm256_set1_ps(A.low_x[i]);
    lanes.hx = _mm256_set1_ps(A.high_x[i]);
    lanes.ly = _mm256_set1_ps(A.low_y[i]);
    lanes.hy = _mm256_set1_ps(A.high_y[i]);
    lanes.lz = _mm256_set1_ps(A.low_z[i]);
    lanes.hz = _mm256_set1_ps(A.high_z[i]);
}
static inline unsigned test8(const Lanes8 &lanes, const Grid::BoxArrays &B, size_t j) {
    const __m256 in_x = _mm256_and_ps(_mm256_cmp_ps(_mm256_loadu_ps(B.low_x + j), lanes.hx, _CMP_LE_OQ),
                                      _mm256_cmp_ps(lanes.lx, _mm256_loadu_ps(B.high_x + j), _CMP_LE_OQ));
    const __m256 in_y = _mm256_and_ps(_mm256_cmp_ps(_mm256_loadu_ps(B.low_y + j), lanes.hy, _CMP_LE_OQ),
                                      _mm256_cmp_ps(lanes.ly, _mm256_loadu_ps(B.high_y + j), _CMP_LE_OQ));
    const __m256 in_z = _mm256_and_ps(_mm256_cmp_ps(_mm256_loadu_ps(B.low_z + j), lanes.hz, _CMP_LE_OQ),
                                      _mm256_cmp_ps(lanes.lz, _mm256_loadu_ps(B.high_z + j), _CMP_LE_OQ));
    return unsigned(_mm256_movemask_ps(_mm256_and_ps(in_x, _mm256_and_ps(in_y, in_z))));
}
static inline unsigned below8(const float *p, float v) {
    return unsigned(_mm256_movemask_ps(_mm256_cmp_ps(_mm256_loadu_ps(p), _mm256_set1_ps(v), _CMP_LT_OQ)));
}
// The hits' slots packed to the front by one permutation, widened to pairs:
// two stores where write_hits does eight.
static inline size_t write8(uint64_t *to, uint64_t a, const uint32_t *slot, unsigned hits) {
    const __m256i packed =
        _mm256_permutevar8x32_epi32(_mm256_loadu_si256(reinterpret_cast<const __m256i *>(slot)),
                                    _mm256_load_si256(reinterpret_cast<const __m256i *>(kPack.lanes[hits])));
    const __m256i high = _mm256_set1_epi64x(int64_t(a));
    _mm256_storeu_si256(reinterpret_cast<__m256i *>(to),
                        _mm256_or_si256(high, _mm256_cvtepu32_epi64(_mm256_castsi256_si128(packed))));
    _mm256_storeu_si256(reinterpret_cast<__m256i *>(to + 4),
                        _mm256_or_si256(high, _mm256_cvtepu32_epi64(_mm256_extracti128_si256(packed, 1))));
    return size_t(__builtin_popcount(hits));
}
#pragma GCC pop_options

}  // namespace broad
}  // namespace hgcd
