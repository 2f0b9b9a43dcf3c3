// Reordering per-body arrays by a permutation: what renumbering the bodies'
// storage needs (the world's arrays and the grid's per-body ones).
#pragma once
#include <cstddef>
#include <cstdint>
#include <cstring>

#include "common/parallel.hpp"

namespace hgcd {

// Bytes of scratch per element that permute_part needs at most (its
// kBytes): larger records are moved a part at a time.
constexpr size_t kPermuteScratch = 32;

// Moves bytes [0, kBytes) of element old_of_new[k] to element k, for every
// k < n, in an array of elements `stride` bytes apart from `base`: a gather
// into scratch (room for n * kBytes bytes), then a copy back, each a
// parallel loop on `threads` workers. The loads of the gather are
// independent, so many are in flight at once: following the permutation's
// cycles in place waited for each read before the next.
// (The loops take their pointers as arguments: as the loop body's
// captures they were reloaded after every copy, which might write them.)
template <size_t kBytes>
void gather_part(unsigned char *to, const unsigned char *from, size_t stride, const uint32_t *old_of_new, int64_t b,
                 int64_t e) {
    for (int64_t k = b; k < e; ++k) std::memcpy(to + size_t(k) * kBytes, from + size_t(old_of_new[k]) * stride, kBytes);
}
template <size_t kBytes>
void scatter_part(unsigned char *to, const unsigned char *from, size_t stride, int64_t b, int64_t e) {
    for (int64_t k = b; k < e; ++k) std::memcpy(to + size_t(k) * stride, from + size_t(k) * kBytes, kBytes);
}

template <size_t kBytes>
void permute_part(void *base, size_t stride, const uint32_t *old_of_new, size_t n, void *scratch, int threads) {
    static_assert(kBytes <= kPermuteScratch, "scratch too small");
    unsigned char *const a = static_cast<unsigned char *>(base);
    unsigned char *const s = static_cast<unsigned char *>(scratch);
    parallel_for(threads, int64_t(n), 4096, Schedule::Static,
                 [=](int64_t b, int64_t e, int) { gather_part<kBytes>(s, a, stride, old_of_new, b, e); });
    parallel_for(threads, int64_t(n), 4096, Schedule::Static,
                 [=](int64_t b, int64_t e, int) { scatter_part<kBytes>(a, s, stride, b, e); });
}

// The same for an array of n records of kBytes bytes each (T: the element
// type, kPer elements a record).
template <size_t kPer, class T>
void permute_records(T *a, const uint32_t *old_of_new, size_t n, void *scratch, int threads) {
    permute_part<kPer * sizeof(T)>(a, kPer * sizeof(T), old_of_new, n, scratch, threads);
}

}  // namespace hgcd
