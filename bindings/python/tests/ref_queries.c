/*
 * Scene queries through the C API, for the Python tests to compare with the
 * binding's: scene tetra (hgcd_scene_tetra_populate) in a world of THREADS
 * threads, COUNT rays, boxes, points and poses of the tetrahedron mesh drawn
 * with splitmix64 (seeded by SEED + 1) in [0, SIDE]^3.
 *
 *   ref_queries N SEED SIDE THREADS COUNT OUT
 *
 * OUT (little-endian): uint64 COUNT; the rays (COUNT x 7 double: origin,
 * direction, max_distance), the closest hits and the any hits (COUNT x
 * hgcd_ray_hit each); the boxes (COUNT x 6 double), then their results; the
 * points (COUNT x 3 double), their results; the poses (COUNT x 8 double:
 * position, orientation, scale), their results. Results: uint64 body_count,
 * (COUNT + 1) uint64 offsets, body_count x (uint32 index, uint32
 * generation).
 */
#include <hgcd/hgcd.h>
#include <hgcd/hgcd_scene.h>

#include <math.h>
#include <stdio.h>
#include <stdlib.h>

static hgcd_world *world;
static uint64_t state;

static void check(hgcd_status s, const char *what) {
    if (s == HGCD_OK) return;
    fprintf(stderr, "ref_queries: %s: %s (%s)\n", what, hgcd_status_string(s), hgcd_world_last_error(world));
    exit(1);
}

static double unif(void) {
    uint64_t z = (state += 0x9E3779B97F4A7C15ull);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return ldexp((double)((z ^ (z >> 31)) >> 11), -53);
}

static void put(FILE *out, const void *p, size_t bytes) {
    if (bytes && fwrite(p, 1, bytes, out) != bytes) {
        fprintf(stderr, "ref_queries: write failed\n");
        exit(1);
    }
}

static void put_results(FILE *out, const hgcd_query_results *r) {
    const uint64_t m = r->body_count;
    size_t k;
    put(out, &m, sizeof m);
    for (k = 0; k <= r->query_count; ++k) {
        const uint64_t o = r->offsets[k];
        put(out, &o, sizeof o);
    }
    put(out, r->bodies, m * sizeof(hgcd_body));
}

int main(int argc, char **argv) {
    hgcd_world_desc wd = hgcd_world_desc_default();
    hgcd_scene_tetra_desc td = hgcd_scene_tetra_desc_default();
    hgcd_mesh mesh;
    hgcd_query_results res;
    FILE *out;
    double side;
    uint64_t count;
    size_t k;
    int a;
    if (argc != 7) {
        fprintf(stderr, "usage: ref_queries N SEED SIDE THREADS COUNT OUT\n");
        return 2;
    }
    td.n = strtoull(argv[1], NULL, 10);
    td.seed = strtoull(argv[2], NULL, 10);
    td.side = side = strtod(argv[3], NULL);
    wd.thread_count = (uint32_t)strtoul(argv[4], NULL, 10);
    count = strtoull(argv[5], NULL, 10);
    state = td.seed + 1;
    check(hgcd_world_create(&wd, &world), "world_create");
    check(hgcd_scene_tetra_populate(world, &td, &mesh), "populate");
    out = fopen(argv[6], "wb");
    if (!out) return 1;
    put(out, &count, sizeof count);
    {
        hgcd_ray *rays = malloc(count * sizeof *rays);
        hgcd_ray_hit *hits = malloc(count * sizeof *hits);
        for (k = 0; k < count; ++k) {
            for (a = 0; a < 3; ++a) rays[k].origin[a] = side * unif();
            for (a = 0; a < 3; ++a) rays[k].direction[a] = 2 * unif() - 1;
            rays[k].max_distance = 0.25 * side * unif();
        }
        put(out, rays, count * sizeof *rays);
        check(hgcd_world_cast_rays(world, rays, count, 0, HGCD_RAY_CLOSEST, NULL, hits), "cast_rays");
        put(out, hits, count * sizeof *hits);
        check(hgcd_world_cast_rays(world, rays, count, 0, HGCD_RAY_ANY, NULL, hits), "cast_rays any");
        put(out, hits, count * sizeof *hits);
        free(rays);
        free(hits);
    }
    {
        double *boxes = malloc(count * 6 * sizeof *boxes), *points = malloc(count * 3 * sizeof *points);
        hgcd_mesh_pose *poses = malloc(count * sizeof *poses);
        for (k = 0; k < count; ++k)
            for (a = 0; a < 3; ++a) {
                const double c = side * unif(), h = 2 * unif();
                boxes[6 * k + a] = c - h;
                boxes[6 * k + 3 + a] = c + h;
            }
        put(out, boxes, count * 6 * sizeof *boxes);
        check(hgcd_world_query_box(world, boxes, count, 0, NULL, &res), "query_box");
        put_results(out, &res);
        for (k = 0; k < 3 * count; ++k) points[k] = side * unif();
        put(out, points, count * 3 * sizeof *points);
        check(hgcd_world_query_point(world, points, count, 0, NULL, &res), "query_point");
        put_results(out, &res);
        for (k = 0; k < count; ++k) {
            for (a = 0; a < 3; ++a) poses[k].position[a] = side * unif();
            poses[k].orientation[0] = poses[k].orientation[1] = 0;
            poses[k].orientation[2] = sin(0.5 * unif());
            poses[k].orientation[3] = sqrt(1 - poses[k].orientation[2] * poses[k].orientation[2]);
            poses[k].scale = 0.5 + 2 * unif();
        }
        put(out, poses, count * sizeof *poses);
        check(hgcd_world_query_mesh(world, mesh, poses, count, 0, NULL, &res), "query_mesh");
        put_results(out, &res);
        free(boxes);
        free(points);
        free(poses);
    }
    fclose(out);
    hgcd_world_destroy(world);
    return 0;
}
