// The tetrahedron path's batch for CPUs with AVX2 (collide_tetra_batch_avx2):
// many pairs at a time, one per lane, with the one-pair test's verdicts.
#include "common/ieee.hpp"
#include "narrow/tetra.hpp"
#include "narrow/tetra_avx2.hpp"

#if HGCD_AVX2

namespace hgcd {
namespace tet {

#pragma GCC push_options
#pragma GCC target("avx2")

namespace {

// Many pairs at a time, one per lane (collide_tetra_batch). Pairs are first
// filtered by the axis along the line of centres, four at a time, each lane
// in the one-pair test's operations (tet_axis_separates), so with the same
// bits. The survivors, eight at a time in two groups of four, get both
// bodies' world vertices and boxes (FourLaneKernels's world, the same bits), then
// the signs of each body's vertices against the other's faces, certified in
// float (sides8, with a bound of its own), all branch-free (on scene tetra
// 41% of the pairs that reach the faces need both bodies' faces in the
// one-pair test, so a group nearly always needs them). Certified decisions
// cannot disagree, whatever filter certified them. A lane left open (no face
// separates, no vertex is surely inside) takes the one-pair test's edge axis
// (the same bits) and exact path, which makes every sign exact first; a lane
// whose own tetrahedron's orientation is not certified (flat or nearly), or
// whose box is nearly flat, the whole one-pair test. So the verdicts and the
// work counted (exact tests, triangle tests) are the one-pair test's.
struct Side4 {
    f64x4 c[3];     // position
    f64x4 m[9];     // rotation
    f64x4 l[3][4];  // scaled local vertices, l[axis][vertex]
    f64x4 reach;    // scale * tetra_reach
};


// The bodies of one side of four pairs. A Placement is read as two 32-byte
// halves: (x y z qx) and (qy qz qw scale); the shapes from their records
// (write_record).
static inline void load_side(const Placement *const *p, const double *const *shape, Side4 &s) {
    f64x4 r[4], h[4];
    for (int k = 0; k < 4; ++k) {  // (memcpy here goes through the stack: a store forwarding stall)
        const double *half = reinterpret_cast<const double *>(p[k]);
        r[k] = (f64x4)_mm256_loadu_pd(half);
        h[k] = (f64x4)_mm256_loadu_pd(half + 4);
    }
    transpose4(r[0], r[1], r[2], r[3]);
    transpose4(h[0], h[1], h[2], h[3]);
    s.c[0] = r[0];
    s.c[1] = r[1];
    s.c[2] = r[2];
    const f64x4 scale = h[3];
    rotation_entries(r[3], h[0], h[1], h[2], s.m);
    // The reach (Mesh::tetra_reach, the same operations: the same bits) is
    // worked out here rather than stored: a record of 96 bytes, not 128.
    const double *m0 = shape[0];
    if (shape[1] == m0 && shape[2] == m0 && shape[3] == m0) {  // (shared shapes: the usual case)
        double reach = 0;
        for (int v = 0; v < 4; ++v)
            reach = std::max(reach, (std::fabs(m0[v]) + std::fabs(m0[4 + v])) + std::fabs(m0[8 + v]));
        for (int a = 0; a < 3; ++a)
            for (int v = 0; v < 4; ++v) s.l[a][v] = scale * m0[4 * a + v];
        s.reach = scale * reach;
    } else {
        f64x4 sum[4];
        for (int a = 0; a < 3; ++a) {
            f64x4 t[4];
            for (int k = 0; k < 4; ++k) t[k] = (f64x4)_mm256_load_pd(shape[k] + 4 * a);
            transpose4(t[0], t[1], t[2], t[3]);
            for (int v = 0; v < 4; ++v) {
                s.l[a][v] = scale * t[v];
                sum[v] = a ? sum[v] + abs4(t[v]) : abs4(t[v]);
            }
        }
        s.reach = scale * max4(max4(sum[0], sum[1]), max4(sum[2], sum[3]));
    }
}

// Both sides of the pairs p[0..3].
static inline void load_pairs(const TetraPair *const *p, Side4 &A, Side4 &B) {
    const Placement *pa[4] = {p[0]->a, p[1]->a, p[2]->a, p[3]->a}, *pb[4] = {p[0]->b, p[1]->b, p[2]->b, p[3]->b};
    const double *ma[4] = {p[0]->shape_a, p[1]->shape_a, p[2]->shape_a, p[3]->shape_a};
    const double *mb[4] = {p[0]->shape_b, p[1]->shape_b, p[2]->shape_b, p[3]->shape_b};
    load_side(pa, ma, A);
    load_side(pb, mb, B);
}

// Lanes whose pair tet_axis_separates rejects (the same operations).
static inline unsigned axis_separated4(const Side4 &A, const Side4 &B) {
    const f64x4 u0 = B.c[0] - A.c[0], u1 = B.c[1] - A.c[1], u2 = B.c[2] - A.c[2];
    f64x4 ha, hb;
    {
        f64x4 da[3], db[3];
        for (int j = 0; j < 3; ++j) {
            da[j] = ((A.m[j] * u0 + A.m[3 + j] * u1) + A.m[6 + j] * u2);
            db[j] = -1.0 * ((B.m[j] * u0 + B.m[3 + j] * u1) + B.m[6 + j] * u2);
        }
        f64x4 pa[4], pb[4];
        for (int v = 0; v < 4; ++v) {
            pa[v] = (A.l[0][v] * da[0] + A.l[1][v] * da[1]) + A.l[2][v] * da[2];
            pb[v] = (B.l[0][v] * db[0] + B.l[1][v] * db[1]) + B.l[2][v] * db[2];
        }
        ha = max4(max4(pa[0], pa[1]), max4(pa[2], pa[3]));
        hb = max4(max4(pb[0], pb[1]), max4(pb[2], pb[3]));
    }
    const f64x4 uu = (u0 * u0 + u1 * u1) + u2 * u2;
    const f64x4 gap = uu - (ha + hb);
    const f64x4 reach = 2.0 * (A.reach + B.reach);
    const f64x4 cu = ((abs4(A.c[0]) + abs4(B.c[0]) + reach) * abs4(u0) + (abs4(A.c[1]) + abs4(B.c[1]) + reach) * abs4(u1)) +
                  (abs4(A.c[2]) + abs4(B.c[2]) + reach) * abs4(u2);
    const f64x4 margin = kCentresMargin * (uu + cu) + kUnderflowFloor;
    return lanes_of((gap > 0.0) & (gap > margin));
}

// World vertices w[axis][vertex] and box of one side (FourLaneKernels::world).
static inline void world4(const Side4 &s, f64x4 (*w)[4], f64x4 *lo, f64x4 *hi) {
    for (int a = 0; a < 3; ++a) {
        for (int v = 0; v < 4; ++v)
            w[a][v] = s.c[a] + ((s.m[3 * a] * s.l[0][v] + s.m[3 * a + 1] * s.l[1][v]) + s.m[3 * a + 2] * s.l[2][v]);
        lo[a] = min4(min4(w[a][0], w[a][1]), min4(w[a][2], w[a][3]));
        hi[a] = max4(max4(w[a][0], w[a][1]), max4(w[a][2], w[a][3]));
    }
}

// The face planes' signs in float, eight pairs at a time (two groups of
// four), on vertices that are the double world vertices less the low corner
// of the box holding both bodies, scaled by a power of two s that brings the
// box's largest extent below 1, rounded to float (eight lanes a vector,
// where double has four). Why a sign is
// then certain when |d| > bound = 2^-15 P, P = ex ey ez of the scaled
// extents (each at most 1):
//  - let U be the world vertices less the corner, scaled, in exact
//    arithmetic: orient3d's sign on them is the sign on the world vertices
//    (a translation, and a positive scaling);
//  - the float vertices u differ from U by at most (2^-24 + 2^-52) e_k per
//    axis k (e_k the scaled extent), plus 2^-149 below float's normal range:
//    the double subtraction of the corner rounds by at most 2^-53 e_k, the
//    power-of-two scaling is exact, the conversion to float rounds by at
//    most 2^-24 of the value; a difference of two vertices by twice that.
//    orient3d is a sum of six products of three differences, one per axis,
//    each difference at most e_k (both points in the box), so moving every
//    difference so changes it by at most 3 * 6 * 2^-23 P = 36 * 2^-24 P (to
//    first order; the rest is below 2^-40 P);
//  - evaluated in float the same way as the double filters (exact/predicates.hpp's
//    plane_sides3), the computed value is within (7 + 56 eps) eps of the
//    permanent, eps = 2^-24, and the permanent is at most 6 P (1 + 2^-21):
//    42.01 * 2^-24 P;
//  - together below 79 * 2^-24 P < 2^-17.6 P, which 2^-15 P exceeds more
//    than five times over, past its own rounding to float and past the
//    absolute errors below float's normal range (2^-140 in all), as long as
//    P >= 2^-115: a pair whose P is smaller (a box nearly flat, or both
//    bodies nearly one point) takes the whole one-pair test (double).
// The eight lanes' signs are certified signs as the double ones are; only
// a few more stay open (then made exact on the exact path).

// The certified signs of o's vertices against the faces of w (lanes of
// tet_face, as bit sets: bit v of pos[f] / neg[f] per lane) and the sign of
// w's own orientation: inner_pos / inner_neg lanes (neither: uncertain).
struct Sides8 {
    i32x8 pos[4], neg[4];
    unsigned inner_pos, inner_neg;
};
static inline void sides8(f32x8 (*w)[4], f32x8 (*o)[4], const f32x8 &bound, Sides8 &s) {
    i32x8 own_pos = i32x8{}, own_neg = i32x8{};
    const f32x8 minus = -bound;
    for (int f = 0; f < 4; ++f) {
        const int i0 = kFace[f][0], i1 = kFace[f][1], i2 = kFace[f][2];
        const f32x8 t0x = w[0][i0], t0y = w[1][i0], t0z = w[2][i0];
        const f32x8 e1x = w[0][i1] - t0x, e1y = w[1][i1] - t0y, e1z = w[2][i1] - t0z;
        const f32x8 e2x = w[0][i2] - t0x, e2y = w[1][i2] - t0y, e2z = w[2][i2] - t0z;
        const f32x8 a = e1y * e2z, b = e1z * e2y, c = e1z * e2x, d = e1x * e2z, e = e1x * e2y, g = e1y * e2x;
        const f32x8 nx = a - b, ny = c - d, nz = e - g;
        const f32x8 own = ((w[0][f] - t0x) * nx + (w[1][f] - t0y) * ny) + (w[2][f] - t0z) * nz;  // -orient3d
        own_pos |= own < minus;
        own_neg |= bound < own;
        i32x8 pos = i32x8{}, neg = i32x8{};
        for (int v = 0; v < 4; ++v) {
            const f32x8 dd = ((o[0][v] - t0x) * nx + (o[1][v] - t0y) * ny) + (o[2][v] - t0z) * nz;
            pos |= (dd < minus) & int32_t(1 << v);
            neg |= (bound < dd) & int32_t(1 << v);
        }
        s.pos[f] = pos;
        s.neg[f] = neg;
    }
    s.inner_pos = lanes_of(own_pos);
    s.inner_neg = lanes_of(own_neg) & ~s.inner_pos;
}
// From the signs (tet_verdict and TetOuter for a certain inner sign): lanes
// surely apart, surely Containment, surely Surface.
static inline void decide8(const Sides8 &s, unsigned &apart, unsigned &contained, unsigned &surface) {
    const i32x8 all = i32x8{} + 0xF;
    const i32x8 positive = ((i32x8{} + int32_t(s.inner_pos)) & i32x8{1, 2, 4, 8, 16, 32, 64, 128}) != 0;
    i32x8 sep = i32x8{}, inside = all, any_out = i32x8{};
    for (int f = 0; f < 4; ++f) {
        const i32x8 out = (positive & s.neg[f]) | (~positive & s.pos[f]);
        const i32x8 in = (positive & s.pos[f]) | (~positive & s.neg[f]);
        sep |= out == all;
        inside &= in;
        any_out |= out;
    }
    apart = lanes_of(sep);
    contained = lanes_of(inside == all);
    surface = lanes_of((inside != 0) & (any_out != 0));
}
// A vertex and its squared distance to the other body's position, per lane.
struct Near4 {
    f64x4 d, x, y, z;
};
static inline Near4 pick_near4(const i64x4 &take_b, const Near4 &a, const Near4 &b) {
    return Near4{pick4(take_b, a.d, b.d), pick4(take_b, a.x, b.x), pick4(take_b, a.y, b.y), pick4(take_b, a.z, b.z)};
}
// The two vertices of w nearest c (nearest in first), per lane.
static inline void nearest4(f64x4 (*w)[4], const f64x4 *c, Near4 &first, Near4 &second) {
    Near4 p[4];
    for (int v = 0; v < 4; ++v) {
        const f64x4 dx = w[0][v] - c[0], dy = w[1][v] - c[1], dz = w[2][v] - c[2];
        p[v] = Near4{(dx * dx + dy * dy) + dz * dz, w[0][v], w[1][v], w[2][v]};
    }
    const i64x4 s01 = p[1].d < p[0].d, s23 = p[3].d < p[2].d;
    const Near4 l1 = pick_near4(s01, p[0], p[1]), h1 = pick_near4(s01, p[1], p[0]);
    const Near4 l2 = pick_near4(s23, p[2], p[3]), h2 = pick_near4(s23, p[3], p[2]);
    const i64x4 m = l2.d < l1.d;
    first = pick_near4(m, l1, l2);
    const Near4 a = pick_near4(m, h1, l1), b = pick_near4(m, l2, h2);  // the second is the nearer of these
    second = pick_near4(b.d < a.d, a, b);
}
// Lanes whose pair an axis across an edge of each body proves apart: the
// axis of tet_edges_separate (EdgeAxis: the edge joining the two vertices of
// each body nearest the other's position), its origin the vertex of u (b
// where b_is_u, else a) that the one-pair test takes, so the same bits.
static inline unsigned edges_apart4(f64x4 (*wa)[4], f64x4 (*wb)[4], const f64x4 *ca, const f64x4 *cb, const i64x4 &b_is_u,
                                    const f64x4 &ex, const f64x4 &ey, const f64x4 &ez) {
    Near4 a0, a1, b0, b1;
    nearest4(wa, cb, a0, a1);
    nearest4(wb, ca, b0, b1);
    const f64x4 ax = a1.x - a0.x, ay = a1.y - a0.y, az = a1.z - a0.z;
    const f64x4 bx = b1.x - b0.x, by = b1.y - b0.y, bz = b1.z - b0.z;
    // (u x v is exactly -(v x u): the lanes with b as u only flip the
    // projections' signs, which the test below does not see.)
    const f64x4 nx = ay * bz - az * by, ny = az * bx - ax * bz, nz = ax * by - ay * bx;
    const f64x4 cx = pick4(b_is_u, a0.x, b0.x), cy = pick4(b_is_u, a0.y, b0.y), cz = pick4(b_is_u, a0.z, b0.z);
    f64x4 pa[4], pb[4];
    for (int v = 0; v < 4; ++v) {
        pa[v] = ((wa[0][v] - cx) * nx + (wa[1][v] - cy) * ny) + (wa[2][v] - cz) * nz;
        pb[v] = ((wb[0][v] - cx) * nx + (wb[1][v] - cy) * ny) + (wb[2][v] - cz) * nz;
    }
    const f64x4 amin = min4(min4(pa[0], pa[1]), min4(pa[2], pa[3])), amax = max4(max4(pa[0], pa[1]), max4(pa[2], pa[3]));
    const f64x4 bmin = min4(min4(pb[0], pb[1]), min4(pb[2], pb[3])), bmax = max4(max4(pb[0], pb[1]), max4(pb[2], pb[3]));
    const f64x4 margin = kEdgeMargin * ((ex * abs4(nx) + ey * abs4(ny)) + ez * abs4(nz)) + kUnderflowFloor;
    return lanes_of((bmin - amax > margin) | (amin - bmax > margin));
}

// Lane k of four-lane world vertices as rows (x, y, z), and of signs as TetSides.
inline void lane_vertices(f64x4 (*w)[4], int k, double (*out)[3]) {
    for (int v = 0; v < 4; ++v)
        for (int a = 0; a < 3; ++a) out[v][a] = w[a][v][k];
}
inline void lane_sides(const Sides8 &s, int k, TetSides &t) {
    for (int f = 0; f < 4; ++f) {
        t.pos[f] = unsigned(s.pos[f][k]);
        t.neg[f] = unsigned(s.neg[f][k]);
    }
    t.inner = (s.inner_pos >> k & 1) ? 1 : -1;
}

// A lane the face planes leave open, waiting for the edge axis (four of them
// at a time, gathered from all groups: tested group by group, a group with
// one open lane cost a whole four-lane test) and then the exact path.
struct OpenLane {
    double va[4][3], vb[4][3];  // world vertices
    double ca[3], cb[3];        // positions
    double ex, ey, ez;          // extents of the box holding both
    TetSides s_ab, s_ba;        // certified signs (oriented lanes)
    uint32_t pair;
    bool b_is_u, oriented;
};
struct OpenLanes {
    static constexpr int kMax = 64;
    OpenLane lane[kMax];
    int count = 0;
};

// Up to eight pairs (idx[0, count) of pairs; count >= 1) past the axis
// test, whose out[] the axis stage has set to None: writes the verdict of
// every pair the face planes decide, and hands the others to `waiting`.
// World vertices and boxes in double, four pairs a group; the face planes'
// signs in float, both groups at once (sides8).
__attribute__((target("avx2"))) void collide_tetra8(const TetraPair *pairs, const uint32_t *idx, int count,
                                                   Contact *out, NarrowScratch &scratch, OpenLanes &waiting) {
    const unsigned valid = (1u << count) - 1;
    Side4 A[2], B[2];
    f64x4 wa[2][3][4], wb[2][3][4], ex[2], ey[2], ez[2];
    f64x4 lo_a[2][3], hi_a[2][3], lo_b[2][3], hi_b[2][3];
    unsigned boxed = 0, tiny = 0;
    f64x4 corner[2][3], scale[2], bound[2];
    for (int g = 0; g < 2; ++g) {
        const TetraPair *group[4];
        for (int k = 0; k < 4; ++k) group[k] = &pairs[idx[4 * g + k < count ? 4 * g + k : 0]];
        load_pairs(group, A[g], B[g]);
        world4(A[g], wa[g], lo_a[g], hi_a[g]);
        world4(B[g], wb[g], lo_b[g], hi_b[g]);
        // The exact vertex boxes (the one-pair test's prefilter).
        boxed |= (~lanes_of((hi_a[g][0] < lo_b[g][0]) | (hi_b[g][0] < lo_a[g][0]) | (hi_a[g][1] < lo_b[g][1]) |
                            (hi_b[g][1] < lo_a[g][1]) | (hi_a[g][2] < lo_b[g][2]) | (hi_b[g][2] < lo_a[g][2])) & 0xF)
                 << (4 * g);
        for (int a = 0; a < 3; ++a) corner[g][a] = min4(lo_a[g][a], lo_b[g][a]);
        ex[g] = max4(hi_a[g][0], hi_b[g][0]) - corner[g][0];
        ey[g] = max4(hi_a[g][1], hi_b[g][1]) - corner[g][1];
        ez[g] = max4(hi_a[g][2], hi_b[g][2]) - corner[g][2];
        // s = 2^-(E's exponent + 1), E the largest extent: E s < 1.
        const i64x4 field = i64x4{} + (int64_t(0x7FF) << 52);
        const f64x4 largest = max4(ex[g], max4(ey[g], ez[g]));
        scale[g] = (f64x4)((i64x4{} + (int64_t(2045) << 52)) - ((i64x4)largest & field));
        // P of the float bound (the argument above Sides8), and the lanes too flat for it.
        const f64x4 volume = ((ex[g] * scale[g]) * (ey[g] * scale[g])) * (ez[g] * scale[g]);
        tiny |= lanes_of(volume < 0x1p-115) << (4 * g);
        bound[g] = 0x1p-15 * volume;
    }
    boxed &= valid;
    if (!boxed) return;
    scratch.exact_tests += unsigned(__builtin_popcount(boxed));
    // Both groups' floats joined in registers (halves stored to memory and
    // read back whole would wait on store forwarding).
    f32x8 float_a[3][4], float_b[3][4];
    for (int a = 0; a < 3; ++a)
        for (int v = 0; v < 4; ++v) {
            float_a[a][v] = join8((wa[0][a][v] - corner[0][a]) * scale[0], (wa[1][a][v] - corner[1][a]) * scale[1]);
            float_b[a][v] = join8((wb[0][a][v] - corner[0][a]) * scale[0], (wb[1][a][v] - corner[1][a]) * scale[1]);
        }
    const f32x8 bound8 = join8(bound[0], bound[1]);
    Sides8 sab, sba;  // b's vertices against a's faces, and a's against b's
    sides8(float_a, float_b, bound8, sab);
    sides8(float_b, float_a, bound8, sba);
    unsigned apart_a, in_a, surf_a, apart_b, in_b, surf_b;
    decide8(sab, apart_a, in_a, surf_a);
    decide8(sba, apart_b, in_b, surf_b);
    const unsigned oriented = (sab.inner_pos | sab.inner_neg) & (sba.inner_pos | sba.inner_neg) & ~tiny;
    const unsigned apart = (apart_a | apart_b) & oriented & boxed;
    const unsigned contained = (in_a | in_b) & oriented & boxed & ~apart;
    const unsigned surface = (surf_a | surf_b) & oriented & boxed & ~apart & ~contained;
    unsigned open = boxed & ~apart & ~contained & ~surface;
    // Every lane's certified verdict, None where there is none yet (open
    // lanes are written again below): no branch on the verdicts, which are
    // random.
    // (Indexed by the lane's contained bit | its surface bit << 1.)
    static constexpr Contact kVerdict[4] = {Contact::None, Contact::Containment, Contact::Surface,
                                            Contact::Containment};
    for (int k = 0; k < count; ++k) out[idx[k]] = kVerdict[(contained >> k & 1) | (surface >> k & 1) << 1];
    for (int g = 0; g < 2; ++g) {
        unsigned left = open >> (4 * g) & 0xF;
        if (!left) continue;
        // The one-pair test's u: the body of the larger box (the same sums).
        f64x4 size_a, size_b;
        tet_box_size(size_a, lo_a[g], hi_a[g]);
        tet_box_size(size_b, lo_b[g], hi_b[g]);
        const i64x4 b_is_u = size_b > size_a;
        while (left) {
            const int k = __builtin_ctz(left);
            left &= left - 1;
            const int lane = 4 * g + k;
            OpenLane &o = waiting.lane[waiting.count++];
            lane_vertices(wa[g], k, o.va);
            lane_vertices(wb[g], k, o.vb);
            for (int a = 0; a < 3; ++a) {
                o.ca[a] = A[g].c[a][k];
                o.cb[a] = B[g].c[a][k];
            }
            o.ex = ex[g][k];
            o.ey = ey[g][k];
            o.ez = ez[g][k];
            o.pair = idx[lane];
            o.b_is_u = b_is_u[k] != 0;
            o.oriented = (oriented >> lane & 1) != 0;
            if (o.oriented) {
                lane_sides(sab, lane, o.s_ab);
                lane_sides(sba, lane, o.s_ba);
            }
        }
    }
}

// The edge axis for the waiting lanes, four at a time (edges_apart4 on
// each lane's own values: the same bits), then the one-pair test's exact
// path for those it leaves, in its order (which face pairs it tries
// first); a lane whose tetrahedron's orientation or box is not certified
// takes the whole one-pair test.
__attribute__((target("avx2"))) void settle_open(const TetraPair *pairs, Contact *out, NarrowScratch &scratch,
                                                OpenLanes &waiting) {
    for (int first = 0; first < waiting.count; first += 4) {
        const OpenLane *l[4];
        for (int k = 0; k < 4; ++k) l[k] = &waiting.lane[first + k < waiting.count ? first + k : first];
        f64x4 wa[3][4], wb[3][4], ca[3], cb[3];
        for (int a = 0; a < 3; ++a) {
            for (int v = 0; v < 4; ++v) {
                wa[a][v] = f64x4{l[0]->va[v][a], l[1]->va[v][a], l[2]->va[v][a], l[3]->va[v][a]};
                wb[a][v] = f64x4{l[0]->vb[v][a], l[1]->vb[v][a], l[2]->vb[v][a], l[3]->vb[v][a]};
            }
            ca[a] = f64x4{l[0]->ca[a], l[1]->ca[a], l[2]->ca[a], l[3]->ca[a]};
            cb[a] = f64x4{l[0]->cb[a], l[1]->cb[a], l[2]->cb[a], l[3]->cb[a]};
        }
        const i64x4 b_is_u = i64x4{} - i64x4{l[0]->b_is_u, l[1]->b_is_u, l[2]->b_is_u, l[3]->b_is_u};
        const f64x4 ex = f64x4{l[0]->ex, l[1]->ex, l[2]->ex, l[3]->ex}, ey = f64x4{l[0]->ey, l[1]->ey, l[2]->ey, l[3]->ey},
                 ez = f64x4{l[0]->ez, l[1]->ez, l[2]->ez, l[3]->ez};
        const unsigned apart = edges_apart4(wa, wb, ca, cb, b_is_u, ex, ey, ez);
        const int n = std::min(4, waiting.count - first);
        for (int k = 0; k < n; ++k) {
            if (apart >> k & 1) continue;  // (out: None already)
            OpenLane &o = waiting.lane[first + k];
            if (!o.oriented) {  // a tetrahedron flat or nearly, or a tiny box: the whole one-pair test
                const TetraPair &p = pairs[o.pair];
                --scratch.exact_tests;  // (counted again there)
                out[o.pair] = collide_tetra_avx2(pose_of(p.mesh_a, *p.a), pose_of(p.mesh_b, *p.b), scratch);
                continue;
            }
            out[o.pair] = o.b_is_u ? tet_exact_rows(o.vb, o.va, o.s_ba, o.s_ab, scratch)
                                   : tet_exact_rows(o.va, o.vb, o.s_ab, o.s_ba, scratch);
        }
    }
    waiting.count = 0;
}

}  // namespace

__attribute__((target("avx2"))) void collide_tetra_batch_avx2(const TetraPair *pairs, size_t n, Contact *out,
                                                             NarrowScratch &scratch) {
    constexpr size_t kStage = 256;  // pairs per round of the two stages
    uint32_t left[kStage];
    OpenLanes waiting;
    for (size_t begin = 0; begin < n; begin += kStage) {
        const size_t end = std::min(n, begin + kStage);
        size_t kept = 0;
        for (size_t k = begin; k < end; k += 4) {
            if (k + 20 <= n)  // (the placements four groups ahead: see world/detect.cpp)
                for (size_t l = 0; l < 4; ++l) {
                    const TetraPair &ahead = pairs[k + 16 + l];
                    __builtin_prefetch(ahead.a);
                    __builtin_prefetch(ahead.b);
                    // and the shapes' records (one per body where bodies
                    // have meshes of their own: world/mesh_pool.hpp)
                    __builtin_prefetch(ahead.shape_a);
                    __builtin_prefetch(ahead.shape_a + 11);
                    __builtin_prefetch(ahead.shape_b);
                    __builtin_prefetch(ahead.shape_b + 11);
                }
            const TetraPair *group[4];
            for (size_t l = 0; l < 4; ++l) group[l] = &pairs[k + l < end ? k + l : k];
            Side4 A, B;
            load_pairs(group, A, B);
            const unsigned apart = axis_separated4(A, B);
            for (size_t l = 0; l < 4 && k + l < end; ++l) {
                out[k + l] = Contact::None;
                left[kept] = uint32_t(k + l);
                kept += ~apart >> l & 1;
            }
        }
        for (size_t g = 0; g < kept; g += 8) {
            collide_tetra8(pairs, left + g, int(std::min<size_t>(8, kept - g)), out, scratch, waiting);
            if (waiting.count > OpenLanes::kMax - 8) settle_open(pairs, out, scratch, waiting);
        }
        settle_open(pairs, out, scratch, waiting);
    }
}

#pragma GCC pop_options

}  // namespace tet
}  // namespace hgcd

#endif  // HGCD_AVX2
