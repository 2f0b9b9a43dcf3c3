/* The contact margin: the exact "triangles within distance d" predicate
 * (src/exact/distance.cpp) and whole worlds with margins, against the GMP
 * oracle's exact rational distances (oracle_distance.c), on random and
 * hand-built degenerate cases. */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#ifndef M_PI
#define M_PI 3.14159265358979323846
#endif

#include "hgcd/hgcd.h"
#include "oracle.h"
#include "support/testing.h"
#include "test_rng.h"

static long iters(long n) { return getenv("HGCD_SKIP_SLOW_TESTS") ? n / 4 : n; }

static void set_tri(double *t, double ax, double ay, double az, double bx, double by, double bz, double cx,
                    double cy, double cz) {
    const double v[9] = {ax, ay, az, bx, by, bz, cx, cy, cz};
    memcpy(t, v, sizeof v);
}

/* The library against the oracle for one pair and d, both argument orders
 * and every vertex rotation of p. */
static void check_within(const double *p, const double *q, double d) {
    const int want = oracle_tri_tri_within(p, q, d);
    int r;
    for (r = 0; r < 3; r++) {
        double pr[9];
        int i;
        for (i = 0; i < 9; i++) pr[i] = p[(3 * r + i) % 9];
        if (hgcdi_tri_tri_within(pr, q, d) != want || hgcdi_tri_tri_within(q, pr, d) != want) {
            fprintf(stderr, "d = %a, oracle %d\np:", d, want);
            for (i = 0; i < 9; i++) fprintf(stderr, " %a", p[i]);
            fprintf(stderr, "\nq:");
            for (i = 0; i < 9; i++) fprintf(stderr, " %a", q[i]);
            fprintf(stderr, "\n");
            fail_msg("tri_tri_within differs from the oracle");
        }
    }
}

/* The least double d the oracle finds the pair within (the pair's distance
 * rounded up to a double), by bisection on the bit patterns of doubles. */
static double threshold(const double *p, const double *q) {
    uint64_t lo = 0, hi = 0x7FF0000000000000ull; /* d = 0 .. inf */
    double x;
    if (oracle_tri_tri_within(p, q, 0)) return 0;
    while (hi - lo > 1) {
        const uint64_t mid = lo + (hi - lo) / 2;
        memcpy(&x, &mid, sizeof x);
        if (oracle_tri_tri_within(p, q, x)) hi = mid;
        else lo = mid;
    }
    memcpy(&x, &hi, sizeof x);
    return x;
}

/* Each pair at its exact threshold and one double below and above. */
static void check_at_threshold(const double *p, const double *q) {
    const double t = threshold(p, q);
    int hits = 0;
    check_within(p, q, t);
    if (t > 0) check_within(p, q, nextafter(t, 0));
    check_within(p, q, nextafter(t, INFINITY));
    hits += hgcdi_tri_tri_within(p, q, t);
    assert_int_equal(hits, 1); /* the threshold itself is within */
    if (t > 0) assert_int_equal(hgcdi_tri_tri_within(p, q, nextafter(t, 0)), 0);
}

/* Hand-built cases whose distance is known: vertex-face, edge-edge skew and
 * parallel, face-face parallel, degenerate triangles, each at distance h. */
static void test_known_distances(void **state) {
    const double hs[] = {1.0, 0.5, 0x1p-30, 3.0, 1e-300, 0x1p40};
    size_t i;
    (void)state;
    for (i = 0; i < sizeof hs / sizeof *hs; i++) {
        const double h = hs[i], below = nextafter(h, 0), above = nextafter(h, INFINITY);
        double p[9], q[9];
        /* vertex over a face */
        set_tri(p, 0, 0, 0, 4, 0, 0, 0, 4, 0);
        set_tri(q, 1, 1, h, 9, 9, h + 9, 8, 9, h + 9);
        assert_int_equal(hgcdi_tri_tri_within(p, q, h), 1);
        assert_int_equal(hgcdi_tri_tri_within(p, q, below), 0);
        check_within(p, q, h), check_within(p, q, below), check_within(p, q, above);
        /* skew edges: along x at z = 0 and along y at z = h */
        set_tri(p, -1, 0, 0, 1, 0, 0, 0, 0, -5);
        set_tri(q, 0, -1, h, 0, 1, h, 0, 0, h + 5);
        assert_int_equal(hgcdi_tri_tri_within(p, q, h), 1);
        assert_int_equal(hgcdi_tri_tri_within(p, q, below), 0);
        check_within(p, q, h), check_within(p, q, below), check_within(p, q, above);
        /* parallel edges, overlapping in x */
        set_tri(p, 0, 0, 0, 2, 0, 0, 1, 0, -5);
        set_tri(q, 1, 0, h, 3, 0, h, 2, 0, h + 5);
        assert_int_equal(hgcdi_tri_tri_within(p, q, h), 1);
        assert_int_equal(hgcdi_tri_tri_within(p, q, below), 0);
        check_within(p, q, h), check_within(p, q, below), check_within(p, q, above);
        /* parallel faces */
        set_tri(p, 0, 0, 0, 2, 0, 0, 0, 2, 0);
        set_tri(q, 0.5, 0.5, h, 2.5, 0.5, h, 0.5, 2.5, h);
        assert_int_equal(hgcdi_tri_tri_within(p, q, h), 1);
        assert_int_equal(hgcdi_tri_tri_within(p, q, below), 0);
        check_within(p, q, h), check_within(p, q, below), check_within(p, q, above);
        /* a point (all vertices equal) over a segment (collinear) */
        set_tri(p, 0, 0, 0, 1, 0, 0, 2, 0, 0);
        set_tri(q, 1.5, h, 0, 1.5, h, 0, 1.5, h, 0);
        assert_int_equal(hgcdi_tri_tri_within(p, q, h), 1);
        assert_int_equal(hgcdi_tri_tri_within(p, q, below), 0);
        check_within(p, q, h), check_within(p, q, below), check_within(p, q, above);
        /* two points */
        set_tri(p, 0, 0, 0, 0, 0, 0, 0, 0, 0);
        set_tri(q, 0, 0, h, 0, 0, h, 0, 0, h);
        assert_int_equal(hgcdi_tri_tri_within(p, q, h), 1);
        assert_int_equal(hgcdi_tri_tri_within(p, q, below), 0);
        check_within(p, q, h), check_within(p, q, below), check_within(p, q, above);
    }
    /* Distance sqrt(2): a vertex off a face's corner diagonally. Not a
     * double: the threshold search finds the double above it. */
    {
        double p[9], q[9];
        set_tri(p, 0, 0, 0, 4, 0, 0, 0, 4, 0);
        set_tri(q, -1, -1, 0, -7, -1, 0, -1, -9, 3);
        check_at_threshold(p, q);
    }
}

/* Random pairs on a coarse lattice (many degeneracies: shared planes,
 * parallel edges, repeated vertices) and in general position, rotated, at a
 * random d and at their exact threshold. */
static void test_random_pairs(void **state) {
    rng r = {42};
    long n = iters(2000), k;
    (void)state;
    for (k = 0; k < n; k++) {
        double p[9], q[9];
        int i;
        const int lattice = k % 2 == 0;
        for (i = 0; i < 9; i++) {
            if (lattice) {
                p[i] = (double)(int)(next(&r) % 5);
                q[i] = (double)(int)(next(&r) % 5) + (i % 3 == 2 ? 1.0 : 0.0);
            } else {
                p[i] = 4 * unif(&r);
                q[i] = 4 * unif(&r) + (i % 3 == 2 ? 2.0 : 0.0);
            }
        }
        if (next(&r) % 8 == 0) memcpy(q + 3, q, 3 * sizeof(double)); /* degenerate */
        if (next(&r) % 8 == 0) memcpy(p + 6, p + 3, 3 * sizeof(double));
        check_within(p, q, 0);
        check_within(p, q, 3 * unif(&r));
        check_within(p, q, (double)(int)(next(&r) % 4));
        if (k % 10 == 0) check_at_threshold(p, q);
    }
}

/* ------------------------------------------------------------------------ */
/* Worlds with margins                                                       */
/* ------------------------------------------------------------------------ */

enum { kShapes = 5, kBodies = 36, kSphereLat = 5, kSphereLon = 10 };

static const double tetra_v[] = {1, 1, 1, 1, -1, -1, -1, 1, -1, -1, -1, 1};
static const uint32_t tetra_t[] = {0, 1, 2, 0, 3, 1, 0, 2, 3, 1, 3, 2};
static const double cube_v[] = {-1, -1, -1, 1, -1, -1, 1, 1, -1, -1, 1, -1,
                                -1, -1, 1,  1, -1, 1,  1, 1, 1,  -1, 1, 1};
static const uint32_t cube_t[] = {0, 2, 1, 0, 3, 2, 0, 1, 5, 0, 5, 4, 1, 2, 6, 1, 6, 5,
                                  2, 3, 7, 2, 7, 6, 3, 0, 4, 3, 4, 7, 4, 5, 6, 4, 6, 7};
/* An open sheet with a zero-area triangle (collinear) and a point triangle. */
static const double sheet_v[] = {-1.5, -1, 0, 1.5, -1, 0.25, 0, 1.5, -0.25, 0.5, 0.5, 0.5, 1, 1, 1};
static const uint32_t sheet_t[] = {0, 1, 2, 2, 3, 4, 4, 4, 4};
static double sphere_v[3 * (2 + (kSphereLat - 1) * kSphereLon)];
static uint32_t sphere_t[3 * 2 * kSphereLon * (kSphereLat - 1)];

static oracle_mesh shapes[kShapes];

/* A closed latitude-longitude sphere of more than 48 triangles (a tree). */
static void make_sphere(void) {
    int i, j, n = 0, t = 0;
    sphere_v[n++] = 0, sphere_v[n++] = 0, sphere_v[n++] = 1;
    for (i = 1; i < kSphereLat; i++)
        for (j = 0; j < kSphereLon; j++) {
            const double th = M_PI * i / kSphereLat, ph = 2 * M_PI * j / kSphereLon;
            sphere_v[n++] = sin(th) * cos(ph), sphere_v[n++] = sin(th) * sin(ph), sphere_v[n++] = cos(th);
        }
    sphere_v[n++] = 0, sphere_v[n++] = 0, sphere_v[n++] = -1;
    for (j = 0; j < kSphereLon; j++) {
        const uint32_t a = 1 + j, b = 1 + (j + 1) % kSphereLon;
        sphere_t[t++] = 0, sphere_t[t++] = a, sphere_t[t++] = b;
    }
    for (i = 0; i + 2 < kSphereLat; i++)
        for (j = 0; j < kSphereLon; j++) {
            const uint32_t a = 1 + i * kSphereLon + j, b = 1 + i * kSphereLon + (j + 1) % kSphereLon;
            const uint32_t c = a + kSphereLon, d = b + kSphereLon;
            sphere_t[t++] = a, sphere_t[t++] = c, sphere_t[t++] = b;
            sphere_t[t++] = b, sphere_t[t++] = c, sphere_t[t++] = d;
        }
    {
        const uint32_t south = 1 + (kSphereLat - 1) * kSphereLon, ring = 1 + (kSphereLat - 2) * kSphereLon;
        for (j = 0; j < kSphereLon; j++) {
            sphere_t[t++] = ring + j, sphere_t[t++] = south, sphere_t[t++] = ring + (j + 1) % kSphereLon;
        }
    }
    shapes[0] = (oracle_mesh){tetra_v, tetra_t, 4, 4, 1};
    shapes[1] = (oracle_mesh){cube_v, cube_t, 8, 12, 1};
    shapes[2] = (oracle_mesh){sheet_v, sheet_t, 5, 3, 0};
    shapes[3] = (oracle_mesh){sphere_v, sphere_t, (uint32_t)(n / 3), (uint32_t)(t / 3), 1};
    shapes[4] = shapes[0];
}

typedef struct {
    hgcd_world *w;
    hgcd_mesh mesh[kShapes];
    int count, shape[kBodies];
    hgcd_body id[kBodies];
    double pos[kBodies][3], quat[kBodies][4], scale[kBodies], margin[kBodies];
    double world_margin;
} scene;

static int scene_init(scene *m, double world_margin, uint32_t threads, int32_t narrow, uint32_t contacts) {
    hgcd_world_desc wd = hgcd_world_desc_default();
    int k;
    memset(m, 0, sizeof *m);
    wd.contact_margin = world_margin;
    wd.thread_count = threads;
    wd.thread_policy = HGCD_THREADS_FIXED;
    wd.narrow_phase = narrow;
    wd.contacts = contacts;
    m->world_margin = world_margin;
    if (hgcd_world_create(&wd, &m->w) != HGCD_OK) return 0;
    for (k = 0; k < kShapes; ++k) {
        hgcd_mesh_desc md = hgcd_mesh_desc_default();
        md.vertices = shapes[k].verts;
        md.triangles = shapes[k].tris;
        md.vertex_count = shapes[k].vertex_count;
        md.triangle_count = shapes[k].triangle_count;
        assert_int_equal(hgcd_mesh_create(m->w, &md, &m->mesh[k]), HGCD_OK);
    }
    return 1;
}

static void scene_add(scene *m, int shape, const double *p, const double *q, double scale, double margin) {
    hgcd_body_desc bd = hgcd_body_desc_default();
    const int i = m->count++;
    bd.mesh = m->mesh[shape];
    memcpy(bd.position, p, 3 * sizeof(double));
    memcpy(bd.orientation, q, 4 * sizeof(double));
    bd.scale = scale;
    bd.margin = margin;
    assert_int_equal(hgcd_body_create(m->w, &bd, &m->id[i]), HGCD_OK);
    assert_int_equal(m->id[i].index, (uint32_t)i);
    m->shape[i] = shape;
    memcpy(m->pos[i], p, sizeof m->pos[i]);
    memcpy(m->quat[i], q, sizeof m->quat[i]);
    m->scale[i] = scale;
    m->margin[i] = margin;
}

/* Detects and compares the pairs with the oracle's; with contacts, checks
 * each pair's kind against the oracle too. Returns the pair count. */
static size_t scene_check(scene *m, int contacts) {
    const oracle_mesh *meshes[kBodies];
    uint32_t want[2 * kBodies * kBodies];
    const hgcd_pair *pairs;
    size_t count, n, k;
    int i;
    for (i = 0; i < m->count; i++) meshes[i] = &shapes[m->shape[i]];
    n = oracle_pairs_within((size_t)m->count, meshes, &m->pos[0][0], &m->quat[0][0], m->scale, m->world_margin,
                            m->margin, want, kBodies * kBodies);
    assert_int_equal(hgcd_world_detect(m->w), HGCD_OK);
    assert_int_equal(hgcd_world_pairs(m->w, &pairs, &count), HGCD_OK);
    if (count != n) fprintf(stderr, "hgcd %zu pairs, oracle %zu\n", count, n);
    assert_int_equal(count, n);
    for (k = 0; k < n; k++) {
        assert_int_equal(pairs[k].a.index, want[2 * k]);
        assert_int_equal(pairs[k].b.index, want[2 * k + 1]);
    }
    if (contacts) {
        const hgcd_contact *c;
        size_t cc;
        assert_int_equal(hgcd_world_contacts(m->w, &c, &cc), HGCD_OK);
        assert_int_equal(cc, count);
        for (k = 0; k < cc; k++) {
            const int a = (int)c[k].pair.a.index, b = (int)c[k].pair.b.index;
            const oracle_mesh *two[2] = {meshes[a], meshes[b]};
            double pos[6], ori[8], sc[2] = {m->scale[a], m->scale[b]};
            uint32_t pr[2];
            int touch;
            memcpy(pos, m->pos[a], 3 * sizeof(double)), memcpy(pos + 3, m->pos[b], 3 * sizeof(double));
            memcpy(ori, m->quat[a], 4 * sizeof(double)), memcpy(ori + 4, m->quat[b], 4 * sizeof(double));
            touch = oracle_colliding_pairs(2, two, pos, ori, sc, pr, 1) > 0;
            if (c[k].kind == HGCD_CONTACT_NEAR) {
                /* apart, and the witness triangles within d */
                double P[9], Q[9], wa[3], wb[3];
                const double d = oracle_pair_margin(m->world_margin, m->margin[a], m->margin[b]);
                int v;
                assert_int_equal(touch, 0);
                for (v = 0; v < 3; v++) {
                    oracle_world_vertex(m->pos[a], m->quat[a], m->scale[a],
                                        meshes[a]->verts + 3 * meshes[a]->tris[3 * c[k].triangle_a + v], wa);
                    oracle_world_vertex(m->pos[b], m->quat[b], m->scale[b],
                                        meshes[b]->verts + 3 * meshes[b]->tris[3 * c[k].triangle_b + v], wb);
                    memcpy(P + 3 * v, wa, sizeof wa), memcpy(Q + 3 * v, wb, sizeof wb);
                }
                assert_int_equal(oracle_tri_tri_within(P, Q, d), 1);
            } else {
                assert_int_equal(touch, 1);
            }
        }
    }
    return count;
}

static void random_scene(scene *m, rng *r, double side) {
    int i;
    for (i = 0; i < kBodies; i++) {
        double p[3], q[4];
        const int shape = (int)(next(r) % 8) < 1 ? 3 : (int)(next(r) % 3) + (next(r) % 4 == 0);
        int k;
        for (k = 0; k < 3; k++) p[k] = side * unif(r);
        random_unit_quaternion(r, q);
        scene_add(m, shape == 3 && i % 3 ? 0 : shape, p, q, 0.4 + 0.6 * unif(r),
                  next(r) % 2 ? 0 : 0.25 * unif(r));
    }
}

/* Random scenes with world and body margins, through every narrow path
 * (tetrahedra, convex, direct, tree, libccd asked for, contacts), at 1 and
 * 2 threads, detected again after moves and margin changes. */
static void test_scenes(void **state) {
    const double world_margins[] = {0, 0.05, 0.3};
    const int32_t narrow[] = {HGCD_NARROW_EXACT, HGCD_NARROW_GJK};
    int wmi, ni, threads, seed, nonempty = 0;
    (void)state;
    for (seed = 0; seed < 1; seed++)
        for (wmi = 0; wmi < 3; wmi++)
            for (ni = 0; ni < 2; ni++)
                for (threads = 1; threads <= 2; threads++) {
                    const int contacts = (seed + threads + ni) % 2;
                    rng r = {(uint64_t)(1000 * seed + 10 * wmi + ni + 1)};
                    scene m;
                    int round;
                    if (!scene_init(&m, world_margins[wmi], (uint32_t)threads, narrow[ni], (uint32_t)contacts)) {
                        assert_int_equal(ni, 1); /* (built without libccd) */
                        continue;
                    }
                    random_scene(&m, &r, 5.0);
                    nonempty += scene_check(&m, contacts) > 0;
                    for (round = 0; round < (getenv("HGCD_SKIP_SLOW_TESTS") ? 1 : 2); round++) {
                        int k;
                        for (k = 0; k < 6; k++) {
                            const int i = (int)(next(&r) % kBodies);
                            if (k % 2) {
                                m.margin[i] = next(&r) % 3 ? 0.2 * unif(&r) : 0;
                                assert_int_equal(hgcd_body_set_margin(m.w, m.id[i], m.margin[i]), HGCD_OK);
                            } else {
                                m.pos[i][0] += 0.1 * (unif(&r) - 0.5);
                                assert_int_equal(hgcd_body_set_pose(m.w, m.id[i], m.pos[i], NULL), HGCD_OK);
                            }
                        }
                        scene_check(&m, contacts);
                    }
                    hgcd_world_destroy(m.w);
                }
    assert_true(nonempty > 0);
}

/* Pairs exactly at their threshold: for random rotated pairs of every
 * shape, the least world margin the oracle reports them at, and one double
 * below and above it (body margins 0 and not). */
static void test_scene_thresholds(void **state) {
    rng r = {7};
    int k, n = getenv("HGCD_SKIP_SLOW_TESTS") ? 4 : 9;
    (void)state;
    for (k = 0; k < n; k++) {
        const int sa = k % 3, sb = (k / 3) % 3; /* (the sphere: test_scenes) */
        double p[2][3], q[2][4], sc[2] = {1, 0.75}, mg[2] = {0, 0};
        const oracle_mesh *two[2] = {&shapes[sa], &shapes[sb]};
        uint64_t lo = 0, hi = 0;
        double t, x;
        int j, c;
        uint32_t pr[2];
        for (j = 0; j < 2; j++) {
            random_unit_quaternion(&r, q[j]);
            for (c = 0; c < 3; c++) p[j][c] = j ? 2.2 + unif(&r) : 0;
        }
        if (k % 3 == 0) mg[0] = 0.125, mg[1] = 0.0625;
        {
            const double big = 100;
            memcpy(&hi, &big, sizeof hi);
        }
        if (oracle_pairs_within(2, two, &p[0][0], &q[0][0], sc, 0, mg, pr, 1)) continue;
        while (hi - lo > 1) {
            const uint64_t mid = lo + (hi - lo) / 2;
            memcpy(&x, &mid, sizeof x);
            if (oracle_pairs_within(2, two, &p[0][0], &q[0][0], sc, x, mg, pr, 1)) hi = mid;
            else lo = mid;
        }
        memcpy(&t, &hi, sizeof t);
        for (j = -1; j <= 1; j++) {
            const double wm = j < 0 ? nextafter(t, 0) : j > 0 ? nextafter(t, INFINITY) : t;
            int th;
            for (th = 1; th <= 2; th++) {
                scene m;
                const hgcd_pair *pairs;
                size_t count;
                assert_true(scene_init(&m, wm, (uint32_t)th, HGCD_NARROW_EXACT, (uint32_t)(th - 1)));
                scene_add(&m, sa, p[0], q[0], sc[0], mg[0]);
                scene_add(&m, sb, p[1], q[1], sc[1], mg[1]);
                assert_int_equal(hgcd_world_detect(m.w), HGCD_OK);
                assert_int_equal(hgcd_world_pairs(m.w, &pairs, &count), HGCD_OK);
                assert_int_equal(count, j >= 0 ? 1 : 0);
                hgcd_world_destroy(m.w);
            }
        }
    }
}

/* Hand-built: cubes a gap g apart at exactly the pair margin, a hair above
 * and below; one cube inside a bigger one (distance 0, the margin does not
 * matter); huge margins (every pair). */
static void test_scene_cases(void **state) {
    const double q0[4] = {0, 0, 0, 1};
    const double g = 0.375;
    const double margins[3][3] = {{0.125, 0.125, 0.125}, {0, 0.25, 0.125}, {0.375, 0, 0}};
    int k, i;
    (void)state;
    for (k = 0; k < 3; k++)
        for (i = -1; i <= 1; i++) {
            scene m;
            const double a[3] = {0, 0, 0}, b[3] = {2 + g, 0.5, -0.25};
            double mb = margins[k][2];
            if (i) mb = nextafter(mb + (mb == 0 && i > 0 ? 0 : 0), i < 0 ? 0 : INFINITY);
            assert_true(scene_init(&m, margins[k][0], 1, HGCD_NARROW_EXACT, 0));
            scene_add(&m, 1, a, q0, 1, margins[k][1]);
            scene_add(&m, 1, b, q0, 1, mb);
            scene_check(&m, 0);
            hgcd_world_destroy(m.w);
        }
    {
        scene m;
        const double a[3] = {0, 0, 0};
        assert_true(scene_init(&m, 0.01, 2, HGCD_NARROW_EXACT, 1));
        scene_add(&m, 1, a, q0, 3, 0);
        scene_add(&m, 3, a, q0, 1, 0);
        scene_add(&m, 0, a, q0, 0.5, 0.5);
        assert_int_equal(scene_check(&m, 1), 3);
        hgcd_world_destroy(m.w);
    }
    {
        scene m;
        rng r = {99};
        assert_true(scene_init(&m, 1e15, 2, HGCD_NARROW_EXACT, 0));
        random_scene(&m, &r, 1e3);
        assert_int_equal(scene_check(&m, 0), (size_t)kBodies * (kBodies - 1) / 2);
        hgcd_world_destroy(m.w);
    }
}

/* The world's margin set after creation: each detect equals the oracle at
 * the new margin (every pair tested again, the broad phase grown or shrunk),
 * on 1 and 2 threads, contacts on and off; refusals change nothing. */
static void test_world_margin_setter(void **state) {
    const double margins[] = {0.3, 0, 1e-9, 0.05, 0.3};
    const double bad[] = {-1, NAN, INFINITY, 1.0000001e15};
    int threads;
    size_t k;
    (void)state;
    for (threads = 1; threads <= 2; threads++) {
        scene m;
        rng r = {(uint64_t)(40 + threads)};
        double got;
        assert_true(scene_init(&m, 0.05, (uint32_t)threads, HGCD_NARROW_EXACT, (uint32_t)(threads - 1)));
        random_scene(&m, &r, 5.0);
        scene_check(&m, threads - 1);
        for (k = 0; k < sizeof margins / sizeof *margins; k++) {
            assert_int_equal(hgcd_world_set_contact_margin(m.w, margins[k]), HGCD_OK);
            m.world_margin = margins[k];
            scene_check(&m, threads - 1);
        }
        for (k = 0; k < sizeof bad / sizeof *bad; k++) {
            assert_int_equal(hgcd_world_set_contact_margin(m.w, bad[k]), HGCD_ERROR_INVALID_ARGUMENT);
            assert_int_equal(hgcd_world_get_contact_margin(m.w, &got), HGCD_OK);
            assert_true(got == 0.3);
        }
        scene_check(&m, threads - 1);
        assert_int_equal(hgcd_world_set_contact_margin(NULL, 0), HGCD_ERROR_NULL_ARGUMENT);
        assert_int_equal(hgcd_world_get_contact_margin(m.w, NULL), HGCD_ERROR_NULL_ARGUMENT);
        assert_int_equal(hgcd_world_get_contact_margin(NULL, &got), HGCD_ERROR_NULL_ARGUMENT);
        hgcd_world_destroy(m.w);
    }
}

/* Refusals change nothing; the default is 0. */
static void test_margin_refusals(void **state) {
    const double bad[] = {-1, -0x1p-1074, NAN, INFINITY, 1.0000001e15};
    scene m;
    size_t k;
    double got;
    const double p[3] = {0, 0, 0}, q[4] = {0, 0, 0, 1};
    (void)state;
    assert_true(hgcd_world_desc_default().contact_margin == 0);
    assert_true(hgcd_body_desc_default().margin == 0);
    for (k = 0; k < sizeof bad / sizeof *bad; k++) {
        hgcd_world_desc wd = hgcd_world_desc_default();
        hgcd_world *w = NULL;
        wd.contact_margin = bad[k];
        assert_int_equal(hgcd_world_create(&wd, &w), HGCD_ERROR_INVALID_ARGUMENT);
        assert_null(w);
    }
    assert_true(scene_init(&m, 1e15, 1, HGCD_NARROW_EXACT, 0));
    scene_add(&m, 0, p, q, 1, 0.5);
    for (k = 0; k < sizeof bad / sizeof *bad; k++) {
        hgcd_body_desc bd = hgcd_body_desc_default();
        hgcd_body b;
        bd.mesh = m.mesh[0];
        bd.margin = bad[k];
        assert_int_equal(hgcd_body_create(m.w, &bd, &b), HGCD_ERROR_INVALID_ARGUMENT);
        assert_int_equal(hgcd_world_body_count(m.w), 1);
        assert_int_equal(hgcd_body_set_margin(m.w, m.id[0], bad[k]), HGCD_ERROR_INVALID_ARGUMENT);
        assert_int_equal(hgcd_body_get_margin(m.w, m.id[0], &got), HGCD_OK);
        assert_true(got == 0.5);
    }
    assert_int_equal(hgcd_body_set_margin(m.w, m.id[0], 1e15), HGCD_OK);
    assert_int_equal(hgcd_body_get_margin(m.w, m.id[0], &got), HGCD_OK);
    assert_true(got == 1e15);
    assert_int_equal(hgcd_body_get_margin(m.w, m.id[0], NULL), HGCD_ERROR_NULL_ARGUMENT);
    assert_int_equal(hgcd_body_set_margin(NULL, m.id[0], 0), HGCD_ERROR_NULL_ARGUMENT);
    assert_int_equal(hgcd_body_destroy(m.w, m.id[0]), HGCD_OK);
    assert_int_equal(hgcd_body_set_margin(m.w, m.id[0], 0), HGCD_ERROR_STALE_ID);
    assert_int_equal(hgcd_body_get_margin(m.w, m.id[0], &got), HGCD_ERROR_STALE_ID);
    hgcd_world_destroy(m.w);
}

int main(void) {
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_known_distances),
        cmocka_unit_test(test_random_pairs),
        cmocka_unit_test(test_margin_refusals),
        cmocka_unit_test(test_scene_cases),
        cmocka_unit_test(test_scene_thresholds),
        cmocka_unit_test(test_scenes),
        cmocka_unit_test(test_world_margin_setter),
    };
    make_sphere();
    if (getenv("HGCD_TEST_FILTER")) cmocka_set_test_filter(getenv("HGCD_TEST_FILTER"));
    return cmocka_run_group_tests(tests, NULL, NULL);
}
