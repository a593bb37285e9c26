//! The unit tests' deterministic random numbers: xorshift64 (G. Marsaglia,
//! *Xorshift RNGs*, 2003; shifts 13, 7, 17), one generator for every test
//! module instead of a copy in each.

use glam::Vec3;

/// An xorshift64 generator; the seed must not be 0.
pub(crate) struct XorShift(pub u64);

impl XorShift {
    /// The next 64 bits.
    pub fn next_u64(&mut self) -> u64 {
        self.0 ^= self.0 << 13;
        self.0 ^= self.0 >> 7;
        self.0 ^= self.0 << 17;
        self.0
    }

    /// Uniform in [0, 1), 24 bits (exact in an `f32`).
    pub fn unit(&mut self) -> f32 {
        (self.next_u64() >> 40) as f32 / (1u64 << 24) as f32
    }

    /// Uniform in [`lo`, `hi`).
    pub fn range(&mut self, lo: f32, hi: f32) -> f32 {
        self.unit() * (hi - lo) + lo
    }

    /// Each coordinate uniform in [`lo`, `hi`).
    pub fn vec(&mut self, lo: f32, hi: f32) -> Vec3 {
        let x = self.range(lo, hi);
        let y = self.range(lo, hi);
        Vec3::new(x, y, self.range(lo, hi))
    }
}
