//! The render-pipeline settings every pass shares (the host's target
//! formats, depth, MSAA: [`crate::TargetFormat`]), so each pass states only
//! what differs.

use crate::TargetFormat;

/// How a pass uses the depth buffer (when the target has one).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum DepthUse {
    /// Tested (less) and written: solid geometry.
    Write,
    /// Tested (less or equal), not written: the sky at the far plane fills
    /// only what nothing was drawn on.
    TestOnly,
    /// Neither: debug lines over everything.
    Ignore,
}

/// What differs between the passes' pipelines.
pub struct Spec<'a> {
    /// Debug label.
    pub label: &'a str,
    /// Module with `vs_main` and `fs_main`.
    pub module: &'a wgpu::ShaderModule,
    /// Bind group layouts, group 0 first (the globals).
    pub layouts: &'a [&'a wgpu::BindGroupLayout],
    /// Vertex buffers (empty for passes that pull from storage buffers).
    pub buffers: &'a [wgpu::VertexBufferLayout<'a>],
    /// Primitive topology.
    pub topology: wgpu::PrimitiveTopology,
    /// Face culling (`None` = two-sided).
    pub cull: Option<wgpu::Face>,
    /// How the pass uses depth.
    pub depth: DepthUse,
    /// The host's target (colour and depth formats, samples).
    pub target: &'a TargetFormat,
    /// Alpha to coverage (alpha-tested billboards under MSAA).
    pub alpha_to_coverage: bool,
}

/// Builds the pipeline of `spec` for its target's formats and samples.
#[must_use]
pub fn build(device: &wgpu::Device, spec: &Spec<'_>) -> wgpu::RenderPipeline {
    let layouts: Vec<Option<&wgpu::BindGroupLayout>> =
        spec.layouts.iter().map(|l| Some(*l)).collect();
    let layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
        label: Some(spec.label),
        bind_group_layouts: &layouts,
        immediate_size: 0,
    });
    device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
        label: Some(spec.label),
        layout: Some(&layout),
        vertex: wgpu::VertexState {
            module: spec.module,
            entry_point: Some("vs_main"),
            compilation_options: wgpu::PipelineCompilationOptions::default(),
            buffers: spec.buffers,
        },
        primitive: wgpu::PrimitiveState {
            topology: spec.topology,
            cull_mode: spec.cull,
            ..Default::default()
        },
        depth_stencil: spec.target.depth.map(|format| wgpu::DepthStencilState {
            format,
            depth_write_enabled: Some(spec.depth == DepthUse::Write),
            depth_compare: Some(match spec.depth {
                DepthUse::Write => wgpu::CompareFunction::Less,
                DepthUse::TestOnly => wgpu::CompareFunction::LessEqual,
                DepthUse::Ignore => wgpu::CompareFunction::Always,
            }),
            stencil: wgpu::StencilState::default(),
            bias: wgpu::DepthBiasState::default(),
        }),
        multisample: wgpu::MultisampleState {
            count: spec.target.samples,
            mask: !0,
            alpha_to_coverage_enabled: spec.alpha_to_coverage && spec.target.samples > 1,
        },
        fragment: Some(wgpu::FragmentState {
            module: spec.module,
            entry_point: Some("fs_main"),
            compilation_options: wgpu::PipelineCompilationOptions::default(),
            targets: &[Some(wgpu::ColorTargetState {
                format: spec.target.color,
                blend: None,
                write_mask: wgpu::ColorWrites::ALL,
            })],
        }),
        multiview_mask: None,
        cache: None,
    })
}

/// A bind-group-layout entry for a read-only storage buffer seen by the vertex stage.
#[must_use]
pub fn vertex_storage(binding: u32) -> wgpu::BindGroupLayoutEntry {
    wgpu::BindGroupLayoutEntry {
        binding,
        visibility: wgpu::ShaderStages::VERTEX,
        ty: wgpu::BindingType::Buffer {
            ty: wgpu::BufferBindingType::Storage { read_only: true },
            has_dynamic_offset: false,
            min_binding_size: None,
        },
        count: None,
    }
}

/// A bind-group-layout entry for a uniform buffer seen by the vertex stage.
#[must_use]
pub fn vertex_uniform(binding: u32) -> wgpu::BindGroupLayoutEntry {
    uniform(binding, wgpu::ShaderStages::VERTEX)
}

/// A bind-group-layout entry for a uniform buffer seen by the stages `visibility`.
#[must_use]
pub fn uniform(binding: u32, visibility: wgpu::ShaderStages) -> wgpu::BindGroupLayoutEntry {
    wgpu::BindGroupLayoutEntry {
        binding,
        visibility,
        ty: wgpu::BindingType::Buffer {
            ty: wgpu::BufferBindingType::Uniform,
            has_dynamic_offset: false,
            min_binding_size: None,
        },
        count: None,
    }
}

/// Bind-group-layout entries for a filterable 2D texture and its sampler (fragment stage).
#[must_use]
pub fn texture_and_sampler(binding: u32) -> [wgpu::BindGroupLayoutEntry; 2] {
    [
        wgpu::BindGroupLayoutEntry {
            binding,
            visibility: wgpu::ShaderStages::FRAGMENT,
            ty: wgpu::BindingType::Texture {
                sample_type: wgpu::TextureSampleType::Float { filterable: true },
                view_dimension: wgpu::TextureViewDimension::D2,
                multisampled: false,
            },
            count: None,
        },
        wgpu::BindGroupLayoutEntry {
            binding: binding + 1,
            visibility: wgpu::ShaderStages::FRAGMENT,
            ty: wgpu::BindingType::Sampler(wgpu::SamplerBindingType::Filtering),
            count: None,
        },
    ]
}

/// A per-frame buffer that must hold `bytes`: `None` when `current` does,
/// else a new buffer of the next power of two bytes (`usage` plus
/// `COPY_DST`) to replace it (bind groups over the old one must be made
/// again). Growing by powers of two keeps reallocations rare as lists grow.
/// A storage buffer grows no larger than the device binds whole (nor
/// below `bytes`): the next power of two of a list just within the
/// binding was over it.
#[must_use]
pub fn grown(
    device: &wgpu::Device,
    current: Option<&wgpu::Buffer>,
    label: &str,
    usage: wgpu::BufferUsages,
    bytes: u64,
) -> Option<wgpu::Buffer> {
    if current.is_some_and(|b| b.size() >= bytes) {
        return None;
    }
    let limits = device.limits();
    let limit = if usage.contains(wgpu::BufferUsages::STORAGE) {
        limits
            .max_storage_buffer_binding_size
            .min(limits.max_buffer_size)
    } else {
        limits.max_buffer_size
    };
    Some(device.create_buffer(&wgpu::BufferDescriptor {
        label: Some(label),
        size: grown_size(bytes, limit),
        usage: usage | wgpu::BufferUsages::COPY_DST,
        mapped_at_creation: false,
    }))
}

/// The size [`grown`] gives a buffer that must hold `bytes` (a multiple of
/// 4) within `limit` bytes: the next power of two (16 at least), cut to
/// the limit (a multiple of 4 below it), never below `bytes`.
#[must_use]
pub fn grown_size(bytes: u64, limit: u64) -> u64 {
    bytes.max(16).next_power_of_two().min(limit & !3).max(bytes)
}

#[cfg(test)]
mod tests {
    use super::grown_size;

    #[test]
    fn grown_sizes_stay_within_the_binding() {
        assert_eq!(grown_size(10, 1 << 20), 16);
        assert_eq!(grown_size(100, 1 << 20), 128);
        // The next power of two (1 MiB) is over a binding of 767 KiB.
        assert_eq!(grown_size(700 << 10, 767 << 10), 767 << 10);
        // A limit that is not a multiple of 4 is cut down to one.
        assert_eq!(grown_size(1000, 1026), 1024);
        assert_eq!(grown_size(1000, 1003), 1000);
    }
}
