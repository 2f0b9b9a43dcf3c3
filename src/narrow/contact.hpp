// What a colliding pair is made of (hgcd_contact of hgcd.h) for pairs the
// exact narrow phase decided: from collide()'s Witness when the path that
// decided recorded one, else worked out here.
#pragma once
#include <cstdint>
#include <vector>

#include "hgcd/hgcd.h"
#include "narrow/ccd_narrow.hpp"
#include "narrow/narrow.hpp"

namespace hgcd {

struct ContactScratch {
    std::vector<double> world_a, world_b;
    NearTriangles near_b;
};

// Fills out (all but out->pair) for a pair collide() reported as `hit`
// (Surface or Containment) with witness w. A witness that was not recorded
// (a path that does not fill it) is found again exactly: a triangle pair that
// meets, or which solid holds the other.
void exact_contact(const BodyPose &a, const BodyPose &b, Contact hit, const Witness &w,
                   ContactScratch &scratch, hgcd_contact *out);

// Fills out (all but out->pair) for a pair libccd reported colliding.
void penetration_contact(const CcdContact &c, hgcd_contact *out);

}  // namespace hgcd
