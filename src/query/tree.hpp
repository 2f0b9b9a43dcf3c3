// The scene queries' tree: a bounding volume hierarchy over the live
// bodies' boxes, built on the first query after the bodies or their poses
// changed and kept until they change again. Boxes are the grid's (they hold
// each body's rounded world vertices) rounded outward to float, so the tree
// only prunes: every body it reports is then decided exactly (solid.cpp).
#pragma once
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <new>
#include <vector>

namespace hgcd {

struct QueryNode {
    float lo[3], hi[3];  // holds every box under the node
    // Internal node (count == 0): children first and first + 1. Leaf: items
    // first .. first + count - 1.
    uint32_t first, count;
};

struct QueryItem {
    float lo[3], hi[3];  // the body's box, rounded outward
    uint32_t slot;
    uint32_t mesh;  // mesh slot (storage indices change when the world renumbers)
};

constexpr uint32_t kQueryLeafSize = 4;

// Storage aligned to 64 bytes: a node's two children (2 x 32 bytes, at an
// even index) then share one cache line, the one line a traversal step reads.
template <class T>
struct CacheLineAllocator {
    using value_type = T;
    CacheLineAllocator() = default;
    template <class U>
    CacheLineAllocator(const CacheLineAllocator<U> &) noexcept {}
    T *allocate(size_t n) {
        const size_t bytes = (n * sizeof(T) + 63) / 64 * 64;
        if (void *p = std::aligned_alloc(64, bytes)) return static_cast<T *>(p);
        throw std::bad_alloc();
    }
    void deallocate(T *p, size_t) noexcept { std::free(p); }
    template <class U>
    bool operator==(const CacheLineAllocator<U> &) const noexcept { return true; }
    template <class U>
    bool operator!=(const CacheLineAllocator<U> &) const noexcept { return false; }
};
static_assert(sizeof(QueryNode) == 32, "two nodes a cache line");
constexpr int kQueryStack = 128;  // above the tree's depth bound (tree.cpp, kSahDepth)

struct QueryTree {
    // nodes[0] is the root, nodes[1] unused, children pairs at even
    // indices; empty: no bodies.
    std::vector<QueryNode, CacheLineAllocator<QueryNode>> nodes;
    std::vector<QueryItem> items;  // in leaf order
    // World vertices of the items whose mesh has at most kCachedVertices
    // vertices (tetrahedra), kCachedVertices * 3 doubles an item in leaf
    // order, so that a query reaching them reads one place and transforms
    // nothing (filled by the world after build()).
    static constexpr uint32_t kCachedVertices = 4;
    std::vector<double> world;
    // Builds over the items (any order; the result depends only on the
    // items, sorted by slot first, so not on storage order).
    void build(std::vector<QueryItem> &&in, int threads);
};

// The closed segment from o to e as the slab test reads it; see
// segment_meets_box for why the test never drops a box the segment meets.
struct SegmentProbe {
    double o[3], e[3];
    double inv[3];       // 1 / (e - o) rounded, per axis not flat
    bool flat[3];        // |e - o| below 2^-1020 on the axis: the span is tested instead
    double smin[3], smax[3];  // the segment's exact box
    void set(const double *origin, const double *end);
};

// False only when the closed segment provably misses the closed box
// [lo, hi] (or meets it only beyond parameter limit, limit in [0, 1]).
bool segment_meets_box(const SegmentProbe &s, const float *lo, const float *hi, double limit, double *enter);

}  // namespace hgcd
