/* Independent brute-force oracle (see oracle.h). Plain C99 + GMP.
 *
 * Formulations (deliberately different from src/exact):
 *  - orientation: a generous double filter (relative bound 1e-12, far above
 *    the true rounding error), otherwise the determinant in mpq_t;
 *  - segment/triangle: the rational intersection point of the segment with
 *    the triangle's plane, then barycentric-type signs
 *    ((t_{i+1} - t_i) x (X - t_i)) . n, all in exact rationals; coplanar
 *    pieces by rational parametric segment/segment solving; degenerate
 *    triangles as the union of their edges;
 *  - triangle/triangle: an edge of one meets the other (true for closed
 *    triangles, degenerate or not, coplanar or not);
 *  - point in mesh: parity of rational crossing points along a segment to a
 *    point outside the box, retrying other directions on any degeneracy.
 */
#include "oracle.h"

#include <gmp.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* ------------------------------------------------------------------------ */
/* Rational vectors                                                          */
/* ------------------------------------------------------------------------ */

typedef struct {
    mpq_t c[3];
} qv;

static void qv_init(qv *v) {
    int k;
    for (k = 0; k < 3; k++) mpq_init(v->c[k]);
}

static void qv_clear(qv *v) {
    int k;
    for (k = 0; k < 3; k++) mpq_clear(v->c[k]);
}

static void qv_set_d(qv *v, const double *x) {
    int k;
    for (k = 0; k < 3; k++) mpq_set_d(v->c[k], x[k]); /* exact */
}

static void qv_set(qv *r, const qv *a) {
    int k;
    for (k = 0; k < 3; k++) mpq_set(r->c[k], a->c[k]);
}

static void qv_sub(qv *r, const qv *a, const qv *b) {
    int k;
    for (k = 0; k < 3; k++) mpq_sub(r->c[k], a->c[k], b->c[k]);
}

/* r = a x b; r must not alias a or b. */
static void qv_cross(qv *r, const qv *a, const qv *b) {
    mpq_t t;
    mpq_init(t);
    mpq_mul(r->c[0], a->c[1], b->c[2]);
    mpq_mul(t, a->c[2], b->c[1]);
    mpq_sub(r->c[0], r->c[0], t);
    mpq_mul(r->c[1], a->c[2], b->c[0]);
    mpq_mul(t, a->c[0], b->c[2]);
    mpq_sub(r->c[1], r->c[1], t);
    mpq_mul(r->c[2], a->c[0], b->c[1]);
    mpq_mul(t, a->c[1], b->c[0]);
    mpq_sub(r->c[2], r->c[2], t);
    mpq_clear(t);
}

static void qv_dot(mpq_t r, const qv *a, const qv *b) {
    mpq_t t;
    mpq_init(t);
    mpq_mul(r, a->c[0], b->c[0]);
    mpq_mul(t, a->c[1], b->c[1]);
    mpq_add(r, r, t);
    mpq_mul(t, a->c[2], b->c[2]);
    mpq_add(r, r, t);
    mpq_clear(t);
}

static int qv_is_zero(const qv *a) {
    return mpq_sgn(a->c[0]) == 0 && mpq_sgn(a->c[1]) == 0 &&
           mpq_sgn(a->c[2]) == 0;
}

static int qv_equal(const qv *a, const qv *b) {
    return mpq_equal(a->c[0], b->c[0]) && mpq_equal(a->c[1], b->c[1]) &&
           mpq_equal(a->c[2], b->c[2]);
}

/* ------------------------------------------------------------------------ */
/* Orientation                                                               */
/* ------------------------------------------------------------------------ */

int oracle_orient3d(const double a[3], const double b[3], const double c[3],
                    const double d[3]) {
    double adx = a[0] - d[0], ady = a[1] - d[1], adz = a[2] - d[2];
    double bdx = b[0] - d[0], bdy = b[1] - d[1], bdz = b[2] - d[2];
    double cdx = c[0] - d[0], cdy = c[1] - d[1], cdz = c[2] - d[2];
    double det = adx * (bdy * cdz - bdz * cdy) - ady * (bdx * cdz - bdz * cdx) +
                 adz * (bdx * cdy - bdy * cdx);
    double perm = fabs(adx) * (fabs(bdy * cdz) + fabs(bdz * cdy)) +
                  fabs(ady) * (fabs(bdx * cdz) + fabs(bdz * cdx)) +
                  fabs(adz) * (fabs(bdx * cdy) + fabs(bdy * cdx));
    if (isfinite(det) && isfinite(perm) && perm > 1e-200 &&
        fabs(det) > 1e-12 * perm) {
        return det > 0 ? 1 : -1;
    }
    {
        qv A, B, C, D, ad, bd, cd, x;
        mpq_t r;
        int s;
        qv_init(&A); qv_init(&B); qv_init(&C); qv_init(&D);
        qv_init(&ad); qv_init(&bd); qv_init(&cd); qv_init(&x);
        mpq_init(r);
        qv_set_d(&A, a); qv_set_d(&B, b); qv_set_d(&C, c); qv_set_d(&D, d);
        qv_sub(&ad, &A, &D);
        qv_sub(&bd, &B, &D);
        qv_sub(&cd, &C, &D);
        qv_cross(&x, &bd, &cd);
        qv_dot(r, &ad, &x); /* det[ad; bd; cd] = ad . (bd x cd) */
        s = mpq_sgn(r);
        mpq_clear(r);
        qv_clear(&A); qv_clear(&B); qv_clear(&C); qv_clear(&D);
        qv_clear(&ad); qv_clear(&bd); qv_clear(&cd); qv_clear(&x);
        return s;
    }
}

int oracle_orient2d(const double a[2], const double b[2], const double c[2]) {
    mpq_t ax, ay, bx, by, t, u;
    int s;
    mpq_init(ax); mpq_init(ay); mpq_init(bx); mpq_init(by);
    mpq_init(t); mpq_init(u);
    mpq_set_d(ax, a[0]); mpq_set_d(t, c[0]); mpq_sub(ax, ax, t);
    mpq_set_d(ay, a[1]); mpq_set_d(t, c[1]); mpq_sub(ay, ay, t);
    mpq_set_d(bx, b[0]); mpq_set_d(t, c[0]); mpq_sub(bx, bx, t);
    mpq_set_d(by, b[1]); mpq_set_d(t, c[1]); mpq_sub(by, by, t);
    mpq_mul(t, ax, by);
    mpq_mul(u, ay, bx);
    mpq_sub(t, t, u);
    s = mpq_sgn(t);
    mpq_clear(ax); mpq_clear(ay); mpq_clear(bx); mpq_clear(by);
    mpq_clear(t); mpq_clear(u);
    return s;
}

/* ------------------------------------------------------------------------ */
/* Rational segment / segment and segment / triangle                         */
/* ------------------------------------------------------------------------ */

/* x on the closed segment [b0, b1], b0 != b1. */
static int q_point_on_segment(const qv *x, const qv *b0, const qv *b1) {
    qv w, r, cr;
    mpq_t rw, ww;
    int on = 0;
    qv_init(&w); qv_init(&r); qv_init(&cr);
    mpq_init(rw); mpq_init(ww);
    qv_sub(&w, b1, b0);
    qv_sub(&r, x, b0);
    qv_cross(&cr, &r, &w);
    if (qv_is_zero(&cr)) {
        qv_dot(rw, &r, &w);
        qv_dot(ww, &w, &w);
        on = mpq_sgn(rw) >= 0 && mpq_cmp(rw, ww) <= 0;
    }
    qv_clear(&w); qv_clear(&r); qv_clear(&cr);
    mpq_clear(rw); mpq_clear(ww);
    return on;
}

/* Closed segments [a0, a1] and [b0, b1] in 3D, each possibly a point:
 * solve a0 + s u = b0 + t w for s, t in [0, 1]. */
static int q_seg_seg(const qv *a0, const qv *a1, const qv *b0, const qv *b1) {
    qv u, w, c, r, t1, t2;
    mpq_t x, y, cc, s;
    int hit = 0;
    int ua = 0, wa = 0;
    qv_init(&u); qv_init(&w); qv_init(&c); qv_init(&r);
    qv_init(&t1); qv_init(&t2);
    mpq_init(x); mpq_init(y); mpq_init(cc); mpq_init(s);
    qv_sub(&u, a1, a0);
    qv_sub(&w, b1, b0);
    ua = qv_is_zero(&u);
    wa = qv_is_zero(&w);
    if (ua && wa) {
        hit = qv_equal(a0, b0);
    } else if (ua) {
        hit = q_point_on_segment(a0, b0, b1);
    } else if (wa) {
        hit = q_point_on_segment(b0, a0, a1);
    } else {
        qv_cross(&c, &u, &w);
        qv_sub(&r, b0, a0);
        if (qv_is_zero(&c)) {
            /* Parallel: they meet iff collinear and the parameter intervals
             * along u overlap: [0, u.u] against [r.u, (b1-a0).u]. */
            qv_cross(&t1, &r, &u);
            if (qv_is_zero(&t1)) {
                mpq_t lo, hi, uu;
                mpq_init(lo); mpq_init(hi); mpq_init(uu);
                qv_dot(x, &r, &u);
                qv_sub(&t2, b1, a0);
                qv_dot(y, &t2, &u);
                qv_dot(uu, &u, &u);
                if (mpq_cmp(x, y) <= 0) {
                    mpq_set(lo, x);
                    mpq_set(hi, y);
                } else {
                    mpq_set(lo, y);
                    mpq_set(hi, x);
                }
                hit = mpq_cmp(lo, uu) <= 0 && mpq_sgn(hi) >= 0;
                mpq_clear(lo); mpq_clear(hi); mpq_clear(uu);
            }
        } else {
            qv_dot(x, &r, &c);
            if (mpq_sgn(x) == 0) { /* coplanar */
                qv_dot(cc, &c, &c);
                qv_cross(&t1, &r, &w);
                qv_dot(s, &t1, &c);
                mpq_div(s, s, cc); /* s */
                if (mpq_sgn(s) >= 0 && mpq_cmp_si(s, 1, 1) <= 0) {
                    qv_cross(&t2, &r, &u);
                    qv_dot(y, &t2, &c);
                    mpq_div(y, y, cc); /* t */
                    hit = mpq_sgn(y) >= 0 && mpq_cmp_si(y, 1, 1) <= 0;
                }
            }
        }
    }
    qv_clear(&u); qv_clear(&w); qv_clear(&c); qv_clear(&r);
    qv_clear(&t1); qv_clear(&t2);
    mpq_clear(x); mpq_clear(y); mpq_clear(cc); mpq_clear(s);
    return hit;
}

/* Signs of ((t_{i+1} - t_i) x (x - t_i)) . n for x in the plane of the
 * proper triangle t with normal n = (t1-t0) x (t2-t0): returns 2 if all are
 * > 0 (strictly inside), 1 if all >= 0 with some zero (on the boundary),
 * 0 if some < 0 (outside). */
static int q_point_in_triangle(const qv *x, const qv *const *t, const qv *n) {
    qv e, d, cr;
    mpq_t s;
    int i, anyzero = 0, out = 0;
    qv_init(&e); qv_init(&d); qv_init(&cr);
    mpq_init(s);
    for (i = 0; i < 3 && !out; i++) {
        qv_sub(&e, t[(i + 1) % 3], t[i]);
        qv_sub(&d, x, t[i]);
        qv_cross(&cr, &e, &d);
        qv_dot(s, &cr, n);
        if (mpq_sgn(s) < 0) out = 1;
        else if (mpq_sgn(s) == 0) anyzero = 1;
    }
    qv_clear(&e); qv_clear(&d); qv_clear(&cr);
    mpq_clear(s);
    if (out) return 0;
    return anyzero ? 1 : 2;
}

/* Segment [a, b] against the closed triangle t (rational). */
static int q_seg_tri(const qv *a, const qv *b, const qv *const *t) {
    qv e1, e2, n, d, x;
    mpq_t da, db, k;
    int hit = 0;
    qv_init(&e1); qv_init(&e2); qv_init(&n); qv_init(&d); qv_init(&x);
    mpq_init(da); mpq_init(db); mpq_init(k);
    qv_sub(&e1, t[1], t[0]);
    qv_sub(&e2, t[2], t[0]);
    qv_cross(&n, &e1, &e2);
    if (qv_is_zero(&n)) {
        /* Zero-area triangle: the union of its edges. */
        int i;
        for (i = 0; i < 3 && !hit; i++) hit = q_seg_seg(a, b, t[i], t[(i + 1) % 3]);
    } else {
        qv_sub(&d, a, t[0]);
        qv_dot(da, &n, &d);
        qv_sub(&d, b, t[0]);
        qv_dot(db, &n, &d);
        if (mpq_sgn(da) * mpq_sgn(db) > 0) {
            hit = 0;
        } else if (mpq_sgn(da) == 0 && mpq_sgn(db) == 0) {
            int i;
            hit = q_point_in_triangle(a, t, &n) != 0;
            for (i = 0; i < 3 && !hit; i++) hit = q_seg_seg(a, b, t[i], t[(i + 1) % 3]);
        } else {
            /* X = a + da / (da - db) (b - a) */
            int c;
            mpq_sub(k, da, db);
            mpq_div(k, da, k);
            qv_sub(&d, b, a);
            for (c = 0; c < 3; c++) {
                mpq_mul(x.c[c], d.c[c], k);
                mpq_add(x.c[c], x.c[c], a->c[c]);
            }
            hit = q_point_in_triangle(&x, t, &n) != 0;
        }
    }
    qv_clear(&e1); qv_clear(&e2); qv_clear(&n); qv_clear(&d); qv_clear(&x);
    mpq_clear(da); mpq_clear(db); mpq_clear(k);
    return hit;
}

int oracle_segment_triangle(const double a[3], const double b[3],
                            const double t[9]) {
    qv A, B, T0, T1, T2;
    const qv *tt[3];
    int hit;
    int sa = oracle_orient3d(t, t + 3, t + 6, a);
    int sb = oracle_orient3d(t, t + 3, t + 6, b);
    if (sa * sb > 0) return 0;
    qv_init(&A); qv_init(&B); qv_init(&T0); qv_init(&T1); qv_init(&T2);
    qv_set_d(&A, a); qv_set_d(&B, b);
    qv_set_d(&T0, t); qv_set_d(&T1, t + 3); qv_set_d(&T2, t + 6);
    tt[0] = &T0; tt[1] = &T1; tt[2] = &T2;
    hit = q_seg_tri(&A, &B, tt);
    qv_clear(&A); qv_clear(&B); qv_clear(&T0); qv_clear(&T1); qv_clear(&T2);
    return hit;
}

/* ------------------------------------------------------------------------ */
/* Triangle / triangle                                                       */
/* ------------------------------------------------------------------------ */

int oracle_tri_tri(const double p[9], const double q[9]) {
    int k, i, hit = 0;
    qv P[3], Q[3];
    const qv *pp[3], *qq[3];
    /* Exact prunes: disjoint boxes; all of one strictly on one side of the
     * other's plane (both are sound for any triangles). */
    for (k = 0; k < 3; k++) {
        double plo = p[k], phi = p[k], qlo = q[k], qhi = q[k];
        for (i = 1; i < 3; i++) {
            if (p[3 * i + k] < plo) plo = p[3 * i + k];
            if (p[3 * i + k] > phi) phi = p[3 * i + k];
            if (q[3 * i + k] < qlo) qlo = q[3 * i + k];
            if (q[3 * i + k] > qhi) qhi = q[3 * i + k];
        }
        if (phi < qlo || qhi < plo) return 0;
    }
    {
        int s0 = oracle_orient3d(p, p + 3, p + 6, q);
        int s1 = oracle_orient3d(p, p + 3, p + 6, q + 3);
        int s2 = oracle_orient3d(p, p + 3, p + 6, q + 6);
        if (s0 != 0 && s0 == s1 && s1 == s2) return 0;
        s0 = oracle_orient3d(q, q + 3, q + 6, p);
        s1 = oracle_orient3d(q, q + 3, q + 6, p + 3);
        s2 = oracle_orient3d(q, q + 3, q + 6, p + 6);
        if (s0 != 0 && s0 == s1 && s1 == s2) return 0;
    }
    for (i = 0; i < 3; i++) {
        qv_init(&P[i]); qv_init(&Q[i]);
        qv_set_d(&P[i], p + 3 * i);
        qv_set_d(&Q[i], q + 3 * i);
        pp[i] = &P[i];
        qq[i] = &Q[i];
    }
    for (i = 0; i < 3 && !hit; i++) hit = q_seg_tri(pp[i], pp[(i + 1) % 3], qq);
    for (i = 0; i < 3 && !hit; i++) hit = q_seg_tri(qq[i], qq[(i + 1) % 3], pp);
    for (i = 0; i < 3; i++) {
        qv_clear(&P[i]); qv_clear(&Q[i]);
    }
    return hit;
}

/* ------------------------------------------------------------------------ */
/* Point in closed mesh                                                      */
/* ------------------------------------------------------------------------ */

/* Directions: integer vectors from a small LCG (different from src/), one
 * component +-1024 so that the segment leaves the box. */
static void oracle_direction(int attempt, double dir[3]) {
    uint32_t s = 2654435761u * (uint32_t)(attempt + 1) + 12345u;
    int k;
    for (k = 0; k < 3; k++) {
        s = s * 1664525u + 1013904223u;
        dir[k] = (double)((int)((s >> 8) % 2001u) - 1000) + 0.5;
    }
    k = attempt % 3;
    dir[k] = (attempt / 3) % 2 ? -1024.0 : 1024.0;
}

int oracle_point_in_closed_mesh(const double p[3], const double *verts,
                                uint32_t vertex_count, const uint32_t *tris,
                                uint32_t tri_count) {
    double lo[3], hi[3], ext = 0, len, q[3], dir[3];
    uint32_t i, t;
    int k, attempt;
    qv Pq, Qq, T0, T1, T2, e1, e2, n, d, x;
    const qv *tt[3];
    mpq_t dp, dq, f;
    int result = -1;
    if (vertex_count == 0) return 0;
    for (k = 0; k < 3; k++) lo[k] = hi[k] = verts[k];
    for (i = 1; i < vertex_count; i++) {
        for (k = 0; k < 3; k++) {
            double v = verts[3 * (size_t)i + k];
            if (v < lo[k]) lo[k] = v;
            if (v > hi[k]) hi[k] = v;
        }
    }
    for (k = 0; k < 3; k++) {
        if (p[k] < lo[k] || p[k] > hi[k]) return 0;
        if (hi[k] - lo[k] > ext) ext = hi[k] - lo[k];
    }
    qv_init(&Pq); qv_init(&Qq); qv_init(&T0); qv_init(&T1); qv_init(&T2);
    qv_init(&e1); qv_init(&e2); qv_init(&n); qv_init(&d); qv_init(&x);
    mpq_init(dp); mpq_init(dq); mpq_init(f);
    tt[0] = &T0; tt[1] = &T1; tt[2] = &T2;
    qv_set_d(&Pq, p);
    for (attempt = 0; attempt < 64 && result < 0; attempt++) {
        int parity = 0, degenerate = 0;
        oracle_direction(attempt, dir);
        len = (2.0 * ext + 1.0) / 1024.0;
        for (;;) {
            int out = 0;
            for (k = 0; k < 3; k++) {
                q[k] = p[k] + len * dir[k];
                if (q[k] < lo[k] || q[k] > hi[k]) out = 1;
            }
            if (out) break;
            len *= 2.0;
        }
        qv_set_d(&Qq, q);
        for (t = 0; t < tri_count && !degenerate; t++) {
            const double *v0 = verts + 3 * (size_t)tris[3 * t];
            const double *v1 = verts + 3 * (size_t)tris[3 * t + 1];
            const double *v2 = verts + 3 * (size_t)tris[3 * t + 2];
            int sp = oracle_orient3d(v0, v1, v2, p);
            int sq = oracle_orient3d(v0, v1, v2, q);
            if (sp * sq > 0) continue;
            qv_set_d(&T0, v0); qv_set_d(&T1, v1); qv_set_d(&T2, v2);
            qv_sub(&e1, &T1, &T0);
            qv_sub(&e2, &T2, &T0);
            qv_cross(&n, &e1, &e2);
            if (qv_is_zero(&n)) continue; /* zero area: never crossed generically */
            qv_sub(&d, &Pq, &T0);
            qv_dot(dp, &n, &d);
            qv_sub(&d, &Qq, &T0);
            qv_dot(dq, &n, &d);
            if (mpq_sgn(dp) == 0 && mpq_sgn(dq) == 0) {
                if (q_seg_tri(&Pq, &Qq, tt)) degenerate = 1;
                continue;
            }
            if (mpq_sgn(dp) == 0) {
                if (q_point_in_triangle(&Pq, tt, &n)) degenerate = 1;
                continue;
            }
            if (mpq_sgn(dq) == 0) {
                if (q_point_in_triangle(&Qq, tt, &n)) degenerate = 1;
                continue;
            }
            mpq_sub(f, dp, dq);
            mpq_div(f, dp, f);
            qv_sub(&d, &Qq, &Pq);
            for (k = 0; k < 3; k++) {
                mpq_mul(x.c[k], d.c[k], f);
                mpq_add(x.c[k], x.c[k], Pq.c[k]);
            }
            switch (q_point_in_triangle(&x, tt, &n)) {
            case 2: parity ^= 1; break;
            case 1: degenerate = 1; break;
            default: break;
            }
        }
        if (!degenerate) result = parity;
    }
    qv_clear(&Pq); qv_clear(&Qq); qv_clear(&T0); qv_clear(&T1); qv_clear(&T2);
    qv_clear(&e1); qv_clear(&e2); qv_clear(&n); qv_clear(&d); qv_clear(&x);
    mpq_clear(dp); mpq_clear(dq); mpq_clear(f);
    (void)qv_set;
    return result;
}

/* ------------------------------------------------------------------------ */
/* Mesh topology                                                             */
/* ------------------------------------------------------------------------ */

static int cmp_u64(const void *a, const void *b) {
    uint64_t x = *(const uint64_t *)a, y = *(const uint64_t *)b;
    return x < y ? -1 : x > y;
}

static void *xmalloc(size_t n) {
    void *p = malloc(n ? n : 1);
    if (!p) {
        fprintf(stderr, "oracle: out of memory\n");
        abort();
    }
    return p;
}

int oracle_mesh_is_closed(const uint32_t *tris, uint32_t tri_count) {
    uint64_t *e = (uint64_t *)xmalloc(sizeof(uint64_t) * 3 * (size_t)tri_count);
    size_t n = 0, i, j;
    uint32_t t;
    int k, closed = 1;
    for (t = 0; t < tri_count; t++) {
        for (k = 0; k < 3; k++) {
            uint32_t u = tris[3 * t + k], v = tris[3 * t + (k + 1) % 3];
            if (u == v) continue;
            if (u > v) { uint32_t w = u; u = v; v = w; }
            e[n++] = ((uint64_t)u << 32) | v;
        }
    }
    qsort(e, n, sizeof(uint64_t), cmp_u64);
    if (n == 0) closed = 0; /* no edge at all: bounds nothing */
    for (i = 0; i < n; i = j) {
        for (j = i; j < n && e[j] == e[i]; j++) {}
        if ((j - i) % 2) { closed = 0; break; }
    }
    free(e);
    return closed;
}

static uint32_t uf_find(uint32_t *parent, uint32_t x) {
    while (parent[x] != x) {
        parent[x] = parent[parent[x]];
        x = parent[x];
    }
    return x;
}

/* One representative vertex per connected component (triangles joined by
 * shared vertex indices). Returns the count; *out is malloc'ed. */
static uint32_t mesh_components(const oracle_mesh *m, uint32_t **out) {
    uint32_t *parent = (uint32_t *)xmalloc(sizeof(uint32_t) * (size_t)m->vertex_count);
    unsigned char *seen = (unsigned char *)xmalloc((size_t)m->vertex_count);
    uint32_t *reps = (uint32_t *)xmalloc(sizeof(uint32_t) * ((size_t)m->triangle_count + 1));
    uint32_t i, t, n = 0;
    for (i = 0; i < m->vertex_count; i++) {
        parent[i] = i;
        seen[i] = 0;
    }
    for (t = 0; t < m->triangle_count; t++) {
        uint32_t a = uf_find(parent, m->tris[3 * t]);
        uint32_t b = uf_find(parent, m->tris[3 * t + 1]);
        uint32_t c = uf_find(parent, m->tris[3 * t + 2]);
        parent[b] = a;
        parent[uf_find(parent, c)] = a;
    }
    for (t = 0; t < m->triangle_count; t++) {
        uint32_t r = uf_find(parent, m->tris[3 * t]);
        if (!seen[r]) {
            seen[r] = 1;
            reps[n++] = m->tris[3 * t];
        }
    }
    free(parent);
    free(seen);
    *out = reps;
    return n;
}

/* ------------------------------------------------------------------------ */
/* Whole scene                                                               */
/* ------------------------------------------------------------------------ */

void oracle_world_vertex(const double position[3], const double orientation[4],
                         double scale, const double m[3], double out[3]) {
    /* volatile stores keep every product and sum a separately rounded double
     * operation whatever the compiler's contraction settings. */
    volatile double x = orientation[0], y = orientation[1],
                    z = orientation[2], w = orientation[3];
    volatile double xx = x * x, yy = y * y, zz = z * z;
    volatile double xy = x * y, xz = x * z, yz = y * z;
    volatile double xw = x * w, yw = y * w, zw = z * w;
    volatile double s1, s2;
    double R[3][3], v[3];
    int a;
    s1 = yy + zz; s2 = 2.0 * s1; R[0][0] = 1.0 - s2;
    s1 = xy - zw; R[0][1] = 2.0 * s1;
    s1 = xz + yw; R[0][2] = 2.0 * s1;
    s1 = xy + zw; R[1][0] = 2.0 * s1;
    s1 = xx + zz; s2 = 2.0 * s1; R[1][1] = 1.0 - s2;
    s1 = yz - xw; R[1][2] = 2.0 * s1;
    s1 = xz - yw; R[2][0] = 2.0 * s1;
    s1 = yz + xw; R[2][1] = 2.0 * s1;
    s1 = xx + yy; s2 = 2.0 * s1; R[2][2] = 1.0 - s2;
    for (a = 0; a < 3; a++) {
        volatile double t = scale * m[a];
        v[a] = t;
    }
    for (a = 0; a < 3; a++) {
        volatile double p0 = R[a][0] * v[0];
        volatile double p1 = R[a][1] * v[1];
        volatile double p2 = R[a][2] * v[2];
        volatile double s = p0 + p1;
        volatile double s3 = s + p2;
        out[a] = position[a] + s3;
    }
}

typedef struct {
    const oracle_mesh *mesh;
    int closed;
    uint32_t comp_count;
    uint32_t *comps;
} mesh_info;

typedef struct {
    double *wv; /* world vertices */
    double lo[3], hi[3];
    mesh_info *info;
} body_data;

static const body_data *g_sort_bodies; /* qsort context (single-threaded) */

static int cmp_body_minx(const void *a, const void *b) {
    size_t i = *(const size_t *)a, j = *(const size_t *)b;
    double x = g_sort_bodies[i].lo[0], y = g_sort_bodies[j].lo[0];
    if (x < y) return -1;
    if (x > y) return 1;
    return i < j ? -1 : i > j;
}

static int cmp_ptr(const void *a, const void *b) {
    const oracle_mesh *x = *(const oracle_mesh *const *)a;
    const oracle_mesh *y = *(const oracle_mesh *const *)b;
    return x < y ? -1 : x > y;
}

static int boxes_overlap(const double *alo, const double *ahi,
                         const double *blo, const double *bhi) {
    int k;
    for (k = 0; k < 3; k++) {
        if (ahi[k] < blo[k] || bhi[k] < alo[k]) return 0;
    }
    return 1;
}

static void tri_box(const double *wv, const uint32_t *tri, double *lo,
                    double *hi) {
    int k, i;
    for (k = 0; k < 3; k++) {
        lo[k] = hi[k] = wv[3 * (size_t)tri[0] + k];
        for (i = 1; i < 3; i++) {
            double v = wv[3 * (size_t)tri[i] + k];
            if (v < lo[k]) lo[k] = v;
            if (v > hi[k]) hi[k] = v;
        }
    }
}

/* Is a component of body a inside closed body b? */
static int contains_component(const body_data *b, const body_data *a) {
    uint32_t c;
    const oracle_mesh *mb = b->info->mesh;
    if (!b->info->closed) return 0;
    for (c = 0; c < a->info->comp_count; c++) {
        const double *v = a->wv + 3 * (size_t)a->info->comps[c];
        int r;
        if (!boxes_overlap(v, v, b->lo, b->hi)) continue;
        r = oracle_point_in_closed_mesh(v, b->wv, mb->vertex_count, mb->tris,
                                        mb->triangle_count);
        if (r < 0) {
            fprintf(stderr, "oracle: undecidable containment test\n");
            abort();
        }
        if (r) return 1;
    }
    return 0;
}

static size_t g_containment_pairs;

size_t oracle_last_containment_pairs(void) { return g_containment_pairs; }

/* 0: apart, 1: surfaces meet, 2: containment only. */
static int bodies_collide(const body_data *a, const body_data *b) {
    const oracle_mesh *ma = a->info->mesh, *mb = b->info->mesh;
    uint32_t s, t;
    int k;
    for (s = 0; s < ma->triangle_count; s++) {
        double alo[3], ahi[3], P[9];
        tri_box(a->wv, ma->tris + 3 * (size_t)s, alo, ahi);
        if (!boxes_overlap(alo, ahi, b->lo, b->hi)) continue;
        for (k = 0; k < 9; k++) P[k] = a->wv[3 * (size_t)ma->tris[3 * s + k / 3] + k % 3];
        for (t = 0; t < mb->triangle_count; t++) {
            double blo[3], bhi[3], Q[9];
            tri_box(b->wv, mb->tris + 3 * (size_t)t, blo, bhi);
            if (!boxes_overlap(alo, ahi, blo, bhi)) continue;
            for (k = 0; k < 9; k++) Q[k] = b->wv[3 * (size_t)mb->tris[3 * t + k / 3] + k % 3];
            if (oracle_tri_tri(P, Q)) return 1;
        }
    }
    return (contains_component(b, a) || contains_component(a, b)) ? 2 : 0;
}

size_t oracle_colliding_pairs(size_t body_count,
                              const oracle_mesh *const *body_mesh,
                              const double *positions,
                              const double *orientations,
                              const double *scales, uint32_t *out_pairs,
                              size_t out_capacity) {
    body_data *bd;
    const oracle_mesh **uniq;
    mesh_info *infos;
    size_t uniq_count = 0, i, j, pair_count = 0, pair_cap = 1024;
    size_t *order;
    uint64_t *pairs;
    g_containment_pairs = 0;
    if (body_count == 0) return 0;
    bd = (body_data *)xmalloc(sizeof(body_data) * body_count);
    uniq = (const oracle_mesh **)xmalloc(sizeof(*uniq) * body_count);
    for (i = 0; i < body_count; i++) uniq[i] = body_mesh[i];
    qsort(uniq, body_count, sizeof(*uniq), cmp_ptr);
    for (i = 0; i < body_count; i++) {
        if (i == 0 || uniq[i] != uniq[i - 1]) uniq[uniq_count++] = uniq[i];
    }
    infos = (mesh_info *)xmalloc(sizeof(mesh_info) * uniq_count);
    for (i = 0; i < uniq_count; i++) {
        infos[i].mesh = uniq[i];
        infos[i].closed = oracle_mesh_is_closed(uniq[i]->tris, uniq[i]->triangle_count);
        infos[i].comp_count = mesh_components(uniq[i], &infos[i].comps);
    }
    for (i = 0; i < body_count; i++) {
        const oracle_mesh *m = body_mesh[i];
        size_t lo = 0, hi = uniq_count;
        uint32_t v;
        int k;
        while (hi - lo > 1) { /* binary search of the mesh pointer */
            size_t mid = (lo + hi) / 2;
            if (cmp_ptr(&uniq[mid], &m) <= 0) lo = mid; else hi = mid;
        }
        bd[i].info = &infos[lo];
        bd[i].wv = (double *)xmalloc(sizeof(double) * 3 * ((size_t)m->vertex_count + 1));
        for (k = 0; k < 3; k++) {
            bd[i].lo[k] = INFINITY;
            bd[i].hi[k] = -INFINITY;
        }
        for (v = 0; v < m->vertex_count; v++) {
            double *w = bd[i].wv + 3 * (size_t)v;
            oracle_world_vertex(positions + 3 * i, orientations + 4 * i,
                                scales[i], m->verts + 3 * (size_t)v, w);
            for (k = 0; k < 3; k++) {
                if (w[k] < bd[i].lo[k]) bd[i].lo[k] = w[k];
                if (w[k] > bd[i].hi[k]) bd[i].hi[k] = w[k];
            }
        }
    }
    order = (size_t *)xmalloc(sizeof(size_t) * body_count);
    for (i = 0; i < body_count; i++) order[i] = i;
    g_sort_bodies = bd;
    qsort(order, body_count, sizeof(size_t), cmp_body_minx);
    pairs = (uint64_t *)xmalloc(sizeof(uint64_t) * pair_cap);
    /* Sweep along x: every pair whose boxes overlap in x is visited once. */
    for (i = 0; i < body_count; i++) {
        const body_data *a = &bd[order[i]];
        for (j = i + 1; j < body_count && bd[order[j]].lo[0] <= a->hi[0]; j++) {
            const body_data *b = &bd[order[j]];
            if (!boxes_overlap(a->lo, a->hi, b->lo, b->hi)) continue;
            int hit = bodies_collide(a, b);
            if (hit) {
                size_t x = order[i], y = order[j];
                if (x > y) { size_t t = x; x = y; y = t; }
                if (pair_count == pair_cap) {
                    uint64_t *np;
                    pair_cap *= 2;
                    np = (uint64_t *)realloc(pairs, sizeof(uint64_t) * pair_cap);
                    if (!np) { fprintf(stderr, "oracle: out of memory\n"); abort(); }
                    pairs = np;
                }
                pairs[pair_count++] = ((uint64_t)x << 32) | (uint64_t)y;
                if (hit == 2) g_containment_pairs++;
            }
        }
    }
    qsort(pairs, pair_count, sizeof(uint64_t), cmp_u64);
    for (i = 0; i < pair_count && i < out_capacity; i++) {
        out_pairs[2 * i] = (uint32_t)(pairs[i] >> 32);
        out_pairs[2 * i + 1] = (uint32_t)(pairs[i] & 0xffffffffu);
    }
    for (i = 0; i < body_count; i++) free(bd[i].wv);
    for (i = 0; i < uniq_count; i++) free(infos[i].comps);
    free(infos);
    free(uniq);
    free(order);
    free(pairs);
    free(bd);
    g_sort_bodies = NULL;
    return pair_count;
}
