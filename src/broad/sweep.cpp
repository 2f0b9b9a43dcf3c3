// The sweeps: each level's rows against their own and the neighbouring rows
// of residents, four boxes a test (SSE2, NEON) or eight (AVX2, sweep_avx2.hpp,
// picked at run time). Called per row chunk by find_pairs (pairs.cpp).
#include <algorithm>
#include <cstring>
#include <vector>

#include "broad/cells.hpp"
#include "broad/grid.hpp"
#include "common/cpu.hpp"
#include "common/ieee.hpp"
#include "common/simd.hpp"

#if defined(__SSE2__)
#include <immintrin.h>
#endif
#if HGCD_AVX2
#include "broad/sweep_avx2.hpp"
#endif

// The sweep's helpers are forced inline where the AVX2 sweeps instantiate
// them inside functions of that target.
#if HGCD_AVX2
#define HGCD_SWEEP_INLINE inline __attribute__((always_inline))
#else
#define HGCD_SWEEP_INLINE inline
#endif

namespace hgcd {
using namespace broad;

namespace {

// First row at or after `from` whose key is >= target (rows are sorted).
inline size_t advance(const std::vector<CellKey> &keys, size_t from, CellKey target) {
    while (from < keys.size() && keys[from] < target) ++from;
    return from;
}

// Key offset of the row (z + dz, y + dy) from row (z, y). Components stay
// within [1, 2^42 - 2], so +-1 never carries: modular arithmetic on the
// packed key moves exactly one component.
inline CellKey row_step(int dz, int dy) { return (CellKey(int64_t(dz)) << kAxisBits) + CellKey(int64_t(dy)); }

// Writes the pairs (a | slot[k]) of a block's hits (bit k of hits) from
// `to` on and returns their count. All kBlock places are written: a branch
// per hit mispredicted often.
template <int kBlock>
HGCD_SWEEP_INLINE size_t write_hits(uint64_t *to, uint64_t a, const uint32_t *slot, unsigned hits) {
    size_t n = 0;
    for (int k = 0; k < kBlock; ++k) {
        to[n] = a | slot[k];
        n += (hits >> k) & 1;
    }
    return n;
}

// A sweep's box test: box i of list A in every lane (lx..hz: its low x,
// high x, low y, ...) against kBlock consecutive boxes of a row; bit k of
// test() is set when box k overlaps it (closed intervals on every axis).
// No window test: the windows only prune (every pair a sweep may test is
// one it owns, see sweep_resident_rows), so they bound where a scan starts
// and stops, no more.
#if defined(__SSE2__)
struct Lanes4 {
    static constexpr int kBlock = 4;
    __m128 lx, hx, ly, hy, lz, hz;
    HGCD_SWEEP_INLINE Lanes4(const Grid::BoxArrays &A, size_t i)
        : lx(_mm_set1_ps(A.low_x[i])), hx(_mm_set1_ps(A.high_x[i])), ly(_mm_set1_ps(A.low_y[i])),
          hy(_mm_set1_ps(A.high_y[i])), lz(_mm_set1_ps(A.low_z[i])), hz(_mm_set1_ps(A.high_z[i])) {}
    HGCD_SWEEP_INLINE unsigned test(const Grid::BoxArrays &B, size_t j) const {
        const __m128 in_x =
            _mm_and_ps(_mm_cmple_ps(_mm_loadu_ps(B.low_x + j), hx), _mm_cmple_ps(lx, _mm_loadu_ps(B.high_x + j)));
        const __m128 in_y =
            _mm_and_ps(_mm_cmple_ps(_mm_loadu_ps(B.low_y + j), hy), _mm_cmple_ps(ly, _mm_loadu_ps(B.high_y + j)));
        const __m128 in_z =
            _mm_and_ps(_mm_cmple_ps(_mm_loadu_ps(B.low_z + j), hz), _mm_cmple_ps(lz, _mm_loadu_ps(B.high_z + j)));
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
inline f32x4 load4(const float *p) {
    f32x4 v;
    std::memcpy(&v, p, sizeof v);
    return v;
}
inline unsigned lane_bits(i32x4 in) { return unsigned((in[0] & 1) | (in[1] & 2) | (in[2] & 4) | (in[3] & 8)); }
struct Lanes4 {
    static constexpr int kBlock = 4;
    float lx, hx, ly, hy, lz, hz;
    Lanes4(const Grid::BoxArrays &A, size_t i)
        : lx(A.low_x[i]), hx(A.high_x[i]), ly(A.low_y[i]), hy(A.high_y[i]), lz(A.low_z[i]), hz(A.high_z[i]) {}
    unsigned test(const Grid::BoxArrays &B, size_t j) const {
        return lane_bits((load4(B.low_x + j) <= hx) & (lx <= load4(B.high_x + j)) & (load4(B.low_y + j) <= hy) &
                         (ly <= load4(B.high_y + j)) & (load4(B.low_z + j) <= hz) & (lz <= load4(B.high_z + j)));
    }
    static unsigned below(const float *p, float v) { return lane_bits(load4(p) < v); }
    static size_t write(uint64_t *to, uint64_t a, const uint32_t *slot, unsigned hits) {
        return write_hits<kBlock>(to, a, slot, hits);
    }
};
#endif

// The pairs of box `slot` (its lanes) with the entries [j, e) of a list up
// to the block holding the first whose low x passes `right` (none after it
// can overlap), two blocks at a time: a scan takes 1 to 5 blocks (1 to 3 for
// most), and the test for its end after every block mispredicted about once
// a scan; after every second one it costs a block test where one block
// would do. Needs j < e; the padding past e is read and masked.
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
        if (j + 2 * kBlock >= e || B.low_x[j + 2 * kBlock - 1] > right) return;
    }
}

// Which neighbouring rows a box of a row can reach (kReach* bits): every
// body of this level has its point p in its row and its box within w / 2 of
// p (the level's cells fit it, see Grid::exponent_of), so a body of row y - 1 has
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

// The first entry of [j, e) whose reach (a row's largest high x so far: it
// only grows along the row) reaches v, or e: a block of entries at a time,
// counting those below v at the block's start (their lanes are the lowest;
// reads past e, into the next row or the padding, are cut off at e).
// Usually one block (the cursor moves a few entries a box): a compare and a
// count where a search step by step mispredicted its exit.
template <class Lanes>
HGCD_SWEEP_INLINE size_t floor_entry(const float *reach, size_t j, size_t e, float v) {
    for (;;) {
        const unsigned step = unsigned(__builtin_ctz(~Lanes::below(reach + j, v)));
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
// mispredicted about once a box. Chunks of 32: longer ones separated each
// box's pairs more and slowed the narrow phase, which reads the bodies of
// the pairs in their order.
template <class Lanes>
HGCD_SWEEP_INLINE void sweep_rows(const Grid::BoxArrays &A, const RowReach &row_reach, size_t ib, size_t ie,
                                  const Grid::BoxArrays &B, const size_t *jb, const size_t *je,
                                  const uint8_t *need, int rows, bool own_row, PairBuffer &out) {
    const float *BL = B.low_x, *BP = B.reach;
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
                const float right = A.high_x[i];
                if (A.low_x[i + 1] <= right) scan(Lanes(A, i), A, i + 1, ie, right, A.slot[i], out);
            }
        if (!live) continue;  // (own-row pairs only from here on)
        for (size_t i = cb; i < ce; ++i)
            bits[i - cb] = uint8_t(row_reach.bits(A.low_y[i], A.high_y[i], A.low_z[i], A.high_z[i]));
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
                j = floor_entry<Lanes>(BP, j, e, A.low_x[i]);
                if (j == e) {
                    live &= ~(1u << r);
                    break;
                }
                const float right = A.high_x[i];
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

// Where the rows at the given offsets from row key `row` are among the
// rows `keys` (entries from start[k]), as entry ranges [jb, je) (empty where
// the row is not there): cur holds the cursors, which only move forward
// while rows are visited in order.
template <int kRows>
HGCD_SWEEP_INLINE void find_rows(const std::vector<CellKey> &keys, const uint32_t *start, CellKey row,
                                 const CellKey *off, size_t *cur, size_t *jb, size_t *je) {
    for (int r = 0; r < kRows; ++r) {
        const CellKey target = row + off[r];
        const size_t k = cur[r] = advance(keys, cur[r], target);
        const bool found = k < keys.size() && keys[k] == target;
        jb[r] = found ? start[k] : 0;
        je[r] = found ? start[k + 1] : 0;
    }
}

// A level's residents, rows (z, y) sorted by key and each by low x: each
// body meets the later bodies of its own row up to its high x (sweep and
// prune: a pair of the row is found from the member with the lower low x),
// and is swept against the rows (z, y+1), (z+1, y-1), (z+1, y) and
// (z+1, y+1) (the later half of the 3x3 rows around it in key order, so
// each pair of two rows once).
template <class Lanes>
HGCD_SWEEP_INLINE void sweep_resident_rows(const RowsView &R, int exponent, size_t begin, size_t end,
                                           PairBuffer &out) {
    const std::vector<CellKey> &rows = R.keys;
    const uint32_t *start = R.start;
    const Grid::BoxArrays &S = R.box;
    static const int later[4][2] = {{0, 1}, {1, -1}, {1, 0}, {1, 1}};
    uint8_t need[4];
    CellKey off[4];
    size_t cur[4];
    for (int r = 0; r < 4; ++r) {
        need[r] = reach_needed(later[r][0], later[r][1]);
        off[r] = row_step(later[r][0], later[r][1]);
        cur[r] = first_row(rows, rows[begin] + off[r]);
    }
    for (size_t row = begin; row < end; ++row) {
        size_t jb[4], je[4];
        find_rows<4>(rows, start, rows[row], off, cur, jb, je);
        sweep_rows<Lanes>(S, RowReach(exponent, rows[row]), start[row], start[row + 1], S, jb, je, need, 4, true,
                          out);
    }
}

// Rows of a level's guests G against the 3x3 rows of residents R around each.
template <class Lanes>
HGCD_SWEEP_INLINE void sweep_guest_rows(const RowsView &G, const RowsView &R, int exponent, size_t begin,
                                        size_t end, PairBuffer &out) {
    const std::vector<CellKey> &grows = G.keys, &rows = R.keys;
    if (rows.empty()) return;
    const uint32_t *gstart = G.start, *start = R.start;
    uint8_t need[9];
    CellKey off[9];
    size_t cur[9];
    for (int r = 0; r < 9; ++r) {
        need[r] = reach_needed(r / 3 - 1, r % 3 - 1);
        off[r] = row_step(r / 3 - 1, r % 3 - 1);
        cur[r] = first_row(rows, grows[begin] + off[r]);
    }
    for (size_t row = begin; row < end; ++row) {
        size_t jb[9], je[9];
        find_rows<9>(rows, start, grows[row], off, cur, jb, je);
        sweep_rows<Lanes>(G.box, RowReach(exponent, grows[row]), gstart[row], gstart[row + 1], R.box, jb, je, need,
                          9, false, out);
    }
}

// The first index i of [b, e) with !(v[i] < x) (or e) in an ascending
// array, searched from the hint h outwards by doubling steps, then by
// bisection: a few steps when the answer is near the hint.
template <class T>
HGCD_SWEEP_INLINE size_t seek(const T *v, size_t b, size_t e, size_t h, const T &x) {
    h = std::min(std::max(h, b), e);
    if (h < e && v[h] < x) {  // the answer is past h
        size_t lo = h + 1, step = 1, p = lo;
        while (p < e && v[p] < x) {
            lo = p + 1;
            step *= 2;
            p = lo + step - 1;
        }
        return size_t(std::lower_bound(v + lo, v + std::min(p, e), x) - v);
    }
    size_t hi = h, step = 1;  // the answer is at most h
    while (hi - b >= step && !(v[hi - step] < x)) {
        hi -= step;
        step *= 2;
    }
    const size_t lo = hi - b >= step ? hi - step + 1 : b;
    return size_t(std::lower_bound(v + lo, v + hi, x) - v);
}

// The pairs of the box q (low x, high x, low y, high y, low z, high z) with
// the entries of the rows of R in the range rr: each row found from the
// last one found (row_hint), keys of one z in a run; in each row, the scan
// starts at the first entry whose reach (the row's largest high x so far)
// reaches the box's low x (those before it end before the box), searched
// from where it started last time in that row (entry_hint), and stops with
// the block that passes its high x.
// scan_row(j, e): the entries from j up to the box's high x, of the row
// ending at e.
constexpr size_t kNearEntries = 16;  // a query's start this close to the hint is stepped to
template <class Lanes, class ScanRow>
HGCD_SWEEP_INLINE void query_rows(const RowsView &R, const float *q, const RowRange &rr, size_t &row_hint,
                                  uint32_t *entry_hint, ScanRow &&scan_row) {
    const CellKey *keys = R.keys.data();
    const size_t rows = R.keys.size();
    const CellKey last = row_key(rr.z_hi, rr.y_hi);
    size_t k = row_hint = seek(keys, 0, rows, row_hint, row_key(rr.z_lo, rr.y_lo));
    while (k < rows && keys[k] <= last) {
        const uint64_t y = uint64_t(keys[k]) & kAxisMask, z = uint64_t(keys[k] >> kAxisBits);
        if (y < rr.y_lo || y > rr.y_hi) {  // (z + 1 stays within the key's 42 bits)
            k = seek(keys, k, rows, k, y < rr.y_lo ? row_key(z, rr.y_lo) : row_key(z + 1, rr.y_lo));
            continue;
        }
        // (Forward from the hint a block at a time, as the sweeps' cursors
        // move, when the start is near; else by seek, back or far ahead:
        // sparse queries, such as the re-searches of a few moved bodies,
        // land far from the last one in the row, and stepping there block
        // by block read the row's whole stretch.)
        const size_t b = R.start[k], e = R.start[k + 1];
        const size_t h = std::min<size_t>(std::max<size_t>(entry_hint[k], b), e);
        const size_t near = std::min<size_t>(h + kNearEntries, e);
        const size_t j = (h > b && !(R.box.reach[h - 1] < q[0])) || (near < e && R.box.reach[near] < q[0])
                             ? seek(R.box.reach, b, e, h, q[0])
                             : floor_entry<Lanes>(R.box.reach, h, e, q[0]);
        entry_hint[k] = uint32_t(j);
        if (j < e && R.box.low_x[j] <= q[1]) scan_row(j, e);
        ++k;
    }
}

#if HGCD_AVX2
__attribute__((target("avx2"), noinline)) void query_rows_avx2(const RowsView &R, const float *q, uint32_t self,
                                                               const RowRange &rr, size_t &row_hint,
                                                               uint32_t *entry_hint, PairBuffer &out) {
    const Grid::BoxArrays box{q, q + 1, q + 2, q + 3, q + 4, q + 5, nullptr, nullptr};
    const Lanes8 lanes(box, 0);
    query_rows<Lanes8>(R, q, rr, row_hint, entry_hint,
                       [&](size_t j, size_t e) { scan(lanes, R.box, j, e, q[1], self, out); });
}
#endif

// The entries [j, e) of a list that meet the box of `lanes`, appended to
// out with their boxes, a block at a time up to the block holding the first
// whose low x passes `right` (needs j < e; the padding past e is read and
// masked). Hits are few a block: a branch each.
template <class Lanes>
HGCD_SWEEP_INLINE void scan_boxes(const Lanes &lanes, const Grid::BoxArrays &B, size_t j, size_t e, float right,
                                  std::vector<Grid::QueryBox> &out) {
    constexpr int kBlock = Lanes::kBlock;
    for (;; j += kBlock) {
        unsigned hits = lanes.test(B, j);
        if (j + kBlock > e) hits &= (1u << (e - j)) - 1;
        for (; hits; hits &= hits - 1) {
            const size_t i = j + size_t(__builtin_ctz(hits));
            out.push_back(Grid::QueryBox{{B.low_x[i], B.low_y[i], B.low_z[i]}, {B.high_x[i], B.high_y[i], B.high_z[i]},
                                         B.slot[i]});
        }
        if (j + kBlock >= e || B.low_x[j + kBlock - 1] > right) return;
    }
}

#if HGCD_AVX2
__attribute__((target("avx2"), noinline)) void query_boxes_avx2(const RowsView &R, const float *q,
                                                                const RowRange &rr, size_t &row_hint,
                                                                uint32_t *entry_hint,
                                                                std::vector<Grid::QueryBox> &out) {
    const Grid::BoxArrays box{q, q + 1, q + 2, q + 3, q + 4, q + 5, nullptr, nullptr};
    const Lanes8 lanes(box, 0);
    query_rows<Lanes8>(R, q, rr, row_hint, entry_hint,
                       [&](size_t j, size_t e) { scan_boxes(lanes, R.box, j, e, q[1], out); });
}
#endif

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
    const RowsView R{lv.residents.row_keys, lv.residents.row_start.data(), lv.residents.arrays()};
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

template <class Visit>
void Grid::for_each_query_level(const float *lo, const float *hi, QueryCursors &cursors, Visit &&visit) const {
    const size_t levels = levels_.size();
    if (cursors.row.size() != levels) {
        cursors.row.assign(levels, 0);
        cursors.entry.assign(levels, {});
    }
    const double dlo[3] = {lo[0], lo[1], lo[2]}, dhi[3] = {hi[0], hi[1], hi[2]};
    const float q[6] = {lo[0], hi[0], lo[1], hi[1], lo[2], hi[2]};
    for (size_t l = 0; l < levels; ++l) {
        const List &list = levels_[l].residents;
        if (list.count() == 0) continue;
        std::vector<uint32_t> &entry = cursors.entry[l];
        if (entry.size() != list.row_keys.size()) entry.assign(list.row_keys.size(), 0);
        const RowsView R{list.row_keys, list.row_start.data(), list.arrays()};
        visit(R, rows_meeting(dlo, dhi, levels_[l].exponent), cursors.row[l], entry.data(), q);
    }
}

void Grid::query(const float *lo, const float *hi, uint32_t self, QueryCursors &cursors, PairBuffer &out) const {
    for_each_query_level(lo, hi, cursors,
                         [&](const RowsView &R, const RowRange &rr, size_t &row, uint32_t *entry, const float *q) {
#if HGCD_AVX2
                             if (use_avx2()) {
                                 query_rows_avx2(R, q, self, rr, row, entry, out);
                                 return;
                             }
#endif
                             const Grid::BoxArrays box{q, q + 1, q + 2, q + 3, q + 4, q + 5, nullptr, nullptr};
                             const Lanes4 lanes(box, 0);
                             query_rows<Lanes4>(R, q, rr, row, entry, [&](size_t j, size_t e) {
                                 scan(lanes, R.box, j, e, q[1], self, out);
                             });
                         });
}

void Grid::query_boxes(const float *lo, const float *hi, QueryCursors &cursors, std::vector<QueryBox> &out) const {
    for_each_query_level(lo, hi, cursors,
                         [&](const RowsView &R, const RowRange &rr, size_t &row, uint32_t *entry, const float *q) {
#if HGCD_AVX2
                             if (use_avx2()) {
                                 query_boxes_avx2(R, q, rr, row, entry, out);
                                 return;
                             }
#endif
                             const Grid::BoxArrays box{q, q + 1, q + 2, q + 3, q + 4, q + 5, nullptr, nullptr};
                             const Lanes4 lanes(box, 0);
                             query_rows<Lanes4>(R, q, rr, row, entry, [&](size_t j, size_t e) {
                                 scan_boxes(lanes, R.box, j, e, q[1], out);
                             });
                         });
}

}  // namespace hgcd
