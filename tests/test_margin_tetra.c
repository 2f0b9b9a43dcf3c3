/* The contact margin's tetrahedron test (src/narrow/within.cpp): pairs of
 * tetrahedra with a margin d, through the one-pair test, the batch and the
 * general exact margin path, against the GMP oracle's exact distances
 * (oracle_distance.c): random pairs at random margins, pairs at their exact
 * threshold margin and one double either side, and parallel faces, edges and
 * flat tetrahedra a known gap apart. */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#include "hgcd/hgcd_scene.h"
#include "oracle.h"
#include "support/testing.h"
#include "test_rng.h"

enum { kMeshes = 5, kMaxPairs = 600 };

/* The scene's tetrahedron, an irregular one, two corner tetrahedra (apex
 * down and up: their faces in z = 0 are parallel), and a flat one. */
static const double mesh_v[kMeshes][12] = {
    {1, 1, 1, 1, -1, -1, -1, 1, -1, -1, -1, 1},
    {0, 0, 0, 1, 0, 0, 0.25, 1, 0, 0.25, 0.25, 0.75},
    {0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, -1},
    {0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1},
    {0, 0, 0, 1, 0, 0, 0, 1, 0, 0.25, 0.25, 0},
};
static uint32_t faces[12];
static oracle_mesh omesh[kMeshes];

typedef struct {
    uint32_t mesh[2 * kMaxPairs];
    double pose[16 * kMaxPairs], d[kMaxPairs];
    int oracle[kMaxPairs];
    uint32_t count;
} pairs;

static void add_pair(pairs *p, uint32_t ma, uint32_t mb, const double *pa, const double *qa, double sa,
                     const double *pb, const double *qb, double sb, double d) {
    double *pose = p->pose + 16 * p->count;
    const oracle_mesh *two[2] = {&omesh[ma], &omesh[mb]};
    double pos[6], ori[8], sc[2] = {sa, sb}, mg[2] = {0, 0};
    uint32_t out[2];
    assert_true(p->count < kMaxPairs);
    memcpy(pose, pa, 3 * sizeof(double)), memcpy(pose + 3, qa, 4 * sizeof(double)), pose[7] = sa;
    memcpy(pose + 8, pb, 3 * sizeof(double)), memcpy(pose + 11, qb, 4 * sizeof(double)), pose[15] = sb;
    p->mesh[2 * p->count] = ma, p->mesh[2 * p->count + 1] = mb;
    p->d[p->count] = d;
    memcpy(pos, pa, 3 * sizeof(double)), memcpy(pos + 3, pb, 3 * sizeof(double));
    memcpy(ori, qa, 4 * sizeof(double)), memcpy(ori + 4, qb, 4 * sizeof(double));
    p->oracle[p->count] = oracle_pairs_within(2, two, pos, ori, sc, d, mg, out, 1) > 0;
    p->count++;
}

/* Every path against the oracle; returns the certificates' fallbacks. */
static int64_t check_pairs(const pairs *p) {
    static int one[kMaxPairs], batch[kMaxPairs], general[kMaxPairs];
    const int64_t fallbacks = hgcdi_tetra_within_check(&mesh_v[0][0], kMeshes, p->mesh, p->pose, p->d, p->count,
                                                       one, batch, general);
    uint32_t k;
    assert_true(fallbacks >= 0);
    for (k = 0; k < p->count; k++) {
        if (one[k] != p->oracle[k] || batch[k] != p->oracle[k] || general[k] != p->oracle[k]) {
            const double *x = p->pose + 16 * k;
            int i;
            fprintf(stderr, "pair %u meshes %u %u d = %a: oracle %d, one-pair %d, batch %d, general %d\npose:", k,
                    p->mesh[2 * k], p->mesh[2 * k + 1], p->d[k], p->oracle[k], one[k], batch[k], general[k]);
            for (i = 0; i < 16; i++) fprintf(stderr, " %a", x[i]);
            fprintf(stderr, "\n");
            fail_msg("the margin test of two tetrahedra differs from the oracle");
        }
    }
    return fallbacks;
}

static void random_pose(rng *r, double range, double *pos, double *q) {
    int k;
    for (k = 0; k < 3; k++) pos[k] = range * (2 * unif(r) - 1);
    random_unit_quaternion(r, q);
}

/* Random pairs a random distance apart at log-uniform margins: most are
 * decided by the certificates (touching, apart, within), all exactly. */
static void test_random_tetra_pairs(void **state) {
    static pairs p;
    rng r = {11};
    const uint32_t n = getenv("HGCD_SKIP_SLOW_TESTS") ? 150 : kMaxPairs;
    int within = 0, apart = 0;
    uint32_t k;
    (void)state;
    p.count = 0;
    for (k = 0; k < n; k++) {
        double pa[3], qa[4], pb[3], qb[4];
        const uint32_t ma = (uint32_t)(next(&r) % kMeshes), mb = (uint32_t)(next(&r) % kMeshes);
        const double sa = 0.5 + unif(&r), sb = 0.5 + unif(&r), d = pow(2, -30 + 31 * unif(&r));
        random_pose(&r, 0.1, pa, qa);
        random_pose(&r, 1.6, pb, qb);
        add_pair(&p, ma, mb, pa, qa, sa, pb, qb, sb, d);
        within += p.oracle[k];
        apart += !p.oracle[k];
    }
    assert_true(within > (int)n / 10 && apart > (int)n / 10);
    /* The certificates decide nearly every pair (only distances within
     * rounding of d need the direct path). */
    assert_true(check_pairs(&p) < (int64_t)n / 20);
}

/* Random pairs apart at d = 0, at their exact threshold margin t (the least
 * double the oracle reports them at) and one double below and above. */
static void test_tetra_thresholds(void **state) {
    static pairs p;
    rng r = {12};
    const int n = getenv("HGCD_SKIP_SLOW_TESTS") ? 6 : 24;
    int k, found = 0;
    (void)state;
    p.count = 0;
    for (k = 0; k < 4 * n && found < n; k++) {
        double pa[3], qa[4], pb[3], qb[4], pos[6], ori[8], t, x;
        const uint32_t ma = (uint32_t)(next(&r) % kMeshes), mb = (uint32_t)(next(&r) % kMeshes);
        const oracle_mesh *two[2] = {&omesh[ma], &omesh[mb]};
        double sc[2] = {1, 0.75}, mg[2] = {0, 0};
        const double big = 100;
        uint64_t lo = 0, hi;
        uint32_t out[2];
        random_pose(&r, 0.1, pa, qa);
        random_pose(&r, 1.6, pb, qb);
        memcpy(pos, pa, sizeof pa), memcpy(pos + 3, pb, sizeof pb);
        memcpy(ori, qa, sizeof qa), memcpy(ori + 4, qb, sizeof qb);
        if (oracle_pairs_within(2, two, pos, ori, sc, 0, mg, out, 1)) continue;
        memcpy(&hi, &big, sizeof hi);
        if (!oracle_pairs_within(2, two, pos, ori, sc, big, mg, out, 1)) continue;
        while (hi - lo > 1) {
            const uint64_t mid = lo + (hi - lo) / 2;
            memcpy(&x, &mid, sizeof x);
            if (oracle_pairs_within(2, two, pos, ori, sc, x, mg, out, 1)) hi = mid;
            else lo = mid;
        }
        memcpy(&t, &hi, sizeof t);
        add_pair(&p, ma, mb, pa, qa, sc[0], pb, qb, sc[1], nextafter(t, 0));
        add_pair(&p, ma, mb, pa, qa, sc[0], pb, qb, sc[1], t);
        add_pair(&p, ma, mb, pa, qa, sc[0], pb, qb, sc[1], nextafter(t, INFINITY));
        assert_int_equal(p.oracle[p.count - 3] * 4 + p.oracle[p.count - 2] * 2 + p.oracle[p.count - 1], 3);
        found++;
    }
    assert_int_equal(found, n);
    check_pairs(&p);
}

/* Hand-built gaps g (exact: dyadic positions, rotations by half turns):
 * parallel faces of the corner tetrahedra g apart, apex below apex (one
 * turned a half turn about x), a flat tetrahedron g above a face, and one
 * turned a quarter about z (any distance, checked against the oracle); each
 * at d = g, one double below and above; then touching faces at tiny d. */
static void test_tetra_gaps(void **state) {
    static pairs p;
    const double id[4] = {0, 0, 0, 1}, flip[4] = {1, 0, 0, 0}, quarter[4] = {0, 0, 0.70710678118654752, 0.70710678118654752};
    const double gaps[] = {0x1p-40, 0x1p-20, 0.0625, 0.375};
    size_t k;
    int j;
    (void)state;
    p.count = 0;
    for (k = 0; k < sizeof gaps / sizeof *gaps; k++) {
        const double g = gaps[k], o[3] = {0, 0, 0};
        const double face[3] = {0.25, 0.25, g}, apex[3] = {0, 0, 2 + g}, flat[3] = {0.125, 0.125, g};
        for (j = -1; j <= 1; j++) {
            const double d = j < 0 ? nextafter(g, 0) : j > 0 ? nextafter(g, INFINITY) : g;
            add_pair(&p, 2, 3, o, id, 1, face, id, 1, d);      /* face over face */
            add_pair(&p, 3, 3, o, id, 1, apex, flip, 1, d);    /* apex over apex */
            add_pair(&p, 2, 4, o, id, 1, flat, id, 1, d);      /* flat over a face */
            add_pair(&p, 3, 2, o, quarter, 1, face, id, 1, d); /* turned: not exactly g (any answer checked) */
        }
    }
    {
        const double touch[3] = {0.25, 0.25, 0};
        add_pair(&p, 2, 3, touch, id, 1, touch, id, 1, 0x1p-1000); /* touching faces */
        add_pair(&p, 2, 4, touch, id, 1, touch, id, 1, 1e-300);    /* flat in a face */
    }
    for (k = 0; k < p.count; k += 4)
        if (k < 48) { /* the three exact gaps: within at d >= g only */
            const int j = (int)(k / 4) % 3 - 1;
            assert_int_equal(p.oracle[k], j >= 0);
            assert_int_equal(p.oracle[k + 1], j >= 0);
            assert_int_equal(p.oracle[k + 2], j >= 0);
        }
    check_pairs(&p);
}

int main(void) {
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_tetra_gaps),
        cmocka_unit_test(test_random_tetra_pairs),
        cmocka_unit_test(test_tetra_thresholds),
    };
    int m;
    hgcd_scene_tetra_unit_mesh(NULL, faces);
    for (m = 0; m < kMeshes; m++) {
        omesh[m].verts = mesh_v[m];
        omesh[m].tris = faces;
        omesh[m].vertex_count = 4;
        omesh[m].triangle_count = 4;
    }
    if (getenv("HGCD_TEST_FILTER")) cmocka_set_test_filter(getenv("HGCD_TEST_FILTER"));
    return cmocka_run_group_tests(tests, NULL, NULL);
}
