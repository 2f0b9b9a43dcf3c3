/* bench_hgcd: scene `tetra` (docs/scenes.md) through the public C API of hgcd.
 *
 *   bench_hgcd [--n N] [--seed S] [--threads K] [--ticks T] [--commit HASH]
 *              [--lib NAME] [--min-cell-size W] [--side L] [--check]
 *
 * --lib sets the JSON's "lib" field (default hgcd; make bench's 100-tick
 * runs are hgcd-long).
 * --min-cell-size sets the world descriptor's min_cell_size (default 0: the
 * grid adapts to the body sizes, levels a factor 2 apart). --side sets the
 * scene's cube side L (default 200; the reference counts of docs/scenes.md hold for
 * the default only).
 *
 * Generates the scene with hgcd_scene_tetra_generate, creates the N bodies on
 * the shared unit mesh (hgcd_scene_tetra_unit_mesh, body scale = generated
 * scale) in a world that reflects at the cube [0, side]^3 (which is exactly
 * the motion of docs/scenes.md), runs one initial hgcd_world_detect and then T
 * ticks of hgcd_world_step, and prints ONE JSON line on stdout:
 *
 *   lib, scene, n, seed, threads, ticks, commit,
 *   broad_ms, narrow_ms, update_ms, motion_ms, tick_ms  medians over the ticks
 *       of the library's own per-phase timers (hgcd_world_stats);
 *   wall_ms           median wall-clock time of hgcd_world_step seen here;
 *   tick_mean_ms, tick_max_ms, update_mean_ms, broad_mean_ms, narrow_mean_ms
 *                     means (and the largest tick) over the ticks: ticks that
 *                     renumber the bodies' storage cost more than the others;
 *   candidate_pairs, narrow_tests, colliding_pairs, containment_pairs,
 *   triangle_tests, moved_bodies   of the last tick (moved_bodies: bodies
 *                     that changed row or level in the grid's update);
 *   pairs_fnv         FNV-1a (64-bit, hex) of the last tick's pairs, indices
 *                     in order: equal when two builds report the same pairs;
 *   initial_pairs, initial_containment, initial_ms   of the initial detect;
 *   setup_ms          world creation and hgcd_scene_tetra_populate (scene drawn, mesh and bodies made);
 *   peak_rss_mb       getrusage ru_maxrss at the end;
 *   bytes_per_body    growth of the peak RSS from just before world creation
 *                     to after the ticks, divided by n;
 *   reference_ok      with --check: whether the initial detect matches the
 *                     reference counts of docs/scenes.md (pairs and containment;
 *                     null when docs/scenes.md has no row for this n and seed).
 *
 * --per-tick prints each tick's times to stderr. Diagnostics go to stderr. Exit status: 0 when the JSON line was printed
 * (even with reference_ok false: the caller reads the JSON), 1 on an API
 * failure, 2 on a usage error.
 */
#define _POSIX_C_SOURCE 200809L
#include <hgcd/hgcd.h>
#include <hgcd/hgcd_scene.h>

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/resource.h>
#include <time.h>

static double now_seconds(void) {
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

/* Peak resident set size in bytes (Linux reports ru_maxrss in KiB). */
static double peak_rss_bytes(void) {
    struct rusage ru;
    if (getrusage(RUSAGE_SELF, &ru) != 0) return 0.0;
    return 1024.0 * (double)ru.ru_maxrss;
}

static int cmp_double(const void *a, const void *b) {
    const double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

/* Median of v[0..count) (sorts v); 0 for an empty array. */
static double mean(const double *v, int count) {
    double sum = 0;
    for (int k = 0; k < count; ++k) sum += v[k];
    return sum / count;
}

static double maximum(const double *v, int count) {
    double m = v[0];
    for (int k = 1; k < count; ++k) m = v[k] > m ? v[k] : m;
    return m;
}

static double median(double *v, int count) {
    if (count <= 0) return 0.0;
    qsort(v, (size_t)count, sizeof *v, cmp_double);
    return count % 2 ? v[count / 2] : 0.5 * (v[count / 2 - 1] + v[count / 2]);
}

static int failed(hgcd_status s, const hgcd_world *w, const char *what) {
    if (s == HGCD_OK) return 0;
    fprintf(stderr, "bench_hgcd: %s failed: %s (%s)\n", what, hgcd_status_string(s),
            w ? hgcd_world_last_error(w) : "");
    return 1;
}

static void usage(const char *argv0) {
    fprintf(stderr,
            "usage: %s [--n N] [--seed S] [--threads K] [--ticks T] [--commit HASH] [--lib NAME] [--min-cell-size W] [--side L] [--check] [--per-tick]\n"
            "  --threads 0 = all cores; --check compares the initial detect with docs/scenes.md\n",
            argv0);
}

/* Reference answers of docs/scenes.md (seed 1, default scene parameters). */
static const struct {
    uint64_t n, pairs, containment;
} reference[] = {{100000, 4266, 30}, {200000, 17201, 151}, {500000, 106075, 926}, {750000, 237561, 2155}};

int main(int argc, char **argv) {
    uint64_t n = 100000, seed = 1;
    unsigned threads = 1;
    int ticks = 5, check = 0, per_tick = 0;
    const char *commit = "unknown", *lib = "hgcd";
    double min_cell = 0, side = 0;
    for (int i = 1; i < argc; ++i) {
        const char *a = argv[i];
        if (!strcmp(a, "--per-tick")) {
            per_tick = 1;
            continue;
        }
        if (!strcmp(a, "--check")) {
            check = 1;
            continue;
        }
        if (i + 1 >= argc) {
            usage(argv[0]);
            return 2;
        }
        const char *v = argv[++i];
        if (!strcmp(a, "--n")) n = strtoull(v, NULL, 10);
        else if (!strcmp(a, "--seed")) seed = strtoull(v, NULL, 10);
        else if (!strcmp(a, "--threads")) threads = (unsigned)strtoul(v, NULL, 10);
        else if (!strcmp(a, "--ticks")) ticks = atoi(v);
        else if (!strcmp(a, "--commit")) commit = v;
        else if (!strcmp(a, "--lib")) lib = v;
        else if (!strcmp(a, "--min-cell-size")) min_cell = strtod(v, NULL);
        else if (!strcmp(a, "--side")) side = strtod(v, NULL);
        else {
            usage(argv[0]);
            return 2;
        }
    }
    if (n == 0 || ticks < 1) {
        fprintf(stderr, "bench_hgcd: need n >= 1 and ticks >= 1\n");
        return 2;
    }

    /* The scene, bit for bit as docs/scenes.md defines it. */
    hgcd_scene_tetra_desc sd = hgcd_scene_tetra_desc_default();
    sd.n = n;
    sd.seed = seed;
    if (side > 0) sd.side = side;
    double *tick_total = malloc((size_t)ticks * sizeof(double)), *tick_broad = malloc((size_t)ticks * sizeof(double));
    double *tick_narrow = malloc((size_t)ticks * sizeof(double)), *tick_update = malloc((size_t)ticks * sizeof(double));
    double *tick_motion = malloc((size_t)ticks * sizeof(double)), *tick_wall = malloc((size_t)ticks * sizeof(double));
    if (!tick_total || !tick_broad || !tick_narrow || !tick_update ||
        !tick_motion || !tick_wall) {
        fprintf(stderr, "bench_hgcd: out of memory for n = %llu\n", (unsigned long long)n);
        return 1;
    }
    const double rss_before = peak_rss_bytes();
    double t0 = now_seconds();
    hgcd_world_desc wd = hgcd_world_desc_default();
    wd.thread_count = threads;
    wd.reflect_at_bounds = 1;
    wd.min_cell_size = min_cell;
    for (int k = 0; k < 3; ++k) {
        wd.bounds_min[k] = 0.0;
        wd.bounds_max[k] = sd.side;
    }
    hgcd_world *w = NULL;
    if (failed(hgcd_world_create(&wd, &w), NULL, "world_create")) return 1;

    if (failed(hgcd_scene_tetra_populate(w, &sd, NULL), w, "scene_tetra_populate")) return 1;
    const double setup_ms = 1e3 * (now_seconds() - t0);

    hgcd_stats st;
    memset(&st, 0, sizeof st);
    st.struct_size = sizeof st;
    t0 = now_seconds();
    if (failed(hgcd_world_detect(w), w, "world_detect")) return 1;
    const double initial_ms = 1e3 * (now_seconds() - t0);
    if (failed(hgcd_world_stats(w, &st), w, "world_stats")) return 1;
    const uint64_t initial_pairs = st.colliding_pairs, initial_containment = st.containment_pairs;

    const char *reference_ok = "null";
    uint64_t reference_pairs = 0;
    int has_reference = 0;
    if (check) {
        for (size_t k = 0; k < sizeof reference / sizeof reference[0]; ++k) {
            if (seed == 1 && side == 0 && n == reference[k].n) {
                has_reference = 1;
                reference_pairs = reference[k].pairs;
                const int ok = initial_pairs == reference[k].pairs && initial_containment == reference[k].containment;
                reference_ok = ok ? "true" : "false";
                if (!ok)
                    fprintf(stderr,
                            "bench_hgcd: n = %llu: initial detect gave %llu pairs (%llu by containment), "
                            "docs/scenes.md says %llu (%llu)\n",
                            (unsigned long long)n, (unsigned long long)initial_pairs,
                            (unsigned long long)initial_containment, (unsigned long long)reference[k].pairs,
                            (unsigned long long)reference[k].containment);
            }
        }
    }

    for (int k = 0; k < ticks; ++k) {
        t0 = now_seconds();
        if (failed(hgcd_world_step(w), w, "world_step")) return 1;
        tick_wall[k] = 1e3 * (now_seconds() - t0);
        memset(&st, 0, sizeof st);
        st.struct_size = sizeof st;
        if (failed(hgcd_world_stats(w, &st), w, "world_stats")) return 1;
        tick_total[k] = 1e3 * st.total_seconds;
        tick_broad[k] = 1e3 * st.broad_seconds;
        tick_narrow[k] = 1e3 * st.narrow_seconds;
        tick_update[k] = 1e3 * st.update_seconds;
        tick_motion[k] = 1e3 * st.motion_seconds;
        if (per_tick)
            fprintf(stderr, "tick %d: %.1f ms (motion %.1f, update %.1f, broad %.1f, narrow %.1f)\n", k + 1,
                    tick_total[k], tick_motion[k], tick_update[k], tick_broad[k], tick_narrow[k]);
    }
    const double rss_after = peak_rss_bytes();
    /* FNV-1a over the last tick's pairs (indices, in order): two builds that
     * report the same pairs print the same value (scripts/check-ieee.sh). */
    uint64_t pairs_fnv = 14695981039346656037ull;
    {
        const hgcd_pair *pairs = NULL;
        size_t count = 0;
        if (failed(hgcd_world_pairs(w, &pairs, &count), w, "world_pairs")) return 1;
        for (size_t k = 0; k < count; ++k) {
            const uint32_t ab[2] = {pairs[k].a.index, pairs[k].b.index};
            const unsigned char *byte = (const unsigned char *)ab;
            for (size_t i = 0; i < sizeof ab; ++i) pairs_fnv = (pairs_fnv ^ byte[i]) * 1099511628211ull;
        }
    }

    printf("{\"lib\":\"%s\",\"scene\":\"tetra\",\"n\":%llu,\"seed\":%llu,\"threads\":%u,\"ticks\":%d,"
           "\"commit\":\"%s\",\"version\":\"%s\",\"bounding_volume\":\"box\",\"min_cell_size\":%g,"
           "\"broad_ms\":%.3f,\"narrow_ms\":%.3f,\"update_ms\":%.3f,\"motion_ms\":%.3f,\"tick_ms\":%.3f,"
           "\"wall_ms\":%.3f,\"candidate_pairs\":%llu,\"narrow_tests\":%llu,\"colliding_pairs\":%llu,"
           "\"containment_pairs\":%llu,\"triangle_tests\":%llu,\"moved_bodies\":%llu,\"pairs_fnv\":\"%016llx\","
           "\"initial_pairs\":%llu,\"initial_containment\":%llu,"
           "\"initial_ms\":%.3f,\"setup_ms\":%.3f,\"levels\":%u,\"oversize\":%u,"
           "\"peak_rss_mb\":%.1f,\"bytes_per_body\":%.1f,"
           "\"tick_mean_ms\":%.3f,\"tick_max_ms\":%.3f,\"update_mean_ms\":%.3f,\"broad_mean_ms\":%.3f,"
           "\"narrow_mean_ms\":%.3f,",
           lib, (unsigned long long)n, (unsigned long long)seed, st.thread_count, ticks, commit, hgcd_version_string(),
           min_cell, median(tick_broad, ticks), median(tick_narrow, ticks), median(tick_update, ticks),
           median(tick_motion, ticks), median(tick_total, ticks), median(tick_wall, ticks),
           (unsigned long long)st.candidate_pairs, (unsigned long long)st.narrow_tests,
           (unsigned long long)st.colliding_pairs, (unsigned long long)st.containment_pairs,
           (unsigned long long)st.triangle_tests, (unsigned long long)st.moved_bodies, (unsigned long long)pairs_fnv, (unsigned long long)initial_pairs,
           (unsigned long long)initial_containment, initial_ms, setup_ms,
           st.level_count, st.oversize_count, rss_after / (1024.0 * 1024.0),
           (rss_after - rss_before) / (double)n, mean(tick_total, ticks), maximum(tick_total, ticks),
           mean(tick_update, ticks), mean(tick_broad, ticks), mean(tick_narrow, ticks));
    if (has_reference)
        printf("\"reference_pairs\":%llu,", (unsigned long long)reference_pairs);
    printf("\"reference_ok\":%s}\n", reference_ok);
    fflush(stdout);

    hgcd_world_destroy(w);
    free(tick_total);
    free(tick_broad);
    free(tick_narrow);
    free(tick_update);
    free(tick_motion);
    free(tick_wall);
    return 0;
}
