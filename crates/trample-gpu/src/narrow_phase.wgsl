// Narrow phase and DBG forces (paper §4.2, §5.1 Eq. 2; DESIGN §4.2): one
// thread per blade. The blade's vertices are moved into the object's local
// frame once, each segment walks the OBB tree depth first down to the
// precision (root = depth 1) with a fixed-size stack, all levels in this one
// dispatch (no read-back between levels). Mirrors, float op for float op,
// `trample::collision::narrow_phase::collide_segment` and
// `trample::collision::segment_obb`, so the hit flags agree bit for bit where
// the shader compiler does not contract a*b+c into an fma.
//
// One dispatch per object; dispatches of the objects run in order in one
// submission and each thread adds its own blade's force (no atomics), so the
// sum is taken in the CPU's order (object by object).

// Layout-compatible with `GpuNode` in object.rs.
struct Node {
    center: vec4<f32>,
    axis_u: vec4<f32>,
    axis_v: vec4<f32>,
    axis_w: vec4<f32>,
    half: vec4<f32>,
    // xyz: Eq. 3's EqN normalised when w == 1; else the smallest box axis,
    // pointing up (the fallback of `ObbTree::eqn_direction`).
    dir: vec4<f32>,
    // left child, right child (0xffffffff for a leaf), first triangle, count
    children: vec4<u32>,
}

// Layout-compatible with `GpuObjectParams` in object.rs.
struct ObjectParams {
    position: vec4<f32>,
    rotation: vec4<f32>,
    velocity: vec4<f32>,
    angular_velocity: vec4<f32>,
    grid_center: vec4<f32>,
    grid_u: vec4<f32>,
    grid_v: vec4<f32>,
    grid_w: vec4<f32>,
    grid_half: vec4<f32>,
    // node count, closed (1) / open (0), final depth, 1 for the first object
    tree: vec4<u32>,
    // blade count, segments, blades per cell, inside-grid side (0: no grid)
    field: vec4<u32>,
}

@group(0) @binding(0) var<storage, read> pos: array<vec4<f32>>;
// Bits 0–1: the cell's level of detail (see cells.wgsl).
@group(0) @binding(1) var<storage, read> cell_state: array<u32>;
@group(0) @binding(2) var<storage, read_write> force: array<vec4<f32>>;
@group(0) @binding(3) var<storage, read_write> hit_mask: array<u32>;
// The chunk of patches this dispatch runs over (`chunk.wgsl`): `pos` is its own.
@group(0) @binding(4) var<uniform> chunk: Chunk;
// The broad phase's patch lists (`broad_phase.wgsl`), read by
// `collide_listed`: the chunk's list starts at its first patch, its count
// is entry `chunk.groups.z`.
@group(0) @binding(5) var<storage, read> lists: array<u32>;

@group(1) @binding(0) var<uniform> obj: ObjectParams;
@group(1) @binding(1) var<storage, read> nodes: array<Node>;
@group(1) @binding(2) var<storage, read> triangles: array<vec4<f32>>;
@group(1) @binding(3) var<storage, read> voxels: array<u32>;

// The object's header as every branch and loop bound below reads it: a copy
// of `obj.tree` and `obj.field` with `gid.z` added, which is 0 (this kernel
// is always dispatched one workgroup deep in z) but unknown to the driver
// when it compiles. Why: Mesa's lavapipe (22.3, what CI installs) finds the
// uniform values that decide a branch or a loop's trip count, folds them into
// the shader and compiles it again through LLVM at every dispatch, without a
// cache of the variants. With `obj.tree` / `obj.field` deciding branches it
// did that for this kernel at every dispatch: 3–13 s each on the 2-core CI
// machine, against ≈ 10–20 ms for the dispatch itself (Mesa's on-disk shader
// cache hid it for the poses an earlier run had already compiled). Values
// that only index (`obj.field.x`, `.z`) may stay plain uniform reads.
var<private> tree: vec4<u32>;
var<private> field: vec4<u32>;

const NO_CHILD: u32 = 0xffffffffu;
const NONE: u32 = 0xffffffffu;
// MAX_TREE_DEPTH + 2, as `exact::STACK_SIZE`.
const STACK_SIZE: u32 = 66u;
const MAX_SEGMENTS: u32 = 15u;
const LOD_GEOMETRY: u32 = 0u;
const VOXEL_INSIDE: u32 = 1u;
const VOXEL_OUTSIDE: u32 = 0u;
// `exact::INSIDE_RAY`.
const INSIDE_RAY: vec3<f32> = vec3<f32>(0.012345679, -1.0, 0.017320508);
// `Walk::contact`: a sum of unit vectors shorter than this has cancelled.
const CANCELLED: f32 = 1e-3;

// Vector into the box frame: rows u, v, w (glam: transposed `Mat3A` times v).
fn to_box(n: Node, v: vec3<f32>) -> vec3<f32> {
    return vec3<f32>(dot3(n.axis_u.xyz, v), dot3(n.axis_v.xyz, v), dot3(n.axis_w.xyz, v));
}

fn hits_obb(centre: vec3<f32>, half: vec3<f32>, n: Node) -> bool {
    return hits_box(centre, half, n.center.xyz, n.axis_u.xyz, n.axis_v.xyz, n.axis_w.xyz, n.half.xyz);
}

// glam `Quat::mul_vec3a` (SSE path) for a unit quaternion q = (x, y, z, w).
fn rotate(q: vec4<f32>, v: vec3<f32>) -> vec3<f32> {
    let w = q.w;
    let b = q.xyz;
    let b2 = dot3(b, b);
    return (v * (w * w - b2) + b * (dot3(v, b) * 2.0)) + cross3(b, v) * (w * 2.0);
}

// `Pose::to_local`: rotation⁻¹ (p − position).
fn to_local(p: vec3<f32>) -> vec3<f32> {
    let q = vec4<f32>(-obj.rotation.xyz, obj.rotation.w);
    return rotate(q, p - obj.position.xyz);
}

// `obb::build::closest_point_on_segment`.
fn closest_point(p0: vec3<f32>, p1: vec3<f32>, q: vec3<f32>) -> vec3<f32> {
    let d = p1 - p0;
    let dd = dot3(d, d);
    if dd > 0.0 {
        let t = clamp(dot3(q - p0, d) / dd, 0.0, 1.0);
        return p0 + d * t;
    }
    return p0;
}

// `ObbTree::eqn_direction`.
fn eqn_direction(i: u32, p0: vec3<f32>, p1: vec3<f32>) -> vec3<f32> {
    let n = nodes[i];
    if n.dir.w == 1.0 {
        return n.dir.xyz;
    }
    let c = n.center.xyz;
    let away = closest_point(p0, p1, c) - c;
    let len2 = dot3(away, away);
    if len2 > 0.0 {
        return away * (1.0 / sqrt(len2));
    }
    return n.dir.xyz;
}

struct Walk {
    sum: vec3<f32>,
    first: u32,
    first_dir: vec3<f32>,
    deepest_hit: u32,
}

// `narrow_phase::walk`: depth first, left child first, fixed-size stack.
fn walk(p0: vec3<f32>, p1: vec3<f32>, final_depth: u32) -> Walk {
    let centre = (p0 + p1) * 0.5;
    let half = (p1 - p0) * 0.5;
    var out = Walk(vec3<f32>(0.0), NONE, vec3<f32>(0.0), 0u);
    var stack: array<vec2<u32>, STACK_SIZE>;
    stack[0] = vec2<u32>(0u, 1u);
    var len = 1u;
    let count = tree.x;
    while len > 0u {
        len -= 1u;
        let i = stack[len].x;
        let depth = stack[len].y;
        if i >= count {
            continue;
        }
        let n = nodes[i];
        if !hits_obb(centre, half, n) {
            continue;
        }
        out.deepest_hit = max(out.deepest_hit, depth);
        let l = n.children.x;
        let r = n.children.y;
        let leaf = l == NO_CHILD;
        if depth < final_depth && !leaf && l > i && r > i && len + 2u <= STACK_SIZE {
            stack[len] = vec2<u32>(r, depth + 1u);
            stack[len + 1u] = vec2<u32>(l, depth + 1u);
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

// `Walk::contact`: (direction, point), object-local frame.
struct Contact {
    dir: vec3<f32>,
    point: vec3<f32>,
}

fn contact(w: Walk, p0: vec3<f32>, p1: vec3<f32>) -> Contact {
    var dir = w.first_dir;
    let len2 = dot3(w.sum, w.sum);
    if sqrt(len2) > CANCELLED {
        dir = w.sum * (1.0 / sqrt(len2));
    }
    return Contact(dir, closest_point(p0, p1, nodes[w.first].center.xyz));
}

// `segment_triangle::segment_crosses_triangle_interior`, in f32 (the CPU
// works in f64; WGSL has no f64): Möller–Trumbore, strict interior.
fn crosses_triangle(p0: vec3<f32>, p1: vec3<f32>, t: u32) -> bool {
    let a = triangles[3u * t].xyz;
    let b = triangles[3u * t + 1u].xyz;
    let c = triangles[3u * t + 2u].xyz;
    let e1 = b - a;
    let e2 = c - a;
    let n_len = length(cross3(e1, e2));
    let scale = max(max(length(e1), length(e2)), length(c - b));
    if n_len <= 1e-12 * scale * scale {
        return false;
    }
    let d = p1 - p0;
    let pvec = cross3(d, e2);
    let det = dot3(e1, pvec);
    if abs(det) <= 1e-12 * length(d) * n_len {
        return false;
    }
    let inv = 1.0 / det;
    let s = p0 - a;
    let u = dot3(s, pvec) * inv;
    let qvec = cross3(s, e1);
    let v = dot3(d, qvec) * inv;
    let tt = dot3(e2, qvec) * inv;
    return u > 0.0 && v > 0.0 && u + v < 1.0 && tt > 0.0 && tt < 1.0;
}

// `exact::point_inside_by_ray` (f32 triangle tests, see `crosses_triangle`).
fn inside_by_ray(p: vec3<f32>) -> bool {
    let root = nodes[0];
    let q = to_box(root, p - root.center.xyz);
    let hh = root.half.xyz;
    if any(abs(q) > hh) {
        return false;
    }
    let d = vec3<f32>(dot3(INSIDE_RAY, root.axis_u.xyz), dot3(INSIDE_RAY, root.axis_v.xyz), dot3(INSIDE_RAY, root.axis_w.xyz));
    var t_exit = 3.0e38;
    for (var k = 0u; k < 3u; k++) {
        if d[k] != 0.0 {
            let side = select(hh[k], -hh[k], d[k] < 0.0);
            t_exit = min(t_exit, (side - q[k]) / d[k]);
        }
    }
    if t_exit >= 3.0e38 {
        return false;
    }
    let end = p + INSIDE_RAY * (max(t_exit, 0.0) * 1.001 + 1e-3 * max(max(hh.x, hh.y), hh.z) + 1e-5);
    // `exact::visit_leaves` with the ray segment, counting crossings.
    let centre = (p + end) * 0.5;
    let half = (end - p) * 0.5;
    var stack: array<u32, STACK_SIZE>;
    stack[0] = 0u;
    var len = 1u;
    var crossings = 0u;
    let count = tree.x;
    while len > 0u {
        len -= 1u;
        let i = stack[len];
        if i >= count {
            continue;
        }
        let n = nodes[i];
        if !hits_obb(centre, half, n) {
            continue;
        }
        let l = n.children.x;
        let r = n.children.y;
        if l == NO_CHILD || l <= i || r <= i || len + 2u > STACK_SIZE {
            for (var t = n.children.z; t < n.children.z + n.children.w; t++) {
                if crosses_triangle(p, end, t) {
                    crossings += 1u;
                }
            }
        } else {
            stack[len] = r;
            stack[len + 1u] = l;
            len += 2u;
        }
    }
    return crossings % 2u == 1u;
}

// `exact::point_inside`: the voxel grid first, the ray where it cannot tell.
fn point_inside(p: vec3<f32>) -> bool {
    let side = field.w;
    if side > 0u {
        let dd = p - obj.grid_center.xyz;
        let q = vec3<f32>(dot3(dd, obj.grid_u.xyz), dot3(dd, obj.grid_v.xyz), dot3(dd, obj.grid_w.xyz));
        let h = obj.grid_half.xyz;
        let g = (q + h) / (2.0 * h) * f32(side);
        if any(g < vec3<f32>(0.0)) || any(g >= vec3<f32>(f32(side))) {
            return false;
        }
        let v = vec3<u32>(g);
        let voxel = voxels[(v.z * side + v.y) * side + v.x];
        if voxel == VOXEL_INSIDE {
            return true;
        }
        if voxel == VOXEL_OUTSIDE {
            return false;
        }
    }
    return inside_by_ray(p);
}

// `narrow_phase::collide_segment`: hit flag in `hit`, contact when hit.
struct SegmentHit {
    hit: bool,
    c: Contact,
}

fn collide_segment(p0: vec3<f32>, p1: vec3<f32>) -> SegmentHit {
    let miss = SegmentHit(false, Contact(vec3<f32>(0.0), vec3<f32>(0.0)));
    if tree.x == 0u {
        return miss;
    }
    let centre = (p0 + p1) * 0.5;
    let half = (p1 - p0) * 0.5;
    if !hits_obb(centre, half, nodes[0]) {
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

// `Pose::point_velocity` of a world point: v + ω × (p − position).
fn point_velocity(p: vec3<f32>) -> vec3<f32> {
    return obj.velocity.xyz + cross3(obj.angular_velocity.xyz, p - obj.position.xyz);
}

// Every blade of the chunk (no broad phase: `trample collide`, stage tests).
@compute @workgroup_size(64)
fn collide(@builtin(global_invocation_id) gid: vec3<u32>) {
    opaque_uniforms(gid);
    let b = chunk_blade(gid);
    if b != NOT_IN_CHUNK {
        collide_blade(b);
    }
}

// The blades of the chunk's patches the broad phase listed (indirect
// dispatch of `dispatch_args`); forces and hit masks were cleared first.
@compute @workgroup_size(64)
fn collide_listed(@builtin(global_invocation_id) gid: vec3<u32>, @builtin(num_workgroups) groups: vec3<u32>) {
    opaque_uniforms(gid);
    let per_patch = max(chunk.groups.w, 1u);
    let t = gid.x + gid.y * groups.x * 64u;
    let slot = t / per_patch;
    if slot >= lists[chunk.groups.z] {
        return;
    }
    let p = lists[chunk.range.x / per_patch + slot];
    collide_blade(p * per_patch + t % per_patch);
}

// `tree` and `field`: the object's uniforms as the compiler cannot fold
// them (see their declarations).
fn opaque_uniforms(gid: vec3<u32>) {
    tree = obj.tree + vec4<u32>(gid.z);
    field = obj.field + vec4<u32>(gid.z);
}

fn collide_blade(b: u32) {
    let first_object = tree.w == 1u;
    var f = vec4<f32>(0.0);
    if !first_object {
        f = force[b];
    }
    var mask = 0u;
    let segments = min(field.y, MAX_SEGMENTS);
    let cell = b / max(obj.field.z, 1u);
    if (cell_state[cell] & 3u) == LOD_GEOMETRY {
        var prev = to_local(pos[vertex_at(0u, b)].xyz);
        var sum = vec3<f32>(0.0);
        for (var k = 0u; k < segments; k++) {
            let next = to_local(pos[vertex_at(k + 1u, b)].xyz);
            let s = collide_segment(prev, next);
            if s.hit {
                mask |= 1u << k;
                // Eq. 2: EqF = |v + ω × r| · EqN, EqN turned into the world.
                let point = rotate(obj.rotation, s.c.point) + obj.position.xyz;
                let speed = length(point_velocity(point));
                let dir = rotate(obj.rotation, s.c.dir);
                let dl = length(dir);
                if dl > 0.0 {
                    sum += dir * (abs(speed) / dl);
                }
            }
            prev = next;
        }
        // `num` saturates at 255 as the CPU's u8.
        f = vec4<f32>(f.xyz + sum, min(f.w + f32(countOneBits(mask)), 255.0));
    }
    force[b] = f;
    // Bit k: segment k hit any object so far this step.
    if first_object {
        hit_mask[b] = mask;
    } else {
        hit_mask[b] = hit_mask[b] | mask;
    }
}
