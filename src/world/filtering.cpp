// Body types, enabling, filters and excluded pairs: the calls that set
// them, the pass that drops the pairs they refuse between the pair search
// and the narrow phase, and the live array the grid reads (disabled bodies
// leave the grid; motion.cpp leaves static and disabled ones where they are).

#include <algorithm>
#include <string>

#include "common/ieee.hpp"
#include "common/parallel.hpp"
#include "world/world.hpp"

namespace hgcd {

namespace {

bool known_type(int32_t type) {
    return type == HGCD_BODY_DYNAMIC || type == HGCD_BODY_KINEMATIC || type == HGCD_BODY_STATIC;
}

}  // namespace

void World::set_body_filter(size_t i, const BodyFilter &f) {
    BodyFilter &old = filter_[i];
    special_bodies_ += uint32_t(!f.plain()) - uint32_t(!old.plain());
    disabled_bodies_ += uint32_t((f.flags & BodyFilter::kDisabled) != 0) -
                        uint32_t((old.flags & BodyFilter::kDisabled) != 0);
    static_bodies_ += uint32_t(f.type == HGCD_BODY_STATIC) - uint32_t(old.type == HGCD_BODY_STATIC);
    plain_static_bodies_ += uint32_t(f.plain_static()) - uint32_t(old.plain_static());
    old = f;
    // (Temporal coherence keeps the answers of unmoved pairs: a pair whose
    // filtering changed must be searched and decided again.)
    moved_at_[i] = 1;
}

hgcd_status World::set_type(hgcd_body id, int32_t type) {
    int64_t slot;
    if (hgcd_status s = check_body(id, "body_set_type", &slot)) return s;
    if (!known_type(type))
        return fail(HGCD_ERROR_INVALID_ARGUMENT, "body_set_type: " + std::to_string(type) +
                                                     " is not HGCD_BODY_DYNAMIC, KINEMATIC or STATIC");
    BodyFilter f = filter_[at_[slot]];
    if (f.type == type) return HGCD_OK;
    f.type = uint8_t(type);
    set_body_filter(at_[slot], f);
    return HGCD_OK;
}

hgcd_status World::get_type(hgcd_body id, int32_t *out) const {
    const int64_t slot = live_body(id);
    if (slot < 0) return HGCD_ERROR_STALE_ID;
    *out = filter_[at_[slot]].type;
    return HGCD_OK;
}

hgcd_status World::set_enabled(hgcd_body id, bool enabled) {
    int64_t slot;
    if (hgcd_status s = check_body(id, "body_set_enabled", &slot)) return s;
    BodyFilter f = filter_[at_[slot]];
    if (((f.flags & BodyFilter::kDisabled) == 0) == enabled) return HGCD_OK;
    f.flags ^= BodyFilter::kDisabled;
    set_body_filter(at_[slot], f);
    return HGCD_OK;
}

hgcd_status World::get_enabled(hgcd_body id, uint32_t *out) const {
    const int64_t slot = live_body(id);
    if (slot < 0) return HGCD_ERROR_STALE_ID;
    *out = (filter_[at_[slot]].flags & BodyFilter::kDisabled) ? 0 : 1;
    return HGCD_OK;
}

hgcd_status World::set_filter(hgcd_body id, const hgcd_filter &filter) {
    int64_t slot;
    if (hgcd_status s = check_body(id, "body_set_filter", &slot)) return s;
    if (filter.reserved != 0) return fail(HGCD_ERROR_INVALID_ARGUMENT, "body_set_filter: filter.reserved is not 0");
    BodyFilter f = filter_[at_[slot]];
    if (f.category == filter.category_bits && f.mask == filter.mask_bits && f.group == filter.group_index)
        return HGCD_OK;
    f.category = filter.category_bits;
    f.mask = filter.mask_bits;
    f.group = filter.group_index;
    set_body_filter(at_[slot], f);
    return HGCD_OK;
}

hgcd_status World::get_filter(hgcd_body id, hgcd_filter *out) const {
    const int64_t slot = live_body(id);
    if (slot < 0) return HGCD_ERROR_STALE_ID;
    *out = filter_[at_[slot]].filter();
    return HGCD_OK;
}

hgcd_status World::check_pair(const char *what, hgcd_body a, hgcd_body b, int64_t *sa, int64_t *sb) const {
    if (hgcd_status s = check_body(a, what, sa)) return s;
    if (hgcd_status s = check_body(b, what, sb)) return s;
    if (*sa == *sb) return fail(HGCD_ERROR_INVALID_ARGUMENT, std::string(what) + ": a and b are the same body");
    return HGCD_OK;
}

hgcd_status World::exclude_pair(hgcd_body a, hgcd_body b, bool exclude) {
    const char *what = exclude ? "world_exclude_pair" : "world_include_pair";
    int64_t sa, sb;
    if (hgcd_status s = check_pair(what, a, b, &sa, &sb)) return s;
    const uint64_t key = pair_key(uint32_t(sa), uint32_t(sb));
    const uint32_t ends[2] = {uint32_t(sa), uint32_t(sb)};
    if (exclude) {
        if (excluded_.count(key)) return HGCD_OK;
        // Room first (each may throw): then nothing below allocates.
        std::vector<uint32_t> *with[2];
        excluded_.reserve(excluded_.size() + 1);
        for (int e = 0; e < 2; ++e) {
            with[e] = &excluded_with_[ends[e]];  // (a new empty entry is harmless)
            with[e]->reserve(with[e]->size() + 1);
        }
        excluded_.insert(key);
        for (int e = 0; e < 2; ++e) with[e]->push_back(ends[1 - e]);
    } else {
        if (!excluded_.erase(key)) return HGCD_OK;
        for (int e = 0; e < 2; ++e) {
            std::vector<uint32_t> &with = excluded_with_[ends[e]];
            with.erase(std::find(with.begin(), with.end(), ends[1 - e]));
        }
    }
    for (int e = 0; e < 2; ++e) {
        BodyFilter f = filter_[at_[ends[e]]];
        const auto it = excluded_with_.find(ends[e]);
        const bool any = it != excluded_with_.end() && !it->second.empty();
        if (!any && it != excluded_with_.end()) excluded_with_.erase(it);
        f.flags = uint8_t(any ? f.flags | BodyFilter::kExcluded : f.flags & ~BodyFilter::kExcluded);
        set_body_filter(at_[ends[e]], f);  // (marks both moved: the pair's answer changes)
    }
    return HGCD_OK;
}

hgcd_status World::pair_excluded(hgcd_body a, hgcd_body b, uint32_t *out) const {
    const int64_t sa = live_body(a), sb = live_body(b);
    if (sa < 0 || sb < 0) return HGCD_ERROR_STALE_ID;
    if (sa == sb) return HGCD_ERROR_INVALID_ARGUMENT;
    *out = excluded_.count(pair_key(uint32_t(sa), uint32_t(sb))) ? 1 : 0;
    return HGCD_OK;
}

// The exclusions of a body being destroyed (slot), each removed from its
// partner too; allocates nothing.
void World::forget_exclusions(uint32_t slot) {
    const auto it = excluded_with_.find(slot);
    if (it == excluded_with_.end()) return;
    for (const uint32_t other : it->second) {
        excluded_.erase(pair_key(slot, other));
        auto &with = excluded_with_[other];  // (present: exclusions are listed both ways)
        with.erase(std::find(with.begin(), with.end(), slot));
        if (with.empty()) {
            excluded_with_.erase(other);
            BodyFilter f = filter_[at_[other]];
            f.flags &= uint8_t(~BodyFilter::kExcluded);
            set_body_filter(at_[other], f);
        }
    }
    excluded_with_.erase(it);
}

uint64_t World::drop_filtered_pairs(int threads, std::vector<PairBuffer> &found) {
    const BodyFilter *filter = filter_.data();
    const uint32_t *slot_of = slot_of_.data();
    const bool kinematic_pairs = kinematic_pairs_;
    // Every special body a plain static one: a pair is refused exactly when
    // both are static (types_accept; plain filters accept each other).
    const bool only_static = special_bodies_ == plain_static_bodies_;
    std::vector<uint64_t> dropped(size_t(threads), 0);
    // One candidate list an item, compacted in place.
    parallel_for(threads, threads, 1, Schedule::Dynamic, [&](int64_t begin, int64_t end, int) {
        for (int64_t t = begin; t < end; ++t) {
            PairBuffer &list = found[size_t(t)];
            uint64_t *pairs = list.data();
            const size_t n = list.size();
            size_t write = 0;
            if (only_static) {
                // (The second body is read only when the first is static:
                // the pairs of a moved body with the residents near it have
                // the moved body first, and it is seldom static.)
                for (size_t k = 0; k < n; ++k) {
                    const uint64_t key = pairs[k];
                    pairs[write] = key;
                    write += filter[key >> 32].type != HGCD_BODY_STATIC ||
                             filter[uint32_t(key)].type != HGCD_BODY_STATIC;
                }
                dropped[size_t(t)] = n - write;
                list.shrink(write);
                continue;
            }
            for (size_t k = 0; k < n; ++k) {
                const uint64_t key = pairs[k];
                const BodyFilter &fa = filter[key >> 32], &fb = filter[uint32_t(key)];
                bool keep = pair_accepted(fa, fb, kinematic_pairs);
                if (keep && (fa.flags & fb.flags & BodyFilter::kExcluded))
                    keep = excluded_.count(pair_key(slot_of[key >> 32], slot_of[uint32_t(key)])) == 0;
                pairs[write] = key;  // (branch-free: most pairs are kept or most dropped, unpredictably)
                write += keep;
            }
            dropped[size_t(t)] = n - write;
            list.shrink(write);
        }
    });
    uint64_t total = 0;
    for (const uint64_t d : dropped) total += d;
    return total;
}

const uint32_t *World::grid_live(int threads) {
    if (!disabled_bodies_) return stored_gen_.data();
    const size_t n = stored_gen_.size();
    live_scratch_.resize(n);
    parallel_for(threads, int64_t(n), 4096, Schedule::Static, [&](int64_t begin, int64_t end, int) {
        for (int64_t s = begin; s < end; ++s)
            live_scratch_[size_t(s)] = (filter_[size_t(s)].flags & BodyFilter::kDisabled) ? 0 : stored_gen_[size_t(s)];
    });
    return live_scratch_.data();
}

}  // namespace hgcd
