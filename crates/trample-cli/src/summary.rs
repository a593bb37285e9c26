//! `summary.json`: what a run did and how long each part took.

use serde::Serialize;
use std::collections::BTreeMap;
use trample::StepTimings;

/// min / median / mean / max of a series, milliseconds.
#[derive(Serialize, Debug, Default, Clone, Copy)]
pub struct Stats {
    pub min: f64,
    pub median: f64,
    pub mean: f64,
    pub max: f64,
}

impl Stats {
    /// Statistics of `v` (all zero when empty).
    pub fn of(v: &[f64]) -> Self {
        if v.is_empty() {
            return Self::default();
        }
        let mut s = v.to_vec();
        s.sort_by(f64::total_cmp);
        let median = if s.len() % 2 == 1 {
            s[s.len() / 2]
        } else {
            0.5 * (s[s.len() / 2 - 1] + s[s.len() / 2])
        };
        Self {
            min: s[0],
            median,
            mean: s.iter().sum::<f64>() / s.len() as f64,
            max: s[s.len() - 1],
        }
    }
}

/// Collects every step's timings.
#[derive(Default)]
pub struct Recorder {
    pub steps: Vec<StepTimings>,
}

impl Recorder {
    /// Step times, milliseconds.
    pub fn step_ms(&self) -> Stats {
        Stats::of(&self.steps.iter().map(|t| t.total_ms).collect::<Vec<_>>())
    }

    /// Median of each stage, milliseconds, by stage name.
    pub fn stages_ms(&self) -> BTreeMap<&'static str, f64> {
        let mut out = BTreeMap::new();
        if let Some(first) = self.steps.first() {
            for (i, (name, _)) in first.stages().iter().enumerate() {
                let v: Vec<f64> = self.steps.iter().map(|t| t.stages()[i].1).collect();
                out.insert(*name, Stats::of(&v).median);
            }
        }
        out
    }
}

/// Peak resident memory of this process, MiB: `VmHWM` of
/// `/proc/self/status` (Linux); `None` where that cannot be read.
pub fn peak_rss_mib() -> Option<f64> {
    let status = std::fs::read_to_string("/proc/self/status").ok()?;
    let line = status.lines().find(|l| l.starts_with("VmHWM:"))?;
    let kib: f64 = line.split_whitespace().nth(1)?.parse().ok()?;
    Some(kib / 1024.0)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn stats_of_a_series() {
        let s = Stats::of(&[3.0, 1.0, 2.0, 10.0]);
        assert_eq!((s.min, s.median, s.mean, s.max), (1.0, 2.5, 4.0, 10.0));
        assert_eq!(Stats::of(&[5.0]).median, 5.0);
    }

    #[test]
    fn peak_rss_is_read_on_linux() {
        let mib = peak_rss_mib().expect("/proc/self/status has VmHWM");
        assert!(mib > 1.0 && mib < 1e6, "{mib}");
    }
}
