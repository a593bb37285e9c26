// The contact response (ours, DESIGN §5 "Contact"): after the bending of
// Eq. 5–7, every blade some object touched this sub-step is moved out of
// this object — `trample::deform::contact::resolve_contact` as the CPU's
// `step::deform::resolve_contacts` runs it: for all objects at once, one
// thread per touched blade of the patches the broad phase listed (per chunk
// of patches: `list_touched` lists them, `contact_listed` responds), each
// applying the objects it marked for the blade's patch in object order
// (the CPU's order), from the lowest segment touched. A vertex inside the object turns
// its segment towards the way out (`turn_towards`), a segment starting at
// a vertex pinned under the object is laid flat (`pinned`), the segments
// above follow with the ground guard (`preserve_from`, guard.wgsl).

@group(0) @binding(0) var<uniform> params: StepParams;
// The chunk's vertices; vertex 0's w holds the blade's segment length.
@group(0) @binding(1) var<storage, read_write> pos: array<vec4<f32>>;
// x: segment mask of the blade this sub-step (0: untouched); w set to 1
// when this pass moves the blade (counted here, once a sub-step).
@group(0) @binding(2) var<storage, read_write> touch: array<vec4<u32>>;
@group(0) @binding(3) var<storage, read_write> displaced: array<u32>;
@group(0) @binding(4) var<uniform> chunk: Chunk;
@group(0) @binding(5) var<storage, read> ground: array<f32>;
// The broad phase's lists and per-patch object masks (see narrow_phase.wgsl).
@group(0) @binding(6) var<storage, read> lists: array<u32>;
// The step's counters: the blades moved, and in a far pass those moved
// from rest (the main pass's recovery counts the displaced set itself).
@group(0) @binding(7) var<storage, read_write> state: State;
// The touched blades of the chunk's listed patches (`list_touched`): [0]
// their count (0 before `list_touched`), then the blades (the field's
// `near_blades`, which the narrow phase is done with).
@group(0) @binding(8) var<storage, read_write> touched_blades: array<atomic<u32>>;
// `contact_listed`'s indirect dispatch (`touched_args`); an unused buffer
// in `contact_listed`'s own bind group.
@group(0) @binding(9) var<storage, read_write> touched_dispatch: array<u32>;

// `deform::contact::CONTACT_ITERATIONS`, `LEAN_BIAS`, `PIN_HEIGHT`,
// `FLAT_LEAN`, `FLAT_OUT`, `FLAT_FLOOR`.
const CONTACT_ITERATIONS: u32 = 4u;
const LEAN_BIAS: f32 = 0.05;
const PIN_HEIGHT: f32 = 0.02;
const FLAT_LEAN: f32 = 0.1;
const FLAT_OUT: f32 = 2.0;
const FLAT_FLOOR: f32 = 0.25;
// `deform::contact::PIN_REACH`.
const PIN_REACH: f32 = 0.75;

// `deform::contact::pin_for_push`: how far towards flat a segment `pin`
// pinned at its start is turned when its end is pushed by `push` metres,
// `turn` = |flat − turned|: pin · min(push / (min(turn, PIN_REACH) ·
// seg_len), 1), 0 for a push not positive or NaN.
fn pin_for_push(pin: f32, push: f32, turn: f32, seg_len: f32) -> f32 {
    if !(push > 0.0) {
        return 0.0;
    }
    let span = min(turn, PIN_REACH) * seg_len;
    if !(span > push) {
        return pin;
    }
    return pin * (push / span);
}

// glam `Vec3A::try_normalize`, with a fallback.
fn normalize_or(v: vec3<f32>, fallback: vec3<f32>) -> vec3<f32> {
    let rcp = 1.0 / sqrt(dot3(v, v));
    if rcp < 3.0e38 && rcp > 0.0 {
        return v * rcp;
    }
    return fallback;
}

// `deform::contact::flat_direction`'s parts: the horizontal part of v
// divided by max(its length, floor).
fn flat_part(v: vec3<f32>, floor: f32) -> vec3<f32> {
    let h = v * vec3<f32>(1.0, 0.0, 1.0);
    return h / max(sqrt(dot3(h, h)), floor);
}

// `deform::contact::flat_direction`, `fallback` for its `None`.
fn flat_direction(seg_in: vec3<f32>, lean_in: vec3<f32>, out: vec3<f32>, seg_len: f32, fallback: vec3<f32>) -> vec3<f32> {
    let floor = max(FLAT_FLOOR * seg_len, 1.17549435e-38);
    let sum = flat_part(seg_in, floor) + flat_part(lean_in, floor) * FLAT_LEAN + flat_part(out, floor) * FLAT_OUT;
    return normalize_or(sum, fallback);
}

// `contact::turn_towards`.
fn turn_towards(dir: vec3<f32>, push: vec3<f32>, lean_in: vec3<f32>, len: f32) -> vec3<f32> {
    let d = normalize_or(dir, vec3<f32>(0.0, 1.0, 0.0));
    let delta = sqrt(dot3(push, push));
    if !(delta > 0.0 && len > 0.0 && delta < 3.0e38) {
        return d;
    }
    let lean_unit = normalize_or(lean_in, vec3<f32>(0.0));
    let lean = lean_unit - d * dot3(lean_unit, d);
    let bias = (LEAN_BIAS + max(-dot3(d, push) / delta, 0.0)) * delta;
    return normalize_or(d * len + push + lean * bias, d);
}

// `contact::pinned` in two halves around the walk (`contact_blade` asks
// `surface_and_side_near` at one call site for this and for the push): how
// pinned under the object a vertex at p (world) is. The first half: how
// near the ground p is (0: not pinned, no walk).
fn pin_ground(p: vec3<f32>) -> f32 {
    let guard = ground_at(p.x, p.z) + max(params.b.x, 0.0);
    return clamp(1.0 - (p.y - guard) / PIN_HEIGHT, 0.0, 1.0);
}

// Where `pinned` asks for the penetration (object frame): the point
// PIN_HEIGHT above p, with PIN_HEIGHT as the open-mesh depth.
fn pin_probe(p: vec3<f32>) -> vec3<f32> {
    return to_local(p + vec3<f32>(0.0, 1.0, 0.0) * PIN_HEIGHT);
}

// The second half: the answer from `pin_ground(p)` and
// `surface_and_side(pin_probe(p), PIN_HEIGHT, ∞)`.
fn pin_from(on_ground: f32, side: Side) -> f32 {
    if !(on_ground > 0.0) {
        return 0.0;
    }
    let pen = penetration_of(side);
    var under = 0.0;
    if pen.w >= 0.0 {
        under = min(pen.w / PIN_HEIGHT, 1.0);
    }
    return on_ground * under;
}

// Two dispatches a chunk (and `touched_args` between them): `list_touched`
// over every blade of the chunk's patches the broad phase listed keeps
// those some object touched this sub-step, `contact_listed` responds on
// them alone (the others it left as they were): the software drivers run
// every branch of a kernel whether a lane takes it or not, so the response
// cost every blade of a listed patch (BENCHMARKS.md, "Session 55").
@compute @workgroup_size(64)
fn list_touched(@builtin(global_invocation_id) gid: vec3<u32>, @builtin(num_workgroups) groups: vec3<u32>) {
    let at = listed_thread(gid, groups);
    if at.slot >= lists[chunk.groups.z] {
        return;
    }
    let b = lists[at.entry] * at.per_patch + at.lane;
    if touch[b].x != 0u {
        let slot = atomicAdd(&touched_blades[0], 1u);
        atomicStore(&touched_blades[1u + slot], b);
    }
}

// One thread: the workgroups of `contact_listed` over the touched blades.
@compute @workgroup_size(1)
fn touched_args() {
    let d = list_dispatch(atomicLoad(&touched_blades[0]), chunk.groups.x);
    touched_dispatch[0] = d.x;
    touched_dispatch[1] = d.y;
    touched_dispatch[2] = d.z;
}

// The blades `list_touched` kept, each against the objects the broad phase
// marked for its patch, in object order.
@compute @workgroup_size(64)
fn contact_listed(@builtin(global_invocation_id) gid: vec3<u32>, @builtin(num_workgroups) groups: vec3<u32>) {
    let i = list_thread(gid, groups);
    if i >= atomicLoad(&touched_blades[0]) {
        return;
    }
    let b = atomicLoad(&touched_blades[1u + i]);
    let p = b / max(chunk.groups.w, 1u);
    let words = objects[0].y;
    for (var w = 0u; w < words; w++) {
        var bits = lists[objects[0].z + p * words + w];
        while bits != 0u {
            load_object(32u * w + countTrailingZeros(bits), gid.z);
            bits &= bits - 1u;
            contact_blade(b);
        }
    }
}

// The loaded object's contact response on blade b (touched this sub-step).
fn contact_blade(b: u32) {
    let mask = touch[b].x;
    let n = min(field.y, MAX_SEGMENTS);
    let seg_len = pos[vertex_at(0u, b)].w;
    var v: array<vec3<f32>, MAX_VERTS>;
    for (var k = 0u; k <= n; k++) {
        v[k] = pos[vertex_at(k, b)].xyz;
    }
    if !(seg_len > 0.0 && seg_len < 3.0e38) || !all(abs(v[0]) < vec3<f32>(3.0e38)) {
        return;
    }
    // The segment length as the open-mesh depth (the CPU passes it too).
    let open_depth = seg_len;
    var first = max(countTrailingZeros(mask), 1u);
    var moved = false;
    // Per vertex, the triangle of its last closest point, tried first by a
    // later round (`push_out_hinted`: the same answers), and the last point
    // `pinned` was asked at and its answer (the CPU's `pins`).
    var hints: array<u32, MAX_VERTS>;
    var pin_at: array<vec3<u32>, MAX_VERTS>;
    var pin_was: array<f32, MAX_VERTS>;
    for (var k = 0u; k <= n; k++) {
        hints[k] = NONE;
        pin_was[k] = -1.0;
    }
    for (var iter = 0u; iter < CONTACT_ITERATIONS; iter++) {
        var lowest = NONE;
        // One pass a question to `surface_and_side_near`: vertex k's way
        // out, then, when k must move and the pin of its segment's start is
        // not known, that pin in a pass of its own (`out`, w = 1, holds the
        // way out meanwhile). One call site: shader compilers inline every
        // call, and each copy holds a whole closest-point walk
        // (BENCHMARKS.md, "Session 54").
        var k = first;
        var out = vec4<f32>(0.0);
        loop {
            if k > n {
                break;
            }
            let start = v[k - 1u];
            let at = bitcast<vec3<u32>>(start);
            let asks_pin = out.w != 0.0;
            var ask = false;
            var q = vec3<f32>(0.0);
            var depth = open_depth;
            var bound_sq = squared(3.0e38);
            var reach = PUSH_BLEND_M;
            var on_ground = 0.0;
            var hint = NONE;
            if asks_pin {
                on_ground = pin_ground(start);
                ask = on_ground > 0.0;
                if ask {
                    q = pin_probe(start);
                    depth = PIN_HEIGHT;
                    reach = -1.0;
                }
            } else {
                // A vertex with no triangle of its own yet tries the one
                // below it (a few centimetres away: the walk is bounded
                // near there instead of starting unbounded; the same
                // answers).
                hint = hints[k];
                if hint == NONE {
                    hint = hints[k - 1u];
                }
                q = to_local(v[k]);
                bound_sq = push_bound_sq(q, hint);
                ask = bound_sq >= 0.0;
            }
            var side = no_side();
            if ask {
                side = surface_and_side_near(q, depth, bound_sq, reach);
            }
            if asks_pin {
                pin_at[k - 1u] = at;
                pin_was[k - 1u] = pin_from(on_ground, side);
            } else {
                let pushed = push_from(q, side, hint);
                hints[k] = pushed.hint;
                out = pushed.to;
                if out.w == 0.0 {
                    k++;
                    continue;
                }
                if pin_was[k - 1u] < 0.0 || any(pin_at[k - 1u] != at) {
                    continue;
                }
            }
            let horizontal = vec3<f32>(1.0, 0.0, 1.0);
            let lean = normalize_or((v[k] - v[0]) * horizontal, vec3<f32>(0.0));
            let push = to_world(out.xyz) - v[k];
            let turned = turn_towards(v[k] - start, push, lean, seg_len);
            let flat = flat_direction(v[k] - start, v[k] - v[0], start - obj.position.xyz, seg_len, turned);
            let pin = pin_for_push(pin_was[k - 1u], length(push), length(flat - turned), seg_len);
            let dir = normalize_or(turned * (1.0 - pin) + flat * pin, turned);
            v[k] = start + dir * seg_len;
            preserve_from(&v, k, n, seg_len);
            if lowest == NONE {
                lowest = k;
            }
            out = vec4<f32>(0.0);
            k++;
        }
        if lowest == NONE {
            break;
        }
        moved = true;
        first = lowest;
    }
    if moved {
        for (var k = 1u; k <= n; k++) {
            pos[vertex_at(k, b)] = vec4<f32>(v[k], 0.0);
        }
        if params.far.x != 0u && displaced[b] == 0u {
            atomicAdd(&state.displaced, 1u);
        }
        displaced[b] = 1u;
        if touch[b].w == 0u {
            atomicAdd(&state.contact, 1u);
        }
        touch[b].w = 1u;
    }
}
