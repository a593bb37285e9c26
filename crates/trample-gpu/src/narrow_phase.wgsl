// Narrow phase and DBG forces (paper §4.2, §5.1 Eq. 2; DESIGN §4.2, §5):
// one thread per blade. The blade's vertices are moved into the object's
// local frame once, each segment walks the OBB tree depth first down to the
// precision (root = depth 1) with a fixed-size stack, all levels in this one
// dispatch (no read-back between levels).
//
// Two walks, as on the CPU (`trample::collision::narrow_phase`):
// - `collide` (every blade of the chunk): the paper's yes/no hit flags,
//   `collide_segment`, for `trample collide` and the stage tests;
// - `collide_listed` (the blades of the patches the broad phase listed
//   that `list_blades` kept): the simulation's weighted contacts,
//   `contact_segment` (boxes grown by the contact shell, reach boxes for
//   pruning, weights from how deep a segment reaches) and the forces of
//   Eq. 2 as `trample::step::collide` sums them, with the track owner of
//   the firmest contact.
// Float op for float op as the CPU (glam's order), so the results agree
// bit for bit where the shader compiler does not contract a*b+c.
//
// In `collide_listed`, a blade first lists the final nodes its own box may
// meet (`list_near`, the CPU's `final_nodes_near`) and its segments test
// those alone instead of walking from the root (the CPU lists them per tile
// of 6 × 6 cells: a superset, in the same order, gives the same contacts).
//
// One dispatch (per chunk of patches) for all objects (issue 16 item 3):
// each thread loops over the objects that may touch its blade — every
// object in `collide`, those the broad phase marked for the blade's patch
// in `collide_listed` — in object order, and adds each one's force to its
// own blade's (no atomics), so the sum is taken in the CPU's order (object
// by object).

@group(0) @binding(0) var<storage, read> pos: array<vec4<f32>>;
// Bits 0–1: the cell's level of detail (see classify.wgsl).
@group(0) @binding(1) var<storage, read> cell_state: array<u32>;
// Σ over objects and segments of weight · press · EqF in xyz; Σ weights
// (Eq. 5's `num`, the contact weight) in w.
@group(0) @binding(2) var<storage, read_write> force: array<vec4<f32>>;
// Per blade: segment mask (bit k: segment k touched some object),
// bits of the firmest single-object weight so far, its owner id, and (set
// later by the contact pass) 1 when the contact response moved the blade.
@group(0) @binding(3) var<storage, read_write> touch: array<vec4<u32>>;
// The chunk of patches this dispatch runs over (`chunk.wgsl`): `pos` is its own.
@group(0) @binding(4) var<uniform> chunk: Chunk;
// The broad phase's patch lists (`broad_phase.wgsl`), read by
// `collide_listed`: the chunk's list starts at its first patch, its count
// is entry `chunk.groups.z`; the objects marked for patch p are the bits
// of the words from `objects[0].z + p · objects[0].y` (`listed_objects`).
@group(0) @binding(5) var<storage, read> lists: array<u32>;
// The blades of the listed patches that may touch an object (`list_blades`):
// [0] their count (0 before `list_blades`), then the blades.
@group(0) @binding(6) var<storage, read_write> near_blades: array<atomic<u32>>;
// `collide_listed`'s indirect dispatch (`near_args`); an unused buffer in
// `collide_listed`'s own bind group.
@group(0) @binding(7) var<storage, read_write> near_dispatch: array<u32>;

const LOD_GEOMETRY: u32 = 0u;
// `Walk::contact`: a sum of unit vectors shorter than this has cancelled.
const CANCELLED: f32 = 1e-3;
// `narrow_phase::RAMP_TRAVELS`, `RAMP_STEP_S`.
const RAMP_TRAVELS: f32 = 2.0;
const RAMP_STEP_S: f32 = 0.033333335;
// `stages::DBG_WEIGHT`.
const DBG_WEIGHT: f32 = 0.01;

struct Walk {
    sum: vec3<f32>,
    first: u32,
    first_dir: vec3<f32>,
    deepest_hit: u32,
}

// The walks' stack (`walk`, `contact_segment`, `list_near`; none calls
// another while its stack is in use) and the blade in the object's frame
// (`collide_blade`). Module-scope, not function-scope: WGSL zero-initialises
// a variable where it is declared, and naga declares a function's variables
// at its entry, so a function-scope stack cost 528 zeroed bytes a call
// (four calls a blade and object, most of them returning at the root box);
// these are zeroed once a thread.
var<private> walk_stack: array<vec2<u32>, STACK_SIZE>;
var<private> blade_local: array<vec3<f32>, 16>;

// `narrow_phase::walk` with shell 0: the paper's walk, depth first, left
// child first, fixed-size stack; a node is met when its box and its tilted
// boxes are (`hits_node`).
fn walk(p0: vec3<f32>, p1: vec3<f32>, final_depth: u32) -> Walk {
    let centre = (p0 + p1) * 0.5;
    let half = (p1 - p0) * 0.5;
    var out = Walk(vec3<f32>(0.0), NONE, vec3<f32>(0.0), 0u);
    walk_stack[0] = vec2<u32>(0u, 1u);
    var len = 1u;
    let count = tree.x;
    while len > 0u {
        len -= 1u;
        let i = walk_stack[len].x;
        let depth = walk_stack[len].y;
        if i >= count {
            continue;
        }
        let n = node_at(i);
        if !hits_node(centre, half, n, i) {
            continue;
        }
        out.deepest_hit = max(out.deepest_hit, depth);
        let l = n.children.x;
        let r = n.children.y;
        let leaf = l == NO_CHILD;
        if depth < final_depth && !leaf && l > i && r > i && len + 2u <= STACK_SIZE {
            walk_stack[len] = vec2<u32>(r, depth + 1u);
            walk_stack[len + 1u] = vec2<u32>(l, depth + 1u);
            len += 2u;
        } else {
            let dir = eqn_direction(i, p0, p1);
            if out.first == NONE {
                out.first = i;
                out.first_dir = dir;
            }
            out.sum += dir;
        }
    }
    return out;
}

// `FirstAndSum::contact`: (direction, point), object-local frame.
struct Contact {
    dir: vec3<f32>,
    point: vec3<f32>,
    weight: f32,
    // `SegmentContact::velocity`: the deforming mesh's own velocity there.
    velocity: vec3<f32>,
    // `SegmentContact::agree`: how much the final nodes' directions agree.
    agree: f32,
}

fn contact(w: Walk, p0: vec3<f32>, p1: vec3<f32>) -> Contact {
    var dir = w.first_dir;
    let len2 = dot3(w.sum, w.sum);
    if sqrt(len2) > CANCELLED {
        dir = w.sum * (1.0 / sqrt(len2));
    }
    let n = node_at(w.first);
    return Contact(dir, closest_point(p0, p1, n.center.xyz), 1.0, n.velocity.xyz, 1.0);
}

// `narrow_phase::collide_segment`: hit flag in `hit`, contact when hit.
struct SegmentHit {
    hit: bool,
    c: Contact,
}

fn collide_segment(p0: vec3<f32>, p1: vec3<f32>) -> SegmentHit {
    let miss = SegmentHit(false, Contact(vec3<f32>(0.0), vec3<f32>(0.0), 0.0, vec3<f32>(0.0), 0.0));
    if tree.x == 0u {
        return miss;
    }
    let centre = (p0 + p1) * 0.5;
    let half = (p1 - p0) * 0.5;
    if !hits_obb(centre, half, node_at(0u)) {
        return miss;
    }
    let w = walk(p0, p1, tree.z);
    if w.first != NONE {
        return SegmentHit(true, contact(w, p0, p1));
    }
    if w.deepest_hit == 0u || tree.y == 0u || !point_inside((p0 + p1) * 0.5) {
        return miss;
    }
    let deep = walk(p0, p1, w.deepest_hit);
    if deep.first == NONE {
        return miss;
    }
    return SegmentHit(true, contact(deep, p0, p1));
}

// `segment_obb::max_depth_local`: how far the segment c ± h (box frame)
// reaches into the box of half extents e; the 17 candidates in the CPU's order.
fn depth_at(c: vec3<f32>, h: vec3<f32>, e: vec3<f32>, s: f32) -> f32 {
    let q = e - abs(c + h * s);
    return min(min(q.x, q.y), q.z);
}

fn max_depth_local(c: vec3<f32>, h: vec3<f32>, e: vec3<f32>) -> f32 {
    var best = max(depth_at(c, h, e, -1.0), depth_at(c, h, e, 1.0));
    for (var i = 0u; i < 3u; i++) {
        if h[i] != 0.0 {
            best = max(best, depth_at(c, h, e, clamp(-c[i] / h[i], -1.0, 1.0)));
        }
        for (var j = i + 1u; j < 3u; j++) {
            for (var k = 0u; k < 4u; k++) {
                let si = select(-1.0, 1.0, k < 2u);
                let sj = select(-1.0, 1.0, k % 2u == 0u);
                let den = sj * h[j] - si * h[i];
                if den != 0.0 {
                    let s = (e[j] - e[i] - sj * c[j] + si * c[i]) / den;
                    best = max(best, depth_at(c, h, e, clamp(s, -1.0, 1.0)));
                }
            }
        }
    }
    return best;
}

// The segment in node i's frame, against the box grown by `shell`, own box
// (`reach` false) or reach box (true): `segment_obb::to_box_frame`.
struct Framed {
    c: vec3<f32>,
    h: vec3<f32>,
    e: vec3<f32>,
}

fn framed(centre: vec3<f32>, half: vec3<f32>, i: u32, reach: bool, shell: f32) -> Framed {
    let n = node_at(i);
    var bc = n.center.xyz;
    var he = n.half.xyz;
    if reach {
        bc = n.reach_center.xyz;
        he = n.reach_half.xyz;
    }
    let d = centre - bc;
    let c = vec3<f32>(dot3(n.axis_u.xyz, d), dot3(n.axis_v.xyz, d), dot3(n.axis_w.xyz, d));
    let h = vec3<f32>(dot3(n.axis_u.xyz, half), dot3(n.axis_v.xyz, half), dot3(n.axis_w.xyz, half));
    return Framed(c, h, he + vec3<f32>(shell));
}

// `segment_obb::hits_centred_local`.
fn hits_local(f: Framed) -> bool {
    let ah = abs(f.h);
    let e = f.e;
    let faces = abs(f.c) <= e + ah;
    let cr = abs(cross3(f.c, f.h));
    let reach = vec3<f32>(e.y, e.x, e.x) * vec3<f32>(ah.z, ah.z, ah.y)
        + vec3<f32>(e.z, e.z, e.y) * vec3<f32>(ah.y, ah.x, ah.x);
    return all(faces) && all(cr <= reach);
}

// `LocalMotion::ramp_at`; `deform`: the node's deformation velocity.
fn ramp_at(p: vec3<f32>, deform: vec3<f32>) -> f32 {
    let v = obj.local_velocity.xyz + cross_scalar(obj.local_angular.xyz, p) + deform;
    let speed = sqrt(dot3(v, v));
    let r = RAMP_TRAVELS * min(max(obj.local_angular.w, RAMP_STEP_S) * speed, obj.local_velocity.w);
    if r < 3.0e38 {
        return r;
    }
    return 0.0;
}

// `narrow_phase::AGREED`.
const AGREED: f32 = 0.25;

// `narrow_phase::agreement`: min(len / (AGREED · sum), 1), exactly 1 from
// AGREED on, 0 for a sum not positive or NaN.
fn agreement(len: f32, sum: f32) -> f32 {
    let full = AGREED * sum;
    if len >= full {
        return 1.0;
    }
    let a = len / full;
    if a > 0.0 {
        return a;
    }
    return 0.0;
}

// `narrow_phase::Weighted`.
struct Weighted {
    dir: vec3<f32>,
    point: vec3<f32>,
    velocity: vec3<f32>,
    sum: f32,
    max_w: f32,
    max_dir: vec3<f32>,
    // The largest box depth of the final nodes met.
    box_depth: f32,
}

fn weighted_add(acc: ptr<function, Weighted>, w: f32, dir: vec3<f32>, at: vec3<f32>, velocity: vec3<f32>) {
    (*acc).dir += dir * w;
    (*acc).point += at * w;
    (*acc).velocity += velocity * w;
    (*acc).sum += w;
    if w > (*acc).max_w {
        (*acc).max_w = w;
        (*acc).max_dir = dir;
    }
}

// The true depth of each vertex of the blade inside the mesh, asked at most
// once a blade and object (`known` in `contact_blade_by`: a vertex ends
// one segment and starts the next); < 0 outside. `pen_asked`: bit v set
// once vertex v was asked; `pen_segment`: the segment being tested (its
// ends are vertices `pen_segment` and `pen_segment + 1`).
var<private> pen_known: array<f32, 16>;
var<private> pen_asked: u32;
var<private> pen_segment: u32;

fn pen_of(k: u32, q: vec3<f32>) -> f32 {
    if tree.y == 0u && !winds() {
        return -1.0;
    }
    let v = pen_segment + k;
    if (pen_asked & (1u << v)) == 0u {
        pen_asked |= 1u << v;
        pen_known[v] = penetration(q, 0.0).w;
    }
    return pen_known[v];
}

// Each vertex's way out (`way_out(q, 0.0)`), asked at most once a blade and
// object (`ways` in `contact_blade_by`: a segment wholly in a hollow asks
// both its ends, and a vertex ends one segment and starts the next — the
// same answers, half the walks). Reset with `pen_asked`; the vertex is
// `pen_segment + k`, as in `pen_of`.
var<private> way_known: array<vec4<f32>, 16>;
var<private> way_asked: u32;

fn way_of(k: u32, q: vec3<f32>) -> vec4<f32> {
    let v = pen_segment + k;
    if (way_asked & (1u << v)) == 0u {
        way_asked |= 1u << v;
        way_known[v] = way_out(q, 0.0);
    }
    return way_known[v];
}

// `narrow_phase::below_patch`.
fn below_patch(c: vec3<f32>, n: vec3<f32>, p0: vec3<f32>, p1: vec3<f32>, shell: f32, floor_reach: f32) -> f32 {
    let b0 = dot3(c - p0, n);
    let b1 = dot3(c - p1, n);
    var q = p1;
    var below = b1;
    var k = 1u;
    if b0 >= b1 {
        q = p0;
        below = b0;
        k = 0u;
    }
    if below <= 0.0 || below + shell <= floor_reach {
        return 0.0;
    }
    let depth = pen_of(k, q);
    if depth < 0.0 {
        return 0.0;
    }
    // The shell comes in with the depth: 0 on the surface, as outside.
    return min(below, depth) + min(depth, shell);
}

// `narrow_phase::contact_segment`: the weighted contact (weight 0: none).
fn contact_segment(p0: vec3<f32>, p1: vec3<f32>, shell: f32) -> Contact {
    let none = Contact(vec3<f32>(0.0), vec3<f32>(0.0), 0.0, vec3<f32>(0.0), 0.0);
    if tree.x == 0u {
        return none;
    }
    let centre = (p0 + p1) * 0.5;
    let half = (p1 - p0) * 0.5;
    if !meets_root(centre, half, shell) {
        return none;
    }
    var acc = Weighted(vec3<f32>(0.0), vec3<f32>(0.0), vec3<f32>(0.0), 0.0, 0.0, vec3<f32>(0.0), 0.0);
    var deepest = 0u;
    walk_stack[0] = vec2<u32>(0u, 1u);
    var len = 1u;
    let count = tree.x;
    let final_depth = tree.z;
    // The blade's final nodes (`list_near`), in the walk's order: the
    // nodes the walk would end at, without the walk
    // (`narrow_phase::contact_blade_near`); else the walk from the root.
    // One loop for both, so that `final_node` has one call site: shader
    // compilers inline every call, and each copy of it holds a whole
    // closest-point walk (BENCHMARKS.md, "Session 54": fewer copies, the
    // pipelines compile and run about twice as fast on llvmpipe).
    let listed = near_count != NEAR_NONE;
    var j = 0u;
    if listed {
        // The root was hit.
        deepest = 1u;
        len = 0u;
    }
    loop {
        var i = 0u;
        if listed {
            if j >= near_count {
                break;
            }
            i = near[j];
            j++;
            if !hits_local(framed(centre, half, i, false, shell)) {
                continue;
            }
        } else {
            if len == 0u {
                break;
            }
            len -= 1u;
            i = walk_stack[len].x;
            let depth = walk_stack[len].y;
            if i >= count {
                continue;
            }
            let n = node_at(i);
            let l = n.children.x;
            let r = n.children.y;
            let descend = depth < final_depth && l != NO_CHILD && l > i && r > i && len + 2u <= STACK_SIZE;
            if !hits_local(framed(centre, half, i, descend, shell)) {
                continue;
            }
            deepest = max(deepest, depth);
            if descend {
                walk_stack[len] = vec2<u32>(r, depth + 1u);
                walk_stack[len + 1u] = vec2<u32>(l, depth + 1u);
                len += 2u;
                continue;
            }
        }
        final_node(i, centre, half, p0, p1, shell, &acc);
    }
    // `narrow_phase::contact_finish`: the ends inside a closed mesh or a
    // winding open mesh's hollow push out their own ways, counting `rest`
    // as much as the nodes met take over. While the box depth is under the
    // shell the segment crosses no triangle: its midpoint tells inside.
    let open = winds();
    let rest = (1.0 - acc.max_w) * (1.0 - min(acc.box_depth / shell, 1.0));
    if rest > 0.0 && deepest > 0u && (open || point_inside((p0 + p1) * 0.5)) {
        // `contact::way_out` of each end inside (each vertex's asked once),
        // added as a node weighed by its depth, p0 first.
        for (var k = 0u; k < 2u; k++) {
            var q = p0;
            if k == 1u {
                q = p1;
            }
            let out = way_of(k, q);
            if out.w >= 0.0 {
                var reach = out.w + min(out.w, shell);
                if open {
                    reach = out.w;
                }
                let w = min(reach / (shell + ramp_at(q, vec3<f32>(0.0))), 1.0) * rest;
                if w > 0.0 {
                    weighted_add(&acc, w, out.xyz, q, vec3<f32>(0.0));
                }
            }
        }
    }
    if acc.max_w == 0.0 {
        return none;
    }
    var dir = acc.max_dir;
    let dl = sqrt(dot3(acc.dir, acc.dir));
    if dl > CANCELLED * acc.sum {
        let rcp = 1.0 / dl;
        if rcp < 3.0e38 && rcp > 0.0 {
            dir = acc.dir * rcp;
        }
    }
    return Contact(dir, acc.point / acc.sum, acc.max_w, acc.velocity / acc.sum, agreement(dl, acc.sum));
}

// `narrow_phase::contact_node`: final node i, whose box (grown by the
// shell) the segment met, added to `acc` when the segment reaches into it.
fn final_node(i: u32, centre: vec3<f32>, half: vec3<f32>, p0: vec3<f32>, p1: vec3<f32>, shell: f32, acc: ptr<function, Weighted>) {
    let n = node_at(i);
    let d = max_depth_local_of(framed(centre, half, i, false, shell));
    if d > 0.0 {
        let at = closest_point(p0, p1, n.center.xyz);
        let full = shell + ramp_at(at, n.velocity.xyz);
        // The below-patch depth, at most `full`, comes in with the box
        // depth over the shell (`fade`); floor = d / fade.
        let fade = min(d / shell, 1.0);
        var reach = d;
        if n.dir.w == 1.0 && d < full && full * fade > d {
            let below = below_patch(n.center.xyz, n.dir.xyz, p0, p1, shell, max(d, shell));
            reach = max(d, min(below, full) * fade);
        }
        let w = min(reach / full, 1.0);
        weighted_add(acc, w, eqn_direction(i, p0, p1), at, n.velocity.xyz);
        (*acc).box_depth = max((*acc).box_depth, d);
    }
}

// The final nodes the blade being tested may meet (ours, issue 16; the
// CPU's `narrow_phase::final_nodes_near` for the blade's own box): listed
// once per blade and object by `list_near`, then each segment tests their
// grown boxes alone instead of walking from the root. They are every final
// node whose grown box a segment in the box can meet, in the walk's
// depth-first, left-first order, so the contacts are the walk's.
// NEAR_NONE: not listed (too many, or the yes/no walk): the segments walk.
const NEAR_MAX: u32 = 32u;
const NEAR_NONE: u32 = 0xffffffffu;
// `broad_phase::PARALLEL_PAD`; five times `broad_phase::REL_SLACK` (the
// list only prunes: a wider slack costs a few tests, never a contact).
const NEAR_PAD: f32 = 1e-6;
const NEAR_SLACK: f32 = 5e-5;
var<private> near: array<u32, NEAR_MAX>;
var<private> near_count: u32;

// `broad_phase::obb_may_overlap_aabb` (the face axes; errs towards
// overlap, with the broad phase's slack) for node n's own box, or its reach
// box when `reach`, grown by `shell`, against the box lo..hi.
fn node_may_meet(n: Node, reach: bool, shell: f32, lo: vec3<f32>, hi: vec3<f32>) -> bool {
    var c = n.center.xyz;
    var e = n.half.xyz;
    if reach {
        c = n.reach_center.xyz;
        e = n.reach_half.xyz;
    }
    e = e + vec3<f32>(shell);
    let a = (hi - lo) * 0.5;
    let t = c - (lo + hi) * 0.5;
    let pad = vec3<f32>(NEAR_PAD);
    let au = abs(n.axis_u.xyz) + pad;
    let av = abs(n.axis_v.xyz) + pad;
    let aw = abs(n.axis_w.xyz) + pad;
    let rb = au * e.x + av * e.y + aw * e.z;
    if any(abs(t) > (a + rb) * (1.0 + NEAR_SLACK)) {
        return false;
    }
    return abs(dot3(t, n.axis_u.xyz)) <= (dot3(a, au) + e.x) * (1.0 + NEAR_SLACK)
        && abs(dot3(t, n.axis_v.xyz)) <= (dot3(a, av) + e.y) * (1.0 + NEAR_SLACK)
        && abs(dot3(t, n.axis_w.xyz)) <= (dot3(a, aw) + e.z) * (1.0 + NEAR_SLACK);
}

// Fills `near` with the final nodes of the loaded object that a segment in
// lo..hi (object frame) may meet (`narrow_phase::final_nodes_near_each`).
fn list_near(lo: vec3<f32>, hi: vec3<f32>, shell: f32) {
    near_count = 0u;
    walk_stack[0] = vec2<u32>(0u, 1u);
    var len = 1u;
    let count = tree.x;
    let final_depth = tree.z;
    while len > 0u {
        len -= 1u;
        let i = walk_stack[len].x;
        let depth = walk_stack[len].y;
        if i >= count {
            continue;
        }
        let n = node_at(i);
        let l = n.children.x;
        let r = n.children.y;
        let descend = depth < final_depth && l != NO_CHILD && l > i && r > i;
        if descend && len + 2u > STACK_SIZE {
            near_count = NEAR_NONE;
            return;
        }
        if !node_may_meet(n, descend, shell, lo, hi) {
            continue;
        }
        if descend {
            walk_stack[len] = vec2<u32>(r, depth + 1u);
            walk_stack[len + 1u] = vec2<u32>(l, depth + 1u);
            len += 2u;
        } else if near_count == NEAR_MAX {
            near_count = NEAR_NONE;
            return;
        } else {
            near[near_count] = i;
            near_count += 1u;
        }
    }
}

fn max_depth_local_of(f: Framed) -> f32 {
    return max_depth_local(f.c, f.h, f.e);
}

// Every blade of the chunk (no broad phase: `trample collide`, stage
// tests): the paper's hit flags and forces, `collide_blade`, every object.
@compute @workgroup_size(64)
fn collide(@builtin(global_invocation_id) gid: vec3<u32>) {
    let b = chunk_blade(gid);
    if b == NOT_IN_CHUNK {
        return;
    }
    var f = vec4<f32>(0.0);
    var touched = vec4<u32>(0u);
    for (var o = 0u; o < object_count(); o++) {
        load_object(o, gid.z);
        collide_blade(b, false, &f, &touched);
    }
    force[b] = f;
    touch[b] = touched;
}

// The simulation's weighted contacts run in two dispatches a chunk (and
// `near_args` between them): `list_blades` over every blade of the chunk's
// patches the broad phase listed keeps the blades that may touch an object
// (a segment meets one's root box grown by its shell: `contact_segment`'s
// first test) and writes the others' zero force and contact; then
// `collide_listed` runs the walks over the kept blades alone. The same
// results as one pass over every blade (a blade no segment of which meets
// a root box gets no contact), for a fraction of the work where most
// blades of a listed patch are away from the objects: on the software
// drivers, which run every branch of a kernel whether a lane takes it or
// not, the walks cost every blade of a listed patch (BENCHMARKS.md,
// "Session 55"); on a GPU the kept blades fill the warps.

// Segment p0..p1 (centre and half, object frame) meets the loaded
// object's root box grown by `shell` (`contact_segment`'s first test).
fn meets_root(centre: vec3<f32>, half: vec3<f32>, shell: f32) -> bool {
    return hits_local(framed(centre, half, 0u, true, shell));
}

// Whether `collide_blade(b, true, ..)` may find a contact with the loaded
// object: the blade counts for it and a segment meets its root box.
fn may_touch(b: u32) -> bool {
    if tree.x == 0u || !counts_for_object(b, true) {
        return false;
    }
    let segments = min(field.y, MAX_SEGMENTS);
    let shell = obj.contact.x;
    var prev = to_local(pos[vertex_at(0u, b)].xyz);
    for (var k = 0u; k < segments; k++) {
        let next = to_local(pos[vertex_at(k + 1u, b)].xyz);
        if meets_root((prev + next) * 0.5, (next - prev) * 0.5, shell) {
            return true;
        }
        prev = next;
    }
    return false;
}

// The blades of the chunk's patches the broad phase listed (indirect
// dispatch of `dispatch_args`), against the objects it marked for the
// blade's patch: those that may touch one are listed for
// `collide_listed`, the others get zero force and contact.
@compute @workgroup_size(64)
fn list_blades(@builtin(global_invocation_id) gid: vec3<u32>, @builtin(num_workgroups) groups: vec3<u32>) {
    let at = listed_thread(gid, groups);
    if at.slot >= lists[chunk.groups.z] {
        return;
    }
    let p = lists[at.entry];
    let b = p * at.per_patch + at.lane;
    var near = false;
    let words = objects[0].y;
    for (var w = 0u; w < words; w++) {
        var bits = lists[objects[0].z + p * words + w];
        while bits != 0u && !near {
            load_object(32u * w + countTrailingZeros(bits), gid.z);
            bits &= bits - 1u;
            near = may_touch(b);
        }
    }
    if near {
        let slot = atomicAdd(&near_blades[0], 1u);
        atomicStore(&near_blades[1u + slot], b);
    } else {
        force[b] = vec4<f32>(0.0);
        touch[b] = vec4<u32>(0u);
    }
}

// One thread: the workgroups of `collide_listed` over the listed blades
// (at most `chunk.groups.x` in x, as the chunk's blade dispatch).
@compute @workgroup_size(1)
fn near_args() {
    let d = list_dispatch(atomicLoad(&near_blades[0]), chunk.groups.x);
    near_dispatch[0] = d.x;
    near_dispatch[1] = d.y;
    near_dispatch[2] = d.z;
}

// The blades `list_blades` kept, against the objects the broad phase
// marked for the blade's patch, in object order; forces and touches were
// cleared first: the simulation's weighted contacts.
@compute @workgroup_size(64)
fn collide_listed(@builtin(global_invocation_id) gid: vec3<u32>, @builtin(num_workgroups) groups: vec3<u32>) {
    let i = list_thread(gid, groups);
    if i >= atomicLoad(&near_blades[0]) {
        return;
    }
    let b = atomicLoad(&near_blades[1u + i]);
    let p = b / max(chunk.groups.w, 1u);
    var f = vec4<f32>(0.0);
    var touched = vec4<u32>(0u);
    let words = objects[0].y;
    for (var w = 0u; w < words; w++) {
        var bits = lists[objects[0].z + p * words + w];
        while bits != 0u {
            load_object(32u * w + countTrailingZeros(bits), gid.z);
            bits &= bits - 1u;
            collide_blade(b, true, &f, &touched);
        }
    }
    force[b] = f;
    touch[b] = touched;
}

// Whether blade b counts for the loaded object: a blade a grass map left
// out (`seg_len` 0 in vertex 0's w, `Blades::is_present`) does not in the
// simulation's contacts, as the CPU's blade lists leave it out
// (`step::collide`; the plain test takes every blade), nor one whose cell
// is not geometry unless the object tracks everywhere.
fn counts_for_object(b: u32, weighted: bool) -> bool {
    let cell = b / max(obj.field.z, 1u);
    let everywhere = weighted && extra.y != 0u;
    let present = !weighted || pos[vertex_at(0u, b)].w > 0.0;
    return present && (everywhere || (cell_state[cell] & 3u) == LOD_GEOMETRY);
}

// Adds the loaded object's contacts with blade b to `f` (Σ force, Σ
// weights) and `touched` (segment mask, firmest weight, its owner).
fn collide_blade(b: u32, weighted: bool, f: ptr<function, vec4<f32>>, touched: ptr<function, vec4<u32>>) {
    var mask = 0u;
    let segments = min(field.y, MAX_SEGMENTS);
    if counts_for_object(b, weighted) {
        var sum = vec3<f32>(0.0);
        var weights = 0.0;
        let shell = obj.contact.x;
        let press = obj.contact.y;
        // The blade in the object's frame, and its box.
        var lo = vec3<f32>(3.0e38);
        var hi = vec3<f32>(-3.0e38);
        for (var k = 0u; k <= segments; k++) {
            blade_local[k] = to_local(pos[vertex_at(k, b)].xyz);
            lo = min(lo, blade_local[k]);
            hi = max(hi, blade_local[k]);
        }
        near_count = NEAR_NONE;
        if weighted && shell > 0.0 && tree.x > 0u && all(lo <= hi) {
            // `step::collide::TILE_PAD_M`.
            list_near(lo - vec3<f32>(1.0e-4), hi + vec3<f32>(1.0e-4), shell);
        }
        var prev = blade_local[0];
        pen_asked = 0u;
        way_asked = 0u;
        for (var k = 0u; k < segments; k++) {
            let next = blade_local[k + 1u];
            pen_segment = k;
            var c = Contact(vec3<f32>(0.0), vec3<f32>(0.0), 0.0, vec3<f32>(0.0), 0.0);
            if weighted {
                c = contact_segment(prev, next, shell);
            } else {
                let s = collide_segment(prev, next);
                if s.hit {
                    c = s.c;
                }
            }
            if c.weight > 0.0 {
                mask |= 1u << k;
                // Eq. 2: EqF = |v + ω × r| · EqN, EqN turned into the world,
                // times the weight and the object's press (`eqf`).
                // The deforming mesh's own velocity there adds to the
                // rigid motion (`SegmentContact::velocity`).
                let speed = length(point_velocity(to_world(c.point)) + rotate(obj.rotation, c.velocity));
                let dir = rotate(obj.rotation, c.dir);
                let dl = sqrt(dot3(dir, dir));
                let rcp = 1.0 / dl;
                if rcp < 3.0e38 && rcp > 0.0 {
                    var eqf = (dir * rcp) * abs(speed);
                    if weighted {
                        eqf = eqf * (c.weight * c.agree * press);
                    }
                    sum += eqf;
                }
                weights += c.weight;
            }
            prev = next;
        }
        if weighted {
            *f = vec4<f32>((*f).xyz + sum, (*f).w + weights);
            (*touched).x = (*touched).x | mask;
            // The firmest single-object contact names the track owner
            // (`step::collide::accumulate_contacts`).
            if weights >= DBG_WEIGHT && weights > bitcast<f32>((*touched).y) {
                (*touched).y = bitcast<u32>(weights);
                (*touched).z = extra.x;
            }
        } else {
            // `num` saturates at 255 as the CPU's u8 did.
            *f = vec4<f32>((*f).xyz + sum, min((*f).w + f32(countOneBits(mask)), 255.0));
            (*touched).x = (*touched).x | mask;
        }
    }
}
