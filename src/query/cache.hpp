// What a world keeps for its scene queries: the tree over its bodies' boxes
// (brought up to date on the first query after a body was created,
// destroyed or moved: refitted, or rebuilt when refits have loosened it)
// and the last box, point or mesh query's results.
#pragma once
#include <cstddef>
#include <vector>

#include "hgcd/hgcd.h"
#include "query/tree.hpp"
#include "world/filter.hpp"

namespace hgcd {

struct QueryCache {
    QueryTree tree;
    bool stale = true;  // the tree does not describe the bodies' boxes any more
    // Bodies were created or destroyed since the tree was built: its items
    // are not the live bodies, and a refit (which moves boxes, not items)
    // cannot follow.
    bool rebuild = true;
    std::vector<uint32_t> item_of_slot;  // each live body's index in tree.items
    std::vector<size_t> offsets;
    std::vector<hgcd_body> bodies;
};

// Whether a query with this filter considers a body with this filter
// (hgcd.h, "Scene queries"): never a disabled body; NULL: every enabled one;
// else the pairs' rule, the query standing for a body with filter f.
inline bool filter_accepts(const hgcd_filter *f, const BodyFilter &body) {
    if (body.flags & BodyFilter::kDisabled) return false;
    return !f || filters_accept(f->category_bits, f->mask_bits, f->group_index, body.category, body.mask, body.group);
}

}  // namespace hgcd
