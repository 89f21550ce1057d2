//! The frame around saved bytes (snapshots, scenes): what they are, which
//! format and engine version wrote them, and a checksum, so that foreign,
//! truncated, corrupted or newer data is refused with a message saying which.
//!
//! Layout (integers little-endian): `RIGIDRS\0`, a 4-byte kind (`WRLD`,
//! `SCEN`), format version u32, engine version (u32 length, UTF-8), payload
//! length u64, CRC-32 of the payload u32, then the payload (postcard).

use super::checksum::crc32;
use crate::error::{Error, Result};

const MAGIC: &[u8; 8] = b"RIGIDRS\0";
/// Bumped whenever the payload's layout changes.
/// 2: scenes keep the calls that filled them (`recipe`), planes their given
/// normal, compounds their parts' given orientations.
/// 3: the narrow phase keeps its pairs in slots, with their order by key.
/// 4: the rocking state of the support sweeps.
/// 5: the broad phase keeps its pairs of fat boxes sorted (a step filters the
/// candidates from them in order).
/// 6: the support sweeps' scratch and list of solved blocks are no longer
/// kept (they are rebuilt by every pass).
/// 7: the solver bodies' fields in the order a pass reads them; the
/// patches' polygons apart from the patches.
/// 8: each body's last support-block change (the echo bound of the quiet
/// islands).
/// 9: the restitution threshold optional (its default follows the step).
/// 10: the solver bodies' chords (a turning kinematic body's turn in a
/// substep: friction along its points' chords).
/// 11: every body's chord, and the patches' drift (the chords' difference
/// friction holds, on free bodies too).
/// 12: each contact point's curve (see `solve::rounded_curve`).
/// 13: the relative pose and prediction each pair's manifolds were computed
/// at (kept while the pair is still: see `collide::narrow_phase::STILL`).
/// 14: each constraint's slack, arm and whether it was kept as still, and
/// the orientation at the last build of each tracked constraint's body 1 (see
/// `solve::reuse::still_slack`).
/// 15: the contact points' and constraints' fields in the order the passes
/// read them.
/// 16: whether the last step's contacts could be laid out in halves (see
/// `solve::seams`).
/// 17: a contact point's impulses, mass and anchors first, a constraint's `fresh`
/// and `central` in its first two cache lines,
/// its restitution after them.
pub const FORMAT_VERSION: u32 = 17;
pub const ENGINE_VERSION: &str = env!("CARGO_PKG_VERSION");
/// Longest engine version string accepted (a guard against reading garbage).
const MAX_VERSION_LEN: usize = 64;

/// What a frame holds: its 4-byte tag and a name for messages.
#[derive(Clone, Copy)]
pub struct Kind {
    pub tag: &'static [u8; 4],
    pub name: &'static str,
}

pub const WORLD: Kind = Kind { tag: b"WRLD", name: "world snapshot" };
pub const SCENE: Kind = Kind { tag: b"SCEN", name: "scene" };

pub fn frame(kind: Kind, payload: &[u8]) -> Vec<u8> {
    let mut out = Vec::with_capacity(payload.len() + 64);
    out.extend_from_slice(MAGIC);
    out.extend_from_slice(kind.tag);
    out.extend_from_slice(&FORMAT_VERSION.to_le_bytes());
    out.extend_from_slice(&(ENGINE_VERSION.len() as u32).to_le_bytes());
    out.extend_from_slice(ENGINE_VERSION.as_bytes());
    out.extend_from_slice(&(payload.len() as u64).to_le_bytes());
    out.extend_from_slice(&crc32(payload).to_le_bytes());
    out.extend_from_slice(payload);
    out
}

/// A cursor over the header that names what is missing when the data ends.
struct Reader<'a> {
    data: &'a [u8],
    at: usize,
    what: &'static str,
}

impl<'a> Reader<'a> {
    fn take(&mut self, n: usize, field: &str) -> Result<&'a [u8]> {
        let end = self.at.checked_add(n).filter(|&e| e <= self.data.len()).ok_or_else(|| {
            Error::input(format!(
                "{} data is truncated: it ends ({} bytes) inside the header's {field}",
                self.what,
                self.data.len()
            ))
        })?;
        let s = &self.data[self.at..end];
        self.at = end;
        Ok(s)
    }

    fn u32(&mut self, field: &str) -> Result<u32> {
        let b = self.take(4, field)?;
        Ok(u32::from_le_bytes([b[0], b[1], b[2], b[3]]))
    }

    fn u64(&mut self, field: &str) -> Result<u64> {
        let b = self.take(8, field)?;
        let mut a = [0u8; 8];
        a.copy_from_slice(b);
        Ok(u64::from_le_bytes(a))
    }
}

/// The payload of `data`, after checking every field of the frame.
pub fn unframe(kind: Kind, data: &[u8]) -> Result<&[u8]> {
    let mut r = Reader { data, at: 0, what: kind.name };
    let magic = r.take(MAGIC.len(), "magic").map_err(|_| not_ours(kind, data))?;
    if magic != MAGIC {
        return Err(not_ours(kind, data));
    }
    let tag = r.take(4, "kind")?;
    if tag != kind.tag {
        return Err(Error::input(format!(
            "this is rigidrs data of another kind (b\"{}\"), not a {}",
            tag.escape_ascii(),
            kind.name
        )));
    }
    let format = r.u32("format version")?;
    let len = r.u32("engine version")? as usize;
    if len > MAX_VERSION_LEN {
        return Err(Error::input(format!("{} data is corrupted: engine version of {len} bytes", kind.name)));
    }
    let engine = String::from_utf8_lossy(r.take(len, "engine version")?).into_owned();
    if format != FORMAT_VERSION || engine != ENGINE_VERSION {
        return Err(Error::input(format!(
            "{} written by rigidrs {engine} (format {format}); this is rigidrs {ENGINE_VERSION} (format \
             {FORMAT_VERSION}), which reads only its own: load it with the version that wrote it",
            kind.name
        )));
    }
    let size = r.u64("payload length")?;
    let crc = r.u32("checksum")?;
    let payload = &data[r.at..];
    if payload.len() as u64 != size {
        let how = if (payload.len() as u64) < size { "truncated" } else { "corrupted (bytes after its end)" };
        return Err(Error::input(format!(
            "{} data is {how}: the header announces {size} bytes of state, {} follow",
            kind.name,
            payload.len()
        )));
    }
    if crc32(payload) != crc {
        return Err(Error::input(format!("{} data is corrupted: its checksum does not match its contents", kind.name)));
    }
    Ok(payload)
}

fn not_ours(kind: Kind, data: &[u8]) -> Error {
    let head = &data[..data.len().min(8)];
    Error::input(format!(
        "not a rigidrs {}: the data starts with b\"{}\", not b\"{}\"",
        kind.name,
        head.escape_ascii(),
        MAGIC.escape_ascii()
    ))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn round_trip_and_every_cut_is_refused() {
        let data = frame(WORLD, b"payload bytes");
        assert_eq!(unframe(WORLD, &data).unwrap(), b"payload bytes");
        for n in 0..data.len() {
            assert!(unframe(WORLD, &data[..n]).is_err(), "cut at {n}");
        }
        assert!(unframe(SCENE, &data).is_err());
    }

    #[test]
    fn every_flipped_bit_is_refused() {
        let data = frame(SCENE, b"some scene");
        for k in 0..data.len() * 8 {
            let mut bad = data.clone();
            bad[k / 8] ^= 1 << (k % 8);
            assert!(unframe(SCENE, &bad).is_err(), "bit {k}");
        }
    }
}
