//! The shared test scenes: each a scene file in `crates/trample-testkit/scenes/`
//! (so it can also be run: `trample run crates/trample-testkit/scenes/busy.toml`),
//! embedded here. A test that needs a variant parses the scene with
//! [`scene`] and changes its [`SceneFile`](trample::scene::SceneFile)
//! before [`build`], rather than keeping a near-copy of the text.

use std::path::Path;
use trample::Simulation;
use trample::scene::Scene;

/// A 0.5 m ball rolling across 4,096 blades (4 × 4 patches of 16 × 16
/// cells of 0.1 m), every cell geometric, precision 5, recovery 1.5 s, for
/// 5 s. File: `scenes/rolling_ball.toml`.
pub const ROLLING_BALL: &str = include_str!("../scenes/rolling_ball.toml");

/// Four objects (ball, box, knot, capsule) on endless circles over 2,304
/// blades on noise terrain, a circling camera that changes cells' levels
/// of detail in every step, recovery 1.5 s. File: `scenes/busy.toml`.
pub const BUSY: &str = include_str!("../scenes/busy.toml");

/// A camera following a rolling ball along a 9,216-blade field (6 × 6
/// patches) with a box crossing it: cells change level (geometry within
/// 2.5 m, billboards within 5 m), billboards bend and transitions run both
/// ways; precision 3, recovery 3 s. File: `scenes/lod.toml`.
pub const LOD: &str = include_str!("../scenes/lod.toml");

/// Contact that holds (issue 12): the paper's density at precision 7 on
/// 16,384 blades (4 × 4 patches of 32 × 32 cells), a 1.2 m box standing in
/// the grass, a 1.6 m ball that rolls at 2.5 m/s and stops after 1.6 s, and
/// a 0.8 m ball rolling at 2.5 m/s for 4 s. File: `scenes/contact.toml`.
pub const CONTACT: &str = include_str!("../scenes/contact.toml");

/// Parses and validates `text` (relative paths resolved against the
/// current folder).
///
/// # Panics
/// When the scene is invalid, with the scene error's message: a test scene
/// that does not parse is a broken test.
#[must_use]
pub fn scene(text: &str) -> Scene {
    scene_in(text, Path::new("."))
}

/// As [`scene`], with relative paths (a height map, a mesh) resolved
/// against `dir`.
///
/// # Panics
/// As [`scene`].
#[must_use]
pub fn scene_in(text: &str, dir: &Path) -> Scene {
    let name = text
        .lines()
        .find_map(|l| l.strip_prefix("name = "))
        .unwrap_or("test scene");
    Scene::parse(text, name, dir).unwrap_or_else(|e| panic!("test scene {name}: {e}"))
}

/// Builds the simulation of `scene` (validated again by
/// [`Scene::build`]).
///
/// # Panics
/// When it does not build (a variant a test made invalid), with the error.
#[must_use]
pub fn build(scene: &Scene) -> Simulation {
    scene
        .build()
        .unwrap_or_else(|e| panic!("test scene {}: {e}", scene.source))
}

/// [`build`] of [`scene`]`(text)`.
///
/// # Panics
/// As [`scene`] and [`build`].
#[must_use]
pub fn simulation(text: &str) -> Simulation {
    build(&scene(text))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_test_scene_builds_with_the_size_its_doc_states() {
        for (text, blades, objects) in [
            (ROLLING_BALL, 4_096, 1),
            (BUSY, 2_304, 4),
            (LOD, 9_216, 2),
            (CONTACT, 16_384, 3),
        ] {
            let sim = simulation(text);
            assert_eq!(sim.field.blades.count, blades, "{}", scene(text).source);
            assert_eq!(sim.bodies.len(), objects, "{}", scene(text).source);
        }
    }
}
