// Temporal coherence: a pair of bodies whose poses (bit for bit) and meshes
// are those of the last detect has that detect's answer, so it is not
// tested again. A resting pile then costs little more than its broad phase,
// and a world where nothing moved costs a pass over its bodies and pairs.
#include <algorithm>
#include <cmath>
#include <cstring>
#include <new>

#include "common/ieee.hpp"
#include "common/parallel.hpp"
#include "world/world.hpp"

namespace hgcd {

// In equal ranges of storage, one a worker, without a branch a body (a
// share of them moved, in no pattern) but one a word of eight moved flags
// (storage where nothing moved, static bodies' for one, is read eight
// flags at a time). Each range's first moved bodies are written as it goes
// into moved_found_ from the range's start, for list_moved: up to a quarter
// of the range (more means too many for a search around them, and list_moved
// finds them again), the others over the last of those, in cache.
World::MovedCount World::count_moved(int threads) {
    const size_t n = stored_gen_.size(), known = mover_.size(), parts = size_t(threads);
    moved_found_.resize(n);
    std::vector<MovedCount> of(parts);
    parallel_for(threads, int64_t(parts), 1, Schedule::Static, [&](int64_t p0, int64_t p1, int) {
        for (size_t p = size_t(p0); p < size_t(p1); ++p) {
            const size_t b = n * p / parts, e = n * (p + 1) / parts;
            uint32_t *const to = moved_found_.data() + b;
            const size_t room = (e - b) / 4;
            size_t moved = 0, fresh = 0;
            auto one = [&](size_t i) {
                const size_t m = size_t(stored_gen_[i] != 0) & size_t(moved_at_[i] != 0);
                to[std::min(moved, room)] = uint32_t(i);
                moved += m;
                fresh += m & size_t(i >= known || !(mover_[i] & kMover));
            };
            size_t i = b;
            for (; i < e && (i & 7); ++i) one(i);
            for (; i + 8 <= e && moved <= room; i += 8) {
                uint64_t word;
                std::memcpy(&word, &moved_at_[i], sizeof word);
                if (!word) continue;
                for (size_t k = i; k < i + 8; ++k) one(k);
            }
            if (moved <= room) {
                for (; i < e; ++i) one(i);
            } else {
                // More than the list keeps: the rest only counted (a loop
                // the compiler vectorizes; list_moved finds them again).
                const uint32_t *const live = stored_gen_.data();
                const uint8_t *const flag = moved_at_.data(), *const mover = mover_.data();
                const size_t mid = std::max(i, std::min(e, known));
                for (; i < mid; ++i) {
                    const size_t m = size_t(live[i] != 0) & size_t(flag[i] != 0);
                    moved += m;
                    fresh += m & size_t(!(mover[i] & kMover));
                }
                for (; i < e; ++i) {
                    const size_t m = size_t(live[i] != 0) & size_t(flag[i] != 0);
                    moved += m;
                    fresh += m;
                }
            }
            of[p] = MovedCount{moved, fresh};
        }
    });
    moved_parts_.resize(parts);
    MovedCount all;
    for (size_t p = 0; p < parts; ++p) {
        moved_parts_[p] = of[p].moved;
        all.moved += of[p].moved;
        all.new_movers += of[p].new_movers;
    }
    return all;
}

void World::clear_moved() {
    std::fill(moved_at_.begin(), moved_at_.end(), uint8_t(0));
}

// No live body moved or was created: the last pairs less those of bodies
// destroyed since are this detect's.
void World::reuse_pairs() {
    pairs_.clear();
    pairs_.reserve(prev_pairs_.size());  // (may throw: then nothing is half done)
    for (const hgcd_pair &p : prev_pairs_)
        if (live_gen_[p.a.index] == p.a.generation && live_gen_[p.b.index] == p.b.generation) pairs_.push_back(p);
    stats_.unmoved_pairs = pairs_.size();
    stats_.colliding_pairs = pairs_.size();
    stats_.level_count = grid_.level_count();
    stats_.oversize_count = grid_.oversize_count();
}

uint64_t World::keep_unmoved_pairs(int threads, std::vector<PairBuffer> &found) {
    // Where each slot's pairs start in the last pairs (sorted by (a, b)):
    // a pair (a, b) is looked up among a's few.
    const size_t slots = live_gen_.size();
    prev_start_.assign(slots + 1, 0);
    for (const hgcd_pair &p : prev_pairs_) ++prev_start_[p.a.index + 1];
    for (size_t s = 0; s < slots; ++s) prev_start_[s + 1] += prev_start_[s];
    std::vector<uint64_t> kept(size_t(threads), 0);
    // One candidate list a worker (find_pairs made one per worker): its
    // untested pairs leave it, the colliding ones go to that list's hits.
    parallel_for(threads, threads, 1, Schedule::Dynamic, [&](int64_t t0, int64_t t1, int) {
        for (int64_t t = t0; t < t1; ++t) {
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
                for (uint32_t j = prev_start_[sa]; j < prev_start_[sa + 1]; ++j)
                    if (prev_pairs_[j].b.index == sb) {
                        hits_[size_t(t)].push_back(pair_key(sa, sb));
                        break;
                    }
            }
            list.shrink(write);
            kept[size_t(t)] = here;
        }
    });
    uint64_t total = 0;
    for (uint64_t k : kept) total += k;
    return total;
}

const World::NodeWitness *World::find_witness(uint64_t key) const {
    const NodeWitness *b = witness_.data(), *e = b + witness_.size();
    if (!witness_start_.empty()) {
        // The lower slot's few witnesses (pair_key: it is the high half).
        const size_t lo = size_t(key >> 32);
        if (lo + 1 >= witness_start_.size()) return nullptr;
        for (const NodeWitness *w = b + witness_start_[lo], *end = b + witness_start_[lo + 1]; w != end; ++w)
            if (w->key == key) return w;
        return nullptr;
    }
    const auto it = std::lower_bound(b, e, key, [](const NodeWitness &w, uint64_t k) { return w.key < k; });
    return it != e && it->key == key ? it : nullptr;
}

uint32_t World::pack_axis(const double *v, double sign) {
    const double l1 = (std::fabs(v[0]) + std::fabs(v[1])) + std::fabs(v[2]);
    if (!(l1 > 0) || !std::isfinite(l1)) return 0;
    double x = sign * v[0] / l1, y = sign * v[1] / l1;
    if (sign * v[2] < 0) {  // the lower half folded over the diagonals
        const double fx = std::copysign(1 - std::fabs(y), x), fy = std::copysign(1 - std::fabs(x), y);
        x = fx, y = fy;
    }
    auto word = [](double c) { return uint32_t(std::lround((std::clamp(c, -1.0, 1.0) + 1) * 32767.5)); };
    return word(x) << 16 | word(y);
}

void World::unpack_axis(uint32_t w, double *v, double sign) {
    double x = double(w >> 16) / 32767.5 - 1, y = double(w & 0xffff) / 32767.5 - 1;
    const double z = 1 - std::fabs(x) - std::fabs(y);
    if (z < 0) {
        const double fx = std::copysign(1 - std::fabs(y), x), fy = std::copysign(1 - std::fabs(x), y);
        x = fx, y = fy;
    }
    v[0] = sign * x, v[1] = sign * y, v[2] = sign * z;
}

// Sorts witnesses by key. Many (more than slots / 8): by lower slot (the
// key's high half) in one counting pass, then each slot's few by key, where
// std::sort would compare n log n times.
void World::sort_witnesses(std::vector<NodeWitness> &w, size_t slots) {
    const auto by_key = [](const NodeWitness &x, const NodeWitness &y) { return x.key < y.key; };
    if (w.size() * 8 <= slots) {
        std::sort(w.begin(), w.end(), by_key);
        return;
    }
    std::vector<uint32_t> start(slots + 1, 0);
    for (const NodeWitness &x : w) ++start[(x.key >> 32) + 1];
    for (size_t k = 0; k < slots; ++k) start[k + 1] += start[k];
    std::vector<NodeWitness> out(w.size());
    std::vector<uint32_t> at(start.begin(), start.end() - 1);
    for (const NodeWitness &x : w) out[at[x.key >> 32]++] = x;
    for (size_t k = 0; k < slots; ++k)
        if (start[k + 1] - start[k] > 1) std::sort(out.begin() + start[k], out.begin() + start[k + 1], by_key);
    w.swap(out);
}

// A merge of three sorted lists: the new witnesses (all kept), the last
// ones (for pairs kept untested: a new one replaces its pair's), and pairs_,
// whose pairs alone keep their last ones. Without memory for it the
// witnesses are dropped: they only save time.
void World::keep_witnesses(std::vector<NodeWitness> &fresh) {
    if (fresh.empty() && witness_.empty()) return;
    try {
        const auto by_key = [](const NodeWitness &x, const NodeWitness &y) { return x.key < y.key; };
        const size_t slots = live_gen_.size();
        sort_witnesses(fresh, slots);
        std::vector<NodeWitness> last;
        size_t f = 0, o = 0;
        for (const hgcd_pair &p : pairs_) {
            const uint64_t key = (uint64_t(p.a.index) << 32) | p.b.index;
            while (f < fresh.size() && fresh[f].key < key) ++f;
            while (o < witness_.size() && witness_[o].key < key) ++o;
            if (!(f < fresh.size() && fresh[f].key == key) && o < witness_.size() && witness_[o].key == key)
                last.push_back(witness_[o]);
        }
        std::vector<NodeWitness> out(fresh.size() + last.size());
        std::merge(fresh.begin(), fresh.end(), last.begin(), last.end(), out.begin(), by_key);
        // Where each lower slot's run starts, when there are enough
        // witnesses that one lookup's binary search costs more than its
        // share of this pass (a lookup then reads one slot's run).
        std::vector<uint32_t> start;
        if (out.size() * 8 > slots) {
            start.assign(slots + 1, 0);
            for (const NodeWitness &w : out) ++start[(w.key >> 32) + 1];
            for (size_t k = 0; k < slots; ++k) start[k + 1] += start[k];
        }
        witness_.swap(out);
        witness_start_.swap(start);
    } catch (const std::bad_alloc &) {
        witness_.clear();
        witness_start_.clear();
    }
}

}  // namespace hgcd
