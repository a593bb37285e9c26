//! Bodies joining and leaving a running simulation (issue 14), found by
//! their stable [`BodyId`].
//!
//! A body added at time t is posed at t (its path's clock is simulation
//! time: give it `start_s = t` to start its path now) and collides from the
//! next step on; it appears where it is, without sweeping the grass on the
//! way there. A removed body stops acting at once; the blades it left bent
//! are displaced blades like any others and recover at the next steps with
//! `[sim]`'s `recovery_s` and `trail` (its own track settings go with it;
//! with the paper's `recovery_s = inf` its track stays).

use super::body::{Body, BodyId};
use super::simulation::Simulation;
use crate::camera::CameraTarget;

/// A body operation that named a body the simulation does not have, or
/// gave a pose that is not finite.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum BodyError {
    /// No body has this id (never added, or removed).
    #[error("{id}: no such body in the simulation (bodies: {known:?})")]
    Unknown {
        /// The id asked for.
        id: BodyId,
        /// The ids the simulation has.
        known: Vec<u32>,
    },
    /// No part of the body has this name or index, or the part's joint is
    /// not a `host` joint.
    #[error("{id}: part {part}: {problem}; allowed: {allowed}")]
    Part {
        /// The body.
        id: BodyId,
        /// The part as asked for (a quoted name or an index).
        part: String,
        /// What is wrong.
        problem: &'static str,
        /// The parts with `host` joints, or what else is allowed.
        allowed: String,
    },
    /// A position, rotation or time step with a NaN or infinite value.
    #[error("{id}: {what}: every value must be finite{extra}")]
    NotFinite {
        /// The body.
        id: BodyId,
        /// What was given, e.g. `position = [NaN, 0, 0]`.
        what: String,
        /// More of what is allowed (e.g. `; dt > 0`).
        extra: &'static str,
    },
    /// Vertices the host gave a body's mesh
    /// ([`Simulation::set_body_vertices`]) that it cannot take.
    #[error("{id}: set_body_vertices: {problem}")]
    Vertices {
        /// The body.
        id: BodyId,
        /// What is wrong and what is allowed.
        problem: String,
    },
}

/// The track owners after the bodies `before` became `after` (ids in
/// body order; [`Simulation::track_owner`] holds 1 + a body's index, 0 for
/// `[sim]`): `table[o]` is old owner `o`'s new number. A body still there
/// keeps its blades under its new index; a body gone gives them to `[sim]`
/// (0), as do owners past the table (over 254 bodies) and owner 0. The
/// CPU's [`Simulation::remove_body`] and the GPU path (which renumbers its
/// own copy of the owners when it sees the bodies change) both use it.
#[must_use]
pub fn renumbered_owners(before: &[BodyId], after: &[BodyId]) -> [u8; 256] {
    let mut table = [0u8; 256];
    for (index, id) in before.iter().enumerate().take(255) {
        table[index + 1] = after
            .iter()
            .position(|a| a == id)
            .and_then(|i| u8::try_from(i + 1).ok())
            .unwrap_or(0);
    }
    table
}

impl Simulation {
    /// Adds `body` at the current time and returns its new id (never one a
    /// removed body had). It is posed at the current time at once; it acts
    /// on the grass from the next [`Simulation::step`].
    pub fn add_body(&mut self, mut body: Body) -> BodyId {
        let id = BodyId(self.next_body_id);
        self.next_body_id = self.next_body_id.wrapping_add(1);
        body.id = id;
        body.set_time(self.time as f32);
        body.stepped_to = self.time;
        self.bodies.push(body);
        id
    }

    /// Removes the body `id` and gives it back. The blades it bent stay
    /// displaced and recover normally, with `[sim]`'s `recovery_s` and
    /// `trail` (its own track settings went with it); a scene camera that
    /// followed it keeps looking where it was; the other bodies keep their
    /// ids (and the blades they pressed, their track settings).
    ///
    /// # Errors
    /// [`BodyError::Unknown`] when there is no such body.
    pub fn remove_body(&mut self, id: BodyId) -> Result<Body, BodyError> {
        let index = self.index_of(id)?;
        let before: Vec<BodyId> = self.bodies.iter().map(|b| b.id).collect();
        let body = self.bodies.remove(index);
        let after: Vec<BodyId> = self.bodies.iter().map(|b| b.id).collect();
        let table = renumbered_owners(&before, &after);
        for o in &mut self.track_owner {
            *o = table[usize::from(*o)];
        }
        if let CameraTarget::Object(i) = self.camera.target {
            self.camera.target = match i.cmp(&index) {
                std::cmp::Ordering::Less => CameraTarget::Object(i),
                std::cmp::Ordering::Equal => CameraTarget::Point(body.pose.position),
                std::cmp::Ordering::Greater => CameraTarget::Object(i - 1),
            };
        }
        Ok(body)
    }

    /// The body `id`, if the simulation has it.
    #[must_use]
    pub fn body(&self, id: BodyId) -> Option<&Body> {
        self.bodies.iter().find(|b| b.id == id)
    }

    /// The body `id`, mutable (to change its parameters; see
    /// [`Simulation::move_body`] and [`Simulation::teleport_body`] to move it).
    pub fn body_mut(&mut self, id: BodyId) -> Option<&mut Body> {
        self.bodies.iter_mut().find(|b| b.id == id)
    }

    /// Where the body `id` is in [`Simulation::bodies`] now (indices shift
    /// when an earlier body is removed; ids do not).
    ///
    /// # Errors
    /// [`BodyError::Unknown`] when there is no such body.
    pub fn index_of(&self, id: BodyId) -> Result<usize, BodyError> {
        self.bodies
            .iter()
            .position(|b| b.id == id)
            .ok_or_else(|| BodyError::Unknown {
                id,
                known: self.bodies.iter().map(|b| b.id.0).collect(),
            })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn owners_follow_their_bodies() {
        let ids = |v: &[u32]| v.iter().map(|&i| BodyId(i)).collect::<Vec<_>>();
        // Body 5 (owner 2) leaves; body 9 (owner 3) becomes owner 2; a new
        // body 11 takes owner 4; [sim] stays 0.
        let t = renumbered_owners(&ids(&[2, 5, 9, 7]), &ids(&[2, 9, 7, 11]));
        assert_eq!(&t[..6], &[0, 1, 0, 2, 3, 0]);
        assert!(t[6..].iter().all(|&o| o == 0));
        // Nothing changed: the identity on the bodies' owners.
        let same = renumbered_owners(&ids(&[0, 1]), &ids(&[0, 1]));
        assert_eq!(&same[..3], &[0, 1, 2]);
        // Past 255 bodies there is no owner number: body 300 of 300 keeps
        // owner 0, body 255's blades (owner 255) move down to 254.
        let before: Vec<BodyId> = (0..300).map(BodyId).collect();
        let after: Vec<BodyId> = (1..300).map(BodyId).collect();
        let t = renumbered_owners(&before, &after);
        assert_eq!((t[1], t[2], t[255]), (0, 1, 254));
    }
}
