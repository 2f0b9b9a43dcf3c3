//! The narrow phase choice and the contacts through the safe API.

use hgcd::{BodyDesc, ContactKind, ErrorKind, MeshDesc, NarrowPhase, World, WorldDesc};

fn two_tetrahedra(desc: &WorldDesc) -> (World, hgcd::MeshId) {
    let mut world = World::new(desc).unwrap();
    let (vertices, triangles) = hgcd::scene::unit_mesh();
    let mesh = world
        .create_mesh(&MeshDesc::new(&vertices, &triangles))
        .unwrap();
    world.create_body(&BodyDesc::new(mesh)).unwrap();
    world
        .create_body(&BodyDesc {
            position: [1.0, 0.0, 0.0],
            ..BodyDesc::new(mesh)
        })
        .unwrap();
    (world, mesh)
}

#[test]
fn exact_contacts_name_a_triangle_pair() {
    let (mut world, _) = two_tetrahedra(&WorldDesc {
        contacts: true,
        ..WorldDesc::default()
    });
    world.detect().unwrap();
    let contacts = world.contacts().unwrap();
    assert_eq!(contacts.len(), 1);
    assert_eq!(contacts[0].pair, world.pairs()[0]);
    match contacts[0].kind {
        ContactKind::Surface {
            triangle_a,
            triangle_b,
        } => assert!(triangle_a < 4 && triangle_b < 4),
        other => panic!("expected a surface contact, got {other:?}"),
    }
    world.set_contacts(false).unwrap();
    world.detect().unwrap();
    assert_eq!(
        world.contacts().unwrap_err().kind(),
        ErrorKind::InvalidArgument
    );
    assert_eq!(world.stats().libccd_tests, 0);
}

#[test]
fn libccd_narrow_phase() {
    let desc = WorldDesc {
        narrow_phase: NarrowPhase::Gjk,
        contacts: true,
        ..WorldDesc::default()
    };
    if hgcd::libccd_precision() == 0 {
        assert_eq!(
            World::new(&desc).unwrap_err().kind(),
            ErrorKind::NotSupported
        );
        return;
    }
    let (mut world, mesh) = two_tetrahedra(&desc);
    assert_eq!(
        world.mesh_info(mesh).unwrap().narrow_phase,
        NarrowPhase::Gjk
    );
    assert_eq!(
        world.mesh_info(mesh).unwrap().narrow_phase_setting,
        NarrowPhase::World
    );
    world.detect().unwrap();
    assert_eq!(world.stats().libccd_tests, 1);
    match world.contacts().unwrap()[0].kind {
        ContactKind::Penetration { depth, normal, .. } => {
            assert!(depth > 0.0);
            let len =
                (normal[0] * normal[0] + normal[1] * normal[1] + normal[2] * normal[2]).sqrt();
            assert!((len - 1.0).abs() < 1e-9);
        }
        other => panic!("expected a penetration, got {other:?}"),
    }
    world
        .set_mesh_narrow_phase(mesh, NarrowPhase::Exact)
        .unwrap();
    world.set_narrow_phase(NarrowPhase::Mpr).unwrap();
    world.detect().unwrap();
    assert!(matches!(
        world.contacts().unwrap()[0].kind,
        ContactKind::Surface { .. }
    ));
    // A non-convex (open) mesh cannot take libccd.
    let tri = world
        .create_mesh(&MeshDesc::new(
            &[[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]],
            &[[0, 1, 2]],
        ))
        .unwrap();
    let err = world
        .set_mesh_narrow_phase(tri, NarrowPhase::Gjk)
        .unwrap_err();
    assert_eq!(err.kind(), ErrorKind::InvalidArgument);
    assert!(err.to_string().contains("not convex"), "{err}");
    assert_eq!(
        world
            .set_narrow_phase(NarrowPhase::World)
            .unwrap_err()
            .kind(),
        ErrorKind::InvalidArgument
    );
}
