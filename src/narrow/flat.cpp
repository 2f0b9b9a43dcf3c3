// Contact in a flat region (flat.hpp).
//
// Why the plane decides: solid A lies in its box, so with c an end of the
// box's range along k, A lies on one side of the plane P: x_k = c. A point
// of A in P then has no ball around it inside A, so it lies on A's surface,
// on some triangle t, and t (one side of P too) meets P exactly in the hull
// of its vertices with x_k == c (none, a point, an edge or t itself). So
// A's part of P is the union of those hulls, and the same for B; the solids
// share a point only inside both boxes, that is in P, so they share one iff
// a hull of A meets a hull of B. Every hull lies in P, where dropping axis
// k loses nothing: flat_hulls_meet decides each pair with exact orient2d.
#include "common/ieee.hpp"
#include "narrow/flat.hpp"

#include <algorithm>

#include "exact/geometry.hpp"
#include "narrow/bvh.hpp"

namespace hgcd {

namespace {

// The hull of a triangle's vertices in P, and its box along the two axes
// kept (i, j) = ((k + 1) % 3, (k + 2) % 3).
struct Section {
    const double *p[3];
    int n;
    double lo[2], hi[2];
};

// The sections of mesh m (world vertices w) in x_k = c that reach the
// region's box (the others meet nothing of the other body); returns their
// count.
uint32_t sections(const Mesh &m, const double *w, int k, double c, const double *region, Section *out) {
    const int i = (k + 1) % 3, j = (k + 2) % 3;
    uint32_t count = 0;
    for (uint32_t t = 0; t < m.triangle_count; ++t) {
        Section &s = out[count];
        s.n = 0;
        for (int v = 0; v < 3; ++v) {
            const double *x = &w[3 * size_t(m.triangles[3 * size_t(t) + v])];
            if (x[k] == c) s.p[s.n++] = x;
        }
        if (!s.n) continue;
        s.lo[0] = s.hi[0] = s.p[0][i];
        s.lo[1] = s.hi[1] = s.p[0][j];
        for (int v = 1; v < s.n; ++v) {
            s.lo[0] = std::min(s.lo[0], s.p[v][i]), s.hi[0] = std::max(s.hi[0], s.p[v][i]);
            s.lo[1] = std::min(s.lo[1], s.p[v][j]), s.hi[1] = std::max(s.hi[1], s.p[v][j]);
        }
        if (s.hi[0] < region[i] || s.lo[0] > region[3 + i] || s.hi[1] < region[j] || s.lo[1] > region[3 + j])
            continue;
        ++count;
    }
    return count;
}

}  // namespace

int flat_contact(const Mesh &ma, const double *wa, const double *box_a, const Mesh &mb, const double *wb,
                 const double *box_b) {
    double region[6];
    for (int k = 0; k < 3; ++k) {
        region[k] = std::max(box_a[k], box_b[k]);
        region[3 + k] = std::min(box_a[3 + k], box_b[3 + k]);
    }
    int k = 0;
    double c = 0;
    for (; k < 3; ++k) {
        c = region[k];
        if (region[3 + k] == c && (box_a[k] == c || box_a[3 + k] == c) && (box_b[k] == c || box_b[3 + k] == c))
            break;
    }
    if (k == 3 || ma.triangle_count > kBvhMinTriangles || mb.triangle_count > kBvhMinTriangles) return -1;
    Section sa[kBvhMinTriangles], sb[kBvhMinTriangles];
    const uint32_t na = sections(ma, wa, k, c, region, sa);
    const uint32_t nb = na ? sections(mb, wb, k, c, region, sb) : 0;
    for (uint32_t x = 0; x < na; ++x)
        for (uint32_t y = 0; y < nb; ++y) {
            const Section &s = sa[x], &t = sb[y];
            if (s.hi[0] < t.lo[0] || t.hi[0] < s.lo[0] || s.hi[1] < t.lo[1] || t.hi[1] < s.lo[1]) continue;
            if (flat_hulls_meet(k, s.p, s.n, t.p, t.n)) return 1;
        }
    return 0;
}

}  // namespace hgcd
