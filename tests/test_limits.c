/* The coordinate limits of hgcd.h ("Coordinate limits"), each on both sides
 * of its boundary: vertex norms, positions, scales (scale * reach), step
 * destinations, reflection bounds; and that a refused call changes nothing. */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#include <hgcd/hgcd.h>

static const double kLimit = 1e15;
static const uint32_t kTriangle[3] = {0, 1, 2};

static hgcd_world *new_world(void) {
    hgcd_world *w = NULL;
    hgcd_world_desc d = hgcd_world_desc_default();
    d.thread_count = 1;
    assert_int_equal(hgcd_world_create(&d, &w), HGCD_OK);
    return w;
}

/* hgcd_mesh_create on one triangle; the mesh count must change only when it
 * is accepted. */
static hgcd_status triangle_mesh(hgcd_world *w, const double v[9], hgcd_mesh *out) {
    const uint32_t before = hgcd_world_mesh_count(w);
    hgcd_mesh_desc md = hgcd_mesh_desc_default();
    md.vertices = v;
    md.vertex_count = 3;
    md.triangles = kTriangle;
    md.triangle_count = 1;
    const hgcd_status s = hgcd_mesh_create(w, &md, out);
    assert_int_equal(hgcd_world_mesh_count(w), before + (s == HGCD_OK));
    return s;
}

static hgcd_status body_at(hgcd_world *w, hgcd_mesh m, const double p[3], double scale, hgcd_body *out) {
    const uint32_t before = hgcd_world_body_count(w);
    hgcd_body_desc bd = hgcd_body_desc_default();
    bd.mesh = m;
    memcpy(bd.position, p, sizeof bd.position);
    bd.scale = scale;
    const hgcd_status s = hgcd_body_create(w, &bd, out);
    assert_int_equal(hgcd_world_body_count(w), before + (s == HGCD_OK));
    return s;
}

/* A vertex is measured by its norm sqrt((x*x + y*y) + z*z), not per
 * component. */
static void test_vertex_norm(void **state) {
    (void)state;
    hgcd_world *w = new_world();
    hgcd_mesh m;
    const double above = nextafter(kLimit, INFINITY);
    const double on_axis[9] = {kLimit, 0, 0, 0, kLimit, 0, 0, 0, -kLimit};
    assert_int_equal(triangle_mesh(w, on_axis, &m), HGCD_OK);
    const double past_axis[9] = {above, 0, 0, 0, 1, 0, 0, 0, 1};
    assert_int_equal(triangle_mesh(w, past_axis, &m), HGCD_ERROR_INVALID_MESH);
    assert_non_null(strstr(hgcd_world_last_error(w), "vertex 0 is beyond 1e15"));
    /* Every component within 1e15, the norm about 1.56e15: refused. */
    const double diagonal[9] = {9e14, 9e14, 9e14, 0, 0, 0, 1, 0, 0};
    assert_int_equal(triangle_mesh(w, diagonal, &m), HGCD_ERROR_INVALID_MESH);
    /* 5.7e14 (1, 1, 1): norm about 9.87e14, accepted. */
    const double inside[9] = {1, 0, 0, 5.7e14, 5.7e14, 5.7e14, 0, 0, 0};
    assert_int_equal(triangle_mesh(w, inside, &m), HGCD_OK);
    /* Components whose squares overflow: refused, as is a NaN. */
    const double huge[9] = {0, 0, 0, 1e200, 0, 0, 0, 1, 0};
    assert_int_equal(triangle_mesh(w, huge, &m), HGCD_ERROR_INVALID_MESH);
    const double nan_vertex[9] = {0, 0, 0, 0, NAN, 0, 0, 1, 0};
    assert_int_equal(triangle_mesh(w, nan_vertex, &m), HGCD_ERROR_INVALID_MESH);
    assert_non_null(strstr(hgcd_world_last_error(w), "vertex 1 coordinate 1 is not finite"));
    hgcd_world_destroy(w);
}

/* scale * reach <= 1e15, reach the largest vertex norm (a triangle at the
 * origin of reach 1 takes scales up to 1e15 exactly). */
static void test_scale_reach(void **state) {
    (void)state;
    hgcd_world *w = new_world();
    hgcd_mesh m;
    hgcd_body b;
    const double unit[9] = {1, 0, 0, 0, 1, 0, 0, 0, 0};
    assert_int_equal(triangle_mesh(w, unit, &m), HGCD_OK);
    hgcd_mesh_info info;
    info.struct_size = sizeof info;
    assert_int_equal(hgcd_mesh_get_info(w, m, &info), HGCD_OK);
    assert_true(info.reach == 1.0);
    const double origin[3] = {0, 0, 0};
    assert_int_equal(body_at(w, m, origin, 0.9e15, &b), HGCD_OK);
    assert_int_equal(body_at(w, m, origin, kLimit, &b), HGCD_OK);
    assert_int_equal(body_at(w, m, origin, nextafter(kLimit, INFINITY), &b), HGCD_ERROR_INVALID_ARGUMENT);
    assert_non_null(strstr(hgcd_world_last_error(w), "scale"));
    assert_int_equal(body_at(w, m, origin, 0.0, &b), HGCD_ERROR_INVALID_ARGUMENT);
    assert_int_equal(body_at(w, m, origin, INFINITY, &b), HGCD_ERROR_INVALID_ARGUMENT);

    /* reach counts only the vertices the triangles use: an unused vertex far
     * out changes nothing. */
    const double with_unused[12] = {2, 0, 0, 0, 2, 0, 0, 0, 0, 9e14, 0, 0};
    hgcd_mesh_desc md = hgcd_mesh_desc_default();
    md.vertices = with_unused;
    md.vertex_count = 4;
    md.triangles = kTriangle;
    md.triangle_count = 1;
    assert_int_equal(hgcd_mesh_create(w, &md, &m), HGCD_OK);
    assert_int_equal(hgcd_mesh_get_info(w, m, &info), HGCD_OK);
    assert_true(info.reach == 2.0);
    assert_int_equal(body_at(w, m, origin, kLimit / 2, &b), HGCD_OK);
    assert_int_equal(body_at(w, m, origin, nextafter(kLimit / 2, INFINITY), &b), HGCD_ERROR_INVALID_ARGUMENT);
    hgcd_world_destroy(w);
}

/* Positions per component within 1e15, at creation, by set_pose and by a
 * step's destination. */
static void test_positions_and_steps(void **state) {
    (void)state;
    hgcd_world *w = new_world();
    hgcd_mesh m;
    hgcd_body b, c;
    const double small[9] = {1, 0, 0, 0, 1, 0, 0, 0, 1};
    assert_int_equal(triangle_mesh(w, small, &m), HGCD_OK);
    const double corner[3] = {kLimit, -kLimit, kLimit};
    assert_int_equal(body_at(w, m, corner, 1.0, &b), HGCD_OK);
    const double past[3] = {0, nextafter(-kLimit, -INFINITY), 0};
    assert_int_equal(body_at(w, m, past, 1.0, &c), HGCD_ERROR_INVALID_ARGUMENT);
    assert_non_null(strstr(hgcd_world_last_error(w), "position[1] is beyond 1e15"));
    assert_int_equal(hgcd_body_set_pose(w, b, past, NULL), HGCD_ERROR_INVALID_ARGUMENT);
    double got[3], q[4];
    assert_int_equal(hgcd_body_get_pose(w, b, got, q), HGCD_OK);
    assert_memory_equal(got, corner, sizeof got);

    /* A step to exactly 1e15 moves; one an ulp past moves nothing. */
    const double start[3] = {kLimit - 4, 0, 0};
    assert_int_equal(hgcd_body_set_pose(w, b, start, NULL), HGCD_OK);
    const double to_limit[3] = {4, 0, 0};
    assert_int_equal(hgcd_body_set_velocity(w, b, to_limit), HGCD_OK);
    assert_int_equal(hgcd_world_step(w), HGCD_OK);
    assert_int_equal(hgcd_body_get_pose(w, b, got, q), HGCD_OK);
    assert_true(got[0] == kLimit);
    const double past_limit[3] = {0.125, 0, 0}; /* the spacing of doubles at 1e15 */
    assert_int_equal(hgcd_body_set_velocity(w, b, past_limit), HGCD_OK);
    assert_int_equal(hgcd_world_step(w), HGCD_ERROR_INVALID_ARGUMENT);
    assert_int_equal(hgcd_body_get_pose(w, b, got, q), HGCD_OK);
    assert_true(got[0] == kLimit);
    hgcd_world_destroy(w);
}

/* Reflection bounds are read, and so checked, only when the world
 * reflects. */
static void test_reflection_bounds(void **state) {
    (void)state;
    hgcd_world *w = NULL;
    hgcd_world_desc d = hgcd_world_desc_default();
    for (int k = 0; k < 3; ++k) {
        d.bounds_min[k] = -1e300;
        d.bounds_max[k] = NAN;
    }
    assert_int_equal(hgcd_world_create(&d, &w), HGCD_OK); /* not reflecting: ignored */
    hgcd_world_destroy(w);
    w = NULL;

    d.reflect_at_bounds = 1;
    assert_int_equal(hgcd_world_create(&d, &w), HGCD_ERROR_INVALID_ARGUMENT);
    assert_null(w);
    for (int k = 0; k < 3; ++k) {
        d.bounds_min[k] = -kLimit;
        d.bounds_max[k] = kLimit;
    }
    assert_int_equal(hgcd_world_create(&d, &w), HGCD_OK);
    hgcd_world_destroy(w);
    w = NULL;
    d.bounds_max[2] = nextafter(kLimit, INFINITY);
    assert_int_equal(hgcd_world_create(&d, &w), HGCD_ERROR_INVALID_ARGUMENT);
    d.bounds_max[2] = -kLimit; /* min == max: an empty box */
    assert_int_equal(hgcd_world_create(&d, &w), HGCD_ERROR_INVALID_ARGUMENT);
    d.bounds_max[2] = 1e300;
    assert_int_equal(hgcd_world_create(&d, &w), HGCD_ERROR_INVALID_ARGUMENT);
    assert_null(w);
}

/* Bodies at the limits still collide exactly. The mesh spans (1e15, 0, 0),
 * (0, 1, 0), (0, 0, 1); body b sits at the origin, body a at (-1e15, y, 0),
 * so a's world vertices are (0, y, 0), (-1e15, y + 1, 0), (-1e15, y, 1).
 * Only a's first vertex has x = 0, the only x b's triangle shares with a's:
 * with y = 0 it misses b's edge from (0, 1, 0) to (0, 0, 1); with y = 1 it
 * is b's vertex (0, 1, 0), and the bodies touch. */
static void test_extreme_bodies_detect(void **state) {
    (void)state;
    hgcd_world *w = new_world();
    hgcd_mesh m;
    hgcd_body a, b;
    const double spike[9] = {kLimit, 0, 0, 0, 1, 0, 0, 0, 1};
    assert_int_equal(triangle_mesh(w, spike, &m), HGCD_OK);
    const double pa[3] = {-kLimit, 0, 0}, pb[3] = {0, 0, 0};
    assert_int_equal(body_at(w, m, pa, 1.0, &a), HGCD_OK);
    assert_int_equal(body_at(w, m, pb, 1.0, &b), HGCD_OK);
    assert_int_equal(hgcd_world_detect(w), HGCD_OK);
    size_t count = 99;
    const hgcd_pair *pairs;
    assert_int_equal(hgcd_world_pairs(w, &pairs, &count), HGCD_OK);
    assert_int_equal(count, 0);
    const double touching[3] = {-kLimit, 1, 0};
    assert_int_equal(hgcd_body_set_pose(w, a, touching, NULL), HGCD_OK);
    assert_int_equal(hgcd_world_detect(w), HGCD_OK);
    assert_int_equal(hgcd_world_pairs(w, &pairs, &count), HGCD_OK);
    assert_int_equal(count, 1);
    hgcd_world_destroy(w);
}

int main(void) {
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_vertex_norm),
        cmocka_unit_test(test_scale_reach),
        cmocka_unit_test(test_positions_and_steps),
        cmocka_unit_test(test_reflection_bounds),
        cmocka_unit_test(test_extreme_bodies_detect),
    };
    if (getenv("HGCD_TEST_FILTER")) cmocka_set_test_filter(getenv("HGCD_TEST_FILTER"));
    return cmocka_run_group_tests(tests, NULL, NULL);
}
