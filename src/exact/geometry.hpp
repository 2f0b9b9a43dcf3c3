// Exact geometric predicates and tests on world-space double coordinates:
// the orientation predicates (predicates.cpp), the triangle-triangle and
// segment-triangle tests (tri_tri.cpp) and point in mesh (point_in_mesh.cpp).
// Every function here is exact: it decides with orientation predicates whose
// sign is computed exactly (floating-point filter, exact fallback), never with
// a tolerance.
#pragma once
#include <algorithm>
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

// True if the hulls of the points a[0, na) and b[0, nb) (na, nb in 1..3:
// a point, a segment, a triangle, degenerate or not) share a point, all of
// them lying in one plane x_k = c (so that dropping axis k, as
// orient2d_proj does, maps that plane one to one). Exact.
bool flat_hulls_meet(int k, const double *const *a, int na, const double *const *b, int nb);

// True if the closed triangles (p0,p1,p2) and (q0,q1,q2) are within
// Euclidean distance d of each other (some point of one and some point of
// the other at most d apart; d = 0: tri_tri_intersect). Degenerate triangles
// count as the segment or point they are. Exact (distance.cpp) for
// coordinates and d below 2^52 in magnitude, d >= 0.
bool tri_tri_within(const double *p0, const double *p1, const double *p2, const double *q0,
                    const double *q1, const double *q2, double d);

// True if the hulls of the points a[0, na) and b[0, nb) (1: a point, 2: a
// segment, 3: a triangle, each as the closed set it is, degenerate or not)
// are within Euclidean distance d > 0. Exact, with the same signs as
// tri_tri_within, but for a vertex-vertex, vertex-segment, vertex-triangle or
// segment-segment pair it evaluates only that pair's tests (the certificate
// of a closest feature pair found in floating point).
bool features_within(const double *const *a, int na, const double *const *b, int nb, double d);

// A triangle with its exact box, and its plane filter data computed on
// first use, for callers that test one triangle against several others (a
// tree's leaf against another's: most pairs are told apart by one plane, so
// the other is never needed). The vertex pointers must stay valid while it
// is used.
struct PreparedTriangle {
    const double *v[3];
    double box[6];  // exact bounding box: low x y z, high x y z
    double n[3];    // rounded normal (v1-v0) x (v2-v0), filter use only
    double an[3];   // filter permanents of n's components
    bool planed;    // n and an computed
};

// (Inline: a leaf pair prepares several, each a few instructions.)
inline void prepare_triangle(PreparedTriangle &t, const double *v0, const double *v1, const double *v2) {
    t.v[0] = v0;
    t.v[1] = v1;
    t.v[2] = v2;
    for (int k = 0; k < 3; ++k) {
        t.box[k] = std::min(std::min(v0[k], v1[k]), v2[k]);
        t.box[3 + k] = std::max(std::max(v0[k], v1[k]), v2[k]);
    }
    t.planed = false;
}

// Same answer as tri_tri_intersect on the triangles' vertices (the planes
// computed on first use). Its box filter is left to the caller, who has
// the boxes: the plane tests decide alone.
bool tri_tri_intersect(PreparedTriangle &p, PreparedTriangle &q);

// Same answer as tri_tri_intersect(p[0], p[1], p[2], q[0], q[1], q[2]), for
// callers that already hold the exact signs sp[i] = orient3d(q0, q1, q2, p_i)
// and sq[i] = orient3d(p0, p1, p2, q_i) (e.g. shared by the faces of two
// tetrahedra). The signs must be exact and in this vertex order.
bool tri_tri_intersect_signed(const double *const *p, const double *const *q,
                              const int *sp, const int *sq);

// Parity test: true if p lies inside the solid bounded by the closed mesh
// (every edge shared by an even number of triangles). Precondition: p is not
// on the mesh surface (the caller has shown the surfaces disjoint). verts are
// world-space xyz triples, tris index triples; box_min/box_max bound verts.
bool point_in_closed_mesh(const double *p, const double *verts,
                          const uint32_t *tris, uint32_t tri_count,
                          const double *box_min, const double *box_max);

// Mesh-solid test for a closed convex mesh: every vertex lies on the side of
// each face plane whose orient3d(face, vertex) sign is inward_sign (or on the
// plane). Precondition: p is not on the surface. True if p is inside, i.e. for
// every face orient3d(face, p) is inward_sign or 0 (zero-area faces give 0
// and so never exclude p).
bool point_in_convex_closed_mesh(const double *p, const double *verts,
                                 const uint32_t *tris, uint32_t tri_count,
                                 int inward_sign);

// True if the closed segment [e0, e1] (possibly a single point) meets the
// closed triangle (t0, t1, t2) (possibly degenerate). Exact.
bool segment_triangle_intersect(const double *e0, const double *e1,
                                const double *t0, const double *t1,
                                const double *t2);

// True if a, b, c are collinear (zero-area triangle, including coincident
// points). Exact.
bool collinear3d(const double *a, const double *b, const double *c);

// A transversal crossing of the closed segment [o, e] with a triangle
// (crossing.cpp): the magnitudes of A = orient3d(t, o) and E = orient3d(t,
// e) in double with bounds on their errors, and which of them is exactly 0.
// Its parameter along [o, e] is |A| / (|A| + |E|).
struct RayCrossing {
    double a, b;    // |A~|, |E~|
    double ea, eb;  // |a - |A|| <= ea, |b - |E|| <= eb
    bool a_zero, b_zero;  // A = 0 (o on the plane: t = 0), E = 0 (t = 1)
};

// True, filling *c, when [o, e] crosses the plane of the triangle v
// transversally (o and e not strictly on one side, not both in it) at a
// point of the closed triangle. A segment in the plane of the triangle
// (grazing along it) and zero-area triangles never cross. Exact.
bool segment_crosses(const double *o, const double *e, const double *const *v, RayCrossing *c);

// Sign of t1 - t2 for two crossings of [o, e] with triangles v1 and v2: the
// order of the two points along the segment, exact (0: the same point).
int compare_crossings(const double *o, const double *e, const double *const *v1, const RayCrossing &c1,
                      const double *const *v2, const RayCrossing &c2);

// Bounds on a crossing's parameter t: crossing_lower <= t <= crossing_upper.
double crossing_lower(const RayCrossing &c);
double crossing_upper(const RayCrossing &c);

// The crossing's parameter t in [0, 1], with relative error below 2^-41
// (exact ends 0 and 1 exactly).
double crossing_parameter(const double *o, const double *e, const double *const *v, const RayCrossing &c);

}  // namespace hgcd
