// The C ABI: argument checks, descriptor checks and exception-to-status
// translation. No logic lives here; the world does the work.
#include <cmath>
#include <cstring>
#include <new>

#include "narrow/ccd_narrow.hpp"
#include "hgcd/hgcd.h"
#include "common/ieee.hpp"
#include "common/tags.hpp"
#include "world/world.hpp"

struct hgcd_world {
    hgcd::World impl;
    explicit hgcd_world(const hgcd_world_desc &d) : impl(d) {}
};

namespace {

// Records a refusal on the world and returns its status, without ever
// throwing: composing the message needs memory, and an exception must not
// leave an extern "C" function. If the message cannot be built, the fixed
// text "out of memory" (13 characters: it fits std::string's inline buffer, so
// it needs no allocation) is recorded with the original status.
hgcd_status refuse(hgcd_world *w, hgcd_status status, const char *what, const char *detail) noexcept {
    try {
        return w->impl.fail(status, std::string(what) + ": " + detail);
    } catch (...) {
        try {
            return w->impl.fail(status, std::string("out of memory"));
        } catch (...) {
            return status;
        }
    }
}

// Runs f in IEEE's default floating-point mode, turning exceptions into
// statuses (and messages when there is a world).
template <class F>
hgcd_status guarded(hgcd_world *w, const char *what, F &&f) noexcept {
    const hgcd::IeeeMode ieee;  // (ieee.hpp)
    const hgcd::TaskSystem::Attach tasks(w ? w->impl.task_system() : nullptr);  // (parallel.hpp)
    try {
        return f();
    } catch (const std::bad_alloc &) {
        return w ? refuse(w, HGCD_ERROR_OUT_OF_MEMORY, what, "out of memory") : HGCD_ERROR_OUT_OF_MEMORY;
    } catch (const std::exception &e) {
        return w ? refuse(w, HGCD_ERROR_INTERNAL, what, e.what()) : HGCD_ERROR_INTERNAL;
    } catch (...) {
        return w ? refuse(w, HGCD_ERROR_INTERNAL, what, "unknown exception") : HGCD_ERROR_INTERNAL;
    }
}

template <class D>
bool initialised(const D *d) {
    return d->struct_size == sizeof(D) && d->init_tag == hgcd::kInitTag;
}

}  // namespace

extern "C" {

const char *hgcd_status_string(hgcd_status s) {
    switch (s) {
        case HGCD_OK: return "HGCD_OK";
        case HGCD_ERROR_NULL_ARGUMENT: return "HGCD_ERROR_NULL_ARGUMENT";
        case HGCD_ERROR_INVALID_ARGUMENT: return "HGCD_ERROR_INVALID_ARGUMENT";
        case HGCD_ERROR_BAD_DESCRIPTOR: return "HGCD_ERROR_BAD_DESCRIPTOR";
        case HGCD_ERROR_STALE_ID: return "HGCD_ERROR_STALE_ID";
        case HGCD_ERROR_INVALID_MESH: return "HGCD_ERROR_INVALID_MESH";
        case HGCD_ERROR_MESH_IN_USE: return "HGCD_ERROR_MESH_IN_USE";
        case HGCD_ERROR_OUT_OF_MEMORY: return "HGCD_ERROR_OUT_OF_MEMORY";
        case HGCD_ERROR_CAPACITY: return "HGCD_ERROR_CAPACITY";
        case HGCD_ERROR_NOT_SUPPORTED: return "HGCD_ERROR_NOT_SUPPORTED";
        case HGCD_ERROR_INTERNAL: return "HGCD_ERROR_INTERNAL";
        default: return "HGCD_ERROR_UNKNOWN";
    }
}

uint32_t hgcd_version(void) {
    return (uint32_t(HGCD_VERSION_MAJOR) << 16) | (uint32_t(HGCD_VERSION_MINOR) << 8) |
           uint32_t(HGCD_VERSION_PATCH);
}

#define HGCD_STR2(x) #x
#define HGCD_STR(x) HGCD_STR2(x)
const char *hgcd_version_string(void) {
    return HGCD_STR(HGCD_VERSION_MAJOR) "." HGCD_STR(HGCD_VERSION_MINOR) "." HGCD_STR(HGCD_VERSION_PATCH);
}

// ----------------------------------------------------------------- world --

hgcd_world_desc hgcd_world_desc_default(void) {
    hgcd_world_desc d;
    std::memset(&d, 0, sizeof(d));
    d.struct_size = sizeof(d);
    d.init_tag = hgcd::kInitTag;
    d.time_step = 1.0;
    for (int k = 0; k < 3; ++k) {
        d.bounds_min[k] = 0.0;
        d.bounds_max[k] = 1.0;
    }
    return d;
}

hgcd_status hgcd_world_create(const hgcd_world_desc *desc, hgcd_world **out_world) {
    const hgcd::IeeeMode ieee;  // (its checks compare doubles)
    if (!out_world) return HGCD_ERROR_NULL_ARGUMENT;
    *out_world = nullptr;
    if (!desc) return HGCD_ERROR_NULL_ARGUMENT;
    if (!initialised(desc)) return HGCD_ERROR_BAD_DESCRIPTOR;
    if (!std::isfinite(desc->time_step) || desc->time_step < 0) return HGCD_ERROR_INVALID_ARGUMENT;
    if (desc->thread_count > 4096) return HGCD_ERROR_INVALID_ARGUMENT;
    if (desc->thread_policy != HGCD_THREADS_ADAPTIVE && desc->thread_policy != HGCD_THREADS_FIXED)
        return HGCD_ERROR_INVALID_ARGUMENT;
    if (!desc->enqueue_task != !desc->finish_task) return HGCD_ERROR_INVALID_ARGUMENT;
    if (desc->enqueue_task && desc->thread_count == 0) return HGCD_ERROR_INVALID_ARGUMENT;
    for (int k = 0; k < 3 && desc->reflect_at_bounds; ++k)  // (the bounds serve the reflection only)
        if (!hgcd::coordinate_ok(desc->bounds_min[k]) || !hgcd::coordinate_ok(desc->bounds_max[k]) ||
            !(desc->bounds_min[k] < desc->bounds_max[k]))
            return HGCD_ERROR_INVALID_ARGUMENT;
    if (!hgcd::margin_ok(desc->contact_margin)) return HGCD_ERROR_INVALID_ARGUMENT;
    const double lo = desc->min_cell_size, hi = desc->max_cell_size;
    if (!std::isfinite(lo) || !std::isfinite(hi) || lo < 0 || hi < 0 || (lo > 0 && hi > 0 && lo > hi))
        return HGCD_ERROR_INVALID_ARGUMENT;
    const int32_t np = desc->narrow_phase;
    if (np != HGCD_NARROW_EXACT && np != HGCD_NARROW_GJK && np != HGCD_NARROW_MPR)
        return HGCD_ERROR_INVALID_ARGUMENT;
    if (np != HGCD_NARROW_EXACT && hgcd::libccd_precision() == 0) return HGCD_ERROR_NOT_SUPPORTED;
    return guarded(nullptr, "world_create", [&] {
        *out_world = new hgcd_world(*desc);
        return HGCD_OK;
    });
}

void hgcd_world_destroy(hgcd_world *world) { delete world; }

const char *hgcd_world_last_error(const hgcd_world *world) {
    return world ? world->impl.last_error() : "world is NULL";
}

uint32_t hgcd_world_body_count(const hgcd_world *world) { return world ? world->impl.body_count() : 0; }
uint32_t hgcd_world_mesh_count(const hgcd_world *world) { return world ? world->impl.mesh_count() : 0; }

hgcd_status hgcd_world_set_thread_count(hgcd_world *world, uint32_t thread_count) {
    if (!world) return HGCD_ERROR_NULL_ARGUMENT;
    if (thread_count > 4096)
        return refuse(world, HGCD_ERROR_INVALID_ARGUMENT, "world_set_thread_count",
                      "thread_count is more than 4096");
    if (thread_count == 0 && world->impl.task_system())
        return refuse(world, HGCD_ERROR_INVALID_ARGUMENT, "world_set_thread_count",
                      "thread_count 0 with a task system (it is the number of workers)");
    world->impl.set_thread_count(thread_count);
    return HGCD_OK;
}

hgcd_status hgcd_world_set_thread_policy(hgcd_world *world, int32_t thread_policy) {
    if (!world) return HGCD_ERROR_NULL_ARGUMENT;
    if (thread_policy != HGCD_THREADS_ADAPTIVE && thread_policy != HGCD_THREADS_FIXED)
        return refuse(world, HGCD_ERROR_INVALID_ARGUMENT, "world_set_thread_policy",
                      "thread_policy is not HGCD_THREADS_ADAPTIVE or HGCD_THREADS_FIXED");
    world->impl.set_thread_policy(thread_policy);
    return HGCD_OK;
}

hgcd_status hgcd_world_step(hgcd_world *world) {
    if (!world) return HGCD_ERROR_NULL_ARGUMENT;
    return guarded(world, "world_step", [&] { return world->impl.step(); });
}

hgcd_status hgcd_world_detect(hgcd_world *world) {
    if (!world) return HGCD_ERROR_NULL_ARGUMENT;
    return guarded(world, "world_detect", [&] { return world->impl.detect(); });
}

hgcd_status hgcd_world_pairs(const hgcd_world *world, const hgcd_pair **out_pairs, size_t *out_count) {
    if (!world || !out_pairs || !out_count) return HGCD_ERROR_NULL_ARGUMENT;
    const auto &p = world->impl.pairs();
    *out_pairs = p.empty() ? nullptr : p.data();
    *out_count = p.size();
    return HGCD_OK;
}

hgcd_status hgcd_world_copy_pairs(const hgcd_world *world, hgcd_pair *buffer, size_t capacity,
                                  size_t *out_total) {
    if (!world || !out_total || (!buffer && capacity > 0)) return HGCD_ERROR_NULL_ARGUMENT;
    const auto &p = world->impl.pairs();
    const size_t n = p.size() < capacity ? p.size() : capacity;
    if (n) std::memcpy(buffer, p.data(), n * sizeof(hgcd_pair));
    *out_total = p.size();
    return HGCD_OK;
}

hgcd_status hgcd_world_events(const hgcd_world *world, const hgcd_pair_event **out_began, size_t *out_began_count,
                              const hgcd_pair_event **out_ended, size_t *out_ended_count) {
    if (!world || !out_began || !out_began_count || !out_ended || !out_ended_count) return HGCD_ERROR_NULL_ARGUMENT;
    const auto &b = world->impl.began(), &e = world->impl.ended();
    *out_began = b.empty() ? nullptr : b.data();
    *out_began_count = b.size();
    *out_ended = e.empty() ? nullptr : e.data();
    *out_ended_count = e.size();
    return HGCD_OK;
}

hgcd_status hgcd_world_stats(const hgcd_world *world, hgcd_stats *out_stats) {
    if (!world || !out_stats) return HGCD_ERROR_NULL_ARGUMENT;
    size_t size = out_stats->struct_size ? out_stats->struct_size : sizeof(hgcd_stats);
    if (size < 8) return HGCD_ERROR_BAD_DESCRIPTOR;
    if (size > sizeof(hgcd_stats)) size = sizeof(hgcd_stats);
    hgcd_stats s = world->impl.stats();
    s.struct_size = uint32_t(size);
    std::memcpy(out_stats, &s, size);
    return HGCD_OK;
}

// ---------------------------------------------------------------- meshes --

hgcd_mesh_desc hgcd_mesh_desc_default(void) {
    hgcd_mesh_desc d;
    std::memset(&d, 0, sizeof(d));
    d.struct_size = sizeof(d);
    d.init_tag = hgcd::kInitTag;
    return d;
}

hgcd_status hgcd_mesh_create(hgcd_world *world, const hgcd_mesh_desc *desc, hgcd_mesh *out_mesh) {
    if (!world) return HGCD_ERROR_NULL_ARGUMENT;
    if (!desc) return refuse(world, HGCD_ERROR_NULL_ARGUMENT, "mesh_create", "desc is NULL");
    if (!out_mesh) return refuse(world, HGCD_ERROR_NULL_ARGUMENT, "mesh_create", "out_mesh is NULL");
    if (!initialised(desc))
        return refuse(world, HGCD_ERROR_BAD_DESCRIPTOR, "mesh_create",
                      "descriptor not initialised by hgcd_mesh_desc_default() (struct_size or init_tag)");
    return guarded(world, "mesh_create", [&] { return world->impl.create_mesh(*desc, out_mesh); });
}

hgcd_status hgcd_mesh_destroy(hgcd_world *world, hgcd_mesh mesh) {
    if (!world) return HGCD_ERROR_NULL_ARGUMENT;
    return guarded(world, "mesh_destroy", [&] { return world->impl.destroy_mesh(mesh); });
}

hgcd_status hgcd_mesh_get_info(const hgcd_world *world, hgcd_mesh mesh, hgcd_mesh_info *out_info) {
    if (!world || !out_info) return HGCD_ERROR_NULL_ARGUMENT;
    size_t size = out_info->struct_size ? out_info->struct_size : sizeof(hgcd_mesh_info);
    if (size < 8) return HGCD_ERROR_BAD_DESCRIPTOR;
    if (size > sizeof(hgcd_mesh_info)) size = sizeof(hgcd_mesh_info);
    hgcd_mesh_info info;
    if (hgcd_status s = world->impl.mesh_info(mesh, &info)) return s;
    info.struct_size = uint32_t(size);
    std::memcpy(out_info, &info, size);
    return HGCD_OK;
}

// ---------------------------------------------------------------- bodies --

hgcd_body_desc hgcd_body_desc_default(void) {
    hgcd_body_desc d;
    std::memset(&d, 0, sizeof(d));
    d.struct_size = sizeof(d);
    d.init_tag = hgcd::kInitTag;
    d.orientation[3] = 1.0;
    d.scale = 1.0;
    d.type = HGCD_BODY_DYNAMIC;
    d.enabled = 1;
    d.filter = hgcd_filter_default();
    return d;
}

hgcd_filter hgcd_filter_default(void) {
    hgcd_filter f;
    std::memset(&f, 0, sizeof(f));
    f.category_bits = 1;
    f.mask_bits = UINT64_MAX;
    return f;
}

hgcd_status hgcd_body_create(hgcd_world *world, const hgcd_body_desc *desc, hgcd_body *out_body) {
    if (!world) return HGCD_ERROR_NULL_ARGUMENT;
    if (!desc) return refuse(world, HGCD_ERROR_NULL_ARGUMENT, "body_create", "desc is NULL");
    if (!out_body) return refuse(world, HGCD_ERROR_NULL_ARGUMENT, "body_create", "out_body is NULL");
    if (!initialised(desc))
        return refuse(world, HGCD_ERROR_BAD_DESCRIPTOR, "body_create",
                      "descriptor not initialised by hgcd_body_desc_default() (struct_size or init_tag)");
    return guarded(world, "body_create", [&] { return world->impl.create_body(*desc, out_body); });
}

hgcd_status hgcd_body_destroy(hgcd_world *world, hgcd_body body) {
    if (!world) return HGCD_ERROR_NULL_ARGUMENT;
    return guarded(world, "body_destroy", [&] { return world->impl.destroy_body(body); });
}

hgcd_status hgcd_body_set_pose(hgcd_world *world, hgcd_body body, const double *position,
                               const double *orientation) {
    if (!world) return HGCD_ERROR_NULL_ARGUMENT;
    return guarded(world, "body_set_pose", [&] { return world->impl.set_pose(body, position, orientation); });
}

hgcd_status hgcd_body_set_velocity(hgcd_world *world, hgcd_body body, const double *velocity) {
    if (!world) return HGCD_ERROR_NULL_ARGUMENT;
    if (!velocity) return refuse(world, HGCD_ERROR_NULL_ARGUMENT, "body_set_velocity", "velocity is NULL");
    return guarded(world, "body_set_velocity", [&] { return world->impl.set_velocity(body, velocity); });
}

hgcd_status hgcd_world_set_poses(hgcd_world *world, const hgcd_body *bodies, size_t count, const double *positions,
                                 size_t position_stride, const double *orientations, size_t orientation_stride) {
    if (!world) return HGCD_ERROR_NULL_ARGUMENT;
    if (!positions && !orientations)
        return refuse(world, HGCD_ERROR_NULL_ARGUMENT, "world_set_poses", "positions and orientations are both NULL");
    return guarded(world, "world_set_poses", [&] {
        return world->impl.set_poses(bodies, count, positions, position_stride, orientations, orientation_stride);
    });
}

hgcd_status hgcd_world_set_velocities(hgcd_world *world, const hgcd_body *bodies, size_t count,
                                      const double *velocities, size_t velocity_stride) {
    if (!world) return HGCD_ERROR_NULL_ARGUMENT;
    if (!velocities) return refuse(world, HGCD_ERROR_NULL_ARGUMENT, "world_set_velocities", "velocities is NULL");
    return guarded(world, "world_set_velocities",
                   [&] { return world->impl.set_velocities(bodies, count, velocities, velocity_stride); });
}

hgcd_status hgcd_world_get_poses(const hgcd_world *world, const hgcd_body *bodies, size_t count, double *positions,
                                 size_t position_stride, double *orientations, size_t orientation_stride) {
    if (!world || (!positions && !orientations)) return HGCD_ERROR_NULL_ARGUMENT;
    const hgcd::TaskSystem::Attach tasks(world->impl.task_system());
    try {
        return world->impl.get_poses(bodies, count, positions, position_stride, orientations, orientation_stride);
    } catch (...) {
        return HGCD_ERROR_OUT_OF_MEMORY;
    }
}

hgcd_status hgcd_body_get_pose(const hgcd_world *world, hgcd_body body, double *position, double *orientation) {
    if (!world) return HGCD_ERROR_NULL_ARGUMENT;
    return world->impl.get_pose(body, position, orientation);
}

hgcd_status hgcd_body_get_velocity(const hgcd_world *world, hgcd_body body, double *velocity) {
    if (!world || !velocity) return HGCD_ERROR_NULL_ARGUMENT;
    return world->impl.get_velocity(body, velocity);
}

hgcd_status hgcd_body_get_mesh(const hgcd_world *world, hgcd_body body, hgcd_mesh *out_mesh) {
    if (!world || !out_mesh) return HGCD_ERROR_NULL_ARGUMENT;
    return world->impl.get_mesh(body, out_mesh);
}

hgcd_status hgcd_body_get_user_data(const hgcd_world *world, hgcd_body body, uint64_t *out_user_data) {
    if (!world || !out_user_data) return HGCD_ERROR_NULL_ARGUMENT;
    return world->impl.get_user_data(body, out_user_data);
}

hgcd_status hgcd_body_validate(const hgcd_world *world, hgcd_body body) {
    if (!world) return HGCD_ERROR_NULL_ARGUMENT;
    return world->impl.body_valid(body) ? HGCD_OK : HGCD_ERROR_STALE_ID;
}

hgcd_status hgcd_mesh_validate(const hgcd_world *world, hgcd_mesh mesh) {
    if (!world) return HGCD_ERROR_NULL_ARGUMENT;
    hgcd_mesh_info info;  // (mesh_info checks the id as every mesh call does, recording nothing)
    return world->impl.mesh_info(mesh, &info);
}

// ------------------------------------------- types, filters, exclusions --

hgcd_status hgcd_body_set_type(hgcd_world *world, hgcd_body body, int32_t type) {
    if (!world) return HGCD_ERROR_NULL_ARGUMENT;
    return guarded(world, "body_set_type", [&] { return world->impl.set_type(body, type); });
}

hgcd_status hgcd_body_get_type(const hgcd_world *world, hgcd_body body, int32_t *out_type) {
    if (!world || !out_type) return HGCD_ERROR_NULL_ARGUMENT;
    return world->impl.get_type(body, out_type);
}

hgcd_status hgcd_body_set_enabled(hgcd_world *world, hgcd_body body, uint32_t enabled) {
    if (!world) return HGCD_ERROR_NULL_ARGUMENT;
    return guarded(world, "body_set_enabled", [&] { return world->impl.set_enabled(body, enabled != 0); });
}

hgcd_status hgcd_body_get_enabled(const hgcd_world *world, hgcd_body body, uint32_t *out_enabled) {
    if (!world || !out_enabled) return HGCD_ERROR_NULL_ARGUMENT;
    return world->impl.get_enabled(body, out_enabled);
}

hgcd_status hgcd_body_set_filter(hgcd_world *world, hgcd_body body, const hgcd_filter *filter) {
    if (!world) return HGCD_ERROR_NULL_ARGUMENT;
    if (!filter) return refuse(world, HGCD_ERROR_NULL_ARGUMENT, "body_set_filter", "filter is NULL");
    return guarded(world, "body_set_filter", [&] { return world->impl.set_filter(body, *filter); });
}

hgcd_status hgcd_body_get_filter(const hgcd_world *world, hgcd_body body, hgcd_filter *out_filter) {
    if (!world || !out_filter) return HGCD_ERROR_NULL_ARGUMENT;
    return world->impl.get_filter(body, out_filter);
}

hgcd_status hgcd_body_set_margin(hgcd_world *world, hgcd_body body, double margin) {
    if (!world) return HGCD_ERROR_NULL_ARGUMENT;
    return guarded(world, "body_set_margin", [&] { return world->impl.set_margin(body, margin); });
}

hgcd_status hgcd_body_get_margin(const hgcd_world *world, hgcd_body body, double *out_margin) {
    if (!world || !out_margin) return HGCD_ERROR_NULL_ARGUMENT;
    return world->impl.get_margin(body, out_margin);
}

hgcd_status hgcd_world_exclude_pair(hgcd_world *world, hgcd_body a, hgcd_body b) {
    if (!world) return HGCD_ERROR_NULL_ARGUMENT;
    return guarded(world, "world_exclude_pair", [&] { return world->impl.exclude_pair(a, b, true); });
}

hgcd_status hgcd_world_include_pair(hgcd_world *world, hgcd_body a, hgcd_body b) {
    if (!world) return HGCD_ERROR_NULL_ARGUMENT;
    return guarded(world, "world_include_pair", [&] { return world->impl.exclude_pair(a, b, false); });
}

hgcd_status hgcd_world_pair_excluded(const hgcd_world *world, hgcd_body a, hgcd_body b, uint32_t *out_excluded) {
    if (!world || !out_excluded) return HGCD_ERROR_NULL_ARGUMENT;
    return world->impl.pair_excluded(a, b, out_excluded);
}

// ------------------------------------------------ narrow phase, contacts --

int32_t hgcd_feature_libccd(void) { return hgcd::libccd_precision(); }

hgcd_status hgcd_world_set_narrow_phase(hgcd_world *world, int32_t narrow_phase) {
    if (!world) return HGCD_ERROR_NULL_ARGUMENT;
    return guarded(world, "world_set_narrow_phase", [&] { return world->impl.set_narrow_phase(narrow_phase); });
}

hgcd_status hgcd_mesh_set_narrow_phase(hgcd_world *world, hgcd_mesh mesh, int32_t narrow_phase) {
    if (!world) return HGCD_ERROR_NULL_ARGUMENT;
    return guarded(world, "mesh_set_narrow_phase",
                   [&] { return world->impl.set_mesh_narrow_phase(mesh, narrow_phase); });
}

hgcd_status hgcd_world_set_contact_margin(hgcd_world *world, double contact_margin) {
    if (!world) return HGCD_ERROR_NULL_ARGUMENT;
    return guarded(world, "world_set_contact_margin", [&] { return world->impl.set_contact_margin(contact_margin); });
}

hgcd_status hgcd_world_get_contact_margin(const hgcd_world *world, double *out_margin) {
    if (!world || !out_margin) return HGCD_ERROR_NULL_ARGUMENT;
    *out_margin = world->impl.contact_margin();
    return HGCD_OK;
}

hgcd_status hgcd_world_set_contacts(hgcd_world *world, uint32_t enable) {
    if (!world) return HGCD_ERROR_NULL_ARGUMENT;
    world->impl.set_contacts(enable != 0);
    return HGCD_OK;
}

hgcd_status hgcd_world_contacts(const hgcd_world *world, const hgcd_contact **out_contacts,
                                size_t *out_count) {
    if (!world || !out_contacts || !out_count) return HGCD_ERROR_NULL_ARGUMENT;
    const auto &c = world->impl.contacts();
    *out_contacts = nullptr;
    *out_count = 0;
    if (!world->impl.contacts_recorded()) return HGCD_ERROR_INVALID_ARGUMENT;
    *out_contacts = c.empty() ? nullptr : c.data();
    *out_count = c.size();
    return HGCD_OK;
}

// --------------------------------------------------------------- queries --

hgcd_status hgcd_world_cast_rays(hgcd_world *world, const hgcd_ray *rays, size_t count, size_t ray_stride,
                                 int32_t mode, const hgcd_filter *filter, hgcd_ray_hit *out_hits) {
    if (!world) return HGCD_ERROR_NULL_ARGUMENT;
    if (count > 0 && (!rays || !out_hits))
        return refuse(world, HGCD_ERROR_NULL_ARGUMENT, "world_cast_rays", "rays or out_hits is NULL");
    return guarded(world, "world_cast_rays",
                   [&] { return world->impl.cast_rays(rays, count, ray_stride, mode, filter, out_hits); });
}

hgcd_status hgcd_world_query_box(hgcd_world *world, const double *boxes, size_t count, size_t box_stride,
                                 const hgcd_filter *filter, hgcd_query_results *out) {
    if (!world) return HGCD_ERROR_NULL_ARGUMENT;
    if (!out || (count > 0 && !boxes))
        return refuse(world, HGCD_ERROR_NULL_ARGUMENT, "world_query_box", "boxes or out is NULL");
    return guarded(world, "world_query_box",
                   [&] { return world->impl.query_boxes(boxes, count, box_stride, filter, out); });
}

hgcd_status hgcd_world_query_point(hgcd_world *world, const double *points, size_t count, size_t point_stride,
                                   const hgcd_filter *filter, hgcd_query_results *out) {
    if (!world) return HGCD_ERROR_NULL_ARGUMENT;
    if (!out || (count > 0 && !points))
        return refuse(world, HGCD_ERROR_NULL_ARGUMENT, "world_query_point", "points or out is NULL");
    return guarded(world, "world_query_point",
                   [&] { return world->impl.query_points(points, count, point_stride, filter, out); });
}

hgcd_status hgcd_world_query_mesh(hgcd_world *world, hgcd_mesh mesh, const hgcd_mesh_pose *poses, size_t count,
                                  size_t pose_stride, const hgcd_filter *filter, hgcd_query_results *out) {
    if (!world) return HGCD_ERROR_NULL_ARGUMENT;
    if (!out || (count > 0 && !poses))
        return refuse(world, HGCD_ERROR_NULL_ARGUMENT, "world_query_mesh", "poses or out is NULL");
    return guarded(world, "world_query_mesh",
                   [&] { return world->impl.query_meshes(mesh, poses, count, pose_stride, filter, out); });
}

}  // extern "C"
