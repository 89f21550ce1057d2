//! Stepping: the plan's stages run in order, each timed into the profile.

use std::time::Instant;

use super::pipeline::{Group, Stage, StageKind};
use super::{validate, World};
use crate::error::Result;
use crate::integrate::kick::KickSources;
use crate::integrate::fast_rotation::Substeps;
use crate::integrate::{
    drift, euler, fast_rotation, implicit_gyro, kick, parallel, rk4, symplectic_euler, Aniso, BodyLists, Gyroscopic,
    InertiaClass, Rotation,
};

use crate::body::Bodies;
use crate::math::{quat, Vec3};

impl World {
    /// Advances `n` steps. The state is checked first: if a body is invalid (NaN,
    /// non-unit quaternion written through a view) nothing moves and the error
    /// names the body. (`step_guarded` also undoes a step that fails.)
    pub fn step(&mut self, n: u64) -> Result<()> {
        self.check_inputs()?;
        let src = self.prepare();
        for _ in 0..n {
            self.one_step(&src);
        }
        self.profile.count_steps(n);
        self.finish();
        if validate::all_finite(&self.bodies) {
            return Ok(());
        }
        validate::check(&self.bodies).map_err(|e| {
            crate::error::Error::state(format!(
                "{} after stepping from t = {:.6} s to {:.6} s: the simulation blew up (a smaller dt, more \
                 substeps or a stable integrator such as strang or implicit_gyro avoids it)",
                e.message,
                self.time() - n as f64 * self.settings.dt,
                self.time()
            ))
        })
    }

    /// Refuses a state written through views that no step can take (NaN,
    /// non-unit quaternions), naming the body or particle; changes nothing.
    pub(crate) fn check_inputs(&self) -> Result<()> {
        validate::check(&self.bodies)?;
        self.check_particles()
    }

    /// What every `step` call does once before its steps: round-off out of
    /// written quaternions, sleepers given a velocity woken, the plan and drive
    /// targets brought up to date. Returns the force sources of its steps.
    pub(crate) fn prepare(&mut self) -> KickSources {
        validate::normalize(&mut self.bodies);
        #[cfg(test)]
        if self.fail_at == Some(u64::MAX) {
            self.fail_at = None; // once: the replay that undoes it prepares too
            panic!("injected failure in prepare");
        }
        self.wake_on_user_input();
        self.sync_targets();
        self.articulations.invalidate();
        // After every wake-up: the sources scan the awake bodies.
        let src = self.kick_sources();
        self.replan_for(&src, false);
        src
    }

    /// One step of `dt`: the plan's stages, substeps and all. A world whose
    /// last step had work enough to split runs the whole step on its pool, and
    /// only then splits its contact stages: the pool's threads, spinning a
    /// while after a parallel stage, would otherwise take a core from the
    /// calling thread (a 210-box pyramid whose narrow phase alone went to the
    /// pool stepped 30 % slower on two threads than on one).
    pub(crate) fn one_step(&mut self, src: &KickSources) {
        let threads = super::threads::resolve(self.settings.threads);
        let parallel = threads > 1 && self.worth_splitting();
        self.contact_threads = if parallel { threads } else { 1 };
        if parallel {
            super::threads::install(threads, || self.one_step_here(src));
        } else {
            self.one_step_here(src);
        }
    }

    /// Whether the last step had contact work enough to split over threads:
    /// support islands to sweep side by side (see `solve::island_sweeps`), or
    /// so many contact pairs (or pairs whose manifolds parry clips) that their
    /// narrow phase and constraints' build are worth the hand-offs.
    fn worth_splitting(&self) -> bool {
        use crate::collide::narrow_phase::{MIN_PARALLEL_MANIFOLD_PAIRS, MIN_PARALLEL_PAIRS};
        self.collision.as_ref().is_some_and(|c| {
            c.solver.islands_were_split() || c.solver.halves_were_split() || c.narrow.len() >= MIN_PARALLEL_PAIRS || c.narrow.manifold_pairs() >= MIN_PARALLEL_MANIFOLD_PAIRS
        })
    }

    fn one_step_here(&mut self, src: &KickSources) {
        // After a step whose contacts were split in halves (see
        // `solve::seams`) the whole step has a second thread at hand: the
        // narrow phase and the build share their pairs with it too.
        let team = self.contact_threads > 1 && self.collision.as_ref().is_some_and(|c| c.solver.split);
        crate::solve::team::with_team(team, || self.one_step_stages(src));
    }

    fn one_step_stages(&mut self, src: &KickSources) {
        let base = self.rocking_substeps();
        let h = self.settings.dt / base as f64;
        // Indexing, not iterating: a stage may rebuild the plan (bodies waking
        // in the narrow phase, falling asleep in the sleep stage).
        for k in 0..self.plan.pre.len() {
            self.timed(self.plan.pre[k], h, src);
        }
        let (substeps, h) = self.step_substeps(base, h);
        self.last_substeps = substeps;
        for _ in 0..substeps {
            for k in 0..self.plan.sub.len() {
                self.timed(self.plan.sub[k], h, src);
            }
        }
        if let Some(c) = self.collision.as_mut() {
            c.solver.finish(&mut c.narrow);
        }
        self.finish_link_contacts(substeps);
        for k in 0..self.plan.post.len() {
            self.timed(self.plan.post[k], h, src);
        }
        self.steps += 1;
    }

    /// The world's substeps, or more after a step in which a slow body rocked
    /// in a settling scene (see `solve::rocking`).
    fn rocking_substeps(&mut self) -> u32 {
        let (fixed, dt) = (self.settings.substeps.is_some(), self.settings.dt);
        let Some(c) = self.collision.as_mut() else { return self.substeps };
        // Whether every body is slow, looked at once (a pass over the bodies)
        // and only where it matters: support blocks, or rocking substeps held.
        let holding = c.solver.support.rocking.hold > 0;
        let slow = (!c.solver.support.blocks.is_empty() || holding) && c.solver.settling(&self.bodies);
        c.solver.note_settling(&self.bodies, slow);
        let settling = c.solver.support.rocking.seen && c.solver.settling_now;
        let in_motion = holding && !slow;
        c.solver.support.rocking.substeps(self.substeps, dt, fixed, settling, in_motion)
    }

    /// What every `step` call does once after its steps: the joint coordinates
    /// and the derived arrays the views show.
    pub(crate) fn finish(&mut self) {
        if !self.articulations.is_empty() || !self.joints.is_empty() {
            self.read_joints();
        }
        if self.keep_derived {
            self.bodies.update_derived();
        }
    }

    #[inline(always)]
    fn timed(&mut self, stage: Stage, h: f64, src: &KickSources) {
        // Rotation substeps run (and show in the profile) only when a body needs them.
        if matches!(stage.kind, StageKind::RotateFast(_)) && self.fast.is_empty() {
            return;
        }
        if let Some(w) = self.watch.as_mut() {
            w.current = stage.name();
        }
        #[cfg(test)]
        if self.fail_at == Some(self.steps) && matches!(stage.kind, StageKind::NarrowPhase) {
            panic!("injected failure");
        }
        if self.profile.enabled {
            let t0 = Instant::now();
            self.run(stage, h, src);
            self.profile.add(stage.slot, t0);
        } else {
            self.run(stage, h, src);
        }
        if self.watch.is_some() {
            self.watch_after(stage.name());
        }
    }

    fn run(&mut self, stage: Stage, h: f64, src: &KickSources) {
        let dt = self.settings.dt;
        let step = if stage.whole { dt } else { h };
        let hf = step * stage.frac;
        let threads = super::threads::resolve(self.settings.threads);
        let group = |g: Group| match g {
            Group::All => &self.lists,
            Group::Free => &self.split[0],
            Group::Touching => &self.split[1],
        };
        match stage.kind {
            StageKind::Forces(Group::Touching) => {
                kick::kick(&mut self.bodies, &self.split[1].dynamic, hf, src);
                remember_kick(&self.bodies, &self.split[1].dynamic, &mut self.kicked);
            }
            StageKind::Forces(g) => kick::kick(&mut self.bodies, &group(g).dynamic, hf, src),
            StageKind::Translate(Group::Touching) if src.any() && !self.kicked.is_empty() => {
                drift::translate_touching(&mut self.bodies, &self.split[1].dynamic, (hf, h), &self.kicked, src)
            }
            StageKind::Translate(g) => drift::translate(&mut self.bodies, &group(g).dynamic, hf),
            StageKind::Rotate(InertiaClass::Asymmetric, g, first) if self.rotation == Rotation::Free => {
                let l = group(g);
                if first {
                    // Which bodies turn too fast for one split per drift: decided once
                    // per step, so that each sits out exactly the drifts of this step.
                    let sub = Substeps::new(self.settings.rotation_angle(), step, &self.fast_weights);
                    self.fast.clear();
                    let (list, spread) = (&l.asymmetric, &l.asymmetric_inv_spread);
                    parallel::rotate_asymmetric(threads, &mut self.bodies, list, spread, hf, sub, &mut self.fast);
                    if !self.fast.is_empty() && self.fast_weights.len() > 1 {
                        slow_list(&l.asymmetric, &self.fast, &mut self.slow, &mut self.fast_mark);
                    }
                } else if self.fast.is_empty() {
                    parallel::rotate_asymmetric_unchecked(threads, &mut self.bodies, &l.asymmetric, hf);
                } else {
                    parallel::rotate_asymmetric_unchecked(threads, &mut self.bodies, &self.slow, hf);
                }
            }
            StageKind::Rotate(class, g, _) => rotate(&mut self.bodies, group(g), class, self.rotation, hf, threads),
            StageKind::RotateFast(_) => {
                // The whole step (the stage's fraction is 1) in rotation substeps.
                let sub = Substeps::new(self.settings.rotation_angle(), step, &self.fast_weights);
                fast_rotation::rotate_fast(&mut self.bodies, &self.fast, hf, sub);
            }
            StageKind::Rk4 { group: g, forces } => {
                let none = KickSources { gravity: Vec3::zeros(), force: false, torque: false };
                let sub = Substeps::new(self.settings.rotation_angle(), step, &[1.0]);
                rk4::step(&mut self.bodies, &group(g).dynamic, hf, if forces { src } else { &none }, sub);
            }
            StageKind::Gyroscopic(Gyroscopic::Explicit, g) => {
                symplectic_euler::gyroscopic_explicit(&mut self.bodies, &group(g).anisotropic_index, hf)
            }
            StageKind::Gyroscopic(Gyroscopic::Implicit, g) => {
                implicit_gyro::gyroscopic_implicit(&mut self.bodies, &group(g).anisotropic_index, hf)
            }
            StageKind::Kinematic => move_kinematic(&mut self.bodies, &self.kinematic, hf),
            StageKind::BroadPhase => {
                if let Some(c) = self.collision.as_mut() {
                    c.broad_phase(&self.bodies, dt);
                }
            }
            StageKind::NarrowPhase => self.narrow_phase(h),
            StageKind::Gather { relax } => {
                self.with_solver(|s, b| s.gather(b, relax));
                self.gather_links();
            }
            StageKind::Scatter { relax } => {
                self.with_solver(|s, b| {
                    s.scatter(b);
                    if relax {
                        s.write_poses(b)
                    }
                });
                self.scatter_links();
            }
            StageKind::Impacts => {
                if let Some(c) = self.collision.as_mut() {
                    c.solver.impacts(&mut self.bodies, h, src, &c.colliders);
                }
            }
            StageKind::WarmStart => self.with_solver(|s, _| {
                s.warm_start();
                s.warm_start_links();
            }),
            StageKind::Friction { relax } => {
                let planned = self.settings.iterations;
                self.with_solver(|s, _| {
                    s.solve_friction(relax);
                    // A pile's further iterations (see `solve::second_pass`),
                    // each as the planned Normal and Friction stages run it.
                    for _ in 0..s.extra_iterations(planned) {
                        normal_pass(s, relax, h);
                        s.solve_friction(relax);
                    }
                });
            }
            StageKind::Normal { relax } => self.with_solver(|s, _| normal_pass(s, relax, h)),
            StageKind::Ccd => {
                if let Some(c) = self.collision.as_mut() {
                    c.ccd_stage(&mut self.bodies);
                }
            }
            StageKind::Sleep => self.sleep(dt),
            StageKind::Joints => self.project_joints(h),
            StageKind::Articulation => self.step_articulations(),
            StageKind::ArticulationKick => self.articulation_kick(h),
            StageKind::ArticulationDrift => self.articulation_drift(h),
            StageKind::ParticlePredict | StageKind::ShapeMatching | StageKind::ParticleProject => {
                self.particle_stage(stage.kind, hf)
            }
        }
    }

    /// Whether a stage does something now: `RotateFast` only when a body of its
    /// group turns too fast for one split (for `stage_names`).
    pub(crate) fn stage_active(&self, stage: &Stage) -> bool {
        let StageKind::RotateFast(g) = stage.kind else { return true };
        let lists = match g {
            Group::All => &self.lists,
            Group::Free => &self.split[0],
            Group::Touching => &self.split[1],
        };
        let step = if stage.whole { self.settings.dt } else { self.settings.dt / self.substeps as f64 };
        let max_rate = Substeps::new(self.settings.rotation_angle(), step, &[]).max_rate;
        lists.asymmetric.iter().any(|a| fast_rotation::orbit_max_omega(&self.bodies, a) > max_rate)
    }

    fn with_solver(&mut self, f: impl FnOnce(&mut crate::solve::ContactSolver, &mut Bodies)) {
        if let Some(c) = self.collision.as_mut() {
            f(&mut c.solver, &mut self.bodies);
        }
    }

    /// Contacts of this step, then which awake bodies touch something.
    fn narrow_phase(&mut self, h: f64) {
        let threads = self.contact_threads.max(1);
        let step = super::collision::NarrowStep { dt: self.settings.dt, h, gravity: self.gravity, threads };
        let Some(c) = self.collision.as_mut() else { return };
        if c.narrow_phase(&mut self.bodies, &step) {
            self.relist();
        }
        self.mark_articulation_contacts();
        let Some(c) = self.collision.as_ref() else { return };
        if self.split_mask.as_ref() == Some(&c.solver.touching) {
            return;
        }
        let [free, touching] = &mut self.split;
        self.lists.partition(&c.solver.touching, free, touching);
        self.split_mask = Some(c.solver.touching.clone());
    }

    fn sleep(&mut self, dt: f64) {
        let Some(c) = self.collision.as_mut() else { return };
        if c.islands.update(&mut self.bodies, (&c.solver.constraints, &c.solver.patches), self.joints.pairs(), dt, &self.settings.sleep) {
            self.relist();
        }
    }

    /// Sleeping bodies given a velocity or a force by the user wake up.
    fn wake_on_user_input(&mut self) {
        let Some(c) = self.collision.as_mut() else { return };
        let b = &self.bodies;
        let poked: Vec<usize> = (0..b.len())
            .filter(|&i| {
                b.sleeping[i]
                    && (b.linear_velocity[i] != [0.0; 3]
                        || b.angular_velocity[i] != [0.0; 3]
                        || b.force[i] != [0.0; 3]
                        || b.torque[i] != [0.0; 3])
            })
            .collect();
        if poked.is_empty() {
            return;
        }
        for i in poked {
            c.islands.wake(&mut self.bodies, i);
        }
        self.relist();
    }
}

/// `list` without the bodies of `fast` (in order), into `slow`; `mark` is a
/// scratch array indexed by body, left all false.
fn slow_list(list: &[Aniso], fast: &[Aniso], slow: &mut Vec<Aniso>, mark: &mut Vec<bool>) {
    let end = fast.iter().map(|a| a.index as usize + 1).max().unwrap_or(0);
    if mark.len() < end {
        mark.resize(end, false);
    }
    fast.iter().for_each(|a| mark[a.index as usize] = true);
    slow.clear();
    slow.extend(list.iter().filter(|a| !mark.get(a.index as usize).copied().unwrap_or(false)));
    fast.iter().for_each(|a| mark[a.index as usize] = false);
}

/// Rotation of one class of bodies by the integrator's method (the exact
/// rotation of asymmetric bodies, with its rotation substeps, is in `run`).
/// The free rotations run over `threads` for large groups (`integrate::parallel`).
pub(crate) fn rotate(b: &mut Bodies, l: &BodyLists, class: InertiaClass, method: Rotation, h: f64, threads: usize) {
    use InertiaClass::*;
    match (method, class) {
        (Rotation::Free, Isotropic) => parallel::rotate_isotropic(threads, b, &l.isotropic, h),
        (Rotation::Free, Symmetric) => parallel::rotate_symmetric(threads, b, &l.symmetric, h),
        (Rotation::Free, Asymmetric) => parallel::rotate_asymmetric_unchecked(threads, b, &l.asymmetric, h),
        (Rotation::Euler, Isotropic) => euler::rotate_isotropic(b, &l.isotropic, h),
        (Rotation::Euler, c) => euler::rotate(b, l.indices(c), h),
        (Rotation::Exp, c) => symplectic_euler::rotate_exp(b, l.indices(c), h),
    }
}

/// Kinematic bodies: `p += h v`, `q ← exp(h ω) q`.
fn move_kinematic(b: &mut Bodies, list: &[u32], h: f64) {
    for &i in list {
        let i = i as usize;
        let v = Vec3::from(b.linear_velocity[i]);
        b.position[i] = (Vec3::from(b.position[i]) + h * v).into();
        let w = Vec3::from(b.angular_velocity[i]);
        if w != Vec3::zeros() {
            let q = quat::exp(&(w * h)) * b.q(i);
            b.orientation[i] = quat::to_xyzw(&(q / q.norm()));
        }
    }
}

/// What a `Normal` stage does: in a relax pass the positions first, then the
/// normals of the contacts and of the articulations' links.
fn normal_pass(s: &mut crate::solve::ContactSolver, relax: bool, h: f64) {
    if relax {
        s.correct_positions(h);
    }
    s.solve_normal(relax);
    s.solve_links(relax);
}

/// Records the velocities the kick gave the bodies of `list` (see
/// `drift::translate_touching`).
fn remember_kick(b: &crate::body::Bodies, list: &[u32], kicked: &mut Vec<[f64; 3]>) {
    kicked.resize(b.linear_velocity.len(), [f64::NAN; 3]);
    for &i in list {
        kicked[i as usize] = b.linear_velocity[i as usize];
    }
}
