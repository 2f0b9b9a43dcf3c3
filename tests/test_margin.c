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
    long n = iters(3000), k;
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

int main(void) {
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_known_distances),
        cmocka_unit_test(test_random_pairs),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
