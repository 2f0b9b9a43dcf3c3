// The convex path's search for crossing surfaces on world vertices
// (narrow/convex.hpp), for the pairs the kernel (convex_kernel.cpp) leaves
// open.
#include "common/ieee.hpp"
#include "narrow/convex.hpp"

#include <algorithm>
#include <cmath>

#include "narrow/boxes.hpp"
#include "narrow/tetra.hpp"

namespace hgcd {

namespace {

// A triangle's plane for certified signs of orient3d(a, b, c, x) =
// -(x - a) . n, n = (b - a) x (c - a) as rounded: the filter of
// exact/predicates.hpp's PlaneFilter (plane_sides3), whose argument covers
// this evaluation operation for operation: the sign of the computed value is
// orient3d's when |value| > 2^-50 perm + 2^-960, perm the permanent computed
// from the same rounded differences.
struct Plane {
    const double *a;
    double n[3], an[3];
};
inline void plane_of(const double *a, const double *b, const double *c, Plane &p) {
    p.a = a;
    const double e1x = b[0] - a[0], e1y = b[1] - a[1], e1z = b[2] - a[2];
    const double e2x = c[0] - a[0], e2y = c[1] - a[1], e2z = c[2] - a[2];
    const double m0 = e1y * e2z, m1 = e1z * e2y, m2 = e1z * e2x, m3 = e1x * e2z, m4 = e1x * e2y, m5 = e1y * e2x;
    p.n[0] = m0 - m1;
    p.n[1] = m2 - m3;
    p.n[2] = m4 - m5;
    p.an[0] = std::fabs(m0) + std::fabs(m1);
    p.an[1] = std::fabs(m2) + std::fabs(m3);
    p.an[2] = std::fabs(m4) + std::fabs(m5);
}
// The sign of orient3d(a, b, c, x) when certain, else 0.
inline int plane_side(const Plane &p, const double *x) {
    const double dx = x[0] - p.a[0], dy = x[1] - p.a[1], dz = x[2] - p.a[2];
    const double det = -((dx * p.n[0] + dy * p.n[1]) + dz * p.n[2]);
    const double perm = (std::fabs(dx) * p.an[0] + std::fabs(dy) * p.an[1]) + std::fabs(dz) * p.an[2];
    const double bound = 0x1p-50 * perm + 0x1p-960;
    return (det > bound) - (-det > bound);
}

// With p and q strictly on either side of the plane of triangle t: does
// the segment pq certainly cross t's interior? It does when orient3d(p, q,
// t0, t1), orient3d(p, q, t1, t2) and orient3d(p, q, t2, t0) have one
// strict sign (the line pq passes inside all three edges).
inline bool crosses_inside(const double *p, const double *q, const double *const *t) {
    int s[3];
    for (int k = 0; k < 3; ++k) {
        Plane pl;
        plane_of(p, q, t[k], pl);
        s[k] = plane_side(pl, t[(k + 1) % 3]);
    }
    return s[0] != 0 && s[0] == s[1] && s[1] == s[2];
}

inline uint32_t nearest_vertex(const double *w, uint32_t n, const double *c) {
    uint32_t best = 0;
    double d2 = INFINITY;
    for (uint32_t i = 0; i < n; ++i, w += 3) {
        const double dx = w[0] - c[0], dy = w[1] - c[1], dz = w[2] - c[2];
        const double d = (dx * dx + dy * dy) + dz * dz;
        if (d < d2) {
            d2 = d;
            best = i;
        }
    }
    return best;
}

// Meshes of at most SatData::kAllTriangles triangles have all of them tried
// against each edge; larger ones those at the vertex nearest the edge's
// start (at most this many).
constexpr uint32_t kMaxTried = 32;

// An edge of mesh me (world vertices we) that certainly crosses the
// interior of a triangle of mt (world vertices wt), tried on the edges at
// me's vertex nearest ct (mt's position).
bool edge_crosses(const Mesh &me, const double *we, const Mesh &mt, const double *wt, const double *ct) {
    const uint32_t v = nearest_vertex(we, me.vertex_count, ct);
    const double *p = &we[3 * size_t(v)];
    uint32_t tris[kMaxTried];
    uint32_t count = 0;
    if (mt.triangle_count <= SatData::kAllTriangles) {
        for (uint32_t t = 0; t < mt.triangle_count; ++t) tris[count++] = t;
    } else {
        const uint32_t u = nearest_vertex(wt, mt.vertex_count, p);
        const SatData &st = *mt.sat;
        for (uint32_t k = st.vertex_tri_start()[u]; k < st.vertex_tri_start()[u + 1] && count < kMaxTried; ++k)
            tris[count++] = st.vertex_tris()[k];
    }
    // The box of the edges at p: an edge crosses only triangles its box
    // meets, and the planes are prepared only for the triangles that meet
    // this one and have p certainly on one side.
    const SatData &se = *me.sat;
    double reach[6] = {p[0], p[1], p[2], p[0], p[1], p[2]};
    for (uint32_t e = se.vertex_edge_start()[v]; e < se.vertex_edge_start()[v + 1]; ++e) {
        const double *q = &we[3 * size_t(se.vertex_edges()[e])];
        for (int i = 0; i < 3; ++i) {
            reach[i] = std::min(reach[i], q[i]);
            reach[3 + i] = std::max(reach[3 + i], q[i]);
        }
    }
    Plane plane[kMaxTried];
    int side_p[kMaxTried];
    double box[kMaxTried][6];
    const double *corner[kMaxTried][3];
    uint32_t kept = 0;
    for (uint32_t k = 0; k < count; ++k) {
        const uint32_t *f = &mt.triangles[3 * size_t(tris[k])];
        triangle_box(wt, f, box[kept]);
        if (boxes_disjoint(box[kept], reach)) continue;
        for (int i = 0; i < 3; ++i) corner[kept][i] = &wt[3 * size_t(f[i])];
        plane_of(corner[kept][0], corner[kept][1], corner[kept][2], plane[kept]);
        side_p[kept] = plane_side(plane[kept], p);
        kept += side_p[kept] != 0;
    }
    for (uint32_t e = se.vertex_edge_start()[v]; e < se.vertex_edge_start()[v + 1]; ++e) {
        const double *q = &we[3 * size_t(se.vertex_edges()[e])];
        const double edge_box[6] = {std::min(p[0], q[0]), std::min(p[1], q[1]), std::min(p[2], q[2]),
                                    std::max(p[0], q[0]), std::max(p[1], q[1]), std::max(p[2], q[2])};
        for (uint32_t k = 0; k < kept; ++k)
            if (!boxes_disjoint(edge_box, box[k]) && plane_side(plane[k], q) == -side_p[k] &&
                crosses_inside(p, q, corner[k]))
                return true;
    }
    return false;
}

// At most this many triangles of a mesh are tried by any_edge_crosses (the
// first that reach the region).
constexpr uint32_t kMaxNear = 64;

// Any edge of mesh me (world vertices we) that reaches the box `region`
// certainly crossing the interior of a triangle of mt (world vertices wt)
// that reaches it too? The same certificate as edge_crosses, on every edge
// (each once) against at most kMaxNear triangles: false proves nothing. A
// crossing point lies in both bodies' boxes: region is their intersection.
bool any_edge_crosses(const Mesh &me, const double *we, const Mesh &mt, const double *wt, const double *region) {
    Plane plane[kMaxNear];
    double box[kMaxNear][6];
    const double *corner[kMaxNear][3];
    uint32_t kept = 0;
    for (uint32_t t = 0; t < mt.triangle_count && kept < kMaxNear; ++t) {
        const uint32_t *f = &mt.triangles[3 * size_t(t)];
        triangle_box(wt, f, box[kept]);
        if (boxes_disjoint(box[kept], region)) continue;
        for (int i = 0; i < 3; ++i) corner[kept][i] = &wt[3 * size_t(f[i])];
        plane_of(corner[kept][0], corner[kept][1], corner[kept][2], plane[kept]);
        ++kept;
    }
    if (!kept) return false;
    const SatData &se = *me.sat;
    for (uint32_t v = 0; v < me.vertex_count; ++v) {
        const double *p = &we[3 * size_t(v)];
        for (uint32_t e = se.vertex_edge_start()[v]; e < se.vertex_edge_start()[v + 1]; ++e) {
            const uint32_t w = se.vertex_edges()[e];
            if (w < v) continue;  // (each edge once)
            const double *q = &we[3 * size_t(w)];
            const double edge_box[6] = {std::min(p[0], q[0]), std::min(p[1], q[1]), std::min(p[2], q[2]),
                                        std::max(p[0], q[0]), std::max(p[1], q[1]), std::max(p[2], q[2])};
            if (boxes_disjoint(edge_box, region)) continue;
            for (uint32_t k = 0; k < kept; ++k) {
                if (boxes_disjoint(edge_box, box[k])) continue;
                const int side_p = plane_side(plane[k], p);
                if (side_p != 0 && plane_side(plane[k], q) == -side_p && crosses_inside(p, q, corner[k]))
                    return true;
            }
        }
    }
    return false;
}

}  // namespace

bool convex_surfaces_cross(const BodyPose &a, const double *wa, const double *box_a, const BodyPose &b,
                           const double *wb, const double *box_b) {
    const Mesh &ma = *a.mesh, &mb = *b.mesh;
    const double region[6] = {std::max(box_a[0], box_b[0]), std::max(box_a[1], box_b[1]),
                              std::max(box_a[2], box_b[2]), std::min(box_a[3], box_b[3]),
                              std::min(box_a[4], box_b[4]), std::min(box_a[5], box_b[5])};
    // Boxes that meet in a flat region (faces resting on each other at one
    // coordinate) leave no crossing to find: just past the point where an
    // edge of b certainly crosses a triangle of a, the edge is inside a's
    // solid, so in both solids, so in the region; a line with two points in
    // the flat plane lies in it, but a's interior points near a face
    // interior point lie strictly on one side of the box's face there.
    for (int k = 0; k < 3; ++k)
        if (!(region[3 + k] > region[k])) return false;
    if (edge_crosses(mb, wb, ma, wa, a.position) || edge_crosses(ma, wa, mb, wb, b.position)) return true;
    // Then every edge in the region where the boxes meet.
    return any_edge_crosses(mb, wb, ma, wa, region) || any_edge_crosses(ma, wa, mb, wb, region);
}

}  // namespace hgcd
