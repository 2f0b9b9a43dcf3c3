/*
 * hgcd: parallel collision detection between many rigid triangle meshes.
 *
 * This header is the whole contract. It is strict C99 and contains no macros
 * that are part of the API (the version macros live in hgcd_version.h).
 *
 * Model
 * -----
 * A world holds meshes (shared shapes: vertices and triangles, copied in) and
 * bodies (placed instances of a mesh: position, orientation, velocity). Each
 * tick, hgcd_world_detect() reports every pair of bodies whose closed solids
 * share a point: their surfaces intersect (touching counts), or one closed mesh
 * lies wholly inside the other. An open mesh (one that does not bound a volume)
 * collides only through its surface. The test is exact: it is decided with
 * exact orientation predicates on the world-space vertices as hgcd computes
 * them (see "World-space vertices" below), never with a tolerance. (A world
 * or mesh may instead hand pairs of convex meshes to libccd, which uses
 * tolerances: see enum hgcd_narrow_phase.)
 *
 * Ids
 * ---
 * Meshes and bodies are small value ids {index, generation}. The all-zero id is
 * the null id and is never returned for a live object. A destroyed object's id
 * becomes stale: every call given it returns HGCD_ERROR_STALE_ID, also after the
 * index has been reused. On a fresh world, bodies get indices 0, 1, 2, ... in
 * creation order, so pairs map straight back to the caller's arrays; a
 * destroyed body's index is reused by a later hgcd_body_create.
 * Ids of one world given to another world are refused as HGCD_ERROR_STALE_ID
 * (the generation carries an 8-bit world tag: the tags of any 256 worlds
 * created one after another differ, so a foreign id from one of them is always
 * caught, and from others with probability 255/256; a forged id with a wrong
 * generation always is). Two worlds built alike therefore agree on indices,
 * not on generations. The tag follows the order in which the process creates
 * worlds, so a program that creates them in the same order gets the same ids,
 * bit for bit, on every run.
 *
 * Errors
 * ------
 * Every fallible call returns an hgcd_status: HGCD_OK (0) or a negative code.
 * hgcd_status_string() names a code; hgcd_world_last_error() gives the detail
 * of the last failed call on that world that takes a non-const world
 * ("body_create: position[1] is not finite"). Calls taking a const world only
 * read it and return a status without recording a message, so they can
 * overlap safely. A failed call leaves the world exactly as it was (apart from
 * the recorded message); the one exception is HGCD_ERROR_OUT_OF_MEMORY from
 * hgcd_world_detect and hgcd_world_step, described there. When several
 * things are wrong, the first of these is reported: a NULL pointer, a
 * descriptor not from its *_desc_default(), a stale id, a bad value. No call
 * aborts, throws or crashes on bad arguments; out-of-memory is reported as
 * HGCD_ERROR_OUT_OF_MEMORY (if the message itself cannot be allocated, it is
 * the fixed text "out of memory", and a refusal may then be reported as
 * HGCD_ERROR_OUT_OF_MEMORY instead of its own status).
 *
 * Threading
 * ---------
 * One world is used by one thread at a time; calls that only read the world
 * (those taking a const hgcd_world*) may overlap with each other, but not with
 * a call that changes it. Separate worlds are fully independent and may be used
 * from different threads at once. Inside hgcd_world_step/hgcd_world_detect the
 * library runs OpenMP parallel regions with hgcd_world_desc.thread_count
 * threads (0 = all cores), set per region: the global OpenMP state of the
 * process (omp_set_num_threads and friends) is never changed. The pairs
 * reported never depend on the thread count, bit for bit and in order.
 *
 * Floating-point mode
 * -------------------
 * The caller may run in any floating-point mode: flush-to-zero and
 * denormals-are-zero (what -ffast-math's start-up code sets), another
 * rounding direction, exceptions unmasked. Every call, and every parallel
 * region on every thread, works in IEEE's default mode (subnormals kept,
 * round to nearest, no traps: MXCSR on x86-64, FPCR on arm64) and restores
 * the thread's own mode before it returns, so answers are the same in any
 * mode. (Calls that only copy values out need no arithmetic and do not
 * switch.)
 *
 * World-space vertices
 * --------------------
 * For a body at position c with orientation quaternion (x, y, z, w), the
 * rotation matrix is, entry by entry in double precision without fused
 * multiply-add,
 *     R = [1-2(yy+zz)  2(xy-zw)    2(xz+yw)  ]
 *         [2(xy+zw)    1-2(xx+zz)  2(yz-xw)  ]
 *         [2(xz-yw)    2(yz+xw)    1-2(xx+yy)]
 * and world component a of mesh vertex m is c_a + ((R_a0*v0 + R_a1*v1) + R_a2*v2)
 * with v = scale * m (see hgcd_body_desc.scale).
 * Any other implementation of that formula gets the same bits, so results are
 * reproducible outside hgcd. The collision test is exact on these rounded
 * vertices. Far from the origin their spacing is coarse (0.125 near 1e15,
 * 1.2e-7 near 1e9): a body much smaller than that has vertices that coincide
 * or line up, and it then collides as the segments and points they form.
 */
#ifndef HGCD_H
#define HGCD_H

#include <stddef.h>
#include <stdint.h>

#include "hgcd_export.h"
#include "hgcd_version.h"

#ifdef __cplusplus
extern "C" {
#endif

/* ------------------------------------------------------------------------ */
/* Status codes                                                              */
/* ------------------------------------------------------------------------ */

/** Result of every fallible call: HGCD_OK or one of the negative codes. */
typedef int32_t hgcd_status;

enum hgcd_status_code {
    HGCD_OK = 0,
    /** A required pointer argument was NULL. */
    HGCD_ERROR_NULL_ARGUMENT = -1,
    /** A value is out of its documented range: NaN, infinite, negative where
     *  it must not be, a quaternion that is not unit length, ... */
    HGCD_ERROR_INVALID_ARGUMENT = -2,
    /** A descriptor was not initialised by its hgcd_*_desc_default() function
     *  (wrong struct_size or init tag). */
    HGCD_ERROR_BAD_DESCRIPTOR = -3,
    /** A mesh or body id is null, stale (destroyed), forged or of another world. */
    HGCD_ERROR_STALE_ID = -4,
    /** Mesh data rejected: no triangles, index out of range, non-finite vertex,
     *  too large. */
    HGCD_ERROR_INVALID_MESH = -5,
    /** hgcd_mesh_destroy on a mesh that live bodies still use. */
    HGCD_ERROR_MESH_IN_USE = -6,
    /** An allocation failed; the world is unchanged. */
    HGCD_ERROR_OUT_OF_MEMORY = -7,
    /** A count limit was reached (more than 2^31 - 2 bodies or meshes, a size
     *  that would overflow). */
    HGCD_ERROR_CAPACITY = -8,
    /** The feature was not compiled into this build of the library. */
    HGCD_ERROR_NOT_SUPPORTED = -9,
    /** A bug in hgcd: please report it with the message. */
    HGCD_ERROR_INTERNAL = -10
};

/** Static name of a status code ("HGCD_ERROR_STALE_ID"); never NULL. Unknown
 *  codes give "HGCD_ERROR_UNKNOWN". */
HGCD_API const char *hgcd_status_string(hgcd_status status);

/* ------------------------------------------------------------------------ */
/* Version                                                                   */
/* ------------------------------------------------------------------------ */

/** The run-time version as (major << 16) | (minor << 8) | patch. */
HGCD_API uint32_t hgcd_version(void);
/** The run-time version as a static string, "0.1.0". */
HGCD_API const char *hgcd_version_string(void);

/* ------------------------------------------------------------------------ */
/* Handles and ids                                                           */
/* ------------------------------------------------------------------------ */

/** Opaque world: owns meshes, bodies and the tick's results. */
typedef struct hgcd_world hgcd_world;

/** A mesh (shared shape) of one world. The all-zero id is the null id. */
typedef struct hgcd_mesh {
    uint32_t index;
    uint32_t generation;
} hgcd_mesh;

/** A body (placed instance of a mesh) of one world. All-zero is null. */
typedef struct hgcd_body {
    uint32_t index;
    uint32_t generation;
} hgcd_body;

/** One colliding pair: a.index < b.index. */
typedef struct hgcd_pair {
    hgcd_body a;
    hgcd_body b;
} hgcd_pair;

/* ------------------------------------------------------------------------ */
/* World                                                                     */
/* ------------------------------------------------------------------------ */

/** Which test decides a candidate pair (hgcd_world_desc.narrow_phase,
 *  hgcd_world_set_narrow_phase, hgcd_mesh_set_narrow_phase).
 *
 *  HGCD_NARROW_EXACT is the exact definition of a collision given at the top
 *  of this header. HGCD_NARROW_GJK and HGCD_NARROW_MPR hand a pair to libccd
 *  instead (GJK, or Minkowski portal refinement), on the convex hulls of the
 *  two bodies' world-space vertices (the same bits the exact test uses), when
 *  both meshes are convex (hgcd_mesh_info.convex) and both are set to GJK or
 *  MPR (one GJK and the other MPR: GJK). Every other pair, in particular
 *  every pair with a non-convex mesh, takes the exact test.
 *
 *  libccd is not exact: a pair whose solids only touch, or overlap or are
 *  apart by less than its tolerance, may be reported either way. The
 *  tolerance, libccd's mpr_tolerance and epa_tolerance, is set per pair to
 *  1e-6 * (r_a + r_b) with libccd in double precision (1e-4 * (r_a + r_b) in
 *  single precision), r being a body's bounding radius (scale *
 *  hgcd_mesh_info.radius). GJK's yes/no answer uses no tolerance, only
 *  libccd's fixed rounding thresholds; MPR may miss an overlap shallower than
 *  the tolerance. libccd's iterations are capped at 1000 per call. Pairs
 *  whose exact vertex boxes are disjoint are refused before libccd. */
enum hgcd_narrow_phase {
    /** Per mesh only: follow the world's setting (every mesh starts so). */
    HGCD_NARROW_WORLD = -1,
    /** The exact test (the default). */
    HGCD_NARROW_EXACT = 0,
    /** libccd's GJK (ccdGJKIntersect; ccdGJKPenetration, i.e. EPA, for
     *  contacts). */
    HGCD_NARROW_GJK = 1,
    /** libccd's Minkowski portal refinement (ccdMPRIntersect;
     *  ccdMPRPenetration for contacts). */
    HGCD_NARROW_MPR = 2
};

/** Precision of the libccd compiled in, read from libccd's own config.h at
 *  build time (CCD_SINGLE: ccd_real_t is float; CCD_DOUBLE: double). */
enum hgcd_libccd_precision {
    /** Built without libccd. */
    HGCD_LIBCCD_NONE = 0,
    /** libccd with ccd_real_t = float. */
    HGCD_LIBCCD_SINGLE = 1,
    /** libccd with ccd_real_t = double (Debian's libccd-dev). */
    HGCD_LIBCCD_DOUBLE = 2
};

/** Whether this build can use libccd: HGCD_LIBCCD_NONE (0: built without it;
 *  every request for GJK or MPR fails with HGCD_ERROR_NOT_SUPPORTED, message
 *  "not built with libccd"), HGCD_LIBCCD_SINGLE (1) or HGCD_LIBCCD_DOUBLE
 *  (2). In double precision libccd reads the world vertices bit for bit; in
 *  single precision it gets them minus a point of the pair (the centre of
 *  body a's vertex box), rounded to float. */
HGCD_API int32_t hgcd_feature_libccd(void);

/** World descriptor. Obtain one from hgcd_world_desc_default(), then change
 *  fields. */
typedef struct hgcd_world_desc {
    /** sizeof(hgcd_world_desc), set by hgcd_world_desc_default(). */
    uint32_t struct_size;
    /** Set by hgcd_world_desc_default(); catches uninitialised descriptors. */
    uint32_t init_tag;
    /** OpenMP threads per parallel region; 0 (default) = all cores.
     *  At most 4096 (more is INVALID_ARGUMENT). */
    uint32_t thread_count;
    /** Non-zero: hgcd_world_step reflects bodies at the bounds box, as the
     *  reference scenes do (a coordinate that leaves [min, max] is mirrored
     *  back inside and that velocity component changes sign). Default 0. */
    uint32_t reflect_at_bounds;
    /** Time step of hgcd_world_step: position += velocity * time_step.
     *  Finite and >= 0; default 1. */
    double time_step;
    /** Bounds used when reflect_at_bounds is set: min[3] then max[3].
     *  Finite, min < max. Default 0..1 on each axis. */
    double bounds_min[3];
    double bounds_max[3];
    /** Broad-phase grid override. The broad phase compares each body's
     *  axis-aligned box (see hgcd_stats.candidate_pairs) in a hierarchical
     *  grid keyed by the bodies' positions. Cell widths are powers of two; a
     *  body lives on the level whose width is the smallest power of two >=
     *  twice the farthest its vertices reach from its position in any
     *  orientation (scale x (distance of the mesh's bounding-sphere centre
     *  from the mesh origin + that sphere's radius)), except where bodies are
     *  sparse (the previous detect found fewer than 3 candidate pairs per
     *  body): then the levels at most a factor 4 finer than the coarsest
     *  populated level join it (fewer levels, same pairs). min_cell_size > 0 raises the finest width to the
     *  power of two >= min_cell_size (bodies smaller than that share it).
     *  max_cell_size > 0 caps the coarsest width at the largest power of two
     *  <= max_cell_size: bodies larger than that are kept in a separate
     *  oversize set, still exactly handled, each compared with the others
     *  through a range query, never all-pairs. 0 (default) = adapt to the
     *  bodies. Both finite and >= 0; if both are set, min <= max. */
    double min_cell_size;
    double max_cell_size;
    /** Narrow phase of the world's pairs (enum hgcd_narrow_phase): EXACT (0,
     *  default), GJK or MPR. Meshes follow it unless set otherwise with
     *  hgcd_mesh_set_narrow_phase; non-convex meshes always fall back to the
     *  exact test (hgcd_mesh_info.narrow_phase says which test a mesh gets,
     *  hgcd_stats.libccd_fallback_tests counts such pairs). GJK or MPR
     *  without libccd: NOT_SUPPORTED; other values: INVALID_ARGUMENT. */
    int32_t narrow_phase;
    /** Non-zero: step/detect also record what each colliding pair is made of
     *  (hgcd_world_contacts). Default 0: nothing is recorded and the pair
     *  query pays nothing for it. See hgcd_world_set_contacts. */
    uint32_t contacts;
} hgcd_world_desc;

/** A descriptor with every default filled in. */
HGCD_API hgcd_world_desc hgcd_world_desc_default(void);

/** Creates a world. On success *out_world owns the new world (free it with
 *  hgcd_world_destroy). On failure *out_world is set to NULL.
 *  Errors: NULL_ARGUMENT, BAD_DESCRIPTOR, INVALID_ARGUMENT, OUT_OF_MEMORY,
 *  NOT_SUPPORTED (narrow_phase GJK or MPR without libccd). */
HGCD_API hgcd_status hgcd_world_create(const hgcd_world_desc *desc,
                                       hgcd_world **out_world);

/** Frees the world and everything in it; every pointer it returned becomes
 *  invalid. NULL is a no-op. */
HGCD_API void hgcd_world_destroy(hgcd_world *world);

/** Detail of the last failed call (of those taking a non-const world) on this
 *  world, or "" if none failed yet: the call and what was wrong, naming the
 *  field, index or id. The string is owned by the world and valid until the
 *  next non-const call on it. NULL world gives a static message. */
HGCD_API const char *hgcd_world_last_error(const hgcd_world *world);

/** Number of live bodies and meshes. NULL world gives 0. */
HGCD_API uint32_t hgcd_world_body_count(const hgcd_world *world);
HGCD_API uint32_t hgcd_world_mesh_count(const hgcd_world *world);

/** Sets the number of OpenMP threads per parallel region (0 = all cores).
 *  Errors: NULL_ARGUMENT, INVALID_ARGUMENT (more than 4096). */
HGCD_API hgcd_status hgcd_world_set_thread_count(hgcd_world *world,
                                                 uint32_t thread_count);

/** Sets the world's narrow phase (enum hgcd_narrow_phase,
 *  hgcd_world_desc.narrow_phase), used from the next step/detect.
 *  Errors: NULL_ARGUMENT, INVALID_ARGUMENT (not EXACT, GJK or MPR),
 *  NOT_SUPPORTED (GJK or MPR without libccd: "not built with libccd"). */
HGCD_API hgcd_status hgcd_world_set_narrow_phase(hgcd_world *world,
                                                 int32_t narrow_phase);

/** Switches contact recording on (non-zero) or off for the following
 *  step/detect calls (hgcd_world_desc.contacts). Errors: NULL_ARGUMENT. */
HGCD_API hgcd_status hgcd_world_set_contacts(hgcd_world *world,
                                             uint32_t enable);

/** Moves every body by velocity * time_step (reflecting at the bounds when
 *  the descriptor asked for it; a move longer than the box is clamped into
 *  it), then detects as hgcd_world_detect does. Without reflection, if a move
 *  would take a coordinate beyond 1e15 in magnitude (or make it non-finite),
 *  nothing moves and INVALID_ARGUMENT is returned naming the body.
 *  Errors: NULL_ARGUMENT, INVALID_ARGUMENT, OUT_OF_MEMORY (the motion, which
 *  needs no memory, has then been applied and the detection failed as for
 *  hgcd_world_detect: pairs cleared, statistics zeroed; calling
 *  hgcd_world_detect finishes the tick). */
HGCD_API hgcd_status hgcd_world_step(hgcd_world *world);

/** Detects the colliding pairs at the current poses without moving anything.
 *  The result replaces the previous tick's pairs and statistics.
 *  Errors: NULL_ARGUMENT, OUT_OF_MEMORY (the previous pairs are then
 *  cleared and the statistics zeroed). */
HGCD_API hgcd_status hgcd_world_detect(hgcd_world *world);

/** The pairs of the last step/detect: *out_pairs points to *out_count pairs
 *  owned by the world, sorted by (a.index, b.index), no duplicates, and
 *  a.index < b.index. Valid until the next call that changes the world
 *  (step, detect, create/destroy of a body or mesh, set_pose, set_velocity,
 *  destroy). Before the first detect the count is 0 (and *out_pairs may be
 *  NULL). Pairs of bodies destroyed since the detect are still listed (with
 *  their now-stale ids) until the next detect.
 *  Errors: NULL_ARGUMENT. */
HGCD_API hgcd_status hgcd_world_pairs(const hgcd_world *world,
                                      const hgcd_pair **out_pairs,
                                      size_t *out_count);

/** Copies up to capacity pairs of the last tick into buffer (which may be
 *  NULL when capacity is 0) and sets *out_total to the full count, so a
 *  caller can size its buffer with a first call. Same order as
 *  hgcd_world_pairs.
 *  Errors: NULL_ARGUMENT (world or out_total NULL, or buffer NULL with
 *  capacity > 0). */
HGCD_API hgcd_status hgcd_world_copy_pairs(const hgcd_world *world,
                                           hgcd_pair *buffer, size_t capacity,
                                           size_t *out_total);

/** What a colliding pair is made of (hgcd_contact.kind). */
enum hgcd_contact_kind {
    /** The surfaces meet (exact test): triangle triangle_a of body a's mesh
     *  and triangle triangle_b of body b's mesh share a point. One such
     *  witness pair, not all of them. */
    HGCD_CONTACT_SURFACE = 1,
    /** The surfaces are apart and a's closed mesh holds b: a connected
     *  component of b's mesh (all of b when it has one) lies inside a. */
    HGCD_CONTACT_A_CONTAINS_B = 2,
    /** The same with the roles swapped (when each holds a component of the
     *  other, this kind is reported). */
    HGCD_CONTACT_B_CONTAINS_A = 3,
    /** Decided by libccd (a GJK or MPR pair, enum hgcd_narrow_phase): depth,
     *  normal and point are libccd's penetration estimate (EPA after GJK, or
     *  MPR's own). */
    HGCD_CONTACT_PENETRATION = 4
};

/** One colliding pair and what it is made of. */
typedef struct hgcd_contact {
    /** The pair, equal to the pair of the same index in hgcd_world_pairs. */
    hgcd_pair pair;
    /** enum hgcd_contact_kind. */
    int32_t kind;
    /** SURFACE: a triangle index (as given to hgcd_mesh_create) in a's mesh
     *  and one in b's mesh; UINT32_MAX for the other kinds. */
    uint32_t triangle_a;
    uint32_t triangle_b;
    /** Always 0. */
    uint32_t reserved;
    /** PENETRATION: translating body b by depth along normal (a unit
     *  vector) brings the two convex hulls to touching, within libccd's
     *  tolerance (EPA gives the smallest such translation; MPR one along
     *  its own direction, close to the line between the bodies' centres).
     *  point is libccd's contact position in world space: an average of
     *  support points near the contact, not guaranteed to lie in both
     *  bodies. normal is all zero when libccd gave no direction (bodies that
     *  only touch). All zero for the other kinds. */
    double depth;
    double normal[3];
    double point[3];
} hgcd_contact;

/** The contacts of the last step/detect, parallel to hgcd_world_pairs:
 *  *out_contacts points to *out_count contacts owned by the world (as many as
 *  there are pairs), contact k describing pair k; same lifetime as the pairs.
 *  Recorded only when contacts were on (hgcd_world_desc.contacts,
 *  hgcd_world_set_contacts) during that step/detect; switching them on or
 *  off never changes the pairs. Before the first detect the count is 0.
 *  Errors: NULL_ARGUMENT; INVALID_ARGUMENT when the last step/detect ran with
 *  contacts off (then *out_contacts is NULL and *out_count 0). */
HGCD_API hgcd_status hgcd_world_contacts(const hgcd_world *world,
                                         const hgcd_contact **out_contacts,
                                         size_t *out_count);

/** Statistics of the last step/detect. */
typedef struct hgcd_stats {
    /** sizeof(hgcd_stats): set it before calling hgcd_world_stats (the
     *  library fills min(struct_size, its own size) bytes). */
    uint32_t struct_size;
    /** Number of grid levels in use and bodies in the oversize set. */
    uint32_t level_count;
    uint32_t oversize_count;
    uint32_t thread_count;
    /** Bodies that changed grid cell in the last update. */
    uint64_t moved_bodies;
    /** Pairs whose axis-aligned boxes overlap (broad-phase output; closed
     *  intervals, so touching boxes count). A body's box holds its solid:
     *  for meshes of at most 128 triangles it is the box of the world
     *  vertices themselves (their offsets from the position, computed when
     *  the orientation is set, rounded outward to float, plus the position),
     *  for larger meshes the box of the mesh's bounding sphere. The grid
     *  compares these boxes with each bound rounded outward to float (the
     *  absolute position, so a box at coordinate x grows by up to about
     *  |x| 2^-23 a side), so this may also count pairs that overlap only
     *  once rounded (13 of 844,304 on scene tetra at n = 750000; many more
     *  where bodies are smaller than about |x| 2^-20, e.g. under 1 unit at
     *  |x| = 1e6: keep the origin near the bodies). The pairs reported are
     *  unaffected: every candidate gets the exact test. */
    uint64_t candidate_pairs;
    /** Candidate pairs that reached the exact test (not rejected by the
     *  exact prefilters: vertex boxes, and for two tetrahedra also a
     *  separating axis along the line between their positions). */
    uint64_t narrow_tests;
    /** Triangle-triangle tests performed. */
    uint64_t triangle_tests;
    /** Colliding pairs, and those of them found by containment alone. */
    uint64_t colliding_pairs;
    uint64_t containment_pairs;
    /** Wall-clock seconds: what step does before the grid update (checking
     *  the moves when the world does not reflect, and now and then
     *  reordering the bodies' storage to follow the grid, which a detect
     *  called alone counts in the update; step only), updating the grid
     *  (for step, with the moves themselves: the update's pass over the
     *  bodies moves each range of them just before it reads them), broad
     *  phase, narrow phase (with sorting of the output), total. */
    double motion_seconds;
    double update_seconds;
    double broad_seconds;
    double narrow_seconds;
    double total_seconds;
    /** Candidate pairs decided by libccd (both meshes convex and set to GJK
     *  or MPR, exact vertex boxes overlapping); not counted in narrow_tests,
     *  and their pairs never count in containment_pairs. */
    uint64_t libccd_tests;
    /** Candidate pairs whose meshes were both set to GJK or MPR but one of
     *  them is not convex: tested exactly instead. */
    uint64_t libccd_fallback_tests;
} hgcd_stats;

/** Fills *out_stats (whose struct_size the caller sets; 0 is taken as
 *  sizeof(hgcd_stats)). Errors: NULL_ARGUMENT, BAD_DESCRIPTOR (struct_size
 *  smaller than 8). */
HGCD_API hgcd_status hgcd_world_stats(const hgcd_world *world,
                                      hgcd_stats *out_stats);

/* ------------------------------------------------------------------------ */
/* Meshes                                                                    */
/* ------------------------------------------------------------------------ */

/** Mesh descriptor. Obtain one from hgcd_mesh_desc_default(). */
typedef struct hgcd_mesh_desc {
    uint32_t struct_size;
    uint32_t init_tag;
    /** vertex_count * 3 doubles (x, y, z per vertex), in the mesh's frame.
     *  Copied in; the caller may free it when hgcd_mesh_create returns. */
    const double *vertices;
    /** triangle_count * 3 vertex indices, each < vertex_count. Copied in. */
    const uint32_t *triangles;
    uint32_t vertex_count;
    uint32_t triangle_count;
} hgcd_mesh_desc;

HGCD_API hgcd_mesh_desc hgcd_mesh_desc_default(void);

/** Registers a mesh. Vertices must be finite and within 1e15 of the
 *  origin; 1 <= triangle_count <= 2^26 and vertex_count <= 2^26. Triangles may
 *  be degenerate (zero area: they then count as the segment or point they
 *  are) and may repeat vertices. The library works out whether the mesh is
 *  closed (every edge shared by an even number of triangles, so it bounds a
 *  volume) and whether it is convex; see hgcd_mesh_info. The sizes are
 *  checked before the arrays are read. Creation takes O(n log n) time in the
 *  mesh size (about a second for two million triangles).
 *  Errors: NULL_ARGUMENT, BAD_DESCRIPTOR, INVALID_MESH, CAPACITY,
 *  OUT_OF_MEMORY. */
HGCD_API hgcd_status hgcd_mesh_create(hgcd_world *world,
                                      const hgcd_mesh_desc *desc,
                                      hgcd_mesh *out_mesh);

/** Removes a mesh no body uses any more; its id becomes stale.
 *  Errors: NULL_ARGUMENT, STALE_ID, MESH_IN_USE. */
HGCD_API hgcd_status hgcd_mesh_destroy(hgcd_world *world, hgcd_mesh mesh);

/** What hgcd worked out about a mesh. */
typedef struct hgcd_mesh_info {
    uint32_t struct_size;
    uint32_t vertex_count;
    uint32_t triangle_count;
    /** 1 if every edge is shared by an even number of triangles. */
    uint32_t closed;
    /** 1 if closed and every vertex lies on or behind every face plane. The
     *  test costs triangles x vertices exact orientation tests; beyond 5e7
     *  of them it is skipped and the mesh reported not convex (still handled
     *  exactly, without the convex shortcuts). */
    uint32_t convex;
    /** Connected components (via shared vertices). */
    uint32_t component_count;
    /** Zero-area triangles. */
    uint32_t degenerate_triangle_count;
    /** Bodies using this mesh. */
    uint32_t body_count;
    /** Bounding sphere in the mesh frame (centre of the vertex box, radius
     *  reaching every vertex). */
    double center[3];
    double radius;
    /** The narrow phase set for this mesh: HGCD_NARROW_WORLD (default) or
     *  the value given to hgcd_mesh_set_narrow_phase. */
    int32_t narrow_phase_setting;
    /** The test this mesh's pairs get now (enum hgcd_narrow_phase, never
     *  WORLD): the setting or else the world's, and HGCD_NARROW_EXACT for a
     *  mesh that is not convex. A pair uses libccd only when both of its
     *  meshes say GJK or MPR. */
    int32_t narrow_phase;
} hgcd_mesh_info;

/** Fills *out_info (the caller sets struct_size; 0 is taken as the full size).
 *  Errors: NULL_ARGUMENT, STALE_ID, BAD_DESCRIPTOR. */
HGCD_API hgcd_status hgcd_mesh_get_info(const hgcd_world *world,
                                        hgcd_mesh mesh,
                                        hgcd_mesh_info *out_info);

/** Chooses the narrow phase of this mesh's pairs (enum hgcd_narrow_phase):
 *  HGCD_NARROW_WORLD (the default: follow the world), EXACT, GJK or MPR,
 *  used from the next step/detect. A pair uses libccd only when both of its
 *  meshes are convex and say GJK or MPR.
 *  Errors: NULL_ARGUMENT, STALE_ID, INVALID_ARGUMENT (an unknown value, or
 *  GJK or MPR for a mesh that is not convex: libccd handles convex shapes
 *  only, so the mesh keeps its setting and the exact test), NOT_SUPPORTED
 *  (GJK or MPR without libccd: "not built with libccd"). */
HGCD_API hgcd_status hgcd_mesh_set_narrow_phase(hgcd_world *world,
                                                hgcd_mesh mesh,
                                                int32_t narrow_phase);

/* ------------------------------------------------------------------------ */
/* Bodies                                                                    */
/* ------------------------------------------------------------------------ */

/** Body descriptor. Obtain one from hgcd_body_desc_default(). */
typedef struct hgcd_body_desc {
    uint32_t struct_size;
    uint32_t init_tag;
    /** The shape; must be a live mesh of this world. Default: null (refused). */
    hgcd_mesh mesh;
    /** Position of the mesh frame's origin. Finite, |x| <= 1e15. Default 0. */
    double position[3];
    /** Orientation quaternion (x, y, z, w). Finite and of unit length within
     *  1e-6 (| x^2+y^2+z^2+w^2 - 1 | <= 1e-6); it is used exactly as given,
     *  not normalised, so results are reproducible bit for bit. Default
     *  (0, 0, 0, 1). */
    double orientation[4];
    /** Velocity used by hgcd_world_step. Finite. Default 0. */
    double velocity[3];
    /** Uniform scale of the mesh: local vertex = scale * v, component by
     *  component, before the rotation. Finite, > 0 and such that the scaled
     *  mesh stays within 1e15 of its origin. Default 1. Lets one mesh serve
     *  bodies of many sizes (the tetra scene uses scale = r / sqrt(3) on the
     *  unit sign-pattern tetrahedron, which gives its vertices bit for bit). */
    double scale;
    /** Opaque caller value, returned by hgcd_body_get_user_data. */
    uint64_t user_data;
} hgcd_body_desc;

HGCD_API hgcd_body_desc hgcd_body_desc_default(void);

/** Places a body. Errors: NULL_ARGUMENT, BAD_DESCRIPTOR, STALE_ID (mesh),
 *  INVALID_ARGUMENT, CAPACITY, OUT_OF_MEMORY. */
HGCD_API hgcd_status hgcd_body_create(hgcd_world *world,
                                      const hgcd_body_desc *desc,
                                      hgcd_body *out_body);

/** Removes a body; its id becomes stale. Errors: NULL_ARGUMENT, STALE_ID. */
HGCD_API hgcd_status hgcd_body_destroy(hgcd_world *world, hgcd_body body);

/** Sets position[3] and orientation[4] (x, y, z, w), same rules as the
 *  descriptor. Either pointer may be NULL to keep the current value.
 *  Errors: NULL_ARGUMENT (world), STALE_ID, INVALID_ARGUMENT. */
HGCD_API hgcd_status hgcd_body_set_pose(hgcd_world *world, hgcd_body body,
                                        const double *position,
                                        const double *orientation);

/** Sets velocity[3]. Errors: NULL_ARGUMENT, STALE_ID, INVALID_ARGUMENT. */
HGCD_API hgcd_status hgcd_body_set_velocity(hgcd_world *world, hgcd_body body,
                                            const double *velocity);

/** Reads position[3] and orientation[4]; either may be NULL to skip it.
 *  Errors: NULL_ARGUMENT (world), STALE_ID. */
HGCD_API hgcd_status hgcd_body_get_pose(const hgcd_world *world,
                                        hgcd_body body, double *position,
                                        double *orientation);

/** Reads velocity[3]. Errors: NULL_ARGUMENT, STALE_ID. */
HGCD_API hgcd_status hgcd_body_get_velocity(const hgcd_world *world,
                                            hgcd_body body, double *velocity);

/** Reads the mesh and user data given at creation. Errors: NULL_ARGUMENT,
 *  STALE_ID. */
HGCD_API hgcd_status hgcd_body_get_mesh(const hgcd_world *world,
                                        hgcd_body body, hgcd_mesh *out_mesh);
HGCD_API hgcd_status hgcd_body_get_user_data(const hgcd_world *world,
                                             hgcd_body body,
                                             uint64_t *out_user_data);

/** HGCD_OK if body is a live body of this world, else STALE_ID (or
 *  NULL_ARGUMENT). Does not record an error message. */
HGCD_API hgcd_status hgcd_body_validate(const hgcd_world *world,
                                        hgcd_body body);

#ifdef __cplusplus
}
#endif

#endif /* HGCD_H */
