// The convex hull of a mesh's vertices (hull.cpp), for the tree path's
// first test of a pair (tree_path.cpp): two hulls apart prove the solids
// apart at the cost of a few support queries over the hull vertices, where
// the trees would be descended to their small nodes to prove it.
// Internal to src/narrow and src/world.
#pragma once
#include <cstddef>
#include <cstdint>
#include <vector>

namespace hgcd {

// The convex hull of a mesh's used vertices (Mesh::hull): its vertices, by
// which any support query over the mesh is answered (hull_support, a scan),
// and their neighbours along the hull's edges, by which one is proposed
// fast on a large hull (hull_climb).
struct Hull {
    uint32_t size = 0;            // vertices; 0: no hull
    std::vector<double> xyz;      // 3 doubles a vertex
    // x, then y, then z of every vertex, each row padded to a multiple of
    // kGroup (with vertex 0 again). The vertices are numbered in groups of
    // kGroup that lie near each other (median splits of the longest side).
    std::vector<double> rows;
    // A ball about each group of kGroup rows, kGroupFields rows of the
    // groups' count rounded up to a multiple of 4 (the padding repeats group
    // 0): centre x y z, radius (rounded up), and 2e-15 (|centre|_inf +
    // radius), what hull_support's bound adds for roundings.
    static constexpr size_t kGroup = 16;
    static constexpr size_t kGroupFields = 5;
    static constexpr size_t kMaxGroups = 64;  // beyond, hull_support scans every group
    std::vector<double> groups;
    double extent = 0;  // the largest |coordinate| of a vertex
    std::vector<uint32_t> first;  // the neighbours of vertex i: adj[first[i], first[i + 1])
    std::vector<uint32_t> adj;
    uint32_t seed[14] = {};       // the vertices farthest along the axes and the diagonals
    size_t padded() const { return rows.size() / 3; }
    size_t group_count() const { return padded() / kGroup; }
    size_t group_stride() const { return groups.size() / kGroupFields; }
};

// Up to this many vertices GJK's supports scan the hull (at 144 vertices a
// scan costs about 450 instructions against 850 for a climb), beyond it they
// climb.
constexpr uint32_t kScanHull = 256;

// The hull of the points of `vertices` (xyz each) whose flag in `used` is
// set: every such point lies in the hull of its vertices (exact:
// orientation predicates, see hull.cpp). No hull (size 0) when the points
// are coplanar, or when it has more than max_vertices vertices (stopped
// early). faces, when given, receives the hull's triangles (3 indices into
// `vertices` each, counter-clockwise seen from outside), for tests.
Hull build_hull(const double *vertices, const std::vector<char> &used, uint32_t max_vertices,
                std::vector<uint32_t> *faces = nullptr);

// A vertex of h at which fl((d0 x + d1 y) + d2 z) is largest (the lowest
// index of those), that value into *best: each vertex's within g_3 (|d0 x| +
// |d1 y| + |d2 z|) of exact. Groups whose ball's bound stays below the best
// value found are not scanned (hull.cpp): the answer is the full scan's.
uint32_t hull_support(const Hull &h, const double *dir, double *best);

// A vertex of h where dir . x is largest (exact), found by climbing from
// `start` along the hull's edges: each step to a neighbour certainly higher,
// and at the end every neighbour certainly not higher (hull.cpp argues the
// signs), which on the convex hull makes it a top. *bound then receives a
// value at least the largest fl((d0 x + d1 y) + d2 z) of a vertex (what
// hull_support's *best is exactly). UINT32_MAX when it cannot say (no
// start, a neighbour level within rounding, or a long climb): scan instead.
// A few dozen instructions from last detect's support, where a scan of a
// 144-vertex hull costs about 450.
uint32_t hull_support_near(const Hull &h, const double *dir, uint32_t start, double *bound);

// A vertex of h where dir . x is largest among its neighbours (in float),
// climbing from `start` (UINT32_MAX: the best seed): on a convex polytope
// the largest but for rounding; a proposal, never a bound.
uint32_t hull_climb(const Hull &h, const double *dir, uint32_t start);

struct RelFrame;
struct BvhNode;
struct BodyView;
struct NodeHint;

// Are the hulls of two bodies' rounded world vertices apart (certain)? f:
// a's frame with b as its other side (prepare_frame); root_a, root_b: the
// roots of their trees; v: GJK's first direction in a's frame (null: from
// b's root centre to a's); axis: when apart, the certified axis (a beyond b
// along it, a's frame); near (or null): a's and b's supports to climb from
// for v (UINT32_MAX: none), and when apart their supports along the axis
// (hull_apart.cpp).
bool hulls_apart(const RelFrame &f, const Hull &a, const BvhNode &root_a, const Hull &b, const BvhNode &root_b,
                 const double *v, double *axis, uint32_t *near = nullptr);

// hulls_apart for two bodies (views with trees, meshes with hulls), from
// the hint's axis when it has one (a world direction: R_a^T takes it to a's
// frame), the certified axis into it (axis_found) when apart.
bool bodies_hulls_apart(const RelFrame &f, const BodyView &a, const BodyView &b, NodeHint *hint);

}  // namespace hgcd
