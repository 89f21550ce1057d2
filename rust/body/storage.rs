//! Body state as a struct of arrays, one `Vec` per field. A world allocates these
//! once; they never reallocate, so NumPy views of them stay valid.

use crate::math::{quat, Mat3, Quat, Vec3};

/// How a body moves.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
pub enum BodyKind {
    /// Moved by forces, torques and contacts.
    Dynamic,
    /// Never moves (infinite mass); its pose may be set by the user between steps.
    Fixed,
    /// Moved by the user through its velocities (infinite mass): pushes dynamic
    /// bodies, is pushed by nothing.
    Kinematic,
}

/// Per-body arrays. Index `i` of every field is body `i`.
#[derive(Debug, Default, serde::Serialize, serde::Deserialize)]
pub struct Bodies {
    /// Centre of mass, world frame (m).
    pub position: Vec<[f64; 3]>,
    /// Orientation of the principal frame, unit quaternion (x, y, z, w).
    pub orientation: Vec<[f64; 4]>,
    /// Velocity of the centre of mass, world frame (m/s).
    pub linear_velocity: Vec<[f64; 3]>,
    /// Angular velocity, world frame (rad/s).
    pub angular_velocity: Vec<[f64; 3]>,
    /// Applied force at the centre of mass, world frame (N). Persists across steps.
    pub force: Vec<[f64; 3]>,
    /// Applied torque, world frame (N·m). Persists across steps.
    pub torque: Vec<[f64; 3]>,
    /// Mass (kg); `inf` for fixed bodies.
    pub mass: Vec<f64>,
    /// 1 / mass (1/kg); 0 for fixed bodies.
    pub inv_mass: Vec<f64>,
    /// Principal moments of inertia, body frame (kg·m²); `inf` for fixed bodies.
    pub inertia: Vec<[f64; 3]>,
    /// Inverse principal moments (1/(kg·m²)); 0 for fixed bodies.
    pub inv_inertia: Vec<[f64; 3]>,
    pub kind: Vec<BodyKind>,
    /// Whether a dynamic body is asleep (at rest in an island that costs nothing
    /// until something touches it).
    pub sleeping: Vec<bool>,
    /// Derived, read-only to users: rotation matrix of each body, row-major.
    pub rotation: Vec<[f64; 9]>,
    /// Derived: world-frame angular momentum about the centre of mass (kg·m²/s).
    pub angular_momentum: Vec<[f64; 3]>,
    /// Derived: world-frame inertia tensor `R I0 Rᵀ`, row-major (kg·m²).
    pub inertia_world: Vec<[f64; 9]>,
}

clone_in_place!(Bodies { position, orientation, linear_velocity, angular_velocity, force, torque, mass, inv_mass, inertia, inv_inertia, kind, sleeping, rotation, angular_momentum, inertia_world });

/// The initial state and mass of one body, in its principal frame.
#[derive(Clone, Debug, serde::Serialize, serde::Deserialize)]
pub struct BodyInit {
    pub kind: BodyKind,
    pub position: Vec3,
    pub orientation: Quat,
    pub linear_velocity: Vec3,
    pub angular_velocity: Vec3,
    pub mass: f64,
    pub inertia: [f64; 3],
}

impl Bodies {
    pub fn with_capacity(n: usize) -> Self {
        Self {
            position: Vec::with_capacity(n),
            orientation: Vec::with_capacity(n),
            linear_velocity: Vec::with_capacity(n),
            angular_velocity: Vec::with_capacity(n),
            force: Vec::with_capacity(n),
            torque: Vec::with_capacity(n),
            mass: Vec::with_capacity(n),
            inv_mass: Vec::with_capacity(n),
            inertia: Vec::with_capacity(n),
            inv_inertia: Vec::with_capacity(n),
            kind: Vec::with_capacity(n),
            sleeping: Vec::with_capacity(n),
            rotation: Vec::with_capacity(n),
            angular_momentum: Vec::with_capacity(n),
            inertia_world: Vec::with_capacity(n),
        }
    }

    pub fn len(&self) -> usize {
        self.position.len()
    }

    pub fn is_empty(&self) -> bool {
        self.position.is_empty()
    }

    pub fn push(&mut self, b: &BodyInit) {
        let fixed = b.kind == BodyKind::Fixed;
        let infinite = b.kind != BodyKind::Dynamic;
        self.position.push(b.position.into());
        self.orientation.push(quat::to_xyzw(&b.orientation));
        let zero = [0.0; 3];
        self.linear_velocity.push(if fixed { zero } else { b.linear_velocity.into() });
        self.angular_velocity.push(if fixed { zero } else { b.angular_velocity.into() });
        self.force.push(zero);
        self.torque.push(zero);
        let (m, im) = if infinite { (f64::INFINITY, 0.0) } else { (b.mass, 1.0 / b.mass) };
        self.mass.push(m);
        self.inv_mass.push(im);
        self.inertia.push(if infinite { [f64::INFINITY; 3] } else { b.inertia });
        self.inv_inertia.push(if infinite { zero } else { b.inertia.map(|x| 1.0 / x) });
        self.kind.push(b.kind);
        self.sleeping.push(false);
        self.rotation.push([0.0; 9]);
        self.angular_momentum.push(zero);
        self.inertia_world.push([0.0; 9]);
    }

    /// A dynamic body that is not asleep.
    #[inline(always)]
    pub fn awake(&self, i: usize) -> bool {
        self.kind[i] == BodyKind::Dynamic && !self.sleeping[i]
    }

    /// Whether body `i` can move this step: awake dynamic, or kinematic with a velocity.
    pub fn moving(&self, i: usize) -> bool {
        match self.kind[i] {
            BodyKind::Dynamic => !self.sleeping[i],
            BodyKind::Kinematic => self.linear_velocity[i] != [0.0; 3] || self.angular_velocity[i] != [0.0; 3],
            BodyKind::Fixed => false,
        }
    }

    #[inline(always)]
    pub fn q(&self, i: usize) -> Quat {
        quat::from_xyzw(self.orientation[i])
    }

    /// World-frame inverse inertia applied to a world vector: `R I0⁻¹ Rᵀ v`.
    #[inline(always)]
    pub fn inv_inertia_world_mul(&self, i: usize, v: &Vec3) -> Vec3 {
        let q = self.q(i);
        let b = quat::rotate_inv(&q, v).component_mul(&Vec3::from(self.inv_inertia[i]));
        quat::rotate(&q, &b)
    }

    /// World-frame angular momentum about the centre of mass, `R I0 Rᵀ ω`.
    #[inline(always)]
    pub fn spin_momentum(&self, i: usize) -> Vec3 {
        if self.kind[i] != BodyKind::Dynamic {
            return Vec3::zeros();
        }
        let q = self.q(i);
        let wb = quat::rotate_inv(&q, &Vec3::from(self.angular_velocity[i]));
        quat::rotate(&q, &wb.component_mul(&Vec3::from(self.inertia[i])))
    }

    /// Refreshes the derived arrays (rotation, angular momentum, world inertia).
    pub fn update_derived(&mut self) {
        for i in 0..self.len() {
            let r = quat::to_matrix(&self.q(i));
            self.rotation[i] = row_major(&r);
            self.angular_momentum[i] = self.spin_momentum(i).into();
            let iw = if self.kind[i] != BodyKind::Dynamic {
                Mat3::from_diagonal_element(f64::INFINITY)
            } else {
                r * Mat3::from_diagonal(&Vec3::from(self.inertia[i])) * r.transpose()
            };
            self.inertia_world[i] = row_major(&iw);
        }
    }
}

fn row_major(m: &Mat3) -> [f64; 9] {
    [m[(0, 0)], m[(0, 1)], m[(0, 2)], m[(1, 0)], m[(1, 1)], m[(1, 2)], m[(2, 0)], m[(2, 1)], m[(2, 2)]]
}
