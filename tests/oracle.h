/* Independent brute-force reference for hgcd's exact geometry, in plain C99
 * with GMP rationals. Shares no code with src/: it uses different
 * formulations (exact rational intersection points and barycentric signs
 * instead of orientation-only tests) so that both must agree by mathematics,
 * not by construction. Slow but exact; single-threaded (no global state is
 * kept, but it is only meant for tests). */
#ifndef HGCD_TESTS_ORACLE_H
#define HGCD_TESTS_ORACLE_H

#include <stddef.h>
#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

/* Exact sign of det[a-d; b-d; c-d]: +1, 0, -1. */
int oracle_orient3d(const double a[3], const double b[3], const double c[3],
                    const double d[3]);
/* Exact sign of det[a-c; b-c] (2D). */
int oracle_orient2d(const double a[2], const double b[2], const double c[2]);

/* 1 if the closed segment [a, b] (possibly a point) meets the closed triangle
 * t[0..8] (possibly degenerate), else 0. */
int oracle_segment_triangle(const double a[3], const double b[3],
                            const double t[9]);

/* 1 if the closed triangles p[0..8] and q[0..8] share a point. Degenerate
 * triangles count as the segment or point they are. */
int oracle_tri_tri(const double p[9], const double q[9]);

/* Exact parity point-in-solid test: 1 inside, 0 outside, -1 if p lies on the
 * surface or every one of the oracle's 64 ray directions was degenerate. The
 * mesh should be closed; the box is taken over all vertex_count vertices. */
int oracle_point_in_closed_mesh(const double p[3], const double *verts,
                                uint32_t vertex_count, const uint32_t *tris,
                                uint32_t tri_count);

/* 1 if every undirected edge {u, v}, u != v, is used by an even number of
 * triangles and there is at least one such edge. Self-edges {u, u} of
 * index-degenerate triangles are ignored (they bound nothing). */
int oracle_mesh_is_closed(const uint32_t *tris, uint32_t tri_count);

typedef struct {
    const double *verts;   /* 3 per vertex, mesh frame */
    const uint32_t *tris;  /* 3 per triangle */
    uint32_t vertex_count, triangle_count;
    /* Ignored: the oracle works closedness out itself with
     * oracle_mesh_is_closed (so a wrong field cannot mask a library bug). */
    int closed;
} oracle_mesh;

/* All colliding body pairs (i < j), as hgcd.h defines a collision: the
 * closed solids share a point (surfaces intersect, or one closed mesh holds
 * a component of the other). World vertices use exactly hgcd.h's formula,
 * evaluated without fused multiply-add. Writes up to out_capacity pairs
 * (2 uint32 each, sorted by (i, j)) and returns the total count. Aborts with
 * a message if memory runs out or a containment ray test is undecidable. */
size_t oracle_colliding_pairs(size_t body_count,
                              const oracle_mesh *const *body_mesh,
                              const double *positions,
                              const double *orientations,
                              const double *scales, uint32_t *out_pairs,
                              size_t out_capacity);

/* Number of the pairs of the last oracle_colliding_pairs call that collide
 * only by containment (no triangle pair meets). */
size_t oracle_last_containment_pairs(void);

/* World vertex of mesh vertex m for a body, exactly as hgcd.h specifies. */
void oracle_world_vertex(const double position[3], const double orientation[4],
                         double scale, const double m[3], double out[3]);


/* Contact margin (oracle_distance.c). 1 if the closed triangles p and q
 * (possibly degenerate) are within Euclidean distance d >= 0, exactly: their
 * exact squared distance, a rational, is at most d^2. */
int oracle_tri_tri_within(const double p[9], const double q[9], double d);

/* A pair's margin as hgcd.h defines it: world_margin + (margin_a + margin_b),
 * each addition rounded to double. */
double oracle_pair_margin(double world_margin, double margin_a, double margin_b);

/* All body pairs (i < j) within their margin d = oracle_pair_margin(
 * world_margin, margins[i], margins[j]) (margins NULL: all 0): some
 * triangle pair within d, or the bodies collide (oracle_colliding_pairs:
 * containment). Pairs sorted, as oracle_colliding_pairs. Brute force over
 * every pair of bodies and triangles: small scenes only. */
size_t oracle_pairs_within(size_t body_count, const oracle_mesh *const *body_mesh, const double *positions,
                           const double *orientations, const double *scales, double world_margin,
                           const double *margins, uint32_t *out_pairs, size_t out_capacity);

#ifdef __cplusplus
}
#endif

#endif /* HGCD_TESTS_ORACLE_H */
