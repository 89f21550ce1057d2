//! Before/after check for kernel changes: steps a fixed set of scenes (500 boxes,
//! spheres, cylinders and fast thin rods; gravity off and on; every integrator)
//! and saves or compares the final states.
//!
//! ```text
//! cargo run --release --example state_dump -- save /tmp/before.bin [STEPS]
//! # ... change a kernel ...
//! cargo run --release --example state_dump -- compare /tmp/before.bin [STEPS]
//! ```
//!
//! `compare` prints, per scene and integrator, the largest difference (quaternion
//! components; positions and angular velocities relative to their scale) and the
//! fraction of bodies that are bit-identical. With `--perturb` the initial ω_x of
//! every body is multiplied by (1 + 2⁻⁵²) instead: the same comparison then shows
//! how much the scenes themselves amplify a one-ulp change (the round-off floor
//! any non-bit-identical change will show).

use std::io::{Read, Write};

use rigidrs::body::Shape;
use rigidrs::collide::Filter;
use rigidrs::integrate::Integrator;
use rigidrs::world::{BodySpec, Scene, Settings};

const N: usize = 500;
const FIELDS: usize = 13;

fn run(steps: u64, perturb: bool) -> Vec<(String, Vec<f64>)> {
    let shapes = [
        ("box", Shape::cuboid([0.05, 0.1, 0.2]).unwrap(), 5.0),
        ("sphere", Shape::sphere(0.1).unwrap(), 5.0),
        ("cylinder", Shape::cylinder(0.1, 0.3).unwrap(), 5.0),
        ("rod", Shape::cuboid([0.01, 0.02, 0.5]).unwrap(), 60.0),
    ];
    let eps = if perturb { f64::EPSILON } else { 0.0 };
    let mut out = Vec::new();
    for (name, shape, omega) in &shapes {
        for gravity in [false, true] {
            for integrator in Integrator::ALL {
                let g = if gravity { [0.0, 0.0, -9.81] } else { [0.0; 3] };
                let mut scene = Scene::new(g).unwrap();
                for k in 0..N {
                    let a = k as f64 * 0.37;
                    let spec = BodySpec {
                        shape: Some(shape.clone()),
                        density: Some(1000.0),
                        position: [k as f64, 0.0, 0.0],
                        orientation: [a.sin() * 0.5, a.cos() * 0.5, 0.5, 0.5 + 0.1 * a.cos()],
                        linear_velocity: [0.1, 0.2, 0.3],
                        angular_velocity: [
                            omega * a.cos() * (1.0 + eps),
                            omega * a.sin() * 0.9,
                            omega * (0.3 * a).cos(),
                        ],
                        // Free bodies: the shapes give the mass properties and collide with nothing.
                        filter: Filter { group: 1, mask: 0 },
                        ..Default::default()
                    };
                    scene.add_body(spec).unwrap();
                }
                let mut settings = Settings::new(1.0 / 240.0);
                settings.integrator = integrator;
                let mut world = scene.build(&settings).unwrap();
                // A method that blows up (euler, symplectic_euler on the fast rods) ends
                // with non-finite states: those are compared bit for bit like the rest.
                if let Err(e) = world.step(steps) {
                    eprintln!("{name} {}: {}", integrator.name(), e.message);
                }
                let b = &world.bodies;
                let mut v = Vec::with_capacity(N * FIELDS);
                for i in 0..N {
                    v.extend(b.position[i]);
                    v.extend(b.orientation[i]);
                    v.extend(b.linear_velocity[i]);
                    v.extend(b.angular_velocity[i]);
                }
                let label = format!("{name:8} {:7} {:16}", if gravity { "gravity" } else { "free" }, integrator.name());
                out.push((label, v));
            }
        }
    }
    out
}

fn max_abs(v: &[f64], range: std::ops::Range<usize>) -> f64 {
    v.chunks(FIELDS).flat_map(|c| c[range.clone()].iter()).fold(0.0, |m, x| m.max(x.abs()))
}

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let usage = "usage: state_dump save|compare FILE [STEPS] [--perturb]";
    let (mode, path) = (args.first().expect(usage), args.get(1).expect(usage));
    let steps = args.get(2).filter(|s| !s.starts_with("--")).map_or(1000, |s| s.parse().expect(usage));
    let perturb = args.iter().any(|a| a == "--perturb");
    let states = run(steps, perturb);
    match mode.as_str() {
        "save" => {
            let mut f = std::fs::File::create(path).unwrap();
            for (_, v) in &states {
                v.iter().for_each(|x| f.write_all(&x.to_le_bytes()).unwrap());
            }
            println!("saved {} scenes after {steps} steps to {path}", states.len());
        }
        "compare" => {
            let mut bytes = Vec::new();
            std::fs::File::open(path).unwrap().read_to_end(&mut bytes).unwrap();
            let saved: Vec<f64> = bytes.chunks_exact(8).map(|c| f64::from_le_bytes(c.try_into().unwrap())).collect();
            let mut worst: f64 = 0.0;
            println!(
                "{:34} {:>10} {:>10} {:>10} {:>10}",
                "scene / integrator", "max dq", "rel dp", "rel dw", "bit-same"
            );
            for (k, (label, new)) in states.iter().enumerate() {
                let old = &saved[k * N * FIELDS..(k + 1) * N * FIELDS];
                let diff: Vec<f64> = old.iter().zip(new).map(|(a, b)| a - b).collect();
                let dq = max_abs(&diff, 3..7);
                let dp = max_abs(&diff, 0..3) / max_abs(old, 0..3);
                let dw = max_abs(&diff, 10..13) / max_abs(old, 10..13);
                let bits_equal = |(a, b): (&[f64], &[f64])| a.iter().zip(b).all(|(x, y)| x.to_bits() == y.to_bits());
                let same = old.chunks(FIELDS).zip(new.chunks(FIELDS)).filter(|&p| bits_equal(p)).count() as f64 / N as f64;
                worst = worst.max(dq.max(dp).max(dw));
                println!("{label:34} {dq:10.1e} {dp:10.1e} {dw:10.1e} {same:10.2}");
            }
            println!("worst difference {worst:.1e} after {steps} steps");
        }
        _ => panic!("{usage}"),
    }
}
