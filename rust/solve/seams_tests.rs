use crate::body::Shape;
use crate::solve::island_sweeps::tests::{bits, step_alike};
use crate::world::{BodySpec, Scene, Settings, World};

/// 1000 balls of 0.1 m in a lattice 0.2 m apart (touching) in a box of
/// fixed walls: some 2800 touching pairs from the first step.
pub(crate) fn lattice_pit(threads: u32) -> World {
    let mut sc = Scene::new([0.0, 0.0, -9.81]).unwrap();
    let (half, t) = (1.0, 0.1);
    let walls = [
        ([0.0, 0.0, -t], [half + 2.0 * t, half + 2.0 * t, t]),
        ([half + t, 0.0, 1.0], [t, half + 2.0 * t, 1.0]),
        ([-half - t, 0.0, 1.0], [t, half + 2.0 * t, 1.0]),
        ([0.0, half + t, 1.0], [half, t, 1.0]),
        ([0.0, -half - t, 1.0], [half, t, 1.0]),
    ];
    for (c, h) in walls {
        sc.add_body(BodySpec { shape: Some(Shape::cuboid(h).unwrap()), fixed: true, position: c, ..Default::default() }).unwrap();
    }
    let ball = Shape::sphere(0.1).unwrap();
    for i in 0..1000 {
        let (x, y, z) = ((i % 10) as f64, ((i / 10) % 10) as f64, (i / 100) as f64);
        // A deterministic jitter: not a perfect lattice.
        let j = 1e-3 * ((i as f64 * 0.754877).fract() - 0.5);
        let position = [(x - 4.5) * 0.2 + j, (y - 4.5) * 0.2 - j, 0.1 + z * 0.2];
        sc.add_body(BodySpec { shape: Some(ball.clone()), density: Some(1000.0), position, ..Default::default() }).unwrap();
    }
    let mut settings = Settings::new(1.0 / 60.0);
    settings.sleep.enabled = false;
    settings.threads = Some(threads);
    sc.build(&settings).unwrap()
}

/// The pit's contacts are laid out in halves and passed over side by side
/// on two threads (checked, so that the test tests that), and every step
/// ends in the bits of one thread; on three threads too.
#[test]
fn a_pit_split_in_halves_gives_the_bits_of_one_thread() {
    let (mut one, mut two, mut three) = (lattice_pit(1), lattice_pit(2), lattice_pit(3));
    let mut split = 0;
    for _ in 0..40 {
        step_alike([&mut one, &mut two, &mut three]);
        let halves = |w: &World| w.collision.as_ref().and_then(|c| c.solver.halves);
        assert_eq!(halves(&one), halves(&two), "the layout does not follow the thread count");
        split += (halves(&two).is_some() && two.contact_threads == 2) as u32;
    }
    assert!(split >= 35, "the halves went side by side in {split} steps of 40");
}

/// A world restored from its bytes mid-run builds its contacts as the one
/// that kept going (the layout follows the last step's plan, kept in the
/// snapshot) and ends in the same bits.
#[test]
fn a_split_pit_restored_from_bytes_steps_to_the_same_bits() {
    let mut kept = lattice_pit(2);
    kept.step(20).unwrap();
    let mut restored = World::from_bytes(&kept.to_bytes().unwrap()).unwrap();
    assert!(restored.collision.as_ref().is_some_and(|c| c.solver.split), "the snapshot keeps the split");
    kept.step(20).unwrap();
    restored.step(20).unwrap();
    assert!(bits(&kept) == bits(&restored));
}

/// Sides and parts: a contact joining the halves, or touching a kinematic
/// body, is the seam's; one with a fixed body is its dynamic body's half.
#[test]
fn the_seam_takes_what_joins_the_halves_or_touches_a_kinematic_body() {
    let s = super::ContactSolver { side: vec![super::NO_SIDE, 0, 1, 0, super::KINEMATIC], ..Default::default() };
    assert_eq!(s.part_of(1, 3), 0);
    assert_eq!(s.part_of(2, 2), 1);
    assert_eq!(s.part_of(0, 2), 1);
    assert_eq!(s.part_of(1, 2), super::SEAM);
    assert_eq!(s.part_of(4, 1), super::SEAM);
    assert_eq!(s.part_of(0, 0), 0);
}
