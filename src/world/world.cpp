// The world's construction, ids and meshes, and the narrow phase settings.
// Bodies and poses: bodies.cpp; a tick's motion and the renumbering of
// storage: motion.cpp; detection: detect.cpp.
#include "world/world.hpp"

#include <omp.h>

#include <algorithm>
#include <atomic>
#include <climits>
#include <cmath>

#include "common/ieee.hpp"
#include "narrow/ccd_narrow.hpp"

namespace hgcd {

namespace {

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

}  // namespace

World::World(const hgcd_world_desc &d)
    : thread_count_(d.thread_count),
      adaptive_threads_(d.thread_policy == HGCD_THREADS_ADAPTIVE && !d.enqueue_task),
      tasks_{d.enqueue_task, d.finish_task, d.task_context},
      time_step_(d.time_step), reflect_(d.reflect_at_bounds != 0) {
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
    kinematic_pairs_ = d.kinematic_pairs != 0;
    world_margin_ = d.contact_margin;
}

hgcd_status World::fail(hgcd_status status, std::string message) const {
    last_error_ = std::move(message);
    return status;
}

int World::full_threads() const {
    return thread_count_ ? int(thread_count_) : std::max(1, omp_get_num_procs());
}

int World::threads() const { return adaptive_threads_ ? governor_.threads(full_threads()) : full_threads(); }

int64_t World::live_mesh(hgcd_mesh id) const {
    if (id.index >= mesh_alive_.size() || !mesh_alive_[id.index] || mesh_gen_[id.index] != id.generation)
        return -1;
    return id.index;
}

// ---------------------------------------------------------------- meshes --

// A hash of a mesh's vertex and triangle arrays (sat_slot_): FNV-1a's step
// on 64-bit words (the triangles' indices two at a time), each product's
// high half folded into its low one so every bit reaches the buckets.
static uint64_t sat_key(const Mesh &m) {
    uint64_t h = 0xcbf29ce484222325ull;
    const auto mix = [&h](uint64_t w) {
        h = (h ^ w) * 0x100000001b3ull;
        h ^= h >> 32;
    };
    for (double x : m.vertices) {
        uint64_t w;
        std::memcpy(&w, &x, sizeof w);
        mix(w);
    }
    const size_t n = m.triangles.size();
    for (size_t i = 0; i + 1 < n; i += 2) mix(uint64_t(m.triangles[i]) << 32 | m.triangles[i + 1]);
    if (n % 2) mix(m.triangles[n - 1]);
    return h;
}

hgcd_status World::create_mesh(const hgcd_mesh_desc &d, hgcd_mesh *out) {
    if (!d.vertices) return fail(HGCD_ERROR_NULL_ARGUMENT, "mesh_create: desc.vertices is NULL");
    if (!d.triangles) return fail(HGCD_ERROR_NULL_ARGUMENT, "mesh_create: desc.triangles is NULL");
    if (live_meshes_ >= kMaxSlots) return fail(HGCD_ERROR_CAPACITY, "mesh_create: too many meshes");
    // A live mesh of the same arrays lends its SatData (sat_slot_).
    uint64_t key = 0;
    bool keyed = false;  // (the key worked out once, for the lookup and the entry below)
    const auto same = [this, &key, &keyed](const Mesh &m) -> SatRef {
        key = sat_key(m);
        keyed = true;
        const auto found = sat_slot_.find(key);
        if (found == sat_slot_.end()) return SatRef();
        const Mesh &o = meshes_[found->second];
        if (o.vertex_count != m.vertex_count || o.triangle_count != m.triangle_count ||
            std::memcmp(o.vertices.data(), m.vertices.data(), m.vertices.size() * sizeof(double)) ||
            std::memcmp(o.triangles.data(), m.triangles.data(), m.triangles.size() * sizeof(uint32_t)))
            return SatRef();
        return o.sat;
    };
    Mesh m;
    std::string error;
    if (!build_mesh(d.vertices, d.vertex_count, d.triangles, d.triangle_count, &m, &error, same, tetra_sat_,
                    threads()))
        return fail(HGCD_ERROR_INVALID_MESH, "mesh_create: " + error);
    uint32_t slot = mesh_free_.empty() ? uint32_t(meshes_.size()) : mesh_free_.back();
    pool_.reserve(slot, m);  // (may throw: nothing has changed yet)
    if (!mesh_free_.empty()) {
        meshes_[slot] = std::move(m);
        mesh_free_.pop_back();
    } else {
        const size_t cap = std::max<size_t>(8, 2 * meshes_.size());
        if (meshes_.capacity() <= meshes_.size()) {
            mesh_gen_.reserve(cap);
            mesh_alive_.reserve(cap);
            mesh_users_.reserve(cap);
            mesh_narrow_.reserve(cap);
            mesh_sat_.reserve(cap);
            meshes_.reserve(cap);
        }
        meshes_.push_back(std::move(m));
        mesh_gen_.push_back(tag_ << kCounterBits);
        mesh_alive_.push_back(0);
        mesh_users_.push_back(0);
        mesh_narrow_.push_back(HGCD_NARROW_WORLD);
        mesh_sat_.push_back(nullptr);
    }
    mesh_narrow_[slot] = HGCD_NARROW_WORLD;
    mesh_sat_[slot] = meshes_[slot].sat.get();
    pool_.add(slot, meshes_[slot]);
    mesh_gen_[slot] = (tag_ << kCounterBits) | ((mesh_gen_[slot] + 1) & kCounterMask);
    mesh_alive_[slot] = 1;
    mesh_users_[slot] = 0;
    ++live_meshes_;
    tetra_meshes_ += meshes_[slot].tetra;
    sat_meshes_ += bool(meshes_[slot].sat) && !meshes_[slot].tetra;
    if (meshes_[slot].sat) {
        try {
            sat_slot_.emplace(keyed ? key : sat_key(meshes_[slot]), slot);  // (kept for the first: only an economy)
        } catch (const std::bad_alloc &) {
        }
    }
    if (!tetra_sat_ && meshes_[slot].sat && !meshes_[slot].tetra) {
        // The first small convex mesh other than a tetrahedron: from now on
        // tetrahedra get their SatData too, those built before now, so that
        // their pairs with it take the convex path. Out of memory leaves some
        // without: their pairs take the general path, with the same answers.
        tetra_sat_ = true;
        try {
            for (size_t k = 0; k < meshes_.size(); ++k)
                if (mesh_alive_[k] && meshes_[k].tetra && !meshes_[k].sat) {
                    add_tetra_sat(meshes_[k], same);
                    mesh_sat_[k] = meshes_[k].sat.get();
                    if (meshes_[k].sat) sat_slot_.emplace(sat_key(meshes_[k]), uint32_t(k));
                }
        } catch (const std::bad_alloc &) {
        }
    }
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
    tetra_meshes_ -= meshes_[slot].tetra;
    sat_meshes_ -= bool(meshes_[slot].sat) && !meshes_[slot].tetra;
    if (meshes_[slot].sat) {
        const auto at = sat_slot_.find(sat_key(meshes_[slot]));
        if (at != sat_slot_.end() && at->second == uint32_t(slot)) sat_slot_.erase(at);
    }
    meshes_[slot] = Mesh();
    mesh_sat_[slot] = nullptr;
    if (pool_.remove(uint32_t(slot))) refresh_records();  // (the pool closed its holes)
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
    info.reach = m.reach;
    info.narrow_phase_setting = mesh_narrow_[slot];
    info.narrow_phase = effective_narrow_phase(uint32_t(slot));
    *out = info;
    return HGCD_OK;
}

// ---------------------------------------------------------- narrow phase --

hgcd_status World::set_narrow_phase(int32_t mode) {
    hgcd_status s;
    if (const char *why = check_narrow_phase(mode, false, &s))
        return fail(s, "world_set_narrow_phase: " + std::to_string(mode) + ": " + why);
    narrow_phase_ = mode;
    coherent_ = false;  // (a pair's test, and so its result, may change)
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
    coherent_ = false;
    return HGCD_OK;
}

int32_t World::effective_narrow_phase(uint32_t slot) const {
    const int32_t set = mesh_narrow_[slot];
    const int32_t mode = set == HGCD_NARROW_WORLD ? narrow_phase_ : set;
    return meshes_[slot].convex ? mode : HGCD_NARROW_EXACT;
}

}  // namespace hgcd
