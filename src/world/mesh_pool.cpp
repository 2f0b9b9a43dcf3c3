// The packed records of small meshes (mesh_pool.hpp).
#include "common/ieee.hpp"
#include "world/mesh_pool.hpp"

#include <algorithm>
#include <array>
#include <cstring>
#include <new>

#include "world/memory.hpp"

namespace hgcd {

namespace {

// The distinct vertices the triangles of mesh m (of at most
// Mesh::kExactBoxTriangles triangles) use, in index order, into `out`;
// returns their count. No allocation: add() may not throw.
using UsedVertices = std::array<uint32_t, 3 * Mesh::kExactBoxTriangles>;
size_t used_vertices(const Mesh &m, UsedVertices &out) {
    const size_t n = m.triangles.size();
    std::copy(m.triangles.begin(), m.triangles.end(), out.begin());
    std::sort(out.begin(), out.begin() + n);
    return size_t(std::unique(out.begin(), out.begin() + n) - out.begin());
}

}  // namespace

uint32_t record_groups(const Mesh &m) {
    if (m.tetra) return 1;
    if (m.triangle_count > Mesh::kExactBoxTriangles) return 0;
    UsedVertices v;
    return uint32_t((used_vertices(m, v) + 3) / 4);
}

void write_record(const Mesh &m, double *out) {
    if (m.tetra) {
        std::copy(m.tetra_local, m.tetra_local + 12, out);
        return;
    }
    UsedVertices v;
    const size_t count = used_vertices(m, v);
    for (size_t g = 0; g < count; g += 4, out += 12)
        for (size_t k = 0; k < 4; ++k) {
            const double *p = &m.vertices[3 * size_t(v[g + k < count ? g + k : g])];
            for (int a = 0; a < 3; ++a) out[4 * a + k] = p[a];
        }
}

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
    if (!grow(end_ + 3 * size_t(record_groups(m)))) throw std::bad_alloc();
}

void MeshPool::add(uint32_t slot, const Mesh &m) noexcept {
    const uint32_t n = 3 * record_groups(m);
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
