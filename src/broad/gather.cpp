// The gather: every list's box arrays brought to the current boxes, and each
// row's order by low x restored.
#include <algorithm>
#include <cmath>
#include <vector>

#include "broad/cells.hpp"
#include "broad/float_box.hpp"
#include "broad/grid.hpp"
#include "common/cpu.hpp"
#include "common/ieee.hpp"
#include "common/parallel.hpp"

namespace hgcd {
using namespace broad;

namespace {

// A list's arrays as the gather writes them.
struct GatherArrays {
    float *low_x, *high_x, *low_y, *high_y, *low_z, *high_z, *reach;
    uint32_t *slot;
};

// The boxes of the entries [k, e) of a list, rounded outward to float, where
// the entries are (end: how far ahead the prefetches may look).
void copy_boxes(const Boxes &boxes, const GatherArrays &A, size_t k, size_t e, size_t end) {
    float *const arrays[6] = {A.low_x, A.high_x, A.low_y, A.high_y, A.low_z, A.high_z};
#if HGCD_AVX2
    if (use_avx2()) k = float_boxes_avx2(boxes, A.slot, k, e, end, arrays);
#endif
    for (; k < e; ++k) {
        if (k + kAhead < end) {
            __builtin_prefetch(boxes.point(A.slot[k + kAhead]));
            __builtin_prefetch(boxes.off + 6 * size_t(A.slot[k + kAhead]));
        }
        float lo[3], hi[3];
        float_box(boxes, A.slot[k], lo, hi);
        for (int a = 0; a < 3; ++a) {
            arrays[2 * a][k] = lo[a];
            arrays[2 * a + 1][k] = hi[a];
        }
    }
}

// Restores the order by low x of the row [row_b, row_e) by insertion sort
// (between ticks the order barely changes), with each entry's largest high
// x so far; returns false when the row would take long (many bodies
// entering one row): the caller then sorts it outright. count_jumps: 1
// where the row's slot jumps count to the disorder (residents), else 0;
// prev: the slot before the row's first in sweep order, below the split
// and from it on (Grid::set_split).
inline bool insertion_sort_row(const GatherArrays &A, size_t row_b, size_t row_e, uint32_t count_jumps,
                               uint32_t split, uint32_t *prev, uint64_t &jumps) {
    float *low_x = A.low_x, *high_x = A.high_x, *low_y = A.low_y, *high_y = A.high_y, *low_z = A.low_z,
          *high_z = A.high_z, *reach = A.reach;
    uint32_t *slots = A.slot;
    size_t budget = 64;  // insertion steps left to the row
    bool whole = false;  // the row needs sorting outright
    float most = -INFINITY;  // the row's largest high x so far
    for (size_t k = row_b; k < row_e; ++k) {
        const uint32_t slot = slots[k];
        // A resident more than 64 slots from the one before it on its side
        // of the split (its box is in another stretch of memory).
        const size_t side = slot >= split;
        jumps += count_jumps & (uint32_t(slot - prev[side] + 64) > 128);
        prev[side] = slot;
        budget += 8;
        if (whole || k == row_b || !(low_x[k] < low_x[k - 1])) {
            reach[k] = most = std::max(most, high_x[k]);
            continue;
        }
        const float lx = low_x[k], hx = high_x[k], ly = low_y[k], hy = high_y[k], lz = low_z[k], hz = high_z[k];
        size_t j = k;
        for (; j > row_b && lx < low_x[j - 1]; --j) {
            low_x[j] = low_x[j - 1];
            high_x[j] = high_x[j - 1];
            low_y[j] = low_y[j - 1];
            high_y[j] = high_y[j - 1];
            low_z[j] = low_z[j - 1];
            high_z[j] = high_z[j - 1];
            slots[j] = slots[j - 1];
            if (--budget == 0) {
                whole = true;
                break;
            }
        }
        low_x[j] = lx;
        high_x[j] = hx;
        low_y[j] = ly;
        high_y[j] = hy;
        low_z[j] = lz;
        high_z[j] = hz;
        slots[j] = slot;
        // The largest high x again from where the order changed.
        most = j > row_b ? reach[j - 1] : -INFINITY;
        for (size_t t = j; t <= k; ++t) reach[t] = most = std::max(most, high_x[t]);
    }
    return !whole;
}

}  // namespace

// In parallel over parts of whole rows of all lists together (lists differ
// in size tenfold: one task per list balanced badly), a block of rows at a
// time while they are in cache: first every entry's box (reads by slot,
// nearly in sequence while storage follows the sweep order), then each
// row's order by low x.
uint64_t Grid::gather(const std::vector<List *> &lists, const Boxes &boxes, uint32_t split, int threads) {
    constexpr size_t kPart = 16384;  // entries
    constexpr size_t kBlock = 512;   // entries
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
        for (auto *v : {&list->low_x, &list->high_x, &list->low_y, &list->high_y, &list->low_z, &list->high_z,
                        &list->reach}) {
            v->resize(m + kPad);
            std::fill(v->begin() + std::ptrdiff_t(m), v->end(), 0.0f);
        }
        list->slot.resize(m + kPad);
        std::fill(list->slot.begin() + std::ptrdiff_t(m), list->slot.end(), 0u);
        // (all_lists(): residents at even positions.)
        const std::vector<size_t> cut = row_cuts(*list, kPart);
        for (size_t k = 0; k + 1 < cut.size(); ++k) parts.push_back({list, cut[k], cut[k + 1], l % 2 == 0});
    }
    std::vector<uint64_t> jumps_of(parts.size(), 0);  // each part's residents' jumps (disorder())
    parallel_for(threads, int64_t(parts.size()), 1, Schedule::Dynamic, [&](int64_t p0, int64_t p1, int) {
        for (int64_t p = p0; p < p1; ++p) {
            const Part &part = parts[size_t(p)];
            List &list = *part.list;
            const GatherArrays A{list.low_x.data(), list.high_x.data(), list.low_y.data(), list.high_y.data(),
                                 list.low_z.data(), list.high_z.data(), list.reach.data(), list.slot.data()};
            const uint32_t *start = list.row_start.data();
            const size_t end = start[part.row_e];
            uint64_t jumps = 0;
            uint32_t prev[2] = {A.slot[start[part.row_b]], A.slot[start[part.row_b]]};
            for (size_t r0 = part.row_b; r0 < part.row_e;) {
                size_t r1 = r0 + 1;
                while (r1 < part.row_e && start[r1] - start[r0] < kBlock) ++r1;
                copy_boxes(boxes, A, start[r0], start[r1], end);
                for (size_t r = r0; r < r1; ++r)
                    if (!insertion_sort_row(A, start[r], start[r + 1], part.residents, split, prev, jumps))
                        sort_row(list, start[r], start[r + 1]);  // (and its largest high x)
                r0 = r1;
            }
            jumps_of[size_t(p)] = jumps;
        }
    });
    uint64_t disorder = 0;
    for (const uint64_t j : jumps_of) disorder += j;
    return disorder;
}

// Sorts the entries [b, e) of a row outright by low x (then slot).
void Grid::sort_row(List &list, size_t b, size_t e) {
    uint32_t *slots = list.slot.data();
    float *arrays[6] = {list.low_x.data(),  list.high_x.data(), list.low_y.data(),
                        list.high_y.data(), list.low_z.data(),  list.high_z.data()};
    const float *low_x = arrays[0];
    std::vector<uint32_t> order(e - b);
    for (size_t k = 0; k < order.size(); ++k) order[k] = uint32_t(k);
    std::sort(order.begin(), order.end(), [&](uint32_t p, uint32_t q) {
        return low_x[b + p] < low_x[b + q] || (low_x[b + p] == low_x[b + q] && slots[b + p] < slots[b + q]);
    });
    std::vector<float> values(order.size());
    for (int a = 0; a < 6; ++a) {
        for (size_t k = 0; k < order.size(); ++k) values[k] = arrays[a][b + order[k]];
        std::copy(values.begin(), values.end(), arrays[a] + b);
    }
    std::vector<uint32_t> sorted_slots(order.size());
    for (size_t k = 0; k < order.size(); ++k) sorted_slots[k] = slots[b + order[k]];
    std::copy(sorted_slots.begin(), sorted_slots.end(), slots + b);
    float most = -INFINITY;
    for (size_t k = b; k < e; ++k) list.reach[k] = most = std::max(most, list.high_x[k]);
}

}  // namespace hgcd
