use rigidrs::body::Shape;
use rigidrs::integrate::Integrator;
use rigidrs::world::{BodySpec, Scene, Settings};
use rigidrs::math::{quat, Vec3};

fn main() {
    for integ in Integrator::ALL {
        for dt in [1.0 / 60.0, 1.0 / 240.0] {
            let mut scene = Scene::new([0.0; 3]).unwrap();
            scene.add_body(BodySpec {
                shape: Some(Shape::cuboid([0.05, 0.2, 0.45]).unwrap()),
                mass: Some(10.0),
                angular_velocity: [0.1, 5.0, 0.1],
                ..Default::default()
            }).unwrap();
            let mut s = Settings::new(dt);
            s.integrator = integ;
            let mut w = scene.build(&s).unwrap();
            let e0 = w.kinetic_energy();
            let l0 = w.angular_momentum().norm();
            let mut prev = 5.0;
            let mut flips = vec![];
            let n = (12.0 / dt) as u64;
            for k in 0..n {
                w.step(1).unwrap();
                let q = quat::from_xyzw(w.bodies.orientation[0]);
                let wb = quat::rotate_inv(&q, &Vec3::from(w.bodies.angular_velocity[0]));
                if wb.y.signum() != f64::signum(prev) {
                    let t1 = (k + 1) as f64 * dt;
                    let t = t1 - dt * wb.y / (wb.y - prev);
                    flips.push(t);
                }
                prev = wb.y;
            }
            println!("{:18} dt={:.5} dE={:+.3e} dL={:+.3e} flips={:?} stages={:?}", integ.name(), dt,
                w.kinetic_energy() / e0 - 1.0, w.angular_momentum().norm() / l0 - 1.0,
                flips.iter().map(|t| format!("{t:.5}")).collect::<Vec<_>>(), w.stage_names());
        }
    }
}
