/* The whole pipeline (grid + narrow phase) against the independent
 * brute-force oracle (tests/oracle.c: every body pair, every triangle pair,
 * containment, in exact rationals), on random scenes with every kind of mesh,
 * exact touching configurations, bodies larger than the coarsest level,
 * incremental motion, removal, and the tetra scene of docs/scenes.md. */
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
#include <hgcd/hgcd_scene.h>

#include "support/shapes.h"
#include "support/testing.h"
#include "oracle.h"

/* ------------------------------------------------------------- shapes -- */

enum { SHAPE_TETRA, SHAPE_CUBE, SHAPE_DENTED, SHAPE_TRIANGLE, SHAPE_BOWL, SHAPE_NEEDLE, SHAPE_TWIN, SHAPE_COUNT };


static oracle_mesh shapes[SHAPE_COUNT] = {
    {tetra_v, tetra_t, 4, 4, 1},   {cube_v, cube_t, 8, 12, 1},    {dented_v, dented_t, 9, 14, 1},
    {triangle_v, triangle_t, 3, 1, 0}, {cube_v, cube_t, 8, 10, 0}, {needle_v, needle_t, 4, 2, 0},
    {twin_v, twin_t, 8, 8, 1},
};

/* -------------------------------------------------------------- scene -- */

#include "test_rng.h"

/* A scene mirrored on the test side: what the oracle is given. */
typedef struct {
    hgcd_world *w;
    hgcd_mesh mesh[SHAPE_COUNT];
    size_t cap;
    int *shape;        /* per slot, -1 if no live body */
    hgcd_body *id;     /* per slot */
    double *pos, *quat, *scale;
} scene;

static void scene_init(scene *sc, size_t cap, const hgcd_world_desc *wd) {
    memset(sc, 0, sizeof *sc);
    assert_int_equal(hgcd_world_create(wd, &sc->w), HGCD_OK);
    for (int k = 0; k < SHAPE_COUNT; ++k) {
        hgcd_mesh_desc md = hgcd_mesh_desc_default();
        md.vertices = shapes[k].verts;
        md.triangles = shapes[k].tris;
        md.vertex_count = shapes[k].vertex_count;
        md.triangle_count = shapes[k].triangle_count;
        assert_int_equal(hgcd_mesh_create(sc->w, &md, &sc->mesh[k]), HGCD_OK);
    }
    sc->cap = cap;
    sc->shape = malloc(cap * sizeof(int));
    sc->id = calloc(cap, sizeof(hgcd_body));
    sc->pos = calloc(3 * cap, sizeof(double));
    sc->quat = calloc(4 * cap, sizeof(double));
    sc->scale = calloc(cap, sizeof(double));
    for (size_t i = 0; i < cap; ++i) sc->shape[i] = -1;
}

static void scene_free(scene *sc) {
    hgcd_world_destroy(sc->w);
    free(sc->shape);
    free(sc->id);
    free(sc->pos);
    free(sc->quat);
    free(sc->scale);
}

/* Exact rotations (entries 0, +-1 in R) give exactly touching faces and edges. */
static const double exact_quats[][4] = {{0, 0, 0, 1}, {1, 0, 0, 0}, {0, 1, 0, 0},
                                        {0, 0, 1, 0}, {0.5, 0.5, 0.5, 0.5}, {-0.5, 0.5, -0.5, 0.5}};

static void random_pose(rng *r, double side, int snap, double *p, double *q) {
    for (int k = 0; k < 3; ++k) {
        p[k] = side * unif(r);
        if (snap) p[k] = floor(p[k] * 2) / 2; /* multiples of 0.5 */
    }
    if (snap) {
        memcpy(q, exact_quats[next(r) % 6], 4 * sizeof(double));
    } else {
        const double u1 = unif(r), u2 = unif(r), u3 = unif(r);
        q[0] = sqrt(1 - u1) * sin(6.283185307179586 * u2);
        q[1] = sqrt(1 - u1) * cos(6.283185307179586 * u2);
        q[2] = sqrt(u1) * sin(6.283185307179586 * u3);
        q[3] = sqrt(u1) * cos(6.283185307179586 * u3);
    }
}

static void add(scene *sc, int shape, const double *p, const double *q, double scale) {
    hgcd_body_desc bd = hgcd_body_desc_default();
    bd.mesh = sc->mesh[shape];
    memcpy(bd.position, p, sizeof bd.position);
    memcpy(bd.orientation, q, sizeof bd.orientation);
    bd.scale = scale;
    bd.user_data = 0x5EED000000000000ull ^ (uint64_t)(scale * 1e6);
    hgcd_body b;
    assert_int_equal(hgcd_body_create(sc->w, &bd, &b), HGCD_OK);
    assert_true(b.index < sc->cap);
    sc->shape[b.index] = shape;
    sc->id[b.index] = b;
    memcpy(&sc->pos[3 * b.index], p, 3 * sizeof(double));
    memcpy(&sc->quat[4 * b.index], q, 4 * sizeof(double));
    sc->scale[b.index] = scale;
}

/* Every live body's state as the world reports it equals what the test
 * set: the world moves bodies' storage around (renumbering), their ids and
 * state must not move with it. */
static void check_bodies(const scene *sc) {
    for (size_t i = 0; i < sc->cap; ++i) {
        if (sc->shape[i] < 0) continue;
        double p[3], q[4];
        assert_int_equal(hgcd_body_get_pose(sc->w, sc->id[i], p, q), HGCD_OK);
        assert_memory_equal(p, &sc->pos[3 * i], sizeof p);
        assert_memory_equal(q, &sc->quat[4 * i], sizeof q);
        uint64_t u;
        assert_int_equal(hgcd_body_get_user_data(sc->w, sc->id[i], &u), HGCD_OK);
        assert_true(u == (0x5EED000000000000ull ^ (uint64_t)(sc->scale[i] * 1e6)));
        hgcd_mesh m;
        assert_int_equal(hgcd_body_get_mesh(sc->w, sc->id[i], &m), HGCD_OK);
        assert_int_equal(m.index, sc->mesh[sc->shape[i]].index);
    }
}

static void remove_body(scene *sc, size_t slot) {
    assert_int_equal(hgcd_body_destroy(sc->w, sc->id[slot]), HGCD_OK);
    sc->shape[slot] = -1;
}

static void move(scene *sc, size_t slot, const double *p, const double *q) {
    assert_int_equal(hgcd_body_set_pose(sc->w, sc->id[slot], p, q), HGCD_OK);
    memcpy(&sc->pos[3 * slot], p, 3 * sizeof(double));
    if (q) memcpy(&sc->quat[4 * slot], q, 4 * sizeof(double));
}

/* Detects and compares with the oracle, pair by pair. Returns the count. */
static size_t check_against_oracle(scene *sc) {
    assert_int_equal(hgcd_world_detect(sc->w), HGCD_OK);
    size_t live = 0;
    size_t *slot_of = malloc(sc->cap * sizeof(size_t));
    const oracle_mesh **meshes = malloc(sc->cap * sizeof(*meshes));
    double *p = malloc(3 * sc->cap * sizeof(double)), *q = malloc(4 * sc->cap * sizeof(double));
    double *s = malloc(sc->cap * sizeof(double));
    for (size_t i = 0; i < sc->cap; ++i) {
        if (sc->shape[i] < 0) continue;
        slot_of[live] = i;
        meshes[live] = &shapes[sc->shape[i]];
        memcpy(&p[3 * live], &sc->pos[3 * i], 3 * sizeof(double));
        memcpy(&q[4 * live], &sc->quat[4 * i], 4 * sizeof(double));
        s[live] = sc->scale[i];
        ++live;
    }
    const size_t n = oracle_colliding_pairs(live, meshes, p, q, s, NULL, 0);
    uint32_t *expect = malloc((2 * n + 2) * sizeof(uint32_t));
    assert_int_equal(oracle_colliding_pairs(live, meshes, p, q, s, expect, n), n);
    const hgcd_pair *got;
    size_t count;
    assert_int_equal(hgcd_world_pairs(sc->w, &got, &count), HGCD_OK);
    size_t mismatches = 0;
    for (size_t k = 0; k < n || k < count; ++k) {
        const int has_e = k < n, has_g = k < count;
        const size_t ea = has_e ? slot_of[expect[2 * k]] : 0, eb = has_e ? slot_of[expect[2 * k + 1]] : 0;
        if (!has_e || !has_g || got[k].a.index != ea || got[k].b.index != eb) {
            if (mismatches++ < 5)
                fprintf(stderr, "pair %zu: hgcd (%u, %u)%s, oracle (%zu, %zu)%s\n", k, has_g ? got[k].a.index : 0,
                        has_g ? got[k].b.index : 0, has_g ? "" : " none", ea, eb, has_e ? "" : " none");
        }
        if (has_g) {
            assert_int_equal(got[k].a.generation, sc->id[got[k].a.index].generation);
            assert_int_equal(got[k].b.generation, sc->id[got[k].b.index].generation);
        }
    }
    assert_int_equal(mismatches, 0);
    assert_int_equal(count, n);
    free(expect);
    free(slot_of);
    free(meshes);
    free(p);
    free(q);
    free(s);
    return n;
}

static void fill_random(scene *sc, rng *r, size_t n, double side, int snap, double smin, double smax) {
    for (size_t i = 0; i < n; ++i) {
        double p[3], q[4];
        random_pose(r, side, snap, p, q);
        const int shape = (int)(next(r) % SHAPE_COUNT);
        double scale = smin + (smax - smin) * unif(r);
        if (snap) scale = 0.5 + 0.5 * (double)(next(r) % 3); /* 0.5, 1, 1.5: exact contacts */
        add(sc, shape, p, q, scale);
    }
}

/* -------------------------------------------------------------- tests -- */

static void test_random_scenes(void **state) {
    (void)state;
    size_t total = 0;
    for (uint64_t seed = 1; seed <= 6; ++seed) {
        rng r = {seed};
        scene sc;
        hgcd_world_desc wd = hgcd_world_desc_default();
        wd.thread_count = (uint32_t)(seed % 3) + 1;
        scene_init(&sc, 400, &wd);
        fill_random(&sc, &r, 400, 30, 0, 0.2, 3.0);
        total += check_against_oracle(&sc);
        scene_free(&sc);
    }
    assert_true(total > 200); /* the scenes are dense enough to mean something */
}

static void test_exact_contacts(void **state) {
    (void)state;
    /* Positions on a 0.5 grid, axis-aligned exact rotations and scales in
     * {0.5, 1, 1.5}: faces, edges and vertices touch exactly, coplanar faces
     * overlap, and the oracle decides every such case exactly. */
    size_t total = 0;
    for (uint64_t seed = 10; seed < 16; ++seed) {
        rng r = {seed};
        scene sc;
        hgcd_world_desc wd = hgcd_world_desc_default();
        scene_init(&sc, 300, &wd);
        fill_random(&sc, &r, 300, 12, 1, 0, 0);
        total += check_against_oracle(&sc);
        scene_free(&sc);
    }
    assert_true(total > 500);
}

static void test_hand_built_pairs(void **state) {
    (void)state;
    scene sc;
    hgcd_world_desc wd = hgcd_world_desc_default();
    scene_init(&sc, 16, &wd);
    const double id[4] = {0, 0, 0, 1};
    const double o[3] = {0, 0, 0};
    const double face[3] = {2, 0, 0};      /* cube touching cube face to face */
    const double far[3] = {40, 40, 40};
    const double near_far[3] = {40.5, 40, 40};
    add(&sc, SHAPE_CUBE, o, id, 1);         /* 0 */
    add(&sc, SHAPE_CUBE, face, id, 1);      /* 1: touches 0 exactly */
    add(&sc, SHAPE_TETRA, o, id, 0.25);     /* 2: inside cube 0 (containment) */
    add(&sc, SHAPE_TRIANGLE, far, id, 0.1); /* 3: open triangle inside cube 4 */
    add(&sc, SHAPE_CUBE, far, id, 1);       /* 4 */
    add(&sc, SHAPE_BOWL, near_far, id, 3);  /* 5: open bowl around cube 4, surfaces apart? */
    const size_t n = check_against_oracle(&sc);
    const hgcd_pair *p;
    size_t count;
    assert_int_equal(hgcd_world_pairs(sc.w, &p, &count), HGCD_OK);
    /* (0,1) touch, (0,2) containment, (3,4) open surface inside a closed solid. */
    int seen01 = 0, seen02 = 0, seen34 = 0, seen12 = 0;
    for (size_t k = 0; k < count; ++k) {
        seen01 |= p[k].a.index == 0 && p[k].b.index == 1;
        seen02 |= p[k].a.index == 0 && p[k].b.index == 2;
        seen34 |= p[k].a.index == 3 && p[k].b.index == 4;
        seen12 |= p[k].a.index == 1 && p[k].b.index == 2;
    }
    assert_true(seen01 && seen02 && seen34);
    assert_false(seen12);
    assert_true(n >= 3);
    hgcd_stats st;
    st.struct_size = sizeof st;
    assert_int_equal(hgcd_world_stats(sc.w, &st), HGCD_OK);
    assert_true(st.containment_pairs >= 2);
    scene_free(&sc);
}

static void test_oversize_and_cell_limits(void **state) {
    (void)state;
    /* The same random scene with bodies up to 40 units across, under the
     * adaptive grid, a grid capped at cell width 1 (most bodies oversize),
     * and a grid with a large minimum cell. All must match the oracle. */
    const double limits[3][2] = {{0, 0}, {0, 1}, {8, 0}};
    for (int k = 0; k < 3; ++k) {
        rng r = {77};
        scene sc;
        hgcd_world_desc wd = hgcd_world_desc_default();
        wd.min_cell_size = limits[k][0];
        wd.max_cell_size = limits[k][1];
        scene_init(&sc, 300, &wd);
        fill_random(&sc, &r, 280, 60, 0, 0.1, 1.0);
        for (int i = 0; i < 20; ++i) { /* a few giants */
            double p[3], q[4];
            random_pose(&r, 60, 0, p, q);
            add(&sc, (int)(next(&r) % SHAPE_COUNT), p, q, 5 + 15 * unif(&r));
        }
        check_against_oracle(&sc);
        hgcd_stats st;
        st.struct_size = sizeof st;
        assert_int_equal(hgcd_world_stats(sc.w, &st), HGCD_OK);
        if (k == 1) assert_true(st.oversize_count > 100);
        if (k == 0) assert_int_equal(st.oversize_count, 0);
        scene_free(&sc);
    }
}

static void test_incremental_motion(void **state) {
    (void)state;
    /* Bodies teleported across many cells, nudged within cells, removed and
     * re-created (reusing slots), over several ticks: every tick matches. */
    rng r = {99};
    scene sc;
    hgcd_world_desc wd = hgcd_world_desc_default();
    wd.thread_count = 2;
    scene_init(&sc, 400, &wd);
    fill_random(&sc, &r, 300, 25, 0, 0.2, 2.5);
    check_against_oracle(&sc);
    for (int tick = 0; tick < 8; ++tick) {
        for (size_t i = 0; i < sc.cap; ++i) {
            if (sc.shape[i] < 0) continue;
            const uint64_t what = next(&r) % 10;
            double p[3], q[4];
            if (what == 0) { /* teleport */
                random_pose(&r, 25, 0, p, q);
                move(&sc, i, p, q);
            } else if (what < 4) { /* nudge */
                for (int k = 0; k < 3; ++k) p[k] = sc.pos[3 * i + k] + 0.3 * (unif(&r) - 0.5);
                move(&sc, i, p, NULL);
            } else if (what == 4 && tick % 2 == 0) {
                remove_body(&sc, i);
            }
        }
        for (int k = 0; k < 20; ++k) { /* re-create into freed slots */
            double p[3], q[4];
            random_pose(&r, 25, 0, p, q);
            add(&sc, (int)(next(&r) % SHAPE_COUNT), p, q, 0.2 + 2.3 * unif(&r));
        }
        check_against_oracle(&sc);
        check_bodies(&sc);
    }
    /* One body marched across the whole scene in small steps. */
    size_t walker = 0;
    while (sc.shape[walker] < 0) ++walker;
    for (int stepi = 0; stepi < 40; ++stepi) {
        double p[3] = {-2 + 0.8 * stepi, 12.5, 12.5};
        move(&sc, walker, p, NULL);
        check_against_oracle(&sc);
    }
    scene_free(&sc);
}

/* Bodies i and j trade their x coordinates. */
static void swap_x(scene *sc, size_t i, size_t j) {
    const double pi[3] = {sc->pos[3 * j], sc->pos[3 * i + 1], sc->pos[3 * i + 2]};
    const double pj[3] = {sc->pos[3 * i], sc->pos[3 * j + 1], sc->pos[3 * j + 2]};
    move(sc, i, pi, NULL);
    move(sc, j, pj, NULL);
}

static void test_row_reversed(void **state) {
    (void)state;
    /* Bodies on one line along x share a grid row; a second line just across
     * the plane y = 0 (a row boundary at every level) lies in the row next
     * to it and overlaps it. Mirroring the first line reverses its row's
     * order at once (more than the insertion sort of the grid's update may
     * take on, so the row is sorted outright, its sweep floors too), then a
     * random shuffle, then single swaps: every detect matches the oracle. */
    rng r = {4242};
    scene sc;
    hgcd_world_desc wd = hgcd_world_desc_default();
    wd.thread_count = 2;
    const size_t n = 300, m = 100;
    const double y = 0.05, z = 0.5; /* (the rows later in the sweep are read through their floors) */
    scene_init(&sc, n + m, &wd);
    const double q[4] = {0, 0, 0, 1};
    for (size_t i = 0; i < n; ++i) {
        const double p[3] = {0.2 * (double)i, y, z};
        add(&sc, (int)(i % SHAPE_COUNT), p, q, 0.3);
    }
    for (size_t i = 0; i < m; ++i) { /* the second line, never moved */
        const double p[3] = {0.6 * (double)i + 0.1, -y, z};
        add(&sc, (int)(i % SHAPE_COUNT), p, q, 0.3);
    }
    assert_true(check_against_oracle(&sc) > n / 2);
    for (size_t i = 0; i < n; ++i) {
        const double p[3] = {0.2 * (double)(n - 1) - sc.pos[3 * i], y, z};
        move(&sc, i, p, NULL);
    }
    assert_true(check_against_oracle(&sc) > n / 2);
    for (size_t i = n - 1; i > 0; --i) /* Fisher-Yates over the x positions */
        swap_x(&sc, i, (size_t)(next(&r) % (i + 1)));
    check_against_oracle(&sc);
    for (int k = 0; k < 5; ++k) {
        swap_x(&sc, (size_t)(next(&r) % n), (size_t)(next(&r) % n));
        check_against_oracle(&sc);
    }
    check_bodies(&sc);
    scene_free(&sc);
}

static void test_step_matches_oracle(void **state) {
    (void)state;
    /* Motion through hgcd_world_step (reflecting at the bounds), mirrored on
     * the test side with the formula of docs/scenes.md. */
    rng r = {5};
    scene sc;
    hgcd_world_desc wd = hgcd_world_desc_default();
    wd.reflect_at_bounds = 1;
    for (int k = 0; k < 3; ++k) {
        wd.bounds_min[k] = 0;
        wd.bounds_max[k] = 20;
    }
    scene_init(&sc, 250, &wd);
    fill_random(&sc, &r, 250, 20, 0, 0.3, 2.0);
    double *vel = malloc(3 * 250 * sizeof(double));
    for (size_t i = 0; i < 250; ++i) {
        for (int k = 0; k < 3; ++k) vel[3 * i + k] = 1.5 * (2 * unif(&r) - 1);
        assert_int_equal(hgcd_body_set_velocity(sc.w, sc.id[i], &vel[3 * i]), HGCD_OK);
    }
    for (int tick = 0; tick < 6; ++tick) {
        assert_int_equal(hgcd_world_step(sc.w), HGCD_OK);
        for (size_t k = 0; k < 3 * 250; ++k) {
            double x = sc.pos[k] + vel[k];
            if (x < 0) { x = -x; vel[k] = -vel[k]; }
            else if (x > 20) { x = 2 * 20.0 - x; vel[k] = -vel[k]; }
            sc.pos[k] = x;
        }
        for (size_t i = 0; i < 250; ++i) {
            double p[3];
            assert_int_equal(hgcd_body_get_pose(sc.w, sc.id[i], p, NULL), HGCD_OK);
            assert_memory_equal(p, &sc.pos[3 * i], sizeof p);
        }
        check_against_oracle(&sc);
    }
    free(vel);
    scene_free(&sc);
}

/* The tetra scene of docs/scenes.md in a world with the given threads (scene
 * object i in slot i, with user data i). */
static hgcd_world *tetra_world(const hgcd_scene_tetra_desc *sd, uint32_t threads) {
    hgcd_world_desc wd = hgcd_world_desc_default();
    wd.thread_count = threads;
    hgcd_world *w;
    assert_int_equal(hgcd_world_create(&wd, &w), HGCD_OK);
    assert_int_equal(hgcd_scene_tetra_populate(w, sd, NULL), HGCD_OK);
    assert_int_equal(hgcd_world_body_count(w), sd->n);
    return w;
}

/* Each pair's bodies carry their scene index as user data: slot i is object i. */
static void assert_slots_are_objects(hgcd_world *w, const hgcd_pair *p, size_t count) {
    for (size_t k = 0; k < count; ++k) {
        uint64_t ua, ub;
        assert_int_equal(hgcd_body_get_user_data(w, p[k].a, &ua), HGCD_OK);
        assert_int_equal(hgcd_body_get_user_data(w, p[k].b, &ub), HGCD_OK);
        assert_int_equal(ua, p[k].a.index);
        assert_int_equal(ub, p[k].b.index);
    }
}

static void test_tetra_scene(void **state) {
    (void)state;
    const char *env = getenv("HGCD_TEST_TETRA_N");
    const uint64_t n = env ? strtoull(env, NULL, 10) : 20000;
    hgcd_scene_tetra_desc sd = hgcd_scene_tetra_desc_default();
    sd.n = n;
    double *c = malloc(3 * n * sizeof(double)), *s = malloc(n * sizeof(double));
    double *q = malloc(4 * n * sizeof(double));
    assert_int_equal(hgcd_scene_tetra_generate(&sd, c, NULL, s, q, NULL), HGCD_OK);
    hgcd_world *w = tetra_world(&sd, 2);
    assert_int_equal(hgcd_world_detect(w), HGCD_OK);
    const hgcd_pair *p;
    size_t count;
    assert_int_equal(hgcd_world_pairs(w, &p, &count), HGCD_OK);
    assert_slots_are_objects(w, p, count);

    oracle_mesh tm = {tetra_v, tetra_t, 4, 4, 1};
    const oracle_mesh **meshes = malloc(n * sizeof(*meshes));
    for (uint64_t i = 0; i < n; ++i) meshes[i] = &tm;
    const size_t expect_n = oracle_colliding_pairs(n, meshes, c, q, s, NULL, 0);
    uint32_t *expect = malloc((2 * expect_n + 2) * sizeof(uint32_t));
    oracle_colliding_pairs(n, meshes, c, q, s, expect, expect_n);
    assert_int_equal(count, expect_n);
    for (size_t k = 0; k < count; ++k) {
        assert_int_equal(p[k].a.index, expect[2 * k]);
        assert_int_equal(p[k].b.index, expect[2 * k + 1]);
    }
    printf("tetra n = %llu seed 1: %zu colliding pairs, equal to the oracle\n", (unsigned long long)n, count);
    hgcd_world_destroy(w);
    free(meshes);
    free(expect);
    free(c);
    free(s);
    free(q);
}

/* Pair indices only: generations carry a per-world tag, so they differ
 * between worlds by design. */
static uint32_t *pair_indices(const hgcd_pair *p, size_t count) {
    uint32_t *out = malloc((2 * count + 1) * sizeof *out);
    for (size_t k = 0; k < count; ++k) {
        out[2 * k] = p[k].a.index;
        out[2 * k + 1] = p[k].b.index;
    }
    return out;
}

static void test_thread_counts_identical(void **state) {
    (void)state;
    /* Pairs are bit-identical, in order, for 1, 2, 3 and 8 threads, on the
     * tetra scene and on a mixed random scene with oversize bodies. */
    const uint64_t n = 30000;
    hgcd_scene_tetra_desc sd = hgcd_scene_tetra_desc_default();
    sd.n = n;
    sd.side = 100; /* denser than the default at this n */
    uint32_t *first = NULL;
    size_t first_n = 0;
    const uint32_t threads[4] = {1, 2, 3, 8};
    for (int k = 0; k < 4; ++k) {
        hgcd_world *w = tetra_world(&sd, threads[k]);
        assert_int_equal(hgcd_world_detect(w), HGCD_OK);
        const hgcd_pair *p;
        size_t count;
        assert_int_equal(hgcd_world_pairs(w, &p, &count), HGCD_OK);
        assert_slots_are_objects(w, p, count);
        assert_true(count > 1000);
        uint32_t *idx = pair_indices(p, count);
        if (k == 0) {
            first = idx;
            first_n = count;
        } else {
            assert_int_equal(count, first_n);
            assert_memory_equal(idx, first, 2 * count * sizeof *idx);
            free(idx);
        }
        hgcd_world_destroy(w);
    }
    free(first);

    uint32_t *hash = NULL;
    for (int k = 0; k < 4; ++k) {
        rng r = {123};
        scene sc;
        hgcd_world_desc wd = hgcd_world_desc_default();
        wd.thread_count = threads[k];
        wd.max_cell_size = 2;
        scene_init(&sc, 2000, &wd);
        fill_random(&sc, &r, 2000, 60, 0, 0.2, 4);
        assert_int_equal(hgcd_world_detect(sc.w), HGCD_OK);
        const hgcd_pair *p;
        size_t count;
        assert_int_equal(hgcd_world_pairs(sc.w, &p, &count), HGCD_OK);
        assert_true(count > 100);
        uint32_t *idx = pair_indices(p, count);
        if (!hash) {
            hash = idx;
            first_n = count;
        } else {
            assert_int_equal(count, first_n);
            assert_memory_equal(idx, hash, 2 * count * sizeof *idx);
            free(idx);
        }
        scene_free(&sc);
    }
    free(hash);
}

static void test_tetra_reference_counts(void **state) {
    (void)state;
    /* The reference answers of docs/scenes.md (exact, computed independently). */
    static const struct { uint64_t n, pairs, containment; } ref[] = {{100000, 4266, 30}, {200000, 17201, 151}};
    for (int k = 0; k < 2; ++k) {
        const uint64_t n = ref[k].n;
        hgcd_scene_tetra_desc sd = hgcd_scene_tetra_desc_default();
        sd.n = n;
        hgcd_world *w = tetra_world(&sd, 0);
        assert_int_equal(hgcd_world_detect(w), HGCD_OK);
        hgcd_stats st;
        st.struct_size = sizeof st;
        assert_int_equal(hgcd_world_stats(w, &st), HGCD_OK);
        assert_int_equal(st.colliding_pairs, ref[k].pairs);
        assert_int_equal(st.containment_pairs, ref[k].containment);
        hgcd_world_destroy(w);
    }
}


/* The dedicated path for pairs of 4-vertex meshes whose triangles are the 4
 * faces (narrow/tetra.hpp, collide_tetra): proper, flat, collinear and repeated-point
 * tetrahedra, and one whose orientation only the exact orient3d tells, with
 * faces in several orders and orientations, placed to touch
 * exactly (shared vertex, edge and face, coplanar faces, one inside the other,
 * flat inside solid) and then on a 0.5 grid with exact rotations. Pairs and
 * containment counts must equal the oracle's. */
enum { TV_REGULAR, TV_CORNER, TV_MIRROR, TV_FLAT_QUAD, TV_FLAT_TRI, TV_LINE, TV_BENT, TV_REPEAT, TV_NEAR_FLAT, TV_NEAR_FLAT_MIRROR, TV_COUNT };
static const double tv_v[TV_COUNT][12] = {
    {1, 1, 1, 1, -1, -1, -1, 1, -1, -1, -1, 1},
    {0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1},
    {0, 0, 0, -1, 0, 0, 0, 1, 0, 0, 0, 1},     /* the corner mirrored in x = 0 */
    {0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0},      /* coplanar, convex position */
    {0, 0, 0, 2, 0, 0, 0, 2, 0, 0.5, 0.5, 0},  /* coplanar, one point inside */
    {0, 0, 0, 1, 0, 0, 2, 0, 0, 3, 0, 0},      /* collinear */
    {0, 0, 0, 1, 0, 0, 2, 0, 0, 0, 1, 0},      /* three collinear */
    {0, 0, 0, 0, 0, 0, 1, 0, 0, 0, 1, 1},      /* a repeated point */
    {0, 0, 0, 1, 0, 0, 0, 1, 0, 1, 1, 1e-200}, /* a proper tetrahedron too flat for the filters' bounds */
    {0, 0, 0, 0, 1, 0, 1, 0, 0, 1, 1, 1e-200}, /* the same, the other orientation */
};
static const uint32_t tv_t[3][12] = {
    {0, 1, 2, 0, 3, 1, 0, 2, 3, 1, 3, 2},
    {0, 2, 1, 0, 1, 3, 1, 2, 3, 0, 3, 2},
    {3, 2, 1, 2, 3, 0, 1, 0, 3, 0, 1, 2},
};

typedef struct {
    hgcd_world *w;
    hgcd_mesh mesh[TV_COUNT];
    oracle_mesh om[TV_COUNT];
    size_t n, cap;
    const oracle_mesh **bm;
    double *p, *q, *s;
} tv_scene;

/* Meshes 0..count-1 from vertex sets v (at most TV_COUNT). */
static void tv_init_with(tv_scene *sc, size_t cap, const double (*v)[12], int count) {
    memset(sc, 0, sizeof *sc);
    hgcd_world_desc wd = hgcd_world_desc_default();
    assert_int_equal(hgcd_world_create(&wd, &sc->w), HGCD_OK);
    for (int k = 0; k < count; ++k) {
        const oracle_mesh om = {v[k], tv_t[k % 3], 4, 4, 1};
        sc->om[k] = om;
        hgcd_mesh_desc md = hgcd_mesh_desc_default();
        md.vertices = v[k];
        md.triangles = tv_t[k % 3];
        md.vertex_count = 4;
        md.triangle_count = 4;
        assert_int_equal(hgcd_mesh_create(sc->w, &md, &sc->mesh[k]), HGCD_OK);
    }
    sc->cap = cap;
    sc->bm = malloc(cap * sizeof *sc->bm);
    sc->p = malloc(3 * cap * sizeof(double));
    sc->q = malloc(4 * cap * sizeof(double));
    sc->s = malloc(cap * sizeof(double));
}

static void tv_init(tv_scene *sc, size_t cap) { tv_init_with(sc, cap, tv_v, TV_COUNT); }

static void tv_add(tv_scene *sc, int shape, double x, double y, double z, const double *q, double scale) {
    assert_true(sc->n < sc->cap);
    hgcd_body_desc bd = hgcd_body_desc_default();
    bd.mesh = sc->mesh[shape];
    bd.position[0] = x;
    bd.position[1] = y;
    bd.position[2] = z;
    memcpy(bd.orientation, q, sizeof bd.orientation);
    bd.scale = scale;
    hgcd_body b;
    assert_int_equal(hgcd_body_create(sc->w, &bd, &b), HGCD_OK);
    assert_int_equal(b.index, sc->n);
    sc->bm[sc->n] = &sc->om[shape];
    memcpy(&sc->p[3 * sc->n], bd.position, 3 * sizeof(double));
    memcpy(&sc->q[4 * sc->n], q, 4 * sizeof(double));
    sc->s[sc->n] = scale;
    ++sc->n;
}

/* Compares pairs and containment count with the oracle; returns the pairs. */
static size_t tv_check(tv_scene *sc, int (*has)[2], size_t expect_count) {
    assert_int_equal(hgcd_world_detect(sc->w), HGCD_OK);
    const size_t n = oracle_colliding_pairs(sc->n, sc->bm, sc->p, sc->q, sc->s, NULL, 0);
    uint32_t *expect = malloc((2 * n + 2) * sizeof(uint32_t));
    assert_int_equal(oracle_colliding_pairs(sc->n, sc->bm, sc->p, sc->q, sc->s, expect, n), n);
    const hgcd_pair *got;
    size_t count;
    assert_int_equal(hgcd_world_pairs(sc->w, &got, &count), HGCD_OK);
    assert_int_equal(count, n);
    for (size_t k = 0; k < n; ++k) {
        if (got[k].a.index != expect[2 * k] || got[k].b.index != expect[2 * k + 1])
            fprintf(stderr, "tetra pair %zu: hgcd (%u, %u), oracle (%u, %u)\n", k, got[k].a.index, got[k].b.index,
                    expect[2 * k], expect[2 * k + 1]);
        assert_int_equal(got[k].a.index, expect[2 * k]);
        assert_int_equal(got[k].b.index, expect[2 * k + 1]);
    }
    for (size_t e = 0; e < expect_count; ++e) { /* the configurations meant to touch do */
        int seen = 0;
        for (size_t k = 0; k < n; ++k) seen |= got[k].a.index == (uint32_t)has[e][0] && got[k].b.index == (uint32_t)has[e][1];
        if (!seen) fprintf(stderr, "expected pair (%d, %d) missing\n", has[e][0], has[e][1]);
        assert_true(seen);
    }
    hgcd_stats st;
    st.struct_size = sizeof st;
    assert_int_equal(hgcd_world_stats(sc->w, &st), HGCD_OK);
    assert_int_equal(st.containment_pairs, oracle_last_containment_pairs());
    free(expect);
    return n;
}

static void tv_free(tv_scene *sc) {
    hgcd_world_destroy(sc->w);
    free(sc->bm);
    free(sc->p);
    free(sc->q);
    free(sc->s);
}

static void test_tetra_path_degenerate(void **state) {
    (void)state;
    const double id[4] = {0, 0, 0, 1}, rz[4] = {0, 0, 1, 0}, rx[4] = {1, 0, 0, 0};
    tv_scene sc;
    tv_init(&sc, 64);
    /* Each configuration 50 units from the others. */
    tv_add(&sc, TV_CORNER, 0, 0, 0, id, 1); /* 0, 1: share the vertex (1, 0, 0) only */
    tv_add(&sc, TV_CORNER, 1, 0, 0, id, 1);
    tv_add(&sc, TV_CORNER, 50, 0, 0, id, 1); /* 2, 3: share the face x = 50 */
    tv_add(&sc, TV_MIRROR, 50, 0, 0, id, 1);
    tv_add(&sc, TV_CORNER, 100, 0, 0, id, 1); /* 4, 5: coplanar faces z = 0 overlap, solids apart */
    tv_add(&sc, TV_CORNER, 100.25, 0.25, 0, rx, 1);
    tv_add(&sc, TV_REGULAR, 150, 0, 0, id, 1); /* 6, 7: one inside the other */
    tv_add(&sc, TV_REGULAR, 150, 0, 0, rz, 0.25);
    tv_add(&sc, TV_REGULAR, 200, 0, 0, id, 3); /* 8, 9: flat quad inside a solid */
    tv_add(&sc, TV_FLAT_QUAD, 200, 0, 0.5, id, 1);
    tv_add(&sc, TV_FLAT_QUAD, 250, 0, 0, id, 1); /* 10, 11: coplanar flat quads overlap */
    tv_add(&sc, TV_FLAT_QUAD, 250.5, 0.5, 0, rz, 1);
    tv_add(&sc, TV_FLAT_QUAD, 300, 0, 0, id, 1); /* 12, 13: parallel flat quads apart */
    tv_add(&sc, TV_FLAT_QUAD, 300, 0, 0.5, id, 1);
    tv_add(&sc, TV_CORNER, 350, 0, 0, id, 1); /* 14, 15: a segment through a face */
    tv_add(&sc, TV_LINE, 349.5, 0.25, 0.25, id, 1);
    tv_add(&sc, TV_CORNER, 400, 0, 0, id, 1); /* 16, 17: flat triangle's point on an edge */
    tv_add(&sc, TV_FLAT_TRI, 400.5, -0.5, 0, rz, 1);
    tv_add(&sc, TV_CORNER, 450, 0, 0, id, 1); /* 18, 19: repeated-point tetra inside, off the surface */
    tv_add(&sc, TV_REPEAT, 450.1, 0.1, 0.1, id, 0.25);
    tv_add(&sc, TV_CORNER, 500, 0, 0, id, 1); /* 20, 21: edge on edge, crossing */
    tv_add(&sc, TV_BENT, 500.5, -0.5, 0, rz, 1);
    tv_add(&sc, TV_REGULAR, 550, 0, 0, id, 1); /* 22, 23: one ulp apart along x */
    tv_add(&sc, TV_REGULAR, 552.0000000000001, 0, 0, rz, 1);
    int has[][2] = {{0, 1}, {2, 3}, {4, 5}, {6, 7}, {8, 9}, {10, 11}, {14, 15}, {18, 19}};
    tv_check(&sc, has, sizeof has / sizeof has[0]);
    tv_free(&sc);

    /* Dense exact grids of every variant. */
    const double r = 0.70710678118654757;
    const double quats[][4] = {{0, 0, 0, 1}, {1, 0, 0, 0}, {0, 1, 0, 0}, {0, 0, 1, 0},
                               {0.5, 0.5, 0.5, 0.5}, {-0.5, 0.5, -0.5, 0.5}, {0, 0, r, r}};
    size_t total = 0;
    for (uint64_t seed = 40; seed < 44; ++seed) {
        rng g = {seed};
        tv_init(&sc, 220);
        for (int i = 0; i < 220; ++i) {
            const double x = 0.5 * (double)(next(&g) % 9), y = 0.5 * (double)(next(&g) % 9),
                         z = 0.5 * (double)(next(&g) % 9);
            const int shape = (int)(next(&g) % TV_COUNT);
            const double scale = 0.5 * (double)(1 + next(&g) % 4);
            tv_add(&sc, shape, x, y, z, quats[next(&g) % (seed == 43 ? 7 : 6)], scale);
        }
        total += tv_check(&sc, NULL, 0);
        tv_free(&sc);
    }
    assert_true(total > 1000);
}

/* The tetra path's separating-axis prefilter along the line of centres
 * (narrow/tetra.hpp, collide_tetra_with) on pairs whose contact normal is that
 * line, so that the test is tight: the regular tetrahedron T (scale 3) and
 * -T with one rotation, B placed at A's position plus the rotated offset
 * (computed as a world vertex) where they touch vertex on vertex, edge across
 * edge, face on face and vertex on face, then moved by -3..3 ulps of each
 * coordinate along the offset. Exact rotations at small coordinates touch
 * exactly (and must be reported); random rotations and positions near 1e6
 * and 1e12 touch within rounding, so the step where the pair parts is a
 * 1-ulp gap. Pairs and containment must equal the oracle's. */
static void test_tetra_axis_prefilter(void **state) {
    (void)state;
    static const double shapes2[2][12] = {{1, 1, 1, 1, -1, -1, -1, 1, -1, -1, -1, 1},
                                          {-1, -1, -1, -1, 1, 1, 1, -1, 1, 1, 1, -1}};
    static const struct { int b_shape; double offset[3]; } config[4] = {
        {1, {6, 6, 6}},    /* vertex (3, 3, 3) on the vertex of -T */
        {0, {6, 0, 0}},    /* edge x = 3 of A across that of B, at (3, 0, 0) */
        {1, {-2, -2, -2}}, /* faces in the plane x + y + z = -3 */
        {0, {4, 4, 4}},    /* vertex (3, 3, 3) on the centre of B's face */
    };
    const double magnitude[5] = {10, 1e6, 1e9, 1e12, 5e14};
    enum { ROTATIONS = 16, STEPS = 7 };
    const size_t cap = 2 * 4 * 5 * ROTATIONS * STEPS;
    tv_scene sc;
    tv_init_with(&sc, cap, shapes2, 2);
    int(*has)[2] = malloc(cap * sizeof *has);
    size_t must = 0;
    rng g = {77};
    double x = 0; /* each pair 50 units along x from the last */
    for (int m = 0; m < 5; ++m)
        for (int rot = 0; rot < ROTATIONS; ++rot)
            for (int c = 0; c < 4; ++c) {
                double q[4] = {0, 0, 0, 1}, p[3];
                if (rot > 0) random_pose(&g, 1, 0, p, q);
                for (int k = 0; k < 3; ++k) {
                    p[k] = magnitude[m] + x;
                    if (m > 0) p[k] += unif(&g); /* inexact world vertices */
                }
                for (int step = -3; step <= 3; ++step) {
                    double pb[3], b[3];
                    oracle_world_vertex(p, q, 1.0, config[c].offset, pb);
                    for (int k = 0; k < 3; ++k) {
                        b[k] = pb[k];
                        const double away = pb[k] > p[k] ? INFINITY : -INFINITY;
                        for (int i = 0; i < abs(step); ++i) b[k] = nextafter(b[k], step > 0 ? away : -away);
                    }
                    if (m == 0 && rot == 0 && step == 0) {
                        has[must][0] = (int)sc.n;
                        has[must][1] = (int)sc.n + 1;
                        ++must;
                    }
                    tv_add(&sc, 0, p[0], p[1], p[2], q, 3);
                    tv_add(&sc, config[c].b_shape, b[0], b[1], b[2], q, 3);
                    x += 50;
                    for (int k = 0; k < 3; ++k) p[k] += 50;
                }
            }
    const size_t pairs = tv_check(&sc, has, must);
    printf("axis prefilter: %zu of %zu touching or apart by ulps collide, as the oracle says\n", pairs, sc.n / 2);
    assert_true(pairs > sc.n / 8 && pairs < 3 * sc.n / 8); /* both sides of contact are tested */
    free(has);
    tv_free(&sc);
}

/* The batched tetrahedron test (four pairs per AVX2 lane group, narrow/tetra_batch_avx2.cpp
 * collide_tetra_batch) against the one-pair test, pair by pair: verdicts and
 * the work counters (exact tests, triangle tests) must be equal. Pairs of
 * every shape of the degenerate scenes (flat, collinear, repeated-point,
 * nearly flat), in the same group as others, on a 0.5 grid with exact
 * rotations (touching exactly) or at random, near the origin and near 1e6. */
static void test_tetra_batch_matches_one_pair(void **state) {
    (void)state;
    enum { PAIRS = 39998 }; /* (not a multiple of 4: the batch's last group is partial) */
    uint32_t *pair_mesh = malloc(2 * PAIRS * sizeof(uint32_t));
    double *poses = malloc(16 * PAIRS * sizeof(double));
    rng g = {91};
    for (size_t k = 0; k < PAIRS; ++k) {
        const int snap = next(&g) % 2 == 0;
        const double far = next(&g) % 3 == 0 ? 1e6 : 0;
        double pa[3], pb[3];
        for (int side = 0; side < 2; ++side) {
            double *pose = poses + 16 * k + 8 * side;
            pair_mesh[2 * k + side] = (uint32_t)(next(&g) % TV_COUNT);
            random_pose(&g, 3, snap, side ? pb : pa, pose + 3);
            pose[7] = snap ? 0.5 * (double)(1 + next(&g) % 4) : 0.3 + 1.7 * unif(&g);
        }
        for (int c = 0; c < 3; ++c) {
            poses[16 * k + c] = far + pa[c];
            poses[16 * k + 8 + c] = far + pb[c];
        }
    }
    uint64_t counts[6];
    const int64_t differ = hgcdi_tetra_batch_check(&tv_v[0][0], TV_COUNT, pair_mesh, poses, PAIRS, counts);
    printf("batched tetra test: %llu of %d pairs collide (%llu by containment), %llu exact tests, %llu triangle "
           "tests, the same pair by pair\n",
           (unsigned long long)counts[4], PAIRS, (unsigned long long)counts[5], (unsigned long long)counts[0],
           (unsigned long long)counts[2]);
    assert_int_equal(differ, 0);
    assert_int_equal(counts[1], counts[0]);
    assert_int_equal(counts[3], counts[2]);
    /* Every kind of answer, and the exact path, were exercised. */
    assert_true(counts[4] > PAIRS / 10 && counts[4] < PAIRS - PAIRS / 10);
    assert_true(counts[5] > 0 && counts[2] > 0);
    free(pair_mesh);
    free(poses);
}

/* The batched test's float signs (narrow/tetra_batch_avx2.cpp, sides8) where the box holding
 * a pair is nearly flat: tetrahedra 1 wide and h high (h = 2^-90 .. 2^-160,
 * apex up or down), each pair with a vertex of b placed on a's slanted face
 * z = 2 h (1 - x - y) in double, then moved by up to 4 ulps of z, half of
 * them 1000 along x (coordinates that neither float nor the subtraction of
 * the box's corner hold exactly), so that the signs hang on heights that
 * float holds badly or not at all. A pair whose box's scaled volume is
 * below 2^-115 must take the double path, and every certified sign must be
 * right: the batch must agree with the one-pair test pair by pair. (Without
 * that guard, or with the float bound 2^-40 instead of 2^-15, pairs
 * differ; exactly representable placements, tried first, did not show it.) */
static void test_tetra_batch_nearly_flat(void **state) {
    (void)state;
    enum { HEIGHTS = 8, MESHES = 2 * HEIGHTS, PAIRS = 4000 };
    double meshes[MESHES][12];
    for (int m = 0; m < MESHES; ++m) {
        const double h = ldexp(1.0, -90 - 10 * (m / 2)) * (m % 2 ? -1 : 1);
        const double v[12] = {0, 0, 0, 1, 0, 0, 0, 1, 0, 0.25, 0.25, h};
        memcpy(meshes[m], v, sizeof v);
    }
    uint32_t *pair_mesh = malloc(2 * PAIRS * sizeof(uint32_t));
    double *poses = calloc(16 * PAIRS, sizeof(double));
    rng g = {97};
    for (size_t k = 0; k < PAIRS; ++k) {
        const uint32_t ma = (uint32_t)(next(&g) % MESHES), mb = (uint32_t)(next(&g) % MESHES);
        pair_mesh[2 * k] = ma;
        pair_mesh[2 * k + 1] = mb;
        const double h = meshes[ma][11];
        double *a = poses + 16 * k, *b = a + 8;
        a[6] = b[6] = 1; /* identity rotations */
        a[7] = b[7] = 1;
        b[0] = 0.5 * unif(&g);
        b[1] = 0.5 * unif(&g);
        b[2] = 2 * h * (1 - b[0] - b[1]);
        const int steps = (int)(next(&g) % 9) - 4;
        for (int i = 0; i < abs(steps); ++i) b[2] = nextafter(b[2], steps > 0 ? INFINITY : -INFINITY);
        b[0] = 1 - b[1] - b[2] / (2 * h);
        if (next(&g) % 2) {
            a[0] += 1000.0;
            b[0] += 1000.0;
        }
    }
    uint64_t counts[6];
    const int64_t differ = hgcdi_tetra_batch_check(&meshes[0][0], MESHES, pair_mesh, poses, PAIRS, counts);
    printf("nearly flat tetra pairs: %llu of %d collide, the same pair by pair\n", (unsigned long long)counts[4],
           PAIRS);
    assert_int_equal(differ, 0);
    assert_int_equal(counts[1], counts[0]);
    assert_int_equal(counts[3], counts[2]);
    assert_true(counts[4] > PAIRS / 20 && counts[4] < PAIRS - PAIRS / 20);
    free(pair_mesh);
    free(poses);
}

/* The caller's floating-point mode: flush-to-zero and denormals-are-zero (as
 * -ffast-math's start-up code sets), rounding toward +infinity, and traps on
 * invalid, divide-by-zero, overflow and underflow. The library works in IEEE's
 * default mode inside each call and gives the caller's back. */
#if defined(__x86_64__)
#include <xmmintrin.h>
#define HAVE_FP_MODE 1
typedef unsigned fp_mode;
static fp_mode fp_get(void) { return _mm_getcsr(); }
static void fp_set(fp_mode m) { _mm_setcsr(m); }
static fp_mode fp_hostile(fp_mode m) {
    /* FTZ (bit 15), DAZ (bit 6), rounding up (bits 13-14 = 10), exceptions
     * unmasked: invalid (7), divide-by-zero (9), overflow (10), underflow (11). */
    return ((m | 0x8040u | 0x4000u) & ~0x2000u) & ~(0x0080u | 0x0200u | 0x0400u | 0x0800u);
}
#elif defined(__aarch64__)
#define HAVE_FP_MODE 1
typedef uint64_t fp_mode;
static fp_mode fp_get(void) {
    uint64_t v;
    __asm__ __volatile__("mrs %0, fpcr" : "=r"(v));
    return v;
}
static void fp_set(fp_mode v) { __asm__ __volatile__("msr fpcr, %0" : : "r"(v)); }
static fp_mode fp_hostile(fp_mode m) {
    /* FZ (bit 24), rounding toward +infinity (bits 22-23 = 01), trap enables
     * for invalid, divide-by-zero, overflow, underflow (bits 8-11; hardware
     * without trapping ignores them). */
    return ((m | (1ull << 24) | (1ull << 22)) & ~(1ull << 23)) | (0xFull << 8);
}
#else
#define HAVE_FP_MODE 0
#endif


static void test_caller_fp_mode(void **state) {
    (void)state;
#if !HAVE_FP_MODE
    skip();
#else
    enum { N = 48 };
    static const int kinds[3] = {SHAPE_TETRA, SHAPE_CUBE, SHAPE_TRIANGLE};
    for (uint32_t threads = 1; threads <= 2; ++threads) {
        /* Bodies whose world coordinates are subnormal (about 2^-1050: under
         * DAZ every one of them reads as 0), drawn in the default mode. */
        rng r = {300 + threads};
        double p[3 * N], q[4 * N], s[N];
        const oracle_mesh *m[N];
        int shape[N];
        const double unit = ldexp(1.0, -1050);
        for (int i = 0; i < N; ++i) {
            random_pose(&r, 6, 0, &p[3 * i], &q[4 * i]);
            for (int k = 0; k < 3; ++k) p[3 * i + k] *= unit;
            s[i] = (0.5 + unif(&r)) * unit;
            shape[i] = kinds[next(&r) % 3];
            m[i] = &shapes[shape[i]];
        }
        const size_t n = oracle_colliding_pairs(N, m, p, q, s, NULL, 0);
        uint32_t *expect = malloc((2 * n + 2) * sizeof(uint32_t));
        assert_int_equal(oracle_colliding_pairs(N, m, p, q, s, expect, n), n);
        assert_true(n > 0 && n < N * (N - 1) / 2 / 2); /* not all pairs, as all coordinates 0 would give */

        hgcd_world_desc wd = hgcd_world_desc_default();
        wd.thread_count = threads;
        hgcd_mesh_desc md[3];
        for (int k = 0; k < 3; ++k) {
            md[k] = hgcd_mesh_desc_default();
            md[k].vertices = shapes[kinds[k]].verts;
            md[k].triangles = shapes[kinds[k]].tris;
            md[k].vertex_count = shapes[kinds[k]].vertex_count;
            md[k].triangle_count = shapes[kinds[k]].triangle_count;
        }
        hgcd_body_desc bd[N];
        for (int i = 0; i < N; ++i) {
            bd[i] = hgcd_body_desc_default();
            memcpy(bd[i].position, &p[3 * i], sizeof bd[i].position);
            memcpy(bd[i].orientation, &q[4 * i], sizeof bd[i].orientation);
            bd[i].scale = s[i];
        }
        /* Only library calls, and no arithmetic of the test's own, in the hostile mode. */
        const fp_mode saved = fp_get();
        fp_set(fp_hostile(saved));
        const fp_mode hostile = fp_get(); /* (as the hardware took it: arm64 cores without trapping drop those bits) */
#ifdef _OPENMP
        /* The host's own OpenMP region first: the runtime's threads, which
         * the library's regions reuse, start in the host's mode (this test
         * runs first in its process, before any thread exists). */
        int ran = 0;
#pragma omp parallel num_threads(4) reduction(+ : ran)
        ran += 1;
        (void)ran;
#endif
        hgcd_world *w = NULL;
        hgcd_status st = hgcd_world_create(&wd, &w);
        hgcd_mesh mesh[3];
        for (int k = 0; k < 3 && st == HGCD_OK; ++k) st = hgcd_mesh_create(w, &md[k], &mesh[k]);
        for (int i = 0; i < N && st == HGCD_OK; ++i) {
            hgcd_body b;
            bd[i].mesh = mesh[shape[i] == SHAPE_TETRA ? 0 : shape[i] == SHAPE_CUBE ? 1 : 2];
            st = hgcd_body_create(w, &bd[i], &b);
        }
        hgcd_status detect = HGCD_ERROR_INTERNAL, step = HGCD_ERROR_INTERNAL;
        if (st == HGCD_OK) detect = hgcd_world_detect(w);
        const hgcd_pair *first = NULL;
        size_t first_count = 0;
        if (detect == HGCD_OK) hgcd_world_pairs(w, &first, &first_count);
        hgcd_pair *copy = malloc((first_count + 1) * sizeof *copy);
        if (first_count) memcpy(copy, first, first_count * sizeof *copy);
        if (detect == HGCD_OK) step = hgcd_world_step(w); /* (no velocity: the same poses) */
        const fp_mode during = fp_get();
        fp_set(saved);

        assert_int_equal(st, HGCD_OK);
        assert_int_equal(detect, HGCD_OK);
        assert_int_equal(step, HGCD_OK);
        assert_true(during == hostile); /* the caller's mode given back */
        const hgcd_pair *got;
        size_t count;
        assert_int_equal(hgcd_world_pairs(w, &got, &count), HGCD_OK);
        assert_int_equal(first_count, n);
        assert_int_equal(count, n);
        for (size_t k = 0; k < n; ++k) {
            assert_int_equal(copy[k].a.index, expect[2 * k]);
            assert_int_equal(copy[k].b.index, expect[2 * k + 1]);
            assert_int_equal(got[k].a.index, expect[2 * k]);
            assert_int_equal(got[k].b.index, expect[2 * k + 1]);
        }
        printf("caller's mode FTZ/DAZ, rounding up, traps on (%u thread%s): %zu of %d pairs of subnormal bodies "
               "collide, as the oracle says\n",
               threads, threads > 1 ? "s" : "", n, N * (N - 1) / 2);
        free(copy);
        free(expect);
        hgcd_world_destroy(w);
    }
#endif
}

int main(void) {
    const struct CMUnitTest tests[] = {
        /* First: OpenMP's threads then start in the caller's hostile mode. */
        cmocka_unit_test(test_caller_fp_mode),
        cmocka_unit_test(test_hand_built_pairs),
        cmocka_unit_test(test_random_scenes),
        cmocka_unit_test(test_exact_contacts),
        cmocka_unit_test(test_oversize_and_cell_limits),
        cmocka_unit_test(test_incremental_motion),
        cmocka_unit_test(test_row_reversed),
        cmocka_unit_test(test_step_matches_oracle),
        cmocka_unit_test(test_thread_counts_identical),
        cmocka_unit_test(test_tetra_scene),
        cmocka_unit_test(test_tetra_reference_counts),
        cmocka_unit_test(test_tetra_path_degenerate),
        cmocka_unit_test(test_tetra_axis_prefilter),
        cmocka_unit_test(test_tetra_batch_matches_one_pair),
        cmocka_unit_test(test_tetra_batch_nearly_flat),
    };
    /* Sanitizer and valgrind runs pick tests by name (cmocka patterns). */
    if (getenv("HGCD_TEST_FILTER")) cmocka_set_test_filter(getenv("HGCD_TEST_FILTER"));
    if (getenv("HGCD_TEST_SKIP")) cmocka_set_skip_filter(getenv("HGCD_TEST_SKIP"));
    return cmocka_run_group_tests(tests, NULL, NULL);
}
