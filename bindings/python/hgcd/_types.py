"""The plain result types: enums, Stats, MeshInfo and the contact, filter and event dtypes."""
import dataclasses
import enum

import numpy as np

from ._arrays import BODY_ID
from ._hgcd import ffi, lib


class NarrowPhase(enum.IntEnum):
    """Which test decides a candidate pair (enum hgcd_narrow_phase)."""

    WORLD = lib.HGCD_NARROW_WORLD  # per mesh only: follow the world
    EXACT = lib.HGCD_NARROW_EXACT
    GJK = lib.HGCD_NARROW_GJK
    MPR = lib.HGCD_NARROW_MPR


class ThreadPolicy(enum.IntEnum):
    """How many of its threads a world uses (enum hgcd_thread_policy)."""

    ADAPTIVE = lib.HGCD_THREADS_ADAPTIVE  # fewer while the cores are busy with other work
    FIXED = lib.HGCD_THREADS_FIXED  # always the thread count


class BodyType(enum.IntEnum):
    """How a body moves and which pairs it takes part in (enum hgcd_body_type)."""

    DYNAMIC = lib.HGCD_BODY_DYNAMIC  # moves every tick (the default)
    KINEMATIC = lib.HGCD_BODY_KINEMATIC  # moved by the caller; pairs with kinematic/static only if asked
    STATIC = lib.HGCD_BODY_STATIC  # level geometry: static-static pairs are never searched


class ContactKind(enum.IntEnum):
    """What a colliding pair is made of (enum hgcd_contact_kind)."""

    SURFACE = lib.HGCD_CONTACT_SURFACE
    A_CONTAINS_B = lib.HGCD_CONTACT_A_CONTAINS_B
    B_CONTAINS_A = lib.HGCD_CONTACT_B_CONTAINS_A
    PENETRATION = lib.HGCD_CONTACT_PENETRATION


def _from_struct(cls, c_struct):
    """cls filled from the C struct's fields of the same names (C arrays as tuples)."""
    values = {}
    for f in dataclasses.fields(cls):
        v = getattr(c_struct, f.name)
        values[f.name] = tuple(v) if isinstance(v, ffi.CData) else v
    return cls(**values)


@dataclasses.dataclass(frozen=True)
class Stats:
    """Statistics of the last step/detect (hgcd_stats; see hgcd.h for each
    field). Counts and times are zero before the first detect."""

    level_count: int
    oversize_count: int
    thread_count: int
    moved_bodies: int
    candidate_pairs: int
    narrow_tests: int
    triangle_tests: int
    colliding_pairs: int
    containment_pairs: int
    motion_seconds: float
    update_seconds: float
    broad_seconds: float
    narrow_seconds: float
    total_seconds: float
    libccd_tests: int
    libccd_fallback_tests: int
    unmoved_pairs: int
    searched_bodies: int
    filtered_pairs: int
    events_seconds: float


@dataclasses.dataclass(frozen=True)
class MeshInfo:
    """What hgcd worked out about a mesh (hgcd_mesh_info; see hgcd.h)."""

    vertex_count: int
    triangle_count: int
    closed: bool
    convex: bool
    component_count: int
    degenerate_triangle_count: int
    body_count: int
    center: tuple
    radius: float
    narrow_phase_setting: NarrowPhase
    narrow_phase: NarrowPhase
    reach: float


def stats_from_c(c):
    return _from_struct(Stats, c)


def mesh_info_from_c(c):
    info = _from_struct(MeshInfo, c)
    return dataclasses.replace(info, closed=bool(info.closed), convex=bool(info.convex),
                               narrow_phase_setting=NarrowPhase(info.narrow_phase_setting),
                               narrow_phase=NarrowPhase(info.narrow_phase))


def _contact_dtype():
    """numpy's view of hgcd_contact: offsets and size from the compiled header."""
    off = lambda f: ffi.offsetof("hgcd_contact", f)  # noqa: E731
    return np.dtype({
        "names": ["a", "b", "kind", "triangle_a", "triangle_b", "depth", "normal", "point"],
        "formats": [BODY_ID, BODY_ID, "<i4", "<u4", "<u4", "<f8", ("<f8", 3), ("<f8", 3)],
        "offsets": [off("pair") + ffi.offsetof("hgcd_pair", "a"), off("pair") + ffi.offsetof("hgcd_pair", "b"),
                    off("kind"), off("triangle_a"), off("triangle_b"), off("depth"), off("normal"),
                    off("point")],
        "itemsize": ffi.sizeof("hgcd_contact"),
    })


#: dtype of World.contacts(): fields a, b (BODY_ID), kind (ContactKind values),
#: triangle_a, triangle_b, depth, normal (3), point (3), as hgcd_contact.
CONTACT = _contact_dtype()


def _struct_dtype(ctype, fields):
    """numpy's view of a C struct: (name, format, C field path) with the
    offsets and size of the compiled header."""
    def off(path):
        return sum(ffi.offsetof(t, f) for t, f in path)
    return np.dtype({"names": [f[0] for f in fields], "formats": [f[1] for f in fields],
                     "offsets": [off(f[2]) for f in fields], "itemsize": ffi.sizeof(ctype)})


#: dtype of a body's filter (hgcd_filter, Box2D v3's semantics): category_bits,
#: mask_bits (uint64), group_index (int32), reserved (uint32, must be 0).
FILTER = _struct_dtype("hgcd_filter", [
    ("category_bits", "<u8", [("hgcd_filter", "category_bits")]),
    ("mask_bits", "<u8", [("hgcd_filter", "mask_bits")]),
    ("group_index", "<i4", [("hgcd_filter", "group_index")]),
    ("reserved", "<u4", [("hgcd_filter", "reserved")])])

#: dtype of World.events(): a, b (BODY_ID, a.index < b.index), user_data_a,
#: user_data_b (uint64), as hgcd_pair_event.
PAIR_EVENT = _struct_dtype("hgcd_pair_event", [
    ("a", BODY_ID, [("hgcd_pair_event", "pair"), ("hgcd_pair", "a")]),
    ("b", BODY_ID, [("hgcd_pair_event", "pair"), ("hgcd_pair", "b")]),
    ("user_data_a", "<u8", [("hgcd_pair_event", "user_data_a")]),
    ("user_data_b", "<u8", [("hgcd_pair_event", "user_data_b")])])
