// The C calls of hgcd_mpi.h: argument checks, collective agreement, and the
// bodies' bookkeeping. The tick itself is in detect.cpp.
#include <algorithm>
#include <cmath>
#include <cstring>
#include <new>

#include <omp.h>

#include "internal.hpp"

using namespace hgcd_mpi;

namespace hgcd_mpi {

void Bodies::push(const Record &r, hgcd_body b) {
    index.emplace(r.id, (uint32_t)rec.size());
    rec.push_back(r);
    local.push_back(b);
}

void Bodies::erase_at(uint32_t k) {
    const uint32_t last = (uint32_t)rec.size() - 1;
    index.erase(rec[k].id);
    if (k != last) {
        rec[k] = rec[last];
        local[k] = local[last];
        index[rec[k].id] = k;
    }
    rec.pop_back();
    local.pop_back();
}

hgcd_body local_create(hgcd_mpi_world *w, const Record &r, bool owned) {
    hgcd_body_desc bd = hgcd_body_desc_default();
    bd.mesh = w->meshes[r.mesh].local;
    std::memcpy(bd.position, r.position, sizeof bd.position);
    std::memcpy(bd.orientation, r.orientation, sizeof bd.orientation);
    bd.scale = r.scale;
    bd.user_data = r.id;
    hgcd_body b;
    // The body was checked when it was added: only memory or capacity fail.
    if (hgcd_body_create(w->local, &bd, &b) != HGCD_OK) throw std::bad_alloc();
    if (b.index >= w->id_of_local.size()) {
        const size_t n = std::max<size_t>(b.index + 1, 2 * w->id_of_local.size());
        w->id_of_local.resize(n);
        w->owned_of_local.resize(n);
    }
    w->id_of_local[b.index] = r.id;
    w->owned_of_local[b.index] = owned;
    if (b.index != w->live) w->dense = false;
    ++w->live;
    return b;
}

// Destroys a local body. While the world is dense, the body of the highest
// index takes the freed index: it is destroyed first, then b, and created
// again, which hgcd places in the slot freed last (b's); the top index is
// then the next free one, for the next create.
void local_destroy(hgcd_mpi_world *w, hgcd_body b) {
    const uint32_t top = w->live - 1;
    if (!w->dense || b.index == top) {
        hgcd_body_destroy(w->local, b);
        w->owned_of_local[b.index] = 0;
        --w->live;
        return;
    }
    const uint64_t id = w->id_of_local[top];
    Bodies &set = w->owned_of_local[top] ? w->owned : w->ghosts;
    const uint32_t k = set.index.at(id);
    hgcd_body_destroy(w->local, set.local[k]);
    hgcd_body_destroy(w->local, b);
    w->owned_of_local[top] = 0;
    w->owned_of_local[b.index] = 0;
    w->live -= 2;
    const uint32_t expected = b.index;
    const bool dense = w->dense;
    w->live = expected;  // local_create checks the index against live
    set.local[k] = local_create(w, set.rec[k], &set == &w->owned);
    w->live = top;
    w->dense = dense && set.local[k].index == expected;
}

void add_owned(hgcd_mpi_world *w, const Record &r) {
    // A body arriving where it was a ghost stops being one.
    auto g = w->ghosts.index.find(r.id);
    if (g != w->ghosts.index.end()) remove_ghost_at(w, g->second);
    w->owned.push(r, local_create(w, r, true));
    w->owned_ids.push_back(r.id);
}

void remove_owned_at(hgcd_mpi_world *w, uint32_t k) {
    local_destroy(w, w->owned.local[k]);
    w->owned.erase_at(k);
    w->owned_ids[k] = w->owned_ids.back();
    w->owned_ids.pop_back();
}

void remove_ghost_at(hgcd_mpi_world *w, uint32_t k) {
    local_destroy(w, w->ghosts.local[k]);
    w->ghosts.erase_at(k);
}

}  // namespace hgcd_mpi

namespace {

template <class D>
bool initialised(const D *d) {
    return d->struct_size == sizeof(D) && d->init_tag == kInitTag;
}

// Runs a rank's local part of a collective call, turning exceptions into a
// status (and message) that the agreement then shares.
template <class F>
hgcd_status local_part(hgcd_mpi_world *w, const char *what, F &&f) noexcept {
    try {
        return f();
    } catch (const std::bad_alloc &) {
        return fail(w, HGCD_ERROR_OUT_OF_MEMORY, std::string(what) + ": out of memory");
    } catch (const std::exception &e) {
        return fail(w, HGCD_ERROR_INTERNAL, std::string(what) + ": " + e.what());
    } catch (...) {
        return fail(w, HGCD_ERROR_INTERNAL, std::string(what) + ": unknown exception");
    }
}

// The part after every rank agreed: a failure here leaves the world unusable.
template <class F>
hgcd_status commit(hgcd_mpi_world *w, const char *what, F &&f) noexcept {
    try {
        return f();
    } catch (...) {
        w->broken = true;
        try {
            w->error = std::string(what) + ": out of memory while moving bodies; the world is unusable";
        } catch (...) {
        }
        return HGCD_ERROR_OUT_OF_MEMORY;
    }
}

std::string id_str(uint64_t id) { return std::to_string((unsigned long long)id); }

}  // namespace

extern "C" {

hgcd_mpi_world_desc hgcd_mpi_world_desc_default(void) {
    hgcd_mpi_world_desc d;
    std::memset(&d, 0, sizeof d);
    d.struct_size = sizeof d;
    d.init_tag = kInitTag;
    d.imbalance_factor = 1.2;
    return d;
}

hgcd_mpi_body_desc hgcd_mpi_body_desc_default(void) {
    hgcd_mpi_body_desc d;
    std::memset(&d, 0, sizeof d);
    d.struct_size = sizeof d;
    d.init_tag = kInitTag;
    d.orientation[3] = 1;
    d.scale = 1;
    return d;
}

hgcd_status hgcd_mpi_world_create(MPI_Comm comm, const hgcd_mpi_world_desc *desc,
                                  hgcd_mpi_world **out_world) {
    if (out_world) *out_world = nullptr;
    if (comm == MPI_COMM_NULL) return HGCD_ERROR_INVALID_ARGUMENT;
    int inter = 0;
    MPI_Comm_test_inter(comm, &inter);
    if (inter) return HGCD_ERROR_INVALID_ARGUMENT;
    // Every rank's verdict and settings, compared before anything is made.
    hgcd_status s = HGCD_OK;
    if (!desc || !out_world) s = HGCD_ERROR_NULL_ARGUMENT;
    else if (!initialised(desc)) s = HGCD_ERROR_BAD_DESCRIPTOR;
    else if (desc->thread_count > 4096 || !std::isfinite(desc->imbalance_factor) ||
             desc->imbalance_factor < 1 || !std::isfinite(desc->motion_allowance) ||
             desc->motion_allowance < 0)
        s = HGCD_ERROR_INVALID_ARGUMENT;
    double v[4] = {0, 0, 0, 0}, lo[4], hi[4];
    if (s == HGCD_OK) v[0] = desc->imbalance_factor, v[1] = desc->motion_allowance;
    v[2] = -(double)s;  // statuses are negative: max of -s is the worst
    MPI_Allreduce(v, lo, 3, MPI_DOUBLE, MPI_MIN, comm);
    MPI_Allreduce(v, hi, 3, MPI_DOUBLE, MPI_MAX, comm);
    if (hi[2] != 0) return s != HGCD_OK ? s : (hgcd_status)(-hi[2]);
    if (lo[0] != hi[0] || lo[1] != hi[1]) return HGCD_ERROR_INVALID_ARGUMENT;

    hgcd_mpi_world *w = new (std::nothrow) hgcd_mpi_world();
    s = w ? HGCD_OK : HGCD_ERROR_OUT_OF_MEMORY;
    if (w) {
        hgcd_world_desc wd = hgcd_world_desc_default();
        wd.thread_count = desc->thread_count;
        s = hgcd_world_create(&wd, &w->local);
        wd.thread_count = 1;
        if (s == HGCD_OK) s = hgcd_world_create(&wd, &w->checking);
    }
    int bad = s != HGCD_OK, anybad = 0;
    MPI_Allreduce(&bad, &anybad, 1, MPI_INT, MPI_MAX, comm);
    if (anybad) {
        if (w) {
            hgcd_world_destroy(w->local);
            hgcd_world_destroy(w->checking);
            delete w;
        }
        return s != HGCD_OK ? s : HGCD_ERROR_OUT_OF_MEMORY;
    }
    MPI_Comm_dup(comm, &w->comm);
    MPI_Comm_rank(w->comm, &w->rank);
    MPI_Comm_size(w->comm, &w->size);
    w->threads = desc->thread_count ? (int)desc->thread_count : omp_get_num_procs();
    w->imbalance_factor = desc->imbalance_factor;
    w->motion_allowance = desc->motion_allowance;
    try {
        w->decomp.single(w->size);
    } catch (...) {
        hgcd_mpi_world_destroy(w);
        return HGCD_ERROR_OUT_OF_MEMORY;  // on this rank only: too little for a few boxes
    }
    *out_world = w;
    return HGCD_OK;
}

void hgcd_mpi_world_destroy(hgcd_mpi_world *w) {
    if (!w) return;
    hgcd_world_destroy(w->local);
    hgcd_world_destroy(w->checking);
    if (w->comm != MPI_COMM_NULL) MPI_Comm_free(&w->comm);
    delete w;
}

const char *hgcd_mpi_world_last_error(const hgcd_mpi_world *w) {
    return w ? w->error.c_str() : "hgcd_mpi_world_last_error: world is NULL";
}

hgcd_status hgcd_mpi_world_rank(const hgcd_mpi_world *w, int *out_rank, int *out_size) {
    if (!w || !out_rank || !out_size) return HGCD_ERROR_NULL_ARGUMENT;
    *out_rank = w->rank;
    *out_size = w->size;
    return HGCD_OK;
}

uint64_t hgcd_mpi_world_body_count(const hgcd_mpi_world *w) { return w ? w->global_bodies : 0; }

hgcd_status hgcd_mpi_mesh_register(hgcd_mpi_world *w, const hgcd_mesh_desc *desc, uint32_t *out_mesh) {
    if (!w) return HGCD_ERROR_NULL_ARGUMENT;
    hgcd_mesh local{0, 0}, checking{0, 0};
    uint64_t hash = 1469598103934665603ull;
    hgcd_status s = local_part(w, "mesh_register", [&]() -> hgcd_status {
        if (w->broken) return fail(w, HGCD_ERROR_OUT_OF_MEMORY, "mesh_register: the world is unusable");
        if (!desc || !out_mesh) return fail(w, HGCD_ERROR_NULL_ARGUMENT, "mesh_register: desc or out_mesh is NULL");
        hgcd_status st = hgcd_mesh_create(w->local, desc, &local);
        if (st != HGCD_OK) return fail(w, st, std::string("mesh_register: ") + hgcd_world_last_error(w->local));
        st = hgcd_mesh_create(w->checking, desc, &checking);
        if (st != HGCD_OK) return fail(w, st, std::string("mesh_register: ") + hgcd_world_last_error(w->checking));
        // FNV-1a of the counts and the bytes, compared between ranks below.
        auto mix = [&](const void *p, size_t n) {
            for (size_t i = 0; i < n; ++i) hash = (hash ^ ((const unsigned char *)p)[i]) * 1099511628211ull;
        };
        mix(&desc->vertex_count, 4);
        mix(&desc->triangle_count, 4);
        mix(desc->vertices, (size_t)desc->vertex_count * 3 * sizeof(double));
        mix(desc->triangles, (size_t)desc->triangle_count * 3 * sizeof(uint32_t));
        w->meshes.reserve(w->meshes.size() + 1);
        return HGCD_OK;
    });
    s = agree(w, s, "mesh_register");
    if (s == HGCD_OK) {
        uint64_t lo, hi;
        MPI_Allreduce(&hash, &lo, 1, MPI_UINT64_T, MPI_MIN, w->comm);
        MPI_Allreduce(&hash, &hi, 1, MPI_UINT64_T, MPI_MAX, w->comm);
        w->stats.collective_calls += 2;
        if (lo != hi)
            s = fail(w, HGCD_ERROR_INVALID_ARGUMENT, "mesh_register: the mesh data differ between ranks");
    }
    if (s != HGCD_OK) {
        if (local.generation) hgcd_mesh_destroy(w->local, local);
        if (checking.generation) hgcd_mesh_destroy(w->checking, checking);
        return s;
    }
    hgcd_mesh_info info;
    info.struct_size = sizeof info;
    hgcd_mesh_get_info(w->local, local, &info);
    w->meshes.push_back(Mesh{local, checking, info.reach});  // reserved above
    *out_mesh = (uint32_t)(w->meshes.size() - 1);
    return HGCD_OK;
}

hgcd_status hgcd_mpi_bodies_add(hgcd_mpi_world *w, const hgcd_mpi_body_desc *descs, size_t count) {
    if (!w) return HGCD_ERROR_NULL_ARGUMENT;
    std::vector<Record> recs;
    // Each rank checks its own entries as hgcd_body_create would.
    hgcd_status s = local_part(w, "bodies_add", [&]() -> hgcd_status {
        if (w->broken) return fail(w, HGCD_ERROR_OUT_OF_MEMORY, "bodies_add: the world is unusable");
        if (count && !descs) return fail(w, HGCD_ERROR_NULL_ARGUMENT, "bodies_add: descs is NULL");
        recs.resize(count);
        for (size_t k = 0; k < count; ++k) {
            const hgcd_mpi_body_desc &d = descs[k];
            const std::string entry = "bodies_add: entry " + std::to_string(k);
            if (!initialised(&d))
                return fail(w, HGCD_ERROR_BAD_DESCRIPTOR,
                            entry + ": not initialised by hgcd_mpi_body_desc_default()");
            if (d.mesh >= w->meshes.size())
                return fail(w, HGCD_ERROR_INVALID_ARGUMENT, entry + ": mesh " + std::to_string(d.mesh) +
                                                                " is not registered");
            hgcd_body_desc bd = hgcd_body_desc_default();
            bd.mesh = w->meshes[d.mesh].checking;
            std::memcpy(bd.position, d.position, sizeof bd.position);
            std::memcpy(bd.orientation, d.orientation, sizeof bd.orientation);
            bd.scale = d.scale;
            hgcd_body b;
            const hgcd_status st = hgcd_body_create(w->checking, &bd, &b);
            if (st != HGCD_OK)
                return fail(w, st, entry + " (id " + id_str(d.id) + "): " + hgcd_world_last_error(w->checking));
            hgcd_body_destroy(w->checking, b);
            Record &r = recs[k];
            std::memset(&r, 0, sizeof r);
            r.id = d.id;
            r.mesh = d.mesh;
            std::memcpy(r.position, d.position, sizeof r.position);
            std::memcpy(r.orientation, d.orientation, sizeof r.orientation);
            r.scale = d.scale;
        }
        return HGCD_OK;
    });
    if ((s = agree(w, s, "bodies_add")) != HGCD_OK) return s;

    // The ids to the ranks keeping their part of the directory (id % size),
    // which refuse an id live already or given twice.
    std::vector<char> ids;
    s = local_part(w, "bodies_add", [&]() -> hgcd_status {
        std::vector<std::vector<char>> out(w->size);
        for (const Record &r : recs) {
            auto &o = out[r.id % (uint64_t)w->size];
            o.insert(o.end(), (const char *)&r.id, (const char *)&r.id + 8);
        }
        ids = hgcd_mpi::exchange(w, out);
        std::unordered_set<uint64_t> seen;
        for (size_t k = 0; k < ids.size() / 8; ++k) {
            uint64_t id;
            std::memcpy(&id, ids.data() + 8 * k, 8);
            if (w->directory.count(id))
                return fail(w, HGCD_ERROR_INVALID_ARGUMENT, "bodies_add: id " + id_str(id) + " is already live");
            if (!seen.insert(id).second)
                return fail(w, HGCD_ERROR_INVALID_ARGUMENT, "bodies_add: id " + id_str(id) + " is given twice");
        }
        return HGCD_OK;
    });
    if ((s = agree(w, s, "bodies_add")) != HGCD_OK) return s;

    return commit(w, "bodies_add", [&]() -> hgcd_status {
        for (size_t k = 0; k < ids.size() / 8; ++k) {
            uint64_t id;
            std::memcpy(&id, ids.data() + 8 * k, 8);
            w->directory.insert(id);
        }
        unsigned long long n = recs.size(), total = 0;
        MPI_Allreduce(&n, &total, 1, MPI_UNSIGNED_LONG_LONG, MPI_SUM, w->comm);
        ++w->stats.collective_calls;
        if (w->global_bodies == 0 && total > 0) {
            // An empty world: cut space by the bodies being added.
            std::vector<double> points(3 * recs.size());
            for (size_t k = 0; k < recs.size(); ++k) std::memcpy(&points[3 * k], recs[k].position, 24);
            rcb(w, points);
        }
        std::vector<std::vector<char>> out(w->size);
        for (const Record &r : recs) {
            auto &o = out[w->decomp.locate(r.position)];
            o.insert(o.end(), (const char *)&r, (const char *)&r + sizeof r);
        }
        const std::vector<char> in = hgcd_mpi::exchange(w, out);
        for (size_t k = 0; k < in.size() / sizeof(Record); ++k) {
            Record r;
            std::memcpy(&r, in.data() + k * sizeof r, sizeof r);
            add_owned(w, r);
        }
        w->global_bodies += total;
        return HGCD_OK;
    });
}

hgcd_status hgcd_mpi_bodies_remove(hgcd_mpi_world *w, const uint64_t *ids, size_t count) {
    if (!w) return HGCD_ERROR_NULL_ARGUMENT;
    hgcd_status s = HGCD_OK;
    if (w->broken) s = fail(w, HGCD_ERROR_OUT_OF_MEMORY, "bodies_remove: the world is unusable");
    else if (count && !ids) s = fail(w, HGCD_ERROR_NULL_ARGUMENT, "bodies_remove: ids is NULL");
    else if (count > (size_t)INT32_MAX) s = fail(w, HGCD_ERROR_CAPACITY, "bodies_remove: count above 2^31 - 1");
    if ((s = agree(w, s, "bodies_remove")) != HGCD_OK) return s;
    std::vector<uint64_t> all;
    s = local_part(w, "bodies_remove", [&]() -> hgcd_status {
        int n = (int)count;
        std::vector<int> counts(w->size), displ(w->size);
        MPI_Allgather(&n, 1, MPI_INT, counts.data(), 1, MPI_INT, w->comm);
        size_t total = 0;
        for (int r = 0; r < w->size; ++r) {
            if (total + counts[r] > (size_t)INT32_MAX) throw std::bad_alloc();
            displ[r] = (int)total;
            total += counts[r];
        }
        all.resize(total);
        MPI_Allgatherv(ids, n, MPI_UINT64_T, all.data(), counts.data(), displ.data(), MPI_UINT64_T, w->comm);
        w->stats.collective_calls += 2;
        std::vector<uint64_t> sorted(all);
        std::sort(sorted.begin(), sorted.end());
        for (size_t k = 1; k < sorted.size(); ++k)
            if (sorted[k] == sorted[k - 1])
                return fail(w, HGCD_ERROR_INVALID_ARGUMENT, "bodies_remove: id " + id_str(sorted[k]) + " is given twice");
        for (uint64_t id : sorted)
            if (id % (uint64_t)w->size == (uint64_t)w->rank && !w->directory.count(id))
                return fail(w, HGCD_ERROR_INVALID_ARGUMENT, "bodies_remove: id " + id_str(id) + " is not live");
        return HGCD_OK;
    });
    if ((s = agree(w, s, "bodies_remove")) != HGCD_OK) return s;
    for (uint64_t id : all) {
        auto o = w->owned.index.find(id);
        if (o != w->owned.index.end()) remove_owned_at(w, o->second);
        auto g = w->ghosts.index.find(id);
        if (g != w->ghosts.index.end()) remove_ghost_at(w, g->second);
        w->directory.erase(id);
    }
    w->global_bodies -= all.size();
    return HGCD_OK;
}

hgcd_status hgcd_mpi_owned(const hgcd_mpi_world *w, const uint64_t **out_ids, size_t *out_count) {
    if (!w || !out_ids || !out_count) return HGCD_ERROR_NULL_ARGUMENT;
    *out_ids = w->owned_ids.data();
    *out_count = w->owned_ids.size();
    return HGCD_OK;
}

}  // extern "C"
