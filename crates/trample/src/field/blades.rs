//! Blade storage: structure-of-arrays, vertex-major.
//!
//! The paper keeps vertex k of every blade of a patch in texture k (Eq. 1,
//! Fig. 4). Here "buffer k holds vertex k of every blade": `pos[k * count + b]`
//! is vertex k of blade b, blades patch-major (a patch's blades are one
//! contiguous range), cells row-major inside a patch. The CPU path, the GPU
//! path and the renderer all read this layout without reshuffling.
//!
//! # The layout a host reads
//! Each vertex is one [`BladeVertex`]: 16 bytes, `#[repr(C)]`, `Pod`: x, y,
//! z as native-endian `f32` (metres, world space, y up) and one `f32` of
//! padding that is always 0.0 — the layout of a WGSL
//! `array<vec4<f32>>` and of the GPU path's position buffers.
//! [`Blades::pos_bytes`] hands out the whole array as bytes without a copy:
//! byte offset `16 · (k · count + b)` holds vertex k of blade b. This
//! layout (element type, order and padding) is part of the API: a change
//! to it is a breaking change of the crate.
//!
//! Blades a grass map leaves out (density 0 at their root, or height 0)
//! have zero height: every vertex at the root and `seg_len` 0 (see
//! [`Blades::is_present`]); nothing draws or collides with them.

use super::changes::ChangeSet;
use glam::{Vec3, Vec3A, Vec4};
use rayon::prelude::*;

/// Largest supported number of segments per blade (stack arrays are sized by it).
pub const MAX_SEGMENTS: usize = 15;

/// One blade vertex as stored: world position, metres, and a padding
/// `f32` that is always 0.0, 16 bytes (layout-compatible with a WGSL
/// `vec4<f32>`). See the module docs for the order of the vertices.
///
/// Aligned to 16 bytes, so that loading one into a SIMD [`Vec3A`] is a single
/// aligned load ([`BladeVertex::vec3a`]).
#[repr(C, align(16))]
#[derive(Clone, Copy, Debug, Default, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
pub struct BladeVertex {
    /// x, y, z, metres.
    pub pos: [f32; 3],
    /// Always 0.0 (what the GPU path's buffers hold there too).
    pub pad: f32,
}

const _: () = assert!(std::mem::size_of::<BladeVertex>() == 16);
const _: () = assert!(std::mem::align_of::<BladeVertex>() == 16);

impl BladeVertex {
    /// The vertex at `v` (padding 0).
    #[must_use]
    #[inline]
    pub fn new(v: Vec3A) -> Self {
        bytemuck::cast(v.extend(0.0))
    }

    /// The position as a SIMD vector (what the stages compute with).
    #[must_use]
    #[inline]
    pub fn vec3a(self) -> Vec3A {
        Vec3A::from_vec4(bytemuck::cast::<Self, Vec4>(self))
    }
}

impl From<Vec3A> for BladeVertex {
    fn from(v: Vec3A) -> Self {
        Self::new(v)
    }
}

impl From<Vec3> for BladeVertex {
    fn from(v: Vec3) -> Self {
        Self::new(v.into())
    }
}

impl From<BladeVertex> for Vec3A {
    fn from(v: BladeVertex) -> Self {
        v.vec3a()
    }
}

impl From<BladeVertex> for Vec3 {
    fn from(v: BladeVertex) -> Self {
        Vec3::from_array(v.pos)
    }
}

/// Every blade of the field. Vertex 0 is the root (fixed), vertex `n` the tip.
#[derive(Clone, Debug)]
pub struct Blades {
    /// Number of blades.
    pub count: usize,
    /// Segments per blade (`n`); each blade has `n + 1` vertices.
    pub segments: usize,
    /// Current vertices, vertex-major: `pos[k * count + b]`. Write them
    /// with [`Blades::store`] (or [`Blades::store_slots`]), which records
    /// what changed.
    pub pos: Vec<BladeVertex>,
    /// Rest vertices, same layout as `pos`.
    pub rest: Vec<BladeVertex>,
    /// Rest length of every segment of blade `b` (all segments of a blade are
    /// equally long, Fig. 7 "the unit length of a segment"); 0 for a blade
    /// a grass map left out.
    pub seg_len: Vec<f32>,
    /// Blade width at the root, metres (renderer).
    pub width: Vec<f32>,
    /// Colour variation in [0, 1] (renderer): random per blade, or the
    /// tint map's value at the blade's root.
    pub tint: Vec<f32>,
    /// Blades written by [`Blades::store`] since the last step began
    /// ([`super::Field::changed_blades`]).
    pub(crate) changed: ChangeSet,
}

impl Blades {
    /// Blades at rest: `rest` holds `count · (segments + 1)` vertices in
    /// the vertex-major order (`rest[k * count + b]`), `count` is the
    /// length of `seg_len`; `width` and `tint` have one value per blade.
    ///
    /// # Panics
    /// When the lengths disagree (a programming error, not input).
    #[must_use]
    pub fn new(
        segments: usize,
        rest: Vec<BladeVertex>,
        seg_len: Vec<f32>,
        width: Vec<f32>,
        tint: Vec<f32>,
    ) -> Self {
        let count = seg_len.len();
        assert!(
            rest.len() == count * (segments + 1) && width.len() == count && tint.len() == count,
            "Blades::new: {} vertices, {} widths and {} tints for {count} blades of {segments} segments",
            rest.len(),
            width.len(),
            tint.len()
        );
        // In parallel: the herd's 16.8 M blades hold 1.3 GB of vertices, and
        // the copy's cost is first touching fresh pages (a quarter of the
        // herd's build on one thread).
        let pos = rest.par_iter().copied().collect();
        Self {
            count,
            segments,
            pos,
            rest,
            seg_len,
            width,
            tint,
            changed: ChangeSet::new(count),
        }
    }

    /// Number of vertices per blade, `n + 1`.
    #[must_use]
    pub fn verts_per_blade(&self) -> usize {
        self.segments + 1
    }

    /// Copies blade `b`'s current vertices into `out[..=n]`.
    pub fn load(&self, b: usize, out: &mut [Vec3A]) {
        for (k, v) in out.iter_mut().enumerate().take(self.segments + 1) {
            *v = self.pos[k * self.count + b].vec3a();
        }
    }

    /// Copies blade `b`'s rest vertices into `out[..=n]`.
    pub fn load_rest(&self, b: usize, out: &mut [Vec3A]) {
        for (k, v) in out.iter_mut().enumerate().take(self.segments + 1) {
            *v = self.rest[k * self.count + b].vec3a();
        }
    }

    /// Writes `verts[..=n]` as blade `b`'s current vertices and records
    /// blade `b` as changed in this step ([`super::Field::changed_blades`]).
    pub fn store(&mut self, b: usize, verts: &[Vec3A]) {
        for (k, v) in verts.iter().enumerate().take(self.segments + 1) {
            self.pos[k * self.count + b] = BladeVertex::new(*v);
        }
        self.changed.mark(b);
    }

    /// [`Blades::store`] for many blades: for each `(b, slot)` of
    /// `stored`, blade `b`'s vertices become
    /// `work[slot · (n + 1) ..][..=n]`. The same writes; with many blades
    /// the vertex buffers (one per vertex index, see the module docs) are
    /// written in parallel, each by one thread — a blade's vertices lie a
    /// buffer apart, so a loop over blades misses the caches at every
    /// vertex and, on the herd, took a tenth of the deformation stage.
    ///
    /// # Panics
    /// When a blade or a slot is out of range.
    pub fn store_slots(&mut self, stored: &[(u32, u32)], work: &[Vec3A]) {
        /// Fewer blades than this are written by one thread (a fork costs
        /// more than it saves).
        const PARALLEL_FROM: usize = 2048;
        let (n1, count) = (self.segments + 1, self.count);
        let write = |(k, plane): (usize, &mut [BladeVertex])| {
            for &(b, slot) in stored {
                plane[b as usize] = BladeVertex::new(work[slot as usize * n1 + k]);
            }
        };
        let planes = &mut self.pos[..n1 * count];
        if stored.len() >= PARALLEL_FROM {
            planes.par_chunks_mut(count).enumerate().for_each(write);
        } else {
            planes.chunks_mut(count).enumerate().for_each(write);
        }
        for &(b, _) in stored {
            self.changed.mark(b as usize);
        }
    }

    /// Vertex `k` of blade `b`.
    #[must_use]
    pub fn vertex(&self, b: usize, k: usize) -> Vec3A {
        self.pos[k * self.count + b].vec3a()
    }

    /// Rest vertex `k` of blade `b`.
    #[must_use]
    pub fn rest_vertex(&self, b: usize, k: usize) -> Vec3A {
        self.rest[k * self.count + b].vec3a()
    }

    /// How far blade `b`'s tip is below its rest tip, metres (negative when
    /// above): what a bend visibly does to a blade. Tests state "tips
    /// lowered by at least d" with it, which, unlike a count of blades hit,
    /// holds only when blades really moved.
    ///
    /// See also [`Blades::tips_lowered_by`].
    #[must_use]
    pub fn tip_lowering(&self, b: usize) -> f32 {
        self.rest_vertex(b, self.segments).y - self.vertex(b, self.segments).y
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

    /// True when blade `b` is grass: a grass map (density 0 at its root,
    /// or height 0) did not leave it out. Absent blades have zero height
    /// and are never collided, bent or propagated through.
    #[must_use]
    pub fn is_present(&self, b: usize) -> bool {
        self.seg_len[b] > 0.0
    }

    /// Every current vertex as bytes, without a copy: the layout of the
    /// module docs (`16 · (k · count + b)` is vertex k of blade b).
    #[must_use]
    pub fn pos_bytes(&self) -> &[u8] {
        bytemuck::cast_slice(&self.pos)
    }

    /// Every rest vertex as bytes, same layout as [`Blades::pos_bytes`].
    #[must_use]
    pub fn rest_bytes(&self) -> &[u8] {
        bytemuck::cast_slice(&self.rest)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::test_rng::XorShift;

    /// `store_slots` writes what `store` writes, blade by blade, and marks
    /// the same blades changed, with few blades (one thread) and with many
    /// (the vertex buffers in parallel); blades not listed keep their
    /// vertices.
    #[test]
    fn storing_by_slots_writes_what_storing_each_blade_does() {
        let mut rng = XorShift(0x9e37_79b9_7f4a_7c15);
        let (n, count) = (4, 6000);
        let rest: Vec<BladeVertex> = (0..count * (n + 1))
            .map(|_| BladeVertex::from(Vec3::new(rng.unit(), rng.unit(), rng.unit())))
            .collect();
        let base = Blades::new(
            n,
            rest,
            vec![0.1; count],
            vec![0.01; count],
            vec![0.5; count],
        );
        for listed in [10, 5000] {
            let mut blades: Vec<u32> = (0..count as u32).collect();
            // A random subset of `listed` blades, in a random order.
            for i in 0..listed {
                let j = i + (rng.unit() * (count - i) as f32) as usize % (count - i);
                blades.swap(i, j);
            }
            blades.truncate(listed);
            let slots = listed + 7;
            let work: Vec<Vec3A> = (0..slots * (n + 1))
                .map(|_| Vec3A::new(rng.unit(), rng.unit(), rng.unit()))
                .collect();
            let stored: Vec<(u32, u32)> = blades
                .iter()
                .map(|&b| (b, (rng.unit() * slots as f32) as u32 % slots as u32))
                .collect();
            let (mut one, mut all) = (base.clone(), base.clone());
            for &(b, slot) in &stored {
                let s = slot as usize * (n + 1);
                one.store(b as usize, &work[s..=s + n]);
            }
            all.store_slots(&stored, &work);
            assert!(one.pos == all.pos, "{listed} blades: the same vertices");
            assert_eq!(one.changed, all.changed, "{listed} blades: the same marks");
            assert_eq!(all.changed.len(), listed);
        }
    }
}
