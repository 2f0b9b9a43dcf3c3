//! Contact margins through the safe API: two unit cubes a gap apart are a
//! pair exactly when the world margin plus both bodies' margins reach the
//! gap; contacts say NEAR; bad margins are refused and change nothing.

use hgcd::{BodyDesc, ContactKind, ErrorKind, MeshDesc, Pair, World, WorldDesc};

const CUBE_V: [[f64; 3]; 8] = [
    [-0.5, -0.5, -0.5],
    [0.5, -0.5, -0.5],
    [0.5, 0.5, -0.5],
    [-0.5, 0.5, -0.5],
    [-0.5, -0.5, 0.5],
    [0.5, -0.5, 0.5],
    [0.5, 0.5, 0.5],
    [-0.5, 0.5, 0.5],
];
const CUBE_T: [[u32; 3]; 12] = [
    [0, 2, 1],
    [0, 3, 2],
    [0, 1, 5],
    [0, 5, 4],
    [1, 2, 6],
    [1, 6, 5],
    [2, 3, 7],
    [2, 7, 6],
    [3, 0, 4],
    [3, 4, 7],
    [4, 5, 6],
    [4, 6, 7],
];

/// Two cubes whose faces are `gap` apart along x.
fn two_cubes(contact_margin: f64, gap: f64, contacts: bool) -> (World, Vec<hgcd::BodyId>) {
    let mut world = World::new(&WorldDesc {
        contact_margin,
        contacts,
        ..WorldDesc::default()
    })
    .unwrap();
    let mesh = world.create_mesh(&MeshDesc::new(&CUBE_V, &CUBE_T)).unwrap();
    let mut bodies = Vec::new();
    for x in [0.0, 1.0 + gap] {
        let mut d = BodyDesc::new(mesh);
        d.position[0] = x;
        bodies.push(world.create_body(&d).unwrap());
    }
    (world, bodies)
}

fn indices(world: &mut World) -> Vec<(u32, u32)> {
    world.detect().unwrap();
    world.pairs().iter().map(Pair::indices).collect()
}

#[test]
fn margins_add_up_exactly() {
    let gap = 0.375;
    let (mut world, b) = two_cubes(0.125, gap, false);
    assert!(indices(&mut world).is_empty());
    world.set_body_margin(b[0], 0.125).unwrap();
    assert!(indices(&mut world).is_empty());
    world.set_body_margin(b[1], 0.125).unwrap();
    assert_eq!(indices(&mut world), vec![(0, 1)]);
    assert_eq!(world.body_margin(b[1]).unwrap(), 0.125);
    // One ulp short of the gap: apart.
    world.set_body_margin(b[1], f64::from_bits(0.125f64.to_bits() - 1)).unwrap();
    world.set_body_margin(b[0], 0.0).unwrap();
    assert!(indices(&mut world).is_empty());
}

#[test]
fn near_contacts_and_refusals() {
    let (mut world, b) = two_cubes(0.5, 0.25, true);
    world.detect().unwrap();
    let c = world.contacts().unwrap();
    assert_eq!(c.len(), 1);
    assert!(matches!(c[0].kind, ContactKind::Near { .. }));
    for bad in [-1.0, f64::NAN, f64::INFINITY, 2e15] {
        let e = world.set_body_margin(b[0], bad).unwrap_err();
        assert_eq!(e.kind(), ErrorKind::InvalidArgument);
        assert_eq!(world.body_margin(b[0]).unwrap(), 0.0);
        assert!(World::new(&WorldDesc {
            contact_margin: bad,
            ..WorldDesc::default()
        })
        .is_err());
    }
}

#[test]
fn world_margin_set_later() {
    let (mut world, _) = two_cubes(0.0, 0.375, false);
    assert!(indices(&mut world).is_empty());
    world.set_contact_margin(0.375).unwrap();
    assert_eq!(world.contact_margin().unwrap(), 0.375);
    assert_eq!(indices(&mut world), vec![(0, 1)]);
    for bad in [-1.0, f64::NAN, f64::INFINITY, 2e15] {
        let e = world.set_contact_margin(bad).unwrap_err();
        assert_eq!(e.kind(), ErrorKind::InvalidArgument);
        assert_eq!(world.contact_margin().unwrap(), 0.375);
    }
    world.set_contact_margin(f64::from_bits(0.375f64.to_bits() - 1)).unwrap();
    assert!(indices(&mut world).is_empty());
}
