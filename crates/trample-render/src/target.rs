//! The offscreen target: a (multisampled) colour texture resolved into an
//! RGBA8 texture, a depth buffer, and the read-back to an image.

use crate::error::RenderError;

/// Offscreen colour + depth of one size and sample count.
pub struct Target {
    /// Width, pixels.
    pub width: u32,
    /// Height, pixels.
    pub height: u32,
    /// MSAA samples.
    pub samples: u32,
    msaa: Option<wgpu::TextureView>,
    resolved: wgpu::Texture,
    resolved_view: wgpu::TextureView,
    depth: wgpu::TextureView,
    readback: wgpu::Buffer,
    padded_row: u32,
}

impl Target {
    /// Creates the textures.
    ///
    /// # Errors
    /// [`RenderError::BadSize`] when a side is 0 or above the device's limit.
    pub fn new(
        device: &wgpu::Device,
        width: u32,
        height: u32,
        samples: u32,
    ) -> Result<Self, RenderError> {
        let max = device.limits().max_texture_dimension_2d;
        if width == 0 || height == 0 || width > max || height > max {
            return Err(RenderError::BadSize { width, height, max });
        }
        let size = wgpu::Extent3d {
            width,
            height,
            depth_or_array_layers: 1,
        };
        let texture = |label, format, samples, usage| {
            device.create_texture(&wgpu::TextureDescriptor {
                label: Some(label),
                size,
                mip_level_count: 1,
                sample_count: samples,
                dimension: wgpu::TextureDimension::D2,
                format,
                usage,
                view_formats: &[],
            })
        };
        let attach = wgpu::TextureUsages::RENDER_ATTACHMENT;
        let msaa = (samples > 1).then(|| {
            texture("colour (msaa)", crate::COLOR_FORMAT, samples, attach)
                .create_view(&wgpu::TextureViewDescriptor::default())
        });
        // TEXTURE_BINDING: a window samples the frame to present it.
        let resolved = texture(
            "colour",
            crate::COLOR_FORMAT,
            1,
            attach | wgpu::TextureUsages::COPY_SRC | wgpu::TextureUsages::TEXTURE_BINDING,
        );
        let resolved_view = resolved.create_view(&wgpu::TextureViewDescriptor::default());
        let depth = texture("depth", crate::DEPTH_FORMAT, samples, attach)
            .create_view(&wgpu::TextureViewDescriptor::default());
        let padded_row = (width * 4).div_ceil(wgpu::COPY_BYTES_PER_ROW_ALIGNMENT)
            * wgpu::COPY_BYTES_PER_ROW_ALIGNMENT;
        let readback = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("readback"),
            size: u64::from(padded_row) * u64::from(height),
            usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        Ok(Self {
            width,
            height,
            samples,
            msaa,
            resolved,
            resolved_view,
            depth,
            readback,
            padded_row,
        })
    }

    /// The single-sample frame ([`crate::COLOR_FORMAT`]) the passes resolve
    /// into: overlays draw on it, windows sample it to present it.
    #[must_use]
    pub fn frame_view(&self) -> &wgpu::TextureView {
        &self.resolved_view
    }

    /// The colour attachment (resolving into the RGBA8 texture under MSAA).
    #[must_use]
    pub fn color_attachment(&self, clear: wgpu::Color) -> wgpu::RenderPassColorAttachment<'_> {
        let (view, resolve_target) = match &self.msaa {
            Some(m) => (m, Some(&self.resolved_view)),
            None => (&self.resolved_view, None),
        };
        wgpu::RenderPassColorAttachment {
            view,
            depth_slice: None,
            resolve_target,
            ops: wgpu::Operations {
                load: wgpu::LoadOp::Clear(clear),
                // The multisampled texture is not needed after the resolve.
                store: if self.msaa.is_some() {
                    wgpu::StoreOp::Discard
                } else {
                    wgpu::StoreOp::Store
                },
            },
        }
    }

    /// The depth attachment, cleared to the far plane.
    #[must_use]
    pub fn depth_attachment(&self) -> wgpu::RenderPassDepthStencilAttachment<'_> {
        wgpu::RenderPassDepthStencilAttachment {
            view: &self.depth,
            depth_ops: Some(wgpu::Operations {
                load: wgpu::LoadOp::Clear(1.0),
                store: wgpu::StoreOp::Discard,
            }),
            stencil_ops: None,
        }
    }

    /// Records the copy of the resolved frame into the read-back buffer.
    pub fn copy_out(&self, encoder: &mut wgpu::CommandEncoder) {
        encoder.copy_texture_to_buffer(
            wgpu::TexelCopyTextureInfo {
                texture: &self.resolved,
                mip_level: 0,
                origin: wgpu::Origin3d::ZERO,
                aspect: wgpu::TextureAspect::All,
            },
            wgpu::TexelCopyBufferInfo {
                buffer: &self.readback,
                layout: wgpu::TexelCopyBufferLayout {
                    offset: 0,
                    bytes_per_row: Some(self.padded_row),
                    rows_per_image: Some(self.height),
                },
            },
            wgpu::Extent3d {
                width: self.width,
                height: self.height,
                depth_or_array_layers: 1,
            },
        );
    }

    /// Waits for the GPU and reads the copied frame (sRGB-encoded RGBA8).
    ///
    /// # Errors
    /// [`RenderError::Readback`] when mapping fails.
    pub fn read(&self, device: &wgpu::Device) -> Result<image::RgbaImage, RenderError> {
        let slice = self.readback.slice(..);
        let (tx, rx) = std::sync::mpsc::channel();
        slice.map_async(wgpu::MapMode::Read, move |r| {
            let _ = tx.send(r);
        });
        device
            .poll(wgpu::PollType::wait_indefinitely())
            .map_err(|e| RenderError::Readback(e.to_string()))?;
        rx.recv()
            .map_err(|e| RenderError::Readback(e.to_string()))?
            .map_err(|e| RenderError::Readback(e.to_string()))?;
        let mut pixels = Vec::with_capacity((self.width * self.height * 4) as usize);
        {
            let data = slice.get_mapped_range();
            for row in data.chunks(self.padded_row as usize) {
                pixels.extend_from_slice(&row[..(self.width * 4) as usize]);
            }
        }
        self.readback.unmap();
        image::RgbaImage::from_raw(self.width, self.height, pixels)
            .ok_or_else(|| RenderError::Readback("short buffer".into()))
    }
}
