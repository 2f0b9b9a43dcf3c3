// Detection, stage by stage: the grid update (with a step's motion inside
// it), the candidate pairs, the narrow phase over them on every thread, and
// the merge of the threads' hits into the reported pairs (merge_hits.cpp).
// The grid's stage is in grid_stage.cpp.
#include <omp.h>

#include <algorithm>
#include <cmath>
#include <memory>
#include <vector>

#include "common/ieee.hpp"
#include "common/parallel.hpp"
#include "narrow/ccd_narrow.hpp"
#include "narrow/contact.hpp"
#include "narrow/narrow.hpp"
#include "narrow/within.hpp"
#include "world/hit_sort.hpp"
#include "world/world.hpp"

namespace hgcd {

namespace {

// Candidate pairs per unit of the narrow phase's dynamic schedule.
constexpr size_t kNarrowChunk = 512;

// Per mesh slot, what the narrow phase loop reads.
constexpr uint8_t kCcdUse = 1;    // convex and set to GJK or MPR: libccd
constexpr uint8_t kCcdGjk = 2;    // set to GJK
constexpr uint8_t kCcdAsked = 4;  // set to GJK or MPR, convex or not
constexpr uint8_t kQueueTetra = 1, kQueueConvex = 2;  // (NarrowPlan::queued)

}  // namespace

// A run of one thread's candidate list: the unit of the narrow phase's
// dynamic schedule (pairs cost very different amounts).
struct World::NarrowChunk {
    uint32_t list;
    size_t begin, end;
};

// What every thread of the narrow phase reads.
struct World::NarrowPlan {
    std::vector<NarrowChunk> chunks;
    bool want_contacts = false;
    // Per mesh slot (kCcd* bits): libccd or exact, read only if any_ccd.
    std::vector<uint8_t> ccd_mode;
    bool any_ccd = false;
    // Pairs of tetrahedra (without contacts or libccd) go to the batched
    // test a chunk at a time (narrow.hpp), through per-thread arrays on the
    // heap, from before the region (thread 0 runs on the caller's stack).
    bool batch = false;
    // Every live mesh a tetrahedron: every pair goes to the batch, no mesh
    // need be looked at per pair.
    bool all_tetra = false;
    // Some pair may have a contact margin (world or body margins > 0).
    bool margins = false;
    std::unique_ptr<TetraPair[]> batch_pairs;
    std::unique_ptr<Contact[]> batch_verdicts;
    // Likewise pairs of small convex meshes (Mesh::sat), when some live mesh
    // has it.
    bool convex_batch = false;
    // Every live mesh small convex and none a tetrahedron: every pair goes
    // to the convex batch, in the chunk's order.
    bool all_convex = false;
    // Per mesh slot: kQueueTetra when the batch takes its pairs with
    // tetrahedra, kQueueConvex when the convex batch takes its pairs with
    // small convex meshes (a pair is queued when its two share a bit).
    std::vector<uint8_t> queued;
    std::unique_ptr<ConvexPair[]> convex_pairs;
    std::unique_ptr<Contact[]> convex_verdicts;
};

// One worker's narrow phase, on the heap apart from the others': the
// vectors of hits_ share cache lines, and every push writes the vector's
// end, so a worker's hits sit in its own record while it pushes (the
// storage of hits_[worker], kept across detects).
struct World::NarrowThread {
    NarrowScratch scratch;
    CcdScratch ccd_scratch;
    ContactScratch contact_scratch;
    std::vector<uint64_t> hits;          // pair keys, slot a << 32 | slot b
    std::vector<hgcd_contact> contacts;  // parallel to hits (contacts on)
    std::vector<NodeWitness> witnesses;   // of this detect's tree pairs that met
    uint64_t containment = 0, ccd_fallback = 0;
    TetraPair *tetra = nullptr;  // this thread's batch (plan.batch)
    Contact *verdict = nullptr;
    ConvexPair *convex = nullptr;  // and its convex batch (plan.convex_batch)
    Contact *convex_verdict = nullptr;
    size_t convex_count = 0;
    uint32_t hit_index[kNarrowChunk];
};

hgcd_status World::detect() { return detect_with(false); }

hgcd_status World::detect_with(bool renumbered, const SlotPass *motion) {
    // The last pairs decide the unmoved bodies' pairs (not in a step: its
    // motion moves every body with a velocity).
    const bool coherence = coherent_ && !motion && !contacts_on_;
    coherent_ = false;  // until this detect succeeds
    // (After a failed detect prev_pairs_ holds the last successful pairs:
    // the events compare with them.)
    if (!base_in_prev_) prev_pairs_.swap(pairs_);
    base_in_prev_ = true;  // until this detect succeeds, whatever throws
    base_indexed_ = false;
    pairs_.clear();
    began_.clear();
    ended_.clear();
    contacts_.clear();
    contacts_recorded_ = contacts_on_;
    const uint32_t struct_size = stats_.struct_size;
    stats_ = hgcd_stats{};
    stats_.struct_size = struct_size;
    const int T = threads();
    const double t0 = omp_get_wtime();
    const MovedCount moved = coherence ? count_moved(T) : MovedCount{};
    const size_t unmoved = coherence ? live_bodies_ - moved.moved : 0;
    if (coherence && unmoved == live_bodies_) {
        // Nothing moved or was born: no search at all (the grid catches up
        // with destroyed bodies at the next detect that searches).
        try {
            reuse_pairs();
            find_events(T);
        } catch (...) {
            pairs_.clear();
            began_.clear();
            ended_.clear();
            base_in_prev_ = true;
            stats_ = hgcd_stats{};
            stats_.struct_size = struct_size;
            throw;
        }
        clear_moved();  // (destroyed bodies count as moved)
        base_in_prev_ = false;
        stats_.thread_count = uint32_t(T);
        stats_.total_seconds = stats_.narrow_seconds = omp_get_wtime() - t0;
        coherent_ = true;
        return HGCD_OK;
    }
    if (grid_stale_) {
        // A margin changed a body's level radius, which the grid caches:
        // rebuild it (and search everything).
        drop_movers();
        grid_ = Grid();
        grid_stale_ = false;
    }
    // (The adaptive thread policy's measure: none under the fixed policy.)
    LoadMeter meter;
    const LoadMeter::Attach attach(adaptive_threads_ ? &meter : nullptr);
    try {
        if (coherence && incremental_fits(moved)) {
            // Few bodies moved: a search around them alone (which reads the
            // moved bodies in storage order, the grid's once renumbered).
            if (!renumbered) renumber_if_disordered();
            detect_incremental(T, moved, t0);
            clear_moved();
            base_in_prev_ = false;
            coherent_ = true;
            return HGCD_OK;
        }
        drop_movers();  // (the grid is brought to every body's box)
        if (!renumbered) renumber_if_disordered();
        const GridUpdateStats us = update_grid(T, motion);
        const double t1 = omp_get_wtime();
        // (Fewer than two unmoved bodies make no unmoved pair.)
        const size_t total = find_candidates(T, unmoved >= 2);
        const double t2 = omp_get_wtime();
        test_candidates(T);
        const double t3 = omp_get_wtime();

        stats_.level_count = grid_.level_count();
        stats_.oversize_count = grid_.oversize_count();
        stats_.thread_count = uint32_t(T);
        stats_.moved_bodies = us.moved;
        stats_.searched_bodies = live_bodies_;
        stats_.candidate_pairs = uint64_t(total);
        candidates_per_body_ = live_bodies_ ? double(total) / live_bodies_ : -1;
        stats_.colliding_pairs = pairs_.size();
        stats_.update_seconds = t1 - t0;
        stats_.broad_seconds = t2 - t1;
        stats_.narrow_seconds = t3 - t2;
        stats_.total_seconds = t3 - t0;
        clear_moved();
        base_in_prev_ = false;
        coherent_ = !contacts_on_;
        if (adaptive_threads_) governor_.record(full_threads(), t3 - t0, double(live_bodies_) + double(total), meter.lost());
    } catch (...) {
        // The grid may be half updated: drop it (and the movers, whose
        // boxes it lacks), the next detect rebuilds it.
        drop_movers();
        grid_ = Grid();
        pairs_.clear();
        began_.clear();
        ended_.clear();
        base_in_prev_ = true;
        contacts_.clear();
        stats_ = hgcd_stats{};
        stats_.struct_size = struct_size;
        throw;
    }
    return HGCD_OK;
}

size_t World::find_candidates(int threads, bool keep_unmoved) {
    // Kept across detects: a tick's candidates need not grow fresh buffers
    // (and fault in fresh pages) every time.
    // (Never shrunk: the adaptive thread policy changes the count back and
    // forth. Lists past `threads` stay empty.)
    std::vector<PairBuffer> &found = candidates_;
    if (found.size() < size_t(threads)) found.resize(size_t(threads));
    for (auto &f : found) f.clear();
    if (hits_.size() < size_t(threads)) hits_.resize(size_t(threads));
    for (auto &h : hits_) h.clear();
    grid_.find_pairs(boxes(), threads, found);
    size_t total = 0;
    for (int t = 0; t < threads; ++t) total += found[t].size();
    // Pairs the types, filters and exclusions refuse never reach the narrow
    // phase (nor the lookups of temporal coherence).
    if (special_bodies_) stats_.filtered_pairs = drop_filtered_pairs(threads, found);
    if (keep_unmoved) stats_.unmoved_pairs = keep_unmoved_pairs(threads, found);
    return total;
}

void World::test_candidates(int threads, bool moved_only) {
    NarrowPlan plan;
    // The narrow phase runs straight over every thread's candidate list.
    const std::vector<PairBuffer> &found = candidates_;
    for (int t = 0; t < threads; ++t) {
        for (size_t b = 0; b < found[t].size(); b += kNarrowChunk)
            plan.chunks.push_back({uint32_t(t), b, std::min(found[t].size(), b + kNarrowChunk)});
    }
    plan_narrow(threads, plan);
    std::vector<std::vector<hgcd_contact>> hit_contacts(static_cast<size_t>(threads));  // per thread, parallel to hits_
    std::vector<NodeWitness> fresh;
    narrow_phase(threads, plan, hit_contacts, fresh);
    if (moved_only) {
        stats_.unmoved_pairs = merge_moved(threads);
        keep_witnesses(fresh);
        return;
    }
    merge_hits(threads, plan.want_contacts, hit_contacts);
    keep_witnesses(fresh);
    find_events(threads);
}

void World::plan_narrow(int threads, NarrowPlan &plan) const {
    plan.want_contacts = contacts_on_;
    plan.ccd_mode.assign(meshes_.size(), 0);
    for (size_t m = 0; m < meshes_.size(); ++m) {
        if (!mesh_alive_[m]) continue;
        const int32_t set = mesh_narrow_[m] == HGCD_NARROW_WORLD ? narrow_phase_ : mesh_narrow_[m];
        if (set != HGCD_NARROW_GJK && set != HGCD_NARROW_MPR) continue;
        plan.ccd_mode[m] = uint8_t(kCcdAsked | (set == HGCD_NARROW_GJK ? kCcdGjk : 0) |
                                   (meshes_[m].convex ? kCcdUse : 0));
        plan.any_ccd = true;
    }
    // (With a margin, the batch decides which tetrahedron pairs touch, and
    // those apart go on to the margin test one at a time: narrow_chunk.)
    plan.margins = world_margin_ > 0 || margin_bodies_ > 0;
    plan.batch = !plan.want_contacts && !plan.any_ccd;
    plan.all_tetra = plan.batch && tetra_meshes_ == live_meshes_;
    if (plan.batch) {
        plan.batch_pairs.reset(new TetraPair[size_t(threads) * kNarrowChunk]);
        plan.batch_verdicts.reset(new Contact[size_t(threads) * kNarrowChunk]);
    }
    // (The convex batch decides touching only: not with margins.)
    plan.convex_batch = plan.batch && !plan.margins && sat_meshes_ > 0;
    plan.all_convex = plan.convex_batch && tetra_meshes_ == 0 && sat_meshes_ == live_meshes_;
    if (plan.convex_batch) {
        plan.convex_pairs.reset(new ConvexPair[size_t(threads) * kNarrowChunk]);
        plan.convex_verdicts.reset(new Contact[size_t(threads) * kNarrowChunk]);
    }
    plan.queued.assign(meshes_.size(), 0);
    for (size_t m = 0; m < meshes_.size(); ++m)
        plan.queued[m] = uint8_t((plan.batch && meshes_[m].tetra ? kQueueTetra : 0) |
                                 (plan.convex_batch && meshes_[m].sat ? kQueueConvex : 0));
}

void World::narrow_phase(int threads, const NarrowPlan &plan,
                         std::vector<std::vector<hgcd_contact>> &hit_contacts, std::vector<NodeWitness> &fresh) {
    // Kept across detects, as the candidates: fresh buffers would grow (and
    // fault in pages) every tick. (hits_ holds the pairs temporal coherence
    // kept: find_candidates.)
    if (sort_scratch_.size() < size_t(threads)) sort_scratch_.resize(size_t(threads));
    struct Counts {
        uint64_t narrow_tests, triangle_tests, containment, libccd_tests, libccd_fallback;
    };
    std::vector<Counts> counts(size_t(threads), Counts{0, 0, 0, 0, 0});
    // Each worker's state, made by the worker on its first chunk (so that
    // its pages are its thread's).
    std::vector<std::unique_ptr<NarrowThread>> worker(static_cast<size_t>(threads));
    parallel_for(threads, int64_t(plan.chunks.size()), 1, Schedule::Dynamic, [&](int64_t c0, int64_t c1, int me) {
        std::unique_ptr<NarrowThread> &t = worker[size_t(me)];
        if (!t) {
            t.reset(new NarrowThread);
            t->hits.swap(hits_[me]);
            if (plan.batch) {
                t->tetra = plan.batch_pairs.get() + size_t(me) * kNarrowChunk;
                t->verdict = plan.batch_verdicts.get() + size_t(me) * kNarrowChunk;
            }
            if (plan.convex_batch) {
                t->convex = plan.convex_pairs.get() + size_t(me) * kNarrowChunk;
                t->convex_verdict = plan.convex_verdicts.get() + size_t(me) * kNarrowChunk;
            }
        }
        for (int64_t c = c0; c < c1; ++c) narrow_chunk(plan, plan.chunks[size_t(c)], *t);
    });
    // Each worker's hits sorted, then kept in hits_ (with its contacts).
    parallel_for(threads, threads, 1, Schedule::Dynamic, [&](int64_t w0, int64_t w1, int) {
        for (int64_t me = w0; me < w1; ++me) {
            NarrowThread *t = worker[size_t(me)].get();
            if (!t) {  // no chunk: only what temporal coherence kept (never with contacts)
                sort_keys(hits_[size_t(me)], sort_scratch_[size_t(me)]);
                continue;
            }
            counts[size_t(me)] = Counts{t->scratch.exact_tests, t->scratch.triangle_tests, t->containment,
                                        t->ccd_scratch.tests, t->ccd_fallback};
            if (plan.want_contacts)
                sort_with_contacts(t->hits, t->contacts);
            else
                sort_keys(t->hits, sort_scratch_[size_t(me)]);
            hits_[size_t(me)].swap(t->hits);
            hit_contacts[size_t(me)].swap(t->contacts);
        }
    });
    for (const auto &t : worker)
        if (t) fresh.insert(fresh.end(), t->witnesses.begin(), t->witnesses.end());
    for (const Counts &c : counts) {
        stats_.narrow_tests += c.narrow_tests;
        stats_.triangle_tests += c.triangle_tests;
        stats_.containment_pairs += c.containment;
        stats_.libccd_tests += c.libccd_tests;
        stats_.libccd_fallback_tests += c.libccd_fallback;
    }
}

// Appends the pairs among n batch verdicts that met to t.hits: listed first
// without a branch (a branch per pair on its verdict mispredicted often:
// hits are 28% of the pairs), then keyed by slots, read from `keys` when the
// batch's pairs are the chunk's in order (keys non-null), else from the pairs.
template <class Pair>
void World::append_hits(const Contact *verdict, size_t n, const Pair *pairs, const uint64_t *keys,
                        NarrowThread &t) const {
    size_t hit_count = 0;
    for (size_t k = 0; k < n; ++k) {
        t.hit_index[hit_count] = uint32_t(k);
        hit_count += verdict[k] != Contact::None;
        t.containment += verdict[k] == Contact::Containment;
    }
    const size_t at = t.hits.size();
    t.hits.resize(at + hit_count);
    uint64_t *to = t.hits.data() + at;
    if (keys) {
        for (size_t h = 0; h < hit_count; ++h) {
            const uint64_t key = keys[t.hit_index[h]];
            to[h] = pair_key(slot_of_[key >> 32], slot_of_[uint32_t(key)]);
        }
    } else {
        for (size_t h = 0; h < hit_count; ++h) {
            const Pair &p = pairs[t.hit_index[h]];
            to[h] = pair_key(slot_of_[p.a - place_.data()], slot_of_[p.b - place_.data()]);
        }
    }
}

void World::narrow_chunk(const NarrowPlan &plan, const NarrowChunk &chunk, NarrowThread &t) const {
    const PairBuffer &list = candidates_[chunk.list];
    size_t tetras = 0;
    if (plan.all_tetra) {
        const Mesh *meshes = meshes_.data();
        const Placement *place = place_.data();
        const uint32_t *body_mesh = body_mesh_.data();
        const MeshPool::Block *records = pool_.blocks();
        const BodyRecord *record = body_record_.data();
        const uint32_t *slot_of = slot_of_.data();
        for (size_t k = chunk.begin; k < chunk.end; ++k, ++tetras) {
            // The lines of the pair 16 ahead asked for (around moved
            // bodies the other body of a pair is anywhere in storage, the
            // static ones of a large world in tens of megabytes); the
            // slots for the hits below, the placements for the batch.
            if (k + 16 < chunk.end) {
                const uint32_t a2 = uint32_t(list[k + 16] >> 32), b2 = uint32_t(list[k + 16]);
                __builtin_prefetch(&record[a2]);
                __builtin_prefetch(&record[b2]);
                __builtin_prefetch(&body_mesh[a2]);
                __builtin_prefetch(&body_mesh[b2]);
                __builtin_prefetch(&slot_of[a2]);
                __builtin_prefetch(&slot_of[b2]);
                __builtin_prefetch(place + a2);
                __builtin_prefetch(place + b2);
            }
            const uint32_t a = uint32_t(list[k] >> 32), b = uint32_t(list[k]);
            t.tetra[tetras] = TetraPair{meshes + body_mesh[a], meshes + body_mesh[b], place + a, place + b,
                                        records[record[a].block].d, records[record[b].block].d};
        }
    } else if (plan.all_convex) {
        const Mesh *meshes = meshes_.data();
        const Placement *place = place_.data();
        const uint32_t *body_mesh = body_mesh_.data();
        const uint32_t *slot_of = slot_of_.data();
        const SatData *const *sat = mesh_sat_.data();
        for (size_t k = chunk.begin; k < chunk.end; ++k) {
            // (as above: the slots for the hits below, and the meshes'
            // convex data pointers, through their slots asked for first;
            // the batch asks for the placements itself)
            if (k + 16 < chunk.end) {
                const uint32_t a2 = uint32_t(list[k + 16] >> 32), b2 = uint32_t(list[k + 16]);
                __builtin_prefetch(&body_mesh[a2]);
                __builtin_prefetch(&body_mesh[b2]);
                __builtin_prefetch(&slot_of[a2]);
                __builtin_prefetch(&slot_of[b2]);
            }
            if (k + 8 < chunk.end) {
                __builtin_prefetch(&sat[body_mesh[uint32_t(list[k + 8] >> 32)]]);
                __builtin_prefetch(&sat[body_mesh[uint32_t(list[k + 8])]]);
            }
            const uint32_t a = uint32_t(list[k] >> 32), b = uint32_t(list[k]);
            const uint32_t ma = body_mesh[a], mb = body_mesh[b];
            t.convex[t.convex_count++] = ConvexPair{meshes + ma, meshes + mb, place + a, place + b, sat[ma], sat[mb]};
        }
    } else {
        tetras = narrow_pairs(plan, list, chunk, t);
    }
    if (tetras) {
        collide_tetra_batch(t.tetra, tetras, t.verdict, t.scratch);
        if (plan.margins) within_margins(tetras, t);
    }
    append_hits(t.verdict, tetras, t.tetra, plan.all_tetra ? list.begin() + chunk.begin : nullptr, t);
    if (!t.convex_count) return;
    const size_t n = t.convex_count;
    t.convex_count = 0;
    collide_convex_batch(t.convex, n, t.convex_verdict, t.scratch);
    append_hits(t.convex_verdict, n, t.convex, plan.all_convex ? list.begin() + chunk.begin : nullptr, t);
}

// The batch's pairs whose solids do not touch, with a margin d > 0: Near
// when within d (tet::tetra_within_apart).
void World::within_margins(size_t tetras, NarrowThread &t) const {
    const Placement *place = place_.data();
    const bool uniform = margin_bodies_ == 0;  // (then every pair's margin is the world's)
    for (size_t k = 0; k < tetras; ++k) {
        if (t.verdict[k] != Contact::None) continue;
        const TetraPair &p = t.tetra[k];
        const double d =
            uniform ? world_margin_ : pair_margin(world_margin_, margin_[p.a - place], margin_[p.b - place]);
        if (d > 0) t.verdict[k] = tet::tetra_within_apart(pose_of(p.mesh_a, *p.a), pose_of(p.mesh_b, *p.b), d, t.scratch);
    }
}

// What the later pairs of a chunk will read, asked for in stages, each
// stage's lines read by the next (their latency hidden): for the pair 16
// on, its meshes and slots; 8 on, when no batch will take it, its
// placements and where its witnesses' run starts (by its lower slot); 4 on,
// that run. On `scanned` (a tree pair every candidate) the three lookups
// took 8% of the detect unasked for. A batch asks for its pairs'
// placements itself: asked for here, 512 pairs before their use, they held
// up this loop. (Inlined into the loop: a call GCC's analysis finds free of
// side effects, a prefetch not counting, is deleted.)
__attribute__((always_inline)) inline void World::ask_ahead(const NarrowPlan &plan, const PairBuffer &list,
                                                            size_t k, size_t end) const {
    if (k + 16 < end) {
        const uint64_t p = list[k + 16];
        __builtin_prefetch(&body_mesh_[p >> 32]);
        __builtin_prefetch(&body_mesh_[uint32_t(p)]);
        __builtin_prefetch(&slot_of_[p >> 32]);
        __builtin_prefetch(&slot_of_[uint32_t(p)]);
    }
    const bool runs = !witness_start_.empty();
    if (k + 8 < end) {
        const uint64_t p = list[k + 8];
        const uint32_t a = uint32_t(p >> 32), b = uint32_t(p);
        if (!(plan.queued[body_mesh_[a]] & plan.queued[body_mesh_[b]])) {
            __builtin_prefetch(&place_[a]);
            __builtin_prefetch(&place_[b]);
            if (runs) __builtin_prefetch(&witness_start_[std::min(slot_of_[a], slot_of_[b])]);
        }
    }
    if (runs && k + 4 < end) {
        const uint64_t p = list[k + 4];
        const uint32_t lo = std::min(slot_of_[p >> 32], slot_of_[uint32_t(p)]);
        if (lo < witness_start_.size()) __builtin_prefetch(witness_.data() + witness_start_[lo]);
    }
}

// The pairs of a chunk whose meshes are not all tetrahedra: each tested here,
// or queued for a batch (NarrowPlan::queued).
// Returns the count queued.
size_t World::narrow_pairs(const NarrowPlan &plan, const PairBuffer &list, const NarrowChunk &chunk,
                           NarrowThread &t) const {
    const bool want_contacts = plan.want_contacts, any_ccd = plan.any_ccd, margins = plan.margins;
    const size_t end = chunk.end;
    size_t tetras = 0;
    for (size_t k = chunk.begin; k < end; ++k) {
        ask_ahead(plan, list, k, end);
        // Storage indices. The exact verdict does not depend on the order of
        // the two bodies, so only contacts (which follow the pair's order as
        // reported) and libccd (whose tolerances might) take them in slot
        // order, and only hits look their slots up (28% of the pairs on tetra).
        uint32_t a = uint32_t(list[k] >> 32), b = uint32_t(list[k]);
        if ((want_contacts || any_ccd) && slot_of_[a] > slot_of_[b]) std::swap(a, b);
        const Placement &la = place_[a], &lb = place_[b];
        const Mesh *mesh_a = &meshes_[body_mesh_[a]], *mesh_b = &meshes_[body_mesh_[b]];
        const uint8_t queue = plan.queued[body_mesh_[a]] & plan.queued[body_mesh_[b]];
        if (queue & kQueueTetra) {
            t.tetra[tetras++] = TetraPair{mesh_a, mesh_b, &la, &lb, pool_.blocks()[body_record_[a].block].d,
                                          pool_.blocks()[body_record_[b].block].d};
            continue;
        }
        if (queue & kQueueConvex) {
            t.convex[t.convex_count++] = ConvexPair{mesh_a, mesh_b, &la, &lb, mesh_a->sat.get(), mesh_b->sat.get()};
            continue;
        }
        const BodyPose pa = pose_of(mesh_a, la), pb = pose_of(mesh_b, lb);
        hgcd_contact contact;
        const uint8_t ma = any_ccd ? plan.ccd_mode[body_mesh_[a]] : 0;
        const uint8_t mb = any_ccd ? plan.ccd_mode[body_mesh_[b]] : 0;
        const double d = margins ? pair_margin(world_margin_, margin_[a], margin_[b]) : 0;
        Contact hit;
        if ((!mesh_a->bvh.empty() || !mesh_b->bvh.empty()) && !want_contacts && !(ma & mb & kCcdUse) && !(d > 0)) {
            // A pair with a tree: the meeting triangles of its last detect first.
            const uint32_t sa = slot_of_[a], sb = slot_of_[b];
            const uint64_t key = pair_key(sa, sb);
            NodeHint hint;
            if (const NodeWitness *w = find_witness(key)) {
                if (w->node[0] >= kAxisTag) {  // the axis is kept pointing from the higher slot's body
                    unpack_axis(w->node[1], hint.axis, sa < sb ? 1 : -1);
                    hint.axis_given = true;
                    hint.support_a = witness_support(w->node[0], sa < sb);
                    hint.support_b = witness_support(w->node[0], sa > sb);
                } else {
                    hint.node_a = w->node[sa > sb];
                    hint.node_b = w->node[sa < sb];
                }
            }
            if (ma & mb & kCcdAsked) ++t.ccd_fallback;
            hit = collide(pa, pb, t.scratch, nullptr, &hint);
            if (hint.found)
                t.witnesses.push_back(NodeWitness{key, {sa < sb ? hint.node_a : hint.node_b, sa < sb ? hint.node_b : hint.node_a}});
            else if (hint.axis_found)
                t.witnesses.push_back(NodeWitness{key, {sa < sb ? axis_witness(hint.support_a, hint.support_b)
                                                               : axis_witness(hint.support_b, hint.support_a),
                                                        pack_axis(hint.axis, sa < sb ? 1 : -1)}});
        } else {
            hit = collide_pair(pa, pb, ma, mb, d, want_contacts, t, &contact);
        }
        if (hit != Contact::None) {
            t.hits.push_back(pair_key(slot_of_[a], slot_of_[b]));
            if (want_contacts) t.contacts.push_back(contact);
            if (hit == Contact::Containment) ++t.containment;
        }
    }
    return tetras;
}

// One pair by libccd (both meshes convex and set to it) or by the exact test,
// with its contact if asked for; ma, mb: the meshes' kCcd* bits. A pair with
// a margin d > 0 is decided exactly (never by libccd); its contact is the
// exact touching one when the solids touch, else NEAR.
Contact World::collide_pair(const BodyPose &pa, const BodyPose &pb, uint8_t ma, uint8_t mb, double d,
                            bool want_contacts, NarrowThread &t, hgcd_contact *contact) {
    Contact hit;
    if (d > 0) {
        if (ma & mb & kCcdAsked) ++t.ccd_fallback;
        if (!want_contacts) return collide_within(pa, pb, d, t.scratch);
        Witness witness;
        hit = collide_within(pa, pb, d, t.scratch, &witness);
        if (hit != Contact::None) exact_contact(pa, pb, hit, witness, t.contact_scratch, contact);
    } else if (ma & mb & kCcdUse) {
        const CcdMethod method = ((ma | mb) & kCcdGjk) ? CcdMethod::Gjk : CcdMethod::Mpr;
        CcdContact cc;
        hit = ccd_collide(pa, pb, method, t.ccd_scratch, want_contacts ? &cc : nullptr) ? Contact::Surface
                                                                                       : Contact::None;
        if (want_contacts && hit != Contact::None) penetration_contact(cc, contact);
    } else if (want_contacts) {
        if (ma & mb & kCcdAsked) ++t.ccd_fallback;
        Witness witness;
        hit = collide(pa, pb, t.scratch, &witness);
        if (hit != Contact::None) exact_contact(pa, pb, hit, witness, t.contact_scratch, contact);
    } else {
        if (ma & mb & kCcdAsked) ++t.ccd_fallback;
        hit = collide(pa, pb, t.scratch);
    }
    return hit;
}

}  // namespace hgcd
