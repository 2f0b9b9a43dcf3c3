/*
 * hgcd_mpi: hgcd over MPI, by spatial domain decomposition. An optional
 * library (libhgcd_mpi, built only where OpenMPI is found) on top of the
 * public hgcd API: libhgcd itself never depends on MPI.
 *
 * A distributed world spans the ranks of the caller's communicator. Every
 * body has a global id chosen by the caller (any uint64_t, unique in the
 * world), kept across ranks and migrations. Each rank owns the bodies whose
 * position lies in its subdomain, keeps ghost copies of the bodies near its
 * own, runs an ordinary hgcd world (hgcd.h) on owned and ghost bodies, and
 * reports each colliding pair on exactly one rank. The union of the ranks'
 * pairs is exactly the pairs a single hgcd world holding every body reports
 * (same meshes, poses and scales, bit for bit): every pair is decided by the
 * same exact test on the same world-space vertices.
 *
 * The loop
 * --------
 *   hgcd_mpi_world_create     collective: a world over a communicator
 *   hgcd_mpi_mesh_register    collective: each shape, the same data on every
 *                             rank, in the same order (mesh 0, 1, 2, ...)
 *   hgcd_mpi_bodies_add       collective: each rank passes any bodies (or
 *                             none); each goes to the rank owning its position
 *   every tick:
 *     hgcd_mpi_owned          local: the ids this rank owns now
 *     hgcd_mpi_set_poses      local: new poses of owned bodies
 *     hgcd_mpi_detect         collective: migrate, rebalance, exchange
 *                             ghosts, detect
 *     hgcd_mpi_pairs          local: the pairs this rank reports
 *     (hgcd_mpi_gather_pairs  collective: every pair, sorted, on one rank)
 *   hgcd_mpi_world_destroy    collective
 *
 * Decomposition. Space is cut by recursive coordinate bisection (RCB) of the
 * body counts: the ranks are split in two halves (the first floor(p/2) ranks
 * and the rest), the bodies' positions are cut by a plane normal to the
 * longest side of their bounding box so that each side holds its share of the
 * bodies in proportion to its ranks, and so on down to one rank per
 * subdomain. Subdomains cover all space (the outer ones are unbounded); a
 * position on a cut belongs to the upper side. The cut is computed on the
 * first hgcd_mpi_bodies_add that finds the world empty, and again by
 * hgcd_mpi_detect whenever the most loaded rank owns more than
 * imbalance_factor times the mean (and more than one body above it).
 *
 * Migration. hgcd_mpi_detect first sends every owned body whose position left
 * the rank's subdomain by more than motion_allowance (distance measured per
 * axis) to the rank whose subdomain holds it; after a rebalance, every body
 * goes to the subdomain holding it.
 *
 * Halo. A body's reach is r = scale * hgcd_mesh_info.reach, enlarged by a
 * relative 1e-5 and by the rounding of its position (enough for every
 * quaternion hgcd accepts and every floating-point mode), so its solid lies
 * in the box [position - r, position + r]. Each rank publishes S, the
 * bounding box of its owned bodies' boxes: its subdomain (or, with a motion
 * allowance, the subdomain grown by it), grown by the largest reach of its
 * own bodies. A rank receives as a ghost every body of another rank whose box
 * meets its S. So the halo of a rank is its region, plus the largest reach
 * among its bodies, plus the motion allowance, plus each ghost's own reach;
 * the contact margin is 0 because hgcd reports exactly the bodies that share
 * a point. A body larger than a subdomain is ghosted to every rank its box
 * meets.
 *
 * Owner rule. A colliding pair {a, b}, a < b, is reported by the rank owning
 * body a (the lower global id). That rank sees the pair: b's solid meets a's,
 * so b's box meets a's box, which lies in the rank's S. Pairs of two ghosts
 * found by a rank's local world are dropped there.
 *
 * Conventions (for every function unless its comment says otherwise)
 * -----------
 * Collective calls must be called by every rank of the communicator, in the
 * same order. A collective call refused on one rank is refused on every rank
 * with the same status and message (the message of the lowest rank that
 * found a fault, naming that rank), and then changes nothing on any rank. A
 * NULL world cannot take part: the call returns HGCD_ERROR_NULL_ARGUMENT on
 * that rank at once, and the other ranks wait for it (an MPI program error,
 * as a missing MPI call). Local calls involve this rank only.
 * Statuses and ownership follow hgcd.h: hgcd_status codes, inputs copied,
 * returned arrays owned by the world and valid until the next call that
 * changes it; hgcd_mpi_world_last_error gives the message.
 * Threads: one world, one thread at a time; the calls use the world's
 * communicator (a duplicate of the caller's), so MPI must be initialised
 * with at least MPI_THREAD_FUNNELED if other threads exist, and finalized
 * only after hgcd_mpi_world_destroy. The local hgcd world runs OpenMP
 * regions of thread_count threads inside hgcd_mpi_detect.
 * Out of memory after a collective call has agreed to go ahead (while bodies
 * are being moved) leaves the world unusable: that call and every later one
 * return HGCD_ERROR_OUT_OF_MEMORY, except hgcd_mpi_world_destroy.
 */
#ifndef HGCD_MPI_H
#define HGCD_MPI_H

#include <stddef.h>
#include <stdint.h>

#include <mpi.h>

#include <hgcd/hgcd.h>

#ifdef __cplusplus
extern "C" {
#endif

/** Opaque distributed world: one per rank, created and destroyed
 *  collectively. */
typedef struct hgcd_mpi_world hgcd_mpi_world;

/** One colliding pair, by global ids: a < b. */
typedef struct hgcd_mpi_pair {
    uint64_t a;
    uint64_t b;
} hgcd_mpi_pair;

/** Distributed world descriptor: from hgcd_mpi_world_desc_default(), then
 *  change fields. The same values must be given on every rank (checked). */
typedef struct hgcd_mpi_world_desc {
    /** sizeof(hgcd_mpi_world_desc), set by hgcd_mpi_world_desc_default(). */
    uint32_t struct_size;
    /** Set by hgcd_mpi_world_desc_default(); catches uninitialised
     *  descriptors. */
    uint32_t init_tag;
    /** OpenMP threads of each rank's local hgcd world (0, the default: all
     *  cores; at most 4096). May differ between ranks. */
    uint32_t thread_count;
    /** Always 0. */
    uint32_t reserved;
    /** Rebalance when the most loaded rank owns more than this factor times
     *  the mean number of bodies per rank. Finite, >= 1; default 1.2. */
    double imbalance_factor;
    /** How far (per axis) an owned body may stray outside its rank's
     *  subdomain before it migrates. Larger values migrate fewer bodies back
     *  and forth across a cut and widen the halo by as much. Finite, >= 0;
     *  default 0. Never changes the pairs. */
    double motion_allowance;
} hgcd_mpi_world_desc;

/** A descriptor with every default. Any thread. */
HGCD_API hgcd_mpi_world_desc hgcd_mpi_world_desc_default(void);

/** Collective. Creates an empty distributed world over comm (duplicated:
 *  the world's messages never mix with the caller's; comm may be freed
 *  after the call). Every rank gets its own *out_world (NULL on failure).
 *  MPI must be initialised.
 *  Errors: NULL_ARGUMENT (desc or out_world), BAD_DESCRIPTOR,
 *  INVALID_ARGUMENT (a field out of range, comm MPI_COMM_NULL or an
 *  intercommunicator, or imbalance_factor or motion_allowance differing
 *  between ranks), OUT_OF_MEMORY. No message is recorded (there is no
 *  world). Cost: MPI_Comm_dup and one allreduce. */
HGCD_API hgcd_status hgcd_mpi_world_create(MPI_Comm comm,
                                           const hgcd_mpi_world_desc *desc,
                                           hgcd_mpi_world **out_world);

/** Collective. Frees the world (its duplicated communicator included).
 *  NULL is a no-op (on that rank only: every rank must pass NULL or a world
 *  together). */
HGCD_API void hgcd_mpi_world_destroy(hgcd_mpi_world *world);

/** The message of the last refused call on this world, "" if none. Owned by
 *  the world, valid until the next call that changes it. Local. */
HGCD_API const char *hgcd_mpi_world_last_error(const hgcd_mpi_world *world);

/** This rank's number in the world's communicator, and the number of ranks.
 *  Errors: NULL_ARGUMENT. Local, O(1). */
HGCD_API hgcd_status hgcd_mpi_world_rank(const hgcd_mpi_world *world,
                                         int *out_rank, int *out_size);

/** Number of live bodies in the whole world (all ranks), as of the last
 *  collective call. NULL world gives 0. Local, O(1). */
HGCD_API uint64_t hgcd_mpi_world_body_count(const hgcd_mpi_world *world);

/** Collective. Registers a mesh: every rank passes the same vertices and
 *  triangles (compared through a 64-bit hash of the counts and bytes), in
 *  the same order; the n-th registered mesh gets id n (0, 1, 2, ...),
 *  written to *out_mesh. The data are checked as hgcd_mesh_create checks
 *  them and copied in. Meshes are never removed.
 *  Errors: NULL_ARGUMENT, BAD_DESCRIPTOR, INVALID_MESH (as
 *  hgcd_mesh_create), INVALID_ARGUMENT (the data differ between ranks),
 *  CAPACITY, OUT_OF_MEMORY. Cost: as hgcd_mesh_create (twice: the local
 *  world and a checking world) plus three allreduces. */
HGCD_API hgcd_status hgcd_mpi_mesh_register(hgcd_mpi_world *world,
                                            const hgcd_mesh_desc *desc,
                                            uint32_t *out_mesh);

/** A body to add: from hgcd_mpi_body_desc_default(), then set id and mesh. */
typedef struct hgcd_mpi_body_desc {
    /** sizeof(hgcd_mpi_body_desc), set by hgcd_mpi_body_desc_default(). */
    uint32_t struct_size;
    /** Set by hgcd_mpi_body_desc_default(); catches uninitialised
     *  descriptors. */
    uint32_t init_tag;
    /** The caller's global id: any value not live in the world. */
    uint64_t id;
    /** A registered mesh (hgcd_mpi_mesh_register). Default 0. */
    uint32_t mesh;
    /** Always 0. */
    uint32_t reserved;
    /** Position, orientation (x, y, z, w) and scale, with the rules of
     *  hgcd_body_desc (hgcd.h). Defaults (0, 0, 0), (0, 0, 0, 1), 1. */
    double position[3];
    double orientation[4];
    double scale;
} hgcd_mpi_body_desc;

/** A body descriptor with the defaults. Any thread. */
HGCD_API hgcd_mpi_body_desc hgcd_mpi_body_desc_default(void);

/** Collective. Adds bodies: each rank passes its own count descriptors
 *  (count 0 and descs NULL is fine), and each body goes to the rank owning
 *  its position. If the world held no body, the decomposition is first
 *  computed from the bodies added.
 *  Errors (nothing is added anywhere): NULL_ARGUMENT (descs NULL with count
 *  > 0), BAD_DESCRIPTOR, INVALID_ARGUMENT (a value hgcd_body_create refuses,
 *  an unregistered mesh, an id given twice in the call or already live; the
 *  message names the entry or id), CAPACITY, OUT_OF_MEMORY.
 *  Cost: O(count) checks (each body is created and destroyed in a checking
 *  world), two all-to-all exchanges (ids to the rank keeping the id
 *  directory, id % ranks; bodies to their owners), a few allreduces; the
 *  first add of an empty world also computes the decomposition (about 64
 *  allreduces per level of log2(ranks)). */
HGCD_API hgcd_status hgcd_mpi_bodies_add(hgcd_mpi_world *world,
                                         const hgcd_mpi_body_desc *descs,
                                         size_t count);

/** Collective. Removes bodies by id: each rank passes any ids (owned here
 *  or not; count 0 and ids NULL is fine). The pairs of the last detect keep
 *  listing them until the next detect.
 *  Errors (nothing is removed): NULL_ARGUMENT, INVALID_ARGUMENT (an id not
 *  live, or given twice over all ranks; the message names it),
 *  OUT_OF_MEMORY. Cost: an allgather of every rank's ids, so
 *  O(total ids removed) on every rank. */
HGCD_API hgcd_status hgcd_mpi_bodies_remove(hgcd_mpi_world *world,
                                            const uint64_t *ids, size_t count);

/** Local. The ids of the bodies this rank owns: *out_ids points to *out_count
 *  ids owned by the world, in the rank's owned order, which
 *  hgcd_mpi_set_poses with ids NULL follows. Valid until the next call that
 *  changes the world; the collective calls change the set and the order
 *  (migration, adds, removes). Errors: NULL_ARGUMENT. O(1). */
HGCD_API hgcd_status hgcd_mpi_owned(const hgcd_mpi_world *world,
                                    const uint64_t **out_ids,
                                    size_t *out_count);

/** Local. Sets the poses of bodies this rank owns, as hgcd_world_set_poses
 *  (hgcd.h): ids lists count owned ids, each at most once; or ids NULL,
 *  entry k being the k-th owned body (hgcd_mpi_owned), count at most the
 *  owned count. positions: 3 doubles per entry, position_stride bytes apart
 *  (0 = packed); orientations: 4 doubles (x, y, z, w), orientation_stride
 *  apart; either array may be NULL to keep that part, not both. Checked
 *  whole first. Bodies owned elsewhere are set on their owner: an engine
 *  integrates the bodies its rank owns.
 *  Errors (nothing changes): NULL_ARGUMENT, STALE_ID (an id not owned by
 *  this rank, or count above the owned count), INVALID_ARGUMENT (as
 *  hgcd_world_set_poses: a value, an id twice, a stride).
 *  Cost: O(count) (a hash lookup per id when ids is given); with ids NULL
 *  the poses of the whole local world (owned and ghosts, by index: see
 *  hgcd_mpi_stats.poses_by_index) are handed to hgcd, which skips those
 *  whose bits did not change. */
HGCD_API hgcd_status hgcd_mpi_set_poses(hgcd_mpi_world *world,
                                        const uint64_t *ids, size_t count,
                                        const double *positions,
                                        size_t position_stride,
                                        const double *orientations,
                                        size_t orientation_stride);

/** Local. Reads the poses of owned bodies (ids or NULL as in
 *  hgcd_mpi_set_poses; either output may be NULL, not both), bit for bit as
 *  last set or added. Nothing is written on failure.
 *  Errors: NULL_ARGUMENT, STALE_ID, INVALID_ARGUMENT (a stride). O(count). */
HGCD_API hgcd_status hgcd_mpi_get_poses(const hgcd_mpi_world *world,
                                        const uint64_t *ids, size_t count,
                                        double *positions,
                                        size_t position_stride,
                                        double *orientations,
                                        size_t orientation_stride);

/** Collective. One tick: migrates owned bodies that left their subdomain,
 *  rebalances if needed (see the top of this header), exchanges ghosts with
 *  the ranks whose region meets this rank's, runs hgcd_world_detect on the
 *  local world and keeps the pairs this rank reports (the owner rule),
 *  replacing the previous pairs.
 *  Errors: NULL_ARGUMENT; OUT_OF_MEMORY: when a rank's local detect ran
 *  out, every rank returns it with its pairs cleared (bodies untouched: the
 *  next detect may succeed); when moving bodies ran out, the world is
 *  unusable (see the top of this header).
 *  Cost: O(owned + ghosts) per rank plus the local detect; messages: two
 *  allgathers of a few numbers per rank, an all-to-all of counts (migration)
 *  and one point-to-point message each way per neighbouring rank (the
 *  ghosts); a rebalance adds about 64 allreduces per level of
 *  log2(ranks) and moves up to every body. */
HGCD_API hgcd_status hgcd_mpi_detect(hgcd_mpi_world *world);

/** Local. The pairs this rank reports from the last detect: *out_pairs
 *  points to *out_count pairs of global ids (a < b) owned by the world,
 *  each pair's a owned by this rank at that detect. Their order is
 *  deterministic for a given history but otherwise unspecified (the local
 *  world's). The union over ranks is the world's pairs, each on exactly one
 *  rank. Valid until the next call that changes the world.
 *  Errors: NULL_ARGUMENT. O(1). */
HGCD_API hgcd_status hgcd_mpi_pairs(const hgcd_mpi_world *world,
                                    const hgcd_mpi_pair **out_pairs,
                                    size_t *out_count);

/** Collective. Gathers every rank's pairs on rank root, sorted by (a, b):
 *  there *out_pairs points to the *out_count pairs (owned by the world, valid
 *  until the next call that changes it); on the other ranks *out_count is 0.
 *  For tests and small runs: the root holds every pair.
 *  Errors: NULL_ARGUMENT, INVALID_ARGUMENT (root out of range or differing
 *  between ranks), CAPACITY (more than INT_MAX bytes of pairs in total),
 *  OUT_OF_MEMORY. Cost: one gather; O(P log P) on the root for P pairs. */
HGCD_API hgcd_status hgcd_mpi_gather_pairs(hgcd_mpi_world *world, int root,
                                           const hgcd_mpi_pair **out_pairs,
                                           size_t *out_count);

/** Figures of this rank's last hgcd_mpi_detect. */
typedef struct hgcd_mpi_stats {
    /** In: sizeof(hgcd_mpi_stats) as the caller knows it (0 = the library's
     *  size); the library fills min(struct_size, its size) bytes. Out: the
     *  number of bytes filled. */
    uint32_t struct_size;
    /** 1 if the detect rebalanced (recomputed the decomposition). */
    uint32_t rebalanced;
    /** Bodies owned by this rank and ghost copies it holds, after the
     *  detect's migration. */
    uint64_t owned_bodies;
    uint64_t ghost_bodies;
    /** Bodies this rank sent to and received from other ranks by migration
     *  (a rebalance included). */
    uint64_t migrated_out;
    uint64_t migrated_in;
    /** Ghost copies sent and received (one record each, 80 bytes). */
    uint64_t ghosts_sent;
    uint64_t ghosts_received;
    /** Payload bytes and point-to-point messages (each non-empty part of an
     *  all-to-all exchange counts as one) this rank sent and received;
     *  collective operations of a few numbers are counted in
     *  collective_calls. */
    uint64_t bytes_sent;
    uint64_t bytes_received;
    uint64_t messages_sent;
    uint64_t messages_received;
    uint64_t collective_calls;
    /** Neighbouring ranks: those whose region S meets this rank's. */
    uint64_t neighbour_ranks;
    /** Pairs this rank reports, and all pairs its local world found (ghost
     *  pairs and pairs owned by another rank included). */
    uint64_t reported_pairs;
    uint64_t local_world_pairs;
    /** Most owned bodies on any rank over the mean, after the detect's
     *  migration and rebalance (1 = perfect; 0 for an empty world). */
    double imbalance;
    /** Wall-clock seconds of the phases on this rank: migration (choosing
     *  and exchanging the bodies that leave, updating the local world),
     *  rebalance (the exchange of every rank's count and region, and when
     *  due the decomposition and its migration), ghost exchange (choosing,
     *  packing, messages), ghost update (the local world's ghosts), local
     *  detect (hgcd_world_detect), pairs (applying the owner rule), and the
     *  whole call. Waiting for other ranks shows in the phase that waits. */
    double migrate_seconds;
    double rebalance_seconds;
    double ghost_exchange_seconds;
    double ghost_update_seconds;
    double local_detect_seconds;
    double pairs_seconds;
    double total_seconds;
    /** 1 while this rank's local world keeps its bodies at indices 0 ..
     *  count-1, so hgcd_mpi_set_poses with ids NULL hands the poses over by
     *  index (hgcd_world_set_poses's fast path); 0 once hgcd placed a body
     *  elsewhere (then by listed ids: slower, same results). */
    uint32_t poses_by_index;
    /** Always 0. */
    uint32_t reserved;
} hgcd_mpi_stats;

/** Local. Copies this rank's figures of the last detect into *out_stats
 *  (caller sets struct_size first; zeros before the first detect).
 *  Errors: NULL_ARGUMENT, BAD_DESCRIPTOR (struct_size between 1 and 7). */
HGCD_API hgcd_status hgcd_mpi_stats_get(const hgcd_mpi_world *world,
                                        hgcd_mpi_stats *out_stats);

/** Local. The last detect's hgcd statistics of this rank's local world
 *  (hgcd_world_stats: candidate pairs, tests, times). Errors: as
 *  hgcd_world_stats. */
HGCD_API hgcd_status hgcd_mpi_local_stats(const hgcd_mpi_world *world,
                                          hgcd_stats *out_stats);

#ifdef __cplusplus
}
#endif

#endif /* HGCD_MPI_H */
