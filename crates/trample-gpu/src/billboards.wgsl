// Billboards bent by an object (paper Eq. 8, §6.2; `deform::billboard`, as
// `step::deform::bend_billboards` applies it): the paper's mode only
// (`sim.track_everywhere = false`; otherwise billboards follow their
// blades, follow.wgsl). One thread per billboard cell, every object.

// Layout-compatible with `GpuWorldObb` in cells.rs: an object's root box in
// the world at this sub-step.
struct WorldObb {
    center: vec4<f32>,
    u: vec4<f32>,
    v: vec4<f32>,
    w: vec4<f32>,
    half: vec4<f32>,
}

@group(0) @binding(0) var<uniform> params: StepParams;
@group(0) @binding(1) var<storage, read_write> cell_state: array<u32>;
@group(0) @binding(2) var<storage, read> cell_rest: array<vec4<f32>>;
@group(0) @binding(3) var<storage, read_write> slope: array<vec4<f32>>;
@group(0) @binding(4) var<storage, read> world_roots: array<WorldObb>;
@group(0) @binding(5) var<uniform> chunk: Chunk;
@group(0) @binding(6) var<storage, read> ground: array<f32>;

// `billboard::MIN_T`.
const MIN_T: f32 = 1e-4;

// Eq. 8 (`billboard::billboard_slope`): slope_origin + t · R / |t|².
fn billboard_slope(origin: vec3<f32>, t: vec3<f32>, r: f32) -> vec3<f32> {
    let t2 = dot3(t, t);
    if t2 < MIN_T * MIN_T {
        return origin + vec3<f32>(0.0, -1.0, 0.0) * (r / MIN_T);
    }
    return origin + t * (r / t2);
}

@compute @workgroup_size(64)
fn billboards(@builtin(global_invocation_id) gid: vec3<u32>) {
    let c = chunk_cell(gid);
    if c == NOT_IN_CHUNK || level(cell_state[c]) != BILLBOARD {
        return;
    }
    let base = cell_rest[2u * c].xyz;
    let height = cell_rest[2u * c].w;
    // A cell without grass (grass maps) has a billboard of height 0.
    if !(height > 0.0) {
        return;
    }
    let origin = cell_rest[2u * c + 1u].xyz;
    var sl = slope[c].xyz;
    var bent = false;
    let packed = bitcast<u32>(cell_rest[2u * c + 1u].w);
    let gx = f32(packed & 0xffffu);
    let gz = f32(packed >> 16u);
    for (var i = 0u; i < params.cells.z; i++) {
        let o = world_roots[i];
        // Only the cells the CPU path tests: squares overlapping the box's
        // (x, z) extent (`GpuWorldObb::new`).
        if gx < o.center.w || gx > o.u.w || gz < o.v.w || gz > o.w.w {
            continue;
        }
        let top = billboard_top(base, sl, height);
        let centre = (base + top) * 0.5;
        if !hits_box(centre, (top - base) * 0.5, o.center.xyz, o.u.xyz, o.v.xyz, o.w.xyz, o.half.xyz) {
            continue;
        }
        let r = length(o.half.xyz);
        let candidate = billboard_slope(origin, centre - o.center.xyz, r);
        // `billboard::deflect_billboard`: keep the larger deflection.
        if distance2(candidate, origin) > distance2(sl, origin) {
            sl = candidate;
        }
        bent = true;
    }
    if bent {
        slope[c] = vec4<f32>(sl, 0.0);
        cell_state[c] |= BENT;
    }
}
