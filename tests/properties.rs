//! Property tests of the Rust core (proptest, a fixed budget of cases each so
//! that `cargo test --release` stays fast): the polar decomposition, mass
//! properties against closed forms, the narrow phase and contact solve
//! (finite, momentum-conserving for any pair of convex shapes at any poses),
//! and snapshot bytes (a world read back steps on bitwise as the original).

use nalgebra::{Isometry3, Translation3, UnitQuaternion, Vector3};
use proptest::prelude::*;
use rigidrs::body::Shape;
use rigidrs::math::polar::{polar, PolarMethod};
use rigidrs::math::Mat3;
use rigidrs::world::{BodySpec, Scene, Settings, World};

fn cases(n: u32) -> ProptestConfig {
    ProptestConfig { cases: n, failure_persistence: None, ..ProptestConfig::default() }
}

fn matrix() -> impl Strategy<Value = Mat3> {
    prop::array::uniform9(-10.0f64..10.0).prop_map(|a| Mat3::from_row_slice(&a))
}

fn unit_quat() -> impl Strategy<Value = [f64; 4]> {
    prop::array::uniform4(-1.0f64..1.0).prop_filter_map("zero quaternion", |q| {
        let n = q.iter().map(|x| x * x).sum::<f64>().sqrt();
        (n > 1e-3).then(|| q.map(|x| x / n))
    })
}

/// A convex shape of sizes 0.05–1 m.
fn convex() -> impl Strategy<Value = Shape> {
    let size = 0.05f64..1.0;
    (0..5usize, size.clone(), size.clone(), size).prop_map(|(k, a, b, c)| match k {
        0 => Shape::sphere(a).unwrap(),
        1 => Shape::cuboid([a, b, c]).unwrap(),
        2 => Shape::capsule(a, b).unwrap(),
        3 => Shape::cylinder(a, b).unwrap(),
        _ => Shape::cone(a, b).unwrap(),
    })
}

fn frobenius(m: &Mat3) -> f64 {
    m.norm()
}

proptest! {
    #![proptest_config(cases(256))]

    /// `M = R S` with `R` a proper rotation and `S` symmetric, to round-off
    /// relative to `|M|` (1e-9: the iterations stop at ~1e-12; SVD is backward
    /// stable to ~1e-15), for SVD and Higham on any matrix; Müller's rotation
    /// is proper for any matrix too.
    #[test]
    fn polar_decomposition_is_a_rotation_times_a_symmetric_matrix(m in matrix()) {
        let scale = frobenius(&m).max(1e-300);
        for method in [PolarMethod::Svd, PolarMethod::Higham] {
            let p = polar(&m, method, None).unwrap();
            prop_assert!((p.r.transpose() * p.r - Mat3::identity()).norm() < 1e-9, "{method:?}: RᵀR ≠ I");
            prop_assert!((p.r.determinant() - 1.0).abs() < 1e-9, "{method:?}: det R = {}", p.r.determinant());
            prop_assert!((p.r * p.s - m).norm() < 1e-9 * scale, "{method:?}: RS ≠ M");
            prop_assert!((p.s - p.s.transpose()).norm() < 1e-9 * scale, "{method:?}: S not symmetric");
        }
        let p = polar(&m, PolarMethod::Muller, None).unwrap();
        prop_assert!((p.r.transpose() * p.r - Mat3::identity()).norm() < 1e-9);
        prop_assert!((p.r.determinant() - 1.0).abs() < 1e-9);
    }

    /// A box's and a ball's mass and inertia are the closed forms
    /// (`8abcρ`, `m(b² + c²)/3`; `4/3 πr³ρ`, `2/5 m r²`) to 1e-12 relative; a
    /// compound of one box moved by `d` and turned by `q` has the same mass,
    /// its centre at `d` and its inertia `R I Rᵀ` (parallel-axis bookkeeping).
    #[test]
    fn mass_properties_match_closed_forms(a in 0.01f64..3.0, b in 0.01f64..3.0, c in 0.01f64..3.0,
                                          rho in 1e-3f64..1e4, d in prop::array::uniform3(-5.0f64..5.0),
                                          q in unit_quat()) {
        let bx = Shape::cuboid([a, b, c]).unwrap().mass_properties(rho).unwrap();
        let m = 8.0 * a * b * c * rho;
        prop_assert!((bx.mass - m).abs() <= 1e-12 * m);
        let expect = Mat3::from_diagonal(&Vector3::new(m * (b * b + c * c) / 3.0, m * (a * a + c * c) / 3.0, m * (a * a + b * b) / 3.0));
        prop_assert!((bx.inertia - expect).norm() <= 1e-12 * expect.norm());
        let ball = Shape::sphere(a).unwrap().mass_properties(rho).unwrap();
        let mb = 4.0 / 3.0 * std::f64::consts::PI * a.powi(3) * rho;
        prop_assert!((ball.mass - mb).abs() <= 1e-12 * mb);
        prop_assert!((ball.inertia - Mat3::identity() * (0.4 * mb * a * a)).norm() <= 1e-12 * mb * a * a);
        let rot = UnitQuaternion::from_quaternion(nalgebra::Quaternion::new(q[3], q[0], q[1], q[2]));
        let pose = Isometry3::from_parts(Translation3::new(d[0], d[1], d[2]), rot);
        let moved = Shape::compound(vec![(pose, Shape::cuboid([a, b, c]).unwrap())]).unwrap().mass_properties(rho).unwrap();
        prop_assert!((moved.mass - m).abs() <= 1e-12 * m);
        prop_assert!((moved.com - Vector3::from(d)).norm() <= 1e-12 * (1.0 + Vector3::from(d).norm()));
        let r = rot.to_rotation_matrix().into_inner();
        let turned = r * expect * r.transpose();
        // The compound's inertia is summed about the origin and moved back to the
        // centre (m d² cancels): the error is relative to m |d|², not to I.
        let scale = expect.norm() + m * Vector3::from(d).norm_squared();
        prop_assert!((moved.inertia - turned).norm() <= 1e-10 * scale);
    }
}

/// Two free bodies (no gravity) of random convex shapes, poses and velocities,
/// often overlapping: one step.
fn pair_world(a: Shape, b: Shape, x: [f64; 3], qa: [f64; 4], qb: [f64; 4], v: [f64; 3]) -> World {
    let mut scene = Scene::new([0.0; 3]).unwrap();
    let spec = |shape, position, orientation, linear_velocity| BodySpec {
        shape: Some(shape),
        density: Some(1000.0),
        position,
        orientation,
        linear_velocity,
        ..Default::default()
    };
    scene.add_body(spec(a, [0.0; 3], qa, v)).unwrap();
    scene.add_body(spec(b, x, qb, [0.0; 3])).unwrap();
    scene.build(&Settings::new(1.0 / 240.0)).unwrap()
}

fn momentum(w: &World) -> Vector3<f64> {
    let b = &w.bodies;
    (0..2).map(|i| Vector3::from(b.linear_velocity[i]) * b.mass[i]).sum()
}

proptest! {
    #![proptest_config(cases(128))]

    /// Whatever two convex shapes do (touching, overlapping deeply, apart),
    /// the narrow phase and the contact solve leave every value finite and
    /// exchange equal and opposite impulses: the total linear momentum after
    /// 5 steps is the initial one to 1e-9 relative (round-off of the impulse
    /// sums; the push-out of overlaps is a velocity too, and pairwise).
    #[test]
    fn contact_between_any_two_convex_shapes_is_finite_and_conserves_momentum(
        a in convex(), b in convex(), x in prop::array::uniform3(-1.5f64..1.5), qa in unit_quat(), qb in unit_quat(),
        v in prop::array::uniform3(-5.0f64..5.0)) {
        let mut w = pair_world(a, b, x, qa, qb, v);
        let p0 = momentum(&w);
        w.step(5).unwrap();
        let b = &w.bodies;
        for i in 0..2 {
            prop_assert!(b.position[i].iter().chain(&b.linear_velocity[i]).chain(&b.angular_velocity[i]).all(|x| x.is_finite()));
        }
        let scale = p0.norm() + b.mass[0].max(b.mass[1]) * 1.0;
        prop_assert!((momentum(&w) - p0).norm() <= 1e-9 * scale, "momentum {:?} → {:?}", p0, momentum(&w));
    }

    /// A world saved to bytes after `k` steps and read back steps on bitwise
    /// as the original (a random pile of boxes and balls over a floor: contacts,
    /// warm starts, sleep timers all travel in the bytes).
    #[test]
    fn snapshot_bytes_round_trip_steps_on_bitwise(n in 1usize..6, k in 0u64..60, seed in prop::array::uniform3(-0.3f64..0.3)) {
        let mut scene = Scene::new([0.0, 0.0, -9.81]).unwrap();
        let floor = BodySpec { shape: Some(Shape::cuboid([3.0, 3.0, 0.5]).unwrap()), fixed: true, ..Default::default() };
        scene.add_body(floor).unwrap();
        for i in 0..n {
            let shape = if i % 2 == 0 { Shape::cuboid([0.2, 0.15, 0.1]).unwrap() } else { Shape::sphere(0.15).unwrap() };
            let position = [seed[0] * i as f64, seed[1], 0.8 + 0.35 * i as f64 + seed[2]];
            scene.add_body(BodySpec { shape: Some(shape), density: Some(500.0), position, ..Default::default() }).unwrap();
        }
        let mut world = scene.build(&Settings::new(1.0 / 120.0)).unwrap();
        world.step(k).unwrap();
        let mut copy = World::from_bytes(&world.to_bytes().unwrap()).unwrap();
        world.step(30).unwrap();
        copy.step(30).unwrap();
        let bits = |w: &World| -> Vec<u64> {
            let b = &w.bodies;
            (0..b.len()).flat_map(|i| b.position[i].iter().chain(&b.orientation[i]).chain(&b.linear_velocity[i]).map(|x| x.to_bits()).collect::<Vec<_>>()).collect()
        };
        prop_assert_eq!(bits(&world), bits(&copy));
    }
}
