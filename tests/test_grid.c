/* The broad phase alone (src/broad through tests/support/testing.h) against brute
 * force: every pair of bodies whose boxes overlap (closed intervals on every
 * axis; a body (x, y, z, r) is the box [x + lo, x + hi] per axis with lo, hi
 * = -r, r rounded outward to float, as the hook builds it) must be reported,
 * once, and nothing whose boxes do not overlap once rounded outward to float
 * (as the grid's lists hold them). Scenes aim at the grid's shortcuts: the dense coarse
 * levels where the reach filter skips neighbouring rows, boxes touching
 * exactly across cell faces, positions on cell faces, far-out coordinates,
 * incremental updates after motion, several thread counts, with and without
 * the coarsening of close levels (GridLimits::coarsen). */
#include <float.h>
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>
#if defined(__SSE2__)
#include <xmmintrin.h>
#endif

#include "support/testing.h"
#include "test_rng.h"

/* v rounded to a float at most, or at least, v (the nearest float, one
 * step out if on the wrong side; magnitudes below FLT_MIN to 0 or
 * -FLT_MIN, 0 or FLT_MIN: grid.hpp's float_at_most and float_at_least). */
static double float_down(double v) {
    if (fabs(v) < FLT_MIN) return signbit(v) ? -FLT_MIN : 0.0;
    float f = (float)v;
    if ((double)f > v) f = nextafterf(f, -INFINITY);
    return (double)f;
}
static double float_up(double v) { return -float_down(-v); }

/* A body's offsets -r and r rounded outward to float, as the hook does. */
static double out_lo(double r) { return float_down(-r); }
static double out_hi(double r) { return float_up(r); }

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

/* Whether boxes a and b (low x y z, high x y z) overlap. */
static int boxes_meet(const double *a, const double *b) {
    return a[0] <= b[3] && b[0] <= a[3] && a[1] <= b[4] && b[1] <= a[4] && a[2] <= b[5] && b[2] <= a[5];
}

/* Brute force over all pairs, sorted: those whose boxes overlap (*must)
 * and those whose boxes overlap once each bound is rounded outward to
 * float, as the grid's lists hold them (*may, a superset). */
static uint64_t brute(const double *s, uint32_t n, uint64_t **must, uint64_t **may, uint64_t *may_count) {
    double *box = malloc(12 * sizeof(double) * (n + 1));  /* per body: double box, float box */
    assert_non_null(box);
    for (uint32_t i = 0; i < n; ++i) {
        const double *a = s + 4 * (size_t)i;
        double *b = box + 12 * (size_t)i;
        for (int k = 0; k < 3; ++k) {
            b[k] = a[k] + out_lo(a[3]);
            b[3 + k] = a[k] + out_hi(a[3]);
            b[6 + k] = float_down(b[k]);
            b[9 + k] = float_up(b[3 + k]);
        }
    }
    uint64_t cap[2] = {1024, 1024}, m[2] = {0, 0};
    uint64_t *p[2] = {malloc(cap[0] * sizeof(uint64_t)), malloc(cap[1] * sizeof(uint64_t))};
    assert_non_null(p[0]);
    assert_non_null(p[1]);
    for (uint32_t i = 0; i < n; ++i)
        for (uint32_t j = i + 1; j < n; ++j) {
            const double *a = box + 12 * (size_t)i, *b = box + 12 * (size_t)j;
            const int in[2] = {boxes_meet(a, b), boxes_meet(a + 6, b + 6)};
            for (int t = 0; t < 2; ++t) {
                if (!in[t]) continue;
                if (m[t] == cap[t]) {
                    cap[t] *= 2;
                    p[t] = realloc(p[t], cap[t] * sizeof(uint64_t));
                    assert_non_null(p[t]);
                }
                p[t][m[t]++] = ((uint64_t)i << 32) | j;
            }
        }
    free(box);
    *must = p[0];
    *may = p[1];
    *may_count = m[1];
    return m[0];
}

/* The hook on 1 thread (the calling thread: a team of one) with subnormals
 * flushed to zero and read as zero (MXCSR FTZ and DAZ, as a host linked
 * with -ffast-math runs), where x86-64 has them; without them, as usual. */
static int64_t grid_pairs_flushing(const double *before, const double *after, uint32_t n, int coarsen,
                                   uint64_t *out, uint64_t cap) {
#if defined(__SSE2__)
    const unsigned saved = _mm_getcsr();
    _mm_setcsr(saved | 0x8040u); /* FTZ (bit 15), DAZ (bit 6) */
    const int64_t k = hgcdi_grid_pairs(before, after, n, 1, coarsen, out, cap);
    _mm_setcsr(saved);
    return k;
#else
    return hgcdi_grid_pairs(before, after, n, 1, coarsen, out, cap);
#endif
}

/* The grid's pairs for `after` (built from `before` first, if given), for
 * 1, 2 and 3 threads: sorted without duplicates, every pair whose boxes
 * overlap, and none whose float-rounded boxes do not. Returns the count of
 * pairs whose boxes overlap. */
static uint64_t check_in(const double *before, const double *after, uint32_t n, const char *what, int ftz) {
    uint64_t *want, *may, may_count;
    const uint64_t m = brute(after, n, &want, &may, &may_count);
    uint64_t *got = malloc((may_count + 16) * sizeof *got);
    assert_non_null(got);
    for (int variant = 0; variant < 6; ++variant) {
        const int threads = ftz ? 1 : 1 + variant % 3, coarsen = variant / 3;
        const int64_t k = ftz ? grid_pairs_flushing(before, after, n, coarsen, got, may_count + 16)
                              : hgcdi_grid_pairs(before, after, n, threads, coarsen, got, may_count + 16);
        if (k < 0 || (uint64_t)k > may_count)
            fail_msg("%s, %d threads, coarsen %d: grid %lld pairs, brute force at most %llu", what, threads,
                     coarsen, (long long)k, (unsigned long long)may_count);
        uint64_t w = 0, v = 0;
        for (int64_t i = 0; i < k; ++i) {
            if (i > 0 && got[i] <= got[i - 1])
                fail_msg("%s, %d threads, coarsen %d: pair %llx reported twice", what, threads, coarsen,
                         (unsigned long long)got[i]);
            while (v < may_count && may[v] < got[i]) ++v;
            if (v == may_count || may[v] != got[i])
                fail_msg("%s, %d threads, coarsen %d: pair %llx reported, but not even its float boxes "
                         "overlap", what, threads, coarsen, (unsigned long long)got[i]);
            if (w < m && want[w] < got[i])
                fail_msg("%s, %d threads, coarsen %d: pair %llx missed (%lld reported, %llu overlap)", what,
                         threads, coarsen, (unsigned long long)want[w], (long long)k, (unsigned long long)m);
            w += w < m && want[w] == got[i];
        }
        if (w < m)
            fail_msg("%s, %d threads, coarsen %d: pair %llx missed (%lld reported, %llu overlap)", what, threads,
                     coarsen, (unsigned long long)want[w], (long long)k, (unsigned long long)m);
    }
    free(got);
    free(want);
    free(may);
    return m;
}

static uint64_t check(const double *before, const double *after, uint32_t n, const char *what) {
    return check_in(before, after, n, what, 0);
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

/* Far from the origin, where floats are 4 apart (x near 2^25): a few large
 * boxes (so few that their level queries the finer one by range) each
 * exactly touch a small box along x, whose low x is not a float. The range
 * query (the small boxes spread over many rows, so that it visits rows
 * rather than testing every box) must allow for the lists' boxes rounded
 * outward below the bound it derives from the query box. */
static void test_queries_far_out(void **state) {
    (void)state;
    enum { small = 8000, large = 8, n = small + 2 * large };
    static double s[4 * n];
    const double x0 = 0x1p25;
    rng r = {53};
    for (uint32_t i = 0; i < small; ++i) {
        s[4 * i] = x0 - 300.0 + 600.0 * unif(&r);
        s[4 * i + 1] = 400.0 * unif(&r);
        s[4 * i + 2] = 400.0 * unif(&r);
        s[4 * i + 3] = 0.375;
    }
    for (uint32_t k = 0; k < large; ++k) {
        double *big = s + 4 * (small + 2 * k), *touch = big + 4;
        big[0] = x0 + 64.0 * k + 7.5; /* low x: x0 + 64 k, a float */
        touch[0] = x0 + 64.0 * k - 0.375; /* high x the same, low x between floats */
        big[1] = touch[1] = 10.0 + 2.0 * k;
        big[2] = touch[2] = 20.0 - 2.0 * k;
        big[3] = 7.5;
        touch[3] = 0.375;
    }
    check(NULL, s, n, "far-out queries");
}

/* Bodies of sizes around FLT_MIN near the origin, whose bounds fall in
 * float's subnormal range, a few of them oversize (a half side that is a
 * power of two leaves no slack in its level), with subnormals flushed to
 * zero: the grid stores no subnormal bound, so every overlap is still
 * found (before, a bound that the rounding stepped to the smallest
 * subnormal read as 0, on the wrong side, and pairs were lost). */
static void test_tiny_with_flush_to_zero(void **state) {
    (void)state;
    enum { n = 1500 };
    static double s[4 * n];
    rng r = {61};
    for (uint32_t i = 0; i < n; ++i) {
        for (int k = 0; k < 3; ++k) s[4 * i + k] = FLT_MIN * (16.0 * unif(&r) - 8.0);
        s[4 * i + 3] = i % 100 == 0 ? 4.0 * FLT_MIN : FLT_MIN * (0.02 + 2.0 * unif(&r));
    }
    check_in(NULL, s, n, "tiny, flushing", 1);
    check(NULL, s, n, "tiny");
}

/* Bodies whose slack (their level's cell width less twice their reach) is
 * 2^-19, so that 4e-16 |p|_1 passes it, and they become oversize, near
 * |p|_1 = 4.77e9: moved along x across that (their rows unchanged), among
 * others that stay. The incremental update must move them out of their
 * level as a rebuild puts them (the hook compares the two grids), and the
 * pairs stay right. */
static void test_oversize_by_motion_along_x(void **state) {
    (void)state;
    enum { n = 600 };
    static double before[4 * n], after[4 * n];
    rng r = {71};
    const double threshold = 0x1p-19 / 4e-16;
    for (uint32_t i = 0; i < n; ++i) {
        double *b = before + 4 * i, *a = after + 4 * i;
        const int near = i % 8 < 4; /* (in runs of four slots: the census takes four at a time) */
        for (int k = 1; k < 3; ++k) a[k] = b[k] = 8.0 * unif(&r);
        /* |p|_1 about 1.5 below the threshold, then about 1.5 above */
        b[0] = near ? threshold - 1.5 - (b[1] + b[2]) : threshold - 40.0 + 20.0 * unif(&r);
        a[0] = b[0] + (near ? 3.0 : 0.25);
        a[3] = b[3] = near ? 1.0 - 0x1p-20 : (double)(float)(0.3 + unif(&r));
    }
    check(before, after, n, "oversize by motion along x");
    check(after, before, n, "back from oversize along x");
}

/* The gather's four-at-a-time box rounding against the one-body rounding,
 * bit for bit: sums that fall exactly on a float, just above and below one
 * (by a double ulp), at float's halfway points, around FLT_MIN and in the
 * subnormal range (which no bound may take), at -0.0 and +0.0, far out, and
 * at random. (On a CPU without AVX2 the kernel does not run: skipped.) */
static void test_float_boxes_kernel(void **state) {
    (void)state;
    enum { n = 4096 };
    static double p[3 * n];
    static float o[6 * n];
    rng r = {83};
    const double special[] = {0.0, -0.0, 1.0, -1.0, FLT_MIN, -FLT_MIN, FLT_MIN / 2, -FLT_MIN / 2,
                              1e-45, -1e-45, 1e-300, -1e-300, 0x1p-126 * (1 - 0x1p-30),
                              1.0 + 0x1p-24, 1.0 + 0x1p-52, 1.0 - 0x1p-53, -(1.0 + 0x1p-24), 3.0e38,
                              1e15, -1e15, 0.1, -0.1, 0x1.000001p0 + 0x1p-25};
    const int specials = (int)(sizeof special / sizeof special[0]);
    for (uint32_t i = 0; i < n; ++i) {
        for (int k = 0; k < 3; ++k) {
            const uint64_t u = next(&r);
            double v;
            switch (u % 4) {
            case 0: v = special[(u >> 8) % (uint64_t)specials]; break;
            case 1: v = ldexp(unif(&r) - 0.5, (int)((u >> 8) % 300) - 150); break;
            case 2: v = (double)(float)(100 * unif(&r) - 50) + ldexp((double)((int)((u >> 8) % 5) - 2), -53); break;
            default: v = 1000.0 * (unif(&r) - 0.5); break;
            }
            p[3 * i + k] = v;
            /* offsets: 0, small, or the negation of the point (sums of 0) */
            const uint64_t w = next(&r) % 4;
            const float lo = w == 0 ? 0.0f : w == 1 ? -(float)unif(&r) : w == 2 ? (float)-v : -FLT_MIN;
            const float hi = w == 0 ? 0.0f : w == 1 ? (float)unif(&r) : w == 2 ? (float)-v : FLT_MIN;
            o[6 * i + k] = lo;
            o[6 * i + 3 + k] = hi;
        }
    }
    const int64_t mismatches = hgcdi_float_boxes_check(p, o, n);
    if (mismatches == -1) skip();
    assert_int_equal(mismatches, 0);
}

/* A body's box offsets, vector against scalar, bit for bit: quaternions
 * with zero and negative zero components (products of -0), tiny and huge
 * scales, points on the axes and at the origin. */
static void test_offset_box_kernel(void **state) {
    (void)state;
    enum { n = 4000, points = 9 };
    static double q[4 * n], s[n];
    rng r = {91};
    const double p[3 * points] = {1, 1, 1, 1, -1, -1, -1, 1, -1, -1, -1, 1, 0, 0, 0, -0.0, 2, -0.0,
                                  0.5, -0.0, 0, 1e-300, -1e300, 3, -2.5, 0.1, 7};
    for (uint32_t i = 0; i < n; ++i) {
        random_unit_quaternion(&r, &q[4 * i]);
        const uint64_t u = next(&r);
        if (u % 3 == 0) q[4 * i + (u >> 8) % 4] = (u >> 16) % 2 ? 0.0 : -0.0;
        if (u % 7 == 0) { q[4 * i] = q[4 * i + 1] = q[4 * i + 2] = (u >> 20) % 2 ? 0.0 : -0.0; q[4 * i + 3] = 1; }
        s[i] = u % 5 == 0 ? 1e-200 : u % 5 == 1 ? 1e200 : 0.1 + 10 * unif(&r);
    }
    /* 1 to 9 points: a mesh record's groups of 4, full and padded. */
    for (uint32_t c = 1; c <= points; ++c) assert_int_equal(hgcdi_offset_box_check(q, s, n, p, c), 0);
    /* A point at the origin alone: every offset a sum of signed zeros. */
    const double origin[2][3] = {{-0.0, -0.0, -0.0}, {0.0, -0.0, 0.0}};
    assert_int_equal(hgcdi_offset_box_check(q, s, n, origin[0], 1), 0);
    assert_int_equal(hgcdi_offset_box_check(q, s, n, origin[1], 1), 0);
}

int main(void) {
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_float_boxes_kernel),
        cmocka_unit_test(test_offset_box_kernel),
        cmocka_unit_test(test_row_sorted_outright),
        cmocka_unit_test(test_dense_mixed_levels),
        cmocka_unit_test(test_touching_on_cell_faces),
        cmocka_unit_test(test_far_coordinates),
        cmocka_unit_test(test_reach_exactly_to_faces),
        cmocka_unit_test(test_few_large_among_many),
        cmocka_unit_test(test_queries_far_out),
        cmocka_unit_test(test_tiny_with_flush_to_zero),
        cmocka_unit_test(test_oversize_by_motion_along_x),
    };
    if (getenv("HGCD_TEST_FILTER")) cmocka_set_test_filter(getenv("HGCD_TEST_FILTER"));
    if (getenv("HGCD_TEST_SKIP")) cmocka_set_skip_filter(getenv("HGCD_TEST_SKIP"));
    return cmocka_run_group_tests(tests, NULL, NULL);
}
