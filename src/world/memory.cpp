#include "world/memory.hpp"

#include <atomic>
#include <cstdint>

#if defined(__linux__)
#include <sys/mman.h>
#endif

#include "common/ieee.hpp"  // (every source refuses -ffast-math: see ieee.hpp)

namespace hgcd {

namespace {

// Below this, or where there are no huge pages to ask for, operator new.
constexpr size_t kHugePage = size_t(1) << 21;

#if defined(__linux__) && defined(MADV_HUGEPAGE)
constexpr bool kHugePages = true;
constexpr size_t kPage = 4096;

size_t round_up(size_t v, size_t to) { return (v + to - 1) & ~(to - 1); }

// An array in huge pages starts this far into its first one (a multiple of
// 64 bytes, at least 64: the 8 bytes before the array keep it), different
// from one array to the next: arrays all at one offset from a 2 MiB
// boundary share cache sets (the seven box arrays of a grid list are read
// at one index together, and conflicted so).
size_t next_colour() {
    static std::atomic<unsigned> counter{0};
    return (counter.fetch_add(1, std::memory_order_relaxed) % 29 + 1) * (kPage + 64);
}
#else
constexpr bool kHugePages = false;
#endif

bool in_huge_pages(size_t bytes, size_t align) { return kHugePages && bytes >= kHugePage && align <= 64; }

}  // namespace

void *allocate_large(size_t bytes, size_t align) {
    if (!in_huge_pages(bytes, align))
        return align > __STDCPP_DEFAULT_NEW_ALIGNMENT__ ? ::operator new(bytes, std::align_val_t(align))
                                                        : ::operator new(bytes);
#if defined(__linux__) && defined(MADV_HUGEPAGE)
    // Straight from the system (mmap), not malloc's heap: freed, the pages go
    // back at once, where the heap could keep the old arrays of a growing
    // world resident.
    const size_t colour = next_colour();
    if (bytes > SIZE_MAX / 2) throw std::bad_alloc();
    const size_t length = round_up(bytes + colour, kPage);
    void *m = mmap(nullptr, length + kHugePage, PROT_READ | PROT_WRITE, MAP_PRIVATE | MAP_ANONYMOUS, -1, 0);
    if (m == MAP_FAILED) throw std::bad_alloc();
    const uintptr_t start = reinterpret_cast<uintptr_t>(m), base = round_up(start, kHugePage);
    if (base > start) munmap(m, base - start);
    munmap(reinterpret_cast<void *>(base + length), start + length + kHugePage - (base + length));
    // Whole huge pages only: the last, partly used, stays in small pages.
    // (Advice: where it is refused, the memory is the same, in small pages.)
    madvise(reinterpret_cast<void *>(base), (bytes + colour) & ~(kHugePage - 1), MADV_HUGEPAGE);
    unsigned char *p = reinterpret_cast<unsigned char *>(base) + colour;
    reinterpret_cast<size_t *>(p)[-1] = colour;
    return p;
#else
    return nullptr;  // (not reached)
#endif
}

void free_large(void *p, size_t bytes, size_t align) noexcept {
    if (!p) return;
    if (!in_huge_pages(bytes, align)) {
        if (align > __STDCPP_DEFAULT_NEW_ALIGNMENT__)
            ::operator delete(p, std::align_val_t(align));
        else
            ::operator delete(p);
        return;
    }
#if defined(__linux__) && defined(MADV_HUGEPAGE)
    unsigned char *q = static_cast<unsigned char *>(p);
    const size_t colour = reinterpret_cast<size_t *>(q)[-1];
    munmap(q - colour, round_up(bytes + colour, kPage));
#endif
}

}  // namespace hgcd
