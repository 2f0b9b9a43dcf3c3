// Memory for the world's arrays of a value per body: from 2 MiB up it comes
// straight from the system (mmap), aligned to 2 MiB and marked for
// transparent huge pages (Linux's madvise MADV_HUGEPAGE, honoured when
// /sys/kernel/mm/transparent_hugepage/enabled says "always" or "madvise").
// The narrow phase reads placements at the candidates' storage indices, the
// gather reads points and offsets where bodies that changed rows left them,
// and the pairs look their slots up at random: with 4 KiB pages a 750k-body
// world's 114 MB of these arrays span 28 k pages, far more than the TLB
// holds. The grid's lists and the candidate buffers, read in sequence,
// gained nothing so. Only whole huge pages are marked (the last,
// partly used, stays in small pages), so resident memory does not grow.
// Elsewhere, and below 2 MiB, operator new.
#pragma once
#include <cstddef>
#include <cstdint>
#include <new>
#include <vector>

namespace hgcd {

// bytes at alignment `align` (a power of two); throws std::bad_alloc.
void *allocate_large(size_t bytes, size_t align);
// Gives back what allocate_large(bytes, align) returned (nullptr: nothing).
void free_large(void *p, size_t bytes, size_t align) noexcept;

template <class T>
struct LargeAllocator {
    using value_type = T;
    LargeAllocator() = default;
    template <class U>
    LargeAllocator(const LargeAllocator<U> &) noexcept {}
    T *allocate(size_t n) {
        if (n > SIZE_MAX / sizeof(T)) throw std::bad_array_new_length();
        return static_cast<T *>(allocate_large(n * sizeof(T), alignof(T)));
    }
    void deallocate(T *p, size_t n) noexcept { free_large(p, n * sizeof(T), alignof(T)); }
};
template <class T, class U>
bool operator==(const LargeAllocator<T> &, const LargeAllocator<U> &) noexcept {
    return true;
}
template <class T, class U>
bool operator!=(const LargeAllocator<T> &, const LargeAllocator<U> &) noexcept {
    return false;
}

template <class T>
using LargeVector = std::vector<T, LargeAllocator<T>>;

}  // namespace hgcd
