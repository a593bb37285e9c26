//! Small scenes for the integration tests (full-size runs belong to benchmarks).
#![allow(dead_code)]

pub mod gltf;

use trample::Simulation;
use trample::scene::Scene;

/// A field of `patches`² patches of 16×16 cells (0.1 m), geometry everywhere,
/// a sphere of radius 0.5 m rolling along x at z = 0 across it in `duration` s.
pub fn rolling_ball_toml(patches: u32, recovery: &str, duration: f32) -> String {
    let half = patches as f32 * 16.0 * 0.1 * 0.5;
    format!(
        r#"
[field]
patches = [{patches}, {patches}]
cells_per_patch = 16
[lod]
geometry_m = 1000.0
billboard_m = 2000.0
[sim]
recovery_s = {recovery}
[camera]
path = {{ kind = "static", position = [0.0, 3.0, {cz}] }}
look_at = {{ kind = "point", at = [0.0, 0.0, 0.0] }}
[[objects]]
name = "ball"
shape = {{ kind = "sphere", radius_m = 0.5 }}
orientation = "rolling"
path = {{ kind = "line", from = [{x0}, 0.5, 0.0], to = [{x1}, 0.5, 0.0], duration_s = {duration} }}
"#,
        cz = half + 2.0,
        x0 = -half - 0.6,
        x1 = half + 0.6,
    )
}

/// Builds a simulation from scene text.
pub fn sim_from(toml: &str) -> Simulation {
    Scene::parse(toml, "test.toml", std::path::Path::new("."))
        .expect("valid scene")
        .build()
        .expect("buildable scene")
}

/// A 12.8 m field at precision 5 with `sim` (more `[sim]` lines) and
/// `objects`, the camera `eye_z` metres from its centre.
pub fn field_12m(eye_z: f32, sim: &str, objects: &str) -> Simulation {
    field_12m_seen_from([0.0, 3.0, eye_z], [0.0, 0.0, 0.0], sim, objects)
}

/// [`field_12m`] with the camera at `eye` looking at `at`.
pub fn field_12m_seen_from(eye: [f32; 3], at: [f32; 3], sim: &str, objects: &str) -> Simulation {
    sim_from(&format!(
        r#"
[field]
patches = [4, 4]
cells_per_patch = 32
[sim]
precision = 5
{sim}
[camera]
path = {{ kind = "static", position = {eye:?} }}
look_at = {{ kind = "point", at = {at:?} }}
{objects}"#
    ))
}

/// Every blade vertex's position bits, in storage order (what a step's
/// changed blades are checked against).
pub fn position_bits(sim: &Simulation) -> Vec<[u32; 3]> {
    sim.field
        .blades
        .pos
        .iter()
        .map(|v| v.pos.map(f32::to_bits))
        .collect()
}

/// Height of blade `b`'s tip above its root.
pub fn tip_height(sim: &Simulation, b: usize) -> f32 {
    let bl = &sim.field.blades;
    bl.vertex(b, bl.segments).y - bl.vertex(b, 0).y
}

/// Rest height of blade `b`'s tip above its root.
pub fn rest_tip_height(sim: &Simulation, b: usize) -> f32 {
    let bl = &sim.field.blades;
    bl.rest_vertex(b, bl.segments).y - bl.rest_vertex(b, 0).y
}

/// Root (x, z) of blade `b`.
pub fn root_xz(sim: &Simulation, b: usize) -> (f32, f32) {
    let r = sim.field.blades.rest_vertex(b, 0);
    (r.x, r.z)
}

/// SplitMix64: a small seeded generator for the property tests (the
/// library's own mixer, so tests and field generation share one definition).
pub struct Rng(pub u64);

impl Rng {
    /// Next 64 random bits.
    pub fn next(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        trample::field::rng::mix64(self.0)
    }

    /// Uniform in [lo, hi).
    pub fn f32(&mut self, lo: f32, hi: f32) -> f32 {
        lo + (hi - lo) * ((self.next() >> 40) as f32 / (1u64 << 24) as f32)
    }

    /// Uniform in the cube [-r, r]³.
    pub fn vec(&mut self, r: f32) -> glam::Vec3 {
        glam::Vec3::new(self.f32(-r, r), self.f32(-r, r), self.f32(-r, r))
    }

    /// Uniform in 0..n.
    pub fn below(&mut self, n: u32) -> u32 {
        (self.next() % u64::from(n)) as u32
    }
}

/// The deepest any blade vertex lies inside body `i` at its current pose:
/// distance to the mesh surface of every vertex the exact inside test puts
/// inside, metres (0 if none).
pub fn deepest_inside(sim: &Simulation, i: usize) -> f32 {
    use trample::collision::closest_point::closest_point_on_mesh;
    use trample::collision::exact::point_inside;
    let body = &sim.bodies[i];
    let bl = &sim.field.blades;
    let mut deepest = 0.0f32;
    for b in 0..bl.count {
        for k in 0..=bl.segments {
            let p = body.pose.to_local(glam::Vec3::from(bl.vertex(b, k)));
            if point_inside(&body.tree, p) {
                let s = closest_point_on_mesh(&body.tree, p, f32::INFINITY).unwrap();
                deepest = deepest.max(s.distance_sq.sqrt());
            }
        }
    }
    deepest
}

/// How two runs of the same field differ (DESIGN §6's frame-rate
/// independence): the mean distance between their blades' tips over the
/// blades either moved, divided by the mean tip displacement from rest
/// (the larger of the two), and the blades bent (tip more than 5 cm from
/// rest) in both and in either.
pub fn track_difference(a: &Simulation, b: &Simulation) -> (f64, usize, usize) {
    let bl = (&a.field.blades, &b.field.blades);
    let n = bl.0.segments;
    let (mut diff, mut disp, mut both, mut either) = (0.0f64, 0.0f64, 0, 0);
    for i in 0..bl.0.count {
        let rest = bl.0.rest_vertex(i, n);
        let (ta, tb) = (bl.0.vertex(i, n), bl.1.vertex(i, n));
        let (da, db) = (ta.distance(rest), tb.distance(rest));
        if da > 0.05 || db > 0.05 {
            either += 1;
            if da > 0.05 && db > 0.05 {
                both += 1;
            }
        }
        if da > 1e-6 || db > 1e-6 {
            diff += f64::from(ta.distance(tb));
            disp += f64::from(da.max(db));
        }
    }
    (diff / disp.max(1e-12), both, either)
}
