// Scene `tetra` of SCENES.md, bit for bit.
#include <cmath>
#include <cstdint>
#include <limits>

#include "hgcd/hgcd.h"
#include "tags.hpp"

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
    if (!desc) return HGCD_ERROR_NULL_ARGUMENT;
    if (desc->struct_size != sizeof(*desc) || desc->init_tag != hgcd::kInitTag)
        return HGCD_ERROR_BAD_DESCRIPTOR;
    const double L = desc->side, rmin = desc->rmin, rmax = desc->rmax, vmax = desc->vmax;
    if (!std::isfinite(L) || !std::isfinite(rmin) || !std::isfinite(rmax) ||
        !std::isfinite(vmax) || L <= 0 || rmin <= 0 || rmax < rmin || vmax < 0)
        return HGCD_ERROR_INVALID_ARGUMENT;
    if (desc->n > std::numeric_limits<size_t>::max() / (4 * sizeof(double)))
        return HGCD_ERROR_CAPACITY;
    SplitMix64 rng{desc->seed};
    const double ratio = rmax / rmin;
    for (uint64_t i = 0; i < desc->n; ++i) {
        const double cx = L * rng.u(), cy = L * rng.u(), cz = L * rng.u();
        const double r = rmin * std::pow(ratio, rng.u());
        const double u1 = rng.u(), u2 = rng.u(), u3 = rng.u();
        const double vx = vmax * (2 * rng.u() - 1);
        const double vy = vmax * (2 * rng.u() - 1);
        const double vz = vmax * (2 * rng.u() - 1);
        if (centers) {
            centers[3 * i] = cx;
            centers[3 * i + 1] = cy;
            centers[3 * i + 2] = cz;
        }
        if (radii) radii[i] = r;
        if (scales) scales[i] = r / std::sqrt(3.0);
        if (orientations) {
            const double a2 = (2.0 * M_PI) * u2, a3 = (2.0 * M_PI) * u3;
            orientations[4 * i] = std::sqrt(1 - u1) * std::sin(a2);
            orientations[4 * i + 1] = std::sqrt(1 - u1) * std::cos(a2);
            orientations[4 * i + 2] = std::sqrt(u1) * std::sin(a3);
            orientations[4 * i + 3] = std::sqrt(u1) * std::cos(a3);
        }
        if (velocities) {
            velocities[3 * i] = vx;
            velocities[3 * i + 1] = vy;
            velocities[3 * i + 2] = vz;
        }
    }
    return HGCD_OK;
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
