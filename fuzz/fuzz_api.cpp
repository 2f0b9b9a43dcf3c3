// libFuzzer target for the whole C API.
//
// The input bytes are read as a world descriptor and then a sequence of API
// calls: create/destroy meshes (preset shapes, random small meshes with
// degenerate triangles, NaN/huge vertices, bad indices, bad descriptors),
// create/destroy bodies (poses from tables of ordinary, far, tiny, huge,
// NaN and infinite values; unit, near-unit, non-unit, zero and NaN
// quaternions), set_pose, set_velocity, step, detect, pairs, copy_pairs,
// stats, mesh info, the getters and validation, with live, stale, forged
// and random ids; the batch calls (world_set_poses, world_set_velocities,
// world_get_poses) with listed ids (repeated ones too) or indices, good and
// bad strides, arrays interleaved as a caller's struct; body types, enabling,
// filters and excluded pairs (set, read back, refused); the events of each
// tick against the difference of its pairs and the last.
//
// A shadow model predicts every status (refusals included, and for a batch
// the entry its message names) and the full observable state; after every
// call the world must agree with it. After
// every detect and step, the pairs are compared with the GMP brute-force
// oracle of tests/oracle.c. Any disagreement aborts (a finding).
//
// Built by fuzz/build.sh (clang, -fsanitize=fuzzer,address,undefined). One
// file over 600 lines: the calls, the model they update and the value tables
// they draw from are one program, read from top to bottom.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <iterator>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include <hgcd/hgcd.h>

extern "C" {
#include "oracle.h"
#include "oracle_query.h"
}

namespace {

// ------------------------------------------------------------- input --

struct Input {
    const uint8_t *p;
    size_t n;
    bool empty() const { return n == 0; }
    uint8_t u8() {
        if (!n) return 0;
        --n;
        return *p++;
    }
    uint32_t u16() { return uint32_t(u8()) | uint32_t(u8()) << 8; }
    uint32_t u32() { return u16() | u16() << 16; }
    double unit() { return double(u16()) / 65536.0; }
};

[[noreturn]] void finding(const char *what) {
    std::fprintf(stderr, "FUZZ FINDING: %s\n", what);
    std::fflush(stderr);
    std::abort();
}

#define EXPECT(cond, ...)                                         \
    do {                                                          \
        if (!(cond)) {                                            \
            std::fprintf(stderr, "%s:%d: ", __FILE__, __LINE__);  \
            std::fprintf(stderr, __VA_ARGS__);                    \
            std::fprintf(stderr, "\n");                           \
            finding(#cond);                                       \
        }                                                         \
    } while (0)

const double kNaN = std::nan("");
const double kInf = HUGE_VAL;

// --------------------------------------------------------------- shapes --

struct Shape {
    std::vector<double> v;
    std::vector<uint32_t> t;
};

std::vector<Shape> make_presets() {
    std::vector<Shape> s;
    s.push_back({{1, 1, 1, 1, -1, -1, -1, 1, -1, -1, -1, 1}, {0, 1, 2, 0, 3, 1, 0, 2, 3, 1, 3, 2}});
    const std::vector<double> cube = {-1, -1, -1, 1, -1, -1, 1, 1, -1, -1, 1, -1,
                                      -1, -1, 1,  1, -1, 1,  1, 1, 1,  -1, 1, 1};
    const std::vector<uint32_t> cube_t = {0, 2, 1, 0, 3, 2, 0, 1, 5, 0, 5, 4, 1, 2, 6, 1, 6, 5,
                                          2, 3, 7, 2, 7, 6, 3, 0, 4, 3, 4, 7, 4, 5, 6, 4, 6, 7};
    s.push_back({cube, cube_t});
    s.push_back({cube, std::vector<uint32_t>(cube_t.begin(), cube_t.begin() + 30)});  // bowl (open)
    s.push_back({{-1.5, -1, 0, 1.5, -1, 0.25, 0, 1.5, -0.25}, {0, 1, 2}});             // triangle
    s.push_back({{-1.5, 0, 0, 0, 0, 0, 1.5, 0, 0, 0.5, 0.5, 0.5}, {0, 1, 2, 3, 3, 3}});   // needle
    s.push_back({{0, 0, 0}, {0, 0, 0}});                                                   // point
    {  // dented cube: closed, not convex
        std::vector<double> v = cube;
        v.insert(v.end(), {0, 0, -0.25});
        s.push_back({v, {0, 2, 1, 0, 3, 2, 0, 1, 5, 0, 5, 4, 1, 2, 6, 1, 6, 5, 2, 3, 7,
                         2, 7, 6, 3, 0, 4, 3, 4, 7, 4, 5, 8, 5, 6, 8, 6, 7, 8, 7, 4, 8}});
    }
    s.push_back({{0.5, 0.5, 0.5, 0.5, -0.5, -0.5, -0.5, 0.5, -0.5, -0.5, -0.5, 0.5,
                  2.5, 0.5, 0.5, 2.5, -0.5, -0.5, 1.5, 0.5, -0.5, 1.5, -0.5, 0.5},
                 {0, 1, 2, 0, 3, 1, 0, 2, 3, 1, 3, 2, 4, 5, 6, 4, 7, 5, 4, 6, 7, 5, 7, 6}});  // twin
    {  // a wavy open sheet of 2 * 6 * 6 triangles (the tree path of the narrow phase)
        Shape sh;
        const int n = 6;
        for (int j = 0; j <= n; ++j)
            for (int i = 0; i <= n; ++i)
                sh.v.insert(sh.v.end(), {-1.5 + 3.0 * i / n, -1.5 + 3.0 * j / n, 0.25 * ((i + j) % 3) - 0.25});
        for (int j = 0; j < n; ++j)
            for (int i = 0; i < n; ++i) {
                const uint32_t a = j * (n + 1) + i, b = a + 1, c = a + n + 1, d = c + 1;
                sh.t.insert(sh.t.end(), {a, b, d, a, d, c});
            }
        s.push_back(sh);
    }
    {  // closed tessellated cube, 3 x 3 squares per face: 108 triangles
        Shape sh;
        const int n = 3;
        auto vid = [&](int x, int y, int z) -> uint32_t {
            const double p[3] = {-1.0 + 2.0 * x / n, -1.0 + 2.0 * y / n, -1.0 + 2.0 * z / n};
            for (size_t k = 0; k < sh.v.size() / 3; ++k)
                if (sh.v[3 * k] == p[0] && sh.v[3 * k + 1] == p[1] && sh.v[3 * k + 2] == p[2]) return uint32_t(k);
            sh.v.insert(sh.v.end(), p, p + 3);
            return uint32_t(sh.v.size() / 3 - 1);
        };
        for (int f = 0; f < 6; ++f) {
            const int axis = f / 2, hi = f % 2, u = (axis + 1) % 3, w = (axis + 2) % 3;
            for (int j = 0; j < n; ++j)
                for (int i = 0; i < n; ++i) {
                    int c[4][3];
                    const int di[4] = {0, 1, 0, 1}, dj[4] = {0, 0, 1, 1};
                    for (int k = 0; k < 4; ++k) {
                        c[k][axis] = hi ? n : 0;
                        c[k][u] = i + di[k];
                        c[k][w] = j + dj[k];
                    }
                    uint32_t id[4];
                    for (int k = 0; k < 4; ++k) id[k] = vid(c[k][0], c[k][1], c[k][2]);
                    if (hi) sh.t.insert(sh.t.end(), {id[0], id[1], id[3], id[0], id[3], id[2]});
                    else sh.t.insert(sh.t.end(), {id[0], id[3], id[1], id[0], id[2], id[3]});
                }
        }
        s.push_back(sh);
    }
    return s;
}

const std::vector<Shape> &presets() {
    static const std::vector<Shape> s = make_presets();
    return s;
}

// ---------------------------------------------------------- value tables --

const double kCoords[] = {0, 0.5, -0.5, 1, -1, 1.5, 2, -3, 0.25, 1e-9, -1e-300, 5e-324,
                          1e3, 1e9 + 0.5, 3.3e12, 1e15, -1e15, 999999999999999.875,
                          1.0000000000000002e15, -2e15, 1e16, 1.7976931348623157e308, kNaN, kInf, -kInf};
const double kScales[] = {1, 0.5, 2, 0.25, 1.5, 1e-3, 1e-6, 1e-9, 1e-12, 3, 0, -1, kNaN, kInf,
                          1e15, 4e14, 5e-324, 1e-300, 1e6};
const double kVel[] = {0, 0.25, -0.25, 1, -1, 3, -0.5, 1e-9, 1e14, -2e15, kNaN, kInf, 1.7976931348623157e308};
const double kAnchors[] = {0, 1e3, 1e9, 3.3e12, 1e15 - 64, -1e15 + 64};
const double kUnits[] = {0.25, 0.5, 1e-3, 0};  // 0: ulps of the anchor

struct Ctx {
    double anchor = 0, unit = 0.25;
};

// clean: only the grid near the anchor (no table values, so no refusals).
double coord(Input &in, const Ctx &cx, bool clean = false) {
    const uint8_t k = clean ? in.u8() % 200 : in.u8();
    if (k < 200) {  // near the anchor, on a grid (so contacts are exact and dense)
        const double off = double(int(k % 25) - 12);
        if (cx.unit == 0) return cx.anchor == 0 ? off * 5e-324 : cx.anchor + off * (std::nextafter(std::fabs(cx.anchor), kInf) - std::fabs(cx.anchor));
        return cx.anchor + off * cx.unit;
    }
    return kCoords[k % (sizeof kCoords / sizeof kCoords[0])];
}

// clean: exact or random rotations only (no odd values).
void quaternion(Input &in, double *q, bool clean = false) {
    static const double r = 0.70710678118654757;
    static const double exact[][4] = {{0, 0, 0, 1}, {1, 0, 0, 0}, {0, 1, 0, 0}, {0, 0, 1, 0},
                                      {0.5, 0.5, 0.5, 0.5}, {-0.5, 0.5, -0.5, 0.5}, {0, 0, r, r}, {r, 0, 0, r}};
    const uint8_t k = clean ? in.u8() % 200 : in.u8();
    if (k < 100) {
        std::memcpy(q, exact[k % 8], 4 * sizeof(double));
    } else if (k < 200) {  // uniform-ish random rotation
        const double u1 = in.unit(), u2 = in.unit(), u3 = in.unit();
        q[0] = std::sqrt(1 - u1) * std::sin(6.283185307179586 * u2);
        q[1] = std::sqrt(1 - u1) * std::cos(6.283185307179586 * u2);
        q[2] = std::sqrt(u1) * std::sin(6.283185307179586 * u3);
        q[3] = std::sqrt(u1) * std::cos(6.283185307179586 * u3);
    } else {
        static const double odd[][4] = {{0, 0, 0, 1 + 4e-7}, {0, 0, 0, 1 + 2e-6}, {0, 0, 0, 0},
                                        {0.5, 0.5, 0.5, 0.4999}, {kNaN, 0, 0, 1}, {0, kInf, 0, 1},
                                        {1e200, 0, 0, 0}, {0, 0, 0, -1}, {0.6, 0, 0, 0.8}};
        std::memcpy(q, odd[k % 9], 4 * sizeof(double));
    }
}

// ---------------------------------------------------------------- model --

struct MMesh {
    hgcd_mesh id{};
    bool live = false;
    std::vector<double> v;
    std::vector<uint32_t> t;
    uint32_t users = 0;
    hgcd_mesh_info info{};
    double reach = 0;  // the model's own: largest vertex norm of a used vertex
};

struct MBody {
    hgcd_body id{};
    bool live = false;
    size_t mesh = 0;  // index into Model::meshes
    double p[3], q[4], v[3], s;
    uint64_t user;
    int32_t type = HGCD_BODY_DYNAMIC;
    bool enabled = true;
    hgcd_filter filter = hgcd_filter_default();
    double margin = 0;
};

struct Model {
    hgcd_world *w = nullptr;
    hgcd_world_desc desc{};
    std::vector<MMesh> meshes;
    std::vector<MBody> bodies;
    std::set<std::pair<uint32_t, uint32_t>> issued_bodies, issued_meshes;
    uint32_t live_bodies = 0, live_meshes = 0;
    bool detected = false;
    std::vector<hgcd_pair> last_pairs;  // as returned by the last detect/step
    std::set<std::pair<uint32_t, uint32_t>> excluded;  // slot pairs (lower first)
};

// Whether the pair of model bodies a, b is considered, by hgcd.h's rules
// (body types, enabling, Box2D's filter, exclusions), written out again.
bool considered(const Model &m, const MBody &a, const MBody &b) {
    if (!a.enabled || !b.enabled) return false;
    if (m.excluded.count({std::min(a.id.index, b.id.index), std::max(a.id.index, b.id.index)})) return false;
    if (a.type == HGCD_BODY_STATIC && b.type == HGCD_BODY_STATIC) return false;
    if (a.type != HGCD_BODY_DYNAMIC && b.type != HGCD_BODY_DYNAMIC && !m.desc.kinematic_pairs) return false;
    const hgcd_filter &fa = a.filter, &fb = b.filter;
    if (fa.group_index != 0 && fa.group_index == fb.group_index) return fa.group_index > 0;
    return (fa.mask_bits & fb.category_bits) && (fa.category_bits & fb.mask_bits);
}

enum { kMaxLiveBodies = 12, kMaxLiveMeshes = 8 };

// The coordinate limits as hgcd.h states them ("Coordinate limits").
bool finite_in_range(double x) { return std::isfinite(x) && std::fabs(x) <= 1e15; }
double vertex_norm(const double *v) { return std::sqrt((v[0] * v[0] + v[1] * v[1]) + v[2] * v[2]); }
bool vertex_ok(const double *v) {
    return std::isfinite(v[0]) && std::isfinite(v[1]) && std::isfinite(v[2]) && vertex_norm(v) <= 1e15;
}

// A contact margin as hgcd.h states it: finite, >= 0, <= 1e15.
bool margin_ok(double x) { return std::isfinite(x) && x >= 0 && x <= 1e15; }
const double kMargins[] = {0.25, 1e-9, 1, 0.0625, kNaN, -1, 2e15, -0.0};
double pick_margin(uint8_t k) { return kMargins[k % (sizeof kMargins / sizeof kMargins[0])]; }

bool pose_ok(const double *p, const double *q) {
    if (p)
        for (int k = 0; k < 3; ++k)
            if (!finite_in_range(p[k])) return false;
    if (q) {
        double n2 = 0;
        for (int k = 0; k < 4; ++k) {
            if (!std::isfinite(q[k])) return false;
            n2 += q[k] * q[k];
        }
        if (!(std::fabs(n2 - 1.0) <= 1e-6)) return false;
    }
    return true;
}

hgcd_body pick_body_id(Input &in, const Model &m) {
    const uint8_t k = in.u8();
    if (!m.bodies.empty() && k < 220) {
        hgcd_body id = m.bodies[k % m.bodies.size()].id;
        if (k >= 200) id.generation ^= 1u << (in.u8() % 32);  // forged
        return id;
    }
    return hgcd_body{in.u8() % 4u == 0 ? 0u : in.u32() % 40, in.u8() % 2 ? 0u : in.u32()};
}

hgcd_mesh pick_mesh_id(Input &in, const Model &m) {
    const uint8_t k = in.u8();
    if (!m.meshes.empty() && k < 220) {
        hgcd_mesh id = m.meshes[k % m.meshes.size()].id;
        if (k >= 200) id.generation ^= 1u << (in.u8() % 32);
        return id;
    }
    return hgcd_mesh{in.u32() % 16, in.u8() % 2 ? 0u : in.u32()};
}

int live_body_of(const Model &m, hgcd_body id) {
    for (size_t i = 0; i < m.bodies.size(); ++i)
        if (m.bodies[i].live && m.bodies[i].id.index == id.index && m.bodies[i].id.generation == id.generation)
            return int(i);
    return -1;
}

int live_mesh_of(const Model &m, hgcd_mesh id) {
    for (size_t i = 0; i < m.meshes.size(); ++i)
        if (m.meshes[i].live && m.meshes[i].id.index == id.index && m.meshes[i].id.generation == id.generation)
            return int(i);
    return -1;
}

// ---------------------------------------------------- checks vs oracle --

long g_detects = 0, g_pairs_checked = 0;
// Batch calls per call and verdict (the model's: why refused, or applied).
enum BatchVerdict { kApplied, kNullArray, kBadStride, kCountPastSlots, kStaleEntry, kRepeatedEntry, kBadValue, kVerdicts };
long g_batch[3][kVerdicts] = {}, g_batch_entries[3] = {};  // (entries: of the applied calls)
long g_ops = 0;  // scripted API calls (each followed by check_state's own reads)

oracle_mesh as_oracle(const MMesh &mm) {
    oracle_mesh om;
    om.verts = mm.v.data();
    om.tris = mm.t.data();
    om.vertex_count = uint32_t(mm.v.size() / 3);
    om.triangle_count = uint32_t(mm.t.size() / 3);
    om.closed = 0;
    return om;
}

void check_pairs(Model &m) {
    const hgcd_pair *got;
    size_t count;
    EXPECT(hgcd_world_pairs(m.w, &got, &count) == HGCD_OK, "pairs");
    // Live bodies in slot order.
    std::vector<std::pair<uint32_t, size_t>> order;
    for (size_t i = 0; i < m.bodies.size(); ++i)
        if (m.bodies[i].live) order.push_back({m.bodies[i].id.index, i});
    std::sort(order.begin(), order.end());
    std::vector<oracle_mesh> om(m.meshes.size());
    for (size_t k = 0; k < m.meshes.size(); ++k)
        if (m.meshes[k].live) om[k] = as_oracle(m.meshes[k]);
    const size_t n = order.size();
    std::vector<const oracle_mesh *> bm(n + 1);
    std::vector<double> p(3 * n + 3), q(4 * n + 4), s(n + 1);
    for (size_t k = 0; k < n; ++k) {
        const MBody &b = m.bodies[order[k].second];
        bm[k] = &om[b.mesh];
        std::memcpy(&p[3 * k], b.p, sizeof b.p);
        std::memcpy(&q[4 * k], b.q, sizeof b.q);
        s[k] = b.s;
    }
    // With margins, the pairs within each pair's margin (oracle_distance.c).
    std::vector<double> mg(n + 1, 0.0);
    bool margins = m.desc.contact_margin > 0;
    for (size_t k = 0; k < n; ++k) margins |= (mg[k] = m.bodies[order[k].second].margin) > 0;
    // One oracle call, into room for every pair (the margin oracle's GMP
    // distances are the dearest part of an input).
    std::vector<uint32_t> e(n * (n > 0 ? n - 1 : 0) + 2);
    const size_t room = e.size() / 2;
    const size_t ne = margins ? oracle_pairs_within(n, bm.data(), p.data(), q.data(), s.data(), m.desc.contact_margin,
                                                    mg.data(), e.data(), room)
                              : oracle_colliding_pairs(n, bm.data(), p.data(), q.data(), s.data(), e.data(), room);
    EXPECT(ne <= room, "oracle pairs %zu past %zu", ne, room);
    std::set<std::pair<uint32_t, uint32_t>> want, have;
    for (size_t k = 0; k < ne; ++k)
        if (considered(m, m.bodies[order[e[2 * k]].second], m.bodies[order[e[2 * k + 1]].second]))
            want.insert({order[e[2 * k]].first, order[e[2 * k + 1]].first});
    for (size_t k = 0; k < count; ++k) {
        EXPECT(got[k].a.index < got[k].b.index, "pair %zu not ordered", k);
        if (k) EXPECT(got[k - 1].a.index < got[k].a.index ||
                          (got[k - 1].a.index == got[k].a.index && got[k - 1].b.index < got[k].b.index),
                      "pairs not sorted/unique at %zu", k);
        const hgcd_body ids[2] = {got[k].a, got[k].b};
        for (const hgcd_body &id : ids) EXPECT(live_body_of(m, id) >= 0, "pair id {%u,%u} not live", id.index, id.generation);
        have.insert({got[k].a.index, got[k].b.index});
    }
    g_pairs_checked += long(ne);
    ++g_detects;
    if (want == have) return;
    // A difference is a finding: print both bodies and meshes, then abort.
    auto body_at = [&](uint32_t slot) -> const MBody & {
        for (auto &o : order)
            if (o.first == slot) return m.bodies[o.second];
        finding("slot not found");
    };
    std::vector<std::pair<uint32_t, uint32_t>> diff;
    std::set_symmetric_difference(want.begin(), want.end(), have.begin(), have.end(), std::back_inserter(diff));
    for (auto &d : diff) {
        const bool missing = want.count(d) != 0;
        const MBody &a = body_at(d.first), &b = body_at(d.second);
        std::fprintf(stderr, "pair (%u, %u): %s by hgcd\n", d.first, d.second, missing ? "missed" : "extra");
        for (const MBody *x : {&a, &b})
            std::fprintf(stderr, "  body %u: mesh %u (%zu vertices, %zu triangles, convex %u) p (%.17g, %.17g, %.17g) "
                         "q (%.17g, %.17g, %.17g, %.17g) scale %.17g\n",
                         x->id.index, m.meshes[x->mesh].id.index, m.meshes[x->mesh].v.size() / 3,
                         m.meshes[x->mesh].t.size() / 3, m.meshes[x->mesh].info.convex, x->p[0], x->p[1], x->p[2],
                         x->q[0], x->q[1], x->q[2], x->q[3], x->s);
        for (const MBody *x : {&a, &b}) {
            const MMesh &mm = m.meshes[x->mesh];
            std::fprintf(stderr, "  mesh %u vertices {", mm.id.index);
            for (double c : mm.v) std::fprintf(stderr, "%.17g, ", c);
            std::fprintf(stderr, "} triangles {");
            for (uint32_t c : mm.t) std::fprintf(stderr, "%u, ", c);
            std::fprintf(stderr, "}\n");
        }
    }
    finding("pairs differ from the oracle");
}

void check_state(Model &m) {
    EXPECT(hgcd_world_body_count(m.w) == m.live_bodies, "body count %u != %u", hgcd_world_body_count(m.w), m.live_bodies);
    EXPECT(hgcd_world_mesh_count(m.w) == m.live_meshes, "mesh count");
    for (const MBody &b : m.bodies) {
        const hgcd_status s = hgcd_body_validate(m.w, b.id);
        EXPECT(s == (b.live ? HGCD_OK : HGCD_ERROR_STALE_ID), "validate body {%u,%u}: %d", b.id.index, b.id.generation, s);
        if (!b.live) continue;
        double p[3], q[4], v[3];
        uint64_t u;
        hgcd_mesh mid;
        EXPECT(hgcd_body_get_pose(m.w, b.id, p, q) == HGCD_OK, "get_pose");
        EXPECT(!std::memcmp(p, b.p, sizeof p) && !std::memcmp(q, b.q, sizeof q), "pose of body %u differs", b.id.index);
        EXPECT(hgcd_body_get_velocity(m.w, b.id, v) == HGCD_OK && !std::memcmp(v, b.v, sizeof v), "velocity of %u", b.id.index);
        EXPECT(hgcd_body_get_user_data(m.w, b.id, &u) == HGCD_OK && u == b.user, "user data");
        int32_t type;
        uint32_t enabled;
        hgcd_filter f;
        EXPECT(hgcd_body_get_type(m.w, b.id, &type) == HGCD_OK && type == b.type, "type of %u", b.id.index);
        EXPECT(hgcd_body_get_enabled(m.w, b.id, &enabled) == HGCD_OK && enabled == uint32_t(b.enabled), "enabled");
        EXPECT(hgcd_body_get_filter(m.w, b.id, &f) == HGCD_OK && f.category_bits == b.filter.category_bits &&
                   f.mask_bits == b.filter.mask_bits && f.group_index == b.filter.group_index && f.reserved == 0,
               "filter of %u", b.id.index);
        double mg;
        EXPECT(hgcd_body_get_margin(m.w, b.id, &mg) == HGCD_OK && !std::memcmp(&mg, &b.margin, sizeof mg),
               "margin of %u", b.id.index);
        EXPECT(hgcd_body_get_mesh(m.w, b.id, &mid) == HGCD_OK && mid.index == m.meshes[b.mesh].id.index &&
                   mid.generation == m.meshes[b.mesh].id.generation,
               "body mesh");
    }
    {
        double wm;
        EXPECT(hgcd_world_get_contact_margin(m.w, &wm) == HGCD_OK && !std::memcmp(&wm, &m.desc.contact_margin, sizeof wm),
               "world margin");
    }
    {  // the same poses in one batch read, listed in reverse order
        std::vector<hgcd_body> ids;
        std::vector<const MBody *> of;
        for (auto b = m.bodies.rbegin(); b != m.bodies.rend(); ++b)
            if (b->live) {
                ids.push_back(b->id);
                of.push_back(&*b);
            }
        std::vector<double> p(3 * ids.size() + 3), q(4 * ids.size() + 4);
        EXPECT(hgcd_world_get_poses(m.w, ids.data(), ids.size(), p.data(), 0, q.data(), 0) == HGCD_OK, "get_poses");
        for (size_t k = 0; k < ids.size(); ++k)
            EXPECT(!std::memcmp(&p[3 * k], of[k]->p, sizeof of[k]->p) && !std::memcmp(&q[4 * k], of[k]->q, sizeof of[k]->q),
                   "get_poses: body %u differs", ids[k].index);
    }
    for (MMesh &mm : m.meshes) {
        hgcd_mesh_info info;
        info.struct_size = sizeof info;
        const hgcd_status s = hgcd_mesh_get_info(m.w, mm.id, &info);
        EXPECT(s == (mm.live ? HGCD_OK : HGCD_ERROR_STALE_ID), "mesh info status");
        EXPECT(hgcd_mesh_validate(m.w, mm.id) == (mm.live ? HGCD_OK : HGCD_ERROR_STALE_ID), "validate mesh {%u,%u}",
               mm.id.index, mm.id.generation);
        if (!mm.live) continue;
        EXPECT(info.body_count == mm.users, "mesh users %u != %u", info.body_count, mm.users);
        EXPECT(!std::memcmp(&info.center, &mm.info.center, sizeof info.center) && info.radius == mm.info.radius,
               "mesh info changed");
        EXPECT(info.reach == mm.reach, "mesh reach %.17g, the model's %.17g", info.reach, mm.reach);
    }
    if (m.detected) {  // the last tick's pairs stay until the next detect
        const hgcd_pair *got;
        size_t count;
        EXPECT(hgcd_world_pairs(m.w, &got, &count) == HGCD_OK, "pairs");
        EXPECT(count == m.last_pairs.size() && (!count || !std::memcmp(got, m.last_pairs.data(), count * sizeof *got)),
               "pairs changed without a detect");
    }
}

// The events of a tick: the difference between the last pairs and these,
// by full ids, sorted, with the user data the model gave each body (the
// model keeps destroyed bodies).
void check_events(const Model &m, const hgcd_pair *now, size_t count) {
    const hgcd_pair_event *ev[2];
    size_t n[2];
    EXPECT(hgcd_world_events(m.w, &ev[0], &n[0], &ev[1], &n[1]) == HGCD_OK, "events");
    const std::vector<hgcd_pair> before = m.detected ? m.last_pairs : std::vector<hgcd_pair>();
    const std::vector<hgcd_pair> after(now, now + count);
    const auto user = [&](hgcd_body id) {
        for (const MBody &b : m.bodies)
            if (b.id.index == id.index && b.id.generation == id.generation) return b.user;
        finding("event names a body never created");
    };
    for (int e = 0; e < 2; ++e) {  // began: in after, not in before; ended: the reverse
        const std::vector<hgcd_pair> &from = e ? before : after, &to = e ? after : before;
        size_t k = 0;
        for (const hgcd_pair &p : from) {
            if (std::any_of(to.begin(), to.end(), [&](const hgcd_pair &q) { return !std::memcmp(&p, &q, sizeof p); }))
                continue;
            EXPECT(k < n[e] && !std::memcmp(&ev[e][k].pair, &p, sizeof p), "%s event %zu of %zu: want {%u,%u}-{%u,%u} (%zu before, %zu after)", e ? "ended" : "began", k, n[e], p.a.index, p.a.generation, p.b.index, p.b.generation, before.size(), after.size());
            EXPECT(ev[e][k].user_data_a == user(p.a) && ev[e][k].user_data_b == user(p.b), "event user data");
            ++k;
        }
        EXPECT(k == n[e], "%s: %zu events, expected %zu", e ? "ended" : "began", n[e], k);
    }
}

void after_tick(Model &m, hgcd_status s, const char *what) {
    EXPECT(s == HGCD_OK, "%s: %s (%s)", what, hgcd_status_string(s), hgcd_world_last_error(m.w));
    check_pairs(m);
    const hgcd_pair *got;
    size_t count;
    hgcd_world_pairs(m.w, &got, &count);
    check_events(m, got, count);
    m.last_pairs.assign(got, got + count);
    m.detected = true;
    hgcd_stats st;
    st.struct_size = sizeof st;
    EXPECT(hgcd_world_stats(m.w, &st) == HGCD_OK, "stats");
    // (A detect where nothing moved makes no search: no candidates, and the
    // pairs it reports are all kept from the last one.)
    const bool searched = st.candidate_pairs > 0 || st.unmoved_pairs == 0;
    EXPECT(st.colliding_pairs == count && st.containment_pairs <= count &&
               (searched ? st.candidate_pairs >= count &&
                               st.narrow_tests + st.unmoved_pairs + st.filtered_pairs <= st.candidate_pairs
                         : st.unmoved_pairs == count && st.narrow_tests == 0),
           "stats inconsistent");
}

// Mesh facts computed independently of hgcd.
void check_mesh_info(const MMesh &mm) {
    const hgcd_mesh_info &i = mm.info;
    const uint32_t nv = uint32_t(mm.v.size() / 3), nt = uint32_t(mm.t.size() / 3);
    EXPECT(i.vertex_count == nv && i.triangle_count == nt, "mesh counts");
    EXPECT(i.closed == uint32_t(oracle_mesh_is_closed(mm.t.data(), nt)), "closed flag %u", i.closed);
    EXPECT(!i.convex || i.closed, "convex but not closed");
    uint32_t degenerate = 0;
    for (uint32_t t = 0; t < nt; ++t) {
        const double *a = &mm.v[3 * mm.t[3 * t]], *b = &mm.v[3 * mm.t[3 * t + 1]], *c = &mm.v[3 * mm.t[3 * t + 2]];
        bool zero = true;
        for (int k = 0; k < 3 && zero; ++k) {
            const double pa[2] = {a[k], a[(k + 1) % 3]}, pb[2] = {b[k], b[(k + 1) % 3]}, pc[2] = {c[k], c[(k + 1) % 3]};
            zero = oracle_orient2d(pa, pb, pc) == 0;
        }
        degenerate += zero;
    }
    EXPECT(i.degenerate_triangle_count == degenerate, "degenerate count %u != %u", i.degenerate_triangle_count, degenerate);
    std::vector<uint32_t> parent(nv);
    for (uint32_t k = 0; k < nv; ++k) parent[k] = k;
    auto root = [&](uint32_t x) {
        while (parent[x] != x) x = parent[x] = parent[parent[x]];
        return x;
    };
    std::vector<char> used(nv, 0);
    for (uint32_t t = 0; t < nt; ++t)
        for (int k = 0; k < 3; ++k) {
            used[mm.t[3 * t + k]] = 1;
            parent[root(mm.t[3 * t + k])] = root(mm.t[3 * t]);
        }
    uint32_t comps = 0;
    for (uint32_t k = 0; k < nv; ++k) comps += used[k] && root(k) == k;
    EXPECT(i.component_count == comps, "components %u != %u", i.component_count, comps);
    for (uint32_t k = 0; k < nv; ++k) {
        if (!used[k]) continue;
        double d2 = 0;
        for (int a = 0; a < 3; ++a) d2 += (mm.v[3 * k + a] - i.center[a]) * (mm.v[3 * k + a] - i.center[a]);
        EXPECT(std::sqrt(d2) <= i.radius * (1 + 1e-9) + 1e-300, "vertex %u beyond the radius", k);
    }
}

// --------------------------------------------------------------- calls --

void op_mesh_create(Input &in, Model &m) {
    const uint8_t kind = in.u8();
    MMesh mm;
    if (kind < 120) {
        const Shape &s = presets()[kind % presets().size()];
        mm.v = s.v;
        mm.t = s.t;
    } else {  // random small mesh, degenerate triangles and bad values included
        const uint32_t nv = in.u8() % 9, nt = in.u8() % 11;
        for (uint32_t k = 0; k < 3 * nv; ++k) {
            const uint8_t c = in.u8();
            mm.v.push_back(c < 240 ? double(int(c % 9) - 4) * 0.5 : kCoords[c % (sizeof kCoords / sizeof kCoords[0])]);
        }
        for (uint32_t k = 0; k < 3 * nt; ++k) {
            const uint8_t c = in.u8();
            mm.t.push_back(c < 250 ? (nv ? c % nv : 0) : nv + c % 3);
        }
    }
    hgcd_mesh_desc d = hgcd_mesh_desc_default();
    d.vertices = mm.v.empty() ? nullptr : mm.v.data();
    d.triangles = mm.t.empty() ? nullptr : mm.t.data();
    d.vertex_count = uint32_t(mm.v.size() / 3);
    d.triangle_count = uint32_t(mm.t.size() / 3);
    static const double dummy_v[3] = {0, 0, 0};
    static const uint32_t dummy_t[3] = {0, 0, 0};
    if (!d.vertices) d.vertices = dummy_v;  // counts decide the refusal, as documented
    if (!d.triangles) d.triangles = dummy_t;
    hgcd_status expect = HGCD_OK;
    const uint8_t corrupt = in.u8();
    const hgcd_mesh_desc *dp = &d;
    hgcd_mesh out{77, 77}, *outp = &out;
    switch (corrupt % 16) {
        case 0: d.struct_size ^= 4; expect = HGCD_ERROR_BAD_DESCRIPTOR; break;
        case 1: d.init_tag = 0; expect = HGCD_ERROR_BAD_DESCRIPTOR; break;
        case 2: dp = nullptr; expect = HGCD_ERROR_NULL_ARGUMENT; break;
        case 3: outp = nullptr; expect = HGCD_ERROR_NULL_ARGUMENT; break;
        case 4: d.vertices = nullptr; expect = HGCD_ERROR_NULL_ARGUMENT; break;
        case 5: d.triangles = nullptr; expect = HGCD_ERROR_NULL_ARGUMENT; break;
        case 6: d.triangle_count = (1u << 26) + 1 + in.u32() % 1000; expect = HGCD_ERROR_INVALID_MESH; break;
        case 7: d.vertex_count = (1u << 26) + 1; expect = HGCD_ERROR_INVALID_MESH; break;
        default: break;
    }
    if (expect == HGCD_OK) {
        if (d.triangle_count == 0 || d.vertex_count == 0) expect = HGCD_ERROR_INVALID_MESH;
        for (size_t k = 0; k + 2 < mm.v.size(); k += 3)
            if (!vertex_ok(&mm.v[k])) expect = HGCD_ERROR_INVALID_MESH;
        for (uint32_t x : mm.t)
            if (x >= d.vertex_count) expect = HGCD_ERROR_INVALID_MESH;
        if (expect == HGCD_OK && m.live_meshes >= kMaxLiveMeshes) return;  // keep the oracle cheap
    }
    const hgcd_status s = hgcd_mesh_create(m.w, dp, outp);
    EXPECT(s == expect, "mesh_create: %s, expected %s (%s)", hgcd_status_string(s), hgcd_status_string(expect),
           hgcd_world_last_error(m.w));
    if (s != HGCD_OK) {
        EXPECT(out.index == 77 && out.generation == 77, "refused mesh_create wrote out_mesh");
        EXPECT(hgcd_world_last_error(m.w)[0] != 0, "no message");
        return;
    }
    EXPECT(out.generation != 0, "null id");
    EXPECT(m.issued_meshes.insert({out.index, out.generation}).second, "mesh id {%u,%u} handed out twice", out.index,
           out.generation);
    mm.id = out;
    mm.live = true;
    for (uint32_t x : mm.t) mm.reach = std::max(mm.reach, vertex_norm(&mm.v[3 * size_t(x)]));
    mm.info.struct_size = sizeof mm.info;
    EXPECT(hgcd_mesh_get_info(m.w, out, &mm.info) == HGCD_OK, "info");
    check_mesh_info(mm);
    m.meshes.push_back(std::move(mm));
    ++m.live_meshes;
}

void op_mesh_destroy(Input &in, Model &m) {
    const hgcd_mesh id = pick_mesh_id(in, m);
    const int k = live_mesh_of(m, id);
    const hgcd_status expect = k < 0 ? HGCD_ERROR_STALE_ID : m.meshes[k].users ? HGCD_ERROR_MESH_IN_USE : HGCD_OK;
    const hgcd_status s = hgcd_mesh_destroy(m.w, id);
    EXPECT(s == expect, "mesh_destroy: %s, expected %s", hgcd_status_string(s), hgcd_status_string(expect));
    if (s == HGCD_OK) {
        m.meshes[k].live = false;
        --m.live_meshes;
    }
}

void op_body_create(Input &in, Model &m, const Ctx &cx) {
    hgcd_body_desc d = hgcd_body_desc_default();
    d.mesh = pick_mesh_id(in, m);
    for (int k = 0; k < 3; ++k) d.position[k] = coord(in, cx);
    quaternion(in, d.orientation);
    for (int k = 0; k < 3; ++k) {
        const uint8_t c = in.u8();
        d.velocity[k] = c < 128 ? 0 : kVel[c % (sizeof kVel / sizeof kVel[0])];
    }
    const uint8_t sc = in.u8();
    d.scale = sc < 128 ? 0.25 + double(sc % 16) * 0.125 : kScales[sc % (sizeof kScales / sizeof kScales[0])];
    if (cx.unit == 0 && sc < 128) d.scale *= 1e-9;  // tiny bodies far out
    d.user_data = in.u32();
    hgcd_status expect = HGCD_OK;
    const int mk = live_mesh_of(m, d.mesh);
    if (mk < 0) {
        expect = HGCD_ERROR_STALE_ID;
    } else if (!pose_ok(d.position, d.orientation)) {
        expect = HGCD_ERROR_INVALID_ARGUMENT;
    } else {
        for (int k = 0; k < 3; ++k)
            if (!std::isfinite(d.velocity[k])) expect = HGCD_ERROR_INVALID_ARGUMENT;
        const double reach = m.meshes[mk].reach;
        if (!std::isfinite(d.scale) || !(d.scale > 0) || d.scale * reach > 1e15) expect = HGCD_ERROR_INVALID_ARGUMENT;
    }
    const uint8_t corrupt = in.u8();
    if (corrupt / 20 >= 8) {  // (from the corruption byte: older inputs keep their bytes' meaning)
        d.margin = pick_margin(uint8_t(corrupt / 20 - 8));
        if (expect == HGCD_OK && !margin_ok(d.margin)) expect = HGCD_ERROR_INVALID_ARGUMENT;
    }
    const hgcd_body_desc *dp = &d;
    hgcd_body out{77, 77}, *outp = &out;
    switch (corrupt % 20) {
        case 0: d.struct_size = 0; expect = HGCD_ERROR_BAD_DESCRIPTOR; break;
        case 1: dp = nullptr; expect = HGCD_ERROR_NULL_ARGUMENT; break;
        case 2: outp = nullptr; expect = HGCD_ERROR_NULL_ARGUMENT; break;
        default: break;
    }
    if (expect == HGCD_OK && m.live_bodies >= kMaxLiveBodies) return;
    const hgcd_status s = hgcd_body_create(m.w, dp, outp);
    EXPECT(s == expect, "body_create: %s, expected %s (%s)", hgcd_status_string(s), hgcd_status_string(expect),
           hgcd_world_last_error(m.w));
    if (s != HGCD_OK) {
        EXPECT(out.index == 77 && out.generation == 77, "refused body_create wrote out_body");
        return;
    }
    EXPECT(out.generation != 0, "null id");
    EXPECT(m.issued_bodies.insert({out.index, out.generation}).second, "body id {%u,%u} handed out twice", out.index,
           out.generation);
    for (const MBody &b : m.bodies) EXPECT(!b.live || b.id.index != out.index, "index %u of a live body reused", out.index);
    MBody b;
    b.id = out;
    b.live = true;
    b.mesh = size_t(mk);
    std::memcpy(b.p, d.position, sizeof b.p);
    std::memcpy(b.q, d.orientation, sizeof b.q);
    std::memcpy(b.v, d.velocity, sizeof b.v);
    b.s = d.scale;
    b.user = d.user_data;
    b.margin = d.margin;
    m.bodies.push_back(b);
    ++m.meshes[mk].users;
    ++m.live_bodies;
}

void op_body_destroy(Input &in, Model &m) {
    const hgcd_body id = pick_body_id(in, m);
    const int k = live_body_of(m, id);
    const hgcd_status s = hgcd_body_destroy(m.w, id);
    EXPECT(s == (k < 0 ? HGCD_ERROR_STALE_ID : HGCD_OK), "body_destroy: %s", hgcd_status_string(s));
    if (s == HGCD_OK) {
        m.bodies[k].live = false;
        --m.meshes[m.bodies[k].mesh].users;
        --m.live_bodies;
        for (auto it = m.excluded.begin(); it != m.excluded.end();)  // (its exclusions die with it)
            it = it->first == id.index || it->second == id.index ? m.excluded.erase(it) : std::next(it);
    }
}

// Body types, enabling, filters and excluded pairs: set (good and bad
// values, any id), then read back by check_state.
void op_filtering(Input &in, Model &m) {
    const hgcd_body id = pick_body_id(in, m);
    const int k = live_body_of(m, id);
    const uint8_t what = in.u8();
    hgcd_status s, expect = k < 0 ? HGCD_ERROR_STALE_ID : HGCD_OK;
    switch (what % 6) {
        case 5: {  // a contact margin: the body's, or (one in eight) the world's
            const uint8_t pick = in.u8();
            const double mg = pick_margin(pick);
            if (pick >= 0xE0) {
                expect = margin_ok(mg) ? HGCD_OK : HGCD_ERROR_INVALID_ARGUMENT;
                s = hgcd_world_set_contact_margin(m.w, mg);
                if (s == HGCD_OK) m.desc.contact_margin = mg;
                break;
            }
            if (expect == HGCD_OK && !margin_ok(mg)) expect = HGCD_ERROR_INVALID_ARGUMENT;
            s = hgcd_body_set_margin(m.w, id, mg);
            if (s == HGCD_OK) m.bodies[k].margin = mg;
            break;
        }
        case 0: {
            const int32_t type = int32_t(in.u8() % 4) - (in.u8() % 16 == 0 ? 5 : 0);  // 3 and negatives: refused
            if (expect == HGCD_OK && (type < 0 || type > 2)) expect = HGCD_ERROR_INVALID_ARGUMENT;
            s = hgcd_body_set_type(m.w, id, type);
            if (s == HGCD_OK) m.bodies[k].type = type;
            break;
        }
        case 1: {
            const uint32_t on = in.u8() % 3 ? 1 : in.u8() % 2 ? 0 : 0x100;
            s = hgcd_body_set_enabled(m.w, id, on);
            if (s == HGCD_OK) m.bodies[k].enabled = on != 0;
            break;
        }
        case 2: {
            hgcd_filter f = hgcd_filter_default();
            const uint8_t c = in.u8();
            f.category_bits = uint64_t(1) << (c % 3) | (c & 0x80 ? uint64_t(1) << 63 : 0);
            f.mask_bits = c & 0x40 ? ~uint64_t(0) : uint64_t(in.u8()) | uint64_t(in.u8()) << 56;
            f.group_index = int32_t(in.u8() % 5) - 2;
            f.reserved = in.u8() % 32 == 0 ? 1 : 0;
            const bool null = in.u8() % 32 == 0;
            if (null) expect = HGCD_ERROR_NULL_ARGUMENT;
            else if (expect == HGCD_OK && f.reserved) expect = HGCD_ERROR_INVALID_ARGUMENT;
            s = hgcd_body_set_filter(m.w, id, null ? nullptr : &f);
            if (s == HGCD_OK) m.bodies[k].filter = f;
            break;
        }
        default: {  // exclude (3) or include (4) a pair
            const hgcd_body other = pick_body_id(in, m);
            const int j = live_body_of(m, other);
            if (expect == HGCD_OK && j < 0) expect = HGCD_ERROR_STALE_ID;
            if (expect == HGCD_OK && j == k) expect = HGCD_ERROR_INVALID_ARGUMENT;
            const bool exclude = what % 6 == 3;
            s = exclude ? hgcd_world_exclude_pair(m.w, id, other) : hgcd_world_include_pair(m.w, id, other);
            uint32_t got = 7;
            const hgcd_status q = hgcd_world_pair_excluded(m.w, id, other, &got);
            EXPECT(q == expect, "pair_excluded: %s, expected %s", hgcd_status_string(q), hgcd_status_string(expect));
            if (s == HGCD_OK) {
                const std::pair<uint32_t, uint32_t> key{std::min(id.index, other.index), std::max(id.index, other.index)};
                if (exclude) m.excluded.insert(key);
                else m.excluded.erase(key);
                EXPECT(got == uint32_t(exclude), "pair_excluded says %u", got);
            }
            break;
        }
    }
    EXPECT(s == expect, "filtering call %u: %s, expected %s (%s)", what % 6, hgcd_status_string(s),
           hgcd_status_string(expect), hgcd_world_last_error(m.w));
}

void op_set_pose(Input &in, Model &m, const Ctx &cx) {
    const hgcd_body id = pick_body_id(in, m);
    double p[3], q[4];
    for (int k = 0; k < 3; ++k) p[k] = coord(in, cx);
    quaternion(in, q);
    const uint8_t which = in.u8() % 4;
    const double *pp = which & 1 ? nullptr : p, *qp = which & 2 ? nullptr : q;
    const int k = live_body_of(m, id);
    const hgcd_status expect = k < 0 ? HGCD_ERROR_STALE_ID : pose_ok(pp, qp) ? HGCD_OK : HGCD_ERROR_INVALID_ARGUMENT;
    const hgcd_status s = hgcd_body_set_pose(m.w, id, pp, qp);
    EXPECT(s == expect, "set_pose: %s, expected %s", hgcd_status_string(s), hgcd_status_string(expect));
    if (s == HGCD_OK) {
        if (pp) std::memcpy(m.bodies[k].p, p, sizeof p);
        if (qp) std::memcpy(m.bodies[k].q, q, sizeof q);
    }
}

void op_set_velocity(Input &in, Model &m) {
    const hgcd_body id = pick_body_id(in, m);
    double v[3];
    for (int k = 0; k < 3; ++k) v[k] = kVel[in.u8() % (sizeof kVel / sizeof kVel[0])];
    const bool null = in.u8() % 16 == 0;
    const int k = live_body_of(m, id);
    hgcd_status expect = null ? HGCD_ERROR_NULL_ARGUMENT : k < 0 ? HGCD_ERROR_STALE_ID : HGCD_OK;
    if (expect == HGCD_OK)
        for (int a = 0; a < 3; ++a)
            if (!std::isfinite(v[a])) expect = HGCD_ERROR_INVALID_ARGUMENT;
    const hgcd_status s = hgcd_body_set_velocity(m.w, id, null ? nullptr : v);
    EXPECT(s == expect, "set_velocity: %s, expected %s", hgcd_status_string(s), hgcd_status_string(expect));
    if (s == HGCD_OK) std::memcpy(m.bodies[k].v, v, sizeof v);
}

// ------------------------------------------------------------- batches --
// hgcd_world_set_poses, hgcd_world_set_velocities, hgcd_world_get_poses: ids
// listed (live in a shuffled order, with stale, forged, random or repeated
// ones mixed in) or NULL (indices 0 .. count-1); strides good and bad; arrays
// of their own or interleaved as a caller's struct would be.

// Mostly good strides (0 = packed, the entry, a struct's size), sometimes bad
// ones (not a multiple of 8, or short of the entry: 24 is short for a
// quaternion).
size_t pick_stride(Input &in) {
    static const size_t good[] = {0, 0, 0, 0, 0, 24, 32, 56, 64, 96, 40};
    static const size_t bad[] = {4, 8, 12, 16, 25, 31};
    const uint8_t k = in.u8();
    return k < 240 ? good[k % 11] : bad[k % 6];
}

bool stride_ok(size_t stride, size_t doubles) {
    return stride == 0 || (stride % sizeof(double) == 0 && stride >= doubles * sizeof(double));
}

// One array argument: entries of `doubles` doubles at `offset + k * step()`
// in `bytes` (which another array may share); `base` is NULL when absent.
struct Strided {
    std::vector<unsigned char> *bytes = nullptr;
    size_t offset = 0, stride = 0, doubles = 0;
    unsigned char *base = nullptr;
    size_t step() const { return stride ? stride : doubles * sizeof(double); }
    void put(size_t k, const double *v) { std::memcpy(base + k * step(), v, doubles * sizeof(double)); }
};

// Lays out `count` entries of a and b (b may be absent: doubles 0): in one
// buffer as fields of a struct when asked and both strides are 56, else in
// a buffer each. Every byte starts as 0xAB, so stray writes show.
void lay_out(size_t count, bool interleave, bool a_present, bool b_present, Strided &a, Strided &b,
             std::vector<unsigned char> &bytes_a, std::vector<unsigned char> &bytes_b) {
    const auto size = [&](const Strided &s) { return count * std::max(s.step(), s.doubles * sizeof(double)) + 64; };
    if (interleave && a_present && b_present && a.stride == 56 && b.stride == 56) {
        bytes_a.assign(count * 56 + 64, 0xAB);
        a.bytes = b.bytes = &bytes_a;
        b.offset = a.doubles * sizeof(double);
    } else {
        bytes_a.assign(size(a), 0xAB);
        bytes_b.assign(b.doubles ? size(b) : 0, 0xAB);
        a.bytes = &bytes_a;
        b.bytes = &bytes_b;
    }
    if (a_present) a.base = a.bytes->data() + a.offset;
    if (b_present) b.base = b.bytes->data() + b.offset;
}

// Distinct live bodies in a shuffled order, mostly all of them, else a count
// up to 2 past them (so stale, forged, random or repeated ids follow);
// sometimes an entry replaced.
std::vector<hgcd_body> pick_batch_ids(Input &in, const Model &m) {
    std::vector<hgcd_body> live;
    for (const MBody &b : m.bodies)
        if (b.live) live.push_back(b.id);
    for (size_t k = live.size(); k > 1; --k) std::swap(live[k - 1], live[in.u8() % k]);
    const uint8_t c = in.u8();
    const size_t count = c < 160 ? live.size() : c % (live.size() + 3);
    std::vector<hgcd_body> ids;
    for (size_t k = 0; k < count; ++k) ids.push_back(k < live.size() ? live[k] : pick_body_id(in, m));
    for (int r = 0; r < 3 && !ids.empty(); ++r) {
        const uint8_t c = in.u8();
        if (c % 4) break;
        const size_t j = in.u8() % ids.size();
        ids[j] = c & 4 && j ? ids[in.u8() % j] : pick_body_id(in, m);  // a repeat, or any id
    }
    return ids;
}

int live_body_at_index(const Model &m, size_t index) {
    for (size_t i = 0; i < m.bodies.size(); ++i)
        if (m.bodies[i].live && m.bodies[i].id.index == index) return int(i);
    return -1;
}

// The body indices in use (the world's slots): one past the largest index
// ever handed out.
size_t body_slots(const Model &m) {
    size_t n = 0;
    for (const MBody &b : m.bodies) n = std::max(n, size_t(b.id.index) + 1);
    return n;
}

// The first k < count for which bad(k), or -1.
template <class Bad>
long first_entry(size_t count, Bad &&bad) {
    for (size_t k = 0; k < count; ++k)
        if (bad(k)) return long(k);
    return -1;
}

// Whether a message names entry k ("entry 12" but not "entry 123").
bool names_entry(const char *msg, long k) {
    char needle[32];
    std::snprintf(needle, sizeof needle, "entry %ld", k);
    for (const char *at = std::strstr(msg, needle); at; at = std::strstr(at + 1, needle)) {
        const char next = at[std::strlen(needle)];
        if (next < '0' || next > '9') return true;
    }
    return false;
}

enum class BatchCall { kSetPoses, kSetVelocities, kGetPoses };

void op_batch(Input &in, Model &m, const Ctx &cx) {
    const uint8_t c = in.u8() % 8;
    const BatchCall call = c < 4 ? BatchCall::kSetPoses : c < 6 ? BatchCall::kSetVelocities : BatchCall::kGetPoses;
    const uint8_t flags = in.u8(), rare = in.u8(), arrays = in.u8() % 8;
    const bool by_index = (flags & 3) == 0 || rare % 64 == 62, clean = (flags >> 2) & 3, interleave = (flags >> 4) & 1;
    const bool null_world = rare % 64 == 63, huge = rare % 64 == 62;
    // Poses: positions (a) and orientations (b); velocities: a only.
    const bool poses = call != BatchCall::kSetVelocities;
    const bool a_present = poses ? arrays != 6 && arrays != 7 : arrays != 7;
    const bool b_present = poses && arrays != 5 && arrays != 7;
    Strided a, b;
    a.doubles = 3;
    b.doubles = poses ? 4 : 0;
    a.stride = pick_stride(in);
    if (poses) b.stride = pick_stride(in);

    std::vector<hgcd_body> ids;
    size_t count;
    const size_t slots = body_slots(m);
    if (by_index) {
        const uint8_t n = in.u8();
        count = huge ? (size_t(1) << 40) + rare : n < 160 ? slots : n % (slots + 2);
    } else {
        ids = pick_batch_ids(in, m);
        count = ids.size();
    }
    const size_t stored = huge ? 0 : count;  // a huge count must be refused unread
    std::vector<unsigned char> bytes_a, bytes_b;
    lay_out(stored, interleave, a_present, b_present, a, b, bytes_a, bytes_b);

    // The values (what set reads), clean ones mostly valid, then maybe one
    // entry given a table value.
    std::vector<double> va(3 * stored), vb(4 * stored);
    if (call == BatchCall::kSetPoses) {
        for (size_t k = 0; k < stored; ++k) {
            for (int x = 0; x < 3; ++x) va[3 * k + x] = coord(in, cx, clean);
            quaternion(in, &vb[4 * k], clean);
        }
        if (stored && in.u8() % 3 == 0) {
            const size_t j = in.u8() % stored;
            if (in.u8() % 2) va[3 * j + in.u8() % 3] = kCoords[in.u8() % (sizeof kCoords / sizeof kCoords[0])];
            else quaternion(in, &vb[4 * j]);
        }
    } else if (call == BatchCall::kSetVelocities) {
        for (size_t k = 0; k < 3 * stored; ++k) {
            const uint8_t v = in.u8();
            va[k] = clean && v < 240 ? 0.25 * (int(v % 9) - 4) : kVel[v % (sizeof kVel / sizeof kVel[0])];
        }
    }
    if (call != BatchCall::kGetPoses)
        for (size_t k = 0; k < stored; ++k) {
            if (a.base) a.put(k, &va[3 * k]);
            if (b.base) b.put(k, &vb[4 * k]);
        }
    const std::vector<unsigned char> before_a = bytes_a, before_b = bytes_b;

    // The model's verdict, in the order of hgcd.h and src/world/batch.cpp:
    // NULL pointers, strides, ids (stale before repeated), values.
    const hgcd_body *idp = by_index ? nullptr : ids.data();
    const auto body_of = [&](size_t k) { return by_index ? live_body_at_index(m, k) : live_body_of(m, ids[k]); };
    hgcd_status expect = HGCD_OK;
    BatchVerdict verdict = kApplied;
    long entry = -1;  // the entry the message must name
    if (null_world || (!a.base && !b.base)) {
        expect = HGCD_ERROR_NULL_ARGUMENT;
        verdict = kNullArray;
    } else if (!stride_ok(a.stride, a.doubles) || (poses && !stride_ok(b.stride, b.doubles))) {
        expect = HGCD_ERROR_INVALID_ARGUMENT;
        verdict = kBadStride;
    } else if (by_index && count > slots) {  // the message says so, naming no entry
        expect = HGCD_ERROR_STALE_ID;
        verdict = kCountPastSlots;
    } else if ((entry = first_entry(count, [&](size_t k) { return body_of(k) < 0; })) >= 0) {
        expect = HGCD_ERROR_STALE_ID;
        verdict = kStaleEntry;
    } else if (call != BatchCall::kGetPoses &&
               (entry = first_entry(count, [&](size_t k) {
                    return !by_index && first_entry(k, [&](size_t j) { return ids[j].index == ids[k].index; }) >= 0;
                })) >= 0) {
        expect = HGCD_ERROR_INVALID_ARGUMENT;
        verdict = kRepeatedEntry;
    } else if (call == BatchCall::kSetPoses &&
               (entry = first_entry(count, [&](size_t k) {
                    return !pose_ok(a.base ? &va[3 * k] : nullptr, b.base ? &vb[4 * k] : nullptr);
                })) >= 0) {
        expect = HGCD_ERROR_INVALID_ARGUMENT;
        verdict = kBadValue;
    } else if (call == BatchCall::kSetVelocities &&
               (entry = first_entry(count, [&](size_t k) {
                    return !(std::isfinite(va[3 * k]) && std::isfinite(va[3 * k + 1]) && std::isfinite(va[3 * k + 2]));
                })) >= 0) {
        expect = HGCD_ERROR_INVALID_ARGUMENT;
        verdict = kBadValue;
    }

    hgcd_world *w = null_world ? nullptr : m.w;
    const std::string message_before = hgcd_world_last_error(m.w);
    hgcd_status s;
    const char *what;
    switch (call) {
        case BatchCall::kSetPoses:
            what = "world_set_poses";
            s = hgcd_world_set_poses(w, idp, count, reinterpret_cast<const double *>(a.base), a.stride,
                                     reinterpret_cast<const double *>(b.base), b.stride);
            break;
        case BatchCall::kSetVelocities:
            what = "world_set_velocities";
            s = hgcd_world_set_velocities(w, idp, count, reinterpret_cast<const double *>(a.base), a.stride);
            break;
        default:
            what = "world_get_poses";
            s = hgcd_world_get_poses(w, idp, count, reinterpret_cast<double *>(a.base), a.stride,
                                     reinterpret_cast<double *>(b.base), b.stride);
            break;
    }
    ++g_batch[int(call)][verdict];
    if (verdict == kApplied) g_batch_entries[int(call)] += long(count);
    EXPECT(s == expect, "%s (%s, count %zu, strides %zu %zu): %s, expected %s (%s)", what,
           by_index ? "by index" : "ids", count, a.stride, b.stride, hgcd_status_string(s), hgcd_status_string(expect),
           hgcd_world_last_error(m.w));

    if (call == BatchCall::kGetPoses) {
        EXPECT(message_before == hgcd_world_last_error(m.w), "get_poses recorded a message");
        std::vector<unsigned char> want_a = before_a, want_b = before_b;
        if (s == HGCD_OK)
            for (size_t k = 0; k < count; ++k) {
                const MBody &body = m.bodies[size_t(body_of(k))];
                if (a.base) std::memcpy((a.bytes == &bytes_a ? want_a : want_b).data() + a.offset + k * a.step(), body.p, sizeof body.p);
                if (b.base) std::memcpy((b.bytes == &bytes_a ? want_a : want_b).data() + b.offset + k * b.step(), body.q, sizeof body.q);
            }
        EXPECT(bytes_a == want_a && bytes_b == want_b, "get_poses: the outputs differ from the model (%s)",
               s == HGCD_OK ? "wrong value or a byte between entries written" : "written when refusing");
        return;
    }
    EXPECT(bytes_a == before_a && bytes_b == before_b, "%s wrote into its input", what);
    if (s != HGCD_OK) {
        if (null_world) return;
        const char *msg = hgcd_world_last_error(m.w);
        EXPECT(std::strncmp(msg, what, std::strlen(what)) == 0, "%s: message \"%s\"", what, msg);
        EXPECT(verdict != kCountPastSlots || std::strstr(msg, "exceeds"), "%s: message \"%s\" (count %zu > %zu slots)", what, msg, count, slots);
        EXPECT(entry < 0 || names_entry(msg, entry), "%s: message \"%s\" should name entry %ld", what, msg, entry);
        return;
    }
    for (size_t k = 0; k < count; ++k) {
        MBody &body = m.bodies[size_t(body_of(k))];
        if (call == BatchCall::kSetVelocities) {
            std::memcpy(body.v, &va[3 * k], sizeof body.v);
            continue;
        }
        if (a.base) std::memcpy(body.p, &va[3 * k], sizeof body.p);
        if (b.base) std::memcpy(body.q, &vb[4 * k], sizeof body.q);
    }
}

void op_step(Model &m) {
    // The model's motion: hgcd.h's rule, evaluated the same way.
    const double dt = m.desc.time_step;
    bool bad = false;
    // (Static and disabled bodies do not move, and their moves are not checked.)
    const auto moves = [](const MBody &b) { return b.live && b.enabled && b.type != HGCD_BODY_STATIC; };
    for (const MBody &b : m.bodies)
        if (moves(b))
            for (int k = 0; k < 3; ++k)
                if (!finite_in_range(b.p[k] + b.v[k] * dt)) bad = true;
    if (bad && !m.desc.reflect_at_bounds) {
        const hgcd_status s = hgcd_world_step(m.w);
        EXPECT(s == HGCD_ERROR_INVALID_ARGUMENT, "step should be refused: %s", hgcd_status_string(s));
        return;
    }
    for (MBody &b : m.bodies) {
        if (!moves(b)) continue;
        for (int k = 0; k < 3; ++k) {
            double x = b.p[k] + b.v[k] * dt;
            if (m.desc.reflect_at_bounds) {
                const double lo = m.desc.bounds_min[k], hi = m.desc.bounds_max[k];
                if (x < lo) {
                    x = 2 * lo - x;
                    b.v[k] = -b.v[k];
                } else if (x > hi) {
                    x = 2 * hi - x;
                    b.v[k] = -b.v[k];
                }
                x = std::min(std::max(x, lo), hi);
            }
            b.p[k] = x;
        }
    }
    after_tick(m, hgcd_world_step(m.w), "step");
}

// A point, box or ray query against the oracle over every live body (its
// inputs from the same grid as the bodies, so they touch them exactly, or
// from the table of odd values, which must be refused).
long g_queries = 0, g_query_answers = 0;
void op_query(Input &in, Model &m, const Ctx &cx) {
    // Live, enabled bodies in slot order (a disabled body is in no query's
    // answer; these queries pass no filter).
    std::vector<std::pair<uint32_t, size_t>> order;
    for (size_t i = 0; i < m.bodies.size(); ++i)
        if (m.bodies[i].live && m.bodies[i].enabled) order.push_back({m.bodies[i].id.index, i});
    std::sort(order.begin(), order.end());
    std::vector<std::vector<double>> world(order.size());
    std::vector<oracle_solid> solids(order.size());
    for (size_t k = 0; k < order.size(); ++k) {
        const MBody &b = m.bodies[order[k].second];
        const MMesh &mm = m.meshes[b.mesh];
        const uint32_t nv = uint32_t(mm.v.size() / 3);
        world[k].resize(3 * size_t(nv));
        for (uint32_t v = 0; v < nv; ++v) oracle_world_vertex(b.p, b.q, b.s, &mm.v[3 * v], &world[k][3 * v]);
        solids[k] = oracle_solid{world[k].data(), nv, mm.t.data(), uint32_t(mm.t.size() / 3)};
    }
    const uint8_t kind = in.u8() % 3;
    const bool clean = (in.u8() & 3) != 0;
    ++g_queries;
    if (kind < 2) {
        double box[6];
        for (int k = 0; k < 3; ++k) box[k] = coord(in, cx, clean);
        for (int k = 0; k < 3; ++k) box[3 + k] = kind == 0 ? box[k] : coord(in, cx, clean);
        bool valid = true;
        for (int k = 0; k < 3; ++k) {
            if (kind == 1 && box[k] > box[3 + k]) std::swap(box[k], box[3 + k]);
            valid = valid && finite_in_range(box[k]) && finite_in_range(box[3 + k]) && box[k] <= box[3 + k];
        }
        hgcd_query_results res;
        const hgcd_status s = kind == 0 ? hgcd_world_query_point(m.w, box, 1, 0, nullptr, &res)
                                        : hgcd_world_query_box(m.w, box, 1, 0, nullptr, &res);
        if (!valid) {
            EXPECT(s == HGCD_ERROR_INVALID_ARGUMENT, "query of a bad %s: %s", kind ? "box" : "point", hgcd_status_string(s));
            return;
        }
        EXPECT(s == HGCD_OK, "query: %s", hgcd_status_string(s));
        EXPECT(res.query_count == 1 && res.offsets[0] == 0 && res.offsets[1] == res.body_count, "query offsets");
        size_t at = 0;
        for (size_t k = 0; k < order.size(); ++k) {
            const oracle_solid &o = solids[k];
            const int want = kind == 0 ? oracle_point_in_solid(box, o.wv, o.vertex_count, o.tris, o.tri_count)
                                       : oracle_box_meets_solid(box, box + 3, o.wv, o.vertex_count, o.tris, o.tri_count);
            const int have = at < res.body_count && res.bodies[at].index == order[k].first;
            EXPECT(want == have, "%s query: body %u oracle %d hgcd %d", kind ? "box" : "point", order[k].first, want, have);
            if (have) {
                EXPECT(res.bodies[at].generation == m.bodies[order[k].second].id.generation, "query generation");
                ++at;
            }
            g_query_answers += want;
        }
        EXPECT(at == res.body_count, "query: bodies not live");
        return;
    }
    hgcd_ray ray;
    for (int k = 0; k < 3; ++k) {
        ray.origin[k] = coord(in, cx, clean);
        ray.direction[k] = double(int(in.u8() % 5) - 2);
    }
    ray.max_distance = double(in.u8() % 8) * (cx.unit == 0 ? 1 : cx.unit);
    if (!clean && (in.u8() & 1)) ray.max_distance = kCoords[in.u8() % (sizeof kCoords / sizeof kCoords[0])];
    double e[3];
    bool valid = std::isfinite(ray.max_distance) && ray.max_distance >= 0 &&
                 (ray.direction[0] != 0 || ray.direction[1] != 0 || ray.direction[2] != 0);
    for (int k = 0; k < 3; ++k) {
        e[k] = ray.origin[k] + ray.max_distance * ray.direction[k];
        valid = valid && finite_in_range(ray.origin[k]) && finite_in_range(e[k]);
    }
    hgcd_ray_hit hit;
    const hgcd_status s = hgcd_world_cast_rays(m.w, &ray, 1, 0, HGCD_RAY_CLOSEST, nullptr, &hit);
    if (!valid) {
        EXPECT(s == HGCD_ERROR_INVALID_ARGUMENT, "bad ray: %s", hgcd_status_string(s));
        return;
    }
    EXPECT(s == HGCD_OK, "ray: %s", hgcd_status_string(s));
    uint32_t body = 0, tri = 0;
    int inside = 0;
    double t = 0;
    const int want = oracle_ray_closest(ray.origin, e, solids.data(), uint32_t(solids.size()), &body, &tri, &inside, &t);
    EXPECT(want == (hit.body.generation != 0), "ray hit: oracle %d", want);
    if (want) {
        EXPECT(hit.body.index == order[body].first && hit.triangle == tri && hit.inside == uint32_t(inside),
               "ray: oracle body %u tri %u inside %d, hgcd %u %u %u", order[body].first, tri, inside, hit.body.index,
               hit.triangle, hit.inside);
        const double d = ray.max_distance * t;
        EXPECT(std::fabs(hit.distance - d) <= 0x1p-39 * std::fabs(d) + 1e-300, "ray distance %.17g vs %.17g",
               hit.distance, d);
        ++g_query_answers;
    }
}

void op_read(Input &in, Model &m) {
    const uint8_t k = in.u8() % 8;
    size_t total = 12345;
    if (k == 0) {  // copy_pairs with a random capacity
        const size_t cap = in.u8() % 6;
        std::vector<hgcd_pair> buf(cap + 1);
        std::memset(buf.data(), 0xAB, buf.size() * sizeof(hgcd_pair));
        EXPECT(hgcd_world_copy_pairs(m.w, cap ? buf.data() : nullptr, cap, &total) == HGCD_OK, "copy_pairs");
        const size_t expect = m.detected ? m.last_pairs.size() : 0;
        EXPECT(total == expect, "copy_pairs total");
        const size_t n = std::min(cap, total);
        EXPECT(!n || !std::memcmp(buf.data(), m.last_pairs.data(), n * sizeof(hgcd_pair)), "copy_pairs content");
        uint8_t after[sizeof(hgcd_pair)];
        std::memcpy(after, &buf[n], sizeof after);
        for (uint8_t x : after) EXPECT(x == 0xAB, "copy_pairs wrote past the count");
    } else if (k == 1) {
        EXPECT(hgcd_world_copy_pairs(m.w, nullptr, 1 + in.u8(), &total) == HGCD_ERROR_NULL_ARGUMENT, "copy_pairs NULL");
    } else if (k == 2) {  // stats with any struct_size
        unsigned char buf[sizeof(hgcd_stats) + 16];
        std::memset(buf, 0xCD, sizeof buf);
        const uint32_t size = in.u8() % 2 ? uint32_t(sizeof(hgcd_stats)) : in.u8();
        std::memcpy(buf, &size, 4);
        const hgcd_status s = hgcd_world_stats(m.w, reinterpret_cast<hgcd_stats *>(buf));
        const size_t eff = size ? size : sizeof(hgcd_stats);
        EXPECT(s == (eff < 8 ? HGCD_ERROR_BAD_DESCRIPTOR : HGCD_OK), "stats size %u", size);
        for (size_t x = std::max<size_t>(std::min(eff, sizeof(hgcd_stats)), 4); x < sizeof buf; ++x)
            EXPECT(buf[x] == 0xCD, "stats wrote past struct_size");
    } else if (k == 3) {  // mesh info with any struct_size
        const hgcd_mesh id = pick_mesh_id(in, m);
        unsigned char buf[sizeof(hgcd_mesh_info) + 16];
        std::memset(buf, 0xCD, sizeof buf);
        const uint32_t size = in.u8() % 2 ? uint32_t(sizeof(hgcd_mesh_info)) : in.u8();
        std::memcpy(buf, &size, 4);
        const hgcd_status s = hgcd_mesh_get_info(m.w, id, reinterpret_cast<hgcd_mesh_info *>(buf));
        const size_t eff = size ? size : sizeof(hgcd_mesh_info);
        const hgcd_status expect = eff < 8 ? HGCD_ERROR_BAD_DESCRIPTOR
                                   : live_mesh_of(m, id) < 0 ? HGCD_ERROR_STALE_ID : HGCD_OK;
        EXPECT(s == expect, "mesh_get_info: %s expected %s", hgcd_status_string(s), hgcd_status_string(expect));
        EXPECT(hgcd_mesh_validate(m.w, id) == (live_mesh_of(m, id) < 0 ? HGCD_ERROR_STALE_ID : HGCD_OK),
               "validate mesh {%u,%u}", id.index, id.generation);
        for (size_t x = std::max<size_t>(std::min(eff, sizeof(hgcd_mesh_info)), 4); x < sizeof buf; ++x)
            EXPECT(buf[x] == 0xCD, "mesh_get_info wrote past struct_size (or wrote when refusing)");
    } else if (k == 4) {  // getters on any id, NULL outputs
        const hgcd_body id = pick_body_id(in, m);
        const bool live = live_body_of(m, id) >= 0;
        double p[3], q[4];
        hgcd_mesh mm;
        uint64_t u;
        EXPECT(hgcd_body_get_pose(m.w, id, in.u8() % 2 ? p : nullptr, in.u8() % 2 ? q : nullptr) ==
                   (live ? HGCD_OK : HGCD_ERROR_STALE_ID),
               "get_pose");
        EXPECT(hgcd_body_get_velocity(m.w, id, nullptr) == HGCD_ERROR_NULL_ARGUMENT, "get_velocity NULL");
        EXPECT(hgcd_body_get_mesh(m.w, id, &mm) == (live ? HGCD_OK : HGCD_ERROR_STALE_ID), "get_mesh");
        EXPECT(hgcd_body_get_user_data(m.w, id, &u) == (live ? HGCD_OK : HGCD_ERROR_STALE_ID), "get_user_data");
    } else if (k == 5) {
        const uint32_t t = in.u8() % 2 ? in.u8() % 4 : 4090 + in.u8() % 12;
        const hgcd_status s = hgcd_world_set_thread_count(m.w, t);
        const bool refused = t > 4096 || (t == 0 && m.desc.enqueue_task);  // (0 workers with a task system)
        EXPECT(s == (refused ? HGCD_ERROR_INVALID_ARGUMENT : HGCD_OK), "set_thread_count %u", t);
        if (s == HGCD_OK && (t == 0 || t > 2)) hgcd_world_set_thread_count(m.w, 1 + t % 2);  // keep runs cheap
        // The thread policy: either valid one (the pairs never depend on it), or a bad value refused.
        const int32_t policy = int32_t(in.u8() % 4) - 1;
        const bool valid = policy == HGCD_THREADS_ADAPTIVE || policy == HGCD_THREADS_FIXED;
        EXPECT(hgcd_world_set_thread_policy(m.w, policy) == (valid ? HGCD_OK : HGCD_ERROR_INVALID_ARGUMENT),
               "set_thread_policy %d", int(policy));
    } else {
        const hgcd_pair *p;
        size_t n;
        EXPECT(hgcd_world_pairs(m.w, &p, nullptr) == HGCD_ERROR_NULL_ARGUMENT, "pairs NULL count");
        EXPECT(hgcd_world_pairs(m.w, nullptr, &n) == HGCD_ERROR_NULL_ARGUMENT, "pairs NULL out");
    }
}

// A task system that runs each loop inline, its second half first, as the
// last worker, then its first half as worker 0 (hgcd_world_desc.enqueue_task).
uint32_t task_workers = 1;
void *enqueue_inline(hgcd_task_fn *task, uint32_t count, uint32_t min_range, void *task_context, void *) {
    const uint32_t half = std::max(min_range, count / 2) < count ? std::max(min_range, count / 2) : count;
    if (half < count) task(half, count, task_workers - 1, task_context);
    task(0, half, 0, task_context);
    return nullptr;
}
void finish_never(void *, void *) { std::abort(); }  // (enqueue_inline returns NULL)

bool make_world(Input &in, Model &m, Ctx &cx) {
    hgcd_world_desc d = hgcd_world_desc_default();
    const uint8_t a = in.u8(), b = in.u8(), c = in.u8();
    d.thread_count = 1 + (a & 1);
    d.reflect_at_bounds = (a >> 1) & 1;
    static const double steps[] = {1, 0.5, 0, 2, 1e-3, 1e6, kNaN, -1, kInf};
    d.time_step = steps[(a >> 2) % 9];
    static const double cells[][2] = {{0, 0}, {0, 0}, {0, 0}, {0, 1}, {2, 0}, {0.5, 4}, {1e-12, 0},
                                      {0, 1e-9}, {4, 2}, {kNaN, 0}, {0, -1}, {5e-324, 1.7976931348623157e308}};
    const int ci = b % 12;
    d.kinematic_pairs = (a ^ b ^ c) & 1;
    const uint8_t mi = uint8_t(((b ^ c) >> 3) % 16);  // (mostly 0; from bits already read)
    d.contact_margin = mi < 10 ? 0 : pick_margin(uint8_t(mi - 10));
    d.min_cell_size = cells[ci][0];
    d.max_cell_size = cells[ci][1];
    cx.anchor = kAnchors[(b >> 4) % 6];
    cx.unit = kUnits[c % 4];
    const double lo = cx.anchor - 4, hi = cx.anchor + 4;
    for (int k = 0; k < 3; ++k) {
        d.bounds_min[k] = lo;
        d.bounds_max[k] = (c >> 2) % 16 == 0 ? lo : hi;  // sometimes empty: refused
    }
    if ((c >> 6) & 1) {  // the caller's task system instead of OpenMP (the pairs are the same)
        d.enqueue_task = enqueue_inline;
        d.finish_task = finish_never;
        task_workers = d.thread_count;
    }
    bool valid = std::isfinite(d.time_step) && d.time_step >= 0 && margin_ok(d.contact_margin);
    const double mn = d.min_cell_size, mx = d.max_cell_size;
    valid = valid && std::isfinite(mn) && std::isfinite(mx) && mn >= 0 && mx >= 0 && !(mn > 0 && mx > 0 && mn > mx);
    for (int k = 0; k < 3 && d.reflect_at_bounds; ++k)  // (bounds are read only when reflecting)
        valid = valid && finite_in_range(d.bounds_min[k]) && finite_in_range(d.bounds_max[k]) &&
                d.bounds_min[k] < d.bounds_max[k];
    hgcd_world *w = reinterpret_cast<hgcd_world *>(0x1);
    const hgcd_status s = hgcd_world_create(&d, &w);
    EXPECT(s == (valid ? HGCD_OK : HGCD_ERROR_INVALID_ARGUMENT), "world_create: %s", hgcd_status_string(s));
    if (s != HGCD_OK) {
        EXPECT(w == nullptr, "refused world_create left *out_world set");
        return false;
    }
    EXPECT(hgcd_world_last_error(w)[0] == 0, "fresh world has a message");
    m.w = w;
    m.desc = d;
    return true;
}

}  // namespace

extern "C" int LLVMFuzzerInitialize(int *, char ***) {
    presets();
    return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size) {
    Input in{data, size};
    Model m;
    Ctx cx;
    if (!make_world(in, m, cx)) return 0;
    int ops = 0;
    while (!in.empty() && ops++ < 64) {
        const uint8_t op = in.u8();
        ++g_ops;
        switch (op % 22) {  // (seeds written for % 16 keep their meaning: their ops are below 16)
            case 0: case 1: op_mesh_create(in, m); break;
            case 2: op_mesh_destroy(in, m); break;
            case 3: case 4: case 5: op_body_create(in, m, cx); break;
            case 6: op_body_destroy(in, m); break;
            case 7: case 8: op_set_pose(in, m, cx); break;
            case 9: op_set_velocity(in, m); break;
            case 10: op_step(m); break;
            case 11: case 12: after_tick(m, hgcd_world_detect(m.w), "detect"); break;
            case 16: case 17: op_batch(in, m, cx); break;
            case 18: case 19: op_query(in, m, cx); break;
            case 20: case 21: op_filtering(in, m); break;
            default: op_read(in, m); break;
        }
        check_state(m);
    }
    after_tick(m, hgcd_world_detect(m.w), "detect");
    hgcd_world_destroy(m.w);
    return 0;
}

// Figures for tests/VALIDATION.md: printed at exit.
namespace {
struct Report {
    ~Report() {
        if (g_detects)
            std::fprintf(stderr, "fuzz_api: %ld detects checked against the oracle (%ld colliding pairs), all equal\n",
                         g_detects, g_pairs_checked);
        if (g_ops) std::fprintf(stderr, "fuzz_api: %ld scripted API calls, each followed by a check of the whole state\n", g_ops);
        if (g_queries)
            std::fprintf(stderr, "fuzz_api: %ld point, box and ray queries checked against the oracle (%ld answers), all equal\n",
                         g_queries, g_query_answers);
        static const char *const call[] = {"set_poses", "set_velocities", "get_poses"};
        for (int c = 0; c < 3; ++c) {
            const long *v = g_batch[c];
            if (v[kApplied] + v[kNullArray] + v[kBadStride] + v[kCountPastSlots] + v[kStaleEntry] + v[kRepeatedEntry] + v[kBadValue])
                std::fprintf(stderr, "fuzz_api: world_%s as predicted: %ld applied (%ld entries); refused: %ld NULL, %ld stride, "
                             "%ld count, %ld stale, %ld repeated, %ld value\n", call[c], v[kApplied], g_batch_entries[c], v[kNullArray], v[kBadStride],
                             v[kCountPastSlots], v[kStaleEntry], v[kRepeatedEntry], v[kBadValue]);
        }
    }
} g_report;
}  // namespace
