//! The solver's packed copy of the bodies it touches, gathered from the world
//! before each solve pass and scattered back after, and the register-held pair of
//! bodies a constraint is solved on.

use super::contact::{inv_inertia_world, refresh, Constraint, ContactSolver, Point};
use rayon::prelude::*;
use super::friction::Patch;
use crate::body::Bodies;
// Where a cylinder's contact leaves its flat cap for its rim or side (the
// narrow phase gives a flat cap its round polygon on the same bound).
use crate::collide::cylinder_cap::ACROSS_AXIS;
use crate::math::{quat, Mat3, Quat, Vec3};

/// A body as the solver sees it. Entry 0 stands for every fixed body.
///
/// Laid out in this order (`repr(C)`) so that what a pass reads of a body for
/// every contact (velocities, inverse mass, pose change, flags) comes first,
/// in two cache lines rather than the three the compiler's order spread it
/// over: a 1000-ball pit's bodies are read at random, 6 000 times a pass.
#[derive(Clone, Copy, Debug, serde::Serialize, serde::Deserialize)]
#[repr(C)]
pub struct SolverBody {
    pub v: Vec3,
    pub w: Vec3,
    pub inv_m: f64,
    /// Position and rotation change since the step start.
    pub dq: Quat,
    pub dp: Vec3,
    /// Whether its velocities are written back.
    pub dynamic: bool,
    /// How its contact points follow it as it turns (see [`Gap`]).
    pub surface: Surface,
    /// Moved by the position pass since its pose was gathered.
    pub pushed: bool,
    /// Moved by more than round-off since the last refresh of its
    /// constraints' arms (see `gather`).
    pub moved: bool,
    /// Index in the world's bodies.
    pub body: u32,
    /// The inverse inertia is `iso · 1` whatever the body's orientation (a
    /// uniform ball, a cube; fixed bodies, at 0): `inv_i` is kept exactly that
    /// and products with it are scalings (see [`SolverBody::inv_i_mul`]).
    pub iso: Option<f64>,
    pub inv_i: Mat3,
    /// Pose change at the last refresh of its constraints' arms.
    pub dp_ref: Vec3,
    pub dq_ref: Quat,
    /// Its rounded surface, for [`Surface::Rounded`].
    pub rounding: Rounding,
    /// The body's turn over one contact substep at its angular velocity
    /// when last gathered, `ω h` (rad; zero below [`MIN_CHORD`] and above [`MAX_CHORD`]): its material points
    /// travel the chord of their arc in a substep, not the tangent (see
    /// [`SolverBody::chord_gap`]).
    pub chord: Vec3,
}

/// How the contact points of a body follow it as it turns within a step.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[repr(u8)]
pub enum Surface {
    /// As material points: a box's corner, a point on a flat face.
    #[default]
    Material,
    /// Not at all: a ball touches under its centre however it spins.
    Ball,
    /// A capsule, a cylinder's side and rims, a cone's rim: see [`Rounding`].
    Rounded,
}

/// A rounded surface: a capsule (a ball swept along a segment, `axis` zero)
/// or a cylinder's side and rims or a cone's rim (circles of `radius` about
/// `axis`, world frame at the step start). Its contact point is the point of the surface
/// nearest the other body, not a material point: rolling about its axis, a
/// cylinder lying on the ground keeps touching under its axis. Followed as
/// material points, the points of a cylinder rolling at 10 rad/s (dt 1/60)
/// rose `r (1 − cos ωh)` a substep, and it sank 0.78 mm into the ground, 3.3 mm
/// at 30 rad/s, and bounced off it at 0.1 m/s.
#[derive(Clone, Copy, Debug, Default, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Rounding {
    pub radius: f64,
    pub axis: Vec3,
}

/// Turn per substep (rad) below which a body's material points are taken to
/// move along their tangents: the drift outward that leaves, `r θ² / 2` a
/// substep, is below 1e-7 m/s for r = 1 m at 240 substeps a second, and a
/// body at rest keeps the arithmetic it had without the chord.
pub const MIN_CHORD: f64 = 1e-5;

/// Turn per substep (rad) above which the chord is left out: a patch held by
/// static friction on a body turning faster (4.8 rad/s at 240 substeps a
/// second) is rare, and there the chord's target is a push, not a correction.
/// Found needed while the patches' drift was built (a cube spun at 1e3–1e8
/// rad/s wedged in a column gained up to ×2 energy in a step,
/// `tests/test_fast_spin_in_contact.py`; a cube pivoting over its edge at up
/// to 0.1 rad a substep lost its mirror symmetry, `tests/test_landing_symmetry.py`);
/// both pass without it since the landing's own instabilities were fixed
/// (`impulse::close_gaps`, `projected_gauss_seidel::Reach`), and it is kept as
/// a guard.
pub const MAX_CHORD: f64 = 0.02;

/// The [`chord`](SolverBody::chord) of a body turning `turn` (rad) in a substep.
pub fn chord(turn: Vec3) -> Vec3 {
    // Squared: the step's gathers compare every body's turn, and a square
    // root there was a fifth of their time.
    let angle2 = turn.norm_squared();
    if angle2 > MIN_CHORD * MIN_CHORD && angle2 <= MAX_CHORD * MAX_CHORD {
        turn
    } else {
        Vec3::zeros()
    }
}

impl Rounding {
    /// How much farther apart (m) than its material points the rounded surface
    /// is along the normal `n`, for `back` the normal turned back by the
    /// body's rotation since the step start (`ΔRᵀ n`). The surface
    /// point nearest the other body is its core point (on the capsule's segment,
    /// or the centre of the cylinder's rim circle: material, at `anchor + r u`)
    /// plus `r` across: along `n` for a capsule, `u` the normal's part across
    /// the axis for a cylinder. 0 at the step start.
    #[inline]
    pub(super) fn gap_change(&self, back: &Vec3, n: &Vec3) -> f64 {
        self.across(n).map_or(0.0, |u| self.gap_change_across(back, &u))
    }

    /// [`Self::gap_change`] given `u = across(n)`.
    #[inline]
    pub(super) fn gap_change_across(&self, back: &Vec3, u: &Vec3) -> f64 {
        let t = back.dot(&self.axis);
        self.radius * (back.dot(u) - (1.0 - t * t).max(0.0).sqrt())
    }

    /// The unit vector `u` across the axis toward the normal `n` (`n` itself
    /// for a capsule), if a contact of that normal touches the rounded surface.
    #[inline]
    pub(super) fn across(&self, n: &Vec3) -> Option<Vec3> {
        if self.axis == Vec3::zeros() {
            return Some(*n);
        }
        let s = n.dot(&self.axis);
        let across = 1.0 - s * s;
        (across >= ACROSS_AXIS).then(|| (n - self.axis * s) / across.sqrt())
    }

    /// The arm, after the body turned by `dq` since the step start, to the
    /// contact at `anchor` (on side `side`, 1 or 2, of a contact of normal `n`
    /// whose surfaces were `separation` apart, the anchor midway) moved to
    /// where the surface is nearest the other body: its core point turned with
    /// the body, then the radius across the turned axis and the half gap back.
    /// `None` where the contact is not on the rounded surface (a material
    /// point then).
    pub fn turned_arm(&self, dq: &Quat, anchor: &Vec3, side: u8, n: &Vec3, separation: f64) -> Option<Vec3> {
        let n = *n;
        let u = self.across(&n)?;
        // Body 2 lies along +n from the contact, body 1 along −n; its surface
        // is half the separation from the anchor, its core a radius further.
        let sign = if side == 2 { 1.0 } else { -1.0 };
        let to_surface = n * (sign * 0.5 * separation);
        let core = quat::rotate(dq, &(anchor + to_surface + u * (sign * self.radius)));
        let axis = quat::rotate(dq, &self.axis);
        let s = n.dot(&axis);
        let turned = if axis == Vec3::zeros() { n } else { (n - axis * s).try_normalize(0.0).unwrap_or(u) };
        Some(core - turned * (sign * self.radius) - to_surface)
    }
}

impl SolverBody {
    /// The arm of point `p` on side `side` (1 or 2) of a contact of normal
    /// `n` to where this body's rounded surface is nearest the other body
    /// ([`Rounding::turned_arm`]); `None` for any other surface, and for a
    /// corner of this body (a material point).
    pub fn rounded_arm(&self, p: &Point, side: u8, n: &Vec3) -> Option<Vec3> {
        if self.surface != Surface::Rounded || p.corner == side {
            return None;
        }
        let anchor = if side == 1 { &p.anchor1 } else { &p.anchor2 };
        self.rounding.turned_arm(&self.dq, anchor, side, n, p.separation)
    }

    /// How much farther (m) the material point at arm `r` travels in a
    /// substep than its velocity carries it: along the chord of its arc,
    /// `(R(θ) − I) r`, rather than the tangent, `θ × r` (`θ` the [`chord`](SolverBody::chord)).
    /// Zero for a ball's point and a rounded side's (they stay where the
    /// surface is nearest, not with the material). Friction holds the two
    /// bodies' chords together: on the tangents, a box held by static friction
    /// on a turntable moved outward by `r θ² / 2` a substep (10.5 mm in 10 s
    /// at 1 rad/s, r = 0.5 m, 60 Hz), kinematic or free.
    pub fn chord_gap(&self, r: &Vec3, n: &Vec3) -> Vec3 {
        let material = match self.surface {
            Surface::Material => true,
            Surface::Ball => false,
            Surface::Rounded => self.rounding.across(n).is_none(),
        };
        if !material || self.chord == Vec3::zeros() {
            return Vec3::zeros();
        }
        quat::rotate(&quat::exp(&self.chord), r) - r - self.chord.cross(r)
    }

    /// `I⁻¹ v` (world frame).
    #[inline(always)]
    pub fn inv_i_mul(&self, v: &Vec3) -> Vec3 {
        match self.iso {
            Some(s) => v * s,
            None => self.inv_i * v,
        }
    }

    /// Brings `inv_i` to world body `i`'s current orientation (nothing to do
    /// for an isotropic one).
    pub fn turn_inertia(&mut self, b: &Bodies, i: usize) {
        if self.dynamic && self.iso.is_none() {
            self.inv_i = inv_inertia_world(b, i);
        }
    }
}

impl Default for SolverBody {
    fn default() -> Self {
        Self {
            v: Vec3::zeros(),
            w: Vec3::zeros(),
            dp: Vec3::zeros(),
            dq: Quat::identity(),
            inv_m: 0.0,
            inv_i: Mat3::zeros(),
            iso: Some(0.0),
            body: u32::MAX,
            dynamic: false,
            surface: Surface::Material,
            rounding: Rounding::default(),
            dp_ref: Vec3::zeros(),
            dq_ref: Quat::identity(),
            moved: false,
            pushed: false,
            chord: Vec3::zeros(),
        }
    }
}

/// The two bodies of a constraint, held in registers while its points are solved.
/// Each vector padded to 32 bytes: spilled packed, the compiler wrote `v1.z`
/// and `w1.x` as one 16-byte store and read `w1.xy` back across two, a
/// store-forwarding stall that was 17 % of the ball pit's velocity passes
/// (2 % of its step).
#[repr(C)]
pub struct Pair {
    pub v1: Vec3,
    pad1: f64,
    pub w1: Vec3,
    pad2: f64,
    pub v2: Vec3,
    pad3: f64,
    pub w2: Vec3,
    pad4: f64,
    m1: f64,
    m2: f64,
}

impl Pair {
    #[inline(always)]
    pub fn load(bodies: &[SolverBody], c: &Constraint) -> Self {
        let (a, b) = (&bodies[c.s1 as usize], &bodies[c.s2 as usize]);
        Self {
            v1: a.v,
            pad1: 0.0,
            w1: a.w,
            pad2: 0.0,
            v2: b.v,
            pad3: 0.0,
            w2: b.w,
            pad4: 0.0,
            m1: a.inv_m,
            m2: b.inv_m,
        }
    }

    /// Writes the velocities back. The fixed bodies' entry 0 is left alone:
    /// its zero velocities come back unchanged (no inverse mass or inertia),
    /// and the groups passed over in parallel (see `super::contact_groups`)
    /// all touch it.
    #[inline(always)]
    pub fn store(&self, bodies: &mut [SolverBody], c: &Constraint) {
        if c.s1 != 0 {
            let a = &mut bodies[c.s1 as usize];
            a.v = self.v1;
            a.w = self.w1;
        }
        if c.s2 != 0 {
            let b = &mut bodies[c.s2 as usize];
            b.v = self.v2;
            b.w = self.w2;
        }
    }

    /// Point `p`'s [`curve`](Point::curve) at the pair's angular velocities,
    /// where it has one (substep `1 / inv_h`).
    #[inline(always)]
    pub fn curve(&self, bodies: &[SolverBody], c: &Constraint, p: &Point, inv_h: f64) -> f64 {
        super::rounded_curve::curve_now(bodies, c, p, Some((&self.w1, &self.w2)), inv_h)
    }

    #[inline(always)]
    pub fn normal_velocity(&self, c: &Constraint, p: &Point) -> f64 {
        c.normal.dot(&(self.v2 - self.v1)) + self.w2.dot(&p.rn2) - self.w1.dot(&p.rn1)
    }

    /// Change of point `a`'s normal velocity per unit normal impulse at point
    /// `b` of the same constraint (m/s per N·s): an entry of `K`.
    #[inline(always)]
    pub fn coupling(&self, a: &Point, b: &Point) -> f64 {
        self.m1 + self.m2 + a.rn1.dot(&b.irn1) + a.rn2.dot(&b.irn2)
    }

    #[inline(always)]
    pub fn apply_normal(&mut self, c: &Constraint, p: &Point, j: f64) {
        self.v1 -= c.normal * (j * self.m1);
        self.w1 -= p.irn1 * j;
        self.v2 += c.normal * (j * self.m2);
        self.w2 += p.irn2 * j;
    }

    /// [`Self::apply_normal`] for a [`Constraint::central`] point (its arms
    /// across the normal are zero).
    #[inline(always)]
    pub fn apply_central(&mut self, c: &Constraint, j: f64) {
        self.v1 -= c.normal * (j * self.m1);
        self.v2 += c.normal * (j * self.m2);
    }

    /// Tangential velocity of body 2 relative to body 1 at a patch's centre (m/s).
    #[inline(always)]
    pub fn patch_velocity(&self, c: &Constraint, f: &Patch) -> [f64; 2] {
        let dv = self.v2 - self.v1;
        [
            c.t1.dot(&dv) + self.w2.dot(&f.rt2[0]) - self.w1.dot(&f.rt1[0]),
            c.t2.dot(&dv) + self.w2.dot(&f.rt2[1]) - self.w1.dot(&f.rt1[1]),
        ]
    }

    /// Relative angular velocity about the normal (rad/s).
    #[inline(always)]
    pub fn twist_velocity(&self, c: &Constraint) -> f64 {
        c.normal.dot(&(self.w2 - self.w1))
    }

    /// A tangential impulse `d` (N·s, in the `t1, t2` basis) at a patch's centre.
    #[inline(always)]
    pub fn apply_patch(&mut self, c: &Constraint, f: &Patch, d: [f64; 2]) {
        let imp = c.t1 * d[0] + c.t2 * d[1];
        self.v1 -= imp * self.m1;
        self.w1 -= f.irt1[0] * d[0] + f.irt1[1] * d[1];
        self.v2 += imp * self.m2;
        self.w2 += f.irt2[0] * d[0] + f.irt2[1] * d[1];
    }

    /// An angular impulse `j` (N·m·s) about the normal.
    #[inline(always)]
    pub fn apply_twist(&mut self, f: &Patch, j: f64) {
        self.w1 -= f.in1 * j;
        self.w2 += f.in2 * j;
    }
}

/// [`ContactSolver::gather`] of the solver bodies `bodies`, the first of
/// them entry `from`, from the world's bodies `b` (`p0`, `q0`: every entry's
/// pose at the step start; `later`: not the step's first gather); whether
/// one moved enough for its contacts to be refreshed.
fn gather_range(bodies: &mut [SolverBody], from: usize, (p0, q0): (&[Vec3], &[Quat]), b: &Bodies, (later, inv_h): (bool, f64)) -> bool {
    let mut any = false;
    for (s, (p0, q0)) in bodies.iter_mut().zip(p0.iter().skip(from).zip(q0.iter().skip(from))) {
        let i = s.body as usize;
        s.v = Vec3::from(b.linear_velocity[i]);
        s.w = Vec3::from(b.angular_velocity[i]);
        // The turn of this substep, not the step start's. A body that turns
        // is refreshed every substep (it turns more than `MOVE_EPS`); one that
        // starts or stops turning is refreshed too, even if it hardly moved,
        // so that its patches' drift starts or stops with it (a ball's points
        // have none: see `chord_gap`): a can whose
        // spin friction stopped within a step kept its chord and was pushed
        // at 1e-8 m/s as it came to rest. A ball has no use for its chord
        // (three divisions a ball and gather in a ball pit).
        let new_turn = s.surface != Surface::Ball && {
            let turn = chord(s.w / inv_h);
            let new = (turn == Vec3::zeros()) != (s.chord == Vec3::zeros());
            s.chord = turn;
            new
        };
        s.dp = Vec3::from(b.position[i]) - p0;
        s.dq = b.q(i) * q0.conjugate();
        // A ball's contact geometry does not turn with it (its points stay
        // under its centre, `chord_gap` is zero): only its translation counts.
        let turned = if s.surface == Surface::Ball { 0.0 } else { (s.dq - s.dq_ref).norm_squared() };
        let far = MOVE_EPS * MOVE_EPS;
        s.moved = later && ((s.dp - s.dp_ref).norm_squared() > far || turned > far || new_turn);
        if s.moved {
            s.dp_ref = s.dp;
            s.dq_ref = s.dq;
            s.turn_inertia(b, i);
            any = true;
        }
    }
    any
}

/// Whether constraint `c` is due a refresh of its arms on the solver bodies
/// `bodies` (after a gather): a body of it moved by more than [`MOVE_EPS`]
/// since its last refresh. A central contact's refresh reads only how far
/// its bodies moved apart, `Δp2 − Δp1` (its line of centres, its arms
/// about the point the masses share, see `refresh`), so it waits until that
/// changed by `MOVE_EPS` since its own last refresh (`apart`, updated):
/// balls falling or rolling together keep their contacts' arms.
fn refresh_due(c: &Constraint, bodies: &[SolverBody], apart: &mut Vec3) -> bool {
    let (a, b) = (&bodies[c.s1 as usize], &bodies[c.s2 as usize]);
    if !(a.moved || b.moved) {
        return false;
    }
    if !c.central {
        return true;
    }
    let now = b.dp - a.dp;
    if (now - *apart).norm_squared() <= MOVE_EPS * MOVE_EPS {
        return false;
    }
    *apart = now;
    true
}

/// How far the points of one constraint have moved apart along its normal since
/// the step start, from the two bodies' pose changes: computed once per
/// constraint, it gives each point's separation with two dot products.
pub struct Gap {
    /// The normal in each body's step-start frame turned back by its rotation
    /// since, `ΔRᵀ n`: `n·(ΔR a) = (ΔRᵀ n)·a` for an anchor `a`.
    n1: Vec3,
    n2: Vec3,
    /// `n·(Δp2 − Δp1)` (m).
    shift: f64,
    /// How much farther apart each body's rounded surface is than its
    /// material points (m; see [`Rounding`]), for points not at its corners
    /// (a cone's apex is one, its rim round).
    round: [f64; 2],
}

impl Gap {
    /// Anchors turn with their body, as a box's corner does, except on a ball,
    /// whose contact point stays under its centre however it spins, and on a
    /// rounded surface (see [`Rounding`]).
    #[inline(always)]
    pub fn new(bodies: &[SolverBody], c: &Constraint) -> Self {
        let (a, b) = (&bodies[c.s1 as usize], &bodies[c.s2 as usize]);
        let back = |s: &SolverBody, fixed: bool| {
            if fixed || s.surface == Surface::Ball {
                c.normal
            } else {
                quat::rotate(&s.dq.conjugate(), &c.normal)
            }
        };
        let (n1, n2) = (back(a, c.s1 == 0), back(b, c.s2 == 0));
        let round = |s: &SolverBody, n: &Vec3| {
            if s.surface == Surface::Rounded {
                s.rounding.gap_change(n, &c.normal)
            } else {
                0.0
            }
        };
        Self { n1, n2, shift: c.normal.dot(&(b.dp - a.dp)), round: [round(a, &n1), round(b, &n2)] }
    }

    /// Current separation of a point (m): its step-start separation plus how far
    /// its anchors have moved apart along the normal since.
    #[inline(always)]
    pub fn separation(&self, p: &Point) -> f64 {
        let material = p.base_separation + self.shift + self.n2.dot(&p.anchor2) - self.n1.dot(&p.anchor1);
        let round = |side: u8| if p.corner == side { 0.0 } else { self.round[side as usize - 1] };
        material + round(1) + round(2)
    }
}

/// Displacement (m) and quaternion change (rad/2) since the last refresh below
/// which a body's contact arms are not recomputed: 1 µm, far below what a contact
/// resolves (the slop is 5 mm) and above what a body resting in a stack or a
/// pyramid sags or creeps per substep, so at rest nothing is recomputed. A body
/// moving faster than 1 µm per substep is refreshed every substep.
pub(crate) const MOVE_EPS: f64 = 1e-6;

/// Fewest constraints for the refresh of a gather to be split over threads.
const MIN_PARALLEL_REFRESH: usize = 256;

impl ContactSolver {
    /// Copies velocities and pose changes of the solver bodies from the world,
    /// and brings the inverse inertias and contact arms up to the current poses
    /// (after the first gather of a step, when they already are).
    ///
    /// A body that has moved less than `MOVE_EPS` since its last refresh keeps its
    /// arms: at rest (a stack, a pyramid) nothing is recomputed, and the angular
    /// momentum left unbalanced is at most that distance times the impulse.
    /// `relax`: the gather before the relax pass (the rounded contacts'
    /// curves are found before each velocity pass).
    pub fn gather(&mut self, b: &Bodies, relax: bool) {
        let later = self.substeps_done > 0 || self.gathered;
        self.gathered = true;
        let (p0, q0, inv_h) = (&self.p0[..], &self.q0[..], self.inv_h);
        let gather = |bodies: &mut [SolverBody], from: usize| gather_range(bodies, from, (p0, q0), b, (later, inv_h));
        let halves = self.by_halves().and(self.body_ends).filter(|&[k0, k1]| 1 <= k0 && k0 <= k1 && k1 <= self.bodies.len());
        let any = match halves {
            // Each thread writes the solver bodies its half's passes read next
            // (written here by the stepping thread alone, the helper's half
            // of the warm start fetched every one of them back: 31 µs a
            // substep against 18 for the stepping thread's half).
            Some([k0, k1]) => {
                let (head, rest) = self.bodies.split_at_mut(k0);
                let (second, seam) = rest.split_at_mut(k1 - k0);
                let (a, b) = super::team::both(|| gather(&mut head[1..], 1), || gather(second, k0));
                gather(seam, k1) | a | b
            }
            None => {
                let n = self.bodies.len();
                gather(self.bodies.get_mut(1..n).unwrap_or_default(), 1)
            }
        };
        if any {
            self.refresh_moved();
        }
        // Each substep, before its velocity pass (not again before the relax:
        // its velocities start the next substep, which takes its own). Once a
        // step, points whose curve was below the least at the step start were
        // left out until the next: Euler's disk at 30 rad/s sank 29 / 23 µm in
        // 0.1 s (1.77 / 1.98 µm now), and 300 cylinders tumbling onto a plane
        // stepped 1.17× faster.
        if !relax && self.bodies.iter().any(|s| s.surface == Surface::Rounded) {
            self.set_curves();
        }
    }

    /// The arms of the constraints of the bodies [`Self::gather`] found moved.
    fn refresh_moved(&mut self) {
        self.apart.resize(self.constraints.len(), Vec3::zeros());
        if self.wide() && self.constraints.len() >= MIN_PARALLEL_REFRESH && self.refresh_in_parallel() {
            return;
        }
        if let Some(h) = self.by_halves() {
            // Each constraint's refresh writes only its own points and patch
            // (and no support group: a split step has no blocks).
            self.each_half(h, |cs, range| {
                for ci in range {
                    if refresh_due(&cs.constraints[ci], &cs.bodies, &mut cs.apart[ci]) {
                        cs.refresh_constraint(ci);
                    }
                }
                false
            });
            return;
        }
        for ci in 0..self.constraints.len() {
            if refresh_due(&self.constraints[ci], &self.bodies, &mut self.apart[ci]) {
                self.refresh_constraint(ci);
            }
        }
    }

    /// The refresh of `gather` on the pool's threads (each constraint writes
    /// only its own points and patch); false, with nothing done, if the points
    /// are not laid out constraint after constraint.
    fn refresh_in_parallel(&mut self) -> bool {
        let bodies = &self.bodies;
        let ranges = self.constraints.iter().map(|c| (c.start as usize, c.len as usize));
        let Some(runs) = super::lists::runs(&mut self.points, ranges) else {
            return false;
        };
        let patches = self.patches.iter_mut().zip(self.shapes.iter_mut());
        let all = self.constraints.iter_mut().zip(self.apart.iter_mut()).zip(patches).zip(runs);
        let mut jobs: Vec<_> = all.filter_map(|(((c, apart), patch), points)| refresh_due(c, bodies, apart).then_some((c, patch, points))).collect();
        jobs.par_iter_mut().for_each(|(c, (patch, shape), points)| refresh(c, (patch, shape), points, bodies));
        let touched: Vec<u32> = jobs.iter().filter(|(c, _, _)| c.lower != 0).map(|(c, _, _)| c.group).collect();
        touched.into_iter().for_each(|g| self.support.touch(g));
        true
    }

    /// Writes the solved velocities of the dynamic solver bodies back.
    pub fn scatter(&self, b: &mut Bodies) {
        for s in &self.bodies[1..] {
            if s.dynamic {
                b.linear_velocity[s.body as usize] = s.v.into();
                b.angular_velocity[s.body as usize] = s.w.into();
            }
        }
    }

    /// Moves solver body `s` (and its world body) by `dx` and turns it by
    /// `dtheta`, keeping its inverse inertia current.
    pub fn displace(&mut self, b: &mut Bodies, s: usize, dx: &Vec3, dtheta: &Vec3) {
        let i = self.bodies[s].body as usize;
        b.position[i] = (Vec3::from(b.position[i]) + dx).into();
        let turn = quat::exp(dtheta);
        b.orientation[i] = quat::to_xyzw(&quat::normalize(&(turn * b.q(i))));
        let sb = &mut self.bodies[s];
        sb.dp += dx;
        sb.dq = turn * sb.dq;
        sb.turn_inertia(b, i);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use super::super::limit_surface::PatchShape;

    /// A body of `rounding` as side 2 of a contact of normal +z with the
    /// fixed world, turned by `turn` (rotation vector, rad) since the step start.
    fn gap(rounding: Rounding, turn: Vec3, anchor: Vec3) -> f64 {
        let c = Constraint { s1: 0, s2: 1, normal: Vec3::z(), len: 1, ..Default::default() };
        let body = SolverBody { dq: quat::exp(&turn), dynamic: true, surface: Surface::Rounded, rounding, ..Default::default() };
        let bodies = [SolverBody::default(), body];
        // Touching at the step start: separation 0.
        let p = Point { anchor2: anchor, base_separation: -anchor.z, ..Default::default() };
        Gap::new(&bodies, &c).separation(&p)
    }

    #[test]
    fn a_cylinder_rolling_about_its_axis_keeps_its_gap() {
        // Lying along y, touching under its axis at the end y = 0.2.
        let r = Rounding { radius: 0.1, axis: Vec3::y() };
        let anchor = Vec3::new(0.0, 0.2, -0.1);
        for theta in [0.05, 0.5, 2.0] {
            assert!(gap(r, Vec3::y() * theta, anchor).abs() <= 1e-15, "{theta}");
        }
        // Tilted about x, the rim at that end rises with its centre, 0.2 sin φ,
        // and its lowest point a further r (1 − cos φ) as the rim leans.
        let phi: f64 = 0.1;
        let exact = 0.2 * phi.sin() + 0.1 * (1.0 - phi.cos());
        assert!((gap(r, Vec3::x() * phi, anchor) - exact).abs() <= 1e-15);
    }

    #[test]
    fn a_capsule_turning_about_its_contact_keeps_touching_under_its_core() {
        // A capsule's point under a segment end: any turn about the segment's
        // point keeps it a radius above the floor.
        let r = Rounding { radius: 0.1, axis: Vec3::zeros() };
        let anchor = Vec3::new(0.0, 0.2, -0.1);
        let turn = Vec3::new(0.0, 0.7, 0.0);
        assert!(gap(r, turn, anchor).abs() <= 1e-15);
        // Material points would have risen r (1 − cos 0.7) = 23.5 mm.
        let material = gap(Rounding::default(), turn, anchor);
        assert!((material - 0.1 * (1.0 - 0.7f64.cos())).abs() <= 1e-15);
    }

    /// Two balls of radius 0.1 m touching along +z (ball 1 under ball 2),
    /// each displaced by `dp1`, `dp2` since the step start: the solver
    /// bodies (fixed entry, ball 1, ball 2) and their constraint and point.
    fn two_balls(dp1: Vec3, dp2: Vec3) -> ([SolverBody; 3], Constraint, Point) {
        let ball = |dp: Vec3| SolverBody { dp, inv_m: 1.0, iso: Some(250.0), inv_i: Mat3::identity() * 250.0, dynamic: true, surface: Surface::Ball, moved: true, ..Default::default() };
        let bodies = [SolverBody::default(), ball(dp1), ball(dp2)];
        let c = Constraint { s1: 1, s2: 2, len: 1, normal: Vec3::z(), t1: Vec3::x(), t2: Vec3::y(), central: true, ..Default::default() };
        let (a1, a2) = (Vec3::new(0.0, 0.0, 0.1), Vec3::new(0.0, 0.0, -0.1));
        // Touching: `Gap::separation` zero at the step start.
        let p = Point { anchor1: a1, anchor2: a2, r1: a1, r2: a2, base_separation: a1.z - a2.z, ..Default::default() };
        (bodies, c, p)
    }

    #[test]
    fn balls_moving_together_keep_their_contacts_arms() {
        // Moved together by 1 mm: the refresh gives back the arms as built
        // (to round-off of the displacement), so none is due.
        let together = Vec3::new(1e-3, -2e-3, 0.5e-3);
        let (bodies, mut c, mut p) = two_balls(together, together);
        let (built, _) = Patch::new(&c, &[p], &bodies);
        let mut apart = Vec3::zeros();
        assert!(!refresh_due(&c, &bodies, &mut apart));
        let (mut f, mut shape) = (built, PatchShape::default());
        refresh(&mut c, (&mut f, &mut shape), std::slice::from_mut(&mut p), &bodies);
        assert!((c.normal - Vec3::z()).norm() <= 1e-15 && (p.base_separation - 0.2).abs() <= 1e-15);
        assert!((p.r1 - Vec3::new(0.0, 0.0, 0.1)).norm() <= 1e-15);
        assert!((f.rt1[0] - built.rt1[0]).norm() <= 1e-15 && (f.irt2[1] - built.irt2[1]).norm() <= 1e-13);
        // Ball 2 moved 2 µm sideways relative to ball 1 (more than MOVE_EPS):
        // due, and its line of centres turns by 2e-6 / 0.2 rad.
        let side = Vec3::new(2e-6, 0.0, 0.0);
        let (bodies, mut c, mut p) = two_balls(together, together + side);
        assert!(refresh_due(&c, &bodies, &mut apart));
        assert_eq!(apart, bodies[2].dp - bodies[1].dp);
        refresh(&mut c, (&mut f, &mut shape), std::slice::from_mut(&mut p), &bodies);
        assert!((c.normal.x - 2e-6 / 0.2).abs() <= 1e-15);
        // Not again until they move apart by MOVE_EPS more.
        assert!(!refresh_due(&c, &bodies, &mut apart));
        // A contact that is not central is due whenever a body moved.
        let box_contact = Constraint { central: false, ..c };
        assert!(refresh_due(&box_contact, &bodies, &mut apart));
    }

    #[test]
    fn a_turning_bodys_point_travels_its_chord() {
        // 2.06 rad/s at 240 substeps a second: 8.6e-3 rad a substep.
        let (w, h) = (Vec3::new(0.3, -0.4, 2.0), 1.0 / 240.0);
        let body = SolverBody { chord: chord(w * h), ..Default::default() };
        assert_eq!(body.chord, w * h);
        let r = Vec3::new(0.5, 0.2, -0.1);
        let travelled = quat::rotate(&quat::exp(&(w * h)), &r) - r;
        let gap = body.chord_gap(&r, &Vec3::z());
        assert!((w.cross(&r) * h + gap - travelled).norm() <= 1e-15);
        // Not on a ball (its point stays under the centre), nor on a
        // cylinder's side; on its cap (a flat face's material points), yes.
        let ball = SolverBody { surface: Surface::Ball, ..body };
        assert_eq!(ball.chord_gap(&r, &Vec3::z()), Vec3::zeros());
        let rounding = Rounding { radius: 0.1, axis: Vec3::z() };
        let cylinder = SolverBody { surface: Surface::Rounded, rounding, ..body };
        assert_eq!(cylinder.chord_gap(&r, &Vec3::x()), Vec3::zeros());
        assert_eq!(cylinder.chord_gap(&r, &Vec3::z()), gap);
        // A body turning less than MIN_CHORD a substep has none, nor one
        // turning more than MAX_CHORD.
        assert_eq!(chord(Vec3::new(0.0, 0.0, 0.5 * MIN_CHORD)), Vec3::zeros());
        assert_eq!(chord(Vec3::new(0.0, 0.0, 2.0 * MAX_CHORD)), Vec3::zeros());
    }
}
