//! glTF animations (glTF 2.0 §3.11): keyframed translation, rotation and
//! scale of nodes, sampled by name at any time, looping (ours, DESIGN §3
//! "Deforming meshes").
//!
//! A channel drives one property of one node through a sampler: key times
//! (seconds) and values, interpolated `STEP` (hold the previous key),
//! `LINEAR` (lerp; slerp for rotations) or `CUBICSPLINE` (cubic Hermite with
//! the file's in- and out-tangents, glTF Appendix C; rotations normalised
//! after). Morph-target `weights` channels are skipped: trample deforms
//! meshes by skins only. Sampling is a pure function of time: the same t
//! gives the same bits, whatever was sampled before.

use ::gltf::Document;
use ::gltf::accessor::Dimensions;
use ::gltf::animation::{Interpolation as GltfInterpolation, Property as GltfProperty};
use glam::{Quat, Vec4};

use super::gltf::read_floats;
use super::rig_error::RigError;
use super::skin::NodeTransform;

/// The property of a node a channel drives.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Property {
    /// Translation, metres (values in `xyz`).
    Translation,
    /// Rotation, a unit quaternion `(x, y, z, w)`.
    Rotation,
    /// Scale factors (values in `xyz`).
    Scale,
}

/// How values between keys are found (glTF `sampler.interpolation`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Interpolation {
    /// The value of the last key at or before t.
    Step,
    /// Linear between keys; spherical linear for rotations.
    Linear,
    /// Cubic Hermite spline through the keys with the stored tangents.
    CubicSpline,
}

/// One animated property of one node.
#[derive(Clone, Debug, PartialEq)]
pub struct Channel {
    /// The glTF node index it drives.
    pub node: u32,
    /// Which property.
    pub property: Property,
    /// How values between keys are found.
    pub interpolation: Interpolation,
    /// Key times, seconds, non-decreasing, finite; at least one.
    pub times: Vec<f32>,
    /// Key values (3-vectors in `xyz`, `w` = 0). One per key; for
    /// [`Interpolation::CubicSpline`] three per key: in-tangent, value,
    /// out-tangent (glTF's layout).
    pub values: Vec<Vec4>,
}

/// A named animation: channels that play together.
#[derive(Clone, Debug, PartialEq)]
pub struct Animation {
    /// The name in the file (`animation 3` when it has none).
    pub name: String,
    /// Loop length, seconds: the last key time over all channels (≥ 0).
    pub duration_s: f32,
    /// The channels (morph-weight channels left out).
    pub channels: Vec<Channel>,
}

impl Channel {
    /// The channel's value at time `t` seconds (not looped: before the first
    /// key the first value, after the last the last).
    #[must_use]
    pub fn sample(&self, t: f32) -> Vec4 {
        let cubic = self.interpolation == Interpolation::CubicSpline;
        let value = |k: usize| {
            if cubic {
                self.values[3 * k + 1]
            } else {
                self.values[k]
            }
        };
        let n = self.times.len();
        // First key whose time is > t.
        let next = self.times.partition_point(|&k| k <= t);
        if next == 0 {
            return value(0);
        }
        if next >= n {
            return value(n - 1);
        }
        let k = next - 1;
        let (t0, t1) = (self.times[k], self.times[next]);
        let span = t1 - t0;
        let s = if span > 0.0 {
            ((t - t0) / span).clamp(0.0, 1.0)
        } else {
            1.0
        };
        match self.interpolation {
            Interpolation::Step => value(k),
            Interpolation::Linear if self.property == Property::Rotation => {
                let q0 = Quat::from_vec4(value(k));
                let q1 = Quat::from_vec4(value(next));
                Vec4::from(q0.slerp(q1, s))
            }
            Interpolation::Linear => value(k).lerp(value(next), s),
            Interpolation::CubicSpline => {
                let (s2, s3) = (s * s, s * s * s);
                let v0 = self.values[3 * k + 1];
                let b0 = self.values[3 * k + 2];
                let a1 = self.values[3 * next];
                let v1 = self.values[3 * next + 1];
                let p = v0 * (2.0 * s3 - 3.0 * s2 + 1.0)
                    + b0 * (span * (s3 - 2.0 * s2 + s))
                    + v1 * (-2.0 * s3 + 3.0 * s2)
                    + a1 * (span * (s3 - s2));
                if self.property == Property::Rotation {
                    p.try_normalize().unwrap_or(v1)
                } else {
                    p
                }
            }
        }
    }
}

impl Animation {
    /// The local transform of every node at time `t` seconds, looping:
    /// `rest` (the nodes' transforms in the file) with the animated
    /// properties replaced by the channels' values at `t mod duration_s`
    /// (a negative t wraps too; a zero-length animation holds its keys).
    /// `out` is overwritten with `rest.len()` transforms; channels naming a
    /// node beyond `rest` are ignored.
    pub fn sample_into(&self, t: f32, rest: &[NodeTransform], out: &mut Vec<NodeTransform>) {
        out.clear();
        out.extend_from_slice(rest);
        let t = self.loop_time(t);
        for channel in &self.channels {
            let Some(node) = out.get_mut(channel.node as usize) else {
                continue;
            };
            let v = channel.sample(t);
            match channel.property {
                Property::Translation => node.translation = v.truncate(),
                Property::Rotation => {
                    node.rotation = v.try_normalize().map_or(node.rotation, Quat::from_vec4);
                }
                Property::Scale => node.scale = v.truncate(),
            }
        }
    }

    /// `t` wrapped into `[0, duration_s)`; `t` itself (clamped at 0) for a
    /// zero-length animation; 0 for a non-finite t.
    #[must_use]
    pub fn loop_time(&self, t: f32) -> f32 {
        if !t.is_finite() {
            return 0.0;
        }
        if self.duration_s > 0.0 {
            t.rem_euclid(self.duration_s)
        } else {
            t.max(0.0)
        }
    }
}

/// Every animation of `document` (`name` names the file in messages).
///
/// # Errors
/// [`RigError::Accessor`] when a sampler's input is not `SCALAR` floats,
/// its times are not finite and non-decreasing, its output is not the
/// property's type or has the wrong count (one value per key, three for
/// `CUBICSPLINE`).
pub(crate) fn load_animations(
    document: &Document,
    buffers: &[Vec<u8>],
    name: &str,
) -> Result<Vec<Animation>, RigError> {
    let mut out = Vec::with_capacity(document.animations().len());
    for animation in document.animations() {
        let label = animation
            .name()
            .map_or_else(|| format!("animation {}", animation.index()), str::to_owned);
        let mut channels = Vec::new();
        for channel in animation.channels() {
            let property = match channel.target().property() {
                GltfProperty::Translation => Property::Translation,
                GltfProperty::Rotation => Property::Rotation,
                GltfProperty::Scale => Property::Scale,
                GltfProperty::MorphTargetWeights => continue,
            };
            let sampler = channel.sampler();
            let item =
                |part: &str| format!("animation {label:?} sampler {} {part}", sampler.index());
            let error = |part: &str, problem: String| RigError::Accessor {
                source_name: name.to_owned(),
                item: item(part),
                problem,
            };
            let times = read_floats(&sampler.input(), buffers, Dimensions::Scalar)
                .map_err(|p| error("input", p))?;
            if times.is_empty() {
                return Err(error("input", "has no keys; allowed: at least one".into()));
            }
            if let Some(k) = times.windows(2).position(|w| w[1] < w[0]) {
                return Err(error(
                    "input",
                    format!(
                        "key {} at {} s comes before key {k} at {} s; allowed: non-decreasing times",
                        k + 1,
                        times[k + 1],
                        times[k]
                    ),
                ));
            }
            let interpolation = match sampler.interpolation() {
                GltfInterpolation::Step => Interpolation::Step,
                GltfInterpolation::Linear => Interpolation::Linear,
                GltfInterpolation::CubicSpline => Interpolation::CubicSpline,
            };
            let dimensions = match property {
                Property::Rotation => Dimensions::Vec4,
                _ => Dimensions::Vec3,
            };
            let flat = read_floats(&sampler.output(), buffers, dimensions)
                .map_err(|p| error("output", p))?;
            let width = dimensions.multiplicity();
            let values: Vec<Vec4> = flat
                .chunks_exact(width)
                .map(|c| Vec4::new(c[0], c[1], c[2], c.get(3).copied().unwrap_or(0.0)))
                .collect();
            let per_key = if interpolation == Interpolation::CubicSpline {
                3
            } else {
                1
            };
            if values.len() != per_key * times.len() {
                return Err(error(
                    "output",
                    format!(
                        "holds {} values for {} keys; allowed: {} ({per_key} per key)",
                        values.len(),
                        times.len(),
                        per_key * times.len()
                    ),
                ));
            }
            channels.push(Channel {
                node: channel.target().node().index() as u32,
                property,
                interpolation,
                times,
                values,
            });
        }
        let duration_s = channels
            .iter()
            .filter_map(|c| c.times.last().copied())
            .fold(0.0f32, f32::max);
        out.push(Animation {
            name: label,
            duration_s,
            channels,
        });
    }
    Ok(out)
}
