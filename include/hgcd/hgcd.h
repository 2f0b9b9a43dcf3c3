/*
 * hgcd: exact, parallel collision detection between many rigid triangle
 * meshes. This header is the whole C contract, kept in one file (over 600
 * lines) so that it reads in one place; it is strict C99 and defines no API
 * macros (the version macros are in hgcd_version.h).
 *
 * The loop
 * --------
 *   hgcd_world_create       a world (hgcd_world_desc_default, then edit fields)
 *   hgcd_mesh_create        each shape: vertices and triangles, copied in
 *   hgcd_body_create        each placed instance of a mesh
 *   every tick:
 *     hgcd_world_set_poses  move the bodies (all at once; hgcd_body_set_pose
 *                           for one; or set velocities and call
 *                           hgcd_world_step, which moves them and detects)
 *     hgcd_world_detect     find the colliding pairs
 *     hgcd_world_pairs      read them: each pair of bodies whose closed solids
 *                           share a point (touching and containment count)
 *   hgcd_world_destroy
 *
 * docs/semantics.md defines what counts as a collision, why the answer is
 * exact, the world-space transform bit for bit, the coordinate limits, the
 * determinism across thread counts and the threading model. This header
 * states what each call does, takes, refuses and returns.
 *
 * Conventions (for every function unless its comment says otherwise)
 * -----------
 * Status: every fallible call returns an hgcd_status, HGCD_OK (0) or a
 *   negative hgcd_status_code. When several things are wrong, the first of
 *   these is reported: a NULL pointer, a descriptor not from its
 *   *_desc_default(), a stale id, a bad value. A refused call leaves the
 *   world exactly as it was (except the recorded message); the only
 *   exception is HGCD_ERROR_OUT_OF_MEMORY from hgcd_world_step and
 *   hgcd_world_detect, described there. No call aborts, throws or crashes on
 *   bad arguments.
 * Messages: a refused call taking a non-const hgcd_world* records a message
 *   naming the call and what was wrong (hgcd_world_last_error). Calls taking
 *   a const hgcd_world* record nothing. If the message itself cannot be
 *   allocated it is "out of memory", and the status may then be
 *   HGCD_ERROR_OUT_OF_MEMORY instead of the refusal's own.
 * Ids: meshes and bodies are value ids {index, generation}; all-zero is the
 *   null id, never given to a live object. Destroying an object makes its id
 *   stale for good, also after its index is reused. An id of another world
 *   is refused as stale: always between any 256 worlds created one after
 *   another, otherwise with probability 255/256 (docs/semantics.md, "Ids").
 * Threads: one world is used by one thread at a time, except that calls
 *   taking a const hgcd_world* ("read-only" below) may overlap with each
 *   other. Different worlds are independent. Functions without a world
 *   argument may be called from any thread at any time. Inside a call the
 *   world runs its parallel loops on OpenMP threads (thread_count,
 *   thread_policy) or, if its descriptor names one, on the caller's task
 *   system (enqueue_task); the results are the same bits either way.
 * Floating point: callers may run in any floating-point mode; every call
 *   computes in IEEE's default mode and restores the caller's.
 * Memory: the library owns everything it returns a pointer to; the caller
 *   frees nothing but the world itself (hgcd_world_destroy). Input arrays
 *   are read during the call only (meshes are copied in).
 *
 * Coordinate limits (checked exactly as stated; a value past one is refused
 * with HGCD_ERROR_INVALID_ARGUMENT, or INVALID_MESH for vertices)
 * -----------------
 * Vertex: finite, and its norm sqrt((x*x + y*y) + z*z), evaluated in IEEE
 *   double as written, is <= 1e15.
 * Position: each component finite and |x| <= 1e15; also where
 *   hgcd_world_step would move a body (without reflection).
 * Scale: finite, > 0, and scale * reach <= 1e15 (the product in double), where
 *   reach is the largest vertex norm over the vertices the mesh's triangles
 *   use (hgcd_mesh_info.reach).
 * Reflection bounds: read only when reflect_at_bounds is set; then each
 *   component finite, |x| <= 1e15, and bounds_min < bounds_max per axis.
 * So every world-space vertex component stays within about 2e15.
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

/** Result of every fallible call: HGCD_OK or one of the negative codes of
 *  enum hgcd_status_code. */
typedef int32_t hgcd_status;

enum hgcd_status_code {
    /** Success. */
    HGCD_OK = 0,
    /** A required pointer argument was NULL. */
    HGCD_ERROR_NULL_ARGUMENT = -1,
    /** A value is out of its documented range: NaN, infinite, negative where
     *  it must not be, a quaternion that is not unit length, an unknown enum
     *  value, ... */
    HGCD_ERROR_INVALID_ARGUMENT = -2,
    /** A descriptor was not initialised by its hgcd_*_desc_default() function
     *  (wrong struct_size or init_tag), or an output struct_size is too
     *  small. */
    HGCD_ERROR_BAD_DESCRIPTOR = -3,
    /** A mesh or body id is null, stale (destroyed), forged or of another
     *  world. */
    HGCD_ERROR_STALE_ID = -4,
    /** Mesh data rejected: no triangles, an index out of range, a vertex not
     *  finite or farther than 1e15 from the mesh origin ("Coordinate
     *  limits" above), more than 2^26 vertices or triangles. */
    HGCD_ERROR_INVALID_MESH = -5,
    /** hgcd_mesh_destroy on a mesh that live bodies still use. */
    HGCD_ERROR_MESH_IN_USE = -6,
    /** An allocation failed; the world is unchanged (but see
     *  hgcd_world_detect). */
    HGCD_ERROR_OUT_OF_MEMORY = -7,
    /** A count limit was reached: more than 2^31 - 2 live bodies or meshes. */
    HGCD_ERROR_CAPACITY = -8,
    /** The feature was not compiled into this build (GJK or MPR without
     *  libccd). */
    HGCD_ERROR_NOT_SUPPORTED = -9,
    /** A bug in hgcd: please report it with the message. */
    HGCD_ERROR_INTERNAL = -10
};

/** Name of a status code, e.g. "HGCD_ERROR_STALE_ID"; "HGCD_ERROR_UNKNOWN"
 *  for a value that is not a code. Never NULL.
 *  Returns a static string (do not free). Any thread. */
HGCD_API const char *hgcd_status_string(hgcd_status status);

/* ------------------------------------------------------------------------ */
/* Version                                                                   */
/* ------------------------------------------------------------------------ */

/** Version of the linked library as (major << 16) | (minor << 8) | patch;
 *  compare with HGCD_VERSION_* of hgcd_version.h to detect a mismatched
 *  header. Any thread. */
HGCD_API uint32_t hgcd_version(void);

/** Version of the linked library as "major.minor.patch", e.g. "0.1.0".
 *  Returns a static string (do not free). Any thread. */
HGCD_API const char *hgcd_version_string(void);

/* ------------------------------------------------------------------------ */
/* Handles and ids                                                           */
/* ------------------------------------------------------------------------ */

/** Opaque world: owns its meshes, bodies and the last tick's results.
 *  Created by hgcd_world_create, freed by hgcd_world_destroy. */
typedef struct hgcd_world hgcd_world;

/** Id of a mesh (a shared shape) of one world. A value: copy and compare it
 *  freely (equal ids have equal index and generation). */
typedef struct hgcd_mesh {
    /** Slot of the mesh in its world; reused after the mesh is destroyed. */
    uint32_t index;
    /** Distinguishes successive meshes of one slot and worlds; never 0 in a
     *  live id. {0, 0} is the null id. */
    uint32_t generation;
} hgcd_mesh;

/** Id of a body (a placed instance of a mesh) of one world. A value, like
 *  hgcd_mesh. On a fresh world bodies get indices 0, 1, 2, ... in creation
 *  order, so pairs map straight back to the caller's arrays; a destroyed
 *  body's index is given to a later hgcd_body_create. */
typedef struct hgcd_body {
    /** Slot of the body in its world. */
    uint32_t index;
    /** As hgcd_mesh.generation; {0, 0} is the null id. */
    uint32_t generation;
} hgcd_body;

/** One colliding pair of bodies. */
typedef struct hgcd_pair {
    /** The body of smaller index (a.index < b.index). */
    hgcd_body a;
    /** The body of larger index. */
    hgcd_body b;
} hgcd_pair;

/* ------------------------------------------------------------------------ */
/* World                                                                     */
/* ------------------------------------------------------------------------ */

/** Which test decides a candidate pair (hgcd_world_desc.narrow_phase,
 *  hgcd_world_set_narrow_phase, hgcd_mesh_set_narrow_phase). A pair is handed
 *  to libccd only when both meshes are convex (hgcd_mesh_info.convex) and
 *  both are set to GJK or MPR (one of each: GJK); every other pair takes the
 *  exact test. libccd works with a tolerance, so pairs that touch or nearly
 *  touch may be answered either way: docs/semantics.md, "libccd". */
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

/** Precision of the libccd compiled in (hgcd_feature_libccd), read from
 *  libccd's own config.h at build time. */
enum hgcd_libccd_precision {
    /** Built without libccd. */
    HGCD_LIBCCD_NONE = 0,
    /** libccd with ccd_real_t = float (CCD_SINGLE). */
    HGCD_LIBCCD_SINGLE = 1,
    /** libccd with ccd_real_t = double (CCD_DOUBLE; Debian's libccd-dev). */
    HGCD_LIBCCD_DOUBLE = 2
};

/** How many of its threads a world's step, detect and batch calls use
 *  (hgcd_world_desc.thread_policy, hgcd_world_set_thread_policy). The pairs
 *  never depend on it. */
enum hgcd_thread_policy {
    /** The default: thread_count threads while they get the cores, fewer
     *  while they are descheduled. OpenMP threads spin while they wait (the
     *  runtime's default), so on cores shared with other busy processes a
     *  region's threads wait for a descheduled one while holding the core it
     *  needs: there, 2 threads can be several times slower than 1. Each
     *  detect measures the time its threads spend off a core (two reads of
     *  the thread's CPU clock per thread and parallel region) and its time
     *  per unit of work (bodies plus candidate pairs); when threads lost a
     *  quarter of their time, the next detect tries half as many threads
     *  and the one after it the count before again; the world keeps the
     *  fewer threads only if they did the work faster than both (one detect
     *  slowed by a passing descheduling does not move it). While on
     *  fewer threads it tries the larger count again after 8 detects, then
     *  after 16, 32, ... 512 detects while that stays slower. Batch calls
     *  (hgcd_world_set_poses ...) use the count of the last detect.
     *  hgcd_stats.thread_count reports each detect's count. */
    HGCD_THREADS_ADAPTIVE = 0,
    /** Always thread_count threads (e.g. for benchmarks, or when the caller
     *  manages the machine's load itself). */
    HGCD_THREADS_FIXED = 1
};

/** Whether this build can use libccd: an enum hgcd_libccd_precision value.
 *  With HGCD_LIBCCD_NONE every request for GJK or MPR fails with
 *  HGCD_ERROR_NOT_SUPPORTED ("not built with libccd"). Any thread. */
HGCD_API int32_t hgcd_feature_libccd(void);

/** One range of a parallel loop, for the caller's task system
 *  (hgcd_world_desc.enqueue_task): runs the loop's items [begin, end) as
 *  worker `worker`. Called with the task_context that enqueue_task received. */
typedef void hgcd_task_fn(uint32_t begin, uint32_t end, uint32_t worker, void *task_context);

/** The caller's task system, in the manner of Box2D v3's b2EnqueueTaskCallback:
 *  run task(begin, end, worker, task_context) over ranges that cover
 *  [0, item_count) exactly once, each of at least min_range items (except
 *  perhaps the last), on any threads, in any order, at once or not, where
 *  `worker` < the world's thread_count and no two ranges run at once with
 *  the same worker (hgcd keeps state per worker). Return a handle that
 *  finish_task receives, or NULL when every range has already run (e.g.
 *  inline, in this call). user_context is hgcd_world_desc.task_context. A
 *  task never waits for another task; it returns normally (hgcd catches its
 *  own errors). */
typedef void *hgcd_enqueue_task_fn(hgcd_task_fn *task, uint32_t item_count, uint32_t min_range,
                                   void *task_context, void *user_context);

/** Waits until every range of the loop enqueue_task returned `handle` for
 *  has run (Box2D v3's b2FinishTaskCallback). The calling thread may run
 *  ranges meanwhile. */
typedef void hgcd_finish_task_fn(void *handle, void *user_context);

/** World descriptor: get one from hgcd_world_desc_default(), change the
 *  fields you need, pass it to hgcd_world_create (which copies it). */
typedef struct hgcd_world_desc {
    /** sizeof(hgcd_world_desc), set by hgcd_world_desc_default(). */
    uint32_t struct_size;
    /** Set by hgcd_world_desc_default(); catches uninitialised descriptors. */
    uint32_t init_tag;
    /** OpenMP threads per parallel region of step/detect; 0 (default) = all
     *  cores (omp_get_num_procs). At most 4096. Under the default
     *  thread_policy (ADAPTIVE) a detect may use fewer while the cores are
     *  busy with other work. */
    uint32_t thread_count;
    /** Non-zero: hgcd_world_step keeps bodies inside [bounds_min,
     *  bounds_max] by reflection (docs/semantics.md, "Motion"). Default 0:
     *  bodies move freely. */
    uint32_t reflect_at_bounds;
    /** Time step of hgcd_world_step: position += velocity * time_step.
     *  Finite and >= 0; default 1. */
    double time_step;
    /** Lower corner of the reflection box, read only with
     *  reflect_at_bounds (then finite, |x| <= 1e15 and bounds_min <
     *  bounds_max on each axis: "Coordinate limits" above; otherwise any
     *  value is ignored). Default (0, 0, 0). */
    double bounds_min[3];
    /** Upper corner of the reflection box. Same rules; default (1, 1, 1). */
    double bounds_max[3];
    /** Broad-phase grid: the finest cell width is the power of two >=
     *  min_cell_size (bodies smaller than that share it). 0 (default) = adapt
     *  to the bodies. Finite and >= 0. Never changes the pairs, only speed
     *  (docs/semantics.md, "Broad phase"). */
    double min_cell_size;
    /** Broad-phase grid: the coarsest cell width is the largest power of two
     *  <= max_cell_size; larger bodies go to an oversize set, still handled
     *  exactly. 0 (default) = adapt. Finite, >= 0, and >= min_cell_size when
     *  both are non-zero. Never changes the pairs. */
    double max_cell_size;
    /** enum hgcd_narrow_phase: EXACT (0, default), GJK or MPR (WORLD is not
     *  allowed here). Meshes follow it unless set otherwise with
     *  hgcd_mesh_set_narrow_phase. */
    int32_t narrow_phase;
    /** Non-zero: step/detect also record what each colliding pair is made of
     *  (hgcd_world_contacts). Default 0: nothing is recorded and costs
     *  nothing. Never changes the pairs. */
    uint32_t contacts;
    /** enum hgcd_thread_policy: ADAPTIVE (0, default: fewer threads while
     *  the cores are busy with other work) or FIXED (always thread_count).
     *  Never changes the pairs. */
    int32_t thread_policy;
    /** The caller's task system (both set, or both NULL: the default).
     *  When set, step, detect, the batch calls and the scene queries run
     *  their parallel loops as tasks: enqueue_task, then finish_task, each loop finished before
     *  the call goes on, from the thread calling hgcd, never from another
     *  thread; no OpenMP thread is started. thread_count (at least 1) is the
     *  number of workers, and the thread policy is not used. The pairs are
     *  the same bits as with OpenMP. Parts of the work that are not loops
     *  run on the calling thread. A task system that breaks the contract of
     *  hgcd_enqueue_task_fn (a worker index >= thread_count, a range past
     *  item_count, an item run twice or never) makes the call fail with
     *  HGCD_ERROR_INTERNAL where it is seen: items run twice or at once
     *  under one worker are undefined behaviour. Default NULL. */
    hgcd_enqueue_task_fn *enqueue_task;
    hgcd_finish_task_fn *finish_task;
    /** Passed to enqueue_task and finish_task as user_context. Default NULL. */
    void *task_context;
    /** Non-zero: report pairs of two kinematic bodies and of a kinematic
     *  and a static body (enum hgcd_body_type). Default 0: such pairs are
     *  dropped before the narrow phase. Pairs of two static bodies are never
     *  reported. */
    uint32_t kinematic_pairs;
    /** Contact margin of every pair: a pair of bodies a, b is reported when
     *  their closed solids come within Euclidean distance
     *  d = contact_margin + (margin_a + margin_b) of each other (one solid
     *  grown by a ball of radius d meets the other), each addition rounded
     *  to double as written (margin_*: hgcd_body_desc.margin). Decided
     *  exactly on the world vertices, with no tolerance but d itself
     *  (docs/semantics.md, "Contact margin"). Default 0: the closed solids
     *  must share a point (today's exact touching, at its speed). Finite,
     *  >= 0 and <= 1e15. Pairs with d > 0 are decided exactly as well:
     *  touching first (tetrahedra keep their batch), then, for pairs apart,
     *  certified tests of the distance (no libccd, no convex batch). Set
     *  later with hgcd_world_set_contact_margin. */
    double contact_margin;
} hgcd_world_desc;

/** A world descriptor with every default filled in (see the fields).
 *  Any thread. */
HGCD_API hgcd_world_desc hgcd_world_desc_default(void);

/** Creates an empty world configured by *desc (copied; desc may be freed on
 *  return). On success *out_world is a new world the caller owns and must
 *  free with hgcd_world_destroy; on failure *out_world is set to NULL (if
 *  out_world itself is not NULL). No message is recorded (there is no world).
 *  Errors: NULL_ARGUMENT (desc or out_world), BAD_DESCRIPTOR,
 *  INVALID_ARGUMENT (a field out of range), NOT_SUPPORTED (narrow_phase GJK
 *  or MPR without libccd), OUT_OF_MEMORY. Any thread. Cost: O(1). */
HGCD_API hgcd_status hgcd_world_create(const hgcd_world_desc *desc,
                                       hgcd_world **out_world);

/** Frees the world and all its meshes, bodies and results; every id of it
 *  becomes meaningless and every pointer it returned (pairs, contacts, error
 *  message) dangles. NULL is a no-op. Needs exclusive use of the world.
 *  Cost: O(memory held). */
HGCD_API void hgcd_world_destroy(hgcd_world *world);

/** The message of the last refused call on this world that takes a
 *  non-const world, e.g. "body_create: position[1] is not finite", or "" if
 *  none was refused yet. A later successful call does not clear it.
 *  The string is owned by the world and valid until the next call taking a
 *  non-const world; for a NULL world, a static message. Read-only. */
HGCD_API const char *hgcd_world_last_error(const hgcd_world *world);

/** Number of live bodies. NULL world gives 0. Read-only, O(1). */
HGCD_API uint32_t hgcd_world_body_count(const hgcd_world *world);

/** Number of live meshes. NULL world gives 0. Read-only, O(1). */
HGCD_API uint32_t hgcd_world_mesh_count(const hgcd_world *world);

/** Sets the OpenMP threads per parallel region of the following
 *  step/detect calls (0 = all cores), as hgcd_world_desc.thread_count. The
 *  pairs never depend on it. The process's OpenMP settings are not touched.
 *  Errors: NULL_ARGUMENT, INVALID_ARGUMENT (more than 4096). */
HGCD_API hgcd_status hgcd_world_set_thread_count(hgcd_world *world,
                                                 uint32_t thread_count);

/** Sets the world's thread policy (enum hgcd_thread_policy: ADAPTIVE or
 *  FIXED) for the following calls, as hgcd_world_desc.thread_policy; the
 *  adaptive policy starts again from all threads, as after a change of
 *  thread count. The pairs never depend on it.
 *  Errors: NULL_ARGUMENT, INVALID_ARGUMENT (any other value). Cost: O(1). */
HGCD_API hgcd_status hgcd_world_set_thread_policy(hgcd_world *world,
                                                  int32_t thread_policy);

/** Sets the world's narrow phase (enum hgcd_narrow_phase: EXACT, GJK or
 *  MPR), used from the next step/detect by every mesh set to
 *  HGCD_NARROW_WORLD.
 *  Errors: NULL_ARGUMENT, INVALID_ARGUMENT (any other value), NOT_SUPPORTED
 *  (GJK or MPR without libccd). */
HGCD_API hgcd_status hgcd_world_set_narrow_phase(hgcd_world *world,
                                                 int32_t narrow_phase);

/** Sets the world's contact margin (hgcd_world_desc.contact_margin) from the
 *  next step/detect. Every body counts as moved (every pair is tested
 *  again) and the next step/detect rebuilds the broad phase: O(bodies) here
 *  and then. Setting the same value (bit for bit) changes nothing.
 *  Errors: NULL_ARGUMENT, INVALID_ARGUMENT (not finite, < 0 or > 1e15; the
 *  world is left as it was). */
HGCD_API hgcd_status hgcd_world_set_contact_margin(hgcd_world *world,
                                                   double contact_margin);

/** Sets *out_margin to the world's contact margin.
 *  Errors: NULL_ARGUMENT (world or out_margin). Read-only, O(1). */
HGCD_API hgcd_status hgcd_world_get_contact_margin(const hgcd_world *world,
                                                   double *out_margin);

/** Switches contact recording on (non-zero) or off for the following
 *  step/detect calls, as hgcd_world_desc.contacts.
 *  Errors: NULL_ARGUMENT. */
HGCD_API hgcd_status hgcd_world_set_contacts(hgcd_world *world,
                                             uint32_t enable);

/** Moves every live body by velocity * time_step (reflected at the bounds
 *  if the world reflects), then detects as hgcd_world_detect.
 *  Without reflection, if any move would take a coordinate beyond 1e15 in
 *  magnitude or make it non-finite, nothing moves and INVALID_ARGUMENT is
 *  returned, the message naming the body.
 *  Errors: NULL_ARGUMENT, INVALID_ARGUMENT, OUT_OF_MEMORY (the moves have
 *  then been applied and the detection failed as in hgcd_world_detect;
 *  calling hgcd_world_detect finishes the tick).
 *  Invalidates the previous pairs and contacts. Runs parallel regions.
 *  Cost: O(bodies) plus the detection. */
HGCD_API hgcd_status hgcd_world_step(hgcd_world *world);

/** Finds every colliding pair of live bodies at their current poses,
 *  replacing the previous pairs, contacts and statistics.
 *  Errors: NULL_ARGUMENT, OUT_OF_MEMORY (the only refusal that changes the
 *  world: the previous pairs and contacts are cleared and the statistics
 *  zeroed; bodies and meshes are untouched).
 *  Invalidates the pointers given by hgcd_world_pairs and
 *  hgcd_world_contacts. Runs parallel regions with the world's thread
 *  count; the pairs do not depend on it. The world keeps its working memory
 *  for the next call. Cost: about O(bodies + candidate pairs x pair test),
 *  the pair test growing with the meshes' sizes; a pair of bodies whose
 *  poses did not change since the previous detect is not tested again; when
 *  few bodies moved (up to about a quarter since the grid was last brought
 *  up to date), only they search for pairs: O(pairs + moved bodies x their
 *  candidates x pair test) beside a pass over a byte per body; when no body
 *  moved or was created, no search is made: O(pairs) beside that pass
 *  (temporal coherence: docs/semantics.md). */
HGCD_API hgcd_status hgcd_world_detect(hgcd_world *world);

/** The pairs of the last step/detect: *out_pairs points to *out_count pairs
 *  owned by the world, sorted by (a.index, b.index), without duplicates.
 *  0 pairs (and *out_pairs possibly NULL) before the first detect. Pairs of
 *  bodies destroyed since are still listed, with their now-stale ids.
 *  The array stays valid and unchanged until the next call that changes the
 *  world (step, detect, create/destroy of a body or mesh, set_pose,
 *  set_velocity, hgcd_world_destroy).
 *  Errors: NULL_ARGUMENT (any argument). Read-only, O(1). */
HGCD_API hgcd_status hgcd_world_pairs(const hgcd_world *world,
                                      const hgcd_pair **out_pairs,
                                      size_t *out_count);

/** Copies the first min(capacity, total) pairs of the last step/detect (same
 *  order as hgcd_world_pairs) into the caller's buffer and sets *out_total
 *  to the total, so a first call with capacity 0 (buffer may then be NULL)
 *  sizes the buffer.
 *  Errors: NULL_ARGUMENT (world or out_total NULL, or buffer NULL with
 *  capacity > 0). Read-only. Cost: O(pairs copied). */
HGCD_API hgcd_status hgcd_world_copy_pairs(const hgcd_world *world,
                                           hgcd_pair *buffer, size_t capacity,
                                           size_t *out_total);

/** A pair that began or ended colliding (hgcd_world_events), with both
 *  bodies' user data (hgcd_body_desc.user_data), so that no lookup is needed
 *  per event, also for a body destroyed since. */
typedef struct hgcd_pair_event {
    /** The pair, as hgcd_world_pairs reports it (a.index < b.index). */
    hgcd_pair pair;
    /** The user data of pair.a and of pair.b. */
    uint64_t user_data_a;
    uint64_t user_data_b;
} hgcd_pair_event;

/** The pairs that began and ended colliding at the last step/detect:
 *  began holds each pair of this detect that the previous successful
 *  detect did not report, ended each pair that detect reported and this one
 *  does not, whatever the reason (apart, a body destroyed, disabled, made
 *  static, filtered out or its pair excluded). Pairs are compared by their
 *  full ids, generations included: a slot reused between the two detects
 *  ends its old body's pairs and begins its new body's. Each array is
 *  sorted by (a.index, b.index), without duplicates. Before the first detect
 *  every pair of the first detect has begun; after a detect refused for
 *  lack of memory both are empty, and the next detect compares with the
 *  last successful one.
 *  Both arrays are owned by the world, with the lifetime of the pairs'
 *  array (hgcd_world_pairs); a pointer may be NULL when its count is 0.
 *  Errors: NULL_ARGUMENT (any argument). Read-only, O(1); finding them costs
 *  each detect one merge of the previous and the new pairs
 *  (hgcd_stats.events_seconds). */
HGCD_API hgcd_status hgcd_world_events(const hgcd_world *world,
                                       const hgcd_pair_event **out_began,
                                       size_t *out_began_count,
                                       const hgcd_pair_event **out_ended,
                                       size_t *out_ended_count);

/** What a colliding pair is made of (hgcd_contact.kind). */
enum hgcd_contact_kind {
    /** The surfaces meet (exact test): triangle triangle_a of body a's mesh
     *  and triangle triangle_b of body b's mesh share a point. One witness
     *  pair of triangles, not all of them. */
    HGCD_CONTACT_SURFACE = 1,
    /** The surfaces are apart and a's closed mesh holds b: a connected
     *  component of b's mesh (all of b when it has one) lies inside a. */
    HGCD_CONTACT_A_CONTAINS_B = 2,
    /** The same with the roles swapped (when each holds a component of the
     *  other, this kind is reported). */
    HGCD_CONTACT_B_CONTAINS_A = 3,
    /** Decided by libccd (a GJK or MPR pair): depth, normal and point are
     *  libccd's penetration estimate (EPA after GJK, or MPR's own). */
    HGCD_CONTACT_PENETRATION = 4,
    /** The solids do not share a point but are within the pair's contact
     *  margin (hgcd_world_desc.contact_margin): triangle triangle_a of a's
     *  mesh and triangle_b of b's are within that distance. */
    HGCD_CONTACT_NEAR = 5
};

/** One colliding pair and what it is made of. */
typedef struct hgcd_contact {
    /** The pair, equal to the pair of the same index in hgcd_world_pairs. */
    hgcd_pair pair;
    /** enum hgcd_contact_kind. */
    int32_t kind;
    /** SURFACE and NEAR: the index of a triangle of a's mesh (as given to
     *  hgcd_mesh_create) that meets triangle_b (NEAR: that is within the
     *  margin of triangle_b); UINT32_MAX for other kinds. */
    uint32_t triangle_a;
    /** SURFACE and NEAR: the index of that triangle's partner in b's mesh;
     *  UINT32_MAX for other kinds. */
    uint32_t triangle_b;
    /** Always 0. */
    uint32_t reserved;
    /** PENETRATION: translating body b by depth along normal brings the two
     *  convex hulls to touching, within libccd's tolerance (EPA: the
     *  smallest such translation; MPR: one along its own direction, near the
     *  line between the bodies' centres). 0 for other kinds. */
    double depth;
    /** PENETRATION: unit direction of that translation, in world space; all
     *  zero when libccd gave none (bodies that only touch) and for other
     *  kinds. */
    double normal[3];
    /** PENETRATION: libccd's contact position in world space (an average of
     *  support points near the contact, not guaranteed to lie in both
     *  bodies); all zero for other kinds. */
    double point[3];
} hgcd_contact;

/** The contacts of the last step/detect, parallel to hgcd_world_pairs:
 *  *out_contacts points to *out_count contacts owned by the world, contact k
 *  describing pair k; same lifetime as the pairs' array. 0 contacts before
 *  the first detect.
 *  Errors: NULL_ARGUMENT (any argument); INVALID_ARGUMENT when the last
 *  step/detect ran with contacts off (then *out_contacts is NULL and
 *  *out_count 0). Read-only, O(1). */
HGCD_API hgcd_status hgcd_world_contacts(const hgcd_world *world,
                                         const hgcd_contact **out_contacts,
                                         size_t *out_count);

/** Statistics of the last step/detect. Counts and times are zero before
 *  the first, and after a detect refused for lack of memory. */
typedef struct hgcd_stats {
    /** In: sizeof(hgcd_stats) as the caller knows it (0 = the library's
     *  size); the library fills min(struct_size, its own size) bytes, so
     *  older callers keep working. Out: the number of bytes filled. */
    uint32_t struct_size;
    /** Broad-phase grid levels in use. */
    uint32_t level_count;
    /** Bodies in the oversize set (larger than the coarsest level). */
    uint32_t oversize_count;
    /** Threads the last detect ran with. */
    uint32_t thread_count;
    /** Bodies that changed grid cell in the last update. */
    uint64_t moved_bodies;
    /** Pairs whose axis-aligned boxes overlap (the broad phase's output;
     *  touching boxes count). May include pairs that overlap only once the
     *  boxes are rounded outward to float; the pairs reported are unaffected
     *  (docs/semantics.md, "Broad phase"). */
    uint64_t candidate_pairs;
    /** Candidate pairs that reached the exact test (not rejected by its
     *  exact prefilters: the vertex boxes, and for two tetrahedra a
     *  separating axis along the line between their positions; for two
     *  small convex meshes that axis alone). */
    uint64_t narrow_tests;
    /** Triangle-triangle tests performed. */
    uint64_t triangle_tests;
    /** Colliding pairs (the count of hgcd_world_pairs). */
    uint64_t colliding_pairs;
    /** Colliding pairs found by containment alone (surfaces apart). */
    uint64_t containment_pairs;
    /** Wall-clock seconds of hgcd_world_step before the grid update:
     *  checking the moves (without reflection) and occasionally reordering
     *  the bodies' storage; 0 for hgcd_world_detect, which counts such a
     *  reordering in update_seconds. */
    double motion_seconds;
    /** Seconds updating the grid (with step, including the moves). */
    double update_seconds;
    /** Seconds of the broad phase. */
    double broad_seconds;
    /** Seconds of the narrow phase, including sorting the pairs. */
    double narrow_seconds;
    /** Seconds of the whole call. */
    double total_seconds;
    /** Candidate pairs decided by libccd (both meshes convex and set to GJK
     *  or MPR, exact vertex boxes overlapping); not counted in narrow_tests,
     *  and never in containment_pairs. */
    uint64_t libccd_tests;
    /** Candidate pairs whose meshes were both set to GJK or MPR but one of
     *  them is not convex: tested exactly instead. */
    uint64_t libccd_fallback_tests;
    /** Pairs whose answer is the previous detect's (temporal coherence):
     *  candidate pairs of two bodies whose poses did not change since then,
     *  counted in candidate_pairs, not in narrow_tests. When the search ran
     *  around the moved bodies only (searched_bodies below the live bodies),
     *  the unmoved pairs are not searched for: this counts those of them
     *  that collide (reported again without a test). When no body moved or
     *  was created, the detect makes no search: candidate_pairs is 0 and
     *  this counts the pairs reported. Always 0 for hgcd_world_step, with
     *  contacts on, and after a change of narrow phase. */
    uint64_t unmoved_pairs;
    /** Bodies the broad phase searched pairs for: every live body, or, when
     *  few bodies moved since the previous detect (temporal coherence), the
     *  bodies created or moved since then alone; 0 when none was. */
    uint64_t searched_bodies;
    /** Candidate pairs dropped before the narrow phase by the body types,
     *  the filters or the excluded pairs (hgcd_filter); counted in
     *  candidate_pairs, not in narrow_tests. */
    uint64_t filtered_pairs;
    /** Seconds finding the began and ended pairs (hgcd_world_events),
     *  counted in narrow_seconds and total_seconds. */
    double events_seconds;
} hgcd_stats;

/** Copies the statistics of the last step/detect into *out_stats, whose
 *  struct_size the caller sets first (see hgcd_stats.struct_size); nothing
 *  past struct_size is written.
 *  Errors: NULL_ARGUMENT, BAD_DESCRIPTOR (struct_size between 1 and 7).
 *  Read-only, O(1). */
HGCD_API hgcd_status hgcd_world_stats(const hgcd_world *world,
                                      hgcd_stats *out_stats);

/* ------------------------------------------------------------------------ */
/* Meshes                                                                    */
/* ------------------------------------------------------------------------ */

/** Mesh descriptor: get one from hgcd_mesh_desc_default(), then set the
 *  arrays and counts. */
typedef struct hgcd_mesh_desc {
    /** sizeof(hgcd_mesh_desc), set by hgcd_mesh_desc_default(). */
    uint32_t struct_size;
    /** Set by hgcd_mesh_desc_default(); catches uninitialised descriptors. */
    uint32_t init_tag;
    /** vertex_count * 3 doubles (x, y, z per vertex) in the mesh's own
     *  frame; each finite and at most 1e15 from the origin ("Coordinate
     *  limits" above). Copied in: the caller may
     *  free it when hgcd_mesh_create returns. Default NULL (refused). */
    const double *vertices;
    /** triangle_count * 3 vertex indices, each < vertex_count. Copied in.
     *  The winding never changes the pairs; only a consistently wound mesh
     *  (all faces outward, or all inward) can be found convex. Default NULL
     *  (refused). */
    const uint32_t *triangles;
    /** Number of vertices, 1 to 2^26. Vertices no triangle uses are
     *  allowed (and checked) but ignored. */
    uint32_t vertex_count;
    /** Number of triangles, 1 to 2^26. Triangles may be degenerate (zero
     *  area: they count as the segment or point they are) and may repeat. */
    uint32_t triangle_count;
} hgcd_mesh_desc;

/** A mesh descriptor with NULL arrays and zero counts. Any thread. */
HGCD_API hgcd_mesh_desc hgcd_mesh_desc_default(void);

/** Copies a mesh into the world and sets *out_mesh to its id. The library
 *  works out whether the mesh is closed and convex and its bounding sphere
 *  (hgcd_mesh_info). The counts are checked before the arrays are read.
 *  Errors: NULL_ARGUMENT (world, desc, out_mesh or an array), BAD_DESCRIPTOR,
 *  INVALID_MESH (see the descriptor's fields; the message says which index
 *  or vertex), CAPACITY, OUT_OF_MEMORY.
 *  Cost: O(n log n) in the mesh's size, plus the convexity test (at most
 *  5e7 orientation tests, see hgcd_mesh_info.convex). The tree of a mesh of
 *  more than 48 triangles is built on the world's threads (thread_count, or
 *  the last detect's count under the adaptive policy, as the batch calls),
 *  the same tree on any count: about 5 ms for 5120 triangles on 2 threads,
 *  8.6 on 1. Such a mesh of at most 65,536 vertices also gets its convex
 *  hull (one thread, exact: about 2 ms for 2486 vertices, at most about a
 *  microsecond a vertex), kept when it has at most 1024 vertices. */
HGCD_API hgcd_status hgcd_mesh_create(hgcd_world *world,
                                      const hgcd_mesh_desc *desc,
                                      hgcd_mesh *out_mesh);

/** Destroys a mesh that no live body uses, freeing its memory; its id
 *  becomes stale.
 *  Errors: NULL_ARGUMENT, STALE_ID (mesh not live in this world),
 *  MESH_IN_USE (destroy its bodies first). Cost: O(1) plus the free. */
HGCD_API hgcd_status hgcd_mesh_destroy(hgcd_world *world, hgcd_mesh mesh);

/** What hgcd worked out about a mesh (hgcd_mesh_get_info). */
typedef struct hgcd_mesh_info {
    /** In: sizeof(hgcd_mesh_info) as the caller knows it (0 = the
     *  library's size). Out: the number of bytes filled. */
    uint32_t struct_size;
    /** As given to hgcd_mesh_create. */
    uint32_t vertex_count;
    uint32_t triangle_count;
    /** 1 if every edge is shared by an even number of triangles (the mesh
     *  bounds a volume and can contain other bodies), else 0. */
    uint32_t closed;
    /** 1 if closed, not all degenerate, and every vertex lies on or behind
     *  every face's plane (taking the faces' winding, all one way), else 0.
     *  The test costs triangles x vertices exact orientation tests;
     *  beyond 5e7 of them it is skipped and the mesh reported not convex
     *  (still handled exactly, without the convex shortcuts). */
    uint32_t convex;
    /** Connected components (triangles joined through shared vertices). */
    uint32_t component_count;
    /** Zero-area triangles. */
    uint32_t degenerate_triangle_count;
    /** Live bodies using this mesh. */
    uint32_t body_count;
    /** Centre of the bounding sphere in the mesh frame: the centre of the
     *  box of the vertices the triangles use. */
    double center[3];
    /** Radius of the bounding sphere: it reaches every used vertex. */
    double radius;
    /** The mesh's setting: HGCD_NARROW_WORLD (default) or the value given
     *  to hgcd_mesh_set_narrow_phase. */
    int32_t narrow_phase_setting;
    /** The test the mesh's pairs get now (enum hgcd_narrow_phase, never
     *  WORLD): the setting, else the world's, and EXACT for a mesh that is
     *  not convex. A pair uses libccd only when both meshes say GJK or MPR. */
    int32_t narrow_phase;
    /** The largest norm sqrt((x*x + y*y) + z*z) of a vertex the triangles
     *  use: a body of this mesh needs scale * reach <= 1e15. */
    double reach;
} hgcd_mesh_info;

/** Fills *out_info about a live mesh; the caller sets out_info->struct_size
 *  first (see hgcd_mesh_info.struct_size); nothing past it is written, and
 *  nothing at all on failure.
 *  Errors: NULL_ARGUMENT, BAD_DESCRIPTOR (struct_size between 1 and 7),
 *  STALE_ID. Read-only, O(1). */
HGCD_API hgcd_status hgcd_mesh_get_info(const hgcd_world *world,
                                        hgcd_mesh mesh,
                                        hgcd_mesh_info *out_info);

/** Chooses the narrow phase of this mesh's pairs (enum hgcd_narrow_phase):
 *  HGCD_NARROW_WORLD (follow the world), EXACT, GJK or MPR, used from the
 *  next step/detect.
 *  Errors: NULL_ARGUMENT, STALE_ID, INVALID_ARGUMENT (an unknown value, or
 *  GJK or MPR for a mesh that is not convex: the mesh keeps its setting),
 *  NOT_SUPPORTED (GJK or MPR without libccd). O(1). */
HGCD_API hgcd_status hgcd_mesh_set_narrow_phase(hgcd_world *world,
                                                hgcd_mesh mesh,
                                                int32_t narrow_phase);

/* ------------------------------------------------------------------------ */
/* Bodies                                                                    */
/* ------------------------------------------------------------------------ */

/** How a body moves, and so which of its pairs are searched and reported
 *  (hgcd_body_desc.type, hgcd_body_set_type). A pair with a dynamic body is
 *  always considered; two static bodies never are; a kinematic body with a
 *  kinematic or static one only when hgcd_world_desc.kinematic_pairs is set.
 *  A pair that is not considered costs no narrow test and is never reported.
 *  hgcd_world_step moves dynamic and kinematic bodies by their velocity,
 *  never static ones (their velocity is kept, unused); every type moves with
 *  hgcd_body_set_pose and hgcd_world_set_poses. */
enum hgcd_body_type {
    /** Moves every tick (the default). */
    HGCD_BODY_DYNAMIC = 0,
    /** Moved by the caller, like a platform or a door. */
    HGCD_BODY_KINEMATIC = 1,
    /** Level geometry: moved only when the caller sets its pose. */
    HGCD_BODY_STATIC = 2
};

/** Which bodies a body may collide with, with the semantics of Box2D v3's
 *  b2Filter: two bodies A and B with the same non-zero group_index collide
 *  when it is positive and never when it is negative; otherwise they
 *  collide when (A.mask_bits & B.category_bits) != 0 and
 *  (A.category_bits & B.mask_bits) != 0. A pair refused by the filters is
 *  dropped before the narrow phase (no test, never reported), as are the
 *  pairs excluded with hgcd_world_exclude_pair. The test is symmetric. */
typedef struct hgcd_filter {
    /** The categories the body belongs to (usually one bit). Default 1. */
    uint64_t category_bits;
    /** The categories it collides with. Default UINT64_MAX (all). */
    uint64_t mask_bits;
    /** Group: same positive value, always collide; same negative value,
     *  never; 0 (default) or different values, decided by the bits. */
    int32_t group_index;
    /** Must be 0. */
    uint32_t reserved;
} hgcd_filter;

/** The default filter: category 1, mask UINT64_MAX, group 0 (collides with
 *  every body whose own filter accepts category 1). Any thread. */
HGCD_API hgcd_filter hgcd_filter_default(void);

/** Body descriptor: get one from hgcd_body_desc_default(), then set at least
 *  the mesh. */
typedef struct hgcd_body_desc {
    /** sizeof(hgcd_body_desc), set by hgcd_body_desc_default(). */
    uint32_t struct_size;
    /** Set by hgcd_body_desc_default(); catches uninitialised descriptors. */
    uint32_t init_tag;
    /** The shape: a live mesh of this world. Default: the null id
     *  (refused). */
    hgcd_mesh mesh;
    /** World position of the mesh frame's origin. Finite, |x| <= 1e15.
     *  Default (0, 0, 0). */
    double position[3];
    /** Orientation quaternion (x, y, z, w): finite and of unit length within
     *  1e-6 (|x^2 + y^2 + z^2 + w^2 - 1| <= 1e-6). Used exactly as given,
     *  not normalised (docs/semantics.md, "World-space vertices").
     *  Default (0, 0, 0, 1). */
    double orientation[4];
    /** Velocity used by hgcd_world_step. Finite. Default (0, 0, 0). */
    double velocity[3];
    /** Uniform scale applied to the mesh's vertices before the rotation, so
     *  one mesh can serve bodies of many sizes. Finite, > 0, and
     *  scale * hgcd_mesh_info.reach <= 1e15 ("Coordinate limits" above).
     *  Default 1. */
    double scale;
    /** Any caller value, returned by hgcd_body_get_user_data. Default 0. */
    uint64_t user_data;
    /** enum hgcd_body_type. Default HGCD_BODY_DYNAMIC. */
    int32_t type;
    /** Non-zero (default 1): the body takes part in detection; 0: it is
     *  created disabled (see hgcd_body_set_enabled). */
    uint32_t enabled;
    /** Which bodies it may collide with. Default hgcd_filter_default();
     *  reserved must be 0. */
    hgcd_filter filter;
    /** The body's own contact margin, added to the world's and the other
     *  body's (hgcd_world_desc.contact_margin). Finite, >= 0 and <= 1e15.
     *  Default 0. */
    double margin;
} hgcd_body_desc;

/** A body descriptor with the defaults of its fields. Any thread. */
HGCD_API hgcd_body_desc hgcd_body_desc_default(void);

/** Places a new body and sets *out_body to its id. The body takes part
 *  from the next step/detect.
 *  Errors: NULL_ARGUMENT (world, desc or out_body), BAD_DESCRIPTOR, STALE_ID
 *  (desc->mesh), INVALID_ARGUMENT (a field out of range; the message names
 *  it), CAPACITY, OUT_OF_MEMORY.
 *  Cost: amortised O(1), plus one transform of each vertex for meshes of at
 *  most 128 triangles (their exact bounding box); larger meshes, up to 8
 *  box transforms (the box of a few nodes of their tree). */
HGCD_API hgcd_status hgcd_body_create(hgcd_world *world,
                                      const hgcd_body_desc *desc,
                                      hgcd_body *out_body);

/** Removes a body; its id becomes stale and its index may be reused by the
 *  next hgcd_body_create. The last pairs still list it until the next
 *  detect. Errors: NULL_ARGUMENT, STALE_ID. O(1). */
HGCD_API hgcd_status hgcd_body_destroy(hgcd_world *world, hgcd_body body);

/** Sets a body's position[3] and orientation[4] (x, y, z, w), with the rules
 *  of hgcd_body_desc; either pointer may be NULL to keep the current value.
 *  The arrays are read during the call only.
 *  Errors: NULL_ARGUMENT (world), STALE_ID, INVALID_ARGUMENT (nothing is
 *  changed, not even the valid half).
 *  Cost: O(1), plus with a new orientation one transform of each vertex
 *  for meshes of at most 128 triangles, up to 8 box transforms for larger
 *  ones (a 2-core AMD EPYC, CPU time: about 13 ns with an unchanged
 *  orientation; with a new one about 30 ns for a tetrahedron, 35 to 80 ns
 *  for a 12-triangle box; bench/bench_pose.c). Calls in slot order (the
 *  bodies' index order) cost least in a large world: each asks for the
 *  storage of the body four slots on, which is otherwise a cache miss a
 *  call. For many bodies hgcd_world_set_poses costs less per body. */
HGCD_API hgcd_status hgcd_body_set_pose(hgcd_world *world, hgcd_body body,
                                        const double *position,
                                        const double *orientation);

/** Sets the poses of many bodies in one call, as count calls of
 *  hgcd_body_set_pose would, but checked whole first and applied in
 *  parallel.
 *  bodies: count ids, each at most once; or NULL, meaning entry k is the
 *  body of index k (every index below count must hold a live body: on a
 *  fresh world without destroyed bodies, creation order).
 *  positions: entry k's 3 doubles start at byte k * position_stride
 *  (0 = packed, 3 * sizeof(double)); orientations likewise, 4 doubles
 *  (x, y, z, w), orientation_stride 0 = packed. Either array may be NULL
 *  to keep that part of every pose, not both. Strides let an array of the
 *  caller's own structs be passed without a copy (stride = the struct's size,
 *  each pointer at its first body's field); a stride must be a multiple of
 *  sizeof(double), and, when not 0, at least the entry's size (checked
 *  even when its array is NULL).
 *  Errors (nothing changes; the message names the first bad entry k):
 *  NULL_ARGUMENT (world, or both arrays), STALE_ID (an id not live, or with
 *  bodies NULL an index below count without a live body), INVALID_ARGUMENT
 *  (a value as hgcd_body_set_pose refuses it, an id twice, a bad stride).
 *  Cost: O(count) on the world's threads, plus, per new orientation, the
 *  box of the mesh's distinct vertices (as hgcd_body_set_pose, four bodies
 *  at a time). With bodies NULL the entries are first copied, in index
 *  order, each to its body's place in a stage the world keeps (64 bytes a
 *  body, until the world is destroyed), which the pass in the world's
 *  storage order then reads in sequence: 750,000 tetrahedra with new
 *  orientations take about 11 ms on 1 thread and 6.5 ms on 2 of a 2-core
 *  AMD EPYC (bench/bench_hgcd.c --mode engine-batch). */
HGCD_API hgcd_status hgcd_world_set_poses(hgcd_world *world,
                                          const hgcd_body *bodies, size_t count,
                                          const double *positions,
                                          size_t position_stride,
                                          const double *orientations,
                                          size_t orientation_stride);

/** Sets the velocities of many bodies, as hgcd_world_set_poses sets poses:
 *  bodies (or NULL for indices 0 .. count-1), velocities of 3 finite doubles
 *  each, velocity_stride bytes apart (0 = packed).
 *  Errors: as hgcd_world_set_poses (NULL_ARGUMENT for velocities).
 *  Cost: O(count). */
HGCD_API hgcd_status hgcd_world_set_velocities(hgcd_world *world,
                                               const hgcd_body *bodies,
                                               size_t count,
                                               const double *velocities,
                                               size_t velocity_stride);

/** Reads the poses of many bodies into the caller's arrays (layout as in
 *  hgcd_world_set_poses; either output may be NULL, not both). Nothing is
 *  written on failure. Errors: NULL_ARGUMENT, STALE_ID, INVALID_ARGUMENT
 *  (a bad stride). Read-only, O(count). */
HGCD_API hgcd_status hgcd_world_get_poses(const hgcd_world *world,
                                          const hgcd_body *bodies, size_t count,
                                          double *positions,
                                          size_t position_stride,
                                          double *orientations,
                                          size_t orientation_stride);

/** Sets a body's velocity[3] (finite), used by hgcd_world_step.
 *  Errors: NULL_ARGUMENT (world or velocity), STALE_ID, INVALID_ARGUMENT.
 *  O(1). */
HGCD_API hgcd_status hgcd_body_set_velocity(hgcd_world *world, hgcd_body body,
                                            const double *velocity);

/** Copies a body's position into position[3] and its orientation into
 *  orientation[4], bit for bit as last set or moved; either pointer may be
 *  NULL to skip it.
 *  Errors: NULL_ARGUMENT (world), STALE_ID. Read-only, O(1). */
HGCD_API hgcd_status hgcd_body_get_pose(const hgcd_world *world,
                                        hgcd_body body, double *position,
                                        double *orientation);

/** Copies a body's velocity into velocity[3] (its sign flipped by any
 *  reflection of hgcd_world_step).
 *  Errors: NULL_ARGUMENT (world or velocity), STALE_ID. Read-only, O(1). */
HGCD_API hgcd_status hgcd_body_get_velocity(const hgcd_world *world,
                                            hgcd_body body, double *velocity);

/** Sets *out_mesh to the mesh the body was created with.
 *  Errors: NULL_ARGUMENT (world or out_mesh), STALE_ID. Read-only, O(1). */
HGCD_API hgcd_status hgcd_body_get_mesh(const hgcd_world *world,
                                        hgcd_body body, hgcd_mesh *out_mesh);

/** Sets *out_user_data to the body's hgcd_body_desc.user_data.
 *  Errors: NULL_ARGUMENT (world or out_user_data), STALE_ID. Read-only,
 *  O(1). */
HGCD_API hgcd_status hgcd_body_get_user_data(const hgcd_world *world,
                                             hgcd_body body,
                                             uint64_t *out_user_data);

/** Sets a body's type (enum hgcd_body_type), from the next step/detect.
 *  Errors: NULL_ARGUMENT (world), STALE_ID, INVALID_ARGUMENT (not a type).
 *  O(1). */
HGCD_API hgcd_status hgcd_body_set_type(hgcd_world *world, hgcd_body body,
                                        int32_t type);

/** Sets *out_type to the body's type (enum hgcd_body_type).
 *  Errors: NULL_ARGUMENT (world or out_type), STALE_ID. Read-only, O(1). */
HGCD_API hgcd_status hgcd_body_get_type(const hgcd_world *world,
                                        hgcd_body body, int32_t *out_type);

/** Enables (non-zero) or disables (0) a body, from the next step/detect. A
 *  disabled body keeps its id, pose, velocity, type, filter, exclusions and
 *  user data, and every call on it works as before, but it leaves the grid
 *  and every pair: it is never searched, tested or reported, and
 *  hgcd_world_step does not move it. Errors: NULL_ARGUMENT (world),
 *  STALE_ID. O(1). */
HGCD_API hgcd_status hgcd_body_set_enabled(hgcd_world *world, hgcd_body body,
                                           uint32_t enabled);

/** Sets *out_enabled to 1 if the body is enabled, else 0.
 *  Errors: NULL_ARGUMENT (world or out_enabled), STALE_ID. Read-only,
 *  O(1). */
HGCD_API hgcd_status hgcd_body_get_enabled(const hgcd_world *world,
                                           hgcd_body body,
                                           uint32_t *out_enabled);

/** Sets a body's filter (copied), from the next step/detect.
 *  Errors: NULL_ARGUMENT (world or filter), STALE_ID, INVALID_ARGUMENT
 *  (reserved not 0). O(1). */
HGCD_API hgcd_status hgcd_body_set_filter(hgcd_world *world, hgcd_body body,
                                          const hgcd_filter *filter);

/** Copies a body's filter into *out_filter.
 *  Errors: NULL_ARGUMENT (world or out_filter), STALE_ID. Read-only,
 *  O(1). */
HGCD_API hgcd_status hgcd_body_get_filter(const hgcd_world *world,
                                          hgcd_body body,
                                          hgcd_filter *out_filter);

/** Sets a body's contact margin (hgcd_body_desc.margin), from the next
 *  step/detect. The body counts as moved (its pairs are tested again).
 *  Changing a margin makes the next step/detect rebuild the broad phase
 *  (O(bodies)): set margins when creating bodies where possible.
 *  Errors: NULL_ARGUMENT (world), STALE_ID, INVALID_ARGUMENT (not finite,
 *  < 0 or > 1e15). Setting the same value changes nothing. O(1). */
HGCD_API hgcd_status hgcd_body_set_margin(hgcd_world *world, hgcd_body body,
                                          double margin);

/** Sets *out_margin to the body's contact margin.
 *  Errors: NULL_ARGUMENT (world or out_margin), STALE_ID. Read-only, O(1). */
HGCD_API hgcd_status hgcd_body_get_margin(const hgcd_world *world,
                                          hgcd_body body, double *out_margin);

/** Excludes the pair {a, b} from detection from the next step/detect (two
 *  bodies joined by a joint, say): it is dropped before the narrow phase,
 *  whatever the types and filters say. Excluding an excluded pair changes
 *  nothing. The exclusion lasts until hgcd_world_include_pair or until
 *  either body is destroyed (disabling keeps it).
 *  Errors: NULL_ARGUMENT (world), STALE_ID (a or b), INVALID_ARGUMENT
 *  (a and b the same body), OUT_OF_MEMORY.
 *  Cost: amortised O(1) (a hash set); destroying a body costs O(1) more per
 *  exclusion it has. */
HGCD_API hgcd_status hgcd_world_exclude_pair(hgcd_world *world, hgcd_body a,
                                             hgcd_body b);

/** Ends the exclusion of the pair {a, b} (from the next step/detect); a
 *  pair that is not excluded is left as it is.
 *  Errors: NULL_ARGUMENT (world), STALE_ID (a or b), INVALID_ARGUMENT (a and
 *  b the same body). Amortised O(1). */
HGCD_API hgcd_status hgcd_world_include_pair(hgcd_world *world, hgcd_body a,
                                             hgcd_body b);

/** Sets *out_excluded to 1 if the pair {a, b} is excluded, else 0.
 *  Errors: NULL_ARGUMENT (world or out_excluded), STALE_ID, INVALID_ARGUMENT
 *  (a and b the same body). Read-only, O(1). */
HGCD_API hgcd_status hgcd_world_pair_excluded(const hgcd_world *world,
                                              hgcd_body a, hgcd_body b,
                                              uint32_t *out_excluded);

/** HGCD_OK if body is a live body of this world; STALE_ID for the null
 *  id, a destroyed body's id, a forged id or another world's id (see
 *  "Ids" at the top of hgcd.h); NULL_ARGUMENT for a NULL world. Records no
 *  message (the world is const). Read-only, O(1). */
HGCD_API hgcd_status hgcd_body_validate(const hgcd_world *world,
                                        hgcd_body body);

/** HGCD_OK if mesh is a live mesh of this world; STALE_ID for the null
 *  id, a destroyed mesh's id, a forged id or another world's id (see
 *  "Ids" at the top of hgcd.h); NULL_ARGUMENT for a NULL world. Records no
 *  message (the world is const). Read-only, O(1). */
HGCD_API hgcd_status hgcd_mesh_validate(const hgcd_world *world,
                                        hgcd_mesh mesh);

/* ------------------------------------------------------------------------ */
/* Scene queries                                                             */
/* ------------------------------------------------------------------------ */

/* Rays, boxes, points and meshes at a pose against the world's bodies, many
 * at once, each decided exactly like the pairs (docs/semantics.md, "Scene
 * queries"): on the bodies' world vertices, with exact predicates, touching
 * counts. Batched and parallel on the world's threads; every answer, and its
 * order, is the same at any thread count.
 *
 * Cost: the first query after bodies were created or destroyed builds a
 * tree over the bodies' boxes, O(n log n), mostly on one thread (about half
 * a second for 750,000 bodies); the first after bodies only moved (a pose
 * set, a step) refits it, O(n) on the world's threads (about a tenth of a
 * build), and rebuilds it once moves have loosened it to twice its boxes'
 * area at its build; later queries reuse it. A query then costs about O(log n) plus the exact tests of the
 * bodies its tree search reaches; in a mesh of more than 48 triangles those
 * descend the mesh's own tree (hgcd_mesh_info), so they reach the triangles
 * near the query, not every triangle.
 *
 * Filters: each query takes an optional hgcd_filter and considers the
 * enabled bodies (hgcd_body_set_enabled) that a body with that filter would
 * collide with, by hgcd_filter's rule (group index included; body types play
 * no part): a query can pass its own body's filter and skip that body's
 * group. NULL stands for every enabled body. filter->reserved must be 0.
 *
 * Threading: a query call changes the world's query cache and result arrays,
 * so it needs exclusive use of the world like every hgcd_world * call.
 * Refusals: every input is checked before any work; a refused call changes
 * nothing (the previous query's results stay valid). */

/** A ray: the closed segment from origin to end = origin + max_distance *
 *  direction, end computed in double as written (per component, one product
 *  and one sum, no FMA). origin and end must be within the coordinate range
 *  (each component finite, |x| <= 1e15); direction non-zero and finite;
 *  max_distance finite and >= 0. */
typedef struct hgcd_ray {
    double origin[3];
    double direction[3];
    double max_distance;
} hgcd_ray;

/** What a ray hit. body is the null id {0, 0} when it hit nothing. */
typedef struct hgcd_ray_hit {
    /** The body hit (the lowest index among bodies hit at the same point). */
    hgcd_body body;
    /** The triangle of body's mesh crossed there (the lowest index among
     *  those crossed at that point), or UINT32_MAX when the origin lies in
     *  the body's closed solid (inside == 1). */
    uint32_t triangle;
    /** 1 when the origin lies in the closed solid of body's closed mesh
     *  (inside or on its surface): the hit is at distance 0. */
    uint32_t inside;
    /** max_distance * t, t in [0, 1] the exact parameter of the hit point on
     *  the segment, computed with relative error below 2^-40 (0 and 1 exact
     *  when the hit is exactly at an end). With a unit direction, the
     *  distance from the origin along the ray. */
    double distance;
} hgcd_ray_hit;

/** hgcd_world_cast_rays modes. */
enum hgcd_ray_mode {
    /** The closest hit: the hit with the smallest t; ties by body index,
     *  then triangle index. */
    HGCD_RAY_CLOSEST = 0,
    /** Any hit: whether the segment hits anything (visibility). The hit
     *  reported is a true hit, not necessarily the closest; which one is a
     *  function of the bodies and poses (the same at any thread count). */
    HGCD_RAY_ANY = 1
};

/** Casts count rays and writes one hgcd_ray_hit per ray into out_hits
 *  (the caller's array of count entries). Ray k starts at byte
 *  k * ray_stride of rays (0 = packed, sizeof(hgcd_ray)).
 *  A ray hits a body where its segment first meets the body's closed solid:
 *  at distance 0 when the origin lies in the solid of a closed mesh
 *  (inside = 1), else at the first transversal crossing of a triangle (the
 *  segment passes from one side of the triangle's plane to the other, or
 *  starts or ends on it, at a point of the closed triangle, its edges and
 *  vertices included). A segment lying in a triangle's plane does not cross
 *  that triangle: along a face of a closed mesh it hits where it enters the
 *  solid through a neighbouring face; it misses an open sheet it lies in.
 *  Errors (nothing written): NULL_ARGUMENT (world; rays or out_hits with
 *  count > 0), INVALID_ARGUMENT (mode, stride not a multiple of 8 or below
 *  sizeof(hgcd_ray) when not 0, filter->reserved not 0, a ray out of range:
 *  the message names ray k); OUT_OF_MEMORY (out_hits may then be partly written). Cost: see
 *  above; count = 0 is a no-op. */
HGCD_API hgcd_status hgcd_world_cast_rays(hgcd_world *world,
                                          const hgcd_ray *rays, size_t count,
                                          size_t ray_stride, int32_t mode,
                                          const hgcd_filter *filter,
                                          hgcd_ray_hit *out_hits);

/** Results of a batch of box, point or mesh queries, in world-owned arrays:
 *  the bodies of query k are bodies[offsets[k]] .. bodies[offsets[k+1] - 1],
 *  ascending by index; offsets has query_count + 1 entries, offsets[0] = 0,
 *  offsets[query_count] = body_count. Valid until the next query call on
 *  this world (hgcd_world_query_*), or its destruction; not changed by any
 *  other call. */
typedef struct hgcd_query_results {
    const size_t *offsets;
    const hgcd_body *bodies;
    size_t query_count;
    size_t body_count;
} hgcd_query_results;

/** The bodies whose closed solid meets each closed axis-aligned box (a
 *  triangle meets the box, or a closed mesh holds it; touching counts).
 *  Box k is 6 doubles (min x y z, max x y z) at byte k * box_stride of
 *  boxes (0 = packed); each component within the coordinate range, min <=
 *  max per axis (a flat box or a point is allowed).
 *  Errors (nothing changes): NULL_ARGUMENT (world, out; boxes with count >
 *  0), INVALID_ARGUMENT (stride, filter->reserved not 0, a bad box: the
 *  message names it), OUT_OF_MEMORY. */
HGCD_API hgcd_status hgcd_world_query_box(hgcd_world *world,
                                          const double *boxes, size_t count,
                                          size_t box_stride,
                                          const hgcd_filter *filter,
                                          hgcd_query_results *out);

/** The bodies whose closed solid contains each point: on a triangle (edges
 *  and vertices included), or inside a closed mesh. Point k is 3 doubles at
 *  byte k * point_stride of points (0 = packed), within the coordinate range.
 *  Errors: as hgcd_world_query_box. */
HGCD_API hgcd_status hgcd_world_query_point(hgcd_world *world,
                                            const double *points, size_t count,
                                            size_t point_stride,
                                            const hgcd_filter *filter,
                                            hgcd_query_results *out);

/** A pose of a query mesh: position, orientation (x, y, z, w) and scale,
 *  with the rules of hgcd_body_desc. */
typedef struct hgcd_mesh_pose {
    double position[3];
    double orientation[4];
    double scale;
} hgcd_mesh_pose;

/** The bodies that a body of `mesh` at each pose would collide with, with
 *  the pairs' semantics (surfaces meet or containment either way, exact;
 *  libccd settings do not apply: always the exact test). Pose k is at byte
 *  k * pose_stride of poses (0 = packed, sizeof(hgcd_mesh_pose)). The mesh
 *  is any live mesh of the world; no body is created.
 *  Errors: as hgcd_world_query_box, and STALE_ID (mesh). */
HGCD_API hgcd_status hgcd_world_query_mesh(hgcd_world *world, hgcd_mesh mesh,
                                           const hgcd_mesh_pose *poses,
                                           size_t count, size_t pose_stride,
                                           const hgcd_filter *filter,
                                           hgcd_query_results *out);

#ifdef __cplusplus
}
#endif

#endif /* HGCD_H */
