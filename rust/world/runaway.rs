//! Finite runaways: a step that ends with kinetic energy no force in the scene
//! can explain. The non-finite check of `guard` catches a blow-up once it
//! overflows; an unstable scene (a light body squeezed between heavy ones, a
//! chain of extreme mass ratios, a stiff drive at a large step) grows
//! geometrically for many steps before that, through absurd but finite speeds
//! (a chain at 7e11 J, a cloth 150 km wide), and each of those steps is slow
//! (rotation substeps, CCD sweeps of huge motions).
//!
//! The budget. Since the last reset (the first step of a world, a restore, a
//! pose, a step that failed) the kinetic
//! energy of the dynamic bodies and particles can only come from: the kinetic
//! energy they had then, `K₀`; the
//! gravity potential they have lost since, `max(0, U₀ − U)`; and the work of
//! the scene's active sources, accumulated step by step into `A`:
//!
//! - applied forces and torques: `dt (|F| |v| + |τ| |ω|)` per body and step
//!   (an impulse `J` on a body ending at `v` does at most `|J| |v|` of work);
//! - contact push-out: `½ m v_push²` per body in contact per step
//!   (`v_push` = `max_push_velocity`), the same per particle of a world with
//!   particles (their collisions project them out);
//! - moving kinematic bodies: `½ M (2 V)²` per step, `M` the mass of all
//!   dynamic bodies and particles and `V` the fastest kinematic point
//!   (`|v| + |ω| r`);
//! - articulation drives: `dt F |q̇|` per driven joint and step, `F` the drive's
//!   `max_force` or, when that is infinite, `k |q* − q| + c |q̇* − q̇|` (a
//!   spherical joint's angle error taken as π);
//! - what the user writes to positions, orientations or velocities between two
//!   `step` calls: the budget then carries what it allowed so far and adds
//!   the state as written (forces and drive targets written are counted as
//!   above);
//! - and, once after each reset or write, `½ M v_push²`: what pushing
//!   overlaps apart may give.
//!
//! The step after a reset or a write is checked at once, against the state
//! before it: a write of absurd but finite velocities whose first step
//! multiplied them (a spinning cube wedged in a column, ×4300 in one step)
//! was taken as the reference before. Not in a world with XPBD joints,
//! particles or articulations: a body written off its joint, a cloth placed
//! stretched or a link past its limit snaps back within that step at speeds
//! no bound of the state before explains, so there the reference is the
//! state after that step.
//!
//! A step is a runaway when the kinetic energy after it exceeds
//! [`RUNAWAY_FACTOR`] times `K₀ + A + max(0, U₀ − U)`. The factor (100 in
//! energy, 10 in speed) covers what this accounting leaves out and cannot
//! exceed in a stable scene: energy stored in XPBD joints, cloth and soft
//! contacts and given back, a push-out that adds up along a chain of overlaps,
//! the energy error of the integrators. An exponential runaway passes it within
//! a few steps of leaving the scene's energy scale, while the budget only ever
//! grows linearly with time.
//!
//! When. The check runs every [`CHECK_EVERY`] steps (and before every
//! checkpoint of `guard`, and after the first step since a reset or a write
//! where that step is judged); one that fails replays the steps since the last
//! check that passed, checking each, and the world goes back before the first
//! step over budget, never before the current `step` call (earlier calls have
//! returned): a world already over budget at the start of the call stays as it
//! was, with the error saying so.

use super::World;
use crate::articulation::DriveMode;
use crate::body::BodyKind;
use crate::integrate::kick::KickSources;

/// How many times the kinetic energy the scene can explain a step may end with.
pub const RUNAWAY_FACTOR: f64 = 100.0;

/// Steps between two energy checks. The check is one pass over the bodies
/// (some 90 instructions each, a tenth of a free body's step); made every
/// `CHECK_EVERY` steps it costs about 1 %, and a failed check finds the first
/// step over budget among those since the last one by replaying them.
pub const CHECK_EVERY: u32 = 8;

/// Kinetic energy (J), gravity potential (J, zero at the origin) and mass (kg)
/// of the dynamic bodies and the particles that are not pinned.
#[derive(Clone, Copy, Debug, Default)]
pub struct Energy {
    pub kinetic: f64,
    pub potential: f64,
    pub mass: f64,
    /// Of which particles (kg).
    pub particle_mass: f64,
}

/// The energy budget of one world since its last reset (see the module).
#[derive(Clone, Debug, Default)]
pub struct Budget {
    live: bool,
    /// Reset or written before the first step since, in a world whose
    /// constraints snap back (see the module): the reference is taken after
    /// that step (what a body written off its joint gives in one step is
    /// its own).
    warm: bool,
    /// Reset or written in a world without such constraints: the next step is
    /// checked as soon as it is taken.
    due: bool,
    kinetic_ref: f64,
    potential_ref: f64,
    /// Work of the sources up to the last check (J), and since (J).
    allowance: f64,
    work: f64,
    /// Steps since the last check.
    pending: u32,
    mass: f64,
    particle_mass: f64,
}

/// A check that failed: the kinetic energy (J) and the bound it broke (J).
#[derive(Clone, Copy, Debug)]
pub struct Runaway {
    pub kinetic: f64,
    pub bound: f64,
}

impl Budget {
    /// Starts over from the world as it is.
    pub fn reset(&mut self, w: &World) {
        let e = w.energy();
        let v = w.settings.solver.max_push_velocity;
        let snaps = w.snaps_back();
        *self = Self {
            live: true,
            warm: snaps,
            due: !snaps,
            kinetic_ref: e.kinetic,
            potential_ref: e.potential,
            allowance: 0.5 * e.mass * v * v,
            work: 0.0,
            pending: 0,
            mass: e.mass,
            particle_mass: e.particle_mass,
        };
    }

    /// At the start of a `step` call after the user wrote positions,
    /// orientations or velocities: the world as it is now (or after the next
    /// step, where constraints snap back) is explained by the energy the
    /// budget allowed until now plus what it holds then (the writes count as
    /// work, and so do the unchecked steps before them).
    pub fn written(&mut self, w: &World) {
        if !self.live {
            return self.reset(w);
        }
        let e = w.energy();
        let before = self.kinetic_ref + self.allowance + self.work + (self.potential_ref - e.potential).max(0.0);
        let v = w.settings.solver.max_push_velocity;
        let snaps = w.snaps_back();
        *self = Self {
            warm: snaps,
            due: !snaps,
            kinetic_ref: e.kinetic,
            potential_ref: e.potential,
            allowance: before + 0.5 * e.mass * v * v,
            work: 0.0,
            pending: 0,
            ..self.clone()
        };
    }

    /// After a step that left the world finite: adds the most work the
    /// scene's sources can have done over it. Whether a check is due.
    pub fn stepped(&mut self, w: &World, src: &KickSources) -> bool {
        if !self.live {
            self.reset(w);
        }
        if self.warm {
            let e = w.energy();
            (self.kinetic_ref, self.potential_ref, self.warm) = (e.kinetic, e.potential, false);
            return false;
        }
        self.work += w.step_work(src, self.mass, self.particle_mass);
        self.pending += 1;
        std::mem::take(&mut self.due) || self.pending >= CHECK_EVERY
    }

    /// Steps since the last check.
    pub fn pending(&self) -> u32 {
        if self.live {
            self.pending
        } else {
            0
        }
    }

    /// Compares the world's kinetic energy with the budget; passing folds the
    /// work since the last check into the allowance. Not inlined: its cost
    /// shows apart in a profile.
    #[inline(never)]
    pub fn check(&mut self, w: &World) -> Result<(), Runaway> {
        if !self.live || self.pending == 0 {
            return Ok(());
        }
        let e = w.energy();
        let bound = self.bound(e.potential);
        if e.kinetic > bound {
            return Err(Runaway { kinetic: e.kinetic, bound });
        }
        self.allowance += self.work;
        self.work = 0.0;
        self.pending = 0;
        Ok(())
    }

    /// Whether `w` is over this budget as it is (for a state no check saw).
    pub fn over(&self, w: &World) -> Option<Runaway> {
        let e = w.energy();
        let bound = self.bound(e.potential);
        (self.live && e.kinetic > bound).then_some(Runaway { kinetic: e.kinetic, bound })
    }

    /// The budget as at its last check (a replay of the steps since adds
    /// their work again).
    pub fn at_last_check(&self) -> Self {
        Self { work: 0.0, pending: 0, ..self.clone() }
    }

    /// The bound (J) on the kinetic energy at gravity potential `potential`.
    pub fn bound(&self, potential: f64) -> f64 {
        RUNAWAY_FACTOR * (self.kinetic_ref + self.allowance + self.work + (self.potential_ref - potential).max(0.0))
    }
}

/// `½ ωᵀ I ω` of a body of principal inertia `inertia`, orientation `q`
/// (x, y, z, w) and world angular velocity `w`: ω taken to the body frame.
#[inline(always)]
fn spin_energy(q: &[f64; 4], w: &[f64; 3], inertia: &[f64; 3]) -> f64 {
    let (u, s) = ([-q[0], -q[1], -q[2]], q[3]);
    let cross = |a: &[f64; 3], b: &[f64; 3]| [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]];
    let t = cross(&u, w).map(|x| 2.0 * x);
    let c = cross(&u, &t);
    let wb = [w[0] + s * t[0] + c[0], w[1] + s * t[1] + c[1], w[2] + s * t[2] + c[2]];
    0.5 * (inertia[0] * wb[0] * wb[0] + inertia[1] * wb[1] * wb[1] + inertia[2] * wb[2] * wb[2])
}

fn norm(v: &[f64; 3]) -> f64 {
    (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt()
}

impl World {
    /// Whether some constraint of the world may snap back within one step
    /// from a state as written or placed (XPBD joints, particles,
    /// articulations): see the module.
    fn snaps_back(&self) -> bool {
        !self.joints.is_empty() || self.particles().is_some() || !self.articulations.is_empty()
    }

    /// Kinetic energy, gravity potential and mass of the dynamic bodies and
    /// the free particles: one pass.
    pub fn energy(&self) -> Energy {
        let b = &self.bodies;
        let g = [self.gravity.x, self.gravity.y, self.gravity.z];
        let mut e = Energy::default();
        for i in 0..b.len() {
            if b.kind[i] != BodyKind::Dynamic {
                continue;
            }
            let (m, v, x) = (b.mass[i], &b.linear_velocity[i], &b.position[i]);
            e.kinetic += 0.5 * m * (v[0] * v[0] + v[1] * v[1] + v[2] * v[2])
                + spin_energy(&b.orientation[i], &b.angular_velocity[i], &b.inertia[i]);
            e.potential -= m * (g[0] * x[0] + g[1] * x[1] + g[2] * x[2]);
            e.mass += m;
        }
        if let Some(p) = self.particles() {
            for i in 0..p.len() {
                if p.inv_mass[i] == 0.0 {
                    continue;
                }
                let (m, v, x) = (p.mass[i], &p.velocity[i], &p.position[i]);
                e.kinetic += 0.5 * m * (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
                e.potential -= m * (g[0] * x[0] + g[1] * x[1] + g[2] * x[2]);
                e.particle_mass += m;
            }
            e.mass += e.particle_mass;
        }
        e
    }

    /// The most the scene's active sources can have added over the step just
    /// taken (J; see the module): applied forces, push-out, kinematic bodies,
    /// drives. `mass`, `particle_mass`: of the dynamic bodies and free
    /// particles, and of the particles alone (kg).
    #[inline(never)]
    fn step_work(&self, src: &KickSources, mass: f64, particle_mass: f64) -> f64 {
        let (b, dt) = (&self.bodies, self.settings.dt);
        let push = self.settings.solver.max_push_velocity;
        let mut work = 0.0;
        if src.force || src.torque {
            for i in 0..b.len() {
                if b.kind[i] == BodyKind::Dynamic {
                    work += dt * (norm(&b.force[i]) * norm(&b.linear_velocity[i]) + norm(&b.torque[i]) * norm(&b.angular_velocity[i]));
                }
            }
        }
        if self.collision.is_some() {
            let touching: f64 = self.split[1].dynamic.iter().map(|&i| b.mass[i as usize]).sum();
            work += 0.5 * touching * push * push;
        }
        work += 0.5 * particle_mass * push * push;
        let fastest = self.fastest_kinematic();
        work += 2.0 * mass * fastest * fastest;
        work + dt * self.drive_power()
    }

    /// The speed (m/s) of the fastest point of a kinematic body: `|v| + |ω| r`,
    /// `r` the reach of its colliders.
    fn fastest_kinematic(&self) -> f64 {
        let b = &self.bodies;
        let mut fastest: f64 = 0.0;
        for &k in &self.kinematic {
            let k = k as usize;
            let spin = norm(&b.angular_velocity[k]);
            let reach = if spin == 0.0 {
                0.0
            } else {
                self.collision.as_ref().map_or(0.0, |c| {
                    c.colliders.iter().filter(|c| c.body as usize == k && !c.infinite).map(|c| c.reach).fold(0.0, f64::max)
                })
            };
            fastest = fastest.max(norm(&b.linear_velocity[k]) + spin * reach);
        }
        fastest
    }

    /// The most power (W) the articulations' drives can deliver now.
    fn drive_power(&self) -> f64 {
        let mut power = 0.0;
        for a in &self.articulations.list {
            for l in &a.links {
                let Some(d) = &l.control.drive else { continue };
                let nv = l.model.nv();
                let Some(v) = a.v.get(l.v_at..l.v_at + nv) else { continue };
                let rate = v.iter().map(|x| x * x).sum::<f64>().sqrt();
                let force = if d.max_force.is_finite() {
                    d.max_force * (nv as f64).sqrt()
                } else {
                    let target = |k: usize| d.target.get(k).copied().unwrap_or(0.0);
                    let error = match d.mode {
                        DriveMode::Position if nv == 1 => a.q.get(l.q_at).map_or(std::f64::consts::PI, |q| (target(0) - q).abs()),
                        DriveMode::Position => std::f64::consts::PI,
                        DriveMode::Velocity => 0.0,
                    };
                    let rate_error = match d.mode {
                        DriveMode::Velocity => (0..nv).map(|k| (target(k) - v[k]).powi(2)).sum::<f64>().sqrt(),
                        DriveMode::Position => rate,
                    };
                    d.stiffness * error + d.damping * rate_error
                };
                power += force * rate;
            }
        }
        power
    }
}

impl World {
    /// The dynamic body or free particle with the most kinetic energy, in
    /// words: the one a runaway report names.
    pub(crate) fn fastest(&self) -> String {
        let b = &self.bodies;
        let body = (0..b.len())
            .filter(|&i| b.kind[i] == BodyKind::Dynamic)
            .map(|i| {
                let v = &b.linear_velocity[i];
                let k = 0.5 * b.mass[i] * (v[0] * v[0] + v[1] * v[1] + v[2] * v[2])
                    + spin_energy(&b.orientation[i], &b.angular_velocity[i], &b.inertia[i]);
                (i, k)
            })
            .max_by(|x, y| x.1.total_cmp(&y.1));
        let particle = self.particles().and_then(|p| {
            (0..p.len())
                .filter(|&i| p.inv_mass[i] != 0.0)
                .map(|i| (i, 0.5 * p.mass[i] * norm(&p.velocity[i]).powi(2)))
                .max_by(|x, y| x.1.total_cmp(&y.1))
        });
        match (body, particle) {
            (Some((i, k)), p) if p.is_none_or(|p| p.1 <= k) => format!(
                "body {i} has {k:.4e} J of kinetic energy (speed {:.4e} m/s, angular velocity {:.4e} rad/s)",
                norm(&b.linear_velocity[i]),
                norm(&b.angular_velocity[i])
            ),
            (_, Some((i, k))) => format!(
                "particle {i} has {k:.4e} J of kinetic energy (speed {:.4e} m/s)",
                self.particles().map_or(0.0, |p| norm(&p.velocity[i]))
            ),
            _ => "no body or particle".to_string(),
        }
    }
}
