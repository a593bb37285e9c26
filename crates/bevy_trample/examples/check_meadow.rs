//! Checks a screenshot of the `meadow` example (CI runs it on the frame the
//! example saved under Xvfb on lavapipe): the picture is not blank, its
//! lower half is grass (mostly green pixels), the red car and the orange
//! walker are in it, and the grass has no ring round the camera where
//! blades give way to billboards (DESIGN §8: levels of detail blend).
//!
//! ```sh
//! cargo run --release -p bevy_trample --example meadow -- --frames 45 --screenshot meadow.png
//! cargo run --release -p bevy_trample --example check_meadow -- meadow.png
//! ```

use anyhow::{Context, Result, bail};
use image::RgbImage;

/// Share of the lower half's pixels that must be grass-coloured.
const MIN_GRASS_SHARE: f64 = 0.5;
/// Share of the picture's pixels that must be the car's red.
const MIN_CAR_SHARE: f64 = 0.002;
/// Share of the picture's pixels that must be the walker's orange.
const MIN_WALKER_SHARE: f64 = 0.0005;
/// Least standard deviation of the luminance (0..255): a blank or flat
/// picture has about 0.
const MIN_LUMA_STDDEV: f64 = 8.0;
/// Most change of the grass's mean luminance (0..255) over [`RING_ROWS`]
/// rows, in the side strips of the picture below [`RING_FROM`] of its
/// height (the horizon is above): a ring round the camera where blades
/// give way to billboards is a step there. Measured on lavapipe, frame 8,
/// 2026-12-02: 17.3 as shipped (blend bands, billboards lit as the blades
/// look from afar, the grass's ambient occlusion); 15.1 without the
/// occlusion; 20.9 with no blend band and no extra blades
/// (`--hard-switch`; 18.7 before the occlusion); 34.8 with the band and the billboards lit as before (a
/// yellow-green wash past a dark edge); 37.4 with neither; 46.0 on
/// session 60's frame-100 picture, 18.6 on this session's. The blades'
/// own rows change by about 2.
const MAX_RING_STEP: f64 = 28.0;
/// Rows over which [`MAX_RING_STEP`] is measured.
const RING_ROWS: u32 = 24;
/// Share of the height above which the ring is not looked for.
const RING_FROM: f64 = 0.32;
/// The side strips measured: left and right of the car and the walker.
const RING_STRIPS: [(f64, f64); 2] = [(0.0, 0.23), (0.78, 1.0)];

/// Green clearly above red and blue: grass, lit or in shade.
fn is_grass([r, g, b]: [u8; 3]) -> bool {
    let (r, g, b) = (f64::from(r), f64::from(g), f64::from(b));
    g > 20.0 && g > 1.05 * r && g > 1.15 * b
}

/// Red clearly above green and blue: the car's paint.
fn is_car([r, g, b]: [u8; 3]) -> bool {
    let (r, g, b) = (f64::from(r), f64::from(g), f64::from(b));
    r > 50.0 && r > 1.8 * g && r > 1.8 * b
}

/// Orange: red high, green between 0.55 and 0.85 of it, little blue (the
/// car's red has green under 0.56 of its red, grass more green than red,
/// the sky more blue).
fn is_walker([r, g, b]: [u8; 3]) -> bool {
    let (r, g, b) = (f64::from(r), f64::from(g), f64::from(b));
    r > 60.0 && g > 0.58 * r && g < 0.85 * r && b < 0.45 * r
}

/// What was measured, and whether each criterion held.
struct Report {
    luma_stddev: f64,
    grass_share: f64,
    car_share: f64,
    walker_share: f64,
    /// Largest change of the side strips' mean luminance over
    /// [`RING_ROWS`] rows, and the row where it starts.
    ring_step: (f64, u32),
}

fn luma([r, g, b]: [u8; 3]) -> f64 {
    0.2126 * f64::from(r) + 0.7152 * f64::from(g) + 0.0722 * f64::from(b)
}

/// The largest change of the mean luminance of the side strips
/// ([`RING_STRIPS`]) between rows `RING_ROWS` apart, each row's mean
/// averaged over 6 rows, below [`RING_FROM`] of the height; and its row.
fn ring_step(img: &RgbImage) -> (f64, u32) {
    let (w, h) = img.dimensions();
    let columns: Vec<u32> = RING_STRIPS
        .iter()
        .flat_map(|&(a, b)| (a * f64::from(w)) as u32..((b * f64::from(w)) as u32).min(w))
        .collect();
    if columns.is_empty() || h <= RING_ROWS {
        return (0.0, 0);
    }
    let rows: Vec<f64> = (0..h)
        .map(|y| {
            let sum: f64 = columns.iter().map(|&x| luma(img.get_pixel(x, y).0)).sum();
            sum / columns.len() as f64
        })
        .collect();
    let smooth = |y: u32| {
        let (a, b) = (
            y.saturating_sub(3) as usize,
            ((y + 3) as usize).min(rows.len()),
        );
        rows[a..b].iter().sum::<f64>() / (b - a) as f64
    };
    let from = (RING_FROM * f64::from(h)) as u32;
    (from..h - RING_ROWS)
        .map(|y| ((smooth(y) - smooth(y + RING_ROWS)).abs(), y))
        .fold((0.0, 0), |best, s| if s.0 > best.0 { s } else { best })
}

fn measure(img: &RgbImage) -> Report {
    let (w, h) = img.dimensions();
    let n = f64::from(w) * f64::from(h);
    let (mut sum, mut sum2, mut car, mut walker) = (0.0, 0.0, 0u64, 0u64);
    let (mut grass, mut lower) = (0u64, 0u64);
    for (_, y, p) in img.enumerate_pixels() {
        let l = luma(p.0);
        sum += l;
        sum2 += l * l;
        car += u64::from(is_car(p.0));
        walker += u64::from(is_walker(p.0));
        if y >= h / 2 {
            lower += 1;
            grass += u64::from(is_grass(p.0));
        }
    }
    let mean = sum / n.max(1.0);
    Report {
        luma_stddev: (sum2 / n.max(1.0) - mean * mean).max(0.0).sqrt(),
        grass_share: grass as f64 / (lower as f64).max(1.0),
        car_share: car as f64 / n.max(1.0),
        walker_share: walker as f64 / n.max(1.0),
        ring_step: ring_step(img),
    }
}

fn check(img: &RgbImage) -> Result<()> {
    let r = measure(img);
    println!(
        "luminance stddev {:.1} (>= {MIN_LUMA_STDDEV}), grass in the lower half {:.1}% (>= {:.0}%), car {:.2}% (>= {:.1}%), walker {:.3}% (>= {:.2}%), ring step {:.1} at row {} (<= {MAX_RING_STEP})",
        r.luma_stddev,
        100.0 * r.grass_share,
        100.0 * MIN_GRASS_SHARE,
        100.0 * r.car_share,
        100.0 * MIN_CAR_SHARE,
        100.0 * r.walker_share,
        100.0 * MIN_WALKER_SHARE,
        r.ring_step.0,
        r.ring_step.1,
    );
    let mut failed = Vec::new();
    if r.luma_stddev < MIN_LUMA_STDDEV {
        failed.push("the picture is blank");
    }
    if r.grass_share < MIN_GRASS_SHARE {
        failed.push("the lower half is not grass");
    }
    if r.car_share < MIN_CAR_SHARE {
        failed.push("the car is not visible");
    }
    if r.walker_share < MIN_WALKER_SHARE {
        failed.push("the walker is not visible");
    }
    if r.ring_step.0 > MAX_RING_STEP {
        failed.push("a ring round the camera where blades give way to billboards");
    }
    if !failed.is_empty() {
        bail!("{}", failed.join("; "));
    }
    Ok(())
}

fn main() -> Result<()> {
    let path = std::env::args()
        .nth(1)
        .context("usage: check_meadow SCREENSHOT.png")?;
    let img = image::open(&path)
        .with_context(|| format!("{path}: cannot read the screenshot"))?
        .to_rgb8();
    check(&img).with_context(|| format!("{path}: not the meadow"))?;
    println!("{path}: ok");
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn picture(top: [u8; 3], bottom: [u8; 3], car: bool) -> RgbImage {
        walker_picture(top, bottom, car, true)
    }

    fn walker_picture(top: [u8; 3], bottom: [u8; 3], car: bool, walker: bool) -> RgbImage {
        RgbImage::from_fn(64, 64, |x, y| {
            let p = if car && (28..36).contains(&x) && (30..36).contains(&y) {
                [180, 20, 15]
            } else if walker && (40..42).contains(&x) && (26..30).contains(&y) {
                [230, 150, 30]
            } else if y >= 16 {
                // Some texture, as grass has (the horizon a quarter down,
                // as in the meadow).
                let v = ((x * 7 + y * 13) % 20) as u8;
                [bottom[0] + v / 2, bottom[1] + v, bottom[2] + v / 3]
            } else {
                top
            };
            image::Rgb(p)
        })
    }

    #[test]
    fn a_meadow_passes_and_blank_grassless_or_carless_pictures_fail() {
        let sky = [150, 190, 230];
        let green = [40, 90, 20];
        assert!(check(&picture(sky, green, true)).is_ok());
        assert!(
            check(&picture([0, 0, 0], [0, 0, 0], false)).is_err(),
            "blank"
        );
        assert!(
            check(&picture(sky, [90, 80, 70], true)).is_err(),
            "brown ground"
        );
        assert!(check(&picture(sky, green, false)).is_err(), "no car");
        assert!(
            check(&walker_picture(sky, green, true, false)).is_err(),
            "no walker"
        );
    }

    #[test]
    fn a_step_in_the_grass_is_a_ring_and_a_gradient_is_not() {
        let sky = [150, 190, 230];
        let base = picture(sky, [40, 90, 20], true);
        // Lighter grass from row 40 up to the horizon (row 16): a step of
        // 40 levels of green.
        let mut ring = base.clone();
        // The same change spread over the 48 rows below the horizon.
        let mut gradient = base.clone();
        for (_, y, p) in ring.enumerate_pixels_mut() {
            if (16..40).contains(&y) {
                p.0[1] = p.0[1].saturating_add(40);
            }
        }
        for (_, y, p) in gradient.enumerate_pixels_mut() {
            if y >= 16 {
                p.0[1] = p.0[1].saturating_add(((64 - y) * 40 / 48) as u8);
            }
        }
        let (flat, _) = ring_step(&base);
        assert!(flat < 5.0, "{flat}");
        let (step, row) = ring_step(&ring);
        assert!(step > MAX_RING_STEP, "{step} at {row}");
        assert!(check(&ring).is_err());
        let (spread, _) = ring_step(&gradient);
        assert!(spread < MAX_RING_STEP, "{spread}");
        assert!(check(&gradient).is_ok());
    }
}
