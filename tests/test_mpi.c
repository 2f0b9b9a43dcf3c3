/* hgcd_mpi against one process: run under mpirun with any number of ranks
 * (scripts/run-tests.sh uses 1 to 4), every rank computes the same scene and
 * moves the bodies it owns; after each detect the pairs gathered on rank 0
 * must equal, pair for pair, those of a single hgcd world holding every body
 * (the reference), and every rank must report only pairs whose lower id it
 * owns. Scenes: `tetra` (small, fast) and a clustered scene of four meshes
 * with bodies larger than a subdomain, rotating, drifting across the cuts,
 * removed and added on ranks that do not own them. Then the refusals: every
 * rank gets the same status and message, and nothing changes.
 * Every assertion tests a value agreed by all ranks, so all fail together. */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#include <hgcd/hgcd.h>
#include <hgcd/hgcd_mpi.h>
#include <hgcd/hgcd_scene.h>

static int g_rank, g_size;

/* 1 on every rank when ok is non-zero on every rank. */
static int all_ranks(int ok) {
    int all = 0;
    MPI_Allreduce(&ok, &all, 1, MPI_INT, MPI_MIN, MPI_COMM_WORLD);
    return all;
}

static uint64_t fnv(const void *p, size_t n) {
    uint64_t h = 1469598103934665603ull;
    for (size_t i = 0; i < n; ++i) h = (h ^ ((const unsigned char *)p)[i]) * 1099511628211ull;
    return h;
}

/* 1 when every rank holds the same string. */
static int same_everywhere(const char *s) {
    uint64_t h = fnv(s, strlen(s)), lo, hi;
    MPI_Allreduce(&h, &lo, 1, MPI_UINT64_T, MPI_MIN, MPI_COMM_WORLD);
    MPI_Allreduce(&h, &hi, 1, MPI_UINT64_T, MPI_MAX, MPI_COMM_WORLD);
    return lo == hi;
}

/* ---- the scene, the same on every rank ---------------------------------- */

enum { kMeshes = 4 };
typedef struct {
    size_t n;
    uint64_t *id;         /* global id of body k */
    uint32_t *mesh;
    double *pos, *vel;    /* 3 per body */
    double *rot;          /* 4 per body (x, y, z, w) */
    double *spin;         /* per-tick turn, a unit quaternion (4 per body) */
    double *scale;
    uint8_t *live;
    double side;          /* tetra: the reflecting cube; 0 = free motion */
} scene;

static const double kTetraV[12] = {1, 1, 1, 1, -1, -1, -1, 1, -1, -1, -1, 1};
static const uint32_t kTetraT[12] = {0, 1, 2, 0, 3, 1, 0, 2, 3, 1, 3, 2};
static const double kCubeV[24] = {-1, -1, -1, 1, -1, -1, 1, 1, -1, -1, 1, -1,
                                  -1, -1, 1,  1, -1, 1,  1, 1, 1,  -1, 1, 1};
static const uint32_t kCubeT[36] = {0, 2, 1, 0, 3, 2, 4, 5, 6, 4, 6, 7, 0, 1, 5, 0, 5, 4,
                                    1, 2, 6, 1, 6, 5, 2, 3, 7, 2, 7, 6, 3, 0, 4, 3, 4, 7};
/* An open sheet (two triangles) and a non-convex mesh of two components
 * (two disjoint tetrahedra, one off-centre). */
static const double kSheetV[12] = {-1, -1, 0, 1, -1, 0, 1, 1, 0, -1, 1, 0};
static const uint32_t kSheetT[6] = {0, 1, 2, 0, 2, 3};
static const double kPairV[24] = {1, 1, 1, 1, -1, -1, -1, 1, -1, -1, -1, 1,
                                  3.5, 0.5, 0.5, 3.5, -0.5, -0.5, 2.5, 0.5, -0.5, 2.5, -0.5, 0.5};
static const uint32_t kPairT[24] = {0, 1, 2, 0, 3, 1, 0, 2, 3, 1, 3, 2, 4, 5, 6, 4, 7, 5, 4, 6, 7, 5, 7, 6};

static hgcd_mesh_desc mesh_desc(int m) {
    hgcd_mesh_desc d = hgcd_mesh_desc_default();
    const double *v[kMeshes] = {kTetraV, kCubeV, kSheetV, kPairV};
    const uint32_t *t[kMeshes] = {kTetraT, kCubeT, kSheetT, kPairT};
    const uint32_t nv[kMeshes] = {4, 8, 4, 8}, nt[kMeshes] = {4, 12, 2, 8};
    d.vertices = v[m], d.triangles = t[m], d.vertex_count = nv[m], d.triangle_count = nt[m];
    return d;
}

static uint64_t g_rng;
static double uniform(void) {
    g_rng = g_rng * 6364136223846793005ull + 1442695040888963407ull;
    return (double)(g_rng >> 11) * (1.0 / 9007199254740992.0);
}

static void normalise(double *q) {
    const double n = sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]);
    for (int i = 0; i < 4; ++i) q[i] /= n;
}

static void scene_alloc(scene *s, size_t n) {
    memset(s, 0, sizeof *s);
    s->n = n;
    s->id = calloc(n, sizeof *s->id);
    s->mesh = calloc(n, sizeof *s->mesh);
    s->pos = calloc(3 * n, sizeof(double));
    s->vel = calloc(3 * n, sizeof(double));
    s->rot = calloc(4 * n, sizeof(double));
    s->spin = calloc(4 * n, sizeof(double));
    s->scale = calloc(n, sizeof(double));
    s->live = calloc(n, 1);
    for (size_t k = 0; k < n; ++k) {
        s->id[k] = 1000 + 7 * (uint64_t)k; /* ids are not indices */
        s->spin[4 * k + 3] = 1;
        s->rot[4 * k + 3] = 1;
    }
}

static void scene_free(scene *s) {
    free(s->id), free(s->mesh), free(s->pos), free(s->vel), free(s->rot), free(s->spin), free(s->scale);
    free(s->live);
}

/* Scene `tetra` at density of the reference scene, faster motion. */
static void make_tetra(scene *s, size_t n) {
    scene_alloc(s, n);
    hgcd_scene_tetra_desc d = hgcd_scene_tetra_desc_default();
    d.n = n;
    d.side = 200.0 * cbrt((double)n / 750000.0);
    d.vmax = 0.6;
    assert_int_equal(hgcd_scene_tetra_generate(&d, s->pos, NULL, s->scale, s->rot, s->vel), 0);
    s->side = d.side;
    for (size_t k = 0; k < n; ++k) s->live[k] = 1;
}

/* Five drifting clusters of mixed meshes and sizes, and three bodies larger
 * than a subdomain (a cube, a sheet, a two-part mesh) crossing the scene. */
static void make_clustered(scene *s, size_t n) {
    scene_alloc(s, n + 40); /* 40 spare slots for bodies added later */
    g_rng = 12345;
    double centre[5][3], drift[5][3];
    for (int c = 0; c < 5; ++c)
        for (int a = 0; a < 3; ++a) {
            centre[c][a] = 10 + 30 * uniform();
            drift[c][a] = 1.6 * (uniform() - 0.5);
        }
    for (size_t k = 0; k < s->n; ++k) {
        const int c = (int)(k % 5);
        s->mesh[k] = (uint32_t)((k / 5) % kMeshes);
        for (int a = 0; a < 3; ++a) {
            const double g = uniform() + uniform() + uniform() - 1.5; /* about normal */
            s->pos[3 * k + a] = centre[c][a] + 4 * g;
            s->vel[3 * k + a] = drift[c][a] + 0.2 * (uniform() - 0.5);
        }
        s->scale[k] = 0.25 + 0.9 * uniform();
        for (int i = 0; i < 4; ++i) s->rot[4 * k + i] = uniform() - 0.5;
        normalise(&s->rot[4 * k]);
        const double ang = 0.08 * uniform();
        double axis[3] = {uniform() - 0.5, uniform() - 0.5, uniform() - 0.5};
        const double an = sqrt(axis[0] * axis[0] + axis[1] * axis[1] + axis[2] * axis[2]);
        for (int a = 0; a < 3; ++a) s->spin[4 * k + a] = sin(ang / 2) * axis[a] / an;
        s->spin[4 * k + 3] = cos(ang / 2);
        s->live[k] = k < n;
    }
    for (size_t k = 0; k < 3; ++k) { /* the big ones */
        s->mesh[k] = (uint32_t)(k == 0 ? 1 : k == 1 ? 2 : 3);
        s->scale[k] = k == 2 ? 6 : 14;
        s->pos[3 * k] = 5 + 15 * (double)k, s->pos[3 * k + 1] = 25, s->pos[3 * k + 2] = 25;
        s->vel[3 * k] = 1.5, s->vel[3 * k + 1] = -0.7, s->vel[3 * k + 2] = 0.3;
    }
}

static void quat_mul(const double *a, const double *b, double *out) {
    out[0] = a[3] * b[0] + a[0] * b[3] + a[1] * b[2] - a[2] * b[1];
    out[1] = a[3] * b[1] - a[0] * b[2] + a[1] * b[3] + a[2] * b[0];
    out[2] = a[3] * b[2] + a[0] * b[1] - a[1] * b[0] + a[2] * b[3];
    out[3] = a[3] * b[3] - a[0] * b[0] - a[1] * b[1] - a[2] * b[2];
}

static void scene_move(scene *s) {
    if (s->side > 0) {
        hgcd_scene_tetra_move(s->n, s->side, s->pos, s->vel);
        return;
    }
    for (size_t k = 0; k < 3 * s->n; ++k) s->pos[k] += s->vel[k];
    for (size_t k = 0; k < s->n; ++k) {
        double q[4];
        quat_mul(&s->rot[4 * k], &s->spin[4 * k], q);
        normalise(q);
        memcpy(&s->rot[4 * k], q, sizeof q);
    }
}

/* The body of an id (ids are 1000 + 7k). */
static size_t index_of(uint64_t id) { return (size_t)((id - 1000) / 7); }

/* ---- the reference: one hgcd world, every body -------------------------- */

typedef struct {
    hgcd_world *w;
    hgcd_mesh mesh[kMeshes];
    hgcd_body *body; /* per scene slot */
} reference;

static void ref_add(reference *r, const scene *s, size_t k) {
    hgcd_body_desc bd = hgcd_body_desc_default();
    bd.mesh = r->mesh[s->mesh[k]];
    memcpy(bd.position, &s->pos[3 * k], 24);
    memcpy(bd.orientation, &s->rot[4 * k], 32);
    bd.scale = s->scale[k];
    bd.user_data = s->id[k];
    assert_int_equal(hgcd_body_create(r->w, &bd, &r->body[k]), HGCD_OK);
}

static void ref_init(reference *r, const scene *s) {
    hgcd_world_desc wd = hgcd_world_desc_default();
    wd.thread_count = 1;
    assert_int_equal(hgcd_world_create(&wd, &r->w), HGCD_OK);
    for (int m = 0; m < kMeshes; ++m) {
        hgcd_mesh_desc md = mesh_desc(m);
        assert_int_equal(hgcd_mesh_create(r->w, &md, &r->mesh[m]), HGCD_OK);
    }
    r->body = calloc(s->n, sizeof *r->body);
    for (size_t k = 0; k < s->n; ++k)
        if (s->live[k]) ref_add(r, s, k);
}

/* The reference's pairs as sorted id pairs; the count goes to *count. */
static hgcd_mpi_pair *ref_pairs(reference *r, const scene *s, size_t *count) {
    for (size_t k = 0; k < s->n; ++k)
        if (s->live[k])
            assert_int_equal(hgcd_body_set_pose(r->w, r->body[k], &s->pos[3 * k], &s->rot[4 * k]), HGCD_OK);
    assert_int_equal(hgcd_world_detect(r->w), HGCD_OK);
    const hgcd_pair *p;
    assert_int_equal(hgcd_world_pairs(r->w, &p, count), HGCD_OK);
    hgcd_mpi_pair *out = malloc((*count + 1) * sizeof *out);
    for (size_t k = 0; k < *count; ++k) {
        uint64_t a, b;
        hgcd_body_get_user_data(r->w, p[k].a, &a);
        hgcd_body_get_user_data(r->w, p[k].b, &b);
        out[k].a = a < b ? a : b;
        out[k].b = a < b ? b : a;
    }
    return out;
}

static int cmp_pair(const void *x, const void *y) {
    const hgcd_mpi_pair *a = x, *b = y;
    if (a->a != b->a) return a->a < b->a ? -1 : 1;
    return a->b < b->b ? -1 : a->b > b->b;
}

/* ---- the distributed world ---------------------------------------------- */

static hgcd_mpi_world *dist_create(double allowance, double factor, uint32_t threads) {
    hgcd_mpi_world_desc d = hgcd_mpi_world_desc_default();
    d.thread_count = threads;
    d.motion_allowance = allowance;
    d.imbalance_factor = factor;
    hgcd_mpi_world *w = NULL;
    assert_int_equal(hgcd_mpi_world_create(MPI_COMM_WORLD, &d, &w), HGCD_OK);
    for (int m = 0; m < kMeshes; ++m) {
        hgcd_mesh_desc md = mesh_desc(m);
        uint32_t id;
        assert_int_equal(hgcd_mpi_mesh_register(w, &md, &id), HGCD_OK);
        assert_int_equal(id, (uint32_t)m);
    }
    return w;
}

static hgcd_mpi_body_desc body_desc(const scene *s, size_t k) {
    hgcd_mpi_body_desc d = hgcd_mpi_body_desc_default();
    d.id = s->id[k];
    d.mesh = s->mesh[k];
    memcpy(d.position, &s->pos[3 * k], 24);
    memcpy(d.orientation, &s->rot[4 * k], 32);
    d.scale = s->scale[k];
    return d;
}

/* Rank r adds the live bodies k with k % size == r (mostly owned elsewhere). */
static void dist_add_all(hgcd_mpi_world *w, const scene *s) {
    hgcd_mpi_body_desc *d = malloc((s->n + 1) * sizeof *d);
    size_t c = 0;
    for (size_t k = 0; k < s->n; ++k)
        if (s->live[k] && (int)(k % (size_t)g_size) == g_rank) d[c++] = body_desc(s, k);
    assert_int_equal(hgcd_mpi_bodies_add(w, d, c), HGCD_OK);
    free(d);
}

/* Each rank pushes its owned bodies' poses: by owned order on even ticks,
 * by ids (reversed) on odd ones. */
static void dist_push(hgcd_mpi_world *w, const scene *s, int tick) {
    const uint64_t *ids;
    size_t n;
    assert_int_equal(hgcd_mpi_owned(w, &ids, &n), HGCD_OK);
    double *pos = malloc((3 * n + 1) * sizeof(double)), *rot = malloc((4 * n + 1) * sizeof(double));
    uint64_t *rev = malloc((n + 1) * sizeof *rev);
    for (size_t j = 0; j < n; ++j) {
        const size_t e = tick % 2 ? n - 1 - j : j;
        const size_t k = index_of(ids[e]);
        rev[j] = ids[e];
        memcpy(&pos[3 * j], &s->pos[3 * k], 24);
        memcpy(&rot[4 * j], &s->rot[4 * k], 32);
    }
    assert_int_equal(hgcd_mpi_set_poses(w, tick % 2 ? rev : NULL, n, pos, 0, rot, 0), HGCD_OK);
    free(pos), free(rot), free(rev);
}

/* Detects and compares with the reference; returns the gathered pair count. */
static size_t check_tick(hgcd_mpi_world *w, reference *r, const scene *s) {
    assert_int_equal(hgcd_mpi_detect(w), HGCD_OK);
    const hgcd_mpi_pair *mine;
    size_t nm;
    assert_int_equal(hgcd_mpi_pairs(w, &mine, &nm), HGCD_OK);
    /* The owner rule: this rank owned the lower id at this detect. */
    const uint64_t *ids;
    size_t no;
    assert_int_equal(hgcd_mpi_owned(w, &ids, &no), HGCD_OK);
    int owner_ok = 1;
    for (size_t k = 0; k < nm && owner_ok; ++k) {
        int found = 0;
        for (size_t j = 0; j < no && !found; ++j) found = ids[j] == mine[k].a;
        owner_ok = found && mine[k].a < mine[k].b;
    }
    assert_true(all_ranks(owner_ok));
    const hgcd_mpi_pair *all;
    size_t na;
    assert_int_equal(hgcd_mpi_gather_pairs(w, 0, &all, &na), HGCD_OK);
    unsigned long long sum = 0, mine_ull = nm;
    MPI_Allreduce(&mine_ull, &sum, 1, MPI_UNSIGNED_LONG_LONG, MPI_SUM, MPI_COMM_WORLD);
    int ok = 1;
    unsigned long long total = na;
    if (g_rank == 0) {
        size_t nr;
        hgcd_mpi_pair *ref = ref_pairs(r, s, &nr);
        qsort(ref, nr, sizeof *ref, cmp_pair);
        ok = nr == na && sum == na && (na == 0 || memcmp(ref, all, na * sizeof *all) == 0);
        if (!ok) fprintf(stderr, "ranks %d: %zu pairs gathered (%llu reported), reference %zu\n", g_size, na, sum, nr);
        free(ref);
    } else {
        ok = na == 0;
    }
    assert_true(all_ranks(ok));
    MPI_Bcast(&total, 1, MPI_UNSIGNED_LONG_LONG, 0, MPI_COMM_WORLD);
    return (size_t)total;
}

/* 20 ticks of motion, checking every tick; with churn, bodies are removed
 * and added mid-way on ranks chosen without regard to ownership. */
static void run_scene(scene *s, double allowance, double factor, int churn, uint32_t threads) {
    reference r = {0};
    if (g_rank == 0) ref_init(&r, s);
    hgcd_mpi_world *w = dist_create(allowance, factor, threads);
    dist_add_all(w, s);
    size_t live = 0, pairs = 0;
    for (size_t k = 0; k < s->n; ++k) live += s->live[k];
    assert_int_equal(hgcd_mpi_world_body_count(w), live);
    uint64_t migrated = 0, ghosts = 0, rebalances = 0, by_index = 1;
    for (int tick = 0; tick < 20; ++tick) {
        if (tick > 0) {
            scene_move(s);
            dist_push(w, s, tick);
        }
        if (churn && tick == 8) {
            /* The last rank removes bodies 10, 20, ..., 200; rank 0 adds the
             * spare slots; body 3 (mid-size) goes and comes back at tick 12. */
            uint64_t gone[21];
            size_t c = 0;
            for (size_t k = 10; k <= 200; k += 10) gone[c++] = s->id[k];
            gone[c++] = s->id[3];
            const int remover = g_size - 1;
            assert_int_equal(hgcd_mpi_bodies_remove(w, g_rank == remover ? gone : NULL, g_rank == remover ? c : 0),
                             HGCD_OK);
            for (size_t j = 0; j < c; ++j) {
                const size_t k = index_of(gone[j]);
                s->live[k] = 0;
                if (g_rank == 0) hgcd_body_destroy(r.w, r.body[k]);
            }
            hgcd_mpi_body_desc add[40];
            size_t na = 0;
            for (size_t k = s->n - 40; k < s->n; ++k) {
                add[na++] = body_desc(s, k);
                s->live[k] = 1;
                if (g_rank == 0) ref_add(&r, s, k);
            }
            assert_int_equal(hgcd_mpi_bodies_add(w, g_rank == 0 ? add : NULL, g_rank == 0 ? na : 0), HGCD_OK);
            assert_int_equal(hgcd_mpi_world_body_count(w), live - c + 40);
        }
        if (churn && tick == 12) {
            hgcd_mpi_body_desc back = body_desc(s, 3);
            s->live[3] = 1;
            if (g_rank == 0) ref_add(&r, s, 3);
            assert_int_equal(hgcd_mpi_bodies_add(w, g_rank == g_size - 1 ? &back : NULL, g_rank == g_size - 1), HGCD_OK);
        }
        pairs += check_tick(w, &r, s);
        hgcd_mpi_stats st;
        st.struct_size = sizeof st;
        assert_int_equal(hgcd_mpi_stats_get(w, &st), HGCD_OK);
        migrated += st.migrated_in, ghosts += st.ghosts_received, rebalances += st.rebalanced;
        by_index &= st.poses_by_index;
    }
    /* The scene did what it is for: pairs, and with several ranks,
     * migration and ghosts (summed over the ranks). */
    uint64_t v[4] = {migrated, ghosts, rebalances, by_index}, t[4];
    MPI_Allreduce(v, t, 4, MPI_UINT64_T, MPI_SUM, MPI_COMM_WORLD);
    if (g_rank == 0)
        printf("# %d rank(s): %zu pairs over 20 ticks, %llu migrations, %llu ghost copies, %llu rebalances, "
               "poses by index on %llu rank(s)\n", g_size, pairs, (unsigned long long)t[0], (unsigned long long)t[1],
               (unsigned long long)(t[2] / g_size), (unsigned long long)t[3]);
    assert_true(pairs > 100);
    if (g_size > 1) assert_true(t[0] > 0 && t[1] > 0);
    hgcd_mpi_world_destroy(w);
    if (g_rank == 0) {
        hgcd_world_destroy(r.w);
        free(r.body);
    }
}

static void test_tetra(void **state) {
    (void)state;
    scene s;
    make_tetra(&s, 6000);
    run_scene(&s, 0, 1.2, 0, 2); /* 2 threads: the parallel loops over bodies */
    scene_free(&s);
}

static void test_clustered(void **state) {
    (void)state;
    scene s;
    make_clustered(&s, 1500);
    run_scene(&s, 0, 1.2, 1, 1);
    scene_free(&s);
}

/* A motion allowance and a tight balance factor (a rebalance every few ticks). */
static void test_clustered_allowance(void **state) {
    (void)state;
    scene s;
    make_clustered(&s, 1000);
    run_scene(&s, 1.5, 1.02, 1, 1);
    scene_free(&s);
}

/* ---- refusals ------------------------------------------------------------ */

/* A collective refusal: the same status and message on every rank. */
static void refused_everywhere(hgcd_mpi_world *w, hgcd_status got, hgcd_status want, const char *part) {
    const char *msg = hgcd_mpi_world_last_error(w);
    const int ok = got == want && strstr(msg, part) != NULL;
    if (!ok && g_rank == 0) fprintf(stderr, "got %d (%s), want %d with \"%s\"\n", got, msg, want, part);
    assert_true(all_ranks(ok));
    assert_true(same_everywhere(msg));
}

static size_t gather_copy(hgcd_mpi_world *w, hgcd_mpi_pair **out) {
    assert_int_equal(hgcd_mpi_detect(w), HGCD_OK);
    const hgcd_mpi_pair *p;
    size_t n;
    assert_int_equal(hgcd_mpi_gather_pairs(w, 0, &p, &n), HGCD_OK);
    *out = malloc((n + 1) * sizeof **out);
    if (n) memcpy(*out, p, n * sizeof *p);
    return n;
}

static void test_refusals(void **state) {
    (void)state;
    scene s;
    make_clustered(&s, 300);
    hgcd_mpi_world *w = dist_create(0, 1.2, 1);
    dist_add_all(w, &s);
    hgcd_mpi_pair *before;
    const size_t nbefore = gather_copy(w, &before);
    const uint64_t count = hgcd_mpi_world_body_count(w);
    const int last = g_size - 1;

    /* An id already live, added on the last rank. */
    hgcd_mpi_body_desc d = body_desc(&s, 5);
    refused_everywhere(w, hgcd_mpi_bodies_add(w, &d, g_rank == last), HGCD_ERROR_INVALID_ARGUMENT, "already live");
    /* A new id given twice (by two ranks, or twice by rank 0). */
    hgcd_mpi_body_desc twice[2] = {body_desc(&s, 5), body_desc(&s, 6)};
    twice[0].id = twice[1].id = 99999999;
    const size_t nt = g_size == 1 ? 2 : g_rank < 2;
    refused_everywhere(w, hgcd_mpi_bodies_add(w, twice, nt), HGCD_ERROR_INVALID_ARGUMENT, "given twice");
    /* A bad quaternion on rank 0 while the others add good bodies. */
    hgcd_mpi_body_desc fresh = body_desc(&s, 7);
    fresh.id = 88888888 + (uint64_t)g_rank;
    if (g_rank == 0) fresh.orientation[3] = 2;
    refused_everywhere(w, hgcd_mpi_bodies_add(w, &fresh, 1), HGCD_ERROR_INVALID_ARGUMENT, "entry 0");
    /* An unregistered mesh; an uninitialised descriptor; NULL with a count. */
    fresh = body_desc(&s, 7);
    fresh.id = 77777777;
    fresh.mesh = g_rank == last ? kMeshes : 0;
    refused_everywhere(w, hgcd_mpi_bodies_add(w, &fresh, g_rank == last), HGCD_ERROR_INVALID_ARGUMENT,
                       "not registered");
    fresh.mesh = 0;
    fresh.struct_size = 0;
    refused_everywhere(w, hgcd_mpi_bodies_add(w, &fresh, g_rank == 0), HGCD_ERROR_BAD_DESCRIPTOR, "entry 0");
    refused_everywhere(w, hgcd_mpi_bodies_add(w, NULL, g_rank == last), HGCD_ERROR_NULL_ARGUMENT, "NULL");
    /* Removing an id that is not live, or one id from two ranks. */
    uint64_t gone = 5;
    refused_everywhere(w, hgcd_mpi_bodies_remove(w, &gone, g_rank == 0), HGCD_ERROR_INVALID_ARGUMENT, "not live");
    gone = s.id[9];
    refused_everywhere(w, hgcd_mpi_bodies_remove(w, &gone, g_size == 1 ? 1 : g_rank < 2),
                       g_size == 1 ? HGCD_OK : HGCD_ERROR_INVALID_ARGUMENT, g_size == 1 ? "" : "given twice");
    if (g_size == 1) { /* put it back: the world must be as before */
        hgcd_mpi_body_desc back = body_desc(&s, 9);
        assert_int_equal(hgcd_mpi_bodies_add(w, &back, 1), HGCD_OK);
    }
    /* Mesh data differing between ranks. */
    if (g_size > 1) {
        hgcd_mesh_desc md = mesh_desc(g_rank == 1 ? 1 : 0);
        uint32_t id = 77;
        refused_everywhere(w, hgcd_mpi_mesh_register(w, &md, &id), HGCD_ERROR_INVALID_ARGUMENT, "differ");
        assert_int_equal(id, 77);
    }
    hgcd_mesh_desc md = mesh_desc(2);
    uint32_t id;
    assert_int_equal(hgcd_mpi_mesh_register(w, &md, &id), HGCD_OK);
    assert_int_equal(id, kMeshes);
    /* A gather's root out of range, or differing between ranks. */
    const hgcd_mpi_pair *p;
    size_t n;
    refused_everywhere(w, hgcd_mpi_gather_pairs(w, g_rank == last ? g_size : 0, &p, &n), HGCD_ERROR_INVALID_ARGUMENT,
                       "not a rank");
    if (g_size > 1)
        refused_everywhere(w, hgcd_mpi_gather_pairs(w, g_rank == last, &p, &n), HGCD_ERROR_INVALID_ARGUMENT, "differs");
    /* Local refusals: an id not owned here, a bad pose. */
    const uint64_t *ids;
    size_t no;
    assert_int_equal(hgcd_mpi_owned(w, &ids, &no), HGCD_OK);
    const double pos[3] = {1, 2, 3}, badq[4] = {0, 0, 0, 0.5};
    const uint64_t unknown = 6;
    assert_int_equal(hgcd_mpi_set_poses(w, &unknown, 1, pos, 0, NULL, 0), HGCD_ERROR_STALE_ID);
    assert_int_equal(hgcd_mpi_set_poses(w, NULL, no + 1, pos, 0, NULL, 0), HGCD_ERROR_STALE_ID);
    if (no) {
        assert_int_equal(hgcd_mpi_set_poses(w, ids, 1, pos, 0, badq, 0), HGCD_ERROR_INVALID_ARGUMENT);
        assert_non_null(strstr(hgcd_mpi_world_last_error(w), "set_poses"));
        /* By owned order (the by-index path): the last entry bad. */
        double *all = malloc(3 * no * sizeof(double));
        assert_int_equal(hgcd_mpi_get_poses(w, NULL, no, all, 0, NULL, 0), HGCD_OK);
        all[3 * no - 1] = NAN;
        assert_int_equal(hgcd_mpi_set_poses(w, NULL, no, all, 0, NULL, 0), HGCD_ERROR_INVALID_ARGUMENT);
        char want[64];
        snprintf(want, sizeof want, "entry %zu", no - 1);
        assert_non_null(strstr(hgcd_mpi_world_last_error(w), want));
        free(all);
    }
    /* Descriptors of the world: out of range, or differing between ranks. */
    hgcd_mpi_world_desc wd = hgcd_mpi_world_desc_default();
    hgcd_mpi_world *w2 = (hgcd_mpi_world *)1;
    wd.imbalance_factor = g_rank == last ? 0.5 : 1.2;
    assert_true(all_ranks(hgcd_mpi_world_create(MPI_COMM_WORLD, &wd, &w2) == HGCD_ERROR_INVALID_ARGUMENT && !w2));
    wd.imbalance_factor = 1.2 + g_rank;
    assert_true(all_ranks(hgcd_mpi_world_create(MPI_COMM_WORLD, &wd, &w2) ==
                          (g_size > 1 ? HGCD_ERROR_INVALID_ARGUMENT : HGCD_OK)));
    hgcd_mpi_world_destroy(w2);
    wd.struct_size = 0;
    assert_true(all_ranks(hgcd_mpi_world_create(MPI_COMM_WORLD, &wd, &w2) == HGCD_ERROR_BAD_DESCRIPTOR));

    /* Nothing changed. */
    assert_true(all_ranks(hgcd_mpi_world_body_count(w) == count));
    hgcd_mpi_pair *after;
    const size_t nafter = gather_copy(w, &after);
    assert_true(all_ranks(nafter == nbefore && memcmp(before, after, nafter * sizeof *after) == 0));
    free(before), free(after);
    hgcd_mpi_world_destroy(w);
    scene_free(&s);
}

int main(int argc, char **argv) {
    MPI_Init(&argc, &argv);
    MPI_Comm_rank(MPI_COMM_WORLD, &g_rank);
    MPI_Comm_size(MPI_COMM_WORLD, &g_size);
    /* Only rank 0 reports; the others' output would interleave. */
    if (g_rank != 0) cmocka_set_message_output(CM_OUTPUT_TAP), freopen("/dev/null", "w", stdout);
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_tetra),
        cmocka_unit_test(test_clustered),
        cmocka_unit_test(test_clustered_allowance),
        cmocka_unit_test(test_refusals),
    };
    const int failed = cmocka_run_group_tests(tests, NULL, NULL);
    MPI_Finalize();
    return failed;
}
