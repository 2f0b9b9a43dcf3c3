// Reordering arrays in place by a permutation, without a second copy of
// them: what renumbering the bodies' storage needs (world.cpp, grid.cpp).
#pragma once
#include <cstddef>
#include <cstdint>
#include <vector>

namespace hgcd {

// Moves element old_of_new[k] to position k for every k < n, following the
// permutation's cycles: load(k) returns element k (all of its arrays' values
// as one record), store(k, record) writes it. `done` is scratch for n bits.
// Reads are sequential when the permutation only moves elements a little
// (the usual renumbering), random the first time.
template <class Load, class Store>
void permute_in_place(const uint32_t *old_of_new, size_t n, std::vector<uint64_t> &done, Load load,
                      Store store) {
    done.assign((n + 63) / 64, 0);
    for (size_t start = 0; start < n; ++start) {
        if ((done[start / 64] >> (start % 64)) & 1) continue;
        if (old_of_new[start] == start) continue;
        const auto held = load(start);
        size_t k = start;
        for (;;) {
            done[k / 64] |= uint64_t(1) << (k % 64);
            const size_t from = old_of_new[k];
            if (from == start) break;
            store(k, load(from));
            k = from;
        }
        store(k, held);
    }
}

}  // namespace hgcd
