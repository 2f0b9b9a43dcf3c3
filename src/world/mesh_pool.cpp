// The packed records of small meshes (mesh_pool.hpp).
#include "common/ieee.hpp"
#include "world/mesh_pool.hpp"

#include <cstring>
#include <new>

#include "narrow/narrow.hpp"
#include "world/memory.hpp"

namespace hgcd {

MeshPool::~MeshPool() { free_large(data_, capacity_ * sizeof(Block), alignof(Block)); }

bool MeshPool::grow(size_t blocks) {
    if (blocks <= capacity_) return true;
    const size_t cap = std::max(blocks, 2 * capacity_ + 16);
    Block *fresh;
    try {
        fresh = static_cast<Block *>(allocate_large(cap * sizeof(Block), alignof(Block)));
    } catch (const std::bad_alloc &) {
        return false;
    }
    if (end_) std::memcpy(static_cast<void *>(fresh), data_, end_ * sizeof(Block));
    free_large(data_, capacity_ * sizeof(Block), alignof(Block));
    data_ = fresh;
    capacity_ = cap;
    return true;
}

void MeshPool::reserve(uint32_t slot, const Mesh &m) {
    // (Each on its own: a failed resize of the second leaves the first grown.)
    if (offset_.size() <= slot) offset_.resize(size_t(slot) + 1, kNone);
    if (size_.size() <= slot) size_.resize(size_t(slot) + 1, 0);
    if (!grow(end_ + record_blocks(m))) throw std::bad_alloc();
}

void MeshPool::add(uint32_t slot, const Mesh &m) noexcept {
    const uint32_t n = record_blocks(m);
    offset_[slot] = n ? uint32_t(end_) : kNone;
    size_[slot] = n;
    if (!n) return;
    write_record(m, data_[end_].d);
    end_ += n;
    used_ += n;
}

bool MeshPool::remove(uint32_t slot) noexcept {
    if (slot >= offset_.size() || offset_[slot] == kNone) return false;
    used_ -= size_[slot];
    offset_[slot] = kNone;
    size_[slot] = 0;
    // Holes are closed when they reach half the pool (or by the next repack).
    return end_ > 64 && 2 * used_ < end_ && repack(nullptr, nullptr, 0);
}

bool MeshPool::repack(const uint32_t *body_mesh, const uint32_t *live, size_t n) noexcept {
    if (!used_) {
        end_ = 0;
        return false;
    }
    Block *fresh;
    std::vector<uint32_t> where;
    try {
        where.assign(offset_.size(), kNone);
        fresh = static_cast<Block *>(allocate_large(capacity_ * sizeof(Block), alignof(Block)));
    } catch (const std::bad_alloc &) {
        return false;
    }
    size_t at = 0;
    auto place = [&](uint32_t m) {
        if (offset_[m] == kNone || where[m] != kNone) return;
        where[m] = uint32_t(at);
        std::memcpy(static_cast<void *>(fresh + at), data_ + offset_[m], size_[m] * sizeof(Block));
        at += size_[m];
    };
    for (size_t i = 0; i < n; ++i)
        if (live[i]) place(body_mesh[i]);
    for (uint32_t m = 0; m < uint32_t(offset_.size()); ++m) place(m);
    free_large(data_, capacity_ * sizeof(Block), alignof(Block));
    data_ = fresh;
    end_ = used_ = at;
    offset_.swap(where);
    return true;
}

}  // namespace hgcd
