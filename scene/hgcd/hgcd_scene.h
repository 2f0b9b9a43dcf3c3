/*
 * The reference scenes of docs/scenes.md, generated bit for bit: the support
 * library libhgcd_scene for the tests, examples, benchmarks and bindings. Not
 * part of libhgcd (`make scene`; `make install-scene` installs it).
 */
#ifndef HGCD_SCENE_H
#define HGCD_SCENE_H

#include <stdint.h>

#include <hgcd/hgcd.h>

#ifdef __cplusplus
extern "C" {
#endif

/** Parameters of scene `tetra`. Obtain with hgcd_scene_tetra_desc_default(). */
typedef struct hgcd_scene_tetra_desc {
    uint32_t struct_size;
    uint32_t init_tag;
    /** Number of tetrahedra. Default 750000. */
    uint64_t n;
    /** splitmix64 seed. Default 1. */
    uint64_t seed;
    /** Cube side. Default 200. */
    double side;
    /** Circumradius range, log-uniform. Defaults 0.25 and 2. */
    double rmin;
    double rmax;
    /** Speed bound per tick. Default 0.05. */
    double vmax;
} hgcd_scene_tetra_desc;

HGCD_API hgcd_scene_tetra_desc hgcd_scene_tetra_desc_default(void);

/** Draws the n objects of scene `tetra`. Each output array may be NULL to
 *  skip it; otherwise it holds n entries of: centers 3 doubles, radii 1
 *  (circumradius r), scales 1 (r / sqrt(3), the body scale for the unit mesh
 *  of hgcd_scene_tetra_unit_mesh), orientations 4 (x, y, z, w), velocities 3.
 *  Errors: -1 (HGCD_ERROR_NULL_ARGUMENT) for a NULL desc, -3
 *  (HGCD_ERROR_BAD_DESCRIPTOR), -2 (HGCD_ERROR_INVALID_ARGUMENT) for
 *  non-finite or out-of-order parameters, -8 (HGCD_ERROR_CAPACITY) when
 *  n * 4 doubles would overflow. */
HGCD_API int32_t hgcd_scene_tetra_generate(const hgcd_scene_tetra_desc *desc,
                                           double *centers, double *radii,
                                           double *scales,
                                           double *orientations,
                                           double *velocities);

/** Puts scene `tetra` into world: one mesh (the unit tetrahedron of
 *  hgcd_scene_tetra_unit_mesh) and desc->n bodies, body i with the pose,
 *  scale and velocity hgcd_scene_tetra_generate draws for object i and
 *  user_data i, created in that order (so body i gets slot i in a fresh
 *  world). The world's bounds and reflection are the caller's: the scene
 *  lives in [0, side]^3 and reflects there. The mesh id goes to *mesh_out
 *  unless it is NULL. Errors: HGCD_ERROR_NULL_ARGUMENT for a NULL world or
 *  desc, the errors of hgcd_scene_tetra_generate for desc, and the first
 *  error of hgcd_mesh_create or hgcd_body_create (e.g.
 *  HGCD_ERROR_OUT_OF_MEMORY, or HGCD_ERROR_CAPACITY past the body limit);
 *  then the bodies and the mesh made so far are destroyed again, so the
 *  world holds nothing of the call (the ids they had are retired). Same
 *  threading rules as hgcd_body_create: no other call on the world meanwhile. */
HGCD_API int32_t hgcd_scene_tetra_populate(hgcd_world *world, const hgcd_scene_tetra_desc *desc,
                                           hgcd_mesh *mesh_out);

/** The unit sign-pattern tetrahedron of docs/scenes.md: vertices (1,1,1),
 *  (1,-1,-1), (-1,1,-1), (-1,-1,1) into vertices[12] and the faces (0,1,2)
 *  (0,3,1) (0,2,3) (1,3,2) into triangles[12]. Scaled by r / sqrt(3) it is the
 *  scene's tetrahedron of circumradius r, bit for bit. NULL pointers are
 *  skipped. */
HGCD_API void hgcd_scene_tetra_unit_mesh(double *vertices, uint32_t *triangles);

/** One tick of the scene's motion for n objects: center += velocity, mirrored
 *  back into [0, side] per coordinate with that velocity component negated,
 *  exactly as docs/scenes.md writes it. For callers that move bodies themselves. */
HGCD_API void hgcd_scene_tetra_move(uint64_t n, double side, double *centers,
                                    double *velocities);

#ifdef __cplusplus
}
#endif

#endif /* HGCD_SCENE_H */
