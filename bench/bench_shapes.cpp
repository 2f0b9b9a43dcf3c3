// bench_shapes: worlds of other shapes than tetrahedra, hgcd beside FCL's
// full pipeline (dynamic AABB tree + per-pair collide) in the same run.
//
//   bench_shapes --scene scanned|boxes|icospheres|meshes|mixed|resting [--n N]
//                [--side L] [--seed S] [--threads K] [--ticks T]
//                [--turn A] [--no-fcl] [--commit HASH]
//
// Scenes (placement, velocities and the motion of scene `tetra`,
// hgcd_scene_tetra_generate / _move; docs/scenes.md):
//   scanned     n = 20000 instances of one closed non-convex mesh of 4968
//               triangles (the blob of scene `meshes` at 92 x 28, stretched
//               2.5x along x, as a scanned part is longer than wide), all of
//               one size (circumradius 1.5), side 86: about 65,000 candidate pairs.
//   boxes       n = 750000 cubes (12 triangles) of the tetrahedra's
//               circumradii, side 200: scene `tetra` with boxes.
//   icospheres  n = 50000 icospheres of 80 triangles, circumradius = the
//               scene's radius, side 81 (the density of `tetra`).
//   meshes      n = 1000 blobs of 2976 triangles (scene `meshes`), side 30.
//   mixed       n = 20000, side 100: by index mod 4 scanned meshes, boxes,
//               icospheres (80 triangles) and boxes again, plus every 2000th
//               body a box or an icosphere 50x the median size.
//   resting     n = 100000 unit cubes, axis-aligned, in stacks of 8 on a
//               grid of spacing 1.25 (side: the grid's extent), each cube's
//               faces exactly on those above and below it; each tick they
//               slide 0.01 in their own direction in x and y (no turn), so
//               the stacked pairs stay exactly touching: the degenerate
//               case of resting contact, every colliding pair touching.
// Sizes other than `scanned`'s are rounded to one of 16 log-spaced values
// (both libraries get the same ones), because FCL has no per-object scale:
// each (shape, size) is one FCL model shared by its bodies.
//
// Each tick the caller moves the centres and turns every body by about A
// radians (default 0.01) about its velocity direction (bench_hgcd's engine
// mode), then hands the poses to hgcd with one hgcd_body_set_pose per body
// and calls hgcd_world_detect; FCL gets setTransform + computeAABB per
// object, DynamicAABBTreeCollisionManager::update, then collide whose
// callback runs fcl::collide (one contact wanted) on each candidate. Boxes
// are fcl::Box (FCL's box-box test), every other shape a BVHModel<OBBRSS>.
// Tick 0 (creation, first detect, tree setup) is not timed; medians over the
// T following ticks, hgcd's and FCL's ticks alternating.
//
// One JSON line: hgcd's set_pose and detect medians, narrow_ms, candidates,
// colliding pairs, detect cost per candidate (ns); FCL's tick median, its
// candidates and pairs; the ratio fcl_ms / hgcd_detect_ms, and
// fcl_over_hgcd_tick_cpu, the median over ticks of FCL's tick over hgcd's
// set_pose + detect in the same tick (process CPU: a host whose speed
// shifts between runs moves both sides of a tick's ratio alike); and the pair sets
// compared on the last tick: fcl_only, hgcd_only (beyond hgcd's containment
// pairs, which FCL's surface test of meshes misses) — FCL rounds its own
// way, so touching pairs may differ. pairs_fnv hashes hgcd's pairs of every
// tick (a check that a change kept the pairs).
//
// FCL's pkg-config adds -std=c++11: this file is C++11.
#include <hgcd/hgcd.h>
#include <hgcd/hgcd_scene.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <ctime>
#include <memory>
#include <string>
#include <vector>

#include "../src/common/transform.hpp"
#include "../scene/scene_meshes.h"
#include "../scene/scene_shapes.h"
#include "turn.h"

#ifdef HGCD_BENCH_FCL
#include <fcl/broadphase/broadphase_dynamic_AABB_tree.h>
#include <fcl/geometry/bvh/BVH_model.h>
#include <fcl/geometry/shape/box.h>
#include <fcl/narrowphase/collision.h>

#include "fcl_pairs.hpp"
#endif

namespace {

double now() {
    return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

// Process CPU time: on a shared, loaded machine wall time also counts the
// time other processes hold the cores (the runs here are serial, or all
// threads busy).
double cpu_now() {
    timespec ts;
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
    return double(ts.tv_sec) + 1e-9 * double(ts.tv_nsec);
}

double median(std::vector<double> v) {
    if (v.empty()) return 0;
    std::sort(v.begin(), v.end());
    const size_t m = v.size() / 2;
    return v.size() % 2 ? v[m] : 0.5 * (v[m - 1] + v[m]);
}

void check(hgcd_status s, hgcd_world *w, const char *what) {
    if (s == HGCD_OK) return;
    std::fprintf(stderr, "%s failed: %s (%s)\n", what, hgcd_status_string(s), w ? hgcd_world_last_error(w) : "");
    std::exit(1);
}

struct Shape {
    std::vector<double> v;
    std::vector<uint32_t> t;
    double reach = 0;  // largest vertex distance from the origin
    bool box = false;  // the cube [-1, 1]^3
    void finish() {
        for (size_t i = 0; i < v.size(); i += 3)
            reach = std::max(reach, std::sqrt(v[i] * v[i] + v[i + 1] * v[i + 1] + v[i + 2] * v[i + 2]));
    }
};

Shape blob(uint32_t nu, uint32_t nv, double stretch) {
    Shape s;
    s.v.resize(3 * size_t(hgcd_blob_vertex_count(nu, nv)));
    s.t.resize(3 * size_t(hgcd_blob_triangle_count(nu, nv)));
    hgcd_blob_mesh(nu, nv, s.v.data(), s.t.data());
    for (size_t i = 0; i < s.v.size(); i += 3) s.v[i] *= stretch;
    s.finish();
    return s;
}

Shape cube() {
    Shape s;
    s.v.resize(24);
    s.t.resize(36);
    hgcd_box_mesh(1, 1, 1, s.v.data(), s.t.data());
    s.box = true;
    s.finish();
    return s;
}

Shape icosphere(int level) {
    Shape s;
    s.v.resize(3 * size_t(hgcd_icosphere_vertex_count(level)));
    s.t.resize(3 * size_t(hgcd_icosphere_triangle_count(level)));
    std::vector<uint32_t> scratch(5 * size_t(hgcd_icosphere_triangle_count(level)));
    hgcd_icosphere(level, s.v.data(), s.t.data(), scratch.data());
    s.finish();
    return s;
}

// Body i: shape kind[i] at size (circumradius) size[i].
struct Scene {
    std::vector<Shape> shapes;
    std::vector<uint32_t> kind;
    std::vector<double> size, centers, quats, velocities, turns;
    double side = 200;
};

// One of 16 log-spaced sizes per octave-ish step over [0.25, 2] (the
// scene's radius range), or 50x the median for giants.
double bucket(double r) {
    const double lo = std::log(0.25), hi = std::log(2.0);
    const int k = std::min(15, std::max(0, int(std::floor((std::log(r) - lo) / (hi - lo) * 16))));
    return std::exp(lo + (k + 0.5) * (hi - lo) / 16);
}

void make_turns(Scene &s, double turn) {
    const size_t n = s.kind.size();
    s.turns.resize(4 * n);
    const double h = 0.5 * turn;
    for (size_t i = 0; i < n; ++i) {
        const double *v = &s.velocities[3 * i];
        const double speed = std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
        double axis[3] = {0, 0, 1};
        if (speed > 0)
            for (int k = 0; k < 3; ++k) axis[k] = v[k] / speed;
        const double norm = std::sqrt(1 + h * h);
        for (int k = 0; k < 3; ++k) s.turns[4 * i + k] = h * axis[k] / norm;
        s.turns[4 * i + 3] = 1 / norm;
    }
}

void turn_bodies(Scene &s) {
    for (size_t i = 0; i < s.kind.size(); ++i) {
        turn_orientation(&s.quats[4 * i], &s.turns[4 * i]);
    }
}

// Scene `resting` (above): cubes of half side 0.5 (size 0.5 reach: the
// scale is exactly 0.5), centres and heights exact.
Scene resting_scene(uint64_t n, uint64_t seed) {
    Scene s;
    s.shapes.push_back(cube());
    const uint64_t stacks = (n + 7) / 8, row = uint64_t(std::ceil(std::sqrt(double(stacks))));
    s.side = 1.25 * double(row);
    s.kind.assign(n, 0);
    s.size.assign(n, 0.5 * s.shapes[0].reach);
    s.centers.resize(3 * n);
    s.quats.assign(4 * n, 0.0);
    s.velocities.assign(3 * n, 0.0);
    uint64_t z = seed * 0x9E3779B97F4A7C15ull + 1;
    for (uint64_t i = 0; i < n; ++i) {
        const uint64_t stack = i / 8;
        s.centers[3 * i] = 1.25 * double(stack % row) + 0.625;
        s.centers[3 * i + 1] = 1.25 * double(stack / row) + 0.625;
        s.centers[3 * i + 2] = 0.5 + double(i % 8);
        s.quats[4 * i + 3] = 1;
        z = z * 6364136223846793005ull + 1442695040888963407ull;
        const double angle = double(z >> 11) / 9007199254740992.0 * 6.283185307179586;
        s.velocities[3 * i] = 0.01 * std::cos(angle);
        s.velocities[3 * i + 1] = 0.01 * std::sin(angle);
    }
    return s;
}

Scene make_scene(const std::string &name, uint64_t n, double side, uint64_t seed) {
    if (name == "resting") return resting_scene(n, seed);
    Scene s;
    hgcd_scene_tetra_desc sd = hgcd_scene_tetra_desc_default();
    sd.n = n;
    sd.seed = seed;
    sd.side = side;
    s.side = side;
    std::vector<double> radii(n);
    s.centers.resize(3 * n);
    s.quats.resize(4 * n);
    s.velocities.resize(3 * n);
    if (hgcd_scene_tetra_generate(&sd, s.centers.data(), radii.data(), nullptr, s.quats.data(),
                                  s.velocities.data()) != HGCD_OK) {
        std::fprintf(stderr, "bad scene parameters\n");
        std::exit(2);
    }
    s.kind.assign(n, 0);
    s.size.resize(n);
    if (name == "scanned") {
        s.shapes.push_back(blob(92, 28, 2.5));
        for (size_t i = 0; i < n; ++i) s.size[i] = 1.5;
        return s;
    }
    if (name == "boxes") {
        s.shapes.push_back(cube());
    } else if (name == "icospheres") {
        s.shapes.push_back(icosphere(1));
    } else if (name == "meshes") {
        s.shapes.push_back(blob(HGCD_BLOB_NU, HGCD_BLOB_NV, 1));
    } else if (name == "mixed") {
        s.shapes.push_back(blob(92, 28, 2.5));
        s.shapes.push_back(cube());
        s.shapes.push_back(icosphere(1));
        for (size_t i = 0; i < n; ++i) s.kind[i] = i % 4 == 3 ? 1 : uint32_t(i % 4);
    } else {
        std::fprintf(stderr, "unknown scene %s\n", name.c_str());
        std::exit(2);
    }
    const double median_size = bucket(std::sqrt(0.25 * 2.0));
    for (size_t i = 0; i < n; ++i) {
        s.size[i] = bucket(radii[i]);
        if (name == "mixed" && i % 2000 == 1999) {
            s.kind[i] = 1 + uint32_t(i / 2000) % 2;
            s.size[i] = 50 * median_size;
        }
    }
    return s;
}

#ifdef HGCD_BENCH_FCL
struct Fcl {
    std::vector<std::shared_ptr<fcl::CollisionGeometryd>> models;  // per (shape, size)
    std::vector<fcl::CollisionObjectd *> objects;
    fcl::DynamicAABBTreeCollisionManagerd manager;
    static void transform(const Scene &s, size_t i, fcl::Transform3d &tf) {
        double r[9];
        hgcd::rotation_entries(s.quats[4 * i], s.quats[4 * i + 1], s.quats[4 * i + 2], s.quats[4 * i + 3], r);
        fcl::Matrix3d m;
        m << r[0], r[1], r[2], r[3], r[4], r[5], r[6], r[7], r[8];
        tf = fcl::Transform3d::Identity();
        tf.linear() = m;
        tf.translation() = fcl::Vector3d(s.centers[3 * i], s.centers[3 * i + 1], s.centers[3 * i + 2]);
    }
    explicit Fcl(const Scene &s) {
        std::vector<std::pair<double, uint32_t>> keys;  // (size, shape) -> model
        std::vector<uint32_t> model_of(s.kind.size());
        for (size_t i = 0; i < s.kind.size(); ++i) {
            const std::pair<double, uint32_t> key(s.size[i], s.kind[i]);
            size_t m = std::find(keys.begin(), keys.end(), key) - keys.begin();
            if (m == keys.size()) {
                keys.push_back(key);
                const Shape &sh = s.shapes[key.second];
                const double scale = key.first / sh.reach;
                if (sh.box) {
                    models.push_back(std::make_shared<fcl::Boxd>(2 * scale, 2 * scale, 2 * scale));
                } else {
                    std::vector<fcl::Vector3d> points(sh.v.size() / 3);
                    std::vector<fcl::Triangle> tris(sh.t.size() / 3);
                    for (size_t v = 0; v < points.size(); ++v)
                        points[v] = fcl::Vector3d(scale * sh.v[3 * v], scale * sh.v[3 * v + 1], scale * sh.v[3 * v + 2]);
                    for (size_t t = 0; t < tris.size(); ++t) tris[t] = fcl::Triangle(sh.t[3 * t], sh.t[3 * t + 1], sh.t[3 * t + 2]);
                    auto model = std::make_shared<fcl::BVHModel<fcl::OBBRSSd>>();
                    model->beginModel();
                    model->addSubModel(points, tris);
                    model->endModel();
                    models.push_back(model);
                }
            }
            model_of[i] = uint32_t(m);
        }
        for (size_t i = 0; i < s.kind.size(); ++i) {
            fcl::Transform3d tf;
            transform(s, i, tf);
            fcl::CollisionObjectd *o = new fcl::CollisionObjectd(models[model_of[i]], tf);
            o->setUserData(reinterpret_cast<void *>(uintptr_t(i)));
            objects.push_back(o);
        }
        manager.registerObjects(objects);
        manager.setup();
    }
    ~Fcl() {
        manager.clear();
        for (size_t i = 0; i < objects.size(); ++i) delete objects[i];
    }
    FclPairs tick(const Scene &s) {
        FclPairs d;
        for (size_t i = 0; i < objects.size(); ++i) {
            fcl::Transform3d tf;
            transform(s, i, tf);
            objects[i]->setTransform(tf);
            objects[i]->computeAABB();
        }
        manager.update();
        manager.collide(&d, FclPairs::callback);
        std::sort(d.pairs.begin(), d.pairs.end());
        return d;
    }
};
#endif

std::vector<uint64_t> hgcd_pairs(hgcd_world *w, uint64_t &fnv) {
    const hgcd_pair *p;
    size_t count;
    check(hgcd_world_pairs(w, &p, &count), w, "world_pairs");
    std::vector<uint64_t> out(count);
    for (size_t k = 0; k < count; ++k) {
        out[k] = (uint64_t(p[k].a.index) << 32) | p[k].b.index;
        const uint32_t ab[2] = {p[k].a.index, p[k].b.index};
        const unsigned char *byte = reinterpret_cast<const unsigned char *>(ab);
        for (size_t i = 0; i < sizeof ab; ++i) fnv = (fnv ^ byte[i]) * 1099511628211ull;
    }
    std::sort(out.begin(), out.end());
    return out;
}

}  // namespace

int main(int argc, char **argv) {
    std::string scene = "scanned";
    uint64_t n = 0, seed = 1;
    double side = 0, turn = 0.01;
    uint32_t threads = 1;
    int ticks = 5;
    bool fcl = true;
    const char *commit = "unknown";
    for (int i = 1; i < argc; ++i) {
        const std::string a = argv[i];
        const bool has = i + 1 < argc;
        if (a == "--scene" && has) scene = argv[++i];
        else if (a == "--n" && has) n = std::strtoull(argv[++i], nullptr, 10);
        else if (a == "--side" && has) side = std::atof(argv[++i]);
        else if (a == "--seed" && has) seed = std::strtoull(argv[++i], nullptr, 10);
        else if (a == "--threads" && has) threads = uint32_t(std::atoi(argv[++i]));
        else if (a == "--ticks" && has) ticks = std::max(1, std::atoi(argv[++i]));
        else if (a == "--turn" && has) turn = std::atof(argv[++i]);
        else if (a == "--commit" && has) commit = argv[++i];
        else if (a == "--no-fcl") fcl = false;
        else {
            std::fprintf(stderr,
                         "usage: %s --scene scanned|boxes|icospheres|meshes|mixed|resting [--n N] [--side L] [--seed S]\n"
                         "          [--threads K] [--ticks T] [--turn A] [--no-fcl] [--commit HASH]\n",
                         argv[0]);
            return 2;
        }
    }
    struct Default {
        const char *name;
        uint64_t n;
        double side;
    } defaults[] = {{"scanned", 20000, 86}, {"boxes", 750000, 200}, {"icospheres", 50000, 81},
                    {"meshes", 1000, 30},    {"mixed", 20000, 100},     {"resting", 100000, 0}};
    for (const Default &d : defaults)
        if (scene == d.name) {
            if (n == 0) n = d.n;
            if (side == 0) side = d.side;
        }
    if (scene == "resting") turn = 0;  // (a turn would end the exact touching)
    Scene s = make_scene(scene, n, side, seed);
    make_turns(s, turn);

    hgcd_world_desc wd = hgcd_world_desc_default();
    wd.thread_count = threads;
    wd.thread_policy = HGCD_THREADS_FIXED;
    hgcd_world *w;
    check(hgcd_world_create(&wd, &w), nullptr, "world_create");
    std::vector<hgcd_mesh> meshes;
    for (const Shape &sh : s.shapes) {
        hgcd_mesh_desc md = hgcd_mesh_desc_default();
        md.vertices = sh.v.data();
        md.triangles = sh.t.data();
        md.vertex_count = uint32_t(sh.v.size() / 3);
        md.triangle_count = uint32_t(sh.t.size() / 3);
        hgcd_mesh m;
        check(hgcd_mesh_create(w, &md, &m), w, "mesh_create");
        meshes.push_back(m);
    }
    std::vector<hgcd_body> bodies(n);
    for (uint64_t i = 0; i < n; ++i) {
        hgcd_body_desc bd = hgcd_body_desc_default();
        bd.mesh = meshes[s.kind[i]];
        std::memcpy(bd.position, &s.centers[3 * i], 3 * sizeof(double));
        std::memcpy(bd.orientation, &s.quats[4 * i], 4 * sizeof(double));
        bd.scale = s.size[i] / s.shapes[s.kind[i]].reach;
        check(hgcd_body_create(w, &bd, &bodies[i]), w, "body_create");
    }
    check(hgcd_world_detect(w), w, "world_detect");
#ifdef HGCD_BENCH_FCL
    std::unique_ptr<Fcl> f;
    if (fcl) f.reset(new Fcl(s));
    std::vector<double> fcl_ms, fcl_cpu_ms, tick_ratio;  // tick_ratio: FCL's tick / hgcd's (set_pose + detect), CPU
    FclPairs fd;
#else
    (void)fcl;
#endif
    std::vector<double> pose_ms, detect_ms, narrow_ms, detect_cpu_ms, tick_cpu_ms;
    hgcd_stats st;
    uint64_t fnv = 14695981039346656037ull;
    std::vector<uint64_t> mine;
    for (int k = 0; k < ticks; ++k) {
        hgcd_scene_tetra_move(n, s.side, s.centers.data(), s.velocities.data());
        if (turn > 0) turn_bodies(s);
        const double t0 = now(), c0 = cpu_now();
        for (uint64_t i = 0; i < n; ++i)
            check(hgcd_body_set_pose(w, bodies[i], &s.centers[3 * i], &s.quats[4 * i]), w, "set_pose");
        const double t1 = now(), c1 = cpu_now();
        check(hgcd_world_detect(w), w, "world_detect");
        const double t2 = now(), c2 = cpu_now();
        detect_cpu_ms.push_back(1e3 * (c2 - c1));
        tick_cpu_ms.push_back(1e3 * (c2 - c0));
        pose_ms.push_back(1e3 * (t1 - t0));
        detect_ms.push_back(1e3 * (t2 - t1));
        std::memset(&st, 0, sizeof st);
        st.struct_size = sizeof st;
        check(hgcd_world_stats(w, &st), w, "world_stats");
        narrow_ms.push_back(1e3 * st.narrow_seconds);
        mine = hgcd_pairs(w, fnv);
#ifdef HGCD_BENCH_FCL
        if (f) {
            const double t3 = now(), c3 = cpu_now();
            fd = f->tick(s);
            fcl_ms.push_back(1e3 * (now() - t3));
            fcl_cpu_ms.push_back(1e3 * (cpu_now() - c3));
            tick_ratio.push_back(fcl_cpu_ms.back() / tick_cpu_ms.back());
        }
#endif
    }
    const double detect = median(detect_ms), detect_cpu = median(detect_cpu_ms);
    std::printf("{\"scene\":\"%s\",\"commit\":\"%s\",\"n\":%llu,\"side\":%g,\"seed\":%llu,\"threads\":%u,\"ticks\":%d,"
                "\"turn\":%g,\"set_pose_ms\":%.3f,\"detect_ms\":%.3f,\"detect_cpu_ms\":%.3f,\"narrow_ms\":%.3f,\"candidate_pairs\":%llu,"
                "\"colliding_pairs\":%llu,\"containment_pairs\":%llu,\"ns_per_candidate\":%.1f,\"pairs_fnv\":\"%016llx\"",
                scene.c_str(), commit, (unsigned long long)n, s.side, (unsigned long long)seed, st.thread_count,
                ticks, turn, median(pose_ms), detect, detect_cpu, median(narrow_ms), (unsigned long long)st.candidate_pairs,
                (unsigned long long)st.colliding_pairs, (unsigned long long)st.containment_pairs,
                st.candidate_pairs ? 1e6 * detect_cpu / double(st.candidate_pairs) : 0.0, (unsigned long long)fnv);
#ifdef HGCD_BENCH_FCL
    if (f) {
        std::vector<uint64_t> fcl_only, hgcd_only;
        std::set_difference(fd.pairs.begin(), fd.pairs.end(), mine.begin(), mine.end(), std::back_inserter(fcl_only));
        std::set_difference(mine.begin(), mine.end(), fd.pairs.begin(), fd.pairs.end(), std::back_inserter(hgcd_only));
        const double fm = median(fcl_ms), fc = median(fcl_cpu_ms);
        std::printf(",\"fcl_ms\":%.3f,\"fcl_cpu_ms\":%.3f,\"fcl_candidates\":%llu,\"fcl_pairs\":%llu,"
                    "\"fcl_ns_per_candidate\":%.1f,\"fcl_only\":%llu,\"hgcd_only\":%llu,\"fcl_over_hgcd_detect\":%.2f,"
                    "\"fcl_over_hgcd_detect_cpu\":%.2f,\"fcl_over_hgcd_tick_cpu\":%.2f",
                    fm, fc, (unsigned long long)fd.candidates, (unsigned long long)fd.pairs.size(),
                    fd.candidates ? 1e6 * fc / double(fd.candidates) : 0.0, (unsigned long long)fcl_only.size(),
                    (unsigned long long)hgcd_only.size(), fm / detect, fc / detect_cpu, median(tick_ratio));
    }
#endif
    std::printf("}\n");
    hgcd_world_destroy(w);
    return 0;
}
