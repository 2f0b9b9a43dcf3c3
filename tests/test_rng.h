/* The tests' random numbers: splitmix64 (as docs/scenes.md) and random unit
 * quaternions. Shared by the test programs. */
#ifndef HGCD_TEST_RNG_H
#define HGCD_TEST_RNG_H

#include <math.h>
#include <stdint.h>

typedef struct {
    uint64_t s;
} rng;
static inline uint64_t next(rng *r) {
    uint64_t z = (r->s += 0x9E3779B97F4A7C15ull);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return z ^ (z >> 31);
}
static inline double unif(rng *r) { return (double)(next(r) >> 11) * 0x1.0p-53; }

/* A random unit quaternion (x, y, z, w): a point of the unit 4-ball by
 * rejection, normalised. */
static inline void random_unit_quaternion(rng *r, double q[4]) {
    double n;
    int k;
    do {
        for (k = 0; k < 4; ++k) q[k] = 2 * unif(r) - 1;
        n = q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3];
    } while (n < 0.01 || n > 1);
    n = sqrt(n);
    for (k = 0; k < 4; ++k) q[k] /= n;
}

#endif
