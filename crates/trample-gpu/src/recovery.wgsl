// Recovery of displaced blades towards rest (ours, DESIGN §6; the paper's
// future work): `trample::step::recover` / `recovery::recover_blade`. Each
// displaced vertex moves the fraction 1 − exp(−h'/τ) of the way back
// (more within 1 cm of rest: `tail_fraction`, the same speed), τ =
// recovery_s · (1 + trail · flatness) with the settings of the blade's
// track owner, h' = h · (1 − min(1, contact weight)): a blade an object
// holds does not recover. With far patches in turns (`params.b.w` = 2,
// `trample::step::recovery_turns`), h' is also multiplied by the blade's
// patch's entry of `turns` (0: it waits for its turn, counted as
// displaced and not looked at, as on the CPU). Then lengths are restored;
// a blade within 1e-4 m of rest snaps to it and leaves the displaced set.
// With recovery off for every owner (all recovery_s = ∞) the pass only
// counts the displaced blades.
//
// Slow blades in strides (`params.far.z`, the bits of `[sim]`
// `recovery_stride_m`; `trample::step::recover`): a blade recovers only
// once it owes the time its clock waits for (`clock[b]`: owed, wait), and
// then over all of it; the wait is `trample::recovery::stride_wait` of how
// far its last recovery moved it. The flag tells who moved a blade last:
// 1 (set by the bend, the contact response and the transitions) — it
// recovers now, its clock dropped (`trample::step::stages::mark_displaced`);
// 2 — its recovery, so its clock holds.

@group(0) @binding(0) var<uniform> params: StepParams;
@group(0) @binding(1) var<storage, read_write> state: State;
// The chunk's vertices; vertex 0's w holds the blade's segment length.
@group(0) @binding(2) var<storage, read_write> pos: array<vec4<f32>>;
@group(0) @binding(3) var<storage, read> rest: array<vec4<f32>>;
@group(0) @binding(4) var<storage, read_write> displaced: array<u32>;
@group(0) @binding(5) var<uniform> chunk: Chunk;
@group(0) @binding(6) var<storage, read> ground: array<f32>;
// w: the blade's contact weight this sub-step.
@group(0) @binding(7) var<storage, read> force: array<vec4<f32>>;
// Bits 8–15: the blade's track owner.
@group(0) @binding(8) var<storage, read> blade_class: array<u32>;
// Per track owner (0: `[sim]`, i: body i − 1): recovery_s (0 for ∞), trail.
@group(0) @binding(9) var<uniform> owners: array<vec4<f32>, 256>;
// The broad phase's uniform and lists: the active patches' kept marks
// (`active_patches.wgsl`; `BroadParams` and the layout: broad_params.wgsl,
// prepended), for `recover_listed`.
@group(0) @binding(10) var<uniform> broad: BroadParams;
@group(0) @binding(11) var<storage, read_write> lists: array<atomic<u32>>;
// Per patch: this step's recovery time as a multiple of h
// (`Simulation::recovery_scale`), read when `params.b.w` is 2.
@group(0) @binding(12) var<storage, read> turns: array<f32>;
// Per blade, with strides: the recovery time owed and the wait (s).
@group(0) @binding(13) var<storage, read_write> clock: array<vec2<f32>>;
// The blades to recover (`active_list.wgsl`'s `list_displaced`): [0] their
// count.
@group(0) @binding(14) var<storage, read> listed: array<u32>;

// `trample::recovery::RECOVERY_WAIT_MAX_S`.
const RECOVERY_WAIT_MAX_S: f32 = 0.25;

// `trample::recovery::stride_wait`.
fn stride_wait(stride: f32, moved: f32, recovered: f32) -> f32 {
    if !(stride > 0.0 && recovered > 0.0) {
        return 0.0;
    }
    if !(moved > 0.0) {
        return RECOVERY_WAIT_MAX_S;
    }
    return min(stride * recovered / moved, RECOVERY_WAIT_MAX_S);
}

fn recovery_stride() -> f32 {
    return bitcast<f32>(params.far.z);
}

@compute @workgroup_size(64)
fn recover(@builtin(global_invocation_id) gid: vec3<u32>) {
    let b = chunk_blade(gid);
    if b != NOT_IN_CHUNK {
        recover_or_count(b);
    }
}

// `recover` over the blades `list_displaced` listed (`active_list.wgsl`):
// the displaced blades of the chunk's active recover list (the patches
// dirty this sub-step and those kept, where a blade may be displaced;
// every other blade is at rest). A patch where a blade is left displaced
// is kept for the next recovery.
@compute @workgroup_size(64)
fn recover_listed(@builtin(global_invocation_id) gid: vec3<u32>, @builtin(num_workgroups) groups: vec3<u32>) {
    let i = list_thread(gid, groups);
    if i >= listed[0] {
        return;
    }
    let b = listed[1u + i];
    recover_or_count(b);
    if displaced[b] != 0u {
        atomicStore(&lists[active_word(ACTIVE_KEEP, b / max(broad.dispatch.x, 1u))], 1u);
    }
}

// The sub-step's recovery time for blade b: h, times its patch's turn
// when far patches take turns (`trample::step::recover`).
fn recovery_h(b: u32) -> f32 {
    if params.b.w == 2.0 {
        return params.a.x * turns[b / max(chunk.groups.w, 1u)];
    }
    return params.a.x;
}

fn recover_or_count(b: u32) {
    if displaced[b] == 0u {
        return;
    }
    // Recovery off, or a far patch waiting for its turn: the blade stays
    // displaced, not looked at (the CPU's `recover` skips it too).
    if params.b.w == 0.0 || (params.b.w == 2.0 && recovery_h(b) == 0.0) {
        atomicAdd(&state.displaced, 1u);
        return;
    }
    // Its recovery time: h (times its patch's turn) times how free it is,
    // plus in strides what it owes; not due yet, it owes all of it.
    var t = recovery_h(b) * (1.0 - min(force[b].w, 1.0));
    if recovery_stride() > 0.0 && displaced[b] == 2u {
        t = clock[b].x + t;
        if !(t >= clock[b].y) {
            clock[b].x = t;
            atomicAdd(&state.displaced, 1u);
            return;
        }
    }
    recover_blade(b, t);
}

// After blade b's recovery over t seconds moved it `moved` metres: in
// strides, its clock starts again and its flag says its recovery moved it.
fn restart_clock(b: u32, moved: f32, t: f32) {
    let stride = recovery_stride();
    if stride > 0.0 {
        clock[b] = vec2<f32>(0.0, stride_wait(stride, moved, t));
        displaced[b] = 2u;
    }
}

// The recovery of displaced blade b. A function of its own: the blade's
// vertex arrays are zero-initialised where they are declared (WGSL), and
// declared here they cost only the displaced blades, not every thread of
// the field (naga declares a function's variables at its entry).
fn recover_blade(b: u32, t: f32) {
    let n = min(params.counts.y, MAX_VERTS - 1u);
    var v: array<vec3<f32>, MAX_VERTS>;
    var r: array<vec3<f32>, MAX_VERTS>;
    var same = true;
    var deviation2 = 0.0;
    for (var k = 0u; k <= n; k++) {
        v[k] = pos[vertex_at(k, b)].xyz;
        r[k] = rest[vertex_at(k, b)].xyz;
        same = same && all(v[k] == r[k]);
        let d = v[k] - r[k];
        deviation2 = max(deviation2, dot(d, d));
    }
    if same {
        displaced[b] = 0u;
        return;
    }
    let owner = owners[min((blade_class[b] >> 8u) & 0xffu, 255u)];
    let flat = flatness(v[n].y - v[0].y, r[n].y - r[0].y);
    var q = 0.0;
    if owner.x > 0.0 {
        q = tail_fraction(recovered_fraction(t, time_constant(owner.x, owner.y, flat)), sqrt(deviation2));
    }
    if q == 0.0 {
        restart_clock(b, 0.0, t);
        atomicAdd(&state.displaced, 1u);
        return;
    }
    for (var k = 1u; k <= n; k++) {
        v[k] += (r[k] - v[k]) * q;
    }
    preserve_lengths(&v, n, pos[vertex_at(0u, b)].w);
    var at_rest = true;
    for (var k = 0u; k <= n; k++) {
        let d = v[k] - r[k];
        at_rest = at_rest && dot(d, d) < REST_EPSILON * REST_EPSILON;
    }
    var moved2 = 0.0;
    for (var k = 1u; k <= n; k++) {
        let out = select(v[k], r[k], at_rest);
        let d = out - pos[vertex_at(k, b)].xyz;
        moved2 = max(moved2, dot(d, d));
        pos[vertex_at(k, b)] = vec4<f32>(out, 0.0);
    }
    if at_rest {
        displaced[b] = 0u;
    } else {
        restart_clock(b, sqrt(moved2), t);
        atomicAdd(&state.displaced, 1u);
    }
}
