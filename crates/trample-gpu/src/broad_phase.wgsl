// Broad phase (paper §4 stage 2, DESIGN §4.1): which patches the objects
// may touch. Each object's rectangle of candidate patches comes from the
// CPU's grid lookup (`trample::collision::patch_rect`, in `rects`); one
// thread per (object, candidate patch) tests the patch's AABB (blade
// heights included) against the object's root box in the world by the
// separating axis theorem on the 15 axes, as
// `trample::collision::obb_overlaps_aabb`, with twice its slack (the GPU's
// list must hold every patch the CPU's does). A hit patch is appended to
// its chunk's list by the first thread to mark it; `args` then turns each
// chunk's count into the indirect dispatch of the narrow phase.
//
// `lists` layout: the list of chunk i starts at entry `first patch of chunk
// i`; entry `patches + i` is its count (the narrow phase finds it through
// its chunk uniform); entry `patches + chunks + p` marks patch p listed;
// the `mask words` entries from `2 patches + chunks + p · mask words` hold
// the objects whose box meets patch p, bit o % 32 of word o / 32 (the
// narrow phase and the contact response test only those, in order).

// Layout-compatible with `GpuWorldObb` in cells.rs.
struct WorldObb {
    center: vec4<f32>,
    u: vec4<f32>,
    v: vec4<f32>,
    w: vec4<f32>,
    half: vec4<f32>,
}

// `BroadParams`: broad_params.wgsl, prepended.

@group(0) @binding(0) var<uniform> broad: BroadParams;
@group(0) @binding(1) var<storage, read> world_roots: array<WorldObb>;
// Per patch: (min xyz, 0), (max xyz, 0).
@group(0) @binding(2) var<storage, read> patch_aabbs: array<vec4<f32>>;
@group(0) @binding(3) var<storage, read_write> lists: array<atomic<u32>>;
// Per chunk: workgroups x, y, z of its narrow-phase dispatch.
@group(0) @binding(4) var<storage, read_write> args: array<u32>;
// `GpuPatchRect` in broad_phase.rs: entry 0 = (candidates, objects, 0, 0);
// entry 1 + i = object i's (x0, z0, width, first candidate). In a storage
// buffer, not a uniform: it changes every sub-step, and lavapipe recompiles
// a kernel whose branches read a changed uniform (see narrow_phase.wgsl).
@group(0) @binding(5) var<storage, read> rects: array<vec4<u32>>;

// `broad_phase::PARALLEL_PAD`.
const PARALLEL_PAD: f32 = 1e-6;
// 2 × `broad_phase::REL_SLACK`.
const REL_SLACK: f32 = 2e-5;

fn separated(dist: f32, ra: f32, rb: f32) -> bool {
    return abs(dist) > (ra + rb) * (1.0 + REL_SLACK);
}

// `broad_phase::obb_overlaps_aabb`.
fn overlaps(o: WorldObb, lo: vec3<f32>, hi: vec3<f32>) -> bool {
    // Function variables: indexed with loop counters below.
    var a = (hi - lo) * 0.5;
    var b = o.half.xyz;
    var t = o.center.xyz - (lo + hi) * 0.5;
    // CPU r[i][j] = e_i · B_j is r[j][i] here: column j is axis j.
    var r = mat3x3<f32>(o.u.xyz, o.v.xyz, o.w.xyz);
    let pad = vec3<f32>(PARALLEL_PAD);
    var ar = mat3x3<f32>(abs(r[0]) + pad, abs(r[1]) + pad, abs(r[2]) + pad);
    // AABB axes e_i.
    for (var i = 0; i < 3; i++) {
        let rb = b.x * ar[0][i] + b.y * ar[1][i] + b.z * ar[2][i];
        if separated(t[i], a[i], rb) {
            return false;
        }
    }
    // OBB axes B_j.
    for (var j = 0; j < 3; j++) {
        let ra = a.x * ar[j][0] + a.y * ar[j][1] + a.z * ar[j][2];
        let dist = t.x * r[j][0] + t.y * r[j][1] + t.z * r[j][2];
        if separated(dist, ra, b[j]) {
            return false;
        }
    }
    // Cross products e_i × B_j.
    for (var i = 0; i < 3; i++) {
        let i1 = (i + 1) % 3;
        let i2 = (i + 2) % 3;
        for (var j = 0; j < 3; j++) {
            let j1 = (j + 1) % 3;
            let j2 = (j + 2) % 3;
            let ra = a[i1] * ar[j][i2] + a[i2] * ar[j][i1];
            let rb = b[j1] * ar[j2][i] + b[j2] * ar[j1][i];
            let dist = t[i2] * r[j][i1] - t[i1] * r[j][i2];
            if separated(dist, ra, rb) {
                return false;
            }
        }
    }
    return true;
}

// One thread per (object, candidate patch), objects in order, each
// object's rectangle row by row.
@compute @workgroup_size(64)
fn candidates(@builtin(global_invocation_id) gid: vec3<u32>, @builtin(num_workgroups) groups: vec3<u32>) {
    let t = gid.x + gid.y * groups.x * 64u;
    let head = rects[0];
    if t >= head.x {
        return;
    }
    // The object whose candidates hold t: the last whose first is ≤ t
    // (an object without candidates shares its first with the next one).
    var lo = 0u;
    var hi = head.y;
    while hi - lo > 1u {
        let mid = (lo + hi) / 2u;
        if rects[1u + mid].w <= t {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    let r = rects[1u + lo];
    let local = t - r.w;
    let width = max(r.z, 1u);
    let p = (r.y + local / width) * broad.counts.w + r.x + local % width;
    if p >= broad.counts.x || !overlaps(world_roots[lo], patch_aabbs[2u * p].xyz, patch_aabbs[2u * p + 1u].xyz) {
        return;
    }
    let words = broad.dispatch.z;
    let masks = 2u * broad.counts.x + broad.counts.z + p * words;
    atomicOr(&lists[masks + lo / 32u], 1u << (lo % 32u));
    if atomicExchange(&lists[broad.counts.x + broad.counts.z + p], 1u) != 0u {
        return; // listed by another object
    }
    let per = max(broad.counts.y, 1u);
    let chunk = p / per;
    let slot = atomicAdd(&lists[broad.counts.x + chunk], 1u);
    atomicStore(&lists[chunk * per + slot], p);
}

// One thread per chunk: its count of listed patches × blades per patch as
// a grid of workgroups of 64 (x at most the device's limit).
@compute @workgroup_size(64)
fn dispatch_args(@builtin(global_invocation_id) gid: vec3<u32>) {
    let c = gid.x;
    if c >= broad.counts.z {
        return;
    }
    let threads = atomicLoad(&lists[broad.counts.x + c]) * broad.dispatch.x;
    let groups = (threads + 63u) / 64u;
    let max_x = max(broad.dispatch.y, 1u);
    let x = min(groups, max_x);
    let y = (groups + max_x - 1u) / max_x;
    args[3u * c] = x;
    args[3u * c + 1u] = y;
    args[3u * c + 2u] = 1u;
}
