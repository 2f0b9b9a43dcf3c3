// Mesh creation: the arrays checked, and what hgcd works out about the shape
// once (mesh.hpp).
#include "world/mesh.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <new>
#include <numeric>
#include <string>

#include "exact/geometry.hpp"
#include "common/ieee.hpp"

namespace hgcd {

namespace {

constexpr uint32_t kMaxCount = 1u << 26;
// Exact convexity costs triangles x vertices orientation tests; beyond this
// a mesh is treated as non-convex (still exact, only without the shortcut).
constexpr uint64_t kConvexCheckBudget = 50'000'000;

uint32_t find_root(std::vector<uint32_t> &parent, uint32_t v) {
    while (parent[v] != v) {
        parent[v] = parent[parent[v]];
        v = parent[v];
    }
    return v;
}

bool is_degenerate(const double *a, const double *b, const double *c) {
    // Collinear (or coincident) iff every coordinate-plane projection has zero area.
    const double pa[3][2] = {{a[0], a[1]}, {a[1], a[2]}, {a[2], a[0]}};
    const double pb[3][2] = {{b[0], b[1]}, {b[1], b[2]}, {b[2], b[0]}};
    const double pc[3][2] = {{c[0], c[1]}, {c[1], c[2]}, {c[2], c[0]}};
    for (int k = 0; k < 3; ++k)
        if (orient2d(pa[k], pb[k], pc[k]) != 0) return false;
    return true;
}

// The reason the arrays are refused, or "" when they are accepted.
std::string check_arrays(const double *vertices, uint32_t vertex_count, const uint32_t *triangles,
                         uint32_t triangle_count) {
    if (triangle_count == 0) return "mesh has no triangles";
    if (vertex_count == 0) return "mesh has no vertices";
    if (triangle_count > kMaxCount || vertex_count > kMaxCount)
        return "mesh too large: at most 2^26 vertices and 2^26 triangles";
    for (uint32_t v = 0; v < vertex_count; ++v) {
        if (vertex_ok(vertices + 3 * v)) continue;
        for (int k = 0; k < 3; ++k)
            if (!std::isfinite(vertices[3 * v + k]))
                return "vertex " + std::to_string(v) + " coordinate " + std::to_string(k) + " is not finite";
        return "vertex " + std::to_string(v) + " is beyond 1e15 from the mesh origin";
    }
    for (uint32_t i = 0; i < 3 * triangle_count; ++i)
        if (triangles[i] >= vertex_count)
            return "triangle " + std::to_string(i / 3) + " index " + std::to_string(triangles[i]) +
                   " >= vertex_count " + std::to_string(vertex_count);
    return "";
}

// Bounding sphere about the centre of the vertex box of the used vertices,
// and the reach that limits a body's scale.
void set_bounding_sphere(Mesh &m, const std::vector<char> &used) {
    const double *vertices = m.vertices.data();
    double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
    for (uint32_t v = 0; v < m.vertex_count; ++v) {
        if (!used[v]) continue;
        for (int k = 0; k < 3; ++k) {
            lo[k] = std::min(lo[k], vertices[3 * v + k]);
            hi[k] = std::max(hi[k], vertices[3 * v + k]);
        }
    }
    for (int k = 0; k < 3; ++k) m.center[k] = 0.5 * lo[k] + 0.5 * hi[k];
    double r2 = 0;
    m.reach = 0;
    for (uint32_t v = 0; v < m.vertex_count; ++v) {
        if (!used[v]) continue;
        m.reach = std::max(m.reach, vertex_norm(vertices + 3 * v));
        double d2 = 0;
        for (int k = 0; k < 3; ++k) {
            const double d = vertices[3 * v + k] - m.center[k];
            d2 += d * d;
        }
        r2 = std::max(r2, d2);
    }
    // Inflate by a relative margin far above the rounding of the sum above.
    m.radius = std::sqrt(r2) * (1 + 1e-12);
}

// Mesh::box_cut: the nodes kBoxCutDepth levels below the root, or leaves
// above that (every triangle lies under exactly one of them).
void set_box_cut(Mesh &m) {
    const std::vector<BvhNode> &nodes = m.bvh.nodes;
    std::vector<const BvhNode *> cut;
    std::vector<std::pair<uint32_t, uint32_t>> stack{{0u, 0u}};  // (node, depth)
    while (!stack.empty()) {
        const auto top = stack.back();
        stack.pop_back();
        const BvhNode &n = nodes[top.first];
        if (n.count == 0 && top.second < Mesh::kBoxCutDepth) {
            stack.push_back({n.first + 1, top.second + 1});
            stack.push_back({n.first, top.second + 1});
            continue;
        }
        cut.push_back(&n);
    }
    while (cut.size() % 4) cut.push_back(cut.back());
    const size_t count = cut.size();
    m.box_cut_nodes = count;
    m.box_cut.assign(Mesh::kBoxCutFields * count, 0.0);
    for (size_t i = 0; i < count; ++i)
        for (int k = 0; k < 3; ++k) {
            m.box_cut[k * count + i] = cut[i]->center[k];
            m.box_cut[(3 + k) * count + i] = cut[i]->half[k];
            m.box_cut_reach[k] = std::max(m.box_cut_reach[k], std::fabs(cut[i]->center[k]) + cut[i]->half[k]);
        }
}

// Mesh::root_ball and root_reach (the factor 1 + 1e-12 covers the roundings
// of the sum and the square root).
void set_root_ball(Mesh &m) {
    const BvhNode &n = root_node(m);
    const double *h = n.half;
    m.root_ball = std::sqrt((h[0] * h[0] + h[1] * h[1]) + h[2] * h[2]) * ((1 + 4.3e-6) * (1 + 1e-12));
    for (int k = 0; k < 3; ++k) m.root_reach = std::max(m.root_reach, std::fabs(n.center[k]) + h[k]);
}

// Mesh::point_node and point_lanes: [c - half, c + half] holds every vertex
// exactly (the half widths rounded up, as a tree node's).
void set_point_node(Mesh &m) {
    double l[3] = {INFINITY, INFINITY, INFINITY}, h[3] = {-INFINITY, -INFINITY, -INFINITY};
    for (uint32_t i = 0; i < m.vertex_count; ++i)
        for (int k = 0; k < 3; ++k) {
            l[k] = std::min(l[k], m.vertices[3 * size_t(i) + k]);
            h[k] = std::max(h[k], m.vertices[3 * size_t(i) + k]);
        }
    for (int k = 0; k < 3; ++k)
        if (!(l[k] <= h[k])) l[k] = h[k] = 0;  // (no vertex)
    BvhNode &n = m.point_node;
    set_node_box(n, l, h);
    NodeObb o;
    for (int k = 0; k < 3; ++k) {
        o.center[k] = n.center[k];
        o.half[k] = n.half[k];
    }
    for (int k = 0; k < 9; ++k) o.axis[k] = k % 4 == 0;
    n.first = 0;
    n.count = m.triangle_count;
    m.point_lanes.assign(kLaneBlock, 0.0);
    node_lanes(n, o, 0, m.triangle_count, 0, m.point_lanes.data());
}

// Degenerate triangles and connected components (union-find on vertices).
void set_components(Mesh &m, const std::vector<char> &used) {
    const double *vertices = m.vertices.data();
    std::vector<uint32_t> parent(m.vertex_count);
    std::iota(parent.begin(), parent.end(), 0u);
    for (uint32_t t = 0; t < m.triangle_count; ++t) {
        const uint32_t *f = &m.triangles[3 * t];
        if (is_degenerate(&vertices[3 * f[0]], &vertices[3 * f[1]], &vertices[3 * f[2]]))
            ++m.degenerate_count;
        for (int k = 1; k < 3; ++k) {
            const uint32_t a = find_root(parent, f[0]), b = find_root(parent, f[k]);
            if (a != b) parent[std::max(a, b)] = std::min(a, b);
        }
    }
    for (uint32_t v = 0; v < m.vertex_count; ++v)
        if (used[v] && find_root(parent, v) == v) m.component_vertices.push_back(v);
}

// Closed: every undirected edge appears an even number of times.
bool is_closed(const Mesh &m) {
    std::vector<uint64_t> edges;
    edges.reserve(3 * size_t(m.triangle_count));
    for (uint32_t t = 0; t < m.triangle_count; ++t) {
        const uint32_t *f = &m.triangles[3 * t];
        for (int k = 0; k < 3; ++k) {
            uint32_t a = f[k], b = f[(k + 1) % 3];
            if (a == b) continue;  // a repeated index adds no edge
            if (a > b) std::swap(a, b);
            edges.push_back((uint64_t(a) << 32) | b);
        }
    }
    std::sort(edges.begin(), edges.end());
    bool closed = !edges.empty();
    for (size_t i = 0; i < edges.size() && closed;) {
        size_t j = i;
        while (j < edges.size() && edges[j] == edges[i]) ++j;
        if ((j - i) % 2) closed = false;
        i = j;
    }
    return closed;
}

// Convex: closed, and every vertex on one consistent side of every face.
void set_convexity(Mesh &m, const std::vector<char> &used) {
    if (!m.closed || m.degenerate_count >= m.triangle_count ||
        uint64_t(m.triangle_count) * m.vertex_count > kConvexCheckBudget)
        return;
    const double *vertices = m.vertices.data();
    int sign = 0;
    bool convex = true;
    for (uint32_t t = 0; t < m.triangle_count && convex; ++t) {
        const uint32_t *f = &m.triangles[3 * t];
        const double *a = &vertices[3 * f[0]], *b = &vertices[3 * f[1]], *c = &vertices[3 * f[2]];
        for (uint32_t v = 0; v < m.vertex_count && convex; ++v) {
            // (The triangle's own corners are on its plane: orient3d's exact
            // 0, which its filter cannot tell quickly.)
            if (!used[v] || v == f[0] || v == f[1] || v == f[2]) continue;
            const int s = orient3d(a, b, c, &vertices[3 * v]);
            if (s == 0) continue;
            if (sign == 0) sign = s;
            else if (s != sign) convex = false;
        }
    }
    m.convex = convex && sign != 0;
    m.inward_sign = m.convex ? sign : 0;
}

// A tetrahedron: 4 vertices, and 4 triangles that are its 4 vertex triples.
void set_tetra(Mesh &m) {
    if (m.vertex_count != 4 || m.triangle_count != 4) return;
    unsigned seen = 0;  // bit (6 - sum of the indices): the vertex a face misses
    for (uint32_t t = 0; t < 4; ++t) {
        const uint32_t *f = &m.triangles[3 * t];
        if (f[0] != f[1] && f[1] != f[2] && f[0] != f[2]) seen |= 1u << (6 - (f[0] + f[1] + f[2]));
    }
    m.tetra = seen == 0xF;
    for (int v = 0; v < 4; ++v) {
        const double *p = &m.vertices[3 * v];
        for (int k = 0; k < 3; ++k) m.tetra_local[4 * k + v] = p[k];
        m.tetra_reach = std::max(m.tetra_reach, std::fabs(p[0]) + std::fabs(p[1]) + std::fabs(p[2]));
    }
}

// SatData's runs while they are worked out (set_sat), then packed into
// one block (SatBuilder::pack).
struct SatParts {
    std::vector<double> axes, face_range, soa, half_soa, planes;
    std::vector<uint32_t> half_arg, vertex_edge_start, vertex_edges, vertex_tri_start, vertex_tris;
    uint32_t faces = 0, edges = 0, padded = 0, half_padded = 0, plane_count = 0, planes_padded = 0;
    double reach = 0, theta = 0, inner = 0;
    bool inside_test = false;
};

}  // namespace

// The parts as one block: the header, then the runs in the order of
// SatData's accessors (each list aligned for its type).
struct SatBuilder {
    static SatRef pack(const Mesh &m, const SatParts &d) {
        const size_t doubles = d.soa.size() + d.half_soa.size() + d.planes.size() + d.axes.size() + d.face_range.size();
        const size_t edges_end = 8 * doubles + d.half_arg.size() + 2 * d.vertex_edge_start.size() + d.vertex_edges.size();
        const size_t tri_at = d.vertex_tri_start.empty() ? 0 : (edges_end + 3) / 4 * 4;
        const size_t bytes = tri_at ? tri_at + 4 * (d.vertex_tri_start.size() + d.vertex_tris.size()) : edges_end;
        SatData *h = new (::operator new(sizeof(SatData) + bytes)) SatData;
        SatRef ref(h);
        h->reach = d.reach;
        h->theta = d.theta;
        h->inner = d.inner;
        h->vertex_count = uint16_t(m.vertex_count);
        h->padded = uint16_t(d.padded);
        h->half_padded = uint16_t(d.half_padded);
        h->faces = uint16_t(d.faces);
        h->edges = uint16_t(d.edges);
        h->plane_count = uint16_t(d.plane_count);
        h->planes_padded = uint16_t(d.planes_padded);
        h->inside_test = d.inside_test;
        h->tri_at = uint32_t(tri_at);
        h->hot_bytes = uint32_t(sizeof(SatData) + edges_end);
        char *at = reinterpret_cast<char *>(h + 1);
        const auto put = [&at](const auto &v) {
            if (v.empty()) return;  // (data() may be null: not for memcpy)
            std::memcpy(at, v.data(), v.size() * sizeof(v[0]));
            at += v.size() * sizeof(v[0]);
        };
        put(d.soa);
        put(d.half_soa);
        put(d.planes);
        put(d.axes);
        put(d.face_range);
        for (uint32_t v : d.half_arg) *at++ = char(v);
        for (uint32_t v : d.vertex_edge_start) {
            const uint16_t e = uint16_t(v);
            std::memcpy(at, &e, 2);
            at += 2;
        }
        for (uint32_t v : d.vertex_edges) *at++ = char(v);
        if (tri_at) {
            at = reinterpret_cast<char *>(h + 1) + tri_at;
            put(d.vertex_tri_start);
            put(d.vertex_tris);
        }
        return ref;
    }
};

namespace {

// Appends direction d (3 doubles) to axes unless it is zero or parallel to
// one there; returns whether it was added.
bool add_axis(std::vector<double> &axes, const double *d) {
    const double n = std::sqrt((d[0] * d[0] + d[1] * d[1]) + d[2] * d[2]);
    if (!(n > 0) || !std::isfinite(n)) return false;
    const double u[3] = {d[0] / n, d[1] / n, d[2] / n};
    for (size_t k = 0; k < axes.size(); k += 3) {
        const double *a = &axes[k];
        const double c[3] = {u[1] * a[2] - u[2] * a[1], u[2] * a[0] - u[0] * a[2], u[0] * a[1] - u[1] * a[0]};
        if ((c[0] * c[0] + c[1] * c[1]) + c[2] * c[2] < 1e-18) return false;
    }
    axes.insert(axes.end(), u, u + 3);
    return true;
}

// Per vertex, its neighbours (each edge once per end) and, past
// SatData::kAllTriangles triangles, its triangles.
void set_adjacency(const Mesh &m, SatParts &d) {
    const uint32_t nv = m.vertex_count;
    std::vector<uint64_t> edges;
    for (uint32_t t = 0; t < m.triangle_count; ++t)
        for (int k = 0; k < 3; ++k) {
            const uint32_t a = m.triangles[3 * t + k], b = m.triangles[3 * t + (k + 1) % 3];
            if (a != b) {
                edges.push_back(uint64_t(a) << 32 | b);
                edges.push_back(uint64_t(b) << 32 | a);
            }
        }
    std::sort(edges.begin(), edges.end());
    edges.erase(std::unique(edges.begin(), edges.end()), edges.end());
    d.vertex_edge_start.assign(nv + 1, 0);
    for (uint64_t e : edges) ++d.vertex_edge_start[(e >> 32) + 1];
    for (uint32_t v = 0; v < nv; ++v) d.vertex_edge_start[v + 1] += d.vertex_edge_start[v];
    d.vertex_edges.resize(edges.size());
    for (size_t k = 0; k < edges.size(); ++k) d.vertex_edges[k] = uint32_t(edges[k]);  // (sorted by first end)
    if (m.triangle_count <= SatData::kAllTriangles) return;
    d.vertex_tri_start.assign(nv + 1, 0);
    for (uint32_t i = 0; i < 3 * m.triangle_count; ++i) ++d.vertex_tri_start[m.triangles[i] + 1];
    for (uint32_t v = 0; v < nv; ++v) d.vertex_tri_start[v + 1] += d.vertex_tri_start[v];
    d.vertex_tris.resize(3 * size_t(m.triangle_count));
    std::vector<uint32_t> fill(d.vertex_tri_start.begin(), d.vertex_tri_start.end() - 1);
    for (uint32_t i = 0; i < 3 * m.triangle_count; ++i) d.vertex_tris[fill[m.triangles[i]]++] = i / 3;
}

// The vertices in runs of x, y, z for the batched kernel, padded with
// copies of vertex 0.
void set_soa(const Mesh &m, SatParts &d) {
    const uint32_t n = m.vertex_count, p = (n + SatData::kLanes - 1) / SatData::kLanes * SatData::kLanes;
    d.padded = p;
    d.soa.resize(3 * size_t(p));
    for (uint32_t i = 0; i < p; ++i)
        for (int k = 0; k < 3; ++k) d.soa[k * size_t(p) + i] = m.vertices[3 * size_t(i < n ? i : 0) + k];
    // The symmetric half (SatData::half_padded): each vertex paired with
    // its exact negation, the first of each pair kept (n is small).
    const double *x = m.vertices.data();
    std::vector<uint32_t> mirror(n, UINT32_MAX);
    for (uint32_t i = 0; i < n; ++i)
        for (uint32_t j = 0; j < n && mirror[i] == UINT32_MAX; ++j)
            if (x[3 * j] == -x[3 * i] && x[3 * j + 1] == -x[3 * i + 1] && x[3 * j + 2] == -x[3 * i + 2]) mirror[i] = j;
    std::vector<uint32_t> half;
    for (uint32_t i = 0; i < n; ++i) {
        if (mirror[i] == UINT32_MAX) return;  // (not symmetric)
        if (mirror[i] >= i) half.push_back(i);
    }
    const uint32_t h = uint32_t(half.size()), hp = (h + SatData::kLanes - 1) / SatData::kLanes * SatData::kLanes;
    if (hp >= p) return;
    d.half_padded = hp;
    d.half_soa.resize(3 * size_t(hp));
    for (uint32_t i = 0; i < hp; ++i) {
        const uint32_t v = half[i < h ? i : 0];
        for (int k = 0; k < 3; ++k) d.half_soa[k * size_t(hp) + i] = x[3 * size_t(v) + k];
        d.half_arg.insert(d.half_arg.end(), {v, mirror[v]});
    }
}

// The planes of the deep-inside test (SatData::inside_test). It needs a
// mesh whose solid is its hull: one component, no zero-area triangle, the
// origin strictly on the inner side of every triangle's plane (exact
// orient3d) and inside the solid by exact ray parity. Every point of the
// open hull then has the origin's parity (the segment between them stays in
// the open hull, which no triangle reaches), so it is inside the solid.
// Per triangle, N~ = fl((b - a) x (c - a)) from rounded differences is
// within 4 eps perm_k of the exact N on each axis (perm_k the sum of the two
// products' magnitudes, first order), so |N~ - N|_2 <= 4 eps sum_k perm_k;
// unit vectors differ by at most twice that over |N|, and fl(N~ / |N~|)
// adds 4 eps: theta = 16 eps sum perm / |N~| + 8 eps bounds |n - N/|N||_2
// while 4 eps sum perm <= |N~| / 2, which theta <= 2^-30 ensures.
void set_planes(const Mesh &m, SatParts &d) {
    if (m.component_vertices.size() != 1 || m.degenerate_count || !m.inward_sign) return;
    const double *x = m.vertices.data();
    const double origin[3] = {0, 0, 0};
    double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
    for (uint32_t v = 0; v < m.vertex_count; ++v)
        for (int k = 0; k < 3; ++k) {
            lo[k] = std::min(lo[k], x[3 * v + k]);
            hi[k] = std::max(hi[k], x[3 * v + k]);
        }
    std::vector<double> planes;  // n x, n y, n z, k per plane
    double theta = 0;
    for (uint32_t t = 0; t < m.triangle_count; ++t) {
        const uint32_t *f = &m.triangles[3 * t];
        const double *a = &x[3 * f[0]], *b = &x[3 * f[1]], *c = &x[3 * f[2]];
        if (orient3d(a, b, c, origin) != m.inward_sign) return;
        const double e1[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]}, e2[3] = {c[0] - a[0], c[1] - a[1], c[2] - a[2]};
        const double m0 = e1[1] * e2[2], m1 = e1[2] * e2[1], m2 = e1[2] * e2[0], m3 = e1[0] * e2[2],
                     m4 = e1[0] * e2[1], m5 = e1[1] * e2[0];
        const double N[3] = {m0 - m1, m2 - m3, m4 - m5};
        const double perm = (std::fabs(m0) + std::fabs(m1)) + (std::fabs(m2) + std::fabs(m3)) +
                            (std::fabs(m4) + std::fabs(m5));
        const double len = std::sqrt((N[0] * N[0] + N[1] * N[1]) + N[2] * N[2]);
        if (!(len > 0)) return;
        theta = std::max(theta, 16 * 0x1p-53 * perm / len + 8 * 0x1p-53);
        // Outward: orient3d(a, b, c, p) = -(p - a) . N has the inward sign
        // for inner points p.
        const double sign = m.inward_sign;
        const double n[3] = {sign * N[0] / len, sign * N[1] / len, sign * N[2] / len};
        const double k = (n[0] * a[0] + n[1] * a[1]) + n[2] * a[2];
        bool seen = false;
        for (size_t q = 0; q < planes.size() && !seen; q += 4)
            seen = planes[q] == n[0] && planes[q + 1] == n[1] && planes[q + 2] == n[2] && planes[q + 3] == k;
        if (!seen) planes.insert(planes.end(), {n[0], n[1], n[2], k});
    }
    if (!(theta <= 0x1p-30)) return;
    if (!point_in_closed_mesh(origin, x, m.triangles.data(), m.triangle_count, lo, hi)) return;
    const uint32_t count = uint32_t(planes.size() / 4);
    const uint32_t p = (count + SatData::kLanes - 1) / SatData::kLanes * SatData::kLanes;
    d.planes.resize(4 * size_t(p));
    for (uint32_t i = 0; i < p; ++i)
        for (int k = 0; k < 4; ++k) d.planes[k * size_t(p) + i] = planes[4 * size_t(i < count ? i : 0) + k];
    d.plane_count = count;
    d.planes_padded = p;
    d.theta = theta;
    d.inner = INFINITY;
    for (uint32_t i = 0; i < count; ++i) d.inner = std::min(d.inner, planes[4 * size_t(i) + 3]);
    d.inside_test = d.inner > 0;
}

// The convex path's data (Mesh::sat): face normals, then edge directions,
// parallel ones once; reach; adjacency; the kernel's vertex runs and planes.
void set_sat(Mesh &m, const std::vector<char> &used, const SameSat &same, bool tetra_sat) {
    if (!m.convex || m.vertex_count > Mesh::kSatVertices || (m.tetra && !tetra_sat)) return;
    for (uint32_t v = 0; v < m.vertex_count; ++v)
        if (!used[v]) return;
    if (same && (m.sat = same(m))) return;
    const double *x = m.vertices.data();
    std::vector<double> axes;
    uint32_t faces = 0;
    for (uint32_t t = 0; t < m.triangle_count; ++t) {
        const uint32_t *f = &m.triangles[3 * t];
        const double *a = &x[3 * f[0]], *b = &x[3 * f[1]], *c = &x[3 * f[2]];
        const double u[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]}, v[3] = {c[0] - a[0], c[1] - a[1], c[2] - a[2]};
        const double n[3] = {u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0]};
        faces += add_axis(axes, n);
    }
    if (!faces) return;
    // Edge directions of the hull's edges: an edge between two triangles in
    // one plane (a box face's diagonal) is none, and its direction is not
    // needed for the separating axes (any edge shared otherwise is kept).
    std::vector<std::array<uint32_t, 3>> sides;  // (low end, high end, opposite vertex)
    for (uint32_t t = 0; t < m.triangle_count; ++t) {
        const uint32_t *f = &m.triangles[3 * t];
        for (int k = 0; k < 3; ++k)
            sides.push_back({std::min(f[k], f[(k + 1) % 3]), std::max(f[k], f[(k + 1) % 3]), f[(k + 2) % 3]});
    }
    std::sort(sides.begin(), sides.end());
    std::vector<double> edge_axes;
    uint32_t edges = 0;
    for (size_t i = 0; i < sides.size();) {
        size_t j = i;
        while (j < sides.size() && sides[j][0] == sides[i][0] && sides[j][1] == sides[i][1]) ++j;
        const double *a = &x[3 * sides[i][0]], *b = &x[3 * sides[i][1]];
        const bool flat = j - i == 2 && orient3d(a, b, &x[3 * sides[i][2]], &x[3 * sides[i + 1][2]]) == 0;
        if (!flat) {
            const double e[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]};
            edges += add_axis(edge_axes, e);
        }
        i = j;
    }
    axes.insert(axes.end(), edge_axes.begin(), edge_axes.end());
    SatParts d;
    set_adjacency(m, d);
    d.axes = std::move(axes);
    d.faces = faces;
    for (uint32_t k = 0; k < faces; ++k) {
        const double *n = &d.axes[3 * k];
        double lo = INFINITY, hi = -INFINITY;
        for (uint32_t v = 0; v < m.vertex_count; ++v) {
            const double p = (x[3 * v] * n[0] + x[3 * v + 1] * n[1]) + x[3 * v + 2] * n[2];
            lo = std::min(lo, p);
            hi = std::max(hi, p);
        }
        d.face_range.insert(d.face_range.end(), {lo, hi});
    }
    d.edges = edges;
    for (uint32_t v = 0; v < m.vertex_count; ++v)
        d.reach = std::max(d.reach, std::fabs(x[3 * v]) + std::fabs(x[3 * v + 1]) + std::fabs(x[3 * v + 2]));
    set_soa(m, d);
    set_planes(m, d);
    m.sat = SatBuilder::pack(m, d);
}

}  // namespace

bool build_mesh(const double *vertices, uint32_t vertex_count, const uint32_t *triangles,
                uint32_t triangle_count, Mesh *out, std::string *error, const SameSat &same, bool tetra_sat,
                int threads) {
    *error = check_arrays(vertices, vertex_count, triangles, triangle_count);
    if (!error->empty()) return false;
    Mesh m;
    m.vertex_count = vertex_count;
    m.triangle_count = triangle_count;
    m.vertices.assign(vertices, vertices + 3 * size_t(vertex_count));
    m.triangles.assign(triangles, triangles + 3 * size_t(triangle_count));
    std::vector<char> used(vertex_count, 0);
    for (uint32_t v : m.triangles) used[v] = 1;
    set_bounding_sphere(m, used);
    set_components(m, used);
    m.closed = is_closed(m);
    set_convexity(m, used);
    set_tetra(m);
    set_sat(m, used, same, tetra_sat);
    if (triangle_count > kBvhMinTriangles) {
        build_bvh(m.vertices.data(), m.triangles.data(), triangle_count, &m.bvh, threads);
        if (vertex_count <= Mesh::kHullPoints) m.hull = build_hull(m.vertices.data(), used, Mesh::kHullVertices);
    } else {
        set_point_node(m);
    }
    if (triangle_count > Mesh::kExactBoxTriangles) set_box_cut(m);
    set_root_ball(m);
    *out = std::move(m);
    return true;
}

SatRef::~SatRef() {
    if (p_ && p_->refs.fetch_sub(1, std::memory_order_acq_rel) == 1) {
        p_->~SatData();
        ::operator delete(p_);
    }
}

void add_tetra_sat(Mesh &m, const SameSat &same) {
    if (!m.tetra || m.sat) return;
    std::vector<char> used(m.vertex_count, 0);
    for (uint32_t v : m.triangles) used[v] = 1;
    set_sat(m, used, same, true);
}

}  // namespace hgcd
