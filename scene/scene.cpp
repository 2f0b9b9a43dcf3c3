// Scene `tetra` (docs/scenes.md), bit for bit.
#include <cmath>
#include <cstdint>
#include <limits>
#include <vector>

#include "hgcd/hgcd.h"
#include "hgcd/hgcd_scene.h"
#include "common/ieee.hpp"
#include "common/tags.hpp"

namespace {

struct SplitMix64 {
    uint64_t state;
    uint64_t next() {
        state += 0x9E3779B97F4A7C15ull;
        uint64_t z = state;
        z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
        z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
        return z ^ (z >> 31);
    }
    double u() { return static_cast<double>(next() >> 11) * 0x1.0p-53; }
};

// One object of the scene: the ten numbers docs/scenes.md draws, in its order and
// arithmetic, turned into what a body needs.
struct Object {
    double center[3], radius, scale, orientation[4], velocity[3];
};

class Draw {
  public:
    explicit Draw(const hgcd_scene_tetra_desc &d)
        : rng_{d.seed}, side_(d.side), rmin_(d.rmin), ratio_(d.rmax / d.rmin), vmax_(d.vmax) {}
    Object next() {
        Object o;
        for (double &c : o.center) c = side_ * rng_.u();
        o.radius = rmin_ * std::pow(ratio_, rng_.u());
        o.scale = o.radius / std::sqrt(3.0);
        const double u1 = rng_.u(), u2 = rng_.u(), u3 = rng_.u();
        for (double &v : o.velocity) v = vmax_ * (2 * rng_.u() - 1);
        const double a2 = (2.0 * M_PI) * u2, a3 = (2.0 * M_PI) * u3;
        o.orientation[0] = std::sqrt(1 - u1) * std::sin(a2);
        o.orientation[1] = std::sqrt(1 - u1) * std::cos(a2);
        o.orientation[2] = std::sqrt(u1) * std::sin(a3);
        o.orientation[3] = std::sqrt(u1) * std::cos(a3);
        return o;
    }

  private:
    SplitMix64 rng_;
    double side_, rmin_, ratio_, vmax_;
};

int32_t check(const hgcd_scene_tetra_desc *desc) {
    if (!desc) return HGCD_ERROR_NULL_ARGUMENT;
    if (desc->struct_size != sizeof(*desc) || desc->init_tag != hgcd::kInitTag)
        return HGCD_ERROR_BAD_DESCRIPTOR;
    const double L = desc->side, rmin = desc->rmin, rmax = desc->rmax, vmax = desc->vmax;
    if (!std::isfinite(L) || !std::isfinite(rmin) || !std::isfinite(rmax) || !std::isfinite(vmax) ||
        L <= 0 || rmin <= 0 || rmax < rmin || vmax < 0)
        return HGCD_ERROR_INVALID_ARGUMENT;
    if (desc->n > std::numeric_limits<size_t>::max() / (4 * sizeof(double))) return HGCD_ERROR_CAPACITY;
    return HGCD_OK;
}

}  // namespace

extern "C" {

hgcd_scene_tetra_desc hgcd_scene_tetra_desc_default(void) {
    hgcd_scene_tetra_desc d{};
    d.struct_size = sizeof(d);
    d.init_tag = hgcd::kInitTag;
    d.n = 750000;
    d.seed = 1;
    d.side = 200.0;
    d.rmin = 0.25;
    d.rmax = 2.0;
    d.vmax = 0.05;
    return d;
}

int32_t hgcd_scene_tetra_generate(const hgcd_scene_tetra_desc *desc, double *centers,
                                  double *radii, double *scales, double *orientations,
                                  double *velocities) {
    const hgcd::IeeeMode ieee;  // (the scene's arithmetic is IEEE's)
    const int32_t status = check(desc);
    if (status != HGCD_OK) return status;
    Draw draw(*desc);
    for (uint64_t i = 0; i < desc->n; ++i) {
        const Object o = draw.next();
        if (centers)
            for (int k = 0; k < 3; ++k) centers[3 * i + k] = o.center[k];
        if (radii) radii[i] = o.radius;
        if (scales) scales[i] = o.scale;
        if (orientations)
            for (int k = 0; k < 4; ++k) orientations[4 * i + k] = o.orientation[k];
        if (velocities)
            for (int k = 0; k < 3; ++k) velocities[3 * i + k] = o.velocity[k];
    }
    return HGCD_OK;
}

int32_t hgcd_scene_tetra_populate(hgcd_world *world, const hgcd_scene_tetra_desc *desc,
                                  hgcd_mesh *mesh_out) {
    const hgcd::IeeeMode ieee;  // (the scene's arithmetic is IEEE's)
    if (!world) return HGCD_ERROR_NULL_ARGUMENT;
    int32_t status = check(desc);
    if (status != HGCD_OK) return status;
    double vertices[12];
    uint32_t triangles[12];
    hgcd_scene_tetra_unit_mesh(vertices, triangles);
    hgcd_mesh_desc md = hgcd_mesh_desc_default();
    md.vertices = vertices;
    md.triangles = triangles;
    md.vertex_count = 4;
    md.triangle_count = 4;
    // The ids made, to undo the call if a body cannot be made.
    std::vector<hgcd_body> bodies;
    try {
        bodies.reserve(size_t(desc->n));
    } catch (...) {
        return HGCD_ERROR_OUT_OF_MEMORY;
    }
    hgcd_mesh mesh;
    status = hgcd_mesh_create(world, &md, &mesh);
    if (status != HGCD_OK) return status;
    hgcd_body_desc bd = hgcd_body_desc_default();
    bd.mesh = mesh;
    Draw draw(*desc);
    uint64_t created = 0;
    for (; created < desc->n; ++created) {
        const Object o = draw.next();
        for (int k = 0; k < 3; ++k) bd.position[k] = o.center[k];
        for (int k = 0; k < 4; ++k) bd.orientation[k] = o.orientation[k];
        for (int k = 0; k < 3; ++k) bd.velocity[k] = o.velocity[k];
        bd.scale = o.scale;
        bd.user_data = created;
        hgcd_body body;
        status = hgcd_body_create(world, &bd, &body);
        if (status != HGCD_OK) break;
        bodies.push_back(body);  // within the reserved capacity
    }
    if (status == HGCD_OK) {
        if (mesh_out) *mesh_out = mesh;
        return HGCD_OK;
    }
    // Leave the world without anything this call made.
    for (const hgcd_body &b : bodies) hgcd_body_destroy(world, b);
    hgcd_mesh_destroy(world, mesh);
    return status;
}

void hgcd_scene_tetra_unit_mesh(double *vertices, uint32_t *triangles) {
    static const double v[12] = {1, 1, 1, 1, -1, -1, -1, 1, -1, -1, -1, 1};
    static const uint32_t t[12] = {0, 1, 2, 0, 3, 1, 0, 2, 3, 1, 3, 2};
    if (vertices)
        for (int i = 0; i < 12; ++i) vertices[i] = v[i];
    if (triangles)
        for (int i = 0; i < 12; ++i) triangles[i] = t[i];
}

void hgcd_scene_tetra_move(uint64_t n, double side, double *centers, double *velocities) {
    const hgcd::IeeeMode ieee;  // (the scene's arithmetic is IEEE's)
    if (!centers || !velocities) return;
    for (uint64_t k = 0; k < 3 * n; ++k) {
        double x = centers[k] + velocities[k];
        if (x < 0) {
            x = -x;
            velocities[k] = -velocities[k];
        } else if (x > side) {
            x = 2 * side - x;
            velocities[k] = -velocities[k];
        }
        centers[k] = x;
    }
}

}  // extern "C"
