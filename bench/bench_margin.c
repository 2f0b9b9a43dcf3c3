/* bench_margin: a settled pile under solver jitter, with and without a
 * contact margin (hgcd_world_desc.contact_margin).
 *
 *   bench_margin [--columns C] [--layers L] [--ticks T] [--jitter J]
 *                [--margin M] [--threads K] [--commit HASH]
 *
 * The pile: a static ground box (top face at z = 0) and C x C columns of L
 * unit cubes (side 1), stacked face on face exactly (centres at z = 0.5,
 * 1.5, ...), columns 1.25 apart (no side contacts). The resting pairs are
 * the pairs of the first detect, all touching exactly: each cube with the
 * one below (or the ground). Each tick, as a solver's round-off would, every
 * cube is put back at its resting pose moved by up to J (default 1e-12) on
 * each axis and turned by up to J radians about each axis (splitmix64
 * draws), through one hgcd_world_set_poses, and the world detects.
 *
 * Runs two worlds on the same poses, margin 0 and margin M (default 1e-6:
 * 1e-6 of the cube's side), and prints ONE JSON line with, for each: the
 * resting pairs, per tick the fewest of them still reported (min_kept: all
 * kept on every tick when it equals resting_pairs), the mean and largest
 * count of began + ended events per tick, and the median detect time.
 */
#define _POSIX_C_SOURCE 200809L
#include <hgcd/hgcd.h>

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

static double now_seconds(void) {
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

static uint64_t rng_state = 12345;
static uint64_t next(void) {
    uint64_t z = (rng_state += 0x9E3779B97F4A7C15ull);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return z ^ (z >> 31);
}
static double sym(void) { return 2 * ((double)(next() >> 11) * 0x1p-53) - 1; } /* [-1, 1) */

static const double cube_v[] = {-0.5, -0.5, -0.5, 0.5, -0.5, -0.5, 0.5, 0.5, -0.5, -0.5, 0.5, -0.5,
                                -0.5, -0.5, 0.5,  0.5, -0.5, 0.5,  0.5, 0.5, 0.5,  -0.5, 0.5, 0.5};
static const uint32_t cube_t[] = {0, 2, 1, 0, 3, 2, 0, 1, 5, 0, 5, 4, 1, 2, 6, 1, 6, 5,
                                  2, 3, 7, 2, 7, 6, 3, 0, 4, 3, 4, 7, 4, 5, 6, 4, 6, 7};

static int cmp_double(const void *a, const void *b) {
    const double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

typedef struct {
    hgcd_world *w;
    size_t resting, min_kept, events_max;
    double events_sum;
    double *detect_ms;
    uint64_t *rest_keys;
} run;

static void die(const char *what) {
    fprintf(stderr, "bench_margin: %s failed\n", what);
    exit(1);
}

/* The world: ground body 0, then the cubes. */
static void make(run *r, double margin, unsigned threads, int columns, int layers, double *pos, int ticks) {
    hgcd_world_desc wd = hgcd_world_desc_default();
    hgcd_mesh_desc md = hgcd_mesh_desc_default();
    hgcd_body_desc bd = hgcd_body_desc_default();
    hgcd_mesh mesh;
    hgcd_body id;
    int i;
    memset(r, 0, sizeof *r);
    wd.contact_margin = margin;
    wd.thread_count = threads;
    wd.thread_policy = HGCD_THREADS_FIXED;
    if (hgcd_world_create(&wd, &r->w)) die("world_create");
    md.vertices = cube_v;
    md.triangles = cube_t;
    md.vertex_count = 8;
    md.triangle_count = 12;
    if (hgcd_mesh_create(r->w, &md, &mesh)) die("mesh_create");
    bd.mesh = mesh;
    bd.type = HGCD_BODY_STATIC;
    bd.scale = 2.0 * columns * 1.25 + 4; /* (the ground: its top face at z = 0) */
    bd.position[2] = -0.5 * bd.scale;
    if (hgcd_body_create(r->w, &bd, &id)) die("ground");
    bd = hgcd_body_desc_default();
    bd.mesh = mesh;
    for (i = 0; i < columns * columns * layers; i++) {
        memcpy(bd.position, pos + 3 * i, 3 * sizeof(double));
        if (hgcd_body_create(r->w, &bd, &id)) die("body_create");
    }
    r->detect_ms = (double *)calloc((size_t)ticks + 1, sizeof(double));
}

static void tick(run *r, size_t n, const double *p, const double *q, int t) {
    const hgcd_pair *pairs;
    const hgcd_pair_event *began, *ended;
    size_t count, nb, ne, k, kept = 0, j = 0;
    double t0;
    if (hgcd_world_set_poses(r->w, NULL, n + 1, p, 0, q, 0)) die("set_poses");
    t0 = now_seconds();
    if (hgcd_world_detect(r->w)) die("detect");
    r->detect_ms[t] = 1e3 * (now_seconds() - t0);
    hgcd_world_pairs(r->w, &pairs, &count);
    hgcd_world_events(r->w, &began, &nb, &ended, &ne);
    if (t == 0) { /* the resting pairs */
        r->resting = count;
        r->rest_keys = (uint64_t *)malloc((count + 1) * sizeof(uint64_t));
        for (k = 0; k < count; k++) r->rest_keys[k] = (uint64_t)pairs[k].a.index << 32 | pairs[k].b.index;
        r->min_kept = count;
        return;
    }
    for (k = 0; k < count && j < r->resting; k++) { /* both sorted */
        const uint64_t key = (uint64_t)pairs[k].a.index << 32 | pairs[k].b.index;
        while (j < r->resting && r->rest_keys[j] < key) j++;
        if (j < r->resting && r->rest_keys[j] == key) kept++, j++;
    }
    if (kept < r->min_kept) r->min_kept = kept;
    r->events_sum += (double)(nb + ne);
    if (nb + ne > r->events_max) r->events_max = nb + ne;
}

int main(int argc, char **argv) {
    int columns = 20, layers = 5, ticks = 50, i, t;
    double jitter = 1e-12, margin = 1e-6;
    unsigned threads = 1;
    const char *commit = "unknown";
    size_t n;
    double *rest, *p, *q;
    run r[2];
    for (i = 1; i + 1 < argc; i += 2) {
        if (!strcmp(argv[i], "--columns")) columns = atoi(argv[i + 1]);
        else if (!strcmp(argv[i], "--layers")) layers = atoi(argv[i + 1]);
        else if (!strcmp(argv[i], "--ticks")) ticks = atoi(argv[i + 1]);
        else if (!strcmp(argv[i], "--jitter")) jitter = strtod(argv[i + 1], NULL);
        else if (!strcmp(argv[i], "--margin")) margin = strtod(argv[i + 1], NULL);
        else if (!strcmp(argv[i], "--threads")) threads = (unsigned)atoi(argv[i + 1]);
        else if (!strcmp(argv[i], "--commit")) commit = argv[i + 1];
        else {
            fprintf(stderr, "usage: %s [--columns C] [--layers L] [--ticks T] [--jitter J] [--margin M] "
                            "[--threads K] [--commit HASH]\n", argv[0]);
            return 2;
        }
    }
    if (columns < 1 || layers < 1 || ticks < 1) return 2;
    n = (size_t)columns * columns * layers;
    rest = (double *)malloc(3 * n * sizeof(double));
    p = (double *)malloc(3 * (n + 1) * sizeof(double));
    q = (double *)malloc(4 * (n + 1) * sizeof(double));
    for (i = 0; i < (int)n; i++) {
        const int c = i / layers, l = i % layers;
        rest[3 * i] = 1.25 * (c % columns);
        rest[3 * i + 1] = 1.25 * (c / columns);
        rest[3 * i + 2] = 0.5 + l;
    }
    make(&r[0], 0, threads, columns, layers, rest, ticks);
    make(&r[1], margin, threads, columns, layers, rest, ticks);
    /* The ground (body 0) keeps its pose: see make. */
    p[0] = p[1] = 0;
    p[2] = -0.5 * (2.0 * columns * 1.25 + 4);
    q[0] = q[1] = q[2] = 0;
    q[3] = 1;
    for (t = 0; t <= ticks; t++) {
        for (i = 0; i < (int)n; i++) {
            double *pi = p + 3 * (i + 1), *qi = q + 4 * (i + 1);
            const double e = t ? jitter : 0;
            int k;
            for (k = 0; k < 3; k++) pi[k] = rest[3 * i + k] + e * sym();
            /* A turn by about (ax, ay, az) radians: q = (a / 2, 1), unit to 1e-24. */
            for (k = 0; k < 3; k++) qi[k] = 0.5 * e * sym();
            qi[3] = 1;
        }
        tick(&r[0], n, p, q, t);
        tick(&r[1], n, p, q, t);
    }
    printf("{\"bench\":\"margin_pile\",\"commit\":\"%s\",\"cubes\":%zu,\"threads\":%u,\"ticks\":%d,\"jitter\":%g",
           commit, n, threads, ticks, jitter);
    for (i = 0; i < 2; i++) {
        qsort(r[i].detect_ms + 1, (size_t)ticks, sizeof(double), cmp_double);
        printf(",\"%s\":{\"margin\":%g,\"resting_pairs\":%zu,\"min_kept\":%zu,\"events_mean\":%.1f,"
               "\"events_max\":%zu,\"detect_ms\":%.3f}",
               i ? "with_margin" : "without", i ? margin : 0.0, r[i].resting, r[i].min_kept,
               r[i].events_sum / ticks, r[i].events_max, r[i].detect_ms[1 + ticks / 2]);
        hgcd_world_destroy(r[i].w);
    }
    printf("}\n");
    return 0;
}
