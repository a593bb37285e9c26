//! Line charts of the benchmark results (plotters, bitmap backend), written
//! as PNG. Text is drawn with DejaVu Sans embedded in the binary (the
//! `dejavu` crate through plotters' `ab_glyph` feature), so the charts need
//! no system fonts: a bare machine draws the same picture (checked: with
//! `/usr/share/fonts` hidden behind an empty bind mount, `trample bench`
//! drew the same labels; the binary links no fontconfig or freetype).

use anyhow::{Context, Result, anyhow};
use plotters::coord::Shift;
use plotters::coord::ranged1d::{AsRangedCoord, Ranged, ValueFormatter};
use plotters::prelude::*;
use std::path::Path;
use std::sync::OnceLock;

/// Chart size, pixels.
pub const WIDTH: u32 = 960;
/// Chart size, pixels.
pub const HEIGHT: u32 = 600;

/// The font family the charts ask for.
const FONT: &str = "sans-serif";

/// One line of a chart.
pub struct Series {
    /// Legend text.
    pub name: String,
    /// (x, y) points, in x order.
    pub points: Vec<(f64, f64)>,
    /// Line colour.
    pub color: RGBColor,
}

/// How a chart's axes look.
pub struct Chart<'a> {
    /// Caption above the plot.
    pub title: &'a str,
    /// Axis descriptions.
    pub x_label: &'a str,
    /// Axis descriptions.
    pub y_label: &'a str,
    /// Logarithmic axes.
    pub x_log: bool,
    /// Logarithmic axes.
    pub y_log: bool,
    /// Label the x axis with whole numbers only (precisions).
    pub x_integers: bool,
    /// Where the legend goes (away from the lines).
    pub legend: SeriesLabelPosition,
}

/// Colours of successive series (colour-blind-safe Okabe–Ito hues).
pub const COLORS: [RGBColor; 5] = [
    RGBColor(0, 114, 178),
    RGBColor(213, 94, 0),
    RGBColor(0, 158, 115),
    RGBColor(204, 121, 167),
    RGBColor(86, 180, 233),
];

/// The caption's font size: 24 px, or less for a title that would not fit
/// the picture's width between its margins (a long title was cut at both
/// ends). Not below 12 px.
fn caption_size(root: &DrawingArea<BitMapBackend<'_>, Shift>, title: &str) -> u32 {
    let room = WIDTH.saturating_sub(2 * 16);
    (12..=24)
        .rev()
        .find(|&size| {
            root.estimate_text_size(title, &(FONT, size).into_text_style(root))
                .is_ok_and(|(w, _)| w <= room)
        })
        .unwrap_or(12)
}

/// Draws `series` as lines with dots and writes the PNG to `path`
/// atomically. Axis ranges come from the data (with a margin); log axes
/// need positive values (others are left out).
pub fn line_chart(path: &Path, chart: &Chart<'_>, series: &[Series]) -> Result<()> {
    register_font()?;
    let mut pixels = vec![0u8; (WIDTH * HEIGHT * 3) as usize];
    {
        let root = BitMapBackend::with_buffer(&mut pixels, (WIDTH, HEIGHT)).into_drawing_area();
        root.fill(&WHITE).map_err(draw_err)?;
        let xs = bounds(
            series.iter().flat_map(|s| s.points.iter().map(|p| p.0)),
            chart.x_log,
        );
        let ys = bounds(
            series.iter().flat_map(|s| s.points.iter().map(|p| p.1)),
            chart.y_log,
        );
        let (xs, ys) = (
            pad(xs, chart.x_log, chart.x_integers),
            pad(ys, chart.y_log, false),
        );
        let span = xs.0..xs.1;
        match (chart.x_log, chart.y_log) {
            (false, false) => draw(&root, chart, series, span.clone(), span, ys.0..ys.1),
            (false, true) => draw(
                &root,
                chart,
                series,
                span.clone(),
                span,
                (ys.0..ys.1).log_scale(),
            ),
            (true, false) => draw(
                &root,
                chart,
                series,
                span.clone(),
                span.log_scale(),
                ys.0..ys.1,
            ),
            (true, true) => draw(
                &root,
                chart,
                series,
                span.clone(),
                span.log_scale(),
                (ys.0..ys.1).log_scale(),
            ),
        }?;
        root.present().map_err(draw_err)?;
    }
    let img = image::RgbImage::from_raw(WIDTH, HEIGHT, pixels)
        .ok_or_else(|| anyhow!("chart buffer has the wrong size"))?;
    let mut bytes = Vec::new();
    img.write_to(
        &mut std::io::Cursor::new(&mut bytes),
        image::ImageFormat::Png,
    )?;
    trample::npy::write_atomic(path, &bytes)
        .with_context(|| format!("{}: cannot write", path.display()))
}

/// Registers the embedded font once per process.
fn register_font() -> Result<()> {
    static DONE: OnceLock<bool> = OnceLock::new();
    let ok = *DONE.get_or_init(|| {
        plotters::style::register_font(FONT, FontStyle::Normal, dejavu::sans::regular()).is_ok()
    });
    ok.then_some(())
        .ok_or_else(|| anyhow!("the embedded chart font cannot be read"))
}

fn draw_err<E: std::fmt::Debug>(e: E) -> anyhow::Error {
    anyhow!("cannot draw the chart: {e:?}")
}

/// Smallest and largest finite value (positive only on a log axis); (0, 1)
/// when there is none.
fn bounds(values: impl Iterator<Item = f64>, log: bool) -> (f64, f64) {
    let (lo, hi) = values
        .filter(|v| v.is_finite() && (!log || *v > 0.0))
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), v| {
            (lo.min(v), hi.max(v))
        });
    if lo.is_finite() {
        (lo, hi)
    } else if log {
        (1.0, 10.0)
    } else {
        (0.0, 1.0)
    }
}

/// A margin around the data: a factor on a log axis (more above, where
/// the legend goes), half a unit for whole numbers, 8 % of the span
/// otherwise (a linear axis of values ≥ 0 starts at 0, so heights compare).
fn pad((lo, hi): (f64, f64), log: bool, integers: bool) -> (f64, f64) {
    if log {
        (lo / 1.5, hi * 4.0)
    } else if integers {
        (lo - 0.5, hi + 0.5)
    } else {
        let span = (hi - lo).max(hi.abs() * 0.1).max(1e-9);
        let lo = if lo >= 0.0 { 0.0 } else { lo - 0.08 * span };
        (lo, hi + 0.08 * span)
    }
}

fn draw<X, Y>(
    root: &DrawingArea<BitMapBackend<'_>, Shift>,
    chart: &Chart<'_>,
    series: &[Series],
    x_span: std::ops::Range<f64>,
    x: X,
    y: Y,
) -> Result<()>
where
    X: AsRangedCoord<Value = f64>,
    Y: AsRangedCoord<Value = f64>,
    X::CoordDescType: Ranged<ValueType = f64> + ValueFormatter<f64>,
    Y::CoordDescType: Ranged<ValueType = f64> + ValueFormatter<f64>,
{
    let ctx_x = x_span.clone();
    let mut ctx = ChartBuilder::on(root)
        .caption(chart.title, (FONT, caption_size(root, chart.title)))
        .margin(16)
        .x_label_area_size(56)
        .y_label_area_size(80)
        .build_cartesian_2d(x, y)
        .map_err(draw_err)?;
    let x_fmt = |v: &f64| {
        if chart.x_integers {
            // Whole numbers only: ticks between precisions get no label.
            if (v - v.round()).abs() < 1e-6 {
                format!("{}", v.round())
            } else {
                String::new()
            }
        } else {
            number(*v)
        }
    };
    let y_fmt = |v: &f64| number(*v);
    let mut mesh = ctx.configure_mesh();
    if chart.x_integers {
        // One tick per whole number.
        let (lo, hi) = (ctx_x.start.ceil(), ctx_x.end.floor());
        mesh.x_labels((hi - lo + 1.0).max(2.0) as usize);
    }
    mesh.max_light_lines(4)
        .x_desc(chart.x_label)
        .y_desc(chart.y_label)
        .axis_desc_style((FONT, 18))
        .label_style((FONT, 15))
        .x_label_formatter(&x_fmt)
        .y_label_formatter(&y_fmt)
        .light_line_style(RGBColor(235, 235, 235));
    if chart.x_integers {
        mesh.disable_x_mesh();
    }
    mesh.draw().map_err(draw_err)?;
    for s in series {
        let points: Vec<(f64, f64)> = s
            .points
            .iter()
            .copied()
            .filter(|&(x, y)| {
                x.is_finite()
                    && y.is_finite()
                    && (!chart.x_log || x > 0.0)
                    && (!chart.y_log || y > 0.0)
            })
            .collect();
        let color = s.color;
        ctx.draw_series(LineSeries::new(points.clone(), color.stroke_width(2)))
            .map_err(draw_err)?
            .label(s.name.as_str())
            .legend(move |(x, y)| {
                PathElement::new(vec![(x, y), (x + 24, y)], color.stroke_width(2))
            });
        ctx.draw_series(points.iter().map(|&p| Circle::new(p, 4, color.filled())))
            .map_err(draw_err)?;
    }
    ctx.configure_series_labels()
        .position(chart.legend.clone())
        .label_font((FONT, 16))
        .background_style(WHITE.mix(0.85))
        .border_style(RGBColor(160, 160, 160))
        .draw()
        .map_err(draw_err)?;
    Ok(())
}

/// `n` with thin thousands separators: 262,144.
pub fn thousands(n: u64) -> String {
    let digits = n.to_string();
    let mut out = String::new();
    for (i, c) in digits.chars().enumerate() {
        if i > 0 && (digits.len() - i).is_multiple_of(3) {
            out.push(',');
        }
        out.push(c);
    }
    out
}

/// A short label: 3 significant digits, thousands as k, millions as M.
fn number(v: f64) -> String {
    let a = v.abs();
    let short = |x: f64| {
        let s = if x >= 100.0 {
            format!("{x:.0}")
        } else if x >= 10.0 {
            format!("{x:.1}")
        } else {
            format!("{x:.2}")
        };
        // 2.50 → 2.5, 3.0 → 3
        if s.contains('.') {
            s.trim_end_matches('0').trim_end_matches('.').to_string()
        } else {
            s
        }
    };
    if a >= 1e6 {
        format!("{}M", short(v / 1e6))
    } else if a >= 1e4 {
        format!("{}k", short(v / 1e3))
    } else if a == 0.0 {
        "0".into()
    } else if a < 0.01 {
        format!("{v:.0e}")
    } else {
        short(v)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn labels_are_short() {
        assert_eq!(number(262_144.0), "262k");
        assert_eq!(number(16_777_216.0), "16.8M");
        assert_eq!(number(1280.0), "1280");
        assert_eq!(number(2.5), "2.5");
        assert_eq!(number(0.0), "0");
        assert_eq!(number(0.75), "0.75");
        assert_eq!(thousands(262_144), "262,144");
        assert_eq!(thousands(999), "999");
        assert_eq!(thousands(1_000_000), "1,000,000");
    }

    /// Draws a small chart titled `title` into a temporary folder named
    /// after `tag`; returns the picture.
    fn drawn(title: &str, tag: &str) -> image::RgbImage {
        let dir = std::env::temp_dir().join(format!("trample-chart-{tag}-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let path = dir.join("c.png");
        let chart = Chart {
            title,
            x_label: "precision",
            y_label: "fps",
            x_log: false,
            y_log: true,
            x_integers: true,
            legend: SeriesLabelPosition::UpperRight,
        };
        let s = Series {
            name: "avg".into(),
            points: vec![(1.0, 900.0), (2.0, 800.0), (3.0, 0.0)],
            color: COLORS[0],
        };
        line_chart(&path, &chart, &[s]).unwrap();
        let img = image::open(&path).unwrap().to_rgb8();
        std::fs::remove_dir_all(&dir).unwrap();
        img
    }

    /// The columns of the caption strip (the top 40 rows) that hold dark
    /// text pixels.
    fn caption_columns(img: &image::RgbImage) -> Vec<u32> {
        (0..WIDTH)
            .filter(|&x| (0..40).any(|y| img.get_pixel(x, y).0.iter().all(|&c| c < 100)))
            .collect()
    }

    #[test]
    fn a_chart_is_a_png_of_the_stated_size_with_text() {
        let img = drawn("test", "short");
        assert_eq!(img.dimensions(), (WIDTH, HEIGHT));
        // The caption strip holds dark text pixels (the font rendered).
        let dark = (0..40)
            .flat_map(|y| (0..WIDTH).map(move |x| (x, y)))
            .filter(|&(x, y)| img.get_pixel(x, y).0.iter().all(|&c| c < 100))
            .count();
        assert!(dark > 20, "caption text missing: {dark} dark pixels");
    }

    /// A title too long for the picture at the caption's size is drawn
    /// smaller, whole: no text in the margins (at 24 px this one ran off
    /// both edges, `bench --objects` with far and unseen objects).
    #[test]
    fn a_long_title_fits_between_the_margins() {
        let title = "Step time vs objects (1048576 blades, 300 frames a point, far and unseen objects every 16 steps)";
        let columns = caption_columns(&drawn(title, "long"));
        let (first, last) = (columns[0], columns[columns.len() - 1]);
        assert!(
            first >= 8 && last < WIDTH - 8,
            "the caption spans columns {first}..={last} of {WIDTH}"
        );
    }
}
