// The moved bodies' pairs with the grid's residents during incremental
// detection, through a cache per mover of the residents near it, in the
// manner of the enlarged boxes of Box2D's tree: a moved body queries the
// grid with its box grown by a margin (its fat box) and keeps the residents
// found, with their boxes; while its box stays inside its fat box, later
// detects test it against that short list alone, in sequence, instead of
// searching the grid's rows (where each query read long stretches of rows
// shared with many static bodies, memory-bound).
//
// Why the list holds every pair: the grid's residents do not change between
// its updates, and a resident that is not a mover has the box the grid holds
// (it has not moved since the update; bodies that move, change or are
// created become movers and stay movers until the grid is updated, which
// drops every cache). So a resident that is not a mover now and whose box
// meets the moved body's box, which lies inside its fat box, met the fat box
// when the list was made, and the query found it then, with the box it still
// has. Residents that became movers (or died) since are dropped from the
// list as it is read (their pairs come from the movers' own grid); that
// check is skipped while no body has become a mover since the list was made.
//
// A list stays where it was written, in the arena of the worker that wrote
// it, and is read in place while its mover stays inside its fat box (also
// across detects where the mover rests): a detect writes only the lists it
// makes or filters anew, and the arenas are compacted once they are mostly
// garbage. Reading a list is one vector compare of each corner an entry
// and a branch-free append of the pairs.
//
// The entries hold their boxes in 16-bit steps of the list's fat box (a
// sixth of the bytes of float boxes: the lists of every mover are read at
// every detect, and their bytes were the cost), and the moved body's box is
// put on the same steps: x goes to t(x) = (x - fat low) * (steps / fat
// width), computed in double, a nondecreasing function of x (each rounding
// is), clamped to [0, steps], a low bound rounded down and a high bound up.
// Two float boxes that meet on an axis (low <= other's high) then meet on
// the steps: floor(t(low)) <= floor(t(high')) <= ceil(t(high')). So the
// candidates hold every pair the float boxes give, and perhaps a few more
// within a step (a few parts in 10^5 of the fat box), which the narrow
// phase decides like any other.
#include "common/ieee.hpp"

#include <algorithm>
#include <cfloat>
#include <cmath>
#include <new>
#include <vector>
#include <cstdio>
#include <cstdlib>

#if defined(__SSE2__)
#include <immintrin.h>
#endif

#include "broad/float_box.hpp"
#include "common/parallel.hpp"
#include "world/world.hpp"

namespace hgcd {

namespace {

// Bodies a unit of the dynamic schedule.
constexpr int64_t kCacheChunk = 64;

// The fat box's margin on every side, as a share of the box's longest side:
// a body that moves a tenth of its size per tick searches the grid every
// several ticks, for a query a little wider than its box. (A search cost
// about a microsecond, a list's entry a few nanoseconds at every detect:
// on scene tetra, one body in ten moving, a quarter searched more often
// and a whole side read longer lists, both for a longer detect.)
constexpr float kFatShare = 0.5f;
// Lengths of its last move the fat box reaches ahead of a moving body.
constexpr float kAhead = 4.0f;
// Entries past twice the valid lists' that the arenas may hold before they
// are compacted.
constexpr size_t kArenaSlack = size_t(1) << 16;
// Steps of a list's scale across its fat box.
constexpr double kSteps = 32767;

// A list's scale (see the file's header): per axis, the fat box's low end
// and steps per unit (0, with low end 0, for a fat box without a finite
// positive width: every box then meets on that axis).
struct Scale {
    double low[3], per[3];
    explicit Scale(const float *fat) {
        for (int a = 0; a < 3; ++a) {
            const double lo = fat[a], width = double(fat[3 + a]) - lo;
            const bool ok = std::isfinite(lo) && width > 0 && std::isfinite(width);
            low[a] = ok ? lo : 0;
            per[a] = ok ? kSteps / width : 0;
        }
    }
    double at(float x, int a) const { return std::min(std::max((double(x) - low[a]) * per[a], 0.0), kSteps); }
    // (Of t >= 0: floor by truncation, ceil one more when that was below.)
    int16_t down(float x, int a) const { return int16_t(at(x, a)); }
    int16_t up(float x, int a) const {
        const double t = at(x, a);
        const int16_t f = int16_t(t);
        return int16_t(f + (double(f) < t));
    }
};

// Appends high | slot to out for each of the n entries at e whose box meets
// the box q on the list's steps (q: high corner, then low corner negated:
// an entry meets it when each of its six values is at most q's), without a
// branch an entry.
template <class Entry>
void test_list(const Entry *e, size_t n, const int16_t *q, uint64_t high, PairBuffer &out) {
    uint64_t *to = out.room(n);
    size_t hits = 0;
#if defined(__SSE2__)
    static_assert(sizeof(Entry) == 16, "an entry is one vector");
    const __m128i m = _mm_setr_epi16(q[0], q[1], q[2], q[3], q[4], q[5], 0, 0);
    for (size_t j = 0; j < n; ++j) {
        // (The last two lanes hold the slot: their compare is dropped.)
        const __m128i v = _mm_loadu_si128(reinterpret_cast<const __m128i *>(e + j));
        to[hits] = high | e[j].slot;
        hits += (_mm_movemask_epi8(_mm_cmpgt_epi16(v, m)) & 0xFFF) == 0;
    }
#else
    for (size_t j = 0; j < n; ++j) {
        const int16_t *b = e[j].box;
        to[hits] = high | e[j].slot;
        hits += b[0] <= q[0] && b[1] <= q[1] && b[2] <= q[2] && b[3] <= q[3] && b[4] <= q[4] && b[5] <= q[5];
    }
#endif
    out.commit(hits);
}

}  // namespace

void World::forget_resident_cache() noexcept {
    resident_cache_.clear();
    for (std::vector<ResidentEntry> &a : resident_arena_) a.clear();
    ++mover_marks_;
}

void World::find_resident_candidates(int threads, std::vector<Grid::QueryCursors> &cursors_of) {
    const size_t k_count = side_storage_.size();
    resident_cache_.resize(k_count);  // (new movers: no list)
    if (resident_arena_.size() < size_t(threads)) resident_arena_.resize(size_t(threads));
    if (resident_fresh_.size() < size_t(threads)) resident_fresh_.resize(size_t(threads));
    if (resident_found_.size() < size_t(threads)) resident_found_.resize(size_t(threads));
    for (std::vector<ResidentEntry> &f : resident_fresh_) f.clear();
    // Where each worker's fresh lists will start in its arena (they are
    // appended after the pass: the arenas are read during it).
    std::vector<size_t> base(static_cast<size_t>(threads));
    for (size_t w = 0; w < base.size(); ++w) base[w] = resident_arena_[w].size();
    std::vector<size_t> live(static_cast<size_t>(threads), 0);  // entries of the valid lists
    const std::vector<std::vector<ResidentEntry>> &arena = resident_arena_;
    const Boxes side{side_point_.data(), side_off_.data()};
    const uint64_t marks = mover_marks_;
    parallel_for(threads, int64_t(k_count), kCacheChunk, Schedule::Dynamic, [&](int64_t k0, int64_t k1, int me) {
        PairBuffer &mine = candidates_[size_t(me)];
        std::vector<ResidentEntry> &fresh = resident_fresh_[size_t(me)];
        std::vector<Grid::QueryBox> &found = resident_found_[size_t(me)];
        size_t &alive = live[size_t(me)];
        for (size_t k = size_t(k0); k < size_t(k1); ++k) {
            ResidentCache &c = resident_cache_[k];
            if (!side_now_[k]) {  // (resting: its list stays for when it moves again)
                alive += c.valid ? c.count : 0;
                continue;
            }
            const uint64_t high = uint64_t(side_storage_[k]) << 32;
            float lo[3], hi[3];
            broad::float_box(side, k, lo, hi);
            const bool inside = c.valid && lo[0] >= c.fat[0] && lo[1] >= c.fat[1] && lo[2] >= c.fat[2] &&
                                hi[0] <= c.fat[3] && hi[1] <= c.fat[4] && hi[2] <= c.fat[5];
            if (!inside) {
                // The fat box: the box grown by the margin, and on the side
                // it moves to by kAhead times its last move (known if it had
                // a list); rounded down and up, it holds the box.
                float g = kFatShare * std::max(std::max(hi[0] - lo[0], hi[1] - lo[1]), hi[2] - lo[2]);
                if (!(g >= 0 && g <= FLT_MAX)) g = 0;
                for (int a = 0; a < 3; ++a) {
                    float d = c.valid ? kAhead * (lo[a] - c.last[a]) : 0;
                    if (!(std::fabs(d) <= FLT_MAX)) d = 0;
                    c.fat[a] = lo[a] - g + std::min(d, 0.0f);
                    c.fat[3 + a] = hi[a] + g + std::max(d, 0.0f);
                }
            }
            const Scale scale(c.fat);
            const int16_t q[6] = {scale.up(hi[0], 0),    scale.up(hi[1], 1),    scale.up(hi[2], 2),
                                  int16_t(-scale.down(lo[0], 0)), int16_t(-scale.down(lo[1], 1)),
                                  int16_t(-scale.down(lo[2], 2))};
            if (inside && c.marks == marks) {
                test_list(arena[c.worker].data() + c.begin, c.count, q, high, mine);
            } else {
                const size_t begin = fresh.size();
                if (inside) {
                    // Bodies became movers since the list was written: it
                    // is written anew without them.
                    const ResidentEntry *e = arena[c.worker].data() + c.begin;
                    for (uint32_t j = 0; j < c.count; ++j)
                        if (!mover_[e[j].slot]) fresh.push_back(e[j]);
                } else {
                    found.clear();
                    grid_.query_boxes(c.fat, c.fat + 3, cursors_of[size_t(me)], found);
                    for (const Grid::QueryBox &f : found) {
                        if (mover_[f.slot]) continue;  // (its box there is old, or it died)
                        fresh.push_back(ResidentEntry{{scale.down(f.lo[0], 0), scale.down(f.lo[1], 1),
                                                       scale.down(f.lo[2], 2), int16_t(-scale.up(f.hi[0], 0)),
                                                       int16_t(-scale.up(f.hi[1], 1)), int16_t(-scale.up(f.hi[2], 2))},
                                                      f.slot});
                    }
                }
                test_list(fresh.data() + begin, fresh.size() - begin, q, high, mine);
                c.valid = true;
                c.worker = uint32_t(me);
                c.begin = uint32_t(base[size_t(me)] + begin);
                c.count = uint32_t(fresh.size() - begin);
                c.marks = marks;
            }
            std::copy(lo, lo + 3, c.last);
            alive += c.count;
        }
    });
    // The fresh lists into the arenas, where their positions said. Without
    // memory for it the lists are dropped (the candidates are complete: the
    // next detect searches again).
    size_t held = 0, valid = 0;
    try {
        for (size_t w = 0; w < size_t(threads); ++w)
            resident_arena_[w].insert(resident_arena_[w].end(), resident_fresh_[w].begin(), resident_fresh_[w].end());
        for (const std::vector<ResidentEntry> &a : resident_arena_) held += a.size();
        for (const size_t l : live) valid += l;
        if (held > 2 * valid + kArenaSlack) compact_resident_lists(threads);
    } catch (const std::bad_alloc &) {
        forget_resident_cache();
    }
}

// Each worker copies the valid lists of its range of movers into an arena
// of its own, and the new arenas replace the old; the lists are pointed to
// their copies only once every copy is made (a bad_alloc before changes
// nothing).
void World::compact_resident_lists(int threads) {
    const size_t k_count = resident_cache_.size();
    std::vector<std::vector<ResidentEntry>> out(static_cast<size_t>(threads));
    std::vector<uint32_t> at(k_count);  // each valid list's begin in its new arena
    const std::vector<std::vector<ResidentEntry>> &arena = resident_arena_;
    const int64_t parts = threads;
    const auto first = [&](int64_t p) { return k_count * size_t(p) / size_t(parts); };
    parallel_for(threads, parts, 1, Schedule::Static, [&](int64_t p0, int64_t p1, int) {
        for (int64_t p = p0; p < p1; ++p) {
            std::vector<ResidentEntry> &to = out[size_t(p)];
            for (size_t k = first(p); k < first(p + 1); ++k) {
                const ResidentCache &c = resident_cache_[k];
                if (!c.valid) continue;
                at[k] = uint32_t(to.size());
                const ResidentEntry *e = arena[c.worker].data() + c.begin;
                to.insert(to.end(), e, e + c.count);
            }
        }
    });
    parallel_for(threads, parts, 1, Schedule::Static, [&](int64_t p0, int64_t p1, int) {
        for (int64_t p = p0; p < p1; ++p) {
            for (size_t k = first(p); k < first(p + 1); ++k) {
                resident_cache_[k].worker = uint32_t(p);
                resident_cache_[k].begin = at[k];
            }
        }
    });
    resident_arena_.swap(out);
}

}  // namespace hgcd
