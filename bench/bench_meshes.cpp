// bench_meshes: hgcd on large non-convex meshes (scene `meshes`,
// docs/scenes.md), against FCL's BVHModel<OBBRSS> mesh-mesh
// collision on the same scene in the same run.
//
//   bench_meshes [--n N] [--side L] [--seed S] [--threads K] [--reps R]
//                [--nu U --nv V] [--contact-nu U --contact-nv V]
//                [--no-fcl] [--no-contact] [--commit HASH]
//
// Prints JSON lines on stdout (diagnostics on stderr):
//
//  1. "case":"contact" (unless --no-contact): two blobs of 2*U*(V-1)
//     triangles (default 100 x 51: 10000 triangles, 5002 vertices each) in a
//     2-body world, one thread. The second body is moved along a fixed
//     direction by bisection on the distance down to adjacent doubles, so
//     that at `touch` the surfaces share a point and at `apart` (one unit in
//     the last place further) they do not: the shallowest contact there is.
//     Also `overlap` (centre distance 0.8 of the touching one). Reported per
//     configuration: the median over R*200 calls of hgcd_world_detect's
//     wall time (detect_us) and of the narrow phase's own timer
//     (narrow_us), the triangle tests of one detect, and for reference the
//     time to transform all vertices of both bodies once (transform_all_us),
//     which is what the narrow phase would pay per pair without lazy
//     per-vertex transforms.
//  2. "case":"scene": scene `meshes` with n bodies: hgcd_world_detect at the
//     initial poses, R repetitions (the first one cold: grid built from
//     nothing), median, minimum and first reported; with FCL (when compiled
//     in and not --no-fcl): a DynamicAABBTreeCollisionManager over one
//     BVHModel<OBBRSS> per body (FCL has no per-object scale, so each body
//     gets its own model of pre-scaled vertices; building them is setup, not
//     timed), candidate pairs from manager.collide, each decided by
//     fcl::collide with one contact wanted; R repetitions of
//     (manager.update + collide), alternating with hgcd's so that load on a
//     shared machine hits both alike, median, minimum and first reported,
//     and hgcd's speedup (ratio of medians and of minima). Then the pair
//     sets are compared: fcl_only (FCL reports, hgcd not), hgcd_only (hgcd
//     reports, FCL not) and hgcd's containment count: FCL tests only
//     surfaces, so it misses every pair where one blob lies inside another.
//
// Pose and rotation given to FCL: the rotation matrix of hgcd.h's formula and
// the centre; the model's vertices are scale * mesh vertex, exactly hgcd's
// local vertices. FCL then rounds its own way, so near-tangent pairs could
// differ by rounding (reported as fcl_only / hgcd_only beyond containment).
//
// FCL's pkg-config adds -std=c++11: this file is C++11.
#include <hgcd/hgcd.h>
#include <hgcd/hgcd_scene.h>

#include <sys/resource.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <memory>
#include <string>
#include <vector>

#include "../src/common/transform.hpp"
#include "../scene/scene_meshes.h"

#ifdef HGCD_BENCH_FCL
#include <fcl/broadphase/broadphase_dynamic_AABB_tree.h>
#include <fcl/geometry/bvh/BVH_model.h>
#include <fcl/narrowphase/collision.h>

#include "fcl_pairs.hpp"
#endif

namespace {

double now() {
    return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

double median(std::vector<double> v) {
    if (v.empty()) return 0;
    std::sort(v.begin(), v.end());
    const size_t m = v.size() / 2;
    return v.size() % 2 ? v[m] : 0.5 * (v[m - 1] + v[m]);
}

double peak_rss_mb() {
    struct rusage ru;
    getrusage(RUSAGE_SELF, &ru);
    return ru.ru_maxrss / 1024.0;
}

void check(hgcd_status s, hgcd_world *w, const char *what) {
    if (s == HGCD_OK) return;
    std::fprintf(stderr, "%s failed: %s (%s)\n", what, hgcd_status_string(s), w ? hgcd_world_last_error(w) : "");
    std::exit(1);
}

struct Blob {
    std::vector<double> v;
    std::vector<uint32_t> t;
    Blob(uint32_t nu, uint32_t nv)
        : v(3 * size_t(hgcd_blob_vertex_count(nu, nv))), t(3 * size_t(hgcd_blob_triangle_count(nu, nv))) {
        hgcd_blob_mesh(nu, nv, v.data(), t.data());
    }
    uint32_t vertex_count() const { return uint32_t(v.size() / 3); }
    uint32_t triangle_count() const { return uint32_t(t.size() / 3); }
};

hgcd_mesh make_mesh(hgcd_world *w, const Blob &b) {
    hgcd_mesh_desc md = hgcd_mesh_desc_default();
    md.vertices = b.v.data();
    md.triangles = b.t.data();
    md.vertex_count = b.vertex_count();
    md.triangle_count = b.triangle_count();
    hgcd_mesh m;
    check(hgcd_mesh_create(w, &md, &m), w, "mesh_create");
    return m;
}

// hgcd.h's rotation matrix, as the library computes it (src/transform.hpp).
void rotation(const double *q, double *r) { hgcd::rotation_entries(q[0], q[1], q[2], q[3], r); }

bool colliding(hgcd_world *w) {
    const hgcd_pair *p;
    size_t n;
    check(hgcd_world_detect(w), w, "world_detect");
    check(hgcd_world_pairs(w, &p, &n), w, "world_pairs");
    return n == 1;
}

// ------------------------------------------------------------ contact case

void contact_case(uint32_t nu, uint32_t nv, int reps, const char *commit) {
    const Blob blob(nu, nv);
    hgcd_world_desc wd = hgcd_world_desc_default();
    wd.thread_count = 1;
    hgcd_world *w;
    check(hgcd_world_create(&wd, &w), nullptr, "world_create");
    const hgcd_mesh mesh = make_mesh(w, blob);
    const double qa[4] = {0.18257418583505536, 0.3651483716701107, 0.5477225575051661, 0.7302967433402214};
    const double qb[4] = {-0.5, 0.5, 0.5, 0.5};
    const double pa[3] = {0.1, 0.2, 0.3};
    const double u[3] = {0.6, 0.48, 0.64};  // unit length up to rounding
    hgcd_body_desc bd = hgcd_body_desc_default();
    bd.mesh = mesh;
    std::memcpy(bd.position, pa, sizeof pa);
    std::memcpy(bd.orientation, qa, sizeof qa);
    hgcd_body a, b;
    check(hgcd_body_create(w, &bd, &a), w, "body_create");
    std::memcpy(bd.orientation, qb, sizeof qb);
    check(hgcd_body_create(w, &bd, &b), w, "body_create");
    auto place = [&](double t) {
        double p[3];
        for (int k = 0; k < 3; ++k) p[k] = pa[k] + t * u[k];
        check(hgcd_body_set_pose(w, b, p, nullptr), w, "body_set_pose");
    };
    double lo = 0, hi = 3.5;  // radii below 1.45: apart at 3.5
    for (;;) {
        const double mid = 0.5 * lo + 0.5 * hi;
        if (mid <= lo || mid >= hi) break;
        place(mid);
        if (colliding(w)) lo = mid;
        else hi = mid;
    }
    // Transforming every vertex of both bodies once, as a per-pair eager
    // transform would.
    double transform_all_us;
    {
        double r[9];
        rotation(qa, r);
        std::vector<double> out(blob.v.size());
        std::vector<double> times;
        double sink = 0;
        for (int it = 0; it < 200; ++it) {
            const double t0 = now();
            for (int body = 0; body < 2; ++body)
                for (size_t i = 0; i < blob.v.size(); i += 3) {
                    const double lx = blob.v[i], ly = blob.v[i + 1], lz = blob.v[i + 2];
                    out[i] = pa[0] + ((r[0] * lx + r[1] * ly) + r[2] * lz);
                    out[i + 1] = pa[1] + ((r[3] * lx + r[4] * ly) + r[5] * lz);
                    out[i + 2] = pa[2] + ((r[6] * lx + r[7] * ly) + r[8] * lz);
                }
            times.push_back(now() - t0);
            sink += out[it % out.size()];
        }
        transform_all_us = 1e6 * median(times);
        if (sink == 12345.678) std::fprintf(stderr, " ");
    }
    struct Config {
        const char *name;
        double t;
        bool expect;
    } configs[3] = {{"touch", lo, true}, {"apart", hi, false}, {"overlap", 0.8 * lo, true}};
    for (const Config &c : configs) {
        place(c.t);
        std::vector<double> wall, narrow;
        hgcd_stats st;
        bool ok = true;
        for (int it = 0; it < 200 * reps; ++it) {
            const double t0 = now();
            ok &= colliding(w) == c.expect;
            wall.push_back(now() - t0);
            std::memset(&st, 0, sizeof st);
            st.struct_size = sizeof st;
            check(hgcd_world_stats(w, &st), w, "world_stats");
            narrow.push_back(st.narrow_seconds);
        }
        std::printf("{\"lib\":\"hgcd\",\"scene\":\"meshes\",\"case\":\"contact\",\"config\":\"%s\",\"commit\":\"%s\","
                    "\"threads\":1,\"triangles\":%u,\"vertices\":%u,\"distance\":%.17g,\"answer_ok\":%s,"
                    "\"detect_us\":%.2f,\"narrow_us\":%.2f,\"triangle_tests\":%llu,\"containment\":%llu,"
                    "\"transform_all_us\":%.2f}\n",
                    c.name, commit, blob.triangle_count(), blob.vertex_count(), c.t, ok ? "true" : "false",
                    1e6 * median(wall), 1e6 * median(narrow), (unsigned long long)st.triangle_tests,
                    (unsigned long long)st.containment_pairs, transform_all_us);
        std::fflush(stdout);
    }
    hgcd_world_destroy(w);
}

// -------------------------------------------------------------- scene case

#ifdef HGCD_BENCH_FCL
struct FclScene {
    std::vector<std::shared_ptr<fcl::CollisionGeometryd>> models;
    std::vector<fcl::CollisionObjectd *> objects;
    fcl::DynamicAABBTreeCollisionManagerd manager;

    FclScene(const Blob &blob, size_t n, const double *centers, const double *scales, const double *quats) {
        std::vector<fcl::Vector3d> points(blob.vertex_count());
        std::vector<fcl::Triangle> tris(blob.triangle_count());
        for (uint32_t i = 0; i < blob.triangle_count(); ++i)
            tris[i] = fcl::Triangle(blob.t[3 * i], blob.t[3 * i + 1], blob.t[3 * i + 2]);
        for (size_t i = 0; i < n; ++i) {
            const double s = scales[i];
            for (uint32_t v = 0; v < blob.vertex_count(); ++v)
                points[v] = fcl::Vector3d(s * blob.v[3 * v], s * blob.v[3 * v + 1], s * blob.v[3 * v + 2]);
            std::shared_ptr<fcl::BVHModel<fcl::OBBRSSd>> model(new fcl::BVHModel<fcl::OBBRSSd>());
            model->beginModel();
            model->addSubModel(points, tris);
            model->endModel();
            models.push_back(model);
            double r[9];
            rotation(&quats[4 * i], r);
            fcl::Matrix3d m;
            m << r[0], r[1], r[2], r[3], r[4], r[5], r[6], r[7], r[8];
            fcl::Transform3d tf = fcl::Transform3d::Identity();
            tf.linear() = m;
            tf.translation() = fcl::Vector3d(centers[3 * i], centers[3 * i + 1], centers[3 * i + 2]);
            fcl::CollisionObjectd *o = new fcl::CollisionObjectd(model, tf);
            o->setUserData(reinterpret_cast<void *>(uintptr_t(i)));
            objects.push_back(o);
        }
        manager.registerObjects(objects);
        manager.setup();
    }
    ~FclScene() {
        manager.clear();
        for (size_t i = 0; i < objects.size(); ++i) delete objects[i];
    }
    FclPairs run() {
        FclPairs d;
        manager.update();
        manager.collide(&d, FclPairs::callback);
        std::sort(d.pairs.begin(), d.pairs.end());
        return d;
    }
};
#endif

void scene_case(uint64_t n, double side, uint64_t seed, uint32_t threads, int reps, uint32_t nu, uint32_t nv,
                bool fcl, const char *commit) {
    const Blob blob(nu, nv);
    hgcd_scene_tetra_desc sd = hgcd_scene_tetra_desc_default();
    sd.n = n;
    sd.seed = seed;
    sd.side = side;
    std::vector<double> centers(3 * n), radii(n), quats(4 * n);
    if (hgcd_scene_tetra_generate(&sd, centers.data(), radii.data(), nullptr, quats.data(), nullptr) != HGCD_OK) {
        std::fprintf(stderr, "bad scene parameters\n");
        std::exit(2);
    }
    hgcd_world_desc wd = hgcd_world_desc_default();
    wd.thread_count = threads;
    hgcd_world *w;
    const double t_setup = now();
    check(hgcd_world_create(&wd, &w), nullptr, "world_create");
    const hgcd_mesh mesh = make_mesh(w, blob);
    for (uint64_t i = 0; i < n; ++i) {
        hgcd_body_desc bd = hgcd_body_desc_default();
        bd.mesh = mesh;
        std::memcpy(bd.position, &centers[3 * i], 3 * sizeof(double));
        std::memcpy(bd.orientation, &quats[4 * i], 4 * sizeof(double));
        bd.scale = radii[i];
        hgcd_body b;
        check(hgcd_body_create(w, &bd, &b), w, "body_create");
    }
    const double setup_ms = 1e3 * (now() - t_setup);
#ifdef HGCD_BENCH_FCL
    std::unique_ptr<FclScene> f;
    double fcl_setup_ms = 0;
    if (fcl) {
        const double t0 = now();
        f.reset(new FclScene(blob, n, centers.data(), radii.data(), quats.data()));
        fcl_setup_ms = 1e3 * (now() - t0);
    }
    std::vector<double> ft;
    FclPairs d;
#else
    (void)fcl;
#endif
    // Repetitions alternate between the libraries, so that a busy machine
    // slows both alike; medians and minima are reported.
    std::vector<double> times, narrow;
    hgcd_stats st;
    for (int r = 0; r < reps; ++r) {
        const double t0 = now();
        check(hgcd_world_detect(w), w, "world_detect");
        times.push_back(now() - t0);
        std::memset(&st, 0, sizeof st);
        st.struct_size = sizeof st;
        check(hgcd_world_stats(w, &st), w, "world_stats");
        narrow.push_back(st.narrow_seconds);
#ifdef HGCD_BENCH_FCL
        if (f) {
            const double t1 = now();
            d = f->run();
            ft.push_back(now() - t1);
        }
#endif
    }
    const hgcd_pair *p;
    size_t count;
    check(hgcd_world_pairs(w, &p, &count), w, "world_pairs");
    std::vector<uint64_t> mine(count);
    for (size_t k = 0; k < count; ++k) mine[k] = (uint64_t(p[k].a.index) << 32) | p[k].b.index;
    const double hgcd_ms = 1e3 * median(times);
    const double hgcd_min_ms = 1e3 * *std::min_element(times.begin(), times.end());
    std::printf("{\"lib\":\"hgcd\",\"scene\":\"meshes\",\"case\":\"scene\",\"commit\":\"%s\",\"n\":%llu,"
                "\"side\":%g,\"seed\":%llu,\"threads\":%u,\"triangles\":%u,\"reps\":%d,\"detect_ms\":%.3f,"
                "\"min_ms\":%.3f,\"first_ms\":%.3f,\"narrow_ms\":%.3f,\"candidate_pairs\":%llu,"
                "\"narrow_tests\":%llu,\"triangle_tests\":%llu,\"colliding_pairs\":%llu,"
                "\"containment_pairs\":%llu,\"setup_ms\":%.1f}\n",
                commit, (unsigned long long)n, side, (unsigned long long)seed, st.thread_count,
                blob.triangle_count(), reps, hgcd_ms, hgcd_min_ms, 1e3 * times[0], 1e3 * median(narrow),
                (unsigned long long)st.candidate_pairs, (unsigned long long)st.narrow_tests,
                (unsigned long long)st.triangle_tests, (unsigned long long)st.colliding_pairs,
                (unsigned long long)st.containment_pairs, setup_ms);
    std::fflush(stdout);
    const unsigned long long containment = st.containment_pairs;
    hgcd_world_destroy(w);

#ifdef HGCD_BENCH_FCL
    if (f) {
        std::vector<uint64_t> fcl_only, hgcd_only;
        std::set_difference(d.pairs.begin(), d.pairs.end(), mine.begin(), mine.end(),
                            std::back_inserter(fcl_only));
        std::set_difference(mine.begin(), mine.end(), d.pairs.begin(), d.pairs.end(),
                            std::back_inserter(hgcd_only));
        const double fcl_ms = 1e3 * median(ft);
        const double fcl_min_ms = 1e3 * *std::min_element(ft.begin(), ft.end());
        std::printf("{\"lib\":\"fcl\",\"scene\":\"meshes\",\"case\":\"scene\",\"commit\":\"%s\",\"n\":%llu,"
                    "\"side\":%g,\"seed\":%llu,\"threads\":1,\"bv\":\"OBBRSS\",\"reps\":%d,\"detect_ms\":%.3f,"
                    "\"min_ms\":%.3f,\"first_ms\":%.3f,\"candidate_pairs\":%llu,\"colliding_pairs\":%llu,"
                    "\"fcl_only\":%llu,\"hgcd_only\":%llu,\"hgcd_containment\":%llu,"
                    "\"missed_are_containment\":%s,\"hgcd_speedup_median\":%.2f,\"hgcd_speedup_min\":%.2f,"
                    "\"setup_ms\":%.1f,\"peak_rss_mb\":%.1f}\n",
                    commit, (unsigned long long)n, side, (unsigned long long)seed, reps, fcl_ms, fcl_min_ms,
                    1e3 * ft[0], (unsigned long long)d.candidates, (unsigned long long)d.pairs.size(),
                    (unsigned long long)fcl_only.size(), (unsigned long long)hgcd_only.size(), containment,
                    (fcl_only.empty() && hgcd_only.size() == containment) ? "true" : "false", fcl_ms / hgcd_ms,
                    fcl_min_ms / hgcd_min_ms, fcl_setup_ms, peak_rss_mb());
        for (size_t k = 0; k < fcl_only.size() && k < 5; ++k)
            std::fprintf(stderr, "fcl only: (%u, %u)\n", unsigned(fcl_only[k] >> 32), unsigned(fcl_only[k]));
        std::fflush(stdout);
    }
#else
    (void)containment;
    (void)hgcd_ms;
#endif
}

}  // namespace

int main(int argc, char **argv) {
    uint64_t n = 1000, seed = 1;
    double side = 30;
    uint32_t threads = 1, nu = HGCD_BLOB_NU, nv = HGCD_BLOB_NV, cnu = 100, cnv = 51;
    int reps = 3;
    bool fcl = true, contact = true;
    const char *commit = "unknown";
    for (int i = 1; i < argc; ++i) {
        const std::string a = argv[i];
        const bool has = i + 1 < argc;
        if (a == "--n" && has) n = std::strtoull(argv[++i], nullptr, 10);
        else if (a == "--side" && has) side = std::atof(argv[++i]);
        else if (a == "--seed" && has) seed = std::strtoull(argv[++i], nullptr, 10);
        else if (a == "--threads" && has) threads = uint32_t(std::atoi(argv[++i]));
        else if (a == "--reps" && has) reps = std::max(1, std::atoi(argv[++i]));
        else if (a == "--nu" && has) nu = uint32_t(std::atoi(argv[++i]));
        else if (a == "--nv" && has) nv = uint32_t(std::atoi(argv[++i]));
        else if (a == "--contact-nu" && has) cnu = uint32_t(std::atoi(argv[++i]));
        else if (a == "--contact-nv" && has) cnv = uint32_t(std::atoi(argv[++i]));
        else if (a == "--commit" && has) commit = argv[++i];
        else if (a == "--no-fcl") fcl = false;
        else if (a == "--no-contact") contact = false;
        else {
            std::fprintf(stderr,
                         "usage: %s [--n N] [--side L] [--seed S] [--threads K] [--reps R] [--nu U --nv V]\n"
                         "          [--contact-nu U --contact-nv V] [--no-fcl] [--no-contact] [--commit HASH]\n",
                         argv[0]);
            return 2;
        }
    }
    if (nu < 3 || nv < 2 || cnu < 3 || cnv < 2) {
        std::fprintf(stderr, "mesh resolution too small (nu >= 3, nv >= 2)\n");
        return 2;
    }
    if (contact) contact_case(cnu, cnv, reps, commit);
    if (n > 0) scene_case(n, side, seed, threads, reps, nu, nv, fcl, commit);
    return 0;
}
