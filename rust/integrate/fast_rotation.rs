//! Fast spinners: a body whose torque-free rotation turns it by more than
//! its integrator's split angle in one step takes the step's rotation as
//! repeated compositions of the split over shorter times (only that body:
//! the others keep the single split of [`super::free_rotation`] bit for bit).
//! How many comes from the largest `|ω|` over the body's torque-free orbit,
//! which the flows conserve, so a body keeps its count from step to step.

use super::free_rotation::{flow_axis, flow_axis_k, flow_norm, load, store};
use super::Aniso;
use crate::body::Bodies;
use crate::math::{Quat, Vec3};

/// Most split substeps one body takes in one drift: a body turning faster than
/// that (`W·dt` above `MAX_SUBSTEPS × max_angle`: 205 rad per step for strang,
/// 12 000 rad/s at dt = 1/60) is split this many times and no more, each split
/// then turning it by more than `max_angle`: still a composition of exact
/// rotations (|L| kept to round-off), with a larger period error. One absurd
/// spin costs at most some 10⁵ instructions per step; it was 65 536 splits
/// (minutes per step for a few bodies spun up by a runaway, which the energy
/// check of `world::runaway` now stops).
pub const MAX_SUBSTEPS: u32 = 1024;

/// When an asymmetric body's rotation is subdivided, and how.
///
/// The integrator's step (its composition of splits, `weights`: one split for
/// strang, three for yoshida4, five for suzuki4) is accurate while `W·step`
/// (`W` = [`orbit_max_omega`], the largest `|ω|` over the body's orbit) is at
/// most `max_angle`, the integrator's
/// [`crate::integrate::Integrator::max_split_angle`]. A faster body sits out the
/// step's drifts and takes the whole step's rotation in the middle one as
/// `n = ⌈W·step / max_angle⌉` repetitions of the composition over `step/n`:
/// the method itself at a step that turns the body by at most `max_angle`, the
/// regime its error was measured in. Without torque this is exact composition;
/// the kicks before the middle drift of a palindromic composition add up to half
/// the step, so a torque acts on the fast body as in strang. (Subdividing each
/// drift instead loses the cancellation between the drifts of a composition:
/// each split into `n` Strang splits makes it a second-order method, measured
/// 3.4x worse than strang on the box of REFERENCES.md at 480 rad/s; each into
/// `n` compositions keeps the order but shifted that box's flip period by 0.6 %
/// (yoshida4) and 6 % (suzuki4) at the same `max_angle`, against 0.02 % and
/// 0.003 % for the whole step.)
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Substeps<'w> {
    /// Largest angle (rad) one composition step may turn a body by, at `W`.
    pub max_angle: f64,
    /// Largest `W` (rad/s) one drift per step covers: `max_angle / |step|`.
    pub max_rate: f64,
    /// Step fractions of the integrator's composition of splits (sum 1).
    pub weights: &'w [f64],
}

impl Substeps<'static> {
    /// No body is ever subdivided.
    pub const NEVER: Substeps<'static> =
        Substeps { max_angle: f64::INFINITY, max_rate: f64::INFINITY, weights: &[1.0] };
}

impl<'w> Substeps<'w> {
    /// `max_angle` (rad): see [`crate::integrate::Integrator::max_split_angle`];
    /// `step` (s): the whole step whose drifts this covers (the world's `dt`, or
    /// its substep for bodies in contact); `weights`: the composition's drift
    /// fractions (`[1.0]` for strang).
    pub fn new(max_angle: f64, step: f64, weights: &'w [f64]) -> Self {
        Self { max_angle, max_rate: max_angle / step.abs(), weights }
    }

    /// Composition steps for a rotation over `h` (s) of a body of orbit rate `w`
    /// (rad/s): `⌈w·|h| / max_angle⌉`, at least 1 (a NaN rate gives 1), at most
    /// [`MAX_SUBSTEPS`].
    pub fn count(&self, w: f64, h: f64) -> u32 {
        let n = (w * h.abs() / self.max_angle).ceil();
        if n >= MAX_SUBSTEPS as f64 {
            MAX_SUBSTEPS
        } else if n > 1.0 {
            n as u32
        } else {
            1
        }
    }
}

/// `W²`, the square of the largest `|ω|` over the torque-free orbit of the
/// body with split coefficients `c = [c_a, c_b, c_c]` and squared body-frame
/// momentum components `x = [L_a², L_b², L_c²]`.
///
/// Over the orbit `x` stays on the segment `x_a + x_b + x_c = |L|²`,
/// `c_b x_b + c_c x_c = D` (the split energy), `x ≥ 0`, and passes both of its
/// ends; `|ω|² = Σ x_j / I_j²` is linear in `x`, so its largest value is at an
/// end. With `c_b < 0 < c_c` (`a` the intermediate axis, `b` the largest
/// moment, as `classify` orders them) and `Δ = c_c − c_b`, one end is `x_a = 0`,
/// where `Δ x_b = P = c_c L_a² + Δ L_b²` and `Δ x_c = Q = Δ L_c² − c_b L_a²`; the
/// other is `x_b = 0` (`D ≥ 0`: `x_c = D / c_c`, `c_c x_a = P`) or `x_c = 0`
/// (`D < 0`: `x_b = D / c_b`, `−c_b x_a = Q`). `P`, `Q` are sums of
/// non-negative terms: no cancellation.
#[inline(always)]
fn orbit_max_omega2(c: &[f64; 3], x: [f64; 3]) -> f64 {
    let [ca, cb, cc] = *c;
    let d = cc - cb;
    let p = cc * x[0] + d * x[1];
    let q = d * x[2] - cb * x[0];
    let (ga, gb, gc) = (ca * ca, (ca + cb) * (ca + cb), (ca + cc) * (ca + cc));
    let end_a = (gb * p + gc * q) / d;
    let split = cb * x[1] + cc * x[2];
    let other = if split >= 0.0 { (ga * p + gc * split) / cc } else { (ga * q - gb * split) / -cb };
    end_a.max(other)
}

/// Whether `W² > max_rate2`, as [`orbit_max_omega2`] without its divisions
/// (each end's value is compared times its positive denominator).
#[inline(always)]
pub(super) fn orbit_max_omega2_exceeds(c: &[f64; 3], x: [f64; 3], max_rate2: f64) -> bool {
    let [ca, cb, cc] = *c;
    let d = cc - cb;
    let p = cc * x[0] + d * x[1];
    let q = d * x[2] - cb * x[0];
    let (ga, gb, gc) = (ca * ca, (ca + cb) * (ca + cb), (ca + cc) * (ca + cc));
    let split = cb * x[1] + cc * x[2];
    let (other, den) = if split >= 0.0 { (ga * p + gc * split, cc) } else { (ga * q - gb * split, -cb) };
    gb * p + gc * q > max_rate2 * d || other > max_rate2 * den
}

/// `W²` of the body `a` with body momentum `lb`.
#[inline(always)]
fn orbit_max_omega2_of(a: &Aniso, lb: &Vec3) -> f64 {
    let [ja, jb, jc] = a.axes.map(usize::from);
    orbit_max_omega2(&a.coef, [lb[ja] * lb[ja], lb[jb] * lb[jb], lb[jc] * lb[jc]])
}

/// `W` (rad/s) of the body `a` with body momentum `lb`.
fn orbit_max_omega_of(a: &Aniso, lb: &Vec3) -> f64 {
    orbit_max_omega2_of(a, lb).sqrt()
}

/// `W` (rad/s): the largest `|ω|` an asymmetric body reaches over its
/// torque-free orbit, the rate that decides its rotation substeps. It depends
/// only on `|L|` and the split energy, which every flow conserves, so it does
/// not change while the body flies free (a body keeps its `n`). For the box of
/// REFERENCES.md spun near its intermediate axis it is 1.26 times the initial `|ω|`
/// (the flip passes close to the fast minor axis).
pub fn orbit_max_omega(b: &Bodies, a: &Aniso) -> f64 {
    orbit_max_omega_of(a, &load(b, a.index as usize).1)
}

/// The bodies [`super::free_rotation::rotate_asymmetric`] left for being too fast: each takes its
/// rotation over `h` (the whole step) as `n = sub.count(W, h)` repetitions of the
/// composition `sub.weights` of splits over `h/n` (see [`Substeps`]). Consecutive half flows
/// about `b` merge into one (`B(s) B(t) = B(s + t)`: the flow keeps `L_b`) and
/// the flows about `L`, which commute with the others, into one `A(h)`: per
/// split one flow about `b` and one about `c`, plus one of each at the end.
/// `|L|` is restored to its loaded value at the end (every flow is a rotation,
/// but rounding would make `|L|` random-walk by about `√n` ulp per step).
pub fn rotate_fast(b: &mut Bodies, list: &[Aniso], h: f64, sub: Substeps) {
    for a in list {
        let i = a.index as usize;
        let (mut q, mut lb) = load(b, i);
        let n = sub.count(orbit_max_omega_of(a, &lb), h);
        let s = (&mut q, &mut lb, a, h, n, sub.weights);
        match (a.axes[1], a.axes[2]) {
            (0, 1) => fast_split::<0, 1>(s),
            (0, 2) => fast_split::<0, 2>(s),
            (1, 0) => fast_split::<1, 0>(s),
            (1, 2) => fast_split::<1, 2>(s),
            (2, 0) => fast_split::<2, 0>(s),
            (2, 1) => fast_split::<2, 1>(s),
            // Not an axis order `classify` gives: one body at a time.
            _ => {
                let (jb, jc) = (a.axes[1] as usize, a.axes[2] as usize);
                for _ in 0..n {
                    for &w in sub.weights {
                        let t = w * h / n as f64;
                        flow_axis(&mut q, &mut lb, jb, 0.5 * t * a.coef[1]);
                        flow_axis(&mut q, &mut lb, jc, t * a.coef[2]);
                        flow_axis(&mut q, &mut lb, jb, 0.5 * t * a.coef[1]);
                    }
                }
                flow_norm(&mut q, &lb, h * a.coef[0]);
            }
        }
        store(b, i, q, &lb);
    }
}

/// [`rotate_fast`] of one body with the split axes known at compile time:
/// `(q, L_body, body, h, n, weights)`.
#[inline(always)]
fn fast_split<const JB: usize, const JC: usize>(
    (q, lb, a, h, n, weights): (&mut Quat, &mut Vec3, &Aniso, f64, u32, &[f64]),
) {
    let l0 = lb.norm();
    let hs = h / n as f64;
    let (cb, cc) = (a.coef[1], a.coef[2]);
    let (mut q1, mut l1) = ([*q], [*lb]);
    // Time of the half flow about `b` the previous split left to do.
    let mut pending = 0.0;
    for _ in 0..n {
        for &w in weights {
            let t = w * hs;
            flow_axis_k::<JB, 1>(&mut q1, &mut l1, &[(pending + 0.5 * t) * cb]);
            flow_axis_k::<JC, 1>(&mut q1, &mut l1, &[t * cc]);
            pending = 0.5 * t;
        }
    }
    flow_axis_k::<JB, 1>(&mut q1, &mut l1, &[pending * cb]);
    let l = l1[0].norm();
    if l > 0.0 {
        l1[0] *= l0 / l;
    }
    flow_norm(&mut q1[0], &l1[0], h * a.coef[0]);
    (*q, *lb) = (q1[0], l1[0]);
}

#[cfg(test)]
mod tests {
    use super::*;
    use super::super::free_rotation::{rotate_asymmetric, rotate_asymmetric_one};
    use crate::body::storage::BodyInit;
    use crate::body::BodyKind;
    use crate::integrate::BodyLists;
    use crate::math::quat;

    fn one_body(inertia: [f64; 3], w_body: [f64; 3], rotvec: [f64; 3]) -> (Bodies, Aniso) {
        let mut b = Bodies::with_capacity(1);
        let q = quat::exp(&Vec3::from(rotvec));
        b.push(&BodyInit {
            kind: BodyKind::Dynamic,
            position: Vec3::zeros(),
            orientation: q,
            linear_velocity: Vec3::zeros(),
            angular_velocity: quat::rotate(&q, &Vec3::from(w_body)),
            mass: 1.0,
            inertia,
        });
        let lists = BodyLists::new(&b);
        assert_eq!(lists.asymmetric.len(), 1);
        (b, lists.asymmetric[0])
    }

    fn omega_body(b: &Bodies) -> Vec3 {
        quat::rotate_inv(&b.q(0), &Vec3::from(b.angular_velocity[0]))
    }

    /// `W` from the ends of the orbit's segment is the largest `|ω|` the body reaches:
    /// against the largest sampled along one traversal with tiny steps (0.002 rad of
    /// turn per step: the split's energy error, ~1e-7, and the sampling, ~1e-7, set
    /// the 1e-5 tolerance), for orbits near each axis and moments in three orders.
    #[test]
    fn orbit_max_omega_is_the_largest_omega_on_the_orbit() {
        let cases = [
            ([0.80833, 0.68333, 0.14167], [0.1, 5.0, 0.1]),
            ([0.80833, 0.68333, 0.14167], [5.0, 0.8, 0.6]),
            ([0.80833, 0.68333, 0.14167], [0.3, 0.5, 5.0]),
            ([2.0, 2.9, 1.0], [0.2, 0.3, 5.0]),
            ([0.0208, 0.0833, 0.1042], [2.0, 3.0, 4.0]),
        ];
        for (inertia, w) in cases {
            let (mut b, a) = one_body(inertia, w, [0.3, -0.2, 0.5]);
            let big_w = orbit_max_omega(&b, &a);
            let h = 0.002 / big_w;
            let mut seen: f64 = 0.0;
            // More than one period of ω for every case here (|ω| ~ 5 rad/s: 40 s).
            for _ in 0..(40.0 / h) as usize {
                rotate_asymmetric_one(&mut b, &a, h);
                seen = seen.max(omega_body(&b).norm());
            }
            assert!((seen / big_w - 1.0).abs() < 1e-5, "{inertia:?} {w:?}: sampled {seen}, W {big_w}");
        }
    }

    /// A group with fast bodies: those are left untouched and listed, every other body
    /// gets exactly the bits of the one-body reference (groups of one axis order with
    /// a fast member, a mixed group and the remainder).
    #[test]
    fn fast_bodies_leave_the_others_bit_identical() {
        let mut bodies = Bodies::with_capacity(16);
        let fast_ones = [1usize, 6, 9, 13];
        for k in 0..14 {
            let m = if (8..12).contains(&k) { [[1.0, 2.0, 2.5], [2.5, 1.0, 2.0]][k % 2] } else { [1.0, 2.0, 2.5] };
            let rate = if fast_ones.contains(&k) { 400.0 } else { 3.0 };
            let a = k as f64;
            bodies.push(&BodyInit {
                kind: BodyKind::Dynamic,
                position: Vec3::zeros(),
                orientation: quat::exp(&Vec3::new(a.sin(), a.cos(), 0.3 * a)),
                linear_velocity: Vec3::zeros(),
                angular_velocity: Vec3::new(a.cos(), 0.7, a.sin()).normalize() * rate,
                mass: 1.0,
                inertia: m,
            });
        }
        let lists = BodyLists::new(&bodies);
        let h = 1.0 / 60.0;
        let weights = [1.0];
        let sub = Substeps::new(0.2, h, &weights);
        let (mut grouped, mut reference) = (bodies.clone(), bodies.clone());
        let mut fast = Vec::new();
        rotate_asymmetric(&mut grouped, &lists.asymmetric, &lists.asymmetric_inv_spread, h, sub, &mut fast);
        let listed: Vec<usize> = fast.iter().map(|a| a.index as usize).collect();
        assert_eq!(listed, fast_ones);
        for a in &lists.asymmetric {
            if !fast_ones.contains(&(a.index as usize)) {
                rotate_asymmetric_one(&mut reference, a, h);
            }
        }
        assert_eq!(grouped.orientation, reference.orientation);
        assert_eq!(grouped.angular_velocity, reference.angular_velocity);
        for &k in &fast_ones {
            assert_eq!(grouped.orientation[k], bodies.orientation[k]);
        }
    }

    /// The fast path (half flows merged, one `A` at the end, `|L|` restored) is the
    /// composition repeated `n` times, to round-off: against `n` Yoshida steps of
    /// `rotate_asymmetric_one` (1e-12: a few ulp per flow over 3 × 21 splits).
    #[test]
    fn fast_path_is_the_repeated_composition() {
        let weights = crate::integrate::composition::yoshida4().drifts;
        let (b0, a) = one_body([0.80833, 0.68333, 0.14167], [9.6, 480.0, 9.6], [0.3, -0.2, 0.5]);
        let h = 1.0 / 60.0;
        let sub = Substeps::new(0.5, h, &weights);
        let n = sub.count(orbit_max_omega(&b0, &a), h);
        assert_eq!(n, 21); // ⌈1.2613 · 480.04 / 60 / 0.5⌉
        let (mut fast, mut plain) = (b0.clone(), b0);
        rotate_fast(&mut fast, &[a], h, sub);
        for _ in 0..n {
            for &w in &weights {
                rotate_asymmetric_one(&mut plain, &a, w * h / n as f64);
            }
        }
        assert!(quat::angle_between(&fast.q(0), &plain.q(0)) < 1e-12);
        let (wf, wp) = (omega_body(&fast), omega_body(&plain));
        assert!((wf - wp).norm() < 1e-12 * wp.norm());
    }

    /// `|L|` through many substeps stays at round-off: 1000 steps of a body taking
    /// 51 splits each (51 000 splits), world `L` within 1e-13.
    #[test]
    fn fast_path_keeps_angular_momentum() {
        let (mut b, a) = one_body([0.80833, 0.68333, 0.14167], [9.6, 480.0, 9.6], [0.3, -0.2, 0.5]);
        let l0 = b.spin_momentum(0);
        let h = 1.0 / 60.0;
        let sub = Substeps::new(0.2, h, &[1.0]);
        assert_eq!(sub.count(orbit_max_omega(&b, &a), h), 51);
        for _ in 0..1000 {
            rotate_fast(&mut b, &[a], h, sub);
        }
        assert!((b.spin_momentum(0) - l0).norm() < 1e-13 * l0.norm());
    }

    #[test]
    fn substep_counts() {
        let sub = Substeps::new(0.5, 0.1, &[1.0]);
        assert_eq!(sub.max_rate, 5.0);
        assert_eq!(sub.count(5.0, 0.1), 1);
        assert_eq!(sub.count(5.000001, 0.1), 2);
        assert_eq!(sub.count(20.0, -0.1), 4);
        assert_eq!(sub.count(0.0, 0.1), 1);
        assert_eq!(sub.count(f64::NAN, 0.1), 1);
        assert_eq!(sub.count(f64::INFINITY, 0.1), MAX_SUBSTEPS);
        assert_eq!(sub.count(1e300, 0.1), MAX_SUBSTEPS);
        assert_eq!(Substeps::NEVER.count(1e300, 1.0), 1);
    }
}
