// An exception must not leave an OpenMP region: the runtime would call
// std::terminate, turning an out-of-memory into an abort. Region bodies run
// through RegionGuard::run, which keeps the first exception; the caller
// rethrows it once the region has ended. Once one body has failed, the rest
// are skipped: the region's result is discarded anyway, and a thread's
// scratch state may be half updated by the failure.
#pragma once
#include <atomic>
#include <exception>

#include "common/ieee.hpp"

namespace hgcd {

class RegionGuard {
  public:
    template <class F>
    void run(F &&f) noexcept {
        if (failed_.load(std::memory_order_relaxed)) return;
        try {
            f();
        } catch (...) {
            failed_.store(true, std::memory_order_relaxed);
#pragma omp critical(hgcd_region_guard)
            if (!first_) first_ = std::current_exception();
        }
    }
    void rethrow() const {
        if (first_) std::rethrow_exception(first_);
    }

  private:
    std::atomic<bool> failed_{false};
    std::exception_ptr first_;
};

// One OpenMP region on `threads` threads: each runs body(guard) under the
// IEEE mode (ieee.hpp); the first exception is rethrown after the region.
// The body may hold worksharing loops; each iteration that can throw runs
// through guard.run, so that a failing thread still reaches the loops'
// barriers and the region ends.
template <class Body>
void parallel_region(int threads, Body &&body) {
    RegionGuard guard;
#pragma omp parallel num_threads(threads)
    {
        const IeeeMode ieee;
        body(guard);
    }
    guard.rethrow();
}

}  // namespace hgcd
