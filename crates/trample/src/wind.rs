//! Wind (DESIGN §6, ours): an optional wind field that bends blades and
//! billboards **at draw time**, on top of the interaction state. The
//! simulation state (and its dumps) shows the interaction alone; the
//! renderer's vertex stages evaluate [`tip_offset`] (`blades.wgsl`,
//! `billboards.wgsl`), and this function is their specification.
//!
//! A steady lean of `strength_m` plus gusts: waves of extra lean
//! `gust_m · (½ + ½ sin φ)` that travel downwind,
//! `φ = 2π (t / gust_period_s − (x·d) / gust_wavelength_m)` with `d` the
//! wind direction, so neighbouring blades sway together and a gust crosses
//! the field.

use glam::Vec3;
use serde::{Deserialize, Serialize};

/// `[wind]` table of a scene file. Default: no wind.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct WindParams {
    /// Direction the wind blows towards, degrees from +x towards −z (seen
    /// from above, counter-clockwise, as circle paths turn). Default 0.
    pub direction_deg: f32,
    /// Steady tip displacement of a blade, metres. Default 0 (no wind).
    pub strength_m: f32,
    /// Extra tip displacement at the crest of a gust, metres. Default 0.
    pub gust_m: f32,
    /// Time between two gusts at one place, seconds (> 0). Default 3.
    pub gust_period_s: f32,
    /// Distance between two gust crests, metres (> 0). Default 8.
    pub gust_wavelength_m: f32,
}

impl Default for WindParams {
    fn default() -> Self {
        Self {
            direction_deg: 0.0,
            strength_m: 0.0,
            gust_m: 0.0,
            gust_period_s: 3.0,
            gust_wavelength_m: 8.0,
        }
    }
}

/// Largest tip displacement accepted, metres: a blade is at most about half
/// a metre long, so more would only fold it into the ground.
pub const MAX_WIND_M: f32 = 2.0;

impl WindParams {
    /// Checks every value; the message names the key.
    ///
    /// # Errors
    /// One line: `wind.KEY = VALUE: what is allowed`.
    pub fn validate(&self) -> Result<(), String> {
        let finite = |key: &str, v: f32| {
            if v.is_finite() {
                Ok(())
            } else {
                Err(format!("wind.{key} = {v}: must be a finite number"))
            }
        };
        finite("direction_deg", self.direction_deg)?;
        for (key, v) in [("strength_m", self.strength_m), ("gust_m", self.gust_m)] {
            if !(v.is_finite() && (0.0..=MAX_WIND_M).contains(&v)) {
                return Err(format!("wind.{key} = {v}: must be 0..={MAX_WIND_M} metres"));
            }
        }
        for (key, v) in [
            ("gust_period_s", self.gust_period_s),
            ("gust_wavelength_m", self.gust_wavelength_m),
        ] {
            if !(v.is_finite() && v > 0.0) {
                return Err(format!("wind.{key} = {v}: must be a finite number > 0"));
            }
        }
        Ok(())
    }

    /// Unit direction the wind blows towards (horizontal).
    #[must_use]
    pub fn direction(&self) -> Vec3 {
        let a = self.direction_deg.to_radians();
        Vec3::new(a.cos(), 0.0, -a.sin())
    }

    /// True when the wind moves nothing.
    #[must_use]
    pub fn is_calm(&self) -> bool {
        self.strength_m == 0.0 && self.gust_m == 0.0
    }
}

/// Horizontal displacement of a blade tip rooted at `root` at time
/// `time_s`, metres (see the module documentation). A vertex at fraction `f`
/// of the blade's height moves by `f²` times this (a bend, not a shear).
#[must_use]
pub fn tip_offset(wind: &WindParams, root: Vec3, time_s: f32) -> Vec3 {
    let d = wind.direction();
    let phase = std::f32::consts::TAU
        * (time_s / wind.gust_period_s - root.dot(d) / wind.gust_wavelength_m);
    d * (wind.strength_m + wind.gust_m * (0.5 + 0.5 * phase.sin()))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn calm_moves_nothing() {
        let w = WindParams::default();
        assert!(w.is_calm());
        assert_eq!(tip_offset(&w, Vec3::new(3.0, 0.0, -2.0), 7.5), Vec3::ZERO);
    }

    #[test]
    fn steady_wind_leans_every_blade_downwind_by_its_strength() {
        let w = WindParams {
            direction_deg: 90.0,
            strength_m: 0.1,
            ..WindParams::default()
        };
        for x in [-5.0, 0.0, 12.0] {
            let o = tip_offset(&w, Vec3::new(x, 0.0, x * 0.5), x);
            // 90° from +x towards −z.
            assert!((o - Vec3::new(0.0, 0.0, -0.1)).length() < 1e-6, "{o}");
        }
    }

    #[test]
    fn gusts_stay_within_their_amplitude_and_travel_downwind() {
        let w = WindParams {
            strength_m: 0.05,
            gust_m: 0.2,
            gust_period_s: 2.0,
            gust_wavelength_m: 4.0,
            ..WindParams::default()
        };
        for i in 0..100 {
            let t = i as f32 * 0.07;
            let o = tip_offset(&w, Vec3::new(i as f32 * 0.3, 0.0, 0.0), t).x;
            assert!((0.05 - 1e-6..=0.25 + 1e-6).contains(&o), "{o}");
        }
        // The crest at x = 0, t = 0.5 s is at x = 1 m a quarter period later
        // (wave speed = wavelength / period = 2 m/s).
        let a = tip_offset(&w, Vec3::ZERO, 0.5).x;
        let b = tip_offset(&w, Vec3::new(1.0, 0.0, 0.0), 1.0).x;
        assert!((a - b).abs() < 1e-5, "{a} {b}");
    }

    #[test]
    fn bad_values_name_the_key() {
        let bad = [
            (
                WindParams {
                    strength_m: -1.0,
                    ..WindParams::default()
                },
                "wind.strength_m",
            ),
            (
                WindParams {
                    gust_m: f32::NAN,
                    ..WindParams::default()
                },
                "wind.gust_m",
            ),
            (
                WindParams {
                    gust_period_s: 0.0,
                    ..WindParams::default()
                },
                "wind.gust_period_s",
            ),
            (
                WindParams {
                    gust_wavelength_m: f32::INFINITY,
                    ..WindParams::default()
                },
                "wind.gust_wavelength_m",
            ),
            (
                WindParams {
                    direction_deg: f32::NAN,
                    ..WindParams::default()
                },
                "wind.direction_deg",
            ),
        ];
        for (w, key) in bad {
            let e = w.validate().unwrap_err();
            assert!(e.starts_with(key), "{e}");
        }
    }
}
