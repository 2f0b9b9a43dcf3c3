// A body's box offsets from its mesh's record (pose_box.hpp): the offsets of
// a group's 4 points lane by lane (4 lanes with AVX2, picked at run time, 2
// with SSE2), folded into running minima and maxima, reduced across the
// lanes at the end. Each lane computes transform_point's expression for its
// point, operation for operation, so every offset has its scalar bits; the
// box is the same set's minimum and maximum, whatever the order.
#include "world/pose_box.hpp"

#include <algorithm>
#include <cfloat>
#include <cmath>
#include <cstring>

#include "broad/float_box.hpp"
#include "broad/float_down_avx2.hpp"
#include "common/cpu.hpp"
#include "common/ieee.hpp"
#include "common/simd.hpp"

// (f64x4 values passed between inlined helpers: no ABI boundary is crossed.)
#pragma GCC diagnostic ignored "-Wpsabi"

#if defined(__SSE2__)
#include <immintrin.h>
#endif

namespace hgcd {

namespace {

#if HGCD_AVX2
// The running bounds of the record's offsets, 4 lanes an axis.
struct Bounds4 {
    __m256d lo[3], hi[3];
};

__attribute__((target("avx2"))) inline Bounds4 record_bounds_avx2(const Rotation &r, double s, const double *rec,
                                                                   uint32_t groups) {
    __m256d m[9];
    for (int k = 0; k < 9; ++k) m[k] = _mm256_set1_pd(r.m[k]);
    const __m256d scale = _mm256_set1_pd(s), zero = _mm256_setzero_pd();
    Bounds4 b;
    for (int a = 0; a < 3; ++a) {
        b.lo[a] = _mm256_set1_pd(INFINITY);
        b.hi[a] = _mm256_set1_pd(-INFINITY);
    }
    for (uint32_t g = 0; g < groups; ++g, rec += 12) {
        const __m256d lx = _mm256_mul_pd(scale, _mm256_load_pd(rec));
        const __m256d ly = _mm256_mul_pd(scale, _mm256_load_pd(rec + 4));
        const __m256d lz = _mm256_mul_pd(scale, _mm256_load_pd(rec + 8));
        for (int a = 0; a < 3; ++a) {
            const __m256d d = _mm256_add_pd(
                zero, _mm256_add_pd(_mm256_add_pd(_mm256_mul_pd(m[3 * a], lx), _mm256_mul_pd(m[3 * a + 1], ly)),
                                    _mm256_mul_pd(m[3 * a + 2], lz)));
            b.lo[a] = _mm256_min_pd(d, b.lo[a]);
            b.hi[a] = _mm256_max_pd(d, b.hi[a]);
        }
    }
    return b;
}

// Lane k of the result: the minimum of the lanes of v[k] (v: 4 vectors).
__attribute__((target("avx2"))) inline __m256d lane_minima(__m256d v0, __m256d v1, __m256d v2, __m256d v3) {
    const __m256d a = _mm256_min_pd(_mm256_unpacklo_pd(v0, v1), _mm256_unpackhi_pd(v0, v1));  // v0 01, v1 01, v0 23, v1 23
    const __m256d b = _mm256_min_pd(_mm256_unpacklo_pd(v2, v3), _mm256_unpackhi_pd(v2, v3));
    return _mm256_min_pd(_mm256_permute2f128_pd(a, b, 0x20), _mm256_permute2f128_pd(a, b, 0x31));
}

__attribute__((target("avx2"))) void record_box_avx2(const Rotation &r, double s, const double *rec, uint32_t groups,
                                                      double *lo, double *hi) {
    const Bounds4 b = record_bounds_avx2(r, s, rec, groups);
    const __m256d sign = _mm256_set1_pd(-0.0);
    alignas(32) double t[8];
    _mm256_store_pd(t, lane_minima(b.lo[0], b.lo[1], b.lo[2], _mm256_xor_pd(b.hi[0], sign)));
    _mm256_store_pd(t + 4, lane_minima(_mm256_xor_pd(b.hi[1], sign), _mm256_xor_pd(b.hi[2], sign), b.lo[0], b.lo[0]));
    lo[0] = t[0], lo[1] = t[1], lo[2] = t[2];
    hi[0] = -t[3], hi[1] = -t[4], hi[2] = -t[5];
}

// The highs as negated lows (max = -min of the negations, exactly), so that
// one rounding down (float_down4) serves both: lo[0..2], -hi[0] in one
// vector, -hi[1], -hi[2] in another, as round_outward pairs them.
__attribute__((target("avx2"))) void record_float_box_avx2(const Rotation &r, double s, const double *rec,
                                                            uint32_t groups, float *off) {
    const Bounds4 b = record_bounds_avx2(r, s, rec, groups);
    const __m256d sign = _mm256_set1_pd(-0.0);
    const __m256d first = lane_minima(b.lo[0], b.lo[1], b.lo[2], _mm256_xor_pd(b.hi[0], sign));
    const __m256d ny = _mm256_xor_pd(b.hi[1], sign), nz = _mm256_xor_pd(b.hi[2], sign);
    const __m256d c = _mm256_min_pd(_mm256_unpacklo_pd(ny, nz), _mm256_unpackhi_pd(ny, nz));
    const __m256d second = _mm256_min_pd(c, _mm256_permute2f128_pd(c, c, 0x01));  // -hi y, -hi z (twice)
    const __m128 f = broad::float_down4(first), h = broad::float_down4(second);
    _mm_storeu_ps(off, _mm_xor_ps(f, _mm_setr_ps(0.0f, 0.0f, 0.0f, -0.0f)));
    _mm_storel_pi(reinterpret_cast<__m64 *>(off + 4), _mm_xor_ps(h, _mm_set1_ps(-0.0f)));
}

// Four bodies at once, one a lane: the quaternions transposed,
// rotation_entries and transform_point's
// expression lane by lane (the same bits as rotation_of and the one-body
// kernels), each lane's running bounds over its own record's points (a
// record with fewer groups repeats its last: a repeated point changes no
// minimum or maximum), then the bounds of all four rounded down as one
// vector an axis (the highs negated) and transposed into the offsets.
__attribute__((target("avx2"))) inline void transpose4_pd(__m256d &r0, __m256d &r1, __m256d &r2, __m256d &r3) {
    const __m256d t0 = _mm256_unpacklo_pd(r0, r1), t1 = _mm256_unpackhi_pd(r0, r1);
    const __m256d t2 = _mm256_unpacklo_pd(r2, r3), t3 = _mm256_unpackhi_pd(r2, r3);
    r0 = _mm256_permute2f128_pd(t0, t2, 0x20);
    r1 = _mm256_permute2f128_pd(t1, t3, 0x20);
    r2 = _mm256_permute2f128_pd(t0, t2, 0x31);
    r3 = _mm256_permute2f128_pd(t1, t3, 0x31);
}

// Each lane's bounds: lo[a], hi[a] per axis (inlined into each ISA's kernel).
__attribute__((target("avx2"), always_inline)) inline void boxes4_bounds(const BoxJob *job, __m256d *lo, __m256d *hi) {
    typedef double v4 __attribute__((vector_size(32)));
    __m256d q[4];  // x y z w of each body, then each of the four bodies'
    for (int k = 0; k < 4; ++k) q[k] = _mm256_loadu_pd(job[k].orientation);
    transpose4_pd(q[0], q[1], q[2], q[3]);
    v4 m[9];
    rotation_entries((v4)q[0], (v4)q[1], (v4)q[2], (v4)q[3], m);
    const __m256d scale = _mm256_setr_pd(job[0].scale, job[1].scale, job[2].scale, job[3].scale);
    const __m256d zero = _mm256_setzero_pd();
    for (int a = 0; a < 3; ++a) {
        lo[a] = _mm256_set1_pd(INFINITY);
        hi[a] = _mm256_set1_pd(-INFINITY);
    }
    const uint32_t groups = std::max(std::max(job[0].groups, job[1].groups), std::max(job[2].groups, job[3].groups));
    for (uint32_t g = 0; g < groups; ++g) {
        __m256d c[3][4];  // c[axis][lane]: then c[axis][point], across the lanes
        for (int k = 0; k < 4; ++k) {
            const double *rec = job[k].record + 12 * size_t(std::min(g, job[k].groups - 1));
            for (int a = 0; a < 3; ++a) c[a][k] = _mm256_load_pd(rec + 4 * a);
        }
        for (int a = 0; a < 3; ++a) transpose4_pd(c[a][0], c[a][1], c[a][2], c[a][3]);
        for (int p = 0; p < 4; ++p) {
            const __m256d lx = _mm256_mul_pd(scale, c[0][p]);
            const __m256d ly = _mm256_mul_pd(scale, c[1][p]);
            const __m256d lz = _mm256_mul_pd(scale, c[2][p]);
            for (int a = 0; a < 3; ++a) {
                const __m256d d = _mm256_add_pd(
                    zero, _mm256_add_pd(_mm256_add_pd(_mm256_mul_pd((__m256d)m[3 * a], lx),
                                                      _mm256_mul_pd((__m256d)m[3 * a + 1], ly)),
                                        _mm256_mul_pd((__m256d)m[3 * a + 2], lz)));
                lo[a] = _mm256_min_pd(d, lo[a]);
                hi[a] = _mm256_max_pd(d, hi[a]);
            }
        }
    }
}

// Body k's offsets from the rounded bounds (r0 r1 r2: lows, r3 hy hz: highs);
// stream: in six streaming stores of 4 floats where the four bodies' 24
// offsets lie in one aligned run.
__attribute__((target("avx2"), always_inline)) inline void store_offsets4(const BoxJob *job, __m128 r0, __m128 r1,
                                                                          __m128 r2, __m128 r3, __m128 hy, __m128 hz,
                                                                          bool stream) {
    _MM_TRANSPOSE4_PS(r0, r1, r2, r3);  // body k: low x y z, high x
    const __m128 yz01 = _mm_unpacklo_ps(hy, hz), yz23 = _mm_unpackhi_ps(hy, hz);
    float *const off = job[0].off;
    if (stream && job[1].off == off + 6 && job[2].off == off + 12 && job[3].off == off + 18 &&
        (reinterpret_cast<uintptr_t>(off) & 15) == 0) {
        _mm_stream_ps(off, r0);
        _mm_stream_ps(off + 4, _mm_movelh_ps(yz01, r1));
        _mm_stream_ps(off + 8, _mm_shuffle_ps(r1, yz01, _MM_SHUFFLE(3, 2, 3, 2)));
        _mm_stream_ps(off + 12, r2);
        _mm_stream_ps(off + 16, _mm_movelh_ps(yz23, r3));
        _mm_stream_ps(off + 20, _mm_shuffle_ps(r3, yz23, _MM_SHUFFLE(3, 2, 3, 2)));
        return;
    }
    _mm_storeu_ps(job[0].off, r0);
    _mm_storeu_ps(job[1].off, r1);
    _mm_storeu_ps(job[2].off, r2);
    _mm_storeu_ps(job[3].off, r3);
    _mm_storel_pi(reinterpret_cast<__m64 *>(job[0].off + 4), yz01);
    _mm_storeh_pi(reinterpret_cast<__m64 *>(job[1].off + 4), yz01);
    _mm_storel_pi(reinterpret_cast<__m64 *>(job[2].off + 4), yz23);
    _mm_storeh_pi(reinterpret_cast<__m64 *>(job[3].off + 4), yz23);
}

__attribute__((target("avx2"))) void record_float_boxes4_avx2(const BoxJob *job, bool stream) {
    __m256d lo[3], hi[3];
    boxes4_bounds(job, lo, hi);
    const __m256d sign = _mm256_set1_pd(-0.0);
    const __m128 nsign = _mm_set1_ps(-0.0f);
    const __m128 r0 = broad::float_down4(lo[0]), r1 = broad::float_down4(lo[1]), r2 = broad::float_down4(lo[2]);
    const __m128 r3 = _mm_xor_ps(broad::float_down4(_mm256_xor_pd(hi[0], sign)), nsign);
    const __m128 hy = _mm_xor_ps(broad::float_down4(_mm256_xor_pd(hi[1], sign)), nsign);
    const __m128 hz = _mm_xor_ps(broad::float_down4(_mm256_xor_pd(hi[2], sign)), nsign);
    store_offsets4(job, r0, r1, r2, r3, hy, hz, stream);
}

// The same with AVX-512's 32 registers (the nine entries of the rotations
// and the bounds stay in registers) and its rounding toward -inf on
// conversion, 8 at a time: for |x| >= FLT_MIN that is float_at_most (the
// greatest float at most x; -inf below -FLT_MAX, FLT_MAX above it), and
// magnitudes below FLT_MIN go to 0 or, by the sign bit, -FLT_MIN as there.
// (GCC 12 warns of the undefined vectors inside its own AVX-512 intrinsics.)
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wuninitialized"
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#define HGCD_AVX512 __attribute__((target("avx2,avx512f,avx512dq,avx512vl")))
HGCD_AVX512 inline __m256 float_down8(__m256d a, __m256d b) {
    const __m512d x = _mm512_insertf64x4(_mm512_castpd256_pd512(a), b, 1);
    const __m256 f = _mm512_cvt_roundpd_ps(x, _MM_FROUND_TO_NEG_INF | _MM_FROUND_NO_EXC);
    const __mmask8 tiny = _mm512_cmp_pd_mask(_mm512_abs_pd(x), _mm512_set1_pd(FLT_MIN), _CMP_LT_OQ);
    const __mmask8 negative = _mm512_movepi64_mask(_mm512_castpd_si512(x));
    return _mm256_mask_blend_ps(tiny, f, _mm256_maskz_mov_ps(negative, _mm256_set1_ps(-FLT_MIN)));
}

HGCD_AVX512 void record_float_boxes4_avx512(const BoxJob *job, bool stream) {
    __m256d lo[3], hi[3];
    boxes4_bounds(job, lo, hi);
    const __m256d sign = _mm256_set1_pd(-0.0);
    const __m256 a = float_down8(lo[0], lo[1]);
    const __m256 b = _mm256_xor_ps(float_down8(lo[2], _mm256_xor_pd(hi[0], sign)),
                                   _mm256_setr_ps(0, 0, 0, 0, -0.0f, -0.0f, -0.0f, -0.0f));
    const __m256 c = _mm256_xor_ps(float_down8(_mm256_xor_pd(hi[1], sign), _mm256_xor_pd(hi[2], sign)),
                                   _mm256_set1_ps(-0.0f));
    store_offsets4(job, _mm256_castps256_ps128(a), _mm256_extractf128_ps(a, 1), _mm256_castps256_ps128(b),
                   _mm256_extractf128_ps(b, 1), _mm256_castps256_ps128(c), _mm256_extractf128_ps(c, 1), stream);
}
#undef HGCD_AVX512
#pragma GCC diagnostic pop
#endif

// The same on 2 lanes (SSE2) or one (elsewhere).
void record_box_base(const Rotation &r, double s, const double *rec, uint32_t groups, double *lo, double *hi) {
#if defined(__SSE2__)
    __m128d m[9];
    for (int k = 0; k < 9; ++k) m[k] = _mm_set1_pd(r.m[k]);
    const __m128d scale = _mm_set1_pd(s), zero = _mm_setzero_pd();
    __m128d vlo[3], vhi[3];
    for (int a = 0; a < 3; ++a) {
        vlo[a] = _mm_set1_pd(INFINITY);
        vhi[a] = _mm_set1_pd(-INFINITY);
    }
    for (uint32_t g = 0; g < groups; ++g, rec += 12)
        for (int h = 0; h < 4; h += 2) {
            const __m128d lx = _mm_mul_pd(scale, _mm_load_pd(rec + h));
            const __m128d ly = _mm_mul_pd(scale, _mm_load_pd(rec + 4 + h));
            const __m128d lz = _mm_mul_pd(scale, _mm_load_pd(rec + 8 + h));
            for (int a = 0; a < 3; ++a) {
                const __m128d d = _mm_add_pd(
                    zero, _mm_add_pd(_mm_add_pd(_mm_mul_pd(m[3 * a], lx), _mm_mul_pd(m[3 * a + 1], ly)),
                                     _mm_mul_pd(m[3 * a + 2], lz)));
                vlo[a] = _mm_min_pd(d, vlo[a]);
                vhi[a] = _mm_max_pd(d, vhi[a]);
            }
        }
    for (int a = 0; a < 3; ++a) {
        lo[a] = _mm_cvtsd_f64(_mm_min_sd(vlo[a], _mm_unpackhi_pd(vlo[a], vlo[a])));
        hi[a] = _mm_cvtsd_f64(_mm_max_sd(vhi[a], _mm_unpackhi_pd(vhi[a], vhi[a])));
    }
#else
    const double zero[3] = {0, 0, 0};
    for (int a = 0; a < 3; ++a) {
        lo[a] = INFINITY;
        hi[a] = -INFINITY;
    }
    for (uint32_t g = 0; g < groups; ++g, rec += 12)
        for (int k = 0; k < 4; ++k) {
            const double v[3] = {rec[k], rec[4 + k], rec[8 + k]};
            double d[3];
            transform_point(r, zero, s, v, d);
            for (int a = 0; a < 3; ++a) {
                lo[a] = std::min(lo[a], d[a]);
                hi[a] = std::max(hi[a], d[a]);
            }
        }
#endif
}

// cut_box, four nodes a step (f64x4: two SSE2 halves in the base build;
// each lane the same operations, so the same bits either way). For a node
// [c - h, c + h] and any vertex v under it, the computed offset d_v is
// within g_5 M_a of the exact R (s v), M_a = sum_j |R_aj| s |v_j| <= F_a =
// sum_j |R_aj| s reach_j, and R (s v) within E_a = sum_j |R_aj| s h_j of
// R (s c); the computed centre offset o is within g_5 F_a of R (s c), the
// computed E_a within g_5 relatively, o - E_a and o + E_a within u F_a of
// theirs, the final subtraction or addition of the margin within 2u F_a:
// all under 2e-15 F_a, far below the margin 1e-14 F_a (+ 1e-300 for
// underflow).
inline __attribute__((always_inline)) void cut_box_in(const Rotation &r, double s, const double *cut, size_t count,
                                                       const double *reach, double *lo, double *hi) {
    auto all = [](double x) __attribute__((always_inline)) { return f64x4{x, x, x, x}; };
    auto row = [&](size_t k, size_t n) __attribute__((always_inline)) {
        f64x4 v;
        std::memcpy(&v, cut + k * count + n, sizeof v);
        return v;
    };
    const f64x4 sv = all(s);
    f64x4 rm[9], ra[9];
    for (int k = 0; k < 9; ++k) {
        rm[k] = all(r.m[k]);
        ra[k] = all(std::fabs(r.m[k]));
    }
    f64x4 vlo[3], vhi[3];
    for (int a = 0; a < 3; ++a) {
        vlo[a] = all(INFINITY);
        vhi[a] = all(-INFINITY);
    }
    for (size_t n = 0; n < count; n += 4) {
        f64x4 c[3], h[3];
        for (int k = 0; k < 3; ++k) {
            c[k] = sv * row(k, n);
            h[k] = sv * row(3 + k, n);
        }
        for (int a = 0; a < 3; ++a) {
            const f64x4 *x = rm + 3 * a, *y = ra + 3 * a;
            const f64x4 o = (x[0] * c[0] + x[1] * c[1]) + x[2] * c[2];
            const f64x4 e = (y[0] * h[0] + y[1] * h[1]) + y[2] * h[2];
            const f64x4 low = o - e, high = o + e;
            vlo[a] = low < vlo[a] ? low : vlo[a];
            vhi[a] = high > vhi[a] ? high : vhi[a];
        }
    }
    for (int a = 0; a < 3; ++a) {
        const double *y = r.m + 3 * a;
        const double far = s * ((std::fabs(y[0]) * reach[0] + std::fabs(y[1]) * reach[1]) + std::fabs(y[2]) * reach[2]);
        const double margin = 1e-14 * far + 1e-300;
        lo[a] = std::min(std::min(vlo[a][0], vlo[a][1]), std::min(vlo[a][2], vlo[a][3])) - margin;
        hi[a] = std::max(std::max(vhi[a][0], vhi[a][1]), std::max(vhi[a][2], vhi[a][3])) + margin;
    }
}

#if HGCD_AVX2
__attribute__((target("avx2"), noinline)) void cut_box_avx2(const Rotation &r, double s, const double *cut,
                                                            size_t count, const double *reach, double *lo,
                                                            double *hi) {
    cut_box_in(r, s, cut, count, reach, lo, hi);
}
#endif

}  // namespace

void cut_box(const Rotation &r, double s, const double *cut, size_t count, const double *reach, double *lo,
             double *hi) {
#if HGCD_AVX2
    if (use_avx2()) return cut_box_avx2(r, s, cut, count, reach, lo, hi);
#endif
    cut_box_in(r, s, cut, count, reach, lo, hi);
}

void record_box(const Rotation &r, double s, const double *record, uint32_t groups, double *lo, double *hi) {
#if HGCD_AVX2
    if (use_avx2()) return record_box_avx2(r, s, record, groups, lo, hi);
#endif
    record_box_base(r, s, record, groups, lo, hi);
}

void record_float_box(const Rotation &r, double s, const double *record, uint32_t groups, float *off) {
#if HGCD_AVX2
    if (use_avx2()) return record_float_box_avx2(r, s, record, groups, off);
#endif
    double lo[3], hi[3];
    record_box_base(r, s, record, groups, lo, hi);
    broad::round_outward(lo, hi, off, off + 3);
}

void record_float_boxes4(const BoxJob *job, bool stream) {
#if HGCD_AVX2
    if (use_avx512()) return record_float_boxes4_avx512(job, stream);
    if (use_avx2()) return record_float_boxes4_avx2(job, stream);
#endif
    for (int k = 0; k < 4; ++k)
        record_float_box(rotation_of(job[k].orientation), job[k].scale, job[k].record, job[k].groups, job[k].off);
}

}  // namespace hgcd
