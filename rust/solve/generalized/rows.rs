//! The rows of the constraints touching a link, built at every gather (the
//! velocity pass and the relax pass) from the constraints' current arms and each
//! articulation's factorization at its current pose (see the parent module).
//!
//! The effective masses are written where the shared rules read them: each
//! point's `normal_mass`, each patch's `tangent_mass` (the inverse of the 2 × 2
//! `K` of its two tangents, coupled through the articulation) and `twist_mass`.

use super::{ArtTerm, BodyTerm, Row};
use crate::articulation::contact::add_jacobian;
use crate::articulation::spatial::{force_at, join, Vec6};
use crate::articulation::{aba, Articulations};
use crate::math::{quat, Vec3};
use crate::solve::contact::{Constraint, ContactSolver};
use crate::solve::solver_body::Surface;

/// What a row pushes along: a force along `d` at the point the arms `r[0]`,
/// `r[1]` reach from the two bodies' centres of mass, or a couple about `d`.
#[derive(Clone, Copy)]
enum Along {
    Force { d: Vec3, r: [Vec3; 2] },
    Couple(Vec3),
}


/// Response along a row, as a fraction of the free bodies' (`1/m + (r×d)ᵀI⁻¹(r×d)`),
/// below which the links cannot move along it at all.
const IMMOBILE: f64 = 1e-12;

impl ContactSolver {
    /// Copies the joint velocities of the articulations in contact and builds
    /// the rows of every constraint touching a link. Each articulation's last
    /// solve must be at its current pose (its factorization gives the responses).
    pub fn gather_links(&mut self, arts: &mut Articulations) {
        if self.gen.constraints.is_empty() {
            return;
        }
        for s in &self.gen.slots {
            let (at, n) = (s.qd as usize, s.nv as usize);
            if let Some(art) = arts.list.get(s.art as usize) {
                self.gen.qd[at..at + n].copy_from_slice(&art.v[..n]);
            }
        }
        self.gen.rows.clear();
        self.gen.jac.clear();
        self.gen.resp.clear();
        for g in 0..self.gen.constraints.len() {
            self.link_rows(g, arts);
        }
    }

    /// Writes the solved joint velocities back to the articulations.
    pub fn scatter_links(&self, arts: &mut Articulations) {
        for s in &self.gen.slots {
            let (at, n) = (s.qd as usize, s.nv as usize);
            if let Some(art) = arts.list.get_mut(s.art as usize) {
                art.v[..n].copy_from_slice(&self.gen.qd[at..at + n]);
            }
        }
    }

    /// The rows of link constraint `g` and the effective masses of its points
    /// and patch.
    fn link_rows(&mut self, g: usize, arts: &mut Articulations) {
        let ci = self.gen.constraints[g].ci as usize;
        let c = self.constraints[ci];
        let first = self.gen.rows.len() as u32;
        let (start, end) = (c.start as usize, (c.start + c.len) as usize);
        self.material_arms(ci);
        let (mut r1, mut r2) = (Vec3::zeros(), Vec3::zeros());
        for pi in start..end {
            let p = self.points[pi];
            r1 += p.r1;
            r2 += p.r2;
            let k = self.push_row(&c, Along::Force { d: c.normal, r: [p.r1, p.r2] }, arts);
            self.points[pi].normal_mass = if k > 0.0 { 1.0 / k } else { 0.0 };
        }
        let friction = c.static_friction > 0.0;
        let twist = friction && self.patches[ci].lever > 0.0;
        if friction {
            // The patch's centre, as the shared patch takes it.
            let centre = [r1 / c.len as f64, r2 / c.len as f64];
            let a = self.push_row(&c, Along::Force { d: c.t1, r: centre }, arts);
            let cc = self.push_row(&c, Along::Force { d: c.t2, r: centre }, arts);
            let t = first as usize + c.len as usize;
            let b = self.cross(t, t + 1);
            let det = a * cc - b * b;
            self.patches[ci].tangent_mass = tangent_mass(a, b, cc, det);
            self.gen.constraints[g].k = [a, b, cc];
        }
        let twist_mass = if twist {
            let k = self.push_row(&c, Along::Couple(c.normal), arts);
            if k > 0.0 { 1.0 / k } else { 0.0 }
        } else {
            0.0
        };
        let lc = &mut self.gen.constraints[g];
        lc.twist_mass = twist_mass;
        lc.row = first;
        lc.friction = friction;
        lc.twist = twist;
    }

    /// The arms of `c`'s points to the material point of its link (the midpoint
    /// of the two material points between two links), where the separation the
    /// solver tracks is measured (see `Gap`): a link turns fast within a step
    /// (a chain whipping over an edge: 50 rad/s, a radian per step), and the
    /// free bodies' arms, which follow translations only, would then read the
    /// velocity of another point of it than the one whose gap they close. The
    /// bodies' arms and the patch follow, so that the shared warm start applies
    /// the impulses at the same point.
    fn material_arms(&mut self, ci: usize) {
        let c = self.constraints[ci];
        let x = |s: u32| self.p0[s as usize] + self.bodies[s as usize].dp;
        let (x1, x2) = (x(c.s1), x(c.s2));
        let link = |s: u32, b: u32| s != 0 && self.gen.link(b).is_some();
        let (l1, l2) = (link(c.s1, c.b1), link(c.s2, c.b2));
        let turn = |s: u32, a: &Vec3, side: u8, p: &crate::solve::contact::Point| {
            let sb = &self.bodies[s as usize];
            if sb.surface == Surface::Ball {
                return *a;
            }
            sb.rounded_arm(p, side, &c.normal).unwrap_or_else(|| quat::rotate(&sb.dq, a))
        };
        let (a1, a2) = (self.bodies[c.s1 as usize], self.bodies[c.s2 as usize]);
        for pi in c.start as usize..(c.start + c.len) as usize {
            let p = &self.points[pi];
            let (m1, m2) = (x1 + turn(c.s1, &p.anchor1, 1, p), x2 + turn(c.s2, &p.anchor2, 2, p));
            let point = match (l1, l2) {
                (true, true) => (m1 + m2) * 0.5,
                (true, false) => m1,
                _ => m2,
            };
            let p = &mut self.points[pi];
            p.r1 = point - x1;
            p.r2 = point - x2;
            p.rn1 = p.r1.cross(&c.normal);
            p.rn2 = p.r2.cross(&c.normal);
            p.irn1 = a1.inv_i * p.rn1;
            p.irn2 = a2.inv_i * p.rn2;
        }
        self.refresh_patch(ci);
    }

    /// Appends the row of `c` along `along` and returns its `K`.
    fn push_row(&mut self, c: &Constraint, along: Along, arts: &mut Articulations) -> f64 {
        let mut row = Row::default();
        let (mut k, mut free) = (0.0, 0.0);
        // The articulated sides: (articulation, link, spatial force, sign).
        let mut links: [Option<(usize, usize, Vec6, f64)>; 2] = [None, None];
        for (i, (s, b, sign)) in [(c.s1, c.b1, -1.0), (c.s2, c.b2, 1.0)].into_iter().enumerate() {
            if s == 0 {
                continue;
            }
            let sb = &self.bodies[s as usize];
            let (lin, ang) = match along {
                Along::Force { d, r } => (d, r[i].cross(&d)),
                Along::Couple(d) => (Vec3::zeros(), d),
            };
            free += lin.norm_squared() * sb.inv_m + ang.dot(&(sb.inv_i * ang));
            match self.gen.link(b) {
                Some((a, link)) => {
                    let f = match along {
                        Along::Force { d, r } => force_at(&d, &(self.p0[s as usize] + sb.dp + r[i])),
                        Along::Couple(d) => join(&d, &Vec3::zeros()),
                    };
                    links[i] = Some((a, link, f, sign));
                }
                None => {
                    let (lin, ang) = (lin * sign, ang * sign);
                    let (dlin, dang) = (lin * sb.inv_m, sb.inv_i * ang);
                    k += lin.dot(&dlin) + ang.dot(&dang);
                    row.body[i] = BodyTerm { s, lin, ang, dlin, dang };
                }
            }
        }
        // One response per articulation: two links of one articulation share it.
        let same = matches!(links, [Some(x), Some(y)] if x.0 == y.0);
        for i in 0..2 {
            let Some((a, link, f, sign)) = links[i] else { continue };
            if same && i == 1 {
                break;
            }
            let (Some(slot), Some(art)) = (self.gen.slot(a).copied(), arts.list.get_mut(a)) else { continue };
            let n = slot.nv as usize;
            let gen = &mut self.gen;
            gen.scratch_j.clear();
            gen.scratch_j.resize(n, 0.0);
            gen.scratch_r.clear();
            gen.scratch_r.resize(n, 0.0);
            add_jacobian(art, link, &f, sign, &mut gen.scratch_j);
            if let (true, Some((_, link2, f2, sign2))) = (same, links[1]) {
                add_jacobian(art, link2, &f2, sign2, &mut gen.scratch_j);
            }
            aba::response(art, &gen.scratch_j, &mut gen.scratch_r);
            k += gen.scratch_j.iter().zip(&gen.scratch_r).map(|(j, r)| j * r).sum::<f64>();
            row.art[i] = ArtTerm { at: gen.jac.len() as u32, qd: slot.qd, n: n as u32 };
            gen.jac.extend_from_slice(&gen.scratch_j);
            gen.resp.extend_from_slice(&gen.scratch_r);
        }
        // A direction the joints do not let the links move along (a contact
        // normal along a hinge's axis) comes out of the response as round-off,
        // 1e-31 to 1e-63 of the free body's: its inverse would push with 1e31
        // and more (NaN in one step).
        if k <= IMMOBILE * free {
            k = 0.0;
        }
        row.k = k;
        self.gen.rows.push(row);
        k
    }

    /// `J_a M⁻¹ J_bᵀ` of two rows of one constraint (same sides).
    fn cross(&self, a: usize, b: usize) -> f64 {
        let (ra, rb) = (&self.gen.rows[a], &self.gen.rows[b]);
        let mut k = 0.0;
        for i in 0..2 {
            let (x, y) = (&ra.body[i], &rb.body[i]);
            if x.s != 0 {
                k += x.lin.dot(&y.dlin) + x.ang.dot(&y.dang);
            }
            let (x, y) = (&ra.art[i], &rb.art[i]);
            let n = x.n as usize;
            if n > 0 {
                let (ja, rb) = (&self.gen.jac[x.at as usize..x.at as usize + n], &self.gen.resp[y.at as usize..y.at as usize + n]);
                k += ja.iter().zip(rb).map(|(j, r)| j * r).sum::<f64>();
            }
        }
        k
    }
}

/// Inverse of the tangent effective mass `[[a, b], [b, c]]` (`det` its
/// determinant). Where the links can move along one tangent direction only (a
/// contact on a hinge's axis) the matrix is of rank one and its determinant
/// round-off: its inverse there is the pseudo-inverse `K / tr(K)²`, friction
/// along the one direction that moves (the plain inverse pushed with 1e40).
fn tangent_mass(a: f64, b: f64, c: f64, det: f64) -> [f64; 3] {
    let trace = a + c;
    if det > RANK_ONE * a * c && det > 0.0 {
        [c / det, -b / det, a / det]
    } else if trace > 0.0 {
        let t2 = trace * trace;
        [a / t2, b / t2, c / t2]
    } else {
        [0.0; 3]
    }
}

/// `det / (a c)` of a tangent effective mass below which it is taken as of rank
/// one: `1 − cos²` of the angle between its two rows.
const RANK_ONE: f64 = 1e-9;

