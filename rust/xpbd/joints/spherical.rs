//! Spherical (ball) joint: the anchors of a and b coincide; every rotation is free.

use super::correction::Pair;
use super::{attach, Joint};

pub fn project(j: &Joint, pair: &mut Pair<'_>) {
    attach(j, pair);
}
