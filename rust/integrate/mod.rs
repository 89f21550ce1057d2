//! Time integrators: one file per method, each a set of kernels over lists of body
//! indices, so that a pipeline only touches the bodies a stage concerns.
//!
//! Every method but RK4 is a splitting `kick(a₀h) drift(b₁h) kick(a₁h) …`: the
//! kicks apply forces and torques, the drifts move bodies with their current
//! velocities and rotate them by a method of their own ([`Rotation`]).

pub mod classes;
pub mod composition;
pub mod drift;
pub mod euler;
pub mod fast_rotation;
pub mod free_rotation;
pub mod implicit_gyro;
pub mod kick;
pub mod parallel;
pub mod rk4;
pub mod strang;
pub mod symplectic_euler;

pub use classes::{Aniso, BodyLists, InertiaClass};

use crate::error::{Error, Result};

/// The integrators a world can be built with.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, serde::Serialize, serde::Deserialize)]
pub enum Integrator {
    /// Textbook explicit Euler on (p, P, R, L); first order, gains energy.
    Euler,
    /// Semi-implicit Euler with the explicit gyroscopic term; first order.
    SymplecticEuler,
    /// Semi-implicit Euler with a backward-Euler gyroscopic term (one Newton step),
    /// as Bullet, Box2D and Jolt do; first order, loses energy.
    ImplicitGyro,
    /// Classical Runge–Kutta on position, quaternion and momenta; fourth order.
    Rk4,
    /// Strang splitting into exact rotations about the principal axes; second
    /// order, |L| conserved exactly, energy bounded. The default.
    Strang,
    /// Yoshida's triple-jump composition of `Strang`; fourth order.
    Yoshida4,
    /// Suzuki's five-stage composition of `Strang`; fourth order, smaller error
    /// constant than Yoshida's for one more stage.
    Suzuki4,
}

/// How a drift rotates a body.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
pub enum Rotation {
    /// Exact torque-free flow (closed form for isotropic and symmetric bodies,
    /// Strang splitting into principal-axis rotations for asymmetric ones).
    Free,
    /// Explicit Euler on the quaternion at fixed world angular momentum.
    Euler,
    /// Rotation by the exponential map of `h ω` at fixed world angular velocity.
    Exp,
}

/// Which velocity-level gyroscopic update a scheme uses before its first kick.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
pub enum Gyroscopic {
    Explicit,
    Implicit,
}

/// A splitting scheme: `kicks.len() == drifts.len() + 1`, step fractions summing to 1.
#[derive(Clone, Debug, serde::Serialize, serde::Deserialize)]
pub struct Splitting {
    pub gyroscopic: Option<Gyroscopic>,
    pub kicks: Vec<f64>,
    pub drifts: Vec<f64>,
    pub rotation: Rotation,
}

/// RK4's [`Integrator::max_split_angle`]: the largest angle (rad) one RK4
/// step may turn a body by, at the fastest `|ω|` of its torque-free orbit
/// (`rk4::orbit_max_rate`), before its rotation is taken in equal substeps.
/// Measured on the fast spinners of `tests/test_fast_spinner.py` (the box of
/// REFERENCES.md at 480 and 800 rad/s for 60 s; five other bodies and orbits
/// at the fastest rate whose flips dt = 1/60 resolves, and at 1500 rad/s, 20 s):
/// at 0.03 the worst energy error is 1.2e-6 and the worst period error 2.5e-3
/// (the box at 800 rad/s: within half the 1e-3 and 1 % bars); at 0.05 the box's
/// period is off by 1.7 % and 2.6 % (RK4's error falls as the angle's fourth
/// power); at 0.02, 1.6e-7 and 3.7e-4 for half as many substeps again. Without
/// substeps the box ended spinning about its minor axis (energy ×4.82, period
/// +14 % and +102 %).
pub const RK4_MAX_ANGLE: f64 = 0.03;

impl Integrator {
    pub const ALL: [Integrator; 7] = [
        Integrator::Euler,
        Integrator::SymplecticEuler,
        Integrator::ImplicitGyro,
        Integrator::Rk4,
        Integrator::Strang,
        Integrator::Yoshida4,
        Integrator::Suzuki4,
    ];

    pub fn name(self) -> &'static str {
        match self {
            Integrator::Euler => "euler",
            Integrator::SymplecticEuler => "symplectic_euler",
            Integrator::ImplicitGyro => "implicit_gyro",
            Integrator::Rk4 => "rk4",
            Integrator::Strang => "strang",
            Integrator::Yoshida4 => "yoshida4",
            Integrator::Suzuki4 => "suzuki4",
        }
    }

    /// Nominal order of convergence.
    pub fn order(self) -> u32 {
        match self {
            Integrator::Euler | Integrator::SymplecticEuler | Integrator::ImplicitGyro => 1,
            Integrator::Strang => 2,
            Integrator::Rk4 | Integrator::Yoshida4 | Integrator::Suzuki4 => 4,
        }
    }

    /// Whether the method keeps the world angular momentum of a torque-free body
    /// to round-off.
    pub fn conserves_angular_momentum(self) -> bool {
        !matches!(self, Integrator::SymplecticEuler | Integrator::ImplicitGyro)
    }

    pub fn from_name(name: &str) -> Result<Self> {
        Self::ALL.into_iter().find(|i| i.name() == name).ok_or_else(|| {
            let names: Vec<&str> = Self::ALL.iter().map(|i| i.name()).collect();
            Error::input(format!("integrator: unknown name {name:?}; choose one of {}", names.join(", ")))
        })
    }

    /// The largest angle (rad) one step of the method may turn an asymmetric body
    /// by, taken at the largest `|ω|` of its free orbit, before that body's
    /// rotation is subdivided ([`fast_rotation::Substeps`]; for RK4, which does
    /// not split, [`RK4_MAX_ANGLE`]); infinite for euler, symplectic_euler and
    /// implicit_gyro, whose first-order rotation substeps would not buy the bars.
    ///
    /// Measured (`examples/spinner_calibration.rs`: 17 bodies and orbits, boxes,
    /// plates, a near-symmetric rod, moment ratios 1:1.1:3 to 1:2.9:3, near each
    /// axis, 400 periods each): the largest angle at which the worst body keeps its
    /// energy and its period within half the REFERENCES.md fast-spinner bars (1e-3,
    /// 1 %). strang: 0.2 rad (worst energy 4.5e-4, period 1.4e-3; at 0.3: 1.0e-3;
    /// the worked box of REFERENCES.md 3.6e-4 and 6.9e-4); yoshida4: 0.5 (8.2e-5,
    /// 3.4e-3; at 0.6 the period is off by 7.2e-3); suzuki4: 0.6 (2.8e-5, 9.4e-5),
    /// two thirds of the 0.9 rad where its error leaves the fourth-order trend
    /// (period 2.8e-4 at 0.8, 1.1e-2 at 0.9). A smaller angle buys accuracy at the
    /// fast body's cost (`max_rotation_angle`); a third of the bars would mean
    /// 0.15 / 0.4 / 0.6, and with 0.15 strang would test 10 000 boxes turning
    /// 5 rad/s at dt = 1/60 s exactly every step (8 % of its kernel) instead of
    /// clearing them from their `|ω|`.
    pub fn max_split_angle(self) -> f64 {
        match self {
            Integrator::Strang => 0.2,
            Integrator::Yoshida4 => 0.5,
            Integrator::Suzuki4 => 0.6,
            Integrator::Rk4 => RK4_MAX_ANGLE,
            _ => f64::INFINITY,
        }
    }

    /// The splitting this method is, or `None` for RK4 (one monolithic stage).
    pub fn splitting(self) -> Option<Splitting> {
        match self {
            Integrator::Euler => Some(euler::splitting()),
            Integrator::SymplecticEuler => Some(symplectic_euler::splitting()),
            Integrator::ImplicitGyro => Some(implicit_gyro::splitting()),
            Integrator::Rk4 => None,
            Integrator::Strang => Some(strang::splitting()),
            Integrator::Yoshida4 => Some(composition::yoshida4()),
            Integrator::Suzuki4 => Some(composition::suzuki4()),
        }
    }
}
