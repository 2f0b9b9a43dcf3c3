/* Body types, enabling, filters and excluded pairs against the oracle: a
 * world driven with random types, filters (categories, masks, groups),
 * disabled bodies and excluded pairs, changed between detects along with
 * poses, deaths and births, must report exactly the oracle's colliding pairs
 * that the test's own reading of the rules accepts, at 1, 2 and 3 threads;
 * the refused pairs must never reach the narrow phase. Also the step's
 * motion by type, and the refusals of the new calls. */
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
#include "test_rng.h"

enum { kCap = 360, kShapes = 3 };


static oracle_mesh shapes[kShapes] = {
    {tetra_v, tetra_t, 4, 4, 1}, {cube_v, cube_t, 8, 12, 1}, {triangle_v, triangle_t, 3, 1, 0}};

/* The test's mirror of the world: what the oracle and the rules are given. */
typedef struct {
    hgcd_world *w;
    hgcd_mesh mesh[kShapes];
    int kinematic_pairs;
    int shape[kCap]; /* -1: no live body */
    hgcd_body id[kCap];
    double pos[kCap][3], quat[kCap][4], scale[kCap];
    int type[kCap], enabled[kCap];
    hgcd_filter filter[kCap];
    unsigned char excluded[kCap][kCap];
} mirror;

/* The rules as hgcd.h states them, written out here again. */
static int accepted(const mirror *m, int i, int j) {
    const int ti = m->type[i], tj = m->type[j];
    if (!m->enabled[i] || !m->enabled[j] || m->excluded[i][j]) return 0;
    if (ti == HGCD_BODY_STATIC && tj == HGCD_BODY_STATIC) return 0;
    if (ti != HGCD_BODY_DYNAMIC && tj != HGCD_BODY_DYNAMIC && !m->kinematic_pairs) return 0;
    const hgcd_filter *a = &m->filter[i], *b = &m->filter[j];
    if (a->group_index != 0 && a->group_index == b->group_index) return a->group_index > 0;
    return (a->mask_bits & b->category_bits) != 0 && (a->category_bits & b->mask_bits) != 0;
}

static void mirror_init(mirror *m, uint32_t kinematic_pairs) {
    memset(m, 0, sizeof *m);
    hgcd_world_desc wd = hgcd_world_desc_default();
    wd.kinematic_pairs = kinematic_pairs;
    m->kinematic_pairs = kinematic_pairs != 0;
    assert_int_equal(hgcd_world_create(&wd, &m->w), HGCD_OK);
    for (int k = 0; k < kShapes; ++k) {
        hgcd_mesh_desc md = hgcd_mesh_desc_default();
        md.vertices = shapes[k].verts;
        md.triangles = shapes[k].tris;
        md.vertex_count = shapes[k].vertex_count;
        md.triangle_count = shapes[k].triangle_count;
        assert_int_equal(hgcd_mesh_create(m->w, &md, &m->mesh[k]), HGCD_OK);
    }
    for (int i = 0; i < kCap; ++i) m->shape[i] = -1;
}

/* A filter from a few categories and groups, so that every rule is hit. */
static hgcd_filter random_filter(rng *r) {
    hgcd_filter f = hgcd_filter_default();
    if (next(r) % 3) {
        f.category_bits = (uint64_t)1 << (next(r) % 4) | (next(r) % 8 == 0 ? (uint64_t)1 << 63 : 0);
        f.mask_bits = next(r) | (next(r) % 2 ? 0xF000000000000000ull : 0);
    }
    const int g = (int)(next(r) % 7);
    f.group_index = g < 3 ? 0 : g - 5; /* 0 (g < 3 or 5), -2, -1, or 2 below */
    if (g == 6) f.group_index = 2;
    return f;
}

static int random_type(rng *r) {
    const uint64_t k = next(r) % 8;
    return k < 4 ? HGCD_BODY_DYNAMIC : k < 6 ? HGCD_BODY_STATIC : HGCD_BODY_KINEMATIC;
}

static void random_pose(rng *r, double side, double p[3], double q[4]) {
    for (int k = 0; k < 3; ++k) p[k] = side * unif(r);
    random_unit_quaternion(r, q);
}

static void add(mirror *m, rng *r, double side) {
    hgcd_body_desc bd = hgcd_body_desc_default();
    const int shape = (int)(next(r) % kShapes);
    bd.mesh = m->mesh[shape];
    random_pose(r, side, bd.position, bd.orientation);
    bd.scale = 0.5 + unif(r);
    bd.type = random_type(r);
    bd.enabled = next(r) % 8 != 0;
    bd.filter = random_filter(r);
    hgcd_body b;
    assert_int_equal(hgcd_body_create(m->w, &bd, &b), HGCD_OK);
    assert_true(b.index < kCap);
    const int i = (int)b.index;
    m->shape[i] = shape;
    m->id[i] = b;
    memcpy(m->pos[i], bd.position, sizeof m->pos[i]);
    memcpy(m->quat[i], bd.orientation, sizeof m->quat[i]);
    m->scale[i] = bd.scale;
    m->type[i] = bd.type;
    m->enabled[i] = bd.enabled;
    m->filter[i] = bd.filter;
    for (int j = 0; j < kCap; ++j) m->excluded[i][j] = m->excluded[j][i] = 0;
}

static void destroy(mirror *m, int i) {
    assert_int_equal(hgcd_body_destroy(m->w, m->id[i]), HGCD_OK);
    m->shape[i] = -1;
    for (int j = 0; j < kCap; ++j) m->excluded[i][j] = m->excluded[j][i] = 0;
}

/* Detects on `threads` threads and checks every pair against the oracle's
 * pairs that the rules accept; returns the pairs the rules refused. */
static size_t check(mirror *m, uint32_t threads, size_t *pairs_out) {
    assert_int_equal(hgcd_world_set_thread_count(m->w, threads), HGCD_OK);
    assert_int_equal(hgcd_world_detect(m->w), HGCD_OK);
    static int slot_of[kCap];
    static const oracle_mesh *meshes[kCap];
    static double p[3 * kCap], q[4 * kCap], s[kCap];
    size_t live = 0;
    for (int i = 0; i < kCap; ++i) {
        if (m->shape[i] < 0) continue;
        slot_of[live] = i;
        meshes[live] = &shapes[m->shape[i]];
        memcpy(&p[3 * live], m->pos[i], 3 * sizeof(double));
        memcpy(&q[4 * live], m->quat[i], 4 * sizeof(double));
        s[live] = m->scale[i];
        ++live;
    }
    const size_t n = oracle_colliding_pairs(live, meshes, p, q, s, NULL, 0);
    uint32_t *all = malloc((2 * n + 2) * sizeof(uint32_t));
    assert_int_equal(oracle_colliding_pairs(live, meshes, p, q, s, all, n), n);
    const hgcd_pair *got;
    size_t count, k = 0, refused = 0;
    assert_int_equal(hgcd_world_pairs(m->w, &got, &count), HGCD_OK);
    for (size_t e = 0; e < n; ++e) {
        const int a = slot_of[all[2 * e]], b = slot_of[all[2 * e + 1]];
        if (!accepted(m, a, b)) {
            ++refused;
            continue;
        }
        assert_true(k < count);
        assert_int_equal(got[k].a.index, a);
        assert_int_equal(got[k].b.index, b);
        assert_int_equal(got[k].a.generation, m->id[a].generation);
        assert_int_equal(got[k].b.generation, m->id[b].generation);
        ++k;
    }
    assert_int_equal(k, count);
    free(all);
    *pairs_out = count;
    return refused;
}

static void random_changes(mirror *m, rng *r, double side) {
    for (int c = 0; c < 40; ++c) {
        const int i = (int)(next(r) % kCap);
        if (m->shape[i] < 0) {
            if (next(r) % 2) add(m, r, side);
            continue;
        }
        switch (next(r) % 8) {
        case 0:
            m->type[i] = random_type(r);
            assert_int_equal(hgcd_body_set_type(m->w, m->id[i], m->type[i]), HGCD_OK);
            break;
        case 1:
            m->enabled[i] = !m->enabled[i];
            assert_int_equal(hgcd_body_set_enabled(m->w, m->id[i], (uint32_t)m->enabled[i]), HGCD_OK);
            break;
        case 2:
            m->filter[i] = random_filter(r);
            assert_int_equal(hgcd_body_set_filter(m->w, m->id[i], &m->filter[i]), HGCD_OK);
            break;
        case 3: {
            const int j = (int)(next(r) % kCap);
            if (j == i || m->shape[j] < 0) break;
            const int ex = (int)(next(r) % 3 != 0);
            assert_int_equal(ex ? hgcd_world_exclude_pair(m->w, m->id[i], m->id[j])
                                : hgcd_world_include_pair(m->w, m->id[i], m->id[j]),
                             HGCD_OK);
            m->excluded[i][j] = m->excluded[j][i] = (unsigned char)ex;
            break;
        }
        case 4:
            destroy(m, i);
            break;
        default:
            random_pose(r, side, m->pos[i], m->quat[i]);
            assert_int_equal(hgcd_body_set_pose(m->w, m->id[i], m->pos[i], m->quat[i]), HGCD_OK);
        }
    }
}

/* Exclusions between close neighbours, so that some excluded pairs would collide. */
static void exclude_neighbours(mirror *m) {
    for (int i = 0; i + 1 < kCap; i += 3) {
        const int j = i + 1;
        if (m->shape[i] < 0 || m->shape[j] < 0) continue;
        m->pos[j][0] = m->pos[i][0] + 0.5;
        m->pos[j][1] = m->pos[i][1];
        m->pos[j][2] = m->pos[i][2];
        assert_int_equal(hgcd_body_set_pose(m->w, m->id[j], m->pos[j], NULL), HGCD_OK);
        assert_int_equal(hgcd_world_exclude_pair(m->w, m->id[i], m->id[j]), HGCD_OK);
        m->excluded[i][j] = m->excluded[j][i] = 1;
    }
}

static void test_rules_match_oracle(void **state) {
    (void)state;
    size_t refused = 0, reported = 0, filtered_stat = 0;
    const uint64_t seeds = getenv("HGCD_SKIP_SLOW_TESTS") ? 2 : 4;
    for (uint64_t seed = 1; seed <= seeds; ++seed) {
        static mirror m;
        mirror_init(&m, (uint32_t)(seed % 2));
        rng r = {seed * 977};
        const double side = 16;
        for (int i = 0; i < 300; ++i) add(&m, &r, side);
        exclude_neighbours(&m);
        for (int tick = 0; tick < 8; ++tick) {
            if (tick) random_changes(&m, &r, side);
            size_t pairs;
            refused += check(&m, 1 + (uint32_t)(tick % 3), &pairs);
            reported += pairs;
            hgcd_stats st;
            st.struct_size = sizeof st;
            assert_int_equal(hgcd_world_stats(m.w, &st), HGCD_OK);
            filtered_stat += st.filtered_pairs;
            /* A detect with nothing changed keeps the same pairs. */
            if (tick == 3) {
                size_t again;
                check(&m, 2, &again);
                assert_int_equal(again, pairs);
            }
        }
        hgcd_world_destroy(m.w);
    }
    /* Dense enough for every rule to matter. */
    assert_true(reported > 75 * seeds);
    assert_true(refused > 75 * seeds);
    assert_true(filtered_stat > 0); /* (a detect around moved bodies searches those alone) */
}

/* A filtered pair never reaches the narrow phase: with every pair refused
 * by the masks, no exact test runs though the boxes overlap. */
static void test_filtered_pairs_cost_no_test(void **state) {
    (void)state;
    static mirror m;
    mirror_init(&m, 0);
    rng r = {3};
    for (int i = 0; i < 200; ++i) add(&m, &r, 6);
    for (int i = 0; i < kCap; ++i) {
        if (m.shape[i] < 0) continue;
        m.enabled[i] = 1;
        m.type[i] = HGCD_BODY_DYNAMIC;
        m.filter[i] = hgcd_filter_default();
        m.filter[i].category_bits = (uint64_t)1 << (i % 2);
        m.filter[i].mask_bits = (uint64_t)1 << (i % 2); /* only bodies of its own parity */
        assert_int_equal(hgcd_body_set_enabled(m.w, m.id[i], 1), HGCD_OK);
        assert_int_equal(hgcd_body_set_type(m.w, m.id[i], HGCD_BODY_DYNAMIC), HGCD_OK);
        assert_int_equal(hgcd_body_set_filter(m.w, m.id[i], &m.filter[i]), HGCD_OK);
    }
    size_t pairs;
    check(&m, 2, &pairs);
    hgcd_stats st;
    st.struct_size = sizeof st;
    assert_int_equal(hgcd_world_stats(m.w, &st), HGCD_OK);
    assert_true(st.filtered_pairs > 100);
    assert_true(st.narrow_tests <= st.candidate_pairs - st.filtered_pairs);
    /* Now every pair refused: groups of -1 for all. */
    for (int i = 0; i < kCap; ++i) {
        if (m.shape[i] < 0) continue;
        m.filter[i].group_index = -1;
        assert_int_equal(hgcd_body_set_filter(m.w, m.id[i], &m.filter[i]), HGCD_OK);
    }
    check(&m, 2, &pairs);
    assert_int_equal(pairs, 0);
    assert_int_equal(hgcd_world_stats(m.w, &st), HGCD_OK);
    assert_true(st.candidate_pairs > 100);
    assert_int_equal(st.filtered_pairs, st.candidate_pairs);
    assert_int_equal(st.narrow_tests, 0);
    hgcd_world_destroy(m.w);
}

/* hgcd_world_step moves dynamic and kinematic bodies, not static or
 * disabled ones; a static body's velocity is kept and never checked. */
static void test_step_by_type(void **state) {
    (void)state;
    hgcd_world *w;
    hgcd_world_desc wd = hgcd_world_desc_default();
    assert_int_equal(hgcd_world_create(&wd, &w), HGCD_OK);
    hgcd_mesh_desc md = hgcd_mesh_desc_default();
    md.vertices = tetra_v, md.vertex_count = 4, md.triangles = tetra_t, md.triangle_count = 4;
    hgcd_mesh mesh;
    assert_int_equal(hgcd_mesh_create(w, &md, &mesh), HGCD_OK);
    hgcd_body b[4];
    const int types[4] = {HGCD_BODY_DYNAMIC, HGCD_BODY_KINEMATIC, HGCD_BODY_STATIC, HGCD_BODY_DYNAMIC};
    for (int i = 0; i < 4; ++i) {
        hgcd_body_desc bd = hgcd_body_desc_default();
        bd.mesh = mesh;
        bd.position[0] = 10.0 * i;
        bd.velocity[1] = i == 2 ? 1e300 : 1; /* the static one would leave the range */
        bd.type = types[i];
        bd.enabled = i != 3;
        assert_int_equal(hgcd_body_create(w, &bd, &b[i]), HGCD_OK);
    }
    assert_int_equal(hgcd_world_step(w), HGCD_OK);
    const double expect_y[4] = {1, 1, 0, 0};
    for (int i = 0; i < 4; ++i) {
        double p[3], v[3];
        assert_int_equal(hgcd_body_get_pose(w, b[i], p, NULL), HGCD_OK);
        assert_true(p[1] == expect_y[i]);
        assert_int_equal(hgcd_body_get_velocity(w, b[i], v), HGCD_OK);
        assert_true(v[1] == (i == 2 ? 1e300 : 1));
    }
    /* Made dynamic, the static body's move is refused, and nothing moves. */
    assert_int_equal(hgcd_body_set_type(w, b[2], HGCD_BODY_DYNAMIC), HGCD_OK);
    assert_int_equal(hgcd_world_step(w), HGCD_ERROR_INVALID_ARGUMENT);
    double p[3];
    assert_int_equal(hgcd_body_get_pose(w, b[0], p, NULL), HGCD_OK);
    assert_true(p[1] == 1);
    hgcd_world_destroy(w);
}

static void test_refusals(void **state) {
    (void)state;
    hgcd_world *w;
    hgcd_world_desc wd = hgcd_world_desc_default();
    assert_int_equal(hgcd_world_create(&wd, &w), HGCD_OK);
    hgcd_mesh_desc md = hgcd_mesh_desc_default();
    md.vertices = tetra_v, md.vertex_count = 4, md.triangles = tetra_t, md.triangle_count = 4;
    hgcd_mesh mesh;
    assert_int_equal(hgcd_mesh_create(w, &md, &mesh), HGCD_OK);
    hgcd_body_desc bd = hgcd_body_desc_default();
    bd.mesh = mesh;
    hgcd_body a, b, c;
    assert_int_equal(hgcd_body_create(w, &bd, &a), HGCD_OK);
    assert_int_equal(hgcd_body_create(w, &bd, &b), HGCD_OK);
    bd.type = 3;
    assert_int_equal(hgcd_body_create(w, &bd, &c), HGCD_ERROR_INVALID_ARGUMENT);
    assert_non_null(strstr(hgcd_world_last_error(w), "type 3"));
    bd.type = HGCD_BODY_STATIC;
    bd.filter.reserved = 1;
    assert_int_equal(hgcd_body_create(w, &bd, &c), HGCD_ERROR_INVALID_ARGUMENT);
    assert_int_equal(hgcd_world_body_count(w), 2);
    assert_int_equal(hgcd_body_set_type(w, a, -1), HGCD_ERROR_INVALID_ARGUMENT);
    hgcd_filter f = hgcd_filter_default();
    assert_true(f.category_bits == 1 && f.mask_bits == UINT64_MAX && f.group_index == 0 && f.reserved == 0);
    f.reserved = 7;
    assert_int_equal(hgcd_body_set_filter(w, a, &f), HGCD_ERROR_INVALID_ARGUMENT);
    assert_int_equal(hgcd_body_set_filter(w, a, NULL), HGCD_ERROR_NULL_ARGUMENT);
    assert_int_equal(hgcd_world_exclude_pair(w, a, a), HGCD_ERROR_INVALID_ARGUMENT);
    const hgcd_body null_id = {0, 0};
    assert_int_equal(hgcd_world_exclude_pair(w, a, null_id), HGCD_ERROR_STALE_ID);
    int32_t type;
    uint32_t on, ex;
    hgcd_filter got;
    assert_int_equal(hgcd_body_get_type(w, a, &type), HGCD_OK);
    assert_int_equal(type, HGCD_BODY_DYNAMIC);
    assert_int_equal(hgcd_body_get_enabled(w, a, &on), HGCD_OK);
    assert_int_equal(on, 1);
    assert_int_equal(hgcd_body_get_filter(w, a, &got), HGCD_OK);
    assert_true(got.category_bits == 1 && got.mask_bits == UINT64_MAX && got.group_index == 0);
    /* The two bodies overlap: excluded, then destroyed with the exclusion. */
    assert_int_equal(hgcd_world_detect(w), HGCD_OK);
    size_t count;
    const hgcd_pair *pairs;
    assert_int_equal(hgcd_world_pairs(w, &pairs, &count), HGCD_OK);
    assert_int_equal(count, 1);
    assert_int_equal(hgcd_world_exclude_pair(w, b, a), HGCD_OK);
    assert_int_equal(hgcd_world_exclude_pair(w, a, b), HGCD_OK);
    assert_int_equal(hgcd_world_pair_excluded(w, a, b, &ex), HGCD_OK);
    assert_int_equal(ex, 1);
    assert_int_equal(hgcd_world_detect(w), HGCD_OK);
    assert_int_equal(hgcd_world_pairs(w, &pairs, &count), HGCD_OK);
    assert_int_equal(count, 0);
    assert_int_equal(hgcd_body_destroy(w, b), HGCD_OK);
    bd.type = HGCD_BODY_DYNAMIC;
    bd.filter.reserved = 0;
    assert_int_equal(hgcd_body_create(w, &bd, &c), HGCD_OK); /* b's slot, no exclusion */
    assert_int_equal(c.index, b.index);
    assert_int_equal(hgcd_world_pair_excluded(w, a, c, &ex), HGCD_OK);
    assert_int_equal(ex, 0);
    assert_int_equal(hgcd_world_detect(w), HGCD_OK);
    assert_int_equal(hgcd_world_pairs(w, &pairs, &count), HGCD_OK);
    assert_int_equal(count, 1);
    hgcd_world_destroy(w);
}

int main(void) {
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_rules_match_oracle),
        cmocka_unit_test(test_filtered_pairs_cost_no_test),
        cmocka_unit_test(test_step_by_type),
        cmocka_unit_test(test_refusals),
    };
    if (getenv("HGCD_TEST_FILTER")) cmocka_set_test_filter(getenv("HGCD_TEST_FILTER"));
    return cmocka_run_group_tests(tests, NULL, NULL);
}
