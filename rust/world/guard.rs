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
//! bitwise compare and copy of the view-writable arrays the user was handed a
//! writable view of; per step: one pass of sums over positions and velocities
//! (as the old end-of-call check); per checkpoint (every 1024 steps, 256
//! logged calls or 64 MB of log, or after a change the log cannot hold, such
//! as a restore): one copy of the world, into the last checkpoint's arrays
//! (see `crate::clone_in_place`: a million free boxes, 0.75 s a checkpoint
//! against 3.8 s for a fresh clone). Measured with callgrind over 300
//! `step(1)` calls: +0.06 % on the 210-box pyramid, +0.10 % on 1000 free bodies.

use std::panic::{catch_unwind, AssertUnwindSafe};
use std::sync::atomic::{AtomicU16, Ordering};

pub use super::inputs::exposed;
use super::inputs::Inputs;
use super::runaway::{Budget, Runaway, CHECK_EVERY, RUNAWAY_FACTOR};
use super::{validate, World};
use crate::error::{Error, Result};
use crate::integrate::kick::KickSources;

/// A checkpoint costs one clone of the world (up to most of a step's time
/// for a contact scene), a failure a replay of up to this many steps.
const CHECKPOINT_STEPS: u64 = 1024;
const CHECKPOINT_CALLS: usize = 256;
const CHECKPOINT_LOG_BYTES: usize = 64 << 20;

/// What the watched re-run of a failed step saw: the stage running, and the
/// first stage after which the state was not finite, with what was not.
#[derive(Clone, Debug, Default)]
pub struct Watch {
    pub current: &'static str,
    pub first_bad: Option<(&'static str, String)>,
    /// Re-running a runaway: the energy budget before the step (a stage that
    /// ends over it is the culprit).
    pub budget: Option<Budget>,
    /// Per body: its largest velocity component at the step start (m/s).
    pub start_speed: Vec<f64>,
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
    /// The view-writable arrays the user may have written (`exposed` bits).
    exposed: AtomicU16,
    /// Checkpoints only at the start of a call, never between two of its
    /// steps (a batch: any copy can then be rewound to any step of the call).
    calls_only: bool,
    /// The energy the scene can explain (`runaway`).
    budget: Budget,
}

impl Guard {
    /// The world was changed other than through its views (restored, posed):
    /// the next call starts from a new checkpoint.
    pub fn invalidate(&mut self) {
        self.stale = true;
    }

    /// A writable view of the arrays of `bits` was handed out (or they were
    /// changed through a method): from now on they are compared and logged.
    pub fn expose(&self, bits: u16) {
        self.exposed.fetch_or(bits, Ordering::Relaxed);
    }

    /// The `exposed` bits: the arrays the user holds writable views of.
    pub fn exposed_bits(&self) -> u16 {
        self.exposed.load(Ordering::Relaxed)
    }

    /// A guard that takes checkpoints only at the start of a call: a failure
    /// late in a long call replays more, but [`Guard::rewind`] reaches every
    /// step of the current call.
    pub fn at_calls_only() -> Self {
        Self { calls_only: true, ..Self::default() }
    }

    fn due(&self) -> bool {
        self.steps >= CHECKPOINT_STEPS || self.calls.len() >= CHECKPOINT_CALLS || self.log_bytes >= CHECKPOINT_LOG_BYTES
    }

    fn checkpoint(&mut self, w: &World, prepare: bool) {
        // Into the last checkpoint's buffers (see `crate::clone_in_place`).
        match &mut self.checkpoint {
            Some(cp) => cp.as_mut().clone_from(w),
            None => self.checkpoint = Some(Box::new(w.clone())),
        }
        self.calls.clear();
        self.calls.push(Call { inputs: None, prepare, steps: 0 });
        self.steps = 0;
        self.log_bytes = 0;
    }

    /// At the start of a call, before `prepare`. Fails (logging nothing) when
    /// the energy check that a checkpoint due now needs first fails.
    fn begin(&mut self, w: &mut World) -> std::result::Result<(), Runaway> {
        let fresh = self.stale || self.checkpoint.is_none();
        let mask = self.exposed.load(Ordering::Relaxed);
        let written = !fresh && !self.last.same_as(w, mask);
        if fresh {
            self.budget.reset(w);
        } else if written && !self.last.same_in(w, mask & exposed::STATE) {
            self.budget.written(w);
        } else if self.due() {
            // The steps since the last check must pass before a checkpoint
            // covers them (a failed one is found by replaying from the last).
            self.budget.check(w)?;
        }
        if fresh || self.due() {
            self.stale = false;
            self.checkpoint(w, true);
            return Ok(());
        }
        let inputs = written.then(|| {
            let mut i = Inputs::default();
            i.read(w, mask);
            self.log_bytes += i.bytes();
            i
        });
        self.calls.push(Call { inputs, prepare: true, steps: 0 });
        Ok(())
    }

    /// The current call's `prepare` failed: a replay must not run it.
    fn unprepared(&mut self) {
        if let Some(c) = self.calls.last_mut() {
            c.prepare = false;
        }
    }

    /// After a step that left the world finite: logs it, checks the energy
    /// when due (always before a checkpoint), takes the checkpoint when due.
    fn stepped(&mut self, w: &World, src: &KickSources) -> std::result::Result<(), Runaway> {
        if let Some(c) = self.calls.last_mut() {
            c.steps += 1;
        }
        self.steps += 1;
        let checkpoint = self.steps >= CHECKPOINT_STEPS && !self.calls_only;
        if self.budget.stepped(w, src) || checkpoint {
            self.budget.check(w)?;
        }
        if checkpoint {
            self.checkpoint(w, false);
        }
        Ok(())
    }

    /// After a failed energy check: replays from the checkpoint to the last
    /// check that passed (at step `from`), then step by step, checking each,
    /// and leaves `w` before the first step over budget. Returns the budget
    /// before that step, what it broke and whether the state at `from` (which
    /// no check saw: the start of the call) was already over budget; `None`
    /// (and `w` untouched) when the replay cannot be done or finds no such step.
    fn runaway_step(&mut self, w: &mut World, from: u64) -> Option<(Budget, Runaway, bool)> {
        let cp = self.checkpoint.as_deref()?;
        if cp.steps > from {
            return None;
        }
        let mut probe = cp.clone();
        let mut budget = self.budget.at_last_check();
        let mut found: Option<(World, Budget, Runaway, bool)> = None;
        let replayed = catch_unwind(AssertUnwindSafe(|| {
            'calls: for c in &mut self.calls {
                if let Some(i) = &mut c.inputs {
                    i.write(&mut probe);
                }
                if c.prepare {
                    probe.prepare();
                }
                let src = probe.kick_sources();
                for _ in 0..c.steps {
                    if probe.steps < from {
                        probe.one_step(&src);
                        continue;
                    }
                    let before = (probe.clone(), budget.clone());
                    if probe.steps == from {
                        if let Some(r) = budget.over(&probe) {
                            found = Some((before.0, before.1, r, true));
                            break 'calls;
                        }
                    }
                    probe.one_step(&src);
                    budget.stepped(&probe, &src);
                    if let Err(r) = budget.check(&probe) {
                        found = Some((before.0, before.1, r, false));
                        break 'calls;
                    }
                }
                probe.finish();
            }
        }));
        let (before, budget, r, already) = found.filter(|_| replayed.is_ok())?;
        w.restore(&before).ok()?;
        self.stale = true;
        Some((budget, r, already))
    }

    fn end(&mut self, w: &mut World) {
        self.last.read(w, self.exposed.load(Ordering::Relaxed));
    }

    /// Puts `w` back to the checkpoint (a runaway whose step the replay did
    /// not find). Always false: `w` is not before the failed step.
    fn back_to_checkpoint(&mut self, w: &mut World) -> bool {
        if let Some(cp) = self.checkpoint.as_deref() {
            let _ = w.restore(cp);
        }
        self.stale = true;
        false
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
            for c in &mut self.calls {
                if let Some(i) = &mut c.inputs {
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
        if replayed.is_err() {
            // Cannot happen for a deterministic step; if it does, the
            // checkpoint is still a consistent state.
            let _ = w.restore(cp);
            return false;
        }
        true
    }
}

impl Guard {
    /// Puts `w` back to the state it had after `target` steps (its step count),
    /// by the checkpoint and a replay of the log, as `roll_back` does but
    /// stopping there: what a batch does to the copies that went on past the
    /// step at which another copy failed. False (and `w` untouched) when the
    /// checkpoint is later than `target` or `w` is not past it.
    pub fn rewind(&mut self, w: &mut World, target: u64) -> bool {
        let Some(cp) = self.checkpoint.as_deref() else { return false };
        if cp.steps > target || w.steps < target {
            return false;
        }
        if w.steps == target {
            return true;
        }
        let mut probe = cp.clone();
        let replayed = catch_unwind(AssertUnwindSafe(|| {
            for c in &mut self.calls {
                // A call starting at `target` still counts for what the user
                // wrote before it (its steps are the ones undone).
                if probe.steps > target || (probe.steps == target && c.inputs.is_none()) {
                    break;
                }
                if let Some(i) = &mut c.inputs {
                    i.write(&mut probe);
                }
                if c.prepare {
                    probe.prepare();
                }
                let src = probe.kick_sources();
                let k = c.steps.min(target - probe.steps);
                for _ in 0..k {
                    probe.one_step(&src);
                }
                probe.finish();
            }
        }));
        if replayed.is_err() || probe.steps != target || w.restore(&probe).is_err() {
            return false;
        }
        self.stale = true;
        true
    }
}

/// Why a step failed.
enum Failure {
    NotFinite,
    /// Found by the energy check of a step of this call (which started at
    /// the step count given): undone to before the first step of the call
    /// over budget.
    Runaway(Runaway, u64),
    /// Found before the call's first step (unchecked steps of the calls
    /// before): nothing to undo.
    RunawayBefore(Runaway),
    Panic(String),
}

fn panic_message(p: &(dyn std::any::Any + Send)) -> String {
    p.downcast_ref::<&str>().map(|s| s.to_string()).or_else(|| p.downcast_ref::<String>().cloned()).unwrap_or_default()
}

impl World {
    /// Whether every body and particle position, velocity and orientation is
    /// finite (one pass of sums).
    pub(crate) fn state_finite(&self) -> bool {
        validate::all_finite(&self.bodies) && self.particles().is_none_or(|p| validate::finite3s(&[&p.position, &p.velocity]))
    }

    /// After a stage of a watched step: the first stage that left the state
    /// not finite.
    pub(crate) fn watch_after(&mut self, stage: &'static str) {
        let Some(watch) = self.watch.as_ref() else { return };
        if watch.first_bad.is_some() {
            return;
        }
        if !self.state_finite() {
            let what = self.culprit();
            if let Some(w) = self.watch.as_mut() {
                w.first_bad = Some((stage, what));
            }
            return;
        }
        let over = watch.budget.as_ref().is_some_and(|b| {
            let e = self.energy();
            e.kinetic > b.bound(e.potential)
        });
        if over {
            let what = self.fastest();
            if let Some(w) = self.watch.as_mut() {
                w.first_bad = Some((stage, what));
            }
        }
    }

    /// The body or particle that is not finite, in words, and how many more
    /// are (a NaN spreads through contacts and constraints within a stage).
    fn culprit(&self) -> String {
        let b = &self.bodies;
        let bad3 = |v: &[f64; 3]| !v.iter().all(|x| x.is_finite());
        let bodies: Vec<usize> = (0..b.len())
            .filter(|&i| {
                bad3(&b.position[i]) || bad3(&b.linear_velocity[i]) || bad3(&b.angular_velocity[i])
                    || !b.orientation[i].iter().all(|x| x.is_finite())
            })
            .collect();
        let particles: Vec<usize> = self.particles().map_or(Vec::new(), |p| {
            (0..p.len()).filter(|&i| bad3(&p.position[i]) || bad3(&p.velocity[i])).collect()
        });
        // A NaN spreads through contacts within a stage: of the bodies it
        // reached, the one that was fastest at the step start is the one that
        // ran away (the lowest-numbered was named before, a neighbour it hit).
        let start = self.watch.as_ref().map_or(&[][..], |w| &w.start_speed[..]);
        let runaway = bodies.iter().copied().max_by(|&i, &j| {
            let (a, b) = (start.get(i).copied().unwrap_or(0.0), start.get(j).copied().unwrap_or(0.0));
            a.total_cmp(&b).then(j.cmp(&i))
        });
        let first = runaway
            .and_then(|i| validate::check_body(&self.bodies, i).err())
            .or_else(|| validate::check(&self.bodies).err())
            .or_else(|| self.check_particles().err())
            .map_or_else(|| "no body or particle".to_string(), |e| e.message);
        let list = |what: &str, v: &[usize]| {
            let shown: Vec<String> = v.iter().take(8).map(|i| i.to_string()).collect();
            let more = if v.len() > 8 { format!(" and {} more", v.len() - 8) } else { String::new() };
            format!("{what} {}{more}", shown.join(", "))
        };
        let mut all = Vec::new();
        if !bodies.is_empty() {
            all.push(list("bodies", &bodies));
        }
        if !particles.is_empty() {
            all.push(list("particles", &particles));
        }
        if bodies.len() + particles.len() > 1 {
            format!("{first} (not finite: {})", all.join("; "))
        } else {
            first
        }
    }

    /// Advances up to `n` steps as `step` does, calling `interrupted` between
    /// two steps (true: stop there). Returns the steps taken. A step that
    /// leaves the state not finite, or fails inside, is undone: the world is
    /// as before it, and the error names the body or particle, the stage and
    /// the time.
    pub fn step_guarded(&mut self, guard: &mut Guard, n: u64, interrupted: &mut dyn FnMut() -> bool) -> Result<u64> {
        self.check_inputs()?;
        if let Err(r) = guard.begin(self) {
            return Err(self.undo(guard, Failure::RunawayBefore(r)));
        }
        let start = self.steps;
        let src = match catch_unwind(AssertUnwindSafe(|| self.prepare())) {
            Ok(src) => src,
            Err(p) => {
                // Undone as a failed step, but to the start of this call.
                guard.unprepared();
                let back = guard.roll_back(self);
                let t = self.time();
                let place = if back { "as at the start of this call" } else { "at its last checkpoint" };
                return Err(Error::simulation(format!(
                    "internal error while preparing the step from t = {t:.6} s (a bug in rigidrs: please report it): \
                     {}; the world is back at t = {t:.6} s, {place}",
                    panic_message(p.as_ref())
                )));
            }
        };
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
            if let Err(r) = guard.stepped(self, &src) {
                self.profile.count_steps(done);
                return Err(self.undo(guard, Failure::Runaway(r, start)));
            }
        }
        self.profile.count_steps(done);
        self.finish();
        guard.end(self);
        Ok(done)
    }

    /// Puts the world back before the failed step and says what failed.
    fn undo(&mut self, guard: &mut Guard, failure: Failure) -> Error {
        let (back, budget, failure) = match failure {
            Failure::Runaway(r, start) => {
                // Never before the call: the calls before it returned.
                let from = (self.steps - guard.budget.pending() as u64).max(start);
                match guard.runaway_step(self, from) {
                    Some((_, r, true)) => return self.undo(guard, Failure::RunawayBefore(r)),
                    Some((b, r, false)) => (true, Some(b), Failure::Runaway(r, start)),
                    None => (guard.back_to_checkpoint(self), None, Failure::Runaway(r, start)),
                }
            }
            Failure::RunawayBefore(r) => {
                guard.invalidate();
                let t = self.time();
                return Error::simulation(format!(
                    "the world ran away before t = {t:.6} s, over the last steps of the calls before this one (the energy \
                     is checked every {CHECK_EVERY} steps): {}; it holds {:.4e} J of kinetic energy, over {RUNAWAY_FACTOR} times the {:.4e} J that the energy at the \
                     last reset, gravity, applied forces, drives, kinematic bodies and contact push-out can explain; \
                     the world is as at the start of this call (the next call starts a new energy budget; a smaller dt, more substeps or a \
                     stable integrator such as strang or implicit_gyro avoids it)",
                    self.fastest(),
                    r.kinetic,
                    r.bound / RUNAWAY_FACTOR
                ));
            }
            f => (guard.roll_back(self), None, f),
        };
        let t = self.time();
        let (stage, what) = if back { self.diagnose(budget) } else { ("?", String::new()) };
        let head = match &failure {
            Failure::NotFinite => format!("the step from t = {t:.6} s diverged in stage '{stage}': {what}"),
            Failure::Runaway(r, _) => format!(
                "the step from t = {t:.6} s ran away in stage '{stage}': {what}; it ended with {:.4e} J of kinetic \
                 energy, over {RUNAWAY_FACTOR} times the {:.4e} J that the energy at the last reset, gravity, applied \
                 forces, drives, kinematic bodies and contact push-out can explain",
                r.kinetic,
                r.bound / RUNAWAY_FACTOR
            ),
            Failure::RunawayBefore(_) => String::new(), // returned above
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
            Failure::NotFinite | Failure::Runaway(..) | Failure::RunawayBefore(_) => " (a smaller dt, more substeps or a stable integrator such as strang or implicit_gyro avoids it)",
            Failure::Panic(_) => "",
        };
        Error::simulation(format!("{head}; {tail}{hint}"))
    }

    /// Runs the failed step again on a copy, watched: the stage that failed
    /// and the body or particle it left not finite.
    fn diagnose(&self, budget: Option<Budget>) -> (&'static str, String) {
        let mut probe = self.clone();
        // Largest component, not the norm: a runaway's norm overflows.
        let speed = |v: &[f64; 3]| v.iter().fold(0.0f64, |a, x| a.max(x.abs()));
        let start_speed = probe.bodies.linear_velocity.iter().map(speed).collect();
        probe.watch = Some(Watch { budget, start_speed, ..Watch::default() });
        probe.profile.enabled = false;
        let src = probe.kick_sources();
        let panicked = catch_unwind(AssertUnwindSafe(|| probe.one_step(&src))).is_err();
        let watch = probe.watch.take().unwrap_or_default();
        match watch.first_bad {
            Some((stage, what)) if !panicked => (stage, what),
            _ if panicked => (watch.current, String::new()),
            _ => ("unknown (it did not fail when run again)", String::new()),
        }
    }
}

#[cfg(test)]
#[path = "guard_tests.rs"]
mod tests;
