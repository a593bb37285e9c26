//! Blade storage: structure-of-arrays, vertex-major.
//!
//! The paper keeps vertex k of every blade of a patch in texture k (Eq. 1,
//! Fig. 4). Here "buffer k holds vertex k of every blade": `pos[k * count + b]`
//! is vertex k of blade b, blades patch-major (a patch's blades are one
//! contiguous range), cells row-major inside a patch. The CPU path, the GPU
//! path and the renderer all read this layout without reshuffling.

use glam::Vec3A;

/// Largest supported number of segments per blade (stack arrays are sized by it).
pub const MAX_SEGMENTS: usize = 15;

/// Every blade of the field. Vertex 0 is the root (fixed), vertex `n` the tip.
#[derive(Clone, Debug)]
pub struct Blades {
    /// Number of blades.
    pub count: usize,
    /// Segments per blade (`n`); each blade has `n + 1` vertices.
    pub segments: usize,
    /// Current vertices, vertex-major: `pos[k * count + b]`.
    pub pos: Vec<Vec3A>,
    /// Rest vertices, same layout as `pos`.
    pub rest: Vec<Vec3A>,
    /// Rest length of every segment of blade `b` (all segments of a blade are
    /// equally long, Fig. 7 "the unit length of a segment").
    pub seg_len: Vec<f32>,
    /// Blade width at the root, metres (renderer).
    pub width: Vec<f32>,
    /// Colour variation in [0, 1] (renderer).
    pub tint: Vec<f32>,
}

impl Blades {
    /// Number of vertices per blade, `n + 1`.
    #[must_use]
    pub fn verts_per_blade(&self) -> usize {
        self.segments + 1
    }

    /// Copies blade `b`'s current vertices into `out[..=n]`.
    pub fn load(&self, b: usize, out: &mut [Vec3A]) {
        for (k, v) in out.iter_mut().enumerate().take(self.segments + 1) {
            *v = self.pos[k * self.count + b];
        }
    }

    /// Copies blade `b`'s rest vertices into `out[..=n]`.
    pub fn load_rest(&self, b: usize, out: &mut [Vec3A]) {
        for (k, v) in out.iter_mut().enumerate().take(self.segments + 1) {
            *v = self.rest[k * self.count + b];
        }
    }

    /// Writes `verts[..=n]` as blade `b`'s current vertices.
    pub fn store(&mut self, b: usize, verts: &[Vec3A]) {
        for (k, v) in verts.iter().enumerate().take(self.segments + 1) {
            self.pos[k * self.count + b] = *v;
        }
    }

    /// Vertex `k` of blade `b`.
    #[must_use]
    pub fn vertex(&self, b: usize, k: usize) -> Vec3A {
        self.pos[k * self.count + b]
    }

    /// How far blade `b`'s tip is below its rest tip, metres (negative when
    /// above): what a bend visibly does to a blade. Tests state "tips
    /// lowered by at least d" with it, which, unlike a count of blades hit,
    /// holds only when blades really moved.
    ///
    /// See also [`Blades::tips_lowered_by`].
    #[must_use]
    pub fn tip_lowering(&self, b: usize) -> f32 {
        let tip = self.segments * self.count + b;
        self.rest[tip].y - self.pos[tip].y
    }

    /// Number of blades whose tip is at least `d` metres below its rest tip
    /// ([`Blades::tip_lowering`] `>= d`).
    #[must_use]
    pub fn tips_lowered_by(&self, d: f32) -> usize {
        (0..self.count)
            .filter(|&b| self.tip_lowering(b) >= d)
            .count()
    }

    /// True when blade `b` is bit-for-bit at its rest shape.
    #[must_use]
    pub fn is_at_rest(&self, b: usize) -> bool {
        (0..=self.segments).all(|k| {
            let i = k * self.count + b;
            self.pos[i] == self.rest[i]
        })
    }
}
