#include "narrow/bvh.hpp"

#include <algorithm>
#include <cmath>
#include <numeric>

#include "common/ieee.hpp"
#include "common/parallel.hpp"
#include "exact/geometry.hpp"

namespace hgcd {

namespace {

constexpr int kBins = 16;
// Past this depth, splits are at the object median, which halves the count:
// the depth stays below kSahDepth + 27 (at most 2^26 triangles).
constexpr uint32_t kSahDepth = 48;
// Trees of this many triangles or more are built in 2^kDeferLevel subtrees
// at once (after the levels above them).
constexpr uint32_t kDeferTriangles = 2048, kDeferLevel = 4;

struct Builder {
    const double *v;
    const uint32_t *t;
    std::vector<double> lo, hi, cen;  // per triangle: exact box, centroid
    std::vector<uint32_t> order;      // triangle ids, partitioned in place
    std::vector<BvhNode> nodes;
    uint32_t depth = 0;

    static double area(const double *l, const double *h) {
        const double x = h[0] - l[0], y = h[1] - l[1], z = h[2] - l[2];
        return x * y + y * z + z * x;
    }

    void set_box(BvhNode &n, uint32_t begin, uint32_t end) const {
        double l[3] = {INFINITY, INFINITY, INFINITY}, h[3] = {-INFINITY, -INFINITY, -INFINITY};
        for (uint32_t i = begin; i < end; ++i) {
            const uint32_t tr = order[i];
            for (int k = 0; k < 3; ++k) {
                l[k] = std::min(l[k], lo[3 * size_t(tr) + k]);
                h[k] = std::max(h[k], hi[3 * size_t(tr) + k]);
            }
        }
        set_node_box(n, l, h);
    }

    // The bin of triangle tr's centroid on `axis`: scale = kBins (1 - 1e-9)
    // / extent of the centroids from cen_lo.
    int bin_of(uint32_t tr, int axis, double cen_lo, double scale) const {
        const int b = int((cen[3 * size_t(tr) + axis] - cen_lo) * scale);
        return std::min(std::max(b, 0), kBins - 1);
    }

    // Binned SAH on one axis (centroids from cen_lo over extent > 0): lowers
    // best_cost to the cost of this axis's cheapest cut, if cheaper, and sets
    // best_axis and best_bin (the last bin of the left part).
    void try_axis(uint32_t begin, uint32_t end, int axis, double cen_lo, double extent, double &best_cost,
                  int &best_axis, int &best_bin) const {
        const double scale = kBins * (1 - 1e-9) / extent;
        uint32_t bin_count[kBins] = {};
        double bin_lo[kBins][3], bin_hi[kBins][3];
        for (int b = 0; b < kBins; ++b)
            for (int k = 0; k < 3; ++k) bin_lo[b][k] = INFINITY, bin_hi[b][k] = -INFINITY;
        for (uint32_t i = begin; i < end; ++i) {
            const uint32_t tr = order[i];
            const int b = bin_of(tr, axis, cen_lo, scale);
            ++bin_count[b];
            for (int k = 0; k < 3; ++k) {
                bin_lo[b][k] = std::min(bin_lo[b][k], lo[3 * size_t(tr) + k]);
                bin_hi[b][k] = std::max(bin_hi[b][k], hi[3 * size_t(tr) + k]);
            }
        }
        // Right-to-left sweep of areas and counts, then left to right.
        double right_area[kBins];
        uint32_t right_count[kBins];
        double right_lo[3] = {INFINITY, INFINITY, INFINITY}, right_hi[3] = {-INFINITY, -INFINITY, -INFINITY};
        uint32_t right_total = 0;
        for (int b = kBins - 1; b > 0; --b) {
            for (int k = 0; k < 3; ++k)
                right_lo[k] = std::min(right_lo[k], bin_lo[b][k]), right_hi[k] = std::max(right_hi[k], bin_hi[b][k]);
            right_total += bin_count[b];
            right_area[b] = right_total ? area(right_lo, right_hi) : 0;
            right_count[b] = right_total;
        }
        double left_lo[3] = {INFINITY, INFINITY, INFINITY}, left_hi[3] = {-INFINITY, -INFINITY, -INFINITY};
        uint32_t left_total = 0;
        for (int b = 0; b + 1 < kBins; ++b) {
            for (int k = 0; k < 3; ++k)
                left_lo[k] = std::min(left_lo[k], bin_lo[b][k]), left_hi[k] = std::max(left_hi[k], bin_hi[b][k]);
            left_total += bin_count[b];
            if (left_total == 0 || right_count[b + 1] == 0) continue;
            const double cost = left_total * area(left_lo, left_hi) + right_count[b + 1] * right_area[b + 1];
            if (cost < best_cost) {
                best_cost = cost;
                best_axis = axis;
                best_bin = b;
            }
        }
    }

    // Splits order[begin, end) and returns the first index of the right part
    // (strictly between begin and end).
    uint32_t split(uint32_t begin, uint32_t end, uint32_t level) {
        const uint32_t count = end - begin;
        double cen_lo[3] = {INFINITY, INFINITY, INFINITY}, cen_hi[3] = {-INFINITY, -INFINITY, -INFINITY};
        for (uint32_t i = begin; i < end; ++i)
            for (int k = 0; k < 3; ++k) {
                cen_lo[k] = std::min(cen_lo[k], cen[3 * size_t(order[i]) + k]);
                cen_hi[k] = std::max(cen_hi[k], cen[3 * size_t(order[i]) + k]);
            }
        int wide = 0;
        for (int k = 1; k < 3; ++k)
            if (cen_hi[k] - cen_lo[k] > cen_hi[wide] - cen_lo[wide]) wide = k;
        const uint32_t mid = begin + count / 2;
        auto median = [&](int axis) {
            std::nth_element(order.begin() + begin, order.begin() + mid, order.begin() + end,
                             [&](uint32_t a, uint32_t b) {
                                 const double x = cen[3 * size_t(a) + axis], y = cen[3 * size_t(b) + axis];
                                 return x < y || (x == y && a < b);
                             });
            return mid;
        };
        if (!(cen_hi[wide] > cen_lo[wide]) || level >= kSahDepth) return median(wide);

        // Binned SAH over the three axes.
        double best_cost = INFINITY;
        int best_axis = -1, best_bin = 0;
        for (int axis = 0; axis < 3; ++axis) {
            const double extent = cen_hi[axis] - cen_lo[axis];
            if (extent > 0) try_axis(begin, end, axis, cen_lo[axis], extent, best_cost, best_axis, best_bin);
        }
        if (best_axis < 0) return median(wide);
        const double scale = kBins * (1 - 1e-9) / (cen_hi[best_axis] - cen_lo[best_axis]);
        auto it = std::partition(order.begin() + begin, order.begin() + end, [&](uint32_t tr) {
            return bin_of(tr, best_axis, cen_lo[best_axis], scale) <= best_bin;
        });
        const uint32_t cut = uint32_t(it - order.begin());
        if (cut == begin || cut == end) return median(wide);
        return cut;
    }

    // A subtree left for later: its root's index, triangles, level.
    struct Job {
        uint32_t node, begin, end, level;
    };

    // Builds the subtree of out[node] over order[begin, end) into out (its
    // nodes appended, children in adjacent pairs after their parent); with
    // `defer`, a node at kDeferLevel is left unbuilt and listed there instead.
    void build(std::vector<BvhNode> &out, uint32_t node, uint32_t begin, uint32_t end, uint32_t level,
               uint32_t &deepest, std::vector<Job> *defer) {
        deepest = std::max(deepest, level + 1);
        if (defer && level == kDeferLevel) {
            defer->push_back({node, begin, end, level});
            return;
        }
        set_box(out[node], begin, end);
        if (end - begin <= kBvhLeafSize) {
            out[node].first = begin;
            out[node].count = end - begin;
            return;
        }
        const uint32_t cut = split(begin, end, level);
        const uint32_t left = uint32_t(out.size());
        out.emplace_back();
        out.emplace_back();
        out[node].first = left;
        out[node].count = 0;
        build(out, left, begin, cut, level + 1, deepest, defer);
        build(out, left + 1, cut, end, level + 1, deepest, defer);
    }

    // The whole tree: the levels above kDeferLevel on the calling thread,
    // the subtrees below on `threads` (each into its own array, spliced in
    // the order listed). The layout depends on the triangle count alone,
    // not on the threads; trees of few triangles are built in one piece.
    void build_all(int threads) {
        const uint32_t n = uint32_t(order.size());
        nodes.emplace_back();
        std::vector<Job> jobs;
        build(nodes, 0, 0, n, 0, depth, n >= kDeferTriangles ? &jobs : nullptr);
        if (jobs.empty()) return;
        std::vector<std::vector<BvhNode>> sub(jobs.size());
        std::vector<uint32_t> sub_depth(jobs.size(), 0);
        parallel_for(threads, int64_t(jobs.size()), 1, Schedule::Dynamic, [&](int64_t b, int64_t e, int) {
            for (int64_t j = b; j < e; ++j) {
                const Job &job = jobs[size_t(j)];
                sub[size_t(j)].reserve(2 * ((job.end - job.begin) / kBvhLeafSize + 1));
                sub[size_t(j)].emplace_back();
                build(sub[size_t(j)], 0, job.begin, job.end, job.level, sub_depth[size_t(j)], nullptr);
            }
        });
        // Splice: a subtree's node i >= 1 goes to base + i - 1 (base is odd,
        // as is every left child's index, so sibling pairs keep their lanes).
        for (size_t j = 0; j < jobs.size(); ++j) {
            const uint32_t base = uint32_t(nodes.size());
            for (BvhNode &x : sub[j])
                if (x.count == 0) x.first += base - 1;
            nodes[jobs[j].node] = sub[j][0];
            nodes.insert(nodes.end(), sub[j].begin() + 1, sub[j].end());
            depth = std::max(depth, sub_depth[j]);
            std::vector<BvhNode>().swap(sub[j]);
        }
    }
};

}  // namespace

void build_bvh(const double *vertices, const uint32_t *triangles, uint32_t triangle_count, Bvh *out,
               int threads) {
    Builder b;
    b.v = vertices;
    b.t = triangles;
    const size_t n = triangle_count;
    b.lo.resize(3 * n);
    b.hi.resize(3 * n);
    b.cen.resize(3 * n);
    for (size_t i = 0; i < n; ++i) {
        const double *p[3] = {&vertices[3 * size_t(triangles[3 * i])],
                              &vertices[3 * size_t(triangles[3 * i + 1])],
                              &vertices[3 * size_t(triangles[3 * i + 2])]};
        for (int k = 0; k < 3; ++k) {
            b.lo[3 * i + k] = std::min(std::min(p[0][k], p[1][k]), p[2][k]);
            b.hi[3 * i + k] = std::max(std::max(p[0][k], p[1][k]), p[2][k]);
            b.cen[3 * i + k] = 0.5 * b.lo[3 * i + k] + 0.5 * b.hi[3 * i + k];
        }
    }
    b.order.resize(n);
    std::iota(b.order.begin(), b.order.end(), 0u);
    b.nodes.reserve(2 * (n / kBvhLeafSize + 1));
    b.build_all(threads);
    Bvh bvh;
    bvh.nodes = std::move(b.nodes);
    bvh.depth = b.depth;
    bvh.parent.assign(bvh.nodes.size(), 0);
    for (size_t k = 0; k < bvh.nodes.size(); ++k)
        if (bvh.nodes[k].count == 0) bvh.parent[bvh.nodes[k].first] = bvh.parent[bvh.nodes[k].first + 1] = uint32_t(k);
    bvh.tris.resize(3 * n);
    bvh.tri_ids = b.order;
    for (size_t i = 0; i < n; ++i)
        for (int k = 0; k < 3; ++k) bvh.tris[3 * i + k] = triangles[3 * size_t(b.order[i]) + k];
    fit_node_obbs(vertices, bvh, threads);
    *out = std::move(bvh);
}

// Does the closed segment [p, q] certainly miss the box b? Tests the
// segment's box, then the three axes d x e_k (d = q - p as rounded; any axis
// proves separation when both endpoints project beyond the box's range). The
// projections are taken about a rounded box centre C with a half width H
// that is only nearly exact; every rounding in a projection is below
// 4u times the sum of the absolute terms involved, so the margin of 1e-12
// times that sum (plus 1e-300 for underflow) makes a rejection certain.
bool segment_misses_box(const double *p, const double *q, const double *smin, const double *smax,
                        const double *d, const double *b) {
    if (smax[0] < b[0] || smin[0] > b[3] || smax[1] < b[1] || smin[1] > b[4] ||
        smax[2] < b[2] || smin[2] > b[5])
        return true;
    double P[3], Q[3], H[3];
    for (int k = 0; k < 3; ++k) {
        const double c = 0.5 * b[k] + 0.5 * b[3 + k];
        H[k] = std::max(b[3 + k] - c, c - b[k]);
        P[k] = p[k] - c;
        Q[k] = q[k] - c;
    }
    // Axis d x e_k has components (i, j) = (k+1, k+2) mod 3:
    // e_0: (0, d_z, -d_y), e_1: (-d_z, 0, d_x), e_2: (d_y, -d_x, 0).
    for (int k = 0; k < 3; ++k) {
        const int i = (k + 1) % 3, j = (k + 2) % 3;
        const double ai = d[j], aj = -d[i];
        const double sp = ai * P[i] + aj * P[j];
        const double sq = ai * Q[i] + aj * Q[j];
        const double bi = std::fabs(ai), bj = std::fabs(aj);
        const double r = bi * H[i] + bj * H[j];
        const double m = 1e-12 * (bi * (std::fabs(P[i]) + std::fabs(Q[i]) + H[i]) +
                                  bj * (std::fabs(P[j]) + std::fabs(Q[j]) + H[j])) +
                         1e-300;
        const double lim = r + m;
        if ((sp > lim && sq > lim) || (sp < -lim && sq < -lim)) return true;
    }
    return false;
}

namespace {

// Deterministic small offsets in [-1/8, 1/8) for the ray directions.
double offset(uint32_t i) {
    uint64_t z = 0x9E3779B97F4A7C15ull * (uint64_t(i) + 1);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    z ^= z >> 31;
    return (double(z >> 11) * 0x1p-53 - 0.5) * 0.25;
}

constexpr int kRayAttempts = 32;

// How the closed segment pq (box smin, smax) meets the triangle v.
enum class Crossing {
    Miss,
    Through,     // through the triangle's interior: flips the parity
    Degenerate,  // through an edge or a vertex, or in the plane: try another ray
};

inline Crossing segment_crossing(const double *p, const double *q, const double *smin, const double *smax,
                                 const double *const *v) {
    for (int k = 0; k < 3; ++k) {
        const double lo = std::min(std::min(v[0][k], v[1][k]), v[2][k]);
        const double hi = std::max(std::max(v[0][k], v[1][k]), v[2][k]);
        if (hi < smin[k] || lo > smax[k]) return Crossing::Miss;
    }
    const int sp = orient3d(v[0], v[1], v[2], p);
    const int sq = orient3d(v[0], v[1], v[2], q);
    if (sp != 0 && sp == sq) return Crossing::Miss;
    if (sp == 0 && sq == 0) {  // in the plane, or a zero-area triangle
        if (collinear3d(v[0], v[1], v[2])) return Crossing::Miss;
        return segment_triangle_intersect(p, q, v[0], v[1], v[2]) ? Crossing::Degenerate : Crossing::Miss;
    }
    if (sp == 0 || sq == 0) {  // an endpoint on the plane
        if (collinear3d(v[0], v[1], v[2])) return Crossing::Miss;
        const double *x = sp == 0 ? p : q;
        return segment_triangle_intersect(x, x, v[0], v[1], v[2]) ? Crossing::Degenerate : Crossing::Miss;
    }
    const int s0 = orient3d(p, q, v[0], v[1]);
    const int s1 = orient3d(p, q, v[1], v[2]);
    const int s2 = orient3d(p, q, v[2], v[0]);
    if (s0 == s1 && s1 == s2 && s0 != 0) return Crossing::Through;
    if (!((s0 > 0 || s1 > 0 || s2 > 0) && (s0 < 0 || s1 < 0 || s2 < 0))) return Crossing::Degenerate;
    return Crossing::Miss;
}

}  // namespace

bool point_in_closed_mesh_bvh(const double *p, BodyView &o, std::vector<uint32_t> &stack) {
    double rb[6];
    std::copy(o.box(0), o.box(0) + 6, rb);
    for (int k = 0; k < 3; ++k)
        if (!(p[k] >= rb[k] && p[k] <= rb[3 + k])) return false;
    double ext = 0;
    for (int k = 0; k < 3; ++k) ext = std::max(ext, rb[3 + k] - rb[k]);
    // Faces of the root box by distance from p: short rays cross few nodes.
    struct Face {
        double dist;
        int axis, sign;
    } face[6];
    for (int k = 0; k < 3; ++k) {
        face[2 * k] = {p[k] - rb[k], k, -1};
        face[2 * k + 1] = {rb[3 + k] - p[k], k, +1};
    }
    std::stable_sort(face, face + 6, [](const Face &x, const Face &y) { return x.dist < y.dist; });

    bool parity = false;
    for (int attempt = 0; attempt < kRayAttempts; ++attempt) {
        const bool last = attempt + 1 == kRayAttempts;
        const Face &f = face[(attempt / 4) % 6];
        double dir[3];
        dir[f.axis] = f.sign;
        dir[(f.axis + 1) % 3] = offset(2 * uint32_t(attempt));
        dir[(f.axis + 2) % 3] = offset(2 * uint32_t(attempt) + 1);
        double len = 1.125 * f.dist + 0.0625 * ext;
        if (!(len > 0)) len = 1;
        double q[3];
        for (;;) {
            for (int k = 0; k < 3; ++k) q[k] = p[k] + len * dir[k];
            bool outside = false;
            for (int k = 0; k < 3; ++k) outside |= q[k] < rb[k] || q[k] > rb[3 + k];
            if (outside) break;
            len *= 2;
        }
        double smin[3], smax[3], d[3];
        for (int k = 0; k < 3; ++k) {
            smin[k] = std::min(p[k], q[k]);
            smax[k] = std::max(p[k], q[k]);
            d[k] = q[k] - p[k];
        }
        parity = false;
        bool degenerate = false;
        stack.clear();
        stack.push_back(0);
        while (!stack.empty() && !(degenerate && !last)) {
            const uint32_t n = stack.back();
            stack.pop_back();
            if (segment_misses_box(p, q, smin, smax, d, o.box(n))) continue;
            const BvhNode &node = o.nodes[n];
            if (node.count == 0) {
                stack.push_back(node.first + 1);
                stack.push_back(node.first);
                continue;
            }
            // The exact crossing tests of point_in_closed_mesh, triangle by
            // triangle. A triangle that misses the closed segment adds nothing
            // there (no crossing, no degeneracy), so skipping such triangles,
            // as the tree does, leaves the answer unchanged.
            for (uint32_t i = node.first; i < node.first + node.count; ++i) {
                const uint32_t *t = &o.tris[3 * size_t(i)];
                const double *v[3] = {o.vertex(t[0]), o.vertex(t[1]), o.vertex(t[2])};
                const Crossing c = segment_crossing(p, q, smin, smax, v);
                parity ^= c == Crossing::Through;
                degenerate |= c == Crossing::Degenerate;
            }
        }
        if (!degenerate) return parity;
    }
    return parity;
}

}  // namespace hgcd
