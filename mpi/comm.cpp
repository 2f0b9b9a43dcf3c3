// Messages between ranks: the agreement behind every collective refusal, the
// all-to-all exchange of migration and adds, and the neighbour exchange of
// ghosts. Payloads are raw bytes (MPI_BYTE), so doubles arrive bit for bit.
#include <climits>
#include <new>
#include <stdexcept>

#include "internal.hpp"

namespace hgcd_mpi {

double now() { return MPI_Wtime(); }

hgcd_status fail(hgcd_mpi_world *w, hgcd_status status, const std::string &msg) {
    w->error = msg;
    return status;
}

hgcd_status agree(hgcd_mpi_world *w, hgcd_status status, const std::string &what) {
    int key = status != HGCD_OK ? w->rank : w->size, first = w->size;
    MPI_Allreduce(&key, &first, 1, MPI_INT, MPI_MIN, w->comm);
    ++w->stats.collective_calls;
    if (first == w->size) return HGCD_OK;
    // The lowest failing rank's status and message, to every rank.
    int st = status;
    std::string msg = w->rank == first ? w->error : std::string();
    unsigned long len = msg.size();
    MPI_Bcast(&st, 1, MPI_INT, first, w->comm);
    MPI_Bcast(&len, 1, MPI_UNSIGNED_LONG, first, w->comm);
    msg.resize(len);
    if (len) MPI_Bcast(&msg[0], (int)len, MPI_CHAR, first, w->comm);
    w->stats.collective_calls += 3;
    if (msg.empty()) msg = what + ": refused";
    w->error = msg + " (on rank " + std::to_string(first) + ")";
    return st;
}

namespace {
int count_of(size_t n) {
    if (n > (size_t)INT_MAX) throw std::length_error("more than INT_MAX bytes for one rank");
    return (int)n;
}
}  // namespace

std::vector<char> exchange(hgcd_mpi_world *w, const std::vector<std::vector<char>> &out) {
    const int p = w->size;
    std::vector<int> scount(p), rcount(p), sdispl(p), rdispl(p);
    size_t stotal = 0;
    for (int r = 0; r < p; ++r) {
        scount[r] = count_of(out[r].size());
        sdispl[r] = count_of(stotal);
        stotal += out[r].size();
        if (r != w->rank && scount[r]) {
            w->stats.bytes_sent += scount[r];
            ++w->stats.messages_sent;
        }
    }
    MPI_Alltoall(scount.data(), 1, MPI_INT, rcount.data(), 1, MPI_INT, w->comm);
    size_t rtotal = 0;
    for (int r = 0; r < p; ++r) {
        rdispl[r] = count_of(rtotal);
        rtotal += rcount[r];
        if (r != w->rank && rcount[r]) {
            w->stats.bytes_received += rcount[r];
            ++w->stats.messages_received;
        }
    }
    count_of(stotal);
    count_of(rtotal);
    std::vector<char> send(stotal), recv(rtotal);
    for (int r = 0; r < p; ++r)
        if (!out[r].empty()) std::copy(out[r].begin(), out[r].end(), send.begin() + sdispl[r]);
    MPI_Alltoallv(send.data(), scount.data(), sdispl.data(), MPI_BYTE, recv.data(), rcount.data(),
                  rdispl.data(), MPI_BYTE, w->comm);
    w->stats.collective_calls += 2;
    return recv;
}

std::vector<char> exchange_neighbours(hgcd_mpi_world *w, const std::vector<int> &peers,
                                      const std::vector<std::vector<char>> &out) {
    // One message each way per neighbour, possibly empty; the receiver
    // learns its size by probing.
    const size_t n = peers.size();
    std::vector<MPI_Request> req(n);
    for (size_t k = 0; k < n; ++k) {
        MPI_Isend(out[k].data(), count_of(out[k].size()), MPI_BYTE, peers[k], 2, w->comm, &req[k]);
        ++w->stats.messages_sent;
        w->stats.bytes_sent += out[k].size();
    }
    std::vector<char> recv;
    for (size_t k = 0; k < n; ++k) {
        MPI_Status st;
        MPI_Probe(peers[k], 2, w->comm, &st);
        int bytes = 0;
        MPI_Get_count(&st, MPI_BYTE, &bytes);
        const size_t at = recv.size();
        recv.resize(at + (size_t)bytes);
        MPI_Recv(recv.data() + at, bytes, MPI_BYTE, peers[k], 2, w->comm, MPI_STATUS_IGNORE);
        ++w->stats.messages_received;
        w->stats.bytes_received += (size_t)bytes;
    }
    MPI_Waitall((int)n, req.data(), MPI_STATUSES_IGNORE);
    return recv;
}

}  // namespace hgcd_mpi
