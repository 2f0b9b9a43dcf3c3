// Bodies: creation and destruction in the structure of arrays (world.hpp),
// poses and velocities, and the boxes' offsets that follow a pose.
#include <algorithm>
#include <cmath>
#include <cstring>
#include <string>

#include "broad/float_box.hpp"
#include "common/ieee.hpp"
#include "common/transform.hpp"
#include "world/pose_box.hpp"
#include "world/world.hpp"

namespace hgcd {

namespace {

// Level radius: the largest stretch an accepted quaternion can give is
// 1 + 2e-6 (see rotation_stretch), the offsets' rounding to float adds
// 2^-23 at most; the rest is slack for the rounding of the offsets.
constexpr double kLevelInflation = 1 + 4e-6;

std::string vec_text(const char *name, int k) {
    return std::string(name) + "[" + std::to_string(k) + "]";
}

}  // namespace

int64_t World::live_body(hgcd_body id) const {
    if (id.index >= live_gen_.size() || live_gen_[id.index] == 0 || live_gen_[id.index] != id.generation)
        return -1;
    return id.index;
}

hgcd_status World::check_body(hgcd_body id, const char *what, int64_t *slot) const {
    *slot = live_body(id);
    if (*slot < 0)
        return fail(HGCD_ERROR_STALE_ID, std::string(what) + ": body {" + std::to_string(id.index) +
                                             ", " + std::to_string(id.generation) +
                                             "} is not a live body of this world");
    return HGCD_OK;
}

hgcd_status World::check_pose(const char *what, const double *position,
                              const double *orientation) const {
    if (position)
        for (int k = 0; k < 3; ++k)
            if (!coordinate_ok(position[k]))
                return fail(HGCD_ERROR_INVALID_ARGUMENT,
                            std::string(what) + ": " + vec_text("position", k) +
                                (std::isfinite(position[k]) ? " is beyond 1e15" : " is not finite"));
    if (orientation && !orientation_ok(orientation)) {
        for (int k = 0; k < 4; ++k)
            if (!std::isfinite(orientation[k]))
                return fail(HGCD_ERROR_INVALID_ARGUMENT,
                            std::string(what) + ": " + vec_text("orientation", k) + " is not finite");
        return fail(HGCD_ERROR_INVALID_ARGUMENT,
                    std::string(what) + ": orientation is not a unit quaternion (squared norm " +
                        std::to_string(squared_norm4(orientation)) + ", must be within 1e-6 of 1)");
    }
    return HGCD_OK;
}

// ---------------------------------------------------------------- bodies --

hgcd_status World::create_body(const hgcd_body_desc &d, hgcd_body *out) {
    const int64_t mesh = live_mesh(d.mesh);
    if (mesh < 0) return fail(HGCD_ERROR_STALE_ID, "body_create: desc.mesh is not a live mesh of this world");
    if (hgcd_status s = check_pose("body_create", d.position, d.orientation)) return s;
    for (int k = 0; k < 3; ++k)
        if (!std::isfinite(d.velocity[k]))
            return fail(HGCD_ERROR_INVALID_ARGUMENT, "body_create: " + vec_text("velocity", k) + " is not finite");
    if (!scale_ok(d.scale, meshes_[mesh].reach))
        return fail(HGCD_ERROR_INVALID_ARGUMENT,
                    "body_create: scale must be finite, > 0 and keep the mesh within 1e15 of its position "
                    "(scale * mesh reach <= 1e15)");
    if (d.type != HGCD_BODY_DYNAMIC && d.type != HGCD_BODY_KINEMATIC && d.type != HGCD_BODY_STATIC)
        return fail(HGCD_ERROR_INVALID_ARGUMENT,
                    "body_create: type " + std::to_string(d.type) + " is not HGCD_BODY_DYNAMIC, KINEMATIC or STATIC");
    if (d.filter.reserved != 0) return fail(HGCD_ERROR_INVALID_ARGUMENT, "body_create: filter.reserved is not 0");
    if (!margin_ok(d.margin))
        return fail(HGCD_ERROR_INVALID_ARGUMENT, "body_create: margin must be finite, >= 0 and <= 1e15");
    if (live_bodies_ >= kMaxSlots) return fail(HGCD_ERROR_CAPACITY, "body_create: too many bodies");

    uint32_t slot;
    const bool reuse = !body_free_.empty();
    if (reuse) {
        slot = body_free_.back();
    } else {
        // Reserve everything first (growing geometrically): a failed
        // allocation then changes nothing.
        const size_t n = live_gen_.size() + 1;
        if (live_gen_.capacity() < n) {
            const size_t cap = std::max<size_t>(16, 2 * live_gen_.capacity());
            place_.reserve(cap);
            velocity_.reserve(3 * cap);
            body_mesh_.reserve(cap);
            body_record_.reserve(cap);
            filter_.reserve(cap);
            user_data_.reserve(cap);
            body_gen_.reserve(cap);
            box_off_.reserve(6 * cap);
            r_level_.reserve(cap);
            margin_.reserve(cap);
            point_.reserve(3 * cap);
            at_.reserve(cap);
            moved_at_.reserve(cap);
            slot_of_.reserve(cap);
            stored_gen_.reserve(cap);
            live_gen_.reserve(cap);  // last: its capacity says all are reserved
        }
        // A new slot comes with a new storage index; a freed slot keeps its own.
        slot = uint32_t(live_gen_.size());
        place_.resize(n);
        velocity_.resize(3 * n);
        body_mesh_.resize(n);
        body_record_.resize(n);
        filter_.resize(n);
        user_data_.resize(n);
        body_gen_.resize(n, tag_ << kCounterBits);
        live_gen_.resize(n, 0);
        box_off_.resize(6 * n);
        r_level_.resize(n);
        margin_.resize(n);
        point_.resize(3 * n);
        at_.push_back(slot);
        moved_at_.push_back(1);
        slot_of_.push_back(slot);
        stored_gen_.push_back(0);
    }
    if (reuse) body_free_.pop_back();
    query_.stale = query_.rebuild = true;
    const size_t i = at_[slot];
    moved_at_[i] = 1;
    for (int k = 0; k < 3; ++k) {
        place_[i].position[k] = point_[3 * i + k] = d.position[k];
        velocity_[3 * i + k] = d.velocity[k];
    }
    for (int k = 0; k < 4; ++k) place_[i].orientation[k] = d.orientation[k];
    place_[i].scale = d.scale;
    body_mesh_[i] = uint32_t(mesh);
    body_record_[i] = BodyRecord{pool_.offset(uint32_t(mesh)), pool_.groups(uint32_t(mesh))};
    user_data_[slot] = d.user_data;
    filter_[i] = BodyFilter();  // (counted as plain: set_body_filter counts the body's own)
    BodyFilter f;
    f.category = d.filter.category_bits;
    f.mask = d.filter.mask_bits;
    f.group = d.filter.group_index;
    f.type = uint8_t(d.type);
    f.flags = d.enabled ? 0 : BodyFilter::kDisabled;
    set_body_filter(i, f);
    margin_[i] = d.margin;
    margin_bodies_ += d.margin > 0;
    r_level_[i] = level_radius(i);
    set_box_offsets(i);
    body_gen_[slot] = (tag_ << kCounterBits) | ((body_gen_[slot] + 1) & kCounterMask);
    live_gen_[slot] = body_gen_[slot];
    stored_gen_[i] = body_gen_[slot];
    ++mesh_users_[mesh];
    ++live_bodies_;
    *out = hgcd_body{slot, body_gen_[slot]};
    return HGCD_OK;
}

hgcd_status World::destroy_body(hgcd_body id) {
    int64_t slot;
    if (hgcd_status s = check_body(id, "body_destroy", &slot)) return s;
    if (body_free_.capacity() == body_free_.size()) body_free_.reserve(2 * body_free_.size() + 8);
    if (graves_.capacity() == graves_.size()) graves_.reserve(2 * graves_.size() + 8);
    bury(uint32_t(slot));  // (its user data, for the ended events)
    forget_exclusions(uint32_t(slot));
    set_body_filter(at_[slot], BodyFilter());  // (out of the counts of special bodies)
    margin_bodies_ -= margin_[at_[slot]] > 0;
    margin_[at_[slot]] = 0;
    live_gen_[slot] = 0;
    stored_gen_[at_[slot]] = 0;
    query_.stale = query_.rebuild = true;
    moved_at_[at_[slot]] = 1;  // (its last pairs end)
    if (at_[slot] < mover_.size()) mover_[at_[slot]] |= kDead;  // (the grid may still hold it)
    ++mover_marks_;  // (the movers' lists of residents may hold it)
    --mesh_users_[body_mesh_[at_[slot]]];
    --live_bodies_;
    if ((body_gen_[slot] & kCounterMask) != kCounterMask) body_free_.push_back(uint32_t(slot));
    return HGCD_OK;
}

// (apply_pose_with: world.hpp)
void World::apply_pose(size_t i, const double *p, const double *q) {
    apply_pose_with(i, p, q, [&](const double *) { set_box_offsets(i); });
}

hgcd_status World::set_pose(hgcd_body id, const double *position, const double *orientation) {
    int64_t slot;
    if (hgcd_status s = check_body(id, "body_set_pose", &slot)) return s;
    if (hgcd_status s = check_pose("body_set_pose", position, orientation)) return s;
    apply_pose(at_[slot], position, orientation);
    query_.stale = true;
    // Callers mostly pose their bodies in slot order, while storage follows
    // space: the lines of the slot kPoseAhead on are asked for now, and have
    // arrived by its call (bench_pose, 200k boxes: 220 -> 71 ns a call with
    // a new position, 320 -> 133 with a new orientation; 1 ahead was too
    // late). Callers in another order lose a few needless requests a call.
    constexpr size_t kPoseAhead = 4;
    if (size_t(slot) + kPoseAhead < at_.size()) {
        const size_t n = at_[size_t(slot) + kPoseAhead];
        if (n < place_.size()) {
            __builtin_prefetch(place_.data() + n, 1);
            __builtin_prefetch(point_.data() + 3 * n, 1);
            __builtin_prefetch(box_off_.data() + 6 * n, 1);
            __builtin_prefetch(body_record_.data() + n);
            __builtin_prefetch(body_mesh_.data() + n);
            __builtin_prefetch(moved_at_.data() + n, 1);
        }
    }
    return HGCD_OK;
}

hgcd_status World::set_margin(hgcd_body id, double margin) {
    int64_t slot;
    if (hgcd_status s = check_body(id, "body_set_margin", &slot)) return s;
    if (!margin_ok(margin))
        return fail(HGCD_ERROR_INVALID_ARGUMENT, "body_set_margin: margin must be finite, >= 0 and <= 1e15");
    const size_t i = at_[slot];
    if (std::memcmp(&margin_[i], &margin, sizeof margin) == 0) return HGCD_OK;
    margin_bodies_ += (margin > 0) - (margin_[i] > 0);
    margin_[i] = margin;
    // A new level radius: the grid's cached levels no longer hold (see
    // grid_stale_); its pairs are tested again.
    r_level_[i] = level_radius(i);
    set_box_offsets(i);
    grid_stale_ = true;
    query_.stale = true;
    moved_at_[i] = 1;
    return HGCD_OK;
}

// As set_margin, for every live body at once.
hgcd_status World::set_contact_margin(double margin) {
    if (!margin_ok(margin))
        return fail(HGCD_ERROR_INVALID_ARGUMENT, "world_set_contact_margin: margin must be finite, >= 0 and <= 1e15");
    if (std::memcmp(&world_margin_, &margin, sizeof margin) == 0) return HGCD_OK;
    world_margin_ = margin;
    for (size_t slot = 0; slot < live_gen_.size(); ++slot) {
        if (!live_gen_[slot]) continue;
        const size_t i = at_[slot];
        r_level_[i] = level_radius(i);
        set_box_offsets(i);
        moved_at_[i] = 1;
    }
    grid_stale_ = true;
    query_.stale = true;
    coherent_ = false;  // (every pair's d changed)
    return HGCD_OK;
}

hgcd_status World::get_margin(hgcd_body id, double *out) const {
    const int64_t slot = live_body(id);
    if (slot < 0) return HGCD_ERROR_STALE_ID;
    *out = margin_[at_[slot]];
    return HGCD_OK;
}

hgcd_status World::set_velocity(hgcd_body id, const double *velocity) {
    int64_t slot;
    if (hgcd_status s = check_body(id, "body_set_velocity", &slot)) return s;
    for (int k = 0; k < 3; ++k)
        if (!std::isfinite(velocity[k]))
            return fail(HGCD_ERROR_INVALID_ARGUMENT, "body_set_velocity: " + vec_text("velocity", k) + " is not finite");
    for (int k = 0; k < 3; ++k) velocity_[3 * size_t(at_[slot]) + k] = velocity[k];
    return HGCD_OK;
}

hgcd_status World::get_pose(hgcd_body id, double *position, double *orientation) const {
    const int64_t slot = live_body(id);
    if (slot < 0) return HGCD_ERROR_STALE_ID;
    const Placement &pl = place_[at_[slot]];
    if (position)
        for (int k = 0; k < 3; ++k) position[k] = pl.position[k];
    if (orientation)
        for (int k = 0; k < 4; ++k) orientation[k] = pl.orientation[k];
    return HGCD_OK;
}

hgcd_status World::get_velocity(hgcd_body id, double *velocity) const {
    const int64_t slot = live_body(id);
    if (slot < 0) return HGCD_ERROR_STALE_ID;
    for (int k = 0; k < 3; ++k) velocity[k] = velocity_[3 * size_t(at_[slot]) + k];
    return HGCD_OK;
}

hgcd_status World::get_mesh(hgcd_body id, hgcd_mesh *out) const {
    const int64_t slot = live_body(id);
    if (slot < 0) return HGCD_ERROR_STALE_ID;
    const uint32_t m = body_mesh_[at_[slot]];
    *out = hgcd_mesh{m, mesh_gen_[m]};
    return HGCD_OK;
}

hgcd_status World::get_user_data(hgcd_body id, uint64_t *out) const {
    const int64_t slot = live_body(id);
    if (slot < 0) return HGCD_ERROR_STALE_ID;
    *out = user_data_[slot];
    return HGCD_OK;
}

// Offsets d of the world vertices from the position, by transform_point's
// operations with a zero position (so c + d is the world vertex as every
// path computes it, and fl(c + min d) <= fl(c + d): rounding is monotone),
// rounded outward to float, over the vertices the triangles use (those the
// mesh's bounding sphere, and so r_level, bounds), read from the mesh's
// record (mesh_pool.hpp, pose_box.hpp). Meshes of more triangles than
// Mesh::kExactBoxTriangles have none: they take the cube around their
// bounding sphere instead (a pose set costs no more than a few hundred
// vertex transforms), widened past the rounding of R, cut down to the
// rotated boxes of a few tree nodes where those are tighter.
void World::set_box_offsets(size_t s) {
    if (!float_record_box(s)) return set_box_offsets_general(s);
    const BodyRecord rec = body_record_[s];
    const Placement &pl = place_[s];
    record_float_box(rotation_of(pl.orientation), pl.scale, pool_.blocks()[rec.block].d, rec.groups,
                     &box_off_[6 * s]);
}

void World::set_box_offsets_general(size_t s) {
    const Placement &pl = place_[s];
    const Rotation r = rotation_of(pl.orientation);
    const BodyRecord rec = body_record_[s];
    const double g = box_growth(s);
    double lo[3], hi[3];
    if (rec.groups) {
        record_box(r, pl.scale, pool_.blocks()[rec.block].d, rec.groups, lo, hi);
    } else {
        const Mesh &m = meshes_[body_mesh_[s]];
        const double zero[3] = {0, 0, 0};
        // |R (s v) - R (s c)| <= stretch s radius for every vertex v; each
        // computed offset is within 8 eps (|R| |s v|) of R (s v), |R| <= 2.
        double c[3];
        transform_point(r, zero, pl.scale, m.center, c);
        const double local = std::fabs(m.center[0]) + std::fabs(m.center[1]) + std::fabs(m.center[2]) + m.radius;
        const double reach = pl.scale * (rotation_stretch(pl.orientation) * m.radius + 1e-14 * local);
        for (int k = 0; k < 3; ++k) {
            lo[k] = c[k] - reach * (1 + 1e-12);
            hi[k] = c[k] + reach * (1 + 1e-12);
        }
        // Where tighter, the union of the rotated boxes of the tree's node
        // cut (Mesh::box_cut, pose_box.hpp).
        double cut_lo[3], cut_hi[3];
        cut_box(r, pl.scale, m.box_cut.data(), m.box_cut_nodes, m.box_cut_reach, cut_lo, cut_hi);
        for (int k = 0; k < 3; ++k) {
            lo[k] = std::max(lo[k], cut_lo[k]);
            hi[k] = std::min(hi[k], cut_hi[k]);
        }
    }
    if (g != 0) {
        // (nextafter: the rounded sum is within an ulp of the exact one.)
        for (int k = 0; k < 3; ++k) {
            lo[k] = std::nextafter(lo[k] - g, -INFINITY);
            hi[k] = std::nextafter(hi[k] + g, INFINITY);
        }
    }
    broad::round_outward(lo, hi, &box_off_[6 * s], &box_off_[6 * s + 3]);
}

// The pair margin d = fl(w + fl(m_a + m_b)) is at most (w + m_a + m_b)
// (1 + 2^-52)^2; the growths g_a + g_b >= (w + m_a + m_b)(1 + 2^-48) (w / 2
// is exact but for subnormal w, which the two nextafter steps cover with the
// rounding of the sum), so boxes of a pair within d overlap once each is
// grown by its g. 0 when both margins are 0 (the boxes of today).
double World::box_growth(size_t s) const {
    if (world_margin_ == 0 && margin_bodies_ == 0) return 0;  // (no read of margin_: a cache miss a pose)
    const double m = margin_[s];
    if (world_margin_ == 0 && m == 0) return 0;
    const double g = (world_margin_ * 0.5 + m) * (1 + 0x1p-48);
    return std::nextafter(std::nextafter(g, INFINITY), INFINITY);
}

// A bound on the box offsets' magnitude in any orientation: every vertex is
// within |centre| + radius of the mesh origin, the box grows by
// box_growth; inflated for rounding (kLevelInflation).
double World::level_radius(size_t s) const {
    const Mesh &m = meshes_[body_mesh_[s]];
    const double centre = std::sqrt(m.center[0] * m.center[0] + m.center[1] * m.center[1] + m.center[2] * m.center[2]);
    const double g = box_growth(s);
    const double r = place_[s].scale * (centre + m.radius);
    return (g == 0 ? r : r + g) * kLevelInflation;
}

}  // namespace hgcd
