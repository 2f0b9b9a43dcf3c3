// Poses and velocities of many bodies in one call (hgcd_world_set_poses and
// its siblings): every entry is checked before any is applied, so a refused
// call changes nothing; both passes run on the world's threads.
#include <algorithm>
#include <cstddef>
#include <cstring>
#include <limits>
#include <string>
#include <type_traits>

#if defined(__SSE2__)
#include <immintrin.h>
#endif


#include "common/cpu.hpp"
#include "common/ieee.hpp"
#include "common/parallel.hpp"
#include "world/pose_box.hpp"
#include "world/world.hpp"

namespace hgcd {

namespace {

// Below this many entries a call runs on the calling thread: a parallel
// region costs more than the work.
constexpr size_t kParallelEntries = 4096;

constexpr int64_t kNone = std::numeric_limits<int64_t>::max();

const double *entry(const double *base, size_t stride, size_t k) {
    return reinterpret_cast<const double *>(reinterpret_cast<const char *>(base) + k * stride);
}
double *entry(double *base, size_t stride, size_t k) {
    return reinterpret_cast<double *>(reinterpret_cast<char *>(base) + k * stride);
}

// The byte stride of an array of `doubles`-double entries: 0 means packed;
// otherwise a multiple of sizeof(double), at least the entry. 0 when bad.
size_t stride_of(size_t stride, size_t doubles) {
    if (stride == 0) return doubles * sizeof(double);
    return stride % sizeof(double) == 0 && stride >= doubles * sizeof(double) ? stride : 0;
}

// Entry k's pose into its stage line, the whole 64-byte line in streaming
// stores: the lines are written in the order of the indices, at random
// over the stage, and a whole line written so is not read first. (The
// line's last 8 bytes are padding; a NULL part leaves garbage, never read.)
inline void stage_pose(void *line, const double *p, const double *q) {
#if defined(__SSE2__)
    double *d = static_cast<double *>(line);
    const __m128d z = _mm_setzero_pd();
    _mm_stream_pd(d, p ? _mm_loadu_pd(p) : z);
    _mm_stream_pd(d + 2, _mm_set_pd(q ? q[0] : 0.0, p ? p[2] : 0.0));
    _mm_stream_pd(d + 4, q ? _mm_loadu_pd(q + 1) : z);
    _mm_stream_pd(d + 6, _mm_set_pd(0.0, q ? q[3] : 0.0));
#else
    double *d = static_cast<double *>(line);
    if (p) std::memcpy(d, p, 3 * sizeof(double));
    if (q) std::memcpy(d + 3, q, 4 * sizeof(double));
#endif
}

// Orders the streaming stores before the lines are read (by any thread).
inline void stage_fence() {
#if defined(__SSE2__)
    _mm_sfence();
#endif
}

// The entries [b, e) checked and staged as above, by index at storage index
// at[k]; returns the first that fails, or e.
template <class Ok>
size_t stage_entries(size_t b, size_t e, Ok &ok, void *stage, const uint32_t *at, const double *positions,
                     size_t ps, const double *orientations, size_t os) {
    for (size_t k = b; k < e; ++k) {
        if (!ok(k)) return k;
        stage_pose(static_cast<char *>(stage) + 64 * size_t(at[k]), positions ? entry(positions, ps, k) : nullptr,
                   orientations ? entry(orientations, os, k) : nullptr);
    }
    return e;
}

#if HGCD_AVX2
// The same with each line in one 64-byte streaming store: the memory
// system takes a whole line at once rather than merging four parts (the
// pass is bound by these scattered stores). The orientation's masked load
// starts 3 doubles before it, into lanes 3..6: the lanes masked off read
// nothing (and fault on nothing).
template <class Ok>
__attribute__((target("avx2,avx512f"))) size_t stage_entries_avx512(size_t b, size_t e, Ok &ok, void *stage,
                                                                    const uint32_t *at, const double *positions,
                                                                    size_t ps, const double *orientations,
                                                                    size_t os) {
    for (size_t k = b; k < e; ++k) {
        if (!ok(k)) return k;
        __m512d line = positions ? _mm512_maskz_loadu_pd(0x07, entry(positions, ps, k)) : _mm512_setzero_pd();
        if (orientations)
            line = _mm512_mask_loadu_pd(
                line, 0x78, reinterpret_cast<const double *>(reinterpret_cast<uintptr_t>(entry(orientations, os, k)) -
                                                             3 * sizeof(double)));
        _mm512_stream_pd(static_cast<double *>(stage) + 8 * size_t(at[k]), line);
    }
    return e;
}
#endif

}  // namespace

// Checks the entries k < count a range at a time (on the world's threads for
// large counts) and returns the smallest k that fails, or kNone; the same k
// for any thread count. done() runs after each worker's range.
template <class FirstInRange, class Done>
int64_t World::first_failing_by_range(size_t count, FirstInRange &&first_in_range, Done &&done) const {
    const int T = count >= kParallelEntries ? threads() : 1;
    std::vector<int64_t> first(size_t(T), kNone);
    parallel_for(T, int64_t(count), 4096, Schedule::Static, [&](int64_t b, int64_t e, int me) {
        const int64_t k = int64_t(first_in_range(size_t(b), size_t(e)));
        done();
        if (k < e) first[size_t(me)] = std::min(first[size_t(me)], k);  // (the least failing of the worker's ranges)
    });
    return *std::min_element(first.begin(), first.end());
}

template <class Apply>
void World::for_entries(size_t count, Apply &&apply) {
    const int T = count >= kParallelEntries ? threads() : 1;
    parallel_for(T, int64_t(count), 4096, Schedule::Static, [&](int64_t b, int64_t e, int) {
        for (int64_t k = b; k < e; ++k) apply(size_t(k));
    });
}

// Checks that each entry names a live body, and (storage) puts its storage
// index into batch_at_; a refusal names the first entry without a live
// body, or one named twice. Listed ids always need their storage indices.
hgcd_status World::resolve_entries(const char *what, const hgcd_body *bodies, size_t count, bool storage) {
    if (count > live_gen_.size() && !bodies)
        return fail(HGCD_ERROR_STALE_ID, std::string(what) + ": count " + std::to_string(count) +
                                             " exceeds the body indices in use (" +
                                             std::to_string(live_gen_.size()) + ")");
    storage = storage || bodies;
    if (storage) batch_at_.resize(count);
    const int64_t bad = first_failing(count, [&](size_t k) {
        const int64_t slot = bodies ? live_body(bodies[k]) : (live_gen_[k] ? int64_t(k) : -1);
        if (slot < 0) return false;
        if (storage) batch_at_[k] = at_[size_t(slot)];
        return true;
    });
    if (bad != kNone)
        return fail(HGCD_ERROR_STALE_ID,
                    std::string(what) + ": entry " + std::to_string(bad) +
                        (bodies ? ": body {" + std::to_string(bodies[bad].index) + ", " +
                                      std::to_string(bodies[bad].generation) + "} is not a live body of this world"
                                : ": no live body has index " + std::to_string(bad)));
    if (!bodies) return HGCD_OK;
    // An id named twice would be written by two threads: refused. (The
    // marks are per storage index; a serial pass, cheap beside the rest.)
    if (batch_mark_.size() < live_gen_.size()) batch_mark_.resize(live_gen_.size(), 0);
    if (++batch_epoch_ == 0) {
        std::fill(batch_mark_.begin(), batch_mark_.end(), 0);
        batch_epoch_ = 1;
    }
    for (size_t k = 0; k < count; ++k) {
        uint32_t &mark = batch_mark_[batch_at_[k]];
        if (mark == batch_epoch_)
            return fail(HGCD_ERROR_INVALID_ARGUMENT, std::string(what) + ": entry " + std::to_string(k) +
                                                         " names a body an earlier entry names");
        mark = batch_epoch_;
    }
    return HGCD_OK;
}

inline void World::apply_pose_queued(size_t i, const double *p, const double *q, BoxQueue &boxes, bool stream) {
    apply_pose_with(i, p, q, [&](const double *q_) {
        const BodyRecord rec = body_record_[i];
        // (A bound on the groups: a lane of the kernel takes as many as the
        // largest. q_, not the placement: a load spanning the stores just
        // made to it waits for them.)
        if (float_record_box(i) && rec.groups <= kQueuedGroups)
            boxes.push(BoxJob{q_, place_[i].scale, pool_.blocks()[rec.block].d, rec.groups, &box_off_[6 * i]});
        else
            set_box_offsets(i);
    }, stream);
}

// Whether i starts an aligned run of eight stored bodies below e none of which
// the call names (slot_of >= count): the apply passes skip such runs, for a
// few bodies by index among many (static ones stored after them).
static inline bool none_of_eight_named(const uint32_t *slot_of, size_t count, int64_t i, int64_t e) {
    if ((i & 7) || i + 8 > e) return false;
    bool named = false;
    for (int64_t j = i; j < i + 8; ++j) named |= slot_of[j] < count;
    return !named;
}

#if HGCD_AVX2
// The pass's stage line and the body's placement share a layout (position,
// orientation, then the scale in the placement): one 64-byte load of each,
// the entries given compared bit for bit (memcmp's answer) in one
// comparison, the placement written back whole.
template <bool kSome>
__attribute__((target("avx2,avx512f"))) void World::apply_staged_avx512(int64_t b, int64_t e,
                                                                        const StagedPose *stage, size_t count,
                                                                        bool has_p, bool has_q, BoxQueue &boxes) {
    static_assert(sizeof(StagedPose) == sizeof(Placement) && offsetof(Placement, orientation) == 3 * sizeof(double) &&
                      offsetof(StagedPose, orientation) == 3 * sizeof(double),
                  "stage line and placement share a layout");
    // (Locals: the compiler need not reload them after each store.)
    Placement *const place = place_.data();
    double *const point = point_.data();
    float *const box_off = box_off_.data();
    uint8_t *const moved_at = moved_at_.data();
    const uint32_t *const slot_of = slot_of_.data(), *const stored_gen = stored_gen_.data();
    const BodyRecord *const record = body_record_.data();
    const MeshPool::Block *const blocks = pool_.blocks();
    const bool no_margins = world_margin_ == 0 && margin_bodies_ == 0;  // (float_record_box: a record)
    const __mmask8 given = __mmask8((has_p ? 0x07 : 0) | (has_q ? 0x78 : 0));
    for (int64_t i = b; i < e; ++i) {
        if (kSome && none_of_eight_named(slot_of, count, i, e)) {
            i += 7;
            continue;
        }
        if ((kSome && slot_of[i] >= count) || !stored_gen[i]) continue;
        const __m512d line = _mm512_load_pd(stage[i].position), old = _mm512_load_pd(place[i].position);
        const __mmask8 differ =
            _mm512_mask_cmpneq_epi64_mask(given, _mm512_castpd_si512(line), _mm512_castpd_si512(old));
        const double scale = place[i].scale;
        _mm512_store_pd(place[i].position, _mm512_mask_blend_pd(given, old, line));
        if (has_p) {
            long long bits[3];
            std::memcpy(bits, stage[i].position, sizeof bits);
            for (int a = 0; a < 3; ++a) _mm_stream_si64(reinterpret_cast<long long *>(&point[3 * i + a]), bits[a]);
        }
        if (differ & 0x78) {  // a new orientation: its box
            const BodyRecord rec = record[size_t(i)];
            if (rec.groups != 0 && rec.groups <= kQueuedGroups && (no_margins || float_record_box(size_t(i))))
                boxes.push(BoxJob{stage[i].orientation, scale, blocks[rec.block].d, rec.groups, &box_off[6 * i]});
            else
                set_box_offsets(size_t(i));
        }
        if (differ) moved_at[i] = 1;
    }
}
#endif

hgcd_status World::set_poses(const hgcd_body *bodies, size_t count, const double *positions, size_t position_stride,
                             const double *orientations, size_t orientation_stride) {
    const char *what = "world_set_poses";
    const size_t ps = stride_of(position_stride, 3), os = stride_of(orientation_stride, 4);
    if (!ps || !os)
        return fail(HGCD_ERROR_INVALID_ARGUMENT,
                    std::string(what) + ": a stride must be 0 or a multiple of 8 bytes holding its entry");
    // (By index, the apply pass follows storage and needs no storage indices,
    // and the liveness of the indices is checked in the staging pass.)
    if (bodies || count > live_gen_.size())
        if (hgcd_status s = resolve_entries(what, bodies, count, false)) return s;
    const auto ok = [&](size_t k) {
        return (!positions || position_ok(entry(positions, ps, k))) &&
               (!orientations || orientation_ok(entry(orientations, os, k)));
    };
    const uint32_t *const live = live_gen_.data();
    const auto live_and_ok = [&](size_t k) { return live[k] && ok(k); };
    // By index, each entry is copied to pose_stage_ as it is checked, at its
    // body's storage index (see below); a refusal leaves only that scratch
    // written. (The stage reaches as far as the last storage index named:
    // static bodies are stored after the others, and a call for the moving
    // ones does not name them.)
    // (Every index named: every stored body, without a pass over at_.)
    const size_t n = slot_of_.size();
    const bool some = count < live_gen_.size();
    if (!bodies && count) {
        const size_t last = some ? *std::max_element(at_.begin(), at_.begin() + ptrdiff_t(count)) : n - 1;
        if (pose_stage_.size() <= last) pose_stage_.resize(last + 1);
    }
    StagedPose *const stage = pose_stage_.data();
    const uint32_t *const at = at_.data();
#if HGCD_AVX2
    const bool wide = use_avx512();
#endif
    const int64_t bad = bodies ? first_failing(count, ok) : first_failing_by_range(
        count,
        [&](size_t b, size_t e) {
#if HGCD_AVX2
            if (wide) return stage_entries_avx512(b, e, live_and_ok, stage, at, positions, ps, orientations, os);
#endif
            return stage_entries(b, e, live_and_ok, stage, at, positions, ps, orientations, os);
        },
        stage_fence);
    if (bad != kNone) {
        // A dead index anywhere is the error (as resolve_entries reports
        // it for listed ids); else the pose's, as hgcd_body_set_pose's
        // message for that entry.
        if (!bodies)
            if (hgcd_status s = resolve_entries(what, bodies, count, false)) return s;
        const std::string at = std::string(what) + ": entry " + std::to_string(bad);
        return check_pose(at.c_str(), positions ? entry(positions, ps, size_t(bad)) : nullptr,
                          orientations ? entry(orientations, os, size_t(bad)) : nullptr);
    }
    query_.stale = true;
    if (bodies) {
        const int T = count >= kParallelEntries ? threads() : 1;
        parallel_for(T, int64_t(count), 4096, Schedule::Static, [&](int64_t b, int64_t e, int) {
            BoxQueue boxes;
            for (int64_t k = b; k < e; ++k)
                apply_pose_queued(batch_at_[size_t(k)], positions ? entry(positions, ps, size_t(k)) : nullptr,
                                  orientations ? entry(orientations, os, size_t(k)) : nullptr, boxes);
            boxes.flush();
        });
        return HGCD_OK;
    }
    // All bodies by index: one pass in storage order (the grid's, not the
    // indices'), writing the world's arrays and reading the meshes' records
    // and the staged entries in sequence.
    const int T = n >= kParallelEntries ? threads() : 1;
    const bool has_p = positions, has_q = orientations;
    parallel_for(T, int64_t(n), 4096, Schedule::Static, [&](int64_t b, int64_t e, int) {
        // (Locals, not the captures: apply_pose's writes might alias those.)
        const StagedPose *const stage_ = stage;
        const size_t count_ = count;
        const bool has_p_ = has_p, has_q_ = has_q;
        const uint32_t *const slot_of = slot_of_.data(), *const stored_gen = stored_gen_.data();
        BoxQueue boxes;
        boxes.stream = true;  // (points and offsets written in sequence: see apply_pose_with)
        // (Two loops, with and without the skip below.)
        const auto pass = [&](auto skip) {
            for (int64_t i = b; i < e; ++i) {
                if (skip && none_of_eight_named(slot_of, count_, i, e)) {
                    i += 7;
                    continue;
                }
                // (With every index named, every stored body is.)
                if ((skip && slot_of[i] >= count_) || !stored_gen[i]) continue;
                apply_pose_queued(size_t(i), has_p_ ? stage_[i].position : nullptr,
                                  has_q_ ? stage_[i].orientation : nullptr, boxes, true);
            }
        };
#if HGCD_AVX2
        if (wide) {
            if (some)
                apply_staged_avx512<true>(b, e, stage_, count_, has_p_, has_q_, boxes);
            else
                apply_staged_avx512<false>(b, e, stage_, count_, has_p_, has_q_, boxes);
        } else
#endif
        if (some)
            pass(std::true_type{});
        else
            pass(std::false_type{});
        boxes.flush();
        stage_fence();
    });
    return HGCD_OK;
}

hgcd_status World::set_velocities(const hgcd_body *bodies, size_t count, const double *velocities,
                                  size_t velocity_stride) {
    const char *what = "world_set_velocities";
    const size_t vs = stride_of(velocity_stride, 3);
    if (!vs)
        return fail(HGCD_ERROR_INVALID_ARGUMENT,
                    std::string(what) + ": velocity_stride must be 0 or a multiple of 8 bytes of at least 24");
    if (hgcd_status s = resolve_entries(what, bodies, count, true)) return s;
    const int64_t bad = first_failing(count, [&](size_t k) {
        const double *v = entry(velocities, vs, k);
        return std::isfinite(v[0]) && std::isfinite(v[1]) && std::isfinite(v[2]);
    });
    if (bad != kNone)
        return fail(HGCD_ERROR_INVALID_ARGUMENT,
                    std::string(what) + ": entry " + std::to_string(bad) + ": velocity is not finite");
    for_entries(count, [&](size_t k) {
        const double *v = entry(velocities, vs, k);
        for (int a = 0; a < 3; ++a) velocity_[3 * size_t(batch_at_[k]) + a] = v[a];
    });
    return HGCD_OK;
}

hgcd_status World::get_poses(const hgcd_body *bodies, size_t count, double *positions, size_t position_stride,
                             double *orientations, size_t orientation_stride) const {
    const size_t ps = stride_of(position_stride, 3), os = stride_of(orientation_stride, 4);
    if (!ps || !os) return HGCD_ERROR_INVALID_ARGUMENT;
    if (!bodies && count > live_gen_.size()) return HGCD_ERROR_STALE_ID;
    // (Read-only, so no scratch of the world's: checked, then read.)
    const auto slot_of = [&](size_t k) { return bodies ? live_body(bodies[k]) : (live_gen_[k] ? int64_t(k) : -1); };
    if (first_failing(count, [&](size_t k) { return slot_of(k) >= 0; }) != kNone) return HGCD_ERROR_STALE_ID;
    const int T = count >= kParallelEntries ? threads() : 1;
    parallel_for(T, int64_t(count), 4096, Schedule::Static, [&](int64_t b, int64_t e, int) {
        double *const positions_ = positions, *const orientations_ = orientations;  // (locals, as in set_poses)
        const size_t ps_ = ps, os_ = os;
        for (int64_t k = b; k < e; ++k) {
            const Placement &pl = place_[at_[size_t(slot_of(size_t(k)))]];
            if (positions_) std::memcpy(entry(positions_, ps_, size_t(k)), pl.position, sizeof pl.position);
            if (orientations_) std::memcpy(entry(orientations_, os_, size_t(k)), pl.orientation, sizeof pl.orientation);
        }
    });
    return HGCD_OK;
}

}  // namespace hgcd
