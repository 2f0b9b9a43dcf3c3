// The grid's stage of a detect: the grid's limits (coarsened or not, from
// the candidate pairs per body) and its update with the bodies' boxes.
#include "common/ieee.hpp"

#include <algorithm>
#include <cmath>
#include <vector>

#include "common/parallel.hpp"
#include "world/world.hpp"

namespace hgcd {

Boxes World::boxes() const { return Boxes{point_.data(), box_off_.data()}; }

// The grid's limits for this detect. Coarsening (GridLimits::coarsen) is
// decided from the previous detect's candidate pairs per body, a count that
// does not depend on the grid's shape: below 3 (sparse, as scene tetra at
// its reference density, 1.4) the levels close below the coarsest join it,
// above 6 they part again: sparse scenes are much faster coarsened, while
// denser ones (11 and 32 candidates per body) are faster with the paper's
// finer levels.
//
// Before the first detect there is no count yet: it is estimated from the
// boxes as if their positions were spread evenly over their bounding box
// (estimated_candidates_per_body), which the real count soon corrects.
// Without it the first detect built the finer levels and the first step
// rebuilt the grid coarsened, both far slower.
GridLimits World::grid_limits(int threads) {
    const double per_body = candidates_per_body_ >= 0 ? candidates_per_body_ : estimated_candidates_per_body(threads);
    if (per_body >= 0) coarse_grid_ = coarse_grid_ ? per_body <= 6 : per_body < 3;
    GridLimits limits = limits_;
    limits.coarsen = coarse_grid_;
    return limits;
}

double World::estimated_candidates_per_body(int threads) const {
    const int64_t n = int64_t(stored_gen_.size());
    // Per block of bodies, merged here in block order: the same sums for
    // any thread count or schedule.
    struct Sums {
        double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
        double a1 = 0, a2 = 0, a3 = 0, count = 0;
    };
    constexpr int64_t kBlock = 16384;
    std::vector<Sums> sums(size_t((n + kBlock - 1) / kBlock));
    parallel_for(threads, int64_t(sums.size()), 1, Schedule::Static, [&](int64_t b0, int64_t b1, int) {
        for (int64_t b = b0; b < b1; ++b) {
        Sums mine;
        for (int64_t s = b * kBlock; s < std::min(n, (b + 1) * kBlock); ++s) {
            if (!stored_gen_[s]) continue;
            const double *p = &point_[3 * s];
            const float *o = &box_off_[6 * s];
            for (int k = 0; k < 3; ++k) {
                mine.lo[k] = std::min(mine.lo[k], p[k]);
                mine.hi[k] = std::max(mine.hi[k], p[k]);
            }
            // Half the box's mean side.
            const double a = ((double(o[3]) - o[0]) + (double(o[4]) - o[1]) + (double(o[5]) - o[2])) / 6;
            mine.a1 += a;
            mine.a2 += a * a;
            mine.a3 += a * a * a;
            mine.count += 1;
        }
        sums[size_t(b)] = mine;
        }
    });
    Sums all;
    for (const Sums &t : sums) {
        for (int k = 0; k < 3; ++k) {
            all.lo[k] = std::min(all.lo[k], t.lo[k]);
            all.hi[k] = std::max(all.hi[k], t.hi[k]);
        }
        all.a1 += t.a1;
        all.a2 += t.a2;
        all.a3 += t.a3;
        all.count += t.count;
    }
    const double a1 = all.a1, a2 = all.a2, a3 = all.a3, count = all.count;
    const double volume = (all.hi[0] - all.lo[0]) * (all.hi[1] - all.lo[1]) * (all.hi[2] - all.lo[2]);
    if (count < 2 || !(volume > 0) || !std::isfinite(volume)) return -1;  // no estimate
    // Cubes of half sides a_i, a_j meet when within a_i + a_j on every
    // axis: (n / V) E[8 (a_i + a_j)^3] / 2 pairs per body.
    const double e1 = a1 / count, e2 = a2 / count, e3 = a3 / count;
    return count / volume * 8 * (e3 + 3 * e2 * e1);
}

GridUpdateStats World::update_grid(int threads, const SlotPass *motion) {
    const bool first_detect = candidates_per_body_ < 0;
    // (On a step that is the world's first detect, grid_limits estimates the
    // density from the positions before this tick's moves, which run inside
    // the update: a heuristic, off by one tick's motion.)
    grid_.set_split(static_from_);
    const GridUpdateStats us = grid_.update(boxes(), r_level_.data(), grid_live(threads),
                                            uint32_t(stored_gen_.size()), grid_limits(threads), threads, motion);
    grid_rebuilt_ = us.rebuilt && !first_detect;  // (renumber need not wait after the first)
    return us;
}

}  // namespace hgcd
