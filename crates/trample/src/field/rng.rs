//! Counter-based random numbers: the value for (seed, index, stream) does not
//! depend on the order of generation, so a parallel generator gives the same
//! field on any number of threads (DESIGN §2: same seed → same field, bit for bit).

/// splitmix64 finaliser.
#[must_use]
pub fn mix64(mut h: u64) -> u64 {
    h = (h ^ (h >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    h = (h ^ (h >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    h ^ (h >> 31)
}

/// Uniform in [0, 1) for draw `stream` of item `index` under `seed`.
#[must_use]
pub fn unit(seed: u64, index: u64, stream: u64) -> f32 {
    let h = mix64(
        seed ^ mix64(
            index.wrapping_mul(0x9E37_79B9_7F4A_7C15) ^ stream.wrapping_mul(0xD6E8_FEB8_6659_FD93),
        ),
    );
    (h >> 40) as f32 / (1u64 << 24) as f32
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn unit_is_in_range_and_spread() {
        let mut sum = 0.0;
        for i in 0..10_000 {
            let u = unit(3, i, 1);
            assert!((0.0..1.0).contains(&u));
            sum += f64::from(u);
        }
        assert!((sum / 10_000.0 - 0.5).abs() < 0.02);
        assert_ne!(unit(3, 5, 1), unit(3, 5, 2));
        assert_ne!(unit(3, 5, 1), unit(4, 5, 1));
    }
}
