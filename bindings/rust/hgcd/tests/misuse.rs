//! Misuse gives `Err` with the library's status (and leaves the world as it
//! was), never a panic or undefined behaviour.

use std::collections::HashSet;

use hgcd::scene;
use hgcd::sys;
use hgcd::{BodyDesc, BodyId, Error, ErrorKind, MeshDesc, MeshId, Pair, World, WorldDesc};

const IDENTITY: [f64; 4] = [0.0, 0.0, 0.0, 1.0];

fn world() -> World {
    World::new(&WorldDesc::default()).unwrap()
}

fn tetra(world: &mut World) -> MeshId {
    let (v, t) = scene::unit_mesh();
    world.create_mesh(&MeshDesc::new(&v, &t)).unwrap()
}

fn body_at(world: &mut World, mesh: MeshId, x: f64) -> BodyId {
    world
        .create_body(&BodyDesc {
            position: [x, 0.0, 0.0],
            ..BodyDesc::new(mesh)
        })
        .unwrap()
}

fn kind<T: std::fmt::Debug>(r: Result<T, Error>) -> ErrorKind {
    r.unwrap_err().kind()
}

#[test]
fn stale_body_after_destroy() {
    let mut w = world();
    let m = tetra(&mut w);
    let b0 = body_at(&mut w, m, 0.0);
    let b1 = body_at(&mut w, m, 10.0);
    assert_eq!(
        (b0.index(), b1.index()),
        (0, 1),
        "indices in creation order"
    );
    w.destroy_body(b0).unwrap();
    assert_eq!(w.body_count(), 1);
    assert!(!w.is_body_alive(b0));

    let e = w.destroy_body(b0).unwrap_err();
    assert_eq!(e.kind(), ErrorKind::StaleId);
    assert!(
        !e.message().is_empty(),
        "changing calls carry the library's message"
    );
    assert_eq!(kind(w.set_pose(b0, [1.0; 3], IDENTITY)), ErrorKind::StaleId);
    assert_eq!(kind(w.set_position(b0, [1.0; 3])), ErrorKind::StaleId);
    assert_eq!(kind(w.set_velocity(b0, [1.0; 3])), ErrorKind::StaleId);
    assert_eq!(kind(w.get_pose(b0)), ErrorKind::StaleId);
    assert_eq!(kind(w.get_velocity(b0)), ErrorKind::StaleId);
    assert_eq!(kind(w.body_mesh(b0)), ErrorKind::StaleId);
    assert_eq!(kind(w.body_user_data(b0)), ErrorKind::StaleId);

    // The index is reused, the old id stays stale.
    let b2 = body_at(&mut w, m, 20.0);
    assert_eq!(b2.index(), b0.index());
    assert_ne!(b2, b0);
    assert!(w.is_body_alive(b2));
    assert!(!w.is_body_alive(b0));
    assert_eq!(kind(w.get_pose(b0)), ErrorKind::StaleId);
    assert_eq!(w.get_pose(b2).unwrap().position, [20.0, 0.0, 0.0]);
    assert_eq!(w.body_count(), 2);
}

#[test]
fn null_and_forged_ids() {
    let mut w = world();
    let m = tetra(&mut w);
    let b = body_at(&mut w, m, 0.0);
    assert!(BodyId::NULL.is_null() && BodyId::default().is_null() && MeshId::NULL.is_null());
    assert_eq!(kind(w.get_pose(BodyId::NULL)), ErrorKind::StaleId);
    assert_eq!(kind(w.destroy_body(BodyId::NULL)), ErrorKind::StaleId);
    assert_eq!(kind(w.mesh_info(MeshId::NULL)), ErrorKind::StaleId);
    assert_eq!(kind(w.destroy_mesh(MeshId::NULL)), ErrorKind::StaleId);
    // BodyDesc::default() has the null mesh.
    assert_eq!(
        kind(w.create_body(&BodyDesc::default())),
        ErrorKind::StaleId
    );
    // A forged generation is always caught.
    let forged = BodyId::from_raw(sys::hgcd_body {
        index: b.index(),
        generation: b.generation() ^ 1,
    });
    assert_eq!(kind(w.destroy_body(forged)), ErrorKind::StaleId);
    let beyond = BodyId::from_raw(sys::hgcd_body {
        index: 1_000_000,
        generation: b.generation(),
    });
    assert_eq!(kind(w.set_velocity(beyond, [0.0; 3])), ErrorKind::StaleId);
    assert!(w.is_body_alive(b));
    assert_eq!(w.body_count(), 1);
}

#[test]
fn mesh_alive_until_destroyed() {
    let mut w = world();
    let m = tetra(&mut w);
    assert_eq!(m.index(), 0);
    assert!(w.is_mesh_alive(m));
    // The null id shares index 0 with the live mesh; a forged generation and
    // an index beyond the slots are refused too.
    assert!(!w.is_mesh_alive(MeshId::NULL));
    let forged = MeshId::from_raw(sys::hgcd_mesh {
        index: m.index(),
        generation: m.generation() ^ 1,
    });
    assert!(!w.is_mesh_alive(forged));
    let beyond = MeshId::from_raw(sys::hgcd_mesh {
        index: 1_000_000,
        generation: m.generation(),
    });
    assert!(!w.is_mesh_alive(beyond));
    // Destroyed: stale, also once a new mesh takes its index.
    let n = tetra(&mut w);
    assert!(w.is_mesh_alive(n));
    w.destroy_mesh(n).unwrap();
    assert!(!w.is_mesh_alive(n));
    let again = tetra(&mut w);
    assert_eq!(again.index(), n.index());
    assert!(w.is_mesh_alive(again));
    assert!(!w.is_mesh_alive(n));
    // Another world's mesh of the same index.
    let mut other = world();
    let foreign = tetra(&mut other);
    assert_eq!(foreign.index(), m.index());
    assert!(other.is_mesh_alive(foreign));
    assert!(!w.is_mesh_alive(foreign));
    assert!(!other.is_mesh_alive(m));
    assert_eq!(w.mesh_count(), 2);
}

#[test]
fn destroy_mesh_in_use() {
    let mut w = world();
    let m = tetra(&mut w);
    let a = body_at(&mut w, m, 0.0);
    let b = body_at(&mut w, m, 10.0);
    assert_eq!(w.mesh_info(m).unwrap().body_count, 2);
    let e = w.destroy_mesh(m).unwrap_err();
    assert_eq!(e.kind(), ErrorKind::MeshInUse);
    assert!(!e.message().is_empty());
    assert_eq!(w.mesh_count(), 1);
    w.destroy_body(a).unwrap();
    assert_eq!(kind(w.destroy_mesh(m)), ErrorKind::MeshInUse);
    w.destroy_body(b).unwrap();
    assert_eq!(w.mesh_info(m).unwrap().body_count, 0);
    w.destroy_mesh(m).unwrap();
    assert_eq!(w.mesh_count(), 0);
    assert_eq!(kind(w.destroy_mesh(m)), ErrorKind::StaleId);
    assert_eq!(kind(w.mesh_info(m)), ErrorKind::StaleId);
    assert_eq!(kind(w.create_body(&BodyDesc::new(m))), ErrorKind::StaleId);
}

#[test]
fn bad_meshes() {
    let mut w = world();
    let v = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]];
    // Index out of range.
    let e = w.create_mesh(&MeshDesc::new(&v, &[[0, 1, 3]])).unwrap_err();
    assert_eq!(e.kind(), ErrorKind::InvalidMesh);
    assert!(!e.message().is_empty());
    // No triangles, no vertices, the default (empty) descriptor.
    assert_eq!(
        kind(w.create_mesh(&MeshDesc::new(&v, &[]))),
        ErrorKind::InvalidMesh
    );
    assert_eq!(
        kind(w.create_mesh(&MeshDesc::new(&[], &[[0, 0, 0]]))),
        ErrorKind::InvalidMesh
    );
    assert_eq!(
        kind(w.create_mesh(&MeshDesc::default())),
        ErrorKind::InvalidMesh
    );
    // Non-finite or too far vertices.
    let nan = [[0.0, 0.0, 0.0], [f64::NAN, 0.0, 0.0], [0.0, 1.0, 0.0]];
    assert_eq!(
        kind(w.create_mesh(&MeshDesc::new(&nan, &[[0, 1, 2]]))),
        ErrorKind::InvalidMesh
    );
    let inf = [[0.0, 0.0, 0.0], [1.0, f64::INFINITY, 0.0], [0.0, 1.0, 0.0]];
    assert_eq!(
        kind(w.create_mesh(&MeshDesc::new(&inf, &[[0, 1, 2]]))),
        ErrorKind::InvalidMesh
    );
    let far = [[0.0, 0.0, 0.0], [1e16, 0.0, 0.0], [0.0, 1.0, 0.0]];
    assert_eq!(
        kind(w.create_mesh(&MeshDesc::new(&far, &[[0, 1, 2]]))),
        ErrorKind::InvalidMesh
    );
    assert_eq!(w.mesh_count(), 0, "failed calls leave the world unchanged");

    // An open, degenerate-tolerant mesh is fine.
    let m = w
        .create_mesh(&MeshDesc::new(&v, &[[0, 1, 2], [0, 0, 1]]))
        .unwrap();
    let info = w.mesh_info(m).unwrap();
    assert!(!info.closed && !info.convex);
    assert_eq!(info.degenerate_triangle_count, 1);
}

#[test]
fn invalid_body_values() {
    let mut w = world();
    let m = tetra(&mut w);
    let bad_position = BodyDesc {
        position: [0.0, f64::NAN, 0.0],
        ..BodyDesc::new(m)
    };
    let e = w.create_body(&bad_position).unwrap_err();
    assert_eq!(e.kind(), ErrorKind::InvalidArgument);
    assert!(e.message().contains("position"), "message: {}", e.message());
    for desc in [
        BodyDesc {
            position: [f64::INFINITY, 0.0, 0.0],
            ..BodyDesc::new(m)
        },
        BodyDesc {
            position: [2e15, 0.0, 0.0],
            ..BodyDesc::new(m)
        },
        BodyDesc {
            orientation: [0.0, 0.0, 0.0, 2.0],
            ..BodyDesc::new(m)
        },
        BodyDesc {
            orientation: [0.0, 0.0, 0.0, 0.0],
            ..BodyDesc::new(m)
        },
        BodyDesc {
            orientation: [f64::NAN, 0.0, 0.0, 1.0],
            ..BodyDesc::new(m)
        },
        BodyDesc {
            orientation: [0.0, 0.0, 0.0, 1.0 + 1e-5],
            ..BodyDesc::new(m)
        },
        BodyDesc {
            velocity: [0.0, 0.0, f64::NAN],
            ..BodyDesc::new(m)
        },
        BodyDesc {
            scale: 0.0,
            ..BodyDesc::new(m)
        },
        BodyDesc {
            scale: -1.0,
            ..BodyDesc::new(m)
        },
        BodyDesc {
            scale: f64::NAN,
            ..BodyDesc::new(m)
        },
    ] {
        assert_eq!(
            kind(w.create_body(&desc)),
            ErrorKind::InvalidArgument,
            "{desc:?}"
        );
    }
    assert_eq!(w.body_count(), 0);
    // Within the 1e-6 tolerance: accepted, and kept exactly as given.
    let q = [0.0, 0.0, 0.0, 1.0 + 1e-7];
    let b = w
        .create_body(&BodyDesc {
            orientation: q,
            ..BodyDesc::new(m)
        })
        .unwrap();
    assert_eq!(w.get_pose(b).unwrap().orientation, q);

    // set_pose / set_velocity refuse bad values and change nothing.
    let before = w.get_pose(b).unwrap();
    assert_eq!(
        kind(w.set_pose(b, [f64::NAN, 0.0, 0.0], IDENTITY)),
        ErrorKind::InvalidArgument
    );
    assert_eq!(
        kind(w.set_pose(b, [1.0, 2.0, 3.0], [0.5, 0.5, 0.5, 0.6])),
        ErrorKind::InvalidArgument
    );
    assert_eq!(
        kind(w.set_orientation(b, [1.0, 1.0, 0.0, 0.0])),
        ErrorKind::InvalidArgument
    );
    assert_eq!(
        kind(w.set_position(b, [0.0, -f64::INFINITY, 0.0])),
        ErrorKind::InvalidArgument
    );
    assert_eq!(w.get_pose(b).unwrap(), before);
    assert_eq!(
        kind(w.set_velocity(b, [f64::NAN; 3])),
        ErrorKind::InvalidArgument
    );
    assert_eq!(w.get_velocity(b).unwrap(), [0.0; 3]);

    // Partial updates keep the other half.
    w.set_position(b, [1.0, 2.0, 3.0]).unwrap();
    let h = std::f64::consts::FRAC_1_SQRT_2;
    w.set_orientation(b, [0.0, 0.0, h, h]).unwrap();
    let pose = w.get_pose(b).unwrap();
    assert_eq!(pose.position, [1.0, 2.0, 3.0]);
    assert_eq!(pose.orientation, [0.0, 0.0, h, h]);
}

#[test]
fn invalid_world_descriptors() {
    for desc in [
        WorldDesc {
            time_step: f64::NAN,
            ..WorldDesc::default()
        },
        WorldDesc {
            time_step: -1.0,
            ..WorldDesc::default()
        },
        WorldDesc {
            reflect_at_bounds: true,
            bounds_min: [1.0; 3],
            bounds_max: [0.0; 3],
            ..WorldDesc::default()
        },
        WorldDesc {
            min_cell_size: -1.0,
            ..WorldDesc::default()
        },
        WorldDesc {
            min_cell_size: 4.0,
            max_cell_size: 2.0,
            ..WorldDesc::default()
        },
    ] {
        let e = World::new(&desc).unwrap_err();
        assert_eq!(e.kind(), ErrorKind::InvalidArgument, "{desc:?}");
    }
    // Bounds are read only when the world reflects.
    let ignored = WorldDesc {
        bounds_min: [1.0; 3],
        bounds_max: [f64::NAN; 3],
        ..WorldDesc::default()
    };
    assert!(World::new(&ignored).is_ok());
}

#[test]
fn step_out_of_range_moves_nothing() {
    let mut w = world();
    let m = tetra(&mut w);
    let still = body_at(&mut w, m, 5.0);
    let b = w
        .create_body(&BodyDesc {
            velocity: [f64::MAX, 0.0, 0.0],
            ..BodyDesc::new(m)
        })
        .unwrap();
    w.set_velocity(still, [1.0, 0.0, 0.0]).unwrap();
    let e = w.step().unwrap_err();
    assert_eq!(e.kind(), ErrorKind::InvalidArgument);
    assert!(!e.message().is_empty());
    // Nothing moved, not even the body with a harmless velocity.
    assert_eq!(w.get_pose(b).unwrap().position, [0.0; 3]);
    assert_eq!(w.get_pose(still).unwrap().position, [5.0, 0.0, 0.0]);
    w.set_velocity(b, [0.0; 3]).unwrap();
    w.step().unwrap();
    assert_eq!(w.get_pose(still).unwrap().position, [6.0, 0.0, 0.0]);
}

#[test]
fn pairs_detect_and_stats() {
    let mut w = world();
    let m = tetra(&mut w);
    let a = body_at(&mut w, m, 0.0);
    let b = body_at(&mut w, m, 1.0);
    let c = body_at(&mut w, m, 50.0);
    assert!(w.pairs().is_empty());
    assert_eq!(w.stats(), hgcd::Stats::default());
    w.detect().unwrap();
    assert_eq!(w.pairs(), &[Pair { a, b }]);
    assert_eq!(w.stats().colliding_pairs, 1);
    // Move c onto a: two pairs, sorted.
    w.set_position(c, [0.5, 0.0, 0.0]).unwrap();
    w.detect().unwrap();
    assert_eq!(
        w.pairs(),
        &[Pair { a, b }, Pair { a, b: c }, Pair { a: b, b: c }]
    );
    // A small tetrahedron wholly inside a big one: containment.
    let inner = w
        .create_body(&BodyDesc {
            position: [100.0, 100.0, 100.0],
            scale: 0.01,
            ..BodyDesc::new(m)
        })
        .unwrap();
    let outer = w
        .create_body(&BodyDesc {
            position: [100.0, 100.0, 100.0],
            scale: 10.0,
            ..BodyDesc::new(m)
        })
        .unwrap();
    w.detect().unwrap();
    assert!(w.pairs().contains(&Pair { a: inner, b: outer }));
    assert_eq!(w.stats().containment_pairs, 1);
    // Destroyed bodies leave the pairs at the next detect.
    w.destroy_body(a).unwrap();
    w.detect().unwrap();
    assert_eq!(
        w.pairs(),
        &[Pair { a: b, b: c }, Pair { a: inner, b: outer }]
    );
    w.set_thread_count(1).unwrap();
    w.step().unwrap();
    assert_eq!(w.stats().thread_count, 1);
    assert_eq!(w.pairs().len(), 2);
}

#[test]
fn body_accessors() {
    let mut w = world();
    let m = tetra(&mut w);
    let d = BodyDesc {
        position: [1.0, 2.0, 3.0],
        velocity: [0.5, 0.0, -0.5],
        scale: 2.0,
        user_data: 0xdead_beef,
        ..BodyDesc::new(m)
    };
    let b = w.create_body(&d).unwrap();
    assert_eq!(w.body_mesh(b).unwrap(), m);
    assert_eq!(w.body_user_data(b).unwrap(), 0xdead_beef);
    assert_eq!(w.get_velocity(b).unwrap(), [0.5, 0.0, -0.5]);
    w.set_velocity(b, [0.0, 1.0, 0.0]).unwrap();
    w.step().unwrap();
    assert_eq!(w.get_pose(b).unwrap().position, [1.0, 3.0, 3.0]);
    let defaults = BodyDesc::default();
    assert_eq!(
        (defaults.orientation, defaults.scale, defaults.position),
        (IDENTITY, 1.0, [0.0; 3])
    );
    let wd = WorldDesc::default();
    assert_eq!(
        (wd.thread_count, wd.reflect_at_bounds, wd.time_step),
        (0, false, 1.0)
    );
}

#[test]
fn error_type() {
    let mut w = world();
    let e = w.destroy_body(BodyId::NULL).unwrap_err();
    assert_eq!(e.code(), sys::HGCD_ERROR_STALE_ID);
    let shown = e.to_string();
    assert!(shown.starts_with("HGCD_ERROR_STALE_ID: "), "{shown}");
    assert!(shown.ends_with(e.message()));
    assert_eq!(w.last_error(), e.message());
    let boxed: Box<dyn std::error::Error + Send + Sync> = Box::new(e.clone());
    assert_eq!(boxed.to_string(), shown);
    for code in -10..=-1 {
        let k = ErrorKind::from_code(code);
        assert!(!matches!(k, ErrorKind::Unknown(_)));
        assert_eq!(k.code(), code);
        assert!(k.name().starts_with("HGCD_ERROR_"));
    }
    assert_eq!(ErrorKind::from_code(-99), ErrorKind::Unknown(-99));
    assert_eq!(
        ErrorKind::Unknown(-99).to_string(),
        "HGCD_ERROR_UNKNOWN (-99)"
    );
    let rust_side = Error::new(ErrorKind::Capacity, "");
    assert_eq!(rust_side.to_string(), "HGCD_ERROR_CAPACITY");
}

#[test]
fn ids_are_values() {
    let mut w = world();
    let m = tetra(&mut w);
    let ids: Vec<BodyId> = (0..10)
        .map(|i| body_at(&mut w, m, 10.0 * i as f64))
        .collect();
    let set: HashSet<BodyId> = ids.iter().copied().collect();
    assert_eq!(set.len(), 10);
    let mut sorted = ids.clone();
    sorted.reverse();
    sorted.sort();
    assert_eq!(sorted, ids);
    let raw: sys::hgcd_body = ids[3].into();
    assert_eq!(BodyId::from(raw), ids[3]);
    assert_eq!(
        format!("{:?}", ids[3]),
        format!("BodyId {{ index: 3, generation: {} }}", ids[3].generation())
    );
}

#[test]
fn raw_handle_roundtrip_and_drop() {
    // Many worlds created and dropped: Drop frees them (run under valgrind or
    // ASan for a leak check; here it must simply not crash).
    for _ in 0..200 {
        let mut w = world();
        let m = tetra(&mut w);
        body_at(&mut w, m, 0.0);
        w.detect().unwrap();
    }
    let mut w = world();
    tetra(&mut w);
    let raw = w.into_raw();
    // SAFETY: `raw` came from into_raw and is used by nothing else.
    let w = unsafe { World::from_raw(raw) };
    assert_eq!(w.mesh_count(), 1);
    assert_eq!(unsafe { sys::hgcd_world_mesh_count(w.as_ptr()) }, 1);
    assert!(format!("{w:?}").contains("meshes: 1"));
}

#[test]
fn versions_agree() {
    assert_eq!(hgcd::version(), hgcd::HEADER_VERSION);
    let (a, b, c) = hgcd::HEADER_VERSION;
    assert_eq!(hgcd::version_string(), format!("{a}.{b}.{c}"));
}

#[test]
fn pair_layout_matches_c() {
    use std::mem::{align_of, size_of};
    assert_eq!(size_of::<Pair>(), size_of::<sys::hgcd_pair>());
    assert_eq!(align_of::<Pair>(), align_of::<sys::hgcd_pair>());
    // Field offsets, via a real value (no offset_of!: Rust 1.63 compatible).
    let p = Pair {
        a: BodyId::NULL,
        b: BodyId::NULL,
    };
    let base = &p as *const Pair as usize;
    assert_eq!(&p.a as *const BodyId as usize - base, 0);
    assert_eq!(&p.b as *const BodyId as usize - base, 8);
    let raw = sys::hgcd_pair {
        a: BodyId::NULL.to_raw(),
        b: BodyId::NULL.to_raw(),
    };
    let raw_base = &raw as *const sys::hgcd_pair as usize;
    assert_eq!(&raw.b as *const sys::hgcd_body as usize - raw_base, 8);
    // A slice of C pairs reads back as the same ids.
    let c_pairs = [sys::hgcd_pair {
        a: sys::hgcd_body {
            index: 1,
            generation: 2,
        },
        b: sys::hgcd_body {
            index: 3,
            generation: 4,
        },
    }];
    let rust: &[Pair] = unsafe { std::slice::from_raw_parts(c_pairs.as_ptr().cast::<Pair>(), 1) };
    assert_eq!(rust[0].indices(), (1, 3));
    assert_eq!((rust[0].a.generation(), rust[0].b.generation()), (2, 4));
    assert_eq!(
        size_of::<Option<World>>(),
        size_of::<*mut sys::hgcd_world>()
    );
}
