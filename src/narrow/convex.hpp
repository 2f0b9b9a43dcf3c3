// The convex path of the narrow phase: pairs of small convex meshes
// (Mesh::sat) are first tried on separating axes, each certified against the
// rounding of its evaluation, before the exact triangle test. Internal to
// src/narrow (narrow.cpp calls it).
#pragma once
#include "common/transform.hpp"
#include "narrow/narrow.hpp"

namespace hgcd {

// Edge-edge axes are tried when the two meshes have at most this many pairs
// of edge directions (box and box: 9).
constexpr uint32_t kEdgeAxisPairs = 36;

// Certainly apart along the line between the bodies' positions (tested
// before any world vertex is computed)? ra, rb: the bodies' rotations. Sets
// *deep when the two bodies reach along that line past each other by more
// than kDeep - 1 times the distance between their positions: such a pair
// most likely collides, and the search for crossing surfaces goes first.
constexpr double kDeep = 1.0;
bool convex_centres_apart(const BodyPose &a, const BodyPose &b, const Rotation &ra, const Rotation &rb, bool *deep);

// Certainly apart along a face normal of either mesh (those most nearly
// along the line of centres) or, for meshes with few edge directions, the
// cross product of an edge direction of each? wa, wb: the world vertices
// (world_vertices), box_a, box_b their exact boxes.
bool convex_axes_apart(const BodyPose &a, const double *wa, const double *box_a, const Rotation &ra,
                       const BodyPose &b, const double *wb, const double *box_b, const Rotation &rb);

// Certainly do the surfaces cross: an edge of one mesh through the
// interior of a triangle of the other (both its ends strictly on either
// side of the triangle's plane, the line strictly inside its three edges,
// every sign certified by a filter)? Tried on the edges at each mesh's
// vertex nearest the other's position; false proves nothing.
bool convex_surfaces_cross(const BodyPose &a, const double *wa, const BodyPose &b, const double *wb);

}  // namespace hgcd
