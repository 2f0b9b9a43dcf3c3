/* bench_pose: the cost of one hgcd_body_set_pose call, as an engine's loop
 * pays it, on small meshes: a box (12 triangles, 8 vertices) and a
 * tetrahedron (4 triangles).
 *
 *   bench_pose [--bodies N] [--rounds R] [--commit HASH]
 *
 * A world of N bodies (default 7200, scattered in a cube, created in index
 * order) per mesh; each round sets every body's pose once, in index order,
 * in one of four ways: the same position and orientation bits as before
 * (nothing changes), a new position with the same orientation, a new
 * position alone (orientation NULL), and a new position with a new
 * orientation (each body turned a little every round). A detect runs
 * between rounds, as in an engine's tick (not timed). Prints one JSON line
 * per mesh and way: ns_per_call, the median over R rounds (default 31) of
 * the round's time divided by N, and cpu_ns_per_call, the same of the
 * thread's CPU time (the figure to read on a busy machine). Exit status: 0, 1 on an API failure, 2 on
 * a usage error.
 */
#define _POSIX_C_SOURCE 200809L
#include <hgcd/hgcd.h>

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

static double now_seconds(void) {
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

/* The calling thread's CPU time: on a machine busy with other work the
 * wall-clock time of a round counts the time the thread was not running. */
static double thread_cpu_seconds(void) {
    struct timespec ts;
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

static int cmp_double(const void *a, const void *b) {
    const double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

static int failed(hgcd_status s, const hgcd_world *w, const char *what) {
    if (s == HGCD_OK) return 0;
    fprintf(stderr, "bench_pose: %s failed: %s (%s)\n", what, hgcd_status_string(s), w ? hgcd_world_last_error(w) : "");
    return 1;
}

static uint64_t rng_state = 1;
static double unif(void) {
    uint64_t z = (rng_state += 0x9E3779B97F4A7C15ull);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return (double)((z ^ (z >> 31)) >> 11) * 0x1.0p-53;
}

static const double kBoxV[24] = {-1, -1, -1, 1, -1, -1, -1, 1, -1, 1, 1, -1, -1, -1, 1, 1, -1, 1, -1, 1, 1, 1, 1, 1};
static const uint32_t kBoxT[36] = {0, 2, 1, 1, 2, 3, 4, 5, 6, 5, 7, 6, 0, 1, 4, 1, 5, 4,
                                   2, 6, 3, 3, 6, 7, 0, 4, 2, 2, 4, 6, 1, 3, 5, 3, 7, 5};
static const double kTetraV[12] = {1, 1, 1, 1, -1, -1, -1, 1, -1, -1, -1, 1};
static const uint32_t kTetraT[12] = {0, 1, 2, 0, 3, 1, 0, 2, 3, 1, 3, 2};

enum way { SAME, NEW_POSITION, POSITION_ONLY, NEW_ORIENTATION, WAYS };
static const char *const way_names[WAYS] = {"unchanged", "new_position", "position_only", "new_orientation"};

/* A unit quaternion turned by a small rotation about z, renormalised. */
static void turn(double *q) {
    const double c = 0.99999950000004166, s = 0.00099999983333334167; /* cos, sin of 0.001 */
    const double x = q[0] * c + q[1] * s, y = q[1] * c - q[0] * s, z = q[2] * c + q[3] * s,
                 w = q[3] * c - q[2] * s;
    const double k = 0.5 * (3 - (((x * x + y * y) + z * z) + w * w));
    q[0] = x * k, q[1] = y * k, q[2] = z * k, q[3] = w * k;
}

static int run(const char *mesh_name, const double *v, uint32_t nv, const uint32_t *t, uint32_t nt, size_t n,
               int rounds, const char *commit) {
    hgcd_world *w = NULL;
    hgcd_world_desc wd = hgcd_world_desc_default();
    wd.thread_count = 1;
    if (failed(hgcd_world_create(&wd, &w), NULL, "world_create")) return 1;
    hgcd_mesh_desc md = hgcd_mesh_desc_default();
    md.vertices = v, md.vertex_count = nv, md.triangles = t, md.triangle_count = nt;
    hgcd_mesh mesh;
    if (failed(hgcd_mesh_create(w, &md, &mesh), w, "mesh_create")) return 1;
    hgcd_body *ids = malloc(n * sizeof *ids);
    double *p = malloc(3 * n * sizeof *p), *q = malloc(4 * n * sizeof *q), *ms = malloc((size_t)rounds * sizeof *ms);
    double *cpu = malloc((size_t)rounds * sizeof *cpu);
    if (!ids || !p || !q || !ms || !cpu) return 1;
    const double side = 60; /* (7200 unit boxes: sparse, as an engine's scene) */
    for (size_t i = 0; i < n; ++i) {
        hgcd_body_desc bd = hgcd_body_desc_default();
        bd.mesh = mesh;
        for (int k = 0; k < 3; ++k) p[3 * i + k] = bd.position[k] = side * unif();
        const double a = unif(), b = unif(), c = unif(), d = unif() + 0.1;
        const double norm2 = a * a + b * b + c * c + d * d;
        double r = 1; /* 1 / sqrt(norm2) by Newton steps (no libm) */
        for (int it = 0; it < 60; ++it) r = r * (1.5 - 0.5 * norm2 * r * r);
        q[4 * i] = a * r, q[4 * i + 1] = b * r, q[4 * i + 2] = c * r, q[4 * i + 3] = d * r;
        memcpy(bd.orientation, &q[4 * i], sizeof bd.orientation);
        if (failed(hgcd_body_create(w, &bd, &ids[i]), w, "body_create")) return 1;
    }
    if (failed(hgcd_world_detect(w), w, "world_detect")) return 1;
    for (int way = 0; way < WAYS; ++way) {
        for (int r = 0; r < rounds; ++r) {
            if (way != SAME)
                for (size_t i = 0; i < n; ++i) p[3 * i] += 1e-3;
            if (way == NEW_ORIENTATION)
                for (size_t i = 0; i < n; ++i) turn(&q[4 * i]);
            const double t0 = now_seconds(), c0 = thread_cpu_seconds();
            for (size_t i = 0; i < n; ++i)
                if (failed(hgcd_body_set_pose(w, ids[i], &p[3 * i], way == POSITION_ONLY ? NULL : &q[4 * i]), w,
                           "body_set_pose"))
                    return 1;
            ms[r] = (now_seconds() - t0) * 1e9 / (double)n;
            cpu[r] = (thread_cpu_seconds() - c0) * 1e9 / (double)n;
            if (failed(hgcd_world_detect(w), w, "world_detect")) return 1;
        }
        qsort(ms, (size_t)rounds, sizeof *ms, cmp_double);
        qsort(cpu, (size_t)rounds, sizeof *cpu, cmp_double);
        printf("{\"lib\":\"hgcd\",\"bench\":\"set_pose\",\"commit\":\"%s\",\"mesh\":\"%s\",\"triangles\":%u,"
               "\"bodies\":%zu,\"way\":\"%s\",\"rounds\":%d,\"ns_per_call\":%.1f,\"ns_per_call_min\":%.1f,"
               "\"cpu_ns_per_call\":%.1f}\n",
               commit, mesh_name, nt, n, way_names[way], rounds, ms[rounds / 2], ms[0], cpu[rounds / 2]);
        fflush(stdout);
    }
    hgcd_world_destroy(w);
    free(ids), free(p), free(q), free(ms), free(cpu);
    return 0;
}

int main(int argc, char **argv) {
    size_t n = 7200;
    int rounds = 31;
    const char *commit = "unknown";
    for (int i = 1; i < argc; ++i) {
        if (i + 1 >= argc) goto usage;
        if (!strcmp(argv[i], "--bodies")) n = (size_t)strtoull(argv[++i], NULL, 10);
        else if (!strcmp(argv[i], "--rounds")) rounds = atoi(argv[++i]);
        else if (!strcmp(argv[i], "--commit")) commit = argv[++i];
        else goto usage;
    }
    if (n == 0 || rounds < 1) goto usage;
    if (run("box", kBoxV, 8, kBoxT, 12, n, rounds, commit)) return 1;
    if (run("tetrahedron", kTetraV, 4, kTetraT, 4, n, rounds, commit)) return 1;
    return 0;
usage:
    fprintf(stderr, "usage: %s [--bodies N] [--rounds R] [--commit HASH]\n", argv[0]);
    return 2;
}
