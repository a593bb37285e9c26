// Track everywhere (ours, DESIGN §2): every cell's billboard takes its slope
// from its blades (Eq. 9–12) and its flatness from their tips
// (`transition::cell_offset_and_flatness`, as `step::deform::
// cells_from_blades` keeps them), at the end of a sub-step. The CPU updates
// only the cells whose blades moved; a cell whose blades did not keeps
// exactly these values. Here only the cells of the active patches that may
// hold a displaced blade are visited (`follow`), and of those a cell whose
// blades are all at rest (not displaced: a blade leaves the displaced set
// only at its rest position, bit for bit) and were at rest when it was
// last computed (`AT_REST`) is not computed again: it would get the same
// values. Every other cell is computed, so the result is the same as
// computing every cell; where the field is at rest the pass reads nothing.

@group(0) @binding(0) var<uniform> params: StepParams;
@group(0) @binding(1) var<storage, read_write> cell_state: array<u32>;
@group(0) @binding(2) var<storage, read> cell_rest: array<vec4<f32>>;
@group(0) @binding(3) var<storage, read_write> slope: array<vec4<f32>>;
@group(0) @binding(4) var<storage, read_write> flatness_of: array<f32>;
@group(0) @binding(5) var<storage, read> pos: array<vec4<f32>>;
@group(0) @binding(6) var<storage, read> rest: array<vec4<f32>>;
@group(0) @binding(7) var<uniform> chunk: Chunk;
@group(0) @binding(8) var<storage, read> displaced: array<u32>;
// The broad phase's uniform and lists: the active patches' recover lists
// (`active_patches.wgsl`; `BroadParams` and the layout: broad_params.wgsl,
// prepended).
@group(0) @binding(9) var<uniform> broad: BroadParams;
@group(0) @binding(10) var<storage, read_write> lists: array<atomic<u32>>;

// Over the cells of the chunk's active recover list (the dispatch of that
// list: one thread a blade of each patch, the first cells-a-patch of them
// take a cell each). A cell outside it has all its blades at rest, and was
// computed when they came to rest (their patch was on the list then, as
// every patch is on the first sub-step's): it keeps its values.
@compute @workgroup_size(64)
fn follow(@builtin(global_invocation_id) gid: vec3<u32>, @builtin(num_workgroups) groups: vec3<u32>) {
    let at = active_chunk_thread(gid, groups, ACTIVE_RECOVER);
    let bpc = max(params.cells.y, 1u);
    let cells = broad.dispatch.x / bpc;
    if at.x == NOT_IN_CHUNK || at.y >= cells {
        return;
    }
    follow_cell(at.x * cells + at.y);
}

fn follow_cell(c: u32) {
    let bpc = params.cells.y;
    let s = cell_state[c];
    var at_rest = true;
    for (var b = c * bpc; b < (c + 1u) * bpc; b++) {
        at_rest = at_rest && displaced[b] == 0u;
    }
    if at_rest && (s & AT_REST) != 0u {
        return;
    }
    let n = min(params.counts.y, MAX_VERTS - 1u);
    // `transition::mean_offset` of `blade_offset`s and the mean flatness.
    var sum = vec3<f32>(0.0);
    var k = 0u;
    var flat = 0.0;
    var kf = 0u;
    for (var b = c * bpc; b < (c + 1u) * bpc; b++) {
        // Blades a grass map left out (`seg_len` 0) do not count.
        if !(pos[vertex_at(0u, b)].w > 0.0) {
            continue;
        }
        let root = pos[vertex_at(0u, b)].xyz;
        let rest_root = rest[vertex_at(0u, b)].xyz;
        let chord = pos[vertex_at(n, b)].xyz - root;
        let rest_chord = rest[vertex_at(n, b)].xyz - rest_root;
        let f = flatness(chord.y, rest_chord.y);
        flat += f;
        kf += 1u;
        let rest_height = sqrt(dot3(rest_chord, rest_chord));
        var off = vec3<f32>(0.0);
        if rest_height > 1e-12 && rest_height < 3.0e38 {
            off = (chord - rest_chord) / rest_height;
        }
        sum += off;
        k += 1u;
    }
    var mean = vec3<f32>(0.0);
    if k > 0u {
        mean = sum / f32(k);
    }
    let origin = cell_rest[2u * c + 1u].xyz;
    let sl = origin + mean;
    slope[c] = vec4<f32>(sl, 0.0);
    flatness_of[c] = select(0.0, flat / f32(kf), kf > 0u);
    let kept = s & ~(BENT | AT_REST);
    cell_state[c] = kept | select(BENT, 0u, all(sl == origin)) | select(0u, AT_REST, at_rest);
}
