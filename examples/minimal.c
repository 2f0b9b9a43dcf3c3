/* The loop an engine runs: one world, one mesh, a few bodies; each tick the
 * engine sets the poses it computed, hgcd detects, the engine reads pairs. */
#include <hgcd/hgcd.h>
#include <stdio.h>

#define CHECK(call)                                                        \
    do {                                                                   \
        hgcd_status s_ = (call);                                           \
        if (s_ != HGCD_OK) {                                               \
            fprintf(stderr, "%s: %s (%s)\n", #call, hgcd_status_string(s_), \
                    hgcd_world_last_error(world));                         \
            return 1;                                                      \
        }                                                                  \
    } while (0)

int main(void) {
    hgcd_world *world = NULL;
    hgcd_world_desc wd = hgcd_world_desc_default(); /* thread_count 0: all cores */
    CHECK(hgcd_world_create(&wd, &world));

    /* A tetrahedron (any closed or open triangle mesh will do). */
    static const double vertices[] = {1, 1, 1, 1, -1, -1, -1, 1, -1, -1, -1, 1};
    static const uint32_t triangles[] = {0, 1, 2, 0, 3, 1, 0, 2, 3, 1, 3, 2};
    hgcd_mesh_desc md = hgcd_mesh_desc_default();
    md.vertices = vertices; /* copied in */
    md.vertex_count = 4;
    md.triangles = triangles;
    md.triangle_count = 4;
    hgcd_mesh mesh;
    CHECK(hgcd_mesh_create(world, &md, &mesh));

    /* Three bodies on the x axis, 3 units apart: bodies 0, 1, 2. */
    hgcd_body bodies[3];
    for (int i = 0; i < 3; ++i) {
        hgcd_body_desc bd = hgcd_body_desc_default();
        bd.mesh = mesh;
        bd.position[0] = 3.0 * i;
        CHECK(hgcd_body_create(world, &bd, &bodies[i]));
    }

    for (int tick = 0; tick < 4; ++tick) {
        /* The engine's poses: body 1 slides towards body 0; at tick 2 an edge
         * of each touches the other's (touching counts), at tick 3 they overlap. */
        const double position[3] = {3.0 - 0.5 * tick, 0, 0};
        const double orientation[4] = {0, 0, 0, 1}; /* (x, y, z, w) */
        CHECK(hgcd_body_set_pose(world, bodies[1], position, orientation));

        CHECK(hgcd_world_detect(world));
        const hgcd_pair *pairs;
        size_t count;
        CHECK(hgcd_world_pairs(world, &pairs, &count));
        printf("tick %d: %zu pair(s)", tick, count);
        for (size_t k = 0; k < count; ++k) /* sorted, a.index < b.index */
            printf("  (%u, %u)", pairs[k].a.index, pairs[k].b.index);
        printf("\n");
    }
    hgcd_world_destroy(world);
    return 0;
}
