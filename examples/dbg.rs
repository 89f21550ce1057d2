use rigidrs::body::Shape;
use rigidrs::collide::Material;
use rigidrs::world::{BodySpec, Scene, Settings};
fn main() {
    let mut sc = Scene::default();
    let m = Material::new(0.0, None, 1.0).unwrap();
    sc.add_body(BodySpec { shape: Some(Shape::plane([0.0, 0.0, 1.0], 0.0).unwrap()), fixed: true, material: m, ..Default::default() }).unwrap();
    sc.add_body(BodySpec { shape: Some(Shape::sphere(0.1).unwrap()), density: Some(1000.0), position: [0.0, 0.0, 0.13], linear_velocity: [0.0, 0.0, -4.4], material: m, ..Default::default() }).unwrap();
    let mut s = Settings::new(1.0 / 240.0);
    s.substeps = Some(1);
    s.solver.restitution_threshold = 0.1;
    s.sleep.enabled = false;
    let mut w = sc.build(&s).unwrap();
    for _ in 0..3 {
        w.step(1).unwrap();
        let c = w.collision.as_ref().unwrap();
        for con in &c.solver.constraints { println!("n={:?} b1={} b2={}", con.normal, con.b1, con.b2); }
        for p in &c.solver.points { println!("  r1={:?} r2={:?} base={} sep={} nm={} imp={}", p.r1, p.r2, p.base_separation, p.separation, p.normal_mass, p.total_normal); }
        println!("z={:?} v={:?}", w.bodies.position[1], w.bodies.linear_velocity[1]);
    }
}
