//! The scene queries over slices: rays, boxes, points and meshes at a pose,
//! checked against what each body is known to be (the scene's tetrahedra
//! hold their centres; the unit tetrahedron's faces are the planes
//! x + y + z = -1 and x + y - z = x - y + z = -x + y + z = 1), the same
//! answers on 1 and 2 threads, and refusals.

use hgcd::scene::TetraDesc;
use hgcd::{BodyDesc, ErrorKind, Filter, MeshDesc, MeshPose, Ray, RayMode, World, WorldDesc};

fn unit_world() -> (World, hgcd::MeshId, hgcd::BodyId) {
    let mut world = World::new(&WorldDesc::default()).unwrap();
    let (v, t) = hgcd::scene::unit_mesh();
    let mesh = world.create_mesh(&MeshDesc::new(&v, &t)).unwrap();
    let body = world.create_body(&BodyDesc::new(mesh)).unwrap();
    (world, mesh, body)
}

#[test]
fn rays_hit_the_unit_tetrahedron() {
    let (mut world, _, body) = unit_world();
    let rays = [
        Ray { origin: [-5.0, 0.0, 0.0], direction: [1.0, 0.0, 0.0], max_distance: 10.0 },
        Ray { origin: [0.0, 0.0, 0.0], direction: [0.0, 1.0, 0.0], max_distance: 1.0 },
        Ray { origin: [-5.0, 3.0, 0.0], direction: [1.0, 0.0, 0.0], max_distance: 10.0 },
        Ray { origin: [-5.0, 0.0, 0.0], direction: [2.0, 0.0, 0.0], max_distance: 2.0 },
    ];
    let hits = world.cast_rays(&rays, RayMode::Closest, None).unwrap();
    assert_eq!(hits[0].body, body);
    assert_eq!(hits[0].distance, 4.0); // enters at x = -1
    assert_eq!(hits[0].inside, 0);
    assert!(hits[1].is_hit() && hits[1].inside == 1 && hits[1].distance == 0.0 && hits[1].triangle == u32::MAX);
    assert!(!hits[2].is_hit());
    assert_eq!(hits[3].distance, 2.0); // ends exactly on the face: t = 1
    let any = world.cast_rays(&rays, RayMode::Any, None).unwrap();
    for (a, c) in any.iter().zip(&hits) {
        assert_eq!(a.is_hit(), c.is_hit());
    }
}

#[test]
fn queries_on_a_scene_agree_with_the_bodies_and_across_threads() {
    let desc = TetraDesc { side: 200.0 * (2000.0f64 / 750_000.0).cbrt(), ..TetraDesc::new(2000, 3) };
    let scene = desc.generate().unwrap();
    let mut world = World::new(&desc.world_desc(1)).unwrap();
    let (_, bodies) = scene.populate(&mut world).unwrap();
    // Every body holds its centre.
    let centres: Vec<[f64; 3]> = scene.centers.clone();
    {
        let res = world.query_points(&centres, None).unwrap();
        assert_eq!(res.len(), centres.len());
        for (k, found) in res.iter().enumerate() {
            assert!(found.contains(&bodies[k]), "point {k}");
            assert!(found.windows(2).all(|w| w[0].index() < w[1].index()));
        }
    }
    // A box around a centre finds that body; a mesh at a body's own pose
    // collides with it.
    let boxes: Vec<[f64; 6]> = centres.iter().map(|c| [c[0] - 0.1, c[1] - 0.1, c[2] - 0.1, c[0], c[1], c[2]]).collect();
    let res = world.query_boxes(&boxes, None).unwrap();
    for k in 0..boxes.len() {
        assert!(res.get(k).contains(&bodies[k]));
    }
    let mesh = world.body_mesh(bodies[0]).unwrap();
    let poses: Vec<MeshPose> = (0..50)
        .map(|k| {
            let p = world.get_pose(bodies[k]).unwrap();
            MeshPose { position: p.position, orientation: p.orientation, scale: scene.scales[k] }
        })
        .collect();
    let res = world.query_mesh(mesh, &poses, None).unwrap();
    for k in 0..poses.len() {
        assert!(res.get(k).contains(&bodies[k]));
    }
    // Rays: the same bits on 1 and 2 threads.
    let mut x: u64 = 0x1234_5678;
    let mut unif = || {
        x ^= x << 13;
        x ^= x >> 7;
        x ^= x << 17;
        (x >> 11) as f64 * (1.0 / (1u64 << 53) as f64)
    };
    let rays: Vec<Ray> = (0..3000)
        .map(|_| Ray {
            origin: [desc.side * unif(), desc.side * unif(), desc.side * unif()],
            direction: [unif() - 0.5, unif() - 0.5, unif() - 0.5],
            max_distance: desc.side * unif(),
        })
        .collect();
    let one = world.cast_rays(&rays, RayMode::Closest, None).unwrap();
    world.set_thread_count(2).unwrap();
    let two = world.cast_rays(&rays, RayMode::Closest, None).unwrap();
    assert_eq!(one, two);
    assert!(one.iter().filter(|h| h.is_hit()).count() > 100);
    // A filter that takes no category finds nothing.
    let none = Filter { category_bits: 1, mask_bits: 0, group_index: 0 };
    assert!(world.cast_rays(&rays, RayMode::Closest, Some(&none)).unwrap().iter().all(|h| !h.is_hit()));
    // The group decides before the bits, as between bodies: with every body
    // in group -3, a query of group -3 whose bits accept them all hits
    // nothing; in group 3, one whose bits accept none hits all it did.
    let first = world.query_boxes(&[[-1e9, -1e9, -1e9, 1e9, 1e9, 1e9]], None).unwrap().get(0).to_vec();
    let grouped = Filter { category_bits: 1, mask_bits: u64::MAX, group_index: -3 };
    for &b in &first {
        world.set_body_filter(b, &grouped).unwrap();
    }
    assert!(world.cast_rays(&rays, RayMode::Closest, Some(&grouped)).unwrap().iter().all(|h| !h.is_hit()));
    let friends = Filter { category_bits: 1, mask_bits: 0, group_index: 3 };
    for &b in &first {
        world.set_body_filter(b, &friends).unwrap();
    }
    assert_eq!(world.cast_rays(&rays, RayMode::Closest, Some(&friends)).unwrap(), two);
}

#[test]
fn refusals() {
    let (mut world, mesh, _) = unit_world();
    let bad = [Ray { origin: [f64::NAN, 0.0, 0.0], direction: [1.0, 0.0, 0.0], max_distance: 1.0 }];
    let err = world.cast_rays(&bad, RayMode::Closest, None).unwrap_err();
    assert_eq!(err.kind(), ErrorKind::InvalidArgument);
    assert!(err.to_string().contains("ray 0"));
    let mut short = [];
    let err = world.cast_rays_into(&bad, RayMode::Any, None, &mut short).unwrap_err();
    assert_eq!(err.kind(), ErrorKind::InvalidArgument);
    let err = world.query_boxes(&[[1.0, 0.0, 0.0, 0.0, 1.0, 1.0]], None).unwrap_err();
    assert_eq!(err.kind(), ErrorKind::InvalidArgument);
    let pose = MeshPose { position: [0.0; 3], orientation: [0.0, 0.0, 0.0, 2.0], scale: 1.0 };
    assert_eq!(world.query_mesh(mesh, &[pose], None).unwrap_err().kind(), ErrorKind::InvalidArgument);
    assert!(world.query_points(&[], None).unwrap().is_empty());
}
