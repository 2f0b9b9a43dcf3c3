#include "world/world.hpp"

#include <omp.h>

#include <algorithm>
#include <atomic>
#include <climits>
#include <cmath>
#include <memory>
#include <new>

#include "narrow/ccd_narrow.hpp"
#include "narrow/contact.hpp"
#include "common/ieee.hpp"
#include "narrow/narrow.hpp"
#include "common/parallel.hpp"
#include "world/permute.hpp"
#include "common/transform.hpp"

namespace hgcd {

namespace {

constexpr uint32_t kCounterBits = 24;
constexpr uint32_t kCounterMask = (1u << kCounterBits) - 1;
constexpr uint32_t kMaxSlots = 0x7FFFFFFEu;
constexpr double kMaxCoordinate = 1e15;
constexpr double kUnitTolerance = 1e-6;
// Level radius: the largest stretch an accepted quaternion can give is
// 1 + 2e-6 (see rotation_stretch), the offsets' rounding to float adds
// 2^-23 at most; the rest is slack for the rounding of the offsets.
constexpr double kLevelInflation = 1 + 4e-6;
// Candidate pairs per unit of the narrow phase's dynamic schedule.
constexpr size_t kNarrowChunk = 512;

// Sorts pair keys (a << 32 | b) ascending: least significant digit first,
// on the keys packed as a << w | b (w the bits of the largest b: 40 bits in
// all for slots below 2^20), kDigit bits a pass, with every pass's counts
// taken in the one pass that packs. (A comparison sort of a tick's pairs
// cost more than the rest of the merge; at tetra 750k, 1 thread, 238 k keys,
// this takes 3.3 ms with 10-bit digits, four passes, where 8-bit digits,
// five passes, took 3.9 and 11-bit digits on the unpacked keys, a count and
// a scatter per pass, about 4.1.)
void sort_keys(std::vector<uint64_t> &keys, std::vector<uint64_t> &tmp) {
    constexpr int kDigit = 10, kBuckets = 1 << kDigit;
    const size_t n = keys.size();
    if (n < 2) return;
    uint64_t high = 0, low = 0;
    for (const uint64_t k : keys) {
        high |= k >> 32;
        low |= uint32_t(k);
    }
    const int w = low ? 64 - __builtin_clzll(low) : 0;
    const int bits = (high ? 64 - __builtin_clzll(high) : 0) + w;
    const int passes = (bits + kDigit - 1) / kDigit;
    if (passes == 0) return;
    std::vector<uint32_t> count(size_t(passes) * kBuckets, 0);
    for (uint64_t &k : keys) {
        k = (k >> 32) << w | uint32_t(k);
        for (int p = 0; p < passes; ++p) ++count[size_t(p) * kBuckets + ((k >> (p * kDigit)) & (kBuckets - 1))];
    }
    tmp.resize(n);
    const uint64_t low_mask = (uint64_t(1) << w) - 1;  // (w < 64)
    for (int p = 0; p < passes; ++p) {
        uint32_t *c = &count[size_t(p) * kBuckets];
        uint32_t at = 0;
        for (int d = 0; d < kBuckets; ++d) {
            const uint32_t m = c[d];
            c[d] = at;
            at += m;
        }
        const int shift = p * kDigit;
        if (p + 1 < passes) {
            for (const uint64_t k : keys) tmp[c[(k >> shift) & (kBuckets - 1)]++] = k;
        } else {  // the last pass unpacks
            for (const uint64_t k : keys)
                tmp[c[(k >> shift) & (kBuckets - 1)]++] = (k >> w) << 32 | (k & low_mask);
        }
        keys.swap(tmp);
    }
}

std::string vec_text(const char *name, int k) {
    return std::string(name) + "[" + std::to_string(k) + "]";
}

int exponent_at_least(double size) {  // smallest e with 2^e >= size
    int k;
    const double m = std::frexp(size, &k);
    return m == 0.5 ? k - 1 : k;
}

int exponent_at_most(double size) {  // largest e with 2^e <= size
    int k;
    std::frexp(size, &k);
    return k - 1;
}

}  // namespace

World::World(const hgcd_world_desc &d)
    : thread_count_(d.thread_count), time_step_(d.time_step), reflect_(d.reflect_at_bounds != 0) {
    // From a count of worlds created, not from an address, so a program that
    // creates its worlds in the same order gets the same ids on every run.
    // An odd multiplier walks all 256 tags before one repeats.
    static std::atomic<uint32_t> worlds_created{0};
    tag_ = (worlds_created.fetch_add(1, std::memory_order_relaxed) * 167u + 0x5Au) & 0xFFu;
    for (int k = 0; k < 3; ++k) {
        bounds_min_[k] = d.bounds_min[k];
        bounds_max_[k] = d.bounds_max[k];
    }
    limits_.min_exponent = d.min_cell_size > 0 ? exponent_at_least(d.min_cell_size) : INT_MIN;
    limits_.max_exponent = d.max_cell_size > 0 ? exponent_at_most(d.max_cell_size) : INT_MAX;
    stats_.struct_size = sizeof(stats_);
    narrow_phase_ = d.narrow_phase;  // checked by hgcd_world_create
    contacts_on_ = d.contacts != 0;
}

hgcd_status World::fail(hgcd_status status, std::string message) const {
    last_error_ = std::move(message);
    return status;
}

int World::threads() const {
    return thread_count_ ? int(thread_count_) : std::max(1, omp_get_num_procs());
}

int64_t World::live_mesh(hgcd_mesh id) const {
    if (id.index >= mesh_alive_.size() || !mesh_alive_[id.index] || mesh_gen_[id.index] != id.generation)
        return -1;
    return id.index;
}

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
            if (!std::isfinite(position[k]) || std::fabs(position[k]) > kMaxCoordinate)
                return fail(HGCD_ERROR_INVALID_ARGUMENT,
                            std::string(what) + ": " + vec_text("position", k) +
                                (std::isfinite(position[k]) ? " is beyond 1e15" : " is not finite"));
    if (orientation) {
        double n2 = 0;
        for (int k = 0; k < 4; ++k) {
            if (!std::isfinite(orientation[k]))
                return fail(HGCD_ERROR_INVALID_ARGUMENT,
                            std::string(what) + ": " + vec_text("orientation", k) + " is not finite");
            n2 += orientation[k] * orientation[k];
        }
        if (!(std::fabs(n2 - 1.0) <= kUnitTolerance))
            return fail(HGCD_ERROR_INVALID_ARGUMENT,
                        std::string(what) + ": orientation is not a unit quaternion (squared norm " +
                            std::to_string(n2) + ", must be within 1e-6 of 1)");
    }
    return HGCD_OK;
}

// ---------------------------------------------------------------- meshes --

hgcd_status World::create_mesh(const hgcd_mesh_desc &d, hgcd_mesh *out) {
    if (!d.vertices) return fail(HGCD_ERROR_NULL_ARGUMENT, "mesh_create: desc.vertices is NULL");
    if (!d.triangles) return fail(HGCD_ERROR_NULL_ARGUMENT, "mesh_create: desc.triangles is NULL");
    if (live_meshes_ >= kMaxSlots) return fail(HGCD_ERROR_CAPACITY, "mesh_create: too many meshes");
    Mesh m;
    std::string error;
    if (!build_mesh(d.vertices, d.vertex_count, d.triangles, d.triangle_count, &m, &error))
        return fail(HGCD_ERROR_INVALID_MESH, "mesh_create: " + error);
    uint32_t slot;
    if (!mesh_free_.empty()) {
        slot = mesh_free_.back();
        meshes_[slot] = std::move(m);
        mesh_free_.pop_back();
    } else {
        slot = uint32_t(meshes_.size());
        const size_t cap = std::max<size_t>(8, 2 * meshes_.size());
        if (meshes_.capacity() <= meshes_.size()) {
            mesh_gen_.reserve(cap);
            mesh_alive_.reserve(cap);
            mesh_users_.reserve(cap);
            mesh_narrow_.reserve(cap);
            meshes_.reserve(cap);
        }
        meshes_.push_back(std::move(m));
        mesh_gen_.push_back(tag_ << kCounterBits);
        mesh_alive_.push_back(0);
        mesh_users_.push_back(0);
        mesh_narrow_.push_back(HGCD_NARROW_WORLD);
    }
    mesh_narrow_[slot] = HGCD_NARROW_WORLD;
    mesh_gen_[slot] = (tag_ << kCounterBits) | ((mesh_gen_[slot] + 1) & kCounterMask);
    mesh_alive_[slot] = 1;
    mesh_users_[slot] = 0;
    ++live_meshes_;
    *out = hgcd_mesh{slot, mesh_gen_[slot]};
    return HGCD_OK;
}

hgcd_status World::destroy_mesh(hgcd_mesh id) {
    const int64_t slot = live_mesh(id);
    if (slot < 0) return fail(HGCD_ERROR_STALE_ID, "mesh_destroy: not a live mesh of this world");
    if (mesh_users_[slot])
        return fail(HGCD_ERROR_MESH_IN_USE, "mesh_destroy: " + std::to_string(mesh_users_[slot]) +
                                                " bodies still use mesh " + std::to_string(slot));
    if (mesh_free_.capacity() == mesh_free_.size()) mesh_free_.reserve(2 * mesh_free_.size() + 8);
    mesh_alive_[slot] = 0;
    meshes_[slot] = Mesh();
    --live_meshes_;
    // A slot whose generation counter would wrap is retired, so no id is reused.
    if ((mesh_gen_[slot] & kCounterMask) != kCounterMask) mesh_free_.push_back(uint32_t(slot));
    return HGCD_OK;
}

hgcd_status World::mesh_info(hgcd_mesh id, hgcd_mesh_info *out) const {
    const int64_t slot = live_mesh(id);
    if (slot < 0) return HGCD_ERROR_STALE_ID;
    const Mesh &m = meshes_[slot];
    hgcd_mesh_info info{};
    info.struct_size = sizeof(info);
    info.vertex_count = m.vertex_count;
    info.triangle_count = m.triangle_count;
    info.closed = m.closed;
    info.convex = m.convex;
    info.component_count = uint32_t(m.component_vertices.size());
    info.degenerate_triangle_count = m.degenerate_count;
    info.body_count = mesh_users_[slot];
    for (int k = 0; k < 3; ++k) info.center[k] = m.center[k];
    info.radius = m.radius;
    info.narrow_phase_setting = mesh_narrow_[slot];
    info.narrow_phase = effective_narrow_phase(uint32_t(slot));
    *out = info;
    return HGCD_OK;
}

// ---------------------------------------------------------- narrow phase --

namespace {

const char *check_narrow_phase(int32_t mode, bool per_mesh, hgcd_status *status) {
    const bool known = mode == HGCD_NARROW_EXACT || mode == HGCD_NARROW_GJK || mode == HGCD_NARROW_MPR ||
                       (per_mesh && mode == HGCD_NARROW_WORLD);
    if (!known) {
        *status = HGCD_ERROR_INVALID_ARGUMENT;
        return per_mesh ? "not HGCD_NARROW_WORLD, EXACT, GJK or MPR" : "not HGCD_NARROW_EXACT, GJK or MPR";
    }
    if ((mode == HGCD_NARROW_GJK || mode == HGCD_NARROW_MPR) && libccd_precision() == 0) {
        *status = HGCD_ERROR_NOT_SUPPORTED;
        return "not built with libccd";
    }
    *status = HGCD_OK;
    return nullptr;
}

// Per mesh slot, what the narrow phase loop reads.
constexpr uint8_t kCcdUse = 1;    // convex and set to GJK or MPR: libccd
constexpr uint8_t kCcdGjk = 2;    // set to GJK
constexpr uint8_t kCcdAsked = 4;  // set to GJK or MPR, convex or not

}  // namespace

hgcd_status World::set_narrow_phase(int32_t mode) {
    hgcd_status s;
    if (const char *why = check_narrow_phase(mode, false, &s))
        return fail(s, "world_set_narrow_phase: " + std::to_string(mode) + ": " + why);
    narrow_phase_ = mode;
    return HGCD_OK;
}

hgcd_status World::set_mesh_narrow_phase(hgcd_mesh id, int32_t mode) {
    const int64_t slot = live_mesh(id);
    if (slot < 0) return fail(HGCD_ERROR_STALE_ID, "mesh_set_narrow_phase: not a live mesh of this world");
    hgcd_status s;
    if (const char *why = check_narrow_phase(mode, true, &s))
        return fail(s, "mesh_set_narrow_phase: " + std::to_string(mode) + ": " + why);
    if ((mode == HGCD_NARROW_GJK || mode == HGCD_NARROW_MPR) && !meshes_[slot].convex)
        return fail(HGCD_ERROR_INVALID_ARGUMENT,
                    "mesh_set_narrow_phase: mesh " + std::to_string(slot) +
                        " is not convex; libccd handles convex meshes only, so it keeps the exact test");
    mesh_narrow_[slot] = int8_t(mode);
    return HGCD_OK;
}

int32_t World::effective_narrow_phase(uint32_t slot) const {
    const int32_t set = mesh_narrow_[slot];
    const int32_t mode = set == HGCD_NARROW_WORLD ? narrow_phase_ : set;
    return meshes_[slot].convex ? mode : HGCD_NARROW_EXACT;
}

// ---------------------------------------------------------------- bodies --

hgcd_status World::create_body(const hgcd_body_desc &d, hgcd_body *out) {
    const int64_t mesh = live_mesh(d.mesh);
    if (mesh < 0) return fail(HGCD_ERROR_STALE_ID, "body_create: desc.mesh is not a live mesh of this world");
    if (hgcd_status s = check_pose("body_create", d.position, d.orientation)) return s;
    for (int k = 0; k < 3; ++k)
        if (!std::isfinite(d.velocity[k]))
            return fail(HGCD_ERROR_INVALID_ARGUMENT, "body_create: " + vec_text("velocity", k) + " is not finite");
    const Mesh &m = meshes_[mesh];
    const double reach = std::fabs(m.center[0]) + std::fabs(m.center[1]) + std::fabs(m.center[2]) + m.radius;
    if (!std::isfinite(d.scale) || !(d.scale > 0) || d.scale * reach > kMaxCoordinate)
        return fail(HGCD_ERROR_INVALID_ARGUMENT,
                    "body_create: scale must be finite, > 0 and keep the mesh within 1e15");
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
            user_data_.reserve(cap);
            body_gen_.reserve(cap);
            box_off_.reserve(6 * cap);
            r_level_.reserve(cap);
            point_.reserve(3 * cap);
            at_.reserve(cap);
            slot_of_.reserve(cap);
            stored_gen_.reserve(cap);
            live_gen_.reserve(cap);  // last: its capacity says all are reserved
        }
        // A new slot comes with a new storage index; a freed slot keeps its own.
        slot = uint32_t(live_gen_.size());
        place_.resize(n);
        velocity_.resize(3 * n);
        body_mesh_.resize(n);
        user_data_.resize(n);
        body_gen_.resize(n, tag_ << kCounterBits);
        live_gen_.resize(n, 0);
        box_off_.resize(6 * n);
        r_level_.resize(n);
        point_.resize(3 * n);
        at_.push_back(slot);
        slot_of_.push_back(slot);
        stored_gen_.push_back(0);
    }
    if (reuse) body_free_.pop_back();
    const size_t i = at_[slot];
    for (int k = 0; k < 3; ++k) {
        place_[i].position[k] = point_[3 * i + k] = d.position[k];
        velocity_[3 * i + k] = d.velocity[k];
    }
    for (int k = 0; k < 4; ++k) place_[i].orientation[k] = d.orientation[k];
    place_[i].scale = d.scale;
    body_mesh_[i] = uint32_t(mesh);
    user_data_[i] = d.user_data;
    // (Every vertex is within |centre| + radius of the mesh origin.)
    const double centre = std::sqrt(m.center[0] * m.center[0] + m.center[1] * m.center[1] + m.center[2] * m.center[2]);
    r_level_[i] = d.scale * (centre + m.radius) * kLevelInflation;
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
    live_gen_[slot] = 0;
    stored_gen_[at_[slot]] = 0;
    --mesh_users_[body_mesh_[at_[slot]]];
    --live_bodies_;
    if ((body_gen_[slot] & kCounterMask) != kCounterMask) body_free_.push_back(uint32_t(slot));
    return HGCD_OK;
}

hgcd_status World::set_pose(hgcd_body id, const double *position, const double *orientation) {
    int64_t slot;
    if (hgcd_status s = check_body(id, "body_set_pose", &slot)) return s;
    if (hgcd_status s = check_pose("body_set_pose", position, orientation)) return s;
    Placement &pl = place_[at_[slot]];
    if (position)
        for (int k = 0; k < 3; ++k) pl.position[k] = point_[3 * size_t(at_[slot]) + k] = position[k];
    if (orientation) {
        for (int k = 0; k < 4; ++k) pl.orientation[k] = orientation[k];
        set_box_offsets(at_[slot]);
    }
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
    *out = user_data_[at_[slot]];
    return HGCD_OK;
}

// ----------------------------------------------------------------- ticks --

// Offsets d of the world vertices from the position, by transform_point's
// operations with a zero position (so c + d is the world vertex as every
// path computes it, and fl(c + min d) <= fl(c + d): rounding is monotone),
// rounded outward to float, over the vertices the triangles use (those the
// mesh's bounding sphere, and so r_level, bounds). Meshes of more triangles
// than kExactBoxTriangles take the cube around their bounding sphere instead
// (a pose set costs no more than a few hundred vertex transforms), widened
// past the rounding of R.
void World::set_box_offsets(size_t s) {
    constexpr uint32_t kExactBoxTriangles = 128;
    const Placement &pl = place_[s];
    const Mesh &m = meshes_[body_mesh_[s]];
    const Rotation r = rotation_of(pl.orientation);
    const double zero[3] = {0, 0, 0};
    double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
    if (m.triangle_count <= kExactBoxTriangles) {
        for (const uint32_t v : m.triangles) {  // (a vertex of several triangles is seen again)
            double d[3];
            transform_point(r, zero, pl.scale, &m.vertices[3 * size_t(v)], d);
            for (int k = 0; k < 3; ++k) {
                lo[k] = std::min(lo[k], d[k]);
                hi[k] = std::max(hi[k], d[k]);
            }
        }
    } else {
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
    }
    float *o = &box_off_[6 * s];
    for (int k = 0; k < 3; ++k) {
        o[k] = float_at_most(lo[k]);
        o[3 + k] = float_at_least(hi[k]);
    }
}

Boxes World::boxes() const { return Boxes{point_.data(), box_off_.data()}; }

// Storage in the grid's sweep order again once two fifths of it are out of
// order (bodies that changed rows since, or the order of creation the first
// time); before the motion, so that it moves storage in order. Not right
// after the grid was rebuilt: its levels may still be settling
// (coarsening), and each new set of levels is a new order; but right after the first detect, whose
// levels come from an estimate that is usually right (grid_limits): the
// first ticks then read in sequence too (on tetra at n = 750000, 1 thread,
// the first two ticks took 525 ms where they took 550: the first tick
// renumbers, 120 ms, and no tick runs on storage out of order), and a world
// detected only once never pays for it. Storage in the order of creation
// costs about 33 ms a tick at tetra 750k (1 thread), while the disorder of
// moves costs little (the tick before a renumbering is 1-2 ms slower than
// the one after); a renumbering costs about 60 ms on 1 thread and 33 on 2,
// so it waits for 40% (every ~40 ticks there; at 20%, every 19 ticks, the
// mean tick over 120 ticks was 1-2 ms longer, at 60% about the same).
void World::renumber_if_disordered() {
    if (!grid_rebuilt_ && grid_.disorder() * 5 > 2 * uint64_t(live_bodies_)) renumber();
}

// The grid's limits for this detect. Coarsening (GridLimits::coarsen) is
// decided from the previous detect's candidate pairs per body, a count that
// does not depend on the grid's shape: below 3 (sparse, as scene tetra at
// its reference density, 1.4) the levels close below the coarsest join it,
// above 6 they part again. On tetra at n = 750000 that takes the tick from
// 322 to 245 ms; in a cube 8 and 23 times denser (11 and 32 candidates per
// body) the paper's finer levels are 2% and 10% faster, so they stay.
//
// Before the first detect there is no count yet: it is estimated from the
// boxes as if their positions were spread evenly over their bounding box
// (estimated_candidates_per_body), which the real count soon corrects.
// Without it the first detect built the finer levels and the first step
// rebuilt the grid coarsened: on tetra at n = 750000 (measured with
// spheres, whose estimate was 1.44 against a count of 1.43) the first
// detect took 360 ms where it took 510, and the first step 235 where it
// took 340 (1 thread).
GridLimits World::grid_limits(int threads) {
    const double per_body = candidates_per_body_ >= 0 ? candidates_per_body_ : estimated_candidates_per_body(threads);
    if (per_body >= 0) coarse_grid_ = coarse_grid_ ? per_body <= 6 : per_body < 3;
    GridLimits limits = limits_;
    limits.coarsen = coarse_grid_;
    return limits;
}

double World::estimated_candidates_per_body(int threads) const {
    const int64_t n = int64_t(stored_gen_.size());
    // Per thread, merged here on the calling thread: an OpenMP reduction
    // would merge the workers' shares after their IeeeMode has ended.
    struct Sums {
        double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
        double a1 = 0, a2 = 0, a3 = 0, count = 0;
    };
    std::vector<Sums> sums(static_cast<size_t>(threads));
#pragma omp parallel num_threads(threads)
    {
        const IeeeMode ieee;
        Sums mine;
#pragma omp for schedule(static) nowait
        for (int64_t s = 0; s < n; ++s) {
            if (!stored_gen_[s]) continue;
            const double *p = &point_[3 * s];
            const float *o = &box_off_[6 * s];
            for (int k = 0; k < 3; ++k) {
                mine.lo[k] = std::min(mine.lo[k], p[k]);
                mine.hi[k] = std::max(mine.hi[k], p[k]);
            }
            // Half the box's mean side.
            const double a = ((double(o[3]) - o[0]) + (double(o[4]) - o[1]) + (double(o[5]) - o[2])) / 6;
            mine.a1 += a;
            mine.a2 += a * a;
            mine.a3 += a * a * a;
            mine.count += 1;
        }
        sums[size_t(omp_get_thread_num())] = mine;
    }
    Sums all;
    for (const Sums &t : sums) {
        for (int k = 0; k < 3; ++k) {
            all.lo[k] = std::min(all.lo[k], t.lo[k]);
            all.hi[k] = std::max(all.hi[k], t.hi[k]);
        }
        all.a1 += t.a1;
        all.a2 += t.a2;
        all.a3 += t.a3;
        all.count += t.count;
    }
    const double a1 = all.a1, a2 = all.a2, a3 = all.a3, count = all.count;
    const double volume = (all.hi[0] - all.lo[0]) * (all.hi[1] - all.lo[1]) * (all.hi[2] - all.lo[2]);
    if (count < 2 || !(volume > 0) || !std::isfinite(volume)) return -1;  // no estimate
    // Cubes of half sides a_i, a_j meet when within a_i + a_j on every
    // axis: (n / V) E[8 (a_i + a_j)^3] / 2 pairs per body.
    const double e1 = a1 / count, e2 = a2 / count, e3 = a3 / count;
    return count / volume * 8 * (e3 + 3 * e2 * e1);
}

hgcd_status World::detect() { return detect_with(false); }

hgcd_status World::detect_with(bool renumbered, const SlotPass *motion) {
    pairs_.clear();
    contacts_.clear();
    contacts_recorded_ = contacts_on_;
    const bool want_contacts = contacts_on_;
    const uint32_t struct_size = stats_.struct_size;
    stats_ = hgcd_stats{};
    stats_.struct_size = struct_size;
    const int T = threads();
    const double t0 = omp_get_wtime();
    const bool first_detect = candidates_per_body_ < 0;
    try {
        if (!renumbered) renumber_if_disordered();
        const uint32_t stored = uint32_t(stored_gen_.size());
        // (On a step that is the world's first detect, grid_limits estimates
        // the density from the positions before this tick's moves, which run
        // inside the update: a heuristic, off by one tick's motion.)
        const GridUpdateStats us = grid_.update(boxes(), r_level_.data(), stored_gen_.data(), stored, grid_limits(T), T, motion);
        grid_rebuilt_ = us.rebuilt && !first_detect;  // (renumber need not wait after the first)
        const double t1 = omp_get_wtime();

        // Kept across detects: a tick's candidates need not grow fresh
        // buffers (and fault in fresh pages) every time.
        std::vector<PairBuffer> &found = candidates_;
        found.resize(size_t(T));
        for (auto &f : found) f.clear();
        grid_.find_pairs(boxes(), T, found);
        // Narrow phase straight over every thread's candidate list, in
        // chunks scheduled dynamically (pairs cost very different amounts).
        struct Chunk {
            uint32_t list;
            size_t begin, end;
        };
        std::vector<Chunk> chunks;
        size_t total = 0;
        for (int t = 0; t < T; ++t) {
            total += found[t].size();
            for (size_t b = 0; b < found[t].size(); b += kNarrowChunk)
                chunks.push_back({uint32_t(t), b, std::min(found[t].size(), b + kNarrowChunk)});
        }
        const double t2 = omp_get_wtime();

        // Narrow phase per mesh (libccd or exact), read only if any is not exact.
        std::vector<uint8_t> ccd_mode(meshes_.size(), 0);
        bool any_ccd = false;
        for (size_t m = 0; m < meshes_.size(); ++m) {
            if (!mesh_alive_[m]) continue;
            const int32_t set = mesh_narrow_[m] == HGCD_NARROW_WORLD ? narrow_phase_ : mesh_narrow_[m];
            if (set != HGCD_NARROW_GJK && set != HGCD_NARROW_MPR) continue;
            ccd_mode[m] = uint8_t(kCcdAsked | (set == HGCD_NARROW_GJK ? kCcdGjk : 0) |
                                  (meshes_[m].convex ? kCcdUse : 0));
            any_ccd = true;
        }
        // Kept across detects, as the candidates: fresh buffers would grow
        // (and fault in pages) every tick.
        std::vector<std::vector<uint64_t>> &hits = hits_;
        hits.resize(size_t(T));
        sort_scratch_.resize(size_t(T));
        for (auto &h : hits) h.clear();
        std::vector<std::vector<hgcd_contact>> hit_contacts(T);  // parallel to hits (contacts on)
        std::vector<uint64_t> containment(T, 0), tri_tests(T, 0), exact(T, 0), ccd_tests(T, 0),
            ccd_fallback(T, 0);
        // Pairs of tetrahedra (without contacts or libccd) go to the batched
        // test a chunk at a time (narrow.hpp), through per-thread arrays on
        // the heap, from before the region (thread 0 runs on the caller's
        // stack).
        const bool batch = !want_contacts && !any_ccd;
        // Every live mesh a tetrahedron: every pair goes to the batch, no
        // mesh need be looked at per pair.
        bool all_tetra = batch;
        for (size_t m = 0; m < meshes_.size() && all_tetra; ++m) all_tetra = !mesh_alive_[m] || meshes_[m].tetra;
        std::unique_ptr<TetraPair[]> batch_pairs(batch ? new TetraPair[size_t(T) * kNarrowChunk] : nullptr);
        std::unique_ptr<Contact[]> batch_verdicts(batch ? new Contact[size_t(T) * kNarrowChunk] : nullptr);
        RegionGuard guard;
#pragma omp parallel num_threads(T)
        {
            const IeeeMode ieee;
            const int me = omp_get_thread_num();
            NarrowScratch scratch;
            CcdScratch ccd_scratch;
            ContactScratch contact_scratch;
            // The thread's hits in a vector of its own stack frame while it
            // pushes (the storage of hits[me], kept across detects): the
            // vectors of hits share cache lines, and every push writes the
            // vector's end.
            std::vector<uint64_t> mine;
            mine.swap(hits[me]);
            std::vector<hgcd_contact> mine_contacts;
            uint64_t my_containment = 0, my_ccd_fallback = 0;
            TetraPair *tetra = batch ? batch_pairs.get() + size_t(me) * kNarrowChunk : nullptr;
            Contact *verdict = batch ? batch_verdicts.get() + size_t(me) * kNarrowChunk : nullptr;
            uint32_t hit_index[kNarrowChunk];
#pragma omp for schedule(dynamic, 1)
            for (int64_t c = 0; c < int64_t(chunks.size()); ++c) guard.run([&] {
                const PairBuffer &list = found[chunks[c].list];
                const size_t end = chunks[c].end;
                size_t tetras = 0;
                if (all_tetra) {
                    const Mesh *meshes = meshes_.data();
                    const Placement *place = place_.data();
                    const uint32_t *body_mesh = body_mesh_.data();
                    for (size_t k = chunks[c].begin; k < end; ++k, ++tetras) {
                        const uint32_t a = uint32_t(list[k] >> 32), b = uint32_t(list[k]);
                        tetra[tetras] = TetraPair{meshes + body_mesh[a], meshes + body_mesh[b], place + a, place + b};
                    }
                }
                for (size_t k = all_tetra ? end : chunks[c].begin; k < end; ++k) {
                    // The meshes of a later pair, to hide the latency, and its
                    // placements unless the batched test will read them (it
                    // asks for them itself: asked for here, 512 pairs before
                    // their use, they held up this loop; tetra 750k, 2
                    // threads, narrow 31.1 -> 29.8 ms).
                    if (k + 8 < end) {
                        const uint64_t ahead = list[k + 8];
                        __builtin_prefetch(&body_mesh_[ahead >> 32]);
                        __builtin_prefetch(&body_mesh_[uint32_t(ahead)]);
                        if (!batch) {
                            __builtin_prefetch(&place_[ahead >> 32]);
                            __builtin_prefetch(&place_[uint32_t(ahead)]);
                        }
                    }
                    // Storage indices. The exact verdict does not depend on
                    // the order of the two bodies, so only contacts (which
                    // follow the pair's order as reported) and libccd (whose
                    // tolerances might) take them in slot order, and only hits
                    // look their slots up (28% of the pairs on tetra).
                    uint32_t a = uint32_t(list[k] >> 32), b = uint32_t(list[k]);
                    if ((want_contacts || any_ccd) && slot_of_[a] > slot_of_[b]) std::swap(a, b);
                    const Placement &la = place_[a], &lb = place_[b];
                    const Mesh *mesh_a = &meshes_[body_mesh_[a]], *mesh_b = &meshes_[body_mesh_[b]];
                    if (batch && mesh_a->tetra && mesh_b->tetra) {
                        tetra[tetras++] = TetraPair{mesh_a, mesh_b, &la, &lb};
                        continue;
                    }
                    const BodyPose pa = pose_of(mesh_a, la), pb = pose_of(mesh_b, lb);
                    Contact hit;
                    hgcd_contact contact;
                    const uint8_t ma = any_ccd ? ccd_mode[body_mesh_[a]] : 0;
                    const uint8_t mb = any_ccd ? ccd_mode[body_mesh_[b]] : 0;
                    if (ma & mb & kCcdUse) {  // both convex and set to libccd
                        const CcdMethod method = ((ma | mb) & kCcdGjk) ? CcdMethod::Gjk : CcdMethod::Mpr;
                        CcdContact cc;
                        hit = ccd_collide(pa, pb, method, ccd_scratch, want_contacts ? &cc : nullptr)
                                  ? Contact::Surface
                                  : Contact::None;
                        if (want_contacts && hit != Contact::None) penetration_contact(cc, &contact);
                    } else if (want_contacts) {
                        if (ma & mb & kCcdAsked) ++my_ccd_fallback;
                        Witness witness;
                        hit = collide(pa, pb, scratch, &witness);
                        if (hit != Contact::None) exact_contact(pa, pb, hit, witness, contact_scratch, &contact);
                    } else {
                        if (ma & mb & kCcdAsked) ++my_ccd_fallback;
                        hit = collide(pa, pb, scratch);
                    }
                    if (hit != Contact::None) {
                        mine.push_back(pair_key(slot_of_[a], slot_of_[b]));
                        if (want_contacts) mine_contacts.push_back(contact);
                        if (hit == Contact::Containment) ++my_containment;
                    }
                }
                if (tetras) collide_tetra_batch(tetra, tetras, verdict, scratch);
                // The hits listed first without a branch (a branch per pair on
                // its verdict mispredicted often: hits are 28% of the pairs).
                size_t hit_count = 0;
                for (size_t k = 0; k < tetras; ++k) {
                    hit_index[hit_count] = uint32_t(k);
                    hit_count += verdict[k] != Contact::None;
                    my_containment += verdict[k] == Contact::Containment;
                }
                const size_t at = mine.size();
                mine.resize(at + hit_count);
                uint64_t *to = mine.data() + at;
                if (all_tetra) {  // (the batch's pairs are the chunk's, in order)
                    const uint64_t *keys = list.begin() + chunks[c].begin;
                    for (size_t h = 0; h < hit_count; ++h) {
                        const uint64_t key = keys[hit_index[h]];
                        to[h] = pair_key(slot_of_[key >> 32], slot_of_[uint32_t(key)]);
                    }
                } else {
                    for (size_t h = 0; h < hit_count; ++h) {
                        const TetraPair &p = tetra[hit_index[h]];
                        to[h] = pair_key(slot_of_[p.a - place_.data()], slot_of_[p.b - place_.data()]);
                    }
                }
            });
            containment[me] = my_containment;
            ccd_fallback[me] = my_ccd_fallback;
            tri_tests[me] = scratch.triangle_tests;
            exact[me] = scratch.exact_tests;
            ccd_tests[me] = ccd_scratch.tests;
            if (want_contacts) guard.run([&] {  // sort the contacts with their keys
                std::vector<uint32_t> order(mine.size());
                for (size_t k = 0; k < order.size(); ++k) order[k] = uint32_t(k);
                std::sort(order.begin(), order.end(), [&](uint32_t x, uint32_t y) { return mine[x] < mine[y]; });
                std::vector<uint64_t> keys(mine.size());
                std::vector<hgcd_contact> sorted(mine.size());
                for (size_t k = 0; k < order.size(); ++k) {
                    keys[k] = mine[order[k]];
                    sorted[k] = mine_contacts[order[k]];
                }
                mine.swap(keys);
                mine_contacts.swap(sorted);
            });
            else guard.run([&] { sort_keys(mine, sort_scratch_[me]); });  // each thread its own share
            hits[me].swap(mine);
            hit_contacts[me].swap(mine_contacts);
        }
        guard.rethrow();
        // Merge the sorted shares: the output is in (a, b) order whatever the
        // thread count, so identical bit for bit. In T parts of the key
        // range at once (splitters from the longest share), each merging
        // its range of every share into its place.
        size_t count = 0, longest = 0;
        for (int t = 0; t < T; ++t) {
            count += hits[t].size();
            if (hits[t].size() > hits[longest].size()) longest = size_t(t);
        }
        pairs_.resize(count);
        if (want_contacts) contacts_.resize(count);
        const int parts = count >= 4096 ? T : 1;
        // first[p * T + t]: where part p starts in share t (p = parts: the end).
        std::vector<size_t> first(size_t(parts + 1) * T), out_at(parts + 1, 0);
        for (int p = 0; p <= parts; ++p) {
            const std::vector<uint64_t> &l = hits[longest];
            // (no pair key is 0 or UINT64_MAX: slots are below 2^31 and a < b)
            const uint64_t splitter = p == 0 ? 0 : p == parts ? UINT64_MAX : l[l.size() * size_t(p) / size_t(parts)];
            for (int t = 0; t < T; ++t) {
                const std::vector<uint64_t> &h = hits[t];
                first[size_t(p) * T + t] = size_t(std::lower_bound(h.begin(), h.end(), splitter) - h.begin());
                out_at[p] += first[size_t(p) * T + t];
            }
        }
#pragma omp parallel num_threads(parts)
        {
            const IeeeMode ieee;
#pragma omp for schedule(static, 1)
            for (int p = 0; p < parts; ++p) guard.run([&] {
                std::vector<size_t> head(T), end(T);
                for (int t = 0; t < T; ++t) {
                    head[t] = first[size_t(p) * T + t];
                    end[t] = first[size_t(p + 1) * T + t];
                }
                for (size_t k = out_at[p]; k < out_at[p + 1]; ++k) {
                    int best = -1;
                    for (int t = 0; t < T; ++t)
                        if (head[t] < end[t] && (best < 0 || hits[t][head[t]] < hits[best][head[best]])) best = t;
                    const size_t at = head[best]++;
                    const uint64_t key = hits[best][at];
                    const uint32_t a = uint32_t(key >> 32), b = uint32_t(key);
                    // The second slots are in no order: ask for a later pair's
                    // generation early.
                    if (at + 16 < end[best]) __builtin_prefetch(&live_gen_[uint32_t(hits[best][at + 16])]);
                    pairs_[k] = hgcd_pair{{a, live_gen_[a]}, {b, live_gen_[b]}};
                    if (want_contacts) {
                        contacts_[k] = hit_contacts[best][at];
                        contacts_[k].pair = pairs_[k];
                    }
                }
            });
        }
        guard.rethrow();
        const double t3 = omp_get_wtime();

        stats_.level_count = grid_.level_count();
        stats_.oversize_count = grid_.oversize_count();
        stats_.thread_count = uint32_t(T);
        stats_.moved_bodies = us.moved;
        stats_.candidate_pairs = uint64_t(total);
        candidates_per_body_ = live_bodies_ ? double(total) / live_bodies_ : -1;
        for (int t = 0; t < T; ++t) {
            stats_.narrow_tests += exact[t];
            stats_.triangle_tests += tri_tests[t];
            stats_.containment_pairs += containment[t];
            stats_.libccd_tests += ccd_tests[t];
            stats_.libccd_fallback_tests += ccd_fallback[t];
        }
        stats_.colliding_pairs = pairs_.size();
        stats_.update_seconds = t1 - t0;
        stats_.broad_seconds = t2 - t1;
        stats_.narrow_seconds = t3 - t2;
        stats_.total_seconds = t3 - t0;
    } catch (...) {
        // The grid may be half updated: drop it, the next detect rebuilds it.
        grid_ = Grid();
        pairs_.clear();
        contacts_.clear();
        stats_ = hgcd_stats{};
        stats_.struct_size = struct_size;
        throw;
    }
    return HGCD_OK;
}

bool World::renumber() {
    const size_t n = stored_gen_.size();
    std::vector<uint32_t> old_of_new, new_of_old;
    std::unique_ptr<unsigned char[]> scratch;
    try {
        old_of_new.reserve(n);
        new_of_old.resize(n);
        scratch.reset(new unsigned char[kPermuteScratch * std::max<size_t>(n, 1)]);
        // The grid may need to grow its per-slot arrays (slots made since
        // the last detect); after this nothing below allocates.
        grid_.reserve_slots(n);
    } catch (const std::bad_alloc &) {
        return false;  // renumbering only saves time; nothing has changed
    }
    // The grid's order (as of the last detect), then everything else:
    // bodies made since, and free storage. new_of_old marks what is placed.
    grid_.order(old_of_new);
    std::fill(new_of_old.begin(), new_of_old.end(), UINT32_MAX);
    size_t placed = 0;
    for (const uint32_t i : old_of_new)
        if (new_of_old[i] == UINT32_MAX) {
            new_of_old[i] = uint32_t(placed);
            old_of_new[placed++] = i;
        }
    old_of_new.resize(placed);
    for (size_t i = 0; i < n; ++i)
        if (new_of_old[i] == UINT32_MAX) {
            new_of_old[i] = uint32_t(old_of_new.size());
            old_of_new.push_back(uint32_t(i));
        }
    // Every per-storage array, one after the other (placements in halves:
    // the scratch holds kPermuteScratch bytes a body), all threads on each.
    const uint32_t *perm = old_of_new.data();
    void *tmp = scratch.get();
#pragma omp parallel num_threads(threads())
    {
        grid_.renumber(old_of_new, new_of_old, tmp);
        static_assert(sizeof(Placement) == 2 * kPermuteScratch, "placements move in two halves");
        permute_part<kPermuteScratch>(place_.data(), sizeof(Placement), perm, n, tmp);
        permute_part<kPermuteScratch>(reinterpret_cast<unsigned char *>(place_.data()) + kPermuteScratch,
                                      sizeof(Placement), perm, n, tmp);
        permute_records<3>(velocity_.data(), perm, n, tmp);
        permute_records<3>(point_.data(), perm, n, tmp);
        permute_records<6>(box_off_.data(), perm, n, tmp);
        permute_records<1>(user_data_.data(), perm, n, tmp);
        permute_records<1>(r_level_.data(), perm, n, tmp);
        permute_records<1>(body_mesh_.data(), perm, n, tmp);
        permute_records<1>(stored_gen_.data(), perm, n, tmp);
        permute_records<1>(slot_of_.data(), perm, n, tmp);
#pragma omp for schedule(static)
        for (int64_t k = 0; k < int64_t(n); ++k) at_[slot_of_[k]] = uint32_t(k);
    }
    return true;
}

namespace {

// One tick's motion, applied a range of slots at a time (a SlotPass).
struct Motion {
    bool reflect;
    double dt, lo[3], hi[3];
    Placement *place;
    double *velocity, *point;
    const uint32_t *live;
    uint32_t count;  // of storage
    std::atomic<bool> applied{false};  // some range has moved

    static void run(void *context, uint32_t begin, uint32_t end) {
        Motion &m = *static_cast<Motion *>(context);
        if (!m.applied.load(std::memory_order_relaxed)) m.applied.store(true, std::memory_order_relaxed);
        // Locals, so the compiler need not reload them after each store.
        const bool reflect = m.reflect;
        const double dt = m.dt, lo[3] = {m.lo[0], m.lo[1], m.lo[2]}, hi[3] = {m.hi[0], m.hi[1], m.hi[2]};
        Placement *place = m.place;
        double *velocity = m.velocity, *point = m.point;
        for (uint32_t s = begin; s < end; ++s) {
            // The placement 16 bodies on (past this range too: the thread's
            // next range follows it): the hardware's prefetch left the
            // motion waiting on every placement line (tetra 750k, 1 thread:
            // grid update 24.9 -> 22.8 ms; asking for the velocities and
            // points as well gained nothing more).
            if (s + 16 < m.count) __builtin_prefetch(&place[s + 16], 1);
            if (!m.live[s]) continue;
            for (int k = 0; k < 3; ++k) {
                double &c = place[s].position[k];
                double &v = velocity[3 * size_t(s) + k];
                double x = c + v * dt;
                if (reflect) {
                    if (x < lo[k]) {
                        x = 2 * lo[k] - x;
                        v = -v;
                    } else if (x > hi[k]) {
                        x = 2 * hi[k] - x;
                        v = -v;
                    }
                    // A move longer than the box is clamped rather than leaving it.
                    x = std::min(std::max(x, lo[k]), hi[k]);
                }
                c = point[3 * size_t(s) + k] = x;
            }
        }
    }
};

}  // namespace

hgcd_status World::step() {
    const int T = threads();
    const double t0 = omp_get_wtime();
    const int64_t n = int64_t(stored_gen_.size());
    const double dt = time_step_;
    // Unless the world reflects (every move then ends inside its box), first
    // check that every move stays finite and in range, then move: a refused
    // step moves nothing.
    if (!reflect_) {
        int64_t bad = -1;  // the largest slot of a body that would leave
#pragma omp parallel num_threads(T) reduction(max : bad)
        {
            const IeeeMode ieee;  // (the moves' own arithmetic)
#pragma omp for schedule(static)
            for (int64_t s = 0; s < n; ++s) {
                if (!stored_gen_[s]) continue;
                for (int k = 0; k < 3; ++k) {
                    const double x = point_[3 * s + k] + velocity_[3 * s + k] * dt;
                    if (!std::isfinite(x) || std::fabs(x) > kMaxCoordinate)
                        bad = std::max(bad, int64_t(slot_of_[s]));
                }
            }
        }
        if (bad >= 0)
            return fail(HGCD_ERROR_INVALID_ARGUMENT, "world_step: body " + std::to_string(bad) +
                                                         " would leave the coordinate range (|x| <= 1e15)");
    }
    renumber_if_disordered();  // (before the motion: it then moves storage in order)
    // The moves run inside the grid update's census, a range of slots at a
    // time right before it reads their points (Grid::update), so those are
    // read while in cache: tetra 750k, motion + update 32.2 -> 31.1 ms on 1
    // thread, 18.1 -> 16.9 ms on 2.
    Motion motion;
    motion.reflect = reflect_;
    motion.dt = dt;
    for (int k = 0; k < 3; ++k) {
        motion.lo[k] = bounds_min_[k];
        motion.hi[k] = bounds_max_[k];
    }
    motion.place = place_.data();
    motion.velocity = velocity_.data();
    motion.point = point_.data();
    motion.live = stored_gen_.data();
    motion.count = uint32_t(n);
    const SlotPass pass{&Motion::run, &motion};
    const double motion_seconds = omp_get_wtime() - t0;
    hgcd_status s;
    try {
        s = detect_with(true, &pass);
    } catch (...) {
        // Failed before its census began: the motion is still owed.
        if (!motion.applied.load(std::memory_order_relaxed)) Motion::run(&motion, 0, uint32_t(n));
        throw;
    }
    stats_.motion_seconds = motion_seconds;
    stats_.total_seconds += motion_seconds;
    return s;
}

}  // namespace hgcd
