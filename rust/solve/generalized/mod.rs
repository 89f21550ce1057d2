//! Contacts on articulated links, in the same contact solver as every other
//! contact: their rows act on the articulation's joint velocities `q̇` through its
//! effective mass, not on the link as if it were a free body.
//!
//! A contact row on link `k` of an articulation (a normal point, a friction
//! direction or the twist of a patch) has a Jacobian `J` over the articulation's
//! dofs: the row's velocity is `J q̇` (the link's velocity at the contact point
//! along the row, through every joint from the link to the root), an impulse `λ`
//! changes `q̇` by `(M + A)⁻¹ Jᵀ λ` (the articulated-body response: every link
//! moves as its joints transmit the impulse), and the row's effective mass is
//! `1 / J (M + A)⁻¹ Jᵀ` (see [`crate::articulation::contact`] for `A`, the
//! implicit part of the joint controls). The other side of the row is a body, the
//! ground, a link of another articulation, or another link of the same one (its
//! Jacobian is then added to the first: one response for the pair). Rows are
//! built at every gather from the constraints' current arms ([`rows`]): at the
//! kick's pose for the velocity pass, after the drift for the relax pass, so each
//! impulse is equal and opposite at one world point at the pose it is applied at,
//! and linear and angular momentum pass between the two sides exactly.
//!
//! Constraints that touch a link are solved both ways by Gauss–Seidel after the
//! support blocks and the other contacts, with the same rules ([`solve`]): rigid
//! normals pushing out penetration at the soft contact's rate, the push-out
//! taken back by the relax pass, friction on the patch's cone with its twist.
//! They are never support blocks (a block holds its lower body still, and a
//! link is held by its joints, not by the solver), and do not bounce: their
//! restitution is taken as zero. Sliding friction takes the point of the cone
//! nearest to the impulse that would stop the patch in the metric of its
//! effective mass ([`cone`]).
//!
//! The shared warm start applies each constraint's impulses to the bodies that
//! are not links (its arms and masses are theirs); [`solve`] adds the links'
//! share through `q̇`. A link's solver body keeps the link's own mass and
//! inertia so that the contact point moves with it as with any body, but its
//! velocities there are not read: `q̇` is the link's state.

pub mod cone;
pub mod rows;
pub mod solve;

use super::contact::ContactSolver;
use crate::math::Vec3;

/// Marks a world body that is not an articulated link.
const NONE: u32 = u32::MAX;

/// The body side of a row: velocity `lin·v + ang·ω` of solver body `s`, and
/// what a unit impulse does to it (`M⁻¹` times the row). `s = 0`: no body.
#[derive(Clone, Copy, Debug, Default, serde::Serialize, serde::Deserialize)]
pub struct BodyTerm {
    pub s: u32,
    pub lin: Vec3,
    pub ang: Vec3,
    pub dlin: Vec3,
    pub dang: Vec3,
}

/// The articulated side of a row: `J` and `(M + A)⁻¹ Jᵀ` at `at` in the
/// Jacobian and response buffers, over the `n` joint velocities at `qd` in
/// `Generalized::qd`. `n = 0`: no articulation.
#[derive(Clone, Copy, Debug, Default, serde::Serialize, serde::Deserialize)]
pub struct ArtTerm {
    pub at: u32,
    pub qd: u32,
    pub n: u32,
}

/// One row of a constraint touching a link: up to two body sides and two
/// articulated sides (links of two articulations), its effective inverse mass.
#[derive(Clone, Copy, Debug, Default, serde::Serialize, serde::Deserialize)]
pub struct Row {
    pub body: [BodyTerm; 2],
    pub art: [ArtTerm; 2],
    /// `J M⁻¹ Jᵀ` over every side (1/kg, or 1/(kg·m²) for a twist).
    pub k: f64,
}

/// A constraint touching a link and where its rows are: its points' normals,
/// then (with friction) the patch's two tangents and (with a lever) its twist.
#[derive(Clone, Copy, Debug, Default, serde::Serialize, serde::Deserialize)]
pub struct LinkConstraint {
    pub ci: u32,
    pub row: u32,
    pub friction: bool,
    pub twist: bool,
    /// `K = [[a, b], [b, c]]` of the patch's two tangents, as `[a, b, c]` (1/kg).
    pub k: [f64; 3],
    /// Effective mass of the patch's twist about its normal (kg·m²).
    pub twist_mass: f64,
}

/// An articulation in contact this step: its joint velocities at `qd`.
#[derive(Clone, Copy, Debug, serde::Serialize, serde::Deserialize)]
pub struct Slot {
    pub art: u32,
    pub qd: u32,
    pub nv: u32,
}

/// The solver's view of the articulations in contact.
#[derive(Clone, Debug, Default, serde::Serialize, serde::Deserialize)]
pub struct Generalized {
    /// Per world body: the articulation and link it is (`NONE` if it is not).
    link_of: Vec<(u32, u32)>,
    /// Per articulation: its dofs.
    nv_of: Vec<u32>,
    any_links: bool,
    /// This step's constraints touching a link, and the articulations in contact.
    pub constraints: Vec<LinkConstraint>,
    pub slots: Vec<Slot>,
    /// Per articulation: its slot this step (`NONE`: not in contact).
    slot_of: Vec<u32>,
    /// Joint velocities of the articulations in contact, slot after slot.
    pub qd: Vec<f64>,
    pub rows: Vec<Row>,
    pub jac: Vec<f64>,
    pub resp: Vec<f64>,
    /// One Jacobian and response being built (per dof of the largest articulation).
    pub(crate) scratch_j: Vec<f64>,
    pub(crate) scratch_r: Vec<f64>,
}

impl Generalized {
    /// Sets which world bodies are links: `links[a]` the bodies of articulation
    /// `a`'s links, in link order, and its dofs; `n` bodies in all.
    pub fn set_links(&mut self, n: usize, links: &[(Vec<u32>, usize)]) {
        self.link_of = vec![(NONE, NONE); n];
        self.nv_of = links.iter().map(|(_, nv)| *nv as u32).collect();
        for (a, (bodies, _)) in links.iter().enumerate() {
            for (k, &b) in bodies.iter().enumerate() {
                if let Some(e) = self.link_of.get_mut(b as usize) {
                    *e = (a as u32, k as u32);
                }
            }
        }
        self.any_links = self.link_of.iter().any(|&(a, _)| a != NONE);
        self.slot_of = vec![NONE; links.len()];
    }

    /// Whether the world has articulated links at all.
    #[inline(always)]
    pub fn any_links(&self) -> bool {
        self.any_links
    }

    /// The articulation and link of world body `b`, if it is a link.
    #[inline(always)]
    pub fn link(&self, b: u32) -> Option<(usize, usize)> {
        match self.link_of.get(b as usize) {
            Some(&(a, k)) if a != NONE => Some((a as usize, k as usize)),
            _ => None,
        }
    }

    /// Whether articulation `a` is in contact this step.
    pub fn in_contact(&self, a: usize) -> bool {
        self.slot_of.get(a).is_some_and(|&s| s != NONE)
    }

    /// The slot of articulation `a` this step.
    pub(crate) fn slot(&self, a: usize) -> Option<&Slot> {
        self.slot_of.get(a).and_then(|&s| self.slots.get(s as usize))
    }

    fn clear(&mut self) {
        for s in &self.slots {
            self.slot_of[s.art as usize] = NONE;
        }
        self.constraints.clear();
        self.slots.clear();
        self.qd.clear();
        self.rows.clear();
        self.jac.clear();
        self.resp.clear();
    }

    /// Gives articulation `a` a slot if it has none.
    fn enter(&mut self, a: usize) {
        if self.slot_of[a] != NONE {
            return;
        }
        let nv = self.nv_of[a] as usize;
        self.slot_of[a] = self.slots.len() as u32;
        self.slots.push(Slot { art: a as u32, qd: self.qd.len() as u32, nv: nv as u32 });
        self.qd.resize(self.qd.len() + nv, 0.0);
    }
}

impl ContactSolver {
    /// Whether world body `b` is an articulated link (a contact on it is solved
    /// through its articulation).
    #[inline(always)]
    pub(crate) fn is_link(&self, b: u32) -> bool {
        self.gen.any_links && self.gen.link(b).is_some()
    }

    /// After the constraints and the support blocks of a step are planned: the
    /// constraints touching a link leave the contacts solved both ways for the
    /// generalized solve, and their articulations get slots.
    pub(crate) fn plan_links(&mut self) {
        if !self.gen.any_links {
            return;
        }
        self.gen.clear();
        for ci in 0..self.constraints.len() {
            let c = &mut self.constraints[ci];
            if !c.generalized {
                continue;
            }
            c.restitution = 0.0;
            self.gen.constraints.push(LinkConstraint { ci: ci as u32, ..Default::default() });
            for (b, s) in [(c.b1, c.s1), (c.b2, c.s2)] {
                if let (Some((a, _)), true) = (self.gen.link(b), s != 0) {
                    self.gen.enter(a);
                }
            }
        }
        if !self.gen.constraints.is_empty() {
            let cs = &self.constraints;
            self.ordinary.retain(|&ci| !cs[ci as usize].generalized);
        }
    }
}
