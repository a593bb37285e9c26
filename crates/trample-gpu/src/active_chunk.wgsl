// Shared by the stages that run over a chunk's active patches (the lists of
// the bend's and the recovery's blades, active_list.wgsl; follow;
// prepended after chunk.wgsl and broad_params.wgsl, not a stage of its
// own).

// Where a thread of a dispatch over the chunk's `list` of active patches
// (`ACTIVE_BEND` or `ACTIVE_RECOVER`; one thread a blade of each patch)
// works: (its patch, its blade within the patch), or NOT_IN_CHUNK as the
// patch past the list's end.
fn active_chunk_thread(gid: vec3<u32>, groups: vec3<u32>, list: u32) -> vec2<u32> {
    let c = chunk.range.x / max(broad.dispatch.x, 1u) / max(broad.counts.y, 1u);
    let at = active_thread(gid, groups);
    if at.x >= atomicLoad(&lists[active_count(list, c)]) {
        return vec2<u32>(NOT_IN_CHUNK, 0u);
    }
    return vec2<u32>(atomicLoad(&lists[active_slot(list, c, at.x)]), at.y);
}

// The global blade of this thread in a dispatch over the chunk's `list`,
// or NOT_IN_CHUNK past its end.
fn active_chunk_blade(gid: vec3<u32>, groups: vec3<u32>, list: u32) -> u32 {
    let at = active_chunk_thread(gid, groups, list);
    if at.x == NOT_IN_CHUNK {
        return NOT_IN_CHUNK;
    }
    return at.x * broad.dispatch.x + at.y;
}
