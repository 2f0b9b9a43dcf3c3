/* Compile-only check: the public header is strict C99, and the ABI layouts
 * are what the documentation and the bindings assume. */
#include <hgcd/hgcd.h>

#include <stddef.h>

#define STATIC_CHECK(name, cond) typedef char static_check_##name[(cond) ? 1 : -1]

STATIC_CHECK(body_size, sizeof(hgcd_body) == 8);
STATIC_CHECK(mesh_size, sizeof(hgcd_mesh) == 8);
STATIC_CHECK(pair_size, sizeof(hgcd_pair) == 16);
STATIC_CHECK(pair_b, offsetof(hgcd_pair, b) == 8);
STATIC_CHECK(world_desc_first, offsetof(hgcd_world_desc, struct_size) == 0);
STATIC_CHECK(body_desc_first, offsetof(hgcd_body_desc, struct_size) == 0);
STATIC_CHECK(mesh_desc_first, offsetof(hgcd_mesh_desc, struct_size) == 0);
STATIC_CHECK(stats_first, offsetof(hgcd_stats, struct_size) == 0);
STATIC_CHECK(status_size, sizeof(hgcd_status) == 4);

int main(void) {
    hgcd_world_desc d = hgcd_world_desc_default();
    return d.struct_size == sizeof d ? 0 : 1;
}
