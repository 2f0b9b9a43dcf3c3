//! The batch calls (`set_poses`, `set_velocities`, `get_poses`) against one
//! call per body, and their refusals: the whole batch or nothing.

use hgcd::scene::{self, TetraDesc};
use hgcd::sys;
use hgcd::{BodyId, ErrorKind, Pair, Pose, World};

/// The tetra scene of `n` objects at the reference density (its side scaled
/// from 200 for 750000 objects), so that there are colliding pairs.
fn scene_desc(n: u64, seed: u64) -> TetraDesc {
    TetraDesc {
        side: 200.0 * (n as f64 / 750_000.0).cbrt(),
        ..TetraDesc::new(n, seed)
    }
}

/// The scene of `n` bodies (body i at index i) on `threads` threads.
fn scene_world(n: u64, threads: u32) -> (World, Vec<BodyId>) {
    let desc = scene_desc(n, 7);
    let scene = desc.generate().unwrap();
    let mut world = World::new(&desc.world_desc(threads)).unwrap();
    let (_, bodies) = scene.populate(&mut world).unwrap();
    (world, bodies)
}

/// New poses for every body: the scene of another seed, one tick on.
fn new_poses(n: u64) -> (Vec<[f64; 3]>, Vec<[f64; 4]>) {
    let desc = scene_desc(n, 8);
    let s = desc.generate().unwrap();
    let (mut centers, mut velocities) = (s.centers.clone(), s.velocities.clone());
    scene::move_tick(desc.side, &mut centers, &mut velocities).unwrap();
    (centers, s.orientations.clone())
}

/// A fixed permutation of 0..n (so the listed ids are not in index order).
fn shuffled(n: usize) -> Vec<usize> {
    let mut order: Vec<usize> = (0..n).collect();
    let mut x: u64 = 0x9e37_79b9_7f4a_7c15;
    for i in (1..n).rev() {
        x ^= x << 13;
        x ^= x >> 7;
        x ^= x << 17;
        order.swap(i, (x % (i as u64 + 1)) as usize);
    }
    order
}

fn all_poses(w: &World, bodies: &[BodyId]) -> Vec<Pose> {
    bodies.iter().map(|&b| w.get_pose(b).unwrap()).collect()
}

/// The pairs as indices: ids carry their world's tag, indices compare across
/// worlds built the same way.
fn detect(w: &mut World) -> Vec<(u32, u32)> {
    w.detect().unwrap();
    index_pairs(w.pairs())
}

fn index_pairs(pairs: &[Pair]) -> Vec<(u32, u32)> {
    pairs.iter().map(|p| (p.a.index(), p.b.index())).collect()
}

/// When few bodies move, the search runs around them alone (temporal
/// coherence, `Stats::searched_bodies`), and the pairs are those of a world
/// that searches everything afresh at the same poses.
#[test]
fn few_moved_search_around_them_alone() {
    let n = 4000u64;
    let (mut world, bodies) = scene_world(n, 2);
    world.detect().unwrap();
    assert_eq!(world.stats().searched_bodies, n);
    let (positions, orientations) = new_poses(n);
    let moved: Vec<usize> = shuffled(bodies.len()).into_iter().take(40).collect();
    let ids: Vec<BodyId> = moved.iter().map(|&i| bodies[i]).collect();
    let p: Vec<[f64; 3]> = moved.iter().map(|&i| positions[i]).collect();
    let q: Vec<[f64; 4]> = moved.iter().map(|&i| orientations[i]).collect();
    world.set_poses(Some(&ids), Some(&p), Some(&q)).unwrap();
    let pairs = detect(&mut world);
    assert_eq!(world.stats().searched_bodies, 40);

    let (mut fresh, others) = scene_world(n, 1);
    let fresh_ids: Vec<BodyId> = moved.iter().map(|&i| others[i]).collect();
    fresh.set_poses(Some(&fresh_ids), Some(&p), Some(&q)).unwrap();
    assert_eq!(pairs, detect(&mut fresh));
    assert_eq!(fresh.stats().searched_bodies, n);
    assert!(!pairs.is_empty());
}

/// Batch == one set_pose per body, for listed (shuffled) ids and for "every
/// index", with positions and orientations, positions only, orientations
/// only; below and above the library's parallel threshold (4096 entries).
#[test]
fn batch_equals_per_body_calls() {
    for &(n, threads) in &[(600u64, 1u32), (5000, 2)] {
        let (mut batch, bodies) = scene_world(n, threads);
        // Ids carry their world: `single`'s body i is `other[i]`.
        let (mut single, other) = scene_world(n, threads);
        let (positions, orientations) = new_poses(n);
        let order = shuffled(bodies.len());
        let ids: Vec<BodyId> = order.iter().map(|&i| bodies[i]).collect();
        let p: Vec<[f64; 3]> = order.iter().map(|&i| positions[i]).collect();

        // Positions only, listed ids; then orientations only, every index.
        batch.set_poses(Some(&ids), Some(&p), None).unwrap();
        for (k, &i) in order.iter().enumerate() {
            single.set_position(other[i], p[k]).unwrap();
        }
        assert_eq!(all_poses(&batch, &bodies), all_poses(&single, &other));
        batch.set_poses(None, None, Some(&orientations)).unwrap();
        for (i, &b) in other.iter().enumerate() {
            single.set_orientation(b, orientations[i]).unwrap();
        }
        let pairs = detect(&mut batch);
        assert!(!pairs.is_empty(), "the scene should have colliding pairs");
        assert_eq!(pairs, detect(&mut single), "n {n}: pairs after the batch");
        assert_eq!(all_poses(&batch, &bodies), all_poses(&single, &other));

        // Both, listed ids, back to the scene's own poses (a second move).
        let (p0, q0): (Vec<[f64; 3]>, Vec<[f64; 4]>) = {
            let (fresh, ids) = scene_world(n, 1);
            all_poses(&fresh, &ids)
        }
        .iter()
        .map(|pose| (pose.position, pose.orientation))
        .unzip();
        let sp: Vec<[f64; 3]> = order.iter().map(|&i| p0[i]).collect();
        let sq: Vec<[f64; 4]> = order.iter().map(|&i| q0[i]).collect();
        batch.set_poses(Some(&ids), Some(&sp), Some(&sq)).unwrap();
        for (k, &i) in order.iter().enumerate() {
            single.set_pose(other[i], sp[k], sq[k]).unwrap();
        }
        assert_eq!(detect(&mut batch), detect(&mut single), "n {n}: pairs back");

        // get_poses returns what get_pose does, in the entries' order.
        let mut gp = vec![[0.0; 3]; ids.len()];
        let mut gq = vec![[0.0; 4]; ids.len()];
        batch
            .get_poses(Some(&ids), Some(&mut gp), Some(&mut gq))
            .unwrap();
        for (k, &i) in order.iter().enumerate() {
            let pose = single.get_pose(other[i]).unwrap();
            assert_eq!((gp[k], gq[k]), (pose.position, pose.orientation));
        }
        let mut by_index = vec![[0.0; 3]; bodies.len()];
        batch.get_poses(None, Some(&mut by_index), None).unwrap();
        assert_eq!(by_index, p0);
    }
}

#[test]
fn velocities_batch_equals_per_body_calls() {
    let (mut batch, bodies) = scene_world(800, 2);
    let (mut single, other) = scene_world(800, 2);
    let order = shuffled(bodies.len());
    let ids: Vec<BodyId> = order.iter().map(|&i| bodies[i]).collect();
    let v: Vec<[f64; 3]> = (0..ids.len())
        .map(|k| [0.01 * (k % 7) as f64, -0.02, 0.005 * (k % 3) as f64])
        .collect();
    batch.set_velocities(Some(&ids), &v).unwrap();
    for (k, &i) in order.iter().enumerate() {
        single.set_velocity(other[i], v[k]).unwrap();
    }
    for (&b, &o) in bodies.iter().zip(&other) {
        assert_eq!(
            batch.get_velocity(b).unwrap(),
            single.get_velocity(o).unwrap()
        );
    }
    for _ in 0..3 {
        batch.step().unwrap();
        single.step().unwrap();
        assert_eq!(index_pairs(batch.pairs()), index_pairs(single.pairs()));
    }
    assert_eq!(all_poses(&batch, &bodies), all_poses(&single, &other));
    // Every index at once.
    batch
        .set_velocities(None, &vec![[0.0; 3]; bodies.len()])
        .unwrap();
    assert!(bodies
        .iter()
        .all(|&b| batch.get_velocity(b).unwrap() == [0.0; 3]));
}

/// The observable state a refusal must leave alone: poses, velocities, pairs.
type Snapshot = (Vec<Pose>, Vec<[f64; 3]>, Vec<(u32, u32)>);

fn snapshot(w: &mut World, bodies: &[BodyId]) -> Snapshot {
    let v = bodies.iter().map(|&b| w.get_velocity(b).unwrap()).collect();
    (all_poses(w, bodies), v, detect(w))
}

#[test]
fn refusals_change_nothing_and_name_the_entry() {
    let (mut w, mut bodies) = scene_world(300, 1);
    let stale = bodies.pop().unwrap();
    w.destroy_body(stale).unwrap();
    let before = snapshot(&mut w, &bodies);
    let n = bodies.len();
    let far = vec![[1.0, 2.0, 3.0]; n];
    let turned = vec![[0.0, 0.0, 1.0, 0.0]; n];

    // A stale id at entry 17 (every other entry valid).
    let mut ids = bodies.clone();
    ids[17] = stale;
    let e = w
        .set_poses(Some(&ids), Some(&far), Some(&turned))
        .unwrap_err();
    assert_eq!(e.kind(), ErrorKind::StaleId);
    assert!(
        e.message().contains("world_set_poses: entry 17"),
        "{}",
        e.message()
    );
    let e = w.set_velocities(Some(&ids), &far).unwrap_err();
    assert_eq!(e.kind(), ErrorKind::StaleId);
    assert!(e.message().contains("entry 17"), "{}", e.message());
    let mut out = vec![[7.0; 3]; n];
    let e = w.get_poses(Some(&ids), Some(&mut out), None).unwrap_err();
    assert_eq!(e.kind(), ErrorKind::StaleId);
    assert!(e.message().contains("entry 17"), "{}", e.message());
    assert!(
        out.iter().all(|&p| p == [7.0; 3]),
        "get_poses wrote on failure"
    );
    // A forged generation.
    ids[17] = BodyId::from_raw(sys::hgcd_body {
        index: bodies[17].index(),
        generation: bodies[17].generation() ^ 1,
    });
    let e = w.set_poses(Some(&ids), Some(&far), None).unwrap_err();
    assert_eq!(e.kind(), ErrorKind::StaleId);
    assert!(e.message().contains("entry 17"), "{}", e.message());
    // Every index: the destroyed body's index (the last) has no live body.
    let e = w
        .set_poses(None, Some(&vec![[0.0; 3]; n + 1]), None)
        .unwrap_err();
    assert_eq!(e.kind(), ErrorKind::StaleId);
    assert!(
        e.message().contains(&format!("entry {n}")),
        "{}",
        e.message()
    );

    // A NaN, an infinite velocity, a non-unit quaternion, a position past 1e15.
    let mut bad = far.clone();
    bad[42][1] = f64::NAN;
    let e = w
        .set_poses(Some(&bodies), Some(&bad), Some(&turned))
        .unwrap_err();
    assert_eq!(e.kind(), ErrorKind::InvalidArgument);
    assert!(e.message().contains("entry 42"), "{}", e.message());
    let e = w.set_velocities(None, &bad).unwrap_err();
    assert_eq!(e.kind(), ErrorKind::InvalidArgument);
    assert!(e.message().contains("entry 42"), "{}", e.message());
    let mut q = turned.clone();
    q[5] = [0.0, 0.0, 0.0, 1.0 + 2e-6];
    let e = w.set_poses(None, None, Some(&q)).unwrap_err();
    assert_eq!(e.kind(), ErrorKind::InvalidArgument);
    assert!(e.message().contains("entry 5"), "{}", e.message());
    let mut huge = far.clone();
    huge[n - 1][0] = 1.0000000000000002e15;
    let e = w.set_poses(None, Some(&huge), None).unwrap_err();
    assert_eq!(e.kind(), ErrorKind::InvalidArgument);
    assert!(
        e.message().contains(&format!("entry {}", n - 1)),
        "{}",
        e.message()
    );

    // An id twice (entry 9 repeats entry 3).
    let mut twice = bodies.clone();
    twice[9] = twice[3];
    let e = w.set_poses(Some(&twice), Some(&far), None).unwrap_err();
    assert_eq!(e.kind(), ErrorKind::InvalidArgument);
    assert!(e.message().contains("entry 9"), "{}", e.message());
    let e = w.set_velocities(Some(&twice), &far).unwrap_err();
    assert_eq!(e.kind(), ErrorKind::InvalidArgument);
    // A stale id is reported before a duplicate, and before a bad value.
    twice[20] = stale;
    let e = w.set_poses(Some(&twice), Some(&bad), None).unwrap_err();
    assert_eq!(e.kind(), ErrorKind::StaleId);

    assert_eq!(
        snapshot(&mut w, &bodies),
        before,
        "a refusal changed the world"
    );
}

#[test]
fn length_mismatch_is_refused_before_c() {
    let (mut w, bodies) = scene_world(10, 1);
    let before = snapshot(&mut w, &bodies);
    assert_eq!(w.last_error(), "");
    let p = vec![[1.0; 3]; 9];
    let q = vec![[0.0, 0.0, 0.0, 1.0]; 10];
    let cases = [
        w.set_poses(Some(&bodies), Some(&p), None),
        w.set_poses(None, Some(&p), Some(&q)),
        w.set_poses(Some(&bodies), None, None),
        w.set_velocities(Some(&bodies[..3]), &p),
    ];
    for r in cases {
        let e = r.unwrap_err();
        assert_eq!(e.kind(), ErrorKind::InvalidArgument);
        assert!(e.message().starts_with("world_set_"), "{}", e.message());
    }
    let mut out = vec![[0.0; 3]; 9];
    let e = w
        .get_poses(Some(&bodies), Some(&mut out), None)
        .unwrap_err();
    assert_eq!(e.kind(), ErrorKind::InvalidArgument);
    assert!(
        e.message().contains("bodies has 10 entries, positions 9"),
        "{}",
        e.message()
    );
    assert_eq!(
        kind_of(w.get_poses(None, None, None)),
        ErrorKind::InvalidArgument
    );
    // No C call was made: the library recorded no message.
    assert_eq!(w.last_error(), "");
    assert_eq!(snapshot(&mut w, &bodies), before);
    // Empty batches are fine.
    w.set_poses(Some(&[]), Some(&[]), None).unwrap();
    w.set_velocities(None, &[]).unwrap();
    w.get_poses(None, None, Some(&mut [])).unwrap();
}

fn kind_of(r: hgcd::Result<()>) -> ErrorKind {
    r.unwrap_err().kind()
}
