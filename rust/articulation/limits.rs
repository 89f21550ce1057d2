//! Joint limits, hard: hinge and slide ranges, a spherical joint's cone (the
//! swing of the child's axis from its build direction) and twist (about that
//! axis). Each limit that the coming drift would cross is a row `J v ≥ b` over the
//! joint's dofs, `b = (bound − value) / h`, so the drift ends on the limit; the
//! rows are solved by projected Gauss–Seidel on non-negative impulses, each
//! impulse changing every velocity of the articulation by `(M + A)⁻¹ Jᵀ λ`
//! ([`super::aba::response`]): momentum-consistent inelastic stops, O(n) per row.

use super::aba;
use super::joint::JointModel;
use super::model::Articulation;
use crate::math::{Quat, Vec3};

/// Gauss–Seidel passes over the active limit rows.
const PASSES: usize = 8;

/// One active limit: `Σ coef[i] v[at + i] ≥ bound_rate`.
#[derive(Clone, Debug, serde::Serialize, serde::Deserialize)]
pub struct Row {
    pub at: usize,
    pub n: usize,
    pub coef: [f64; 3],
    pub bound_rate: f64,
    pub impulse: f64,
    /// `(M + A)⁻¹ Jᵀ` (nv) and `J (M + A)⁻¹ Jᵀ`.
    pub response: Vec<f64>,
    pub inv_mass: f64,
}

fn value(row: &Row, v: &[f64]) -> f64 {
    (0..row.n).map(|i| row.coef[i] * v[row.at + i]).sum()
}

/// The limit rows of the joints whose drift of `h` from `q` at `v` would cross a limit.
pub fn active_rows(art: &Articulation, q: &[f64], v: &[f64], h: f64) -> Vec<Row> {
    let mut rows = Vec::new();
    for link in &art.links {
        let c = &link.control;
        let (qa, va) = (link.q_at, link.v_at);
        let mut push = |n: usize, coef: [f64; 3], val: f64, rate: f64, lo: f64, hi: f64| {
            if val + h * rate < lo {
                rows.push(Row { at: va, n, coef, bound_rate: (lo - val) / h, impulse: 0.0, response: Vec::new(), inv_mass: 0.0 });
            } else if val + h * rate > hi {
                let neg = coef.map(|x| -x);
                rows.push(Row { at: va, n, coef: neg, bound_rate: (val - hi) / h, impulse: 0.0, response: Vec::new(), inv_mass: 0.0 });
            }
        };
        match link.model {
            JointModel::Revolute | JointModel::Prismatic => {
                if let Some([lo, hi]) = c.limits {
                    push(1, [1.0, 0.0, 0.0], q[qa], v[va], lo, hi);
                }
            }
            JointModel::Spherical => {
                let rel = Quat::new(q[qa + 3], q[qa], q[qa + 1], q[qa + 2]);
                let w = Vec3::new(v[va], v[va + 1], v[va + 2]);
                let t = link.frames.axis_child;
                if let Some(cone) = c.cone {
                    if let Some((angle, axis)) = swing(&rel, &t) {
                        push(3, axis.into(), angle, axis.dot(&w), f64::NEG_INFINITY, cone);
                    }
                }
                if let Some([lo, hi]) = c.twist {
                    push(3, t.into(), twist(&rel, &t), t.dot(&w), lo, hi);
                }
            }
            JointModel::Fixed | JointModel::Free => {}
        }
    }
    rows
}

/// Swing angle of the axis `t` under `rel` and the child-frame direction whose
/// angular velocity opens it; `None` at zero swing.
fn swing(rel: &Quat, t: &Vec3) -> Option<(f64, Vec3)> {
    let moved = crate::math::quat::rotate(rel, t);
    let n = t.cross(&moved);
    let s = n.norm();
    if s < 1e-12 {
        return None;
    }
    let angle = s.atan2(t.dot(&moved));
    Some((angle, crate::math::quat::rotate_inv(rel, &(n / s))))
}

/// Twist angle (rad, in (−π, π]) of `rel` about the axis `t`.
pub fn twist(rel: &Quat, t: &Vec3) -> f64 {
    let along = rel.i * t.x + rel.j * t.y + rel.k * t.z;
    let a = 2.0 * along.atan2(rel.w);
    if a > std::f64::consts::PI {
        a - 2.0 * std::f64::consts::PI
    } else if a <= -std::f64::consts::PI {
        a + 2.0 * std::f64::consts::PI
    } else {
        a
    }
}

/// Solves the rows on `v` in place (the factorization of the last solve at this
/// `q` must be current); returns each dof's impulse (N·m·s or N·s) in `impulse`.
pub fn solve(art: &mut Articulation, rows: &mut [Row], v: &mut [f64], impulse: &mut [f64]) {
    let nv = art.nv;
    let mut j = vec![0.0; nv];
    for row in rows.iter_mut() {
        j.fill(0.0);
        for i in 0..row.n {
            j[row.at + i] = row.coef[i];
        }
        row.response = vec![0.0; nv];
        aba::response(art, &j, &mut row.response);
        row.inv_mass = (0..row.n).map(|i| row.coef[i] * row.response[row.at + i]).sum();
    }
    for _ in 0..PASSES {
        for row in rows.iter_mut().filter(|r| r.inv_mass > 0.0) {
            let lambda = (row.impulse + (row.bound_rate - value(row, v)) / row.inv_mass).max(0.0);
            let d = lambda - row.impulse;
            row.impulse = lambda;
            if d != 0.0 {
                for (x, r) in v.iter_mut().zip(&row.response) {
                    *x += d * r;
                }
                for i in 0..row.n {
                    impulse[row.at + i] += d * row.coef[i];
                }
            }
        }
        if rows.len() <= 1 {
            break;
        }
    }
}
