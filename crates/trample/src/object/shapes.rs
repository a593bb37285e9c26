//! Built-in shapes (DESIGN §3): sphere, box, capsule, cylinder (wheels of
//! articulated objects) and the complex knot.
//!
//! Every shape is centred at the origin, closed (every edge shared by exactly
//! two triangles, see [`TriMesh::is_closed`]), has counter-clockwise
//! triangles seen from outside (outward normals, positive
//! [`TriMesh::signed_volume`]) and no degenerate triangle, for positive finite
//! sizes. The functions do not validate their sizes: the scene loader does
//! (`object::object`), and every mesh is sanitised afterwards anyway.

use super::mesh::TriMesh;
use glam::Vec3;
use std::collections::HashMap;
use std::f32::consts::{FRAC_PI_2, TAU};

/// Largest accepted sphere subdivision level: 7 gives 327,680 triangles.
pub const MAX_SPHERE_SUBDIVISIONS: u32 = 7;

/// Segments around a capsule's axis.
const CAPSULE_SEGMENTS: u32 = 32;
/// Latitude steps of each capsule hemisphere, pole to equator.
const CAPSULE_RINGS: u32 = 8;

/// Segments around a cylinder's axis.
const CYLINDER_SEGMENTS: u32 = 32;

/// Knot centre curve: torus major radius, minor radius of the curve's winding
/// and tube radius, in units where the knot is 2 (1 + 0.5 + 0.25) = 3.5
/// across. Measured on the centre curve: the smallest radius of curvature is
/// 0.79 and distinct strands stay 0.84 apart, so a 0.25 tube neither folds
/// nor touches itself.
const KNOT_MAJOR: f32 = 1.0;
const KNOT_MINOR: f32 = 0.5;
const KNOT_TUBE: f32 = 0.25;
/// Rings along the knot and vertices per ring: 2 × 192 × 16 = 6,144 triangles.
const KNOT_RINGS: u32 = 192;
const KNOT_RING_VERTICES: u32 = 16;

/// An icosphere of `radius` metres: the icosahedron (20 triangles) with each
/// triangle split in four `subdivisions` times, vertices pushed onto the
/// sphere: 20 × 4^subdivisions triangles (3 → 1,280). `subdivisions` above
/// [`MAX_SPHERE_SUBDIVISIONS`] is clamped to it. The icosahedron stands on a
/// vertex: there are vertices at (0, ±radius, 0), so the lowest point (the
/// roll radius of a rolling sphere) is exactly `radius` below the centre.
/// Vertices lie on the sphere, so the mesh's volume is a little below
/// 4/3 π r³ (0.9 % at level 3).
#[must_use]
pub fn sphere(radius: f32, subdivisions: u32) -> TriMesh {
    // Poles, then two rings of five at y = ±1/√5, the lower one turned by
    // 36°: a regular icosahedron of circumradius 1.
    let (ring_y, ring_radius) = (1.0 / 5.0_f32.sqrt(), 2.0 / 5.0_f32.sqrt());
    let ring = |y: f32, turn: f32| {
        (0..5).map(move |i| {
            let angle = TAU * (i as f32 + turn) / 5.0;
            Vec3::new(ring_radius * angle.cos(), y, ring_radius * angle.sin())
        })
    };
    let mut positions = vec![Vec3::Y];
    positions.extend(ring(ring_y, 0.0));
    positions.extend(ring(-ring_y, 0.5));
    positions.push(-Vec3::Y);
    let (upper, lower) = (|i: u32| 1 + i % 5, |i: u32| 6 + i % 5);
    let mut indices: Vec<[u32; 3]> = Vec::with_capacity(20);
    for i in 0..5 {
        indices.push([0, upper(i + 1), upper(i)]);
        indices.push([upper(i), upper(i + 1), lower(i)]);
        indices.push([upper(i + 1), lower(i + 1), lower(i)]);
        indices.push([11, lower(i), lower(i + 1)]);
    }
    for _ in 0..subdivisions.min(MAX_SPHERE_SUBDIVISIONS) {
        let mut midpoints: HashMap<(u32, u32), u32> = HashMap::with_capacity(indices.len() * 3 / 2);
        let mut midpoint = |a: u32, b: u32, positions: &mut Vec<Vec3>| -> u32 {
            *midpoints.entry((a.min(b), a.max(b))).or_insert_with(|| {
                let m = (positions[a as usize] + positions[b as usize]).normalize();
                positions.push(m);
                (positions.len() - 1) as u32
            })
        };
        let mut finer = Vec::with_capacity(indices.len() * 4);
        for &[a, b, c] in &indices {
            let ab = midpoint(a, b, &mut positions);
            let bc = midpoint(b, c, &mut positions);
            let ca = midpoint(c, a, &mut positions);
            finer.extend([[a, ab, ca], [b, bc, ab], [c, ca, bc], [ab, bc, ca]]);
        }
        indices = finer;
    }
    for p in &mut positions {
        *p *= radius;
    }
    TriMesh { positions, indices }
}

/// A box with the given half extents (x, y, z), metres: 8 vertices,
/// 12 triangles. See also [`capsule`].
#[must_use]
pub fn cuboid(half_extents: Vec3) -> TriMesh {
    // Vertex i has corner bits (x, y, z) = (i & 1, i >> 1 & 1, i >> 2 & 1).
    let positions = (0..8)
        .map(|i| {
            let sign = |bit: u32| if i >> bit & 1 == 1 { 1.0 } else { -1.0 };
            half_extents * Vec3::new(sign(0), sign(1), sign(2))
        })
        .collect();
    let mut indices = Vec::with_capacity(12);
    for k in 0..3 {
        let (u, v) = ((k + 1) % 3, (k + 2) % 3);
        for side in 0..2 {
            let corner = |a: u32, b: u32| side << k | a << u | b << v;
            // (u, v) = (0,0), (1,0), (1,1), (0,1) is counter-clockwise seen
            // from +axis k because e_u × e_v = e_k.
            let quad = [corner(0, 0), corner(1, 0), corner(1, 1), corner(0, 1)];
            let [a, b, c, d] = if side == 1 {
                quad
            } else {
                [quad[0], quad[3], quad[2], quad[1]]
            };
            indices.extend([[a, b, c], [a, c, d]]);
        }
    }
    TriMesh { positions, indices }
}

/// A capsule along y, centred at the origin: a cylinder of `radius` and
/// `length` metres (the cylindrical part only; negative is taken as 0) capped
/// by two hemispheres. 32 segments around, 8 latitude steps per hemisphere:
/// 1,024 triangles (960 when `length` is 0).
#[must_use]
pub fn capsule(radius: f32, length: f32) -> TriMesh {
    let half = 0.5 * length.max(0.0);
    // Latitude rings from top to bottom: (y, ring radius).
    let mut rings = Vec::with_capacity(2 * CAPSULE_RINGS as usize);
    for i in 1..=CAPSULE_RINGS {
        let theta = FRAC_PI_2 * i as f32 / CAPSULE_RINGS as f32;
        rings.push((half + radius * theta.cos(), radius * theta.sin()));
    }
    let first_bottom = if half > 0.0 { 0 } else { 1 };
    for i in first_bottom..CAPSULE_RINGS {
        let theta = FRAC_PI_2 * i as f32 / CAPSULE_RINGS as f32;
        rings.push((-half - radius * theta.sin(), radius * theta.cos()));
    }
    let mut positions = vec![Vec3::new(0.0, half + radius, 0.0)];
    for &(y, r) in &rings {
        positions.extend((0..CAPSULE_SEGMENTS).map(|j| {
            let alpha = TAU * j as f32 / CAPSULE_SEGMENTS as f32;
            Vec3::new(r * alpha.cos(), y, r * alpha.sin())
        }));
    }
    positions.push(Vec3::new(0.0, -half - radius, 0.0));
    let bottom = (positions.len() - 1) as u32;
    let ring_start = |k: usize| 1 + k as u32 * CAPSULE_SEGMENTS;
    let mut indices = Vec::new();
    for j in 0..CAPSULE_SEGMENTS {
        let next = (j + 1) % CAPSULE_SEGMENTS;
        indices.push([0, ring_start(0) + next, ring_start(0) + j]);
        let last = ring_start(rings.len() - 1);
        indices.push([bottom, last + j, last + next]);
    }
    for k in 0..rings.len() - 1 {
        stitch_rings(
            &mut indices,
            ring_start(k),
            ring_start(k + 1),
            CAPSULE_SEGMENTS,
        );
    }
    TriMesh { positions, indices }
}

/// A closed cylinder along y, centred at the origin, of `radius` and
/// `length` metres: 32 segments around, flat caps fanned from their centres,
/// 128 triangles. A wheel is one turned by 90° about z (axle along x).
/// See also [`capsule`].
#[must_use]
pub fn cylinder(radius: f32, length: f32) -> TriMesh {
    let half = 0.5 * length;
    let mut positions = vec![Vec3::new(0.0, half, 0.0)];
    for y in [half, -half] {
        positions.extend((0..CYLINDER_SEGMENTS).map(|j| {
            let alpha = TAU * j as f32 / CYLINDER_SEGMENTS as f32;
            Vec3::new(radius * alpha.cos(), y, radius * alpha.sin())
        }));
    }
    positions.push(Vec3::new(0.0, -half, 0.0));
    let (top, lower, bottom) = (1, 1 + CYLINDER_SEGMENTS, 1 + 2 * CYLINDER_SEGMENTS);
    let mut indices = Vec::with_capacity(4 * CYLINDER_SEGMENTS as usize);
    for j in 0..CYLINDER_SEGMENTS {
        let next = (j + 1) % CYLINDER_SEGMENTS;
        indices.push([0, top + next, top + j]);
        indices.push([bottom, lower + j, lower + next]);
    }
    stitch_rings(&mut indices, top, lower, CYLINDER_SEGMENTS);
    TriMesh { positions, indices }
}

/// The built-in complex shape: a tube around a (3, 2) torus knot (it winds
/// three times around the y axis and twice around the torus tube), closed,
/// 6,144 triangles, `size` metres across in x and z and 0.43 × `size` high.
#[must_use]
pub fn knot(size: f32) -> TriMesh {
    let scale = size / (2.0 * (KNOT_MAJOR + KNOT_MINOR + KNOT_TUBE));
    let mut positions = Vec::with_capacity((KNOT_RINGS * KNOT_RING_VERTICES) as usize);
    for i in 0..KNOT_RINGS {
        let phi = TAU * i as f32 / KNOT_RINGS as f32;
        let (s2, c2) = (2.0 * phi).sin_cos();
        let (s3, c3) = (3.0 * phi).sin_cos();
        let r = KNOT_MAJOR + KNOT_MINOR * c2;
        let centre = Vec3::new(r * c3, KNOT_MINOR * s2, r * s3);
        let dr = -2.0 * KNOT_MINOR * s2;
        let tangent = Vec3::new(
            dr * c3 - 3.0 * r * s3,
            2.0 * KNOT_MINOR * c2,
            dr * s3 + 3.0 * r * c3,
        )
        .normalize();
        // The horizontal outward direction is never along the tangent (whose
        // component around y is at least 3 × 0.5), so this frame is smooth
        // and periodic: the tube closes without a seam.
        let outward = Vec3::new(c3, 0.0, s3);
        let normal = (outward - outward.dot(tangent) * tangent).normalize();
        let binormal = tangent.cross(normal);
        positions.extend((0..KNOT_RING_VERTICES).map(|j| {
            let (sv, cv) = (TAU * j as f32 / KNOT_RING_VERTICES as f32).sin_cos();
            (centre + KNOT_TUBE * (cv * normal + sv * binormal)) * scale
        }));
    }
    let mut indices = Vec::with_capacity(2 * (KNOT_RINGS * KNOT_RING_VERTICES) as usize);
    for i in 0..KNOT_RINGS {
        let next = (i + 1) % KNOT_RINGS;
        stitch_rings(
            &mut indices,
            i * KNOT_RING_VERTICES,
            next * KNOT_RING_VERTICES,
            KNOT_RING_VERTICES,
        );
    }
    TriMesh { positions, indices }
}

/// Joins two rings of `n` vertices (starting at indices `upper` and `lower`)
/// with `2n` triangles. Both rings must run counter-clockwise about the
/// direction from `upper` to `lower` for the triangles to face outwards.
fn stitch_rings(indices: &mut Vec<[u32; 3]>, upper: u32, lower: u32, n: u32) {
    for j in 0..n {
        let next = (j + 1) % n;
        indices.push([upper + j, lower + next, lower + j]);
        indices.push([upper + j, upper + next, lower + next]);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::PI;

    /// Closed, outward, no degenerate triangle, centred at the origin.
    fn assert_well_formed(mesh: &TriMesh, name: &str) {
        assert!(mesh.is_closed(), "{name} is not closed");
        assert!(mesh.signed_volume() > 0.0, "{name} faces inwards");
        let (lo, hi) = mesh.bounds().expect("non-empty");
        let size = (hi - lo).length() as f64;
        for i in 0..mesh.triangle_count() {
            let area = mesh.triangle_area(i).expect("indices in range");
            assert!(
                area > 1e-6 * size * size,
                "{name} triangle {i} has area {area}"
            );
        }
        assert!(
            ((lo + hi) * 0.5).length() < 1e-5 * size as f32,
            "{name} is not centred: {lo} {hi}"
        );
    }

    fn relative_error(actual: f64, expected: f64) -> f64 {
        (actual - expected).abs() / expected
    }

    #[test]
    fn sphere_level_3_has_1280_triangles_and_its_volume_within_1_5_percent() {
        let mesh = sphere(2.0, 3);
        assert_eq!(mesh.triangle_count(), 1280);
        assert_eq!(mesh.positions.len(), 642);
        assert_well_formed(&mesh, "sphere");
        let exact = 4.0 / 3.0 * PI * 8.0;
        let error = relative_error(mesh.signed_volume(), exact);
        assert!(error < 0.015, "volume error {error}");
        assert!(
            mesh.signed_volume() < exact,
            "an inscribed polyhedron is smaller than its sphere"
        );
    }

    #[test]
    fn sphere_triangle_count_is_20_times_4_to_the_level_and_clamped_at_7() {
        for level in 0..=4 {
            let mesh = sphere(1.0, level);
            assert_eq!(mesh.triangle_count(), 20 * 4usize.pow(level));
            assert_well_formed(&mesh, "sphere");
        }
        assert_eq!(
            sphere(1.0, 99).triangle_count(),
            20 * 4usize.pow(MAX_SPHERE_SUBDIVISIONS)
        );
    }

    #[test]
    fn icosahedron_is_regular_and_sphere_has_poles() {
        let mesh = sphere(1.0, 0);
        for i in 0..20 {
            let [a, b, c] = mesh.triangle(i);
            for edge in [a.distance(b), b.distance(c), c.distance(a)] {
                assert!(
                    (edge - 1.051_462_2).abs() < 1e-5,
                    "triangle {i} has an edge of {edge}"
                );
            }
        }
        let (lo, hi) = sphere(0.5, 3).bounds().expect("non-empty");
        assert_eq!((lo.y, hi.y), (-0.5, 0.5));
    }

    #[test]
    fn cuboid_is_closed_outward_and_its_volume_exact() {
        let mesh = cuboid(Vec3::new(1.0, 2.0, 0.5));
        assert_eq!(mesh.triangle_count(), 12);
        assert_well_formed(&mesh, "box");
        assert!(relative_error(mesh.signed_volume(), 8.0) < 1e-12);
        assert_eq!(
            mesh.bounds(),
            Some((Vec3::new(-1.0, -2.0, -0.5), Vec3::new(1.0, 2.0, 0.5)))
        );
    }

    #[test]
    fn capsule_is_closed_outward_and_its_volume_within_2_percent() {
        let (r, l) = (0.5, 2.0);
        let mesh = capsule(r, l);
        assert_eq!(mesh.triangle_count(), 1024);
        assert_well_formed(&mesh, "capsule");
        let exact = PI * (r * r * l) as f64 + 4.0 / 3.0 * PI * (r * r * r) as f64;
        let error = relative_error(mesh.signed_volume(), exact);
        assert!(error < 0.02, "volume error {error}");
        let (lo, hi) = mesh.bounds().expect("non-empty");
        assert!((hi.y - 1.5).abs() < 1e-6 && (lo.y + 1.5).abs() < 1e-6);
    }

    #[test]
    fn capsule_of_length_0_is_a_closed_sphere() {
        let mesh = capsule(1.0, 0.0);
        assert_eq!(mesh.triangle_count(), 960);
        assert_well_formed(&mesh, "capsule");
    }

    #[test]
    fn cylinder_is_closed_outward_and_its_volume_within_1_percent() {
        let (r, l) = (0.6, 0.4);
        let mesh = cylinder(r, l);
        assert_eq!(mesh.triangle_count(), 128);
        assert_well_formed(&mesh, "cylinder");
        // A 32-gon's area is sin(2π/32)·32/(2π) = 99.4 % of the circle's.
        let exact = PI * (r * r * l) as f64;
        let error = relative_error(mesh.signed_volume(), exact);
        assert!(error < 0.01, "volume error {error}");
        let (lo, hi) = mesh.bounds().expect("non-empty");
        assert!((hi.y - 0.2).abs() < 1e-6 && (lo.y + 0.2).abs() < 1e-6);
        assert!((hi.x - 0.6).abs() < 1e-6);
    }

    #[test]
    fn knot_is_closed_outward_6144_triangles_and_size_across() {
        let mesh = knot(3.5);
        assert_eq!(mesh.triangle_count(), 6144);
        assert!((4000..=10_000).contains(&mesh.triangle_count()));
        assert_well_formed(&mesh, "knot");
        let (lo, hi) = mesh.bounds().expect("non-empty");
        let across = (hi - lo).x.max((hi - lo).z);
        assert!((across - 3.5).abs() < 0.02, "knot is {across} across");
        // Volume of a tube = cross-section × centre-curve length (Pappus);
        // the 16-gon cross-section is 2.5 % smaller than the circle.
        let tube = PI * 0.25f64.powi(2) * 20.0;
        let error = relative_error(mesh.signed_volume(), tube);
        assert!(error < 0.04, "knot volume error {error}");
    }
}
