// The convex kernel's certificates that a point lies strictly inside a
// body, and from them that two bodies' surfaces cross or one holds the
// other (convex_kernel.cpp includes this header alone: every function is
// inlined into the kernel, see there).
#pragma once
#include "narrow/convex.hpp"
#include "narrow/convex_vec.hpp"
#include "narrow/tetra.hpp"

namespace hgcd {

namespace {

// Is a point certainly strictly inside the solid of body `in` (pose in,
// rotation r, data m with m.inside_test)? z: the point's coordinates in the
// body's frame as computed, within 14 eps dz per axis of the exact ones
// (dz: see the callers).
// In the body's frame, phi(y) = R^T (y - c) (R as rounded: an affine
// bijection, so phi carries solids, surfaces and parity along), the solid is
// the parity solid of the mesh with vertices phi(w_i) = l_i + E_i,
// l_i = fl(s v_i), E_i = (R^T R - I) l_i + R^T e_i, e_i = w_i - (c + R l_i).
// For a quaternion with n2 = |q|^2 = 1 + delta, R = n2 Rhat - delta I up to
// entry roundings of 6 eps, so R^T R - I has entries below 5 |delta| + 40 eps
// and |E_i|_inf <= (5 |delta| + 40 eps) L + 4 eps |c|_inf + 26 eps L; l_i
// is within eps L of s v_i. Let z* be the exact point, and D the largest
// Euclidean displacement of a vertex between the mesh s v and the mesh
// phi(w_i), D <= 2 (that inf-norm bound). If every exact facet plane of the
// hull s H has z* more than D on its inner side, z* is inside s H at
// distance > D from its boundary, which holds the surface of mesh s v; z* / s
// then has the origin's odd parity (SatData::inside_test); moving each
// vertex in a straight line from s v_i to phi(w_i) moves every surface
// point by at most D, never through z*, so the parity stays odd: z* is in
// phi's image of the solid, off its surface, and so is the point in the
// solid, off its surface.
// Per plane g = fl(fl(n . z) - fl(s k)) misses the exact signed distance
// N . (z* - s a) of the facet plane (a a vertex of its triangle) by at most
// theta (|z|_1 + L) + 3 eps L (n and k, mesh.cpp) + 5 eps (|z|_1 + L)
// (evaluation) + |z - z*|_2. So g < -m for every plane with
//   m = 2^-40 (|c|_inf + L + |z|_1 + dz) + 12 dq L + 2 theta (|z|_1 + L)
//       + 2^-960,
// dq = |1 - fl(n2)| + 2^-50 >= |delta| + 24 eps, settles it: 2^-40 = 8192
// eps covers twice the eps terms above, 12 dq L twice 5 |delta| L + 40 eps L.
HGCD_CK_INLINE double inside_margin(const BodyPose &in, const SatData &m, double z1, double dz) {
    const double *c = in.position, *q = in.orientation;
    const double n2 = ((q[0] * q[0] + q[1] * q[1]) + q[2] * q[2]) + q[3] * q[3];
    const double dq = std::fabs(1.0 - n2) + 0x1p-50;
    const double L = in.scale * m.reach;
    return 0x1p-40 * (((norm_inf(c) + L) + z1) + dz) + 12 * dq * L + 2 * m.theta * (z1 + L) + tet::kUnderflowFloor;
}
HGCD_CK_INLINE bool strictly_inside(const BodyPose &in, const SatData &m, const double *z, double dz) {
    const double z1 = norm1(z), margin = inside_margin(in, m, z1, dz);
    // Inside the ball that every plane leaves on its inner side, compared in
    // squares (no square root, whose libm fallback valgrind cannot follow in
    // the AVX2 build): with t = fl(fl(s inner) (1 - 2^-48)) - m > 0 and
    // fl(z . z) (1 + 2^-46) < fl(t t) (1 - 2^-48), |z|_2 < t (the roundings
    // are below 4 eps), so for each plane n . z - s k <= (1 + 4 eps) |z|_2 -
    // s inner < (1 + 6 eps) (fl(s inner) (1 - 2^-48) - m) - s inner < -m:
    // the planes' test holds, without the evaluation error m also covers.
    const double t = (in.scale * m.inner) * (1 - 0x1p-48) - margin;
    const double zz2 = (z[0] * z[0] + z[1] * z[1]) + z[2] * z[2];
    if (t > 0 && zz2 * (1 + 0x1p-46) < (t * t) * (1 - 0x1p-48)) return true;
    const uint32_t n = m.planes_padded;
    const double *nx = m.planes(), *ny = nx + n, *nz = ny + n, *k = nz + n;
    const f64x4 zx = splat(z[0]), zy = splat(z[1]), zz = splat(z[2]), s = splat(in.scale), lim = splat(-margin);
    for (uint32_t i = 0; i < n; i += SatData::kLanes) {
        const f64x4 g = ((load4(nx + i) * zx + load4(ny + i) * zy) + load4(nz + i) * zz) - s * load4(k + i);
        const i64x4 out = g >= lim;
        if (any4(out)) return false;
    }
    return true;
}

// Is the world vertex w of another body strictly inside body `in`? Its
// frame coordinates z = fl(R^T fl(w - c)) are within 10 eps |fl(w - c)|_1
// of the exact ones on each axis.
HGCD_CK_INLINE bool vertex_inside(const BodyPose &in, const Rotation &r, const SatData &m, const double *w) {
    const double *c = in.position;
    const double D[3] = {w[0] - c[0], w[1] - c[1], w[2] - c[2]};
    double z[3];
    rotate_t(r, D, z);
    return strictly_inside(in, m, z, norm1(D));
}

// Does vertex v of `b` lie strictly inside a, while some vertex of b lies
// strictly outside a (found on the line of centres)? Then b's surface,
// connected (inside_test: one component), has a path of edges from a point
// inside a's solid to one outside, which crosses a's surface: the surfaces
// meet.
HGCD_CK_INLINE bool vertex_poke(const BodyPose &a, const Rotation &ra, const SatData &sa, const BodyPose &b,
                                const Rotation &rb, const SatData &sb, uint32_t v) {
    double w[3];
    double x[3];
    vertex_of(sb, v, x);
    transform_point(rb, b.position, b.scale, x, w);
    return vertex_inside(a, ra, sa, w);
}

// Where the ray from the body's position along d (its frame) leaves the
// hull of its face planes, in units of d: min (s k) / (n . d) over the
// planes facing d. Only a guess (the point it yields is certified later).
HGCD_CK_INLINE double exit_along(const SatData &m, double s, const double *d) {
    const uint32_t n = m.planes_padded;
    const double *nx = m.planes(), *ny = nx + n, *nz = ny + n, *k = nz + n;
    const f64x4 dx = splat(d[0]), dy = splat(d[1]), dz = splat(d[2]), sv = splat(s), inf = splat(INFINITY);
    f64x4 t = inf;
    for (uint32_t i = 0; i < n; i += SatData::kLanes) {
        const f64x4 g = (load4(nx + i) * dx + load4(ny + i) * dy) + load4(nz + i) * dz;
        const f64x4 r = (sv * load4(k + i)) / g;
        t = vmin4(t, g > 0 ? r : inf);
    }
    return hmin4(t);
}

// A point strictly inside both solids, while each body has a vertex
// strictly outside the other (a_out, b_out: found on the line of centres):
// then the surfaces meet. (Were they apart, each connected surface would lie
// wholly outside the other solid, as its outer vertex does; the
// intersection of the solids would be a bounded mod-2 3-chain whose boundary,
// (S_a in b) + (a in S_b), is empty, hence null, yet it holds a ball about
// the point.) The point: P = c_a + t u, u = fl(c_b - c_a), the middle of the
// stretch of the segment from c_a to c_b inside both faces' hulls. In a's
// frame its exact coordinates are t R_a^T u, computed as fl(t da), within
// 14 eps |t| |u|_1 (da within 12 eps |u|_1 of R_a^T u); in b's frame
// R_b^T ((t - 1) u + (u - (c_b - c_a))), computed as fl((1 - t) db), within
// 14 eps (|1 - t| + 1) |u|_1 (u within eps |u|_inf of c_b - c_a).
HGCD_CK_INLINE bool point_inside_both(const BodyPose &a, const SatData &sa, const BodyPose &b, const SatData &sb,
                                      const double *u, const double *da, const double *db) {
    const double ta = exit_along(sa, a.scale, da), tb = exit_along(sb, b.scale, db);
    if (!(ta + tb > 1)) return false;
    const double t = 0.5 * ((1 - tb) + ta), t1 = 1 - t, u1 = norm1(u);
    const double za[3] = {t * da[0], t * da[1], t * da[2]}, zb[3] = {t1 * db[0], t1 * db[1], t1 * db[2]};
    return strictly_inside(a, sa, za, std::fabs(t) * u1) && strictly_inside(b, sb, zb, (std::fabs(t1) + 1) * u1);
}

// The edge test below reads every vertex of one body against every plane of
// the other: at most this many values.
constexpr uint32_t kEdgePokeWork = 512;

// Does a point of an edge of b lie strictly inside a, while some vertex of
// b lies strictly outside a (b_out, found on the line of centres, else
// found here: its value g on one of a's planes above strictly_inside's
// margin m, which covers the error of g against the exact distance N . (z*
// - s a) of z* beyond the exact facet plane of the hull s H plus the largest
// vertex displacement D there, so z* lies more than D beyond that plane,
// while the solid of the mesh with vertices phi(w_i), in the hull of those
// vertices, each within D of s v_i, lies within D of it: z* is outside the
// solid, off its surface)? Then, as
// for vertex_poke, b's connected surface has a path from a point inside a's
// solid to one outside, which crosses a's surface: the surfaces meet. (Two
// boxes crossing edge to edge have no vertex inside the other.)
// The point is only guessed from the planes' values g at the vertices (g is
// affine along an edge: the stretch of the edge that every plane leaves on
// its inner side) and then certified by strictly_inside: with z_p, z_q the
// frame coordinates of the edge's ends p, q as vertex_inside computes them
// (within 10 eps D_p, 10 eps D_q per axis of the exact ones, D = |fl(w -
// c)|_1) and t in [0, 1], z = fl(z_p + fl(t fl(z_q - z_p))) is the point
// (1 - t) w_p + t w_q of the edge, whose exact frame coordinates are z*_p +
// t (z*_q - z*_p) (the frame map is affine), up to (1 - t) (z_p - z*_p) +
// t (z_q - z*_q), at most 10 eps (D_p + D_q), and three roundings of values
// below 4 (D_p + D_q) (|z_p|_inf < 2 D_p: |R_kj| < 2), below 8 eps (D_p +
// D_q) with a product's underflow (2^-1074, below strictly_inside's floor):
// strictly_inside's dz = 2 (D_p + D_q) covers the 18 eps (D_p + D_q).
HGCD_CK_INLINE bool edge_poke(const BodyPose &a, const Rotation &ra, const SatData &sa, const BodyPose &b,
                              const Rotation &rb, const SatData &sb, bool b_out) {
    const uint32_t nv = sb.vertex_count, np = sa.planes_padded;
    if (nv * np > kEdgePokeWork) return false;
    double zx[Mesh::kSatVertices], zy[Mesh::kSatVertices], zz[Mesh::kSatVertices], dist[Mesh::kSatVertices];
    double g[kEdgePokeWork];
    const double *ca = a.position, *nx = sa.planes(), *ny = nx + np, *nz = ny + np, *k = nz + np;
    const f64x4 s = splat(a.scale);
    {
        // Four vertices at a time from b's runs (padded: at most
        // kSatVertices), lane by lane vertex_inside's operations on
        // transform_point's world vertex: the same bits.
        const uint32_t pad = sb.padded;
        const double *bx = sb.soa(), *by = bx + pad, *bz = by + pad, *cb = b.position;
        const f64x4 sv = splat(b.scale);
        for (uint32_t v = 0; v < nv; v += SatData::kLanes) {
            const f64x4 lx = sv * load4(bx + v), ly = sv * load4(by + v), lz = sv * load4(bz + v);
            f64x4 D[3], z[3];
            for (int j = 0; j < 3; ++j)
                D[j] = (splat(cb[j]) + ((splat(rb.m[3 * j]) * lx + splat(rb.m[3 * j + 1]) * ly) +
                                        splat(rb.m[3 * j + 2]) * lz)) -
                       splat(ca[j]);
            for (int j = 0; j < 3; ++j)
                z[j] = (splat(ra.m[j]) * D[0] + splat(ra.m[3 + j]) * D[1]) + splat(ra.m[6 + j]) * D[2];
            const f64x4 d1 = (vabs(D[0]) + vabs(D[1])) + vabs(D[2]);
            std::memcpy(zx + v, &z[0], sizeof z[0]);
            std::memcpy(zy + v, &z[1], sizeof z[1]);
            std::memcpy(zz + v, &z[2], sizeof z[2]);
            std::memcpy(dist + v, &d1, sizeof d1);
        }
    }
    for (uint32_t v = 0; v < nv; ++v) {
        const f64x4 vx = splat(zx[v]), vy = splat(zy[v]), vz = splat(zz[v]);
        for (uint32_t i = 0; i < np; i += SatData::kLanes) {
            const f64x4 gv = ((load4(nx + i) * vx + load4(ny + i) * vy) + load4(nz + i) * vz) - s * load4(k + i);
            std::memcpy(&g[v * np + i], &gv, sizeof gv);
        }
    }
    for (uint32_t v = 0; v < nv && !b_out; ++v) {
        f64x4 most = load4(&g[v * np]);
        for (uint32_t i = SatData::kLanes; i < np; i += SatData::kLanes) most = vmax4(most, load4(&g[v * np + i]));
        const double gv = hmax4(most);
        b_out = gv > 0 && gv > inside_margin(a, sa, (std::fabs(zx[v]) + std::fabs(zy[v])) + std::fabs(zz[v]), dist[v]);
    }
    if (!b_out) return false;
    const f64x4 zero = splat(0), one = splat(1);
    for (uint32_t p = 0; p < nv; ++p)
        for (uint32_t e = sb.vertex_edge_start()[p]; e < sb.vertex_edge_start()[p + 1]; ++e) {
            const uint32_t q = sb.vertex_edges()[e];
            if (q < p) continue;  // (each edge once)
            // (First whether both ends are outside one plane, most edges'
            // case, without the divisions.)
            i64x4 none = i64x4{};
            for (uint32_t i = 0; i < np; i += SatData::kLanes)
                none |= (load4(&g[p * np + i]) >= zero) & (load4(&g[q * np + i]) >= zero);
            if (any4(none)) continue;
            f64x4 lo = zero, hi = one;
            for (uint32_t i = 0; i < np; i += SatData::kLanes) {
                const f64x4 gp = load4(&g[p * np + i]), gq = load4(&g[q * np + i]);
                const i64x4 p_out = gp >= zero, q_out = gq >= zero;
                const f64x4 r = gp / (gp - gq);  // (used only where the signs differ)
                lo = vmax4(lo, (p_out & ~q_out) ? r : zero);
                hi = vmin4(hi, (q_out & ~p_out) ? r : one);
            }
            const double tlo = hmax4(lo), thi = hmin4(hi);
            if (!(tlo < thi)) continue;
            const double t = 0.5 * (tlo + thi);
            const double z[3] = {zx[p] + t * (zx[q] - zx[p]), zy[p] + t * (zy[q] - zy[p]),
                                 zz[p] + t * (zz[q] - zz[p])};
            if (strictly_inside(a, sa, z, 2 * (dist[p] + dist[q]))) return true;
        }
    return false;
}

// Every vertex of `in` strictly inside `out` (by vertex_inside's depth
// test): then `in`'s surface, in the hull of its vertices, is inside out's
// solid and off its surface. (The depth test puts each vertex's image z*
// more than D inside every facet plane of s H, and the hull of such points
// is too, plane by plane; the argument of strictly_inside then holds for
// each of its points.) So the solids meet and the surfaces do not.
HGCD_CK_INLINE bool holds_all(const BodyPose &out, const Rotation &ro, const SatData &so, const BodyPose &in,
                              const Rotation &ri, const SatData &m) {
    for (uint32_t v = 0; v < m.vertex_count; ++v) {
        double w[3];
        double x[3];
        vertex_of(m, v, x);
        transform_point(ri, in.position, in.scale, x, w);
        if (!vertex_inside(out, ro, so, w)) return false;
    }
    return true;
}

}  // namespace

}  // namespace hgcd
