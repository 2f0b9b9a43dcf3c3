// The sweep order and the renumbering that brings the world's storage to
// it: the grid's per-slot state and its lists' slots follow the bodies.
#include <algorithm>
#include <vector>

#include "broad/grid.hpp"
#include "common/ieee.hpp"
#include "world/permute.hpp"

namespace hgcd {

void Grid::order(std::vector<uint32_t> &out) const {
    for (const Level &lv : levels_)
        out.insert(out.end(), lv.residents.slot.begin(), lv.residents.slot.begin() + std::ptrdiff_t(lv.residents.count()));
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
                    void *scratch, int threads) {
    const size_t n = old_of_new.size();  // (slots made since the last update are not in the grid)
    for (Level &lv : levels_)
        for (List *list : {&lv.residents, &lv.guests}) {
            uint32_t *slot = list->slot.data();
            const uint32_t *map = new_of_old.data();
            parallel_for(threads, int64_t(list->count()), 4096, Schedule::Static, [=](int64_t b, int64_t e, int) {
                uint32_t *const to = slot;  // (locals: the stores cannot change them)
                const uint32_t *const by = map;
                for (int64_t k = b; k < e; ++k) to[k] = by[to[k]];
            });
        }
    permute_records<2>(cell_.data(), old_of_new.data(), n, scratch, threads);
    permute_records<1>(gen_.data(), old_of_new.data(), n, scratch, threads);
    permute_records<1>(slack_.data(), old_of_new.data(), n, scratch, threads);
    permute_records<1>(level_.data(), old_of_new.data(), n, scratch, threads);
    permute_records<1>(exponent_.data(), old_of_new.data(), n, scratch, threads);
    for (uint32_t &s : oversize_) s = new_of_old[s];
    std::sort(oversize_.begin(), oversize_.end());
    disorder_ = 0;
}

}  // namespace hgcd
