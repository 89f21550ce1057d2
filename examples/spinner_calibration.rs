//! Where the split rotation stops being accurate: the error of the torque-free
//! asymmetric split (strang, yoshida4, suzuki4) against the exact solution, as a
//! function of the angle `θ = W·h` a body turns by per step (`W` the largest
//! `|ω|` over its orbit, `free_rotation::orbit_max_omega`), for bodies of several shapes on
//! orbits near each axis. It is what `Integrator::max_split_angle` is chosen
//! from: rotation substeps keep every body at or below that angle per split.
//!
//! ```text
//! cargo run --release --example spinner_calibration            # the table
//! cargo run --release --example spinner_calibration -- 800     # periods per run
//! ```
//!
//! For each case and `θ`, one body steps `h = θ/W` for 400 periods of its exact
//! motion (`P = 4 K(k²)/λ`, Landau–Lifshitz §37, `K` by the arithmetic-geometric
//! mean): the largest relative energy error, the relative error of the period
//! measured from the sign changes of the intermediate momentum component, and the
//! drift of `|L|`. Errors depend on `θ` and the orbit only (time scales with
//! `1/|ω|`), so one run covers every rate and step with that `θ`.

use rigidrs::body::storage::BodyInit;
use rigidrs::body::{BodyKind, Bodies};
use rigidrs::integrate::classes::{aniso, classify};
use rigidrs::integrate::{fast_rotation, free_rotation, Aniso, InertiaClass, Integrator};
use rigidrs::math::{quat, Vec3};

/// `K(m)` (`m = k²`) by the arithmetic-geometric mean: `π / (2 AGM(1, √(1 − m)))`.
fn ellipk(m: f64) -> f64 {
    let (mut a, mut b) = (1.0, (1.0 - m).sqrt());
    for _ in 0..60 {
        let (an, bn) = (0.5 * (a + b), (a * b).sqrt());
        (a, b) = (an, bn);
        if (a - b).abs() <= 1e-16 * a {
            break;
        }
    }
    std::f64::consts::PI / (2.0 * a)
}

/// Period of body-frame ω of the torque-free top (REFERENCES.md, both branches).
fn exact_period(inertia: [f64; 3], w: [f64; 3]) -> f64 {
    let mut p = [0, 1, 2];
    p.sort_by(|&x, &y| inertia[x].total_cmp(&inertia[y]));
    let (i1, i2, i3) = (inertia[p[0]], inertia[p[1]], inertia[p[2]]);
    let e: f64 = (0..3).map(|j| 0.5 * inertia[j] * w[j] * w[j]).sum();
    let m2: f64 = (0..3).map(|j| (inertia[j] * w[j]).powi(2)).sum();
    let (hi, lo) = (2.0 * e * i3 - m2, m2 - 2.0 * e * i1);
    let (lam, k2) = if m2 > 2.0 * e * i2 {
        (((i3 - i2) * lo / (i1 * i2 * i3)).sqrt(), (i2 - i1) * hi / ((i3 - i2) * lo))
    } else {
        (((i2 - i1) * hi / (i1 * i2 * i3)).sqrt(), (i3 - i2) * lo / ((i2 - i1) * hi))
    };
    4.0 * ellipk(k2) / lam
}

struct Case {
    name: &'static str,
    inertia: [f64; 3],
    w: [f64; 3],
}

fn box_moments(m: f64, full: [f64; 3]) -> [f64; 3] {
    let [a, b, c] = full;
    [m / 12.0 * (b * b + c * c), m / 12.0 * (a * a + c * c), m / 12.0 * (a * a + b * b)]
}

fn cases() -> Vec<Case> {
    let dz = box_moments(10.0, [0.1, 0.4, 0.9]);
    let bench = box_moments(8.0, [0.1, 0.2, 0.4]);
    let plate = box_moments(1.0, [1.0, 0.5, 0.01]);
    let rod = box_moments(0.4, [0.02, 0.04, 1.0]);
    vec![
        Case { name: "dzhanibekov box (0.1, 5, 0.1)", inertia: dz, w: [0.1, 5.0, 0.1] },
        Case { name: "dzhanibekov box (1, 5, 1)", inertia: dz, w: [1.0, 5.0, 1.0] },
        Case { name: "same box near max axis", inertia: dz, w: [5.0, 0.8, 0.6] },
        Case { name: "same box near min axis", inertia: dz, w: [0.3, 0.5, 5.0] },
        Case { name: "bench box near intermediate", inertia: bench, w: [0.3, 5.0, 0.2] },
        Case { name: "bench box, generic", inertia: bench, w: [2.0, 3.0, 4.0] },
        Case { name: "plate near intermediate", inertia: plate, w: [0.1, 5.0, 0.1] },
        Case { name: "plate near max axis", inertia: plate, w: [0.5, 0.5, 5.0] },
        Case { name: "rod (near-symmetric) tilted", inertia: rod, w: [1.0, 0.5, 5.0] },
        Case { name: "rod (near-symmetric) tumbling", inertia: rod, w: [5.0, 0.5, 0.2] },
        Case { name: "moments 1:2:2.5, generic", inertia: [1.0, 2.0, 2.5], w: [1.0, 2.0, 3.0] },
        Case { name: "moments 1:1.1:3, near intermediate", inertia: [1.0, 1.1, 3.0], w: [0.1, 5.0, 0.1] },
        Case { name: "moments 1:2.9:3, near intermediate", inertia: [1.0, 2.9, 3.0], w: [0.1, 5.0, 0.1] },
        Case { name: "moments 1:1.1:3, near max axis", inertia: [1.0, 1.1, 3.0], w: [0.3, 0.2, 5.0] },
        Case { name: "moments 1:1.1:3, near min axis", inertia: [1.0, 1.1, 3.0], w: [5.0, 0.3, 0.2] },
        Case { name: "moments 1:2.9:3, near max axis", inertia: [1.0, 2.9, 3.0], w: [0.2, 0.3, 5.0] },
        Case { name: "plate near min axis", inertia: plate, w: [5.0, 0.3, 0.2] },
    ]
}

fn energy(b: &Bodies) -> f64 {
    let wb = quat::rotate_inv(&b.q(0), &Vec3::from(b.angular_velocity[0]));
    0.5 * (0..3).map(|j| b.inertia[0][j] * wb[j] * wb[j]).sum::<f64>()
}

fn body_momentum(b: &Bodies) -> Vec3 {
    quat::rotate_inv(&b.q(0), &Vec3::from(b.angular_velocity[0])).component_mul(&Vec3::from(b.inertia[0]))
}

/// Strang weights of one step of each integrator (torque-free: the kicks do nothing).
fn weights(i: Integrator) -> Vec<f64> {
    i.splitting().map(|s| s.drifts).unwrap_or_default()
}

struct Errors {
    energy: f64,
    period: f64,
    momentum: f64,
}

fn run(case: &Case, integrator: Integrator, theta: f64, periods: f64) -> Errors {
    let mut b = Bodies::with_capacity(1);
    b.push(&BodyInit {
        kind: BodyKind::Dynamic,
        position: Vec3::zeros(),
        orientation: quat::exp(&Vec3::new(0.3, -0.2, 0.5)),
        linear_velocity: Vec3::zeros(),
        angular_velocity: quat::rotate(&quat::exp(&Vec3::new(0.3, -0.2, 0.5)), &Vec3::from(case.w)),
        mass: 1.0,
        inertia: case.inertia,
    });
    let (class, axes) = classify(&case.inertia);
    assert_eq!(class, InertiaClass::Asymmetric, "{}", case.name);
    let a: Aniso = aniso(0, &case.inertia, axes);
    let omega = fast_rotation::orbit_max_omega(&b, &a);
    let h = theta / omega;
    let period = exact_period(case.inertia, case.w);
    let steps = (periods * period / h).ceil() as usize;
    let e0 = energy(&b);
    let l0 = body_momentum(&b).norm();
    let ax = {
        let mut p = [0, 1, 2];
        p.sort_by(|&x, &y| case.inertia[x].total_cmp(&case.inertia[y]));
        p[1]
    };
    let ws = weights(integrator);
    let (mut de, mut dl): (f64, f64) = (0.0, 0.0);
    let (mut first, mut last, mut count) = (f64::NAN, f64::NAN, 0usize);
    let mut prev = body_momentum(&b)[ax];
    for k in 1..=steps {
        for &w in &ws {
            free_rotation::rotate_asymmetric_one(&mut b, &a, w * h);
        }
        de = de.max((energy(&b) / e0 - 1.0).abs());
        let l = body_momentum(&b);
        dl = dl.max((l.norm() / l0 - 1.0).abs());
        let y = l[ax];
        if (y < 0.0) != (prev < 0.0) {
            let t = h * (k as f64 - y / (y - prev));
            if count == 0 {
                first = t;
            }
            last = t;
            count += 1;
        }
        prev = y;
    }
    let measured = if count > 2 { 2.0 * (last - first) / (count - 1) as f64 } else { f64::NAN };
    Errors { energy: de, period: measured / period - 1.0, momentum: dl }
}

fn main() {
    let periods: f64 = std::env::args().nth(1).and_then(|s| s.parse().ok()).unwrap_or(400.0);
    let thetas = [0.05, 0.1, 0.15, 0.2, 0.3, 0.4, 0.5, 0.6, 0.7, 0.8, 0.9, 1.0, 1.5, 2.0];
    let integrators = [Integrator::Strang, Integrator::Yoshida4, Integrator::Suzuki4];
    for case in cases() {
        let mut b = Bodies::with_capacity(1);
        b.push(&BodyInit {
            kind: BodyKind::Dynamic,
            position: Vec3::zeros(),
            orientation: quat::exp(&Vec3::zeros()),
            linear_velocity: Vec3::zeros(),
            angular_velocity: Vec3::from(case.w),
            mass: 1.0,
            inertia: case.inertia,
        });
        let a = aniso(0, &case.inertia, classify(&case.inertia).1);
        let ratio = fast_rotation::orbit_max_omega(&b, &a) / Vec3::from(case.w).norm();
        println!("\n{} — I = {:.4?}, ω0 = {:?}, W/|ω0| = {ratio:.3}", case.name, case.inertia, case.w);
        println!("{:>9} | {:>28} | {:>28} | {:>28}", "θ = W·h", "strang: dE  dP  d|L|", "yoshida4", "suzuki4");
        for &theta in &thetas {
            let cells: Vec<String> = integrators
                .iter()
                .map(|&i| {
                    let e = run(&case, i, theta, periods);
                    format!("{:8.1e} {:+9.1e} {:8.1e}", e.energy, e.period, e.momentum)
                })
                .collect();
            println!("{theta:9.2} | {}", cells.join(" | "));
        }
    }
}
