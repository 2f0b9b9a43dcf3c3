/*
 * The C side of bench/tick.py --against-c: a second world, driven by C, ticked
 * in the same process, alternating tick by tick with the Python one, so both
 * see the same machine. Built by bench/compare.sh into c_tick.so, linked with
 * the same libhgcd.a as the Python module (its symbols kept private).
 */
#define _POSIX_C_SOURCE 200809L
#include <hgcd/hgcd.h>
#include <hgcd/hgcd_scene.h>

#include <time.h>

static double clock_seconds(clockid_t clock) {
    struct timespec ts;
    clock_gettime(clock, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

/* The world of bench_hgcd's engine modes (--thread-policy fixed): reflecting
 * at [0, side]^3, one shared unit tetrahedron, body i from entry i of the
 * arrays. NULL on failure. */
hgcd_world *c_world_create(uint64_t n, double side, unsigned threads, const double *centers,
                           const double *orientations, const double *velocities, const double *scales) {
    hgcd_world_desc wd = hgcd_world_desc_default();
    wd.thread_count = threads;
    wd.thread_policy = HGCD_THREADS_FIXED; /* as the Python world of tick.py */
    wd.reflect_at_bounds = 1;
    for (int k = 0; k < 3; ++k) wd.bounds_max[k] = side;
    hgcd_world *w = NULL;
    if (hgcd_world_create(&wd, &w) != HGCD_OK) return NULL;
    double vertices[12];
    uint32_t triangles[12];
    hgcd_scene_tetra_unit_mesh(vertices, triangles);
    hgcd_mesh_desc md = hgcd_mesh_desc_default();
    md.vertices = vertices;
    md.triangles = triangles;
    md.vertex_count = 4;
    md.triangle_count = 4;
    hgcd_body_desc bd = hgcd_body_desc_default();
    if (hgcd_mesh_create(w, &md, &bd.mesh) != HGCD_OK) goto fail;
    for (uint64_t i = 0; i < n; ++i) {
        for (int k = 0; k < 3; ++k) bd.position[k] = centers[3 * i + k];
        for (int k = 0; k < 4; ++k) bd.orientation[k] = orientations[4 * i + k];
        for (int k = 0; k < 3; ++k) bd.velocity[k] = velocities[3 * i + k];
        bd.scale = scales[i];
        bd.user_data = i;
        hgcd_body body;
        if (hgcd_body_create(w, &bd, &body) != HGCD_OK) goto fail;
    }
    if (hgcd_world_detect(w) != HGCD_OK) goto fail;
    return w;
fail:
    hgcd_world_destroy(w);
    return NULL;
}

/* One engine tick as bench_hgcd --mode engine-batch: the poses in one call,
 * the detect, the pairs read in place. Its wall-clock seconds go to *seconds
 * and the CPU seconds of the process (all its threads) to *cpu_seconds,
 * FNV-1a of the pair indices to *fnv. Returns the status. */
int32_t c_tick(hgcd_world *w, uint64_t n, const double *centers, const double *orientations, double *seconds,
               double *cpu_seconds, uint64_t *count, uint64_t *fnv) {
    const double c0 = clock_seconds(CLOCK_PROCESS_CPUTIME_ID), t0 = clock_seconds(CLOCK_MONOTONIC);
    hgcd_status s = hgcd_world_set_poses(w, NULL, (size_t)n, centers, 0, orientations, 0);
    if (s == HGCD_OK) s = hgcd_world_detect(w);
    const hgcd_pair *pairs = NULL;
    size_t total = 0;
    if (s == HGCD_OK) s = hgcd_world_pairs(w, &pairs, &total);
    *seconds = clock_seconds(CLOCK_MONOTONIC) - t0;
    *cpu_seconds = clock_seconds(CLOCK_PROCESS_CPUTIME_ID) - c0;
    uint64_t hash = 14695981039346656037ull;
    for (size_t k = 0; k < total; ++k) {
        const uint32_t ab[2] = {pairs[k].a.index, pairs[k].b.index};
        const unsigned char *byte = (const unsigned char *)ab;
        for (size_t i = 0; i < sizeof ab; ++i) hash = (hash ^ byte[i]) * 1099511628211ull;
    }
    *count = total;
    *fnv = hash;
    return s;
}

void c_world_destroy(hgcd_world *w) { hgcd_world_destroy(w); }
