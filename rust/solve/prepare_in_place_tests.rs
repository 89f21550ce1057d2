use crate::solve::island_sweeps::tests::bits;
use crate::solve::seams::tests::lattice_pit;
use crate::world::World;

/// Pairs the last step built in place (the serial build's), and pairs.
fn in_place(w: &World) -> (usize, usize) {
    w.collision.as_ref().map_or((0, 0), |c| (c.solver.in_place, c.solver.constraints.len()))
}

/// A pit of 1000 balls resting in a lattice: on one thread its constraints
/// are updated in place once their pairs stop changing (checked, so that
/// the test tests that), on two they are laid out afresh over threads (the
/// build that never updates in place), and every step ends in the same bits.
#[test]
fn a_resting_pit_updated_in_place_gives_the_bits_of_the_build() {
    let (mut one, mut two) = (lattice_pit(1), lattice_pit(2));
    let mut whole = 0;
    for _ in 0..40 {
        one.step(1).unwrap();
        two.step(1).unwrap();
        assert!(bits(&one) == bits(&two));
        assert_eq!(in_place(&two).0, 0, "the parallel build does not update in place");
        let (done, pairs) = in_place(&one);
        whole += (done == pairs && pairs > 2000) as u32;
    }
    assert!(whole >= 20, "every pair was updated in place in {whole} steps of 40");
}

/// A ball made ten times heavier mid-run: its contacts are no longer
/// central (it may rest on the balls under it as on supports), so the
/// update in place stops at its first pair and the build takes the rest from
/// there, with the records updated before it; the same bits as the build
/// over threads.
#[test]
fn a_pit_whose_ball_got_heavy_ends_its_update_in_place_there() {
    let (mut one, mut two) = (lattice_pit(1), lattice_pit(2));
    for _ in 0..30 {
        one.step(1).unwrap();
        two.step(1).unwrap();
    }
    assert_eq!(in_place(&one).0, in_place(&one).1, "at rest, every pair in place");
    // A ball of the middle layer, away from the walls (body 0 is a wall).
    let heavy = 5 + 555;
    for w in [&mut one, &mut two] {
        w.bodies.mass[heavy] *= 10.0;
        w.bodies.inv_mass[heavy] /= 10.0;
    }
    one.step(1).unwrap();
    two.step(1).unwrap();
    let (done, pairs) = in_place(&one);
    assert!(done > 0 && done < pairs, "{done} of {pairs} pairs in place: the update did not stop midway");
    assert!(bits(&one) == bits(&two));
    for _ in 0..5 {
        one.step(1).unwrap();
        two.step(1).unwrap();
        assert!(bits(&one) == bits(&two));
    }
}

/// A resting pit restored from its bytes on one thread updates its
/// constraints in place as the one that kept going (last step's records are
/// in the snapshot) and ends in the same bits.
#[test]
fn a_resting_pit_restored_from_bytes_updates_in_place_to_the_same_bits() {
    let mut kept = lattice_pit(1);
    kept.step(30).unwrap();
    let mut restored = World::from_bytes(&kept.to_bytes().unwrap()).unwrap();
    for _ in 0..10 {
        kept.step(1).unwrap();
        restored.step(1).unwrap();
        assert_eq!(in_place(&kept), in_place(&restored));
        assert!(bits(&kept) == bits(&restored));
    }
    assert!(in_place(&restored).0 > 0, "the restored pit did not update in place");
}
