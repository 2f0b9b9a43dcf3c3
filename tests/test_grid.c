/* The broad phase alone (src/grid.cpp through src/testing.h) against brute
 * force: every pair of bodies whose boxes overlap (closed intervals on every
 * axis; a body (x, y, z, r) is the box [x + lo, x + hi] per axis with lo, hi
 * = -r, r rounded outward to float, as the hook builds it) must be reported,
 * and nothing else. Scenes aim at the grid's shortcuts: the dense coarse
 * levels where the reach filter skips neighbouring rows, boxes touching
 * exactly across cell faces, positions on cell faces, far-out coordinates,
 * incremental updates after motion, several thread counts, with and without
 * the coarsening of close levels (GridLimits::coarsen). */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#include "../src/testing.h"
#include "test_rng.h"

static int cmp_u64(const void *a, const void *b) {
    const uint64_t x = *(const uint64_t *)a, y = *(const uint64_t *)b;
    return x < y ? -1 : x > y;
}

/* r rounded outward to float: the nearest float, one step out if inside. */
static double out_lo(double r) {
    float f = (float)-r;
    if ((double)f > -r) f = nextafterf(f, -INFINITY);
    return (double)f;
}
static double out_hi(double r) {
    float f = (float)r;
    if ((double)f < r) f = nextafterf(f, INFINITY);
    return (double)f;
}

/* Whether the boxes of bodies a and b (4 doubles each) overlap; *touch is
 * set when they do with some face against another exactly. */
static int boxes_overlap(const double *a, const double *b, int *touch) {
    int meet = 1, face = 0;
    for (int k = 0; k < 3; ++k) {
        const double alo = a[k] + out_lo(a[3]), ahi = a[k] + out_hi(a[3]);
        const double blo = b[k] + out_lo(b[3]), bhi = b[k] + out_hi(b[3]);
        meet &= alo <= bhi && blo <= ahi;
        face |= alo == bhi || blo == ahi;
    }
    if (touch) *touch = meet && face;
    return meet;
}

/* Brute force over all pairs, sorted. */
static uint64_t brute(const double *s, uint32_t n, uint64_t **out) {
    uint64_t cap = 1024, m = 0;
    uint64_t *p = malloc(cap * sizeof *p);
    assert_non_null(p);
    for (uint32_t i = 0; i < n; ++i)
        for (uint32_t j = i + 1; j < n; ++j) {
            if (boxes_overlap(s + 4 * (size_t)i, s + 4 * (size_t)j, NULL)) {
                if (m == cap) {
                    cap *= 2;
                    p = realloc(p, cap * sizeof *p);
                    assert_non_null(p);
                }
                p[m++] = ((uint64_t)i << 32) | j;
            }
        }
    qsort(p, m, sizeof *p, cmp_u64);
    *out = p;
    return m;
}

/* The grid's pairs for `after` (built from `before` first, if given) equal
 * brute force, for 1, 2 and 3 threads. Returns the pair count. */
static uint64_t check(const double *before, const double *after, uint32_t n, const char *what) {
    uint64_t *want;
    const uint64_t m = brute(after, n, &want);
    uint64_t *got = malloc((m + 16) * sizeof *got);
    assert_non_null(got);
    for (int variant = 0; variant < 6; ++variant) {
        const int threads = 1 + variant % 3, coarsen = variant / 3;
        const int64_t k = hgcdi_grid_pairs(before, after, n, threads, coarsen, got, m + 16);
        if (k != (int64_t)m || memcmp(got, want, m * sizeof *got) != 0) {
            uint64_t i = 0;
            while (i < m && k > (int64_t)i && got[i] == want[i]) ++i;
            fail_msg("%s, %d threads, coarsen %d: grid %lld pairs, brute force %llu; first difference at "
                     "%llu: grid %llx, brute %llx", what, threads, coarsen, (long long)k, (unsigned long long)m,
                     (unsigned long long)i, i < (uint64_t)k ? (unsigned long long)got[i] : 0ull,
                     i < m ? (unsigned long long)want[i] : 0ull);
        }
    }
    free(got);
    free(want);
    return m;
}

static void test_row_sorted_outright(void **state) {
    (void)state;
    /* A row whose order changes too much for the update's insertion sort is
     * sorted outright; the running largest high x that the sweeps of the
     * row before it start from must then be those of the new order. Row B
     * (y = +0.3, z = 0.5): boxes of half side 1.1 along x, one of 1.95 at
     * the far right; then the second half of the row reversed (more
     * inversions than the insertion sort takes on) and the big box moved to
     * the far left, where its high x is the largest of the row's first
     * entries. Row A (y just below 0, across the row boundary y = 0 at
     * every level, earlier in the sweep) has boxes whose low x fall between
     * the first small boxes' high x and the big one's. (With the floors of
     * the old order, test_far_coordinates fails too.) */
    enum { NB = 160, NA = 40, N = NB + 1 + NA };
    static double before[4 * N], after[4 * N];
    for (int i = 0; i < NB; ++i) {
        const double x = 0.2 * i;
        double *b = before + 4 * i, *a = after + 4 * i;
        b[0] = x, b[1] = 0.3, b[2] = 0.5, b[3] = 1.1;
        a[0] = i < NB / 2 ? x : 0.2 * (NB / 2) + 0.2 * (NB - 1 - i), a[1] = 0.3, a[2] = 0.5, a[3] = 1.1;
    }
    double *big_b = before + 4 * NB, *big_a = after + 4 * NB;
    big_b[0] = 0.2 * NB + 5, big_b[1] = 0.3, big_b[2] = 0.5, big_b[3] = 1.95;
    big_a[0] = -0.2, big_a[1] = 0.3, big_a[2] = 0.5, big_a[3] = 1.95;  /* high x 1.75 */
    for (int i = 0; i < NA; ++i) {
        double *b = before + 4 * (NB + 1 + i), *a = after + 4 * (NB + 1 + i);
        /* low x 1.15 .. 1.64, above the first small boxes' high x (1.1,
         * 1.3, 1.5) but within the big box's (a finer body: a guest of the
         * level, or a resident where levels join) */
        a[0] = b[0] = 1.45 + 0.0125 * i, a[1] = b[1] = -0.05 - 0.001 * i, a[2] = b[2] = 0.5, a[3] = b[3] = 0.3;
    }
    assert_true(check(before, after, N, "row sorted outright") > NB);
}

/* Scene tetra's mix: log-uniform sizes over three octaves, at its density
 * (the coarsest level holds about two bodies per cell), moved by up to 0.3. */
static void test_dense_mixed_levels(void **state) {
    (void)state;
    const uint32_t n = 12000;
    const double side = 50.0;
    double *a = malloc(4 * sizeof(double) * n), *b = malloc(4 * sizeof(double) * n);
    rng r = {7};
    for (uint32_t i = 0; i < n; ++i) {
        for (int k = 0; k < 3; ++k) a[4 * i + k] = side * unif(&r);
        a[4 * i + 3] = 0.25 * pow(8.0, unif(&r));
        for (int k = 0; k < 3; ++k) b[4 * i + k] = a[4 * i + k] + 0.3 * (2 * unif(&r) - 1);
        b[4 * i + 3] = a[4 * i + 3];
    }
    const uint64_t m = check(NULL, a, n, "dense, built");
    assert_true(m > 5000);  /* the scene is dense enough to mean something */
    check(a, b, n, "dense, moved");
    free(a);
    free(b);
}

/* Positions on a lattice of step 1/4 (so on cell faces of every level from
 * 1/4 up), half sides powers of two and their sums (exact in float), many
 * pairs of boxes exactly touching, which the test counts as overlapping. */
static void fill_lattice(double *s, uint32_t n, double offset, uint64_t seed) {
    static const double radii[] = {0.125, 0.25, 0.5, 0.75, 1.0, 1.5, 2.0};
    rng r = {seed};
    for (uint32_t i = 0; i < n; ++i) {
        for (int k = 0; k < 3; ++k) s[4 * i + k] = offset + 0.25 * (double)(next(&r) % 48) - 4.0;
        s[4 * i + 3] = radii[next(&r) % 7];
    }
}

static void test_touching_on_cell_faces(void **state) {
    (void)state;
    const uint32_t n = 6000;
    double *a = malloc(4 * sizeof(double) * n), *b = malloc(4 * sizeof(double) * n);
    fill_lattice(a, n, 0.0, 11);
    uint64_t touching = 0;
    for (uint32_t i = 0; i < n; ++i)  /* some pairs are exactly touching */
        for (uint32_t j = i + 1; j < n; ++j) {
            int touch;
            boxes_overlap(a + 4 * i, a + 4 * j, &touch);
            touching += (uint64_t)touch;
        }
    assert_true(touching > 50);
    check(NULL, a, n, "lattice");
    /* Moved by whole lattice steps: bodies change cells, stay on faces. */
    memcpy(b, a, 4 * sizeof(double) * n);
    rng r = {12};
    for (uint32_t i = 0; i < n; ++i)
        for (int k = 0; k < 3; ++k) b[4 * i + k] += 0.25 * (double)((int)(next(&r) % 5) - 2);
    check(a, b, n, "lattice, moved by lattice steps");
    free(a);
    free(b);
}

/* The same lattice far from the origin and on the negative side: cell
 * coordinates are large, and at 2^45 the fine levels' keys saturate. */
static void test_far_coordinates(void **state) {
    (void)state;
    const uint32_t n = 3000;
    double *a = malloc(4 * sizeof(double) * n);
    static const double offsets[] = {-1000.0, 1048576.0, -0x1p40, 0x1p45, 1e12 + 0.5};
    for (size_t k = 0; k < sizeof offsets / sizeof *offsets; ++k) {
        char what[64];
        snprintf(what, sizeof what, "lattice at %g", offsets[k]);
        fill_lattice(a, n, offsets[k], 20 + k);
        check(NULL, a, n, what);
    }
    free(a);
}

/* Half sides that are not powers of two (but exact in float), with one box
 * exactly reaching the face of its cell from either side, along each axis,
 * the other touching it there, or just apart, or just overlapping. */
static void test_reach_exactly_to_faces(void **state) {
    (void)state;
    enum { n = 4000 };
    static double s[4 * n];
    rng r = {31};
    for (uint32_t i = 0; i < n; i += 2) {
        const int axis = (int)(next(&r) % 3);
        const double w = 4.0;  /* cell width of radii in (1, 2] */
        const double ra = (double)(float)(1.0 + unif(&r)), rb = (double)(float)(0.1 + 0.5 * unif(&r));
        double *p = s + 4 * i, *q = s + 4 * (i + 1);
        for (int k = 0; k < 3; ++k) p[k] = q[k] = w * (double)(next(&r) % 6) + w * unif(&r);
        /* p's position at a face, q beyond it at exactly ra + rb (when that
         * is representable) or just around it. */
        p[axis] = w * (double)(next(&r) % 6);
        const int jitter = (int)(next(&r) % 3) - 1;
        q[axis] = p[axis] - (ra + rb) + jitter * 1e-15;
        p[3] = ra;
        q[3] = rb;
    }
    check(NULL, s, n, "reach to faces");
}

/* A few large boxes among many small ones: the coarse levels hold too few
 * bodies to keep a guest list and query the finer levels instead; moving
 * the scene takes the incremental path with that choice kept, and growing
 * the number of large boxes switches it back (a rebuild). */
static void test_few_large_among_many(void **state) {
    (void)state;
    const uint32_t n = 8000;
    double *a = malloc(4 * sizeof(double) * n), *b = malloc(4 * sizeof(double) * n);
    rng r = {41};
    for (uint32_t i = 0; i < n; ++i) {
        for (int k = 0; k < 3; ++k) a[4 * i + k] = 40.0 * unif(&r);
        const int large = i % 400 == 0;
        a[4 * i + 3] = large ? 2.0 + 14.0 * unif(&r) : 0.1 + 0.3 * unif(&r);
        for (int k = 0; k < 3; ++k) b[4 * i + k] = a[4 * i + k] + 0.5 * (2 * unif(&r) - 1);
        b[4 * i + 3] = a[4 * i + 3];
    }
    check(NULL, a, n, "few large");
    check(a, b, n, "few large, moved");
    for (uint32_t i = 0; i < n; i += 3) b[4 * i + 3] = 2.0 + 6.0 * unif(&r);  /* many large now */
    check(a, b, n, "many large after few");
    free(a);
    free(b);
}

int main(void) {
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_row_sorted_outright),
        cmocka_unit_test(test_dense_mixed_levels),
        cmocka_unit_test(test_touching_on_cell_faces),
        cmocka_unit_test(test_far_coordinates),
        cmocka_unit_test(test_reach_exactly_to_faces),
        cmocka_unit_test(test_few_large_among_many),
    };
    if (getenv("HGCD_TEST_FILTER")) cmocka_set_test_filter(getenv("HGCD_TEST_FILTER"));
    if (getenv("HGCD_TEST_SKIP")) cmocka_set_skip_filter(getenv("HGCD_TEST_SKIP"));
    return cmocka_run_group_tests(tests, NULL, NULL);
}
