// White-box tests of the tree path's first-tried witness (NodeHint,
// src/narrow/tree_path.cpp), through the internal headers (static library):
// a hint of any value leaves the verdict exact. Pairs of trees (the
// non-convex blob, an icosphere) and a tree against a tree-less box, posed
// at random near contact; each pair's verdict without a hint is checked
// against the GMP oracle, then every hint (the roots, random nodes, leaves,
// the meeting leaves of a nearby pose, out of range) must give that
// verdict, whether its subtrees meet or the search has to climb from them
// towards the roots. And the frame's bound on a rotation matrix's defect.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>

extern "C" {  // this cmocka.h has no C++ guard
#include <cmocka.h>
}

#include "../scene/scene_meshes.h"
#include "../scene/scene_shapes.h"
#include "narrow/narrow.hpp"
#include "oracle.h"
#include "test_rng.h"
#include "world/mesh.hpp"

namespace {

struct Shape {
    std::vector<double> v;
    std::vector<uint32_t> t;
    hgcd::Mesh mesh;
    oracle_mesh om;
    void build() {
        std::string error;
        assert_true(hgcd::build_mesh(v.data(), uint32_t(v.size() / 3), t.data(), uint32_t(t.size() / 3), &mesh,
                                     &error));
        om = oracle_mesh{v.data(), t.data(), uint32_t(v.size() / 3), uint32_t(t.size() / 3), 1};
    }
};

void blob(Shape &s) {
    const uint32_t nu = 14, nv = 12;
    s.v.resize(3 * hgcd_blob_vertex_count(nu, nv));
    s.t.resize(3 * hgcd_blob_triangle_count(nu, nv));
    hgcd_blob_mesh(nu, nv, s.v.data(), s.t.data());
    s.build();
}

void icosphere(Shape &s) {
    const int level = 2;
    s.v.resize(3 * hgcd_icosphere_vertex_count(level));
    s.t.resize(3 * hgcd_icosphere_triangle_count(level));
    std::vector<uint32_t> scratch(4 * s.t.size());
    hgcd_icosphere(level, s.v.data(), s.t.data(), scratch.data());
    s.build();
}

void box(Shape &s) {
    s.v.resize(24);
    s.t.resize(36);
    hgcd_box_mesh(0.5, 0.3, 0.2, s.v.data(), s.t.data());
    s.build();
}

struct Body {
    double position[3], orientation[4], scale;
};

hgcd::BodyPose pose(const Shape &s, const Body &b) { return hgcd::BodyPose{&s.mesh, b.position, b.orientation, b.scale}; }

bool oracle_collide(const Shape &sa, const Body &a, const Shape &sb, const Body &b) {
    const oracle_mesh *meshes[2] = {&sa.om, &sb.om};
    double positions[6], orientations[8], scales[2] = {a.scale, b.scale};
    for (int k = 0; k < 3; ++k) positions[k] = a.position[k], positions[3 + k] = b.position[k];
    for (int k = 0; k < 4; ++k) orientations[k] = a.orientation[k], orientations[4 + k] = b.orientation[k];
    uint32_t out[2];
    return oracle_colliding_pairs(2, meshes, positions, orientations, scales, out, 1) == 1;
}

// Nodes of a mesh's tree to hint at (0 alone for a mesh without one), and a
// leaf of it.
uint32_t any_node(const hgcd::Mesh &m, rng *r) {
    return m.bvh.empty() ? 0 : uint32_t(next(r) % m.bvh.nodes.size());
}
uint32_t any_leaf(const hgcd::Mesh &m, rng *r) {
    if (m.bvh.empty()) return 0;
    for (;;) {
        const uint32_t n = any_node(m, r);
        if (m.bvh.nodes[n].count) return n;
    }
}

// Pairs of sa's and sb's bodies near contact (their centres reach_lo to 2.3
// reach_lo apart): each verdict without a hint against the oracle, then
// under each hint.
void check_pairs(const Shape &sa, const Shape &sb, double reach_lo, uint64_t seed, int pairs) {
    rng r;
    r.s = seed;
    hgcd::NarrowScratch s;
    int met = 0, apart = 0, found = 0;
    for (int p = 0; p < pairs; ++p) {
        Body a{{unif(&r) - 0.5, unif(&r) - 0.5, unif(&r) - 0.5}, {}, 0.8 + 0.4 * unif(&r)};
        Body b{{}, {}, 0.6 + 0.8 * unif(&r)};
        random_unit_quaternion(&r, a.orientation);
        random_unit_quaternion(&r, b.orientation);
        double dir[3] = {unif(&r) - 0.5, unif(&r) - 0.5, unif(&r) - 0.5};
        const double len = std::sqrt(dir[0] * dir[0] + dir[1] * dir[1] + dir[2] * dir[2]);
        const double reach = reach_lo * (1 + 1.3 * unif(&r));
        for (int k = 0; k < 3; ++k) b.position[k] = a.position[k] + reach * dir[k] / len;
        const hgcd::Contact want = hgcd::collide(pose(sa, a), pose(sb, b), s);
        assert_int_equal(want != hgcd::Contact::None, oracle_collide(sa, a, sb, b));
        (want != hgcd::Contact::None ? met : apart) += 1;
        // The hint a pose a little off gives (where the surfaces met there).
        Body near = b;
        for (int k = 0; k < 3; ++k) near.position[k] += 0.05 * (unif(&r) - 0.5);
        hgcd::NodeHint last;
        hgcd::collide(pose(sa, a), pose(sb, near), s, nullptr, &last);
        std::vector<hgcd::NodeHint> hints;
        if (last.found) hints.push_back(last), ++found;
        const uint32_t na = uint32_t(sa.mesh.bvh.nodes.size()), nb = uint32_t(sb.mesh.bvh.nodes.size());
        const uint32_t given[][2] = {{0, 0},
                                     {any_node(sa.mesh, &r), any_node(sb.mesh, &r)},
                                     {any_node(sa.mesh, &r), any_node(sb.mesh, &r)},
                                     {any_leaf(sa.mesh, &r), any_leaf(sb.mesh, &r)},
                                     {any_leaf(sa.mesh, &r), 0},
                                     {0, any_leaf(sb.mesh, &r)},
                                     {na, 0},
                                     {0, nb + 1},
                                     {UINT32_MAX, UINT32_MAX}};
        for (const auto &g : given) {
            hgcd::NodeHint h;
            h.node_a = g[0];
            h.node_b = g[1];
            hints.push_back(h);
        }
        for (hgcd::NodeHint h : hints) {
            const hgcd::Contact got = hgcd::collide(pose(sa, a), pose(sb, b), s, nullptr, &h);
            assert_int_equal(int(got), int(want));
            assert_int_equal(h.found, want == hgcd::Contact::Surface);
        }
    }
    // Both verdicts and the nearby poses' hints were exercised.
    assert_true(met > pairs / 10 && apart > pairs / 10 && found > pairs / 10);
}

void test_blob_blob(void **) {
    Shape a, b;
    blob(a);
    blob(b);
    check_pairs(a, b, 1.2, 11, 120);
}

// The blob against another shape, either way round.
void check_blob_with(void (*make)(Shape &), double reach_lo, uint64_t seed) {
    Shape a, b;
    blob(a);
    make(b);
    check_pairs(a, b, reach_lo, seed, 80);
    check_pairs(b, a, reach_lo, seed + 1, 80);
}

void test_blob_icosphere(void **) { check_blob_with(icosphere, 1.2, 12); }

void test_blob_box(void **) { check_blob_with(box, 0.8, 14); }

// rotation_defect (common/transform.hpp), which the frame's node tests take
// for ||R^T R - I||_inf, bounds it as computed in long double from the
// rounded matrix, for quaternions up to 1e-6 off unit length (and none
// beyond).
void test_rotation_defect(void **) {
    rng r{21};
    double worst = 0;
    for (int k = 0; k < 20000; ++k) {
        double q[4];
        random_unit_quaternion(&r, q);
        const double stretch = 1 + (k % 3 == 0 ? 0.999e-6 : 2 * unif(&r) - 1) * 0.49e-6;  // |q|^2 within 1e-6 of 1
        for (double &c : q) c *= (k & 1) ? stretch : 1 / stretch;
        const hgcd::Rotation rot = hgcd::rotation_of(q);
        long double row_max = 0;
        for (int i = 0; i < 3; ++i) {
            long double row = 0;
            for (int j = 0; j < 3; ++j) {
                long double dot = 0;
                for (int m = 0; m < 3; ++m) dot += (long double)rot.m[3 * m + i] * rot.m[3 * m + j];
                row += fabsl(dot - (i == j ? 1 : 0));
            }
            row_max = std::max(row_max, row);
        }
        const double bound = hgcd::rotation_defect(q);
        assert_true(bound >= row_max);
        worst = std::max(worst, double(row_max / bound));
    }
    assert_true(worst > 0.5);  // (the bound is not loose by more than 2x here)
    double far[4] = {0, 0, 0, 1 + 1e-6};
    assert_true(std::isinf(hgcd::rotation_defect(far)));
}

}  // namespace

int main() {
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_blob_blob),
        cmocka_unit_test(test_blob_icosphere),
        cmocka_unit_test(test_blob_box),
        cmocka_unit_test(test_rotation_defect),
    };
    return cmocka_run_group_tests(tests, nullptr, nullptr);
}
