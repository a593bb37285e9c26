// The ground guard and length preservation (paper Fig. 7, DESIGN §6;
// prepended to bend.wgsl, recovery.wgsl and cells.wgsl, not a stage of its
// own): `trample::field::Terrain::height_at` over the tables of
// `terrain.rs`, `trample::deform::bend::guarded_end`, `preserve_from`.
// Each stage declares `var<storage, read> ground: array<f32>` (the
// `GpuTerrain` buffer).
//
// `ground` layout: [0] kind (0 flat, 1 noise, 2 height map), then
// flat: [1] height;
// height map: [1] samples in x, [2] in z, [3] origin x, [4] origin z,
//   [5] size x, [6] size z; heights row-major (z then x) from entry 16;
// noise: [1] amplitude, [2] wavelength; octave k (0, 1) tabulated over the
//   lattice points i0 .. i0 + nx, j0 .. j0 + nz: [3 + 5k] i0, [4 + 5k] j0,
//   [5 + 5k] nx, [6 + 5k] nz, [7 + 5k] first entry of its table.

const TERRAIN_FLAT: f32 = 0.0;
const TERRAIN_NOISE: f32 = 1.0;

// `HeightGrid::sample`: bilinear, clamped to the grid.
fn height_map(x: f32, z: f32) -> f32 {
    let w = u32(ground[1]);
    let h = u32(ground[2]);
    let fx = clamp((x - ground[3]) / ground[5] * f32(w - 1u), 0.0, f32(w - 1u));
    let fz = clamp((z - ground[4]) / ground[6] * f32(h - 1u), 0.0, f32(h - 1u));
    let x0 = min(u32(fx), w - 2u);
    let z0 = min(u32(fz), h - 2u);
    let tx = fx - f32(x0);
    let tz = fz - f32(z0);
    let at00 = ground[16u + z0 * w + x0];
    let at10 = ground[16u + z0 * w + x0 + 1u];
    let at01 = ground[16u + (z0 + 1u) * w + x0];
    let at11 = ground[16u + (z0 + 1u) * w + x0 + 1u];
    let a = at00 + (at10 - at00) * tx;
    let b = at01 + (at11 - at01) * tx;
    return a + (b - a) * tz;
}

// `terrain::lattice` of octave k at (i, j), from its table (clamped to it:
// exact within the field and a blade's reach beyond it).
fn lattice_value(k: u32, i: i32, j: i32) -> f32 {
    let base = 3u + 5u * k;
    let nx = i32(ground[base + 2u]);
    let nz = i32(ground[base + 3u]);
    let ci = clamp(i - i32(ground[base]), 0, nx - 1);
    let cj = clamp(j - i32(ground[base + 1u]), 0, nz - 1);
    return ground[u32(ground[base + 4u]) + u32(cj * nx + ci)];
}

// `terrain::smooth` (`smooth` is reserved in WGSL).
fn smooth_t(t: f32) -> f32 {
    return t * t * (3.0 - 2.0 * t);
}

// `terrain::value_noise` of octave k.
fn value_noise(k: u32, x: f32, z: f32) -> f32 {
    let xf = floor(x);
    let zf = floor(z);
    let ix = i32(xf);
    let iz = i32(zf);
    let tx = smooth_t(x - xf);
    let tz = smooth_t(z - zf);
    let v00 = lattice_value(k, ix, iz);
    let v10 = lattice_value(k, ix + 1, iz);
    let v01 = lattice_value(k, ix, iz + 1);
    let v11 = lattice_value(k, ix + 1, iz + 1);
    let a = v00 + (v10 - v00) * tx;
    let b = v01 + (v11 - v01) * tx;
    return a + (b - a) * tz;
}

// `Terrain::height_at`.
fn ground_at(x: f32, z: f32) -> f32 {
    let kind = ground[0];
    if kind == TERRAIN_FLAT {
        return ground[1];
    }
    if kind == TERRAIN_NOISE {
        let wl = ground[2];
        let n1 = value_noise(0u, x / wl, z / wl);
        let n2 = value_noise(1u, x * 2.0 / wl, z * 2.0 / wl);
        return ground[1] * (0.75 * n1 + 0.25 * n2);
    }
    return height_map(x, z);
}

fn clears(p: vec3<f32>) -> bool {
    return p.y >= ground_at(p.x, p.z) + params.b.x;
}

// `bend::guarded_end`.
fn guarded_end(start: vec3<f32>, dir: vec3<f32>, len: f32, fallback: vec3<f32>) -> vec3<f32> {
    let end = start + dir * len;
    if clears(end) {
        return end;
    }
    var h = unit_or(vec3<f32>(dir.x, 0.0, dir.z), vec3<f32>(0.0));
    if all(h == vec3<f32>(0.0)) {
        h = unit_or(vec3<f32>(fallback.x, 0.0, fallback.z), vec3<f32>(0.0));
    }
    if all(h == vec3<f32>(0.0)) {
        h = vec3<f32>(1.0, 0.0, 0.0);
    }
    // Exact on flat ground: the elevation that puts the end on the guard.
    // Elsewhere it brackets the answer for the bisection.
    let guard_y = ground_at(end.x, end.z) + params.b.x;
    var lo = clamp(dir.y, -1.0, 1.0);
    let guess = clamp((guard_y - start.y) / len, lo, 1.0);
    var hi = 1.0;
    let at_guess = start + (h * sqrt(max(1.0 - guess * guess, 0.0)) + vec3<f32>(0.0, guess, 0.0)) * len;
    if clears(at_guess) {
        if ground[0] == TERRAIN_FLAT {
            return at_guess;
        }
        hi = guess;
    } else {
        let top = start + vec3<f32>(0.0, len, 0.0);
        if !clears(top) {
            return top;
        }
    }
    for (var k = 0; k < 24; k++) {
        let mid = 0.5 * (lo + hi);
        let p = start + (h * sqrt(max(1.0 - mid * mid, 0.0)) + vec3<f32>(0.0, mid, 0.0)) * len;
        if clears(p) {
            hi = mid;
        } else {
            lo = mid;
        }
    }
    return start + (h * sqrt(max(1.0 - hi * hi, 0.0)) + vec3<f32>(0.0, hi, 0.0)) * len;
}

// `bend::preserve_lengths`: from the root up, every segment back to
// `seg_len` along its new direction, above the ground guard.
fn preserve_lengths(v: ptr<function, array<vec3<f32>, MAX_VERTS>>, n: u32, seg_len: f32) {
    preserve_from(v, 1u, n, seg_len);
}

// `bend::preserve_from`: as `preserve_lengths` for vertices first ..= n.
fn preserve_from(v: ptr<function, array<vec3<f32>, MAX_VERTS>>, first: u32, n: u32, seg_len: f32) {
    if !(seg_len > 0.0) || first == 0u || first > n {
        return;
    }
    var last_dir = vec3<f32>(0.0, 1.0, 0.0);
    if first >= 2u {
        last_dir = unit_or((*v)[first - 1u] - (*v)[first - 2u], last_dir);
    }
    for (var i = first; i <= n; i++) {
        let start = (*v)[i - 1u];
        let dir = unit_or((*v)[i] - start, last_dir);
        let end = guarded_end(start, dir, seg_len, last_dir);
        last_dir = unit_or(end - start, dir);
        (*v)[i] = end;
    }
}

