"""Body types, enabling, filters, pair exclusions and events from Python,
checked against a model written here: the pairs of the same world with every
feature off, kept or dropped by the documented rules (Box2D v3's filter,
the type table, exclusions), and events as the difference of consecutive
pair sets."""
from fractions import Fraction

import numpy as np
import pytest

import hgcd

ALL = 2**64 - 1


def dense_scene(rng, n):
    """n unit tetrahedra at random in a cube small enough that most touch others."""
    return rng.uniform(0.0, 2.5 * n ** (1 / 3), (n, 3))


def model_pairs(raw, types, enabled, filters, excluded, kinematic_pairs):
    """The pairs of raw (all touching pairs, index pairs) that the rules keep."""
    keep = []
    for a, b in raw:
        if not (enabled[a] and enabled[b]) or (a, b) in excluded:
            continue
        ta, tb = sorted((types[a], types[b]))
        if tb == hgcd.BodyType.STATIC and ta != hgcd.BodyType.DYNAMIC:
            if ta == hgcd.BodyType.STATIC or not kinematic_pairs:
                continue
        if ta == tb == hgcd.BodyType.KINEMATIC and not kinematic_pairs:
            continue
        fa, fb = filters[a], filters[b]
        if fa["group_index"] == fb["group_index"] != 0:
            if fa["group_index"] < 0:
                continue
        elif not (int(fa["mask_bits"]) & int(fb["category_bits"]) and int(fa["category_bits"]) & int(fb["mask_bits"])):
            continue
        keep.append((a, b))
    return keep


def random_filters(rng, n):
    f = np.zeros(n, dtype=hgcd.FILTER)
    f["category_bits"] = 1 << rng.integers(0, 3, n)
    f["mask_bits"] = rng.choice(np.array([ALL, 1, 3, 6], dtype=np.uint64), n)
    f["group_index"] = rng.choice([0, 0, 0, 1, -1, 2], n)
    return f


@pytest.mark.parametrize("kinematic_pairs", [False, True])
def test_features_equal_the_model(kinematic_pairs):
    rng = np.random.default_rng(7 + kinematic_pairs)
    n = 240
    positions = dense_scene(rng, n)
    user = rng.integers(0, 2**63, n).astype(np.uint64)
    with hgcd.World(threads=2) as plain, hgcd.World(threads=2, kinematic_pairs=kinematic_pairs) as world:
        for w in (plain, world):
            mesh = w.create_mesh(*hgcd.scene.unit_mesh())
            bodies = w.create_bodies(mesh, positions=positions, user_data=user)
        previous = set()
        for tick in range(6):
            types = rng.integers(0, 3, n).astype(np.int32)
            enabled = rng.random(n) > 0.1
            filters = random_filters(rng, n)
            world.set_types(bodies, types)
            world.set_enabled(bodies, enabled)
            world.set_filters(bodies, filters)
            plain.detect()
            raw = [tuple(p) for p in plain.pairs()]
            pick = rng.choice(len(raw), size=min(len(raw), 15), replace=False) if raw else []
            excluded = {raw[k] for k in pick}
            world.include_pairs(np.array([[bodies[a], bodies[b]] for a, b in raw]))
            world.exclude_pairs(np.array([[bodies[a], bodies[b]] for a, b in excluded]).reshape(-1, 2))
            world.detect()
            want = model_pairs(raw, types, enabled, filters, excluded, kinematic_pairs)
            got = [tuple(p) for p in world.pairs()]
            assert got == want and len(want) > 0
            t, e, f = world.get_body_flags(bodies)
            assert np.array_equal(t, types) and np.array_equal(e, enabled) and np.array_equal(f, filters)
            began, ended = world.events()
            now = set(want)
            for events, expected in ((began, now - previous), (ended, previous - now)):
                assert [(int(x["a"]["index"]), int(x["b"]["index"])) for x in events] == sorted(expected)
                assert np.array_equal(events["user_data_a"], user[events["a"]["index"]])
                assert np.array_equal(events["user_data_b"], user[events["b"]["index"]])
            assert world.stats().filtered_pairs > 0
            previous = now
            moved = rng.uniform(-0.3, 0.3, (n, 3))
            for w in (plain, world):
                w.set_poses(positions + moved)


def test_create_bodies_with_types_and_filters():
    with hgcd.World(threads=1) as w:
        mesh = w.create_mesh(*hgcd.scene.unit_mesh())
        ground = w.create_bodies(mesh, positions=np.zeros((3, 3)), types=hgcd.BodyType.STATIC)
        w.detect()
        assert len(w.pairs()) == 0  # static-static: never
        ghost = w.create_bodies(mesh, count=1, enabled=False, filters=hgcd.make_filter(group_index=-1))
        mover = w.create_bodies(mesh, count=2, filters=np.array([hgcd.make_filter(group_index=-1)] * 2))
        w.detect()
        # 4-5 share a negative group, 3 is disabled, 0-2 are static.
        assert w.pairs().tolist() == [[0, 4], [0, 5], [1, 4], [1, 5], [2, 4], [2, 5]]
        types, enabled, filters = w.get_body_flags(np.concatenate([ground, ghost, mover]))
        assert types.tolist() == [2, 2, 2, 0, 0, 0] and enabled.tolist() == [True] * 3 + [False] + [True] * 2
        assert filters["group_index"].tolist() == [0, 0, 0, -1, -1, -1]
        w.set_enabled(ghost, True)
        w.detect()
        assert [3, 4] not in w.pairs().tolist() and [0, 3] in w.pairs().tolist()
        began, ended = w.events()
        assert [int(x["a"]["index"]) for x in began] == [0, 1, 2] and len(ended) == 0
        w.destroy_bodies(mover[:1])
        w.detect()
        began, ended = w.events()
        assert len(began) == 0 and [(int(x["a"]["index"]), int(x["b"]["index"])) for x in ended] == [(0, 4), (1, 4),
                                                                                                       (2, 4)]


def test_refusals_change_nothing():
    with hgcd.World(threads=1) as w:
        mesh = w.create_mesh(*hgcd.scene.unit_mesh())
        bodies = w.create_bodies(mesh, count=4)
        gone = w.create_bodies(mesh, count=1)
        w.destroy_bodies(gone)
        before = w.get_body_flags(bodies)
        mixed = np.concatenate([bodies[:2], gone])

        def same():
            after = w.get_body_flags(bodies)
            assert all(np.array_equal(x, y) for x, y in zip(before, after))

        for call, status, word in (
                (lambda: w.set_types(mixed, hgcd.BodyType.STATIC), hgcd.Status.STALE_ID, "entry 2"),
                (lambda: w.set_enabled(mixed, False), hgcd.Status.STALE_ID, "entry 2"),
                (lambda: w.set_types(bodies, [0, 1, 2, 3]), hgcd.Status.INVALID_ARGUMENT, "BodyType"),
                (lambda: w.set_types(bodies, [0.0, 1, 2, 2]), hgcd.Status.INVALID_ARGUMENT, "BodyType"),
                (lambda: w.set_types(bodies, [0, 1]), hgcd.Status.INVALID_ARGUMENT, "shape"),
                (lambda: w.set_filters(bodies, np.array([(1, 1, 0, 0)] * 3 + [(1, 1, 0, 5)], dtype=hgcd.FILTER)),
                 hgcd.Status.INVALID_ARGUMENT, "entry 3"),
                (lambda: w.set_filters(bodies, np.zeros(4, np.uint64)), hgcd.Status.INVALID_ARGUMENT, "filters")):
            with pytest.raises(hgcd.Error) as e:
                call()
            assert e.value.status == status and word in e.value.message, e.value
            same()
        with pytest.raises(hgcd.Error) as e:
            hgcd.make_filter(category_bits=-1)
        assert e.value.status == hgcd.Status.INVALID_ARGUMENT
        pairs = np.array([[bodies[0], bodies[1]], [bodies[2], bodies[2]]])
        with pytest.raises(hgcd.Error) as e:
            w.exclude_pairs(pairs)
        assert e.value.status == hgcd.Status.INVALID_ARGUMENT and "pair 1" in e.value.message
        with pytest.raises(hgcd.Error) as e:
            w.exclude_pairs(np.array([[bodies[0], bodies[1]], [bodies[2], gone[0]]]))
        assert e.value.status == hgcd.Status.STALE_ID and "pair 1" in e.value.message
        assert not w.pairs_excluded(pairs[:1]).any()  # the valid first pair was not excluded either
        w.exclude_pairs(pairs[:1])
        with pytest.raises(hgcd.Error):
            w.include_pairs(pairs)
        assert w.pairs_excluded(pairs[:1]).all()
        with pytest.raises(hgcd.Error) as e:
            w.exclude_pairs(np.zeros((2, 3), dtype=hgcd.BODY_ID))
        assert "(N, 2)" in e.value.message


def cube_mesh():
    """The axis-aligned cube [-1/2, 1/2]^3, 12 triangles facing out."""
    v = np.array([[x, y, z] for x in (-0.5, 0.5) for y in (-0.5, 0.5) for z in (-0.5, 0.5)])
    t = np.array([[0, 1, 3], [0, 3, 2], [4, 6, 7], [4, 7, 5], [0, 4, 5], [0, 5, 1],
                  [2, 3, 7], [2, 7, 6], [0, 2, 6], [0, 6, 4], [1, 5, 7], [1, 7, 3]], dtype=np.uint32)
    return v, t


def margin_model(positions, world_margin, margins):
    """Index pairs of unit cubes (axis-aligned, at positions) within world_margin +
    (margin_a + margin_b), rounded as the library rounds it: the squared
    distance of two boxes (exact: the positions are multiples of 1/8) against
    the squared margin in rationals."""
    gap = np.maximum(np.abs(positions[:, None, :] - positions[None, :, :]) - 1.0, 0.0)
    dist2 = (gap ** 2).sum(axis=2)
    n = len(positions)
    return [(a, b) for a in range(n) for b in range(a + 1, n)
            if Fraction(dist2[a, b]) <= Fraction(float(world_margin + (margins[a] + margins[b]))) ** 2]


@pytest.mark.parametrize("threads", [1, 2])
def test_margins_equal_the_model(threads):
    rng = np.random.default_rng(11 + threads)
    n = 120
    positions = rng.integers(0, 48, (n, 3)) / 8.0  # cubes on a 1/8 lattice in [0, 6]^3
    margins = rng.integers(0, 3, n) / 16.0
    with hgcd.World(threads=threads, contact_margin=0.125) as w:
        assert w.contact_margin == 0.125
        mesh = w.create_mesh(*cube_mesh())
        bodies = w.create_bodies(mesh, positions=positions, margins=margins)
        assert np.array_equal(w.get_margins(bodies), margins)
        for d in (0.125, 0.0, 0.375, np.nextafter(0.25, 0.0), 0.25):
            w.set_contact_margin(d)
            w.detect()
            got = sorted(map(tuple, w.pairs(ids=False).tolist()))
            assert got == margin_model(positions, d, margins), d
        margins = rng.integers(0, 5, n) / 16.0
        w.set_margins(bodies, margins)
        w.detect()
        assert sorted(map(tuple, w.pairs(ids=False).tolist())) == margin_model(positions, 0.25, margins)


def test_margin_refusals_change_nothing():
    with hgcd.World(threads=1) as w:
        mesh = w.create_mesh(*cube_mesh())
        bodies = w.create_bodies(mesh, positions=[[0, 0, 0], [1.5, 0, 0], [3, 0, 0]], margins=0.25)
        gone = w.create_bodies(mesh, count=1)
        w.destroy_bodies(gone)
        w.detect()
        pairs = w.pairs(ids=False).tolist()
        assert pairs == [[0, 1], [1, 2]]
        for call, status, word in (
                (lambda: w.set_margins(bodies, [0.0, 1.0, np.nan]), hgcd.Status.INVALID_ARGUMENT, "entry 2"),
                (lambda: w.set_margins(bodies, [0.0, -1.0, 0.0]), hgcd.Status.INVALID_ARGUMENT, "entry 1"),
                (lambda: w.set_margins(bodies, [0.0, 0.0, 2e15]), hgcd.Status.INVALID_ARGUMENT, "entry 2"),
                (lambda: w.set_margins(np.concatenate([bodies, gone]), 0.0), hgcd.Status.STALE_ID, "entry 3"),
                (lambda: w.set_margins(bodies, [0.0, 0.0]), hgcd.Status.INVALID_ARGUMENT, "margins"),
                (lambda: w.set_contact_margin(np.inf), hgcd.Status.INVALID_ARGUMENT, "margin"),
                (lambda: w.set_contact_margin(-0.5), hgcd.Status.INVALID_ARGUMENT, "margin"),
                (lambda: w.set_contact_margin("x"), hgcd.Status.INVALID_ARGUMENT, "float")):
            with pytest.raises(hgcd.Error) as e:
                call()
            assert e.value.status == status and word in e.value.message, e.value
            assert np.array_equal(w.get_margins(bodies), [0.25] * 3) and w.contact_margin == 0.0
            w.detect()
            assert w.pairs(ids=False).tolist() == pairs
        with pytest.raises(hgcd.Error) as e:
            w.get_margins(gone)
        assert e.value.status == hgcd.Status.STALE_ID
        with pytest.raises(hgcd.Error) as e:
            w.create_bodies(mesh, count=2, margins=[0.0, np.nan])
        assert e.value.status == hgcd.Status.INVALID_ARGUMENT and "entry 1" in e.value.message
        assert w.body_count == 3
    with pytest.raises(hgcd.Error) as e:
        hgcd.World(contact_margin=-1.0)
    assert e.value.status == hgcd.Status.BAD_DESCRIPTOR or e.value.status == hgcd.Status.INVALID_ARGUMENT
