//! A host's animated mesh (ours, DESIGN §3 "Deforming meshes": "a host's
//! animated mesh"; issue 13 item 2): the host hands a body its mesh's
//! vertices each frame — skinned, morphed or simulated by the host's own
//! engine, the same triangles — and the body's OBB tree is refitted to
//! them at every sub-step, as a skinned glTF's is (`step/rig.rs`).
//!
//! [`Simulation::set_body_vertices`] is to the mesh what
//! [`Simulation::move_body`] is to the pose: the vertices go from where they
//! are to where the host puts them over the next `dt`, each sub-step taking
//! them in between (linearly), so the surface sweeps the grass on the way
//! and each node's deformation velocity (Eq. 2's contact speed, added to
//! the body's rigid motion) is how fast its box moves.

use glam::Vec3;

use super::bodies::BodyError;
use super::body::BodyId;
use super::simulation::Simulation;
use crate::obb::refit::RefitMap;

/// The host's vertices of a body's mesh over a span of time: `from` at
/// `t0` (where they stood when the host set them), `to` from `t1` on,
/// linear in between.
#[derive(Clone, Debug, Default)]
pub(crate) struct HostVertices {
    /// The vertices at `t0`, the body's local frame.
    pub(crate) from: Vec<Vec3>,
    /// The vertices from `t1` on.
    pub(crate) to: Vec<Vec3>,
    /// The span, seconds of simulated time.
    pub(crate) t0: f32,
    pub(crate) t1: f32,
    /// The farthest any vertex goes from `from` to `to`, m.
    pub(crate) farthest: f32,
}

impl HostVertices {
    /// The vertices at time `t` into `out`: `from` up to `t0`, `to` from
    /// `t1`, `from + (to − from) · s` between (`s` the fraction of the
    /// span), so that `t1` gives `to` bit for bit.
    pub(crate) fn at(&self, t: f32, out: &mut Vec<Vec3>) {
        out.clear();
        let span = self.t1 - self.t0;
        let s = if span > 0.0 {
            ((t - self.t0) / span).clamp(0.0, 1.0)
        } else {
            1.0
        };
        if s >= 1.0 {
            out.extend_from_slice(&self.to);
        } else if s <= 0.0 {
            out.extend_from_slice(&self.from);
        } else {
            out.extend(
                self.from
                    .iter()
                    .zip(&self.to)
                    .map(|(a, b)| *a + (*b - *a) * s),
            );
        }
    }

    /// How fast its farthest vertex goes at time `t`, m/s: the span's
    /// [`HostVertices::farthest`] over its length while it lasts, 0 after
    /// it (the mesh stays where the host put it). What a far turn's cost is
    /// estimated by, as a body's speed is (`step/passes.rs`, `far_work`).
    pub(crate) fn speed_at(&self, t: f32) -> f32 {
        let span = self.t1 - self.t0;
        if span > 0.0 && t < self.t1 {
            self.farthest / span
        } else {
            0.0
        }
    }

    /// The farthest any vertex goes between times `a` and `b` (≥ a): the
    /// share of the span they cover times [`HostVertices::farthest`]. What
    /// the sub-steps are planned by, as a body's travel is
    /// (`step/stages.rs`), so that a mesh the host moves fast sweeps the
    /// grass without skipping blades.
    pub(crate) fn travel_within(&self, a: f32, b: f32) -> f32 {
        let span = self.t1 - self.t0;
        let covered = (b.min(self.t1) - a.max(self.t0)).max(0.0);
        if span > 0.0 {
            self.farthest * (covered / span).min(1.0)
        } else {
            0.0
        }
    }
}

impl Simulation {
    /// Gives body `id`'s mesh new vertex positions: the host's animated
    /// mesh (a skinned character, a morph, a soft body) with the same
    /// triangles. `positions` are the vertices of the mesh the body was
    /// made from, in its order and frame: the host's own triangles for
    /// [`crate::builder::BodyBuilder::mesh`], a file's or a built-in
    /// shape's vertices otherwise. The body bakes them as it baked that
    /// mesh ([`crate::object::SourceVertices`]: the body's `scale` and
    /// `rotation_deg`, its anchor's shift; vertices that sanitising welded
    /// or dropped are taken from the first of them or left out).
    ///
    /// Like [`Simulation::move_body`] for the pose: the mesh goes from its
    /// vertices now to `positions` over the next `dt` seconds, each
    /// sub-step of the step taking it in between, and the body's OBB tree
    /// is refitted at each (same topology; boxes, Eq. 3's EqN and each
    /// node's deformation velocity recomputed: a foot that stamps pushes
    /// with its own speed). Call it once a frame with the frame's `dt`,
    /// before [`Simulation::step`]; the pose is set apart
    /// ([`Simulation::move_body`] or the body's path). The body's own mesh
    /// only: an articulated body's parts are posed with
    /// [`Simulation::set_part_pose`].
    ///
    /// Cost: a refit of the tree per sub-step (BENCHMARKS.md, "Deforming
    /// meshes": ~0.1 ms for a 10,000-triangle character); the body is no
    /// longer taken as standing still while its mesh is the host's (its
    /// contact answers are not reused between sub-steps).
    ///
    /// # Errors
    /// [`BodyError`] (and nothing changes) for an unknown id, a number of
    /// positions other than the source mesh's vertex count, a NaN or
    /// infinite coordinate, given or once scaled (named by its index), `dt`
    /// not finite and > 0, or a body that plays a glTF animation (its
    /// vertices are the animation's).
    pub fn set_body_vertices(
        &mut self,
        id: BodyId,
        positions: &[Vec3],
        dt: f32,
    ) -> Result<(), BodyError> {
        let index = self.index_of(id)?;
        let t = self.time as f32;
        let body = &mut self.bodies[index];
        let problem = |problem: String| BodyError::Vertices { id, problem };
        if body.object.animated.is_some() {
            return Err(problem(
                "the body plays a glTF animation, which sets its vertices; allowed: a body \
                 without `animation`"
                    .into(),
            ));
        }
        let count = body.object.sources.count;
        if positions.len() != count {
            return Err(problem(format!(
                "{} positions given; allowed: exactly {count}, one per vertex of the mesh the body \
                 was made from",
                positions.len()
            )));
        }
        if let Some((k, p)) = positions.iter().enumerate().find(|(_, p)| !p.is_finite()) {
            return Err(problem(format!(
                "position {k} = {p} is not finite; every coordinate must be"
            )));
        }
        if !(dt.is_finite() && dt > 0.0) {
            return Err(problem(format!("dt = {dt}; allowed: finite and > 0")));
        }
        let mut baked = Vec::with_capacity(body.object.mesh.positions.len());
        body.object.sources.bake(positions, &mut baked);
        if let Some((k, p)) = baked.iter().enumerate().find(|(_, p)| !p.is_finite()) {
            return Err(problem(format!(
                "vertex {k} = {p} is not finite once scaled and rotated as the body is; \
                 allowed: positions within range"
            )));
        }
        let rig = &mut body.rig;
        let first = rig.refit_map.is_none();
        if first {
            let map = RefitMap::new(&body.tree, &body.object.mesh).map_err(|e| {
                problem(format!(
                    "the body's tree cannot be refitted to its mesh: {e}"
                ))
            })?;
            rig.refit_map = Some(map);
        }
        // A body that sat out steps (far from the camera, waiting for its
        // turn: `sim.far_every`) goes from the shape its last turn left it
        // in, through the frames it sat out, as `move_body` joins its
        // moves (`step/drive.rs`): its turn sweeps the way the mesh went.
        let t0 = if body.stepped_to < self.time {
            body.stepped_to as f32
        } else {
            t
        };
        let host = rig.host.get_or_insert_with(HostVertices::default);
        host.from.clone_from(&body.object.mesh.positions);
        host.to = baked;
        host.t0 = t0;
        host.t1 = t + dt;
        host.farthest = host
            .from
            .iter()
            .zip(&host.to)
            .map(|(a, b)| a.distance(*b))
            .fold(0.0, f32::max);
        if first {
            // The tree becomes the body's own and takes the form it keeps
            // while deforming (refitted where it stands: no inside grid,
            // no tilted boxes) now, before a step: a GPU path sees the
            // same tree from the start of its next step.
            super::rig::refit_now(body, t);
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_vertices_go_from_the_first_to_the_last_over_the_span() {
        let host = HostVertices {
            from: vec![Vec3::ZERO, Vec3::ONE],
            to: vec![Vec3::X * 0.3, Vec3::ONE * 2.0],
            t0: 1.0,
            t1: 1.1,
            farthest: Vec3::ONE.length(),
        };
        assert_eq!(host.travel_within(0.0, 1.0), 0.0);
        assert!((host.travel_within(1.05, 2.0) - 0.5 * host.farthest).abs() < 1e-5);
        assert!((host.travel_within(0.0, 2.0) - host.farthest).abs() < 1e-6);
        let mut out = Vec::new();
        host.at(0.5, &mut out);
        assert_eq!(out, host.from);
        host.at(1.1, &mut out);
        assert_eq!(out, host.to);
        host.at(7.0, &mut out);
        assert_eq!(out, host.to);
        host.at(1.05, &mut out);
        assert!((out[0] - Vec3::X * 0.15).length() < 1e-6);
        assert!((out[1] - Vec3::ONE * 1.5).length() < 1e-5);
    }
}
