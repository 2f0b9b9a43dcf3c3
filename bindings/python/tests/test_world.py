"""The World surface: meshes, bodies in bulk, poses and velocities in and out,
step, pairs, contacts, stats."""
import numpy as np
import pytest

import hgcd

STRAIGHT = np.array([0.0, 0.0, 0.0, 1.0])


@pytest.fixture
def world():
    with hgcd.World(threads=1) as w:
        yield w


@pytest.fixture
def tetra(world):
    return world.create_mesh(*hgcd.scene.unit_mesh())


def test_version():
    assert hgcd.version().count(".") == 2
    assert hgcd.libccd_precision() in (0, 1, 2)


def test_mesh_info_and_lifetime(world, tetra):
    info = tetra.info()
    assert (info.vertex_count, info.triangle_count, info.closed, info.convex) == (4, 4, True, True)
    assert info.radius >= np.sqrt(3) and info.body_count == 0
    assert info.narrow_phase_setting == hgcd.NarrowPhase.WORLD and info.narrow_phase == hgcd.NarrowPhase.EXACT
    assert tetra.alive and world.mesh_count == 1
    open_mesh = world.create_mesh([[0.0, 0, 0], [1, 0, 0], [0, 1, 0]], [[0, 1, 2]])  # lists are converted
    assert not open_mesh.info().closed
    bodies = world.create_bodies(tetra, count=2)
    assert tetra.info().body_count == 2
    with pytest.raises(hgcd.Error) as e:
        tetra.destroy()
    assert e.value.status == hgcd.Status.MESH_IN_USE and "mesh_destroy" in e.value.message
    world.destroy_bodies(bodies)
    tetra.destroy()
    assert not tetra.alive and world.mesh_count == 1
    with pytest.raises(hgcd.Error) as e:
        tetra.info()
    assert e.value.status == hgcd.Status.STALE_ID


def test_create_bodies_defaults_and_indices(world, tetra):
    bodies = world.create_bodies(tetra, count=3)
    assert bodies.dtype == hgcd.BODY_ID and list(bodies["index"]) == [0, 1, 2]
    assert np.all(bodies["generation"] != 0)
    pos, quat = world.get_poses()
    assert np.array_equal(pos, np.zeros((3, 3))) and np.array_equal(quat, np.tile(STRAIGHT, (3, 1)))
    vel, meshes, user = world.get_bodies(bodies)
    assert np.array_equal(vel, np.zeros((3, 3))) and np.array_equal(user, np.zeros(3, np.uint64))
    assert all((m["index"], m["generation"]) == (tetra.index, tetra.generation) for m in meshes)
    more = world.create_bodies(tetra, positions=np.arange(6.0).reshape(2, 3), user_data=np.array([7, 9], np.uint64),
                               velocities=np.ones((2, 3)), scales=np.array([0.5, 2.0]))
    assert list(more["index"]) == [3, 4] and world.body_count == 5
    vel, _, user = world.get_bodies(more)
    assert np.array_equal(vel, np.ones((2, 3))) and list(user) == [7, 9]
    assert np.array_equal(world.get_poses(more)[0], np.arange(6.0).reshape(2, 3))


def test_poses_round_trip_through_record_arrays(world, tetra):
    n = 50
    rng = np.random.default_rng(3)
    world.create_bodies(tetra, count=n)
    rec = np.zeros(n, dtype=[("id", "<u4"), ("pad", "<u4"), ("q", "<f8", 4), ("p", "<f8", 3)])
    rec["p"] = rng.uniform(-5, 5, size=(n, 3))
    q = rng.normal(size=(n, 4))
    rec["q"] = q / np.linalg.norm(q, axis=1, keepdims=True)
    world.set_poses(rec["p"], rec["q"])  # strided views, 64-byte rows
    pos, quat = world.get_poses()
    assert np.array_equal(pos, rec["p"]) and np.array_equal(quat, rec["q"])  # bit for bit
    out = np.zeros(n, dtype=rec.dtype)
    world.get_poses(positions=out["p"], orientations=out["q"])  # filled in place, strided
    assert np.array_equal(out["p"], rec["p"]) and np.array_equal(out["q"], rec["q"])
    # Positions only, on a subset of ids; orientations kept.
    ids = world.create_bodies(tetra, count=0)
    assert ids.shape == (0,)
    world.set_poses(positions=np.zeros((2, 3)))
    assert np.array_equal(world.get_poses(count=2)[0], np.zeros((2, 3)))
    assert np.array_equal(world.get_poses(count=2)[1], rec["q"][:2])


def test_strided_rows_are_passed_in_place():
    from hgcd import _arrays

    rec = np.zeros(10, dtype=[("id", "<u4"), ("pad", "<u4"), ("q", "<f8", 4), ("p", "<f8", 3)])
    p = rec["p"]
    assert _arrays.strided(p)[0] is p and _arrays.strided(p)[1] == 64  # the record's size
    pose = np.zeros((10, 7))
    cols = pose[:, 3:]
    assert _arrays.strided(cols)[0] is cols and _arrays.strided(cols)[1] == 56
    packed = np.zeros((10, 3))
    assert _arrays.strided(packed) == (packed, 0)
    for copied in (np.zeros((3, 10)).T, packed[::-1], np.zeros((10, 6))[:, ::2], np.broadcast_to(np.zeros(3), (10, 3))):
        arr, stride = _arrays.strided(copied)
        assert arr is not copied and stride == 0 and arr.flags.c_contiguous and np.array_equal(arr, copied)


def test_velocities_and_step(tetra):
    with hgcd.World(threads=1, time_step=0.5, bounds=((0, 0, 0), (10, 10, 10))) as world:
        mesh = world.create_mesh(*hgcd.scene.unit_mesh())
        bodies = world.create_bodies(mesh, positions=[[2.0, 5, 5], [8, 5, 5]])
        world.set_velocities(np.array([[2.0, 0, 0], [-2, 0, 0]]))
        world.step()
        assert np.array_equal(world.get_poses()[0][:, 0], [3.0, 7.0])
        assert len(world.pairs()) == 0
        world.step()
        world.step()
        assert np.array_equal(world.get_poses()[0][:, 0], [5.0, 5.0])
        assert world.pairs().tolist() == [[0, 1]]
        assert np.array_equal(world.pairs(ids=True), bodies.reshape(1, 2))
        st = world.stats()
        assert st.colliding_pairs == 1 and st.thread_count == 1 and st.total_seconds >= 0
        world.set_velocities(np.array([[-9.0, 0, 0]]), bodies=bodies[:1])
        world.step()  # 5 - 4.5 = 0.5, inside the box
        world.step()  # 0.5 - 4.5 reflected at 0: 4.0, velocity flipped
        assert world.get_poses(bodies[:1])[0][0, 0] == 4.0
        assert world.get_velocities(bodies[:1])[0, 0] == 9.0


def test_pairs_sorted_contacts_and_containment():
    with hgcd.World(threads=2, contacts=True) as world:
        tetra = world.create_mesh(*hgcd.scene.unit_mesh())
        world.create_bodies(tetra, positions=[[0.0, 0, 0], [1, 0, 0], [20, 0, 0], [-0.5, 0, 0]],
                            scales=[1.0, 1.0, 1.0, 0.05])
        world.detect()
        pairs = world.pairs()
        assert pairs.tolist() == [[0, 1], [0, 3]] and pairs.flags.c_contiguous
        contacts = world.contacts()
        assert contacts.dtype == hgcd.CONTACT and len(contacts) == 2
        assert np.array_equal(contacts["a"]["index"], pairs[:, 0])
        assert np.array_equal(contacts["b"]["index"], pairs[:, 1])
        assert contacts["kind"][0] == hgcd.ContactKind.SURFACE
        assert contacts["triangle_a"][0] < 4 and contacts["triangle_b"][0] < 4
        assert contacts["kind"][1] == hgcd.ContactKind.A_CONTAINS_B  # body 3 is inside body 0
        assert world.stats().containment_pairs == 1
        world.set_contacts(False)
        world.detect()
        with pytest.raises(hgcd.Error) as e:
            world.contacts()
        assert e.value.status == hgcd.Status.INVALID_ARGUMENT and "contacts off" in e.value.message


def test_settings(world, tetra):
    world.set_thread_policy(hgcd.ThreadPolicy.FIXED)  # 2 threads every detect, busy cores or not
    world.set_thread_count(2)
    world.create_bodies(tetra, positions=[[0.0, 0, 0], [1, 0, 0]])
    world.detect()
    assert world.stats().thread_count == 2
    if hgcd.libccd_precision():
        world.set_narrow_phase(hgcd.NarrowPhase.GJK)
        tetra.set_narrow_phase(hgcd.NarrowPhase.MPR)
        assert tetra.info().narrow_phase == hgcd.NarrowPhase.MPR
    else:
        with pytest.raises(hgcd.Error) as e:
            world.set_narrow_phase(hgcd.NarrowPhase.GJK)
        assert e.value.status == hgcd.Status.NOT_SUPPORTED
    world.detect()
    assert world.pairs().tolist() == [[0, 1]]
    assert "bodies=2" in repr(world)
