// A body's box offsets from its mesh's record (world/mesh_pool.hpp): what a
// new orientation costs a body of a small mesh (hgcd_body_set_pose,
// hgcd_world_set_poses, creation).
#pragma once
#include <cstdint>

#include "common/transform.hpp"

namespace hgcd {

// The box [lo, hi] of the offsets 0 + R (s v) of the points v of a record
// (`groups` groups of 4 points: 4 x, 4 y, 4 z), each by transform_point's
// operations with a zero position: the same bits as offset_box on the same
// points in any order. (min and max choose by value alone here: no offset is
// NaN, and none is -0, as 0 + -0 is +0; the padding repeats a point.)
void record_box(const Rotation &r, double s, const double *record, uint32_t groups, double *lo, double *hi);

// The same box rounded outward to float (broad::round_outward's bits):
// off[0..2] the low corner, off[3..5] the high one.
void record_float_box(const Rotation &r, double s, const double *record, uint32_t groups, float *off);

}  // namespace hgcd
