/* bench_mpi: hgcd_mpi on scene `tetra` (docs/scenes.md), run under mpirun.
 *
 * Every rank draws the whole scene (the bench's own bookkeeping, not the
 * library's: a real engine keeps the state of the bodies it owns); rank r adds
 * the bodies of ids [r n / p, (r + 1) n / p) and the library sends each to
 * its owner. Each tick, as an engine would: every rank moves the scene's
 * centres (hgcd_scene_tetra_move, the scene's motion bit for bit, untimed),
 * copies the positions of the bodies it owns into a packed array (untimed),
 * hands them over with hgcd_mpi_set_poses (timed: set_poses) and calls
 * hgcd_mpi_detect (timed: detect). Orientations do not change (the scene's
 * motion has none). One detect at the initial poses comes first, untimed.
 *
 * After it, one line per rank ("bench":"mpi-rank") with that rank's own
 * medians: each phase, bytes and messages sent, ghosts and owned bodies.
 *
 * --plain runs the same loop on one ordinary hgcd world (hgcd_world_set_poses
 * with all bodies by index, then hgcd_world_detect), one process: the
 * comparison for "p ranks x 1 thread against 1 rank x p threads".
 *
 * Rank 0 prints one JSON line: per tick medians of the slowest rank's
 * set_poses + detect (tick_ms), of each phase (the slowest rank), the bytes
 * and messages summed over the ranks, the ghosts and owned bodies, the halo
 * ratio (ghost bytes a rank receives over its owned bodies' state, 80 bytes a
 * body, the largest over the ranks), the load imbalance, and pairs_fnv: FNV-1a
 * of the last tick's pairs sorted by (a, b) as pairs of uint64 ids, equal for
 * --plain and any rank count.
 * Options: --n (750000) --seed (1) --ticks (7) --threads (1) --side (the
 * scene's, scaled to keep its density: 200 (n / 750000)^(1/3)) --plain
 * --allowance (0) --imbalance (1.2) --per-tick (each tick to stderr). */
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <hgcd/hgcd.h>
#include <hgcd/hgcd_mpi.h>
#include <hgcd/hgcd_scene.h>

#define CHECK(call)                                                                                 \
    do {                                                                                            \
        hgcd_status s_ = (call);                                                                    \
        if (s_ != HGCD_OK) {                                                                        \
            fprintf(stderr, "%s: %s (%s)\n", #call, hgcd_status_string(s_), err ? err(ctx) : "");   \
            MPI_Abort(MPI_COMM_WORLD, 1);                                                           \
        }                                                                                           \
    } while (0)

typedef const char *(*err_fn)(const void *);
static const char *mpi_err(const void *w) { return hgcd_mpi_world_last_error(w); }
static const char *plain_err(const void *w) { return hgcd_world_last_error(w); }
/* What CHECK reports a refusal with: the world in use and its message. */
static err_fn err;
static const void *ctx;

enum { kFields = 14 };
/* Per tick, per rank: what rank 0 reduces. */
typedef struct {
    double set_poses, detect, migrate, rebalance, ghost_exchange, ghost_update, local_detect, pairs;
    double bytes, messages, ghosts, owned, halo_ratio, imbalance;
} tick_figures;

static int cmp_double(const void *a, const void *b) {
    const double x = *(const double *)a, y = *(const double *)b;
    return x < y ? -1 : x > y;
}
static double median(double *v, int n) {
    qsort(v, (size_t)n, sizeof *v, cmp_double);
    return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}
static int cmp_pair(const void *x, const void *y) {
    const hgcd_mpi_pair *a = x, *b = y;
    if (a->a != b->a) return a->a < b->a ? -1 : 1;
    return a->b < b->b ? -1 : a->b > b->b;
}
static uint64_t fnv(const hgcd_mpi_pair *p, size_t n) {
    uint64_t h = 1469598103934665603ull;
    const unsigned char *c = (const unsigned char *)p;
    for (size_t i = 0; i < n * sizeof *p; ++i) h = (h ^ c[i]) * 1099511628211ull;
    return h;
}

typedef struct {
    uint64_t n, seed;
    int ticks, threads, plain, per_tick;
    double side, allowance, imbalance;
} options;

static options parse_options(int argc, char **argv, int rank, int size) {
    options o = {750000, 1, 7, 1, 0, 0, 0, 0, 1.2};
    for (int i = 1; i < argc; ++i) {
        const char *a = argv[i], *v = i + 1 < argc ? argv[i + 1] : "0";
        if (!strcmp(a, "--n")) o.n = strtoull(v, NULL, 10), ++i;
        else if (!strcmp(a, "--seed")) o.seed = strtoull(v, NULL, 10), ++i;
        else if (!strcmp(a, "--ticks")) o.ticks = atoi(v), ++i;
        else if (!strcmp(a, "--threads")) o.threads = atoi(v), ++i;
        else if (!strcmp(a, "--side")) o.side = atof(v), ++i;
        else if (!strcmp(a, "--allowance")) o.allowance = atof(v), ++i;
        else if (!strcmp(a, "--imbalance")) o.imbalance = atof(v), ++i;
        else if (!strcmp(a, "--plain")) o.plain = 1;
        else if (!strcmp(a, "--per-tick")) o.per_tick = 1;
        else {
            if (rank == 0) fprintf(stderr, "bench_mpi: unknown option %s\n", a);
            MPI_Abort(MPI_COMM_WORLD, 2);
        }
    }
    if (o.ticks < 1) o.ticks = 1;
    if (o.plain && size != 1) {
        if (rank == 0) fprintf(stderr, "bench_mpi: --plain runs on one rank\n");
        MPI_Abort(MPI_COMM_WORLD, 2);
    }
    return o;
}

/* The scene as every rank draws it, and the world it runs on. */
typedef struct {
    hgcd_scene_tetra_desc sd;
    double *centers, *scales, *rot, *vel, *packed;
    hgcd_world *pw;
    hgcd_mpi_world *mw;
} bench;

static void setup_plain(bench *b, const options *o, const hgcd_mesh_desc *md) {
    hgcd_world_desc wd = hgcd_world_desc_default();
    wd.thread_count = (uint32_t)o->threads;
    err = plain_err;
    CHECK(hgcd_world_create(&wd, &b->pw));
    ctx = b->pw;
    hgcd_mesh mesh;
    CHECK(hgcd_mesh_create(b->pw, md, &mesh));
    for (uint64_t k = 0; k < o->n; ++k) {
        hgcd_body_desc bd = hgcd_body_desc_default();
        bd.mesh = mesh;
        memcpy(bd.position, &b->centers[3 * k], 24);
        memcpy(bd.orientation, &b->rot[4 * k], 32);
        bd.scale = b->scales[k];
        hgcd_body id;
        CHECK(hgcd_body_create(b->pw, &bd, &id));
    }
    CHECK(hgcd_world_detect(b->pw));
}

/* Rank r adds the bodies of ids [r n / p, (r + 1) n / p). */
static void setup_mpi(bench *b, const options *o, const hgcd_mesh_desc *md, int rank, int size) {
    hgcd_mpi_world_desc wd = hgcd_mpi_world_desc_default();
    wd.thread_count = (uint32_t)o->threads;
    wd.motion_allowance = o->allowance;
    wd.imbalance_factor = o->imbalance;
    err = mpi_err;
    CHECK(hgcd_mpi_world_create(MPI_COMM_WORLD, &wd, &b->mw));
    ctx = b->mw;
    uint32_t mesh;
    CHECK(hgcd_mpi_mesh_register(b->mw, md, &mesh));
    const uint64_t lo = o->n * (uint64_t)rank / (uint64_t)size, hi = o->n * (uint64_t)(rank + 1) / (uint64_t)size;
    hgcd_mpi_body_desc *d = malloc((hi - lo + 1) * sizeof *d);
    if (!d) MPI_Abort(MPI_COMM_WORLD, 1);
    for (uint64_t k = lo; k < hi; ++k) {
        hgcd_mpi_body_desc *e = &d[k - lo];
        *e = hgcd_mpi_body_desc_default();
        e->id = k;
        e->mesh = mesh;
        memcpy(e->position, &b->centers[3 * k], 24);
        memcpy(e->orientation, &b->rot[4 * k], 32);
        e->scale = b->scales[k];
    }
    CHECK(hgcd_mpi_bodies_add(b->mw, d, hi - lo));
    free(d);
    CHECK(hgcd_mpi_detect(b->mw));
}

static void tick_plain(bench *b, uint64_t n, tick_figures *f) {
    double t0 = MPI_Wtime();
    CHECK(hgcd_world_set_poses(b->pw, NULL, n, b->centers, 0, NULL, 0));
    double t1 = MPI_Wtime();
    CHECK(hgcd_world_detect(b->pw));
    f->set_poses = t1 - t0, f->detect = MPI_Wtime() - t1;
    f->owned = (double)n, f->local_detect = f->detect, f->imbalance = 1;
}

static void tick_mpi(bench *b, tick_figures *f) {
    const uint64_t *ids;
    size_t owned;
    CHECK(hgcd_mpi_owned(b->mw, &ids, &owned));
    for (size_t j = 0; j < owned; ++j) memcpy(&b->packed[3 * j], &b->centers[3 * ids[j]], 24);
    MPI_Barrier(MPI_COMM_WORLD); /* every rank starts the tick together */
    double t0 = MPI_Wtime();
    CHECK(hgcd_mpi_set_poses(b->mw, NULL, owned, b->packed, 0, NULL, 0));
    double t1 = MPI_Wtime();
    CHECK(hgcd_mpi_detect(b->mw));
    f->set_poses = t1 - t0, f->detect = MPI_Wtime() - t1;
    hgcd_mpi_stats st;
    st.struct_size = sizeof st;
    CHECK(hgcd_mpi_stats_get(b->mw, &st));
    f->migrate = st.migrate_seconds, f->rebalance = st.rebalance_seconds;
    f->ghost_exchange = st.ghost_exchange_seconds, f->ghost_update = st.ghost_update_seconds;
    f->local_detect = st.local_detect_seconds, f->pairs = st.pairs_seconds;
    f->bytes = (double)st.bytes_sent, f->messages = (double)st.messages_sent;
    f->ghosts = (double)st.ghost_bodies, f->owned = (double)st.owned_bodies;
    f->halo_ratio = st.owned_bodies ? (double)st.ghosts_received / (double)st.owned_bodies : 0;
    f->imbalance = st.imbalance;
}

/* FNV-1a of the last tick's pairs, sorted by (a, b) as uint64 ids. */
static uint64_t last_pairs_fnv(const bench *b, size_t *npairs) {
    if (b->pw) {
        const hgcd_pair *p;
        CHECK(hgcd_world_pairs(b->pw, &p, npairs));
        hgcd_mpi_pair *q = malloc((*npairs + 1) * sizeof *q);
        if (!q) MPI_Abort(MPI_COMM_WORLD, 1);
        for (size_t k = 0; k < *npairs; ++k) q[k].a = p[k].a.index, q[k].b = p[k].b.index;
        qsort(q, *npairs, sizeof *q, cmp_pair);
        const uint64_t h = fnv(q, *npairs);
        free(q);
        return h;
    }
    const hgcd_mpi_pair *p;
    CHECK(hgcd_mpi_gather_pairs(b->mw, 0, &p, npairs));
    return fnv(p, *npairs);
}

/* Rank 0's line: per tick, time phases by the slowest rank, bytes and
 * messages summed over the ranks, ghosts and owned as max and sum; medians
 * over the ticks. */
static void report_totals(const options *o, const tick_figures *fig, uint64_t pairs_fnv, size_t npairs,
                          int rank, int size) {
    double *med = calloc(kFields + 4, sizeof(double)), *v = calloc((size_t)o->ticks, sizeof(double));
    if (!med || !v) MPI_Abort(MPI_COMM_WORLD, 1);
    for (int field = 0; field < kFields + 3; ++field) {
        for (int t = 0; t < o->ticks; ++t) {
            const double *row = (const double *)&fig[t];
            double x = field < kFields ? row[field] : field == kFields ? row[0] + row[1] : row[field - kFields + 9];
            const int summed = field == 8 || field == 9 || field == kFields + 1 || field == kFields + 2;
            double r = 0;
            MPI_Allreduce(&x, &r, 1, MPI_DOUBLE, summed ? MPI_SUM : MPI_MAX, MPI_COMM_WORLD);
            v[t] = r;
        }
        med[field] = median(v, o->ticks);
    }
    if (rank == 0)
        printf("{\"bench\":\"mpi\",\"mode\":\"%s\",\"n\":%llu,\"ranks\":%d,\"threads\":%d,\"ticks\":%d,"
               "\"tick_ms\":%.3f,\"set_poses_ms\":%.3f,\"detect_ms\":%.3f,\"migrate_ms\":%.3f,\"rebalance_ms\":%.3f,"
               "\"ghost_exchange_ms\":%.3f,\"ghost_update_ms\":%.3f,\"local_detect_ms\":%.3f,\"pairs_ms\":%.3f,"
               "\"bytes_per_tick\":%.0f,\"messages_per_tick\":%.0f,\"ghosts_max\":%.0f,\"owned_max\":%.0f,"
               "\"ghosts_total\":%.0f,\"owned_total\":%.0f,\"halo_ratio_max\":%.4f,\"imbalance\":%.4f,"
               "\"pairs\":%zu,\"pairs_fnv\":\"%016llx\"}\n",
               o->plain ? "plain" : "mpi", (unsigned long long)o->n, size, o->threads, o->ticks, 1e3 * med[kFields],
               1e3 * med[0], 1e3 * med[1], 1e3 * med[2], 1e3 * med[3], 1e3 * med[4], 1e3 * med[5], 1e3 * med[6],
               1e3 * med[7], med[8], med[9], med[10], med[11], med[kFields + 1], med[kFields + 2], med[12], med[13],
               npairs, (unsigned long long)pairs_fnv);
    free(med), free(v);
}

/* Each rank's own medians, one line per rank (time per phase per rank). */
static void report_ranks(const options *o, const tick_figures *fig, int rank, int size) {
    double mine[kFields];
    double *v = calloc((size_t)o->ticks, sizeof(double));
    if (!v) MPI_Abort(MPI_COMM_WORLD, 1);
    for (int field = 0; field < kFields; ++field) {
        for (int t = 0; t < o->ticks; ++t) v[t] = ((const double *)&fig[t])[field];
        mine[field] = median(v, o->ticks);
    }
    double *every = rank == 0 ? malloc((size_t)size * kFields * sizeof(double)) : NULL;
    MPI_Gather(mine, kFields, MPI_DOUBLE, every, kFields, MPI_DOUBLE, 0, MPI_COMM_WORLD);
    if (rank == 0 && !o->plain)
        for (int r = 0; r < size; ++r) {
            const double *m = &every[r * kFields];
            printf("{\"bench\":\"mpi-rank\",\"n\":%llu,\"ranks\":%d,\"threads\":%d,\"rank\":%d,"
                   "\"set_poses_ms\":%.3f,\"detect_ms\":%.3f,\"migrate_ms\":%.3f,\"rebalance_ms\":%.3f,"
                   "\"ghost_exchange_ms\":%.3f,\"ghost_update_ms\":%.3f,\"local_detect_ms\":%.3f,"
                   "\"pairs_ms\":%.3f,\"bytes_sent\":%.0f,\"messages_sent\":%.0f,\"ghosts\":%.0f,\"owned\":%.0f}\n",
                   (unsigned long long)o->n, size, o->threads, r, 1e3 * m[0], 1e3 * m[1], 1e3 * m[2], 1e3 * m[3],
                   1e3 * m[4], 1e3 * m[5], 1e3 * m[6], 1e3 * m[7], m[8], m[9], m[10], m[11]);
        }
    free(every), free(v);
}

int main(int argc, char **argv) {
    MPI_Init(&argc, &argv);
    int rank, size;
    MPI_Comm_rank(MPI_COMM_WORLD, &rank);
    MPI_Comm_size(MPI_COMM_WORLD, &size);
    const options o = parse_options(argc, argv, rank, size);
    const uint64_t n = o.n;
    bench b = {0};
    b.sd = hgcd_scene_tetra_desc_default();
    b.sd.n = n;
    b.sd.seed = o.seed;
    b.sd.side = o.side > 0 ? o.side : 200.0 * cbrt((double)n / 750000.0);
    b.centers = malloc(3 * n * sizeof(double)), b.scales = malloc(n * sizeof(double));
    b.rot = malloc(4 * n * sizeof(double)), b.vel = malloc(3 * n * sizeof(double));
    b.packed = malloc((3 * n + 3) * sizeof(double));
    if (!b.centers || !b.scales || !b.rot || !b.vel || !b.packed ||
        hgcd_scene_tetra_generate(&b.sd, b.centers, NULL, b.scales, b.rot, b.vel))
        MPI_Abort(MPI_COMM_WORLD, 1);

    double verts[12];
    uint32_t tris[12];
    hgcd_scene_tetra_unit_mesh(verts, tris);
    hgcd_mesh_desc md = hgcd_mesh_desc_default();
    md.vertices = verts, md.triangles = tris, md.vertex_count = 4, md.triangle_count = 4;
    if (o.plain)
        setup_plain(&b, &o, &md);
    else
        setup_mpi(&b, &o, &md, rank, size);

    tick_figures *fig = calloc((size_t)o.ticks, sizeof *fig);
    if (!fig) MPI_Abort(MPI_COMM_WORLD, 1);
    for (int t = 0; t < o.ticks; ++t) {
        hgcd_scene_tetra_move(n, b.sd.side, b.centers, b.vel);
        if (o.plain)
            tick_plain(&b, n, &fig[t]);
        else
            tick_mpi(&b, &fig[t]);
        if (o.per_tick && rank == 0)
            fprintf(stderr, "tick %d: set_poses %.2f ms, detect %.2f ms\n", t, 1e3 * fig[t].set_poses,
                    1e3 * fig[t].detect);
    }
    size_t npairs = 0;
    const uint64_t pairs_fnv = last_pairs_fnv(&b, &npairs);
    report_totals(&o, fig, pairs_fnv, npairs, rank, size);
    report_ranks(&o, fig, rank, size);
    free(fig);
    hgcd_world_destroy(b.pw);
    hgcd_mpi_world_destroy(b.mw);
    free(b.centers), free(b.scales), free(b.rot), free(b.vel), free(b.packed);
    MPI_Finalize();
    return 0;
}
