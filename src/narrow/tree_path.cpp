// The narrow phase's tree path: pairs where at least one mesh has a BVH.
//
// World vertices are computed lazily, per pair, for the triangles the
// traversal reaches (BodyView::vertex), instead of all vertices of both
// bodies: for two large meshes in shallow contact, transforming them all
// costs more than the whole test. (Caching them per body per tick would need
// storage owned by the world, for little: a body takes part in few pairs.)
// When both meshes have trees (and no margin), the node tests run in a's
// mesh frame (rel_frame.hpp): a's boxes as built, b's nodes mapped there once
// per pair. Otherwise node boxes are conservative world boxes of the
// mesh-frame node boxes (BodyView::node_box argues the margin). Either way a
// node pair is skipped only when no rounded world vertex under one can share
// a point with the other; leaves get exact triangle boxes from the world
// vertices and the exact triangle test, exactly as the direct path.
#include "common/ieee.hpp"
#include "common/cpu.hpp"

#include <algorithm>
#include <cmath>

#include "exact/geometry.hpp"
#include "narrow/boxes.hpp"
#include "narrow/bvh.hpp"
#include "narrow/hull.hpp"
#include "narrow/narrow.hpp"
#include "narrow/rel_frame.hpp"
#include "narrow/tree_leaves.hpp"

namespace hgcd {

namespace {

void next_epoch(NarrowScratch &s) {
    if (++s.epoch == 0) {  // stamps wrapped: forget every cached value
        for (auto &c : s.side) {
            std::fill(c.vertex_stamp.begin(), c.vertex_stamp.end(), 0u);
            std::fill(c.box_stamp.begin(), c.box_stamp.end(), 0u);
            std::fill(c.image_slot.begin(), c.image_slot.end(), uint64_t(0));
        }
        s.epoch = 1;
    }
}

void prepare_side(const BodyPose &pose, const Rotation &r, NarrowScratch::Side &c, uint32_t epoch, BodyView &v) {
    const Mesh &m = *pose.mesh;
    v.mesh = &m;
    v.local = m.vertices.data();
    v.set_pose(pose.position, r, pose.scale);
    v.defect = rotation_defect(pose.orientation);
    v.epoch = epoch;
    const size_t nv = m.vertex_count;
    if (c.vertex_stamp.size() < nv) {
        c.vertex_stamp.resize(nv, 0);
        c.world.reset(new double[3 * nv]);
    }
    v.world = c.world.get();
    v.vertex_stamp = c.vertex_stamp.data();
    v.root = m.bvh.empty() ? &m.point_node : &m.bvh.nodes[0];
    v.lanes = m.bvh.empty() ? m.point_lanes.data() : m.bvh.lanes.data();
    if (m.bvh.empty()) {
        // A small mesh: one leaf with every triangle, its exact box.
        v.nodes = nullptr;
        v.tris = m.triangles.data();
        v.tri_ids = nullptr;
        double *b = v.root_box;
        b[0] = b[1] = b[2] = INFINITY;
        b[3] = b[4] = b[5] = -INFINITY;
        for (uint32_t i = 0; i < m.vertex_count; ++i) {
            const double *w = v.vertex(i);
            for (int k = 0; k < 3; ++k) {
                b[k] = std::min(b[k], w[k]);
                b[3 + k] = std::max(b[3 + k], w[k]);
            }
        }
        std::copy(b, b + 6, v.near_box);
        return;
    }
    const size_t nn = m.bvh.nodes.size();
    if (c.box_stamp.size() < nn) {
        c.box_stamp.resize(nn, 0);
        c.boxes.reset(new double[kNodeData * nn]);
    }
    v.nodes = m.bvh.nodes.data();
    v.tris = m.bvh.tris.data();
    v.tri_ids = m.bvh.tri_ids.data();
    v.boxes = c.boxes.get();
    v.box_stamp = c.box_stamp.data();
}

// Squared distance of box centres, times 4.
inline double dist2(const double *x, const double *y) {
    const double dx = (x[0] + x[3]) - (y[0] + y[3]), dy = (x[1] + x[4]) - (y[1] + y[4]),
                 dz = (x[2] + x[5]) - (y[2] + y[5]);
    return dx * dx + dy * dy + dz * dz;
}

inline double box_size(const double *b) { return (b[3] - b[0]) + (b[4] - b[1]) + (b[5] - b[2]); }

// Do the surfaces meet under the node pair (start_a, start_b)? meet: the
// meeting triangles (leaf order), leaves: their leaves. Node tests on world
// boxes (a side may have no tree). With kMargin: surfaces within d, node
// boxes grown by d (the plane test, which would need its own margin
// argument, is left out).
template <bool kMargin>
bool surfaces_meet(BodyView &a, BodyView &b, NarrowScratch &s, uint32_t start_a, uint32_t start_b, uint32_t *meet,
                   uint32_t *leaves, double d) {
    std::vector<uint64_t> &stack = s.pair_stack;
    stack.clear();
    stack.push_back((uint64_t(start_a) << 32) | start_b);
    while (!stack.empty()) {
        const uint64_t top = stack.back();
        stack.pop_back();
        const uint32_t i = uint32_t(top >> 32), j = uint32_t(top);
        const double *ba = a.box(i), *bb = b.box(j);
        if (kMargin ? boxes_apart(ba, bb, d) : boxes_disjoint(ba, bb)) continue;
        const bool la = a.leaf(i), lb = b.leaf(j);
        if (!kMargin && la != lb && (la ? plane_cut(a, i, bb) : plane_cut(b, j, ba))) continue;
        if (la && lb) {
            if (leaves_meet<kMargin>(a, i, b, j, s, meet, d)) {
                leaves[0] = i;
                leaves[1] = j;
                return true;
            }
            continue;
        }
        // Descend the larger node (or the one that is not a leaf).
        // The child whose centre is farther from the other node's is visited
        // first: where two surfaces cross, each lies near the other's box
        // boundary, not its middle (on the `meshes` scene, several times
        // fewer node pairs before the first meeting triangles than in a
        // fixed order).
        if (lb || (!la && box_size(ba) >= box_size(bb))) {
            const uint64_t c = a.nodes[i].first;
            const bool swap = dist2(a.box(c), bb) > dist2(a.box(c + 1), bb);
            stack.push_back(((c + !swap) << 32) | j);
            stack.push_back(((c + swap) << 32) | j);
        } else {
            const uint64_t c = b.nodes[j].first;
            const bool swap = dist2(b.box(c), ba) > dist2(b.box(c + 1), ba);
            stack.push_back((uint64_t(i) << 32) | (c + !swap));
            stack.push_back((uint64_t(i) << 32) | (c + swap));
        }
    }
    return false;
}

// b's node images in a's frame (rel_frame.hpp), a block of two siblings at
// a time, computed on first use in the pair and stored at the next free slot.
struct Images {
    const RelFrame *f;
    const double *lanes;  // b's Bvh::lanes
    double *data;
    uint64_t *slot;  // NarrowScratch::Side::image_slot
    uint32_t epoch;
    uint32_t used;
    HGCD_RF_INLINE const double *block(size_t p) {
        uint64_t at = slot[p];
        if (at >> 32 != epoch) {
            at = uint64_t(epoch) << 32 | used++;
            slot[p] = at;
            node_images(*f, lanes + kLaneBlock * p, data + kImageBlock * uint32_t(at));
        }
        return data + kImageBlock * uint32_t(at);
    }
};

inline double sq(double x) { return x * x; }

// Squared distance of lane l of the centre at field k of block x to lane m
// of that at field j of block y.
inline double lane_dist2(const double *x, int k, int l, const double *y, int j, int m) {
    return (sq(x[2 * k + l] - y[2 * j + m]) + sq(x[2 * k + 2 + l] - y[2 * j + 2 + m])) +
           sq(x[2 * k + 4 + l] - y[2 * j + 4 + m]);
}

// surfaces_meet for two meshes with trees, without a margin: the node tests
// in a's mesh frame (rel_apart2), the same plane test and leaves. A node
// pair is tested before it is pushed, the two children of a descent at once
// (a's two siblings against b's node, or a's node against b's two), so the
// stack holds only pairs that passed. skip (or null): the spans of a node
// pair searched already (its subtrees hold no meeting triangles), whose
// descendant pairs are passed over.
// kWide: the four child pairs in one four-lane test (AVX2), else in two
// two-lane ones (the same bits).
template <bool kWide>
HGCD_RF_INLINE bool meet_rel(BodyView &a, BodyView &b, Images &img, NarrowScratch &s, uint32_t start_a,
                             uint32_t start_b, uint32_t *meet, uint32_t *leaves, bool start_tested,
                             const uint64_t *skip) {
    const double *lanes_a = a.lanes;
    const RelFrame &f = *img.f;
    auto block_a = [&](uint32_t n) __attribute__((always_inline)) { return lanes_a + kLaneBlock * lane_block(n); };
    std::vector<uint64_t> &stack = s.pair_stack;
    stack.clear();
    if (!start_tested && rel_apart2<false, false>(f, block_a(start_a), lane_of(start_a),
                                                  img.block(lane_block(start_b)), lane_of(start_b)) &
                             1)
        return false;
    stack.push_back((uint64_t(start_a) << 32) | start_b);
    while (!stack.empty()) {
        const uint64_t top = stack.back();
        stack.pop_back();
        const uint32_t i = uint32_t(top >> 32), j = uint32_t(top);
        const double *ba = block_a(i), *mb = img.block(lane_block(j));
        const int li = lane_of(i), lj = lane_of(j);
        if (skip && span_within(lane_link(ba, kSpanField, li), skip[0]) &&
            span_within(lane_link(mb, kImageSpan, lj), skip[1]))
            continue;  // (searched already)
        const uint64_t link_a = lane_link(ba, kLinkField, li), link_b = lane_link(mb, kImageLink, lj);
        const bool la = link_a >> 32 != 0, lb = link_b >> 32 != 0;
        // The plane test where it pays: a leaf at least twice the other
        // node's size (in a's frame), as a body deep inside a much larger
        // mesh meets that mesh's leaves (between meshes of like sizes it
        // cut 105 of 1.2M node pairs on `scanned`, for 1.5% of the time).
        const double size_a = (ba[6 + li] + ba[8 + li]) + ba[10 + li];
        const double size_b = (mb[30 + lj] + mb[32 + lj]) + mb[34 + lj];
        if (la != lb && (la ? size_a >= 2 * size_b && plane_cut(a, i, b.box(j))
                            : size_b >= 2 * size_a && plane_cut(b, j, a.box(i))))
            continue;
        if (la && lb) {
            if (leaves_meet<false>(a, i, b, j, s, meet, 0)) {
                leaves[0] = i;
                leaves[1] = j;
                return true;
            }
            continue;
        }
        // Nodes of like sizes: both descended at once, their four child
        // pairs tested in one go, the nearest pair (centres in a's frame)
        // searched first.
        if (!la && !lb && size_a <= 2 * size_b && size_b <= 2 * size_a) {
            const uint32_t c = uint32_t(link_a), e = uint32_t(link_b);
            const double *x = block_a(c), *y = img.block(lane_block(e));
            const unsigned apart = rel_apart4<kWide>(f, x, y);
            uint64_t item[4];
            double far[4];
            int n = 0;
            for (int q = 0; q < 4; ++q) {
                if (apart >> q & 1) continue;
                const double dq = lane_dist2(x, 0, q & 1, y, 0, q >> 1);
                int at = n++;
                for (; at > 0 && far[at - 1] < dq; --at) {  // farthest first on the stack
                    far[at] = far[at - 1];
                    item[at] = item[at - 1];
                }
                far[at] = dq;
                item[at] = (uint64_t(c + (q & 1)) << 32) | (e + (q >> 1));
            }
            stack.insert(stack.end(), item, item + n);
            continue;
        }
        // Else as surfaces_meet: the larger node descended, the child farther from
        // the other node first (sizes and centres in a's frame).
        if (lb || (!la && size_a >= size_b)) {
            const uint32_t c = uint32_t(link_a);
            const double *x = block_a(c);
            const bool swap = lane_dist2(x, 0, 0, mb, 0, lj) > lane_dist2(x, 0, 1, mb, 0, lj);
            const unsigned apart = rel_apart2<true, false>(f, x, 0, mb, lj);
            const uint32_t first = c + !swap, second = c + swap;
            if (!(apart >> (first - c) & 1)) stack.push_back((uint64_t(first) << 32) | j);
            if (!(apart >> (second - c) & 1)) stack.push_back((uint64_t(second) << 32) | j);
        } else {
            const uint32_t c = uint32_t(link_b);
            const double *y = img.block(lane_block(c));
            const bool swap = lane_dist2(y, 0, 0, ba, 0, li) > lane_dist2(y, 0, 1, ba, 0, li);
            const unsigned apart = rel_apart2<false, true>(f, ba, li, y, 0);
            const uint32_t first = c + !swap, second = c + swap;
            if (!(apart >> (first - c) & 1)) stack.push_back((uint64_t(i) << 32) | first);
            if (!(apart >> (second - c) & 1)) stack.push_back((uint64_t(i) << 32) | second);
        }
    }
    return false;
}

// meet_rel built for AVX2 where the CPU has it (common/cpu.hpp), else SSE2.
#if HGCD_AVX2
__attribute__((target("avx2"), noinline)) bool surfaces_meet_rel_avx2(BodyView &a, BodyView &b, Images &img,
                                                                     NarrowScratch &s, uint32_t start_a,
                                                                     uint32_t start_b, uint32_t *meet,
                                                                     uint32_t *leaves, bool start_tested,
                                                                     const uint64_t *skip) {
    return meet_rel<true>(a, b, img, s, start_a, start_b, meet, leaves, start_tested, skip);
}
#endif
__attribute__((noinline)) bool surfaces_meet_rel_base(BodyView &a, BodyView &b, Images &img, NarrowScratch &s,
                                                      uint32_t start_a, uint32_t start_b, uint32_t *meet,
                                                      uint32_t *leaves, bool start_tested,
                                                      const uint64_t *skip) {
    return meet_rel<false>(a, b, img, s, start_a, start_b, meet, leaves, start_tested, skip);
}
bool surfaces_meet_rel(BodyView &a, BodyView &b, Images &img, NarrowScratch &s, uint32_t start_a,
                       uint32_t start_b, uint32_t *meet, uint32_t *leaves, bool start_tested,
                       const uint64_t *skip) {
#if HGCD_AVX2
    if (use_avx2()) return surfaces_meet_rel_avx2(a, b, img, s, start_a, start_b, meet, leaves, start_tested, skip);
#endif
    return surfaces_meet_rel_base(a, b, img, s, start_a, start_b, meet, leaves, start_tested, skip);
}

// The roots' pair apart in a's frame (the first test of a pair), built as
// meet_rel is.
HGCD_RF_INLINE bool roots_apart_in(const RelFrame &f, const double *lanes_a, Images &img) {
    return rel_apart2<false, false>(f, lanes_a, lane_of(0), img.block(0), lane_of(0)) & 1;
}
#if HGCD_AVX2
__attribute__((target("avx2"), noinline)) bool roots_apart_avx2(const RelFrame &f, const double *lanes_a,
                                                               Images &img) {
    return roots_apart_in(f, lanes_a, img);
}
#endif
bool roots_apart(const RelFrame &f, const double *lanes_a, Images &img) {
#if HGCD_AVX2
    if (use_avx2()) return roots_apart_avx2(f, lanes_a, img);
#endif
    return roots_apart_in(f, lanes_a, img);
}

// Is inner's mesh point v (its rounded world vertex) certainly outside
// outer's root boxes? f: outer's frame, with inner as its other side
// (prepare_frame(outer, inner)). The vertex as a node of its own (centre v,
// halves 0, axes the identity: every point of it is exactly c + sum_i b_i
// u_i with |b_i| <= 0, as NodeObb asks), whose image node_images bounds
// like any node's; the root pair's test then proves that point and a's
// root apart, and a's solid lies in the convex hull of its surface, inside
// that root's certified boxes.
bool vertex_outside(const RelFrame &f, const BodyView &outer, const double *v) {
    double in[kLaneBlock] = {};
    for (int k = 0; k < 3; ++k) {
        in[2 * (6 + k)] = in[2 * (6 + k) + 1] = v[k];
        in[2 * (9 + 4 * k)] = in[2 * (9 + 4 * k) + 1] = 1;  // u_k = e_k (field 9 + 3k + k)
    }
    double image[kImageBlock];
    node_images(f, in, image);
    return rel_apart2<false, false>(f, outer.lanes, lane_of(0), image, 0) & 1;
}

// Outer's frame with inner as its other side (prepare_frame(outer, inner)),
// made when first asked for: null when there is none (a side without a
// tree, or the frame's range refused).
struct LazyFrame {
    explicit LazyFrame(const RelFrame *given) : made(given) {}  // already made (or none)
    LazyFrame(const BodyView &o, const BodyView &i) : outer(&o), inner(&i) {}
    const BodyView *outer = nullptr, *inner = nullptr;  // null: decided
    const RelFrame *made = nullptr;
    RelFrame frame;
    const RelFrame *get() {
        if (outer && !made) {
            made = prepare_frame(*outer, *inner, frame) ? &frame : nullptr;
            outer = nullptr;
        }
        return made;
    }
};

// Is some component of `inner` inside the closed mesh `outer`? Asked once the
// surfaces are disjoint, so no tested vertex lies on outer's surface. f:
// outer's frame (both with trees), in which a vertex is first tried against
// outer's root (vertex_outside).
bool view_holds_component(BodyView &outer, BodyView &inner, NarrowScratch &s, LazyFrame &f) {
    const Mesh &mo = *outer.mesh;
    for (uint32_t v : inner.mesh->component_vertices) {
        const double *p = inner.vertex(v);
        const double *rb = outer.nodes ? outer.box(0) : outer.root_box;
        if (!point_in_box(p, rb)) continue;
        const RelFrame *frame = f.get();
        if (frame && vertex_outside(*frame, outer, inner.local + 3 * size_t(v))) continue;
        bool inside;
        if (outer.nodes) {
            inside = point_in_closed_mesh_bvh(p, outer, s.node_stack);
        } else {  // every world vertex of a small mesh is computed; parity, see holds_component
            inside = point_in_closed_mesh(p, outer.world, mo.triangles.data(), mo.triangle_count, rb, rb + 3);
        }
        if (inside) return true;
    }
    return false;
}

// v (without a tree): near_box becomes the box of the triangles whose exact
// boxes meet `other` (inverted, so meeting nothing, when there are none).
void narrow_to_near(BodyView &v, const double *other) {
    double *nb = v.near_box;
    nb[0] = nb[1] = nb[2] = INFINITY;
    nb[3] = nb[4] = nb[5] = -INFINITY;
    const Mesh &m = *v.mesh;
    for (uint32_t t = 0; t < m.triangle_count; ++t) {
        double tb[6];
        triangle_box(v.world, &m.triangles[3 * size_t(t)], tb);
        if (boxes_disjoint(tb, other)) continue;
        for (int k = 0; k < 3; ++k) {
            nb[k] = std::min(nb[k], tb[k]);
            nb[3 + k] = std::max(nb[3 + k], tb[3 + k]);
        }
    }
}

// How far above the meeting leaves a hint points (NodeHint), and how far a
// search climbs when the surfaces do not meet under it. On scene `scanned`,
// of the pairs that met at the last detect, the meeting leaf pair itself
// meets again in one of seven, the subtrees a level up in two of five,
// three levels up in seven of ten; but a miss costs little more than the
// climb's first step, and hints 1 level up, climbing 3 at a time, cost
// least (1% less than 3 and 3; 2 to 4 levels either way within 1%).
constexpr int kHintLevels = 1;
constexpr int kClimbLevels = 3;

uint32_t ancestor(const Bvh &t, uint32_t n, int levels) {
    if (t.empty()) return 0;
    for (int k = 0; k < levels; ++k) n = t.parent[n];
    return n;
}

// Node n's span (kSpanField) in its tree's lanes.
uint64_t span_of(const double *lanes, uint32_t n) {
    return lane_link(lanes + kLaneBlock * lane_block(n), kSpanField, lane_of(n));
}

}  // namespace

template <bool kMargin>
Contact collide_tree(const BodyPose &a, const BodyPose &b, NarrowScratch &s, Witness *witness, bool counted,
                     double d, NodeHint *hint) {
    // A mesh without a tree against one with: the pair is traversed in the
    // tree's frame, so the tree's side goes first (and the answers are
    // turned back).
    if (!kMargin && a.mesh->bvh.empty() && !b.mesh->bvh.empty()) {
        NodeHint turned;
        if (hint) {
            turned = *hint;
            std::swap(turned.node_a, turned.node_b);
            std::swap(turned.support_a, turned.support_b);
        }
        Witness w;
        const Contact c = collide_tree<kMargin>(b, a, s, &w, counted, d, hint ? &turned : nullptr);
        if (hint) {
            *hint = turned;
            std::swap(hint->node_a, hint->node_b);
            std::swap(hint->support_a, hint->support_b);
        }
        if (witness && c != Contact::None)
            *witness = Witness{w.tri_b, w.tri_a, c == Contact::Containment ? !w.a_holds_b : w.a_holds_b, true};
        return c;
    }
    next_epoch(s);
    const Rotation ra = rotation_of(a.orientation), rb = rotation_of(b.orientation);
    // What the last detect learnt of the pair: where the surfaces met, or an
    // axis between the hulls. The quick tests below did not tell such a pair
    // apart then, and after a tick of motion they seldom do (`scanned`, 9
    // ticks: none of 74,000 pairs that met, 4% of 96,000 pairs with an
    // axis, which the axis tells apart too): a pair that met skips them, a
    // pair with an axis tries it first.
    const bool hint_nodes = hint && hint->node_a != UINT32_MAX;
    const bool hint_axis = hint && !hint_nodes && hint->axis_given;
    if (!kMargin && !a.mesh->bvh.empty() && !hint_nodes && !hint_axis) {
        const BallSide sa{*a.mesh, ra, a.position, a.scale}, sb{*b.mesh, rb, b.position, b.scale};
        if (root_ball_apart(sa, sb) || root_ball_apart(sb, sa)) {
            s.exact_tests += counted;  // (as the roots' test below would have)
            return Contact::None;
        }
    }
    BodyView va, vb;
    prepare_side(a, ra, s.side[0], s.epoch, va);
    prepare_side(b, rb, s.side[1], s.epoch, vb);
    // a with a tree: the node tests in a's mesh frame, b's nodes (or its
    // point node, Mesh::point_node) mapped there.
    RelFrame frame;
    Images img{&frame, nullptr, nullptr, nullptr, s.epoch, 0};
    const bool rel = !kMargin && va.nodes && prepare_frame(va, vb, frame);
    if (rel) {
        NarrowScratch::Side &c = s.side[1];
        const size_t nn = vb.nodes ? b.mesh->bvh.lanes.size() / kLaneBlock : 1;
        if (c.image_slot.size() < nn) {
            c.image_slot.resize(nn, 0);
            c.images.reset(new double[kImageBlock * nn]);
        }
        img.lanes = vb.lanes;
        img.data = c.images.get();
        img.slot = c.image_slot.data();
    }
    // (skip: the spans of a node pair searched already in vain; the frame
    // path alone passes them over.)
    auto search = [&](uint32_t na, uint32_t nb, uint32_t *meet, uint32_t *leaves, bool tested = false,
                      const uint64_t *skip = nullptr) {
        return rel ? surfaces_meet_rel(va, vb, img, s, na, nb, meet, leaves, tested, skip)
                   : surfaces_meet<kMargin>(va, vb, s, na, nb, meet, leaves, d);
    };
    if (hint) hint->found = false;
    // Conservative prefilter: the solids lie inside the root boxes. (Not
    // on the frame path, whose roots' test below is tighter: the world boxes
    // hold the broad phase's, so they meet for every candidate pair.)
    if (!rel && (kMargin ? boxes_apart(va.box(0), vb.box(0), d) : boxes_disjoint(va.box(0), vb.box(0))))
        return Contact::None;
    s.exact_tests += counted;
    // Pairs apart at the last detect try the hulls, from the last detect's
    // axis when they have one (a world direction, taken to a's frame by
    // R_a^T), before the roots' test when they do. A pair that met at the
    // last detect mostly meets again: its hint is tried first, below.
    const bool hulls = rel && !hint_nodes && a.mesh->hull.size && b.mesh->hull.size;
    if (hulls && hint_axis && bodies_hulls_apart(frame, va, vb, hint)) return Contact::None;
    // The root pair apart in a's frame: so are the solids (each lies in the
    // convex hull of its surface, inside its root's certified boxes), and
    // containment need not be asked.
    const bool roots_tested = rel && !hint_nodes;
    if (roots_tested && roots_apart(frame, va.lanes, img)) return Contact::None;
    if (hulls && !hint_axis && bodies_hulls_apart(frame, va, vb, hint)) return Contact::None;
    // A side without a tree is one leaf of all its triangles: only those whose
    // exact boxes reach the other's root box can meet it, and the box of
    // those alone prunes the other's nodes (a body deep inside a large box
    // then costs no traversal at all).
    if (!kMargin && !va.nodes) narrow_to_near(va, vb.box(0));
    if (!kMargin && !vb.nodes) narrow_to_near(vb, va.box(0));
    // (None of them: the surfaces do not meet.)
    const bool none_near = !kMargin && ((!va.nodes && !(va.near_box[0] <= va.near_box[3])) ||
                                        (!vb.nodes && !(vb.near_box[0] <= vb.near_box[3])));
    uint32_t meet[2], leaves[2];
    bool met = false;
    bool whole = false;  // (the whole trees searched already)
    if (hint && !none_near) {
        // The subtrees near where the surfaces met at the last detect,
        // searched first: after a tick of motion they mostly still meet there.
        const uint32_t na = va.nodes ? uint32_t(a.mesh->bvh.nodes.size()) : 1;
        const uint32_t nb = vb.nodes ? uint32_t(b.mesh->bvh.nodes.size()) : 1;
        uint32_t up_a = hint->node_a, up_b = hint->node_b;
        if (up_a < na && up_b < nb) {
            met = search(up_a, up_b, meet, leaves);
            // A miss: mostly the meeting point moved next door, so the
            // subtrees kClimbLevels further up are searched next, and so on
            // up to the roots, each time but for the part searched already.
            while (!met && rel && (up_a | up_b) != 0) {
                const uint64_t searched[2] = {span_of(va.lanes, up_a), span_of(vb.lanes, up_b)};
                up_a = ancestor(a.mesh->bvh, up_a, kClimbLevels);
                up_b = ancestor(b.mesh->bvh, up_b, kClimbLevels);
                met = search(up_a, up_b, meet, leaves, false, searched);
            }
            whole = rel;  // (the climb ends at the roots)
        }
    }
    if (!none_near && (met || (!whole && search(0, 0, meet, leaves, roots_tested)))) {
        if (witness)
            *witness = Witness{va.mesh_triangle(meet[0]), vb.mesh_triangle(meet[1]), false, true};
        if (hint)
            *hint = NodeHint{ancestor(a.mesh->bvh, leaves[0], kHintLevels),
                             ancestor(b.mesh->bvh, leaves[1], kHintLevels), true};
        return kMargin ? Contact::Near : Contact::Surface;
    }
    if (kMargin) return Contact::None;  // (collide_within asked about containment first)
    LazyFrame frame_b = rel ? LazyFrame(vb, va) : LazyFrame(nullptr);  // (b holding a: vertex_outside)
    if (b.mesh->closed && view_holds_component(vb, va, s, frame_b)) {
        if (witness) *witness = Witness{UINT32_MAX, UINT32_MAX, false, true};
        return Contact::Containment;
    }
    LazyFrame frame_a(rel ? &frame : nullptr);
    if (a.mesh->closed && view_holds_component(va, vb, s, frame_a)) {
        if (witness) *witness = Witness{UINT32_MAX, UINT32_MAX, true, true};
        return Contact::Containment;
    }
    return Contact::None;
}

template Contact collide_tree<false>(const BodyPose &, const BodyPose &, NarrowScratch &, Witness *, bool, double,
                                     NodeHint *);
template Contact collide_tree<true>(const BodyPose &, const BodyPose &, NarrowScratch &, Witness *, bool, double,
                                    NodeHint *);

void prepare_query_view(const BodyPose &pose, NarrowScratch &s, BodyView &v) {
    next_epoch(s);
    prepare_side(pose, rotation_of(pose.orientation), s.side[0], s.epoch, v);
}

}  // namespace hgcd
