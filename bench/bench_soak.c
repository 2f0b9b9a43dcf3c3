/* bench_soak: a long run of a churning world through the public C API.
 *
 *   bench_soak [--ticks T] [--bodies N] [--churn K] [--check-every C]
 *              [--threads P] [--seed S]
 *
 * A world of about N bodies in a cube, on a few shared meshes (tetrahedron,
 * box, octahedron) and on meshes of their own (a random small closed mesh
 * made for the body and destroyed with it). Every tick K bodies are
 * destroyed and K created, every live body gets a new pose
 * (hgcd_body_set_pose: a random step and a new orientation), and the world
 * detects. It checks, and exits 1 at the first failure:
 *   - no id is ever handed out twice (per index, the generations' counters
 *     rise from one id to the next, bodies and meshes), and a destroyed id
 *     is refused;
 *   - every C-th tick, the pairs equal the brute-force GMP oracle's
 *     (tests/oracle.c) on every live body;
 *   - resident memory stays bounded: after the first tenth of the run, the
 *     resident set never exceeds its value then by more than 25% + 16 MB.
 * Prints one JSON line: ticks, bodies, churn, ids issued, oracle checks,
 * pairs checked, RSS at the first tenth and at most after, time per tick.
 * bench/soak.sh runs it (not part of make test: it takes minutes).
 */
#define _POSIX_C_SOURCE 200809L
#include <hgcd/hgcd.h>

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "../tests/oracle.h"

static double now_seconds(void) {
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

/* Resident set size in bytes, from /proc/self/statm. */
static double rss_bytes(void) {
    FILE *f = fopen("/proc/self/statm", "r");
    long pages = 0, resident = 0;
    if (!f) return 0;
    if (fscanf(f, "%ld %ld", &pages, &resident) != 2) resident = 0;
    fclose(f);
    return (double)resident * 4096.0;
}

static uint64_t rng_state;
static uint64_t next_u64(void) { /* splitmix64 */
    uint64_t z = (rng_state += 0x9E3779B97F4A7C15ull);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return z ^ (z >> 31);
}
static double uniform(void) { return (double)(next_u64() >> 11) * 0x1.0p-53; }

#define FAIL(...)                                         \
    do {                                                  \
        fprintf(stderr, "bench_soak: FAIL: " __VA_ARGS__); \
        fprintf(stderr, "\n");                            \
        exit(1);                                          \
    } while (0)

#define CHECK(w, call)                                                               \
    do {                                                                             \
        hgcd_status s_ = (call);                                                     \
        if (s_ != HGCD_OK)                                                           \
            FAIL("%s: %s (%s)", #call, hgcd_status_string(s_), hgcd_world_last_error(w)); \
    } while (0)

/* No id may be handed out twice: per index, the generations' counters (their
 * low 24 bits; the top byte is the world's tag) must rise from one id to the
 * next. Kept as the last counter per index, so the bench's own memory does
 * not grow with the ids issued. */
typedef struct {
    uint32_t *last;
    size_t cap;
    size_t issued;
} id_log;

static int id_log_issue(id_log *l, uint32_t index, uint32_t generation) { /* 0: an alias */
    const uint32_t counter = generation & 0xFFFFFFu;
    if (index >= l->cap) {
        size_t cap = l->cap ? l->cap : 1024;
        while (cap <= index) cap *= 2;
        uint32_t *grown = realloc(l->last, cap * sizeof *grown);
        if (!grown) FAIL("out of memory");
        memset(grown + l->cap, 0, (cap - l->cap) * sizeof *grown);
        l->last = grown;
        l->cap = cap;
    }
    ++l->issued;
    if (counter <= l->last[index]) return 0;
    l->last[index] = counter;
    return 1;
}

/* A mesh the bench keeps a copy of, for the oracle. */
typedef struct {
    double verts[3 * 14];
    uint32_t tris[3 * 24];
    oracle_mesh om;
    hgcd_mesh id;
} shape;

static void shape_finish(shape *m, uint32_t nv, uint32_t nt) {
    m->om.verts = m->verts;
    m->om.tris = m->tris;
    m->om.vertex_count = nv;
    m->om.triangle_count = nt;
    m->om.closed = 1;
}

static void make_tetra(shape *m) {
    static const double v[] = {1, 1, 1, 1, -1, -1, -1, 1, -1, -1, -1, 1};
    static const uint32_t t[] = {0, 1, 2, 0, 3, 1, 0, 2, 3, 1, 3, 2};
    memcpy(m->verts, v, sizeof v);
    memcpy(m->tris, t, sizeof t);
    shape_finish(m, 4, 4);
}

static void make_box(shape *m, double hx, double hy, double hz) {
    static const uint32_t t[] = {0, 2, 1, 1, 2, 3, 4, 5, 6, 5, 7, 6, 0, 1, 4, 1, 5, 4,
                                 2, 6, 3, 3, 6, 7, 0, 4, 2, 2, 4, 6, 1, 3, 5, 3, 7, 5};
    int i;
    for (i = 0; i < 8; ++i) {
        m->verts[3 * i + 0] = (i & 1) ? hx : -hx;
        m->verts[3 * i + 1] = (i & 2) ? hy : -hy;
        m->verts[3 * i + 2] = (i & 4) ? hz : -hz;
    }
    memcpy(m->tris, t, sizeof t);
    shape_finish(m, 8, 12);
}

/* An octahedron with its six vertices pushed in or out at random: closed,
 * usually non-convex, sometimes with coplanar or degenerate faces. */
static void make_octa(shape *m, int jitter) {
    static const uint32_t t[] = {0, 2, 4, 2, 1, 4, 1, 3, 4, 3, 0, 4, 2, 0, 5, 1, 2, 5, 3, 1, 5, 0, 3, 5};
    int i;
    for (i = 0; i < 6; ++i) {
        const double r = jitter ? 0.3 + 1.2 * uniform() : 1.0;
        m->verts[3 * i + 0] = m->verts[3 * i + 1] = m->verts[3 * i + 2] = 0;
        m->verts[3 * i + i / 2] = (i & 1) ? -r : r;
    }
    memcpy(m->tris, t, sizeof t);
    shape_finish(m, 6, 8);
}

static void create_mesh(hgcd_world *w, shape *m) {
    hgcd_mesh_desc md = hgcd_mesh_desc_default();
    md.vertices = m->verts;
    md.vertex_count = m->om.vertex_count;
    md.triangles = m->tris;
    md.triangle_count = m->om.triangle_count;
    CHECK(w, hgcd_mesh_create(w, &md, &m->id));
}

/* The bench's view of a live body. */
typedef struct {
    hgcd_body id;
    shape *mesh;
    int own_mesh;
    double position[3], orientation[4], scale;
} body;

static void random_orientation(double q[4]) {
    double n;
    do {
        int k;
        for (k = 0, n = 0; k < 4; ++k) {
            q[k] = 2 * uniform() - 1;
            n += q[k] * q[k];
        }
    } while (n < 0.01 || n > 1);
    n = sqrt(n);
    q[0] /= n, q[1] /= n, q[2] /= n, q[3] /= n;
}

/* The run's state: the world, the bench's own copy of every live body, and
 * what the checks keep between ticks. */
typedef struct {
    long ticks, nbodies, churn, check_every;
    int threads;
    double side;
    hgcd_world *w;
    shape shared[3];
    id_log body_ids, mesh_ids;
    body *live;
    long n;
    /* The oracle's inputs and pairs, and the slot-to-bench numbering, grown as needed. */
    const oracle_mesh **om;
    double *pos, *ori, *scl;
    uint32_t *index_of, *oracle_pairs;
    size_t index_cap, pairs_cap;
    long checks;
    uint64_t pairs_checked;
} soak;

static void parse_args(soak *s, int argc, char **argv, uint64_t *seed) {
    int i;
    s->ticks = 100000, s->nbodies = 2000, s->churn = 20, s->check_every = 1000, s->threads = 0;
    for (i = 1; i + 1 < argc; i += 2) {
        if (!strcmp(argv[i], "--ticks")) s->ticks = atol(argv[i + 1]);
        else if (!strcmp(argv[i], "--bodies")) s->nbodies = atol(argv[i + 1]);
        else if (!strcmp(argv[i], "--churn")) s->churn = atol(argv[i + 1]);
        else if (!strcmp(argv[i], "--check-every")) s->check_every = atol(argv[i + 1]);
        else if (!strcmp(argv[i], "--threads")) s->threads = atoi(argv[i + 1]);
        else if (!strcmp(argv[i], "--seed")) *seed = strtoull(argv[i + 1], NULL, 10);
        else {
            fprintf(stderr, "bench_soak: unknown option %s\n", argv[i]);
            exit(2);
        }
    }
    if (i != argc || s->ticks < 1 || s->nbodies < 2 || s->churn < 0 || s->churn > s->nbodies ||
        s->check_every < 1) {
        fprintf(stderr, "usage: bench_soak [--ticks T] [--bodies N] [--churn K] [--check-every C] "
                        "[--threads P] [--seed S]\n");
        exit(2);
    }
}

/* Destroys k random bodies (and the meshes of their own), checking their
 * ids are refused afterwards. */
static void destroy_some(soak *s, long k) {
    for (; k > 0 && s->n > 0; --k) {
        long j = (long)(next_u64() % (uint64_t)s->n);
        body b = s->live[j];
        CHECK(s->w, hgcd_body_destroy(s->w, b.id));
        if (hgcd_body_validate(s->w, b.id) == HGCD_OK) FAIL("a destroyed body id is still valid");
        if (b.own_mesh) {
            CHECK(s->w, hgcd_mesh_destroy(s->w, b.mesh->id));
            if (hgcd_mesh_validate(s->w, b.mesh->id) == HGCD_OK) FAIL("a destroyed mesh id is still valid");
            free(b.mesh);
        }
        s->live[j] = s->live[--s->n];
    }
}

/* Creates bodies up to N, a quarter on meshes of their own, checking that
 * no id is handed out twice. */
static void create_up_to_n(soak *s) {
    while (s->n < s->nbodies) {
        body *b = &s->live[s->n];
        hgcd_body_desc bd = hgcd_body_desc_default();
        int k;
        b->own_mesh = next_u64() % 4 == 0;
        if (b->own_mesh) {
            b->mesh = malloc(sizeof *b->mesh);
            if (!b->mesh) FAIL("out of memory");
            make_octa(b->mesh, 1);
            create_mesh(s->w, b->mesh);
            if (!id_log_issue(&s->mesh_ids, b->mesh->id.index, b->mesh->id.generation))
                FAIL("mesh id {%u, %u} handed out twice", b->mesh->id.index, b->mesh->id.generation);
        } else {
            b->mesh = &s->shared[next_u64() % 3];
        }
        for (k = 0; k < 3; ++k) b->position[k] = s->side * uniform();
        random_orientation(b->orientation);
        b->scale = 0.5 + uniform();
        bd.mesh = b->mesh->id;
        memcpy(bd.position, b->position, sizeof bd.position);
        memcpy(bd.orientation, b->orientation, sizeof bd.orientation);
        bd.scale = b->scale;
        CHECK(s->w, hgcd_body_create(s->w, &bd, &b->id));
        if (!id_log_issue(&s->body_ids, b->id.index, b->id.generation))
            FAIL("body id {%u, %u} handed out twice", b->id.index, b->id.generation);
        ++s->n;
    }
}

/* Every body takes a small random step (reflected into the cube) and a new
 * orientation, one hgcd_body_set_pose each. */
static void move_all(soak *s) {
    long k;
    for (k = 0; k < s->n; ++k) {
        body *b = &s->live[k];
        int a;
        for (a = 0; a < 3; ++a) {
            b->position[a] += 0.2 * (uniform() - 0.5);
            if (b->position[a] < 0) b->position[a] = -b->position[a];
            if (b->position[a] > s->side) b->position[a] = 2 * s->side - b->position[a];
        }
        random_orientation(b->orientation);
        CHECK(s->w, hgcd_body_set_pose(s->w, b->id, b->position, b->orientation));
    }
}

/* Whether (a, b) is in the sorted pair list of count entries. */
static int sorted_pairs_hold(const uint32_t *pairs, size_t count, uint32_t a, uint32_t b) {
    size_t lo = 0, hi = count;
    while (lo < hi) {
        const size_t q = (lo + hi) / 2;
        if (pairs[2 * q] < a || (pairs[2 * q] == a && pairs[2 * q + 1] < b))
            lo = q + 1;
        else
            hi = q;
    }
    return lo < count && pairs[2 * lo] == a && pairs[2 * lo + 1] == b;
}

/* The library's pairs must equal the oracle's on every live body. */
static void check_with_oracle(soak *s, long t) {
    const hgcd_pair *pp;
    size_t count, expect, m;
    long k;
    CHECK(s->w, hgcd_world_pairs(s->w, &pp, &count));
    /* The oracle numbers bodies 0..n-1 in the bench's order; map the
     * library's slot indices to those. */
    uint32_t max_index = 0;
    for (k = 0; k < s->n; ++k)
        if (s->live[k].id.index > max_index) max_index = s->live[k].id.index;
    if (max_index + 1 > s->index_cap) {
        s->index_cap = 2 * (size_t)(max_index + 1);
        s->index_of = realloc(s->index_of, s->index_cap * sizeof *s->index_of);
        if (!s->index_of) FAIL("out of memory");
    }
    for (k = 0; k < s->n; ++k) {
        s->index_of[s->live[k].id.index] = (uint32_t)k;
        s->om[k] = &s->live[k].mesh->om;
        memcpy(s->pos + 3 * k, s->live[k].position, 3 * sizeof *s->pos);
        memcpy(s->ori + 4 * k, s->live[k].orientation, 4 * sizeof *s->ori);
        s->scl[k] = s->live[k].scale;
    }
    expect = oracle_colliding_pairs((size_t)s->n, s->om, s->pos, s->ori, s->scl, NULL, 0);
    if (expect > s->pairs_cap) {
        s->pairs_cap = 2 * expect + 16;
        s->oracle_pairs = realloc(s->oracle_pairs, 2 * s->pairs_cap * sizeof *s->oracle_pairs);
        if (!s->oracle_pairs) FAIL("out of memory");
    }
    oracle_colliding_pairs((size_t)s->n, s->om, s->pos, s->ori, s->scl, s->oracle_pairs, s->pairs_cap);
    if (count != expect) FAIL("tick %ld: %zu pairs, the oracle finds %zu", t, count, expect);
    /* Same count, and every library pair (in the bench's numbering) is one
     * of the oracle's sorted pairs: the lists are equal. */
    for (m = 0; m < count; ++m) {
        const uint32_t a = s->index_of[pp[m].a.index], b = s->index_of[pp[m].b.index];
        if (!sorted_pairs_hold(s->oracle_pairs, expect, a < b ? a : b, a < b ? b : a))
            FAIL("tick %ld: pair (%u, %u) is not the oracle's", t, a < b ? a : b, a < b ? b : a);
    }
    ++s->checks;
    s->pairs_checked += count;
}

int main(int argc, char **argv) {
    soak s = {0};
    uint64_t seed = 1;
    int i;
    parse_args(&s, argc, argv, &seed);
    rng_state = seed;
    /* The cube holds about one body per 12 unit cubes: many touching pairs. */
    s.side = cbrt(12.0 * (double)s.nbodies);

    hgcd_world_desc wd = hgcd_world_desc_default();
    wd.thread_count = (uint32_t)s.threads;
    CHECK(s.w, hgcd_world_create(&wd, &s.w));
    make_tetra(&s.shared[0]);
    make_box(&s.shared[1], 1.0, 0.5, 0.25);
    make_octa(&s.shared[2], 0);
    for (i = 0; i < 3; ++i) {
        create_mesh(s.w, &s.shared[i]);
        if (!id_log_issue(&s.mesh_ids, s.shared[i].id.index, s.shared[i].id.generation))
            FAIL("mesh id handed out twice");
    }
    const size_t nb = (size_t)s.nbodies;
    s.live = calloc(nb, sizeof *s.live);
    s.om = calloc(nb, sizeof *s.om);
    s.pos = calloc(3 * nb, sizeof *s.pos), s.ori = calloc(4 * nb, sizeof *s.ori), s.scl = calloc(nb, sizeof *s.scl);
    if (!s.live || !s.om || !s.pos || !s.ori || !s.scl) FAIL("out of memory");

    double rss_tenth = 0, rss_max = 0, t0 = now_seconds(), detect_s = 0;
    long t;
    for (t = 0; t < s.ticks; ++t) {
        destroy_some(&s, t == 0 ? 0 : s.churn);
        create_up_to_n(&s);
        move_all(&s);
        const double d0 = now_seconds();
        CHECK(s.w, hgcd_world_detect(s.w));
        detect_s += now_seconds() - d0;
        if ((t + 1) % s.check_every == 0 || t + 1 == s.ticks) check_with_oracle(&s, t);
        /* Resident memory: bounded after the first tenth. */
        if (t + 1 == (s.ticks + 9) / 10) rss_tenth = rss_bytes();
        if (t + 1 > (s.ticks + 9) / 10 && (t + 1) % 100 == 0) {
            const double r = rss_bytes();
            if (r > rss_max) rss_max = r;
            if (r > 1.25 * rss_tenth + 16e6)
                FAIL("tick %ld: resident memory %.1f MB, %.1f MB after the first tenth", t, r / 1e6, rss_tenth / 1e6);
        }
        if ((t + 1) % 10000 == 0)
            fprintf(stderr, "bench_soak: tick %ld, %zu ids, %ld oracle checks, RSS %.1f MB\n", t + 1,
                    s.body_ids.issued + s.mesh_ids.issued, s.checks, rss_bytes() / 1e6);
    }
    const double total = now_seconds() - t0;
    printf("{\"bench\":\"soak\",\"ticks\":%ld,\"bodies\":%ld,\"churn\":%ld,\"threads\":%d,\"seed\":%llu,"
           "\"ids_issued\":%zu,\"oracle_checks\":%ld,\"pairs_checked\":%llu,\"rss_tenth_mb\":%.1f,"
           "\"rss_max_after_mb\":%.1f,\"tick_ms\":%.3f,\"detect_ms\":%.3f,\"seconds\":%.1f}\n",
           s.ticks, s.nbodies, s.churn, s.threads, (unsigned long long)seed, s.body_ids.issued + s.mesh_ids.issued,
           s.checks, (unsigned long long)s.pairs_checked, rss_tenth / 1e6, rss_max / 1e6,
           1e3 * total / (double)s.ticks, 1e3 * detect_s / (double)s.ticks, total);

    for (i = 0; i < s.n; ++i)
        if (s.live[i].own_mesh) free(s.live[i].mesh);
    hgcd_world_destroy(s.w);
    free(s.live), free(s.om), free(s.pos), free(s.ori), free(s.scl), free(s.index_of), free(s.oracle_pairs);
    free(s.body_ids.last), free(s.mesh_ids.last);
    return 0;
}
