// The grid's cell arithmetic, shared by its files: level exponents, row
// coordinates and keys, and the row index's helpers. Inline: the census and
// the sweeps call these per body.
#pragma once
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <vector>

#include "broad/grid.hpp"

namespace hgcd {
namespace broad {

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
// Level exponents e (cell width 2^e, from the bits of a positive double)
// lie in [-1074, 1024]; tables over them are indexed by e + kExponentBias.
constexpr int kExponentBias = 1080;
constexpr int kExponents = 2110;
// A body is oversize once kOversizeFactor |p|_1 passes its slack
// (Grid::exponent_of, census.cpp, argues the factor).
constexpr double kOversizeFactor = 4e-16;
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

// The rows [z_lo, z_hi] x [y_lo, y_hi] of a level of cell width w = 2^exponent
// that can hold a resident whose box meets the box [lo, hi]: a resident's
// box lies within w / 2 of its point (Grid::exponent_of), so its point is
// within w / 2 of [lo, hi]. Widened past the rounding of these bounds, which
// grows with the coordinates. (Clamping is monotone: a far row stays in
// range.)
struct RowRange {
    uint64_t y_lo, y_hi, z_lo, z_hi;
};
inline RowRange rows_meeting(const double *lo, const double *hi, int exponent) {
    const double w = cell_width(exponent);
    auto wide = [](double v, double d) { return v + d * (1 + 1e-9) + (d < 0 ? -1 : 1) * std::fabs(v) * 0x1p-50; };
    const int e = exponent + kRowShift;
    return RowRange{clamp_bias(cell_coord(wide(lo[1], -w / 2), e)), clamp_bias(cell_coord(wide(hi[1], w / 2), e)),
                    clamp_bias(cell_coord(wide(lo[2], -w / 2), e)), clamp_bias(cell_coord(wide(hi[2], w / 2), e))};
}

// The row (y, z) of point p on the level of the given exponent.
inline void row_cell(const double *p, int level_exponent, int64_t *cell) {
    const int e = level_exponent + kRowShift;
    cell[0] = cell_coord(p[1], e);
    cell[1] = cell_coord(p[2], e);
}

// The row key on the level of exponent `level_exponent` of a body whose row
// on its own level (exponent own_exponent, at most level_exponent) is cell.
inline CellKey key_on_level(const int64_t *cell, int own_exponent, int level_exponent) {
    const int shift = std::min(level_exponent - own_exponent, 63);
    return row_key(clamp_bias(cell[1] >> shift), clamp_bias(cell[0] >> shift));
}

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

// Entries ordered by row, then low x, then slot: the lists' order. (A
// template so that Grid's members can name their private Keyed.)
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

}  // namespace broad
}  // namespace hgcd
