// The pairs of a detect put in order: each thread's hit keys sorted, then
// the threads' shares merged into the reported pairs, in (a, b) order
// whatever the thread count.
#include <algorithm>
#include <vector>

#include "common/ieee.hpp"
#include "common/parallel.hpp"
#include "world/hit_sort.hpp"
#include "world/world.hpp"

namespace hgcd {

// Sorts pair keys (a << 32 | b) ascending: least significant digit first,
// on the keys packed as a << w | b (w the bits of the largest b: 40 bits in
// all for slots below 2^20), kDigit bits a pass, with every pass's counts
// taken in the one pass that packs. (A comparison sort of a tick's pairs
// cost more than the rest of the merge; 10-bit digits beat 8 and 11.)
void sort_keys(std::vector<uint64_t> &keys, std::vector<uint64_t> &tmp) {
    constexpr int kDigit = 10, kBuckets = 1 << kDigit;
    const size_t n = keys.size();
    if (n < 2) return;
    uint64_t high = 0, low = 0;
    for (const uint64_t k : keys) {
        high |= k >> 32;
        low |= uint32_t(k);
    }
    const int w = low ? 64 - __builtin_clzll(low) : 0;
    const int bits = (high ? 64 - __builtin_clzll(high) : 0) + w;
    const int passes = (bits + kDigit - 1) / kDigit;
    if (passes == 0) return;
    std::vector<uint32_t> count(size_t(passes) * kBuckets, 0);
    for (uint64_t &k : keys) {
        k = (k >> 32) << w | uint32_t(k);
        for (int p = 0; p < passes; ++p) ++count[size_t(p) * kBuckets + ((k >> (p * kDigit)) & (kBuckets - 1))];
    }
    tmp.resize(n);
    const uint64_t low_mask = (uint64_t(1) << w) - 1;  // (w < 64)
    for (int p = 0; p < passes; ++p) {
        uint32_t *c = &count[size_t(p) * kBuckets];
        uint32_t at = 0;
        for (int d = 0; d < kBuckets; ++d) {
            const uint32_t m = c[d];
            c[d] = at;
            at += m;
        }
        const int shift = p * kDigit;
        if (p + 1 < passes) {
            for (const uint64_t k : keys) tmp[c[(k >> shift) & (kBuckets - 1)]++] = k;
        } else {  // the last pass unpacks
            for (const uint64_t k : keys)
                tmp[c[(k >> shift) & (kBuckets - 1)]++] = (k >> w) << 32 | (k & low_mask);
        }
        keys.swap(tmp);
    }
}

// Sorts a thread's hit keys, and its contacts with them.
void sort_with_contacts(std::vector<uint64_t> &keys, std::vector<hgcd_contact> &contacts) {
    std::vector<uint32_t> order(keys.size());
    for (size_t k = 0; k < order.size(); ++k) order[k] = uint32_t(k);
    std::sort(order.begin(), order.end(), [&](uint32_t x, uint32_t y) { return keys[x] < keys[y]; });
    std::vector<uint64_t> sorted_keys(keys.size());
    std::vector<hgcd_contact> sorted(keys.size());
    for (size_t k = 0; k < order.size(); ++k) {
        sorted_keys[k] = keys[order[k]];
        sorted[k] = contacts[order[k]];
    }
    keys.swap(sorted_keys);
    contacts.swap(sorted);
}

// Merges the sorted shares of hits_ (the threads', and any kept from the
// last detect after them) into pairs_ (and contacts_, from the threads'
// shares): the output is in (a, b) order whatever the thread count, so
// identical bit for bit. In one part of the key range per thread at once
// (splitters from the longest share), each merging its range of every share
// into its place.
void World::merge_hits(int threads, bool want_contacts, const std::vector<std::vector<hgcd_contact>> &hit_contacts) {
    const int T = int(hits_.size());  // shares
    const std::vector<std::vector<uint64_t>> &hits = hits_;
    size_t count = 0, longest = 0;
    for (int t = 0; t < T; ++t) {
        count += hits[t].size();
        if (hits[t].size() > hits[longest].size()) longest = size_t(t);
    }
    pairs_.resize(count);
    if (want_contacts) contacts_.resize(count);
    const int parts = count >= 4096 ? threads : 1;
    // first[p * T + t]: where part p starts in share t (p = parts: the end).
    std::vector<size_t> first(size_t(parts + 1) * T), out_at(parts + 1, 0);
    for (int p = 0; p <= parts; ++p) {
        const std::vector<uint64_t> &l = hits[longest];
        // (no pair key is 0 or UINT64_MAX: slots are below 2^31 and a < b)
        const uint64_t splitter = p == 0 ? 0 : p == parts ? UINT64_MAX : l[l.size() * size_t(p) / size_t(parts)];
        for (int t = 0; t < T; ++t) {
            const std::vector<uint64_t> &h = hits[t];
            first[size_t(p) * T + t] = size_t(std::lower_bound(h.begin(), h.end(), splitter) - h.begin());
            out_at[p] += first[size_t(p) * T + t];
        }
    }
    parallel_for(parts, parts, 1, Schedule::Dynamic, [&](int64_t p0, int64_t p1, int) {
        for (int64_t p = p0; p < p1; ++p) {
            std::vector<size_t> head(T), end(T);
            for (int t = 0; t < T; ++t) {
                head[t] = first[size_t(p) * T + t];
                end[t] = first[size_t(p + 1) * T + t];
            }
            for (size_t k = out_at[p]; k < out_at[p + 1]; ++k) {
                int best = -1;
                for (int t = 0; t < T; ++t)
                    if (head[t] < end[t] && (best < 0 || hits[t][head[t]] < hits[best][head[best]])) best = t;
                const size_t at = head[best]++;
                const uint64_t key = hits[best][at];
                const uint32_t a = uint32_t(key >> 32), b = uint32_t(key);
                // The second slots are in no order: ask for a later pair's
                // generation early.
                if (at + 16 < end[best]) __builtin_prefetch(&live_gen_[uint32_t(hits[best][at + 16])]);
                pairs_[k] = hgcd_pair{{a, live_gen_[a]}, {b, live_gen_[b]}};
                if (want_contacts) {
                    contacts_[k] = hit_contacts[best][at];
                    contacts_[k].pair = pairs_[k];
                }
            }
        }
    });
}

}  // namespace hgcd
