// Two bodies' hulls apart, in a's mesh frame (rel_frame.hpp): GJK proposes
// an axis (the supports over the hull vertices, b's in b's own frame, only
// the support point mapped to a's), and the axis is then certified over
// every hull vertex.
//
// The certificate. Let z be the axis, L_a, L_b the roots' reaches (every mesh point within them, max
// norm), tmax = |t~|, qmax = max |Q~_ij|. a's rounded world vertices map
// under Phi within mu_a of their mesh points p (max norm), so each projects
// on z above z . p - |z|_1 mu_a, and the computed fl(z . p) is within g_3
// |z|_1 L_a of z . p (g_3 < 4e-16). b's map within mu_b of F(q) = t~ + Q~ q,
// and z . F(q) = z . t~ + w . q exactly, w = Q~^T z; the computed w~ is
// within g_3 qmax |z|_1 of w in each component (so (w - w~) . q within that
// times |q|_1 <= 3 L_b), fl(w~ . q) within g_3 |w~|_1 L_b of w~ . q, fl(z .
// t~) within g_3 |z|_1 tmax of z . t~. The gap (lo_a - zt) - hb, two
// roundings, is within 4e-16 (|lo_a| + |zt| + |hb|) of its value. Products
// that underflow lose 2^-1074 each, below the 1e-300. When the gap exceeds
// the sum of these (times 1 + 1e-12 for the rounding of the sum), every
// rounded vertex of a lies strictly beyond every one of b on z: their hulls,
// which hold the solids, are apart.
#include "common/ieee.hpp"
#include <algorithm>
#include <cmath>

#include "narrow/gjk.hpp"
#include "narrow/hull.hpp"
#include "narrow/narrow.hpp"
#include "narrow/rel_frame.hpp"

namespace hgcd {

namespace {

// w = Q~^T z: a direction of a's frame in b's.
inline void to_b(const double *q, const double *z, double *w) {
    for (int j = 0; j < 3; ++j) w[j] = (q[j] * z[0] + q[3 + j] * z[1]) + q[6 + j] * z[2];
}

// Is every vertex of a certainly beyond every vertex of b along v? lo_a:
// the least fl(v . p) over a's hull, hb: the largest fl(w~ . q) over b's,
// w~ = fl(Q~^T v).
bool certify(const RelFrame &f, const double *v, double lo_a, double hb) {
    double w[3];
    to_b(f.q, v, w);
    const double zt = (v[0] * f.t[0] + v[1] * f.t[1]) + v[2] * f.t[2];
    const double tmax = f.tmax, qmax = f.qmax, la = f.la, lb = f.lb;
    const double z1 = (std::fabs(v[0]) + std::fabs(v[1])) + std::fabs(v[2]);
    const double w1 = (std::fabs(w[0]) + std::fabs(w[1])) + std::fabs(w[2]);
    const double need = (z1 * ((f.mu_a + f.mu_b) + 4e-16 * ((la + tmax) + 3 * qmax * lb)) + 4e-16 * w1 * lb +
                         4e-16 * ((std::fabs(lo_a) + std::fabs(zt)) + std::fabs(hb))) *
                            (1 + 1e-12) +
                        1e-300;
    return (lo_a - zt) - hb > need;
}

}  // namespace

bool hulls_apart(const RelFrame &f, const Hull &a, const BvhNode &root_a, const Hull &b, const BvhNode &root_b,
                 const double *first, double *axis, uint32_t *near) {
    // GJK's supports: on a small hull, the first from the given supports
    // (hull_support_near) when it can tell, else a scan (either gives the
    // certificate its value); a climb on a large one (from its last
    // support).
    uint32_t at_a = UINT32_MAX, at_b = UINT32_MAX;
    uint32_t near_a = near ? near[0] : UINT32_MAX, near_b = near ? near[1] : UINT32_MAX;
    double point_b[3], lo_a = 0, hb = 0;
    // A small hull's support: from `from` the first time (then forgotten),
    // by a scan when that cannot tell.
    auto small_support = [](const Hull &h, const double *dir, uint32_t &from, double *value) {
        const uint32_t at = from != UINT32_MAX ? hull_support_near(h, dir, from, value) : UINT32_MAX;
        from = UINT32_MAX;
        return at != UINT32_MAX ? at : hull_support(h, dir, value);
    };
    auto lowest_a = [&](const double *dir, const double **point) {
        const double down[3] = {-dir[0], -dir[1], -dir[2]};
        if (a.size <= kScanHull) {
            at_a = small_support(a, down, near_a, &lo_a);
            lo_a = -lo_a;
        } else {
            at_a = hull_climb(a, down, at_a);
        }
        *point = &a.xyz[3 * size_t(at_a)];
        return at_a;
    };
    auto highest_b = [&](const double *dir, const double **point) {
        double w[3];
        to_b(f.q, dir, w);
        at_b = b.size <= kScanHull ? small_support(b, w, near_b, &hb) : hull_climb(b, w, at_b);
        const double *q = &b.xyz[3 * size_t(at_b)];
        for (int i = 0; i < 3; ++i)
            point_b[i] = f.t[i] + ((f.q[3 * i] * q[0] + f.q[3 * i + 1] * q[1]) + f.q[3 * i + 2] * q[2]);
        *point = point_b;
        return at_b;
    };
    // On Apart, v is the direction of the last supports.
    Simplex s;
    s.n = 0;
    double *v = axis;
    const double *ca = root_a.center, *cb = root_b.center;
    for (int i = 0; i < 3; ++i)
        v[i] = first ? first[i]
                     : ca[i] - (f.t[i] + ((f.q[3 * i] * cb[0] + f.q[3 * i + 1] * cb[1]) + f.q[3 * i + 2] * cb[2]));
    if (gjk_run(lowest_a, highest_b, 0, s, v) != Gjk::Apart) return false;
    if (a.size > kScanHull) {
        const double down[3] = {-v[0], -v[1], -v[2]};
        hull_support(a, down, &lo_a);
        lo_a = -lo_a;
    }
    if (b.size > kScanHull) {
        double w[3];
        to_b(f.q, v, w);
        hull_support(b, w, &hb);
    }
    if (!certify(f, v, lo_a, hb)) return false;
    if (near) {
        near[0] = at_a;
        near[1] = at_b;
    }
    return true;
}

bool bodies_hulls_apart(const RelFrame &f, const BodyView &a, const BodyView &b, NodeHint *hint) {
    double first[3], axis[3];
    const double *r = a.r.m;
    const bool given = hint && hint->axis_given;
    if (given)
        for (int i = 0; i < 3; ++i)
            first[i] = (r[i] * hint->axis[0] + r[3 + i] * hint->axis[1]) + r[6 + i] * hint->axis[2];
    uint32_t near[2] = {UINT32_MAX, UINT32_MAX};
    if (given) {
        near[0] = hint->support_a;
        near[1] = hint->support_b;
    }
    if (!hulls_apart(f, a.mesh->hull, a.nodes[0], b.mesh->hull, b.nodes[0], given ? first : nullptr, axis, near))
        return false;
    if (hint) {
        for (int k = 0; k < 3; ++k) hint->axis[k] = (r[3 * k] * axis[0] + r[3 * k + 1] * axis[1]) + r[3 * k + 2] * axis[2];
        hint->axis_found = true;
        hint->support_a = near[0];
        hint->support_b = near[1];
    }
    return true;
}

}  // namespace hgcd
