//! Cylinders and cones placed exactly touching. parry's manifold of a cylinder
//! or a cone and another solid with flat or straight features (a box, a hull, a
//! cylinder, a cone) starts from GJK's closest points, and GJK ending at
//! distance zero (to round-off) hands back an arbitrary direction, as it does
//! for two polyhedra (see [`super::touching_polyhedra`]): a can set down on a
//! round table 0.337 m off its centre got a sideways normal and points 1.05 m
//! deep, and slid 75 mm; a box set on it 0.5 m off centre got one point on a
//! normal tilted 63°, and tipped at 0.7 rad/s.
//!
//! A cylinder's side and a cone's are curved, so the polyhedra's test over
//! face normals does not cover them. Instead, where a point of such a
//! manifold (or of a compound's such parts: a table on round legs set on a
//! box slid 14 mm) is within [`TOUCH`] of touching, the manifold is computed again
//! with shape 2 moved away from shape 1 by [`SHIFT`] along the line between
//! their centres, where GJK's distance is well above round-off and its normal
//! that of the features that touch, and its points are brought back: each
//! point stays where it is on each shape, and its separation loses what the
//! shift added along the normal. Two convex solids touching have their
//! centres on either side of the plane between them, so the shift always
//! parts them. A normal found that way that is a flat face's (a cap's, a
//! box's face) is taken exactly, and the two faces are clipped one against
//! the other on it, as two polyhedra's are.

use nalgebra::{Isometry3, Translation3, Unit, Vector3};
use parry3d_f64::query::{DefaultQueryDispatcher, PersistentQueryDispatcher};
use parry3d_f64::shape::Shape;

use super::narrow_phase::Manifold;
use super::touching_polyhedra::{face_normals, part, part_pose, rebuild};

/// GJK distances (m) within this of zero are touching to round-off (as in
/// [`super::touching_polyhedra`]).
const TOUCH: f64 = 1e-9;

/// Angle (rad) within which the normal found apart is a flat face's: GJK a
/// micrometre apart resolves it to ~1e-9.
const SNAP: f64 = 1e-6;

/// How far (m) shape 2 is moved apart: far above the round-off of the poses
/// (1e-16 of the distances), far below anything a contact resolves.
const SHIFT: f64 = 1e-6;

/// A cylinder or a cone.
pub(super) fn axial(s: &dyn Shape) -> bool {
    s.as_cylinder().is_some() || s.as_cone().is_some()
}

/// A solid this module pairs with an axial shape: an axial shape, a box or a
/// hull (balls and capsules meet others at a distance of their radius from
/// their core, never at GJK's zero).
fn solid(s: &dyn Shape) -> bool {
    axial(s) || s.as_cuboid().is_some() || s.as_convex_polyhedron().is_some()
}

/// Whether two shapes (or parts of compounds) are a pair this module checks:
/// a cylinder or a cone with a solid.
fn applies(s1: &dyn Shape, s2: &dyn Shape) -> bool {
    (axial(s1) || axial(s2)) && solid(s1) && solid(s2)
}

/// Whether some manifold of the pair may be one this module checks (a
/// compound's parts may be cylinders: a table on four round legs).
pub fn may_apply(s1: &dyn Shape, s2: &dyn Shape) -> bool {
    let compound = |s: &dyn Shape| s.as_compound().is_some();
    (axial(s1) || axial(s2) || compound(s1) || compound(s2)) && (solid(s1) || compound(s1)) && (solid(s2) || compound(s2))
}

/// Computes again, apart (see the module docs), each manifold of the pair
/// (`pos12`: shape 2 in shape 1's frame) between a cylinder or a cone and a
/// solid found touching.
pub fn repair(manifolds: &mut [Manifold], s1: &dyn Shape, s2: &dyn Shape, pos12: &Isometry3<f64>, prediction: f64) {
    for m in manifolds.iter_mut() {
        let (p1, p2) = (part(s1, m.subshape1), part(s2, m.subshape2));
        if !applies(p1, p2) || !touching(m) {
            continue;
        }
        let pos = part_pose(m, pos12);
        recompute(m, p1, p2, &pos, prediction);
    }
}

/// Manifold `m` of the convex shapes `s1`, `s2` (`pos12`) computed with shape
/// 2 moved [`SHIFT`] apart along the line between their centres, brought back,
/// its normal taken exactly where it is a flat face's. Afresh: parry keeps a
/// manifold whose pose moved less than 1 µm and 1°, and starts GJK from its
/// normal.
fn recompute(m: &mut Manifold, s1: &dyn Shape, s2: &dyn Shape, pos12: &Isometry3<f64>, prediction: f64) {
    let Some(u) = pos12.translation.vector.try_normalize(0.0) else { return };
    let shifted = Translation3::from(u * SHIFT) * pos12;
    let (mut fresh, mut ws): (Vec<Manifold>, _) = (Vec::new(), None);
    if DefaultQueryDispatcher.contact_manifolds(&shifted, s1, s2, prediction + SHIFT, &mut fresh, &mut ws).is_err() {
        return;
    }
    let Some(mut f) = fresh.pop() else { return };
    f.match_contacts(&m.points);
    let back = SHIFT * u.dot(&f.local_n1);
    for p in &mut f.points {
        p.dist -= back;
    }
    if let Some(face) = flat_normal_near(s1, s2, pos12, &f.local_n1) {
        rebuild(&mut f, s1, s2, pos12, &face, true);
    }
    m.points = f.points;
    m.local_n1 = f.local_n1;
    m.local_n2 = f.local_n2;
}

/// Whether some point of `m` is within [`TOUCH`] (not only the GJK point:
/// a can set on the centre of a round table got no GJK point, and its
/// normal was tilted 5.4° toward the table's rim).
fn touching(m: &Manifold) -> bool {
    m.points.iter().any(|p| p.dist.abs() <= TOUCH)
}

/// The flat normal (a cap's, a face's; frame 1, from 1 toward 2) of either
/// shape within [`SNAP`] of `n`, if one is. Two flat faces that touch (a can
/// on a can, on a box) are then clipped one against the other on it: parry's
/// clipping of two caps that coincide kept two or three of their corners, and
/// a tower of ten cans set on each other rocked at 0.1 rad/s and moved 0.8 mm.
fn flat_normal_near(s1: &dyn Shape, s2: &dyn Shape, pos12: &Isometry3<f64>, n: &Vector3<f64>) -> Option<Unit<Vector3<f64>>> {
    let own = flat_normals(s1).into_iter();
    let other = flat_normals(s2).into_iter().map(|u| Unit::new_unchecked(pos12.rotation * -u.into_inner()));
    own.chain(other).find(|f| (f.into_inner() - n).norm() <= SNAP)
}

/// The outward normals of a shape's flat faces, in its own frame: a
/// cylinder's caps, a cone's base, a box's or a hull's faces.
fn flat_normals(s: &dyn Shape) -> Vec<Unit<Vector3<f64>>> {
    if s.as_cylinder().is_some() {
        vec![Vector3::y_axis(), -Vector3::y_axis()]
    } else if s.as_cone().is_some() {
        vec![-Vector3::y_axis()]
    } else {
        face_normals(s)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::UnitQuaternion;
    use parry3d_f64::shape::{Cone, Cuboid, Cylinder};

    /// The manifolds of shape 2 set exactly on top of shape 1 (both standing
    /// along y, parry's axis), `x` off its centre, posed through the world
    /// frame as the engine poses them (its up axis z: the round-off of that
    /// turn and of `2 h1 + h2` is what GJK meets).
    fn placed(s1: &dyn Shape, h1: f64, s2: &dyn Shape, h2: f64, x: f64) -> Vec<Manifold> {
        let up = UnitQuaternion::from_axis_angle(&Vector3::x_axis(), std::f64::consts::FRAC_PI_2);
        let p1 = Isometry3::from_parts(Vector3::new(0.0, 0.0, h1).into(), up);
        let p2 = Isometry3::from_parts(Vector3::new(x, 0.0, 2.0 * h1 + h2).into(), up);
        let pos12 = p1.inv_mul(&p2);
        let (mut m, mut ws) = (Vec::new(), None);
        DefaultQueryDispatcher.contact_manifolds(&pos12, s1, s2, 0.01, &mut m, &mut ws).unwrap();
        repair(&mut m, s1, s2, &pos12, 0.01);
        m
    }

    /// Cans, cubes and cones set exactly on a round table at 40 offsets
    /// each: without the repair 80 of the 120 got a tilted or sideways
    /// normal (40 cans, 39 cones, the cube 0.5 m off centre; the can 0.337 m
    /// off centre had points 1.05 m deep).
    #[test]
    fn shapes_set_exactly_on_a_cylinder_touch_on_its_cap() {
        let table = Cylinder::new(0.05, 1.0);
        let can = Cylinder::new(0.05, 0.05);
        let cube = Cuboid::new(Vector3::new(0.05, 0.05, 0.05));
        let cone = Cone::new(0.05, 0.05);
        let tops: [&dyn Shape; 3] = [&can, &cube, &cone];
        let mut bad = Vec::new();
        for (k, top) in tops.iter().enumerate() {
            for i in 0..40 {
                let x = [0.0, 0.337, 0.5].get(i).copied().unwrap_or(0.9 * (i as f64 * 0.618034).fract());
                let m = placed(&table, 0.05, *top, 0.05, x);
                // GJK 0.1–1 µm apart resolves the normal to round-off over
                // that distance, ~1e-9.
                let ok = m.len() == 1 && (m[0].local_n1 - Vector3::y()).norm() < 1e-8 && m[0].points.iter().all(|p| p.dist.abs() <= TOUCH);
                if !ok {
                    bad.push((k, x));
                }
            }
        }
        assert!(bad.is_empty(), "wrong manifolds at (case, offset) {bad:?}");
    }
}
