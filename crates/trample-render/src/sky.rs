//! The sky: drawn first, a full-screen triangle that never writes depth.

use crate::globals::shader_module;

/// The sky pass.
pub struct SkyPass {
    pipeline: wgpu::RenderPipeline,
}

impl SkyPass {
    /// Creates the pass.
    #[must_use]
    pub fn new(
        device: &wgpu::Device,
        globals: &wgpu::BindGroupLayout,
        target: &crate::TargetFormat,
    ) -> Self {
        let module = shader_module(device, "sky.wgsl", include_str!("sky.wgsl"));
        let pipeline = crate::pipeline::build(
            device,
            &crate::pipeline::Spec {
                label: "sky",
                module: &module,
                layouts: &[globals],
                buffers: &[],
                topology: wgpu::PrimitiveTopology::TriangleList,
                cull: None,
                depth: crate::pipeline::DepthUse::TestOnly,
                target,
                alpha_to_coverage: false,
            },
        );
        Self { pipeline }
    }

    /// Records the draw into `pass`.
    pub fn draw(&self, pass: &mut wgpu::RenderPass<'_>) {
        pass.set_pipeline(&self.pipeline);
        pass.draw(0..3, 0..1);
    }
}
