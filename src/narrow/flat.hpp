// Pairs of small meshes whose exact boxes meet in a flat region: faces,
// edges or corners resting exactly on each other at one coordinate (stacked
// axis-aligned boxes, a body on a floor, cubes side by side on a grid).
// Internal to src/narrow (narrow.cpp calls it).
#pragma once
#include "narrow/narrow.hpp"

namespace hgcd {

// The meshes' world vertices wa, wb (world_vertices) and their exact boxes,
// which meet (boxes_disjoint is false). When the two boxes meet in a plane
// x_k = c that is an end of both boxes' ranges along k, every point the
// solids share lies in that plane, and decides exactly whether they share
// one: 1 yes (their surfaces meet), 0 no. -1 when no such plane exists (the
// caller goes on as before). Each mesh at most kBvhMinTriangles triangles.
int flat_contact(const Mesh &ma, const double *wa, const double *box_a, const Mesh &mb, const double *wb,
                 const double *box_b);

}  // namespace hgcd
