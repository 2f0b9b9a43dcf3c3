// Ray casts: each ray's segment against the query tree, nearest boxes
// first, pruned by the best hit so far; the bodies reached get the exact
// tests of solid.cpp, and hits are ordered exactly (crossing.cpp).
#include <omp.h>

#include <cmath>
#include <string>

#include "common/ieee.hpp"
#include "common/parallel.hpp"
#include "narrow/narrow.hpp"
#include "query/solid.hpp"
#include "world/limits.hpp"
#include "world/world.hpp"

namespace hgcd {

namespace {

constexpr double kMargin = 0x1p-40;  // segment_meets_box's

struct Hit {
    uint32_t slot = UINT32_MAX;
    uint32_t triangle = UINT32_MAX;
    bool inside = false;
    RayCrossing c{};
    double v[9];  // the crossed triangle's world vertices
    double upper = 1;  // bound on its parameter
    const double *tri(int i) const { return v + 3 * i; }
};

inline void prefetch_below(const QueryTree &tree, const QueryNode &n) {
    if (n.count == 0) __builtin_prefetch(&tree.nodes[n.first]);
    else __builtin_prefetch(&tree.items[n.first]);
}

// Is candidate (slot, crossing c on triangle cv) before the best hit?
bool before(const double *o, const double *e, uint32_t slot, const RayCrossing &c, const double *const *cv,
            const Hit &best) {
    if (best.slot == UINT32_MAX) return true;
    const double *bv[3] = {best.tri(0), best.tri(1), best.tri(2)};
    const int s = compare_crossings(o, e, cv, c, bv, best.c);
    return s < 0 || (s == 0 && slot < best.slot);
}

}  // namespace

hgcd_status World::cast_rays(const hgcd_ray *rays, size_t count, size_t stride, int32_t mode,
                             const hgcd_query_filter *filter, hgcd_ray_hit *out) {
    if (mode != HGCD_RAY_CLOSEST && mode != HGCD_RAY_ANY)
        return fail(HGCD_ERROR_INVALID_ARGUMENT, "world_cast_rays: mode must be HGCD_RAY_CLOSEST or HGCD_RAY_ANY");
    if (stride != 0 && (stride % sizeof(double) != 0 || stride < sizeof(hgcd_ray)))
        return fail(HGCD_ERROR_INVALID_ARGUMENT,
                    "world_cast_rays: ray_stride must be 0 or a multiple of 8 of at least sizeof(hgcd_ray)");
    if (stride == 0) stride = sizeof(hgcd_ray);
    const auto ray = [&](size_t k) {
        return reinterpret_cast<const hgcd_ray *>(reinterpret_cast<const char *>(rays) + k * stride);
    };
    for (size_t k = 0; k < count; ++k) {
        const hgcd_ray &r = *ray(k);
        bool ok = std::isfinite(r.max_distance) && r.max_distance >= 0;
        bool nonzero = false;
        for (int a = 0; a < 3; ++a) {
            ok = ok && coordinate_ok(r.origin[a]) && std::isfinite(r.direction[a]) &&
                 coordinate_ok(r.origin[a] + r.max_distance * r.direction[a]);
            nonzero = nonzero || r.direction[a] != 0;
        }
        if (!ok || !nonzero)
            return fail(HGCD_ERROR_INVALID_ARGUMENT,
                        "world_cast_rays: ray " + std::to_string(k) +
                            (nonzero ? ": origin and end must be finite and within 1e15, max_distance finite and >= 0"
                                     : ": direction is zero or not finite"));
    }
    if (count == 0) return HGCD_OK;
    ensure_query_tree();
    // Only a query filter or a disabled body makes the per-body test needed.
    const bool every = !filter && disabled_bodies_ == 0;
    const auto considers = [&](uint32_t slot) { return every || filter_accepts(filter, filter_[at_[slot]]); };
    const QueryTree &tree = query_.tree;
    const bool any = mode == HGCD_RAY_ANY;
    parallel_region(threads(), [&](RegionGuard &guard) {
        std::vector<double> world;
        std::pair<uint32_t, double> stack[kQueryStack];
#pragma omp for schedule(dynamic, 256)
        for (int64_t k = 0; k < int64_t(count); ++k) {
            guard.run([&] {
                const hgcd_ray &r = *ray(size_t(k));
                double e[3];
                for (int a = 0; a < 3; ++a) e[a] = r.origin[a] + r.max_distance * r.direction[a];
                const double *o = r.origin;
                SegmentProbe probe;
                probe.set(o, e);
                Hit best;
                int top = 0;
                double enter;
                if (!tree.nodes.empty() &&
                    segment_meets_box(probe, tree.nodes[0].lo, tree.nodes[0].hi, 1.0, &enter))
                    stack[top++] = {0, enter};
                while (top > 0) {
                    const auto [n, at] = stack[--top];
                    if (at > best.upper + kMargin) continue;
                    const QueryNode &node = tree.nodes[n];
                    if (node.count == 0) {
                        double e0, e1;
                        const QueryNode &c0 = tree.nodes[node.first], &c1 = tree.nodes[node.first + 1];
                        const bool h0 = segment_meets_box(probe, c0.lo, c0.hi, best.upper, &e0);
                        const bool h1 = segment_meets_box(probe, c1.lo, c1.hi, best.upper, &e1);
                        // What a child's visit reads next, asked for now (the
                        // walk is bound by memory latency).
                        if (h0) prefetch_below(tree, c0);
                        if (h1) prefetch_below(tree, c1);
                        if (h0 && h1) {  // nearer one on top
                            if (e0 <= e1) {
                                stack[top++] = {node.first + 1, e1};
                                stack[top++] = {node.first, e0};
                            } else {
                                stack[top++] = {node.first, e0};
                                stack[top++] = {node.first + 1, e1};
                            }
                        } else if (h0) {
                            stack[top++] = {node.first, e0};
                        } else if (h1) {
                            stack[top++] = {node.first + 1, e1};
                        }
                        continue;
                    }
                    for (uint32_t i = node.first; i < node.first + node.count; ++i) {
                        const QueryItem &it = tree.items[i];
                        if (!segment_meets_box(probe, it.lo, it.hi, best.upper, &enter)) continue;
                        if (!considers(it.slot)) continue;
                        double box[6];
                        const SolidView view = query_view(i, world, box);
                        const Mesh &m = *view.mesh;
                        RayCrossing c;
                        if (m.closed && point_in_solid(view, o)) {
                            c = RayCrossing{0, 0, 0, 0, true, false};
                            const double *none[3] = {o, o, o};
                            if (!before(o, e, it.slot, c, none, best)) continue;
                            best.slot = it.slot;
                            best.triangle = UINT32_MAX;
                            best.inside = true;
                            best.c = c;
                            best.upper = 0;
                        } else {
                            const uint32_t t =
                                first_crossing(view, o, e, probe.smin, probe.smax, any, &c);
                            if (t == UINT32_MAX) continue;
                            const double *v[3] = {view.vertex(t, 0), view.vertex(t, 1), view.vertex(t, 2)};
                            if (!before(o, e, it.slot, c, v, best)) continue;
                            best.slot = it.slot;
                            best.triangle = t;
                            best.inside = false;
                            best.c = c;
                            for (int j = 0; j < 3; ++j)
                                for (int a = 0; a < 3; ++a) best.v[3 * j + a] = v[j][a];
                            best.upper = crossing_upper(c);
                        }
                        if (any) break;
                    }
                    if (any && best.slot != UINT32_MAX) break;
                }
                hgcd_ray_hit &h = out[k];
                if (best.slot == UINT32_MAX) {
                    h = hgcd_ray_hit{hgcd_body{0, 0}, UINT32_MAX, 0, 0.0};
                    return;
                }
                const double *bv[3] = {best.tri(0), best.tri(1), best.tri(2)};
                const double t = best.inside ? 0.0 : crossing_parameter(o, e, bv, best.c);
                h = hgcd_ray_hit{hgcd_body{best.slot, live_gen_[best.slot]}, best.triangle,
                                 uint32_t(best.inside), r.max_distance * t};
            });
        }
    });
    return HGCD_OK;
}

}  // namespace hgcd
