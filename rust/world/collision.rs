//! The collision side of a world: colliders built from the scene, the decision
//! whether any two of them can ever touch (if not, the world has no collision
//! stage at all), and the per-step broad phase, narrow phase and CCD.

use std::collections::HashMap;

use super::scene::BodyDesc;
use super::Settings;
use crate::body::{BodyKind, Bodies};
use crate::collide::broad_phase::{Aabb, HalfSpace, SweepAndPrune};
use crate::collide::ccd::{self, Start};
use crate::collide::fat_pairs::{self, Changes};
use crate::collide::narrow_phase::{supported, ContactReport, NarrowPhase, Prediction};
use crate::collide::{Collider, Filter};
use crate::error::{Error, Result};
use crate::math::Vec3;
use crate::solve::islands::Islands;
use crate::solve::prepare::Preparation;
use crate::solve::ContactSolver;

#[derive(serde::Serialize, serde::Deserialize)]
pub struct Collision {
    pub colliders: Vec<Collider>,
    finite: Vec<u32>,
    infinite: Vec<u32>,
    boxes: Vec<Aabb>,
    /// Boxes grown beyond `boxes`, kept until a body leaves its own, and the pairs
    /// of them that overlap.
    fat: Vec<Aabb>,
    /// Pose (position, quaternion) each box of a body at rest was computed at: a
    /// sleeping or fixed body keeps its box until something moves it.
    boxed_at: Vec<[f64; 7]>,
    /// The pairs of fat boxes, sorted.
    sap_pairs: Vec<(u32, u32)>,
    sap: SweepAndPrune,
    candidates: Vec<(u32, u32)>,
    /// Scratch for merging the half-space pairs into the candidates.
    #[serde(skip)]
    merged: Vec<(u32, u32)>,
    /// Scratch for the counting sort of the pairs of fat boxes.
    #[serde(skip)]
    runs: Vec<u32>,
    /// The fat boxes changed in a call, and scratch for the update of their pairs.
    #[serde(skip)]
    changes: Changes,
    pub narrow: NarrowPhase,
    pub solver: ContactSolver,
    pub islands: Islands,
    /// Colliders of bodies that asked for continuous collision detection, and
    /// their bodies' poses before the drift.
    pub ccd: Vec<u32>,
    ccd_start: Vec<Start>,
    /// Some pair that can touch may bounce (restitution > 0) / has friction.
    pub bouncy: bool,
    pub frictional: bool,
    margin: f64,
    /// Body pairs tied by a joint, sorted: they never collide.
    jointed: Vec<(u32, u32)>,
    /// No collider's body can move this step (all asleep or fixed): there is no
    /// pair to look at, and the pairs kept for waking bodies stay as they are.
    idle: bool,
}

clone_in_place!(Collision {
    colliders,
    finite,
    infinite,
    boxes,
    fat,
    boxed_at,
    sap_pairs,
    sap,
    candidates,
    merged,
    runs,
    changes,
    narrow,
    solver,
    islands,
    ccd,
    ccd_start,
    bouncy,
    frictional,
    margin,
    jointed,
    idle,
});

pub(crate) fn collider_of(i: usize, d: &BodyDesc) -> Option<Collider> {
    let (shape, pose) = (d.shape.as_ref()?, d.shape_pose);
    let local = pose * shape.parry_pose;
    let infinite = matches!(shape.kind, crate::body::shape::ShapeKind::Plane { .. });
    let reach = if infinite {
        f64::INFINITY
    } else {
        // The farther corner of the box or of the bounding sphere, whichever is
        // nearer: r for a ball, not the √3 r of its box's corner.
        let a = shape.parry.compute_aabb(&local);
        let corner = |k: usize| if a.mins[k].abs() > a.maxs[k].abs() { a.mins[k] } else { a.maxs[k] };
        let s = shape.parry.compute_bounding_sphere(&local);
        Vec3::new(corner(0), corner(1), corner(2)).norm().min(s.center.coords.norm() + s.radius)
    };
    Some(Collider {
        body: i as u32,
        shape: shape.parry.clone(),
        local,
        material: d.material,
        filter: d.filter,
        infinite,
        reach,
        ccd: d.ccd,
        ball: shape.parry.as_ball().map(|b| b.radius),
        many_cornered: crate::collide::face_points::many_cornered(shape.parry.as_ref()),
        corners: crate::collide::corners::Corners::of(shape.parry.as_ref()),
    })
}

/// Whether some pair of colliders can ever touch: different bodies, filters that
/// allow it, at least one of the two able to move. Checked over the distinct
/// filters, not over all pairs.
fn can_touch(colliders: &[Collider], kinds: &[BodyKind]) -> bool {
    let mut by_filter: HashMap<(u32, u32), (usize, usize)> = HashMap::new();
    for c in colliders {
        let e = by_filter.entry((c.filter.group, c.filter.mask)).or_default();
        e.1 += 1;
        if kinds[c.body as usize] != BodyKind::Fixed {
            e.0 += 1;
        }
    }
    let f = |k: &(u32, u32)| Filter { group: k.0, mask: k.1 };
    by_filter.iter().any(|(ka, &(movable_a, total_a))| {
        movable_a > 0
            && by_filter.iter().any(|(kb, &(_, total_b))| {
                f(ka).allows(&f(kb)) && (ka != kb || total_a >= 2) && total_b > 0
            })
    })
}

impl Collision {
    /// `jointed`: sorted body pairs (smaller index first) tied by a joint.
    pub fn new(descs: &[BodyDesc], bodies: &Bodies, settings: &Settings, jointed: &[(u32, u32)]) -> Result<Option<Self>> {
        let colliders: Vec<Collider> = descs.iter().enumerate().filter_map(|(i, d)| collider_of(i, d)).collect();
        if !can_touch(&colliders, &bodies.kind) || !super::joints::some_pair_unjointed(&colliders, &bodies.kind, jointed) {
            return Ok(None);
        }
        check_supported(&colliders, &bodies.kind)?;
        let (infinite, finite): (Vec<u32>, Vec<u32>) = (0..colliders.len() as u32).partition(|&k| colliders[k as usize].infinite);
        let ccd: Vec<u32> = (0..colliders.len() as u32).filter(|&k| colliders[k as usize].ccd).collect();
        let frictional = colliders.iter().filter(|c| c.material.static_friction > 0.0).count() >= 2;
        let bouncy = colliders.iter().any(|c| c.material.restitution > 0.0);
        let n = bodies.len();
        Ok(Some(Self {
            boxes: vec![Aabb::default(); colliders.len()],
            fat: vec![Aabb::default(); colliders.len()],
            boxed_at: vec![[f64::NAN; 7]; colliders.len()],
            sap_pairs: Vec::new(),
            ccd_start: Vec::with_capacity(ccd.len()),
            colliders,
            finite,
            infinite,
            sap: SweepAndPrune::default(),
            candidates: Vec::new(),
            merged: Vec::new(),
            runs: Vec::new(),
            changes: Changes::default(),
            narrow: NarrowPhase::default(),
            solver: ContactSolver::new(n, settings.solver),
            islands: Islands::new(n),
            ccd,
            bouncy,
            frictional,
            margin: settings.solver.slop,
            jointed: jointed.to_vec(),
            idle: false,
        }))
    }

    /// Boxes of every finite collider (swept over the step for moving bodies) and
    /// the candidate pairs.
    pub fn broad_phase(&mut self, b: &Bodies, dt: f64) {
        self.idle = !self.colliders.iter().any(|c| b.moving(c.body as usize));
        if self.idle {
            self.candidates.clear();
            self.record_ccd_start(b);
            return;
        }
        let sweep = self.sap_pairs.is_empty() && self.fat.iter().all(|f| *f == Aabb::default());
        self.changes.boxes.clear();
        for &k in &self.finite {
            let c = &self.colliders[k as usize];
            let i = c.body as usize;
            let moving = b.moving(i);
            if !moving {
                let (x, q) = (b.position[i], b.orientation[i]);
                let pose = [x[0], x[1], x[2], q[0], q[1], q[2], q[3]];
                if self.boxed_at[k as usize] == pose {
                    continue;
                }
                self.boxed_at[k as usize] = pose;
            } else {
                self.boxed_at[k as usize][0] = f64::NAN;
            }
            let w = Vec3::from(b.angular_velocity[i]).norm() * dt;
            let d: [f64; 3] = (Vec3::from(b.linear_velocity[i]) * dt).into();
            // A body turning by more than a milliradian a step gets the box of the
            // ball of its reach: six additions, and it only changes as the body moves.
            let turning = w > TURNING;
            let mut a = if turning {
                ball_box(b, c, self.margin)
            } else {
                Aabb::from_parry(&c.shape.compute_aabb(&c.pose(b))).loosened(self.margin)
            };
            if moving {
                a = a.swept(d).loosened(if turning { 0.0 } else { w * c.reach });
            }
            self.boxes[k as usize] = a;
            let grow = self.margin.max(0.02 * c.reach);
            let fat = &mut self.fat[k as usize];
            if !a.inside(fat) || fat.slack(&a) > 4.0 * grow {
                *fat = a.loosened(grow);
                self.changes.boxes.push(k);
            }
        }
        // The pairs of fat boxes change only when a body leaves its fat box: a scene
        // that moves in place (bodies spinning, settling, at rest) sorts nothing.
        let (cols, jointed) = (&self.colliders, &self.jointed);
        let keep = |i: u32, j: u32| may_touch(cols, i, j, jointed);
        if sweep || !self.changes.few(self.finite.len(), &self.sap) {
            self.sap_pairs.clear();
            self.sap.pairs(&self.fat, &self.finite, keep, &mut self.sap_pairs);
            self.changes.swept();
            // Sorted once per rebuild, not once per step (the candidates'
            // sort was 3 % of a settled ball pit's step): the candidates
            // below are filtered from them in order.
            fat_pairs::sort_pairs(&mut self.sap_pairs, self.colliders.len(), (&mut self.runs, &mut self.merged));
        } else if !self.changes.boxes.is_empty() {
            self.changes.update(&mut self.sap_pairs, (&self.fat, &self.finite, &self.sap), keep);
        }
        self.candidates.clear();
        let (cols, boxes) = (&self.colliders, &self.boxes);
        let jointed = &self.jointed;
        for &(i, j) in &self.sap_pairs {
            if boxes[i as usize].overlaps(&boxes[j as usize]) && pair_allowed(cols, b, i, j, jointed) {
                self.candidates.push((i, j));
            }
        }
        let finite = self.candidates.len();
        for &h in &self.infinite {
            let c = &cols[h as usize];
            let pose = c.pose(b);
            let Some(hs) = c.shape.as_halfspace() else { continue };
            let n = pose.rotation * hs.normal.into_inner();
            let half = HalfSpace { normal: n.into(), offset: n.dot(&pose.translation.vector) };
            for &f in &self.finite {
                if pair_allowed(cols, b, h, f, jointed) && half.touches(&boxes[f as usize], 0.0) {
                    self.candidates.push((h.min(f), h.max(f)));
                }
            }
        }
        if self.candidates.len() > finite {
            self.candidates[finite..].sort_unstable();
            fat_pairs::merge_sorted(&mut self.candidates, finite, &mut self.merged);
        }
        self.record_ccd_start(b);
    }

    /// The poses CCD bodies sweep from.
    fn record_ccd_start(&mut self, b: &Bodies) {
        self.ccd_start.clear();
        for &k in &self.ccd {
            let i = self.colliders[k as usize].body as usize;
            self.ccd_start.push(Start { position: Vec3::from(b.position[i]), orientation: b.q(i) });
        }
    }

    /// Manifolds of the candidates, bodies woken by touch, and the constraints of
    /// this step. Returns whether a body woke.
    pub fn narrow_phase(&mut self, b: &mut Bodies, step: &NarrowStep) -> bool {
        let parallel = step.threads > 1;
        let prep = Preparation { h: step.h, gravity: step.gravity, parallel };
        if self.idle {
            self.narrow.touching.clear();
            self.solver.prepare(&self.narrow, &self.colliders, b, &prep);
            return false;
        }
        let pred = Prediction { margin: self.margin, dt: step.dt, gravity: step.gravity };
        self.narrow.arrange(self.solver.constraints.iter().map(|c| c.slot));
        let cols = &self.colliders;
        self.narrow.update(cols, b, &self.candidates, &pred, parallel, |i, j| {
            !b.moving(cols[i as usize].body as usize) && !b.moving(cols[j as usize].body as usize)
        });
        let mut woke = false;
        // Only a sleeping body can be woken (a world without one skips the
        // pairs: 16 µs a step of the 1000-ball pit).
        let touching = if b.sleeping.contains(&true) { &self.narrow.touching[..] } else { &[] };
        for &k in touching {
            let (i, j) = self.narrow.pairs[k as usize].key;
            let (bi, bj) = (cols[i as usize].body as usize, cols[j as usize].body as usize);
            if b.moving(bi) {
                woke |= self.islands.wake(b, bj);
            }
            if b.moving(bj) {
                woke |= self.islands.wake(b, bi);
            }
        }
        self.solver.prepare(&self.narrow, cols, b, &prep);
        self.narrow.forget_poses();
        woke
    }

    /// Sweeps every CCD body over its last drift and records its pose for the next.
    pub fn ccd_stage(&mut self, b: &mut Bodies) {
        for (slot, &k) in self.ccd.iter().enumerate() {
            let i = self.colliders[k as usize].body as usize;
            if b.awake(i) {
                ccd::sweep(b, k as usize, &self.colliders, &self.boxes, &self.ccd_start[slot]);
            }
            self.ccd_start[slot] = Start { position: Vec3::from(b.position[i]), orientation: b.q(i) };
        }
    }

    pub fn reports(&self) -> Vec<ContactReport> {
        self.solver.reports()
    }
}

/// What the narrow phase of a step needs to know.
pub struct NarrowStep {
    /// The step (s), over which contacts are predicted.
    pub dt: f64,
    /// The contact substep (s) the solver is prepared for.
    pub h: f64,
    pub gravity: Vec3,
    /// Worker threads the pairs may be stepped on (same bits for every count);
    /// more than one only on the pool's threads (the caller installed it).
    pub threads: usize,
}

/// Rotation per step (rad) above which a body's box is that of its reach.
const TURNING: f64 = 1e-3;

/// The box of the ball around a body's centre that holds its collider, grown by
/// `margin`.
fn ball_box(b: &Bodies, c: &Collider, margin: f64) -> Aabb {
    let x = b.position[c.body as usize];
    let r = c.reach + margin;
    Aabb { min: [x[0] - r, x[1] - r, x[2] - r], max: [x[0] + r, x[1] + r, x[2] + r] }
}

/// Whatever the bodies do, colliders `i` and `j` may touch: different bodies,
/// filters agree, not jointed, not both infinite.
fn may_touch(cols: &[Collider], i: u32, j: u32, jointed: &[(u32, u32)]) -> bool {
    let (ci, cj) = (&cols[i as usize], &cols[j as usize]);
    ci.body != cj.body
        && ci.filter.allows(&cj.filter)
        && !(ci.infinite && cj.infinite)
        && !super::joints::jointed(jointed, ci.body, cj.body)
}

/// Colliders `i` and `j` may touch now: different bodies not tied by a joint,
/// filters agree, and one of the two bodies moves.
fn pair_allowed(cols: &[Collider], b: &Bodies, i: u32, j: u32, jointed: &[(u32, u32)]) -> bool {
    let (bi, bj) = (cols[i as usize].body as usize, cols[j as usize].body as usize);
    (b.moving(bi) || b.moving(bj)) && may_touch(cols, i, j, jointed)
}

/// Rejects at build time a pair of shapes that can touch but that parry cannot
/// generate contacts for, naming two such bodies.
fn check_supported(cols: &[Collider], kinds: &[BodyKind]) -> Result<()> {
    let mut reps: HashMap<String, &Collider> = HashMap::new();
    for c in cols {
        reps.entry(format!("{:?}", c.shape.shape_type())).or_insert(c);
    }
    let types: Vec<&&Collider> = reps.values().collect();
    for a in &types {
        for bb in &types {
            if supported(a, bb) {
                continue;
            }
            let (ta, tb) = (a.shape.shape_type(), bb.shape.shape_type());
            let clash = cols.iter().find_map(|x| {
                let movable = kinds[x.body as usize] != BodyKind::Fixed;
                (x.shape.shape_type() == ta && movable)
                    .then(|| cols.iter().find(|y| y.body != x.body && y.shape.shape_type() == tb && x.filter.allows(&y.filter)))
                    .flatten()
                    .map(|y| (x.body, y.body))
            });
            if let Some((x, y)) = clash {
                return Err(Error::shape(format!(
                    "bodies {x} ({ta:?}) and {y} ({tb:?}) can touch, but parry has no contacts for that pair of shapes; \
                     use convex hulls or compounds for moving meshes, or filter the pair out"
                )));
            }
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use crate::body::Shape;
    use crate::integrate::BodyLists;
    use crate::world::{BodySpec, Scene, Settings, World};

    fn balls(gravity: [f64; 3], specs: &[([f64; 3], [f64; 3], bool)]) -> World {
        let mut sc = Scene::new(gravity).unwrap();
        for &(position, linear_velocity, fixed) in specs {
            let shape = Some(Shape::sphere(0.1).unwrap());
            let density = (!fixed).then_some(1000.0);
            sc.add_body(BodySpec { shape, density, position, linear_velocity, fixed, ..Default::default() }).unwrap();
        }
        let mut s = Settings::new(1.0 / 60.0);
        s.sleep.enabled = false;
        sc.build(&s).unwrap()
    }

    /// The free/touching split is kept while the touching mask is unchanged
    /// (`World::split_mask`): it must still follow a ball that lands on a
    /// fixed one and one thrown off it, step by step, as a split made afresh.
    #[test]
    fn kept_split_follows_bodies_into_and_out_of_contact() {
        let (up, rest) = ([0.0, 0.0, 2.0], [0.0; 3]);
        let mut w = balls([0.0, 0.0, -9.81], &[([0.0; 3], rest, true), ([0.0, 0.0, 0.5], rest, false), ([1.0, 0.0, 0.2], rest, false)]);
        let mut seen = [false; 2];
        for k in 0..120 {
            if k == 60 {
                w.bodies.linear_velocity[1] = up;
            }
            w.step(1).unwrap();
            let touching = w.collision.as_ref().unwrap().solver.touching.clone();
            let (mut free, mut held) = (BodyLists::default(), BodyLists::default());
            w.lists.partition(&touching, &mut free, &mut held);
            assert_eq!(w.split[0].dynamic, free.dynamic, "step {k}");
            assert_eq!(w.split[1].dynamic, held.dynamic, "step {k}");
            seen[touching[1] as usize] = true;
        }
        assert_eq!(seen, [true, true], "ball 1 both free and touching");
    }

    /// The candidates must come sorted (the narrow phase matches them to its
    /// pairs by a merge): with a ground plane added between the balls, its
    /// pairs fall among theirs.
    #[test]
    fn candidates_stay_sorted_with_a_plane_among_the_bodies() {
        let mut sc = Scene::new([0.0, 0.0, -9.81]).unwrap();
        let ball = || Some(Shape::sphere(0.1).unwrap());
        for k in 0..6 {
            if k == 3 {
                sc.add_body(BodySpec { shape: Some(Shape::plane([0.0, 0.0, 1.0], 0.0).unwrap()), fixed: true, ..Default::default() }).unwrap();
            }
            let position = [0.19 * (k % 3) as f64, 0.0, 0.1 + 0.19 * (k / 3) as f64];
            sc.add_body(BodySpec { shape: ball(), density: Some(1000.0), position, ..Default::default() }).unwrap();
        }
        let mut w = sc.build(&Settings::new(1.0 / 60.0)).unwrap();
        w.step(2).unwrap();
        let c = w.collision.as_ref().unwrap();
        let plane_pairs = c.candidates.iter().filter(|&&(i, j)| i == 3 || j == 3).count();
        assert!(plane_pairs >= 3 && c.candidates.len() > plane_pairs, "{:?}", c.candidates);
        assert!(c.candidates.windows(2).all(|p| p[0] < p[1]), "{:?}", c.candidates);
    }

    #[test]
    fn a_ball_reaches_as_far_as_its_radius_not_its_box_corner() {
        let w = balls([0.0; 3], &[([0.0; 3], [0.0; 3], false), ([1.0, 0.0, 0.0], [0.0; 3], false)]);
        let reach = w.collision.as_ref().unwrap().colliders[0].reach;
        assert!((reach - 0.1).abs() <= 1e-15, "{reach}");
    }

    #[test]
    fn balls_falling_side_by_side_predict_no_contact() {
        // 5 cm apart at 10 m/s: the distance either could travel in a step (17 cm)
        // spans the gap, but they do not approach each other.
        let v = [0.0, 0.0, -10.0];
        let mut w = balls([0.0, 0.0, -9.81], &[([0.0; 3], v, false), ([0.25, 0.0, 0.0], v, false)]);
        w.step(1).unwrap();
        assert!(w.collision.as_ref().unwrap().narrow.touching.is_empty());
        assert!(w.collision.as_ref().unwrap().narrow.is_empty());
    }

    #[test]
    fn a_ball_falling_onto_a_fixed_one_predicts_the_contact() {
        // 5 cm above it at 10 m/s: it would pass 12 cm into it within the step.
        let mut w = balls([0.0, 0.0, -9.81], &[([0.0; 3], [0.0; 3], true), ([0.0, 0.0, 0.25], [0.0, 0.0, -10.0], false)]);
        let c = w.collision.as_mut().unwrap();
        c.broad_phase(&w.bodies, 1.0 / 60.0);
        let step = super::NarrowStep { dt: 1.0 / 60.0, h: 1.0 / 240.0, gravity: nalgebra::Vector3::new(0.0, 0.0, -9.81), threads: 1 };
        c.narrow_phase(&mut w.bodies, &step);
        assert_eq!(c.narrow.touching.len(), 1);
    }

    #[test]
    fn the_fat_box_of_a_body_that_slowed_down_shrinks_back() {
        let mut w = balls([0.0; 3], &[([0.0; 3], [60.0, 0.0, 0.0], false), ([10.0, 5.0, 0.0], [0.0; 3], false)]);
        w.step(1).unwrap();
        let c = w.collision.as_ref().unwrap();
        assert!(c.fat[0].max[0] - c.fat[0].min[0] > 1.2, "swept a metre: {:?}", c.fat[0]);
        w.bodies.linear_velocity[0] = [0.0; 3];
        w.step(1).unwrap();
        let c = w.collision.as_ref().unwrap();
        let grow = c.margin.max(0.02 * c.colliders[0].reach);
        assert!(c.fat[0].slack(&c.boxes[0]) <= grow + 1e-12, "{:?} around {:?}", c.fat[0], c.boxes[0]);
    }
}
