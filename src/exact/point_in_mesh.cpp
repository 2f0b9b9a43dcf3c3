// Point in a closed mesh, exactly: the parity of a ray's crossings for any
// closed mesh, the side of every face plane for a convex one. The narrow
// phase asks it of one vertex per component when two surfaces do not cross.
#include <cstddef>
#include <cstdint>

#include "common/ieee.hpp"
#include "exact/geometry.hpp"
#include "exact/predicates.hpp"

namespace hgcd {

using namespace predicates;

namespace {

// Fixed "generic" directions (random, full-precision components; one
// component is exactly +-1 so the segment provably leaves the box).
constexpr double kDirections[32][3] = {
    {1.0, 0.0935817916500935, -0.016930054247476733},
    {0.2007225393078308, 1.0, -0.4946207010107702},
    {0.44788822782939064, -0.6906693700061936, 1.0},
    {-1.0, 0.1695679353745877, 0.2821414776144783},
    {0.77382813823161, -1.0, 0.6854467277224109},
    {-0.3644828074192151, 0.100268934525365, 1.0},
    {1.0, -0.8596645014289273, -0.6506934030106357},
    {0.7034952300920198, 1.0, 0.0008216490721728587},
    {-0.016129958063424876, -0.3820996535285678, 1.0},
    {-1.0, -0.10336276040369208, 0.6440068499368016},
    {0.025260738424357942, -1.0, 0.5520275040223425},
    {-0.0626699102152436, -0.08465666527411231, -1.0},
    {-1.0, 0.30231348175180484, 0.012551726506148553},
    {-0.09048269460159863, 1.0, 0.4324322612823911},
    {0.8584192512310963, -0.04981394072274192, 1.0},
    {-1.0, -0.036161502419769787, 0.4850034309062593},
    {-0.22568896426358886, -1.0, -0.29218964873154973},
    {0.9046758003457708, -0.06930679101000203, -1.0},
    {1.0, -0.28839389032120344, -0.5511162360112578},
    {0.7548708209579681, -1.0, 0.7648675152211665},
    {-0.5289879543057623, 0.35849831185096936, 1.0},
    {-1.0, 0.6877990603376621, 0.9218769929293337},
    {-0.4924911870771004, -1.0, 0.8636427140596873},
    {0.09808070213706166, -0.21881296273158135, -1.0},
    {1.0, -0.6014918066435995, -0.6121608564333201},
    {-0.4539766533257843, 1.0, -0.4593933956215954},
    {0.20546452648160496, -0.5754435138711405, -1.0},
    {-1.0, 0.8706553307849888, -0.9074941015587997},
    {0.349334839723178, -1.0, 0.9231535222195858},
    {-0.23055428686955315, 0.5063698813531022, -1.0},
    {1.0, -0.404309839944094, -0.4377207190964512},
    {0.4110444609739782, 1.0, -0.9022506586077742},
};
constexpr int kDirectionCount = 32;

}  // namespace

// Counts the triangles the segment p -> q crosses; a crossing counts only
// when it is strictly decisive: p and q strictly on opposite sides of the
// triangle's plane and the segment's line strictly inside all three edges. A
// segment through an edge or a vertex, or lying in a triangle's plane and
// meeting it, makes the attempt degenerate and another direction is tried.
// Zero-area triangles are skipped: a generic segment cannot cross them (and
// a segment through one passes through an edge of the adjacent faces, which
// is caught as degenerate there). If all 32 directions are degenerate
// (practically impossible: the segment would have to pass exactly through a
// mesh edge for every one of them) the parity of the strict crossings of the
// last attempt is returned.
bool point_in_closed_mesh(const double *p, const double *verts,
                          const uint32_t *tris, uint32_t tri_count,
                          const double *box_min, const double *box_max) {
    for (int k = 0; k < 3; ++k) {
        if (!(p[k] >= box_min[k] && p[k] <= box_max[k])) return false;
    }
    double ext = 0;
    for (int k = 0; k < 3; ++k) {
        double e = box_max[k] - box_min[k];
        if (e > ext) ext = e;
    }
    bool parity = false;
    for (int attempt = 0; attempt < kDirectionCount; ++attempt) {
        const double *dir = kDirections[attempt];
        double len = 2.0 * ext + 1.0;
        double q[3];
        for (;;) {
            for (int k = 0; k < 3; ++k) q[k] = p[k] + len * dir[k];
            bool outside = false;
            for (int k = 0; k < 3; ++k) {
                outside |= q[k] < box_min[k] || q[k] > box_max[k];
            }
            if (outside) break;
            len *= 2.0;
        }
        double smin[3], smax[3];
        for (int k = 0; k < 3; ++k) {
            smin[k] = p[k] < q[k] ? p[k] : q[k];
            smax[k] = p[k] < q[k] ? q[k] : p[k];
        }
        parity = false;
        bool degenerate = false;
        // On a degenerate attempt keep counting (the last attempt's strict
        // crossings are the documented fallback answer).
        for (uint32_t t = 0; t < tri_count; ++t) {
            const double *v[3] = {verts + 3 * std::size_t(tris[3 * t]),
                                  verts + 3 * std::size_t(tris[3 * t + 1]),
                                  verts + 3 * std::size_t(tris[3 * t + 2])};
            bool away = false;
            for (int k = 0; k < 3 && !away; ++k) {
                double lo = v[0][k], hi = v[0][k];
                for (int i = 1; i < 3; ++i) {
                    if (v[i][k] < lo) lo = v[i][k];
                    if (v[i][k] > hi) hi = v[i][k];
                }
                away = hi < smin[k] || lo > smax[k];
            }
            if (away) continue;
            int sp = orient3d_filtered(v[0], v[1], v[2], p);
            int sq = orient3d_filtered(v[0], v[1], v[2], q);
            if (sp != 0 && sp == sq) continue;
            if (sp == 0 && sq == 0) {
                // In the plane (or a zero-area triangle).
                if (is_collinear(v[0], v[1], v[2])) continue;
                if (coplanar_seg_tri(p, q, v)) degenerate = true;
                continue;
            }
            if (sp == 0 || sq == 0) {
                // Touches the plane only at p (not on the surface by the
                // precondition) or at q (outside the box): but check, so
                // that a violated precondition is treated as degenerate.
                if (is_collinear(v[0], v[1], v[2])) continue;
                const double *x = sp == 0 ? p : q;
                int o = 0;
                int k = choose_projection(v, &o);
                if (point_in_tri_proj(k, x, v, o)) degenerate = true;
                continue;
            }
            int s0 = orient3d_filtered(p, q, v[0], v[1]);
            int s1 = orient3d_filtered(p, q, v[1], v[2]);
            int s2 = orient3d_filtered(p, q, v[2], v[0]);
            if (s0 == s1 && s1 == s2 && s0 != 0) {
                parity = !parity;
            } else if (!((s0 > 0 || s1 > 0 || s2 > 0) &&
                         (s0 < 0 || s1 < 0 || s2 < 0))) {
                degenerate = true;  // through an edge or a vertex
            }
        }
        if (!degenerate) return parity;
    }
    return parity;
}

bool point_in_convex_closed_mesh(const double *p, const double *verts,
                                 const uint32_t *tris, uint32_t tri_count,
                                 int inward_sign) {
    for (uint32_t t = 0; t < tri_count; ++t) {
        int s = orient3d_filtered(verts + 3 * std::size_t(tris[3 * t]),
                                  verts + 3 * std::size_t(tris[3 * t + 1]),
                                  verts + 3 * std::size_t(tris[3 * t + 2]), p);
        if (s == -inward_sign) return false;
    }
    return true;
}


}  // namespace hgcd
