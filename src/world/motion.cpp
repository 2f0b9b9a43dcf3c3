// A tick's motion (step) and the renumbering of the bodies' storage into the
// grid's sweep order.
#include <omp.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <memory>
#include <new>
#include <vector>

#include "common/ieee.hpp"
#include "common/parallel.hpp"
#include "world/permute.hpp"
#include "world/world.hpp"

namespace hgcd {

namespace {

// One tick's motion, applied a range of slots at a time (a SlotPass).
struct Motion {
    bool reflect;
    double dt, lo[3], hi[3];
    Placement *place;
    double *velocity, *point;
    const uint32_t *live;
    const BodyFilter *still;  // when some bodies are static or disabled: they do not move
    uint32_t count;  // of storage
    std::atomic<bool> applied{false};  // some range has moved

    static void run(void *context, uint32_t begin, uint32_t end) {
        Motion &m = *static_cast<Motion *>(context);
        if (!m.applied.load(std::memory_order_relaxed)) m.applied.store(true, std::memory_order_relaxed);
        // Locals, so the compiler need not reload them after each store.
        const bool reflect = m.reflect;
        const double dt = m.dt, lo[3] = {m.lo[0], m.lo[1], m.lo[2]}, hi[3] = {m.hi[0], m.hi[1], m.hi[2]};
        Placement *place = m.place;
        double *velocity = m.velocity, *point = m.point;
        for (uint32_t s = begin; s < end; ++s) {
            // The placement 16 bodies on (past this range too: the thread's
            // next range follows it): the hardware's prefetch left the
            // motion waiting on every placement line (the velocities and
            // points need no such request).
            if (s + 16 < m.count) __builtin_prefetch(&place[s + 16], 1);
            if (!m.live[s]) continue;
            if (m.still && (m.still[s].type == HGCD_BODY_STATIC || (m.still[s].flags & BodyFilter::kDisabled)))
                continue;
            for (int k = 0; k < 3; ++k) {
                double &c = place[s].position[k];
                double &v = velocity[3 * size_t(s) + k];
                double x = c + v * dt;
                if (reflect) {
                    if (x < lo[k]) {
                        x = 2 * lo[k] - x;
                        v = -v;
                    } else if (x > hi[k]) {
                        x = 2 * hi[k] - x;
                        v = -v;
                    }
                    // A move longer than the box is clamped rather than leaving it.
                    x = std::min(std::max(x, lo[k]), hi[k]);
                }
                c = point[3 * size_t(s) + k] = x;
            }
        }
    }
};

}  // namespace

hgcd_status World::step() {
    const int T = threads();
    const double t0 = omp_get_wtime();
    const int64_t n = int64_t(stored_gen_.size());
    const double dt = time_step_;
    // Unless the world reflects (every move then ends inside its box), first
    // check that every move stays finite and in range, then move: a refused
    // step moves nothing.
    if (!reflect_) {
        // Per thread, the largest slot of a body that would leave (-1: none).
        std::vector<int64_t> bad_of(size_t(T), -1);
        // (the moves' own arithmetic, in IEEE mode)
        parallel_for(T, n, 4096, Schedule::Static, [&](int64_t b, int64_t e, int me) {
            int64_t mine = bad_of[size_t(me)];
            for (int64_t s = b; s < e; ++s) {
                if (!stored_gen_[s] || ((static_bodies_ || disabled_bodies_) && still(size_t(s)))) continue;
                for (int k = 0; k < 3; ++k) {
                    if (!coordinate_ok(point_[3 * s + k] + velocity_[3 * s + k] * dt))
                        mine = std::max(mine, int64_t(slot_of_[s]));
                }
            }
            bad_of[size_t(me)] = mine;
        });
        const int64_t bad = *std::max_element(bad_of.begin(), bad_of.end());
        if (bad >= 0)
            return fail(HGCD_ERROR_INVALID_ARGUMENT, "world_step: body " + std::to_string(bad) +
                                                         " would leave the coordinate range (|x| <= 1e15)");
    }
    query_.stale = true;
    drop_movers();             // (the grid is brought to every body's box)
    renumber_if_disordered();  // (before the motion: it then moves storage in order)
    // The moves run inside the grid update's census, a range of slots at a
    // time right before it reads their points (Grid::update), so those are
    // read while in cache.
    Motion motion;
    motion.reflect = reflect_;
    motion.dt = dt;
    for (int k = 0; k < 3; ++k) {
        motion.lo[k] = bounds_min_[k];
        motion.hi[k] = bounds_max_[k];
    }
    motion.place = place_.data();
    motion.velocity = velocity_.data();
    motion.point = point_.data();
    motion.live = stored_gen_.data();
    motion.still = static_bodies_ || disabled_bodies_ ? filter_.data() : nullptr;
    motion.count = uint32_t(n);
    const SlotPass pass{&Motion::run, &motion};
    const double motion_seconds = omp_get_wtime() - t0;
    hgcd_status s;
    try {
        s = detect_with(true, &pass);
    } catch (...) {
        // Failed before its census began: the motion is still owed.
        if (!motion.applied.load(std::memory_order_relaxed)) Motion::run(&motion, 0, uint32_t(n));
        throw;
    }
    stats_.motion_seconds = motion_seconds;
    stats_.total_seconds += motion_seconds;
    return s;
}

// Storage in the grid's sweep order again once two fifths of it are out of
// order (bodies that changed rows since, or the order of creation the first
// time); before the motion, so that it moves storage in order. Not right
// after the grid was rebuilt: its levels may still be settling
// (coarsening), and each new set of levels is a new order; but right after
// the first detect, whose levels come from an estimate that is usually right
// (grid_limits), so that the first ticks read in sequence too, and a world
// detected only once never pays for it. Storage in the order of creation
// costs a tick much more than the disorder that moves leave, and a
// renumbering costs more than half a tick: hence the wait for 40% (at 20%
// the mean tick was longer, at 60% no shorter).
void World::renumber_if_disordered() {
    if (!grid_rebuilt_ && grid_.disorder() * 5 > 2 * uint64_t(live_bodies_)) renumber();
}

bool World::renumber() {
    const size_t n = stored_gen_.size();
    std::vector<uint32_t> sweep, old_of_new, new_of_old;
    std::unique_ptr<unsigned char[]> scratch;
    try {
        sweep.reserve(n);
        old_of_new.reserve(n);
        new_of_old.resize(n);
        scratch.reset(new unsigned char[kPermuteScratch * std::max<size_t>(n, 1)]);
        // The grid may need to grow its per-slot arrays (slots made since
        // the last detect); after this nothing below allocates.
        grid_.reserve_slots(n);
        if (!mover_.empty() && mover_.size() < n) mover_.resize(n, 0);
    } catch (const std::bad_alloc &) {
        return false;  // renumbering only saves time; nothing has changed
    }
    // The grid's order (as of the last detect), its bodies that are not
    // static first and the static ones after, then everything else: bodies
    // made since, and free storage. new_of_old marks what is placed. (The
    // bodies that move then share a short stretch of every array, which
    // the passes over moved bodies read, however many static bodies the
    // world holds.)
    grid_.order(sweep);
    std::fill(new_of_old.begin(), new_of_old.end(), UINT32_MAX);
    uint32_t static_from = UINT32_MAX;
    for (const bool statics : {false, true}) {
        for (const uint32_t i : sweep)
            if (new_of_old[i] == UINT32_MAX && (filter_[i].type == HGCD_BODY_STATIC) == statics) {
                new_of_old[i] = uint32_t(old_of_new.size());
                old_of_new.push_back(i);
            }
        if (!statics) static_from = uint32_t(old_of_new.size());
    }
    // (No static body in the grid: one run, as without the split.)
    static_from_ = static_from < old_of_new.size() ? static_from : UINT32_MAX;
    for (size_t i = 0; i < n; ++i)
        if (new_of_old[i] == UINT32_MAX) {
            new_of_old[i] = uint32_t(old_of_new.size());
            old_of_new.push_back(uint32_t(i));
        }
    // Every per-storage array, one after the other (placements in halves:
    // the scratch holds kPermuteScratch bytes a body), all threads on each.
    const uint32_t *perm = old_of_new.data();
    void *tmp = scratch.get();
    const int T = threads();
    grid_.renumber(old_of_new, new_of_old, tmp, T);
    static_assert(sizeof(Placement) == 2 * kPermuteScratch, "placements move in two halves");
    permute_part<kPermuteScratch>(place_.data(), sizeof(Placement), perm, n, tmp, T);
    permute_part<kPermuteScratch>(reinterpret_cast<unsigned char *>(place_.data()) + kPermuteScratch,
                                  sizeof(Placement), perm, n, tmp, T);
    permute_records<3>(velocity_.data(), perm, n, tmp, T);
    permute_records<3>(point_.data(), perm, n, tmp, T);
    permute_records<6>(box_off_.data(), perm, n, tmp, T);
    permute_records<1>(r_level_.data(), perm, n, tmp, T);
    permute_records<1>(margin_.data(), perm, n, tmp, T);
    permute_records<1>(body_mesh_.data(), perm, n, tmp, T);
    permute_records<1>(reinterpret_cast<uint64_t *>(body_record_.data()), perm, n, tmp, T);
    permute_records<3>(reinterpret_cast<uint64_t *>(filter_.data()), perm, n, tmp, T);
    permute_records<1>(stored_gen_.data(), perm, n, tmp, T);
    permute_records<1>(moved_at_.data(), perm, n, tmp, T);
    if (!mover_.empty()) permute_records<1>(mover_.data(), perm, n, tmp, T);
    permute_records<1>(slot_of_.data(), perm, n, tmp, T);
    parallel_for(T, int64_t(n), 4096, Schedule::Static, [&](int64_t b, int64_t e, int) {
        for (int64_t k = b; k < e; ++k) at_[slot_of_[k]] = uint32_t(k);
    });
    for (uint32_t &i : side_storage_) i = new_of_old[i];  // (the second grid's slots are its own)
    forget_resident_cache();  // (its lists name storage indices)
    moved_parts_.clear();     // (counted by storage index)
    // The meshes' records follow (where bodies have meshes of their own).
    if (pool_.repack(body_mesh_.data(), stored_gen_.data(), n)) refresh_records();
    return true;
}

void World::refresh_records() {
    const size_t n = body_mesh_.size();
    const uint32_t *offset = pool_.offsets(), *size = pool_.sizes();
    parallel_for(threads(), int64_t(n), 4096, Schedule::Static, [&](int64_t b, int64_t e, int) {
        for (int64_t k = b; k < e; ++k)
            body_record_[k] = stored_gen_[k] ? BodyRecord{offset[body_mesh_[k]], size[body_mesh_[k]] / 3}
                                             : BodyRecord{MeshPool::kNone, 0};
    });
}

}  // namespace hgcd
