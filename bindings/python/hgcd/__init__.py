"""hgcd: exact collision detection between many rigid triangle meshes, from numpy.

    import numpy as np, hgcd

    with hgcd.World() as world:
        v, t = hgcd.scene.unit_mesh()                 # (4, 3) float64, (4, 3) uint32
        mesh = world.create_mesh(v, t)
        bodies = world.create_bodies(mesh, positions=np.array([[0., 0, 0], [1, 0, 0], [10, 0, 0]]))
        world.detect()
        world.pairs()                                 # array([[0, 1]], dtype=uint32)

Whole arrays go in and come out: bodies are created, posed and read in bulk,
pairs come back as an (N, 2) array of body indices. Errors raise hgcd.Error
(status and the library's message). See bindings/python/README.md.
"""
from . import scene
from ._arrays import BODY_ID, MESH_ID
from ._errors import Error, Status
from ._hgcd import ffi as _ffi
from ._hgcd import lib as _lib
from ._features import make_filter
from ._queries import RAY_HIT
from ._types import CONTACT, FILTER, PAIR_EVENT, BodyType, ContactKind, MeshInfo, NarrowPhase, Stats, ThreadPolicy
from ._world import Mesh, World

__all__ = ["World", "Mesh", "Error", "Status", "NarrowPhase", "ThreadPolicy", "ContactKind", "Stats", "MeshInfo",
           "BodyType", "make_filter", "BODY_ID", "MESH_ID", "CONTACT", "FILTER", "PAIR_EVENT", "RAY_HIT", "scene",
           "version", "libccd_precision"]


def version():
    """The linked library's version string, e.g. "0.1.0"."""
    return _ffi.string(_lib.hgcd_version_string()).decode()


def libccd_precision():
    """libccd compiled in: 0 none (GJK/MPR raise NOT_SUPPORTED), 1 float, 2 double."""
    return int(_lib.hgcd_feature_libccd())
