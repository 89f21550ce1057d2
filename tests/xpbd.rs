//! XPBD through the Rust API, no Python: the stages a scene with particles gets,
//! the force read-back of a hanging chain (λ/h² equals the carried weight at rest,
//! for any split of substeps and iterations), and iteration independence of a
//! single compliant constraint.

use rigidrs::body::Shape;
use rigidrs::world::{BodySpec, Scene, Settings, World};
use rigidrs::xpbd::shape_matching::{ClusterSpec, Mode};
use rigidrs::xpbd::{Compliance, ParticleSpec};

const G: f64 = 9.81;

fn particle(p: [f64; 3], mass: f64, fixed: bool) -> ParticleSpec {
    ParticleSpec { mass, fixed, ..ParticleSpec::at(p) }
}

fn build(scene: &Scene, dt: f64, substeps: u32, iterations: u32) -> World {
    let mut s = Settings::new(dt);
    s.substeps = Some(substeps);
    s.iterations = iterations;
    scene.build(&s).unwrap()
}

#[test]
fn stages_follow_particles_and_clusters() {
    let mut scene = Scene::new([0.0, 0.0, 0.0]).unwrap();
    let ball = BodySpec { shape: Some(Shape::sphere(0.1).unwrap()), density: Some(1000.0), ..Default::default() };
    scene.add_body(ball).unwrap();
    assert_eq!(build(&scene, 0.01, 1, 1).stage_names(), ["translate", "rotate_isotropic"]);
    for p in [[0.0, 0.0, 1.0], [1.0, 0.0, 1.0], [0.0, 1.0, 1.0]] {
        scene.add_particle(&particle(p, 1.0, false)).unwrap();
    }
    assert_eq!(build(&scene, 0.01, 1, 1).stage_names(), ["translate", "rotate_isotropic", "xpbd"]);
    let spec = ClusterSpec { mode: Mode::Rigid, ..Default::default() };
    scene.add_shape_matching(&[0, 1, 2], spec).unwrap();
    let names = build(&scene, 0.01, 1, 1).stage_names();
    assert_eq!(names, ["translate", "rotate_isotropic", "xpbd", "shape_matching", "xpbd"]);
}

#[test]
fn hanging_chain_reads_back_its_carried_weights_for_every_split() {
    // 6 links of 0.3 kg, compliance 0: at rest the corrections of each substep
    // cancel gravity's drift g h² on every particle, which fixes λ/h² = −W_j.
    for (substeps, iterations) in [(1, 1), (1, 8), (8, 1), (3, 3)] {
        let mut scene = Scene::default();
        scene.add_particle(&particle([0.0; 3], 0.3, true)).unwrap();
        for k in 1..=6 {
            scene.add_particle(&particle([0.0, 0.0, -0.2 * k as f64], 0.3, false)).unwrap();
            scene.add_distance_constraint(k - 1, k, Compliance::default(), None).unwrap();
        }
        let mut world = build(&scene, 1.0 / 60.0, substeps, iterations);
        world.step(1800).unwrap();
        let f = world.constraint_forces();
        for (j, fj) in f.iter().enumerate() {
            let w = 0.3 * G * (6 - j) as f64;
            // Settled to 1e-9 of the load after 30 s (PBD damps a rigid chain fast).
            assert!((fj + w).abs() < 1e-9 * w, "{substeps}x{iterations} link {j}: {fj} vs {w}");
        }
    }
}

#[test]
fn compliant_constraint_is_iteration_independent() {
    // One spring (α = 1e-3 m/N) along its own line: the first pass solves it.
    let run = |iterations| {
        let mut scene = Scene::new([0.0; 3]).unwrap();
        scene.add_particle(&particle([0.0; 3], 1.0, true)).unwrap();
        scene.add_particle(&particle([1.5, 0.0, 0.0], 1.0, false)).unwrap();
        scene.add_distance_constraint(0, 1, Compliance::new(1e-3, 0.0).unwrap(), Some(1.0)).unwrap();
        let mut world = build(&scene, 1.0 / 240.0, 1, iterations);
        (0..480)
            .map(|_| {
                world.step(1).unwrap();
                world.particles().unwrap().position[1][0]
            })
            .collect::<Vec<f64>>()
    };
    let (a, b) = (run(1), run(64));
    let diff = a.iter().zip(&b).map(|(x, y)| (x - y).abs()).fold(0.0, f64::max);
    assert!(diff <= 1e-12, "{diff}");
}

#[test]
fn bad_input_names_the_constraint_and_leaves_the_scene_unchanged() {
    let mut scene = Scene::default();
    scene.add_particle(&particle([0.0; 3], 1.0, false)).unwrap();
    scene.add_particle(&particle([1.0, 0.0, 0.0], 1.0, false)).unwrap();
    let neg = scene.add_distance_constraint(0, 1, Compliance { alpha: -1.0, damping: 0.0 }, None).unwrap_err();
    assert!(neg.message.starts_with("constraint 0 (distance): compliance"), "{}", neg.message);
    let own = scene.add_distance_constraint(1, 1, Compliance::default(), None).unwrap_err();
    assert!(own.message.contains("particle 1 is constrained to itself"), "{}", own.message);
    let nan = scene.add_particle(&particle([f64::NAN, 0.0, 0.0], 1.0, false)).unwrap_err();
    assert!(nan.message.starts_with("particle 2: position"), "{}", nan.message);
    assert_eq!(scene.xpbd().constraint_count(), 0);
    assert_eq!(scene.xpbd().particles.len(), 2);
}

#[test]
fn gauss_seidel_pass_does_not_pump_the_in_plane_modes_of_a_cloth() {
    // A 20 × 20 cloth of rigid links, no gravity, every particle kicked in its
    // plane by ±1e-4 m/s. One forward sweep per substep made its slowest in-plane
    // modes grow by 0.82 % per substep (1e-4 -> 5 m/s within 2 s at 16 substeps);
    // the symmetric pass projects the velocities onto the links' motions with a
    // self-adjoint contraction, so the rms speed can only fall (measured in the
    // same setting from Python: 1.4e-4 -> 3.5e-6 m/s, the kick's rigid motion).
    let n = 20usize;
    let mut scene = Scene::new([0.0; 3]).unwrap();
    let mat = rigidrs::xpbd::builders::Material { mass: 0.3, radius: 0.0, friction: 0.5, filter: Default::default() };
    scene.add_cloth([0.0; 3], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [n as i64; 2], &mat, Compliance::default(), None, &[]).unwrap();
    let mut world = build(&scene, 1.0 / 60.0, 16, 1);
    let mut seed = 12345u64;
    let mut noise = || {
        seed = seed.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
        if (seed >> 40) & 1 == 0 { 1e-4 } else { -1e-4 }
    };
    let p = &mut world.xpbd.as_mut().unwrap().particles;
    for v in p.velocity.iter_mut() {
        *v = [noise(), noise(), 0.0];
    }
    let rms = |w: &World| {
        let v = &w.particles().unwrap().velocity;
        (v.iter().map(|v| v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sum::<f64>() / v.len() as f64).sqrt()
    };
    let start = rms(&world);
    for _ in 0..120 {
        world.step(1).unwrap();
        assert!(rms(&world) <= start, "{} > {start} at t = {}", rms(&world), world.time());
    }
}
