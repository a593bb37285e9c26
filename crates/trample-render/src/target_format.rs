//! What the host draws into: the colour and depth formats and the sample
//! count of the render pass a [`crate::FieldRenderer`] records into (the
//! wgpu middleware pattern, STYLE.md).

/// The host's render target, as its render pass is opened: the renderer's
/// pipelines are built for exactly these (wgpu refuses a pipeline whose
/// formats or sample count differ from the pass's).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct TargetFormat {
    /// Colour attachment format. An sRGB format (e.g. `Rgba8UnormSrgb`,
    /// `Bgra8UnormSrgb`) stores the shaders' linear colour encoded by the
    /// hardware; for any other format the shaders encode sRGB themselves,
    /// so the frame looks the same either way.
    pub color: wgpu::TextureFormat,
    /// Depth attachment format, or `None` for a pass without depth (the
    /// grass then draws in submission order, hiding nothing of the host's
    /// and hidden by nothing). The depth convention is the usual one:
    /// cleared to 1.0, nearer is less (clip z in [0, 1]); the renderer
    /// tests with `Less` and writes, so grass and the host's geometry
    /// occlude each other whichever draws first. Reversed-z is not
    /// supported.
    pub depth: Option<wgpu::TextureFormat>,
    /// MSAA samples of the pass's attachments (1 = none).
    pub samples: u32,
}

impl TargetFormat {
    /// The offscreen frame of [`crate::Renderer`]: [`crate::COLOR_FORMAT`],
    /// [`crate::DEPTH_FORMAT`], `samples` samples.
    #[must_use]
    pub fn offscreen(samples: u32) -> Self {
        Self {
            color: crate::COLOR_FORMAT,
            depth: Some(crate::DEPTH_FORMAT),
            samples,
        }
    }

    /// Whether the shaders must encode sRGB themselves (the colour format
    /// is not an sRGB one).
    #[must_use]
    pub fn shader_encodes_srgb(&self) -> bool {
        !self.color.is_srgb()
    }
}
