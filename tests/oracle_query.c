/* Brute-force references for the scene queries (see oracle_query.h). */
#include "oracle_query.h"

#include <gmp.h>
#include <stdlib.h>

#include "oracle.h"

typedef struct {
    mpq_t c[3];
} qv;

static void qv_init(qv *v) { mpq_init(v->c[0]); mpq_init(v->c[1]); mpq_init(v->c[2]); }
static void qv_clear(qv *v) { mpq_clear(v->c[0]); mpq_clear(v->c[1]); mpq_clear(v->c[2]); }
static void qv_set_d(qv *v, const double *x) { int k; for (k = 0; k < 3; k++) mpq_set_d(v->c[k], x[k]); }
static void qv_sub(qv *r, const qv *a, const qv *b) { int k; for (k = 0; k < 3; k++) mpq_sub(r->c[k], a->c[k], b->c[k]); }
static void qv_cross(qv *r, const qv *a, const qv *b) {
    mpq_t t;
    mpq_init(t);
    mpq_mul(r->c[0], a->c[1], b->c[2]); mpq_mul(t, a->c[2], b->c[1]); mpq_sub(r->c[0], r->c[0], t);
    mpq_mul(r->c[1], a->c[2], b->c[0]); mpq_mul(t, a->c[0], b->c[2]); mpq_sub(r->c[1], r->c[1], t);
    mpq_mul(r->c[2], a->c[0], b->c[1]); mpq_mul(t, a->c[1], b->c[0]); mpq_sub(r->c[2], r->c[2], t);
    mpq_clear(t);
}
static void qv_dot(mpq_t r, const qv *a, const qv *b) {
    mpq_t t;
    mpq_init(t);
    mpq_mul(r, a->c[0], b->c[0]); mpq_mul(t, a->c[1], b->c[1]); mpq_add(r, r, t);
    mpq_mul(t, a->c[2], b->c[2]); mpq_add(r, r, t);
    mpq_clear(t);
}

/* The crossing parameter as a rational (k), or 0 if no transversal crossing. */
static int crossing(const double *o, const double *e, const double *t, mpq_t k) {
    qv O, E, T[3], e1, e2, n, d, x, a, b, cr;
    mpq_t da, db, s;
    int i, hit = 0;
    qv_init(&O); qv_init(&E); qv_init(&e1); qv_init(&e2); qv_init(&n); qv_init(&d); qv_init(&x);
    qv_init(&a); qv_init(&b); qv_init(&cr);
    for (i = 0; i < 3; i++) { qv_init(&T[i]); qv_set_d(&T[i], t + 3 * i); }
    mpq_init(da); mpq_init(db); mpq_init(s);
    qv_set_d(&O, o); qv_set_d(&E, e);
    qv_sub(&e1, &T[1], &T[0]);
    qv_sub(&e2, &T[2], &T[0]);
    qv_cross(&n, &e1, &e2);
    qv_sub(&d, &O, &T[0]); qv_dot(da, &n, &d);
    qv_sub(&d, &E, &T[0]); qv_dot(db, &n, &d);
    if (!(mpq_sgn(da) * mpq_sgn(db) > 0) && !(mpq_sgn(da) == 0 && mpq_sgn(db) == 0)) {
        /* x = o + k (e - o), k = da / (da - db); barycentric signs of x:
         * n . ((t_{i+1} - x) x (t_{i+2} - x)) >= 0 for all i. */
        mpq_sub(k, da, db);
        mpq_div(k, da, k);
        qv_sub(&d, &E, &O);
        for (i = 0; i < 3; i++) { mpq_mul(x.c[i], d.c[i], k); mpq_add(x.c[i], x.c[i], O.c[i]); }
        hit = 1;
        for (i = 0; i < 3 && hit; i++) {
            qv_sub(&a, &T[(i + 1) % 3], &x);
            qv_sub(&b, &T[(i + 2) % 3], &x);
            qv_cross(&cr, &a, &b);
            qv_dot(s, &n, &cr);
            if (mpq_sgn(s) < 0) hit = 0;
        }
    }
    qv_clear(&O); qv_clear(&E); qv_clear(&e1); qv_clear(&e2); qv_clear(&n); qv_clear(&d); qv_clear(&x);
    qv_clear(&a); qv_clear(&b); qv_clear(&cr);
    for (i = 0; i < 3; i++) qv_clear(&T[i]);
    mpq_clear(da); mpq_clear(db); mpq_clear(s);
    return hit;
}

int oracle_ray_crossing(const double o[3], const double e[3], const double t[9], double *t_out) {
    mpq_t k;
    int hit;
    mpq_init(k);
    hit = crossing(o, e, t, k);
    if (hit && t_out) *t_out = mpq_get_d(k);
    mpq_clear(k);
    return hit;
}

int oracle_crossing_compare(const double o[3], const double e[3], const double t1[9], const double t2[9]) {
    mpq_t k1, k2;
    int c;
    mpq_init(k1); mpq_init(k2);
    if (!crossing(o, e, t1, k1) || !crossing(o, e, t2, k2)) abort();
    c = mpq_cmp(k1, k2);
    mpq_clear(k1); mpq_clear(k2);
    return (c > 0) - (c < 0);
}

int oracle_point_in_solid(const double p[3], const double *wv, uint32_t vertex_count, const uint32_t *tris,
                          uint32_t tri_count) {
    uint32_t f;
    int k, r;
    for (f = 0; f < tri_count; f++) {
        double t[9];
        for (k = 0; k < 9; k++) t[k] = wv[3 * tris[3 * f + k / 3] + k % 3];
        if (oracle_segment_triangle(p, p, t)) return 1;
    }
    if (!oracle_mesh_is_closed(tris, tri_count)) return 0;
    r = oracle_point_in_closed_mesh(p, wv, vertex_count, tris, tri_count);
    if (r < 0) abort(); /* (not on the surface, so only all-degenerate rays) */
    return r;
}

/* Sutherland-Hodgman: the polygon poly[0..n) clipped by the closed
 * half-space sign * (x_axis - bound) >= 0 into out; returns its size. */
static int clip(qv *poly, int n, int axis, const mpq_t bound, int sign, qv *out) {
    int i, m = 0;
    mpq_t dp, dq, k, tmp;
    mpq_init(dp); mpq_init(dq); mpq_init(k); mpq_init(tmp);
    for (i = 0; i < n; i++) {
        const qv *P = &poly[i], *Q = &poly[(i + 1) % n];
        int ip, iq, c;
        mpq_sub(dp, P->c[axis], bound);
        mpq_sub(dq, Q->c[axis], bound);
        if (sign < 0) { mpq_neg(dp, dp); mpq_neg(dq, dq); }
        ip = mpq_sgn(dp) >= 0;
        iq = mpq_sgn(dq) >= 0;
        if (ip != iq) { /* the crossing point P + dp / (dp - dq) (Q - P) */
            mpq_sub(k, dp, dq);
            mpq_div(k, dp, k);
            for (c = 0; c < 3; c++) {
                mpq_sub(tmp, Q->c[c], P->c[c]);
                mpq_mul(tmp, tmp, k);
                mpq_add(out[m].c[c], P->c[c], tmp);
            }
            m++;
        }
        if (iq) {
            for (c = 0; c < 3; c++) mpq_set(out[m].c[c], Q->c[c]);
            m++;
        }
    }
    mpq_clear(dp); mpq_clear(dq); mpq_clear(k); mpq_clear(tmp);
    return m;
}

int oracle_triangle_box(const double lo[3], const double hi[3], const double t[9]) {
    qv a[16], b[16];
    int i, n = 3, side;
    mpq_t bound;
    mpq_init(bound);
    for (i = 0; i < 16; i++) { qv_init(&a[i]); qv_init(&b[i]); }
    for (i = 0; i < 3; i++) qv_set_d(&a[i], t + 3 * i);
    for (i = 0; i < 3 && n > 0; i++)
        for (side = 0; side < 2 && n > 0; side++) {
            mpq_set_d(bound, side ? hi[i] : lo[i]);
            n = clip(a, n, i, bound, side ? -1 : 1, b);
            { int j, c; for (j = 0; j < n; j++) for (c = 0; c < 3; c++) mpq_set(a[j].c[c], b[j].c[c]); }
        }
    for (i = 0; i < 16; i++) { qv_clear(&a[i]); qv_clear(&b[i]); }
    mpq_clear(bound);
    return n > 0;
}

int oracle_box_meets_solid(const double lo[3], const double hi[3], const double *wv, uint32_t vertex_count,
                           const uint32_t *tris, uint32_t tri_count) {
    uint32_t f;
    int k;
    for (f = 0; f < tri_count; f++) {
        double t[9];
        for (k = 0; k < 9; k++) t[k] = wv[3 * tris[3 * f + k / 3] + k % 3];
        if (oracle_triangle_box(lo, hi, t)) return 1;
    }
    if (!oracle_mesh_is_closed(tris, tri_count)) return 0;
    k = oracle_point_in_closed_mesh(lo, wv, vertex_count, tris, tri_count);
    if (k < 0) abort();
    return k;
}

int oracle_ray_closest(const double o[3], const double e[3], const oracle_solid *bodies, uint32_t count,
                       uint32_t *body, uint32_t *tri, int *inside, double *t) {
    int hit = 0;
    double bt[9], best_t = 0;
    uint32_t b, f;
    int k;
    /* Bodies ascending, triangles ascending: a candidate replaces the best
     * only when strictly before it. */
    for (b = 0; b < count; ++b) {
        const oracle_solid *s = &bodies[b];
        if (oracle_mesh_is_closed(s->tris, s->tri_count) &&
            oracle_point_in_solid(o, s->wv, s->vertex_count, s->tris, s->tri_count)) {
            if (!hit || best_t > 0) {
                hit = 1;
                *body = b;
                *tri = UINT32_MAX;
                *inside = 1;
                best_t = 0;
            }
            continue;
        }
        for (f = 0; f < s->tri_count; ++f) {
            double tt[9], tp;
            for (k = 0; k < 9; k++) tt[k] = s->wv[3 * s->tris[3 * f + k / 3] + k % 3];
            if (!oracle_ray_crossing(o, e, tt, &tp)) continue;
            if (hit && (*inside || oracle_crossing_compare(o, e, tt, bt) >= 0)) continue;
            hit = 1;
            *body = b;
            *tri = f;
            *inside = 0;
            best_t = tp;
            for (k = 0; k < 9; k++) bt[k] = tt[k];
        }
    }
    if (hit) *t = best_t;
    return hit;
}
