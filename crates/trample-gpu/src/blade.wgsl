// Shared by bend.wgsl and recovery.wgsl (prepended to each; not a stage of
// its own): the step parameters, the blade buffers, and length preservation
// with the ground guard (paper Fig. 7; `trample::deform::bend::preserve_from`
// and `guarded_end`), on flat terrain only.

// Layout-compatible with `GpuStepParams` in step_params.rs.
struct StepParams {
    // sub-step h (s), att, threshold L (m/s), ground height (m)
    a: vec4<f32>,
    // ground clearance (m), recovery_s, trail, recovery on (1) / off (0)
    b: vec4<f32>,
    // P(1) .. P(15) (Eq. 7), zero beyond n
    weights: array<vec4<f32>, 4>,
    // blade count, segments, generation passes, workgroups in x
    counts: vec4<u32>,
    // viewpoint (LOD eye) xyz, geometry_m
    eye: vec4<f32>,
    // billboard_m, unused ×3
    lod: vec4<f32>,
    // cell count, blades per cell, object count, unused
    cells: vec4<u32>,
}

// Layout-compatible with `GpuCounters` in step_params.rs.
struct State {
    g: u32,
    stop: u32,
    any: atomic<u32>,
    generations: u32,
    dbg: atomic<u32>,
    pbg: atomic<u32>,
    displaced: atomic<u32>,
    // cells that changed level this sub-step
    transitions: atomic<u32>,
}

const NO_GENERATION: u32 = 255u;
const MAX_VERTS: u32 = 16u;
// `recovery::REST_EPSILON`: closer than this to rest (m) snaps to rest.
const REST_EPSILON: f32 = 1e-4;

fn blade_index(gid: vec3<u32>) -> u32 {
    return gid.x + gid.y * params.counts.w * 64u;
}

fn weight(i: u32) -> f32 {
    return params.weights[i / 4u][i % 4u];
}

// `bend::unit_or`.
fn unit_or(d: vec3<f32>, fallback: vec3<f32>) -> vec3<f32> {
    let len2 = dot(d, d);
    if len2 > 1e-24 && len2 < 3.0e38 {
        return d / sqrt(len2);
    }
    return fallback;
}

fn clears(p: vec3<f32>) -> bool {
    return p.y >= params.a.w + params.b.x;
}

// `bend::guarded_end` on flat ground.
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
    let guard_y = params.a.w + params.b.x;
    var lo = clamp(dir.y, -1.0, 1.0);
    let guess = clamp((guard_y - start.y) / len, lo, 1.0);
    var hi = 1.0;
    let at_guess = start + (h * sqrt(max(1.0 - guess * guess, 0.0)) + vec3<f32>(0.0, guess, 0.0)) * len;
    if clears(at_guess) {
        return at_guess;
    }
    let top = start + vec3<f32>(0.0, len, 0.0);
    if !clears(top) {
        return top;
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

// exp(y) − 1 without the cancellation near 0 (WGSL has no expm1).
fn expm1(y: f32) -> f32 {
    if abs(y) < 0.5 {
        // Taylor to y^9: relative error < 1e-9 for |y| < 0.5.
        var term = y;
        var sum = y;
        for (var k = 2; k <= 9; k++) {
            term *= y / f32(k);
            sum += term;
        }
        return sum;
    }
    return exp(y) - 1.0;
}

// `recovery::recovered_fraction`.
fn recovered_fraction(dt: f32, tau: f32) -> f32 {
    if dt > 0.0 && tau > 0.0 {
        return clamp(-expm1(-(dt / tau)), 0.0, 1.0);
    }
    if tau <= 0.0 && dt > 0.0 {
        return 1.0;
    }
    return 0.0;
}

// `recovery::flatness`.
fn flatness(height: f32, rest_height: f32) -> f32 {
    if rest_height > 0.0 {
        return clamp(1.0 - height / rest_height, 0.0, 1.0);
    }
    return 0.0;
}

// `recovery::time_constant`: τ = recovery_s · (1 + trail · flatness).
fn time_constant(flat: f32) -> f32 {
    var extra = 0.0;
    if params.b.z > 0.0 && flat > 0.0 {
        extra = params.b.z * flat;
    }
    return params.b.y * (1.0 + extra);
}
