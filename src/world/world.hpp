// The world: meshes, bodies (structure of arrays, indexed by slot), the grid,
// and one tick's results. Every method validates its values and ids, leaves
// the world unchanged when it fails, and records the reason in last_error.
#pragma once
#include <cstdint>
#include <cstring>
#include <memory>
#include <new>
#include <string>
#include <type_traits>
#include <unordered_map>
#include <unordered_set>
#include <vector>
#if defined(__SSE2__) && defined(__x86_64__)
#include <immintrin.h>
#endif

#include "broad/grid.hpp"
#include "common/parallel.hpp"
#include "hgcd/hgcd.h"
#include "world/filter.hpp"
#include "world/mesh.hpp"
#include "world/mesh_pool.hpp"
#include "world/pose_box.hpp"
#include "world/threads.hpp"
#include "world/memory.hpp"
#include "narrow/narrow.hpp"
#include "query/cache.hpp"
#include "query/solid.hpp"

namespace hgcd {

// An allocator whose value-initialisation leaves the value uninitialised:
// the tick's pair (and contact) lists are resized, then written whole in
// parallel, and zeroing them first was a serial pass of its own.
template <class T>
struct UninitAllocator : std::allocator<T> {
    template <class U>
    struct rebind {
        using other = UninitAllocator<U>;
    };
    UninitAllocator() = default;
    template <class U>
    UninitAllocator(const UninitAllocator<U> &) noexcept {}
    template <class U>
    void construct(U *p) noexcept(std::is_nothrow_default_constructible<U>::value) {
        ::new (static_cast<void *>(p)) U;
    }
};

class World {
  public:
    explicit World(const hgcd_world_desc &desc);

    hgcd_status create_mesh(const hgcd_mesh_desc &desc, hgcd_mesh *out);
    hgcd_status destroy_mesh(hgcd_mesh id);
    hgcd_status mesh_info(hgcd_mesh id, hgcd_mesh_info *out) const;

    hgcd_status create_body(const hgcd_body_desc &desc, hgcd_body *out);
    hgcd_status destroy_body(hgcd_body id);
    hgcd_status set_pose(hgcd_body id, const double *position, const double *orientation);
    hgcd_status set_velocity(hgcd_body id, const double *velocity);
    hgcd_status get_pose(hgcd_body id, double *position, double *orientation) const;
    // Many bodies at once (batch.cpp); bodies NULL: indices 0 .. count-1.
    hgcd_status set_poses(const hgcd_body *bodies, size_t count, const double *positions, size_t position_stride,
                          const double *orientations, size_t orientation_stride);
    hgcd_status set_velocities(const hgcd_body *bodies, size_t count, const double *velocities,
                               size_t velocity_stride);
    hgcd_status get_poses(const hgcd_body *bodies, size_t count, double *positions, size_t position_stride,
                          double *orientations, size_t orientation_stride) const;
    hgcd_status get_velocity(hgcd_body id, double *velocity) const;
    hgcd_status get_mesh(hgcd_body id, hgcd_mesh *out) const;
    hgcd_status get_user_data(hgcd_body id, uint64_t *out) const;
    bool body_valid(hgcd_body id) const { return live_body(id) >= 0; }
    // Types, enabling, filters and excluded pairs (filtering.cpp).
    hgcd_status set_type(hgcd_body id, int32_t type);
    hgcd_status get_type(hgcd_body id, int32_t *out) const;
    hgcd_status set_enabled(hgcd_body id, bool enabled);
    hgcd_status get_enabled(hgcd_body id, uint32_t *out) const;
    hgcd_status set_filter(hgcd_body id, const hgcd_filter &filter);
    hgcd_status get_filter(hgcd_body id, hgcd_filter *out) const;
    hgcd_status exclude_pair(hgcd_body a, hgcd_body b, bool exclude);
    // Contact margins (bodies.cpp).
    hgcd_status set_margin(hgcd_body id, double margin);
    hgcd_status get_margin(hgcd_body id, double *out) const;
    hgcd_status set_contact_margin(double margin);
    double contact_margin() const { return world_margin_; }
    hgcd_status pair_excluded(hgcd_body a, hgcd_body b, uint32_t *out) const;

    hgcd_status step();
    hgcd_status detect();
    void set_thread_count(uint32_t n) {
        thread_count_ = n;
        governor_.reset();
    }
    // The caller's task system, or NULL (OpenMP).
    const TaskSystem *task_system() const { return tasks_.enqueue ? &tasks_ : nullptr; }
    void set_thread_policy(int32_t policy) {
        adaptive_threads_ = policy == HGCD_THREADS_ADAPTIVE && !tasks_.enqueue;
        governor_.reset();
    }
    // Narrow phase choice (enum hgcd_narrow_phase) and contacts (hgcd.h).
    hgcd_status set_narrow_phase(int32_t mode);
    hgcd_status set_mesh_narrow_phase(hgcd_mesh id, int32_t mode);
    void set_contacts(bool on) { contacts_on_ = on; }
    const std::vector<hgcd_contact, UninitAllocator<hgcd_contact>> &contacts() const { return contacts_; }
    bool contacts_recorded() const { return contacts_recorded_; }

    const std::vector<hgcd_pair, UninitAllocator<hgcd_pair>> &pairs() const { return pairs_; }
    const std::vector<hgcd_pair_event> &began() const { return began_; }
    const std::vector<hgcd_pair_event> &ended() const { return ended_; }
    const hgcd_stats &stats() const { return stats_; }
    uint32_t body_count() const { return live_bodies_; }
    uint32_t mesh_count() const { return live_meshes_; }

    // Scene queries (src/query): the calls of hgcd.h, arguments checked by
    // the shim for NULL only.
    hgcd_status cast_rays(const hgcd_ray *rays, size_t count, size_t stride, int32_t mode,
                          const hgcd_filter *filter, hgcd_ray_hit *out);
    hgcd_status query_boxes(const double *boxes, size_t count, size_t stride, const hgcd_filter *filter,
                            hgcd_query_results *out);
    hgcd_status query_points(const double *points, size_t count, size_t stride, const hgcd_filter *filter,
                             hgcd_query_results *out);
    hgcd_status query_meshes(hgcd_mesh mesh, const hgcd_mesh_pose *poses, size_t count, size_t stride,
                             const hgcd_filter *filter, hgcd_query_results *out);

    // Records a message and returns status, for the shim's argument checks too.
    hgcd_status fail(hgcd_status status, std::string message) const;
    const char *last_error() const { return last_error_.c_str(); }

  private:
    // Ids: generation = world tag (8 bits) << 24 | counter (24 bits, >= 1).
    static constexpr uint32_t kCounterBits = 24;
    static constexpr uint32_t kCounterMask = (1u << kCounterBits) - 1;
    static constexpr uint32_t kMaxSlots = 0x7FFFFFFEu;

    int64_t live_body(hgcd_body id) const;
    int64_t live_mesh(hgcd_mesh id) const;
    hgcd_status check_body(hgcd_body id, const char *what, int64_t *slot) const;
    hgcd_status check_pose(const char *what, const double *position,
                           const double *orientation) const;
    // The batch calls' passes (batch.cpp).
    // (first_in_range(b, e): the first entry in [b, e) that fails, or e.)
    template <class FirstInRange, class Done>
    int64_t first_failing_by_range(size_t count, FirstInRange &&first_in_range, Done &&done) const;
    template <class Check>
    int64_t first_failing(size_t count, Check &&check) const {
        return first_failing_by_range(
            count,
            [&](size_t b, size_t e) {
                while (b < e && check(b)) ++b;
                return b;
            },
            [] {});
    }
    template <class Apply>
    void for_entries(size_t count, Apply &&apply);
    hgcd_status resolve_entries(const char *what, const hgcd_body *bodies, size_t count, bool storage);
    void apply_pose(size_t i, const double *position, const double *orientation);
    // The same, the box of a new orientation taken by boxes when its kernel
    // can (batch.cpp: a record of at most kQueuedGroups groups, no margin).
    static constexpr uint32_t kQueuedGroups = 4;
    void apply_pose_queued(size_t i, const double *position, const double *orientation, BoxQueue &boxes,
                           bool stream = false);
    template <class Box>
    void apply_pose_with(size_t i, const double *position, const double *orientation, Box &&box,
                         bool stream = false);
    // set_poses's pass by index over storage [b, e) from the stage (stage
    // lines, count entries named; kSome: not every index), the same writes
    // as apply_pose_queued's with AVX-512 (batch.cpp).
    struct StagedPose;
    template <bool kSome>
    void apply_staged_avx512(int64_t b, int64_t e, const StagedPose *stage, size_t count, bool has_p, bool has_q,
                             BoxQueue &boxes);
    // The offsets from its position of a box holding the solid of the body
    // stored at s (box_off_), for its current orientation and scale.
    void set_box_offsets(size_t s);
    void set_box_offsets_general(size_t s);  // (with a margin, or no record)
    // Whether that box comes from the mesh's record in floats
    // (record_float_box): a record, and no margin to grow the box by.
    bool float_record_box(size_t s) const {
        return body_record_[s].groups != 0 && world_margin_ == 0 && (margin_bodies_ == 0 || margin_[s] == 0);
    }
    // How far the box of the body stored at s is grown for the contact
    // margins: at least world margin / 2 + its own margin, so that the
    // boxes of two bodies within their pair's margin overlap (bodies.cpp).
    double box_growth(size_t s) const;
    // The level radius of the body stored at s (r_level_).
    double level_radius(size_t s) const;
    Boxes boxes() const;
    void renumber_if_disordered();
    // detect(); renumbered: step() has renumbered storage already; motion:
    // what the grid update's census runs on each range of slots first (see
    // Grid::update).
    hgcd_status detect_with(bool renumbered, const SlotPass *motion = nullptr);
    // detect_with's stages (detect.cpp).
    struct NarrowChunk;
    struct NarrowPlan;
    struct NarrowThread;
    GridUpdateStats update_grid(int threads, const SlotPass *motion);
    // Fills candidates_ (and with keep_unmoved hits_ with the unmoved pairs
    // kept); returns their count.
    size_t find_candidates(int threads, bool keep_unmoved);
    // The narrow phase over candidates_, its hits merged with those in
    // hits_ into pairs_, and the events; moved_only: a detect around the
    // moved bodies, whose hits are merged with the last pairs of unmoved
    // bodies instead (merge_moved).
    void test_candidates(int threads, bool moved_only = false);
    // pairs_ and the events from the threads' hits (all with a body moved
    // since the last detect) and the last pairs (moved_merge.cpp); returns
    // how many last pairs were kept untested.
    size_t merge_moved(int threads);
    std::vector<hgcd_pair, UninitAllocator<hgcd_pair>> new_hits_;  // (its scratch)
    std::vector<uint64_t> moved_slots_;                            // (and its bits by slot)
    // Temporal coherence (coherence.cpp): removes from the candidates the
    // pairs of two bodies unmoved since the last detect, their result taken
    // from its pairs (prev_pairs_) into hits_; returns how many.
    uint64_t keep_unmoved_pairs(int threads, std::vector<PairBuffer> &found);
    // Removes from the candidates the pairs the types, filters or excluded
    // pairs refuse (filtering.cpp); returns how many.
    uint64_t drop_filtered_pairs(int threads, std::vector<PairBuffer> &found);
    // The body stored at i gets filter record f: keeps plain_ and disabled_
    // counts, and marks the body moved (its pairs' answers may change).
    void set_body_filter(size_t i, const BodyFilter &f);
    // What the grid reads as each stored body's generation (0: not there):
    // stored_gen_ unless some bodies are disabled, then a copy without them.
    const uint32_t *grid_live(int threads);
    void forget_exclusions(uint32_t slot);
    // The body stored at s does not move with hgcd_world_step (static or disabled).
    bool still(size_t s) const {
        return filter_[s].type == HGCD_BODY_STATIC || (filter_[s].flags & BodyFilter::kDisabled);
    }
    // Events (events.cpp): began_ and ended_ from prev_pairs_ and pairs_.
    void find_events(int threads);
    void bury(uint32_t slot);
    uint64_t user_data_of(hgcd_body id) const;
    hgcd_status check_pair(const char *what, hgcd_body a, hgcd_body b, int64_t *sa, int64_t *sb) const;
    // Live bodies created or moved since the last detect, and how many of
    // them are not movers yet (see below).
    struct MovedCount {
        size_t moved = 0, new_movers = 0;
    };
    // (Also keeps how many are in each of `threads` equal ranges of
    // storage, for list_moved.)
    MovedCount count_moved(int threads);
    void reuse_pairs();  // pairs_ from prev_pairs_ when no live body moved
    void clear_moved();  // (after a detect)
    // Incremental detection (incremental.cpp): whether this detect may search
    // around the moved bodies alone, and that detect (its statistics from t0).
    bool incremental_fits(const MovedCount &moved) const;
    void detect_incremental(int threads, const MovedCount &moved, double t0);
    void list_moved(int threads, size_t count);
    uint64_t update_movers(int threads);  // returns the bodies that changed cell
    size_t find_moved_candidates(int threads);
    // The moved bodies' pairs with the grid's residents that are not
    // movers, into candidates_, through each mover's cached list of the
    // residents near it (resident_cache.cpp).
    void find_resident_candidates(int threads, std::vector<Grid::QueryCursors> &cursors_of);
    void forget_resident_cache() noexcept;  // (the grid or storage changed, or the lists lack memory)
    // Forgets the movers (before the grid is updated, or dropped). No throw.
    void drop_movers() noexcept;
    void plan_narrow(int threads, NarrowPlan &plan) const;
    // Each thread's colliding pairs, sorted, into hits_ (and hit_contacts).
    // The first-tried witnesses (coherence.cpp), sorted by pair_key: for
    // each colliding pair of the last detect with a mesh that has a tree,
    // the tree nodes near where its surfaces met (NodeHint; the lower slot's
    // first), and for each pair its hulls proved apart at the last detect,
    // the axis (pack_axis's word) and the hulls' supports along it
    // (axis_witness's word). Hints that the next detect tries first: any
    // entry leaves verdicts exact.
    struct NodeWitness {
        uint64_t key;
        uint32_t node[2];
    };
    // An axis witness's first word: kAxisTag and the two supports (10 bits
    // each, the lower slot's first; kNoSupport: none), above every node
    // index (no tree has so many nodes).
    static constexpr uint32_t kAxisTag = 0xFFF00000u, kNoSupport = 1023;
    static uint32_t axis_witness(uint32_t low, uint32_t high) {
        return kAxisTag | std::min(low, kNoSupport) << 10 | std::min(high, kNoSupport);
    }
    // Its support of the lower slot's body (first) or the higher's, or
    // UINT32_MAX.
    static uint32_t witness_support(uint32_t word, bool first) {
        const uint32_t v = first ? word >> 10 & kNoSupport : word & kNoSupport;
        return v == kNoSupport ? UINT32_MAX : v;
    }
    // A direction (times sign) in 32 bits, octahedral (16 bits a
    // coordinate, about 1e-4 radians), and back.
    static uint32_t pack_axis(const double *v, double sign);
    static void unpack_axis(uint32_t w, double *v, double sign);
    std::vector<NodeWitness> witness_;
    // Where each slot's witnesses (as the pair's lower slot) start in
    // witness_, while there are more than slots / 8 of them (else empty:
    // find_witness searches).
    std::vector<uint32_t> witness_start_;
    const NodeWitness *find_witness(uint64_t key) const;
    // witness_ from this detect's new witnesses (any order) and the last
    // ones of the pairs kept untested that are in pairs_.
    void keep_witnesses(std::vector<NodeWitness> &fresh);
    // Sorts them by key (slots: every key's high half is below it).
    static void sort_witnesses(std::vector<NodeWitness> &w, size_t slots);
    void narrow_phase(int threads, const NarrowPlan &plan, std::vector<std::vector<hgcd_contact>> &hit_contacts,
                      std::vector<NodeWitness> &fresh);
    void narrow_chunk(const NarrowPlan &plan, const NarrowChunk &chunk, NarrowThread &t) const;
    template <class Pair>
    void append_hits(const Contact *verdict, size_t n, const Pair *pairs, const uint64_t *keys, NarrowThread &t) const;
    void within_margins(size_t tetras, NarrowThread &t) const;
    // Asks for what the pairs after the k-th of list[.., end) will read.
    void ask_ahead(const NarrowPlan &plan, const PairBuffer &list, size_t k, size_t end) const;
    size_t narrow_pairs(const NarrowPlan &plan, const PairBuffer &list, const NarrowChunk &chunk,
                        NarrowThread &t) const;
    static Contact collide_pair(const BodyPose &pa, const BodyPose &pb, uint8_t ma, uint8_t mb, double d,
                                bool want_contacts, NarrowThread &t, hgcd_contact *contact);
    // The threads' hits into pairs_ (and contacts_).
    void merge_hits(int threads, bool want_contacts, const std::vector<std::vector<hgcd_contact>> &hit_contacts);
    // Moves every body's storage to the grid's sweep order (see at_), the
    // static bodies after the others; false, changing nothing, when there
    // is no memory for it.
    bool renumber();
    // Where the static bodies' run begins in storage since the last
    // renumbering (UINT32_MAX: none), for the grid's disorder (set_split).
    uint32_t static_from_ = UINT32_MAX;
    // body_record_ again from the pool, after it moved its records.
    void refresh_records();
    int32_t effective_narrow_phase(uint32_t mesh_slot) const;
    // The threads of the next detect or batch call: the world's count, or
    // fewer under the adaptive policy while the cores are busy (threads.hpp).
    int threads() const;
    int full_threads() const;
    GridLimits grid_limits(int threads);
    // Candidate pairs per body expected of boxes spread evenly over their
    // positions' box; -1 when there is no such box.
    double estimated_candidates_per_body(int threads) const;

    uint32_t tag_;  // of the ids' generations
    uint32_t thread_count_;
    bool adaptive_threads_;
    ThreadGovernor governor_;
    TaskSystem tasks_;
    double time_step_;
    bool reflect_;
    double bounds_min_[3], bounds_max_[3];
    GridLimits limits_;

    // Meshes, by slot.
    std::vector<Mesh> meshes_;
    std::vector<uint32_t> mesh_gen_;
    std::vector<uint8_t> mesh_alive_;
    std::vector<uint32_t> mesh_users_;
    std::vector<uint32_t> mesh_free_;
    std::vector<int8_t> mesh_narrow_;
    // Per mesh slot its Mesh::sat (null: none, or no live mesh), where the
    // convex batch's pairs read it (ConvexPair): 8 bytes a mesh, dense.
    std::vector<const SatData *> mesh_sat_;  // hgcd_mesh_set_narrow_phase, or HGCD_NARROW_WORLD
    MeshPool pool_;  // the records of small meshes, by slot (mesh_pool.hpp)
    uint32_t live_meshes_ = 0;
    // Live meshes that are tetrahedra (Mesh::tetra), and the others that have
    // Mesh::sat (the convex batch is needed only with one of those): what the
    // narrow phase's plan asks, without a pass over the meshes.
    uint32_t tetra_meshes_ = 0, sat_meshes_ = 0;
    // A live mesh with Mesh::sat per hash of its arrays (sat_key): a new
    // mesh with the same arrays shares its SatData, so that the convex
    // batch's steps that need one SatData per side of four pairs also serve
    // bodies that each have a copy of one mesh.
    std::unordered_map<uint64_t, uint32_t> sat_slot_;
    // Set by the first small convex mesh other than a tetrahedron: from then
    // on tetrahedra carry Mesh::sat too (create_mesh).
    bool tetra_sat_ = false;
    int32_t narrow_phase_ = HGCD_NARROW_EXACT;
    bool contacts_on_ = false;
    bool contacts_recorded_ = true;  // contacts_ describe pairs_ (false: detected with contacts off)

    // Bodies. A body's slot is the index of its handle; its state lives at
    // a storage index (at_), and the world renumbers storage now and then to
    // follow the grid's sweep order (renumber()), so that the gather of the
    // grid update and the narrow phase read memory nearly in sequence.
    // Per slot:
    std::vector<uint32_t> body_gen_;   // last generation handed out in the slot
    LargeVector<uint32_t> live_gen_;   // body_gen_ if alive, else 0
    std::vector<uint32_t> at_;         // storage index
    std::vector<uint32_t> body_free_;  // stack of reusable slots
    std::vector<uint64_t> user_data_;  // (by slot: the events read it by slot)
    // Per storage index (structure of arrays):
    LargeVector<uint32_t> slot_of_;
    LargeVector<uint32_t> stored_gen_;  // live_gen_ of the slot stored here
    LargeVector<Placement> place_;  // (narrow.hpp)
    LargeVector<double> velocity_;     // 3
    LargeVector<uint32_t> body_mesh_;  // mesh slot
    LargeVector<BodyFilter> filter_;   // type, enabled, filter (filter.hpp)
    // The mesh's record in pool_: its first block (MeshPool::kNone: none)
    // and groups of 4 points (0: none), read by the narrow phase and the
    // box of a new orientation beside the placements (refresh_records()).
    struct BodyRecord {
        uint32_t block, groups;
    };
    LargeVector<BodyRecord> body_record_;
    // The body's box less its position, fixed while its orientation is:
    // 6 floats (low x y z, high x y z), rounded outward (grid.hpp, Boxes).
    LargeVector<float> box_off_;
    // A bound on the magnitude of the offsets in any orientation, that picks
    // the body's grid level: scale (|mesh centre| + mesh radius), inflated.
    std::vector<double> r_level_;
    // The positions again, 3 doubles each: what the grid reads every tick,
    // in a third of the memory of the placements.
    LargeVector<double> point_;
    uint32_t live_bodies_ = 0;
    // Live bodies whose filter_ is not plain, those disabled, and those
    // static (the motion skips them).
    uint32_t special_bodies_ = 0, disabled_bodies_ = 0, static_bodies_ = 0;
    uint32_t plain_static_bodies_ = 0;  // live static bodies otherwise plain (BodyFilter::plain_static)
    // Contact margins: the world's (hgcd_world_desc.contact_margin), each
    // body's by storage index, the live bodies with one > 0, and whether a
    // margin changed since the grid's last update (its cached levels are
    // then stale: the next detect rebuilds it).
    double world_margin_ = 0;
    LargeVector<double> margin_;
    uint32_t margin_bodies_ = 0;
    bool grid_stale_ = false;
    bool kinematic_pairs_ = false;
    // Excluded pairs, by pair_key of their slots, and each slot's partners.
    std::unordered_set<uint64_t> excluded_;
    std::unordered_map<uint32_t, std::vector<uint32_t>> excluded_with_;
    std::vector<uint32_t> live_scratch_;  // grid_live
    // Temporal coherence. Per storage index, whether the body there was
    // created, destroyed (its pairs end) or its pose changed since the last
    // detect (a slot's flag: moved_at_[at_[slot]]); whether the last
    // detect's pairs (prev_pairs_ during a detect) decide the pairs of
    // unmoved bodies: not after a failed detect, a change of narrow phase,
    // or with contacts on.
    LargeVector<uint8_t> moved_at_;
    bool coherent_ = false;
    std::vector<hgcd_pair, UninitAllocator<hgcd_pair>> prev_pairs_;
    std::vector<uint32_t> prev_start_;  // where each slot's pairs (as a) start in prev_pairs_
    // The batch calls' scratch: each entry's storage index, and the marks
    // (per storage index, of epoch batch_epoch_) that find an id named twice.
    std::vector<uint32_t> batch_at_, batch_mark_;
    uint32_t batch_epoch_ = 0;
    // hgcd_world_set_poses by index: each entry's pose at its body's storage
    // index, copied from the caller's arrays in index order (batch.cpp), one
    // cache line each.
    struct alignas(64) StagedPose {
        double position[3], orientation[4];
    };
    LargeVector<StagedPose> pose_stage_;

    // Scene queries (src/query): the tree over the bodies and the last
    // results; its helpers.
    QueryCache query_;
    void ensure_query_tree();
    // Fills query_'s offsets and bodies with each query's bodies: box(q,
    // lo, hi) gives query q's box; accept(q, i, scratch) decides the tree
    // item i whose box meets it (region.cpp).
    template <class Box, class Accept>
    void run_region_queries(size_t count, const hgcd_filter *filter, Box &&box, Accept &&accept);
    void publish(hgcd_query_results *out);
    // The body of tree item i as the exact tests read it: its cached world
    // vertices, or the scratch's world vertices or tree view; box receives
    // the box of SolidView::box.
    SolidView query_view(size_t i, QueryScratch &s, double *box) const;

    // Incremental detection. The movers: bodies created or moved since the
    // grid's last update (which still holds their old boxes), marked by
    // storage index (kMover; kDead marks bodies destroyed since, which the
    // grid may hold too), each with an index into a second grid that holds
    // their current boxes: arrays by that index of the storage index, the
    // point, offsets, level radius and generation (0: destroyed since), and
    // whether the body moved since the last detect. None whenever the grid
    // is updated. moved_list_: the storage indices of the bodies moved since
    // the last detect, during one.
    static constexpr uint8_t kMover = 1, kDead = 2;
    std::vector<uint8_t> mover_;
    std::vector<uint32_t> side_storage_, side_gen_;
    std::vector<double> side_point_, side_r_level_;
    std::vector<float> side_off_;
    std::vector<uint8_t> side_now_;
    Grid side_grid_;
    std::vector<PairBuffer> side_found_;
    std::vector<uint32_t> moved_list_;
    std::vector<size_t> moved_parts_;  // count_moved's counts by range (empty after a renumbering)
    std::vector<uint32_t, UninitAllocator<uint32_t>> moved_found_;  // and what it found, by range
    // Per mover (by its index in the second grid), the grid's residents
    // that met its fat box when it last searched the grid, with their boxes
    // (resident_cache.cpp): a run of one of the arenas (one per worker that
    // made lists), where a list stays put until the arenas are compacted;
    // valid until the grid is updated, and free of new movers while
    // mover_marks_ (which counts bodies that became movers or died) has not
    // changed since the list was written.
    // An entry: the resident's storage index, and its box on the list's
    // own scale (resident_cache.cpp): low corner, then high corner negated.
    struct ResidentEntry {
        int16_t box[6];
        uint32_t slot;
    };
    struct ResidentCache {
        float fat[6], last[3];  // fat box, and the low corner of the box at the last detect
        uint32_t worker, begin, count;
        bool valid = false;
        uint64_t marks;
    };
    std::vector<ResidentCache> resident_cache_;
    std::vector<std::vector<ResidentEntry>> resident_arena_;  // per worker
    std::vector<std::vector<ResidentEntry>> resident_fresh_;  // per worker, the lists one detect writes
    std::vector<std::vector<Grid::QueryBox>> resident_found_;  // per worker, a search's residents
    uint64_t mover_marks_ = 0;
    // The arenas holding only the valid lists (when mostly garbage).
    void compact_resident_lists(int threads);

    Grid grid_;
    std::vector<PairBuffer> candidates_;  // per thread, one detect's candidate pairs
    std::vector<std::vector<uint64_t>> hits_, sort_scratch_;  // per thread, its colliding pairs (keys)
    // Candidate pairs per body of the last successful detect (-1: none yet),
    // and whether the grid is coarsened (grid_limits).
    double candidates_per_body_ = -1;
    bool coarse_grid_ = false;
    bool grid_rebuilt_ = true;  // by the last detect, after its first (renumber waits for an incremental one)
    std::vector<hgcd_pair, UninitAllocator<hgcd_pair>> pairs_;
    std::vector<hgcd_contact, UninitAllocator<hgcd_contact>> contacts_;  // parallel to pairs_ when contacts_recorded_
    hgcd_stats stats_{};
    // Events of the last detect, and what they need: whether prev_pairs_
    // holds the last successful detect's pairs (after a failed detect, so
    // the next one compares with them), per slot whether its body is in
    // those pairs (built by the first destruction that needs it), and the
    // user data of such bodies destroyed since.
    std::vector<hgcd_pair_event> began_, ended_;
    bool base_in_prev_ = false;
    bool base_indexed_ = false;  // in_pairs_ describes those pairs (bury)
    std::vector<uint8_t> in_pairs_;
    struct Grave {
        uint32_t slot, generation;
        uint64_t user_data;
    };
    std::vector<Grave> graves_;
    mutable std::string last_error_;
};

// The pose of the body stored at i: p (3 doubles) and q (4), either NULL to
// keep it; the body counts as moved when a bit changes (hgcd_body_set_pose
// and hgcd_world_set_poses alike). box(q) brings box_off_ to a new
// orientation q. stream: point_ in streaming stores, for a pass that writes
// storage in sequence (its lines are then not read before being written;
// the pass fences its stores before others read them).
template <class Box>
inline void World::apply_pose_with(size_t i, const double *p, const double *q, Box &&box, bool stream) {
    bool moved = false;
    if (p) {
        moved = std::memcmp(place_[i].position, p, sizeof place_[i].position) != 0;
#if defined(__SSE2__) && defined(__x86_64__)
        if (stream) {
            for (int a = 0; a < 3; ++a) {
                long long bits;
                std::memcpy(&bits, &p[a], sizeof bits);
                _mm_stream_si64(reinterpret_cast<long long *>(&point_[3 * i + a]), bits);
                place_[i].position[a] = p[a];
            }
        } else
#endif
        for (int a = 0; a < 3; ++a) place_[i].position[a] = point_[3 * i + a] = p[a];
    }
    if (q && std::memcmp(place_[i].orientation, q, sizeof place_[i].orientation) != 0) {
        std::memcpy(place_[i].orientation, q, sizeof place_[i].orientation);
        box(q);
        moved = true;
    }
    if (moved) moved_at_[i] = 1;
}

}  // namespace hgcd
