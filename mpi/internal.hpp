// The distributed world's state and the helpers its calls share. Built on the
// public hgcd API only (hgcd.h): each rank's bodies live in an ordinary
// hgcd_world.
#pragma once

#include <cstdint>
#include <string>
#include <unordered_map>
#include <unordered_set>
#include <vector>

// The C bindings only: OpenMPI's C++ ones are deprecated and noisy.
#define OMPI_SKIP_MPICXX 1
#define MPICH_SKIP_MPICXX 1
#include "hgcd/hgcd_mpi.h"

namespace hgcd_mpi {

constexpr uint32_t kInitTag = 0x4d504948u;  // "HIPM"

// A body as it travels between ranks (migration, ghosts, adds): 80 bytes,
// sent as raw bytes so every double arrives bit for bit.
struct Record {
    uint64_t id;
    uint32_t mesh;
    uint32_t pad;
    double position[3];
    double orientation[4];
    double scale;
};
static_assert(sizeof(Record) == 80, "Record is sent as 80 raw bytes");

// An axis-aligned box; empty when lo > hi.
struct Box {
    double lo[3], hi[3];
    static Box empty();
    bool meets(const Box &o) const;
    void grow(const Box &o);
};

// One node of the recursive coordinate bisection: an inner node cuts on axis
// at cut (x < cut: left), a leaf names a rank.
struct Node {
    int32_t axis;
    int32_t rank;  // >= 0 for a leaf
    int32_t left, right;
    double cut;
};

struct Decomposition {
    std::vector<Node> nodes;  // nodes[0] the root; one leaf (rank 0) at first
    std::vector<Box> domains;  // per rank, unbounded faces at +-infinity
    void single(int ranks);
    int locate(const double *p) const;
    void compute_domains(int ranks);
};

struct Mesh {
    hgcd_mesh local;     // in the local world
    hgcd_mesh checking;  // in the checking world
    double reach;        // hgcd_mesh_info.reach
};

// A body in this rank's local world: owned or ghost.
struct Bodies {
    std::vector<Record> rec;
    std::vector<hgcd_body> local;
    std::unordered_map<uint64_t, uint32_t> index;  // id -> position in rec
    void push(const Record &r, hgcd_body b);
    void erase_at(uint32_t k);  // swap with the last
};

}  // namespace hgcd_mpi

struct hgcd_mpi_world {
    MPI_Comm comm = MPI_COMM_NULL;
    int rank = 0, size = 1;
    double imbalance_factor = 1.2, motion_allowance = 0;
    int threads = 1;  // OpenMP threads of this rank's loops over its bodies
    hgcd_world *local = nullptr;     // owned and ghost bodies
    hgcd_world *checking = nullptr;  // validates new bodies as hgcd would
    bool broken = false;             // out of memory mid-way: unusable
    std::string error;
    std::vector<hgcd_mpi::Mesh> meshes;
    hgcd_mpi::Decomposition decomp;
    hgcd_mpi::Bodies owned, ghosts;
    std::vector<uint64_t> owned_ids;  // parallel to owned.rec
    // Local body index -> global id and whether owned (for the owner rule).
    std::vector<uint64_t> id_of_local;
    std::vector<uint8_t> owned_of_local;
    // The local world's live bodies hold exactly the indices 0 .. live-1
    // (kept so by local_destroy), so poses go through hgcd_world_set_poses
    // by index, its fast path. dense turns false for good if hgcd ever
    // places a body elsewhere (its reuse order is not a documented
    // promise); the listed-id path then serves, with the same results.
    uint32_t live = 0;
    bool dense = true;
    std::vector<double> pose_buffer;
    std::unordered_set<uint64_t> directory;  // live ids with id % size == rank
    uint64_t global_bodies = 0;
    std::vector<hgcd_mpi_pair> pairs, gathered;
    hgcd_mpi_stats stats{}, last_stats{};  // counting now; of the last detect
};

namespace hgcd_mpi {

// Records msg as the world's error and returns status.
hgcd_status fail(hgcd_mpi_world *w, hgcd_status status, const std::string &msg);

// Collective: every rank learns the first (lowest rank's) non-OK status and
// its message, records it and returns it; OK when every rank is OK.
hgcd_status agree(hgcd_mpi_world *w, hgcd_status status, const std::string &what);

// Collective all-to-all of bytes: out[r] goes to rank r; returns what each
// rank sent here, concatenated in rank order. Counts into w->stats.
std::vector<char> exchange(hgcd_mpi_world *w, const std::vector<std::vector<char>> &out);

// Point-to-point exchange with a symmetric set of neighbour ranks (each rank
// lists the other): out[k] goes to peers[k]; returns what they sent here.
std::vector<char> exchange_neighbours(hgcd_mpi_world *w, const std::vector<int> &peers,
                                      const std::vector<std::vector<char>> &out);

// The box holding a body's solid: position +- conservative reach.
Box body_box(const hgcd_mpi_world *w, const Record &r);

// Collective RCB over each rank's points (xyz triples); sets w->decomp.
void rcb(hgcd_mpi_world *w, const std::vector<double> &points);

// Local world maintenance (throw std::bad_alloc when hgcd runs out).
hgcd_body local_create(hgcd_mpi_world *w, const Record &r, bool owned);
void local_destroy(hgcd_mpi_world *w, hgcd_body b);
void add_owned(hgcd_mpi_world *w, const Record &r);
void remove_owned_at(hgcd_mpi_world *w, uint32_t k);
void remove_ghost_at(hgcd_mpi_world *w, uint32_t k);

// Collective: sends every owned body whose position left this rank's
// subdomain (by more than the allowance unless all) to its owner.
void migrate(hgcd_mpi_world *w, bool all);

double now();

}  // namespace hgcd_mpi
