"""Lifetime and threads: arrays outlive their world, meshes keep it alive,
calls run without the GIL, threads sharing a world are serialised."""
import gc
import os
import re
import sys
import threading

import numpy as np
import pytest

import hgcd
from hgcd._hgcd import lib


def small_world(threads=1, contacts=False):
    world = hgcd.World(threads=threads, contacts=contacts)
    mesh = world.create_mesh(*hgcd.scene.unit_mesh())
    world.create_bodies(mesh, positions=[[0.0, 0, 0], [1, 0, 0], [1.5, 0.5, 0], [30, 0, 0]])
    world.detect()
    return world, mesh


def test_results_outlive_the_world():
    world, _ = small_world(contacts=True)
    pairs, ids, contacts = world.pairs(), world.pairs(ids=True), world.contacts()
    poses, stats = world.get_poses(), world.stats()
    expected = pairs.copy()
    world.set_poses(np.full((4, 3), 100.0) * np.arange(4)[:, None])
    world.detect()  # the world's own pair array changes ...
    assert len(world.pairs()) == 0
    assert np.array_equal(pairs, expected)  # ... the copy does not
    world.close()
    del world
    gc.collect()
    assert np.array_equal(pairs, expected) and len(ids) == len(contacts) == len(expected) > 0
    assert pairs.flags.owndata and ids.flags.owndata and contacts.flags.owndata  # numpy's memory, not the world's
    assert np.sum(ids["index"]) == np.sum(expected) and stats.colliding_pairs == len(expected)
    assert poses[0].shape == (4, 3)


def test_a_mesh_keeps_its_world_alive():
    def make():
        world, mesh = small_world()
        return mesh  # the only reference to the world

    mesh = make()
    gc.collect()
    assert mesh.alive and mesh.info().body_count == 4
    mesh.world.detect()
    assert mesh.world.pairs().tolist() == [[0, 1], [0, 2], [1, 2]]


def test_many_worlds_created_and_dropped():
    for k in range(200):
        world, _ = small_world()
        if k % 2:
            world.close()
        del world
    gc.collect()


def test_calls_run_without_the_gil():
    # The probe goes through the same kind of cffi wrapper as every call of
    # the module: the GIL is released around the C call.
    assert lib.hgcd_py_gil_held() == 0
    # And the wrappers of detect and step do release it: their generated C.
    sys.path.insert(0, os.path.join(os.path.dirname(__file__), ".."))
    try:
        import hgcd_build
    except ImportError:
        pytest.skip("hgcd_build.py is not beside the tests (an installed copy of them)")
    finally:
        sys.path.pop(0)
    source = hgcd_build.make_ffi(link=False)
    out = os.path.join(os.environ.get("TMPDIR", "/tmp"), f"hgcd_gil_{os.getpid()}.c")
    source.emit_c_code(out)
    with open(out) as f:
        code = f.read()
    os.remove(out)
    for name in ("hgcd_world_detect", "hgcd_world_step", "hgcd_world_set_poses"):
        body = re.search(r"_cffi_f_%s\(.*?\n}\n" % name, code, re.S).group(0)
        assert re.search(r"Py_BEGIN_ALLOW_THREADS.*\{ result = %s\(" % name, body, re.S), name


def test_threads_sharing_a_world_are_serialised():
    world, mesh = hgcd.scene.tetra_world(5000, 3, threads=1, side=25.0)
    errors = []

    def worker(seed):
        try:
            rng = np.random.default_rng(seed)
            for _ in range(20):
                pos, quat = world.get_poses()
                world.set_poses(pos + rng.normal(scale=0.01, size=pos.shape), quat)
                world.detect()
                pairs = world.pairs()
                assert pairs.shape[1] == 2 and np.all(pairs[:, 0] < pairs[:, 1])
        except Exception as e:  # reported below, on the main thread
            errors.append(e)

    threads = [threading.Thread(target=worker, args=(s,)) for s in range(3)]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    assert not errors, errors
    # Detecting again at the final poses gives what a fresh world gives there.
    pos, quat = world.get_poses()
    world.detect()
    final = world.pairs()
    with hgcd.World(threads=2) as fresh:
        m = fresh.create_mesh(*hgcd.scene.unit_mesh())
        fresh.create_bodies(m, pos, quat, scales=hgcd.scene.tetra(5000, 3, side=25.0).scales)
        fresh.detect()
        assert np.array_equal(fresh.pairs(), final) and len(final) > 0
    world.close()


def test_worlds_on_separate_threads():
    results = {}

    def run(k):
        world, _ = hgcd.scene.tetra_world(4000, k + 1, threads=1, side=20.0)
        with world:
            for _ in range(3):
                world.step()
            results[k] = world.pairs()

    threads = [threading.Thread(target=run, args=(k,)) for k in range(2)]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    for k in range(2):
        world, _ = hgcd.scene.tetra_world(4000, k + 1, threads=1, side=20.0)
        with world:
            for _ in range(3):
                world.step()
            assert np.array_equal(world.pairs(), results[k]) and len(results[k]) > 0
