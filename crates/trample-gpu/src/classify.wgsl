// Level of detail per cell from the viewpoint (paper Fig. 1;
// `trample::field::lod::classify_cells`): one thread per cell, first in a
// sub-step. Counts the cells per level and the cells that changed.

@group(0) @binding(0) var<uniform> params: StepParams;
@group(0) @binding(1) var<storage, read_write> state: State;
@group(0) @binding(2) var<storage, read_write> cell_state: array<u32>;
@group(0) @binding(3) var<storage, read> cell_rest: array<vec4<f32>>;
@group(0) @binding(4) var<uniform> chunk: Chunk;

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
    cell_state[c] = (s & (BENT | AT_REST)) | (from_level << 2u) | new_level;
}
