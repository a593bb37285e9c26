// The blades of a chunk's active patches that bend or recover this
// sub-step, listed before they are worked on (`active_list.rs`; the bend
// and recovery's first two dispatches): `list_bent` over the chunk's bend
// list keeps the blades with a generation (propagation reached them: the
// only ones `bend_blade` moves), `list_displaced` over its recover list
// those marked displaced (the only ones `recover_or_count` looks at), then
// `listed_args` writes the indirect arguments of the work over the list
// (`bend_listed`, `recover_listed`). The software drivers run every branch
// of a kernel whether a lane takes it or not (BENCHMARKS.md, "Session
// 55"): over every blade of an active patch, the bend's and the recovery's
// work cost the blades that have none; on a GPU the listed blades fill the
// warps. The order of the list does not matter: each blade's work reads
// and writes that blade alone (and counters summed by atomics).
// `chunk.wgsl`, `broad_params.wgsl` and `active_chunk.wgsl` prepended.

@group(0) @binding(0) var<uniform> broad: BroadParams;
@group(0) @binding(1) var<storage, read_write> lists: array<atomic<u32>>;
@group(0) @binding(2) var<uniform> chunk: Chunk;
// Per blade: its generation (`list_bent`) or its displaced flag
// (`list_displaced`).
@group(0) @binding(3) var<storage, read> flags: array<u32>;
// [0] the count (cleared before `list_*`), then the blades.
@group(0) @binding(4) var<storage, read_write> listed: array<atomic<u32>>;
// The indirect arguments of the work over `listed` (`listed_args`).
@group(0) @binding(5) var<storage, read_write> listed_dispatch: array<u32>;

// `blade.wgsl`'s (not prepended here: it reads the step uniform):
// propagation did not reach the blade.
const NO_GENERATION: u32 = 255u;

// Appends this thread's blade of the chunk's `list` of active patches when
// its flag is not `idle`.
fn list_unless(gid: vec3<u32>, groups: vec3<u32>, list: u32, idle: u32) {
    let b = active_chunk_blade(gid, groups, list);
    if b != NOT_IN_CHUNK && flags[b] != idle {
        let slot = atomicAdd(&listed[0], 1u);
        atomicStore(&listed[1u + slot], b);
    }
}

@compute @workgroup_size(64)
fn list_bent(@builtin(global_invocation_id) gid: vec3<u32>, @builtin(num_workgroups) groups: vec3<u32>) {
    list_unless(gid, groups, ACTIVE_BEND, NO_GENERATION);
}

@compute @workgroup_size(64)
fn list_displaced(@builtin(global_invocation_id) gid: vec3<u32>, @builtin(num_workgroups) groups: vec3<u32>) {
    list_unless(gid, groups, ACTIVE_RECOVER, 0u);
}

// One thread: the workgroups of the work over the listed blades.
@compute @workgroup_size(1)
fn listed_args() {
    let d = list_dispatch(atomicLoad(&listed[0]), chunk.groups.x);
    listed_dispatch[0] = d.x;
    listed_dispatch[1] = d.y;
    listed_dispatch[2] = d.z;
}
