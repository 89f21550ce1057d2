//! One constraint, one friction patch, for a body's contacts with several
//! fixed shapes whose faces are flush: a box on a floor of tiles (boxes,
//! hulls or separate meshes), straddling a seam.
//!
//! Each tile is a collider pair of its own, and each pair a constraint with a
//! friction patch limited by its own share of the load. How a rigid face's
//! load splits between its patches is arbitrary (any split that balances its
//! moments), so their frictions, each at its own patch's centre, need not
//! cancel about the vertical: a 0.2 m cube sliding at 5 m/s along a seam,
//! 0.05 m off it, carried 0.87 of its weight on the quarter of its face over
//! one tile, and turned at 0.3 rad/s more each step, up to 12 rad/s. Within
//! one pair the manifolds of one normal already share a patch (see
//! [`super::coplanar`]); here the constraints of one moving body with fixed
//! or resting bodies (solver body 0, whose velocity is nil whichever it is),
//! of one normal, one plane and one material, become one: their points laid
//! out together, their fixed-side arms taken from one origin, one patch over
//! the union of their polygons. Each point remembers its pair ([`Part`]), so
//! its impulses go back to its own manifold and it is reported with its own
//! bodies.

use super::contact::{Constraint, ContactSolver, Point};
use super::coplanar::SAME_NORMAL_COS;
use super::friction::Patch;
use super::limit_surface::PatchShape;
use super::reuse;
use crate::body::Bodies;
use crate::math::Vec3;

/// How far apart (m) two fixed faces' planes may be, along the normal, and
/// still be flush: tiles placed flush agree to round-off; a 1 mm step is a
/// step.
const FLUSH: f64 = 1e-6;

/// Most pairs joined in one constraint (a point's part is a byte).
const MAX_PARTS: usize = u8::MAX as usize + 1;

/// Where the points of one pair begin in a joined constraint.
#[derive(Clone, Copy, Debug, Default, serde::Serialize, serde::Deserialize)]
pub struct Part {
    /// Index of its first point in `ContactSolver::points`.
    pub start: u32,
    /// The pair's index in the narrow phase's `pairs`, and its bodies.
    pub slot: u32,
    pub b1: u32,
    pub b2: u32,
}

/// Marks a constraint left alone.
const ALONE: u32 = u32::MAX;

impl ContactSolver {
    /// Joins the constraints of each moving body with flush fixed faces (see
    /// the module). Runs after the build, before the support plan.
    pub(crate) fn join_flush_pairs(&mut self, b: &Bodies) {
        self.parts.clear();
        let leads = self.flush_leads(b);
        if leads.is_empty() {
            return;
        }
        self.rebuild_joined(&leads, b);
    }

    /// Whether constraint `c` may join others: one side fixed (solver body 0),
    /// the other a dynamic body, not an articulation's.
    fn joinable(&self, c: &Constraint) -> bool {
        (c.s1 == 0) != (c.s2 == 0) && !c.generalized && c.len > 0 && self.bodies.get(moving(c)).is_some_and(|s| s.dynamic)
    }

    /// Per constraint, the constraint leading the group it joins (itself for
    /// a leader), or [`ALONE`]; empty when nothing joins.
    fn flush_leads(&self, b: &Bodies) -> Vec<u32> {
        let mut count = vec![0u8; self.bodies.len()];
        for c in self.constraints.iter().filter(|c| self.joinable(c)) {
            if let Some(n) = count.get_mut(moving(c)) {
                *n = n.saturating_add(1);
            }
        }
        let mut several: Vec<(u32, u32)> = (self.constraints.iter().enumerate())
            .filter(|(_, c)| self.joinable(c) && count.get(moving(c)).is_some_and(|&n| n >= 2))
            .map(|(ci, c)| (moving(c) as u32, ci as u32))
            .collect();
        if several.is_empty() {
            return Vec::new();
        }
        several.sort_unstable();
        let mut leads = vec![ALONE; self.constraints.len()];
        for body in several.chunk_by(|a, b| a.0 == b.0) {
            self.group_flush(body.iter().map(|&(_, ci)| ci as usize), b, &mut leads);
        }
        if leads.iter().all(|&l| l == ALONE) {
            return Vec::new();
        }
        leads
    }

    /// Groups one body's joinable constraints `cis` (in order) that are
    /// flush with a leader's: the same side fixed, normal, material and plane
    /// (a leader is marked once another joins it).
    fn group_flush(&self, cis: impl Iterator<Item = usize>, b: &Bodies, leads: &mut [u32]) {
        let mut leaders: Vec<(usize, usize)> = Vec::new();
        for ci in cis {
            let c = &self.constraints[ci];
            let found = leaders.iter_mut().find(|(l, n)| *n < MAX_PARTS && self.flush(&self.constraints[*l], c, b));
            match found {
                Some((l, n)) => {
                    leads[ci] = *l as u32;
                    leads[*l] = *l as u32;
                    *n += 1;
                }
                None => leaders.push((ci, 1)),
            }
        }
    }

    /// Whether `c` lies flush with `lead`.
    fn flush(&self, lead: &Constraint, c: &Constraint, b: &Bodies) -> bool {
        let same_material = lead.friction == c.friction && lead.static_friction == c.static_friction && lead.restitution == c.restitution;
        if (lead.s1 == 0) != (c.s1 == 0) || !same_material || lead.normal.dot(&c.normal) < SAME_NORMAL_COS {
            return false;
        }
        let (Some(p), Some(q)) = (self.points.get(lead.start as usize), self.points.get(c.start as usize)) else { return false };
        let face = |c: &Constraint, p: &Point| {
            let out = if c.s1 == 0 { c.normal } else { -c.normal };
            p.point - out * (p.separation * 0.5)
        };
        let apart = lead.normal.dot(&(face(c, q) - face(lead, p)));
        apart.abs() <= FLUSH && self.origin_of(c, b).is_some()
    }

    /// World position of the fixed body of `c` (its arms on that side are
    /// from there).
    fn origin_of(&self, c: &Constraint, b: &Bodies) -> Option<Vec3> {
        let fixed = if c.s1 == 0 { c.b1 } else { c.b2 };
        b.position.get(fixed as usize).map(|&x| Vec3::from(x))
    }

    /// The constraints, points, patches and polygons laid out again with each
    /// group of `leads` as one constraint where its leader was.
    fn rebuild_joined(&mut self, leads: &[u32], b: &Bodies) {
        let constraints = std::mem::take(&mut self.constraints);
        let patches = std::mem::take(&mut self.patches);
        let shapes = std::mem::take(&mut self.shapes);
        let points = std::mem::take(&mut self.points);
        let kept = std::mem::take(&mut self.previous.kept);
        // Each leader comes first in its group: the groups in leader order.
        let mut members: Vec<(u32, u32)> = (leads.iter().enumerate()).filter(|(_, &l)| l != ALONE).map(|(ci, &l)| (l, ci as u32)).collect();
        members.sort_unstable();
        let mut groups = members.chunk_by(|a, b| a.0 == b.0);
        for (ci, c) in constraints.iter().enumerate() {
            let lead = leads.get(ci).copied().unwrap_or(ALONE);
            if lead == ALONE {
                let start = self.points.len() as u32;
                self.points.extend_from_slice(range(&points, c));
                self.constraints.push(Constraint { start, ..*c });
                self.patches.push(patches.get(ci).copied().unwrap_or_default());
                self.shapes.push(shapes.get(ci).copied().unwrap_or_default());
                self.previous.kept.push(kept.get(ci).copied().unwrap_or(reuse::NONE));
            } else if lead == ci as u32 {
                let mut group: Vec<usize> = groups.next().unwrap_or_default().iter().map(|&(_, m)| m as usize).collect();
                if group.first() != Some(&ci) {
                    group = vec![ci];
                }
                self.push_joined(&constraints, &patches, &points, &group, b);
            }
        }
    }

    /// Appends the constraint of the group `group` (leader first) of
    /// `constraints`, its points rebased on the leader's fixed body, and its
    /// patch over their union, warm-started from the members'.
    fn push_joined(&mut self, constraints: &[Constraint], patches: &[Patch], points: &[Point], group: &[usize], b: &Bodies) {
        let lead = constraints[group[0]];
        let origin = self.origin_of(&lead, b).unwrap_or_default();
        let start = self.points.len() as u32;
        let mut force = Vec3::zeros();
        let (mut twist, mut sliding, mut fresh) = (0.0, false, true);
        for (k, &m) in group.iter().enumerate() {
            let c = &constraints[m];
            self.parts.push(Part { start: self.points.len() as u32, slot: c.slot, b1: c.b1, b2: c.b2 });
            let d = self.origin_of(c, b).unwrap_or(origin) - origin;
            for p in range(points, c) {
                self.points.push(rebased(p, d, &lead, k as u8));
            }
            if let Some(f) = patches.get(m) {
                force += c.t1 * f.impulse[0] + c.t2 * f.impulse[1];
                twist += f.twist;
                sliding |= f.sliding;
            }
            fresh &= c.fresh;
        }
        let len = self.points.len() as u32 - start;
        // Its points' arms are laid out below across the lead's normal: not central.
        let c = Constraint { start, len, fresh, as_built: false, joined: true, central: false, ..lead };
        let mut shape = PatchShape::default();
        let mut patch = Patch::default();
        patch.set_geometry(&mut shape, &c, &self.points[start as usize..], &self.bodies);
        // A ball on a seam touches every tile at its one point: its spin
        // friction is the lead's, over the Hertz patch it presses there.
        patch.spin = if lead.central { patches.get(group[0]).map_or(0.0, |f| f.spin) } else { 0.0 };
        patch.impulse = [force.dot(&c.t1), force.dot(&c.t2)];
        patch.twist = if patch.lever > 0.0 || patch.spin > 0.0 { twist } else { 0.0 };
        patch.sliding = sliding;
        self.constraints.push(c);
        self.patches.push(patch);
        self.shapes.push(shape);
        self.previous.kept.push(reuse::NONE);
    }
}

/// The pairs of constraint `c`, in the order of its points' `part` (none if
/// it is not joined), of a step's `parts`.
pub(crate) fn parts_of<'a>(parts: &'a [Part], c: &Constraint) -> &'a [Part] {
    if !c.joined {
        return &[];
    }
    parts.get(parts.partition_point(|q| q.start < c.start)..).unwrap_or(&[])
}

/// The solver body of `c` that moves (the other is solver body 0).
fn moving(c: &Constraint) -> usize {
    (if c.s1 == 0 { c.s2 } else { c.s1 }) as usize
}

/// The points of `c` in `points` (none if out of range).
fn range<'a>(points: &'a [Point], c: &Constraint) -> &'a [Point] {
    points.get(c.start as usize..(c.start + c.len) as usize).unwrap_or(&[])
}

/// Point `p` with its fixed-side anchor and arm taken from a fixed body `d`
/// (m) behind its own (its separation unchanged: see `Gap::separation`), of
/// part `part` of a joined constraint.
fn rebased(p: &Point, d: Vec3, lead: &Constraint, part: u8) -> Point {
    let mut q = *p;
    // The fixed side's inverse inertia is nil: its `I⁻¹ (r × n)` stays 0.
    if lead.s1 == 0 {
        q.anchor1 += d;
        q.r1 += d;
        q.rn1 = q.r1.cross(&lead.normal);
        q.base_separation += lead.normal.dot(&d);
    } else {
        q.anchor2 += d;
        q.r2 += d;
        q.rn2 = q.r2.cross(&lead.normal);
        q.base_separation -= lead.normal.dot(&d);
    }
    q.part = part;
    q
}

#[cfg(test)]
mod tests {
    use crate::body::Shape;
    use crate::collide::material::Material;
    use crate::world::{BodySpec, Scene, Settings, World};

    /// A 0.2 m cube at rest across the seam of two 0.5 m box tiles (the
    /// second `rise` higher, of friction `mu`), after one step.
    fn straddling(rise: f64, mu: f64) -> World {
        let mut scene = Scene::new([0.0, 0.0, -9.81]).unwrap();
        for (x, top, friction) in [(-0.25, 0.0, 0.3), (0.25, rise, mu)] {
            let tile = Some(Shape::cuboid([0.25; 3]).unwrap());
            let material = Material { friction, static_friction: friction, restitution: 0.0 };
            scene.add_body(BodySpec { shape: tile, fixed: true, position: [x, 0.0, top - 0.25], material, ..Default::default() }).unwrap();
        }
        let cube = Some(Shape::cuboid([0.1; 3]).unwrap());
        let material = Material { friction: 0.3, static_friction: 0.3, restitution: 0.0 };
        scene.add_body(BodySpec { shape: cube, density: Some(1000.0), position: [0.05, 0.0, 0.1 + rise.max(0.0)], material, ..Default::default() }).unwrap();
        let mut w = scene.build(&Settings::new(1.0 / 60.0)).unwrap();
        w.step(1).unwrap();
        w
    }

    /// Constraints of the last step, and how many of them are joined.
    fn joined(w: &World) -> (usize, usize) {
        let s = &w.collision.as_ref().unwrap().solver;
        (s.constraints.len(), s.constraints.iter().filter(|c| c.joined).count())
    }

    #[test]
    fn a_cube_on_two_flush_tiles_has_one_constraint_whose_points_report_their_own_tile() {
        let w = straddling(0.0, 0.3);
        assert_eq!(joined(&w), (1, 1));
        let s = &w.collision.as_ref().unwrap().solver;
        assert_eq!(s.parts.len(), 2);
        let reports = s.reports();
        for tile in [0, 1] {
            let mine: Vec<_> = reports.iter().filter(|r| r.body_a == tile).collect();
            assert!(!mine.is_empty());
            let (lo, hi) = if tile == 0 { (-0.5, 1e-9) } else { (-1e-9, 0.5) };
            assert!(mine.iter().all(|r| (lo..=hi).contains(&r.point[0])), "a point of tile {tile} lies off it");
        }
        let weight = 8.0 * 9.81 / 60.0;
        let carried: f64 = reports.iter().map(|r| r.normal_impulse).sum();
        assert!((carried - weight).abs() < 1e-6 * weight, "{carried} N·s for a weight of {weight}");
    }

    #[test]
    fn tiles_not_flush_or_of_another_material_are_not_joined() {
        // A millimetre higher: the cube rests on the higher tile, the lower
        // one's contact only predicted; another friction: two patches.
        assert_eq!(joined(&straddling(1e-3, 0.3)).1, 0);
        assert_eq!(joined(&straddling(0.0, 0.6)), (2, 0));
    }
}
