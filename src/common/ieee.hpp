// Every library source includes this. Their results rest on IEEE double
// rounding and on NaN and infinity behaving as IEEE says: the exact
// predicates and their filters (src/exact, and the narrow phase's own), the
// broad phase grid's window, floor and reach margins, the bodies' boxes and
// the motion formula of docs/scenes.md (src/world), the scene generator's
// bit-exact arithmetic, and the refusal of non-finite input (std::isfinite,
// which -ffinite-math-only may fold to true). -ffast-math (and -Ofast)
// would let the compiler reorder, contract and drop those roundings and
// checks, so the reported pairs would depend on the compiler.
// meson.build and the Makefile put flags undoing them (and -ffp-contract=off)
// after the user's, so a build with CXXFLAGS=-Ofast is still IEEE, and
// scripts/check-ieee.sh checks that it gives the same results. A build that
// compiles these sources some other way with -ffast-math or -Ofast stops
// here; the script checks that every source does.
#pragma once
#if defined(__FAST_MATH__) || defined(__FINITE_MATH_ONLY__) && __FINITE_MATH_ONLY__
#error "hgcd needs IEEE arithmetic: build without -ffast-math / -Ofast"
#endif

#include <cstdint>
#if defined(__x86_64__) || defined(_M_X64)
#include <xmmintrin.h>
#endif

namespace hgcd {

// The exact predicates, their filters' error bounds and the grid's margins
// also assume the run-time mode IEEE prescribes by default: subnormals kept,
// round to nearest, no trap. A host may run otherwise: -ffast-math's start-up
// code sets flush-to-zero and denormals-are-zero (a subnormal coordinate then
// reads as 0), fesetround changes the rounding, feenableexcept turns an
// underflow in a filter into SIGFPE. So every entry point (the C shim) and
// every parallel region (parallel.hpp) sets that mode on its thread for its
// duration and gives the caller's back after (OpenMP's threads keep whatever
// mode they had: they inherit the mode of the thread that started them).
// x86-64: MXCSR; arm64: FPCR; elsewhere nothing is done.
class IeeeMode {
  public:
    IeeeMode() noexcept : saved_(read()) {
        const uint64_t want = standard(saved_);
        changed_ = want != saved_;
        if (changed_) write(want);
    }
    ~IeeeMode() {
        if (changed_) write(saved_);
    }
    IeeeMode(const IeeeMode &) = delete;
    IeeeMode &operator=(const IeeeMode &) = delete;

  private:
#if defined(__x86_64__) || defined(_M_X64)
    // MXCSR: flush to zero (bit 15), rounding (bits 13-14, 0: nearest),
    // exception masks (bits 7-12, set: masked), denormals are zero (bit 6).
    static uint64_t read() { return _mm_getcsr(); }
    static void write(uint64_t v) { _mm_setcsr(unsigned(v)); }
    static uint64_t standard(uint64_t v) { return (v & ~uint64_t(0x8000 | 0x6000 | 0x0040)) | 0x1F80; }
#elif defined(__aarch64__)
    // FPCR: flush to zero (bit 24), rounding (bits 22-23, 0: nearest), FZ16
    // (bit 19), trap enables (bits 8-12 and 15, clear: no trap), and with
    // FEAT_AFP flush inputs to zero (FIZ, bit 0) and the alternate handling
    // (AH, bit 1). (The memory clobbers keep the compiler from moving memory
    // operations across the switch.)
    static uint64_t read() {
        uint64_t v;
        __asm__ __volatile__("mrs %0, fpcr" : "=r"(v) : : "memory");
        return v;
    }
    static void write(uint64_t v) { __asm__ __volatile__("msr fpcr, %0" : : "r"(v) : "memory"); }
    static uint64_t standard(uint64_t v) {
        return v & ~((uint64_t(1) << 24) | (uint64_t(3) << 22) | (uint64_t(1) << 19) | (uint64_t(1) << 15) |
                     (uint64_t(0x1F) << 8) | uint64_t(3));
    }
#else
    static uint64_t read() { return 0; }
    static void write(uint64_t) {}
    static uint64_t standard(uint64_t v) { return v; }
#endif
    uint64_t saved_;
    bool changed_ = false;
};

}  // namespace hgcd
