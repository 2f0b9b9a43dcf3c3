// Oriented boxes fitted to the triangles under each tree node (principal axes
// of the node's vertices), in the mesh frame. A surface patch is thin along
// its normal, so two nearly parallel patches a little apart are told apart
// several levels above the leaves, where the mesh-frame boxes of a tilted
// patch still overlap (on scene `scanned`, half the node pairs).
//
// What is certified (NodeObb): every vertex p under the node is exactly
// center + sum_i b_i u_i with |b_i| <= half[i], u_i the rows of `axis` as
// stored. The axes come from a floating-point eigensolver and are only nearly
// orthonormal; with U the matrix of rows u_i and E = U U^T - I (exact), a
// bound eps >= ||E||_inf below 1e-12 is computed first (else the node takes
// the identity axes, for which E = 0). Then for a = U (p - c) (exact):
//     p - c = U^{-1} a = U^T (I + E)^{-1} a,
// and b = (I + E)^{-1} a differs from a by at most eps / (1 - eps) |a|_inf
// <= 2 eps max_j A_j in each component, where |a_i| <= A_i (below). So
// half[i] = A_i + 2 eps max_j A_j (times 1 + 1e-12, which covers the
// roundings of these few sums of non-negative terms) holds every b_i.
//
// A_i: computed a_i = fl(u_i . fl(p - c)) is within (u + g_3 (1 + u)) S_i
// <= 5e-16 S_i of the exact u_i . (p - c), with S_i = sum_k |u_ik| |fl(p_k -
// c_k)|; A_i = max over p of |a_i| + 1e-14 S_i + 1e-300 (the last for
// underflow; vertices are finite and below 1e15, so nothing overflows).
// eps: orthonormal_defect (bvh.hpp).
#include "common/ieee.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>

#include "common/parallel.hpp"
#include "narrow/bvh.hpp"

namespace hgcd {

namespace {

// Eigenvectors of the symmetric 3x3 matrix a (destroyed) by cyclic Jacobi
// rotations: the columns of v, orthonormal up to rounding.
void jacobi3(double a[3][3], double v[3][3]) {
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) v[i][j] = i == j;
    for (int sweep = 0; sweep < 32; ++sweep) {
        const double off = std::fabs(a[0][1]) + std::fabs(a[0][2]) + std::fabs(a[1][2]);
        const double diag = std::fabs(a[0][0]) + std::fabs(a[1][1]) + std::fabs(a[2][2]);
        if (!(off > 1e-18 * diag)) break;
        for (int p = 0; p < 2; ++p)
            for (int q = p + 1; q < 3; ++q) {
                if (a[p][q] == 0) continue;
                const double theta = (a[q][q] - a[p][p]) / (2 * a[p][q]);
                const double t = (theta >= 0 ? 1 : -1) / (std::fabs(theta) + std::sqrt(theta * theta + 1));
                const double c = 1 / std::sqrt(t * t + 1), s = t * c;
                for (int k = 0; k < 3; ++k) {
                    const double kp = a[k][p], kq = a[k][q];
                    a[k][p] = c * kp - s * kq;
                    a[k][q] = s * kp + c * kq;
                }
                for (int k = 0; k < 3; ++k) {
                    const double pk = a[p][k], qk = a[q][k];
                    a[p][k] = c * pk - s * qk;
                    a[q][k] = s * pk + c * qk;
                }
                for (int k = 0; k < 3; ++k) {
                    const double kp = v[k][p], kq = v[k][q];
                    v[k][p] = c * kp - s * kq;
                    v[k][q] = s * kp + c * kq;
                }
            }
    }
}

void fit_node(const double *vertices, const uint32_t *corners, size_t corner_count, NodeObb &o) {
    auto point = [&](size_t i) { return vertices + 3 * size_t(corners[i]); };
    double mean[3] = {0, 0, 0};
    for (size_t i = 0; i < corner_count; ++i)
        for (int k = 0; k < 3; ++k) mean[k] += point(i)[k];
    for (int k = 0; k < 3; ++k) mean[k] /= double(corner_count);
    double cov[3][3] = {};
    for (size_t i = 0; i < corner_count; ++i) {
        const double *p = point(i);
        for (int a = 0; a < 3; ++a)
            for (int b = 0; b < 3; ++b) cov[a][b] += (p[a] - mean[a]) * (p[b] - mean[b]);
    }
    double v[3][3];
    jacobi3(cov, v);
    double *u = o.axis;
    for (int i = 0; i < 3; ++i)
        for (int k = 0; k < 3; ++k) u[3 * i + k] = v[k][i];
    double eps = orthonormal_defect(u);
    if (!(eps <= 1e-12)) {
        for (int i = 0; i < 9; ++i) u[i] = i % 4 == 0;
        eps = 0;
    }
    // The centre: the middle of the (approximate) projections on each axis.
    double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
    for (size_t i = 0; i < corner_count; ++i) {
        const double *p = point(i);
        for (int a = 0; a < 3; ++a) {
            const double t = (u[3 * a] * p[0] + u[3 * a + 1] * p[1]) + u[3 * a + 2] * p[2];
            lo[a] = std::min(lo[a], t);
            hi[a] = std::max(hi[a], t);
        }
    }
    for (int k = 0; k < 3; ++k) {
        const double m0 = 0.5 * lo[0] + 0.5 * hi[0], m1 = 0.5 * lo[1] + 0.5 * hi[1], m2 = 0.5 * lo[2] + 0.5 * hi[2];
        o.center[k] = (m0 * u[k] + m1 * u[3 + k]) + m2 * u[6 + k];
    }
    // The certified half widths about that centre.
    double A[3] = {0, 0, 0};
    for (size_t i = 0; i < corner_count; ++i) {
        const double *p = point(i);
        const double d[3] = {p[0] - o.center[0], p[1] - o.center[1], p[2] - o.center[2]};
        for (int a = 0; a < 3; ++a) {
            const double *x = u + 3 * a;
            const double t = (x[0] * d[0] + x[1] * d[1]) + x[2] * d[2];
            const double s = (std::fabs(x[0]) * std::fabs(d[0]) + std::fabs(x[1]) * std::fabs(d[1])) +
                             std::fabs(x[2]) * std::fabs(d[2]);
            A[a] = std::max(A[a], std::fabs(t) + 1e-14 * s + 1e-300);
        }
    }
    const double top = std::max(std::max(A[0], A[1]), A[2]);
    for (int a = 0; a < 3; ++a) o.half[a] = (A[a] + 2 * eps * top) * (1 + 1e-12);
}

}  // namespace

void node_lanes(const BvhNode &n, const NodeObb &o, uint32_t first, uint32_t count, uint32_t k, double *block) {
    double field[23];
    const uint64_t link = node_link(n), span = uint64_t(first) | uint64_t(first + count) << 32;
    std::memcpy(&field[kLinkField], &link, sizeof link);
    std::memcpy(&field[kSpanField], &span, sizeof span);
    for (int i = 0; i < 3; ++i) {
        field[i] = n.center[i];
        field[3 + i] = n.half[i];
        field[6 + i] = o.center[i];
        field[18 + i] = o.half[i];
    }
    for (int i = 0; i < 9; ++i) field[9 + i] = o.axis[i];
    for (int f = 0; f < 23; ++f) {
        if (k == 0) block[2 * f] = field[f];
        block[2 * f + lane_of(k)] = field[f];
    }
}

void fit_node_obbs(const double *vertices, Bvh &bvh, int threads) {
    const size_t nn = bvh.nodes.size();
    std::vector<NodeObb> obb(nn);
    // Triangle ranges: children follow their parents and split the parent's
    // range, so one backward sweep gives every internal node's range.
    std::vector<uint32_t> first(nn), count(nn);
    for (size_t k = nn; k-- > 0;) {
        const BvhNode &n = bvh.nodes[k];
        if (n.count) {
            first[k] = n.first;
            count[k] = n.count;
        } else {
            first[k] = first[n.first];
            count[k] = count[n.first] + count[n.first + 1];
        }
    }
    // (Each node's fit reads its corners alone: the top ones cost most.)
    parallel_for(nn >= 256 ? threads : 1, int64_t(nn), 16, Schedule::Dynamic, [&](int64_t b, int64_t e, int) {
        for (int64_t k = b; k < e; ++k)
            fit_node(vertices, &bvh.tris[3 * size_t(first[k])], 3 * size_t(count[k]), obb[size_t(k)]);
    });
    // The blocks of sibling pairs (kLaneBlock), the root in both lanes of
    // block 0.
    bvh.lanes.assign(kLaneBlock * (nn / 2 + 1), 0.0);
    for (size_t k = 0; k < nn; ++k) {
        const BvhNode &n = bvh.nodes[k];
        node_lanes(n, obb[k], first[k], count[k], uint32_t(k), &bvh.lanes[kLaneBlock * lane_block(uint32_t(k))]);
    }
}

}  // namespace hgcd
