// The triangle-triangle and segment-triangle tests: closed (touching counts),
// exact (every decision is the sign of an exact orientation predicate,
// predicates.hpp), zero-area triangles taken as the segments or points they
// are. The narrow phase runs tri_tri_intersect per triangle pair.
#include <cstdint>

#include "common/ieee.hpp"
#include "exact/geometry.hpp"
#include "exact/predicates.hpp"

namespace hgcd {

using namespace predicates;

namespace {

// Closed segments [a0,a1] and [b0,b1] (each possibly a point) meet in
// projection k.
bool seg_seg_proj(int k, const double *a0, const double *a1, const double *b0,
                  const double *b1) {
    int o1 = orient2d_proj(k, a0, a1, b0);
    int o2 = orient2d_proj(k, a0, a1, b1);
    if (o1 != 0 && o1 == o2) return false;
    int o3 = orient2d_proj(k, b0, b1, a0);
    int o4 = orient2d_proj(k, b0, b1, a1);
    if (o3 != 0 && o3 == o4) return false;
    if (o1 * o2 < 0 && o3 * o4 < 0) return true;  // proper crossing
    // Otherwise they meet iff an endpoint lies on the other segment.
    if (o1 == 0 && in_box_proj(k, a0, a1, b0)) return true;
    if (o2 == 0 && in_box_proj(k, a0, a1, b1)) return true;
    if (o3 == 0 && in_box_proj(k, b0, b1, a0)) return true;
    if (o4 == 0 && in_box_proj(k, b0, b1, a1)) return true;
    return false;
}

}  // namespace

namespace predicates {

// Segment [e0, e1] lying in the plane of the non-degenerate triangle t.
bool coplanar_seg_tri(const double *e0, const double *e1,
                      const double *const *t) {
    int o = 0;
    int k = choose_projection(t, &o);
    if (k < 0) return false;  // unreachable for non-degenerate t
    if (point_in_tri_proj(k, e0, t, o)) return true;
    for (int i = 0; i < 3; ++i) {
        if (seg_seg_proj(k, e0, e1, t[i], t[(i + 1) % 3])) return true;
    }
    return false;
}

}  // namespace predicates

namespace {

// Segment vs non-degenerate triangle, closed, exact.
bool seg_tri_nondegenerate(const double *e0, const double *e1,
                           const double *const *t) {
    int s0 = orient3d_filtered(t[0], t[1], t[2], e0);
    int s1 = orient3d_filtered(t[0], t[1], t[2], e1);
    if (s0 != 0 && s0 == s1) return false;
    if (s0 == 0 && s1 == 0) return coplanar_seg_tri(e0, e1, t);
    // The segment meets the plane in exactly one point X (e0 != e1 here);
    // X is in the closed triangle iff the line e0e1 passes on the same side
    // (or on) each directed edge.
    bool pos = false, neg = false;
    for (int i = 0; i < 3; ++i) {
        int s = orient3d_filtered(e0, e1, t[i], t[(i + 1) % 3]);
        pos |= s > 0;
        neg |= s < 0;
        if (pos && neg) return false;
    }
    return true;
}

// Closed 3D segments (each possibly a point). Coplanar segments meet iff they
// meet in all three coordinate projections (necessary; and one projection is
// injective on the line or plane they span, which makes it sufficient).
bool seg_seg_3d(const double *a0, const double *a1, const double *b0,
                const double *b1) {
    for (int i = 0; i < 3; ++i) {
        double alo = a0[i] < a1[i] ? a0[i] : a1[i];
        double ahi = a0[i] < a1[i] ? a1[i] : a0[i];
        double blo = b0[i] < b1[i] ? b0[i] : b1[i];
        double bhi = b0[i] < b1[i] ? b1[i] : b0[i];
        if (ahi < blo || bhi < alo) return false;
    }
    if (orient3d_filtered(a0, a1, b0, b1) != 0) return false;
    for (int k = 0; k < 3; ++k) {
        if (!seg_seg_proj(k, a0, a1, b0, b1)) return false;
    }
    return true;
}

// Two coplanar non-degenerate triangles.
bool coplanar_tri_tri(const double *const *p, const double *const *q) {
    int o = 0;
    int k = choose_projection(p, &o);
    if (k < 0) return false;  // unreachable
    for (int i = 0; i < 3; ++i) {
        for (int j = 0; j < 3; ++j) {
            if (seg_seg_proj(k, p[i], p[(i + 1) % 3], q[j], q[(j + 1) % 3]))
                return true;
        }
    }
    // No boundary contact: one contains the other or they are disjoint.
    if (point_in_tri_proj(k, p[0], q, orient2d_proj(k, q[0], q[1], q[2])))
        return true;
    if (point_in_tri_proj(k, q[0], p, o)) return true;
    return false;
}

// Slow general path: coplanar triangles or at least one zero-area triangle.
// Two closed triangles meet iff an edge of one meets the other triangle; a
// zero-area triangle is the union of its edges.
HGCD_NOINLINE bool tri_tri_general(const double *const *p,
                                   const double *const *q) {
    bool dp = is_collinear(p[0], p[1], p[2]);
    bool dq = is_collinear(q[0], q[1], q[2]);
    if (!dp && !dq) return coplanar_tri_tri(p, q);
    if (dp && dq) {
        for (int i = 0; i < 3; ++i) {
            for (int j = 0; j < 3; ++j) {
                if (seg_seg_3d(p[i], p[(i + 1) % 3], q[j], q[(j + 1) % 3]))
                    return true;
            }
        }
        return false;
    }
    if (dq) {
        const double *const *t = p;
        p = q;
        q = t;
    }
    // p is degenerate, q is not.
    for (int i = 0; i < 3; ++i) {
        if (seg_tri_nondegenerate(p[i], p[(i + 1) % 3], q)) return true;
    }
    return false;
}

// For a sign pattern of a triangle's vertices against the other triangle's
// plane (not all equal and non-zero, not all zero), the "apex" vertex a and
// flip f such that f*s[a] >= 0 >= f*s[b], f*s[c] (b, c the next vertices
// in cyclic order) and the edges a-b and a-c each have an endpoint off the
// plane. Encoded as a + 3 * (f > 0); index (s0+1)*9 + (s1+1)*3 + (s2+1).
struct ApexTable {
    unsigned char v[27];
    constexpr ApexTable() : v() {
        for (int i = 0; i < 27; ++i) {
            int s[3] = {i / 9 - 1, (i / 3) % 3 - 1, i % 3 - 1};
            int np = 0, nn = 0, nz = 0, ip = 0, in = 0, iz = 0;
            for (int k = 0; k < 3; ++k) {
                if (s[k] > 0) { ++np; ip = k; }
                else if (s[k] < 0) { ++nn; in = k; }
                else { ++nz; iz = k; }
            }
            int a = 0, f = 1;
            if (np == 1 && nn + nz == 2) { a = ip; f = 1; }
            else if (nn == 1 && np + nz == 2) { a = in; f = -1; }
            else if (nz == 1 && np == 2) { a = iz; f = -1; }
            else if (nz == 1 && nn == 2) { a = iz; f = 1; }
            v[i] = (unsigned char)(a + (f > 0 ? 3 : 0));
        }
    }
};
constexpr ApexTable kApex;

inline double min2(double a, double b) { return b < a ? b : a; }
inline double max2(double a, double b) { return a < b ? b : a; }

// Boxes of the two triangles are disjoint (exact comparisons).
inline bool boxes_disjoint(const double *const *p, const double *const *q) {
    bool apart = false;
    for (int k = 0; k < 3; ++k) {
        double plo = min2(min2(p[0][k], p[1][k]), p[2][k]);
        double phi = max2(max2(p[0][k], p[1][k]), p[2][k]);
        double qlo = min2(min2(q[0][k], q[1][k]), q[2][k]);
        double qhi = max2(max2(q[0][k], q[1][k]), q[2][k]);
        apart |= (phi < qlo) | (qhi < plo);
    }
    return apart;
}

// Steps 2-3 of tri_tri_intersect, given both sign triples (neither all
// equal and non-zero).
inline bool tri_tri_finish(const double *const *p, const double *const *q,
                           const int *sp, const int *sq) {
    if ((sp[0] == 0 && sp[1] == 0 && sp[2] == 0) ||
        (sq[0] == 0 && sq[1] == 0 && sq[2] == 0)) {
        return tri_tri_general(p, q);
    }
    int ap = kApex.v[(sp[0] + 1) * 9 + (sp[1] + 1) * 3 + (sp[2] + 1)];
    int aq = kApex.v[(sq[0] + 1) * 9 + (sq[1] + 1) * 3 + (sq[2] + 1)];
    int a = ap % 3, f = ap >= 3 ? 1 : -1;
    int b = aq % 3, g = aq >= 3 ? 1 : -1;
    const double *pa = p[a], *pb = p[(a + 1) % 3], *pc = p[(a + 2) % 3];
    const double *qa = q[b], *qb = q[(b + 1) % 3], *qc = q[(b + 2) % 3];
    const double *plo = g < 0 ? pb : pc, *phi = g < 0 ? pc : pb;
    const double *qlo = f < 0 ? qc : qb, *qhi = f < 0 ? qb : qc;
    if (orient3d_filtered(pa, plo, qa, qhi) < 0) return false;
    return orient3d_filtered(pa, phi, qa, qlo) <= 0;
}

// The plane filter of a prepared triangle, its data computed on first use
// (by plane_prepare, so the same bits as the vertex version's).
inline PlaneFilter plane_of(PreparedTriangle &t) {
    PlaneFilter pf;
    if (!t.planed) {
        plane_prepare(pf, t.v[0], t.v[1], t.v[2]);
        for (int k = 0; k < 3; ++k) {
            t.n[k] = pf.n[k];
            t.an[k] = pf.an[k];
        }
        t.planed = true;
        return pf;
    }
    pf.t0 = t.v[0];
    pf.t1 = t.v[1];
    pf.t2 = t.v[2];
    for (int k = 0; k < 3; ++k) {
        pf.n[k] = t.n[k];
        pf.an[k] = t.an[k];
    }
    return pf;
}

inline bool all_same_nonzero(const int *s) {
    return (s[0] == s[1]) & (s[1] == s[2]) & (s[0] != 0);
}

}  // namespace

bool segment_triangle_intersect(const double *e0, const double *e1,
                                const double *t0, const double *t1,
                                const double *t2) {
    const double *t[3] = {t0, t1, t2};
    if (is_collinear(t0, t1, t2)) {
        for (int i = 0; i < 3; ++i) {
            if (seg_seg_3d(e0, e1, t[i], t[(i + 1) % 3])) return true;
        }
        return false;
    }
    return seg_tri_nondegenerate(e0, e1, t);
}

// Triangle-triangle test.
//
// 0. Disjoint bounding boxes: no contact (exact, cheap, rejects about half of
//    the triangle pairs of box-overlapping tetrahedra).
// 1. Plane-side rejection: if the three vertices of one triangle are strictly
//    on one side of the other's plane there is no contact.
// 2. If all vertices of one triangle lie on the other's plane, the triangles
//    are coplanar or one of them has zero area: general exact path.
// 3. Otherwise both triangles are proper and their planes cross in a line L.
//    Each triangle meets L in a segment (possibly a point): S_P = [X_ab, X_ac]
//    where a is P's apex vertex (alone on its side of Q's plane, after
//    flipping) and X_ab is where edge a-b meets Q's plane; likewise S_Q. The
//    triangles meet iff S_P and S_Q overlap. Ordering along L needs no
//    constructed points: with P's apex on the positive side of Q's plane (after
//    the flip f) and Q's apex on the positive side of P's plane (flip g),
//    sign orient3d(p_a, p_x, q_a, q_y) = sign of (Y_y - X_x) along one fixed
//    direction of L (X_x on edge a-x of P, Y_y on edge a-y of Q). [Proof: an
//    orientation-preserving affine map sends P's plane to z=0, Q's to y=0,
//    with the apex sides to y>0 and z>0; writing p_a = X + l u,
//    p_x = X - m u (u = (u1, u2, 0), u2 > 0), q_a = Y + r w, q_y = Y - s w
//    (w = (w1, 0, w3), w3 > 0), the determinant expands to
//    (l+m)(r+s) u2 w3 (Y_1 - X_1).] In those coordinates, the order of the
//    two crossing points of each triangle follows from its orientation:
//    X_ab <= X_ac iff g = -1, and Y_ab >= Y_ac iff f = -1. With (lo, hi) the
//    endpoints so ordered, the segments overlap iff X_lo <= Y_hi and
//    Y_lo <= X_hi: two more orientation tests (the Guigue-Devillers idea).
bool flat_hulls_meet(int k, const double *const *a, int na, const double *const *b, int nb) {
    // Closed convex sets in a plane meet iff their boundaries do or one holds
    // a point of the other; a point or a segment is its own boundary.
    const int ea = na == 1 ? 1 : na == 2 ? 1 : 3, eb = nb == 1 ? 1 : nb == 2 ? 1 : 3;
    for (int i = 0; i < ea; ++i)
        for (int j = 0; j < eb; ++j)
            if (seg_seg_proj(k, a[i], a[(i + 1) % na], b[j], b[(j + 1) % nb])) return true;
    if (na == 3) {
        const int o = orient2d_proj(k, a[0], a[1], a[2]);
        if (o != 0 && point_in_tri_proj(k, b[0], a, o)) return true;
    }
    if (nb == 3) {
        const int o = orient2d_proj(k, b[0], b[1], b[2]);
        if (o != 0 && point_in_tri_proj(k, a[0], b, o)) return true;
    }
    return false;
}

bool tri_tri_intersect(const double *p0, const double *p1, const double *p2,
                       const double *q0, const double *q1, const double *q2) {
    const double *p[3] = {p0, p1, p2};
    const double *q[3] = {q0, q1, q2};
    if (boxes_disjoint(p, q)) return false;

    PlaneFilter pq;
    plane_prepare(pq, q0, q1, q2);
    int sp[3];
    plane_sides3(pq, p0, p1, p2, sp);
    if (all_same_nonzero(sp)) return false;
    // P in Q's plane (or Q of zero area): coplanar or degenerate, and the
    // signs of Q against P's plane are not needed.
    if ((sp[0] == 0) & (sp[1] == 0) & (sp[2] == 0)) return tri_tri_general(p, q);

    PlaneFilter pp;
    plane_prepare(pp, p0, p1, p2);
    int sq[3];
    plane_sides3(pp, q0, q1, q2, sq);
    if (all_same_nonzero(sq)) return false;

    return tri_tri_finish(p, q, sp, sq);
}

bool tri_tri_intersect_signed(const double *const *p, const double *const *q,
                              const int *sp, const int *sq) {
    if (all_same_nonzero(sp) || all_same_nonzero(sq)) return false;
    return tri_tri_finish(p, q, sp, sq);
}

bool tri_tri_intersect(PreparedTriangle &p, PreparedTriangle &q) {
    // (The steps of tri_tri_intersect on the vertices after its box filter,
    // which the callers run on the prepared boxes; each plane's filter data
    // computed once.)
    int sp[3];
    plane_sides3(plane_of(q), p.v[0], p.v[1], p.v[2], sp);
    if (all_same_nonzero(sp)) return false;
    if ((sp[0] == 0) & (sp[1] == 0) & (sp[2] == 0)) return tri_tri_general(p.v, q.v);
    int sq[3];
    plane_sides3(plane_of(p), q.v[0], q.v[1], q.v[2], sq);
    if (all_same_nonzero(sq)) return false;
    return tri_tri_finish(p.v, q.v, sp, sq);
}

}  // namespace hgcd
