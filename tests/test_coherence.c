/* Temporal coherence: a pair of bodies whose poses did not change since the
 * last detect keeps that detect's answer untested. World A is driven as an
 * engine drives it (some bodies moved, bodies created and destroyed, poses
 * set again to the same bits); world B gets the same calls but re-tests every
 * pair (a narrow-phase call before each detect turns coherence off). Their
 * pairs must agree every tick; A's statistics must show pairs kept. */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#include <hgcd/hgcd.h>

#include "test_rng.h"

enum { kBodies = 1500 };

/* A closed octahedron with jittered vertices (non-convex in general) and a
 * large closed box that holds other bodies (containment). */
static const uint32_t kOctaTris[24] = {0, 2, 4, 2, 1, 4, 1, 3, 4, 3, 0, 4, 2, 0, 5, 1, 2, 5, 3, 1, 5, 0, 3, 5};
static const double kBoxVerts[24] = {-1, -1, -1, 1, -1, -1, -1, 1, -1, 1, 1, -1,
                                     -1, -1, 1,  1, -1, 1,  -1, 1, 1,  1, 1, 1};
static const uint32_t kBoxTris[36] = {0, 2, 1, 1, 2, 3, 4, 5, 6, 5, 7, 6, 0, 1, 4, 1, 5, 4,
                                      2, 6, 3, 3, 6, 7, 0, 4, 2, 2, 4, 6, 1, 3, 5, 3, 7, 5};

typedef struct {
    hgcd_world *w;
    hgcd_mesh octa[4], box;
    hgcd_body body[kBodies];
    int live[kBodies];
} world;

static void world_init(world *x, uint64_t seed) {
    memset(x, 0, sizeof *x);
    hgcd_world_desc d = hgcd_world_desc_default();
    d.thread_count = 2;
    assert_int_equal(hgcd_world_create(&d, &x->w), HGCD_OK);
    rng r = {seed};
    for (int m = 0; m < 4; ++m) {
        double v[18];
        for (int i = 0; i < 6; ++i) {
            v[3 * i] = v[3 * i + 1] = v[3 * i + 2] = 0;
            v[3 * i + i / 2] = (i & 1 ? -1 : 1) * (0.4 + unif(&r));
        }
        hgcd_mesh_desc md = hgcd_mesh_desc_default();
        md.vertices = v, md.vertex_count = 6, md.triangles = kOctaTris, md.triangle_count = 8;
        assert_int_equal(hgcd_mesh_create(x->w, &md, &x->octa[m]), HGCD_OK);
    }
    hgcd_mesh_desc md = hgcd_mesh_desc_default();
    md.vertices = kBoxVerts, md.vertex_count = 8, md.triangles = kBoxTris, md.triangle_count = 12;
    assert_int_equal(hgcd_mesh_create(x->w, &md, &x->box), HGCD_OK);
}

static void random_pose(rng *r, double side, double p[3], double q[4]) {
    for (int k = 0; k < 3; ++k) p[k] = side * unif(r);
    random_unit_quaternion(r, q);
}

static void create(world *x, int i, const double p[3], const double q[4]) {
    hgcd_body_desc bd = hgcd_body_desc_default();
    bd.mesh = i % 50 == 0 ? x->box : x->octa[i % 4];
    bd.scale = i % 50 == 0 ? 4.0 : 1.0;
    memcpy(bd.position, p, sizeof bd.position);
    memcpy(bd.orientation, q, sizeof bd.orientation);
    assert_int_equal(hgcd_body_create(x->w, &bd, &x->body[i]), HGCD_OK);
    x->live[i] = 1;
}

static size_t same_pairs(world *a, world *b) {
    const hgcd_pair *pa, *pb;
    size_t na, nb;
    assert_int_equal(hgcd_world_pairs(a->w, &pa, &na), HGCD_OK);
    assert_int_equal(hgcd_world_pairs(b->w, &pb, &nb), HGCD_OK);
    assert_int_equal(na, nb);
    for (size_t k = 0; k < na; ++k) {
        assert_int_equal(pa[k].a.index, pb[k].a.index);
        assert_int_equal(pa[k].b.index, pb[k].b.index);
        assert_int_equal(pa[k].a.generation & 0xFFFFFF, pb[k].a.generation & 0xFFFFFF);
    }
    return na;
}

static hgcd_stats stats_of(world *x) {
    hgcd_stats s;
    s.struct_size = sizeof s;
    assert_int_equal(hgcd_world_stats(x->w, &s), HGCD_OK);
    return s;
}

static void test_coherence_matches_full_tests(void **state) {
    (void)state;
    static world A, B;
    world_init(&A, 11);
    world_init(&B, 11);
    const double side = 24; /* dense: many touching pairs and containments */
    rng r = {5};
    static double pos[kBodies][3], ori[kBodies][4];
    for (int i = 0; i < kBodies; ++i) {
        random_pose(&r, side, pos[i], ori[i]);
        create(&A, i, pos[i], ori[i]);
        create(&B, i, pos[i], ori[i]);
    }
    uint64_t kept = 0, contained = 0, incremental = 0;
    size_t pairs = 0;
    for (int tick = 0; tick < 24; ++tick) {
        /* The share of bodies moved: none, one in ten, all, in turn. */
        const int every = tick % 3 == 0 ? 0 : tick % 3 == 1 ? 10 : 1;
        for (int i = 0; i < kBodies; ++i) {
            if (!A.live[i]) continue;
            if (every && i % every == (tick % every)) {
                random_pose(&r, side, pos[i], ori[i]);
                /* a small step instead, now and then: pairs that stay close */
                if (i % 3 == 0) pos[i][0] = fmod(pos[i][0] + 0.01, side);
            }
        }
        /* Poses pushed for every body, moved or not (the same bits for the
         * unmoved: that must count as unmoved), half by batch, half singly. */
        static hgcd_body ids_a[kBodies], ids_b[kBodies];
        static double bp[kBodies][3], bq[kBodies][4];
        size_t n = 0;
        for (int i = 0; i < kBodies; ++i) {
            if (!A.live[i]) continue;
            if (i % 2) {
                assert_int_equal(hgcd_body_set_pose(A.w, A.body[i], pos[i], ori[i]), HGCD_OK);
                assert_int_equal(hgcd_body_set_pose(B.w, B.body[i], pos[i], ori[i]), HGCD_OK);
            } else {
                ids_a[n] = A.body[i], ids_b[n] = B.body[i];
                memcpy(bp[n], pos[i], sizeof bp[n]);
                memcpy(bq[n], ori[i], sizeof bq[n]);
                ++n;
            }
        }
        assert_int_equal(hgcd_world_set_poses(A.w, ids_a, n, bp[0], 0, bq[0], 0), HGCD_OK);
        assert_int_equal(hgcd_world_set_poses(B.w, ids_b, n, bp[0], 0, bq[0], 0), HGCD_OK);
        /* Some bodies die and are born again in other places (new ids, same
         * indices: a reused index must not inherit the old body's pairs). */
        if (tick % 4 == 3)
            for (int i = tick; i < kBodies; i += 97) {
                if (A.live[i]) {
                    assert_int_equal(hgcd_body_destroy(A.w, A.body[i]), HGCD_OK);
                    assert_int_equal(hgcd_body_destroy(B.w, B.body[i]), HGCD_OK);
                }
                random_pose(&r, side, pos[i], ori[i]);
                create(&A, i, pos[i], ori[i]);
                create(&B, i, pos[i], ori[i]);
            }
        /* Now and then bodies only die: nothing moved, the last pairs less
         * theirs (and the next search's grid catches up). */
        if (every == 0 && tick % 4 == 0)
            for (int i = tick; i < kBodies; i += 211)
                if (A.live[i]) {
                    assert_int_equal(hgcd_body_destroy(A.w, A.body[i]), HGCD_OK);
                    assert_int_equal(hgcd_body_destroy(B.w, B.body[i]), HGCD_OK);
                    A.live[i] = 0;
                }
        /* B re-tests everything: a narrow-phase call ends coherence. */
        assert_int_equal(hgcd_world_set_narrow_phase(B.w, HGCD_NARROW_EXACT), HGCD_OK);
        if (tick == 13) /* and so must it in A, once */
            assert_int_equal(hgcd_world_set_narrow_phase(A.w, HGCD_NARROW_EXACT), HGCD_OK);
        assert_int_equal(hgcd_world_detect(A.w), HGCD_OK);
        assert_int_equal(hgcd_world_detect(B.w), HGCD_OK);
        pairs += same_pairs(&A, &B);
        const hgcd_stats sa = stats_of(&A), sb = stats_of(&B);
        assert_int_equal(sb.unmoved_pairs, 0);
        if (tick == 0 || tick == 13) assert_int_equal(sa.unmoved_pairs, 0);
        if (tick > 0 && tick != 13 && every == 0 && tick % 4 != 3) {
            /* nothing moved or was born: the last pairs, without a search */
            assert_int_equal(sa.candidate_pairs, 0);
            assert_int_equal(sa.narrow_tests, 0);
            assert_int_equal(sa.unmoved_pairs, sa.colliding_pairs);
        } else if (sa.searched_bodies == sb.searched_bodies) {
            assert_int_equal(sa.candidate_pairs, sb.candidate_pairs);
        } else {
            /* one in ten moved, or a few were born: the search ran around
             * them alone (test_incremental.c checks that path at length) */
            assert_true(every != 1);
            assert_true(sa.searched_bodies < sb.searched_bodies / 5);
            ++incremental;
        }
        if (every == 1 && tick % 4 != 3) assert_int_equal(sa.unmoved_pairs, 0);
        kept += sa.unmoved_pairs;
        contained += sb.containment_pairs;
    }
    assert_true(kept > 1000);
    assert_true(incremental >= 6);
    assert_true(contained > 0);
    assert_true(pairs > 1000);
    hgcd_world_destroy(A.w);
    hgcd_world_destroy(B.w);
}

/* A step moves bodies without set_pose: it must not reuse the last pairs,
 * nor may the detect after it treat its moves as unmoved. */
static void test_step_then_detect(void **state) {
    (void)state;
    static world A;
    world_init(&A, 3);
    static const double q[4] = {0, 0, 0, 1};
    const double p0[3] = {0, 0, 0}, p1[3] = {0.5, 0, 0}; /* overlapping on the x axis */
    create(&A, 1, p0, q);
    create(&A, 2, p1, q);
    const hgcd_pair *pairs;
    size_t count;
    assert_int_equal(hgcd_world_detect(A.w), HGCD_OK);
    assert_int_equal(hgcd_world_pairs(A.w, &pairs, &count), HGCD_OK);
    const size_t before = count;
    const double away[3] = {100, 0, 0}, still[3] = {0, 0, 0};
    assert_int_equal(hgcd_body_set_velocity(A.w, A.body[2], away), HGCD_OK);
    assert_int_equal(hgcd_world_step(A.w), HGCD_OK);
    assert_int_equal(hgcd_world_pairs(A.w, &pairs, &count), HGCD_OK);
    assert_int_equal(count, 0);
    assert_int_equal(hgcd_body_set_velocity(A.w, A.body[2], still), HGCD_OK);
    assert_int_equal(hgcd_world_detect(A.w), HGCD_OK); /* nothing moved since the step */
    assert_int_equal(hgcd_world_pairs(A.w, &pairs, &count), HGCD_OK);
    assert_int_equal(count, 0);
    assert_true(before == 1);
    hgcd_world_destroy(A.w);
}

int main(void) {
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_coherence_matches_full_tests),
        cmocka_unit_test(test_step_then_detect),
    };
    if (getenv("HGCD_TEST_FILTER")) cmocka_set_test_filter(getenv("HGCD_TEST_FILTER"));
    return cmocka_run_group_tests(tests, NULL, NULL);
}
