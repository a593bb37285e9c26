//! Errors of the plugin's API (bad input is an error value, never a panic).

/// What the plugin could not do, with what was given and what is allowed.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
pub enum TrampleError {
    /// A scene (file or values) the core refused: its message names the
    /// file, the key, the value and what is allowed.
    #[error("{0}")]
    Scene(String),
    /// A trampler's shape or mesh the core refused: the entity, then why.
    #[error("{0}: {1}")]
    Object(String, String),
    /// The GPU path could not read its state back (a lost device).
    #[error("the GPU path: {0}")]
    Gpu(String),
}
