// The tree path's node tests in the frame of one body's mesh: a pair of
// meshes with trees is traversed in a's mesh frame, where a's node boxes (the
// mesh-frame box and the fitted box, built with the tree) are used as they
// are, and each of b's nodes is mapped there once per pair (its image: the
// fitted box's centre and axes through the pair's relative transform). So a
// node pair costs one image at most, not two world images.
//
// Exactness. The answer is defined on the rounded world vertices w~ =
// fl(T(p)) of both bodies (hgcd.h), T(p) = pos + R (s p) with R the rounded
// rotation matrix taken exactly. Let Phi(w) = R_a^T (w - pos_a) / s_a, with
// R_a^T the exact transpose: an invertible affine map (R_a is within 1e-5 of
// a rotation, the quaternion being unit to within 1e-6), so two sets of
// triangles are disjoint when their images under Phi are. Every test below
// shows that Phi of the rounded world vertices under a's node and those
// under b's node lie in two convex sets strictly apart; the triangles they
// span lie in those sets too, so they are disjoint.
//
// Norms: |x| is the max norm, u = 2^-53, g_k = k u / (1 - k u). The
// rotation matrix of a quaternion q with |q|^2 = n (validated: |n - 1| <=
// 1e-6) is n R_u + (1 - n) I, R_u a rotation (rotation_entries), so with
// the entries' roundings ||R||_2 <= 1 + 2.1e-6: rows and columns have 2-norm
// below that and 1-norm <= 1.74; L_a = max_k (|c_k| + h_k) of a's root box bounds |p|
// for every vertex p of a (the root's mesh-frame box holds them all; a
// mesh without a tree: its point node, Mesh::point_node), P_a =
// |pos_a|; likewise for b; sigma = s_b / s_a.
//
// a's vertices. w~ = T_a(p) + e, |e| <= g_5 (P_a + 1.74 s_a L_a) (the five
// roundings of transform_point, as at BodyView::node_box; underflow at
// prepare_frame). Phi(w~) = R_a^T
// R_a p + R_a^T e / s_a = p + D p + R_a^T e / s_a with D = R_a^T R_a - I,
// ||D||_inf <= rho_a (BodyView::defect, else orthonormal_defect of R_a's
// columns), so |Phi(w~) - p|
// <= rho_a L_a + 1.74 g_5 (P_a / s_a + 1.74 L_a) <= mu_a (RelFrame::mu_a,
// twice that with the roundings of its own evaluation).
//
// b's vertices. Phi(w~) = t + Q q + R_a^T e / s_a, t = R_a^T (pos_b -
// pos_a) / s_a, Q = sigma R_a^T R_b, exactly. Computed: t~ (a subtraction, a
// dot product, a division: within (1.74 u + 1.74 g_3 + 1.75 u) (P_a + P_b) /
// s_a < 1e-15 (P_a + P_b) / s_a of t) and Q~ (each entry a dot product of two
// columns, |.| <= 1.00001, times fl(sigma): within 6e-16 sigma of Q's), so
// with F(q) = t~ + Q~ q (exact), |Phi(w~) - F(q)| <= 1e-15 (P_a + P_b) /
// s_a + 3e-15 sigma L_b + 1e-15 (P_b / s_a + 1.74 sigma L_b), the pair's
// part mu_b below (doubled, with 2e-15 |t~| of the node images' centres).
// b's node: every vertex q under it is c + sum_j b_j v_j exactly, |b_j| <=
// half_j (NodeObb), so F(q) = C + sum_j b_j V_j + d with C = fl(t~ + Q~ c),
// V_j = fl(Q~ v_j) (the image) and |d| <= g_4 (|t~| + qmax |c|_1) + sum_j
// half_j g_3 qmax |v_j|_1 <= 1e-15 |t~| + 1e-15 qmax (|c|_1 + sum half)
// (qmax = max |Q~_ij|, |v_j|_1 <= 1.74). So Phi of b's rounded vertices
// under the node lie in C + sum_j b_j V_j + a cube of half-side eps_b =
// mu_b + 2e-15 qmax (|c|_1 + sum half) (the node's eps).
//
// |V_j|_2 <= ||Q~||_2 (1 + 1e-12) + rounding <= 1.0001 sigma <= qn =
// 1.001 fl(sigma); |u_i|_2 <= 1.0001 for a's fitted axes u_i; a computed dot
// product fl(x . y) is within g_3 |x|_2 |y|_2 < 3.4e-16 |x|_2 |y|_2 of x . y.
// The comparisons: every radius is a sum of non-negative terms computed
// within a relative 1e-15 of its value, so the factor 1 + 1e-12 covers them
// with the rounding of the sum and of the centres' difference (the box
// test); the projection of the centres' difference gets its own slack (at
// rel_apart).
#pragma once
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>

#include "common/cpu.hpp"
#include "common/simd.hpp"

// (f64x4 values passed between inlined helpers: no ABI boundary is crossed.)
#pragma GCC diagnostic ignored "-Wpsabi"
#include "narrow/bvh.hpp"
#include "world/mesh.hpp"

namespace hgcd {

// The node tests are expanded in place in both builds of the traversal
// (tree_path.cpp: SSE2, and AVX2 where the CPU has it), so that each gets
// its own instruction set; the same IEEE operations either way.
#define HGCD_RF_INLINE inline __attribute__((always_inline))

struct RelFrame {
    double t[3];      // t~
    double q[9];      // Q~, row-major: column j is b's mesh axis j in a's frame
    double mu_a;      // a's rounded vertices are within mu_a of their mesh points
    double mu_b;      // the pair's part of each node image's eps
    double node_eps;  // times (|c|_1 + sum half): the node's part (2e-15 qmax)
    double qn;        // >= |V_j|_2 of every image axis
    // |V_j . V_k| <= gram (j = k) or gram_off (j != k) for the computed
    // axes V_j of every node image (prepare_frame)
    double gram, gram_off;
    double tmax, qmax;  // |t~| and max |Q~_ij|
    double la, lb;      // the roots' reaches L_a, L_b
};

// Node images come in blocks of two siblings, as Bvh::lanes (lane l of
// field k at 2k + l): centre C (0..2), axes V_j (3 + 3j), halves (12..14),
// half extents in a's frame (15..17), radii on their own axes (18..20),
// |V_j|_1 (21..23), the radius on any a axis beyond the halves' (24: 1e-15
// qn sum half + 1.74 eps), the nodes' links and spans (kImageLink,
// kImageSpan, copied from the lanes' kLinkField, kSpanField).
constexpr size_t kImageBlock = 54;
constexpr int kImageLink = 25;
constexpr int kImageSpan = 26;

// Both lanes of a block of doubles (field k), or lane l of it in both.
HGCD_RF_INLINE f64x2 lanes2(const double *block, int k) {
    f64x2 r;
    std::memcpy(&r, block + 2 * k, sizeof r);
    return r;
}
HGCD_RF_INLINE f64x2 splat(const double *block, int k, int l) {
    const double x = block[2 * k + l];
    return f64x2{x, x};
}
HGCD_RF_INLINE f64x2 vabs(f64x2 x) { return (f64x2)((i64x2)x & i64x2{INT64_MAX, INT64_MAX}); }
HGCD_RF_INLINE f64x2 both(double x) { return f64x2{x, x}; }

// max_k |p_k|.
inline double max_abs3(const double *p) { return std::max(std::max(std::fabs(p[0]), std::fabs(p[1])), std::fabs(p[2])); }

// The frame of the pair (a, b): a's mesh frame. False when the frame's
// values leave the range where the argument above holds (the caller then
// takes the world-space node tests): a's frame divides by s_a, so a tiny
// scale can push the centres towards overflow, where an infinite centre
// would compare as apart against finite radii. With tmax, qmax, qmax L_b,
// L_a and 1 / fl(sigma) at most 1e100, every centre, axis, difference and
// dot product below stays under 1e250; radii may still overflow, which
// only makes a test fail to separate.
inline bool prepare_frame(const BodyView &a, const BodyView &b, RelFrame &f) {
    const double *ra = a.r.m, *rb = b.r.m;
    const double d[3] = {b.position[0] - a.position[0], b.position[1] - a.position[1],
                         b.position[2] - a.position[2]};
    double tmax = 0;
    for (int i = 0; i < 3; ++i) {
        f.t[i] = ((ra[i] * d[0] + ra[3 + i] * d[1]) + ra[6 + i] * d[2]) / a.scale;
        tmax = std::max(tmax, std::fabs(f.t[i]));
    }
    const double sigma = b.scale / a.scale;
    double qmax = 0;
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) {
            f.q[3 * i + j] = ((ra[i] * rb[j] + ra[3 + i] * rb[3 + j]) + ra[6 + i] * rb[6 + j]) * sigma;
            qmax = std::max(qmax, std::fabs(f.q[3 * i + j]));
        }
    const double la = a.mesh->root_reach, lb = b.mesh->root_reach;  // (Mesh::root_reach: of a.root, b.root)
    const double pa = max_abs3(a.position) / a.scale, pab = (max_abs3(a.position) + max_abs3(b.position)) / a.scale;
    double rho = a.defect;
    if (!(rho <= 1)) {
        const double columns[9] = {ra[0], ra[3], ra[6], ra[1], ra[4], ra[7], ra[2], ra[5], ra[8]};
        rho = orthonormal_defect(columns);
    }
    const double big = 1e100;
    if (!(tmax <= big && qmax <= big && qmax * lb <= big && la <= big && sigma * big >= 1)) return false;
    // Underflow: each rounding of a world vertex may also be off by half a
    // subnormal ulp (2^-1075, absolute), at most 2^-1070 over the five of
    // transform_point; Phi maps that to 1.74 2^-1070 / s_a < 2^-1069 / s_a,
    // and t~'s products add 3 2^-1075 / s_a. 2^-1068 / s_a covers both (at
    // most 64, as s_a >= 2^-1074). Underflow in a's frame itself (images,
    // products of Q~) is absolute there and below the 1e-300 terms or, for
    // Q~'s entries, 1e-322 sigma L_b, within the 1e-14 sigma L_b term.
    const double under = 0x1p-1068 / a.scale;
    f.mu_a = (2e-15 * pa + (4e-15 + 1.01 * rho) * la) * (1 + 1e-10) + 1e-300 + under;
    f.mu_b = (6e-15 * pab + 1e-14 * sigma * lb + 2e-15 * tmax) * (1 + 1e-10) + 1e-300 + under;
    f.node_eps = 2e-15 * qmax;
    f.qn = 1.001 * sigma;
    // The Gram bound. V_j = fl(Q~ v_j) is within g_3 qmax |v_j|_1 (max
    // norm, |v_j|_1 <= 1.74) of Q~ v_j, so |V_j - Q~ v_j|_2 < 1.1e-15 qmax
    // <= 1.1e-15 qn and |V_j . V_k - v_j^T M v_k| <= 2.3e-15 qn^2, M =
    // Q~^T Q~. R_a = n R_u + (1 - n) I up to its entries' roundings has
    // singular values within 2.1e-6 of 1 (|n - 1| <= 1e-6), as R_b has, so
    // Q = sigma R_a^T R_b has them within sigma [1 - 4.2e-6, 1 + 4.3e-6],
    // Q~ (entries within 6e-16 sigma of Q's, 2-norm 1.8e-15 sigma) within
    // sigma [1 - 4.3e-6, 1 + 4.4e-6], and M's eigenvalues are within
    // sigma^2 [1 - 8.6e-6, 1 + 8.9e-6]: ||M - sigma^2 I||_2 <= 9e-6
    // sigma^2. With |v_j . v_k - d_jk| <= 1e-12 (NodeObb) and |v_j|_2^2 <= 1
    // + 1e-12, |v_j^T M v_k| <= sigma^2 (d_jk + 1e-5); sigma^2 <= fl(sigma)^2
    // (1 + 3u).
    const double s2 = sigma * sigma * (1 + 1e-15);
    f.gram = s2 * (1 + 1e-5) + 2.3e-15 * f.qn * f.qn;
    f.gram_off = s2 * 1e-5 + 2.3e-15 * f.qn * f.qn;
    f.tmax = tmax, f.qmax = qmax, f.la = la, f.lb = lb;
    return true;
}

// A test cheaper than the frame and the roots' test, tried first: b's root
// box taken as a ball about its centre, the centre mapped to a's frame, apart
// from a's root box (on `scanned`, with the same test turned round, it
// settles two in three of the pairs the roots' test would).
//
// The ball. b's mesh points q lie in [c_b - h_b, c_b + h_b], so T_b(q) is
// within ||R_b||_2 s_b |h_b|_2 <= (1 + 2.1e-6) s_b |h_b|_2 of T_b(c_b)
// (2-norm); each rounded world vertex, and the computed centre m =
// fl(T_b(c_b)), is within g_5 (P_b + 1.74 s_b L_b) (max norm) of its exact
// value, so every rounded vertex of b lies within rb = (1 + 2.1e-6) s_b
// |h_b|_2 + 2e-15 (P_b + 1.74 s_b L_b) of m (2-norm: 2 sqrt(3) g_5 < 2e-15).
// Phi(x) - Phi(m) = R_a^T (x - m) / s_a, whose max norm is below its 2-norm,
// at most (1 + 2.1e-6) rb / s_a. The computed y = fl(fl(R_a^T fl(m - pos_a))
// fl(1 / s_a)) is within (1.74 u + 1.74 g_3 + 1.74 u + 2u) (|m| + P_a) / s_a
// < 2e-15 (|m| + P_a) / s_a of Phi(m), and |m| <= (P_b + 1.74 s_b L_b) (1 +
// 1e-15). So Phi of b's vertices lie within ball = (Mesh::root_ball s_b + 5e-15
// (P_b + 1.74 s_b L_b) + 2e-15 P_a) / s_a of y (root_ball >= (1 + 4.3e-6)
// |h_b|_2).
//
// a's side as above, with rho_a bounded without computing it: R_a = n R_u +
// (1 - n) I up to its entries' roundings (about 1e-15 each), so R_a^T R_a - I
// = n (n - 1) (2 I - R_u - R_u^T), of norm at most 1.000001e-6 (2 + 2 sqrt(3))
// < 6e-6 (|n - 1| <= 1e-6, validated), and mu_a <= 6e-6 L_a + 2e-15 (P_a /
// s_a + 1.74 L_a) < 1e-5 L_a + 2e-15 P_a / s_a. b's vertices are apart from
// a's on axis k when |y_k - c_k| > h_k + mu_a + ball: the terms are
// non-negative, each computed within a relative 1e-15, and |y_k - c_k| within
// u, which the factor 1 + 1e-12 covers. Underflow (world roundings, b's and
// m's, and the products before the division) stays under 2^-1066 / s_a.
// Overflow (a tiny s_a) leaves an infinity or a NaN in y, which an axis then
// does not take (only |y_k| <= 1e300, so no step overflowed), or in the
// bound, which then separates nothing.

// A body's side of the balls' test: its mesh, rotation, position and scale.
struct BallSide {
    const Mesh &mesh;
    const Rotation &r;
    const double *position;
    double scale;
};
inline bool root_ball_apart(const BallSide &a, const BallSide &b) {
    const BvhNode &na = root_node(a.mesh);
    double m[3];
    transform_point(b.r, b.position, b.scale, root_node(b.mesh).center, m);
    const double inv = 1 / a.scale, pa = max_abs3(a.position);
    const double ball = (b.mesh.root_ball * b.scale + 5e-15 * (max_abs3(b.position) + 1.74 * b.scale * b.mesh.root_reach) +
                         4e-15 * pa + 0x1p-1066) * inv +
                        1e-5 * a.mesh.root_reach;
    const double d[3] = {m[0] - a.position[0], m[1] - a.position[1], m[2] - a.position[2]};
    const double *r = a.r.m;
    bool apart = false;
    for (int k = 0; k < 3; ++k) {
        const double y = ((r[k] * d[0] + r[3 + k] * d[1]) + r[6 + k] * d[2]) * inv;
        apart |= std::fabs(y) <= 1e300 && std::fabs(y - na.center[k]) > (na.half[k] + ball) * (1 + 1e-12) + 1e-300;
    }
    return apart;
}

// The images of the two nodes of b's block `in` (Bvh::lanes) in a's frame:
// the image block `out`. Each lane is the scalar formula on its node.
HGCD_RF_INLINE void node_images(const RelFrame &f, const double *in, double *out) {
    const double *q = f.q;
    f64x2 c[3], h[3], V[9];
    for (int k = 0; k < 3; ++k) {
        c[k] = lanes2(in, 6 + k);
        h[k] = lanes2(in, 18 + k);
    }
    for (int i = 0; i < 3; ++i) {
        const f64x2 C = both(f.t[i]) + ((both(q[3 * i]) * c[0] + both(q[3 * i + 1]) * c[1]) + both(q[3 * i + 2]) * c[2]);
        std::memcpy(out + 2 * i, &C, sizeof C);
    }
    for (int j = 0; j < 3; ++j) {
        const f64x2 v0 = lanes2(in, 9 + 3 * j), v1 = lanes2(in, 10 + 3 * j), v2 = lanes2(in, 11 + 3 * j);
        for (int i = 0; i < 3; ++i)
            V[3 * j + i] = (both(q[3 * i]) * v0 + both(q[3 * i + 1]) * v1) + both(q[3 * i + 2]) * v2;
    }
    const f64x2 hsum = (h[0] + h[1]) + h[2];
    const f64x2 eps = both(f.mu_b) + both(f.node_eps) * (((vabs(c[0]) + vabs(c[1])) + vabs(c[2])) + hsum);
    // Each field stored as computed (one 16-byte store; a block built
    // aside and copied went out as a rep movs, 2% of a detect on `scanned`).
    auto put = [out](int k, f64x2 v) __attribute__((always_inline)) { std::memcpy(out + 2 * k, &v, sizeof v); };
    for (int k = 0; k < 9; ++k) put(3 + k, V[k]);
    for (int k = 0; k < 3; ++k) {
        put(12 + k, h[k]);
        put(15 + k, ((h[0] * vabs(V[k]) + h[1] * vabs(V[3 + k])) + h[2] * vabs(V[6 + k])) + eps);
    }
    // The radius on an own axis V_j, sum_k half_k |V_j . V_k|, from
    // RelFrame::gram's bound on the axes' Gram matrix.
    const f64x2 off = both(f.gram_off) * hsum + both(1e-300);
    for (int j = 0; j < 3; ++j) {
        const f64x2 l1 = (vabs(V[3 * j]) + vabs(V[3 * j + 1])) + vabs(V[3 * j + 2]);
        put(18 + j, (both(f.gram) * h[j] + off) + eps * l1);
        put(21 + j, l1);
    }
    put(24, (both(1e-15 * f.qn) * hsum + both(1.74) * eps) + both(1e-300));
    static_assert(kImageSpan == kImageLink + 1 && kSpanField == kLinkField + 1, "links and spans copied at once");
    std::memcpy(out + 2 * kImageLink, in + 2 * kLinkField, 4 * sizeof(double));
}

// Node pairs several at once, one per lane (f64x2, f64x4: each lane does
// the IEEE double operations of the scalar formulas, so the bits do not
// depend on the vector width): lane l pairs a node of a (its fields in
// Bvh::lanes: the mesh-frame box, the fitted box; field k from A(k)) with a
// node image of b (B(k)). A lane of the result is set when that pair is
// certainly apart. First the
// boxes in a's frame: a's vertices lie within mu_a of [c - h, c + h]
// (BvhNode), b's within the half extents of C (the image's fitted box and its
// eps, projected on the frame's axes). Then the fitted boxes on their six
// face axes z: a's vertices project on z within sum_i half_i |z . u_i| (+
// mu_a |z|_1) of z . c_a, b's within sum_j half_j |z . V_j| (+ eps |z|_1) of
// z . C. On a's own axis z = u_i the first is below half_i + 1e-12 sum half
// (||U U^T - I||_inf <= 1e-12, NodeObb), |u_i|_1 <= 1.74; the cross terms
// carry 1e-15 qn sum half for the dot products' roundings. The centres'
// projection t = fl(z . fl(C - c_a)) is within (u + g_3 (1 + u)) |z|_1 |C -
// c_a|_inf < 5e-16 |z|_1 |C - c_a|_1 of exact (dl below is |C - c_a|_1,
// computed within 2u): the slack 2e-15 dl on a's axes (|z|_1 <= 1.74), 1e-15
// |V_j|_1 dl on b's.
template <class V>
HGCD_RF_INLINE V vsplat(double x) {
    V v;
    for (size_t l = 0; l < sizeof(V) / sizeof(double); ++l) v[l] = x;
    return v;
}
template <class V, class I>
HGCD_RF_INLINE V vabs_lanes(V x) {
    return (V)((I)x & (vsplat<I>(0) + INT64_MAX));
}
template <class I>
HGCD_RF_INLINE bool all_lanes(I m) {
    int64_t all = -1;
    for (size_t l = 0; l < sizeof(I) / sizeof(int64_t); ++l) all &= m[l];
    return all != 0;
}
template <class I>
HGCD_RF_INLINE unsigned lane_bits(I m) {
    unsigned bits = 0;
    for (size_t l = 0; l < sizeof(I) / sizeof(int64_t); ++l) bits |= unsigned(m[l] & 1) << l;
    return bits;
}

template <class V, class I, class LoadA, class LoadB>
HGCD_RF_INLINE unsigned rel_apart_lanes(const RelFrame &f, LoadA A, LoadB B) {
    auto vabs = [](V x) __attribute__((always_inline)) { return vabs_lanes<V, I>(x); };
    auto all = [](double x) __attribute__((always_inline)) { return vsplat<V>(x); };
    const V mu_a = all(f.mu_a), grow = all(1 + 1e-12), tiny = all(1e-300);
    I apart = vsplat<I>(0);
    for (int k = 0; k < 3; ++k)
        apart |= vabs(B(k) - A(k)) > ((A(3 + k) + mu_a) + B(15 + k)) * grow;
    if (all_lanes(apart)) return lane_bits(apart);
    V d[3], Vb[9], ha[3], hb[3], u[9];
    for (int k = 0; k < 3; ++k) {
        d[k] = B(k) - A(6 + k);
        ha[k] = A(18 + k);
        hb[k] = B(12 + k);
    }
    for (int k = 0; k < 9; ++k) {
        Vb[k] = B(3 + k);
        u[k] = A(9 + k);
    }
    const V dl = (vabs(d[0]) + vabs(d[1])) + vabs(d[2]);
    const V hsum = (ha[0] + ha[1]) + ha[2];
    V rel[3][3];  // |u_i . V_j|
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) {
            const V *x = u + 3 * i, *y = Vb + 3 * j;
            rel[i][j] = vabs((x[0] * y[0] + x[1] * y[1]) + x[2] * y[2]);
        }
    const V own_a = (all(1e-12) * hsum + all(1.74) * mu_a) + tiny;
    const V slack_a = all(2e-15) * dl + tiny;
    const V extra_b = B(24);
    for (int i = 0; i < 3; ++i) {
        const V *z = u + 3 * i;
        const V t = (z[0] * d[0] + z[1] * d[1]) + z[2] * d[2];
        const V rb = ((hb[0] * rel[i][0] + hb[1] * rel[i][1]) + hb[2] * rel[i][2]) + extra_b;
        apart |= vabs(t) > ((ha[i] + own_a) + rb) * grow + slack_a;
    }
    const V cross_a = all(1e-15 * f.qn) * hsum + tiny;
    for (int j = 0; j < 3; ++j) {
        const V *z = Vb + 3 * j;
        const V t = (z[0] * d[0] + z[1] * d[1]) + z[2] * d[2];
        const V l1 = B(21 + j);
        const V ra = ((ha[0] * rel[0][j] + ha[1] * rel[1][j]) + ha[2] * rel[2][j]) + (cross_a + mu_a * l1);
        apart |= vabs(t) > (B(18 + j) + ra) * grow + (all(1e-15) * l1 * dl + tiny);
    }
    return lane_bits(apart);
}

// Two pairs: bit l for lane l. kPairA: a's two lanes are the two nodes of
// block `a` (else lane la of it in both); likewise kPairB for b's image
// block.
template <bool kPairA, bool kPairB>
HGCD_RF_INLINE unsigned rel_apart2(const RelFrame &f, const double *a, int la, const double *b, int lb) {
    auto A = [&](int k) __attribute__((always_inline)) { return kPairA ? lanes2(a, k) : splat(a, k, la); };
    auto B = [&](int k) __attribute__((always_inline)) { return kPairB ? lanes2(b, k) : splat(b, k, lb); };
    return rel_apart_lanes<f64x2, i64x2>(f, A, B);
}

// The four pairs of a's two nodes of block `a` with b's two of image block
// `b`: bit la + 2 lb for the pair (lane la of a, lane lb of b). kWide: in
// one four-lane test, expanded only inside AVX2 functions (its builtin
// needs their target), else in two two-lane ones (the same bits).
template <bool kWide>
HGCD_RF_INLINE unsigned rel_apart4(const RelFrame &f, const double *a, const double *b) {
#if HGCD_AVX2
    if constexpr (kWide) {
        // Lane 2 la + lb: b's two nodes repeated, a 16-byte broadcast load
        // for each of b's fields (the more numerous), one load and a
        // shuffle for each of a's; as written out element by element or as
        // shuffles, the compiler took a lane-crossing permute for each.
        auto A = [&](int k) __attribute__((always_inline)) {
            const f64x2 v = lanes2(a, k);
            return f64x4(__builtin_shufflevector(v, v, 0, 0, 1, 1));
        };
        auto B = [&](int k) __attribute__((always_inline)) {
            return f64x4(__builtin_ia32_vbroadcastf128_pd256(reinterpret_cast<const f64x2 *>(b + 2 * k)));
        };
        const unsigned bits = rel_apart_lanes<f64x4, i64x4>(f, A, B);
        return (bits & 9u) | (bits & 2u) << 1 | (bits & 4u) >> 1;
    }
#endif
    return rel_apart2<true, false>(f, a, 0, b, 0) | rel_apart2<true, false>(f, a, 0, b, 1) << 2;
}

}  // namespace hgcd
