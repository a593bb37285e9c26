// Transitions between levels of detail, per cell (paper Eq. 9–13, §6.3;
// `deform::transition` as `step::deform::apply_transitions` applies it): a
// cell leaving geometry takes its blades' mean offset as its billboard's
// (Eq. 9–12); one coming back gets on its blades' last segment what its
// billboard shows and they do not (Eq. 13, Eq. 5) — the paper's mode only:
// with `track_everywhere` the blades hold the track already. One thread per
// cell; it owns its blades.
//
// Eq. 13 runs in a dispatch of its own over the cells coming back
// (`transitions` lists them in `back`, `back_args` sizes the dispatch,
// `transitions_back` bends their blades): the software drivers (llvmpipe,
// lavapipe) run every branch of a kernel for every group of lanes, taken
// or not, so Eq. 13's bending and its ground guard, inlined into the pass
// over every cell, cost that pass ~90 ms a step on llvmpipe over the
// default scene's 262,144 cells, whichever cells came back (BENCHMARKS.md,
// "Session 55"). The same results: no cell's Eq. 12 reads or writes what
// Eq. 13 reads or writes (the blades and slope of a cell coming back).

@group(0) @binding(0) var<uniform> params: StepParams;
@group(0) @binding(1) var<storage, read_write> cell_state: array<u32>;
@group(0) @binding(2) var<storage, read> cell_rest: array<vec4<f32>>;
@group(0) @binding(3) var<storage, read_write> slope: array<vec4<f32>>;
// The chunk's vertices; vertex 0's w holds the blade's segment length.
@group(0) @binding(4) var<storage, read_write> pos: array<vec4<f32>>;
@group(0) @binding(5) var<storage, read> rest: array<vec4<f32>>;
@group(0) @binding(6) var<storage, read_write> displaced: array<u32>;
@group(0) @binding(7) var<uniform> chunk: Chunk;
@group(0) @binding(8) var<storage, read> ground: array<f32>;
// The cells coming back to geometry (Eq. 13): [0] their count (set to 0
// before `transitions`), then their indices.
@group(0) @binding(9) var<storage, read_write> back: array<atomic<u32>>;
// `transitions_back`'s indirect dispatch (`back_args`); an unused buffer in
// the bind group of `transitions_back` itself.
@group(0) @binding(10) var<storage, read_write> back_dispatch: array<u32>;

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

// Eq. 9–11: off_g, the mean offset of cell c's blades. Read only by the
// transitions that use it: a cell passing between billboard and texture
// (most of the changes when the camera jumps) reads no blade.
fn cell_offset(c: u32, bpc: u32) -> vec3<f32> {
    var sum = vec3<f32>(0.0);
    var k = 0u;
    for (var b = c * bpc; b < (c + 1u) * bpc; b++) {
        // Blades a grass map left out (`seg_len` 0) do not count.
        if pos[vertex_at(0u, b)].w > 0.0 {
            sum += blade_offset(b);
            k += 1u;
        }
    }
    if k == 0u {
        return vec3<f32>(0.0);
    }
    return sum / f32(k);
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
    if from_level == GEOMETRY {
        // Eq. 12: the billboard takes its blades' offset.
        let origin = cell_rest[2u * c + 1u].xyz;
        let sl = origin + cell_offset(c, params.cells.y);
        slope[c] = vec4<f32>(sl, 0.0);
        if any(sl != origin) {
            cell_state[c] = s | BENT;
        }
        return;
    }
    if level(s) != GEOMETRY || params.cells.w != 0u {
        return;
    }
    // Eq. 13, in `transitions_back`.
    let slot = atomicAdd(&back[0], 1u);
    atomicStore(&back[1u + slot], c);
}

// One thread: the workgroups of `transitions_back` over the listed cells
// (at most as many in x as the chunk's cell dispatch).
@compute @workgroup_size(1)
fn back_args() {
    let d = list_dispatch(atomicLoad(&back[0]), chunk.groups.y);
    back_dispatch[0] = d.x;
    back_dispatch[1] = d.y;
    back_dispatch[2] = d.z;
}

// Eq. 13 on each cell `transitions` listed: what the billboard shows and
// the blades do not acts on their last segment through Eq. 5
// (`transition::bend_last_segment`).
@compute @workgroup_size(64)
fn transitions_back(@builtin(global_invocation_id) gid: vec3<u32>, @builtin(num_workgroups) groups: vec3<u32>) {
    let i = list_thread(gid, groups);
    if i >= atomicLoad(&back[0]) {
        return;
    }
    let c = atomicLoad(&back[1u + i]);
    let bpc = params.cells.y;
    let n = min(params.counts.y, MAX_VERTS - 1u);
    let origin = cell_rest[2u * c + 1u].xyz;
    let missing = (slope[c].xyz - origin) - cell_offset(c, bpc);
    if dot3(missing, missing) < 1e-12 {
        return;
    }
    for (var b = c * bpc; b < (c + 1u) * bpc; b++) {
        if pos[vertex_at(0u, b)].w > 0.0 {
            bend_last_segment(b, n, missing);
        }
    }
}

// Eq. 13 on blade b: `missing` on its last segment through Eq. 5. A
// function of its own: its vertex array is zero-initialised where it is
// declared (naga declares a function's variables at its entry), so only
// the blades of cells coming back to geometry pay for it, not every
// cell's thread.
fn bend_last_segment(b: u32, n: u32, missing: vec3<f32>) {
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
        return;
    }
    let perpendicular = v1 - ab * (dot(v1, ab) / ab_len2);
    if dot(perpendicular, perpendicular) <= 1e-12 * dot(v1, v1) {
        return;
    }
    v[n] += perpendicular;
    preserve_from(&v, n, n, pos[vertex_at(0u, b)].w);
    pos[vertex_at(n, b)] = vec4<f32>(v[n], 0.0);
}
