// Midphase for large meshes: a bounding volume hierarchy over a mesh's
// triangles, built once in the mesh frame (so no pose ever rebuilds it), and
// the world-space view of a posed mesh that the narrow phase traverses.
//
// Exactness. The exact answer is defined on the world vertices of hgcd.h's
// formula (transform_point). The tree only prunes: a node is skipped when a
// box that provably holds the *rounded* world vertices of every triangle under
// it misses the other side. Leaves run the same exact triangle tests on the
// same world vertices as the direct path, so the tree never changes an answer
// (the argument for the box margin is at BodyView::node_box).
#pragma once
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <vector>

#include "common/transform.hpp"

namespace hgcd {

// Meshes with at most this many triangles get no tree: the direct path of the
// narrow phase (all world vertices, all triangle boxes) is faster for them
// (on scene `meshes` with coarse blobs the two cross between 36 and 64
// triangles).
constexpr uint32_t kBvhMinTriangles = 48;
// A leaf holds at most this many triangles.
constexpr uint32_t kBvhLeafSize = 4;

struct BvhNode {
    // Mesh frame. Every point of every triangle under the node lies in
    // [center - half, center + half] in exact arithmetic (half is rounded up).
    double center[3];
    double half[3];
    // Internal node (count == 0): children are nodes first and first + 1.
    // Leaf: triangles first .. first + count - 1 of Bvh::tris.
    uint32_t first;
    uint32_t count;
};

// A node's oriented box in the mesh frame (node_obb.cpp; stored in
// Bvh::lanes): every vertex of
// every triangle under the node is exactly center + sum_i b_i u_i with |b_i|
// <= half[i], u_i = axis[3i..3i+2] (orthonormal up to ||U U^T - I||_inf <=
// 1e-12, which the halves already absorb).
struct NodeObb {
    double center[3];
    double axis[9];
    double half[3];
};

// The frame path's node data (rel_frame.hpp), two sibling nodes per block,
// field by field: lane l of field k at 2k + l. Block p holds nodes 2p - 1
// and 2p (children are allocated in pairs after the root); block 0 holds the
// root in both lanes. Fields: the mesh-frame box's centre (0..2) and half
// (3..5), the fitted box's centre (6..8), axes (u_i at 9 + 3i) and halves
// (18..20), the node's link (21: BvhNode's first | count << 32, the bits
// of the double), so that a traversal reads no BvhNode, and its span (22:
// the triangles under it are those of leaf order first .. end - 1, first |
// end << 32: a subtree's triangles are contiguous there).
constexpr size_t kLaneBlock = 46;
constexpr int kLinkField = 21;
constexpr int kSpanField = 22;
inline size_t lane_block(uint32_t n) { return (size_t(n) + 1) >> 1; }
inline int lane_of(uint32_t n) { return int((n + 1) & 1); }
inline uint64_t node_link(const BvhNode &n) { return uint64_t(n.first) | uint64_t(n.count) << 32; }
// The link at field k, lane l of a block.
inline uint64_t lane_link(const double *block, int k, int l) {
    uint64_t w;
    std::memcpy(&w, block + 2 * k + l, sizeof w);
    return w;
}

// Sets n's centre and half widths from the box [l, h] of its points so
// that [c - half, c + half] holds [l, h] exactly: fl(x) >= x - ulp/2, and
// the next double up from the rounded half width is above the exact one.
inline void set_node_box(BvhNode &n, const double *l, const double *h) {
    for (int k = 0; k < 3; ++k) {
        const double c = 0.5 * l[k] + 0.5 * h[k];
        n.center[k] = c;
        n.half[k] = std::nextafter(std::max(h[k] - c, c - l[k]), INFINITY);
    }
}

struct Bvh {
    std::vector<BvhNode> nodes;     // nodes[0] is the root; empty: no tree
    std::vector<double> lanes;      // kLaneBlock per block of two siblings
    std::vector<uint32_t> tris;     // 3 vertex indices per triangle, leaf order
    std::vector<uint32_t> tri_ids;  // the mesh's index of each of those triangles
    std::vector<uint32_t> parent;   // per node (the root's: 0)
    uint32_t depth = 0;             // longest root-to-leaf path (root alone: 1)
    bool empty() const { return nodes.empty(); }
};

// Builds the tree of a mesh (binned surface area heuristic, object-median
// splits past a depth guard, so the depth stays below 80), on up to
// `threads` threads (parallel_for); the tree does not depend on them.
void build_bvh(const double *vertices, const uint32_t *triangles, uint32_t triangle_count, Bvh *out,
               int threads = 1);

// A bound eps >= ||U U^T - I||_inf for the 3x3 matrix U of rows u (row-major),
// infinity when not finite: fl(u_i . u_j) is within g_3 sum_k |u_ik u_jk| of
// exact and subtracting 1 from a value near 1 is exact, so |E_ij| <=
// |fl(u_i . u_j) - d_ij| + 1e-15 sum_k |u_ik u_jk| (rows near unit length);
// the factor 1 + 1e-12 covers the roundings of the sums.
inline double orthonormal_defect(const double *u) {
    double worst = 0;
    for (int i = 0; i < 3; ++i) {
        double row = 0;
        for (int j = 0; j < 3; ++j) {
            const double *x = u + 3 * i, *y = u + 3 * j;
            const double dot = (x[0] * y[0] + x[1] * y[1]) + x[2] * y[2];
            const double mag = (std::fabs(x[0] * y[0]) + std::fabs(x[1] * y[1])) + std::fabs(x[2] * y[2]);
            row += std::fabs(dot - (i == j ? 1.0 : 0.0)) + 1e-15 * mag;
        }
        worst = std::max(worst, row);
    }
    return std::isfinite(worst) ? worst * (1 + 1e-12) : INFINITY;
}

// Writes node k's fields (n, its fitted box o, the first and count of the
// triangles under it) into its lane of `block` (both lanes for the root, k =
// 0).
void node_lanes(const BvhNode &n, const NodeObb &o, uint32_t first, uint32_t count, uint32_t k, double *block);
// Whether span x lies within span y (x's node is in the subtree of y's).
inline bool span_within(uint64_t x, uint64_t y) { return uint32_t(x) >= uint32_t(y) && x >> 32 <= y >> 32; }

// Fits an oriented box to each of the tree's nodes (principal axes of their
// vertices) and fills bvh.lanes, on up to `threads` threads.
void fit_node_obbs(const double *vertices, Bvh &bvh, int threads = 1);

struct Mesh;

constexpr size_t kNodeData = 8;  // doubles cached per node (6 used)
// A posed mesh as the narrow phase sees it during one pair test: world
// vertices computed on first use, conservative world boxes of tree nodes
// computed on first use. The caches belong
// to the caller's scratch and are valid for one epoch (one pair test).
struct BodyView {
    const Mesh *mesh = nullptr;
    const double *local = nullptr;   // mesh-frame vertices, 3 per vertex
    const BvhNode *nodes = nullptr;  // null: treated as one leaf of every triangle
    const uint32_t *tris = nullptr;  // leaf-order triangles (mesh order without a tree)
    const uint32_t *tri_ids = nullptr;  // mesh index of leaf-order triangle (null: identity)
    // The tree's root, or without a tree the mesh's point node (Mesh), and
    // the matching lanes (Bvh::lanes or Mesh::point_lanes).
    const BvhNode *root = nullptr;
    const double *lanes = nullptr;
    Rotation r;
    const double *position = nullptr;
    double scale = 1;
    // A bound on ||R^T R - I||_inf for r (rotation_defect), or infinity:
    // then computed where needed (orthonormal_defect).
    double defect = INFINITY;
    double abs_r[9];
    double abs_position[3];
    // Caches, sized by the caller: 3 doubles and a stamp per vertex,
    // kNodeData doubles and a stamp per node.
    double *world = nullptr;
    uint32_t *vertex_stamp = nullptr;
    double *boxes = nullptr;
    uint32_t *box_stamp = nullptr;
    uint32_t epoch = 0;
    double root_box[6];  // without a tree: the exact box of all world vertices
    // Without a tree, what box() gives: the exact box of the triangles that
    // may meet the other body (root_box until collide_tree narrows it).
    double near_box[6];
    // World vertex v, computed with transform_point on first use.
    const double *vertex(uint32_t v) {
        double *w = world + 3 * size_t(v);
        if (vertex_stamp[v] != epoch) {
            transform_point(r, position, scale, local + 3 * size_t(v), w);
            vertex_stamp[v] = epoch;
        }
        return w;
    }
    // Cached world box of node n (min xyz, max xyz): it holds every rounded
    // world vertex of the triangles under it.
    const double *box(uint32_t n) {
        if (!nodes) return near_box;
        double *b = boxes + kNodeData * size_t(n);
        if (box_stamp[n] != epoch) {
            node_box(nodes[n], b);
            box_stamp[n] = epoch;
        }
        return b;
    }
    bool leaf(uint32_t n) const { return !nodes || nodes[n].count != 0; }
    uint32_t mesh_triangle(uint32_t t) const { return tri_ids ? tri_ids[t] : t; }

    // Sets r, abs_r, abs_position from the pose.
    void set_pose(const double *pos, const Rotation &rotation, double s) {
        position = pos;
        scale = s;
        r = rotation;
        for (int k = 0; k < 9; ++k) abs_r[k] = std::fabs(r.m[k]);
        for (int k = 0; k < 3; ++k) abs_position[k] = std::fabs(pos[k]);
    }

    // World box of a node: the image of its mesh-frame box, inflated by a
    // rounding margin. out: box (min xyz, max xyz).
    //
    // Why the box holds every rounded world vertex w~ = fl(T(m)) of a point
    // m of the node's box [c - h, c + h] (T(m) = pos + R (s m), R the
    // rounded matrix hgcd uses, computed exactly), with u = 2^-53, g_k =
    // k u/(1-k u):
    //  - transform_point makes 5 roundings on the way to component a (s*m_j,
    //    the three products, two sums, the final add of pos_a), so
    //    |w~_a - T(m)_a| <= g_5 M_a with M_a = |pos_a| + sum_j |R_aj| s |m_j|
    //    <= |pos_a| + sum_j |R_aj| s (|c_j| + h_j), the `reach` below;
    //  - exactly, |T(m)_a - T(c)_a| <= sum_j |R_aj| s h_j = E_a;
    //  - the computed centre wc = fl(T(c)) is within g_5 M_a of T(c) (same
    //    formula), the computed extent within g_5 E_a <= g_5 M_a of E_a, and
    //    the computed reach within g_5 of M_a relatively;
    //  - the last add/subtract rounds by at most u (|wc_a| + d) <= 3u M_a.
    // Total under 2e-15 M_a, far below the margin 1e-14 * reach (the factor
    // five covers the rounding of the margin itself). Underflow adds at most a
    // few 2^-1074 per operation: the 1e-300 term. No overflow: coordinates
    // are below 1e15 and |R_aj| <= 1 + 1e-6.
    void node_box(const BvhNode &node, double *out) const {
        double wc[3];
        transform_point(r, position, scale, node.center, wc);
        const double sh0 = scale * node.half[0], sh1 = scale * node.half[1],
                     sh2 = scale * node.half[2];
        const double sm0 = scale * (std::fabs(node.center[0]) + node.half[0]);
        const double sm1 = scale * (std::fabs(node.center[1]) + node.half[1]);
        const double sm2 = scale * (std::fabs(node.center[2]) + node.half[2]);
        for (int a = 0; a < 3; ++a) {
            const double *ar = &abs_r[3 * a];
            const double extent = ar[0] * sh0 + ar[1] * sh1 + ar[2] * sh2;
            const double reach = abs_position[a] + (ar[0] * sm0 + ar[1] * sm1 + ar[2] * sm2);
            const double d = extent + (1e-14 * reach + 1e-300);
            out[a] = wc[a] - d;
            out[3 + a] = wc[a] + d;
        }
    }
};

// Does the closed segment [p, q] certainly miss the box b (min xyz, max
// xyz)? smin, smax: the segment's box; d = q - p as rounded. False when
// unsure (conservative: never true for a box the segment meets).
bool segment_misses_box(const double *p, const double *q, const double *smin, const double *smax,
                        const double *d, const double *b);

// Exact parity test of point p against the closed mesh of `outer` (which has
// a tree), with the same answer as point_in_closed_mesh on outer's world
// vertices: rays from p leave the root box, nodes the ray segment provably
// misses are skipped, and the triangles left get the exact crossing tests; a
// ray that meets an edge, a vertex or lies in a face plane is discarded and
// the next direction is tried. Precondition: p is not on outer's surface.
bool point_in_closed_mesh_bvh(const double *p, BodyView &outer, std::vector<uint32_t> &stack);

}  // namespace hgcd
