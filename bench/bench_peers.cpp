// bench_peers: the broad phases of FCL, Bullet and ODE on scene `tetra`.
//
//   bench_peers --lib fcl|bullet|ode [--n N] [--seed S] [--ticks T]
//               [--commit HASH] [--max-tick-seconds X] [--max-seconds Y]
//   bench_peers --list          prints the peers compiled in, one a line
//
// The scene is the one of docs/scenes.md, drawn by hgcd_scene_tetra_generate (so
// centres, orientations, velocities and scales are bit-identical to what
// bench_hgcd uses) and moved each tick by hgcd_scene_tetra_move. Each body is
// handed to the peer as an axis-aligned box of its 4 world vertices (world
// vertex = centre + R * (scale * m), exactly the formula of hgcd.h), moved
// rigidly with the body, as a peer's user would move a rigid box:
//   * once, the box of the 4 rotated local vertices is rounded outward to the
//     grid g = 2^-16 and widened by one more g on each side: [lo_off, hi_off];
//   * each tick, box = round_to_g(centre) + [lo_off, hi_off].
// The box contains the 4 world vertices (checked every tick: "boxes_ok") and
// is at most ~3e-5 larger than their exact bounding box. Every bound is a
// multiple of 2^-16 below 2^8, so it is exact in single precision (Bullet is
// single precision in Debian), a box's extents never change, and centre and
// half-extents are exact in double, so FCL and ODE, which store a box as a
// fixed-size shape at a position, give back exactly the same bounds. (Rounding
// the exact per-tick bounding box instead would change the extents by one g
// from tick to tick, and FCL/ODE boxes of fixed size then miss touching pairs.)
// All peers therefore see bit-identical boxes and their pair counts must agree
// exactly with the reference sweep.
//
// What is measured is the BROAD PHASE ONLY: per tick, handing the new boxes to
// the peer (update_ms) plus finding all pairs of overlapping boxes (pairs_ms);
// broad_ms = update_ms + pairs_ms, median over the ticks. Moving the centres
// (motion_ms), computing the boxes and checking that they contain the world
// vertices (aabb_ms) and the reference sweep (reference_ms) are reported but
// not included.
//
// Pair counts are checked against a sort-and-sweep in this file (count_overlaps):
// the boxes are binned into (y, z) strips, each strip is swept along x, and a
// pair is counted only in the strip holding the low corner of the two boxes'
// intersection, so every overlapping pair is counted exactly once. Touching
// boxes overlap (closed intervals), as in all three peers.
// "pairs_ok" is true when the peer's count equals the sweep's on the initial
// poses and on every measured tick.
//
// Note: hgcd's own broad phase works on boxes too, but on the vertices' exact
// box (offsets rounded outward to float, not to the 2^-16 grid used here), so
// its candidate_pairs (bench_hgcd) are a little fewer than the counts here
// (844,291 against 845,035 at n = 750000, initial poses); the comparison is
// one of time at nearly equal work.
//
// Peers are compiled in only when meson finds their Debian packages
// (HGCD_BENCH_FCL, HGCD_BENCH_BULLET, HGCD_BENCH_ODE). They are serial, so
// "threads" is always 1.
//
// Peer notes (pitfalls met while writing this):
//  * FCL: CollisionObject::setTranslation does not refresh the cached AABB;
//    computeAABB() must be called before DynamicAABBTreeCollisionManager::
//    update(), which re-reads every object's AABB, refits, then rebalances.
//    Self-collide() calls the callback once per pair of overlapping leaves.
//    FCL's pkg-config file adds -std=c++11, so this file is C++11.
//  * Bullet: btDbvtBroadphase keeps a persistent pair cache of pairs whose
//    FATTENED tree leaves overlap (leaves grow by gDbvtMargin when they move
//    and are only refitted when the box leaves them), and removes stale pairs
//    only incrementally (m_cupdates percent per call). getNumOverlappingPairs()
//    is therefore a superset of the box overlaps; the exact set is the cached
//    pairs whose proxies' own boxes overlap, which is what is counted here
//    (the filter is timed as part of pairs_ms); the raw cache size is
//    reported as "cache_pairs". After the bulk creation the trees are rebuilt
//    top-down with btDbvtBroadphase::optimize() (part of setup_ms): without
//    it, the per-proxy insertion order leaves a tree that makes every later
//    setAabb about 3x slower. Tearing down is slow too: destroyProxy scans the
//    whole pair cache for each proxy (O(n * pairs), ~15 minutes at n = 750000),
//    so this program ends with _Exit right after printing its JSON line.
//  * ODE: dHashSpace puts a geom on the level 2^k with 2^(k-1) < largest box
//    side <= 2^k, clamped to [minlevel, maxlevel]; geoms above maxlevel are
//    tested against everything. The levels are chosen from the data as the
//    range of those k over all boxes (for the default scene: -1..2, cells 0.5
//    to 4), reported as "ode_levels". dSpaceCollide calls back only for pairs
//    whose AABBs overlap, each once. BUT dHashSpace's collide() allocates and
//    clears an n x n bit matrix every call (n^2/8 bytes: 1.25 GB and most of
//    the time at n = 100000) whose size is computed in int: for n > 131071 it
//    overflows and ODE aborts. Such runs are skipped and reported with a
//    "skipped" member instead of timings.
#include <hgcd/hgcd.h>
#include <hgcd/hgcd_scene.h>

#include <sys/resource.h>
#include <unistd.h>

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

#ifdef HGCD_BENCH_FCL
#include <fcl/broadphase/broadphase_dynamic_AABB_tree.h>
#include <fcl/geometry/shape/box.h>
#include <fcl/narrowphase/collision_object.h>
#endif
#ifdef HGCD_BENCH_BULLET
#include <BulletCollision/BroadphaseCollision/btDbvtBroadphase.h>
#include <BulletCollision/BroadphaseCollision/btOverlappingPairCache.h>
#include <LinearMath/btAabbUtil2.h>
#endif
#ifdef HGCD_BENCH_ODE
#include <ode/ode.h>
#endif

namespace {

double now_seconds() {
    return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

double peak_rss_bytes() {
    struct rusage ru;
    if (getrusage(RUSAGE_SELF, &ru) != 0) return 0.0;
    return 1024.0 * static_cast<double>(ru.ru_maxrss);
}

double median(std::vector<double> v) {
    if (v.empty()) return 0.0;
    std::sort(v.begin(), v.end());
    const size_t m = v.size() / 2;
    return v.size() % 2 ? v[m] : 0.5 * (v[m - 1] + v[m]);
}

// Boxes as structure of arrays: lo[3 * i + a], hi[3 * i + a].
struct Boxes {
    size_t n = 0;
    std::vector<double> lo, hi;
};

// The scene and, per body, the rotated local vertices (R * (scale * m)), which
// are constant because the orientation never changes: world component a of
// vertex k is then c_a + offset[12 * i + 3 * k + a], bit for bit the formula
// of hgcd.h, c_a + ((R_a0*v0 + R_a1*v1) + R_a2*v2).
struct Scene {
    size_t n = 0;
    double side = 0.0;
    std::vector<double> centers, velocities;
    // Rotated local vertices R * (scale * m): offsets[12 * i + 3 * k + a].
    std::vector<double> offsets;
    // The body's box relative to its rounded centre: box_lo[3 * i + a] ...
    std::vector<double> box_lo, box_hi;
};

// The grid of the boxes: g = 2^-16. Scene coordinates stay below 2^8 in
// magnitude, so every bound is an integer below 2^24 times 2^-16.
const double kGrid = 1.0 / 65536.0;

bool make_scene(uint64_t n, uint64_t seed, Scene &s) {
    hgcd_scene_tetra_desc d = hgcd_scene_tetra_desc_default();
    d.n = n;
    d.seed = seed;
    s.n = static_cast<size_t>(n);
    s.side = d.side;
    s.centers.resize(3 * s.n);
    s.velocities.resize(3 * s.n);
    std::vector<double> scales(s.n), quats(4 * s.n);
    if (hgcd_scene_tetra_generate(&d, s.centers.data(), nullptr, scales.data(), quats.data(), s.velocities.data()) !=
        HGCD_OK)
        return false;
    double unit[12];
    hgcd_scene_tetra_unit_mesh(unit, nullptr);
    s.offsets.resize(12 * s.n);
    s.box_lo.resize(3 * s.n);
    s.box_hi.resize(3 * s.n);
    for (size_t i = 0; i < s.n; ++i) {
        // hgcd.h: R entry by entry as written, world component a of vertex k
        // is c_a + ((R_a0*v0 + R_a1*v1) + R_a2*v2) with v = scale * m.
        const double x = quats[4 * i], y = quats[4 * i + 1], z = quats[4 * i + 2], w = quats[4 * i + 3];
        const double R[3][3] = {{1.0 - 2.0 * (y * y + z * z), 2.0 * (x * y - z * w), 2.0 * (x * z + y * w)},
                                {2.0 * (x * y + z * w), 1.0 - 2.0 * (x * x + z * z), 2.0 * (y * z - x * w)},
                                {2.0 * (x * z - y * w), 2.0 * (y * z + x * w), 1.0 - 2.0 * (x * x + y * y)}};
        for (int k = 0; k < 4; ++k) {
            const double v0 = scales[i] * unit[3 * k], v1 = scales[i] * unit[3 * k + 1],
                         v2 = scales[i] * unit[3 * k + 2];
            for (int a = 0; a < 3; ++a) s.offsets[12 * i + 3 * k + a] = (R[a][0] * v0 + R[a][1] * v1) + R[a][2] * v2;
        }
        for (int a = 0; a < 3; ++a) {
            double lo = s.offsets[12 * i + a], hi = lo;
            for (int k = 1; k < 4; ++k) {
                lo = std::min(lo, s.offsets[12 * i + 3 * k + a]);
                hi = std::max(hi, s.offsets[12 * i + 3 * k + a]);
            }
            // Outward to the grid, plus one g for the rounded centre (|error| <= g/2).
            s.box_lo[3 * i + a] = (std::floor(lo / kGrid) - 1.0) * kGrid;
            s.box_hi[3 * i + a] = (std::ceil(hi / kGrid) + 1.0) * kGrid;
        }
    }
    return true;
}

// The boxes at the current centres; returns how many of the world vertices
// (computed as hgcd.h does) fall outside their box: always 0.
uint64_t compute_boxes(const Scene &s, Boxes &b) {
    b.n = s.n;
    b.lo.resize(3 * s.n);
    b.hi.resize(3 * s.n);
    uint64_t outside = 0;
    for (size_t i = 0; i < s.n; ++i) {
        for (int a = 0; a < 3; ++a) {
            const double c = s.centers[3 * i + a];
            const double rounded = std::nearbyint(c / kGrid) * kGrid;
            const double lo = rounded + s.box_lo[3 * i + a], hi = rounded + s.box_hi[3 * i + a];
            b.lo[3 * i + a] = lo;
            b.hi[3 * i + a] = hi;
            for (int k = 0; k < 4; ++k) {
                const double v = c + s.offsets[12 * i + 3 * k + a];
                outside += (v < lo) | (v > hi);
            }
        }
    }
    return outside;
}

inline bool overlap(const Boxes &b, size_t i, size_t j) {
    for (int a = 0; a < 3; ++a)
        if (b.lo[3 * i + a] > b.hi[3 * j + a] || b.lo[3 * j + a] > b.hi[3 * i + a]) return false;
    return true;
}

// The reference count: sort-and-sweep along x inside (y, z) strips (see the
// top of the file). O(n log n + pairs) for boxes of bounded size.
uint64_t count_overlaps(const Boxes &b) {
    const size_t n = b.n;
    if (n < 2) return 0;
    double miny = b.lo[1], minz = b.lo[2], maxy = b.hi[1], maxz = b.hi[2], width = 0.0;
    for (size_t i = 0; i < n; ++i) {
        miny = std::min(miny, b.lo[3 * i + 1]);
        minz = std::min(minz, b.lo[3 * i + 2]);
        maxy = std::max(maxy, b.hi[3 * i + 1]);
        maxz = std::max(maxz, b.hi[3 * i + 2]);
        width = std::max(width, std::max(b.hi[3 * i + 1] - b.lo[3 * i + 1], b.hi[3 * i + 2] - b.lo[3 * i + 2]));
    }
    // Strip width: the largest box side in y or z (so a box spans at most two
    // strips per axis), but not so small that there are more than 1024^2 strips.
    width = std::max(width, std::max(maxy - miny, maxz - minz) / 1024.0);
    if (!(width > 0.0)) width = 1.0;
    // strip_of is monotone in v, which is all the counting rule needs.
    auto strip_of = [width](double v, double origin) { return static_cast<int64_t>(std::floor((v - origin) / width)); };
    const int64_t sy_count = strip_of(maxy, miny) + 1, sz_count = strip_of(maxz, minz) + 1;
    const size_t strips = static_cast<size_t>(sy_count * sz_count);
    // Counting sort of (strip, box) entries: every box goes into each strip it overlaps.
    std::vector<size_t> start(strips + 1, 0);
    for (size_t i = 0; i < n; ++i) {
        const int64_t y0 = strip_of(b.lo[3 * i + 1], miny), y1 = strip_of(b.hi[3 * i + 1], miny);
        const int64_t z0 = strip_of(b.lo[3 * i + 2], minz), z1 = strip_of(b.hi[3 * i + 2], minz);
        for (int64_t sy = y0; sy <= y1; ++sy)
            for (int64_t sz = z0; sz <= z1; ++sz) ++start[static_cast<size_t>(sy * sz_count + sz) + 1];
    }
    for (size_t s = 1; s <= strips; ++s) start[s] += start[s - 1];
    std::vector<uint32_t> entries(start[strips]);
    std::vector<size_t> fill(start.begin(), start.end() - 1);
    for (size_t i = 0; i < n; ++i) {
        const int64_t y0 = strip_of(b.lo[3 * i + 1], miny), y1 = strip_of(b.hi[3 * i + 1], miny);
        const int64_t z0 = strip_of(b.lo[3 * i + 2], minz), z1 = strip_of(b.hi[3 * i + 2], minz);
        for (int64_t sy = y0; sy <= y1; ++sy)
            for (int64_t sz = z0; sz <= z1; ++sz)
                entries[fill[static_cast<size_t>(sy * sz_count + sz)]++] = static_cast<uint32_t>(i);
    }
    // Sweep each strip along x.
    uint64_t count = 0;
    for (int64_t sy = 0; sy < sy_count; ++sy)
        for (int64_t sz = 0; sz < sz_count; ++sz) {
            const size_t s = static_cast<size_t>(sy * sz_count + sz);
            uint32_t *first = entries.data() + start[s], *last = entries.data() + start[s + 1];
            std::sort(first, last, [&b](uint32_t p, uint32_t q) {
                return b.lo[3 * p] < b.lo[3 * q] || (b.lo[3 * p] == b.lo[3 * q] && p < q);
            });
            for (uint32_t *p = first; p != last; ++p) {
                const double hx = b.hi[3 * *p];
                for (uint32_t *q = p + 1; q != last && b.lo[3 * *q] <= hx; ++q) {
                    if (!overlap(b, *p, *q)) continue;
                    // Count the pair only in the strip of the intersection's low corner.
                    const double ry = std::max(b.lo[3 * *p + 1], b.lo[3 * *q + 1]);
                    const double rz = std::max(b.lo[3 * *p + 2], b.lo[3 * *q + 2]);
                    if (strip_of(ry, miny) == sy && strip_of(rz, minz) == sz) ++count;
                }
            }
        }
    return count;
}

// One broad phase behind a common face: build on the initial boxes, then per
// tick update() with the new boxes and find() the overlapping pairs.
struct Peer {
    virtual ~Peer() {}
    virtual void build(const Boxes &b) = 0;
    virtual void update(const Boxes &b) = 0;
    virtual uint64_t find() = 0;
    // Non-empty: why this peer cannot run n objects (the run is then skipped).
    virtual std::string unsupported(uint64_t n) const {
        (void)n;
        return std::string();
    }
    // Extra JSON members (leading comma), e.g. raw counts or parameters.
    virtual std::string extra() const { return std::string(); }
};

std::string json_u64(const char *key, uint64_t v) {
    char buf[96];
    std::snprintf(buf, sizeof buf, ",\"%s\":%llu", key, static_cast<unsigned long long>(v));
    return buf;
}

#ifdef HGCD_BENCH_FCL
struct FclPeer : Peer {
    std::vector<fcl::CollisionObjectd *> objects;
    fcl::DynamicAABBTreeCollisionManagerd manager;
    uint64_t callbacks = 0;

    struct Count {
        uint64_t overlapping = 0, calls = 0;
    };
    static bool callback(fcl::CollisionObjectd *o1, fcl::CollisionObjectd *o2, void *data) {
        Count *c = static_cast<Count *>(data);
        ++c->calls;
        if (o1->getAABB().overlap(o2->getAABB())) ++c->overlapping;
        return false;  // never stop early
    }
    ~FclPeer() {
        manager.clear();
        for (auto *o : objects) delete o;
    }
    static fcl::Vector3d center_of(const Boxes &b, size_t i) {
        return fcl::Vector3d(0.5 * (b.lo[3 * i] + b.hi[3 * i]), 0.5 * (b.lo[3 * i + 1] + b.hi[3 * i + 1]),
                             0.5 * (b.lo[3 * i + 2] + b.hi[3 * i + 2]));
    }
    void build(const Boxes &b) override {
        objects.reserve(b.n);
        for (size_t i = 0; i < b.n; ++i) {
            std::shared_ptr<fcl::CollisionGeometryd> box(new fcl::Boxd(
                b.hi[3 * i] - b.lo[3 * i], b.hi[3 * i + 1] - b.lo[3 * i + 1], b.hi[3 * i + 2] - b.lo[3 * i + 2]));
            fcl::Transform3d tf = fcl::Transform3d::Identity();
            tf.translation() = center_of(b, i);
            objects.push_back(new fcl::CollisionObjectd(box, tf));  // computes the AABB
        }
        manager.registerObjects(objects);
        manager.setup();
    }
    void update(const Boxes &b) override {
        for (size_t i = 0; i < b.n; ++i) {
            objects[i]->setTranslation(center_of(b, i));
            objects[i]->computeAABB();
        }
        manager.update();
    }
    uint64_t find() override {
        Count c;
        manager.collide(&c, callback);
        callbacks = c.calls;
        return c.overlapping;
    }
    std::string extra() const override { return json_u64("callback_pairs", callbacks); }
};
#endif

#ifdef HGCD_BENCH_BULLET
struct BulletPeer : Peer {
    btDbvtBroadphase broadphase;
    std::vector<btBroadphaseProxy *> proxies;
    uint64_t cache_pairs = 0;

    static btVector3 lo_of(const Boxes &b, size_t i) {
        return btVector3(btScalar(b.lo[3 * i]), btScalar(b.lo[3 * i + 1]), btScalar(b.lo[3 * i + 2]));
    }
    static btVector3 hi_of(const Boxes &b, size_t i) {
        return btVector3(btScalar(b.hi[3 * i]), btScalar(b.hi[3 * i + 1]), btScalar(b.hi[3 * i + 2]));
    }
    ~BulletPeer() {
        for (auto *p : proxies) broadphase.destroyProxy(p, nullptr);
    }
    void build(const Boxes &b) override {
        proxies.reserve(b.n);
        for (size_t i = 0; i < b.n; ++i)
            proxies.push_back(broadphase.createProxy(lo_of(b, i), hi_of(b, i), BOX_SHAPE_PROXYTYPE,
                                                     reinterpret_cast<void *>(static_cast<uintptr_t>(i)),
                                                     int(btBroadphaseProxy::DefaultFilter),
                                                     int(btBroadphaseProxy::AllFilter), nullptr));
        // Proxies are inserted one by one (greedy descent); rebuild both trees
        // top-down once, as a user adding many objects at once would.
        broadphase.optimize();
    }
    void update(const Boxes &b) override {
        for (size_t i = 0; i < b.n; ++i) broadphase.setAabb(proxies[i], lo_of(b, i), hi_of(b, i), nullptr);
    }
    uint64_t find() override {
        broadphase.calculateOverlappingPairs(nullptr);
        btOverlappingPairCache *cache = broadphase.getOverlappingPairCache();
        cache_pairs = static_cast<uint64_t>(cache->getNumOverlappingPairs());
        // The cache holds pairs of overlapping fattened leaves; keep the pairs
        // whose own boxes overlap (closed intervals, as TestAabbAgainstAabb2).
        const btBroadphasePairArray &pairs = cache->getOverlappingPairArray();
        uint64_t count = 0;
        for (int k = 0; k < pairs.size(); ++k) {
            const btBroadphaseProxy *p = pairs[k].m_pProxy0, *q = pairs[k].m_pProxy1;
            if (TestAabbAgainstAabb2(p->m_aabbMin, p->m_aabbMax, q->m_aabbMin, q->m_aabbMax)) ++count;
        }
        return count;
    }
    std::string extra() const override { return json_u64("cache_pairs", cache_pairs); }
};
#endif

#ifdef HGCD_BENCH_ODE
struct OdePeer : Peer {
    dSpaceID space = nullptr;
    std::vector<dGeomID> geoms;
    int min_level = 0, max_level = 0;
    uint64_t callbacks = 0;

    struct Count {
        uint64_t overlapping = 0, calls = 0;
    };
    static void callback(void *data, dGeomID g1, dGeomID g2) {
        Count *c = static_cast<Count *>(data);
        ++c->calls;
        dReal a[6], b[6];  // minx maxx miny maxy minz maxz
        dGeomGetAABB(g1, a);
        dGeomGetAABB(g2, b);
        if (a[0] <= b[1] && b[0] <= a[1] && a[2] <= b[3] && b[2] <= a[3] && a[4] <= b[5] && b[4] <= a[5])
            ++c->overlapping;
    }
    OdePeer() {
        dInitODE2(0);
        dAllocateODEDataForThread(dAllocateMaskAll);
    }
    ~OdePeer() {
        if (space) dSpaceDestroy(space);  // destroys the geoms too (cleanup mode on)
        dCloseODE();
    }
    void build(const Boxes &b) override {
        // Levels: ODE puts a geom on level k with 2^(k-1) < largest side <= 2^k.
        bool first = true;
        for (size_t i = 0; i < b.n; ++i) {
            double side = 0.0;
            for (int a = 0; a < 3; ++a) side = std::max(side, b.hi[3 * i + a] - b.lo[3 * i + a]);
            int level = 0;
            std::frexp(side, &level);
            if (first || level < min_level) min_level = level;
            if (first || level > max_level) max_level = level;
            first = false;
        }
        space = dHashSpaceCreate(nullptr);
        dHashSpaceSetLevels(space, min_level, max_level);
        geoms.reserve(b.n);
        for (size_t i = 0; i < b.n; ++i) {
            dGeomID g = dCreateBox(space, b.hi[3 * i] - b.lo[3 * i], b.hi[3 * i + 1] - b.lo[3 * i + 1],
                                   b.hi[3 * i + 2] - b.lo[3 * i + 2]);
            dGeomSetPosition(g, 0.5 * (b.lo[3 * i] + b.hi[3 * i]), 0.5 * (b.lo[3 * i + 1] + b.hi[3 * i + 1]),
                             0.5 * (b.lo[3 * i + 2] + b.hi[3 * i + 2]));
            geoms.push_back(g);
        }
    }
    void update(const Boxes &b) override {
        for (size_t i = 0; i < b.n; ++i)
            dGeomSetPosition(geoms[i], 0.5 * (b.lo[3 * i] + b.hi[3 * i]), 0.5 * (b.lo[3 * i + 1] + b.hi[3 * i + 1]),
                             0.5 * (b.lo[3 * i + 2] + b.hi[3 * i + 2]));
    }
    uint64_t find() override {
        Count c;
        dSpaceCollide(space, &c, callback);
        callbacks = c.calls;
        return c.overlapping;
    }
    // dxHashSpace::collide keeps an n x n bit matrix ("tested") of
    // n * ((n + 7) >> 3) bytes, computed in int: beyond n = 131071 the size
    // overflows and ODE aborts ("assertion i >= 0 && (sizeint)i <
    // (tested_rowsize*n) failed", seen at n = 140000), and below that it
    // still costs n^2/8 bytes (1.25 GB at n = 100000), cleared on every call.
    std::string unsupported(uint64_t n) const override {
        const uint64_t bytes = n * ((n + 7) >> 3);
        if (bytes > 0x7fffffffull)
            return "ODE dHashSpace allocates an n*n bit matrix of n*((n+7)>>3) bytes in int arithmetic; "
                   "it overflows for n > 131071 and ODE aborts";
        const double phys = static_cast<double>(sysconf(_SC_PHYS_PAGES)) * static_cast<double>(sysconf(_SC_PAGESIZE));
        if (phys > 0.0 && static_cast<double>(bytes) > 0.5 * phys)
            return "ODE dHashSpace's n*n bit matrix would take more than half of the physical memory";
        return std::string();
    }
    std::string extra() const override {
        char buf[96];
        std::snprintf(buf, sizeof buf, ",\"ode_levels\":[%d,%d]", min_level, max_level);
        return json_u64("callback_pairs", callbacks) + buf;
    }
};
#endif

std::vector<std::string> compiled_peers() {
    std::vector<std::string> v;
#ifdef HGCD_BENCH_FCL
    v.push_back("fcl");
#endif
#ifdef HGCD_BENCH_BULLET
    v.push_back("bullet");
#endif
#ifdef HGCD_BENCH_ODE
    v.push_back("ode");
#endif
    return v;
}

std::unique_ptr<Peer> make_peer(const std::string &lib) {
#ifdef HGCD_BENCH_FCL
    if (lib == "fcl") return std::unique_ptr<Peer>(new FclPeer);
#endif
#ifdef HGCD_BENCH_BULLET
    if (lib == "bullet") return std::unique_ptr<Peer>(new BulletPeer);
#endif
#ifdef HGCD_BENCH_ODE
    if (lib == "ode") return std::unique_ptr<Peer>(new OdePeer);
#endif
    (void)lib;
    return std::unique_ptr<Peer>();
}

void usage(const char *argv0) {
    std::fprintf(stderr,
                 "usage: %s --lib fcl|bullet|ode [--n N] [--seed S] [--ticks T] [--commit HASH]\n"
                 "          [--max-tick-seconds X] [--max-seconds Y]\n"
                 "       %s --list\n"
                 "  A peer whose tick (update + pair finding) takes longer than X seconds\n"
                 "  (default 60) stops after that tick, and one whose build, initial search and\n"
                 "  ticks would pass Y seconds (default 300) stops before the tick that would;\n"
                 "  at least one tick is always measured; \"ticks\" in the JSON is the number measured.\n",
                 argv0, argv0);
}

}  // namespace

int main(int argc, char **argv) {
    std::string lib, commit = "unknown";
    uint64_t n = 100000, seed = 1;
    int ticks = 5;
    double max_tick_seconds = 60.0, max_seconds = 300.0;
    for (int i = 1; i < argc; ++i) {
        const std::string a = argv[i];
        if (a == "--list") {
            for (const auto &p : compiled_peers()) std::printf("%s\n", p.c_str());
            return 0;
        }
        if (i + 1 >= argc) {
            usage(argv[0]);
            return 2;
        }
        const char *v = argv[++i];
        if (a == "--lib") lib = v;
        else if (a == "--n") n = std::strtoull(v, nullptr, 10);
        else if (a == "--seed") seed = std::strtoull(v, nullptr, 10);
        else if (a == "--ticks") ticks = std::atoi(v);
        else if (a == "--commit") commit = v;
        else if (a == "--max-tick-seconds") max_tick_seconds = std::atof(v);
        else if (a == "--max-seconds") max_seconds = std::atof(v);
        else {
            usage(argv[0]);
            return 2;
        }
    }
    if (n < 1 || n > 0xffffffffu || ticks < 1) {
        std::fprintf(stderr, "bench_peers: need 1 <= n < 2^32 and ticks >= 1\n");
        return 2;
    }
    std::unique_ptr<Peer> peer = make_peer(lib);
    if (!peer) {
        std::fprintf(stderr, "bench_peers: peer '%s' is not compiled in (available:", lib.c_str());
        for (const auto &p : compiled_peers()) std::fprintf(stderr, " %s", p.c_str());
        std::fprintf(stderr, ")\n");
        usage(argv[0]);
        return 2;
    }

    const std::string why_not = peer->unsupported(n);
    if (!why_not.empty()) {
        std::fprintf(stderr, "bench_peers: %s skipped at n = %llu: %s\n", lib.c_str(),
                     static_cast<unsigned long long>(n), why_not.c_str());
        std::printf("{\"lib\":\"%s\",\"scene\":\"tetra\",\"n\":%llu,\"seed\":%llu,\"threads\":1,\"ticks\":0,"
                    "\"ticks_requested\":%d,\"commit\":\"%s\",\"bounding_volume\":\"aabb\",\"skipped\":\"%s\","
                    "\"pairs_ok\":null}\n",
                    lib.c_str(), static_cast<unsigned long long>(n), static_cast<unsigned long long>(seed), ticks,
                    commit.c_str(), why_not.c_str());
        return 0;
    }

    Scene scene;
    if (!make_scene(n, seed, scene)) {
        std::fprintf(stderr, "bench_peers: scene generation failed\n");
        return 1;
    }
    Boxes boxes;
    uint64_t outside = compute_boxes(scene, boxes);
    const uint64_t initial_reference = count_overlaps(boxes);
    // Peak RSS before the peer exists (scene, boxes and the sweep's buffers included).
    const double rss_before = peak_rss_bytes();

    double t0 = now_seconds();
    peer->build(boxes);
    const double setup_ms = 1e3 * (now_seconds() - t0);
    t0 = now_seconds();
    const uint64_t initial_pairs = peer->find();
    const double initial_ms = 1e3 * (now_seconds() - t0);
    bool pairs_ok = initial_pairs == initial_reference;
    if (!pairs_ok)
        std::fprintf(stderr, "bench_peers: %s, initial poses: %llu pairs, sweep says %llu\n", lib.c_str(),
                     static_cast<unsigned long long>(initial_pairs),
                     static_cast<unsigned long long>(initial_reference));

    std::vector<double> motion_ms, aabb_ms, update_ms, pairs_ms, broad_ms, reference_ms;
    uint64_t pairs = initial_pairs, reference = initial_reference;
    // A slow first pair search predicts slow ticks: measure one tick only.
    int budget = ticks;
    if (setup_ms + initial_ms > 1e3 * max_tick_seconds) budget = 1;
    const double run_start = now_seconds() - 1e-3 * (setup_ms + initial_ms);
    for (int k = 0; k < budget; ++k) {
        t0 = now_seconds();
        hgcd_scene_tetra_move(scene.n, scene.side, scene.centers.data(), scene.velocities.data());
        double t1 = now_seconds();
        motion_ms.push_back(1e3 * (t1 - t0));
        outside += compute_boxes(scene, boxes);
        t0 = now_seconds();
        aabb_ms.push_back(1e3 * (t0 - t1));
        reference = count_overlaps(boxes);
        t1 = now_seconds();
        reference_ms.push_back(1e3 * (t1 - t0));

        t0 = now_seconds();
        peer->update(boxes);
        t1 = now_seconds();
        pairs = peer->find();
        const double t2 = now_seconds();
        update_ms.push_back(1e3 * (t1 - t0));
        pairs_ms.push_back(1e3 * (t2 - t1));
        broad_ms.push_back(1e3 * (t2 - t0));
        if (pairs != reference) {
            pairs_ok = false;
            std::fprintf(stderr, "bench_peers: %s, tick %d: %llu pairs, sweep says %llu\n", lib.c_str(), k + 1,
                         static_cast<unsigned long long>(pairs), static_cast<unsigned long long>(reference));
        }
        if (k + 1 < budget && t2 - t0 > max_tick_seconds) {
            std::fprintf(stderr, "bench_peers: %s took %.1f s for tick %d (> %.0f s): stopping after %d tick(s)\n",
                         lib.c_str(), t2 - t0, k + 1, max_tick_seconds, k + 1);
            break;
        }
        if (k + 1 < budget && now_seconds() + (t2 - t0) - run_start > max_seconds) {
            std::fprintf(stderr, "bench_peers: %s: another tick would pass the %.0f s budget: stopping after %d tick(s)\n",
                         lib.c_str(), max_seconds, k + 1);
            break;
        }
    }
    const double rss_after = peak_rss_bytes();
    const std::string extra = peer->extra();

    std::printf("{\"lib\":\"%s\",\"scene\":\"tetra\",\"n\":%llu,\"seed\":%llu,\"threads\":1,\"ticks\":%d,"
                "\"ticks_requested\":%d,\"commit\":\"%s\",\"bounding_volume\":\"aabb\","
                "\"broad_ms\":%.3f,\"update_ms\":%.3f,\"pairs_ms\":%.3f,\"motion_ms\":%.3f,\"aabb_ms\":%.3f,"
                "\"reference_ms\":%.3f,\"candidate_pairs\":%llu,\"reference_pairs\":%llu,\"initial_pairs\":%llu,"
                "\"initial_ms\":%.3f,\"setup_ms\":%.3f,\"peak_rss_mb\":%.1f,\"bytes_per_body\":%.1f%s,"
                "\"boxes_ok\":%s,\"pairs_ok\":%s}\n",
                lib.c_str(), static_cast<unsigned long long>(n), static_cast<unsigned long long>(seed),
                static_cast<int>(broad_ms.size()), ticks, commit.c_str(), median(broad_ms), median(update_ms),
                median(pairs_ms), median(motion_ms), median(aabb_ms), median(reference_ms),
                static_cast<unsigned long long>(pairs), static_cast<unsigned long long>(reference),
                static_cast<unsigned long long>(initial_pairs), initial_ms, setup_ms, rss_after / (1024.0 * 1024.0),
                (rss_after - rss_before) / static_cast<double>(n), extra.c_str(), outside == 0 ? "true" : "false",
                pairs_ok ? "true" : "false");
    std::fflush(stdout);
    std::fflush(stderr);
    // Skip the teardown: it is not measured, and Bullet's destroyProxy scans
    // the whole pair cache for each proxy (O(n * pairs): a quarter of an hour
    // at n = 750000). The system reclaims everything.
    std::_Exit(0);
}
