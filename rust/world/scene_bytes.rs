//! A scene as bytes (for `pickle`): serialized with postcard in a checked frame.

use super::framing::{frame, unframe, SCENE};
use super::Scene;
use crate::error::{Error, Result};

impl Scene {
    pub fn to_bytes(&self) -> Result<Vec<u8>> {
        let payload = postcard::to_stdvec(self).map_err(|e| Error::input(format!("scene could not be encoded: {e}")))?;
        Ok(frame(SCENE, &payload))
    }

    pub fn from_bytes(data: &[u8]) -> Result<Scene> {
        let payload = unframe(SCENE, data)?;
        match postcard::take_from_bytes::<Scene>(payload) {
            Ok((scene, [])) => Ok(scene),
            Ok((_, rest)) => Err(Error::input(format!("scene data has {} bytes after the scene", rest.len()))),
            Err(e) => Err(Error::input(format!("scene data could not be decoded ({e}): it was not written by this build of rigidrs"))),
        }
    }
}
