//! What can go wrong when rendering.

/// Errors of the render crate: each carries what a user needs to act on it.
#[derive(Debug, thiserror::Error)]
pub enum RenderError {
    /// No adapter on the backends tried.
    #[error(
        "no GPU adapter found on backends {backends} ({why}); on a machine without a GPU try WGPU_BACKEND=gl (Mesa llvmpipe) or WGPU_BACKEND=vulkan with mesa-vulkan-drivers installed"
    )]
    NoAdapter {
        /// The backends asked for.
        backends: String,
        /// wgpu's reason.
        why: String,
    },
    /// The adapter refused to create a device.
    #[error("cannot create a GPU device: {0}")]
    Device(String),
    /// The adapter cannot hold one of the field's whole arrays (the
    /// blades' shapes, 8 bytes a blade; the cells' flatness, 4 bytes a
    /// cell; drawing from the GPU path, its draw lists) or one blade's
    /// vertices in one binding. (Blade vertices and billboards over one
    /// binding are drawn in chunks and pieces.)
    #[error(
        "one of the field's arrays drawn whole (the blades' shapes or the cells' flatness; the GPU path's draw lists) needs {needed} bytes in one storage binding; this adapter allows {allowed}"
    )]
    BladesTooLarge {
        /// Bytes the array needs.
        needed: u64,
        /// `max_storage_buffer_binding_size`.
        allowed: u64,
    },
    /// The adapter cannot read storage buffers in vertex shaders.
    #[error(
        "this adapter cannot read storage buffers in vertex shaders (needed to pull blade vertices)"
    )]
    NoVertexStorage,
    /// Bad image size.
    #[error("image size {width}x{height}: both sides must be 1..={max}")]
    BadSize {
        /// Requested width.
        width: u32,
        /// Requested height.
        height: u32,
        /// `max_texture_dimension_2d`.
        max: u32,
    },
    /// Reading the frame back failed.
    #[error("cannot read the frame back from the GPU: {0}")]
    Readback(String),
}
