//! `--precisions`: an inclusive range `A..B`, one number, or a comma list.

use anyhow::{Result, bail};
use trample::step::params::MAX_PRECISION;

/// Parses `--precisions`: `1..7` (inclusive), `3`, or `1,3,5` (items may
/// themselves be ranges: `1..3,7`). The result is ascending, without
/// repeats. Every value must be a precision the simulation accepts
/// (1..=`MAX_PRECISION`).
pub fn parse_precisions(text: &str) -> Result<Vec<u32>> {
    let bad = |why: &str| -> Result<Vec<u32>> {
        bail!(
            "--precisions {text:?}: {why}; expected a range A..B (inclusive), a number or a comma list, each in 1..={MAX_PRECISION}, e.g. 1..7, 3 or 1,3,5"
        )
    };
    let number = |s: &str| s.trim().parse::<u32>().ok();
    let mut out = Vec::new();
    for item in text.split(',') {
        let item = item.trim();
        if item.is_empty() {
            return bad("empty item");
        }
        let (lo, hi) = match item.split_once("..") {
            Some((a, b)) => {
                // `A..=B` reads the same as `A..B`: both are inclusive here.
                let b = b.strip_prefix('=').unwrap_or(b);
                match (number(a), number(b)) {
                    (Some(a), Some(b)) => (a, b),
                    _ => return bad(&format!("{item:?} is not a range of whole numbers")),
                }
            }
            None => match number(item) {
                Some(p) => (p, p),
                None => return bad(&format!("{item:?} is not a whole number")),
            },
        };
        if lo > hi {
            return bad(&format!("the range {item} is empty"));
        }
        if lo == 0 || hi > MAX_PRECISION {
            return bad(&format!("{item} is out of range"));
        }
        out.extend(lo..=hi);
    }
    out.sort_unstable();
    out.dedup();
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ranges_numbers_and_lists() {
        assert_eq!(
            parse_precisions("1..7").unwrap(),
            (1..=7).collect::<Vec<_>>()
        );
        assert_eq!(parse_precisions("1..=3").unwrap(), vec![1, 2, 3]);
        assert_eq!(parse_precisions("3").unwrap(), vec![3]);
        assert_eq!(parse_precisions("5, 1,3").unwrap(), vec![1, 3, 5]);
        assert_eq!(parse_precisions("1..3,2,7").unwrap(), vec![1, 2, 3, 7]);
        assert_eq!(parse_precisions("4..4").unwrap(), vec![4]);
    }

    #[test]
    fn bad_input_names_the_flag_and_what_is_allowed() {
        for bad in ["", "0..3", "7..1", "a", "1..", "1,,2", "1..33", "-1", "2.5"] {
            let e = parse_precisions(bad).unwrap_err().to_string();
            assert!(e.starts_with("--precisions"), "{bad}: {e}");
            assert!(e.contains("1..=32"), "{bad}: {e}");
            assert!(!e.contains('\n'), "{bad}: {e}");
        }
    }
}
