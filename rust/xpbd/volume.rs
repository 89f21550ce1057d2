//! Volume constraints: one tetrahedron, `C = V − V₀` with
//! `V = (x₁ − x₀)·((x₂ − x₀) × (x₃ − x₀)) / 6`, and a closed triangle mesh (a
//! balloon, Müller et al. 2007), `C = V − k·V₀` with `V = Σ (xₐ × x_b)·x_c / 6`
//! over its outward (counter-clockwise) triangles and `k` the pressure factor.
//! Volumes in m³; `λ/h²` is the pressure the constraint exerts (Pa); compliance
//! in m³/Pa (m⁵/N).

use std::collections::HashMap;

use super::compliance::{delta_lambda, Compliance, Substep};
use crate::error::{Error, Result};
use crate::math::Vec3;

/// Smallest |6V| (m³) of a tetrahedron that still has a volume to keep.
pub const DEGENERATE_VOLUME: f64 = 1e-18;

#[derive(Clone, Copy, Debug, serde::Serialize, serde::Deserialize)]
pub struct TetVolume {
    pub p: [u32; 4],
    /// Rest volume V₀ (m³), signed by the vertex order.
    pub rest: f64,
    pub compliance: Compliance,
    pub id: u32,
    pub lambda: f64,
}

/// Signed volume of a tetrahedron and its gradient with respect to the vertices.
pub fn tet_volume(x: [Vec3; 4]) -> (f64, [Vec3; 4]) {
    let (a, b, c) = (x[1] - x[0], x[2] - x[0], x[3] - x[0]);
    let g1 = b.cross(&c) / 6.0;
    let g2 = c.cross(&a) / 6.0;
    let g3 = a.cross(&b) / 6.0;
    (a.dot(&g1), [-(g1 + g2 + g3), g1, g2, g3])
}

/// Checks a tetrahedron's rest shape; returns its signed rest volume (m³).
pub fn tet_rest(x: [Vec3; 4]) -> Result<f64> {
    let v = tet_volume(x).0;
    if !(v.abs() * 6.0 > DEGENERATE_VOLUME) {
        return Err(Error::shape(format!("the tetrahedron is degenerate (volume {v:.3e} m³): its 4 particles are coplanar")));
    }
    Ok(v)
}

#[inline]
pub fn project_tet(c: &mut TetVolume, x: &mut [[f64; 3]], prev: &[[f64; 3]], w: &[f64], k: &Substep) {
    let idx = c.p.map(|i| i as usize);
    let pos = idx.map(|i| Vec3::from(x[i]));
    let (v, g) = tet_volume(pos);
    let ws = idx.map(|i| w[i]);
    let wsum: f64 = (0..4).map(|a| ws[a] * g[a].norm_squared()).sum();
    if !(wsum > 0.0) {
        return;
    }
    let (alpha_t, gamma) = k.factors(&c.compliance);
    let grad_dx = if gamma > 0.0 { (0..4).map(|a| g[a].dot(&(pos[a] - Vec3::from(prev[idx[a]])))).sum() } else { 0.0 };
    let dl = delta_lambda(v - c.rest, c.lambda, wsum, alpha_t, gamma, grad_dx);
    c.lambda += dl;
    for a in 0..4 {
        x[idx[a]] = (pos[a] + g[a] * (ws[a] * dl)).into();
    }
}

/// The volume of a closed mesh of particles.
#[derive(Clone, Debug, serde::Serialize, serde::Deserialize)]
pub struct MeshVolume {
    /// The distinct particles of the mesh.
    pub particles: Vec<u32>,
    /// Triangles as indices into `particles`, counter-clockwise from outside.
    pub triangles: Vec<[u32; 3]>,
    /// Rest volume V₀ (m³) > 0.
    pub rest: f64,
    /// Pressure factor k (–): the target volume is k·V₀. Default 1.
    pub pressure: f64,
    pub compliance: Compliance,
    pub id: u32,
    pub lambda: f64,
    /// Scratch: the gradient for each particle (m²).
    grad: Vec<Vec3>,
}

impl MeshVolume {
    /// Validates a closed, outward-oriented mesh of particles (`triangles` hold
    /// particle indices, already range-checked) at positions `x`.
    pub fn new(triangles: &[[u32; 3]], x: &[[f64; 3]], pressure: f64, compliance: Compliance, id: u32) -> Result<Self> {
        if triangles.len() < 4 {
            return Err(Error::shape(format!("a closed mesh needs at least 4 triangles, got {}", triangles.len())));
        }
        check_closed(triangles)?;
        let mut local: HashMap<u32, u32> = HashMap::new();
        let mut particles = Vec::new();
        let mut tris = Vec::with_capacity(triangles.len());
        for t in triangles {
            tris.push(t.map(|p| {
                *local.entry(p).or_insert_with(|| {
                    particles.push(p);
                    (particles.len() - 1) as u32
                })
            }));
        }
        let mut m = Self {
            grad: vec![Vec3::zeros(); particles.len()],
            particles,
            triangles: tris,
            rest: 0.0,
            pressure,
            compliance,
            id,
            lambda: 0.0,
        };
        let v = m.volume(x);
        if !(v > DEGENERATE_VOLUME) {
            return Err(Error::shape(format!(
                "the mesh encloses a volume of {v:.3e} m³: its triangles face inward or it is flat \
                 (triangles must be counter-clockwise seen from outside)"
            )));
        }
        m.rest = v;
        Ok(m)
    }

    /// Enclosed volume (m³), and the gradient into the scratch buffer.
    fn volume_and_gradient(&mut self, x: &[[f64; 3]]) -> f64 {
        // Relative to one vertex: the same volume for a closed mesh, less round-off.
        let o = Vec3::from(x[self.particles[0] as usize]);
        self.grad.fill(Vec3::zeros());
        let mut v = 0.0;
        for t in &self.triangles {
            let [a, b, c] = t.map(|k| Vec3::from(x[self.particles[k as usize] as usize]) - o);
            v += a.cross(&b).dot(&c);
            self.grad[t[0] as usize] += b.cross(&c);
            self.grad[t[1] as usize] += c.cross(&a);
            self.grad[t[2] as usize] += a.cross(&b);
        }
        self.grad.iter_mut().for_each(|g| *g /= 6.0);
        v / 6.0
    }

    /// Enclosed volume (m³).
    pub fn volume(&mut self, x: &[[f64; 3]]) -> f64 {
        self.volume_and_gradient(x)
    }

    pub fn project(&mut self, x: &mut [[f64; 3]], prev: &[[f64; 3]], w: &[f64], k: &Substep) {
        let v = self.volume_and_gradient(x);
        let mut wsum = 0.0;
        let mut grad_dx = 0.0;
        for (g, &p) in self.grad.iter().zip(&self.particles) {
            let p = p as usize;
            wsum += w[p] * g.norm_squared();
            grad_dx += g.dot(&(Vec3::from(x[p]) - Vec3::from(prev[p])));
        }
        if !(wsum > 0.0) {
            return;
        }
        let (alpha_t, gamma) = k.factors(&self.compliance);
        let dl = delta_lambda(v - self.pressure * self.rest, self.lambda, wsum, alpha_t, gamma, grad_dx);
        self.lambda += dl;
        for (g, &p) in self.grad.iter().zip(&self.particles) {
            let p = p as usize;
            x[p] = (Vec3::from(x[p]) + g * (w[p] * dl)).into();
        }
    }
}

/// Every directed edge appears once, and its reverse once: closed and
/// consistently oriented.
fn check_closed(triangles: &[[u32; 3]]) -> Result<()> {
    let mut edges: HashMap<(u32, u32), usize> = HashMap::new();
    for (t, tri) in triangles.iter().enumerate() {
        if tri[0] == tri[1] || tri[1] == tri[2] || tri[0] == tri[2] {
            return Err(Error::shape(format!("triangle {t} repeats a particle: {tri:?}")));
        }
        for k in 0..3 {
            let e = (tri[k], tri[(k + 1) % 3]);
            if edges.insert(e, t).is_some() {
                return Err(Error::shape(format!(
                    "edge {}-{} appears twice in the same direction (triangle {t}): the mesh is not consistently oriented",
                    e.0, e.1
                )));
            }
        }
    }
    for &(a, b) in edges.keys() {
        if !edges.contains_key(&(b, a)) {
            return Err(Error::shape(format!("edge {a}-{b} has a triangle on one side only: the mesh is not closed")));
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn tetra() -> [Vec3; 4] {
        [Vec3::new(0.0, 0.0, 0.0), Vec3::new(1.0, 0.0, 0.0), Vec3::new(0.0, 1.0, 0.0), Vec3::new(0.0, 0.0, 1.0)]
    }

    #[test]
    fn tet_volume_and_gradient() {
        let (v, g) = tet_volume(tetra());
        assert!((v - 1.0 / 6.0).abs() < 1e-16);
        for a in 0..4 {
            for d in 0..3 {
                let mut x = tetra();
                x[a][d] += 1e-7;
                // V is linear in each vertex: forward differences are exact up to round-off.
                assert!(((tet_volume(x).0 - v) / 1e-7 - g[a][d]).abs() < 1e-8);
            }
        }
    }

    #[test]
    fn mesh_volume_of_a_tetrahedron_surface() {
        let x: Vec<[f64; 3]> = tetra().iter().map(|v| [v.x + 5.0, v.y, v.z]).collect();
        let tris = [[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]];
        let m = MeshVolume::new(&tris, &x, 1.0, Compliance::default(), 0).unwrap();
        assert!((m.rest - 1.0 / 6.0).abs() < 1e-15);
        let inward = tris.map(|t| [t[0], t[2], t[1]]);
        assert!(MeshVolume::new(&inward, &x, 1.0, Compliance::default(), 0).is_err());
        assert!(MeshVolume::new(&tris[..3], &x, 1.0, Compliance::default(), 0).is_err());
    }

    #[test]
    fn rigid_volume_projection_restores_the_volume() {
        let mut x: Vec<[f64; 3]> = tetra().iter().map(|v| [v.x * 1.3, v.y, v.z]).collect();
        let prev = x.clone();
        let mut c = TetVolume { p: [0, 1, 2, 3], rest: 1.0 / 6.0, compliance: Compliance::default(), id: 0, lambda: 0.0 };
        for _ in 0..10 {
            project_tet(&mut c, &mut x, &prev, &[1.0; 4], &Substep::new(0.01));
        }
        let v = tet_volume([0, 1, 2, 3].map(|i| Vec3::from(x[i]))).0;
        assert!((v - 1.0 / 6.0).abs() < 1e-12);
    }
}
