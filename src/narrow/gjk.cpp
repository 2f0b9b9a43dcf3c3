// GJK's distance subalgorithm and loop (gjk.hpp).
#include "common/ieee.hpp"
#include "narrow/gjk.hpp"

#include <cmath>

namespace hgcd {

namespace {

inline double dot3(const double *a, const double *b) { return (a[0] * b[0] + a[1] * b[1]) + a[2] * b[2]; }

inline void sub3(const double *a, const double *b, double *out) {
    out[0] = a[0] - b[0];
    out[1] = a[1] - b[1];
    out[2] = a[2] - b[2];
}

// The point of the triangle (a, b, c) nearest the origin into v, and the
// vertices it needs (bits 1, 2, 4 for a, b, c): Ericson, Real-Time
// Collision Detection, 5.1.5.
unsigned nearest_on_triangle(const double *a, const double *b, const double *c, double *v) {
    double ab[3], ac[3], bc[3];
    sub3(b, a, ab);
    sub3(c, a, ac);
    const double d1 = -dot3(ab, a), d2 = -dot3(ac, a);
    if (d1 <= 0 && d2 <= 0) {
        for (int k = 0; k < 3; ++k) v[k] = a[k];
        return 1;
    }
    const double d3 = -dot3(ab, b), d4 = -dot3(ac, b);
    if (d3 >= 0 && d4 <= d3) {
        for (int k = 0; k < 3; ++k) v[k] = b[k];
        return 2;
    }
    const double vc = d1 * d4 - d3 * d2;
    if (vc <= 0 && d1 >= 0 && d3 <= 0) {
        const double t = d1 / (d1 - d3);
        for (int k = 0; k < 3; ++k) v[k] = a[k] + t * ab[k];
        return 3;
    }
    const double d5 = -dot3(ab, c), d6 = -dot3(ac, c);
    if (d6 >= 0 && d5 <= d6) {
        for (int k = 0; k < 3; ++k) v[k] = c[k];
        return 4;
    }
    const double vb = d5 * d2 - d1 * d6;
    if (vb <= 0 && d2 >= 0 && d6 <= 0) {
        const double t = d2 / (d2 - d6);
        for (int k = 0; k < 3; ++k) v[k] = a[k] + t * ac[k];
        return 5;
    }
    const double va = d3 * d6 - d5 * d4;
    if (va <= 0 && d4 - d3 >= 0 && d5 - d6 >= 0) {
        const double t = (d4 - d3) / ((d4 - d3) + (d5 - d6));
        sub3(c, b, bc);
        for (int k = 0; k < 3; ++k) v[k] = b[k] + t * bc[k];
        return 6;
    }
    const double den = 1 / ((va + vb) + vc), s = vb * den, t = vc * den;
    for (int k = 0; k < 3; ++k) v[k] = a[k] + s * ab[k] + t * ac[k];
    return 7;
}

}  // namespace

// The simplex reduced to the points whose hull holds its point nearest the
// origin, that point into v. False when a full simplex (a tetrahedron)
// holds the origin.
bool gjk_reduce(Simplex &s, double *v) {
    const double(*w)[3] = s.w;
    if (s.n == 1) {
        for (int k = 0; k < 3; ++k) v[k] = w[0][k];
        return true;
    }
    if (s.n == 2) {
        double ab[3];
        sub3(w[1], w[0], ab);
        const double t = -dot3(w[0], ab), len = dot3(ab, ab);
        if (t <= 0 || !(len > 0)) {
            s.keep(1);
            return gjk_reduce(s, v);
        }
        if (t >= len) {
            s.keep(2);
            return gjk_reduce(s, v);
        }
        const double f = t / len;
        for (int k = 0; k < 3; ++k) v[k] = w[0][k] + f * ab[k];
        return true;
    }
    if (s.n == 3) {
        s.keep(nearest_on_triangle(w[0], w[1], w[2], v));
        return true;
    }
    // A tetrahedron: the nearest of the faces the origin lies outside of
    // (or on the plane of); none: the origin is inside.
    static const int kFaces[4][4] = {{0, 1, 2, 3}, {0, 2, 3, 1}, {0, 3, 1, 2}, {1, 3, 2, 0}};
    double best = INFINITY;
    unsigned best_mask = 0;
    for (const int *f : kFaces) {
        double e1[3], e2[3], n[3], o[3];
        sub3(w[f[1]], w[f[0]], e1);
        sub3(w[f[2]], w[f[0]], e2);
        n[0] = e1[1] * e2[2] - e1[2] * e2[1];
        n[1] = e1[2] * e2[0] - e1[0] * e2[2];
        n[2] = e1[0] * e2[1] - e1[1] * e2[0];
        sub3(w[f[3]], w[f[0]], o);
        if (-dot3(w[f[0]], n) * dot3(o, n) > 0) continue;  // origin on the inner side
        double q[3];
        const unsigned m = nearest_on_triangle(w[f[0]], w[f[1]], w[f[2]], q);
        const double qq = dot3(q, q);
        if (qq < best) {
            best = qq;
            best_mask = 0;
            for (int k = 0; k < 3; ++k)
                if (m >> k & 1) best_mask |= 1u << f[k];
            for (int k = 0; k < 3; ++k) v[k] = q[k];
        }
    }
    if (!best_mask) return false;
    s.keep(best_mask);
    return true;
}

Gjk gjk(const double *wa, uint32_t na, const double *wb, uint32_t nb, double d, Simplex &s, double *v,
        const double *v0) {
    if (v0) {
        s.n = 0;
        for (int k = 0; k < 3; ++k) v[k] = v0[k];
    } else {
        s.n = 1;
        s.ia[0] = s.ib[0] = 0;
        sub3(wa, wb, s.w[0]);
        for (int k = 0; k < 3; ++k) v[k] = s.w[0][k];
    }
    // The point of w (n points) farthest along sign * dir.
    auto extreme = [](const double *w, uint32_t n, double sign, const double *dir, const double **point) {
        uint32_t best = 0;
        double far = sign * dot3(dir, w);
        for (uint32_t i = 1; i < n; ++i)
            if (const double p = sign * dot3(dir, &w[3 * size_t(i)]); p > far) far = p, best = i;
        *point = &w[3 * size_t(best)];
        return best;
    };
    auto lowest_a = [&](const double *dir, const double **point) { return extreme(wa, na, -1, dir, point); };
    auto highest_b = [&](const double *dir, const double **point) { return extreme(wb, nb, 1, dir, point); };
    return gjk_run(lowest_a, highest_b, d, s, v);
}

}  // namespace hgcd
