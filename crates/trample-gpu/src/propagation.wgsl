// Force propagation from DBG to PBG (paper §5.2, Definitions 1–7, Eq. 4;
// DESIGN §5) as generation passes: `begin` and `seed` once, then
// `gather` + `advance` once per generation up to the cap. Each blade of
// generation G+1 gathers, in the fixed order −x, +x, −z, +z, the
// contributions of the active generation-G neighbours that point at it:
// the gather of `trample::force::propagation::gather_force`, no float
// atomics. A pass after the last generation returns at once (`stop`).

@group(0) @binding(0) var<uniform> params: StepParams;
@group(0) @binding(1) var<storage, read_write> state: State;
@group(0) @binding(2) var<storage, read_write> force: array<vec4<f32>>;
@group(0) @binding(3) var<storage, read_write> generation: array<u32>;
@group(0) @binding(4) var<storage, read_write> blade_class: array<u32>;
@group(0) @binding(5) var<storage, read> neighbours: array<vec4<u32>>;
// Workgroups of the next gather pass (x, y, z), read as indirect dispatch
// arguments: (0, 1, 1) once propagation has ended, so the passes left over
// cost a dispatch of nothing.
@group(0) @binding(6) var<storage, read_write> next_gather: array<u32, 3>;

const CLASS_UNTOUCHED: u32 = 0u;
const CLASS_DIRECT: u32 = 1u;
const CLASS_PROPAGATED: u32 = 2u;

// Reset the per-sub-step state.
@compute @workgroup_size(1)
fn begin() {
    state.g = 0u;
    state.stop = 0u;
    atomicStore(&state.any, 0u);
    state.generations = 0u;
    atomicStore(&state.dbg, 0u);
    atomicStore(&state.pbg, 0u);
    atomicStore(&state.displaced, 0u);
    atomicStore(&state.transitions, 0u);
    atomicStore(&state.lod[0], 0u);
    atomicStore(&state.lod[1], 0u);
    atomicStore(&state.lod[2], 0u);
    next_gather[0] = params.counts.w;
    next_gather[1] = (params.counts.x + params.counts.w * 64u - 1u) / (params.counts.w * 64u);
    next_gather[2] = 1u;
    if params.counts.z == 0u {
        state.stop = 1u;
        next_gather[0] = 0u;
    }
}

// Generation 0 = the ancestors (DBG, Definition 4): blades the narrow phase hit.
@compute @workgroup_size(64)
fn seed(@builtin(global_invocation_id) gid: vec3<u32>) {
    let b = blade_index(gid);
    if b >= params.counts.x {
        return;
    }
    if force[b].w > 0.0 {
        generation[b] = 0u;
        blade_class[b] = CLASS_DIRECT;
        atomicAdd(&state.dbg, 1u);
    } else {
        generation[b] = NO_GENERATION;
    }
}

// Active status (Definition 2): finite energy |F| (Definition 1) ≥ L.
fn is_active(f: vec3<f32>) -> bool {
    let e = sqrt((f.x * f.x + f.y * f.y) + f.z * f.z);
    return e < 3.0e38 && e >= params.a.z;
}

@compute @workgroup_size(64)
fn gather(@builtin(global_invocation_id) gid: vec3<u32>) {
    let c = blade_index(gid);
    if c >= params.counts.x || state.stop != 0u || generation[c] != NO_GENERATION {
        return;
    }
    let g = state.g;
    let nb = neighbours[c];
    var sum = force[c].xyz;
    var reached = false;
    // (slot of J seen from c, slot of c seen from J, axis, sign of J's
    // component that points at c): −x, +x, −z, +z.
    for (var s = 0u; s < 4u; s++) {
        let j = nb[s];
        if j >= params.counts.x || generation[j] != g || neighbours[j][s ^ 1u] != c {
            continue;
        }
        let f = force[j].xyz;
        let axis = select(0u, 2u, s >= 2u);
        let sign = select(-1.0, 1.0, s % 2u == 0u);
        let component = f[axis];
        if component * sign > 0.0 && is_active(f) {
            var ef = vec3<f32>(0.0);
            ef[axis] = component;
            sum += ef * params.a.y;
            reached = true;
        }
    }
    if reached {
        force[c] = vec4<f32>(sum, 0.0);
        generation[c] = g + 1u;
        if blade_class[c] == CLASS_UNTOUCHED {
            blade_class[c] = CLASS_PROPAGATED;
        }
        atomicAdd(&state.pbg, 1u);
        atomicStore(&state.any, 1u);
    }
}

// After a gather pass: stop when no blade was reached (termination status,
// Definition 3) or at the cap, else on to the next generation.
@compute @workgroup_size(1)
fn advance() {
    if state.stop != 0u {
        return;
    }
    if atomicLoad(&state.any) == 0u {
        state.stop = 1u;
        next_gather[0] = 0u;
        return;
    }
    state.generations += 1u;
    state.g += 1u;
    atomicStore(&state.any, 0u);
    if state.generations >= params.counts.z {
        state.stop = 1u;
        next_gather[0] = 0u;
    }
}
