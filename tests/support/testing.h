/* Internal test surface of hgcd's exact geometry (not part of the public
 * API). These symbols are visible in the static library only; the shared
 * library exports hgcd_* alone. Plain C so the C tests can call them. */
#ifndef HGCD_TESTING_H
#define HGCD_TESTING_H

#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

/* Exact sign of det[a-d; b-d; c-d] (+1, 0, -1). */
int hgcdi_orient3d(const double *a, const double *b, const double *c,
                   const double *d);
/* Exact sign of det[a-c; b-c] in 2D. */
int hgcdi_orient2d(const double *a, const double *b, const double *c);
/* 1 if the closed triangles p (p[0..8]) and q share a point, else 0. */
int hgcdi_tri_tri(const double p[9], const double q[9]);
/* Builds the tree of a mesh (hgcd::build_bvh) on 1 thread and on `threads`
 * threads (parallel_for on OpenMP) and compares the two bit for bit (nodes,
 * node data blocks, triangle order, parents, depth): 1 if equal, 0 if not;
 * *nodes gets the node count. */
int hgcdi_bvh_same_on_threads(const double *vertices, const uint32_t *triangles, uint32_t triangle_count,
                              int threads, uint32_t *nodes);
/* hgcd::flat_hulls_meet: the hulls of a[0, na) and b[0, nb) (1 to 3
 * points each, all in the plane x_k = c) share a point. */
int hgcdi_flat_hulls_meet(int k, const double *const *a, int na, const double *const *b, int nb);
/* hgcd::tri_tri_within: the closed triangles within distance d. */
int hgcdi_tri_tri_within(const double p[9], const double q[9], double d);
/* Same through hgcd::PreparedTriangle (prepare_triangle + tri_tri). */
int hgcdi_tri_tri_prepared(const double p[9], const double q[9]);
/* 1 if the closed segment [e0, e1] meets the closed triangle t[0..8]. */
int hgcdi_segment_triangle(const double e0[3], const double e1[3],
                           const double t[9]);
/* Parity point-in-solid test for a closed mesh; the box is computed from all
 * vertex_count vertices. p must not lie on the surface. */
int hgcdi_point_in_closed_mesh(const double p[3], const double *verts,
                               uint32_t vertex_count, const uint32_t *tris,
                               uint32_t tri_count);
/* Convex closed mesh test (see geometry.hpp point_in_convex_closed_mesh). */
int hgcdi_point_in_convex(const double p[3], const double *verts,
                          const uint32_t *tris, uint32_t tri_count,
                          int inward_sign);

/* The broad phase alone (src/broad): n bodies given as 4 doubles each
 * (x, y, z, r): position (x, y, z) and offsets -r and r on every axis, each
 * rounded outward to float (the nearest float, moved one step out when it
 * falls inside), so body i's box is [x + lo, x + hi] per axis, evaluated in
 * double; each on the level its box picks (coarsened as GridLimits::coarsen
 * says when coarsen is not 0). If before is not NULL the grid is first built
 * from it, then brought to after incrementally, as a step does (a body
 * whose r changes is a new body there: sizes are fixed for a body's life,
 * as in a world). Writes every
 * reported pair (i << 32 | j, i < j), sorted, to out (room for cap); returns
 * the count (which may exceed cap), -1 on an error, or -2 when the grid
 * brought to after incrementally holds other levels, rows, oversize bodies
 * or list rows than one built from after afresh. */
int64_t hgcdi_grid_pairs(const double *before, const double *after, uint32_t n,
                         int threads, int coarsen, uint64_t *out, uint64_t cap);

/* The grid's box rounding (src/broad/float_box.hpp): body i has position
 * points[3 i .. 3 i + 2] and offsets offsets[6 i .. 6 i + 5] (low x y z,
 * high x y z). Returns how many of the first n - n % 4 bodies get other
 * float bits from the gather's four-at-a-time kernel than from the one-body
 * rounding, or -1 where that kernel does not run (no AVX2). */
int64_t hgcdi_float_boxes_check(const double *points, const float *offsets, uint32_t n);

/* A body's box offsets (src/common/transform.hpp, src/world/pose_box.hpp):
 * for each of n cases (quaternion q[4 i .. 4 i + 3], taken as it is, scale
 * s[i], and the `points` points p, 3 doubles each), offset_box and
 * record_box (the points as a mesh record, padded) against
 * offset_box_scalar, then the rounding to float (round_outward and
 * record_float_box against float_at_most and float_at_least), and
 * record_float_boxes4 four cases at a time (lanes on records of the first
 * points, points - 1, ... points: 1 at least) against record_float_box.
 * Returns how many cases differ in any bit. */
int64_t hgcdi_offset_box_check(const double *q, const double *s, uint32_t n, const double *p, uint32_t points);

/* The narrow phase's batched tetrahedron test (src/narrow/tetra.cpp,
 * collide_tetra_batch) against the one-pair test (collide) on pair_count
 * pairs: meshes holds 12 doubles per mesh (4 vertices x y z, the 4 faces
 * made of them), pair_mesh the two mesh indices of each pair, poses 16
 * doubles per pair (per body: position, quaternion x y z w, scale). counts
 * (6) receives exact_tests of the one-pair test and of the batch,
 * triangle_tests of each, the one-pair test's colliding and containment
 * pairs. Returns how many pairs got another verdict, or -1 when a mesh is
 * refused or not a tetrahedron. */
int64_t hgcdi_tetra_batch_check(const double *meshes, uint32_t mesh_count, const uint32_t *pair_mesh,
                                const double *poses, uint32_t pair_count, uint64_t *counts);

/* The contact margin's test of two tetrahedra (src/narrow/within.cpp,
 * tet::collide_tetra_within, the batch's and the one-pair path's) on
 * pair_count pairs (meshes, pair_mesh and poses as in
 * hgcdi_tetra_batch_check), pair k with margin d[k] > 0: verdict[k] = 1 when
 * the pair is reported by the one-pair test, batch[k] by the batch's
 * (collide_tetra_batch, then tet::tetra_within_apart for the pairs apart),
 * and general[k] through the general exact margin path (the touching test,
 * then the direct path's triangle pairs within d). Returns how many pairs the certificates left to the direct
 * path, or -1 when a mesh is refused or not a tetrahedron. */
int64_t hgcdi_tetra_within_check(const double *meshes, uint32_t mesh_count, const uint32_t *pair_mesh,
                                 const double *poses, const double *d, uint32_t pair_count, int *verdict,
                                 int *batch, int *general);

/* The adaptive thread policy's decisions (src/world/threads.hpp) on a
 * simulated machine, for a world set to `full` threads: detect k (k <
 * count) run on t threads takes rate[k * (full + 1) + t] seconds per unit of
 * work and its threads lose lost[k * (full + 1) + t] of their time off a
 * core. Writes the threads each detect ran on to used[k]. */
void hgcdi_thread_governor(int full, uint32_t count, const double *rate, const double *lost, int *used);

#ifdef __cplusplus
}
#endif

#endif /* HGCD_TESTING_H */
