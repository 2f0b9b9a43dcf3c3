"""hgcd.World and hgcd.Mesh."""
import threading

import numpy as np

from . import _arrays as A
from ._arrays import BODY_ID, MESH_ID
from ._errors import Error, Status, argument_error
from ._features import EngineFeatures, per_body, type_values
from ._hgcd import ffi, lib
from ._queries import QueryMixin
from ._types import CONTACT, FILTER, NarrowPhase, ThreadPolicy, mesh_info_from_c, stats_from_c


def _enum(cls, value, call):
    try:
        return int(cls(value))
    except ValueError:
        raise argument_error(f"{call}: {value!r} is not a {cls.__name__}") from None


def _narrow(value, call):
    return _enum(NarrowPhase, value, call)


class Mesh:
    """A mesh (a shared shape) of a World. It keeps its world alive; once the
    mesh is destroyed, or its world closed, its calls raise hgcd.Error."""

    __slots__ = ("world", "index", "generation")

    def __init__(self, world, c_id):
        self.world = world
        self.index = int(c_id.index)
        self.generation = int(c_id.generation)

    @property
    def id(self):
        """The id as a MESH_ID scalar (the C struct hgcd_mesh)."""
        return np.array((self.index, self.generation), dtype=MESH_ID)[()]

    def _c(self):
        return ffi.new("hgcd_mesh *", (self.index, self.generation))[0]

    @property
    def alive(self):
        """Whether the mesh is live in its (open) world (hgcd_mesh_validate)."""
        with self.world._lock:
            if self.world._w == ffi.NULL:
                return False
            return lib.hgcd_mesh_validate(self.world._w, self._c()) == lib.HGCD_OK

    def info(self):
        """What hgcd worked out about the mesh: a MeshInfo (hgcd_mesh_get_info)."""
        out = ffi.new("hgcd_mesh_info *")
        out.struct_size = ffi.sizeof("hgcd_mesh_info")
        with self.world._lock:
            self.world._const_check(lib.hgcd_mesh_get_info(self.world._live(), self._c(), out),
                                    "mesh_get_info")
        return mesh_info_from_c(out)

    def set_thread_policy(self, policy):
        """ThreadPolicy.ADAPTIVE or FIXED for the following calls; never changes the pairs."""
        with self._lock:
            self._check(lib.hgcd_world_set_thread_policy(self._live(), _enum(ThreadPolicy, policy,
                                                                             "set_thread_policy")))

    def set_narrow_phase(self, narrow_phase):
        """The narrow phase of this mesh's pairs (NarrowPhase; WORLD = follow the world)."""
        with self.world._lock:
            self.world._check(lib.hgcd_mesh_set_narrow_phase(self.world._live(), self._c(),
                                                             _narrow(narrow_phase, "mesh_set_narrow_phase")))

    def destroy(self):
        """Frees the mesh (its bodies must be destroyed first: else MESH_IN_USE)."""
        with self.world._lock:
            self.world._check(lib.hgcd_mesh_destroy(self.world._live(), self._c()))

    def __eq__(self, other):
        return (isinstance(other, Mesh) and self.world is other.world
                and (self.index, self.generation) == (other.index, other.generation))

    def __hash__(self):
        return hash((id(self.world), self.index, self.generation))

    def __repr__(self):
        return f"hgcd.Mesh(index={self.index}, generation={self.generation})"


class World(EngineFeatures, QueryMixin):
    """A world of meshes and bodies (hgcd_world). Frees its C world on close(),
    at the end of a `with` block, or when garbage-collected; after close()
    every call raises hgcd.Error (status NULL_ARGUMENT).

    Bodies are ids in numpy arrays of dtype hgcd.BODY_ID (index, generation);
    on a fresh world body k of creation order has index k. Calls on one world
    are serialised by a lock, so threads may share it safely; detect() and
    step() run without the GIL, so other Python threads (and other worlds)
    keep running meanwhile.

    Keyword arguments (hgcd_world_desc): threads (0 = all cores),
    thread_policy (ThreadPolicy: ADAPTIVE, the default, uses fewer threads
    while the cores are busy with other work; FIXED always threads), bounds
    ((min xyz, max xyz): step() reflects bodies there; None = no reflection),
    time_step, min_cell_size, max_cell_size, narrow_phase (NarrowPhase),
    contacts (record what each pair is made of: contacts()), kinematic_pairs
    (also report kinematic-kinematic and kinematic-static pairs: BodyType),
    contact_margin (report two bodies within this distance of each other, plus
    their own margins; 0, the default, reports touching solids only: see
    set_contact_margin).
    """

    def __init__(self, *, threads=0, bounds=None, time_step=1.0, min_cell_size=0.0,
                 max_cell_size=0.0, narrow_phase=NarrowPhase.EXACT, contacts=False,
                 thread_policy=ThreadPolicy.ADAPTIVE, kinematic_pairs=False, contact_margin=0.0):
        self._lock = threading.Lock()
        self._w = ffi.NULL
        desc = ffi.new("hgcd_world_desc *", lib.hgcd_world_desc_default())
        try:
            desc.thread_count = threads
            desc.time_step = time_step
            desc.min_cell_size = min_cell_size
            desc.max_cell_size = max_cell_size
            desc.narrow_phase = _narrow(narrow_phase, "world_create")
            desc.thread_policy = _enum(ThreadPolicy, thread_policy, "world_create")
            desc.contact_margin = contact_margin
        except (TypeError, ValueError, OverflowError) as e:
            raise argument_error(f"world_create: {e}")
        desc.contacts = 1 if contacts else 0
        desc.kinematic_pairs = 1 if kinematic_pairs else 0
        if bounds is not None:
            lo = A.column(bounds[0], 3, "bounds[0]", "world_create", np.float64)
            hi = A.column(bounds[1], 3, "bounds[1]", "world_create", np.float64)
            desc.reflect_at_bounds = 1
            desc.bounds_min = list(lo)
            desc.bounds_max = list(hi)
        out = ffi.new("hgcd_world **")
        status = lib.hgcd_world_create(desc, out)
        if status != lib.HGCD_OK:
            # No world, so no message: say which fields the header checks.
            raise Error(status, "world_create: refused (threads <= 4096, time_step and cell sizes finite "
                                "and >= 0, bounds finite with min < max, narrow phase available, "
                                "contact_margin finite, >= 0 and <= 1e15)")
        self._w = out[0]

    # -- lifetime ---------------------------------------------------------

    def close(self):
        """Frees the C world (hgcd_world_destroy); a second close() does nothing.
        Arrays returned earlier (pairs, poses, contacts) are copies and stay valid."""
        with self._lock:
            w, self._w = self._w, ffi.NULL
            lib.hgcd_world_destroy(w)

    @property
    def closed(self):
        return self._w == ffi.NULL

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.close()

    def __del__(self):
        w = getattr(self, "_w", None)
        if w is not None and w != ffi.NULL:
            lib.hgcd_world_destroy(w)

    def __repr__(self):
        if self.closed:
            return "hgcd.World(closed)"
        return f"hgcd.World(bodies={self.body_count}, meshes={self.mesh_count})"

    # -- status plumbing (the caller holds the lock) ----------------------

    def _live(self):
        if self._w == ffi.NULL:
            raise Error(Status.NULL_ARGUMENT, "the world is closed")
        return self._w

    def _check(self, status, prefix=""):
        """Raise for a refused call taking a non-const world: its message is recorded."""
        if status != lib.HGCD_OK:
            raise Error(status, prefix + ffi.string(lib.hgcd_world_last_error(self._w)).decode())

    def _check_entry(self, status, call, entry):
        """Raise for a refused call over many bodies, naming the entry refused."""
        if status == lib.HGCD_ERROR_STALE_ID:
            raise Error(status, f"{call}: entry {entry} is not a live body of this world")
        self._check(status, f"{call}: entry {entry}: ")

    @staticmethod
    def _const_check(status, call, why="refused"):
        """Raise for a refused read-only call: those record no message, so the
        binding says what the header gives as the reason."""
        if status != lib.HGCD_OK:
            if status == lib.HGCD_ERROR_STALE_ID:
                why = "an id is not a live body or mesh of this world"
            raise Error(status, f"{call}: {why}")

    # -- world settings ---------------------------------------------------

    @property
    def last_error(self):
        """The library's message of the last refused call ("" if none)."""
        with self._lock:
            return ffi.string(lib.hgcd_world_last_error(self._live())).decode()

    @property
    def body_count(self):
        with self._lock:
            return int(lib.hgcd_world_body_count(self._live()))

    @property
    def mesh_count(self):
        with self._lock:
            return int(lib.hgcd_world_mesh_count(self._live()))

    def set_thread_count(self, threads):
        """Threads per parallel region of step/detect (0 = all cores); never changes the pairs."""
        if not isinstance(threads, (int, np.integer)) or threads < 0:
            raise argument_error(f"set_thread_count: threads must be an int >= 0, not {threads!r}")
        with self._lock:
            self._check(lib.hgcd_world_set_thread_count(self._live(), min(int(threads), 2**32 - 1)))

    def set_thread_policy(self, policy):
        """ThreadPolicy.ADAPTIVE or FIXED for the following calls; never changes the pairs."""
        with self._lock:
            self._check(lib.hgcd_world_set_thread_policy(self._live(), _enum(ThreadPolicy, policy,
                                                                             "set_thread_policy")))

    def set_narrow_phase(self, narrow_phase):
        """The world's narrow phase: NarrowPhase.EXACT, GJK or MPR."""
        with self._lock:
            self._check(lib.hgcd_world_set_narrow_phase(self._live(), _narrow(narrow_phase, "set_narrow_phase")))

    def set_contacts(self, enable):
        """Record contacts from the next step/detect on (True) or not."""
        with self._lock:
            self._check(lib.hgcd_world_set_contacts(self._live(), 1 if enable else 0))

    # -- meshes -----------------------------------------------------------

    def create_mesh(self, vertices, triangles):
        """A mesh from (V, 3) float64 vertices and (T, 3) uint32 vertex indices
        (copied in by the library; C-contiguous arrays are passed without a copy)."""
        v = A.packed(A.rows(vertices, 3, None, "vertices", "mesh_create"))
        t = A.packed(A.rows(triangles, 3, None, "triangles", "mesh_create", np.uint32))
        if v.shape[0] >= 2**32 or t.shape[0] >= 2**32:
            raise argument_error("mesh_create: 2^32 or more vertices or triangles")
        desc = ffi.new("hgcd_mesh_desc *", lib.hgcd_mesh_desc_default())
        desc.vertices = A.ptr("double *", v)
        desc.triangles = A.ptr("uint32_t *", t)
        desc.vertex_count = v.shape[0]
        desc.triangle_count = t.shape[0]
        out = ffi.new("hgcd_mesh *")
        with self._lock:
            self._check(lib.hgcd_mesh_create(self._live(), desc, out))
        return Mesh(self, out[0])

    def _mesh_ids(self, mesh, count):
        if isinstance(mesh, Mesh):
            if mesh.world is not self:
                raise Error(Status.STALE_ID, "body_create: the mesh belongs to another world")
            return np.array([(mesh.index, mesh.generation)], dtype=MESH_ID)
        if isinstance(mesh, (list, tuple)) and mesh and all(isinstance(m, Mesh) for m in mesh):
            if any(m.world is not self for m in mesh):
                raise Error(Status.STALE_ID, "body_create: a mesh belongs to another world")
            mesh = np.array([(m.index, m.generation) for m in mesh], dtype=MESH_ID)
        return A.ids(mesh, count, "meshes", "body_create")

    # -- bodies -----------------------------------------------------------

    def create_bodies(self, mesh, positions=None, orientations=None, velocities=None, scales=None,
                      user_data=None, *, count=None, types=None, enabled=None, filters=None, margins=None):
        """Creates bodies in one call and returns their ids, a (N,) BODY_ID array.

        mesh: a Mesh for all, or one per body (a list of Mesh, or a MESH_ID
        array); positions (N, 3), orientations (N, 4) unit quaternions
        (x, y, z, w), velocities (N, 3), scales (N,) float64; user_data (N,)
        uint64; types (BodyType, one or (N,)), enabled (bool, one or (N,)),
        filters (a FILTER from make_filter, one or (N,)), margins (float, one
        or (N,): each body's own contact margin, finite, >= 0, <= 1e15). An
        argument left None takes the library's default (origin, identity, at
        rest, 1, 0, DYNAMIC, enabled, the default filter, margin 0); count
        gives N when every array is None.
        Bodies are created in order; if one is refused, those made are
        destroyed again and the error names the entry."""
        given = [a for a in (positions, orientations, velocities, scales, user_data) if a is not None]
        n = count
        try:
            if n is None and given:
                n = len(given[0])
            elif n is None and not isinstance(mesh, Mesh):
                n = len(mesh)
        except TypeError:
            raise argument_error("create_bodies: the arrays must be sequences of rows") from None
        if n is None:
            raise argument_error("create_bodies: give count or at least one array")
        if not isinstance(n, (int, np.integer)) or n < 0:
            raise argument_error(f"create_bodies: count must be an int >= 0, not {n!r}")
        call = "create_bodies"
        arrays = [
            None if positions is None else A.packed(A.rows(positions, 3, n, "positions", call)),
            None if orientations is None else A.packed(A.rows(orientations, 4, n, "orientations", call)),
            None if velocities is None else A.packed(A.rows(velocities, 3, n, "velocities", call)),
            None if scales is None else A.packed(A.column(scales, n, "scales", call, np.float64)),
            None if user_data is None else A.packed(A.column(user_data, n, "user_data", call, np.uint64)),
        ]
        arrays += [
            None if types is None else type_values(types, n, call),
            None if enabled is None else per_body(np.asarray(enabled, dtype=bool).astype(np.uint8), n,
                                                  np.uint8, "enabled", call),
            None if filters is None else per_body(filters, n, FILTER, "filters", call),
            None if margins is None else per_body(margins, n, np.float64, "margins", call),
        ]
        meshes = self._mesh_ids(mesh, None if isinstance(mesh, Mesh) else n)
        ctypes = ("double *", "double *", "double *", "double *", "uint64_t *", "int32_t *", "uint8_t *",
                  "hgcd_filter *", "double *")
        columns = ffi.new("hgcd_py_body_columns *",
                          [ffi.NULL if a is None else A.ptr(t, a) for a, t in zip(arrays, ctypes)])
        out = np.empty(n, dtype=BODY_ID)
        failed = ffi.new("size_t *")
        with self._lock:
            status = lib.hgcd_py_create_bodies(self._live(), A.ptr("hgcd_mesh *", meshes), len(meshes), n,
                                               columns, A.ptr("hgcd_body *", out), failed)
            self._check(status, f"create_bodies: entry {failed[0]}: ")
        return out

    def destroy_bodies(self, bodies):
        """Destroys the bodies of a BODY_ID array (each live, none twice); a stale
        id refuses the call with nothing destroyed."""
        b = A.ids(bodies, None, "bodies", "destroy_bodies")
        if len(np.unique(b)) != len(b):
            raise argument_error("destroy_bodies: an id is given twice")
        failed = ffi.new("size_t *")
        with self._lock:
            status = lib.hgcd_py_destroy_bodies(self._live(), A.ptr("hgcd_body *", b), len(b), failed)
            self._check_entry(status, "destroy_bodies", failed[0])

    def bodies_alive(self, bodies):
        """A (N,) bool array: whether each id is a live body of this world."""
        b = A.ids(bodies, None, "bodies", "bodies_alive")
        out = np.empty(len(b), dtype=np.uint8)
        with self._lock:
            lib.hgcd_py_validate_bodies(self._live(), A.ptr("hgcd_body *", b), len(b),
                                        A.ptr("uint8_t *", out))
        return out.astype(bool)

    def _batch_target(self, bodies, n, call):
        """(C pointer, keep-alive array) of the bodies argument of a batch call."""
        if bodies is None:
            return ffi.NULL, None
        b = A.ids(bodies, n, "bodies", call)
        return A.ptr("hgcd_body *", b), b

    def set_poses(self, positions=None, orientations=None, bodies=None):
        """Sets many poses in one call (hgcd_world_set_poses): positions (N, 3)
        and/or orientations (N, 4) float64 (either may be None to keep that
        part). bodies: a (N,) BODY_ID array, or None for the bodies of index
        0 .. N-1. Checked whole first: a refusal changes nothing. Rows may be
        strided (a field of a record array): they are read in place."""
        if positions is None and orientations is None:
            raise Error(Status.NULL_ARGUMENT, "set_poses: give positions, orientations or both")
        n = None
        c_args = []
        keep = []
        for value, width, what in ((positions, 3, "positions"), (orientations, 4, "orientations")):
            if value is None:
                c_args += [ffi.NULL, 0]
                continue
            arr, stride = A.strided(A.rows(value, width, n, what, "set_poses"))
            n = arr.shape[0]
            keep.append(arr)
            c_args += [A.ptr("double *", arr), stride]
        c_bodies, _b = self._batch_target(bodies, n, "set_poses")
        with self._lock:
            self._check(lib.hgcd_world_set_poses(self._live(), c_bodies, n, *c_args))

    def set_velocities(self, velocities, bodies=None):
        """Sets many velocities in one call: (N, 3) float64, bodies as set_poses."""
        arr, stride = A.strided(A.rows(velocities, 3, None, "velocities", "set_velocities"))
        n = arr.shape[0]
        c_bodies, _b = self._batch_target(bodies, n, "set_velocities")
        with self._lock:
            self._check(lib.hgcd_world_set_velocities(self._live(), c_bodies, n, A.ptr("double *", arr),
                                                      stride))

    def _output(self, out, n, width, what):
        if out is None:
            return np.empty((n, width), dtype=np.float64)
        arr = A.rows(out, width, n, what, "get_poses")
        if not isinstance(out, np.ndarray) or not arr.flags.writeable:
            raise argument_error(f"get_poses: {what} must be a writeable float64 array")
        if A.strided(arr)[0] is not arr:
            raise argument_error(f"get_poses: {what} must have packed rows of 8-byte elements, "
                                 "rows a multiple of 8 bytes apart")
        return arr

    def get_poses(self, bodies=None, *, count=None, positions=None, orientations=None):
        """Reads many poses in one call (hgcd_world_get_poses) and returns
        (positions (N, 3), orientations (N, 4)). bodies: a BODY_ID array, or
        None for the bodies of index 0 .. count-1 (count defaults to
        body_count). positions/orientations: arrays to fill in place (any
        row stride, as set_poses reads) instead of new ones."""
        if bodies is not None:
            n = len(A.ids(bodies, None, "bodies", "get_poses"))
        else:
            n = self.body_count if count is None else count
            if not isinstance(n, (int, np.integer)) or n < 0:
                raise argument_error(f"get_poses: count must be an int >= 0, not {n!r}")
        pos = self._output(positions, n, 3, "positions")
        ori = self._output(orientations, n, 4, "orientations")
        c_bodies, _b = self._batch_target(bodies, n, "get_poses")
        _, ps = A.strided(pos)
        _, qs = A.strided(ori)
        with self._lock:
            status = lib.hgcd_world_get_poses(self._live(), c_bodies, n, A.ptr("double *", pos), ps,
                                              A.ptr("double *", ori), qs)
            self._const_check(status, "get_poses")
        return pos, ori

    def get_bodies(self, bodies):
        """(velocities (N, 3), meshes (N,) MESH_ID, user_data (N,) uint64) of the
        bodies of a BODY_ID array, read in one call."""
        b = A.ids(bodies, None, "bodies", "get_bodies")
        vel = np.empty((len(b), 3))
        meshes = np.empty(len(b), dtype=MESH_ID)
        user = np.empty(len(b), dtype=np.uint64)
        failed = ffi.new("size_t *")
        with self._lock:
            status = lib.hgcd_py_get_bodies(self._live(), A.ptr("hgcd_body *", b), len(b),
                                            A.ptr("double *", vel), A.ptr("hgcd_mesh *", meshes),
                                            A.ptr("uint64_t *", user), failed)
            self._const_check(status, f"get_bodies: entry {failed[0]}")
        return vel, meshes, user

    def get_velocities(self, bodies):
        """The (N, 3) velocities of the bodies of a BODY_ID array (get_bodies()[0])."""
        return self.get_bodies(bodies)[0]

    # -- ticks ------------------------------------------------------------

    def step(self):
        """Moves every body by velocity * time_step (reflecting at the bounds), then detects."""
        with self._lock:
            self._check(lib.hgcd_world_step(self._live()))

    def detect(self):
        """Finds every colliding pair at the current poses (hgcd_world_detect)."""
        with self._lock:
            self._check(lib.hgcd_world_detect(self._live()))

    def pairs(self, ids=False):
        """The pairs of the last step/detect, sorted, a.index < b.index: a new
        (N, 2) uint32 array of body indices, or with ids=True an (N, 2) BODY_ID
        array of full ids. A copy: it stays valid after later ticks and after
        the world is closed (the world's own array changes at every tick)."""
        out_pairs = ffi.new("hgcd_pair **")
        out_count = ffi.new("size_t *")
        with self._lock:
            self._const_check(lib.hgcd_world_pairs(self._live(), out_pairs, out_count), "world_pairs")
            n = out_count[0]
            if n == 0:
                return np.empty((0, 2), dtype=BODY_ID if ids else np.uint32)
            raw = np.frombuffer(ffi.buffer(out_pairs[0], n * ffi.sizeof("hgcd_pair")), dtype=BODY_ID)
            raw = raw.reshape(n, 2)
            return raw.copy() if ids else raw["index"].copy()

    def contacts(self):
        """What each pair of the last step/detect is made of: a new (N,) array of
        dtype hgcd.CONTACT, entry k for pair k (needs contacts on: World(contacts=True)
        or set_contacts(True) before that tick; otherwise INVALID_ARGUMENT)."""
        out = ffi.new("hgcd_contact **")
        out_count = ffi.new("size_t *")
        with self._lock:
            self._const_check(lib.hgcd_world_contacts(self._live(), out, out_count), "world_contacts",
                              "the last step/detect ran with contacts off (World(contacts=True), set_contacts)")
            n = out_count[0]
            if n == 0:
                return np.empty(0, dtype=CONTACT)
            return np.frombuffer(ffi.buffer(out[0], n * CONTACT.itemsize), dtype=CONTACT).copy()

    def stats(self):
        """Statistics of the last step/detect: a Stats."""
        out = ffi.new("hgcd_stats *")
        out.struct_size = ffi.sizeof("hgcd_stats")
        with self._lock:
            self._const_check(lib.hgcd_world_stats(self._live(), out), "world_stats")
        return stats_from_c(out)
