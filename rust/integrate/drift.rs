//! The translation part of a drift: `p += h v`.

use crate::body::Bodies;

pub fn translate(b: &mut Bodies, list: &[u32], h: f64) {
    for &i in list {
        let i = i as usize;
        let (p, v) = (&mut b.position[i], b.linear_velocity[i]);
        p[0] += h * v[0];
        p[1] += h * v[1];
        p[2] += h * v[2];
    }
}
