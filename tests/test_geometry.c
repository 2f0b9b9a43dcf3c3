/* Tests of hgcd's exact geometry (src/exact through tests/support/testing.h)
 * against hand-known answers and against the independent GMP oracle. */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include <cmocka.h>

#ifndef M_PI
#define M_PI 3.14159265358979323846
#endif

#include "support/testing.h"
#include "oracle.h"

/* ------------------------------------------------------------------------ */
/* Helpers                                                                   */
/* ------------------------------------------------------------------------ */

static uint64_t rng_state = 0x243F6A8885A308D3ull;

static uint64_t rnd(void) { /* splitmix64 */
    uint64_t z = (rng_state += 0x9E3779B97F4A7C15ull);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return z ^ (z >> 31);
}

static double urand(void) { return (double)(rnd() >> 11) * 0x1p-53; }

static int irand(int n) { return (int)(rnd() % (uint64_t)n); }

/* Iteration counts of the randomized tests; a quarter of them when
 * HGCD_SKIP_SLOW_TESTS is set (sanitizer builds). */
static long iters(long n) { return getenv("HGCD_SKIP_SLOW_TESTS") ? n / 4 : n; }

static void set3(double *v, double x, double y, double z) {
    v[0] = x;
    v[1] = y;
    v[2] = z;
}

static void tri(double *t, double ax, double ay, double az, double bx,
                double by, double bz, double cx, double cy, double cz) {
    set3(t, ax, ay, az);
    set3(t + 3, bx, by, bz);
    set3(t + 6, cx, cy, cz);
}

static const int kPerm[6][3] = {{0, 1, 2}, {1, 2, 0}, {2, 0, 1},
                                {0, 2, 1}, {2, 1, 0}, {1, 0, 2}};

static void permute(const double *t, int perm, double *out) {
    int i;
    for (i = 0; i < 3; i++) memcpy(out + 3 * i, t + 3 * kPerm[perm][i], 3 * sizeof(double));
}

/* Checks the expected answer for all vertex orders of both triangles, both
 * argument orders, for hgcd and (on a subset) for the oracle. */
static void check_tt(const double *p, const double *q, int expected) {
    int a, b;
    assert_int_equal(oracle_tri_tri(p, q), expected);
    assert_int_equal(oracle_tri_tri(q, p), expected);
    for (a = 0; a < 6; a++) {
        for (b = 0; b < 6; b++) {
            double pp[9], qq[9];
            permute(p, a, pp);
            permute(q, b, qq);
            if (hgcdi_tri_tri(pp, qq) != expected || hgcdi_tri_tri(qq, pp) != expected ||
                hgcdi_tri_tri_prepared(pp, qq) != expected) {
                print_error("tri_tri mismatch: perm %d %d expected %d\n", a, b, expected);
                fail();
            }
        }
    }
    {
        double pp[9], qq[9];
        permute(p, 4, pp);
        permute(q, 3, qq);
        assert_int_equal(oracle_tri_tri(pp, qq), expected);
    }
}

/* Same test with every triangle translated by t (exact when t and the
 * coordinates are small dyadic numbers). */
static void check_tt_shift(const double *p, const double *q, int expected,
                           double tx, double ty, double tz) {
    double pp[9], qq[9];
    int i;
    for (i = 0; i < 3; i++) {
        pp[3 * i] = p[3 * i] + tx; pp[3 * i + 1] = p[3 * i + 1] + ty; pp[3 * i + 2] = p[3 * i + 2] + tz;
        qq[3 * i] = q[3 * i] + tx; qq[3 * i + 1] = q[3 * i + 1] + ty; qq[3 * i + 2] = q[3 * i + 2] + tz;
    }
    check_tt(pp, qq, expected);
}

/* Base triangle: the unit right triangle in z = 0. */
static double T0[9] = {0, 0, 0, 1, 0, 0, 0, 1, 0};

/* ------------------------------------------------------------------------ */
/* orient3d / orient2d                                                       */
/* ------------------------------------------------------------------------ */

static void check_o3d(const double *a, const double *b, const double *c,
                      const double *d, int expected) {
    int o = oracle_orient3d(a, b, c, d);
    assert_int_equal(o, expected);
    assert_int_equal(hgcdi_orient3d(a, b, c, d), o);
    /* antisymmetry under a swap, invariance under even permutations */
    assert_int_equal(hgcdi_orient3d(b, a, c, d), -o);
    assert_int_equal(hgcdi_orient3d(b, c, a, d), o);
    assert_int_equal(hgcdi_orient3d(a, b, d, c), -o);
}

static void test_orient3d_basic(void **state) {
    double a[3] = {0, 0, 0}, b[3] = {1, 0, 0}, c[3] = {0, 1, 0};
    double below[3] = {0.2, 0.2, -1}, above[3] = {0.2, 0.2, 1}, on[3] = {5, -7, 0};
    (void)state;
    check_o3d(a, b, c, below, 1);
    check_o3d(a, b, c, above, -1);
    check_o3d(a, b, c, on, 0);
    check_o3d(a, a, c, above, 0);
    check_o3d(a, a, a, a, 0);
}

static void test_orient3d_ulp_perturbed(void **state) {
    /* Points on the plane z = x/2 + y/4 + 1 (exact), the fourth perturbed by
     * one ulp in each coordinate and direction. */
    double a[3] = {0.5, 0.75, 0}, b[3] = {3, -1, 0}, c[3] = {-2.5, 4, 0};
    double d[3] = {1.25, 2.5, 0};
    int k, dir;
    (void)state;
    a[2] = a[0] / 2 + a[1] / 4 + 1;
    b[2] = b[0] / 2 + b[1] / 4 + 1;
    c[2] = c[0] / 2 + c[1] / 4 + 1;
    d[2] = d[0] / 2 + d[1] / 4 + 1;
    check_o3d(a, b, c, d, 0);
    for (k = 0; k < 3; k++) {
        for (dir = -1; dir <= 1; dir += 2) {
            double e[3];
            int o;
            memcpy(e, d, sizeof e);
            e[k] = nextafter(e[k], dir * INFINITY);
            o = oracle_orient3d(a, b, c, e);
            assert_int_not_equal(o, 0);
            check_o3d(a, b, c, e, o);
        }
    }
    /* Moving d up in z puts it above the plane (a, b, c counter-clockwise
     * seen from above? orientation of (a,b,c) in xy decides). */
    {
        double e[3];
        double o2 = (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]);
        memcpy(e, d, sizeof e);
        e[2] = nextafter(e[2], INFINITY);
        check_o3d(a, b, c, e, o2 > 0 ? -1 : 1);
    }
}

static void test_orient3d_large_coordinates(void **state) {
    /* 1e15-sized coordinates with tiny offsets: the filter cannot decide. */
    double big = 1e15;
    double a[3] = {big, big, big};
    double b[3] = {big + 1, big, big};
    double c[3] = {big, big + 1, big};
    double d[3] = {big + 0.125, big + 0.125, big}; /* exact: 1e15 + 1/8 */
    double e[3];
    (void)state;
    check_o3d(a, b, c, d, 0);
    memcpy(e, d, sizeof e);
    e[2] = nextafter(big, INFINITY);
    check_o3d(a, b, c, e, -1);
    e[2] = nextafter(big, 0);
    check_o3d(a, b, c, e, 1);
    /* Opposite corners of the 1e15 range. */
    {
        double p[3] = {-1e15, -1e15, -1e15}, q[3] = {1e15, -1e15, 1e15};
        double r[3] = {-1e15, 1e15, 1e15}, s[3] = {1e15, 1e15, -1e15};
        double m[3] = {0, 0, 0};
        int o = oracle_orient3d(p, q, r, s);
        assert_int_not_equal(o, 0);
        check_o3d(p, q, r, s, o);
        check_o3d(p, q, s, m, oracle_orient3d(p, q, s, m));
    }
}

static void test_orient3d_extreme_ranges(void **state) {
    /* Subnormal and tiny coordinates next to large ones: the expansion
     * path must scale, or fall back to big integers. */
    double tiny = 4.9406564584124654e-324; /* 2^-1074 */
    double a[3] = {0, 0, 0}, b[3] = {1, 0, 0}, c[3] = {0, 1, 0};
    double d[3] = {0.25, 0.25, tiny};
    double e[3] = {1e15, 3e14, tiny};
    double f[3] = {1e-300, 1e-300, 1e-300};
    double g[3] = {2e-300, 1e-300, 3e-300};
    double h[3] = {1e-300, 5e-300, 1e-300};
    double k[3] = {7e-300, 7e-300, 0};
    (void)state;
    check_o3d(a, b, c, d, -1);
    d[2] = -tiny;
    check_o3d(a, b, c, d, 1);
    check_o3d(a, b, c, e, -1);
    check_o3d(f, g, h, k, oracle_orient3d(f, g, h, k));
    check_o3d(f, g, h, a, oracle_orient3d(f, g, h, a));
    {
        double big1[3] = {1e15, 1e15, 1e-310};
        check_o3d(a, b, big1, d, oracle_orient3d(a, b, big1, d));
    }
    /* Random mixes of magnitudes. */
    {
        static const double mags[] = {0, 1e-320, 1e-310, 1e-300, 1e-200, 1e-20,
                                      1, 3, 1e10, 1e15};
        int it;
        for (it = 0; it < iters(20000); it++) {
            double v[12];
            int i;
            for (i = 0; i < 12; i++) {
                double m = mags[irand(10)];
                v[i] = (irand(2) ? -1 : 1) * m * (irand(4) ? 1.0 : 1 + urand());
            }
            if (irand(3) == 0) { /* make it coplanar-ish: d = a */
                v[9] = v[0]; v[10] = v[1]; v[11] = v[2] + (irand(2) ? v[11] * 0x1p-60 : 0);
            }
            {
                int o = oracle_orient3d(v, v + 3, v + 6, v + 9);
                if (hgcdi_orient3d(v, v + 3, v + 6, v + 9) != o) {
                    print_error("orient3d mismatch at iteration %d\n", it);
                    fail();
                }
            }
        }
    }
}

static void test_orient3d_random_near_degenerate(void **state) {
    int it, zeros = 0, nonzero = 0;
    (void)state;
    for (it = 0; it < iters(100000); it++) {
        double a[3], b[3], c[3], d[3];
        int k, o;
        double s = urand(), t = urand();
        double scale = it % 3 == 0 ? 1e15 : (it % 3 == 1 ? 1.0 : 1e-5);
        for (k = 0; k < 3; k++) {
            a[k] = (urand() - 0.5) * scale;
            b[k] = (urand() - 0.5) * scale;
            c[k] = (urand() - 0.5) * scale;
        }
        if (it % 4 == 0) {
            /* Snap to a coarse grid: exact coplanarity happens. */
            for (k = 0; k < 3; k++) {
                a[k] = floor(a[k] * 4 / scale);
                b[k] = floor(b[k] * 4 / scale);
                c[k] = floor(c[k] * 4 / scale);
                d[k] = a[k] + (double)irand(3) * (b[k] - a[k]) + (double)irand(3) * (c[k] - a[k]);
            }
        } else {
            for (k = 0; k < 3; k++) d[k] = a[k] + s * (b[k] - a[k]) + t * (c[k] - a[k]);
            if (it % 5 == 0) d[irand(3)] = nextafter(d[irand(3)], irand(2) ? INFINITY : -INFINITY);
        }
        o = oracle_orient3d(a, b, c, d);
        zeros += o == 0;
        nonzero += o != 0;
        if (hgcdi_orient3d(a, b, c, d) != o || hgcdi_orient3d(d, a, c, b) != o) {
            print_error("orient3d mismatch at iteration %d\n", it);
            fail();
        }
    }
    assert_true(zeros > iters(1000));
    assert_true(nonzero > iters(1000));
}

static void test_orient2d(void **state) {
    double a[2] = {0, 0}, b[2] = {1, 0}, c[2] = {0, 1}, d[2] = {0.5, 0.5};
    int it;
    (void)state;
    assert_int_equal(hgcdi_orient2d(a, b, c), 1);
    assert_int_equal(hgcdi_orient2d(b, a, c), -1);
    assert_int_equal(hgcdi_orient2d(b, c, d), 0);
    d[0] = nextafter(0.5, 1);
    assert_int_equal(hgcdi_orient2d(b, c, d), oracle_orient2d(b, c, d));
    assert_int_equal(hgcdi_orient2d(b, c, d), -1); /* right of b -> c */
    /* tiny coordinates (scaled exact path) and mixed ranges (big integers) */
    {
        double p[2] = {1e-200, 3e-200}, q[2] = {5e-200, 7e-200}, r[2];
        r[0] = 3e-200; r[1] = 5e-200; /* (nearly) the midpoint */
        assert_int_equal(hgcdi_orient2d(p, q, r), oracle_orient2d(p, q, r));
        r[1] = nextafter(r[1], 1);
        assert_int_equal(hgcdi_orient2d(p, q, r), oracle_orient2d(p, q, r));
        r[0] = 1e15;
        r[1] = 1e15 + 2;
        assert_int_equal(hgcdi_orient2d(p, q, r), oracle_orient2d(p, q, r));
        p[0] = 0; p[1] = 0; q[0] = 1e15; q[1] = 1e15; r[0] = 4.9e-324; r[1] = 4.9e-324;
        assert_int_equal(hgcdi_orient2d(p, q, r), 0);
        r[1] = 0;
        assert_int_equal(hgcdi_orient2d(p, q, r), -1);
        assert_int_equal(oracle_orient2d(p, q, r), -1);
    }
    for (it = 0; it < iters(50000); it++) {
        double p[2], q[2], r[2];
        double t = urand();
        double scale = it % 2 ? 1e15 : 1.0;
        p[0] = urand() * scale; p[1] = urand() * scale;
        q[0] = urand() * scale; q[1] = urand() * scale;
        r[0] = p[0] + t * (q[0] - p[0]);
        r[1] = p[1] + t * (q[1] - p[1]);
        if (it % 7 == 0) { r[0] = 1e-310 * urand(); p[1] = -1e-300; }
        if (hgcdi_orient2d(p, q, r) != oracle_orient2d(p, q, r)) {
            print_error("orient2d mismatch at %d\n", it);
            fail();
        }
    }
}

/* ------------------------------------------------------------------------ */
/* Triangle / triangle: hand-made degenerate configurations                 */
/* ------------------------------------------------------------------------ */

static void test_tt_vertex_vertex(void **state) {
    double q[9];
    (void)state;
    tri(q, 0, 0, 0, -1, -1, 1, -1, -2, 1);
    check_tt(T0, q, 1);
    tri(q, 0, 0, nextafter(0, 1), -1, -1, 1, -1, -2, 1); /* 2^-1074 above */
    check_tt(T0, q, 0);
    /* touching at T0's vertex (1,0,0) from below, in another orientation */
    tri(q, 1, 0, 0, 2, 1, -1, 2, -1, -1);
    check_tt(T0, q, 1);
    tri(q, nextafter(1, 2), 0, 0, 2, 1, -1, 2, -1, -1);
    check_tt(T0, q, 0);
    tri(q, 1, 0, 0, 2, 1, -1, 2, -1, -1);
    check_tt_shift(T0, q, 1, 1024, -3, 0.5); /* exact translation */
    tri(q, 1.125, 0, 0, 2, 1, -1, 2, -1, -1);
    check_tt_shift(T0, q, 0, 1024, -3, 0.5);
}

static void test_tt_vertex_on_edge(void **state) {
    double q[9];
    (void)state;
    tri(q, 0.5, 0, 0, 0.5, -1, 1, 1.5, -1, 1);
    check_tt(T0, q, 1);
    tri(q, 0.5, nextafter(0, -1), 0, 0.5, -1, 1, 1.5, -1, 1);
    check_tt(T0, q, 0);
    tri(q, 0.5, -0x1p-60, 0, 0.5, -1, 1, 1.5, -1, 1);
    check_tt(T0, q, 0);
    /* on the hypotenuse x + y = 1 */
    tri(q, 0.25, 0.75, 0, 2, 2, 1, 2, 3, -1);
    check_tt(T0, q, 1);
    tri(q, 0.25, nextafter(0.75, 1), 0, 2, 2, 1, 2, 3, -1);
    check_tt(T0, q, 0);
    tri(q, 0.25, 0.75, 0, 2, 2, 1, 2, 3, -1);
    check_tt_shift(T0, q, 1, -7, 0.25, 3); /* exact translation */
    tri(q, 0.25, 0.75 + 0x1p-40, 0, 2, 2, 1, 2, 3, -1);
    check_tt_shift(T0, q, 0, -7, 0.25, 3);
}

static void test_tt_vertex_in_face(void **state) {
    double q[9];
    (void)state;
    tri(q, 0.25, 0.25, 0, 1, 1, 1, -1, 2, 1);
    check_tt(T0, q, 1);
    tri(q, 0.25, 0.25, 0x1p-70, 1, 1, 1, -1, 2, 1);
    check_tt(T0, q, 0);
    tri(q, 0.25, 0.25, -0x1p-70, 1, 1, 1, -1, 2, 1);
    check_tt(T0, q, 1); /* pokes through */
}

static void test_tt_edge_edge(void **state) {
    double q[9];
    (void)state;
    /* Q in the plane x = 0.5; its edge crosses T0's edge y = 0 at (0.5,0,0)
     * and Q meets z = 0 only along y <= 0. */
    tri(q, 0.5, 0.5, -1, 0.5, -0.5, 1, 0.5, -2, 0);
    check_tt(T0, q, 1);
    tri(q, 0.5, 0.5 - 0x1p-40, -1, 0.5, -0.5 - 0x1p-40, 1, 0.5, -2 - 0x1p-40, 0);
    check_tt(T0, q, 0);
    /* Skew edges crossing at one point, triangles on opposite sides. */
    tri(q, 0.5, 0.5, 0, 1, 1, 0, 0.5, 0.5, 1); /* vertical, touches hypotenuse */
    check_tt(T0, q, 1);
    tri(q, 0.5, 0.5, 0x1p-50, 1, 1, 0, 0.5, 0.5, 1);
    check_tt(T0, q, 0); /* only (1,1,0) is left in z = 0, outside T0 */
}

static void test_tt_collinear_edges(void **state) {
    double q[9];
    (void)state;
    /* Q in the plane y = 0 sharing part of T0's edge [0,1] x {0} x {0} */
    tri(q, 0.5, 0, 0, 1.5, 0, 0, 1, 0, 1);
    check_tt(T0, q, 1);
    /* touching only at T0's vertex (1,0,0) */
    tri(q, 1, 0, 0, 2, 0, 0, 1.5, 0, 1);
    check_tt(T0, q, 1);
    tri(q, nextafter(1, 2), 0, 0, 2, 0, 0, 1.5, 0, 1);
    check_tt(T0, q, 0);
    /* Q below the plane touching the whole edge from the other side */
    tri(q, -1, 0, 0, 2, 0, 0, 0.5, 0, -3);
    check_tt(T0, q, 1);
}

static void test_tt_coplanar(void **state) {
    double q[9];
    (void)state;
    /* overlap */
    tri(q, 0.25, 0.25, 0, 2, 0.25, 0, 0.25, 2, 0);
    check_tt(T0, q, 1);
    /* containment both ways */
    tri(q, 0.125, 0.125, 0, 0.25, 0.125, 0, 0.125, 0.25, 0);
    check_tt(T0, q, 1);
    check_tt(q, T0, 1);
    /* star of David-like crossing without vertex containment */
    tri(q, -0.25, 0.25, 0, 1, 0.25, 0, 0.5, -1, 0);
    check_tt(T0, q, 1);
    /* touching edges (shared hypotenuse) */
    tri(q, 1, 0, 0, 0, 1, 0, 1, 1, 0);
    check_tt(T0, q, 1);
    /* vertex touching the hypotenuse */
    tri(q, 0.5, 0.5, 0, 1, 1, 0, 0.5, 1.5, 0);
    check_tt(T0, q, 1);
    tri(q, 0.5 + 0x1p-50, 0.5, 0, 1, 1, 0, 0.5 + 0x1p-50, 1.5, 0);
    check_tt(T0, q, 0);
    /* collinear edge overlap, triangles on either side */
    tri(q, 0.5, 0, 0, 2, 0, 0, 1, -1, 0);
    check_tt(T0, q, 1);
    /* disjoint */
    tri(q, 1, 1, 0, 2, 1, 0, 1, 2, 0);
    check_tt(T0, q, 0);
    tri(q, -1, -1, 0, -0.5, -1, 0, -1, -0.5, 0);
    check_tt(T0, q, 0);
    /* coplanar in a tilted plane (x + y + z = 1), with projections needed */
    {
        double p[9];
        tri(p, 1, 0, 0, 0, 1, 0, 0, 0, 1);
        tri(q, 0.5, 0.5, 0, 0, 0.5, 0.5, 0.5, 0, 0.5);
        check_tt(p, q, 1);
        tri(q, 1, 0, 0, 2, -1, 0, 2, 0, -1);
        check_tt(p, q, 1); /* touching at a vertex */
        tri(q, 1.25, 0, -0.25, 2, -1, 0, 2, 0, -1);
        check_tt(p, q, 0);
        /* vertical plane x = y: the xy projection is degenerate */
        tri(p, 0, 0, 0, 1, 1, 0, 0, 0, 1);
        tri(q, 0.5, 0.5, 0.25, 2, 2, 2, 0.5, 0.5, 3);
        check_tt(p, q, 1);
        tri(q, 0.5, 0.5, 0.5 + 0x1p-40, 2, 2, 2, 0.5, 0.5, 3);
        check_tt(p, q, 0);
    }
}

static void test_tt_shared_edge_vertex(void **state) {
    double q[9];
    (void)state;
    tri(q, 0, 0, 0, 1, 0, 0, 0, 0, 1);
    check_tt(T0, q, 1);
    tri(q, 0, 0, 0, -1, 0, 1, 0, -1, 1);
    check_tt(T0, q, 1);
    tri(q, 0, 1, 0, 1, 0, 0, 1, 1, -1); /* shared hypotenuse, folded */
    check_tt(T0, q, 1);
    check_tt(T0, T0, 1); /* identical */
    check_tt_shift(T0, T0, 1, 1e15, -1e15, 12345.5);
}

static void test_tt_near_parallel(void **state) {
    double p[9], q[9];
    double z1 = nextafter(1.0, 2.0), z0 = nextafter(1.0, 0.0);
    (void)state;
    tri(p, 0, 0, 1, 1, 0, 1, 0, 1, 1);
    tri(q, 0, 0, z1, 1, 0, z1, 0, 1, z1);
    check_tt(p, q, 0);
    tri(q, 0.25, 0.25, z1, 1, 0.25, z1, 0.25, 1, z1);
    check_tt(p, q, 0);
    tri(q, 0.25, 0.25, 1, 1, 0.25, z1, 0.25, 1, z1); /* touches at a vertex */
    check_tt(p, q, 1);
    tri(q, 0.25, 0.25, z0, 1, 0.25, z1, 0.25, 1, z1); /* crosses */
    check_tt(p, q, 1);
    tri(q, 2, 2, z0, 3, 2, z1, 2, 3, z1); /* crosses the plane, away */
    check_tt(p, q, 0);
    /* large coordinates: 1e15 plane and the next double */
    {
        double b = 1e15, bn = nextafter(1e15, 2e15);
        tri(p, 0, 0, b, 1, 0, b, 0, 1, b);
        tri(q, 0, 0, bn, 1, 0, bn, 0, 1, bn);
        check_tt(p, q, 0);
        tri(q, 0, 0, b, 1, 0, bn, 0, 1, bn);
        check_tt(p, q, 1);
    }
}

static void test_tt_zero_area(void **state) {
    double s[9], q[9];
    (void)state;
    /* segment through T0 */
    tri(s, 0.25, 0.25, -1, 0.25, 0.25, 1, 0.25, 0.25, 0);
    check_tt(T0, s, 1);
    tri(s, 0.25, 0.25, 0x1p-30, 0.25, 0.25, 1, 0.25, 0.25, 0.5);
    check_tt(T0, s, 0);
    /* segment lying in T0's plane, crossing it / outside it */
    tri(s, -1, 0.5, 0, 2, 0.5, 0, 0.5, 0.5, 0);
    check_tt(T0, s, 1);
    tri(s, -1, 1.5, 0, 2, 1.5, 0, 0.5, 1.5, 0);
    check_tt(T0, s, 0);
    /* repeated vertex forms */
    tri(s, 0.5, 0.5, 0, 0.5, 0.5, 0, 3, 3, 0);
    check_tt(T0, s, 1); /* touches hypotenuse at its end */
    tri(s, 0.5 + 0x1p-52, 0.5, 0, 0.5 + 0x1p-52, 0.5, 0, 3, 3, 0);
    check_tt(T0, s, 0);
    /* points */
    tri(s, 0.25, 0.25, 0, 0.25, 0.25, 0, 0.25, 0.25, 0);
    check_tt(T0, s, 1);
    tri(s, 0.5, 0, 0, 0.5, 0, 0, 0.5, 0, 0);
    check_tt(T0, s, 1); /* on an edge */
    tri(s, 0.25, 0.25, 0x1p-60, 0.25, 0.25, 0x1p-60, 0.25, 0.25, 0x1p-60);
    check_tt(T0, s, 0);
    tri(s, 1, 0, 0, 1, 0, 0, 1, 0, 0);
    check_tt(T0, s, 1); /* at a vertex */
    /* degenerate vs degenerate */
    tri(s, 0, 0, 0, 2, 2, 2, 1, 1, 1);
    tri(q, 0, 2, 0, 2, 0, 2, 1, 1, 1); /* crossing at (1,1,1) */
    check_tt(s, q, 1);
    tri(q, 0, 2, 0, 2, 0, 2.5, 1, 1, 1.25); /* skew */
    check_tt(s, q, 0);
    tri(q, 1.5, 1.5, 1.5, 3, 3, 3, 4, 4, 4); /* collinear overlap */
    check_tt(s, q, 1);
    tri(q, 2, 2, 2, 3, 3, 3, 4, 4, 4); /* collinear, touching at an end */
    check_tt(s, q, 1);
    tri(q, 2.5, 2.5, 2.5, 3, 3, 3, 4, 4, 4); /* collinear, disjoint */
    check_tt(s, q, 0);
    tri(q, 0.5, 0.5, 0.5, 0.5, 0.5, 0.5, 0.5, 0.5, 0.5); /* point on it */
    check_tt(s, q, 1);
    tri(q, 0.5, 0.5, nextafter(0.5, 1), 0.5, 0.5, nextafter(0.5, 1), 0.5, 0.5,
        nextafter(0.5, 1));
    check_tt(s, q, 0);
    tri(q, 2, 2, 2, 2, 2, 2, 2, 2, 2); /* point at an end */
    check_tt(s, q, 1);
    tri(s, 2, 2, 2, 2, 2, 2, 2, 2, 2);
    check_tt(s, q, 1); /* identical points */
    tri(s, 2, 2, 3, 2, 2, 3, 2, 2, 3);
    check_tt(s, q, 0);
    /* degenerate segment parallel to an axis: projections are degenerate */
    tri(s, 0, 0, 0, 0, 0, 2, 0, 0, 1);
    tri(q, 0, 0, 1, 0, 0, 1, 0, 0, 1);
    check_tt(s, q, 1);
    tri(q, -1, 0, 1, 1, 0, 1, 0, 0, 1);
    check_tt(s, q, 1);
    tri(q, -1, 0x1p-80, 1, 1, 0x1p-80, 1, 0, 0x1p-80, 1);
    check_tt(s, q, 0);
}

static void test_segment_triangle(void **state) {
    double a[3], b[3];
    (void)state;
    set3(a, 0.25, 0.25, -1);
    set3(b, 0.25, 0.25, 1);
    assert_int_equal(hgcdi_segment_triangle(a, b, T0), 1);
    assert_int_equal(oracle_segment_triangle(a, b, T0), 1);
    set3(b, 0.25, 0.25, 0);
    assert_int_equal(hgcdi_segment_triangle(a, b, T0), 1);
    set3(b, 0.25, 0.25, -0x1p-60);
    assert_int_equal(hgcdi_segment_triangle(a, b, T0), 0);
    assert_int_equal(oracle_segment_triangle(a, b, T0), 0);
    set3(a, 1, 1, 1);
    set3(b, -1, -1, -1); /* through the vertex (0,0,0) */
    assert_int_equal(hgcdi_segment_triangle(a, b, T0), 1);
    assert_int_equal(oracle_segment_triangle(a, b, T0), 1);
}

/* ------------------------------------------------------------------------ */
/* Triangle / triangle: randomized cross-check against the oracle            */
/* ------------------------------------------------------------------------ */

static void random_grid_tri(double *t, int cells, double step) {
    int i;
    for (i = 0; i < 9; i++) t[i] = (double)irand(cells + 1) * step;
}

static void cross_check_pair(const double *p, const double *q, int *hits,
                             int *misses, long it) {
    int o = oracle_tri_tri(p, q);
    int h = hgcdi_tri_tri(p, q);
    int h2 = hgcdi_tri_tri(q, p);
    int h3 = hgcdi_tri_tri_prepared(p, q);
    if (h != o || h2 != o || h3 != o) {
        int k;
        print_error("tri_tri mismatch at %ld: hgcd %d/%d oracle %d\n", it, h, h2, o);
        for (k = 0; k < 9; k++) print_error("p[%d] = %a\n", k, p[k]);
        for (k = 0; k < 9; k++) print_error("q[%d] = %a\n", k, q[k]);
        fail();
    }
    *hits += o;
    *misses += !o;
}

static void test_tt_random_grid(void **state) {
    long it;
    int hits = 0, misses = 0;
    (void)state;
    for (it = 0; it < iters(60000); it++) {
        double p[9], q[9];
        int cells = it % 3 == 0 ? 1 : (it % 3 == 1 ? 2 : 8);
        random_grid_tri(p, cells, 0.25);
        random_grid_tri(q, cells, 0.25);
        if (it % 5 == 1) { /* share a vertex */
            memcpy(q, p + 3 * irand(3), 3 * sizeof(double));
        } else if (it % 5 == 2) { /* share an edge */
            int e = irand(3);
            memcpy(q, p + 3 * e, 3 * sizeof(double));
            memcpy(q + 3, p + 3 * ((e + 1) % 3), 3 * sizeof(double));
        }
        cross_check_pair(p, q, &hits, &misses, it);
    }
    print_message("grid pairs: %d hits, %d misses\n", hits, misses);
    assert_true(hits > iters(5000));
    assert_true(misses > iters(5000));
}

/* Hulls of 1 to 3 points lying in one plane x_k = c (points, segments,
 * triangles, degenerate ones among them) on a coarse grid, so that
 * vertices, edges and containment touch exactly: flat_hulls_meet (the flat
 * region's test) against the oracle's triangle test (a point or a segment
 * as a triangle with repeated corners), both orders. */
static void test_flat_hulls(void **state) {
    long it;
    int hits = 0, misses = 0;
    (void)state;
    for (it = 0; it < iters(40000); it++) {
        const int k = irand(3), cells = it % 2 ? 2 : 4, n[2] = {1 + irand(3), 1 + irand(3)};
        const double c = 0.25 * (double)irand(5) - 0.5;
        double v[2][9];
        const double *pt[2][3];
        for (int h = 0; h < 2; ++h) {
            for (int i = 0; i < 3; ++i) {
                const int from = i < n[h] ? i : n[h] - 1; /* repeated corners */
                double *x = &v[h][3 * i];
                if (from == i)
                    for (int a = 0; a < 3; ++a) x[a] = a == k ? c : (double)irand(cells + 1) * (2.0 / cells);
                else
                    memcpy(x, &v[h][3 * from], 3 * sizeof(double));
                pt[h][i] = x;
            }
        }
        const int o = oracle_tri_tri(v[0], v[1]);
        assert_int_equal(hgcdi_flat_hulls_meet(k, pt[0], n[0], pt[1], n[1]), o);
        assert_int_equal(hgcdi_flat_hulls_meet(k, pt[1], n[1], pt[0], n[0]), o);
        if (o) ++hits;
        else ++misses;
    }
    assert_true(hits > iters(5000));
    assert_true(misses > iters(5000));
}

static void test_tt_random_perturbed(void **state) {
    long it;
    int hits = 0, misses = 0;
    (void)state;
    for (it = 0; it < iters(40000); it++) {
        double p[9], q[9];
        int k, n;
        random_grid_tri(p, 4, 0.25);
        random_grid_tri(q, 4, 0.25);
        /* nudge a few coordinates by one ulp (or a tiny power of two) */
        n = 1 + irand(3);
        for (k = 0; k < n; k++) {
            double *t = irand(2) ? p : q;
            int i = irand(9);
            if (irand(2)) t[i] = nextafter(t[i], irand(2) ? INFINITY : -INFINITY);
            else t[i] += (irand(2) ? 1 : -1) * 0x1p-45;
        }
        if (it % 4 == 0) { /* translate far away: same answer expected */
            double tx = 1e12 * (irand(3) - 1);
            int i;
            for (i = 0; i < 9; i += 3) { p[i] += tx; q[i] += tx; }
        }
        cross_check_pair(p, q, &hits, &misses, it);
    }
    print_message("perturbed pairs: %d hits, %d misses\n", hits, misses);
    assert_true(hits > iters(2000));
    assert_true(misses > iters(2000));
}

static void test_tt_random_general(void **state) {
    long it;
    int hits = 0, misses = 0;
    (void)state;
    for (it = 0; it < iters(40000); it++) {
        double p[9], q[9];
        int i;
        double off = it % 2 ? 0.3 : 0.6;
        for (i = 0; i < 9; i++) {
            p[i] = urand();
            q[i] = urand() + off;
        }
        if (it % 10 == 0) { /* zero-area P: collinear by construction */
            double t = urand();
            for (i = 0; i < 3; i++) p[6 + i] = p[i] + t * (p[3 + i] - p[i]);
        }
        if (it % 10 == 1) { /* Q's vertex on P's plane (up to rounding) */
            double s = urand() * 0.5, t = urand() * 0.5;
            for (i = 0; i < 3; i++) q[i] = p[i] + s * (p[3 + i] - p[i]) + t * (p[6 + i] - p[i]);
        }
        cross_check_pair(p, q, &hits, &misses, it);
    }
    print_message("general pairs: %d hits, %d misses\n", hits, misses);
    assert_true(hits > iters(1000));
    assert_true(misses > iters(1000));
}

/* ------------------------------------------------------------------------ */
/* Point in closed mesh                                                      */
/* ------------------------------------------------------------------------ */

/* Voxel meshes: boundary squares of a set of unit cubes in an N^3 grid, two
 * triangles each, outward orientation; vertices indexed on the (N+1)^3
 * lattice (so the mesh is closed in the index sense). */
#define VN 6
typedef struct {
    double verts[2 * 3 * (VN + 1) * (VN + 1) * (VN + 1)]; /* two lattices */
    uint32_t tris[3 * 12 * VN * VN * VN * 2];
    uint32_t vertex_count, tri_count;
} vmesh;

static uint32_t lat(int x, int y, int z) {
    return (uint32_t)((x * (VN + 1) + y) * (VN + 1) + z);
}

static int vox_in(const unsigned char *s, int x, int y, int z) {
    if (x < 0 || y < 0 || z < 0 || x >= VN || y >= VN || z >= VN) return 0;
    return s[(x * VN + y) * VN + z];
}

static void vm_quad(vmesh *m, uint32_t a, uint32_t b, uint32_t c, uint32_t d,
                    int flip) {
    uint32_t *t = m->tris + 3 * m->tri_count;
    if (flip) { uint32_t w = b; b = d; d = w; }
    t[0] = a; t[1] = b; t[2] = c;
    t[3] = a; t[4] = c; t[5] = d;
    m->tri_count += 2;
}

/* Adds the boundary of voxel set s (offset o, scale h, inverted if inv). */
static void vm_add(vmesh *m, const unsigned char *s, double h, double ox,
                   double oy, double oz, int inv) {
    int x, y, z;
    uint32_t base = m->vertex_count;
    for (x = 0; x <= VN; x++)
        for (y = 0; y <= VN; y++)
            for (z = 0; z <= VN; z++) {
                double *v = m->verts + 3 * (base + lat(x, y, z));
                v[0] = ox + h * x; v[1] = oy + h * y; v[2] = oz + h * z;
            }
    m->vertex_count += (VN + 1) * (VN + 1) * (VN + 1);
    for (x = 0; x < VN; x++)
        for (y = 0; y < VN; y++)
            for (z = 0; z < VN; z++) {
                if (!vox_in(s, x, y, z)) continue;
                /* -x face: outward normal -x; ccw seen from outside */
                if (!vox_in(s, x - 1, y, z))
                    vm_quad(m, base + lat(x, y, z), base + lat(x, y, z + 1), base + lat(x, y + 1, z + 1), base + lat(x, y + 1, z), inv);
                if (!vox_in(s, x + 1, y, z))
                    vm_quad(m, base + lat(x + 1, y, z), base + lat(x + 1, y + 1, z), base + lat(x + 1, y + 1, z + 1), base + lat(x + 1, y, z + 1), inv);
                if (!vox_in(s, x, y - 1, z))
                    vm_quad(m, base + lat(x, y, z), base + lat(x + 1, y, z), base + lat(x + 1, y, z + 1), base + lat(x, y, z + 1), inv);
                if (!vox_in(s, x, y + 1, z))
                    vm_quad(m, base + lat(x, y + 1, z), base + lat(x, y + 1, z + 1), base + lat(x + 1, y + 1, z + 1), base + lat(x + 1, y + 1, z), inv);
                if (!vox_in(s, x, y, z - 1))
                    vm_quad(m, base + lat(x, y, z), base + lat(x, y + 1, z), base + lat(x + 1, y + 1, z), base + lat(x + 1, y, z), inv);
                if (!vox_in(s, x, y, z + 1))
                    vm_quad(m, base + lat(x, y, z + 1), base + lat(x + 1, y, z + 1), base + lat(x + 1, y + 1, z + 1), base + lat(x, y + 1, z + 1), inv);
            }
}

static int check_pim(const double *p, const vmesh *m) {
    int o = oracle_point_in_closed_mesh(p, m->verts, m->vertex_count, m->tris, m->tri_count);
    int h = hgcdi_point_in_closed_mesh(p, m->verts, m->vertex_count, m->tris, m->tri_count);
    assert_true(o == 0 || o == 1);
    if (h != o) {
        print_error("point_in_closed_mesh mismatch at (%a, %a, %a): %d vs %d\n", p[0], p[1], p[2], h, o);
        fail();
    }
    return h;
}

/* Checks every voxel centre, and points in the lattice planes, lines and
 * vertices around which all voxels have the same status (so the point lies
 * in the plane of faces, or on the line of edges, of the mesh without being
 * on its surface). */
static void check_voxels(const vmesh *m, const unsigned char *s) {
    int x, y, z, dx, dy, dz;
    for (x = -1; x <= VN; x++)
        for (y = -1; y <= VN; y++)
            for (z = -1; z <= VN; z++) {
                double p[3];
                int in = vox_in(s, x, y, z);
                set3(p, x + 0.5, y + 0.5, z + 0.5);
                assert_int_equal(check_pim(p, m), in);
                /* the 7 other lattice points (x+1 or x+.5, ...) */
                for (dx = 0; dx < 2; dx++)
                    for (dy = 0; dy < 2; dy++)
                        for (dz = 0; dz < 2; dz++) {
                            int same = 1, a, b, c;
                            if (!dx && !dy && !dz) continue;
                            for (a = 0; a <= dx; a++)
                                for (b = 0; b <= dy; b++)
                                    for (c = 0; c <= dz; c++)
                                        same &= vox_in(s, x + a, y + b, z + c) == in;
                            if (!same) continue;
                            set3(p, x + (dx ? 1.0 : 0.5), y + (dy ? 1.0 : 0.5), z + (dz ? 1.0 : 0.5));
                            assert_int_equal(check_pim(p, m), in);
                        }
            }
}

static void test_pim_cube(void **state) {
    static vmesh m;
    unsigned char s[VN * VN * VN];
    double p[3];
    (void)state;
    memset(&m, 0, sizeof m);
    memset(s, 0, sizeof s);
    s[(1 * VN + 1) * VN + 1] = 1;
    vm_add(&m, s, 1.0, 0, 0, 0, 0);
    assert_int_equal(m.tri_count, 12);
    assert_int_equal(oracle_mesh_is_closed(m.tris, m.tri_count), 1);
    set3(p, 1.5, 1.5, 1.5);
    assert_int_equal(check_pim(p, &m), 1);
    set3(p, 2.5, 1.5, 1.5);
    assert_int_equal(check_pim(p, &m), 0);
    set3(p, 1.5, 1.5, 0.5);
    assert_int_equal(check_pim(p, &m), 0);
    set3(p, 1.0 + 0x1p-52, 1.5, 1.5); /* just inside a face */
    assert_int_equal(check_pim(p, &m), 1);
    set3(p, nextafter(1.0, 0), 1.5, 1.5); /* just outside */
    assert_int_equal(check_pim(p, &m), 0);
    set3(p, 1.5, 1.5, 3); /* in the plane of nothing, outside */
    assert_int_equal(check_pim(p, &m), 0);
    set3(p, 2, 2, 2.5); /* on the line through a cube edge, outside */
    assert_int_equal(check_pim(p, &m), 0);
    check_voxels(&m, s);
    /* convex test on the same cube: outward ccw faces, inward sign +1 */
    set3(p, 1.5, 1.5, 1.5);
    assert_int_equal(hgcdi_point_in_convex(p, m.verts, m.tris, m.tri_count, 1), 1);
    set3(p, 1.5, 2.5, 1.5);
    assert_int_equal(hgcdi_point_in_convex(p, m.verts, m.tris, m.tri_count, 1), 0);
    set3(p, 1.0 + 0x1p-52, 1.5, 1.999);
    assert_int_equal(hgcdi_point_in_convex(p, m.verts, m.tris, m.tri_count, 1), 1);
    set3(p, 1.5, 1.5, 2 + 0x1p-51);
    assert_int_equal(hgcdi_point_in_convex(p, m.verts, m.tris, m.tri_count, 1), 0);
    /* inverted orientation: inward sign -1 */
    {
        static vmesh mi;
        memset(&mi, 0, sizeof mi);
        vm_add(&mi, s, 1.0, 0, 0, 0, 1);
        set3(p, 1.5, 1.5, 1.5);
        assert_int_equal(hgcdi_point_in_convex(p, mi.verts, mi.tris, mi.tri_count, -1), 1);
        assert_int_equal(hgcdi_point_in_convex(p, mi.verts, mi.tris, mi.tri_count, 1), 0);
        assert_int_equal(check_pim(p, &mi), 1); /* parity ignores orientation */
    }
}

static void test_pim_nonconvex(void **state) {
    static vmesh m;
    unsigned char s[VN * VN * VN];
    int x, y, z;
    (void)state;
    /* L-shape */
    memset(&m, 0, sizeof m);
    memset(s, 0, sizeof s);
    for (x = 0; x < 3; x++) s[(x * VN + 0) * VN + 0] = 1;
    for (y = 0; y < 3; y++) s[(0 * VN + y) * VN + 0] = 1;
    vm_add(&m, s, 1.0, 0, 0, 0, 0);
    assert_int_equal(oracle_mesh_is_closed(m.tris, m.tri_count), 1);
    check_voxels(&m, s);
    /* torus-like ring around a hole, two layers */
    memset(&m, 0, sizeof m);
    memset(s, 0, sizeof s);
    for (x = 1; x < 4; x++)
        for (y = 1; y < 4; y++)
            for (z = 1; z < 3; z++)
                if (!(x == 2 && y == 2)) s[(x * VN + y) * VN + z] = 1;
    vm_add(&m, s, 1.0, 0, 0, 0, 0);
    assert_int_equal(oracle_mesh_is_closed(m.tris, m.tri_count), 1);
    check_voxels(&m, s);
    /* random voxel blobs (non-manifold edges included: still closed) */
    for (x = 0; x < 6; x++) {
        int i;
        memset(&m, 0, sizeof m);
        for (i = 0; i < VN * VN * VN; i++) s[i] = irand(3) == 0;
        vm_add(&m, s, 0.5, -1.25, 0.75, 3, x & 1);
        assert_int_equal(oracle_mesh_is_closed(m.tris, m.tri_count), 1);
        /* check voxel centres in the scaled frame */
        for (i = 0; i < 300; i++) {
            int a = irand(VN + 2) - 1, b = irand(VN + 2) - 1, c = irand(VN + 2) - 1;
            double p[3];
            set3(p, -1.25 + 0.5 * a + 0.25, 0.75 + 0.5 * b + 0.25, 3 + 0.5 * c + 0.25);
            assert_int_equal(check_pim(p, &m), vox_in(s, a, b, c));
        }
    }
}

/* Voxel blobs under a rotation (inexact coordinates: general position, no
 * axis-aligned coincidences); voxel centres stay half a cell from the
 * surface, so the voxel membership is still the answer. */
static void test_pim_rotated(void **state) {
    static vmesh m;
    unsigned char s[VN * VN * VN];
    int rep, i;
    /* rotation from the unit quaternion (1, 2, 3, 4) / sqrt(30) */
    const double qx = 1 / sqrt(30.0), qy = 2 / sqrt(30.0), qz = 3 / sqrt(30.0), qw = 4 / sqrt(30.0);
    const double R[3][3] = {
        {1 - 2 * (qy * qy + qz * qz), 2 * (qx * qy - qz * qw), 2 * (qx * qz + qy * qw)},
        {2 * (qx * qy + qz * qw), 1 - 2 * (qx * qx + qz * qz), 2 * (qy * qz - qx * qw)},
        {2 * (qx * qz - qy * qw), 2 * (qy * qz + qx * qw), 1 - 2 * (qx * qx + qy * qy)}};
    (void)state;
    for (rep = 0; rep < 4; rep++) {
        memset(&m, 0, sizeof m);
        for (i = 0; i < VN * VN * VN; i++) s[i] = irand(2);
        vm_add(&m, s, 1.0, 0, 0, 0, rep & 1);
        for (i = 0; i < (int)m.vertex_count; i++) {
            double *v = m.verts + 3 * i, w[3];
            int k;
            for (k = 0; k < 3; k++) w[k] = R[k][0] * v[0] + R[k][1] * v[1] + R[k][2] * v[2] + 100.0;
            memcpy(v, w, sizeof w);
        }
        for (i = 0; i < 400; i++) {
            int a = irand(VN + 2) - 1, b = irand(VN + 2) - 1, c = irand(VN + 2) - 1, k;
            double p[3] = {a + 0.5, b + 0.5, c + 0.5}, w[3];
            for (k = 0; k < 3; k++) w[k] = R[k][0] * p[0] + R[k][1] * p[1] + R[k][2] * p[2] + 100.0;
            assert_int_equal(check_pim(w, &m), vox_in(s, a, b, c));
        }
    }
}

static void test_pim_nested_shells(void **state) {
    static vmesh m;
    unsigned char outer[VN * VN * VN], inner[VN * VN * VN];
    int x, y, z;
    double p[3];
    (void)state;
    memset(&m, 0, sizeof m);
    memset(outer, 0, sizeof outer);
    memset(inner, 0, sizeof inner);
    for (x = 0; x < 5; x++)
        for (y = 0; y < 5; y++)
            for (z = 0; z < 5; z++) outer[(x * VN + y) * VN + z] = 1;
    for (x = 1; x < 4; x++)
        for (y = 1; y < 4; y++)
            for (z = 1; z < 4; z++) inner[(x * VN + y) * VN + z] = 1;
    vm_add(&m, outer, 1.0, 0, 0, 0, 0);
    vm_add(&m, inner, 1.0, 0, 0, 0, 1); /* inverted: a cavity */
    assert_int_equal(oracle_mesh_is_closed(m.tris, m.tri_count), 1);
    set3(p, 2.5, 2.5, 2.5);
    assert_int_equal(check_pim(p, &m), 0); /* in the cavity */
    set3(p, 0.5, 2.5, 2.5);
    assert_int_equal(check_pim(p, &m), 1); /* in the shell */
    set3(p, 2, 2, 2);                      /* cavity, on lattice lines */
    assert_int_equal(check_pim(p, &m), 0);
    set3(p, 0.5, 0.5, 0.5);
    assert_int_equal(check_pim(p, &m), 1);
    set3(p, 5.5, 2.5, 2.5);
    assert_int_equal(check_pim(p, &m), 0);
    for (x = 0; x < 500; x++) {
        double q[3];
        int a, b, c, want;
        set3(q, urand() * 6 - 0.5, urand() * 6 - 0.5, urand() * 6 - 0.5);
        a = (int)floor(q[0]); b = (int)floor(q[1]); c = (int)floor(q[2]);
        want = vox_in(outer, a, b, c) && !vox_in(inner, a, b, c);
        assert_int_equal(check_pim(q, &m), want);
    }
}

/* The first generic direction of src/ passes exactly through a mesh vertex:
 * the attempt is degenerate and must be retried. Box x in [-0.5, 1],
 * y, z in [-0.75, 0.75] gives extent 1.5, so the segment from the origin
 * ends at q = 4 * dir0 and passes through dir0 = (1, dy, dz) exactly; the
 * face x = 1 is a fan around the vertex (1, dy, dz). */
static void test_pim_degenerate_ray(void **state) {
    const double dy = 0.0935817916500935, dz = -0.016930054247476733;
    double verts[3 * 9];
    uint32_t tris[3 * 14];
    uint32_t n = 0;
    double p[3] = {0, 0, 0};
    int i;
    /* corners: index = 4*xi... use explicit list */
    const double xs[2] = {-0.5, 1}, ys[2] = {-0.75, 0.75}, zs[2] = {-0.75, 0.75};
    (void)state;
    for (i = 0; i < 8; i++) set3(verts + 3 * i, xs[(i >> 2) & 1], ys[(i >> 1) & 1], zs[i & 1]);
    set3(verts + 24, 1, dy, dz); /* vertex 8 on face x = 1 */
#define T(a, b, c) (tris[3 * n] = (a), tris[3 * n + 1] = (b), tris[3 * n + 2] = (c), n++)
    /* x = -0.5 face (0,1,2,3): outward -x */
    T(0, 1, 3); T(0, 3, 2);
    /* x = 1 face (4,5,6,7) as a fan around 8: outward +x */
    T(8, 4, 6); T(8, 6, 7); T(8, 7, 5); T(8, 5, 4);
    /* y = -0.75 face (0,1,4,5) */
    T(0, 4, 5); T(0, 5, 1);
    /* y = 0.75 face (2,3,6,7) */
    T(2, 3, 7); T(2, 7, 6);
    /* z = -0.75 face (0,2,4,6) */
    T(0, 2, 6); T(0, 6, 4);
    /* z = 0.75 face (1,3,5,7) */
    T(1, 5, 7); T(1, 7, 3);
#undef T
    assert_int_equal(oracle_mesh_is_closed(tris, n), 1);
    {
        /* the segment of src/'s first attempt really passes through vertex 8 */
        double q[3] = {4.0, 4 * dy, 4 * dz}, pt[9];
        memcpy(pt, verts + 24, 3 * sizeof(double));
        memcpy(pt + 3, verts + 24, 3 * sizeof(double));
        memcpy(pt + 6, verts + 24, 3 * sizeof(double));
        assert_int_equal(oracle_segment_triangle(p, q, pt), 1);
        assert_int_equal(hgcdi_segment_triangle(p, q, pt), 1);
    }
    assert_int_equal(hgcdi_point_in_closed_mesh(p, verts, 9, tris, n), 1);
    assert_int_equal(oracle_point_in_closed_mesh(p, verts, 9, tris, n), 1);
    set3(p, 0.5, 0.5 * dy, 0.5 * dz);
    assert_int_equal(hgcdi_point_in_closed_mesh(p, verts, 9, tris, n), 1);
    set3(p, 1.25, 0, 0);
    assert_int_equal(hgcdi_point_in_closed_mesh(p, verts, 9, tris, n), 0);
    assert_int_equal(oracle_point_in_closed_mesh(p, verts, 9, tris, n), 0);
}

/* ------------------------------------------------------------------------ */
/* Scene oracle sanity (the oracle checks itself against a brute force over  */
/* all pairs built from hgcd's predicates).                                  */
/* ------------------------------------------------------------------------ */

static const double kTetVerts[12] = {1, 1, 1, 1, -1, -1, -1, 1, -1, -1, -1, 1};
static const uint32_t kTetTris[12] = {0, 1, 2, 0, 3, 1, 0, 2, 3, 1, 3, 2};

static void test_scene_oracle_small(void **state) {
    enum { N = 400 };
    static double pos[3 * N], ori[4 * N], sc[N];
    static uint32_t pairs[2 * N * N];
    static double wv[N][12];
    const oracle_mesh *meshes[N];
    oracle_mesh tet = {kTetVerts, kTetTris, 4, 4, 1};
    size_t count, i, j, brute = 0, k;
    (void)state;
    assert_int_equal(oracle_mesh_is_closed(kTetTris, 4), 1);
    for (i = 0; i < N; i++) {
        double u1 = urand(), u2 = urand(), u3 = urand();
        meshes[i] = &tet;
        set3(pos + 3 * i, urand() * 6, urand() * 6, urand() * 6);
        ori[4 * i] = sqrt(1 - u1) * sin(2 * M_PI * u2);
        ori[4 * i + 1] = sqrt(1 - u1) * cos(2 * M_PI * u2);
        ori[4 * i + 2] = sqrt(u1) * sin(2 * M_PI * u3);
        ori[4 * i + 3] = sqrt(u1) * cos(2 * M_PI * u3);
        sc[i] = (0.1 + urand() * 0.6) / sqrt(3.0);
        if (i % 50 == 7) sc[i] = 2.0; /* a few big ones to swallow others */
        for (k = 0; k < 4; k++) oracle_world_vertex(pos + 3 * i, ori + 4 * i, sc[i], kTetVerts + 3 * k, wv[i] + 3 * k);
    }
    count = oracle_colliding_pairs(N, meshes, pos, ori, sc, pairs, (size_t)N * N);
    assert_true(count > 50);
    assert_true(oracle_last_containment_pairs() > 0);
    /* brute force with hgcd's predicates over all pairs */
    for (i = 0; i < N; i++) {
        for (j = i + 1; j < N; j++) {
            int hit = 0, a, b;
            for (a = 0; a < 4 && !hit; a++) {
                for (b = 0; b < 4 && !hit; b++) {
                    double P[9], Q[9];
                    int c;
                    for (c = 0; c < 9; c++) {
                        P[c] = wv[i][3 * kTetTris[3 * a + c / 3] + c % 3];
                        Q[c] = wv[j][3 * kTetTris[3 * b + c / 3] + c % 3];
                    }
                    hit = hgcdi_tri_tri(P, Q);
                }
            }
            if (!hit) {
                hit = hgcdi_point_in_closed_mesh(wv[j], wv[i], 4, kTetTris, 4) ||
                      hgcdi_point_in_closed_mesh(wv[i], wv[j], 4, kTetTris, 4);
            }
            if (hit) {
                assert_true(brute < count);
                assert_int_equal(pairs[2 * brute], i);
                assert_int_equal(pairs[2 * brute + 1], j);
                brute++;
            }
        }
    }
    assert_int_equal(brute, count);
}

/* The reference answer of docs/scenes.md: tetra scene, n = 100000, seed 1,
 * initial poses: 4266 colliding pairs, 30 by containment. */
static uint64_t sm_state;
static uint64_t sm_next(void) {
    uint64_t z = (sm_state += 0x9E3779B97F4A7C15ull);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return z ^ (z >> 31);
}
static double sm_u(void) { return (double)(sm_next() >> 11) * 0x1p-53; }

static void test_scene_oracle_tetra_reference(void **state) {
    size_t n = 100000, i, count;
    double *pos = (double *)malloc(sizeof(double) * 3 * n);
    double *ori = (double *)malloc(sizeof(double) * 4 * n);
    double *sc = (double *)malloc(sizeof(double) * n);
    const oracle_mesh **meshes = (const oracle_mesh **)malloc(sizeof(*meshes) * n);
    oracle_mesh tet = {kTetVerts, kTetTris, 4, 4, 1};
    const double L = 200, rmin = 0.25, rmax = 2.0, vmax = 0.05;
    (void)state;
    if (getenv("HGCD_SKIP_SLOW_TESTS")) { /* about 3 s, 40 s under ASan */
        free(pos); free(ori); free(sc); free(meshes);
        skip();
    }
    assert_non_null(pos);
    assert_non_null(ori);
    assert_non_null(sc);
    assert_non_null(meshes);
    sm_state = 1;
    for (i = 0; i < n; i++) {
        double cx = L * sm_u(), cy = L * sm_u(), cz = L * sm_u();
        double r = rmin * pow(rmax / rmin, sm_u());
        double u1 = sm_u(), u2 = sm_u(), u3 = sm_u();
        double a2 = (2.0 * M_PI) * u2, a3 = (2.0 * M_PI) * u3;
        (void)(vmax * (2 * sm_u() - 1));
        (void)(vmax * (2 * sm_u() - 1));
        (void)(vmax * (2 * sm_u() - 1));
        set3(pos + 3 * i, cx, cy, cz);
        ori[4 * i] = sqrt(1 - u1) * sin(a2);
        ori[4 * i + 1] = sqrt(1 - u1) * cos(a2);
        ori[4 * i + 2] = sqrt(u1) * sin(a3);
        ori[4 * i + 3] = sqrt(u1) * cos(a3);
        sc[i] = r / sqrt(3.0);
        meshes[i] = &tet;
    }
    count = oracle_colliding_pairs(n, meshes, pos, ori, sc, NULL, 0);
    print_message("tetra n=100000: %zu pairs, %zu by containment\n", count,
                  oracle_last_containment_pairs());
    assert_int_equal(count, 4266);
    assert_int_equal(oracle_last_containment_pairs(), 30);
    free(pos);
    free(ori);
    free(sc);
    free(meshes);
}

int main(void) {
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_orient3d_basic),
        cmocka_unit_test(test_orient3d_ulp_perturbed),
        cmocka_unit_test(test_orient3d_large_coordinates),
        cmocka_unit_test(test_orient3d_extreme_ranges),
        cmocka_unit_test(test_orient3d_random_near_degenerate),
        cmocka_unit_test(test_orient2d),
        cmocka_unit_test(test_tt_vertex_vertex),
        cmocka_unit_test(test_tt_vertex_on_edge),
        cmocka_unit_test(test_tt_vertex_in_face),
        cmocka_unit_test(test_tt_edge_edge),
        cmocka_unit_test(test_tt_collinear_edges),
        cmocka_unit_test(test_tt_coplanar),
        cmocka_unit_test(test_flat_hulls),
        cmocka_unit_test(test_tt_shared_edge_vertex),
        cmocka_unit_test(test_tt_near_parallel),
        cmocka_unit_test(test_tt_zero_area),
        cmocka_unit_test(test_segment_triangle),
        cmocka_unit_test(test_tt_random_grid),
        cmocka_unit_test(test_tt_random_perturbed),
        cmocka_unit_test(test_tt_random_general),
        cmocka_unit_test(test_pim_cube),
        cmocka_unit_test(test_pim_nonconvex),
        cmocka_unit_test(test_pim_nested_shells),
        cmocka_unit_test(test_pim_rotated),
        cmocka_unit_test(test_pim_degenerate_ray),
        cmocka_unit_test(test_scene_oracle_small),
        cmocka_unit_test(test_scene_oracle_tetra_reference),
    };
    if (getenv("HGCD_TEST_FILTER")) cmocka_set_test_filter(getenv("HGCD_TEST_FILTER"));
    return cmocka_run_group_tests(tests, NULL, NULL);
}
