/* Test helper: the observable state of a world, read only through the public
 * API, so a test can check that a refused call left the world exactly as it
 * was. Header-only (static functions) for the C test programs. */
#ifndef HGCD_TESTS_SNAPSHOT_H
#define HGCD_TESTS_SNAPSHOT_H

#include <stddef.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include <hgcd/hgcd.h>

/* Generations carry an 8-bit per-world tag in their top byte; the counter
 * (low 24 bits) is what two identically driven worlds share. */
#define SNAP_COUNTER(g) ((g) & 0xFFFFFFu)

typedef struct {
    hgcd_status valid;
    double position[3], orientation[4], velocity[3];
    hgcd_mesh mesh;
    uint64_t user_data;
    int32_t type;
    uint32_t enabled;
    hgcd_filter filter;
    double margin;
} snap_body;

typedef struct {
    hgcd_status valid;
    hgcd_mesh_info info;
} snap_mesh;

typedef struct {
    uint32_t body_count, mesh_count;
    size_t nbodies, nmeshes, npairs;
    snap_body *bodies; /* one per id given to snap_take */
    snap_mesh *meshes;
    hgcd_pair *pairs;  /* the last tick's pairs */
    const hgcd_pair *pairs_ptr;
    hgcd_stats stats;  /* timings zeroed */
    size_t nevents[2];
    hgcd_pair_event *events[2]; /* began, ended */
} snapshot;

/* Reads everything observable about the given ids. Allocates with malloc
 * only (never C++ operator new), so it can run under an allocation hook. */
static void snap_take(snapshot *s, const hgcd_world *w, const hgcd_body *bodies, size_t nbodies,
                      const hgcd_mesh *meshes, size_t nmeshes) {
    size_t k;
    memset(s, 0, sizeof *s);
    s->body_count = hgcd_world_body_count(w);
    s->mesh_count = hgcd_world_mesh_count(w);
    s->nbodies = nbodies;
    s->nmeshes = nmeshes;
    s->bodies = (snap_body *)calloc(nbodies + 1, sizeof *s->bodies);
    s->meshes = (snap_mesh *)calloc(nmeshes + 1, sizeof *s->meshes);
    for (k = 0; k < nbodies; ++k) {
        snap_body *b = &s->bodies[k];
        b->valid = hgcd_body_validate(w, bodies[k]);
        if (b->valid != HGCD_OK) continue;
        hgcd_body_get_pose(w, bodies[k], b->position, b->orientation);
        hgcd_body_get_velocity(w, bodies[k], b->velocity);
        hgcd_body_get_mesh(w, bodies[k], &b->mesh);
        hgcd_body_get_user_data(w, bodies[k], &b->user_data);
        hgcd_body_get_type(w, bodies[k], &b->type);
        hgcd_body_get_enabled(w, bodies[k], &b->enabled);
        hgcd_body_get_filter(w, bodies[k], &b->filter);
        hgcd_body_get_margin(w, bodies[k], &b->margin);
    }
    for (k = 0; k < nmeshes; ++k) {
        s->meshes[k].info.struct_size = sizeof s->meshes[k].info;
        s->meshes[k].valid = hgcd_mesh_get_info(w, meshes[k], &s->meshes[k].info);
    }
    hgcd_world_pairs(w, &s->pairs_ptr, &s->npairs);
    s->pairs = (hgcd_pair *)malloc((s->npairs + 1) * sizeof *s->pairs);
    if (s->npairs) memcpy(s->pairs, s->pairs_ptr, s->npairs * sizeof *s->pairs);
    s->stats.struct_size = sizeof s->stats;
    hgcd_world_stats(w, &s->stats);
    s->stats.motion_seconds = s->stats.update_seconds = s->stats.broad_seconds = 0;
    s->stats.narrow_seconds = s->stats.total_seconds = s->stats.events_seconds = 0;
    s->stats.thread_count = 0; /* the adaptive thread policy's choice, like a timing */
    {
        const hgcd_pair_event *ev[2];
        int e;
        hgcd_world_events(w, &ev[0], &s->nevents[0], &ev[1], &s->nevents[1]);
        for (e = 0; e < 2; ++e) {
            s->events[e] = (hgcd_pair_event *)malloc((s->nevents[e] + 1) * sizeof *s->events[e]);
            if (s->nevents[e]) memcpy(s->events[e], ev[e], s->nevents[e] * sizeof *s->events[e]);
        }
    }
}

static void snap_free(snapshot *s) {
    free(s->bodies);
    free(s->meshes);
    free(s->pairs);
    free(s->events[0]);
    free(s->events[1]);
    memset(s, 0, sizeof *s);
}

/* NULL if equal, else the name of the first difference. With same_world,
 * ids and the pairs pointer must match bit for bit; otherwise generations are
 * compared by their counters (two worlds driven the same way). */
static const char *snap_diff(const snapshot *a, const snapshot *b, int same_world) {
    size_t k;
    if (a->body_count != b->body_count) return "body count";
    if (a->mesh_count != b->mesh_count) return "mesh count";
    if (a->nbodies != b->nbodies || a->nmeshes != b->nmeshes) return "snapshot shape";
    for (k = 0; k < a->nbodies; ++k) {
        const snap_body *x = &a->bodies[k], *y = &b->bodies[k];
        if (x->valid != y->valid) return "body liveness";
        if (x->valid != HGCD_OK) continue;
        if (memcmp(x->position, y->position, sizeof x->position)) return "body position";
        if (memcmp(x->orientation, y->orientation, sizeof x->orientation)) return "body orientation";
        if (memcmp(x->velocity, y->velocity, sizeof x->velocity)) return "body velocity";
        if (x->user_data != y->user_data) return "body user data";
        if (x->type != y->type || x->enabled != y->enabled) return "body type or enabling";
        if (memcmp(&x->filter, &y->filter, sizeof x->filter)) return "body filter";
        if (memcmp(&x->margin, &y->margin, sizeof x->margin)) return "body margin";
        if (x->mesh.index != y->mesh.index) return "body mesh";
        if (same_world ? x->mesh.generation != y->mesh.generation
                       : SNAP_COUNTER(x->mesh.generation) != SNAP_COUNTER(y->mesh.generation))
            return "body mesh generation";
    }
    for (k = 0; k < a->nmeshes; ++k) {
        const snap_mesh *x = &a->meshes[k], *y = &b->meshes[k];
        if (x->valid != y->valid) return "mesh liveness";
        if (x->valid == HGCD_OK && memcmp(&x->info, &y->info, sizeof x->info)) return "mesh info";
    }
    if (a->npairs != b->npairs) return "pair count";
    if (same_world && a->npairs && a->pairs_ptr != b->pairs_ptr) return "pairs pointer";
    for (k = 0; k < a->npairs; ++k) {
        const hgcd_pair *x = &a->pairs[k], *y = &b->pairs[k];
        if (x->a.index != y->a.index || x->b.index != y->b.index) return "pair indices";
        if (same_world ? (x->a.generation != y->a.generation || x->b.generation != y->b.generation)
                       : (SNAP_COUNTER(x->a.generation) != SNAP_COUNTER(y->a.generation) ||
                          SNAP_COUNTER(x->b.generation) != SNAP_COUNTER(y->b.generation)))
            return "pair generations";
    }
    if (memcmp(&a->stats, &b->stats, sizeof a->stats)) return "statistics";
    for (k = 0; k < 2; ++k) {
        size_t j;
        if (a->nevents[k] != b->nevents[k]) return "event count";
        for (j = 0; j < a->nevents[k]; ++j) {
            const hgcd_pair_event *x = &a->events[k][j], *y = &b->events[k][j];
            if (x->pair.a.index != y->pair.a.index || x->pair.b.index != y->pair.b.index ||
                SNAP_COUNTER(x->pair.a.generation) != SNAP_COUNTER(y->pair.a.generation) ||
                SNAP_COUNTER(x->pair.b.generation) != SNAP_COUNTER(y->pair.b.generation) ||
                x->user_data_a != y->user_data_a || x->user_data_b != y->user_data_b)
                return "events";
        }
    }
    return NULL;
}

#endif /* HGCD_TESTS_SNAPSHOT_H */
