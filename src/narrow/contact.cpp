#include "narrow/contact.hpp"

#include <algorithm>
#include <cmath>

#include "exact/geometry.hpp"
#include "common/ieee.hpp"

namespace hgcd {

namespace {

inline bool boxes_disjoint(const double *a, const double *b) {
    return a[3] < b[0] || b[3] < a[0] || a[4] < b[1] || b[4] < a[1] || a[5] < b[2] || b[5] < a[2];
}

inline void triangle_box(const double *v, const uint32_t *t, double *box) {
    const double *p = &v[3 * size_t(t[0])], *q = &v[3 * size_t(t[1])], *r = &v[3 * size_t(t[2])];
    for (int k = 0; k < 3; ++k) {
        box[k] = std::min(std::min(p[k], q[k]), r[k]);
        box[3 + k] = std::max(std::max(p[k], q[k]), r[k]);
    }
}

// A triangle of a and one of b that share a point (exact), or false.
bool find_surface_witness(const Mesh &ma, const double *wa, const double *box_a, const Mesh &mb,
                          const double *wb, const double *box_b, ContactScratch &s, uint32_t *ta,
                          uint32_t *tb) {
    s.tri_b.clear();
    s.box_b.clear();
    for (uint32_t t = 0; t < mb.triangle_count; ++t) {
        double bb[6];
        triangle_box(wb, &mb.triangles[3 * size_t(t)], bb);
        if (boxes_disjoint(bb, box_a)) continue;
        s.tri_b.push_back(t);
        s.box_b.insert(s.box_b.end(), bb, bb + 6);
    }
    for (uint32_t t = 0; t < ma.triangle_count && !s.tri_b.empty(); ++t) {
        const uint32_t *fa = &ma.triangles[3 * size_t(t)];
        double ba[6];
        triangle_box(wa, fa, ba);
        if (boxes_disjoint(ba, box_b)) continue;
        for (size_t k = 0; k < s.tri_b.size(); ++k) {
            if (boxes_disjoint(ba, &s.box_b[6 * k])) continue;
            const uint32_t *fb = &mb.triangles[3 * size_t(s.tri_b[k])];
            if (tri_tri_intersect(&wa[3 * size_t(fa[0])], &wa[3 * size_t(fa[1])], &wa[3 * size_t(fa[2])],
                                  &wb[3 * size_t(fb[0])], &wb[3 * size_t(fb[1])], &wb[3 * size_t(fb[2])])) {
                *ta = t;
                *tb = s.tri_b[k];
                return true;
            }
        }
    }
    return false;
}

// Does the closed mesh `outer` hold a component of `inner`? Asked only for
// pairs whose surfaces are disjoint, so no tested vertex is on outer's surface.
bool holds(const Mesh &outer, const double *wo, const double *box_o, const Mesh &inner, const double *wi) {
    if (!outer.closed) return false;
    for (uint32_t v : inner.component_vertices) {
        const double *p = &wi[3 * size_t(v)];
        if (p[0] < box_o[0] || p[0] > box_o[3] || p[1] < box_o[1] || p[1] > box_o[4] || p[2] < box_o[2] ||
            p[2] > box_o[5])
            continue;
        // Exact parity even for convex meshes (see holds_component in narrow.cpp).
        if (point_in_closed_mesh(p, wo, outer.triangles.data(), outer.triangle_count, box_o, box_o + 3))
            return true;
    }
    return false;
}

}  // namespace

void exact_contact(const BodyPose &a, const BodyPose &b, Contact hit, const Witness &w, ContactScratch &s,
                   hgcd_contact *out) {
    out->kind = 0;
    out->triangle_a = out->triangle_b = UINT32_MAX;
    out->reserved = 0;
    out->depth = 0;
    for (int k = 0; k < 3; ++k) out->normal[k] = out->point[k] = 0;
    if (hit == Contact::Surface) {
        out->kind = HGCD_CONTACT_SURFACE;
        if (w.recorded) {
            out->triangle_a = w.tri_a;
            out->triangle_b = w.tri_b;
            return;
        }
    } else if (hit == Contact::Containment) {
        if (w.recorded) {
            out->kind = w.a_holds_b ? HGCD_CONTACT_A_CONTAINS_B : HGCD_CONTACT_B_CONTAINS_A;
            return;
        }
    } else {
        return;
    }
    // Not recorded: work it out on the world vertices (the same bits).
    double box_a[6], box_b[6];
    world_vertices(a, s.world_a, box_a);
    world_vertices(b, s.world_b, box_b);
    const double *wa = s.world_a.data(), *wb = s.world_b.data();
    if (hit == Contact::Surface) {
        find_surface_witness(*a.mesh, wa, box_a, *b.mesh, wb, box_b, s, &out->triangle_a, &out->triangle_b);
        return;
    }
    // collide() asks b about a first: the same order here.
    out->kind = holds(*b.mesh, wb, box_b, *a.mesh, wa) ? HGCD_CONTACT_B_CONTAINS_A : HGCD_CONTACT_A_CONTAINS_B;
}

void penetration_contact(const CcdContact &c, hgcd_contact *out) {
    out->kind = HGCD_CONTACT_PENETRATION;
    out->triangle_a = out->triangle_b = UINT32_MAX;
    out->reserved = 0;
    out->depth = c.depth;
    for (int k = 0; k < 3; ++k) {
        out->normal[k] = c.normal[k];
        out->point[k] = c.point[k];
    }
}

}  // namespace hgcd
