//! What the numbers were measured on, and when: recorded in the JSON so a
//! result can be compared with the right row of BENCHMARKS.md.

use serde::Serialize;
use std::time::{SystemTime, UNIX_EPOCH};

/// The machine and the date of a run.
#[derive(Serialize, Debug, Clone)]
pub struct Machine {
    /// CPU model (Linux: `/proc/cpuinfo`), empty where unknown.
    pub cpu: String,
    /// Logical cores the process may use.
    pub cores: usize,
    /// Installed memory, GiB (Linux: `/proc/meminfo`), 0 where unknown.
    pub memory_gib: f64,
    /// Operating system and architecture, e.g. `linux x86_64`.
    pub os: String,
    /// Build profile of this binary: `release` or `debug`.
    pub profile: &'static str,
    /// UTC date of the run, `YYYY-MM-DD`.
    pub date: String,
    /// 1-minute load average when the run started (Linux: `/proc/loadavg`;
    /// -1 where unknown): above the core count, other work shared the CPU
    /// and the times are inflated.
    pub load_average: f64,
}

impl Machine {
    /// Reads the machine and today's date.
    pub fn read() -> Self {
        let cpuinfo = std::fs::read_to_string("/proc/cpuinfo").unwrap_or_default();
        let cpu = cpuinfo
            .lines()
            .find_map(|l| l.strip_prefix("model name"))
            .and_then(|l| l.split_once(':'))
            .map(|(_, v)| v.trim().to_string())
            .unwrap_or_default();
        let meminfo = std::fs::read_to_string("/proc/meminfo").unwrap_or_default();
        let memory_kib: f64 = meminfo
            .lines()
            .find_map(|l| l.strip_prefix("MemTotal:"))
            .and_then(|v| v.trim().trim_end_matches("kB").trim().parse().ok())
            .unwrap_or(0.0);
        let secs = SystemTime::now()
            .duration_since(UNIX_EPOCH)
            .map_or(0, |d| d.as_secs());
        Self {
            cpu,
            cores: std::thread::available_parallelism().map_or(1, usize::from),
            memory_gib: (memory_kib / (1024.0 * 1024.0) * 10.0).round() / 10.0,
            os: format!("{} {}", std::env::consts::OS, std::env::consts::ARCH),
            profile: if cfg!(debug_assertions) {
                "debug"
            } else {
                "release"
            },
            date: civil_date(secs / 86_400),
            load_average: std::fs::read_to_string("/proc/loadavg")
                .ok()
                .and_then(|l| l.split_whitespace().next()?.parse().ok())
                .unwrap_or(-1.0),
        }
    }
}

/// `YYYY-MM-DD` of day `days` since 1970-01-01 (proleptic Gregorian; H.
/// Hinnant's `civil_from_days`).
fn civil_date(days: u64) -> String {
    let z = days as i64 + 719_468;
    let era = z.div_euclid(146_097);
    let doe = z - era * 146_097;
    let yoe = (doe - doe / 1460 + doe / 36_524 - doe / 146_096) / 365;
    let doy = doe - (365 * yoe + yoe / 4 - yoe / 100);
    let mp = (5 * doy + 2) / 153;
    let day = doy - (153 * mp + 2) / 5 + 1;
    let month = if mp < 10 { mp + 3 } else { mp - 9 };
    let year = yoe + era * 400 + i64::from(month <= 2);
    format!("{year:04}-{month:02}-{day:02}")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn dates() {
        assert_eq!(civil_date(0), "1970-01-01");
        assert_eq!(civil_date(11_016), "2000-02-29");
        assert_eq!(civil_date(20_454), "2026-01-01");
    }
}
