// bench_queries: scene queries on scene `tetra` (docs/scenes.md): random rays
// (closest hit and any hit) and random boxes, hgcd against Bullet's
// btCollisionWorld::rayTest (closest hit), Embree's rtcIntersect1 (closest
// hit, the speed anchor for rays) and FCL's DynamicAABBTreeCollisionManager
// (one box object against the manager, each candidate decided by
// fcl::collide).
//
//   bench_queries [--n N] [--rays R] [--boxes B] [--peer-rays K]
//                 [--peer-boxes K] [--seed S] [--commit HASH] [--no-peers]
//
// Workload (seeded splitmix64, the same for every library): ray origins
// uniform in the cube [0, L]^3, directions uniform on the sphere, lengths
// uniform in [0, L]; boxes with centres uniform in the cube and half sides
// uniform in [0.5, 2.5] per axis. The bodies are the n tetrahedra of scene
// `tetra` at their initial poses; every library gets the same shapes:
// Bullet a btConvexHullShape of the 4 scaled mesh vertices at the body's
// transform (single precision), FCL a fcl::Convexd likewise (double),
// Embree the world triangles (float), hgcd the bodies themselves. Peers are
// serial (Embree's rays run on an OpenMP loop like hgcd's); Bullet and FCL
// run the first K rays / boxes only (their time per query is what counts).
//
// hgcd answers a batch of rays or boxes in a spatial order of its own (a
// Morton curve of the origins or centres); Embree's rays run twice, in the
// given random order and in that order ("rays_closest_sorted").
//
// Output: one JSON line per measurement: lib, what, threads, count, ms,
// us_per_query, and "hits" (rays that hit, or bodies found by boxes);
// "agree" counts the rays whose hit body equals hgcd's (peers are not
// exact: they differ on rays that graze a body).
#include <omp.h>

#include <algorithm>
#include <functional>
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

#include <hgcd/hgcd.h>
#include <hgcd/hgcd_scene.h>

#ifdef HGCD_BENCH_FCL
#include <fcl/broadphase/broadphase_dynamic_AABB_tree.h>
#include <fcl/geometry/shape/box.h>
#include <fcl/geometry/shape/convex.h>
#include <fcl/narrowphase/collision.h>
#include <fcl/narrowphase/collision_object.h>
#endif
#ifdef HGCD_BENCH_BULLET
#include <btBulletCollisionCommon.h>
#endif
#ifdef HGCD_BENCH_EMBREE
#include <embree3/rtcore.h>
#endif

namespace {

double now() { return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count(); }

// The process's CPU time: on a machine shared with other work, a 1-thread
// run's CPU time is its cost, where wall time also counts the waiting.
double cpu_now() {
    timespec ts;
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
    return double(ts.tv_sec) + 1e-9 * double(ts.tv_nsec);
}
double cpu_mark = 0;

struct Rng {
    uint64_t s;
    uint64_t next() {
        uint64_t z = (s += 0x9E3779B97F4A7C15ull);
        z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
        z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
        return z ^ (z >> 31);
    }
    double unif() { return std::ldexp(double(next() >> 11), -53); }
};

struct Scene {
    size_t n;
    double side;
    std::vector<double> centers, radii, scales, quats, vel;
    double unit[12];
    uint32_t tris[12];
    std::vector<double> world;  // 12 per body: hgcd.h's formula
};

void world_vertex(const double *c, const double *q, double s, const double *m, double *out) {
    const double x = q[0], y = q[1], z = q[2], w = q[3];
    const double R[9] = {1.0 - 2.0 * (y * y + z * z), 2.0 * (x * y - z * w), 2.0 * (x * z + y * w),
                         2.0 * (x * y + z * w), 1.0 - 2.0 * (x * x + z * z), 2.0 * (y * z - x * w),
                         2.0 * (x * z - y * w), 2.0 * (y * z + x * w), 1.0 - 2.0 * (x * x + y * y)};
    const double l[3] = {s * m[0], s * m[1], s * m[2]};
    for (int a = 0; a < 3; ++a) out[a] = c[a] + ((R[3 * a] * l[0] + R[3 * a + 1] * l[1]) + R[3 * a + 2] * l[2]);
}

// cpu: the process's CPU seconds since the last emit (or cpu_mark reset).
void emit(const char *lib, const char *what, int threads, size_t count, double seconds, uint64_t hits, long agree,
          const std::string &extra, const std::string &commit) {
    const double cpu = cpu_now() - cpu_mark;
    std::printf("{\"bench\":\"queries\",\"scene\":\"tetra\",\"lib\":\"%s\",\"what\":\"%s\",\"threads\":%d,\"count\":%zu,"
                "\"ms\":%.3f,\"us_per_query\":%.4f,\"cpu_us_per_query\":%.4f,\"hits\":%llu,\"agree\":%ld%s,"
                "\"commit\":\"%s\"}\n",
                lib, what, threads, count, seconds * 1e3, seconds * 1e6 / double(count ? count : 1),
                cpu * 1e6 / double(count ? count : 1), (unsigned long long)hits, agree, extra.c_str(), commit.c_str());
    std::fflush(stdout);
}

#ifdef HGCD_BENCH_EMBREE
// The rays' order along a Morton curve of their origins in [0, side]^3, 10
// bits an axis (the order hgcd answers a batch in, src/query/tree.hpp).
void morton_order(const std::vector<hgcd_ray> &rays, double side, std::vector<uint32_t> &order) {
    std::vector<uint64_t> keys(rays.size());
    for (size_t k = 0; k < rays.size(); ++k) {
        uint32_t code = 0;
        for (int a = 0; a < 3; ++a) {
            uint32_t v = uint32_t(std::min(std::max(rays[k].origin[a] / side * 1024.0, 0.0), 1023.0));
            v = (v | (v << 16)) & 0x030000FFu;
            v = (v | (v << 8)) & 0x0300F00Fu;
            v = (v | (v << 4)) & 0x030C30C3u;
            v = (v | (v << 2)) & 0x09249249u;
            code |= v << a;
        }
        keys[k] = uint64_t(code) << 32 | k;
    }
    std::sort(keys.begin(), keys.end());
    for (size_t k = 0; k < rays.size(); ++k) order[k] = uint32_t(keys[k]);
}
#endif

}  // namespace

int main(int argc, char **argv) {
    size_t n = 750000, nrays = 1000000, nboxes = 100000, peer_rays = 100000, peer_boxes = 20000;
    uint64_t seed = 7;
    bool peers = true;
    std::string commit = "unknown";
    for (int i = 1; i < argc; ++i) {
        const std::string a = argv[i];
        auto val = [&]() { return i + 1 < argc ? argv[++i] : (std::fprintf(stderr, "%s needs a value\n", a.c_str()), std::exit(2), argv[0]); };
        if (a == "--n") n = std::strtoull(val(), nullptr, 10);
        else if (a == "--rays") nrays = std::strtoull(val(), nullptr, 10);
        else if (a == "--boxes") nboxes = std::strtoull(val(), nullptr, 10);
        else if (a == "--peer-rays") peer_rays = std::strtoull(val(), nullptr, 10);
        else if (a == "--peer-boxes") peer_boxes = std::strtoull(val(), nullptr, 10);
        else if (a == "--seed") seed = std::strtoull(val(), nullptr, 10);
        else if (a == "--commit") commit = val();
        else if (a == "--no-peers") peers = false;
        else {
            std::fprintf(stderr, "unknown option %s\n", a.c_str());
            return 2;
        }
    }
    peer_rays = std::min(peer_rays, nrays);
    peer_boxes = std::min(peer_boxes, nboxes);

    // The scene.
    Scene sc;
    hgcd_scene_tetra_desc td = hgcd_scene_tetra_desc_default();
    td.n = n;
    sc.n = n;
    sc.side = td.side;
    sc.centers.resize(3 * n);
    sc.radii.resize(n);
    sc.scales.resize(n);
    sc.quats.resize(4 * n);
    sc.vel.resize(3 * n);
    if (hgcd_scene_tetra_generate(&td, sc.centers.data(), sc.radii.data(), sc.scales.data(), sc.quats.data(),
                                  sc.vel.data()) != 0)
        return 1;
    hgcd_scene_tetra_unit_mesh(sc.unit, sc.tris);
    sc.world.resize(12 * n);
    for (size_t i = 0; i < n; ++i)
        for (int v = 0; v < 4; ++v)
            world_vertex(&sc.centers[3 * i], &sc.quats[4 * i], sc.scales[i], sc.unit + 3 * v, &sc.world[12 * i + 3 * v]);

    // The workload.
    Rng rng{seed};
    std::vector<hgcd_ray> rays(nrays);
    for (hgcd_ray &r : rays) {
        for (int a = 0; a < 3; ++a) r.origin[a] = sc.side * rng.unif();
        double d[3], len;
        do {
            for (int a = 0; a < 3; ++a) d[a] = 2 * rng.unif() - 1;
            len = std::sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
        } while (len > 1 || len < 1e-3);
        for (int a = 0; a < 3; ++a) r.direction[a] = d[a] / len;
        r.max_distance = sc.side * rng.unif();
    }
    std::vector<double> boxes(6 * nboxes);
    for (size_t k = 0; k < nboxes; ++k)
        for (int a = 0; a < 3; ++a) {
            const double c = sc.side * rng.unif(), h = 0.5 + 2.0 * rng.unif();
            boxes[6 * k + a] = c - h;
            boxes[6 * k + 3 + a] = c + h;
        }

    // hgcd.
    hgcd_world_desc wd = hgcd_world_desc_default();
    hgcd_world *w = nullptr;
    if (hgcd_world_create(&wd, &w) != HGCD_OK || hgcd_scene_tetra_populate(w, &td, nullptr) != HGCD_OK) return 1;
    std::vector<hgcd_ray_hit> hits(nrays), hits2(nrays);
    {
        cpu_mark = cpu_now();
        double t0 = now();
        hgcd_query_results res;
        hgcd_world_query_point(w, sc.centers.data(), 1, 0, nullptr, &res);  // builds the query tree
        emit("hgcd", "tree_build", 1, n, now() - t0, 0, -1, "", commit);
    }
    uint64_t hgcd_ray_hits = 0;
    for (int threads = 1; threads <= 2; ++threads) {
        hgcd_world_set_thread_count(w, uint32_t(threads));
        cpu_mark = cpu_now();
        double t0 = now();
        if (hgcd_world_cast_rays(w, rays.data(), nrays, 0, HGCD_RAY_CLOSEST, nullptr,
                                 threads == 1 ? hits.data() : hits2.data()) != HGCD_OK)
            return 1;
        const double dt = now() - t0;
        uint64_t h = 0;
        for (size_t k = 0; k < nrays; ++k) h += hits[k].body.generation != 0;
        hgcd_ray_hits = h;
        if (threads == 2 && std::memcmp(hits.data(), hits2.data(), nrays * sizeof(hgcd_ray_hit)) != 0) {
            std::fprintf(stderr, "rays differ between 1 and 2 threads\n");
            return 1;
        }
        emit("hgcd", "rays_closest", threads, nrays, dt, h, -1, "", commit);
        cpu_mark = cpu_now();
        t0 = now();
        hgcd_world_cast_rays(w, rays.data(), nrays, 0, HGCD_RAY_ANY, nullptr, hits2.data());
        const double da = now() - t0;
        uint64_t ha = 0;
        for (size_t k = 0; k < nrays; ++k) ha += hits2[k].body.generation != 0;
        emit("hgcd", "rays_any", threads, nrays, da, ha, -1, "", commit);
        hgcd_query_results res;
        cpu_mark = cpu_now();
        t0 = now();
        if (hgcd_world_query_box(w, boxes.data(), nboxes, 0, nullptr, &res) != HGCD_OK) return 1;
        emit("hgcd", "boxes", threads, nboxes, now() - t0, res.body_count, -1, "", commit);
    }
    (void)hgcd_ray_hits;
    std::vector<size_t> box_counts(nboxes);
    {
        hgcd_query_results res;
        hgcd_world_query_box(w, boxes.data(), nboxes, 0, nullptr, &res);
        for (size_t k = 0; k < nboxes; ++k) box_counts[k] = res.offsets[k + 1] - res.offsets[k];
    }
    // The first query after a change of the world (the tree brought up to
    // date plus one point, what an engine's first query of a tick pays), 3
    // rounds on each thread count, the median; change() returns false on error.
    const auto first_query_after = [&](const char *what, const std::function<bool()> &change) {
        for (int threads = 1; threads <= 2; ++threads) {
            hgcd_world_set_thread_count(w, uint32_t(threads));
            std::vector<double> dts;
            double cpu = 0;
            for (int round = 0; round < 3; ++round) {
                if (!change()) return false;
                hgcd_query_results res;
                const double c0 = cpu_now(), t0 = now();
                hgcd_world_query_point(w, sc.centers.data(), 1, 0, nullptr, &res);
                dts.push_back(now() - t0);
                cpu = cpu_now() - c0;
            }
            std::sort(dts.begin(), dts.end());
            cpu_mark = cpu_now() - cpu;  // (emit's CPU time: the last round's)
            emit("hgcd", what, threads, n, dts[1], 0, -1, "", commit);
        }
        return true;
    };
    // After a tick of the reference motion (every body moved: a refit).
    if (!first_query_after("tree_update", [&] { return hgcd_world_step(w) == HGCD_OK; })) return 1;
    // After bodies came and went (100 destroyed, 100 created, as an engine's
    // projectiles).
    double unit_v[12];
    uint32_t unit_t[12];
    hgcd_scene_tetra_unit_mesh(unit_v, unit_t);
    hgcd_mesh_desc md = hgcd_mesh_desc_default();
    md.vertices = unit_v;
    md.triangles = unit_t;
    md.vertex_count = 4;
    md.triangle_count = 4;
    hgcd_mesh unit;
    if (hgcd_mesh_create(w, &md, &unit) != HGCD_OK) return 1;
    std::vector<hgcd_body> churn;
    const bool churned = first_query_after("tree_churn", [&] {
        for (const hgcd_body &b : churn) hgcd_body_destroy(w, b);
        churn.clear();
        for (int k = 0; k < 100; ++k) {
            hgcd_body_desc bd = hgcd_body_desc_default();
            bd.mesh = unit;
            for (int a = 0; a < 3; ++a) bd.position[a] = sc.side * rng.unif();
            hgcd_body id;
            if (hgcd_body_create(w, &bd, &id) != HGCD_OK) return false;
            churn.push_back(id);
        }
        return true;
    });
    if (!churned) return 1;
    if (!peers) {
        std::fflush(stdout);
        std::_Exit(0);
    }

#ifdef HGCD_BENCH_EMBREE
    {
        cpu_mark = cpu_now();
        double t0 = now();
        RTCDevice dev = rtcNewDevice("threads=1");
        RTCScene scene = rtcNewScene(dev);
        RTCGeometry geom = rtcNewGeometry(dev, RTC_GEOMETRY_TYPE_TRIANGLE);
        float *vb = (float *)rtcSetNewGeometryBuffer(geom, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3,
                                                     3 * sizeof(float), 4 * n);
        unsigned *ib = (unsigned *)rtcSetNewGeometryBuffer(geom, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3,
                                                           3 * sizeof(unsigned), 4 * n);
        for (size_t i = 0; i < 4 * n * 3; ++i) vb[i] = float(sc.world[i]);
        for (size_t i = 0; i < n; ++i)
            for (int k = 0; k < 12; ++k) ib[12 * i + k] = unsigned(4 * i + sc.tris[k]);
        rtcCommitGeometry(geom);
        rtcAttachGeometry(scene, geom);
        rtcReleaseGeometry(geom);
        rtcCommitScene(scene);
        emit("embree", "tree_build", 1, n, now() - t0, 0, -1, "", commit);
        // Each thread count twice: the rays in their given (random) order,
        // then in the order hgcd answers a batch in (a Morton curve of the
        // origins, sorted inside the timing as hgcd sorts inside its call),
        // so that Embree gets the same memory coherence.
        for (int run = 0; run < 4; ++run) {
            const int threads = 1 + run / 2;
            const bool sorted = run % 2 == 1;
            std::vector<int64_t> body(nrays, -1);
            cpu_mark = cpu_now();
            const double t1 = now();
            std::vector<uint32_t> order(nrays);
            for (size_t k = 0; k < nrays; ++k) order[k] = uint32_t(k);
            if (sorted) morton_order(rays, sc.side, order);
#pragma omp parallel for num_threads(threads) schedule(dynamic, 256)
            for (int64_t j = 0; j < int64_t(nrays); ++j) {
                const size_t k = order[size_t(j)];
                const hgcd_ray &r = rays[k];
                RTCIntersectContext ctx;
                rtcInitIntersectContext(&ctx);
                RTCRayHit rh;
                rh.ray.org_x = float(r.origin[0]);
                rh.ray.org_y = float(r.origin[1]);
                rh.ray.org_z = float(r.origin[2]);
                rh.ray.dir_x = float(r.direction[0]);
                rh.ray.dir_y = float(r.direction[1]);
                rh.ray.dir_z = float(r.direction[2]);
                rh.ray.tnear = 0;
                rh.ray.tfar = float(r.max_distance);
                rh.ray.mask = 0xFFFFFFFFu;
                rh.ray.flags = 0;
                rh.ray.time = 0;
                rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
                rtcIntersect1(scene, &ctx, &rh);
                if (rh.hit.geomID != RTC_INVALID_GEOMETRY_ID) body[k] = rh.hit.primID / 4;
            }
            const double dt = now() - t1;
            uint64_t h = 0;
            long agree = 0;
            for (size_t k = 0; k < nrays; ++k) {
                h += body[k] >= 0;
                agree += body[k] >= 0 && hits[k].body.generation != 0 &&
                         uint32_t(body[k]) == hits[k].body.index;
            }
            emit("embree", sorted ? "rays_closest_sorted" : "rays_closest", threads, nrays, dt, h, agree, "", commit);
        }
        rtcReleaseScene(scene);
        rtcReleaseDevice(dev);
    }
#endif

#ifdef HGCD_BENCH_BULLET
    {
        cpu_mark = cpu_now();
        double t0 = now();
        auto *config = new btDefaultCollisionConfiguration();
        auto *dispatcher = new btCollisionDispatcher(config);
        auto *broad = new btDbvtBroadphase();
        auto *world = new btCollisionWorld(dispatcher, broad, config);
        for (size_t i = 0; i < n; ++i) {
            auto *shape = new btConvexHullShape();
            for (int v = 0; v < 4; ++v)
                shape->addPoint(btVector3(btScalar(sc.scales[i] * sc.unit[3 * v]), btScalar(sc.scales[i] * sc.unit[3 * v + 1]),
                                          btScalar(sc.scales[i] * sc.unit[3 * v + 2])),
                                v == 3);
            shape->setMargin(0);
            auto *obj = new btCollisionObject();
            obj->setCollisionShape(shape);
            const double *q = &sc.quats[4 * i], *c = &sc.centers[3 * i];
            obj->setWorldTransform(btTransform(btQuaternion(btScalar(q[0]), btScalar(q[1]), btScalar(q[2]), btScalar(q[3])),
                                               btVector3(btScalar(c[0]), btScalar(c[1]), btScalar(c[2]))));
            obj->setUserIndex(int(i));
            world->addCollisionObject(obj);
        }
        broad->optimize();
        emit("bullet", "tree_build", 1, n, now() - t0, 0, -1, "", commit);
        cpu_mark = cpu_now();
            const double t1 = now();
        uint64_t h = 0;
        long agree = 0;
        for (size_t k = 0; k < peer_rays; ++k) {
            const hgcd_ray &r = rays[k];
            const btVector3 from(btScalar(r.origin[0]), btScalar(r.origin[1]), btScalar(r.origin[2]));
            const btVector3 to(btScalar(r.origin[0] + r.max_distance * r.direction[0]),
                               btScalar(r.origin[1] + r.max_distance * r.direction[1]),
                               btScalar(r.origin[2] + r.max_distance * r.direction[2]));
            btCollisionWorld::ClosestRayResultCallback cb(from, to);
            world->rayTest(from, to, cb);
            if (cb.hasHit()) {
                ++h;
                agree += hits[k].body.generation != 0 &&
                         uint32_t(cb.m_collisionObject->getUserIndex()) == hits[k].body.index;
            }
        }
        emit("bullet", "rays_closest", 1, peer_rays, now() - t1, h, agree, "", commit);
        // (Tearing down 750,000 objects is slow and measures nothing: see the end.)
    }
#endif

#ifdef HGCD_BENCH_FCL
    {
        cpu_mark = cpu_now();
        double t0 = now();
        auto verts_faces = std::make_shared<std::vector<int>>();
        for (int f = 0; f < 4; ++f) {
            verts_faces->push_back(3);
            for (int k = 0; k < 3; ++k) verts_faces->push_back(int(sc.tris[3 * f + k]));
        }
        std::vector<fcl::CollisionObjectd *> objs(n);
        fcl::DynamicAABBTreeCollisionManagerd manager;
        for (size_t i = 0; i < n; ++i) {
            auto v = std::make_shared<std::vector<fcl::Vector3d>>();
            for (int k = 0; k < 4; ++k)
                v->push_back(fcl::Vector3d(sc.scales[i] * sc.unit[3 * k], sc.scales[i] * sc.unit[3 * k + 1],
                                           sc.scales[i] * sc.unit[3 * k + 2]));
            std::shared_ptr<fcl::CollisionGeometryd> g(new fcl::Convexd(v, 4, verts_faces));
            const double *q = &sc.quats[4 * i], *c = &sc.centers[3 * i];
            fcl::Transform3d tf = fcl::Transform3d::Identity();
            tf.linear() = fcl::Quaterniond(q[3], q[0], q[1], q[2]).toRotationMatrix();
            tf.translation() = fcl::Vector3d(c[0], c[1], c[2]);
            objs[i] = new fcl::CollisionObjectd(g, tf);
            objs[i]->setUserData(reinterpret_cast<void *>(i));
        }
        manager.registerObjects(objs);
        manager.setup();
        emit("fcl", "tree_build", 1, n, now() - t0, 0, -1, "", commit);
        struct Data {
            uint64_t found = 0;
        } data;
        cpu_mark = cpu_now();
            const double t1 = now();
        long agree = 0;
        for (size_t k = 0; k < peer_boxes; ++k) {
            const double *b = &boxes[6 * k];
            std::shared_ptr<fcl::CollisionGeometryd> g(new fcl::Boxd(b[3] - b[0], b[4] - b[1], b[5] - b[2]));
            fcl::Transform3d tf = fcl::Transform3d::Identity();
            tf.translation() = fcl::Vector3d(0.5 * (b[0] + b[3]), 0.5 * (b[1] + b[4]), 0.5 * (b[2] + b[5]));
            fcl::CollisionObjectd q(g, tf);
            const uint64_t before = data.found;
            manager.collide(&q, &data, [](fcl::CollisionObjectd *o1, fcl::CollisionObjectd *o2, void *d) {
                fcl::CollisionRequestd request;
                fcl::CollisionResultd result;
                fcl::collide(o1, o2, request, result);
                if (result.isCollision()) ++static_cast<Data *>(d)->found;
                return false;
            });
            agree += data.found - before == box_counts[k];
        }
        emit("fcl", "boxes", 1, peer_boxes, now() - t1, data.found, agree, "", commit);
    }
#endif
    std::fflush(stdout);
    std::_Exit(0);  // (the peers' teardown of 750,000 objects takes minutes and measures nothing)
}
