/* Benchmarks of body types, filters and events on scene `tetra` (docs/scenes.md).
 *
 *   bench_features --mode static|mask|events [--n N] [--dynamic D]
 *                  [--threads K] [--ticks T] [--rounds R] [--commit HASH]
 *                  [--engine 0|1] [--per-tick 0|1]
 *
 * static: a scene of N + D objects (default 1000000 + 50000) in the
 *   reference cube (side 200); objects 0 .. D-1 are dynamic and move with the
 *   reference motion (hgcd_world_step), the N others are static. Against it,
 *   world B: the same D dynamic bodies with only the static ones they can
 *   reach (a static whose bounding sphere comes within a dynamic one's at any
 *   of the T + 1 positions of the run). Both worlds report the same pairs at
 *   every tick (checked, mapped back to the scene's objects).
 * mask: scene `tetra` of N objects (default 750000) stepped, A with the
 *   default filter, B with body i in category i % 10 and colliding only with
 *   its own category: 90% of the candidate pairs filtered out.
 * events: scene `tetra` of N objects stepped: hgcd_stats.events_seconds
 *   against the whole tick.
 *
 * --engine (static mode): the caller moves the dynamic bodies (the same
 *   reference motion, hgcd_scene_tetra_move) and hands their positions over
 *   with hgcd_world_set_poses (by index: they are bodies 0 .. D-1), then
 *   calls hgcd_world_detect, as an engine does; the static bodies are never
 *   touched; a tick's time is then set_poses plus detect. Default: each tick
 *   is one hgcd_world_step.
 *
 * Each round builds world A, runs T ticks, frees it, then the same for B
 * (A/B interleaved by round; building is not timed). Prints one JSON line:
 * medians over every tick of every round, in ms, and the ratios; the
 * *_cpu_ms figures are the process's CPU time of a tick (hgcd's part only),
 * which a loaded machine does not stretch as it does the wall clock (with
 * 1 thread). --per-tick 1: each tick's times and counts to stderr. */
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include <hgcd/hgcd.h>
#include <hgcd/hgcd_scene.h>

typedef struct {
    const char *mode, *commit;
    uint64_t n, dynamic;
    unsigned threads;
    int ticks, rounds, engine, per_tick;
} options;

static double now(void) {
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return (double)t.tv_sec + 1e-9 * (double)t.tv_nsec;
}

/* The process's CPU time: a loaded machine stretches the wall-clock time
 * of a tick, not its CPU time on 1 thread. */
static double cpu_now(void) {
    struct timespec t;
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
    return (double)t.tv_sec + 1e-9 * (double)t.tv_nsec;
}

static int failed(hgcd_status s, const hgcd_world *w, const char *what) {
    if (s == HGCD_OK) return 0;
    fprintf(stderr, "bench_features: %s: %s (%s)\n", what, hgcd_status_string(s), w ? hgcd_world_last_error(w) : "");
    return 1;
}

static int cmp_double(const void *a, const void *b) {
    const double x = *(const double *)a, y = *(const double *)b;
    return x < y ? -1 : x > y;
}

static double median(double *v, int n) {
    qsort(v, (size_t)n, sizeof *v, cmp_double);
    return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

/* The scene's objects. */
typedef struct {
    uint64_t n;
    double side, *centers, *radii, *scales, *orientations, *velocities;
} scene;

static int scene_make(scene *s, uint64_t n, double side) {
    hgcd_scene_tetra_desc d = hgcd_scene_tetra_desc_default();
    d.n = n;
    d.side = side;
    s->n = n;
    s->side = side;
    s->centers = malloc(3 * n * sizeof(double));
    s->radii = malloc(n * sizeof(double));
    s->scales = malloc(n * sizeof(double));
    s->orientations = malloc(4 * n * sizeof(double));
    s->velocities = malloc(3 * n * sizeof(double));
    if (!s->centers || !s->radii || !s->scales || !s->orientations || !s->velocities) return 1;
    return failed(hgcd_scene_tetra_generate(&d, s->centers, s->radii, s->scales, s->orientations, s->velocities),
                  NULL, "scene_tetra_generate");
}

/* A world of the objects listed in `which` (count of them), object
 * which[k] as body k; type[k] and filter (NULL: defaults) per body. */
static hgcd_world *make_world(const options *o, const scene *s, const uint64_t *which, uint64_t count,
                              const int32_t *type, const hgcd_filter *filter) {
    hgcd_world_desc wd = hgcd_world_desc_default();
    wd.thread_count = o->threads;
    wd.reflect_at_bounds = 1;
    for (int k = 0; k < 3; ++k) wd.bounds_max[k] = s->side;
    hgcd_world *w = NULL;
    if (failed(hgcd_world_create(&wd, &w), NULL, "world_create")) return NULL;
    double v[12];
    uint32_t t[12];
    hgcd_scene_tetra_unit_mesh(v, t);
    hgcd_mesh_desc md = hgcd_mesh_desc_default();
    md.vertices = v, md.vertex_count = 4, md.triangles = t, md.triangle_count = 4;
    hgcd_body_desc bd = hgcd_body_desc_default();
    if (failed(hgcd_mesh_create(w, &md, &bd.mesh), w, "mesh_create")) return NULL;
    for (uint64_t k = 0; k < count; ++k) {
        const uint64_t i = which ? which[k] : k;
        memcpy(bd.position, s->centers + 3 * i, sizeof bd.position);
        memcpy(bd.orientation, s->orientations + 4 * i, sizeof bd.orientation);
        memcpy(bd.velocity, s->velocities + 3 * i, sizeof bd.velocity);
        bd.scale = s->scales[i];
        bd.user_data = i;
        bd.type = type ? type[k] : HGCD_BODY_DYNAMIC;
        if (filter) bd.filter = filter[k];
        hgcd_body b;
        if (failed(hgcd_body_create(w, &bd, &b), w, "body_create")) return NULL;
    }
    return w;
}

typedef struct {
    double *total, *narrow, *broad, *events, *cpu; /* ms, one per tick of every round */
    hgcd_stats last;
} samples;

/* Runs T ticks of w, appending to smp at *at; pairs of tick k mapped to
 * objects (which, or identity) go to pairs_out[k] (when not NULL). */
static int run(hgcd_world *w, const options *o, const scene *s, samples *smp, int *at, const uint64_t *which,
               uint64_t **pairs_out, size_t *pairs_n) {
    /* Engine mode: the dynamic bodies are bodies 0 .. D-1 of both worlds
     * (which[k] = k for k < D), moved by the caller and handed over by index. */
    const uint64_t D = o->dynamic;
    double *c = NULL, *v = NULL;
    if (o->engine) {
        c = malloc(3 * D * sizeof(double)), v = malloc(3 * D * sizeof(double));
        memcpy(c, s->centers, 3 * D * sizeof(double));
        memcpy(v, s->velocities, 3 * D * sizeof(double));
    }
    for (int k = 0; k < o->ticks; ++k) {
        double wall = 0;
        double c0 = cpu_now();
        if (o->engine) {
            hgcd_scene_tetra_move(D, s->side, c, v);
            c0 = cpu_now();
            const double t0 = now();
            if (failed(hgcd_world_set_poses(w, NULL, D, c, 0, NULL, 0), w, "world_set_poses") ||
                failed(hgcd_world_detect(w), w, "world_detect"))
                return 1;
            wall = now() - t0;
        } else if (failed(hgcd_world_step(w), w, "world_step")) {
            return 1;
        }
        hgcd_stats st;
        st.struct_size = sizeof st;
        if (failed(hgcd_world_stats(w, &st), w, "world_stats")) return 1;
        smp->total[*at] = 1e3 * (o->engine ? wall : st.total_seconds);  /* engine: set_poses + detect */
        smp->cpu[*at] = 1e3 * (cpu_now() - c0);
        smp->narrow[*at] = 1e3 * st.narrow_seconds;
        smp->broad[*at] = 1e3 * st.broad_seconds;
        smp->events[*at] = 1e3 * st.events_seconds;
        ++*at;
        smp->last = st;
        if (o->per_tick)
            fprintf(stderr, "%s tick %d: %.3f ms cpu %.3f (update %.3f broad %.3f narrow %.3f) searched %llu candidates %llu levels %u oversize %u\n",
                    which ? "B" : "A", k, smp->total[*at - 1], smp->cpu[*at - 1], 1e3 * st.update_seconds, 1e3 * st.broad_seconds,
                    1e3 * st.narrow_seconds, (unsigned long long)st.searched_bodies,
                    (unsigned long long)st.candidate_pairs, st.level_count, st.oversize_count);
        if (!pairs_out) continue;
        const hgcd_pair *p;
        size_t n;
        if (failed(hgcd_world_pairs(w, &p, &n), w, "world_pairs")) return 1;
        free(pairs_out[k]);
        pairs_out[k] = malloc((n + 1) * sizeof(uint64_t));
        for (size_t j = 0; j < n; ++j) {
            uint64_t a = which ? which[p[j].a.index] : p[j].a.index, b = which ? which[p[j].b.index] : p[j].b.index;
            if (a > b) {
                const uint64_t x = a;
                a = b, b = x;
            }
            pairs_out[k][j] = a << 32 | b;
        }
        pairs_n[k] = n;
    }
    free(c), free(v);
    return 0;
}

static int cmp_u64(const void *a, const void *b) {
    const uint64_t x = *(const uint64_t *)a, y = *(const uint64_t *)b;
    return x < y ? -1 : x > y;
}

/* The static objects (index >= D) within reach of a dynamic one at any of
 * its T + 1 positions, by a hash of the centres into cells of width 4 (twice
 * the largest circumradius): sphere centres closer than r_a + r_b. */
static uint64_t *reachable(const options *o, const scene *s, uint64_t *count) {
    const uint64_t D = o->dynamic, N = s->n;
    const double cell = 4.0;
    const int cells = (int)ceil(s->side / cell) + 1;
    const size_t n_cells = (size_t)cells * cells * cells;
    uint32_t *start = calloc(n_cells + 1, sizeof(uint32_t)), *order = malloc((N - D) * sizeof(uint32_t));
    char *hit = calloc(N, 1);
    size_t *key = malloc((N - D) * sizeof(size_t));
    for (uint64_t i = D; i < N; ++i) {
        const double *c = s->centers + 3 * i;
        key[i - D] = ((size_t)(c[2] / cell) * cells + (size_t)(c[1] / cell)) * cells + (size_t)(c[0] / cell);
        ++start[key[i - D] + 1];
    }
    for (size_t k = 0; k < n_cells; ++k) start[k + 1] += start[k];
    uint32_t *fill = malloc(n_cells * sizeof(uint32_t));
    memcpy(fill, start, n_cells * sizeof(uint32_t));
    for (uint64_t i = D; i < N; ++i) order[fill[key[i - D]]++] = (uint32_t)i;
    double *c = malloc(3 * D * sizeof(double)), *v = malloc(3 * D * sizeof(double));
    memcpy(c, s->centers, 3 * D * sizeof(double));
    memcpy(v, s->velocities, 3 * D * sizeof(double));
    for (int t = 0; t <= o->ticks; ++t) {
        if (t) hgcd_scene_tetra_move(D, s->side, c, v);
        for (uint64_t d = 0; d < D; ++d) {
            const double *p = c + 3 * d;
            const int x = (int)(p[0] / cell), y = (int)(p[1] / cell), z = (int)(p[2] / cell);
            for (int dz = -1; dz <= 1; ++dz)
                for (int dy = -1; dy <= 1; ++dy)
                    for (int dx = -1; dx <= 1; ++dx) {
                        if (x + dx < 0 || y + dy < 0 || z + dz < 0 || x + dx >= cells || y + dy >= cells ||
                            z + dz >= cells)
                            continue;
                        const size_t k = ((size_t)(z + dz) * cells + (size_t)(y + dy)) * cells + (size_t)(x + dx);
                        for (uint32_t j = start[k]; j < start[k + 1]; ++j) {
                            const double *q = s->centers + 3 * (size_t)order[j];
                            const double r = s->radii[d] + s->radii[order[j]];
                            const double dx2 = p[0] - q[0], dy2 = p[1] - q[1], dz2 = p[2] - q[2];
                            if (dx2 * dx2 + dy2 * dy2 + dz2 * dz2 <= r * r * (1 + 1e-9)) hit[order[j]] = 1;
                        }
                    }
        }
    }
    uint64_t *which = malloc(N * sizeof(uint64_t));
    uint64_t m = 0;
    for (uint64_t i = 0; i < N; ++i)
        if (i < D || hit[i]) which[m++] = i;
    *count = m;
    free(start), free(order), free(hit), free(key), free(fill), free(c), free(v);
    return which;
}

int main(int argc, char **argv) {
    options o = {.mode = "events", .commit = "unknown", .n = 0, .dynamic = 50000, .threads = 1, .ticks = 5, .rounds = 3};
    for (int i = 1; i + 1 < argc; i += 2) {
        const char *a = argv[i], *v = argv[i + 1];
        if (!strcmp(a, "--mode")) o.mode = v;
        else if (!strcmp(a, "--n")) o.n = strtoull(v, NULL, 10);
        else if (!strcmp(a, "--dynamic")) o.dynamic = strtoull(v, NULL, 10);
        else if (!strcmp(a, "--threads")) o.threads = (unsigned)strtoul(v, NULL, 10);
        else if (!strcmp(a, "--ticks")) o.ticks = atoi(v);
        else if (!strcmp(a, "--rounds")) o.rounds = atoi(v);
        else if (!strcmp(a, "--commit")) o.commit = v;
        else if (!strcmp(a, "--engine")) o.engine = atoi(v);
        else if (!strcmp(a, "--per-tick")) o.per_tick = atoi(v);
        else {
            fprintf(stderr, "usage: %s --mode static|mask|events [--n N] [--dynamic D] [--threads K] [--ticks T] "
                            "[--rounds R] [--commit HASH] [--engine 0|1] [--per-tick 0|1]\n", argv[0]);
            return 2;
        }
    }
    const int is_static = !strcmp(o.mode, "static"), is_mask = !strcmp(o.mode, "mask");
    if (!o.n) o.n = is_static ? 1000000 : 750000;
    const uint64_t total = is_static ? o.n + o.dynamic : o.n;
    scene s;
    if (scene_make(&s, total, 200)) return 1;
    const size_t T = (size_t)o.ticks * (size_t)o.rounds;
    samples A = {calloc(T, 8), calloc(T, 8), calloc(T, 8), calloc(T, 8), calloc(T, 8), {0}};
    samples B = {calloc(T, 8), calloc(T, 8), calloc(T, 8), calloc(T, 8), calloc(T, 8), {0}};
    int at_a = 0, at_b = 0;
    uint64_t *which_b = NULL, count_b = total;
    int32_t *type_a = NULL, *type_b = NULL;
    hgcd_filter *filter_b = NULL;
    if (is_static) {
        which_b = reachable(&o, &s, &count_b);
        type_a = malloc(total * sizeof(int32_t));
        type_b = malloc(count_b * sizeof(int32_t));
        for (uint64_t i = 0; i < total; ++i) type_a[i] = i < o.dynamic ? HGCD_BODY_DYNAMIC : HGCD_BODY_STATIC;
        for (uint64_t k = 0; k < count_b; ++k) type_b[k] = which_b[k] < o.dynamic ? HGCD_BODY_DYNAMIC : HGCD_BODY_STATIC;
    } else if (is_mask) {
        filter_b = malloc(total * sizeof(hgcd_filter));
        for (uint64_t i = 0; i < total; ++i) {
            filter_b[i] = hgcd_filter_default();
            filter_b[i].category_bits = filter_b[i].mask_bits = (uint64_t)1 << (i % 10);
        }
    }
    uint64_t **pairs_a = calloc((size_t)o.ticks, sizeof(uint64_t *)), **pairs_b = calloc((size_t)o.ticks, sizeof(uint64_t *));
    size_t *na = calloc((size_t)o.ticks, sizeof(size_t)), *nb = calloc((size_t)o.ticks, sizeof(size_t));
    int same = 1;
    for (int r = 0; r < o.rounds; ++r) {
        hgcd_world *w = make_world(&o, &s, NULL, total, type_a, NULL);
        if (!w || run(w, &o, &s, &A, &at_a, NULL, is_static ? pairs_a : NULL, na)) return 1;
        hgcd_world_destroy(w);
        if (!strcmp(o.mode, "events")) continue;
        w = make_world(&o, &s, which_b, count_b, type_b, filter_b);
        if (!w || run(w, &o, &s, &B, &at_b, which_b, is_static ? pairs_b : NULL, nb)) return 1;
        hgcd_world_destroy(w);
        for (int k = 0; is_static && k < o.ticks; ++k) {
            qsort(pairs_b[k], nb[k], sizeof(uint64_t), cmp_u64);
            same = same && na[k] == nb[k] && !memcmp(pairs_a[k], pairs_b[k], na[k] * sizeof(uint64_t));
        }
    }
    const int nt = (int)T;
    double ev[4096];
    for (int k = 0; k < nt && k < 4096; ++k) ev[k] = A.events[k] / A.total[k];
    const double a_total = median(A.total, nt), a_narrow = median(A.narrow, nt), a_broad = median(A.broad, nt);
    printf("{\"bench\":\"features\",\"mode\":\"%s\",\"commit\":\"%s\",\"n\":%llu,\"threads\":%u,\"ticks\":%d,"
           "\"rounds\":%d,\"engine\":%d,\"a_tick_ms\":%.3f,\"a_broad_ms\":%.3f,\"a_narrow_ms\":%.3f,\"a_candidates\":%llu,"
           "\"a_filtered\":%llu,\"a_narrow_tests\":%llu,\"a_pairs\":%llu",
           o.mode, o.commit, (unsigned long long)total, o.threads, o.ticks, o.rounds, o.engine, a_total, a_broad, a_narrow,
           (unsigned long long)A.last.candidate_pairs, (unsigned long long)A.last.filtered_pairs,
           (unsigned long long)A.last.narrow_tests, (unsigned long long)A.last.colliding_pairs);
    if (!strcmp(o.mode, "events")) {
        printf(",\"events_ms\":%.3f,\"events_share\":%.4f}\n", median(A.events, nt), median(ev, nt < 4096 ? nt : 4096));
        return 0;
    }
    const double a_cpu = median(A.cpu, nt), b_cpu = median(B.cpu, nt);
    const double b_total = median(B.total, nt), b_narrow = median(B.narrow, nt), b_broad = median(B.broad, nt);
    printf(",\"b_bodies\":%llu,\"b_tick_ms\":%.3f,\"b_broad_ms\":%.3f,\"b_narrow_ms\":%.3f,\"b_candidates\":%llu,"
           "\"b_filtered\":%llu,\"b_narrow_tests\":%llu,\"b_pairs\":%llu,\"tick_ratio_a_over_b\":%.3f,"
           "\"narrow_ratio_b_over_a\":%.3f,\"broad_plus_narrow_ratio_b_over_a\":%.3f",
           (unsigned long long)count_b, b_total, b_broad, b_narrow, (unsigned long long)B.last.candidate_pairs,
           (unsigned long long)B.last.filtered_pairs, (unsigned long long)B.last.narrow_tests,
           (unsigned long long)B.last.colliding_pairs, a_total / b_total, b_narrow / a_narrow,
           (b_broad + b_narrow) / (a_broad + a_narrow));
    printf(",\"a_tick_cpu_ms\":%.3f,\"b_tick_cpu_ms\":%.3f,\"cpu_ratio_a_over_b\":%.3f", a_cpu, b_cpu, a_cpu / b_cpu);
    if (is_static) printf(",\"same_pairs\":%s", same ? "true" : "false");
    printf("}\n");
    return is_static && !same;
}
