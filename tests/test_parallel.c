/* How hgcd runs its parallel work. The adaptive thread policy
 * (hgcd_world_desc.thread_policy, src/world/threads.hpp): its decisions on
 * simulated machines (quiet, loaded for a while, idle threads sleeping at
 * barriers, more cores than pay), and through the API: the policy's
 * refusals, and the same pairs under either policy. */
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
 * threads lose time, and settles on 2 (1 is never tried: 2 lose nothing). */
static void test_halves_to_the_best(void **state) {
    (void)state;
    static const double rate[] = {0, 1.0, 0.7, 0, 1.5, 0, 0, 0, 3.0};
    static const double lost[] = {0, 0, 0.05, 0, 0.6, 0, 0, 0, 0.8};
    machine m = machine_new(8, 2000);
    machine_set(&m, 0, 2000, rate, lost);
    machine_run(&m);
    assert_int_equal(m.used[0], 8);
    assert_int_equal(m.used[1], 4);
    assert_int_equal(m.used[2], 2);
    assert_int_equal(count_used(&m, 0, 2000, 1), 0);
    assert_true(count_used(&m, 0, 2000, 2) >= 1980);
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

int main(void) {
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_quiet_keeps_all_threads), cmocka_unit_test(test_load_comes_and_goes),
        cmocka_unit_test(test_lost_time_but_faster),    cmocka_unit_test(test_halves_to_the_best),
        cmocka_unit_test(test_policy_api),              cmocka_unit_test(test_same_pairs_either_policy),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
