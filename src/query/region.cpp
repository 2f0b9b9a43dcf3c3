// Box, point and mesh queries: each query's box against the query tree,
// the bodies reached decided exactly, the answers gathered per query in
// index order into the world's result arrays. Also the tree's upkeep.
#include <algorithm>
#include <cmath>
#include <cstring>
#include <string>

#include "common/ieee.hpp"
#include "broad/float_box.hpp"
#include "broad/grid.hpp"
#include "common/simd.hpp"
#include "common/parallel.hpp"
#include "common/transform.hpp"
#include "narrow/narrow.hpp"
#include "query/solid.hpp"
#include "world/limits.hpp"
#include "world/world.hpp"

namespace hgcd {

namespace {

constexpr size_t kChunk = 64;  // queries per unit of the dynamic schedule

const char *entry(const void *base, size_t stride, size_t k) {
    return reinterpret_cast<const char *>(base) + k * stride;
}

bool stride_ok(size_t stride, size_t size) { return stride == 0 || (stride % sizeof(double) == 0 && stride >= size); }

}  // namespace

void World::ensure_query_tree() {
    if (!query_.stale) return;
    QueryTree &tree = query_.tree;
    const Boxes b = boxes();
    const auto item_box = [&](QueryItem &it, size_t s) {
        double lo[3], hi[3];
        b.at(s, lo, hi);
        broad::round_outward(lo, hi, it.lo, it.hi);
    };
    // The passes over every body run in storage order, reading the world's
    // arrays in sequence and writing each body's item where the tree put it
    // (in the tree's order they were scattered reads, each a cache miss).
    const auto each_stored = [&](auto &&f) {
        parallel_for(threads(), int64_t(slot_of_.size()), 4096, Schedule::Static, [&](int64_t s0, int64_t s1, int) {
            for (int64_t s = s0; s < s1; ++s)
                if (stored_gen_[size_t(s)]) f(query_.item_of_slot[slot_of_[size_t(s)]], size_t(s));
        });
    };
    const auto index_items = [&] {
        query_.item_of_slot.resize(live_gen_.size());
        for (uint32_t i = 0; i < uint32_t(tree.items.size()); ++i) query_.item_of_slot[tree.items[i].slot] = i;
    };
    // Only boxes moved (no body created or destroyed): the items' boxes
    // again and a refit, a pass over the tree instead of a build; rebuilt
    // once the moves have loosened it to twice its nodes' area at the build
    // (a looser tree only costs the queries time: answers do not depend on
    // the tree).
    if (!query_.rebuild && !tree.wide.empty()) {
        each_stored([&](uint32_t i, size_t s) { item_box(tree.items[i], s); });
        if (tree.refit() > 2 * tree.built_area) {
            std::vector<QueryItem> items;
            items.swap(tree.items);
            tree.build(std::move(items), threads());
            index_items();
        }
    } else {
        std::vector<QueryItem> items;
        items.reserve(live_bodies_);
        for (uint32_t slot = 0; slot < uint32_t(live_gen_.size()); ++slot) {
            if (!live_gen_[slot]) continue;
            QueryItem it;
            it.slot = slot;
            it.mesh = body_mesh_[at_[slot]];
            item_box(it, at_[slot]);
            items.push_back(it);
        }
        tree.build(std::move(items), threads());
        index_items();
    }
    constexpr size_t kCache = 3 * QueryTree::kCachedVertices;
    tree.world.resize(kCache * tree.items.size());
    each_stored([&](uint32_t i, size_t s) {
        const Mesh &m = meshes_[body_mesh_[s]];
        if (m.vertex_count > QueryTree::kCachedVertices) return;
        const Placement &p = place_[s];
        const Rotation r = rotation_of(p.orientation);
        for (uint32_t v = 0; v < m.vertex_count; ++v)
            transform_point(r, p.position, p.scale, &m.vertices[3 * v], &tree.world[kCache * size_t(i) + 3 * v]);
    });
    query_.stale = query_.rebuild = false;
}

SolidView World::query_view(size_t i, QueryScratch &s, double *box) const {
    const QueryTree &tree = query_.tree;
    const QueryItem &it = tree.items[i];
    const Mesh &m = meshes_[it.mesh];
    const double *wv;
    if (m.vertex_count <= QueryTree::kCachedVertices) {
        wv = &tree.world[3 * QueryTree::kCachedVertices * i];
        for (int k = 0; k < 3; ++k) {
            box[k] = INFINITY;
            box[3 + k] = -INFINITY;
        }
        for (uint32_t v = 0; v < m.vertex_count; ++v)
            for (int k = 0; k < 3; ++k) {
                box[k] = std::min(box[k], wv[3 * v + k]);
                box[3 + k] = std::max(box[3 + k], wv[3 * v + k]);
            }
    } else if (!m.bvh.empty()) {
        // (By slot: storage may have been renumbered since the build.)
        prepare_query_view(pose_of(&m, place_[at_[it.slot]]), s.narrow, s.view);
        std::copy(s.view.box(0), s.view.box(0) + 6, box);
        return SolidView{&m, nullptr, box, &s.view, &s.narrow};
    } else {
        world_vertices(pose_of(&m, place_[at_[it.slot]]), s.world, box);
        wv = s.world.data();
    }
    return SolidView{&m, wv, box};
}

template <class Box, class Accept>
void World::run_region_queries(size_t count, const hgcd_filter *filter, Box &&box, Accept &&accept) {
    ensure_query_tree();
    // Only a query filter or a disabled body makes the per-body test needed.
    const bool every = !filter && disabled_bodies_ == 0;
    const auto considers = [&](uint32_t slot) { return every || filter_accepts(filter, filter_[at_[slot]]); };
    const QueryTree &tree = query_.tree;
    const size_t chunks = (count + kChunk - 1) / kChunk;
    // Queries are answered in spatial order (QueryTree::spatial_order), in
    // chunks of that order; each chunk keeps its queries' bodies, and each
    // query where they start (the chunk is that of its place in the order).
    const std::vector<uint32_t> order = tree.spatial_order(count, [&](size_t q, double *p) {
        double lo[3], hi[3];
        box(q, lo, hi);
        for (int a = 0; a < 3; ++a) p[a] = 0.5 * lo[a] + 0.5 * hi[a];
    });
    std::vector<std::vector<uint32_t>> found(chunks);
    std::vector<size_t> start(count);
    std::vector<size_t> sizes(count + 1, 0);
    const int T = threads();
    std::vector<QueryScratch> scratches(static_cast<size_t>(T));  // per worker
    std::vector<std::vector<uint32_t>> mines(static_cast<size_t>(T));
    parallel_for(T, int64_t(chunks), 1, Schedule::Dynamic, [&](int64_t c0, int64_t c1, int me) {
        QueryScratch &sc = scratches[size_t(me)];
        std::vector<uint32_t> &mine = mines[size_t(me)];
        std::pair<uint32_t, uint32_t> stack[kQueryStack];  // (wide node, 0) or (items, count)
        for (int64_t c = c0; c < c1; ++c) {
            std::vector<uint32_t> &out = found[size_t(c)];
            const size_t end = std::min(count, size_t(c + 1) * kChunk);
            for (size_t j = size_t(c) * kChunk; j < end; ++j) {
                const size_t q = order.empty() ? j : order[j];
                mine.clear();
                double lo[3], hi[3];
                box(q, lo, hi);
                // The tree's boxes are floats: compared with the query's
                // box rounded outward to float, which keeps every box the
                // doubles would keep (and may keep a few more).
                float flo[3], fhi[3];
                broad::round_outward(lo, hi, flo, fhi);
                const f32x4 qlo[3] = {f32x4{} + flo[0], f32x4{} + flo[1], f32x4{} + flo[2]};
                const f32x4 qhi[3] = {f32x4{} + fhi[0], f32x4{} + fhi[1], f32x4{} + fhi[2]};
                int top = 0;
                if (!tree.wide.empty()) stack[top++] = {0, 0};
                while (top > 0) {
                    const auto [ref, cnt] = stack[--top];
                    if (cnt == 0) {
                        // The children whose box meets the query's; what the
                        // visit of one reads first is asked for now.
                        const QueryWide &w = tree.wide[ref];
                        i32x4 apart = i32x4{};
                        for (int k = 0; k < 3; ++k) {
                            f32x4 clo, chi;
                            std::memcpy(&clo, w.lo[k], sizeof clo);
                            std::memcpy(&chi, w.hi[k], sizeof chi);
                            apart |= (clo > qhi[k]) | (chi < qlo[k]);
                        }
                        for (uint32_t c = w.n; c-- > 0;) {
                            if (apart[c]) continue;
                            if (w.count[c] == 0) {
                                const char *p = reinterpret_cast<const char *>(&tree.wide[w.ref[c]]);
                                __builtin_prefetch(p);
                                __builtin_prefetch(p + 64);
                            } else {
                                __builtin_prefetch(&tree.items[w.ref[c]]);
                            }
                            stack[top++] = {w.ref[c], w.count[c]};
                        }
                        continue;
                    }
                    for (uint32_t i = ref; i < ref + cnt; ++i) {
                        const QueryItem &it = tree.items[i];
                        bool away = false;
                        for (int k = 0; k < 3; ++k) away |= (it.lo[k] > fhi[k]) | (it.hi[k] < flo[k]);
                        if (!away && considers(it.slot) && accept(q, size_t(i), sc)) mine.push_back(it.slot);
                    }
                }
                std::sort(mine.begin(), mine.end());
                sizes[q + 1] = mine.size();
                start[q] = out.size();
                out.insert(out.end(), mine.begin(), mine.end());
            }
        }
    });
    for (size_t q = 0; q < count; ++q) sizes[q + 1] += sizes[q];
    std::vector<hgcd_body> bodies(sizes[count]);
    parallel_for(T, int64_t(chunks), 16, Schedule::Static, [&](int64_t c0, int64_t c1, int) {
        for (int64_t c = c0; c < c1; ++c) {
            const std::vector<uint32_t> &f = found[size_t(c)];
            const size_t end = std::min(count, size_t(c + 1) * kChunk);
            for (size_t j = size_t(c) * kChunk; j < end; ++j) {
                const size_t q = order.empty() ? j : order[j];
                for (size_t i = 0; i < sizes[q + 1] - sizes[q]; ++i) {
                    const uint32_t slot = f[start[q] + i];
                    bodies[sizes[q] + i] = hgcd_body{slot, live_gen_[slot]};
                }
            }
        }
    });
    query_.offsets.swap(sizes);
    query_.bodies.swap(bodies);
}

void World::publish(hgcd_query_results *out) {
    out->offsets = query_.offsets.data();
    out->bodies = query_.bodies.data();
    out->query_count = query_.offsets.size() - 1;
    out->body_count = query_.bodies.size();
}

hgcd_status World::query_boxes(const double *boxes, size_t count, size_t stride, const hgcd_filter *filter,
                               hgcd_query_results *out) {
    if (!stride_ok(stride, 6 * sizeof(double)))
        return fail(HGCD_ERROR_INVALID_ARGUMENT, "world_query_box: box_stride must be 0 or a multiple of 8 of at least 48");
    if (filter && filter->reserved != 0)
        return fail(HGCD_ERROR_INVALID_ARGUMENT, "world_query_box: filter.reserved is not 0");
    if (stride == 0) stride = 6 * sizeof(double);
    for (size_t k = 0; k < count; ++k) {
        const double *b = reinterpret_cast<const double *>(entry(boxes, stride, k));
        for (int a = 0; a < 3; ++a)
            if (!coordinate_ok(b[a]) || !coordinate_ok(b[3 + a]) || !(b[a] <= b[3 + a]))
                return fail(HGCD_ERROR_INVALID_ARGUMENT,
                            "world_query_box: box " + std::to_string(k) +
                                ": bounds must be finite, within 1e15, and min <= max on each axis");
    }
    run_region_queries(
        count, filter,
        [&](size_t q, double *lo, double *hi) {
            const double *b = reinterpret_cast<const double *>(entry(boxes, stride, q));
            for (int a = 0; a < 3; ++a) {
                lo[a] = b[a];
                hi[a] = b[3 + a];
            }
        },
        [&](size_t q, size_t i, QueryScratch &s) {
            const double *b = reinterpret_cast<const double *>(entry(boxes, stride, q));
            double box[6];
            return box_meets_solid(query_view(i, s, box), b, b + 3);
        });
    publish(out);
    return HGCD_OK;
}

hgcd_status World::query_points(const double *points, size_t count, size_t stride, const hgcd_filter *filter,
                                hgcd_query_results *out) {
    if (!stride_ok(stride, 3 * sizeof(double)))
        return fail(HGCD_ERROR_INVALID_ARGUMENT,
                    "world_query_point: point_stride must be 0 or a multiple of 8 of at least 24");
    if (filter && filter->reserved != 0)
        return fail(HGCD_ERROR_INVALID_ARGUMENT, "world_query_point: filter.reserved is not 0");
    if (stride == 0) stride = 3 * sizeof(double);
    for (size_t k = 0; k < count; ++k)
        if (!position_ok(reinterpret_cast<const double *>(entry(points, stride, k))))
            return fail(HGCD_ERROR_INVALID_ARGUMENT,
                        "world_query_point: point " + std::to_string(k) + " must be finite and within 1e15");
    run_region_queries(
        count, filter,
        [&](size_t q, double *lo, double *hi) {
            const double *p = reinterpret_cast<const double *>(entry(points, stride, q));
            for (int a = 0; a < 3; ++a) lo[a] = hi[a] = p[a];
        },
        [&](size_t q, size_t i, QueryScratch &s) {
            const double *p = reinterpret_cast<const double *>(entry(points, stride, q));
            double box[6];
            return point_in_solid(query_view(i, s, box), p);
        });
    publish(out);
    return HGCD_OK;
}

hgcd_status World::query_meshes(hgcd_mesh mesh, const hgcd_mesh_pose *poses, size_t count, size_t stride,
                                const hgcd_filter *filter, hgcd_query_results *out) {
    const int64_t ms = live_mesh(mesh);
    if (ms < 0) return fail(HGCD_ERROR_STALE_ID, "world_query_mesh: mesh is not a live mesh of this world");
    if (!stride_ok(stride, sizeof(hgcd_mesh_pose)))
        return fail(HGCD_ERROR_INVALID_ARGUMENT,
                    "world_query_mesh: pose_stride must be 0 or a multiple of 8 of at least sizeof(hgcd_mesh_pose)");
    if (filter && filter->reserved != 0)
        return fail(HGCD_ERROR_INVALID_ARGUMENT, "world_query_mesh: filter.reserved is not 0");
    if (stride == 0) stride = sizeof(hgcd_mesh_pose);
    const Mesh &qm = meshes_[size_t(ms)];
    const auto pose = [&](size_t k) { return reinterpret_cast<const hgcd_mesh_pose *>(entry(poses, stride, k)); };
    for (size_t k = 0; k < count; ++k) {
        const hgcd_mesh_pose &p = *pose(k);
        if (!position_ok(p.position) || !orientation_ok(p.orientation) || !scale_ok(p.scale, qm.reach))
            return fail(HGCD_ERROR_INVALID_ARGUMENT,
                        "world_query_mesh: pose " + std::to_string(k) +
                            ": position within 1e15, unit orientation (within 1e-6) and scale > 0 with "
                            "scale * mesh reach <= 1e15 required");
    }
    // Each pose's exact world box, computed once (the tree search reads it).
    std::vector<double> qbox(6 * count);
    parallel_for(threads(), int64_t(count), 64, Schedule::Dynamic, [&](int64_t k0, int64_t k1, int) {
        std::vector<double> w;
        for (int64_t k = k0; k < k1; ++k) {
            const hgcd_mesh_pose &p = *pose(size_t(k));
            world_vertices(BodyPose{&qm, p.position, p.orientation, p.scale}, w, &qbox[6 * size_t(k)]);
        }
    });
    run_region_queries(
        count, filter,
        [&](size_t q, double *lo, double *hi) {
            for (int a = 0; a < 3; ++a) {
                lo[a] = qbox[6 * q + a];
                hi[a] = qbox[6 * q + 3 + a];
            }
        },
        [&](size_t q, size_t i, QueryScratch &s) {
            const hgcd_mesh_pose &p = *pose(q);
            const size_t at = at_[query_.tree.items[i].slot];
            const BodyPose a{&qm, p.position, p.orientation, p.scale};
            return collide(a, pose_of(&meshes_[body_mesh_[at]], place_[at]), s.narrow) != Contact::None;
        });
    publish(out);
    return HGCD_OK;
}

}  // namespace hgcd
