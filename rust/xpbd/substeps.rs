//! The substeps a world with particle links takes when the user does not say.
//!
//! XPBD resolves stiff links only as far as one Gauss–Seidel pass per substep
//! gets: what a pass leaves over shows as stretch, and it grows with how far the
//! particles move in a substep compared with their links. Measured on the README's
//! cloth (30 × 30, 1 m, links of 3.45 cm) dropped 0.4 m onto a sphere, the largest
//! strain is about 1.1 × (impact speed × h / link length): 15 % at 8 substeps of a
//! 60 Hz step, 8.3 % at 16, 4.6 % at 32; finer cloths stretch in proportion to
//! their resolution at the same h, larger ones of the same resolution do not.
//!
//! So the default is a Courant-like bound: in each connected structure of
//! distance links, a particle moving at the structure's reference speed travels at
//! most [`COURANT`] of the structure's shortest link per substep:
//!
//! ```text
//! h ≤ COURANT · L_min / v_ref,   v_ref = max(√(2 |g| ℓ), fastest initial speed)
//! ```
//!
//! with `ℓ` the diagonal of the structure's bounding box (the speed of a fall over
//! its own size) — the README cloth gets 26 substeps at 60 Hz, 7 at 240 Hz, and
//! stretches at most 5.6 % over the sphere (REFERENCES.md allows 10 %); 0.6 m and
//! 2 m cloths at 120 and 30 Hz stay within 6.1 %. A structure hit much faster than
//! its reference speed (a drop from far higher, a thrown body) needs the substeps
//! given by hand.

use super::model::XpbdModel;
use crate::math::Vec3;

/// Largest travel per substep, as a fraction of the shortest link (–).
pub const COURANT: f64 = 0.1;

/// The most substeps the rule asks for: links far shorter than the motion they
/// carry (sub-millimetre links in a metre-sized scene) need substeps given by hand.
pub const MAX_SUBSTEPS: u32 = 1024;

/// Substeps per step of `dt` seconds that the particle links of `m` ask for under
/// `gravity` (m/s²): at least 1, at most [`MAX_SUBSTEPS`]; 1 without links.
pub fn for_links(m: &XpbdModel, gravity: Vec3, dt: f64) -> u32 {
    let p = &m.particles;
    let mut root: Vec<u32> = (0..p.len() as u32).collect();
    for c in &m.distance {
        let (a, b) = (find(&mut root, c.i), find(&mut root, c.j));
        root[a.max(b) as usize] = a.min(b);
    }
    // Per structure (root): bounding box, shortest link, fastest initial speed.
    let mut lo = vec![Vec3::repeat(f64::INFINITY); p.len()];
    let mut hi = vec![Vec3::repeat(f64::NEG_INFINITY); p.len()];
    let mut speed = vec![0.0f64; p.len()];
    for i in 0..p.len() {
        let r = find(&mut root, i as u32) as usize;
        let x = Vec3::from(p.position[i]);
        lo[r] = lo[r].inf(&x);
        hi[r] = hi[r].sup(&x);
        if p.inv_mass[i] > 0.0 {
            speed[r] = speed[r].max(Vec3::from(p.velocity[i]).norm());
        }
    }
    let mut shortest = vec![f64::INFINITY; p.len()];
    for c in &m.distance {
        let movable = p.inv_mass[c.i as usize] + p.inv_mass[c.j as usize] > 0.0;
        if movable && c.rest > 0.0 {
            let r = find(&mut root, c.i) as usize;
            shortest[r] = shortest[r].min(c.rest);
        }
    }
    let mut n = 1.0f64;
    for r in 0..p.len() {
        if !shortest[r].is_finite() {
            continue;
        }
        let extent = (hi[r] - lo[r]).norm();
        let v_ref = (2.0 * gravity.norm() * extent).sqrt().max(speed[r]);
        n = n.max((dt * v_ref / (COURANT * shortest[r])).ceil());
    }
    // NaN cannot reach here (validated inputs); the cast saturates.
    n.min(MAX_SUBSTEPS as f64) as u32
}

/// Root of `i` in the union-find forest, halving the path on the way.
fn find(root: &mut [u32], mut i: u32) -> u32 {
    while root[i as usize] != i {
        let up = root[root[i as usize] as usize];
        root[i as usize] = up;
        i = up;
    }
    i
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::xpbd::builders::{cloth, rope, Material};
    use crate::xpbd::Compliance;

    fn material() -> Material {
        Material { mass: 0.3, radius: 0.0, friction: 0.5, filter: Default::default() }
    }

    #[test]
    fn the_readme_cloth_gets_the_courant_bound() {
        let mut m = XpbdModel::default();
        cloth(&mut m, [0.0, 0.0, 1.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0], 30, 30, &material(), Compliance::default(), None, &[])
            .unwrap();
        let g = Vec3::new(0.0, 0.0, -9.81);
        let v_ref = (2.0 * 9.81 * 2f64.sqrt()).sqrt();
        for dt in [1.0 / 60.0, 1.0 / 240.0] {
            let expect = (dt * v_ref / (COURANT / 29.0)).ceil() as u32;
            assert_eq!(for_links(&m, g, dt), expect);
        }
        assert_eq!(for_links(&m, g, 1.0 / 60.0), 26);
        // No gravity and nothing moving: no load to carry, one substep.
        assert_eq!(for_links(&m, Vec3::zeros(), 1.0 / 60.0), 1);
    }

    #[test]
    fn each_structure_is_bounded_by_its_own_links() {
        // A coarse rope far from a fine one: the fine one decides, and the
        // distance between them does not count as an extent.
        let mut m = XpbdModel::default();
        let k = Compliance::default();
        rope(&mut m, [0.0, 0.0, 0.0], [1.0, 0.0, 0.0], 2, &material(), k, &[]).unwrap();
        rope(&mut m, [100.0, 0.0, 0.0], [101.0, 0.0, 0.0], 100, &material(), k, &[]).unwrap();
        let g = Vec3::new(0.0, 0.0, -9.81);
        let expect = (0.1 * (2.0 * 9.81f64).sqrt() / (COURANT * 0.01)).ceil() as u32;
        assert_eq!(for_links(&m, g, 0.1), expect);
    }
}
