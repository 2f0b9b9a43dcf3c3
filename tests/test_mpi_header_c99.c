/* Compile-only check: hgcd_mpi.h is strict C99 (with mpi.h), and its layouts
 * are what the documentation states. */
#include <hgcd/hgcd_mpi.h>

#include <stddef.h>

#define STATIC_CHECK(name, cond) typedef char static_check_##name[(cond) ? 1 : -1]

STATIC_CHECK(pair_size, sizeof(hgcd_mpi_pair) == 16);
STATIC_CHECK(world_desc_first, offsetof(hgcd_mpi_world_desc, struct_size) == 0);
STATIC_CHECK(body_desc_first, offsetof(hgcd_mpi_body_desc, struct_size) == 0);
STATIC_CHECK(body_desc_id, offsetof(hgcd_mpi_body_desc, id) == 8);
STATIC_CHECK(stats_first, offsetof(hgcd_mpi_stats, struct_size) == 0);

int main(void) {
    hgcd_mpi_world_desc d = hgcd_mpi_world_desc_default();
    return d.struct_size == sizeof d ? 0 : 1;
}
