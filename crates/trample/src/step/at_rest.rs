//! Colliders at rest (ours; `sim.reuse_at_rest`): a parked car, a standing
//! character, a ball that stopped keep costing their full narrow phase and
//! contact response every step — 128 parked objects over 16.8 M blades
//! 53–59 ms a step, forever (`scenes/herd_parked.toml`) — although nothing
//! under them changes.
//!
//! Both stages are pure functions of what they read. The narrow phase of a
//! tile ([`super::collide`]) reads the tile's blade vertices and, besides,
//! only the collider's pose and velocities, its tree, the sub-step's length
//! and four parameters ([`RestKey`]); the contact response of one blade
//! ([`crate::deform::contact::resolve_contact`]) reads the blade's vertices,
//! its segment length, its lowest touched segment, the pose and the tree
//! (and the terrain, which a run never changes). So, while a collider's
//! [`RestKey`] is the one of its sub-step before, bit for bit:
//!
//! - the narrow phase keeps each tile's hits with a copy of the tile's
//!   vertices, and a tile whose vertices are still those bits takes its kept
//!   hits instead of being tested again;
//! - the contact response keeps each blade it left as it found it (a blade
//!   at its fixed point: resting against the object, or pinned flat under
//!   it), and a blade found again with the same bits, segment length and
//!   lowest touched segment is left again without a query, counted as moved
//!   or not as it was then.
//!
//! Whatever wrote the blades in between (another object, the recovery,
//! the host), a tile or a blade is reused only when its vertices are the
//! kept bits: the comparison reads them, it trusts no record of writes.
//! The answers are those of the stages, bit for bit (`tests/at_rest.rs`
//! steps scenes with parked, stopping, starting and passing objects with
//! `reuse_at_rest` on and off and compares every blade). A moving collider
//! pays one key comparison a sub-step and keeps nothing; a collider at rest
//! keeps a copy of the vertices of the blades its root box may reach and
//! pays a comparison of them a sub-step instead of its queries (the parked
//! herd: 18 ms a step instead of 54, peak memory unchanged at 4.2 GB).
//! Not for animated bodies (their trees are refitted in place) or in the
//! paper's mode (`sim.track_everywhere = false`, where a cell's level of
//! detail also decides what is tested).

use super::collide::BladeHit;
use crate::field::{BladeVertex, Blades};
use crate::obb::ObbTree;
use crate::object::Pose;
use glam::{Vec3, Vec3A};

/// Everything a collider's narrow phase and contact response read besides
/// the blades, as bits: its pose and velocities, the sub-step's length,
/// `sim.precision`, `sim.contact_shell_m`, the object's press, the reach of
/// its candidate rectangle, and which tree (by address and size: an
/// animated body's tree, refitted in place, is never keyed).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) struct RestKey {
    bits: [u32; 18],
    tree: (usize, usize),
}

impl RestKey {
    /// The key of a collider at `pose` with `tree`, in a sub-step of `h`
    /// seconds. The sub-step's length counts only for a moving collider:
    /// the narrow phase reads it as the travel `speed · h` of the contact
    /// weights' ramp (`LocalMotion::ramp_at`), and Eq. 2's force is
    /// `speed · EqN`, so with no velocity and no spin neither depends on
    /// it — a parked object keeps its work under a host's varying `dt`.
    pub(crate) fn new(
        pose: &Pose,
        tree: &ObbTree,
        h: f32,
        precision: u32,
        shell: f32,
        press: f32,
        reach: f32,
    ) -> Self {
        let h = if is_still(pose) { 0.0 } else { h };
        let mut bits = [0; 18];
        let values = pose
            .position
            .to_array()
            .into_iter()
            .chain(pose.rotation.to_array())
            .chain(pose.velocity.to_array())
            .chain(pose.angular_velocity.to_array())
            .chain([h, shell, press, reach]);
        for (b, v) in bits.iter_mut().zip(values) {
            *b = v.to_bits();
        }
        bits[17] = precision;
        Self {
            bits,
            tree: (std::ptr::from_ref(tree) as usize, tree.nodes.len()),
        }
    }
}

/// Whether a collider at `pose` neither moves nor spins (its velocity and
/// angular velocity are zero): its [`RestKey`] does not depend on the
/// sub-step's length, and it stays the same from one sub-step to the next.
pub(crate) fn is_still(pose: &Pose) -> bool {
    pose.velocity == Vec3::ZERO && pose.angular_velocity == Vec3::ZERO
}

/// Whether `body`'s colliders are keyed ([`RestKey`]) under `params`: with
/// `reuse_at_rest`, in the track-everywhere mode, and not animated (an
/// animated body's tree is refitted in place, as is one whose vertices the
/// host sets: [`super::Body::deforms`]).
pub(crate) fn may_reuse(params: &super::SimParams, body: &super::Body) -> bool {
    params.reuse_at_rest && params.track_everywhere && !body.deforms()
}

/// What a collider kept from its latest sub-steps: while at rest, its
/// narrow phase and contact response; always, its contact response's hints
/// ([`super::contact_hints`]).
#[derive(Clone, Debug, Default)]
pub(crate) struct ColliderMemo {
    /// The closest triangles of the vertices its contact response asked
    /// about last (moving or not).
    pub(crate) hints: super::contact_hints::ContactHints,
    /// The key of the latest sub-step the collider took part in.
    last: Option<RestKey>,
    /// The narrow phase's tiles, with the key they were tested under.
    narrow: Option<NarrowMemo>,
    /// The contact response's blades at their fixed point.
    contact: Option<ContactMemo>,
}

#[derive(Clone, Debug)]
struct NarrowMemo {
    key: RestKey,
    candidates: Vec<u32>,
    tiles: Vec<(u32, u32)>,
    /// The candidates' vertices, world, as tested, tile by tile: each
    /// tile's `n + 1` vertices, each over the tile's blades, as stored
    /// (padding included, so that a vertex compares as one 16-byte word).
    verts: Vec<BladeVertex>,
    /// Each tile's hits.
    hits: Vec<Vec<BladeHit>>,
}

#[derive(Clone, Debug)]
struct ContactMemo {
    key: RestKey,
    kept: RestingBlades,
}

/// The blades the contact response left as it found it, to keep
/// ([`ColliderMemo::keep_blades`]): per blade, ascending, its lowest
/// touched segment, its segment length's bits, whether it counted as
/// moved, and its `stride` vertices. Flat lists whose memory a collider
/// keeps from one sub-step to the next
/// ([`ColliderMemo::resting_buffers`]): a parked herd keeps ~19 k blades
/// a step.
#[derive(Clone, Debug, Default)]
pub(crate) struct RestingBlades {
    blades: Vec<u32>,
    meta: Vec<(u32, u32, bool)>,
    verts: Vec<Vec3>,
    stride: usize,
}

impl RestingBlades {
    /// Adds blade `b` (after every blade added before), its lowest touched
    /// segment `first`, segment length `seg_len`, whether it `moved`, and
    /// its vertices `verts` (`stride` of them).
    pub(crate) fn push(&mut self, b: u32, first: u32, seg_len: f32, moved: bool, verts: &[Vec3A]) {
        self.blades.push(b);
        self.meta.push((first, seg_len.to_bits(), moved));
        self.verts.extend(verts.iter().map(|&v| Vec3::from(v)));
    }
}

/// A tile tested this sub-step, to keep: its vertices (as kept, see
/// [`ColliderMemo::kept_tile`]) and its hits.
pub(crate) type TestedTile = (Vec<BladeVertex>, Vec<BladeHit>);

/// How a collider's narrow phase runs this sub-step.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum NarrowPlan {
    /// Moving, or not keyed: every tile tested, nothing kept.
    Plain,
    /// At rest since the sub-step before: every tile tested and kept.
    Record,
    /// At rest with kept tiles: a tile whose vertices are the kept bits
    /// takes its kept hits; the others are tested and kept.
    Reuse,
}

/// Whether two vertices have the same bits (`==` would take `-0.0` for
/// `0.0`).
fn same_bits(a: Vec3A, b: Vec3) -> bool {
    a.x.to_bits() == b.x.to_bits()
        && a.y.to_bits() == b.y.to_bits()
        && a.z.to_bits() == b.z.to_bits()
}

/// The vertices of `tile`'s blades as a collider at rest keeps them:
/// vertex by vertex, each over the tile's blades — the field's own
/// vertex-major order, so that comparing them ([`same_tile`]) streams
/// through memory.
pub(crate) fn tile_vertices(blades: &Blades, tile: &[u32]) -> Vec<BladeVertex> {
    let mut out = Vec::with_capacity((blades.segments + 1) * tile.len());
    for k in 0..=blades.segments {
        out.extend(
            tile.iter()
                .map(|&b| blades.pos[k * blades.count + b as usize]),
        );
    }
    out
}

/// Whether the vertices of `tile`'s blades in `blades` are `kept`
/// ([`tile_vertices`]), bit for bit: each vertex as stored, padding
/// included, compared as one 16-byte word (a padding that is not 0, which
/// nothing writes, only makes a tile tested again).
fn same_tile(blades: &Blades, tile: &[u32], kept: &[BladeVertex]) -> bool {
    let word = |v: &BladeVertex| bytemuck::cast::<BladeVertex, u128>(*v);
    if tile.is_empty() || kept.len() != (blades.segments + 1) * tile.len() {
        return false;
    }
    kept.chunks_exact(tile.len())
        .enumerate()
        .all(|(k, kept_row)| {
            let Some(row) = blades.pos.get(k * blades.count..(k + 1) * blades.count) else {
                return false;
            };
            tile.iter()
                .zip(kept_row)
                .all(|(&b, kept)| row.get(b as usize).is_some_and(|v| word(v) == word(kept)))
        })
}

/// Whether `verts` (a blade's vertices now) are `kept`, bit for bit.
pub(crate) fn same_vertices(verts: impl IntoIterator<Item = Vec3A>, kept: &[Vec3]) -> bool {
    let mut n = 0;
    for (v, k) in verts.into_iter().zip(kept) {
        if !same_bits(v, *k) {
            return false;
        }
        n += 1;
    }
    n == kept.len()
}

impl ColliderMemo {
    /// The plan of this sub-step for a collider with `key` (`None`: not
    /// keyed) over `candidates` in `tiles`; forgets what a moving collider
    /// kept.
    pub(crate) fn plan(
        &mut self,
        key: Option<RestKey>,
        candidates: &[u32],
        tiles: &[(u32, u32)],
    ) -> NarrowPlan {
        let last = std::mem::replace(&mut self.last, key);
        let Some(key) = key else {
            (self.narrow, self.contact) = (None, None);
            return NarrowPlan::Plain;
        };
        if self
            .narrow
            .as_ref()
            .is_some_and(|m| m.key == key && m.candidates == candidates && m.tiles == tiles)
        {
            return NarrowPlan::Reuse;
        }
        self.narrow = None;
        if last == Some(key) {
            NarrowPlan::Record
        } else {
            self.contact = None;
            NarrowPlan::Plain
        }
    }

    /// The kept hits of tile `t`, whose blades are `tile`, when their
    /// vertices in `blades` are the kept bits (plan [`NarrowPlan::Reuse`],
    /// under which the tiles are the kept ones); a tile's vertices are kept
    /// vertex by vertex, each over the tile's blades (the field's
    /// vertex-major order, [`crate::field::Blades::pos`]), as
    /// [`tile_vertices`] copies them.
    pub(crate) fn kept_tile(&self, t: usize, blades: &Blades, tile: &[u32]) -> Option<&[BladeHit]> {
        let m = self.narrow.as_ref()?;
        let (start, end) = *m.tiles.get(t)?;
        let per = blades.segments + 1;
        let kept = m.verts.get(start as usize * per..end as usize * per)?;
        same_tile(blades, tile, kept).then_some(m.hits[t].as_slice())
    }

    /// Keeps what the narrow phase found under `plan`: for
    /// [`NarrowPlan::Record`] every tile, for [`NarrowPlan::Reuse`] the
    /// tiles it tested again; `tested[t]` is `Some((vertices, hits))` for a
    /// tile tested and kept this sub-step.
    pub(crate) fn keep_tiles(
        &mut self,
        plan: NarrowPlan,
        candidates: &[u32],
        tiles: &[(u32, u32)],
        segments: usize,
        tested: Vec<Option<TestedTile>>,
    ) {
        let per = segments + 1;
        match plan {
            NarrowPlan::Plain => {}
            NarrowPlan::Record => {
                let Some(key) = self.last else { return };
                let mut verts = Vec::with_capacity(candidates.len() * per);
                let mut hits = Vec::with_capacity(tiles.len());
                for t in tested {
                    let Some((v, h)) = t else { return };
                    verts.extend(v);
                    hits.push(h);
                }
                self.narrow = Some(NarrowMemo {
                    key,
                    candidates: candidates.to_vec(),
                    tiles: tiles.to_vec(),
                    verts,
                    hits,
                });
            }
            NarrowPlan::Reuse => {
                let Some(m) = self.narrow.as_mut() else {
                    return;
                };
                for (t, tested) in tested.into_iter().enumerate() {
                    if let Some((v, h)) = tested {
                        let start = m.tiles[t].0 as usize * per;
                        m.verts[start..start + v.len()].copy_from_slice(&v);
                        m.hits[t] = h;
                    }
                }
            }
        }
    }

    /// The kept contact response of blade `b` (lowest touched segment
    /// `first`, segment length `seg_len`, vertices `verts` now) for a
    /// collider keyed `key`: whether it counted as moved, when the blade is
    /// as it was kept.
    pub(crate) fn kept_blade(
        &self,
        key: Option<RestKey>,
        b: u32,
        first: u32,
        seg_len: f32,
        verts: &[Vec3A],
    ) -> Option<bool> {
        let m = self.contact.as_ref().filter(|m| Some(m.key) == key)?;
        let kept = &m.kept;
        if verts.len() != kept.stride {
            return None;
        }
        let i = kept.blades.binary_search(&b).ok()?;
        let (kept_first, kept_len, moved) = kept.meta[i];
        let kept_verts = kept.verts.get(i * kept.stride..(i + 1) * kept.stride)?;
        (kept_first == first
            && kept_len == seg_len.to_bits()
            && same_vertices(verts.iter().copied(), kept_verts))
        .then_some(moved)
    }

    /// Empty lists for the blades to keep this sub-step, of `stride`
    /// vertices each, in the memory of those kept before (taken from this
    /// memo, which keeps nothing until [`ColliderMemo::keep_blades`]).
    pub(crate) fn resting_buffers(&mut self, stride: usize) -> RestingBlades {
        let mut kept = self.contact.take().map(|m| m.kept).unwrap_or_default();
        kept.blades.clear();
        kept.meta.clear();
        kept.verts.clear();
        kept.stride = stride;
        kept
    }

    /// Keeps the contact response's blades at their fixed point
    /// (`resting`, ascending by blade) for a collider keyed `key` (`None`:
    /// nothing kept).
    pub(crate) fn keep_blades(&mut self, key: Option<RestKey>, resting: RestingBlades) {
        self.contact = key.map(|key| ContactMemo { key, kept: resting });
    }

    /// The key under which this collider is at rest this sub-step: its key
    /// when its narrow phase ran under [`NarrowPlan::Record`] or
    /// [`NarrowPlan::Reuse`].
    pub(crate) fn rest_key(&self, plan: NarrowPlan) -> Option<RestKey> {
        (plan != NarrowPlan::Plain).then_some(self.last).flatten()
    }
}
