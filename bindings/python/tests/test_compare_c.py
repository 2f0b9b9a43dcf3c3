"""The binding's pairs equal the C library's, driven through C one call per body
(ref_pairs.c): scene tetra and random scenes of mixed meshes."""
import numpy as np
import pytest

import hgcd

RECORD = np.dtype([("pos", "<f8", 3), ("vel", "<f8", 3), ("quat", "<f8", 4), ("tag", "<u8")])


def tetra_engine_pairs(n, seed, side, ticks, threads):
    """Scene tetra driven as an engine does: the caller moves its own record
    array (hgcd.scene.move) and hands the poses over in one strided call."""
    s = hgcd.scene.tetra(n, seed, side=side)
    state = np.zeros(n, dtype=RECORD)
    state["pos"], state["vel"], state["quat"] = s.centers, s.velocities, s.orientations
    centers, velocities = s.centers.copy(), s.velocities.copy()
    with hgcd.World(threads=threads) as world:
        mesh = world.create_mesh(*hgcd.scene.unit_mesh())
        bodies = world.create_bodies(mesh, state["pos"], state["quat"], state["vel"], s.scales)
        assert np.array_equal(bodies["index"], np.arange(n))
        world.detect()
        result = [world.pairs()]
        for _ in range(ticks):
            hgcd.scene.move(centers, velocities, side)
            state["pos"] = centers
            world.set_poses(state["pos"], state["quat"])  # rows 88 bytes apart, read in place
            world.detect()
            result.append(world.pairs())
    return result


def tetra_step_pairs(n, seed, side, ticks, threads):
    """Scene tetra moved by the library: hgcd.scene.tetra_world and step()."""
    world, _ = hgcd.scene.tetra_world(n, seed, threads=threads, side=side)
    with world:
        world.detect()
        result = [world.pairs()]
        for _ in range(ticks):
            world.step()
            result.append(world.pairs())
    return result


@pytest.mark.parametrize("threads", [1, 2])
def test_tetra_pairs_equal_c(ref_pairs, threads):
    n, seed, side, ticks = 20000, 7, 60.0, 3
    expected = ref_pairs("tetra", n, seed, side, ticks, threads)
    assert len(expected) == ticks + 1 and all(len(p) > 1000 for p in expected)
    for got in (tetra_engine_pairs(n, seed, side, ticks, threads), tetra_step_pairs(n, seed, side, ticks, threads)):
        assert len(got) == len(expected)
        for g, e in zip(got, expected):
            assert g.dtype == np.uint32 and g.shape == e.shape
            assert np.array_equal(g, e)


def random_meshes(rng):
    """A tetrahedron, a cube, a jittered octahedron (closed) and an open soup
    with a degenerate triangle."""
    tetra = hgcd.scene.unit_mesh()
    corners = np.array([[x, y, z] for x in (-1.0, 1) for y in (-1.0, 1) for z in (-1.0, 1)])
    cube_t = np.array([[0, 1, 3], [0, 3, 2], [4, 6, 7], [4, 7, 5], [0, 4, 5], [0, 5, 1],
                       [2, 3, 7], [2, 7, 6], [0, 2, 6], [0, 6, 4], [1, 5, 7], [1, 7, 3]], dtype=np.uint32)
    octa_v = np.array([[1.0, 0, 0], [-1, 0, 0], [0, 1, 0], [0, -1, 0], [0, 0, 1], [0, 0, -1]])
    octa_v *= rng.uniform(0.6, 1.4, size=(6, 1))
    octa_t = np.array([[0, 2, 4], [2, 1, 4], [1, 3, 4], [3, 0, 4], [2, 0, 5], [1, 2, 5], [3, 1, 5],
                       [0, 3, 5]], dtype=np.uint32)
    soup_v = rng.uniform(-1, 1, size=(15, 3))
    soup_t = rng.integers(0, 15, size=(8, 3)).astype(np.uint32)
    soup_t[0] = [3, 3, 7]  # a segment
    return [tetra, (corners, cube_t), (octa_v, octa_t), (soup_v, soup_t)]


def random_quaternions(rng, n):
    q = rng.normal(size=(n, 4))
    return q / np.linalg.norm(q, axis=1, keepdims=True)


def write_scene(path, meshes, mesh_of, positions, orientations, scales, ticks):
    with open(path, "wb") as f:
        u64 = lambda v: f.write(np.uint64(v).tobytes())  # noqa: E731
        u64(len(meshes))
        for v, t in meshes:
            u64(len(v))
            u64(len(t))
            f.write(np.ascontiguousarray(v, "<f8").tobytes())
            f.write(np.ascontiguousarray(t, "<u4").tobytes())
        u64(len(mesh_of))
        for k in range(len(mesh_of)):
            u64(mesh_of[k])
            f.write(np.concatenate([positions[k], orientations[k], [scales[k]]]).astype("<f8").tobytes())
        u64(len(ticks))
        for pos, quat in ticks:
            f.write(np.hstack([pos, quat]).astype("<f8").tobytes())


@pytest.mark.parametrize("seed", [1, 2, 3, 4])
def test_random_scene_pairs_equal_c(ref_pairs, tmp_path, seed):
    rng = np.random.default_rng(seed)
    n = 400
    meshes = random_meshes(rng)
    mesh_of = rng.integers(0, len(meshes), size=n)
    positions = rng.uniform(0, 8, size=(n, 3))
    orientations = random_quaternions(rng, n)
    scales = rng.uniform(0.2, 1.5, size=n)
    ticks = [(positions + rng.normal(scale=0.3, size=(n, 3)), random_quaternions(rng, n)) for _ in range(3)]
    path = tmp_path / "scene.bin"
    write_scene(path, meshes, mesh_of, positions, orientations, scales, ticks)
    expected = ref_pairs("scene", path, 2)

    with hgcd.World(threads=1) as world:
        handles = [world.create_mesh(v, t) for v, t in meshes]
        bodies = world.create_bodies([handles[m] for m in mesh_of], positions, orientations, scales=scales)
        world.detect()
        got = [world.pairs()]
        for k, (pos, quat) in enumerate(ticks):
            if k % 2:  # by id, in a shuffled order
                order = rng.permutation(n)
                world.set_poses(pos[order], quat[order], bodies=bodies[order])
            else:  # by index, orientations given as the columns of one (n, 7) array
                pose = np.hstack([pos, quat])
                world.set_poses(pose[:, :3], pose[:, 3:])
            world.detect()
            got.append(world.pairs())
        stats = world.stats()
    assert len(got) == len(expected) == 4
    assert sum(len(p) for p in expected) > 100
    for g, e in zip(got, expected):
        assert np.array_equal(g, e)
    assert stats.colliding_pairs == len(got[-1])
