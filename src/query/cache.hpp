// What a world keeps for its scene queries: the tree over its bodies' boxes
// (rebuilt on the first query after a body was created, destroyed or moved)
// and the last box, point or mesh query's results.
#pragma once
#include <cstddef>
#include <vector>

#include "hgcd/hgcd.h"
#include "query/tree.hpp"

namespace hgcd {

struct QueryCache {
    QueryTree tree;
    bool stale = true;  // the tree does not describe the bodies any more
    std::vector<size_t> offsets;
    std::vector<hgcd_body> bodies;
};

// Whether a query with this filter considers a body of category `category`
// and mask `mask` (hgcd.h, hgcd_query_filter). NULL: every body.
inline bool filter_accepts(const hgcd_query_filter *f, uint64_t category, uint64_t mask) {
    return !f || ((f->mask_bits & category) != 0 && (f->category_bits & mask) != 0);
}

}  // namespace hgcd
