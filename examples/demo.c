/* hgcd demo: the `tetra` scene of docs/scenes.md through the C API.
 *
 *   demo [--n N] [--ticks T] [--threads K] [--seed S]
 *
 * Generates N tetrahedra, detects at the initial poses (tick 0, checked
 * against the reference counts of docs/scenes.md when N and the seed are one of
 * its rows), then runs T ticks of motion (hgcd_world_step, reflecting at the
 * cube's walls), printing per tick the colliding pairs and the time per phase. */
#define _POSIX_C_SOURCE 199309L
#include <hgcd/hgcd.h>
#include <hgcd/hgcd_scene.h>

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

static double now(void) {
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return ts.tv_sec + 1e-9 * ts.tv_nsec;
}

static int check(hgcd_status s, hgcd_world *w, const char *what) {
    if (s == HGCD_OK) return 0;
    fprintf(stderr, "%s failed: %s (%s)\n", what, hgcd_status_string(s), w ? hgcd_world_last_error(w) : "");
    return 1;
}

static void print_tick(const char *label, const hgcd_stats *st) {
    printf("%-7s pairs %8llu (containment %5llu)  candidates %9llu  motion %7.1f ms  update %7.1f ms"
           "  broad %7.1f ms  narrow %7.1f ms  total %7.1f ms\n",
           label, (unsigned long long)st->colliding_pairs, (unsigned long long)st->containment_pairs,
           (unsigned long long)st->candidate_pairs, 1e3 * st->motion_seconds, 1e3 * st->update_seconds,
           1e3 * st->broad_seconds, 1e3 * st->narrow_seconds, 1e3 * st->total_seconds);
    fflush(stdout);
}

int main(int argc, char **argv) {
    uint64_t n = 200000, seed = 1;
    int ticks = 5;
    unsigned threads = 0;
    for (int i = 1; i + 1 < argc; i += 2) {
        if (!strcmp(argv[i], "--n")) n = strtoull(argv[i + 1], NULL, 10);
        else if (!strcmp(argv[i], "--ticks")) ticks = atoi(argv[i + 1]);
        else if (!strcmp(argv[i], "--threads")) threads = (unsigned)atoi(argv[i + 1]);
        else if (!strcmp(argv[i], "--seed")) seed = strtoull(argv[i + 1], NULL, 10);
        else {
            fprintf(stderr, "usage: %s [--n N] [--ticks T] [--threads K] [--seed S]\n", argv[0]);
            return 2;
        }
    }
    printf("hgcd %s: scene tetra, n = %llu, seed = %llu, %d ticks, threads = %u%s\n", hgcd_version_string(),
           (unsigned long long)n, (unsigned long long)seed, ticks, threads, threads ? "" : " (all cores)");

    hgcd_scene_tetra_desc sd = hgcd_scene_tetra_desc_default();
    sd.n = n;
    sd.seed = seed;
    hgcd_world_desc wd = hgcd_world_desc_default();
    wd.thread_count = threads;
    wd.reflect_at_bounds = 1;
    for (int k = 0; k < 3; ++k) {
        wd.bounds_min[k] = 0.0;
        wd.bounds_max[k] = sd.side;
    }
    hgcd_world *w = NULL;
    if (check(hgcd_world_create(&wd, &w), NULL, "world_create")) return 1;
    double t = now();
    if (check(hgcd_scene_tetra_populate(w, &sd, NULL), w, "scene_tetra_populate")) return 1;
    printf("scene generated and %llu bodies created in %.2f s\n", (unsigned long long)n, now() - t);

    hgcd_stats st;
    st.struct_size = sizeof st;
    if (check(hgcd_world_detect(w), w, "world_detect")) return 1;
    hgcd_world_stats(w, &st);
    print_tick("tick 0", &st);
    printf("        (first detect builds the grid: %u levels)\n", st.level_count);

    static const struct { uint64_t n, pairs, containment; } ref[] = {
        {100000, 4266, 30}, {200000, 17201, 151}, {500000, 106075, 926}, {750000, 237561, 2155}};
    for (size_t k = 0; k < sizeof ref / sizeof ref[0]; ++k)
        if (seed == 1 && n == ref[k].n && sd.side == 200.0) {
            const int ok = st.colliding_pairs == ref[k].pairs && st.containment_pairs == ref[k].containment;
            printf("        docs/scenes.md reference for n = %llu: %llu pairs (%llu by containment): %s\n",
                   (unsigned long long)n, (unsigned long long)ref[k].pairs,
                   (unsigned long long)ref[k].containment, ok ? "MATCH" : "MISMATCH");
            if (!ok) return 1;
        }

    /* The same detect again: nothing moved, so no search is made and the
     * last pairs stand (temporal coherence; containment counts only the
     * pairs tested, none here). */
    if (check(hgcd_world_detect(w), w, "world_detect")) return 1;
    hgcd_world_stats(w, &st);
    print_tick("again", &st);
    printf("        (nothing moved: %llu pairs kept without a search)\n", (unsigned long long)st.unmoved_pairs);

    for (int k = 1; k <= ticks; ++k) {
        if (check(hgcd_world_step(w), w, "world_step")) return 1;
        hgcd_world_stats(w, &st);
        char label[32];
        snprintf(label, sizeof label, "tick %d", k);
        print_tick(label, &st);
    }
    hgcd_world_destroy(w);
    return 0;
}
