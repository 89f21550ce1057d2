//! From the scene's joints to articulations: the joint graph (dynamic bodies as
//! nodes, fixed bodies and the world as one ground node) split into connected
//! components; a component whose joints all can be articulated and that has no
//! loop (at most one joint to the ground, and no cycle among its bodies) becomes
//! one articulation, rooted at its ground joint or, floating, at its first body
//! on a free joint. Links are ordered breadth first from the root.

use super::control::Control;
use super::joint::{self, Frames, JointModel};
use super::model::{Articulation, Link, Parent};
use crate::math::{quat, Quat, Vec3};

/// A joint as the builder sees it (frames from the bodies' build poses).
#[derive(Clone, Debug, serde::Serialize, serde::Deserialize)]
pub struct JointInput {
    pub model: JointModel,
    pub body_a: u32,
    /// `None`: the world.
    pub body_b: Option<u32>,
    /// Anchors and unit axes in each body's frame (world frame for the world).
    pub anchor_a: Vec3,
    pub anchor_b: Vec3,
    pub axis_a: Vec3,
    pub axis_b: Vec3,
    /// `q_b⁻¹ q_a` at build.
    pub rest: Quat,
    pub control: Control,
    /// Whether this joint may be part of an articulation (a rigid hinge,
    /// prismatic, spherical or fixed joint not asked to stay XPBD).
    pub articulable: bool,
}

/// A body as the builder sees it.
#[derive(Clone, Debug, serde::Serialize, serde::Deserialize)]
pub struct BodyInput {
    /// Dynamic (a node); otherwise part of the ground (fixed) or unusable
    /// (kinematic: a joint to it stays XPBD).
    pub dynamic: bool,
    pub kinematic: bool,
    pub position: Vec3,
    pub orientation: Quat,
    pub linear_velocity: Vec3,
    pub angular_velocity: Vec3,
    pub mass: f64,
    pub inertia: [f64; 3],
}

/// A connected set of dynamic bodies and the joints among them and to the ground.
#[derive(Clone, Debug, Default, serde::Serialize, serde::Deserialize)]
pub struct Component {
    pub bodies: Vec<u32>,
    pub joints: Vec<usize>,
    /// Every joint articulable, no loop: it can be one articulation.
    pub tree: bool,
}

fn find(parent: &mut [usize], mut i: usize) -> usize {
    while parent[i] != i {
        parent[i] = parent[parent[i]];
        i = parent[i];
    }
    i
}

/// The connected components of the joint graph that hold at least one joint.
pub fn components(bodies: &[BodyInput], joints: &[JointInput]) -> Vec<Component> {
    let n = bodies.len();
    let node = |b: Option<u32>| b.filter(|&b| bodies[b as usize].dynamic).map(|b| b as usize);
    let mut parent: Vec<usize> = (0..n).collect();
    let mut cyclic = vec![false; n];
    for j in joints {
        if let (Some(a), Some(b)) = (node(Some(j.body_a)), node(j.body_b)) {
            let (ra, rb) = (find(&mut parent, a), find(&mut parent, b));
            if ra == rb {
                cyclic[ra] = true;
            } else {
                parent[ra] = rb;
                cyclic[rb] |= cyclic[ra];
            }
        }
    }
    let mut index = vec![usize::MAX; n];
    let mut out: Vec<Component> = Vec::new();
    let mut grounded = Vec::new();
    for (k, j) in joints.iter().enumerate() {
        let Some(a) = node(Some(j.body_a)).or(node(j.body_b)) else { continue };
        let r = find(&mut parent, a);
        if index[r] == usize::MAX {
            index[r] = out.len();
            out.push(Component { tree: !cyclic[r], ..Default::default() });
            grounded.push(0usize);
        }
        let c = index[r];
        out[c].joints.push(k);
        let unusable = |b: Option<u32>| b.is_some_and(|b| bodies[b as usize].kinematic);
        if !j.articulable || unusable(Some(j.body_a)) || unusable(j.body_b) {
            out[c].tree = false;
        }
        if node(Some(j.body_a)).is_none() || node(j.body_b).is_none() {
            grounded[c] += 1;
        }
    }
    for i in 0..n {
        if bodies[i].dynamic {
            let r = find(&mut parent, i);
            if index[r] != usize::MAX {
                out[index[r]].bodies.push(i as u32);
            }
        }
    }
    for (c, g) in out.iter_mut().zip(grounded) {
        if g > 1 {
            c.tree = false;
        }
    }
    out
}

/// The articulation of a tree component, at the bodies' build poses and
/// velocities (projected on the joints' dofs).
pub fn articulation(comp: &Component, bodies: &[BodyInput], joints: &[JointInput]) -> Articulation {
    let dynamic = |b: Option<u32>| b.is_some_and(|b| bodies[b as usize].dynamic);
    let ground_joint = comp.joints.iter().copied().find(|&k| !dynamic(Some(joints[k].body_a)) || !dynamic(joints[k].body_b));
    let mut links: Vec<Link> = Vec::new();
    let mut link_of = std::collections::HashMap::new();
    let mut used = vec![false; joints.len()];
    match ground_joint {
        Some(k) => {
            let j = &joints[k];
            let (child, other, child_is_a) =
                if dynamic(Some(j.body_a)) { (j.body_a, j.body_b, true) } else { (j.body_b.unwrap_or(0), Some(j.body_a), false) };
            let parent = other.map_or(Parent::World, Parent::Fixed);
            link_of.insert(child, 0usize);
            links.push(link(j, k, child, parent, child_is_a, bodies));
            used[k] = true;
        }
        None => {
            let root = comp.bodies.iter().copied().min().unwrap_or(0);
            link_of.insert(root, 0usize);
            links.push(free_root(root, bodies));
        }
    }
    let mut head = 0;
    while head < links.len() {
        let at = links[head].body;
        for &k in &comp.joints {
            let j = &joints[k];
            if used[k] {
                continue;
            }
            let (child, child_is_a) = if j.body_b == Some(at) {
                (j.body_a, true)
            } else if j.body_a == at {
                (j.body_b.unwrap_or(0), false)
            } else {
                continue;
            };
            used[k] = true;
            link_of.insert(child, links.len());
            links.push(link(j, k, child, Parent::Link(head), child_is_a, bodies));
        }
        head += 1;
    }
    let (mut q, mut v) = (Vec::new(), Vec::new());
    for l in links.iter_mut() {
        l.q_at = q.len();
        l.v_at = v.len();
        q.resize(q.len() + l.model.nq(), 0.0);
        v.resize(v.len() + l.model.nv(), 0.0);
        joint::neutral(l.model, &mut q[l.q_at..]);
    }
    for k in 0..links.len() {
        initial_coordinates(&links, k, bodies, &mut q, &mut v);
    }
    Articulation::new(links, q, v)
}

fn link(j: &JointInput, k: usize, child: u32, parent: Parent, child_is_a: bool, bodies: &[BodyInput]) -> Link {
    let frames = if child_is_a {
        Frames { anchor_parent: j.anchor_b, anchor_child: j.anchor_a, axis_parent: j.axis_b, axis_child: j.axis_a, rest: j.rest }
    } else {
        Frames { anchor_parent: j.anchor_a, anchor_child: j.anchor_b, axis_parent: j.axis_a, axis_child: j.axis_b, rest: j.rest.conjugate() }
    };
    let b = &bodies[child as usize];
    Link {
        body: child,
        parent,
        joint: Some(k),
        child_is_a,
        model: j.model,
        frames,
        q_at: 0,
        v_at: 0,
        mass: b.mass,
        inertia: b.inertia,
        control: j.control.clone(),
    }
}

fn free_root(body: u32, bodies: &[BodyInput]) -> Link {
    let b = &bodies[body as usize];
    let z = Vec3::zeros();
    Link {
        body,
        parent: Parent::World,
        joint: None,
        child_is_a: true,
        model: JointModel::Free,
        frames: Frames { anchor_parent: z, anchor_child: z, axis_parent: z, axis_child: z, rest: Quat::identity() },
        q_at: 0,
        v_at: 0,
        mass: b.mass,
        inertia: b.inertia,
        control: Control::default(),
    }
}

/// The coordinates of link `k` at build (neutral but for a free root) and its
/// joint velocity: the bodies' relative velocity projected on the joint's dofs.
fn initial_coordinates(links: &[Link], k: usize, bodies: &[BodyInput], q: &mut [f64], v: &mut [f64]) {
    let l = &links[k];
    let b = &bodies[l.body as usize];
    let parent_body = match l.parent {
        Parent::Link(p) => Some(&bodies[links[p].body as usize]),
        _ => None,
    };
    let wp = parent_body.map_or(Vec3::zeros(), |pb| pb.angular_velocity);
    let vp_at = |x: &Vec3| parent_body.map_or(Vec3::zeros(), |pb| pb.linear_velocity + pb.angular_velocity.cross(&(x - pb.position)));
    let anchor = b.position + quat::rotate(&b.orientation, &l.frames.anchor_child);
    let (qa, va) = (l.q_at, l.v_at);
    match l.model {
        JointModel::Revolute => {
            let axis = quat::rotate(&b.orientation, &l.frames.axis_child);
            v[va] = axis.dot(&(b.angular_velocity - wp));
        }
        JointModel::Prismatic => {
            let axis = quat::rotate(&b.orientation, &l.frames.axis_child);
            let vc = b.linear_velocity + b.angular_velocity.cross(&(anchor - b.position));
            v[va] = axis.dot(&(vc - vp_at(&anchor)));
        }
        JointModel::Spherical => {
            let w = quat::rotate_inv(&b.orientation, &(b.angular_velocity - wp));
            v[va..va + 3].copy_from_slice(w.as_slice());
        }
        JointModel::Fixed => {}
        JointModel::Free => {
            q[qa..qa + 3].copy_from_slice(b.position.as_slice());
            joint::store_quat(&b.orientation, &mut q[qa + 3..qa + 7]);
            v[va..va + 3].copy_from_slice(b.angular_velocity.as_slice());
            v[va + 3..va + 6].copy_from_slice(b.linear_velocity.as_slice());
        }
    }
}
