// Local calls on a rank's owned bodies and results, and the gather of every
// rank's pairs.
#include <algorithm>
#include <climits>
#include <cstring>
#include <new>

#include "internal.hpp"

using namespace hgcd_mpi;

namespace {

bool bad_stride(size_t stride, size_t entry) {
    return stride % sizeof(double) != 0 || (stride != 0 && stride < entry);
}

// The owned positions of the entries: ids looked up, or 0 .. count-1.
hgcd_status owned_entries(const hgcd_mpi_world *w, const char *what, const uint64_t *ids, size_t count,
                          std::vector<uint32_t> &at, std::string *msg) {
    if (!ids) {
        if (count > w->owned.rec.size()) {
            if (msg) *msg = std::string(what) + ": count " + std::to_string(count) + " is above the " +
                            std::to_string(w->owned.rec.size()) + " bodies owned by this rank";
            return HGCD_ERROR_STALE_ID;
        }
        return HGCD_OK;
    }
    at.resize(count);
    for (size_t k = 0; k < count; ++k) {
        auto it = w->owned.index.find(ids[k]);
        if (it == w->owned.index.end()) {
            if (msg) *msg = std::string(what) + ": entry " + std::to_string(k) + ": id " +
                            std::to_string((unsigned long long)ids[k]) + " is not owned by this rank";
            return HGCD_ERROR_STALE_ID;
        }
        at[k] = it->second;
    }
    return HGCD_OK;
}

// The new poses into the owned records (entry k: owned body at[k], or k).
void copy_poses(hgcd_mpi_world *w, const uint32_t *at, size_t count, const double *positions, size_t ps,
                const double *orientations, size_t os) {
#pragma omp parallel for num_threads(w->threads) if (count > 4096) schedule(static)
    for (size_t k = 0; k < count; ++k) {
        Record &r = w->owned.rec[at ? at[k] : k];
        if (positions) std::memcpy(r.position, (const char *)positions + k * ps, sizeof r.position);
        if (orientations) std::memcpy(r.orientation, (const char *)orientations + k * os, sizeof r.orientation);
    }
}

// The fast path of a dense local world (hgcd_mpi_world::dense): every pose
// of the local world laid out by local index -- the new ones of owned bodies
// 0 .. count-1, the current ones of the others, whose unchanged bits hgcd
// does not count as moves -- and handed over by index. Any refusal falls
// back to the listed path, which refuses alike and names the caller's entry.
hgcd_status by_index(hgcd_mpi_world *w, size_t count, const double *positions, size_t position_stride,
                     size_t ps, const double *orientations, size_t orientation_stride, size_t os) {
    if (!positions && !orientations) return HGCD_ERROR_NULL_ARGUMENT;
    if (bad_stride(position_stride, 3 * sizeof(double)) || bad_stride(orientation_stride, 4 * sizeof(double)))
        return HGCD_ERROR_INVALID_ARGUMENT;
    const size_t n = w->live, pos_at = 0, rot_at = positions ? 3 * n : 0;
    if (n != w->owned.rec.size() + w->ghosts.rec.size()) return HGCD_ERROR_INTERNAL;  // never: listed path
    w->pose_buffer.resize((positions ? 3 * n : 0) + (orientations ? 4 * n : 0));
    double *buf = w->pose_buffer.data();
    auto put = [&](const hgcd_body b, const double *p, const double *q) {
        if (positions) std::memcpy(buf + pos_at + 3 * (size_t)b.index, p, 24);
        if (orientations) std::memcpy(buf + rot_at + 4 * (size_t)b.index, q, 32);
    };
    const int64_t no = (int64_t)w->owned.rec.size(), ng = (int64_t)w->ghosts.rec.size();
#pragma omp parallel num_threads(w->threads) if (n > 4096)
    {
#pragma omp for schedule(static) nowait
        for (int64_t k = 0; k < no; ++k) {
            const Record &r = w->owned.rec[k];
            const bool fresh = (size_t)k < count;
            put(w->owned.local[k], fresh && positions ? (const double *)((const char *)positions + k * ps) : r.position,
                fresh && orientations ? (const double *)((const char *)orientations + k * os) : r.orientation);
        }
#pragma omp for schedule(static)
        for (int64_t k = 0; k < ng; ++k) put(w->ghosts.local[k], w->ghosts.rec[k].position, w->ghosts.rec[k].orientation);
    }
    return hgcd_world_set_poses(w->local, nullptr, n, positions ? buf + pos_at : nullptr, 0,
                                orientations ? buf + rot_at : nullptr, 0);
}

}  // namespace

extern "C" {

hgcd_status hgcd_mpi_set_poses(hgcd_mpi_world *w, const uint64_t *ids, size_t count, const double *positions,
                               size_t position_stride, const double *orientations, size_t orientation_stride) {
    if (!w) return HGCD_ERROR_NULL_ARGUMENT;
    try {
        if (w->broken) return fail(w, HGCD_ERROR_OUT_OF_MEMORY, "set_poses: the world is unusable");
        std::vector<uint32_t> at;
        std::string msg;
        hgcd_status s = owned_entries(w, "set_poses", ids, count, at, &msg);
        if (s != HGCD_OK) return fail(w, s, msg);
        const size_t ps = position_stride ? position_stride : 3 * sizeof(double);
        const size_t os = orientation_stride ? orientation_stride : 4 * sizeof(double);
        if (!ids && w->dense && by_index(w, count, positions, position_stride, ps, orientations,
                                         orientation_stride, os) == HGCD_OK) {
            copy_poses(w, nullptr, count, positions, ps, orientations, os);
            return HGCD_OK;
        }
        // The local world checks the whole batch as hgcd_world_set_poses
        // does (values, an id twice, strides) and applies it, or nothing.
        std::vector<hgcd_body> listed;
        const hgcd_body *bodies = w->owned.local.data();
        if (ids) {
            listed.resize(count);
            for (size_t k = 0; k < count; ++k) listed[k] = w->owned.local[at[k]];
            bodies = listed.data();
        }
        s = hgcd_world_set_poses(w->local, bodies, count, positions, position_stride, orientations,
                                 orientation_stride);
        if (s != HGCD_OK) return fail(w, s, std::string("set_poses: ") + hgcd_world_last_error(w->local));
        copy_poses(w, ids ? at.data() : nullptr, count, positions, ps, orientations, os);
        return HGCD_OK;
    } catch (...) {
        // Before the local world changed: only the lookup's memory failed.
        return fail(w, HGCD_ERROR_OUT_OF_MEMORY, "set_poses: out of memory");
    }
}

hgcd_status hgcd_mpi_get_poses(const hgcd_mpi_world *w, const uint64_t *ids, size_t count, double *positions,
                               size_t position_stride, double *orientations, size_t orientation_stride) {
    if (!w || (!positions && !orientations)) return HGCD_ERROR_NULL_ARGUMENT;
    if (bad_stride(position_stride, 3 * sizeof(double)) || bad_stride(orientation_stride, 4 * sizeof(double)))
        return HGCD_ERROR_INVALID_ARGUMENT;
    try {
        std::vector<uint32_t> at;
        const hgcd_status s = owned_entries(w, "get_poses", ids, count, at, nullptr);
        if (s != HGCD_OK) return s;
        const size_t ps = position_stride ? position_stride : 3 * sizeof(double);
        const size_t os = orientation_stride ? orientation_stride : 4 * sizeof(double);
        for (size_t k = 0; k < count; ++k) {
            const Record &r = w->owned.rec[ids ? at[k] : k];
            if (positions) std::memcpy((char *)positions + k * ps, r.position, sizeof r.position);
            if (orientations) std::memcpy((char *)orientations + k * os, r.orientation, sizeof r.orientation);
        }
        return HGCD_OK;
    } catch (...) {
        return HGCD_ERROR_OUT_OF_MEMORY;
    }
}

hgcd_status hgcd_mpi_pairs(const hgcd_mpi_world *w, const hgcd_mpi_pair **out_pairs, size_t *out_count) {
    if (!w || !out_pairs || !out_count) return HGCD_ERROR_NULL_ARGUMENT;
    *out_pairs = w->pairs.data();
    *out_count = w->pairs.size();
    return HGCD_OK;
}

hgcd_status hgcd_mpi_gather_pairs(hgcd_mpi_world *w, int root, const hgcd_mpi_pair **out_pairs,
                                  size_t *out_count) {
    if (!w) return HGCD_ERROR_NULL_ARGUMENT;
    hgcd_status s = HGCD_OK;
    if (w->broken) s = fail(w, HGCD_ERROR_OUT_OF_MEMORY, "gather_pairs: the world is unusable");
    else if (!out_pairs || !out_count) s = fail(w, HGCD_ERROR_NULL_ARGUMENT, "gather_pairs: an output is NULL");
    else if (root < 0 || root >= w->size)
        s = fail(w, HGCD_ERROR_INVALID_ARGUMENT, "gather_pairs: root " + std::to_string(root) + " is not a rank");
    if ((s = agree(w, s, "gather_pairs")) != HGCD_OK) return s;
    int lo = root, hi = root;
    MPI_Allreduce(MPI_IN_PLACE, &lo, 1, MPI_INT, MPI_MIN, w->comm);
    MPI_Allreduce(MPI_IN_PLACE, &hi, 1, MPI_INT, MPI_MAX, w->comm);
    w->stats.collective_calls += 2;
    if (lo != hi) return fail(w, HGCD_ERROR_INVALID_ARGUMENT, "gather_pairs: root differs between ranks");
    const long long mine = (long long)(w->pairs.size() * sizeof(hgcd_mpi_pair));
    std::vector<long long> sizes(w->rank == root ? w->size : 0);
    MPI_Gather(&mine, 1, MPI_LONG_LONG, sizes.data(), 1, MPI_LONG_LONG, root, w->comm);
    ++w->stats.collective_calls;
    std::vector<int> counts, displ;
    s = HGCD_OK;
    try {
        w->gathered.clear();
        if (w->rank == root) {
            long long total = 0;
            counts.resize(w->size);
            displ.resize(w->size);
            for (int r = 0; r < w->size; ++r) {
                displ[r] = (int)std::min<long long>(total, INT_MAX);
                counts[r] = (int)std::min<long long>(sizes[r], INT_MAX);
                total += sizes[r];
            }
            if (total > INT_MAX)
                s = fail(w, HGCD_ERROR_CAPACITY, "gather_pairs: more than INT_MAX bytes of pairs");
            else
                w->gathered.resize((size_t)total / sizeof(hgcd_mpi_pair));
        }
    } catch (...) {
        s = fail(w, HGCD_ERROR_OUT_OF_MEMORY, "gather_pairs: out of memory");
    }
    if ((s = agree(w, s, "gather_pairs")) != HGCD_OK) return s;
    MPI_Gatherv(w->pairs.data(), (int)mine, MPI_BYTE, w->gathered.data(), counts.data(), displ.data(), MPI_BYTE,
                root, w->comm);
    ++w->stats.collective_calls;
    std::sort(w->gathered.begin(), w->gathered.end(), [](const hgcd_mpi_pair &x, const hgcd_mpi_pair &y) {
        return x.a != y.a ? x.a < y.a : x.b < y.b;
    });
    *out_pairs = w->gathered.data();
    *out_count = w->gathered.size();
    return HGCD_OK;
}

hgcd_status hgcd_mpi_stats_get(const hgcd_mpi_world *w, hgcd_mpi_stats *out) {
    if (!w || !out) return HGCD_ERROR_NULL_ARGUMENT;
    if (out->struct_size > 0 && out->struct_size < 8) return HGCD_ERROR_BAD_DESCRIPTOR;
    const size_t n = out->struct_size ? std::min<size_t>(out->struct_size, sizeof *out) : sizeof *out;
    hgcd_mpi_stats s = w->last_stats;
    s.struct_size = (uint32_t)n;
    std::memcpy(out, &s, n);
    return HGCD_OK;
}

hgcd_status hgcd_mpi_local_stats(const hgcd_mpi_world *w, hgcd_stats *out) {
    if (!w) return HGCD_ERROR_NULL_ARGUMENT;
    return hgcd_world_stats(w->local, out);
}

}  // extern "C"
