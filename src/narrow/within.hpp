// The contact margin's narrow phase for small meshes (within.cpp, and the
// direct path in narrow.cpp): certificates in floating point that two point
// sets' hulls are more than d apart or within d, and the tetrahedron pairs'
// margin test built on them. Internal to src/narrow and src/world.
#pragma once
#include <cstdint>

#include "narrow/narrow.hpp"

namespace hgcd {

// Is there an axis, c scaled by a power of two, along which every point of
// wb (nb points, 3 doubles each) lies more than d beyond every point of wa,
// or the other way round? Then the hulls of the two sets are more than d
// apart. Certified in float (within.cpp); an uncertain axis proves nothing.
bool axis_apart(const double *c, const double *wa, uint32_t na, const double *wb, uint32_t nb, double d);

// Is there a face of the convex mesh ca (world vertices wa) with every
// vertex of mb more than d beyond its plane and ca on the other side
// (narrow.cpp's face test with a gap, certified)? False for a mesh not
// flagged convex.
bool face_apart(const Mesh &ca, const double *wa, const Mesh &mb, const double *wb, double d);

// The margin path of small meshes (no tree) whose solids do not share a
// point (narrow.cpp): Near when some triangle of each is within d, exact.
Contact collide_within_direct(const BodyPose &a, const BodyPose &b, double d, NarrowScratch &s,
                              Witness *witness);

namespace tet {

// For two tetrahedra (Mesh::tetra) whose solids do not share a point (the
// exact touching test said so), and d > 0: Near when the solids are within
// d, else None. Exact: the separating axis along the line of centres with a
// gap of d, the vertex boxes d apart, a face plane of either with a gap of
// d (face_apart), then the closest points of the two hulls in float (GJK)
// give either an axis with a gap of d (axis_apart) or a closest feature
// pair whose distance the exact features_within certifies; a pair neither
// settles takes collide_within_direct (counted in margin_fallbacks).
Contact tetra_within_apart(const BodyPose &a, const BodyPose &b, double d, NarrowScratch &s);

// collide_within for two tetrahedra without a witness request: the axis
// along the line of centres first (apart by more than d: None), then the
// exact touching test (collide_tetra), then tetra_within_apart.
Contact collide_tetra_within(const BodyPose &a, const BodyPose &b, double d, NarrowScratch &s);

}  // namespace tet
}  // namespace hgcd
