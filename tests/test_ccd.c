/* The libccd narrow phase (HGCD_NARROW_GJK, HGCD_NARROW_MPR) against the
 * exact one, and the contact API (hgcd_world_contacts).
 *
 * Agreement. On random convex scenes (scene `tetra` of docs/scenes.md at small n,
 * rotated cubes, finely tessellated cubes) every pair is decided by the exact
 * path and by libccd. libccd is not exact, so the two may differ, but only on
 * pairs that touch or overlap by less than libccd's tolerance. hgcd sets the
 * tolerance per pair to tol = rel * (r_a + r_b) with rel = 1e-6 when libccd
 * is built in double precision (1e-4 in single), r = bounding radius (hgcd.h,
 * enum hgcd_narrow_phase). Every disagreement is checked with the exact
 * GMP oracle (tests/oracle.c):
 *   - libccd says yes, exact says no (a gap): body b grown about its centre
 *     by tol (scale += tol / inradius of the unit mesh, which adds at least
 *     tol all around) must collide exactly; so the gap is below
 *     tol * R / rho (3 tol for the tetrahedron, sqrt(3) tol for the cube);
 *   - libccd says no, exact says yes (an overlap): body b shrunk by tol
 *     (scale -= tol / inradius, which removes at least tol all around) must
 *     be apart exactly; so the overlap is shallower than tol in every
 *     direction that matters.
 * For each disagreement the smallest multiple k of tol (1/1000, 1/100, 1/10,
 * 1) that flips the oracle's answer is printed, with the counts.
 *
 * Known weak spots of libccd, covered and documented by test_weak_spots:
 * face-to-face stacked boxes (GJK's simplex degenerates on coplanar faces)
 * and bodies exactly touching (face, edge, vertex): with gaps or overlaps far
 * below the tolerance libccd may answer either way (the oracle check above
 * must hold), beyond 1000 tol it must agree.
 *
 * Contacts. Witness triangles of SURFACE contacts really intersect
 * (hgcdi_tri_tri on the world vertices), containment kinds are right (a
 * vertex of the held body inside the holder, surfaces apart), penetration
 * depth and normal match two overlapping cubes with a known overlap, the
 * contacts do not depend on the thread count and switching contacts on does
 * not change the pairs. */
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

#include "support/shapes.h"
#include "support/testing.h"
#include "oracle.h"

/* ------------------------------------------------------------- shapes -- */

enum { SH_TETRA, SH_CUBE, SH_FINE_CUBE, SH_DENTED, SH_TWIN, SH_COUNT };


/* The cube [-1, 1]^3 with every face cut into 4 x 4 squares: 98 vertices,
 * 192 triangles, convex (enough triangles for the narrow phase's tree path). */
#define FINE 4
static double fine_v[3 * 98];
static uint32_t fine_t[3 * 192];

static void build_fine_cube(void) {
    int index[FINE + 1][FINE + 1][FINE + 1];
    uint32_t nv = 0, nt = 0;
    for (int i = 0; i <= FINE; ++i)
        for (int j = 0; j <= FINE; ++j)
            for (int k = 0; k <= FINE; ++k) {
                index[i][j][k] = -1;
                if (i == 0 || i == FINE || j == 0 || j == FINE || k == 0 || k == FINE) {
                    index[i][j][k] = (int)nv;
                    fine_v[3 * nv] = -1 + 2.0 * i / FINE;
                    fine_v[3 * nv + 1] = -1 + 2.0 * j / FINE;
                    fine_v[3 * nv + 2] = -1 + 2.0 * k / FINE;
                    ++nv;
                }
            }
    for (int axis = 0; axis < 3; ++axis)
        for (int side = 0; side <= FINE; side += FINE) {
            const int u = (axis + 1) % 3, v = (axis + 2) % 3;
            for (int a = 0; a < FINE; ++a)
                for (int b = 0; b < FINE; ++b) {
                    int c[4][3];
                    const int du[4] = {0, 1, 1, 0}, dv[4] = {0, 0, 1, 1};
                    for (int q = 0; q < 4; ++q) {
                        c[q][axis] = side;
                        c[q][u] = a + du[q];
                        c[q][v] = b + dv[q];
                    }
                    uint32_t id[4];
                    for (int q = 0; q < 4; ++q) id[q] = (uint32_t)index[c[q][0]][c[q][1]][c[q][2]];
                    /* u x v = axis: counter-clockwise seen from outside on the + side. */
                    const uint32_t tri[2][3] = {{id[0], id[1], id[2]}, {id[0], id[2], id[3]}};
                    for (int t = 0; t < 2; ++t) {
                        fine_t[3 * nt] = tri[t][0];
                        fine_t[3 * nt + 1] = side ? tri[t][1] : tri[t][2];
                        fine_t[3 * nt + 2] = side ? tri[t][2] : tri[t][1];
                        ++nt;
                    }
                }
        }
    assert_int_equal(nv, 98);
    assert_int_equal(nt, 192);
}

static oracle_mesh shapes[SH_COUNT] = {
    {tetra_v, tetra_t, 4, 4, 1},    {cube_v, cube_t, 8, 12, 1},    {fine_v, fine_t, 98, 192, 1},
    {dented_v, dented_t, 9, 14, 1}, {twin_v, twin_t, 8, 8, 1},
};
/* Radius of the largest ball about the mesh origin inside the unit mesh. */
static const double inradius[SH_COUNT] = {0.57735026918962573, 1, 1, 0.25, 0};

/* -------------------------------------------------------------- scene -- */

#include "test_rng.h"

static void random_quat(rng *r, double *q) {
    const double u1 = unif(r), u2 = unif(r), u3 = unif(r);
    q[0] = sqrt(1 - u1) * sin(6.283185307179586 * u2);
    q[1] = sqrt(1 - u1) * cos(6.283185307179586 * u2);
    q[2] = sqrt(u1) * sin(6.283185307179586 * u3);
    q[3] = sqrt(u1) * cos(6.283185307179586 * u3);
}

/* Bodies on the test side, body k gets index k in every world. */
typedef struct {
    size_t n, cap;
    int *shape;
    double *pos, *quat, *scale;
} bodies;

static void bodies_init(bodies *b, size_t cap) {
    b->n = 0;
    b->cap = cap;
    b->shape = malloc(cap * sizeof(int));
    b->pos = malloc(3 * cap * sizeof(double));
    b->quat = malloc(4 * cap * sizeof(double));
    b->scale = malloc(cap * sizeof(double));
    assert_non_null(b->shape);
}

static void bodies_free(bodies *b) {
    free(b->shape);
    free(b->pos);
    free(b->quat);
    free(b->scale);
}

static void push(bodies *b, int shape, const double *p, const double *q, double scale) {
    assert_true(b->n < b->cap);
    b->shape[b->n] = shape;
    memcpy(&b->pos[3 * b->n], p, 3 * sizeof(double));
    memcpy(&b->quat[4 * b->n], q, 4 * sizeof(double));
    b->scale[b->n] = scale;
    ++b->n;
}

typedef struct {
    hgcd_world *w;
    hgcd_mesh mesh[SH_COUNT];
} world;

static void make_world(world *out, const bodies *b, int32_t narrow, uint32_t contacts, uint32_t threads) {
    hgcd_world_desc wd = hgcd_world_desc_default();
    wd.narrow_phase = narrow;
    wd.contacts = contacts;
    wd.thread_count = threads;
    assert_int_equal(hgcd_world_create(&wd, &out->w), HGCD_OK);
    for (int k = 0; k < SH_COUNT; ++k) {
        hgcd_mesh_desc md = hgcd_mesh_desc_default();
        md.vertices = shapes[k].verts;
        md.triangles = shapes[k].tris;
        md.vertex_count = shapes[k].vertex_count;
        md.triangle_count = shapes[k].triangle_count;
        assert_int_equal(hgcd_mesh_create(out->w, &md, &out->mesh[k]), HGCD_OK);
    }
    for (size_t i = 0; i < b->n; ++i) {
        hgcd_body_desc bd = hgcd_body_desc_default();
        bd.mesh = out->mesh[b->shape[i]];
        memcpy(bd.position, &b->pos[3 * i], sizeof bd.position);
        memcpy(bd.orientation, &b->quat[4 * i], sizeof bd.orientation);
        bd.scale = b->scale[i];
        hgcd_body id;
        assert_int_equal(hgcd_body_create(out->w, &bd, &id), HGCD_OK);
        assert_int_equal(id.index, i);
    }
    assert_int_equal(hgcd_world_detect(out->w), HGCD_OK);
}

/* Pairs of the last detect as sorted keys a << 32 | b. */
static uint64_t *pair_keys(const hgcd_world *w, size_t *count) {
    const hgcd_pair *p;
    assert_int_equal(hgcd_world_pairs(w, &p, count), HGCD_OK);
    uint64_t *k = malloc((*count + 1) * sizeof(uint64_t));
    for (size_t i = 0; i < *count; ++i) k[i] = (uint64_t)p[i].a.index << 32 | p[i].b.index;
    return k;
}

/* Bounding radius of the unit meshes (hgcd_mesh_info.radius). */
static double mesh_radius[SH_COUNT];

static double pair_tolerance(const bodies *b, size_t i, size_t j) {
    const double rel = hgcd_feature_libccd() == HGCD_LIBCCD_DOUBLE ? 1e-6 : 1e-4;
    return rel * (b->scale[i] * mesh_radius[b->shape[i]] + b->scale[j] * mesh_radius[b->shape[j]]);
}

/* Exact answer (GMP oracle) for bodies i and j, with j's scale replaced. */
static int oracle_pair(const bodies *b, size_t i, size_t j, double scale_j) {
    const oracle_mesh *m[2] = {&shapes[b->shape[i]], &shapes[b->shape[j]]};
    double p[6], q[8], s[2] = {b->scale[i], scale_j};
    memcpy(p, &b->pos[3 * i], 3 * sizeof(double));
    memcpy(p + 3, &b->pos[3 * j], 3 * sizeof(double));
    memcpy(q, &b->quat[4 * i], 4 * sizeof(double));
    memcpy(q + 4, &b->quat[4 * j], 4 * sizeof(double));
    return oracle_colliding_pairs(2, m, p, q, s, NULL, 0) == 1;
}

/* For a pair on which libccd (says `ccd`) and the exact path differ: the
 * smallest k in {0.001, 0.01, 0.1, 1} such that growing (ccd = 1) or
 * shrinking (ccd = 0) body j by k * tol makes the oracle agree with libccd;
 * 0 if even k = 1 does not (the tolerance claim is broken). */
static double flip_factor(const bodies *b, size_t i, size_t j, int ccd) {
    const double tol = pair_tolerance(b, i, j);
    const double ks[4] = {0.001, 0.01, 0.1, 1};
    for (int t = 0; t < 4; ++t) {
        const double d = ks[t] * tol / inradius[b->shape[j]];
        const double sj = ccd ? b->scale[j] + d : b->scale[j] - d;
        if (oracle_pair(b, i, j, sj) == ccd) return ks[t];
    }
    return 0;
}

typedef struct {
    size_t exact_pairs, ccd_pairs, false_yes, false_no;
    double worst_factor; /* largest flip factor seen (1 = needed the whole tolerance) */
    double max_false_depth; /* GJK false yes: largest EPA depth / tol */
} agreement;

/* Compares libccd (method) with the exact path on the bodies; checks every
 * disagreement against the tolerance. */
static agreement compare(const bodies *b, int32_t method, uint32_t threads) {
    world ex, cc;
    make_world(&ex, b, HGCD_NARROW_EXACT, 0, threads);
    make_world(&cc, b, method, 1, threads);
    agreement r = {0, 0, 0, 0, 0, 0};
    uint64_t *e = pair_keys(ex.w, &r.exact_pairs), *c = pair_keys(cc.w, &r.ccd_pairs);
    const hgcd_contact *con;
    size_t ncon;
    assert_int_equal(hgcd_world_contacts(cc.w, &con, &ncon), HGCD_OK);
    assert_int_equal(ncon, r.ccd_pairs);
    hgcd_stats st;
    st.struct_size = sizeof st;
    assert_int_equal(hgcd_world_stats(cc.w, &st), HGCD_OK);
    assert_true(st.libccd_tests > 0);
    assert_int_equal(st.libccd_fallback_tests, 0);
    size_t x = 0, y = 0;
    while (x < r.exact_pairs || y < r.ccd_pairs) {
        if (x < r.exact_pairs && y < r.ccd_pairs && e[x] == c[y]) {
            ++x;
            ++y;
            continue;
        }
        const int ccd_only = x >= r.exact_pairs || (y < r.ccd_pairs && c[y] < e[x]);
        const uint64_t key = ccd_only ? c[y] : e[x];
        const size_t i = (size_t)(key >> 32), j = (size_t)(uint32_t)key;
        const double f = flip_factor(b, i, j, ccd_only);
        if (f == 0)
            fprintf(stderr, "pair (%zu, %zu): libccd says %s, exact says %s, beyond the tolerance %g\n", i, j,
                    ccd_only ? "yes" : "no", ccd_only ? "no" : "yes", pair_tolerance(b, i, j));
        assert_true(f > 0);
        if (f > r.worst_factor) r.worst_factor = f;
        if (ccd_only) {
            ++r.false_yes;
            const double depth = con[y].depth / pair_tolerance(b, i, j);
            assert_int_equal(con[y].kind, HGCD_CONTACT_PENETRATION);
            if (depth > r.max_false_depth) r.max_false_depth = depth;
            ++y;
        } else {
            ++r.false_no;
            ++x;
        }
    }
    free(e);
    free(c);
    hgcd_world_destroy(ex.w);
    hgcd_world_destroy(cc.w);
    return r;
}

static void report(const char *scene, const char *method, const agreement *r) {
    printf("%-28s %-3s exact %6zu libccd %6zu  libccd-only %3zu  exact-only %3zu  worst flip %.3g tol"
           "  max EPA depth of libccd-only %.3g tol\n",
           scene, method, r->exact_pairs, r->ccd_pairs, r->false_yes, r->false_no, r->worst_factor,
           r->max_false_depth);
}

/* -------------------------------------------------------------- tests -- */

static int setup(void **state) {
    (void)state;
    build_fine_cube();
    hgcd_world *w;
    hgcd_world_desc wd = hgcd_world_desc_default();
    if (hgcd_world_create(&wd, &w) != HGCD_OK) return 1;
    for (int k = 0; k < SH_COUNT; ++k) {
        hgcd_mesh_desc md = hgcd_mesh_desc_default();
        md.vertices = shapes[k].verts;
        md.triangles = shapes[k].tris;
        md.vertex_count = shapes[k].vertex_count;
        md.triangle_count = shapes[k].triangle_count;
        hgcd_mesh m;
        hgcd_mesh_info info;
        info.struct_size = sizeof info;
        if (hgcd_mesh_create(w, &md, &m) != HGCD_OK || hgcd_mesh_get_info(w, m, &info) != HGCD_OK) return 1;
        mesh_radius[k] = info.radius;
    }
    hgcd_world_destroy(w);
    return 0;
}

static void test_feature_and_refusals(void **state) {
    (void)state;
    const int32_t f = hgcd_feature_libccd();
    printf("hgcd_feature_libccd() = %d (%s)\n", f, f == 2 ? "double" : f == 1 ? "single" : "none");
    assert_true(f == HGCD_LIBCCD_SINGLE || f == HGCD_LIBCCD_DOUBLE);

    hgcd_world_desc wd = hgcd_world_desc_default();
    assert_int_equal(wd.narrow_phase, HGCD_NARROW_EXACT);
    assert_int_equal(wd.contacts, 0);
    hgcd_world *w = (hgcd_world *)&wd;
    wd.narrow_phase = 3;
    assert_int_equal(hgcd_world_create(&wd, &w), HGCD_ERROR_INVALID_ARGUMENT);
    assert_null(w);
    wd.narrow_phase = HGCD_NARROW_WORLD; /* per mesh only */
    assert_int_equal(hgcd_world_create(&wd, &w), HGCD_ERROR_INVALID_ARGUMENT);
    wd.narrow_phase = HGCD_NARROW_GJK;
    assert_int_equal(hgcd_world_create(&wd, &w), HGCD_OK);

    /* A convex tetrahedron, a non-convex dented cube. */
    bodies none;
    bodies_init(&none, 1);
    world tw;
    hgcd_world_destroy(w);
    make_world(&tw, &none, HGCD_NARROW_GJK, 0, 1);
    w = tw.w;
    hgcd_mesh_info info;
    info.struct_size = sizeof info;
    assert_int_equal(hgcd_mesh_get_info(w, tw.mesh[SH_TETRA], &info), HGCD_OK);
    assert_int_equal(info.narrow_phase_setting, HGCD_NARROW_WORLD);
    assert_int_equal(info.narrow_phase, HGCD_NARROW_GJK);
    assert_int_equal(hgcd_mesh_get_info(w, tw.mesh[SH_DENTED], &info), HGCD_OK);
    assert_int_equal(info.convex, 0);
    assert_int_equal(info.narrow_phase, HGCD_NARROW_EXACT); /* the world's GJK falls back */

    /* Per mesh: GJK on the non-convex mesh is refused, with the reason. */
    assert_int_equal(hgcd_mesh_set_narrow_phase(w, tw.mesh[SH_DENTED], HGCD_NARROW_GJK),
                     HGCD_ERROR_INVALID_ARGUMENT);
    assert_non_null(strstr(hgcd_world_last_error(w), "not convex"));
    assert_int_equal(hgcd_mesh_set_narrow_phase(w, tw.mesh[SH_DENTED], HGCD_NARROW_MPR),
                     HGCD_ERROR_INVALID_ARGUMENT);
    assert_int_equal(hgcd_mesh_set_narrow_phase(w, tw.mesh[SH_DENTED], HGCD_NARROW_EXACT), HGCD_OK);
    assert_int_equal(hgcd_mesh_set_narrow_phase(w, tw.mesh[SH_DENTED], HGCD_NARROW_WORLD), HGCD_OK);
    assert_int_equal(hgcd_mesh_set_narrow_phase(w, tw.mesh[SH_TETRA], 7), HGCD_ERROR_INVALID_ARGUMENT);
    assert_int_equal(hgcd_mesh_set_narrow_phase(w, tw.mesh[SH_TETRA], HGCD_NARROW_MPR), HGCD_OK);
    assert_int_equal(hgcd_mesh_get_info(w, tw.mesh[SH_TETRA], &info), HGCD_OK);
    assert_int_equal(info.narrow_phase_setting, HGCD_NARROW_MPR);
    assert_int_equal(info.narrow_phase, HGCD_NARROW_MPR);
    const hgcd_mesh stale = {tw.mesh[SH_TETRA].index, tw.mesh[SH_TETRA].generation + 1};
    assert_int_equal(hgcd_mesh_set_narrow_phase(w, stale, HGCD_NARROW_GJK), HGCD_ERROR_STALE_ID);
    assert_int_equal(hgcd_mesh_set_narrow_phase(NULL, tw.mesh[SH_TETRA], HGCD_NARROW_GJK),
                     HGCD_ERROR_NULL_ARGUMENT);
    assert_int_equal(hgcd_world_set_narrow_phase(w, HGCD_NARROW_WORLD), HGCD_ERROR_INVALID_ARGUMENT);
    assert_int_equal(hgcd_world_set_narrow_phase(w, -7), HGCD_ERROR_INVALID_ARGUMENT);
    assert_int_equal(hgcd_world_set_narrow_phase(NULL, HGCD_NARROW_GJK), HGCD_ERROR_NULL_ARGUMENT);
    assert_int_equal(hgcd_world_set_narrow_phase(w, HGCD_NARROW_EXACT), HGCD_OK);
    /* The tetrahedron's own MPR stays; the world's EXACT leaves the cube exact. */
    assert_int_equal(hgcd_mesh_get_info(w, tw.mesh[SH_CUBE], &info), HGCD_OK);
    assert_int_equal(info.narrow_phase, HGCD_NARROW_EXACT);
    assert_int_equal(hgcd_mesh_get_info(w, tw.mesh[SH_TETRA], &info), HGCD_OK);
    assert_int_equal(info.narrow_phase, HGCD_NARROW_MPR);

    /* Contacts: off by default, so the query says there are none recorded. */
    const hgcd_contact *c = (const hgcd_contact *)&info;
    size_t n = 99;
    assert_int_equal(hgcd_world_detect(w), HGCD_OK);
    assert_int_equal(hgcd_world_contacts(w, &c, &n), HGCD_ERROR_INVALID_ARGUMENT);
    assert_null(c);
    assert_int_equal(n, 0);
    assert_int_equal(hgcd_world_contacts(w, NULL, &n), HGCD_ERROR_NULL_ARGUMENT);
    assert_int_equal(hgcd_world_contacts(w, &c, NULL), HGCD_ERROR_NULL_ARGUMENT);
    assert_int_equal(hgcd_world_contacts(NULL, &c, &n), HGCD_ERROR_NULL_ARGUMENT);
    assert_int_equal(hgcd_world_set_contacts(NULL, 1), HGCD_ERROR_NULL_ARGUMENT);
    assert_int_equal(hgcd_world_set_contacts(w, 1), HGCD_OK);
    /* Still the last detect's (made with contacts off) until the next one. */
    assert_int_equal(hgcd_world_contacts(w, &c, &n), HGCD_ERROR_INVALID_ARGUMENT);
    assert_int_equal(hgcd_world_detect(w), HGCD_OK);
    assert_int_equal(hgcd_world_contacts(w, &c, &n), HGCD_OK);
    assert_int_equal(n, 0);
    hgcd_world_destroy(w);
    bodies_free(&none);

    /* A fresh world with contacts on: no detect yet, no contacts. */
    wd = hgcd_world_desc_default();
    wd.contacts = 1;
    assert_int_equal(hgcd_world_create(&wd, &w), HGCD_OK);
    assert_int_equal(hgcd_world_contacts(w, &c, &n), HGCD_OK);
    assert_int_equal(n, 0);
    hgcd_world_destroy(w);
}

/* Scene `tetra` of docs/scenes.md at small n, the cube side shrunk so that the
 * density of the n = 750000 scene is kept. */
static void tetra_scene(bodies *b, uint64_t n, uint64_t seed) {
    hgcd_scene_tetra_desc sd = hgcd_scene_tetra_desc_default();
    sd.n = n;
    sd.seed = seed;
    sd.side = 200 * cbrt((double)n / 750000.0);
    double *c = malloc(3 * n * sizeof(double)), *s = malloc(n * sizeof(double)), *q = malloc(4 * n * sizeof(double));
    assert_int_equal(hgcd_scene_tetra_generate(&sd, c, NULL, s, q, NULL), HGCD_OK);
    bodies_init(b, n);
    for (uint64_t i = 0; i < n; ++i) push(b, SH_TETRA, &c[3 * i], &q[4 * i], s[i]);
    free(c);
    free(s);
    free(q);
}

static void test_tetra_agreement(void **state) {
    (void)state;
    size_t pairs = 0, differ = 0;
    for (uint64_t seed = 1; seed <= 3; ++seed) {
        bodies b;
        tetra_scene(&b, 6000, seed);
        char name[64];
        snprintf(name, sizeof name, "tetra n=6000 seed %llu", (unsigned long long)seed);
        const agreement g = compare(&b, HGCD_NARROW_GJK, 2), m = compare(&b, HGCD_NARROW_MPR, 1);
        report(name, "GJK", &g);
        report(name, "MPR", &m);
        pairs += g.exact_pairs;
        differ += g.false_yes + g.false_no + m.false_yes + m.false_no;
        bodies_free(&b);
    }
    assert_true(pairs > 3000);
    /* Random poses almost never come within 1e-6 of touching. */
    assert_true(differ <= pairs / 1000);
}

static void random_convex_scene(bodies *b, uint64_t seed, size_t n, double side, int fine) {
    rng r = {seed};
    bodies_init(b, n);
    for (size_t i = 0; i < n; ++i) {
        double p[3], q[4];
        for (int k = 0; k < 3; ++k) p[k] = side * unif(&r);
        random_quat(&r, q);
        const uint64_t what = next(&r) % 3;
        const int shape = what == 0 ? SH_TETRA : (fine && what == 1) ? SH_FINE_CUBE : SH_CUBE;
        push(b, shape, p, q, 0.15 + 0.85 * unif(&r));
    }
}

static void test_cube_agreement(void **state) {
    (void)state;
    for (uint64_t seed = 1; seed <= 3; ++seed) {
        bodies b;
        random_convex_scene(&b, seed, 1500, 22, seed == 3);
        char name[64];
        snprintf(name, sizeof name, "cubes+tetra seed %llu%s", (unsigned long long)seed,
                 seed == 3 ? " +fine" : "");
        const agreement g = compare(&b, HGCD_NARROW_GJK, 2), m = compare(&b, HGCD_NARROW_MPR, 2);
        report(name, "GJK", &g);
        report(name, "MPR", &m);
        assert_true(g.exact_pairs > 500);
        bodies_free(&b);
    }
}

/* Random convex pairs brought to touching (bisection with the exact oracle
 * along a random direction, to 1e-13 of the scale), then moved apart or
 * together by f * tol for f in -10 .. 10: the regime where libccd's tolerance
 * matters. Every disagreement must be within the tolerance (flip_factor);
 * the counts per f are printed. */
static void test_near_contact_agreement(void **state) {
    (void)state;
    enum { PAIRS = 150 };
    const double factors[] = {-10, -1, -0.1, -0.01, 0, 0.01, 0.1, 1, 10};
    const size_t nf = sizeof factors / sizeof factors[0];
    rng r = {2024};
    int shape[PAIRS][2];
    double pa[PAIRS][3], qa[PAIRS][4], qb[PAIRS][4], sa[PAIRS], sb[PAIRS], u[PAIRS][3], touch[PAIRS];
    const int convex_shapes[3] = {SH_TETRA, SH_CUBE, SH_FINE_CUBE};
    for (int t = 0; t < PAIRS; ++t) {
        shape[t][0] = convex_shapes[next(&r) % 3];
        shape[t][1] = convex_shapes[next(&r) % 3];
        for (int k = 0; k < 3; ++k) pa[t][k] = 50 + 10.0 * (t % 10) + (k == 1 ? 10.0 * (t / 10) : 0) + unif(&r);
        random_quat(&r, qa[t]);
        random_quat(&r, qb[t]);
        sa[t] = 0.3 + 1.2 * unif(&r);
        sb[t] = 0.3 + 1.2 * unif(&r);
        double n2 = 0;
        for (int k = 0; k < 3; ++k) {
            u[t][k] = unif(&r) - 0.5;
            n2 += u[t][k] * u[t][k];
        }
        for (int k = 0; k < 3; ++k) u[t][k] /= sqrt(n2);
        /* Bisection: at distance lo along u they collide, at hi they do not. */
        bodies two;
        bodies_init(&two, 2);
        push(&two, shape[t][0], pa[t], qa[t], sa[t]);
        push(&two, shape[t][1], pa[t], qb[t], sb[t]);
        double lo = 0, hi = 2 * (sa[t] + sb[t]) * 1.7320508075688772;
        while (hi - lo > 1e-13 * (sa[t] + sb[t])) {
            const double mid = 0.5 * (lo + hi);
            for (int k = 0; k < 3; ++k) two.pos[3 + k] = pa[t][k] + mid * u[t][k];
            if (oracle_pair(&two, 0, 1, sb[t])) lo = mid;
            else hi = mid;
        }
        touch[t] = lo;
        bodies_free(&two);
    }
    printf("near-contact pairs (%d), disagreements per offset f * tol:\n", PAIRS);
    for (int method = HGCD_NARROW_GJK; method <= HGCD_NARROW_MPR; ++method) {
        printf("  %s", method == HGCD_NARROW_GJK ? "GJK" : "MPR");
        double worst = 0;
        for (size_t f = 0; f < nf; ++f) {
            bodies b;
            bodies_init(&b, 2 * PAIRS);
            for (int t = 0; t < PAIRS; ++t) {
                push(&b, shape[t][0], pa[t], qa[t], sa[t]);
                double p[3];
                push(&b, shape[t][1], pa[t], qb[t], sb[t]);
                const double d = touch[t] + factors[f] * pair_tolerance(&b, 2 * (size_t)t, 2 * (size_t)t + 1);
                for (int k = 0; k < 3; ++k) p[k] = pa[t][k] + d * u[t][k];
                memcpy(&b.pos[3 * (2 * (size_t)t + 1)], p, sizeof p);
            }
            const agreement g = compare(&b, method, 2);
            printf("  f=%+g: %zu/%zu", factors[f], g.false_yes + g.false_no, g.exact_pairs);
            if (g.worst_factor > worst) worst = g.worst_factor;
            if (fabs(factors[f]) >= 10) assert_int_equal(g.false_yes + g.false_no, 0);
            bodies_free(&b);
        }
        printf("  (worst flip %.3g tol)\n", worst);
    }
}

/* Pairs of bodies a known distance apart, one pair per case, far apart from
 * each other. gap > 0: apart; gap = 0: touching; gap < 0: overlapping. */
typedef struct {
    const char *what;
    int shape_a, shape_b;
    double offset[3]; /* b's position relative to a's, before the gap */
    double dir[3];    /* unit direction the gap is added along */
    int rotate;       /* b rotated about the contact normal by 30 degrees */
} weak_case;

static void test_weak_spots(void **state) {
    (void)state;
    const weak_case cases[] = {
        {"face on face, stacked", SH_CUBE, SH_CUBE, {0, 0, 2}, {0, 0, 1}, 0},
        {"face on face, shifted", SH_CUBE, SH_CUBE, {0.7, 0.3, 2}, {0, 0, 1}, 0},
        {"face on face, twisted", SH_CUBE, SH_CUBE, {0, 0, 2}, {0, 0, 1}, 1},
        {"fine face on face", SH_FINE_CUBE, SH_FINE_CUBE, {0.5, 0, 2}, {0, 0, 1}, 0},
        {"edge on edge", SH_CUBE, SH_CUBE, {2, 2, 0}, {0.70710678118654752, 0.70710678118654752, 0}, 0},
        {"vertex on vertex", SH_CUBE, SH_CUBE, {2, 2, 2}, {0.57735026918962573, 0.57735026918962573, 0.57735026918962573}, 0},
        {"tetra edge on cube face", SH_CUBE, SH_TETRA, {0, 0, 2}, {0, 0, 1}, 0},
    };
    const double gaps[] = {0, 1e-14, -1e-14, 1e-10, -1e-10, 1e-7, -1e-7, 1e-3, -1e-3, 0.1, -0.1};
    const size_t ncases = sizeof cases / sizeof cases[0], ngaps = sizeof gaps / sizeof gaps[0];
    const double id[4] = {0, 0, 0, 1};
    /* 30 degrees about z. */
    const double twist[4] = {0, 0, 0.25881904510252074, 0.96592582628906831};
    bodies b;
    bodies_init(&b, 2 * ncases * ngaps);
    for (size_t c = 0; c < ncases; ++c)
        for (size_t g = 0; g < ngaps; ++g) {
            /* Away from the origin, as the tetra scene's bodies are. */
            const double base[3] = {100 + 10.0 * (double)c, 100 + 10.0 * (double)g, 100};
            double pb[3];
            for (int k = 0; k < 3; ++k) pb[k] = base[k] + cases[c].offset[k] + gaps[g] * cases[c].dir[k];
            push(&b, cases[c].shape_a, base, id, 1);
            double sb = 1;
            if (cases[c].shape_b == SH_TETRA) {
                /* The tetrahedron's lowest edge (z = -s) on the cube's top (z = 1). */
                sb = 0.5;
                pb[2] = base[2] + 1 + 0.5 + gaps[g];
            }
            push(&b, cases[c].shape_b, pb, cases[c].rotate ? twist : id, sb);
        }
    for (int method = HGCD_NARROW_GJK; method <= HGCD_NARROW_MPR; ++method) {
        world ex, cc;
        make_world(&ex, &b, HGCD_NARROW_EXACT, 0, 1);
        make_world(&cc, &b, method, 0, 1);
        size_t ne, nc;
        uint64_t *e = pair_keys(ex.w, &ne), *k = pair_keys(cc.w, &nc);
        printf("%s, answers per gap (E exact, L libccd; 1 = collide):\n", method == HGCD_NARROW_GJK ? "GJK" : "MPR");
        for (size_t c = 0; c < ncases; ++c) {
            printf("  %-24s", cases[c].what);
            for (size_t g = 0; g < ngaps; ++g) {
                const size_t i = 2 * (c * ngaps + g), j = i + 1;
                const uint64_t key = (uint64_t)i << 32 | j;
                int in_e = 0, in_c = 0;
                for (size_t t = 0; t < ne; ++t) in_e |= e[t] == key;
                for (size_t t = 0; t < nc; ++t) in_c |= k[t] == key;
                /* The exact answer is the geometry's, wherever the gap is representable. */
                if (gaps[g] <= 0 && fabs(gaps[g]) != 1e-14) assert_int_equal(in_e, 1);
                if (gaps[g] >= 1e-10) assert_int_equal(in_e, 0);
                printf(" %+.0e:E%dL%d", gaps[g], in_e, in_c);
                const double tol = pair_tolerance(&b, i, j);
                if (fabs(gaps[g]) >= 1000 * tol) {
                    assert_int_equal(in_c, in_e); /* far beyond the tolerance: must agree */
                } else if (in_c != in_e) {
                    assert_true(flip_factor(&b, i, j, in_c) > 0);
                }
            }
            printf("\n");
        }
        free(e);
        free(k);
        hgcd_world_destroy(ex.w);
        hgcd_world_destroy(cc.w);
    }
    bodies_free(&b);
}

/* World vertices of body i of b, as hgcd.h defines them. */
static double *world_verts(const bodies *b, size_t i) {
    const oracle_mesh *m = &shapes[b->shape[i]];
    double *w = malloc(3 * m->vertex_count * sizeof(double));
    for (uint32_t v = 0; v < m->vertex_count; ++v)
        oracle_world_vertex(&b->pos[3 * i], &b->quat[4 * i], b->scale[i], &m->verts[3 * v], &w[3 * v]);
    return w;
}

static int surfaces_meet(const bodies *b, size_t i, size_t j) {
    const oracle_mesh *mi = &shapes[b->shape[i]], *mj = &shapes[b->shape[j]];
    double *wi = world_verts(b, i), *wj = world_verts(b, j);
    int meet = 0;
    for (uint32_t s = 0; s < mi->triangle_count && !meet; ++s)
        for (uint32_t t = 0; t < mj->triangle_count && !meet; ++t) {
            double p[9], q[9];
            for (int k = 0; k < 3; ++k) {
                memcpy(&p[3 * k], &wi[3 * mi->tris[3 * s + k]], 3 * sizeof(double));
                memcpy(&q[3 * k], &wj[3 * mj->tris[3 * t + k]], 3 * sizeof(double));
            }
            meet = hgcdi_tri_tri(p, q);
        }
    free(wi);
    free(wj);
    return meet;
}

/* Some vertex of body inner lies inside the closed mesh of body outer. */
static int holds_a_vertex(const bodies *b, size_t outer, size_t inner) {
    const oracle_mesh *mo = &shapes[b->shape[outer]], *mi = &shapes[b->shape[inner]];
    double *wo = world_verts(b, outer), *wi = world_verts(b, inner);
    int inside = 0;
    for (uint32_t v = 0; v < mi->vertex_count && !inside; ++v)
        inside = hgcdi_point_in_closed_mesh(&wi[3 * v], wo, mo->vertex_count, mo->tris, mo->triangle_count);
    free(wo);
    free(wi);
    return inside;
}

static void test_exact_contacts(void **state) {
    (void)state;
    rng r = {42};
    bodies b;
    bodies_init(&b, 700);
    const double id[4] = {0, 0, 0, 1}, o[3] = {-10, -10, -10}, o2[3] = {-20, -20, -20};
    push(&b, SH_CUBE, o, id, 3);         /* 0 holds 1: A_CONTAINS_B */
    push(&b, SH_TETRA, o, id, 0.5);      /* 1 */
    push(&b, SH_TETRA, o2, id, 0.5);     /* 2 is held by 3: B_CONTAINS_A */
    push(&b, SH_DENTED, o2, id, 3);      /* 3 */
    for (size_t i = 4; i < b.cap; ++i) {
        double p[3], q[4];
        for (int k = 0; k < 3; ++k) p[k] = 25 * unif(&r);
        random_quat(&r, q);
        push(&b, (int)(next(&r) % SH_COUNT), p, q, 0.1 + 2.5 * unif(&r) * unif(&r));
    }
    world plain, w1, w3;
    make_world(&plain, &b, HGCD_NARROW_EXACT, 0, 2);
    make_world(&w1, &b, HGCD_NARROW_EXACT, 1, 1);
    make_world(&w3, &b, HGCD_NARROW_EXACT, 1, 3);
    size_t np, n1, n3;
    uint64_t *kp = pair_keys(plain.w, &np), *k1 = pair_keys(w1.w, &n1);
    assert_int_equal(np, n1);
    assert_memory_equal(kp, k1, np * sizeof(uint64_t)); /* contacts do not change the pairs */
    const hgcd_contact *c1, *c3;
    assert_int_equal(hgcd_world_contacts(w1.w, &c1, &n1), HGCD_OK);
    assert_int_equal(hgcd_world_contacts(w3.w, &c3, &n3), HGCD_OK);
    assert_int_equal(n1, np);
    assert_int_equal(n3, np);
    for (size_t k = 0; k < np; ++k) { /* nor does the thread count (ids carry a per-world tag) */
        hgcd_contact x = c1[k], y = c3[k];
        x.pair.a.generation = x.pair.b.generation = y.pair.a.generation = y.pair.b.generation = 0;
        assert_memory_equal(&x, &y, sizeof x);
    }
    const hgcd_pair *pairs;
    assert_int_equal(hgcd_world_pairs(w1.w, &pairs, &np), HGCD_OK);
    size_t kinds[5] = {0, 0, 0, 0, 0}, fine = 0;
    for (size_t k = 0; k < np; ++k) {
        const hgcd_contact *c = &c1[k];
        assert_memory_equal(&c->pair, &pairs[k], sizeof(hgcd_pair));
        const size_t i = c->pair.a.index, j = c->pair.b.index;
        assert_true(c->kind >= HGCD_CONTACT_SURFACE && c->kind <= HGCD_CONTACT_B_CONTAINS_A);
        ++kinds[c->kind];
        assert_int_equal(c->reserved, 0);
        assert_true(c->depth == 0 && c->normal[0] == 0 && c->point[2] == 0);
        if (c->kind == HGCD_CONTACT_SURFACE) {
            const oracle_mesh *mi = &shapes[b.shape[i]], *mj = &shapes[b.shape[j]];
            assert_true(c->triangle_a < mi->triangle_count);
            assert_true(c->triangle_b < mj->triangle_count);
            double *wi = world_verts(&b, i), *wj = world_verts(&b, j), p[9], q[9];
            for (int v = 0; v < 3; ++v) {
                memcpy(&p[3 * v], &wi[3 * mi->tris[3 * c->triangle_a + v]], 3 * sizeof(double));
                memcpy(&q[3 * v], &wj[3 * mj->tris[3 * c->triangle_b + v]], 3 * sizeof(double));
            }
            assert_int_equal(hgcdi_tri_tri(p, q), 1); /* the witness triangles meet */
            assert_int_equal(oracle_tri_tri(p, q), 1);
            fine += b.shape[i] == SH_FINE_CUBE || b.shape[j] == SH_FINE_CUBE;
            free(wi);
            free(wj);
        } else {
            assert_int_equal(c->triangle_a, UINT32_MAX);
            assert_int_equal(c->triangle_b, UINT32_MAX);
            assert_false(surfaces_meet(&b, i, j));
            if (c->kind == HGCD_CONTACT_A_CONTAINS_B) assert_true(holds_a_vertex(&b, i, j));
            else assert_true(holds_a_vertex(&b, j, i));
        }
    }
    printf("%zu contacts: %zu surface (%zu with the 192-triangle cube), %zu a holds b, %zu b holds a\n", np,
           kinds[HGCD_CONTACT_SURFACE], fine, kinds[HGCD_CONTACT_A_CONTAINS_B], kinds[HGCD_CONTACT_B_CONTAINS_A]);
    assert_true(kinds[HGCD_CONTACT_SURFACE] > 100 && fine > 10);
    assert_true(kinds[HGCD_CONTACT_A_CONTAINS_B] >= 1 && kinds[HGCD_CONTACT_B_CONTAINS_A] >= 1);
    assert_int_equal(pairs[0].a.index, 0);
    assert_int_equal(pairs[0].b.index, 1);
    assert_int_equal(c1[0].kind, HGCD_CONTACT_A_CONTAINS_B);
    free(kp);
    free(k1);
    hgcd_world_destroy(plain.w);
    hgcd_world_destroy(w1.w);
    hgcd_world_destroy(w3.w);
    bodies_free(&b);
}

static void test_penetration(void **state) {
    (void)state;
    /* Cube a = [-1, 1]^3 at the origin; cube b (same size) moved so that the
     * overlap is smallest along one axis: that is the penetration. */
    const struct {
        double pos[3], depth, normal[3];
        int mpr; /* MPR's estimate is checked too (it follows the centre line) */
    } cases[] = {
        {{1.5, 0, 0}, 0.5, {1, 0, 0}, 1},      {{0, -1.8, 0}, 0.2, {0, -1, 0}, 1},
        {{0, 0, 1.99}, 0.01, {0, 0, 1}, 1},    {{0.3, 0.2, 1.9}, 0.1, {0, 0, 1}, 0},
        {{-1.2, 0.5, -0.4}, 0.8, {-1, 0, 0}, 0},
    };
    const size_t n = sizeof cases / sizeof cases[0];
    const double id[4] = {0, 0, 0, 1};
    bodies b;
    bodies_init(&b, 2 * n);
    for (size_t k = 0; k < n; ++k) {
        const double base[3] = {50.0 * (double)k, 7, -3};
        double p[3];
        for (int d = 0; d < 3; ++d) p[d] = base[d] + cases[k].pos[d];
        push(&b, SH_CUBE, base, id, 1);
        push(&b, SH_CUBE, p, id, 1);
    }
    for (int method = HGCD_NARROW_GJK; method <= HGCD_NARROW_MPR; ++method) {
        world w;
        make_world(&w, &b, method, 1, 2);
        const hgcd_contact *c;
        size_t count;
        assert_int_equal(hgcd_world_contacts(w.w, &c, &count), HGCD_OK);
        assert_int_equal(count, n);
        for (size_t k = 0; k < n; ++k) {
            assert_int_equal(c[k].pair.a.index, 2 * k);
            assert_int_equal(c[k].pair.b.index, 2 * k + 1);
            assert_int_equal(c[k].kind, HGCD_CONTACT_PENETRATION);
            assert_int_equal(c[k].triangle_a, UINT32_MAX);
            const double len = sqrt(c[k].normal[0] * c[k].normal[0] + c[k].normal[1] * c[k].normal[1] +
                                    c[k].normal[2] * c[k].normal[2]);
            const double dot = c[k].normal[0] * cases[k].normal[0] + c[k].normal[1] * cases[k].normal[1] +
                               c[k].normal[2] * cases[k].normal[2];
            printf("%s case %zu: depth %.9f (true %.3f) normal (%.6f %.6f %.6f) point (%.4f %.4f %.4f)\n",
                   method == HGCD_NARROW_GJK ? "GJK/EPA" : "MPR", k, c[k].depth, cases[k].depth, c[k].normal[0],
                   c[k].normal[1], c[k].normal[2], c[k].point[0] - 50.0 * (double)k, c[k].point[1] - 7,
                   c[k].point[2] + 3);
            assert_true(fabs(len - 1) < 1e-9);
            /* libccd's contact position: near the contact, not always in the
             * overlap (hgcd.h); at least within the box of both cubes. */
            for (int d = 0; d < 3; ++d) {
                const double lo = fmin(b.pos[6 * k + d], b.pos[6 * k + 3 + d]) - 1,
                             hi = fmax(b.pos[6 * k + d], b.pos[6 * k + 3 + d]) + 1;
                assert_true(c[k].point[d] >= lo && c[k].point[d] <= hi);
            }
            if (method == HGCD_NARROW_GJK || cases[k].mpr) {
                assert_true(fabs(c[k].depth - cases[k].depth) <= 1e-6);
                assert_true(dot > 1 - 1e-9);
            } else {
                /* MPR: a penetration along its own direction, no shallower than the true one. */
                assert_true(dot > 0);
                assert_true(c[k].depth >= cases[k].depth - 1e-6 && c[k].depth <= 2);
            }
        }
        hgcd_world_destroy(w.w);
    }
    bodies_free(&b);
}

static void test_mixed_fallback(void **state) {
    (void)state;
    /* A GJK world with non-convex meshes: their pairs take the exact path
     * (counted), the pairs of two convex meshes take libccd, and the result
     * equals the exact world's except within the tolerance. */
    rng r = {5};
    bodies b;
    bodies_init(&b, 800);
    for (size_t i = 0; i < b.cap; ++i) {
        double p[3], q[4];
        for (int k = 0; k < 3; ++k) p[k] = 20 * unif(&r);
        random_quat(&r, q);
        push(&b, (int)(next(&r) % SH_COUNT), p, q, 0.2 + 0.8 * unif(&r));
    }
    world ex, cc;
    make_world(&ex, &b, HGCD_NARROW_EXACT, 0, 2);
    make_world(&cc, &b, HGCD_NARROW_GJK, 1, 2);
    hgcd_stats se, sc;
    se.struct_size = sc.struct_size = sizeof se;
    assert_int_equal(hgcd_world_stats(ex.w, &se), HGCD_OK);
    assert_int_equal(hgcd_world_stats(cc.w, &sc), HGCD_OK);
    printf("GJK world with non-convex meshes: %llu libccd tests, %llu fallback (exact) tests, %llu exact tests; "
           "%llu pairs (exact world %llu)\n",
           (unsigned long long)sc.libccd_tests, (unsigned long long)sc.libccd_fallback_tests,
           (unsigned long long)sc.narrow_tests, (unsigned long long)sc.colliding_pairs,
           (unsigned long long)se.colliding_pairs);
    assert_true(sc.libccd_tests > 0 && sc.libccd_fallback_tests > 0);
    assert_int_equal(se.libccd_tests, 0);
    assert_int_equal(se.libccd_fallback_tests, 0);
    const hgcd_contact *c;
    size_t n;
    assert_int_equal(hgcd_world_contacts(cc.w, &c, &n), HGCD_OK);
    size_t pen = 0;
    for (size_t k = 0; k < n; ++k) {
        const int convex_pair = b.shape[c[k].pair.a.index] <= SH_FINE_CUBE && b.shape[c[k].pair.b.index] <= SH_FINE_CUBE;
        assert_int_equal(c[k].kind == HGCD_CONTACT_PENETRATION, convex_pair);
        pen += convex_pair;
    }
    assert_true(pen > 0 && pen < n);
    /* Per mesh: the cube back to exact; then its pairs leave libccd. */
    assert_int_equal(hgcd_mesh_set_narrow_phase(cc.w, cc.mesh[SH_CUBE], HGCD_NARROW_EXACT), HGCD_OK);
    assert_int_equal(hgcd_world_detect(cc.w), HGCD_OK);
    assert_int_equal(hgcd_world_contacts(cc.w, &c, &n), HGCD_OK);
    for (size_t k = 0; k < n; ++k)
        if (b.shape[c[k].pair.a.index] == SH_CUBE || b.shape[c[k].pair.b.index] == SH_CUBE)
            assert_int_not_equal(c[k].kind, HGCD_CONTACT_PENETRATION);
    hgcd_world_destroy(ex.w);
    hgcd_world_destroy(cc.w);
    bodies_free(&b);
}

int main(void) {
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_feature_and_refusals), cmocka_unit_test(test_tetra_agreement),
        cmocka_unit_test(test_cube_agreement),       cmocka_unit_test(test_near_contact_agreement),
        cmocka_unit_test(test_weak_spots),
        cmocka_unit_test(test_exact_contacts),       cmocka_unit_test(test_penetration),
        cmocka_unit_test(test_mixed_fallback),
    };
    /* Valgrind and sanitizer runs pick tests by name (cmocka patterns). */
    if (getenv("HGCD_TEST_FILTER")) cmocka_set_test_filter(getenv("HGCD_TEST_FILTER"));
    if (getenv("HGCD_TEST_SKIP")) cmocka_set_skip_filter(getenv("HGCD_TEST_SKIP"));
    return cmocka_run_group_tests(tests, setup, NULL);
}
