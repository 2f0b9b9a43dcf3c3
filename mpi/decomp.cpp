// Recursive coordinate bisection of the body counts, and the boxes the halo
// is made of.
#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>

#include "internal.hpp"

namespace hgcd_mpi {

namespace {
constexpr double kInf = std::numeric_limits<double>::infinity();

// A key whose unsigned order is the order of finite doubles, with -0 and +0
// equal (both map to +0's key), so x < c exactly when key(x) < key(c).
uint64_t key_of(double x) {
    if (x == 0) x = 0.0;
    uint64_t u;
    std::memcpy(&u, &x, 8);
    return (u >> 63) ? ~u : u | (1ull << 63);
}
double double_of(uint64_t k) {
    uint64_t u = (k >> 63) ? k & ~(1ull << 63) : ~k;
    double x;
    std::memcpy(&x, &u, 8);
    return x;
}
}  // namespace

Box Box::empty() { return Box{{kInf, kInf, kInf}, {-kInf, -kInf, -kInf}}; }

bool Box::meets(const Box &o) const {
    for (int a = 0; a < 3; ++a)
        if (lo[a] > o.hi[a] || o.lo[a] > hi[a]) return false;
    return true;
}

void Box::grow(const Box &o) {
    for (int a = 0; a < 3; ++a) {
        lo[a] = std::min(lo[a], o.lo[a]);
        hi[a] = std::max(hi[a], o.hi[a]);
    }
}

// The solid lies within scale * reach of the position (hgcd.h's vertex
// formula): the rotation of a quaternion of squared norm n is n R' + (1 - n) I
// for a rotation R', of norm at most 1 + 2e-6 for every n hgcd accepts; the
// relative 1e-5 covers that and the rounding of the transform, the 1e-15
// relative to the coordinates the rounding of position + offset and of this
// box's own bounds in any rounding mode, the 1e-300 flushed subnormals.
Box body_box(const hgcd_mpi_world *w, const Record &r) {
    const double reach = w->meshes[r.mesh].reach * r.scale;
    double m = 0;
    for (int a = 0; a < 3; ++a) m = std::max(m, std::fabs(r.position[a]));
    const double h = reach * (1 + 1e-5) + 1e-15 * (m + reach) + 1e-300;
    Box b;
    for (int a = 0; a < 3; ++a) {
        b.lo[a] = r.position[a] - h;
        b.hi[a] = r.position[a] + h;
    }
    return b;
}

void Decomposition::single(int ranks) {
    nodes.assign(1, Node{0, 0, -1, -1, 0});
    compute_domains(ranks);
}

int Decomposition::locate(const double *p) const {
    const Node *n = &nodes[0];
    while (n->rank < 0) n = &nodes[p[n->axis] < n->cut ? n->left : n->right];
    return n->rank;
}

void Decomposition::compute_domains(int ranks) {
    // Ranks that own no leaf (only before the first cut) get an empty box.
    domains.assign(ranks, Box::empty());
    struct Item { int node; Box box; };
    std::vector<Item> stack{{0, Box{{-kInf, -kInf, -kInf}, {kInf, kInf, kInf}}}};
    while (!stack.empty()) {
        Item it = stack.back();
        stack.pop_back();
        const Node &n = nodes[it.node];
        if (n.rank >= 0) {
            domains[n.rank] = it.box;
            continue;
        }
        Item l = {n.left, it.box}, r = {n.right, it.box};
        l.box.hi[n.axis] = n.cut;
        r.box.lo[n.axis] = n.cut;
        stack.push_back(l);
        stack.push_back(r);
    }
}

// Every rank runs the same loop on the same reduced numbers, so every rank
// builds the same tree. Level by level, each group of ranks [r0, r1) with
// more than one rank cuts its bodies along the longest side of their
// bounding box so that the lower side holds floor(n * m / (r1 - r0)) of its
// n bodies, m = floor((r1 - r0) / 2) its ranks: the smallest key K with
// count(key < K) >= that target, found by bisection over the keys (at most
// 64 allreduces per level, all groups of a level together).
void rcb(hgcd_mpi_world *w, const std::vector<double> &points) {
    struct Group { int node, r0, r1; };
    Decomposition d;
    d.nodes.assign(1, Node{0, -1, -1, -1, 0});
    std::vector<Group> groups{{0, 0, w->size}};
    const size_t np = points.size() / 3;
    std::vector<int> member(np, 0);  // index into groups
    while (true) {
        std::vector<int> active;
        for (size_t g = 0; g < groups.size(); ++g)
            if (groups[g].r1 - groups[g].r0 == 1)
                d.nodes[groups[g].node].rank = groups[g].r0;
            else
                active.push_back((int)g);
        if (active.empty()) break;
        const size_t G = groups.size();
        // Bounding boxes (min of lo and of -hi) and counts per group.
        std::vector<double> ext(6 * G, kInf), gext(6 * G);
        std::vector<long long> cnt(G, 0), gcnt(G);
        for (size_t i = 0; i < np; ++i) {
            const int g = member[i];
            if (g < 0) continue;
            ++cnt[g];
            for (int a = 0; a < 3; ++a) {
                ext[6 * g + a] = std::min(ext[6 * g + a], points[3 * i + a]);
                ext[6 * g + 3 + a] = std::min(ext[6 * g + 3 + a], -points[3 * i + a]);
            }
        }
        MPI_Allreduce(ext.data(), gext.data(), (int)(6 * G), MPI_DOUBLE, MPI_MIN, w->comm);
        MPI_Allreduce(cnt.data(), gcnt.data(), (int)G, MPI_LONG_LONG, MPI_SUM, w->comm);
        w->stats.collective_calls += 2;
        std::vector<int> axis(G, 0);
        std::vector<uint64_t> lo(G), hi(G);
        std::vector<long long> target(G, 0);
        for (int g : active) {
            const Group &gr = groups[g];
            const int m = (gr.r1 - gr.r0) / 2;
            target[g] = (long long)((double)gcnt[g] * m / (gr.r1 - gr.r0));
            if (gcnt[g] == 0) continue;  // cut at 0 on x: any cut will do
            double best = -1;
            for (int a = 0; a < 3; ++a) {
                const double e = -gext[6 * g + 3 + a] - gext[6 * g + a];
                if (e > best) best = e, axis[g] = a;
            }
            lo[g] = key_of(gext[6 * g + axis[g]]);        // count(< lo) = 0
            hi[g] = key_of(-gext[6 * g + 3 + axis[g]]) + 1;  // count(< hi) = n
        }
        // Bisection: keep count(< lo) < target <= count(< hi).
        std::vector<uint64_t> cut(G, key_of(0.0));
        for (int g : active)
            if (gcnt[g] > 0) cut[g] = target[g] == 0 ? lo[g] : hi[g];
        while (true) {
            bool any = false;
            std::vector<uint64_t> mid(G, 0);
            for (int g : active)
                if (gcnt[g] > 0 && target[g] > 0 && hi[g] - lo[g] > 1) {
                    mid[g] = lo[g] + (hi[g] - lo[g]) / 2;
                    any = true;
                }
            if (!any) break;
            std::vector<long long> below(G, 0), gbelow(G);
            for (size_t i = 0; i < np; ++i) {
                const int g = member[i];
                if (g >= 0 && mid[g] && key_of(points[3 * i + axis[g]]) < mid[g]) ++below[g];
            }
            MPI_Allreduce(below.data(), gbelow.data(), (int)G, MPI_LONG_LONG, MPI_SUM, w->comm);
            ++w->stats.collective_calls;
            for (int g : active) {
                if (!mid[g]) continue;
                if (gbelow[g] >= target[g]) hi[g] = mid[g]; else lo[g] = mid[g];
                cut[g] = hi[g];
            }
        }
        // Split the active groups into their two children.
        std::vector<Group> next;
        std::vector<int> child_lo(G, -1), child_hi(G, -1);
        for (size_t g = 0; g < G; ++g) {
            const Group gr = groups[g];
            if (gr.r1 - gr.r0 == 1) continue;
            const int m = (gr.r1 - gr.r0) / 2;
            const int l = (int)d.nodes.size();
            d.nodes.push_back(Node{0, -1, -1, -1, 0});
            d.nodes.push_back(Node{0, -1, -1, -1, 0});
            Node &n = d.nodes[gr.node];
            n.axis = axis[g];
            n.cut = double_of(cut[g]);
            n.left = l;
            n.right = l + 1;
            child_lo[g] = (int)next.size();
            next.push_back(Group{l, gr.r0, gr.r0 + m});
            child_hi[g] = (int)next.size();
            next.push_back(Group{l + 1, gr.r0 + m, gr.r1});
        }
        for (size_t i = 0; i < np; ++i) {
            const int g = member[i];
            if (g < 0 || child_lo[g] < 0) { member[i] = -1; continue; }
            const Node &n = d.nodes[groups[g].node];
            member[i] = points[3 * i + n.axis] < n.cut ? child_lo[g] : child_hi[g];
        }
        groups.swap(next);
    }
    d.compute_domains(w->size);
    w->decomp.nodes.swap(d.nodes);
    w->decomp.domains.swap(d.domains);
}

}  // namespace hgcd_mpi
