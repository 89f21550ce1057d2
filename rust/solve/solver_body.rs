//! The solver's packed copy of the bodies it touches (gathered and scattered
//! in [`super::gather`], solved on in pairs by [`super::pair`]), their rounded
//! surfaces and chords, and the gap of a constraint's points as its bodies move.

use super::contact::{inv_inertia_world, Constraint, Point};
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

#[cfg(test)]
mod tests {
    use super::*;

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
