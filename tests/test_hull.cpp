// White-box tests of the mesh hull (hgcd::build_hull, src/narrow/hull.cpp),
// through the internal headers (static library), against the GMP oracle's
// orient3d: on random points, the non-convex blob, points on a cube's faces
// and edges (coplanar and collinear by the hundred), repeated points, points
// a few ulps off a face, and flat sets. For each: the faces close up (every
// directed edge has its twin), every point is inside or on every face's
// plane (exact), the hull's vertices are input points, each group's ball
// holds its vertices, and the support queries (hull_support,
// hull_support_near, hull_climb's climbs) agree with a scan of all points.
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <set>
#include <utility>
#include <vector>

#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>

extern "C" {  // this cmocka.h has no C++ guard
#include <cmocka.h>
}

#include "../scene/scene_meshes.h"
#include "narrow/hull.hpp"
#include "oracle.h"
#include "test_rng.h"

namespace {

// Each group's ball holds its rows (the padding repeats vertex 0).
void check_groups(const hgcd::Hull &h) {
    const size_t n = h.padded(), stride = h.group_stride();
    assert_true(n % hgcd::Hull::kGroup == 0 && n >= h.size && n < h.size + hgcd::Hull::kGroup);
    for (size_t i = 0; i < n; ++i) {
        const size_t v = i < h.size ? i : 0, g = i / hgcd::Hull::kGroup;
        double d2 = 0;
        for (int k = 0; k < 3; ++k) {
            assert_true(h.rows[k * n + i] == h.xyz[3 * v + k]);
            const double d = h.rows[k * n + i] - h.groups[k * stride + g];
            d2 += d * d;
        }
        assert_true(std::sqrt(d2) <= h.groups[3 * stride + g]);
    }
}

// hull_support answers as a scan of every vertex in order would: the
// largest computed projection, at the lowest index that has it. Directions
// at random, along the axes and diagonals, zero, tiny and huge.
void check_supports(const hgcd::Hull &h) {
    rng r;
    r.s = 5;
    std::vector<std::vector<double>> dirs;
    for (int t = 0; t < 300; ++t) dirs.push_back({unif(&r) - 0.5, unif(&r) - 0.5, unif(&r) - 0.5});
    for (int d = 1; d < 27; ++d) dirs.push_back({double(d % 3 - 1), double(d / 3 % 3 - 1), double(d / 9 - 1)});
    dirs.push_back({0, 0, 0});
    for (double s : {1e-310, 1e-200, 1e200, 1e305}) dirs.push_back({s * 0.3, -s * 0.7, s * 0.1});
    size_t answered = 0;
    for (const auto &d : dirs) {
        double want = -INFINITY, best;
        uint32_t at = 0;
        for (uint32_t i = 0; i < h.size; ++i) {
            const double *p = &h.xyz[3 * size_t(i)];
            const double v = (d[0] * p[0] + d[1] * p[1]) + d[2] * p[2];
            if (v > want) want = v, at = i;
        }
        assert_int_equal(hgcd::hull_support(h, d.data(), &best), at);
        assert_true(best == want);
        // hull_support_near, from any start: when it answers, a top, and a
        // bound at least the scan's value and within roundings of it.
        const double n1 = (std::fabs(d[0]) + std::fabs(d[1])) + std::fabs(d[2]);
        for (uint32_t start : {0u, h.size / 2, h.size - 1, at}) {
            double bound;
            const uint32_t c = hgcd::hull_support_near(h, d.data(), start, &bound);
            if (c == UINT32_MAX) continue;
            ++answered;
            assert_true(c < h.size);
            const double *q = &h.xyz[3 * size_t(c)];
            assert_true(bound >= want);
            assert_true(bound <= want + 4e-15 * n1 * h.extent + 1e-299);
            assert_true((d[0] * q[0] + d[1] * q[1]) + d[2] * q[2] >= want - 4e-15 * n1 * h.extent - 1e-299);
        }
    }
    assert_true(answered >= dirs.size());  // (most directions, from most starts)
}

// Checks the hull of pts (all used) exactly; returns its vertex count.
uint32_t check_hull(const std::vector<double> &pts) {
    const std::vector<char> used(pts.size() / 3, 1);
    std::vector<uint32_t> faces;
    const hgcd::Hull h = hgcd::build_hull(pts.data(), used, 1u << 20, &faces);
    assert_true(h.size >= 4);
    // Closed: each directed edge once, with its twin.
    std::set<std::pair<uint32_t, uint32_t>> edges;
    for (size_t f = 0; f < faces.size(); f += 3)
        for (int k = 0; k < 3; ++k) assert_true(edges.insert({faces[f + k], faces[f + (k + 1) % 3]}).second);
    for (const auto &e : edges) assert_true(edges.count({e.second, e.first}) == 1);
    // Every point inside or on every face (orient3d >= 0: below the plane).
    for (size_t f = 0; f < faces.size(); f += 3)
        for (size_t i = 0; i < pts.size() / 3; ++i)
            assert_true(oracle_orient3d(&pts[3 * faces[f]], &pts[3 * faces[f + 1]], &pts[3 * faces[f + 2]],
                                        &pts[3 * i]) >= 0);
    // The vertices are the faces' corners, each once (numbered in groups).
    std::set<uint32_t> corners(faces.begin(), faces.end());
    assert_int_equal(corners.size(), h.size);
    std::set<std::vector<double>> want, have;
    for (uint32_t v : corners) want.insert({pts[3 * v], pts[3 * v + 1], pts[3 * v + 2]});
    for (uint32_t k = 0; k < h.size; ++k) have.insert({h.xyz[3 * k], h.xyz[3 * k + 1], h.xyz[3 * k + 2]});
    assert_true(want == have);
    check_groups(h);
    check_supports(h);
    // Supports: the largest projection over all points is reached at a
    // hull vertex (up to the rounding of the projections).
    rng r;
    r.s = 99;
    double scale = 0;
    for (double x : pts) scale = std::fmax(scale, std::fabs(x));
    for (int t = 0; t < 200; ++t) {
        const double d[3] = {unif(&r) - 0.5, unif(&r) - 0.5, unif(&r) - 0.5};
        double best, all = -INFINITY;
        const uint32_t at = hgcd::hull_support(h, d, &best);
        assert_true(at < h.size);
        const double *p = &h.xyz[3 * size_t(at)];
        assert_true(best == (d[0] * p[0] + d[1] * p[1]) + d[2] * p[2]);
        for (size_t i = 0; i < pts.size() / 3; ++i)
            all = std::fmax(all, (d[0] * pts[3 * i] + d[1] * pts[3 * i + 1]) + d[2] * pts[3 * i + 2]);
        assert_true(all <= best + 1e-14 * scale);
        // A climb, from the seeds or from any vertex, reaches the top.
        for (uint32_t start : {UINT32_MAX, uint32_t(t) % h.size}) {
            const uint32_t c = hgcd::hull_climb(h, d, start);
            assert_true(c < h.size);
            const double *q = &h.xyz[3 * size_t(c)];
            assert_true((d[0] * q[0] + d[1] * q[1]) + d[2] * q[2] >= best - 1e-14 * scale);
        }
    }
    return h.size;
}

void test_random_points(void **) {
    rng r;
    r.s = 1;
    for (int round = 0; round < 20; ++round) {
        std::vector<double> pts;
        const int n = 4 + round * 37;
        for (int i = 0; i < 3 * n; ++i) pts.push_back((unif(&r) - 0.5) * std::ldexp(1.0, round - 10));
        check_hull(pts);
    }
    // Tiny and large coordinates.
    for (int e : {-250, -200, 45}) {
        std::vector<double> pts;
        for (int i = 0; i < 3 * 300; ++i) pts.push_back((unif(&r) - 0.5) * std::ldexp(1.0, e));
        check_hull(pts);
    }
}

void test_blob(void **) {
    const uint32_t nu = 92, nv = 28;
    std::vector<double> v(3 * hgcd_blob_vertex_count(nu, nv));
    std::vector<uint32_t> t(3 * hgcd_blob_triangle_count(nu, nv));
    hgcd_blob_mesh(nu, nv, v.data(), t.data());
    for (size_t i = 0; i < v.size(); i += 3) v[i] *= 2.5;
    const uint32_t n = check_hull(v);
    assert_true(n < v.size() / 3 / 4);  // far fewer than the points: a dented shape
}

// Points of an n x n x n integer grid on the cube's surface, in an order
// that puts face and edge points before corners.
void test_cube_surface(void **) {
    const int n = 9;
    std::vector<double> pts;
    for (int x = 0; x < n; ++x)
        for (int y = 0; y < n; ++y)
            for (int z = 0; z < n; ++z)
                if (x == 0 || y == 0 || z == 0 || x == n - 1 || y == n - 1 || z == n - 1) {
                    const bool corner = (x % (n - 1) == 0) + (y % (n - 1) == 0) + (z % (n - 1) == 0) == 3;
                    if (!corner) pts.insert(pts.end(), {double(x), double(y), double(z)});
                }
    const double e = n - 1;
    for (int c = 0; c < 8; ++c) pts.insert(pts.end(), {(c & 1) * e, (c >> 1 & 1) * e, (c >> 2) * e});
    check_hull(pts);
    // Each point twice.
    std::vector<double> twice = pts;
    twice.insert(twice.end(), pts.begin(), pts.end());
    check_hull(twice);
}

// A tetrahedron with points a few ulps inside, on and outside its faces.
void test_near_faces(void **) {
    std::vector<double> pts = {0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1};
    rng r;
    r.s = 7;
    for (int i = 0; i < 400; ++i) {
        const double a = unif(&r), b = unif(&r) * (1 - a);
        double p[3] = {a, b, 1 - a - b};  // on the slanted face (rounded)
        const int ulps = int(unif(&r) * 5) - 2;
        for (double &x : p)
            for (int k = 0; k < std::abs(ulps); ++k) x = std::nextafter(x, ulps > 0 ? 2.0 : -1.0);
        if (i % 3 == 0) p[i % 2] = 0;  // on a coordinate face too
        pts.insert(pts.end(), p, p + 3);
    }
    check_hull(pts);
}

void test_flat_sets(void **) {
    std::vector<double> plane, line;
    for (int i = 0; i < 50; ++i) {
        plane.insert(plane.end(), {double(i % 7), double(i / 7), 3.0});
        line.insert(line.end(), {double(i), 2.0 * i, -1.0 * i});
    }
    for (const auto *pts : {&plane, &line}) {
        const std::vector<char> used(pts->size() / 3, 1);
        assert_int_equal(hgcd::build_hull(pts->data(), used, 1u << 20).size, 0);
    }
    // Too many vertices: none.
    std::vector<double> ball;
    rng r;
    r.s = 3;
    while (ball.size() < 3 * 2000) {
        const double p[3] = {unif(&r) - 0.5, unif(&r) - 0.5, unif(&r) - 0.5};
        const double len = std::sqrt(p[0] * p[0] + p[1] * p[1] + p[2] * p[2]);
        if (len > 0.1) ball.insert(ball.end(), {p[0] / len, p[1] / len, p[2] / len});
    }
    const std::vector<char> used(ball.size() / 3, 1);
    assert_int_equal(hgcd::build_hull(ball.data(), used, 256).size, 0);
    // Unused points are left out.
    std::vector<char> some(used);
    some[0] = 0;
    const hgcd::Hull h = hgcd::build_hull(ball.data(), some, 1u << 20);
    assert_int_equal(h.size, 1999);
    check_groups(h);
    check_supports(h);  // (more groups than hull_support bounds: a plain scan)
    // Points on a sphere, up to the size bound's groups.
    ball.resize(3 * 1000);
    const hgcd::Hull g = hgcd::build_hull(ball.data(), std::vector<char>(1000, 1), 1u << 20);
    assert_int_equal(g.size, 1000);
    assert_true(g.group_count() <= hgcd::Hull::kMaxGroups);
    check_groups(g);
    check_supports(g);
}

}  // namespace

int main() {
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_random_points), cmocka_unit_test(test_blob), cmocka_unit_test(test_cube_surface),
        cmocka_unit_test(test_near_faces), cmocka_unit_test(test_flat_sets),
    };
    return cmocka_run_group_tests(tests, nullptr, nullptr);
}
