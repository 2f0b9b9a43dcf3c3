// Whether the AVX2 kernels (the `*_avx2` files beside the broad and narrow
// phases) may run: the CPU has AVX2 and POPCNT, and HGCD_NO_AVX2 is not set
// (any value keeps the SSE2 kernels on AVX2 machines too, so that the tests
// cover both: scripts/run-tests.sh). Decided once.
#pragma once
#include <cstdlib>

// Whether this build has the AVX2 kernels at all: GCC on x86-64 (they rest
// on its target attributes and vector extensions; clang and other targets
// build the SSE2 / NEON kernels only).
#if defined(__x86_64__) && defined(__GNUC__) && !defined(__clang__)
#define HGCD_AVX2 1
#else
#define HGCD_AVX2 0
#endif

namespace hgcd {

inline bool use_avx2() {
#if HGCD_AVX2
    static const bool avx2 = [] {
        __builtin_cpu_init();
        return __builtin_cpu_supports("avx2") != 0 && __builtin_cpu_supports("popcnt") != 0 &&
               !std::getenv("HGCD_NO_AVX2");
    }();
    return avx2;
#else
    return false;
#endif
}

// Whether the AVX-512 kernels may run (a few, in place of AVX2 ones): AVX-512
// F, DQ and VL, and use_avx2() (HGCD_NO_AVX2 keeps them off too);
// HGCD_NO_AVX512 keeps the AVX2 kernels in their place.
inline bool use_avx512() {
#if HGCD_AVX2
    static const bool avx512 = [] {
        __builtin_cpu_init();
        return use_avx2() && __builtin_cpu_supports("avx512f") != 0 && __builtin_cpu_supports("avx512dq") != 0 &&
               __builtin_cpu_supports("avx512vl") != 0 && !std::getenv("HGCD_NO_AVX512");
    }();
    return avx512;
#else
    return false;
#endif
}

}  // namespace hgcd
