// Temporal coherence: a pair of bodies whose poses (bit for bit) and meshes
// are those of the last detect has that detect's answer, so it is not
// tested again. A resting pile then costs little more than its broad phase.
#include <algorithm>
#include <cstring>

#include <omp.h>

#include "common/ieee.hpp"
#include "common/parallel.hpp"
#include "world/world.hpp"

namespace hgcd {

uint64_t World::keep_unmoved_pairs(int threads, std::vector<PairBuffer> &found) {
    // Nothing to keep when every body moved (the usual tick of a simulation
    // whose bodies all move): one pass over a byte per slot.
    const size_t slots = moved_.size();
    size_t unmoved = 0;
    for (size_t s = 0; s < slots; ++s) unmoved += live_gen_[s] != 0 && !moved_[s];
    if (unmoved < 2) return 0;
    const size_t n = stored_gen_.size();
    moved_at_.resize(n);
    std::vector<uint64_t> kept(size_t(threads), 0);
    parallel_region(threads, [&](RegionGuard &guard) {
#pragma omp for schedule(static)
        for (int64_t s = 0; s < int64_t(n); ++s) moved_at_[size_t(s)] = moved_[slot_of_[size_t(s)]];
        // One candidate list a thread (find_pairs made one per thread): its
        // untested pairs leave it, the colliding ones go to that thread's hits.
#pragma omp for schedule(dynamic, 1)
        for (int t = 0; t < threads; ++t) guard.run([&] {
            PairBuffer &list = found[size_t(t)];
            uint64_t *pairs = list.data();
            size_t write = 0;
            uint64_t here = 0;
            for (size_t k = 0; k < list.size(); ++k) {
                const uint32_t a = uint32_t(pairs[k] >> 32), b = uint32_t(pairs[k]);
                if (moved_at_[a] | moved_at_[b]) {
                    pairs[write++] = pairs[k];
                    continue;
                }
                ++here;
                const uint32_t sa = std::min(slot_of_[a], slot_of_[b]), sb = std::max(slot_of_[a], slot_of_[b]);
                const auto it = std::lower_bound(prev_pairs_.begin(), prev_pairs_.end(), std::make_pair(sa, sb),
                                                 [](const hgcd_pair &p, const std::pair<uint32_t, uint32_t> &key) {
                                                     return p.a.index < key.first ||
                                                            (p.a.index == key.first && p.b.index < key.second);
                                                 });
                if (it != prev_pairs_.end() && it->a.index == sa && it->b.index == sb)
                    hits_[size_t(t)].push_back(pair_key(sa, sb));
            }
            list.shrink(write);
            kept[size_t(t)] = here;
        });
    });
    uint64_t total = 0;
    for (uint64_t k : kept) total += k;
    return total;
}

}  // namespace hgcd
