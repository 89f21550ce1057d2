//! Tests of the narrow phase's pair states.

use super::*;
use nalgebra::Point3;

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
    let mut state = PairState { key: (0, 1), manifolds: vec![m], prediction: 1e-3, workspace: None, ball: None };
    state.forget_beyond_reach();
    assert_eq!(state.manifolds[0].points[0].data.friction_impulse, [0.5, 0.0, 0.0]);
    assert_eq!(state.manifolds[0].points[1].data, ContactData::default());
}
