// The coordinate limits of the contract (hgcd.h, "Coordinate limits"), in the
// one place that checks them. They keep every world-space vertex component
// within about 2e15 (a few parts per million more for a quaternion off unit
// length by the tolerated 1e-6) < 2^51, where the exact predicates' filters
// and the grid's integer cells have room to spare.
#pragma once
#include <cmath>

namespace hgcd {

constexpr double kMaxCoordinate = 1e15;

// A position component, a step's destination, a reflection bound.
inline bool coordinate_ok(double x) { return std::isfinite(x) && std::fabs(x) <= kMaxCoordinate; }

// A vertex's distance from its mesh's origin as the contract defines it:
// sqrt((x * x + y * y) + z * z) in IEEE double, so a caller can compute the
// same bits. Infinite for components past about 1e154 (refused).
inline double vertex_norm(const double *v) { return std::sqrt((v[0] * v[0] + v[1] * v[1]) + v[2] * v[2]); }

inline bool vertex_ok(const double *v) {
    return std::isfinite(v[0]) && std::isfinite(v[1]) && std::isfinite(v[2]) && vertex_norm(v) <= kMaxCoordinate;
}

// A body's scale: the scaled mesh stays within 1e15 of the body's position
// (reach: the largest vertex_norm of the vertices the mesh's triangles use).
inline bool scale_ok(double scale, double reach) {
    return std::isfinite(scale) && scale > 0 && scale * reach <= kMaxCoordinate;
}

// An orientation (x, y, z, w): finite, its squared norm within 1e-6 of 1.
constexpr double kUnitTolerance = 1e-6;
inline double squared_norm4(const double *q) { return ((q[0] * q[0] + q[1] * q[1]) + q[2] * q[2]) + q[3] * q[3]; }
inline bool orientation_ok(const double *q) {
    return std::isfinite(q[0]) && std::isfinite(q[1]) && std::isfinite(q[2]) && std::isfinite(q[3]) &&
           std::fabs(squared_norm4(q) - 1.0) <= kUnitTolerance;
}

// A contact margin (world or body): finite, >= 0 and <= 1e15, so a pair's
// margin (the sum of three) stays below 2^52, where the exact distance
// test's filter is argued (exact/distance.cpp).
inline bool margin_ok(double m) { return std::isfinite(m) && m >= 0 && m <= kMaxCoordinate; }

inline bool position_ok(const double *p) { return coordinate_ok(p[0]) && coordinate_ok(p[1]) && coordinate_ok(p[2]); }

}  // namespace hgcd
