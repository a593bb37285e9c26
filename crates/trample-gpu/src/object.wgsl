// One object as the narrow phase and the contact response see it (prepended
// to narrow_phase.wgsl and contact.wgsl, not a stage of its own): its OBB
// tree, triangles and inside-voxel grid (in the object table, group 1, with
// every other object's: `object.rs`), its pose, and the mesh
// queries of `trample::collision` — the inside test (`exact.rs`,
// `inside_grid.rs`), the closest point of the mesh (`closest_point.rs`) and
// the contact test (`contact.rs`: `penetration`, `push_out_hinted`, the
// latter in two halves). Float op for
// float op as the CPU where it can be (glam's operation order).

// Layout-compatible with `GpuNode` in object.rs.
struct Node {
    center: vec4<f32>,
    axis_u: vec4<f32>,
    axis_v: vec4<f32>,
    axis_w: vec4<f32>,
    // xyz: half extents; w: the thin axis the tilted boxes turn from (0, 1,
    // 2), or -1 for none (`GpuNode::half`).
    half: vec4<f32>,
    // xyz: Eq. 3's EqN normalised when w == 1; else the smallest box axis,
    // pointing up (the fallback of `ObbTree::eqn_direction`).
    dir: vec4<f32>,
    // left child, right child (0xffffffff for a leaf), first triangle, count
    children: vec4<u32>,
    // The reach box (`trample::obb::reach`): the node's axes, this centre
    // and half extents, holding the node's box and every descendant's.
    reach_center: vec4<f32>,
    reach_half: vec4<f32>,
    // The node's deformation velocity in the object's frame, m/s
    // (`ObbTree::node_velocity`; zero for a mesh that does not deform).
    velocity: vec4<f32>,
    // Then five words the walk reads only where it needs them
    // (`hits_tilted`): the node's tilted boxes (`trample::obb::slabs`).
}

// Words of one node in the table: the ten of `Node`, then its five tilted
// boxes (`GpuNode::tilted`).
const NODE_WORDS: u32 = 15u;

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
    // velocity in the object's frame xyz (`LocalMotion`), thickness (m)
    local_velocity: vec4<f32>,
    // angular velocity in the object's frame xyz, sub-step h (s)
    local_angular: vec4<f32>,
    // contact shell (m), press (Eq. 2 factor), unused ×2
    contact: vec4<f32>,
    // 1 + the object's index (its track owner id, 0 past 254), track
    // everywhere (1) or the paper's geometric cells only (0), 1 + the first
    // word of its winding data (0: none), 1 + the first word of its winding
    // grid (0: none), both from its nodes' first word
    extra: vec4<u32>,
    // first word of its nodes, triangles, voxels, pseudo-normals in the table
    base: vec4<u32>,
}

// The object table (`object.rs`): word 0 = (objects, mask words per patch,
// first mask word in the broad phase's lists, 0); object o's parameters at
// words 1 + 16 o ..; its nodes (15 words each), triangles (3 words each),
// pseudo-normals (6 words a triangle, open meshes), winding data (2 words a
// node, from `extra.z`; winding open meshes), winding grid (2 corners a
// word, from `extra.w`) and voxels (4 to a word)
// from the words its `base` names. Floats by their bits.
@group(1) @binding(0) var<storage, read> objects: array<vec4<u32>>;

// The object being tested, loaded by `load_object`.
var<private> obj: ObjectParams;

// The object's header as every branch and loop bound below reads it: a copy
// of `obj.tree` and `obj.field` with `gid.z` added, which is 0 (the kernels
// are always dispatched one workgroup deep in z) but unknown to the driver
// when it compiles. Why: Mesa's lavapipe (22.3, what CI installs) finds the
// uniform values that decide a branch or a loop's trip count, folds them into
// the shader and compiles it again through LLVM at every dispatch, without a
// cache of the variants: 3–13 s a dispatch on the 2-core CI machine when the
// objects were uniforms. The table is a storage buffer now, which the driver
// does not fold; the copies stay as a guard.
var<private> tree: vec4<u32>;
var<private> field: vec4<u32>;
var<private> extra: vec4<u32>;

fn word_f(i: u32) -> vec4<f32> {
    return bitcast<vec4<f32>>(objects[i]);
}

// Number of objects in the table.
fn object_count() -> u32 {
    return objects[0].x;
}

// Makes object o the one the functions below test (`gz` is gid.z: 0).
fn load_object(o: u32, gz: u32) {
    let a = 1u + 16u * o;
    obj = ObjectParams(
        word_f(a), word_f(a + 1u), word_f(a + 2u), word_f(a + 3u), word_f(a + 4u),
        word_f(a + 5u), word_f(a + 6u), word_f(a + 7u), word_f(a + 8u),
        objects[a + 9u], objects[a + 10u], word_f(a + 11u), word_f(a + 12u),
        word_f(a + 13u), objects[a + 14u], objects[a + 15u],
    );
    tree = obj.tree + vec4<u32>(gz);
    field = obj.field + vec4<u32>(gz);
    extra = obj.extra + vec4<u32>(gz);
}

// Node i of the object's tree.
fn node_at(i: u32) -> Node {
    let a = obj.base.x + NODE_WORDS * i;
    return Node(
        word_f(a), word_f(a + 1u), word_f(a + 2u), word_f(a + 3u), word_f(a + 4u),
        word_f(a + 5u), objects[a + 6u], word_f(a + 7u), word_f(a + 8u), word_f(a + 9u),
    );
}

// Corner k of the object's triangle t.
fn corner(t: u32, k: u32) -> vec3<f32> {
    return word_f(obj.base.y + 3u * t + k).xyz;
}

// Pseudo-normal k (edges ab, bc, ca, corners a, b, c) of the object's
// triangle t (`trample::obb::pseudo_normals`; open meshes only).
fn feature_normal(t: u32, k: u32) -> vec3<f32> {
    return word_f(obj.base.w + 6u * t + k).xyz;
}

// True when the object's open mesh takes its inside from its winding
// number (`ObbTree::winds`): its winding data follow (`extra.z`).
fn winds() -> bool {
    return tree.y == 0u && extra.z != 0u;
}

// The area vector of node i of a winding mesh (`ObbTree::dipoles`).
fn dipole(i: u32) -> vec3<f32> {
    return word_f(obj.base.x + extra.z - 1u + 2u * i).xyz;
}

// Node i's dipole centre (xyz) and radius (w) (`winding::Dipole`).
fn dipole_sphere(i: u32) -> vec4<f32> {
    return word_f(obj.base.x + extra.z - 1u + 2u * i + 1u);
}

// The object's inside-grid voxel j (two bits each, 16 to a u32:
// `object.rs`).
fn voxel_at(j: u32) -> u32 {
    let w = objects[obj.base.z + j / 64u][(j / 16u) % 4u];
    return (w >> ((j % 16u) * 2u)) & 3u;
}

const NO_CHILD: u32 = 0xffffffffu;
const NONE: u32 = 0xffffffffu;
// MAX_TREE_DEPTH + 2, as `exact::STACK_SIZE`.
const STACK_SIZE: u32 = 66u;
const MAX_SEGMENTS: u32 = 15u;
const VOXEL_INSIDE: u32 = 1u;
const VOXEL_OUTSIDE: u32 = 0u;
// `exact::INSIDE_RAY`.
const INSIDE_RAY: vec3<f32> = vec3<f32>(0.012345679, -1.0, 0.017320508);
// `contact::CONTACT_TOLERANCE_M`.
const CONTACT_TOLERANCE_M: f32 = 0.003;

// Vector into the box frame: rows u, v, w (glam: transposed `Mat3A` times v).
fn to_box(n: Node, v: vec3<f32>) -> vec3<f32> {
    return vec3<f32>(dot3(n.axis_u.xyz, v), dot3(n.axis_v.xyz, v), dot3(n.axis_w.xyz, v));
}

fn hits_obb(centre: vec3<f32>, half: vec3<f32>, n: Node) -> bool {
    return hits_box(centre, half, n.center.xyz, n.axis_u.xyz, n.axis_v.xyz, n.axis_w.xyz, n.half.xyz);
}

// `trample::obb::slabs`: sin and cos of the tilt (15°), and of the turn (45°).
const TILT_SIN: f32 = 0.25881904;
const TILT_COS: f32 = 0.9659258;
const TURN_45: f32 = 0.70710677;

// `segment_slabs::hits_tilted_local`: segment c ± h in node i's box frame
// against its five tilted boxes (`slabs::TURNS`), each on its own.
fn hits_tilted(c: vec3<f32>, h: vec3<f32>, e: vec3<f32>, i: u32, thin: u32) -> bool {
    let a = obj.base.x + NODE_WORDS * i + 10u;
    for (var j = 0u; j < 5u; j++) {
        var p = 0u;
        var q = 1u;
        var sn = TILT_SIN;
        var cs = TILT_COS;
        if j >= 2u && j < 4u {
            q = 2u;
        }
        if j == 1u || j == 3u {
            sn = -TILT_SIN;
        }
        if j == 4u {
            p = 1u;
            q = 2u;
            sn = TURN_45;
            cs = TURN_45;
        }
        p = (thin + p) % 3u;
        q = (thin + q) % 3u;
        let r = 3u - p - q;
        let f = word_f(a + j);
        let lc = vec3<f32>(cs * c[p] + sn * c[q] - f.x, cs * c[q] - sn * c[p] - f.z, c[r]);
        let lh = vec3<f32>(cs * h[p] + sn * h[q], cs * h[q] - sn * h[p], h[r]);
        if !hits_box_local(lc, lh, vec3<f32>(f.y, f.w, e[r])) {
            return false;
        }
    }
    return true;
}

// `segment_slabs::segment_hits_node`: the node's box, then its tilted boxes
// (none where `half.w` < 0).
fn hits_node(centre: vec3<f32>, half: vec3<f32>, n: Node, i: u32) -> bool {
    let d = centre - n.center.xyz;
    let c = vec3<f32>(dot3(n.axis_u.xyz, d), dot3(n.axis_v.xyz, d), dot3(n.axis_w.xyz, d));
    let h = vec3<f32>(dot3(n.axis_u.xyz, half), dot3(n.axis_v.xyz, half), dot3(n.axis_w.xyz, half));
    if !hits_box_local(c, h, n.half.xyz) {
        return false;
    }
    return n.half.w < 0.0 || hits_tilted(c, h, n.half.xyz, i, u32(n.half.w));
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

// `Pose::to_world`: position + rotation p.
fn to_world(p: vec3<f32>) -> vec3<f32> {
    return obj.position.xyz + rotate(obj.rotation, p);
}

// `Pose::point_velocity` of a world point: v + ω × (p − position).
fn point_velocity(p: vec3<f32>) -> vec3<f32> {
    return obj.velocity.xyz + cross3(obj.angular_velocity.xyz, p - obj.position.xyz);
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
    let n = node_at(i);
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

// `segment_triangle::segment_crosses_triangle_interior`, in f32 (the CPU
// works in f64; WGSL has no f64): Möller–Trumbore, strict interior.
fn crosses_triangle(p0: vec3<f32>, p1: vec3<f32>, t: u32) -> bool {
    let a = corner(t, 0u);
    let b = corner(t, 1u);
    let c = corner(t, 2u);
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
    let root = node_at(0u);
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
        let n = node_at(i);
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

// `InsideGrid::classify`: 1 inside, 0 outside, 2 the exact test must decide.
fn grid_classify(p: vec3<f32>) -> u32 {
    let side = field.w;
    if side == 0u {
        return 2u;
    }
    let dd = p - obj.grid_center.xyz;
    let q = vec3<f32>(dot3(dd, obj.grid_u.xyz), dot3(dd, obj.grid_v.xyz), dot3(dd, obj.grid_w.xyz));
    let h = obj.grid_half.xyz;
    let g = (q + h) / (2.0 * h) * f32(side);
    if any(g < vec3<f32>(0.0)) || any(g >= vec3<f32>(f32(side))) {
        return 0u;
    }
    let v = vec3<u32>(g);
    let voxel = voxel_at((v.z * side + v.y) * side + v.x);
    if voxel == VOXEL_INSIDE {
        return 1u;
    }
    if voxel == VOXEL_OUTSIDE {
        return 0u;
    }
    return 2u;
}

// `exact::point_inside`: the voxel grid first, the ray where it cannot tell.
fn point_inside(p: vec3<f32>) -> bool {
    if tree.y == 0u {
        return false;
    }
    let known = grid_classify(p);
    if known != 2u {
        return known == 1u;
    }
    return inside_by_ray(p);
}

// `closest_point::closest_point_on_triangle_region`: the point and its
// feature (edges ab, bc, ca = 0, 1, 2, corners a, b, c = 3, 4, 5, face 6).
struct TrianglePoint {
    point: vec3<f32>,
    region: u32,
}

const FACE: u32 = 6u;

fn closest_on_triangle(p: vec3<f32>, t: u32) -> TrianglePoint {
    let a = corner(t, 0u);
    let b = corner(t, 1u);
    let c = corner(t, 2u);
    let ab = b - a;
    let ac = c - a;
    let ap = p - a;
    let d1 = dot3(ab, ap);
    let d2 = dot3(ac, ap);
    if d1 <= 0.0 && d2 <= 0.0 {
        return TrianglePoint(a, 3u);
    }
    let bp = p - b;
    let d3 = dot3(ab, bp);
    let d4 = dot3(ac, bp);
    if d3 >= 0.0 && d4 <= d3 {
        return TrianglePoint(b, 4u);
    }
    let vc = d1 * d4 - d3 * d2;
    if vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0 {
        let v = d1 / (d1 - d3);
        return TrianglePoint(a + ab * v, 0u);
    }
    let cp = p - c;
    let d5 = dot3(ab, cp);
    let d6 = dot3(ac, cp);
    if d6 >= 0.0 && d5 <= d6 {
        return TrianglePoint(c, 5u);
    }
    let vb = d5 * d2 - d1 * d6;
    if vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0 {
        let w = d2 / (d2 - d6);
        return TrianglePoint(a + ac * w, 2u);
    }
    let va = d3 * d6 - d5 * d4;
    if va <= 0.0 && (d4 - d3) >= 0.0 && (d5 - d6) >= 0.0 {
        let w = (d4 - d3) / ((d4 - d3) + (d5 - d6));
        return TrianglePoint(b + (c - b) * w, 1u);
    }
    let denom = 1.0 / (va + vb + vc);
    let v = vb * denom;
    let w = vc * denom;
    return TrianglePoint(a + ab * v + ac * w, FACE);
}

// glam `Vec3::cross` (scalar): a.y b.z − b.y a.z, …
fn cross_scalar(a: vec3<f32>, b: vec3<f32>) -> vec3<f32> {
    return vec3<f32>(a.y * b.z - b.y * a.z, a.z * b.x - b.z * a.x, a.x * b.y - b.x * a.y);
}

// `closest_point::SurfacePoint`; `found` false when there is none.
struct SurfacePoint {
    point: vec3<f32>,
    distance_sq: f32,
    normal: vec3<f32>,
    face: bool,
    found: bool,
    triangle: u32,
    region: u32,
}

// `winding::FAR_LO`, `FAR_HI`, `WINDING_INSIDE_LO`, `_HI`, 1 / 4π.
const FAR_LO: f32 = 2.0;
const FAR_HI: f32 = 3.0;
const WINDING_INSIDE_LO: f32 = 0.3;
const WINDING_INSIDE_HI: f32 = 0.5;
const INV_4PI: f32 = 0.07957747;
// `winding::EXACT_TRIANGLES`: an opened node of this many triangles or
// fewer is summed exactly.
const EXACT_TRIANGLES: u32 = 4u;

// `winding::solid_angle`: the signed solid angle triangle t subtends at p.
fn solid_angle(t: u32, p: vec3<f32>) -> f32 {
    let a = corner(t, 0u) - p;
    let b = corner(t, 1u) - p;
    let c = corner(t, 2u) - p;
    let la = sqrt(dot3(a, a));
    let lb = sqrt(dot3(b, b));
    let lc = sqrt(dot3(c, c));
    let num = dot3(a, cross_scalar(b, c));
    let den = la * lb * lc + dot3(a, b) * lc + dot3(a, c) * lb + dot3(b, c) * la;
    return 2.0 * atan2_poly(num, den);
}

// `winding::ATAN_POLY` and `winding::atan2`: the polynomial atan2 both
// paths share (a GPU's own atan2 may stray by thousands of ulps).
const ATAN_C1: f32 = 0.9999794;
const ATAN_C3: f32 = -0.33262417;
const ATAN_C5: f32 = 0.19354387;
const ATAN_C7: f32 = -0.11643311;
const ATAN_C9: f32 = 0.05265343;
const ATAN_C11: f32 = -0.011721225;
const HALF_PI: f32 = 1.5707964;
const PI: f32 = 3.1415927;

fn atan2_poly(y: f32, x: f32) -> f32 {
    let ax = abs(x);
    let ay = abs(y);
    let lo = min(ax, ay);
    let hi = max(ax, ay);
    var a = 0.0;
    if hi > 0.0 {
        a = lo / hi;
    }
    let s = a * a;
    var r = a * (ATAN_C1 + s * (ATAN_C3 + s * (ATAN_C5 + s * (ATAN_C7 + s * (ATAN_C9 + s * ATAN_C11)))));
    if ay > ax {
        r = HALF_PI - r;
    }
    if x < 0.0 {
        r = PI - r;
    }
    if y < 0.0 {
        r = -r;
    }
    return r;
}

// `winding::winding_number` of the loaded object's winding mesh at p
// (object frame): down the tree, a node counting as its dipole from FAR_HI
// times its sphere's radius, opened nearer than FAR_LO, blended between.
fn winding_number(p: vec3<f32>) -> f32 {
    if tree.x == 0u || !all(abs(p) < vec3<f32>(3.0e38)) {
        return 0.0;
    }
    var nodes: array<u32, STACK_SIZE>;
    var weights: array<f32, STACK_SIZE>;
    nodes[0] = 0u;
    weights[0] = 1.0;
    var len = 1u;
    var sum = 0.0;
    while len > 0u {
        len -= 1u;
        let i = nodes[len];
        let weight = weights[len];
        if i >= tree.x {
            continue;
        }
        let n = node_at(i);
        let sphere = dipole_sphere(i);
        let to_centre = sphere.xyz - p;
        let r = sqrt(dot3(to_centre, to_centre));
        let radius = sphere.w;
        var far = 0.0;
        if r > 0.0 && r >= FAR_HI * radius {
            far = 1.0;
        } else if r > FAR_LO * radius {
            far = (r / radius - FAR_LO) / (FAR_HI - FAR_LO);
        }
        if far > 0.0 {
            sum += weight * far * (dot3(dipole(i), to_centre) / (r * r * r)) * INV_4PI;
        }
        let near = weight * (1.0 - far);
        if !(near > 0.0) {
            continue;
        }
        let l = n.children.x;
        let rr = n.children.y;
        if l == NO_CHILD || n.children.w <= EXACT_TRIANGLES || l <= i || rr <= i || len + 2u > STACK_SIZE {
            var exact = 0.0;
            for (var t = n.children.z; t < n.children.z + n.children.w; t++) {
                exact += solid_angle(t, p);
            }
            sum += near * exact * INV_4PI;
        } else {
            nodes[len] = rr;
            weights[len] = near;
            nodes[len + 1u] = l;
            weights[len + 1u] = near;
            len += 2u;
        }
    }
    return sum;
}

// Corner k of the loaded object's winding grid: (tree sum, trust).
fn winding_corner(k: u32) -> vec2<f32> {
    let w = word_f(obj.base.x + extra.w - 1u + k / 2u);
    return select(w.xy, w.zw, (k & 1u) == 1u);
}

fn lerp2(a: vec2<f32>, b: vec2<f32>, t: f32) -> vec2<f32> {
    return a + (b - a) * t;
}

// `winding_grid::winding_at`: the winding grid's trilinear value where its
// trust is whole, blended with the tree sum by the trust where it is
// partial, the tree sum alone elsewhere (`WindingGrid::sample`: the box in
// `grid_*`, the voxels along u, v, w in their w lanes).
fn winding_at(p: vec3<f32>) -> f32 {
    // The grid's trust where it is partial and its sample: the tree sum
    // below has one call site (a shader compiler inlines each call).
    var trust = 0.0;
    var sampled = 0.0;
    if extra.w != 0u {
        let n = vec3<f32>(obj.grid_u.w, obj.grid_v.w, obj.grid_w.w);
        let dd = p - obj.grid_center.xyz;
        let q = vec3<f32>(dot3(dd, obj.grid_u.xyz), dot3(dd, obj.grid_v.xyz), dot3(dd, obj.grid_w.xyz));
        let h = obj.grid_half.xyz;
        let g = (q + h) / (2.0 * h) * n;
        if all(g >= vec3<f32>(0.0)) && all(g <= n) {
            let i = min(floor(g), n - vec3<f32>(1.0));
            let f = g - i;
            let iu = vec3<u32>(i);
            let sx = u32(n.x) + 1u;
            let sy = sx * (u32(n.y) + 1u);
            let k = iu.z * sy + iu.y * sx + iu.x;
            let x00 = lerp2(winding_corner(k), winding_corner(k + 1u), f.x);
            let x10 = lerp2(winding_corner(k + sx), winding_corner(k + sx + 1u), f.x);
            let x01 = lerp2(winding_corner(k + sy), winding_corner(k + sy + 1u), f.x);
            let x11 = lerp2(winding_corner(k + sy + sx), winding_corner(k + sy + sx + 1u), f.x);
            let s = lerp2(lerp2(x00, x10, f.y), lerp2(x01, x11, f.y), f.z);
            if s.y >= 1.0 {
                return s.x;
            }
            if s.y > 0.0 {
                trust = s.y;
                sampled = s.x;
            }
        }
    }
    let w = winding_number(p);
    if trust > 0.0 {
        return trust * sampled + (1.0 - trust) * w;
    }
    return w;
}

// `winding::ROOT_FADE_M`.
const ROOT_FADE_M: f32 = 0.01;

// `winding::root_fade`: how far inside the root box p lies, over
// ROOT_FADE_M, clamped to [0, 1].
fn root_fade(p: vec3<f32>) -> f32 {
    let n = node_at(0u);
    let q = abs(to_box(n, p - n.center.xyz));
    let gap = n.half.xyz - q;
    let f = min(min(gap.x, gap.y), gap.z) / ROOT_FADE_M;
    if f != f {
        return 0.0;
    }
    return clamp(f, 0.0, 1.0);
}

// `winding::inside_factor`.
fn inside_factor(w: f32) -> f32 {
    let s = (w - WINDING_INSIDE_LO) / (WINDING_INSIDE_HI - WINDING_INSIDE_LO);
    if s != s {
        return 0.0;
    }
    return clamp(s, 0.0, 1.0);
}

// `SurfacePoint::side_normal`: the face normal inside a face, else the
// pseudo-normal of the edge or corner (open meshes; a closed one has none:
// its pseudo-normals end where they start, at its voxels).
fn side_normal(s: SurfacePoint) -> vec3<f32> {
    if s.region == FACE || obj.base.w == obj.base.z {
        return s.normal;
    }
    return feature_normal(s.triangle, s.region);
}

// Squared distance from p to node i's box.
fn distance_sq_to_box(p: vec3<f32>, i: u32) -> f32 {
    let n = node_at(i);
    let q = to_box(n, p - n.center.xyz);
    let d = max(abs(q) - n.half.xyz, vec3<f32>(0.0));
    return dot3(d, d);
}

// The stack of `closest_point_within_sq`: (node, bits of its box's squared
// distance, measured once when it is pushed, as the CPU's walk keeps it).
// Module scope, as narrow_phase.wgsl's `walk_stack` (WGSL zeroes a
// function's variables at every call); a narrow-phase walk that asks a
// depth uses this one, not its own.
var<private> cp_stack: array<vec2<u32>, STACK_SIZE>;

// x · x at run time (3e38 squared is infinity; a constant would not compile).
fn squared(x: f32) -> f32 {
    return x * x;
}

// `closest_point::NEAR_POINTS_MAX`.
const NEAR_POINTS_MAX: u32 = 8u;

// `closest_point::NearPoints`: (point, squared distance) and triangle, the
// first `near_len` set (module scope: not zeroed per call).
var<private> near_points: array<vec4<f32>, NEAR_POINTS_MAX>;
var<private> near_tris: array<u32, NEAR_POINTS_MAX>;
var<private> near_len: u32;

// (d_sq, triangle) of a kept point before (a_d, a_t)?
fn near_before(a_d: f32, a_t: u32, b_d: f32, b_t: u32) -> bool {
    return a_d < b_d || (a_d == b_d && a_t < b_t);
}

// `NearPoints::add`: when all places are taken, the farthest (ties: the
// higher triangle) gives its place to a nearer point.
fn add_near(q: vec3<f32>, d_sq: f32, tri: u32) {
    if near_len < NEAR_POINTS_MAX {
        near_points[near_len] = vec4<f32>(q, d_sq);
        near_tris[near_len] = tri;
        near_len += 1u;
        return;
    }
    var far = 0u;
    for (var k = 1u; k < NEAR_POINTS_MAX; k++) {
        if near_before(near_points[far].w, near_tris[far], near_points[k].w, near_tris[k]) {
            far = k;
        }
    }
    if near_before(d_sq, tri, near_points[far].w, near_tris[far]) {
        near_points[far] = vec4<f32>(q, d_sq);
        near_tris[far] = tri;
    }
}

// `closest_point::closest_point_within_sq`: branch and bound, nearer child
// first, each box's distance measured once (when it is pushed); ties keep
// the first found. `max_sq`: only points within its square root count.
fn closest_point_within_sq(p: vec3<f32>, max_sq: f32) -> SurfacePoint {
    return closest_walk(p, max_sq, -1.0);
}

// `closest_point::walk`: with `reach` ≥ 0 (`closest_point_and_near`),
// boxes are skipped only beyond `reach` past the best distance and every
// point within that goes to `near_points` (cleared first).
fn closest_walk(p: vec3<f32>, max_sq: f32, reach: f32) -> SurfacePoint {
    var best = SurfacePoint(vec3<f32>(0.0), 0.0, vec3<f32>(0.0), false, false, 0u, 0u);
    var best_sq = max_sq;
    var bound_sq = max_sq;
    near_len = 0u;
    let count = tree.x;
    if count == 0u {
        return best;
    }
    cp_stack[0] = vec2<u32>(0u, bitcast<u32>(distance_sq_to_box(p, 0u)));
    var len = 1u;
    while len > 0u {
        len -= 1u;
        let i = cp_stack[len].x;
        // The bound may have shrunk since the node was pushed.
        if i >= count || bitcast<f32>(cp_stack[len].y) > bound_sq {
            continue;
        }
        let n = node_at(i);
        let l = n.children.x;
        let r = n.children.y;
        if l == NO_CHILD || l <= i || r <= i || len + 2u > STACK_SIZE {
            for (var t = n.children.z; t < n.children.z + n.children.w; t++) {
                let c = closest_on_triangle(p, t);
                let dv = c.point - p;
                let d = dot3(dv, dv);
                if d <= best_sq && (!best.found || d < best_sq) {
                    best_sq = d;
                    // The normal is that of the final triangle, taken once
                    // after the walk.
                    best = SurfacePoint(c.point, d, vec3<f32>(0.0), c.region == FACE, true, t, c.region);
                    bound_sq = d;
                    if reach >= 0.0 {
                        bound_sq = (sqrt(d) + reach) * (sqrt(d) + reach);
                    }
                }
                if reach >= 0.0 && d <= bound_sq {
                    add_near(c.point, d, t);
                }
            }
        } else {
            var dl = 3.0e38;
            var dr = 3.0e38;
            if l < count {
                dl = distance_sq_to_box(p, l);
            }
            if r < count {
                dr = distance_sq_to_box(p, r);
            }
            var near = vec2<u32>(l, bitcast<u32>(dl));
            var far = vec2<u32>(r, bitcast<u32>(dr));
            if dr < dl {
                near = vec2<u32>(r, bitcast<u32>(dr));
                far = vec2<u32>(l, bitcast<u32>(dl));
            }
            // Without `reach` the bound only shrinks, so a child beyond it
            // now would be skipped when popped: it is not pushed. (With
            // `reach` the bound may grow past max_sq at the first hit.)
            if !(reach < 0.0 && bitcast<f32>(far.y) > bound_sq) {
                cp_stack[len] = far;
                len += 1u;
            }
            if !(reach < 0.0 && bitcast<f32>(near.y) > bound_sq) {
                cp_stack[len] = near;
                len += 1u;
            }
        }
    }
    if best.found {
        let t = best.triangle;
        let a = corner(t, 0u);
        let nrm = cross_scalar(corner(t, 1u) - a, corner(t, 2u) - a);
        let nl = sqrt(dot3(nrm, nrm));
        if nl > 0.0 {
            best.normal = nrm * (1.0 / nl);
        }
    }
    return best;
}

// `contact::surface_and_side`: the closest surface point measured (found
// false when none was needed: a voxel known outside, an open mesh's
// winding factor 0, nothing within the open depth or the bound) and how
// much p is inside (1 or 0 for a closed mesh, the winding number's factor
// for an open one). `bound_sq`: a squared distance from p to some point of
// the mesh, or infinity (the same answer).
struct Side {
    s: SurfacePoint,
    inside: f32,
}

// No surface point, outside: what `surface_and_side_near` answers without
// a walk.
fn no_side() -> Side {
    return Side(SurfacePoint(vec3<f32>(0.0), 0.0, vec3<f32>(0.0), false, false, 0u, 0u), 0.0);
}

fn surface_and_side(p: vec3<f32>, open_depth: f32, bound_sq: f32) -> Side {
    return surface_and_side_near(p, open_depth, bound_sq, -1.0);
}

// `surface_and_side` with `near` (`reach` ≥ 0: PUSH_BLEND_M): the walk also
// keeps the points within `reach` of the closest in `near_points`.
fn surface_and_side_near(p: vec3<f32>, open_depth: f32, bound_sq: f32, reach: f32) -> Side {
    var out = no_side();
    if tree.x == 0u {
        return out;
    }
    // The three kinds of mesh decide whether and how far to walk first, so
    // that `closest_walk` has one call site: shader compilers inline every
    // call, and three copies of the walk in each copy of this function made
    // the narrow phase's and the contact's pipelines take a minute each to
    // compile on llvmpipe (BENCHMARKS.md, "Session 54").
    var walk_sq = bound_sq;
    // The closed mesh's grid answer (1: inside, 2: ask the surface), or
    // SIDE_WINDS / SIDE_SHEET for an open mesh.
    var known = 0u;
    var winding = 0.0;
    if tree.y != 0u {
        known = grid_classify(p);
        if known == 0u {
            return out;
        }
    } else {
        if !(open_depth >= 0.0) {
            return out;
        }
        if winds() {
            // Outside (factor 0) needs no closest point; no depth bound.
            let fade = root_fade(p);
            if !(fade > 0.0) {
                return out;
            }
            winding = inside_factor(winding_at(p)) * fade;
            if !(winding > 0.0) {
                return out;
            }
            known = SIDE_WINDS;
        } else {
            walk_sq = min(open_depth * open_depth, bound_sq);
            known = SIDE_SHEET;
        }
    }
    out.s = closest_walk(p, walk_sq, reach);
    if known == SIDE_WINDS {
        out.inside = winding;
        return out;
    }
    if known == SIDE_SHEET {
        out.inside = select(0.0, 1.0, out.s.found && dot3(p - out.s.point, side_normal(out.s)) < 0.0);
        return out;
    }
    if !out.s.found {
        return out;
    }
    var inside = known == 1u;
    if !inside {
        if out.s.face {
            inside = dot3(p - out.s.point, out.s.normal) < 0.0;
        } else {
            inside = inside_by_ray(p);
        }
    }
    out.inside = select(0.0, 1.0, inside);
    return out;
}

// `surface_and_side_near`'s kinds of open mesh (a closed mesh's are the
// grid's answers, 1 and 2).
const SIDE_WINDS: u32 = 3u;
const SIDE_SHEET: u32 = 4u;

// `contact::penetration`: (surface point, depth) in xyz and w when p is
// inside the object, w < 0 when it is outside (a winding mesh's depth: the
// distance times its winding factor). `open_depth`: how far behind an
// open mesh a point still counts as inside by the sheet rule.
fn penetration(p: vec3<f32>, open_depth: f32) -> vec4<f32> {
    return penetration_of(surface_and_side(p, open_depth, squared(3.0e38)));
}

// `penetration` from the point's `surface_and_side`.
fn penetration_of(side: Side) -> vec4<f32> {
    if !side.s.found || !(side.inside > 0.0) {
        return vec4<f32>(0.0, 0.0, 0.0, -1.0);
    }
    return vec4<f32>(side.s.point, sqrt(side.s.distance_sq) * side.inside);
}

// `contact::way_out`: the unit way out (`push_direction`, else the way to
// the closest point) in xyz and the depth in w when p is inside the
// object; w < 0 when it is outside or has no way out.
fn way_out(p: vec3<f32>, open_depth: f32) -> vec4<f32> {
    let side = surface_and_side_near(p, open_depth, squared(3.0e38), PUSH_BLEND_M);
    if !side.s.found || !(side.inside > 0.0) {
        return vec4<f32>(0.0, 0.0, 0.0, -1.0);
    }
    let depth = sqrt(side.s.distance_sq);
    let away = side.s.point - p;
    let rcp = 1.0 / sqrt(dot3(away, away));
    var fallback = vec3<f32>(0.0);
    if rcp < 3.0e38 && rcp > 0.0 {
        fallback = away * rcp;
    }
    let way = push_direction(p, depth, fallback);
    if all(way == vec3<f32>(0.0)) {
        return vec4<f32>(0.0, 0.0, 0.0, -1.0);
    }
    return vec4<f32>(way, depth * side.inside);
}

// `contact::push_out_hinted` in two halves around the walk (the contact
// kernel asks `surface_and_side_near` at one call site for this and for
// `pinned`): where p must go to lie no deeper than the contact tolerance
// (`to`, w = 1 when it must move, 0 when it stays), trying triangle `hint`
// first (NONE: none): within the tolerance of it, p stays without a walk;
// else the walk looks no farther than it. `hint` comes back as the
// triangle of the closest point measured (kept when none was). The same
// answers as without a hint.
struct Pushed {
    to: vec4<f32>,
    hint: u32,
}

// The first half: how far (squared) the walk for p must look, or -1 when
// p stays without one (within the tolerance of its hint).
fn push_bound_sq(p: vec3<f32>, hint: u32) -> f32 {
    var bound_sq = squared(3.0e38);
    if hint != NONE {
        let c = closest_on_triangle(p, hint);
        let dv = c.point - p;
        let d = dot3(dv, dv);
        if sqrt(d) <= CONTACT_TOLERANCE_M {
            return -1.0;
        }
        // No farther than the hint and the blend past it (same answer).
        bound_sq = (sqrt(d) + PUSH_BLEND_M) * (sqrt(d) + PUSH_BLEND_M);
    }
    return bound_sq;
}

// The second half: the answer from `surface_and_side_near(p, open_depth,
// push_bound_sq(p, hint), PUSH_BLEND_M)`, or from `no_side()` where that
// bound is -1 (p stays).
fn push_from(p: vec3<f32>, side: Side, hint: u32) -> Pushed {
    if !side.s.found {
        return Pushed(vec4<f32>(p, 0.0), hint);
    }
    let depth = sqrt(side.s.distance_sq);
    // An open mesh's depth is the distance times how much p is inside.
    let deep = depth * side.inside;
    if deep > CONTACT_TOLERANCE_M {
        let way = push_direction(p, depth, (side.s.point - p) / depth);
        return Pushed(vec4<f32>(p + way * (deep - CONTACT_TOLERANCE_M), 1.0), side.s.triangle);
    }
    return Pushed(vec4<f32>(p, 0.0), side.s.triangle);
}

// `contact::PUSH_BLEND_M`.
const PUSH_BLEND_M: f32 = 0.001;

// `contact::push_direction`: the unit way out of p, `depth` from its
// closest surface point — the ways to the points the walk kept
// (`near_points`), weighted 1 − (distance − depth) / PUSH_BLEND_M, summed
// in triangle order; `fallback` where the sum vanishes.
fn push_direction(p: vec3<f32>, depth: f32, fallback: vec3<f32>) -> vec3<f32> {
    if !(depth > 0.0) {
        return fallback;
    }
    var sum = vec3<f32>(0.0);
    // In ascending triangle order (`NearPoints::in_triangle_order`).
    let count = min(near_len, NEAR_POINTS_MAX);
    var last = 0u;
    for (var n = 0u; n < count; n++) {
        var k = NEAR_POINTS_MAX;
        for (var j = 0u; j < count; j++) {
            if (n == 0u || near_tris[j] > last) && (k == NEAR_POINTS_MAX || near_tris[j] < near_tris[k]) {
                k = j;
            }
        }
        last = near_tris[k];
        let dv = near_points[k].xyz - p;
        let d = sqrt(near_points[k].w);
        let w = min(1.0 - (d - depth) / PUSH_BLEND_M, 1.0);
        if w > 0.0 && d > 0.0 {
            sum += dv * (w / d);
        }
    }
    // glam `Vec3::try_normalize`.
    let rcp = 1.0 / sqrt(dot3(sum, sum));
    if rcp < 3.0e38 && rcp > 0.0 {
        return sum * rcp;
    }
    return fallback;
}
