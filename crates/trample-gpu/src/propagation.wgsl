// Force propagation from DBG to PBG (paper §5.2, Definitions 1–7, Eq. 4;
// DESIGN §5) as generation passes: `begin`, `seed` and `prime` once, then
// `gather` + `commit` + `advance` for generation 1 and `gather_commit` +
// `advance` for generation 2 as wide passes, then `finish`, one workgroup
// that loops over the generations left, up to the cap; each generation
// runs over its candidates (`frontier`: the blades next to the last
// generation, listed by `seed` and by each blade as it joins), not the
// field. Each blade of generation
// G+1 gathers, in the fixed order −x, +x, −z, +z, the contributions of the
// active generation-G neighbours that point at it: the gather of
// `trample::force::propagation::gather_force`, no float atomics. For
// generation 1, `gather` only reads the state and writes `next`, and
// `commit` applies it: a blade may be both a source and a candidate of
// generation 0 → 1 (an ancestor an object holds lightly, which takes part
// of a push), and its sources must see it as it was. From generation 1 on
// no blade is both, and one pass does both (`gather_commit`). A pass after
// the last generation returns at once (`stop`).

@group(0) @binding(0) var<uniform> params: StepParams;
@group(0) @binding(1) var<storage, read_write> state: State;
// xyz: force (m/s); w: the blade's contact weight this sub-step.
@group(0) @binding(2) var<storage, read_write> force: array<vec4<f32>>;
@group(0) @binding(3) var<storage, read_write> generation: array<u32>;
// Bits 0–1: `BladeClass`; bits 8–15: the track owner (1 + object index).
@group(0) @binding(4) var<storage, read_write> blade_class: array<u32>;
@group(0) @binding(5) var<storage, read> neighbours: array<vec4<u32>>;
// Workgroups of the next gather pass (x, y, z), read as indirect dispatch
// arguments: (0, 1, 1) once propagation has ended, so the passes left over
// cost a dispatch of nothing.
@group(0) @binding(6) var<storage, read_write> next_gather: array<u32, 3>;
// The narrow phase's per-blade contact: segment mask, firmest weight's
// bits, its owner (see narrow_phase.wgsl). Written by `tidy` alone.
@group(0) @binding(7) var<storage, read_write> touch: array<vec4<u32>>;
// Per blade, written by `gather`, applied by `commit`: the new force in
// xyz, and in w 1 + the owner of the first pusher (0: not reached). Zero
// between the two passes' runs (zero when made; `gather` writes only the
// blades it reaches, and `commit`, which always follows it over the same
// list, clears what it applies), so `seed` need not clear it.
@group(0) @binding(8) var<storage, read_write> next: array<vec4<u32>>;
// The candidates of a generation (the blades next to the last one), in
// two lists used in turn: words 0 and 1 the lists' lengths, then per blade
// two bits (bit p: listed in list p, so a blade is listed once), then the
// two lists of N blade indices each (`list_base`).
@group(0) @binding(9) var<storage, read_write> frontier: array<atomic<u32>>;

// The broad phase's uniform and lists (broad_phase.wgsl): the active
// patches (`active_patches.wgsl`), whose tidy and seed lists `tidy` and
// `seed_active` run over, and whose dirty marks `list_candidate` sets.
// Without a broad phase (the propagation recorded on its own) a zero
// uniform: `seed` runs over every blade and nothing is marked.
// (`BroadParams` and the region's layout: broad_params.wgsl, prepended.)
@group(0) @binding(10) var<uniform> broad: BroadParams;
@group(0) @binding(11) var<storage, read_write> lists: array<atomic<u32>>;

const NONE_U32: u32 = 0xffffffffu;
const CLASS_UNTOUCHED: u32 = 0u;
const CLASS_DIRECT: u32 = 1u;
const CLASS_PROPAGATED: u32 = 2u;
// `stages::DBG_WEIGHT`. The threshold's fade-in and the hold weight
// (`PropagationParams`) are in the step uniform: `params.lod.y`, `.z`.
const DBG_WEIGHT: f32 = 0.01;
// Words of `frontier` before the per-blade bits.
const FRONTIER_HEAD: u32 = 4u;

// First word of candidate list p (0 or 1) in `frontier`.
fn list_base(p: u32) -> u32 {
    return FRONTIER_HEAD + params.counts.x * (1u + p);
}

// Puts blade c in candidate list p unless it is there already; its patch
// is dirty (its candidate bit, and the force and generation it may take,
// are tidied once the broad phase no longer lists it).
fn list_candidate(c: u32, p: u32) {
    if c >= params.counts.x {
        return;
    }
    let bit = 1u << p;
    if (atomicOr(&frontier[FRONTIER_HEAD + c], bit) & bit) == 0u {
        let i = atomicAdd(&frontier[p], 1u);
        atomicStore(&frontier[list_base(p) + i], c);
        if broad.counts.x != 0u {
            atomicStore(&lists[active_word(ACTIVE_DIRTY, c / max(broad.dispatch.x, 1u))], 1u);
        }
    }
}

// The candidate of this thread in list p (a dispatch over the list's
// length, `set_args`), or NONE_U32 past its end.
fn listed(gid: vec3<u32>, p: u32) -> u32 {
    let i = blade_index(gid);
    if i >= atomicLoad(&frontier[p]) {
        return NONE_U32;
    }
    return atomicLoad(&frontier[list_base(p) + i]);
}

// The indirect arguments of a dispatch over `n` candidates (the layout of
// `blade_index`: at most `counts.w` workgroups in x).
fn set_args(n: u32) {
    let groups = (n + 63u) / 64u;
    next_gather[0] = min(groups, params.counts.w);
    next_gather[1] = max((groups + params.counts.w - 1u) / params.counts.w, 1u);
    next_gather[2] = 1u;
}

// Reset the per-sub-step state. The counts as the CPU's `StepTimings`
// keeps them (`trample::step::stages`): a main-pass sub-step counts anew,
// a far pass's adds to them (its generations: their largest); the
// transitions add up over the step.
@compute @workgroup_size(1)
fn begin() {
    state.g = 0u;
    state.stop = 0u;
    atomicStore(&state.any, 0u);
    if params.far.x != 0u {
        state.earlier_generations = max(state.earlier_generations, state.generations);
    } else {
        state.earlier_generations = 0u;
        atomicStore(&state.dbg, 0u);
        atomicStore(&state.pbg, 0u);
        atomicStore(&state.displaced, 0u);
        atomicStore(&state.contact, 0u);
    }
    state.generations = 0u;
    if params.far.y != 0u {
        atomicStore(&state.transitions, 0u);
    }
    // Not classified this sub-step (lod_settle.rs): the last counts stand.
    if params.lod.w == 0.0 {
        atomicStore(&state.lod[0], 0u);
        atomicStore(&state.lod[1], 0u);
        atomicStore(&state.lod[2], 0u);
    }
    atomicStore(&frontier[0], 0u);
    atomicStore(&frontier[1], 0u);
    next_gather[0] = 0u;
    next_gather[1] = 1u;
    next_gather[2] = 1u;
    if params.counts.z == 0u {
        state.stop = 1u;
    }
}

// A dirty patch the broad phase did not list (`active_patches.wgsl`): its blades' state
// of the last sub-step put back to none — no force, no contact, no
// generation, no candidate bit — as the narrow phase's clear and `seed`
// left every blade of the field before (the same state, written only where
// it was set).
@compute @workgroup_size(64)
fn tidy(@builtin(global_invocation_id) gid: vec3<u32>, @builtin(num_workgroups) groups: vec3<u32>) {
    let b = active_blade(gid, groups, ACTIVE_TIDY, 0u);
    if b >= params.counts.x {
        return;
    }
    force[b] = vec4<f32>(0.0);
    touch[b] = vec4<u32>(0u);
    generation[b] = NO_GENERATION;
    atomicStore(&frontier[FRONTIER_HEAD + b], 0u);
}

// Generation 0 = every blade an object touched (Definition 4, held by its
// contact weight); DBG in the paper's sense (class, count) from
// DBG_WEIGHT on; the track owner of the firmest contact. Every blade of the
// field (no broad phase bound).
@compute @workgroup_size(64)
fn seed(@builtin(global_invocation_id) gid: vec3<u32>) {
    let b = blade_index(gid);
    if b < params.counts.x {
        seed_blade(b);
    }
}

// `seed` over the active patches' seed list: the patches the broad phase
// listed and the four beside each. Only there can a blade or one of its
// neighbours have been touched; everywhere else `tidy` (or no contact
// since) left no generation and no candidate bit, `seed`'s answer there.
@compute @workgroup_size(64)
fn seed_active(@builtin(global_invocation_id) gid: vec3<u32>, @builtin(num_workgroups) groups: vec3<u32>) {
    let b = active_blade(gid, groups, ACTIVE_SEED, 0u);
    if b < params.counts.x {
        seed_blade(b);
    }
}

fn seed_blade(b: u32) {
    // The blade's listed bits start clear every sub-step (a list left over
    // at the cap, or by a caller recording fewer passes, is forgotten); no
    // other thread writes them in this pass.
    atomicStore(&frontier[FRONTIER_HEAD + b], 0u);
    // A candidate of generation 1 (list 0): a neighbour that points back
    // at it was touched (generation 0), as `reach` will look for.
    if params.counts.z != 0u {
        let nb = neighbours[b];
        var near_touched = false;
        for (var s = 0u; s < 4u; s++) {
            let j = nb[s];
            if j < params.counts.x && force[j].w > 0.0 && neighbours[j][s ^ 1u] == b {
                near_touched = true;
            }
        }
        if near_touched {
            let i = atomicAdd(&frontier[0], 1u);
            atomicStore(&frontier[list_base(0u) + i], b);
        }
    }
    // Touched: a contact weight above 0 (a segment mask bit set).
    if force[b].w > 0.0 {
        generation[b] = 0u;
        var kind = blade_class[b];
        if force[b].w >= DBG_WEIGHT {
            kind = (kind & ~3u) | CLASS_DIRECT;
            atomicAdd(&state.dbg, 1u);
        }
        // Read for the touched blades only: 16 bytes a blade of the field.
        let owner = touch[b].z;
        if owner != 0u {
            kind = (kind & ~0xff00u) | (owner << 8u);
        }
        blade_class[b] = kind;
    } else {
        generation[b] = NO_GENERATION;
    }
}

// Active status (Definition 2): finite energy |F| (Definition 1) ≥ L.
fn is_active(f: vec3<f32>) -> bool {
    let e = sqrt((f.x * f.x + f.y * f.y) + f.z * f.z);
    return e < 3.0e38 && e >= params.a.z;
}

// `propagation::fade_in`.
fn fade_in(f: vec3<f32>) -> f32 {
    var fade = 0.0;
    if params.lod.y > 0.0 {
        fade = params.lod.y * params.a.z;
    }
    if fade > 0.0 {
        let e = sqrt((f.x * f.x + f.y * f.y) + f.z * f.z);
        return clamp((e - params.a.z) / fade, 0.0, 1.0);
    }
    return 1.0;
}

// How firmly an object holds an ancestor (`propagate_forces`'s `held`).
fn held(b: u32) -> f32 {
    if params.lod.z > 0.0 {
        return clamp(force[b].w / params.lod.z, 0.0, 1.0);
    }
    return 1.0;
}

// What generation G+1 brings blade c (`gather_force`): in xyz the new
// force's bits, in w 1 + the owner of the first pusher (0: not reached).
fn reach(c: u32) -> vec4<u32> {
    let none = vec4<u32>(0u);
    let own = generation[c];
    var take = 1.0;
    if own == 0u {
        take = 1.0 - held(c);
        if !(take > 0.0) {
            return none;
        }
    } else if own != NO_GENERATION {
        return none;
    }
    let g = state.g;
    let nb = neighbours[c];
    var sum = force[c].xyz;
    var first = NONE_U32;
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
            sum += ef * (params.a.y * fade_in(f) * take);
            if first == NONE_U32 {
                first = j;
            }
        }
    }
    if first == NONE_U32 {
        return none;
    }
    let owner = (blade_class[first] >> 8u) & 0xffu;
    return vec4<u32>(bitcast<vec3<u32>>(sum), owner + 1u);
}

// After `seed`: the first gather pass runs over list 0.
@compute @workgroup_size(1)
fn prime() {
    if state.stop != 0u {
        return;
    }
    let n = atomicLoad(&frontier[0]);
    if n == 0u {
        state.stop = 1u;
        return;
    }
    set_args(n);
}

// Generation 0 → 1 over list 0: `reach` only reads the state and writes
// `next`, applied by `commit`, since a blade may be both a source of
// generation 0 and a candidate (an ancestor an object holds lightly).
@compute @workgroup_size(64)
fn gather(@builtin(global_invocation_id) gid: vec3<u32>) {
    let c = listed(gid, state.g % 2u);
    if c == NONE_U32 || state.stop != 0u {
        return;
    }
    let nx = reach(c);
    if nx.w != 0u {
        next[c] = nx;
    }
}

// Applies what `gather` found: the blade joins generation G+1.
@compute @workgroup_size(64)
fn commit(@builtin(global_invocation_id) gid: vec3<u32>) {
    let c = listed(gid, state.g % 2u);
    if c == NONE_U32 || state.stop != 0u {
        return;
    }
    let nx = next[c];
    if nx.w == 0u {
        return;
    }
    next[c] = vec4<u32>(0u);
    join(c, nx);
}

// Generations G ≥ 1: gather and commit in one pass. No blade is both a
// source (generation G ≥ 1) and a candidate (no generation, or 0), and a
// blade joining G+1 mid-pass reads as no source either way (0 or none
// before, G+1 after), so applying each reach at once gives what the two
// passes give — with one pass and one barrier less a generation.
@compute @workgroup_size(64)
fn gather_commit(@builtin(global_invocation_id) gid: vec3<u32>) {
    let p = state.g % 2u;
    let c = listed(gid, p);
    if c == NONE_U32 || state.stop != 0u {
        return;
    }
    gather_commit_one(c, p);
}

// Candidate c of list p, gathered and committed (`gather_commit`, and each
// turn of `finish`).
fn gather_commit_one(c: u32, p: u32) {
    // Out of list p (the next list but one uses its bit again); this pass
    // only adds to the other list.
    atomicAnd(&frontier[FRONTIER_HEAD + c], ~(1u << p));
    let nx = reach(c);
    if nx.w != 0u {
        join(c, nx);
    }
}

// Blade c joins generation G+1 with what `reach` found.
fn join(c: u32, nx: vec4<u32>) {
    force[c] = vec4<f32>(bitcast<vec3<f32>>(nx.xyz), force[c].w);
    generation[c] = state.g + 1u;
    var kind = blade_class[c];
    if (kind & 3u) == CLASS_UNTOUCHED {
        kind = kind | CLASS_PROPAGATED;
    }
    blade_class[c] = (kind & ~0xff00u) | ((nx.w - 1u) << 8u);
    atomicAdd(&state.pbg, 1u);
    atomicStore(&state.any, 1u);
    // Its neighbours are the next generation's candidates.
    let nb = neighbours[c];
    let p = (state.g + 1u) % 2u;
    for (var s = 0u; s < 4u; s++) {
        list_candidate(nb[s], p);
    }
}

// Ends generation G after its commit (termination status, Definition 3):
// whether another follows — a blade was reached and the cap is not met.
fn next_generation() -> bool {
    // The list just gone through is empty for the generation after next.
    atomicStore(&frontier[state.g % 2u], 0u);
    if atomicLoad(&state.any) == 0u {
        state.stop = 1u;
        return false;
    }
    state.generations += 1u;
    state.g += 1u;
    atomicStore(&state.any, 0u);
    if state.generations >= params.counts.z {
        state.stop = 1u;
        return false;
    }
    return true;
}

// After a wide commit pass: stop when no blade was reached or at the cap,
// else size the next wide pass.
@compute @workgroup_size(1)
fn advance() {
    if state.stop != 0u {
        return;
    }
    if next_generation() {
        set_args(atomicLoad(&frontier[state.g % 2u]));
    } else {
        next_gather[0] = 0u;
    }
}

// Threads of the `finish` workgroup.
const FINISH_THREADS: u32 = 256u;
// `state.stop` as the `finish` workgroup last read it (uniform).
var<workgroup> finish_stop: u32;

// The generations after the wide passes, in one workgroup: each turn of the
// loop is `gather_commit` over the candidate list (the workgroup's threads
// striding through it) and then `advance`, with a barrier between them in
// place of a dispatch. The generations that reach past the wide passes are
// the faint edges of the push, a short list each, and the passes an
// earlier end leaves over cost this one dispatch, not two a generation.
@compute @workgroup_size(256)
fn finish(@builtin(local_invocation_index) lid: u32) {
    loop {
        if lid == 0u {
            finish_stop = state.stop;
        }
        if workgroupUniformLoad(&finish_stop) != 0u {
            break;
        }
        let p = state.g % 2u;
        let n = atomicLoad(&frontier[p]);
        for (var i = lid; i < n; i += FINISH_THREADS) {
            gather_commit_one(atomicLoad(&frontier[list_base(p) + i]), p);
        }
        storageBarrier();
        if lid == 0u {
            _ = next_generation();
        }
        storageBarrier();
    }
}
