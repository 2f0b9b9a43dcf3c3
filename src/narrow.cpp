#include "narrow.hpp"

#include <algorithm>
#include <cmath>

#include "geometry.hpp"
#include "transform.hpp"

namespace hgcd {

void world_vertices(const BodyPose &body, std::vector<double> &out, double *box) {
    const Mesh &m = *body.mesh;
    out.resize(3 * size_t(m.vertex_count));
    const Rotation r = rotation_of(body.orientation);
    box[0] = box[1] = box[2] = INFINITY;
    box[3] = box[4] = box[5] = -INFINITY;
    for (uint32_t v = 0; v < m.vertex_count; ++v) {
        double *w = &out[3 * size_t(v)];
        transform_point(r, body.position, body.scale, &m.vertices[3 * size_t(v)], w);
        for (int k = 0; k < 3; ++k) {
            box[k] = std::min(box[k], w[k]);
            box[3 + k] = std::max(box[3 + k], w[k]);
        }
    }
}

namespace {

inline bool boxes_disjoint(const double *a, const double *b) {
    return a[3] < b[0] || b[3] < a[0] || a[4] < b[1] || b[4] < a[1] || a[5] < b[2] ||
           b[5] < a[2];
}

inline bool point_in_box(const double *p, const double *box) {
    return p[0] >= box[0] && p[0] <= box[3] && p[1] >= box[1] && p[1] <= box[4] &&
           p[2] >= box[2] && p[2] <= box[5];
}

inline void triangle_box(const double *v, const uint32_t *t, double *box) {
    const double *p = &v[3 * size_t(t[0])], *q = &v[3 * size_t(t[1])], *r = &v[3 * size_t(t[2])];
    for (int k = 0; k < 3; ++k) {
        box[k] = std::min(std::min(p[k], q[k]), r[k]);
        box[3 + k] = std::max(std::max(p[k], q[k]), r[k]);
    }
}

// Is there a face of the convex mesh `ca` (world vertices wa) with every
// vertex of the other body certainly strictly outside its plane? Then the
// other body, which lies in the convex hull of its vertices, is disjoint from
// `ca`. The sign of each orientation determinant is trusted only when it
// exceeds the rounding error bound of its evaluation (Shewchuk's orient3d
// bound (7 + 56 eps) eps * permanent, rounded up to 1e-15 * permanent);
// otherwise that face proves nothing, so this test never changes an answer.
bool separated_by_face(const Mesh &ca, const double *wa, const Mesh &mb, const double *wb) {
    constexpr double kBound = 1e-15;
    const double inward = ca.inward_sign;
    for (uint32_t t = 0; t < ca.triangle_count; ++t) {
        const uint32_t *f = &ca.triangles[3 * size_t(t)];
        const double *a = &wa[3 * size_t(f[0])], *b = &wa[3 * size_t(f[1])], *c = &wa[3 * size_t(f[2])];
        const double ux = b[0] - a[0], uy = b[1] - a[1], uz = b[2] - a[2];
        const double vx = c[0] - a[0], vy = c[1] - a[1], vz = c[2] - a[2];
        // orient3d(a, b, c, d) = -(d - a) . (u x v)
        const double nx = uy * vz - uz * vy, ny = uz * vx - ux * vz, nz = ux * vy - uy * vx;
        const double px = std::fabs(uy * vz) + std::fabs(uz * vy);
        const double py = std::fabs(uz * vx) + std::fabs(ux * vz);
        const double pz = std::fabs(ux * vy) + std::fabs(uy * vx);
        bool all_outside = true;
        for (uint32_t v = 0; v < mb.vertex_count && all_outside; ++v) {
            const double *d = &wb[3 * size_t(v)];
            const double wx = d[0] - a[0], wy = d[1] - a[1], wz = d[2] - a[2];
            const double det = -(wx * nx + wy * ny + wz * nz);
            const double perm = std::fabs(wx) * px + std::fabs(wy) * py + std::fabs(wz) * pz;
            // Outside: orient3d has the sign opposite to the interior's.
            all_outside = -inward * det > kBound * perm;
        }
        if (all_outside) return true;
    }
    return false;
}

// The face test costs faces x vertices; beyond this it is left to the
// triangle tests, which prune by boxes.
constexpr uint64_t kFaceTestBudget = 4096;

// Is some component of `inner` (world vertices wv) inside the closed mesh
// `outer` (world vertices wo)? Only asked once the surfaces are disjoint, so
// no tested vertex lies on the outer surface.
bool holds_component(const Mesh &outer, const std::vector<double> &wo, const double *outer_box,
                     const Mesh &inner, const std::vector<double> &wv) {
    for (uint32_t v : inner.component_vertices) {
        const double *p = &wv[3 * size_t(v)];
        if (!point_in_box(p, outer_box)) continue;
        const bool inside =
            outer.convex
                ? point_in_convex_closed_mesh(p, wo.data(), outer.triangles.data(),
                                              outer.triangle_count, outer.inward_sign)
                : point_in_closed_mesh(p, wo.data(), outer.triangles.data(), outer.triangle_count,
                                       outer_box, outer_box + 3);
        if (inside) return true;
    }
    return false;
}

}  // namespace

Contact collide(const BodyPose &a, const BodyPose &b, NarrowScratch &s, Witness *witness) {
    double box_a[6], box_b[6];
    world_vertices(a, s.world_a, box_a);
    world_vertices(b, s.world_b, box_b);
    // Exact prefilter: the solids lie inside these boxes.
    if (boxes_disjoint(box_a, box_b)) return Contact::None;
    ++s.exact_tests;
    const Mesh &ma = *a.mesh, &mb = *b.mesh;
    const double *wa = s.world_a.data(), *wb = s.world_b.data();
    if (ma.convex && uint64_t(ma.triangle_count) * mb.vertex_count <= kFaceTestBudget &&
        separated_by_face(ma, wa, mb, wb))
        return Contact::None;
    if (mb.convex && uint64_t(mb.triangle_count) * ma.vertex_count <= kFaceTestBudget &&
        separated_by_face(mb, wb, ma, wa))
        return Contact::None;

    // Triangles of b that reach a's box, with their boxes.
    s.tri_b.clear();
    s.box_b.clear();
    for (uint32_t t = 0; t < mb.triangle_count; ++t) {
        double tb[6];
        triangle_box(wb, &mb.triangles[3 * size_t(t)], tb);
        if (boxes_disjoint(tb, box_a)) continue;
        s.tri_b.push_back(t);
        s.box_b.insert(s.box_b.end(), tb, tb + 6);
    }
    if (!s.tri_b.empty()) {
        for (uint32_t t = 0; t < ma.triangle_count; ++t) {
            const uint32_t *fa = &ma.triangles[3 * size_t(t)];
            double ta[6];
            triangle_box(wa, fa, ta);
            if (boxes_disjoint(ta, box_b)) continue;
            const double *p0 = &wa[3 * size_t(fa[0])], *p1 = &wa[3 * size_t(fa[1])],
                         *p2 = &wa[3 * size_t(fa[2])];
            for (size_t k = 0; k < s.tri_b.size(); ++k) {
                if (boxes_disjoint(ta, &s.box_b[6 * k])) continue;
                const uint32_t *fb = &mb.triangles[3 * size_t(s.tri_b[k])];
                ++s.triangle_tests;
                if (tri_tri_intersect(p0, p1, p2, &wb[3 * size_t(fb[0])], &wb[3 * size_t(fb[1])],
                                      &wb[3 * size_t(fb[2])])) {
                    if (witness) *witness = Witness{t, s.tri_b[k], false, true};
                    return Contact::Surface;
                }
            }
        }
    }
    // Surfaces disjoint: the solids meet only if one holds a component of the other.
    if (mb.closed && holds_component(mb, s.world_b, box_b, ma, s.world_a)) {
        if (witness) *witness = Witness{UINT32_MAX, UINT32_MAX, false, true};
        return Contact::Containment;
    }
    if (ma.closed && holds_component(ma, s.world_a, box_a, mb, s.world_b)) {
        if (witness) *witness = Witness{UINT32_MAX, UINT32_MAX, true, true};
        return Contact::Containment;
    }
    return Contact::None;
}

}  // namespace hgcd
