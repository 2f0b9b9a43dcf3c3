/* bench_hgcd: scene `tetra` (docs/scenes.md) through the public C API of hgcd.
 *
 *   bench_hgcd [--n N] [--seed S] [--threads K] [--ticks T] [--commit HASH]
 *              [--lib NAME] [--min-cell-size W] [--side L] [--check]
 *              [--mode step|engine-batch|engine-single] [--mesh-per-body]
 *              [--turn A] [--moving-fraction F] [--per-tick]
 *              [--thread-policy adaptive|fixed] [--tasks] [--margin M]
 *
 * --margin sets hgcd_world_desc.contact_margin (default 0; the JSON's
 * "margin"): every pair takes the exact margin path of the narrow phase.
 * --thread-policy sets the world's hgcd_world_desc.thread_policy (default
 * adaptive, the library's default: fewer threads while the cores are busy
 * with other work; fixed: always --threads).
 * --tasks runs hgcd's parallel loops on a small job system of the caller's
 * (bench/jobs.h: --threads workers, the calling thread one of them) through
 * hgcd_world_desc.enqueue_task instead of OpenMP; --threads must then be
 * at least 1. The JSON's "tasks" field says which.
 * --lib sets the JSON's "lib" field (default hgcd; make bench's 100-tick
 * runs are hgcd-long).
 * --min-cell-size sets the world descriptor's min_cell_size (default 0: the
 * grid adapts to the body sizes, levels a factor 2 apart). --side sets the
 * scene's cube side L (default 200; the reference counts of docs/scenes.md hold for
 * the default only).
 *
 * Generates the scene with hgcd_scene_tetra_generate, creates the N bodies on
 * the shared unit mesh (hgcd_scene_tetra_unit_mesh, body scale = generated
 * scale; --mesh-per-body: each body on its own copy of that mesh, so the
 * world holds N meshes) in a world that reflects at the cube [0, side]^3
 * (which is exactly the motion of docs/scenes.md), runs one initial
 * hgcd_world_detect and then T ticks.
 *
 * --mode step (default): each tick is one hgcd_world_step (the library moves
 * the bodies). The engine modes do what a physics engine does: the caller
 * moves its own centres (hgcd_scene_tetra_move, the same motion) and turns
 * each body by its own fixed rotation, then hands the poses over --
 * engine-batch: one hgcd_world_set_poses (bodies NULL, packed arrays);
 * engine-single: one hgcd_body_set_pose per body -- and calls
 * hgcd_world_detect. --turn A (default 0.01): each body's orientation q
 * becomes q * r, r the rotation by 2 atan(A / 2) (about A radians) about the
 * body's initial velocity direction, then q is normalised; --turn 0 hands the
 * unchanged orientations over (the same bits every tick), so that
 * set_poses's path for an unchanged orientation is measured, and the pairs
 * equal step mode's at every tick count. --moving-fraction F (default 1,
 * engine modes): only the bodies whose index hashes below F (splitmix64 of
 * the index, over 2^64) move and turn; the others rest bit for bit where
 * they are (their poses are handed over all the same), as in a pile where
 * some bodies settle: F = 0.1 measures the detect where one body in ten
 * moves, F = 0 the detect where none does.
 *
 * Prints ONE JSON line on stdout:
 *
 *   lib, scene, n, seed, threads, ticks, commit, mode,
 *   thread_policy, threads_used_mean   the policy, and the mean over the
 *                     ticks of the threads each tick's detect ran on
 *                     (hgcd_stats.thread_count; threads: the initial
 *                     detect's, all of them);
 *   broad_ms, narrow_ms, update_ms, motion_ms, tick_ms  medians over the ticks
 *       of the library's own per-phase timers (hgcd_world_stats);
 *   wall_ms           median wall-clock time of hgcd's part of a tick seen
 *                     here: hgcd_world_step, or set poses + detect;
 *   tick_mean_ms, tick_max_ms, update_mean_ms, broad_mean_ms, narrow_mean_ms
 *                     means (and the largest tick) over the ticks: ticks that
 *                     renumber the bodies' storage cost more than the others;
 *   candidate_pairs, narrow_tests, colliding_pairs, containment_pairs,
 *   triangle_tests, moved_bodies   of the last tick (moved_bodies: bodies
 *                     that changed row or level in the grid's update);
 *   pairs_fnv         FNV-1a (64-bit, hex) of the last tick's pairs, indices
 *                     in order: equal when two builds report the same pairs;
 *   initial_pairs, initial_containment, initial_ms   of the initial detect;
 *   setup_ms          world creation and the meshes and bodies (with the
 *                     scene drawn by hgcd_scene_tetra_populate; in the engine
 *                     modes and with --mesh-per-body the scene is drawn
 *                     beforehand into the caller's arrays, not counted);
 *   peak_rss_mb       getrusage ru_maxrss at the end;
 *   bytes_per_body    growth of the peak RSS from just before world creation
 *                     to after the ticks, divided by n;
 *   reference_ok      with --check: whether the initial detect matches the
 *                     reference counts of docs/scenes.md (pairs and containment;
 *                     null when docs/scenes.md has no row for this n and seed);
 *   mesh_per_body     true or false (in step mode only when true);
 *   engine modes only: turn (A), moving_fraction (F) and moving_bodies,
 *                     set_poses_ms, detect_ms, caller_ms  medians of the
 *                     wall-clock time of handing the poses over, of
 *                     hgcd_world_detect, and of the caller's own motion and
 *                     turning (not hgcd's work); set_poses_cpu_ms,
 *                     detect_cpu_ms  medians of the process's CPU time
 *                     (all threads) in those calls: on 1 thread, the
 *                     figure to compare on a machine busy with other work;
 *                     searched_bodies and unmoved_pairs of the last tick
 *                     (hgcd_stats);
 *   step mode only:   tick_cpu_ms  median of the process's CPU time in
 *                     hgcd_world_step.
 *
 * --per-tick prints each tick's times and pairs_fnv to stderr. Diagnostics go
 * to stderr. Exit status: 0 when the JSON line was printed (even with
 * reference_ok false: the caller reads the JSON), 1 on an API failure, 2 on a
 * usage error.
 */
#define _POSIX_C_SOURCE 200809L
#include <hgcd/hgcd.h>
#include <hgcd/hgcd_scene.h>

#include "jobs.h"
#include "turn.h"

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

/* CPU time of the process (all its threads), for machines shared with
 * other work: on 1 thread it counts this run's work alone. */
static double cpu_seconds(void) {
    struct timespec ts;
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
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

/* Median of v[0..count) (sorts v); 0 for an empty array. */
static double median(double *v, int count) {
    if (count <= 0) return 0.0;
    qsort(v, (size_t)count, sizeof *v, cmp_double);
    return count % 2 ? v[count / 2] : 0.5 * (v[count / 2 - 1] + v[count / 2]);
}

/* Square root by Newton's method from above (the benchmark links no libm):
 * the iterates decrease until they stop changing. */
static double square_root(double x) {
    if (!(x > 0)) return 0.0;
    double y = x > 1 ? x : 1;
    for (;;) {
        const double next = 0.5 * (y + x / y);
        if (!(next < y)) return y;
        y = next;
    }
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
            "          [--mode step|engine-batch|engine-single] [--mesh-per-body] [--turn A] [--moving-fraction F]\n"
            "          [--thread-policy adaptive|fixed] [--tasks]\n"
            "  --threads 0 = all cores; --check compares the initial detect with docs/scenes.md\n",
            argv0);
}

/* Reference answers of docs/scenes.md (seed 1, default scene parameters). */
static const struct {
    uint64_t n, pairs, containment;
} reference[] = {{100000, 4266, 30}, {200000, 17201, 151}, {500000, 106075, 926}, {750000, 237561, 2155}};

/* How a tick hands the motion to hgcd. */
enum mode { MODE_STEP, MODE_ENGINE_BATCH, MODE_ENGINE_SINGLE };
static const char *const mode_names[] = {"step", "engine-batch", "engine-single"};

typedef struct options {
    uint64_t n, seed;
    unsigned threads;
    int ticks, check, per_tick, mesh_per_body, fixed_threads, tasks;
    enum mode mode;
    const char *commit, *lib;
    double min_cell, side, turn, moving_fraction, margin;
} options;

/* 0 on success, 2 on a usage error (printed). */
static int parse_options(int argc, char **argv, options *o) {
    *o = (options){.n = 100000, .seed = 1, .threads = 1, .ticks = 5, .mode = MODE_STEP,
                   .commit = "unknown", .lib = "hgcd", .turn = 0.01, .moving_fraction = 1};
    for (int i = 1; i < argc; ++i) {
        const char *a = argv[i];
        if (!strcmp(a, "--per-tick")) {
            o->per_tick = 1;
            continue;
        }
        if (!strcmp(a, "--check")) {
            o->check = 1;
            continue;
        }
        if (!strcmp(a, "--mesh-per-body")) {
            o->mesh_per_body = 1;
            continue;
        }
        if (!strcmp(a, "--tasks")) {
            o->tasks = 1;
            continue;
        }
        if (i + 1 >= argc) {
            usage(argv[0]);
            return 2;
        }
        const char *v = argv[++i];
        if (!strcmp(a, "--n")) o->n = strtoull(v, NULL, 10);
        else if (!strcmp(a, "--seed")) o->seed = strtoull(v, NULL, 10);
        else if (!strcmp(a, "--threads")) o->threads = (unsigned)strtoul(v, NULL, 10);
        else if (!strcmp(a, "--ticks")) o->ticks = atoi(v);
        else if (!strcmp(a, "--commit")) o->commit = v;
        else if (!strcmp(a, "--lib")) o->lib = v;
        else if (!strcmp(a, "--min-cell-size")) o->min_cell = strtod(v, NULL);
        else if (!strcmp(a, "--margin")) o->margin = strtod(v, NULL);
        else if (!strcmp(a, "--side")) o->side = strtod(v, NULL);
        else if (!strcmp(a, "--turn")) o->turn = strtod(v, NULL);
        else if (!strcmp(a, "--moving-fraction")) o->moving_fraction = strtod(v, NULL);
        else if (!strcmp(a, "--thread-policy") && (!strcmp(v, "adaptive") || !strcmp(v, "fixed")))
            o->fixed_threads = !strcmp(v, "fixed");
        else if (!strcmp(a, "--mode")) {
            int found = 0;
            for (int m = 0; m < 3; ++m)
                if (!strcmp(v, mode_names[m])) {
                    o->mode = (enum mode)m;
                    found = 1;
                }
            if (!found) {
                usage(argv[0]);
                return 2;
            }
        } else {
            usage(argv[0]);
            return 2;
        }
    }
    if (o->tasks && (o->threads < 1 || o->threads > JOBS_MAX_WORKERS)) {
        fprintf(stderr, "bench_hgcd: --tasks needs 1 <= --threads <= %d\n", JOBS_MAX_WORKERS);
        return 2;
    }
    if (o->n == 0 || o->ticks < 1 || !(o->turn >= 0 && o->turn <= 1) ||
        !(o->moving_fraction >= 0 && o->moving_fraction <= 1)) {
        fprintf(stderr, "bench_hgcd: need n >= 1, ticks >= 1, 0 <= turn <= 1 and 0 <= moving fraction <= 1\n");
        return 2;
    }
    if (o->mode == MODE_STEP && o->moving_fraction < 1) {
        fprintf(stderr, "bench_hgcd: --moving-fraction is for the engine modes\n");
        return 2;
    }
    return 0;
}

/* What the caller of an engine mode keeps of its bodies: the scene's arrays
 * (n entries each), the body ids, each body's rotation per tick, and
 * whether it moves (--moving-fraction). */
typedef struct caller_state {
    double *centers, *scales, *orientations, *velocities, *turns;
    hgcd_body *bodies;
    unsigned char *moving;
    uint64_t moving_count;
} caller_state;

static void caller_free(caller_state *c) {
    free(c->centers);
    free(c->scales);
    free(c->orientations);
    free(c->velocities);
    free(c->turns);
    free(c->bodies);
    free(c->moving);
}

/* The rotation per tick of each body: the quaternion (h u, 1) normalised, u
 * the unit initial velocity (the z axis for a body at rest), h = turn / 2. */
static void make_turns(uint64_t n, double turn, const double *velocities, double *turns) {
    const double h = 0.5 * turn;
    for (uint64_t i = 0; i < n; ++i) {
        const double *v = velocities + 3 * i;
        const double speed = square_root((v[0] * v[0] + v[1] * v[1]) + v[2] * v[2]);
        double axis[3] = {0, 0, 1};
        if (speed > 0)
            for (int k = 0; k < 3; ++k) axis[k] = v[k] / speed;
        const double norm = square_root(1 + h * h);
        for (int k = 0; k < 3; ++k) turns[4 * i + k] = h * axis[k] / norm;
        turns[4 * i + 3] = 1 / norm;
    }
}

/* q = q * r for each moving body (turn.h). */
static void turn_bodies(uint64_t n, double *orientations, const double *turns, const unsigned char *moving) {
    for (uint64_t i = 0; i < n; ++i) {
        if (!moving[i]) continue;
        turn_orientation(orientations + 4 * i, turns + 4 * i);
    }
}

/* Draws the scene into the caller's arrays (ids and turns allocated, filled
 * later). 1 on failure (printed). */
static int caller_init(const options *o, const hgcd_scene_tetra_desc *sd, caller_state *c) {
    const size_t n = (size_t)o->n;
    c->centers = malloc(n * 3 * sizeof(double));
    c->scales = malloc(n * sizeof(double));
    c->orientations = malloc(n * 4 * sizeof(double));
    c->velocities = malloc(n * 3 * sizeof(double));
    c->turns = malloc(n * 4 * sizeof(double));
    c->bodies = malloc(n * sizeof(hgcd_body));
    c->moving = malloc(n);
    if (!c->centers || !c->scales || !c->orientations || !c->velocities || !c->turns || !c->bodies || !c->moving) {
        fprintf(stderr, "bench_hgcd: out of memory for n = %llu\n", (unsigned long long)o->n);
        return 1;
    }
    if (failed(hgcd_scene_tetra_generate(sd, c->centers, NULL, c->scales, c->orientations, c->velocities), NULL,
               "scene_tetra_generate"))
        return 1;
    make_turns(o->n, o->turn, c->velocities, c->turns);
    /* The resting bodies: velocity 0, so the caller's motion keeps their
     * centres' bits (c + 0 = c), and no turn. */
    for (uint64_t i = 0; i < o->n; ++i) {
        uint64_t z = (i + 1) * 0x9E3779B97F4A7C15ull;
        z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
        z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
        z ^= z >> 31;
        c->moving[i] = o->moving_fraction >= 1 || (double)(z >> 11) * 0x1.0p-53 < o->moving_fraction;
        c->moving_count += c->moving[i];
        if (!c->moving[i]) memset(c->velocities + 3 * i, 0, 3 * sizeof(double));
    }
    return 0;
}

/* Creates body i (for each i in order, so it gets index i) as
 * hgcd_scene_tetra_populate does, on the shared mesh or on its own copy of
 * the unit tetrahedron. */
static int create_bodies(hgcd_world *w, const options *o, const caller_state *c) {
    double vertices[12];
    uint32_t triangles[12];
    hgcd_scene_tetra_unit_mesh(vertices, triangles);
    hgcd_mesh_desc md = hgcd_mesh_desc_default();
    md.vertices = vertices;
    md.triangles = triangles;
    md.vertex_count = 4;
    md.triangle_count = 4;
    hgcd_body_desc bd = hgcd_body_desc_default();
    for (uint64_t i = 0; i < o->n; ++i) {
        if ((i == 0 || o->mesh_per_body) && failed(hgcd_mesh_create(w, &md, &bd.mesh), w, "mesh_create")) return 1;
        memcpy(bd.position, c->centers + 3 * i, sizeof bd.position);
        memcpy(bd.orientation, c->orientations + 4 * i, sizeof bd.orientation);
        memcpy(bd.velocity, c->velocities + 3 * i, sizeof bd.velocity);
        bd.scale = c->scales[i];
        bd.user_data = i;
        if (failed(hgcd_body_create(w, &bd, &c->bodies[i]), w, "body_create")) return 1;
    }
    return 0;
}

/* Per-tick samples in ms, each an array of `ticks` entries. */
enum sample {
    S_TOTAL, S_BROAD, S_NARROW, S_UPDATE, S_MOTION, S_WALL, S_SET_POSES, S_DETECT, S_CALLER, S_SET_POSES_CPU,
    S_DETECT_CPU, S_THREADS, S_COUNT
};

/* FNV-1a over the pairs of the last step/detect (indices, in order): two
 * builds that report the same pairs print the same value. */
static int pairs_hash(const hgcd_world *w, uint64_t *out) {
    uint64_t hash = 14695981039346656037ull;
    const hgcd_pair *pairs = NULL;
    size_t count = 0;
    if (failed(hgcd_world_pairs(w, &pairs, &count), w, "world_pairs")) return 1;
    for (size_t k = 0; k < count; ++k) {
        const uint32_t ab[2] = {pairs[k].a.index, pairs[k].b.index};
        const unsigned char *byte = (const unsigned char *)ab;
        for (size_t i = 0; i < sizeof ab; ++i) hash = (hash ^ byte[i]) * 1099511628211ull;
    }
    *out = hash;
    return 0;
}

/* One tick of an engine: the caller's motion and turning, the poses handed
 * over, the detect; times into s[*][k]. */
static int engine_tick(hgcd_world *w, const options *o, caller_state *c, double *s[S_COUNT], int k) {
    const double side = o->side > 0 ? o->side : hgcd_scene_tetra_desc_default().side;
    double t0 = now_seconds();
    hgcd_scene_tetra_move(o->n, side, c->centers, c->velocities);
    if (o->turn > 0) turn_bodies(o->n, c->orientations, c->turns, c->moving);
    const double t1 = now_seconds(), c1 = cpu_seconds();
    if (o->mode == MODE_ENGINE_BATCH) {
        if (failed(hgcd_world_set_poses(w, NULL, (size_t)o->n, c->centers, 0, c->orientations, 0), w,
                   "world_set_poses"))
            return 1;
    } else {
        for (uint64_t i = 0; i < o->n; ++i)
            if (failed(hgcd_body_set_pose(w, c->bodies[i], c->centers + 3 * i, c->orientations + 4 * i), w,
                       "body_set_pose"))
                return 1;
    }
    const double t2 = now_seconds(), c2 = cpu_seconds();
    if (failed(hgcd_world_detect(w), w, "world_detect")) return 1;
    const double t3 = now_seconds(), c3 = cpu_seconds();
    s[S_SET_POSES_CPU][k] = 1e3 * (c2 - c1);
    s[S_DETECT_CPU][k] = 1e3 * (c3 - c2);
    s[S_CALLER][k] = 1e3 * (t1 - t0);
    s[S_SET_POSES][k] = 1e3 * (t2 - t1);
    s[S_DETECT][k] = 1e3 * (t3 - t2);
    s[S_WALL][k] = 1e3 * (t3 - t1);
    return 0;
}

/* The T ticks; the last tick's statistics stay in *st. */
static int run_ticks(hgcd_world *w, const options *o, caller_state *c, double *s[S_COUNT], hgcd_stats *st) {
    for (int k = 0; k < o->ticks; ++k) {
        if (o->mode == MODE_STEP) {
            const double t0 = now_seconds(), c0 = cpu_seconds();
            if (failed(hgcd_world_step(w), w, "world_step")) return 1;
            s[S_WALL][k] = 1e3 * (now_seconds() - t0);
            s[S_DETECT_CPU][k] = 1e3 * (cpu_seconds() - c0);
        } else if (engine_tick(w, o, c, s, k)) {
            return 1;
        }
        memset(st, 0, sizeof *st);
        st->struct_size = sizeof *st;
        if (failed(hgcd_world_stats(w, st), w, "world_stats")) return 1;
        s[S_TOTAL][k] = 1e3 * st->total_seconds;
        s[S_BROAD][k] = 1e3 * st->broad_seconds;
        s[S_NARROW][k] = 1e3 * st->narrow_seconds;
        s[S_UPDATE][k] = 1e3 * st->update_seconds;
        s[S_MOTION][k] = 1e3 * st->motion_seconds;
        s[S_THREADS][k] = st->thread_count;
        if (o->per_tick) {
            uint64_t hash = 0;
            if (pairs_hash(w, &hash)) return 1;
            fprintf(stderr, "tick %d: %.1f ms (motion %.1f, update %.1f, broad %.1f, narrow %.1f)", k + 1,
                    s[S_TOTAL][k], s[S_MOTION][k], s[S_UPDATE][k], s[S_BROAD][k], s[S_NARROW][k]);
            if (o->mode != MODE_STEP)
                fprintf(stderr, " caller %.1f, set_poses %.1f, detect %.1f", s[S_CALLER][k], s[S_SET_POSES][k],
                        s[S_DETECT][k]);
            fprintf(stderr, ", %llu pairs, pairs_fnv %016llx\n", (unsigned long long)st->colliding_pairs,
                    (unsigned long long)hash);
        }
    }
    return 0;
}

/* With --check: compares the initial detect with docs/scenes.md. Returns
 * "true", "false" or "null"; *reference_pairs is 0 when there is no row. */
static const char *check_reference(const options *o, const hgcd_stats *initial, uint64_t *reference_pairs) {
    *reference_pairs = 0;
    if (!o->check) return "null";
    for (size_t k = 0; k < sizeof reference / sizeof reference[0]; ++k) {
        if (o->seed != 1 || o->side != 0 || o->n != reference[k].n) continue;
        *reference_pairs = reference[k].pairs;
        const int ok =
            initial->colliding_pairs == reference[k].pairs && initial->containment_pairs == reference[k].containment;
        if (!ok)
            fprintf(stderr,
                    "bench_hgcd: n = %llu: initial detect gave %llu pairs (%llu by containment), "
                    "docs/scenes.md says %llu (%llu)\n",
                    (unsigned long long)o->n, (unsigned long long)initial->colliding_pairs,
                    (unsigned long long)initial->containment_pairs, (unsigned long long)reference[k].pairs,
                    (unsigned long long)reference[k].containment);
        return ok ? "true" : "false";
    }
    return "null";
}

/* What main measured, for the JSON line. */
typedef struct results {
    hgcd_stats last, initial;
    double initial_ms, setup_ms, rss_before, rss_after;
    uint64_t pairs_fnv, moving_bodies;
} results;

static void print_json(const options *o, const results *r, double *s[S_COUNT]) {
    const hgcd_stats *st = &r->last;
    const int ticks = o->ticks;
    uint64_t reference_pairs = 0;
    const char *reference_ok = check_reference(o, &r->initial, &reference_pairs);
    /* The means first: median() sorts its array. */
    const double tick_mean = mean(s[S_TOTAL], ticks), tick_max = maximum(s[S_TOTAL], ticks);
    const double update_mean = mean(s[S_UPDATE], ticks), broad_mean = mean(s[S_BROAD], ticks);
    const double narrow_mean = mean(s[S_NARROW], ticks), threads_used = mean(s[S_THREADS], ticks);
    printf("{\"lib\":\"%s\",\"scene\":\"tetra\",\"n\":%llu,\"seed\":%llu,\"threads\":%u,\"ticks\":%d,"
           "\"commit\":\"%s\",\"version\":\"%s\",\"mode\":\"%s\",\"thread_policy\":\"%s\",\"tasks\":%s,\"threads_used_mean\":%.2f,\"bounding_volume\":\"box\",\"min_cell_size\":%g,\"margin\":%g,"
           "\"broad_ms\":%.3f,\"narrow_ms\":%.3f,\"update_ms\":%.3f,\"motion_ms\":%.3f,\"tick_ms\":%.3f,"
           "\"wall_ms\":%.3f,\"candidate_pairs\":%llu,\"narrow_tests\":%llu,\"colliding_pairs\":%llu,"
           "\"containment_pairs\":%llu,\"triangle_tests\":%llu,\"moved_bodies\":%llu,\"pairs_fnv\":\"%016llx\","
           "\"initial_pairs\":%llu,\"initial_containment\":%llu,"
           "\"initial_ms\":%.3f,\"setup_ms\":%.3f,\"levels\":%u,\"oversize\":%u,"
           "\"peak_rss_mb\":%.1f,\"bytes_per_body\":%.1f,"
           "\"tick_mean_ms\":%.3f,\"tick_max_ms\":%.3f,\"update_mean_ms\":%.3f,\"broad_mean_ms\":%.3f,"
           "\"narrow_mean_ms\":%.3f,",
           o->lib, (unsigned long long)o->n, (unsigned long long)o->seed, r->initial.thread_count, ticks, o->commit,
           hgcd_version_string(), mode_names[o->mode], o->fixed_threads ? "fixed" : "adaptive", o->tasks ? "true" : "false", threads_used,
           o->min_cell, o->margin, median(s[S_BROAD], ticks),
           median(s[S_NARROW], ticks), median(s[S_UPDATE], ticks), median(s[S_MOTION], ticks),
           median(s[S_TOTAL], ticks), median(s[S_WALL], ticks), (unsigned long long)st->candidate_pairs,
           (unsigned long long)st->narrow_tests, (unsigned long long)st->colliding_pairs,
           (unsigned long long)st->containment_pairs, (unsigned long long)st->triangle_tests,
           (unsigned long long)st->moved_bodies, (unsigned long long)r->pairs_fnv,
           (unsigned long long)r->initial.colliding_pairs, (unsigned long long)r->initial.containment_pairs,
           r->initial_ms, r->setup_ms, st->level_count, st->oversize_count, r->rss_after / (1024.0 * 1024.0),
           (r->rss_after - r->rss_before) / (double)o->n, tick_mean, tick_max, update_mean, broad_mean,
           narrow_mean);
    if (o->mode == MODE_STEP) printf("\"tick_cpu_ms\":%.3f,", median(s[S_DETECT_CPU], ticks));
    if (o->mode != MODE_STEP || o->mesh_per_body)
        printf("\"mesh_per_body\":%s,", o->mesh_per_body ? "true" : "false");
    if (o->mode != MODE_STEP)
        printf("\"turn\":%g,\"moving_fraction\":%g,\"moving_bodies\":%llu,\"set_poses_ms\":%.3f,\"detect_ms\":%.3f,"
               "\"caller_ms\":%.3f,\"set_poses_cpu_ms\":%.3f,\"detect_cpu_ms\":%.3f,\"searched_bodies\":%llu,"
               "\"unmoved_pairs\":%llu,",
               o->turn, o->moving_fraction, (unsigned long long)r->moving_bodies, median(s[S_SET_POSES], ticks),
               median(s[S_DETECT], ticks), median(s[S_CALLER], ticks), median(s[S_SET_POSES_CPU], ticks),
               median(s[S_DETECT_CPU], ticks), (unsigned long long)st->searched_bodies,
               (unsigned long long)st->unmoved_pairs);
    if (reference_pairs) printf("\"reference_pairs\":%llu,", (unsigned long long)reference_pairs);
    printf("\"reference_ok\":%s}\n", reference_ok);
    fflush(stdout);
}

/* The world reflecting at the scene's cube, with the scene's bodies. */
static int make_world(const options *o, const hgcd_scene_tetra_desc *sd, const caller_state *c,
                      hgcd_world **out) {
    hgcd_world_desc wd = hgcd_world_desc_default();
    wd.thread_count = o->threads;
    wd.thread_policy = o->fixed_threads ? HGCD_THREADS_FIXED : HGCD_THREADS_ADAPTIVE;
    if (o->tasks) {
        static jobs job_system;
        if (jobs_start(&job_system, o->threads)) {
            fprintf(stderr, "bench_hgcd: cannot start the job system's threads\n");
            return 1;
        }
        wd.enqueue_task = jobs_enqueue;
        wd.finish_task = jobs_finish;
        wd.task_context = &job_system;
    }
    wd.reflect_at_bounds = 1;
    wd.min_cell_size = o->min_cell;
    wd.contact_margin = o->margin;
    for (int k = 0; k < 3; ++k) {
        wd.bounds_min[k] = 0.0;
        wd.bounds_max[k] = sd->side;
    }
    if (failed(hgcd_world_create(&wd, out), NULL, "world_create")) return 1;
    if (c->centers) return create_bodies(*out, o, c);
    return failed(hgcd_scene_tetra_populate(*out, sd, NULL), *out, "scene_tetra_populate");
}

int main(int argc, char **argv) {
    options o;
    const int usage_status = parse_options(argc, argv, &o);
    if (usage_status) return usage_status;

    /* The scene, bit for bit as docs/scenes.md defines it. */
    hgcd_scene_tetra_desc sd = hgcd_scene_tetra_desc_default();
    sd.n = o.n;
    sd.seed = o.seed;
    if (o.side > 0) sd.side = o.side;
    double *samples = malloc((size_t)S_COUNT * (size_t)o.ticks * sizeof(double)), *s[S_COUNT];
    if (!samples) {
        fprintf(stderr, "bench_hgcd: out of memory for %d ticks\n", o.ticks);
        return 1;
    }
    memset(samples, 0, (size_t)S_COUNT * (size_t)o.ticks * sizeof(double));
    for (int k = 0; k < S_COUNT; ++k) s[k] = samples + (size_t)k * (size_t)o.ticks;
    /* An engine keeps the scene in its own arrays (drawn before the RSS
     * baseline: they are the caller's memory, not hgcd's); step mode with the
     * shared mesh lets hgcd_scene_tetra_populate make the bodies. */
    caller_state c;
    memset(&c, 0, sizeof c);
    if ((o.mode != MODE_STEP || o.mesh_per_body) && caller_init(&o, &sd, &c)) return 1;

    results r;
    memset(&r, 0, sizeof r);
    r.rss_before = peak_rss_bytes();
    double t0 = now_seconds();
    hgcd_world *w = NULL;
    if (make_world(&o, &sd, &c, &w)) return 1;
    r.setup_ms = 1e3 * (now_seconds() - t0);

    r.initial.struct_size = sizeof r.initial;
    t0 = now_seconds();
    if (failed(hgcd_world_detect(w), w, "world_detect")) return 1;
    r.initial_ms = 1e3 * (now_seconds() - t0);
    if (failed(hgcd_world_stats(w, &r.initial), w, "world_stats")) return 1;

    if (run_ticks(w, &o, &c, s, &r.last)) return 1;
    r.rss_after = peak_rss_bytes();
    if (pairs_hash(w, &r.pairs_fnv)) return 1;
    r.moving_bodies = c.moving_count;
    print_json(&o, &r, s);

    hgcd_world_destroy(w);
    caller_free(&c);
    free(samples);
    return 0;
}
