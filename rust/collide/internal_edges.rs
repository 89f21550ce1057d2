//! Seams between flush fixed shapes. A body resting a little into the box tile
//! it slides on reaches the top edge of the next tile, placed flush beside it;
//! that edge's contact normal leans back against the motion, and the body hops
//! over the seam (a cube sliding at 5 m/s over 0.5 m tiles hopped 7.7 cm and
//! stopped after 1.76 m instead of 4.24; a rolling ball hopped 9 cm).
//!
//! In the spirit of Jolt's internal edge removal: a contact of a moving body
//! with a fixed box or hull whose points all lie in the plane of a face the
//! same body rests on (another fixed shape's face, touching), down to as deep
//! as the body sinks into that face, is a contact with that plane: it takes
//! the face's normal, and its points are where the body meets the plane. The
//! next tile's top edge, or its side face just below the edge (which the
//! separating-axis test of two boxes picks while the overlap across the seam
//! is the smaller), is then floor. A real step (an edge above the plane) and
//! a wall (points up its height) are left alone.

use nalgebra::{Point3, Vector3};
use parry3d_f64::shape::Shape;

use super::collider::Collider;
use super::narrow_phase::{Manifold, PairState};
use crate::body::{BodyKind, Bodies};

/// How far (m) a point may lie from a face's plane, beyond how deep the body
/// sinks into it, and still be in it.
const FLUSH: f64 = 1e-6;

/// Normals closer than this (1 − cos) are one.
const SAME_NORMAL: f64 = 1e-9;

/// One contact pair of a moving body with a fixed box or hull.
struct Side {
    /// The moving body, the pair's slot, whether the fixed shape is collider 1.
    body: u32,
    slot: u32,
    fixed_first: bool,
}

/// Gives the edge contacts of the pairs `slots` that lie flush in a face
/// contact of the same body that face's normal (see the module; a face
/// contact counts if some point is within its pair's prediction). Returns
/// the slots of the pairs changed.
pub fn smooth(pairs: &mut [PairState], slots: impl Iterator<Item = u32>, colliders: &[Collider], bodies: &Bodies) -> Vec<u32> {
    let mut sides: Vec<Side> = slots.filter_map(|s| side(pairs.get(s as usize)?, s, colliders, bodies)).collect();
    let mut changed = Vec::new();
    if sides.len() < 2 {
        return changed;
    }
    sides.sort_by_key(|s| (s.body, s.slot));
    let mut start = 0;
    while start < sides.len() {
        let mut end = start + 1;
        while end < sides.len() && sides[end].body == sides[start].body {
            end += 1;
        }
        if end - start > 1 {
            smooth_body(pairs, &sides[start..end], colliders, bodies, &mut changed);
        }
        start = end;
    }
    changed
}

/// The pair in `state` as a moving body against a fixed box or hull, if it is one.
fn side(state: &PairState, slot: u32, colliders: &[Collider], bodies: &Bodies) -> Option<Side> {
    let (c1, c2) = colliders_of(state, colliders)?;
    let fixed = |c: &Collider| may_smooth(c, bodies);
    let moving = |c: &Collider| bodies.kind.get(c.body as usize) == Some(&BodyKind::Dynamic);
    if state.manifolds.is_empty() {
        return None;
    }
    match (fixed(c1) && moving(c2), fixed(c2) && moving(c1)) {
        (true, _) => Some(Side { body: c2.body, slot, fixed_first: true }),
        (_, true) => Some(Side { body: c1.body, slot, fixed_first: false }),
        _ => None,
    }
}

/// Whether collider `c`'s contacts may be smoothed here: a fixed box or hull.
pub fn may_smooth(c: &Collider, bodies: &Bodies) -> bool {
    bodies.kind.get(c.body as usize) == Some(&BodyKind::Fixed) && flat(c.shape.as_ref())
}

fn flat(s: &dyn Shape) -> bool {
    s.as_cuboid().is_some() || s.as_convex_polyhedron().is_some()
}

/// A manifold's normal out of the fixed shape (world) and the colliders as
/// (fixed, moving).
fn outward<'a>(m: &Manifold, side: &Side, c: (&'a Collider, &'a Collider), bodies: &Bodies) -> (Vector3<f64>, &'a Collider, &'a Collider) {
    let (fixed, moving) = if side.fixed_first { (c.0, c.1) } else { (c.1, c.0) };
    let n1 = c.0.pose(bodies).rotation * m.local_n1;
    (if side.fixed_first { n1 } else { -n1 }, fixed, moving)
}

/// A face of a fixed shape the body touches or is about to.
struct Face {
    /// Outward normal (world), plane offset `n·x` (m).
    normal: Vector3<f64>,
    offset: f64,
    /// How deep the body sinks into it (m, at least 0), and the separation of
    /// its nearest point (m, negative when sinking).
    depth: f64,
    nearest: f64,
}

/// The faces the body touches, then its other contacts with fixed shapes
/// lying in one of them, given its normal: the nearest such face's. A face
/// only predicted counts too (the body may be about to slide onto it), but
/// after the faces it rests on: a cube straddling a seam, turned 2 mrad,
/// came within the prediction of the side faces of the two tiles ahead; the
/// contact with one, along its top edge, lay in the plane of the other's side
/// face as well as in the floor's, was given the side face's normal, and
/// threw the cube 7.7 cm up.
fn smooth_body(pairs: &mut [PairState], sides: &[Side], colliders: &[Collider], bodies: &Bodies, changed: &mut Vec<u32>) {
    let mut faces: Vec<Face> = Vec::new();
    for s in sides {
        let state = &pairs[s.slot as usize];
        let Some(c) = colliders_of(state, colliders) else { continue };
        let reach = state.prediction;
        for m in state.manifolds.iter().filter(|m| m.subshape_pos1.is_none() && m.subshape_pos2.is_none()) {
            let (n, fixed, _) = outward(m, s, c, bodies);
            let Some(p) = m.points.iter().find(|p| p.dist <= reach) else { continue };
            if is_face_normal(fixed, bodies, &n) {
                let on_fixed = fixed.pose(bodies) * if s.fixed_first { p.local_p1 } else { p.local_p2 };
                let nearest = m.points.iter().map(|p| p.dist).fold(f64::INFINITY, f64::min);
                faces.push(Face { normal: n, offset: n.dot(&on_fixed.coords), depth: (-nearest).max(0.0), nearest });
            }
        }
    }
    if faces.is_empty() {
        return;
    }
    faces.sort_by(|a, b| a.nearest.total_cmp(&b.nearest));
    for s in sides {
        let state = &mut pairs[s.slot as usize];
        let Some(c) = colliders_of(state, colliders) else { continue };
        for m in state.manifolds.iter_mut().filter(|m| m.subshape_pos1.is_none() && m.subshape_pos2.is_none() && !m.points.is_empty()) {
            let (n, fixed, moving) = outward(m, s, c, bodies);
            let pose = fixed.pose(bodies);
            let flush = faces.iter().find(|f| {
                1.0 - f.normal.dot(&n) > SAME_NORMAL
                    && m.points.iter().all(|p| {
                        let h = f.normal.dot(&(pose * if s.fixed_first { p.local_p1 } else { p.local_p2 }).coords) - f.offset;
                        -(f.depth + FLUSH) <= h && h <= FLUSH
                    })
            });
            if let Some(f) = flush {
                onto_plane(m, s, (c.0, c.1), moving, bodies, (f.normal, f.offset));
                changed.push(s.slot);
            }
        }
    }
}

fn colliders_of<'a>(state: &PairState, colliders: &'a [Collider]) -> Option<(&'a Collider, &'a Collider)> {
    Some((colliders.get(state.key.0 as usize)?, colliders.get(state.key.1 as usize)?))
}

/// Whether world direction `n` is an outward face normal of the fixed box or hull.
fn is_face_normal(fixed: &Collider, bodies: &Bodies, n: &Vector3<f64>) -> bool {
    let local = fixed.pose(bodies).rotation.inverse() * n;
    super::touching_polyhedra::face_normals(fixed.shape.as_ref()).iter().any(|u| 1.0 - u.dot(&local) <= SAME_NORMAL)
}

/// Manifold `m` made a contact with the plane `n·x = d` (world, `n` out of the
/// fixed shape): the normal `n`, each point where the moving shape meets it (a
/// ball at its lowest point).
fn onto_plane(m: &mut Manifold, side: &Side, (c1, c2): (&Collider, &Collider), moving: &Collider, bodies: &Bodies, (n, d): (Vector3<f64>, f64)) {
    let (pose1, pose2) = (c1.pose(bodies), c2.pose(bodies));
    let pose_moving = moving.pose(bodies);
    let n12 = if side.fixed_first { n } else { -n };
    m.local_n1 = pose1.rotation.inverse() * n12;
    m.local_n2 = pose2.rotation.inverse() * -n12;
    for p in &mut m.points {
        let on_moving = match moving.ball {
            Some(r) => Point3::from(pose_moving.translation.vector) - n * r,
            None => pose_moving * if side.fixed_first { p.local_p2 } else { p.local_p1 },
        };
        let dist = n.dot(&on_moving.coords) - d;
        let on_fixed = on_moving - n * dist;
        let (q1, q2) = if side.fixed_first { (on_fixed, on_moving) } else { (on_moving, on_fixed) };
        p.local_p1 = pose1.inverse_transform_point(&q1);
        p.local_p2 = pose2.inverse_transform_point(&q2);
        p.dist = dist;
    }
}
