"""Scene queries of a World: rays, boxes, points and a mesh at many poses,
batched (hgcd.h, "Scene queries"). Mixed into hgcd.World."""
import numpy as np

from . import _arrays as A
from ._arrays import BODY_ID
from ._errors import Error, Status, argument_error
from ._hgcd import ffi, lib
from ._types import FILTER

#: dtype of a ray hit (hgcd_ray_hit): body (BODY_ID; generation 0 when the ray
#: hit nothing), triangle (uint32; 2**32 - 1 when inside), inside (uint32: the
#: origin lies in the body's closed solid) and distance (float64).
RAY_HIT = np.dtype([("body", BODY_ID), ("triangle", "<u4"), ("inside", "<u4"), ("distance", "<f8")])

assert RAY_HIT.itemsize == ffi.sizeof("hgcd_ray_hit")
assert ffi.sizeof("hgcd_ray") == 7 * 8 and ffi.sizeof("hgcd_mesh_pose") == 8 * 8


def _filter(value, call):
    """A C hgcd_filter from a FILTER scalar (hgcd.make_filter) or a tuple
    (category_bits, mask_bits[, group_index]), or NULL for None."""
    if value is None:
        return ffi.NULL
    if isinstance(value, (np.ndarray, np.void)) and value.dtype == FILTER:
        if np.ndim(value) != 0:
            raise argument_error(f"{call}: filter must be one FILTER, not an array of shape {np.shape(value)}")
        value = tuple(value[()] if isinstance(value, np.ndarray) else value)
    try:
        fields = tuple(value)
        if len(fields) == 4:  # (a FILTER's fields: reserved last, checked by the library)
            f = ffi.new("hgcd_filter *", [int(x) for x in fields])
            return f
        if len(fields) not in (2, 3):
            raise ValueError("needs 2 or 3 entries")
        f = ffi.new("hgcd_filter *")
        f.category_bits = int(fields[0])
        f.mask_bits = int(fields[1])
        f.group_index = int(fields[2]) if len(fields) == 3 else 0
    except (TypeError, ValueError, OverflowError) as e:
        raise argument_error(f"{call}: filter must be (category_bits, mask_bits[, group_index]) "
                             f"of uint64, uint64, int32: {e}") from None
    return f


def _per_query(value, n, what, call):
    """A (n,) float64 column from a scalar or an array."""
    if np.isscalar(value):
        return np.full(n, float(value))
    return A.column(value, n, what, call, np.float64)


class QueryMixin:
    """The World's query calls (the World's lock and status plumbing)."""

    def cast_rays(self, origins, directions, max_distances, *, any_hit=False, filter=None):
        """Casts N rays (hgcd_world_cast_rays): origins and directions (N, 3)
        float64, max_distances a float or (N,) float64; each ray is the closed
        segment from origin to origin + max_distance * direction. Returns a new
        (N,) array of RAY_HIT: per ray the closest hit (any_hit=True: some
        hit, for visibility), exact; body generation 0 where nothing was hit.
        filter: None (every enabled body), a FILTER (hgcd.make_filter) or
        (category_bits, mask_bits[, group_index]): the query stands for a
        body with that filter and considers the enabled bodies it would
        collide with. Runs without the GIL."""
        o = A.rows(origins, 3, None, "origins", "world_cast_rays")
        n = o.shape[0]
        d = A.rows(directions, 3, n, "directions", "world_cast_rays")
        rays = np.empty((n, 7))
        rays[:, 0:3] = o
        rays[:, 3:6] = d
        rays[:, 6] = _per_query(max_distances, n, "max_distances", "world_cast_rays")
        hits = np.zeros(n, dtype=RAY_HIT)
        f = _filter(filter, "world_cast_rays")
        mode = lib.HGCD_RAY_ANY if any_hit else lib.HGCD_RAY_CLOSEST
        with self._lock:
            self._check(lib.hgcd_world_cast_rays(self._live(), A.ptr("hgcd_ray *", rays), n, 0, mode, f,
                                                 A.ptr("hgcd_ray_hit *", hits)))
        return hits

    def _results(self, out, ids):
        """(offsets, bodies) copied out of the world's result arrays."""
        n, m = out.query_count, out.body_count
        offsets = np.frombuffer(ffi.buffer(out.offsets, (n + 1) * ffi.sizeof("size_t")), dtype=np.uintp)
        offsets = offsets.astype(np.int64)
        if m == 0:
            return offsets, np.empty(0, dtype=BODY_ID if ids else np.uint32)
        bodies = np.frombuffer(ffi.buffer(out.bodies, m * BODY_ID.itemsize), dtype=BODY_ID)
        return offsets, bodies.copy() if ids else bodies["index"].copy()

    def _region_query(self, name, data, n, filter, ids, *prefix):
        out = ffi.new("hgcd_query_results *")
        f = _filter(filter, "world_" + name)
        call = getattr(lib, "hgcd_world_" + name)
        with self._lock:
            self._check(call(self._live(), *prefix, A.ptr("double *", data), n, 0, f, out))
            return self._results(out, ids)

    def query_boxes(self, boxes, *, filter=None, ids=False):
        """The bodies whose closed solid meets each closed box (hgcd_world_query_box):
        boxes (N, 6) float64 (min x y z, max x y z). Returns (offsets, bodies):
        offsets (N + 1,) int64, bodies of query k bodies[offsets[k]:offsets[k + 1]],
        ascending, as uint32 indices (ids=True: BODY_ID). New arrays; filter as
        cast_rays. Runs without the GIL."""
        b = A.packed(A.rows(boxes, 6, None, "boxes", "world_query_box"))
        return self._region_query("query_box", b, b.shape[0], filter, ids)

    def query_points(self, points, *, filter=None, ids=False):
        """The bodies whose closed solid holds each point (hgcd_world_query_point):
        points (N, 3) float64. Returns (offsets, bodies) as query_boxes."""
        p = A.packed(A.rows(points, 3, None, "points", "world_query_point"))
        return self._region_query("query_point", p, p.shape[0], filter, ids)

    def query_mesh(self, mesh, positions, orientations=None, scales=None, *, filter=None, ids=False):
        """The bodies a body of `mesh` at each pose would collide with
        (hgcd_world_query_mesh): positions (N, 3), orientations (N, 4) (x, y, z,
        w; default identity), scales (N,) or a float (default 1). Returns
        (offsets, bodies) as query_boxes."""
        pos = A.rows(positions, 3, None, "positions", "world_query_mesh")
        n = pos.shape[0]
        poses = np.empty((n, 8))
        poses[:, 0:3] = pos
        if orientations is None:
            poses[:, 3:7] = (0.0, 0.0, 0.0, 1.0)
        else:
            poses[:, 3:7] = A.rows(orientations, 4, n, "orientations", "world_query_mesh")
        poses[:, 7] = _per_query(1.0 if scales is None else scales, n, "scales", "world_query_mesh")
        if not hasattr(mesh, "world") or not hasattr(mesh, "_c"):
            raise argument_error(f"world_query_mesh: mesh must be an hgcd.Mesh, not {type(mesh).__name__}")
        if mesh.world is not self:
            raise Error(Status.STALE_ID, "world_query_mesh: the mesh belongs to another world")
        c_mesh = mesh._c()
        out = ffi.new("hgcd_query_results *")
        f = _filter(filter, "world_query_mesh")
        with self._lock:
            self._check(lib.hgcd_world_query_mesh(self._live(), c_mesh, A.ptr("hgcd_mesh_pose *", poses), n, 0, f,
                                                  out))
            return self._results(out, ids)
