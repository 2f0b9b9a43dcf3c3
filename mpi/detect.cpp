// One tick of the distributed world: migration, rebalance, ghost exchange,
// the local detect and the owner rule (hgcd_mpi.h explains each).
#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstring>
#include <new>

#include <omp.h>

#include "internal.hpp"

namespace hgcd_mpi {

namespace {

bool inside(const Box &d, const double *p) {
    for (int a = 0; a < 3; ++a)
        if (!(d.lo[a] <= p[a] && p[a] < d.hi[a])) return false;
    return true;
}

double distance(const Box &d, const double *p) {
    double m = 0;
    for (int a = 0; a < 3; ++a) m = std::max({m, d.lo[a] - p[a], p[a] - d.hi[a]});
    return m;
}

void append(std::vector<char> &o, const Record &r) {
    o.insert(o.end(), (const char *)&r, (const char *)&r + sizeof r);
}

Record record_at(const std::vector<char> &in, size_t k) {
    Record r;
    std::memcpy(&r, in.data() + k * sizeof r, sizeof r);
    return r;
}

// Every rank's owned count and region S (the box of its owned bodies'
// boxes), to every rank.
struct Summary {
    double owned;
    Box region;
};

std::vector<Summary> summarise(hgcd_mpi_world *w) {
    Summary mine{(double)w->owned.rec.size(), Box::empty()};
    const int64_t n = (int64_t)w->owned.rec.size();
#pragma omp parallel num_threads(w->threads) if (n > 4096)
    {
        Box part = Box::empty();
#pragma omp for schedule(static) nowait
        for (int64_t k = 0; k < n; ++k) part.grow(body_box(w, w->owned.rec[k]));
#pragma omp critical(hgcd_mpi_summary)
        mine.region.grow(part);  // min and max: the order does not matter
    }
    std::vector<Summary> all(w->size);
    MPI_Allgather(&mine, sizeof mine, MPI_BYTE, all.data(), sizeof mine, MPI_BYTE, w->comm);
    ++w->stats.collective_calls;
    return all;
}

bool unbalanced(const hgcd_mpi_world *w, const std::vector<Summary> &all, double *imbalance) {
    double total = 0, most = 0;
    for (const Summary &s : all) total += s.owned, most = std::max(most, s.owned);
    const double mean = total / w->size;
    *imbalance = total > 0 ? most / mean : 0;
    return most > w->imbalance_factor * mean && most > mean + 1;
}

// The ghosts this rank's neighbours need: each owned body whose box meets a
// neighbour's region S goes to it.
std::vector<int> send_ghosts(hgcd_mpi_world *w, const std::vector<Summary> &all, std::vector<char> &in) {
    const Box &mine = all[w->rank].region;
    std::vector<int> peers;
    for (int r = 0; r < w->size; ++r)
        if (r != w->rank && all[r].region.meets(mine)) peers.push_back(r);
    // Per thread, per peer, in body order; joined in thread order, so the
    // ghosts arrive in the same order for any thread count.
    std::vector<std::vector<std::vector<char>>> parts(w->threads, std::vector<std::vector<char>>(peers.size()));
    const int64_t n = peers.empty() ? 0 : (int64_t)w->owned.rec.size();
    // An exception must not leave the region: a failed append is noted
    // and thrown after it.
    std::atomic<bool> oom{false};
#pragma omp parallel num_threads(w->threads) if (n > 4096)
    {
        auto &mine = parts[omp_get_thread_num()];
#pragma omp for schedule(static)
        for (int64_t i = 0; i < n; ++i) {
            const Record &r = w->owned.rec[i];
            const Box b = body_box(w, r);
            for (size_t k = 0; k < peers.size(); ++k)
                if (b.meets(all[peers[k]].region)) try {
                        append(mine[k], r);
                    } catch (...) {
                        oom = true;
                    }
        }
    }
    if (oom) throw std::bad_alloc();
    std::vector<std::vector<char>> out(peers.size());
    for (auto &part : parts)
        for (size_t k = 0; k < peers.size(); ++k) out[k].insert(out[k].end(), part[k].begin(), part[k].end());
    for (const auto &o : out) w->stats.ghosts_sent += o.size() / sizeof(Record);
    in = exchange_neighbours(w, peers, out);
    w->stats.neighbour_ranks = peers.size();
    return peers;
}

bool same_pose(const Record &a, const Record &b) {
    return std::memcmp(a.position, b.position, sizeof a.position) == 0 &&
           std::memcmp(a.orientation, b.orientation, sizeof a.orientation) == 0;
}

// The local world's ghosts become exactly the records received: poses
// updated in one batch, the ghosts not received destroyed, new ones created.
void update_ghosts(hgcd_mpi_world *w, const std::vector<char> &in) {
    Bodies &g = w->ghosts;
    std::vector<uint8_t> seen(g.rec.size(), 0);
    std::vector<uint64_t> moved_ids;
    std::vector<Record> fresh;
    const size_t n = in.size() / sizeof(Record);
    w->stats.ghosts_received = n;
    for (size_t k = 0; k < n; ++k) {
        const Record r = record_at(in, k);
        auto it = g.index.find(r.id);
        if (it == g.index.end()) {
            fresh.push_back(r);
            continue;
        }
        seen[it->second] = 1;
        Record &old = g.rec[it->second];
        if (!same_pose(old, r)) {
            old = r;
            moved_ids.push_back(r.id);
        }
    }
    // Removing a ghost may move another body of the local world to a new
    // handle (local_destroy): the moved ones are looked up afterwards.
    for (size_t k = seen.size(); k-- > 0;)
        if (!seen[k]) remove_ghost_at(w, (uint32_t)k);
    std::vector<hgcd_body> moved(moved_ids.size());
    std::vector<Record> moved_rec(moved_ids.size());
    for (size_t k = 0; k < moved_ids.size(); ++k) {
        const uint32_t at = g.index.at(moved_ids[k]);
        moved[k] = g.local[at];
        moved_rec[k] = g.rec[at];
    }
    if (!moved.empty() &&
        hgcd_world_set_poses(w->local, moved.data(), moved.size(), moved_rec[0].position, sizeof(Record),
                             moved_rec[0].orientation, sizeof(Record)) != HGCD_OK)
        throw std::bad_alloc();  // checked when added: only memory can fail
    for (const Record &r : fresh) g.push(r, local_create(w, r, false));
}

void keep_reported_pairs(hgcd_mpi_world *w) {
    const hgcd_pair *p;
    size_t n;
    hgcd_world_pairs(w->local, &p, &n);
    w->pairs.clear();
    for (size_t k = 0; k < n; ++k) {
        const uint64_t a = w->id_of_local[p[k].a.index], b = w->id_of_local[p[k].b.index];
        const uint32_t lower = a < b ? p[k].a.index : p[k].b.index;
        if (w->owned_of_local[lower]) w->pairs.push_back(a < b ? hgcd_mpi_pair{a, b} : hgcd_mpi_pair{b, a});
    }
    w->stats.local_world_pairs = n;
    w->stats.reported_pairs = w->pairs.size();
}

}  // namespace

void migrate(hgcd_mpi_world *w, bool all) {
    const Box &d = w->decomp.domains[w->rank];
    std::vector<std::vector<char>> out(w->size);
    // Where each body goes (-1: stays), in parallel; then sent in order.
    const int64_t n = (int64_t)w->owned.rec.size();
    std::vector<int32_t> dest(n);
#pragma omp parallel for num_threads(w->threads) if (n > 4096) schedule(static)
    for (int64_t k = 0; k < n; ++k) {
        const double *p = w->owned.rec[k].position;
        int32_t to = -1;
        if (!inside(d, p) && (all || w->motion_allowance == 0 || distance(d, p) > w->motion_allowance)) {
            to = w->decomp.locate(p);
            if (to == w->rank) to = -1;
        }
        dest[k] = to;
    }
    std::vector<uint32_t> leaving;
    for (int64_t k = 0; k < n; ++k)
        if (dest[k] >= 0) {
            append(out[dest[k]], w->owned.rec[k]);
            leaving.push_back((uint32_t)k);
        }
    const std::vector<char> in = hgcd_mpi::exchange(w, out);
    for (size_t k = leaving.size(); k-- > 0;) remove_owned_at(w, leaving[k]);
    const size_t arrived = in.size() / sizeof(Record);
    for (size_t k = 0; k < arrived; ++k) add_owned(w, record_at(in, k));
    w->stats.migrated_out += leaving.size();
    w->stats.migrated_in += arrived;
}

}  // namespace hgcd_mpi

using namespace hgcd_mpi;

extern "C" hgcd_status hgcd_mpi_detect(hgcd_mpi_world *w) {
    if (!w) return HGCD_ERROR_NULL_ARGUMENT;
    if (w->broken) {
        w->error = "detect: the world is unusable";
        return HGCD_ERROR_OUT_OF_MEMORY;
    }
    w->stats = hgcd_mpi_stats{};
    hgcd_mpi_stats &st = w->stats;
    const double t0 = now();
    hgcd_status s = HGCD_OK;
    try {
        migrate(w, false);
        const double t1 = now();
        std::vector<Summary> all = summarise(w);
        if (unbalanced(w, all, &st.imbalance)) {
            std::vector<double> points(3 * w->owned.rec.size());
            for (size_t k = 0; k < w->owned.rec.size(); ++k)
                std::memcpy(&points[3 * k], w->owned.rec[k].position, 24);
            rcb(w, points);
            migrate(w, true);
            all = summarise(w);
            unbalanced(w, all, &st.imbalance);
            st.rebalanced = 1;
        }
        const double t2 = now();
        std::vector<char> in;
        send_ghosts(w, all, in);
        const double t3 = now();
        update_ghosts(w, in);
        const double t4 = now();
        s = hgcd_world_detect(w->local);
        const double t5 = now();
        if (s == HGCD_OK) keep_reported_pairs(w);
        else w->pairs.clear();
        const double t6 = now();
        st.migrate_seconds = t1 - t0;
        st.rebalance_seconds = t2 - t1;
        st.ghost_exchange_seconds = t3 - t2;
        st.ghost_update_seconds = t4 - t3;
        st.local_detect_seconds = t5 - t4;
        st.pairs_seconds = t6 - t5;
    } catch (...) {
        w->broken = true;
        w->pairs.clear();
        w->error = "detect: out of memory while moving bodies; the world is unusable";
        return HGCD_ERROR_OUT_OF_MEMORY;
    }
    if (s != HGCD_OK) w->error = std::string("detect: ") + hgcd_world_last_error(w->local);
    s = agree(w, s, "detect");
    if (s != HGCD_OK) w->pairs.clear();
    st.owned_bodies = w->owned.rec.size();
    st.ghost_bodies = w->ghosts.rec.size();
    st.total_seconds = now() - t0;
    st.poses_by_index = w->dense;
    st.struct_size = sizeof st;
    w->last_stats = st;
    return s;
}
