/*
 * The Python binding's own C loops, compiled into the extension module after
 * hgcd.h (hgcd_build.py): calls over many bodies that the C API makes one body
 * at a time, so that Python crosses into C once per array, not once per body.
 * Each checks everything it can before changing the world and, when a call
 * fails half-way, undoes what it did, so a refused call leaves the world's
 * bodies as they were (only the ids of undone bodies are retired).
 */

/* Creates count bodies in order; entry k takes meshes[k] (or meshes[0] when
 * mesh_count is 1) and entry k of each packed array, or the descriptor's
 * default where an array is NULL. On failure the bodies made are destroyed
 * again, newest first (so their slots come back in the same order), and
 * *out_failed is the entry refused. */
static hgcd_status hgcd_py_create_bodies(hgcd_world *world, const hgcd_mesh *meshes, size_t mesh_count,
                                         size_t count, const double *positions,
                                         const double *orientations, const double *velocities,
                                         const double *scales, const uint64_t *user_data,
                                         hgcd_body *out_bodies, size_t *out_failed) {
    hgcd_body_desc desc = hgcd_body_desc_default();
    for (size_t k = 0; k < count; ++k) {
        desc.mesh = meshes[mesh_count == 1 ? 0 : k];
        for (int i = 0; i < 3; ++i) {
            if (positions) desc.position[i] = positions[3 * k + i];
            if (velocities) desc.velocity[i] = velocities[3 * k + i];
        }
        if (orientations)
            for (int i = 0; i < 4; ++i) desc.orientation[i] = orientations[4 * k + i];
        if (scales) desc.scale = scales[k];
        if (user_data) desc.user_data = user_data[k];
        const hgcd_status s = hgcd_body_create(world, &desc, &out_bodies[k]);
        if (s != HGCD_OK) {
            *out_failed = k;
            while (k > 0) hgcd_body_destroy(world, out_bodies[--k]);
            return s;
        }
    }
    return HGCD_OK;
}

/* 1 where bodies[k] is live in world, else 0; returns how many are live. */
static size_t hgcd_py_validate_bodies(const hgcd_world *world, const hgcd_body *bodies, size_t count,
                                      uint8_t *out_live) {
    size_t live = 0;
    for (size_t k = 0; k < count; ++k) {
        out_live[k] = hgcd_body_validate(world, bodies[k]) == HGCD_OK;
        live += out_live[k];
    }
    return live;
}

/* Destroys count distinct bodies (the caller checks they are distinct): all
 * are checked live first, so a stale one refuses the call with nothing
 * destroyed (*out_failed is its entry). */
static hgcd_status hgcd_py_destroy_bodies(hgcd_world *world, const hgcd_body *bodies, size_t count,
                                          size_t *out_failed) {
    for (size_t k = 0; k < count; ++k) {
        if (hgcd_body_validate(world, bodies[k]) != HGCD_OK) {
            *out_failed = k;
            return HGCD_ERROR_STALE_ID;
        }
    }
    for (size_t k = 0; k < count; ++k) {
        const hgcd_status s = hgcd_body_destroy(world, bodies[k]);
        if (s != HGCD_OK) {
            *out_failed = k;
            return s;
        }
    }
    return HGCD_OK;
}

/* Reads the velocities (3 doubles each), meshes and user data of count bodies
 * into the outputs that are not NULL; nothing is written past a stale id,
 * whose entry goes to *out_failed. Read-only. */
static hgcd_status hgcd_py_get_bodies(const hgcd_world *world, const hgcd_body *bodies, size_t count,
                                      double *velocities, hgcd_mesh *meshes, uint64_t *user_data,
                                      size_t *out_failed) {
    for (size_t k = 0; k < count; ++k) {
        hgcd_status s = HGCD_OK;
        if (velocities) s = hgcd_body_get_velocity(world, bodies[k], velocities + 3 * k);
        if (s == HGCD_OK && meshes) s = hgcd_body_get_mesh(world, bodies[k], meshes + k);
        if (s == HGCD_OK && user_data) s = hgcd_body_get_user_data(world, bodies[k], user_data + k);
        if (s != HGCD_OK) {
            *out_failed = k;
            return s;
        }
    }
    return HGCD_OK;
}

/* Whether the calling thread holds the GIL: cffi's API-mode wrappers release
 * it around every call, so through them this returns 0 (a test checks that
 * the same wrappers run detect and step without the GIL). */
static int hgcd_py_gil_held(void) { return PyGILState_Check(); }
