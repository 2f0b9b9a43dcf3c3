// The records of small meshes, packed in one array of 32-byte blocks, and
// laid out again, when the world renumbers its bodies' storage, in the order
// in which the bodies (in storage order) first use them. A mesh's record is
// what the per-body passes read in place of its Mesh: a world whose every
// body has a small mesh of its own then reads the records nearly in
// sequence, beside the placements, where a Mesh per body (a struct and heap
// blocks each, in creation order) was a scattered read per body; a shared
// mesh stays one record, in cache.
//
// The record of a mesh of at most Mesh::kExactBoxTriangles triangles: the
// distinct vertices its triangles use (mesh frame), in groups of 4 points, a
// group being 3 blocks (x of the 4 points, then y, then z), the last group
// padded with copies of its first point (which change no box). A body's box
// is theirs (world/pose_box.hpp). A tetrahedron's is its tetra_local (one
// group), which the narrow phase's batched kernels read (narrow.hpp,
// TetraPair). Larger meshes have none.
#pragma once
#include <cstddef>
#include <cstdint>
#include <vector>

#include "world/mesh.hpp"

namespace hgcd {

// The groups of 4 points of mesh m's record (0: none), and the record itself
// (3 blocks a group) into out.
uint32_t record_groups(const Mesh &m);
void write_record(const Mesh &m, double *out);

class MeshPool {
public:
    static constexpr uint32_t kNone = UINT32_MAX;
    struct alignas(32) Block {
        double d[4];
    };

    MeshPool() = default;
    MeshPool(const MeshPool &) = delete;
    MeshPool &operator=(const MeshPool &) = delete;
    ~MeshPool();

    // Makes room for the record of mesh m, to be added at mesh slot `slot`,
    // so that add() cannot fail. Throws std::bad_alloc (nothing changed).
    void reserve(uint32_t slot, const Mesh &m);
    // The record of mesh m at `slot` (none for a mesh without one), after
    // reserve(slot, m).
    void add(uint32_t slot, const Mesh &m) noexcept;
    // Returns whether the records moved (offsets changed).
    bool remove(uint32_t slot) noexcept;
    // The first block of the record of the mesh at `slot`, or kNone.
    uint32_t offset(uint32_t slot) const { return offset_[slot]; }
    // The groups of 4 points of that record (0: none).
    uint32_t groups(uint32_t slot) const { return size_[slot] / 3; }
    const uint32_t *sizes() const { return size_.data(); }
    // The record of the mesh at `slot`, or null when it has none.
    const double *record(uint32_t slot) const {
        return slot < offset_.size() && offset_[slot] != kNone ? data_[offset_[slot]].d : nullptr;
    }
    // Valid until the next call that changes the pool.
    const Block *blocks() const { return data_; }
    const uint32_t *offsets() const { return offset_.data(); }

    // Lays the records out again in the order of first use by the bodies
    // stored at 0..n-1 (body_mesh: their mesh slots; live[i] == 0: storage i
    // is free), then the records no body uses. Only speed depends on the
    // order: without the memory for it, nothing changes. Returns whether the
    // records moved.
    bool repack(const uint32_t *body_mesh, const uint32_t *live, size_t n) noexcept;

private:
    bool grow(size_t blocks);  // capacity for `blocks` in all (false: no memory)
    Block *data_ = nullptr;
    size_t capacity_ = 0, end_ = 0;  // blocks allocated, and up to the last record
    size_t used_ = 0;                // blocks in records (end_ less the holes)
    std::vector<uint32_t> offset_;   // per mesh slot: first block, or kNone
    std::vector<uint32_t> size_;     // per mesh slot: blocks
};

}  // namespace hgcd
