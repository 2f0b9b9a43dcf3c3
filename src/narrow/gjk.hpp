// GJK (Gilbert, Johnson and Keerthi) on the hulls of two point sets, in
// floating point with no certainty claimed: its answers are candidates
// (an axis, a pair of features) that the callers certify (within.cpp,
// tree_path.cpp's hulls). Internal to src/narrow.
#pragma once
#include <cmath>
#include <cstdint>

namespace hgcd {

// GJK on two small point sets (floating point, no certainty claimed): the
// simplex of points of A - B whose hull holds the point v nearest the
// origin, each point a pair (ia, ib) of vertex indices.
struct Simplex {
    double w[4][3];
    uint16_t ia[4], ib[4];
    int n = 0;
    void keep(unsigned mask) {  // the points of mask's bits, in order
        int m = 0;
        for (int k = 0; k < n; ++k)
            if (mask >> k & 1) {
                for (int j = 0; j < 3; ++j) w[m][j] = w[k][j];
                ia[m] = ia[k];
                ib[m] = ib[k];
                ++m;
            }
        n = m;
    }
};

enum class Gjk {
    Apart,  // v is a candidate axis with a gap above d
    Near,   // converged with |v| <= d (about): the simplex's features are a candidate pair within d
    Open,   // neither (distance about d, overlap in float, or no convergence)
};

// The simplex reduced to the points whose hull holds its point nearest the
// origin, that point into v. False when a full simplex (a tetrahedron)
// holds the origin.
bool gjk_reduce(Simplex &s, double *v);

// GJK from the simplex s (s.n points, or none: then v is the first search
// direction) and v its point nearest the origin, given the supports:
// lowest_a(dir, &point) points `point` at A's point lowest along dir and
// returns its index (below 65536), highest_b(dir, &point) B's highest.
template <class LowA, class HighB>
Gjk gjk_run(LowA &&lowest_a, HighB &&highest_b, double d, Simplex &s, double *v) {
    auto dot3 = [](const double *a, const double *b) { return (a[0] * b[0] + a[1] * b[1]) + a[2] * b[2]; };
    const double dd = d * d;
    for (int it = 0; it < 24; ++it) {
        const double vv = dot3(v, v);
        if (!(vv > 0) || !(vv < INFINITY)) return Gjk::Open;
        const double *pa, *pb;
        const uint32_t ia = lowest_a(v, &pa), ib = highest_b(v, &pb);
        const double w[3] = {pa[0] - pb[0], pa[1] - pb[1], pa[2] - pb[2]};
        const double vw = dot3(v, w);  // the gap along v, times |v|
        if (vw > 0 && vw * vw > dd * vv * (1 + 1e-9)) return Gjk::Apart;
        bool seen = false;
        for (int k = 0; k < s.n; ++k) seen |= s.ia[k] == ia && s.ib[k] == ib;
        if (seen || (s.n && vv - vw <= 1e-12 * vv)) return vv <= dd * (1 + 1e-9) ? Gjk::Near : Gjk::Open;
        for (int k = 0; k < 3; ++k) s.w[s.n][k] = w[k];
        s.ia[s.n] = uint16_t(ia);
        s.ib[s.n] = uint16_t(ib);
        ++s.n;
        if (!gjk_reduce(s, v)) return Gjk::Open;
    }
    return Gjk::Open;
}

// GJK on the hulls of wa (na points, 3 doubles each) and wb (nb, at most
// 65536 each): stops as soon as v looks like an axis with a gap above d (A
// beyond B along v), or once converged. v0, when given, is the first search
// direction (else the first points' difference).
Gjk gjk(const double *wa, uint32_t na, const double *wb, uint32_t nb, double d, Simplex &s, double *v,
        const double *v0 = nullptr);

}  // namespace hgcd
