/* The benchmarks' turning motion, shared by the C and C++ benches. */
#ifndef HGCD_BENCH_TURN_H
#define HGCD_BENCH_TURN_H

/* q = q * r, then normalised: |q|^2 is 1 within a few ulps, so one Newton
 * step of 1/sqrt from 1, (3 - |q|^2) / 2, is exact to ~1e-32. The same bits
 * wherever it runs (no libm call, a fixed order of operations). */
static inline void turn_orientation(double *q, const double *r) {
    const double x = q[3] * r[0] + q[0] * r[3] + q[1] * r[2] - q[2] * r[1];
    const double y = q[3] * r[1] - q[0] * r[2] + q[1] * r[3] + q[2] * r[0];
    const double z = q[3] * r[2] + q[0] * r[1] - q[1] * r[0] + q[2] * r[3];
    const double w = q[3] * r[3] - q[0] * r[0] - q[1] * r[1] - q[2] * r[2];
    const double scale = 0.5 * (3 - (((x * x + y * y) + z * z) + w * w));
    q[0] = x * scale;
    q[1] = y * scale;
    q[2] = z * scale;
    q[3] = w * scale;
}

#endif
