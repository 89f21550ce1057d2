//! Fixed joint: a and b keep their relative orientation and the anchors coincide
//! (a weld).

use super::correction::Pair;
use super::{attach, keep_orientation, Joint};

pub fn project(j: &Joint, pair: &mut Pair<'_>) {
    keep_orientation(j, pair);
    attach(j, pair);
}
