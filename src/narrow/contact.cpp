#include "narrow/contact.hpp"

#include "common/ieee.hpp"

namespace hgcd {

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
    } else if (hit == Contact::Near) {  // (collide_within always records its witness)
        out->kind = HGCD_CONTACT_NEAR;
        out->triangle_a = w.tri_a;
        out->triangle_b = w.tri_b;
        return;
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
        uint32_t meet[2];
        uint64_t tests = 0;  // (counted by collide() already)
        if (find_meeting_triangles(*a.mesh, wa, box_a, *b.mesh, wb, box_b, s.near_b, tests, meet)) {
            out->triangle_a = meet[0];
            out->triangle_b = meet[1];
        }
        return;
    }
    // collide() asks b about a first: the same order here.
    const bool b_holds_a = b.mesh->closed && holds_component(*b.mesh, wb, box_b, *a.mesh, wa);
    out->kind = b_holds_a ? HGCD_CONTACT_B_CONTAINS_A : HGCD_CONTACT_A_CONTAINS_B;
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
