/* The C API contract: lifecycle, ids, every error path named in hgcd.h, and
 * that a refused call leaves the world as it was. */
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

static const double kTetraVerts[12] = {1, 1, 1, 1, -1, -1, -1, 1, -1, -1, -1, 1};
static const uint32_t kTetraTris[12] = {0, 1, 2, 0, 3, 1, 0, 2, 3, 1, 3, 2};

typedef struct {
    hgcd_world *w;
    hgcd_mesh tetra;
} fixture;

static int setup(void **state) {
    static fixture f;
    hgcd_world_desc d = hgcd_world_desc_default();
    d.thread_count = 2;
    d.thread_policy = HGCD_THREADS_FIXED; /* the stats report 2 threads */
    if (hgcd_world_create(&d, &f.w) != HGCD_OK) return -1;
    hgcd_mesh_desc md = hgcd_mesh_desc_default();
    md.vertices = kTetraVerts;
    md.triangles = kTetraTris;
    md.vertex_count = 4;
    md.triangle_count = 4;
    if (hgcd_mesh_create(f.w, &md, &f.tetra) != HGCD_OK) return -1;
    *state = &f;
    return 0;
}

static int teardown(void **state) {
    fixture *f = *state;
    hgcd_world_destroy(f->w);
    return 0;
}

/* A mesh of nv vertices and nt triangles in w (it must be accepted). */
static hgcd_mesh add_mesh(hgcd_world *w, const double *v, uint32_t nv, const uint32_t *t, uint32_t nt) {
    hgcd_mesh_desc md = hgcd_mesh_desc_default();
    md.vertices = v;
    md.triangles = t;
    md.vertex_count = nv;
    md.triangle_count = nt;
    hgcd_mesh m = {0, 0};
    assert_int_equal(hgcd_mesh_create(w, &md, &m), HGCD_OK);
    return m;
}

static hgcd_body add_body(hgcd_world *w, hgcd_mesh m, double x, double y, double z) {
    hgcd_body_desc d = hgcd_body_desc_default();
    d.mesh = m;
    d.position[0] = x;
    d.position[1] = y;
    d.position[2] = z;
    hgcd_body b = {0, 0};
    assert_int_equal(hgcd_body_create(w, &d, &b), HGCD_OK);
    return b;
}

static size_t pair_count(hgcd_world *w) {
    const hgcd_pair *p;
    size_t n;
    assert_int_equal(hgcd_world_pairs(w, &p, &n), HGCD_OK);
    return n;
}

static void test_version(void **state) {
    (void)state;
    assert_int_equal(hgcd_version(),
                     (HGCD_VERSION_MAJOR << 16) | (HGCD_VERSION_MINOR << 8) | HGCD_VERSION_PATCH);
    char expect[32];
    snprintf(expect, sizeof expect, "%d.%d.%d", HGCD_VERSION_MAJOR, HGCD_VERSION_MINOR, HGCD_VERSION_PATCH);
    assert_string_equal(hgcd_version_string(), expect);
}

static void test_status_strings(void **state) {
    (void)state;
    assert_string_equal(hgcd_status_string(HGCD_OK), "HGCD_OK");
    assert_string_equal(hgcd_status_string(HGCD_ERROR_NULL_ARGUMENT), "HGCD_ERROR_NULL_ARGUMENT");
    assert_string_equal(hgcd_status_string(HGCD_ERROR_INVALID_ARGUMENT), "HGCD_ERROR_INVALID_ARGUMENT");
    assert_string_equal(hgcd_status_string(HGCD_ERROR_BAD_DESCRIPTOR), "HGCD_ERROR_BAD_DESCRIPTOR");
    assert_string_equal(hgcd_status_string(HGCD_ERROR_STALE_ID), "HGCD_ERROR_STALE_ID");
    assert_string_equal(hgcd_status_string(HGCD_ERROR_INVALID_MESH), "HGCD_ERROR_INVALID_MESH");
    assert_string_equal(hgcd_status_string(HGCD_ERROR_MESH_IN_USE), "HGCD_ERROR_MESH_IN_USE");
    assert_string_equal(hgcd_status_string(HGCD_ERROR_OUT_OF_MEMORY), "HGCD_ERROR_OUT_OF_MEMORY");
    assert_string_equal(hgcd_status_string(HGCD_ERROR_CAPACITY), "HGCD_ERROR_CAPACITY");
    assert_string_equal(hgcd_status_string(HGCD_ERROR_NOT_SUPPORTED), "HGCD_ERROR_NOT_SUPPORTED");
    assert_string_equal(hgcd_status_string(HGCD_ERROR_INTERNAL), "HGCD_ERROR_INTERNAL");
    assert_string_equal(hgcd_status_string(12345), "HGCD_ERROR_UNKNOWN");
}

static void test_world_create_errors(void **state) {
    (void)state;
    hgcd_world *w = (hgcd_world *)0x1;
    hgcd_world_desc d = hgcd_world_desc_default();
    assert_int_equal(hgcd_world_create(NULL, &w), HGCD_ERROR_NULL_ARGUMENT);
    assert_null(w);
    assert_int_equal(hgcd_world_create(&d, NULL), HGCD_ERROR_NULL_ARGUMENT);

    hgcd_world_desc junk;
    memset(&junk, 0xA5, sizeof junk);
    assert_int_equal(hgcd_world_create(&junk, &w), HGCD_ERROR_BAD_DESCRIPTOR);
    memset(&junk, 0, sizeof junk);
    assert_int_equal(hgcd_world_create(&junk, &w), HGCD_ERROR_BAD_DESCRIPTOR);
    junk = d;
    junk.struct_size = sizeof junk - 8;
    assert_int_equal(hgcd_world_create(&junk, &w), HGCD_ERROR_BAD_DESCRIPTOR);

    hgcd_world_desc bad = d;
    bad.time_step = NAN;
    assert_int_equal(hgcd_world_create(&bad, &w), HGCD_ERROR_INVALID_ARGUMENT);
    bad = d;
    bad.time_step = -1;
    assert_int_equal(hgcd_world_create(&bad, &w), HGCD_ERROR_INVALID_ARGUMENT);
    bad = d;
    bad.min_cell_size = 4;
    bad.max_cell_size = 2;
    assert_int_equal(hgcd_world_create(&bad, &w), HGCD_ERROR_INVALID_ARGUMENT);
    bad = d;
    bad.max_cell_size = INFINITY;
    assert_int_equal(hgcd_world_create(&bad, &w), HGCD_ERROR_INVALID_ARGUMENT);
    bad = d;
    bad.reflect_at_bounds = 1; /* (bounds are read only when reflecting: test_limits.c) */
    bad.bounds_min[1] = 5;
    bad.bounds_max[1] = 5;
    assert_int_equal(hgcd_world_create(&bad, &w), HGCD_ERROR_INVALID_ARGUMENT);
    bad = d;
    bad.thread_count = 100000;
    assert_int_equal(hgcd_world_create(&bad, &w), HGCD_ERROR_INVALID_ARGUMENT);
    assert_null(w);

    assert_int_equal(hgcd_world_create(&d, &w), HGCD_OK);
    assert_non_null(w);
    assert_string_equal(hgcd_world_last_error(w), "");
    assert_int_equal(hgcd_world_body_count(w), 0);
    assert_int_equal(hgcd_world_mesh_count(w), 0);
    hgcd_world_destroy(w);
    hgcd_world_destroy(NULL); /* no-op */
    assert_int_equal(hgcd_world_body_count(NULL), 0);
    assert_non_null(hgcd_world_last_error(NULL));
}

static void test_null_world_everywhere(void **state) {
    (void)state;
    hgcd_mesh m = {0, 0};
    hgcd_body b = {0, 0};
    hgcd_mesh_desc md = hgcd_mesh_desc_default();
    hgcd_body_desc bd = hgcd_body_desc_default();
    double v[4] = {0, 0, 0, 1};
    const hgcd_pair *p;
    size_t n;
    hgcd_stats st;
    st.struct_size = sizeof st;
    hgcd_mesh_info info;
    info.struct_size = sizeof info;
    uint64_t u;
    assert_int_equal(hgcd_world_step(NULL), HGCD_ERROR_NULL_ARGUMENT);
    assert_int_equal(hgcd_world_detect(NULL), HGCD_ERROR_NULL_ARGUMENT);
    assert_int_equal(hgcd_world_pairs(NULL, &p, &n), HGCD_ERROR_NULL_ARGUMENT);
    assert_int_equal(hgcd_world_copy_pairs(NULL, NULL, 0, &n), HGCD_ERROR_NULL_ARGUMENT);
    assert_int_equal(hgcd_world_stats(NULL, &st), HGCD_ERROR_NULL_ARGUMENT);
    assert_int_equal(hgcd_world_set_thread_count(NULL, 1), HGCD_ERROR_NULL_ARGUMENT);
    assert_int_equal(hgcd_mesh_create(NULL, &md, &m), HGCD_ERROR_NULL_ARGUMENT);
    assert_int_equal(hgcd_mesh_destroy(NULL, m), HGCD_ERROR_NULL_ARGUMENT);
    assert_int_equal(hgcd_mesh_get_info(NULL, m, &info), HGCD_ERROR_NULL_ARGUMENT);
    assert_int_equal(hgcd_body_create(NULL, &bd, &b), HGCD_ERROR_NULL_ARGUMENT);
    assert_int_equal(hgcd_body_destroy(NULL, b), HGCD_ERROR_NULL_ARGUMENT);
    assert_int_equal(hgcd_body_set_pose(NULL, b, v, v), HGCD_ERROR_NULL_ARGUMENT);
    assert_int_equal(hgcd_body_set_velocity(NULL, b, v), HGCD_ERROR_NULL_ARGUMENT);
    assert_int_equal(hgcd_body_get_pose(NULL, b, v, v), HGCD_ERROR_NULL_ARGUMENT);
    assert_int_equal(hgcd_body_get_velocity(NULL, b, v), HGCD_ERROR_NULL_ARGUMENT);
    assert_int_equal(hgcd_body_get_mesh(NULL, b, &m), HGCD_ERROR_NULL_ARGUMENT);
    assert_int_equal(hgcd_body_get_user_data(NULL, b, &u), HGCD_ERROR_NULL_ARGUMENT);
    assert_int_equal(hgcd_body_validate(NULL, b), HGCD_ERROR_NULL_ARGUMENT);
}

static void test_null_outputs(void **state) {
    fixture *f = *state;
    hgcd_mesh_desc md = hgcd_mesh_desc_default();
    hgcd_body_desc bd = hgcd_body_desc_default();
    bd.mesh = f->tetra;
    hgcd_body b = add_body(f->w, f->tetra, 0, 0, 0);
    hgcd_mesh m;
    size_t n;
    const hgcd_pair *p;
    assert_int_equal(hgcd_mesh_create(f->w, NULL, &m), HGCD_ERROR_NULL_ARGUMENT);
    assert_int_equal(hgcd_mesh_create(f->w, &md, NULL), HGCD_ERROR_NULL_ARGUMENT);
    assert_int_equal(hgcd_mesh_create(f->w, &md, &m), HGCD_ERROR_NULL_ARGUMENT); /* NULL arrays */
    assert_non_null(strstr(hgcd_world_last_error(f->w), "NULL"));
    assert_int_equal(hgcd_body_create(f->w, NULL, &b), HGCD_ERROR_NULL_ARGUMENT);
    assert_int_equal(hgcd_body_create(f->w, &bd, NULL), HGCD_ERROR_NULL_ARGUMENT);
    assert_int_equal(hgcd_body_set_velocity(f->w, b, NULL), HGCD_ERROR_NULL_ARGUMENT);
    assert_int_equal(hgcd_body_get_velocity(f->w, b, NULL), HGCD_ERROR_NULL_ARGUMENT);
    assert_int_equal(hgcd_body_get_mesh(f->w, b, NULL), HGCD_ERROR_NULL_ARGUMENT);
    assert_int_equal(hgcd_body_get_user_data(f->w, b, NULL), HGCD_ERROR_NULL_ARGUMENT);
    assert_int_equal(hgcd_world_pairs(f->w, NULL, &n), HGCD_ERROR_NULL_ARGUMENT);
    assert_int_equal(hgcd_world_pairs(f->w, &p, NULL), HGCD_ERROR_NULL_ARGUMENT);
    assert_int_equal(hgcd_world_copy_pairs(f->w, NULL, 3, &n), HGCD_ERROR_NULL_ARGUMENT);
    assert_int_equal(hgcd_world_copy_pairs(f->w, NULL, 0, NULL), HGCD_ERROR_NULL_ARGUMENT);
    assert_int_equal(hgcd_world_stats(f->w, NULL), HGCD_ERROR_NULL_ARGUMENT);
    assert_int_equal(hgcd_mesh_get_info(f->w, f->tetra, NULL), HGCD_ERROR_NULL_ARGUMENT);
    /* get_pose with both outputs NULL is allowed and reads nothing. */
    assert_int_equal(hgcd_body_get_pose(f->w, b, NULL, NULL), HGCD_OK);
    assert_int_equal(hgcd_body_destroy(f->w, b), HGCD_OK);
}

static void test_mesh_errors(void **state) {
    fixture *f = *state;
    hgcd_mesh m = {7, 7};
    hgcd_mesh_desc md = hgcd_mesh_desc_default();
    double v[12];
    uint32_t t[12];
    memcpy(v, kTetraVerts, sizeof v);
    memcpy(t, kTetraTris, sizeof t);
    md.vertices = v;
    md.triangles = t;
    md.vertex_count = 4;
    md.triangle_count = 4;

    hgcd_mesh_desc junk;
    memset(&junk, 0x3C, sizeof junk);
    assert_int_equal(hgcd_mesh_create(f->w, &junk, &m), HGCD_ERROR_BAD_DESCRIPTOR);
    assert_non_null(strstr(hgcd_world_last_error(f->w), "hgcd_mesh_desc_default"));

    hgcd_mesh_desc bad = md;
    bad.triangle_count = 0;
    assert_int_equal(hgcd_mesh_create(f->w, &bad, &m), HGCD_ERROR_INVALID_MESH);
    assert_non_null(strstr(hgcd_world_last_error(f->w), "no triangles"));
    bad = md;
    bad.vertex_count = 0;
    assert_int_equal(hgcd_mesh_create(f->w, &bad, &m), HGCD_ERROR_INVALID_MESH);
    t[7] = 4; /* index out of range */
    assert_int_equal(hgcd_mesh_create(f->w, &md, &m), HGCD_ERROR_INVALID_MESH);
    assert_non_null(strstr(hgcd_world_last_error(f->w), "triangle 2"));
    t[7] = 2;
    v[5] = NAN;
    assert_int_equal(hgcd_mesh_create(f->w, &md, &m), HGCD_ERROR_INVALID_MESH);
    assert_non_null(strstr(hgcd_world_last_error(f->w), "vertex 1"));
    v[5] = INFINITY;
    assert_int_equal(hgcd_mesh_create(f->w, &md, &m), HGCD_ERROR_INVALID_MESH);
    v[5] = 2e15;
    assert_int_equal(hgcd_mesh_create(f->w, &md, &m), HGCD_ERROR_INVALID_MESH);
    v[5] = -1;
    bad = md;
    bad.triangle_count = (1u << 26) + 1;
    assert_int_equal(hgcd_mesh_create(f->w, &bad, &m), HGCD_ERROR_INVALID_MESH);
    /* The caller's arrays are untouched by refused and accepted calls. */
    assert_memory_equal(v, kTetraVerts, sizeof v);
    assert_memory_equal(t, kTetraTris, sizeof t);
    assert_int_equal(m.index, 7);
    assert_int_equal(hgcd_world_mesh_count(f->w), 1);

    assert_int_equal(hgcd_mesh_create(f->w, &md, &m), HGCD_OK);
    assert_int_equal(hgcd_world_mesh_count(f->w), 2);
    hgcd_mesh_info info;
    info.struct_size = sizeof info;
    assert_int_equal(hgcd_mesh_get_info(f->w, m, &info), HGCD_OK);
    assert_int_equal(info.vertex_count, 4);
    assert_int_equal(info.triangle_count, 4);
    assert_int_equal(info.closed, 1);
    assert_int_equal(info.convex, 1);
    assert_int_equal(info.component_count, 1);
    assert_int_equal(info.degenerate_triangle_count, 0);
    assert_true(fabs(info.radius - sqrt(3.0)) < 1e-9);
    info.struct_size = 4;
    assert_int_equal(hgcd_mesh_get_info(f->w, m, &info), HGCD_ERROR_BAD_DESCRIPTOR);

    /* An open mesh (one triangle) and a degenerate one are accepted. */
    hgcd_mesh open;
    md.triangle_count = 1;
    assert_int_equal(hgcd_mesh_create(f->w, &md, &open), HGCD_OK);
    info.struct_size = sizeof info;
    assert_int_equal(hgcd_mesh_get_info(f->w, open, &info), HGCD_OK);
    assert_int_equal(info.closed, 0);
    assert_int_equal(info.convex, 0);
    const uint32_t flat[3] = {0, 0, 1};
    md.triangles = flat;
    hgcd_mesh deg;
    assert_int_equal(hgcd_mesh_create(f->w, &md, &deg), HGCD_OK);
    assert_int_equal(hgcd_mesh_get_info(f->w, deg, &info), HGCD_OK);
    assert_int_equal(info.degenerate_triangle_count, 1);

    /* In use, then stale. */
    hgcd_body b = add_body(f->w, m, 0, 0, 0);
    assert_int_equal(hgcd_mesh_destroy(f->w, m), HGCD_ERROR_MESH_IN_USE);
    assert_non_null(strstr(hgcd_world_last_error(f->w), "1 bodies"));
    assert_int_equal(hgcd_body_destroy(f->w, b), HGCD_OK);
    assert_int_equal(hgcd_mesh_destroy(f->w, m), HGCD_OK);
    assert_int_equal(hgcd_mesh_destroy(f->w, m), HGCD_ERROR_STALE_ID);
    assert_int_equal(hgcd_mesh_get_info(f->w, m, &info), HGCD_ERROR_STALE_ID);
    hgcd_body_desc bd = hgcd_body_desc_default();
    bd.mesh = m;
    assert_int_equal(hgcd_body_create(f->w, &bd, &b), HGCD_ERROR_STALE_ID);
    hgcd_mesh null_mesh = {0, 0};
    assert_int_equal(hgcd_mesh_destroy(f->w, null_mesh), HGCD_ERROR_STALE_ID);
    assert_int_equal(hgcd_mesh_destroy(f->w, open), HGCD_OK);
    assert_int_equal(hgcd_mesh_destroy(f->w, deg), HGCD_OK);
    assert_int_equal(hgcd_world_mesh_count(f->w), 1);
}

static void test_body_ids(void **state) {
    fixture *f = *state;
    hgcd_body b[4];
    for (int i = 0; i < 4; ++i) {
        b[i] = add_body(f->w, f->tetra, 10.0 * i, 0, 0);
        assert_int_equal(b[i].index, (uint32_t)i); /* 0, 1, 2, ... on a fresh world */
        assert_int_not_equal(b[i].generation, 0);
    }
    assert_int_equal(hgcd_world_body_count(f->w), 4);
    assert_int_equal(hgcd_body_destroy(f->w, b[2]), HGCD_OK);
    assert_int_equal(hgcd_world_body_count(f->w), 3);
    /* Every call refuses the stale id. */
    double v[4] = {0, 0, 0, 1};
    hgcd_mesh m;
    uint64_t u;
    assert_int_equal(hgcd_body_destroy(f->w, b[2]), HGCD_ERROR_STALE_ID);
    assert_non_null(strstr(hgcd_world_last_error(f->w), "not a live body"));
    assert_int_equal(hgcd_body_set_pose(f->w, b[2], v, v), HGCD_ERROR_STALE_ID);
    assert_int_equal(hgcd_body_set_velocity(f->w, b[2], v), HGCD_ERROR_STALE_ID);
    assert_int_equal(hgcd_body_get_pose(f->w, b[2], v, v), HGCD_ERROR_STALE_ID);
    assert_int_equal(hgcd_body_get_velocity(f->w, b[2], v), HGCD_ERROR_STALE_ID);
    assert_int_equal(hgcd_body_get_mesh(f->w, b[2], &m), HGCD_ERROR_STALE_ID);
    assert_int_equal(hgcd_body_get_user_data(f->w, b[2], &u), HGCD_ERROR_STALE_ID);
    assert_int_equal(hgcd_body_validate(f->w, b[2]), HGCD_ERROR_STALE_ID);
    /* The index is reused with a new generation; the old id stays stale. */
    hgcd_body again = add_body(f->w, f->tetra, 50, 0, 0);
    assert_int_equal(again.index, 2);
    assert_int_not_equal(again.generation, b[2].generation);
    assert_int_equal(hgcd_body_validate(f->w, again), HGCD_OK);
    assert_int_equal(hgcd_body_validate(f->w, b[2]), HGCD_ERROR_STALE_ID);
    assert_int_equal(hgcd_body_set_pose(f->w, b[2], v, v), HGCD_ERROR_STALE_ID);
    /* Null, forged and out-of-range ids. */
    hgcd_body null_body = {0, 0}, forged = b[1], far = {1000, b[1].generation};
    forged.generation ^= 1;
    assert_int_equal(hgcd_body_validate(f->w, null_body), HGCD_ERROR_STALE_ID);
    assert_int_equal(hgcd_body_validate(f->w, forged), HGCD_ERROR_STALE_ID);
    assert_int_equal(hgcd_body_destroy(f->w, far), HGCD_ERROR_STALE_ID);
    /* A mesh id is looked up among meshes only. */
    hgcd_mesh got;
    assert_int_equal(hgcd_body_get_mesh(f->w, b[0], &got), HGCD_OK);
    assert_memory_equal(&got, &f->tetra, sizeof got);
    for (int i = 0; i < 4; ++i)
        if (i != 2) assert_int_equal(hgcd_body_destroy(f->w, b[i]), HGCD_OK);
    assert_int_equal(hgcd_body_destroy(f->w, again), HGCD_OK);
    assert_int_equal(hgcd_world_body_count(f->w), 0);
}

/* hgcd_mesh_validate: OK exactly for the live meshes of this world, STALE_ID
 * for every other id (the null id shares index 0 with the live tetra),
 * NULL_ARGUMENT for no world; it records no message and changes nothing. */
static void test_mesh_validate(void **state) {
    fixture *f = *state;
    assert_int_equal(f->tetra.index, 0);
    assert_int_equal(hgcd_mesh_validate(f->w, f->tetra), HGCD_OK);
    /* Live, then destroyed; its index reused with a new generation. */
    hgcd_mesh m = add_mesh(f->w, kTetraVerts, 4, kTetraTris, 4);
    assert_int_equal(hgcd_mesh_validate(f->w, m), HGCD_OK);
    assert_int_equal(hgcd_mesh_destroy(f->w, m), HGCD_OK);
    assert_int_equal(hgcd_mesh_validate(f->w, m), HGCD_ERROR_STALE_ID);
    hgcd_mesh again = add_mesh(f->w, kTetraVerts, 4, kTetraTris, 4);
    assert_int_equal(again.index, m.index);
    assert_int_not_equal(again.generation, m.generation);
    assert_int_equal(hgcd_mesh_validate(f->w, again), HGCD_OK);
    assert_int_equal(hgcd_mesh_validate(f->w, m), HGCD_ERROR_STALE_ID);
    /* Null, forged and out-of-range ids. */
    hgcd_mesh null_mesh = {0, 0}, forged = f->tetra, far = {1000, f->tetra.generation};
    forged.generation ^= 1;
    assert_int_equal(hgcd_mesh_validate(f->w, null_mesh), HGCD_ERROR_STALE_ID);
    assert_int_equal(hgcd_mesh_validate(f->w, forged), HGCD_ERROR_STALE_ID);
    assert_int_equal(hgcd_mesh_validate(f->w, far), HGCD_ERROR_STALE_ID);
    /* Another world's mesh of the same index. */
    hgcd_world *other;
    hgcd_world_desc d = hgcd_world_desc_default();
    assert_int_equal(hgcd_world_create(&d, &other), HGCD_OK);
    hgcd_mesh foreign = add_mesh(other, kTetraVerts, 4, kTetraTris, 4);
    assert_int_equal(foreign.index, f->tetra.index);
    assert_int_equal(hgcd_mesh_validate(other, foreign), HGCD_OK);
    assert_int_equal(hgcd_mesh_validate(f->w, foreign), HGCD_ERROR_STALE_ID);
    assert_int_equal(hgcd_mesh_validate(other, f->tetra), HGCD_ERROR_STALE_ID);
    hgcd_world_destroy(other);
    /* No world. */
    assert_int_equal(hgcd_mesh_validate(NULL, f->tetra), HGCD_ERROR_NULL_ARGUMENT);
    /* A refusal records no message and changes nothing. */
    assert_int_equal(hgcd_mesh_destroy(f->w, m), HGCD_ERROR_STALE_ID);
    char before[256];
    snprintf(before, sizeof before, "%s", hgcd_world_last_error(f->w));
    assert_true(strlen(before) > 0);
    assert_int_equal(hgcd_mesh_validate(f->w, forged), HGCD_ERROR_STALE_ID);
    assert_string_equal(hgcd_world_last_error(f->w), before);
    assert_int_equal(hgcd_world_mesh_count(f->w), 2);
    assert_int_equal(hgcd_mesh_destroy(f->w, again), HGCD_OK);
}

static void test_foreign_ids(void **state) {
    fixture *f = *state;
    /* f->w and these 255 worlds are 256 worlds created one after another:
     * their tags all differ (hgcd.h, "Ids"), so each refuses every other's
     * ids, which share its indices. */
    enum { kOthers = 255 };
    hgcd_world *other[kOthers];
    hgcd_mesh om[kOthers];
    hgcd_body ob[kOthers + 1];
    hgcd_world_desc d = hgcd_world_desc_default();
    for (int i = 0; i < kOthers; ++i) {
        assert_int_equal(hgcd_world_create(&d, &other[i]), HGCD_OK);
        om[i] = add_mesh(other[i], kTetraVerts, 4, kTetraTris, 4);
        ob[i] = add_body(other[i], om[i], 0, 0, 0);
    }
    ob[kOthers] = add_body(f->w, f->tetra, 0, 0, 0);
    for (int i = 0; i <= kOthers; ++i) {
        hgcd_world *w = i < kOthers ? other[i] : f->w;
        for (int j = 0; j <= kOthers; ++j) {
            assert_int_equal(ob[j].index, ob[i].index);
            assert_int_equal(hgcd_body_validate(w, ob[j]), i == j ? HGCD_OK : HGCD_ERROR_STALE_ID);
        }
    }
    /* A foreign mesh id is refused too, and the refused call adds nothing. */
    hgcd_body_desc bd = hgcd_body_desc_default();
    bd.mesh = om[0];
    hgcd_body x;
    assert_int_equal(hgcd_body_create(f->w, &bd, &x), HGCD_ERROR_STALE_ID);
    assert_int_equal(hgcd_world_body_count(f->w), 1);
    assert_int_equal(hgcd_body_destroy(f->w, ob[kOthers]), HGCD_OK);
    for (int i = 0; i < kOthers; ++i) hgcd_world_destroy(other[i]);
}

static void test_body_value_errors(void **state) {
    fixture *f = *state;
    hgcd_body_desc d = hgcd_body_desc_default();
    d.mesh = f->tetra;
    hgcd_body b = {0, 0};
    hgcd_body_desc junk;
    memset(&junk, 0, sizeof junk);
    assert_int_equal(hgcd_body_create(f->w, &junk, &b), HGCD_ERROR_BAD_DESCRIPTOR);
    hgcd_body_desc bad = d;
    bad.mesh.index = 0;
    bad.mesh.generation = 0;
    assert_int_equal(hgcd_body_create(f->w, &bad, &b), HGCD_ERROR_STALE_ID);
    bad = d;
    bad.position[1] = NAN;
    assert_int_equal(hgcd_body_create(f->w, &bad, &b), HGCD_ERROR_INVALID_ARGUMENT);
    assert_non_null(strstr(hgcd_world_last_error(f->w), "position[1] is not finite"));
    bad = d;
    bad.position[2] = 1e16;
    assert_int_equal(hgcd_body_create(f->w, &bad, &b), HGCD_ERROR_INVALID_ARGUMENT);
    bad = d;
    bad.orientation[3] = 0; /* zero quaternion */
    assert_int_equal(hgcd_body_create(f->w, &bad, &b), HGCD_ERROR_INVALID_ARGUMENT);
    assert_non_null(strstr(hgcd_world_last_error(f->w), "unit quaternion"));
    bad = d;
    bad.orientation[3] = 1.001;
    assert_int_equal(hgcd_body_create(f->w, &bad, &b), HGCD_ERROR_INVALID_ARGUMENT);
    bad = d;
    bad.orientation[0] = INFINITY;
    assert_int_equal(hgcd_body_create(f->w, &bad, &b), HGCD_ERROR_INVALID_ARGUMENT);
    bad = d;
    bad.velocity[0] = -INFINITY;
    assert_int_equal(hgcd_body_create(f->w, &bad, &b), HGCD_ERROR_INVALID_ARGUMENT);
    bad = d;
    bad.scale = 0;
    assert_int_equal(hgcd_body_create(f->w, &bad, &b), HGCD_ERROR_INVALID_ARGUMENT);
    bad.scale = -1;
    assert_int_equal(hgcd_body_create(f->w, &bad, &b), HGCD_ERROR_INVALID_ARGUMENT);
    bad.scale = NAN;
    assert_int_equal(hgcd_body_create(f->w, &bad, &b), HGCD_ERROR_INVALID_ARGUMENT);
    bad.scale = 1e15;
    assert_int_equal(hgcd_body_create(f->w, &bad, &b), HGCD_ERROR_INVALID_ARGUMENT);
    assert_int_equal(hgcd_world_body_count(f->w), 0);
    assert_int_equal(b.index, 0);
    assert_int_equal(b.generation, 0);

    /* A near-unit quaternion within 1e-6 is accepted and kept as given. */
    d.orientation[3] = 1 + 4e-7;
    d.user_data = 0xDEADBEEFCAFEull;
    assert_int_equal(hgcd_body_create(f->w, &d, &b), HGCD_OK);
    double q[4], p[3];
    assert_int_equal(hgcd_body_get_pose(f->w, b, p, q), HGCD_OK);
    assert_true(q[3] == 1 + 4e-7);
    uint64_t u;
    assert_int_equal(hgcd_body_get_user_data(f->w, b, &u), HGCD_OK);
    assert_true(u == 0xDEADBEEFCAFEull);

    /* Refused set_pose / set_velocity change nothing. */
    const double good_p[3] = {1, 2, 3}, good_q[4] = {0, 0, 1, 0}, good_v[3] = {0.5, 0, 0};
    assert_int_equal(hgcd_body_set_pose(f->w, b, good_p, good_q), HGCD_OK);
    assert_int_equal(hgcd_body_set_velocity(f->w, b, good_v), HGCD_OK);
    const double nan_p[3] = {1, NAN, 3}, bad_q[4] = {0, 0, 0.5, 0}, inf_v[3] = {0, INFINITY, 0};
    assert_int_equal(hgcd_body_set_pose(f->w, b, nan_p, good_q), HGCD_ERROR_INVALID_ARGUMENT);
    assert_int_equal(hgcd_body_set_pose(f->w, b, good_p, bad_q), HGCD_ERROR_INVALID_ARGUMENT);
    assert_int_equal(hgcd_body_set_pose(f->w, b, nan_p, NULL), HGCD_ERROR_INVALID_ARGUMENT);
    assert_int_equal(hgcd_body_set_velocity(f->w, b, inf_v), HGCD_ERROR_INVALID_ARGUMENT);
    double v[3];
    assert_int_equal(hgcd_body_get_pose(f->w, b, p, q), HGCD_OK);
    assert_int_equal(hgcd_body_get_velocity(f->w, b, v), HGCD_OK);
    assert_memory_equal(p, good_p, sizeof p);
    assert_memory_equal(q, good_q, sizeof q);
    assert_memory_equal(v, good_v, sizeof v);
    /* NULL keeps a part of the pose. */
    const double moved[3] = {4, 5, 6};
    assert_int_equal(hgcd_body_set_pose(f->w, b, moved, NULL), HGCD_OK);
    assert_int_equal(hgcd_body_get_pose(f->w, b, p, q), HGCD_OK);
    assert_memory_equal(p, moved, sizeof p);
    assert_memory_equal(q, good_q, sizeof q);
    assert_int_equal(hgcd_body_destroy(f->w, b), HGCD_OK);
}

static void test_pairs_and_stats(void **state) {
    fixture *f = *state;
    const hgcd_pair *p = (const hgcd_pair *)0x1;
    size_t n = 99, total = 99;
    assert_int_equal(hgcd_world_pairs(f->w, &p, &n), HGCD_OK);
    assert_int_equal(n, 0); /* before the first detect */
    /* Three tetrahedra in a row, touching neighbours overlap; a far one. */
    hgcd_body a = add_body(f->w, f->tetra, 0, 0, 0);
    hgcd_body b = add_body(f->w, f->tetra, 1.5, 0, 0);
    hgcd_body c = add_body(f->w, f->tetra, 3.0, 0, 0);
    hgcd_body far = add_body(f->w, f->tetra, 100, 100, 100);
    assert_int_equal(hgcd_world_detect(f->w), HGCD_OK);
    assert_int_equal(hgcd_world_pairs(f->w, &p, &n), HGCD_OK);
    assert_int_equal(n, 2);
    assert_int_equal(p[0].a.index, a.index);
    assert_int_equal(p[0].b.index, b.index);
    assert_int_equal(p[0].a.generation, a.generation);
    assert_int_equal(p[1].a.index, b.index);
    assert_int_equal(p[1].b.index, c.index);
    hgcd_pair buf[4];
    assert_int_equal(hgcd_world_copy_pairs(f->w, NULL, 0, &total), HGCD_OK);
    assert_int_equal(total, 2);
    memset(buf, 0, sizeof buf);
    assert_int_equal(hgcd_world_copy_pairs(f->w, buf, 1, &total), HGCD_OK);
    assert_int_equal(total, 2);
    assert_memory_equal(&buf[0], &p[0], sizeof buf[0]);
    assert_int_equal(buf[1].a.generation, 0); /* not written past capacity */
    assert_int_equal(hgcd_world_copy_pairs(f->w, buf, 4, &total), HGCD_OK);
    assert_memory_equal(buf, p, 2 * sizeof buf[0]);

    hgcd_stats st;
    memset(&st, 0, sizeof st);
    st.struct_size = sizeof st;
    assert_int_equal(hgcd_world_stats(f->w, &st), HGCD_OK);
    assert_int_equal(st.colliding_pairs, 2);
    assert_true(st.candidate_pairs >= 2);
    assert_true(st.narrow_tests >= 2);
    assert_true(st.level_count >= 1);
    assert_int_equal(st.thread_count, 2);
    assert_true(st.total_seconds >= st.narrow_seconds);
    st.struct_size = 4;
    assert_int_equal(hgcd_world_stats(f->w, &st), HGCD_ERROR_BAD_DESCRIPTOR);
    /* A shorter struct from an older caller gets only its own bytes. */
    uint64_t small[2];
    unsigned char *bytes = (unsigned char *)small;
    const uint32_t small_size = 12;
    memset(small, 0xEE, sizeof small);
    memcpy(small, &small_size, sizeof small_size);
    assert_int_equal(hgcd_world_stats(f->w, (hgcd_stats *)small), HGCD_OK);
    assert_int_equal(bytes[12], 0xEE);
    uint32_t levels_copied;
    memcpy(&levels_copied, bytes + 4, sizeof levels_copied);
    assert_int_equal(levels_copied, st.level_count);

    /* Destroyed bodies leave the next tick's pairs. */
    assert_int_equal(hgcd_body_destroy(f->w, b), HGCD_OK);
    assert_int_equal(hgcd_world_detect(f->w), HGCD_OK);
    assert_int_equal(pair_count(f->w), 0);
    assert_int_equal(hgcd_body_destroy(f->w, a), HGCD_OK);
    assert_int_equal(hgcd_body_destroy(f->w, c), HGCD_OK);
    assert_int_equal(hgcd_body_destroy(f->w, far), HGCD_OK);
}

static void test_step_motion(void **state) {
    (void)state;
    hgcd_world_desc d = hgcd_world_desc_default();
    d.time_step = 0.5;
    d.reflect_at_bounds = 1;
    for (int k = 0; k < 3; ++k) {
        d.bounds_min[k] = 0;
        d.bounds_max[k] = 10;
    }
    hgcd_world *w;
    assert_int_equal(hgcd_world_create(&d, &w), HGCD_OK);
    hgcd_mesh m = add_mesh(w, kTetraVerts, 4, kTetraTris, 4);
    hgcd_body b = add_body(w, m, 9.5, 5, 0.25);
    const double v[3] = {2, 0, -1};
    assert_int_equal(hgcd_body_set_velocity(w, b, v), HGCD_OK);
    assert_int_equal(hgcd_world_step(w), HGCD_OK);
    double p[3], vel[3];
    assert_int_equal(hgcd_body_get_pose(w, b, p, NULL), HGCD_OK);
    assert_int_equal(hgcd_body_get_velocity(w, b, vel), HGCD_OK);
    /* x: 9.5 + 1 = 10.5 -> mirrored to 9.5, vx = -2; z: 0.25 - 0.5 -> 0.25, vz = 1 */
    assert_true(p[0] == 9.5 && vel[0] == -2);
    assert_true(p[1] == 5 && vel[1] == 0);
    assert_true(p[2] == 0.25 && vel[2] == 1);
    hgcd_world_destroy(w);

    /* Without bounds, a step that would leave the coordinate range moves nothing. */
    d = hgcd_world_desc_default();
    assert_int_equal(hgcd_world_create(&d, &w), HGCD_OK);
    m = add_mesh(w, kTetraVerts, 4, kTetraTris, 4);
    hgcd_body slow = add_body(w, m, 0, 0, 0);
    hgcd_body fast = add_body(w, m, 9e14, 0, 0);
    const double v1[3] = {1, 0, 0}, v2[3] = {2e14, 0, 0};
    assert_int_equal(hgcd_body_set_velocity(w, slow, v1), HGCD_OK);
    assert_int_equal(hgcd_body_set_velocity(w, fast, v2), HGCD_OK);
    assert_int_equal(hgcd_world_step(w), HGCD_ERROR_INVALID_ARGUMENT);
    assert_non_null(strstr(hgcd_world_last_error(w), "body 1"));
    assert_int_equal(hgcd_body_get_pose(w, slow, p, NULL), HGCD_OK);
    assert_true(p[0] == 0);
    assert_int_equal(hgcd_body_set_velocity(w, fast, v1), HGCD_OK);
    assert_int_equal(hgcd_world_step(w), HGCD_OK);
    assert_int_equal(hgcd_body_get_pose(w, slow, p, NULL), HGCD_OK);
    assert_true(p[0] == 1);
    hgcd_stats st;
    st.struct_size = sizeof st;
    assert_int_equal(hgcd_world_stats(w, &st), HGCD_OK);
    assert_true(st.motion_seconds >= 0 && st.total_seconds >= st.motion_seconds);
    assert_int_equal(hgcd_world_set_thread_count(w, 100000), HGCD_ERROR_INVALID_ARGUMENT);
    assert_int_equal(hgcd_world_set_thread_count(w, 1), HGCD_OK);
    hgcd_world_destroy(w);
}

static void test_refused_call_keeps_pairs(void **state) {
    fixture *f = *state;
    hgcd_body a = add_body(f->w, f->tetra, 0, 0, 0);
    hgcd_body b = add_body(f->w, f->tetra, 1, 0, 0);
    assert_int_equal(hgcd_world_detect(f->w), HGCD_OK);
    assert_int_equal(pair_count(f->w), 1);
    const double nan_p[3] = {NAN, 0, 0};
    assert_int_equal(hgcd_body_set_pose(f->w, b, nan_p, NULL), HGCD_ERROR_INVALID_ARGUMENT);
    hgcd_mesh_desc md = hgcd_mesh_desc_default();
    hgcd_mesh m;
    assert_int_equal(hgcd_mesh_create(f->w, &md, &m), HGCD_ERROR_NULL_ARGUMENT);
    assert_int_equal(hgcd_world_detect(f->w), HGCD_OK);
    assert_int_equal(pair_count(f->w), 1);
    assert_int_equal(hgcd_body_destroy(f->w, a), HGCD_OK);
    assert_int_equal(hgcd_body_destroy(f->w, b), HGCD_OK);
}

/* hgcd_scene_tetra_populate makes the same world as drawing the scene with
 * hgcd_scene_tetra_generate and creating the bodies by hand: same poses,
 * velocities, scales (through the mesh), user data and pairs. On a refused
 * body it leaves nothing behind. */
static void test_scene_tetra_populate(void **state) {
    (void)state;
    enum { n = 3000 };
    hgcd_scene_tetra_desc sd = hgcd_scene_tetra_desc_default();
    sd.n = n;
    sd.side = 40;
    static double centers[3 * n], scales[n], quats[4 * n], vels[3 * n];
    assert_int_equal(hgcd_scene_tetra_generate(&sd, centers, NULL, scales, quats, vels), HGCD_OK);

    hgcd_world *a, *b;
    hgcd_world_desc wd = hgcd_world_desc_default();
    assert_int_equal(hgcd_world_create(&wd, &a), HGCD_OK);
    assert_int_equal(hgcd_world_create(&wd, &b), HGCD_OK);
    hgcd_mesh ma;
    assert_int_equal(hgcd_scene_tetra_populate(a, &sd, &ma), HGCD_OK);
    double uv[12];
    uint32_t ut[12];
    hgcd_scene_tetra_unit_mesh(uv, ut);
    const hgcd_mesh mb = add_mesh(b, uv, 4, ut, 4);
    hgcd_body_desc bd = hgcd_body_desc_default();
    bd.mesh = mb;
    for (uint32_t i = 0; i < n; ++i) {
        memcpy(bd.position, centers + 3 * i, sizeof bd.position);
        memcpy(bd.orientation, quats + 4 * i, sizeof bd.orientation);
        memcpy(bd.velocity, vels + 3 * i, sizeof bd.velocity);
        bd.scale = scales[i];
        bd.user_data = i;
        hgcd_body id;
        assert_int_equal(hgcd_body_create(b, &bd, &id), HGCD_OK);
    }
    assert_int_equal(hgcd_world_body_count(a), n);
    assert_int_equal(hgcd_world_mesh_count(a), 1);
    for (int tick = 0; tick < 3; ++tick) {
        assert_int_equal(tick ? hgcd_world_step(a) : hgcd_world_detect(a), HGCD_OK);
        assert_int_equal(tick ? hgcd_world_step(b) : hgcd_world_detect(b), HGCD_OK);
        const hgcd_pair *pa, *pb;
        size_t na, nb;
        assert_int_equal(hgcd_world_pairs(a, &pa, &na), HGCD_OK);
        assert_int_equal(hgcd_world_pairs(b, &pb, &nb), HGCD_OK);
        assert_true(na > 10);
        assert_int_equal(na, nb);
        for (size_t k = 0; k < na; ++k) {
            uint64_t ua[2], ub[2];
            assert_int_equal(hgcd_body_get_user_data(a, pa[k].a, &ua[0]), HGCD_OK);
            assert_int_equal(hgcd_body_get_user_data(a, pa[k].b, &ua[1]), HGCD_OK);
            assert_int_equal(hgcd_body_get_user_data(b, pb[k].a, &ub[0]), HGCD_OK);
            assert_int_equal(hgcd_body_get_user_data(b, pb[k].b, &ub[1]), HGCD_OK);
            assert_true(ua[0] == ub[0] && ua[1] == ub[1]);
        }
    }
    hgcd_world_destroy(a);
    hgcd_world_destroy(b);

    /* Refusals: nothing made. Coordinates beyond 1e15 are refused by
     * hgcd_body_create, so in a cube of side 1.02e15 some body is refused
     * after others were made. */
    hgcd_world *w;
    assert_int_equal(hgcd_world_create(&wd, &w), HGCD_OK);
    assert_int_equal(hgcd_scene_tetra_populate(NULL, &sd, NULL), HGCD_ERROR_NULL_ARGUMENT);
    assert_int_equal(hgcd_scene_tetra_populate(w, NULL, NULL), HGCD_ERROR_NULL_ARGUMENT);
    hgcd_scene_tetra_desc bad = sd;
    bad.struct_size = 0;
    assert_int_equal(hgcd_scene_tetra_populate(w, &bad, NULL), HGCD_ERROR_BAD_DESCRIPTOR);
    bad = sd;
    bad.n = 50;
    bad.side = 1.02e15;
    assert_int_equal(hgcd_scene_tetra_generate(&bad, centers, NULL, NULL, NULL, NULL), HGCD_OK);
    int made_before_refusal = 0;
    while (made_before_refusal < 50 && centers[3 * made_before_refusal] <= 1e15 &&
           centers[3 * made_before_refusal + 1] <= 1e15 && centers[3 * made_before_refusal + 2] <= 1e15)
        ++made_before_refusal;
    assert_true(made_before_refusal > 0 && made_before_refusal < 50);
    assert_int_not_equal(hgcd_scene_tetra_populate(w, &bad, NULL), HGCD_OK);
    assert_int_equal(hgcd_world_body_count(w), 0);
    assert_int_equal(hgcd_world_mesh_count(w), 0);
    assert_int_equal(hgcd_world_detect(w), HGCD_OK);
    hgcd_world_destroy(w);
}

/* A body's box (hgcd_stats.candidate_pairs) is that of the world vertices
 * its triangles use: a vertex no triangle uses, here 10 units out along x,
 * does not widen it. Body b's solid and box lie within [8, 10] in x, body
 * a's within [-1, 1]: no candidate pair, though a box over all of a's
 * vertices would reach x = 10. Likewise turned a quarter about z, the
 * unused vertex then 10 units out along y. */
static void test_box_ignores_unused_vertices(void **state) {
    fixture *f = *state;
    static const double verts[15] = {1, 1, 1, 1, -1, -1, -1, 1, -1, -1, -1, 1, 10, 0, 0};
    const hgcd_mesh m = add_mesh(f->w, verts, 5, kTetraTris, 4);
    const double r = 0.70710678118654757;
    const double turns[2][4] = {{0, 0, 0, 1}, {0, 0, r, r}};
    for (int t = 0; t < 2; ++t) {
        hgcd_body a = add_body(f->w, m, 0, 0, 0);
        hgcd_body b = add_body(f->w, f->tetra, t ? 0 : 9, t ? 9 : 0, 0);
        assert_int_equal(hgcd_body_set_pose(f->w, a, NULL, turns[t]), HGCD_OK);
        assert_int_equal(hgcd_world_detect(f->w), HGCD_OK);
        hgcd_stats st;
        memset(&st, 0, sizeof st);
        st.struct_size = sizeof st;
        assert_int_equal(hgcd_world_stats(f->w, &st), HGCD_OK);
        assert_int_equal(st.candidate_pairs, 0);
        assert_int_equal(st.colliding_pairs, 0);
        /* 2 units closer: still apart (a box over every vertex would meet
         * b's); then touching b's box face to face. */
        const double closer[3] = {t ? 0 : 7, t ? 7 : 0, 0};
        assert_int_equal(hgcd_body_set_pose(f->w, b, closer, NULL), HGCD_OK);
        assert_int_equal(hgcd_world_detect(f->w), HGCD_OK);
        assert_int_equal(hgcd_world_stats(f->w, &st), HGCD_OK);
        assert_int_equal(st.candidate_pairs, 0);
        const double touching[3] = {t ? 0 : 2, t ? 2 : 0, 0};
        assert_int_equal(hgcd_body_set_pose(f->w, b, touching, NULL), HGCD_OK);
        assert_int_equal(hgcd_world_detect(f->w), HGCD_OK);
        assert_int_equal(hgcd_world_stats(f->w, &st), HGCD_OK);
        assert_int_equal(st.candidate_pairs, 1);
        assert_int_equal(hgcd_body_destroy(f->w, a), HGCD_OK);
        assert_int_equal(hgcd_body_destroy(f->w, b), HGCD_OK);
    }
    assert_int_equal(hgcd_mesh_destroy(f->w, m), HGCD_OK);
}

int main(void) {
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_version),
        cmocka_unit_test(test_status_strings),
        cmocka_unit_test(test_world_create_errors),
        cmocka_unit_test(test_null_world_everywhere),
        cmocka_unit_test_setup_teardown(test_null_outputs, setup, teardown),
        cmocka_unit_test_setup_teardown(test_mesh_errors, setup, teardown),
        cmocka_unit_test_setup_teardown(test_body_ids, setup, teardown),
        cmocka_unit_test_setup_teardown(test_mesh_validate, setup, teardown),
        cmocka_unit_test_setup_teardown(test_foreign_ids, setup, teardown),
        cmocka_unit_test_setup_teardown(test_body_value_errors, setup, teardown),
        cmocka_unit_test_setup_teardown(test_pairs_and_stats, setup, teardown),
        cmocka_unit_test(test_step_motion),
        cmocka_unit_test_setup_teardown(test_refused_call_keeps_pairs, setup, teardown),
        cmocka_unit_test(test_scene_tetra_populate),
        cmocka_unit_test_setup_teardown(test_box_ignores_unused_vertices, setup, teardown),
    };
    if (getenv("HGCD_TEST_FILTER")) cmocka_set_test_filter(getenv("HGCD_TEST_FILTER"));
    return cmocka_run_group_tests(tests, NULL, NULL);
}
