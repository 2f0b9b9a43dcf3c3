/* How hgcd runs its parallel work. The adaptive thread policy
 * (hgcd_world_desc.thread_policy, src/world/threads.hpp): its decisions on
 * simulated machines (quiet, loaded for a while, idle threads sleeping at
 * barriers, more cores than pay), and through the API: the policy's
 * refusals, and the same pairs under either policy. The caller's task system
 * (hgcd_world_desc.enqueue_task): a small job system of POSIX threads and a
 * queue, and one that runs every loop inline, give the pairs and counts of
 * the OpenMP path bit for bit through steps, pushed poses, renumbering and
 * destroyed bodies; a task system that breaks its contract fails the call
 * with HGCD_ERROR_INTERNAL, and the world works again after. */
#include <pthread.h>
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

#include "support/testing.h"

/* A simulated machine: per detect and thread count, seconds per unit of
 * work and the fraction of time the threads lose off a core. */
typedef struct machine {
    int full;
    uint32_t count;
    double *rate, *lost;
    int *used;
} machine;

static machine machine_new(int full, uint32_t count) {
    machine m = {full, count, calloc((size_t)count * (size_t)(full + 1), sizeof(double)),
                 calloc((size_t)count * (size_t)(full + 1), sizeof(double)), calloc(count, sizeof(int))};
    assert_non_null(m.rate);
    assert_non_null(m.lost);
    assert_non_null(m.used);
    return m;
}

static void machine_free(machine *m) {
    free(m->rate);
    free(m->lost);
    free(m->used);
}

/* Detects [from, to) run at rate[t] with lost[t] on t threads (t <= full). */
static void machine_set(machine *m, uint32_t from, uint32_t to, const double *rate, const double *lost) {
    for (uint32_t k = from; k < to; ++k)
        for (int t = 1; t <= m->full; ++t) {
            m->rate[(size_t)k * (size_t)(m->full + 1) + (size_t)t] = rate[t];
            m->lost[(size_t)k * (size_t)(m->full + 1) + (size_t)t] = lost[t];
        }
}

static void machine_run(machine *m) { hgcdi_thread_governor(m->full, m->count, m->rate, m->lost, m->used); }

/* Seconds the detects [from, to) took, per unit. */
static double machine_cost(const machine *m, uint32_t from, uint32_t to) {
    double sum = 0;
    for (uint32_t k = from; k < to; ++k) sum += m->rate[(size_t)k * (size_t)(m->full + 1) + (size_t)m->used[k]];
    return sum;
}

/* Seconds the detects [from, to) would take, per unit, all on `threads`. */
static double machine_cost_if(const machine *m, uint32_t from, uint32_t to, int threads) {
    double sum = 0;
    for (uint32_t k = from; k < to; ++k) sum += m->rate[(size_t)k * (size_t)(m->full + 1) + (size_t)threads];
    return sum;
}

static uint32_t count_used(const machine *m, uint32_t from, uint32_t to, int threads) {
    uint32_t c = 0;
    for (uint32_t k = from; k < to; ++k) c += m->used[k] == threads;
    return c;
}

/* Rates and losses of 2 threads on 2 quiet cores, and with 2 busy processes
 * (the spinning threads wait for each other: 2 threads slower than 1). */
static const double quiet_rate[] = {0, 1.0, 0.55}, quiet_lost[] = {0, 0, 0.01};
static const double busy_rate[] = {0, 1.4, 3.0}, busy_lost[] = {0, 0, 0.8};

static void test_quiet_keeps_all_threads(void **state) {
    (void)state;
    machine m = machine_new(2, 3000);
    machine_set(&m, 0, 3000, quiet_rate, quiet_lost);
    machine_run(&m);
    assert_int_equal(count_used(&m, 0, 3000, 2), 3000);
    machine_free(&m);
}

/* Quiet, then 1000 detects under load, then quiet again. */
static void test_load_comes_and_goes(void **state) {
    (void)state;
    enum { LOAD = 100, QUIET = 1100, N = 3000 };
    machine m = machine_new(2, N);
    machine_set(&m, 0, LOAD, quiet_rate, quiet_lost);
    machine_set(&m, LOAD, QUIET, busy_rate, busy_lost);
    machine_set(&m, QUIET, N, quiet_rate, quiet_lost);
    machine_run(&m);
    assert_int_equal(count_used(&m, 0, LOAD + 1, 2), LOAD + 1);  /* the first loaded detect still on 2 */
    assert_int_equal(m.used[LOAD + 1], 1);                          /* then a check on 1, which wins */
    /* Under load: probes of 2 threads after 8, 16, ... 512 detects, no more. */
    const uint32_t probes = count_used(&m, LOAD + 1, QUIET, 2);
    assert_true(probes >= 5 && probes <= 8);
    assert_true(machine_cost(&m, LOAD, QUIET) <= 1.05 * (QUIET - LOAD) * busy_rate[1]);
    /* Back on 2 threads at the next probe (within 512 detects), and staying. */
    uint32_t back = QUIET;
    while (back < N && m.used[back] != 2) ++back;
    assert_true(back - QUIET <= 513);
    assert_int_equal(count_used(&m, back, N, 2), N - back);
    machine_free(&m);
}

/* Idle threads that sleep at barriers (OMP_WAIT_POLICY=passive) lose time
 * even on quiet cores, yet 2 threads stay faster: the checks on 1 thread
 * lose, and come ever more rarely. */
static void test_lost_time_but_faster(void **state) {
    (void)state;
    static const double rate[] = {0, 1.0, 0.6}, lost[] = {0, 0, 0.4};
    machine m = machine_new(2, 3000);
    machine_set(&m, 0, 3000, rate, lost);
    machine_run(&m);
    const uint32_t checks = count_used(&m, 0, 3000, 1);
    assert_true(checks >= 1 && checks <= 14);
    assert_true(machine_cost(&m, 0, 3000) <= 1.02 * 3000 * rate[2]);
    machine_free(&m);
}

/* 8 threads where 2 do the work fastest under load: the count halves while
 * threads lose time (each check followed by a detect on the count before
 * it), and settles on 2 (1 is never tried: 2 lose nothing). */
static void test_halves_to_the_best(void **state) {
    (void)state;
    static const double rate[] = {0, 1.0, 0.7, 0, 1.5, 0, 0, 0, 3.0};
    static const double lost[] = {0, 0, 0.05, 0, 0.6, 0, 0, 0, 0.8};
    machine m = machine_new(8, 2000);
    machine_set(&m, 0, 2000, rate, lost);
    machine_run(&m);
    static const int start[] = {8, 4, 8, 2, 4, 2, 2};
    for (int k = 0; k < 7; ++k) assert_int_equal(m.used[k], start[k]);
    assert_int_equal(count_used(&m, 0, 2000, 1), 0);
    assert_true(count_used(&m, 0, 2000, 2) >= 1980);
    machine_free(&m);
}

/* Quiet cores where one detect in 20 is slowed by a passing blip that
 * loses half its threads' time (short ticks, one descheduling): the check
 * on 1 thread after each blip loses against the detect that follows it, so
 * the world keeps 2 threads (the checks grow rarer: at most 12 in 3000;
 * with the check decided on the blipped detect alone, 1350 detects ran on
 * 1 thread, 33% over the cost of 2). */
static void test_blips_keep_all_threads(void **state) {
    (void)state;
    static const double blip_rate[] = {0, 1.0, 2.0}, blip_lost[] = {0, 0.5, 0.5};
    enum { N = 3000 };
    machine m = machine_new(2, N);
    machine_set(&m, 0, N, quiet_rate, quiet_lost);
    for (uint32_t k = 7; k < N; k += 20) machine_set(&m, k, k + 1, blip_rate, blip_lost);
    machine_run(&m);
    const uint32_t on_one = count_used(&m, 0, N, 1);
    assert_true(on_one >= 1 && on_one <= 12);
    assert_true(machine_cost(&m, 0, N) <= 1.01 * machine_cost_if(&m, 0, N, 2));
    machine_free(&m);
}

static void test_policy_api(void **state) {
    (void)state;
    hgcd_world_desc d = hgcd_world_desc_default();
    assert_int_equal(d.thread_policy, HGCD_THREADS_ADAPTIVE);
    hgcd_world *w = NULL;
    d.thread_policy = 2;
    assert_int_equal(hgcd_world_create(&d, &w), HGCD_ERROR_INVALID_ARGUMENT);
    assert_null(w);
    d.thread_policy = -1;
    assert_int_equal(hgcd_world_create(&d, &w), HGCD_ERROR_INVALID_ARGUMENT);
    d.thread_policy = HGCD_THREADS_FIXED;
    assert_int_equal(hgcd_world_create(&d, &w), HGCD_OK);
    assert_int_equal(hgcd_world_set_thread_policy(NULL, HGCD_THREADS_FIXED), HGCD_ERROR_NULL_ARGUMENT);
    assert_int_equal(hgcd_world_set_thread_policy(w, 5), HGCD_ERROR_INVALID_ARGUMENT);
    assert_non_null(strstr(hgcd_world_last_error(w), "world_set_thread_policy"));
    assert_int_equal(hgcd_world_set_thread_policy(w, HGCD_THREADS_ADAPTIVE), HGCD_OK);
    assert_int_equal(hgcd_world_set_thread_policy(w, HGCD_THREADS_FIXED), HGCD_OK);
    hgcd_world_destroy(w);
}

/* A tetra scene of n bodies under the policy, stepped `ticks` times; each
 * tick's pairs appended to *out (count in *total), stats.thread_count
 * checked against what the policy allows. */
static void run_scene(int32_t policy, uint64_t n, int ticks, hgcd_pair **out, size_t *total) {
    hgcd_world_desc d = hgcd_world_desc_default();
    d.thread_count = 2;
    d.thread_policy = policy;
    hgcd_world *w = NULL;
    hgcd_scene_tetra_desc sd = hgcd_scene_tetra_desc_default();
    sd.n = n;
    sd.side = 60; /* about the reference density at n = 20000 */
    d.reflect_at_bounds = 1;
    for (int k = 0; k < 3; ++k) d.bounds_max[k] = sd.side;
    assert_int_equal(hgcd_world_create(&d, &w), HGCD_OK);
    assert_int_equal(hgcd_scene_tetra_populate(w, &sd, NULL), HGCD_OK);
    *total = 0;
    *out = NULL;
    for (int t = 0; t <= ticks; ++t) {
        assert_int_equal(t ? hgcd_world_step(w) : hgcd_world_detect(w), HGCD_OK);
        hgcd_stats st;
        memset(&st, 0, sizeof st);
        st.struct_size = sizeof st;
        assert_int_equal(hgcd_world_stats(w, &st), HGCD_OK);
        if (policy == HGCD_THREADS_FIXED || t == 0)
            assert_int_equal(st.thread_count, 2);
        else
            assert_true(st.thread_count == 1 || st.thread_count == 2);
        const hgcd_pair *p;
        size_t np;
        assert_int_equal(hgcd_world_pairs(w, &p, &np), HGCD_OK);
        *out = realloc(*out, (*total + np + 1) * sizeof **out);
        assert_non_null(*out);
        memcpy(*out + *total, p, np * sizeof *p);
        *total += np;
    }
    hgcd_world_destroy(w);
}

static void test_same_pairs_either_policy(void **state) {
    (void)state;
    hgcd_pair *a, *b;
    size_t na, nb;
    run_scene(HGCD_THREADS_FIXED, 20000, 12, &a, &na);
    run_scene(HGCD_THREADS_ADAPTIVE, 20000, 12, &b, &nb);
    assert_true(na > 1000);
    assert_int_equal(na, nb);
    for (size_t k = 0; k < na; ++k) { /* (generations carry each world's own tag in their top 8 bits) */
        assert_int_equal(a[k].a.index, b[k].a.index);
        assert_int_equal(a[k].b.index, b[k].b.index);
        assert_int_equal(a[k].a.generation & 0xFFFFFF, b[k].a.generation & 0xFFFFFF);
        assert_int_equal(a[k].b.generation & 0xFFFFFF, b[k].b.generation & 0xFFFFFF);
    }
    free(a);
    free(b);
}

/* ---- A job system: `workers - 1` POSIX threads and the thread calling
 * finish_task take ranges from one queue; worker 0 is the caller's. */
enum { MAX_WORKERS = 8, MAX_ITEMS = 4096 };

typedef struct job {
    hgcd_task_fn *task;
    void *context;
    uint32_t begin, end;
    struct loop *loop;
} job;

typedef struct loop {
    int remaining; /* ranges not yet finished */
} loop;

typedef struct jobs {
    pthread_mutex_t mutex;
    pthread_cond_t work, done;
    job queue[MAX_ITEMS];
    int head, tail; /* queue[head, tail) */
    int workers, stop;
    pthread_t thread[MAX_WORKERS];
    loop loops[64];
    int next_loop;
    /* Misbehaviour on request (once): 1 a worker index past the count, 2 an
     * item skipped. */
    int misbehave;
    uint64_t loops_run, ranges_run;
} jobs;

typedef struct worker_arg {
    jobs *j;
    uint32_t index;
} worker_arg;

static worker_arg worker_args[MAX_WORKERS];

static void run_job(jobs *j, job *x, uint32_t worker) {
    x->task(x->begin, x->end, worker, x->context);
    pthread_mutex_lock(&j->mutex);
    ++j->ranges_run;
    if (--x->loop->remaining == 0) pthread_cond_broadcast(&j->done);
    pthread_mutex_unlock(&j->mutex);
}

static void *worker_main(void *arg) {
    worker_arg *w = arg;
    jobs *j = w->j;
    pthread_mutex_lock(&j->mutex);
    for (;;) {
        while (!j->stop && j->head == j->tail) pthread_cond_wait(&j->work, &j->mutex);
        if (j->stop) break;
        job x = j->queue[j->head++];
        pthread_mutex_unlock(&j->mutex);
        run_job(j, &x, w->index);
        pthread_mutex_lock(&j->mutex);
    }
    pthread_mutex_unlock(&j->mutex);
    return NULL;
}

static void *enqueue(hgcd_task_fn *task, uint32_t item_count, uint32_t min_range, void *task_context,
                     void *user_context) {
    jobs *j = user_context;
    uint32_t range = (item_count + 4 * (uint32_t)j->workers - 1) / (4 * (uint32_t)j->workers);
    if (range < min_range) range = min_range;
    if (range == 0) range = 1;
    pthread_mutex_lock(&j->mutex);
    assert_true(j->head == j->tail); /* hgcd finishes each loop before the next */
    j->head = j->tail = 0;
    loop *l = &j->loops[j->next_loop++ % 64];
    l->remaining = 0;
    int skip = j->misbehave == 2, bad_worker = j->misbehave == 1;
    for (uint32_t b = 0; b < item_count; b += range) {
        job x = {task, task_context, b, b + range < item_count ? b + range : item_count, l};
        if (skip && b > 0) { /* the second range is dropped */
            skip = 0;
            j->misbehave = 0;
            continue;
        }
        if (bad_worker) { /* the first range run here, as a worker past the count */
            bad_worker = 0;
            j->misbehave = 0;
            pthread_mutex_unlock(&j->mutex);
            task(x.begin, x.end, (uint32_t)j->workers, task_context);
            pthread_mutex_lock(&j->mutex);
            continue;
        }
        assert_true(j->tail < MAX_ITEMS);
        j->queue[j->tail++] = x;
        ++l->remaining;
    }
    ++j->loops_run;
    pthread_cond_broadcast(&j->work);
    pthread_mutex_unlock(&j->mutex);
    return l;
}

static void finish(void *handle, void *user_context) {
    jobs *j = user_context;
    loop *l = handle;
    pthread_mutex_lock(&j->mutex);
    while (l->remaining > 0) {
        if (j->head < j->tail) { /* the caller helps, as worker 0 */
            job x = j->queue[j->head++];
            pthread_mutex_unlock(&j->mutex);
            run_job(j, &x, 0);
            pthread_mutex_lock(&j->mutex);
        } else {
            pthread_cond_wait(&j->done, &j->mutex);
        }
    }
    pthread_mutex_unlock(&j->mutex);
}

static void jobs_start(jobs *j, int workers) {
    memset(j, 0, sizeof *j);
    j->workers = workers;
    pthread_mutex_init(&j->mutex, NULL);
    pthread_cond_init(&j->work, NULL);
    pthread_cond_init(&j->done, NULL);
    for (int w = 1; w < workers; ++w) {
        worker_args[w] = (worker_arg){j, (uint32_t)w};
        assert_int_equal(pthread_create(&j->thread[w], NULL, worker_main, &worker_args[w]), 0);
    }
}

static void jobs_stop(jobs *j) {
    pthread_mutex_lock(&j->mutex);
    j->stop = 1;
    pthread_cond_broadcast(&j->work);
    pthread_mutex_unlock(&j->mutex);
    for (int w = 1; w < j->workers; ++w) pthread_join(j->thread[w], NULL);
    pthread_mutex_destroy(&j->mutex);
    pthread_cond_destroy(&j->work);
    pthread_cond_destroy(&j->done);
}

/* A task system that runs each loop at once, inline, as worker 0. */
static uint64_t inline_loops;
static void *enqueue_inline(hgcd_task_fn *task, uint32_t item_count, uint32_t min_range, void *task_context,
                            void *user_context) {
    (void)min_range;
    (void)user_context;
    ++inline_loops;
    task(0, item_count, 0, task_context);
    return NULL;
}
static void finish_never(void *handle, void *user_context) {
    (void)handle;
    (void)user_context;
    fail_msg("finish_task called for a NULL handle");
}

/* A tetra world of n bodies at about the reference density (reflecting), on 2 OpenMP
 * threads or on the given task system with `workers` workers. */
static hgcd_world *tetra_world(uint64_t n, hgcd_enqueue_task_fn *enq, hgcd_finish_task_fn *fin, void *ctx,
                               uint32_t workers, hgcd_scene_tetra_desc *sd) {
    hgcd_world_desc d = hgcd_world_desc_default();
    d.thread_count = enq ? workers : 2;
    d.thread_policy = HGCD_THREADS_FIXED;
    d.enqueue_task = enq;
    d.finish_task = fin;
    d.task_context = ctx;
    *sd = hgcd_scene_tetra_desc_default();
    sd->n = n;
    sd->side = 60 * cbrt((double)n / 20000); /* about the reference density */
    d.reflect_at_bounds = 1;
    for (int k = 0; k < 3; ++k) d.bounds_max[k] = sd->side;
    hgcd_world *w = NULL;
    assert_int_equal(hgcd_world_create(&d, &w), HGCD_OK);
    assert_int_equal(hgcd_scene_tetra_populate(w, sd, NULL), HGCD_OK);
    return w;
}

/* Both worlds report the same pairs (indices and generation counters) and
 * the same counts; returns the pair count. */
static size_t same_results(hgcd_world *a, hgcd_world *b) {
    const hgcd_pair *pa, *pb;
    size_t na, nb;
    assert_int_equal(hgcd_world_pairs(a, &pa, &na), HGCD_OK);
    assert_int_equal(hgcd_world_pairs(b, &pb, &nb), HGCD_OK);
    assert_int_equal(na, nb);
    for (size_t k = 0; k < na; ++k) {
        assert_int_equal(pa[k].a.index, pb[k].a.index);
        assert_int_equal(pa[k].b.index, pb[k].b.index);
        assert_int_equal(pa[k].a.generation & 0xFFFFFF, pb[k].a.generation & 0xFFFFFF);
        assert_int_equal(pa[k].b.generation & 0xFFFFFF, pb[k].b.generation & 0xFFFFFF);
    }
    hgcd_stats sa, sb;
    memset(&sa, 0, sizeof sa);
    memset(&sb, 0, sizeof sb);
    sa.struct_size = sb.struct_size = sizeof sa;
    assert_int_equal(hgcd_world_stats(a, &sa), HGCD_OK);
    assert_int_equal(hgcd_world_stats(b, &sb), HGCD_OK);
    assert_int_equal(sa.candidate_pairs, sb.candidate_pairs);
    assert_int_equal(sa.narrow_tests, sb.narrow_tests);
    assert_int_equal(sa.triangle_tests, sb.triangle_tests);
    assert_int_equal(sa.containment_pairs, sb.containment_pairs);
    assert_int_equal(sa.moved_bodies, sb.moved_bodies);
    assert_int_equal(sa.unmoved_pairs, sb.unmoved_pairs);
    assert_int_equal(sa.level_count, sb.level_count);
    assert_int_equal(sa.searched_bodies, sb.searched_bodies);
    return na;
}

static uint64_t test_n(void) {
    const char *e = getenv("HGCD_TEST_TETRA_N");
    return e ? strtoull(e, NULL, 10) : 20000;
}

/* The same script on an OpenMP world and a task world: steps, then engine
 * ticks (the caller moves and turns its bodies, set_poses, detect), a
 * tick where nothing moved, destroyed bodies, and enough steps for storage
 * renumbering. */
static void run_against_openmp(hgcd_enqueue_task_fn *enq, hgcd_finish_task_fn *fin, void *ctx, uint32_t workers) {
    hgcd_scene_tetra_desc sd;
    const uint64_t n = test_n();
    hgcd_world *omp = tetra_world(n, NULL, NULL, NULL, 0, &sd);
    hgcd_world *tw = tetra_world(n, enq, fin, ctx, workers, &sd);
    double *pos = malloc(3 * n * sizeof(double)), *vel = malloc(3 * n * sizeof(double));
    double *quat = malloc(4 * n * sizeof(double));
    assert_non_null(pos);
    assert_non_null(vel);
    assert_non_null(quat);
    assert_int_equal(hgcd_scene_tetra_generate(&sd, pos, NULL, NULL, quat, vel), 0);
    size_t total = 0;
    for (int t = 0; t < 12; ++t) {
        hgcd_world *both[2] = {omp, tw};
        for (int k = 0; k < 2; ++k) {
            hgcd_world *w = both[k];
            if (t == 0) {
                assert_int_equal(hgcd_world_detect(w), HGCD_OK);
            } else if (t < 5 || t == 9) {
                assert_int_equal(hgcd_world_step(w), HGCD_OK);
            } else if (t == 7) {
                assert_int_equal(hgcd_world_detect(w), HGCD_OK); /* nothing moved */
            } else if (t >= 10) {
                if (t == 10) { /* the a-bodies of every seventh pair die (the same indices in both) */
                    const hgcd_pair *p;
                    size_t np;
                    assert_int_equal(hgcd_world_pairs(w, &p, &np), HGCD_OK);
                    hgcd_body dead[64];
                    size_t nd = 0;
                    for (size_t q = 0; q < np && nd < 64; q += 7)
                        if (nd == 0 || dead[nd - 1].index != p[q].a.index) dead[nd++] = p[q].a;
                    for (size_t q = 0; q < nd; ++q) assert_int_equal(hgcd_body_destroy(w, dead[q]), HGCD_OK);
                }
                assert_int_equal(hgcd_world_step(w), HGCD_OK);
            } else {
                if (k == 0 && t == 8) { /* one body in ten moves: the search around the movers alone */
                    for (uint64_t i = 0; i < n; i += 10) pos[3 * i + (i / 10) % 3] += 0.05;
                } else if (k == 0) { /* the caller's motion, once for both; first from the world's poses */
                    if (t == 5) assert_int_equal(hgcd_world_get_poses(w, NULL, (size_t)n, pos, 0, quat, 0), HGCD_OK);
                    hgcd_scene_tetra_move(n, sd.side, pos, vel);
                    for (uint64_t i = 0; i < n; i += 3) { /* every third body turns */
                        double *q = quat + 4 * i, x = q[0];
                        q[0] = q[1], q[1] = -x; /* (another unit quaternion) */
                    }
                }
                assert_int_equal(hgcd_world_set_poses(w, NULL, (size_t)n, pos, 0, quat, 0), HGCD_OK);
                assert_int_equal(hgcd_world_detect(w), HGCD_OK);
            }
        }
        total += same_results(omp, tw);
        if (t == 8) { /* (the incremental search ran) */
            hgcd_stats st;
            memset(&st, 0, sizeof st);
            st.struct_size = sizeof st;
            assert_int_equal(hgcd_world_stats(tw, &st), HGCD_OK);
            assert_true(st.searched_bodies > 0 && st.searched_bodies < n / 2);
        }
    }
    assert_true(total > n / 10);
    free(pos);
    free(vel);
    free(quat);
    hgcd_world_destroy(omp);
    hgcd_world_destroy(tw);
}

static void test_task_system_same_pairs(void **state) {
    (void)state;
    jobs j;
    jobs_start(&j, 3);
    run_against_openmp(enqueue, finish, &j, 3);
    assert_true(j.loops_run > 50);
    assert_true(j.ranges_run > j.loops_run);
    jobs_stop(&j);
}

static void test_inline_task_system_same_pairs(void **state) {
    (void)state;
    inline_loops = 0;
    run_against_openmp(enqueue_inline, finish_never, NULL, 2); /* (worker 0 only: fine, any worker < 2 is) */
    assert_true(inline_loops > 50);
}

static void test_task_system_misuse(void **state) {
    (void)state;
    jobs j;
    jobs_start(&j, 2);
    hgcd_scene_tetra_desc sd;
    hgcd_world *omp = tetra_world(3000, NULL, NULL, NULL, 0, &sd);
    hgcd_world *tw = tetra_world(3000, enqueue, finish, &j, 2, &sd);
    assert_int_equal(hgcd_world_detect(omp), HGCD_OK);
    for (int bad = 1; bad <= 2; ++bad) {
        j.misbehave = bad;
        assert_int_equal(hgcd_world_detect(tw), HGCD_ERROR_INTERNAL);
        assert_non_null(strstr(hgcd_world_last_error(tw), "task system"));
        assert_int_equal(j.misbehave, 0);
    }
    assert_int_equal(hgcd_world_detect(tw), HGCD_OK); /* and again, with the task system behaving */
    same_results(omp, tw);
    /* Refusals: one callback without the other; no worker count. */
    hgcd_world_desc d = hgcd_world_desc_default();
    hgcd_world *w = NULL;
    d.thread_count = 2;
    d.enqueue_task = enqueue;
    assert_int_equal(hgcd_world_create(&d, &w), HGCD_ERROR_INVALID_ARGUMENT);
    d.enqueue_task = NULL;
    d.finish_task = finish;
    assert_int_equal(hgcd_world_create(&d, &w), HGCD_ERROR_INVALID_ARGUMENT);
    d.enqueue_task = enqueue;
    d.thread_count = 0;
    assert_int_equal(hgcd_world_create(&d, &w), HGCD_ERROR_INVALID_ARGUMENT);
    assert_null(w);
    assert_int_equal(hgcd_world_set_thread_count(tw, 0), HGCD_ERROR_INVALID_ARGUMENT);
    assert_int_equal(hgcd_world_set_thread_count(tw, 1), HGCD_OK); /* fewer workers than the system has: fine */
    assert_int_equal(hgcd_world_step(tw), HGCD_OK);
    assert_int_equal(hgcd_world_step(omp), HGCD_OK);
    same_results(omp, tw);
    hgcd_world_destroy(omp);
    hgcd_world_destroy(tw);
    jobs_stop(&j);
}

int main(void) {
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_quiet_keeps_all_threads), cmocka_unit_test(test_load_comes_and_goes),
        cmocka_unit_test(test_lost_time_but_faster),    cmocka_unit_test(test_halves_to_the_best),
        cmocka_unit_test(test_policy_api),              cmocka_unit_test(test_same_pairs_either_policy),
        cmocka_unit_test(test_task_system_same_pairs),  cmocka_unit_test(test_inline_task_system_same_pairs),
        cmocka_unit_test(test_task_system_misuse),        cmocka_unit_test(test_blips_keep_all_threads),
    };
    if (getenv("HGCD_TEST_FILTER")) cmocka_set_test_filter(getenv("HGCD_TEST_FILTER"));
    return cmocka_run_group_tests(tests, NULL, NULL);
}
