// Events: the pairs that began and those that ended at a detect, found by
// one merge of the previous detect's pairs (prev_pairs_) with this one's
// (pairs_), both sorted by (a.index, b.index). A pair is compared by its full
// ids, so a slot reused between two detects ends its old pairs and begins new
// ones. Each event carries both bodies' user data: a live body's from its
// storage, a body destroyed since the previous detect's from the graves its
// destruction left (only bodies that were in that detect's pairs leave one).
#include <omp.h>

#include <algorithm>

#include "world/world.hpp"

namespace hgcd {

namespace {

bool same_ids(const hgcd_pair &x, const hgcd_pair &y) {
    return x.a.generation == y.a.generation && x.b.generation == y.b.generation;
}

}  // namespace

// A body of the previous pairs, destroyed since: keeps its user data for the
// ended events (called by destroy_body before it changes anything else;
// may throw bad_alloc, changing nothing).
void World::bury(uint32_t slot) {
    if (slot >= in_pairs_.size() || !in_pairs_[slot]) return;
    graves_.push_back(Grave{slot, live_gen_[slot], user_data_[at_[slot]]});
    in_pairs_[slot] = 0;  // (the slot's next body is in no pair yet)
}

uint64_t World::user_data_of(hgcd_body id) const {
    if (live_gen_[id.index] == id.generation) return user_data_[at_[id.index]];
    const auto at = std::lower_bound(graves_.begin(), graves_.end(), id, [](const Grave &g, hgcd_body x) {
        return g.slot < x.index || (g.slot == x.index && g.generation < x.generation);
    });
    // (A pair's body is live or was buried: see bury.)
    return at != graves_.end() && at->slot == id.index && at->generation == id.generation ? at->user_data : 0;
}

void World::find_events() {
    const double t0 = omp_get_wtime();
    began_.clear();
    ended_.clear();
    std::sort(graves_.begin(), graves_.end(), [](const Grave &x, const Grave &y) {
        return x.slot < y.slot || (x.slot == y.slot && x.generation < y.generation);
    });
    const hgcd_pair *old_pairs = prev_pairs_.data(), *new_pairs = pairs_.data();
    const size_t n_old = prev_pairs_.size(), n_new = pairs_.size();
    auto event = [&](const hgcd_pair &p) {
        return hgcd_pair_event{p, user_data_of(p.a), user_data_of(p.b)};
    };
    size_t i = 0, j = 0;
    while (i < n_old || j < n_new) {
        const uint64_t ko = i < n_old ? pair_key(old_pairs[i].a.index, old_pairs[i].b.index) : UINT64_MAX;
        const uint64_t kn = j < n_new ? pair_key(new_pairs[j].a.index, new_pairs[j].b.index) : UINT64_MAX;
        if (ko == kn) {  // (both in range: no key is UINT64_MAX)
            if (!same_ids(old_pairs[i], new_pairs[j])) {
                ended_.push_back(event(old_pairs[i]));
                began_.push_back(event(new_pairs[j]));
            }
            ++i, ++j;
        } else if (ko < kn) {
            ended_.push_back(event(old_pairs[i++]));
        } else {
            began_.push_back(event(new_pairs[j++]));
        }
    }
    // Which slots' bodies are in this detect's pairs (they leave a grave
    // when destroyed before the next one).
    if (in_pairs_.size() < live_gen_.size()) in_pairs_.resize(live_gen_.size(), 0);
    for (size_t k = 0; k < n_old; ++k) in_pairs_[old_pairs[k].a.index] = in_pairs_[old_pairs[k].b.index] = 0;
    for (size_t k = 0; k < n_new; ++k) in_pairs_[new_pairs[k].a.index] = in_pairs_[new_pairs[k].b.index] = 1;
    graves_.clear();
    stats_.events_seconds = omp_get_wtime() - t0;
}

}  // namespace hgcd
