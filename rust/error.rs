//! The one error type of the crate. Every message names the body, shape or field
//! it is about, so a user can find the bad input without reading Rust.

use std::fmt;

/// What went wrong, which decides the Python exception it maps to.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ErrorKind {
    /// A value given by the user is out of range, non-finite or of the wrong shape.
    Input,
    /// A shape is degenerate (no volume, open mesh, too few points).
    Shape,
    /// The state of a world (written through a view) is invalid at the next step.
    State,
    /// A step diverged or failed inside; the world was put back as before it.
    Simulation,
}

#[derive(Debug, Clone, PartialEq)]
pub struct Error {
    pub kind: ErrorKind,
    pub message: String,
}

pub type Result<T> = std::result::Result<T, Error>;

impl Error {
    pub fn input(message: impl Into<String>) -> Self {
        Self { kind: ErrorKind::Input, message: message.into() }
    }
    pub fn shape(message: impl Into<String>) -> Self {
        Self { kind: ErrorKind::Shape, message: message.into() }
    }
    pub fn state(message: impl Into<String>) -> Self {
        Self { kind: ErrorKind::State, message: message.into() }
    }
    pub fn simulation(message: impl Into<String>) -> Self {
        Self { kind: ErrorKind::Simulation, message: message.into() }
    }
    /// Prefixes the message with where it happened, e.g. "body 3: ".
    pub fn context(mut self, prefix: impl fmt::Display) -> Self {
        self.message = format!("{prefix}: {}", self.message);
        self
    }
}

impl fmt::Display for Error {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.message)
    }
}

impl std::error::Error for Error {}

/// Checks that a scalar is finite, naming it otherwise.
pub fn finite(name: &str, x: f64) -> Result<f64> {
    if x.is_finite() {
        Ok(x)
    } else {
        Err(Error::input(format!("{name} must be finite, got {x}")))
    }
}

/// Checks that a scalar is finite and strictly positive.
pub fn positive(name: &str, x: f64) -> Result<f64> {
    if x.is_finite() && x > 0.0 {
        Ok(x)
    } else {
        Err(Error::input(format!("{name} must be positive and finite, got {x}")))
    }
}

/// Checks that a scalar is finite and not negative.
pub fn non_negative(name: &str, x: f64) -> Result<f64> {
    if x.is_finite() && x >= 0.0 {
        Ok(x)
    } else {
        Err(Error::input(format!("{name} must be non-negative and finite, got {x}")))
    }
}

/// Checks that every component of a vector is finite.
pub fn finite3(name: &str, v: [f64; 3]) -> Result<[f64; 3]> {
    if v.iter().all(|x| x.is_finite()) {
        Ok(v)
    } else {
        Err(Error::input(format!("{name} must be finite, got {v:?}")))
    }
}
