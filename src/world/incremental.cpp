// Detection around the moved bodies only. When few bodies moved since the
// last detect, the grid is not updated: the bodies created or moved since
// its last update (the movers) sit in a second, small grid of their own,
// and only the bodies moved since the last detect search for pairs: among
// the grid's other residents (whose boxes are still the ones it holds),
// among the movers, and against the oversize bodies. The pairs of two
// bodies unmoved since the last detect are that detect's (temporal
// coherence: the answer depends on poses and meshes only). Once the movers
// pass a share of the live bodies, a detect updates the grid instead and
// forgets them.
//
// Every pair of bodies whose exact boxes meet and one of which moved is
// found once: with the other a non-mover resident of the grid (the moved
// body's list of the residents near it, resident_cache.cpp), a mover (the second grid's own
// pairs), or a non-mover oversize body of the grid (its box queried in the
// second grid). The narrow phase decides each exactly, so the pairs are
// those a full detect finds, bit for bit.
#include <omp.h>

#include <algorithm>
#include <cstring>
#include <vector>

#include "broad/float_box.hpp"
#include "common/ieee.hpp"
#include "common/parallel.hpp"
#include "world/world.hpp"

namespace hgcd {

namespace {

// The movers' share of the live bodies beyond which a detect updates the
// grid rather than searching around the moved bodies.
constexpr double kMoverShare = 0.25;

}  // namespace

bool World::incremental_fits(const MovedCount &moved) const {
    return grid_.built() && double(side_storage_.size() + moved.new_movers) <= kMoverShare * double(live_bodies_);
}

void World::drop_movers() noexcept {
    std::fill(mover_.begin(), mover_.end(), uint8_t(0));  // (and the marks of the dead)
    side_storage_.clear();
    side_grid_ = Grid();
    forget_resident_cache();
}

// moved_list_: the storage indices of the `count` live bodies created or
// moved since the last detect, ascending: storage follows the grid's sweep
// order, so consecutive queries meet nearby rows and entries.
void World::list_moved(int threads, size_t count) {
    // Ranges of storage in order, one a worker, as count_moved counted and
    // found them (again if storage was renumbered since), each put in its place.
    const size_t parts = size_t(threads);
    if (moved_parts_.size() != parts) count_moved(threads);
    moved_list_.resize(count);
    const size_t n = stored_gen_.size();
    std::vector<size_t> first(parts + 1, 0);
    for (size_t p = 0; p < parts; ++p) first[p + 1] = first[p] + moved_parts_[p];
    moved_parts_.clear();
    parallel_for(threads, int64_t(parts), 1, Schedule::Static, [&](int64_t p0, int64_t p1, int) {
        for (size_t p = size_t(p0); p < size_t(p1); ++p) {
            const size_t b = n * p / parts, e = n * (p + 1) / parts, want = first[p + 1] - first[p];
            uint32_t *to = moved_list_.data() + first[p];
            if (want <= (e - b) / 4) {
                std::memcpy(to, moved_found_.data() + b, want * sizeof(uint32_t));
                continue;
            }
            // (More than count_moved kept: found again, every index written,
            // the next one over it unless it moved.)
            size_t written = 0;
            for (size_t i = b; written < want && i < e; ++i) {
                to[written] = uint32_t(i);
                written += size_t(stored_gen_[i] != 0) & size_t(moved_at_[i] != 0);
            }
        }
    });
}

// The movers: each body moved since the last detect becomes one (if it is
// not yet), and every mover's state is brought to the world's, then the
// second grid to their boxes. Returns the bodies that changed cell there.
uint64_t World::update_movers(int threads) {
    const size_t n = stored_gen_.size(), known = mover_.size();
    if (known < n) {
        mover_.resize(n);
        // (Bodies destroyed from here on are marked as they go.)
        for (size_t i = known; i < n; ++i) mover_[i] = stored_gen_[i] ? 0 : kDead;
    }
    side_storage_.reserve(side_storage_.size() + moved_list_.size());
    for (const uint32_t i : moved_list_)
        if (!(mover_[i] & kMover)) {
            ++mover_marks_;
            side_storage_.push_back(i);
            mover_[i] = kMover;
        }
    const size_t k_count = side_storage_.size();
    side_point_.resize(3 * k_count);
    side_off_.resize(6 * k_count);
    side_r_level_.resize(k_count);
    side_gen_.resize(k_count);
    side_now_.resize(k_count);
    parallel_for(threads, int64_t(k_count), 4096, Schedule::Static, [&](int64_t k0, int64_t k1, int) {
        for (int64_t k = k0; k < k1; ++k) {
            // The movers are spread over storage (one line each of the
            // arrays read): their lines asked for 16 movers ahead.
            if (k + 16 < k1) {
                const uint32_t ahead = side_storage_[size_t(k + 16)];
                __builtin_prefetch(&stored_gen_[ahead]);
                __builtin_prefetch(&moved_at_[ahead]);
                __builtin_prefetch(&point_[3 * size_t(ahead)]);
                __builtin_prefetch(&box_off_[6 * size_t(ahead)]);
                __builtin_prefetch(&r_level_[ahead]);
            }
            const uint32_t i = side_storage_[size_t(k)];
            const uint32_t gen = stored_gen_[i];
            const bool now = gen && moved_at_[i];
            side_gen_[size_t(k)] = gen;
            side_now_[size_t(k)] = now;
            if (!now) continue;
            std::memcpy(&side_point_[3 * size_t(k)], &point_[3 * size_t(i)], 3 * sizeof(double));
            std::memcpy(&side_off_[6 * size_t(k)], &box_off_[6 * size_t(i)], 6 * sizeof(float));
            side_r_level_[size_t(k)] = r_level_[i];
        }
    });
    GridLimits limits = limits_;
    limits.coarsen = coarse_grid_;
    return side_grid_
        .update(Boxes{side_point_.data(), side_off_.data()}, side_r_level_.data(), side_gen_.data(),
                uint32_t(k_count), limits, threads)
        .moved;
}

// The candidate pairs of the bodies moved since the last detect, into
// candidates_ (storage indices, a << 32 | b in either order); returns their
// count.
size_t World::find_moved_candidates(int threads) {
    candidates_.resize(size_t(threads));
    for (PairBuffer &c : candidates_) c.clear();
    side_found_.resize(size_t(threads));
    for (PairBuffer &c : side_found_) c.clear();
    const Boxes side{side_point_.data(), side_off_.data()};
    side_grid_.find_pairs(side, threads, side_found_);
    const Boxes world = boxes();
    const std::vector<uint32_t> &oversize = grid_.oversize();
    // Each worker's cursors, kept from range to range.
    std::vector<Grid::QueryCursors> cursors_of(static_cast<size_t>(threads)), side_cursors_of(cursors_of.size());
    find_resident_candidates(threads, cursors_of);
    // The grid's oversize bodies that are not movers against the movers
    // moved since the last detect.
    parallel_for(threads, int64_t(oversize.size()), 1, Schedule::Dynamic, [&](int64_t v0, int64_t v1, int me) {
        PairBuffer &mine = candidates_[size_t(me)];
        Grid::QueryCursors &side_cursors = side_cursors_of[size_t(me)];
        for (int64_t v = v0; v < v1; ++v) {
            const uint32_t o = oversize[size_t(v)];
            if (mover_[o]) continue;
            float lo[3], hi[3];
            broad::float_box(world, o, lo, hi);
            const size_t from = mine.size();
            side_grid_.query(lo, hi, o, side_cursors, mine);
            uint64_t *pairs = mine.data();
            size_t to = from;
            for (size_t p = from; p < mine.size(); ++p) {
                const uint32_t k = uint32_t(pairs[p]);
                pairs[to] = uint64_t(o) << 32 | side_storage_[k];
                to += side_now_[k];
            }
            mine.shrink(to);
            for (const uint32_t k : side_grid_.oversize()) {
                if (!side_now_[k]) continue;
                float l2[3], h2[3];
                broad::float_box(side, k, l2, h2);
                if (l2[0] <= hi[0] && lo[0] <= h2[0] && l2[1] <= hi[1] && lo[1] <= h2[1] && l2[2] <= hi[2] &&
                    lo[2] <= h2[2])
                    mine.push_back(uint64_t(o) << 32 | side_storage_[k]);
            }
        }
    });
    // The movers' own pairs with one moved since the last detect.
    parallel_for(threads, threads, 1, Schedule::Dynamic, [&](int64_t t0, int64_t t1, int me) {
        PairBuffer &mine = candidates_[size_t(me)];
        for (int64_t t = t0; t < t1; ++t) {
            for (const uint64_t key : side_found_[size_t(t)]) {
                const uint32_t p = uint32_t(key >> 32), q = uint32_t(key);
                if (side_now_[p] | side_now_[q]) mine.push_back(uint64_t(side_storage_[p]) << 32 | side_storage_[q]);
            }
        }
    });
    size_t total = 0;
    for (const PairBuffer &c : candidates_) total += c.size();
    return total;
}

void World::detect_incremental(int threads, const MovedCount &moved, double t0) {
    list_moved(threads, moved.moved);
    const uint64_t changed_cell = update_movers(threads);
    const double t1 = omp_get_wtime();
    const size_t searched = find_moved_candidates(threads);
    if (special_bodies_) stats_.filtered_pairs = drop_filtered_pairs(threads, candidates_);
    hits_.resize(size_t(threads));
    for (std::vector<uint64_t> &h : hits_) h.clear();
    const double t2 = omp_get_wtime();
    test_candidates(threads, true);  // (the last pairs of unmoved bodies: merge_moved)
    const double t3 = omp_get_wtime();

    stats_.level_count = grid_.level_count();
    stats_.oversize_count = grid_.oversize_count();
    stats_.thread_count = uint32_t(threads);
    stats_.moved_bodies = changed_cell;
    stats_.searched_bodies = moved.moved;
    stats_.candidate_pairs = uint64_t(searched) + stats_.unmoved_pairs;
    stats_.colliding_pairs = pairs_.size();
    stats_.update_seconds = t1 - t0;
    stats_.broad_seconds = t2 - t1;
    stats_.narrow_seconds = t3 - t2;
    stats_.total_seconds = t3 - t0;
}

}  // namespace hgcd
