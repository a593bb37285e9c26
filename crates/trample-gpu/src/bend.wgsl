// Deformation of every blade with a force (paper §6.1, Eq. 5–7, Fig. 7;
// DESIGN §6): offset-base vector, weights, length preservation, ground
// guard. `trample::deform::bend::bend_blade` with `v1 = F · h` (ours:
// frame-rate independence), `num` = the blade's contact weight (each
// segment counted by its weight; 0, taken as 1, for PBG).

@group(0) @binding(0) var<uniform> params: StepParams;
// The chunk's vertices; vertex 0's w holds the blade's segment length.
@group(0) @binding(1) var<storage, read_write> pos: array<vec4<f32>>;
@group(0) @binding(2) var<storage, read> force: array<vec4<f32>>;
@group(0) @binding(3) var<storage, read> generation: array<u32>;
@group(0) @binding(4) var<storage, read_write> displaced: array<u32>;
@group(0) @binding(5) var<uniform> chunk: Chunk;
@group(0) @binding(6) var<storage, read> ground: array<f32>;
// The step's counters: a far pass counts the blades it moves from rest
// (the main pass's recovery counts the displaced set itself).
@group(0) @binding(7) var<storage, read_write> state: State;
// The blades to bend (`active_list.wgsl`'s `list_bent`): [0] their count.
@group(0) @binding(8) var<storage, read> listed: array<u32>;

// `bend::offset_base` (Eq. 5): the part of v1 perpendicular to AB, over num.
fn offset_base(ab: vec3<f32>, v1: vec3<f32>, num: f32) -> vec3<f32> {
    let ab_len2 = dot(ab, ab);
    if ab_len2 <= 1.17549435e-38 {
        return vec3<f32>(0.0);
    }
    let perpendicular = v1 - ab * (dot(v1, ab) / ab_len2);
    if dot(perpendicular, perpendicular) <= 1e-12 * dot(v1, v1) {
        return vec3<f32>(0.0);
    }
    return perpendicular / max(num, 1.0);
}

@compute @workgroup_size(64)
fn bend(@builtin(global_invocation_id) gid: vec3<u32>) {
    let first = run_start(gid, chunk.groups.x);
    for (var l = first; l < min(first + RUN, chunk.range.y); l++) {
        let b = chunk.range.x + l;
        if generation[b] != NO_GENERATION {
            bend_blade(b);
        }
    }
}

// `bend` over the blades `list_bent` listed (`active_list.wgsl`): those of
// the chunk's dirty patches (those `seed` ran over and those propagation
// listed a candidate in) with a generation.
@compute @workgroup_size(64)
fn bend_listed(@builtin(global_invocation_id) gid: vec3<u32>, @builtin(num_workgroups) groups: vec3<u32>) {
    let i = list_thread(gid, groups);
    if i < listed[0] {
        bend_blade(listed[1u + i]);
    }
}

// Eq. 6 on blade b (reached by propagation). A function of its own: its
// vertex array is zero-initialised where it is declared (WGSL, and naga
// declares a function's variables at its entry), so only the blades bent
// pay for it, not every thread of the field.
fn bend_blade(b: u32) {
    let n = min(params.counts.y, MAX_VERTS - 1u);
    var v: array<vec3<f32>, MAX_VERTS>;
    for (var k = 0u; k <= n; k++) {
        v[k] = pos[vertex_at(k, b)].xyz;
    }
    let f = force[b];
    let base = offset_base(v[n] - v[0], f.xyz * params.a.x, f.w);
    if all(base == vec3<f32>(0.0)) {
        return;
    }
    // Eq. 6: V_i += P(i) · base.
    for (var i = 1u; i <= n; i++) {
        v[i] += base * weight(i - 1u);
    }
    preserve_lengths(&v, n, pos[vertex_at(0u, b)].w);
    for (var k = 1u; k <= n; k++) {
        pos[vertex_at(k, b)] = vec4<f32>(v[k], 0.0);
    }
    if params.far.x != 0u && displaced[b] == 0u {
        atomicAdd(&state.displaced, 1u);
    }
    displaced[b] = 1u;
}
