//! Tests of `reuse`: kept geometry is what computing it afresh at the kept
//! anchors gives, bit for bit, and it is dropped once a body turns.

use super::NONE;
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
            normal_mass(&mut fresh, &s.bodies[c.s1 as usize], &s.bodies[c.s2 as usize], &c.normal);
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
    }
    assert_eq!(s.support.rows.len(), rows.len());
    for (a, b) in s.support.rows.iter().zip(&rows) {
        assert_eq!((a.ju, a.jl, a.wu, a.lower, a.face, a.kind), (b.ju, b.jl, b.wu, b.lower, b.face, b.kind));
    }
}
