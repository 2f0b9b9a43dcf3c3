"""Scene queries from numpy: the binding's answers equal the C library's,
driven through C (ref_queries.c) on scene tetra, bit for bit; filters,
refusals, and the calls run without the GIL."""
import os
import re
import sys

import numpy as np
import pytest

import hgcd
from hgcd._hgcd import lib


def same_hits(a, b):
    """Equal hits: every field bit for bit, but a generation's top byte, which
    tags the world (bodies of two worlds never compare equal)."""
    for name in ("triangle", "inside"):
        assert np.array_equal(a[name], b[name]), name
    assert a["distance"].tobytes() == b["distance"].tobytes()
    same_bodies(a["body"], b["body"])


def same_bodies(a, b):
    assert np.array_equal(a["index"], b["index"])
    assert np.array_equal(a["generation"] & 0xFFFFFF, b["generation"] & 0xFFFFFF)
    assert np.array_equal(a["generation"] == 0, b["generation"] == 0)


class Reader:
    def __init__(self, path):
        self.raw = np.fromfile(path, dtype=np.uint8)
        self.at = 0

    def take(self, dtype, count):
        dtype = np.dtype(dtype)
        out = self.raw[self.at:self.at + dtype.itemsize * count].view(dtype)
        self.at += dtype.itemsize * count
        return out

    def results(self, count):
        m = int(self.take(np.uint64, 1)[0])
        offsets = self.take(np.uint64, count + 1).astype(np.int64)
        return offsets, self.take(hgcd.BODY_ID, m)


@pytest.mark.parametrize("threads", [1, 2])
def test_queries_equal_c(ref_queries, threads):
    n, seed, side, count = 20000, 5, 60.0, 3000
    r = Reader(ref_queries(n, seed, side, threads, count))
    assert int(r.take(np.uint64, 1)[0]) == count
    rays = r.take(np.float64, 7 * count).reshape(count, 7)
    closest, any_hits = r.take(hgcd.RAY_HIT, count), r.take(hgcd.RAY_HIT, count)
    boxes = r.take(np.float64, 6 * count).reshape(count, 6)
    box_res = r.results(count)
    points = r.take(np.float64, 3 * count).reshape(count, 3)
    point_res = r.results(count)
    poses = r.take(np.float64, 8 * count).reshape(count, 8)
    mesh_res = r.results(count)
    assert r.at == len(r.raw)
    # (scenes that test something)
    assert (closest["body"]["generation"] != 0).sum() > count // 10
    assert len(box_res[1]) > count // 4 and len(mesh_res[1]) > count // 4

    with hgcd.World(threads=threads) as world:
        mesh = hgcd.scene.populate(world, n, seed, side=side)
        same_hits(world.cast_rays(rays[:, 0:3], rays[:, 3:6], rays[:, 6]), closest)
        same_hits(world.cast_rays(rays[:, 0:3], rays[:, 3:6], rays[:, 6], any_hit=True), any_hits)
        for (offsets, bodies), (want_offsets, want_bodies) in (
                (world.query_boxes(boxes, ids=True), box_res),
                (world.query_points(points, ids=True), point_res),
                (world.query_mesh(mesh, poses[:, 0:3], poses[:, 3:7], poses[:, 7], ids=True), mesh_res)):
            assert np.array_equal(offsets, want_offsets)
            same_bodies(bodies, want_bodies)
        # Indices alone by default.
        offsets, indices = world.query_boxes(boxes)
        assert indices.dtype == np.uint32 and np.array_equal(indices, box_res[1]["index"])


def cube():
    v = np.array([[x, y, z] for z in (-1.0, 1.0) for y in (-1.0, 1.0) for x in (-1.0, 1.0)])
    t = np.array([[0, 2, 1], [1, 2, 3], [4, 5, 6], [5, 7, 6], [0, 1, 4], [1, 5, 4],
                  [2, 6, 3], [3, 6, 7], [0, 4, 2], [2, 4, 6], [1, 3, 5], [3, 7, 5]], dtype=np.uint32)
    return v, t


def test_rays_boxes_points_by_hand():
    with hgcd.World(threads=2) as world:
        mesh = world.create_mesh(*cube())
        world.create_bodies(mesh, np.array([[0.0, 0, 0], [5, 0, 0]]))
        hits = world.cast_rays([[-5.0, 0, 0], [0, 0, 0], [-5, 3, 0]], [[1.0, 0, 0]] * 3, 20.0)
        assert hits["body"]["index"][0] == 0 and hits["distance"][0] == 4.0 and hits["inside"][0] == 0
        assert hits["inside"][1] == 1 and hits["distance"][1] == 0.0 and hits["triangle"][1] == 2**32 - 1
        assert hits["body"]["generation"][2] == 0  # a miss
        offsets, bodies = world.query_boxes([[-2.0, -2, -2, 2, 2, 2], [-2, -2, -2, 4.5, 2, 2], [10, 10, 10, 11, 11, 11]])
        assert offsets.tolist() == [0, 1, 3, 3] and bodies.tolist() == [0, 0, 1]
        offsets, bodies = world.query_points([[1.0, 1, 1], [5, 0, 0], [2.5, 0, 0]])
        assert offsets.tolist() == [0, 1, 2, 2] and bodies.tolist() == [0, 1]
        offsets, bodies = world.query_mesh(mesh, [[2.5, 0, 0]], scales=1.5)
        assert bodies.tolist() == [0, 1]
        # Filters: (category, mask[, group]) as a body with that filter.
        assert world.query_points([[1.0, 1, 1]], filter=(1, 0))[1].size == 0
        assert world.query_points([[1.0, 1, 1]], filter=(1, 1))[1].tolist() == [0]
        assert world.cast_rays([[-5.0, 0, 0]], [[1.0, 0, 0]], 20.0, filter=(2, 2))["body"]["generation"][0] == 0
        # A body's own filter: body 0 in group -1, a query of group -1 skips it.
        ids = world.query_points([[0.0, 0, 0], [5, 0, 0]], ids=True)[1]
        world.set_filters(ids[:1], hgcd.make_filter(group_index=-1))
        hit = world.cast_rays([[-5.0, 0, 0]], [[1.0, 0, 0]], 20.0, filter=hgcd.make_filter(group_index=-1))
        assert hit["body"]["index"][0] == 1 and hit["distance"][0] == 9.0
        world.set_enabled(ids[1:], False)
        assert world.query_boxes([[-10.0, -2, -2, 10, 2, 2]])[1].tolist() == [0]
        empty = world.cast_rays(np.empty((0, 3)), np.empty((0, 3)), 1.0)
        assert empty.shape == (0,) and empty.dtype == hgcd.RAY_HIT


def test_refusals():
    with hgcd.World(threads=1) as world:
        mesh = world.create_mesh(*cube())
        world.create_bodies(mesh, np.zeros((1, 3)))
        with pytest.raises(hgcd.Error, match="ray 1") as e:
            world.cast_rays([[0.0, 0, 0], [np.nan, 0, 0]], [[1.0, 0, 0]] * 2, 1.0)
        assert e.value.status == hgcd.Status.INVALID_ARGUMENT
        with pytest.raises(hgcd.Error, match="box 0"):
            world.query_boxes([[1.0, 0, 0, 0, 1, 1]])
        with pytest.raises(hgcd.Error, match="shape"):
            world.query_points(np.zeros((2, 2)))
        with pytest.raises(hgcd.Error, match="float64"):
            world.query_boxes(np.zeros((1, 6), dtype=np.float32))
        with pytest.raises(hgcd.Error, match="filter"):
            world.query_points([[0.0, 0, 0]], filter=(1, -1))
        with pytest.raises(hgcd.Error, match="pose 0"):
            world.query_mesh(mesh, [[0.0, 0, 0]], [[0.0, 0, 0, 2]])
        with hgcd.World() as other:
            with pytest.raises(hgcd.Error, match="another world"):
                other.query_mesh(mesh, [[0.0, 0, 0]])


def test_queries_run_without_the_gil():
    # The generated wrappers of the query calls release the GIL around them
    # (as test_lifetime checks for detect and step).
    sys.path.insert(0, os.path.join(os.path.dirname(__file__), ".."))
    try:
        import hgcd_build
    except ImportError:
        pytest.skip("hgcd_build.py is not beside the tests (an installed copy of them)")
    finally:
        sys.path.pop(0)
    out = os.path.join(os.environ.get("TMPDIR", "/tmp"), f"hgcd_gil_q_{os.getpid()}.c")
    hgcd_build.make_ffi(link=False).emit_c_code(out)
    with open(out) as f:
        code = f.read()
    os.remove(out)
    for name in ("hgcd_world_cast_rays", "hgcd_world_query_box", "hgcd_world_query_point", "hgcd_world_query_mesh"):
        body = re.search(r"_cffi_f_%s\(.*?\n}\n" % name, code, re.S).group(0)
        assert re.search(r"Py_BEGIN_ALLOW_THREADS.*\{ result = %s\(" % name, body, re.S), name
    assert lib.hgcd_py_gil_held() == 0
