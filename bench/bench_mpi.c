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
            fprintf(stderr, "%s: %s (%s)\n", #call, hgcd_status_string(s_), err ? err(ctx) : ""); \
            MPI_Abort(MPI_COMM_WORLD, 1);                                                           \
        }                                                                                           \
    } while (0)

typedef const char *(*err_fn)(const void *);
static const char *mpi_err(const void *w) { return hgcd_mpi_world_last_error(w); }
static const char *plain_err(const void *w) { return hgcd_world_last_error(w); }

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

int main(int argc, char **argv) {
    MPI_Init(&argc, &argv);
    int rank, size;
    MPI_Comm_rank(MPI_COMM_WORLD, &rank);
    MPI_Comm_size(MPI_COMM_WORLD, &size);
    uint64_t n = 750000, seed = 1;
    int ticks = 7, threads = 1, plain = 0, per_tick = 0;
    double side = 0, allowance = 0, imbalance = 1.2;
    for (int i = 1; i < argc; ++i) {
        const char *a = argv[i], *v = i + 1 < argc ? argv[i + 1] : "0";
        if (!strcmp(a, "--n")) n = strtoull(v, NULL, 10), ++i;
        else if (!strcmp(a, "--seed")) seed = strtoull(v, NULL, 10), ++i;
        else if (!strcmp(a, "--ticks")) ticks = atoi(v), ++i;
        else if (!strcmp(a, "--threads")) threads = atoi(v), ++i;
        else if (!strcmp(a, "--side")) side = atof(v), ++i;
        else if (!strcmp(a, "--allowance")) allowance = atof(v), ++i;
        else if (!strcmp(a, "--imbalance")) imbalance = atof(v), ++i;
        else if (!strcmp(a, "--plain")) plain = 1;
        else if (!strcmp(a, "--per-tick")) per_tick = 1;
        else {
            if (rank == 0) fprintf(stderr, "bench_mpi: unknown option %s\n", a);
            MPI_Abort(MPI_COMM_WORLD, 2);
        }
    }
    if (ticks < 1) ticks = 1;
    if (plain && size != 1) {
        if (rank == 0) fprintf(stderr, "bench_mpi: --plain runs on one rank\n");
        MPI_Abort(MPI_COMM_WORLD, 2);
    }
    hgcd_scene_tetra_desc sd = hgcd_scene_tetra_desc_default();
    sd.n = n;
    sd.seed = seed;
    sd.side = side > 0 ? side : 200.0 * cbrt((double)n / 750000.0);
    double *centers = malloc(3 * n * sizeof(double)), *scales = malloc(n * sizeof(double));
    double *rot = malloc(4 * n * sizeof(double)), *vel = malloc(3 * n * sizeof(double));
    double *packed = malloc((3 * n + 3) * sizeof(double));
    if (!centers || !scales || !rot || !vel || !packed || hgcd_scene_tetra_generate(&sd, centers, NULL, scales, rot, vel))
        MPI_Abort(MPI_COMM_WORLD, 1);

    hgcd_world *pw = NULL;
    hgcd_mpi_world *mw = NULL;
    err_fn err = plain ? plain_err : mpi_err;
    const void *ctx = NULL;
    double verts[12];
    uint32_t tris[12];
    hgcd_scene_tetra_unit_mesh(verts, tris);
    hgcd_mesh_desc md = hgcd_mesh_desc_default();
    md.vertices = verts, md.triangles = tris, md.vertex_count = 4, md.triangle_count = 4;
    const uint64_t lo = n * (uint64_t)rank / (uint64_t)size, hi = n * (uint64_t)(rank + 1) / (uint64_t)size;
    if (plain) {
        hgcd_world_desc wd = hgcd_world_desc_default();
        wd.thread_count = (uint32_t)threads;
        CHECK(hgcd_world_create(&wd, &pw));
        ctx = pw;
        hgcd_mesh mesh;
        CHECK(hgcd_mesh_create(pw, &md, &mesh));
        for (uint64_t k = 0; k < n; ++k) {
            hgcd_body_desc bd = hgcd_body_desc_default();
            bd.mesh = mesh;
            memcpy(bd.position, &centers[3 * k], 24);
            memcpy(bd.orientation, &rot[4 * k], 32);
            bd.scale = scales[k];
            hgcd_body b;
            CHECK(hgcd_body_create(pw, &bd, &b));
        }
        CHECK(hgcd_world_detect(pw));
    } else {
        hgcd_mpi_world_desc wd = hgcd_mpi_world_desc_default();
        wd.thread_count = (uint32_t)threads;
        wd.motion_allowance = allowance;
        wd.imbalance_factor = imbalance;
        CHECK(hgcd_mpi_world_create(MPI_COMM_WORLD, &wd, &mw));
        ctx = mw;
        uint32_t mesh;
        CHECK(hgcd_mpi_mesh_register(mw, &md, &mesh));
        hgcd_mpi_body_desc *d = malloc((hi - lo + 1) * sizeof *d);
        for (uint64_t k = lo; k < hi; ++k) {
            hgcd_mpi_body_desc *b = &d[k - lo];
            *b = hgcd_mpi_body_desc_default();
            b->id = k;
            b->mesh = mesh;
            memcpy(b->position, &centers[3 * k], 24);
            memcpy(b->orientation, &rot[4 * k], 32);
            b->scale = scales[k];
        }
        CHECK(hgcd_mpi_bodies_add(mw, d, hi - lo));
        free(d);
        CHECK(hgcd_mpi_detect(mw));
    }

    tick_figures *fig = calloc((size_t)ticks, sizeof *fig);
    for (int t = 0; t < ticks; ++t) {
        hgcd_scene_tetra_move(n, sd.side, centers, vel);
        tick_figures *f = &fig[t];
        if (plain) {
            double t0 = MPI_Wtime();
            CHECK(hgcd_world_set_poses(pw, NULL, n, centers, 0, NULL, 0));
            double t1 = MPI_Wtime();
            CHECK(hgcd_world_detect(pw));
            f->set_poses = t1 - t0, f->detect = MPI_Wtime() - t1;
            f->owned = (double)n, f->local_detect = f->detect, f->imbalance = 1;
        } else {
            const uint64_t *ids;
            size_t owned;
            CHECK(hgcd_mpi_owned(mw, &ids, &owned));
            for (size_t j = 0; j < owned; ++j) memcpy(&packed[3 * j], &centers[3 * ids[j]], 24);
            MPI_Barrier(MPI_COMM_WORLD); /* every rank starts the tick together */
            double t0 = MPI_Wtime();
            CHECK(hgcd_mpi_set_poses(mw, NULL, owned, packed, 0, NULL, 0));
            double t1 = MPI_Wtime();
            CHECK(hgcd_mpi_detect(mw));
            f->set_poses = t1 - t0, f->detect = MPI_Wtime() - t1;
            hgcd_mpi_stats st;
            st.struct_size = sizeof st;
            CHECK(hgcd_mpi_stats_get(mw, &st));
            f->migrate = st.migrate_seconds, f->rebalance = st.rebalance_seconds;
            f->ghost_exchange = st.ghost_exchange_seconds, f->ghost_update = st.ghost_update_seconds;
            f->local_detect = st.local_detect_seconds, f->pairs = st.pairs_seconds;
            f->bytes = (double)st.bytes_sent, f->messages = (double)st.messages_sent;
            f->ghosts = (double)st.ghost_bodies, f->owned = (double)st.owned_bodies;
            f->halo_ratio = st.owned_bodies ? (double)st.ghosts_received / (double)st.owned_bodies : 0;
            f->imbalance = st.imbalance;
        }
        if (per_tick && rank == 0)
            fprintf(stderr, "tick %d: set_poses %.2f ms, detect %.2f ms\n", t, 1e3 * f->set_poses, 1e3 * f->detect);
    }

    /* Reductions over the ranks per tick: time phases by the slowest rank,
     * bytes and messages summed, ghosts and owned as max and sum. */
    double *med = calloc(kFields + 4, sizeof(double)), *v = calloc((size_t)ticks, sizeof(double));
    for (int field = 0; field < kFields + 3; ++field) {
        for (int t = 0; t < ticks; ++t) {
            const double *row = (const double *)&fig[t];
            double x = field < kFields ? row[field] : field == kFields ? row[0] + row[1] : row[field - kFields + 9];
            const int summed = field == 8 || field == 9 || field == kFields + 1 || field == kFields + 2;
            double r = 0;
            MPI_Allreduce(&x, &r, 1, MPI_DOUBLE, summed ? MPI_SUM : MPI_MAX, MPI_COMM_WORLD);
            v[t] = r;
        }
        med[field] = median(v, ticks);
    }
    /* The last tick's pairs, gathered and hashed. */
    uint64_t pairs_fnv = 0;
    size_t npairs = 0;
    if (plain) {
        const hgcd_pair *p;
        CHECK(hgcd_world_pairs(pw, &p, &npairs));
        hgcd_mpi_pair *q = malloc((npairs + 1) * sizeof *q);
        for (size_t k = 0; k < npairs; ++k) q[k].a = p[k].a.index, q[k].b = p[k].b.index;
        qsort(q, npairs, sizeof *q, cmp_pair);
        pairs_fnv = fnv(q, npairs);
        free(q);
    } else {
        const hgcd_mpi_pair *p;
        CHECK(hgcd_mpi_gather_pairs(mw, 0, &p, &npairs));
        pairs_fnv = fnv(p, npairs);
    }
    if (rank == 0)
        printf("{\"bench\":\"mpi\",\"mode\":\"%s\",\"n\":%llu,\"ranks\":%d,\"threads\":%d,\"ticks\":%d,"
               "\"tick_ms\":%.3f,\"set_poses_ms\":%.3f,\"detect_ms\":%.3f,\"migrate_ms\":%.3f,\"rebalance_ms\":%.3f,"
               "\"ghost_exchange_ms\":%.3f,\"ghost_update_ms\":%.3f,\"local_detect_ms\":%.3f,\"pairs_ms\":%.3f,"
               "\"bytes_per_tick\":%.0f,\"messages_per_tick\":%.0f,\"ghosts_max\":%.0f,\"owned_max\":%.0f,"
               "\"ghosts_total\":%.0f,\"owned_total\":%.0f,\"halo_ratio_max\":%.4f,\"imbalance\":%.4f,"
               "\"pairs\":%zu,\"pairs_fnv\":\"%016llx\"}\n",
               plain ? "plain" : "mpi", (unsigned long long)n, size, threads, ticks, 1e3 * med[kFields],
               1e3 * med[0], 1e3 * med[1], 1e3 * med[2], 1e3 * med[3], 1e3 * med[4], 1e3 * med[5], 1e3 * med[6],
               1e3 * med[7], med[8], med[9], med[10], med[11], med[kFields + 1], med[kFields + 2], med[12], med[13],
               npairs, (unsigned long long)pairs_fnv);
    /* Each rank's own medians, one line per rank (time per phase per rank). */
    double mine[kFields];
    for (int field = 0; field < kFields; ++field) {
        for (int t = 0; t < ticks; ++t) v[t] = ((const double *)&fig[t])[field];
        mine[field] = median(v, ticks);
    }
    double *every = rank == 0 ? malloc((size_t)size * kFields * sizeof(double)) : NULL;
    MPI_Gather(mine, kFields, MPI_DOUBLE, every, kFields, MPI_DOUBLE, 0, MPI_COMM_WORLD);
    if (rank == 0 && !plain)
        for (int r = 0; r < size; ++r) {
            const double *m = &every[r * kFields];
            printf("{\"bench\":\"mpi-rank\",\"n\":%llu,\"ranks\":%d,\"threads\":%d,\"rank\":%d,"
                   "\"set_poses_ms\":%.3f,\"detect_ms\":%.3f,\"migrate_ms\":%.3f,\"rebalance_ms\":%.3f,"
                   "\"ghost_exchange_ms\":%.3f,\"ghost_update_ms\":%.3f,\"local_detect_ms\":%.3f,"
                   "\"pairs_ms\":%.3f,\"bytes_sent\":%.0f,\"messages_sent\":%.0f,\"ghosts\":%.0f,\"owned\":%.0f}\n",
                   (unsigned long long)n, size, threads, r, 1e3 * m[0], 1e3 * m[1], 1e3 * m[2], 1e3 * m[3], 1e3 * m[4],
                   1e3 * m[5], 1e3 * m[6], 1e3 * m[7], m[8], m[9], m[10], m[11]);
        }
    free(every);
    free(med), free(v), free(fig);
    hgcd_world_destroy(pw);
    hgcd_mpi_world_destroy(mw);
    free(centers), free(scales), free(rot), free(vel), free(packed);
    MPI_Finalize();
    return 0;
}
