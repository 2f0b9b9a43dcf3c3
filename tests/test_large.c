/* Large meshes in motion against the brute-force oracle of tests/oracle.c:
 * the tree nodes' fitted (oriented) boxes, which must hold every rounded
 * world vertex under them;
 * the broad phase's box of a mesh above 128 triangles (the union of the
 * rotated boxes of a few tree nodes, where tighter than its bounding
 * sphere's), which must never miss a pair, and the first-tried witness (the
 * subtrees where a pair's surfaces met at its last detect, searched first),
 * which must never change a verdict. Elongated meshes (a blob stretched 5x,
 * where the node boxes are far tighter than the sphere's) at many
 * orientations, touching to the last bit; a moving cluster of elongated and
 * round meshes, boxes and a body 50x the others' size, tick after tick, on
 * 1 and 2 threads, contacts off (where the witness is used). */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#include <hgcd/hgcd.h>

#include "../scene/scene_meshes.h"
#include "../scene/scene_shapes.h"
#include "oracle.h"
#include "test_rng.h"

enum { M_LONG, M_ROUND, M_BOX, M_PLATE, M_LENS, M_COUNT };
static struct {
    double *v;
    uint32_t *t;
    uint32_t nv, nt;
} meshes[M_COUNT];
static oracle_mesh omesh[M_COUNT];

static void blob(int k, uint32_t nu, uint32_t nv, double stretch) {
    meshes[k].nv = hgcd_blob_vertex_count(nu, nv);
    meshes[k].nt = hgcd_blob_triangle_count(nu, nv);
    meshes[k].v = malloc(3 * (size_t)meshes[k].nv * sizeof(double));
    meshes[k].t = malloc(3 * (size_t)meshes[k].nt * sizeof(uint32_t));
    assert_non_null(meshes[k].v);
    assert_non_null(meshes[k].t);
    hgcd_blob_mesh(nu, nv, meshes[k].v, meshes[k].t);
    for (uint32_t i = 0; i < meshes[k].nv; ++i) meshes[k].v[3 * i] *= stretch;
}

/* The rotation of quaternion (1, 2, 2, 4) / 5, applied to a mesh vertex in
 * its own frame (its z axis goes to (0.8, 0, 0.6)). */
static void turn_in_frame(double *v) {
    const double x = v[0], y = v[1], z = v[2];
    v[0] = 0.36 * x - 0.48 * y + 0.8 * z;
    v[1] = 0.8 * x + 0.6 * y;
    v[2] = -0.48 * x + 0.64 * y + 0.6 * z;
}

static int setup(void **state) {
    (void)state;
    blob(M_LONG, 16, 10, 5.0);  /* 288 triangles, 10 x 2.9 x 2.9 */
    blob(M_ROUND, 20, 14, 1.0); /* 520 */
    meshes[M_BOX].nv = 8;
    meshes[M_BOX].nt = 12;
    meshes[M_BOX].v = malloc(24 * sizeof(double));
    meshes[M_BOX].t = malloc(36 * sizeof(uint32_t));
    hgcd_box_mesh(1, 0.5, 0.25, meshes[M_BOX].v, meshes[M_BOX].t);
    /* A plate 6 x 6 x 0.2 (480 triangles), turned in its own mesh frame
     * about a skew axis: its tree's mesh-frame boxes are loose, the fitted
     * boxes of its flat patches thin, so near contact they decide. */
    blob(M_PLATE, 24, 11, 3.0);
    for (uint32_t i = 0; i < meshes[M_PLATE].nv; ++i) {
        double *v = &meshes[M_PLATE].v[3 * i];
        v[1] *= 3.0;
        v[2] *= 0.1;
        turn_in_frame(v);
    }
    /* A smooth lens 6 x 4 x 0.8 (16 x 12 bands, 352 triangles), turned the
     * same way: symmetric, so the fitted boxes of its root and caps have a
     * face through each pole. */
    blob(M_LENS, 16, 12, 1.0);
    for (uint32_t i = 0; i < meshes[M_LENS].nv; ++i) {
        double *v = &meshes[M_LENS].v[3 * i];
        const uint32_t j = i == 0 ? 0 : i == meshes[M_LENS].nv - 1 ? 12 : 1 + (i - 1) / 16, k = i == 0 ? 0 : (i - 1) % 16;
        const double theta = (3.14159265358979323846 * j) / 12, phi = (2 * 3.14159265358979323846 * k) / 16;
        v[0] = 3.0 * sin(theta) * cos(phi);
        v[1] = 2.0 * sin(theta) * sin(phi);
        v[2] = 0.4 * cos(theta);
        turn_in_frame(v);
    }
    for (int k = 0; k < M_COUNT; ++k) {
        omesh[k].verts = meshes[k].v;
        omesh[k].tris = meshes[k].t;
        omesh[k].vertex_count = meshes[k].nv;
        omesh[k].triangle_count = meshes[k].nt;
        omesh[k].closed = 1;
    }
    return 0;
}

static int teardown(void **state) {
    (void)state;
    for (int k = 0; k < M_COUNT; ++k) {
        free(meshes[k].v);
        free(meshes[k].t);
    }
    return 0;
}

enum { CAP = 24 };
typedef struct {
    hgcd_world *w;
    hgcd_mesh mesh[M_COUNT];
    size_t n;
    int kind[CAP];
    hgcd_body id[CAP];
    double pos[3 * CAP], quat[4 * CAP], scale[CAP];
} scene;

static void scene_init(scene *sc, uint32_t threads) {
    memset(sc, 0, sizeof *sc);
    hgcd_world_desc wd = hgcd_world_desc_default();
    wd.thread_count = threads;
    assert_int_equal(hgcd_world_create(&wd, &sc->w), HGCD_OK);
    for (int k = 0; k < M_COUNT; ++k) {
        hgcd_mesh_desc md = hgcd_mesh_desc_default();
        md.vertices = meshes[k].v;
        md.triangles = meshes[k].t;
        md.vertex_count = meshes[k].nv;
        md.triangle_count = meshes[k].nt;
        assert_int_equal(hgcd_mesh_create(sc->w, &md, &sc->mesh[k]), HGCD_OK);
    }
}

static void add(scene *sc, int kind, const double *p, const double *q, double scale) {
    assert_true(sc->n < CAP);
    hgcd_body_desc bd = hgcd_body_desc_default();
    bd.mesh = sc->mesh[kind];
    memcpy(bd.position, p, sizeof bd.position);
    memcpy(bd.orientation, q, sizeof bd.orientation);
    bd.scale = scale;
    const size_t i = sc->n++;
    assert_int_equal(hgcd_body_create(sc->w, &bd, &sc->id[i]), HGCD_OK);
    sc->kind[i] = kind;
    memcpy(&sc->pos[3 * i], p, 3 * sizeof(double));
    memcpy(&sc->quat[4 * i], q, 4 * sizeof(double));
    sc->scale[i] = scale;
}

static void set_pose(scene *sc, size_t i, const double *p, const double *q) {
    assert_int_equal(hgcd_body_set_pose(sc->w, sc->id[i], p, q), HGCD_OK);
    memcpy(&sc->pos[3 * i], p, 3 * sizeof(double));
    memcpy(&sc->quat[4 * i], q, 4 * sizeof(double));
}

/* Detects and compares with the oracle pair for pair; returns the count. */
static size_t check(scene *sc) {
    assert_int_equal(hgcd_world_detect(sc->w), HGCD_OK);
    const oracle_mesh *bm[CAP];
    for (size_t i = 0; i < sc->n; ++i) bm[i] = &omesh[sc->kind[i]];
    uint32_t expect[CAP * CAP];
    const size_t n = oracle_colliding_pairs(sc->n, bm, sc->pos, sc->quat, sc->scale, expect, CAP * CAP / 2);
    const hgcd_pair *got;
    size_t count;
    assert_int_equal(hgcd_world_pairs(sc->w, &got, &count), HGCD_OK);
    size_t bad = 0;
    for (size_t k = 0; k < n || k < count; ++k)
        if (k >= n || k >= count || got[k].a.index != expect[2 * k] || got[k].b.index != expect[2 * k + 1])
            if (bad++ < 5)
                fprintf(stderr, "pair %zu: hgcd (%u, %u), oracle (%u, %u)\n", k, k < count ? got[k].a.index : 0,
                        k < count ? got[k].b.index : 0, k < n ? expect[2 * k] : 0, k < n ? expect[2 * k + 1] : 0);
    assert_int_equal(bad, 0);
    assert_int_equal(count, n);
    return n;
}

static int colliding(scene *sc) {
    assert_int_equal(hgcd_world_detect(sc->w), HGCD_OK);
    const hgcd_pair *p;
    size_t count;
    assert_int_equal(hgcd_world_pairs(sc->w, &p, &count), HGCD_OK);
    return count == 1;
}

/* q * (h a, 1), normalised: a turn of about 2h about the unit axis a. */
static void turn(double *q, const double *a, double h) {
    const double r[4] = {h * a[0], h * a[1], h * a[2], 1};
    const double x = q[3] * r[0] + q[0] * r[3] + q[1] * r[2] - q[2] * r[1];
    const double y = q[3] * r[1] - q[0] * r[2] + q[1] * r[3] + q[2] * r[0];
    const double z = q[3] * r[2] + q[0] * r[1] - q[1] * r[0] + q[2] * r[3];
    const double w = q[3] * r[3] - q[0] * r[0] - q[1] * r[1] - q[2] * r[2];
    const double n = sqrt(x * x + y * y + z * z + w * w);
    q[0] = x / n, q[1] = y / n, q[2] = z / n, q[3] = w / n;
}

/* Body b moved from a's position o along the unit direction u, by
 * bisection until the two positions differ in the last bit: touching at one
 * (the oracle agrees: no box of either may be too tight there) and apart at
 * the other. Every bisection step is a detect after a pose change, each with
 * the witness of the one before; both ends are checked with it and from
 * afar (without it). */
static void touch_scaled(int kind_a, const double *qa, double sa, int kind_b, const double *qb, double sb,
                         const double *o, const double *u, double far) {
    scene sc;
    scene_init(&sc, 1);
    add(&sc, kind_a, o, qa, sa);
    double lo = 0, hi = far, pb[3];
    for (int k = 0; k < 3; ++k) pb[k] = o[k] + far * u[k];
    add(&sc, kind_b, pb, qb, sb);
    assert_int_equal(colliding(&sc), 0);
    for (int it = 0; it < 90 && hi - lo > 0; ++it) {
        const double mid = 0.5 * lo + 0.5 * hi;
        if (mid <= lo || mid >= hi) break;
        for (int k = 0; k < 3; ++k) pb[k] = o[k] + mid * u[k];
        set_pose(&sc, 1, pb, qb);
        if (colliding(&sc)) lo = mid;
        else hi = mid;
    }
    for (int k = 0; k < 3; ++k) pb[k] = o[k] + lo * u[k];
    set_pose(&sc, 1, pb, qb);
    assert_int_equal(check(&sc), 1);
    for (int k = 0; k < 3; ++k) pb[k] = o[k] + hi * u[k];
    set_pose(&sc, 1, pb, qb);
    assert_int_equal(check(&sc), 0);
    /* Again from afar, each: the whole trees searched, not the subtrees
     * where the surfaces met at the detect before. */
    for (int side = 0; side < 2; ++side) {
        for (int k = 0; k < 3; ++k) pb[k] = o[k] + far * u[k];
        set_pose(&sc, 1, pb, qb);
        assert_int_equal(colliding(&sc), 0);
        for (int k = 0; k < 3; ++k) pb[k] = o[k] + (side ? lo : hi) * u[k];
        set_pose(&sc, 1, pb, qb);
        assert_int_equal(check(&sc), side);
    }
    hgcd_world_destroy(sc.w);
}

static void touch_by_bisection(int kind_a, const double *qa, double sa, int kind_b, const double *qb, const double *u,
                               double far) {
    const double o[3] = {0.25, -0.5, 1.0};
    touch_scaled(kind_a, qa, sa, kind_b, qb, 1.0, o, u, far);
}

static void random_direction(rng *r, double *u) {
    const double z = 2 * unif(r) - 1, phi = 6.283185307179586 * unif(r);
    u[0] = sqrt(1 - z * z) * cos(phi);
    u[1] = sqrt(1 - z * z) * sin(phi);
    u[2] = z;
}

/* Two elongated meshes at 24 pairs of orientations, random or axis-aligned
 * (and sizes 1 and 7), touching to the last bit. */
static void test_elongated_touching(void **state) {
    (void)state;
    rng r = {7};
    for (int rep = 0; rep < 24; ++rep) {
        double qa[4], qb[4], u[3];
        random_unit_quaternion(&r, qa);
        random_unit_quaternion(&r, qb);
        random_direction(&r, u);
        if (rep % 3 == 0) {
            /* Axis-aligned (rotation entries exactly 0 and +-1) and along an
             * axis: the node boxes' faces then touch the extreme vertices,
             * and the broad-phase box has no slack but its float rounding. */
            static const double aligned[4][4] = {{0, 0, 0, 1}, {1, 0, 0, 0}, {0, 1, 0, 0}, {0, 0, 1, 0}};
            memcpy(qa, aligned[(rep / 3) % 4], sizeof qa);
            memcpy(qb, aligned[(rep / 3 + 1) % 4], sizeof qb);
            u[0] = u[1] = u[2] = 0;
            u[(rep / 3) % 3] = rep % 2 ? -1 : 1;
        }
        const double sa = rep % 4 == 3 ? 7.0 : 1.0;
        touch_by_bisection(M_LONG, qa, sa, rep % 2 ? M_LONG : M_ROUND, qb, u, 8 * (sa + 1));
    }
}

/* Two plates face to face, parallel or turned a little, one moved along the
 * other's normal (tilted a little, or along a random direction) to touching
 * at the last bit, where the fitted boxes of their thin patches decide; and
 * two lenses pole to pole along their common normal (or tilted a little):
 * vertex on vertex, the poles on faces of the fitted boxes (root, caps)
 * along the approach. */
static void test_fitted_touching(void **state) {
    (void)state;
    rng r = {23};
    const double nm[3] = {0.8, 0, 0.6}; /* the meshes' z axis, turned */
    for (int rep = 0; rep < 24; ++rep) {
        const int lens = rep % 3 == 0;
        double qa[4], qb[4], u[3];
        random_unit_quaternion(&r, qa);
        memcpy(qb, qa, sizeof qb);
        if (rep % 2 && !lens) {
            double ax[3];
            random_direction(&r, ax);
            turn(qb, ax, 0.01 * (rep % 4));
        }
        /* u = R(qa) nm, plus a small random tilt; some at random. */
        const double x = qa[0], y = qa[1], z = qa[2], w = qa[3];
        const double m[9] = {1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w),
                             2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w),
                             2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)};
        double t[3];
        random_direction(&r, t);
        const double tilt = lens ? (rep % 2 ? 0.05 : 0) : rep % 4 == 3 ? 1.0 : 0.05 * (rep % 3);
        double len = 0;
        for (int k = 0; k < 3; ++k) {
            u[k] = (m[3 * k] * nm[0] + m[3 * k + 1] * nm[1]) + m[3 * k + 2] * nm[2] + tilt * t[k];
            len += u[k] * u[k];
        }
        for (int k = 0; k < 3; ++k) u[k] /= sqrt(len);
        const int kind = lens ? M_LENS : M_PLATE;
        touch_by_bisection(kind, qa, 1.0, kind, qb, u, 24.0);
    }
}

/* The node tests run in one mesh's frame, with rounding margins that grow
 * with the positions, the ratio of the scales and the quaternions' distance
 * from unit length: pairs far from the origin, of unequal scales, with
 * quaternions of squared norm 1 +- 9e-7 (accepted as given), touching to the
 * last bit: plates and elongated meshes parallel or not along random
 * directions, plates face to face, lenses pole to pole. */
static void test_frame_touching(void **state) {
    (void)state;
    rng r = {41};
    static const int kinds[4][2] = {{M_PLATE, M_PLATE}, {M_LONG, M_LONG}, {M_LENS, M_LENS}, {M_LONG, M_ROUND}};
    static const double scales[4][2] = {{1, 1}, {7, 1}, {0.25, 3}, {1, 0.5}};
    /* Reps 32..63 again with unit quaternions far from the origin: there
     * the matrices' deviation from a rotation no longer swamps the rounding
     * terms of the margins, so those are what the bisection meets. */
    for (int rep = 0; rep < 64; ++rep) {
        const int unit = rep >= 32;
        double qa[4], qb[4], u[3], o[3];
        random_unit_quaternion(&r, qa);
        random_unit_quaternion(&r, qb);
        if (rep % 2 == 0) memcpy(qb, qa, sizeof qb);
        if (rep % 4 == 1) {
            /* Axis-aligned, along an axis (as in test_elongated_touching):
             * node boxes tight at the contact. With a squared norm n, the
             * half turn q = sqrt(n) (1, 0, 0, 0) gives diag(1, 1 - 2n,
             * 1 - 2n): a's vertices 9e-7 beyond their node boxes in its
             * frame. */
            static const double aligned[4][4] = {{1, 0, 0, 0}, {0, 1, 0, 0}, {0, 0, 1, 0}, {0, 0, 0, 1}};
            memcpy(qa, aligned[(rep / 4) % 3], sizeof qa);
            memcpy(qb, aligned[(rep / 4 + 1) % 4], sizeof qb);
        }
        const int normal = rep % 2 == 0; /* plates face to face, lenses pole to pole */
        const double stretch_a = unit ? 1 : sqrt(1 + (normal || rep % 3 ? 9e-7 : -9e-7));
        const double stretch_b = unit ? 1 : normal ? stretch_a : sqrt(1 + (rep % 3 ? -9e-7 : 9e-7));
        for (int k = 0; k < 4; ++k) {
            qa[k] *= stretch_a;
            qb[k] *= stretch_b;
        }
        random_direction(&r, u);
        if (rep % 4 == 1) {
            u[0] = u[1] = u[2] = 0;
            u[(rep / 4 + 1) % 3] = rep % 8 == 1 ? 1 : -1; /* along a stretched axis */
        }
        if (normal) {
            /* Along the meshes' turned z axis: a's top vertices are the
             * extremes of their nodes' boxes, and their world images lie up
             * to about 1e-6 beyond them in a's frame (the quaternion's norm
             * turns the matrix a little off a rotation). */
            const double nm[3] = {0.8, 0, 0.6}, x = qa[0], y = qa[1], z = qa[2], w = qa[3];
            const double m[9] = {1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w),
                                 2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w),
                                 2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)};
            for (int k = 0; k < 3; ++k) u[k] = (m[3 * k] * nm[0] + m[3 * k + 1] * nm[1]) + m[3 * k + 2] * nm[2];
            if (rep % 4 == 2) {
                /* Lenses by their last poles: b turned half a turn about
                 * its y axis (q (0, 1, 0, 0)), moved along -R nm. Not the
                 * first vertices, which the containment test checks. */
                const double t[4] = {-qa[2], qa[3], qa[0], -qa[1]};
                memcpy(qb, t, sizeof qb);
                for (int k = 0; k < 3; ++k) u[k] = -u[k];
            }
        }
        for (int k = 0; k < 3; ++k) o[k] = (rep % 2 ? 3000.0 : -700.0) * (unit ? 1e6 : 1) * (1 + unif(&r));
        const int *kind = kinds[rep % 4];
        const double *sc = scales[(rep / 4) % 4];
        touch_scaled(kind[0], qa, sc[0], kind[1], qb, sc[1], o, u, 12 * (sc[0] + sc[1]));
    }
}

/* Two bodies of small custom meshes (more than 48 triangles each, so both
 * take the tree path) at scales where the world vertices underflow or a's
 * mesh frame is far from the world's: hgcd equals the oracle in both orders
 * of creation (either body can be the frame's). */
enum { FAN = 60, GRID = 8 };
static void cone(double *v, uint32_t *t, double apex, double ring_x, double radius) {
    v[0] = apex, v[1] = v[2] = 0;
    for (int i = 0; i < FAN; ++i) {
        const double th = 6.283185307179586 * i / FAN;
        v[3 * (i + 1)] = ring_x, v[3 * (i + 1) + 1] = radius * cos(th), v[3 * (i + 1) + 2] = radius * sin(th);
        t[3 * i] = 0, t[3 * i + 1] = 1 + i, t[3 * i + 2] = 1 + (i + 1) % FAN;
    }
}
/* A closed, non-convex zigzag bipyramid about the origin, apexes at z = +-1. */
static void bipyramid(double *v, uint32_t *t) {
    v[0] = v[1] = 0, v[2] = 1, v[3] = v[4] = 0, v[5] = -1;
    for (int i = 0; i < FAN; ++i) {
        const double th = 6.283185307179586 * i / FAN, r = i % 2 ? 0.7 : 1.0;
        v[3 * (i + 2)] = r * cos(th), v[3 * (i + 2) + 1] = r * sin(th), v[3 * (i + 2) + 2] = 0;
        t[6 * i] = 0, t[6 * i + 1] = 2 + i, t[6 * i + 2] = 2 + (i + 1) % FAN;
        t[6 * i + 3] = 1, t[6 * i + 4] = 2 + (i + 1) % FAN, t[6 * i + 5] = 2 + i;
    }
}
/* A flat open grid at z = 0 over [x0, x1] x [y0, y1]. */
static void flat_grid(double *v, uint32_t *t, double x0, double x1, double y0, double y1) {
    for (int i = 0; i <= GRID; ++i)
        for (int j = 0; j <= GRID; ++j) {
            double *p = v + 3 * (i * (GRID + 1) + j);
            p[0] = x0 + (x1 - x0) * i / GRID, p[1] = y0 + (y1 - y0) * j / GRID, p[2] = 0;
        }
    int k = 0;
    for (int i = 0; i < GRID; ++i)
        for (int j = 0; j < GRID; ++j) {
            const uint32_t a = i * (GRID + 1) + j, b = a + 1, c = a + GRID + 1, d = c + 1;
            t[k++] = a, t[k++] = c, t[k++] = b, t[k++] = b, t[k++] = c, t[k++] = d;
        }
}
static void two_bodies(const oracle_mesh *m, const double *pos, const double *scale, size_t expect) {
    static const double q[8] = {0, 0, 0, 1, 0, 0, 0, 1};
    const oracle_mesh *bm[2] = {&m[0], &m[1]};
    uint32_t pairs[2];
    assert_int_equal(oracle_colliding_pairs(2, bm, pos, q, scale, pairs, 1), expect);
    for (int first = 0; first < 2; ++first) {
        hgcd_world_desc wd = hgcd_world_desc_default();
        hgcd_world *w;
        assert_int_equal(hgcd_world_create(&wd, &w), HGCD_OK);
        hgcd_mesh mesh[2];
        for (int k = 0; k < 2; ++k) {
            hgcd_mesh_desc md = hgcd_mesh_desc_default();
            md.vertices = m[k].verts, md.triangles = m[k].tris;
            md.vertex_count = m[k].vertex_count, md.triangle_count = m[k].triangle_count;
            assert_int_equal(hgcd_mesh_create(w, &md, &mesh[k]), HGCD_OK);
        }
        for (int i = 0; i < 2; ++i) {
            const int k = first ^ i;
            hgcd_body_desc bd = hgcd_body_desc_default();
            bd.mesh = mesh[k];
            memcpy(bd.position, pos + 3 * k, sizeof bd.position);
            bd.scale = scale[k];
            hgcd_body body;
            assert_int_equal(hgcd_body_create(w, &bd, &body), HGCD_OK);
        }
        assert_int_equal(hgcd_world_detect(w), HGCD_OK);
        const hgcd_pair *got;
        size_t count;
        assert_int_equal(hgcd_world_pairs(w, &got, &count), HGCD_OK);
        assert_int_equal(count, expect);
        hgcd_world_destroy(w);
    }
}
static void test_frame_extreme_scales(void **state) {
    (void)state;
    static double v[2][3 * (GRID + 1) * (GRID + 1)];
    static uint32_t t[2][6 * GRID * GRID];
    oracle_mesh m[2] = {{v[0], t[0], FAN + 1, FAN, 0}, {v[1], t[1], FAN + 1, FAN, 0}};
    /* Subnormal world vertices: cones apart in their meshes (apexes at 31/32
     * and 1) whose apexes round to the same world point at scale 2^-1070. */
    cone(v[0], t[0], 31.0 / 32, 0.0, 0.5);
    cone(v[1], t[1], 1.0, 2.0, 0.5);
    const double origin[6] = {0, 0, 0, 0, 0, 0}, tiny[2] = {ldexp(1, -1070), ldexp(1, -1070)};
    two_bodies(m, origin, tiny, 1);
    const double unit[2] = {1, 1};
    two_bodies(m, origin, unit, 0);
    /* a of scale 1e-295 inside a grid 1e13 wide that passes through it: in
     * a's frame the grid's node centres are near 1e308 and beyond (at scale
     * 1e-300 they overflow, and no test may take that for apart). */
    bipyramid(v[0], t[0]);
    flat_grid(v[1], t[1], 0.9e13, 3.1e13, -1e13, 1e13);
    const oracle_mesh closed_and_grid[2] = {{v[0], t[0], FAN + 2, 2 * FAN, 1},
                                            {v[1], t[1], (GRID + 1) * (GRID + 1), 2 * GRID * GRID, 0}};
    const double apart_x[6] = {0, 0, 0, -1e13, 0, 0};
    for (int k = 0; k < 4; ++k) {
        const double s[4] = {1e-295, 1e-200, 1e-280, 1e-300};
        const double scale[2] = {s[k], 1};
        two_bodies(closed_and_grid, apart_x, scale, 1);
    }
}

/* 20 bodies (elongated and round meshes, boxes, one round mesh 50x larger)
 * packed in a small cube, each moving and turning a little per tick: a
 * world on 1 thread and one on 2 see the same poses; every tick both equal
 * the oracle. The pairs change from tick to tick, and many stay colliding:
 * stale and fresh witnesses both. */
static void test_moving_cluster(void **state) {
    (void)state;
    rng r = {11};
    scene one, two;
    scene_init(&one, 1);
    scene_init(&two, 2);
    double vel[3 * CAP], axis[3 * CAP];
    for (int i = 0; i < 20; ++i) {
        const int kind = i == 19 ? M_ROUND : i % 3 == 2 ? M_BOX : i % 3 == 1 ? M_ROUND : M_LONG;
        const double s = i == 19 ? 0.02 * 50 : 0.02 * (0.7 + 0.6 * unif(&r)) * (kind == M_BOX ? 5 : 1);
        double p[3], q[4];
        for (int k = 0; k < 3; ++k) {
            p[k] = i == 19 ? 0.5 + 1.2 : 0.5 * unif(&r);
            vel[3 * i + k] = 0.01 * (2 * unif(&r) - 1);
        }
        random_unit_quaternion(&r, q);
        random_direction(&r, &axis[3 * i]);
        add(&one, kind, p, q, s);
        add(&two, kind, p, q, s);
    }
    size_t total = 0;
    for (int tick = 0; tick < 8; ++tick) {
        const size_t n = check(&one);
        assert_int_equal(check(&two), n);
        total += n;
        for (size_t i = 0; i < one.n; ++i) {
            double p[3], q[4];
            for (int k = 0; k < 3; ++k) p[k] = one.pos[3 * i + k] + vel[3 * i + k];
            memcpy(q, &one.quat[4 * i], sizeof q);
            turn(q, &axis[3 * i], 0.05);
            set_pose(&one, i, p, q);
            set_pose(&two, i, p, q);
        }
    }
    fprintf(stderr, "moving cluster: %zu colliding pairs over 8 ticks\n", total);
    assert_true(total >= 40);
    hgcd_world_destroy(one.w);
    hgcd_world_destroy(two.w);
}

int main(void) {
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_elongated_touching),
        cmocka_unit_test(test_fitted_touching),
        cmocka_unit_test(test_frame_touching),
        cmocka_unit_test(test_frame_extreme_scales),
        cmocka_unit_test(test_moving_cluster),
    };
    if (getenv("HGCD_TEST_FILTER")) cmocka_set_test_filter(getenv("HGCD_TEST_FILTER"));
    if (getenv("HGCD_TEST_SKIP")) cmocka_set_skip_filter(getenv("HGCD_TEST_SKIP"));
    return cmocka_run_group_tests(tests, setup, teardown);
}
