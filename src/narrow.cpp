#include "narrow.hpp"

#include <algorithm>

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

Contact collide(const BodyPose &a, const BodyPose &b, NarrowScratch &s) {
    double box_a[6], box_b[6];
    world_vertices(a, s.world_a, box_a);
    world_vertices(b, s.world_b, box_b);
    // Exact prefilter: the solids lie inside these boxes.
    if (boxes_disjoint(box_a, box_b)) return Contact::None;
    ++s.exact_tests;
    const Mesh &ma = *a.mesh, &mb = *b.mesh;
    const double *wa = s.world_a.data(), *wb = s.world_b.data();

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
                                      &wb[3 * size_t(fb[2])]))
                    return Contact::Surface;
            }
        }
    }
    // Surfaces disjoint: the solids meet only if one holds a component of the other.
    if (mb.closed && holds_component(mb, s.world_b, box_b, ma, s.world_a))
        return Contact::Containment;
    if (ma.closed && holds_component(ma, s.world_a, box_a, mb, s.world_b))
        return Contact::Containment;
    return Contact::None;
}

}  // namespace hgcd
