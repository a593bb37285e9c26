//! Test meshes and a seeded RNG shared by the `obb_*` and `collision_*`
//! tests (the built-in shapes of `object::shapes` are written elsewhere).
//! Every closed mesh here is welded and wound counter-clockwise outwards.
#![allow(dead_code)]

use std::collections::HashMap;
use std::f32::consts::{PI, TAU};

use glam::Vec3;
use trample::object::TriMesh;

/// SplitMix64: small, seeded, good enough for test inputs.
pub struct Rng(u64);

impl Rng {
    pub fn new(seed: u64) -> Self {
        Self(seed)
    }

    pub fn next_u64(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9e37_79b9_7f4a_7c15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        z ^ (z >> 31)
    }

    /// Uniform in [0, 1).
    pub fn unit(&mut self) -> f32 {
        (self.next_u64() >> 40) as f32 / (1u64 << 24) as f32
    }

    /// Uniform in [lo, hi).
    pub fn range(&mut self, lo: f32, hi: f32) -> f32 {
        lo + (hi - lo) * self.unit()
    }

    /// Uniform on the unit sphere.
    pub fn direction(&mut self) -> Vec3 {
        let z = self.range(-1.0, 1.0);
        let a = self.range(0.0, TAU);
        let s = (1.0 - z * z).max(0.0).sqrt();
        Vec3::new(s * a.cos(), z, s * a.sin())
    }

    /// Uniform in the cube [-h, h]^3.
    pub fn in_cube(&mut self, h: f32) -> Vec3 {
        Vec3::new(self.range(-h, h), self.range(-h, h), self.range(-h, h))
    }
}

/// Merges vertices with bit-identical positions.
pub fn weld(positions: &[Vec3], tris: &[[u32; 3]]) -> TriMesh {
    let mut map: HashMap<[u32; 3], u32> = HashMap::new();
    let mut out = TriMesh::default();
    let remap: Vec<u32> = positions
        .iter()
        .map(|p| {
            let key = (*p + Vec3::ZERO).to_array().map(f32::to_bits);
            *map.entry(key).or_insert_with(|| {
                out.positions.push(*p);
                out.positions.len() as u32 - 1
            })
        })
        .collect();
    out.indices = tris.iter().map(|t| t.map(|i| remap[i as usize])).collect();
    out
}

/// UV sphere centred at the origin: `stacks` rings from pole to pole,
/// `slices` around; 2 · slices · (stacks − 1) triangles.
pub fn uv_sphere(radius: f32, stacks: u32, slices: u32) -> TriMesh {
    star_shaped(stacks, slices, |_, _| radius)
}

/// A closed star-shaped mesh around the origin with radius `r(θ, φ)` (θ
/// from +y, φ around y). Poles are single vertices, the seam is shared.
pub fn star_shaped(stacks: u32, slices: u32, r: impl Fn(f32, f32) -> f32) -> TriMesh {
    let mut mesh = TriMesh::default();
    let north = Vec3::new(0.0, r(0.0, 0.0), 0.0);
    mesh.positions.push(north);
    for i in 1..stacks {
        let theta = PI * i as f32 / stacks as f32;
        for j in 0..slices {
            let phi = TAU * j as f32 / slices as f32;
            let d = Vec3::new(
                theta.sin() * phi.cos(),
                theta.cos(),
                theta.sin() * phi.sin(),
            );
            mesh.positions.push(d * r(theta, phi));
        }
    }
    mesh.positions.push(Vec3::new(0.0, -r(PI, 0.0), 0.0));
    let south = mesh.positions.len() as u32 - 1;
    let ring = |i: u32, j: u32| 1 + (i - 1) * slices + j % slices;
    for j in 0..slices {
        mesh.indices.push([0, ring(1, j + 1), ring(1, j)]);
        mesh.indices
            .push([ring(stacks - 1, j), ring(stacks - 1, j + 1), south]);
    }
    for i in 1..stacks - 1 {
        for j in 0..slices {
            let (a, b, c, d) = (
                ring(i, j),
                ring(i, j + 1),
                ring(i + 1, j + 1),
                ring(i + 1, j),
            );
            mesh.indices.push([a, b, d]);
            mesh.indices.push([b, c, d]);
        }
    }
    mesh
}

/// A non-convex closed star-shaped blob: a sphere of radius `radius` with
/// smooth bumps and dents of ±30 % and a seeded random phase.
pub fn bumpy_sphere(radius: f32, stacks: u32, slices: u32, seed: u64) -> TriMesh {
    let mut rng = Rng::new(seed);
    let (p1, p2, p3) = (
        rng.range(0.0, TAU),
        rng.range(0.0, TAU),
        rng.range(0.0, TAU),
    );
    star_shaped(stacks, slices, move |theta, phi| {
        let bump = 0.18 * (3.0 * theta + p1).sin() * (4.0 * phi + p2).cos()
            + 0.12 * (5.0 * phi + 2.0 * theta + p3).sin();
        // Taper the bumps at the poles so the pole vertex is well defined.
        radius * (1.0 + bump * theta.sin())
    })
}

/// Torus around the y axis: major radius `major`, tube radius `minor`.
pub fn torus(major: f32, minor: f32, n_major: u32, n_minor: u32) -> TriMesh {
    let mut mesh = TriMesh::default();
    for i in 0..n_major {
        let u = TAU * i as f32 / n_major as f32;
        for j in 0..n_minor {
            let v = TAU * j as f32 / n_minor as f32;
            let rr = major + minor * v.cos();
            mesh.positions
                .push(Vec3::new(rr * u.cos(), minor * v.sin(), rr * u.sin()));
        }
    }
    let at = |i: u32, j: u32| (i % n_major) * n_minor + j % n_minor;
    for i in 0..n_major {
        for j in 0..n_minor {
            let (a, b, c, d) = (at(i, j), at(i, j + 1), at(i + 1, j + 1), at(i + 1, j));
            mesh.indices.push([a, b, d]);
            mesh.indices.push([b, c, d]);
        }
    }
    mesh
}

/// Axis-aligned box centred at `centre` with half extents `half`, each face
/// an `n × n` grid of quads (2 triangles each), welded.
pub fn box_mesh(centre: Vec3, half: Vec3, n: u32) -> TriMesh {
    let mut positions = Vec::new();
    let mut tris = Vec::new();
    for axis in 0..3 {
        for sign in [-1.0f32, 1.0] {
            let mut normal = Vec3::ZERO;
            normal[axis] = sign;
            let mut t1 = Vec3::ZERO;
            t1[(axis + 1) % 3] = 1.0;
            let t2 = normal.cross(t1);
            for a in 0..n {
                for b in 0..n {
                    let corner = |da: u32, db: u32| {
                        let s = -1.0 + 2.0 * (a + da) as f32 / n as f32;
                        let t = -1.0 + 2.0 * (b + db) as f32 / n as f32;
                        centre + (normal + t1 * s + t2 * t) * half
                    };
                    let base = positions.len() as u32;
                    positions.extend([corner(0, 0), corner(1, 0), corner(1, 1), corner(0, 1)]);
                    tris.push([base, base + 1, base + 2]);
                    tris.push([base, base + 2, base + 3]);
                }
            }
        }
    }
    weld(&positions, &tris)
}

/// An open height-field sheet over [-1, 1]² in x–z (not closed).
pub fn wavy_sheet(n: u32) -> TriMesh {
    let mut mesh = TriMesh::default();
    for i in 0..=n {
        for j in 0..=n {
            let (x, z) = (
                -1.0 + 2.0 * i as f32 / n as f32,
                -1.0 + 2.0 * j as f32 / n as f32,
            );
            mesh.positions
                .push(Vec3::new(x, 0.2 * (3.0 * x).sin() * (2.0 * z).cos(), z));
        }
    }
    let at = |i: u32, j: u32| i * (n + 1) + j;
    for i in 0..n {
        for j in 0..n {
            mesh.indices.push([at(i, j), at(i, j + 1), at(i + 1, j)]);
            mesh.indices
                .push([at(i, j + 1), at(i + 1, j + 1), at(i + 1, j)]);
        }
    }
    mesh
}

/// A soup of `n` random triangles in [-h, h]^3 (open, unwelded).
pub fn random_soup(n: u32, h: f32, seed: u64) -> TriMesh {
    let mut rng = Rng::new(seed);
    let mut mesh = TriMesh::default();
    for t in 0..n {
        for _ in 0..3 {
            mesh.positions.push(rng.in_cube(h));
        }
        mesh.indices.push([3 * t, 3 * t + 1, 3 * t + 2]);
    }
    mesh
}

/// Signed volume by the divergence theorem: positive for an outward-wound
/// closed mesh.
pub fn signed_volume(mesh: &TriMesh) -> f32 {
    (0..mesh.triangle_count())
        .map(|i| {
            let [a, b, c] = mesh.triangle(i);
            a.dot(b.cross(c)) / 6.0
        })
        .sum()
}

/// The named meshes used across the tests.
pub fn all_meshes() -> Vec<(&'static str, TriMesh)> {
    vec![
        ("uv sphere", uv_sphere(1.0, 24, 48)),
        ("bumpy sphere", bumpy_sphere(1.0, 32, 64, 7)),
        ("torus", torus(1.0, 0.35, 64, 32)),
        (
            "box",
            box_mesh(Vec3::new(0.3, -0.2, 0.1), Vec3::new(1.0, 0.5, 0.25), 4),
        ),
        ("wavy sheet", wavy_sheet(16)),
        ("random soup", random_soup(300, 1.0, 11)),
    ]
}
