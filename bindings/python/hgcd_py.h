/*
 * The Python binding's own C loops, compiled into the extension module after
 * hgcd.h (hgcd_build.py): calls over many bodies that the C API makes one body
 * at a time, so that Python crosses into C once per array, not once per body.
 * Each checks everything it can before changing the world and, when a call
 * fails half-way, undoes what it did, so a refused call leaves the world's
 * bodies as they were (only the ids of undone bodies are retired).
 */

/* Per-body columns of hgcd_py_create_bodies, each packed or NULL (the
 * descriptor's default): positions and velocities 3 doubles a body,
 * orientations 4, the others one value a body. */
typedef struct hgcd_py_body_columns {
    const double *positions;
    const double *orientations;
    const double *velocities;
    const double *scales;
    const uint64_t *user_data;
    const int32_t *types;
    const uint8_t *enabled;
    const hgcd_filter *filters;
    const double *margins;
} hgcd_py_body_columns;

/* Creates count bodies in order; entry k takes meshes[k] (or meshes[0] when
 * mesh_count is 1) and entry k of each column. On failure the bodies made
 * are destroyed again, newest first (so their slots come back in the same
 * order), and *out_failed is the entry refused. */
static hgcd_status hgcd_py_create_bodies(hgcd_world *world, const hgcd_mesh *meshes, size_t mesh_count,
                                         size_t count, const hgcd_py_body_columns *c,
                                         hgcd_body *out_bodies, size_t *out_failed) {
    hgcd_body_desc desc = hgcd_body_desc_default();
    for (size_t k = 0; k < count; ++k) {
        desc.mesh = meshes[mesh_count == 1 ? 0 : k];
        for (int i = 0; i < 3; ++i) {
            if (c->positions) desc.position[i] = c->positions[3 * k + i];
            if (c->velocities) desc.velocity[i] = c->velocities[3 * k + i];
        }
        if (c->orientations)
            for (int i = 0; i < 4; ++i) desc.orientation[i] = c->orientations[4 * k + i];
        if (c->scales) desc.scale = c->scales[k];
        if (c->user_data) desc.user_data = c->user_data[k];
        if (c->types) desc.type = c->types[k];
        if (c->enabled) desc.enabled = c->enabled[k];
        if (c->filters) desc.filter = c->filters[k];
        if (c->margins) desc.margin = c->margins[k];
        const hgcd_status s = hgcd_body_create(world, &desc, &out_bodies[k]);
        if (s != HGCD_OK) {
            *out_failed = k;
            while (k > 0) hgcd_body_destroy(world, out_bodies[--k]);
            return s;
        }
    }
    return HGCD_OK;
}

/* Sets the types, enabled flags and/or filters (each array NULL to leave
 * it; entry k for body k) of count bodies. Everything is checked first (live ids, known types,
 * reserved filter fields 0), so a refusal changes nothing; *out_failed is
 * the entry refused. */
static hgcd_status hgcd_py_set_flags(hgcd_world *world, const hgcd_body *bodies, size_t count,
                                     const int32_t *types, const uint8_t *enabled,
                                     const hgcd_filter *filters, size_t *out_failed) {
    for (size_t k = 0; k < count; ++k) {
        *out_failed = k;
        if (hgcd_body_validate(world, bodies[k]) != HGCD_OK) return HGCD_ERROR_STALE_ID;
        if (types && (types[k] < HGCD_BODY_DYNAMIC || types[k] > HGCD_BODY_STATIC))
            return HGCD_ERROR_INVALID_ARGUMENT;
        if (filters && filters[k].reserved != 0) return HGCD_ERROR_INVALID_ARGUMENT;
    }
    for (size_t k = 0; k < count; ++k) {
        hgcd_status s = HGCD_OK;
        *out_failed = k;
        if (types) s = hgcd_body_set_type(world, bodies[k], types[k]);
        if (s == HGCD_OK && enabled) s = hgcd_body_set_enabled(world, bodies[k], enabled[k]);
        if (s == HGCD_OK && filters) s = hgcd_body_set_filter(world, bodies[k], &filters[k]);
        if (s != HGCD_OK) return HGCD_ERROR_INTERNAL;  /* checked above: cannot happen */
    }
    return HGCD_OK;
}

/* Reads the types, enabled flags and/or filters (each NULL to skip) of count
 * bodies; nothing is written past a stale id, whose entry goes to
 * *out_failed. Read-only. */
static hgcd_status hgcd_py_get_flags(const hgcd_world *world, const hgcd_body *bodies, size_t count,
                                     int32_t *types, uint8_t *enabled, hgcd_filter *filters,
                                     size_t *out_failed) {
    for (size_t k = 0; k < count; ++k) {
        uint32_t on = 0;
        hgcd_status s = hgcd_body_get_enabled(world, bodies[k], &on);
        if (s == HGCD_OK && types) s = hgcd_body_get_type(world, bodies[k], types + k);
        if (s == HGCD_OK && filters) s = hgcd_body_get_filter(world, bodies[k], filters + k);
        if (s != HGCD_OK) {
            *out_failed = k;
            return s;
        }
        if (enabled) enabled[k] = on != 0;
    }
    return HGCD_OK;
}

/* Checks that pair k has two live, distinct bodies; the status of the first
 * bad entry, which goes to *out_failed. */
static hgcd_status hgcd_py_check_pairs(const hgcd_world *world, const hgcd_pair *pairs, size_t count,
                                       size_t *out_failed) {
    for (size_t k = 0; k < count; ++k) {
        *out_failed = k;
        if (hgcd_body_validate(world, pairs[k].a) != HGCD_OK ||
            hgcd_body_validate(world, pairs[k].b) != HGCD_OK)
            return HGCD_ERROR_STALE_ID;
        if (pairs[k].a.index == pairs[k].b.index) return HGCD_ERROR_INVALID_ARGUMENT;
    }
    return HGCD_OK;
}

/* Excludes (exclude != 0) or includes again count pairs, all or none: every
 * pair is checked first, scratch (count bytes) records which pairs were
 * excluded before, and an exclusion refused for lack of memory undoes the
 * ones made. */
static hgcd_status hgcd_py_set_excluded(hgcd_world *world, const hgcd_pair *pairs, size_t count,
                                        uint32_t exclude, uint8_t *scratch, size_t *out_failed) {
    hgcd_status s = hgcd_py_check_pairs(world, pairs, count, out_failed);
    for (size_t k = 0; s == HGCD_OK && k < count; ++k) {
        uint32_t was = 0;
        s = hgcd_world_pair_excluded(world, pairs[k].a, pairs[k].b, &was);
        scratch[k] = was != 0;
    }
    if (s != HGCD_OK) return s;
    for (size_t k = 0; k < count; ++k) {
        s = exclude ? hgcd_world_exclude_pair(world, pairs[k].a, pairs[k].b)
                    : hgcd_world_include_pair(world, pairs[k].a, pairs[k].b);
        if (s != HGCD_OK) {
            *out_failed = k;
            while (k > 0) {  /* only exclusions can fail (memory): undo the new ones */
                --k;
                if (!scratch[k]) hgcd_world_include_pair(world, pairs[k].a, pairs[k].b);
            }
            return s;
        }
    }
    return HGCD_OK;
}

/* out_excluded[k] = 1 if pair k is excluded, else 0. Read-only. */
static hgcd_status hgcd_py_pairs_excluded(const hgcd_world *world, const hgcd_pair *pairs, size_t count,
                                          uint8_t *out_excluded, size_t *out_failed) {
    hgcd_status s = hgcd_py_check_pairs(world, pairs, count, out_failed);
    for (size_t k = 0; s == HGCD_OK && k < count; ++k) {
        uint32_t was = 0;
        s = hgcd_world_pair_excluded(world, pairs[k].a, pairs[k].b, &was);
        out_excluded[k] = was != 0;
    }
    return s;
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

/* Sets the contact margins of count bodies (entry k for body k). The ids are
 * checked first; a margin the library refuses undoes the ones set before it
 * (their old values were read first), so a refusal changes nothing.
 * *out_failed is the entry refused. */
static hgcd_status hgcd_py_set_margins(hgcd_world *world, const hgcd_body *bodies, size_t count,
                                       const double *margins, double *scratch, size_t *out_failed) {
    for (size_t k = 0; k < count; ++k) {
        *out_failed = k;
        if (hgcd_body_get_margin(world, bodies[k], scratch + k) != HGCD_OK) return HGCD_ERROR_STALE_ID;
    }
    for (size_t k = 0; k < count; ++k) {
        const hgcd_status s = hgcd_body_set_margin(world, bodies[k], margins[k]);
        if (s != HGCD_OK) {
            *out_failed = k;
            while (k > 0) {
                --k;
                hgcd_body_set_margin(world, bodies[k], scratch[k]);
            }
            return s;
        }
    }
    return HGCD_OK;
}

/* Reads the contact margins of count bodies; nothing is written past a stale
 * id, whose entry goes to *out_failed. Read-only. */
static hgcd_status hgcd_py_get_margins(const hgcd_world *world, const hgcd_body *bodies, size_t count,
                                       double *margins, size_t *out_failed) {
    for (size_t k = 0; k < count; ++k) {
        const hgcd_status s = hgcd_body_get_margin(world, bodies[k], margins + k);
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
