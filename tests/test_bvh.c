/* The narrow phase's tree path (meshes above the tree threshold: BVH over
 * triangles, simultaneous traversal, lazily transformed vertices, tree-driven
 * ray parity for containment) against the brute-force oracle of
 * tests/oracle.c, on non-convex closed meshes of 500 to 3000 triangles: deep
 * overlap, shallow contact found by bisection down to the last bit,
 * containment, nested shells with a cavity, grid-aligned meshes with exact
 * contacts, mixed small/large pairs, and the `meshes` benchmark scene at a
 * small size. Every scene is checked pair for pair; the oracle's cost is kept
 * bounded by using few large bodies per scene. */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "support/shapes.h"
#include "support/testing.h"

#include <cmocka.h>

#include <hgcd/hgcd.h>
#include <hgcd/hgcd_scene.h>

#include "../scene/scene_meshes.h"
#include "oracle.h"

/* ------------------------------------------------------------- meshes -- */

typedef struct {
    double *v;
    uint32_t *t;
    uint32_t nv, nt;
} mesh_t;

static void mesh_alloc(mesh_t *m, uint32_t nv, uint32_t nt) {
    m->nv = nv;
    m->nt = nt;
    m->v = malloc(3 * (size_t)nv * sizeof(double));
    m->t = malloc(3 * (size_t)nt * sizeof(uint32_t));
    assert_non_null(m->v);
    assert_non_null(m->t);
}

static void mesh_free(mesh_t *m) {
    free(m->v);
    free(m->t);
}

static void blob(mesh_t *m, uint32_t nu, uint32_t nv) {
    mesh_alloc(m, hgcd_blob_vertex_count(nu, nv), hgcd_blob_triangle_count(nu, nv));
    hgcd_blob_mesh(nu, nv, m->v, m->t);
}

/* Tube of radius `tube` around the (2, 3) torus knot
 * ((1 + 0.45 cos 3s) cos 2s, (1 + 0.45 cos 3s) sin 2s, 0.45 sin 3s): `seg`
 * rings of `ring` vertices, closed (a torus topologically), not convex. */
static void torus_knot(mesh_t *m, uint32_t seg, uint32_t ring, double tube) {
    const double pi = 3.14159265358979323846;
    mesh_alloc(m, seg * ring, 2 * seg * ring);
    for (uint32_t i = 0; i < seg; ++i) {
        const double s = 2 * pi * i / seg, h = 1e-4;
        double c[3], c2[3];
        for (int e = 0; e < 2; ++e) {
            const double u = s + e * h;
            double *o = e ? c2 : c;
            o[0] = (1 + 0.45 * cos(3 * u)) * cos(2 * u);
            o[1] = (1 + 0.45 * cos(3 * u)) * sin(2 * u);
            o[2] = 0.45 * sin(3 * u);
        }
        double tg[3] = {c2[0] - c[0], c2[1] - c[1], c2[2] - c[2]};
        double tl = sqrt(tg[0] * tg[0] + tg[1] * tg[1] + tg[2] * tg[2]);
        for (int k = 0; k < 3; ++k) tg[k] /= tl;
        /* Normal: the component of c (from the origin) across the tangent. */
        double d = c[0] * tg[0] + c[1] * tg[1] + c[2] * tg[2];
        double n[3] = {c[0] - d * tg[0], c[1] - d * tg[1], c[2] - d * tg[2]};
        double nl = sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
        for (int k = 0; k < 3; ++k) n[k] /= nl;
        const double b[3] = {tg[1] * n[2] - tg[2] * n[1], tg[2] * n[0] - tg[0] * n[2],
                             tg[0] * n[1] - tg[1] * n[0]};
        for (uint32_t j = 0; j < ring; ++j) {
            const double a = 2 * pi * j / ring;
            for (int k = 0; k < 3; ++k)
                m->v[3 * (i * ring + j) + k] = c[k] + tube * (cos(a) * n[k] + sin(a) * b[k]);
        }
    }
    uint32_t t = 0;
    for (uint32_t i = 0; i < seg; ++i)
        for (uint32_t j = 0; j < ring; ++j) {
            const uint32_t a = i * ring + j, b = i * ring + (j + 1) % ring;
            const uint32_t c = ((i + 1) % seg) * ring + j, d = ((i + 1) % seg) * ring + (j + 1) % ring;
            m->t[t++] = a, m->t[t++] = c, m->t[t++] = d;
            m->t[t++] = a, m->t[t++] = d, m->t[t++] = b;
        }
}

/* A sphere shell: the blob grid with constant radius `outer`, plus an inner
 * sphere of radius `inner` with reversed triangles (a closed mesh of two
 * components bounding a hollow ball; the cavity is outside). */
static void shell(mesh_t *m, uint32_t nu, uint32_t nv, double outer, double inner) {
    mesh_t s;
    blob(&s, nu, nv);
    /* Project the blob to the unit sphere. */
    for (uint32_t i = 0; i < s.nv; ++i) {
        double *p = &s.v[3 * i];
        const double l = sqrt(p[0] * p[0] + p[1] * p[1] + p[2] * p[2]);
        for (int k = 0; k < 3; ++k) p[k] /= l;
    }
    mesh_alloc(m, 2 * s.nv, 2 * s.nt);
    for (uint32_t i = 0; i < s.nv; ++i)
        for (int k = 0; k < 3; ++k) {
            m->v[3 * i + k] = outer * s.v[3 * i + k];
            m->v[3 * (s.nv + i) + k] = inner * s.v[3 * i + k];
        }
    for (uint32_t i = 0; i < s.nt; ++i) {
        for (int k = 0; k < 3; ++k) m->t[3 * i + k] = s.t[3 * i + k];
        m->t[3 * (s.nt + i)] = s.nv + s.t[3 * i];
        m->t[3 * (s.nt + i) + 1] = s.nv + s.t[3 * i + 2];
        m->t[3 * (s.nt + i) + 2] = s.nv + s.t[3 * i + 1];
    }
    mesh_free(&s);
}

/* The cube [-1, 1]^3 with each face cut into n x n squares of two triangles:
 * every vertex on a grid of step 2/n (exact for n a power of two). */
static void grid_cube(mesh_t *m, uint32_t n) {
    mesh_alloc(m, 6 * (n + 1) * (n + 1), 12 * n * n);
    uint32_t t = 0;
    for (int f = 0; f < 6; ++f) {
        const int axis = f / 2;
        const double side = (f % 2) ? 1.0 : -1.0;
        const uint32_t base = f * (n + 1) * (n + 1);
        for (uint32_t i = 0; i <= n; ++i)
            for (uint32_t j = 0; j <= n; ++j) {
                double *p = &m->v[3 * (base + i * (n + 1) + j)];
                p[axis] = side;
                p[(axis + 1) % 3] = -1.0 + 2.0 * i / n;
                p[(axis + 2) % 3] = -1.0 + 2.0 * j / n;
            }
        for (uint32_t i = 0; i < n; ++i)
            for (uint32_t j = 0; j < n; ++j) {
                const uint32_t a = base + i * (n + 1) + j, b = a + 1, c = a + n + 1, d = c + 1;
                if (f % 2) {
                    m->t[t++] = a, m->t[t++] = c, m->t[t++] = d;
                    m->t[t++] = a, m->t[t++] = d, m->t[t++] = b;
                } else {
                    m->t[t++] = a, m->t[t++] = d, m->t[t++] = c;
                    m->t[t++] = a, m->t[t++] = b, m->t[t++] = d;
                }
            }
    }
    /* Faces share their border vertices only geometrically: weld them so
     * the mesh is closed. */
    uint32_t *remap = malloc(m->nv * sizeof(uint32_t));
    for (uint32_t i = 0; i < m->nv; ++i) {
        remap[i] = i;
        for (uint32_t j = 0; j < i; ++j)
            if (remap[j] == j && !memcmp(&m->v[3 * i], &m->v[3 * j], 3 * sizeof(double))) {
                remap[i] = j;
                break;
            }
    }
    for (uint32_t i = 0; i < 3 * m->nt; ++i) m->t[i] = remap[m->t[i]];
    free(remap);
}


/* Fixture: the meshes every test uses. */
enum { M_BLOB, M_KNOT, M_SMALL_BLOB, M_SHELL, M_GRID_CUBE, M_TETRA, M_BOX, M_COUNT };
static mesh_t meshes[M_COUNT];
static oracle_mesh omesh[M_COUNT];

static int setup(void **state) {
    (void)state;
    blob(&meshes[M_BLOB], HGCD_BLOB_NU, HGCD_BLOB_NV);       /* 2976 triangles */
    torus_knot(&meshes[M_KNOT], 96, 8, 0.16);                  /* 1536 */
    blob(&meshes[M_SMALL_BLOB], 20, 14);                       /* 520 */
    shell(&meshes[M_SHELL], 24, 14, 1.0, 0.6);                 /* 1248 */
    grid_cube(&meshes[M_GRID_CUBE], 8);                        /* 768 */
    mesh_alloc(&meshes[M_TETRA], 4, 4);                        /* no tree */
    memcpy(meshes[M_TETRA].v, tetra_v, sizeof tetra_v);
    memcpy(meshes[M_TETRA].t, tetra_t, sizeof tetra_t);
    grid_cube(&meshes[M_BOX], 2);                              /* 48: the largest without a tree */
    for (int k = 0; k < M_COUNT; ++k) {
        omesh[k].verts = meshes[k].v;
        omesh[k].tris = meshes[k].t;
        omesh[k].vertex_count = meshes[k].nv;
        omesh[k].triangle_count = meshes[k].nt;
        omesh[k].closed = 1;
    }
    return 0;
}

static int teardown(void **state) {
    (void)state;
    for (int k = 0; k < M_COUNT; ++k) mesh_free(&meshes[k]);
    return 0;
}

/* -------------------------------------------------------------- scene -- */

#include "test_rng.h"

static void random_direction(rng *r, double *u) {
    const double z = 2 * unif(r) - 1, phi = 6.283185307179586 * unif(r);
    u[0] = sqrt(1 - z * z) * cos(phi);
    u[1] = sqrt(1 - z * z) * sin(phi);
    u[2] = z;
}

static void random_quat(rng *r, double *q) {
    const double u1 = unif(r), u2 = unif(r), u3 = unif(r);
    q[0] = sqrt(1 - u1) * sin(6.283185307179586 * u2);
    q[1] = sqrt(1 - u1) * cos(6.283185307179586 * u2);
    q[2] = sqrt(u1) * sin(6.283185307179586 * u3);
    q[3] = sqrt(u1) * cos(6.283185307179586 * u3);
}

enum { CAP = 64 };
typedef struct {
    hgcd_world *w;
    hgcd_mesh mesh[M_COUNT];
    size_t n;
    int kind[CAP];
    hgcd_body id[CAP];
    double pos[3 * CAP], quat[4 * CAP], scale[CAP];
} scene;

static void scene_init(scene *sc, uint32_t threads) {
    memset(sc, 0, sizeof *sc);
    hgcd_world_desc wd = hgcd_world_desc_default();
    wd.thread_count = threads;
    assert_int_equal(hgcd_world_create(&wd, &sc->w), HGCD_OK);
    assert_int_equal(hgcd_world_set_contacts(sc->w, 1), HGCD_OK);
    for (int k = 0; k < M_COUNT; ++k) {
        hgcd_mesh_desc md = hgcd_mesh_desc_default();
        md.vertices = meshes[k].v;
        md.triangles = meshes[k].t;
        md.vertex_count = meshes[k].nv;
        md.triangle_count = meshes[k].nt;
        assert_int_equal(hgcd_mesh_create(sc->w, &md, &sc->mesh[k]), HGCD_OK);
    }
}

static size_t add(scene *sc, int kind, const double *p, const double *q, double scale) {
    assert_true(sc->n < CAP);
    hgcd_body_desc bd = hgcd_body_desc_default();
    bd.mesh = sc->mesh[kind];
    memcpy(bd.position, p, sizeof bd.position);
    memcpy(bd.orientation, q, sizeof bd.orientation);
    bd.scale = scale;
    const size_t i = sc->n++;
    assert_int_equal(hgcd_body_create(sc->w, &bd, &sc->id[i]), HGCD_OK);
    assert_int_equal(sc->id[i].index, i);
    sc->kind[i] = kind;
    memcpy(&sc->pos[3 * i], p, 3 * sizeof(double));
    memcpy(&sc->quat[4 * i], q, 4 * sizeof(double));
    sc->scale[i] = scale;
    return i;
}

static void move_to(scene *sc, size_t i, const double *p) {
    assert_int_equal(hgcd_body_set_pose(sc->w, sc->id[i], p, NULL), HGCD_OK);
    memcpy(&sc->pos[3 * i], p, 3 * sizeof(double));
}

static void world_triangle(const scene *sc, size_t body, uint32_t tri, double *out) {
    const mesh_t *m = &meshes[sc->kind[body]];
    assert_true(tri < m->nt);
    for (int k = 0; k < 3; ++k)
        oracle_world_vertex(&sc->pos[3 * body], &sc->quat[4 * body], sc->scale[body],
                            &m->v[3 * (size_t)m->t[3 * tri + k]], out + 3 * k);
}

/* The contacts of the last detect: every surface witness (a triangle index
 * of each mesh, mapped back from the tree's leaf order) is a pair of
 * triangles that meet by the oracle, and containment kinds count as the
 * oracle's containment pairs. */
static void check_contacts(const scene *sc, size_t count, size_t oracle_containment) {
    const hgcd_contact *c;
    size_t nc;
    assert_int_equal(hgcd_world_contacts(sc->w, &c, &nc), HGCD_OK);
    assert_int_equal(nc, count);
    size_t held = 0;
    for (size_t k = 0; k < nc; ++k) {
        if (c[k].kind == HGCD_CONTACT_SURFACE) {
            double p[9], q[9];
            world_triangle(sc, c[k].pair.a.index, c[k].triangle_a, p);
            world_triangle(sc, c[k].pair.b.index, c[k].triangle_b, q);
            assert_int_equal(oracle_tri_tri(p, q), 1);
        } else {
            assert_true(c[k].kind == HGCD_CONTACT_A_CONTAINS_B || c[k].kind == HGCD_CONTACT_B_CONTAINS_A);
            ++held;
        }
    }
    assert_int_equal(held, oracle_containment);
}

/* Detects, compares with the oracle pair for pair, returns the pair count
 * (and the containment count in *containment if not NULL). */
static size_t check(scene *sc, size_t *containment) {
    assert_int_equal(hgcd_world_detect(sc->w), HGCD_OK);
    const oracle_mesh *bm[CAP];
    for (size_t i = 0; i < sc->n; ++i) bm[i] = &omesh[sc->kind[i]];
    uint32_t expect[2 * CAP * CAP];
    const size_t n = oracle_colliding_pairs(sc->n, bm, sc->pos, sc->quat, sc->scale, expect, CAP * CAP);
    const size_t oracle_containment = oracle_last_containment_pairs();
    const hgcd_pair *got;
    size_t count;
    assert_int_equal(hgcd_world_pairs(sc->w, &got, &count), HGCD_OK);
    size_t bad = 0;
    for (size_t k = 0; k < n || k < count; ++k) {
        const int he = k < n, hg = k < count;
        if (!he || !hg || got[k].a.index != expect[2 * k] || got[k].b.index != expect[2 * k + 1]) {
            if (bad++ < 5)
                fprintf(stderr, "pair %zu: hgcd (%u, %u)%s, oracle (%u, %u)%s\n", k, hg ? got[k].a.index : 0,
                        hg ? got[k].b.index : 0, hg ? "" : " none", he ? expect[2 * k] : 0,
                        he ? expect[2 * k + 1] : 0, he ? "" : " none");
        }
    }
    assert_int_equal(bad, 0);
    assert_int_equal(count, n);
    hgcd_stats st;
    st.struct_size = sizeof st;
    assert_int_equal(hgcd_world_stats(sc->w, &st), HGCD_OK);
    assert_int_equal(st.containment_pairs, oracle_containment);
    check_contacts(sc, count, oracle_containment);
    if (containment) *containment = oracle_containment;
    return n;
}

static int has_pair(const scene *sc, uint32_t a, uint32_t b) {
    const hgcd_pair *p;
    size_t count;
    assert_int_equal(hgcd_world_pairs(sc->w, &p, &count), HGCD_OK);
    for (size_t k = 0; k < count; ++k)
        if (p[k].a.index == a && p[k].b.index == b) return 1;
    return 0;
}

/* Bounding radius of each mesh (mesh frame, about the origin). */
static double mesh_radius(int kind) {
    double r = 0;
    for (uint32_t i = 0; i < meshes[kind].nv; ++i) {
        const double *p = &meshes[kind].v[3 * i];
        const double d = sqrt(p[0] * p[0] + p[1] * p[1] + p[2] * p[2]);
        if (d > r) r = d;
    }
    return r;
}

/* -------------------------------------------------------------- tests -- */

/* A mesh's tree is built in pieces on the world's threads (above 2048
 * triangles, 16 subtrees after the top levels): the same tree bit for bit on
 * 1, 2 and 3 threads, for meshes below and above that size. */
static void test_tree_same_on_threads(void **state) {
    (void)state;
    static const uint32_t sizes[][2] = {{12, 8}, {40, 30}, {92, 28}, {128, 64}};
    for (int k = 0; k < 4; ++k) {
        mesh_t m;
        blob(&m, sizes[k][0], sizes[k][1]);
        for (int threads = 2; threads <= 3; ++threads) {
            uint32_t nodes = 0;
            assert_int_equal(hgcdi_bvh_same_on_threads(m.v, m.t, m.nt, threads, &nodes), 1);
            assert_true(nodes > 1);
        }
        mesh_free(&m);
    }
}

static void test_mesh_info(void **state) {
    (void)state;
    scene sc;
    scene_init(&sc, 1);
    for (int k = 0; k < M_COUNT; ++k) {
        hgcd_mesh_info info;
        info.struct_size = sizeof info;
        assert_int_equal(hgcd_mesh_get_info(sc.w, sc.mesh[k], &info), HGCD_OK);
        assert_int_equal(info.triangle_count, meshes[k].nt);
        assert_int_equal(info.closed, 1);
        assert_int_equal(info.component_count, k == M_SHELL ? 2 : 1);
        if (k == M_GRID_CUBE || k == M_TETRA || k == M_BOX) assert_int_equal(info.convex, 1);
        else assert_int_equal(info.convex, 0);
    }
    hgcd_world_destroy(sc.w);
}

/* Random pairs of large non-convex meshes (and a few large-small pairs),
 * each pair far from the others, at centre distances from deep overlap to
 * just apart. */
static void test_random_pairs(void **state) {
    (void)state;
    const int kinds[] = {M_BLOB, M_KNOT, M_SMALL_BLOB, M_SHELL, M_GRID_CUBE, M_TETRA};
    size_t total = 0, total_containment = 0, tested = 0;
    for (uint64_t seed = 1; seed <= 4; ++seed) {
        rng r = {seed};
        scene sc;
        scene_init(&sc, (uint32_t)seed % 3 + 1);
        for (int p = 0; p < 8; ++p) {
            const int ka = kinds[next(&r) % 5], kb = kinds[next(&r) % 6];
            const double sa = 0.5 + 1.5 * unif(&r), sb = 0.3 + 1.5 * unif(&r);
            double qa[4], qb[4], u[3], pa[3], pb[3];
            random_quat(&r, qa);
            random_quat(&r, qb);
            /* Direction uniform on the sphere, distance f * (ra + rb). */
            const double z = 2 * unif(&r) - 1, phi = 6.283185307179586 * unif(&r);
            u[0] = sqrt(1 - z * z) * cos(phi);
            u[1] = sqrt(1 - z * z) * sin(phi);
            u[2] = z;
            const double f = 1.1 * unif(&r);
            const double d = f * (sa * mesh_radius(ka) + sb * mesh_radius(kb));
            for (int k = 0; k < 3; ++k) {
                pa[k] = 20.0 * p + (k == 1 ? 5.0 * (double)seed : 0.0);
                pb[k] = pa[k] + d * u[k];
            }
            add(&sc, ka, pa, qa, sa);
            add(&sc, kb, pb, qb, sb);
            ++tested;
        }
        size_t c;
        total += check(&sc, &c);
        total_containment += c;
        hgcd_world_destroy(sc.w);
    }
    /* A mix of answers, not all-colliding nor all-apart. */
    assert_true(total >= 6 && total + 4 <= tested);
    fprintf(stderr, "random pairs: %zu tested, %zu colliding, %zu by containment\n", tested, total,
            total_containment);
}

/* Bisection on the distance between two large meshes along a direction, to
 * the last bit: at the end the two positions differ in one unit of the last
 * place, hgcd says "touching" at one and "apart" at the other, and the oracle
 * agrees at both. The boxes of the tree's nodes are then within rounding of
 * the other surface. */
static void test_shallow_contact(void **state) {
    (void)state;
    const int pairs[][2] = {{M_BLOB, M_BLOB},      {M_KNOT, M_BLOB}, {M_KNOT, M_KNOT},
                            {M_GRID_CUBE, M_SMALL_BLOB}, {M_TETRA, M_KNOT}, {M_SHELL, M_KNOT},
                            {M_BOX, M_BLOB},       {M_SHELL, M_BOX}};
    rng r = {42};
    for (size_t p = 0; p < sizeof pairs / sizeof pairs[0]; ++p) {
        for (int rep = 0; rep < 2; ++rep) {
            scene sc;
            scene_init(&sc, 1);
            double qa[4], qb[4], u[3];
            random_quat(&r, qa);
            random_quat(&r, qb);
            const double z = 2 * unif(&r) - 1, phi = 6.283185307179586 * unif(&r);
            u[0] = sqrt(1 - z * z) * cos(phi);
            u[1] = sqrt(1 - z * z) * sin(phi);
            u[2] = z;
            const double o[3] = {0.25, -0.5, 1.0};
            add(&sc, pairs[p][0], o, qa, 1.0);
            /* Start apart, then bisect t in [0, far] on "collides". */
            const double far = mesh_radius(pairs[p][0]) + mesh_radius(pairs[p][1]) + 0.5;
            double lo = 0, hi = far, pb[3];
            for (int k = 0; k < 3; ++k) pb[k] = o[k] + far * u[k];
            const size_t b = add(&sc, pairs[p][1], pb, qb, 1.0);
            for (int it = 0; it < 80 && hi - lo > 0; ++it) {
                const double mid = 0.5 * lo + 0.5 * hi;
                if (mid <= lo || mid >= hi) break;
                for (int k = 0; k < 3; ++k) pb[k] = o[k] + mid * u[k];
                move_to(&sc, b, pb);
                assert_int_equal(hgcd_world_detect(sc.w), HGCD_OK);
                if (has_pair(&sc, 0, 1)) lo = mid;
                else hi = mid;
            }
            for (int k = 0; k < 3; ++k) pb[k] = o[k] + lo * u[k];
            move_to(&sc, b, pb);
            assert_int_equal(check(&sc, NULL), 1);
            for (int k = 0; k < 3; ++k) pb[k] = o[k] + hi * u[k];
            move_to(&sc, b, pb);
            assert_int_equal(check(&sc, NULL), 0);
            hgcd_world_destroy(sc.w);
        }
    }
}

/* A large mesh wholly inside another (no surface contact): containment,
 * with either body first, for a tree inner mesh and a tree-less one. */
static void test_containment(void **state) {
    (void)state;
    scene sc;
    scene_init(&sc, 2);
    rng r = {7};
    double q[4], q2[4];
    const double o[3] = {0, 0, 0}, o2[3] = {30, 0, 0}, o3[3] = {60, 0, 0}, o4[3] = {90, 0, 0};
    random_quat(&r, q);
    random_quat(&r, q2);
    add(&sc, M_BLOB, o, q, 3.0);                 /* 0: the outer blob (inner radius >= 1.65) */
    add(&sc, M_SMALL_BLOB, o, q2, 1.0);          /* 1: inside 0 */
    add(&sc, M_KNOT, o2, q2, 0.7);               /* 2: inside 3 (created first) */
    add(&sc, M_BLOB, o2, q, 3.0);                /* 3 */
    add(&sc, M_TETRA, o3, q2, 0.5);              /* 4: tetra inside the blob 5 */
    add(&sc, M_BLOB, o3, q, 3.0);                /* 5 */
    add(&sc, M_BLOB, o4, q2, 2.0);               /* 6: blob inside the grid cube 7 */
    add(&sc, M_GRID_CUBE, o4, q, 3.0);           /* 7 */
    size_t c;
    assert_int_equal(check(&sc, &c), 4);
    assert_int_equal(c, 4);
    assert_true(has_pair(&sc, 0, 1) && has_pair(&sc, 2, 3) && has_pair(&sc, 4, 5) && has_pair(&sc, 6, 7));
    /* Which body holds which, in the contacts. */
    const hgcd_contact *ct;
    size_t nc;
    assert_int_equal(hgcd_world_contacts(sc.w, &ct, &nc), HGCD_OK);
    assert_int_equal(nc, 4);
    assert_int_equal(ct[0].kind, HGCD_CONTACT_A_CONTAINS_B); /* (0, 1): 0 holds 1 */
    assert_int_equal(ct[1].kind, HGCD_CONTACT_B_CONTAINS_A); /* (2, 3): 3 holds 2 */
    assert_int_equal(ct[2].kind, HGCD_CONTACT_B_CONTAINS_A); /* (4, 5): 5 holds the tetra */
    assert_int_equal(ct[3].kind, HGCD_CONTACT_B_CONTAINS_A); /* (6, 7): the cube holds 6 */
    hgcd_world_destroy(sc.w);
}

/* Meshes without a tree (a 48-triangle cube, a tetrahedron) against meshes
 * with one, either body first: the pair is traversed in the tree's frame
 * with the other's box as one node. Containment both ways (the tree-less
 * cube holding a tree mesh, a tree mesh holding it), near misses and
 * crossings at random turns, each checked against the oracle. */
static void test_tree_against_point_node(void **state) {
    (void)state;
    rng r = {101};
    size_t total = 0, total_containment = 0;
    for (int order = 0; order < 2; ++order) {
        scene sc;
        scene_init(&sc, 1 + (uint32_t)order);
        for (int p = 0; p < 24; ++p) {
            static const int trees[] = {M_BLOB, M_KNOT, M_SHELL, M_GRID_CUBE};
            const int kt = trees[p % 4], kp = p % 3 ? M_BOX : M_TETRA;
            double qt[4], qp[4], u[3], pt[3], pp[3];
            random_quat(&r, qt);
            random_quat(&r, qp);
            random_direction(&r, u);
            /* Scales: the tree-less body large enough to hold the tree mesh
             * (p % 6 == 1), small enough to sit inside it (p % 6 == 2), or
             * alike; distance from 0 to past touching. */
            const double st = 1.0, sp = p % 6 == 1 ? 4.0 : p % 6 == 2 ? 0.1 : 0.3 + unif(&r);
            const double d = p % 6 == 1 || p % 6 == 2 ? 0.0 : 1.1 * unif(&r) * (mesh_radius(kt) + sp * mesh_radius(kp));
            for (int k = 0; k < 3; ++k) {
                pt[k] = 20.0 * p;
                pp[k] = pt[k] + d * u[k];
            }
            if (order == 0) {
                add(&sc, kp, pp, qp, sp);
                add(&sc, kt, pt, qt, st);
            } else {
                add(&sc, kt, pt, qt, st);
                add(&sc, kp, pp, qp, sp);
            }
        }
        size_t c;
        total += check(&sc, &c);
        total_containment += c;
        /* The holder is the larger body (scales 4 against 1, 1 against 0.1). */
        const hgcd_contact *ct;
        size_t nc;
        assert_int_equal(hgcd_world_contacts(sc.w, &ct, &nc), HGCD_OK);
        for (size_t k = 0; k < nc; ++k) {
            if (ct[k].kind == HGCD_CONTACT_SURFACE) continue;
            const uint32_t a = ct[k].pair.a.index, b = ct[k].pair.b.index;
            const uint32_t holder = ct[k].kind == HGCD_CONTACT_A_CONTAINS_B ? a : b, held = holder == a ? b : a;
            assert_true(sc.scale[holder] * mesh_radius(sc.kind[holder]) > sc.scale[held] * mesh_radius(sc.kind[held]));
        }
        hgcd_world_destroy(sc.w);
    }
    assert_true(total >= 8 && total_containment >= 4 && total + 8 <= 48);
    fprintf(stderr, "tree against point node: 48 pairs, %zu colliding, %zu by containment\n", total,
            total_containment);
}

/* A small cube inside a large one (both with trees, turned alike), its face
 * (and its first vertex, the one the containment test casts from) a few
 * ulps to 1e-6 inside the large cube's face, with either body first: the
 * containment test first tries that vertex against the outer root's boxes
 * in the outer's frame, which must never put a vertex inside the solid out
 * of it. The oracle decides between containment and surface contact. */
static void test_containment_at_face(void **state) {
    (void)state;
    rng r = {29};
    const double gaps[] = {0, 1e-15, 4e-15, 1e-14, 1e-13, 1e-12, 1e-9, 1e-6};
    size_t held = 0;
    for (int order = 0; order < 2; ++order)
        for (int turn = 0; turn < 3; ++turn) {
            double q[4];
            random_quat(&r, q);
            const double o[3] = {1000.25 * turn, -3.5, 7.0};
            for (size_t g = 0; g < sizeof gaps / sizeof gaps[0]; ++g) {
                scene sc;
                scene_init(&sc, 1);
                /* The inner cube's -x face at x = -3 + gap in the outer's frame. */
                const double offset[3] = {-3.0 + 0.5 + 3.0 * gaps[g], 0.25, -0.5};
                double p[3];
                oracle_world_vertex(o, q, 1.0, offset, p);
                if (order) {
                    add(&sc, M_GRID_CUBE, p, q, 0.5);
                    add(&sc, M_GRID_CUBE, o, q, 3.0);
                } else {
                    add(&sc, M_GRID_CUBE, o, q, 3.0);
                    add(&sc, M_GRID_CUBE, p, q, 0.5);
                }
                size_t c;
                assert_int_equal(check(&sc, &c), 1);
                held += c;
                hgcd_world_destroy(sc.w);
            }
        }
    /* (Most gaps leave the small cube wholly inside.) */
    assert_true(held >= 24);
}

/* The shell bounds a hollow ball: a body in the cavity does not collide
 * with it, one in the material does (containment), one across the inner
 * surface does (surface), one outside does not. */
static void test_nested_shells(void **state) {
    (void)state;
    scene sc;
    scene_init(&sc, 1);
    rng r = {11};
    double q[4], q2[4];
    random_quat(&r, q);
    random_quat(&r, q2);
    const double o[3] = {0, 0, 0};
    const double material[3] = {0.78, 0.1, -0.05}, across[3] = {0.6, 0, 0};
    add(&sc, M_SHELL, o, q, 1.0);                   /* 0 */
    add(&sc, M_SMALL_BLOB, o, q2, 0.3);             /* 1: in the cavity (radius <= 0.44 < 0.58) */
    add(&sc, M_SMALL_BLOB, material, q2, 0.06);     /* 2: in the material */
    add(&sc, M_SMALL_BLOB, across, q2, 0.1);        /* 3: across the inner surface */
    add(&sc, M_TETRA, o, q2, 0.2);                  /* 4: tetra in the cavity */
    const double out[3] = {2.5, 0, 0};
    add(&sc, M_KNOT, out, q, 1.0);                  /* 5: apart */
    size_t c;
    check(&sc, &c);
    assert_false(has_pair(&sc, 0, 1));
    assert_true(has_pair(&sc, 0, 2));
    assert_true(has_pair(&sc, 0, 3));
    assert_false(has_pair(&sc, 0, 4));
    assert_false(has_pair(&sc, 0, 5));
    assert_true(has_pair(&sc, 1, 4)); /* the tetra inside the small blob */
    assert_true(c >= 1);
    /* A shell inside the cavity of another shell, and one straddling it. */
    scene sc2;
    scene_init(&sc2, 1);
    add(&sc2, M_SHELL, o, q, 1.0);                  /* 0 */
    add(&sc2, M_SHELL, o, q2, 0.5);                 /* 1: inside the cavity of 0 */
    add(&sc2, M_SHELL, o, q2, 0.2);                 /* 2: inside the cavity of 1 */
    add(&sc2, M_SHELL, material, q2, 0.1);          /* 3: in the material of 0 */
    check(&sc2, NULL);
    assert_false(has_pair(&sc2, 0, 1));
    assert_false(has_pair(&sc2, 1, 2));
    assert_false(has_pair(&sc2, 0, 2));
    assert_true(has_pair(&sc2, 0, 3));
    hgcd_world_destroy(sc.w);
    hgcd_world_destroy(sc2.w);
}

/* Grid-aligned meshes at snapped positions with exact rotations: faces of
 * the tree meshes touch exactly, coplanar faces overlap, containment rays
 * start on the grid. */
static void test_exact_grid_contacts(void **state) {
    (void)state;
    static const double quats[][4] = {{0, 0, 0, 1}, {1, 0, 0, 0}, {0.5, 0.5, 0.5, 0.5}, {0, 0, 1, 0}};
    for (uint64_t seed = 1; seed <= 3; ++seed) {
        rng r = {100 + seed};
        scene sc;
        scene_init(&sc, 2);
        for (int i = 0; i < 24; ++i) {
            double p[3];
            for (int k = 0; k < 3; ++k) p[k] = 0.25 * (double)(next(&r) % 24);
            const int kind = (next(&r) % 3) ? M_GRID_CUBE : M_TETRA;
            const double scale = kind == M_GRID_CUBE ? 0.25 * (double)(1 + next(&r) % 4) : 0.25;
            add(&sc, kind, p, quats[next(&r) % 4], scale);
        }
        assert_true(check(&sc, NULL) > 5);
        hgcd_world_destroy(sc.w);
    }
}

/* The `meshes` benchmark scene (docs/scenes.md) at a small size,
 * detected with 1 and 3 threads, against the oracle. */
static void test_meshes_scene_small(void **state) {
    (void)state;
    hgcd_scene_tetra_desc sd = hgcd_scene_tetra_desc_default();
    sd.n = 40;
    sd.side = 9;
    double centers[3 * 40], radii[40], quats[4 * 40];
    assert_int_equal(hgcd_scene_tetra_generate(&sd, centers, radii, NULL, quats, NULL), HGCD_OK);
    size_t first = 0;
    for (uint32_t threads = 1; threads <= 3; threads += 2) {
        scene sc;
        scene_init(&sc, threads);
        for (int i = 0; i < 40; ++i) add(&sc, M_BLOB, &centers[3 * i], &quats[4 * i], radii[i]);
        size_t c;
        const size_t n = check(&sc, &c);
        if (threads == 1) first = n;
        assert_int_equal(n, first);
        assert_true(n >= 5);
        hgcd_world_destroy(sc.w);
    }
}

int main(void) {
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_tree_same_on_threads),
        cmocka_unit_test(test_mesh_info),
        cmocka_unit_test(test_random_pairs),
        cmocka_unit_test(test_shallow_contact),
        cmocka_unit_test(test_containment),
        cmocka_unit_test(test_containment_at_face),
        cmocka_unit_test(test_tree_against_point_node),
        cmocka_unit_test(test_nested_shells),
        cmocka_unit_test(test_exact_grid_contacts),
        cmocka_unit_test(test_meshes_scene_small),
    };
    /* Valgrind and sanitizer runs pick tests by name (cmocka patterns). */
    if (getenv("HGCD_TEST_FILTER")) cmocka_set_test_filter(getenv("HGCD_TEST_FILTER"));
    if (getenv("HGCD_TEST_SKIP")) cmocka_set_skip_filter(getenv("HGCD_TEST_SKIP"));
    return cmocka_run_group_tests(tests, setup, teardown);
}
