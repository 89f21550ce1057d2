//! Tests of the narrow phase's pair states.

use super::*;
use nalgebra::Point3;
use parry3d_f64::shape::PackedFeatureId;

/// A point stored while it touched, then beyond the prediction, carries
/// nothing into the next step's warm start (its stale friction share
/// pushed a cube wedged in a V down the groove).
#[test]
fn a_point_beyond_the_prediction_forgets_its_share_of_the_patch() {
    let point = |dist| {
        let (o, id) = (Point3::origin(), PackedFeatureId::UNKNOWN);
        let mut tp = Tracked::new(o, o, id, id, dist);
        tp.data = ContactData { normal_impulse: 1.0, friction_impulse: [0.5, 0.0, 0.0], twist_impulse: 0.1, sliding: true };
        tp
    };
    let mut m = Manifold::new();
    m.points = vec![point(-1e-5), point(2e-3)];
    let mut state = PairState { key: (0, 1), manifolds: vec![m], prediction: 1e-3, ..Default::default() };
    state.forget_beyond_reach();
    assert_eq!(state.manifolds[0].points[0].data.friction_impulse, [0.5, 0.0, 0.0]);
    assert_eq!(state.manifolds[0].points[1].data, ContactData::default());
}

/// Two unit cubes, the second resting on the first turned by `turn` (rad)
/// about the vertical and `lift` (m) above touching: their colliders and
/// bodies.
fn cube_on_cube(turn: f64, lift: f64) -> ([Collider; 2], crate::body::Bodies) {
    use crate::body::storage::BodyInit;
    use crate::body::{BodyKind, Bodies};
    use parry3d_f64::shape::{Cuboid, SharedShape};
    let cube = |body: u32| Collider {
        body,
        shape: SharedShape::new(Cuboid::new(Vector3::new(0.5, 0.5, 0.5))),
        local: Isometry3::identity(),
        material: Default::default(),
        filter: Default::default(),
        infinite: false,
        reach: 0.87,
        ccd: false,
        ball: None,
        many_cornered: false,
        corners: crate::collide::corners::Corners::of(&Cuboid::new(Vector3::new(0.5, 0.5, 0.5))),
    };
    let mut b = Bodies::with_capacity(2);
    for (z, q) in [(0.0, crate::math::Quat::identity()), (1.0 + lift, crate::math::quat::exp(&Vec3::new(0.0, 0.0, turn)))] {
        b.push(&BodyInit {
            kind: BodyKind::Dynamic,
            position: Vec3::new(0.0, 0.0, z),
            orientation: q,
            linear_velocity: Vec3::zeros(),
            angular_velocity: Vec3::zeros(),
            mass: 1.0,
            inertia: [1.0 / 6.0; 3],
        });
    }
    ([cube(0), cube(1)], b)
}

/// A pair that has moved less than `STILL` keeps its manifolds, and they are
/// what a computation afresh gives there: the same points (features and
/// local positions within `STILL`), distances within `STILL` times the size.
/// Moved more, they are computed again.
#[test]
fn a_still_pair_keeps_the_manifolds_a_computation_would_give() {
    let pair = |turn: f64, lift: f64, state: &mut PairState| {
        let (c, b) = cube_on_cube(turn, lift);
        state.prediction = 0.01;
        update_pair(state, &c[0], &c[1], (&b, &c[0].pose(&b).inv_mul(&c[1].pose(&b))))
    };
    let mut kept = PairState { key: (0, 1), ..Default::default() };
    assert!(pair(0.3, -1e-6, &mut kept));
    let first = kept.manifolds.clone();
    assert!(kept.computed_at.is_some());
    let (d, a) = (0.4 * STILL, 0.3 + 0.4 * STILL);
    assert!(pair(a, -1e-6 + d, &mut kept));
    let mut fresh = PairState { key: (0, 1), ..Default::default() };
    assert!(pair(a, -1e-6 + d, &mut fresh));
    let points = |ms: &[Manifold]| ms.iter().flat_map(|m| m.points.clone()).collect::<Vec<_>>();
    let (k, f) = (points(&kept.manifolds), points(&fresh.manifolds));
    assert_eq!(points(&first).len(), k.len());
    assert_eq!(k.len(), f.len());
    assert!(k.len() >= 4, "a face on a face: {} points", k.len());
    for (p, q) in k.iter().zip(&f) {
        assert_eq!((p.fid1, p.fid2), (q.fid1, q.fid2));
        assert!((p.local_p1 - q.local_p1).norm() <= 2.0 * STILL, "{:?} {:?}", p.local_p1, q.local_p1);
        assert!((p.local_p2 - q.local_p2).norm() <= 2.0 * STILL);
        assert!((p.dist - q.dist).abs() <= 2.0 * STILL, "{} {}", p.dist, q.dist);
    }
    // Kept as they were: not recomputed.
    assert_eq!(points(&first).iter().map(|p| p.dist).collect::<Vec<_>>(), k.iter().map(|p| p.dist).collect::<Vec<_>>());
    // Lifted by a micrometre more: computed again, the distances follow.
    assert!(pair(a, 0.0, &mut kept));
    let moved = points(&kept.manifolds);
    assert!(moved.iter().all(|p| (p.dist - 0.0).abs() <= 1e-9), "{:?}", moved.iter().map(|p| p.dist).collect::<Vec<_>>());
}
