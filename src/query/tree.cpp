// The query tree's build (binned surface area heuristic, median splits
// where it finds none) and the conservative segment-box test of the ray traversal.
#include "common/ieee.hpp"
#include "query/tree.hpp"

#include <algorithm>
#include <cmath>

namespace hgcd {

namespace {

struct Builder {
    std::vector<QueryItem> &items;
    std::vector<QueryNode> &nodes;

    static float centre(const QueryItem &it, int k) { return it.lo[k] + it.hi[k]; }  // (twice; order only)

    void bounds(uint32_t begin, uint32_t end, QueryNode &n) const {
        for (int k = 0; k < 3; ++k) {
            n.lo[k] = INFINITY;
            n.hi[k] = -INFINITY;
        }
        for (uint32_t i = begin; i < end; ++i)
            for (int k = 0; k < 3; ++k) {
                n.lo[k] = std::min(n.lo[k], items[i].lo[k]);
                n.hi[k] = std::max(n.hi[k], items[i].hi[k]);
            }
    }

    static float area(const float *lo, const float *hi) {
        const float dx = hi[0] - lo[0], dy = hi[1] - lo[1], dz = hi[2] - lo[2];
        return dx * dy + dy * dz + dz * dx;
    }

    // The split of items [begin, end) by the surface area heuristic over
    // kBins bins of the centres per axis: returns the axis and the first bin
    // of the right side, or axis -1 when
    // no binned split separates them (then the median of the longest axis).
    static constexpr int kBins = 16;
    int sah_split(uint32_t begin, uint32_t end, const float *clo, const float *chi, int *cut) const {
        float best = INFINITY;
        int best_axis = -1;
        for (int k = 0; k < 3; ++k) {
            const float extent = chi[k] - clo[k];
            if (!(extent > 0)) continue;
            const float scale = kBins / extent;
            uint32_t count[kBins] = {};
            float blo[kBins][3], bhi[kBins][3];
            for (int b = 0; b < kBins; ++b)
                for (int a = 0; a < 3; ++a) {
                    blo[b][a] = INFINITY;
                    bhi[b][a] = -INFINITY;
                }
            for (uint32_t i = begin; i < end; ++i) {
                const int b = std::min(kBins - 1, int((centre(items[i], k) - clo[k]) * scale));
                ++count[b];
                for (int a = 0; a < 3; ++a) {
                    blo[b][a] = std::min(blo[b][a], items[i].lo[a]);
                    bhi[b][a] = std::max(bhi[b][a], items[i].hi[a]);
                }
            }
            // Right-to-left sweep of areas and counts, then left to right.
            float rarea[kBins];
            uint32_t rcount[kBins];
            float lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
            uint32_t c = 0;
            for (int b = kBins - 1; b > 0; --b) {
                for (int a = 0; a < 3; ++a) {
                    lo[a] = std::min(lo[a], blo[b][a]);
                    hi[a] = std::max(hi[a], bhi[b][a]);
                }
                c += count[b];
                rarea[b] = c ? area(lo, hi) : 0;
                rcount[b] = c;
            }
            for (int a = 0; a < 3; ++a) {
                lo[a] = INFINITY;
                hi[a] = -INFINITY;
            }
            c = 0;
            for (int b = 0; b + 1 < kBins; ++b) {
                for (int a = 0; a < 3; ++a) {
                    lo[a] = std::min(lo[a], blo[b][a]);
                    hi[a] = std::max(hi[a], bhi[b][a]);
                }
                c += count[b];
                if (c == 0 || rcount[b + 1] == 0) continue;
                const float cost = float(c) * area(lo, hi) + float(rcount[b + 1]) * rarea[b + 1];
                if (cost < best) {
                    best = cost;
                    best_axis = k;
                    *cut = b + 1;
                }
            }
        }
        return best_axis;
    }

    // Node `at` over items [begin, end): children are allocated as a pair.
    // Past depth kSahDepth the splits are medians, so the depth stays below
    // kSahDepth + log2(n) + 2 < kQueryStack (the traversals' stacks).
    static constexpr int kSahDepth = 40;
    void build(uint32_t at, uint32_t begin, uint32_t end, int depth) {
        QueryNode &n = nodes[at];
        bounds(begin, end, n);
        if (end - begin <= kQueryLeafSize) {
            n.first = begin;
            n.count = end - begin;
            return;
        }
        float clo[3] = {INFINITY, INFINITY, INFINITY}, chi[3] = {-INFINITY, -INFINITY, -INFINITY};
        for (uint32_t i = begin; i < end; ++i)
            for (int k = 0; k < 3; ++k) {
                clo[k] = std::min(clo[k], centre(items[i], k));
                chi[k] = std::max(chi[k], centre(items[i], k));
            }
        int cut_bin = 0;
        const int sah_axis = depth < kSahDepth ? sah_split(begin, end, clo, chi, &cut_bin) : -1;
        uint32_t mid;
        if (sah_axis >= 0) {
            // The binning above recomputes each item's bin the same way, so
            // both sides are non-empty. (A stable partition: the order of
            // each side stays that of the items, sorted by slot at the root.)
            const float scale = kBins / (chi[sah_axis] - clo[sah_axis]);
            auto it = std::stable_partition(items.begin() + begin, items.begin() + end, [&](const QueryItem &x) {
                return std::min(kBins - 1, int((centre(x, sah_axis) - clo[sah_axis]) * scale)) < cut_bin;
            });
            mid = uint32_t(it - items.begin());
        } else {
            mid = begin;
        }
        if (mid == begin || mid == end) {
            int axis = 0;
            for (int k = 1; k < 3; ++k)
                if (chi[k] - clo[k] > chi[axis] - clo[axis]) axis = k;
            mid = begin + (end - begin) / 2;
            // Ties by slot: the split depends on the items alone.
            std::nth_element(items.begin() + begin, items.begin() + mid, items.begin() + end,
                             [axis](const QueryItem &x, const QueryItem &y) {
                                 const float cx = centre(x, axis), cy = centre(y, axis);
                                 return cx < cy || (cx == cy && x.slot < y.slot);
                             });
        }
        const uint32_t child = uint32_t(nodes.size());
        nodes.emplace_back();
        nodes.emplace_back();
        nodes[at].first = child;
        nodes[at].count = 0;
        build(child, begin, mid, depth + 1);
        build(child + 1, mid, end, depth + 1);
    }
};

// The wide node for binary node b (internal): its children, each internal
// one replaced by its two children, the largest first, while there is room
// for 4; then each internal child's wide node, depth first.
uint32_t collapse(const std::vector<QueryNode> &nodes, uint32_t b,
                  std::vector<QueryWide, CacheLineAllocator<QueryWide>> &wide) {
    uint32_t kids[4] = {nodes[b].first, nodes[b].first + 1, 0, 0};
    uint32_t n = 2;
    const auto area = [&](uint32_t k) {
        const QueryNode &x = nodes[k];
        const float dx = x.hi[0] - x.lo[0], dy = x.hi[1] - x.lo[1], dz = x.hi[2] - x.lo[2];
        return dx * dy + dy * dz + dz * dx;
    };
    while (n < 4) {
        int pick = -1;
        for (uint32_t k = 0; k < n; ++k)
            if (nodes[kids[k]].count == 0 && (pick < 0 || area(kids[k]) > area(kids[pick]))) pick = int(k);
        if (pick < 0) break;
        const uint32_t first = nodes[kids[pick]].first;
        kids[pick] = first;
        kids[n++] = first + 1;
    }
    const uint32_t at = uint32_t(wide.size());
    wide.emplace_back();
    QueryWide &w0 = wide[at];
    for (int a = 0; a < 3; ++a)
        for (int k = 0; k < 4; ++k) {
            w0.lo[a][k] = INFINITY;
            w0.hi[a][k] = -INFINITY;
        }
    w0.n = n;
    for (uint32_t k = 0; k < n; ++k) {
        const QueryNode &c = nodes[kids[k]];
        for (int a = 0; a < 3; ++a) {
            wide[at].lo[a][k] = c.lo[a];
            wide[at].hi[a][k] = c.hi[a];
        }
        wide[at].count[k] = uint8_t(c.count);
        wide[at].ref[k] = c.first;  // (leaves: their items)
    }
    for (uint32_t k = 0; k < n; ++k)
        if (nodes[kids[k]].count == 0) {
            const uint32_t child = collapse(nodes, kids[k], wide);  // (may move wide's storage)
            wide[at].ref[k] = child;
        }
    return at;
}

}  // namespace

double QueryTree::refit() {
    double total = 0;
    for (size_t at = wide.size(); at-- > 0;) {
        QueryWide &w = wide[at];
        for (uint32_t k = 0; k < w.n; ++k) {
            float lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
            const auto take = [&](const float *clo, const float *chi) {
                for (int a = 0; a < 3; ++a) {
                    lo[a] = std::min(lo[a], clo[a]);
                    hi[a] = std::max(hi[a], chi[a]);
                }
            };
            if (w.count[k]) {
                for (uint32_t i = w.ref[k]; i < w.ref[k] + w.count[k]; ++i) take(items[i].lo, items[i].hi);
            } else {
                const QueryWide &c = wide[w.ref[k]];
                for (uint32_t j = 0; j < c.n; ++j) {
                    const float clo[3] = {c.lo[0][j], c.lo[1][j], c.lo[2][j]}, chi[3] = {c.hi[0][j], c.hi[1][j], c.hi[2][j]};
                    take(clo, chi);
                }
            }
            for (int a = 0; a < 3; ++a) {
                w.lo[a][k] = lo[a];
                w.hi[a][k] = hi[a];
            }
            const double dx = double(hi[0]) - lo[0], dy = double(hi[1]) - lo[1], dz = double(hi[2]) - lo[2];
            total += dx * dy + dy * dz + dz * dx;
        }
    }
    return total;
}

void QueryTree::build(std::vector<QueryItem> &&in, int) {
    items = std::move(in);
    wide.clear();
    built_area = 0;
    if (items.empty()) return;
    std::sort(items.begin(), items.end(), [](const QueryItem &x, const QueryItem &y) { return x.slot < y.slot; });
    std::vector<QueryNode> nodes;
    nodes.reserve(2 * items.size() + 2);
    nodes.emplace_back();
    nodes.emplace_back();  // (unused: pairs start at even indices)
    Builder b{items, nodes};
    b.build(0, 0, uint32_t(items.size()), 0);
    wide.reserve(items.size() / 2 + 2);
    if (nodes[0].count != 0) {  // one leaf: a root with it as its one child
        wide.emplace_back();
        QueryWide &w = wide[0];
        for (int a = 0; a < 3; ++a)
            for (int k = 0; k < 4; ++k) {
                w.lo[a][k] = k == 0 ? nodes[0].lo[a] : INFINITY;
                w.hi[a][k] = k == 0 ? nodes[0].hi[a] : -INFINITY;
            }
        w.n = 1;
        w.ref[0] = nodes[0].first;
        w.count[0] = uint8_t(nodes[0].count);
    } else {
        collapse(nodes, 0, wide);
    }
    built_area = refit();
}

void SegmentProbe::set(const double *origin, const double *end) {
    for (int k = 0; k < 3; ++k) {
        o[k] = origin[k];
        e[k] = end[k];
        smin[k] = std::min(o[k], e[k]);
        smax[k] = std::max(o[k], e[k]);
        const double d = e[k] - o[k];  // (0 only when e = o on the axis)
        flat[k] = !(std::fabs(d) >= 0x1p-1020);
        inv[k] = flat[k] ? 0.0 : 1.0 / d;
    }
}

// Why nothing the segment meets is dropped. Per axis not flat, the segment's
// exact parameters at the planes lo and hi are (lo - o) / (e - o) and (hi -
// o) / (e - o); the computed ones round e - o, 1 / d, lo - o and the product
// (relative 5u at most; an underflow adds under 2^-1074, an overflow gives
// an infinity of the right sign: rounding is monotone). The exact segment
// meets the box at parameter t in [0, limit] only if, per axis, t lies
// between its two exact parameters. Then each entry (the smaller of the
// two) that exceeds 0 is at most limit <= 1, so its computed value is at
// most t + 5u; each exit that is below 1 is at least t >= 0, so its computed
// value is at least t - 5u; entries at most 0 and exits at least 1 compute
// to at most 5u above 0 and 5u below 1 (within 5u relative of a value of
// that sign... below and above, respectively). So the computed max entry
// (with 0) and min exit (with limit) are within 2^-50 of values that
// satisfy enter <= exit: the margin 2^-40 suffices. Flat axes: the segment's
// span on the axis is compared with the box exactly.
bool segment_meets_box(const SegmentProbe &s, const float *lo, const float *hi, double limit, double *enter) {
    double t0 = 0, t1 = limit;
    for (int k = 0; k < 3; ++k) {
        const double l = double(lo[k]), h = double(hi[k]);
        if (s.flat[k]) {
            if (s.smax[k] < l || s.smin[k] > h) return false;
            continue;
        }
        double a = (l - s.o[k]) * s.inv[k], b = (h - s.o[k]) * s.inv[k];
        if (a > b) std::swap(a, b);
        t0 = std::max(t0, a);
        t1 = std::min(t1, b);
    }
    *enter = t0;
    return t0 <= t1 + 0x1p-40;
}

uint32_t morton_code(const double *p, const float *lo, const float *hi) {
    uint32_t code = 0;
    for (int a = 0; a < 3; ++a) {
        const double extent = double(hi[a]) - double(lo[a]);
        double x = extent > 0 ? (p[a] - double(lo[a])) / extent * 1024.0 : 0.0;
        x = std::min(std::max(x, 0.0), 1023.0);  // (outside the box: its face)
        uint32_t v = uint32_t(x);
        // Spread the 10 bits three apart.
        v = (v | (v << 16)) & 0x030000FFu;
        v = (v | (v << 8)) & 0x0300F00Fu;
        v = (v | (v << 4)) & 0x030C30C3u;
        v = (v | (v << 2)) & 0x09249249u;
        code |= v << a;
    }
    return code;
}

unsigned segment_meets_children(const SegmentProbe &s, const QueryWide &w, double limit, double *enter) {
    // Per child, the arithmetic of segment_meets_box, axis by axis.
    double t0[4] = {0, 0, 0, 0}, t1[4] = {limit, limit, limit, limit};
    bool out[4] = {false, false, false, false};
    for (int k = 0; k < 3; ++k) {
        if (s.flat[k]) {
            for (int c = 0; c < 4; ++c) out[c] |= s.smax[k] < double(w.lo[k][c]) || s.smin[k] > double(w.hi[k][c]);
            continue;
        }
        for (int c = 0; c < 4; ++c) {
            double a = (double(w.lo[k][c]) - s.o[k]) * s.inv[k], b = (double(w.hi[k][c]) - s.o[k]) * s.inv[k];
            const double lo = std::min(a, b), hi = std::max(a, b);
            t0[c] = std::max(t0[c], lo);
            t1[c] = std::min(t1[c], hi);
        }
    }
    unsigned mask = 0;
    for (uint32_t c = 0; c < w.n; ++c) {
        enter[c] = t0[c];
        if (!out[c] && t0[c] <= t1[c] + 0x1p-40) mask |= 1u << c;
    }
    return mask;
}

}  // namespace hgcd
