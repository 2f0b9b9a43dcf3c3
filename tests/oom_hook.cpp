// Replacement global operator new/delete with a failure countdown (see
// oom_hook.h). Every form of operator new and delete is replaced, aligned
// ones included (hgcd's body storage is 64-byte aligned), so the pairs
// always match: all memory comes from malloc / aligned_alloc and goes back
// through free.
#include "oom_hook.h"

#include <omp.h>

#include <atomic>
#include <cstdlib>
#include <new>

namespace {

std::atomic<long> g_countdown{-1};  // counted allocations left; < 0: disarmed
std::atomic<int> g_sticky{0}, g_in_parallel{0}, g_tripped{0};
std::atomic<long> g_counted{0}, g_total{0};

bool inject() {
    g_total.fetch_add(1, std::memory_order_relaxed);
    if (g_countdown.load(std::memory_order_relaxed) < 0) return false;
    if (!g_in_parallel.load(std::memory_order_relaxed) && omp_get_level() > 0) return false;
    g_counted.fetch_add(1, std::memory_order_relaxed);
    if (g_tripped.load(std::memory_order_relaxed)) return g_sticky.load(std::memory_order_relaxed) != 0;
    if (g_countdown.fetch_sub(1) == 1) {
        g_tripped.store(1);
        return true;
    }
    return false;
}

void *plain(std::size_t n) {
    if (inject()) return nullptr;
    return std::malloc(n ? n : 1);
}

void *aligned(std::size_t n, std::align_val_t al) {
    if (inject()) return nullptr;
    const std::size_t a = static_cast<std::size_t>(al) < sizeof(void *) ? sizeof(void *)
                                                                          : static_cast<std::size_t>(al);
    void *p = nullptr;
    if (posix_memalign(&p, a, n ? n : 1) != 0) return nullptr;
    return p;
}

}  // namespace

extern "C" {
void oom_arm(long n, int sticky, int in_parallel) {
    g_countdown.store(-1);
    g_sticky.store(sticky);
    g_in_parallel.store(in_parallel);
    g_tripped.store(0);
    g_counted.store(0);
    g_countdown.store(n < 1 ? 1 : n);
}
void oom_disarm(void) { g_countdown.store(-1); }
int oom_tripped(void) { return g_tripped.load(); }
long oom_counted(void) { return g_counted.load(); }
long oom_total_allocations(void) { return g_total.load(); }
}

void *operator new(std::size_t n) {
    if (void *p = plain(n)) return p;
    throw std::bad_alloc();
}
void *operator new[](std::size_t n) {
    if (void *p = plain(n)) return p;
    throw std::bad_alloc();
}
void *operator new(std::size_t n, const std::nothrow_t &) noexcept { return plain(n); }
void *operator new[](std::size_t n, const std::nothrow_t &) noexcept { return plain(n); }
void *operator new(std::size_t n, std::align_val_t al) {
    if (void *p = aligned(n, al)) return p;
    throw std::bad_alloc();
}
void *operator new[](std::size_t n, std::align_val_t al) {
    if (void *p = aligned(n, al)) return p;
    throw std::bad_alloc();
}
void *operator new(std::size_t n, std::align_val_t al, const std::nothrow_t &) noexcept { return aligned(n, al); }
void *operator new[](std::size_t n, std::align_val_t al, const std::nothrow_t &) noexcept { return aligned(n, al); }

void operator delete(void *p) noexcept { std::free(p); }
void operator delete[](void *p) noexcept { std::free(p); }
void operator delete(void *p, std::size_t) noexcept { std::free(p); }
void operator delete[](void *p, std::size_t) noexcept { std::free(p); }
void operator delete(void *p, const std::nothrow_t &) noexcept { std::free(p); }
void operator delete[](void *p, const std::nothrow_t &) noexcept { std::free(p); }
void operator delete(void *p, std::align_val_t) noexcept { std::free(p); }
void operator delete[](void *p, std::align_val_t) noexcept { std::free(p); }
void operator delete(void *p, std::size_t, std::align_val_t) noexcept { std::free(p); }
void operator delete[](void *p, std::size_t, std::align_val_t) noexcept { std::free(p); }
void operator delete(void *p, std::align_val_t, const std::nothrow_t &) noexcept { std::free(p); }
void operator delete[](void *p, std::align_val_t, const std::nothrow_t &) noexcept { std::free(p); }
