// The broad phase's uniform (broad_phase.wgsl), also read by the stages
// that run over the active patches (active_patches.wgsl, propagation.wgsl,
// active_list.wgsl, recovery.wgsl, follow.wgsl): prepended to each of their
// sources, each of which binds the broad phase's lists as
// `lists: array<atomic<u32>>`.
// Layout-compatible with `GpuBroadParams` in broad_phase.rs.
struct BroadParams {
    // patches, patches per chunk (all but the last), chunks, patches along x
    counts: vec4<u32>,
    // blades per patch, max workgroups per dimension, mask words per patch,
    // first word of the active patches' region of the lists (`ACTIVE_*`)
    dispatch: vec4<u32>,
}

// The active patches' region of the broad phase's lists (ours;
// `active_patches.rs`), from word `broad.dispatch.w`, in blocks of one word
// a patch (P = patches):
// - `ACTIVE_DIRTY`: 1 where a blade of the patch may hold this sub-step's
//   per-blade state (a force, a contact, a generation, a candidate bit);
// - `ACTIVE_KEEP`: 1 where a blade of the patch may be displaced;
// - `ACTIVE_TIDY`: the patches dirty from the last sub-step that no object
//   is near now (their state is put back to none), one list;
// - `ACTIVE_SEED`: the patches the broad phase listed and the four beside
//   each (where `seed` finds generation 0 and its candidates), one list;
// - `ACTIVE_BEND`: the dirty patches, a list per chunk (chunk c's from
//   patch c · patches per chunk, as the broad phase's own lists);
// - `ACTIVE_RECOVER`: the dirty and kept patches, a list per chunk;
// - then the counts: tidy, seed, then bend's per chunk, recover's per chunk.
const ACTIVE_DIRTY: u32 = 0u;
const ACTIVE_KEEP: u32 = 1u;
const ACTIVE_TIDY: u32 = 2u;
const ACTIVE_SEED: u32 = 3u;
const ACTIVE_BEND: u32 = 4u;
const ACTIVE_RECOVER: u32 = 5u;
const ACTIVE_COUNTS: u32 = 6u;

// Word `i` of block `block` of the active patches' region.
fn active_word(block: u32, i: u32) -> u32 {
    return broad.dispatch.w + block * broad.counts.x + i;
}

// The word of a list's count: `ACTIVE_TIDY`, `ACTIVE_SEED`, or the bend or
// recover list of chunk `c`.
fn active_count(list: u32, c: u32) -> u32 {
    var at = list - ACTIVE_TIDY;
    if list == ACTIVE_RECOVER {
        at = 2u + broad.counts.z + c;
    } else if list == ACTIVE_BEND {
        at = 2u + c;
    }
    return active_word(ACTIVE_COUNTS, at);
}

// The word of slot `slot` of a list: the tidy or seed list, or the bend or
// recover list of chunk `c`.
fn active_slot(list: u32, c: u32, slot: u32) -> u32 {
    var first = 0u;
    if list == ACTIVE_BEND || list == ACTIVE_RECOVER {
        first = c * broad.counts.y;
    }
    return active_word(list, first + slot);
}

// Where a thread of a dispatch over a list of patches works (`per` blades a
// patch, one thread a blade, the grid of `active_patches.wgsl`'s
// `list_args`): (slot in the list, blade within its patch).
fn active_thread(gid: vec3<u32>, groups: vec3<u32>) -> vec2<u32> {
    let per = max(broad.dispatch.x, 1u);
    let t = gid.x + gid.y * groups.x * 64u;
    return vec2<u32>(t / per, t % per);
}

// The global blade of this thread in a dispatch over list `list` of the
// active patches (of chunk `c` for the bend and recover lists; 0 for the
// others), or 0xffffffff past the list's end.
fn active_blade(gid: vec3<u32>, groups: vec3<u32>, list: u32, c: u32) -> u32 {
    let at = active_thread(gid, groups);
    if at.x >= atomicLoad(&lists[active_count(list, c)]) {
        return 0xffffffffu;
    }
    return atomicLoad(&lists[active_slot(list, c, at.x)]) * broad.dispatch.x + at.y;
}
