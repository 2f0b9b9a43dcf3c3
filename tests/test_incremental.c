/* The detect that searches around the moved bodies alone (few moved since
 * the last detect: src/world/incremental.cpp) against full detects and the
 * oracle. World A is driven as an engine drives it: each tick a random share
 * of the bodies moves (none, a few, one in ten, a third, all), by small
 * steps or jumps, position or orientation alone; bodies are destroyed and
 * created (indices reused); now and then a step. World B gets the same calls
 * but tests everything afresh (a narrow-phase call before each detect ends
 * temporal coherence). Their pairs must agree every tick, on 1 and 2
 * threads, and a smaller world's pairs must equal the oracle's. Bodies of
 * every kind the grid handles: small meshes of several sizes (levels), a
 * large closed box holding others (containment), bodies larger than the
 * coarsest cell (oversize, by max_cell_size) and far away (oversize by
 * their coordinates). */
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

#include "oracle.h"
#include "test_rng.h"

enum { kMaxBodies = 2400, kShapes = 3 };

/* A closed octahedron, a unit tetrahedron and a closed box (the box, scaled
 * up, holds other bodies). */
static const double kOctaV[18] = {1, 0, 0, -1, 0, 0, 0, 1, 0, 0, -1, 0, 0, 0, 1, 0, 0, -1};
static const uint32_t kOctaT[24] = {0, 2, 4, 2, 1, 4, 1, 3, 4, 3, 0, 4, 2, 0, 5, 1, 2, 5, 3, 1, 5, 0, 3, 5};
static const double kTetraV[12] = {1, 1, 1, 1, -1, -1, -1, 1, -1, -1, -1, 1};
static const uint32_t kTetraT[12] = {0, 1, 2, 0, 3, 1, 0, 2, 3, 1, 3, 2};
static const double kBoxV[24] = {-1, -1, -1, 1, -1, -1, -1, 1, -1, 1, 1, -1, -1, -1, 1, 1, -1, 1, -1, 1, 1, 1, 1, 1};
static const uint32_t kBoxT[36] = {0, 2, 1, 1, 2, 3, 4, 5, 6, 5, 7, 6, 0, 1, 4, 1, 5, 4,
                                   2, 6, 3, 3, 6, 7, 0, 4, 2, 2, 4, 6, 1, 3, 5, 3, 7, 5};
static const oracle_mesh kOracleMesh[kShapes] = {
    {kOctaV, kOctaT, 6, 8, 1}, {kTetraV, kTetraT, 4, 4, 1}, {kBoxV, kBoxT, 8, 12, 1}};

/* The caller's bodies: test body i is hgcd body id[i] in each world. */
typedef struct {
    hgcd_world *w[2]; /* A (coherent), B (full) */
    hgcd_mesh mesh[2][kShapes];
    hgcd_body id[2][kMaxBodies];
    int live[kMaxBodies], shape[kMaxBodies];
    int is_static[kMaxBodies], disabled[kMaxBodies]; /* (run_static) */
    double pos[kMaxBodies][3], ori[kMaxBodies][4], scale[kMaxBodies];
    int n;
    double side;
    rng r;
} scene;

static void scene_init(scene *sc, int n, double side, uint32_t threads, uint64_t seed) {
    memset(sc, 0, sizeof *sc);
    sc->n = n;
    sc->side = side;
    sc->r.s = seed;
    for (int k = 0; k < 2; ++k) {
        hgcd_world_desc d = hgcd_world_desc_default();
        d.thread_count = threads;
        d.max_cell_size = 4; /* the large boxes are oversize */
        assert_int_equal(hgcd_world_create(&d, &sc->w[k]), HGCD_OK);
        for (int m = 0; m < kShapes; ++m) {
            hgcd_mesh_desc md = hgcd_mesh_desc_default();
            md.vertices = kOracleMesh[m].verts;
            md.vertex_count = kOracleMesh[m].vertex_count;
            md.triangles = kOracleMesh[m].tris;
            md.triangle_count = kOracleMesh[m].triangle_count;
            assert_int_equal(hgcd_mesh_create(sc->w[k], &md, &sc->mesh[k][m]), HGCD_OK);
        }
    }
}

static void scene_free(scene *sc) {
    hgcd_world_destroy(sc->w[0]);
    hgcd_world_destroy(sc->w[1]);
}

/* A new pose for body i: a small step from where it is (pairs that stay
 * close), or a jump anywhere; position or orientation alone now and then. */
static void new_pose(scene *sc, int i, int small) {
    rng *r = &sc->r;
    const unsigned what = (unsigned)(next(r) % 4); /* 0: position alone, 1: orientation alone */
    if (what != 1) {
        const int far = sc->pos[i][2] > 1e12;
        const double old = sc->pos[i][0];
        for (int k = 0; k < 3; ++k)
            sc->pos[i][k] = small ? sc->pos[i][k] + 0.1 * (unif(r) - 0.5) : sc->side * unif(r);
        if (far && !small) sc->pos[i][2] += 1e13;
        if (sc->pos[i][0] == old) sc->pos[i][0] = nextafter(old, INFINITY); /* (moved: other bits) */
    }
    if (what != 0) {
        double q[4];
        do random_unit_quaternion(r, q);
        while (memcmp(q, sc->ori[i], sizeof q) == 0);
        memcpy(sc->ori[i], q, sizeof q);
    }
}

static void create(scene *sc, int i) {
    rng *r = &sc->r;
    /* one in 60 a large box (oversize, holds others), one in 400 far away */
    sc->shape[i] = i % 60 == 0 ? 2 : (int)(next(r) % 2);
    sc->scale[i] = i % 60 == 0 ? 3.0 : 0.3 + 0.9 * unif(r);
    for (int k = 0; k < 3; ++k) sc->pos[i][k] = sc->side * unif(r);
    if (i % 400 == 7) sc->pos[i][2] = 1e13 + sc->side * unif(r); /* oversize by its coordinates */
    random_unit_quaternion(r, sc->ori[i]);
    for (int k = 0; k < 2; ++k) {
        hgcd_body_desc bd = hgcd_body_desc_default();
        bd.mesh = sc->mesh[k][sc->shape[i]];
        bd.scale = sc->scale[i];
        memcpy(bd.position, sc->pos[i], sizeof bd.position);
        memcpy(bd.orientation, sc->ori[i], sizeof bd.orientation);
        bd.velocity[0] = 0.01;
        bd.type = sc->is_static[i] == 1 ? HGCD_BODY_STATIC : HGCD_BODY_DYNAMIC;
        assert_int_equal(hgcd_body_create(sc->w[k], &bd, &sc->id[k][i]), HGCD_OK);
    }
    assert_int_equal(sc->id[0][i].index, sc->id[1][i].index);
    sc->live[i] = 1;
    sc->disabled[i] = 0;
}

static void destroy(scene *sc, int i) {
    for (int k = 0; k < 2; ++k) assert_int_equal(hgcd_body_destroy(sc->w[k], sc->id[k][i]), HGCD_OK);
    sc->live[i] = 0;
}

/* Every live body's pose handed over (the unmoved ones with the same bits),
 * by one batch call, one call per body, or, for the moved ones only
 * (moved[i]), a batch by ids. */
static void push_poses(scene *sc, const int *moved, unsigned how) {
    static hgcd_body ids[2][kMaxBodies];
    static double p[kMaxBodies][3], q[kMaxBodies][4];
    for (int k = 0; k < 2; ++k) {
        size_t count = 0;
        for (int i = 0; i < sc->n; ++i) {
            if (!sc->live[i] || (how == 2 && !moved[i])) continue;
            if (how == 1) {
                assert_int_equal(hgcd_body_set_pose(sc->w[k], sc->id[k][i], sc->pos[i], sc->ori[i]), HGCD_OK);
                continue;
            }
            ids[k][count] = sc->id[k][i];
            memcpy(p[count], sc->pos[i], sizeof p[count]);
            memcpy(q[count], sc->ori[i], sizeof q[count]);
            ++count;
        }
        if (how != 1) assert_int_equal(hgcd_world_set_poses(sc->w[k], ids[k], count, p[0], 0, q[0], 0), HGCD_OK);
    }
}

static hgcd_stats stats_of(hgcd_world *w) {
    hgcd_stats s;
    s.struct_size = sizeof s;
    assert_int_equal(hgcd_world_stats(w, &s), HGCD_OK);
    return s;
}

/* A's pairs equal B's (indices and generations). Returns the count. */
static size_t same_pairs(scene *sc) {
    const hgcd_pair *pa, *pb;
    size_t na, nb;
    assert_int_equal(hgcd_world_pairs(sc->w[0], &pa, &na), HGCD_OK);
    assert_int_equal(hgcd_world_pairs(sc->w[1], &pb, &nb), HGCD_OK);
    assert_int_equal(na, nb);
    for (size_t k = 0; k < na; ++k) {
        assert_int_equal(pa[k].a.index, pb[k].a.index);
        assert_int_equal(pa[k].b.index, pb[k].b.index);
        assert_int_equal(pa[k].a.generation & 0xFFFFFF, pb[k].a.generation & 0xFFFFFF);
        assert_int_equal(pa[k].b.generation & 0xFFFFFF, pb[k].b.generation & 0xFFFFFF);
    }
    return na;
}

static int cmp_pair(const void *x, const void *y) {
    const uint32_t *a = x, *b = y;
    return a[0] != b[0] ? (a[0] > b[0]) - (a[0] < b[0]) : (a[1] > b[1]) - (a[1] < b[1]);
}

/* A's pairs equal the oracle's at the caller's poses. */
static void oracle_check(scene *sc) {
    static const oracle_mesh *meshes[kMaxBodies];
    static double p[kMaxBodies][3], q[kMaxBodies][4], s[kMaxBodies];
    static uint32_t index[kMaxBodies], expect[2 * kMaxBodies * 8];
    size_t live = 0;
    static int still[kMaxBodies];
    for (int i = 0; i < sc->n; ++i) {
        if (!sc->live[i] || sc->disabled[i]) continue;
        still[live] = sc->is_static[i] == 1;
        meshes[live] = &kOracleMesh[sc->shape[i]];
        memcpy(p[live], sc->pos[i], sizeof p[live]);
        memcpy(q[live], sc->ori[i], sizeof q[live]);
        s[live] = sc->scale[i];
        index[live++] = sc->id[0][i].index;
    }
    const size_t all = oracle_colliding_pairs(live, meshes, p[0], q[0], s, expect, sizeof expect / (2 * sizeof *expect));
    assert_true(all <= sizeof expect / (2 * sizeof *expect));
    size_t n = 0;
    for (size_t k = 0; k < all; ++k) { /* to hgcd's indices, a < b, sorted; no static-static pair */
        if (still[expect[2 * k]] && still[expect[2 * k + 1]]) continue;
        const uint32_t a = index[expect[2 * k]], b = index[expect[2 * k + 1]];
        expect[2 * n] = a < b ? a : b;
        expect[2 * n + 1] = a < b ? b : a;
        ++n;
    }
    qsort(expect, n, 2 * sizeof *expect, cmp_pair);
    const hgcd_pair *got;
    size_t count;
    assert_int_equal(hgcd_world_pairs(sc->w[0], &got, &count), HGCD_OK);
    assert_int_equal(count, n);
    for (size_t k = 0; k < n; ++k) {
        assert_int_equal(got[k].a.index, expect[2 * k]);
        assert_int_equal(got[k].b.index, expect[2 * k + 1]);
    }
}

/* The shares of bodies moved in a tick. */
static const double kShares[] = {0, 0.002, 0.02, 0.1, 0.1, 0.2, 0.35, 1};

static void run(int n, double side, uint32_t threads, int ticks, int oracle_every, uint64_t seed) {
    static scene sc;
    scene_init(&sc, n, side, threads, seed);
    for (int i = 0; i < n; ++i) create(&sc, i);
    static int moved[kMaxBodies];
    int incremental = 0, full = 0, oracle_checks = 0, oversize = 0;
    uint64_t kept = 0;
    for (int tick = 0; tick < ticks; ++tick) {
        rng *r = &sc.r;
        const double share = tick == 0 ? 0 : kShares[next(r) % (sizeof kShares / sizeof kShares[0])];
        const int small = (int)(next(r) % 2);
        int expect_moved = 0;
        for (int i = 0; i < n; ++i) {
            moved[i] = sc.live[i] && unif(r) < share;
            if (moved[i]) new_pose(&sc, i, small);
        }
        push_poses(&sc, moved, (unsigned)(next(r) % 3));
        for (int i = 0; i < n; ++i) expect_moved += moved[i];
        /* Deaths and births (reused indices) now and then, or a step. */
        if (tick % 5 == 4)
            for (int i = (int)(next(r) % 37); i < n; i += 37) {
                if (sc.live[i]) destroy(&sc, i);
                expect_moved -= moved[i];
                moved[i] = 0;
                if (next(r) % 2) {
                    create(&sc, i);
                    ++expect_moved;
                    moved[i] = 1;
                }
            }
        const int step = tick % 11 == 10;
        assert_int_equal(hgcd_world_set_narrow_phase(sc.w[1], HGCD_NARROW_EXACT), HGCD_OK);
        for (int k = 0; k < 2; ++k)
            assert_int_equal(step ? hgcd_world_step(sc.w[k]) : hgcd_world_detect(sc.w[k]), HGCD_OK);
        if (step) /* the caller learns the poses the step made */
            for (int i = 0; i < n; ++i)
                if (sc.live[i]) assert_int_equal(hgcd_body_get_pose(sc.w[0], sc.id[0][i], sc.pos[i], sc.ori[i]), HGCD_OK);
        same_pairs(&sc);
        if (oracle_every && tick % oracle_every == 0) {
            oracle_check(&sc);
            ++oracle_checks;
        }
        const hgcd_stats sa = stats_of(sc.w[0]), sb = stats_of(sc.w[1]);
        assert_int_equal(sa.colliding_pairs, sb.colliding_pairs);
        oversize += sb.oversize_count > 0;
        assert_true(sa.narrow_tests + sa.unmoved_pairs <= sa.candidate_pairs || sa.candidate_pairs == 0);
        if (sa.searched_bodies < sb.searched_bodies && sa.searched_bodies > 0) {
            /* searched around the moved and born bodies alone */
            assert_false(step);
            assert_int_equal(sa.searched_bodies, expect_moved);
            assert_true(sa.candidate_pairs >= sa.colliding_pairs);
            kept += sa.unmoved_pairs;
            ++incremental;
        } else if (sa.searched_bodies == sb.searched_bodies) {
            ++full;
        }
    }
    /* Both paths ran, and the search around the moved bodies often. */
    assert_true(incremental >= ticks / 4);
    assert_true(full >= ticks / 10);
    assert_true(kept > 0);
    assert_true(oversize > ticks / 2);
    assert_true(oracle_every == 0 || oracle_checks > 0);
    scene_free(&sc);
}

/* HGCD_SKIP_SLOW_TESTS (sanitizer and valgrind runs): smaller worlds. */
static int slow(void) { return getenv("HGCD_SKIP_SLOW_TESTS") == NULL; }

/* A world mostly of static bodies, as a level's geometry: one body in eight
 * dynamic, moving every tick by a small step along its own direction (so
 * that most ticks its box stays within the margin around the box it
 * searched the grid with last: its list of residents is reused), now and
 * then a jump. Between detects the static bodies change: one is moved, one
 * destroyed and another created static, one made dynamic for a tick and
 * static again, one disabled and later enabled; the large boxes (oversize)
 * are static or dynamic. A's pairs equal B's every tick and the oracle's
 * (less the static-static pairs) every few ticks. */
static void set_type(scene *sc, int i, int is_static) {
    for (int k = 0; k < 2; ++k)
        assert_int_equal(hgcd_body_set_type(sc->w[k], sc->id[k][i], is_static ? HGCD_BODY_STATIC : HGCD_BODY_DYNAMIC),
                         HGCD_OK);
    sc->is_static[i] = is_static;
}

static void set_enabled(scene *sc, int i, int enabled) {
    for (int k = 0; k < 2; ++k) assert_int_equal(hgcd_body_set_enabled(sc->w[k], sc->id[k][i], enabled), HGCD_OK);
    sc->disabled[i] = !enabled;
}

static void run_static(int n, double side, uint32_t threads, int ticks, int oracle_every, uint64_t seed) {
    static scene sc;
    static double dir[kMaxBodies][3];
    static int moved[kMaxBodies];
    scene_init(&sc, n, side, threads, seed);
    for (int i = 0; i < n; ++i) {
        sc.is_static[i] = i % 8 != 3;
        create(&sc, i);
        for (int k = 0; k < 3; ++k) dir[i][k] = 0.04 * (unif(&sc.r) - 0.5);
    }
    int incremental = 0, oracle_checks = 0, type_flips = 0;
    for (int tick = 0; tick < ticks; ++tick) {
        rng *r = &sc.r;
        for (int i = 0; i < n; ++i) {
            moved[i] = sc.live[i] && !sc.is_static[i] && tick > 0;
            if (!moved[i]) continue;
            if (next(r) % 50 == 0) {
                new_pose(&sc, i, 0);
            } else {
                for (int k = 0; k < 3; ++k) sc.pos[i][k] += dir[i][k];
                if (sc.pos[i][0] == sc.pos[i][0] + dir[i][0]) sc.pos[i][0] = nextafter(sc.pos[i][0], INFINITY);
            }
        }
        push_poses(&sc, moved, (unsigned)(next(r) % 3));
        /* The static bodies change between detects. */
        const int a = (int)(next(r) % (uint64_t)n), b = (int)(next(r) % (uint64_t)n), c = (int)(next(r) % (uint64_t)n);
        switch (tick % 6) {
        case 1: /* a static body moved (by a small step or a jump) */
            if (sc.live[a] && sc.is_static[a] == 1) {
                new_pose(&sc, a, (int)(next(r) % 2));
                for (int k = 0; k < 2; ++k)
                    assert_int_equal(hgcd_body_set_pose(sc.w[k], sc.id[k][a], sc.pos[a], sc.ori[a]), HGCD_OK);
            }
            break;
        case 2: /* one destroyed, another created static (indices reused) */
            if (sc.live[a] && sc.is_static[a] == 1) destroy(&sc, a);
            if (!sc.live[b]) {
                sc.is_static[b] = 1;
                create(&sc, b);
            }
            break;
        case 3: /* made dynamic for a tick, or static again; disabled or enabled */
            for (int i = 0; i < n; ++i)
                if (sc.live[i] && sc.is_static[i] == 2) set_type(&sc, i, 1);
            if (sc.live[b] && sc.is_static[b] == 1) {
                set_type(&sc, b, 0);
                sc.is_static[b] = 2; /* (dynamic, unmoved: static again next time) */
                ++type_flips;
            }
            if (sc.live[c]) set_enabled(&sc, c, sc.disabled[c]);
            break;
        default:
            break;
        }
        assert_int_equal(hgcd_world_set_narrow_phase(sc.w[1], HGCD_NARROW_EXACT), HGCD_OK);
        for (int k = 0; k < 2; ++k) assert_int_equal(hgcd_world_detect(sc.w[k]), HGCD_OK);
        same_pairs(&sc);
        if (tick % oracle_every == 0) {
            oracle_check(&sc);
            ++oracle_checks;
        }
        const hgcd_stats sa = stats_of(sc.w[0]), sb = stats_of(sc.w[1]);
        assert_int_equal(sa.colliding_pairs, sb.colliding_pairs);
        incremental += sa.searched_bodies < sb.searched_bodies;
    }
    assert_true(incremental >= ticks / 2);
    assert_true(oracle_checks > 0 && type_flips > 0);
    scene_free(&sc);
}

/* Moved bodies crowded into one part of storage: bodies created in one
 * go take storage at its end, so that on 2 threads the second range holds
 * more moved bodies than count_moved keeps (a quarter of a range) and
 * list_moved finds them again; then those bodies and a few others move by
 * small steps (the second range still the crowded one). A's pairs equal
 * B's and the oracle's every tick, each detect a search around the moved
 * bodies. */
static void run_crowded(int n, int born, double side, uint32_t threads, uint64_t seed) {
    static scene sc;
    static int moved[kMaxBodies];
    scene_init(&sc, n + born, side, threads, seed);
    sc.n = n;
    for (int k = 0; k < 2; ++k) /* (a small world would get one thread) */
        assert_int_equal(hgcd_world_set_thread_policy(sc.w[k], HGCD_THREADS_FIXED), HGCD_OK);
    for (int i = 0; i < n; ++i) create(&sc, i);
    for (int k = 0; k < 2; ++k) assert_int_equal(hgcd_world_detect(sc.w[k]), HGCD_OK);
    for (int tick = 0; tick < 4; ++tick) {
        if (tick == 0) {
            for (int i = n; i < n + born; ++i) create(&sc, i);
            sc.n = n + born;
        } else {
            for (int i = 0; i < sc.n; ++i) {
                moved[i] = i >= n || i % 50 == 0;
                if (moved[i]) new_pose(&sc, i, 1);
            }
            push_poses(&sc, moved, 2);
        }
        assert_int_equal(hgcd_world_set_narrow_phase(sc.w[1], HGCD_NARROW_EXACT), HGCD_OK);
        for (int k = 0; k < 2; ++k) assert_int_equal(hgcd_world_detect(sc.w[k]), HGCD_OK);
        same_pairs(&sc);
        oracle_check(&sc);
        const hgcd_stats sa = stats_of(sc.w[0]), sb = stats_of(sc.w[1]);
        assert_true(sa.searched_bodies > 0 && sa.searched_bodies < sb.searched_bodies);
    }
    scene_free(&sc);
}

/* Static bodies stored after the moving ones: world A's storage is
 * renumbered with its static bodies after the others (src/world/motion.cpp)
 * and its dynamic bodies, slots 0 .. d-1, get their poses by index
 * (hgcd_world_set_poses without ids, count d), whose pass skips eight
 * stored bodies at a time when none is named; B gets them by id. A third
 * of the dynamic bodies (half the world) move each tick, so that searches
 * around the moved bodies and grid updates alternate; now and then half
 * of them jump (a grid update that leaves its order far from storage's,
 * so that A renumbers again); between detects static
 * bodies are moved, destroyed and created (their indices reused), made
 * dynamic for a while (stored among the static ones until the next
 * renumbering) and back, disabled and enabled. A's pairs equal B's every
 * tick and the oracle's every other tick, on 1 and 2 threads. */
static void run_static_runs(int n, int d, double side, uint32_t threads, int ticks, uint64_t seed) {
    static scene sc;
    static int moved[kMaxBodies];
    scene_init(&sc, n, side, threads, seed);
    for (int k = 0; k < 2; ++k) /* (a small world would get one thread) */
        assert_int_equal(hgcd_world_set_thread_policy(sc.w[k], HGCD_THREADS_FIXED), HGCD_OK);
    for (int i = 0; i < n; ++i) {
        sc.is_static[i] = i >= d;
        create(&sc, i);
    }
    int jumps = 0, flips = 0, incremental = 0;
    for (int tick = 0; tick < ticks; ++tick) {
        rng *r = &sc.r;
        const int jump = tick % 7 == 3;
        for (int i = 0; i < d; ++i) {
            moved[i] = tick > 0 && (jump ? next(r) % 2 : next(r) % 3 == 0);
            if (moved[i]) new_pose(&sc, i, !jump);
        }
        jumps += jump;
        assert_int_equal(hgcd_world_set_poses(sc.w[0], NULL, (size_t)d, sc.pos[0], 0, sc.ori[0], 0), HGCD_OK);
        { /* B: the moved ones by id */
            static hgcd_body ids[kMaxBodies];
            static double p[kMaxBodies][3], q[kMaxBodies][4];
            size_t count = 0;
            for (int i = 0; i < d; ++i)
                if (moved[i]) {
                    ids[count] = sc.id[1][i];
                    memcpy(p[count], sc.pos[i], sizeof p[count]);
                    memcpy(q[count++], sc.ori[i], sizeof q[0]);
                }
            assert_int_equal(hgcd_world_set_poses(sc.w[1], ids, count, p[0], 0, q[0], 0), HGCD_OK);
        }
        /* The static bodies change between detects. */
        const int a = d + (int)(next(r) % (uint64_t)(n - d)), b = d + (int)(next(r) % (uint64_t)(n - d));
        const int c = d + (int)(next(r) % (uint64_t)(n - d));
        if (sc.live[a] && sc.is_static[a] == 1) { /* moved */
            new_pose(&sc, a, (int)(next(r) % 2));
            for (int k = 0; k < 2; ++k)
                assert_int_equal(hgcd_body_set_pose(sc.w[k], sc.id[k][a], sc.pos[a], sc.ori[a]), HGCD_OK);
        }
        if (tick % 2 && sc.live[b] && sc.is_static[b] == 1) {
            destroy(&sc, b);
        } else if (!sc.live[b]) {
            sc.is_static[b] = 1;
            create(&sc, b);
        }
        if (sc.live[c]) {
            if (tick % 3 == 0) set_enabled(&sc, c, sc.disabled[c]);
            else if (sc.is_static[c] == 1) set_type(&sc, c, 0), ++flips;
            else set_type(&sc, c, 1);
        }
        assert_int_equal(hgcd_world_set_narrow_phase(sc.w[1], HGCD_NARROW_EXACT), HGCD_OK);
        for (int k = 0; k < 2; ++k) assert_int_equal(hgcd_world_detect(sc.w[k]), HGCD_OK);
        same_pairs(&sc);
        if (tick % 2 == 0) oracle_check(&sc);
        const hgcd_stats sa = stats_of(sc.w[0]), sb = stats_of(sc.w[1]);
        assert_int_equal(sa.colliding_pairs, sb.colliding_pairs);
        incremental += sa.searched_bodies < sb.searched_bodies;
    }
    assert_true(jumps > 0 && flips > 0 && incremental > 0);
    scene_free(&sc);
}

static void test_incremental_static_runs(void **state) {
    (void)state;
    run_static_runs(slow() ? 1600 : 600, slow() ? 800 : 300, slow() ? 20 : 14, 1, slow() ? 40 : 20, 9);
    run_static_runs(slow() ? 1600 : 600, slow() ? 800 : 300, slow() ? 20 : 14, 2, slow() ? 40 : 20, 10);
}

static void test_incremental_crowded(void **state) {
    (void)state;
    run_crowded(600, 120, 10, 2, 7);
    run_crowded(600, 120, 10, 1, 8);
}

static void test_incremental_static(void **state) {
    (void)state;
    run_static(slow() ? 1600 : 600, slow() ? 20 : 14, 1, slow() ? 48 : 24, 3, 5);
    run_static(slow() ? 1600 : 600, slow() ? 20 : 14, 2, slow() ? 48 : 24, 3, 6);
}

static void test_incremental_one_thread(void **state) {
    (void)state;
    if (slow()) run(2400, 24, 1, 60, 0, 1);
    else run(800, 16, 1, 30, 0, 1);
}

static void test_incremental_two_threads(void **state) {
    (void)state;
    if (slow()) run(2400, 24, 2, 60, 0, 2);
    else run(800, 16, 2, 30, 0, 2);
}

static void test_incremental_oracle(void **state) {
    (void)state;
    run(300, 9, 2, slow() ? 40 : 20, 2, 3);
    if (slow()) run(300, 9, 1, 40, 2, 4);
}

int main(void) {
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_incremental_one_thread),
        cmocka_unit_test(test_incremental_two_threads),
        cmocka_unit_test(test_incremental_oracle),
        cmocka_unit_test(test_incremental_static),
        cmocka_unit_test(test_incremental_crowded),
        cmocka_unit_test(test_incremental_static_runs),
    };
    if (getenv("HGCD_TEST_FILTER")) cmocka_set_test_filter(getenv("HGCD_TEST_FILTER"));
    return cmocka_run_group_tests(tests, NULL, NULL);
}
