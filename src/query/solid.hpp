// The exact per-body tests of the scene queries, on a body's world vertices
// (computed by the one transform of hgcd.h, so the same bits the pairs use).
// Every answer is decided with exact predicates.
#pragma once
#include <cstdint>

#include "exact/geometry.hpp"
#include "world/mesh.hpp"

namespace hgcd {

// A body as the queries see it: its mesh, world vertices (3 per vertex) and
// the exact box of those vertices (min xyz, max xyz).
struct SolidView {
    const Mesh *mesh;
    const double *w;
    const double *box;
    const double *vertex(uint32_t t, int i) const { return w + 3 * size_t(mesh->triangles[3 * size_t(t) + i]); }
};

// p lies in the body's closed solid: on a triangle, or, for a closed mesh,
// inside it (ray parity; for a tetrahedron the signs against its faces).
bool point_in_solid(const SolidView &b, const double *p);

// The body's closed solid meets the closed box [lo, hi] (lo <= hi): a
// triangle meets the box, or a closed mesh holds the box.
bool box_meets_solid(const SolidView &b, const double *lo, const double *hi);

// The first transversal crossing of [o, e] with the body's triangles: its
// triangle (the lowest index among those crossed at the same point) and
// crossing, or UINT32_MAX. With `any`, the first crossing found.
uint32_t first_crossing(const SolidView &b, const double *o, const double *e, const double *smin,
                        const double *smax, bool any, RayCrossing *out);

}  // namespace hgcd
