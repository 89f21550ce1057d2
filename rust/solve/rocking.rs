//! Rocking: more substeps for a step after one in which a slow body rocked on
//! its supports.
//!
//! The support sweeps ([`super::support`]) are exact while every block's body
//! is pinned on the bodies under it. A body that rocks (some points of a face
//! let go while others push) is not, and the sweeps over a column of such
//! bodies overshoot: at the default 4 substeps, columns of eight and ten cubes
//! resting 5 cm off each other's axis, kicked at 0.1 m/s, kept moving at up to
//! 0.2 and 5.6 m/s after 4 s and two of six toppled, though their kick was a
//! third of the energy that tips a cube (`tests/test_kicked_column.py`).
//! Repeating the sweeps, solving sliding blocks exactly and softer
//! Gauss–Seidel did not settle them; 16 substeps settled every one. So a step
//! takes substeps of at most [`ROCKING_SUBSTEP`] (16 at 60 Hz, 32 at 30 Hz,
//! none added from 240 Hz on at the default 4) while a slow body rocks, every
//! moving body slow too (the scene is settling), and for [`HOLD`] after. The
//! whole world takes them (substeps per island are not done). A scene in
//! motion keeps its substeps: with rocking alone as the sign, a tumbling
//! 4000-cube pile, where some slow cube always rocks, took 16 substeps
//! throughout (3.3× the time).

use super::block::{RowKind, Scratch};
use super::contact::ContactSolver;

/// Longest substep (s) while a slow body rocks: 1/960 s, 16 substeps at
/// 60 Hz. A length, not a count: 16 substeps at 1 kHz (62.5 µs each) left
/// kicked towers jittering at 1–9 cm/s for ever, 26 of 36 of them
/// (`examples/tower_matrix.rs`, with the Gauss–Seidel pass of
/// [`super::overshoot`]; 34 without), where the default 4 (250 µs) brings all
/// 36 to rest; at 30 Hz, 16 substeps (2.1 ms) stood 28 of 36 and 32 stood 35.
const ROCKING_SUBSTEP: f64 = 1.0 / 960.0;

/// Excess of `dt / ROCKING_SUBSTEP` over a whole number taken as round-off (a
/// thousandth of a substep): 1/60 s, or 0.0166667 s as a user writes it,
/// takes 16 substeps, not 17.
const COUNT_SLACK: f64 = 1e-3;

/// Fastest speed of a rocking body's points (in substeps of gravity, `g h`, h
/// the substep the step took: 0.65 m/s at 60 Hz and 4 substeps, 0.16 m/s
/// once at 16, so that the slower rocking must go on to keep them) for its
/// rocking to count, and of every moving body: a body
/// landing rocks too, at speed, and the landing's own treatment holds it
/// ([`super::support`]). The kicked columns rock at 0.1–0.3 m/s.
const SLOW: f64 = 16.0;

/// How long (s) the steps keep the rocking substeps after the last rocking seen: a
/// column that stops rocking for a step is not yet at rest.
const HOLD: f64 = 0.5;

/// Most doublings of the hold for a pile that rocks again as soon as it is
/// given back the world's substeps: 0.5 s × 2⁶, 32 s.
const MAX_RELAPSES: u32 = 6;

/// What the velocity passes of a step saw, and how many more steps take
/// the rocking substeps.
#[derive(Clone, Copy, serde::Serialize, serde::Deserialize)]
pub struct Rocking {
    pub seen: bool,
    pub hold: u32,
    /// Doublings of the next hold (see [`Rocking::substeps`]).
    pub relapses: u32,
    /// Steps since the substeps were last given back (`u32::MAX`: never).
    pub since: u32,
}

impl Default for Rocking {
    fn default() -> Self {
        Rocking { seen: false, hold: 0, relapses: 0, since: u32::MAX }
    }
}

impl Rocking {
    /// The contact substeps of the next step for `base` (the world's), `dt`
    /// (s); `fixed`: the user set the substeps, which stay as set.
    /// `settling`: every moving body is slow; `in_motion`: some body is fast.
    ///
    /// A pile that rocks again within a hold of being given back the world's
    /// substeps is held twice as long the next time: the drop itself jolts it.
    /// The soft step between two moving bodies is four times stiffer at the
    /// rocking substeps (a third of their rate), so each drop let the pile sag
    /// and each return lift it: pour 1 of `tests/test_pile_rest.py` dropped
    /// every 31 steps, and a cube on the floor under a leaning one walked
    /// 0.26 mm in 10 s, 32 µm at each drop, at |f|/N 0.04 (its neighbourhood
    /// cut out, 12 cubes between fixed ones). A scene in motion goes back to
    /// one hold.
    pub fn substeps(&mut self, base: u32, dt: f64, fixed: bool, settling: bool, in_motion: bool) -> u32 {
        let one = (HOLD / dt).ceil().clamp(1.0, u32::MAX as f64) as u32;
        if std::mem::take(&mut self.seen) && settling && !fixed {
            if self.hold == 0 {
                self.relapses = if self.since < one { (self.relapses + 1).min(MAX_RELAPSES) } else { 0 };
            }
            self.hold = one.saturating_mul(1 << self.relapses);
        }
        if in_motion {
            self.hold = self.hold.min(one);
            self.relapses = 0;
        }
        if self.hold == 0 {
            self.since = self.since.saturating_add(1);
            return base;
        }
        self.hold -= 1;
        if self.hold == 0 {
            self.since = 0;
        }
        base.max(rocking_substeps(dt))
    }
}

/// Substeps of a step of `dt` (s) no longer than [`ROCKING_SUBSTEP`].
fn rocking_substeps(dt: f64) -> u32 {
    (dt / ROCKING_SUBSTEP - COUNT_SLACK).ceil().clamp(1.0, u32::MAX as f64) as u32
}

impl ContactSolver {
    /// Whether every awake dynamic body of the world `b` moves slower than
    /// [`SLOW`]: bodies still falling onto the ones that rock count (with the
    /// bodies in contact alone, a 16 000-cube pile whose bottom layer had landed
    /// took 16 substeps while the nine layers above fell onto it, 2.2× the time
    /// of its first 30 steps).
    pub fn settling(&self, b: &crate::body::Bodies) -> bool {
        let slow2 = (SLOW * self.support.substep_gravity()).powi(2);
        (0..b.len()).filter(|&i| b.awake(i)).all(|i| {
            let [x, y, z] = b.linear_velocity[i];
            x * x + y * y + z * z <= slow2
        })
    }

    /// Whether block `g`'s exact answer (`sc`) pulls at some of the points
    /// that carried load while it pushes at others, its upper body slow: a
    /// point that lets go. One that carried nothing is a corner off its
    /// support (a face resting on three of four points, a brick on two
    /// bricks whose tops differ by round-off); the exact solve, which holds
    /// every row at its target, pulls at it too, but nothing rocks. Counted,
    /// such corners flagged cubes at rest (1e-18 m/s) in a 400-box pile as
    /// rocking, and a brick wall two thick (8 x 2 x 6) switched to the rocking
    /// substeps at step 68, which jolted it to 7 mm/s: 89 of 90 bricks moving
    /// after 4 s.
    pub(super) fn rocks(&self, g: usize, sc: &Scratch) -> bool {
        let b = self.support.blocks[g];
        let u = &self.bodies[b.body as usize];
        if u.v.norm() + u.w.norm() * b.arm > SLOW * self.support.substep_gravity() {
            return false;
        }
        let rows = &self.support.rows[b.rows.0 as usize..b.rows.1 as usize];
        let tiny = sc.round_off();
        let (mut pulls, mut pushes) = (false, false);
        for (i, r) in rows.iter().enumerate() {
            if let RowKind::Normal(_) = r.kind {
                let l = sc.lambda[i] + sc.y[i];
                pulls |= l < -tiny && sc.lambda[i] > tiny;
                pushes |= l > tiny;
            }
        }
        pulls && pushes
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rocking_holds_the_substeps_for_half_a_second_unless_they_were_given() {
        let dt = 1.0 / 60.0;
        let mut r = Rocking::default();
        assert_eq!(r.substeps(4, dt, false, true, false), 4);
        r.seen = true;
        let taken: Vec<u32> = (0..32).map(|_| r.substeps(4, dt, false, true, false)).collect();
        // 0.5 s at 60 Hz: 30 steps, then the world's own again.
        assert!(taken[..30].iter().all(|&n| n == 16), "{taken:?}");
        assert_eq!(&taken[30..], &[4, 4]);
        // Substeps given, or a scene in motion: the world's.
        assert_eq!(Rocking { seen: true, ..Default::default() }.substeps(4, dt, true, true, false), 4);
        assert_eq!(Rocking { seen: true, ..Default::default() }.substeps(4, dt, false, false, false), 4);
        assert_eq!(Rocking { seen: true, ..Default::default() }.substeps(20, dt, false, true, false), 20);
    }

    /// Steps of rocking substeps taken from `r` in a row (rocking seen once).
    fn held(r: &mut Rocking, dt: f64) -> usize {
        r.seen = true;
        let mut n = 0;
        while r.substeps(4, dt, false, true, false) == 16 {
            n += 1;
        }
        n
    }

    #[test]
    fn a_pile_that_rocks_again_as_soon_as_it_is_given_back_its_substeps_is_held_twice_as_long() {
        let dt = 1.0 / 60.0;
        let mut r = Rocking::default();
        // Rocking again in the step after each drop: 30, 60, 120 ... steps, at most 32 s.
        let holds: Vec<usize> = (0..9).map(|_| held(&mut r, dt)).collect();
        assert_eq!(holds, [30, 60, 120, 240, 480, 960, 1920, 1920, 1920]);
        // Quiet for a hold after a drop: the next rocking starts over at one hold.
        (0..30).for_each(|_| assert_eq!(r.substeps(4, dt, false, true, false), 4));
        assert_eq!(held(&mut r, dt), 30);
        // A body in motion cuts a long hold to one.
        held(&mut r, dt);
        r.seen = true;
        assert_eq!(r.substeps(4, dt, false, true, true), 16);
        assert_eq!(r.hold, 29);
    }

    #[test]
    fn rocking_substeps_are_at_most_a_960th_of_a_second() {
        // dt / (1/960 s), rounded up: 1/60 s (or 0.0166667) is 16, not 17 by round-off.
        let cases = [(1.0 / 30.0, 32), (1.0 / 60.0, 16), (0.0166667, 16), (1.0 / 120.0, 8), (1.0 / 240.0, 4), (1e-3, 1), (0.02, 20), (0.021, 21)];
        for (dt, n) in cases {
            assert_eq!(rocking_substeps(dt), n, "dt {dt}");
        }
        // At 1 kHz the world's 4 are shorter already: nothing is added.
        let mut r = Rocking { seen: true, ..Default::default() };
        assert_eq!(r.substeps(4, 1e-3, false, true, false), 4);
    }
}
