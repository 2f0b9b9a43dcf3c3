// The levels an update's census calls for: one per exponent that has
// bodies, those with very few bodies beside the finer levels without
// guests, and where the world asks for it (GridLimits::coarsen) the levels
// close below the coarsest one with guests joined to it.
#include <vector>

#include "broad/cells.hpp"
#include "broad/grid.hpp"
#include "common/ieee.hpp"

namespace hgcd {
using namespace broad;

// Whether each level (exponent, bodies; ascending) keeps no guest list: a
// level whose bodies are very few beside the bodies of the finer levels
// (scene tetra at 750k has 1 or 2 bodies a hair above radius 2 on a fourth
// level, which would otherwise carry every other body as a guest); its
// residents query the finer levels by range instead. Hysteresis on the
// level's previous choice keeps it from flapping.
std::vector<uint8_t> Grid::few_bodies(const std::vector<std::pair<int, uint64_t>> &levels) const {
    std::vector<uint8_t> few(levels.size(), 0);
    uint64_t finer = 0;
    for (size_t i = 0; i < levels.size(); ++i) {
        bool was = false;
        for (const Level &lv : levels_) was |= built_ && lv.exponent == levels[i].first && lv.queries_finer;
        const uint64_t own = levels[i].second;
        few[i] = was ? own * 16 < finer : own * 64 < finer;
        finer += own;
    }
    return few;
}

Grid::LevelPlan Grid::plan_levels(const std::vector<uint64_t> &histogram, int threads,
                                  const GridLimits &limits) const {
    LevelPlan plan;
    std::vector<std::pair<int, uint64_t>> &census = plan.levels;  // (exponent, bodies), ascending
    for (int k = 0; k < kExponents; ++k) {
        uint64_t count = 0;
        for (int t = 0; t < threads; ++t) count += histogram[size_t(t) * kExponents + size_t(k)];
        if (count) census.push_back({k - kExponentBias, count});
    }
    // Coarsening: the levels within a factor 4 below the coarsest one that
    // keeps guests join it (see GridLimits::coarsen): the exponents
    // [join_lo, join_to) go to the level of exponent join_to.
    int join_lo = 0, join_to = 0;
    if (limits.coarsen && census.size() > 1) {
        const std::vector<uint8_t> few = few_bodies(census);
        size_t top = census.size();
        while (top > 0 && few[top - 1]) --top;
        if (top > 0) {
            const int te = census[top - 1].first, lo = te - 2;
            size_t first = top - 1;
            while (first > 0 && census[first - 1].first >= lo) --first;
            if (first < top - 1) {
                for (size_t i = first; i + 1 < top; ++i) census[top - 1].second += census[i].second;
                census.erase(census.begin() + std::ptrdiff_t(first), census.begin() + std::ptrdiff_t(top - 1));
                join_lo = lo;
                join_to = te;
            }
        }
    }
    // Each exponent's level, by table.
    plan.level_of.assign(kExponents, kNone);
    for (size_t i = 0; i < census.size(); ++i) plan.level_of[census[i].first + kExponentBias] = int16_t(i);
    for (int e = join_lo; e < join_to; ++e)
        plan.level_of[e + kExponentBias] = plan.level_of[join_to + kExponentBias];
    plan.queries_finer = few_bodies(census);
    return plan;
}

}  // namespace hgcd
