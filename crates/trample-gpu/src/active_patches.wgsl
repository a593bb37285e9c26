// The active patches (ours; `active_patches.rs`): the passes that went over
// every blade of the field each sub-step — clearing the forces and
// contacts, `seed`, `bend`, `recover` — go over the patches where something
// happens instead, so that their cost follows the objects and their tracks,
// not the field (issue 16: 16.8 M blades, 128 objects).
//
// Two marks a patch (`broad_params.wgsl`'s `ACTIVE_*` region of the broad
// phase's lists): dirty — a blade of the patch may hold per-blade state of
// the last sub-step (force, contact, generation, candidate bit): the patches
// `seed` ran over and those propagation listed a candidate in; kept — a
// blade of the patch may be displaced. Every other patch holds the state of
// no contact (forces and contacts zero, no generation, no candidate bit)
// and no displaced blade, so the passes skip it with the same results.
//
// Per sub-step: `plan_seed` (after the broad phase) lists the dirty patches
// the broad phase did not list for `tidy`, and the patches near the listed
// ones for `seed`, which become dirty; `plan_main` or `plan_far` (after
// propagation) lists the dirty patches for `bend` and the dirty and kept
// ones for `recover`; `list_args` writes each list's indirect dispatch.

// `BroadParams` and the region's layout: broad_params.wgsl, prepended.

@group(0) @binding(0) var<uniform> broad: BroadParams;
@group(0) @binding(1) var<storage, read_write> lists: array<atomic<u32>>;
// The broad phase's per-chunk narrow-phase dispatches, then one per list in
// the order of the counts (`list_args`).
@group(0) @binding(2) var<storage, read_write> args: array<u32>;

fn patch_of(gid: vec3<u32>, groups: vec3<u32>) -> u32 {
    return gid.x + gid.y * groups.x * 64u;
}

// Whether the broad phase listed patch p this sub-step.
fn listed(p: u32) -> bool {
    return atomicLoad(&lists[broad.counts.x + broad.counts.z + p]) != 0u;
}

// Whether the broad phase listed patch p or one of the four beside it: only
// there can a blade or one of its 4-neighbours (Definition 6; across a
// patch border the neighbour lies in the patch beside) have been touched.
fn near_listed(p: u32) -> bool {
    let patches = broad.counts.x;
    let row = max(broad.counts.w, 1u);
    let x = p % row;
    var near = listed(p);
    if x > 0u {
        near = near || listed(p - 1u);
    }
    if x + 1u < row && p + 1u < patches {
        near = near || listed(p + 1u);
    }
    if p >= row {
        near = near || listed(p - row);
    }
    if p + row < patches {
        near = near || listed(p + row);
    }
    return near;
}

fn append(list: u32, c: u32, p: u32) {
    let slot = atomicAdd(&lists[active_count(list, c)], 1u);
    atomicStore(&lists[active_slot(list, c, slot)], p);
}

// After the broad phase (its marks), one thread a patch: a dirty patch the
// broad phase did not list goes to the tidy list (the narrow phase writes
// every blade of a listed patch, no other); a patch near a listed one goes
// to the seed list and is dirty (the narrow phase and `seed` write its
// blades); any other is clean once tidied.
@compute @workgroup_size(64)
fn plan_seed(@builtin(global_invocation_id) gid: vec3<u32>, @builtin(num_workgroups) groups: vec3<u32>) {
    let p = patch_of(gid, groups);
    if p >= broad.counts.x {
        return;
    }
    let near = near_listed(p);
    let was = atomicExchange(&lists[active_word(ACTIVE_DIRTY, p)], select(0u, 1u, near));
    if was != 0u && !listed(p) {
        append(ACTIVE_TIDY, 0u, p);
    }
    if near {
        append(ACTIVE_SEED, 0u, p);
    }
}

// After propagation (which marks the patches it listed a candidate in
// dirty), one thread a patch: the dirty ones to bend's list, the dirty and
// kept ones to recover's (of the patch's chunk). `recovering`: recovery
// runs this sub-step and marks the patches it leaves a displaced blade in
// kept again, so the mark is cleared here; otherwise a dirty patch is kept
// (bend or the contact may displace blades there) until recovery runs.
fn plan_lists(p: u32, recovering: bool) {
    let dirty = atomicLoad(&lists[active_word(ACTIVE_DIRTY, p)]) != 0u;
    let kept = atomicLoad(&lists[active_word(ACTIVE_KEEP, p)]) != 0u;
    let c = p / max(broad.counts.y, 1u);
    if dirty {
        append(ACTIVE_BEND, c, p);
    }
    if dirty || kept {
        append(ACTIVE_RECOVER, c, p);
        atomicStore(&lists[active_word(ACTIVE_KEEP, p)], select(1u, 0u, recovering));
    }
}

@compute @workgroup_size(64)
fn plan_main(@builtin(global_invocation_id) gid: vec3<u32>, @builtin(num_workgroups) groups: vec3<u32>) {
    let p = patch_of(gid, groups);
    if p < broad.counts.x {
        plan_lists(p, true);
    }
}

@compute @workgroup_size(64)
fn plan_far(@builtin(global_invocation_id) gid: vec3<u32>, @builtin(num_workgroups) groups: vec3<u32>) {
    let p = patch_of(gid, groups);
    if p < broad.counts.x {
        plan_lists(p, false);
    }
}

// One thread a list (tidy, seed, then bend's and recover's per chunk, the
// order of the counts): its patches × blades a patch as a grid of
// workgroups of 64 (x at most the device's limit), after the broad phase's
// per-chunk dispatches in `args`.
@compute @workgroup_size(64)
fn list_args(@builtin(global_invocation_id) gid: vec3<u32>) {
    let i = gid.x;
    if i >= 2u + 2u * broad.counts.z {
        return;
    }
    let threads = atomicLoad(&lists[active_word(ACTIVE_COUNTS, i)]) * broad.dispatch.x;
    let groups = (threads + 63u) / 64u;
    let max_x = max(broad.dispatch.y, 1u);
    let at = 3u * (broad.counts.z + i);
    args[at] = min(groups, max_x);
    args[at + 1u] = (groups + max_x - 1u) / max_x;
    args[at + 2u] = 1u;
}
