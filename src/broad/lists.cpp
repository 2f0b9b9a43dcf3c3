// The lists' slots and row indexes: built afresh (rebuild), or brought to
// the bodies an update changed (update_lists). The gather then fills the
// boxes.
#include <algorithm>
#include <stdexcept>
#include <vector>

#include "broad/cells.hpp"
#include "broad/float_box.hpp"
#include "broad/grid.hpp"
#include "common/ieee.hpp"
#include "common/parallel.hpp"

namespace hgcd {
using namespace broad;

CellKey Grid::key_of(uint32_t slot, int level_index) const {
    return key_on_level(&cell_[2 * size_t(slot)], levels_[level_[slot]].exponent, levels_[level_index].exponent);
}

void Grid::rebuild(const Boxes &boxes, uint32_t slot_count, int threads) {
    std::vector<std::vector<Keyed>> keyed(2 * levels_.size());  // by list, as all_lists()
    for (uint32_t s = 0; s < slot_count; ++s) {
        const int16_t own = level_[s];
        if (own < 0) continue;
        const float x = float_low_x(boxes, s);  // (the low x the lists will hold)
        keyed[2 * size_t(own)].push_back({key_of(s, own), s, x});
        for (size_t li = size_t(own) + 1; li < levels_.size(); ++li)
            if (!levels_[li].queries_finer) keyed[2 * li + 1].push_back({key_of(s, int(li)), s, x});
    }
    const int64_t lists = int64_t(2 * levels_.size());
    parallel_for(threads, lists, 1, Schedule::Dynamic, [&](int64_t k0, int64_t k1, int) {
        for (int64_t k = k0; k < k1; ++k) {
            List &list = list_at(size_t(k));
            // Rows sorted by low x (the lists' float copy: no random reads in
            // the comparisons, and gather finds the order made).
            std::vector<Keyed> &in = keyed[size_t(k)];
            std::sort(in.begin(), in.end(), ByRowX<Keyed>());
            list.slot.resize(in.size());
            list.row_keys.clear();
            list.row_start.clear();
            for (size_t i = 0; i < in.size(); ++i) {
                list.slot[i] = in[i].slot;
                const CellKey key = in[i].key;  // (by value: the member is packed)
                if (i == 0 || key != list.row_keys.back()) {
                    list.row_keys.push_back(key);
                    list.row_start.push_back(uint32_t(i));
                }
            }
            list.row_start.push_back(uint32_t(in.size()));
            std::vector<Keyed>().swap(in);
        }
    });
}

// A part of a list's rows, [row_b, row_e), with the entering entries of its
// rows, add[add_b, add_e), and where its output goes in the list's spare,
// [out_b, out_e).
struct Grid::ListPart {
    List *list;
    const std::vector<Keyed> *add;
    size_t row_b, row_e, add_b, add_e, out_b, out_e;
};

// The parts of the dirty lists, cut where whole rows hold about kPart
// entries; adds[k]: the entries that enter list k, sorted. Where each
// part's output starts follows from the entries it loses, known without
// reading it (a changed body's old row names the part its entry is in, by
// the row index), and from the entries that enter in its range of rows.
std::vector<Grid::ListPart> Grid::plan_list_update(const std::vector<uint8_t> &dirty,
                                                   const std::vector<Moved> &changed,
                                                   std::vector<std::vector<Keyed>> &adds) {
    constexpr size_t kPart = 32768;  // entries
    std::vector<ListPart> work;
    for (size_t k = 0; k < dirty.size(); ++k) {
        if (!dirty[k]) continue;
        const int li = int(k / 2);
        const int exponent = levels_[size_t(li)].exponent;
        const bool guests = (k & 1) != 0;
        List &list = list_at(k);
        auto belongs = [&](int own) { return guests ? own >= 0 && own < li : own == li; };
        std::vector<Keyed> &add = adds[k];
        for (const Moved &m : changed)
            if (belongs(m.level))
                add.push_back({key_on_level(m.cell, levels_[size_t(m.level)].exponent, exponent), m.slot, m.x});
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
            const CellKey key = key_on_level(m.old_cell, levels_[size_t(m.old_level)].exponent, exponent);
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
    return work;
}

namespace {

// Rewrites a part of a list into its spare: the entries of its rows that
// stay (flag 0), merged by (row, x) with those that enter (x as of the last
// gather for the others, so that gather's insertion sort has little left to
// do). Appends the part's rows as they come out, (key, entries), to
// out_rows; returns false when the part's entries do not fill its room
// exactly (the plan is out of step with the lists). (A template so that
// it can name Grid's private ListPart.)
template <class Part>
bool merge_part(const Part &part, const uint8_t *flag, std::vector<std::pair<CellKey, uint32_t>> &out_rows) {
    const auto &list = *part.list;
    const uint32_t *slots = list.slot.data();
    const float *low_x = list.low_x.data();  // the entries' low x, as of the last gather
    const uint32_t *start = list.row_start.data();
    const auto *enter = part.add->data();
    uint32_t *out = part.list->spare.data();
    size_t a = part.add_b, w = part.out_b;
    bool full = false;  // more entries than the part's room
    // The entering entries of row keys below `until` (all, when not
    // bounded) that form rows of their own (rows that were empty).
    auto new_rows = [&](bool bounded, CellKey until) {
        while (a < part.add_e && (!bounded || CellKey(enter[a].key) < until) && w < part.out_e) {
            const CellKey key = enter[a].key;
            const size_t first = w;
            while (a < part.add_e && CellKey(enter[a].key) == key && w < part.out_e) out[w++] = enter[a++].slot;
            out_rows.push_back({key, uint32_t(w - first)});
        }
    };
    for (size_t r = part.row_b; r < part.row_e && !full; ++r) {
        const CellKey key = list.row_keys[r];
        new_rows(true, key);
        // The row's entries that stay, merged with those that enter it.
        const size_t first = w;
        for (size_t i = start[r]; i < start[r + 1]; ++i) {
            const uint32_t slot = slots[i];
            if (flag[slot]) continue;  // (entries of changed bodies leave)
            const float x = low_x[i];
            while (a < part.add_e && CellKey(enter[a].key) == key &&
                   (enter[a].x < x || (enter[a].x == x && enter[a].slot < slot)) && w < part.out_e)
                out[w++] = enter[a++].slot;
            if (w == part.out_e) {
                full = true;
                break;
            }
            out[w++] = slot;
        }
        while (a < part.add_e && CellKey(enter[a].key) == key && w < part.out_e) out[w++] = enter[a++].slot;
        if (w > first) out_rows.push_back({key, uint32_t(w - first)});
    }
    new_rows(false, 0);
    return !full && a == part.add_e && w == part.out_e;
}

}  // namespace

// Brings the lists marked dirty (residents of level k / 2 at even k, guests
// at odd k) to the changed bodies (their slots, and their levels, rows and
// low x before and after this update): their entries leave, and those that
// belong to a list now enter it at their place by (row, x); the row index
// follows (rows emptied go, rows entered come). Each list is rewritten into
// its spare array in parts of whole rows, in parallel: one pass reads and
// writes each slot once.
void Grid::update_lists(const std::vector<uint8_t> &dirty, const std::vector<uint8_t> &flag,
                        const std::vector<Moved> &changed, int threads) {
    std::vector<std::vector<Keyed>> adds(dirty.size());
    const std::vector<ListPart> work = plan_list_update(dirty, changed, adds);
    // Each part's rows as they come out: (key, entries).
    std::vector<std::vector<std::pair<CellKey, uint32_t>>> part_rows(work.size());
    // (A flag per part, not a reduction: clang refuses an orphaned reduction
    // on a variable the lambda captures.)
    std::vector<uint8_t> out_of_step(work.size(), 0);
    parallel_for(threads, int64_t(work.size()), 1, Schedule::Dynamic, [&](int64_t k0, int64_t k1, int) {
        for (int64_t k = k0; k < k1; ++k)
            out_of_step[size_t(k)] = !merge_part(work[size_t(k)], flag.data(), part_rows[size_t(k)]);
    });
    if (std::find(out_of_step.begin(), out_of_step.end(), 1) != out_of_step.end())
        throw std::logic_error("grid: a list update is out of step with its rows");
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
        list.slot.swap(list.spare);
    }
}

}  // namespace hgcd
