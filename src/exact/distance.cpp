// Exact "within distance d" tests of triangles, for the contact margin:
// tri_tri_within (geometry.hpp).
//
// Two closed triangles are within d (their distance, the least |x - y| over
// x in one and y in the other, is at most d) exactly when
//   - they share a point (tri_tri_intersect), or
//   - a vertex of one is within d of the other triangle, or
//   - an edge of one and an edge of the other are within d,
// since disjoint convex polygons have a closest pair with one point at a
// vertex or both on edges. Each of these is decided without division or
// square root, as signs of polynomials in the coordinate differences and d:
//
//   point p, segment [a, b], u = b - a:
//     (p - a).u <= 0:            |p - a|^2 <= d^2
//     (p - b).(a - b) <= 0:      |p - b|^2 <= d^2
//     otherwise (interior):      |(p - a) x u|^2 <= d^2 |u|^2
//   point p over the triangle (a, b, c), n = (b - a) x (c - a) != 0, p's
//   projection in the closed triangle (((v' - v) x n).(p - v) <= 0 for each
//   edge v -> v' in the order a, b, c):  (n.(p - a))^2 <= d^2 |n|^2;
//   a projection outside is nearest to an edge, which the point-segment
//   tests cover; so does a zero-area triangle (n = 0), which is its edges;
//   segments p0 + s u and q0 + t v, w = p0 - q0, c = u x v, D = |c|^2 > 0,
//   the lines' closest points interior to both segments:
//     0 < s D = (u.v)(v.w) - (v.v)(u.w) < D,
//     0 < t D = (u.u)(v.w) - (u.v)(u.w) < D,
//   then (c.w)^2 <= d^2 D. Otherwise (parallel, or closest points outside)
//   the segments' closest pair has an endpoint: the point-segment tests.
//
// Every polynomial is homogeneous in the differences and d, of degree at
// most 6. Each sign is decided by a floating-point filter with a proven
// bound, else exactly with big integers (exact/big.hpp).
//
// The filter (Burnikel, Funke and Schirra's running error bound): every
// value carries its rounded value v and a magnitude m, built from the
// rounded differences x - y (m = |v|) and d (m = d) by m(a +- b) = m(a) +
// m(b), m(a b) = m(a) m(b). Without underflow |v - exact| <= k u m' where
// u = 2^-53, k is the value's index (1 for a difference and d^2's factor
// d costs 0; +1 per addition on the larger index, a + b + 1 for a
// product) and m' the magnitude in exact arithmetic, m' <= m (1 + u)^k. The
// largest index here is 18 ((n.w)^2 - d^2 |n|^2 and (c.w)^2 - d^2 D), so
// |v| > 2^-46 m > 18 u (1 + u)^18 m certifies the sign. Underflow: with
// differences and d below 2^53 (world coordinates are within 2^51 by the
// contract; margins are at most 1e15 each), an underflowed product adds at
// most 2^-1075, multiplied afterwards by at most 2^(53 * 5) over fewer than
// 2^8 terms: below 2^-800, which the slack 2^-700 covers.
#include "common/ieee.hpp"

#include <cmath>

#include "exact/big.hpp"
#include "exact/geometry.hpp"

namespace hgcd {

namespace {

using predicates::Big;

constexpr int kUnsure = 2;

// A filtered value: rounded value and magnitude.
struct F {
    double v, m;
};
inline F operator+(F a, F b) { return {a.v + b.v, a.m + b.m}; }
inline F operator-(F a, F b) { return {a.v - b.v, a.m + b.m}; }
inline F operator*(F a, F b) { return {a.v * b.v, a.m * b.m}; }
inline int filter_sign(F a) {
    const double bound = 0x1p-46 * a.m + 0x1p-700;
    return a.v > bound ? 1 : a.v < -bound ? -1 : kUnsure;
}

// An exact value (rare: only where the filter cannot decide).
struct N {
    Big b;
};
inline N operator+(const N &a, const N &c) {
    N r;
    predicates::big_add(a.b, c.b, 0, r.b);
    return r;
}
inline N operator-(const N &a, const N &c) {
    N r;
    predicates::big_add(a.b, c.b, 1, r.b);
    return r;
}
inline N operator*(const N &a, const N &c) {
    N r;
    predicates::big_mul(a.b, c.b, r.b);
    return r;
}

template <class T>
struct V3 {
    T x[3];
};
template <class T>
inline T dot(const V3<T> &a, const V3<T> &b) {
    return (a.x[0] * b.x[0] + a.x[1] * b.x[1]) + a.x[2] * b.x[2];
}
template <class T>
inline V3<T> cross(const V3<T> &a, const V3<T> &b) {
    return V3<T>{{a.x[1] * b.x[2] - a.x[2] * b.x[1], a.x[2] * b.x[0] - a.x[0] * b.x[2],
                  a.x[0] * b.x[1] - a.x[1] * b.x[0]}};
}

// The six vertices (p0 p1 p2 of one triangle, 3 4 5 the other's) and d,
// as doubles, and as big integers on one scale once some sign needs them.
struct Pair {
    const double *p[6];
    double d;
    bool exact_ready = false;
    N big[19];  // 3 per vertex, then d
};

// Reads the pair's values as filtered doubles.
struct FloatView {
    const Pair &c;
    V3<F> diff(int i, int j) const {
        V3<F> r;
        for (int k = 0; k < 3; ++k) {
            const double v = c.p[i][k] - c.p[j][k];
            r.x[k] = F{v, std::fabs(v)};
        }
        return r;
    }
    F margin() const { return F{c.d, c.d}; }
};

// Reads them exactly.
struct ExactView {
    const Pair &c;
    V3<N> diff(int i, int j) const {
        V3<N> r;
        for (int k = 0; k < 3; ++k) r.x[k] = c.big[3 * i + k] - c.big[3 * j + k];
        return r;
    }
    const N &margin() const { return c.big[18]; }
};

void make_exact(Pair &c) {
    double x[19];
    for (int i = 0; i < 6; ++i)
        for (int k = 0; k < 3; ++k) x[3 * i + k] = c.p[i][k];
    x[18] = c.d;
    Big b[19];
    predicates::big_from_doubles(x, 19, b);
    for (int i = 0; i < 19; ++i) c.big[i].b = b[i];
    c.exact_ready = true;
}

// The exact sign of the polynomial poly(view): filtered, else exact.
template <class Poly>
int sign(Pair &c, Poly &&poly) {
    const int s = filter_sign(poly(FloatView{c}));
    if (s != kUnsure) return s;
    if (!c.exact_ready) make_exact(c);
    return predicates::big_sign(poly(ExactView{c}).b);
}

// Is vertex p within d of the segment [a, b]?
bool point_segment(Pair &c, int p, int a, int b) {
    if (sign(c, [&](auto v) { return dot(v.diff(p, a), v.diff(b, a)); }) <= 0)
        return sign(c, [&](auto v) {
                   const auto w = v.diff(p, a);
                   return dot(w, w) - v.margin() * v.margin();
               }) <= 0;
    if (sign(c, [&](auto v) { return dot(v.diff(p, b), v.diff(a, b)); }) <= 0)
        return sign(c, [&](auto v) {
                   const auto w = v.diff(p, b);
                   return dot(w, w) - v.margin() * v.margin();
               }) <= 0;
    return sign(c, [&](auto v) {
               const auto u = v.diff(b, a);
               const auto x = cross(v.diff(p, a), u);
               return dot(x, x) - (v.margin() * v.margin()) * dot(u, u);
           }) <= 0;
}

// Is vertex p within d of the triangle t[0..2] through its face (the
// projection of p in the closed triangle)? False for a zero-area triangle.
bool point_face(Pair &c, int p, const int *t) {
    if (collinear3d(c.p[t[0]], c.p[t[1]], c.p[t[2]])) return false;
    for (int i = 0; i < 3; ++i) {
        const int a = t[i], b = t[(i + 1) % 3];
        const int s = sign(c, [&](auto v) {
            const auto n = cross(v.diff(t[1], t[0]), v.diff(t[2], t[0]));
            return dot(cross(v.diff(b, a), n), v.diff(p, a));
        });
        if (s > 0) return false;
    }
    return sign(c, [&](auto v) {
               const auto n = cross(v.diff(t[1], t[0]), v.diff(t[2], t[0]));
               const auto h = dot(n, v.diff(p, t[0]));
               return h * h - (v.margin() * v.margin()) * dot(n, n);
           }) <= 0;
}

// Are segments [p0, p1] and [q0, q1] within d with their closest points
// interior to both (see the top)?
bool edge_edge_interior(Pair &c, int p0, int p1, int q0, int q1) {
    const int D = sign(c, [&](auto v) {
        const auto x = cross(v.diff(p1, p0), v.diff(q1, q0));
        return dot(x, x);
    });
    if (D <= 0) return false;  // parallel (or a point)
    // s D and t D strictly between 0 and D.
    for (int which = 0; which < 2; ++which) {
        auto num = [&](auto v) {
            const auto u = v.diff(p1, p0), w = v.diff(p0, q0), e = v.diff(q1, q0);
            return which == 0 ? dot(u, e) * dot(e, w) - dot(e, e) * dot(u, w)
                              : dot(u, u) * dot(e, w) - dot(u, e) * dot(u, w);
        };
        if (sign(c, num) <= 0) return false;
        if (sign(c, [&](auto v) {
                const auto x = cross(v.diff(p1, p0), v.diff(q1, q0));
                return dot(x, x) - num(v);
            }) <= 0)
            return false;
    }
    return sign(c, [&](auto v) {
               const auto x = cross(v.diff(p1, p0), v.diff(q1, q0));
               const auto h = dot(x, v.diff(p0, q0));
               return h * h - (v.margin() * v.margin()) * dot(x, x);
           }) <= 0;
}

// A float-only certificate that the plane of triangle t (3 vertices) has
// every vertex of the other triangle o farther than d on one side (then so
// is all of o, and the triangles are more than d apart). Never decides
// "within": an uncertain case is left to the exact tests. Each signed
// value n.(x - t0) (n the rounded normal) is within 2^-48 m of the exact
// one with the exact normal N (index 8 in the sense above, m its
// magnitude), and |N| <= |n| (1 + 2^-50) + 2^-50 mn (mn the normal's
// magnitudes); both bounds carry a wide factor for their own rounding.
bool plane_separates(const double *const *t, const double *const *o, double d) {
    const double ux = t[1][0] - t[0][0], uy = t[1][1] - t[0][1], uz = t[1][2] - t[0][2];
    const double vx = t[2][0] - t[0][0], vy = t[2][1] - t[0][1], vz = t[2][2] - t[0][2];
    const double n[3] = {uy * vz - uz * vy, uz * vx - ux * vz, ux * vy - uy * vx};
    const double an[3] = {std::fabs(uy * vz) + std::fabs(uz * vy), std::fabs(uz * vx) + std::fabs(ux * vz),
                          std::fabs(ux * vy) + std::fabs(uy * vx)};
    const double len = std::sqrt((n[0] * n[0] + n[1] * n[1]) + n[2] * n[2]) * (1 + 0x1p-40) +
                       0x1p-40 * ((an[0] + an[1]) + an[2]);
    const double need = d * len * (1 + 0x1p-40);
    int above = 0, below = 0;
    for (int i = 0; i < 3; ++i) {
        const double wx = o[i][0] - t[0][0], wy = o[i][1] - t[0][1], wz = o[i][2] - t[0][2];
        const double h = (n[0] * wx + n[1] * wy) + n[2] * wz;
        const double m = (an[0] * std::fabs(wx) + an[1] * std::fabs(wy)) + an[2] * std::fabs(wz);
        const double bound = need + 0x1p-45 * m + 0x1p-700;
        above += h > bound;
        below += h < -bound;
    }
    return above == 3 || below == 3;
}

}  // namespace

bool tri_tri_within(const double *p0, const double *p1, const double *p2, const double *q0, const double *q1,
                    const double *q2, double d) {
    // Boxes farther apart than d on an axis: apart (rounding is monotone,
    // so fl(lo - hi) > d implies lo - hi > d).
    const double *p[3] = {p0, p1, p2}, *q[3] = {q0, q1, q2};
    for (int k = 0; k < 3; ++k) {
        const double plo = std::fmin(std::fmin(p0[k], p1[k]), p2[k]), phi = std::fmax(std::fmax(p0[k], p1[k]), p2[k]);
        const double qlo = std::fmin(std::fmin(q0[k], q1[k]), q2[k]), qhi = std::fmax(std::fmax(q0[k], q1[k]), q2[k]);
        if (qlo - phi > d || plo - qhi > d) return false;
    }
    if (!(d > 0)) return tri_tri_intersect(p0, p1, p2, q0, q1, q2);
    if (plane_separates(q, p, d) || plane_separates(p, q, d)) return false;
    Pair c;
    for (int i = 0; i < 3; ++i) {
        c.p[i] = p[i];
        c.p[3 + i] = q[i];
    }
    c.d = d;
    // Any order gives the same answer; the cheap and common first: resting
    // contact nearly always has a vertex within d of a vertex or an edge.
    for (int i = 0; i < 3; ++i)
        for (int j = 3; j < 6; ++j)
            if (sign(c, [&](auto v) {
                    const auto w = v.diff(i, j);
                    return dot(w, w) - v.margin() * v.margin();
                }) <= 0)
                return true;
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j)
            if (point_segment(c, i, 3 + j, 3 + (j + 1) % 3) || point_segment(c, 3 + i, j, (j + 1) % 3))
                return true;
    static const int ta[3] = {0, 1, 2}, tb[3] = {3, 4, 5};
    for (int i = 0; i < 3; ++i)
        if (point_face(c, i, tb) || point_face(c, 3 + i, ta)) return true;
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j)
            if (edge_edge_interior(c, i, (i + 1) % 3, 3 + j, 3 + (j + 1) % 3)) return true;
    // Crossing triangles with every feature pair farther than d apart.
    return tri_tri_intersect(p0, p1, p2, q0, q1, q2);
}

bool features_within(const double *const *a, int na, const double *const *b, int nb, double d) {
    if (na > nb) return features_within(b, nb, a, na, d);
    if (nb == 3 && na >= 2) return tri_tri_within(a[0], a[1], a[na - 1], b[0], b[1], b[2], d);
    Pair c;
    for (int i = 0; i < 3; ++i) {
        c.p[i] = a[i < na ? i : na - 1];
        c.p[3 + i] = b[i < nb ? i : nb - 1];
    }
    c.d = d;
    if (nb == 1)  // two points
        return sign(c, [&](auto v) {
                   const auto w = v.diff(0, 3);
                   return dot(w, w) - v.margin() * v.margin();
               }) <= 0;
    if (na == 1 && nb == 2) return point_segment(c, 0, 3, 4);
    if (na == 1) {  // a point and a triangle: through its face, else an edge
        static const int tb[3] = {3, 4, 5};
        return point_face(c, 0, tb) || point_segment(c, 0, 3, 4) || point_segment(c, 0, 4, 5) ||
               point_segment(c, 0, 5, 3);
    }
    // Two segments: closest points interior to both, else an endpoint.
    return edge_edge_interior(c, 0, 1, 3, 4) || point_segment(c, 0, 3, 4) || point_segment(c, 1, 3, 4) ||
           point_segment(c, 3, 0, 1) || point_segment(c, 4, 0, 1);
}

}  // namespace hgcd
