//! Steps that never leave a world broken. `step_guarded` checks after every
//! step that bodies and particles are finite and catches a panic inside a
//! step; on either it puts the world back exactly as it was before the failing
//! step, finds the stage that failed (by running the step again on a copy,
//! watched stage by stage) and returns a `Simulation` error naming the body or
//! particle, the stage and the time.
//!
//! Putting back without copying the world every step: a checkpoint (a clone)
//! is taken now and then, and every `step` call since is logged (the
//! view-writable arrays when the user changed them, and the steps taken), so
//! that the checkpoint plus a replay of the log is the state before any step.
//! Stepping is deterministic, so the replay is bitwise. Cost per call: one
//! bitwise compare and copy of the view-writable arrays; per step: one pass of
//! sums over positions and velocities; per checkpoint (every 256 steps, 64
//! logged calls or 32 MB of log, or after a change the log cannot hold): one
//! clone of the world.

use std::panic::{catch_unwind, AssertUnwindSafe};

use super::{validate, World};
use crate::error::{Error, Result};

const CHECKPOINT_STEPS: u64 = 256;
const CHECKPOINT_CALLS: usize = 64;
const CHECKPOINT_LOG_BYTES: usize = 32 << 20;

/// What the watched re-run of a failed step saw: the stage running, and the
/// first stage after which the state was not finite, with what was not.
#[derive(Clone, Debug, Default)]
pub struct Watch {
    pub current: &'static str,
    pub first_bad: Option<(&'static str, String)>,
}

/// The arrays a user can write through views, as they were.
#[derive(Clone, Debug, Default)]
struct Inputs {
    position: Vec<[f64; 3]>,
    orientation: Vec<[f64; 4]>,
    linear_velocity: Vec<[f64; 3]>,
    angular_velocity: Vec<[f64; 3]>,
    force: Vec<[f64; 3]>,
    torque: Vec<[f64; 3]>,
    particle_position: Vec<[f64; 3]>,
    particle_velocity: Vec<[f64; 3]>,
    target: Vec<f64>,
}

/// Bitwise equality (`==` on floats would take -0.0 for 0.0 and never NaN for NaN).
fn same<const N: usize>(a: &[[f64; N]], b: &[[f64; N]]) -> bool {
    a.len() == b.len() && a.iter().flatten().zip(b.iter().flatten()).all(|(x, y)| x.to_bits() == y.to_bits())
}

impl Inputs {
    fn read_into(&mut self, w: &World) {
        let b = &w.bodies;
        self.position.clone_from(&b.position);
        self.orientation.clone_from(&b.orientation);
        self.linear_velocity.clone_from(&b.linear_velocity);
        self.angular_velocity.clone_from(&b.angular_velocity);
        self.force.clone_from(&b.force);
        self.torque.clone_from(&b.torque);
        let p = w.particles();
        self.particle_position.clone_from(p.map_or(&Vec::new(), |p| &p.position));
        self.particle_velocity.clone_from(p.map_or(&Vec::new(), |p| &p.velocity));
        self.target.clone_from(&w.joint_target);
    }

    fn same_as(&self, w: &World) -> bool {
        let b = &w.bodies;
        let none = Vec::new();
        let p = w.particles();
        same(&self.position, &b.position)
            && same(&self.orientation, &b.orientation)
            && same(&self.linear_velocity, &b.linear_velocity)
            && same(&self.angular_velocity, &b.angular_velocity)
            && same(&self.force, &b.force)
            && same(&self.torque, &b.torque)
            && same(&self.particle_position, p.map_or(&none, |p| &p.position))
            && same(&self.particle_velocity, p.map_or(&none, |p| &p.velocity))
            && self.target.len() == w.joint_target.len()
            && self.target.iter().zip(&w.joint_target).all(|(x, y)| x.to_bits() == y.to_bits())
    }

    /// Writes these values back (into the same memory: views stay valid).
    fn write(&self, w: &mut World) {
        let b = &mut w.bodies;
        b.position.copy_from_slice(&self.position);
        b.orientation.copy_from_slice(&self.orientation);
        b.linear_velocity.copy_from_slice(&self.linear_velocity);
        b.angular_velocity.copy_from_slice(&self.angular_velocity);
        b.force.copy_from_slice(&self.force);
        b.torque.copy_from_slice(&self.torque);
        if let Some(x) = w.xpbd.as_mut() {
            x.particles.position.copy_from_slice(&self.particle_position);
            x.particles.velocity.copy_from_slice(&self.particle_velocity);
        }
        w.joint_target.copy_from_slice(&self.target);
    }

    fn bytes(&self) -> usize {
        8 * (3 * (self.position.len() * 5 + self.particle_position.len() * 2) + 4 * self.orientation.len() + self.target.len())
    }
}

/// One `step` call since the checkpoint: the inputs the user wrote before it
/// (if they changed), whether it began at the checkpoint without preparing
/// (a checkpoint taken between two steps of one call), and its steps.
struct Call {
    inputs: Option<Inputs>,
    prepare: bool,
    steps: u64,
}

/// The checkpoint and the log since; one per Python world.
#[derive(Default)]
pub struct Guard {
    checkpoint: Option<Box<World>>,
    calls: Vec<Call>,
    steps: u64,
    log_bytes: usize,
    /// The view-writable arrays when the last call ended, and whether the
    /// world has been changed since in ways they do not show.
    last: Inputs,
    stale: bool,
}

impl Guard {
    /// The world was changed other than through its views (restored, posed):
    /// the next call starts from a new checkpoint.
    pub fn invalidate(&mut self) {
        self.stale = true;
    }

    fn due(&self) -> bool {
        self.steps >= CHECKPOINT_STEPS || self.calls.len() >= CHECKPOINT_CALLS || self.log_bytes >= CHECKPOINT_LOG_BYTES
    }

    fn checkpoint(&mut self, w: &World, prepare: bool) {
        self.checkpoint = Some(Box::new(w.clone()));
        self.calls.clear();
        self.calls.push(Call { inputs: None, prepare, steps: 0 });
        self.steps = 0;
        self.log_bytes = 0;
    }

    /// At the start of a call, before `prepare`.
    fn begin(&mut self, w: &World) {
        if self.stale || self.checkpoint.is_none() || self.due() {
            self.stale = false;
            return self.checkpoint(w, true);
        }
        let inputs = (!self.last.same_as(w)).then(|| {
            let mut i = Inputs::default();
            i.read_into(w);
            self.log_bytes += i.bytes();
            i
        });
        self.calls.push(Call { inputs, prepare: true, steps: 0 });
    }

    fn stepped(&mut self, w: &World) {
        if let Some(c) = self.calls.last_mut() {
            c.steps += 1;
        }
        self.steps += 1;
        if self.steps >= CHECKPOINT_STEPS {
            self.checkpoint(w, false);
        }
    }

    fn end(&mut self, w: &World) {
        self.last.read_into(w);
    }

    /// Puts `w` back to the checkpoint and replays the log: the state before
    /// the step that failed. Whether the replay went through (if not, `w` is at
    /// the checkpoint).
    fn roll_back(&mut self, w: &mut World) -> bool {
        let Some(cp) = self.checkpoint.as_deref() else { return false };
        if w.restore(cp).is_err() {
            return false;
        }
        let replayed = catch_unwind(AssertUnwindSafe(|| {
            for c in &self.calls {
                if let Some(i) = &c.inputs {
                    i.write(w);
                }
                if c.prepare {
                    w.prepare();
                }
                let src = w.kick_sources();
                for _ in 0..c.steps {
                    w.one_step(&src);
                }
                w.finish();
            }
        }));
        self.stale = true;
        replayed.is_ok() || w.restore(cp).is_err()
    }
}

/// Why a step failed.
enum Failure {
    NotFinite,
    Panic(String),
}

fn panic_message(p: &(dyn std::any::Any + Send)) -> String {
    p.downcast_ref::<&str>().map(|s| s.to_string()).or_else(|| p.downcast_ref::<String>().cloned()).unwrap_or_default()
}

impl World {
    /// Whether every body and particle position, velocity and orientation is
    /// finite (one pass of sums).
    pub(crate) fn state_finite(&self) -> bool {
        let flat = |v: &[[f64; 3]]| v.iter().map(|a| a[0] * 0.0 + a[1] * 0.0 + a[2] * 0.0).sum::<f64>();
        validate::all_finite(&self.bodies) && self.particles().is_none_or(|p| flat(&p.position) + flat(&p.velocity) == 0.0)
    }

    /// After a stage of a watched step: the first stage that left the state
    /// not finite.
    pub(crate) fn watch_after(&mut self, stage: &'static str) {
        if self.watch.as_ref().is_some_and(|w| w.first_bad.is_none()) && !self.state_finite() {
            let what = self.culprit();
            if let Some(w) = self.watch.as_mut() {
                w.first_bad = Some((stage, what));
            }
        }
    }

    /// The body or particle that is not finite, in words.
    fn culprit(&self) -> String {
        let named = |e: Error| e.message;
        validate::check(&self.bodies)
            .err()
            .map(named)
            .or_else(|| self.check_particles().err().map(named))
            .unwrap_or_else(|| "no body or particle".into())
    }

    /// Advances up to `n` steps as `step` does, calling `interrupted` between
    /// two steps (true: stop there). Returns the steps taken. A step that
    /// leaves the state not finite, or fails inside, is undone: the world is
    /// as before it, and the error names the body or particle, the stage and
    /// the time.
    pub fn step_guarded(&mut self, guard: &mut Guard, n: u64, interrupted: &mut dyn FnMut() -> bool) -> Result<u64> {
        self.check_inputs()?;
        guard.begin(self);
        self.prepare();
        let src = self.kick_sources();
        let mut done = 0;
        while done < n {
            if done > 0 && interrupted() {
                break;
            }
            let failure = match catch_unwind(AssertUnwindSafe(|| self.one_step(&src))) {
                Err(p) => Some(Failure::Panic(panic_message(p.as_ref()))),
                Ok(()) if !self.state_finite() => Some(Failure::NotFinite),
                Ok(()) => None,
            };
            if let Some(f) = failure {
                self.profile.count_steps(done);
                return Err(self.undo(guard, f));
            }
            done += 1;
            guard.stepped(self);
        }
        self.profile.count_steps(done);
        self.finish();
        guard.end(self);
        Ok(done)
    }

    /// Puts the world back before the failed step and says what failed.
    fn undo(&mut self, guard: &mut Guard, failure: Failure) -> Error {
        let back = guard.roll_back(self);
        let t = self.time();
        let (stage, what) = if back { self.diagnose() } else { ("?", String::new()) };
        let head = match &failure {
            Failure::NotFinite => format!("the step from t = {t:.6} s diverged in stage '{stage}': {what}"),
            Failure::Panic(m) => format!(
                "internal error in stage '{stage}' of the step from t = {t:.6} s (a bug in rigidrs: please report \
                 it): {m}"
            ),
        };
        let tail = if back {
            format!("the world is back at t = {t:.6} s, as before that step, and can step on")
        } else {
            format!("the world could not be replayed to that step and is back at its last checkpoint, t = {t:.6} s")
        };
        let hint = match failure {
            Failure::NotFinite => " (a smaller dt, more substeps or a stable integrator such as strang or implicit_gyro avoids it)",
            Failure::Panic(_) => "",
        };
        Error::simulation(format!("{head}; {tail}{hint}"))
    }

    /// Runs the failed step again on a copy, watched: the stage that failed
    /// and the body or particle it left not finite.
    fn diagnose(&self) -> (&'static str, String) {
        let mut probe = self.clone();
        probe.watch = Some(Watch::default());
        probe.profile.enabled = false;
        let src = probe.kick_sources();
        let panicked = catch_unwind(AssertUnwindSafe(|| probe.one_step(&src))).is_err();
        let watch = probe.watch.take().unwrap_or_default();
        match watch.first_bad {
            Some((stage, what)) if !panicked => (stage, what),
            _ => (watch.current, String::new()),
        }
    }
}
