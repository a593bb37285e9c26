// Shared by the stages that read or write blade vertices (narrow phase,
// bend, recovery, cells; prepended to each, not a stage of its own): the
// chunk of patches a dispatch runs over (`chunk.rs`). Blade and cell
// indices stay global (forces, generations, classes, cell states are
// whole-field arrays); only `pos` and `rest` are the chunk's own, in the
// CPU's vertex-major layout over the chunk's blades:
// `pos[k * blades + (b - first_blade)]` is vertex k of global blade b.
// Each stage declares `var<uniform> chunk: Chunk` at a binding of its own.

// Layout-compatible with `GpuChunkParams` in chunk.rs.
struct Chunk {
    // first blade, blades, first cell, cells
    range: vec4<u32>,
    // workgroups in x of the blade dispatch, of the cell dispatch; entry of
    // the chunk's count in the broad phase's lists; blades per patch
    groups: vec4<u32>,
}

const NOT_IN_CHUNK: u32 = 0xffffffffu;

// The global blade of this thread in a dispatch over the chunk's blades,
// or NOT_IN_CHUNK past its end.
fn chunk_blade(gid: vec3<u32>) -> u32 {
    let l = gid.x + gid.y * chunk.groups.x * 64u;
    if l >= chunk.range.y {
        return NOT_IN_CHUNK;
    }
    return chunk.range.x + l;
}

// The global cell of this thread in a dispatch over the chunk's cells, or
// NOT_IN_CHUNK past its end.
fn chunk_cell(gid: vec3<u32>) -> u32 {
    let l = gid.x + gid.y * chunk.groups.y * 64u;
    if l >= chunk.range.w {
        return NOT_IN_CHUNK;
    }
    return chunk.range.z + l;
}

// Index of vertex k of global blade b (of this chunk) in `pos` / `rest`.
fn vertex_at(k: u32, b: u32) -> u32 {
    return k * chunk.range.y + (b - chunk.range.x);
}

// Where a thread of a dispatch over the listed patches of the chunk
// (indirect, `dispatch_args`: one thread per blade of each patch the broad
// phase listed) works: its slot in the chunk's list of patches, the entry
// of that slot in the broad phase's lists, and its blade within the patch
// (`per_patch` blades a patch). The stage checks the slot against the
// list's count, then reads the patch from `lists[entry]`.
struct ListedThread {
    slot: u32,
    entry: u32,
    lane: u32,
    per_patch: u32,
}

fn listed_thread(gid: vec3<u32>, groups: vec3<u32>) -> ListedThread {
    let per_patch = max(chunk.groups.w, 1u);
    let t = list_thread(gid, groups);
    let slot = t / per_patch;
    return ListedThread(slot, chunk.range.x / per_patch + slot, t % per_patch, per_patch);
}

// The stages that list what they will work on, then work on the list in a
// dispatch of its own (transitions, narrow phase, contact: the software
// drivers run every branch of a kernel, taken or not, so rare heavy work
// over a whole pass costs it everywhere; BENCHMARKS.md, "Session 55").

// This thread's index in a dispatch of workgroups of 64 (x + y · x_groups
// · 64, the layout of `list_dispatch`).
fn list_thread(gid: vec3<u32>, groups: vec3<u32>) -> u32 {
    return gid.x + gid.y * groups.x * 64u;
}

// The workgroups (x, y, 1) of a dispatch over `count` threads, at most
// `max_x` in x.
fn list_dispatch(count: u32, max_x: u32) -> vec3<u32> {
    let groups = (count + 63u) / 64u;
    let x = max(max_x, 1u);
    return vec3<u32>(min(groups, x), max((groups + x - 1u) / x, 1u), 1u);
}
