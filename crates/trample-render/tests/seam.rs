//! Seamless levels of detail (issue 15 item 1, "Seam"): on frame 0
//! (640×360) of the default scene and of `scenes/car.toml`, the colour step
//! of the shaded frame across the blade/billboard boundary, found from the
//! classes view, is at most 2× the same step measured inside the blade
//! zone; the same across the billboard/texture boundary against the step
//! inside the billboard zone. Before the blend bands (issue 15 item 1) the
//! default scene measured 4.1 and 3.5 here (the issue's own measure said
//! 7.9 for the first: a ring round the camera). Runs on the adapter of
//! `WGPU_BACKEND`; no adapter = failure. `TRAMPLE_SEAM_DUMP=DIR` writes the
//! frames measured.

mod common;

use std::path::Path;
use trample::Simulation;
use trample::scene::Scene;
use trample_render::{DebugView, Renderer};

const W: u32 = 640;
const H: u32 = 360;
/// Columns per block: the boundary is found and the colours averaged
/// block by block (the boundary is a curve in the image).
const BLOCK: u32 = 16;
/// Allowed ratio of the step across a boundary to the step inside a zone.
const MAX_RATIO: f64 = 2.0;
/// Rows a window at the blade/billboard boundary.
const ROWS: u32 = 6;
/// Rows a window at the billboard/texture boundary: the billboard band is
/// 20–40 rows high at 640×360, and near the horizon a row spans metres
/// (the fog's gradient is steep there).
const FAR_ROWS: u32 = 4;

/// What a pixel of the classes view shows.
#[derive(Clone, Copy, PartialEq, Eq)]
enum Class {
    /// Untouched blade (green).
    Blade,
    /// Billboard (yellow).
    Billboard,
    /// Texture-level ground (grey).
    Texture,
    /// Ground between blades (dark).
    Ground,
    /// Anything else: objects, touched blades (red, blue), sky.
    Other,
}

fn class_of(p: &image::Rgba<u8>) -> Class {
    let [r, g, b] = [i32::from(p[0]), i32::from(p[1]), i32::from(p[2])];
    if r > 100 && g > 95 && r >= g - 5 && r > b + 50 {
        Class::Billboard
    } else if g > 85 && g > r + 25 && g > b + 25 {
        Class::Blade
    } else if (r - g).abs() < 30 && (g - b).abs() < 40 && r > 110 && r < 220 {
        Class::Texture
    } else if r < 90 && g < 95 && b < 80 && g >= b {
        Class::Ground
    } else {
        Class::Other
    }
}

/// Mean sRGB colour of the shaded frame over columns `xs` and rows `ys`.
fn mean(frame: &image::RgbaImage, xs: std::ops::Range<u32>, ys: std::ops::Range<u32>) -> [f64; 3] {
    let mut s = [0.0; 3];
    let mut n = 0.0;
    for y in ys {
        for x in xs.clone() {
            let p = frame.get_pixel(x, y);
            for c in 0..3 {
                s[c] += f64::from(p[c]);
            }
            n += 1.0;
        }
    }
    s.map(|v| v / n)
}

/// Sum over RGB of the absolute difference (0–765).
fn step(a: [f64; 3], b: [f64; 3]) -> f64 {
    (0..3).map(|c| (a[c] - b[c]).abs()).sum()
}

/// The two seams' measures, each (step across, step inside, blocks used).
struct Seams {
    blade_billboard: (f64, f64, usize),
    billboard_texture: (f64, f64, usize),
}

fn render(sim: &Simulation, debug: DebugView, bands: bool) -> image::RgbaImage {
    let gpu = trample_render::headless::create_device()
        .unwrap_or_else(|e| panic!("the seam test needs an adapter: {e}"));
    let params = common::test_params(&gpu, W, H, debug);
    let params = if bands {
        params
    } else {
        params.without_blend_bands()
    };
    Renderer::new(&gpu.device, &gpu.queue, sim, params)
        .unwrap()
        .render(&gpu.device, &gpu.queue, sim)
        .unwrap()
}

/// Pixels of the block on row `y` of class `c`.
fn count(classes: &[Vec<Class>], x0: u32, y: u32, c: Class) -> usize {
    let row = &classes[y as usize];
    (x0..x0 + BLOCK).filter(|&x| row[x as usize] == c).count()
}

/// Share of the block's pixels over rows `ys` that are grass or ground
/// (not an object, a touched blade or the sky).
fn clean(classes: &[Vec<Class>], x0: u32, ys: std::ops::Range<u32>) -> bool {
    let rows = ys.len() as f64;
    let ok = ys
        .flat_map(|y| (x0..x0 + BLOCK).map(move |x| (x, y)))
        .filter(|&(x, y)| classes[y as usize][x as usize] != Class::Other)
        .count();
    ok as f64 >= 0.9 * rows * f64::from(BLOCK)
}

/// The first row, walking up from `from`, where `c` makes at least half
/// of the block's pixels of classes `among` (`c` included) over three rows.
fn boundary(classes: &[Vec<Class>], x0: u32, from: u32, c: Class, among: &[Class]) -> Option<u32> {
    (3..=from).rev().find(|&y| {
        let of = |k: Class| -> usize { (y - 2..=y).map(|r| count(classes, x0, r, k)).sum() };
        let all: usize = among.iter().map(|&k| of(k)).sum();
        all > 0 && 2 * of(c) >= all
    })
}

/// Measures the seams of `sim`'s frame 0, [`ROWS`] and [`FAR_ROWS`] rows
/// per window; `bands`: the renderer's blend bands on, or the hard switch.
fn seams(sim: &Simulation, name: &str, bands: bool) -> Seams {
    let k = ROWS;
    let name = &format!("{name}{}", if bands { "" } else { "-no-bands" });
    let shaded = render(sim, DebugView::None, bands);
    let debug = render(sim, DebugView::Classes, bands);
    if let Ok(dir) = std::env::var("TRAMPLE_SEAM_DUMP") {
        let dir = Path::new(&dir);
        std::fs::create_dir_all(dir).unwrap();
        shaded.save(dir.join(format!("{name}-shaded.png"))).unwrap();
        debug.save(dir.join(format!("{name}-classes.png"))).unwrap();
    }
    let classes: Vec<Vec<Class>> = (0..H)
        .map(|y| (0..W).map(|x| class_of(debug.get_pixel(x, y))).collect())
        .collect();
    let mut bb = (0.0, 0.0, 0usize);
    let mut bt = (0.0, 0.0, 0usize);
    for x0 in (0..W).step_by(BLOCK as usize) {
        let xs = x0..x0 + BLOCK;
        let Some(yb) = boundary(
            &classes,
            x0,
            H - 1,
            Class::Billboard,
            &[Class::Billboard, Class::Blade],
        ) else {
            continue;
        };
        // Blade/billboard: windows above (billboards) and below (blades)
        // the boundary, and two more windows further down, inside the
        // blade zone.
        if yb >= k && yb + 3 * k <= H && clean(&classes, x0, yb - k..yb + 3 * k) {
            let above = mean(&shaded, xs.clone(), yb - k..yb);
            let below = mean(&shaded, xs.clone(), yb..yb + k);
            let in1 = mean(&shaded, xs.clone(), yb + k..yb + 2 * k);
            let in2 = mean(&shaded, xs.clone(), yb + 2 * k..yb + 3 * k);
            bb.0 += step(above, below);
            bb.1 += step(in1, in2);
            bb.2 += 1;
        }
        // Billboard/texture: the first grey rows above the billboards,
        // and two windows inside the billboard zone below them.
        let Some(yt) = boundary(
            &classes,
            x0,
            yb.saturating_sub(1),
            Class::Texture,
            &[Class::Texture, Class::Billboard, Class::Ground],
        ) else {
            continue;
        };
        let k = FAR_ROWS;
        if yt >= k && yt + 3 * k <= yb && clean(&classes, x0, yt - k..yt + 3 * k) {
            let above = mean(&shaded, xs.clone(), yt - k..yt);
            let below = mean(&shaded, xs.clone(), yt..yt + k);
            let in1 = mean(&shaded, xs.clone(), yt + k..yt + 2 * k);
            let in2 = mean(&shaded, xs.clone(), yt + 2 * k..yt + 3 * k);
            bt.0 += step(above, below);
            bt.1 += step(in1, in2);
            bt.2 += 1;
        }
    }
    let avg = |(a, b, n): (f64, f64, usize)| (a / n.max(1) as f64, b / n.max(1) as f64, n);
    let s = Seams {
        blade_billboard: avg(bb),
        billboard_texture: avg(bt),
    };
    for (what, (across, inside, n)) in [
        ("blade/billboard", s.blade_billboard),
        ("billboard/texture", s.billboard_texture),
    ] {
        eprintln!(
            "{name}: {what} step {across:.1} across, {inside:.1} inside, ratio {:.2} ({n} blocks of {BLOCK} columns)",
            across / inside
        );
    }
    s
}

fn frame0(toml_path: &str, edit: impl Fn(String) -> String) -> Simulation {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../..");
    let path = root.join(toml_path);
    let text = edit(std::fs::read_to_string(&path).unwrap());
    let mut sim = Scene::parse(&text, toml_path, path.parent().unwrap())
        .unwrap()
        .build()
        .unwrap();
    sim.step(sim.params.dt_s).unwrap();
    sim
}

/// Both ratios of `s` within [`MAX_RATIO`], and the near blend band at
/// least 30 % better than the hard switch (`hard`), so that the test fails
/// without the band. (The ambient occlusion of issue 15 item 3 darkens the
/// billboards' bases and brought the hard switch's ratio itself to 1.8–2.0
/// from 2.4–2.9.)
fn check(name: &str, s: &Seams, hard: &Seams) {
    let ratio = |(a, b, _): (f64, f64, usize)| a / b;
    assert!(
        ratio(s.blade_billboard) <= 0.7 * ratio(hard.blade_billboard),
        "{name}: the blend band's blade/billboard ratio {:.2} is not 30 % below the hard switch's {:.2}",
        ratio(s.blade_billboard),
        ratio(hard.blade_billboard)
    );
    for (what, (across, inside, n)) in [
        ("blade/billboard", s.blade_billboard),
        ("billboard/texture", s.billboard_texture),
    ] {
        assert!(
            n >= 8,
            "{name}: the {what} boundary was found in {n} blocks only"
        );
        assert!(
            across <= MAX_RATIO * inside,
            "{name}: the colour step across the {what} boundary is {across:.1}, {:.2}× the step inside the zone ({inside:.1}; at most {MAX_RATIO}×)",
            across / inside
        );
    }
}

#[test]
fn no_ring_on_the_default_scene() {
    let sim = frame0("scenes/default.toml", |t| t);
    let hard = seams(&sim, "default", false);
    check("default", &seams(&sim, "default", true), &hard);
}

#[test]
fn no_ring_on_the_car_scene() {
    let sim = frame0("scenes/car.toml", |t| t);
    let hard = seams(&sim, "car", false);
    check("car", &seams(&sim, "car", true), &hard);
}

/// In both scenes above the billboards end at the field's far edge, a
/// little before `lod.billboard_m`: the billboard/texture boundary measured
/// there is the field's edge. With `billboard_m` at 22 m the default
/// scene's billboards give way to the ground inside the field (the far
/// blend band, [`RenderParams::texture_blend_m`]).
#[test]
fn no_ring_where_billboards_give_way_to_the_ground() {
    let sim = frame0("scenes/default.toml", |t| {
        let edited = t.replace("billboard_m = 30.0", "billboard_m = 22.0");
        assert_ne!(edited, t, "scenes/default.toml's billboard_m moved");
        edited
    });
    let hard = seams(&sim, "default-22m", false);
    check("default-22m", &seams(&sim, "default-22m", true), &hard);
}
