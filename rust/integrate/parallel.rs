//! The free rotation of large groups of bodies split over threads. Each chunk
//! of the list is rotated by the serial kernel on a copy of the four arrays it
//! reads and writes (orientation, angular velocity, inertia and its inverse),
//! then written back: a body's arithmetic is the same whatever the chunks (the
//! kernels are per body; chunks are multiples of four, so the kernels' groups
//! of four stay as they are), and the fast bodies come back in list order. So
//! every thread count gives the same bits.

use rayon::prelude::*;

use super::fast_rotation::Substeps;
use super::free_rotation;
use super::Aniso;
use crate::body::Bodies;

/// Below this many bodies in a list the pool costs more than it saves (a
/// rotation is ~50 ns a body; handing work to the pool ~10 µs).
pub const MIN_BODIES: usize = 4096;
/// Bodies per chunk: a multiple of four.
const CHUNK: usize = 1024;

/// Whether `len` bodies are worth splitting over `threads`.
pub fn worth(threads: usize, len: usize) -> bool {
    threads > 1 && len >= MIN_BODIES
}

/// The four arrays of the bodies `index`, in that order (the others empty).
fn gather(b: &Bodies, index: impl Iterator<Item = usize> + Clone) -> Bodies {
    let mut c = Bodies::with_capacity(0);
    c.orientation = index.clone().map(|i| b.orientation[i]).collect();
    c.angular_velocity = index.clone().map(|i| b.angular_velocity[i]).collect();
    c.inertia = index.clone().map(|i| b.inertia[i]).collect();
    c.inv_inertia = index.map(|i| b.inv_inertia[i]).collect();
    c
}

/// Writes a chunk's orientations and angular velocities back.
fn scatter(b: &mut Bodies, c: &Bodies, index: impl Iterator<Item = usize>) {
    for (k, i) in index.enumerate() {
        b.orientation[i] = c.orientation[k];
        b.angular_velocity[i] = c.angular_velocity[k];
    }
}

fn rebased(list: &[Aniso]) -> Vec<Aniso> {
    list.iter().enumerate().map(|(k, a)| Aniso { index: k as u32, ..*a }).collect()
}

/// [`free_rotation::rotate_asymmetric`] over `threads`: the same bodies in `fast`.
pub fn rotate_asymmetric(
    threads: usize,
    b: &mut Bodies,
    list: &[Aniso],
    inv_spread: &[f64],
    h: f64,
    sub: Substeps,
    fast: &mut Vec<Aniso>,
) {
    if !worth(threads, list.len()) {
        return free_rotation::rotate_asymmetric(b, list, inv_spread, h, sub, fast);
    }
    let shared = &*b;
    let done: Vec<(Bodies, Vec<Aniso>)> = crate::world::threads::install(threads, || {
        list.par_chunks(CHUNK)
            .enumerate()
            .map(|(n, part)| {
                let mut c = gather(shared, part.iter().map(|a| a.index as usize));
                let spread = inv_spread.get(n * CHUNK / 4..).unwrap_or(&[]);
                let mut quick = Vec::new();
                free_rotation::rotate_asymmetric(&mut c, &rebased(part), spread, h, sub, &mut quick);
                quick.iter_mut().for_each(|a| a.index = part[a.index as usize].index);
                (c, quick)
            })
            .collect()
    });
    for (part, (c, quick)) in list.chunks(CHUNK).zip(done) {
        scatter(b, &c, part.iter().map(|a| a.index as usize));
        fast.extend(quick);
    }
}

/// A kernel over a list of `T` on a chunk's bodies, split over `threads`.
fn split<T: Sync>(
    threads: usize,
    b: &mut Bodies,
    list: &[T],
    index: impl Fn(&T) -> usize + Sync,
    kernel: impl Fn(&mut Bodies, &[T]) + Sync,
    rebase: impl Fn(&[T]) -> Vec<T> + Sync,
) {
    let shared = &*b;
    let done: Vec<Bodies> = crate::world::threads::install(threads, || {
        list.par_chunks(CHUNK)
            .map(|part| {
                let mut c = gather(shared, part.iter().map(&index));
                kernel(&mut c, &rebase(part));
                c
            })
            .collect()
    });
    for (part, c) in list.chunks(CHUNK).zip(done) {
        scatter(b, &c, part.iter().map(&index));
    }
}

/// [`free_rotation::rotate_asymmetric_unchecked`] over `threads`.
pub fn rotate_asymmetric_unchecked(threads: usize, b: &mut Bodies, list: &[Aniso], h: f64) {
    if !worth(threads, list.len()) {
        return free_rotation::rotate_asymmetric_unchecked(b, list, h);
    }
    let kernel = |c: &mut Bodies, l: &[Aniso]| free_rotation::rotate_asymmetric_unchecked(c, l, h);
    split(threads, b, list, |a| a.index as usize, kernel, rebased);
}

/// [`free_rotation::rotate_symmetric`] over `threads`.
pub fn rotate_symmetric(threads: usize, b: &mut Bodies, list: &[Aniso], h: f64) {
    if !worth(threads, list.len()) {
        return free_rotation::rotate_symmetric(b, list, h);
    }
    let kernel = |c: &mut Bodies, l: &[Aniso]| free_rotation::rotate_symmetric(c, l, h);
    split(threads, b, list, |a| a.index as usize, kernel, rebased);
}

/// [`free_rotation::rotate_isotropic`] over `threads`.
pub fn rotate_isotropic(threads: usize, b: &mut Bodies, list: &[u32], h: f64) {
    if !worth(threads, list.len()) {
        return free_rotation::rotate_isotropic(b, list, h);
    }
    let kernel = |c: &mut Bodies, l: &[u32]| free_rotation::rotate_isotropic(c, l, h);
    split(threads, b, list, |&i| i as usize, kernel, |part| (0..part.len() as u32).collect());
}

#[cfg(test)]
mod tests {
    use crate::body::Shape;
    use crate::world::{BodySpec, Scene, Settings, World};

    /// 6000 free bodies of the three inertia classes (boxes, rods, balls), a
    /// tenth of them spun fast enough to take rotation substeps: every list is
    /// over `MIN_BODIES` or close to it, and the fast list is not empty.
    fn free(threads: u32, integrator: crate::integrate::Integrator) -> World {
        let mut scene = Scene::new([0.0, 0.0, 0.0]).unwrap();
        for k in 0..6000u32 {
            let shape = match k % 3 {
                0 => Shape::cuboid([0.05, 0.1, 0.2]).unwrap(),
                1 => Shape::cuboid([0.05, 0.05, 0.2]).unwrap(),
                _ => Shape::sphere(0.1).unwrap(),
            };
            let x = f64::from(k);
            let spin = if k % 10 == 0 { 300.0 } else { 5.0 };
            let w = [spin * (0.3 * x).sin(), spin * (0.7 * x).cos(), spin * 0.2];
            let spec = BodySpec { shape: Some(shape), density: Some(1000.0), position: [x, 0.0, 0.0], angular_velocity: w, ..Default::default() };
            scene.add_body(spec).unwrap();
        }
        let mut s = Settings::new(1.0 / 60.0);
        s.integrator = integrator;
        s.threads = Some(threads);
        scene.build(&s).unwrap()
    }

    fn bits(w: &World) -> Vec<u64> {
        let b = &w.bodies;
        b.orientation.iter().flatten().chain(b.angular_velocity.iter().flatten()).map(|x| x.to_bits()).collect()
    }

    #[test]
    fn every_thread_count_gives_the_same_bits() {
        for integrator in [crate::integrate::Integrator::Strang, crate::integrate::Integrator::Yoshida4] {
            let mut one = free(1, integrator);
            one.step(5).unwrap();
            assert!(one.stage_names().contains(&"rotate_fast"), "{integrator:?}: no body took rotation substeps");
            for n in [2, 3] {
                let mut many = free(n, integrator);
                many.step(5).unwrap();
                assert_eq!(bits(&one), bits(&many), "{n} threads, {integrator:?}");
            }
        }
    }
}
