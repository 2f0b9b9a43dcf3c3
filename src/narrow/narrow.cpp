// Narrow phase: dispatch (collide, collide_within), the direct path for
// small meshes, the convex path's fallbacks and the margin's direct path. The
// tree path is tree_path.cpp, the tetrahedron path tetra.cpp.
#include "narrow/narrow.hpp"

#include <algorithm>
#include <cmath>

#include "common/ieee.hpp"
#include "common/transform.hpp"
#include "exact/geometry.hpp"
#include "narrow/boxes.hpp"
#include "narrow/bvh.hpp"
#include "narrow/convex.hpp"
#include "narrow/flat.hpp"
#include "narrow/tetra.hpp"
#include "narrow/within.hpp"

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

// find_meeting_triangles, or with kMargin a triangle pair within d.
template <bool kMargin>
bool meeting_triangles(const Mesh &ma, const double *wa, const double *box_a, const Mesh &mb, const double *wb,
                       const double *box_b, NearTriangles &near_b, uint64_t &triangle_tests, uint32_t *meet,
                       double d) {
    near_b.room(mb.triangle_count);
    uint32_t *const near_tri = near_b.tri.data();
    double *const near_box = near_b.box.data();
    size_t near = 0;
    for (uint32_t t = 0; t < mb.triangle_count; ++t) {
        double *tb = near_box + 6 * near;
        triangle_box(wb, &mb.triangles[3 * size_t(t)], tb);
        if (kMargin ? boxes_apart(tb, box_a, d) : boxes_disjoint(tb, box_a)) continue;
        near_tri[near++] = t;
    }
    if (near == 0) return false;
    for (uint32_t t = 0; t < ma.triangle_count; ++t) {
        const uint32_t *fa = &ma.triangles[3 * size_t(t)];
        double ta[6];
        triangle_box(wa, fa, ta);
        if (kMargin ? boxes_apart(ta, box_b, d) : boxes_disjoint(ta, box_b)) continue;
        const double *p0 = &wa[3 * size_t(fa[0])], *p1 = &wa[3 * size_t(fa[1])], *p2 = &wa[3 * size_t(fa[2])];
        for (size_t k = 0; k < near; ++k) {
            if (kMargin ? boxes_apart(ta, near_box + 6 * k, d) : boxes_disjoint(ta, near_box + 6 * k)) continue;
            const uint32_t *fb = &mb.triangles[3 * size_t(near_tri[k])];
            ++triangle_tests;
            const double *q0 = &wb[3 * size_t(fb[0])], *q1 = &wb[3 * size_t(fb[1])], *q2 = &wb[3 * size_t(fb[2])];
            if (kMargin ? tri_tri_within(p0, p1, p2, q0, q1, q2, d) : tri_tri_intersect(p0, p1, p2, q0, q1, q2)) {
                meet[0] = t;
                meet[1] = near_tri[k];
                return true;
            }
        }
    }
    return false;
}

}  // namespace

bool find_meeting_triangles(const Mesh &ma, const double *wa, const double *box_a, const Mesh &mb,
                            const double *wb, const double *box_b, NearTriangles &near_b,
                            uint64_t &triangle_tests, uint32_t *meet) {
    return meeting_triangles<false>(ma, wa, box_a, mb, wb, box_b, near_b, triangle_tests, meet, 0);
}

bool holds_component(const Mesh &outer, const double *wo, const double *outer_box, const Mesh &inner,
                     const double *wi) {
    for (uint32_t v : inner.component_vertices) {
        const double *p = &wi[3 * size_t(v)];
        if (!point_in_box(p, outer_box)) continue;
        // Exact ray parity, also for convex meshes: in world space, after
        // rounding, a convex mesh need not be convex, and the face-by-face
        // test would then misjudge points near a poking vertex.
        if (point_in_closed_mesh(p, wo, outer.triangles.data(), outer.triangle_count, outer_box, outer_box + 3))
            return true;
    }
    return false;
}

namespace {

// Is there a face of mesh `ca` (world vertices wa) whose plane has every
// vertex of the other body certainly strictly outside, and every vertex of
// `ca` inside or on it? Then each body lies in the convex hull of its
// vertices, on its own side of the plane, and they are disjoint. Both sides
// are checked in world space: rounding the world vertices can make a mesh
// that is convex in its own frame slightly non-convex (a cube's coplanar
// fourth vertex poking out by an ulp), so the mesh's convex flag only says
// which meshes are worth trying. A sign is trusted when the determinant
// exceeds the rounding error bound of its evaluation (Shewchuk's orient3d
// bound (7 + 56 eps) eps * permanent, rounded up to 1e-15 * permanent, plus
// 2^-960 for underflowed products, as in exact/predicates.hpp); an uncertain sign on
// the other body's side makes the face prove nothing, an uncertain sign on
// the own side is settled by the exact orient3d. So this test never changes
// an answer.
// With kMargin, the other body's vertices must be certainly farther than d
// beyond the plane: the value exceeds its bound plus d times a bound on the
// exact normal's length (|N| <= |n| + the components' rounding, at most
// 4 eps times their permanents; the factors 1 + 1e-12 cover the rounding of
// these products and sums). Then every point of the other body is more than
// d from the halfspace that holds this one.
template <bool kMargin = false>
bool separated_by_face(const Mesh &ca, const double *wa, const Mesh &mb, const double *wb, double gap = 0) {
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
        // inward * orient3d(a, b, c, d): > bound certainly inside the plane's
        // inner side, < -bound certainly outside, else uncertain.
        auto side = [&](const double *d, double &bound) {
            const double wx = d[0] - a[0], wy = d[1] - a[1], wz = d[2] - a[2];
            bound = kBound * (std::fabs(wx) * px + std::fabs(wy) * py + std::fabs(wz) * pz) + 0x1p-960;
            return -inward * (wx * nx + wy * ny + wz * nz);
        };
        double need = 0;
        if (kMargin)
            need = gap * (std::sqrt((nx * nx + ny * ny) + nz * nz) * (1 + 1e-12) + 1e-15 * ((px + py) + pz)) *
                   (1 + 1e-12);
        bool separating = true;
        for (uint32_t v = 0; v < mb.vertex_count && separating; ++v) {
            double bound;
            const double s = side(&wb[3 * size_t(v)], bound);
            separating = kMargin ? s < -(bound + need) * (1 + 1e-12) : s < -bound;
        }
        for (uint32_t v = 0; v < ca.vertex_count && separating; ++v) {
            if (v == f[0] || v == f[1] || v == f[2]) continue;
            const double *d = &wa[3 * size_t(v)];
            double bound;
            const double s = side(d, bound);
            if (s > bound) continue;
            separating = s >= -bound && inward * orient3d(a, b, c, d) >= 0;
        }
        if (separating) return true;
    }
    return false;
}

// The face test costs faces x vertices; beyond this it is left to the
// triangle tests, which prune by boxes.
constexpr uint64_t kFaceTestBudget = 4096;

// Is there an axis c = e_a x e_b (the rounded cross product of rounded edge
// vectors of two convex meshes' triangles: any vector serves as an axis)
// with a gap of more than d between the bodies' vertices (axis_apart)? Then
// the bodies (in their vertices' hulls) are more than d apart.
bool separated_by_edge_axes(const Mesh &ma, const double *wa, const Mesh &mb, const double *wb, double d) {
    for (uint32_t ta = 0; ta < ma.triangle_count; ++ta)
        for (int i = 0; i < 3; ++i) {
            const double *a0 = &wa[3 * size_t(ma.triangles[3 * ta + i])];
            const double *a1 = &wa[3 * size_t(ma.triangles[3 * ta + (i + 1) % 3])];
            const double ex = a1[0] - a0[0], ey = a1[1] - a0[1], ez = a1[2] - a0[2];
            for (uint32_t tb = 0; tb < mb.triangle_count; ++tb)
                for (int j = 0; j < 3; ++j) {
                    const double *b0 = &wb[3 * size_t(mb.triangles[3 * tb + j])];
                    const double *b1 = &wb[3 * size_t(mb.triangles[3 * tb + (j + 1) % 3])];
                    const double fx = b1[0] - b0[0], fy = b1[1] - b0[1], fz = b1[2] - b0[2];
                    const double c[3] = {ey * fz - ez * fy, ez * fx - ex * fz, ex * fy - ey * fx};
                    if (axis_apart(c, wa, ma.vertex_count, wb, mb.vertex_count, d)) return true;
                }
        }
    return false;
}

// The direct path's exact steps on the world vertices (wa, wb) and exact
// boxes of two small meshes: boxes that meet in a flat region decided there
// (flat.hpp), else the face planes (face_planes: unless the convex path's
// axes have been tried), then triangle pairs, then containment.
Contact direct_exact(const BodyPose &a, const double *wa, const double *box_a, const BodyPose &b,
                     const double *wb, const double *box_b, NarrowScratch &s, Witness *witness, bool face_planes) {
    const Mesh &ma = *a.mesh, &mb = *b.mesh;
    // (A witness request takes the triangle pairs' order below.)
    if (!witness) {
        const int flat = flat_contact(ma, wa, box_a, mb, wb, box_b);
        if (flat >= 0) return flat ? Contact::Surface : Contact::None;
    }
    if (face_planes && ma.convex && uint64_t(ma.triangle_count) * mb.vertex_count <= kFaceTestBudget &&
        separated_by_face(ma, wa, mb, wb))
        return Contact::None;
    if (face_planes && mb.convex && uint64_t(mb.triangle_count) * ma.vertex_count <= kFaceTestBudget &&
        separated_by_face(mb, wb, ma, wa))
        return Contact::None;
    uint32_t meet[2];
    if (find_meeting_triangles(ma, wa, box_a, mb, wb, box_b, s.near_b, s.triangle_tests, meet)) {
        if (witness) *witness = Witness{meet[0], meet[1], false, true};
        return Contact::Surface;
    }
    // Surfaces disjoint: the solids meet only if one holds a component of the other.
    if (mb.closed && holds_component(mb, wb, box_b, ma, wa)) {
        if (witness) *witness = Witness{UINT32_MAX, UINT32_MAX, false, true};
        return Contact::Containment;
    }
    if (ma.closed && holds_component(ma, wa, box_a, mb, wb)) {
        if (witness) *witness = Witness{UINT32_MAX, UINT32_MAX, true, true};
        return Contact::Containment;
    }
    return Contact::None;
}

// The direct path for small meshes other than tetrahedron and convex pairs.
__attribute__((noinline)) Contact collide_direct(const BodyPose &a, const BodyPose &b, NarrowScratch &s,
                                                 Witness *witness) {
    double box_a[6], box_b[6];
    world_vertices(a, s.world_a, box_a);
    world_vertices(b, s.world_b, box_b);
    // Exact prefilter: the solids lie inside these boxes.
    if (boxes_disjoint(box_a, box_b)) return Contact::None;
    ++s.exact_tests;
    return direct_exact(a, s.world_a.data(), box_a, b, s.world_b.data(), box_b, s, witness, true);
}

}  // namespace

bool face_apart(const Mesh &ca, const double *wa, const Mesh &mb, const double *wb, double d) {
    return ca.convex && separated_by_face<true>(ca, wa, mb, wb, d);
}

// The margin path of small meshes whose solids do not share a point: the
// direct path's triangle pairs with boxes grown by d and the within-d
// triangle test, after the face planes of convex meshes.
Contact collide_within_direct(const BodyPose &a, const BodyPose &b, double d, NarrowScratch &s, Witness *witness) {
    double box_a[6], box_b[6];
    world_vertices(a, s.world_a, box_a);
    world_vertices(b, s.world_b, box_b);
    if (boxes_apart(box_a, box_b, d)) return Contact::None;
    const Mesh &ma = *a.mesh, &mb = *b.mesh;
    const double *wa = s.world_a.data(), *wb = s.world_b.data();
    // A face plane with the other body more than d beyond it.
    if (ma.convex && uint64_t(ma.triangle_count) * mb.vertex_count <= kFaceTestBudget &&
        separated_by_face<true>(ma, wa, mb, wb, d))
        return Contact::None;
    if (mb.convex && uint64_t(mb.triangle_count) * ma.vertex_count <= kFaceTestBudget &&
        separated_by_face<true>(mb, wb, ma, wa, d))
        return Contact::None;
    if (ma.convex && mb.convex &&
        9 * uint64_t(ma.triangle_count) * mb.triangle_count * (ma.vertex_count + mb.vertex_count) <= kFaceTestBudget &&
        separated_by_edge_axes(ma, wa, mb, wb, d))
        return Contact::None;
    uint32_t meet[2];
    if (meeting_triangles<true>(ma, wa, box_a, mb, wb, box_b, s.near_b, s.triangle_tests, meet, d)) {
        if (witness) *witness = Witness{meet[0], meet[1], false, true};
        return Contact::Near;
    }
    return Contact::None;
}

// The convex path (both meshes Mesh::sat): the kernel (convex_decide), then
// for the pairs it leaves open the world vertices and their exact boxes, the
// search for an edge through a triangle, and the exact steps of the direct
// or tree path. A witness request (contacts) takes only the kernel's
// separations: its certificates name no triangle pair. exact_tests counts
// the pairs that pass the line of centres.
Contact collide_convex(const BodyPose &a, const BodyPose &b, NarrowScratch &s, Witness *witness) {
    return collide_convex_after(a, b, s, witness, convex_decide(a, b));
}

Contact collide_convex_after(const BodyPose &a, const BodyPose &b, NarrowScratch &s, Witness *witness,
                             ConvexVerdict v) {
    if (v == ConvexVerdict::ApartOnCentres) return Contact::None;
    ++s.exact_tests;
    if (v == ConvexVerdict::Apart) return Contact::None;
    if (!witness) {
        if (v == ConvexVerdict::Surface) return Contact::Surface;
        if (v == ConvexVerdict::AHoldsB || v == ConvexVerdict::BHoldsA) return Contact::Containment;
    }
    double box_a[6], box_b[6];
    world_vertices(a, s.world_a, box_a);
    world_vertices(b, s.world_b, box_b);
    if (boxes_disjoint(box_a, box_b)) return Contact::None;
    const double *wa = s.world_a.data(), *wb = s.world_b.data();
    if (!witness && convex_surfaces_cross(a, wa, box_a, b, wb, box_b)) return Contact::Surface;
    if (!a.mesh->bvh.empty() || !b.mesh->bvh.empty()) return collide_tree(a, b, s, witness, false);
    return direct_exact(a, wa, box_a, b, wb, box_b, s, witness, false);
}

Contact collide_within(const BodyPose &a, const BodyPose &b, double d, NarrowScratch &s, Witness *witness) {
    // Solids that share a point are within any d: the fast exact paths
    // first (they decide containment too), the search within d only for
    // pairs apart.
    if (a.mesh->tetra && b.mesh->tetra && !witness) return tet::collide_tetra_within(a, b, d, s);
    const Contact touching = collide(a, b, s, witness);
    if (touching != Contact::None) return touching;
    if (!a.mesh->bvh.empty() || !b.mesh->bvh.empty()) return collide_tree<true>(a, b, s, witness, false, d);
    return collide_within_direct(a, b, d, s, witness);
}

Contact collide(const BodyPose &a, const BodyPose &b, NarrowScratch &s, Witness *witness, NodeHint *hint) {
    // (A tetrahedron has no tree; a witness asks for the general path's
    // triangle order.)
    if (a.mesh->tetra && b.mesh->tetra && !witness) return tet::collide_tetra(a, b, s);
    if (a.mesh->sat && b.mesh->sat) return collide_convex(a, b, s, witness);
    if (!a.mesh->bvh.empty() || !b.mesh->bvh.empty())
        return collide_tree(a, b, s, witness, true, 0, witness ? nullptr : hint);
    return collide_direct(a, b, s, witness);
}

}  // namespace hgcd
