// The grid update: a census of the bodies (one pass: each body's level
// exponent and, against the last update, whether its level or row changed),
// the levels it calls for, then either the lists rebuilt (other levels) or
// the changed bodies moved, and the boxes gathered.
#include <algorithm>
#include <climits>
#include <cmath>
#include <memory>
#include <vector>

#include "broad/cells.hpp"
#include "broad/float_box.hpp"
#include "broad/grid.hpp"
#include "common/cpu.hpp"
#include "common/ieee.hpp"
#include "common/parallel.hpp"

#if HGCD_AVX2
#include "broad/census_avx2.hpp"
#endif

namespace hgcd {
using namespace broad;

namespace {
// Slots the census takes at a time (and hands to a SlotPass).
constexpr int64_t kCensusBlock = 256;
// The census's exponents of a body that has no level: an empty slot, and an
// oversize body.
constexpr int kNoExponent = INT_MIN;
constexpr int kOversizeExponent = INT_MAX;
}  // namespace

// What the census reads (a copy in each thread's frame: the compiler then
// knows the table stores do not change it).
struct Grid::CensusInput {
    Boxes boxes;
    const double *r_level;
    const uint32_t *live_gen;
    uint8_t *flag;  // per slot, written: Change (incremental updates only)
    int min_exponent, max_exponent;
    bool stale_exponents;  // min_exponent changed since the last update: every exponent again
    bool incremental;      // a grid to compare with (built_)
};

struct Grid::Census {
    CensusInput in;
    uint32_t slot_count;
    std::vector<uint8_t> flag;
    // Per worker: a histogram of the exponents (kExponents counts: no branch
    // on which exponent a body has, which is random), the oversize slots
    // (ascending within a range of slots; OpenMP's static schedule gives
    // worker t the t-th range, a task system any), the changed bodies and
    // their count, and the changed bodies per level (before or after;
    // touched_stride apart, a cache line from the next worker's).
    std::vector<uint64_t> histogram;
    std::vector<std::vector<uint32_t>> oversize;
    std::vector<std::vector<Moved>> changed;
    std::vector<uint64_t> changed_count;
    size_t touched_stride;
    std::vector<uint64_t> touched;
};

// What one worker appends, in its own heap record (the per-worker vectors
// share cache lines), handed over after the loop.
struct Grid::CensusThread {
    uint64_t *histogram;
    uint64_t *touched;
    std::vector<uint32_t> oversize;
    std::vector<Moved> changed;
    uint64_t changed_count = 0;
};

// The level of exponent e (kNone for kNoExponent, kOversize for
// kOversizeExponent), by the table of the last update (level_of_, replaced
// once the census is in).
inline int16_t Grid::level_index(int e) const {
    return e == kNoExponent ? kNone : e == kOversizeExponent ? kOversize : level_of_[e + kExponentBias];
}

// The level exponent of a live body: the smallest e with 2^e at least
// 2 r_level (kept per slot while the body is the same, with the slack
// 2^e - 2 r_level), or kOversizeExponent when the rounding of p + offset,
// which grows with p, could take its box farther than 2^e / 2 from p: each
// coordinate of fl(p + offset) is within 2^-53 (|p| + r_level) of exact,
// which 4e-16 |p|_1 < slack and r_level's own inflation (the world's,
// relative) cover.
inline int Grid::exponent_of(const Boxes &boxes, size_t s, int max_exponent) const {
    const int e = exponent_[s];
    const double *p = boxes.point(s);
    return e > max_exponent || kOversizeFactor * (std::fabs(p[0]) + std::fabs(p[1]) + std::fabs(p[2])) > slack_[s]
               ? kOversizeExponent
               : e;
}

// One body of the census: its exponent (anew for a new body), counted or
// listed oversize; on an incremental update, taking the levels to be those
// of the last update (they nearly always are), its row there and its
// Change. A body whose own row is unchanged keeps every coarser row too, so
// only changed bodies touch the lists (moves along x never do).
inline __attribute__((always_inline)) void Grid::census_slot(const CensusInput &in, CensusThread &mine, int64_t s,
                                                             RegionGuard &guard) {
    int e = kNoExponent;
    if (in.live_gen[s]) {
        if (gen_[s] != in.live_gen[s] || in.stale_exponents) {
            const double h2 = 2 * in.r_level[s];
            const int fresh = std::max(ceil_log2(h2), in.min_exponent);
            exponent_[s] = int16_t(fresh);
            // (Rounded down to float; 0 when it is not positive: oversize.)
            const double slack = cell_width(fresh) - h2;
            slack_[s] = std::max(float_at_most(slack), 0.0f);
        }
        e = exponent_of(in.boxes, size_t(s), in.max_exponent);
        if (e == kOversizeExponent) guard.run([&] { mine.oversize.push_back(uint32_t(s)); });
        else ++mine.histogram[e + kExponentBias];
    }
    if (!in.incremental) {
        gen_[s] = in.live_gen[s];
        return;
    }
    const int16_t li = level_index(e);
    int64_t c[2] = {0, 0};
    if (li >= 0) row_cell(in.boxes.point(size_t(s)), levels_[size_t(li)].exponent, c);
    int64_t *old = &cell_[2 * s];
    uint8_t f = kSameRow;
    if (li != level_[s] || gen_[s] != in.live_gen[s]) f = kNewMembership;
    else if (li >= 0 && (c[0] != old[0] || c[1] != old[1])) f = kNewRow;
    in.flag[s] = f;
    if (f != kSameRow) {  // (most bodies keep their row: their state is not written)
        const float x = li >= 0 ? float_low_x(in.boxes, uint32_t(s)) : 0.0f;
        guard.run([&] {
            mine.changed.push_back(Moved{uint32_t(s), level_[s], li, x, {old[0], old[1]}, {c[0], c[1]}});
        });
        ++mine.changed_count;
        if (level_[s] >= 0) ++mine.touched[level_[s]];
        if (li >= 0) ++mine.touched[li];
        level_[s] = li;
        gen_[s] = in.live_gen[s];
        old[0] = c[0];
        old[1] = c[1];
    }
}

// The census's pass, in blocks of slots, each first handed to `before`.
void Grid::take_census(Census &census, int threads, const SlotPass *before) {
    const uint32_t slot_count = census.slot_count;
    const int64_t blocks = (int64_t(slot_count) + kCensusBlock - 1) / kCensusBlock;
#if HGCD_AVX2
    // Four bodies at a time where nothing changes for them
    // (bodies_unchanged4): on an incremental update whose exponents are not
    // stale. inv: per level, the scale of its rows (0 where cell_coord
    // takes ldexp).
    const bool try_unchanged4 = census.in.incremental && !census.in.stale_exponents && use_avx2();
    std::vector<double> inv(levels_.size());
    for (size_t l = 0; l < levels_.size(); ++l) inv[l] = cell_scale(levels_[l].exponent + kRowShift);
#endif
    // Each worker's appends, made by the worker on its first range.
    std::vector<std::unique_ptr<CensusThread>> worker(static_cast<size_t>(threads));
    RegionGuard guard;  // (census_slot's appends)
    parallel_for(threads, blocks, 1, Schedule::Static, [&](int64_t block0, int64_t block1, int me) {
        const CensusInput in = census.in;
        std::unique_ptr<CensusThread> &w = worker[size_t(me)];
        if (!w) {
            w.reset(new CensusThread);
            w->histogram = census.histogram.data() + size_t(me) * kExponents;
            w->touched = census.touched.data() + size_t(me) * census.touched_stride;
        }
        CensusThread &mine = *w;
        for (int64_t block = block0; block < block1; ++block) {
            const uint32_t block_end = uint32_t(std::min<int64_t>(slot_count, (block + 1) * kCensusBlock));
            if (before) before->run(before->context, uint32_t(block * kCensusBlock), block_end);
            for (int64_t s = block * kCensusBlock; s < int64_t(block_end); ++s) {
#if HGCD_AVX2
                if (try_unchanged4 && s % 4 == 0 && s + 4 <= int64_t(block_end)) {
                    int e4[4];
                    if (bodies_unchanged4(size_t(s), in.boxes.pos, in.live_gen, gen_.data(), exponent_.data(),
                                          slack_.data(), level_.data(), cell_.data(), level_of_.data(), inv.data(),
                                          in.max_exponent, e4)) {
                        for (int k = 0; k < 4; ++k) {
                            ++mine.histogram[e4[k] + kExponentBias];
                            in.flag[size_t(s) + k] = kSameRow;
                        }
                        s += 3;
                        continue;
                    }
                }
#endif
                census_slot(in, mine, s, guard);
            }
        }
    });
    guard.rethrow();
    for (size_t me = 0; me < worker.size(); ++me) {
        if (!worker[me]) continue;
        census.oversize[me].swap(worker[me]->oversize);
        census.changed[me].swap(worker[me]->changed);
        census.changed_count[me] = worker[me]->changed_count;
    }
}

// Every body entered afresh on the levels of level_of_ (other levels than
// the last update's).
void Grid::enter_all(const Boxes &boxes, const uint32_t *live_gen, uint32_t slot_count, int max_exponent,
                     int threads) {
    parallel_for(threads, int64_t(slot_count), 4096, Schedule::Static, [&](int64_t b, int64_t e, int) {
        for (int64_t s = b; s < e; ++s) {
            level_[s] = level_index(live_gen[s] ? exponent_of(boxes, size_t(s), max_exponent) : kNoExponent);
            gen_[s] = live_gen[s];
            if (level_[s] >= 0) row_cell(boxes.point(size_t(s)), levels_[size_t(level_[s])].exponent, &cell_[2 * s]);
        }
    });
    rebuild(boxes, slot_count, threads);
}

// The changed bodies moved in the lists they leave or enter (a level's
// guests change when a finer level's bodies do); returns their count.
uint64_t Grid::apply_moves(const Census &census, int threads) {
    const size_t levels = levels_.size();
    std::vector<uint64_t> touched(levels, 0);
    for (int t = 0; t < threads; ++t)
        for (size_t l = 0; l < levels; ++l) touched[l] += census.touched[size_t(t) * census.touched_stride + l];
    std::vector<Moved> changed;
    for (const auto &v : census.changed) changed.insert(changed.end(), v.begin(), v.end());
    // In slot order, as OpenMP's static schedule leaves them (a task system
    // hands ranges out in any order): ties in the lists then fall alike.
    const auto by_slot = [](const Moved &a, const Moved &b) { return a.slot < b.slot; };
    if (!std::is_sorted(changed.begin(), changed.end(), by_slot)) std::sort(changed.begin(), changed.end(), by_slot);
    uint64_t moved_finer = 0;  // changed bodies on levels below li
    std::vector<uint8_t> dirty(2 * levels, 0);
    for (size_t li = 0; li < levels; ++li) {
        dirty[2 * li] = touched[li] != 0;
        dirty[2 * li + 1] = moved_finer != 0 && !levels_[li].queries_finer;
        moved_finer += touched[li];
    }
    update_lists(dirty, census.flag, changed, threads);
    uint64_t changed_count = 0;
    for (const uint64_t f : census.changed_count) changed_count += f;
    return changed_count;
}

GridUpdateStats Grid::update(const Boxes &boxes, const double *r_level, const uint32_t *live_gen,
                             uint32_t slot_count, const GridLimits &limits, int threads,
                             const SlotPass *before) {
    level_.resize(slot_count, kNone);
    gen_.resize(slot_count, 0);
    cell_.resize(2 * size_t(slot_count), 0);
    exponent_.resize(slot_count, 0);
    slack_.resize(slot_count, 0);
    const bool stale_exponents = limits.min_exponent != exponent_floor_;
    exponent_floor_ = limits.min_exponent;

    Census census;
    census.flag.assign(built_ ? slot_count : 0, kSameRow);
    census.in = CensusInput{boxes,           r_level, live_gen, census.flag.data(), limits.min_exponent,
                            limits.max_exponent, stale_exponents, built_};
    census.slot_count = slot_count;
    census.histogram.assign(size_t(threads) * kExponents, 0);
    census.oversize.resize(size_t(threads));
    census.changed.resize(size_t(threads));
    census.changed_count.assign(size_t(threads), 0);
    census.touched_stride = (levels_.size() + 7) / 8 * 8 + 8;
    census.touched.assign(size_t(threads) * census.touched_stride, 0);
    take_census(census, threads, before);

    LevelPlan plan = plan_levels(census.histogram, threads, limits);
    bool same_levels = built_ && plan.levels.size() == levels_.size() && plan.level_of == level_of_;
    for (size_t i = 0; same_levels && i < plan.levels.size(); ++i)
        same_levels = levels_[i].exponent == plan.levels[i].first &&
                      levels_[i].queries_finer == bool(plan.queries_finer[i]);
    level_of_.swap(plan.level_of);

    GridUpdateStats stats;
    if (!same_levels) {
        levels_.clear();
        levels_.resize(plan.levels.size());
        for (size_t i = 0; i < plan.levels.size(); ++i) {
            levels_[i].exponent = plan.levels[i].first;
            levels_[i].queries_finer = plan.queries_finer[i] != 0;
        }
        enter_all(boxes, live_gen, slot_count, limits.max_exponent, threads);
        stats.rebuilt = true;
        stats.moved = slot_count;  // every body (re-)entered
    } else {
        stats.moved = apply_moves(census, threads);
    }
    disorder_ = gather(all_lists(), boxes, split_, threads);
    oversize_.clear();
    for (const auto &local : census.oversize) oversize_.insert(oversize_.end(), local.begin(), local.end());
    if (!std::is_sorted(oversize_.begin(), oversize_.end())) std::sort(oversize_.begin(), oversize_.end());  // (as changed)
    built_ = true;
    return stats;
}

}  // namespace hgcd
