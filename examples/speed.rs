use rigidrs::body::Shape;
use rigidrs::integrate::Integrator;
use rigidrs::world::{BodySpec, Scene, Settings};
use std::time::Instant;

fn main() {
    let n = 10_000;
    for integ in Integrator::ALL {
        let mut scene = Scene::new([0.0; 3]).unwrap();
        let shape = Shape::cuboid([0.05, 0.1, 0.2]).unwrap();
        for k in 0..n {
            let a = k as f64 * 0.37;
            scene.add_body(BodySpec { shape: Some(shape.clone()), density: Some(1000.0), position: [k as f64, 0.0, 0.0],
                orientation: [a.sin() * 0.5, a.cos() * 0.5, 0.5, 0.5], angular_velocity: [5.0 * a.cos(), 5.0 * a.sin(), 1.0], ..Default::default() }).unwrap();
        }
        let mut s = Settings::new(1.0 / 240.0);
        s.integrator = integ;
        let mut w = scene.build(&s).unwrap();
        w.step(10).unwrap();
        let mut best = f64::MAX;
        for _ in 0..5 {
            let t = Instant::now();
            w.step(100).unwrap();
            best = best.min(t.elapsed().as_secs_f64());
        }
        println!("{:18} {:.1} ns/body-step  {:.2} M body-steps/s", integ.name(), best / (100.0 * n as f64) * 1e9, 100.0 * n as f64 / best / 1e6);
    }
}
