/* Scene queries (rays, boxes, points, meshes at a pose) against brute force
 * over every body and triangle in exact rationals (tests/oracle_query.c,
 * tests/oracle.c), on random scenes and on scenes snapped to integers,
 * where rays run through edges and vertices, along faces, and boxes and
 * points touch faces, edges and vertices; with random body filters, query
 * filters and disabled bodies; 1 and 2 threads, and a caller's task
 * system, give the same bits; bad input is refused without changing the
 * last results. Meshes of more than 48 triangles (SHAPE_FINE) take their
 * own tree's paths. */
#include <math.h>
#include <pthread.h>
#include <stdatomic.h>
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
#include "oracle_query.h"
#include "test_rng.h"

/* ------------------------------------------------------------- shapes -- */

enum { SHAPE_TETRA, SHAPE_CUBE, SHAPE_DENTED, SHAPE_TRIANGLE, SHAPE_BOWL, SHAPE_NEEDLE, SHAPE_TWIN, SHAPE_FINE,
       SHAPE_COUNT };


/* A cube [-1, 1]^3 whose faces are 4 x 4 grids (192 triangles, welded: a
 * closed mesh with a tree of its own). */
#define FINE_N 4
static double fine_v[3 * 6 * (FINE_N + 1) * (FINE_N + 1)];
static uint32_t fine_t[3 * 6 * FINE_N * FINE_N * 2];
static uint32_t fine_vc, fine_tc;

static uint32_t fine_vertex(const double *p) {
    uint32_t v;
    for (v = 0; v < fine_vc; ++v)
        if (fine_v[3 * v] == p[0] && fine_v[3 * v + 1] == p[1] && fine_v[3 * v + 2] == p[2]) return v;
    memcpy(&fine_v[3 * fine_vc], p, 3 * sizeof(double));
    return fine_vc++;
}

static void build_fine(void) {
    int axis, side, i, j;
    if (fine_tc) return;
    for (axis = 0; axis < 3; ++axis)
        for (side = 0; side < 2; ++side)
            for (i = 0; i < FINE_N; ++i)
                for (j = 0; j < FINE_N; ++j) {
                    uint32_t q[4];
                    int c;
                    for (c = 0; c < 4; ++c) {
                        const int di = c == 1 || c == 2, dj = c >= 2;
                        double p[3];
                        p[axis] = side ? 1 : -1;
                        p[(axis + 1) % 3] = -1 + 2.0 * (i + di) / FINE_N;
                        p[(axis + 2) % 3] = -1 + 2.0 * (j + dj) / FINE_N;
                        q[c] = fine_vertex(p);
                    }
                    {
                        const uint32_t t[6] = {q[0], q[1], q[2], q[0], q[2], q[3]};
                        memcpy(&fine_t[3 * fine_tc], t, sizeof t);
                        fine_tc += 2;
                    }
                }
}

static oracle_mesh shapes[SHAPE_COUNT] = {
    {tetra_v, tetra_t, 4, 4, 1},       {cube_v, cube_t, 8, 12, 1},       {dented_v, dented_t, 9, 14, 1},
    {triangle_v, triangle_t, 3, 1, 0}, {cube_v, cube_t, 8, 10, 0},       {needle_v, needle_t, 4, 2, 0},
    {twin_v, twin_t, 8, 8, 1},         {fine_v, fine_t, 0, 0, 1},
};

/* -------------------------------------------------------------- scene -- */

typedef struct {
    hgcd_world *w;
    hgcd_mesh mesh[SHAPE_COUNT];
    size_t n;
    int shape[256];
    double pos[256][3], quat[256][4], scale[256];
    double *wv[256]; /* world vertices, hgcd.h's formula */
    /* The query filter every query passes (NULL: none), and the bodies it
     * or their being disabled leaves out (what the oracle skips). */
    const hgcd_filter *qf;
    int skip[256];
} scene;

/* ------------------------------------------------------- task system -- */

/* A caller's task system of two workers: each loop's ranges are taken in
 * turn by a thread started for the loop (worker 1) and by the thread that
 * waits in finish_task (worker 0). */
typedef struct {
    hgcd_task_fn *task;
    void *context;
    uint32_t count, range;
    atomic_uint next;
    pthread_t thread;
} task_loop;

static atomic_uint task_loops; /* loops run on it */

static void task_drain(task_loop *l, uint32_t worker) {
    for (;;) {
        const uint32_t b = atomic_fetch_add(&l->next, l->range);
        if (b >= l->count) return;
        l->task(b, l->count - b > l->range ? b + l->range : l->count, worker, l->context);
    }
}

static void *task_thread(void *arg) {
    task_drain(arg, 1);
    return NULL;
}

static void *task_enqueue(hgcd_task_fn *task, uint32_t item_count, uint32_t min_range, void *task_context,
                          void *user_context) {
    task_loop *l = malloc(sizeof *l);
    (void)user_context;
    assert_non_null(l);
    l->task = task;
    l->context = task_context;
    l->count = item_count;
    l->range = (item_count + 7) / 8;
    if (l->range < min_range) l->range = min_range;
    if (l->range == 0) l->range = 1;
    atomic_init(&l->next, 0);
    atomic_fetch_add(&task_loops, 1);
    assert_int_equal(pthread_create(&l->thread, NULL, task_thread, l), 0);
    return l;
}

static void task_finish(void *handle, void *user_context) {
    task_loop *l = handle;
    (void)user_context;
    task_drain(l, 0);
    pthread_join(l->thread, NULL);
    free(l);
}

static int use_tasks; /* scene_init gives worlds the task system */

static const double exact_quats[][4] = {{0, 0, 0, 1}, {1, 0, 0, 0}, {0, 1, 0, 0}, {0, 0, 1, 0}};

static void scene_init(scene *sc, uint32_t threads) {
    hgcd_world_desc wd = hgcd_world_desc_default();
    int k;
    build_fine();
    shapes[SHAPE_FINE].vertex_count = fine_vc;
    shapes[SHAPE_FINE].triangle_count = fine_tc;
    memset(sc, 0, sizeof *sc);
    wd.thread_count = threads;
    if (use_tasks) {
        wd.enqueue_task = task_enqueue;
        wd.finish_task = task_finish;
    }
    assert_int_equal(hgcd_world_create(&wd, &sc->w), HGCD_OK);
    for (k = 0; k < SHAPE_COUNT; ++k) {
        hgcd_mesh_desc md = hgcd_mesh_desc_default();
        md.vertices = shapes[k].verts;
        md.triangles = shapes[k].tris;
        md.vertex_count = shapes[k].vertex_count;
        md.triangle_count = shapes[k].triangle_count;
        assert_int_equal(hgcd_mesh_create(sc->w, &md, &sc->mesh[k]), HGCD_OK);
    }
}

static void scene_free(scene *sc) {
    size_t i;
    for (i = 0; i < sc->n; ++i) free(sc->wv[i]);
    hgcd_world_destroy(sc->w);
}

/* A body created as index i (the next new index, or a freed one hgcd
 * reuses), recorded for the oracle. */
static hgcd_body scene_put(scene *sc, size_t i, int shape, const double *p, const double *q, double s) {
    hgcd_body_desc bd = hgcd_body_desc_default();
    hgcd_body id;
    const oracle_mesh *m = &shapes[shape];
    uint32_t v;
    assert_true(i < 256);
    bd.mesh = sc->mesh[shape];
    memcpy(bd.position, p, sizeof bd.position);
    memcpy(bd.orientation, q, sizeof bd.orientation);
    bd.scale = s;
    assert_int_equal(hgcd_body_create(sc->w, &bd, &id), HGCD_OK);
    assert_int_equal(id.index, (uint32_t)i);
    sc->shape[i] = shape;
    memcpy(sc->pos[i], p, sizeof sc->pos[i]);
    memcpy(sc->quat[i], q, sizeof sc->quat[i]);
    sc->scale[i] = s;
    free(sc->wv[i]);
    sc->wv[i] = malloc(3 * sizeof(double) * m->vertex_count);
    for (v = 0; v < m->vertex_count; ++v) oracle_world_vertex(p, q, s, m->verts + 3 * v, sc->wv[i] + 3 * v);
    sc->skip[i] = 0;
    return id;
}

static void scene_add(scene *sc, int shape, const double *p, const double *q, double s) {
    scene_put(sc, sc->n++, shape, p, q, s);
}

/* Random bodies in [0, side]^3; snapped: integer positions, quarter-turn
 * free exact orientations, scales 1 and 2 (so world vertices are exact
 * small binary fractions and queries meet them exactly). */
static void scene_random(scene *sc, rng *r, size_t n, double side, int snap) {
    size_t i;
    for (i = 0; i < n; ++i) {
        double p[3], q[4], s;
        int k, shape = (int)(next(r) % SHAPE_COUNT);
        if (snap) {
            for (k = 0; k < 3; ++k) p[k] = (double)(next(r) % (uint64_t)(side + 1));
            memcpy(q, exact_quats[next(r) % 4], sizeof q);
            s = (double)(1 + next(r) % 2);
        } else {
            for (k = 0; k < 3; ++k) p[k] = side * unif(r);
            random_unit_quaternion(r, q);
            s = 0.3 + 1.2 * unif(r);
        }
        scene_add(sc, shape, p, q, s);
    }
}

static void tri_of(const scene *sc, size_t b, uint32_t f, double *t) {
    const uint32_t *tr = shapes[sc->shape[b]].tris + 3 * f;
    int k;
    for (k = 0; k < 9; ++k) t[k] = sc->wv[b][3 * tr[k / 3] + k % 3];
}

static int body_closed(const scene *sc, size_t b) {
    const oracle_mesh *m = &shapes[sc->shape[b]];
    return oracle_mesh_is_closed(m->tris, m->triangle_count);
}

static int point_in_body(const scene *sc, size_t b, const double *p) {
    const oracle_mesh *m = &shapes[sc->shape[b]];
    return oracle_point_in_solid(p, sc->wv[b], m->vertex_count, m->tris, m->triangle_count);
}

/* --------------------------------------------------------------- rays -- */

/* The oracle's closest hit: (t, body, triangle) least, inside first. */
typedef struct {
    int hit, inside;
    size_t body;
    uint32_t tri;
    double t;
} ray_ref;

static ray_ref oracle_ray(const scene *sc, const double *o, const double *e) {
    ray_ref best = {0, 0, 0, UINT32_MAX, 0};
    double bt[9];
    size_t b;
    /* Bodies ascending, triangles ascending: a candidate replaces the best
     * only when strictly before it. */
    for (b = 0; b < sc->n; ++b) {
        const oracle_mesh *m = &shapes[sc->shape[b]];
        uint32_t f;
        if (sc->skip[b]) continue;
        if (body_closed(sc, b) && point_in_body(sc, b, o)) {
            if (!best.hit || best.t > 0) best = (ray_ref){1, 1, b, UINT32_MAX, 0};
            continue;
        }
        for (f = 0; f < m->triangle_count; ++f) {
            double t[9], tp;
            tri_of(sc, b, f, t);
            if (!oracle_ray_crossing(o, e, t, &tp)) continue;
            if (best.hit && (best.inside || oracle_crossing_compare(o, e, t, bt) >= 0)) continue;
            best = (ray_ref){1, 0, b, f, tp};
            memcpy(bt, t, sizeof bt);
        }
    }
    return best;
}

static void ray_end(const hgcd_ray *r, double *e) {
    int k;
    for (k = 0; k < 3; ++k) {
        volatile double m = r->max_distance * r->direction[k];
        e[k] = r->origin[k] + m;
    }
}

/* Casts the rays in both modes on 1 and 2 threads and checks them. */
static void check_rays(scene *sc, const hgcd_ray *rays, size_t count, size_t *hits_out) {
    hgcd_ray_hit *h1 = calloc(count, sizeof *h1), *h2 = calloc(count, sizeof *h2), *any = calloc(count, sizeof *any);
    size_t k, hits = 0;
    assert_int_equal(hgcd_world_set_thread_count(sc->w, 1), HGCD_OK);
    assert_int_equal(hgcd_world_cast_rays(sc->w, rays, count, 0, HGCD_RAY_CLOSEST, sc->qf, h1), HGCD_OK);
    assert_int_equal(hgcd_world_set_thread_count(sc->w, 2), HGCD_OK);
    assert_int_equal(hgcd_world_cast_rays(sc->w, rays, count, 0, HGCD_RAY_CLOSEST, sc->qf, h2), HGCD_OK);
    assert_memory_equal(h1, h2, count * sizeof *h1);
    assert_int_equal(hgcd_world_cast_rays(sc->w, rays, count, 0, HGCD_RAY_ANY, sc->qf, any), HGCD_OK);
    for (k = 0; k < count; ++k) {
        double e[3];
        ray_ref ref;
        ray_end(&rays[k], e);
        ref = oracle_ray(sc, rays[k].origin, e);
        if (ref.hit != (h1[k].body.generation != 0) || (ref.hit && (h1[k].body.index != ref.body ||
                                                                    h1[k].triangle != ref.tri ||
                                                                    h1[k].inside != (uint32_t)ref.inside))) {
            fprintf(stderr, "ray %zu: hgcd %u/%u/%u d=%.17g, oracle %d %zu/%u/%d t=%.17g\n", k, h1[k].body.index,
                    h1[k].triangle, h1[k].inside, h1[k].distance, ref.hit, ref.body, ref.tri, ref.inside, ref.t);
            fail();
        }
        if (ref.hit) {
            const double want = rays[k].max_distance * ref.t;
            assert_true(fabs(h1[k].distance - want) <= 0x1p-39 * fabs(want) + 1e-300);
            ++hits;
        }
        /* Any-hit: hits exactly when something is hit, and reports a true hit. */
        assert_int_equal(any[k].body.generation != 0, ref.hit);
        if (ref.hit) {
            const size_t b = any[k].body.index;
            if (any[k].inside) {
                assert_true(body_closed(sc, b) && point_in_body(sc, b, rays[k].origin));
                assert_true(any[k].distance == 0);
            } else {
                double t[9], tp;
                tri_of(sc, b, any[k].triangle, t);
                assert_true(oracle_ray_crossing(rays[k].origin, e, t, &tp));
            }
        }
    }
    if (hits_out) *hits_out = hits;
    free(h1);
    free(h2);
    free(any);
}

/* ----------------------------------------------- boxes, points, meshes -- */

typedef int (*body_test)(const scene *sc, size_t b, size_t q, const void *ctx);

/* Checks results (offsets, ascending bodies) against test(b, q) for every
 * body; returns the number of (query, body) answers. */
static size_t check_results(const scene *sc, const hgcd_query_results *res, size_t count, body_test test,
                            const void *ctx) {
    size_t q, b, total = 0;
    assert_int_equal(res->query_count, count);
    assert_int_equal(res->offsets[0], 0);
    assert_int_equal(res->offsets[count], res->body_count);
    for (q = 0; q < count; ++q) {
        size_t at = res->offsets[q];
        for (b = 0; b < sc->n; ++b) {
            const int want = !sc->skip[b] && test(sc, b, q, ctx);
            const int got = at < res->offsets[q + 1] && res->bodies[at].index == b;
            if (want != got) {
                fprintf(stderr, "query %zu body %zu (shape %d): hgcd %d oracle %d\n", q, b, sc->shape[b], got, want);
                fail();
            }
            if (got) {
                assert_true(res->bodies[at].generation != 0);
                ++at;
            }
            total += (size_t)want;
        }
        assert_int_equal(at, res->offsets[q + 1]);
    }
    return total;
}

static int box_test(const scene *sc, size_t b, size_t q, const void *ctx) {
    const double *box = (const double *)ctx + 6 * q;
    const oracle_mesh *m = &shapes[sc->shape[b]];
    return oracle_box_meets_solid(box, box + 3, sc->wv[b], m->vertex_count, m->tris, m->triangle_count);
}

static int point_test(const scene *sc, size_t b, size_t q, const void *ctx) {
    return point_in_body(sc, b, (const double *)ctx + 3 * q);
}

/* The same results on 1 and 2 threads (a copy of the first). */
static void same_on_two_threads(scene *sc, hgcd_status (*run)(scene *, const void *, hgcd_query_results *),
                                const void *ctx, hgcd_query_results *res) {
    hgcd_query_results r2;
    size_t *off;
    hgcd_body *bod;
    assert_int_equal(hgcd_world_set_thread_count(sc->w, 1), HGCD_OK);
    assert_int_equal(run(sc, ctx, res), HGCD_OK);
    off = malloc((res->query_count + 1) * sizeof *off);
    bod = malloc((res->body_count + 1) * sizeof *bod);
    memcpy(off, res->offsets, (res->query_count + 1) * sizeof *off);
    memcpy(bod, res->bodies, res->body_count * sizeof *bod);
    assert_int_equal(hgcd_world_set_thread_count(sc->w, 2), HGCD_OK);
    assert_int_equal(run(sc, ctx, &r2), HGCD_OK);
    assert_int_equal(r2.query_count, res->query_count);
    assert_int_equal(r2.body_count, res->body_count);
    assert_memory_equal(r2.offsets, off, (res->query_count + 1) * sizeof *off);
    if (res->body_count) assert_memory_equal(r2.bodies, bod, res->body_count * sizeof *bod);
    *res = r2;
    free(off);
    free(bod);
}

typedef struct {
    const double *data;
    size_t count;
} batch;

static hgcd_status run_boxes(scene *sc, const void *ctx, hgcd_query_results *out) {
    const batch *b = ctx;
    return hgcd_world_query_box(sc->w, b->data, b->count, 0, sc->qf, out);
}

static hgcd_status run_points(scene *sc, const void *ctx, hgcd_query_results *out) {
    const batch *b = ctx;
    return hgcd_world_query_point(sc->w, b->data, b->count, 0, sc->qf, out);
}

typedef struct {
    int shape;
    const hgcd_mesh_pose *poses;
    size_t count;
} mesh_batch;

static hgcd_status run_meshes(scene *sc, const void *ctx, hgcd_query_results *out) {
    const mesh_batch *b = ctx;
    return hgcd_world_query_mesh(sc->w, sc->mesh[b->shape], b->poses, b->count, 0, sc->qf, out);
}

/* The mesh at each pose against every body, by the pair oracle on a scene
 * of the body and the posed mesh. */
static int mesh_test(const scene *sc, size_t b, size_t q, const void *ctx) {
    const mesh_batch *mb = ctx;
    const oracle_mesh *ms[2] = {&shapes[sc->shape[b]], &shapes[mb->shape]};
    double pos[6], quat[8], scale[2];
    uint32_t pairs[2];
    memcpy(pos, sc->pos[b], 3 * sizeof(double));
    memcpy(pos + 3, mb->poses[q].position, 3 * sizeof(double));
    memcpy(quat, sc->quat[b], 4 * sizeof(double));
    memcpy(quat + 4, mb->poses[q].orientation, 4 * sizeof(double));
    scale[0] = sc->scale[b];
    scale[1] = mb->poses[q].scale;
    return oracle_colliding_pairs(2, ms, pos, quat, scale, pairs, 1) == 1;
}

/* ---------------------------------------------------------- workloads -- */

static void random_rays(rng *r, hgcd_ray *rays, size_t count, double side, int snap) {
    size_t k;
    int a;
    for (k = 0; k < count; ++k) {
        double n;
        do {
            for (a = 0; a < 3; ++a)
                rays[k].direction[a] = snap ? (double)((int)(next(r) % 5) - 2) : 2 * unif(r) - 1;
            n = sqrt(rays[k].direction[0] * rays[k].direction[0] + rays[k].direction[1] * rays[k].direction[1] +
                     rays[k].direction[2] * rays[k].direction[2]);
        } while (n == 0 || (!snap && n > 1));
        for (a = 0; a < 3; ++a) {
            rays[k].origin[a] = snap ? (double)(next(r) % (uint64_t)(2 * side + 3)) * 0.5 - 1 : side * unif(r);
            if (!snap) rays[k].direction[a] /= n;
        }
        rays[k].max_distance = snap ? (double)(next(r) % 8) : side * unif(r);
    }
}

static void random_boxes(rng *r, double *boxes, size_t count, double side, int snap) {
    size_t k;
    int a;
    for (k = 0; k < count; ++k)
        for (a = 0; a < 3; ++a) {
            double c = snap ? (double)(next(r) % (uint64_t)(side + 3)) - 1 : side * unif(r);
            double h = snap ? (double)(next(r) % 3) : 1.5 * unif(r);
            boxes[6 * k + a] = c - h;
            boxes[6 * k + 3 + a] = c + (snap ? (double)(next(r) % 3) : h);
        }
}

static void random_points(rng *r, const scene *sc, double *pts, size_t count, double side, int snap) {
    size_t k;
    int a;
    for (k = 0; k < count; ++k) {
        if (k % 4 == 3 && sc->n) { /* a world vertex of some body */
            const size_t b = next(r) % sc->n;
            const uint32_t v = (uint32_t)(next(r) % shapes[sc->shape[b]].vertex_count);
            memcpy(pts + 3 * k, sc->wv[b] + 3 * v, 3 * sizeof(double));
            continue;
        }
        for (a = 0; a < 3; ++a)
            pts[3 * k + a] = snap ? (double)(next(r) % (uint64_t)(4 * side + 5)) * 0.25 - 0.5 : side * unif(r);
    }
}

static void random_mesh_poses(rng *r, hgcd_mesh_pose *poses, size_t count, double side, int snap) {
    size_t k;
    int a;
    for (k = 0; k < count; ++k) {
        for (a = 0; a < 3; ++a) poses[k].position[a] = snap ? (double)(next(r) % (uint64_t)(side + 1)) : side * unif(r);
        if (snap) memcpy(poses[k].orientation, exact_quats[next(r) % 4], 4 * sizeof(double));
        else random_unit_quaternion(r, poses[k].orientation);
        poses[k].scale = snap ? (double)(1 + next(r) % 2) : 0.3 + unif(r);
    }
}

/* Every query kind on the scene against the oracle (hits and answers
 * counted, so that a scene that tests nothing is seen). */
/* Queries per check_scene are divided by this (the churn test checks often). */
static size_t query_share = 1;

static void check_scene(scene *sc, rng *r, double side, int snap, size_t *hits, size_t *answers) {
    enum { RAYS = 400, BOXES = 120, POINTS = 200, POSES = 24 };
    const size_t nr = RAYS / query_share, nb = BOXES / query_share, np = POINTS / query_share;
    const size_t nm = POSES / query_share;
    hgcd_ray rays[RAYS];
    double boxes[6 * BOXES], pts[3 * POINTS];
    hgcd_mesh_pose poses[POSES];
    hgcd_query_results res;
    int shape;
    random_rays(r, rays, nr, side, snap);
    check_rays(sc, rays, nr, &hits[0]);
    random_boxes(r, boxes, nb, side, snap);
    {
        batch b = {boxes, nb};
        same_on_two_threads(sc, run_boxes, &b, &res);
        answers[0] = check_results(sc, &res, nb, box_test, boxes);
    }
    random_points(r, sc, pts, np, side, snap);
    {
        batch b = {pts, np};
        same_on_two_threads(sc, run_points, &b, &res);
        answers[1] = check_results(sc, &res, np, point_test, pts);
    }
    for (shape = 0; shape < SHAPE_COUNT; shape += 3) {
        mesh_batch mb = {shape, poses, nm};
        random_mesh_poses(r, poses, nm, side, snap);
        same_on_two_threads(sc, run_meshes, &mb, &res);
        check_results(sc, &res, nm, mesh_test, &mb);
    }
}

/* Random filters on the bodies (categories and masks of 3 bits, groups
 * -1, 0, 1), a quarter of them disabled, and a random query filter: the
 * oracle skips the bodies Box2D's rule (the query as a body with its
 * filter) or their being disabled leaves out, written out here anew. */
static void random_filters(scene *sc, rng *r, hgcd_filter *qf) {
    hgcd_query_results res;
    const double everywhere[6] = {-1e9, -1e9, -1e9, 1e9, 1e9, 1e9};
    size_t b;
    sc->qf = NULL;
    assert_int_equal(hgcd_world_query_box(sc->w, everywhere, 1, 0, NULL, &res), HGCD_OK);
    assert_int_equal(res.body_count, sc->n);
    qf->category_bits = 1 + next(r) % 7;
    qf->mask_bits = 1 + next(r) % 7;
    qf->group_index = (int32_t)(next(r) % 3) - 1;
    qf->reserved = 0;
    for (b = 0; b < sc->n; ++b) {
        const hgcd_body id = res.bodies[b];
        hgcd_filter f = hgcd_filter_default();
        const int enabled = next(r) % 4 != 0;
        int accept;
        f.category_bits = 1 + next(r) % 7;
        f.mask_bits = 1 + next(r) % 7;
        f.group_index = (int32_t)(next(r) % 3) - 1;
        assert_int_equal(hgcd_body_set_filter(sc->w, id, &f), HGCD_OK);
        assert_int_equal(hgcd_body_set_enabled(sc->w, id, enabled), HGCD_OK);
        if (f.group_index != 0 && f.group_index == qf->group_index) accept = f.group_index > 0;
        else accept = (f.category_bits & qf->mask_bits) != 0 && (f.mask_bits & qf->category_bits) != 0;
        sc->skip[b] = !enabled || !accept;
    }
    sc->qf = qf;
}

static void run_scene(uint64_t seed, size_t bodies, double side, int snap) {
    scene sc;
    rng r = {seed};
    size_t hits[1], answers[2];
    hgcd_filter qf;
    scene_init(&sc, 1);
    scene_random(&sc, &r, bodies, side, snap);
    check_scene(&sc, &r, side, snap, hits, answers);
    assert_true(hits[0] > 400 / 10); /* (a scene that tests something) */
    assert_true(answers[0] > 120 / 4);
    assert_true(answers[1] > 200 / 8);
    random_filters(&sc, &r, &qf);
    check_scene(&sc, &r, side, snap, hits, answers);
    scene_free(&sc);
}

/* Scenes per test: fewer under the sanitizers (HGCD_SKIP_SLOW_TESTS). */
static uint64_t scene_count(uint64_t full) { return getenv("HGCD_SKIP_SLOW_TESTS") ? 1 : full; }

static void test_random_scenes(void **state) {
    uint64_t seed;
    (void)state;
    for (seed = 1; seed <= scene_count(3); ++seed) run_scene(seed, 60, 8, 0);
}

/* The queries' loops on a caller's task system (2 workers): the same
 * answers as the oracle's. */
static void test_task_system(void **state) {
    const unsigned before = atomic_load(&task_loops);
    (void)state;
    use_tasks = 1;
    run_scene(21, 60, 8, 0);
    use_tasks = 0;
    assert_true(atomic_load(&task_loops) > before);
}

static void test_snapped_scenes(void **state) {
    uint64_t seed;
    (void)state;
    for (seed = 11; seed < 11 + scene_count(4); ++seed) run_scene(seed, 40, 6, 1);
}

/* Hand-built cases on the cube [-1, 1]^3 at the origin (triangles: see
 * cube_t), each checked against the oracle and against the answer worked
 * out by hand. */
static void test_degenerate_rays(void **state) {
    scene sc;
    const double zero[3] = {0, 0, 0}, id[4] = {0, 0, 0, 1}, far_p[3] = {10, 0, 0};
    /* origin, direction, length; expected distance (-1: miss, -2: inside) */
    static const double cases[][8] = {
        {-5, 0, 0, 1, 0, 0, 10, 4},      /* face centre, through the diagonal of triangles 8, 9 */
        {-5, 1, 1, 1, 0, 0, 10, 4},      /* along the edge y = z = 1: enters at vertex 7 */
        {-5, 1, 0, 1, 0, 0, 10, 4},      /* along the face y = 1: enters through the edge x = -1 */
        {-5, 1, 0, 1, 0, 0, 4, 4},       /* ... and ends exactly there */
        {-5, 1, 0, 1, 0, 0, 3.5, -1},    /* ... or just before */
        {-5, 1.5, 0, 1, 0, 0, 10, -1},   /* parallel, outside */
        {-5, 2, 2, 1, -0.5, -0.5, 10, 4}, /* slanted, into the face centre */
        {0, 0, 0, 1, 0, 0, 10, -2},      /* starts inside */
        {1, 0, 0, 1, 0, 0, 10, -2},      /* starts on the surface */
        {0, 0, 0, 1, 0, 0, 0, -2},       /* zero length, inside */
        {-3, -3, -3, 1, 1, 1, 10, 2},    /* through the corner vertex 0 */
    };
    size_t k, n = sizeof cases / sizeof cases[0];
    hgcd_ray rays[16];
    hgcd_ray_hit hits[16];
    (void)state;
    scene_init(&sc, 2);
    scene_add(&sc, SHAPE_CUBE, zero, id, 1);
    scene_add(&sc, SHAPE_TRIANGLE, far_p, id, 1); /* an open sheet far away */
    for (k = 0; k < n; ++k) {
        memcpy(rays[k].origin, cases[k], 3 * sizeof(double));
        memcpy(rays[k].direction, cases[k] + 3, 3 * sizeof(double));
        rays[k].max_distance = cases[k][6];
    }
    check_rays(&sc, rays, n, NULL);
    assert_int_equal(hgcd_world_cast_rays(sc.w, rays, n, 0, HGCD_RAY_CLOSEST, NULL, hits), HGCD_OK);
    for (k = 0; k < n; ++k) {
        const double want = cases[k][7];
        if (want == -1) {
            assert_int_equal(hits[k].body.generation, 0);
        } else if (want == -2) {
            assert_int_equal(hits[k].inside, 1);
            assert_true(hits[k].distance == 0);
        } else {
            assert_int_equal(hits[k].body.index, 0);
            assert_int_equal(hits[k].inside, 0);
            assert_true(fabs(hits[k].distance - want) <= 1e-12 * want);
        }
    }
    /* Face diagonal: triangles 8 (3 0 4) and 9 (3 4 7) share the edge 3-4;
     * the ray through its midpoint hits both at once: the lower index. */
    {
        hgcd_ray d = {{-5, 0, 0}, {1, 0, 0}, 10};
        assert_int_equal(hgcd_world_cast_rays(sc.w, &d, 1, 0, HGCD_RAY_CLOSEST, NULL, hits), HGCD_OK);
        assert_int_equal(hits[0].triangle, 8);
    }
    /* A second cube touching the first at the face x = 1 (bodies 2): a ray
     * along x from inside body 2's far side... the shared face is hit by
     * both at the same point; the lower body wins. */
    {
        const double p2[3] = {2, 0, 0};
        hgcd_ray d = {{5, 0.25, 0.5}, {-1, 0, 0}, 10};
        scene_add(&sc, SHAPE_CUBE, p2, id, 1);
        check_rays(&sc, &d, 1, NULL);
        assert_int_equal(hgcd_world_cast_rays(sc.w, &d, 1, 0, HGCD_RAY_CLOSEST, NULL, hits), HGCD_OK);
        assert_int_equal(hits[0].body.index, 2);
        assert_true(hits[0].distance == 2);
    }
    scene_free(&sc);
}

/* Boxes and points touching the cube's faces, edges and vertices. */
static void test_degenerate_boxes_points(void **state) {
    scene sc;
    const double zero[3] = {0, 0, 0}, id[4] = {0, 0, 0, 1};
    static const double boxes[][6] = {
        {1, -0.5, -0.5, 1.5, 0.5, 0.5}, /* touches the face x = 1 */
        {1, 1, 1, 2, 2, 2},            /* touches the vertex (1, 1, 1) */
        {1, 1, -3, 2, 2, 3},           /* touches the edge x = y = 1 */
        {1.0000001, -1, -1, 1.5, 1, 1}, /* just apart */
        {-0.5, -0.5, -0.5, 0.5, 0.5, 0.5}, /* inside the solid */
        {-3, -3, -3, 3, 3, 3},         /* holds the cube */
        {0, 0, 0, 0, 0, 0},            /* a point box inside */
        {-2, 0, 0, 2, 0, 0},           /* a segment box through it */
    };
    static const double pts[][3] = {{1, 0, 0}, {1, 1, 0}, {1, 1, 1}, {0, 0, 0}, {1.0000001, 0, 0}, {0.5, 0.5, 1}};
    hgcd_query_results res;
    batch b;
    (void)state;
    scene_init(&sc, 2);
    scene_add(&sc, SHAPE_CUBE, zero, id, 1);
    scene_add(&sc, SHAPE_BOWL, zero, id, 2); /* open: an outer bowl holding nothing */
    b.data = &boxes[0][0];
    b.count = sizeof boxes / sizeof boxes[0];
    same_on_two_threads(&sc, run_boxes, &b, &res);
    check_results(&sc, &res, b.count, box_test, b.data);
    assert_int_equal(res.offsets[1] - res.offsets[0], 1);  /* face */
    assert_int_equal(res.offsets[4] - res.offsets[3], 0);  /* apart */
    assert_int_equal(res.offsets[5] - res.offsets[4], 1);  /* inside the cube, not meeting the bowl */
    b.data = &pts[0][0];
    b.count = sizeof pts / sizeof pts[0];
    same_on_two_threads(&sc, run_points, &b, &res);
    check_results(&sc, &res, b.count, point_test, b.data);
    assert_int_equal(res.offsets[3] - res.offsets[2], 1);  /* vertex */
    assert_int_equal(res.offsets[5] - res.offsets[4], 0);  /* just outside */
    scene_free(&sc);
}

/* Body filters and disabled bodies: four cubes in a row along x (at 0, 3,
 * 6, 9), answers worked out by hand. */
static void expect_bodies(const hgcd_query_results *res, size_t q, const uint32_t *want, size_t n) {
    size_t k;
    assert_int_equal(res->offsets[q + 1] - res->offsets[q], n);
    for (k = 0; k < n; ++k) assert_int_equal(res->bodies[res->offsets[q] + k].index, want[k]);
}

static void test_body_filters(void **state) {
    scene sc;
    const double id[4] = {0, 0, 0, 1}, all_box[6] = {-2, -2, -2, 11, 2, 2}, pt[3] = {9, 0, 0};
    const hgcd_filter mask4 = {1, 4 | 1, 0, 0}, cat8 = {8, UINT64_MAX, 0, 0}, mask2 = {1, 2, 0, 0};
    const hgcd_mesh_pose rod = {{4.5, 0, 0}, {0, 0, 0, 1}, 6}; /* a cube spanning x in [-1.5, 10.5] */
    hgcd_filter f = hgcd_filter_default();
    hgcd_query_results res;
    hgcd_ray ray = {{-5, 0, 0}, {1, 0, 0}, 20};
    hgcd_ray_hit hit;
    hgcd_body b1 = {1, 0}, b0 = {0, 0}, b2 = {2, 0}, b3 = {3, 0};
    size_t k;
    (void)state;
    scene_init(&sc, 2);
    for (k = 0; k < 4; ++k) {
        const double p[3] = {3.0 * (double)k, 0, 0};
        scene_add(&sc, SHAPE_CUBE, p, id, 1);
    }
    assert_int_equal(hgcd_world_query_box(sc.w, all_box, 1, 0, NULL, &res), HGCD_OK);
    b0.generation = res.bodies[0].generation;
    b1.generation = res.bodies[1].generation;
    b2.generation = res.bodies[2].generation;
    b3.generation = res.bodies[3].generation;
    f.category_bits = 2;
    assert_int_equal(hgcd_body_set_filter(sc.w, b0, &f), HGCD_OK);
    f.category_bits = 4;
    assert_int_equal(hgcd_body_set_filter(sc.w, b2, &f), HGCD_OK);
    f.category_bits = 1;
    f.mask_bits = ~(uint64_t)8;
    assert_int_equal(hgcd_body_set_filter(sc.w, b3, &f), HGCD_OK);
    assert_int_equal(hgcd_body_set_enabled(sc.w, b1, 0), HGCD_OK);
    {
        const uint32_t every[] = {0, 2, 3}, not3[] = {0, 2};
        assert_int_equal(hgcd_world_query_box(sc.w, all_box, 1, 0, NULL, &res), HGCD_OK);
        expect_bodies(&res, 0, every, 3);
        assert_int_equal(hgcd_world_query_box(sc.w, all_box, 1, 0, &mask4, &res), HGCD_OK);
        expect_bodies(&res, 0, (const uint32_t[]){2, 3}, 2);
        assert_int_equal(hgcd_world_query_box(sc.w, all_box, 1, 0, &cat8, &res), HGCD_OK);
        expect_bodies(&res, 0, not3, 2);
        assert_int_equal(hgcd_world_query_mesh(sc.w, sc.mesh[SHAPE_CUBE], &rod, 1, 0, &mask4, &res), HGCD_OK);
        expect_bodies(&res, 0, (const uint32_t[]){2, 3}, 2);
        assert_int_equal(hgcd_world_query_point(sc.w, pt, 1, 0, &mask2, &res), HGCD_OK);
        expect_bodies(&res, 0, NULL, 0);
        assert_int_equal(hgcd_world_query_point(sc.w, pt, 1, 0, &mask4, &res), HGCD_OK);
        expect_bodies(&res, 0, (const uint32_t[]){3}, 1);
    }
    /* The ray passes the filtered-out cube 0 and the disabled cube 1. */
    assert_int_equal(hgcd_world_cast_rays(sc.w, &ray, 1, 0, HGCD_RAY_CLOSEST, NULL, &hit), HGCD_OK);
    assert_int_equal(hit.body.index, 0);
    assert_true(hit.distance == 4);
    assert_int_equal(hgcd_world_cast_rays(sc.w, &ray, 1, 0, HGCD_RAY_CLOSEST, &mask4, &hit), HGCD_OK);
    assert_int_equal(hit.body.index, 2);
    assert_true(hit.distance == 10);
    assert_int_equal(hgcd_world_cast_rays(sc.w, &ray, 1, 0, HGCD_RAY_CLOSEST, &mask2, &hit), HGCD_OK);
    assert_int_equal(hit.body.index, 0);
    f.category_bits = 8;
    f.mask_bits = UINT64_MAX;
    assert_int_equal(hgcd_body_set_filter(sc.w, b0, &f), HGCD_OK);
    assert_int_equal(hgcd_world_cast_rays(sc.w, &ray, 1, 0, HGCD_RAY_CLOSEST, &mask2, &hit), HGCD_OK);
    assert_int_equal(hit.body.generation, 0); /* nothing of category 2 left */
    /* Enabled again, cube 1 is back in the answers. */
    assert_int_equal(hgcd_body_set_enabled(sc.w, b1, 1), HGCD_OK);
    assert_int_equal(hgcd_world_query_box(sc.w, all_box, 1, 0, NULL, &res), HGCD_OK);
    expect_bodies(&res, 0, (const uint32_t[]){0, 1, 2, 3}, 4);
    assert_int_equal(hgcd_world_cast_rays(sc.w, &ray, 1, 0, HGCD_RAY_CLOSEST, &mask4, &hit), HGCD_OK);
    assert_int_equal(hit.body.index, 1);
    assert_true(hit.distance == 7);
    scene_free(&sc);
}

/* Refusals change nothing: the last results stay, nothing is written. */
static void test_refusals(void **state) {
    scene sc;
    const double zero[3] = {0, 0, 0}, id[4] = {0, 0, 0, 1};
    const double good[6] = {-2, -2, -2, 2, 2, 2};
    double bad[6] = {-2, -2, -2, 2, 2, 2};
    hgcd_query_results res, res2;
    hgcd_ray ray = {{-5, 0, 0}, {1, 0, 0}, 10};
    hgcd_ray_hit hit;
    hgcd_filter none = {1, 0, 0, 0}, all = {1, UINT64_MAX, 0, 0}, odd = {1, UINT64_MAX, 0, 1};
    hgcd_mesh_pose pose = {{0, 0, 0}, {0, 0, 0, 1}, 1};
    (void)state;
    scene_init(&sc, 2);
    scene_add(&sc, SHAPE_CUBE, zero, id, 1);
    assert_int_equal(hgcd_world_query_box(sc.w, good, 1, 0, NULL, &res), HGCD_OK);
    assert_int_equal(res.body_count, 1);
    bad[0] = NAN;
    assert_int_equal(hgcd_world_query_box(sc.w, bad, 1, 0, NULL, &res2), HGCD_ERROR_INVALID_ARGUMENT);
    assert_non_null(strstr(hgcd_world_last_error(sc.w), "box 0"));
    bad[0] = 3; /* min > max */
    assert_int_equal(hgcd_world_query_box(sc.w, bad, 1, 0, NULL, &res2), HGCD_ERROR_INVALID_ARGUMENT);
    bad[0] = -2e15;
    assert_int_equal(hgcd_world_query_box(sc.w, bad, 1, 0, NULL, &res2), HGCD_ERROR_INVALID_ARGUMENT);
    assert_int_equal(hgcd_world_query_box(sc.w, good, 1, 7, NULL, &res2), HGCD_ERROR_INVALID_ARGUMENT);
    assert_int_equal(hgcd_world_query_box(sc.w, NULL, 1, 0, NULL, &res2), HGCD_ERROR_NULL_ARGUMENT);
    assert_int_equal(hgcd_world_query_box(sc.w, good, 1, 0, NULL, NULL), HGCD_ERROR_NULL_ARGUMENT);
    assert_int_equal(hgcd_world_query_point(sc.w, bad, 1, 0, NULL, &res2), HGCD_ERROR_INVALID_ARGUMENT);
    pose.orientation[3] = 2;
    assert_int_equal(hgcd_world_query_mesh(sc.w, sc.mesh[SHAPE_TETRA], &pose, 1, 0, NULL, &res2),
                     HGCD_ERROR_INVALID_ARGUMENT);
    pose.orientation[3] = 1;
    pose.scale = 0;
    assert_int_equal(hgcd_world_query_mesh(sc.w, sc.mesh[SHAPE_TETRA], &pose, 1, 0, NULL, &res2),
                     HGCD_ERROR_INVALID_ARGUMENT);
    {
        hgcd_mesh stale = {sc.mesh[SHAPE_TETRA].index, sc.mesh[SHAPE_TETRA].generation + 1};
        pose.scale = 1;
        assert_int_equal(hgcd_world_query_mesh(sc.w, stale, &pose, 1, 0, NULL, &res2), HGCD_ERROR_STALE_ID);
    }
    /* The first results are still those. */
    assert_int_equal(res.body_count, 1);
    assert_int_equal(res.offsets[1], 1);
    assert_int_equal(res.bodies[0].index, 0);
    /* Rays. */
    memset(&hit, 0xAB, sizeof hit);
    ray.direction[0] = 0;
    assert_int_equal(hgcd_world_cast_rays(sc.w, &ray, 1, 0, HGCD_RAY_CLOSEST, NULL, &hit), HGCD_ERROR_INVALID_ARGUMENT);
    ray.direction[0] = 1;
    ray.max_distance = -1;
    assert_int_equal(hgcd_world_cast_rays(sc.w, &ray, 1, 0, HGCD_RAY_CLOSEST, NULL, &hit), HGCD_ERROR_INVALID_ARGUMENT);
    ray.max_distance = INFINITY;
    assert_int_equal(hgcd_world_cast_rays(sc.w, &ray, 1, 0, HGCD_RAY_CLOSEST, NULL, &hit), HGCD_ERROR_INVALID_ARGUMENT);
    ray.max_distance = 2e15; /* end out of range */
    assert_int_equal(hgcd_world_cast_rays(sc.w, &ray, 1, 0, HGCD_RAY_CLOSEST, NULL, &hit), HGCD_ERROR_INVALID_ARGUMENT);
    ray.max_distance = 10;
    assert_int_equal(hgcd_world_cast_rays(sc.w, &ray, 1, 0, 7, NULL, &hit), HGCD_ERROR_INVALID_ARGUMENT);
    assert_int_equal(hgcd_world_cast_rays(sc.w, &ray, 1, 4, HGCD_RAY_CLOSEST, NULL, &hit), HGCD_ERROR_INVALID_ARGUMENT);
    assert_int_equal(hgcd_world_cast_rays(sc.w, &ray, 1, 0, HGCD_RAY_CLOSEST, NULL, NULL), HGCD_ERROR_NULL_ARGUMENT);
    assert_int_equal(hgcd_world_cast_rays(NULL, &ray, 1, 0, HGCD_RAY_CLOSEST, NULL, &hit), HGCD_ERROR_NULL_ARGUMENT);
    {
        unsigned char pattern[sizeof hit];
        memset(pattern, 0xAB, sizeof pattern);
        assert_memory_equal(&hit, pattern, sizeof hit);
    }
    /* Filters: a query that accepts no category hits nothing. */
    assert_int_equal(hgcd_world_cast_rays(sc.w, &ray, 1, 0, HGCD_RAY_CLOSEST, &none, &hit), HGCD_OK);
    assert_int_equal(hit.body.generation, 0);
    assert_int_equal(hgcd_world_cast_rays(sc.w, &ray, 1, 0, HGCD_RAY_CLOSEST, &all, &hit), HGCD_OK);
    assert_int_equal(hit.body.index, 0);
    assert_true(hit.distance == 4);
    assert_int_equal(hgcd_world_query_box(sc.w, good, 1, 0, &none, &res2), HGCD_OK);
    assert_int_equal(res2.body_count, 0);
    /* A filter's reserved field must be 0. */
    assert_int_equal(hgcd_world_query_box(sc.w, good, 1, 0, NULL, &res), HGCD_OK);
    assert_int_equal(hgcd_world_query_box(sc.w, good, 1, 0, &odd, &res2), HGCD_ERROR_INVALID_ARGUMENT);
    assert_non_null(strstr(hgcd_world_last_error(sc.w), "reserved"));
    assert_int_equal(hgcd_world_query_point(sc.w, zero, 1, 0, &odd, &res2), HGCD_ERROR_INVALID_ARGUMENT);
    assert_int_equal(hgcd_world_query_mesh(sc.w, sc.mesh[SHAPE_TETRA], &pose, 1, 0, &odd, &res2),
                     HGCD_ERROR_INVALID_ARGUMENT);
    memset(&hit, 0xAB, sizeof hit);
    assert_int_equal(hgcd_world_cast_rays(sc.w, &ray, 1, 0, HGCD_RAY_CLOSEST, &odd, &hit), HGCD_ERROR_INVALID_ARGUMENT);
    assert_int_equal(hit.body.index, 0xABABABABu);
    assert_int_equal(res.body_count, 1); /* the last results kept */
    assert_int_equal(res.bodies[0].index, 0);
    /* Empty batches. */
    assert_int_equal(hgcd_world_cast_rays(sc.w, NULL, 0, 0, HGCD_RAY_CLOSEST, NULL, NULL), HGCD_OK);
    assert_int_equal(hgcd_world_query_point(sc.w, NULL, 0, 0, NULL, &res2), HGCD_OK);
    assert_int_equal(res2.query_count, 0);
    assert_int_equal(res2.offsets[0], 0);
    scene_free(&sc);
}

/* The tree follows the world: moved, created and destroyed bodies. */
static void test_tree_follows_world(void **state) {
    scene sc;
    const double zero[3] = {0, 0, 0}, id[4] = {0, 0, 0, 1}, there[3] = {5, 0, 0};
    hgcd_ray ray = {{-5, 0, 0}, {1, 0, 0}, 20};
    hgcd_ray_hit hit;
    hgcd_body b0 = {0, 0};
    (void)state;
    scene_init(&sc, 2);
    scene_add(&sc, SHAPE_CUBE, zero, id, 1);
    assert_int_equal(hgcd_world_cast_rays(sc.w, &ray, 1, 0, HGCD_RAY_CLOSEST, NULL, &hit), HGCD_OK);
    assert_true(hit.distance == 4);
    b0 = hit.body;
    assert_int_equal(hgcd_body_set_pose(sc.w, b0, there, NULL), HGCD_OK);
    assert_int_equal(hgcd_world_cast_rays(sc.w, &ray, 1, 0, HGCD_RAY_CLOSEST, NULL, &hit), HGCD_OK);
    assert_true(hit.distance == 9);
    assert_int_equal(hgcd_world_set_poses(sc.w, NULL, 1, zero, 0, NULL, 0), HGCD_OK);
    assert_int_equal(hgcd_world_cast_rays(sc.w, &ray, 1, 0, HGCD_RAY_CLOSEST, NULL, &hit), HGCD_OK);
    assert_true(hit.distance == 4);
    assert_int_equal(hgcd_body_destroy(sc.w, b0), HGCD_OK);
    assert_int_equal(hgcd_world_cast_rays(sc.w, &ray, 1, 0, HGCD_RAY_CLOSEST, NULL, &hit), HGCD_OK);
    assert_int_equal(hit.body.generation, 0);
    hgcd_world_destroy(sc.w);
    free(sc.wv[0]);
}

/* Bodies destroyed, created (in freed and new indices) and moved between
 * queries, with every query against the oracle after each change (the
 * query tree is built again after bodies come or go, refitted after moves). */
static void test_tree_churn(void **state) {
    enum { N = 48, ROUNDS = 4 };
    const double side = 8;
    scene sc;
    rng r = {4242};
    size_t hits[1], answers[2], round, b;
    hgcd_body ids[256];
    hgcd_query_results res;
    const double everywhere[6] = {-1e9, -1e9, -1e9, 1e9, 1e9, 1e9};
    (void)state;
    scene_init(&sc, 2);
    scene_random(&sc, &r, N, side, 0);
    assert_int_equal(hgcd_world_query_box(sc.w, everywhere, 1, 0, NULL, &res), HGCD_OK);
    for (b = 0; b < N; ++b) ids[b] = res.bodies[b];
    query_share = 4;
    check_scene(&sc, &r, side, 0, hits, answers);
    for (round = 0; round < (getenv("HGCD_SKIP_SLOW_TESTS") ? 2 : ROUNDS); ++round) {
        size_t freed[4], nf = 0, k;
        while (nf < 4) { /* destroy 4 live bodies */
            b = next(&r) % sc.n;
            if (sc.skip[b]) continue;
            assert_int_equal(hgcd_body_destroy(sc.w, ids[b]), HGCD_OK);
            sc.skip[b] = 1;
            freed[nf++] = b;
        }
        check_scene(&sc, &r, side, 0, hits, answers);
        for (k = 0; k < 4; ++k) { /* 4 created again, in the last freed indices first */
            double p[3], q[4];
            int a;
            for (a = 0; a < 3; ++a) p[a] = side * unif(&r);
            random_unit_quaternion(&r, q);
            ids[freed[3 - k]] = scene_put(&sc, freed[3 - k], (int)(next(&r) % SHAPE_COUNT), p, q, 0.3 + unif(&r));
        }
        if (sc.n < 256) { /* and one at a new index */
            double p[3] = {side * unif(&r), side * unif(&r), side * unif(&r)}, q[4];
            random_unit_quaternion(&r, q);
            ids[sc.n] = scene_put(&sc, sc.n, (int)(next(&r) % SHAPE_COUNT), p, q, 0.3 + unif(&r));
            sc.n++;
        }
        check_scene(&sc, &r, side, 0, hits, answers);
        for (b = 0; b < sc.n; ++b) { /* every live body moved a little */
            const oracle_mesh *m = &shapes[sc.shape[b]];
            uint32_t v;
            int a;
            if (sc.skip[b]) continue;
            for (a = 0; a < 3; ++a) sc.pos[b][a] += 0.4 * unif(&r) - 0.2;
            random_unit_quaternion(&r, sc.quat[b]);
            assert_int_equal(hgcd_body_set_pose(sc.w, ids[b], sc.pos[b], sc.quat[b]), HGCD_OK);
            for (v = 0; v < m->vertex_count; ++v)
                oracle_world_vertex(sc.pos[b], sc.quat[b], sc.scale[b], m->verts + 3 * v, sc.wv[b] + 3 * v);
        }
        check_scene(&sc, &r, side, 0, hits, answers);
    }
    query_share = 1;
    scene_free(&sc);
}

/* An engine's loop (new poses, a query, a detect, a query again) on 4000
 * bodies, moved far on even ticks so that detects renumber storage (and the
 * query tree is rebuilt) and by a little on odd ones (the tree is refitted):
 * every query equals that of a twin world built afresh at the same poses. */
static void test_engine_loop(void **state) {
    enum { N = 4000, TICKS = 8, Q = 300 };
    hgcd_world_desc wd = hgcd_world_desc_default();
    hgcd_world *w, *twin;
    hgcd_mesh mesh, tmesh;
    hgcd_mesh_desc md = hgcd_mesh_desc_default();
    static double pos[3 * N], quat[4 * N], pts[3 * Q], boxes[6 * Q];
    static hgcd_ray rays[Q];
    static hgcd_ray_hit h1[Q], h2[Q];
    rng r = {99};
    int tick, pass;
    size_t i;
    (void)state;
    wd.thread_count = 2;
    md.vertices = tetra_v;
    md.triangles = tetra_t;
    md.vertex_count = 4;
    md.triangle_count = 4;
    assert_int_equal(hgcd_world_create(&wd, &w), HGCD_OK);
    assert_int_equal(hgcd_mesh_create(w, &md, &mesh), HGCD_OK);
    for (i = 0; i < N; ++i) {
        hgcd_body_desc bd = hgcd_body_desc_default();
        hgcd_body id;
        bd.mesh = mesh;
        assert_int_equal(hgcd_body_create(w, &bd, &id), HGCD_OK);
    }
    for (tick = 0; tick < TICKS; ++tick) {
        for (i = 0; i < N; ++i) {
            int k;
            for (k = 0; k < 3; ++k) pos[3 * i + k] = tick % 2 ? pos[3 * i + k] + unif(&r) - 0.5 : 40 * unif(&r);
            random_unit_quaternion(&r, quat + 4 * i);
        }
        assert_int_equal(hgcd_world_set_poses(w, NULL, N, pos, 0, quat, 0), HGCD_OK);
        random_rays(&r, rays, Q, 40, 0);
        for (i = 0; i < Q; ++i) memcpy(pts + 3 * i, pos + 3 * (next(&r) % N), 3 * sizeof(double));
        assert_int_equal(hgcd_world_create(&wd, &twin), HGCD_OK);
        assert_int_equal(hgcd_mesh_create(twin, &md, &tmesh), HGCD_OK);
        for (i = 0; i < N; ++i) {
            hgcd_body_desc bd = hgcd_body_desc_default();
            hgcd_body id;
            bd.mesh = tmesh;
            memcpy(bd.position, pos + 3 * i, sizeof bd.position);
            memcpy(bd.orientation, quat + 4 * i, sizeof bd.orientation);
            assert_int_equal(hgcd_body_create(twin, &bd, &id), HGCD_OK);
        }
        assert_int_equal(hgcd_world_cast_rays(twin, rays, Q, 0, HGCD_RAY_CLOSEST, NULL, h2), HGCD_OK);
        for (pass = 0; pass < 2; ++pass) { /* before and after the detect */
            hgcd_query_results a, b;
            size_t k;
            assert_int_equal(hgcd_world_cast_rays(w, rays, Q, 0, HGCD_RAY_CLOSEST, NULL, h1), HGCD_OK);
            for (k = 0; k < Q; ++k) {
                assert_int_equal(h1[k].body.index, h2[k].body.index);
                assert_int_equal(h1[k].triangle, h2[k].triangle);
                assert_true(h1[k].distance == h2[k].distance);
            }
            assert_int_equal(hgcd_world_query_point(w, pts, Q, 0, NULL, &a), HGCD_OK);
            assert_int_equal(hgcd_world_query_point(twin, pts, Q, 0, NULL, &b), HGCD_OK);
            assert_int_equal(a.body_count, b.body_count);
            assert_memory_equal(a.offsets, b.offsets, (Q + 1) * sizeof(size_t));
            for (k = 0; k < a.body_count; ++k) assert_int_equal(a.bodies[k].index, b.bodies[k].index);
            for (k = 0; k < Q; ++k) { /* boxes of side 1 around the points */
                int c;
                for (c = 0; c < 3; ++c) {
                    boxes[6 * k + c] = pts[3 * k + c] - 0.5;
                    boxes[6 * k + 3 + c] = pts[3 * k + c] + 0.5;
                }
            }
            assert_int_equal(hgcd_world_query_box(w, boxes, Q, 0, NULL, &a), HGCD_OK);
            assert_int_equal(hgcd_world_query_box(twin, boxes, Q, 0, NULL, &b), HGCD_OK);
            assert_true(a.body_count > Q);
            assert_int_equal(a.body_count, b.body_count);
            assert_memory_equal(a.offsets, b.offsets, (Q + 1) * sizeof(size_t));
            for (k = 0; k < a.body_count; ++k) assert_int_equal(a.bodies[k].index, b.bodies[k].index);
            if (pass == 0) assert_int_equal(hgcd_world_detect(w), HGCD_OK);
        }
        hgcd_world_destroy(twin);
    }
    hgcd_world_destroy(w);
}

int main(void) {
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_tree_churn),
        cmocka_unit_test(test_degenerate_rays),     cmocka_unit_test(test_degenerate_boxes_points),
        cmocka_unit_test(test_refusals),            cmocka_unit_test(test_tree_follows_world),
        cmocka_unit_test(test_engine_loop),           cmocka_unit_test(test_body_filters),
        cmocka_unit_test(test_random_scenes),       cmocka_unit_test(test_snapped_scenes),
        cmocka_unit_test(test_task_system),
    };
    if (getenv("HGCD_TEST_FILTER")) cmocka_set_test_filter(getenv("HGCD_TEST_FILTER"));
    return cmocka_run_group_tests(tests, NULL, NULL);
}
