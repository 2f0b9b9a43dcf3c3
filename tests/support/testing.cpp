// C entry points onto the internal geometry, for the C test programs.
#include "testing.h"

#include <cstddef>

#include <algorithm>
#include <climits>
#include <cstring>
#include <string>
#include <vector>

#include "exact/geometry.hpp"
#include "hgcd/hgcd.h"
#include "hgcd/hgcd_scene.h"
#include "broad/float_box.hpp"
#include "broad/grid.hpp"
#include "world/mesh.hpp"
#include "world/mesh_pool.hpp"
#include "world/pose_box.hpp"
#include "world/threads.hpp"
#include "narrow/narrow.hpp"
#include "narrow/within.hpp"
#include "common/ieee.hpp"
#include "common/transform.hpp"

namespace hgcd {

// The grid's state, for the tests that compare an incremental update with
// a rebuild.
struct GridTestAccess {
    // Whether grid a holds what b holds for the same bodies: the same
    // levels, each slot on the same level and row, the same oversize
    // bodies, and each list the same slots in each row (the order within a
    // row aside: ties in x are ordered by history; guests aside where one
    // grid's level keeps them and the other's does not, a choice with
    // hysteresis).
    static bool same_state(const Grid &a, const Grid &b) {
        if (a.levels_.size() != b.levels_.size() || a.level_.size() != b.level_.size()) return false;
        for (size_t l = 0; l < a.levels_.size(); ++l)
            if (a.levels_[l].exponent != b.levels_[l].exponent) return false;
        for (size_t s = 0; s < a.level_.size(); ++s) {
            if (a.level_[s] != b.level_[s]) return false;
            if (a.level_[s] >= 0 && (a.cell_[2 * s] != b.cell_[2 * s] || a.cell_[2 * s + 1] != b.cell_[2 * s + 1]))
                return false;
        }
        std::vector<uint32_t> oa(a.oversize_), ob(b.oversize_);
        std::sort(oa.begin(), oa.end());
        std::sort(ob.begin(), ob.end());
        if (oa != ob) return false;
        for (size_t l = 0; l < a.levels_.size(); ++l)
            for (int g = 0; g < 2; ++g) {
                if (g && a.levels_[l].queries_finer != b.levels_[l].queries_finer) continue;
                const Grid::List &x = g ? a.levels_[l].guests : a.levels_[l].residents;
                const Grid::List &y = g ? b.levels_[l].guests : b.levels_[l].residents;
                if (x.row_keys != y.row_keys || x.row_start != y.row_start) return false;
                for (size_t r = 0; r < x.row_keys.size(); ++r) {
                    std::vector<uint32_t> p(x.slot.begin() + x.row_start[r], x.slot.begin() + x.row_start[r + 1]);
                    std::vector<uint32_t> q(y.slot.begin() + y.row_start[r], y.slot.begin() + y.row_start[r + 1]);
                    std::sort(p.begin(), p.end());
                    std::sort(q.begin(), q.end());
                    if (p != q) return false;
                }
            }
        return true;
    }
};

}  // namespace hgcd

namespace {

// How many of the bodies 0..n-1 get other bits from the gather's
// four-at-a-time box kernel than from the one-body rounding (float_box), or
// -1 where that kernel does not run (no AVX2).
int64_t float_boxes_mismatches(const hgcd::Boxes &boxes, uint32_t n) {
#if HGCD_AVX2
    if (!hgcd::use_avx2()) return -1;
    const hgcd::IeeeMode ieee;
    std::vector<uint32_t> slots(n);
    for (uint32_t i = 0; i < n; ++i) slots[i] = i;
    std::vector<float> got(6 * size_t(n), 0.0f);
    float *const arrays[6] = {&got[0], &got[size_t(n)], &got[2 * size_t(n)], &got[3 * size_t(n)],
                              &got[4 * size_t(n)], &got[5 * size_t(n)]};
    const size_t done = hgcd::broad::float_boxes_avx2(boxes, slots.data(), 0, n, n, arrays);
    int64_t mismatches = 0;
    for (uint32_t i = 0; i < done; ++i) {
        float lo[3], hi[3];
        hgcd::broad::float_box(boxes, i, lo, hi);
        const float want[6] = {lo[0], hi[0], lo[1], hi[1], lo[2], hi[2]};
        bool same = true;
        for (int a = 0; a < 6; ++a) same &= std::memcmp(&want[a], &got[a * size_t(n) + i], sizeof(float)) == 0;
        mismatches += !same;
    }
    return mismatches;
#else
    (void)boxes;
    (void)n;
    return -1;
#endif
}

}  // namespace

extern "C" {

int hgcdi_orient3d(const double *a, const double *b, const double *c,
                   const double *d) {
    return hgcd::orient3d(a, b, c, d);
}

int hgcdi_orient2d(const double *a, const double *b, const double *c) {
    return hgcd::orient2d(a, b, c);
}

int hgcdi_tri_tri(const double p[9], const double q[9]) {
    return hgcd::tri_tri_intersect(p, p + 3, p + 6, q, q + 3, q + 6) ? 1 : 0;
}

int hgcdi_bvh_same_on_threads(const double *vertices, const uint32_t *triangles, uint32_t triangle_count,
                              int threads, uint32_t *nodes) {
    hgcd::Bvh one, many;
    hgcd::build_bvh(vertices, triangles, triangle_count, &one, 1);
    hgcd::build_bvh(vertices, triangles, triangle_count, &many, threads);
    *nodes = uint32_t(one.nodes.size());
    const auto same = [](const auto &x, const auto &y) {
        return x.size() == y.size() && (x.empty() || !std::memcmp(x.data(), y.data(), x.size() * sizeof x[0]));
    };
    return same(one.nodes, many.nodes) && same(one.lanes, many.lanes) && same(one.tris, many.tris) &&
           same(one.tri_ids, many.tri_ids) && same(one.parent, many.parent) && one.depth == many.depth;
}

int hgcdi_flat_hulls_meet(int k, const double *const *a, int na, const double *const *b, int nb) {
    return hgcd::flat_hulls_meet(k, a, na, b, nb) ? 1 : 0;
}

int hgcdi_tri_tri_within(const double p[9], const double q[9], double d) {
    return hgcd::tri_tri_within(p, p + 3, p + 6, q, q + 3, q + 6, d) ? 1 : 0;
}

int hgcdi_tri_tri_prepared(const double p[9], const double q[9]) {
    hgcd::PreparedTriangle a, b;
    hgcd::prepare_triangle(a, p, p + 3, p + 6);
    hgcd::prepare_triangle(b, q, q + 3, q + 6);
    return hgcd::tri_tri_intersect(a, b) ? 1 : 0;
}

int hgcdi_segment_triangle(const double e0[3], const double e1[3],
                           const double t[9]) {
    return hgcd::segment_triangle_intersect(e0, e1, t, t + 3, t + 6) ? 1 : 0;
}

int hgcdi_point_in_closed_mesh(const double p[3], const double *verts,
                               uint32_t vertex_count, const uint32_t *tris,
                               uint32_t tri_count) {
    if (vertex_count == 0) return 0;
    double lo[3] = {verts[0], verts[1], verts[2]};
    double hi[3] = {verts[0], verts[1], verts[2]};
    for (uint32_t i = 1; i < vertex_count; ++i) {
        for (int k = 0; k < 3; ++k) {
            double v = verts[3 * std::size_t(i) + k];
            if (v < lo[k]) lo[k] = v;
            if (v > hi[k]) hi[k] = v;
        }
    }
    return hgcd::point_in_closed_mesh(p, verts, tris, tri_count, lo, hi) ? 1
                                                                          : 0;
}

int hgcdi_point_in_convex(const double p[3], const double *verts,
                          const uint32_t *tris, uint32_t tri_count,
                          int inward_sign) {
    return hgcd::point_in_convex_closed_mesh(p, verts, tris, tri_count,
                                             inward_sign)
               ? 1
               : 0;
}

int64_t hgcdi_float_boxes_check(const double *points, const float *offsets, uint32_t n) {
    try {
        return float_boxes_mismatches(hgcd::Boxes{points, offsets}, n);
    } catch (...) {
        return -2;
    }
}

int64_t hgcdi_offset_box_check(const double *q, const double *s, uint32_t n, const double *p, uint32_t points) {
    const hgcd::IeeeMode ieee;
    // The points as a mesh record holds them (mesh_pool.hpp): groups of 4,
    // x y z runs, the last padded with copies of its first point; aligned.
    const uint32_t groups = (points + 3) / 4;
    std::vector<hgcd::MeshPool::Block> record(3 * size_t(groups));
    for (uint32_t g = 0; g < groups; ++g)
        for (uint32_t k = 0; k < 4; ++k) {
            const uint32_t v = 4 * g + k < points ? 4 * g + k : 4 * g;
            for (int a = 0; a < 3; ++a) record[3 * g + uint32_t(a)].d[k] = p[3 * v + uint32_t(a)];
        }
    // The four-body kernel's lanes: lane j takes the first points - j
    // points (at least 1: a record of fewer groups among more), its own
    // record, against the one-body kernel on that record.
    std::vector<hgcd::MeshPool::Block> lane_record[4];
    uint32_t lane_groups[4];
    for (uint32_t j = 0; j < 4; ++j) {
        const uint32_t c = points > j ? points - j : 1, gs = (c + 3) / 4;
        lane_groups[j] = gs;
        lane_record[j].resize(3 * size_t(gs));
        for (uint32_t g = 0; g < gs; ++g)
            for (uint32_t k = 0; k < 4; ++k) {
                const uint32_t v = 4 * g + k < c ? 4 * g + k : 4 * g;
                for (int a = 0; a < 3; ++a) lane_record[j][3 * g + uint32_t(a)].d[k] = p[3 * v + uint32_t(a)];
            }
    }
    int64_t differ = 0;
    for (uint32_t i = 0; i + 4 <= n; i += 4) {
        hgcd::BoxJob job[4];
        float out[4][6], want[4][6];
        for (uint32_t j = 0; j < 4; ++j) {
            // (lanes in a rotating order: every lane sees every record)
            const uint32_t l = (i / 4 + j) % 4;
            job[j] = hgcd::BoxJob{q + 4 * size_t(i + j), s[i + j], lane_record[l][0].d, lane_groups[l], out[j]};
            hgcd::record_float_box(hgcd::rotation_of(q + 4 * size_t(i + j)), s[i + j], lane_record[l][0].d,
                                   lane_groups[l], want[j]);
        }
        hgcd::record_float_boxes4(job);
        for (uint32_t j = 0; j < 4; ++j) differ += std::memcmp(out[j], want[j], sizeof want[j]) != 0;
    }
    for (uint32_t i = 0; i < n; ++i) {
        const hgcd::Rotation r = hgcd::rotation_of(q + 4 * size_t(i));
        double lo[3], hi[3], rlo[3], rhi[3], plo[3], phi[3];
        hgcd::offset_box(r, s[i], p, points, lo, hi);
        hgcd::offset_box_scalar(r, s[i], p, points, rlo, rhi);
        hgcd::record_box(r, s[i], record[0].d, groups, plo, phi);
        float f[6], g[6], h[6];
        hgcd::broad::round_outward(lo, hi, f, f + 3);
        hgcd::record_float_box(r, s[i], record[0].d, groups, h);
        for (int k = 0; k < 3; ++k) {
            g[k] = hgcd::float_at_most(rlo[k]);
            g[3 + k] = hgcd::float_at_least(rhi[k]);
        }
        differ += std::memcmp(lo, rlo, sizeof lo) != 0 || std::memcmp(hi, rhi, sizeof hi) != 0 ||
                  std::memcmp(plo, rlo, sizeof lo) != 0 || std::memcmp(phi, rhi, sizeof hi) != 0 ||
                  std::memcmp(f, g, sizeof f) != 0 || std::memcmp(h, g, sizeof h) != 0;
    }
    return differ;
}

int64_t hgcdi_grid_pairs(const double *before, const double *after, uint32_t n, int threads,
                         int coarsen, uint64_t *out, uint64_t cap) {
    try {
        hgcd::Grid grid;
        std::vector<uint32_t> gen(n, 1);
        std::vector<double> pos(3 * size_t(n));
        std::vector<float> off(6 * size_t(n));
        std::vector<double> r_level(n);
        hgcd::GridLimits limits{INT_MIN, INT_MAX};
        limits.coarsen = coarsen != 0;
        const hgcd::Boxes boxes{pos.data(), off.data()};
        for (int pass = before ? 0 : 1; pass < 2; ++pass) {
            const double *s = pass ? after : before;
            for (uint32_t i = 0; i < n; ++i) {
                const double r = s[4 * i + 3];
                const float lo = hgcd::float_at_most(-r), hi = hgcd::float_at_least(r);
                // A body's size is fixed for its life (the world's r_level):
                // one whose size changes is a new body (a new generation).
                const double level = std::max(-double(lo), double(hi));
                if (pass == 1 && before && level != r_level[i]) gen[i] = 2;
                r_level[i] = level;
                for (int k = 0; k < 3; ++k) {
                    pos[3 * size_t(i) + k] = s[4 * i + k];
                    off[6 * size_t(i) + k] = lo;
                    off[6 * size_t(i) + 3 + k] = hi;
                }
            }
            grid.update(boxes, r_level.data(), gen.data(), n, limits, threads);
        }
        if (before) {  // the incremental update against a grid built afresh
            hgcd::Grid fresh;
            const std::vector<uint32_t> born(n, 1);
            fresh.update(boxes, r_level.data(), born.data(), n, limits, threads);
            if (!hgcd::GridTestAccess::same_state(grid, fresh)) return -2;
        }
        std::vector<hgcd::PairBuffer> found(threads);
        grid.find_pairs(boxes, threads, found);
        std::vector<uint64_t> all;
        for (auto &f : found)
            for (const uint64_t key : f)  // (the grid gives either order)
                all.push_back(hgcd::pair_key(uint32_t(key >> 32), uint32_t(key)));
        std::sort(all.begin(), all.end());
        std::copy_n(all.begin(), std::min<uint64_t>(cap, all.size()), out);
        return int64_t(all.size());
    } catch (...) {
        return -1;
    }
}

int64_t hgcdi_tetra_batch_check(const double *meshes, uint32_t mesh_count, const uint32_t *pair_mesh,
                                const double *poses, uint32_t pair_count, uint64_t *counts) {
    uint32_t faces[12];
    hgcd_scene_tetra_unit_mesh(nullptr, faces);  // (the faces of docs/scenes.md)
    std::vector<hgcd::Mesh> mesh(mesh_count);
    for (uint32_t m = 0; m < mesh_count; ++m) {
        std::string error;
        if (!hgcd::build_mesh(meshes + 12 * size_t(m), 4, faces, 4, &mesh[m], &error) || !mesh[m].tetra) return -1;
    }
    // The meshes' records, as the world's pool holds them (aligned blocks).
    std::vector<hgcd::MeshPool::Block> record(3 * size_t(mesh_count));
    for (uint32_t m = 0; m < mesh_count; ++m) hgcd::write_record(mesh[m], record[3 * size_t(m)].d);
    std::vector<hgcd::Placement> place(2 * size_t(pair_count));
    std::vector<hgcd::TetraPair> pairs(pair_count);
    for (uint32_t k = 0; k < pair_count; ++k) {
        for (int side = 0; side < 2; ++side) {
            hgcd::Placement &pl = place[2 * size_t(k) + side];
            const double *pose = poses + 16 * size_t(k) + 8 * side;
            for (int c = 0; c < 3; ++c) pl.position[c] = pose[c];
            for (int c = 0; c < 4; ++c) pl.orientation[c] = pose[3 + c];
            pl.scale = pose[7];
        }
        const uint32_t ma = pair_mesh[2 * size_t(k)], mb = pair_mesh[2 * size_t(k) + 1];
        pairs[k] = hgcd::TetraPair{&mesh[ma], &mesh[mb], &place[2 * size_t(k)], &place[2 * size_t(k) + 1],
                                   record[3 * size_t(ma)].d, record[3 * size_t(mb)].d};
    }
    hgcd::NarrowScratch one, batch;
    std::vector<hgcd::Contact> verdict(pair_count);
    hgcd::collide_tetra_batch(pairs.data(), pair_count, verdict.data(), batch);
    int64_t differ = 0;
    uint64_t hits = 0, contained = 0;
    for (uint32_t k = 0; k < pair_count; ++k) {
        const hgcd::TetraPair &p = pairs[k];
        const hgcd::Contact c = hgcd::collide(hgcd::pose_of(p.mesh_a, *p.a), hgcd::pose_of(p.mesh_b, *p.b), one);
        differ += c != verdict[k];
        hits += c != hgcd::Contact::None;
        contained += c == hgcd::Contact::Containment;
    }
    counts[0] = one.exact_tests;
    counts[1] = batch.exact_tests;
    counts[2] = one.triangle_tests;
    counts[3] = batch.triangle_tests;
    counts[4] = hits;
    counts[5] = contained;
    return differ;
}

int64_t hgcdi_tetra_within_check(const double *meshes, uint32_t mesh_count, const uint32_t *pair_mesh,
                                 const double *poses, const double *d, uint32_t pair_count, int *verdict,
                                 int *batch, int *general) {
    uint32_t faces[12];
    hgcd_scene_tetra_unit_mesh(nullptr, faces);
    std::vector<hgcd::Mesh> mesh(mesh_count);
    for (uint32_t m = 0; m < mesh_count; ++m) {
        std::string error;
        if (!hgcd::build_mesh(meshes + 12 * size_t(m), 4, faces, 4, &mesh[m], &error) || !mesh[m].tetra) return -1;
    }
    std::vector<hgcd::MeshPool::Block> record(3 * size_t(mesh_count));
    for (uint32_t m = 0; m < mesh_count; ++m) hgcd::write_record(mesh[m], record[3 * size_t(m)].d);
    std::vector<hgcd::Placement> place(2 * size_t(pair_count));
    std::vector<hgcd::TetraPair> pairs(pair_count);
    for (uint32_t k = 0; k < pair_count; ++k) {
        for (int side = 0; side < 2; ++side) {
            hgcd::Placement &pl = place[2 * size_t(k) + side];
            const double *pose = poses + 16 * size_t(k) + 8 * side;
            std::memcpy(pl.position, pose, 3 * sizeof(double));
            std::memcpy(pl.orientation, pose + 3, 4 * sizeof(double));
            pl.scale = pose[7];
        }
        const uint32_t ma = pair_mesh[2 * size_t(k)], mb = pair_mesh[2 * size_t(k) + 1];
        pairs[k] = hgcd::TetraPair{&mesh[ma], &mesh[mb], &place[2 * size_t(k)], &place[2 * size_t(k) + 1],
                                   record[3 * size_t(ma)].d, record[3 * size_t(mb)].d};
    }
    hgcd::NarrowScratch fast, slow, batched;
    std::vector<hgcd::Contact> touching(pair_count);
    hgcd::collide_tetra_batch(pairs.data(), pair_count, touching.data(), batched);
    for (uint32_t k = 0; k < pair_count; ++k) {
        const hgcd::BodyPose a = hgcd::pose_of(pairs[k].mesh_a, *pairs[k].a);
        const hgcd::BodyPose b = hgcd::pose_of(pairs[k].mesh_b, *pairs[k].b);
        batch[k] = touching[k] != hgcd::Contact::None ||
                   hgcd::tet::tetra_within_apart(a, b, d[k], batched) != hgcd::Contact::None;
        verdict[k] = hgcd::tet::collide_tetra_within(a, b, d[k], fast) != hgcd::Contact::None;
        // The general path: collide() with a witness request skips the tetrahedron path.
        hgcd::Witness witness;
        general[k] = hgcd::collide(a, b, slow, &witness) != hgcd::Contact::None ||
                     hgcd::collide_within_direct(a, b, d[k], slow, nullptr) != hgcd::Contact::None;
    }
    return int64_t(fast.margin_fallbacks);
}

void hgcdi_thread_governor(int full, uint32_t count, const double *rate, const double *lost, int *used) {
    hgcd::ThreadGovernor g;
    for (uint32_t k = 0; k < count; ++k) {
        const int t = g.threads(full);
        used[k] = t;
        const size_t at = size_t(k) * size_t(full + 1) + size_t(t);
        g.record(full, rate[at], 1.0, lost[at]);
    }
}

}  // extern "C"
