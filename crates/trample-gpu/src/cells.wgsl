// The per-cell stages (DESIGN §6–7): level of detail from the viewpoint
// (Fig. 1; `trample::field::lod::classify_cells`), billboards (Eq. 8;
// `deform::billboard`), transitions between levels (Eq. 9–13, per cell;
// `deform::transition` as applied by `step::stages::apply_transitions`)
// and recovery of bent billboards (`recovery::recover_slope`). One thread
// per cell; a cell thread owns its blades in `transitions`.
//
// `cell_state` bits 0–1: level (0 geometry, 1 billboard, 2 texture); bits
// 2–3: the level before this sub-step's change (3: unchanged); bit 4: the
// billboard is bent (away from its rest slope).

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
@group(0) @binding(1) var<storage, read_write> state: State;
@group(0) @binding(2) var<storage, read_write> cell_state: array<u32>;
// Per cell two entries: (base xyz, billboard height), (slope_origin_b xyz,
// global cell coordinates gx + 4096 gz as a float).
@group(0) @binding(3) var<storage, read> cell_rest: array<vec4<f32>>;
@group(0) @binding(4) var<storage, read_write> slope: array<vec4<f32>>;
@group(0) @binding(5) var<storage, read> world_roots: array<WorldObb>;
@group(0) @binding(6) var<storage, read_write> pos: array<vec4<f32>>;
// Rest positions; vertex 0's w holds the blade's segment length.
@group(0) @binding(7) var<storage, read> rest: array<vec4<f32>>;
@group(0) @binding(8) var<storage, read_write> displaced: array<u32>;
@group(0) @binding(9) var<uniform> chunk: Chunk;
@group(0) @binding(10) var<storage, read> ground: array<f32>;

const GEOMETRY: u32 = 0u;
const BILLBOARD: u32 = 1u;
const UNCHANGED: u32 = 3u;
const BENT: u32 = 16u;
// `billboard::MIN_T`.
const MIN_T: f32 = 1e-4;

fn level(s: u32) -> u32 {
    return s & 3u;
}

fn changed_from(s: u32) -> u32 {
    return (s >> 2u) & 3u;
}

// Level of a cell at squared distance d2 (`LodParams::level_squared`).
fn level_squared(d2: f32) -> u32 {
    let g = params.eye.w;
    let b = params.lod.x;
    if d2 < g * g {
        return 0u;
    }
    if d2 < b * b {
        return 1u;
    }
    return 2u;
}

@compute @workgroup_size(64)
fn classify(@builtin(global_invocation_id) gid: vec3<u32>) {
    let c = chunk_cell(gid);
    if c == NOT_IN_CHUNK {
        return;
    }
    let s = cell_state[c];
    let d = cell_rest[2u * c].xyz - params.eye.xyz;
    let new_level = level_squared(dot3(d, d));
    var from_level = UNCHANGED;
    if new_level != level(s) {
        from_level = level(s);
        atomicAdd(&state.transitions, 1u);
    }
    atomicAdd(&state.lod[new_level], 1u);
    cell_state[c] = (s & BENT) | (from_level << 2u) | new_level;
}

// Eq. 8 (`billboard::billboard_slope`): slope_origin + t · R / |t|².
fn billboard_slope(origin: vec3<f32>, t: vec3<f32>, r: f32) -> vec3<f32> {
    let t2 = dot3(t, t);
    if t2 < MIN_T * MIN_T {
        return origin + vec3<f32>(0.0, -1.0, 0.0) * (r / MIN_T);
    }
    return origin + t * (r / t2);
}

fn distance2(a: vec3<f32>, b: vec3<f32>) -> f32 {
    let d = a - b;
    return dot3(d, d);
}

@compute @workgroup_size(64)
fn billboards(@builtin(global_invocation_id) gid: vec3<u32>) {
    let c = chunk_cell(gid);
    if c == NOT_IN_CHUNK || level(cell_state[c]) != BILLBOARD {
        return;
    }
    let base = cell_rest[2u * c].xyz;
    let height = cell_rest[2u * c].w;
    let origin = cell_rest[2u * c + 1u].xyz;
    var sl = slope[c].xyz;
    var bent = false;
    let packed = u32(cell_rest[2u * c + 1u].w);
    let gx = f32(packed % 4096u);
    let gz = f32(packed / 4096u);
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

// `transition::blade_offset`: (tip − root − rest chord) / rest height.
fn blade_offset(b: u32) -> vec3<f32> {
    let n = params.counts.y;
    let chord = pos[vertex_at(n, b)].xyz - pos[vertex_at(0u, b)].xyz;
    let rest_chord = rest[vertex_at(n, b)].xyz - rest[vertex_at(0u, b)].xyz;
    let rest_height = length(rest_chord);
    if !(rest_height > 1e-12) {
        return vec3<f32>(0.0);
    }
    return (chord - rest_chord) / rest_height;
}

@compute @workgroup_size(64)
fn transitions(@builtin(global_invocation_id) gid: vec3<u32>) {
    let c = chunk_cell(gid);
    if c == NOT_IN_CHUNK {
        return;
    }
    let s = cell_state[c];
    let from_level = changed_from(s);
    if from_level == UNCHANGED {
        return;
    }
    let bpc = params.cells.y;
    let n = min(params.counts.y, MAX_VERTS - 1u);
    // Eq. 9–11: off_g, the mean offset of the cell's blades.
    var sum = vec3<f32>(0.0);
    for (var b = c * bpc; b < (c + 1u) * bpc; b++) {
        sum += blade_offset(b);
    }
    let off_g = sum / f32(max(bpc, 1u));
    let origin = cell_rest[2u * c + 1u].xyz;
    if from_level == GEOMETRY {
        // Eq. 12: the billboard takes its blades' offset.
        let sl = origin + off_g;
        slope[c] = vec4<f32>(sl, 0.0);
        if any(sl != origin) {
            cell_state[c] = s | BENT;
        }
        return;
    }
    if level(s) != GEOMETRY {
        return;
    }
    // Eq. 13: what the billboard shows and the blades do not acts on their
    // last segment through Eq. 5 (`transition::bend_last_segment`).
    let missing = (slope[c].xyz - origin) - off_g;
    if dot3(missing, missing) < 1e-12 {
        return;
    }
    for (var b = c * bpc; b < (c + 1u) * bpc; b++) {
        displaced[b] = 1u;
        let rest_h = length(rest[vertex_at(n, b)].xyz - rest[vertex_at(0u, b)].xyz);
        var v: array<vec3<f32>, MAX_VERTS>;
        for (var k = 0u; k <= n; k++) {
            v[k] = pos[vertex_at(k, b)].xyz;
        }
        let v1 = missing * rest_h;
        let ab = v[n] - v[0];
        let ab_len2 = dot(ab, ab);
        if ab_len2 <= 1.17549435e-38 {
            continue;
        }
        let perpendicular = v1 - ab * (dot(v1, ab) / ab_len2);
        if dot(perpendicular, perpendicular) <= 1e-12 * dot(v1, v1) {
            continue;
        }
        v[n] += perpendicular;
        preserve_from(&v, n, n, rest[vertex_at(0u, b)].w);
        pos[vertex_at(n, b)] = vec4<f32>(v[n], 0.0);
    }
}

// `recovery::recover_slope` for bent billboards (recovery on only).
@compute @workgroup_size(64)
fn recover_slopes(@builtin(global_invocation_id) gid: vec3<u32>) {
    let c = chunk_cell(gid);
    if c == NOT_IN_CHUNK || params.b.w == 0.0 {
        return;
    }
    let s = cell_state[c];
    if (s & BENT) == 0u {
        return;
    }
    let origin = cell_rest[2u * c + 1u].xyz;
    var sl = slope[c].xyz;
    if all(sl == origin) {
        cell_state[c] = s & ~BENT;
        return;
    }
    let h = normalize_or_zero(sl).y;
    let rest_h = normalize_or_zero(origin).y;
    let q = recovered_fraction(params.a.x, time_constant(flatness(h, rest_h)));
    if q == 0.0 {
        return;
    }
    sl += (origin - sl) * q;
    if distance2(sl, origin) < REST_EPSILON * REST_EPSILON {
        slope[c] = vec4<f32>(origin, 0.0);
        cell_state[c] = s & ~BENT;
    } else {
        slope[c] = vec4<f32>(sl, 0.0);
    }
}

fn normalize_or_zero(v: vec3<f32>) -> vec3<f32> {
    let l2 = dot3(v, v);
    if l2 > 0.0 && l2 < 3.0e38 {
        return v * (1.0 / sqrt(l2));
    }
    return vec3<f32>(0.0);
}
