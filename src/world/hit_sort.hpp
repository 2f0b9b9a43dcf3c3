// Sorting a thread's hit keys (slot a << 32 | slot b) before the merge
// (src/world/merge_hits.cpp).
#pragma once

#include <cstdint>
#include <vector>

#include <hgcd/hgcd.h>

namespace hgcd {

// Ascending; tmp is scratch, kept by the caller across detects.
void sort_keys(std::vector<uint64_t> &keys, std::vector<uint64_t> &tmp);
// Ascending, the contacts (parallel to the keys) moved with them.
void sort_with_contacts(std::vector<uint64_t> &keys, std::vector<hgcd_contact> &contacts);

}  // namespace hgcd
