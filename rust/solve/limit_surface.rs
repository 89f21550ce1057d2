//! The friction limit of a contact patch: the force and the torque about the
//! normal that Coulomb friction can give together (the limit surface of Goyal,
//! Ruina and Papadopoulos, 1991), for a uniform pressure over the patch.
//!
//! A patch that slides with velocity `v` at its centre and spins at `ω` about the
//! normal feels, at each point `r` of its area `A`, the friction `−μ p u/|u|`
//! with `u = v + ω × r`; summed, `f = −μ N ⟨u/|u|⟩` and `τ = −μ N ⟨r × u/|u|⟩`.
//! Force and torque are coupled: a plate that slides and spins feels neither the
//! full `μ N` nor the full twist `μ N r̄`, and slides farther and turns longer
//! than independent limits on each would let it. Pure spin gives the twist
//! `μ N r̄`, `r̄` the mean distance of the patch's area from its centre
//! (`a (√2 + asinh 1) / 3 ≈ 0.765 a` for a square of half side `a`, not the
//! `√2 a` of its corners).
//!
//! Whether a patch sticks is judged on the ellipsoid `|f|²/(μN)² + τ²/(μN r̄)² ≤ 1`
//! that touches the limit surface at pure sliding and pure spin (Howe and
//! Cutkosky, 1996); a sliding patch takes the exact force and torque of its slip,
//! integrated in closed form over the patch when both its sliding and its spin
//! count.

use super::patch_polygon::{area_centroid, farthest_pair, with_hull};

/// `sqrt(x² + y²)` (libm's `hypot` guards against overflow at several times the
/// cost; contact quantities are far from it).
#[inline(always)]
pub(crate) fn norm2(x: f64, y: f64) -> f64 {
    (x * x + y * y).sqrt()
}

/// Most corners a patch's polygon keeps.
pub const MAX_VERTICES: usize = 8;

/// Share of their hull's area above which the polygons of a patch's
/// manifolds are taken to fill it (see [`PatchShape::gathered`]).
const FILLED: f64 = 0.9;

/// Ratio of sliding to spin (`|v| / (r̄ |ω|)`) beyond which a patch is taken to
/// slide or spin only, and its friction is the closed form of that limit.
const PURE: f64 = 1e3;

/// The shape of a contact patch in its tangent plane, about its centre.
#[derive(Clone, Copy, Debug, Default, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct PatchShape {
    /// Corners of the convex polygon (m), counter-clockwise; `n` of them.
    pub corners: [[f64; 2]; MAX_VERTICES],
    pub n: u8,
    /// Mean distance of the patch (its area, or its length for a segment) from
    /// the centre (m): the lever of its twist. 0 for a single point.
    pub lever: f64,
}

impl PatchShape {
    /// The patch of the contact points `p` (tangent-plane coordinates about the
    /// patch centre, m): their convex hull, and its lever.
    #[cfg(test)]
    pub fn new(p: &[[f64; 2]]) -> Self {
        with_hull(p, |hull| Self::of_hull(hull, [0.0; 2]))
    }

    /// The patch of the contact points `p` about the centroid of their convex
    /// hull, and that centroid (in `p`'s coordinates): the centre of a
    /// uniform pressure. The mean of the points is not: points repeat where
    /// the manifolds of a face's triangles meet (see `super::coplanar`).
    pub fn centred(p: &[[f64; 2]]) -> (Self, [f64; 2]) {
        with_hull(p, |hull| {
            let centre = area_centroid(hull).1;
            (Self::of_hull(hull, centre), centre)
        })
    }

    /// The patch of the contact points `p` about `centre` (in `p`'s
    /// coordinates).
    pub fn about(p: &[[f64; 2]], centre: [f64; 2]) -> Self {
        with_hull(p, |hull| Self::of_hull(hull, centre))
    }

    /// The patch of the contact points `p` of several manifolds, `parts` of
    /// `p` (apart but for their edges), about where a uniform pressure over
    /// them is centred, and that centre: the centroid of their hull if they
    /// fill it (a face on triangles), else that of the union of their
    /// polygons (two feet). The union alone is not enough: parry keeps four
    /// points of a manifold, so a face's part on a triangle may lose a
    /// corner, and its centre moved (2 rad/s of yaw at 1/3000 s steps).
    pub fn gathered<'a>(p: &[[f64; 2]], parts: impl Iterator<Item = &'a [[f64; 2]]>) -> (Self, [f64; 2]) {
        let (hull_area, hull_centre) = with_hull(p, area_centroid);
        let (mut area, mut moment) = (0.0, [0.0; 2]);
        for part in parts {
            let (a, c) = with_hull(part, area_centroid);
            area += a;
            moment = [moment[0] + a * c[0], moment[1] + a * c[1]];
        }
        let centre = if area > 0.0 && area < FILLED * hull_area { [moment[0] / area, moment[1] / area] } else { hull_centre };
        (Self::about(p, centre), centre)
    }

    /// The patch of a convex polygon, counter-clockwise, about `centre`.
    fn of_hull(hull: &[[f64; 2]], centre: [f64; 2]) -> Self {
        let mut s = PatchShape::default();
        // More corners than kept (a cylinder's cap, a hull's face of many): every
        // other one, evenly, scaled about the centre to the whole polygon's
        // lever (a cap's 16 corners kept as an octagon turned on 0.633 R, the
        // disk's 2/3 R, and a can spun on its cap stopped 5 % late).
        let stride = hull.len().div_ceil(MAX_VERTICES).max(1);
        for (k, c) in hull.iter().step_by(stride).enumerate() {
            s.corners[k] = [c[0] - centre[0], c[1] - centre[1]];
            s.n = k as u8 + 1;
        }
        s.lever = mean_distance(s.corners());
        if stride > 1 && s.lever > 0.0 {
            let whole: Vec<[f64; 2]> = hull.iter().map(|c| [c[0] - centre[0], c[1] - centre[1]]).collect();
            let lever = mean_distance(&whole);
            let scale = lever / s.lever;
            for c in &mut s.corners[..s.n as usize] {
                *c = [c[0] * scale, c[1] * scale];
            }
            s.lever = lever;
        }
        s
    }

    fn corners(&self) -> &[[f64; 2]] {
        &self.corners[..self.n as usize]
    }

    fn farthest_pair(&self) -> ([f64; 2], [f64; 2]) {
        farthest_pair(self.corners())
    }

    /// Friction force (2D) and torque of the patch sliding with `v` at its
    /// centre and spinning at `w`, for the friction limit `mu_n = μ N` (an impulse
    /// or a force; the results are in the same unit, times m for the torque).
    pub fn sliding(&self, v: [f64; 2], w: f64, mu_n: f64) -> ([f64; 2], f64) {
        let speed = norm2(v[0], v[1]);
        let spin = w.abs() * self.lever;
        if speed == 0.0 && spin == 0.0 {
            return ([0.0; 2], 0.0);
        }
        if spin * PURE <= speed || self.lever == 0.0 {
            // Sliding only: Coulomb against v; a slow spin adds its first-order
            // torque, −μN ⟨|r|²⟩ ω / |v| ≈ the ellipsoid's.
            let t = -mu_n * self.lever * self.lever * w / speed;
            return ([-mu_n * v[0] / speed, -mu_n * v[1] / speed], t);
        }
        if speed * PURE <= spin {
            return ([0.0; 2], -mu_n * self.lever * w.signum());
        }
        let (f, t) = self.integrate(v, w);
        ([-mu_n * f[0], -mu_n * f[1]], -mu_n * t)
    }

    /// `⟨u/|u|⟩` and `⟨r × u/|u|⟩` over the patch, `u = v + ω × r`, exactly.
    ///
    /// The patch turns about its instantaneous centre `c = ẑ × v / ω`:
    /// `u = ω ẑ × (r − c)`, so with `e = (r − c)/|r − c|` the two means are
    /// `sgn ω · ẑ × ⟨e⟩` and `sgn ω · (⟨|r − c|⟩ + c·⟨e⟩)`; both integrals have
    /// closed forms over the triangles of a fan from `c` (see [`fan_triangle`]).
    /// A quadrature of 1152 points did this to 0.1 % at 200 times the cost: half
    /// the step of a pile of tumbling boxes.
    fn integrate(&self, v: [f64; 2], w: f64) -> ([f64; 2], f64) {
        let c = [-v[1] / w, v[0] / w];
        let k = self.corners();
        let (mut area, mut e, mut dist) = (0.0, [0.0; 2], 0.0);
        if k.len() >= 3 {
            for i in 0..k.len() {
                let (a, b) = (k[i], k[(i + 1) % k.len()]);
                let (ta, te, td) = fan_triangle([a[0] - c[0], a[1] - c[1]], [b[0] - c[0], b[1] - c[1]]);
                area += ta;
                e = [e[0] + te[0], e[1] + te[1]];
                dist += td;
            }
        }
        if !(area > 0.0) {
            let (a, b) = if k.len() >= 2 { self.farthest_pair() } else { ([0.0; 2], [0.0; 2]) };
            (area, e, dist) = segment_from([a[0] - c[0], a[1] - c[1]], [b[0] - c[0], b[1] - c[1]]);
        }
        if !(area > 0.0) {
            return ([0.0; 2], 0.0);
        }
        let (e, dist) = ([e[0] / area, e[1] / area], dist / area);
        let sign = w.signum();
        ([-sign * e[1], sign * e[0]], sign * (dist + c[0] * e[0] + c[1] * e[1]))
    }
}

/// Signed area, `∫ r/|r| dA` and `∫ |r| dA` of the triangle (0, a, b) (signed
/// by its orientation). About the foot `d n̂` of the perpendicular from the
/// origin on the edge, a point of the edge is `d n̂ + x ê`; with `t = x/d` the
/// direction `(cos θ, sin θ)` at angle `θ = atan t` from `n̂`, reaching
/// `ρ = d/cos θ`, so `∫ r/|r| dA = (d²/2) ∫ (sec θ, sec θ tan θ) dθ
/// = (d²/2) [asinh t, √(1 + t²)]` in (`n̂`, `ê`), and `∫ |r| dA` as in
/// [`triangle_from_origin`].
fn fan_triangle(a: [f64; 2], b: [f64; 2]) -> (f64, [f64; 2], f64) {
    let area = 0.5 * (a[0] * b[1] - a[1] * b[0]);
    let Some(t) = Edge::of(a, b) else { return (area, [0.0; 2], 0.0) };
    let ds = t.asinh_difference();
    let d2 = 0.5 * t.d * t.d;
    let (n_part, e_part) = (d2 * ds, d2 * (t.rb - t.ra));
    let e = [t.sign * (n_part * t.nt[0] + e_part * t.et[0]), t.sign * (n_part * t.nt[1] + e_part * t.et[1])];
    (area, e, t.distance(ds))
}

/// The edge ab of the triangle (0, a, b) seen from the origin: the foot `d n̂`
/// of the perpendicular on it, its direction `ê`, and the positions `t` of a
/// and b along it from the foot over `d`, with `√(1 + t²)`. None when the
/// edge passes (nearly) through the origin: no area to speak of.
struct Edge {
    d: f64,
    nt: [f64; 2],
    et: [f64; 2],
    ta: f64,
    tb: f64,
    ra: f64,
    rb: f64,
    /// The triangle's orientation (±1).
    sign: f64,
}

impl Edge {
    fn of(a: [f64; 2], b: [f64; 2]) -> Option<Edge> {
        let cross = a[0] * b[1] - a[1] * b[0];
        let ed = [b[0] - a[0], b[1] - a[1]];
        let len = norm2(ed[0], ed[1]);
        if len == 0.0 || cross == 0.0 {
            return None;
        }
        let d = cross.abs() / len;
        if d <= 1e-6 * len {
            return None;
        }
        let et = [ed[0] / len, ed[1] / len];
        let foot = [ed[1] * cross / (len * len), -ed[0] * cross / (len * len)];
        let along = |p: [f64; 2]| ((p[0] - foot[0]) * et[0] + (p[1] - foot[1]) * et[1]) / d;
        let (ta, tb) = (along(a), along(b));
        let (ra, rb) = ((1.0 + ta * ta).sqrt(), (1.0 + tb * tb).sqrt());
        Some(Edge { d, nt: [foot[0] / d, foot[1] / d], et, ta, tb, ra, rb, sign: cross.signum() })
    }

    /// Signed `∫ |r| dA` of the triangle, given `asinh tb − asinh ta`:
    /// `(d³/3) [½ (t √(1 + t²) + asinh t)]` (see [`triangle_from_origin`]).
    fn distance(&self, ds: f64) -> f64 {
        let sec3 = 0.5 * (self.tb * self.rb - self.ta * self.ra + ds);
        self.sign * self.d * self.d * self.d / 3.0 * sec3
    }

    /// `asinh tb − asinh ta`.
    fn asinh_difference(&self) -> f64 {
        asinh_difference(self.ta, self.ra, self.tb, self.rb)
    }
}

/// Length, `∫ r/|r| ds` and `∫ |r| ds` of the segment ab (a patch with no area:
/// its points in a line).
fn segment_from(a: [f64; 2], b: [f64; 2]) -> (f64, [f64; 2], f64) {
    let ed = [b[0] - a[0], b[1] - a[1]];
    let len = norm2(ed[0], ed[1]);
    if len == 0.0 {
        return (0.0, [0.0; 2], 0.0);
    }
    let et = [ed[0] / len, ed[1] / len];
    let xa = a[0] * et[0] + a[1] * et[1];
    // Signed distance of the line from the origin along n̂ = ẑ × ê.
    let d = et[0] * a[1] - et[1] * a[0];
    let nt = [-et[1], et[0]];
    let root = |x: f64| norm2(x, d);
    let (xb, ra, rb) = (xa + len, root(xa), root(xa + len));
    // asinh(xb/|d|) − asinh(xa/|d|), shared by both integrals.
    let ds = if d != 0.0 { asinh_difference(xa / d.abs(), ra / d.abs(), xb / d.abs(), rb / d.abs()) } else { 0.0 };
    let n_part = d * ds;
    let e = [n_part * nt[0] + (rb - ra) * et[0], n_part * nt[1] + (rb - ra) * et[1]];
    (len, e, 0.5 * (xb * rb - xa * ra + d * d * ds))
}

/// Whether force `f` and torque `tau` fit the friction limit `mu_n` of a patch
/// of lever `lever`: the ellipsoid through pure sliding and pure spin.
#[inline(always)]
pub fn inside(f: [f64; 2], tau: f64, mu_n: f64, lever: f64, tiny: f64) -> bool {
    // Compared squared: every friction solve asks, and the square root's
    // latency was a fifth of the ball pit's friction passes.
    let limit = mu_n + tiny;
    let force2 = f[0] * f[0] + f[1] * f[1];
    let twist2 = if lever > 0.0 { (tau / lever) * (tau / lever) } else { 0.0 };
    limit >= 0.0 && force2 + twist2 <= limit * limit
}

/// `(f, τ)` scaled onto the ellipsoid of `mu_n` (a sliding patch whose slip is
/// too slow to have a direction keeps the direction of the impulse that would
/// stop it).
#[inline(always)]
pub fn onto(f: [f64; 2], tau: f64, mu_n: f64, lever: f64) -> ([f64; 2], f64) {
    let twist = if lever > 0.0 { tau / lever } else { 0.0 };
    let n = norm2(norm2(f[0], f[1]), twist);
    if n == 0.0 {
        return ([0.0; 2], 0.0);
    }
    let s = mu_n / n;
    ([f[0] * s, f[1] * s], if lever > 0.0 { tau * s } else { 0.0 })
}

/// Area and `∫ |r| dA` of the triangle (0, a, b), exactly: in polar coordinates
/// about the origin the triangle is `0 ≤ ρ ≤ d / cos(θ − φ)`, `d` the distance
/// of the edge ab from the origin and `φ` its direction, so
/// `∫ |r| dA = (d³/3) ∫ sec³(θ − φ) dθ`. With `t = tan(θ − φ)`, the position
/// along the edge from the foot of the perpendicular over `d`, the primitive is
/// `½ (t √(1 + t²) + asinh t)`: no angle is needed (atan, sin_cos and ln took
/// 10 % of a pyramid's step, once per patch and step).
fn triangle_from_origin(a: [f64; 2], b: [f64; 2]) -> (f64, f64) {
    let area = 0.5 * (a[0] * b[1] - a[1] * b[0]);
    let Some(t) = Edge::of(a, b) else { return (area, 0.0) };
    (area, t.distance(t.asinh_difference()))
}

/// `asinh b − asinh a` given `ra = √(1 + a²)`, `rb = √(1 + b²)`, with one
/// logarithm (two were a twelfth of the step of a pile of tumbling boxes) and
/// no cancellation: `asinh t = ln(|t| + r)` signed, and the argument of
/// `ln_1p` is formed from sums of terms of one sign.
#[inline(always)]
fn asinh_difference(a: f64, ra: f64, b: f64, rb: f64) -> f64 {
    let (u, v) = (a.abs(), b.abs());
    if (a < 0.0) == (b < 0.0) {
        // Same side: ln((v + rv)/(u + ru)), and near 1 the ratio less one is
        // (v − u)(1 + (u + v)/(ru + rv))/(u + ru).
        // Far from 1 the ratio itself is exact enough (`ln_1p` near −1 is not).
        let x = (v - u) * (1.0 + (u + v) / (ra + rb)) / (u + ra);
        let s = if x.abs() < 0.5 { x.ln_1p() } else { ((v + rb) / (u + ra)).ln() };
        if b < 0.0 { -s } else { s }
    } else {
        // Either side of the foot: ln((u + ru)(v + rv)), and with
        // r − 1 = t²/(1 + r) the product less one is a sum of positive terms.
        let (ca, cb) = (u * u / (1.0 + ra), v * v / (1.0 + rb));
        let s = (u * v + u * rb + ra * v + ca * cb + ca + cb).ln_1p();
        if b < 0.0 { -s } else { s }
    }
}

/// `(1/A) ∫ |r| dA` over the convex polygon `c` (about the origin), exactly,
/// or over the segment of its farthest corners when it has no area.
fn mean_distance(c: &[[f64; 2]]) -> f64 {
    match c.len() {
        0 | 1 => 0.0,
        2 => segment_mean_distance(c[0], c[1]),
        _ => {
            let (mut area, mut moment) = (0.0, 0.0);
            for k in 0..c.len() {
                let (a, b) = (c[k], c[(k + 1) % c.len()]);
                let (ta, tm) = triangle_from_origin(a, b);
                area += ta;
                moment += tm;
            }
            let extent = c.iter().map(|p| norm2(p[0], p[1])).fold(0.0, f64::max);
            let lever = moment / area;
            // A sliver (points nearly in a line) is a segment.
            if area > 1e-6 * extent * extent && lever.is_finite() && lever <= extent {
                lever
            } else {
                let (a, b) = farthest_pair(c);
                segment_mean_distance(a, b)
            }
        }
    }
}

/// Mean distance from the origin of the points of the segment ab.
fn segment_mean_distance(a: [f64; 2], b: [f64; 2]) -> f64 {
    match segment_from(a, b) {
        (len, _, dist) if len > 0.0 => dist / len,
        _ => norm2(a[0], a[1]),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn square(a: f64) -> PatchShape {
        PatchShape::new(&[[a, a], [-a, a], [-a, -a], [a, -a]])
    }

    #[test]
    fn one_logarithm_gives_the_difference_of_two_asinh() {
        // Both signs on either side, near 0 (where `ln` of a ratio near 1
        // would lose the digits) and far out; against libm's `asinh`, to a
        // few ulps of the larger of the two.
        let ts = [-1e6, -30.0, -1.0, -1e-3, -1e-9, 0.0, 1e-9, 1e-3, 0.7, 1.0, 30.0, 1e6];
        for &a in &ts {
            for &b in &ts {
                let r = |t: f64| (1.0 + t * t).sqrt();
                let got = asinh_difference(a, r(a), b, r(b));
                let want = b.asinh() - a.asinh();
                let scale = a.asinh().abs().max(b.asinh().abs()).max(f64::MIN_POSITIVE);
                assert!((got - want).abs() <= 8.0 * f64::EPSILON * scale, "{a} {b}: {got} vs {want}");
            }
        }
    }

    #[test]
    fn the_lever_of_a_square_is_its_mean_distance_not_its_corners() {
        let a = 0.2;
        let exact = a * (2f64.sqrt() + 1f64.asinh()) / 3.0;
        assert!((square(a).lever - exact).abs() <= 1e-14, "{} vs {exact}", square(a).lever);
        // Sixteen points round the unit circle: every other one kept.
        let disc: Vec<[f64; 2]> = (0..16).map(|k| {
            let t = k as f64 * std::f64::consts::TAU / 16.0;
            [t.cos(), t.sin()]
        }).collect();
        let d = PatchShape::new(&disc);
        assert_eq!(d.n as usize, MAX_VERTICES);
        // Kept evenly: a regular octagon inscribed in the unit circle, whose mean
        // distance lies between the inscribed disc's 2/3·cos(π/8) and the circle's 2/3.
        assert!(d.lever > 2.0 / 3.0 * (std::f64::consts::PI / 8.0).cos() && d.lever < 2.0 / 3.0, "{}", d.lever);
        // A segment of half-length L through its centre: L/2.
        let s = PatchShape::new(&[[-0.3, 0.0], [0.3, 0.0]]);
        assert!((s.lever - 0.15).abs() <= 1e-15);
        assert_eq!(PatchShape::new(&[[0.1, 0.2]]).lever, 0.0);
    }

    #[test]
    fn pure_spin_and_pure_sliding_are_the_coulomb_limits() {
        let s = square(0.2);
        let (f, t) = s.sliding([0.0; 2], 3.0, 2.0);
        assert_eq!(f, [0.0; 2]);
        assert!((t + 2.0 * s.lever).abs() <= 1e-15);
        let (f, _) = s.sliding([3.0, 4.0], 0.0, 2.0);
        assert!((f[0] + 1.2).abs() <= 1e-15 && (f[1] + 1.6).abs() <= 1e-15);
    }

    #[test]
    fn sliding_and_spinning_together_lies_on_the_limit_surface_below_both_limits() {
        // v = 1, ω r̄ = 1: against a 100 x 100 grid sum of the same integrals.
        let a = 0.2;
        let s = square(a);
        let (v, w) = ([1.0, 0.0], 1.0 / s.lever);
        let (f, t) = s.sliding(v, w, 1.0);
        let n = 400;
        let (mut gf, mut gt) = ([0.0; 2], 0.0);
        for i in 0..n {
            for j in 0..n {
                let r = [(i as f64 + 0.5) / n as f64 * 2.0 * a - a, (j as f64 + 0.5) / n as f64 * 2.0 * a - a];
                let u = [v[0] - w * r[1], v[1] + w * r[0]];
                let l = u[0].hypot(u[1]);
                gf[0] -= u[0] / l;
                gf[1] -= u[1] / l;
                gt -= (r[0] * u[1] - r[1] * u[0]) / l;
            }
        }
        let k = (n * n) as f64;
        assert!((f[0] - gf[0] / k).abs() <= 1e-3 && (f[1] - gf[1] / k).abs() <= 1e-3, "{f:?} vs {:?}", [gf[0] / k, gf[1] / k]);
        assert!((t - gt / k).abs() <= 1e-3 * s.lever, "{t} vs {}", gt / k);
        assert!(f[0].hypot(f[1]) < 0.9 && t.abs() < 0.9 * s.lever);
    }

    /// The means of `integrate` by a centroid rule on 80² sub-triangles of each
    /// triangle (error ~1e-4 at the kink where u = 0, ~1e-6 elsewhere).
    fn quadrature(s: &PatchShape, v: [f64; 2], w: f64) -> ([f64; 2], f64) {
        let mut acc = [0.0; 4];
        let mut add = |r: [f64; 2], weight: f64| {
            let u = [v[0] - w * r[1], v[1] + w * r[0]];
            let n = norm2(u[0], u[1]);
            let u = if n > 0.0 { [u[0] / n, u[1] / n] } else { [0.0; 2] };
            acc[0] += weight * u[0];
            acc[1] += weight * u[1];
            acc[2] += weight * (r[0] * u[1] - r[1] * u[0]);
            acc[3] += weight;
        };
        let c = s.corners();
        if c.len() >= 3 {
            for k in 0..c.len() {
                triangle_points(c[k], c[(k + 1) % c.len()], &mut add);
            }
        } else {
            let m = 100_000;
            for i in 0..m {
                let t = (i as f64 + 0.5) / m as f64;
                add([c[0][0] + t * (c[1][0] - c[0][0]), c[0][1] + t * (c[1][1] - c[0][1])], 1.0);
            }
        }
        ([acc[0] / acc[3], acc[1] / acc[3]], acc[2] / acc[3])
    }

    /// Calls `add(point, weight)` at the centroids of the `QUAD²` equal sub-triangles
    /// of the triangle (0, a, b) (a centroid rule on each; weights are areas);
    /// returns its area.
    fn triangle_points(a: [f64; 2], b: [f64; 2], add: &mut impl FnMut([f64; 2], f64)) -> f64 {
        const QUAD: usize = 80;
        let area = 0.5 * (a[0] * b[1] - a[1] * b[0]).abs();
        let w = area / (QUAD * QUAD) as f64;
        let n = QUAD as f64;
        let at = |i: f64, j: f64| [(i * a[0] + j * b[0]) / n, (i * a[1] + j * b[1]) / n];
        for i in 0..QUAD {
            for j in 0..QUAD - i {
                let (fi, fj) = (i as f64, j as f64);
                // The upward sub-triangle (i, j), (i+1, j), (i, j+1) of the grid.
                add(at(fi + 1.0 / 3.0, fj + 1.0 / 3.0), w);
                if i + j + 1 < QUAD {
                    add(at(fi + 2.0 / 3.0, fj + 2.0 / 3.0), w);
                }
            }
        }
        area
    }


    #[test]
    fn the_exact_means_of_a_sliding_spinning_patch_match_a_fine_quadrature() {
        let shapes = [
            square(0.3),
            PatchShape::new(&[[0.0, 0.0], [0.4, 0.05], [0.1, 0.3]]),
            PatchShape::new(&(0..6).map(|k| {
                let t = k as f64 * std::f64::consts::TAU / 6.0 + 0.2;
                [0.2 * t.cos() + 0.01, 0.15 * t.sin()]
            }).collect::<Vec<_>>()),
            PatchShape::new(&[[-0.3, 0.1], [0.2, -0.05]]),
        ];
        // Centres of rotation inside, outside, on an edge's line and at a corner.
        let cases = [([0.1, 0.0], 2.0), ([0.0, -0.4], -1.5), ([1.0, 0.3], 0.7), ([-0.03, 0.02], 5.0), ([0.3 * 4.0, -0.3 * 4.0], 4.0)];
        for (k, s) in shapes.iter().enumerate() {
            for &(v, w) in &cases {
                let (f, t) = s.integrate(v, w);
                let (fq, tq) = quadrature(s, v, w);
                let scale = s.lever.max(1e-3);
                assert!(norm2(f[0] - fq[0], f[1] - fq[1]) < 2e-4, "shape {k} v {v:?} w {w}: {f:?} vs {fq:?}");
                assert!((t - tq).abs() < 2e-4 * scale, "shape {k} v {v:?} w {w}: {t} vs {tq}");
            }
        }
    }
}
