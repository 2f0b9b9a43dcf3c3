// libccd adapter: support, centre and first-direction callbacks over a body's
// world vertices, the tolerance per pair, and the calls (ccd_narrow.hpp).
//
// The plain Makefile compiles every src/*.cpp: without HGCD_HAVE_CCD this
// file is empty (the header's inline definitions for that build stand in).
#include "common/ieee.hpp"  // (every library source, this one with or without libccd)

#ifdef HGCD_HAVE_CCD

#include "narrow/ccd_narrow.hpp"
#include "narrow/boxes.hpp"

#include <ccd/ccd.h>
#include <ccd/config.h>

#include <algorithm>
#include <cmath>
#include <new>
#include <type_traits>

namespace hgcd {

// The precision libccd was configured with, as its installed config.h says,
// and libccd's mpr_tolerance and epa_tolerance for a pair relative to the sum
// of the two bodies' bounding radii (scale * mesh radius).
#if defined(CCD_DOUBLE) && !defined(CCD_SINGLE)
static_assert(std::is_same<ccd_real_t, double>::value, "CCD_DOUBLE but ccd_real_t is not double");
constexpr int kPrecision = 2;
constexpr double kRelativeTolerance = 1e-6;
#elif defined(CCD_SINGLE) && !defined(CCD_DOUBLE)
static_assert(std::is_same<ccd_real_t, float>::value, "CCD_SINGLE but ccd_real_t is not float");
constexpr int kPrecision = 1;
constexpr double kRelativeTolerance = 1e-4;
#else
#error "<ccd/config.h> defines neither (or both of) CCD_SINGLE and CCD_DOUBLE"
#endif

// GJK and MPR end in a few dozen iterations on polytopes; the cap only stops
// a cycle caused by rounding (libccd's default is unbounded).
constexpr unsigned long kMaxIterations = 1000;

int libccd_precision() { return kPrecision; }

namespace {

// A convex hull as libccd sees it: n points (3 ccd_real_t each) and a point
// inside (their mean).
struct PointHull {
    const ccd_real_t *v;
    uint32_t n;
    ccd_vec3_t center;
};

void hull_support(const void *obj, const ccd_vec3_t *dir, ccd_vec3_t *out) {
    const PointHull &h = *static_cast<const PointHull *>(obj);
    const ccd_real_t dx = dir->v[0], dy = dir->v[1], dz = dir->v[2];
    const ccd_real_t *p = h.v;
    uint32_t best = 0;
    ccd_real_t best_dot = p[0] * dx + p[1] * dy + p[2] * dz;
    for (uint32_t i = 1; i < h.n; ++i) {
        const ccd_real_t *q = p + 3 * size_t(i);
        const ccd_real_t d = q[0] * dx + q[1] * dy + q[2] * dz;
        if (d > best_dot) {
            best_dot = d;
            best = i;
        }
    }
    const ccd_real_t *q = p + 3 * size_t(best);
    out->v[0] = q[0];
    out->v[1] = q[1];
    out->v[2] = q[2];
}

void hull_center(const void *obj, ccd_vec3_t *out) { *out = static_cast<const PointHull *>(obj)->center; }

// First search direction of GJK: from a's centre towards b's, i.e. towards
// the origin from the centre of the Minkowski difference a - b.
void first_dir(const void *o1, const void *o2, ccd_vec3_t *dir) {
    const PointHull &a = *static_cast<const PointHull *>(o1), &b = *static_cast<const PointHull *>(o2);
    for (int k = 0; k < 3; ++k) dir->v[k] = b.center.v[k] - a.center.v[k];
    if (dir->v[0] == 0 && dir->v[1] == 0 && dir->v[2] == 0) dir->v[0] = 1;
}

// The hull's points as ccd_real_t: in double precision the world vertices
// themselves (the exact path's bits, origin is 0); in single precision the
// world vertices minus origin, rounded to float into buf.
template <class Real>
const Real *hull_points(const std::vector<double> &w, const double *origin, std::vector<float> &buf);
template <>
[[maybe_unused]] const double *hull_points<double>(const std::vector<double> &w, const double *,
                                                   std::vector<float> &) {
    return w.data();
}
template <>
[[maybe_unused]] const float *hull_points<float>(const std::vector<double> &w, const double *origin,
                                                 std::vector<float> &buf) {
    buf.resize(w.size());
    for (size_t i = 0; i < w.size(); ++i) buf[i] = float(w[i] - origin[i % 3]);
    return buf.data();
}

void make_hull(const std::vector<double> &w, uint32_t n, const double *origin, std::vector<float> &buf,
               PointHull &h) {
    double sum[3] = {0, 0, 0};
    for (uint32_t i = 0; i < n; ++i)
        for (int k = 0; k < 3; ++k) sum[k] += w[3 * size_t(i) + k];
    h.v = hull_points<ccd_real_t>(w, origin, buf);
    h.n = n;
    for (int k = 0; k < 3; ++k) h.center.v[k] = ccd_real_t(sum[k] / n - origin[k]);
}

}  // namespace

bool ccd_collide(const BodyPose &a, const BodyPose &b, CcdMethod method, CcdScratch &s,
                 CcdContact *contact) {
    double box_a[6], box_b[6];
    world_vertices(a, s.world_a, box_a);
    world_vertices(b, s.world_b, box_b);
    // Exact prefilter: the solids lie inside these boxes.
    if (boxes_disjoint(box_a, box_b)) return false;
    ++s.tests;

    // Single precision: coordinates relative to a point of the pair, so that
    // float keeps the shapes' detail rather than their distance from 0.
    double origin[3] = {0, 0, 0};
    if (kPrecision == 1)
        for (int k = 0; k < 3; ++k) origin[k] = 0.5 * (box_a[k] + box_a[3 + k]);
    PointHull ha, hb;
    make_hull(s.world_a, a.mesh->vertex_count, origin, s.single_a, ha);
    make_hull(s.world_b, b.mesh->vertex_count, origin, s.single_b, hb);

    ccd_t ccd;
    CCD_INIT(&ccd);
    ccd.first_dir = first_dir;
    ccd.support1 = ccd.support2 = hull_support;
    ccd.center1 = ccd.center2 = hull_center;
    ccd.max_iterations = kMaxIterations;
    const double tol = kRelativeTolerance * (a.scale * a.mesh->radius + b.scale * b.mesh->radius);
    ccd.mpr_tolerance = ccd.epa_tolerance = ccd_real_t(tol);

    const bool hit = method == CcdMethod::Gjk ? ccdGJKIntersect(&ha, &hb, &ccd) != 0
                                              : ccdMPRIntersect(&ha, &hb, &ccd) != 0;
    if (!hit || !contact) return hit;

    // The estimate, asked separately so that the answer above is the same
    // with contacts on or off (EPA can give up on a pair GJK accepted).
    ccd_real_t depth = 0;
    ccd_vec3_t dir, pos;
    dir.v[0] = dir.v[1] = dir.v[2] = 0;
    pos.v[0] = pos.v[1] = pos.v[2] = 0;
    const int r = method == CcdMethod::Gjk ? ccdGJKPenetration(&ha, &hb, &ccd, &depth, &dir, &pos)
                                           : ccdMPRPenetration(&ha, &hb, &ccd, &depth, &dir, &pos);
    if (r == -2) throw std::bad_alloc();
    *contact = CcdContact{};
    if (r == 0) {
        const double d[3] = {double(dir.v[0]), double(dir.v[1]), double(dir.v[2])};
        const double len = std::sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
        const bool have_dir = std::isfinite(len) && len > 0;
        contact->depth = std::isfinite(double(depth)) && have_dir ? std::max(0.0, double(depth)) : 0.0;
        for (int k = 0; k < 3; ++k) {
            contact->normal[k] = have_dir ? d[k] / len : 0.0;
            contact->point[k] = double(pos.v[k]) + origin[k];
        }
    }
    if (r != 0 || !std::isfinite(contact->point[0] + contact->point[1] + contact->point[2])) {
        // No estimate (hulls that only touch): the middle of the box overlap.
        for (int k = 0; k < 3; ++k)
            contact->point[k] =
                0.5 * (std::max(box_a[k], box_b[k]) + std::min(box_a[3 + k], box_b[3 + k]));
    }
    return true;
}

}  // namespace hgcd

#endif  // HGCD_HAVE_CCD
