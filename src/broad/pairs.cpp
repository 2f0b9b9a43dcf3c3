// The pair search: the sweeps of every level's rows (sweep.cpp), the range
// queries of the oversize bodies and of levels that keep no guests, and the
// sweep of the oversize bodies among themselves, as one parallel loop.

#include <algorithm>
#include <cmath>
#include <vector>

#include "broad/cells.hpp"
#include "broad/grid.hpp"
#include "common/ieee.hpp"
#include "common/parallel.hpp"

namespace hgcd {
using namespace broad;

namespace {

// Entries a work item of the sweeps holds about (whole rows).
constexpr size_t kChunk = 1024;

// Whether box [lo, hi] and entry j of B overlap (closed intervals).
inline bool box_meets(const double *lo, const double *hi, const Grid::BoxArrays &B, size_t j) {
    return B.low_x[j] <= hi[0] && lo[0] <= B.high_x[j] && B.low_y[j] <= hi[1] && lo[1] <= B.high_y[j] &&
           B.low_z[j] <= hi[2] && lo[2] <= B.high_z[j];
}
// The same for two boxes (low x y z, high x y z).
inline bool boxes_meet(const double *a, const double *b) {
    return b[0] <= a[3] && a[0] <= b[3] && b[1] <= a[4] && a[1] <= b[4] && b[2] <= a[5] && a[2] <= b[5];
}

}  // namespace

void Grid::query_levels(const double *lo, const double *hi, uint32_t slot, size_t level_end,
                        PairBuffer &out) const {
    for (size_t li = 0; li < level_end; ++li) {
        const Level &lv = levels_[li];
        const List &R = lv.residents;
        const BoxArrays S = R.arrays();
        const size_t m = R.count();
        if (m == 0) continue;
        // A resident j meeting the box has its row among rows_meeting's,
        // and its low x at least lo_x less w (its box is at most w wide),
        // widened past the rounding of that bound and past the float
        // rounding of the list's low x (at most |x| 2^-23 below).
        const double w = cell_width(lv.exponent);
        auto wide = [&](double v, double d) { return v + d * (1 + 1e-9) + (d < 0 ? -1 : 1) * std::fabs(v) * 0x1p-50; };
        const RowRange rr = rows_meeting(lo, hi, lv.exponent);
        const uint64_t y_lo = rr.y_lo, y_hi = rr.y_hi, z_lo = rr.z_lo, z_hi = rr.z_hi;
        const double rows = double(z_hi - z_lo + 1) * double(y_hi - y_lo + 1);
        if (rows * 32 >= double(R.row_keys.size())) {  // (most rows: every entry)
            for (size_t j = 0; j < m; ++j)
                if (box_meets(lo, hi, S, j)) out.push_back(pair_key(slot, S.slot[j]));
            continue;
        }
        const double left = wide(lo[0], -w) - (std::fabs(lo[0]) + w) * 0x1p-22 - 0x1p-140;
        for (uint64_t z = z_lo; z <= z_hi; ++z) {
            for (uint64_t y = y_lo; y <= y_hi; ++y) {
                const size_t k = first_row(R.row_keys, row_key(z, y));
                if (k == R.row_keys.size() || R.row_keys[k] != row_key(z, y)) continue;
                for (size_t j = R.row_start[k]; j < R.row_start[k + 1] && S.low_x[j] <= hi[0]; ++j)
                    if (S.low_x[j] >= left && box_meets(lo, hi, S, j)) out.push_back(pair_key(slot, S.slot[j]));
            }
        }
    }
}

// The oversize bodies among themselves: a sweep on x of their boxes.
void Grid::sweep_oversize(const Boxes &boxes, PairBuffer &out) const {
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
            if (boxes_meet(A, B)) out.push_back(pair_key(oversize_[order[i]], oversize_[order[j]]));
        }
    }
}

void Grid::find_pairs(const Boxes &boxes, int threads, std::vector<PairBuffer> &out) const {
    // Work items: chunks of every resident and guest list, one per oversize
    // body, and one for the oversize-oversize sweep. Chunks are small and
    // scheduled dynamically, because dense rows cost far more than sparse ones.
    enum class Work : uint8_t {
        kResidentRows,     // rows [begin, end) of a level's residents
        kGuestRows,        // rows [begin, end) of a level's guests
        kOversizeBody,     // oversize body begin against every level
        kOversizeSweep,    // the oversize bodies among themselves
        kResidentsQuery,   // residents [begin, end) of a level that queries the finer levels
    };
    struct Item {
        Work work;
        uint32_t level;
        size_t begin, end;
    };
    std::vector<Item> items;
    // Chunks of whole rows holding about kChunk entries each.
    auto chunk = [&](const List &list, Work work, uint32_t li) {
        const std::vector<size_t> cut = row_cuts(list, kChunk);
        for (size_t k = 0; k + 1 < cut.size(); ++k) items.push_back({work, li, cut[k], cut[k + 1]});
    };
    for (uint32_t li = 0; li < levels_.size(); ++li) {
        const Level &lv = levels_[li];
        chunk(lv.residents, Work::kResidentRows, li);
        if (lv.queries_finer) {
            for (size_t b = 0; b < lv.residents.count(); b += 64)
                items.push_back({Work::kResidentsQuery, li, b, std::min(lv.residents.count(), b + 64)});
        } else if (lv.residents.count()) {
            chunk(lv.guests, Work::kGuestRows, li);
        }
    }
    for (size_t k = 0; k < oversize_.size(); ++k) items.push_back({Work::kOversizeBody, 0, k, k + 1});
    if (oversize_.size() > 1) items.push_back({Work::kOversizeSweep, 0, 0, 0});

    parallel_for(threads, int64_t(items.size()), 1, Schedule::Dynamic, [&](int64_t k0, int64_t k1, int me) {
        PairBuffer &mine = out[size_t(me)];
        for (int64_t k = k0; k < k1; ++k) {
            const Item &it = items[size_t(k)];
            switch (it.work) {
            case Work::kResidentRows:
                sweep_residents(levels_[it.level], it.begin, it.end, mine);
                break;
            case Work::kGuestRows:
                sweep_guests(levels_[it.level], it.begin, it.end, mine);
                break;
            case Work::kOversizeBody: {
                double lo[3], hi[3];
                boxes.at(oversize_[it.begin], lo, hi);
                query_levels(lo, hi, oversize_[it.begin], levels_.size(), mine);
                break;
            }
            case Work::kResidentsQuery: {
                const BoxArrays S = levels_[it.level].residents.arrays();
                for (size_t j = it.begin; j < it.end; ++j) {
                    const double lo[3] = {S.low_x[j], S.low_y[j], S.low_z[j]};
                    const double hi[3] = {S.high_x[j], S.high_y[j], S.high_z[j]};
                    query_levels(lo, hi, S.slot[j], it.level, mine);
                }
                break;
            }
            case Work::kOversizeSweep:
                sweep_oversize(boxes, mine);
                break;
            }
        }
    });
}

}  // namespace hgcd
