/* Independent exact distance oracle for the contact margin (oracle.h).
 * Plain C99 + GMP rationals, no code shared with src/.
 *
 * Formulation (deliberately different from src/exact/distance.cpp, which
 * decides signs of polynomials in the inputs): the squared distance itself,
 * as an exact rational. Two triangles' squared distance is 0 when they meet
 * (oracle_tri_tri); otherwise it is the least, over the six vertex/triangle
 * and nine edge/edge pairs, of a convex quadratic in two parameters
 * minimised over a parameter polygon (the triangle s, t >= 0, s + t <= 1, or
 * the square [0, 1]^2): its critical point when the 2x2 Gram system is
 * regular and the point lies in the polygon, else the least of the
 * polygon's sides, each a one-parameter quadratic minimised by clamping its
 * critical parameter to [0, 1]. */
#include <gmp.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "oracle.h"

typedef struct {
    mpq_t c[3];
} dv;

static void dv_init(dv *v) { mpq_init(v->c[0]); mpq_init(v->c[1]); mpq_init(v->c[2]); }
static void dv_clear(dv *v) { mpq_clear(v->c[0]); mpq_clear(v->c[1]); mpq_clear(v->c[2]); }

static void dv_dot(mpq_t r, const dv *a, const dv *b) {
    mpq_t t;
    int k;
    mpq_init(t);
    mpq_set_ui(r, 0, 1);
    for (k = 0; k < 3; k++) {
        mpq_mul(t, a->c[k], b->c[k]);
        mpq_add(r, r, t);
    }
    mpq_clear(t);
}

/* |o + s e1 + t e2 - p|^2 into r, all rational. */
static void point_at(mpq_t r, const dv *o, const dv *e1, const dv *e2, const mpq_t s, const mpq_t t, const dv *p) {
    dv x;
    mpq_t u;
    int k;
    dv_init(&x);
    mpq_init(u);
    for (k = 0; k < 3; k++) {
        mpq_sub(x.c[k], o->c[k], p->c[k]);
        mpq_mul(u, s, e1->c[k]);
        mpq_add(x.c[k], x.c[k], u);
        mpq_mul(u, t, e2->c[k]);
        mpq_add(x.c[k], x.c[k], u);
    }
    dv_dot(r, &x, &x);
    mpq_clear(u);
    dv_clear(&x);
}

static void keep_min(mpq_t best, int *have, const mpq_t v) {
    if (!*have || mpq_cmp(v, best) < 0) mpq_set(best, v);
    *have = 1;
}

/* Least |a + s (b - a) - p|^2 over s in [0, 1] (a = b allowed). */
static void point_segment2(mpq_t r, const dv *p, const dv *a, const dv *b) {
    dv e, w, z;
    mpq_t den, num, s, zero;
    int k;
    dv_init(&e); dv_init(&w); dv_init(&z);
    mpq_init(den); mpq_init(num); mpq_init(s); mpq_init(zero);
    for (k = 0; k < 3; k++) {
        mpq_sub(e.c[k], b->c[k], a->c[k]);
        mpq_sub(w.c[k], p->c[k], a->c[k]);
        mpq_set_ui(z.c[k], 0, 1);
    }
    dv_dot(den, &e, &e);
    dv_dot(num, &w, &e);
    if (mpq_sgn(den) == 0 || mpq_sgn(num) <= 0) mpq_set_ui(s, 0, 1);
    else if (mpq_cmp(num, den) >= 0) mpq_set_ui(s, 1, 1);
    else mpq_div(s, num, den);
    point_at(r, a, &e, &z, s, zero, p);
    dv_clear(&e); dv_clear(&w); dv_clear(&z);
    mpq_clear(den); mpq_clear(num); mpq_clear(s); mpq_clear(zero);
}

/* Least of |o + s e1 + t e2 - p|^2 over the critical point of the plane
 * (when regular and accepted by inside(s, t)), into best. */
static void plane_critical(mpq_t best, int *have, const dv *o, const dv *e1, const dv *e2, const dv *p,
                           int triangle) {
    dv w;
    mpq_t a, b, c, d1, d2, det, s, t, x, y;
    int k, ok;
    dv_init(&w);
    mpq_init(a); mpq_init(b); mpq_init(c); mpq_init(d1); mpq_init(d2);
    mpq_init(det); mpq_init(s); mpq_init(t); mpq_init(x); mpq_init(y);
    for (k = 0; k < 3; k++) mpq_sub(w.c[k], p->c[k], o->c[k]);
    dv_dot(a, e1, e1);
    dv_dot(b, e1, e2);
    dv_dot(c, e2, e2);
    dv_dot(d1, e1, &w);
    dv_dot(d2, e2, &w);
    /* [a b; b c] [s; t] = [d1; d2] */
    mpq_mul(x, a, c);
    mpq_mul(y, b, b);
    mpq_sub(det, x, y);
    if (mpq_sgn(det) != 0) {
        mpq_mul(x, d1, c);
        mpq_mul(y, b, d2);
        mpq_sub(s, x, y);
        mpq_div(s, s, det);
        mpq_mul(x, a, d2);
        mpq_mul(y, b, d1);
        mpq_sub(t, x, y);
        mpq_div(t, t, det);
        mpq_add(x, s, t);
        ok = mpq_sgn(s) >= 0 && mpq_sgn(t) >= 0 &&
             (triangle ? mpq_cmp_ui(x, 1, 1) <= 0 : (mpq_cmp_ui(s, 1, 1) <= 0 && mpq_cmp_ui(t, 1, 1) <= 0));
        if (ok) {
            point_at(x, o, e1, e2, s, t, p);
            keep_min(best, have, x);
        }
    }
    dv_clear(&w);
    mpq_clear(a); mpq_clear(b); mpq_clear(c); mpq_clear(d1); mpq_clear(d2);
    mpq_clear(det); mpq_clear(s); mpq_clear(t); mpq_clear(x); mpq_clear(y);
}

/* Squared distance of point p to triangle t[0..2]. */
static void point_triangle2(mpq_t r, const dv *p, const dv *t) {
    dv e1, e2;
    mpq_t v;
    int have = 0, i, k;
    dv_init(&e1); dv_init(&e2);
    mpq_init(v);
    for (i = 0; i < 3; i++) {
        point_segment2(v, p, &t[i], &t[(i + 1) % 3]);
        keep_min(r, &have, v);
    }
    for (k = 0; k < 3; k++) {
        mpq_sub(e1.c[k], t[1].c[k], t[0].c[k]);
        mpq_sub(e2.c[k], t[2].c[k], t[0].c[k]);
    }
    plane_critical(r, &have, &t[0], &e1, &e2, p, 1);
    dv_clear(&e1); dv_clear(&e2);
    mpq_clear(v);
}

/* Squared distance of segments [a0, a1] and [b0, b1]: the point
 * a0 + s (a1 - a0) - t (b1 - b0) against b0. */
static void segment_segment2(mpq_t r, const dv *a0, const dv *a1, const dv *b0, const dv *b1) {
    dv e1, e2;
    mpq_t v;
    int have = 0, k;
    dv_init(&e1); dv_init(&e2);
    mpq_init(v);
    point_segment2(v, a0, b0, b1); keep_min(r, &have, v);
    point_segment2(v, a1, b0, b1); keep_min(r, &have, v);
    point_segment2(v, b0, a0, a1); keep_min(r, &have, v);
    point_segment2(v, b1, a0, a1); keep_min(r, &have, v);
    for (k = 0; k < 3; k++) {
        mpq_sub(e1.c[k], a1->c[k], a0->c[k]);
        mpq_sub(e2.c[k], b0->c[k], b1->c[k]);
    }
    plane_critical(r, &have, a0, &e1, &e2, b0, 0);
    dv_clear(&e1); dv_clear(&e2);
    mpq_clear(v);
}

static void oracle_tri_tri_distance2(const double p[9], const double q[9], mpq_ptr out) {
    dv a[3], b[3];
    mpq_t v;
    int have = 0, i, j, k;
    if (oracle_tri_tri(p, q)) {
        mpq_set_ui(out, 0, 1);
        return;
    }
    mpq_init(v);
    for (i = 0; i < 3; i++) {
        dv_init(&a[i]);
        dv_init(&b[i]);
        for (k = 0; k < 3; k++) {
            mpq_set_d(a[i].c[k], p[3 * i + k]);
            mpq_set_d(b[i].c[k], q[3 * i + k]);
        }
    }
    for (i = 0; i < 3; i++) {
        point_triangle2(v, &a[i], b); keep_min(out, &have, v);
        point_triangle2(v, &b[i], a); keep_min(out, &have, v);
        for (j = 0; j < 3; j++) {
            segment_segment2(v, &a[i], &a[(i + 1) % 3], &b[j], &b[(j + 1) % 3]);
            keep_min(out, &have, v);
        }
    }
    for (i = 0; i < 3; i++) {
        dv_clear(&a[i]);
        dv_clear(&b[i]);
    }
    mpq_clear(v);
}

int oracle_tri_tri_within(const double p[9], const double q[9], double d) {
    mpq_t d2, dd;
    int r;
    mpq_init(d2);
    mpq_init(dd);
    oracle_tri_tri_distance2(p, q, d2);
    mpq_set_d(dd, d);
    mpq_mul(dd, dd, dd);
    r = mpq_cmp(d2, dd) <= 0;
    mpq_clear(d2);
    mpq_clear(dd);
    return r;
}

/* ------------------------------------------------------------------------ */
/* Whole scene                                                               */
/* ------------------------------------------------------------------------ */

double oracle_pair_margin(double world_margin, double margin_a, double margin_b) {
    volatile double s = margin_a + margin_b;
    volatile double d = world_margin + s;
    return d;
}

/* The triangles' boxes are more than d apart on an axis (then so are the
 * triangles): the gap as an exact rational, after a check in doubles that
 * can only say "apart" (rounding is monotone and d is a double, so a
 * rounded gap above d is an exact gap above d). */
static int tri_boxes_apart(const double *P, const double *Q, double d) {
    int k, i, apart = 0;
    mpq_t gap, x, dq;
    for (k = 0; k < 3; k++) {
        double plo = P[k], phi = P[k], qlo = Q[k], qhi = Q[k];
        for (i = 1; i < 3; i++) {
            plo = fmin(plo, P[3 * i + k]), phi = fmax(phi, P[3 * i + k]);
            qlo = fmin(qlo, Q[3 * i + k]), qhi = fmax(qhi, Q[3 * i + k]);
        }
        if (qlo - phi > d || plo - qhi > d) return 1;
    }
    mpq_init(gap);
    mpq_init(x);
    mpq_init(dq);
    mpq_set_d(dq, d);
    for (k = 0; k < 3 && !apart; k++) {
        double plo = P[k], phi = P[k], qlo = Q[k], qhi = Q[k];
        for (i = 1; i < 3; i++) {
            plo = fmin(plo, P[3 * i + k]), phi = fmax(phi, P[3 * i + k]);
            qlo = fmin(qlo, Q[3 * i + k]), qhi = fmax(qhi, Q[3 * i + k]);
        }
        mpq_set_d(gap, qlo);
        mpq_set_d(x, phi);
        mpq_sub(gap, gap, x);
        if (mpq_cmp(gap, dq) > 0) apart = 1;
        mpq_set_d(gap, plo);
        mpq_set_d(x, qhi);
        mpq_sub(gap, gap, x);
        if (mpq_cmp(gap, dq) > 0) apart = 1;
    }
    mpq_clear(gap);
    mpq_clear(x);
    mpq_clear(dq);
    return apart;
}

/* A cheap pre-check that can only say "apart": along the axis n, all of
 * the points b lie more than d beyond all of the points a (or the other way
 * round). The projections are computed in doubles and trusted only with a
 * slack of 2^-40 of their products' magnitudes (a thousand times their
 * rounding error), |n| taken 2^-40 larger, so the GMP distance decides
 * every pair near d. */
static int axis_gap_apart(const double *n, const double *a, size_t na, const double *b, size_t nb, double d) {
    const double an = fabs(n[0]) + fabs(n[1]) + fabs(n[2]);
    const double len = sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]) * (1 + 0x1p-40) + 0x1p-40 * an;
    double lo[2] = {INFINITY, INFINITY}, hi[2] = {-INFINITY, -INFINITY}, need;
    size_t i;
    int side;
    if (!(an > 0x1p-400) || !(an < 0x1p400)) return 0;
    for (side = 0; side < 2; side++)
        for (i = 0; i < (side ? nb : na); i++) {
            const double *x = (side ? b : a) + 3 * i;
            const double w[3] = {x[0] - a[0], x[1] - a[1], x[2] - a[2]};
            const double h = n[0] * w[0] + n[1] * w[1] + n[2] * w[2];
            const double e = 0x1p-40 * (fabs(n[0] * w[0]) + fabs(n[1] * w[1]) + fabs(n[2] * w[2])) + 0x1p-800;
            if (h - e < lo[side]) lo[side] = h - e;
            if (h + e > hi[side]) hi[side] = h + e;
        }
    need = d * len * (1 + 0x1p-40) + 0x1p-800;
    return (lo[1] - hi[0]) * (1 - 0x1p-40) > need || (lo[0] - hi[1]) * (1 - 0x1p-40) > need;
}

/* The normal of triangle P as an axis between P and Q. */
static int tri_plane_apart(const double *P, const double *Q, double d) {
    const double u[3] = {P[3] - P[0], P[4] - P[1], P[5] - P[2]}, v[3] = {P[6] - P[0], P[7] - P[1], P[8] - P[2]};
    const double n[3] = {u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0]};
    return axis_gap_apart(n, P, 3, Q, 3, d);
}

/* The line between the two bodies' box centres as an axis. */
static int bodies_apart(const double *wa, size_t na, const double *box_a, const double *wb, size_t nb,
                        const double *box_b, double d) {
    double n[3];
    int k;
    for (k = 0; k < 3; k++) n[k] = 0.5 * (box_b[k] + box_b[3 + k]) - 0.5 * (box_a[k] + box_a[3 + k]);
    return axis_gap_apart(n, wa, na, wb, nb, d);
}

static int cmp_pair(const void *x, const void *y) {
    const uint32_t *a = (const uint32_t *)x, *b = (const uint32_t *)y;
    if (a[0] != b[0]) return a[0] < b[0] ? -1 : 1;
    return a[1] < b[1] ? -1 : a[1] > b[1];
}

size_t oracle_pairs_within(size_t body_count, const oracle_mesh *const *body_mesh, const double *positions,
                           const double *orientations, const double *scales, double world_margin,
                           const double *margins, uint32_t *out_pairs, size_t out_capacity) {
    double **wv = (double **)calloc(body_count + 1, sizeof(double *));
    double *box = (double *)calloc(6 * body_count + 1, sizeof(double));
    size_t i, j, count = 0, cap = 64;
    uint32_t *pairs = (uint32_t *)malloc(2 * cap * sizeof(uint32_t));
    if (!wv || !box || !pairs) {
        fprintf(stderr, "oracle: out of memory\n");
        abort();
    }
    for (i = 0; i < body_count; i++) {
        const oracle_mesh *m = body_mesh[i];
        uint32_t v;
        int k;
        wv[i] = (double *)malloc(3 * sizeof(double) * ((size_t)m->vertex_count + 1));
        if (!wv[i]) abort();
        for (k = 0; k < 3; k++) {
            box[6 * i + k] = INFINITY;
            box[6 * i + 3 + k] = -INFINITY;
        }
        for (v = 0; v < m->vertex_count; v++) {
            double *w = wv[i] + 3 * (size_t)v;
            oracle_world_vertex(positions + 3 * i, orientations + 4 * i, scales[i], m->verts + 3 * (size_t)v, w);
            for (k = 0; k < 3; k++) {
                if (w[k] < box[6 * i + k]) box[6 * i + k] = w[k];
                if (w[k] > box[6 * i + 3 + k]) box[6 * i + 3 + k] = w[k];
            }
        }
    }
    for (i = 0; i < body_count; i++)
        for (j = i + 1; j < body_count; j++) {
            const double d = oracle_pair_margin(world_margin, margins ? margins[i] : 0, margins ? margins[j] : 0);
            const oracle_mesh *ma = body_mesh[i], *mb = body_mesh[j];
            int hit = 0, k;
            uint32_t s, t;
            mpq_t gap, dq;
            /* Boxes farther apart than d on an axis (in doubles where that
             * says apart, as in tri_boxes_apart, else exact rationals). */
            for (k = 0; k < 3; k++)
                if (box[6 * j + k] - box[6 * i + 3 + k] > d || box[6 * i + k] - box[6 * j + 3 + k] > d) break;
            if (k < 3) continue;
            mpq_init(gap);
            mpq_init(dq);
            mpq_set_d(dq, d);
            for (k = 0; k < 3 && !hit; k++) {
                mpq_t lo;
                mpq_init(lo);
                mpq_set_d(lo, box[6 * j + k]);
                mpq_set_d(gap, box[6 * i + 3 + k]);
                mpq_sub(gap, lo, gap);
                if (mpq_cmp(gap, dq) > 0) hit = -1;
                mpq_set_d(lo, box[6 * i + k]);
                mpq_set_d(gap, box[6 * j + 3 + k]);
                mpq_sub(gap, lo, gap);
                if (mpq_cmp(gap, dq) > 0) hit = -1;
                mpq_clear(lo);
            }
            mpq_clear(gap);
            mpq_clear(dq);
            if (hit < 0) continue;
            if (bodies_apart(wv[i], ma->vertex_count, box + 6 * i, wv[j], mb->vertex_count, box + 6 * j, d)) continue;
            for (s = 0; s < ma->triangle_count && !hit; s++)
                for (t = 0; t < mb->triangle_count && !hit; t++) {
                    double P[9], Q[9];
                    for (k = 0; k < 9; k++) {
                        P[k] = wv[i][3 * (size_t)ma->tris[3 * s + k / 3] + k % 3];
                        Q[k] = wv[j][3 * (size_t)mb->tris[3 * t + k / 3] + k % 3];
                    }
                    if (!tri_boxes_apart(P, Q, d) && !tri_plane_apart(P, Q, d) && !tri_plane_apart(Q, P, d))
                        hit = oracle_tri_tri_within(P, Q, d);
                }
            if (!hit) {
                /* Apart surfaces: within d only if one solid holds the other
                 * (the touching oracle on the pair alone). */
                const oracle_mesh *two[2] = {ma, mb};
                double pos[6], ori[8], sc[2];
                uint32_t pr[2];
                memcpy(pos, positions + 3 * i, 3 * sizeof(double));
                memcpy(pos + 3, positions + 3 * j, 3 * sizeof(double));
                memcpy(ori, orientations + 4 * i, 4 * sizeof(double));
                memcpy(ori + 4, orientations + 4 * j, 4 * sizeof(double));
                sc[0] = scales[i];
                sc[1] = scales[j];
                hit = oracle_colliding_pairs(2, two, pos, ori, sc, pr, 1) > 0;
            }
            if (!hit) continue;
            if (count == cap) {
                uint32_t *np;
                cap *= 2;
                np = (uint32_t *)realloc(pairs, 2 * cap * sizeof(uint32_t));
                if (!np) abort();
                pairs = np;
            }
            pairs[2 * count] = (uint32_t)i;
            pairs[2 * count + 1] = (uint32_t)j;
            count++;
        }
    qsort(pairs, count, 2 * sizeof(uint32_t), cmp_pair);
    if (out_pairs) memcpy(out_pairs, pairs, 2 * sizeof(uint32_t) * (count < out_capacity ? count : out_capacity));
    for (i = 0; i < body_count; i++) free(wv[i]);
    free(wv);
    free(box);
    free(pairs);
    return count;
}
