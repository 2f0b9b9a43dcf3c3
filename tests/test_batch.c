/* The batched state calls (hgcd_world_set_poses, hgcd_world_set_velocities,
 * hgcd_world_get_poses): the same world as the per-body calls give, strided
 * layouts, all bodies by index, and every refusal leaving the world as it
 * was (snapshot.h) with the first bad entry named. */
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

#include "snapshot.h"
#include "test_rng.h"

static const double kTetraVerts[12] = {1, 1, 1, 1, -1, -1, -1, 1, -1, -1, -1, 1};
static const uint32_t kTetraTris[12] = {0, 1, 2, 0, 3, 1, 0, 2, 3, 1, 3, 2};
/* A box: 8 vertices, 12 triangles (its box uses its distinct vertices). */
static const double kBoxVerts[24] = {-1, -1, -1, 1, -1, -1, -1, 1, -1, 1, 1, -1,
                                     -1, -1, 1,  1, -1, 1,  -1, 1, 1,  1, 1, 1};
static const uint32_t kBoxTris[36] = {0, 2, 1, 1, 2, 3, 4, 5, 6, 5, 7, 6, 0, 1, 4, 1, 5, 4,
                                      2, 6, 3, 3, 6, 7, 0, 4, 2, 2, 4, 6, 1, 3, 5, 3, 7, 5};

/* The caller's own body record: the batch reads positions and orientations
 * in place through strides. */
typedef struct {
    uint64_t tag;
    double position[3];
    double velocity[3];
    double orientation[4];
} engine_body;

static hgcd_world *make_world(int threads, hgcd_body *bodies, int n) {
    hgcd_world *w = NULL;
    hgcd_world_desc d = hgcd_world_desc_default();
    d.thread_count = (uint32_t)threads;
    assert_int_equal(hgcd_world_create(&d, &w), HGCD_OK);
    hgcd_mesh_desc md = hgcd_mesh_desc_default();
    hgcd_mesh meshes[2];
    md.vertices = kTetraVerts, md.vertex_count = 4, md.triangles = kTetraTris, md.triangle_count = 4;
    assert_int_equal(hgcd_mesh_create(w, &md, &meshes[0]), HGCD_OK);
    md.vertices = kBoxVerts, md.vertex_count = 8, md.triangles = kBoxTris, md.triangle_count = 12;
    assert_int_equal(hgcd_mesh_create(w, &md, &meshes[1]), HGCD_OK);
    for (int i = 0; i < n; ++i) {
        hgcd_body_desc bd = hgcd_body_desc_default();
        bd.mesh = meshes[i % 2];
        bd.position[0] = i % 23;
        bd.position[1] = (i / 23) % 23;
        bd.position[2] = i / 529;
        bd.scale = 0.4 + 0.01 * (i % 37);
        assert_int_equal(hgcd_body_create(w, &bd, &bodies[i]), HGCD_OK);
    }
    return w;
}

/* HGCD_SKIP_SLOW_TESTS (sanitizer and valgrind runs): the bodies spread
 * over a cube twice as wide, an eighth of the pairs to test. */
static void fill(rng *r, engine_body *e, int n) {
    const double side = getenv("HGCD_SKIP_SLOW_TESTS") ? 40 : 20;
    for (int i = 0; i < n; ++i) {
        e[i].tag = 0xABCDu + (uint64_t)i;
        for (int k = 0; k < 3; ++k) {
            e[i].position[k] = side * unif(r);
            e[i].velocity[k] = unif(r) - 0.5;
        }
        random_unit_quaternion(r, e[i].orientation);
        if (i % 5 == 0) memcpy(e[i].orientation, (double[4]){0, 0, 0, 1}, sizeof e[i].orientation);
    }
}

/* Same pairs, and the same candidate pairs: the same boxes (a box that
 * differs in a bit seldom changes the count, so test_grid checks the box
 * kernels bit for bit). */
static void expect_detected_alike(const hgcd_world *a, const hgcd_world *b) {
    const hgcd_pair *pa, *pb;
    size_t na, nb;
    assert_int_equal(hgcd_world_pairs(a, &pa, &na), HGCD_OK);
    assert_int_equal(hgcd_world_pairs(b, &pb, &nb), HGCD_OK);
    assert_int_equal(na, nb);
    assert_true(na > 0);
    for (size_t k = 0; k < na; ++k) {
        assert_int_equal(pa[k].a.index, pb[k].a.index);
        assert_int_equal(pa[k].b.index, pb[k].b.index);
    }
    hgcd_stats sa = {0}, sb = {0};
    sa.struct_size = sb.struct_size = sizeof sa;
    assert_int_equal(hgcd_world_stats(a, &sa), HGCD_OK);
    assert_int_equal(hgcd_world_stats(b, &sb), HGCD_OK);
    assert_int_equal(sa.candidate_pairs, sb.candidate_pairs);
}

static void expect_same_pairs(hgcd_world *a, hgcd_world *b) {
    assert_int_equal(hgcd_world_detect(a), HGCD_OK);
    assert_int_equal(hgcd_world_detect(b), HGCD_OK);
    expect_detected_alike(a, b);
}

/* Strided batch (ids listed, in a shuffled order; and all bodies by index)
 * == one call per body, at 1 and 2 threads, over several rounds (storage
 * renumbered between them), some bodies with a margin (their boxes taken
 * one at a time); then velocities and a step. */
static void test_batch_matches_single_calls(void **state) {
    (void)state;
    enum { N = 6000 }; /* above the batch's parallel threshold */
    static hgcd_body ids_a[N], ids_b[N], ids_c[N], order[N];
    static engine_body e[N];
    for (int threads = 1; threads <= 2; ++threads) {
        hgcd_world *a = make_world(threads, ids_a, N), *b = make_world(threads, ids_b, N);
        hgcd_world *c = make_world(threads, ids_c, N);
        for (int i = 0; i < N; i += 7) {
            assert_int_equal(hgcd_body_set_margin(a, ids_a[i], 0.01), HGCD_OK);
            assert_int_equal(hgcd_body_set_margin(b, ids_b[i], 0.01), HGCD_OK);
            assert_int_equal(hgcd_body_set_margin(c, ids_c[i], 0.01), HGCD_OK);
        }
        rng r = {7 + (uint64_t)threads};
        for (int round = 0; round < 4; ++round) {
            if (round < 3) {
                fill(&r, e, N);
            } else { /* most poses as they were: a third moved, a ninth turned */
                for (int i = 0; i < N; i += 3) e[i].position[0] += 0.5;
                for (int i = 0; i < N; i += 9) random_unit_quaternion(&r, e[i].orientation);
            }
            /* a: per body; b: one batch, ids in a shuffled order */
            for (int i = 0; i < N; ++i)
                assert_int_equal(hgcd_body_set_pose(a, ids_a[i], e[i].position, e[i].orientation), HGCD_OK);
            static engine_body shuffled[N];
            for (int i = 0; i < N; ++i) {
                order[i] = ids_b[i];
                shuffled[i] = e[i];
            }
            for (int i = N - 1; i > 0; --i) {
                int j = (int)(next(&r) % (uint64_t)(i + 1));
                hgcd_body t = order[i];
                engine_body u = shuffled[i];
                order[i] = order[j], shuffled[i] = shuffled[j];
                order[j] = t, shuffled[j] = u;
            }
            assert_int_equal(hgcd_world_set_poses(b, order, N, shuffled[0].position, sizeof(engine_body),
                                                  shuffled[0].orientation, sizeof(engine_body)),
                             HGCD_OK);
            expect_same_pairs(a, b);
            assert_int_equal(hgcd_world_set_poses(c, NULL, N, e[0].position, sizeof(engine_body),
                                                  e[0].orientation, sizeof(engine_body)),
                             HGCD_OK);
            assert_int_equal(hgcd_world_detect(c), HGCD_OK);
            expect_detected_alike(a, c);
        }
        /* Velocities, strided, for all bodies by index; then a step each. */
        for (int i = 0; i < N; ++i)
            assert_int_equal(hgcd_body_set_velocity(a, ids_a[i], e[i].velocity), HGCD_OK);
        assert_int_equal(hgcd_world_set_velocities(b, NULL, N, e[0].velocity, sizeof(engine_body)), HGCD_OK);
        assert_int_equal(hgcd_world_step(a), HGCD_OK);
        assert_int_equal(hgcd_world_step(b), HGCD_OK);
        expect_same_pairs(a, b);
        /* get_poses agrees with the per-body getter, packed and strided. */
        static double pos[3 * N], ori[4 * N];
        static engine_body out[N];
        assert_int_equal(hgcd_world_get_poses(b, NULL, N, pos, 0, ori, 0), HGCD_OK);
        assert_int_equal(hgcd_world_get_poses(b, ids_b, N, out[0].position, sizeof(engine_body),
                                              out[0].orientation, sizeof(engine_body)),
                         HGCD_OK);
        for (int i = 0; i < N; i += 97) {
            double p[3], q[4];
            assert_int_equal(hgcd_body_get_pose(a, ids_a[i], p, q), HGCD_OK);
            assert_memory_equal(p, pos + 3 * i, sizeof p);
            assert_memory_equal(q, ori + 4 * i, sizeof q);
            assert_memory_equal(p, out[i].position, sizeof p);
            assert_memory_equal(q, out[i].orientation, sizeof q);
        }
        hgcd_world_destroy(a);
        hgcd_world_destroy(b);
        hgcd_world_destroy(c);
    }
}

/* By index for the first `count` bodies only, once storage has been
 * renumbered (entries land at their bodies' storage indices, and the bodies
 * past count keep their poses) == one call per body, at 1 and 2 threads. */
static void test_prefix_by_index(void **state) {
    (void)state;
    enum { N = 6000 };
    static hgcd_body ids_a[N], ids_c[N];
    static engine_body e[N];
    for (int threads = 1; threads <= 2; ++threads) {
        hgcd_world *a = make_world(threads, ids_a, N), *c = make_world(threads, ids_c, N);
        rng r = {31 + (uint64_t)threads};
        /* (storage is renumbered by the second detect: from the third round) */
        const int rounds = getenv("HGCD_SKIP_SLOW_TESTS") ? 3 : 5;
        for (int round = 0; round < rounds; ++round) {
            const int count = round < 2 ? N : N - 1100 * (round - 1);
            fill(&r, e, N);
            for (int i = 0; i < count; ++i)
                assert_int_equal(hgcd_body_set_pose(a, ids_a[i], e[i].position, e[i].orientation), HGCD_OK);
            assert_int_equal(hgcd_world_set_poses(c, NULL, (size_t)count, e[0].position, sizeof(engine_body),
                                                  e[0].orientation, sizeof(engine_body)),
                             HGCD_OK);
            assert_int_equal(hgcd_world_detect(a), HGCD_OK);
            assert_int_equal(hgcd_world_detect(c), HGCD_OK);
            expect_detected_alike(a, c);
        }
        for (int i = 0; i < N; i += 61) {
            double p[3], q[4], pc[3], qc[4];
            assert_int_equal(hgcd_body_get_pose(a, ids_a[i], p, q), HGCD_OK);
            assert_int_equal(hgcd_body_get_pose(c, ids_c[i], pc, qc), HGCD_OK);
            assert_memory_equal(p, pc, sizeof p);
            assert_memory_equal(q, qc, sizeof q);
        }
        hgcd_world_destroy(a);
        hgcd_world_destroy(c);
    }
}

/* Positions only, orientations only: the other part is kept. */
static void test_partial_poses(void **state) {
    (void)state;
    enum { N = 40 };
    hgcd_body ids[N];
    hgcd_world *w = make_world(1, ids, N);
    double pos[3 * N], ori[4 * N], got_p[3 * N], got_q[4 * N];
    for (int i = 0; i < N; ++i) {
        for (int k = 0; k < 3; ++k) pos[3 * i + k] = i + 0.25 * k;
        const double h = sqrt(0.5);
        ori[4 * i] = 0, ori[4 * i + 1] = 0, ori[4 * i + 2] = h, ori[4 * i + 3] = h;
    }
    assert_int_equal(hgcd_world_get_poses(w, ids, N, NULL, 0, got_q, 0), HGCD_OK);
    assert_int_equal(hgcd_world_set_poses(w, ids, N, pos, 0, NULL, 0), HGCD_OK);
    assert_int_equal(hgcd_world_get_poses(w, ids, N, got_p, 0, ori, 0), HGCD_OK);
    assert_memory_equal(got_p, pos, sizeof pos);
    for (int i = 0; i < N; ++i) assert_true(ori[4 * i + 3] == 1.0); /* unchanged: identity */
    const double h = sqrt(0.5);
    for (int i = 0; i < N; ++i) ori[4 * i] = 0, ori[4 * i + 1] = 0, ori[4 * i + 2] = h, ori[4 * i + 3] = h;
    assert_int_equal(hgcd_world_set_poses(w, NULL, N, NULL, 0, ori, 0), HGCD_OK);
    assert_int_equal(hgcd_world_get_poses(w, NULL, N, got_p, 0, got_q, 0), HGCD_OK);
    assert_memory_equal(got_p, pos, sizeof pos);
    assert_memory_equal(got_q, ori, sizeof ori);
    assert_int_equal(hgcd_world_set_poses(w, ids, 0, pos, 0, ori, 0), HGCD_OK); /* nothing to do */
    hgcd_world_destroy(w);
}

/* Each refusal: its status, the entry named, and the world unchanged. */
static void test_batch_refusals(void **state) {
    (void)state;
    enum { N = 5000 };
    static hgcd_body ids[N];
    static engine_body e[N];
    hgcd_world *w = make_world(2, ids, N);
    rng r = {3};
    fill(&r, e, N);
    assert_int_equal(hgcd_world_detect(w), HGCD_OK);
    snapshot before, after;
    snap_take(&before, w, ids, N, NULL, 0);

#define REFUSED(call, status, text)                                             \
    do {                                                                        \
        assert_int_equal((call), (status));                                     \
        if ((text)[0]) assert_non_null(strstr(hgcd_world_last_error(w), (text))); \
        snap_take(&after, w, ids, N, NULL, 0);                                  \
        assert_null(snap_diff(&before, &after, 1));                                     \
        snap_free(&after);                                                      \
    } while (0)

    const size_t S = sizeof(engine_body);
    /* A bad value late in the array: no earlier entry is applied. */
    e[4321].position[2] = NAN;
    REFUSED(hgcd_world_set_poses(w, ids, N, e[0].position, S, e[0].orientation, S), HGCD_ERROR_INVALID_ARGUMENT,
            "entry 4321: position[2] is not finite");
    e[4321].position[2] = 1;
    e[17].orientation[0] += 0.01;
    e[4000].orientation[1] = INFINITY;
    REFUSED(hgcd_world_set_poses(w, ids, N, e[0].position, S, e[0].orientation, S), HGCD_ERROR_INVALID_ARGUMENT,
            "entry 17: orientation is not a unit quaternion");
    REFUSED(hgcd_world_set_poses(w, NULL, N, NULL, 0, e[0].orientation, S), HGCD_ERROR_INVALID_ARGUMENT,
            "entry 17:");
    fill(&r, e, N);
    e[999].position[0] = nextafter(1e15, INFINITY);
    REFUSED(hgcd_world_set_poses(w, ids, N, e[0].position, S, NULL, 0), HGCD_ERROR_INVALID_ARGUMENT,
            "entry 999: position[0] is beyond 1e15");
    fill(&r, e, N);
    /* Ids: stale, forged, named twice (in a copy: the snapshot reads ids). */
    static hgcd_body bad[N];
    memcpy(bad, ids, sizeof bad);
    bad[2500].generation ^= 1;
    REFUSED(hgcd_world_set_poses(w, bad, N, e[0].position, S, e[0].orientation, S), HGCD_ERROR_STALE_ID,
            "entry 2500");
    bad[2500] = ids[12];
    REFUSED(hgcd_world_set_poses(w, bad, N, e[0].position, S, e[0].orientation, S), HGCD_ERROR_INVALID_ARGUMENT,
            "entry 2500 names a body an earlier entry names");
    REFUSED(hgcd_world_set_velocities(w, bad, N, e[0].velocity, S), HGCD_ERROR_INVALID_ARGUMENT, "entry 2500");
    /* Indices beyond the bodies. */
    REFUSED(hgcd_world_set_poses(w, NULL, N + 1, e[0].position, S, NULL, 0), HGCD_ERROR_STALE_ID, "count");
    e[77].velocity[1] = NAN;
    REFUSED(hgcd_world_set_velocities(w, NULL, N, e[0].velocity, S), HGCD_ERROR_INVALID_ARGUMENT,
            "entry 77: velocity is not finite");
    /* Strides and NULLs. */
    REFUSED(hgcd_world_set_poses(w, ids, N, e[0].position, 12, NULL, 0), HGCD_ERROR_INVALID_ARGUMENT, "stride");
    REFUSED(hgcd_world_set_poses(w, ids, N, e[0].position, 20, NULL, 0), HGCD_ERROR_INVALID_ARGUMENT, "stride");
    REFUSED(hgcd_world_set_poses(w, ids, N, NULL, 0, e[0].orientation, 24), HGCD_ERROR_INVALID_ARGUMENT, "stride");
    REFUSED(hgcd_world_set_poses(w, ids, N, NULL, 0, NULL, 0), HGCD_ERROR_NULL_ARGUMENT, "NULL");
    REFUSED(hgcd_world_set_velocities(w, ids, N, NULL, 0), HGCD_ERROR_NULL_ARGUMENT, "NULL");
    assert_int_equal(hgcd_world_set_poses(NULL, ids, N, e[0].position, S, NULL, 0), HGCD_ERROR_NULL_ARGUMENT);
    /* A destroyed body, by id and by index. */
    assert_int_equal(hgcd_body_destroy(w, ids[N - 1]), HGCD_OK);
    snap_free(&before);
    snap_take(&before, w, ids, N, NULL, 0);
    REFUSED(hgcd_world_set_poses(w, ids, N, e[0].position, S, NULL, 0), HGCD_ERROR_STALE_ID, "entry 4999");
    REFUSED(hgcd_world_set_poses(w, NULL, N, e[0].position, S, NULL, 0), HGCD_ERROR_STALE_ID,
            "no live body has index 4999");
    /* A dead index is the error even after a bad value (by index, the two
     * are found in one pass). */
    e[10].position[1] = NAN;
    REFUSED(hgcd_world_set_poses(w, NULL, N, e[0].position, S, NULL, 0), HGCD_ERROR_STALE_ID,
            "no live body has index 4999");
    REFUSED(hgcd_world_set_poses(w, NULL, N - 1, e[0].position, S, NULL, 0), HGCD_ERROR_INVALID_ARGUMENT,
            "entry 10: position[1] is not finite");
    fill(&r, e, N);
    /* get_poses writes nothing on failure. */
    static double out[3 * N];
    for (size_t k = 0; k < 3 * N; ++k) out[k] = -7;
    assert_int_equal(hgcd_world_get_poses(w, ids, N, out, 0, NULL, 0), HGCD_ERROR_STALE_ID);
    for (size_t k = 0; k < 3 * N; ++k) assert_true(out[k] == -7);
    assert_int_equal(hgcd_world_get_poses(w, ids, N - 1, out, 8, NULL, 0), HGCD_ERROR_INVALID_ARGUMENT);
    assert_int_equal(hgcd_world_get_poses(w, ids, N - 1, NULL, 0, NULL, 0), HGCD_ERROR_NULL_ARGUMENT);
    snap_free(&before);
    hgcd_world_destroy(w);
#undef REFUSED
}

int main(void) {
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_batch_matches_single_calls),
        cmocka_unit_test(test_prefix_by_index),
        cmocka_unit_test(test_partial_poses),
        cmocka_unit_test(test_batch_refusals),
    };
    if (getenv("HGCD_TEST_FILTER")) cmocka_set_test_filter(getenv("HGCD_TEST_FILTER"));
    return cmocka_run_group_tests(tests, NULL, NULL);
}
