"""hgcd.scene: scene tetra's arrays, its world and its motion agree."""
import numpy as np
import pytest

import hgcd


def test_unit_mesh():
    v, t = hgcd.scene.unit_mesh()
    assert v.tolist() == [[1, 1, 1], [1, -1, -1], [-1, 1, -1], [-1, -1, 1]]
    assert t.dtype == np.uint32 and t.tolist() == [[0, 1, 2], [0, 3, 1], [0, 2, 3], [1, 3, 2]]


def test_tetra_arrays_match_the_populated_world():
    n = 3000
    s = hgcd.scene.tetra(n, 5, side=40.0)
    assert s.side == 40.0 and s.centers.shape == (n, 3) and s.orientations.shape == (n, 4)
    assert np.all((s.centers >= 0) & (s.centers <= 40)) and np.all((s.radii >= 0.25) & (s.radii <= 2))
    assert np.array_equal(s.scales, s.radii / np.sqrt(3))
    assert np.array_equal(hgcd.scene.tetra(n, 5, side=40.0).centers, s.centers)  # reproducible
    assert not np.array_equal(hgcd.scene.tetra(n, 6, side=40.0).centers, s.centers)
    world, mesh = hgcd.scene.tetra_world(n, 5, threads=1, side=40.0)
    with world:
        pos, quat = world.get_poses()
        assert np.array_equal(pos, s.centers) and np.array_equal(quat, s.orientations)
        assert mesh.info().body_count == n and world.body_count == n
        # The library's step moves as hgcd.scene.move does, bit for bit.
        centers, velocities = s.centers.copy(), s.velocities.copy()
        for _ in range(3):
            world.step()
            hgcd.scene.move(centers, velocities, s.side)
        assert np.array_equal(world.get_poses()[0], centers)


def test_scene_refusals():
    with pytest.raises(hgcd.Error) as e:
        hgcd.scene.tetra(10, side=-1.0)
    assert e.value.status == hgcd.Status.INVALID_ARGUMENT
    c = np.zeros((4, 6))[:, :3]
    with pytest.raises(hgcd.Error) as e:
        hgcd.scene.move(c, np.zeros((4, 3)), 1.0)
    assert "C-contiguous" in e.value.message
    with pytest.raises(hgcd.Error):
        hgcd.scene.move(np.zeros((4, 3)), np.zeros((3, 3)), 1.0)
    with pytest.raises(hgcd.Error) as e:
        hgcd.scene.move([[0.0, 0, 0]], [[1.0, 0, 0]], 1.0)  # a list would not be moved in place
    assert "centers" in e.value.message
    for bad in (-1, 2.5):
        with pytest.raises(hgcd.Error) as e:
            hgcd.scene.tetra(bad)
        assert e.value.status == hgcd.Status.INVALID_ARGUMENT
