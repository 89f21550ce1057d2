//! Islands and sleeping. Each step, dynamic bodies joined by contacts or joints form islands
//! (union–find); an island whose bodies have all stayed slower than the sleep
//! thresholds, and held by their friction (no patch sliding), for `time` goes to
//! sleep: its velocities are zeroed and it leaves
//! every stage until an awake body touches it, or the user gives one of its
//! bodies a velocity or a force.

use super::contact::Constraint;
use super::friction::Patch;
use crate::body::{BodyKind, Bodies};
use crate::math::Vec3;

/// Sleep parameters, with units and defaults.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct SleepSettings {
    /// Whether islands may sleep. Default true.
    pub enabled: bool,
    /// Speed below which a body counts as at rest (m/s). Default 0.05.
    pub linear: f64,
    /// Angular speed below which a body counts as at rest (rad/s). Default 0.05.
    pub angular: f64,
    /// Time an island must stay at rest before it sleeps (s). Default 0.5.
    pub time: f64,
}

impl Default for SleepSettings {
    fn default() -> Self {
        Self { enabled: true, linear: 0.05, angular: 0.05, time: 0.5 }
    }
}

#[derive(Clone, Debug, Default, serde::Serialize, serde::Deserialize)]
pub struct Islands {
    parent: Vec<u32>,
    /// Time each body has been at rest (s).
    pub rest_time: Vec<f64>,
    /// The island a sleeping body went to sleep with.
    pub island: Vec<u32>,
}

/// The root of `i` in a union–find forest, halving the path on the way.
pub(crate) fn find(parent: &mut [u32], mut i: u32) -> u32 {
    while parent[i as usize] != i {
        let p = parent[parent[i as usize] as usize];
        parent[i as usize] = p;
        i = p;
    }
    i
}

impl Islands {
    pub fn new(n: usize) -> Self {
        Self { parent: (0..n as u32).collect(), rest_time: vec![0.0; n], island: vec![u32::MAX; n] }
    }

    /// Ages the rest timers and puts islands at rest to sleep. Returns whether any
    /// body fell asleep.
    pub fn update(
        &mut self,
        b: &mut Bodies,
        contacts: (&[Constraint], &[Patch]),
        joints: &[(u32, u32)],
        dt: f64,
        s: &SleepSettings,
    ) -> bool {
        let (constraints, patches) = contacts;
        let n = b.len();
        // An island sleeps on its shortest rest time: with no awake body at
        // rest long enough, none can (the sliding patches below only shorten
        // rest times), and the islands need not be found (the union–find was
        // 7 % of a step of 2000 spinning boxes).
        let mut ripe = false;
        for i in 0..n {
            if !b.awake(i) {
                continue;
            }
            let v = Vec3::from(b.linear_velocity[i]).norm();
            let w = Vec3::from(b.angular_velocity[i]).norm();
            let forced = b.force[i] != [0.0; 3] || b.torque[i] != [0.0; 3];
            self.rest_time[i] = if v < s.linear && w < s.angular && !forced { self.rest_time[i] + dt } else { 0.0 };
            ripe |= self.rest_time[i] >= s.time;
        }
        if !ripe {
            return false;
        }
        // A body its friction cannot hold is not at rest, however slowly it
        // slides (a box just past its friction angle starts from nothing).
        for (c, f) in constraints.iter().zip(patches) {
            if f.sliding {
                self.rest_time[c.b1 as usize] = 0.0;
                self.rest_time[c.b2 as usize] = 0.0;
            }
        }
        for (i, p) in self.parent.iter_mut().enumerate().take(n) {
            *p = i as u32;
        }
        for (i, j) in constraints.iter().map(|c| (c.b1, c.b2)).chain(joints.iter().copied()) {
            if b.awake(i as usize) && b.awake(j as usize) {
                let (ri, rj) = (find(&mut self.parent, i), find(&mut self.parent, j));
                if ri != rj {
                    self.parent[ri as usize] = rj;
                }
            }
        }
        // The shortest rest time of each island decides for all of it.
        let mut island_rest = vec![f64::INFINITY; n];
        for i in 0..n {
            if b.awake(i) {
                let r = find(&mut self.parent, i as u32) as usize;
                island_rest[r] = island_rest[r].min(self.rest_time[i]);
            }
        }
        let mut any = false;
        for i in 0..n {
            if !b.awake(i) {
                continue;
            }
            let r = find(&mut self.parent, i as u32);
            if island_rest[r as usize] >= s.time {
                b.sleeping[i] = true;
                b.linear_velocity[i] = [0.0; 3];
                b.angular_velocity[i] = [0.0; 3];
                self.island[i] = r;
                any = true;
            }
        }
        any
    }

    /// Wakes every body of the island body `i` sleeps in. Returns whether any woke.
    pub fn wake(&mut self, b: &mut Bodies, i: usize) -> bool {
        if b.kind[i] != BodyKind::Dynamic || !b.sleeping[i] {
            return false;
        }
        let id = self.island[i];
        for k in 0..b.len() {
            if b.sleeping[k] && self.island[k] == id {
                b.sleeping[k] = false;
                self.rest_time[k] = 0.0;
                self.island[k] = u32::MAX;
            }
        }
        true
    }
}
