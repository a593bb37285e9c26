//! `--track-png`: a top-down picture of the field after the run, one pixel
//! per cell, coloured by how far the cell's blades are bent: meadow green at
//! rest, straw for bent, dark soil for flattened. DBG cells get a red tint,
//! PBG-only cells a blue one, so the picture shows the track and how far
//! propagation carried it.

use anyhow::{Context, Result};
use trample::Simulation;
use trample::step::BladeClass;

/// The track picture of `sim` as PNG bytes, scaled so the longer side is
/// at least 512 pixels.
pub fn track_png(sim: &Simulation) -> Result<Vec<u8>> {
    let layout = &sim.field.layout;
    let bl = &sim.field.blades;
    let bpc = layout.blades_per_cell as usize;
    let n = bl.segments;
    let [gw, gh] = layout.grid_size();
    let scale = (512 / gw.max(gh).max(1)).max(1);
    let mut img = image::RgbImage::new(gw * scale, gh * scale);
    for c in 0..layout.cell_count() {
        let [gx, gz] = layout.cell_coord(c);
        let (mut standing, mut class) = (0.0f32, 0u8);
        for b in c * bpc..(c + 1) * bpc {
            let rest = bl.rest_vertex(b, n).y - bl.rest_vertex(b, 0).y;
            let now = bl.vertex(b, n).y - bl.vertex(b, 0).y;
            standing += if rest > 0.0 {
                (now / rest).clamp(0.0, 1.0)
            } else {
                1.0
            };
            class = class.max(match sim.class[b] {
                BladeClass::Direct => 2,
                BladeClass::Propagated => 1,
                BladeClass::Untouched => 0,
            });
        }
        let s = standing / bpc as f32;
        // flattened soil → straw → meadow green
        let lerp = |a: [f32; 3], b: [f32; 3], t: f32| [0, 1, 2].map(|i| a[i] + (b[i] - a[i]) * t);
        let mut rgb = if s < 0.5 {
            lerp([70.0, 52.0, 30.0], [196.0, 170.0, 90.0], s * 2.0)
        } else {
            lerp([196.0, 170.0, 90.0], [72.0, 140.0, 52.0], (s - 0.5) * 2.0)
        };
        match class {
            2 => rgb = lerp(rgb, [200.0, 40.0, 40.0], 0.25),
            1 => rgb = lerp(rgb, [60.0, 90.0, 220.0], 0.25),
            _ => {}
        }
        let px = image::Rgb(rgb.map(|v| v.round().clamp(0.0, 255.0) as u8));
        // Image rows run from +z (top) to −z (bottom), as seen from above with x to the right.
        for dy in 0..scale {
            for dx in 0..scale {
                img.put_pixel(gx * scale + dx, (gh - 1 - gz) * scale + dy, px);
            }
        }
    }
    let mut bytes = Vec::new();
    img.write_to(
        &mut std::io::Cursor::new(&mut bytes),
        image::ImageFormat::Png,
    )
    .context("cannot encode the track picture")?;
    Ok(bytes)
}
