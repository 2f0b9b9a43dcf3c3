// The convex hull of a point set, incrementally (beneath-beyond): each point
// strictly beyond the plane of some face of the hull so far replaces the
// faces it sees by a cone from their horizon to itself; a point that sees no
// face lies in the hull (or on its boundary) and is left out.
//
// Exactness. "Sees" is orient3d < 0 on a face wound counter-clockwise from
// outside, exact. The faces seen from a point strictly outside a convex
// polytope form a disk (coplanar faces are seen together), so the cone over
// its horizon bounds the hull of the polytope and the point, and a point on
// the boundary but outside every face (beyond a face's edge, in its plane)
// still sees the face across that edge. So every point is in the hull of the
// vertices of the final faces, whatever the degeneracies (coplanar or
// repeated points). Only the order of insertion and the first tetrahedron
// use floating point, and neither can change what is inside.
#include "common/ieee.hpp"
#include "narrow/hull.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>

#include "common/cpu.hpp"
#include "common/simd.hpp"
#include "exact/geometry.hpp"

// (f64x4 values passed between inlined helpers: no ABI boundary is crossed.)
#pragma GCC diagnostic ignored "-Wpsabi"

namespace hgcd {

namespace {

struct Builder {
    const double *x;
    std::vector<uint32_t> face;      // 3 vertex indices a face, counter-clockwise from outside
    std::vector<uint32_t> degree;    // faces at each vertex
    uint32_t vertices = 0;           // with degree > 0
    std::vector<uint32_t> seen;      // scratch: faces seen from the point being added
    std::vector<uint64_t> edges;     // scratch: their directed edges, u << 32 | v

    const double *p(uint32_t i) const { return x + 3 * size_t(i); }

    void add_face(uint32_t a, uint32_t b, uint32_t c) {
        for (uint32_t v : {a, b, c})
            if (degree[v]++ == 0) ++vertices;
        face.insert(face.end(), {a, b, c});
    }
    void drop_face(size_t f) {  // the last face takes its place
        for (int k = 0; k < 3; ++k)
            if (--degree[face[3 * f + k]] == 0) --vertices;
        std::copy(face.end() - 3, face.end(), face.begin() + 3 * f);
        face.resize(face.size() - 3);
    }

    // Adds point i: true unless it lies in the hull so far.
    bool add(uint32_t i) {
        seen.clear();
        for (size_t f = 0; f < face.size() / 3; ++f)
            if (orient3d(p(face[3 * f]), p(face[3 * f + 1]), p(face[3 * f + 2]), p(i)) < 0) seen.push_back(uint32_t(f));
        if (seen.empty()) return false;
        edges.clear();
        for (uint32_t f : seen)
            for (int k = 0; k < 3; ++k)
                edges.push_back(uint64_t(face[3 * f + k]) << 32 | face[3 * f + (k + 1) % 3]);
        std::sort(edges.begin(), edges.end());
        for (auto f = seen.rbegin(); f != seen.rend(); ++f) drop_face(*f);  // highest first: swaps keep the rest
        // The horizon: edges of seen faces whose twin is on a face not seen.
        for (uint64_t e : edges) {
            const uint32_t u = uint32_t(e >> 32), v = uint32_t(e);
            if (!std::binary_search(edges.begin(), edges.end(), uint64_t(v) << 32 | u)) add_face(u, v, i);
        }
        return true;
    }
};

inline double dist2(const double *a, const double *b) {
    return (a[0] - b[0]) * (a[0] - b[0]) + (a[1] - b[1]) * (a[1] - b[1]) + (a[2] - b[2]) * (a[2] - b[2]);
}

// Four points not in one plane, the first three spread out (float), or false.
bool first_tetrahedron(const Builder &h, const std::vector<uint32_t> &pts, uint32_t *t) {
    auto farthest = [&](auto &&measure) {
        uint32_t best = pts[0];
        double far = -1;
        for (uint32_t i : pts)
            if (const double m = measure(h.p(i)); m > far) far = m, best = i;
        return best;
    };
    t[0] = farthest([](const double *q) { return -q[0]; });
    t[1] = farthest([&](const double *q) { return dist2(q, h.p(t[0])); });
    const double *a = h.p(t[0]), *b = h.p(t[1]);
    const double u[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]};
    double n[3];
    t[2] = farthest([&](const double *q) {
        const double w[3] = {q[0] - a[0], q[1] - a[1], q[2] - a[2]};
        const double c[3] = {u[1] * w[2] - u[2] * w[1], u[2] * w[0] - u[0] * w[2], u[0] * w[1] - u[1] * w[0]};
        return c[0] * c[0] + c[1] * c[1] + c[2] * c[2];
    });
    const double *c = h.p(t[2]);
    const double w[3] = {c[0] - a[0], c[1] - a[1], c[2] - a[2]};
    n[0] = u[1] * w[2] - u[2] * w[1], n[1] = u[2] * w[0] - u[0] * w[2], n[2] = u[0] * w[1] - u[1] * w[0];
    t[3] = farthest([&](const double *q) {
        return std::fabs(n[0] * (q[0] - a[0]) + n[1] * (q[1] - a[1]) + n[2] * (q[2] - a[2]));
    });
    if (orient3d(a, b, c, h.p(t[3])) != 0) return true;
    for (uint32_t i : pts)  // the float pick was too close to call: any point off the plane
        if (orient3d(a, b, c, h.p(i)) != 0) {
            t[3] = i;
            return true;
        }
    return false;  // coplanar (or the first three collinear: no hull then, which is safe)
}

// Orders v[b, e) so that each run of Hull::kGroup lies close together:
// split at a multiple of kGroup near the middle along the longest side of
// their box (coordinate, then index: the same order on any machine).
void group_order(const Builder &h, std::vector<uint32_t> &v, size_t b, size_t e) {
    if (e - b <= Hull::kGroup) return;
    double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
    for (size_t i = b; i < e; ++i)
        for (int k = 0; k < 3; ++k) {
            lo[k] = std::min(lo[k], h.p(v[i])[k]);
            hi[k] = std::max(hi[k], h.p(v[i])[k]);
        }
    int axis = 0;
    for (int k = 1; k < 3; ++k)
        if (hi[k] - lo[k] > hi[axis] - lo[axis]) axis = k;
    const size_t mid = b + std::max<size_t>(Hull::kGroup, (e - b) / (2 * Hull::kGroup) * Hull::kGroup);
    std::nth_element(v.begin() + b, v.begin() + mid, v.begin() + e, [&](uint32_t x, uint32_t y) {
        const double px = h.p(x)[axis], py = h.p(y)[axis];
        return px < py || (px == py && x < y);
    });
    group_order(h, v, b, mid);
    group_order(h, v, mid, e);
}

// Hull::groups from the rows. The radius: the largest computed distance from
// the centre, each within a few u of exact (times 1 + 1e-12) but for
// underflow in the squares (3 2^-1074 in d2 at most, below 1e-161 once
// rooted).
void set_groups(Hull &out) {
    const size_t n = out.padded(), count = out.group_count(), stride = (count + 3) / 4 * 4;
    for (double v : out.xyz) out.extent = std::max(out.extent, std::fabs(v));
    out.groups.assign(Hull::kGroupFields * stride, 0.0);
    for (size_t g = 0; g < stride; ++g) {
        const size_t from = Hull::kGroup * (g < count ? g : 0);
        double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
        for (size_t i = from; i < from + Hull::kGroup; ++i)
            for (int k = 0; k < 3; ++k) {
                lo[k] = std::min(lo[k], out.rows[k * n + i]);
                hi[k] = std::max(hi[k], out.rows[k * n + i]);
            }
        double c[3], r2 = 0;
        for (int k = 0; k < 3; ++k) c[k] = 0.5 * lo[k] + 0.5 * hi[k];
        for (size_t i = from; i < from + Hull::kGroup; ++i) {
            double d2 = 0;
            for (int k = 0; k < 3; ++k) d2 += (out.rows[k * n + i] - c[k]) * (out.rows[k * n + i] - c[k]);
            r2 = std::max(r2, d2);
        }
        const double r = std::sqrt(r2) * (1 + 1e-12) + 1e-161, cmax = std::max(std::max(std::fabs(c[0]), std::fabs(c[1])), std::fabs(c[2]));
        const double field[Hull::kGroupFields] = {c[0], c[1], c[2], r, 2e-15 * (cmax + r)};
        for (size_t k = 0; k < Hull::kGroupFields; ++k) out.groups[k * stride + g] = field[k];
    }
}

}  // namespace

Hull build_hull(const double *x, const std::vector<char> &used, uint32_t max_vertices, std::vector<uint32_t> *faces) {
    Builder h{x, {}, std::vector<uint32_t>(used.size(), 0), 0, {}, {}};
    std::vector<uint32_t> pts;
    for (uint32_t i = 0; i < used.size(); ++i)
        if (used[i]) pts.push_back(i);
    uint32_t t[4];
    if (pts.size() < 4 || !first_tetrahedron(h, pts, t)) return Hull();
    for (int k = 0; k < 4; ++k) {  // each face wound so that the fourth point is inside
        uint32_t f[3] = {t[k], t[(k + 1) % 4], t[(k + 2) % 4]};
        if (orient3d(h.p(f[0]), h.p(f[1]), h.p(f[2]), h.p(t[(k + 3) % 4])) < 0) std::swap(f[1], f[2]);
        h.add_face(f[0], f[1], f[2]);
    }
    // The points extreme along 26 directions first: the hull is then near
    // its final shape, and the polytope they span (`core`) holds most points:
    // a point that sees none of its faces is in the hull, tested on those few
    // faces only.
    for (int d = 0; d < 27; ++d) {
        const int s[3] = {d % 3 - 1, d / 3 % 3 - 1, d / 9 - 1};
        if (!s[0] && !s[1] && !s[2]) continue;
        uint32_t best = pts[0];
        double far = -INFINITY;
        for (uint32_t i : pts)
            if (const double m = s[0] * h.p(i)[0] + s[1] * h.p(i)[1] + s[2] * h.p(i)[2]; m > far) far = m, best = i;
        h.add(best);
    }
    const std::vector<uint32_t> core = h.face;
    for (uint32_t i : pts) {
        bool outside = false;
        for (size_t f = 0; f < core.size() / 3 && !outside; ++f)
            outside = orient3d(h.p(core[3 * f]), h.p(core[3 * f + 1]), h.p(core[3 * f + 2]), h.p(i)) < 0;
        if (outside && h.add(i) && h.vertices > max_vertices) return Hull();
    }
    if (faces) *faces = h.face;
    // The hull's vertices in groups (group_order), and its edges: each
    // directed edge (u, v) of a face names v as a neighbour of u (its twin,
    // on the face across, names u as v's).
    Hull out;
    std::vector<uint32_t> order, id(used.size(), UINT32_MAX);
    for (uint32_t v = 0; v < h.degree.size(); ++v)
        if (h.degree[v]) order.push_back(v);
    group_order(h, order, 0, order.size());
    for (uint32_t v : order) {
        id[v] = out.size++;
        out.xyz.insert(out.xyz.end(), h.p(v), h.p(v) + 3);
    }
    const size_t padded = (out.size + Hull::kGroup - 1) / Hull::kGroup * Hull::kGroup;
    out.rows.resize(3 * padded);
    for (size_t i = 0; i < padded; ++i)
        for (int k = 0; k < 3; ++k) out.rows[k * padded + i] = out.xyz[3 * (i < out.size ? i : 0) + k];
    set_groups(out);
    out.first.assign(out.size + 1, 0);
    for (uint32_t v : h.face) ++out.first[id[v] + 1];
    for (uint32_t i = 0; i < out.size; ++i) out.first[i + 1] += out.first[i];
    out.adj.resize(h.face.size());
    std::vector<uint32_t> at(out.first.begin(), out.first.end() - 1);
    for (size_t f = 0; f < h.face.size(); f += 3)
        for (int k = 0; k < 3; ++k) out.adj[at[id[h.face[f + k]]]++] = id[h.face[f + (k + 1) % 3]];
    static const double kSeedDirections[14][3] = {{1, 0, 0},  {-1, 0, 0},  {0, 1, 0},   {0, -1, 0},  {0, 0, 1},
                                                   {0, 0, -1}, {1, 1, 1},   {1, 1, -1},  {1, -1, 1},  {1, -1, -1},
                                                   {-1, 1, 1}, {-1, 1, -1}, {-1, -1, 1}, {-1, -1, -1}};
    for (int d = 0; d < 14; ++d) {
        double best;
        out.seed[d] = hull_support(out, kSeedDirections[d], &best);
    }
    return out;
}

uint32_t hull_climb(const Hull &h, const double *dir, uint32_t start) {
    auto dot = [&](uint32_t i) {
        const double *p = &h.xyz[3 * size_t(i)];
        return (dir[0] * p[0] + dir[1] * p[1]) + dir[2] * p[2];
    };
    uint32_t at = start;
    if (at == UINT32_MAX) {
        at = h.seed[0];
        for (uint32_t s : h.seed)
            if (dot(s) > dot(at)) at = s;
    }
    double best = dot(at);
    for (uint32_t from = UINT32_MAX; from != at;) {  // to the best neighbour, while one is higher
        from = at;
        for (uint32_t k = h.first[from]; k < h.first[from + 1]; ++k)
            if (const double d = dot(h.adj[k]); d > best) best = d, at = h.adj[k];
    }
    return at;
}

// The signs. For a vertex p and a neighbour q, e_k = fl(q_k - p_k) is within
// u |e_k| / (1 - u) of q_k - p_k (u = 2^-53), so d . e within that times
// sum |d_k e_k| of d . (q - p), and s = fl((d0 e0 + d1 e1) + d2 e2) within
// g_3 sum |d_k e_k| of d . e: |s - d . (q - p)| < 4.5e-16 sum |d_k e_k|. The
// bound err = 5e-16 fl(sum |fl(d_k e_k)|) + 1e-300 covers it with the
// roundings of the products and sums (and underflow), so s > err proves q
// higher, s < -err proves it lower. Every neighbour lower (or level, which
// is not told apart: then the scan) makes p a top over the hull: it is
// convex, and the cone of p's edges holds it. The value: any vertex x has
// fl(d . x) <= d . x + g_3 |d|_1 X <= d . p + g_3 |d|_1 X <= fl(d . p) + 2
// g_3 |d|_1 X (X: the hull's extent), and 1e-15 |d|_1 X + 1e-300 covers 2
// g_3 |d|_1 X with the roundings of its terms and of the final sum.
uint32_t hull_support_near(const Hull &h, const double *dir, uint32_t start, double *bound) {
    constexpr int kSteps = 16;
    const double n1 = (std::fabs(dir[0]) + std::fabs(dir[1])) + std::fabs(dir[2]);
    if (start >= h.size || !(n1 * h.extent < 1e300)) return UINT32_MAX;
    const double *x = h.xyz.data();
    uint32_t at = start;
    for (int step = 0; step < kSteps; ++step) {
        const double *p = x + 3 * size_t(at);
        uint32_t next = UINT32_MAX;
        double rise = 0;
        bool level = false;
        for (uint32_t k = h.first[at]; k < h.first[at + 1]; ++k) {
            const double *q = x + 3 * size_t(h.adj[k]);
            const double e0 = dir[0] * (q[0] - p[0]), e1 = dir[1] * (q[1] - p[1]), e2 = dir[2] * (q[2] - p[2]);
            const double s = (e0 + e1) + e2;
            const double err = 5e-16 * ((std::fabs(e0) + std::fabs(e1)) + std::fabs(e2)) + 1e-300;
            if (s > err) {
                if (s > rise) rise = s, next = h.adj[k];
            } else {
                level |= !(s < -err);
            }
        }
        if (next != UINT32_MAX) {
            at = next;
            continue;
        }
        if (level) return UINT32_MAX;
        *bound = ((dir[0] * p[0] + dir[1] * p[1]) + dir[2] * p[2]) + (1e-15 * n1 * h.extent + 1e-300);
        return at;
    }
    return UINT32_MAX;
}

namespace {

// hull_support over lanes of V (f64x2 or f64x4). Each group's ball bounds
// its vertices' computed projections from above; the group of the highest
// bound is scanned first, and the groups whose bound is below the top found
// there hold no vertex at the top: they are skipped, the others scanned in
// order of index (a running maximum per lane, strict: the first in each lane,
// then the lowest index among the lanes' equal maxima), so the answer is a
// full scan's whatever the width.
//
// The bound. A vertex q of a group with centre c and radius r has d . q <= d
// . c + |d|_2 r; fl(d . q) is within g_3 |d|_1 |q|_inf <= g_3 |d|_1 (|c|_inf
// + r) of d . q and fl(d . c) within g_3 |d|_1 |c|_inf of d . c, so fl(d . q)
// <= fl(d . c) + |d|_2 r + |d|_1 k, k = 2e-15 (|c|_inf + r) (g_3 < 4e-16),
// which also covers the roundings of the bound's own products and sums
// (relative u each, of terms at most |d|_1 (|c|_inf + r)) and of |d|_2 (taken
// as fl(sqrt(fl(d . d))) (1 + 1e-12), or as |d|_1 where d . d nears the
// subnormals); 1e-300 covers underflow. Only for |d|_1 times the largest
// |coordinate| below 1e300: no value overflows.
template <class V>
__attribute__((always_inline)) inline uint32_t support_lanes(const Hull &h, const double *dir, double *best) {
    constexpr int L = sizeof(V) / sizeof(double);
    const size_t n = h.padded(), count = h.group_count(), stride = h.group_stride();
    const double *x = h.rows.data(), *y = x + n, *z = y + n;
    const double *gx = h.groups.data(), *gy = gx + stride, *gz = gy + stride, *gr = gz + stride, *gk = gr + stride;
    auto all = [](double v) __attribute__((always_inline)) {
        V r;
        for (int l = 0; l < L; ++l) r[l] = v;
        return r;
    };
    auto load = [](const double *p) __attribute__((always_inline)) {
        V r;
        std::memcpy(&r, p, sizeof r);
        return r;
    };
    const V d0 = all(dir[0]), d1 = all(dir[1]), d2 = all(dir[2]);
    const double norm1 = (std::fabs(dir[0]) + std::fabs(dir[1])) + std::fabs(dir[2]);
    V m = all(-INFINITY), at = all(0), first;
    for (int l = 0; l < L; ++l) first[l] = l;
    const V step = all(L);
    auto scan = [&](size_t g) __attribute__((always_inline)) {
        const size_t k0 = Hull::kGroup * g;
        V i = first + all(double(k0));
#pragma GCC unroll 16
        for (size_t j = 0; j < Hull::kGroup; j += L, i += step) {
            const size_t k = k0 + j;
            const V p = (d0 * load(x + k) + d1 * load(y + k)) + d2 * load(z + k);
            const auto higher = p > m;
            m = higher ? p : m;
            at = higher ? i : at;  // indices as doubles: exact, and no 64-bit integer compare in SSE2
        }
    };
    if (count > Hull::kMaxGroups || !(norm1 * h.extent < 1e300)) {
        for (size_t g = 0; g < count; ++g) scan(g);
    } else {
        const double dd = (dir[0] * dir[0] + dir[1] * dir[1]) + dir[2] * dir[2];
        const double norm2 = dd >= 0x1p-1000 ? std::sqrt(dd) * (1 + 1e-12) : norm1;  // (|d|_1 >= |d|_2)
        const V n1 = all(norm1), n2 = all(norm2), tiny = all(1e-300);
        // Each group's bound, and the group of the highest (the lowest index
        // among equals: padding groups repeat group 0).
        double up[Hull::kMaxGroups];
        V top_up = all(-INFINITY), top_g = all(0), g_at = first;
        for (size_t g = 0; g < stride; g += L, g_at += step) {
            const V dc = (d0 * load(gx + g) + d1 * load(gy + g)) + d2 * load(gz + g);
            const V u = dc + ((n2 * load(gr + g) + n1 * load(gk + g)) + tiny);
            std::memcpy(up + g, &u, sizeof u);
            const auto higher = u > top_up;
            top_up = higher ? u : top_up;
            top_g = higher ? g_at : top_g;
        }
        double tu = -INFINITY, tg = 0;
        for (int l = 0; l < L; ++l)
            if (top_up[l] > tu || (top_up[l] == tu && top_g[l] < tg)) tu = top_up[l], tg = top_g[l];
        // Its top bounds the others from below.
        const size_t top = size_t(tg);
        V t = all(-INFINITY);
#pragma GCC unroll 16
        for (size_t j = 0; j < Hull::kGroup; j += L) {
            const size_t k = Hull::kGroup * top + j;
            const V p = (d0 * load(x + k) + d1 * load(y + k)) + d2 * load(z + k);
            t = p > t ? p : t;
        }
        double floor = -INFINITY;
        for (int l = 0; l < L; ++l) floor = t[l] > floor ? t[l] : floor;
        for (size_t g = 0; g < count; ++g)
            if (!(up[g] < floor)) scan(g);
    }
    double bm = -INFINITY, ba = 0;
    for (int l = 0; l < L; ++l)
        if (m[l] > bm || (m[l] == bm && at[l] < ba)) bm = m[l], ba = at[l];
    *best = bm;
    return uint32_t(ba);
}

#if HGCD_AVX2
__attribute__((target("avx2"), noinline)) uint32_t support_avx2(const Hull &h, const double *dir, double *best) {
    return support_lanes<f64x4>(h, dir, best);
}
#endif

}  // namespace

uint32_t hull_support(const Hull &h, const double *dir, double *best) {
#if HGCD_AVX2
    if (use_avx2()) return support_avx2(h, dir, best);
#endif
    return support_lanes<f64x2>(h, dir, best);
}

}  // namespace hgcd
