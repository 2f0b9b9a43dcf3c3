// Exact axis-aligned boxes of the narrow phase: 6 doubles, min xyz then max
// xyz. Every comparison is exact, so a box test only ever prunes pairs that
// cannot share a point (touching boxes are not disjoint).
#pragma once
#include <algorithm>
#include <cstddef>
#include <cstdint>

namespace hgcd {

inline bool boxes_disjoint(const double *a, const double *b) {
    return a[3] < b[0] || b[3] < a[0] || a[4] < b[1] || b[4] < a[1] || a[5] < b[2] || b[5] < a[2];
}

// The boxes are farther apart than d (>= 0) along some axis, so no point of
// one is within d of a point of the other. Exact: rounding is monotone, so a
// rounded gap fl(lo - hi) > d implies the exact gap lo - hi > d.
inline bool boxes_apart(const double *a, const double *b, double d) {
    return b[0] - a[3] > d || a[0] - b[3] > d || b[1] - a[4] > d || a[1] - b[4] > d || b[2] - a[5] > d ||
           a[2] - b[5] > d;
}

inline bool point_in_box(const double *p, const double *box) {
    return p[0] >= box[0] && p[0] <= box[3] && p[1] >= box[1] && p[1] <= box[4] && p[2] >= box[2] &&
           p[2] <= box[5];
}

// The box of triangle t (3 vertex indices) of the vertices v (3 per vertex).
inline void triangle_box(const double *v, const uint32_t *t, double *box) {
    const double *p = &v[3 * size_t(t[0])], *q = &v[3 * size_t(t[1])], *r = &v[3 * size_t(t[2])];
    for (int k = 0; k < 3; ++k) {
        box[k] = std::min(std::min(p[k], q[k]), r[k]);
        box[3 + k] = std::max(std::max(p[k], q[k]), r[k]);
    }
}

}  // namespace hgcd
