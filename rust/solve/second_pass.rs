//! A settling pile takes a second solver iteration.
//!
//! The support blocks ([`super::support`]) solve what rests on what exactly;
//! a contact between two moving bodies that is not a support (a cube leaning
//! through one corner on the side of another, a face tilted more than the
//! support angle) is solved by one Gauss–Seidel pass a substep, after the
//! blocks. Where the two meet, one pass leaves each a residual the other
//! undoes: in a tumbled pile of 400 cubes a cube leaning on a column's top
//! cube slid 14 mm in 10 s with both its contacts well inside their friction
//! cones (|f|/N 0.27 and 0.08 at μ 0.5), pushing the column with it, and 19,
//! 25, 0, 1, 43 and 35 cubes of six pours still moved faster than 1 mm/s
//! after 30 s with sleeping off (`tests/test_pile_rest.py`). Two iterations
//! of every pass throughout (velocity and relax, blocks and Gauss–Seidel)
//! left 0, 4, 2, 0, 7 and 7, and pressed box into box at most 16–31 µm where
//! one pass pressed 12–874 µm, for 10 % more time (79 → 87 s); but they
//! doubled the cost of the tumbling 4000-cube pile's landing (its first 120
//! steps, 17.0 → 28.5 s) for nothing a landing needs.
//!
//! So a step takes at least two iterations when the scene is settling (every
//! awake body slower than the rocking substeps' bound, [`super::rocking`]),
//! something still creeps (faster than the residual the sweeps take as
//! solved), and its plan has support blocks and a contact solved both ways
//! between two moving bodies (balls apart: a ball pit's soft contacts are
//! what bring it to rest, and it has no blocks). Measured: 7, 4, 0, 3, 5 and
//! 31 cubes moving after 30 s with sleeping off (the last pour had a cube
//! falling off at 0.19 m/s), 19–178 µm deepest, 100 s for the six pours
//! (+26 %: the pours settle with more of their steps at two iterations); at
//! the defaults (sleeping on) 5, 0, 0, 7 of pours 1–4 where 18, 12, 0, 10
//! moved, in about the same time. The landing keeps its one iteration and its
//! bits, as do a stack, a pyramid or a column at rest (blocks alone) and a
//! ball pit (no blocks). The further iterations run inside the `friction`
//! stage, whose time in `World::profile` includes them.

use super::contact::ContactSolver;
use super::solver_body::Surface;
use crate::body::Bodies;

/// Iterations a step of a pile takes at least.
const PILE_ITERATIONS: u32 = 2;

impl ContactSolver {
    /// Notes at a step's start, from the world's bodies `b` and whether they
    /// are all slow (`slow`, [`ContactSolver::settling`]), whether the scene is
    /// settling and something still creeps (only where there are support
    /// blocks: the rest never take a second iteration).
    pub fn note_settling(&mut self, b: &Bodies, slow: bool) {
        self.settling_now = !self.support.blocks.is_empty() && slow && self.creeping(b);
    }

    /// Whether some awake body of the world `b` moves faster than the
    /// residual the support sweeps take as solved: a pile at rest, to
    /// round-off, keeps one iteration (a second one echoed a grid of cubes
    /// resting edge to edge from 1e-15 to 3e-10 m/s,
    /// `tests/test_crate_grid.py`).
    fn creeping(&self, b: &Bodies) -> bool {
        let fast2 = self.support.residual * self.support.residual;
        (0..b.len()).filter(|&i| b.awake(i)).any(|i| {
            let [x, y, z] = b.linear_velocity[i];
            x * x + y * y + z * z > fast2
        })
    }

    /// How many iterations of the normal and friction passes this step takes
    /// beyond the `planned` ones (the world's `iterations`, which the
    /// pipeline's stages run).
    pub fn extra_iterations(&self, planned: u32) -> u32 {
        if self.settling_now && self.leaning() {
            PILE_ITERATIONS.saturating_sub(planned)
        } else {
            0
        }
    }

    /// Whether this step's plan has support blocks and a contact solved both
    /// ways between two moving bodies, not both balls.
    fn leaning(&self) -> bool {
        if self.support.blocks.is_empty() {
            return false;
        }
        self.ordinary.iter().any(|&ci| {
            let c = &self.constraints[ci as usize];
            let (a, b) = (&self.bodies[c.s1 as usize], &self.bodies[c.s2 as usize]);
            a.dynamic && b.dynamic && !(a.surface == Surface::Ball && b.surface == Surface::Ball)
        })
    }
}
