// Ray casts: each ray's segment against the query tree, nearest boxes
// first, pruned by the best hit so far; the bodies reached get the exact
// tests of solid.cpp, and hits are ordered exactly (crossing.cpp).
#include <algorithm>
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

// A waiting child of the walk: a wide node (count 0) or a leaf's items,
// and the parameter where the segment enters its box.
struct Waiting {
    uint32_t ref, count;
    double enter;
};

// What a child's visit reads first, asked for now (the walk is bound by
// memory latency).
inline void prefetch_below(const QueryTree &tree, uint32_t ref, uint32_t count) {
    if (count == 0) {
        const char *p = reinterpret_cast<const char *>(&tree.wide[ref]);
        __builtin_prefetch(p);
        __builtin_prefetch(p + 64);
    } else {
        __builtin_prefetch(&tree.items[ref]);
    }
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
                             const hgcd_filter *filter, hgcd_ray_hit *out) {
    if (mode != HGCD_RAY_CLOSEST && mode != HGCD_RAY_ANY)
        return fail(HGCD_ERROR_INVALID_ARGUMENT, "world_cast_rays: mode must be HGCD_RAY_CLOSEST or HGCD_RAY_ANY");
    if (stride != 0 && (stride % sizeof(double) != 0 || stride < sizeof(hgcd_ray)))
        return fail(HGCD_ERROR_INVALID_ARGUMENT,
                    "world_cast_rays: ray_stride must be 0 or a multiple of 8 of at least sizeof(hgcd_ray)");
    if (filter && filter->reserved != 0)
        return fail(HGCD_ERROR_INVALID_ARGUMENT, "world_cast_rays: filter.reserved is not 0");
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
    const int T = threads();
    std::vector<QueryScratch> scratches(static_cast<size_t>(T));  // per worker
    // One ray: the tree walked nearest box first, pruned by the best hit.
    using Stack = Waiting[kQueryStack];
    const auto cast = [&](const hgcd_ray &r, QueryScratch &scratch, Stack &stack) -> hgcd_ray_hit {
        double e[3];
        for (int a = 0; a < 3; ++a) e[a] = r.origin[a] + r.max_distance * r.direction[a];
        const double *o = r.origin;
        SegmentProbe probe;
        probe.set(o, e);
        Hit best;
        int top = 0;
        double enter;
        if (!tree.wide.empty()) stack[top++] = {0, 0, 0.0};
        while (top > 0) {
            const Waiting node = stack[--top];
            if (node.enter > best.upper + kMargin) continue;
            if (node.count == 0) {
                const QueryWide &w = tree.wide[node.ref];
                double in[4];
                unsigned mask = segment_meets_children(probe, w, best.upper, in);
                // The children met, farthest first onto the stack (nearest
                // on top); ties keep the child order.
                Waiting met[4];
                int m = 0;
                for (; mask; mask &= mask - 1) {
                    const int c = __builtin_ctz(mask);
                    prefetch_below(tree, w.ref[c], w.count[c]);
                    Waiting x{w.ref[c], w.count[c], in[c]};
                    int j = m++;
                    for (; j > 0 && met[j - 1].enter < x.enter; --j) met[j] = met[j - 1];
                    met[j] = x;
                }
                for (int j = 0; j < m; ++j) stack[top++] = met[j];
                continue;
            }
            for (uint32_t i = node.ref; i < node.ref + node.count; ++i) {
                const QueryItem &it = tree.items[i];
                if (!segment_meets_box(probe, it.lo, it.hi, best.upper, &enter)) continue;
                if (!considers(it.slot)) continue;
                double box[6];
                const SolidView view = query_view(i, scratch, box);
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
                    double tv[9];
                    const uint32_t t =
                        first_crossing(view, o, e, probe.smin, probe.smax, any, &c, tv);
                    if (t == UINT32_MAX) continue;
                    const double *v[3] = {tv, tv + 3, tv + 6};
                    if (!before(o, e, it.slot, c, v, best)) continue;
                    best.slot = it.slot;
                    best.triangle = t;
                    best.inside = false;
                    best.c = c;
                    std::copy(tv, tv + 9, best.v);
                    best.upper = crossing_upper(c);
                }
                if (any) break;
            }
            if (any && best.slot != UINT32_MAX) break;
        }
        if (best.slot == UINT32_MAX) return hgcd_ray_hit{hgcd_body{0, 0}, UINT32_MAX, 0, 0.0};
        const double *bv[3] = {best.tri(0), best.tri(1), best.tri(2)};
        const double t = best.inside ? 0.0 : crossing_parameter(o, e, bv, best.c);
        return hgcd_ray_hit{hgcd_body{best.slot, live_gen_[best.slot]}, best.triangle, uint32_t(best.inside),
                            r.max_distance * t};
    };
    // Rays in spatial order of their origins (QueryTree::spatial_order).
    const std::vector<uint32_t> order =
        tree.spatial_order(count, [&](size_t k, double *p) { std::copy(ray(k)->origin, ray(k)->origin + 3, p); });
    parallel_for(T, int64_t(count), 256, Schedule::Dynamic, [&](int64_t j0, int64_t j1, int me) {
        Stack stack;
        for (int64_t j = j0; j < j1; ++j) {
            const size_t k = order.empty() ? size_t(j) : order[size_t(j)];
            out[k] = cast(*ray(k), scratches[size_t(me)], stack);
        }
    });
    return HGCD_OK;
}

}  // namespace hgcd
