//! Articulated objects (ours, DESIGN §3 "Articulated bodies"): an object as
//! a tree of rigid parts — a body and its wheels, legs, arms — each with its
//! own mesh and a pose relative to its parent that changes over time.
//!
//! A part hangs from its parent (another part, or the object's own body) at
//! a joint: a point `offset_m` fixed in the parent's frame, whose axes are
//! the parent's. The part's pose in that joint frame comes from its
//! [`Joint`]:
//! - `fixed`: none (the part is welded on);
//! - `keyframes`: positions and rotations at times, interpolated (a
//!   `keyframes` path in the joint frame, optionally looping);
//! - `wheel`: spins about its axle at the rate that makes it roll without
//!   slipping, `ω = (v_c · f) / r` (v_c the velocity of the wheel centre,
//!   f = axle × up the rolling direction, r the radius), and, if `steer`,
//!   turns about the parent's up axis to face the direction its centre moves
//!   (front wheels steer into the path's curve, Ackermann-like, by
//!   construction);
//! - `host`: whatever pose the host sets each frame (by name or index).
//!
//! Everything here is a pure function of its inputs: given the body's world
//! pose and velocities at t (and, for wheels, how far each has rolled,
//! which [`WheelOdometer`] integrates), [`Articulation::poses_into`] gives
//! each part's world pose, linear and angular velocity. Eq. 2's contact
//! speed is then the part's own surface speed, `|v + ω × r|`
//! ([`Pose::point_velocity`]): a rolling wheel's contact point is at rest
//! and pushes no grass by speed, its tread does as it comes down.
//!
//! Rigid-body kinematics of the tree (world from parent P and local L):
//! `R = R_P R_L`, `p = p_P + R_P (o + t_L)`, `ω = ω_P + R_P ω_L`,
//! `v = v_P + ω_P × R_P (o + t_L) + R_P v_L`.

use glam::{Quat, Vec3};
use serde::{Deserialize, Serialize};

use super::mesh::TriMesh;
use super::object::{ObjectErrorKind, Scale, ShapeParams, baked_mesh};
use super::path::{Keyframe, Path, PathError, PathParams};
use super::pose::Pose;

/// Default largest steering angle of a steered wheel, degrees: about what a
/// tractor's or a car's front wheels turn.
pub const DEFAULT_MAX_STEER_DEG: f32 = 35.0;

/// Below this horizontal speed of its centre, m/s, a steered wheel's angle
/// fades towards straight ahead (linearly from this speed to 0), so that the
/// steering angle, undefined at rest, stays continuous as the vehicle stops.
pub const STEER_FADE_SPEED_M_S: f32 = 0.05;

/// One part of an articulated object, as written in a scene file
/// (`[[objects.parts]]`).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PartParams {
    /// Name, unique among the object's parts: used in messages and by the
    /// host to pose the part.
    pub name: String,
    /// The part it hangs from: another part's name; omitted for the
    /// object's body.
    #[serde(default)]
    pub parent: Option<String>,
    /// The part's mesh (any object shape), in the part's frame, whose
    /// origin is the joint.
    pub shape: ShapeParams,
    /// Scale of the mesh (as an object's). Default 1.
    #[serde(default)]
    pub scale: Scale,
    /// Rotation baked into the mesh, Euler degrees (as an object's): a
    /// cylinder turned by `[0, 0, 90]` is a wheel with its axle along x.
    /// Default none.
    #[serde(default)]
    pub rotation_deg: [f32; 3],
    /// Where the joint is in the parent's frame, metres. Default the
    /// parent's origin.
    #[serde(default)]
    pub offset_m: [f32; 3],
    /// How the part moves at its joint. Default `fixed`.
    #[serde(default)]
    pub joint: JointParams,
}

/// How a part moves relative to its joint frame (scene-file form).
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(tag = "kind", rename_all = "snake_case", deny_unknown_fields)]
pub enum JointParams {
    /// Welded on.
    #[default]
    Fixed,
    /// Rolls without slipping; steers if asked.
    Wheel {
        /// Rolling radius, metres (> 0): the axle's height above the ground
        /// when the wheel stands on it.
        radius_m: f32,
        /// The axle in the joint frame (any length, not vertical). Default
        /// `[1, 0, 0]`: a wheel of a vehicle whose +z is forward.
        #[serde(default = "default_axle")]
        axle: [f32; 3],
        /// Whether the wheel turns to face the direction its centre moves.
        /// Default false.
        #[serde(default)]
        steer: bool,
        /// Largest steering angle, degrees, in [0, 89]. Default
        /// [`DEFAULT_MAX_STEER_DEG`].
        #[serde(default = "default_max_steer")]
        max_steer_deg: f32,
    },
    /// Positions (in the joint frame) and rotations at given times,
    /// interpolated as a `keyframes` path is.
    Keyframes {
        /// At least one key; times (seconds of simulation time) strictly
        /// increasing; `rotation_deg` on every key or on none.
        keys: Vec<Keyframe>,
        /// If set, the keys repeat with this period, seconds (> 0): time t
        /// plays the keys at `t mod loop_s`. Default: no loop (the last key
        /// holds).
        #[serde(default)]
        loop_s: Option<f32>,
    },
    /// Posed by the host every frame ([`PartsInput::host`]).
    Host,
}

fn default_axle() -> [f32; 3] {
    [1.0, 0.0, 0.0]
}

fn default_max_steer() -> f32 {
    DEFAULT_MAX_STEER_DEG
}

/// Why a part was refused: `parts[INDEX] (NAME): ` and what is wrong.
#[derive(Debug, thiserror::Error)]
#[error("parts[{index}] ({name}): {kind}")]
pub struct PartError {
    /// Index in the object's `parts`.
    pub index: usize,
    /// The part's name.
    pub name: String,
    /// What is wrong.
    pub kind: PartErrorKind,
}

/// What is wrong with a part.
#[derive(Debug, thiserror::Error)]
pub enum PartErrorKind {
    /// `parent` names no part.
    #[error(
        "parent = {parent:?} does not exist; allowed: omitted (the object's body) or one of {known}"
    )]
    UnknownParent {
        /// The name as written.
        parent: String,
        /// The parts' names, quoted, or "no other part".
        known: String,
    },
    /// Two parts have the same name.
    #[error("name {name:?} is already used by parts[{first}]; allowed: a name no other part has")]
    DuplicateName {
        /// The name.
        name: String,
        /// The first part with it.
        first: usize,
    },
    /// Following parents from this part comes back to it.
    #[error("parent = {parent:?} makes a loop ({chain}); allowed: parents that lead to the body")]
    Cycle {
        /// The parent as written.
        parent: String,
        /// The loop, names joined by " → ".
        chain: String,
    },
    /// A number out of range.
    #[error("{key} = {value}: {allowed}")]
    BadParameter {
        /// The key, e.g. `joint.radius_m`.
        key: &'static str,
        /// The value as written.
        value: String,
        /// What is allowed.
        allowed: &'static str,
    },
    /// The shape, scale or rotation was refused (as an object's would be).
    #[error("{0}")]
    Shape(ObjectErrorKind),
    /// The keyframes were refused (keys checked as a `keyframes` path's).
    #[error("joint.keys: {0}")]
    Keyframes(PathError),
}

/// A validated joint.
#[derive(Clone, Debug, PartialEq)]
pub enum Joint {
    /// Welded on.
    Fixed,
    /// A rolling wheel.
    Wheel(Wheel),
    /// Keyframed motion in the joint frame.
    Keyframes {
        /// The keys as a path (position in the joint frame, rotation).
        path: Path,
        /// Loop period, seconds, if any.
        loop_s: Option<f32>,
    },
    /// Posed by the host.
    Host,
}

/// A wheel joint.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Wheel {
    /// Rolling radius, metres (> 0).
    pub radius_m: f32,
    /// Unit axle in the joint frame, before steering.
    pub axle: Vec3,
    /// Whether it steers.
    pub steer: bool,
    /// Largest steering angle, radians.
    pub max_steer_rad: f32,
}

/// A part, ready: its mesh and how it moves.
#[derive(Clone, Debug)]
pub struct Part {
    /// Unique name.
    pub name: String,
    /// Index of the parent part, `None` for the body. Always smaller than
    /// the part's own index (parents come first).
    pub parent: Option<usize>,
    /// The mesh in the part's frame, sanitised.
    pub mesh: TriMesh,
    /// The joint's position in the parent's frame, metres.
    pub offset: Vec3,
    /// How it moves at the joint.
    pub joint: Joint,
}

/// The parts of an articulated object, parents before children.
#[derive(Clone, Debug, Default)]
pub struct Articulation {
    /// The parts. Their order may differ from the scene file's (parents are
    /// moved before their children); [`Articulation::index_of`] finds one.
    pub parts: Vec<Part>,
}

/// What [`Articulation::poses_into`] needs at one instant.
#[derive(Clone, Copy, Debug)]
pub struct PartsInput<'a> {
    /// Simulation time, seconds (keyframed joints).
    pub t: f32,
    /// The body's world pose and velocities.
    pub body: Pose,
    /// Per part, the distance its wheel has rolled, metres
    /// ([`WheelOdometer::rolled_m`]); it sets the spin angle
    /// `rolled / r`. Missing entries count as 0.
    pub rolled_m: &'a [f32],
    /// Per part, the host's pose of a `host` joint, in the joint frame
    /// (position, rotation, and their rates in the parent's frame); `None`
    /// or missing: the rest pose.
    pub host: &'a [Option<Pose>],
}

/// One part's motion at one instant.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PartPose {
    /// World pose and velocities of the part's frame.
    pub world: Pose,
    /// For a wheel, the speed of its centre along its rolling direction,
    /// m/s (its spin rate is this over the radius); 0 for other parts.
    pub rolling_speed_m_s: f32,
}

impl Articulation {
    /// Builds the parts of an object from their scene-file form; meshes are
    /// made or loaded relative to `base_dir` as an object's are.
    ///
    /// # Errors
    /// [`PartError`] naming the first bad part (in file order): a duplicate
    /// name, a parent that does not exist or makes a loop, a bad shape,
    /// offset or joint.
    pub fn from_params(
        params: &[PartParams],
        base_dir: &std::path::Path,
    ) -> Result<Self, PartError> {
        let error = |index: usize, kind| PartError {
            index,
            name: params[index].name.clone(),
            kind,
        };
        let mut parent_of = Vec::with_capacity(params.len());
        for (i, p) in params.iter().enumerate() {
            if let Some(first) = params[..i].iter().position(|q| q.name == p.name) {
                let name = p.name.clone();
                return Err(error(i, PartErrorKind::DuplicateName { name, first }));
            }
            let parent = match &p.parent {
                None => None,
                Some(name) => {
                    Some(params.iter().position(|q| &q.name == name).ok_or_else(|| {
                        let known: Vec<String> = params
                            .iter()
                            .filter(|q| q.name != p.name)
                            .map(|q| format!("{:?}", q.name))
                            .collect();
                        let known = if known.is_empty() {
                            "no other part".to_owned()
                        } else {
                            known.join(", ")
                        };
                        error(
                            i,
                            PartErrorKind::UnknownParent {
                                parent: name.clone(),
                                known,
                            },
                        )
                    })?)
                }
            };
            parent_of.push(parent);
        }
        // Depth of each part (loops found on the way), then parents first.
        let mut depth = vec![0usize; params.len()];
        for i in 0..params.len() {
            let mut chain = vec![i];
            let mut at = parent_of[i];
            while let Some(p) = at {
                if chain.contains(&p) {
                    let names: Vec<&str> = chain
                        .iter()
                        .chain([&p])
                        .map(|&k| params[k].name.as_str())
                        .collect();
                    return Err(error(
                        i,
                        PartErrorKind::Cycle {
                            parent: params[i].parent.clone().unwrap_or_default(),
                            chain: names.join(" → "),
                        },
                    ));
                }
                chain.push(p);
                at = parent_of[p];
            }
            depth[i] = chain.len();
        }
        let mut order: Vec<usize> = (0..params.len()).collect();
        order.sort_by_key(|&i| depth[i]); // stable: file order within a depth
        let mut new_index = vec![0usize; params.len()];
        for (k, &i) in order.iter().enumerate() {
            new_index[i] = k;
        }
        let mut parts = Vec::with_capacity(params.len());
        for i in 0..params.len() {
            let p = &params[i];
            let (mesh, _report) = baked_mesh(&p.shape, p.scale, p.rotation_deg, base_dir)
                .map_err(|e| error(i, PartErrorKind::Shape(e)))?;
            let offset = Vec3::from_array(p.offset_m);
            if !offset.is_finite() {
                return Err(error(
                    i,
                    bad(
                        "offset_m",
                        format3(p.offset_m),
                        "every coordinate must be finite",
                    ),
                ));
            }
            let joint = joint(&p.joint).map_err(|kind| error(i, kind))?;
            parts.push((
                new_index[i],
                Part {
                    name: p.name.clone(),
                    parent: parent_of[i].map(|q| new_index[q]),
                    mesh,
                    offset,
                    joint,
                },
            ));
        }
        parts.sort_by_key(|(k, _)| *k);
        Ok(Self {
            parts: parts.into_iter().map(|(_, part)| part).collect(),
        })
    }

    /// The index of the part called `name`.
    #[must_use]
    pub fn index_of(&self, name: &str) -> Option<usize> {
        self.parts.iter().position(|p| p.name == name)
    }

    /// Every part's world pose and velocities at one instant (see the
    /// module documentation for the kinematics). `out` is overwritten with
    /// one [`PartPose`] per part, in [`Articulation::parts`] order.
    pub fn poses_into(&self, input: &PartsInput<'_>, out: &mut Vec<PartPose>) {
        out.clear();
        for (i, part) in self.parts.iter().enumerate() {
            let parent = match part.parent {
                Some(p) => out[p].world,
                None => input.body,
            };
            let pose = self.part_pose(i, &parent, input);
            out.push(pose);
        }
    }

    /// Part `i`'s motion given its parent's world pose.
    fn part_pose(&self, i: usize, parent: &Pose, input: &PartsInput<'_>) -> PartPose {
        let part = &self.parts[i];
        let joint_arm = parent.rotation * part.offset;
        let joint_velocity = parent.velocity + parent.angular_velocity.cross(joint_arm);
        let mut rolling_speed = 0.0;
        // The part's pose in the joint frame: translation, rotation, and
        // their rates in the parent's frame.
        let local = match &part.joint {
            Joint::Fixed => Pose::at_rest(Vec3::ZERO),
            Joint::Host => input
                .host
                .get(i)
                .copied()
                .flatten()
                .unwrap_or(Pose::at_rest(Vec3::ZERO)),
            Joint::Keyframes { path, loop_s } => {
                let t = match loop_s {
                    Some(period) => input.t.rem_euclid(*period),
                    None => input.t,
                };
                Pose {
                    position: path.position(t),
                    rotation: path.keyframe_rotation(t).unwrap_or(Quat::IDENTITY),
                    velocity: path.velocity(t),
                    angular_velocity: path.keyframe_angular_velocity(t).unwrap_or(Vec3::ZERO),
                }
            }
            Joint::Wheel(wheel) => {
                // The centre's velocity in the parent's frame.
                let u = parent.rotation.inverse() * joint_velocity;
                let steer = if wheel.steer {
                    steer_angle(wheel, u)
                } else {
                    0.0
                };
                let turn = Quat::from_rotation_y(steer);
                let axle = turn * wheel.axle;
                let forward = axle.cross(Vec3::Y).normalize_or_zero();
                rolling_speed = u.dot(forward);
                let rolled = input.rolled_m.get(i).copied().unwrap_or(0.0);
                Pose {
                    position: Vec3::ZERO,
                    rotation: turn * Quat::from_axis_angle(wheel.axle, rolled / wheel.radius_m),
                    velocity: Vec3::ZERO,
                    angular_velocity: axle * (rolling_speed / wheel.radius_m),
                }
            }
        };
        let arm = parent.rotation * (part.offset + local.position);
        PartPose {
            world: Pose {
                position: parent.position + arm,
                rotation: (parent.rotation * local.rotation).normalize(),
                velocity: parent.velocity
                    + parent.angular_velocity.cross(arm)
                    + parent.rotation * local.velocity,
                angular_velocity: parent.angular_velocity
                    + parent.rotation * local.angular_velocity,
            },
            rolling_speed_m_s: rolling_speed,
        }
    }
}

/// The steering angle (about the joint frame's +y, radians) that turns
/// `wheel`'s rolling direction onto the horizontal part of its centre's
/// velocity `u` (joint frame), forwards or backwards, whichever is nearer;
/// clamped to the wheel's limit and faded out below
/// [`STEER_FADE_SPEED_M_S`].
fn steer_angle(wheel: &Wheel, u: Vec3) -> f32 {
    let forward = wheel.axle.cross(Vec3::Y).normalize_or_zero();
    let along = u.dot(forward);
    let across = u.dot(wheel.axle);
    let speed = (along * along + across * across).sqrt();
    if speed <= 0.0 {
        return 0.0;
    }
    // Turning by δ about +y takes forward f = a × y to cos δ f + sin δ a
    // (y × f = a for a horizontal axle a): it faces u at δ = atan2(u·a, u·f).
    // Driving backwards, the wheel faces −u.
    let raw = if along >= 0.0 {
        across.atan2(along)
    } else {
        (-across).atan2(-along)
    };
    let fade = (speed / STEER_FADE_SPEED_M_S).min(1.0);
    raw.clamp(-wheel.max_steer_rad, wheel.max_steer_rad) * fade
}

/// A validated joint.
fn joint(params: &JointParams) -> Result<Joint, PartErrorKind> {
    Ok(match params {
        JointParams::Fixed => Joint::Fixed,
        JointParams::Host => Joint::Host,
        &JointParams::Wheel {
            radius_m,
            axle,
            steer,
            max_steer_deg,
        } => {
            if !(radius_m.is_finite() && radius_m > 0.0) {
                return Err(bad(
                    "joint.radius_m",
                    radius_m.to_string(),
                    "must be a finite number > 0",
                ));
            }
            let a = Vec3::from_array(axle);
            let Some(unit) = a
                .try_normalize()
                .filter(|u| u.cross(Vec3::Y).length() > 0.1)
            else {
                return Err(bad(
                    "joint.axle",
                    format3(axle),
                    "must be a finite, non-zero direction at least 6° from vertical (a wheel rolls about a horizontal axle)",
                ));
            };
            if !(0.0..=89.0).contains(&max_steer_deg) {
                return Err(bad(
                    "joint.max_steer_deg",
                    max_steer_deg.to_string(),
                    "must be in [0, 89]",
                ));
            }
            Joint::Wheel(Wheel {
                radius_m,
                axle: unit,
                steer,
                max_steer_rad: max_steer_deg.to_radians(),
            })
        }
        JointParams::Keyframes { keys, loop_s } => {
            if let Some(period) = loop_s
                && !(period.is_finite() && *period > 0.0)
            {
                return Err(bad(
                    "joint.loop_s",
                    period.to_string(),
                    "must be a finite number > 0",
                ));
            }
            let path = Path::new(PathParams::Keyframes { keys: keys.clone() })
                .map_err(PartErrorKind::Keyframes)?;
            Joint::Keyframes {
                path,
                loop_s: *loop_s,
            }
        }
    })
}

/// Integrates how far each wheel has rolled (trapezoidal rule over the
/// rolling speeds of [`Articulation::poses_into`]), for
/// [`PartsInput::rolled_m`]. Exact for a constant speed; only the spin
/// *angle* depends on it (the spin rate, which Eq. 2 sees, does not).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct WheelOdometer {
    /// Distance rolled per part, metres (0 for parts that are not wheels).
    pub rolled_m: Vec<f32>,
    /// Rolling speeds at the last call, m/s.
    last_speed: Vec<f32>,
}

impl WheelOdometer {
    /// An odometer at 0 for `parts` parts whose speeds at the start are
    /// `start` ([`PartPose::rolling_speed_m_s`]).
    #[must_use]
    pub fn new(start: &[PartPose]) -> Self {
        Self {
            rolled_m: vec![0.0; start.len()],
            last_speed: start.iter().map(|p| p.rolling_speed_m_s).collect(),
        }
    }

    /// Advances by `dt` seconds to the speeds of `now`.
    pub fn advance(&mut self, dt: f32, now: &[PartPose]) {
        self.rolled_m.resize(now.len(), 0.0);
        self.last_speed.resize(now.len(), 0.0);
        for ((rolled, last), pose) in self.rolled_m.iter_mut().zip(&mut self.last_speed).zip(now) {
            *rolled += 0.5 * dt * (*last + pose.rolling_speed_m_s);
            *last = pose.rolling_speed_m_s;
        }
    }
}

fn bad(key: &'static str, value: String, allowed: &'static str) -> PartErrorKind {
    PartErrorKind::BadParameter {
        key,
        value,
        allowed,
    }
}

fn format3(v: [f32; 3]) -> String {
    format!("[{}, {}, {}]", v[0], v[1], v[2])
}
