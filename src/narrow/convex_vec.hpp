// The convex kernel's vector and small vector-algebra helpers
// (convex_kernel.cpp and convex_inside.hpp, which include this header alone:
// every function is inlined into the kernel, see there).
#pragma once
#include <algorithm>
#include <cmath>
#include <cstring>
#if defined(__SSE2__)
#include <emmintrin.h>
#endif

#include "common/simd.hpp"
#include "common/transform.hpp"
#include "world/mesh.hpp"

// (No vector crosses a call boundary: GCC's note that a 32-byte vector
// return would change the ABI without AVX does not apply.)
#pragma GCC diagnostic ignored "-Wpsabi"

namespace hgcd {

namespace {

#define HGCD_CK_INLINE inline __attribute__((always_inline))

// Four doubles per vector: AVX2 registers in the AVX2 clone, two SSE2 (or
// NEON) registers each elsewhere; IEEE operations lane by lane and no FMA
// (-ffp-contract=off, and no FMA target), so both builds compute the same
// bits as the scalar expressions written beside them.
HGCD_CK_INLINE f64x4 load4(const double *p) {
    f64x4 v;
    std::memcpy(&v, p, sizeof v);
    return v;
}
HGCD_CK_INLINE f64x4 splat(double x) { return f64x4{x, x, x, x}; }
HGCD_CK_INLINE f64x4 vmax4(f64x4 a, f64x4 b) { return a > b ? a : b; }
HGCD_CK_INLINE f64x4 vmin4(f64x4 a, f64x4 b) { return a < b ? a : b; }
HGCD_CK_INLINE double hmax4(f64x4 a) { return std::max(std::max(a[0], a[1]), std::max(a[2], a[3])); }
HGCD_CK_INLINE double hmin4(f64x4 a) { return std::min(std::min(a[0], a[1]), std::min(a[2], a[3])); }

HGCD_CK_INLINE f64x4 vabs(f64x4 a) { return (f64x4)((i64x4)a & (i64x4{} + INT64_MAX)); }

// Whether any lane of a comparison's result (each all ones or zero) is set:
// by SSE2's sign mask where there is one (baseline x86-64, so inlined into
// the AVX2 kernels too), else lane by lane.
HGCD_CK_INLINE bool any4(i64x4 m) {
#if defined(__SSE2__)
    __m128d lo, hi;
    std::memcpy(&lo, &m, sizeof lo);
    std::memcpy(&hi, reinterpret_cast<const char *>(&m) + sizeof lo, sizeof hi);
    return _mm_movemask_pd(_mm_or_pd(lo, hi)) != 0;
#else
    return ((m[0] | m[1]) | (m[2] | m[3])) != 0;
#endif
}

HGCD_CK_INLINE void rotate_t(const Rotation &r, const double *v, double *out) {  // R^T v
    for (int j = 0; j < 3; ++j) out[j] = (r.m[j] * v[0] + r.m[3 + j] * v[1]) + r.m[6 + j] * v[2];
}
HGCD_CK_INLINE void rotate(const Rotation &r, const double *v, double *out) {  // R v
    for (int j = 0; j < 3; ++j) out[j] = (r.m[3 * j] * v[0] + r.m[3 * j + 1] * v[1]) + r.m[3 * j + 2] * v[2];
}
// Vertex v of a mesh read from its SatData's runs: Mesh::vertices's values,
// in memory that copies of one mesh share (World's sat_slot_).
HGCD_CK_INLINE void vertex_of(const SatData &m, uint32_t v, double *out) {
    for (int k = 0; k < 3; ++k) out[k] = m.soa()[k * size_t(m.padded) + v];
}
HGCD_CK_INLINE double norm1(const double *v) { return (std::fabs(v[0]) + std::fabs(v[1])) + std::fabs(v[2]); }
HGCD_CK_INLINE double norm_inf(const double *v) {
    return std::max(std::max(std::fabs(v[0]), std::fabs(v[1])), std::fabs(v[2]));
}

}  // namespace

}  // namespace hgcd
