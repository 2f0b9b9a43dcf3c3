/* Out-of-memory is a status, never an abort, and the world survives it.
 *
 * tests/oom_hook.cpp replaces the global C++ operator new/delete of this
 * executable (hgcd is linked statically, so the replacements serve every
 * allocation hgcd makes) with a countdown: the N-th allocation throws
 * std::bad_alloc. A scripted sequence of API calls (world create, mesh
 * create/destroy, body create/destroy, set_pose, set_velocity, detect, step,
 * pairs, copy_pairs, stats, a refused call) is run for N = 1, 2, 3, ... until
 * a run makes no allocation fail. Each call must return its expected status
 * or HGCD_ERROR_OUT_OF_MEMORY, nothing else and never crash; after a failure
 * the world must be exactly as before the call (for detect and step: as
 * documented in hgcd.h), the same call must then succeed, and the run must
 * end in the same state, with the same pairs, as a run without failures
 * (whose pairs are checked against the GMP oracle).
 *
 * Two regimes: one failed allocation (later ones succeed), and exhausted
 * memory (every allocation after the N-th fails until the call returns, so
 * the error path itself runs without memory).
 *
 * Allocations inside OpenMP parallel regions (by any thread of the team)
 * are failed too with HGCD_OOM_IN_PARALLEL=1 (see below).
 * HGCD_OOM_STRIDE=k fails every k-th allocation point only (for valgrind). */
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

#if defined(__linux__)
#include <signal.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>
#endif

#include <hgcd/hgcd.h>

#include "oom_hook.h"
#include "oracle.h"
#include "snapshot.h"

/* ------------------------------------------------------------- shapes -- */

enum { SHEET_N = 6 }; /* an open, wavy sheet of 2 * 6 * 6 triangles */
static double sheet_v[3 * (SHEET_N + 1) * (SHEET_N + 1)];
static uint32_t sheet_t[6 * SHEET_N * SHEET_N];

enum { SHAPE_TETRA, SHAPE_CUBE, SHAPE_SHEET, SHAPE_SPARE, SHAPES };
static oracle_mesh shapes[SHAPES];

static void init_shapes(void) {
    for (int j = 0, v = 0; j <= SHEET_N; ++j)
        for (int i = 0; i <= SHEET_N; ++i, ++v) {
            sheet_v[3 * v] = -1.5 + 3.0 * i / SHEET_N;
            sheet_v[3 * v + 1] = -1.5 + 3.0 * j / SHEET_N;
            sheet_v[3 * v + 2] = 0.25 * ((i + j) % 3) - 0.25;
        }
    for (int j = 0, t = 0; j < SHEET_N; ++j)
        for (int i = 0; i < SHEET_N; ++i, t += 6) {
            const uint32_t a = (uint32_t)(j * (SHEET_N + 1) + i), b = a + 1, c = a + SHEET_N + 1, d = c + 1;
            const uint32_t tri[6] = {a, b, d, a, d, c};
            memcpy(&sheet_t[t], tri, sizeof tri);
        }
    const oracle_mesh m[SHAPES] = {
        {tetra_v, tetra_t, 4, 4, 1},
        {cube_v, cube_t, 8, 12, 1},
        {sheet_v, sheet_t, (SHEET_N + 1) * (SHEET_N + 1), 2 * SHEET_N * SHEET_N, 0},
        {cube_v, cube_t, 8, 10, 0},
    };
    memcpy(shapes, m, sizeof m);
}

/* ------------------------------------------------------------- script -- */

enum { BODIES = 40, SIDE = 12 };

typedef struct {
    hgcd_world *w;
    hgcd_mesh mesh[SHAPES];
    hgcd_body body[BODIES];
    int body_shape[BODIES];
} ctx;

typedef enum {
    OP_WORLD_CREATE, OP_MESH_CREATE, OP_MESH_DESTROY, OP_BODY_CREATE, OP_BODY_DESTROY,
    OP_SET_POSE, OP_SET_VELOCITY, OP_DETECT, OP_STEP, OP_PAIRS, OP_COPY_PAIRS, OP_STATS,
    OP_REFUSED_POSE, OP_THREADS, OP_EXCLUDE, OP_STATIC
} op_kind;

typedef struct {
    op_kind op;
    int arg;
} op;

static op script[256];
static int script_len;

static void push(op_kind k, int arg) {
    script[script_len].op = k;
    script[script_len].arg = arg;
    ++script_len;
}

static void build_script(void) {
    script_len = 0;
    push(OP_WORLD_CREATE, 0);
    for (int m = 0; m < SHAPES; ++m) push(OP_MESH_CREATE, m);
    for (int i = 0; i < 34; ++i) push(OP_BODY_CREATE, i); /* past the 16 and 32 growth steps */
    push(OP_DETECT, 0);
    push(OP_PAIRS, 0);
    push(OP_COPY_PAIRS, 0);
    push(OP_STATS, 0);
    push(OP_MESH_DESTROY, SHAPE_SPARE);
    for (int i = 0; i < 34; i += 3) push(OP_SET_VELOCITY, i);
    for (int i = 1; i < 34; i += 4) push(OP_SET_POSE, i);
    push(OP_REFUSED_POSE, 2);
    for (int i = 2; i < 30; i += 4) push(OP_EXCLUDE, i); /* (slots 5, 10, ... die below: exclusions die too) */
    for (int i = 3; i < 34; i += 6) push(OP_STATIC, i);
    push(OP_STEP, 0);
    for (int i = 0; i < 34; i += 5) push(OP_BODY_DESTROY, i);
    push(OP_THREADS, 1);
    push(OP_DETECT, 0);
    for (int i = 34; i < BODIES; ++i) push(OP_BODY_CREATE, i); /* reuse freed slots */
    push(OP_MESH_CREATE, SHAPE_SPARE);
    push(OP_THREADS, 2);
    push(OP_STEP, 0);
    push(OP_PAIRS, 0);
    push(OP_DETECT, 0);
}

/* splitmix64 on the body number: every run places body i the same way. */
static uint64_t mix(uint64_t x) {
    x += 0x9E3779B97F4A7C15ull;
    x = (x ^ (x >> 30)) * 0xBF58476D1CE4E5B9ull;
    x = (x ^ (x >> 27)) * 0x94D049BB133111EBull;
    return x ^ (x >> 31);
}
static double unit(uint64_t seed, int k) { return (double)(mix(seed * 16 + (uint64_t)k) >> 11) * 0x1.0p-53; }

static void random_quat(uint64_t seed, double *q) {
    const double u1 = unit(seed, 10), u2 = unit(seed, 11), u3 = unit(seed, 12);
    q[0] = sqrt(1 - u1) * sin(6.283185307179586 * u2);
    q[1] = sqrt(1 - u1) * cos(6.283185307179586 * u2);
    q[2] = sqrt(u1) * sin(6.283185307179586 * u3);
    q[3] = sqrt(u1) * cos(6.283185307179586 * u3);
}

static hgcd_status expected(const op *o) {
    return o->op == OP_REFUSED_POSE ? HGCD_ERROR_INVALID_ARGUMENT : HGCD_OK;
}

static hgcd_status run_op(ctx *c, const op *o) {
    const int i = o->arg;
    switch (o->op) {
        case OP_WORLD_CREATE: {
            hgcd_world_desc d = hgcd_world_desc_default();
            d.thread_count = 2;
            d.reflect_at_bounds = 1;
            for (int k = 0; k < 3; ++k) d.bounds_max[k] = SIDE;
            return hgcd_world_create(&d, &c->w);
        }
        case OP_MESH_CREATE: {
            hgcd_mesh_desc d = hgcd_mesh_desc_default();
            d.vertices = shapes[i].verts;
            d.triangles = shapes[i].tris;
            d.vertex_count = shapes[i].vertex_count;
            d.triangle_count = shapes[i].triangle_count;
            return hgcd_mesh_create(c->w, &d, &c->mesh[i]);
        }
        case OP_MESH_DESTROY: return hgcd_mesh_destroy(c->w, c->mesh[i]);
        case OP_BODY_CREATE: {
            hgcd_body_desc d = hgcd_body_desc_default();
            const int shape = (int)(mix((uint64_t)i) % 3);
            d.mesh = c->mesh[shape];
            for (int k = 0; k < 3; ++k) d.position[k] = SIDE * unit((uint64_t)i, k);
            random_quat((uint64_t)i, d.orientation);
            d.scale = 0.5 + unit((uint64_t)i, 3);
            d.user_data = 1000 + (uint64_t)i;
            const hgcd_status s = hgcd_body_create(c->w, &d, &c->body[i]);
            if (s == HGCD_OK) c->body_shape[i] = shape;
            return s;
        }
        case OP_BODY_DESTROY: return hgcd_body_destroy(c->w, c->body[i]);
        case OP_SET_POSE: {
            double p[3], q[4];
            for (int k = 0; k < 3; ++k) p[k] = SIDE * unit((uint64_t)i + 500, k);
            random_quat((uint64_t)i + 500, q);
            return hgcd_body_set_pose(c->w, c->body[i], p, q);
        }
        case OP_SET_VELOCITY: {
            double v[3];
            for (int k = 0; k < 3; ++k) v[k] = 2 * unit((uint64_t)i + 900, k) - 1;
            return hgcd_body_set_velocity(c->w, c->body[i], v);
        }
        case OP_DETECT: return hgcd_world_detect(c->w);
        case OP_STEP: return hgcd_world_step(c->w);
        case OP_PAIRS: {
            const hgcd_pair *p;
            size_t n;
            return hgcd_world_pairs(c->w, &p, &n);
        }
        case OP_COPY_PAIRS: {
            hgcd_pair buf[8];
            size_t total;
            return hgcd_world_copy_pairs(c->w, buf, 8, &total);
        }
        case OP_STATS: {
            hgcd_stats st;
            st.struct_size = sizeof st;
            return hgcd_world_stats(c->w, &st);
        }
        case OP_REFUSED_POSE: {
            const double p[3] = {1, NAN, 1};
            return hgcd_body_set_pose(c->w, c->body[i], p, NULL);
        }
        case OP_THREADS: return hgcd_world_set_thread_count(c->w, (uint32_t)i);
        case OP_EXCLUDE: return hgcd_world_exclude_pair(c->w, c->body[i], c->body[i + 1]);
        case OP_STATIC: return hgcd_body_set_type(c->w, c->body[i], HGCD_BODY_STATIC);
    }
    return HGCD_ERROR_INTERNAL;
}

static void take(snapshot *s, const ctx *c) { snap_take(s, c->w, c->body, BODIES, c->mesh, SHAPES); }

/* Live bodies of the final state against the oracle. */
static void check_oracle(const ctx *c) {
    const oracle_mesh *meshes[BODIES];
    double p[3 * BODIES], q[4 * BODIES], s[BODIES];
    uint32_t slot[BODIES];
    size_t n = 0;
    for (uint32_t i = 0; i < BODIES; ++i) {
        if (hgcd_body_validate(c->w, c->body[i]) != HGCD_OK) continue;
        assert_int_equal(hgcd_body_get_pose(c->w, c->body[i], &p[3 * n], &q[4 * n]), HGCD_OK);
        meshes[n] = &shapes[c->body_shape[i]];
        s[n] = 0.5 + unit(i, 3);
        slot[n] = c->body[i].index;
        ++n;
    }
    uint32_t expect[2 * 512];
    const size_t count = oracle_colliding_pairs(n, meshes, p, q, s, expect, 512);
    assert_true(count <= 512);
    const hgcd_pair *got;
    size_t got_n;
    assert_int_equal(hgcd_world_pairs(c->w, &got, &got_n), HGCD_OK);
    /* The oracle numbers bodies in slot order of this list; map to slots. */
    uint64_t *want = malloc((count + 1) * sizeof *want);
    for (size_t k = 0; k < count; ++k) {
        uint32_t a = slot[expect[2 * k]], b = slot[expect[2 * k + 1]];
        if (a > b) { uint32_t t = a; a = b; b = t; }
        want[k] = ((uint64_t)a << 32) | b;
    }
    for (size_t x = 1; x < count; ++x) /* insertion sort: small */
        for (size_t y = x; y > 0 && want[y - 1] > want[y]; --y) {
            const uint64_t t = want[y]; want[y] = want[y - 1]; want[y - 1] = t;
        }
    assert_int_equal(got_n, count);
    for (size_t k = 0; k < count; ++k) {
        assert_int_equal(got[k].a.index, (uint32_t)(want[k] >> 32));
        assert_int_equal(got[k].b.index, (uint32_t)want[k]);
    }
    free(want);
}

/* One run of the script with the n-th allocation failing (n = 0: none).
 * Returns 1 if a failure was injected. Fills *final. */
static int run(long n, int sticky, int in_parallel, snapshot *final, int *failed_calls) {
    ctx c;
    memset(&c, 0, sizeof c);
    if (n > 0) oom_arm(n, sticky, in_parallel);
    int injected = 0;
    for (int k = 0; k < script_len; ++k) {
        const op *o = &script[k];
        snapshot before;
        const int have_before = c.w != NULL;
        if (have_before) take(&before, &c);
        hgcd_status s = run_op(&c, o);
        if (s != expected(o)) {
            if (s != HGCD_ERROR_OUT_OF_MEMORY) {
                fprintf(stderr, "n = %ld, call %d (op %d): status %s\n", n, k, (int)o->op, hgcd_status_string(s));
                fail();
            }
            assert_true(oom_tripped());
            oom_disarm();
            ++*failed_calls;
            if (o->op == OP_WORLD_CREATE) {
                assert_null(c.w);
            } else {
                assert_non_null(strstr(hgcd_world_last_error(c.w), "out of memory"));
                snapshot after;
                take(&after, &c);
                if (o->op == OP_DETECT || o->op == OP_STEP) {
                    /* Documented: the previous pairs are cleared and the
                     * statistics zeroed; step has applied the motion. */
                    assert_int_equal(after.npairs, 0);
                    assert_int_equal(after.stats.candidate_pairs, 0);
                    assert_int_equal(after.stats.colliding_pairs, 0);
                    after.npairs = before.npairs;
                    after.pairs_ptr = before.pairs_ptr;
                    free(after.pairs);
                    after.pairs = malloc((before.npairs + 1) * sizeof *after.pairs);
                    if (before.npairs) memcpy(after.pairs, before.pairs, before.npairs * sizeof *after.pairs);
                    after.stats = before.stats;
                    /* Documented too: no events; the next detect compares with the last success. */
                    for (int e = 0; e < 2; ++e) {
                        assert_int_equal(after.nevents[e], 0);
                        after.nevents[e] = before.nevents[e];
                        free(after.events[e]);
                        after.events[e] = malloc((before.nevents[e] + 1) * sizeof *after.events[e]);
                        if (before.nevents[e])
                            memcpy(after.events[e], before.events[e], before.nevents[e] * sizeof *after.events[e]);
                    }
                    if (o->op == OP_STEP)
                        for (size_t b = 0; b < after.nbodies; ++b) { /* moved: take the new poses */
                            memcpy(before.bodies[b].position, after.bodies[b].position, sizeof(double) * 3);
                            memcpy(before.bodies[b].velocity, after.bodies[b].velocity, sizeof(double) * 3);
                        }
                }
                const char *diff = snap_diff(&before, &after, 1);
                if (diff) fprintf(stderr, "n = %ld, call %d (op %d): %s changed by a failed call\n", n, k, (int)o->op, diff);
                assert_null(diff);
                snap_free(&after);
            }
            /* Memory is back: the same call now succeeds (a failed step has
             * moved the bodies already, so its tick is finished by detect). */
            if (o->op == OP_STEP) s = hgcd_world_detect(c.w);
            else s = run_op(&c, o);
            assert_int_equal(s, expected(o));
            injected = 1;
        }
        if (have_before) snap_free(&before);
    }
    oom_disarm();
    if (!injected && n > 0) injected = oom_tripped(); /* failed but recovered inside: still a case */
    take(final, &c);
    if (n == 0) check_oracle(&c);
    hgcd_world_destroy(c.w);
    return injected;
}

static void sweep(int sticky) {
    init_shapes();
    build_script();
    snapshot ref;
    int dummy = 0;
    run(0, 0, 0, &ref, &dummy);
    assert_true(ref.npairs > 5); /* the scene means something */
    /* HGCD_OOM_IN_PARALLEL=1: allocations inside OpenMP parallel regions
     * fail too. Not the default yet: a failure there can leave a per-thread
     * narrow-phase scratch half resized while the thread goes on with its
     * next pairs (see tests/VALIDATION.md, open bugs). */
    const int in_parallel = getenv("HGCD_OOM_IN_PARALLEL") && atoi(getenv("HGCD_OOM_IN_PARALLEL")) != 0;
    /* The number of allocation points: a run armed beyond its end. */
    snapshot counted;
    run(1L << 40, sticky, in_parallel, &counted, &dummy);
    const long points = oom_counted();
    snap_free(&counted);
    /* HGCD_OOM_STRIDE=k tries every k-th allocation only (valgrind runs). */
    const long stride = getenv("HGCD_OOM_STRIDE") ? atol(getenv("HGCD_OOM_STRIDE")) : 1;
    long n = 1, runs = 0;
    int failed_calls = 0;
    for (;; n += stride > 0 ? stride : 1, ++runs) {
        snapshot got;
        const int injected = run(n, sticky, in_parallel, &got, &failed_calls);
        /* A failed detect drops the grid; the next one rebuilds it, so
         * more bodies count as moved. It also ends temporal coherence, so
         * the next detect searches and tests pairs where the reference
         * reused or kept the last answers: the counts of searches and tests
         * may differ, never the pairs. Everything else must agree. */
        got.stats.moved_bodies = ref.stats.moved_bodies;
        if (got.stats.unmoved_pairs != ref.stats.unmoved_pairs || got.stats.candidate_pairs != ref.stats.candidate_pairs ||
            got.stats.searched_bodies != ref.stats.searched_bodies) {
            got.stats.searched_bodies = ref.stats.searched_bodies;
            got.stats.candidate_pairs = ref.stats.candidate_pairs;
            got.stats.unmoved_pairs = ref.stats.unmoved_pairs;
            got.stats.narrow_tests = ref.stats.narrow_tests;
            got.stats.triangle_tests = ref.stats.triangle_tests;
            got.stats.containment_pairs = ref.stats.containment_pairs;
        }
        const char *diff = snap_diff(&ref, &got, 0);
        if (diff) {
            fprintf(stderr, "n = %ld: final state differs from the reference: %s (events %zu/%zu ref %zu/%zu)\n", n, diff, got.nevents[0], got.nevents[1], ref.nevents[0], ref.nevents[1]);
            const hgcd_stats *x = &ref.stats, *y = &got.stats;
            fprintf(stderr, "  stats (reference / this run): levels %u/%u oversize %u/%u threads %u/%u moved %llu/%llu "
                    "candidates %llu/%llu narrow %llu/%llu triangles %llu/%llu colliding %llu/%llu containment %llu/%llu\n",
                    x->level_count, y->level_count, x->oversize_count, y->oversize_count, x->thread_count,
                    y->thread_count, (unsigned long long)x->moved_bodies, (unsigned long long)y->moved_bodies,
                    (unsigned long long)x->candidate_pairs, (unsigned long long)y->candidate_pairs,
                    (unsigned long long)x->narrow_tests, (unsigned long long)y->narrow_tests,
                    (unsigned long long)x->triangle_tests, (unsigned long long)y->triangle_tests,
                    (unsigned long long)x->colliding_pairs, (unsigned long long)y->colliding_pairs,
                    (unsigned long long)x->containment_pairs, (unsigned long long)y->containment_pairs);
        }
        assert_null(diff);
        snap_free(&got);
        if (!injected) break;
    }
    printf("%s: %ld of the script's %ld allocation points failed in turn, %d calls returned "
           "HGCD_ERROR_OUT_OF_MEMORY, all recovered\n",
           sticky ? "memory exhausted" : "one failed allocation", runs, points, failed_calls);
    /* With 2 threads the count differs between runs (how the per-thread
     * lists split decides how often a list grows): a loose check. */
    assert_true(runs > 0 && 2 * runs * (stride > 0 ? stride : 1) >= points);
    snap_free(&ref);
}

static void test_single_failure(void **state) {
    (void)state;
    sweep(0);
}

static void test_exhausted(void **state) {
    (void)state;
    sweep(1);
}

static void test_hook_works(void **state) {
    (void)state;
    /* The hook really intercepts hgcd's allocations. */
    hgcd_world_desc d = hgcd_world_desc_default();
    hgcd_world *w = (hgcd_world *)0x1;
    oom_arm(1, 1, 0);
    assert_int_equal(hgcd_world_create(&d, &w), HGCD_ERROR_OUT_OF_MEMORY);
    assert_null(w);
    oom_disarm();
    const long before = oom_total_allocations();
    assert_int_equal(hgcd_world_create(&d, &w), HGCD_OK);
    assert_true(oom_total_allocations() > before);
    /* Refusals under exhausted memory keep their status and still say why,
     * with a fixed message if the detailed one cannot be built. */
    oom_arm(1, 1, 0);
    assert_int_equal(hgcd_world_set_thread_count(w, 5000), HGCD_ERROR_INVALID_ARGUMENT);
    assert_string_equal(hgcd_world_last_error(w), "out of memory");
    hgcd_body_desc bd = hgcd_body_desc_default();
    hgcd_body b;
    assert_int_equal(hgcd_body_create(w, NULL, &b), HGCD_ERROR_NULL_ARGUMENT);
    bd.struct_size = 3;
    assert_int_equal(hgcd_body_create(w, &bd, &b), HGCD_ERROR_BAD_DESCRIPTOR);
    oom_disarm();
    assert_int_equal(hgcd_body_create(w, &bd, &b), HGCD_ERROR_BAD_DESCRIPTOR);
    assert_non_null(strstr(hgcd_world_last_error(w), "hgcd_body_desc_default"));
    hgcd_world_destroy(w);
}

#if defined(__linux__)
/* The world's large arrays (2 MiB and up) come from mmap, past operator new
 * and so past the hook above (src/memory.cpp): here the system refuses
 * them. In a child process with its address space limited to 48 MB over
 * what it uses, bodies are added until a call fails: the failure must be
 * HGCD_ERROR_OUT_OF_MEMORY, by then arrays of several MiB have been grown,
 * and once the limit is lifted the world holds every body it accepted and
 * detects. (Skipped under ASan and valgrind, HGCD_SKIP_SLOW_TESTS, whose
 * own mappings a limit on the address space would break.) */
static long address_space_bytes(void) {
    FILE *f = fopen("/proc/self/statm", "r");
    long pages = 0;
    if (f) {
        if (fscanf(f, "%ld", &pages) != 1) pages = 0;
        fclose(f);
    }
    return pages * sysconf(_SC_PAGESIZE);
}

static int limited_child(void) {
    hgcd_world_desc wd = hgcd_world_desc_default();
    wd.thread_count = 1;
    hgcd_world *w = NULL;
    if (hgcd_world_create(&wd, &w) != HGCD_OK) return 10;
    hgcd_mesh_desc md = hgcd_mesh_desc_default();
    md.vertices = tetra_v;
    md.triangles = tetra_t;
    md.vertex_count = 4;
    md.triangle_count = 4;
    hgcd_mesh mesh;
    if (hgcd_mesh_create(w, &md, &mesh) != HGCD_OK) return 11;
    struct rlimit old, low;
    if (getrlimit(RLIMIT_AS, &old) != 0) return 12;
    low = old;
    low.rlim_cur = (rlim_t)(address_space_bytes() + (48L << 20));
    if (old.rlim_cur != RLIM_INFINITY && low.rlim_cur > old.rlim_cur) return 13;
    if (setrlimit(RLIMIT_AS, &low) != 0) return 14;
    uint32_t added = 0;
    hgcd_status s = HGCD_OK;
    for (; added < 4000000; ++added) {
        hgcd_body_desc bd = hgcd_body_desc_default();
        bd.mesh = mesh;
        bd.position[0] = (double)(added % 1000) * 3;
        bd.position[1] = (double)(added / 1000) * 3;
        hgcd_body b;
        s = hgcd_body_create(w, &bd, &b);
        if (s != HGCD_OK) break;
    }
    if (setrlimit(RLIMIT_AS, &old) != 0) return 15;
    printf("address space limited: %u bodies placed, then \"%s\"\n", added, hgcd_world_last_error(w));
    fflush(stdout);
    if (s != HGCD_ERROR_OUT_OF_MEMORY) return 16;
    if (added < 100000) return 17; /* (the per-body arrays of 64 bytes a body passed 2 MiB at 32768) */
    if (hgcd_world_body_count(w) != added) return 18;
    if (hgcd_world_detect(w) != HGCD_OK) return 19;
    hgcd_world_destroy(w);
    return 0;
}

static void test_system_refuses_large_arrays(void **state) {
    (void)state;
#if defined(__SANITIZE_ADDRESS__)
    skip();
#endif
    if (getenv("HGCD_SKIP_SLOW_TESTS")) skip();
    fflush(stdout);
    const pid_t pid = fork();
    assert_true(pid >= 0);
    if (pid == 0) { /* (cmocka's signal handlers off: a crash ends the child, and the parent sees it) */
        const int sig[] = {SIGSEGV, SIGBUS, SIGABRT, SIGILL, SIGFPE};
        for (size_t k = 0; k < sizeof sig / sizeof sig[0]; ++k) signal(sig[k], SIG_DFL);
        _exit(limited_child());
    }
    int status = 0;
    assert_int_equal(waitpid(pid, &status, 0), pid);
    assert_true(WIFEXITED(status));
    assert_int_equal(WEXITSTATUS(status), 0);
}
#endif

int main(void) {
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_hook_works),
        cmocka_unit_test(test_single_failure),
        cmocka_unit_test(test_exhausted),
#if defined(__linux__)
        cmocka_unit_test(test_system_refuses_large_arrays),
#endif
    };
    if (getenv("HGCD_TEST_FILTER")) cmocka_set_test_filter(getenv("HGCD_TEST_FILTER"));
    return cmocka_run_group_tests(tests, NULL, NULL);
}
