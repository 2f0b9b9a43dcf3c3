// How hgcd runs parallel work: OpenMP by default, or the caller's task
// system (hgcd_world_desc.enqueue_task). parallel_for runs a loop's ranges,
// with no barrier inside, on either.
//
// An exception must not leave an OpenMP region (the runtime would call
// std::terminate, turning an out-of-memory into an abort) nor a task (the
// caller's task system is C). Loop bodies run through RegionGuard::run,
// which keeps the first exception; the caller rethrows it once the loop has
// ended. Once one body has failed, the rest are
// skipped: the result is discarded anyway, and a thread's scratch state may
// be half updated by the failure.
#pragma once
#include <omp.h>
#include <time.h>

#include <algorithm>
#include <atomic>
#include <cstdint>
#include <exception>
#include <mutex>
#include <stdexcept>
#include <type_traits>

#include "common/ieee.hpp"
#include "hgcd/hgcd.h"

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
            const std::lock_guard<std::mutex> lock(mutex_);
            if (!first_) first_ = std::current_exception();
        }
    }
    void rethrow() const {
        if (first_) std::rethrow_exception(first_);
    }

  private:
    std::atomic<bool> failed_{false};
    std::mutex mutex_;
    std::exception_ptr first_;
};

// The caller's task system, attached to the calling thread for a call's
// duration (as LoadMeter is): the parallel loops inside run on it.
struct TaskSystem {
    hgcd_enqueue_task_fn *enqueue = nullptr;
    hgcd_finish_task_fn *finish = nullptr;
    void *context = nullptr;

    class Attach {
      public:
        explicit Attach(const TaskSystem *t) noexcept : saved_(current()) { current() = t; }
        ~Attach() { current() = saved_; }
        Attach(const Attach &) = delete;
        Attach &operator=(const Attach &) = delete;

      private:
        const TaskSystem *saved_;
    };
    static const TaskSystem *&current() noexcept {
        static thread_local const TaskSystem *tasks = nullptr;
        return tasks;
    }
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

// How a parallel_for hands its items out on OpenMP: Static, one contiguous
// range per thread (the partition of schedule(static)); Dynamic, ranges of
// `grain` items to whichever thread is free. On a task system both hand it
// ranges of at least `grain` items (min_range), in any order and on any
// worker.
enum class Schedule { Static, Dynamic };

namespace detail {

template <class Body>
struct TaskLoop {
    Body *body;
    RegionGuard *guard;
    int64_t count;
    uint32_t workers;
    std::atomic<int64_t> done{0};
    std::atomic<bool> misused{false};

    static void run(uint32_t begin, uint32_t end, uint32_t worker, void *context) {
        TaskLoop &loop = *static_cast<TaskLoop *>(context);
        if (worker >= loop.workers || begin > end || end > uint64_t(loop.count)) {
            loop.misused.store(true, std::memory_order_relaxed);
            return;
        }
        const IeeeMode ieee;
        loop.guard->run([&] { (*loop.body)(int64_t(begin), int64_t(end), int(worker)); });
        loop.done.fetch_add(int64_t(end) - int64_t(begin), std::memory_order_relaxed);
    }
};

}  // namespace detail

// Runs body(begin, end, worker) over ranges that cover the items [0, count)
// once each, on `threads` workers (worker < threads; one range at a time
// per worker, so per-worker state needs no lock; which worker gets which
// range is not fixed, nor their order): on OpenMP threads, or on the
// task system attached to the calling thread, whose workers are the world's
// thread count (so `threads` is that count, or 1: then the loop runs on the
// calling thread alone, as worker 0). Each range runs in IEEE mode
// (ieee.hpp), through one RegionGuard; the first exception is rethrown
// here. The body must not wait for another range. OpenMP loops of 2 or more
// threads report to the calling thread's LoadMeter.
template <class Body>
void parallel_for(int threads, int64_t count, int64_t grain, Schedule schedule, Body &&body) {
    if (count <= 0) return;
    grain = std::max<int64_t>(grain, 1);
    RegionGuard guard;
    if (threads <= 1) {  // (on a task system too: a loop kept on one thread is small)
        guard.run([&] { body(int64_t(0), count, 0); });
        guard.rethrow();
        return;
    }
    if (const TaskSystem *tasks = TaskSystem::current()) {
        if (count > int64_t(UINT32_MAX)) throw std::length_error("parallel_for: more than 2^32 - 1 items");
        using Loop = detail::TaskLoop<std::remove_reference_t<Body>>;
        Loop loop;
        loop.body = &body;
        loop.guard = &guard;
        loop.count = count;
        loop.workers = uint32_t(threads);
        void *handle = tasks->enqueue(&Loop::run, uint32_t(count), uint32_t(std::min<int64_t>(grain, count)), &loop,
                                      tasks->context);
        if (handle) tasks->finish(handle, tasks->context);
        if (loop.misused.load(std::memory_order_relaxed))
            throw std::runtime_error("task system: a task ran with a worker index past thread_count or a bad range");
        guard.rethrow();
        if (loop.done.load(std::memory_order_relaxed) != count)
            throw std::runtime_error("task system: the tasks did not cover every item exactly once");
        return;
    }
    LoadMeter *const meter = LoadMeter::current();
    const int64_t start = meter ? clock_ns(CLOCK_MONOTONIC) : 0;
    // (The region reads locals only: GCC's AddressSanitizer build handed it
    // null addresses for this function's by-value parameters.)
    const int64_t items = count, step = grain;
    const bool static_schedule = schedule == Schedule::Static;
#pragma omp parallel num_threads(threads)
    {
        const IeeeMode ieee;
        const int64_t cpu0 = meter ? clock_ns(CLOCK_THREAD_CPUTIME_ID) : 0;
        const int64_t wall0 = meter ? clock_ns(CLOCK_MONOTONIC) : 0;
        const int me = omp_get_thread_num();
        if (static_schedule) {
            const int64_t team = omp_get_num_threads(), q = items / team, r = items % team;
            const int64_t b = me * q + std::min<int64_t>(me, r), e = b + q + (me < r);
            if (b < e) guard.run([&] { body(b, e, me); });
        } else {
            const int64_t ranges = (items + step - 1) / step;
#pragma omp for schedule(dynamic, 1) nowait
            for (int64_t k = 0; k < ranges; ++k)
                guard.run([&] { body(k * step, std::min(items, (k + 1) * step), me); });
        }
        if (meter) {
            const int64_t wall1 = clock_ns(CLOCK_MONOTONIC);
            const int64_t cpu = clock_ns(CLOCK_THREAD_CPUTIME_ID) - cpu0;
            meter->add(wall1 - start, (wall0 - start) + std::max<int64_t>(0, (wall1 - wall0) - cpu));
        }
    }
    guard.rethrow();
}

}  // namespace hgcd
