"""Misuse: wrong dtypes and shapes refused in Python, the library's refusals as
hgcd.Error with status and message, and a refused call changing nothing."""
import numpy as np
import pytest

import hgcd


@pytest.fixture
def world():
    with hgcd.World(threads=1) as w:
        mesh = w.create_mesh(*hgcd.scene.unit_mesh())
        w.create_bodies(mesh, positions=np.arange(9.0).reshape(3, 3) * 10)
        w.mesh = mesh
        yield w


def refused(call, status, *words):
    with pytest.raises(hgcd.Error) as e:
        call()
    assert e.value.status == status, e.value
    for w in words:
        assert w in e.value.message, e.value.message
    assert e.value.name == "HGCD_" + ("OK" if status == 0 else "ERROR_" + hgcd.Status(status).name)
    return e.value


INVALID = hgcd.Status.INVALID_ARGUMENT


def test_dtypes_refused_before_c(world):
    v, t = hgcd.scene.unit_mesh()
    refused(lambda: world.create_mesh(v.astype(np.float32), t), INVALID, "vertices", "float64", "float32")
    refused(lambda: world.create_mesh(v, t.astype(np.int64)), INVALID, "triangles", "uint32", "int64")
    refused(lambda: world.set_poses(np.zeros((3, 3), np.float32)), INVALID, "positions", "float64")
    refused(lambda: world.set_velocities(np.zeros((3, 3), ">f8")), INVALID, "velocities")
    refused(lambda: world.create_bodies(world.mesh, user_data=np.zeros(2, np.int64)), INVALID, "user_data",
            "uint64")
    refused(lambda: world.set_poses(np.zeros((3, 3)), bodies=np.zeros(3, np.uint64)), INVALID, "bodies")
    refused(lambda: world.set_poses(["a", "b", "c"]), INVALID, "positions", "convertible")
    assert world.last_error == ""  # none of these reached the library


def test_shapes_refused_before_c(world):
    v, t = hgcd.scene.unit_mesh()
    refused(lambda: world.create_mesh(v.reshape(-1), t), INVALID, "vertices", "(N, 3)", "(12,)")
    refused(lambda: world.create_mesh(v, t[:, :2]), INVALID, "triangles", "(N, 3)")
    refused(lambda: world.set_poses(np.zeros((3, 4))), INVALID, "positions", "(N, 3)")
    refused(lambda: world.set_poses(np.zeros((3, 3)), np.zeros((2, 4))), INVALID, "orientations", "(3, 4)")
    refused(lambda: world.set_poses(np.zeros((3, 3, 1))), INVALID, "positions")
    refused(lambda: world.create_bodies(world.mesh, np.zeros((2, 3)), scales=np.ones(3)), INVALID, "scales",
            "(2,)")
    refused(lambda: world.get_poses(positions=np.zeros((3, 3), np.float32)), INVALID, "positions")
    refused(lambda: world.get_poses(positions=np.zeros((3, 6))[:, ::2]), INVALID, "positions", "packed")
    readonly = np.zeros((3, 3))
    readonly.flags.writeable = False
    refused(lambda: world.get_poses(positions=readonly), INVALID, "writeable")
    refused(lambda: world.set_poses(), hgcd.Status.NULL_ARGUMENT, "set_poses")
    refused(lambda: world.create_bodies(world.mesh), INVALID, "count")
    refused(lambda: world.create_bodies(world.mesh, count=-1), INVALID, "count")
    refused(lambda: world.create_bodies(world.mesh, positions=3.0), INVALID, "sequences")
    refused(lambda: world.get_poses(count=-2), INVALID, "count")
    assert world.last_error == ""


def test_library_refusals_carry_status_and_message(world):
    before = world.get_poses()
    bad = np.zeros((3, 3))
    bad[2, 1] = np.nan
    e = refused(lambda: world.set_poses(bad), INVALID, "set_poses", "entry 2", "position[1]")
    assert str(e).endswith("(HGCD_ERROR_INVALID_ARGUMENT)")
    assert world.last_error == e.message
    quats = np.tile([0.0, 0, 0, 1], (3, 1))
    quats[1, 3] = 2.0  # not unit length
    refused(lambda: world.set_poses(np.ones((3, 3)), quats), INVALID, "entry 1")
    after = world.get_poses()
    assert np.array_equal(before[0], after[0]) and np.array_equal(before[1], after[1])  # nothing moved
    refused(lambda: world.set_poses(np.zeros((4, 3))), hgcd.Status.STALE_ID, "3")  # no body of index 3
    refused(lambda: world.set_thread_count(5000), INVALID, "thread")
    refused(lambda: world.set_thread_count(-1), INVALID, "threads")
    refused(lambda: world.create_mesh([[0.0, 0, 0]], [[0, 0, 1]]), hgcd.Status.INVALID_MESH, "mesh_create")
    refused(lambda: world.create_mesh(np.zeros((0, 3)), np.zeros((0, 3), np.uint32)), hgcd.Status.INVALID_MESH)
    refused(lambda: hgcd.World(threads=1, time_step=-1.0), INVALID, "world_create")
    refused(lambda: hgcd.World(bounds=((0, 0, 0), (1, 1))), INVALID, "bounds[1]", "(3,)")
    refused(lambda: hgcd.World(narrow_phase=7), INVALID, "world_create", "NarrowPhase")
    refused(lambda: world.set_narrow_phase(7), INVALID, "set_narrow_phase")
    refused(lambda: world.set_thread_policy(2), INVALID, "set_thread_policy", "ThreadPolicy")
    refused(lambda: hgcd.World(thread_policy=-1), INVALID, "world_create", "ThreadPolicy")
    refused(lambda: world.set_narrow_phase(hgcd.NarrowPhase.WORLD), INVALID, "narrow_phase")
    refused(lambda: world.mesh.set_narrow_phase(-5), INVALID, "NarrowPhase")


def test_errors_pickle(world):
    import pickle

    e = refused(lambda: world.set_poses(np.full((3, 3), np.nan)), INVALID)
    back = pickle.loads(pickle.dumps(e))
    assert (back.status, back.name, back.message, str(back)) == (e.status, e.name, e.message, str(e))


def test_stale_and_foreign_ids(world):
    bodies = world.create_bodies(world.mesh, count=2)
    world.destroy_bodies(bodies[:1])
    assert world.bodies_alive(bodies).tolist() == [False, True]
    refused(lambda: world.set_poses(np.zeros((1, 3)), bodies=bodies[:1]), hgcd.Status.STALE_ID)
    refused(lambda: world.destroy_bodies(bodies), hgcd.Status.STALE_ID, "entry 0")
    assert world.bodies_alive(bodies[1:]).all()  # the refused destroy destroyed nothing
    refused(lambda: world.destroy_bodies(np.concatenate([bodies[1:], bodies[1:]])), INVALID, "twice")
    refused(lambda: world.get_bodies(bodies), hgcd.Status.STALE_ID, "get_bodies", "entry 0")
    with hgcd.World() as other:
        refused(lambda: other.create_bodies(world.mesh, count=1), hgcd.Status.STALE_ID, "another world")
        refused(lambda: other.create_bodies([world.mesh], count=1), hgcd.Status.STALE_ID, "another world")
        assert other.body_count == 0


def test_failed_bulk_create_leaves_the_world_as_it_was(world):
    count = world.body_count
    positions = np.zeros((5, 3))
    positions[3, 0] = np.inf
    e = refused(lambda: world.create_bodies(world.mesh, positions), INVALID, "create_bodies: entry 3",
                "position[0]")
    assert "body_create" in e.message
    assert world.body_count == count
    again = world.create_bodies(world.mesh, np.zeros((5, 3)))
    assert list(again["index"]) == list(range(count, count + 5))  # the slots came back in order


def test_closed_world(world):
    mesh = world.mesh
    world.close()
    world.close()  # a second close does nothing
    assert world.closed and repr(world) == "hgcd.World(closed)"
    for call in (world.detect, world.step, world.pairs, world.stats, lambda: world.body_count,
                 lambda: world.set_poses(np.zeros((1, 3))), mesh.info, mesh.destroy,
                 lambda: world.create_mesh(*hgcd.scene.unit_mesh())):
        refused(call, hgcd.Status.NULL_ARGUMENT, "closed")
    assert not mesh.alive
