#pragma once
#include <cstdint>
namespace hgcd {
// Written by every hgcd_*_desc_default(); a descriptor without it was not
// initialised by the library.
constexpr uint32_t kInitTag = 0x44434748u;  // "HGCD"
}  // namespace hgcd
