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

}  // namespace hgcd
