// Optional narrow phase through libccd for pairs of convex meshes: GJK or MPR
// on the convex hulls of the two bodies' world vertices, and for contacts the
// penetration estimate (EPA after GJK, or MPR's). Not exact: see enum
// hgcd_narrow_phase in hgcd.h for the tolerance and what it means.
//
// Built only with libccd (HGCD_HAVE_CCD, set by meson and the Makefile when
// they find it). Without it the declarations below get inline definitions that are
// never reached: every request for GJK or MPR is refused before a detect.
#pragma once
#include <cstdint>
#include <vector>

#include "narrow/narrow.hpp"

namespace hgcd {

enum class CcdMethod : uint8_t { Gjk, Mpr };

// libccd's penetration estimate of a colliding pair: translating b by
// depth * normal separates the hulls (up to libccd's tolerance).
struct CcdContact {
    double depth = 0;
    double normal[3] = {0, 0, 0};  // unit, or zero when libccd gave none
    double point[3] = {0, 0, 0};   // world coordinates
};

// Per-thread buffers.
struct CcdScratch {
    std::vector<double> world_a, world_b;  // world_vertices() of each body
    std::vector<float> single_a, single_b;  // libccd in single precision only
    uint64_t tests = 0;                     // pairs handed to libccd
};

#ifdef HGCD_HAVE_CCD

// 1: libccd was compiled with ccd_real_t = float (CCD_SINGLE), 2: double.
int libccd_precision();

// True if libccd's GJK or MPR says the convex hulls of the world vertices of
// a and b intersect (pairs whose exact vertex boxes are disjoint are refused
// first, without libccd). With contact != nullptr and a hit, also fills the
// penetration estimate; the yes/no answer is the same either way. Throws
// std::bad_alloc if libccd runs out of memory.
bool ccd_collide(const BodyPose &a, const BodyPose &b, CcdMethod method, CcdScratch &scratch,
                 CcdContact *contact);

#else

inline int libccd_precision() { return 0; }
inline bool ccd_collide(const BodyPose &, const BodyPose &, CcdMethod, CcdScratch &, CcdContact *) {
    return false;
}

#endif

}  // namespace hgcd
