//! The safe API gives the same results as the raw C API, and as the C demo
//! and docs/scenes.md, on the tetra reference scene.

use std::collections::HashSet;

use hgcd::scene::{self, TetraDesc};
use hgcd::sys;
use hgcd::{ErrorKind, Pair, ThreadPolicy, World, WorldDesc};

/// FNV-1a over the pairs' index words, in order. Generations carry a
/// per-world tag (hgcd.h, "Ids"), so two worlds' pairs agree on indices only;
/// each caller checks its generations against its own world.
fn hash_pairs<I: IntoIterator<Item = [u32; 2]>>(pairs: I) -> u64 {
    let mut h: u64 = 0xcbf2_9ce4_8422_2325;
    for words in pairs {
        for w in words {
            for byte in w.to_le_bytes() {
                h ^= u64::from(byte);
                h = h.wrapping_mul(0x0000_0100_0000_01b3);
            }
        }
    }
    h
}

fn words(p: &Pair) -> [u32; 2] {
    [p.a.index(), p.b.index()]
}

/// Per tick (0 = detect at the initial poses, then `ticks` steps): the pairs'
/// hash and count, and the containment count, computed through the raw C API
/// only, exactly as examples/demo.c does it.
fn raw_c_ticks(n: u64, seed: u64, ticks: u32, threads: u32) -> Vec<(u64, usize, u64)> {
    unsafe {
        let mut sd = sys::hgcd_scene_tetra_desc_default();
        sd.n = n;
        sd.seed = seed;
        let n = n as usize;
        let mut centers = vec![0.0f64; 3 * n];
        let mut scales = vec![0.0f64; n];
        let mut quats = vec![0.0f64; 4 * n];
        let mut vels = vec![0.0f64; 3 * n];
        assert_eq!(
            sys::hgcd_scene_tetra_generate(
                &sd,
                centers.as_mut_ptr(),
                std::ptr::null_mut(),
                scales.as_mut_ptr(),
                quats.as_mut_ptr(),
                vels.as_mut_ptr()
            ),
            sys::HGCD_OK
        );
        let mut wd = sys::hgcd_world_desc_default();
        wd.thread_count = threads;
        wd.reflect_at_bounds = 1;
        wd.bounds_min = [0.0; 3];
        wd.bounds_max = [sd.side; 3];
        let mut w: *mut sys::hgcd_world = std::ptr::null_mut();
        assert_eq!(sys::hgcd_world_create(&wd, &mut w), sys::HGCD_OK);
        let mut verts = [0.0f64; 12];
        let mut tris = [0u32; 12];
        sys::hgcd_scene_tetra_unit_mesh(verts.as_mut_ptr(), tris.as_mut_ptr());
        let mut md = sys::hgcd_mesh_desc_default();
        md.vertices = verts.as_ptr();
        md.triangles = tris.as_ptr();
        md.vertex_count = 4;
        md.triangle_count = 4;
        let mut mesh = sys::hgcd_mesh {
            index: 0,
            generation: 0,
        };
        assert_eq!(sys::hgcd_mesh_create(w, &md, &mut mesh), sys::HGCD_OK);
        let mut bd = sys::hgcd_body_desc_default();
        bd.mesh = mesh;
        let mut ids = Vec::with_capacity(n);
        for i in 0..n {
            bd.position.copy_from_slice(&centers[3 * i..3 * i + 3]);
            bd.orientation.copy_from_slice(&quats[4 * i..4 * i + 4]);
            bd.velocity.copy_from_slice(&vels[3 * i..3 * i + 3]);
            bd.scale = scales[i];
            let mut b = sys::hgcd_body {
                index: 0,
                generation: 0,
            };
            assert_eq!(sys::hgcd_body_create(w, &bd, &mut b), sys::HGCD_OK);
            assert_eq!(b.index as usize, i);
            ids.push(b.generation);
        }
        let mut out = Vec::new();
        for tick in 0..=ticks {
            let s = if tick == 0 {
                sys::hgcd_world_detect(w)
            } else {
                sys::hgcd_world_step(w)
            };
            assert_eq!(s, sys::HGCD_OK);
            let mut p: *const sys::hgcd_pair = std::ptr::null();
            let mut count = 0usize;
            assert_eq!(sys::hgcd_world_pairs(w, &mut p, &mut count), sys::HGCD_OK);
            let pairs = if count == 0 {
                &[][..]
            } else {
                std::slice::from_raw_parts(p, count)
            };
            // The copy-out variant agrees with the borrowed array.
            let mut total = 0usize;
            assert_eq!(
                sys::hgcd_world_copy_pairs(w, std::ptr::null_mut(), 0, &mut total),
                sys::HGCD_OK
            );
            assert_eq!(total, count);
            let mut st: sys::hgcd_stats = std::mem::zeroed();
            st.struct_size = std::mem::size_of::<sys::hgcd_stats>() as u32;
            assert_eq!(sys::hgcd_world_stats(w, &mut st), sys::HGCD_OK);
            assert_eq!(st.colliding_pairs as usize, count);
            for p in pairs {
                assert_eq!(p.a.generation, ids[p.a.index as usize]);
                assert_eq!(p.b.generation, ids[p.b.index as usize]);
            }
            let h = hash_pairs(pairs.iter().map(|p| [p.a.index, p.b.index]));
            out.push((h, count, st.containment_pairs));
        }
        sys::hgcd_world_destroy(w);
        out
    }
}

/// The same through the safe API.
fn safe_ticks(n: u64, seed: u64, ticks: u32, threads: u32) -> Vec<(u64, usize, u64)> {
    let mut world = scene::tetra_world(&TetraDesc::new(n, seed), threads).unwrap();
    assert_eq!(world.body_count() as u64, n);
    let mut out = Vec::new();
    for tick in 0..=ticks {
        if tick == 0 {
            world.detect().unwrap()
        } else {
            world.step().unwrap()
        }
        let pairs = world.pairs();
        let stats = world.stats();
        assert_eq!(stats.colliding_pairs as usize, pairs.len());
        assert!(pairs
            .iter()
            .all(|p| world.is_body_alive(p.a) && world.is_body_alive(p.b)));
        out.push((
            hash_pairs(pairs.iter().map(words)),
            pairs.len(),
            stats.containment_pairs,
        ));
    }
    out
}

/// n = 20000, seed 1: Rust == raw C, and the counts examples/demo.c prints
/// (`build-make/demo --n 20000 --ticks 3`: 200 (1 by containment), 197, 201,
/// 202).
#[test]
fn tetra_20000_rust_equals_c() {
    let rust = safe_ticks(20000, 1, 3, 0);
    let c = raw_c_ticks(20000, 1, 3, 0);
    assert_eq!(rust, c);
    let counts: Vec<usize> = rust.iter().map(|t| t.1).collect();
    assert_eq!(counts, [200, 197, 201, 202]);
    assert_eq!(rust[0].2, 1);
}

/// docs/scenes.md reference: n = 100000, seed 1, initial poses: 4266 colliding
/// pairs, 30 by containment.
#[test]
fn tetra_100000_reference() {
    let mut world = scene::tetra_world(&TetraDesc::new(100_000, 1), 0).unwrap();
    world.detect().unwrap();
    assert_eq!(world.pairs().len(), 4266);
    assert_eq!(world.stats().containment_pairs, 30);
}

/// The pairs do not depend on the thread count, bit for bit and in order.
#[test]
fn thread_count_does_not_change_pairs() {
    let one = safe_ticks(20000, 7, 2, 1);
    let two = safe_ticks(20000, 7, 2, 2);
    assert_eq!(one, two);
}

/// The thread policy: the default is adaptive, either policy gives the same
/// pairs, the fixed one always reports its thread count, and a value the
/// library does not know is refused.
#[test]
fn thread_policy_does_not_change_pairs() {
    assert_eq!(WorldDesc::default().thread_policy, ThreadPolicy::Adaptive);
    let run = |policy: ThreadPolicy| {
        let mut world = scene::tetra_world(&TetraDesc::new(20000, 7), 2).unwrap();
        world.set_thread_policy(policy).unwrap();
        let mut out = Vec::new();
        for _ in 0..6 {
            world.step().unwrap();
            let threads = world.stats().thread_count;
            match policy {
                ThreadPolicy::Fixed => assert_eq!(threads, 2),
                _ => assert!(threads == 1 || threads == 2),
            }
            out.push(hash_pairs(world.pairs().iter().map(words)));
        }
        out
    };
    assert_eq!(run(ThreadPolicy::Fixed), run(ThreadPolicy::Adaptive));
    let mut world = World::new(&WorldDesc::default()).unwrap();
    let err = world.set_thread_policy(ThreadPolicy::Unknown(9)).unwrap_err();
    assert_eq!(err.kind(), ErrorKind::InvalidArgument);
    let bad = WorldDesc {
        thread_policy: ThreadPolicy::Unknown(-3),
        ..WorldDesc::default()
    };
    assert_eq!(World::new(&bad).unwrap_err().kind(), ErrorKind::InvalidArgument);
}

#[test]
fn pairs_are_sorted_unique_and_ordered() {
    let mut world = scene::tetra_world(&TetraDesc::new(20000, 1), 0).unwrap();
    assert!(world.pairs().is_empty(), "no pairs before the first detect");
    world.detect().unwrap();
    let pairs = world.pairs();
    assert!(pairs.windows(2).all(|w| w[0].indices() < w[1].indices()));
    assert!(pairs.iter().all(|p| p.a.index() < p.b.index()));
    let set: HashSet<Pair> = pairs.iter().copied().collect();
    assert_eq!(set.len(), pairs.len());
    // The slice is the library's own array, not a copy: same address twice.
    assert_eq!(world.pairs().as_ptr(), pairs.as_ptr());
    for p in pairs {
        assert!(world.is_body_alive(p.a) && world.is_body_alive(p.b));
    }
}

/// A world moves to another thread (World: Send) and works there.
#[test]
fn world_is_send() {
    fn assert_send<T: Send>() {}
    assert_send::<World>();
    let world = scene::tetra_world(&TetraDesc::new(20000, 1), 0).unwrap();
    let handle = std::thread::spawn(move || {
        let mut world = world;
        world.detect().unwrap();
        let n = world.pairs().len();
        (world, n)
    });
    let (mut world, n) = handle.join().unwrap();
    assert_eq!(n, 200);
    world.step().unwrap();
    assert_eq!(world.pairs().len(), 197);
}

/// Separate worlds are independent and may run on different threads at once.
#[test]
fn separate_worlds_in_parallel() {
    let handles: Vec<_> = (0..2)
        .map(|_| std::thread::spawn(|| safe_ticks(20000, 1, 1, 1)))
        .collect();
    for h in handles {
        let r = h.join().unwrap();
        assert_eq!(r[0].1, 200);
        assert_eq!(r[1].1, 197);
    }
}

#[test]
fn unit_mesh_is_the_sign_pattern_tetrahedron() {
    let (v, t) = scene::unit_mesh();
    assert_eq!(
        v,
        [
            [1.0, 1.0, 1.0],
            [1.0, -1.0, -1.0],
            [-1.0, 1.0, -1.0],
            [-1.0, -1.0, 1.0]
        ]
    );
    assert_eq!(t, [[0, 1, 2], [0, 3, 1], [0, 2, 3], [1, 3, 2]]);
    let mut world = World::new(&Default::default()).unwrap();
    let mesh = world.create_mesh(&hgcd::MeshDesc::new(&v, &t)).unwrap();
    let info = world.mesh_info(mesh).unwrap();
    assert!(info.closed && info.convex);
    assert_eq!(
        (info.vertex_count, info.triangle_count, info.component_count),
        (4, 4, 1)
    );
    assert_eq!(info.degenerate_triangle_count, 0);
    assert_eq!(info.body_count, 0);
}

/// World::step with reflection moves the bodies exactly as the scene's own
/// motion (hgcd_scene_tetra_move) does, bit for bit.
#[test]
fn step_matches_scene_motion() {
    let desc = TetraDesc::new(500, 3);
    let mut s = desc.generate().unwrap();
    assert_eq!(s.len(), 500);
    assert!(s
        .radii
        .iter()
        .zip(&s.scales)
        .all(|(r, k)| *k == *r / 3f64.sqrt()));
    let mut world = World::new(&desc.world_desc(1)).unwrap();
    let (_, bodies) = s.populate(&mut world).unwrap();
    for _ in 0..50 {
        world.step().unwrap();
        scene::move_tick(desc.side, &mut s.centers, &mut s.velocities).unwrap();
    }
    for (i, b) in bodies.iter().enumerate() {
        assert_eq!(b.index() as usize, i);
        let pose = world.get_pose(*b).unwrap();
        assert_eq!(
            pose.position.map(f64::to_bits),
            s.centers[i].map(f64::to_bits),
            "body {i}"
        );
        assert_eq!(pose.orientation, s.orientations[i]);
        assert_eq!(world.get_velocity(*b).unwrap(), s.velocities[i]);
        assert_eq!(world.body_user_data(*b).unwrap(), i as u64);
    }
}

#[test]
fn scene_generation_errors() {
    let bad = TetraDesc {
        rmin: 3.0,
        rmax: 1.0,
        ..TetraDesc::new(10, 1)
    };
    assert_eq!(
        bad.generate().unwrap_err().kind(),
        ErrorKind::InvalidArgument
    );
    let nan = TetraDesc {
        side: f64::NAN,
        ..TetraDesc::new(10, 1)
    };
    assert_eq!(
        nan.generate().unwrap_err().kind(),
        ErrorKind::InvalidArgument
    );
    let huge = TetraDesc::new(u64::MAX, 1);
    assert_eq!(huge.generate().unwrap_err().kind(), ErrorKind::Capacity);
    let empty = TetraDesc::new(0, 1).generate().unwrap();
    assert!(empty.is_empty());
    let mut c = vec![[1.0; 3]; 2];
    let mut v = vec![[0.0; 3]; 3];
    assert_eq!(
        scene::move_tick(200.0, &mut c, &mut v).unwrap_err().kind(),
        ErrorKind::InvalidArgument
    );
    // Same scene twice: identical bits.
    let a = TetraDesc::new(1000, 5).generate().unwrap();
    let b = TetraDesc::new(1000, 5).generate().unwrap();
    assert_eq!(a, b);
    assert_eq!(TetraDesc::default().n, 750_000);
}
