// Recovery of displaced blades towards rest (ours, DESIGN §6; the paper's
// future work): `trample::recovery::recover_blade`. Each displaced vertex
// moves the fraction 1 − exp(−h/τ) of the way back, τ = recovery_s ·
// (1 + trail · flatness), then lengths are restored; a blade within 1e-4 m
// of rest snaps to it and leaves the displaced set. With recovery off
// (recovery_s = ∞) the pass only counts the displaced blades.

@group(0) @binding(0) var<uniform> params: StepParams;
@group(0) @binding(1) var<storage, read_write> state: State;
@group(0) @binding(2) var<storage, read_write> pos: array<vec4<f32>>;
@group(0) @binding(3) var<storage, read> rest: array<vec4<f32>>;
@group(0) @binding(4) var<storage, read> seg_len: array<f32>;
@group(0) @binding(5) var<storage, read_write> displaced: array<u32>;
@group(0) @binding(6) var<uniform> chunk: Chunk;
@group(0) @binding(7) var<storage, read> ground: array<f32>;


@compute @workgroup_size(64)
fn recover(@builtin(global_invocation_id) gid: vec3<u32>) {
    let b = chunk_blade(gid);
    if b == NOT_IN_CHUNK || displaced[b] == 0u {
        return;
    }
    if params.b.w == 0.0 {
        atomicAdd(&state.displaced, 1u);
        return;
    }
    let n = min(params.counts.y, MAX_VERTS - 1u);
    var v: array<vec3<f32>, MAX_VERTS>;
    var r: array<vec3<f32>, MAX_VERTS>;
    var same = true;
    for (var k = 0u; k <= n; k++) {
        v[k] = pos[vertex_at(k, b)].xyz;
        r[k] = rest[vertex_at(k, b)].xyz;
        same = same && all(v[k] == r[k]);
    }
    if same {
        displaced[b] = 0u;
        return;
    }
    let flat = flatness(v[n].y - v[0].y, r[n].y - r[0].y);
    let q = recovered_fraction(params.a.x, time_constant(flat));
    if q == 0.0 {
        atomicAdd(&state.displaced, 1u);
        return;
    }
    for (var k = 1u; k <= n; k++) {
        v[k] += (r[k] - v[k]) * q;
    }
    preserve_lengths(&v, n, seg_len[b]);
    var at_rest = true;
    for (var k = 0u; k <= n; k++) {
        let d = v[k] - r[k];
        at_rest = at_rest && dot(d, d) < REST_EPSILON * REST_EPSILON;
    }
    for (var k = 1u; k <= n; k++) {
        pos[vertex_at(k, b)] = vec4<f32>(select(v[k], r[k], at_rest), 0.0);
    }
    if at_rest {
        displaced[b] = 0u;
    } else {
        atomicAdd(&state.displaced, 1u);
    }
}
