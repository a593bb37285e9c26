//! Textures generated in code at start-up: the ground's grass and the
//! billboards' grass clump (DESIGN §8), with box-filtered mip chains.

use trample::field::rng::unit;

/// Uniform numbers in [0, 1) from the library's seeded mixer, one after another.
struct Rng {
    seed: u64,
    next: u64,
}

impl Rng {
    fn new(seed: u64) -> Self {
        Self { seed, next: 0 }
    }

    fn next_f32(&mut self) -> f32 {
        self.next += 1;
        unit(self.seed, self.next, 0x7e47)
    }
}

/// Side of the ground texture, texels (it tiles every [`GROUND_TILE_M`]).
pub const GROUND_SIZE: u32 = 256;
/// World size of one repeat of the ground texture, metres.
pub const GROUND_TILE_M: f32 = 2.0;
/// Width and height of the clump texture, texels.
pub const CLUMP_SIZE: u32 = 128;

/// An RGBA8 image (sRGB colour, linear alpha), row-major.
#[derive(Clone)]
pub struct Pixels {
    /// Width, texels.
    pub width: u32,
    /// Height, texels.
    pub height: u32,
    /// `width * height * 4` bytes.
    pub rgba: Vec<u8>,
}

/// The ground: a dense lawn seen from above — mottled greens with darker
/// gaps and short lighter strokes, tileable (all noise wraps).
#[must_use]
pub fn ground_grass(seed: u64) -> Pixels {
    let n = GROUND_SIZE;
    let mut rng = Rng::new(seed);
    let mut lum = vec![0.0f32; (n * n) as usize];
    // Strokes: short blades lying in random directions, wrapped at the edges.
    for _ in 0..9000 {
        let (x0, y0) = (rng.next_f32() * n as f32, rng.next_f32() * n as f32);
        let a = rng.next_f32() * std::f32::consts::TAU;
        let len = 3.0 + rng.next_f32() * 6.0;
        let v = rng.next_f32() * 0.6 + 0.4;
        for s in 0..(len as i32 * 2) {
            let t = s as f32 * 0.5;
            let x = (x0 + a.cos() * t).rem_euclid(n as f32) as u32;
            let y = (y0 + a.sin() * t).rem_euclid(n as f32) as u32;
            let i = (y * n + x) as usize;
            lum[i] = lum[i].max(v);
        }
    }
    let mut rgba = Vec::with_capacity((n * n * 4) as usize);
    for y in 0..n {
        for x in 0..n {
            let l = lum[(y * n + x) as usize];
            // Soil-dark gaps between strokes, yellow-green tops on strokes.
            let patch = 0.5
                + 0.5
                    * ((x as f32 / n as f32 * std::f32::consts::TAU * 2.0).sin()
                        * (y as f32 / n as f32 * std::f32::consts::TAU * 3.0).cos());
            let base = [44.0, 66.0, 24.0];
            let top = [92.0 + 30.0 * patch, 128.0 + 10.0 * patch, 44.0];
            for c in 0..3 {
                rgba.push((base[c] + (top[c] - base[c]) * l).clamp(0.0, 255.0) as u8);
            }
            rgba.push(255);
        }
    }
    Pixels {
        width: n,
        height: n,
        rgba,
    }
}

/// The billboard clump: a few tapered blades rising from the bottom edge,
/// leaning a little, on a transparent background (alpha 0 or 255, for the
/// alpha test). Sparse on purpose: it stands for the handful of blades a
/// billboard cell holds, so the billboard band has the density of the
/// geometric band beside it.
#[must_use]
pub fn grass_clump(seed: u64, blades: u32) -> Pixels {
    let (w, h) = (CLUMP_SIZE, CLUMP_SIZE);
    let mut rgba = vec![0u8; (w * h * 4) as usize];
    let mut rng = Rng::new(seed);
    for i in 0..blades {
        let root = (i as f32 + 0.2 + 0.6 * rng.next_f32()) / blades as f32 * w as f32;
        let lean = (rng.next_f32() - 0.5) * 0.5 * w as f32;
        let height = (0.7 + 0.3 * rng.next_f32()) * h as f32;
        let half_width = 2.5 + 1.5 * rng.next_f32();
        let shade = 0.85 + 0.3 * rng.next_f32();
        for y in 0..h {
            // y = 0 is the top row of the image; the root is at the bottom.
            let up = (h - 1 - y) as f32;
            if up > height {
                continue;
            }
            let t = up / height;
            let cx = root + lean * t * t;
            let hw = half_width * (1.0 - t) + 0.4;
            for x in 0..w {
                if (x as f32 + 0.5 - cx).abs() <= hw {
                    let i = ((y * w + x) * 4) as usize;
                    // Root dark green to yellow-green tip (sRGB).
                    let c = [
                        (40.0 + 90.0 * t) * shade,
                        (70.0 + 100.0 * t) * shade,
                        (20.0 + 30.0 * t) * shade,
                    ];
                    for (out, v) in rgba[i..i + 3].iter_mut().zip(c) {
                        *out = v.clamp(0.0, 255.0) as u8;
                    }
                    rgba[i + 3] = 255;
                }
            }
        }
    }
    Pixels {
        width: w,
        height: h,
        rgba,
    }
}

/// Halves `p` with a 2×2 box filter; colours weighted by alpha so transparent
/// texels do not darken the edges.
#[must_use]
pub fn half(p: &Pixels) -> Pixels {
    let (w, h) = ((p.width / 2).max(1), (p.height / 2).max(1));
    let mut rgba = vec![0u8; (w * h * 4) as usize];
    for y in 0..h {
        for x in 0..w {
            let mut acc = [0.0f32; 4];
            for (dx, dy) in [(0, 0), (1, 0), (0, 1), (1, 1)] {
                let sx = (2 * x + dx).min(p.width - 1);
                let sy = (2 * y + dy).min(p.height - 1);
                let i = ((sy * p.width + sx) * 4) as usize;
                let a = f32::from(p.rgba[i + 3]) / 255.0;
                for (sum, &c) in acc.iter_mut().zip(&p.rgba[i..i + 3]) {
                    *sum += f32::from(c) * a;
                }
                acc[3] += a;
            }
            let o = ((y * w + x) * 4) as usize;
            for (out, sum) in rgba[o..o + 3].iter_mut().zip(acc) {
                *out = if acc[3] > 0.0 {
                    (sum / acc[3]).round() as u8
                } else {
                    0
                };
            }
            rgba[o + 3] = (acc[3] / 4.0 * 255.0).round() as u8;
        }
    }
    Pixels {
        width: w,
        height: h,
        rgba,
    }
}

/// Mean linear colour of `p`'s opaque texels (alpha-weighted; sRGB decoded).
#[must_use]
pub fn mean_linear(p: &Pixels) -> [f32; 3] {
    mean_linear_by_row(p, |_| 1.0)
}

/// [`mean_linear`] of the texels' colours times `factor(v)`, `v` the
/// texel row's texture coordinate (0 at the top, 1 at the bottom).
#[must_use]
pub fn mean_linear_by_row(p: &Pixels, factor: impl Fn(f32) -> f32) -> [f32; 3] {
    let decode = |c: u8| {
        let x = f32::from(c) / 255.0;
        if x <= 0.04045 {
            x / 12.92
        } else {
            ((x + 0.055) / 1.055).powf(2.4)
        }
    };
    let (mut sum, mut weight) = ([0.0f64; 3], 0.0f64);
    let row_bytes = (p.width as usize * 4).max(1);
    for (i, c) in p.rgba.chunks(4).enumerate() {
        let a = f64::from(c[3]) / 255.0;
        let v = ((i * 4 / row_bytes) as f32 + 0.5) / p.height.max(1) as f32;
        let f = f64::from(factor(v));
        for (s, &x) in sum.iter_mut().zip(&c[..3]) {
            *s += f64::from(decode(x)) * a * f;
        }
        weight += a;
    }
    sum.map(|s| (s / weight.max(1e-9)) as f32)
}

/// The alpha threshold of the billboards' alpha test (billboards.wgsl).
pub const ALPHA_TEST: f32 = 0.5;

/// Share of `p`'s texels that pass the alpha test with alpha scaled by `scale`.
fn coverage(p: &Pixels, scale: f32) -> f32 {
    let n = p.rgba.chunks(4).count().max(1);
    let pass = p
        .rgba
        .chunks(4)
        .filter(|c| f32::from(c[3]) / 255.0 * scale >= ALPHA_TEST)
        .count();
    pass as f32 / n as f32
}

/// Scales `p`'s alpha so that the share of texels passing the alpha test
/// is as near `target` as it can be (coverage-preserving mip maps,
/// Castaño 2010): a box-filtered mip of a sparse alpha-tested texture
/// averages its alpha below the threshold and the billboards vanish with
/// distance — a second ring where billboards give way to the ground.
pub fn keep_coverage(p: &mut Pixels, target: f32) {
    // coverage(scale) grows with scale: bisect in [0, 255] (255 brings
    // any texel with alpha ≥ 1/255 over the threshold).
    let (mut lo, mut hi) = (0.0f32, 255.0f32);
    for _ in 0..24 {
        let mid = 0.5 * (lo + hi);
        if coverage(p, mid) < target {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    let (c_lo, c_hi) = (coverage(p, lo), coverage(p, hi));
    let scale = if (c_hi - target).abs() <= (target - c_lo).abs() {
        hi
    } else {
        lo
    };
    for c in p.rgba.chunks_mut(4) {
        c[3] = (f32::from(c[3]) * scale).round().clamp(0.0, 255.0) as u8;
    }
}

/// Uploads `p` and its mip chain as an `Rgba8UnormSrgb` texture; returns
/// its view. A texture with transparent texels keeps its alpha-test
/// coverage down the chain ([`keep_coverage`]); mips are made from the
/// previous level before its alpha was rescaled.
#[must_use]
pub fn upload(
    device: &wgpu::Device,
    queue: &wgpu::Queue,
    label: &str,
    p: Pixels,
) -> wgpu::TextureView {
    let levels = 32 - p.width.max(p.height).leading_zeros();
    let texture = device.create_texture(&wgpu::TextureDescriptor {
        label: Some(label),
        size: wgpu::Extent3d {
            width: p.width,
            height: p.height,
            depth_or_array_layers: 1,
        },
        mip_level_count: levels,
        sample_count: 1,
        dimension: wgpu::TextureDimension::D2,
        format: wgpu::TextureFormat::Rgba8UnormSrgb,
        usage: wgpu::TextureUsages::TEXTURE_BINDING | wgpu::TextureUsages::COPY_DST,
        view_formats: &[],
    });
    let target = coverage(&p, 1.0);
    let mut level = p;
    for mip in 0..levels {
        let mut scaled;
        let upload = if mip > 0 && target < 1.0 {
            scaled = level.clone();
            keep_coverage(&mut scaled, target);
            &scaled
        } else {
            &level
        };
        queue.write_texture(
            wgpu::TexelCopyTextureInfo {
                texture: &texture,
                mip_level: mip,
                origin: wgpu::Origin3d::ZERO,
                aspect: wgpu::TextureAspect::All,
            },
            &upload.rgba,
            wgpu::TexelCopyBufferLayout {
                offset: 0,
                bytes_per_row: Some(upload.width * 4),
                rows_per_image: Some(upload.height),
            },
            wgpu::Extent3d {
                width: upload.width,
                height: upload.height,
                depth_or_array_layers: 1,
            },
        );
        if mip + 1 < levels {
            level = half(&level);
        }
    }
    texture.create_view(&wgpu::TextureViewDescriptor::default())
}

/// A repeating, trilinear sampler.
#[must_use]
pub fn repeat_sampler(device: &wgpu::Device) -> wgpu::Sampler {
    device.create_sampler(&wgpu::SamplerDescriptor {
        label: Some("repeat"),
        address_mode_u: wgpu::AddressMode::Repeat,
        address_mode_v: wgpu::AddressMode::Repeat,
        mag_filter: wgpu::FilterMode::Linear,
        min_filter: wgpu::FilterMode::Linear,
        mipmap_filter: wgpu::MipmapFilterMode::Linear,
        ..Default::default()
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn clump_has_blades_and_holes() {
        let p = grass_clump(3, 6);
        let opaque = p.rgba.chunks(4).filter(|c| c[3] == 255).count();
        let all = (p.width * p.height) as usize;
        assert!(opaque > all / 20 && opaque < all / 2, "{opaque} of {all}");
    }

    #[test]
    fn clump_mips_keep_their_coverage() {
        let p = grass_clump(7, 6);
        let target = coverage(&p, 1.0);
        let mut level = p;
        let mut box_filtered = Vec::new();
        let mut kept = Vec::new();
        while level.width > 4 {
            level = half(&level);
            box_filtered.push(coverage(&level, 1.0));
            let mut scaled = level.clone();
            keep_coverage(&mut scaled, target);
            kept.push(coverage(&scaled, 1.0));
        }
        // Box filtering alone loses the billboards with distance...
        assert!(
            box_filtered.last().unwrap() < &(0.5 * target),
            "{box_filtered:?} against {target}"
        );
        // ...kept coverage holds within a texel's share at every level.
        for (i, c) in kept.iter().enumerate() {
            let texel = 1.0 / ((CLUMP_SIZE >> (i + 1)) as f32).powi(2);
            assert!(
                (c - target).abs() <= 0.05 + texel,
                "mip {}: coverage {c} against {target}",
                i + 1
            );
        }
    }

    #[test]
    fn mip_of_half_transparent_keeps_colour() {
        let p = Pixels {
            width: 2,
            height: 2,
            rgba: vec![200, 100, 50, 255, 0, 0, 0, 0, 200, 100, 50, 255, 0, 0, 0, 0],
        };
        let h = half(&p);
        assert_eq!(h.rgba, vec![200, 100, 50, 128]);
    }
}
