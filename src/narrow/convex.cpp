// The convex path's filters (narrow/convex.hpp): separating axes for pairs of
// small convex meshes, each certified against the rounding of its own
// evaluation, so that a pair is rejected only when its solids cannot share a
// point.
#include "common/ieee.hpp"
#include "narrow/convex.hpp"

#include <algorithm>
#include <cmath>

#include "narrow/boxes.hpp"
#include "narrow/tetra.hpp"

namespace hgcd {

namespace {

// The largest of l . d over the scaled local vertices l = fl(s v) of mesh m.
inline double local_support(const Mesh &m, double s, const double *d) {
    const double *v = m.vertices.data();
    double h = -INFINITY;
    for (uint32_t i = 0; i < m.vertex_count; ++i, v += 3) {
        const double lx = s * v[0], ly = s * v[1], lz = s * v[2];
        h = std::max(h, (lx * d[0] + ly * d[1]) + lz * d[2]);
    }
    return h;
}

}  // namespace

// The separating axis along the line of centres, before any world vertex:
// tet_axis_separates's test and argument (tetra.hpp), which hold for any
// number of vertices: the world vertices are fl(c + fl(R l)) with l = fl(s v)
// here too (transform_point), and reach bounds |v|_1 of every vertex.
bool convex_centres_apart(const BodyPose &a, const BodyPose &b, const Rotation &ra, const Rotation &rb, bool *deep) {
    const double *ca = a.position, *cb = b.position;
    const double u[3] = {cb[0] - ca[0], cb[1] - ca[1], cb[2] - ca[2]};
    double da[3], db[3];
    for (int j = 0; j < 3; ++j) {
        da[j] = (ra.m[j] * u[0] + ra.m[3 + j] * u[1]) + ra.m[6 + j] * u[2];
        db[j] = -1.0 * ((rb.m[j] * u[0] + rb.m[3 + j] * u[1]) + rb.m[6 + j] * u[2]);
    }
    const double uu = (u[0] * u[0] + u[1] * u[1]) + u[2] * u[2];
    const double reach_ab = local_support(*a.mesh, a.scale, da) + local_support(*b.mesh, b.scale, db);
    const double gap = uu - reach_ab;
    *deep = reach_ab > kDeep * uu;
    if (!(gap > 0)) return false;
    const double reach = 2 * (a.scale * a.mesh->sat->reach + b.scale * b.mesh->sat->reach);
    const double cu = ((std::fabs(ca[0]) + std::fabs(cb[0]) + reach) * std::fabs(u[0]) +
                       (std::fabs(ca[1]) + std::fabs(cb[1]) + reach) * std::fabs(u[1])) +
                      (std::fabs(ca[2]) + std::fabs(cb[2]) + reach) * std::fabs(u[2]);
    return gap > tet::kCentresMargin * (uu + cu) + tet::kUnderflowFloor;
}

namespace {

// The world vertices w (3 per vertex, n of them) projected on axis N from
// origin o: the smallest and largest.
inline void project(const double *w, uint32_t n, const double *o, const double *N, double &lo, double &hi) {
    lo = INFINITY;
    hi = -INFINITY;
    for (uint32_t i = 0; i < n; ++i, w += 3) {
        const double p = ((w[0] - o[0]) * N[0] + (w[1] - o[1]) * N[1]) + (w[2] - o[2]) * N[2];
        lo = std::min(lo, p);
        hi = std::max(hi, p);
    }
}

inline void rotate(const Rotation &r, const double *v, double *out) {
    out[0] = (r.m[0] * v[0] + r.m[1] * v[1]) + r.m[2] * v[2];
    out[1] = (r.m[3] * v[0] + r.m[4] * v[1]) + r.m[5] * v[2];
    out[2] = (r.m[6] * v[0] + r.m[7] * v[1]) + r.m[8] * v[2];
}

// The face axes of m worth trying first: those most nearly along d (the
// direction to the other body in m's frame), at most kFaceAxes of them.
constexpr int kFaceAxes = 6;
int pick_faces(const SatData &m, const double *d, uint32_t *out) {
    const uint32_t n = m.faces;
    if (n <= uint32_t(kFaceAxes)) {
        for (uint32_t k = 0; k < n; ++k) out[k] = k;
        return int(n);
    }
    double score[kFaceAxes];
    int count = 0;
    for (uint32_t k = 0; k < n; ++k) {
        const double *x = &m.axes[3 * k];
        const double s = std::fabs((x[0] * d[0] + x[1] * d[1]) + x[2] * d[2]);
        if (count == kFaceAxes && s <= score[count - 1]) continue;
        int at = count < kFaceAxes ? count++ : count - 1;
        for (; at > 0 && score[at - 1] < s; --at) {
            score[at] = score[at - 1];
            out[at] = out[at - 1];
        }
        score[at] = s;
        out[at] = k;
    }
    return count;
}

}  // namespace

// Any axis N proves two point sets' hulls disjoint when their projections
// on it are strictly apart, and each solid lies in the hull of its world
// vertices, so the axes need not be exact: only the projections' rounding
// is bounded, as for EdgeAxis (tetra.hpp). With the origin o the low corner
// of the box holding both bodies, 0 <= fl(x_k - o_k) <= e_k (the box's
// computed extent; rounding is monotone), so each projection is within
// 5 eps S of the exact (x - o) . N, S = e . |N|, and a computed gap above
// 2^-46 S + 2^-960 (128 eps S, and underflowed products) is a real one.
bool convex_axes_apart(const BodyPose &a, const double *wa, const double *box_a, const Rotation &ra,
                       const BodyPose &b, const double *wb, const double *box_b, const Rotation &rb) {
    const Mesh &ma = *a.mesh, &mb = *b.mesh;
    const SatData &sa = *ma.sat, &sb = *mb.sat;
    double o[3], e[3];
    for (int k = 0; k < 3; ++k) {
        o[k] = std::min(box_a[k], box_b[k]);
        e[k] = std::max(box_a[3 + k], box_b[3 + k]) - o[k];
    }
    auto apart_on = [&](const double *N) {
        double amin, amax, bmin, bmax;
        project(wa, ma.vertex_count, o, N, amin, amax);
        project(wb, mb.vertex_count, o, N, bmin, bmax);
        const double margin =
            tet::kEdgeMargin * ((e[0] * std::fabs(N[0]) + e[1] * std::fabs(N[1])) + e[2] * std::fabs(N[2])) +
            tet::kUnderflowFloor;
        return (bmin - amax > margin) | (amin - bmax > margin);
    };
    // The direction between the centres in each body's frame picks the face
    // axes to try.
    const double u[3] = {b.position[0] - a.position[0], b.position[1] - a.position[1], b.position[2] - a.position[2]};
    double da[3], db[3];
    for (int j = 0; j < 3; ++j) {
        da[j] = (ra.m[j] * u[0] + ra.m[3 + j] * u[1]) + ra.m[6 + j] * u[2];
        db[j] = (rb.m[j] * u[0] + rb.m[3 + j] * u[1]) + rb.m[6 + j] * u[2];
    }
    uint32_t fa[kFaceAxes], fb[kFaceAxes];
    const int na = pick_faces(sa, da, fa), nb = pick_faces(sb, db, fb);
    double N[3];
    for (int k = 0; k < std::max(na, nb); ++k) {
        if (k < na) {
            rotate(ra, &sa.axes[3 * fa[k]], N);
            if (apart_on(N)) return true;
        }
        if (k < nb) {
            rotate(rb, &sb.axes[3 * fb[k]], N);
            if (apart_on(N)) return true;
        }
    }
    // Edge against edge, when there are few such pairs.
    const uint64_t pairs = uint64_t(sa.edges) * sb.edges;
    if (pairs == 0 || pairs > kEdgeAxisPairs) return false;
    double ea[kEdgeAxisPairs][3];
    for (uint32_t i = 0; i < sa.edges; ++i) rotate(ra, &sa.axes[3 * (sa.faces + i)], ea[i]);
    for (uint32_t j = 0; j < sb.edges; ++j) {
        double eb[3];
        rotate(rb, &sb.axes[3 * (sb.faces + j)], eb);
        for (uint32_t i = 0; i < sa.edges; ++i) {
            const double *x = ea[i];
            N[0] = x[1] * eb[2] - x[2] * eb[1];
            N[1] = x[2] * eb[0] - x[0] * eb[2];
            N[2] = x[0] * eb[1] - x[1] * eb[0];
            if (apart_on(N)) return true;
        }
    }
    return false;
}

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

// Meshes of at most this many triangles have all of them tried against
// each edge; larger ones those at the vertex nearest the edge's start.
constexpr uint32_t kAllTriangles = 16;
constexpr uint32_t kMaxTried = 32;

// An edge of mesh me (world vertices we) that certainly crosses the
// interior of a triangle of mt (world vertices wt), tried on the edges at
// me's vertex nearest ct (mt's position).
bool edge_crosses(const Mesh &me, const double *we, const Mesh &mt, const double *wt, const double *ct) {
    const uint32_t v = nearest_vertex(we, me.vertex_count, ct);
    const double *p = &we[3 * size_t(v)];
    uint32_t tris[kMaxTried];
    uint32_t count = 0;
    if (mt.triangle_count <= kAllTriangles) {
        for (uint32_t t = 0; t < mt.triangle_count; ++t) tris[count++] = t;
    } else {
        const uint32_t u = nearest_vertex(wt, mt.vertex_count, p);
        const SatData &st = *mt.sat;
        for (uint32_t k = st.vertex_tri_start[u]; k < st.vertex_tri_start[u + 1] && count < kMaxTried; ++k)
            tris[count++] = st.vertex_tris[k];
    }
    // The box of the edges at p: an edge crosses only triangles its box
    // meets, and the planes are prepared only for the triangles that meet
    // this one and have p certainly on one side.
    const SatData &se = *me.sat;
    double reach[6] = {p[0], p[1], p[2], p[0], p[1], p[2]};
    for (uint32_t e = se.vertex_edge_start[v]; e < se.vertex_edge_start[v + 1]; ++e) {
        const double *q = &we[3 * size_t(se.vertex_edges[e])];
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
    for (uint32_t e = se.vertex_edge_start[v]; e < se.vertex_edge_start[v + 1]; ++e) {
        const double *q = &we[3 * size_t(se.vertex_edges[e])];
        const double edge_box[6] = {std::min(p[0], q[0]), std::min(p[1], q[1]), std::min(p[2], q[2]),
                                    std::max(p[0], q[0]), std::max(p[1], q[1]), std::max(p[2], q[2])};
        for (uint32_t k = 0; k < kept; ++k)
            if (!boxes_disjoint(edge_box, box[k]) && plane_side(plane[k], q) == -side_p[k] &&
                crosses_inside(p, q, corner[k]))
                return true;
    }
    return false;
}

}  // namespace

bool convex_surfaces_cross(const BodyPose &a, const double *wa, const BodyPose &b, const double *wb) {
    return edge_crosses(*b.mesh, wb, *a.mesh, wa, a.position) || edge_crosses(*a.mesh, wa, *b.mesh, wb, b.position);
}

}  // namespace hgcd
