//! Body types, enabling, filters and excluded pairs through the safe API:
//! three overlapping bodies, each rule switching one pair off and on.

use hgcd::{BodyDesc, BodyId, BodyType, ErrorKind, Filter, MeshDesc, Pair, World, WorldDesc};

fn world_of_three(kinematic_pairs: bool) -> (World, Vec<BodyId>) {
    let mut world = World::new(&WorldDesc {
        kinematic_pairs,
        ..WorldDesc::default()
    })
    .unwrap();
    let (v, t) = hgcd::scene::unit_mesh();
    let mesh = world.create_mesh(&MeshDesc::new(&v, &t)).unwrap();
    let bodies = (0..3)
        .map(|i| {
            let mut d = BodyDesc::new(mesh);
            d.position[0] = 0.1 * i as f64;
            d.user_data = 100 + i as u64;
            world.create_body(&d).unwrap()
        })
        .collect();
    (world, bodies)
}

fn indices(world: &mut World) -> Vec<(u32, u32)> {
    world.detect().unwrap();
    world.pairs().iter().map(Pair::indices).collect()
}

#[test]
fn types_decide_which_pairs_are_considered() {
    for kinematic_pairs in [false, true] {
        let (mut world, b) = world_of_three(kinematic_pairs);
        assert_eq!(indices(&mut world), vec![(0, 1), (0, 2), (1, 2)]);
        world.set_body_type(b[0], BodyType::Static).unwrap();
        world.set_body_type(b[1], BodyType::Static).unwrap();
        world.set_body_type(b[2], BodyType::Kinematic).unwrap();
        assert_eq!(world.body_type(b[2]).unwrap(), BodyType::Kinematic);
        let expect = if kinematic_pairs { vec![(0, 2), (1, 2)] } else { vec![] };
        assert_eq!(indices(&mut world), expect);
        world.set_body_type(b[2], BodyType::Dynamic).unwrap();
        assert_eq!(indices(&mut world), vec![(0, 2), (1, 2)]);
        assert_eq!(world.stats().filtered_pairs, 1);
    }
}

#[test]
fn enabling_filters_and_exclusions() {
    let (mut world, b) = world_of_three(false);
    world.set_body_enabled(b[1], false).unwrap();
    assert!(!world.is_body_enabled(b[1]).unwrap());
    assert_eq!(indices(&mut world), vec![(0, 2)]);
    world.set_body_enabled(b[1], true).unwrap();
    let lonely = Filter {
        category_bits: 2,
        mask_bits: 2,
        group_index: 0,
    };
    world.set_body_filter(b[0], &lonely).unwrap();
    assert_eq!(world.body_filter(b[0]).unwrap(), lonely);
    assert_eq!(indices(&mut world), vec![(1, 2)]);
    world.set_body_filter(b[0], &Filter::default()).unwrap();
    world.exclude_pair(b[2], b[1]).unwrap();
    assert!(world.is_pair_excluded(b[1], b[2]).unwrap());
    assert_eq!(indices(&mut world), vec![(0, 1), (0, 2)]);
    world.include_pair(b[1], b[2]).unwrap();
    assert_eq!(indices(&mut world), vec![(0, 1), (0, 2), (1, 2)]);
    let e = world.exclude_pair(b[1], b[1]).unwrap_err();
    assert_eq!(e.kind(), ErrorKind::InvalidArgument);
}

#[test]
fn events_carry_user_data_of_destroyed_bodies() {
    let (mut world, b) = world_of_three(false);
    world.detect().unwrap();
    let (began, ended) = world.events();
    assert_eq!(began.len(), 3);
    assert!(ended.is_empty());
    world.destroy_body(b[1]).unwrap();
    world.detect().unwrap();
    let (began, ended) = world.events();
    assert!(began.is_empty());
    let ended: Vec<(u32, u32, u64, u64)> = ended
        .iter()
        .map(|e| (e.pair.a.index(), e.pair.b.index(), e.user_data_a, e.user_data_b))
        .collect();
    assert_eq!(ended, vec![(0, 1, 100, 101), (1, 2, 101, 102)]);
    world.detect().unwrap();
    assert_eq!(world.events(), (&[][..], &[][..]));
}
