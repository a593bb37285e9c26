//! Errors of the GPU path.

/// What can go wrong on the GPU path. The library never panics on input.
#[derive(Debug, thiserror::Error)]
pub enum GpuError {
    /// A buffer would exceed the adapter's storage-binding limit.
    #[error(
        "{what} needs {bytes} bytes, over the adapter's storage binding limit of {limit} bytes"
    )]
    TooLarge {
        /// Which buffer.
        what: &'static str,
        /// Its size.
        bytes: u64,
        /// `max_storage_buffer_binding_size`.
        limit: u64,
    },
    /// The field and the simulation disagree (e.g. a cell count that does not divide the blade count).
    #[error("field layout: {0}")]
    Layout(String),
    /// The device's limits are below what the GPU path needs
    /// ([`crate::required_limits`]); the message names the limit.
    #[error("device limit: {0}")]
    Limit(String),
    /// A feature of the scene the GPU path does not have yet.
    #[error("not yet on the GPU path: {0}")]
    Unsupported(&'static str),
    /// Mapping a buffer for read-back failed (device lost, out of memory).
    #[error("reading back {what} failed: {why}")]
    ReadBack {
        /// Which buffer.
        what: &'static str,
        /// The driver's message.
        why: String,
    },
}
