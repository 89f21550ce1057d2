//! The pyramid and ball-pit scenes of `benches/peers/` built in Rust, stepped and
//! timed without Python in the way: a target for `perf record` when working on the
//! contact pipeline. `cargo run --release --example contact_scenes [pyramid|pyramid_30|pyramid_35|pyramid_40|pyramid_50|ball_pit|ball_pit_300|ball_pit_3000|box_pile|box_pile_4000] [steps]`
//! (`WINDOW=50` in the environment: time and stage profile every 50 steps).
use rigidrs::body::Shape;
use rigidrs::world::{BodySpec, Scene, Settings, World};
use std::time::Instant;

fn material(friction: f64) -> rigidrs::collide::Material {
    rigidrs::collide::Material { friction, static_friction: friction, restitution: 0.0 }
}

/// As the peer scripts: dt 1/60 s, sleeping off so every engine does the same work.
fn settings() -> Settings {
    let mut s = Settings::new(1.0 / 60.0);
    s.sleep.enabled = false;
    // `THREADS=n`: the world's worker threads (default: every core).
    if let Some(n) = std::env::var("THREADS").ok().and_then(|n| n.parse().ok()) {
        s.threads = Some(n);
    }
    if let Ok(h) = std::env::var("HERTZ") {
        s.solver.contact_hertz = h.parse().unwrap_or(30.0);
    }
    s
}

fn pyramid(base: usize) -> World {
    let mut sc = Scene::new([0.0, 0.0, -9.81]).unwrap();
    let ground = Shape::plane([0.0, 0.0, 1.0], 0.0).unwrap();
    sc.add_body(BodySpec { shape: Some(ground), fixed: true, material: material(0.5), ..Default::default() }).unwrap();
    let cube = Shape::cuboid([0.5; 3]).unwrap();
    for i in 0..base {
        let k = base - i;
        for j in 0..k {
            let x = (j as f64 - (k as f64 - 1.0) / 2.0) * 1.02;
            sc.add_body(BodySpec {
                shape: Some(cube.clone()),
                density: Some(1000.0),
                position: [x, 0.0, 0.5 + i as f64],
                material: material(0.5),
                ..Default::default()
            })
            .unwrap();
        }
    }
    sc.build(&settings()).unwrap()
}

fn ball_pit(n: usize) -> World {
    let mut sc = Scene::new([0.0, 0.0, -9.81]).unwrap();
    let (half, wall_h, t) = (1.25, 3.0, 0.1);
    let (o, outer) = (half + t, half + 2.0 * t);
    let walls = [
        ([0.0, 0.0, -t], [outer, outer, t]),
        ([o, 0.0, wall_h / 2.0], [t, outer, wall_h / 2.0]),
        ([-o, 0.0, wall_h / 2.0], [t, outer, wall_h / 2.0]),
        ([0.0, o, wall_h / 2.0], [half, t, wall_h / 2.0]),
        ([0.0, -o, wall_h / 2.0], [half, t, wall_h / 2.0]),
    ];
    for (c, h) in walls {
        let shape = Shape::cuboid(h).unwrap();
        sc.add_body(BodySpec { shape: Some(shape), fixed: true, position: c, material: material(0.5), ..Default::default() })
            .unwrap();
    }
    let ball = Shape::sphere(0.1).unwrap();
    for i in 0..n {
        // A deterministic jitter in place of the Python script's random one.
        let jx = 0.02 * ((i as f64 * 0.754877).fract() * 2.0 - 1.0);
        let jy = 0.02 * ((i as f64 * 0.569840).fract() * 2.0 - 1.0);
        let (gx, gy, gz) = ((i % 10) as f64, ((i / 10) % 10) as f64, (i / 100) as f64);
        sc.add_body(BodySpec {
            shape: Some(ball.clone()),
            density: Some(1000.0),
            position: [(gx - 4.5) * 0.25 + jx, (gy - 4.5) * 0.25 + jy, 0.3 + gz * 0.25],
            material: material(0.5),
            ..Default::default()
        })
        .unwrap();
    }
    sc.build(&settings()).unwrap()
}

/// The box pile of `benches/peers/box_pile.py` (its seeded tilts replaced by a
/// deterministic sequence): `side`² cubes a layer, 5 cm apart, dropped.
// 0.31831 is the seed of `benches/peers/box_pile.py`'s tilt sequence, not 1/π.
#[allow(clippy::approx_constant)]
fn box_pile(side: usize, layers: usize) -> World {
    let mut sc = Scene::new([0.0, 0.0, -9.81]).unwrap();
    let ground = Shape::plane([0.0, 0.0, 1.0], 0.0).unwrap();
    sc.add_body(BodySpec { shape: Some(ground), fixed: true, material: material(0.5), ..Default::default() }).unwrap();
    let (half, gap) = (0.25, 0.05);
    // As `benches/peers/box_pile.py`: a turned cube reaches √3 half edges along
    // any axis, so none starts inside another (at 2 half edges + gap, tilted
    // neighbours overlapped and the first steps pushed them apart at 0.8 s a step).
    let pitch = 2.0 * half * 3f64.sqrt() + gap;
    let cube = Shape::cuboid([half; 3]).unwrap();
    let mut n = 0.0;
    for k in 0..layers {
        for i in 0..side {
            for j in 0..side {
                n += 1.0;
                let (a, b) = ((n * 0.754877f64).fract() - 0.5, (n * 0.569840f64).fract() - 0.5);
                let angle = 0.05 + 0.25 * (n * 0.31831f64).fract();
                let axis = nalgebra::Vector3::new(a, b, 0.3).normalize();
                let (s, c) = (0.5 * angle).sin_cos();
                let mid = (side as f64 - 1.0) / 2.0;
                sc.add_body(BodySpec {
                    shape: Some(cube.clone()),
                    density: Some(1000.0),
                    position: [(i as f64 - mid) * pitch, (j as f64 - mid) * pitch, half + gap + k as f64 * pitch],
                    orientation: [axis.x * s, axis.y * s, axis.z * s, c],
                    material: material(0.5),
                    ..Default::default()
                })
                .unwrap();
            }
        }
    }
    sc.build(&settings()).unwrap()
}

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let scene = args.get(1).map(String::as_str).unwrap_or("pyramid");
    let steps: u64 = args.get(2).and_then(|s| s.parse().ok()).unwrap_or(600);
    let mut w = match scene {
        "ball_pit" => ball_pit(1000),
        "ball_pit_3000" => ball_pit(3000),
        "ball_pit_300" => ball_pit(300),
        "box_pile" => box_pile(10, 4),
        "box_pile_4000" => box_pile(20, 10),
        "pyramid_40" => pyramid(40),
        "pyramid_30" => pyramid(30),
        "pyramid_35" => pyramid(35),
        "pyramid_50" => pyramid(50),
        _ => pyramid(20),
    };
    let t = Instant::now();
    // `WINDOW=50` prints the step time and the stage profile every 50 steps.
    let window: u64 = std::env::var("WINDOW").ok().and_then(|s| s.parse().ok()).unwrap_or(0);
    let mut tw = Instant::now();
    // `GUARDED=1` steps as Python's `World.step(1)` does (`world::guard`'s checks).
    let mut guard = std::env::var("GUARDED").is_ok_and(|s| s == "1").then(rigidrs::world::guard::Guard::default);
    for k in 1..=steps {
        match guard.as_mut() {
            Some(g) => w.step_guarded(g, 1, &mut || false).map(|_| ()).unwrap(),
            None => w.step(1).unwrap(),
        }
        if window > 0 && k % window == 0 {
            let per_step = |s: f64| s * 1e6 / window as f64;
            let (rows, _) = w.profile.report();
            let stages: Vec<String> = rows.iter().map(|(n, s)| format!("{n} {:.0}", per_step(*s))).collect();
            eprintln!("steps to {k}: {:.0} µs/step; {}", per_step(tw.elapsed().as_secs_f64()), stages.join(", "));
            w.profile.reset();
            tw = Instant::now();
        }
    }
    let s = t.elapsed().as_secs_f64();
    println!("{scene}: {steps} steps in {s:.3} s, {:.0} steps/s", steps as f64 / s);
    if let Some(c) = w.collision.as_ref() {
        let (pairs, touching) = (c.narrow.len(), c.narrow.touching.len());
        let (manifolds, points) = (c.solver.constraints.len(), c.solver.points.len());
        println!("  pairs {pairs}, touching {touching}, manifolds {manifolds}, points {points}");
        let (blocks, islands, largest) = c.solver.support_blocks();
        println!("  support blocks {blocks} in {islands} islands, the largest {largest}");
    }
    println!("  state {:016x}", state_hash(&w));
}

/// FNV-1a over the bits of every body's pose and velocities: equal for runs
/// that end in the same state, whatever their thread count.
fn state_hash(w: &World) -> u64 {
    let b = &w.bodies;
    let words = (0..b.len()).flat_map(|i| {
        let arrays = [&b.position[i][..], &b.orientation[i][..], &b.linear_velocity[i][..], &b.angular_velocity[i][..]];
        arrays.into_iter().flatten().map(|x| x.to_bits()).collect::<Vec<_>>()
    });
    words.fold(0xcbf29ce484222325, |h, x| (h ^ x).wrapping_mul(0x100000001b3))
}
