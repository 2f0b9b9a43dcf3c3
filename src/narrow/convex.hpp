// The convex path of the narrow phase: pairs of small convex meshes
// (Mesh::sat) are first decided by a kernel that reads only the meshes'
// precomputed data and the two poses (convex_kernel.cpp): separating axes and
// a certificate that the surfaces cross, each certified against the rounding
// of its evaluation. What it leaves open goes on with world vertices, a
// search for an edge through a triangle (convex.cpp) and the exact test.
// Internal to src/narrow (narrow.cpp calls it).
#pragma once
#include "common/transform.hpp"
#include "narrow/narrow.hpp"

namespace hgcd {

// Edge-edge axes are tried when the two meshes have at most this many pairs
// of edge directions (box and box: 9).
constexpr uint32_t kEdgeAxisPairs = 36;

// The face axes tried: those nearest the line of centres, at most this many
// per mesh.
constexpr int kFaceAxes = 6;

// The margin of a face axis's test, argued in convex_kernel.cpp (face_apart).
constexpr double kFaceMargin = 0x1p-42;

// Pairs whose bodies reach along the line of centres past each other by
// more than kDeep - 1 times the distance between their positions most
// likely collide: the certificates that they do go first. Those reaching
// past each other by more than kMiddling - 1 times it, and not separated
// by a face axis, collide more often than an edge axis separates them.
constexpr double kDeep = 1.2;
constexpr double kMiddling = 1.1;

enum class ConvexVerdict {
    ApartOnCentres,  // a separating axis along the line of centres
    Apart,           // a separating axis among the face normals and edge pairs
    Surface,         // the surfaces certainly cross
    AHoldsB,         // a's solid holds b's, the surfaces apart
    BHoldsA,
    Open,            // nothing certain
};

// The kernel, for two bodies whose meshes have Mesh::sat: in order, the
// separating axis along the line between their positions (tested on the
// meshes' vertex runs, four vertices per vector, AVX2 where use_avx2(), half
// of them for meshes symmetric about their origin); the vertex of one body
// reaching furthest towards the other strictly inside it, by its face
// planes with a certified margin, while another vertex lies strictly
// outside it on that line; for deep pairs (kDeep) a point strictly inside
// both; when one body's stretch of that line lies within the other's,
// whether every vertex of it lies strictly inside the other (containment);
// then a point of an edge of one body strictly inside the other while a
// vertex of it lies strictly outside (bodies crossing edge to edge) first
// for deep pairs, after the face axes for middling ones (kMiddling), last
// for the others; separating axes along the face normals nearest that line
// (kFaceAxes of each mesh at most, nearest first), for meshes with at most
// kEdgeAxisPairs pairs of edge directions the edge cross products, for the
// pairs not deep the point inside both, and for meshes with more edge
// directions the cross products of the edges at the two vertices reaching
// furthest.
ConvexVerdict convex_decide(const BodyPose &a, const BodyPose &b);

// The kernel's line of centres for a pair (its first step): the rotations
// (rotation_of), u = fl(c_b - c_a), da = fl(R_a^T u), ub = fl(R_b^T u), db =
// -ub, each body's range [lo, hi] of fl(l . d) over its vertices and a
// vertex where hi is reached (range_arg's choice among ties), uu = fl(u . u)
// and the margin of the comparisons on that line.
struct ConvexCentres {
    const SatData *sa, *sb;  // the meshes' Mesh::sat
    Rotation ra, rb;
    double u[3], da[3], ub[3], db[3];
    double alo, ahi, blo, bhi, uu, cmargin;
    uint32_t a_toward, b_toward;
    bool pokes_tried = false;  // the vertex pokes of the later steps were tried (by the batch)
    bool faces_tried = false;  // and the face axes
};

// Whether the two bodies' ranges on the line of centres (a's up to ahi, b's
// from uu - bhi) meet within the margin of its comparisons: neither apart
// nor overlapping past it. (The batch evaluates the same four lanes at once.)
inline bool grazing(double uu, double ahi, double bhi, double cmargin) {
    const double gap = uu - (ahi + bhi);
    return gap <= cmargin && gap >= -cmargin;
}

// convex_decide for a pair its line of centres does not separate, from that
// step's values computed by the caller with the same bits (the batch,
// convex_batch.cpp).
ConvexVerdict convex_decide_past_centres(const BodyPose &a, const BodyPose &b, const ConvexCentres &c);

// collide_convex after the kernel's verdict v.
Contact collide_convex_after(const BodyPose &a, const BodyPose &b, NarrowScratch &s, Witness *witness,
                             ConvexVerdict v);

// The convex path's one-pair test (collide() of two bodies whose meshes have
// Mesh::sat): the kernel, then for the pairs it leaves open the world
// vertices, the search for crossing surfaces and the exact steps
// (narrow.cpp).
Contact collide_convex(const BodyPose &a, const BodyPose &b, NarrowScratch &s, Witness *witness);

// Certainly do the surfaces cross: an edge of one mesh through the
// interior of a triangle of the other (both its ends strictly on either
// side of the triangle's plane, the line strictly inside its three edges,
// every sign certified by a filter)? Tried on the edges at each mesh's
// vertex nearest the other's position, then on every edge against the
// triangles (at most 64 of a mesh) that reach the intersection of the two
// boxes; false proves nothing. wa, wb: the world
// vertices (world_vertices), box_a, box_b their exact boxes.
bool convex_surfaces_cross(const BodyPose &a, const double *wa, const double *box_a, const BodyPose &b,
                           const double *wb, const double *box_b);

}  // namespace hgcd
