// The vector types of the SIMD kernels (GCC and clang vector extensions):
// one name per lane type and width, so a kernel's types say what they hold.
// Lane-wise operators compile to SSE2/NEON by default, and to AVX2 in the
// kernels built with target("avx2") and picked at run time (cpu.hpp).
#pragma once
#include <cstdint>

namespace hgcd {

typedef float f32x4 __attribute__((vector_size(16)));
typedef int32_t i32x4 __attribute__((vector_size(16)));
typedef double f64x2 __attribute__((vector_size(16)));
typedef int64_t i64x2 __attribute__((vector_size(16)));

typedef float f32x8 __attribute__((vector_size(32)));
typedef int32_t i32x8 __attribute__((vector_size(32)));
typedef double f64x4 __attribute__((vector_size(32)));
typedef int64_t i64x4 __attribute__((vector_size(32)));

}  // namespace hgcd
