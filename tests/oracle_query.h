/* Brute-force references for the scene queries, in GMP rationals (plain C99),
 * beside tests/oracle.h: one body at a time, every triangle. Formulations
 * differ from src/query and src/exact: the rational crossing point of the
 * segment with the triangle's plane and its barycentric signs for rays, and
 * Sutherland-Hodgman clipping of each triangle by the box's six closed
 * half-spaces for boxes. */
#ifndef HGCD_TESTS_ORACLE_QUERY_H
#define HGCD_TESTS_ORACLE_QUERY_H

#include <stdint.h>

/* 1 if the segment [o, e] crosses the plane of triangle t[0..8]
 * transversally (o and e not strictly on one side, not both in the plane)
 * at a point of the closed triangle; then *t_out (if not NULL) is its
 * parameter in [0, 1], the exact rational rounded to double. */
int oracle_ray_crossing(const double o[3], const double e[3], const double t[9], double *t_out);

/* Sign of t1 - t2 for two crossings of [o, e] (both must cross). */
int oracle_crossing_compare(const double o[3], const double e[3], const double t1[9], const double t2[9]);

/* 1 if p lies in the closed solid of the mesh (world vertices wv): on a
 * triangle, or inside when the mesh is closed (oracle_mesh_is_closed). */
int oracle_point_in_solid(const double p[3], const double *wv, uint32_t vertex_count, const uint32_t *tris,
                          uint32_t tri_count);

/* 1 if the closed triangle t[0..8] meets the closed box [lo, hi]. */
int oracle_triangle_box(const double lo[3], const double hi[3], const double t[9]);

/* 1 if the mesh's closed solid meets the closed box. */
int oracle_box_meets_solid(const double lo[3], const double hi[3], const double *wv, uint32_t vertex_count,
                           const uint32_t *tris, uint32_t tri_count);

/* A body for oracle_ray_closest: world vertices and triangles. */
typedef struct {
    const double *wv;
    uint32_t vertex_count;
    const uint32_t *tris;
    uint32_t tri_count;
} oracle_solid;

/* The closest hit of [o, e] over the bodies, as hgcd.h defines it: body k
 * hit at t = 0 (inside) when o lies in its closed mesh, else at its first
 * transversal crossing; the least (t, body, triangle). Returns 1 and fills
 * *body, *tri (UINT32_MAX when inside), *inside, *t when there is a hit. */
int oracle_ray_closest(const double o[3], const double e[3], const oracle_solid *bodies, uint32_t count,
                       uint32_t *body, uint32_t *tri, int *inside, double *t);

#endif
