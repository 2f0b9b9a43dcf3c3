/* The narrow phase's convex path (src/narrow/convex.cpp: separating axes
 * along the line of centres, face normals and edge pairs, certified, before
 * the exact test) against the independent oracle: random scenes of boxes,
 * icosahedra, 80-triangle icospheres and convex hulls mixed with
 * tetrahedra and a non-convex mesh (the boxes and hulls also off centre: their
 * vertices then lack the symmetry about the origin the kernel's projections
 * use when they have it), and hand-built touching faces, edges
 * and vertices, gaps of one ulp, containment, and faces a hair apart at
 * random orientations. */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "support/shapes.h"

#include <cmocka.h>

#include <hgcd/hgcd.h>

#include "oracle.h"
#include "scene_shapes.h"
#include "test_rng.h"

enum { BOX, SLAB, ICOSAHEDRON, ICOSPHERE, HULL, PARALLELEPIPED, OFFBOX, OFFHULL, NUDGED, TETRA, DENTED, SHAPE_COUNT };
/* The shapes that must be convex (and so take the convex path together). */
static const int must_be_convex[SHAPE_COUNT] = {1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 0};


static double box_v[24], slab_v[24], par_v[24], ico_v[36], hull_v[36], sphere_v[3 * 42], offbox_v[24], offhull_v[36],
    nudged_v[36];
static uint32_t box_t[36], ico_t[60], sphere_t[3 * 80];
static oracle_mesh shapes[SHAPE_COUNT];

/* A dyadic linear map: applied to the cube's +-1 coordinates it is exact, so
 * the parallelepiped's faces stay planar (and the mesh convex). */
static const double shear[9] = {1.25, 0.25, 0, 0, 0.75, 0.375, 0.5, 0, 1};

static void make_shapes(void) {
    uint32_t scratch[5 * 80];
    hgcd_box_mesh(1, 1, 1, box_v, box_t);
    uint32_t slab_t[36];
    hgcd_box_mesh(2, 0.5, 1, slab_v, slab_t);
    for (int i = 0; i < 8; ++i)
        for (int r = 0; r < 3; ++r)
            par_v[3 * i + r] = shear[3 * r] * box_v[3 * i] + shear[3 * r + 1] * box_v[3 * i + 1] +
                               shear[3 * r + 2] * box_v[3 * i + 2];
    hgcd_icosphere(0, ico_v, ico_t, scratch);
    hgcd_icosphere(1, sphere_v, sphere_t, scratch);
    /* An irregular hull: the icosahedron under a non-dyadic linear map
     * (strictly convex, so rounding keeps it convex). */
    for (int i = 0; i < 12; ++i) {
        const double *p = &ico_v[3 * i];
        hull_v[3 * i] = 1.7 * p[0] + 0.3 * p[1];
        hull_v[3 * i + 1] = 0.2 * p[0] + 0.6 * p[1] - 0.1 * p[2];
        hull_v[3 * i + 2] = 0.4 * p[1] + 1.1 * p[2];
    }
    /* The box and the hull moved off their centre (the origin still inside):
     * no longer symmetric about the origin. */
    const double off[3] = {0.5, -0.25, 0.125};
    for (int i = 0; i < 8; ++i)
        for (int k = 0; k < 3; ++k) offbox_v[3 * i + k] = box_v[3 * i + k] + off[k];
    for (int i = 0; i < 12; ++i)
        for (int k = 0; k < 3; ++k) offhull_v[3 * i + k] = hull_v[3 * i + k] + 0.75 * off[k];
    /* The icosahedron with vertex 3, (1, -phi, 0) / |.|, pushed out by 2^-30
     * of its length: symmetric about the origin but for that vertex. */
    memcpy(nudged_v, ico_v, sizeof nudged_v);
    for (int k = 0; k < 3; ++k) nudged_v[9 + k] *= 1 + 0x1p-30;
    const oracle_mesh m[SHAPE_COUNT] = {
        {box_v, box_t, 8, 12, 1},       {slab_v, box_t, 8, 12, 1},       {ico_v, ico_t, 12, 20, 1},
        {sphere_v, sphere_t, 42, 80, 1}, {hull_v, ico_t, 12, 20, 1},     {par_v, box_t, 8, 12, 1},
        {offbox_v, box_t, 8, 12, 1},    {offhull_v, ico_t, 12, 20, 1},  {nudged_v, ico_t, 12, 20, 1},
        {tetra_v, tetra_t, 4, 4, 1},    {dented_v, dented_t, 9, 14, 1},
    };
    memcpy(shapes, m, sizeof m);
}

typedef struct {
    hgcd_world *w;
    hgcd_mesh mesh[SHAPE_COUNT];
    size_t n, cap;
    int per_body; /* each body a mesh of its own: 1 a copy of its shape's arrays, 2 its shape stretched */
    int *shape;
    double *pos, *quat, *scale;
    hgcd_body *id;
    oracle_mesh *own;  /* per_body 2: each body's mesh, for the oracle */
    double *own_v;     /* and its vertices, 3 * 42 doubles a body */
} scene;

/* 0: scene_init creates no shared meshes (for worlds with a mesh per body). */
static int shared_meshes = 1;
/* When set, scene_init creates the shared meshes of these shapes alone
 * (-1 ends the list): worlds whose every mesh is a small convex one. */
static const int *only_meshes = NULL;

static int in_list(const int *list, int k) {
    for (; *list >= 0; ++list)
        if (*list == k) return 1;
    return 0;
}

static void scene_init(scene *sc, size_t cap, uint32_t threads) {
    memset(sc, 0, sizeof *sc);
    hgcd_world_desc wd = hgcd_world_desc_default();
    wd.thread_count = threads;
    assert_int_equal(hgcd_world_create(&wd, &sc->w), HGCD_OK);
    for (int k = 0; k < SHAPE_COUNT && shared_meshes; ++k) {
        if (only_meshes && !in_list(only_meshes, k)) continue;
        hgcd_mesh_desc md = hgcd_mesh_desc_default();
        md.vertices = shapes[k].verts;
        md.triangles = shapes[k].tris;
        md.vertex_count = shapes[k].vertex_count;
        md.triangle_count = shapes[k].triangle_count;
        assert_int_equal(hgcd_mesh_create(sc->w, &md, &sc->mesh[k]), HGCD_OK);
        hgcd_mesh_info info;
        info.struct_size = sizeof info;
        assert_int_equal(hgcd_mesh_get_info(sc->w, sc->mesh[k], &info), HGCD_OK);
        assert_int_equal(info.convex, must_be_convex[k]);
    }
    sc->cap = cap;
    sc->shape = malloc(cap * sizeof(int));
    sc->pos = malloc(3 * cap * sizeof(double));
    sc->quat = malloc(4 * cap * sizeof(double));
    sc->scale = malloc(cap * sizeof(double));
    sc->id = malloc(cap * sizeof(hgcd_body));
    sc->own = malloc(cap * sizeof(oracle_mesh));
    sc->own_v = malloc(cap * 3 * 42 * sizeof(double));
}

static void scene_free(scene *sc) {
    hgcd_world_destroy(sc->w);
    free(sc->shape);
    free(sc->pos);
    free(sc->quat);
    free(sc->scale);
    free(sc->id);
    free(sc->own);
    free(sc->own_v);
}

static void add(scene *sc, int shape, const double *p, const double *q, double scale) {
    assert_true(sc->n < sc->cap);
    hgcd_body_desc bd = hgcd_body_desc_default();
    bd.mesh = sc->mesh[shape];
    if (sc->per_body) {
        hgcd_mesh_desc md = hgcd_mesh_desc_default();
        md.vertices = shapes[shape].verts;
        if (sc->per_body == 2) {
            /* A shape of its own: stretched along x by 1 + n / 256 and along
             * y by 1 + (n % 3) / 4 (dyadic factors of few bits). */
            const oracle_mesh *m = &shapes[shape];
            double *v = &sc->own_v[3 * 42 * sc->n];
            assert_true(m->vertex_count <= 42);
            const double fx = 1 + (double)(sc->n % 256) / 256, fy = 1 + (double)(sc->n % 3) / 4;
            for (uint32_t i = 0; i < m->vertex_count; ++i) {
                v[3 * i] = fx * m->verts[3 * i];
                v[3 * i + 1] = fy * m->verts[3 * i + 1];
                v[3 * i + 2] = m->verts[3 * i + 2];
            }
            sc->own[sc->n] = *m;
            sc->own[sc->n].verts = v;
            md.vertices = v;
        }
        md.triangles = shapes[shape].tris;
        md.vertex_count = shapes[shape].vertex_count;
        md.triangle_count = shapes[shape].triangle_count;
        assert_int_equal(hgcd_mesh_create(sc->w, &md, &bd.mesh), HGCD_OK);
    }
    memcpy(bd.position, p, sizeof bd.position);
    memcpy(bd.orientation, q, sizeof bd.orientation);
    bd.scale = scale;
    hgcd_body b;
    assert_int_equal(hgcd_body_create(sc->w, &bd, &b), HGCD_OK);
    assert_int_equal(b.index, sc->n); /* a fresh world: bodies in creation order */
    sc->id[sc->n] = b;
    sc->shape[sc->n] = shape;
    memcpy(&sc->pos[3 * sc->n], p, 3 * sizeof(double));
    memcpy(&sc->quat[4 * sc->n], q, 4 * sizeof(double));
    sc->scale[sc->n] = scale;
    ++sc->n;
}

/* Detects and compares every pair with the oracle; returns the pair count. */
static size_t check_against_oracle(scene *sc) {
    assert_int_equal(hgcd_world_detect(sc->w), HGCD_OK);
    const oracle_mesh **meshes = malloc(sc->n * sizeof(*meshes));
    for (size_t i = 0; i < sc->n; ++i) meshes[i] = sc->per_body == 2 ? &sc->own[i] : &shapes[sc->shape[i]];
    const size_t n = oracle_colliding_pairs(sc->n, meshes, sc->pos, sc->quat, sc->scale, NULL, 0);
    uint32_t *expect = malloc((2 * n + 2) * sizeof(uint32_t));
    assert_int_equal(oracle_colliding_pairs(sc->n, meshes, sc->pos, sc->quat, sc->scale, expect, n), n);
    const hgcd_pair *got;
    size_t count;
    assert_int_equal(hgcd_world_pairs(sc->w, &got, &count), HGCD_OK);
    size_t mismatches = 0;
    for (size_t k = 0; k < n || k < count; ++k) {
        const int has_e = k < n, has_g = k < count;
        if (has_e && has_g && got[k].a.index == expect[2 * k] && got[k].b.index == expect[2 * k + 1]) continue;
        if (mismatches++ < 5)
            fprintf(stderr, "pair %zu: hgcd (%u, %u)%s, oracle (%u, %u)%s\n", k, has_g ? got[k].a.index : 0,
                    has_g ? got[k].b.index : 0, has_g ? "" : " none", has_e ? expect[2 * k] : 0,
                    has_e ? expect[2 * k + 1] : 0, has_e ? "" : " none");
    }
    assert_int_equal(mismatches, 0);
    assert_int_equal(count, n);
    /* Containment against surfaces apart: a witness request (contacts) takes
     * the exact path for every pair the convex kernel does not separate, so
     * its containment count is the reference for the kernel's. */
    hgcd_stats plain = {.struct_size = sizeof plain}, exact = {.struct_size = sizeof exact};
    hgcd_world_stats(sc->w, &plain);
    assert_int_equal(hgcd_world_set_contacts(sc->w, 1), HGCD_OK);
    assert_int_equal(hgcd_world_detect(sc->w), HGCD_OK);
    hgcd_world_stats(sc->w, &exact);
    assert_int_equal(hgcd_world_set_contacts(sc->w, 0), HGCD_OK);
    assert_int_equal(exact.colliding_pairs, plain.colliding_pairs);
    assert_int_equal(exact.containment_pairs, plain.containment_pairs);
    free(expect);
    free(meshes);
    return n;
}

/* Whether bodies a < b are reported as colliding. */
static int reported(const scene *sc, uint32_t a, uint32_t b) {
    const hgcd_pair *p;
    size_t count;
    assert_int_equal(hgcd_world_pairs(sc->w, &p, &count), HGCD_OK);
    for (size_t k = 0; k < count; ++k)
        if (p[k].a.index == a && p[k].b.index == b) return 1;
    return 0;
}

static const double exact_quats[][4] = {{0, 0, 0, 1}, {1, 0, 0, 0}, {0, 1, 0, 0},
                                        {0, 0, 1, 0}, {0.5, 0.5, 0.5, 0.5}, {-0.5, 0.5, -0.5, 0.5}};

/* n bodies of random shapes (or all of shape `only` when >= 0) in a cube of
 * side `side`; snap: positions on a 0.5 grid, rotations that permute axes
 * and scales in {0.5, 1, 1.5}, so that faces, edges and vertices touch
 * exactly. */
static void fill_from(scene *sc, rng *r, size_t n, double side, int snap, const int *set, int set_count) {
    for (size_t i = 0; i < n; ++i) {
        double p[3], q[4];
        for (int k = 0; k < 3; ++k) {
            p[k] = side * unif(r);
            if (snap) p[k] = floor(p[k] * 2) / 2;
        }
        if (snap) memcpy(q, exact_quats[next(r) % 6], sizeof q);
        else random_unit_quaternion(r, q);
        const int shape = set[next(r) % (uint64_t)set_count];
        const double scale = snap ? 0.5 + 0.5 * (double)(next(r) % 3) : 0.3 + 1.7 * unif(r);
        add(sc, shape, p, q, scale);
    }
}
static void fill_with(scene *sc, rng *r, size_t n, double side, int snap, int only) {
    static const int all[SHAPE_COUNT] = {0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10};
    if (only >= 0) fill_from(sc, r, n, side, snap, &only, 1);
    else fill_from(sc, r, n, side, snap, all, SHAPE_COUNT);
}
static void fill(scene *sc, rng *r, size_t n, double side, int snap) { fill_with(sc, r, n, side, snap, -1); }

static void test_random_scenes(void **state) {
    (void)state;
    size_t total = 0;
    for (uint64_t seed = 1; seed <= 6; ++seed) {
        rng r = {seed * 7919};
        scene sc;
        scene_init(&sc, 300, (uint32_t)(seed % 2) + 1);
        fill(&sc, &r, 300, 16, 0);
        total += check_against_oracle(&sc);
        scene_free(&sc);
    }
    assert_true(total > 300); /* dense enough to mean something */
}

/* Worlds of one shape, so that the batch's pairs share their meshes (its
 * vertex pokes four pairs at a time), dense enough for bodies inside
 * others, random and grid-snapped (touching), on 1 and 2 threads. */
static void test_one_shape(void **state) {
    (void)state;
    const int one[] = {BOX, PARALLELEPIPED, HULL, SLAB, OFFBOX, OFFHULL};
    size_t total = 0;
    for (uint64_t seed = 1; seed <= 8; ++seed) {
        rng r = {seed * 104729};
        scene sc;
        scene_init(&sc, 160, (uint32_t)(seed % 2) + 1);
        fill_with(&sc, &r, 160, 11, (int)(seed / 2 % 2), one[seed % 6]);
        total += check_against_oracle(&sc);
        scene_free(&sc);
    }
    assert_true(total > 2000);
}

/* Worlds whose every mesh is a small convex one, none a tetrahedron (the
 * narrow phase hands every candidate pair of a chunk to the convex batch in
 * the chunk's order, and lists its hits from the chunk's pairs): one, two
 * or three shapes, shared, a mesh per body, or a shape per body (each
 * body's shape stretched by its own factors: the batch's lanes then read
 * each its own meshes' data), random and grid-snapped, dense, on 1 and 2
 * threads; each world also after a tick of motion. */
static void test_convex_only(void **state) {
    (void)state;
    static const int sets[][4] = {{BOX, -1},          {BOX, HULL, -1},     {ICOSPHERE, OFFBOX, -1},
                                  {SLAB, PARALLELEPIPED, OFFHULL, -1}, {OFFBOX, -1}, {HULL, ICOSAHEDRON, BOX, -1}};
    size_t total = 0;
    for (uint64_t seed = 1; seed <= 6; ++seed) {
        rng r = {seed * 86028121};
        const int *set = sets[seed - 1];
        int count = 0;
        while (set[count] >= 0) ++count;
        only_meshes = set;
        scene sc;
        scene_init(&sc, 150, (uint32_t)(seed % 2) + 1);
        sc.per_body = seed == 5 ? 1 : seed == 6 ? 2 : 0;
        fill_from(&sc, &r, 150, 9.5, (int)(seed / 2 % 2), set, count);
        total += check_against_oracle(&sc);
        /* every body moved a little, and detected again */
        for (size_t i = 0; i < sc.n; ++i) {
            double *p = &sc.pos[3 * i];
            for (int k = 0; k < 3; ++k) p[k] += sc.shape[i] == BOX ? 0.25 : 0.125 * (unif(&r) - 0.5);
            assert_int_equal(hgcd_body_set_pose(sc.w, sc.id[i], p, &sc.quat[4 * i]), HGCD_OK);
        }
        total += check_against_oracle(&sc);
        scene_free(&sc);
        only_meshes = NULL;
    }
    fprintf(stderr, "test_convex_only: %zu pairs\n", total);
    assert_true(total > 4000);
}

/* Worlds of two or three shapes, tetrahedra among them: the batch queues
 * the pairs its line of centres leaves open by combination of meshes
 * (tetrahedron-box, box-tetrahedron, box-box, ...) until four fill its
 * lanes, and with three shapes some combinations find no queue and take the
 * one-pair steps; tetrahedron-convex pairs take the convex path. Random and
 * grid-snapped, dense, on 1 and 2 threads. */
static void test_few_shapes(void **state) {
    (void)state;
    static const int sets[][3] = {{TETRA, BOX, -1},      {TETRA, ICOSPHERE, -1}, {TETRA, OFFHULL, -1},
                                  {TETRA, BOX, HULL},    {BOX, SLAB, -1},        {TETRA, PARALLELEPIPED, -1},
                                  {TETRA, OFFBOX, ICOSAHEDRON}, {TETRA, SLAB, -1}};
    size_t total = 0;
    for (uint64_t seed = 1; seed <= 8; ++seed) {
        rng r = {seed * 15485863};
        scene sc;
        scene_init(&sc, 160, (uint32_t)(seed % 2) + 1);
        const int *set = sets[seed - 1];
        fill_from(&sc, &r, 160, 11, (int)(seed / 2 % 2), set, set[2] < 0 ? 2 : 3);
        total += check_against_oracle(&sc);
        scene_free(&sc);
    }
    assert_true(total > 2000);
}

/* test_few_shapes's worlds with a mesh per body (copies of the shapes'
 * arrays: the copies share their convex data, so the batch's steps four
 * pairs at a time serve them too), the shared meshes of the shapes destroyed
 * halfway (copies made after that share a convex data of their own). */
static void test_mesh_per_body(void **state) {
    (void)state;
    static const int sets[][2] = {{TETRA, BOX}, {BOX, HULL}, {TETRA, OFFHULL}, {SLAB, ICOSPHERE}};
    size_t total = 0;
    for (uint64_t seed = 1; seed <= 4; ++seed) {
        rng r = {seed * 49979687};
        scene sc;
        scene_init(&sc, 160, (uint32_t)(seed % 2) + 1);
        sc.per_body = 1;
        fill_from(&sc, &r, 80, 11, (int)(seed % 2), sets[seed - 1], 2);
        for (int k = 0; k < SHAPE_COUNT; ++k) assert_int_equal(hgcd_mesh_destroy(sc.w, sc.mesh[k]), HGCD_OK);
        fill_from(&sc, &r, 80, 11, (int)(seed % 2), sets[seed - 1], 2);
        total += check_against_oracle(&sc);
        scene_free(&sc);
    }
    assert_true(total > 1000);
}

/* A world of tetrahedra alone, then other convex shapes: the tetrahedra
 * created before the first other convex mesh get their convex data only
 * then (a world of tetrahedra alone does not carry it), and their pairs
 * with the new shapes must stay exact. A mesh per body, 1 and 2 threads. */
static void test_tetra_first(void **state) {
    (void)state;
    static const int tetra[] = {TETRA}, mixed[] = {TETRA, BOX, ICOSPHERE, OFFHULL};
    size_t total = 0;
    shared_meshes = 0;
    for (uint64_t seed = 1; seed <= 4; ++seed) {
        rng r = {seed * 7368787};
        scene sc;
        scene_init(&sc, 200, (uint32_t)(seed % 2) + 1);
        sc.per_body = 1;
        fill_from(&sc, &r, 100, 9, (int)(seed % 2), tetra, 1);
        total += check_against_oracle(&sc);
        fill_from(&sc, &r, 100, 9, (int)(seed % 2), mixed, 4);
        total += check_against_oracle(&sc);
        scene_free(&sc);
    }
    shared_meshes = 1;
    assert_true(total > 1000);
}

static void test_exact_contacts(void **state) {
    (void)state;
    size_t total = 0;
    for (uint64_t seed = 20; seed < 26; ++seed) {
        rng r = {seed};
        scene sc;
        scene_init(&sc, 250, 1);
        fill(&sc, &r, 250, 10, 1);
        total += check_against_oracle(&sc);
        scene_free(&sc);
    }
    assert_true(total > 400);
}

static void test_hand_built(void **state) {
    (void)state;
    scene sc;
    scene_init(&sc, 64, 1);
    const double id[4] = {0, 0, 0, 1};
    /* Coordinates marked UP are moved one ulp up after the base is added. */
    const double UP = 1e300;
    struct {
        int a, b;
        double pb[3];
        double sb;
        int expect; /* -1: the oracle alone decides */
    } cases[] = {
        {BOX, BOX, {2, 0, 0}, 1, 1},             /* faces touch */
        {BOX, BOX, {UP, 0, 0}, 1, 0},            /* faces one ulp apart */
        {BOX, BOX, {2, 2, 0}, 1, 1},             /* edges touch */
        {BOX, BOX, {2, UP, 0}, 1, 0},            /* edges one ulp apart */
        {BOX, BOX, {2, 2, 2}, 1, 1},             /* vertices touch */
        {BOX, BOX, {UP, UP, UP}, 1, 0},          /* vertices one ulp apart */
        {BOX, BOX, {0.25, 0.5, 0}, 0.25, 1},     /* containment */
        {BOX, BOX, {0.5, 0.5, 0.5}, 0.5, 1},     /* inside, touching three faces */
        {BOX, TETRA, {2, 0, 0}, 1, 1},           /* tetrahedron vertex on a face */
        {BOX, TETRA, {UP, 0, 0}, 1, 0},
        {BOX, ICOSPHERE, {0, 0, 0}, 0.5, 1},     /* sphere inside the box */
        {ICOSPHERE, BOX, {0, 0, 0}, 0.5, 1},     /* box inside the sphere */
        {ICOSPHERE, ICOSPHERE, {2, 0, 0}, 1, -1},
        {ICOSPHERE, ICOSAHEDRON, {0, 0, 1.5}, 0.5, -1},
        {SLAB, BOX, {3, 0, 0}, 1, 1},            /* slab end touches the box */
        {SLAB, PARALLELEPIPED, {0, 0, 2.5}, 1, -1},
        {HULL, HULL, {1.5, 0.5, 0}, 1, -1},
        {PARALLELEPIPED, PARALLELEPIPED, {2.5, 0, 0}, 1, -1},
        {DENTED, BOX, {0, 0, 1.5}, 0.25, -1},    /* box in the dent: not convex, exact path */
    };
    const size_t count = sizeof cases / sizeof cases[0];
    for (size_t k = 0; k < count; ++k) {
        /* Each case far from the others. */
        const double base[3] = {40.0 * (double)k, 0, 0};
        double pb[3];
        for (int i = 0; i < 3; ++i)
            pb[i] = cases[k].pb[i] == UP ? nextafter(base[i] + 2, INFINITY) : base[i] + cases[k].pb[i];
        add(&sc, cases[k].a, base, id, 1);
        add(&sc, cases[k].b, pb, id, cases[k].sb);
    }
    check_against_oracle(&sc);
    for (size_t k = 0; k < count; ++k)
        if (cases[k].expect >= 0) {
            assert_int_equal(reported(&sc, (uint32_t)(2 * k), (uint32_t)(2 * k + 1)), cases[k].expect);
        }
    scene_free(&sc);
}

/* Two bodies at random orientations, the second moved along a random
 * direction to where the oracle's answer flips (bisection on the exact
 * answer), then set a few ulps either side: every pair within rounding of
 * touching, where a filter's margin must hold. */
static int oracle_pair(int sa, const double *pa, const double *qa, double s_a, int sb, const double *pb,
                       const double *qb, double s_b) {
    const oracle_mesh *m[2] = {&shapes[sa], &shapes[sb]};
    double p[6], q[8], s[2] = {s_a, s_b};
    memcpy(p, pa, 3 * sizeof(double));
    memcpy(p + 3, pb, 3 * sizeof(double));
    memcpy(q, qa, 4 * sizeof(double));
    memcpy(q + 4, qb, 4 * sizeof(double));
    return oracle_colliding_pairs(2, m, p, q, s, NULL, 0) != 0;
}

/* Resting contact: stacks of axis-aligned boxes whose faces lie exactly on
 * each other's (their boxes meet in a flat region, where the search for an
 * edge through a triangle is skipped), shifted sideways by multiples of
 * 1/4 so that faces overlap, edges and corners touch or the boxes are
 * apart; slabs under them and icospheres and hulls resting on them, axis
 * turned by quarter turns about z (exact quaternions). */
static void test_resting_stacks(void **state) {
    (void)state;
    scene sc;
    scene_init(&sc, 200, 1);
    rng r = {7};
    static const int top[] = {BOX, BOX, SLAB, ICOSAHEDRON, HULL, PARALLELEPIPED};
    const double h = sqrt(0.5);
    const double quarter[4][4] = {{0, 0, 0, 1}, {0, 0, h, h}, {0, 0, 1, 0}, {0, 0, h, -h}};
    for (int st = 0; st < 24; ++st) {
        const double x0 = 10.0 * (st % 6), y0 = 10.0 * (st / 6);
        const double floor_p[3] = {x0, y0, -1};
        add(&sc, SLAB, floor_p, quarter[0], 2); /* its top face at z = 1 */
        double z = 1;                            /* the top of what is below */
        for (int k = 0; k < 5; ++k) {
            const int shape = k < 4 ? BOX : top[(next(&r) % 6)];
            const double dx = 0.25 * (double)((int)(next(&r) % 17) - 8), dy = 0.25 * (double)((int)(next(&r) % 17) - 8);
            const double *q = shape == BOX ? quarter[(next(&r) % 4)] : quarter[0];
            /* Resting on z: the shape's lowest vertex (turned by q about z, so
             * its z is unchanged) exactly at z. */
            double low = INFINITY, high = -INFINITY;
            for (uint32_t v = 0; v < shapes[shape].vertex_count; ++v) {
                low = fmin(low, shapes[shape].verts[3 * v + 2]);
                high = fmax(high, shapes[shape].verts[3 * v + 2]);
            }
            const double p[3] = {x0 + dx, y0 + dy, z - low};
            add(&sc, shape, p, q, 1);
            z = p[2] + high;
        }
    }
    assert_true(check_against_oracle(&sc) >= 24); /* each stack on its slab */
    scene_free(&sc);
}

static void test_near_touching(void **state) {
    (void)state;
    rng r = {99};
    scene sc;
    const int convex_shapes[] = {BOX, SLAB, ICOSAHEDRON, HULL, PARALLELEPIPED, TETRA, OFFBOX, OFFHULL, ICOSPHERE};
    scene_init(&sc, 200, 1);
    int flips = 0;
    for (int k = 0; k < 24; ++k) {
        /* (the icosphere only every third time: the oracle is slow on it) */
        const int sa = convex_shapes[next(&r) % (k % 3 ? 8 : 9)], sb = convex_shapes[next(&r) % (k % 3 ? 8 : 9)];
        double qa[4], qb[4], dir[3] = {2 * unif(&r) - 1, 2 * unif(&r) - 1, 2 * unif(&r) - 1};
        random_unit_quaternion(&r, qa);
        random_unit_quaternion(&r, qb);
        const double pa[3] = {100.0 * k, 7, 0};
        /* Bisection on t: the pair at pa + t dir collides at t = 0, not at t = 8. */
        double lo = 0, hi = 8;
        for (int it = 0; it < 64; ++it) {
            const double mid = 0.5 * (lo + hi);
            if (mid == lo || mid == hi) break;
            const double pb[3] = {pa[0] + mid * dir[0], pa[1] + mid * dir[1], pa[2] + mid * dir[2]};
            if (oracle_pair(sa, pa, qa, 1, sb, pb, qb, 0.7)) lo = mid;
            else hi = mid;
        }
        add(&sc, sa, pa, qa, 1);
        const double ts[3] = {lo, hi, 0.5 * (lo + hi)};
        for (int j = 0; j < 3; ++j) {
            const double pb[3] = {pa[0] + ts[j] * dir[0], pa[1] + ts[j] * dir[1], pa[2] + ts[j] * dir[2]};
            add(&sc, sb, pb, qb, 0.7);
        }
        ++flips;
    }
    /* Each case 100 apart from the others along x; every pair against the oracle. */
    const size_t n = check_against_oracle(&sc);
    assert_true(n >= (size_t)flips); /* each bisection's collided end collides */
    scene_free(&sc);
}

/* The nearly symmetric icosahedron (NUDGED) over a box, turned about axes
 * that keep its pushed vertex 3 and the vertex 2 it was level with equally
 * low over the box's top face: the box moved down to where the oracle's
 * answer flips (touching at vertex 3 alone), then set an ulp either side.
 * Projections taken from half the vertices, as if the mesh were symmetric,
 * would miss vertex 3 and see these pairs apart. */
static void test_nearly_symmetric(void **state) {
    (void)state;
    scene sc;
    scene_init(&sc, 64, 1);
    const double *v3 = &nudged_v[9];
    for (int k = 0; k < 12; ++k) {
        const double ang = 0.15 * (k / 2), s = sin(0.5 * ang), c = cos(0.5 * ang);
        const double qb[4] = {k % 2 ? 0 : s, k % 2 ? s : 0, 0, c}; /* about x, or about y */
        const double qa[4] = {0, 0, 0, 1}, pa[3] = {100.0 * k, 0, 0};
        double lo = -0.5, hi = 1; /* the box's top 0.5 over vertex 3 at t = -0.5, 1 under it at t = 1 */
        for (int it = 0; it < 80; ++it) {
            const double mid = 0.5 * (lo + hi);
            if (mid == lo || mid == hi) break;
            const double pb[3] = {pa[0] + v3[0], v3[1] - 1 - mid, v3[2]};
            if (oracle_pair(NUDGED, pa, qa, 1, BOX, pb, qb, 1)) lo = mid;
            else hi = mid;
        }
        add(&sc, NUDGED, pa, qa, 1);
        const double ts[2] = {lo, hi};
        for (int j = 0; j < 2; ++j) {
            const double pb[3] = {pa[0] + v3[0], v3[1] - 1 - ts[j], v3[2]};
            add(&sc, BOX, pb, qb, 1);
        }
    }
    assert_true(check_against_oracle(&sc) >= 24); /* each touching box, and the two boxes */
    scene_free(&sc);
}

/* Quaternion product a b (x, y, z, w). */
static void qmul(const double *a, const double *b, double *out) {
    out[0] = a[3] * b[0] + a[0] * b[3] + a[1] * b[2] - a[2] * b[1];
    out[1] = a[3] * b[1] - a[0] * b[2] + a[1] * b[3] + a[2] * b[0];
    out[2] = a[3] * b[2] + a[0] * b[1] - a[1] * b[0] + a[2] * b[3];
    out[3] = a[3] * b[3] - a[0] * b[0] - a[1] * b[1] - a[2] * b[2];
}

/* Vertex against vertex along the line of centres, at random orientations:
 * B is A turned half a turn about an axis normal to A's vertex v, so B's
 * copy of v points back at A's, and B is moved along A's vertex direction to
 * within an ulp of touching (bisection on the oracle's answer). The axis
 * along the line of centres is then the tight one, and its margin must
 * hold. */
static void test_tip_to_tip(void **state) {
    (void)state;
    rng r = {4242};
    const int tips[] = {BOX, TETRA, ICOSAHEDRON, HULL, PARALLELEPIPED};
    scene sc;
    scene_init(&sc, 200, 1);
    for (int k = 0; k < 30; ++k) {
        const int shape = tips[next(&r) % 5];
        const oracle_mesh *m = &shapes[shape];
        const double *v = &m->verts[3 * (next(&r) % m->vertex_count)];
        double qa[4], qb[4], w[3] = {2 * unif(&r) - 1, 2 * unif(&r) - 1, 2 * unif(&r) - 1};
        random_unit_quaternion(&r, qa);
        /* w normal to v, normalised: the half turn's axis. */
        const double vv = v[0] * v[0] + v[1] * v[1] + v[2] * v[2], wv = w[0] * v[0] + w[1] * v[1] + w[2] * v[2];
        for (int i = 0; i < 3; ++i) w[i] -= wv / vv * v[i];
        const double wn = sqrt(w[0] * w[0] + w[1] * w[1] + w[2] * w[2]);
        const double half[4] = {w[0] / wn, w[1] / wn, w[2] / wn, 0};
        qmul(qa, half, qb);
        /* dir = R(qa) v, by the quaternion sandwich (only a direction). */
        const double vq[4] = {v[0], v[1], v[2], 0}, conj[4] = {-qa[0], -qa[1], -qa[2], qa[3]};
        double t1[4], dir[4];
        qmul(qa, vq, t1);
        qmul(t1, conj, dir);
        const double pa[3] = {100.0 * k, -50, 0};
        double lo = 0, hi = 4;  /* touching near t = 2 */
        for (int it = 0; it < 64; ++it) {
            const double mid = 0.5 * (lo + hi);
            if (mid == lo || mid == hi) break;
            const double pb[3] = {pa[0] + mid * dir[0], pa[1] + mid * dir[1], pa[2] + mid * dir[2]};
            if (oracle_pair(shape, pa, qa, 1, shape, pb, qb, 1)) lo = mid;
            else hi = mid;
        }
        add(&sc, shape, pa, qa, 1);
        const double pl[3] = {pa[0] + lo * dir[0], pa[1] + lo * dir[1], pa[2] + lo * dir[2]};
        const double ph[3] = {pa[0] + hi * dir[0], pa[1] + hi * dir[1], pa[2] + hi * dir[2]};
        add(&sc, shape, pl, qb, 1);
        add(&sc, shape, ph, qb, 1);
    }
    assert_true(check_against_oracle(&sc) >= 30);
    scene_free(&sc);
}

/* Bodies crossing edge to edge, no vertex of either inside the other (the
 * kernel's edge test), and their touching neighbours: two slabs in a cross
 * (b turned by the exact quaternion (1/2, 1/2, 1/2, 1/2), which takes x to
 * y, y to z, z to x), moved until faces, edges and vertices touch and one
 * ulp beyond; then at random orientations, pairs of edges turned against
 * each other, bisected (oracle) to touching, an ulp either side and crossing
 * deeper. */
static void test_edge_crossing(void **state) {
    (void)state;
    scene sc;
    scene_init(&sc, 256, 1);
    const double id[4] = {0, 0, 0, 1}, cyc[4] = {0.5, 0.5, 0.5, 0.5};
    const double UP = 1e300;
    /* b = [-1, 1] x [-2, 2] x [-0.5, 0.5] about pb, a = [-2, 2] x [-0.5, 0.5] x [-1, 1] */
    const struct {
        double pb[3];
        int expect;
    } cases[] = {
        {{0, 0, 0}, 1},        /* a cross: b's edges through a, a's through b */
        {{0.5, 0.25, 0.25}, 1}, /* off centre */
        {{0, 0, 1.5}, 1},      /* faces coplanar, touching over a square */
        {{0, 0, UP}, 0},       /* one ulp above */
        {{3, 0, 0}, 1},        /* b's face on a's end face */
        {{UP, 0, 0}, 0},
        {{1, 2.5, 1.5}, 1},    /* b's vertex on a's edge */
        {{1, 2.5, UP}, 0},
        {{3, 2.5, 1.5}, 1},    /* vertex on vertex */
        {{0, 0, 1.25}, 1},     /* b's lower edges through a, the rest above */
    };
    const double up_of[3] = {3, 2.5, 1.5}; /* what UP stands for, per axis */
    for (size_t k = 0; k < sizeof cases / sizeof cases[0]; ++k) {
        const double base[3] = {40.0 * (double)k, 0, 0};
        double pb[3];
        for (int i = 0; i < 3; ++i)
            pb[i] = cases[k].pb[i] == UP ? nextafter(base[i] + up_of[i], INFINITY) : base[i] + cases[k].pb[i];
        add(&sc, SLAB, base, id, 1);
        add(&sc, SLAB, pb, cyc, 1);
    }
    check_against_oracle(&sc);
    for (size_t k = 0; k < sizeof cases / sizeof cases[0]; ++k)
        assert_int_equal(reported(&sc, (uint32_t)(2 * k), (uint32_t)(2 * k + 1)), cases[k].expect);
    scene_free(&sc);

    /* Random edges against edges: b is a turned half a turn about an axis
     * normal to a's edge midpoint m (so b's copy of that edge faces a's) and
     * twisted about m first (so the two edges cross at an angle). */
    rng r = {2718};
    const int shapes_e[] = {BOX, SLAB, PARALLELEPIPED, HULL, ICOSAHEDRON, OFFBOX};
    scene_init(&sc, 200, 2);
    for (int k = 0; k < 24; ++k) {
        const int shape = shapes_e[next(&r) % 6];
        const oracle_mesh *m = &shapes[shape];
        const uint32_t *t = &m->tris[3 * (next(&r) % m->triangle_count)];
        const double *v0 = &m->verts[3 * t[0]], *v1 = &m->verts[3 * t[1]];
        const double mid[3] = {0.5 * (v0[0] + v1[0]), 0.5 * (v0[1] + v1[1]), 0.5 * (v0[2] + v1[2])};
        const double mn = sqrt(mid[0] * mid[0] + mid[1] * mid[1] + mid[2] * mid[2]);
        double qa[4], qb[4], q2[4], w[3] = {2 * unif(&r) - 1, 2 * unif(&r) - 1, 2 * unif(&r) - 1};
        random_unit_quaternion(&r, qa);
        const double mw = (w[0] * mid[0] + w[1] * mid[1] + w[2] * mid[2]) / (mn * mn);
        for (int i = 0; i < 3; ++i) w[i] -= mw * mid[i];
        const double wn = sqrt(w[0] * w[0] + w[1] * w[1] + w[2] * w[2]);
        const double half[4] = {w[0] / wn, w[1] / wn, w[2] / wn, 0};
        const double ang = 0.2 + 1.2 * unif(&r), sh = sin(0.5 * ang) / mn;
        const double twist[4] = {sh * mid[0], sh * mid[1], sh * mid[2], cos(0.5 * ang)};
        qmul(qa, half, q2);
        qmul(q2, twist, qb);
        const double vq[4] = {mid[0], mid[1], mid[2], 0}, conj[4] = {-qa[0], -qa[1], -qa[2], qa[3]};
        double t1[4], dir[4];
        qmul(qa, vq, t1);
        qmul(t1, conj, dir);
        const double pa[3] = {100.0 * k, 50, 0};
        double lo = 0, hi = 4; /* the midpoints meet at t = 2 */
        for (int it = 0; it < 64; ++it) {
            const double h = 0.5 * (lo + hi);
            if (h == lo || h == hi) break;
            const double pb[3] = {pa[0] + h * dir[0], pa[1] + h * dir[1], pa[2] + h * dir[2]};
            if (oracle_pair(shape, pa, qa, 1, shape, pb, qb, 1)) lo = h;
            else hi = h;
        }
        add(&sc, shape, pa, qa, 1);
        const double ts[3] = {lo, hi, 0.97 * lo};
        for (int j = 0; j < 3; ++j) {
            const double pb[3] = {pa[0] + ts[j] * dir[0], pa[1] + ts[j] * dir[1], pa[2] + ts[j] * dir[2]};
            add(&sc, shape, pb, qb, 1);
        }
    }
    assert_true(check_against_oracle(&sc) >= 24);
    scene_free(&sc);
}

/* Pairs the convex kernel must settle alone (no exact triangle test): boxes
 * apart only along the cross product of two edges, boxes and icospheres deep
 * in each other (surfaces cross), and each inside a larger one (containment,
 * counted as such). With the oracle's verdicts. */
static void test_kernel_decides(void **state) {
    (void)state;
    const double s2 = sqrt(0.5);
    const double h = 0.39269908169872414; /* pi / 8 */
    const double qz[4] = {0, 0, sin(h), cos(h)}, qy[4] = {0, sin(h), 0, cos(h)};
    const double q1[4] = {0.1, 0.2, 0.3, sqrt(1 - 0.14)}, id[4] = {0, 0, 0, 1};
    struct {
        int a, b;
        const double *qa, *qb;
        double xb, sb;
        size_t pairs, containment;
    } cases[] = {
        {BOX, BOX, qz, qy, 4 * s2 + 0.05, 1, 0, 0},  /* an edge of each towards the other, apart */
        {BOX, BOX, qz, qy, 4 * s2 - 0.05, 1, 1, 0},  /* the same edges crossing */
        {BOX, BOX, id, q1, 1.2, 1, 1, 0},            /* deep */
        {ICOSPHERE, ICOSPHERE, id, q1, 1.1, 1, 1, 0},
        {ICOSPHERE, BOX, q1, id, 1.5, 0.7, 1, 0},
        {BOX, BOX, q1, id, 0.1, 0.3, 1, 1},          /* containment */
        {ICOSPHERE, ICOSPHERE, q1, id, 0.2, 0.5, 1, 1},
        {BOX, ICOSPHERE, q1, qz, 0.1, 0.4, 1, 1},
    };
    /* The whole pair turned by r0, so that no box of world vertices parts
     * the apart pair. */
    const double r0[4] = {0.3, -0.4, 0.5, sqrt(0.5)};
    for (size_t c = 0; c < sizeof cases / sizeof cases[0]; ++c) {
        scene sc;
        scene_init(&sc, 2, 1);
        /* (the two edge cases off the line of centres, which would part them) */
        const double pa[3] = {0, 0, 0}, v[3] = {cases[c].xb, c < 2 ? 0.6 : 0.01, c < 2 ? 0.5 : -0.02};
        double qa[4], qb[4], t[3], pb[3];
        qmul(r0, cases[c].qa, qa);
        qmul(r0, cases[c].qb, qb);
        /* pb = v + 2 w (r x v) + 2 r x (r x v), r = r0's vector part */
        t[0] = 2 * (r0[1] * v[2] - r0[2] * v[1]);
        t[1] = 2 * (r0[2] * v[0] - r0[0] * v[2]);
        t[2] = 2 * (r0[0] * v[1] - r0[1] * v[0]);
        pb[0] = v[0] + r0[3] * t[0] + (r0[1] * t[2] - r0[2] * t[1]);
        pb[1] = v[1] + r0[3] * t[1] + (r0[2] * t[0] - r0[0] * t[2]);
        pb[2] = v[2] + r0[3] * t[2] + (r0[0] * t[1] - r0[1] * t[0]);
        add(&sc, cases[c].a, pa, qa, 1);
        add(&sc, cases[c].b, pb, qb, cases[c].sb);
        assert_int_equal(check_against_oracle(&sc), cases[c].pairs);
        assert_int_equal(hgcd_world_detect(sc.w), HGCD_OK);
        hgcd_stats st = {.struct_size = sizeof st};
        hgcd_world_stats(sc.w, &st);
        if (st.triangle_tests != 0 || st.containment_pairs != cases[c].containment)
            fprintf(stderr, "case %zu: %llu triangle tests, %llu containment\n", c,
                    (unsigned long long)st.triangle_tests, (unsigned long long)st.containment_pairs);
        assert_int_equal(st.colliding_pairs, cases[c].pairs);
        assert_int_equal(st.triangle_tests, 0);
        assert_int_equal(st.containment_pairs, cases[c].containment);
        scene_free(&sc);
    }
}

/* The scene globals back to their defaults before each test (a failed
 * assertion leaves a test without its own reset). */
static int reset_scene_globals(void **state) {
    (void)state;
    shared_meshes = 1;
    only_meshes = NULL;
    return 0;
}

int main(void) {
    make_shapes();
    const struct CMUnitTest tests[] = {
        cmocka_unit_test_setup(test_random_scenes, reset_scene_globals),
        cmocka_unit_test_setup(test_one_shape, reset_scene_globals),
        cmocka_unit_test_setup(test_few_shapes, reset_scene_globals),
        cmocka_unit_test_setup(test_convex_only, reset_scene_globals),
        cmocka_unit_test_setup(test_tetra_first, reset_scene_globals),
        cmocka_unit_test_setup(test_mesh_per_body, reset_scene_globals),
        cmocka_unit_test_setup(test_exact_contacts, reset_scene_globals),
        cmocka_unit_test_setup(test_hand_built, reset_scene_globals),
        cmocka_unit_test_setup(test_near_touching, reset_scene_globals),
        cmocka_unit_test_setup(test_resting_stacks, reset_scene_globals),
        cmocka_unit_test_setup(test_tip_to_tip, reset_scene_globals),
        cmocka_unit_test_setup(test_kernel_decides, reset_scene_globals),
        cmocka_unit_test_setup(test_edge_crossing, reset_scene_globals),
        cmocka_unit_test_setup(test_nearly_symmetric, reset_scene_globals),
    };
    if (getenv("HGCD_TEST_FILTER")) cmocka_set_test_filter(getenv("HGCD_TEST_FILTER"));
    return cmocka_run_group_tests(tests, NULL, NULL);
}
