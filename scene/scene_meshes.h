/*
 * Scene `meshes` (docs/scenes.md): the blob mesh, bit for bit.
 * Header-only C99 (also valid C++), shared by bench/bench_meshes.cpp,
 * examples/load_meshes.cpp and tests/test_bvh.c. Poses come from
 * hgcd_scene_tetra_generate (the `tetra` draws), with body scale = radius.
 */
#ifndef HGCD_BENCH_SCENE_MESHES_H
#define HGCD_BENCH_SCENE_MESHES_H

#include <math.h>
#include <stdint.h>

/* Default resolution: 48 longitudes, 32 latitude bands: 1490 vertices,
 * 2976 triangles. */
enum { HGCD_BLOB_NU = 48, HGCD_BLOB_NV = 32 };

static inline uint32_t hgcd_blob_vertex_count(uint32_t nu, uint32_t nv) {
    return 2 + nu * (nv - 1);
}
static inline uint32_t hgcd_blob_triangle_count(uint32_t nu, uint32_t nv) {
    return 2 * nu * (nv - 1);
}

/* Radius of the blob in direction (theta, phi): star-shaped (between 0.55
 * and 1.45), equal to 1 at the poles, with dents deep enough that the mesh is
 * far from convex. */
static inline double hgcd_blob_radius(double theta, double phi) {
    return 1.0 + 0.3 * sin(3.0 * theta) * cos(4.0 * phi) +
           0.15 * sin(6.0 * theta) * sin(7.0 * phi);
}

/* Vertices: 0 = north pole (0, 0, 1), then for j = 1 .. nv-1 (theta =
 * (M_PI * j) / nv) and i = 0 .. nu-1 (phi = (2 * M_PI * i) / nu) the vertex
 * 1 + (j-1) * nu + i at rho * (sin(theta) cos(phi), sin(theta) sin(phi),
 * cos(theta)) with rho = hgcd_blob_radius(theta, phi) (each product evaluated
 * left to right), and last the south pole (0, 0, -1). Triangles are
 * counter-clockwise seen from outside: the north cap (0, a, b), bands
 * (a, c, d) and (a, d, b) for the quad a = (j, i), b = (j, i+1),
 * c = (j+1, i), d = (j+1, i+1) (i+1 taken mod nu), the south cap
 * (a, south, b). nu >= 3, nv >= 2. */
static inline void hgcd_blob_mesh(uint32_t nu, uint32_t nv, double *verts, uint32_t *tris) {
    const double pi = 3.14159265358979323846;
    uint32_t i, j, t = 0;
    const uint32_t south = 1 + nu * (nv - 1);
    verts[0] = 0.0;
    verts[1] = 0.0;
    verts[2] = 1.0;
    for (j = 1; j < nv; ++j) {
        const double theta = (pi * (double)j) / (double)nv;
        for (i = 0; i < nu; ++i) {
            const double phi = (2.0 * pi * (double)i) / (double)nu;
            const double rho = hgcd_blob_radius(theta, phi);
            double *v = verts + 3 * (1 + (j - 1) * nu + i);
            v[0] = rho * sin(theta) * cos(phi);
            v[1] = rho * sin(theta) * sin(phi);
            v[2] = rho * cos(theta);
        }
    }
    verts[3 * south] = 0.0;
    verts[3 * south + 1] = 0.0;
    verts[3 * south + 2] = -1.0;
    for (i = 0; i < nu; ++i) {
        const uint32_t a = 1 + i, b = 1 + (i + 1) % nu;
        tris[t++] = 0, tris[t++] = a, tris[t++] = b;
    }
    for (j = 1; j + 1 < nv; ++j) {
        for (i = 0; i < nu; ++i) {
            const uint32_t a = 1 + (j - 1) * nu + i, b = 1 + (j - 1) * nu + (i + 1) % nu;
            const uint32_t c = a + nu, d = b + nu;
            tris[t++] = a, tris[t++] = c, tris[t++] = d;
            tris[t++] = a, tris[t++] = d, tris[t++] = b;
        }
    }
    for (i = 0; i < nu; ++i) {
        const uint32_t a = 1 + (nv - 2) * nu + i, b = 1 + (nv - 2) * nu + (i + 1) % nu;
        tris[t++] = a, tris[t++] = south, tris[t++] = b;
    }
}

#endif /* HGCD_BENCH_SCENE_MESHES_H */
