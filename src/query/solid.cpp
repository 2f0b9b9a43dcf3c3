// The exact per-body tests of the scene queries (solid.hpp).
#include "common/ieee.hpp"
#include "query/solid.hpp"

#include <algorithm>

#include "exact/predicates.hpp"
#include "narrow/bvh.hpp"

namespace hgcd {

namespace {

// (| not ||: six compares and no branch each, which mispredicted.)
bool outside(const double *p, const double *lo, const double *hi) {
    return (p[0] < lo[0]) | (p[1] < lo[1]) | (p[2] < lo[2]) | (p[0] > hi[0]) | (p[1] > hi[1]) | (p[2] > hi[2]);
}

bool boxes_apart(const double *alo, const double *ahi, const double *blo, const double *bhi) {
    return (alo[0] > bhi[0]) | (alo[1] > bhi[1]) | (alo[2] > bhi[2]) | (blo[0] > ahi[0]) | (blo[1] > ahi[1]) |
           (blo[2] > ahi[2]);
}

// Calls visit(id, v) on the triangles (mesh index id, world vertices v[3])
// until one returns true, and returns whether one did: every triangle of a
// mesh without a tree, in index order; with a tree, the triangles of the
// leaves reached through nodes whose box near(box) accepts (near must accept
// every box that holds a triangle visit could return true for: node boxes
// hold their triangles' world vertices, bvh.hpp).
template <class Near, class Visit>
bool any_triangle(const SolidView &b, Near &&near, Visit &&visit) {
    if (!b.tree) {
        const uint32_t *tri = b.mesh->triangles.data();
        for (uint32_t t = 0; t < b.mesh->triangle_count; ++t) {
            const double *v[3] = {b.w + 3 * size_t(tri[3 * t]), b.w + 3 * size_t(tri[3 * t + 1]),
                                  b.w + 3 * size_t(tri[3 * t + 2])};
            if (visit(t, v)) return true;
        }
        return false;
    }
    BodyView &view = *b.tree;
    uint32_t stack[2 * 80 + 2];  // (depth below 80, bvh.hpp; one sibling waits per level)
    int top = 0;
    stack[top++] = 0;
    while (top > 0) {
        const uint32_t n = stack[--top];
        if (!near(view.box(n))) continue;
        const BvhNode &node = view.nodes[n];
        if (node.count == 0) {
            stack[top++] = node.first + 1;
            stack[top++] = node.first;
            continue;
        }
        for (uint32_t i = node.first; i < node.first + node.count; ++i) {
            const uint32_t *t = &view.tris[3 * size_t(i)];
            const double *v[3] = {view.vertex(t[0]), view.vertex(t[1]), view.vertex(t[2])};
            if (visit(view.tri_ids[i], v)) return true;
        }
    }
    return false;
}

void triangle_box(const double *const *v, double *lo, double *hi) {
    for (int k = 0; k < 3; ++k) {
        lo[k] = std::min(v[0][k], std::min(v[1][k], v[2][k]));
        hi[k] = std::max(v[0][k], std::max(v[1][k], v[2][k]));
    }
}

bool on_surface(const SolidView &b, const double *p) {
    return any_triangle(
        b, [&](const double *box) { return !outside(p, box, box + 3); },
        [&](uint32_t, const double *const *v) {
            double lo[3], hi[3];
            triangle_box(v, lo, hi);
            return !outside(p, lo, hi) && segment_triangle_intersect(p, p, v[0], v[1], v[2]);
        });
}

// Parity of a point not on the surface of a closed mesh.
bool inside_closed(const SolidView &b, const double *p) {
    if (b.tree) return point_in_closed_mesh_bvh(p, *b.tree, b.scratch->node_stack);
    return point_in_closed_mesh(p, b.w, b.mesh->triangles.data(), b.mesh->triangle_count, b.box, b.box + 3);
}

// A tetrahedron's closed solid is the hull of its 4 world vertices: p is in
// it when, for every face, p is on the face's plane or on the side of the
// fourth vertex. Returns -1 when the 4 points are coplanar (flat: the
// caller takes the general test).
int point_in_tetra(const SolidView &b, const double *p) {
    const uint32_t *tri = b.mesh->triangles.data();
    bool inside = true;
    for (uint32_t f = 0; f < 4; ++f) {
        // The fourth vertex: the one of the next face that is not in this one.
        const uint32_t *face = tri + 3 * f, *next = tri + 3 * ((f + 1) % 4);
        uint32_t opp = next[0];
        for (int i = 0; i < 3; ++i)
            if (next[i] != face[0] && next[i] != face[1] && next[i] != face[2]) opp = next[i];
        const double *v0 = b.w + 3 * size_t(face[0]), *v1 = b.w + 3 * size_t(face[1]), *v2 = b.w + 3 * size_t(face[2]);
        const int so = orient3d(v0, v1, v2, b.w + 3 * size_t(opp));
        if (so == 0) return -1;
        const int sp = orient3d(v0, v1, v2, p);
        if (sp == -so) inside = false;  // (keep checking flatness)
    }
    return inside ? 1 : 0;
}

// Every corner c[i] strictly on one side of the plane of (v0, v1, v2) (a
// zero-area triangle has no side: false).
bool corners_on_one_side(const double *v0, const double *v1, const double *v2, const double (*c)[3]) {
    predicates::PlaneFilter pf;
    predicates::plane_prepare(pf, v0, v1, v2);
    const int s = predicates::plane_side(pf, c[0]);
    if (s == 0) return false;
    for (int i = 1; i < 8; ++i)
        if (predicates::plane_side(pf, c[i]) != s) return false;
    return true;
}

// The last axes of the separating-axis test of a triangle and a box (the
// box's face normals and the triangle's normal tried already): a box axis
// crossed with a triangle edge. Along axis k x (b - a), a and b project
// alike, so the axis separates when, in the projection that drops axis k,
// the line through a and b has the box's four corners strictly on one side
// and the third vertex not on it: signs of exact orient2d. Two disjoint
// convex polytopes have a strictly separating plane parallel to a face of
// their Minkowski difference: a face of either, or spanned by an edge of
// each; edges parallel to axis k span none (their projection is a point,
// every sign 0, and no separation is claimed).
bool edge_axis_separates(const double *const *v, const double *lo, const double *hi) {
    for (int k = 0; k < 3; ++k) {
        const int i = k == 2 ? 0 : k + 1, j = k == 0 ? 2 : k - 1;  // (as orient2d_proj)
        const double cx[4] = {lo[i], hi[i], lo[i], hi[i]}, cy[4] = {lo[j], lo[j], hi[j], hi[j]};
        for (int e = 0; e < 3; ++e) {
            const double *a = v[e], *b = v[(e + 1) % 3], *third = v[(e + 2) % 3];
            const int s = predicates::orient2d_filtered(a[i], a[j], b[i], b[j], cx[0], cy[0]);
            if (s == 0) continue;
            bool apart = true;
            for (int q = 1; q < 4 && apart; ++q) apart = predicates::orient2d_filtered(a[i], a[j], b[i], b[j], cx[q], cy[q]) == s;
            if (apart && predicates::orient2d_proj(k, a, b, third) != s) return true;
        }
    }
    return false;
}

// A tetrahedron's solid (the hull of its 4 vertices) against the box, by
// the separating-axis test of two convex solids (see edge_axis_separates):
// the box's axes, the 4 face planes (every corner strictly on the side away
// from the fourth vertex), and each of the 6 edges crossed with each box
// axis (the other two vertices not strictly on the corners' side). All
// signs exact. 1: they meet; 0: apart; -1: the tetrahedron is flat (no
// inside to be away from; the caller decides).
int tetra_meets_box(const SolidView &b, const double *lo, const double *hi, const double (*c)[3]) {
    const uint32_t *tri = b.mesh->triangles.data();
    uint32_t id[4] = {tri[0], tri[1], tri[2], tri[3]};
    for (int i = 3; i < 6; ++i)
        if (tri[i] != id[0] && tri[i] != id[1] && tri[i] != id[2]) id[3] = tri[i];
    const double *v[4];
    bool vertex_in = false;  // (then they meet; comparisons only, no branch each)
    for (int i = 0; i < 4; ++i) {
        v[i] = b.w + 3 * size_t(id[i]);
        vertex_in |= !outside(v[i], lo, hi);
    }
    if (vertex_in) return 1;
    for (int k = 0; k < 3; ++k) {
        const double vlo = std::min(std::min(v[0][k], v[1][k]), std::min(v[2][k], v[3][k]));
        const double vhi = std::max(std::max(v[0][k], v[1][k]), std::max(v[2][k], v[3][k]));
        if (vlo > hi[k] || vhi < lo[k]) return 0;
    }
    // Every corner against every face: a face with all away separates; a
    // corner on no face's far side lies in the closed solid (they meet).
    bool corner_in[8] = {true, true, true, true, true, true, true, true};
    for (int f = 0; f < 4; ++f) {
        predicates::PlaneFilter pf;
        predicates::plane_prepare(pf, v[(f + 1) % 4], v[(f + 2) % 4], v[(f + 3) % 4]);
        const int so = predicates::plane_side(pf, v[f]);
        if (so == 0) return -1;
        bool away = true;
        for (int i = 0; i < 8; ++i) {
            const int side = predicates::plane_side(pf, c[i]);
            away &= side == -so;
            corner_in[i] &= side != -so;
        }
        if (away) return 0;
    }
    bool some_in = false;
    for (bool in : corner_in) some_in |= in;
    if (some_in) return 1;
    static const int kEdge[6][4] = {{0, 1, 2, 3}, {0, 2, 1, 3}, {0, 3, 1, 2}, {1, 2, 0, 3}, {1, 3, 0, 2}, {2, 3, 0, 1}};
    for (int k = 0; k < 3; ++k) {
        const int i = k == 2 ? 0 : k + 1, j = k == 0 ? 2 : k - 1;  // (as orient2d_proj)
        const double cx[4] = {lo[i], hi[i], lo[i], hi[i]}, cy[4] = {lo[j], lo[j], hi[j], hi[j]};
        for (const auto &e : kEdge) {
            const double *p = v[e[0]], *q = v[e[1]];
            const int s = predicates::orient2d_filtered(p[i], p[j], q[i], q[j], cx[0], cy[0]);
            if (s == 0) continue;
            bool apart = true;
            for (int r = 1; r < 4 && apart; ++r) apart = predicates::orient2d_filtered(p[i], p[j], q[i], q[j], cx[r], cy[r]) == s;
            if (apart && predicates::orient2d_proj(k, p, q, v[e[2]]) != s && predicates::orient2d_proj(k, p, q, v[e[3]]) != s)
                return 0;
        }
    }
    return 1;
}

}  // namespace

bool point_in_solid(const SolidView &b, const double *p) {
    if (outside(p, b.box, b.box + 3)) return false;
    if (b.mesh->tetra) {
        const int r = point_in_tetra(b, p);
        if (r >= 0) return r == 1;
    }
    if (on_surface(b, p)) return true;
    if (!b.mesh->closed) return false;
    // Not on the surface: parity decides (its precondition).
    return inside_closed(b, p);
}

bool box_meets_solid(const SolidView &b, const double *lo, const double *hi) {
    if (boxes_apart(b.box, b.box + 3, lo, hi)) return false;
    // The body's vertices inside the box: its solid meets it (a mesh has a
    // triangle, whose vertices are then in the box).
    if (!outside(b.box, lo, hi) && !outside(b.box + 3, lo, hi)) return true;
    // The box's corners (the same point twice where the box is flat).
    double c[8][3];
    for (int i = 0; i < 8; ++i)
        for (int k = 0; k < 3; ++k) c[i][k] = (i >> k) & 1 ? hi[k] : lo[k];
    if (b.mesh->tetra) {
        const int r = tetra_meets_box(b, lo, hi, c);
        if (r >= 0) return r == 1;
    }
    // A triangle's vertex in the box: they meet (comparisons only, before
    // any sign is taken).
    if (!b.tree) {
        const uint32_t *tri = b.mesh->triangles.data();
        for (size_t i = 0; i < 3 * size_t(b.mesh->triangle_count); ++i)
            if (!outside(b.w + 3 * size_t(tri[i]), lo, hi)) return true;
    }
    const bool meets = any_triangle(
        b, [&](const double *box) { return !boxes_apart(box, box + 3, lo, hi); },
        [&](uint32_t, const double *const *v) {
            double tlo[3], thi[3];
            triangle_box(v, tlo, thi);
            if (boxes_apart(tlo, thi, lo, hi)) return false;
            // A vertex in the box: they meet. Else the separating-axis test
            // of the triangle and the (solid) box: the box's axes failed
            // above; the triangle's normal (every corner strictly on one
            // side of its plane), then the edge axes.
            if (!outside(v[0], lo, hi) || !outside(v[1], lo, hi) || !outside(v[2], lo, hi)) return true;
            if (corners_on_one_side(v[0], v[1], v[2], c)) return false;
            return !edge_axis_separates(v, lo, hi);
        });
    if (meets) return true;
    // No triangle meets the box: it lies wholly inside or outside a closed
    // solid, and its corner (not on the surface) tells which.
    if (!b.mesh->closed) return false;
    if (outside(lo, b.box, b.box + 3)) return false;
    return inside_closed(b, lo);
}

uint32_t first_crossing(const SolidView &b, const double *o, const double *e, const double *smin,
                        const double *smax, bool any, RayCrossing *out, double *hv) {
    uint32_t best = UINT32_MAX;
    const double *bv[3] = {nullptr, nullptr, nullptr};
    const double d[3] = {e[0] - o[0], e[1] - o[1], e[2] - o[2]};
    any_triangle(
        b, [&](const double *box) { return !segment_misses_box(o, e, smin, smax, d, box); },
        [&](uint32_t t, const double *const *v) {
            double tlo[3], thi[3];
            triangle_box(v, tlo, thi);
            if (boxes_apart(tlo, thi, smin, smax)) return false;
            RayCrossing c;
            if (!segment_crosses(o, e, v, &c)) return false;
            if (best != UINT32_MAX) {
                const int s = compare_crossings(o, e, v, c, bv, *out);
                if (s > 0 || (s == 0 && t > best)) return false;
            }
            best = t;
            *out = c;
            for (int i = 0; i < 3; ++i) bv[i] = v[i];
            return any;
        });
    if (best != UINT32_MAX)
        for (int i = 0; i < 3; ++i)
            for (int k = 0; k < 3; ++k) hv[3 * i + k] = bv[i][k];
    return best;
}

}  // namespace hgcd
