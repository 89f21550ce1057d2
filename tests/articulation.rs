//! Articulations through the Rust API, no Python: the closed form of a single
//! hinge agrees with the general articulated-body recursion, a spherical double
//! pendulum keeps its energy (bounded, second order), and a chain's joints never
//! open.

use rigidrs::body::Shape;
use rigidrs::math::{quat, Vec3};
use rigidrs::world::{BodySpec, Scene, Settings, World};
use rigidrs::xpbd::joints::{JointKind, JointSpec};

const G: f64 = 9.81;

fn ball(scene: &mut Scene, mass: f64, position: [f64; 3]) -> usize {
    let spec = BodySpec { shape: Some(Shape::sphere(0.05).unwrap()), mass: Some(mass), position, filter: none(), ..Default::default() };
    scene.add_body(spec).unwrap()
}

fn none() -> rigidrs::collide::Filter {
    rigidrs::collide::Filter { group: 1, mask: 0 }
}

fn joint(kind: JointKind, a: usize, b: Option<usize>, anchor: [f64; 3]) -> JointSpec {
    let mut s = JointSpec::new(kind, a, b);
    s.anchor = Some(anchor);
    s.axis = [0.0, 1.0, 0.0];
    s
}

fn energy(w: &World) -> f64 {
    w.kinetic_energy() + w.potential_energy()
}

#[test]
fn single_hinge_closed_form_matches_the_general_recursion() {
    // The same pendulum hung from the world (closed form) and from a fixed body
    // at the origin (general recursion): the same trajectory to round-off.
    let mut worlds = Vec::new();
    for on_fixed_body in [false, true] {
        let mut scene = Scene::new([0.0, 0.0, -G]).unwrap();
        let b = ball(&mut scene, 1.3, [0.6, 0.0, -0.8]);
        let parent = on_fixed_body.then(|| {
            let spec = BodySpec { shape: Some(Shape::sphere(0.01).unwrap()), fixed: true, filter: none(), ..Default::default() };
            scene.add_body(spec).unwrap()
        });
        scene.add_joint(joint(JointKind::Hinge, b, parent, [0.0; 3])).unwrap();
        let mut w = scene.build(&Settings::new(1.0 / 60.0)).unwrap();
        assert_eq!(w.stage_names(), ["articulation"]);
        w.step(300).unwrap();
        worlds.push(w);
    }
    let (p0, p1) = (Vec3::from(worlds[0].bodies.position[0]), Vec3::from(worlds[1].bodies.position[0]));
    assert!((p0 - p1).norm() < 1e-12, "{p0:?} {p1:?}");
    assert!((worlds[0].joint_position[0] - worlds[1].joint_position[0]).abs() < 1e-12);
}

fn spherical_double(substeps: u32) -> (f64, f64) {
    let mut scene = Scene::new([0.0, 0.0, -G]).unwrap();
    let spin = BodySpec {
        shape: Some(Shape::cuboid([0.05, 0.1, 0.2]).unwrap()),
        mass: Some(1.0),
        position: [0.3, 0.0, -0.2],
        angular_velocity: [0.5, 2.0, -1.0],
        filter: none(),
        ..Default::default()
    };
    let a = scene.add_body(spin).unwrap();
    let b = ball(&mut scene, 0.5, [0.6, 0.3, -0.5]);
    scene.add_joint(joint(JointKind::Spherical, a, None, [0.0; 3])).unwrap();
    scene.add_joint(joint(JointKind::Spherical, b, Some(a), [0.5, 0.1, -0.3])).unwrap();
    let mut s = Settings::new(1.0 / 120.0);
    s.articulation.substeps = Some(substeps);
    let mut w = scene.build(&s).unwrap();
    let e0 = energy(&w);
    let mut worst = 0.0f64;
    for _ in 0..600 {
        w.step(1).unwrap();
        worst = worst.max((energy(&w) - e0).abs());
        // The joint between the bodies never opens.
        let (pa, pb) = (Vec3::from(w.bodies.position[a]), Vec3::from(w.bodies.position[b]));
        let anchor_a = pa + quat::rotate(&w.bodies.q(a), &w.articulations.list[0].links[1].frames.anchor_parent);
        let anchor_b = pb + quat::rotate(&w.bodies.q(b), &w.articulations.list[0].links[1].frames.anchor_child);
        assert!((anchor_a - anchor_b).norm() < 1e-12);
    }
    (worst, e0.abs())
}

#[test]
fn spherical_double_pendulum_energy_is_second_order() {
    // A spinning box on a spherical joint carrying a ball on another, 5 s: the
    // energy error is bounded and falls by 4 per halving of the substep (second
    // order; measured ratio ~4.0).
    let (coarse, scale) = spherical_double(2);
    let (fine, _) = spherical_double(4);

    // Measured: 5.3e-3 J of 3.78 J at 2 substeps of 1/120 s, 1.3e-3 J at 4.
    assert!(coarse < 2e-3 * scale, "{coarse} of {scale}");
    let ratio = coarse / fine;
    assert!((3.3..=4.7).contains(&ratio), "ratio {ratio}");
}
