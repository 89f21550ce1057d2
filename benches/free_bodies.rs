//! Free-body stepping cost, in ns per body-step (criterion reports it as
//! elements/s with `Throughput::Elements(N)`; invert for ns per body-step).
//!
//! Scene: N = 10 000 boxes 0.1 × 0.2 × 0.4 m (ρ = 1000 kg/m³) on a 1 m grid,
//! uniformly random orientations, random directions of ω with |ω| = 5 rad/s,
//! dt = 1/240 s, no collisions (the shapes collide with nothing). Groups:
//!
//! * `free_boxes/<integrator>`: no gravity (no `forces` stage), every integrator;
//! * `gravity_boxes/<integrator>`: gravity on, so the `forces` stage runs;
//! * `free_spheres/<integrator>`: spheres r = 0.1 m (isotropic: no gyroscopic work);
//! * `pipeline/…`: `world.step(1)` and `world.step(10)` of the default integrator
//!   against the bare kernels it runs (`drift::translate` then
//!   `free_rotation::rotate_asymmetric`) on the same bodies, so that the cost of
//!   the pipeline (state check, normalisation, planning) is visible; and
//!   `reference_kernel`, the one-body-at-a-time form of the same kernel
//!   (`free_rotation::rotate_asymmetric_one`, bit-identical results).
//!
//! Each criterion sample starts from the same initial state (restored outside
//! the timed region), so that methods that gain energy (euler) are timed on the
//! scene as built, not on a runaway one.
//!
//! Run: `cargo bench --bench free_bodies` (about 80 s), or a subset, e.g.
//! `cargo bench --bench free_bodies -- pipeline`. On a machine shared with other
//! jobs, `BENCH_CLOCK=cpu cargo bench --bench free_bodies` times with the thread's
//! CPU clock (Linux), which leaves out the time the benchmark waited for a core.

use std::time::{Duration, Instant};

use criterion::measurement::WallTime;
use criterion::{black_box, criterion_group, criterion_main, BenchmarkGroup, Criterion, Throughput};
use rigidrs::body::{Bodies, Shape};
use rigidrs::collide::Filter;
use rigidrs::integrate::{drift, fast_rotation, free_rotation, Integrator};
use rigidrs::world::{BodySpec, Scene, Settings, World};

const N: usize = 10_000;
const DT: f64 = 1.0 / 240.0;
const OMEGA: f64 = 5.0;
const DENSITY: f64 = 1000.0;
const SEED: u64 = 0x5eed;

/// SplitMix64: a small deterministic generator (no `rand` dependency).
struct Rng(u64);

impl Rng {
    fn next_u64(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9e37_79b9_7f4a_7c15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        z ^ (z >> 31)
    }
    /// Uniform in (0, 1).
    fn uniform(&mut self) -> f64 {
        ((self.next_u64() >> 11) as f64 + 0.5) / (1u64 << 53) as f64
    }
    /// Standard normal (Box–Muller).
    fn normal(&mut self) -> f64 {
        let (u, v) = (self.uniform(), self.uniform());
        (-2.0 * u.ln()).sqrt() * (std::f64::consts::TAU * v).cos()
    }
    fn normal_n<const K: usize>(&mut self) -> [f64; K] {
        std::array::from_fn(|_| self.normal())
    }
}

fn normalized<const K: usize>(v: [f64; K]) -> [f64; K] {
    let n = v.iter().map(|x| x * x).sum::<f64>().sqrt();
    v.map(|x| x / n)
}

#[derive(Clone, Copy)]
enum Body {
    Box,
    Sphere,
}

fn build(body: Body, integrator: Integrator, gravity: bool) -> World {
    let g = if gravity { [0.0, 0.0, -9.81] } else { [0.0; 3] };
    let mut scene = Scene::new(g).unwrap();
    let shape = match body {
        Body::Box => Shape::cuboid([0.05, 0.1, 0.2]).unwrap(),
        Body::Sphere => Shape::sphere(0.1).unwrap(),
    };
    let mut rng = Rng(SEED);
    let side = (N as f64).cbrt().ceil() as usize;
    for i in 0..N {
        let position = [(i % side) as f64, ((i / side) % side) as f64, (i / (side * side)) as f64];
        let orientation = normalized(rng.normal_n::<4>());
        let angular_velocity = normalized(rng.normal_n::<3>()).map(|x| OMEGA * x);
        let spec = BodySpec {
            shape: Some(shape.clone()),
            density: Some(DENSITY),
            position,
            orientation,
            angular_velocity,
            // Free bodies: the shapes give the mass properties and collide with nothing
            // (without this the boxes get a collision pipeline and the plan assert fails).
            filter: Filter { group: 1, mask: 0 },
            ..Default::default()
        };
        scene.add_body(spec).unwrap();
    }
    let mut settings = Settings::new(DT);
    settings.integrator = integrator;
    scene.build(&settings).unwrap()
}

/// The moving part of the state, to restore between samples.
#[derive(Clone)]
struct State {
    position: Vec<[f64; 3]>,
    orientation: Vec<[f64; 4]>,
    linear_velocity: Vec<[f64; 3]>,
    angular_velocity: Vec<[f64; 3]>,
}

impl State {
    fn of(b: &Bodies) -> Self {
        Self {
            position: b.position.clone(),
            orientation: b.orientation.clone(),
            linear_velocity: b.linear_velocity.clone(),
            angular_velocity: b.angular_velocity.clone(),
        }
    }
    fn restore(&self, b: &mut Bodies) {
        b.position.copy_from_slice(&self.position);
        b.orientation.copy_from_slice(&self.orientation);
        b.linear_velocity.copy_from_slice(&self.linear_velocity);
        b.angular_velocity.copy_from_slice(&self.angular_velocity);
    }
}

/// The clock of a measurement: wall time, or with `BENCH_CLOCK=cpu` the CPU time of
/// the calling thread (`CLOCK_THREAD_CPUTIME_ID`, Linux only).
#[derive(Clone, Copy)]
enum Clock {
    Wall(Instant),
    #[cfg(target_os = "linux")]
    Cpu(Duration),
}

#[cfg(target_os = "linux")]
fn thread_cpu_time() -> Duration {
    #[repr(C)]
    struct Timespec {
        tv_sec: i64,
        tv_nsec: i64,
    }
    extern "C" {
        fn clock_gettime(clock: i32, ts: *mut Timespec) -> i32;
    }
    const CLOCK_THREAD_CPUTIME_ID: i32 = 3;
    let mut ts = Timespec { tv_sec: 0, tv_nsec: 0 };
    // Safety: a valid out-pointer to a C `struct timespec` (64-bit Linux layout).
    let rc = unsafe { clock_gettime(CLOCK_THREAD_CPUTIME_ID, &mut ts) };
    assert_eq!(rc, 0, "clock_gettime(CLOCK_THREAD_CPUTIME_ID) failed");
    Duration::new(ts.tv_sec as u64, ts.tv_nsec as u32)
}

impl Clock {
    fn start() -> Self {
        #[cfg(target_os = "linux")]
        if std::env::var("BENCH_CLOCK").is_ok_and(|v| v == "cpu") {
            return Clock::Cpu(thread_cpu_time());
        }
        Clock::Wall(Instant::now())
    }
    fn elapsed(self) -> Duration {
        match self {
            Clock::Wall(t0) => t0.elapsed(),
            #[cfg(target_os = "linux")]
            Clock::Cpu(t0) => thread_cpu_time() - t0,
        }
    }
}

/// Times `iters` calls of `world.step(k)`, from the initial state.
fn time_steps(world: &mut World, init: &State, iters: u64, k: u64) -> Duration {
    init.restore(&mut world.bodies);
    let t0 = Clock::start();
    for _ in 0..iters {
        world.step(black_box(k)).unwrap();
    }
    t0.elapsed()
}

fn configure(g: &mut BenchmarkGroup<'_, WallTime>) {
    // One step of 10 000 bodies takes 0.1–5 ms: 20 samples in 1.5 s is plenty.
    g.sample_size(20).warm_up_time(Duration::from_millis(400)).measurement_time(Duration::from_millis(1500));
}

fn per_integrator(c: &mut Criterion, name: &str, body: Body, gravity: bool) {
    let mut g = c.benchmark_group(name);
    configure(&mut g);
    g.throughput(Throughput::Elements(N as u64));
    for integrator in Integrator::ALL {
        let mut world = build(body, integrator, gravity);
        let init = State::of(&world.bodies);
        g.bench_function(integrator.name(), |b| b.iter_custom(|iters| time_steps(&mut world, &init, iters, 1)));
    }
    g.finish();
}

fn free_boxes(c: &mut Criterion) {
    per_integrator(c, "free_boxes", Body::Box, false);
}

fn gravity_boxes(c: &mut Criterion) {
    per_integrator(c, "gravity_boxes", Body::Box, true);
}

fn free_spheres(c: &mut Criterion) {
    per_integrator(c, "free_spheres", Body::Sphere, false);
}

/// `world.step` of the default integrator against the bare kernels it runs.
fn pipeline(c: &mut Criterion) {
    let mut world = build(Body::Box, Integrator::Strang, false);
    assert_eq!(world.stage_names(), ["translate", "rotate_asymmetric"]);
    let init = State::of(&world.bodies);
    let lists = world.lists().clone();
    assert_eq!(lists.asymmetric.len(), N);
    let mut bodies = world.bodies.clone();

    // The kernel as the world runs it: with the default limit on the rotation per
    // split (no body here comes near it: `fast` stays empty).
    let sub = fast_rotation::Substeps::new(world.settings().rotation_angle(), DT, &[1.0]);
    let mut fast = Vec::new();
    let mut g = c.benchmark_group("pipeline");
    configure(&mut g);
    g.throughput(Throughput::Elements(N as u64));
    g.bench_function("bare_kernel", |b| {
        b.iter_custom(|iters| {
            init.restore(&mut bodies);
            let t0 = Clock::start();
            for _ in 0..iters {
                drift::translate(&mut bodies, &lists.dynamic, black_box(DT));
                let spread = &lists.asymmetric_inv_spread;
                free_rotation::rotate_asymmetric(&mut bodies, &lists.asymmetric, spread, black_box(DT), sub, &mut fast);
            }
            t0.elapsed()
        })
    });
    // The same kernel one body at a time with the axes read at run time (how it was
    // written before the grouped, specialised version; bit-identical results).
    g.bench_function("reference_kernel", |b| {
        b.iter_custom(|iters| {
            init.restore(&mut bodies);
            let t0 = Clock::start();
            for _ in 0..iters {
                drift::translate(&mut bodies, &lists.dynamic, black_box(DT));
                for a in &lists.asymmetric {
                    free_rotation::rotate_asymmetric_one(&mut bodies, a, black_box(DT));
                }
            }
            t0.elapsed()
        })
    });
    g.bench_function("world_step_1", |b| b.iter_custom(|iters| time_steps(&mut world, &init, iters, 1)));
    g.throughput(Throughput::Elements(10 * N as u64));
    g.bench_function("world_step_10", |b| b.iter_custom(|iters| time_steps(&mut world, &init, iters, 10)));
    g.finish();
}

criterion_group!(benches, pipeline, free_boxes, gravity_boxes, free_spheres);
criterion_main!(benches);
