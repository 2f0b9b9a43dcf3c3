/*
 * The pairs of a scene through the C API alone, one body per call, for the
 * Python tests to compare with the binding's (which creates, poses and reads
 * in bulk). Writes, for each detect, a uint64 count and count (a, b) uint32
 * index pairs to OUT.
 *
 *   ref_pairs tetra N SEED SIDE TICKS THREADS OUT
 *       scene tetra through hgcd_scene_tetra_populate in a world reflecting
 *       at [0, SIDE]^3; a detect, then TICKS hgcd_world_step.
 *   ref_pairs scene IN THREADS OUT
 *       IN (little-endian, as tests/test_compare_c.py writes it):
 *       uint64 mesh_count; per mesh uint64 V, T, V*3 double, T*3 uint32;
 *       uint64 body_count; per body uint64 mesh, double position[3],
 *       orientation[4], scale; uint64 ticks; per tick body_count * (position[3],
 *       orientation[4]) set one hgcd_body_set_pose at a time, then a detect.
 *       A detect is also made before the first tick.
 */
#include <hgcd/hgcd.h>
#include <hgcd/hgcd_scene.h>

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static hgcd_world *world;

static void check(hgcd_status s, const char *what) {
    if (s == HGCD_OK) return;
    fprintf(stderr, "ref_pairs: %s: %s (%s)\n", what, hgcd_status_string(s), hgcd_world_last_error(world));
    exit(1);
}

static void read_exact(FILE *f, void *p, size_t size, size_t count) {
    if (fread(p, size, count, f) != count) {
        fprintf(stderr, "ref_pairs: short input\n");
        exit(1);
    }
}

static uint64_t read_u64(FILE *f) {
    uint64_t v;
    read_exact(f, &v, sizeof v, 1);
    return v;
}

static void *checked_malloc(size_t bytes) {
    void *p = malloc(bytes ? bytes : 1);
    if (!p) {
        fprintf(stderr, "ref_pairs: out of memory\n");
        exit(1);
    }
    return p;
}

static void write_pairs(FILE *out) {
    size_t total = 0;
    check(hgcd_world_copy_pairs(world, NULL, 0, &total), "copy_pairs");
    hgcd_pair *pairs = checked_malloc(total * sizeof *pairs);
    check(hgcd_world_copy_pairs(world, pairs, total, &total), "copy_pairs");
    const uint64_t count = total;
    fwrite(&count, sizeof count, 1, out);
    for (size_t k = 0; k < total; ++k) {
        const uint32_t ab[2] = {pairs[k].a.index, pairs[k].b.index};
        fwrite(ab, sizeof ab, 1, out);
    }
    free(pairs);
}

static void make_world(unsigned threads, int reflect, double side) {
    hgcd_world_desc wd = hgcd_world_desc_default();
    wd.thread_count = threads;
    wd.reflect_at_bounds = (uint32_t)reflect;
    for (int k = 0; k < 3; ++k) wd.bounds_max[k] = reflect ? side : 1.0;
    check(hgcd_world_create(&wd, &world), "world_create");
}

static void run_tetra(char **argv, FILE *out) {
    hgcd_scene_tetra_desc sd = hgcd_scene_tetra_desc_default();
    sd.n = strtoull(argv[2], NULL, 10);
    sd.seed = strtoull(argv[3], NULL, 10);
    sd.side = strtod(argv[4], NULL);
    const int ticks = atoi(argv[5]);
    make_world((unsigned)atoi(argv[6]), 1, sd.side);
    check(hgcd_scene_tetra_populate(world, &sd, NULL), "scene_tetra_populate");
    check(hgcd_world_detect(world), "detect");
    write_pairs(out);
    for (int t = 0; t < ticks; ++t) {
        check(hgcd_world_step(world), "step");
        write_pairs(out);
    }
}

static void run_scene(FILE *in, unsigned threads, FILE *out) {
    make_world(threads, 0, 0);
    const uint64_t mesh_count = read_u64(in);
    hgcd_mesh *meshes = checked_malloc(mesh_count * sizeof *meshes);
    for (uint64_t m = 0; m < mesh_count; ++m) {
        const uint64_t v = read_u64(in), t = read_u64(in);
        double *vertices = checked_malloc(v * 3 * sizeof *vertices);
        uint32_t *triangles = checked_malloc(t * 3 * sizeof *triangles);
        read_exact(in, vertices, sizeof *vertices, v * 3);
        read_exact(in, triangles, sizeof *triangles, t * 3);
        hgcd_mesh_desc md = hgcd_mesh_desc_default();
        md.vertices = vertices;
        md.triangles = triangles;
        md.vertex_count = (uint32_t)v;
        md.triangle_count = (uint32_t)t;
        check(hgcd_mesh_create(world, &md, &meshes[m]), "mesh_create");
        free(vertices);
        free(triangles);
    }
    const uint64_t body_count = read_u64(in);
    hgcd_body *bodies = checked_malloc(body_count * sizeof *bodies);
    for (uint64_t b = 0; b < body_count; ++b) {
        hgcd_body_desc bd = hgcd_body_desc_default();
        bd.mesh = meshes[read_u64(in)];
        read_exact(in, bd.position, sizeof(double), 3);
        read_exact(in, bd.orientation, sizeof(double), 4);
        read_exact(in, &bd.scale, sizeof(double), 1);
        check(hgcd_body_create(world, &bd, &bodies[b]), "body_create");
    }
    check(hgcd_world_detect(world), "detect");
    write_pairs(out);
    const uint64_t ticks = read_u64(in);
    for (uint64_t t = 0; t < ticks; ++t) {
        for (uint64_t b = 0; b < body_count; ++b) {
            double pose[7];
            read_exact(in, pose, sizeof(double), 7);
            check(hgcd_body_set_pose(world, bodies[b], pose, pose + 3), "body_set_pose");
        }
        check(hgcd_world_detect(world), "detect");
        write_pairs(out);
    }
    free(meshes);
    free(bodies);
}

int main(int argc, char **argv) {
    const int tetra = argc == 8 && !strcmp(argv[1], "tetra");
    if (!tetra && !(argc == 5 && !strcmp(argv[1], "scene"))) {
        fprintf(stderr, "usage: ref_pairs tetra N SEED SIDE TICKS THREADS OUT | scene IN THREADS OUT\n");
        return 2;
    }
    FILE *out = fopen(argv[argc - 1], "wb");
    if (!out) return 1;
    if (tetra) {
        run_tetra(argv, out);
    } else {
        FILE *in = fopen(argv[2], "rb");
        if (!in) return 1;
        run_scene(in, (unsigned)atoi(argv[3]), out);
        fclose(in);
    }
    hgcd_world_destroy(world);
    return fclose(out) == 0 ? 0 : 1;
}
