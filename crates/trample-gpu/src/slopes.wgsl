// Recovery of bent billboards (`recovery::recover_slope`), the paper's mode
// only (`sim.track_everywhere = false`; otherwise billboards follow their
// blades, which recover): with `[sim]`'s recovery time and trail.

@group(0) @binding(0) var<uniform> params: StepParams;
@group(0) @binding(1) var<storage, read_write> cell_state: array<u32>;
@group(0) @binding(2) var<storage, read> cell_rest: array<vec4<f32>>;
@group(0) @binding(3) var<storage, read_write> slope: array<vec4<f32>>;
@group(0) @binding(4) var<uniform> chunk: Chunk;

@compute @workgroup_size(64)
fn recover_slopes(@builtin(global_invocation_id) gid: vec3<u32>) {
    let c = chunk_cell(gid);
    if c == NOT_IN_CHUNK || !(params.b.y > 0.0) {
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
    let q = tail_fraction(recovered_fraction(params.a.x, time_constant(params.b.y, params.b.z, flatness(h, rest_h))), sqrt(distance2(sl, origin)));
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
