// Exact geometric predicates and tests on world-space double coordinates.
// Every function here is exact: it decides with orientation predicates whose
// sign is computed exactly (floating-point filter, exact fallback), never with
// a tolerance.
#pragma once
#include <cstdint>

namespace hgcd {

// Sign of det[a-d; b-d; c-d]: +1, 0 or -1, exact. Positive when d lies below
// the plane through a, b, c (a, b, c counter-clockwise seen from above).
int orient3d(const double *a, const double *b, const double *c, const double *d);

// Sign of det[a-c; b-c] in 2D: +1 when a, b, c turn counter-clockwise. Exact.
int orient2d(const double *a, const double *b, const double *c);

// True if the closed triangles (p0,p1,p2) and (q0,q1,q2) share a point.
// Degenerate (zero-area) triangles count as the segment or point they are.
bool tri_tri_intersect(const double *p0, const double *p1, const double *p2,
                       const double *q0, const double *q1, const double *q2);

// Parity test: true if p lies inside the solid bounded by the closed mesh
// (every edge shared by an even number of triangles). Precondition: p is not
// on the mesh surface (the caller has shown the surfaces disjoint). verts are
// world-space xyz triples, tris index triples; box_min/box_max bound verts.
bool point_in_closed_mesh(const double *p, const double *verts,
                          const uint32_t *tris, uint32_t tri_count,
                          const double *box_min, const double *box_max);

}  // namespace hgcd
