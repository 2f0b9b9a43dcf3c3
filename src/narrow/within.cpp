// The contact margin's certificates for small meshes, and the tetrahedron
// pairs' margin test (within.hpp).
//
// A pair with a margin d is reported when its closed solids are within d.
// Touching pairs are decided by the exact touching test; the pairs left are
// apart, and most of them by far more than d. What decides them cheaply is
// the pair of closest points of the two vertex sets' hulls, found in floating
// point by GJK (Gilbert, Johnson and Keerthi), after the cheaper face
// planes with a gap of d (face_apart): its direction v (from B's
// closest point to A's) is an axis along which the hulls are as far apart as
// they are at all, and its simplex names the features (vertices, an edge, a
// face of each) where the hulls come closest. Neither needs to be exact:
//   - apart: the projections on v are compared with certified error bounds
//     (axis_apart), which proves a gap of more than d whatever v is;
//   - within: the exact predicate features_within decides whether the hulls
//     of the named vertex sets are within d. For a tetrahedron every subset
//     of its vertices spans a vertex, an edge or a face of its solid (the
//     hull of its four vertices), so a pair of features within d is a pair
//     of solid points within d.
// A pair whose distance is too close to d for either (or that GJK leaves
// open) takes the exact direct path, so every answer is exact.
#include "narrow/within.hpp"

#include <algorithm>
#include <cmath>

#include "common/ieee.hpp"
#include "common/transform.hpp"
#include "exact/geometry.hpp"
#include "narrow/boxes.hpp"
#include "narrow/gjk.hpp"
#include "narrow/tetra.hpp"

namespace hgcd {

namespace {

inline double dot3(const double *a, const double *b) { return (a[0] * b[0] + a[1] * b[1]) + a[2] * b[2]; }

}  // namespace

// Each projection c . (x - r) (r the first point of wa) is within 2^-48
// sum |c_k| |x_k - r_k| of its exact value (a rounded difference, three
// products, two sums: index 4; the bound is 8 times that, which also covers
// rounding p -+ e), plus 2^-700 for underflowed products (|c| <= 2 after the
// scaling, so each loses at most 2^-1074). |c| <= sqrt(c.c) (1 + 1e-12) as c
// is scaled to [1, 2) in its largest component (no underflow in c.c); the
// factors 1 +- 1e-12 cover the rounding of the bounds themselves.
bool axis_apart(const double *axis, const double *wa, uint32_t na, const double *wb, uint32_t nb, double d) {
    const double big = std::max(std::max(std::fabs(axis[0]), std::fabs(axis[1])), std::fabs(axis[2]));
    if (!(big > 0) || !std::isfinite(big)) return false;
    const int e = std::ilogb(big);
    const double c[3] = {std::ldexp(axis[0], -e), std::ldexp(axis[1], -e), std::ldexp(axis[2], -e)};
    const double len = std::sqrt(dot3(c, c)) * (1 + 1e-12);
    const double *r = wa;
    double lo[2] = {INFINITY, INFINITY}, hi[2] = {-INFINITY, -INFINITY};
    for (int side = 0; side < 2; ++side) {
        const double *w = side ? wb : wa;
        const uint32_t n = side ? nb : na;
        for (uint32_t v = 0; v < n; ++v) {
            const double *x = &w[3 * size_t(v)];
            const double dx = x[0] - r[0], dy = x[1] - r[1], dz = x[2] - r[2];
            const double p = (c[0] * dx + c[1] * dy) + c[2] * dz;
            const double err =
                ((std::fabs(c[0] * dx) + std::fabs(c[1] * dy)) + std::fabs(c[2] * dz)) * 0x1p-48 + 0x1p-700;
            lo[side] = std::min(lo[side], p - err);
            hi[side] = std::max(hi[side], p + err);
        }
    }
    const double need = d * len * (1 + 1e-12);
    return (lo[1] - hi[0]) * (1 - 1e-12) > need || (lo[0] - hi[1]) * (1 - 1e-12) > need;
}

namespace {

// The simplex's distinct vertices of one side (which: 0 for A, 1 for B).
int simplex_side(const Simplex &s, int which, const double *w, const double **out) {
    int n = 0;
    uint16_t seen[4];
    for (int k = 0; k < s.n; ++k) {
        const uint16_t i = which ? s.ib[k] : s.ia[k];
        bool dup = false;
        for (int j = 0; j < n; ++j) dup |= seen[j] == i;
        if (dup) continue;
        seen[n] = i;
        out[n++] = &w[3 * size_t(i)];
    }
    return n;
}

}  // namespace

namespace tet {

namespace {

// The separating axis along the line of centres with a gap of d, before any
// world vertex: tet_axis_separates's projections (any order of evaluation
// stays within tet_axis_margin, which bounds how far the computed gap
// uu - (h_a + h_b) is from the exact gap between the projections of the
// world vertices on u, times |u|). The hulls are more than d apart when
// that exact gap exceeds d |u|: with |u| <= sqrt(uu) (1 + 2^-51), a rounded
// product and sum, the factors 1 + 1e-12 cover it. Returns 2 when apart by
// more than d, 1 when apart (not touching) but not shown more than d, 0
// when not shown apart.
int centres_apart(const BodyPose &a, const BodyPose &b, const Rotation &ra, const Rotation &rb, double d) {
    const double *ca = a.position, *cb = b.position;
    const double u[3] = {cb[0] - ca[0], cb[1] - ca[1], cb[2] - ca[2]};
    double h[2];
    for (int side = 0; side < 2; ++side) {
        const BodyPose &p = side ? b : a;
        const Rotation &r = side ? rb : ra;
        const double sign = side ? -1 : 1, s = p.scale, *l = p.mesh->tetra_local;
        double dir[3];
        for (int j = 0; j < 3; ++j) dir[j] = sign * ((r.m[j] * u[0] + r.m[3 + j] * u[1]) + r.m[6 + j] * u[2]);
        double best = -INFINITY;
        for (int v = 0; v < 4; ++v)
            best = std::max(best, ((s * l[v]) * dir[0] + (s * l[4 + v]) * dir[1]) + (s * l[8 + v]) * dir[2]);
        h[side] = best;
    }
    const double uu = (u[0] * u[0] + u[1] * u[1]) + u[2] * u[2];
    const double gap = uu - (h[0] + h[1]);
    if (!(gap > 0)) return 0;
    const double margin = tet_axis_margin(a, b, u, uu);
    if (!(gap > margin)) return 0;
    const double need = d * (std::sqrt(uu) * (1 + 1e-12)) * (1 + 1e-12);
    return gap > (margin + need) * (1 + 1e-12) ? 2 : 1;
}

// World vertices of a tetrahedron of rotation r (world_vertices'
// operations: the same bits), 3 doubles each, and their box.
void tet_world_rows(const BodyPose &p, const Rotation &r, double *w, double *box) {
    const double *l = p.mesh->tetra_local;
    for (int v = 0; v < 4; ++v) {
        const double m[3] = {l[v], l[4 + v], l[8 + v]};
        transform_point(r, p.position, p.scale, m, &w[3 * v]);
    }
    for (int k = 0; k < 3; ++k) {
        box[k] = std::min(std::min(w[k], w[3 + k]), std::min(w[6 + k], w[9 + k]));
        box[3 + k] = std::max(std::max(w[k], w[3 + k]), std::max(w[6 + k], w[9 + k]));
    }
}

// The certificates on the world vertices; true when they decide, with the
// answer in *near.
bool tetra_certify(const BodyPose &a, const double *wa, const BodyPose &b, const double *wb, double d,
                   bool *near) {
    // The face planes with a gap first: cheaper than GJK, and most pairs
    // apart are apart across a face.
    if (face_apart(*a.mesh, wa, *b.mesh, wb, d) || face_apart(*b.mesh, wb, *a.mesh, wa, d)) {
        *near = false;
        return true;
    }
    Simplex s;
    double v[3];
    const Gjk g = gjk(wa, 4, wb, 4, d, s, v);
    if (g != Gjk::Near && axis_apart(v, wa, 4, wb, 4, d)) {
        *near = false;
        return true;
    }
    if (g != Gjk::Apart) {
        const double *fa[4], *fb[4];
        const int na = simplex_side(s, 0, wa, fa), nb = simplex_side(s, 1, wb, fb);
        if (na <= 3 && nb <= 3 && features_within(fa, na, fb, nb, d)) {
            *near = true;
            return true;
        }
    }
    return false;
}

}  // namespace

Contact tetra_within_apart(const BodyPose &a, const BodyPose &b, double d, NarrowScratch &s) {
    const Rotation ra = rotation_of(a.orientation), rb = rotation_of(b.orientation);
    if (centres_apart(a, b, ra, rb, d) == 2) return Contact::None;
    double wa[12], wb[12], box_a[6], box_b[6];
    tet_world_rows(a, ra, wa, box_a);
    tet_world_rows(b, rb, wb, box_b);
    if (boxes_apart(box_a, box_b, d)) return Contact::None;
    bool near;
    if (tetra_certify(a, wa, b, wb, d, &near)) return near ? Contact::Near : Contact::None;
    ++s.margin_fallbacks;
    return collide_within_direct(a, b, d, s, nullptr);
}

Contact collide_tetra_within(const BodyPose &a, const BodyPose &b, double d, NarrowScratch &s) {
    const Rotation ra = rotation_of(a.orientation), rb = rotation_of(b.orientation);
    const int apart = centres_apart(a, b, ra, rb, d);
    if (apart == 2) return Contact::None;
    if (apart == 0) {
        const Contact touching = collide_tetra(a, b, s);
        if (touching != Contact::None) return touching;
    }
    double wa[12], wb[12], box_a[6], box_b[6];
    tet_world_rows(a, ra, wa, box_a);
    tet_world_rows(b, rb, wb, box_b);
    if (boxes_apart(box_a, box_b, d)) return Contact::None;
    bool near;
    if (tetra_certify(a, wa, b, wb, d, &near)) return near ? Contact::Near : Contact::None;
    ++s.margin_fallbacks;
    return collide_within_direct(a, b, d, s, nullptr);
}

}  // namespace tet
}  // namespace hgcd
