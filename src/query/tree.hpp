// The scene queries' tree: a bounding volume hierarchy over the live
// bodies' boxes, built on the first query after the bodies or their poses
// changed and kept until they change again. Boxes are the grid's (they hold
// each body's rounded world vertices) rounded outward to float, so the tree
// only prunes: every body it reports is then decided exactly (solid.cpp).
#pragma once
#include <cstddef>
#include <cstdint>
#include <algorithm>
#include <cstdlib>
#include <new>
#include <vector>

namespace hgcd {

constexpr uint32_t kQueryLeafSize = 4;

// A node of the binary tree the build makes (then collapsed, below).
struct QueryNode {
    float lo[3], hi[3];  // holds every box under the node
    // Internal node (count == 0): children first and first + 1. Leaf: items
    // first .. first + count - 1.
    uint32_t first, count;
};

// A node of the tree the queries walk: up to 4 children, their boxes side
// by side per axis (two cache lines, read together: half the levels of the
// binary tree, so half the dependent memory loads of a walk). Child k < n:
// an inner node (count[k] == 0, wide node ref[k]) or a leaf (items ref[k] ..
// ref[k] + count[k] - 1). Boxes of children k >= n are empty (+inf, -inf).
struct alignas(64) QueryWide {
    float lo[3][4], hi[3][4];
    uint32_t ref[4];
    uint8_t count[4];  // (a leaf holds at most kQueryLeafSize items)
    uint32_t n;
    uint32_t pad[2];
};
static_assert(sizeof(QueryWide) == 128, "two cache lines");

struct QueryItem {
    float lo[3], hi[3];  // the body's box, rounded outward
    uint32_t slot;
    uint32_t mesh;  // mesh slot (storage indices change when the world renumbers)
};

// Storage aligned to 64 bytes: a wide node then fills two whole cache
// lines, the two lines a walk's step reads.
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
// Walks keep at most 3 waiting siblings a level, and the depth stays below
// kSahDepth + log2(n) + 2 < 80 (tree.cpp): 256 entries hold any walk.
constexpr int kQueryStack = 256;

struct QueryTree {
    // wide[0] is the root (its children: the root's, or the root alone when
    // it is a leaf); empty: no bodies. The binary tree is the build's.
    std::vector<QueryWide, CacheLineAllocator<QueryWide>> wide;
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
    // After the items' boxes changed in place: every node's box again, the
    // children's unions, bottom up (wide nodes follow their parents).
    // Returns the sum of the surface areas of the nodes' child boxes, which
    // grows as moves loosen the tree.
    double refit();
    double built_area = 0;  // refit()'s sum right after the last build
    // An order in which to answer a batch of queries, point(k, xyz) giving
    // query k's place: along a Morton curve over the tree's root box (ties
    // by index), so that queries answered one after the other walk the same
    // nodes and find them in cache. Each answer is independent of it.
    // Empty (the given order) for 2^32 queries or more.
    template <class Point>
    std::vector<uint32_t> spatial_order(size_t count, Point &&point) const;
};

// The Morton code (10 bits an axis) of p in the box [lo, hi].
uint32_t morton_code(const double *p, const float *lo, const float *hi);

template <class Point>
std::vector<uint32_t> QueryTree::spatial_order(size_t count, Point &&point) const {
    if (count > UINT32_MAX) return {};
    float lo[3] = {0, 0, 0}, hi[3] = {0, 0, 0};
    if (!wide.empty())
        for (int a = 0; a < 3; ++a) {
            lo[a] = wide[0].lo[a][0];
            hi[a] = wide[0].hi[a][0];
            for (uint32_t c = 1; c < wide[0].n; ++c) {
                lo[a] = lo[a] < wide[0].lo[a][c] ? lo[a] : wide[0].lo[a][c];
                hi[a] = hi[a] > wide[0].hi[a][c] ? hi[a] : wide[0].hi[a][c];
            }
        }
    std::vector<uint64_t> keys(count);
    for (size_t k = 0; k < count; ++k) {
        double p[3];
        point(k, p);
        keys[k] = uint64_t(morton_code(p, lo, hi)) << 32 | k;
    }
    std::sort(keys.begin(), keys.end());
    std::vector<uint32_t> order(count);
    for (size_t k = 0; k < count; ++k) order[k] = uint32_t(keys[k]);
    return order;
}

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

// segment_meets_box for the 4 children of a wide node at once (the same
// arithmetic, so the same guarantee): bit k of the result for child k < n,
// enter[k] its entry parameter.
unsigned segment_meets_children(const SegmentProbe &s, const QueryWide &w, double limit, double *enter);

}  // namespace hgcd
