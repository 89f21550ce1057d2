//! Projected Gauss–Seidel on one block of [`super::block`], the fallback for
//! a body that tips or slides on its supports: sweeps over the block's rows in
//! impulse space, each face's normals together ([`super::small_lcp`]), its
//! friction on the patch's limit surface.

use super::block::{RowKind, Scratch, Target};
use super::contact::ContactSolver;
use super::friction::{invert3, mul3};
use super::limit_surface::norm2;
use super::small_lcp::{small_lcp_with, Factor, MAX_POINTS};
use crate::math::Vec3;

/// Projected Gauss–Seidel sweeps over a block's rows when its exact solution
/// does not fit the contact conditions (a body tipping or sliding).
const PGS_SWEEPS: usize = 12;

/// Scratch space of the faces solved together: per row, the length of the
/// run of a face's normals it opens, their `K` (at `row · MAX_POINTS`) and the
/// factor kept between sweeps (only grown: a factor is forgotten when its run
/// is laid out, and the rest is written before it is read); and per face of
/// the block, whether its patch stuck before the solve (kept here rather than
/// allocated per solve: a tumbling pile solves 30 000 blocks this way a step).
#[derive(Clone, Default)]
pub struct Runs {
    len: Vec<usize>,
    k: Vec<f64>,
    factors: Vec<Factor>,
    stuck: Vec<bool>,
}

impl ContactSolver {
    /// Projected Gauss–Seidel on block `g`'s `K` in impulse space: points push,
    /// friction stays in its cone (Coulomb: a patch that breaks away slides with
    /// the dynamic coefficient against its slip), position rows (`Free`) are
    /// unbounded. `together`: each face's normals solved as one (the velocity
    /// passes; in the position passes too, the columns of a landed 400-box
    /// pile kept rocking and began to topple after 600 steps).
    pub(super) fn projected_gauss_seidel(&mut self, g: usize, sc: &mut Scratch, together: bool) {
        let b = self.support.blocks[g];
        let (r0, r1) = (b.rows.0 as usize, b.rows.1 as usize);
        let m = r1 - r0;
        let rows = &self.support.rows[r0..r1];
        let targets = &self.support.targets[r0..r1];
        // `K y` is `J` of the upper body's change (the lower bodies are held),
        // kept as that change: a row's update costs six products, not `m`, and
        // `K` itself is never formed (a tumbling pile's blocks of 28 rows spent
        // a third of its step updating `K y`).
        let (mut dv, mut dw) = (Vec3::zeros(), Vec3::zeros());
        let kij = |i: usize, j: usize| rows[i].ju[0].dot(&rows[j].wu[0]) + rows[i].ju[1].dot(&rows[j].wu[1]);
        // Every slice cut to `m` rows: indices below `m` then need no checks.
        let (y, diag, r) = (&mut sc.y[..m], &mut sc.diag[..m], &sc.r[..m]);
        let (lambda, inv3, before) = (&sc.lambda[..m], &mut sc.inv3[..m], &mut sc.before[..m]);
        y.iter_mut().for_each(|v| *v = 0.0);
        for (i, d) in diag.iter_mut().enumerate() {
            *d = kij(i, i);
        }
        // The tangent pair and the twist (if any) of a patch: their 3×3 block.
        let twist_at = |i: usize| i + 2 < m && rows[i + 2].kind == RowKind::Twist && rows[i + 2].face == rows[i].face;
        for i in 0..m.saturating_sub(1) {
            if rows[i].kind == RowKind::Tangent(0) {
                let kk = |a: usize, b: usize| kij(i + a, i + b);
                inv3[i] = if twist_at(i) {
                    invert3([kk(0, 0), kk(0, 1), kk(0, 2), kk(1, 1), kk(1, 2), kk(2, 2)])
                } else {
                    invert3([kk(0, 0), kk(0, 1), 0.0, kk(1, 1), 0.0, 1.0])
                };
            }
        }
        // Which patches stuck before this solve.
        let faces = &self.support.faces[b.faces.0 as usize..b.faces.1 as usize];
        let stuck = &mut sc.runs.stuck;
        stuck.clear();
        stuck.extend(faces.iter().map(|&f| !self.patches[f as usize].sliding));
        let stuck = &*stuck;
        let held = |face: u32| faces.iter().position(|&f| f == face).is_some_and(|k| stuck[k]);
        let residual = |i: usize, dv: &Vec3, dw: &Vec3| r[i] - (rows[i].ju[0].dot(dv) + rows[i].ju[1].dot(dw));
        let add = |y: &mut [f64], dv: &mut Vec3, dw: &mut Vec3, i: usize, d: f64| {
            if d != 0.0 {
                y[i] += d;
                *dv += rows[i].wu[0] * d;
                *dw += rows[i].wu[1] * d;
            }
        };
        // Per row opening a face's run of normals solved together: its length
        // and (at `i · MAX_POINTS`) their `K`, the same every sweep.
        let (runs, face_k, factors) = (&mut sc.runs.len, &mut sc.runs.k, &mut sc.runs.factors);
        runs.clear();
        runs.resize(m, 0);
        if face_k.len() < m * MAX_POINTS {
            face_k.resize(m * MAX_POINTS, 0.0);
        }
        if factors.len() < m {
            factors.resize(m, Factor::default());
        }
        if together {
            let mut i = 0;
            while i < m {
                let face = rows[i].face;
                let end = (i..m).find(|&k| rows[k].face != face || !matches!(targets[k], Target::AtLeast(_))).unwrap_or(m);
                let n = end - i;
                if (2..=MAX_POINTS).contains(&n) {
                    runs[i] = n;
                    factors[i].forget();
                    for a in 0..n {
                        for c in 0..n {
                            face_k[i * MAX_POINTS + a * n + c] = kij(i + a, i + c);
                        }
                    }
                }
                i = end.max(i + 1);
                while i < m && rows[i].face == face {
                    i += 1;
                }
            }
        }
        // A residual this small is solved: round-off of the block's largest.
        let quiet = 1e-12 * r.iter().fold(0.0f64, |a, v| a.max(v.abs()));
        let settled = self.support.residual;
        for _ in 0..PGS_SWEEPS {
            before.copy_from_slice(y);
            let start = (dv, dw);
            let mut i = 0;
            while i < m {
                let face = rows[i].face;
                let mut normal = 0.0;
                // The face's points together (see `super::small_lcp`): one at a
                // time, the sweeps load the point they meet first.
                let n = runs[i];
                if n >= 2 {
                    let k = &face_k[i * MAX_POINTS..i * MAX_POINTS + n * n];
                    let (mut bv, mut x) = ([0.0; MAX_POINTS], [0.0; MAX_POINTS]);
                    let mut idle = true;
                    for a in 0..n {
                        let res = residual(i + a, &dv, &dw);
                        let l = lambda[i + a] + y[i + a];
                        // Nothing to do at a point that pushes and moves as asked,
                        // or carries nothing and separates.
                        idle &= if l > 0.0 { res.abs() <= quiet } else { res <= quiet };
                        let held: f64 = (0..n).map(|c| k[a * n + c] * (lambda[i + c] + y[i + c])).sum();
                        bv[a] = -(res + held);
                    }
                    if idle {
                        normal += (0..n).map(|a| lambda[i + a] + y[i + a]).sum::<f64>();
                        i += n;
                    } else if small_lcp_with(k, &bv[..n], &mut x[..n], &mut factors[i]) {
                        for a in 0..n {
                            add(y, &mut dv, &mut dw, i + a, x[a] - (lambda[i + a] + y[i + a]));
                            normal += x[a];
                        }
                        i += n;
                    }
                }
                while i < m && rows[i].face == face {
                    let res = residual(i, &dv, &dw);
                    let kii = diag[i];
                    match (rows[i].kind, targets[i]) {
                        (RowKind::Normal(_), Target::Skip) => normal += lambda[i] + y[i],
                        (RowKind::Normal(_), Target::AtLeast(_)) => {
                            let l = lambda[i] + y[i];
                            let new = if kii > 0.0 { (l + res / kii).max(0.0) } else { l.max(0.0) };
                            add(y, &mut dv, &mut dw, i, new - l);
                            normal += new;
                        }
                        (RowKind::Tangent(0), Target::Friction(_)) if i + 1 < m => {
                            // The tangent pair and the twist (if any) together, on
                            // the patch's limit surface.
                            let twist = twist_at(i);
                            let inv = inv3[i];
                            let res3 = [res, residual(i + 1, &dv, &dw), if twist { residual(i + 2, &dv, &dw) } else { 0.0 }];
                            let d = mul3(&inv, res3);
                            let l = [lambda[i] + y[i], lambda[i + 1] + y[i + 1], if twist { lambda[i + 2] + y[i + 2] } else { 0.0 }];
                            let (patch, c) = (&mut self.patches[face as usize], &self.constraints[face as usize]);
                            // A patch that slid before this solve rubs against its slip
                            // and spin as the sweeps leave them (with a zero target,
                            // minus what is left to do: Coulomb's law at the solution),
                            // while they are steady (see [`Reach::steady`]); slower, and one
                            // that stuck, breaks away along the impulse that would
                            // have held it, the direction the net force starts it
                            // sliding in (for one that stuck, the slip of its first
                            // sweeps is noise).
                            let cand = [l[0] + d[0], l[1] + d[1]];
                            let (slip, spin) = ([-res3[0], -res3[1]], -res3[2]);
                            let reach = Reach { k: [diag[i], diag[i + 1], if twist { diag[i + 2] } else { 0.0 }], lever: patch.lever };
                            let rubs = !held(face) && reach.steady(slip, spin, c.friction * normal);
                            let (slip, spin) = if rubs { (slip, spin) } else { ([0.0; 2], 0.0) };
                            let (f, t) = patch.settle(&self.shapes[face as usize], c, cand, l[2] + d[2], slip, spin, normal);
                            add(y, &mut dv, &mut dw, i, f[0] - l[0]);
                            add(y, &mut dv, &mut dw, i + 1, f[1] - l[1]);
                            if twist {
                                add(y, &mut dv, &mut dw, i + 2, t - l[2]);
                                i += 1;
                            }
                            i += 1;
                        }
                        (kind, _) => {
                            if kii > 0.0 {
                                add(y, &mut dv, &mut dw, i, res / kii);
                            }
                            if let RowKind::Normal(_) = kind {
                                normal += lambda[i] + y[i];
                            }
                        }
                    }
                    i += 1;
                }
            }
            // A sweep that changed no impulse has converged: the sweeps left
            // would repeat it. So has one that moved no row by the residual
            // the island sweeps take as solved (1e-6 g h): the impulses of a
            // face's dependent points may still wander, but nothing a row sees
            // (94 % of a tumbling pile's solves ran all twelve sweeps, most of
            // them still changing their impulses by 1e-6 of their size; a
            // settling 400-cube pile's 400 steps took 15 % less time). Measured
            // on the impulses instead, before a sliding patch read Coulomb's
            // law implicitly, the same bound let a box on a 40° incline slide
            // 3–4 % fast (`tests/test_friction.py` holds it now).
            if y == before || moved_less(rows, (dv - start.0, dw - start.1), settled) {
                break;
            }
        }
    }
}

/// Whether the change `(dv, dw)` of the upper body in one sweep moves every
/// row by less than `settled` (m/s).
fn moved_less(rows: &[super::block::Row], (dv, dw): (Vec3, Vec3), settled: f64) -> bool {
    rows.iter().all(|r| (r.ju[0].dot(&dv) + r.ju[1].dot(&dw)).abs() < settled)
}

/// What one solve of a patch's friction can do to its slip: the diagonal of
/// its rows' `K` (tangent pair and twist; 0 for no twist) and its lever (m).
struct Reach {
    k: [f64; 3],
    lever: f64,
}

impl Reach {
    /// Whether Coulomb's law may be read on the slip and spin `(slip, spin)`
    /// the sweep left, for the friction limit `mu_n`: read there, the law is
    /// explicit, and where the patch's whole friction changes its slip by more
    /// than the slip itself, `μN K > |u|`, it overshoots across it, each sweep
    /// further (a cube sliding off its edge onto a face at 8 mm/s: its friction
    /// across the slip grew ×3.7 a sweep, and the cube left its mirror plane at
    /// 1.3e-3 rad/s, `tests/test_landing_symmetry.py`). Below that the patch is
    /// nearly stopped and slides along the impulse that would stop it, the law's
    /// implicit form (exact for an isotropic `K`).
    fn steady(&self, slip: [f64; 2], spin: f64, mu_n: f64) -> bool {
        let speed = norm2(slip[0], slip[1]) + self.lever * spin.abs();
        speed > mu_n * (self.k[0] + self.k[1] + self.lever * self.lever * self.k[2])
    }
}
