// The exact per-body tests of the scene queries, on a body's world vertices
// (computed by the one transform of hgcd.h, so the same bits the pairs use).
// Every answer is decided with exact predicates.
#pragma once
#include <cstdint>
#include <vector>

#include "exact/geometry.hpp"
#include "narrow/narrow.hpp"
#include "world/mesh.hpp"

namespace hgcd {

// A body as the queries see it. A mesh without a tree: its world vertices
// w (3 per vertex) and their exact box. A mesh with a tree (Mesh::bvh):
// tree, the posed view whose world vertices and node boxes are computed on
// first use (w null), box a box that holds every world vertex (the root
// node's), and the scratch the view lives in.
struct SolidView {
    const Mesh *mesh;
    const double *w;
    const double *box;
    BodyView *tree = nullptr;
    NarrowScratch *scratch = nullptr;
};

// A query thread's buffers: world vertices of a mesh without a tree, the
// narrow phase's scratch (mesh queries; the tree views live in it) and the
// view of a mesh with a tree.
struct QueryScratch {
    std::vector<double> world;
    NarrowScratch narrow;
    BodyView view;
};

// p lies in the body's closed solid: on a triangle, or, for a closed mesh,
// inside it (ray parity; for a tetrahedron the signs against its faces).
bool point_in_solid(const SolidView &b, const double *p);

// The body's closed solid meets the closed box [lo, hi] (lo <= hi): a
// triangle meets the box, or a closed mesh holds the box.
bool box_meets_solid(const SolidView &b, const double *lo, const double *hi);

// The first transversal crossing of [o, e] with the body's triangles: its
// triangle (the lowest index among those crossed at the same point), its
// crossing and the triangle's world vertices (9 doubles into v), or
// UINT32_MAX. With `any`, the first crossing found.
uint32_t first_crossing(const SolidView &b, const double *o, const double *e, const double *smin,
                        const double *smax, bool any, RayCrossing *out, double *v);

}  // namespace hgcd
