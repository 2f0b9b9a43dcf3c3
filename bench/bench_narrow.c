/* bench_narrow: the narrow phases of hgcd side by side on scene `tetra`
 * (docs/scenes.md), in one run on the same poses: the exact test, libccd's GJK and
 * MPR (HGCD_NARROW_GJK / HGCD_NARROW_MPR), and each with contacts on
 * (witness triangles for the exact test, EPA / MPR penetration for libccd).
 *
 *   bench_narrow [--n N] [--seed S] [--threads K] [--ticks T] [--commit HASH]
 *                [--modes exact,gjk,mpr,exact+c,gjk+c,mpr+c] [--sphere L] [--box 1]
 *                [--mix 1] [--mesh-per-body 1]
 *
 * --sphere L replaces the tetrahedron by an icosphere of 20 * 4^L triangles
 * (convex, circumradius 1, scaled to each body's circumradius r): the same
 * poses with a mesh that has many triangles (L >= 2 takes the tree path of
 * the exact narrow phase). Default 0: the tetrahedron of the scene.
 * --box 1 replaces it by the cube [-1, 1]^3, at the tetrahedron's scale (the
 * same circumradius): boxes with the tetra scene's placement and motion.
 * --mix 1 (with --box or --sphere) gives every other body (odd indices) the
 * tetrahedron instead: a mixed world, whose pairs are tetrahedron pairs,
 * mesh pairs and tetrahedron-mesh pairs.
 * --mesh-per-body 1 gives each body a mesh of its own (a copy of the same
 * arrays, hgcd_mesh_create once per body) instead of one shared mesh;
 * --mesh-per-body 2 a shape of its own: body i's mesh is the shape stretched
 * along x by 1 + (i mod 1024) / 1024 and along y by 1 + (i / 1024 mod 1024)
 * / 1024 (different boxes, ellipsoidal icospheres, tetrahedra), so that no
 * two bodies of the first million share a mesh's arrays.
 *
 * One world holds the scene; every tick runs hgcd_world_detect once per mode
 * (switching with hgcd_world_set_narrow_phase / hgcd_world_set_contacts, so
 * every mode sees the same grid and the same poses), then moves the bodies
 * one tick of the scene's motion (hgcd_scene_tetra_move + hgcd_body_set_pose).
 * Prints one JSON line per mode on stdout:
 *   lib, scene, n, seed, threads, ticks, commit, narrow ("exact", "gjk",
 *   "mpr"), contacts (0/1), narrow_ms (median of hgcd_stats.narrow_seconds),
 *   detect_ms (median total_seconds; the first mode of a tick also pays the
 *   grid update after the move), pairs (last tick), libccd_tests,
 *   pairs_differ (pairs of the last tick not in the exact answer, plus exact
 *   pairs missing), libccd (hgcd_feature_libccd()), narrow_cpu_ms (median of
 *   the process's CPU time during the detect times the narrow phase's share
 *   of the detect's wall time: on a machine busy with other work, where wall
 *   times are inflated by waiting, the figure to compare on 1 thread),
 *   cpu_ns_per_candidate, mesh_per_body and pairs_fnv (FNV-1a, 64-bit, hex,
 *   of the mode's last-tick pairs, indices as 32-bit words, as bench_hgcd's).
 * and a table on stderr. Exit status 0, 1 on an API failure, 2 on usage. */
#define _POSIX_C_SOURCE 200809L
#include <hgcd/hgcd.h>
#include <hgcd/hgcd_scene.h>

#include "scene_shapes.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

static int failed(hgcd_status s, const hgcd_world *w, const char *what) {
    if (s == HGCD_OK) return 0;
    fprintf(stderr, "bench_narrow: %s failed: %s (%s)\n", what, hgcd_status_string(s),
            w ? hgcd_world_last_error(w) : "");
    return 1;
}

static double cpu_seconds(void) {
    struct timespec t;
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
    return (double)t.tv_sec + 1e-9 * (double)t.tv_nsec;
}

static int cmp_double(const void *a, const void *b) {
    const double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

static double median(double *v, int count) {
    qsort(v, (size_t)count, sizeof *v, cmp_double);
    return count % 2 ? v[count / 2] : 0.5 * (v[count / 2 - 1] + v[count / 2]);
}

typedef struct {
    const char *name;
    int32_t narrow;
    uint32_t contacts;
} mode;

static const mode all_modes[] = {{"exact", HGCD_NARROW_EXACT, 0}, {"gjk", HGCD_NARROW_GJK, 0},
                                 {"mpr", HGCD_NARROW_MPR, 0},     {"exact+c", HGCD_NARROW_EXACT, 1},
                                 {"gjk+c", HGCD_NARROW_GJK, 1},   {"mpr+c", HGCD_NARROW_MPR, 1}};
enum { MODE_COUNT = sizeof all_modes / sizeof all_modes[0] };

/* Pairs of a and b (both sorted) that are in one only. */
static size_t differ(const hgcd_pair *a, size_t na, const hgcd_pair *b, size_t nb) {
    size_t i = 0, j = 0, d = 0;
    while (i < na || j < nb) {
        const uint64_t x = i < na ? (uint64_t)a[i].a.index << 32 | a[i].b.index : UINT64_MAX;
        const uint64_t y = j < nb ? (uint64_t)b[j].a.index << 32 | b[j].b.index : UINT64_MAX;
        if (x == y) {
            ++i;
            ++j;
        } else if (x < y) {
            ++i;
            ++d;
        } else {
            ++j;
            ++d;
        }
    }
    return d;
}

int main(int argc, char **argv) {
    uint64_t n = 100000, seed = 1;
    unsigned threads = 1;
    int ticks = 5, sphere = 0, box = 0, mix = 0, per_body = 0;
    const char *commit = "unknown", *modes_arg = "exact,gjk,mpr,exact+c,gjk+c,mpr+c";
    for (int i = 1; i < argc; ++i) {
        if (i + 1 >= argc) {
            fprintf(stderr, "usage: %s [--n N] [--seed S] [--threads K] [--ticks T] [--commit HASH] [--modes LIST]\n",
                    argv[0]);
            return 2;
        }
        const char *a = argv[i], *v = argv[++i];
        if (!strcmp(a, "--n")) n = strtoull(v, NULL, 10);
        else if (!strcmp(a, "--seed")) seed = strtoull(v, NULL, 10);
        else if (!strcmp(a, "--threads")) threads = (unsigned)strtoul(v, NULL, 10);
        else if (!strcmp(a, "--ticks")) ticks = atoi(v);
        else if (!strcmp(a, "--commit")) commit = v;
        else if (!strcmp(a, "--modes")) modes_arg = v;
        else if (!strcmp(a, "--sphere")) sphere = atoi(v);
        else if (!strcmp(a, "--box")) box = atoi(v);
        else if (!strcmp(a, "--mix")) mix = atoi(v);
        else if (!strcmp(a, "--mesh-per-body")) per_body = atoi(v);
        else {
            fprintf(stderr, "bench_narrow: unknown option %s\n", a);
            return 2;
        }
    }
    if (n == 0 || ticks < 1 || sphere < 0 || sphere > 4 || (box && sphere) || (mix && !box && !sphere)) {
        fprintf(stderr, "bench_narrow: need n >= 1, ticks >= 1, 0 <= sphere <= 4, not both a box and a sphere, "
                        "and a box or a sphere with --mix\n");
        return 2;
    }
    int use[MODE_COUNT] = {0};
    int used = 0;
    for (int m = 0; m < MODE_COUNT; ++m) {
        const char *p = modes_arg;
        const size_t len = strlen(all_modes[m].name);
        while ((p = strstr(p, all_modes[m].name)) != NULL) {
            if ((p == modes_arg || p[-1] == ',') && (p[len] == ',' || p[len] == 0)) use[m] = 1;
            p += len;
        }
        if (use[m] && all_modes[m].narrow != HGCD_NARROW_EXACT && !hgcd_feature_libccd()) {
            fprintf(stderr, "bench_narrow: %s skipped: not built with libccd\n", all_modes[m].name);
            use[m] = 0;
        }
        used += use[m];
    }
    if (!used) {
        fprintf(stderr, "bench_narrow: no mode to run\n");
        return 2;
    }

    hgcd_scene_tetra_desc sd = hgcd_scene_tetra_desc_default();
    sd.n = n;
    sd.seed = seed;
    double *centers = malloc(3 * n * sizeof(double)), *scales = malloc(n * sizeof(double));
    double *quats = malloc(4 * n * sizeof(double)), *vels = malloc(3 * n * sizeof(double));
    double *narrow_ms = malloc((size_t)ticks * MODE_COUNT * sizeof(double));
    double *detect_ms = malloc((size_t)ticks * MODE_COUNT * sizeof(double));
    double *narrow_cpu_ms = malloc((size_t)ticks * MODE_COUNT * sizeof(double));
    hgcd_pair *exact_pairs = NULL;
    size_t exact_count = 0;
    if (!centers || !scales || !quats || !vels || !narrow_ms || !detect_ms || !narrow_cpu_ms) {
        fprintf(stderr, "bench_narrow: out of memory\n");
        return 1;
    }
    if (hgcd_scene_tetra_generate(&sd, centers, NULL, scales, quats, vels) != HGCD_OK) {
        fprintf(stderr, "bench_narrow: scene generation failed\n");
        return 1;
    }
    hgcd_world_desc wd = hgcd_world_desc_default();
    wd.thread_count = threads;
    hgcd_world *w = NULL;
    if (failed(hgcd_world_create(&wd, &w), NULL, "world_create")) return 1;
    double uv[12];
    uint32_t ut[12];
    hgcd_scene_tetra_unit_mesh(uv, ut);
    hgcd_mesh_desc md = hgcd_mesh_desc_default();
    md.vertices = uv;
    md.triangles = ut;
    md.vertex_count = 4;
    md.triangle_count = 4;
    double *sv = NULL, bv[24];
    uint32_t *st_ = NULL, bt[36];
    if (sphere) {
        md.vertex_count = hgcd_icosphere_vertex_count(sphere);
        md.triangle_count = hgcd_icosphere_triangle_count(sphere);
        sv = malloc(3 * (size_t)md.vertex_count * sizeof(double));
        st_ = malloc(8 * (size_t)md.triangle_count * sizeof(uint32_t)); /* triangles, then scratch */
        if (!sv || !st_) return 1;
        hgcd_icosphere(sphere, sv, st_, st_ + 3 * (size_t)md.triangle_count);
        md.vertices = sv;
        md.triangles = st_;
    } else if (box) {
        hgcd_box_mesh(1, 1, 1, bv, bt);
        md.vertices = bv;
        md.triangles = bt;
        md.vertex_count = 8;
        md.triangle_count = 12;
    }
    hgcd_mesh_desc td = hgcd_mesh_desc_default(); /* the tetrahedron of --mix */
    td.vertices = uv;
    td.triangles = ut;
    td.vertex_count = 4;
    td.triangle_count = 4;
    hgcd_mesh mesh, tetra_mesh;
    if (failed(hgcd_mesh_create(w, &md, &mesh), w, "mesh_create")) return 1;
    if (mix && failed(hgcd_mesh_create(w, &td, &tetra_mesh), w, "mesh_create")) return 1;
    hgcd_body_desc bd = hgcd_body_desc_default();
    hgcd_body *ids = malloc(n * sizeof(hgcd_body));
    double *own = malloc(3 * (size_t)(md.vertex_count > 4 ? md.vertex_count : 4) * sizeof(double));
    if (!own) return 1;
    for (uint64_t i = 0; i < n; ++i) {
        const int tetra = mix && (i & 1);
        bd.mesh = tetra ? tetra_mesh : mesh;
        hgcd_mesh_desc pd = tetra ? td : md;
        if (per_body == 2) { /* a shape of its own */
            const double fx = 1 + (double)(i % 1024) / 1024, fy = 1 + (double)(i / 1024 % 1024) / 1024;
            for (uint32_t v = 0; v < pd.vertex_count; ++v) {
                own[3 * v] = fx * pd.vertices[3 * v];
                own[3 * v + 1] = fy * pd.vertices[3 * v + 1];
                own[3 * v + 2] = pd.vertices[3 * v + 2];
            }
            pd.vertices = own;
        }
        if (per_body && failed(hgcd_mesh_create(w, &pd, &bd.mesh), w, "mesh_create")) return 1;
        memcpy(bd.position, centers + 3 * i, sizeof bd.position);
        memcpy(bd.orientation, quats + 4 * i, sizeof bd.orientation);
        bd.scale = sphere && !tetra ? scales[i] * 1.7320508075688772 : scales[i]; /* circumradius r */
        if (failed(hgcd_body_create(w, &bd, &ids[i]), w, "body_create")) return 1;
    }
    if (failed(hgcd_world_detect(w), w, "world_detect")) return 1; /* builds the grid */

    hgcd_stats last[MODE_COUNT];
    size_t last_differ[MODE_COUNT] = {0};
    uint64_t last_fnv[MODE_COUNT] = {0};
    for (int t = 0; t < ticks; ++t) {
        for (int m = 0; m < MODE_COUNT; ++m) {
            if (!use[m]) continue;
            if (failed(hgcd_world_set_narrow_phase(w, all_modes[m].narrow), w, "set_narrow_phase") ||
                failed(hgcd_world_set_contacts(w, all_modes[m].contacts), w, "set_contacts"))
                return 1;
            const double cpu0 = cpu_seconds();
            if (failed(hgcd_world_detect(w), w, "world_detect")) return 1;
            const double cpu = cpu_seconds() - cpu0;
            hgcd_stats *st = &last[m];
            memset(st, 0, sizeof *st);
            st->struct_size = sizeof *st;
            hgcd_world_stats(w, st);
            narrow_ms[t * MODE_COUNT + m] = 1e3 * st->narrow_seconds;
            detect_ms[t * MODE_COUNT + m] = 1e3 * st->total_seconds;
            narrow_cpu_ms[t * MODE_COUNT + m] =
                st->total_seconds > 0 ? 1e3 * cpu * st->narrow_seconds / st->total_seconds : 0;
            const hgcd_pair *p;
            size_t count;
            hgcd_world_pairs(w, &p, &count);
            if (t == ticks - 1) {
                uint64_t hash = 14695981039346656037ull; /* FNV-1a of the pairs, as bench_hgcd's pairs_fnv */
                for (size_t k = 0; k < count; ++k) {
                    const uint32_t ab[2] = {p[k].a.index, p[k].b.index};
                    const unsigned char *byte = (const unsigned char *)ab;
                    for (size_t i = 0; i < sizeof ab; ++i) hash = (hash ^ byte[i]) * 1099511628211ull;
                }
                last_fnv[m] = hash;
                if (all_modes[m].narrow == HGCD_NARROW_EXACT && !exact_pairs) {
                    exact_pairs = malloc((count + 1) * sizeof(hgcd_pair));
                    memcpy(exact_pairs, p, count * sizeof(hgcd_pair));
                    exact_count = count;
                }
                last_differ[m] = exact_pairs ? differ(exact_pairs, exact_count, p, count) : 0;
            }
        }
        hgcd_scene_tetra_move(n, sd.side, centers, vels);
        for (uint64_t i = 0; i < n; ++i)
            if (failed(hgcd_body_set_pose(w, ids[i], centers + 3 * i, NULL), w, "body_set_pose")) return 1;
    }

    const char *mesh_name = sphere ? (mix ? "icosphere+tetrahedron" : "icosphere")
                            : box  ? (mix ? "box+tetrahedron" : "box")
                                   : "tetrahedron";
    fprintf(stderr, "tetra n=%llu seed %llu, mesh %s (%u triangles)%s, %u thread(s), %d ticks, libccd %s, commit %s\n",
            (unsigned long long)n, (unsigned long long)seed, mesh_name, md.triangle_count,
            per_body == 2 ? ", a shape per body" : per_body ? ", a mesh per body" : "",
            last[0].thread_count ? last[0].thread_count : threads, ticks,
            hgcd_feature_libccd() == 2 ? "double" : hgcd_feature_libccd() == 1 ? "single" : "none", commit);
    fprintf(stderr, "%-8s %10s %10s %9s %10s %9s %12s %12s %12s\n", "mode", "narrow_ms", "detect_ms", "pairs", "candidates",
            "ns/cand", "libccd_tests", "pairs_differ", "cpu_ns/cand");
    for (int m = 0; m < MODE_COUNT; ++m) {
        if (!use[m]) continue;
        double nm[4096], dm[4096], cm[4096];
        const int k = ticks < 4096 ? ticks : 4096;
        for (int t = 0; t < k; ++t) {
            nm[t] = narrow_ms[t * MODE_COUNT + m];
            dm[t] = detect_ms[t * MODE_COUNT + m];
            cm[t] = narrow_cpu_ms[t * MODE_COUNT + m];
        }
        const double nmed = median(nm, k), dmed = median(dm, k), cmed = median(cm, k);
        const double cand = (double)(last[m].candidate_pairs ? last[m].candidate_pairs : 1);
        const double per = 1e6 * nmed / cand, cpu_per = 1e6 * cmed / cand;
        fprintf(stderr, "%-8s %10.2f %10.2f %9llu %10llu %9.1f %12llu %12zu %12.1f\n", all_modes[m].name, nmed, dmed,
                (unsigned long long)last[m].colliding_pairs, (unsigned long long)last[m].candidate_pairs, per,
                (unsigned long long)last[m].libccd_tests, last_differ[m], cpu_per);
        printf("{\"lib\":\"hgcd\",\"scene\":\"tetra\",\"n\":%llu,\"seed\":%llu,\"threads\":%u,\"ticks\":%d,"
               "\"commit\":\"%s\",\"mesh_triangles\":%u,\"narrow\":\"%s\",\"contacts\":%u,\"narrow_ms\":%.3f,\"detect_ms\":%.3f,"
               "\"pairs\":%llu,\"candidate_pairs\":%llu,\"ns_per_candidate\":%.1f,\"mesh\":\"%s\",\"libccd_tests\":%llu,"
               "\"pairs_differ\":%zu,\"libccd\":%d,\"narrow_cpu_ms\":%.3f,\"cpu_ns_per_candidate\":%.1f,"
               "\"mesh_per_body\":%d,\"pairs_fnv\":\"%016llx\"}\n",
               (unsigned long long)n, (unsigned long long)seed, last[m].thread_count, ticks, commit,
               md.triangle_count, all_modes[m].narrow == HGCD_NARROW_EXACT ? "exact" : all_modes[m].narrow == HGCD_NARROW_GJK ? "gjk" : "mpr",
               all_modes[m].contacts, nmed, dmed, (unsigned long long)last[m].colliding_pairs,
               (unsigned long long)last[m].candidate_pairs, per, mesh_name,
               (unsigned long long)last[m].libccd_tests, last_differ[m], hgcd_feature_libccd(), cmed, cpu_per, per_body,
               (unsigned long long)last_fnv[m]);
    }
    hgcd_world_destroy(w);
    free(own);
    free(ids);
    free(exact_pairs);
    free(sv);
    free(st_);
    free(centers);
    free(scales);
    free(quats);
    free(vels);
    free(narrow_ms);
    free(detect_ms);
    free(narrow_cpu_ms);
    return 0;
}
