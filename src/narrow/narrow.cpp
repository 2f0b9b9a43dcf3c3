#include "narrow/narrow.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#if defined(__SSE2__)
#include <immintrin.h>
#endif

#include "narrow/bvh.hpp"
#include "common/cpu.hpp"
#include "exact/geometry.hpp"
#include "common/ieee.hpp"
#include "common/transform.hpp"

namespace hgcd {

void world_vertices(const BodyPose &body, std::vector<double> &out, double *box) {
    const Mesh &m = *body.mesh;
    out.resize(3 * size_t(m.vertex_count));
    const Rotation r = rotation_of(body.orientation);
    box[0] = box[1] = box[2] = INFINITY;
    box[3] = box[4] = box[5] = -INFINITY;
    for (uint32_t v = 0; v < m.vertex_count; ++v) {
        double *w = &out[3 * size_t(v)];
        transform_point(r, body.position, body.scale, &m.vertices[3 * size_t(v)], w);
        for (int k = 0; k < 3; ++k) {
            box[k] = std::min(box[k], w[k]);
            box[3 + k] = std::max(box[3 + k], w[k]);
        }
    }
}

namespace {

// Certifying factors of the filters, one set for every kernel that uses them
// (each argued where the one-pair code first uses it): the floor added for
// underflowed products; on the tetra path the face planes' sign bound
// (plane_pair), the separating axis along the line of centres
// (tet_axis_margin) and the axis across two edges (EdgeAxis).
constexpr double kUnderflowFloor = 0x1p-960;
constexpr double kPlaneBound = 0x1p-50, kCentresMargin = 0x1p-48, kEdgeMargin = 0x1p-46;

// The face planes' certifying bound for points in a box of extent (ex, ey,
// ez) that holds both bodies (see the tetra path's notes below), one for
// every face.
inline double tet_plane_bound(double ex, double ey, double ez) {
    return kPlaneBound * (8.0 * ((ex * ey) * ez)) + kUnderflowFloor;
}

// The size of a box (lo, hi: 3 values each) that picks which body's faces
// the tetra test tries first: the same sums in the one-pair test and the
// batch, so both try them in the same order. T is double or a vector of
// doubles (an out-parameter: a vector return would change the ABI where no
// AVX target is on).
template <class T>
inline void tet_box_size(T &size, const T *lo, const T *hi) {
    size = ((hi[0] - lo[0]) + (hi[1] - lo[1])) + (hi[2] - lo[2]);
}

inline bool boxes_disjoint(const double *a, const double *b) {
    return a[3] < b[0] || b[3] < a[0] || a[4] < b[1] || b[4] < a[1] || a[5] < b[2] ||
           b[5] < a[2];
}

inline bool point_in_box(const double *p, const double *box) {
    return p[0] >= box[0] && p[0] <= box[3] && p[1] >= box[1] && p[1] <= box[4] &&
           p[2] >= box[2] && p[2] <= box[5];
}

inline void triangle_box(const double *v, const uint32_t *t, double *box) {
    const double *p = &v[3 * size_t(t[0])], *q = &v[3 * size_t(t[1])], *r = &v[3 * size_t(t[2])];
    for (int k = 0; k < 3; ++k) {
        box[k] = std::min(std::min(p[k], q[k]), r[k]);
        box[3 + k] = std::max(std::max(p[k], q[k]), r[k]);
    }
}

// Is there a face of mesh `ca` (world vertices wa) whose plane has every
// vertex of the other body certainly strictly outside, and every vertex of
// `ca` inside or on it? Then each body lies in the convex hull of its
// vertices, on its own side of the plane, and they are disjoint. Both sides
// are checked in world space: rounding the world vertices can make a mesh
// that is convex in its own frame slightly non-convex (a cube's coplanar
// fourth vertex poking out by an ulp), so the mesh's convex flag only says
// which meshes are worth trying. A sign is trusted when the determinant
// exceeds the rounding error bound of its evaluation (Shewchuk's orient3d
// bound (7 + 56 eps) eps * permanent, rounded up to 1e-15 * permanent, plus
// 2^-960 for underflowed products, as in geometry.cpp); an uncertain sign on
// the other body's side makes the face prove nothing, an uncertain sign on
// the own side is settled by the exact orient3d. So this test never changes
// an answer.
bool separated_by_face(const Mesh &ca, const double *wa, const Mesh &mb, const double *wb) {
    constexpr double kBound = 1e-15;
    const double inward = ca.inward_sign;
    for (uint32_t t = 0; t < ca.triangle_count; ++t) {
        const uint32_t *f = &ca.triangles[3 * size_t(t)];
        const double *a = &wa[3 * size_t(f[0])], *b = &wa[3 * size_t(f[1])], *c = &wa[3 * size_t(f[2])];
        const double ux = b[0] - a[0], uy = b[1] - a[1], uz = b[2] - a[2];
        const double vx = c[0] - a[0], vy = c[1] - a[1], vz = c[2] - a[2];
        // orient3d(a, b, c, d) = -(d - a) . (u x v)
        const double nx = uy * vz - uz * vy, ny = uz * vx - ux * vz, nz = ux * vy - uy * vx;
        const double px = std::fabs(uy * vz) + std::fabs(uz * vy);
        const double py = std::fabs(uz * vx) + std::fabs(ux * vz);
        const double pz = std::fabs(ux * vy) + std::fabs(uy * vx);
        // inward * orient3d(a, b, c, d): > bound certainly inside the plane's
        // inner side, < -bound certainly outside, else uncertain.
        auto side = [&](const double *d, double &bound) {
            const double wx = d[0] - a[0], wy = d[1] - a[1], wz = d[2] - a[2];
            bound = kBound * (std::fabs(wx) * px + std::fabs(wy) * py + std::fabs(wz) * pz) + kUnderflowFloor;
            return -inward * (wx * nx + wy * ny + wz * nz);
        };
        bool separating = true;
        for (uint32_t v = 0; v < mb.vertex_count && separating; ++v) {
            double bound;
            separating = side(&wb[3 * size_t(v)], bound) < -bound;
        }
        for (uint32_t v = 0; v < ca.vertex_count && separating; ++v) {
            if (v == f[0] || v == f[1] || v == f[2]) continue;
            const double *d = &wa[3 * size_t(v)];
            double bound;
            const double s = side(d, bound);
            if (s > bound) continue;
            separating = s >= -bound && inward * orient3d(a, b, c, d) >= 0;
        }
        if (separating) return true;
    }
    return false;
}

// The face test costs faces x vertices; beyond this it is left to the
// triangle tests, which prune by boxes.
constexpr uint64_t kFaceTestBudget = 4096;

// Is some component of `inner` (world vertices wv) inside the closed mesh
// `outer` (world vertices wo)? Only asked once the surfaces are disjoint, so
// no tested vertex lies on the outer surface.
bool holds_component(const Mesh &outer, const std::vector<double> &wo, const double *outer_box,
                     const Mesh &inner, const std::vector<double> &wv) {
    for (uint32_t v : inner.component_vertices) {
        const double *p = &wv[3 * size_t(v)];
        if (!point_in_box(p, outer_box)) continue;
        // Exact ray parity, also for convex meshes: in world space, after
        // rounding, a convex mesh need not be convex, and the face-by-face
        // test would then misjudge points near a poking vertex.
        if (point_in_closed_mesh(p, wo.data(), outer.triangles.data(), outer.triangle_count,
                                 outer_box, outer_box + 3))
            return true;
    }
    return false;
}


// ---------------------------------------------------------------------------
// Tree path: at least one mesh has a BVH.
//
// World vertices are computed lazily, per pair, for the triangles the
// traversal reaches (BodyView::vertex), instead of all vertices of both
// bodies: for two blobs of 5002 vertices in shallow contact, transforming
// them all costs 17.7 us, more than the whole touching test (10 us). (The
// other choice, world vertices and node boxes cached per body per tick,
// would need storage owned by the world; a body takes part in ~2.5 pairs of
// scene `meshes`, so it would save at most the ~20% of the pair time spent in
// node boxes and transforms.) Node boxes are conservative world boxes of the
// mesh-frame node boxes (BodyView::node_box argues the margin), refined above
// the leaves by a separating-axis test on both rotations' face directions
// with the same margins (obb_separated), so a node pair is skipped only when
// no rounded world vertex under one can share a point with the other; leaves
// get exact triangle boxes from the world vertices and the exact triangle
// test, exactly as the direct path.

void prepare_side(const BodyPose &pose, NarrowScratch::Side &c, uint32_t epoch, BodyView &v) {
    const Mesh &m = *pose.mesh;
    v.mesh = &m;
    v.local = m.vertices.data();
    v.set_pose(pose.position, pose.orientation, pose.scale);
    v.epoch = epoch;
    const size_t nv = m.vertex_count;
    if (c.vertex_stamp.size() < nv) {
        c.vertex_stamp.resize(nv, 0);
        c.world.reset(new double[3 * nv]);
    }
    v.world = c.world.get();
    v.vertex_stamp = c.vertex_stamp.data();
    if (m.bvh.empty()) {
        // A small mesh: one leaf with every triangle, its exact box.
        v.nodes = nullptr;
        v.tris = m.triangles.data();
        v.tri_ids = nullptr;
        double *b = v.root_box;
        b[0] = b[1] = b[2] = INFINITY;
        b[3] = b[4] = b[5] = -INFINITY;
        for (uint32_t i = 0; i < m.vertex_count; ++i) {
            const double *w = v.vertex(i);
            for (int k = 0; k < 3; ++k) {
                b[k] = std::min(b[k], w[k]);
                b[3 + k] = std::max(b[3 + k], w[k]);
            }
        }
        return;
    }
    const size_t nn = m.bvh.nodes.size();
    if (c.box_stamp.size() < nn) {
        c.box_stamp.resize(nn, 0);
        c.boxes.reset(new double[kNodeData * nn]);
    }
    v.nodes = m.bvh.nodes.data();
    v.tris = m.bvh.tris.data();
    v.tri_ids = m.bvh.tri_ids.data();
    v.boxes = c.boxes.get();
    v.box_stamp = c.box_stamp.data();
}

inline void leaf_range(const BodyView &v, uint32_t n, uint32_t &first, uint32_t &count) {
    if (v.nodes) {
        first = v.nodes[n].first;
        count = v.nodes[n].count;
    } else {
        first = 0;
        count = v.mesh->triangle_count;
    }
}

inline void view_triangle_box(BodyView &v, uint32_t t, const double *(&p)[3], double *box) {
    const uint32_t *f = &v.tris[3 * size_t(t)];
    p[0] = v.vertex(f[0]);
    p[1] = v.vertex(f[1]);
    p[2] = v.vertex(f[2]);
    for (int k = 0; k < 3; ++k) {
        box[k] = std::min(std::min(p[0][k], p[1][k]), p[2][k]);
        box[3 + k] = std::max(std::max(p[0][k], p[1][k]), p[2][k]);
    }
}

// Exact test of the triangles of leaf i of a against those of leaf j of b.
// On a meeting pair, sets meet[0], meet[1] to their leaf-order indices.
bool leaves_meet(BodyView &a, uint32_t i, const double *node_a, BodyView &b, uint32_t j,
                 const double *node_b, NarrowScratch &s, uint32_t *meet) {
    uint32_t fa, na, fb, nb;
    leaf_range(a, i, fa, na);
    leaf_range(b, j, fb, nb);
    // Triangles of b that reach a's node box, with their exact boxes.
    s.tri_b.clear();
    s.box_b.clear();
    for (uint32_t t = fb; t < fb + nb; ++t) {
        const double *q[3];
        double tb[6];
        view_triangle_box(b, t, q, tb);
        if (boxes_disjoint(tb, node_a)) continue;
        s.tri_b.push_back(t);
        s.box_b.insert(s.box_b.end(), tb, tb + 6);
    }
    if (s.tri_b.empty()) return false;
    for (uint32_t t = fa; t < fa + na; ++t) {
        const double *p[3];
        double ta[6];
        view_triangle_box(a, t, p, ta);
        if (boxes_disjoint(ta, node_b)) continue;
        for (size_t k = 0; k < s.tri_b.size(); ++k) {
            if (boxes_disjoint(ta, &s.box_b[6 * k])) continue;
            const uint32_t *f = &b.tris[3 * size_t(s.tri_b[k])];
            ++s.triangle_tests;
            if (tri_tri_intersect(p[0], p[1], p[2], b.vertex(f[0]), b.vertex(f[1]), b.vertex(f[2]))) {
                meet[0] = t;
                meet[1] = s.tri_b[k];
                return true;
            }
        }
    }
    return false;
}

// Squared distance of box centres, times 4.
inline double dist2(const double *x, const double *y) {
    const double dx = (x[0] + x[3]) - (y[0] + y[3]), dy = (x[1] + x[4]) - (y[1] + y[4]),
                 dz = (x[2] + x[5]) - (y[2] + y[5]);
    return dx * dx + dy * dy + dz * dz;
}

inline double box_size(const double *b) { return (b[3] - b[0]) + (b[4] - b[1]) + (b[5] - b[2]); }

// The two bodies' rotation columns and their dot products, for the oriented
// box test of node pairs.
struct PairFrame {
    double col_a[3][3], col_b[3][3];      // col_a[j][k] = R_a[k][j]
    double abs_col_a[3][3], abs_col_b[3][3];
    double gram_a[3][3], gram_b[3][3];    // |col_a[j] . col_a[l]|, |col_b[i] . col_b[m]|
    double cross[3][3], cross_t[3][3];    // |col_a[j] . col_b[i]| and transposed
};

void prepare_frame(const BodyView &a, const BodyView &b, PairFrame &f) {
    for (int j = 0; j < 3; ++j)
        for (int k = 0; k < 3; ++k) {
            f.col_a[j][k] = a.r.m[3 * k + j];
            f.col_b[j][k] = b.r.m[3 * k + j];
            f.abs_col_a[j][k] = a.abs_r[3 * k + j];
            f.abs_col_b[j][k] = b.abs_r[3 * k + j];
        }
    auto dot = [](const double *x, const double *y) { return x[0] * y[0] + x[1] * y[1] + x[2] * y[2]; };
    for (int j = 0; j < 3; ++j)
        for (int l = 0; l < 3; ++l) {
            f.gram_a[j][l] = std::fabs(dot(f.col_a[j], f.col_a[l]));
            f.gram_b[j][l] = std::fabs(dot(f.col_b[j], f.col_b[l]));
            f.cross[j][l] = std::fabs(dot(f.col_a[j], f.col_b[l]));
            f.cross_t[l][j] = f.cross[j][l];
        }
}

inline double dot3(const double *x, const double *y) { return (x[0] * y[0] + x[1] * y[1]) + x[2] * y[2]; }

// Separating-axis test of two nodes' world images along the six face
// directions (the columns of both rotation matrices). The exact image of a
// node box is the parallelepiped wc +- sum_l s h_l col_l (col_l the columns
// of the rounded matrix, exactly; they need not be orthogonal, hence the
// Gram terms), and every rounded world vertex, as well as the computed wc,
// lies within the node's per-axis margin of it (node_box). On an axis a
// (any double vector) the two sets are apart when
//   |a . (wc_b - wc_a)| > r_a + r_b + sum_k |a_k| (margin_a,k + margin_b,k),
// r the exact projected radii, r_a = sum_l s h_l |a . col_l|. Every rounding
// made in evaluating that here is below 12u times
// mag = sum_k |a_k| (|D_k| + extent_a,k + extent_b,k) (each radius term
// s h_l |a . col_l| sums to at most sum_k |a_k| extent_k), so the tolerance
// margin + 1e-13 * extent cached per node, plus 1e-13 |D_k| here and 1e-300
// for underflow, makes a rejection certain.
bool obb_separated(const double *na, const double *nb, const PairFrame &f) {
    const double d[3] = {nb[6] - na[6], nb[7] - na[7], nb[8] - na[8]};
    const double tol[3] = {(na[9] + nb[9]) + 1e-13 * std::fabs(d[0]),
                           (na[10] + nb[10]) + 1e-13 * std::fabs(d[1]),
                           (na[11] + nb[11]) + 1e-13 * std::fabs(d[2])};
    const double *ha = na + 12, *hb = nb + 12;
    for (int j = 0; j < 3; ++j) {
        const double proj = std::fabs(dot3(f.col_a[j], d));
        const double lim = (dot3(f.gram_a[j], ha) + dot3(f.cross[j], hb)) + dot3(f.abs_col_a[j], tol);
        if (proj > lim + 1e-300) return true;
    }
    for (int i = 0; i < 3; ++i) {
        const double proj = std::fabs(dot3(f.col_b[i], d));
        const double lim = (dot3(f.cross_t[i], ha) + dot3(f.gram_b[i], hb)) + dot3(f.abs_col_b[i], tol);
        if (proj > lim + 1e-300) return true;
    }
    return false;
}

bool surfaces_meet(BodyView &a, BodyView &b, NarrowScratch &s, uint32_t *meet) {
    PairFrame frame;
    const bool oriented = a.nodes && b.nodes;
    if (oriented) prepare_frame(a, b, frame);
    std::vector<uint64_t> &stack = s.pair_stack;
    stack.clear();
    stack.push_back(0);
    while (!stack.empty()) {
        const uint64_t top = stack.back();
        stack.pop_back();
        const uint32_t i = uint32_t(top >> 32), j = uint32_t(top);
        const double *ba = a.box(i), *bb = b.box(j);
        if (boxes_disjoint(ba, bb)) continue;
        const bool la = a.leaf(i), lb = b.leaf(j);
        // The oriented test pays off above the leaves (a leaf pair goes to
        // triangle boxes, which are cheaper).
        if (oriented && !(la && lb) &&
            obb_separated(ba, bb, frame))
            continue;
        if (la && lb) {
            if (leaves_meet(a, i, ba, b, j, bb, s, meet)) return true;
            continue;
        }
        // Descend the larger node (or the one that is not a leaf).
        // The child whose centre is farther from the other node's is visited
        // first: where two surfaces cross, each lies near the other's box
        // boundary, not its middle (measured on the `meshes` scene: 2.6x
        // fewer node pairs before the first meeting triangles than in a
        // fixed order, 10x in the shallow contact benchmark).
        if (lb || (!la && box_size(ba) >= box_size(bb))) {
            const uint64_t c = a.nodes[i].first;
            const bool swap = dist2(a.box(c), bb) > dist2(a.box(c + 1), bb);
            stack.push_back(((c + !swap) << 32) | j);
            stack.push_back(((c + swap) << 32) | j);
        } else {
            const uint64_t c = b.nodes[j].first;
            const bool swap = dist2(b.box(c), ba) > dist2(b.box(c + 1), ba);
            stack.push_back((uint64_t(i) << 32) | (c + !swap));
            stack.push_back((uint64_t(i) << 32) | (c + swap));
        }
    }
    return false;
}

// Is some component of `inner` inside the closed mesh `outer`? Asked once the
// surfaces are disjoint, so no tested vertex lies on outer's surface.
bool view_holds_component(BodyView &outer, BodyView &inner, NarrowScratch &s) {
    const Mesh &mo = *outer.mesh;
    for (uint32_t v : inner.mesh->component_vertices) {
        const double *p = inner.vertex(v);
        const double *rb = outer.box(0);
        if (!point_in_box(p, rb)) continue;
        bool inside;
        if (outer.nodes) {
            inside = point_in_closed_mesh_bvh(p, outer, s.node_stack);
        } else {  // every world vertex of a small mesh is computed; parity, see holds_component
            inside = point_in_closed_mesh(p, outer.world, mo.triangles.data(), mo.triangle_count, rb, rb + 3);
        }
        if (inside) return true;
    }
    return false;
}

__attribute__((noinline)) Contact collide_tree(const BodyPose &a, const BodyPose &b,
                                               NarrowScratch &s, Witness *witness) {
    if (++s.epoch == 0) {  // stamps wrapped: forget every cached value
        for (auto &c : s.side) {
            std::fill(c.vertex_stamp.begin(), c.vertex_stamp.end(), 0u);
            std::fill(c.box_stamp.begin(), c.box_stamp.end(), 0u);
        }
        s.epoch = 1;
    }
    BodyView va, vb;
    prepare_side(a, s.side[0], s.epoch, va);
    prepare_side(b, s.side[1], s.epoch, vb);
    // Conservative prefilter: the solids lie inside the root boxes.
    if (boxes_disjoint(va.box(0), vb.box(0))) return Contact::None;
    ++s.exact_tests;
    uint32_t meet[2];
    if (surfaces_meet(va, vb, s, meet)) {
        if (witness)
            *witness = Witness{va.mesh_triangle(meet[0]), vb.mesh_triangle(meet[1]), false, true};
        return Contact::Surface;
    }
    if (b.mesh->closed && view_holds_component(vb, va, s)) {
        if (witness) *witness = Witness{UINT32_MAX, UINT32_MAX, false, true};
        return Contact::Containment;
    }
    if (a.mesh->closed && view_holds_component(va, vb, s)) {
        if (witness) *witness = Witness{UINT32_MAX, UINT32_MAX, true, true};
        return Contact::Containment;
    }
    return Contact::None;
}


// ---------------------------------------------------------------------------
// Tetra path: both meshes are tetrahedra (Mesh::tetra: 4 vertices, the 4
// distinct vertex triples as triangles), the `tetra` scene's only shape.
//
// For such a mesh the closed solid in any pose is the hull of its 4 rounded
// world vertices: the triangles cover the hull's boundary (or the whole hull
// when the points are coplanar), a ray from a point off the surface crosses
// that boundary an odd number of times exactly when it starts in the open
// interior, and a flat hull has no interior (each of its points is covered by
// two triangles). So the answer depends only on the two point sets, the
// triangles can be taken in a fixed order, and with exact signs
//   - a vertex of B is in A's solid off its surface iff it is strictly on the
//     inner side of all four face planes of A (barycentric signs);
//   - it is outside A's solid if it is strictly on the outer side of one face
//     plane (for a flat A: strictly off its plane).
// Face f of a tetrahedron misses vertex f; its triangle is kFace[f], and with
// these orders orient3d(face f, vertex f) has the sign of -orient3d(v0, v1,
// v2, v3) for every f (each is an odd permutation of 0 1 2 3): one inner sign
// per tetrahedron, 0 when it is flat.
//
// Every sign is exact: a face plane is evaluated at two points per vector
// with the arithmetic and error bound of geometry.cpp's plane_sides3
// (|det| > 2^-50 perm + 2^-960 certifies the sign), except that the
// permanent is replaced by a bound of it, the same for every face of both
// bodies (tet_plane_bound): each factor |fl(x - t0)| is at most the extent
// fl(hi - lo) of the box holding both bodies on its axis (x and t0 lie in
// that box and rounding is monotone), so each of the permanent's six terms is
// at most ex ey ez and their sum at most 6 ex ey ez, which 8 fl(fl(ex ey) ez)
// exceeds past its rounding. (Should fl(ex ey) underflow, this bound and the
// permanent's both round to the floor 2^-960: extents are below 2^52 by the
// coordinate limit of 1e15, so 2^-50 * 8 ex ey ez < 2^-1013 then.) The bound
// only grows: per face it was the
// permanent with the extents alone, about five times smaller on scene tetra
// but 15 operations a face (tetra 750k, 1 thread: narrow phase 54.2 -> 52.1
// ms, the same decisions). Uncertain signs stay undecided until a step needs
// them, then the exact orient3d computes them.
//
// Before any world vertex is computed, a separating axis along the line of
// centres rejects most pairs that are apart (tet_axis_separates), then the
// exact vertex boxes. Decisions, in order, first with the faces of A (the
// larger box) and the vertices of B, then the other way round: a face plane
// of A with all of B strictly on its outer side: no contact. A vertex of B
// strictly inside A and one strictly outside: B's surface (connected,
// containing the edge between them) crosses A's boundary: Surface. All of B
// strictly inside A: Containment (B's hull in A's open interior, surfaces
// apart). Either verdict makes B's faces needless. Anything else (edge crossings,
// touching, undecided filters) makes every sign exact, takes the same
// decisions, then runs the exact triangle test on the face pairs with those
// signs; if no pair meets, there is no contact (a solid holding the other's
// surface would hold all its vertices strictly inside, which the exact
// decisions catch).

// With GCC on x86-64 the two-lane pair test is also compiled for AVX
// (target_clones: the same operations VEX-encoded, without SSE2's register
// copies) and a four-lane version for AVX2 (KernelsV4), picked at run time;
// neither uses FMA, so every lane has the same bits. Clang and other targets
// (NEON) use the two-lane kernels as written.
#if HGCD_AVX2
#define HGCD_TET_CLONES __attribute__((target_clones("avx", "default")))
#define HGCD_TET_INLINE inline __attribute__((always_inline))
#else
#define HGCD_TET_CLONES
#define HGCD_TET_INLINE inline
#endif

// Two doubles per vector (SSE2 or NEON registers as they are; the lanes do
// IEEE double operations, so every value has the bits of the scalar code).
typedef double V2 __attribute__((vector_size(16)));
typedef int64_t M2 __attribute__((vector_size(16)));

inline V2 vmin(V2 a, V2 b) {
#if defined(__SSE2__)
    return _mm_min_pd(a, b);
#else
    return a < b ? a : b;
#endif
}
inline V2 vmax(V2 a, V2 b) {
#if defined(__SSE2__)
    return _mm_max_pd(a, b);
#else
    return a > b ? a : b;
#endif
}
// Bit i set when a[i] < b[i].
inline unsigned less_bits(V2 a, V2 b) {
#if defined(__SSE2__)
    return unsigned(_mm_movemask_pd(_mm_cmplt_pd(a, b)));
#else
    const M2 m = a < b;
    return unsigned((m[0] & 1) | (m[1] & 2));
#endif
}
template <int L> inline V2 lane(V2 a) { return __builtin_shufflevector(a, a, L, L); }

// Face f misses vertex f. The faces go in pairs (0, 1) and (2, 3), one per
// lane, chosen so that each face vertex vector is one shuffle of the vertex
// pairs (0, 1) and (2, 3).
constexpr int kFace[4][3] = {{1, 2, 3}, {0, 3, 2}, {0, 1, 3}, {0, 2, 1}};

struct TetWorld {
    V2 x[2], y[2], z[2];  // world vertices: lanes (0, 1) in [0], (2, 3) in [1]
    double lo[3], hi[3];
};

inline double hmin(V2 a, V2 b) {
    const V2 m = vmin(a, b);
    return std::min(m[0], m[1]);
}
inline double hmax(V2 a, V2 b) {
    const V2 m = vmax(a, b);
    return std::max(m[0], m[1]);
}

// The box of w's four vertices (after they are set).
HGCD_TET_INLINE void tet_box(TetWorld &w) {
    w.lo[0] = hmin(w.x[0], w.x[1]);
    w.lo[1] = hmin(w.y[0], w.y[1]);
    w.lo[2] = hmin(w.z[0], w.z[1]);
    w.hi[0] = hmax(w.x[0], w.x[1]);
    w.hi[1] = hmax(w.y[0], w.y[1]);
    w.hi[2] = hmax(w.z[0], w.z[1]);
}

// Both bodies' rotations at once: body a in lane 0, b in lane 1.
struct TetRotations {
    V2 m[9];
};

HGCD_TET_INLINE void tet_rotations(const BodyPose &a, const BodyPose &b, TetRotations &r) {
    V2 a01, a23, b01, b23;
    std::memcpy(&a01, a.orientation, sizeof a01);
    std::memcpy(&a23, a.orientation + 2, sizeof a23);
    std::memcpy(&b01, b.orientation, sizeof b01);
    std::memcpy(&b23, b.orientation + 2, sizeof b23);
    rotation_entries(__builtin_shufflevector(a01, b01, 0, 2), __builtin_shufflevector(a01, b01, 1, 3),
                     __builtin_shufflevector(a23, b23, 0, 2), __builtin_shufflevector(a23, b23, 1, 3), r.m);
}

// The scaled local vertices l = fl(s m), one per lane, shared by the axis
// test and the world transform.
struct TetLocal {
    V2 x[2], y[2], z[2];
};

HGCD_TET_INLINE void tet_local(const BodyPose &b, TetLocal &l) {
    const double s = b.scale, *m = b.mesh->tetra_local;
    for (int h = 0; h < 2; ++h) {
        V2 mx, my, mz;
        std::memcpy(&mx, m + 2 * h, sizeof mx);
        std::memcpy(&my, m + 4 + 2 * h, sizeof my);
        std::memcpy(&mz, m + 8 + 2 * h, sizeof mz);
        l.x[h] = s * mx;
        l.y[h] = s * my;
        l.z[h] = s * mz;
    }
}

// max_i la_i . da + max_j lb_j . db, da in lane 0 of d, db in lane 1 (each
// dot product evaluated left to right).
HGCD_TET_INLINE double tet_supports(const TetLocal &la, const TetLocal &lb, const V2 *d) {
    const V2 a0 = lane<0>(d[0]), a1 = lane<0>(d[1]), a2 = lane<0>(d[2]);
    const V2 b0 = lane<1>(d[0]), b1 = lane<1>(d[1]), b2 = lane<1>(d[2]);
    const V2 pa = vmax((la.x[0] * a0 + la.y[0] * a1) + la.z[0] * a2, (la.x[1] * a0 + la.y[1] * a1) + la.z[1] * a2);
    const V2 pb = vmax((lb.x[0] * b0 + lb.y[0] * b1) + lb.z[0] * b2, (lb.x[1] * b0 + lb.y[1] * b1) + lb.z[1] * b2);
    const V2 h = vmax(__builtin_shufflevector(pa, pb, 0, 2), __builtin_shufflevector(pa, pb, 1, 3));
    return h[0] + h[1];
}

// World vertices of the body in lane L of r (tet_rotations), l = tet_local(b).
template <int L>
HGCD_TET_INLINE void tet_world(const BodyPose &b, const TetRotations &r, const TetLocal &l, TetWorld &w) {
    const double *c = b.position;
    V2 m[9];
    for (int k = 0; k < 9; ++k) m[k] = lane<L>(r.m[k]);
    for (int h = 0; h < 2; ++h) {
        // transform_point's operations in its order, one vertex per lane.
        const V2 lx = l.x[h], ly = l.y[h], lz = l.z[h];
        w.x[h] = c[0] + ((m[0] * lx + m[1] * ly) + m[2] * lz);
        w.y[h] = c[1] + ((m[3] * lx + m[4] * ly) + m[5] * lz);
        w.z[h] = c[2] + ((m[6] * lx + m[7] * ly) + m[8] * lz);
    }
    tet_box(w);
}

struct TetPlanes {  // faces (0, 1) in [0], (2, 3) in [1]
    V2 t0x[2], t0y[2], t0z[2], nx[2], ny[2], nz[2];
    double bound;  // certifies every face's signs (tet_plane_bound)
};

inline void plane_pair(TetPlanes &p, int h, V2 t0x, V2 t0y, V2 t0z, V2 t1x, V2 t1y, V2 t1z, V2 t2x,
                       V2 t2y, V2 t2z) {
    const V2 e1x = t1x - t0x, e1y = t1y - t0y, e1z = t1z - t0z;
    const V2 e2x = t2x - t0x, e2y = t2y - t0y, e2z = t2z - t0z;
    const V2 a = e1y * e2z, b = e1z * e2y, c = e1z * e2x, d = e1x * e2z, e = e1x * e2y, f = e1y * e2x;
    p.t0x[h] = t0x;
    p.t0y[h] = t0y;
    p.t0z[h] = t0z;
    p.nx[h] = a - b;
    p.ny[h] = c - d;
    p.nz[h] = e - f;
}

// Face planes of w, with the certifying bound (tet_plane_bound of a box
// holding both bodies).
HGCD_TET_INLINE void tet_planes(const TetWorld &w, double bound, TetPlanes &p) {
    p.bound = bound;
    const V2 *x = w.x, *y = w.y, *z = w.z;
#define HGCD_SH(v, i, j) __builtin_shufflevector(v[0], v[1], i, j)
    // faces 0 = (1 2 3), 1 = (0 3 2)
    plane_pair(p, 0, HGCD_SH(x, 1, 0), HGCD_SH(y, 1, 0), HGCD_SH(z, 1, 0), x[1], y[1], z[1],
               HGCD_SH(x, 3, 2), HGCD_SH(y, 3, 2), HGCD_SH(z, 3, 2));
    // faces 2 = (0 1 3), 3 = (0 2 1)
    plane_pair(p, 1, HGCD_SH(x, 0, 0), HGCD_SH(y, 0, 0), HGCD_SH(z, 0, 0), HGCD_SH(x, 1, 2),
               HGCD_SH(y, 1, 2), HGCD_SH(z, 1, 2), HGCD_SH(x, 3, 1), HGCD_SH(y, 3, 1),
               HGCD_SH(z, 3, 1));
#undef HGCD_SH
}

// -orient3d(face, point) for the faces of pair h, points per lane.
inline V2 plane_eval(const TetPlanes &p, int h, V2 px, V2 py, V2 pz) {
    return ((px - p.t0x[h]) * p.nx[h] + (py - p.t0y[h]) * p.ny[h]) + (pz - p.t0z[h]) * p.nz[h];
}

// Certified signs of the four vertices of one body against the four faces of
// the other: bit v of pos[f] / neg[f] when orient3d(face f, vertex v) is
// surely positive / negative; in neither, undecided.
struct TetSides {
    unsigned pos[4], neg[4];
    int inner;  // sign of orient3d(face f, vertex f) of the faces' own tetrahedron
};

// Face F against the four vertices of o (two per vector).
template <int F>
HGCD_TET_INLINE void tet_face(const TetPlanes &p, const TetWorld &o, TetSides &s) {
    constexpr int h = F / 2, l = F % 2;
    const V2 t0x = lane<l>(p.t0x[h]), t0y = lane<l>(p.t0y[h]), t0z = lane<l>(p.t0z[h]);
    const V2 nx = lane<l>(p.nx[h]), ny = lane<l>(p.ny[h]), nz = lane<l>(p.nz[h]);
    const V2 bound = V2{} + p.bound, minus = -bound;
    const V2 d0 = ((o.x[0] - t0x) * nx + (o.y[0] - t0y) * ny) + (o.z[0] - t0z) * nz;
    const V2 d1 = ((o.x[1] - t0x) * nx + (o.y[1] - t0y) * ny) + (o.z[1] - t0z) * nz;
    s.pos[F] = less_bits(d0, minus) | less_bits(d1, minus) << 2;  // d = -orient3d
    s.neg[F] = less_bits(bound, d0) | less_bits(bound, d1) << 2;
}

// Sign of orient3d(face f, vertex f), the same for every f: from any
// certified lane, else exactly.
HGCD_TET_INLINE int tet_inner_sign(const TetWorld &w, const TetPlanes &p) {
    const V2 bound = V2{} + p.bound;
    const V2 d0 = plane_eval(p, 0, w.x[0], w.y[0], w.z[0]);  // faces 0, 1 at vertices 0, 1
    if (less_bits(d0, -bound)) return 1;
    if (less_bits(bound, d0)) return -1;
    const V2 d1 = plane_eval(p, 1, w.x[1], w.y[1], w.z[1]);  // faces 2, 3 at vertices 2, 3
    if (less_bits(d1, -bound)) return 1;
    if (less_bits(bound, d1)) return -1;
    const double v0[3] = {w.x[0][0], w.y[0][0], w.z[0][0]}, v1[3] = {w.x[0][1], w.y[0][1], w.z[0][1]},
                 v2[3] = {w.x[1][0], w.y[1][0], w.z[1][0]}, v3[3] = {w.x[1][1], w.y[1][1], w.z[1][1]};
    return orient3d(v1, v2, v3, v0);  // face 0 and vertex 0
}

// Face f has every vertex of the other body certainly strictly on its outer
// side (on either side when the tetrahedron is flat: it lies in the plane).
// The outer sets: all four vertices (0xF), or 0x10, which no set equals.
struct TetOuter {
    unsigned pos, neg;
    explicit TetOuter(int inner) : pos(inner <= 0 ? 0xFu : 0x10u), neg(inner >= 0 ? 0xFu : 0x10u) {}
    bool separates(const TetSides &s, int f) const { return (s.pos[f] == pos) | (s.neg[f] == neg); }
};
inline bool tet_face_separates(const TetSides &s, int f) { return TetOuter(s.inner).separates(s, f); }

// Signs of the other body's vertices against the faces of w; true (and the
// signs left incomplete) as soon as a face separates the bodies.
HGCD_TET_INLINE bool tet_sides_separate(const TetWorld &w, const TetPlanes &p, const TetWorld &o, TetSides &s) {
    s.inner = tet_inner_sign(w, p);
    const TetOuter outer(s.inner);
    tet_face<0>(p, o, s);
    if (outer.separates(s, 0)) return true;
    tet_face<1>(p, o, s);
    if (outer.separates(s, 1)) return true;
    tet_face<2>(p, o, s);
    if (outer.separates(s, 2)) return true;
    tet_face<3>(p, o, s);
    return outer.separates(s, 3);
}

inline bool tet_separated(const TetSides &s) {
    return tet_face_separates(s, 0) || tet_face_separates(s, 1) || tet_face_separates(s, 2) ||
           tet_face_separates(s, 3);
}

// From the certified signs: 2 surely Surface (a vertex strictly inside, one
// strictly outside), 1 surely Containment (all strictly inside), 0 undecided.
HGCD_TET_INLINE int tet_verdict(const TetSides &s) {
    if (s.inner == 0) return 0;
    const unsigned *inner = s.inner > 0 ? s.pos : s.neg, *outer = s.inner > 0 ? s.neg : s.pos;
    const unsigned in = inner[0] & inner[1] & inner[2] & inner[3];
    if (in == 0xF) return 1;
    return in && (outer[0] | outer[1] | outer[2] | outer[3]) ? 2 : 0;
}

inline void tet_aos(const TetWorld &w, double (*v)[3]) {
    for (int i = 0; i < 4; ++i) {
        v[i][0] = w.x[i / 2][i % 2];
        v[i][1] = w.y[i / 2][i % 2];
        v[i][2] = w.z[i / 2][i % 2];
    }
}

// Makes every sign of s exact: an undecided one is computed exactly (and
// stays in neither set when it is 0). True if there was one.
inline bool tet_resolve(const double (*t)[3], const double (*o)[3], TetSides &s) {
    bool any = false;
    for (int f = 0; f < 4; ++f) {
        unsigned open = ~(s.pos[f] | s.neg[f]) & 0xF;
        while (open) {
            const int v = __builtin_ctz(open);
            open &= open - 1;
            const int sign = orient3d(t[kFace[f][0]], t[kFace[f][1]], t[kFace[f][2]], o[v]);
            if (sign > 0) s.pos[f] |= 1u << v;
            if (sign < 0) s.neg[f] |= 1u << v;
            any = true;
        }
    }
    return any;
}

inline int sign_of(const TetSides &s, int f, int v) {
    return int((s.pos[f] >> v) & 1) - int((s.neg[f] >> v) & 1);
}

// Everything the certified signs left open: the same decisions on exact
// signs, then the exact triangle test on the face pairs whose planes do not
// already keep them apart.
// (Vertices wa[i] = (x, y, z) of vertex i.)
__attribute__((noinline)) HGCD_TET_CLONES Contact collide_tetra_exact_aos(const double (*wa)[3],
                                                                         const double (*wb)[3], TetSides &sab,
                                                                         TetSides &sba, NarrowScratch &scratch) {
    // (The caller took these decisions on the certified signs already.)
    if (tet_resolve(wa, wb, sab) | tet_resolve(wb, wa, sba)) {
        if (tet_separated(sab) || tet_separated(sba)) return Contact::None;
        const int va = tet_verdict(sab), vb = tet_verdict(sba);
        if (va == 2 || vb == 2) return Contact::Surface;
        if (va == 1 || vb == 1) return Contact::Containment;
    }
    // Face pairs (f, g) with one triangle strictly on one side of the other's
    // plane are skipped. kHolds[S]: the faces whose 3 vertices all lie in the
    // vertex set S (face g misses vertex g).
    static constexpr unsigned kHolds[16] = {0, 0, 0, 0, 0, 0, 0, 8, 0, 0, 0, 4, 0, 2, 1, 15};
    const unsigned apart[4] = {kHolds[sba.pos[0]] | kHolds[sba.neg[0]], kHolds[sba.pos[1]] | kHolds[sba.neg[1]],
                               kHolds[sba.pos[2]] | kHolds[sba.neg[2]], kHolds[sba.pos[3]] | kHolds[sba.neg[3]]};
    for (int f = 0; f < 4; ++f) {  // apart[g]: bit f; kHolds[sab.*[f]]: bit g
        unsigned pending = ~(kHolds[sab.pos[f]] | kHolds[sab.neg[f]]) & 0xF;
        const double *p[3] = {wa[kFace[f][0]], wa[kFace[f][1]], wa[kFace[f][2]]};
        while (pending) {
            const int g = __builtin_ctz(pending);
            pending &= pending - 1;
            if ((apart[g] >> f) & 1) continue;
            const double *q[3] = {wb[kFace[g][0]], wb[kFace[g][1]], wb[kFace[g][2]]};
            const int sp[3] = {sign_of(sba, g, kFace[f][0]), sign_of(sba, g, kFace[f][1]),
                               sign_of(sba, g, kFace[f][2])};
            const int sq[3] = {sign_of(sab, f, kFace[g][0]), sign_of(sab, f, kFace[g][1]),
                               sign_of(sab, f, kFace[g][2])};
            ++scratch.triangle_tests;
            if (tri_tri_intersect_signed(p, q, sp, sq)) return Contact::Surface;
        }
    }
    // Surfaces apart: a solid holding the other's surface holds all its
    // vertices strictly inside, which the exact verdicts above would have
    // reported.
    return Contact::None;
}

inline Contact collide_tetra_exact(const TetWorld &ta, const TetWorld &tb, TetSides &sab, TetSides &sba,
                                   NarrowScratch &scratch) {
    double wa[4][3], wb[4][3];
    tet_aos(ta, wa);
    tet_aos(tb, wb);
    return collide_tetra_exact_aos(wa, wb, sab, sba, scratch);
}

// A separating axis across an edge of each tetrahedron, tried on the pairs
// that no face plane keeps apart and no certified sign decides, before the
// exact path. Two disjoint convex hulls with no separating face plane have
// a separating plane parallel to an edge of each; on scene tetra 42 k pairs
// a tick at n = 750000 are such, and their exact path tests up to 16
// triangle pairs each. Of the 36 edge pairs one is tried: the edge joining
// the two vertices of each tetrahedron nearest the other's position (its
// centre); it finds an axis for 83% of those pairs (some pair of the 36 for
// all of them). The choice is a guess and any axis proves disjointness, so
// nothing needs to be exact but the final test.
//
// Why that test is certain. On an axis n (any double vector) the
// projections (x - c) . n of the world vertices, c a vertex of u, are
// evaluated within 5 eps S, S = e . |n| and e the extent of the box holding
// both bodies (which bounds |x - c| per coordinate): eps for x - c, gamma_3
// for the dot product. When the computed gap between the two sets of
// projections passes 2^-46 S + 2^-960 (128 eps S, and underflowed
// products), the real projections of the two hulls are strictly apart.
struct EdgeAxis {
    double n[3], c[3];  // the axis, and the vertex of u the projections are taken from
    // du, dv: the squared distances of u's and v's vertices to the other's
    // centre (any 4-lane type indexed by []).
    template <class D>
    EdgeAxis(const TetWorld &u, const TetWorld &v, const D &du, const D &dv) {
        double ux[4], uy[4], uz[4], vx[4], vy[4], vz[4];
        std::memcpy(ux, u.x, sizeof ux);
        std::memcpy(uy, u.y, sizeof uy);
        std::memcpy(uz, u.z, sizeof uz);
        std::memcpy(vx, v.x, sizeof vx);
        std::memcpy(vy, v.y, sizeof vy);
        std::memcpy(vz, v.z, sizeof vz);
        int a0, a1, b0, b1;
        nearest(du, a0, a1);
        nearest(dv, b0, b1);
        const double ax = ux[a1] - ux[a0], ay = uy[a1] - uy[a0], az = uz[a1] - uz[a0];
        const double bx = vx[b1] - vx[b0], by = vy[b1] - vy[b0], bz = vz[b1] - vz[b0];
        n[0] = ay * bz - az * by;
        n[1] = az * bx - ax * bz;
        n[2] = ax * by - ay * bx;
        c[0] = ux[a0];
        c[1] = uy[a0];
        c[2] = uz[a0];
    }
    // The two smallest of d[0..3] (selects, not branches).
    template <class D>
    static void nearest(const D &d, int &k0, int &k1) {
        int a = d[1] < d[0] ? 1 : 0, b = 1 - a;
        for (int i = 2; i < 4; ++i) {
            const bool below_a = d[i] < d[a], below_b = d[i] < d[b];
            b = below_a ? a : below_b ? i : b;
            a = below_a ? i : a;
        }
        k0 = a;
        k1 = b;
    }
    // u's projections in [amin, amax], v's in [bmin, bmax]: certainly apart?
    bool apart(double amin, double amax, double bmin, double bmax, double ex, double ey, double ez) const {
        const double margin =
            kEdgeMargin * ((ex * std::fabs(n[0]) + ey * std::fabs(n[1])) + ez * std::fabs(n[2])) + kUnderflowFloor;
        return (bmin - amax > margin) | (amin - bmax > margin);
    }
};

// The two-lane version (SSE2, NEON), out of line as the AVX2 one (inlined,
// it slowed the whole pair test).
__attribute__((noinline)) HGCD_TET_CLONES bool tet_edges_separate_v2(const TetWorld &u, const TetWorld &v,
                                                                    const double *cu, const double *cv,
                                                                    double ex, double ey, double ez) {
    auto dist2 = [](const TetWorld &w, const double *c) {
        std::array<double, 4> d;
        for (int h = 0; h < 2; ++h) {
            const V2 dx = w.x[h] - c[0], dy = w.y[h] - c[1], dz = w.z[h] - c[2];
            const V2 dd = (dx * dx + dy * dy) + dz * dz;
            d[2 * h] = dd[0];
            d[2 * h + 1] = dd[1];
        }
        return d;
    };
    const EdgeAxis ax(u, v, dist2(u, cv), dist2(v, cu));
    auto project = [&](const TetWorld &w, double &lo, double &hi) {
        V2 p[2];
        for (int h = 0; h < 2; ++h)
            p[h] = ((w.x[h] - ax.c[0]) * ax.n[0] + (w.y[h] - ax.c[1]) * ax.n[1]) + (w.z[h] - ax.c[2]) * ax.n[2];
        lo = hmin(p[0], p[1]);
        hi = hmax(p[0], p[1]);
    };
    double amin, amax, bmin, bmax;
    project(u, amin, amax);
    project(v, bmin, bmax);
    return ax.apart(amin, amax, bmin, bmax, ex, ey, ez);
}

// Separating axis along the line of centres (the bodies' positions), tested
// before any world vertex is computed: on scene tetra at n = 750000 it rejects
// 47% of the broad phase's box candidates (the exact vertex boxes after it
// almost none: the broad phase's boxes are the same, rounded outward to
// float; with sphere candidates the figures were 56% and 31%). Any axis u proves the hulls
// of two point sets disjoint when their projections on it are strictly apart,
// so u = fl(c_b - c_a) need not be exact, and touching sets are never rejected.
// The projection of a world vertex w = fl(c + fl(R l)) (tet_world) is u.c +
// l.(R^T u), exactly for R as rounded, plus its rounding: at most eps |c|.|u| +
// 4 eps |l|.(|R|^T |u|) (eps = 2^-53; this bound and those below to first order
// in eps, which the slack covers). Here d = fl(R^T u) and h = max_i fl(l_i . d)
// miss max_i l_i.(R^T u) by at most 2 gamma_3 |l|.(|R|^T |u|), and
// (c_b - c_a).u is fl(u.u) within 5 eps u.u. Accepted quaternions are unit
// within 1e-6 (hgcd.h), so |R_kj| <= 1 + 3e-6 < 2 and |l|.(|R|^T |u|) <
// 2 s reach |u|_1; with the rounding of u.u - (h_a + h_b) itself every error
// stays below
//   6 eps u.u + eps (|c_a| + |c_b|).|u| + 24 eps (s_a reach_a + s_b reach_b) |u|_1,
// which tet_axis_margin (2^-48 = 32 eps, reach terms doubled) covers more
// than twice. Underflowed products add less than 2^-1000 (|l|, |u| < 2^52).
HGCD_TET_INLINE double tet_axis_margin(const BodyPose &a, const BodyPose &b, const double *u, double uu) {
    const double *ca = a.position, *cb = b.position;
    const double au[3] = {std::fabs(u[0]), std::fabs(u[1]), std::fabs(u[2])};
    const double reach = 2 * (a.scale * a.mesh->tetra_reach + b.scale * b.mesh->tetra_reach);
    const double cu = ((std::fabs(ca[0]) + std::fabs(cb[0]) + reach) * au[0] +
                       (std::fabs(ca[1]) + std::fabs(cb[1]) + reach) * au[1]) +
                      (std::fabs(ca[2]) + std::fabs(cb[2]) + reach) * au[2];
    return kCentresMargin * (uu + cu) + kUnderflowFloor;
}

// The projections of a reach u.c_a + h_a, those of b go down to u.c_b - h_b,
// with h_a = max_i la_i . (R_a^T u) and h_b = max_j lb_j . (-R_b^T u).
template <class K>
HGCD_TET_INLINE bool tet_axis_separates(const BodyPose &a, const BodyPose &b, const TetRotations &r,
                                        const typename K::Local &la, const typename K::Local &lb) {
    const double *ca = a.position, *cb = b.position;
    const double u[3] = {cb[0] - ca[0], cb[1] - ca[1], cb[2] - ca[2]};
    V2 d[3];  // R_a^T u in lane 0, -R_b^T u in lane 1
    for (int j = 0; j < 3; ++j) d[j] = V2{1, -1} * ((r.m[j] * u[0] + r.m[3 + j] * u[1]) + r.m[6 + j] * u[2]);
    const double uu = (u[0] * u[0] + u[1] * u[1]) + u[2] * u[2];
    const double gap = uu - K::supports(la, lb, d);
    return gap > 0 && gap > tet_axis_margin(a, b, u, uu);  // the margin only when it can matter
}

// The pair test over a set of kernels K (local, supports, world, planes,
// sides_separate).
template <class K>
HGCD_TET_INLINE Contact collide_tetra_with(const BodyPose &a, const BodyPose &b, NarrowScratch &scratch) {
    // One rotation and one set of scaled vertices per body, for the axis
    // test and the world vertices alike.
    TetRotations r;
    tet_rotations(a, b, r);
    typename K::Local la, lb;
    K::local(a, la);
    K::local(b, lb);
    if (tet_axis_separates<K>(a, b, r, la, lb)) return Contact::None;
    TetWorld ta, tb;
    K::template world<0>(a, r, la, ta);
    K::template world<1>(b, r, lb, tb);
    // Exact prefilter: the solids lie inside these boxes. (Behind the broad
    // phase's boxes it only catches pairs within a float step of touching;
    // the boxes are needed below anyway.)
    if (ta.hi[0] < tb.lo[0] || tb.hi[0] < ta.lo[0] || ta.hi[1] < tb.lo[1] || tb.hi[1] < ta.lo[1] ||
        ta.hi[2] < tb.lo[2] || tb.hi[2] < ta.lo[2])
        return Contact::None;
    ++scratch.exact_tests;
    // Extent of a box holding both bodies (bounds |fl(x - t0)| for the filters).
    const double ex = std::max(ta.hi[0], tb.hi[0]) - std::min(ta.lo[0], tb.lo[0]);
    const double ey = std::max(ta.hi[1], tb.hi[1]) - std::min(ta.lo[1], tb.lo[1]);
    const double ez = std::max(ta.hi[2], tb.hi[2]) - std::min(ta.lo[2], tb.lo[2]);
    // The larger body's faces first: they separate more often (on scene
    // tetra, 19% fewer pairs need the second body's faces).
    const TetWorld *u = &ta, *v = &tb;
    const double *cu = a.position, *cv = b.position;
    double size_a, size_b;
    tet_box_size(size_a, ta.lo, ta.hi);
    tet_box_size(size_b, tb.lo, tb.hi);
    const double bound = tet_plane_bound(ex, ey, ez);
    if (size_b > size_a) {
        std::swap(u, v);
        std::swap(cu, cv);
    }
    TetPlanes pu, pv;
    TetSides suv, svu;  // v's vertices against u's faces, and u's against v's
    K::planes(*u, bound, pu);
    if (K::sides_separate(*u, pu, *v, suv)) return Contact::None;
    // A vertex of v strictly inside u is a common point: no face of v can
    // separate them, and v's verdict cannot differ (v wholly inside u's
    // interior leaves no vertex of u inside v).
    const int vu = tet_verdict(suv);
    if (vu == 2) return Contact::Surface;
    if (vu == 1) return Contact::Containment;
    K::planes(*v, bound, pv);
    if (K::sides_separate(*v, pv, *u, svu)) return Contact::None;
    const int vv = tet_verdict(svu);
    if (vv == 2) return Contact::Surface;
    if (vv == 1) return Contact::Containment;
    if (K::edges_separate(*u, *v, cu, cv, ex, ey, ez)) return Contact::None;
    return collide_tetra_exact(*u, *v, suv, svu, scratch);
}

struct KernelsV2 {
    typedef TetLocal Local;
    static HGCD_TET_INLINE void local(const BodyPose &b, Local &l) { tet_local(b, l); }
    static HGCD_TET_INLINE double supports(const Local &la, const Local &lb, const V2 *d) {
        return tet_supports(la, lb, d);
    }
    template <int L>
    static HGCD_TET_INLINE void world(const BodyPose &b, const TetRotations &r, const Local &l, TetWorld &w) {
        tet_world<L>(b, r, l, w);
    }
    static HGCD_TET_INLINE void planes(const TetWorld &w, double bound, TetPlanes &p) {
        tet_planes(w, bound, p);
    }
    static HGCD_TET_INLINE bool sides_separate(const TetWorld &w, const TetPlanes &p, const TetWorld &o,
                                               TetSides &s) {
        return tet_sides_separate(w, p, o, s);
    }
    static HGCD_TET_INLINE bool edges_separate(const TetWorld &u, const TetWorld &v, const double *cu,
                                               const double *cv, double ex, double ey, double ez) {
        return tet_edges_separate_v2(u, v, cu, cv, ex, ey, ez);
    }
};

HGCD_TET_CLONES Contact collide_tetra_v2(const BodyPose &a, const BodyPose &b, NarrowScratch &scratch) {
    return collide_tetra_with<KernelsV2>(a, b, scratch);
}

#if HGCD_AVX2
// The same kernels four lanes wide for CPUs with AVX2 (vpermpd for the face
// shuffles), picked at run time. Each lane does the operations of the V2
// kernels in the same order, without FMA: the same bits, the same signs. The
// kernels have no target of their own: they are only ever expanded inside
// collide_tetra_avx2, whose target allows the AVX builtins.
typedef double V4 __attribute__((vector_size(32)));
typedef int64_t M4 __attribute__((vector_size(32)));

#pragma GCC push_options
#pragma GCC target("avx2")
static inline unsigned less_avx2(const V4 &a, const V4 &b) {
    return unsigned(_mm256_movemask_pd(_mm256_cmp_pd((__m256d)a, (__m256d)b, _CMP_LT_OQ)));
}
// (An out-parameter: the kernels that call it have no target of their own,
// and a vector return would change the ABI there; the batched test's
// helpers below, all of the AVX2 target, return theirs.)
static inline void max_avx2(V4 &out, const V4 &a, const V4 &b) { out = (V4)_mm256_max_pd((__m256d)a, (__m256d)b); }
#pragma GCC pop_options

#pragma GCC push_options
#pragma GCC target("avx2")
static inline double hmax_avx2(const V4 &a) {
    const __m256d m = _mm256_max_pd((__m256d)a, _mm256_permute2f128_pd((__m256d)a, (__m256d)a, 1));
    return _mm_cvtsd_f64(_mm256_castpd256_pd128(_mm256_max_pd(m, _mm256_permute_pd(m, 5))));
}
static inline double hmin_avx2(const V4 &a) {
    const __m256d m = _mm256_min_pd((__m256d)a, _mm256_permute2f128_pd((__m256d)a, (__m256d)a, 1));
    return _mm_cvtsd_f64(_mm256_castpd256_pd128(_mm256_min_pd(m, _mm256_permute_pd(m, 5))));
}
#pragma GCC pop_options

__attribute__((target("avx2"), noinline)) bool tet_edges_separate_avx2(const TetWorld &u, const TetWorld &v,
                                                                      const double *cu, const double *cv,
                                                                      double ex, double ey, double ez) {
    V4 ux, uy, uz, vx, vy, vz;
    std::memcpy(&ux, u.x, sizeof ux);
    std::memcpy(&uy, u.y, sizeof uy);
    std::memcpy(&uz, u.z, sizeof uz);
    std::memcpy(&vx, v.x, sizeof vx);
    std::memcpy(&vy, v.y, sizeof vy);
    std::memcpy(&vz, v.z, sizeof vz);
    // (Written out: a lambda would not inherit the AVX2 target.)
    const V4 dux = ux - cv[0], duy = uy - cv[1], duz = uz - cv[2];
    const V4 dvx = vx - cu[0], dvy = vy - cu[1], dvz = vz - cu[2];
    const V4 du = (dux * dux + duy * duy) + duz * duz, dv = (dvx * dvx + dvy * dvy) + dvz * dvz;
    const EdgeAxis ax(u, v, du, dv);
    const V4 pu = ((ux - ax.c[0]) * ax.n[0] + (uy - ax.c[1]) * ax.n[1]) + (uz - ax.c[2]) * ax.n[2];
    const V4 pv = ((vx - ax.c[0]) * ax.n[0] + (vy - ax.c[1]) * ax.n[1]) + (vz - ax.c[2]) * ax.n[2];
    return ax.apart(hmin_avx2(pu), hmax_avx2(pu), hmin_avx2(pv), hmax_avx2(pv), ex, ey, ez);
}

struct KernelsV4 {
    static HGCD_TET_INLINE void load(V4 &v, const void *p) { std::memcpy(&v, p, sizeof v); }
    static HGCD_TET_INLINE void store(void *p, const V4 &v) { std::memcpy(p, &v, sizeof v); }
#define HGCD_SPLAT4(v) (V4{(v), (v), (v), (v)})
    static HGCD_TET_INLINE unsigned less(const V4 &a, const V4 &b) {  // bit i: a[i] < b[i]
        return less_avx2(a, b);
    }
    struct Local {
        V4 x, y, z;
    };
    static HGCD_TET_INLINE void local(const BodyPose &b, Local &l) {
        const double s = b.scale, *m = b.mesh->tetra_local;
        V4 mx, my, mz;
        load(mx, m);
        load(my, m + 4);
        load(mz, m + 8);
        l.x = s * mx;
        l.y = s * my;
        l.z = s * mz;
    }
    static HGCD_TET_INLINE double supports(const Local &la, const Local &lb, const V2 *d) {
        const V4 pa = (la.x * d[0][0] + la.y * d[1][0]) + la.z * d[2][0];
        const V4 pb = (lb.x * d[0][1] + lb.y * d[1][1]) + lb.z * d[2][1];
        // Lanes (a0 a1 b0 b1) against (a2 a3 b2 b3), then the two halves.
        V4 m, h;
        max_avx2(m, __builtin_shufflevector(pa, pb, 0, 1, 4, 5), __builtin_shufflevector(pa, pb, 2, 3, 6, 7));
        max_avx2(h, m, __builtin_shufflevector(m, m, 1, 0, 3, 2));
        return h[0] + h[2];
    }
    template <int L>
    static HGCD_TET_INLINE void world(const BodyPose &b, const TetRotations &rot, const Local &l, TetWorld &w) {
        const double *c = b.position;
        // Splats of lane L in registers: read back from memory as scalars,
        // GCC merged them into 32-byte loads of 16-byte stores (a store
        // forwarding stall: narrow phase 12% slower on tetra 750k).
        V4 r[9];
        for (int k = 0; k < 9; ++k) r[k] = __builtin_shufflevector(rot.m[k], rot.m[k], L, L, L, L);
        const V4 lx = l.x, ly = l.y, lz = l.z;
        store(w.x, c[0] + ((r[0] * lx + r[1] * ly) + r[2] * lz));
        store(w.y, c[1] + ((r[3] * lx + r[4] * ly) + r[5] * lz));
        store(w.z, c[2] + ((r[6] * lx + r[7] * ly) + r[8] * lz));
        tet_box(w);
    }
    static HGCD_TET_INLINE void planes(const TetWorld &w, double bound, TetPlanes &p) {
        p.bound = bound;
        V4 x, y, z;
        load(x, w.x);
        load(y, w.y);
        load(z, w.z);
        // Faces 0..3 = (1 2 3), (0 3 2), (0 1 3), (0 2 1), one per lane.
        const V4 t0x = __builtin_shufflevector(x, x, 1, 0, 0, 0), t0y = __builtin_shufflevector(y, y, 1, 0, 0, 0),
                 t0z = __builtin_shufflevector(z, z, 1, 0, 0, 0);
        const V4 e1x = __builtin_shufflevector(x, x, 2, 3, 1, 2) - t0x,
                 e1y = __builtin_shufflevector(y, y, 2, 3, 1, 2) - t0y,
                 e1z = __builtin_shufflevector(z, z, 2, 3, 1, 2) - t0z;
        const V4 e2x = __builtin_shufflevector(x, x, 3, 2, 3, 1) - t0x,
                 e2y = __builtin_shufflevector(y, y, 3, 2, 3, 1) - t0y,
                 e2z = __builtin_shufflevector(z, z, 3, 2, 3, 1) - t0z;
        const V4 a = e1y * e2z, b = e1z * e2y, c = e1z * e2x, d = e1x * e2z, e = e1x * e2y, f = e1y * e2x;
        store(p.t0x, t0x);
        store(p.t0y, t0y);
        store(p.t0z, t0z);
        store(p.nx, a - b);
        store(p.ny, c - d);
        store(p.nz, e - f);
    }
    template <int F>
    static HGCD_TET_INLINE void face(const TetPlanes &p, const V4 &x, const V4 &y, const V4 &z, TetSides &s) {
        constexpr int h = F / 2, l = F % 2;
        const V4 tx = HGCD_SPLAT4(p.t0x[h][l]), ty = HGCD_SPLAT4(p.t0y[h][l]), tz = HGCD_SPLAT4(p.t0z[h][l]);
        const V4 nx = HGCD_SPLAT4(p.nx[h][l]), ny = HGCD_SPLAT4(p.ny[h][l]), nz = HGCD_SPLAT4(p.nz[h][l]);
        const V4 bound = HGCD_SPLAT4(p.bound), minus = -bound;
        const V4 d = ((x - tx) * nx + (y - ty) * ny) + (z - tz) * nz;  // -orient3d
        s.pos[F] = less(d, minus);
        s.neg[F] = less(bound, d);
    }
    static HGCD_TET_INLINE bool sides_separate(const TetWorld &w, const TetPlanes &p, const TetWorld &o,
                                               TetSides &s) {
        V4 x, y, z, tx, ty, tz, nx, ny, nz;
        const V4 bound = HGCD_SPLAT4(p.bound);
        load(x, w.x);
        load(y, w.y);
        load(z, w.z);
        load(tx, p.t0x);
        load(ty, p.t0y);
        load(tz, p.t0z);
        load(nx, p.nx);
        load(ny, p.ny);
        load(nz, p.nz);
        // Face f at its own vertex f: the tetrahedron's sign (tet_inner_sign).
        const V4 d = ((x - tx) * nx + (y - ty) * ny) + (z - tz) * nz;
        s.inner = less(d, -bound) ? 1 : less(bound, d) ? -1 : tet_inner_sign(w, p);
        load(x, o.x);
        load(y, o.y);
        load(z, o.z);
        const TetOuter outer(s.inner);
        face<0>(p, x, y, z, s);
        if (outer.separates(s, 0)) return true;
        face<1>(p, x, y, z, s);
        if (outer.separates(s, 1)) return true;
        face<2>(p, x, y, z, s);
        if (outer.separates(s, 2)) return true;
        face<3>(p, x, y, z, s);
        return outer.separates(s, 3);
    }
    static HGCD_TET_INLINE bool edges_separate(const TetWorld &u, const TetWorld &v, const double *cu,
                                               const double *cv, double ex, double ey, double ez) {
        return tet_edges_separate_avx2(u, v, cu, cv, ex, ey, ez);
    }
};

#undef HGCD_SPLAT4

__attribute__((target("avx2"))) Contact collide_tetra_avx2(const BodyPose &a, const BodyPose &b,
                                                           NarrowScratch &scratch) {
    return collide_tetra_with<KernelsV4>(a, b, scratch);
}

// Many pairs at a time, one per lane (collide_tetra_batch). Pairs are first
// filtered by the axis along the line of centres, four at a time, each lane
// in the one-pair test's operations (tet_axis_separates), so with the same
// bits. The survivors, eight at a time in two groups of four, get both
// bodies' world vertices and boxes (KernelsV4's world, the same bits), then
// the signs of each body's vertices against the other's faces, certified in
// float (sides8, with a bound of its own), all branch-free (on scene tetra
// 41% of the pairs that reach the faces need both bodies' faces in the
// one-pair test, so a group nearly always needs them). Certified decisions
// cannot disagree, whatever filter certified them. A lane left open (no face
// separates, no vertex is surely inside) takes the one-pair test's edge axis
// (the same bits) and exact path, which makes every sign exact first; a lane
// whose own tetrahedron's orientation is not certified (flat or nearly), or
// whose box is nearly flat, the whole one-pair test. So the verdicts and the
// work counted (exact tests, triangle tests) are the one-pair test's.
struct Side4 {
    V4 c[3];     // position
    V4 m[9];     // rotation
    V4 l[3][4];  // scaled local vertices, l[axis][vertex]
    V4 reach;    // scale * tetra_reach
};

#pragma GCC push_options
#pragma GCC target("avx2")
static inline void transpose4(V4 &r0, V4 &r1, V4 &r2, V4 &r3) {
    const __m256d t0 = _mm256_unpacklo_pd((__m256d)r0, (__m256d)r1);
    const __m256d t1 = _mm256_unpackhi_pd((__m256d)r0, (__m256d)r1);
    const __m256d t2 = _mm256_unpacklo_pd((__m256d)r2, (__m256d)r3);
    const __m256d t3 = _mm256_unpackhi_pd((__m256d)r2, (__m256d)r3);
    r0 = (V4)_mm256_permute2f128_pd(t0, t2, 0x20);
    r1 = (V4)_mm256_permute2f128_pd(t1, t3, 0x20);
    r2 = (V4)_mm256_permute2f128_pd(t0, t2, 0x31);
    r3 = (V4)_mm256_permute2f128_pd(t1, t3, 0x31);
}
static inline unsigned lanes_of(const M4 &m) { return unsigned(_mm256_movemask_pd((__m256d)m)); }
static inline V4 min4(const V4 &a, const V4 &b) { return (V4)_mm256_min_pd((__m256d)a, (__m256d)b); }
static inline V4 max4(const V4 &a, const V4 &b) { return (V4)_mm256_max_pd((__m256d)a, (__m256d)b); }
static inline V4 abs4(const V4 &a) { return (V4)((M4)a & (M4{} + INT64_MAX)); }

// The bodies of one side of four pairs. A Placement is read as two 32-byte
// halves: (x y z qx) and (qy qz qw scale).
static inline void load_side(const Placement *const *p, const Mesh *const *mesh, Side4 &s) {
    V4 r[4], h[4];
    for (int k = 0; k < 4; ++k) {  // (memcpy here went through the stack: a store forwarding stall)
        const double *half = reinterpret_cast<const double *>(p[k]);
        r[k] = (V4)_mm256_loadu_pd(half);
        h[k] = (V4)_mm256_loadu_pd(half + 4);
    }
    transpose4(r[0], r[1], r[2], r[3]);
    transpose4(h[0], h[1], h[2], h[3]);
    s.c[0] = r[0];
    s.c[1] = r[1];
    s.c[2] = r[2];
    const V4 scale = h[3];
    rotation_entries(r[3], h[0], h[1], h[2], s.m);
    const Mesh *m0 = mesh[0];
    if (mesh[1] == m0 && mesh[2] == m0 && mesh[3] == m0) {  // (shared shapes: the usual case)
        for (int a = 0; a < 3; ++a)
            for (int v = 0; v < 4; ++v) s.l[a][v] = scale * m0->tetra_local[4 * a + v];
        s.reach = scale * m0->tetra_reach;
    } else {
        for (int a = 0; a < 3; ++a) {
            V4 t[4];
            for (int k = 0; k < 4; ++k) t[k] = (V4)_mm256_loadu_pd(mesh[k]->tetra_local + 4 * a);
            transpose4(t[0], t[1], t[2], t[3]);
            for (int v = 0; v < 4; ++v) s.l[a][v] = scale * t[v];
        }
        s.reach = scale * V4{mesh[0]->tetra_reach, mesh[1]->tetra_reach, mesh[2]->tetra_reach, mesh[3]->tetra_reach};
    }
}

// Both sides of the pairs p[0..3].
static inline void load_pairs(const TetraPair *const *p, Side4 &A, Side4 &B) {
    const Placement *pa[4] = {p[0]->a, p[1]->a, p[2]->a, p[3]->a}, *pb[4] = {p[0]->b, p[1]->b, p[2]->b, p[3]->b};
    const Mesh *ma[4] = {p[0]->mesh_a, p[1]->mesh_a, p[2]->mesh_a, p[3]->mesh_a};
    const Mesh *mb[4] = {p[0]->mesh_b, p[1]->mesh_b, p[2]->mesh_b, p[3]->mesh_b};
    load_side(pa, ma, A);
    load_side(pb, mb, B);
}

// Lanes whose pair tet_axis_separates rejects (the same operations).
static inline unsigned axis_separated4(const Side4 &A, const Side4 &B) {
    const V4 u0 = B.c[0] - A.c[0], u1 = B.c[1] - A.c[1], u2 = B.c[2] - A.c[2];
    V4 ha, hb;
    {
        V4 da[3], db[3];
        for (int j = 0; j < 3; ++j) {
            da[j] = ((A.m[j] * u0 + A.m[3 + j] * u1) + A.m[6 + j] * u2);
            db[j] = -1.0 * ((B.m[j] * u0 + B.m[3 + j] * u1) + B.m[6 + j] * u2);
        }
        V4 pa[4], pb[4];
        for (int v = 0; v < 4; ++v) {
            pa[v] = (A.l[0][v] * da[0] + A.l[1][v] * da[1]) + A.l[2][v] * da[2];
            pb[v] = (B.l[0][v] * db[0] + B.l[1][v] * db[1]) + B.l[2][v] * db[2];
        }
        ha = max4(max4(pa[0], pa[1]), max4(pa[2], pa[3]));
        hb = max4(max4(pb[0], pb[1]), max4(pb[2], pb[3]));
    }
    const V4 uu = (u0 * u0 + u1 * u1) + u2 * u2;
    const V4 gap = uu - (ha + hb);
    const V4 reach = 2.0 * (A.reach + B.reach);
    const V4 cu = ((abs4(A.c[0]) + abs4(B.c[0]) + reach) * abs4(u0) + (abs4(A.c[1]) + abs4(B.c[1]) + reach) * abs4(u1)) +
                  (abs4(A.c[2]) + abs4(B.c[2]) + reach) * abs4(u2);
    const V4 margin = kCentresMargin * (uu + cu) + kUnderflowFloor;
    return lanes_of((gap > 0.0) & (gap > margin));
}

// World vertices w[axis][vertex] and box of one side (KernelsV4::world).
static inline void world4(const Side4 &s, V4 (*w)[4], V4 *lo, V4 *hi) {
    for (int a = 0; a < 3; ++a) {
        for (int v = 0; v < 4; ++v)
            w[a][v] = s.c[a] + ((s.m[3 * a] * s.l[0][v] + s.m[3 * a + 1] * s.l[1][v]) + s.m[3 * a + 2] * s.l[2][v]);
        lo[a] = min4(min4(w[a][0], w[a][1]), min4(w[a][2], w[a][3]));
        hi[a] = max4(max4(w[a][0], w[a][1]), max4(w[a][2], w[a][3]));
    }
}

// The face planes' signs in float, eight pairs at a time (two groups of
// four), on vertices that are the double world vertices less the low corner
// of the box holding both bodies, scaled by a power of two s that brings the
// box's largest extent below 1, rounded to float. (Double, four lanes, the
// narrow phase on tetra 750k took 1.3 ms more on 1 thread.) Why a sign is
// then certain when |d| > bound = 2^-15 P, P = ex ey ez of the scaled
// extents (each at most 1):
//  - let U be the world vertices less the corner, scaled, in exact
//    arithmetic: orient3d's sign on them is the sign on the world vertices
//    (a translation, and a positive scaling);
//  - the float vertices u differ from U by at most (2^-24 + 2^-52) e_k per
//    axis k (e_k the scaled extent), plus 2^-149 below float's normal range:
//    the double subtraction of the corner rounds by at most 2^-53 e_k, the
//    power-of-two scaling is exact, the conversion to float rounds by at
//    most 2^-24 of the value; a difference of two vertices by twice that.
//    orient3d is a sum of six products of three differences, one per axis,
//    each difference at most e_k (both points in the box), so moving every
//    difference so changes it by at most 3 * 6 * 2^-23 P = 36 * 2^-24 P (to
//    first order; the rest is below 2^-40 P);
//  - evaluated in float the same way as the double filters (geometry.cpp's
//    plane_sides3), the computed value is within (7 + 56 eps) eps of the
//    permanent, eps = 2^-24, and the permanent is at most 6 P (1 + 2^-21):
//    42.01 * 2^-24 P;
//  - together below 79 * 2^-24 P < 2^-17.6 P, which 2^-15 P exceeds more
//    than five times over, past its own rounding to float and past the
//    absolute errors below float's normal range (2^-140 in all), as long as
//    P >= 2^-115: a pair whose P is smaller (a box nearly flat, or both
//    bodies nearly one point) takes the whole one-pair test (double).
// The eight lanes' signs are certified signs as the double ones are; only
// a few more stay open (then made exact on the exact path).
typedef float F8 __attribute__((vector_size(32)));
typedef int32_t I8 __attribute__((vector_size(32)));

// The certified signs of o's vertices against the faces of w (lanes of
// tet_face, as bit sets: bit v of pos[f] / neg[f] per lane) and the sign of
// w's own orientation: inner_pos / inner_neg lanes (neither: uncertain).
struct Sides8 {
    I8 pos[4], neg[4];
    unsigned inner_pos, inner_neg;
};
static inline unsigned lanes8(const I8 &m) { return unsigned(_mm256_movemask_ps((__m256)m)); }
static inline void sides8(F8 (*w)[4], F8 (*o)[4], const F8 &bound, Sides8 &s) {
    I8 ip = I8{}, in = I8{};
    const F8 minus = -bound;
    for (int f = 0; f < 4; ++f) {
        const int i0 = kFace[f][0], i1 = kFace[f][1], i2 = kFace[f][2];
        const F8 t0x = w[0][i0], t0y = w[1][i0], t0z = w[2][i0];
        const F8 e1x = w[0][i1] - t0x, e1y = w[1][i1] - t0y, e1z = w[2][i1] - t0z;
        const F8 e2x = w[0][i2] - t0x, e2y = w[1][i2] - t0y, e2z = w[2][i2] - t0z;
        const F8 a = e1y * e2z, b = e1z * e2y, c = e1z * e2x, d = e1x * e2z, e = e1x * e2y, g = e1y * e2x;
        const F8 nx = a - b, ny = c - d, nz = e - g;
        const F8 own = ((w[0][f] - t0x) * nx + (w[1][f] - t0y) * ny) + (w[2][f] - t0z) * nz;  // -orient3d
        ip |= own < minus;
        in |= bound < own;
        I8 pos = I8{}, neg = I8{};
        for (int v = 0; v < 4; ++v) {
            const F8 dd = ((o[0][v] - t0x) * nx + (o[1][v] - t0y) * ny) + (o[2][v] - t0z) * nz;
            pos |= (dd < minus) & int32_t(1 << v);
            neg |= (bound < dd) & int32_t(1 << v);
        }
        s.pos[f] = pos;
        s.neg[f] = neg;
    }
    s.inner_pos = lanes8(ip);
    s.inner_neg = lanes8(in) & ~s.inner_pos;
}
// From the signs (tet_verdict and TetOuter for a certain inner sign): lanes
// surely apart, surely Containment, surely Surface.
static inline void decide8(const Sides8 &s, unsigned &apart, unsigned &contained, unsigned &surface) {
    const I8 all = I8{} + 0xF;
    const I8 positive = ((I8{} + int32_t(s.inner_pos)) & I8{1, 2, 4, 8, 16, 32, 64, 128}) != 0;
    I8 sep = I8{}, inside = all, any_out = I8{};
    for (int f = 0; f < 4; ++f) {
        const I8 out = (positive & s.neg[f]) | (~positive & s.pos[f]);
        const I8 in = (positive & s.pos[f]) | (~positive & s.neg[f]);
        sep |= out == all;
        inside &= in;
        any_out |= out;
    }
    apart = lanes8(sep);
    contained = lanes8(inside == all);
    surface = lanes8((inside != 0) & (any_out != 0));
}
// Two groups' four doubles as eight floats (group 0 in lanes 0-3).
static inline F8 join8(const V4 &g0, const V4 &g1) {
    return (F8)_mm256_set_m128(_mm256_cvtpd_ps((__m256d)g1), _mm256_cvtpd_ps((__m256d)g0));
}
#pragma GCC pop_options

#pragma GCC push_options
#pragma GCC target("avx2")
// A vertex and its squared distance to the other body's position, per lane.
struct Near4 {
    V4 d, x, y, z;
};
static inline V4 pick4(const M4 &take_b, const V4 &a, const V4 &b) {
    return (V4)_mm256_blendv_pd((__m256d)a, (__m256d)b, (__m256d)take_b);
}
static inline Near4 pick4(const M4 &take_b, const Near4 &a, const Near4 &b) {
    return Near4{pick4(take_b, a.d, b.d), pick4(take_b, a.x, b.x), pick4(take_b, a.y, b.y), pick4(take_b, a.z, b.z)};
}
// The two vertices of w nearest c (nearest in first), per lane.
static inline void nearest4(V4 (*w)[4], const V4 *c, Near4 &first, Near4 &second) {
    Near4 p[4];
    for (int v = 0; v < 4; ++v) {
        const V4 dx = w[0][v] - c[0], dy = w[1][v] - c[1], dz = w[2][v] - c[2];
        p[v] = Near4{(dx * dx + dy * dy) + dz * dz, w[0][v], w[1][v], w[2][v]};
    }
    const M4 s01 = p[1].d < p[0].d, s23 = p[3].d < p[2].d;
    const Near4 l1 = pick4(s01, p[0], p[1]), h1 = pick4(s01, p[1], p[0]);
    const Near4 l2 = pick4(s23, p[2], p[3]), h2 = pick4(s23, p[3], p[2]);
    const M4 m = l2.d < l1.d;
    first = pick4(m, l1, l2);
    const Near4 a = pick4(m, h1, l1), b = pick4(m, l2, h2);  // the second is the nearer of these
    second = pick4(b.d < a.d, a, b);
}
// Lanes whose pair an axis across an edge of each body proves apart: the
// axis of tet_edges_separate (EdgeAxis: the edge joining the two vertices of
// each body nearest the other's position), its origin the vertex of u (b
// where b_is_u, else a) that the one-pair test takes, so the same bits.
static inline unsigned edges_apart4(V4 (*wa)[4], V4 (*wb)[4], const V4 *ca, const V4 *cb, const M4 &b_is_u,
                                    const V4 &ex, const V4 &ey, const V4 &ez) {
    Near4 a0, a1, b0, b1;
    nearest4(wa, cb, a0, a1);
    nearest4(wb, ca, b0, b1);
    const V4 ax = a1.x - a0.x, ay = a1.y - a0.y, az = a1.z - a0.z;
    const V4 bx = b1.x - b0.x, by = b1.y - b0.y, bz = b1.z - b0.z;
    // (u x v is exactly -(v x u): the lanes with b as u only flip the
    // projections' signs, which the test below does not see.)
    const V4 nx = ay * bz - az * by, ny = az * bx - ax * bz, nz = ax * by - ay * bx;
    const V4 cx = pick4(b_is_u, a0.x, b0.x), cy = pick4(b_is_u, a0.y, b0.y), cz = pick4(b_is_u, a0.z, b0.z);
    V4 pa[4], pb[4];
    for (int v = 0; v < 4; ++v) {
        pa[v] = ((wa[0][v] - cx) * nx + (wa[1][v] - cy) * ny) + (wa[2][v] - cz) * nz;
        pb[v] = ((wb[0][v] - cx) * nx + (wb[1][v] - cy) * ny) + (wb[2][v] - cz) * nz;
    }
    const V4 amin = min4(min4(pa[0], pa[1]), min4(pa[2], pa[3])), amax = max4(max4(pa[0], pa[1]), max4(pa[2], pa[3]));
    const V4 bmin = min4(min4(pb[0], pb[1]), min4(pb[2], pb[3])), bmax = max4(max4(pb[0], pb[1]), max4(pb[2], pb[3]));
    const V4 margin = kEdgeMargin * ((ex * abs4(nx) + ey * abs4(ny)) + ez * abs4(nz)) + kUnderflowFloor;
    return lanes_of((bmin - amax > margin) | (amin - bmax > margin));
}
#pragma GCC pop_options

// Lane k of four-lane world vertices as rows (x, y, z), and of signs as TetSides.
inline void lane_vertices(V4 (*w)[4], int k, double (*out)[3]) {
    for (int v = 0; v < 4; ++v)
        for (int a = 0; a < 3; ++a) out[v][a] = w[a][v][k];
}
inline void lane_sides(const Sides8 &s, int k, TetSides &t) {
    for (int f = 0; f < 4; ++f) {
        t.pos[f] = unsigned(s.pos[f][k]);
        t.neg[f] = unsigned(s.neg[f][k]);
    }
    t.inner = (s.inner_pos >> k & 1) ? 1 : -1;
}

// A lane the face planes leave open, waiting for the edge axis (four of them
// at a time, gathered from all groups: tested group by group, a group with
// one open lane cost a whole four-lane test) and then the exact path.
struct OpenLane {
    double va[4][3], vb[4][3];  // world vertices
    double ca[3], cb[3];        // positions
    double ex, ey, ez;          // extents of the box holding both
    TetSides s_ab, s_ba;        // certified signs (oriented lanes)
    uint32_t pair;
    bool b_is_u, oriented;
};
struct OpenLanes {
    static constexpr int kMax = 64;
    OpenLane lane[kMax];
    int count = 0;
};

// Up to eight pairs (idx[0, count) of pairs; count >= 1) past the axis
// test, whose out[] the axis stage has set to None: writes the verdict of
// every pair the face planes decide, and hands the others to `waiting`.
// World vertices and boxes in double, four pairs a group; the face planes'
// signs in float, both groups at once (sides8).
__attribute__((target("avx2"))) void collide_tetra8(const TetraPair *pairs, const uint32_t *idx, int count,
                                                   Contact *out, NarrowScratch &scratch, OpenLanes &waiting) {
    const unsigned valid = (1u << count) - 1;
    Side4 A[2], B[2];
    V4 wa[2][3][4], wb[2][3][4], ex[2], ey[2], ez[2];
    V4 la[2][3], ha[2][3], lb[2][3], hb[2][3];
    unsigned boxed = 0, small = 0;
    V4 lo[2][3], scale[2], bound[2];
    for (int g = 0; g < 2; ++g) {
        const TetraPair *group[4];
        for (int k = 0; k < 4; ++k) group[k] = &pairs[idx[4 * g + k < count ? 4 * g + k : 0]];
        load_pairs(group, A[g], B[g]);
        world4(A[g], wa[g], la[g], ha[g]);
        world4(B[g], wb[g], lb[g], hb[g]);
        // The exact vertex boxes (the one-pair test's prefilter).
        boxed |= (~lanes_of((ha[g][0] < lb[g][0]) | (hb[g][0] < la[g][0]) | (ha[g][1] < lb[g][1]) |
                            (hb[g][1] < la[g][1]) | (ha[g][2] < lb[g][2]) | (hb[g][2] < la[g][2])) & 0xF)
                 << (4 * g);
        for (int a = 0; a < 3; ++a) lo[g][a] = min4(la[g][a], lb[g][a]);
        ex[g] = max4(ha[g][0], hb[g][0]) - lo[g][0];
        ey[g] = max4(ha[g][1], hb[g][1]) - lo[g][1];
        ez[g] = max4(ha[g][2], hb[g][2]) - lo[g][2];
        // s = 2^-(E's exponent + 1), E the largest extent: E s < 1.
        const M4 field = M4{} + (int64_t(0x7FF) << 52);
        const V4 big = max4(ex[g], max4(ey[g], ez[g]));
        scale[g] = (V4)((M4{} + (int64_t(2045) << 52)) - ((M4)big & field));
        const V4 p = ((ex[g] * scale[g]) * (ey[g] * scale[g])) * (ez[g] * scale[g]);
        small |= lanes_of(p < 0x1p-115) << (4 * g);
        bound[g] = 0x1p-15 * p;
    }
    boxed &= valid;
    if (!boxed) return;
    scratch.exact_tests += unsigned(__builtin_popcount(boxed));
    // Both groups' floats joined in registers (halves stored to memory and
    // read back whole would wait on store forwarding).
    F8 fa[3][4], fb[3][4];
    for (int a = 0; a < 3; ++a)
        for (int v = 0; v < 4; ++v) {
            fa[a][v] = join8((wa[0][a][v] - lo[0][a]) * scale[0], (wa[1][a][v] - lo[1][a]) * scale[1]);
            fb[a][v] = join8((wb[0][a][v] - lo[0][a]) * scale[0], (wb[1][a][v] - lo[1][a]) * scale[1]);
        }
    const F8 bound8 = join8(bound[0], bound[1]);
    Sides8 sab, sba;  // b's vertices against a's faces, and a's against b's
    sides8(fa, fb, bound8, sab);
    sides8(fb, fa, bound8, sba);
    unsigned apart_a, in_a, surf_a, apart_b, in_b, surf_b;
    decide8(sab, apart_a, in_a, surf_a);
    decide8(sba, apart_b, in_b, surf_b);
    const unsigned oriented = (sab.inner_pos | sab.inner_neg) & (sba.inner_pos | sba.inner_neg) & ~small;
    const unsigned apart = (apart_a | apart_b) & oriented & boxed;
    const unsigned contained = (in_a | in_b) & oriented & boxed & ~apart;
    const unsigned surface = (surf_a | surf_b) & oriented & boxed & ~apart & ~contained;
    unsigned open = boxed & ~apart & ~contained & ~surface;
    // Every lane's certified verdict, None where there is none yet (open
    // lanes are written again below): no branch on the verdicts, which are
    // random.
    static constexpr Contact kVerdict[4] = {Contact::None, Contact::Containment, Contact::Surface,
                                            Contact::Containment};
    for (int k = 0; k < count; ++k) out[idx[k]] = kVerdict[(contained >> k & 1) | (surface >> k & 1) << 1];
    for (int g = 0; g < 2; ++g) {
        unsigned left = open >> (4 * g) & 0xF;
        if (!left) continue;
        // The one-pair test's u: the body of the larger box (the same sums).
        V4 size_a, size_b;
        tet_box_size(size_a, la[g], ha[g]);
        tet_box_size(size_b, lb[g], hb[g]);
        const M4 b_is_u = size_b > size_a;
        while (left) {
            const int k = __builtin_ctz(left);
            left &= left - 1;
            const int lane = 4 * g + k;
            OpenLane &o = waiting.lane[waiting.count++];
            lane_vertices(wa[g], k, o.va);
            lane_vertices(wb[g], k, o.vb);
            for (int a = 0; a < 3; ++a) {
                o.ca[a] = A[g].c[a][k];
                o.cb[a] = B[g].c[a][k];
            }
            o.ex = ex[g][k];
            o.ey = ey[g][k];
            o.ez = ez[g][k];
            o.pair = idx[lane];
            o.b_is_u = b_is_u[k] != 0;
            o.oriented = (oriented >> lane & 1) != 0;
            if (o.oriented) {
                lane_sides(sab, lane, o.s_ab);
                lane_sides(sba, lane, o.s_ba);
            }
        }
    }
}

// The edge axis for the waiting lanes, four at a time (edges_apart4 on
// each lane's own values: the same bits), then the one-pair test's exact
// path for those it leaves, in its order (which face pairs it tries
// first); a lane whose tetrahedron's orientation or box is not certified
// takes the whole one-pair test.
__attribute__((target("avx2"))) void settle_open(const TetraPair *pairs, Contact *out, NarrowScratch &scratch,
                                                OpenLanes &waiting) {
    for (int first = 0; first < waiting.count; first += 4) {
        const OpenLane *l[4];
        for (int k = 0; k < 4; ++k) l[k] = &waiting.lane[first + k < waiting.count ? first + k : first];
        V4 wa[3][4], wb[3][4], ca[3], cb[3];
        for (int a = 0; a < 3; ++a) {
            for (int v = 0; v < 4; ++v) {
                wa[a][v] = V4{l[0]->va[v][a], l[1]->va[v][a], l[2]->va[v][a], l[3]->va[v][a]};
                wb[a][v] = V4{l[0]->vb[v][a], l[1]->vb[v][a], l[2]->vb[v][a], l[3]->vb[v][a]};
            }
            ca[a] = V4{l[0]->ca[a], l[1]->ca[a], l[2]->ca[a], l[3]->ca[a]};
            cb[a] = V4{l[0]->cb[a], l[1]->cb[a], l[2]->cb[a], l[3]->cb[a]};
        }
        const M4 b_is_u = M4{} - M4{l[0]->b_is_u, l[1]->b_is_u, l[2]->b_is_u, l[3]->b_is_u};
        const V4 ex = V4{l[0]->ex, l[1]->ex, l[2]->ex, l[3]->ex}, ey = V4{l[0]->ey, l[1]->ey, l[2]->ey, l[3]->ey},
                 ez = V4{l[0]->ez, l[1]->ez, l[2]->ez, l[3]->ez};
        const unsigned apart = edges_apart4(wa, wb, ca, cb, b_is_u, ex, ey, ez);
        const int n = std::min(4, waiting.count - first);
        for (int k = 0; k < n; ++k) {
            if (apart >> k & 1) continue;  // (out: None already)
            OpenLane &o = waiting.lane[first + k];
            if (!o.oriented) {  // a tetrahedron flat or nearly, or a tiny box: the whole one-pair test
                const TetraPair &p = pairs[o.pair];
                --scratch.exact_tests;  // (counted again there)
                out[o.pair] = collide_tetra_avx2(pose_of(p.mesh_a, *p.a), pose_of(p.mesh_b, *p.b), scratch);
                continue;
            }
            out[o.pair] = o.b_is_u ? collide_tetra_exact_aos(o.vb, o.va, o.s_ba, o.s_ab, scratch)
                                   : collide_tetra_exact_aos(o.va, o.vb, o.s_ab, o.s_ba, scratch);
        }
    }
    waiting.count = 0;
}

__attribute__((target("avx2"))) void collide_tetra_batch_avx2(const TetraPair *pairs, size_t n, Contact *out,
                                                             NarrowScratch &scratch) {
    constexpr size_t kStage = 256;  // pairs per round of the two stages
    uint32_t left[kStage];
    OpenLanes waiting;
    for (size_t begin = 0; begin < n; begin += kStage) {
        const size_t end = std::min(n, begin + kStage);
        size_t kept = 0;
        for (size_t k = begin; k < end; k += 4) {
            if (k + 20 <= n)  // (the placements four groups ahead: see world.cpp)
                for (size_t l = 0; l < 4; ++l) {
                    __builtin_prefetch(pairs[k + 16 + l].a);
                    __builtin_prefetch(pairs[k + 16 + l].b);
                }
            const TetraPair *group[4];
            for (size_t l = 0; l < 4; ++l) group[l] = &pairs[k + l < end ? k + l : k];
            Side4 A, B;
            load_pairs(group, A, B);
            const unsigned apart = axis_separated4(A, B);
            for (size_t l = 0; l < 4 && k + l < end; ++l) {
                out[k + l] = Contact::None;
                left[kept] = uint32_t(k + l);
                kept += ~apart >> l & 1;
            }
        }
        for (size_t g = 0; g < kept; g += 8) {
            collide_tetra8(pairs, left + g, int(std::min<size_t>(8, kept - g)), out, scratch, waiting);
            if (waiting.count > OpenLanes::kMax - 8) settle_open(pairs, out, scratch, waiting);
        }
        settle_open(pairs, out, scratch, waiting);
    }
}
#endif

Contact collide_tetra(const BodyPose &a, const BodyPose &b, NarrowScratch &scratch) {
#if HGCD_AVX2
    if (use_avx2()) return collide_tetra_avx2(a, b, scratch);
#endif
    return collide_tetra_v2(a, b, scratch);
}

}  // namespace

namespace {

// The direct path for small meshes other than tetrahedron pairs.
__attribute__((noinline)) Contact collide_direct(const BodyPose &a, const BodyPose &b, NarrowScratch &s,
                                                 Witness *witness) {
    double box_a[6], box_b[6];
    world_vertices(a, s.world_a, box_a);
    world_vertices(b, s.world_b, box_b);
    // Exact prefilter: the solids lie inside these boxes.
    if (boxes_disjoint(box_a, box_b)) return Contact::None;
    ++s.exact_tests;
    const Mesh &ma = *a.mesh, &mb = *b.mesh;
    const double *wa = s.world_a.data(), *wb = s.world_b.data();
    if (ma.convex && uint64_t(ma.triangle_count) * mb.vertex_count <= kFaceTestBudget &&
        separated_by_face(ma, wa, mb, wb))
        return Contact::None;
    if (mb.convex && uint64_t(mb.triangle_count) * ma.vertex_count <= kFaceTestBudget &&
        separated_by_face(mb, wb, ma, wa))
        return Contact::None;

    // Triangles of b that reach a's box, with their boxes.
    s.tri_b.clear();
    s.box_b.clear();
    for (uint32_t t = 0; t < mb.triangle_count; ++t) {
        double tb[6];
        triangle_box(wb, &mb.triangles[3 * size_t(t)], tb);
        if (boxes_disjoint(tb, box_a)) continue;
        s.tri_b.push_back(t);
        s.box_b.insert(s.box_b.end(), tb, tb + 6);
    }
    if (!s.tri_b.empty()) {
        for (uint32_t t = 0; t < ma.triangle_count; ++t) {
            const uint32_t *fa = &ma.triangles[3 * size_t(t)];
            double ta[6];
            triangle_box(wa, fa, ta);
            if (boxes_disjoint(ta, box_b)) continue;
            const double *p0 = &wa[3 * size_t(fa[0])], *p1 = &wa[3 * size_t(fa[1])],
                         *p2 = &wa[3 * size_t(fa[2])];
            for (size_t k = 0; k < s.tri_b.size(); ++k) {
                if (boxes_disjoint(ta, &s.box_b[6 * k])) continue;
                const uint32_t *fb = &mb.triangles[3 * size_t(s.tri_b[k])];
                ++s.triangle_tests;
                if (tri_tri_intersect(p0, p1, p2, &wb[3 * size_t(fb[0])], &wb[3 * size_t(fb[1])],
                                      &wb[3 * size_t(fb[2])])) {
                    if (witness) *witness = Witness{t, s.tri_b[k], false, true};
                    return Contact::Surface;
                }
            }
        }
    }
    // Surfaces disjoint: the solids meet only if one holds a component of the other.
    if (mb.closed && holds_component(mb, s.world_b, box_b, ma, s.world_a)) {
        if (witness) *witness = Witness{UINT32_MAX, UINT32_MAX, false, true};
        return Contact::Containment;
    }
    if (ma.closed && holds_component(ma, s.world_a, box_a, mb, s.world_b)) {
        if (witness) *witness = Witness{UINT32_MAX, UINT32_MAX, true, true};
        return Contact::Containment;
    }
    return Contact::None;
}

}  // namespace

void collide_tetra_batch(const TetraPair *pairs, size_t n, Contact *out, NarrowScratch &scratch) {
#if HGCD_AVX2
    if (use_avx2()) return collide_tetra_batch_avx2(pairs, n, out, scratch);
#endif
    for (size_t k = 0; k < n; ++k) {
        if (k + 8 < n) {  // (the placements of a later pair: see world.cpp)
            __builtin_prefetch(pairs[k + 8].a);
            __builtin_prefetch(pairs[k + 8].b);
        }
        const TetraPair &p = pairs[k];
        out[k] = collide_tetra(pose_of(p.mesh_a, *p.a), pose_of(p.mesh_b, *p.b), scratch);
    }
}

Contact collide(const BodyPose &a, const BodyPose &b, NarrowScratch &s, Witness *witness) {
    // (A tetrahedron has no tree; a witness asks for the general path's
    // triangle order.)
    if (a.mesh->tetra && b.mesh->tetra && !witness) return collide_tetra(a, b, s);
    if (!a.mesh->bvh.empty() || !b.mesh->bvh.empty()) return collide_tree(a, b, s, witness);
    return collide_direct(a, b, s, witness);
}

}  // namespace hgcd
