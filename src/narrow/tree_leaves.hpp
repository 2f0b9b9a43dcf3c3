// The tree path's leaves (tree_path.cpp): a leaf's triangle range, the exact
// test of two leaves' triangles, and the plane test that stops a descent
// against a leaf whose triangles' planes all have the other node on one side.
#pragma once
#include <algorithm>
#include <cmath>
#include <cstdint>

#include "exact/geometry.hpp"
#include "narrow/boxes.hpp"
#include "narrow/bvh.hpp"
#include "narrow/narrow.hpp"

namespace hgcd {

inline void leaf_range(const BodyView &v, uint32_t n, uint32_t &first, uint32_t &count) {
    if (v.nodes) {
        first = v.nodes[n].first;
        count = v.nodes[n].count;
    } else {
        first = 0;
        count = v.mesh->triangle_count;
    }
}

inline void prepare_view_triangle(BodyView &v, uint32_t t, PreparedTriangle &out) {
    const uint32_t *f = &v.tris[3 * size_t(t)];
    prepare_triangle(out, v.vertex(f[0]), v.vertex(f[1]), v.vertex(f[2]));
}

// Exact test of the triangles of leaf i of a against those of leaf j of b.
// On a meeting pair, sets meet[0], meet[1] to their leaf-order indices.
// With kMargin: a triangle pair within d (boxes grown by d). Each side's
// triangles are tried against the box of the other's that can meet them
// (exact, and inside the leaf's node box: no world box of a node is asked
// for). The first meeting pair in a's order, then b's, is the one found.
template <bool kMargin>
bool leaves_meet(BodyView &a, uint32_t i, BodyView &b, uint32_t j, NarrowScratch &s, uint32_t *meet, double d) {
    uint32_t fa, na, fb, nb;
    leaf_range(a, i, fa, na);
    leaf_range(b, j, fb, nb);
    if (s.leaf_a.size() < na) s.leaf_a.resize(na);
    if (s.leaf_near.size() < nb) {
        s.leaf_near.resize(nb);
        s.leaf_near_tri.resize(nb);
    }
    auto grow = [](double *box, const double *t) {
        for (int k = 0; k < 3; ++k) {
            box[k] = std::min(box[k], t[k]);
            box[3 + k] = std::max(box[3 + k], t[3 + k]);
        }
    };
    PreparedTriangle *const tri_a = s.leaf_a.data();
    double box_a[6] = {INFINITY, INFINITY, INFINITY, -INFINITY, -INFINITY, -INFINITY};
    for (uint32_t t = 0; t < na; ++t) {
        prepare_view_triangle(a, fa + t, tri_a[t]);
        grow(box_a, tri_a[t].box);
    }
    // Triangles of b that reach a's, prepared (`near` of them), and their box.
    PreparedTriangle *const near_b = s.leaf_near.data();
    uint32_t *const near_tri = s.leaf_near_tri.data();
    double box_b[6] = {INFINITY, INFINITY, INFINITY, -INFINITY, -INFINITY, -INFINITY};
    size_t near = 0;
    for (uint32_t t = fb; t < fb + nb; ++t) {
        prepare_view_triangle(b, t, near_b[near]);
        if (kMargin ? boxes_apart(near_b[near].box, box_a, d) : boxes_disjoint(near_b[near].box, box_a)) continue;
        grow(box_b, near_b[near].box);
        near_tri[near++] = t;
    }
    if (near == 0) return false;
    for (uint32_t t = 0; t < na; ++t) {
        PreparedTriangle &p = tri_a[t];
        if (kMargin ? boxes_apart(p.box, box_b, d) : boxes_disjoint(p.box, box_b)) continue;
        for (size_t k = 0; k < near; ++k) {
            PreparedTriangle &q = near_b[k];
            if (kMargin ? boxes_apart(p.box, q.box, d) : boxes_disjoint(p.box, q.box)) continue;
            ++s.triangle_tests;
            if (kMargin ? tri_tri_within(p.v[0], p.v[1], p.v[2], q.v[0], q.v[1], q.v[2], d)
                        : tri_tri_intersect(p, q)) {
                meet[0] = fa + t;
                meet[1] = near_tri[k];
                return true;
            }
        }
    }
    return false;
}

// Is the box `other` (which holds every rounded world vertex under a node of
// the other body) strictly on one side of the plane of each triangle of leaf
// n of v? Then no triangle under that node meets the leaf. The axis is the
// computed normal (any vector is a valid axis); a triangle projects within
// its vertices' projections, each computed within g_3 sum_k |n_k v_k| of
// exact, the box within its corners' extremes sum_k max(n_k lo_k, n_k hi_k)
// (and min), computed within g_4 sum_k |n_k| max(|lo_k|, |hi_k|): margins of
// 2e-15 times those sums (+ 1e-300 for underflow) cover them and the
// rounding of the margins and comparisons. A zero normal proves nothing.
inline bool leaf_planes_apart(BodyView &v, uint32_t n, const double *other) {
    uint32_t first, count;
    leaf_range(v, n, first, count);
    for (uint32_t t = first; t < first + count; ++t) {
        const uint32_t *f = &v.tris[3 * size_t(t)];
        const double *p0 = v.vertex(f[0]), *p1 = v.vertex(f[1]), *p2 = v.vertex(f[2]);
        const double u[3] = {p1[0] - p0[0], p1[1] - p0[1], p1[2] - p0[2]};
        const double w[3] = {p2[0] - p0[0], p2[1] - p0[1], p2[2] - p0[2]};
        const double nx = u[1] * w[2] - u[2] * w[1], ny = u[2] * w[0] - u[0] * w[2], nz = u[0] * w[1] - u[1] * w[0];
        const double ax = std::fabs(nx), ay = std::fabs(ny), az = std::fabs(nz);
        double tmin = INFINITY, tmax = -INFINITY, tmag = 0;
        for (const double *p : {p0, p1, p2}) {
            const double d = (nx * p[0] + ny * p[1]) + nz * p[2];
            tmin = std::min(tmin, d);
            tmax = std::max(tmax, d);
            tmag = std::max(tmag, (ax * std::fabs(p[0]) + ay * std::fabs(p[1])) + az * std::fabs(p[2]));
        }
        const double bmax = (std::max(nx * other[0], nx * other[3]) + std::max(ny * other[1], ny * other[4])) +
                            std::max(nz * other[2], nz * other[5]);
        const double bmin = (std::min(nx * other[0], nx * other[3]) + std::min(ny * other[1], ny * other[4])) +
                            std::min(nz * other[2], nz * other[5]);
        const double bmag = (ax * std::max(std::fabs(other[0]), std::fabs(other[3])) +
                             ay * std::max(std::fabs(other[1]), std::fabs(other[4]))) +
                            az * std::max(std::fabs(other[2]), std::fabs(other[5]));
        const double slack = 2e-15 * (tmag + bmag) + 1e-300;
        if (!(bmin - slack > tmax || bmax + slack < tmin)) return false;
    }
    return true;
}

// A leaf of at most this many triangles is tried against the planes of its
// triangles (leaf_planes_apart) before the other node is descended: a body
// deep inside a large mesh, or near its flat faces, stops there.
constexpr uint32_t kPlaneLeaf = 16;

// The leaf of a node pair one of whose nodes is a leaf: is the other node
// (world box `other`) strictly off the planes of the leaf's triangles?
inline bool plane_cut(BodyView &lv, uint32_t ln, const double *other) {
    uint32_t first, count;
    leaf_range(lv, ln, first, count);
    return count <= kPlaneLeaf && leaf_planes_apart(lv, ln, other);
}

}  // namespace hgcd
