/* Events: at every detect, the began and ended pairs must be exactly the
 * difference between the previous detect's pairs and this one's, compared
 * by full ids, sorted, each with both bodies' user data as created (also
 * for bodies destroyed since, and for slots reused in between). The world
 * is driven with moves, deaths, births, disabling, filters, types and
 * exclusions, on 1 to 3 threads, with steps and detects. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include "support/shapes.h"

#include <cmocka.h>

#include <hgcd/hgcd.h>

#include "test_rng.h"

enum { kCap = 600, kMaxIds = 20000 };


/* Every body ever created: its id and user data. */
static hgcd_body ever_id[kMaxIds];
static uint64_t ever_user[kMaxIds];
static size_t ever;

static uint64_t user_of(hgcd_body b) {
    for (size_t k = 0; k < ever; ++k)
        if (ever_id[k].index == b.index && ever_id[k].generation == b.generation) return ever_user[k];
    fail_msg("body {%u, %u} was never created", b.index, b.generation);
    return 0;
}

static int pair_cmp(const hgcd_pair *x, const hgcd_pair *y) {
    if (x->a.index != y->a.index) return x->a.index < y->a.index ? -1 : 1;
    if (x->b.index != y->b.index) return x->b.index < y->b.index ? -1 : 1;
    return 0;
}

static int same(const hgcd_pair *x, const hgcd_pair *y) {
    return !memcmp(x, y, sizeof *x);
}

/* Whether p is in the sorted list (by full id). */
static int contains(const hgcd_pair *list, size_t n, const hgcd_pair *p) {
    for (size_t k = 0; k < n; ++k)
        if (same(&list[k], p)) return 1;
    return 0;
}

/* Checks one array of events against the pairs of `from` missing in `to`. */
static size_t check_diff(const hgcd_pair_event *ev, size_t count, const hgcd_pair *from, size_t n_from,
                         const hgcd_pair *to, size_t n_to) {
    size_t k = 0;
    for (size_t i = 0; i < n_from; ++i) {
        if (contains(to, n_to, &from[i])) continue;
        assert_true(k < count);
        assert_true(same(&ev[k].pair, &from[i]));
        assert_true(ev[k].user_data_a == user_of(from[i].a));
        assert_true(ev[k].user_data_b == user_of(from[i].b));
        if (k) assert_true(pair_cmp(&ev[k - 1].pair, &ev[k].pair) < 0);
        ++k;
    }
    assert_int_equal(k, count);
    return count;
}

static void test_events_are_the_difference(void **state) {
    (void)state;
    hgcd_world *w;
    hgcd_world_desc wd = hgcd_world_desc_default();
    assert_int_equal(hgcd_world_create(&wd, &w), HGCD_OK);
    hgcd_mesh_desc md = hgcd_mesh_desc_default();
    md.vertices = tetra_v, md.vertex_count = 4, md.triangles = tetra_t, md.triangle_count = 4;
    hgcd_mesh mesh;
    assert_int_equal(hgcd_mesh_create(w, &md, &mesh), HGCD_OK);
    static hgcd_body id[kCap];
    static int live[kCap];
    rng r = {42};
    const double side = 18;
    ever = 0;
    hgcd_pair *old = NULL;
    size_t n_old = 0, began_total = 0, ended_total = 0, reborn = 0;
    for (int tick = 0; tick < 30; ++tick) {
        for (int c = 0; c < (tick ? 80 : kCap); ++c) {
            const int i = (int)(next(&r) % kCap);
            if (!live[i]) {
                hgcd_body_desc bd = hgcd_body_desc_default();
                bd.mesh = mesh;
                for (int k = 0; k < 3; ++k) bd.position[k] = side * unif(&r);
                random_unit_quaternion(&r, bd.orientation);
                bd.user_data = next(&r);
                for (int k = 0; k < 3; ++k) bd.velocity[k] = 0.3 * (unif(&r) - 0.5);
                hgcd_body b;
                assert_int_equal(hgcd_body_create(w, &bd, &b), HGCD_OK);
                assert_true(ever < kMaxIds);
                ever_id[ever] = b;
                ever_user[ever++] = bd.user_data;
                /* (the world's slot, not i: the test's own index) */
                int at = -1;
                for (int k = 0; k < kCap && at < 0; ++k)
                    if (!live[k]) at = k;
                id[at] = b;
                live[at] = 1;
                continue;
            }
            double p[3];
            switch (next(&r) % 10) {
            case 0: /* a death, its slot reused soon after by a birth */
                assert_int_equal(hgcd_body_destroy(w, id[i]), HGCD_OK);
                live[i] = 0;
                ++reborn;
                break;
            case 1: {
                uint32_t on;
                assert_int_equal(hgcd_body_get_enabled(w, id[i], &on), HGCD_OK);
                assert_int_equal(hgcd_body_set_enabled(w, id[i], !on), HGCD_OK);
                break;
            }
            case 2: {
                hgcd_filter f = hgcd_filter_default();
                f.group_index = (int32_t)(next(&r) % 3) - 1;
                assert_int_equal(hgcd_body_set_filter(w, id[i], &f), HGCD_OK);
                break;
            }
            case 3:
                assert_int_equal(hgcd_body_set_type(w, id[i], (int32_t)(next(&r) % 3)), HGCD_OK);
                break;
            case 4: {
                const int j = (int)(next(&r) % kCap);
                if (live[j] && j != i) assert_int_equal(hgcd_world_exclude_pair(w, id[i], id[j]), HGCD_OK);
                break;
            }
            default:
                for (int k = 0; k < 3; ++k) p[k] = side * unif(&r);
                assert_int_equal(hgcd_body_set_pose(w, id[i], p, NULL), HGCD_OK);
            }
        }
        assert_int_equal(hgcd_world_set_thread_count(w, 1 + (uint32_t)(tick % 3)), HGCD_OK);
        assert_int_equal(tick % 4 == 3 ? hgcd_world_step(w) : hgcd_world_detect(w), HGCD_OK);
        const hgcd_pair *pairs;
        size_t n;
        assert_int_equal(hgcd_world_pairs(w, &pairs, &n), HGCD_OK);
        const hgcd_pair_event *began, *ended;
        size_t nb, ne;
        assert_int_equal(hgcd_world_events(w, &began, &nb, &ended, &ne), HGCD_OK);
        began_total += check_diff(began, nb, pairs, n, old, n_old);
        ended_total += check_diff(ended, ne, old, n_old, pairs, n);
        /* A detect with nothing changed: no events. */
        if (tick % 5 == 4) {
            assert_int_equal(hgcd_world_detect(w), HGCD_OK);
            assert_int_equal(hgcd_world_events(w, &began, &nb, &ended, &ne), HGCD_OK);
            assert_int_equal(nb, 0);
            assert_int_equal(ne, 0);
            assert_int_equal(hgcd_world_pairs(w, &pairs, &n), HGCD_OK);
        }
        free(old);
        old = malloc((n + 1) * sizeof *old);
        if (n) memcpy(old, pairs, n * sizeof *old);
        n_old = n;
    }
    free(old);
    /* The drive made plenty of both, and reused slots. */
    assert_true(began_total > 500);
    assert_true(ended_total > 300);
    assert_true(reborn > 100);
    const hgcd_pair_event *e;
    size_t c;
    assert_int_equal(hgcd_world_events(w, NULL, &c, &e, &c), HGCD_ERROR_NULL_ARGUMENT);
    assert_int_equal(hgcd_world_events(NULL, &e, &c, &e, &c), HGCD_ERROR_NULL_ARGUMENT);
    hgcd_world_destroy(w);
}

int main(void) {
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_events_are_the_difference),
    };
    if (getenv("HGCD_TEST_FILTER")) cmocka_set_test_filter(getenv("HGCD_TEST_FILTER"));
    return cmocka_run_group_tests(tests, NULL, NULL);
}
