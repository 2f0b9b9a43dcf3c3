// The pairs and events of a detect that searched around the moved bodies
// alone (incremental.cpp). Its new hits are all pairs with a body moved since
// the last detect (or created; destroyed bodies count as moved too), and the
// last pairs of two unmoved bodies are this detect's unchanged. So one merge
// of the last pairs (sorted) with the new hits (sorted) gives both: a last
// pair of two unmoved bodies is kept, with no event; a last pair with a moved
// body ended unless the new hits hold it (same slots and generations); a new
// hit began unless the last pairs held it. This replaces a pass that copied
// the kept pairs out, a merge of every share into the pairs and the events'
// own merge of the last pairs with all the new ones (events.cpp), each a pass
// over every pair of the world.
#include <omp.h>

#include <algorithm>
#include <cstring>
#include <vector>

#include "common/ieee.hpp"
#include "common/parallel.hpp"
#include "world/world.hpp"

namespace hgcd {

namespace {

inline uint64_t key_of(const hgcd_pair &p) { return uint64_t(p.a.index) << 32 | p.b.index; }

}  // namespace

size_t World::merge_moved(int threads) {
    // The threads' sorted hits as one sorted list of pairs (with their
    // generations), then pairs_ from it and prev_pairs_.
    hits_.resize(size_t(threads));
    merge_hits(threads, false, {});
    new_hits_.swap(pairs_);
    const double t0 = omp_get_wtime();
    std::sort(graves_.begin(), graves_.end(), [](const Grave &x, const Grave &y) {
        return x.slot < y.slot || (x.slot == y.slot && x.generation < y.generation);
    });
    const hgcd_pair *old_pairs = prev_pairs_.data(), *hits = new_hits_.data();
    const size_t n_old = prev_pairs_.size(), n_hits = new_hits_.size();
    // The moved slots as bits (a few kilobytes to a hundred, read at random
    // for each last pair's second slot): the live bodies moved or created
    // (moved_list_), and the destroyed ones of the last pairs (graves_).
    const size_t words = (live_gen_.size() + 63) / 64;
    moved_slots_.assign(words, 0);
    uint64_t *bits = moved_slots_.data();
    for (const uint32_t i : moved_list_) bits[slot_of_[i] >> 6] |= uint64_t(1) << (slot_of_[i] & 63);
    for (const Grave &g : graves_) bits[g.slot >> 6] |= uint64_t(1) << (g.slot & 63);
    auto moved = [bits](uint32_t slot) { return (bits[slot >> 6] >> (slot & 63)) & 1; };
    // In parts of the key range (splitters from the last pairs, usually the
    // longer list), one a thread, each written from where it would start
    // if it dropped nothing (its lists' starts summed), then moved down
    // into place; its events apart, joined in order.
    const size_t parts = n_old + n_hits >= 8192 ? size_t(threads) : 1;
    std::vector<size_t> cut_old(parts + 1, n_old), cut_new(parts + 1, n_hits);
    cut_old[0] = cut_new[0] = 0;
    for (size_t p = 1; p < parts; ++p) {
        cut_old[p] = n_old * p / parts;
        const uint64_t split = key_of(old_pairs[cut_old[p]]);
        cut_new[p] = size_t(std::lower_bound(hits, hits + n_hits, split,
                                             [](const hgcd_pair &x, uint64_t k) { return key_of(x) < k; }) -
                            hits);
    }
    pairs_.resize(n_old + n_hits);
    std::vector<std::vector<hgcd_pair_event>> began(parts), ended(parts);
    std::vector<size_t> written(parts, 0), kept(parts, 0);
    auto walk = [&](size_t p) {
        std::vector<hgcd_pair_event> &b = began[p], &e = ended[p];
        auto event = [&](const hgcd_pair &x) { return hgcd_pair_event{x, user_data_of(x.a), user_data_of(x.b)}; };
        hgcd_pair *const out = pairs_.data() + cut_old[p] + cut_new[p];
        size_t count = 0, unmoved = 0;
        size_t i = cut_old[p], j = cut_new[p];
        const size_t i_end = cut_old[p + 1], j_end = cut_new[p + 1];
        for (; i < i_end; ++i) {
            const hgcd_pair &o = old_pairs[i];
            const uint64_t ko = key_of(o);
            // The new hits before it began (no last pair has their slots).
            for (; j < j_end && key_of(hits[j]) < ko; ++j) {
                out[count++] = hits[j];
                b.push_back(event(hits[j]));
            }
            if (j < j_end && key_of(hits[j]) == ko) {  // the same slots: the same bodies, or a slot reused
                const hgcd_pair &h = hits[j++];
                out[count++] = h;
                if (h.a.generation != o.a.generation || h.b.generation != o.b.generation) {
                    e.push_back(event(o));
                    b.push_back(event(h));
                }
            } else if (!(moved(o.a.index) | moved(o.b.index))) {
                out[count++] = o;  // (kept: no event)
                ++unmoved;
            } else {
                e.push_back(event(o));
            }
        }
        for (; j < j_end; ++j) {
            out[count++] = hits[j];
            b.push_back(event(hits[j]));
        }
        written[p] = count;
        kept[p] = unmoved;
    };
    parallel_for(int(parts), int64_t(parts), 1, Schedule::Static, [&](int64_t p0, int64_t p1, int) {
        for (int64_t p = p0; p < p1; ++p) walk(size_t(p));
    });
    // (Each part's place ends at or before its written start: moved in
    // order, none overwrites a part not yet moved.)
    size_t at = written[0];
    for (size_t p = 1; p < parts; ++p) {
        std::memmove(pairs_.data() + at, pairs_.data() + cut_old[p] + cut_new[p], written[p] * sizeof(hgcd_pair));
        at += written[p];
    }
    pairs_.resize(at);
    for (size_t p = 0; p < parts; ++p) {
        began_.insert(began_.end(), began[p].begin(), began[p].end());
        ended_.insert(ended_.end(), ended[p].begin(), ended[p].end());
    }
    graves_.clear();
    stats_.events_seconds = omp_get_wtime() - t0;
    size_t all = 0;
    for (const size_t k : kept) all += k;
    return all;
}

}  // namespace hgcd
