/* The threading contract of hgcd.h: separate worlds are independent and may
 * be driven from different threads at once (each with its own OpenMP
 * parallel regions inside), and calls taking a const world may overlap.
 * Several POSIX threads each build and run their own world (tetra scene
 * draws and mixed random scenes, with steps, pose changes, destroys and
 * re-creates between ticks) and record every tick's pairs; these must equal
 * the same script run on one thread beforehand. Then several threads read
 * one world at once through the const calls.
 *
 * HGCD_TEST_THREADS_N sets the bodies per world (default 20000; the
 * ThreadSanitizer run uses fewer). */
#include <math.h>
#include <pthread.h>
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
#include <hgcd/hgcd_scene.h>

enum { WORKERS = 4, TICKS = 4 };

static const double tri_v[] = {-1.5, -1, 0, 1.5, -1, 0.25, 0, 1.5, -0.25};
static const uint32_t tri_t[] = {0, 1, 2};

typedef struct {
    int id;               /* script number: seed, thread count, scene kind */
    uint64_t n;           /* bodies */
    /* results: per tick, the pairs as (a.index, b.index, a counter, b counter) */
    uint32_t *pairs[TICKS];
    size_t count[TICKS];
    int status;           /* 0 ok, else the first failing line */
} job;

static uint64_t mix(uint64_t x) {
    x += 0x9E3779B97F4A7C15ull;
    x = (x ^ (x >> 30)) * 0xBF58476D1CE4E5B9ull;
    x = (x ^ (x >> 27)) * 0x94D049BB133111EBull;
    return x ^ (x >> 31);
}

#define CHECK(cond)                       \
    do {                                  \
        if (!(cond)) {                    \
            if (!j->status) j->status = __LINE__; \
            goto done;                    \
        }                                 \
    } while (0)

static void record(job *j, int tick, hgcd_world *w) {
    const hgcd_pair *p;
    size_t n;
    if (hgcd_world_pairs(w, &p, &n) != HGCD_OK) {
        j->status = __LINE__;
        return;
    }
    j->pairs[tick] = malloc((4 * n + 1) * sizeof(uint32_t));
    for (size_t k = 0; k < n; ++k) {
        j->pairs[tick][4 * k] = p[k].a.index;
        j->pairs[tick][4 * k + 1] = p[k].b.index;
        j->pairs[tick][4 * k + 2] = p[k].a.generation & 0xFFFFFFu;
        j->pairs[tick][4 * k + 3] = p[k].b.generation & 0xFFFFFFu;
    }
    j->count[tick] = n;
}

/* One world's whole life. Deterministic in j->id. */
static void *run_job(void *arg) {
    job *j = arg;
    const uint64_t n = j->n;
    double *c = malloc(3 * n * sizeof(double)), *s = malloc(n * sizeof(double));
    double *q = malloc(4 * n * sizeof(double)), *v = malloc(3 * n * sizeof(double));
    hgcd_body *ids = malloc(n * sizeof(hgcd_body));
    hgcd_world *w = NULL;
    hgcd_scene_tetra_desc sd = hgcd_scene_tetra_desc_default();
    sd.n = n;
    sd.seed = 1 + (uint64_t)j->id;
    sd.side = 4 * cbrt((double)n); /* dense: many pairs */
    sd.vmax = 0.5;
    CHECK(hgcd_scene_tetra_generate(&sd, c, NULL, s, q, v) == HGCD_OK);
    hgcd_world_desc wd = hgcd_world_desc_default();
    wd.thread_count = 1 + (uint32_t)(j->id % 3);
    wd.reflect_at_bounds = 1;
    for (int k = 0; k < 3; ++k) wd.bounds_max[k] = sd.side;
    wd.max_cell_size = j->id % 2 ? 1.5 : 0; /* some worlds with many oversize bodies */
    CHECK(hgcd_world_create(&wd, &w) == HGCD_OK);
    hgcd_mesh mesh[3];
    double tv[12];
    uint32_t tt[12];
    hgcd_scene_tetra_unit_mesh(tv, tt);
    const double *mv[3] = {tv, cube_v, tri_v};
    const uint32_t *mt[3] = {tt, cube_t, tri_t};
    const uint32_t nv[3] = {4, 8, 3}, nt[3] = {4, 12, 1};
    for (int m = 0; m < 3; ++m) {
        hgcd_mesh_desc md = hgcd_mesh_desc_default();
        md.vertices = mv[m];
        md.triangles = mt[m];
        md.vertex_count = nv[m];
        md.triangle_count = nt[m];
        CHECK(hgcd_mesh_create(w, &md, &mesh[m]) == HGCD_OK);
    }
    for (uint64_t i = 0; i < n; ++i) {
        hgcd_body_desc bd = hgcd_body_desc_default();
        const int m = j->id >= 2 ? (int)(mix(i + 77 * (uint64_t)j->id) % 3) : 0;
        bd.mesh = mesh[m];
        memcpy(bd.position, &c[3 * i], sizeof bd.position);
        memcpy(bd.orientation, &q[4 * i], sizeof bd.orientation);
        memcpy(bd.velocity, &v[3 * i], sizeof bd.velocity);
        bd.scale = m == 0 ? s[i] : s[i] * 0.6;
        CHECK(hgcd_body_create(w, &bd, &ids[i]) == HGCD_OK);
    }
    for (int tick = 0; tick < TICKS; ++tick) {
        CHECK((tick == 0 ? hgcd_world_detect(w) : hgcd_world_step(w)) == HGCD_OK);
        record(j, tick, w);
        CHECK(!j->status);
        /* Between ticks: teleport some, destroy some, re-create some. */
        for (uint64_t i = 0; i < n; i += 37) {
            const uint64_t r = mix(i * 131 + (uint64_t)tick * 7 + (uint64_t)j->id);
            if (r % 3 == 0 && hgcd_body_validate(w, ids[i]) == HGCD_OK) {
                double p[3];
                for (int k = 0; k < 3; ++k) p[k] = sd.side * (double)((r >> (8 + 16 * k)) & 0xFFFF) / 65536.0;
                CHECK(hgcd_body_set_pose(w, ids[i], p, NULL) == HGCD_OK);
            } else if (r % 3 == 1 && hgcd_body_validate(w, ids[i]) == HGCD_OK) {
                CHECK(hgcd_body_destroy(w, ids[i]) == HGCD_OK);
            } else if (hgcd_body_validate(w, ids[i]) != HGCD_OK) {
                hgcd_body_desc bd = hgcd_body_desc_default();
                bd.mesh = mesh[0];
                memcpy(bd.position, &c[3 * ((i + 1) % n)], sizeof bd.position);
                bd.scale = s[i];
                CHECK(hgcd_body_create(w, &bd, &ids[i]) == HGCD_OK);
            }
        }
    }
done:
    hgcd_world_destroy(w);
    free(c);
    free(s);
    free(q);
    free(v);
    free(ids);
    return NULL;
}

static uint64_t bodies(void) {
    const char *env = getenv("HGCD_TEST_THREADS_N");
    return env ? strtoull(env, NULL, 10) : 20000;
}

static void free_job(job *j) {
    for (int t = 0; t < TICKS; ++t) free(j->pairs[t]);
}

static void test_worlds_on_threads(void **state) {
    (void)state;
    const uint64_t n = bodies();
    job ref[WORKERS], par[WORKERS];
    memset(ref, 0, sizeof ref);
    memset(par, 0, sizeof par);
    for (int k = 0; k < WORKERS; ++k) { /* references, one at a time */
        ref[k].id = k;
        ref[k].n = n;
        run_job(&ref[k]);
        if (ref[k].status) fprintf(stderr, "reference %d failed at line %d\n", k, ref[k].status);
        assert_int_equal(ref[k].status, 0);
    }
    for (int round = 0; round < 2; ++round) {
        pthread_t th[WORKERS];
        for (int k = 0; k < WORKERS; ++k) {
            par[k].id = k;
            par[k].n = n;
            assert_int_equal(pthread_create(&th[k], NULL, run_job, &par[k]), 0);
        }
        for (int k = 0; k < WORKERS; ++k) assert_int_equal(pthread_join(th[k], NULL), 0);
        size_t total = 0;
        for (int k = 0; k < WORKERS; ++k) {
            if (par[k].status) fprintf(stderr, "worker %d failed at line %d\n", k, par[k].status);
            assert_int_equal(par[k].status, 0);
            for (int t = 0; t < TICKS; ++t) {
                assert_int_equal(par[k].count[t], ref[k].count[t]);
                assert_memory_equal(par[k].pairs[t], ref[k].pairs[t], 4 * ref[k].count[t] * sizeof(uint32_t));
                total += par[k].count[t];
            }
            free_job(&par[k]);
            memset(&par[k], 0, sizeof par[k]);
        }
        if (round == 0)
            printf("%d worlds of %llu bodies on %d threads at once, %d ticks: %zu pairs, equal to one-thread runs\n",
                   WORKERS, (unsigned long long)n, WORKERS, TICKS, total);
        assert_true(total > (size_t)n / 4);
    }
    for (int k = 0; k < WORKERS; ++k) free_job(&ref[k]);
}

/* ---------------------------------------------- overlapping const calls -- */

typedef struct {
    const hgcd_world *w;
    const hgcd_body *ids;
    size_t n;
    hgcd_mesh mesh;
    const hgcd_pair *expect;
    size_t expect_n;
    int status;
} reader;

static void *read_world(void *arg) {
    reader *r = arg;
    hgcd_pair *buf = malloc((r->expect_n + 1) * sizeof(hgcd_pair));
    for (int rep = 0; rep < 20 && !r->status; ++rep) {
        const hgcd_pair *p;
        size_t n, total;
        if (hgcd_world_pairs(r->w, &p, &n) != HGCD_OK || n != r->expect_n || p != r->expect) r->status = __LINE__;
        if (hgcd_world_copy_pairs(r->w, buf, r->expect_n, &total) != HGCD_OK || total != r->expect_n ||
            (total && memcmp(buf, r->expect, total * sizeof *buf)))
            r->status = __LINE__;
        hgcd_stats st;
        st.struct_size = sizeof st;
        if (hgcd_world_stats(r->w, &st) != HGCD_OK || st.colliding_pairs != r->expect_n) r->status = __LINE__;
        hgcd_mesh_info info;
        info.struct_size = sizeof info;
        if (hgcd_mesh_get_info(r->w, r->mesh, &info) != HGCD_OK || info.body_count != r->n) r->status = __LINE__;
        for (size_t i = 0; i < r->n; i += 7) {
            double pos[3], q[4], v[3];
            uint64_t u;
            hgcd_mesh m;
            if (hgcd_body_validate(r->w, r->ids[i]) != HGCD_OK ||
                hgcd_body_get_pose(r->w, r->ids[i], pos, q) != HGCD_OK ||
                hgcd_body_get_velocity(r->w, r->ids[i], v) != HGCD_OK ||
                hgcd_body_get_mesh(r->w, r->ids[i], &m) != HGCD_OK ||
                hgcd_body_get_user_data(r->w, r->ids[i], &u) != HGCD_OK || u != i)
                r->status = __LINE__;
        }
        const hgcd_body stale = {(uint32_t)r->n + 5, 1};
        if (hgcd_body_validate(r->w, stale) != HGCD_ERROR_STALE_ID) r->status = __LINE__;
        if (hgcd_world_body_count(r->w) != r->n) r->status = __LINE__;
    }
    free(buf);
    return NULL;
}

static void test_const_calls_overlap(void **state) {
    (void)state;
    const uint64_t n = bodies();
    hgcd_scene_tetra_desc sd = hgcd_scene_tetra_desc_default();
    sd.n = n;
    sd.side = 4 * cbrt((double)n);
    double *c = malloc(3 * n * sizeof(double)), *s = malloc(n * sizeof(double)), *q = malloc(4 * n * sizeof(double));
    assert_int_equal(hgcd_scene_tetra_generate(&sd, c, NULL, s, q, NULL), HGCD_OK);
    hgcd_world_desc wd = hgcd_world_desc_default();
    wd.thread_count = 2;
    hgcd_world *w;
    assert_int_equal(hgcd_world_create(&wd, &w), HGCD_OK);
    double tv[12];
    uint32_t tt[12];
    hgcd_scene_tetra_unit_mesh(tv, tt);
    hgcd_mesh_desc md = hgcd_mesh_desc_default();
    md.vertices = tv;
    md.triangles = tt;
    md.vertex_count = 4;
    md.triangle_count = 4;
    hgcd_mesh m;
    assert_int_equal(hgcd_mesh_create(w, &md, &m), HGCD_OK);
    hgcd_body *ids = malloc(n * sizeof *ids);
    for (uint64_t i = 0; i < n; ++i) {
        hgcd_body_desc bd = hgcd_body_desc_default();
        bd.mesh = m;
        memcpy(bd.position, &c[3 * i], sizeof bd.position);
        memcpy(bd.orientation, &q[4 * i], sizeof bd.orientation);
        bd.scale = s[i];
        bd.user_data = i;
        assert_int_equal(hgcd_body_create(w, &bd, &ids[i]), HGCD_OK);
    }
    assert_int_equal(hgcd_world_detect(w), HGCD_OK);
    reader r[WORKERS];
    pthread_t th[WORKERS];
    for (int k = 0; k < WORKERS; ++k) {
        r[k].w = w;
        r[k].ids = ids;
        r[k].n = n;
        r[k].mesh = m;
        r[k].status = 0;
        assert_int_equal(hgcd_world_pairs(w, &r[k].expect, &r[k].expect_n), HGCD_OK);
        assert_int_equal(pthread_create(&th[k], NULL, read_world, &r[k]), 0);
    }
    for (int k = 0; k < WORKERS; ++k) {
        assert_int_equal(pthread_join(th[k], NULL), 0);
        if (r[k].status) fprintf(stderr, "reader %d failed at line %d\n", k, r[k].status);
        assert_int_equal(r[k].status, 0);
    }
    assert_true(r[0].expect_n > 0);
    hgcd_world_destroy(w);
    free(ids);
    free(c);
    free(s);
    free(q);
}

int main(void) {
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_worlds_on_threads),
        cmocka_unit_test(test_const_calls_overlap),
    };
    if (getenv("HGCD_TEST_FILTER")) cmocka_set_test_filter(getenv("HGCD_TEST_FILTER"));
    return cmocka_run_group_tests(tests, NULL, NULL);
}
