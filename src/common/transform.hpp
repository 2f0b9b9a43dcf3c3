// The one world-space transform of hgcd (documented in hgcd.h): every place
// that needs world vertices calls these, so the bits agree everywhere.
#pragma once
#include <cmath>
#include <cstdint>

namespace hgcd {

struct Rotation {
    double m[9];  // row-major
};

// Rotation matrix of quaternion (x, y, z, w), each entry evaluated as written
// in docs/scenes.md. The build uses -ffp-contract=off so no FMA changes the bits.
// T is double, or a vector of doubles with one quaternion per lane (the same
// operations lane by lane, so the same bits).
template <class T>
inline void rotation_entries(const T &x, const T &y, const T &z, const T &w, T *m) {
    m[0] = 1.0 - 2.0 * (y * y + z * z);
    m[1] = 2.0 * (x * y - z * w);
    m[2] = 2.0 * (x * z + y * w);
    m[3] = 2.0 * (x * y + z * w);
    m[4] = 1.0 - 2.0 * (x * x + z * z);
    m[5] = 2.0 * (y * z - x * w);
    m[6] = 2.0 * (x * z - y * w);
    m[7] = 2.0 * (y * z + x * w);
    m[8] = 1.0 - 2.0 * (x * x + y * y);
}

inline Rotation rotation_of(const double *q) {
    Rotation r;
    rotation_entries(q[0], q[1], q[2], q[3], r.m);
    return r;
}

// World vertex of mesh vertex m for a body at c, rotation r, scale s.
inline void transform_point(const Rotation &r, const double *c, double s,
                            const double *m, double *out) {
    const double lx = s * m[0], ly = s * m[1], lz = s * m[2];
    out[0] = c[0] + ((r.m[0] * lx + r.m[1] * ly) + r.m[2] * lz);
    out[1] = c[1] + ((r.m[3] * lx + r.m[4] * ly) + r.m[5] * lz);
    out[2] = c[2] + ((r.m[6] * lx + r.m[7] * ly) + r.m[8] * lz);
}

// Upper bound on |R v| / |v| for the matrix of a quaternion of squared norm
// n2: R = n2 * Rhat + (1 - n2) * I, so the stretch is at most n2 + |1 - n2|.
inline double rotation_stretch(const double *q) {
    const double n2 = q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3];
    return n2 + std::fabs(1.0 - n2);
}

}  // namespace hgcd
