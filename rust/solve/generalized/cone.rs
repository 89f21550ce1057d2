//! Coulomb friction of a patch on a link: the tangential impulse that stops the
//! patch if it fits the static cone, else the point of the sliding cone nearest
//! to it in the metric of the patch's effective mass `K` (the maximal dissipation
//! principle: the impulse is then opposite to the slip it leaves).
//!
//! The free bodies' rule (see [`crate::solve::friction`]) slides against the
//! slip measured before the impulse. That is Coulomb's law when `K` is nearly
//! isotropic, as it is for a body, but a patch on a link of a long chain is
//! heavy along the chain and light across it (`K` differs by orders of
//! magnitude between its two tangents), and an impulse along the old slip then
//! overshoots in the light direction and adds energy: a 20-link chain of thin
//! links on a rough floor gained energy at every substep and blew up. The
//! nearest point in the `K` metric never adds energy to the patch's motion:
//! `ΔE = ½‖λ − λ*‖²_K − ½‖λ₀ − λ*‖²_K ≤ 0` for `λ*` the impulse that stops it
//! and `λ₀` the accumulated one, inside the cone.

use crate::solve::contact::Constraint;
use crate::solve::friction::Patch;

/// Newton iterations at most for the sliding impulse, and its relative tolerance
/// on the cone's radius.
const ITERATIONS: usize = 30;
const TOLERANCE: f64 = 1e-12;

/// The patch's new tangential impulse for the slip `vt` (m/s) at normal impulse
/// `jn` (N·s), with `k = [a, b, c]` its `K = [[a, b], [b, c]]` (1/kg); updates
/// whether it slides. `f.tangent_mass` must be `K⁻¹`.
pub fn cone(f: &mut Patch, c: &Constraint, k: [f64; 3], vt: [f64; 2], jn: f64) -> [f64; 2] {
    let settled = jn.max(f.settled);
    let [ia, ib, ic] = f.tangent_mass;
    let stop = [f.impulse[0] - (ia * vt[0] + ib * vt[1]), f.impulse[1] - (ib * vt[0] + ic * vt[1])];
    let norm = (stop[0] * stop[0] + stop[1] * stop[1]).sqrt();
    let hold = if f.sliding { c.friction } else { c.static_friction };
    if norm <= hold * settled {
        f.sliding = false;
        return stop;
    }
    f.sliding = true;
    nearest_on_disk(k, stop, c.friction * jn)
}

/// The point of the disk of radius `r` nearest to `target` (outside it) in the
/// metric of `K`: `λ = (K + νI)⁻¹ K target` with `ν ≥ 0` such that `|λ| = r`,
/// by Newton's method on `1/|λ(ν)| − 1/r` (monotone from `ν = 0`).
fn nearest_on_disk(k: [f64; 3], target: [f64; 2], r: f64) -> [f64; 2] {
    let norm = (target[0] * target[0] + target[1] * target[1]).sqrt();
    if r <= 0.0 || norm == 0.0 {
        return [0.0; 2];
    }
    let [a, b, c] = k;
    let radial = [target[0] * r / norm, target[1] * r / norm];
    // Of rank one (see `rows::tangent_mass`): the cone's edge in the one direction.
    if !(a > 0.0 && c > 0.0 && a * c - b * b > 1e-9 * a * c) {
        return radial;
    }
    let kt = [a * target[0] + b * target[1], b * target[0] + c * target[1]];
    let mut nu = 0.0;
    let mut lambda = target;
    for _ in 0..ITERATIONS {
        let det = (a + nu) * (c + nu) - b * b;
        lambda = [((c + nu) * kt[0] - b * kt[1]) / det, ((a + nu) * kt[1] - b * kt[0]) / det];
        let len = (lambda[0] * lambda[0] + lambda[1] * lambda[1]).sqrt();
        if (len - r).abs() <= TOLERANCE * r || len == 0.0 {
            break;
        }
        // λᵀ (K + νI)⁻¹ λ
        let m = ((c + nu) * lambda[0] * lambda[0] - 2.0 * b * lambda[0] * lambda[1] + (a + nu) * lambda[1] * lambda[1]) / det;
        if m <= 0.0 {
            break;
        }
        nu += (1.0 / r - 1.0 / len) * len * len * len / m;
        nu = nu.max(0.0);
    }
    let len = (lambda[0] * lambda[0] + lambda[1] * lambda[1]).sqrt();
    if len > 0.0 && len.is_finite() {
        [lambda[0] * r / len, lambda[1] * r / len]
    } else {
        radial
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// `½ (λ − t)ᵀ K (λ − t)`.
    fn dist(k: [f64; 3], l: [f64; 2], t: [f64; 2]) -> f64 {
        let d = [l[0] - t[0], l[1] - t[1]];
        0.5 * (k[0] * d[0] * d[0] + 2.0 * k[1] * d[0] * d[1] + k[2] * d[1] * d[1])
    }

    #[test]
    fn the_sliding_impulse_is_the_nearest_point_of_the_disk_in_the_k_metric() {
        // Anisotropic K (1 : 300): compare with a fine scan of the circle.
        let (k, t, r) = ([1.0, 4.0, 300.0], [3.0, -0.7], 1.5);
        let l = nearest_on_disk(k, t, r);
        assert!(((l[0] * l[0] + l[1] * l[1]).sqrt() - r).abs() < 1e-12);
        let best = (0..200_000)
            .map(|i| {
                let a = i as f64 * std::f64::consts::TAU / 200_000.0;
                dist(k, [r * a.cos(), r * a.sin()], t)
            })
            .fold(f64::INFINITY, f64::min);
        assert!(dist(k, l, t) <= best + 1e-9, "{} vs {best}", dist(k, l, t));
    }

    #[test]
    fn isotropic_k_gives_the_radial_projection() {
        let l = nearest_on_disk([2.0, 0.0, 2.0], [3.0, 4.0], 1.0);
        assert!((l[0] - 0.6).abs() < 1e-14 && (l[1] - 0.8).abs() < 1e-14, "{l:?}");
    }
}
