//! The translation part of a drift: `p += h v`.

use crate::body::Bodies;
use crate::integrate::kick::KickSources;
use crate::math::Vec3;

pub fn translate(b: &mut Bodies, list: &[u32], h: f64) {
    for &i in list {
        let i = i as usize;
        let (p, v) = (&mut b.position[i], b.linear_velocity[i]);
        p[0] += h * v[0];
        p[1] += h * v[1];
        p[2] += h * v[2];
    }
}

/// The drift (fraction `hf` of a contact substep of `h`) of bodies in contact
/// after a full kick at the substep's start: `p += hf v`, but a body whose
/// velocity is still the one its kick gave it (`kicked`: no contact pushed it
/// this substep) drifts along the kick's parabola, `p += hf (v − h a / 2)`, as
/// in free flight. Kick then drift left it `a h² / 2` lower each substep: a
/// ball bouncing at 0.63 m/s, its whole flight within the contact margin, lost
/// 0.1 % of its energy a step and rebounded at e = 0.491 of 0.5. A pushed body
/// keeps `p += hf v`, which the contact's targets (`v_n = −s/h`) assume.
pub fn translate_touching(b: &mut Bodies, list: &[u32], (hf, h): (f64, f64), kicked: &[[f64; 3]], src: &KickSources) {
    for &i in list {
        let i = i as usize;
        let v = b.linear_velocity[i];
        let pushed = kicked.get(i).is_none_or(|k| *k != v);
        let a = if pushed { Vec3::zeros() } else { src.acceleration(b, i) };
        let p = &mut b.position[i];
        for k in 0..3 {
            p[k] += hf * (v[k] - 0.5 * h * a[k]);
        }
    }
}
