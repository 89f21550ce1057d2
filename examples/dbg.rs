use rigidrs::body::Shape;
use rigidrs::world::{BodySpec, Scene, Settings};
fn main() {
    let mut sc = Scene::new([0.0; 3]).unwrap();
    sc.add_body(BodySpec { shape: Some(Shape::cuboid([0.005, 2.0, 2.0]).unwrap()), fixed: true, ..Default::default() }).unwrap();
    let a = 60f64.to_radians();
    let u = [a.cos(), a.sin(), 0.0];
    sc.add_body(BodySpec { shape: Some(Shape::sphere(0.05).unwrap()), density: Some(7800.0), position: [-u[0], -u[1], 0.0], linear_velocity: [100.0 * u[0], 100.0 * u[1], 0.0], ccd: true, ..Default::default() }).unwrap();
    let s = Settings::new(1.0 / 240.0);
    let mut w = sc.build(&s).unwrap();
    for k in 0..5 {
        w.step(1).unwrap();
        println!("step {k}: x={:?} v={:?}", w.bodies.position[1], w.bodies.linear_velocity[1]);
        let c = w.collision.as_ref().unwrap();
        for (ci, con) in c.solver.constraints.iter().enumerate() {
            let p = &c.solver.points[con.start as usize];
            println!("   n={:?} sep0={:.4} jn={:.4} patch={:?} sliding={}", con.normal.as_slice(), p.separation, p.total_normal, c.solver.patches[ci].total, c.solver.patches[ci].sliding);
        }
    }
}
