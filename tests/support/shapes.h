/* The small meshes the tests build their scenes from, each chosen for a case
 * the library must get right: a convex tetrahedron and cube, a closed
 * non-convex cube, an open triangle, zero-area triangles, a mesh of two
 * components. Vertices are x, y, z triples; triangles index them, wound
 * outward where the mesh is closed. Unused tables cost nothing (static const
 * in a header draws no warning). */
#ifndef HGCD_TEST_SHAPES_H
#define HGCD_TEST_SHAPES_H

#include <stdint.h>

/* A regular tetrahedron inscribed in the cube [-1, 1]^3. */
static const double tetra_v[] = {1, 1, 1, 1, -1, -1, -1, 1, -1, -1, -1, 1};
static const uint32_t tetra_t[] = {0, 1, 2, 0, 3, 1, 0, 2, 3, 1, 3, 2};
/* The cube [-1, 1]^3. */
static const double cube_v[] = {-1, -1, -1, 1, -1, -1, 1, 1, -1, -1, 1, -1,
                                -1, -1, 1,  1, -1, 1,  1, 1, 1,  -1, 1, 1};
/* 12 outward triangles; the first 10 (all but the top, z = +1) also form a bowl. */
static const uint32_t cube_t[] = {0, 2, 1, 0, 3, 2, /* bottom */ 0, 1, 5, 0, 5, 4, /* y- */
                                  1, 2, 6, 1, 6, 5, /* x+ */ 2, 3, 7, 2, 7, 6, /* y+ */
                                  3, 0, 4, 3, 4, 7, /* x- */ 4, 5, 6, 4, 6, 7 /* top */};
/* Cube whose top is dented down to a vertex at the centre: closed, not convex. */
static const double dented_v[] = {-1, -1, -1, 1, -1, -1, 1, 1, -1, -1, 1, -1, -1, -1, 1,
                                  1,  -1, 1,  1, 1, 1,  -1, 1, 1,  0, 0, -0.25};
static const uint32_t dented_t[] = {0, 2, 1, 0, 3, 2, 0, 1, 5, 0, 5, 4, 1, 2, 6, 1, 6, 5, 2, 3, 7,
                                    2, 7, 6, 3, 0, 4, 3, 4, 7, 4, 5, 8, 5, 6, 8, 6, 7, 8, 7, 4, 8};
/* One open, tilted triangle. */
static const double triangle_v[] = {-1.5, -1, 0, 1.5, -1, 0.25, 0, 1.5, -0.25};
static const uint32_t triangle_t[] = {0, 1, 2};
/* Zero-area triangles only: a segment along x and a point. */
static const double needle_v[] = {-1.5, 0, 0, 0, 0, 0, 1.5, 0, 0, 0.5, 0.5, 0.5};
static const uint32_t needle_t[] = {0, 1, 2, 3, 3, 3};
/* Two separate tetrahedra in one closed mesh (two components). */
static const double twin_v[] = {0.5,  0.5,  0.5,  0.5,  -0.5, -0.5, -0.5, 0.5,  -0.5, -0.5, -0.5, 0.5,
                                2.5,  0.5,  0.5,  2.5,  -0.5, -0.5, 1.5,  0.5,  -0.5, 1.5,  -0.5, 0.5};
static const uint32_t twin_t[] = {0, 1, 2, 0, 3, 1, 0, 2, 3, 1, 3, 2, 4, 5, 6, 4, 7, 5, 4, 6, 7, 5, 7, 6};

#endif
