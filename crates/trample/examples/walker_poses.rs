//! Draws the walker of `scenes/meshes/walker.glb` skinned at eight times of
//! its "walk" animation, seen from the side (top row) and from the front
//! (bottom row), to a PNG: a check by eye that the rig, the skin weights and
//! the animation load and look right. Orthographic, z-buffered, flat-shaded
//! triangles coloured by the joint that moves them most, on the CPU.
//!
//! ```text
//! cargo run -p trample --example walker_poses -- [OUT.png] [GLB]
//! ```
//!
//! Default output `target/walker_poses.png`.

use glam::{Vec2, Vec3};
use image::{Rgb, RgbImage};
use trample::object::SkinnedMesh;
use trample::object::skin::SkinScratch;

/// Pixels per metre.
const SCALE: f32 = 180.0;
/// One panel, pixels.
const PANEL: (u32, u32) = (200, 330);
/// Poses per row.
const POSES: u32 = 8;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let mut args = std::env::args().skip(1);
    let out = args
        .next()
        .unwrap_or_else(|| "target/walker_poses.png".to_owned());
    let glb = args.next().unwrap_or_else(|| {
        concat!(
            env!("CARGO_MANIFEST_DIR"),
            "/../../scenes/meshes/walker.glb"
        )
        .to_owned()
    });
    let walker = SkinnedMesh::load(std::path::Path::new(&glb))?;
    let walk = walker.animation("walk")?;
    let mut image = RgbImage::from_pixel(PANEL.0 * POSES, PANEL.1 * 2, Rgb([235, 238, 242]));
    let mut depth = vec![f32::NEG_INFINITY; (image.width() * image.height()) as usize];
    let mut scratch = SkinScratch::default();
    let mut posed = Vec::new();
    for k in 0..POSES {
        let t = walk.duration_s * k as f32 / POSES as f32;
        walker.pose_into(Some(walk), t, &mut scratch, &mut posed);
        // Side view from +x: screen right = +z (forward), depth = x.
        draw(&walker, &posed, &mut image, &mut depth, (k, 0), |p| {
            (Vec2::new(p.z, p.y), p.x)
        });
        // Front view from +z: screen right = +x, depth = z.
        draw(&walker, &posed, &mut image, &mut depth, (k, 1), |p| {
            (Vec2::new(p.x, p.y), p.z)
        });
    }
    image.save(&out)?;
    println!(
        "{out}: {} triangles, {} joints, walk {} s, {POSES} poses",
        walker.bind.triangle_count(),
        walker.joints.len(),
        walk.duration_s
    );
    Ok(())
}

/// Rasterises the posed triangles into panel `(column, row)`; `view` maps a
/// point to screen metres (x right, y up) and a depth (larger is nearer).
fn draw(
    walker: &SkinnedMesh,
    posed: &[Vec3],
    image: &mut RgbImage,
    depth: &mut [f32],
    (column, row): (u32, u32),
    view: impl Fn(Vec3) -> (Vec2, f32),
) {
    let origin = Vec2::new(
        (column * PANEL.0 + PANEL.0 / 2) as f32,
        ((row + 1) * PANEL.1 - 15) as f32,
    );
    let width = image.width();
    for tri in &walker.bind.indices {
        let corners = tri.map(|i| posed[i as usize]);
        let normal = (corners[1] - corners[0]).cross(corners[2] - corners[0]);
        let (_, toward) = view(normal);
        let light = 0.35 + 0.65 * (toward / normal.length().max(1e-12)).abs();
        let joint = walker.vertex_joints[tri[0] as usize][0];
        let base = palette(joint);
        let colour = Rgb(base.map(|c| (c as f32 * light) as u8));
        let screen = corners.map(|p| {
            let (s, d) = view(p);
            (origin + Vec2::new(s.x, -s.y) * SCALE, d)
        });
        let lo = screen[0].0.min(screen[1].0).min(screen[2].0).floor();
        let hi = screen[0].0.max(screen[1].0).max(screen[2].0).ceil();
        let area = edge(screen[0].0, screen[1].0, screen[2].0);
        if area.abs() < 1e-9 {
            continue;
        }
        for y in lo.y.max(0.0) as u32..(hi.y.max(0.0) as u32).min(image.height()) {
            for x in lo.x.max(0.0) as u32..(hi.x.max(0.0) as u32).min(width) {
                let p = Vec2::new(x as f32 + 0.5, y as f32 + 0.5);
                let w = [
                    edge(screen[1].0, screen[2].0, p) / area,
                    edge(screen[2].0, screen[0].0, p) / area,
                    edge(screen[0].0, screen[1].0, p) / area,
                ];
                if w.iter().any(|&w| w < 0.0) {
                    continue;
                }
                let z = w[0] * screen[0].1 + w[1] * screen[1].1 + w[2] * screen[2].1;
                let i = (y * width + x) as usize;
                if z > depth[i] {
                    depth[i] = z;
                    image.put_pixel(x, y, colour);
                }
            }
        }
    }
}

/// Twice the signed area of triangle a, b, p.
fn edge(a: Vec2, b: Vec2, p: Vec2) -> f32 {
    (b - a).perp_dot(p - a)
}

/// A colour per joint.
fn palette(joint: u32) -> [u8; 3] {
    const COLOURS: [[u8; 3]; 7] = [
        [200, 90, 70],
        [220, 160, 60],
        [230, 200, 150],
        [70, 120, 200],
        [90, 170, 110],
        [150, 100, 190],
        [60, 170, 180],
    ];
    COLOURS[joint as usize % COLOURS.len()]
}
