// Which pairs are considered at all: body types, filters (Box2D v3's
// b2Filter semantics), and what the world keeps of them per body. The
// tests here are what a scene query reuses to filter its bodies too.
#pragma once
#include <cstdint>

#include "hgcd/hgcd.h"

namespace hgcd {

// Box2D v3's b2ShouldShapesCollide: the same non-zero group decides alone
// (positive: collide, negative: never); otherwise each mask must accept the
// other's category. Symmetric.
inline bool filters_accept(uint64_t category_a, uint64_t mask_a, int32_t group_a, uint64_t category_b,
                           uint64_t mask_b, int32_t group_b) {
    if (group_a == group_b && group_a != 0) return group_a > 0;
    return (mask_a & category_b) != 0 && (category_a & mask_b) != 0;
}
inline bool filters_accept(const hgcd_filter &a, const hgcd_filter &b) {
    return filters_accept(a.category_bits, a.mask_bits, a.group_index, b.category_bits, b.mask_bits,
                          b.group_index);
}

// Whether a pair of these body types (enum hgcd_body_type) is considered:
// any pair with a dynamic body; two static bodies never; otherwise (a
// kinematic body with a kinematic or static one) when the world asks.
inline bool types_accept(uint8_t type_a, uint8_t type_b, bool kinematic_pairs) {
    if (type_a == HGCD_BODY_DYNAMIC || type_b == HGCD_BODY_DYNAMIC) return true;
    if (type_a == HGCD_BODY_STATIC && type_b == HGCD_BODY_STATIC) return false;
    return kinematic_pairs;
}

// What the world keeps per body (by storage index) for the filter pass
// before the narrow phase: 24 bytes, read for both bodies of a candidate.
struct BodyFilter {
    uint64_t category = 1, mask = ~uint64_t(0);
    int32_t group = 0;
    uint8_t type = HGCD_BODY_DYNAMIC;
    uint8_t flags = 0;  // kDisabled, kExcluded
    uint16_t unused = 0;

    static constexpr uint8_t kDisabled = 1;  // out of the grid and every pair
    static constexpr uint8_t kExcluded = 2;  // in at least one excluded pair

    // A body every pair of two plain bodies accepts: when every live body is
    // plain, the filter pass is skipped.
    bool plain() const {
        return category == 1 && mask == ~uint64_t(0) && group == 0 && type == HGCD_BODY_DYNAMIC && flags == 0;
    }
    // A static body otherwise plain: with only such special bodies, a pair
    // is refused exactly when both bodies are static.
    bool plain_static() const {
        return category == 1 && mask == ~uint64_t(0) && group == 0 && type == HGCD_BODY_STATIC && flags == 0;
    }
    hgcd_filter filter() const { return hgcd_filter{category, mask, group, 0}; }
};
static_assert(sizeof(BodyFilter) == 24, "three 8-byte records for the renumbering");

// Whether the pair of bodies a, b passes enabling, the types and the
// filters (the excluded pairs are looked up separately, for bodies flagged
// kExcluded). A full detect never meets a disabled body (the grid leaves
// them out); a search around the moved bodies alone may.
inline bool pair_accepted(const BodyFilter &a, const BodyFilter &b, bool kinematic_pairs) {
    return !((a.flags | b.flags) & BodyFilter::kDisabled) && types_accept(a.type, b.type, kinematic_pairs) &&
           filters_accept(a.category, a.mask, a.group, b.category, b.mask, b.group);
}

}  // namespace hgcd
