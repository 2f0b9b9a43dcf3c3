// Events: the pairs that began and those that ended at a detect, found by
// one merge of the previous detect's pairs (prev_pairs_) with this one's
// (pairs_), both sorted by (a.index, b.index). A pair is compared by its full
// ids, so a slot reused between two detects ends its old pairs and begins new
// ones. Each event carries both bodies' user data: a live body's from its
// storage, a body destroyed since the previous detect's from the grave its
// destruction left (only bodies that were in that detect's pairs leave one).
#include <omp.h>

#include <algorithm>
#include <cstring>
#include <vector>

#include "common/ieee.hpp"
#include "common/parallel.hpp"

#include "world/world.hpp"

namespace hgcd {

// A body of the previous pairs, destroyed since: keeps its user data for the
// ended events (called by destroy_body, with room for a grave reserved,
// before it changes anything else; may throw bad_alloc, changing nothing
// that shows). Which bodies are in the previous pairs is worked out at the
// first destruction after a detect: detects without one pay nothing for it.
void World::bury(uint32_t slot) {
    const auto &base = base_in_prev_ ? prev_pairs_ : pairs_;
    if (base.empty()) return;
    if (!base_indexed_) {
        in_pairs_.assign(live_gen_.size(), 0);
        for (const hgcd_pair &p : base) in_pairs_[p.a.index] = in_pairs_[p.b.index] = 1;
        base_indexed_ = true;
    }
    if (slot >= in_pairs_.size() || !in_pairs_[slot]) return;
    graves_.push_back(Grave{slot, live_gen_[slot], user_data_[slot]});
    in_pairs_[slot] = 0;  // (the slot's next body is in no previous pair)
}

uint64_t World::user_data_of(hgcd_body id) const {
    if (live_gen_[id.index] == id.generation) return user_data_[id.index];
    const auto at = std::lower_bound(graves_.begin(), graves_.end(), id, [](const Grave &g, hgcd_body x) {
        return g.slot < x.index || (g.slot == x.index && g.generation < x.generation);
    });
    // (A pair's body is live or was buried: see bury.)
    return at != graves_.end() && at->slot == id.index && at->generation == id.generation ? at->user_data : 0;
}

// In parts of the key range, one a thread (splitters from the new pairs),
// each merging its range of both lists into events of its own, joined in
// order afterwards.
void World::find_events(int threads) {
    const double t0 = omp_get_wtime();
    began_.clear();
    ended_.clear();
    std::sort(graves_.begin(), graves_.end(), [](const Grave &x, const Grave &y) {
        return x.slot < y.slot || (x.slot == y.slot && x.generation < y.generation);
    });
    const hgcd_pair *old_pairs = prev_pairs_.data(), *new_pairs = pairs_.data();
    const size_t n_old = prev_pairs_.size(), n_new = pairs_.size();
    const int parts = n_old + n_new >= 8192 ? threads : 1;
    auto key = [](const hgcd_pair &p) { return uint64_t(p.a.index) << 32 | p.b.index; };
    std::vector<size_t> cut_old(size_t(parts) + 1, n_old), cut_new(size_t(parts) + 1, n_new);
    cut_old[0] = cut_new[0] = 0;
    for (int p = 1; p < parts; ++p) {
        const uint64_t split = key(new_pairs[n_new * size_t(p) / size_t(parts)]);
        auto below = [&](const hgcd_pair &x, uint64_t k) { return key(x) < k; };
        cut_old[p] = size_t(std::lower_bound(old_pairs, old_pairs + n_old, split, below) - old_pairs);
        cut_new[p] = size_t(std::lower_bound(new_pairs, new_pairs + n_new, split, below) - new_pairs);
    }
    std::vector<std::vector<hgcd_pair_event>> began(static_cast<size_t>(parts)), ended(static_cast<size_t>(parts));
    parallel_for(parts, parts, 1, Schedule::Static, [&](int64_t first, int64_t last, int) {
        for (int64_t p = first; p < last; ++p) {
            std::vector<hgcd_pair_event> &b = began[size_t(p)], &e = ended[size_t(p)];
            auto event = [&](const hgcd_pair &x) { return hgcd_pair_event{x, user_data_of(x.a), user_data_of(x.b)}; };
            size_t i = cut_old[size_t(p)], j = cut_new[size_t(p)];
            const size_t i_end = cut_old[size_t(p) + 1], j_end = cut_new[size_t(p) + 1];
            while (i < i_end && j < j_end) {
                if (!std::memcmp(&old_pairs[i], &new_pairs[j], sizeof(hgcd_pair))) {  // most pairs last
                    ++i, ++j;
                    continue;
                }
                const uint64_t ko = key(old_pairs[i]), kn = key(new_pairs[j]);
                if (ko <= kn) e.push_back(event(old_pairs[i++]));  // (equal keys: the slot was reused)
                if (kn <= ko) b.push_back(event(new_pairs[j++]));
            }
            while (i < i_end) e.push_back(event(old_pairs[i++]));
            while (j < j_end) b.push_back(event(new_pairs[j++]));
        }
    });
    for (int p = 0; p < parts; ++p) {
        began_.insert(began_.end(), began[size_t(p)].begin(), began[size_t(p)].end());
        ended_.insert(ended_.end(), ended[size_t(p)].begin(), ended[size_t(p)].end());
    }
    graves_.clear();
    stats_.events_seconds = omp_get_wtime() - t0;
}

}  // namespace hgcd
