// A body's box offsets from its mesh's record (world/mesh_pool.hpp): what a
// new orientation costs a body of a small mesh (hgcd_body_set_pose,
// hgcd_world_set_poses, creation).
#pragma once
#include <cstddef>
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

// The box [lo, hi] holding the offsets 0 + R (s v) that transform_point
// computes for every vertex v under a mesh's box cut (Mesh::box_cut: rows
// of `count` nodes, count a multiple of 4, centres x y z then half widths
// x y z; reach[k] >= |centre_k| + half_k of every node): the union of the
// nodes' rotated boxes, widened past the roundings (pose_box.cpp).
void cut_box(const Rotation &r, double s, const double *cut, size_t count, const double *reach, double *lo,
             double *hi);

// One body's part in record_float_boxes4: its orientation (x y z w) and
// scale, its mesh's record of `groups` groups (at least 1), and where its
// offsets go.
struct BoxJob {
    const double *orientation;
    double scale;
    const double *record;
    uint32_t groups;
    float *off;
};

// record_float_box for four bodies at once, the same bits for each (a
// set_poses with many new orientations: one lane a body, where one body's
// points fill the lanes only for meshes of 4 or more distinct vertices and
// the lanes' reduction cost as much as the transforms). stream: when the
// four bodies' offsets lie one after the other, 16-byte aligned, they are
// written in streaming stores (a pass writing storage in sequence; it
// fences them).
void record_float_boxes4(const BoxJob *job, bool stream = false);

// The boxes of one thread's run of new orientations, four at a time: push
// a body (its box is written at once or by a later push), flush at the end
// (the last few, padded with copies of the last: same offsets, written twice).
struct BoxQueue {
    BoxJob job[4];
    int count = 0;
    bool stream = false;  // (record_float_boxes4's)
    void push(const BoxJob &j) {
        job[count++] = j;
        if (count == 4) {
            record_float_boxes4(job, stream);
            count = 0;
        }
    }
    void flush() {
        if (count == 0) return;
        for (int k = count; k < 4; ++k) job[k] = job[count - 1];
        record_float_boxes4(job, stream);
        count = 0;
    }
};

}  // namespace hgcd
