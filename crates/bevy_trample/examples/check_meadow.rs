//! Checks a screenshot of the `meadow` example (CI runs it on the frame the
//! example saved under Xvfb on lavapipe): the picture is not blank, its
//! lower half is grass (mostly green pixels), and the red car and the
//! orange walker are in it.
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
}

fn measure(img: &RgbImage) -> Report {
    let (w, h) = img.dimensions();
    let n = f64::from(w) * f64::from(h);
    let (mut sum, mut sum2, mut car, mut walker) = (0.0, 0.0, 0u64, 0u64);
    let (mut grass, mut lower) = (0u64, 0u64);
    for (_, y, p) in img.enumerate_pixels() {
        let [r, g, b] = p.0;
        let l = 0.2126 * f64::from(r) + 0.7152 * f64::from(g) + 0.0722 * f64::from(b);
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
    }
}

fn check(img: &RgbImage) -> Result<()> {
    let r = measure(img);
    println!(
        "luminance stddev {:.1} (>= {MIN_LUMA_STDDEV}), grass in the lower half {:.1}% (>= {:.0}%), car {:.2}% (>= {:.1}%), walker {:.3}% (>= {:.2}%)",
        r.luma_stddev,
        100.0 * r.grass_share,
        100.0 * MIN_GRASS_SHARE,
        100.0 * r.car_share,
        100.0 * MIN_CAR_SHARE,
        100.0 * r.walker_share,
        100.0 * MIN_WALKER_SHARE
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
            } else if y >= 32 {
                // Some texture, as grass has.
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
}
