//! Tests of `reuse`: kept geometry is what computing it afresh at the kept
//! anchors gives, bit for bit, and it is dropped once a body turns.

use super::{KEEP_EPS, NONE};
use crate::math::Vec3;
use crate::body::Shape;
use crate::solve::contact::{normal_mass, ContactSolver};
use crate::solve::friction::Patch;
use crate::world::{BodySpec, Scene, Settings, World};

/// A pyramid of six boxes on the ground, sleeping off.
fn pyramid() -> World {
    let mut scene = Scene::new([0.0, 0.0, -9.81]).unwrap();
    let ground = BodySpec { shape: Some(Shape::plane([0.0, 0.0, 1.0], 0.0).unwrap()), fixed: true, ..Default::default() };
    scene.add_body(ground).unwrap();
    for (row, n) in [3usize, 2, 1].iter().enumerate() {
        for j in 0..*n {
            let x = (j as f64 - (*n as f64 - 1.0) / 2.0) * 1.02;
            let spec = BodySpec {
                shape: Some(Shape::cuboid([0.5; 3]).unwrap()),
                density: Some(1000.0),
                position: [x, 0.0, 0.5 + row as f64],
                ..Default::default()
            };
            scene.add_body(spec).unwrap();
        }
    }
    let mut settings = Settings::new(1.0 / 60.0);
    settings.sleep.enabled = false;
    scene.build(&settings).unwrap()
}

fn solver(w: &World) -> &ContactSolver {
    &w.collision.as_ref().unwrap().solver
}

/// Constraints of the last step that took their geometry from the step before.
fn kept(s: &ContactSolver) -> Vec<usize> {
    (0..s.constraints.len()).filter(|&ci| s.previous.kept.get(ci).is_some_and(|&k| k != NONE)).collect()
}

#[test]
fn kept_geometry_is_the_geometry_of_its_anchors() {
    let mut w = pyramid();
    w.step(120).unwrap();
    // One more step, stopped after prepare: what the solve will use.
    w.step(1).unwrap();
    let s = solver(&w);
    let kept = kept(s);
    assert_eq!(kept.len(), s.constraints.len(), "a pyramid at rest keeps every contact");
    for &ci in &kept {
        let c = s.constraints[ci];
        if !c.as_built {
            continue;
        }
        let points = &s.points[c.start as usize..(c.start + c.len) as usize];
        for p in points {
            let mut fresh = *p;
            fresh.r1 = p.anchor1;
            fresh.r2 = p.anchor2;
            normal_mass(&mut fresh, (&s.bodies[c.s1 as usize], &s.bodies[c.s2 as usize]), &c.normal, c.central);
            assert_eq!(fresh.normal_mass.to_bits(), p.normal_mass.to_bits());
            assert_eq!(fresh.irn1, p.irn1);
        }
        let (f, shape) = Patch::new(&c, points, &s.bodies);
        let k = &s.patches[ci];
        assert_eq!((f.friction_mass, f.tangent_mass, f.lever), (k.friction_mass, k.tangent_mass, k.lever));
        assert_eq!(shape, s.shapes[ci]);
    }
}

#[test]
fn a_turned_body_gets_its_geometry_afresh() {
    let mut w = pyramid();
    w.step(120).unwrap();
    // Turn the apex box by 0.01 rad about the vertical: its contacts move
    // 5 mm at the corners, far beyond the 1 µm kept.
    let apex = w.bodies.len() - 1;
    let turn = nalgebra::UnitQuaternion::from_euler_angles(0.0, 0.0, 0.01).into_inner();
    let q = turn * w.bodies.q(apex);
    w.bodies.orientation[apex] = [q.i, q.j, q.k, q.w];
    w.step(1).unwrap();
    let s = solver(&w);
    let on_apex = |ci: &usize| {
        let c = &s.constraints[*ci];
        c.b1 as usize == apex || c.b2 as usize == apex
    };
    let touching: Vec<usize> = (0..s.constraints.len()).filter(on_apex).collect();
    assert!(!touching.is_empty());
    let kept = kept(s);
    assert!(touching.iter().all(|ci| !kept.contains(ci)), "the turned box's contacts were kept");
    assert!(kept.len() + touching.len() == s.constraints.len(), "the others were not");
}

#[test]
fn a_kept_support_plan_is_the_plan_made_afresh() {
    let mut w = pyramid();
    w.step(120).unwrap();
    w.step(1).unwrap();
    let bodies = &w.bodies;
    let s = &mut w.collision.as_mut().unwrap().solver;
    assert!(s.plan_unchanged(), "a pyramid at rest keeps its plan");
    // Every face kept as still: the blocks kept their bounds too.
    assert!(s.constraints.iter().all(|c| c.still));
    let (blocks, faces, rows) = (s.support.blocks.clone(), s.support.faces.clone(), s.support.rows.clone());
    let sides: Vec<(u8, u32)> = s.constraints.iter().map(|c| (c.lower, c.group)).collect();
    let ordinary = s.ordinary.clone();
    // Planned again with nothing to take from the step before.
    s.previous.kept.clear();
    s.plan_support(&crate::math::Vec3::new(0.0, 0.0, 1.0), 9.81, bodies);
    assert_eq!(s.constraints.iter().map(|c| (c.lower, c.group)).collect::<Vec<_>>(), sides);
    assert_eq!((&s.support.faces, &s.ordinary), (&faces, &ordinary));
    assert_eq!(s.support.blocks.len(), blocks.len());
    for (a, b) in s.support.blocks.iter().zip(&blocks) {
        assert_eq!((a.body, a.level, a.faces, a.rows, a.island, a.q), (b.body, b.level, b.faces, b.rows, b.island, b.q));
        assert_eq!([a.low, a.high, a.arm].map(f64::to_bits), [b.low, b.high, b.arm].map(f64::to_bits));
    }
    assert_eq!(s.support.rows.len(), rows.len());
    for (a, b) in s.support.rows.iter().zip(&rows) {
        assert_eq!((a.ju, a.jl, a.wu, a.lower, a.face, a.kind), (b.ju, b.jl, b.wu, b.lower, b.face, b.kind));
    }
}

/// The largest distance of a kept anchor of world `w`'s constraints from the
/// anchor laid out afresh from the narrow phase's points at the bodies'
/// current poses (m), and how many constraints were kept as still.
fn anchors_off(w: &World) -> (f64, usize) {
    let c = w.collision.as_ref().unwrap();
    let (s, b) = (&c.solver, &w.bodies);
    let mut worst = 0.0f64;
    for k in s.constraints.iter().filter(|k| k.as_built) {
        let state = &c.narrow.pairs[k.slot as usize];
        let (pose1, pose2) = (c.colliders[k.pair.0 as usize].pose(b), c.colliders[k.pair.1 as usize].pose(b));
        for p in &s.points[k.start as usize..(k.start + k.len) as usize] {
            let tp = state.manifold(p.manifold).unwrap().points[p.manifold_point as usize];
            let mid = ((pose1 * tp.local_p1).coords + (pose2 * tp.local_p2).coords) * 0.5;
            let (x1, x2) = (Vec3::from(b.position[k.b1 as usize]), Vec3::from(b.position[k.b2 as usize]));
            worst = worst.max((mid - x1 - p.anchor1).norm()).max((mid - x2 - p.anchor2).norm());
        }
    }
    (worst, s.constraints.iter().filter(|k| k.still).count())
}

/// A resting pyramid turned by 2e-8 rad about the vertical each step, ground
/// and all: every pair stays still (no relative motion), so its constraint is
/// kept without its points being laid out, until the turn added up could take
/// the anchors a check would find beyond the tolerance, when they are checked
/// (and found again). At every step the kept anchors are within the tolerance
/// of the anchors laid out afresh: 4e-6 rad in all moves a corner 3.5 µm, and
/// without the slack's bound they would be that far off.
#[test]
fn a_still_pair_turning_keeps_its_anchors_within_the_tolerance() {
    let mut w = pyramid();
    w.step(120).unwrap();
    let turn = nalgebra::UnitQuaternion::from_euler_angles(0.0, 0.0, 2e-8);
    let (mut still, mut all, mut worst) = (0, 0, 0.0f64);
    for _ in 0..200 {
        for i in 0..w.bodies.len() {
            let x = turn * nalgebra::Point3::from(Vec3::from(w.bodies.position[i]));
            w.bodies.position[i] = x.coords.into();
            let q = turn.into_inner() * w.bodies.q(i);
            w.bodies.orientation[i] = [q.i, q.j, q.k, q.w];
        }
        w.step(1).unwrap();
        let (off, kept) = anchors_off(&w);
        worst = worst.max(off);
        still += kept;
        all += solver(&w).constraints.len();
    }
    assert!(worst <= KEEP_EPS, "a kept anchor {worst:.3e} m from its place");
    // Checked again about every 1e-6 / (2 · 2e-8 · 1 m) = 25 steps.
    assert!(still >= all * 9 / 10 && still < all, "{still} of {all} kept as still");
}

/// Kept as still or checked, a resting pyramid's constraints are the same
/// bits: every step of one whose still constraints are all checked (their
/// slack taken away before each step) gives the same state.
#[test]
fn still_constraints_are_what_the_check_keeps() {
    let (mut a, mut b) = (pyramid(), pyramid());
    for step in 0..240 {
        let s = &mut b.collision.as_mut().unwrap().solver;
        s.constraints.iter_mut().for_each(|c| c.slack = f64::NEG_INFINITY);
        a.step(1).unwrap();
        b.step(1).unwrap();
        let (sa, sb) = (solver(&a), solver(&b));
        assert!(sb.constraints.iter().all(|c| !c.still));
        if step > 60 {
            assert!(sa.constraints.iter().all(|c| c.still), "step {step}");
        }
        for (p, q) in sa.points.iter().zip(&sb.points) {
            let bits = |p: &crate::solve::contact::Point| [p.anchor1, p.anchor2, p.r1, p.r2, p.rn1, p.irn1, p.rn2, p.irn2].map(|v| v.map(f64::to_bits));
            assert_eq!(bits(p), bits(q));
            assert_eq!((p.normal_mass.to_bits(), p.base_separation.to_bits(), p.normal_impulse.to_bits()), (q.normal_mass.to_bits(), q.base_separation.to_bits(), q.normal_impulse.to_bits()));
        }
        assert_eq!(a.bodies.position, b.bodies.position);
        assert_eq!(a.bodies.angular_velocity, b.bodies.angular_velocity);
    }
}
