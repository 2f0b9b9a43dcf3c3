// Narrow phase: the exact collision test of two bodies.
#pragma once
#include <cstddef>
#include <cstdint>
#include <memory>
#include <vector>

#include "exact/geometry.hpp"
#include "narrow/bvh.hpp"
#include "world/mesh.hpp"

namespace hgcd {

struct BodyPose {
    const Mesh *mesh;
    const double *position;     // 3
    const double *orientation;  // 4, x y z w
    double scale;
};

// Near: the margin path (collide_within) found the surfaces within its
// distance (touching or not).
enum class Contact { None, Surface, Containment, Near };

// A body's pose as the world stores it, in one cache line: what the narrow
// phase reads per body (collide_tetra_batch loads it in 32-byte halves).
struct alignas(64) Placement {
    double position[3];
    double orientation[4];  // x y z w
    double scale;
};
static_assert(sizeof(Placement) == 64, "Placement layout");

// The pose of a body of mesh m stored as p (p must outlive it).
inline BodyPose pose_of(const Mesh *m, const Placement &p) {
    return BodyPose{m, p.position, p.orientation, p.scale};
}

// A pair of bodies whose meshes are both tetrahedra (Mesh::tetra), with the
// meshes' records (world/mesh_pool.hpp: a tetrahedron's is its tetra_local,
// 32-byte aligned), which the batched kernels read in place of the Mesh.
struct TetraPair {
    const Mesh *mesh_a, *mesh_b;
    const Placement *a, *b;
    const double *shape_a, *shape_b;
};

// A pair of bodies whose meshes both have Mesh::sat (small convex meshes),
// with those (read by the world from its dense array of them, not through
// the mesh records: with a mesh per body, each record is a cache miss).
struct ConvexPair {
    const Mesh *mesh_a, *mesh_b;
    const Placement *a, *b;
    const SatData *sat_a, *sat_b;
};

// What collide() found, for callers that ask (the contacts of hgcd.h). A path
// that does not record it leaves recorded false.
struct Witness {
    uint32_t tri_a = UINT32_MAX, tri_b = UINT32_MAX;  // Surface: triangles of a and b that meet
    bool a_holds_b = false;  // Containment: a's closed mesh holds a component of b (else b, a's)
    bool recorded = false;
};

// The first-tried witness of a pair with a tree (a mesh above
// kBvhMinTriangles): in, a pair of tree nodes (of a's tree and of b's; 0 for
// a mesh without one) near where the surfaces met at this pair's last
// detect, whose subtrees are searched first, then those of their ancestors
// a few levels up at a time (out of range: none); out, found tells whether
// the surfaces met, then node_a, node_b are the ancestors kHintLevels above
// the meeting leaves (tree_path.cpp). Only a hint: any value
// leaves the verdict exact (the same exact triangle tests decide).
// A pair found apart by its hulls (tree_path.cpp) has an axis instead: in,
// when axis_given, a world direction along which a lay beyond b at the last
// detect, GJK's first; out, when axis_found, the certified one. With the
// axis, the hull vertices of a and b lowest and highest along it (in, where
// the supports climb from; UINT32_MAX: none).
struct NodeHint {
    uint32_t node_a = UINT32_MAX, node_b = UINT32_MAX;
    bool found = false;
    bool axis_given = false, axis_found = false;
    double axis[3] = {0, 0, 0};
    uint32_t support_a = UINT32_MAX, support_b = UINT32_MAX;
};

// Triangles of one body that reach the other's box, with their exact boxes
// (6 doubles each): the candidates of the triangle-pair loops.
struct NearTriangles {
    std::vector<uint32_t> tri;
    std::vector<double> box;  // 6 a triangle
    // Room for n triangles, written by index (the buffers only grow: no
    // per-element insert in the hot loop).
    void room(size_t n) {
        if (tri.size() < n) {
            tri.resize(n);
            box.resize(6 * n);
        }
    }
};

// Per-thread buffers, reused across pairs so the hot loop does not allocate.
struct NarrowScratch {
    std::vector<double> world_a, world_b;
    NearTriangles near_b;  // triangles of b that reach a's box
    // The tree path's leaves (leaves_meet): a's leaf's triangles, prepared,
    // and those of b's that reach them, with their leaf-order indices.
    std::vector<PreparedTriangle> leaf_a, leaf_near;
    std::vector<uint32_t> leaf_near_tri;
    // Tree path (a mesh above kBvhMinTriangles): per side, world vertices and
    // node boxes computed on first use, valid while their stamp is `epoch`
    // (one epoch per pair test). Allocating these afresh costs about half of
    // a detect of two 10000-triangle meshes, more when the allocator hands
    // back fresh pages: a caller that detects often with few pairs should
    // keep one scratch per thread alive between detects.
    struct Side {
        // Left uninitialised (only the stamps say what is valid): a scratch
        // lives for one detect, and zeroing 300 kB per detect for a pair of
        // 10000-triangle meshes would cost more than the pair test itself.
        std::unique_ptr<double[]> world, boxes;
        std::vector<uint32_t> vertex_stamp, box_stamp;
        // Images of the nodes in the other side's mesh frame (rel_frame.hpp),
        // kImageBlock doubles per block of two siblings (side 1 only), stored
        // in the order a pair first asks for them (a pair's few dozen blocks
        // stay in cache from pair to pair, where indexing by block spread
        // them over the whole array); image_slot: the epoch << 32 | the slot.
        std::unique_ptr<double[]> images;
        std::vector<uint64_t> image_slot;
    } side[2];
    uint32_t epoch = 0;
    std::vector<uint64_t> pair_stack;   // (node of a) << 32 | node of b
    std::vector<uint32_t> node_stack;   // ray traversal
    uint64_t triangle_tests = 0;
    uint64_t exact_tests = 0;
    uint64_t margin_fallbacks = 0;  // tetrahedron pairs the margin's certificates left to the direct path
};

// Exact: true when the closed solids of a and b share a point (surfaces meet,
// or one closed mesh holds a component of the other). Pairs of tetrahedra
// (Mesh::tetra) without a witness request take the tetra path (face-plane
// signs of both point sets, tetra.cpp); pairs of small convex meshes
// (Mesh::sat) the convex path (convex.hpp); other pairs of small meshes (no
// tree) the direct path: all world vertices, exact boxes, triangle pairs.
// The direct path counts exact_tests as pairs whose exact boxes overlap, the
// tetra path as those that also pass its separating axis along the line of
// centres (tested first, before any world vertex), the convex path as those
// that pass that axis. If either mesh
// has a tree, a simultaneous traversal of the two trees (a mesh without one
// is a single leaf) reaches the same exact triangle test; exact_tests then
// counts pairs whose conservative root boxes overlap.
// hint: the first-tried witness (NodeHint), read and written by the tree
// path only (pairs where a mesh has a tree and no witness is asked for).
Contact collide(const BodyPose &a, const BodyPose &b, NarrowScratch &scratch,
                Witness *witness = nullptr, NodeHint *hint = nullptr);

// The contact margin of a pair (hgcd_world_desc.contact_margin): the
// world's plus the sum of the two bodies', each addition rounded.
inline double pair_margin(double world, double a, double b) { return world + (a + b); }

// Exact, for a margin d > 0: true (Surface, Containment or Near) when the
// closed solids of a and b are within Euclidean distance d: collide() first
// (solids that share a point, by its fast paths), then, for pairs apart, a
// triangle of each within d (tri_tri_within): the direct path with boxes
// grown by d after a face-plane test of convex meshes with a gap of d, or
// the trees' traversal with node boxes grown by d (without the oriented
// node test). A witness, when asked for, is collide()'s for touching pairs,
// else (Near) the first triangle pair within d found.
Contact collide_within(const BodyPose &a, const BodyPose &b, double d, NarrowScratch &scratch,
                       Witness *witness = nullptr);

// collide() of every pair of tetrahedra pairs[0, n) into out[0, n), the
// same verdicts and counts in scratch. With AVX2 (use_avx2) many pairs at a
// time, one per lane: the separating axis along the line of centres four
// pairs at a time, then, for those it leaves, eight at a time, world
// vertices, boxes, and the signs of both bodies' vertices against the
// other's face planes (certified in float); a lane those leave open goes on
// with the one-pair test's later steps. Elsewhere one pair at a time.
void collide_tetra_batch(const TetraPair *pairs, size_t n, Contact *out, NarrowScratch &scratch);

// collide() of every pair of small convex meshes pairs[0, n) into out[0, n),
// the same verdicts and counts in scratch: the convex path's separating axis
// along the line of centres four pairs at a time (one per lane, the one-pair
// test's operations), then the one-pair test for the pairs it leaves
// (convex_batch.cpp).
void collide_convex_batch(const ConvexPair *pairs, size_t n, Contact *out, NarrowScratch &scratch);

// The tree path (tree_path.cpp), for pairs where at least one mesh has a
// BVH. counted: exact_tests counts the pair once its root boxes overlap
// (false: the caller has counted it). With kMargin: surfaces within d are
// Near, and containment is left to the caller (collide_within asks collide()
// first). hint: where the surfaces met last time, searched first and updated
// (NodeHint; not with kMargin).
template <bool kMargin = false>
Contact collide_tree(const BodyPose &a, const BodyPose &b, NarrowScratch &scratch, Witness *witness,
                     bool counted = true, double d = 0, NodeHint *hint = nullptr);

// A view of one posed mesh with a tree (Mesh::bvh) for the scene queries:
// its world vertices and node boxes computed on first use into side 0 of
// the scratch, under a new epoch (so valid until the scratch's next use).
void prepare_query_view(const BodyPose &pose, NarrowScratch &scratch, BodyView &v);

// World-space vertices of a body into out (3 per vertex) and their box.
void world_vertices(const BodyPose &body, std::vector<double> &out, double *box);

// The direct path's exact steps on the world vertices (wa, wb) and exact
// boxes of two meshes, shared with exact_contact (contact.cpp).
// find_meeting_triangles: a triangle of a and one of b that share a point,
// into meet[0], meet[1] (mesh indices), or false; near_b is scratch, and
// each exact triangle test counts in triangle_tests.
bool find_meeting_triangles(const Mesh &ma, const double *wa, const double *box_a, const Mesh &mb,
                            const double *wb, const double *box_b, NearTriangles &near_b,
                            uint64_t &triangle_tests, uint32_t *meet);
// Is some component of `inner` (world vertices wi) inside the closed mesh
// `outer` (world vertices wo, exact box outer_box)? Asked only once the
// surfaces are disjoint, so no tested vertex lies on outer's surface.
bool holds_component(const Mesh &outer, const double *wo, const double *outer_box, const Mesh &inner,
                     const double *wi);

}  // namespace hgcd
