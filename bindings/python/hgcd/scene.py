"""Scene `tetra` of docs/scenes.md, bit for bit (the C support library
libhgcd_scene): many tetrahedra of log-uniform sizes moving in a cube.

    scene = hgcd.scene.tetra(200_000)            # arrays of the scene
    world, mesh = hgcd.scene.tetra_world(200_000, threads=1)
"""
import dataclasses

import numpy as np

from . import _arrays as A
from ._errors import Error, argument_error
from ._hgcd import ffi, lib
from ._world import Mesh, World


@dataclasses.dataclass
class Tetra:
    """The n objects of scene tetra: centers (n, 3), radii (n,) circumradii,
    scales (n,) (r / sqrt(3), the body scale for unit_mesh()), orientations
    (n, 4) (x, y, z, w) and velocities (n, 3), and the side of the cube."""

    centers: np.ndarray
    radii: np.ndarray
    scales: np.ndarray
    orientations: np.ndarray
    velocities: np.ndarray
    side: float


def _desc(n, seed, side, rmin, rmax, vmax):
    d = ffi.new("hgcd_scene_tetra_desc *", lib.hgcd_scene_tetra_desc_default())
    try:
        d.n = n
        d.seed = seed
        for name, value in (("side", side), ("rmin", rmin), ("rmax", rmax), ("vmax", vmax)):
            if value is not None:
                setattr(d, name, value)
    except (TypeError, OverflowError) as e:
        raise argument_error(f"scene_tetra: {e}") from None
    return d


def tetra(n, seed=1, *, side=None, rmin=None, rmax=None, vmax=None):
    """Draws scene tetra (hgcd_scene_tetra_generate); None keeps the scene's
    default (side 200, radii 0.25 .. 2, speed 0.05)."""
    d = _desc(n, seed, side, rmin, rmax, vmax)
    s = Tetra(np.empty((n, 3)), np.empty(n), np.empty(n), np.empty((n, 4)), np.empty((n, 3)), d.side)
    status = lib.hgcd_scene_tetra_generate(d, *(A.ptr("double *", a) for a in
                                                (s.centers, s.radii, s.scales, s.orientations, s.velocities)))
    if status != lib.HGCD_OK:
        raise Error(status, "scene_tetra_generate: refused (n, or side and radii out of order)")
    return s


def unit_mesh():
    """(vertices (4, 3) float64, triangles (4, 3) uint32) of the unit tetrahedron."""
    v = np.empty((4, 3))
    t = np.empty((4, 3), dtype=np.uint32)
    lib.hgcd_scene_tetra_unit_mesh(A.ptr("double *", v), A.ptr("uint32_t *", t))
    return v, t


def move(centers, velocities, side):
    """One tick of the scene's motion, in place (hgcd_scene_tetra_move): centers
    += velocities, mirrored back into [0, side] with that velocity negated.
    Both arrays (n, 3) float64, C-contiguous and writeable."""
    for arr, what in ((centers, "centers"), (velocities, "velocities")):
        if not (isinstance(arr, np.ndarray) and arr.flags.c_contiguous and arr.flags.writeable):
            raise argument_error(f"scene_tetra_move: {what} must be a C-contiguous, writeable array")
    c = A.rows(centers, 3, None, "centers", "scene_tetra_move")
    v = A.rows(velocities, 3, c.shape[0], "velocities", "scene_tetra_move")
    lib.hgcd_scene_tetra_move(c.shape[0], side, A.ptr("double *", c), A.ptr("double *", v))


def populate(world, n, seed=1, *, side=None, rmin=None, rmax=None, vmax=None):
    """Puts scene tetra into world (hgcd_scene_tetra_populate): one unit mesh
    and n bodies, body i the scene's object i with user_data i. Returns the
    Mesh. On failure the world holds nothing of the call."""
    d = _desc(n, seed, side, rmin, rmax, vmax)
    out = ffi.new("hgcd_mesh *")
    with world._lock:
        status = lib.hgcd_scene_tetra_populate(world._live(), d, out)
        world._check(status, "scene_tetra_populate: ")
    return Mesh(world, out[0])


def tetra_world(n, seed=1, *, threads=0, side=None, **world_args):
    """A World reflecting at the scene's cube [0, side]^3 holding scene tetra,
    as the benchmarks make it: (world, mesh)."""
    s = _desc(1, seed, side, None, None, None).side
    world = World(threads=threads, bounds=((0, 0, 0), (s, s, s)), **world_args)
    try:
        return world, populate(world, n, seed, side=side)
    except BaseException:
        world.close()
        raise
