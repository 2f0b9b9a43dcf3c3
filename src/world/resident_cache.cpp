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
#include "common/ieee.hpp"

#include <algorithm>
#include <cfloat>
#include <cmath>
#include <vector>

#include "broad/float_box.hpp"
#include "common/parallel.hpp"
#include "world/world.hpp"

namespace hgcd {

namespace {

// Bodies a unit of the dynamic schedule.
constexpr int64_t kCacheChunk = 64;

// The fat box's margin on every side, as a share of the box's longest side:
// a body that moves a tenth of its size per tick searches the grid every few
// ticks, for a query a little wider than its box.
constexpr float kFatShare = 0.25f;
// Lengths of its last move the fat box reaches ahead of a moving body.
constexpr float kAhead = 4.0f;

bool meets(const float *lo, const float *hi, const float *lo2, const float *hi2) {
    return lo2[0] <= hi[0] && lo[0] <= hi2[0] && lo2[1] <= hi[1] && lo[1] <= hi2[1] && lo2[2] <= hi[2] &&
           lo[2] <= hi2[2];
}

}  // namespace

void World::forget_resident_cache() noexcept {
    resident_cache_.clear();
    ++mover_marks_;
}

void World::find_resident_candidates(int threads, std::vector<Grid::QueryCursors> &cursors_of) {
    const size_t k_count = side_storage_.size();
    resident_cache_.resize(k_count);  // (new movers: no list)
    std::vector<std::vector<ResidentEntry>> &old_pool = resident_pool_[resident_pool_at_];
    std::vector<std::vector<ResidentEntry>> &pool = resident_pool_[resident_pool_at_ ^ 1];
    if (pool.size() < size_t(threads)) pool.resize(size_t(threads));
    for (std::vector<ResidentEntry> &p : pool) p.clear();
    const Boxes side{side_point_.data(), side_off_.data()};
    const uint64_t marks = mover_marks_;
    parallel_for(threads, int64_t(k_count), kCacheChunk, Schedule::Dynamic, [&](int64_t k0, int64_t k1, int me) {
        PairBuffer &mine = candidates_[size_t(me)];
        std::vector<ResidentEntry> &to = pool[size_t(me)];
        for (size_t k = size_t(k0); k < size_t(k1); ++k) {
            ResidentCache &c = resident_cache_[k];
            if (!side_now_[k]) {  // (its list is in the pool dropped below)
                c.valid = false;
                continue;
            }
            const uint32_t m = side_storage_[k];
            const uint64_t high = uint64_t(m) << 32;
            float lo[3], hi[3];
            broad::float_box(side, k, lo, hi);
            const size_t begin = to.size();
            if (c.valid && lo[0] >= c.fat[0] && lo[1] >= c.fat[1] && lo[2] >= c.fat[2] && hi[0] <= c.fat[3] &&
                hi[1] <= c.fat[4] && hi[2] <= c.fat[5]) {
                const ResidentEntry *e = old_pool[c.worker].data() + c.begin;
                const bool check = c.marks != marks;
                for (uint32_t j = 0; j < c.count; ++j) {
                    if (check && mover_[e[j].slot]) continue;
                    to.push_back(e[j]);
                    if (meets(lo, hi, e[j].lo, e[j].hi)) mine.push_back(high | e[j].slot);
                }
            } else {
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
                grid_.query_boxes(c.fat, c.fat + 3, cursors_of[size_t(me)], to);
                size_t kept = begin;
                for (size_t j = begin; j < to.size(); ++j) {
                    const uint32_t x = to[j].slot;
                    if (mover_[x]) continue;  // (its box there is old, or it died)
                    to[kept++] = to[j];
                    if (meets(lo, hi, to[j].lo, to[j].hi)) mine.push_back(high | x);
                }
                to.resize(kept);
            }
            std::copy(lo, lo + 3, c.last);
            c.valid = true;
            c.worker = uint32_t(me);
            c.begin = uint32_t(begin);
            c.count = uint32_t(to.size() - begin);
            c.marks = marks;
        }
    });
    resident_pool_at_ ^= 1;
}

}  // namespace hgcd
