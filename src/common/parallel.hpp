// An exception must not leave an OpenMP region: the runtime would call
// std::terminate, turning an out-of-memory into an abort. Region bodies run
// through RegionGuard::run, which keeps the first exception; the caller
// rethrows it once the region has ended. Once one body has failed, the rest
// are skipped: the region's result is discarded anyway, and a thread's
// scratch state may be half updated by the failure.
#pragma once
#include <time.h>

#include <algorithm>
#include <atomic>
#include <cstdint>
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

// Nanoseconds of a clock: CLOCK_MONOTONIC, or CLOCK_THREAD_CPUTIME_ID (the
// calling thread's time on a core).
inline int64_t clock_ns(clockid_t clock) noexcept {
    timespec t;
    clock_gettime(clock, &t);
    return int64_t(t.tv_sec) * 1000000000 + t.tv_nsec;
}

// How much of their time the threads of the regions run while it is
// attached (LoadMeter::Attach) spent off a core: descheduled (the cores are
// shared with other work), or asleep at a barrier. For each thread of a
// region of 2 or more threads: `busy`, the wall time from the region's start
// to the end of the thread's body, and `off`, the part of it the thread did
// not run (its late start, and its body's wall time less its CPU time).
// Spinning at a barrier counts as running: it does not hide the descheduled
// time of the thread waited for. Two reads of the thread's CPU clock per
// thread and region (a system call each, about 0.4 us here).
class LoadMeter {
  public:
    // Attaches a meter (or none: NULL) to the calling thread's regions for
    // its lifetime.
    class Attach {
      public:
        explicit Attach(LoadMeter *m) noexcept : saved_(current()) { current() = m; }
        ~Attach() { current() = saved_; }
        Attach(const Attach &) = delete;
        Attach &operator=(const Attach &) = delete;

      private:
        LoadMeter *saved_;
    };
    static LoadMeter *&current() noexcept {
        static thread_local LoadMeter *meter = nullptr;
        return meter;
    }
    void add(int64_t busy, int64_t off) noexcept {
        busy_.fetch_add(busy, std::memory_order_relaxed);
        off_.fetch_add(off, std::memory_order_relaxed);
    }
    // The fraction of the threads' time spent off a core (0 when nothing
    // was measured).
    double lost() const noexcept {
        const int64_t busy = busy_.load(std::memory_order_relaxed);
        return busy > 0 ? double(off_.load(std::memory_order_relaxed)) / double(busy) : 0;
    }

  private:
    std::atomic<int64_t> busy_{0}, off_{0};
};

// One OpenMP region on `threads` threads: each runs body(guard) under the
// IEEE mode (ieee.hpp); the first exception is rethrown after the region.
// The body may hold worksharing loops; each iteration that can throw runs
// through guard.run, so that a failing thread still reaches the loops'
// barriers and the region ends. A region of 2 or more threads reports to
// the calling thread's LoadMeter, if one is attached.
template <class Body>
void parallel_region(int threads, Body &&body) {
    RegionGuard guard;
    LoadMeter *const meter = threads > 1 ? LoadMeter::current() : nullptr;
    const int64_t start = meter ? clock_ns(CLOCK_MONOTONIC) : 0;
#pragma omp parallel num_threads(threads)
    {
        const IeeeMode ieee;
        const int64_t cpu0 = meter ? clock_ns(CLOCK_THREAD_CPUTIME_ID) : 0;
        const int64_t wall0 = meter ? clock_ns(CLOCK_MONOTONIC) : 0;
        body(guard);
        if (meter) {
            const int64_t wall1 = clock_ns(CLOCK_MONOTONIC);
            const int64_t cpu = clock_ns(CLOCK_THREAD_CPUTIME_ID) - cpu0;
            meter->add(wall1 - start, (wall0 - start) + std::max<int64_t>(0, (wall1 - wall0) - cpu));
        }
    }
    guard.rethrow();
}

}  // namespace hgcd
