//! Instruction counts of the free-body kernel, for before/after comparisons that a
//! loaded machine does not disturb (`valgrind --tool=callgrind` counts
//! instructions, not time).
//!
//! Scene: that of `benches/free_bodies.rs` (10 000 boxes 0.1 × 0.2 × 0.4 m,
//! ρ = 1000 kg/m³, random orientations, |ω| = 5 rad/s in random directions,
//! dt = 1/240 s, no gravity, default integrator; the shapes collide with nothing,
//! so the plan is `translate`, `rotate_asymmetric`). `MODE` is `step` (`world.step(1)`
//! `STEPS` times, profiling off) or `kernel` (`drift::translate` and
//! `free_rotation::rotate_asymmetric` called directly) or `guarded` (`step(1)` as
//! Python's `World.step` takes it, with the checks of `world::guard`), each inside a function of
//! its own so that callgrind can count only that:
//!
//! ```text
//! cargo build --release --example free_kernel_count
//! valgrind --tool=callgrind --callgrind-out-file=/tmp/cg.out \
//!     --toggle-collect='free_kernel_count::run_*' \
//!     target/release/examples/free_kernel_count step 20
//! callgrind_annotate /tmp/cg.out | head -20     # "PROGRAM TOTALS": instructions
//! ```
//!
//! It prints a checksum of the final state, so that two builds can also be
//! checked for bit-identical results on this scene. Optional third and fourth
//! arguments: the step `DT` (s, default 1/240; at 1/60 the 5 rad/s boxes turn by
//! up to 0.1 rad per step, half strang's 0.2 rad limit of the rotation substeps)
//! and `rod`, which adds one thin rod (1 m × 1 cm × 2 cm, I_max/I_min ≈ 2000) at
//! 5 rad/s to the same list.

use rigidrs::body::Shape;
use rigidrs::collide::Filter;
use rigidrs::integrate::{drift, fast_rotation, free_rotation, BodyLists};
use rigidrs::world::{BodySpec, Scene, Settings, World};

const N: usize = 10_000;
const DT: f64 = 1.0 / 240.0;
const OMEGA: f64 = 5.0;
const SEED: u64 = 0x5eed;

/// SplitMix64 and Box–Muller, as in `benches/free_bodies.rs` (same scene).
struct Rng(u64);

impl Rng {
    fn next_u64(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9e37_79b9_7f4a_7c15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        z ^ (z >> 31)
    }
    fn uniform(&mut self) -> f64 {
        ((self.next_u64() >> 11) as f64 + 0.5) / (1u64 << 53) as f64
    }
    fn normal(&mut self) -> f64 {
        let (u, v) = (self.uniform(), self.uniform());
        (-2.0 * u.ln()).sqrt() * (std::f64::consts::TAU * v).cos()
    }
    fn unit<const K: usize>(&mut self) -> [f64; K] {
        let v: [f64; K] = std::array::from_fn(|_| self.normal());
        let n = v.iter().map(|x| x * x).sum::<f64>().sqrt();
        v.map(|x| x / n)
    }
}

fn build(dt: f64, rod: bool) -> Result<World, String> {
    let mut scene = Scene::new([0.0; 3]).map_err(|e| e.message)?;
    let shape = Shape::cuboid([0.05, 0.1, 0.2]).map_err(|e| e.message)?;
    let mut rng = Rng(SEED);
    let side = (N as f64).cbrt().ceil() as usize;
    for i in 0..N {
        let spec = BodySpec {
            shape: Some(shape.clone()),
            density: Some(1000.0),
            position: [(i % side) as f64, ((i / side) % side) as f64, (i / (side * side)) as f64],
            orientation: rng.unit::<4>(),
            angular_velocity: rng.unit::<3>().map(|x| OMEGA * x),
            filter: Filter { group: 1, mask: 0 },
            ..Default::default()
        };
        scene.add_body(spec).map_err(|e| e.message)?;
    }
    if rod {
        let spec = BodySpec {
            shape: Some(Shape::cuboid([0.005, 0.01, 0.5]).map_err(|e| e.message)?),
            density: Some(1000.0),
            position: [-10.0, 0.0, 0.0],
            angular_velocity: rng.unit::<3>().map(|x| OMEGA * x),
            filter: Filter { group: 1, mask: 0 },
            ..Default::default()
        };
        scene.add_body(spec).map_err(|e| e.message)?;
    }
    scene.build(&Settings::new(dt)).map_err(|e| e.message)
}

#[inline(never)]
fn run_step(world: &mut World, steps: u64) -> Result<(), String> {
    world.step(std::hint::black_box(steps)).map_err(|e| e.message)
}

/// `world.step_guarded(1)` `steps` times, as Python's `World.step(1)` does
/// (with the divergence and runaway checks of `world::guard`).
#[inline(never)]
fn run_guarded(world: &mut World, steps: u64) -> Result<(), String> {
    let mut guard = rigidrs::world::guard::Guard::default();
    for _ in 0..steps {
        world.step_guarded(&mut guard, std::hint::black_box(1), &mut || false).map_err(|e| e.message)?;
    }
    Ok(())
}

#[inline(never)]
fn run_kernel(world: &mut World, lists: &BodyLists, steps: u64) {
    // The default limit on the rotation per split, as the world uses it.
    let dt = world.dt();
    let sub = fast_rotation::Substeps::new(world.settings().rotation_angle(), dt, &[1.0]);
    let mut fast = Vec::new();
    for _ in 0..steps {
        drift::translate(&mut world.bodies, &lists.dynamic, std::hint::black_box(dt));
        let (b, spread) = (&mut world.bodies, &lists.asymmetric_inv_spread);
        free_rotation::rotate_asymmetric(b, &lists.asymmetric, spread, std::hint::black_box(dt), sub, &mut fast);
    }
    assert!(fast.is_empty(), "no body of this scene turns fast enough for rotation substeps");
}

fn main() -> Result<(), String> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let mode = args.first().map_or("step", String::as_str);
    let steps: u64 = args.get(1).map_or(Ok(20), |s| s.parse()).map_err(|e| format!("STEPS: {e}"))?;
    let dt: f64 = args.get(2).map_or(Ok(DT), |s| s.parse()).map_err(|e| format!("DT: {e}"))?;
    let mut world = build(dt, args.get(3).is_some_and(|s| s == "rod"))?;
    world.profile.enabled = false;
    match mode {
        "step" => {
            for _ in 0..steps {
                run_step(&mut world, 1)?;
            }
        }
        "guarded" => run_guarded(&mut world, steps)?,
        "kernel" => {
            let lists = world.lists().clone();
            run_kernel(&mut world, &lists, steps);
        }
        _ => return Err(format!("MODE must be step, guarded or kernel, not {mode:?}")),
    }
    let b = &world.bodies;
    let sum: f64 = (0..b.len()).map(|i| b.orientation[i].iter().chain(&b.angular_velocity[i]).sum::<f64>()).sum();
    println!("{mode} {steps}: stages {:?}, checksum {sum:.17e}", world.stage_names());
    Ok(())
}
