// A shared shape: local vertices and triangles, and what hgcd works out about
// it once at creation (closedness, convexity, components, bounding sphere).
#pragma once
#include <atomic>
#include <cstdint>
#include <functional>
#include <utility>
#include <string>
#include <vector>

#include "narrow/bvh.hpp"
#include "narrow/hull.hpp"
#include "world/limits.hpp"

namespace hgcd {

// The convex path's data about a small convex mesh (convex, at most
// Mesh::kSatVertices vertices, every vertex used by a triangle; tetrahedra
// too: their pairs with other convex meshes take the convex path). One heap
// block: this header (a cache line: the counts and scalars every pair
// reads), then the runs below in the order the kernel reads them (the
// vertices, the planes, the axes and face ranges, then the integer lists),
// so that a pair of meshes of their own reads two compact blocks rather
// than a dozen scattered arrays each. Made by build_mesh, shared by meshes
// of the same arrays (SatRef counts them).
struct SatData {
    static constexpr uint32_t kLanes = 4;
    // Meshes of more triangles keep the triangles at each vertex
    // (vertex_tri_start, vertex_tris: convex.cpp tries those alone); smaller
    // ones have all of theirs tried, and keep none.
    static constexpr uint32_t kAllTriangles = 16;
    double reach = 0;  // max over the vertices of |x| + |y| + |z| (mesh frame)
    double theta = 0;  // bounds |n - N| for the exact unit normal N of each plane
    double inner = 0;  // the smallest plane offset k: the origin's distance to the nearest plane, within theta
    // Vertices (at most kSatVertices); the runs of soa() and half_soa()
    // (multiples of kLanes; half_padded 0: not symmetric).
    uint16_t vertex_count = 0, padded = 0, half_padded = 0;
    // Separating axes (axes()): the `faces` face normals, then the `edges`
    // edge directions.
    uint16_t faces = 0, edges = 0;
    // Planes of the deep-inside test, when `inside_test` holds.
    uint16_t plane_count = 0, planes_padded = 0;
    bool inside_test = false;
    uint32_t tri_at = 0;  // byte offset of vertex_tri_start() from runs() (0: none kept)
    uint32_t hot_bytes = 0;  // this header and the runs up to vertex_edges()'s end: what the kernel reads
    mutable std::atomic<uint32_t> refs{1};

    // Separating axes: unit directions in the mesh frame, 3 doubles each, no
    // two parallel, the face normals first, then the edge directions. Any
    // direction is a valid axis to try: only speed depends on these.
    const double *axes() const { return planes() + 4 * size_t(planes_padded); }
    // Per face axis n, the smallest and largest fl(v . n) over the vertices
    // (x y z summed in that order).
    const double *face_range() const { return axes() + 3 * (size_t(faces) + edges); }
    // The vertices as the batched kernel reads them (narrow/convex_kernel.cpp):
    // x of every vertex, then y, then z, each run padded to `padded` with
    // copies of vertex 0, which change no support.
    const double *soa() const { return runs(); }
    // When the vertices are symmetric about the origin (the negation of each
    // is one too, exactly: boxes and icospheres about their centre) and half
    // of them fill fewer runs: one of each pair v, -v as runs like soa's,
    // `half_padded` long, padded with copies of its first, and the indices
    // of each and of its negation (half_arg()[2 i], [2 i + 1]). Rounding
    // commutes with negation, so fl(s (-v)) = -fl(s v) and the sums of
    // products fl(l . d) of -v are those of v negated: over every vertex
    // they range over [-h, h], h their largest magnitude over these.
    const double *half_soa() const { return runs() + 3 * size_t(padded); }
    const uint8_t *half_arg() const { return reinterpret_cast<const uint8_t *>(face_range() + 2 * size_t(faces)); }
    // Outward face planes for the test of a point deep inside the solid,
    // when `inside_test` holds (see set_planes in mesh.cpp): unit normal n
    // and offset k = n . (a vertex of the face) per triangle, exact
    // duplicates once, as runs nx, ny, nz, k padded like the vertices (copies
    // of plane 0).
    const double *planes() const { return half_soa() + 3 * size_t(half_padded); }
    // For the search of an edge that crosses a triangle: the edges (other
    // end vertices) and, past kAllTriangles triangles, the triangles at each
    // vertex, as offsets (vertex_count + 1) into lists.
    const uint16_t *vertex_edge_start() const {
        return reinterpret_cast<const uint16_t *>(half_arg() + 2 * size_t(half_padded));
    }
    const uint8_t *vertex_edges() const {
        return reinterpret_cast<const uint8_t *>(vertex_edge_start() + vertex_count + 1);
    }
    const uint32_t *vertex_tri_start() const { return reinterpret_cast<const uint32_t *>(bytes() + tri_at); }
    const uint32_t *vertex_tris() const { return vertex_tri_start() + vertex_count + 1; }

private:
    friend struct SatBuilder;
    const char *bytes() const { return reinterpret_cast<const char *>(this + 1); }
    const double *runs() const { return reinterpret_cast<const double *>(this + 1); }
};
static_assert(sizeof(SatData) <= 64, "SatData's header fits a cache line");

// A counted reference to a SatData block (as a shared_ptr, in the block's
// own header: one allocation a mesh).
class SatRef {
public:
    SatRef() = default;
    SatRef(const SatRef &o) noexcept : p_(o.p_) {
        if (p_) p_->refs.fetch_add(1, std::memory_order_relaxed);
    }
    SatRef(SatRef &&o) noexcept : p_(o.p_) { o.p_ = nullptr; }
    SatRef &operator=(SatRef o) noexcept {
        std::swap(p_, o.p_);
        return *this;
    }
    ~SatRef();
    const SatData *get() const { return p_; }
    const SatData &operator*() const { return *p_; }
    const SatData *operator->() const { return p_; }
    explicit operator bool() const { return p_ != nullptr; }

private:
    friend struct SatBuilder;
    explicit SatRef(SatData *p) : p_(p) {}
    SatData *p_ = nullptr;
};

struct Mesh {
    std::vector<double> vertices;     // xyz per vertex, mesh frame
    std::vector<uint32_t> triangles;  // 3 indices per triangle
    uint32_t vertex_count = 0;
    uint32_t triangle_count = 0;
    bool closed = false;  // every edge shared by an even number of triangles
    bool convex = false;  // closed and all vertices behind/on every face plane
    int inward_sign = 0;  // orient3d sign of interior points w.r.t. faces (convex only)
    uint32_t degenerate_count = 0;
    // One vertex per connected component that some triangle uses: if two
    // surfaces do not cross, each component lies wholly inside or outside.
    std::vector<uint32_t> component_vertices;
    double center[3] = {0, 0, 0};  // centre of the vertex box
    double radius = 0;             // reaches every vertex from center
    double reach = 0;              // largest vertex_norm of a used vertex (limits.hpp)
    // 4 vertices whose 4 triangles are the 4 distinct vertex triples (any
    // order and orientation): the surface is the boundary of the 4 points'
    // hull (or the hull itself when they are coplanar) in any pose, and the
    // narrow phase takes a dedicated exact path (its tetra pairs).
    bool tetra = false;
    double tetra_local[12] = {};  // x0..x3, y0..y3, z0..z3 (mesh frame)
    double tetra_reach = 0;       // max over the 4 vertices of |x| + |y| + |z|
    // Meshes of at most kExactBoxTriangles triangles: a body's box is the
    // box of the distinct vertices the triangles use (each transformed once
    // per new orientation), read from the mesh's record in the world's pool
    // (world/mesh_pool.hpp, world/pose_box.hpp), not from here; larger meshes
    // take their bounding sphere's.
    static constexpr uint32_t kExactBoxTriangles = 128;
    // For larger meshes: the boxes (centre xyz, half widths xyz, mesh frame)
    // of the tree's nodes kBoxCutDepth below the root (and of shallower
    // leaves), which hold every triangle: a body's box is the union of their
    // rotated boxes where tighter than the bounding sphere's (an elongated
    // mesh's by far), at ~2^kBoxCutDepth small transforms per new orientation.
    // Stored field by field (kBoxCutFields rows of box_cut_nodes: centres
    // x y z, half widths x y z), the node count a multiple of 4 (the last
    // node repeated), for a set_pose four nodes at a time; box_cut_reach[k]:
    // the largest |centre_k| + half_k.
    static constexpr uint32_t kBoxCutDepth = 3;
    static constexpr size_t kBoxCutFields = 6;
    std::vector<double> box_cut;
    size_t box_cut_nodes = 0;
    double box_cut_reach[3] = {0, 0, 0};
    // What the convex path of the narrow phase (narrow/convex.cpp) needs
    // about a small convex mesh (SatData), behind one pointer so that other
    // meshes carry 8 bytes for it; null for them. (Tetrahedron pairs take
    // their own path; a tetrahedron against another convex mesh this one.)
    static constexpr uint32_t kSatVertices = 64;
    SatRef sat;
    // Triangle tree in the mesh frame; empty for meshes of at most
    // kBvhMinTriangles triangles (the narrow phase tests those directly).
    Bvh bvh;
    // For meshes without a tree: the box of all vertices (rounded outward,
    // as a tree node's) as one node, first 0 and count triangle_count, and
    // its lanes block (Bvh::lanes, identity axes): against a mesh with a
    // tree, the pair is traversed in that mesh's frame with this node as
    // the other side (narrow/tree_path.cpp).
    BvhNode point_node{};
    std::vector<double> point_lanes;
    // The root node's (the tree's, or point_node): (1 + 4.3e-6) |half|_2
    // rounded up, and its reach max_k |centre_k| + half_k, for the balls'
    // test (narrow/rel_frame.hpp, root_ball_apart).
    double root_ball = 0, root_reach = 0;
    // For meshes with a tree and at most kHullPoints vertices: the convex
    // hull of the used vertices, if it has at most kHullVertices (else none,
    // as for a flat mesh). Two bodies' hulls apart decide their pair before
    // the trees (tree_path.cpp): a few support queries where the descent
    // would reach small nodes to prove it. (The hull costs up to about a
    // microsecond a vertex to build: 0.8 s for a million on a cube's faces.)
    static constexpr uint32_t kHullVertices = 1024;
    static constexpr uint32_t kHullPoints = 1u << 16;
    Hull hull;
};

// The mesh's root node: its tree's, or point_node without a tree.
inline const BvhNode &root_node(const Mesh &m) { return m.bvh.empty() ? m.point_node : m.bvh.nodes[0]; }

// Checks and analyses the arrays, filling *out. Returns false with a message
// naming the problem when the data is refused. `same`, when given, is asked
// (with the checked mesh) before Mesh::sat is built, for the SatData of a
// mesh of the same arrays, taken instead (it is made from them alone).
// `tetra_sat`: whether a tetrahedron gets Mesh::sat as well (only its pairs
// with other small convex meshes read it: a world of tetrahedra alone does
// not pay its kilobyte a mesh). `threads`: the tree is built on up to that
// many (build_bvh).
using SameSat = std::function<SatRef(const Mesh &)>;
bool build_mesh(const double *vertices, uint32_t vertex_count, const uint32_t *triangles,
                uint32_t triangle_count, Mesh *out, std::string *error, const SameSat &same = nullptr,
                bool tetra_sat = true, int threads = 1);
// Gives a tetrahedron built without it its Mesh::sat (from `same` when that
// lends one). May throw std::bad_alloc, leaving m as it was.
void add_tetra_sat(Mesh &m, const SameSat &same);

}  // namespace hgcd
