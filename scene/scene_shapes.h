/*
 * Small convex shapes for the tests and benchmarks: an axis-aligned box and
 * the icosphere of level L (the icosahedron subdivided L times, vertices on
 * the unit sphere), both closed, convex and outward. Header-only C99 (also
 * valid C++), like scene_meshes.h.
 */
#ifndef HGCD_SCENE_SHAPES_H
#define HGCD_SCENE_SHAPES_H

#include <math.h>
#include <stdint.h>
#include <string.h>

/* The box [-hx, hx] x [-hy, hy] x [-hz, hz]: 8 vertices, 12 triangles. */
static inline void hgcd_box_mesh(double hx, double hy, double hz, double v[24], uint32_t t[36]) {
    static const uint32_t faces[36] = {0, 2, 1, 0, 3, 2, 0, 1, 5, 0, 5, 4, 1, 2, 6, 1, 6, 5,
                                       2, 3, 7, 2, 7, 6, 3, 0, 4, 3, 4, 7, 4, 5, 6, 4, 6, 7};
    for (int i = 0; i < 8; ++i) {
        v[3 * i] = ((i & 1) ^ ((i >> 1) & 1)) ? hx : -hx;
        v[3 * i + 1] = (i & 2) ? hy : -hy;
        v[3 * i + 2] = (i & 4) ? hz : -hz;
    }
    memcpy(t, faces, sizeof faces);
}

/* Vertices and triangles of the icosphere of level L (L <= 4). */
static inline uint32_t hgcd_icosphere_triangle_count(int level) {
    uint32_t t = 20;
    for (int k = 0; k < level; ++k) t *= 4;
    return t;
}
static inline uint32_t hgcd_icosphere_vertex_count(int level) {
    return hgcd_icosphere_triangle_count(level) / 2 + 2;
}

/* Writes the icosphere of level L (0 <= L <= 4) into v (3 per vertex) and t
 * (3 per triangle), sized by the counts above; scratch holds
 * 5 * hgcd_icosphere_triangle_count(L) uint32_t. */
static inline void hgcd_icosphere(int level, double *v, uint32_t *t, uint32_t *scratch) {
    static const double base[12][3] = {{-1, 1.6180339887498949, 0}, {1, 1.6180339887498949, 0},
                                       {-1, -1.6180339887498949, 0}, {1, -1.6180339887498949, 0},
                                       {0, -1, 1.6180339887498949}, {0, 1, 1.6180339887498949},
                                       {0, -1, -1.6180339887498949}, {0, 1, -1.6180339887498949},
                                       {1.6180339887498949, 0, -1}, {1.6180339887498949, 0, 1},
                                       {-1.6180339887498949, 0, -1}, {-1.6180339887498949, 0, 1}};
    static const uint32_t faces[20][3] = {{0, 11, 5}, {0, 5, 1},  {0, 1, 7},   {0, 7, 10}, {0, 10, 11},
                                          {1, 5, 9},  {5, 11, 4}, {11, 10, 2}, {10, 7, 6}, {7, 1, 8},
                                          {3, 9, 4},  {3, 4, 2},  {3, 2, 6},   {3, 6, 8},  {3, 8, 9},
                                          {4, 9, 5},  {2, 4, 11}, {6, 2, 10},  {8, 6, 7},  {9, 8, 1}};
    uint32_t cv = 12, ct = 20;
    for (int i = 0; i < 12; ++i) {
        const double l = sqrt(base[i][0] * base[i][0] + base[i][1] * base[i][1] + base[i][2] * base[i][2]);
        for (int k = 0; k < 3; ++k) v[3 * i + k] = base[i][k] / l;
    }
    memcpy(t, faces, sizeof faces);
    for (int lv = 0; lv < level; ++lv) {
        /* The midpoint of each edge is made once: the edges seen so far and
         * their midpoints sit at the end of scratch (a linear search; the
         * shapes are small). */
        uint32_t *out = scratch, ne = 0;
        uint32_t *edge = scratch + 12 * (size_t)ct; /* 3 per edge: a, b, midpoint */
        for (uint32_t f = 0; f < ct; ++f) {
            uint32_t mid[3];
            for (int e = 0; e < 3; ++e) {
                uint32_t a = t[3 * f + e], b = t[3 * f + (e + 1) % 3];
                if (a > b) {
                    const uint32_t x = a;
                    a = b;
                    b = x;
                }
                uint32_t q = 0;
                while (q < ne && !(edge[3 * q] == a && edge[3 * q + 1] == b)) ++q;
                if (q == ne) {
                    double m[3], l = 0;
                    for (int k = 0; k < 3; ++k) {
                        m[k] = 0.5 * (v[3 * a + k] + v[3 * b + k]);
                        l += m[k] * m[k];
                    }
                    for (int k = 0; k < 3; ++k) v[3 * cv + k] = m[k] / sqrt(l);
                    edge[3 * ne] = a;
                    edge[3 * ne + 1] = b;
                    edge[3 * ne + 2] = cv++;
                    ++ne;
                }
                mid[e] = edge[3 * q + 2];
            }
            const uint32_t a = t[3 * f], b = t[3 * f + 1], c = t[3 * f + 2];
            const uint32_t sub[12] = {a, mid[0], mid[2], b, mid[1], mid[0], c, mid[2], mid[1], mid[0], mid[1], mid[2]};
            memcpy(&out[12 * (size_t)f], sub, sizeof sub);
        }
        ct *= 4;
        memcpy(t, out, 3 * (size_t)ct * sizeof(uint32_t));
    }
}

#endif /* HGCD_SCENE_SHAPES_H */
