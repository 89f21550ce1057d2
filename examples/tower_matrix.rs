//! Kicked towers at the default settings: columns of 10, 20 and 30 cubes of
//! 0.5 m (μ 0.5, restitution 0), aligned or each 5 cm off the one under it,
//! every cube kicked sideways and spun (σ 1 cm/s and 0.01 rad/s, or ten times
//! that; three seeds each), stepped 4 s. A kick this small is a fraction of
//! the energy that tips a cube, and contacts that rub only take energy out:
//! every tower must stand (top within 1 cm of its resting height) and come
//! to rest (every cube below 1 mm/s). Prints how many do, per step size:
//! `cargo run --release --example tower_matrix 0.0166667 0.001` (`SUB=n`: a
//! fixed number of substeps).
use rigidrs::body::Shape;
use rigidrs::world::{BodySpec, Scene, Settings};

/// A standard normal deviate from a linear congruential generator (the same
/// kicks on every machine).
fn normal(state: &mut u64) -> f64 {
    let mut u = || {
        *state = state.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
        ((*state >> 11) as f64 + 0.5) / (1u64 << 53) as f64
    };
    let (a, b) = (u(), u());
    (-2.0 * a.ln()).sqrt() * (2.0 * std::f64::consts::PI * b).cos()
}

/// The fastest cube (m/s), the top's height over its resting height (m) and
/// the CPU time (s) of one tower after `secs`.
fn run(dt: f64, n: usize, off: f64, kick: f64, seed: u64, secs: f64) -> (f64, f64, f64) {
    let mut sc = Scene::new([0.0, 0.0, -9.81]).unwrap();
    let m = rigidrs::collide::Material { friction: 0.5, static_friction: 0.5, restitution: 0.0 };
    sc.add_body(BodySpec { shape: Some(Shape::plane([0.0, 0.0, 1.0], 0.0).unwrap()), fixed: true, material: m, ..Default::default() }).unwrap();
    let mut st = seed * 7919 + 17;
    for k in 0..n {
        let x = if k == 0 { 0.0 } else if k % 2 == 1 { off } else { -off };
        let v = [kick * normal(&mut st), kick * normal(&mut st), 0.0];
        let w = [kick * normal(&mut st), kick * normal(&mut st), kick * normal(&mut st)];
        sc.add_body(BodySpec { shape: Some(Shape::cuboid([0.25; 3]).unwrap()), density: Some(1000.0), position: [x, 0.0, 0.25 * (1.0 + 2.0 * k as f64)], linear_velocity: v, angular_velocity: w, material: m, ..Default::default() }).unwrap();
    }
    let mut s = Settings::new(dt);
    s.sleep.enabled = false;
    s.threads = Some(1);
    s.substeps = std::env::var("SUB").ok().and_then(|x| x.parse().ok());
    let mut wd = sc.build(&s).unwrap();
    let steps = (secs / dt).round() as u64;
    let t0 = std::time::Instant::now();
    wd.step(steps).unwrap();
    let b = &wd.bodies;
    let vmax = (1..b.len()).map(|i| nalgebra::Vector3::from(b.linear_velocity[i]).norm()).fold(0.0, f64::max);
    let top = b.position[b.len() - 1][2] - 0.25 * (2 * n - 1) as f64;
    (vmax, top, t0.elapsed().as_secs_f64())
}

fn main() {
    let dts: Vec<f64> = std::env::args().skip(1).map(|s| s.parse().unwrap()).collect();
    for &dt in &dts {
        let (mut rest, mut stand, mut total, mut cpu) = (0, 0, 0, 0.0);
        let mut bad = Vec::new();
        for &n in &[10usize, 20, 30] {
            for &off in &[0.0, 0.05] {
                for &kick in &[0.01, 0.1] {
                    for seed in 1..=3u64 {
                        let (v, top, c) = run(dt, n, off, kick, seed, 4.0);
                        total += 1;
                        cpu += c;
                        let st = top.abs() < 0.01;
                        stand += st as u32;
                        rest += (st && v < 1e-3) as u32;
                        if !(st && v < 1e-3) {
                            bad.push(format!("n{n} off{off} k{kick} s{seed}: v {v:.1e} top {:+.1}mm", top * 1e3));
                        }
                    }
                }
            }
        }
        println!("dt {dt:.6}: at rest {rest}/{total}, standing {stand}/{total}, cpu {cpu:.1} s");
        for b in bad { println!("   {b}"); }
    }
}
