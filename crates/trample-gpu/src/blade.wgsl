// Shared by the step stages (prepended to each; not a stage of its own):
// the step parameters, the counters, indexing and recovery's formulas. The
// ground guard and length preservation are in guard.wgsl.

// Layout-compatible with `GpuStepParams` in step_params.rs.
struct StepParams {
    // sub-step h (s), att, threshold L (m/s), ground height (m)
    a: vec4<f32>,
    // ground clearance (m), `[sim]` recovery_s (0 for ∞) and trail (the
    // paper's billboard recovery; blades recover with their track owner's,
    // recovery.wgsl), recovery on for some owner (1) / off (0)
    b: vec4<f32>,
    // P(1) .. P(15) (Eq. 7), zero beyond n
    weights: array<vec4<f32>, 4>,
    // blade count, segments, generation passes, workgroups in x
    counts: vec4<u32>,
    // viewpoint (LOD eye) xyz, geometry_m
    eye: vec4<f32>,
    // billboard_m, propagation's threshold fade-in (fraction of L), hold
    // weight (`PropagationParams`), unused
    lod: vec4<f32>,
    // cell count, blades per cell, object count, track everywhere
    cells: vec4<u32>,
    // x: 1 in a far pass (its counts add to the step's), y: 1 on the
    // step's first sub-step (`GpuStepParams::far`)
    far: vec4<u32>,
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
    // cells at each level after `classify`: geometry, billboard, texture
    lod: array<atomic<u32>, 3>,
    // blades the contact response moved this sub-step (and the far
    // passes' before it)
    contact: atomic<u32>,
    // the most generations of the step's sub-steps before this one
    earlier_generations: u32,
}

const NO_GENERATION: u32 = 255u;
const MAX_VERTS: u32 = 16u;
// `recovery::REST_EPSILON`: closer than this to rest (m) snaps to rest.
const REST_EPSILON: f32 = 1e-4;

fn blade_index(gid: vec3<u32>) -> u32 {
    return gid.x + gid.y * params.counts.w * 64u;
}

// Blades a thread takes, one after the other, in `bend`, the pass over the
// whole field that does nothing for most blades (`kernel::RUN`): a real
// GPU pays for every workgroup it starts, and a workgroup of 64 threads
// that mostly return at once costs more than the loads it makes (session
// 24, H200: the herd's bend pass, 262,144 workgroups for 67 MB of reads,
// 0.42 ms; in runs of 8, 0.29 ms; the default scene's 0.028 → 0.047 ms).
// Not for the passes that write every blade: `seed` in runs of 8 took the
// herd's propagation from 0.68 to 2.78 ms (presumably a warp's stores 8
// blades apart, 32 cache lines where one blade a thread writes 4), and
// `recover` went from 0.21 to 0.23 ms.
const RUN: u32 = 8u;

// The first of this thread's RUN blades (an index below the pass's count
// of blades, or past it) in a dispatch of `kernel::run_grid` over a grid
// of `groups_x` workgroups in x (64 threads each, one blade a thread).
fn run_start(gid: vec3<u32>, groups_x: u32) -> u32 {
    let gx = (groups_x + RUN - 1u) / RUN;
    return (gid.x + gid.y * gx * 64u) * RUN;
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

// `recovery::RECOVERY_TAIL_M`: within this of rest (m) a blade recovers at
// a constant speed.
const RECOVERY_TAIL_M: f32 = 0.01;

// `recovery::tail_fraction`.
fn tail_fraction(q: f32, deviation: f32) -> f32 {
    if deviation > 0.0 && deviation < RECOVERY_TAIL_M {
        return min(q * (RECOVERY_TAIL_M / deviation), 1.0);
    }
    return q;
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
fn time_constant(recovery_s: f32, trail: f32, flat: f32) -> f32 {
    var extra = 0.0;
    if trail > 0.0 && flat > 0.0 {
        extra = trail * flat;
    }
    return recovery_s * (1.0 + extra);
}
