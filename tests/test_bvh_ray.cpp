// White-box tests of the tree-driven exact ray parity (hgcd::
// point_in_closed_mesh_bvh, src/bvh.cpp), through the internal headers
// (hidden symbols, reachable when linking the static library):
//  - a mesh built so that the first ray from the query point passes exactly
//    through a vertex: the attempt must be discarded as degenerate and a
//    later direction must give the right answer;
//  - random points against non-convex meshes (the blob of scene `meshes`, a
//    posed one, and a hollow shell): same answer as the tree-less
//    point_in_closed_mesh of src/exact and as the GMP oracle.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <memory>
#include <vector>

#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>

extern "C" {  // this cmocka.h has no C++ guard
#include <cmocka.h>
}

#include "../scene/scene_meshes.h"
#include "narrow/bvh.hpp"
#include "exact/geometry.hpp"
#include "world/mesh.hpp"
#include "oracle.h"

namespace {

// A posed mesh with its tree and the caches a BodyView needs.
struct Posed {
    hgcd::Mesh mesh;
    std::vector<double> world;
    std::vector<uint32_t> vstamp, bstamp;
    std::unique_ptr<double[]> boxes;
    double pos[3] = {0, 0, 0}, quat[4] = {0, 0, 0, 1}, scale = 1;
    hgcd::BodyView view;
    std::vector<uint32_t> stack;

    Posed(const std::vector<double> &v, const std::vector<uint32_t> &t) {
        std::string error;
        assert_true(hgcd::build_mesh(v.data(), uint32_t(v.size() / 3), t.data(), uint32_t(t.size() / 3), &mesh,
                                     &error));
        // Small test meshes get a tree too (build_mesh only builds one above
        // kBvhMinTriangles).
        if (mesh.bvh.empty()) hgcd::build_bvh(mesh.vertices.data(), mesh.triangles.data(), mesh.triangle_count, &mesh.bvh);
    }
    // Prepares the view for a new query (fresh caches).
    hgcd::BodyView &pose() {
        world.assign(3 * size_t(mesh.vertex_count), 0.0);
        vstamp.assign(mesh.vertex_count, 0);
        bstamp.assign(mesh.bvh.nodes.size(), 0);
        boxes.reset(new double[hgcd::kNodeData * mesh.bvh.nodes.size()]);
        view = hgcd::BodyView();
        view.mesh = &mesh;
        view.local = mesh.vertices.data();
        view.nodes = mesh.bvh.nodes.data();
        view.tris = mesh.bvh.tris.data();
        view.tri_ids = mesh.bvh.tri_ids.data();
        view.set_pose(pos, hgcd::rotation_of(quat), scale);
        view.world = world.data();
        view.vertex_stamp = vstamp.data();
        view.boxes = boxes.get();
        view.box_stamp = bstamp.data();
        view.epoch = 1;
        return view;
    }
    // All world vertices (for the tree-less test and the oracle).
    std::vector<double> world_vertices() {
        hgcd::BodyView &v = pose();
        std::vector<double> out(3 * size_t(mesh.vertex_count));
        for (uint32_t i = 0; i < mesh.vertex_count; ++i) std::memcpy(&out[3 * i], v.vertex(i), 3 * sizeof(double));
        return out;
    }
    bool inside_bvh(const double *p) { return hgcd::point_in_closed_mesh_bvh(p, pose(), stack); }
    bool inside_plain(const double *p) {
        const std::vector<double> w = world_vertices();
        double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
        for (size_t i = 0; i < w.size(); ++i) {
            lo[i % 3] = std::min(lo[i % 3], w[i]);
            hi[i % 3] = std::max(hi[i % 3], w[i]);
        }
        return hgcd::point_in_closed_mesh(p, w.data(), mesh.triangles.data(), mesh.triangle_count, lo, hi);
    }
    int inside_oracle(const double *p) {
        const std::vector<double> w = world_vertices();
        return oracle_point_in_closed_mesh(p, w.data(), mesh.vertex_count, mesh.triangles.data(),
                                           mesh.triangle_count);
    }
};

// The offsets of the ray directions of bvh.cpp (kept in step with it; the
// test checks that its first ray really meets the planted vertex).
double offset(uint32_t i) {
    uint64_t z = 0x9E3779B97F4A7C15ull * (uint64_t(i) + 1);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    z ^= z >> 31;
    return (double(z >> 11) * 0x1p-53 - 0.5) * 0.25;
}

// The box [-1.5, 0.5] x [-1, 1]^2 whose +x face is dented into a pyramid
// with apex `apex` (the query point 0 stays inside).
void dented_box(const double *apex, std::vector<double> &v, std::vector<uint32_t> &t) {
    v.clear();
    for (int i = 0; i < 8; ++i) {
        v.push_back((i & 1) ? 0.5 : -1.5);
        v.push_back((i & 2) ? 1.0 : -1.0);
        v.push_back((i & 4) ? 1.0 : -1.0);
    }
    v.insert(v.end(), apex, apex + 3);
    // Faces by corner bits (x = bit 0, y = bit 1, z = bit 2), outward.
    t = {0, 2, 6, 0, 6, 4,   // x-
         0, 4, 5, 0, 5, 1,   // y-
         2, 3, 7, 2, 7, 6,   // y+
         0, 1, 3, 0, 3, 2,   // z-
         4, 6, 7, 4, 7, 5,   // z+
         1, 5, 8, 5, 7, 8, 7, 3, 8, 3, 1, 8};  // x+ pyramid to the apex (vertex 8)
}

void test_degenerate_first_ray(void **) {
    // First, with the apex anywhere inside, find the first ray exactly as
    // bvh.cpp does: the nearest face of the root box is x+ (distance 0.5),
    // direction (1, offset(0), offset(1)), length 1.125 dist + 0.0625 ext.
    std::vector<double> v;
    std::vector<uint32_t> t;
    const double placeholder[3] = {0.25, 0, 0};
    dented_box(placeholder, v, t);
    Posed first(v, t);
    const double *rb = first.pose().box(0);
    double ext = 0;
    for (int k = 0; k < 3; ++k) ext = std::max(ext, rb[3 + k] - rb[k]);
    const double dist = rb[3] - 0.0;
    for (int k = 0; k < 3; ++k) {  // x+ is the nearest face
        if (k) assert_true(rb[3 + k] - 0.0 > dist && 0.0 - rb[k] > dist);
    }
    assert_true(0.0 - rb[0] > dist);
    const double dir[3] = {1.0, offset(0), offset(1)};
    const double len = 1.125 * dist + 0.0625 * ext;
    double q[3];
    for (int k = 0; k < 3; ++k) q[k] = 0.0 + len * dir[k];
    assert_true(q[0] > rb[3]);  // leaves the box at the first length
    // The apex halfway along that segment: exactly on it (halving is exact),
    // strictly inside the box, so the root box does not change.
    const double apex[3] = {0.5 * q[0], 0.5 * q[1], 0.5 * q[2]};
    dented_box(apex, v, t);
    Posed dented(v, t);
    const double *rb2 = dented.pose().box(0);
    for (int k = 0; k < 6; ++k) assert_true(rb2[k] == rb[k]);
    const double p[3] = {0, 0, 0};
    // The first ray meets the apex (collinear with p and q, between them).
    assert_true(dented.mesh.closed);
    assert_int_equal(dented.inside_oracle(p), 1);
    assert_true(dented.inside_plain(p));
    assert_true(dented.inside_bvh(p));
    // A point in the dent's pocket, outside the solid but inside the box:
    // the pocket lies between the pyramid and the plane x = 0.5.
    const double pocket[3] = {0.49, 0.5 * q[1], 0.5 * q[2]};
    assert_int_equal(dented.inside_oracle(pocket), 0);
    assert_false(dented.inside_plain(pocket));
    assert_false(dented.inside_bvh(pocket));
}

struct Rng {
    uint64_t s;
    double u() {
        uint64_t z = (s += 0x9E3779B97F4A7C15ull);
        z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
        z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
        z ^= z >> 31;
        return double(z >> 11) * 0x1p-53;
    }
};

void compare_points(Posed &m, uint64_t seed, int count, size_t *inside_count) {
    const std::vector<double> w = m.world_vertices();
    double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
    for (size_t i = 0; i < w.size(); ++i) {
        lo[i % 3] = std::min(lo[i % 3], w[i]);
        hi[i % 3] = std::max(hi[i % 3], w[i]);
    }
    Rng r{seed};
    for (int i = 0; i < count; ++i) {
        double p[3];
        for (int k = 0; k < 3; ++k) p[k] = lo[k] + (hi[k] - lo[k]) * (1.2 * r.u() - 0.1);
        if (i % 8 == 0) std::memcpy(p, &w[3 * (size_t(r.u() * m.mesh.vertex_count))], sizeof p);  // on the surface: skipped
        const int o = oracle_point_in_closed_mesh(p, w.data(), m.mesh.vertex_count, m.mesh.triangles.data(),
                                                  m.mesh.triangle_count);
        if (o < 0) continue;  // on the surface: outside the precondition
        const bool plain = hgcd::point_in_closed_mesh(p, w.data(), m.mesh.triangles.data(), m.mesh.triangle_count,
                                                      lo, hi);
        const bool tree = m.inside_bvh(p);
        if (plain != (o == 1) || tree != (o == 1))
            std::fprintf(stderr, "point (%.17g, %.17g, %.17g): oracle %d, plain %d, tree %d\n", p[0], p[1], p[2], o,
                         int(plain), int(tree));
        assert_int_equal(int(plain), o);
        assert_int_equal(int(tree), o);
        *inside_count += size_t(o);
    }
}

void test_random_points(void **) {
    std::vector<double> v(3 * size_t(hgcd_blob_vertex_count(24, 16)));
    std::vector<uint32_t> t(3 * size_t(hgcd_blob_triangle_count(24, 16)));
    hgcd_blob_mesh(24, 16, v.data(), t.data());
    size_t inside = 0;
    Posed blob(v, t);
    compare_points(blob, 1, 120, &inside);
    // Posed: rotated, scaled, far from the origin.
    blob.pos[0] = 1e4;
    blob.pos[1] = -3.25;
    blob.pos[2] = 7;
    const double q[4] = {0.18257418583505536, 0.3651483716701107, 0.5477225575051661, 0.7302967433402214};
    std::memcpy(blob.quat, q, sizeof q);
    blob.scale = 2.5;
    compare_points(blob, 2, 120, &inside);
    // A hollow shell: the blob and an inverted copy scaled by 1/2 inside it.
    const size_t nv = v.size() / 3, nt = t.size() / 3;
    std::vector<double> sv = v;
    std::vector<uint32_t> st = t;
    for (size_t i = 0; i < 3 * nv; ++i) sv.push_back(0.5 * v[i]);
    for (size_t i = 0; i < nt; ++i) {
        st.push_back(uint32_t(nv) + t[3 * i]);
        st.push_back(uint32_t(nv) + t[3 * i + 2]);
        st.push_back(uint32_t(nv) + t[3 * i + 1]);
    }
    Posed hollow(sv, st);
    assert_int_equal(hollow.mesh.component_vertices.size(), 2);
    compare_points(hollow, 3, 120, &inside);
    const double centre[3] = {0, 0, 0};  // in the cavity
    assert_int_equal(hollow.inside_oracle(centre), 0);
    assert_false(hollow.inside_bvh(centre));
    assert_true(inside > 40);
}

}  // namespace

int main(void) {
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_degenerate_first_ray),
        cmocka_unit_test(test_random_points),
    };
    /* Valgrind and sanitizer runs pick tests by name (cmocka patterns). */
    if (getenv("HGCD_TEST_FILTER")) cmocka_set_test_filter(getenv("HGCD_TEST_FILTER"));
    if (getenv("HGCD_TEST_SKIP")) cmocka_set_skip_filter(getenv("HGCD_TEST_SKIP"));
    return cmocka_run_group_tests(tests, nullptr, nullptr);
}
