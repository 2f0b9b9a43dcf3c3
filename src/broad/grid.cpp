#include "broad/grid.hpp"

#include <omp.h>

#include <algorithm>
#include <cfloat>
#include <climits>
#include <cmath>
#include <cstring>
#include <stdexcept>

#include "common/cpu.hpp"
#include "common/ieee.hpp"
#include "common/parallel.hpp"
#include "world/permute.hpp"

#if defined(__SSE2__)
#include <immintrin.h>
#endif

namespace hgcd {

namespace {

// Body s's box [fl(p + low), fl(p + high)] rounded outward to float as
// float_at_most and float_at_least do (grid.hpp): what the lists hold,
// half the bytes of doubles and twice the boxes to a vector compare. SSE2
// converts two at a time in whole registers: scalar cvtsd2ss keeps the rest
// of its destination register, which chained every conversion of a gather
// (update 22 -> 39 ms, tetra 750k). Rounded down as integers: a float's
// bits step down by 1 when it is positive and up by 1 when negative, so the
// highs are rounded down negated; magnitudes below FLT_MIN (tested on the
// double, which reads a subnormal as 0 under DAZ: still below) go to 0 or,
// by the sign bit, -FLT_MIN.
inline void float_box(const Boxes &boxes, uint32_t s, float *lo, float *hi) {
    double dlo[3], dhi[3];
    boxes.at(s, dlo, dhi);
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

// How many entries ahead the gather asks for the boxes it will read: on
// tetra 750k (1 thread) 16 took 10.7 ms a gather right after a
// renumbering and 13.0 ms 20-40 ticks after it, 48 took 9.4 and 11.1.
constexpr size_t kAhead = 48;

#if HGCD_AVX2
// float_box for the bodies S[0..3], written to out[a][0..3] (a: low x, high
// x, low y, high y, low z, high z): the same sums and the same rounding,
// four at a time (the 64-bit compare masks narrowed to 32 bits by one
// permute, tiny's in the odd halves).
#pragma GCC push_options
#pragma GCC target("avx2")
static inline __m128 float_down4(__m256d x) {
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

__attribute__((target("avx2"))) static inline void float_boxes4(const Boxes &boxes, const uint32_t *S,
                                                                float *const *out) {
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

// float_boxes4 over the entries [k, e) of a list four at a time (those left
// at the end for float_box): returns where it stopped. (end: the part's end,
// how far ahead the prefetches may look.)
__attribute__((target("avx2"))) size_t float_boxes_avx2(const Boxes &boxes, const uint32_t *S, size_t k, size_t e,
                                                        size_t end, float *const *arrays) {
    for (; k + 4 <= e; k += 4) {
        // Later bodies' points and offsets (storage drifts from this order
        // between renumberings, bodies that changed rows are elsewhere):
        // asked for early.
        for (size_t a = k + kAhead; a < k + kAhead + 4 && a < end; ++a) {
            __builtin_prefetch(boxes.point(S[a]));
            __builtin_prefetch(boxes.off + 6 * size_t(S[a]));
        }
        float *const at[6] = {arrays[0] + k, arrays[1] + k, arrays[2] + k, arrays[3] + k, arrays[4] + k, arrays[5] + k};
        float_boxes4(boxes, S + k, at);
    }
    return k;
}
#endif

// float_box's low x alone (float_at_most of the same double), where only
// that one is needed.
inline float float_low_x(const Boxes &boxes, uint32_t s) {
    return float_at_most(boxes.point(s)[0] + double(boxes.off[6 * size_t(s)]));
}

// Row coordinates (y and z) are kept in 42 bits each so a row key packs into
// 128 bits. Clamping is monotone and never increases a difference, so two
// bodies in neighbouring rows stay in neighbouring (or equal) rows: far-away
// bodies only crowd the border rows, they are never missed (x is swept on
// the boxes themselves).
constexpr int64_t kCoordLimit = (int64_t(1) << 41) - 2;
constexpr int64_t kCoordBias = int64_t(1) << 41;
constexpr int64_t kSaturate = int64_t(1) << 62;
constexpr int kAxisBits = 42;
constexpr uint64_t kAxisMask = (uint64_t(1) << kAxisBits) - 1;
constexpr size_t kChunk = 1024;
// Level exponents e (cell width 2^e, from the bits of a positive double)
// lie in [-1074, 1024]; tables over them are indexed by e + kExponentBias.
constexpr int kExponentBias = 1080;
constexpr int kExponents = 2110;
// A body is oversize once kOversizeFactor |p|_1 passes its slack (the
// census, Grid::update, argues the factor).
constexpr double kOversizeFactor = 4e-16;
// Slots the census takes at a time (and hands to a SlotPass).
constexpr int64_t kCensusBlock = 256;
constexpr size_t kPad = 16;  // readable entries past the end of a list's box arrays (>= two blocks: scan)
// Rows are 2^kRowShift cells high and deep.
constexpr int kRowShift = 1;
// Reach bits: the neighbouring rows a box can reach (RowReach).
constexpr uint8_t kReachYLo = 1, kReachYHi = 2, kReachZLo = 4, kReachZHi = 8, kReachAll = 15;

// The bits a box needs to meet the row (z + dz, y + dy).
inline uint8_t reach_needed(int dz, int dy) {
    return uint8_t((dy < 0 ? kReachYLo : dy > 0 ? kReachYHi : 0) | (dz < 0 ? kReachZLo : dz > 0 ? kReachZHi : 0));
}

// 2^k for |k| < 1000, built from the exponent bits (no libm call).
inline double pow2(int k) {
    const uint64_t bits = uint64_t(k + 1023) << 52;
    double d;
    std::memcpy(&d, &bits, sizeof d);
    return d;
}

// 2^k for any k a level can have (cell widths).
inline double cell_width(int k) { return k > -1000 && k < 1000 ? pow2(k) : std::ldexp(1.0, k); }

// 2^-e where x * 2^-e by a product stays exact (pow2's range), else 0:
// cell_coord then scales by ldexp.
inline double cell_scale(int exponent) { return exponent > -1000 && exponent < 1000 ? pow2(-exponent) : 0.0; }

inline int64_t cell_coord(double x, int exponent) {
    // x * 2^-e is exact (a power-of-two scale) unless it leaves the normal
    // range, where ldexp keeps it exact too.
    const double scale = cell_scale(exponent);
    const double v = scale != 0 ? x * scale : std::ldexp(x, -exponent);
    if (!(v < double(kSaturate))) return kSaturate;
    if (!(v > -double(kSaturate))) return -kSaturate;
    // floor without a libm call (baseline x86-64 has no rounding instruction)
    const int64_t t = int64_t(v);
    return t - (v < double(t));
}

inline uint64_t clamp_bias(int64_t c) {
    c = std::min(std::max(c, -kCoordLimit), kCoordLimit);
    return uint64_t(c + kCoordBias);
}

// The key of the row of cells (z, y): the grid is sparse in y and z, and
// each row is a sweep along x.
inline CellKey row_key(uint64_t z, uint64_t y) { return (CellKey(z) << kAxisBits) | CellKey(y); }

// Smallest e with 2^e >= d, for finite d > 0 (from the bits: this runs for
// every body on every tick).
inline int ceil_log2(double d) {
    uint64_t bits;
    std::memcpy(&bits, &d, sizeof bits);
    const int biased = int(bits >> 52) & 0x7ff;
    if (biased == 0) {  // subnormal: rare, leave it to libm
        int k;
        const double m = std::frexp(d, &k);
        return m == 0.5 ? k - 1 : k;
    }
    const bool power = (bits & ((uint64_t(1) << 52) - 1)) == 0;
    return biased - 1023 + (power ? 0 : 1);
}

inline size_t first_row(const std::vector<CellKey> &keys, CellKey target) {
    return size_t(std::lower_bound(keys.begin(), keys.end(), target) - keys.begin());
}

// (A template so that Grid's members can name their private Keyed.)
template <class T>
struct ByRowX {
    bool operator()(const T &a, const T &b) const {
        const CellKey ka = a.key, kb = b.key;  // by value: the member is packed
        return ka < kb || (ka == kb && (a.x < b.x || (a.x == b.x && a.slot < b.slot)));
    }
};

// Cuts of a list's rows into runs of whole rows holding about `part`
// entries each: run k is rows [cut[k], cut[k + 1]). (By the row index, as
// the last rebuild or update_lists left it.)
template <class ListT>
std::vector<size_t> row_cuts(const ListT &list, size_t part) {
    const size_t rows = list.row_keys.size();
    std::vector<size_t> cut{0};
    for (size_t r = 0; r < rows;) {
        size_t e = r + 1;
        while (e < rows && list.row_start[e] - list.row_start[r] < part) ++e;
        cut.push_back(e);
        r = e;
    }
    return cut;
}

}  // namespace

CellKey Grid::key_at(const int64_t *cell, int own, int level_index) const {
    const int shift = std::min(levels_[level_index].exponent - levels_[own].exponent, 63);
    return row_key(clamp_bias(cell[1] >> shift), clamp_bias(cell[0] >> shift));
}

CellKey Grid::key_of(uint32_t slot, int level_index) const {
    return key_at(&cell_[2 * size_t(slot)], level_[slot], level_index);
}

void Grid::cell_at(const double *p, int level_index, int64_t *cell) const {
    const int e = levels_[level_index].exponent + kRowShift;
    cell[0] = cell_coord(p[1], e);
    cell[1] = cell_coord(p[2], e);
}

#if HGCD_AVX2
// The census's usual case four bodies at a time (slots s to s + 3): each is
// live with the generation last seen, its level exponent at most
// max_exponent and not oversize, on the level of the last update, and its
// cell there on both axes the one kept, so nothing about it changes. The
// same tests as the census's own, on the same values: the oversize sum in
// its order, and x * 2^-e (exact) whose floor, below 2^51 in magnitude, is
// read from the bits of floor + 1.5 * 2^52. inv[l]: 2^-(exponent + row
// shift) of level l, 0 where that leaves the normal range (those bodies
// take the census's own path). e: the four exponents when true.
__attribute__((target("avx2"))) bool quiet4(size_t s, const double *point, const uint32_t *live_gen,
                                          const uint32_t *gen, const int16_t *exponent, const float *slack,
                                          const int16_t *level, const int64_t *cell, const int16_t *level_of,
                                          const double *inv, int max_exponent, int *e) {
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
    if (_mm256_movemask_pd(_mm256_cmp_pd(_mm256_mul_pd(_mm256_set1_pd(kOversizeFactor), sum), room, _CMP_GT_OQ))) return false;
    // (From registers: a vector load of the four stores stalled on store
    // forwarding, 36% of the samples in this function.)
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
#endif

GridUpdateStats Grid::update(const Boxes &boxes, const double *r_level, const uint32_t *live_gen,
                             uint32_t slot_count, const GridLimits &limits, int threads,
                             const SlotPass *before) {
    GridUpdateStats stats;
    level_.resize(slot_count, kNone);
    gen_.resize(slot_count, 0);
    cell_.resize(2 * size_t(slot_count), 0);
    exponent_.resize(slot_count, 0);
    slack_.resize(slot_count, 0);
    const bool stale_exponents = limits.min_exponent != exponent_floor_;
    exponent_floor_ = limits.min_exponent;
    // The level exponent of a live body: the smallest e with 2^e at least
    // 2 r_level (kept per slot while the body is the same, with the slack
    // 2^e - 2 r_level), or oversize (INT_MAX) when the rounding of p +
    // offset, which grows with p, could take its box farther than 2^e / 2
    // from p: each coordinate of fl(p + offset) is within 2^-53 (|p| +
    // r_level) of exact, which 4e-16 |p|_1 < slack and r_level's own
    // inflation (the world's, relative) cover.
    // The level of exponent e (INT_MIN: none, INT_MAX: oversize), by the
    // table of the last update (level_of_, replaced once the census is in).
    auto level_index = [&](int e) -> int16_t {
        return e == INT_MIN ? kNone : e == INT_MAX ? kOversize : level_of_[e + kExponentBias];
    };
    auto exponent_of = [&](int64_t s) {
        const int e = exponent_[s];
        const double *p = boxes.point(size_t(s));
        return e > limits.max_exponent || kOversizeFactor * (std::fabs(p[0]) + std::fabs(p[1]) + std::fabs(p[2])) > slack_[s]
                   ? INT_MAX
                   : e;
    };
    // One pass over the bodies. Per slot, the level exponent (INT_MIN: empty
    // slot, INT_MAX: oversize), and per thread a histogram of the exponents
    // (a count per possible exponent: no branch on which exponent a body
    // has, which is random) and the oversize slots, ascending (static
    // schedule: thread t has the t-th range of slots). In the same pass,
    // taking the levels to be those of the last update (they nearly always
    // are), each body's row there and a flag: 0 same row, 1 moved to another
    // row of the same level, 2 membership changed (new, destroyed, slot
    // reused, or other level). A body whose own row is unchanged keeps every
    // coarser row too, so only flagged bodies touch the lists (moves along x
    // never do). Should the census give other levels, the grid is rebuilt.
    const bool incremental = built_;
    const size_t L = levels_.size();
    std::vector<uint64_t> histogram(size_t(threads) * kExponents, 0);
    std::vector<std::vector<uint32_t>> oversize_local(threads);
    std::vector<uint8_t> flag(incremental ? slot_count : 0, 0);
    std::vector<std::vector<Moved>> changed_local(threads);
    // Per thread, its count of flagged bodies per level, a cache line apart
    // from the next thread's.
    const size_t touched_stride = (L + 7) / 8 * 8 + 8;
    std::vector<uint64_t> touched_local(size_t(threads) * touched_stride, 0);
    uint64_t flagged = 0;
    const int64_t blocks = (int64_t(slot_count) + kCensusBlock - 1) / kCensusBlock;
#if HGCD_AVX2
    // Four bodies at a time where nothing changes for them (quiet4): on an
    // incremental update whose exponents are not stale. inv: per level,
    // the scale of its rows (0 where cell_coord takes ldexp).
    const bool quiet = incremental && !stale_exponents && use_avx2();
    std::vector<double> inv(L);
    for (size_t l = 0; l < L; ++l) inv[l] = cell_scale(levels_[l].exponent + kRowShift);
#endif
    {
        RegionGuard guard;
#pragma omp parallel num_threads(threads) reduction(+ : flagged)
        {
            const IeeeMode ieee;
            const int me = omp_get_thread_num();
            uint64_t *hist = histogram.data() + size_t(me) * kExponents;
            // What the thread appends, in vectors of its own frame (the
            // per-thread vectors share cache lines) handed over after the
            // loop.
            std::vector<uint32_t> oversize_mine;
            std::vector<Moved> changed_mine;
            uint64_t *my_touched = touched_local.data() + size_t(me) * touched_stride;
#pragma omp for schedule(static) nowait
            for (int64_t block = 0; block < blocks; ++block) {
                const uint32_t block_end = uint32_t(std::min<int64_t>(slot_count, (block + 1) * kCensusBlock));
                if (before) before->run(before->context, uint32_t(block * kCensusBlock), block_end);
                for (int64_t s = block * kCensusBlock; s < int64_t(block_end); ++s) {
#if HGCD_AVX2
                    if (quiet && s % 4 == 0 && s + 4 <= int64_t(block_end)) {
                        int e4[4];
                        if (quiet4(size_t(s), boxes.pos, live_gen, gen_.data(), exponent_.data(), slack_.data(),
                                   level_.data(), cell_.data(), level_of_.data(), inv.data(), limits.max_exponent,
                                   e4)) {
                            for (int k = 0; k < 4; ++k) {
                                ++hist[e4[k] + kExponentBias];
                                flag[size_t(s) + k] = 0;
                            }
                            s += 3;
                            continue;
                        }
                    }
#endif
                    int e = INT_MIN;
                    if (live_gen[s]) {
                        if (gen_[s] != live_gen[s] || stale_exponents) {
                            const double h2 = 2 * r_level[s];
                            const int e = std::max(ceil_log2(h2), limits.min_exponent);
                            exponent_[s] = int16_t(e);
                            // (Rounded down to float; 0 when it is not positive: oversize.)
                            const double slack = cell_width(e) - h2;
                            slack_[s] = std::max(float_at_most(slack), 0.0f);
                        }
                        e = exponent_of(s);
                        if (e == INT_MAX) guard.run([&] { oversize_mine.push_back(uint32_t(s)); });
                        else ++hist[e + kExponentBias];
                    }
                    if (!incremental) {
                        gen_[s] = live_gen[s];
                        continue;
                    }
                    const int16_t li = level_index(e);
                    int64_t c[2] = {0, 0};
                    if (li >= 0) cell_at(boxes.point(size_t(s)), li, c);
                    int64_t *old = &cell_[2 * s];
                    uint8_t f = 0;
                    if (li != level_[s] || gen_[s] != live_gen[s]) f = 2;
                    else if (li >= 0 && (c[0] != old[0] || c[1] != old[1])) f = 1;
                    flag[s] = f;
                    if (f) {  // (most bodies keep their row: their state is not written)
                        const float x = li >= 0 ? float_low_x(boxes, uint32_t(s)) : 0.0f;
                        guard.run([&] {
                            changed_mine.push_back(
                                Moved{uint32_t(s), level_[s], li, x, {old[0], old[1]}, {c[0], c[1]}});
                        });
                        ++flagged;
                        if (level_[s] >= 0) ++my_touched[level_[s]];
                        if (li >= 0) ++my_touched[li];
                        level_[s] = li;
                        gen_[s] = live_gen[s];
                        old[0] = c[0];
                        old[1] = c[1];
                    }
                }
            }
            oversize_local[me].swap(oversize_mine);
            changed_local[me].swap(changed_mine);
        }
        guard.rethrow();
    }
    std::vector<std::pair<int, uint64_t>> census;  // (exponent, bodies), ascending
    for (int k = 0; k < kExponents; ++k) {
        uint64_t count = 0;
        for (int t = 0; t < threads; ++t) count += histogram[size_t(t) * kExponents + size_t(k)];
        if (count) census.push_back({k - kExponentBias, count});
    }
    // A level whose bodies are very few beside the bodies of the finer levels
    // keeps no guest list: its residents query the finer levels by range
    // instead (scene tetra at 750k has 1 or 2 bodies a hair above radius 2 on
    // a fourth level, which would otherwise carry every other body as a
    // guest). Hysteresis on the level's previous choice keeps it from flapping.
    auto down_flags = [&](const std::vector<std::pair<int, uint64_t>> &levels) {
        std::vector<uint8_t> down(levels.size(), 0);
        uint64_t finer = 0;
        for (size_t i = 0; i < levels.size(); ++i) {
            bool was = false;
            for (const Level &lv : levels_) was |= built_ && lv.exponent == levels[i].first && lv.down;
            const uint64_t own = levels[i].second;
            down[i] = was ? own * 16 < finer : own * 64 < finer;
            finer += own;
        }
        return down;
    };
    // Coarsening: the levels within a factor 4 below the coarsest one that
    // keeps guests join it (see GridLimits::coarsen): the exponents
    // [join_lo, join_to) go to the level of exponent join_to.
    int join_lo = 0, join_to = 0;
    if (limits.coarsen && census.size() > 1) {
        const std::vector<uint8_t> few = down_flags(census);
        size_t top = census.size();
        while (top > 0 && few[top - 1]) --top;
        if (top > 0) {
            const int te = census[top - 1].first, lo = te - 2;
            size_t first = top - 1;
            while (first > 0 && census[first - 1].first >= lo) --first;
            if (first < top - 1) {
                for (size_t i = first; i + 1 < top; ++i) census[top - 1].second += census[i].second;
                census.erase(census.begin() + std::ptrdiff_t(first), census.begin() + std::ptrdiff_t(top - 1));
                join_lo = lo;
                join_to = te;
            }
        }
    }
    // Each exponent's level, by table.
    std::vector<int16_t> level_of(kExponents, kNone);
    for (size_t i = 0; i < census.size(); ++i) level_of[census[i].first + kExponentBias] = int16_t(i);
    for (int e = join_lo; e < join_to; ++e) level_of[e + kExponentBias] = level_of[join_to + kExponentBias];
    const std::vector<uint8_t> down = down_flags(census);
    bool same_levels = incremental && census.size() == levels_.size() && level_of == level_of_;
    for (size_t i = 0; same_levels && i < census.size(); ++i)
        same_levels = levels_[i].exponent == census[i].first && levels_[i].down == bool(down[i]);
    level_of_.swap(level_of);

    if (!same_levels) {
        levels_.clear();
        levels_.resize(census.size());
        for (size_t i = 0; i < census.size(); ++i) {
            levels_[i].exponent = census[i].first;
            levels_[i].down = down[i] != 0;
        }
#pragma omp parallel num_threads(threads)
        {
            const IeeeMode ieee;
#pragma omp for schedule(static)
            for (int64_t s = 0; s < int64_t(slot_count); ++s) {
                level_[s] = level_index(live_gen[s] ? exponent_of(s) : INT_MIN);
                gen_[s] = live_gen[s];
                if (level_[s] >= 0) cell_at(boxes.point(size_t(s)), level_[s], &cell_[2 * s]);
            }
        }
        rebuild(boxes, slot_count, threads);
        stats.rebuilt = true;
        stats.moved = slot_count;  // every body (re-)entered
    } else {
        std::vector<uint64_t> touched(L, 0);
        for (int t = 0; t < threads; ++t)
            for (size_t l = 0; l < L; ++l) touched[l] += touched_local[size_t(t) * touched_stride + l];
        std::vector<Moved> changed;
        for (auto &v : changed_local) changed.insert(changed.end(), v.begin(), v.end());
        uint64_t moved_finer = 0;  // flagged bodies on levels below li
        std::vector<uint8_t> dirty(2 * L, 0);
        for (size_t li = 0; li < L; ++li) {
            dirty[2 * li] = touched[li] != 0;
            dirty[2 * li + 1] = moved_finer != 0 && !levels_[li].down;
            moved_finer += touched[li];
        }
        update_lists(dirty, flag, changed, threads);
        stats.moved = flagged;
    }
    disorder_ = gather(all_lists(), boxes, threads);
    oversize_.clear();
    for (const auto &local : oversize_local) oversize_.insert(oversize_.end(), local.begin(), local.end());
    built_ = true;
    return stats;
}

void Grid::rebuild(const Boxes &boxes, uint32_t slot_count, int threads) {
    std::vector<std::vector<Keyed>> keyed(2 * levels_.size());  // by list, as all_lists()
    for (uint32_t s = 0; s < slot_count; ++s) {
        const int16_t own = level_[s];
        if (own < 0) continue;
        const float x = float_low_x(boxes, s);  // (the low x the lists will hold)
        keyed[2 * size_t(own)].push_back({key_of(s, own), s, x});
        for (size_t li = size_t(own) + 1; li < levels_.size(); ++li)
            if (!levels_[li].down) keyed[2 * li + 1].push_back({key_of(s, int(li)), s, x});
    }
    const int64_t lists = int64_t(2 * levels_.size());
    RegionGuard guard;
#pragma omp parallel num_threads(threads)
    {
        const IeeeMode ieee;
#pragma omp for schedule(dynamic, 1)
        for (int64_t k = 0; k < lists; ++k) guard.run([&] {
            List &list = list_at(size_t(k));
            // Rows sorted by low x (the lists' float copy: no random reads in
            // the comparisons, and gather finds the order made).
            std::vector<Keyed> &in = keyed[size_t(k)];
            std::sort(in.begin(), in.end(), ByRowX<Keyed>());
            list.bslot.resize(in.size());
            list.row_keys.clear();
            list.row_start.clear();
            for (size_t i = 0; i < in.size(); ++i) {
                list.bslot[i] = in[i].slot;
                const CellKey key = in[i].key;  // (by value: the member is packed)
                if (i == 0 || key != list.row_keys.back()) {
                    list.row_keys.push_back(key);
                    list.row_start.push_back(uint32_t(i));
                }
            }
            list.row_start.push_back(uint32_t(in.size()));
            std::vector<Keyed>().swap(in);
        });
    }
    guard.rethrow();
}

// Brings the lists marked dirty (residents of level k / 2 at even k, guests
// at odd k) to the flagged bodies (changed: their slots, and their levels,
// rows and low x before and after this update): their entries leave, and those that belong to a list
// now enter it at their place by (row, x) (x as of the last gather for the
// others), so that gather's insertion sort has little left to do; the row
// index follows (rows emptied go, rows entered come). Each list is
// rewritten into its spare array in parts of whole rows, in parallel:
// where each part's output starts follows from the entries it loses, known
// without reading it (a flagged body's old row names the part its entry is
// in, by the row index), and from the entries that enter in its range of
// rows. One pass reads and writes each slot once.
void Grid::update_lists(const std::vector<uint8_t> &dirty, const std::vector<uint8_t> &flag,
                        const std::vector<Moved> &changed, int threads) {
    constexpr size_t kPart = 32768;  // entries
    struct Work {
        List *list;
        const std::vector<Keyed> *add;
        size_t row_b, row_e, add_b, add_e, out_b, out_e;
    };
    std::vector<Work> work;
    std::vector<std::vector<Keyed>> adds(dirty.size());
    for (size_t k = 0; k < dirty.size(); ++k) {
        if (!dirty[k]) continue;
        const int li = int(k / 2);
        const bool guests = (k & 1) != 0;
        List &list = list_at(k);
        auto belongs = [&](int own) { return guests ? own >= 0 && own < li : own == li; };
        std::vector<Keyed> &add = adds[k];
        for (const Moved &m : changed)
            if (belongs(m.level)) add.push_back({key_at(m.cell, m.level, li), m.slot, m.x});
        std::sort(add.begin(), add.end(), ByRowX<Keyed>());
        // Parts: rows [cut[p], cut[p + 1]) of the list as it is.
        const std::vector<CellKey> &keys = list.row_keys;
        const size_t rows = keys.size();
        std::vector<size_t> cut = row_cuts(list, kPart);
        if (cut.size() == 1) cut.push_back(0);  // an empty list: one part, nothing in it
        const size_t parts = cut.size() - 1;
        std::vector<size_t> lost(parts, 0);
        for (const Moved &m : changed) {
            if (!belongs(m.old_level)) continue;
            const CellKey key = key_at(m.old_cell, m.old_level, li);
            const size_t r = first_row(keys, key);
            if (r == rows || keys[r] != key) throw std::logic_error("grid: an entry is not in its row");
            ++lost[size_t(std::upper_bound(cut.begin() + 1, cut.end() - 1, r) - (cut.begin() + 1))];
        }
        // (With room to grow: a reallocation would hold three copies at once.)
        const size_t most = list.count() + add.size();
        if (list.spare.capacity() < most + kPad) {
            list.spare.clear();
            list.spare.shrink_to_fit();
            list.spare.reserve(most + most / 16 + kPad);
        }
        size_t out = 0, a = 0;
        for (size_t p = 0; p < parts; ++p) {
            const size_t in_b = rows ? list.row_start[cut[p]] : 0, in_e = rows ? list.row_start[cut[p + 1]] : 0;
            // The entries that enter in this part: keys below the next part's first row.
            size_t a_e = add.size();
            if (p + 1 < parts) {
                const CellKey next = keys[cut[p + 1]];
                a_e = size_t(std::partition_point(add.begin() + std::ptrdiff_t(a), add.end(),
                                                  [&](const Keyed &en) { return CellKey(en.key) < next; }) -
                             add.begin());
            }
            if (lost[p] > in_e - in_b) throw std::logic_error("grid: a part loses more entries than it has");
            const size_t size = in_e - in_b - lost[p] + (a_e - a);
            work.push_back({&list, &add, cut[p], cut[p + 1], a, a_e, out, out + size});
            out += size;
            a = a_e;
        }
        list.spare.resize(out);
    }
    // Each part's rows as they come out: (key, entries).
    std::vector<std::vector<std::pair<CellKey, uint32_t>>> part_rows(work.size());
    bool out_of_step = false;
    RegionGuard guard;
#pragma omp parallel num_threads(threads)
    {
        const IeeeMode ieee;
#pragma omp for schedule(dynamic, 1) reduction(|| : out_of_step)
        for (int64_t k = 0; k < int64_t(work.size()); ++k) guard.run([&] {
            const Work &wk = work[k];
            const List &list = *wk.list;
            const uint32_t *S = list.bslot.data();
            const float *X = list.bl.data();  // the entries' low x, as of the last gather
            const uint32_t *start = list.row_start.data();
            const Keyed *A = wk.add->data();
            uint32_t *O = wk.list->spare.data();
            auto &out_rows = part_rows[size_t(k)];
            size_t a = wk.add_b, w = wk.out_b;
            bool full = false;  // more entries than the part's room
            // The entering entries of row keys below `until` (all, when not
            // bounded) that form rows of their own (rows that were empty).
            auto new_rows = [&](bool bounded, CellKey until) {
                while (a < wk.add_e && (!bounded || CellKey(A[a].key) < until) && w < wk.out_e) {
                    const CellKey key = A[a].key;
                    const size_t first = w;
                    while (a < wk.add_e && CellKey(A[a].key) == key && w < wk.out_e) O[w++] = A[a++].slot;
                    out_rows.push_back({key, uint32_t(w - first)});
                }
            };
            for (size_t r = wk.row_b; r < wk.row_e && !full; ++r) {
                const CellKey key = list.row_keys[r];
                new_rows(true, key);
                // The row's entries that stay, merged with those that enter it.
                const size_t first = w;
                for (size_t i = start[r]; i < start[r + 1]; ++i) {
                    const uint32_t slot = S[i];
                    if (flag[slot]) continue;  // (entries of flagged bodies leave)
                    const float x = X[i];
                    while (a < wk.add_e && CellKey(A[a].key) == key &&
                           (A[a].x < x || (A[a].x == x && A[a].slot < slot)) && w < wk.out_e)
                        O[w++] = A[a++].slot;
                    if (w == wk.out_e) {
                        full = true;
                        break;
                    }
                    O[w++] = slot;
                }
                while (a < wk.add_e && CellKey(A[a].key) == key && w < wk.out_e) O[w++] = A[a++].slot;
                if (w > first) out_rows.push_back({key, uint32_t(w - first)});
            }
            new_rows(false, 0);
            out_of_step |= full || a != wk.add_e || w != wk.out_e;
        });
    }
    guard.rethrow();
    if (out_of_step) throw std::logic_error("grid: a list update is out of step with its rows");
    // The new row index of each list from its parts' rows (consecutive in work, in order).
    for (size_t k = 0; k < work.size();) {
        List &list = *work[k].list;
        list.row_keys.clear();
        list.row_start.clear();
        uint32_t at = 0;
        for (; k < work.size() && work[k].list == &list; ++k)
            for (const auto &row : part_rows[k]) {
                if (!list.row_keys.empty() && !(list.row_keys.back() < row.first))
                    throw std::logic_error("grid: rows out of order after a list update");
                list.row_keys.push_back(row.first);
                list.row_start.push_back(at);
                at += row.second;
            }
        list.row_start.push_back(at);
        list.bslot.swap(list.spare);
    }
}

// Brings the box arrays of every list to the current boxes, in parallel
// over parts of whole rows of all lists together (lists differ in size
// tenfold, one task per list balanced badly), a block of rows at a time:
// copies the boxes (reads by slot, nearly in sequence while storage follows
// the sweep order), then restores each row's order by low x.
uint64_t Grid::gather(const std::vector<List *> &lists, const Boxes &boxes, int threads) {
    constexpr size_t kPart = 16384;
    struct Part {
        List *list;
        size_t row_b, row_e;
        bool residents;
    };
    std::vector<Part> parts;
    for (size_t l = 0; l < lists.size(); ++l) {
        List *list = lists[l];
        const size_t m = list->count();
        // Padded so that the sweep may read past the end.
        for (auto *v : {&list->bl, &list->bhx, &list->bly, &list->bhy, &list->blz, &list->bhz, &list->breach}) {
            v->resize(m + kPad);
            std::fill(v->begin() + std::ptrdiff_t(m), v->end(), 0.0f);
        }
        list->bslot.resize(m + kPad);
        std::fill(list->bslot.begin() + std::ptrdiff_t(m), list->bslot.end(), 0u);
        // Parts of about kPart entries in whole rows. (all_lists():
        // residents at even positions.)
        const std::vector<size_t> cut = row_cuts(*list, kPart);
        for (size_t k = 0; k + 1 < cut.size(); ++k) parts.push_back({list, cut[k], cut[k + 1], l % 2 == 0});
    }
    std::vector<uint64_t> jumps_of(parts.size(), 0);  // each part's residents' jumps (disorder())
    RegionGuard guard;
#pragma omp parallel num_threads(threads)
    {
        const IeeeMode ieee;
#pragma omp for schedule(dynamic, 1)
        for (int64_t p = 0; p < int64_t(parts.size()); ++p) guard.run([&] {
            List &list = *parts[p].list;
            float *L = list.bl.data(), *HX = list.bhx.data(), *LY = list.bly.data(), *HY = list.bhy.data(),
                  *LZ = list.blz.data(), *HZ = list.bhz.data(), *P = list.breach.data();
            uint32_t *S = list.bslot.data();
            const uint32_t *start = list.row_start.data();
            const size_t e = start[parts[p].row_e];
            uint64_t jumps = 0;
            const uint32_t counts = parts[p].residents;
            uint32_t prev = S[start[parts[p].row_b]];
            float *const arrays[6] = {L, HX, LY, HY, LZ, HZ};
            for (size_t r0 = parts[p].row_b; r0 < parts[p].row_e;) {
                // A block of whole rows of about kBlock entries, while they
                // are in cache: first every entry's box where the entry is,
                // then each row's order by low x restored (insertion sort:
                // between ticks the order barely changes; a row it would
                // take long over, many bodies entering one row, is sorted
                // outright at its end).
                constexpr size_t kBlock = 512;
                size_t r1 = r0 + 1;
                while (r1 < parts[p].row_e && start[r1] - start[r0] < kBlock) ++r1;
                const size_t eb = start[r0], ee = start[r1];
                size_t k = eb;
#if HGCD_AVX2
                if (use_avx2()) k = float_boxes_avx2(boxes, S, k, ee, e, arrays);
#endif
                for (; k < ee; ++k) {
                    if (k + kAhead < e) {
                        __builtin_prefetch(boxes.point(S[k + kAhead]));
                        __builtin_prefetch(boxes.off + 6 * size_t(S[k + kAhead]));
                    }
                    float lo[3], hi[3];
                    float_box(boxes, S[k], lo, hi);
                    for (int a = 0; a < 3; ++a) {
                        arrays[2 * a][k] = lo[a];
                        arrays[2 * a + 1][k] = hi[a];
                    }
                }
                for (size_t r = r0; r < r1; ++r) {
                    const size_t row_b = start[r], row_e = start[r + 1];
                    size_t budget = 64;  // insertion steps left to the row
                    bool whole = false;  // the row needs sorting outright
                    float most = -INFINITY;  // the row's largest high x so far
                    for (size_t k = row_b; k < row_e; ++k) {
                        const uint32_t slot = S[k];
                        // A resident more than 64 slots from the one before it (its
                        // box is in another stretch of memory).
                        jumps += counts & (uint32_t(slot - prev + 64) > 128);
                        prev = slot;
                        budget += 8;
                        if (whole || k == row_b || !(L[k] < L[k - 1])) {
                            P[k] = most = std::max(most, HX[k]);
                            continue;
                        }
                        const float lx = L[k], hx = HX[k], ly = LY[k], hy = HY[k], lz = LZ[k], hz = HZ[k];
                        size_t j = k;
                        for (; j > row_b && lx < L[j - 1]; --j) {
                            L[j] = L[j - 1];
                            HX[j] = HX[j - 1];
                            LY[j] = LY[j - 1];
                            HY[j] = HY[j - 1];
                            LZ[j] = LZ[j - 1];
                            HZ[j] = HZ[j - 1];
                            S[j] = S[j - 1];
                            if (--budget == 0) {
                                whole = true;
                                break;
                            }
                        }
                        L[j] = lx;
                        HX[j] = hx;
                        LY[j] = ly;
                        HY[j] = hy;
                        LZ[j] = lz;
                        HZ[j] = hz;
                        S[j] = slot;
                        // The largest high x again from where the order changed.
                        most = j > row_b ? P[j - 1] : -INFINITY;
                        for (size_t t = j; t <= k; ++t) P[t] = most = std::max(most, HX[t]);
                    }
                    if (whole) sort_row(list, row_b, row_e);  // (and its largest high x)
                }
                r0 = r1;
            }
            jumps_of[size_t(p)] = jumps;
        });
    }
    guard.rethrow();
    uint64_t disorder = 0;
    for (const uint64_t j : jumps_of) disorder += j;
    return disorder;
}

// Sorts the entries [b, e) of a row outright by low x (then slot).
void Grid::sort_row(List &list, size_t b, size_t e) {
    uint32_t *S = list.bslot.data();
    float *A[6] = {list.bl.data(), list.bhx.data(), list.bly.data(), list.bhy.data(), list.blz.data(), list.bhz.data()};
    const float *L = A[0];
    std::vector<uint32_t> order(e - b);
    for (size_t k = 0; k < order.size(); ++k) order[k] = uint32_t(k);
    std::sort(order.begin(), order.end(), [&](uint32_t p, uint32_t q) {
        return L[b + p] < L[b + q] || (L[b + p] == L[b + q] && S[b + p] < S[b + q]);
    });
    std::vector<float> t(order.size());
    for (int a = 0; a < 6; ++a) {
        for (size_t k = 0; k < order.size(); ++k) t[k] = A[a][b + order[k]];
        std::copy(t.begin(), t.end(), A[a] + b);
    }
    std::vector<uint32_t> ts(order.size());
    for (size_t k = 0; k < order.size(); ++k) ts[k] = S[b + order[k]];
    std::copy(ts.begin(), ts.end(), S + b);
    float most = -INFINITY;
    for (size_t k = b; k < e; ++k) list.breach[k] = most = std::max(most, list.bhx[k]);
}

namespace {

// First row at or after `from` whose key is >= target (rows are sorted).
inline size_t advance(const std::vector<CellKey> &keys, size_t from, CellKey target) {
    while (from < keys.size() && keys[from] < target) ++from;
    return from;
}


// Key offset of the row (z + dz, y + dy) from row (z, y). Components stay
// within [1, 2^42 - 2], so +-1 never carries: modular arithmetic on the
// packed key moves exactly one component.
inline CellKey row_step(int dz, int dy) {
    return (CellKey(int64_t(dz)) << kAxisBits) + CellKey(int64_t(dy));
}

// A sweep's box test: one box against kBlock consecutive boxes of a row;
// bit k of the result is set when box k overlaps it (closed intervals on
// every axis). No window test: the windows only prune (every pair a sweep
// may test is one it owns, see sweep_resident_rows), so they bound where a scan
// starts and stops, no more. Four boxes at a time with SSE2 on x86-64,
// vector extensions elsewhere (NEON on arm64); eight with AVX2 where the
// CPU has it (GCC on x86-64, picked at run time: tetra 750k broad phase
// 52.9 -> 46.8 ms on 1 thread, both builds VEX-encoded).
#if HGCD_AVX2
#define HGCD_SWEEP_INLINE inline __attribute__((always_inline))
#else
#define HGCD_SWEEP_INLINE inline
#endif

// Writes the pairs (a | slot[k]) of a block's hits (bit k of hits) from
// `to` on and returns their count. All kBlock places are written: a branch
// per hit mispredicted often enough that this took the broad phase from 63
// to 59 ms (tetra 750k, 1 thread).
template <int kBlock>
HGCD_SWEEP_INLINE size_t write_hits(uint64_t *to, uint64_t a, const uint32_t *slot, unsigned hits) {
    size_t n = 0;
    for (int k = 0; k < kBlock; ++k) {
        to[n] = a | slot[k];
        n += (hits >> k) & 1;
    }
    return n;
}

#if defined(__SSE2__)
struct Lanes4 {
    static constexpr int kBlock = 4;
    __m128 lx, hx, ly, hy, lz, hz;
    HGCD_SWEEP_INLINE Lanes4(const Grid::BoxArrays &A, size_t i)
        : lx(_mm_set1_ps(A.l[i])), hx(_mm_set1_ps(A.hx[i])), ly(_mm_set1_ps(A.ly[i])), hy(_mm_set1_ps(A.hy[i])),
          lz(_mm_set1_ps(A.lz[i])), hz(_mm_set1_ps(A.hz[i])) {}
    HGCD_SWEEP_INLINE unsigned test(const Grid::BoxArrays &B, size_t j) const {
        const __m128 in_x = _mm_and_ps(_mm_cmple_ps(_mm_loadu_ps(B.l + j), hx), _mm_cmple_ps(lx, _mm_loadu_ps(B.hx + j)));
        const __m128 in_y = _mm_and_ps(_mm_cmple_ps(_mm_loadu_ps(B.ly + j), hy), _mm_cmple_ps(ly, _mm_loadu_ps(B.hy + j)));
        const __m128 in_z = _mm_and_ps(_mm_cmple_ps(_mm_loadu_ps(B.lz + j), hz), _mm_cmple_ps(lz, _mm_loadu_ps(B.hz + j)));
        return unsigned(_mm_movemask_ps(_mm_and_ps(in_x, _mm_and_ps(in_y, in_z))));
    }
    HGCD_SWEEP_INLINE static unsigned below(const float *p, float v) {
        return unsigned(_mm_movemask_ps(_mm_cmplt_ps(_mm_loadu_ps(p), _mm_set1_ps(v))));
    }
    HGCD_SWEEP_INLINE static size_t write(uint64_t *to, uint64_t a, const uint32_t *slot, unsigned hits) {
        return write_hits<kBlock>(to, a, slot, hits);
    }
};
#else
typedef float V4 __attribute__((vector_size(16)));
typedef int32_t M4 __attribute__((vector_size(16)));
inline V4 load4(const float *p) {
    V4 v;
    std::memcpy(&v, p, sizeof v);
    return v;
}
struct Lanes4 {
    static constexpr int kBlock = 4;
    float lx, hx, ly, hy, lz, hz;
    Lanes4(const Grid::BoxArrays &A, size_t i)
        : lx(A.l[i]), hx(A.hx[i]), ly(A.ly[i]), hy(A.hy[i]), lz(A.lz[i]), hz(A.hz[i]) {}
    unsigned test(const Grid::BoxArrays &B, size_t j) const {
        const M4 in = (load4(B.l + j) <= hx) & (lx <= load4(B.hx + j)) & (load4(B.ly + j) <= hy) &
                      (ly <= load4(B.hy + j)) & (load4(B.lz + j) <= hz) & (lz <= load4(B.hz + j));
        return unsigned((in[0] & 1) | (in[1] & 2) | (in[2] & 4) | (in[3] & 8));
    }
    static unsigned below(const float *p, float v) {
        const M4 in = load4(p) < v;
        return unsigned((in[0] & 1) | (in[1] & 2) | (in[2] & 4) | (in[3] & 8));
    }
    static size_t write(uint64_t *to, uint64_t a, const uint32_t *slot, unsigned hits) {
        return write_hits<kBlock>(to, a, slot, hits);
    }
};
#endif

#if HGCD_AVX2
// (Its code is in helpers of the AVX2 target, inlined once the sweep that
// uses them is expanded inside sweep_*_avx2, as narrow.cpp's AVX2 kernels;
// vectors pass by reference, as a default-target function may not take
// them by value.)
struct Lanes8;
#pragma GCC push_options
#pragma GCC target("avx2")
static inline void splat8(Lanes8 &lanes, const Grid::BoxArrays &A, size_t i);
static inline unsigned test8(const Lanes8 &lanes, const Grid::BoxArrays &B, size_t j);
static inline unsigned below8(const float *p, float v);
static inline size_t write8(uint64_t *to, uint64_t a, const uint32_t *slot, unsigned hits);
#pragma GCC pop_options
struct Lanes8 {
    static constexpr int kBlock = 8;
    __m256 lx, hx, ly, hy, lz, hz;
    HGCD_SWEEP_INLINE Lanes8(const Grid::BoxArrays &A, size_t i) { splat8(*this, A, i); }
    HGCD_SWEEP_INLINE unsigned test(const Grid::BoxArrays &B, size_t j) const { return test8(*this, B, j); }
    HGCD_SWEEP_INLINE static unsigned below(const float *p, float v) { return below8(p, v); }
    HGCD_SWEEP_INLINE static size_t write(uint64_t *to, uint64_t a, const uint32_t *slot, unsigned hits) {
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
    lanes.lx = _mm256_set1_ps(A.l[i]);
    lanes.hx = _mm256_set1_ps(A.hx[i]);
    lanes.ly = _mm256_set1_ps(A.ly[i]);
    lanes.hy = _mm256_set1_ps(A.hy[i]);
    lanes.lz = _mm256_set1_ps(A.lz[i]);
    lanes.hz = _mm256_set1_ps(A.hz[i]);
}
static inline unsigned test8(const Lanes8 &lanes, const Grid::BoxArrays &B, size_t j) {
    const __m256 in_x = _mm256_and_ps(_mm256_cmp_ps(_mm256_loadu_ps(B.l + j), lanes.hx, _CMP_LE_OQ),
                                      _mm256_cmp_ps(lanes.lx, _mm256_loadu_ps(B.hx + j), _CMP_LE_OQ));
    const __m256 in_y = _mm256_and_ps(_mm256_cmp_ps(_mm256_loadu_ps(B.ly + j), lanes.hy, _CMP_LE_OQ),
                                      _mm256_cmp_ps(lanes.ly, _mm256_loadu_ps(B.hy + j), _CMP_LE_OQ));
    const __m256 in_z = _mm256_and_ps(_mm256_cmp_ps(_mm256_loadu_ps(B.lz + j), lanes.hz, _CMP_LE_OQ),
                                      _mm256_cmp_ps(lanes.lz, _mm256_loadu_ps(B.hz + j), _CMP_LE_OQ));
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
#endif

// Whether box [lo, hi] and entry j of B overlap (closed intervals).
inline bool box_meets(const double *lo, const double *hi, const Grid::BoxArrays &B, size_t j) {
    return B.l[j] <= hi[0] && lo[0] <= B.hx[j] && B.ly[j] <= hi[1] && lo[1] <= B.hy[j] && B.lz[j] <= hi[2] &&
           lo[2] <= B.hz[j];
}
// The same for two boxes (low x y z, high x y z).
inline bool boxes_meet(const double *a, const double *b) {
    return b[0] <= a[3] && a[0] <= b[3] && b[1] <= a[4] && a[1] <= b[4] && b[2] <= a[5] && a[2] <= b[5];
}

// The pairs of box `slot` (its lanes) with the entries [j, e) of a list up
// to the block holding the first whose low x passes `right` (none after it
// can overlap), two blocks at a time: a scan takes 1 to 5 blocks (1 to 3 for
// 86% of them at tetra 750k), and the test for its end, after every block,
// mispredicted about once a scan; after every second one it costs a block
// test where one block would do (broad phase 32.3 -> 27.8 ms on 1 thread;
// three at a time: 30.0). Needs j < e; the padding past e is read and
// masked.
template <class Lanes>
HGCD_SWEEP_INLINE void scan(const Lanes &lanes, const Grid::BoxArrays &B, size_t j, size_t e, float right,
                            uint32_t slot, PairBuffer &out) {
    constexpr int kBlock = Lanes::kBlock;
    static_assert(size_t(2 * kBlock) <= kPad, "a scan reads past the end of a list");
    const uint64_t a = uint64_t(slot) << 32;  // (either order: see find_pairs)
    for (;; j += 2 * kBlock) {
        unsigned hits = lanes.test(B, j), more = lanes.test(B, j + kBlock);
        if (j + kBlock > e) hits &= (1u << (e - j)) - 1;
        if (j + 2 * kBlock > e) more &= j + kBlock < e ? (1u << (e - j - kBlock)) - 1 : 0;
        uint64_t *to = out.room(2 * kBlock);
        const size_t n = Lanes::write(to, a, B.slot + j, hits);
        out.commit(n + Lanes::write(to + n, a, B.slot + j + kBlock, more));
        if (j + 2 * kBlock >= e || B.l[j + 2 * kBlock - 1] > right) return;
    }
}

// Which neighbouring rows a box of a row can reach (kReach* bits): every
// body of this level has its point p in its row and its box within w / 2 of
// p (the level's cells fit it, see Grid::update), so a body of row y - 1 has
// its box below the row's lower face plus w / 2, and the box [lo, hi] meets
// it only if lo_y is below that too (for the float box, which holds the
// box: float-only overlaps may be skipped). Compared in row units, where v - c is
// within 2^-53 of exact, and inflated past that. In a row at the edge of the
// key range (far keys saturate: the row holds bodies that are not in it)
// every box reaches every row.
class RowReach {
  public:
    RowReach(int exponent, CellKey row)
        : on_(exponent > -990 && exponent < 990 && inner(uint64_t(row) & kAxisMask) &&
              inner(uint64_t(row >> kAxisBits) & kAxisMask)),
          inv_(on_ ? pow2(-exponent - kRowShift) : 0),
          reach_(0.5 * pow2(-kRowShift) * (1 + 1e-9) + 1e-12),
          cy_(double(int64_t(uint64_t(row) & kAxisMask) - kCoordBias)),
          cz_(double(int64_t(uint64_t(row >> kAxisBits) & kAxisMask) - kCoordBias)) {}
    unsigned bits(double ly, double hy, double lz, double hz) const {
        const double fly = ly * inv_ - cy_, fhy = hy * inv_ - cy_, flz = lz * inv_ - cz_, fhz = hz * inv_ - cz_;
        const unsigned b = (fly < reach_ ? kReachYLo : 0) | (1 - fhy <= reach_ ? kReachYHi : 0) |
                           (flz < reach_ ? kReachZLo : 0) | (1 - fhz <= reach_ ? kReachZHi : 0);
        return on_ ? b : kReachAll;
    }

  private:
    // A row coordinate that no clamped coordinate lands on (clamp_bias).
    static bool inner(uint64_t c) {
        return c > uint64_t(kCoordBias - kCoordLimit) && c < uint64_t(kCoordBias + kCoordLimit);
    }
    bool on_;
    double inv_, reach_, cy_, cz_;
};

// The first entry of [j, e) whose BP (a row's largest high x so far: it
// only grows along the row) reaches v, or e: a block of entries at a time,
// counting those below v at the block's start (their lanes are the lowest;
// reads past e, into the next row or the padding, are cut off at e). Usually
// one block (the cursor moves a few entries a box): a compare and a count
// where a search step by step mispredicted its exit (tetra 750k, broad
// phase 41.7 -> 37.8 ms on 1 thread).
template <class Lanes>
HGCD_SWEEP_INLINE size_t floor_entry(const float *BP, size_t j, size_t e, float v) {
    for (;;) {
        const unsigned step = unsigned(__builtin_ctz(~Lanes::below(BP + j, v)));
        j += step;
        if (step < unsigned(Lanes::kBlock) || j >= e) return std::min(j, e);
    }
}

// Every overlapping pair of an entry of row A [ib, ie) with an entry of the
// rows B[r] = [jb[r], je[r]) (r < rows), all sorted by low x. A box of A
// visits only the rows its reach bits allow (need[r] are the bits row r
// needs); in each, it scans from the first entry whose row's largest high x
// so far reaches its own low x (none before it can overlap it; and the
// floor only rises as A's low x do) up to its high x. Row by row, over the
// boxes of A that row admits, listed first without branches (a chunk of A
// at a time, after the chunk's own-row pairs when A is B's own row): a
// branch per box on whether it visits any row, and one on how many,
// mispredicted about once a box (tetra 750k, broad phase 38.9 -> 31.7 ms on
// 1 thread, 20.0 -> 16.5 on 2). Chunks of 32: longer ones separated each
// box's pairs more and slowed the narrow phase, which reads the bodies of
// the pairs in their order (256: narrow 53 -> 58 ms).
template <class Lanes>
HGCD_SWEEP_INLINE void sweep_rows(const Grid::BoxArrays &A, const RowReach &row_reach, size_t ib, size_t ie,
                                  const Grid::BoxArrays &B, const size_t *jb, const size_t *je,
                                  const uint8_t *need, int rows, bool own_row, PairBuffer &out) {
    const float *BL = B.l, *BP = B.reach;
    constexpr size_t kAdmit = 32;  // boxes of A a chunk
    uint8_t bits[kAdmit];
    uint32_t admitted[kAdmit];
    size_t lo[9];
    unsigned live = 0;  // rows with candidates left
    for (int r = 0; r < rows; ++r) {
        lo[r] = jb[r];
        live |= unsigned(jb[r] < je[r]) << r;
    }
    for (size_t cb = ib; cb < ie && (live || own_row); cb += kAdmit) {
        const size_t ce = std::min(ie, cb + kAdmit);
        if (own_row)  // (the same chunk's own-row pairs first: the narrow phase then finds its bodies in cache)
            for (size_t i = cb; i < ce && i + 1 < ie; ++i) {
                const float right = A.hx[i];
                if (A.l[i + 1] <= right) scan(Lanes(A, i), A, i + 1, ie, right, A.slot[i], out);
            }
        if (!live) continue;  // (own-row pairs only from here on)
        for (size_t i = cb; i < ce; ++i) bits[i - cb] = uint8_t(row_reach.bits(A.ly[i], A.hy[i], A.lz[i], A.hz[i]));
        for (int r = 0; r < rows; ++r) {
            if (!(live >> r & 1)) continue;
            const unsigned want = need[r];
            size_t n = 0;
            for (size_t i = cb; i < ce; ++i) {
                admitted[n] = uint32_t(i);
                n += (bits[i - cb] & want) == want;
            }
            size_t j = lo[r];
            const size_t e = je[r];
            for (size_t k = 0; k < n; ++k) {
                const size_t i = admitted[k];
                j = floor_entry<Lanes>(BP, j, e, A.l[i]);
                if (j == e) {
                    live &= ~(1u << r);
                    break;
                }
                const float right = A.hx[i];
                if (BL[j] <= right) scan(Lanes(A, i), B, j, e, right, A.slot[i], out);
            }
            lo[r] = j;
        }
    }
}

// A list's rows as the sweeps read them: the occupied rows' keys, where
// each row's entries start, and the boxes.
struct RowsView {
    const std::vector<CellKey> &keys;
    const uint32_t *start;
    Grid::BoxArrays box;
};

// A level's residents, rows (z, y) sorted by key and each by low x: each
// body meets the later bodies of its own row up to its high x (sweep and
// prune: a pair of the row is found from the member with the lower low x),
// and is swept against the rows (z, y+1), (z+1, y-1), (z+1, y) and
// (z+1, y+1) (the later half of the 3x3 rows around it in key order, so
// each pair of two rows once). Rows are found by cursors that only move
// forward.
template <class Lanes>
HGCD_SWEEP_INLINE void sweep_resident_rows(const RowsView &R, int exponent, size_t begin, size_t end,
                                           PairBuffer &out) {
    const std::vector<CellKey> &rows = R.keys;
    const uint32_t *start = R.start;
    const Grid::BoxArrays &S = R.box;
    static const int later[4][2] = {{0, 1}, {1, -1}, {1, 0}, {1, 1}};
    uint8_t need[4];
    for (int r = 0; r < 4; ++r) need[r] = reach_needed(later[r][0], later[r][1]);
    CellKey off[4];
    size_t cur[4];
    for (int r = 0; r < 4; ++r) {
        off[r] = row_step(later[r][0], later[r][1]);
        cur[r] = first_row(rows, rows[begin] + off[r]);
    }
    for (size_t row = begin; row < end; ++row) {
        const size_t b = start[row], e = start[row + 1];
        size_t jb[4], je[4];
        for (int r = 0; r < 4; ++r) {
            const CellKey target = rows[row] + off[r];
            const size_t k = cur[r] = advance(rows, cur[r], target);
            const bool found = k < rows.size() && rows[k] == target;
            jb[r] = found ? start[k] : 0;
            je[r] = found ? start[k + 1] : 0;
        }
        sweep_rows<Lanes>(S, RowReach(exponent, rows[row]), b, e, S, jb, je, need, 4, true, out);
    }
}

// Rows of a level's guests G against the 3x3 rows of residents R around each.
template <class Lanes>
HGCD_SWEEP_INLINE void sweep_guest_rows(const RowsView &G, const RowsView &R, int exponent, size_t begin,
                                        size_t end, PairBuffer &out) {
    const std::vector<CellKey> &grows = G.keys, &rows = R.keys;
    if (rows.empty()) return;
    const uint32_t *gstart = G.start, *start = R.start;
    CellKey off[9];
    size_t cur[9];
    for (int r = 0; r < 9; ++r) {
        off[r] = row_step(r / 3 - 1, r % 3 - 1);
        cur[r] = first_row(rows, grows[begin] + off[r]);
    }
    uint8_t need[9];
    for (int r = 0; r < 9; ++r) need[r] = reach_needed(r / 3 - 1, r % 3 - 1);
    for (size_t row = begin; row < end; ++row) {
        size_t jb[9], je[9];
        for (int r = 0; r < 9; ++r) {
            const CellKey target = grows[row] + off[r];
            const size_t k = cur[r] = advance(rows, cur[r], target);
            const bool found = k < rows.size() && rows[k] == target;
            jb[r] = found ? start[k] : 0;
            je[r] = found ? start[k + 1] : 0;
        }
        sweep_rows<Lanes>(G.box, RowReach(exponent, grows[row]), gstart[row], gstart[row + 1], R.box, jb, je,
                          need, 9, false, out);
    }
}

#if HGCD_AVX2
__attribute__((target("avx2"), noinline)) void sweep_resident_rows_avx2(const RowsView &R, int exponent,
                                                                        size_t begin, size_t end,
                                                                        PairBuffer &out) {
    sweep_resident_rows<Lanes8>(R, exponent, begin, end, out);
}
__attribute__((target("avx2"), noinline)) void sweep_guest_rows_avx2(const RowsView &G, const RowsView &R,
                                                                     int exponent, size_t begin, size_t end,
                                                                     PairBuffer &out) {
    sweep_guest_rows<Lanes8>(G, R, exponent, begin, end, out);
}
#endif

}  // namespace

void Grid::sweep_residents(const Level &lv, size_t begin, size_t end, PairBuffer &out) const {
    const List &L = lv.residents;
    const RowsView R{L.row_keys, L.row_start.data(), L.arrays()};
#if HGCD_AVX2
    if (use_avx2()) return sweep_resident_rows_avx2(R, lv.exponent, begin, end, out);
#endif
    sweep_resident_rows<Lanes4>(R, lv.exponent, begin, end, out);
}

void Grid::sweep_guests(const Level &lv, size_t begin, size_t end, PairBuffer &out) const {
    const RowsView G{lv.guests.row_keys, lv.guests.row_start.data(), lv.guests.arrays()};
    const RowsView R{lv.residents.row_keys, lv.residents.row_start.data(), lv.residents.arrays()};
#if HGCD_AVX2
    if (use_avx2()) return sweep_guest_rows_avx2(G, R, lv.exponent, begin, end, out);
#endif
    sweep_guest_rows<Lanes4>(G, R, lv.exponent, begin, end, out);
}

void Grid::query_levels(const double *lo, const double *hi, uint32_t slot, size_t level_end,
                        PairBuffer &out) const {
    for (size_t li = 0; li < level_end; ++li) {
        const Level &lv = levels_[li];
        const List &R = lv.residents;
        const BoxArrays S = R.arrays();
        const size_t m = R.count();
        if (m == 0) continue;
        // A resident j meeting the box has its point p_j within w / 2 of
        // its box, so within w / 2 of [lo, hi], and its low x at least lo_x
        // less w (its box is at most w wide). Widened past the rounding of
        // these bounds, which grows with the coordinates, and past the
        // float rounding of the list's low x (at most |x| 2^-23 below).
        const double w = cell_width(lv.exponent);
        auto wide = [&](double v, double d) { return v + d * (1 + 1e-9) + (d < 0 ? -1 : 1) * std::fabs(v) * 0x1p-50; };
        const int e = lv.exponent + kRowShift;
        const uint64_t ly = clamp_bias(cell_coord(wide(lo[1], -w / 2), e)), hy = clamp_bias(cell_coord(wide(hi[1], w / 2), e));
        const uint64_t lz = clamp_bias(cell_coord(wide(lo[2], -w / 2), e)), hz = clamp_bias(cell_coord(wide(hi[2], w / 2), e));
        const double rows = double(hz - lz + 1) * double(hy - ly + 1);
        if (rows * 32 >= double(R.row_keys.size())) {
            for (size_t j = 0; j < m; ++j)
                if (box_meets(lo, hi, S, j)) out.push_back(pair_key(slot, S.slot[j]));
            continue;
        }
        const double left = wide(lo[0], -w) - (std::fabs(lo[0]) + w) * 0x1p-22 - 0x1p-140;
        for (uint64_t z = lz; z <= hz; ++z) {
            for (uint64_t y = ly; y <= hy; ++y) {
                const size_t k = first_row(R.row_keys, row_key(z, y));
                if (k == R.row_keys.size() || R.row_keys[k] != row_key(z, y)) continue;
                for (size_t j = R.row_start[k]; j < R.row_start[k + 1] && S.l[j] <= hi[0]; ++j)
                    if (S.l[j] >= left && box_meets(lo, hi, S, j)) out.push_back(pair_key(slot, S.slot[j]));
            }
        }
    }
}

void Grid::find_pairs(const Boxes &boxes, int threads, std::vector<PairBuffer> &out) const {
    // Work items: chunks of every resident and guest list, one per oversize
    // body, and one for the oversize-oversize sweep. Chunks are small and
    // scheduled dynamically, because dense rows cost far more than sparse ones.
    struct Item {
        int kind;  // 0 residents, 1 guests, 2 oversize body, 3 oversize sweep, 4 residents querying down
        uint32_t level;
        size_t begin, end;
    };
    std::vector<Item> items;
    // Chunks of whole rows holding about kChunk entries each.
    auto chunk = [&](const List &list, int kind, uint32_t li) {
        const std::vector<size_t> cut = row_cuts(list, kChunk);
        for (size_t k = 0; k + 1 < cut.size(); ++k) items.push_back({kind, li, cut[k], cut[k + 1]});
    };
    for (uint32_t li = 0; li < levels_.size(); ++li) {
        const Level &lv = levels_[li];
        chunk(lv.residents, 0, li);
        if (lv.down) {
            for (size_t b = 0; b < lv.residents.count(); b += 64)
                items.push_back({4, li, b, std::min(lv.residents.count(), b + 64)});
        } else if (lv.residents.count()) {
            chunk(lv.guests, 1, li);
        }
    }
    for (size_t k = 0; k < oversize_.size(); ++k) items.push_back({2, 0, k, k + 1});
    if (oversize_.size() > 1) items.push_back({3, 0, 0, 0});

    RegionGuard guard;
#pragma omp parallel num_threads(threads)
    {
        const IeeeMode ieee;
#pragma omp for schedule(dynamic, 1)
        for (int64_t k = 0; k < int64_t(items.size()); ++k) guard.run([&] {
            const Item &it = items[k];
            PairBuffer &mine = out[omp_get_thread_num()];
            if (it.kind == 0) {
                sweep_residents(levels_[it.level], it.begin, it.end, mine);
            } else if (it.kind == 1) {
                sweep_guests(levels_[it.level], it.begin, it.end, mine);
            } else if (it.kind == 2) {
                double lo[3], hi[3];
                boxes.at(oversize_[it.begin], lo, hi);
                query_levels(lo, hi, oversize_[it.begin], levels_.size(), mine);
            } else if (it.kind == 4) {
                const List &R = levels_[it.level].residents;
                const BoxArrays S = R.arrays();
                for (size_t j = it.begin; j < it.end; ++j) {
                    const double lo[3] = {S.l[j], S.ly[j], S.lz[j]}, hi[3] = {S.hx[j], S.hy[j], S.hz[j]};
                    query_levels(lo, hi, S.slot[j], it.level, mine);
                }
            } else {
                const size_t m = oversize_.size();
                std::vector<double> b(6 * m);
                for (size_t i = 0; i < m; ++i) boxes.at(oversize_[i], &b[6 * i], &b[6 * i + 3]);
                std::vector<uint32_t> order(m);
                for (size_t i = 0; i < m; ++i) order[i] = uint32_t(i);
                std::sort(order.begin(), order.end(), [&](uint32_t a, uint32_t c) {
                    return b[6 * a] < b[6 * c] || (b[6 * a] == b[6 * c] && a < c);
                });
                for (size_t i = 0; i < m; ++i) {
                    const double *A = &b[6 * order[i]];
                    for (size_t j = i + 1; j < m; ++j) {
                        const double *B = &b[6 * order[j]];
                        if (B[0] > A[3]) break;
                        if (boxes_meet(A, B)) mine.push_back(pair_key(oversize_[order[i]], oversize_[order[j]]));
                    }
                }
            }
        });
    }
    guard.rethrow();
}

void Grid::order(std::vector<uint32_t> &out) const {
    for (const Level &lv : levels_)
        out.insert(out.end(), lv.residents.bslot.begin(),
                   lv.residents.bslot.begin() + std::ptrdiff_t(lv.residents.count()));
    out.insert(out.end(), oversize_.begin(), oversize_.end());
}

void Grid::reserve_slots(size_t n) {
    if (level_.size() >= n) return;
    level_.reserve(n);
    gen_.reserve(n);
    cell_.reserve(2 * n);
    exponent_.reserve(n);
    slack_.reserve(n);
    level_.resize(n, kNone);  // (no allocation past here)
    gen_.resize(n, 0);
    cell_.resize(2 * n, 0);
    exponent_.resize(n, 0);
    slack_.resize(n, 0);
}

void Grid::renumber(const std::vector<uint32_t> &old_of_new, const std::vector<uint32_t> &new_of_old,
                    void *scratch) {
    const size_t n = old_of_new.size();  // (slots made since the last update are not in the grid)
    for (Level &lv : levels_)
        for (List *list : {&lv.residents, &lv.guests}) {
            uint32_t *slot = list->bslot.data();
#pragma omp for schedule(static)
            for (int64_t k = 0; k < int64_t(list->count()); ++k) slot[k] = new_of_old[slot[k]];
        }
    permute_records<2>(cell_.data(), old_of_new.data(), n, scratch);
    permute_records<1>(gen_.data(), old_of_new.data(), n, scratch);
    permute_records<1>(slack_.data(), old_of_new.data(), n, scratch);
    permute_records<1>(level_.data(), old_of_new.data(), n, scratch);
    permute_records<1>(exponent_.data(), old_of_new.data(), n, scratch);
#pragma omp single
    {
        for (uint32_t &s : oversize_) s = new_of_old[s];
        std::sort(oversize_.begin(), oversize_.end());
        disorder_ = 0;
    }
}

int64_t float_boxes_mismatches(const Boxes &boxes, uint32_t n) {
#if HGCD_AVX2
    if (!use_avx2()) return -1;
    const IeeeMode ieee;
    std::vector<uint32_t> slots(n);
    for (uint32_t i = 0; i < n; ++i) slots[i] = i;
    std::vector<float> got(6 * size_t(n), 0.0f);
    float *const arrays[6] = {&got[0], &got[size_t(n)], &got[2 * size_t(n)], &got[3 * size_t(n)],
                              &got[4 * size_t(n)], &got[5 * size_t(n)]};
    const size_t done = float_boxes_avx2(boxes, slots.data(), 0, n, n, arrays);
    int64_t mismatches = 0;
    for (uint32_t i = 0; i < done; ++i) {
        float lo[3], hi[3];
        float_box(boxes, i, lo, hi);
        const float want[6] = {lo[0], hi[0], lo[1], hi[1], lo[2], hi[2]};
        bool same = true;
        for (int a = 0; a < 6; ++a) same &= std::memcmp(&want[a], &got[a * size_t(n) + i], sizeof(float)) == 0;
        mismatches += !same;
    }
    return mismatches;
#else
    (void)boxes;
    (void)n;
    return -1;
#endif
}

bool Grid::same_state(const Grid &o) const {
    if (levels_.size() != o.levels_.size() || level_.size() != o.level_.size()) return false;
    for (size_t l = 0; l < levels_.size(); ++l)
        if (levels_[l].exponent != o.levels_[l].exponent) return false;
    for (size_t s = 0; s < level_.size(); ++s) {
        if (level_[s] != o.level_[s]) return false;
        if (level_[s] >= 0 && (cell_[2 * s] != o.cell_[2 * s] || cell_[2 * s + 1] != o.cell_[2 * s + 1]))
            return false;
    }
    std::vector<uint32_t> a(oversize_), b(o.oversize_);
    std::sort(a.begin(), a.end());
    std::sort(b.begin(), b.end());
    if (a != b) return false;
    for (size_t l = 0; l < levels_.size(); ++l)
        for (int g = 0; g < 2; ++g) {
            // (Whether a level keeps guests has hysteresis: an updated grid
            // may keep a choice a fresh one would not make.)
            if (g && levels_[l].down != o.levels_[l].down) continue;
            const List &x = g ? levels_[l].guests : levels_[l].residents;
            const List &y = g ? o.levels_[l].guests : o.levels_[l].residents;
            if (x.row_keys != y.row_keys || x.row_start != y.row_start) return false;
            for (size_t r = 0; r < x.row_keys.size(); ++r) {
                std::vector<uint32_t> p(x.bslot.begin() + x.row_start[r], x.bslot.begin() + x.row_start[r + 1]);
                std::vector<uint32_t> q(y.bslot.begin() + y.row_start[r], y.bslot.begin() + y.row_start[r + 1]);
                std::sort(p.begin(), p.end());
                std::sort(q.begin(), q.end());
                if (p != q) return false;
            }
        }
    return true;
}

}  // namespace hgcd
