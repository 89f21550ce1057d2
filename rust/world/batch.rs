//! A batch: B worlds of one layout stepped together, each on one thread of a
//! pool, each bitwise the world it would be stepped alone (a world's step reads
//! nothing outside itself). Per-copy parameters change a copy's scene, and the
//! copy is built again from it.

use std::sync::atomic::{AtomicBool, Ordering};

use rayon::prelude::*;

use super::guard::{exposed, Guard};
use super::{threads, Scene, Settings, World};
use crate::collide::Material;
use crate::error::{finite3, Error, Result};

pub struct Batch {
    /// Per copy: the scene it was built from, with its parameters.
    pub scenes: Vec<Scene>,
    pub settings: Settings,
    pub worlds: Vec<World>,
    pub guards: Vec<Guard>,
}

/// Bodies, joints and particles of a scene.
fn layout(s: &Scene) -> [(usize, &'static str); 3] {
    [(s.bodies().len(), "bodies"), (s.joints().len(), "joints"), (s.xpbd.particles.len(), "particles")]
}

/// Per-copy parameters `Batch::set` knows, with what one value is.
pub const PARAMETERS: [(&str, &str); 6] = [
    ("friction", "dynamic and static friction coefficient (–), per copy (B,) or per body (B, N)"),
    ("static_friction", "static friction coefficient (–), at least the dynamic one, (B,) or (B, N)"),
    ("restitution", "coefficient of restitution (–), (B,) or (B, N)"),
    ("gravity", "gravitational acceleration (m/s², world), (B, 3)"),
    ("mass", "mass (kg) of each dynamic body, inertia scaled with it, (B,) or (B, N)"),
    ("mass_scale", "factor on each dynamic body's mass and inertia (–), (B,) or (B, N)"),
];

impl Batch {
    /// Builds one world per scene; the scenes must have equal numbers of
    /// bodies, joints and particles (the first difference is named).
    pub fn new(scenes: Vec<Scene>, settings: Settings) -> Result<Self> {
        let Some(first) = scenes.first() else {
            return Err(Error::input("a batch needs at least one copy (copies >= 1 or a non-empty list of scenes)"));
        };
        for (i, s) in scenes.iter().enumerate().skip(1) {
            for ((n0, what), (n, _)) in layout(first).into_iter().zip(layout(s)) {
                if n != n0 {
                    return Err(Error::input(format!(
                        "scene {i} has {n} {what}, scene 0 has {n0}: a batch needs scenes of equal layout"
                    )));
                }
            }
        }
        settings.validate()?;
        let worlds = build_all(&scenes, &settings)?;
        let guards = worlds.iter().map(|_| new_guard()).collect();
        Ok(Self { scenes, settings, worlds, guards })
    }

    /// B copies of one world (clones: bitwise the world `scene.build` makes).
    pub fn copies(scene: Scene, world: World, copies: usize) -> Result<Self> {
        if copies == 0 {
            return Err(Error::input("copies must be at least 1, got 0"));
        }
        let settings = world.settings().clone();
        Ok(Self {
            scenes: vec![scene; copies],
            settings,
            worlds: vec![world; copies],
            guards: (0..copies).map(|_| new_guard()).collect(),
        })
    }

    pub fn len(&self) -> usize {
        self.worlds.len()
    }

    pub fn is_empty(&self) -> bool {
        self.worlds.is_empty()
    }

    /// Bodies per copy.
    pub fn bodies(&self) -> usize {
        self.worlds.first().map_or(0, |w| w.bodies.len())
    }

    /// The pool size: the settings' `threads`, all cores by default.
    pub fn threads(&self) -> usize {
        threads::resolve(self.settings.threads)
    }

    /// Refuses a state no step can take, naming the copy; nothing moves.
    pub fn check_inputs(&self) -> Result<()> {
        for (i, w) in self.worlds.iter().enumerate() {
            w.check_inputs().map_err(|e| e.context(format!("copy {i}")))?;
        }
        Ok(())
    }

    /// Steps every copy `n` steps in parallel, each copy one `step_guarded`
    /// call on one thread (its state stays in that core's cache for all its
    /// steps). `stop` (set by the caller on Ctrl-C, or here when a copy fails)
    /// makes every copy stop at its next step boundary; the copies are then
    /// brought to one step count: the furthest after a stop, the step before
    /// the earliest failure after a failure (copies past it are rewound by
    /// their guards, those short of it step on). The error names the copy.
    pub fn step(&mut self, n: u64, stop: &AtomicBool) -> Result<()> {
        let start = self.worlds.first().map_or(0, |w| w.steps);
        let results: Vec<Result<u64>> = threads::install(self.threads(), || {
            self.worlds
                .par_iter_mut()
                .zip(self.guards.par_iter_mut())
                .with_max_len(1)
                .map(|(w, g)| {
                    let r = w.step_guarded(g, n, &mut || stop.load(Ordering::Relaxed));
                    if r.is_err() {
                        stop.store(true, Ordering::Relaxed);
                    }
                    r
                })
                .collect()
        });
        let mut failed: Option<(u64, usize, Error)> = None;
        for (i, r) in results.into_iter().enumerate() {
            if let Err(e) = r {
                let at = self.worlds[i].steps;
                if failed.as_ref().is_none_or(|(t, _, _)| at < *t) {
                    failed = Some((at, i, e));
                }
            }
        }
        let Some((mut target, mut copy, mut err)) = failed else {
            let furthest = self.worlds.iter().map(|w| w.steps).max().unwrap_or(start);
            return match self.align(furthest) {
                Ok(_) => Ok(()),
                Err((_, i, e)) => self.failed(i, e, start),
            };
        };
        // Copies short of the failing step step on to it; one may fail earlier.
        loop {
            match self.align(target) {
                Ok(stuck) => return Err(self.report(copy, err, target, start, &stuck)),
                Err((at, i, e)) => (target, copy, err) = (at, i, e),
            }
        }
    }

    /// Brings every copy to `target` steps: those past it rewound (the copies
    /// that cannot be are returned), those short of it stepped on (the first
    /// that fails on the way is returned, at its step count).
    fn align(&mut self, target: u64) -> std::result::Result<Vec<usize>, (u64, usize, Error)> {
        let results: Vec<std::result::Result<bool, Error>> = threads::install(self.threads(), || {
            self.worlds
                .par_iter_mut()
                .zip(self.guards.par_iter_mut())
                .with_max_len(1)
                .map(|(w, g)| match w.steps.cmp(&target) {
                    std::cmp::Ordering::Greater => Ok(g.rewind(w, target)),
                    std::cmp::Ordering::Less => w.step_guarded(g, target - w.steps, &mut || false).map(|_| true),
                    std::cmp::Ordering::Equal => Ok(true),
                })
                .collect()
        });
        let mut stuck = Vec::new();
        let mut first: Option<(u64, usize, Error)> = None;
        for (i, r) in results.into_iter().enumerate() {
            match r {
                Ok(true) => {}
                Ok(false) => stuck.push(i),
                Err(e) => {
                    let at = self.worlds[i].steps;
                    if first.as_ref().is_none_or(|(t, _, _)| at < *t) {
                        first = Some((at, i, e));
                    }
                }
            }
        }
        first.map_or(Ok(stuck), Err)
    }

    /// A copy failed while the others were brought to a stop: align on it.
    fn failed(&mut self, copy: usize, err: Error, start: u64) -> Result<()> {
        let (mut target, mut copy, mut err) = (self.worlds[copy].steps, copy, err);
        loop {
            match self.align(target) {
                Ok(stuck) => return Err(self.report(copy, err, target, start, &stuck)),
                Err((at, i, e)) => (target, copy, err) = (at, i, e),
            }
        }
    }

    fn report(&self, copy: usize, err: Error, target: u64, start: u64, stuck: &[usize]) -> Error {
        let dt = self.settings.dt;
        let tail = if stuck.is_empty() {
            format!("every copy of the batch is back at t = {:.6} s", target as f64 * dt)
        } else {
            format!(
                "the other copies are back at t = {:.6} s but for copies {stuck:?}, which could not be \
                 replayed to it (they are at their own last step; the batch started this call at t = {:.6} s)",
                target as f64 * dt,
                start as f64 * dt
            )
        };
        Error { message: format!("copy {copy}: {}; {tail}", err.message), ..err }
    }

    /// Sets a per-copy parameter (see [`PARAMETERS`]) from `values`, B rows of
    /// `width` numbers each (`width` 1 for one per copy, N for one per body, 3
    /// for gravity). Every copy is built again from its changed scene, keeping
    /// the state written into its world (`keep`); on an error nothing changes.
    pub fn set(&mut self, name: &str, values: &[f64], width: usize, keep: &dyn Fn(usize, &mut World)) -> Result<()> {
        if !PARAMETERS.iter().any(|(known, _)| *known == name) {
            return Err(unknown(name));
        }
        let (b, n) = (self.len(), self.bodies());
        if values.len() != b * width {
            return Err(Error::input(format!("{name}: {} values for {b} copies of {width}", values.len())));
        }
        let mut scenes = self.scenes.clone();
        for (c, scene) in scenes.iter_mut().enumerate() {
            let row = &values[c * width..(c + 1) * width];
            apply(scene, name, row, n).map_err(|e| e.context(format!("{name}, copy {c}")))?;
        }
        let mut worlds = build_all(&scenes, &self.settings)?;
        for (c, (w, old)) in worlds.iter_mut().zip(&self.worlds).enumerate() {
            w.steps = old.steps;
            keep(c, w);
        }
        self.scenes = scenes;
        self.worlds = worlds;
        self.guards = self.worlds.iter().map(|_| new_guard()).collect();
        Ok(())
    }
}

/// A guard that compares and logs the four arrays the batch's views write,
/// with checkpoints at call starts only (so that every copy can be rewound).
fn new_guard() -> Guard {
    let g = Guard::at_calls_only();
    g.expose(exposed::POSITION | exposed::ORIENTATION | exposed::LINEAR_VELOCITY | exposed::ANGULAR_VELOCITY);
    g
}

fn build_all(scenes: &[Scene], settings: &Settings) -> Result<Vec<World>> {
    let n = threads::resolve(settings.threads);
    threads::install(n, || {
        scenes
            .par_iter()
            .enumerate()
            .map(|(i, s)| s.build(settings).map_err(|e| e.context(format!("copy {i}"))))
            .collect()
    })
}

/// Writes one copy's `row` of parameter `name` into `scene` (`n` bodies).
fn apply(scene: &mut Scene, name: &str, row: &[f64], n: usize) -> Result<()> {
    if name == "gravity" {
        let g = finite3("gravity", [row[0], row[1], row[2]])?;
        scene.gravity = g;
        return Ok(());
    }
    let value = |i: usize| if row.len() == 1 { row[0] } else { row[i] };
    for (i, body) in scene.bodies_mut().iter_mut().enumerate().take(n) {
        let x = value(i);
        let m = &body.material;
        let here = |e: Error| e.context(format!("body {i}"));
        match name {
            "friction" => body.material = Material::new(x, Some(x), m.restitution).map_err(here)?,
            "static_friction" => body.material = Material::new(m.friction, Some(x), m.restitution).map_err(here)?,
            "restitution" => body.material = Material::new(m.friction, Some(m.static_friction), x).map_err(here)?,
            "mass" | "mass_scale" => {
                if body.init.kind != crate::body::BodyKind::Dynamic {
                    continue; // fixed and kinematic bodies have no mass to set
                }
                let scale = if name == "mass" { x / body.init.mass } else { x };
                if !(x.is_finite() && x > 0.0) {
                    return Err(here(Error::input(format!("{name} must be positive and finite, got {x}"))));
                }
                body.init.mass *= scale;
                body.init.inertia = body.init.inertia.map(|v| v * scale);
            }
            _ => return Err(unknown(name)),
        }
    }
    Ok(())
}

/// The error for a name `set` does not know, listing those it does.
pub fn unknown(name: &str) -> Error {
    let known: Vec<String> = PARAMETERS.iter().map(|(n, what)| format!("{n}: {what}")).collect();
    Error::input(format!("unknown batch parameter {name:?}; known: {}", known.join("; ")))
}
