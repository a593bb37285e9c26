// Shared by the stages that run over a chunk's active patches (bend,
// recovery; prepended after chunk.wgsl and broad_params.wgsl, not a stage
// of its own).

// The global blade of this thread in a dispatch over the chunk's `list` of
// active patches (`ACTIVE_BEND` or `ACTIVE_RECOVER`), or NOT_IN_CHUNK past
// its end.
fn active_chunk_blade(gid: vec3<u32>, groups: vec3<u32>, list: u32) -> u32 {
    let c = chunk.range.x / max(broad.dispatch.x, 1u) / max(broad.counts.y, 1u);
    return active_blade(gid, groups, list, c);
}
