// Geometric blades (DESIGN §8): one instance per blade, a two-sided tapered
// strip of 2·(n+1) vertices pulled from the blade vertex buffer, laid out as
// the core stores it over a chunk of blades: vertex k of blade b at
// pos[k * blades + (b - first)] (Eq. 1). The CPU path draws the whole field
// as one chunk; the GPU path (trample-gpu) one draw per chunk, straight from
// its buffers.

// x: width (m), y: tint in [0, 1).
@group(1) @binding(0) var<storage, read> pos: array<vec4<f32>>;
@group(1) @binding(1) var<storage, read> shape: array<vec2<f32>>;
// x: blade index, y: debug colour (RGBA8, 0 = shade normally).
@group(1) @binding(2) var<storage, read> instances: array<vec2<u32>>;
// x: the chunk's first blade (and its first instance), y: its blades.
@group(1) @binding(3) var<uniform> chunk: vec4<u32>;

struct VertexOut {
    @builtin(position) clip: vec4<f32>,
    @location(0) world: vec3<f32>,
    @location(1) normal: vec3<f32>,
    @location(2) albedo: vec3<f32>,
    // 0 at the root, 1 at the tip.
    @location(3) along: f32,
    // The sun's visibility (globals.wgsl), per vertex: blades are thin,
    // and a lookup per fragment costs llvmpipe about a sixth of the frame.
    @location(4) sun: f32,
}

// Vertex k of the chunk's blade l as drawn: the stored vertex moved by the
// wind (draw time only, trample::blade_shape; calm leaves it), given the
// blade's stored root and its wind tip offset, which every vertex of the
// blade shares (computed once per invocation, not once per vertex read).
// Vertex 0 is the root itself.
fn drawn_vertex(k: u32, l: u32, root: vec3<f32>, tip: vec3<f32>) -> vec3<f32> {
    return blade_wind_vertex(root, pos[k * chunk.y + l].xyz, k, globals.params.y, tip);
}
// Render density beyond the simulation's (issue 15 item 2): each simulated
// blade is drawn `copies` times (globals.gusts.z, ≥ 1; instance ii is copy
// ii % copies of listed blade ii / copies). Copy 0 is the simulated blade;
// copy j > 0 is its bent shape (so it follows the deformation: a track, the
// wind) moved by a fixed random offset within the blade spacing
// (globals.sky_zenith.w, m), with its own facing, height and tint. Copies
// thin out with the root's distance d from the eye: copy j is drawn to
// reach_j = near_m · (1 − (j − 1) / copies), near_m = min(globals.gusts.w,
// NEAR_OF_GEOMETRY · geometry_m), and shrinks to its root over the last
// fifth of that, so nothing pops: the drawn density is back to the
// simulated one well before cells change level (the copies would vanish
// with their blades there).
fn drawn_copies() -> u32 {
    return max(u32(globals.gusts.z), 1u);
}

// How much of copy `copy` (≥ 1) of `copies` shows at distance `d` (m):
// 1 near, 0 past its reach, linear between.
const NEAR_OF_GEOMETRY: f32 = 0.6;

fn copy_scale(copy: u32, copies: u32, d: f32) -> f32 {
    let near = min(globals.gusts.w, NEAR_OF_GEOMETRY * globals.fog.z);
    let reach = near * (1.0 - f32(copy - 1u) / f32(copies));
    return clamp((reach - d) / max(0.2 * reach, 1e-3), 0.0, 1.0);
}

// How upright blade b stands as stored (without the drawn wind): the sine
// of its root-to-tip elevation, 1 standing, 0 laid flat (grass_ao).
fn blade_upright(b: u32) -> f32 {
    let l = b - chunk.x;
    let chord = pos[globals.params.y * chunk.y + l].xyz - pos[l].xyz;
    return chord.y / max(length(chord), 1e-6);
}

@vertex
fn vs_main(@builtin(vertex_index) vi: u32, @builtin(instance_index) ii: u32) -> VertexOut {
    let copies = drawn_copies();
    let inst = instances[chunk.x + ii / copies];
    let copy = ii % copies;
    let b = inst.x;
    let n = globals.params.y;
    let k = vi / 2u;
    let side = f32(vi % 2u) - 0.5;
    let l = b - chunk.x;
    let root = pos[l].xyz;
    let tip = wind_tip_offset(root);
    let p = drawn_vertex(k, l, root, tip);
    // Tangent of the bent shape at vertex k (central difference).
    let dir = normalize(drawn_vertex(min(k + 1u, n), l, root, tip) - drawn_vertex(max(k, 1u) - 1u, l, root, tip));
    // A copy's own seed: its facing, offset, height and tint.
    let seed = select(b, b * 7919u + copy * 104729u, copy != 0u);
    // The blade's flat side faces a fixed random direction, kept perpendicular to the tangent.
    let across = blade_across(seed, dir);
    let t = f32(k) / f32(n);
    var world = p + across * side * blade_width(shape[b].x, t);
    var tint = shape[b].y;
    // The near blend band (billboard cells' blades): a growing share
    // shrinks to the root with distance as the billboards fade in.
    let fade = blade_fade(hash01(seed ^ 0x2c1b3c6du), distance(root, globals.eye.xyz));
    world = root + (world - root) * fade;
    if (copy != 0u) {
        let offset = vec3<f32>(hash01(seed ^ 0x68e31da4u) - 0.5, 0.0, hash01(seed ^ 0xb5297a4du) - 0.5)
            * globals.sky_zenith.w;
        let d = distance(root.xz + offset.xz, globals.eye.xz);
        let height = 0.8 + 0.35 * hash01(seed ^ 0x1b56c4e9u);
        world = root + offset + (world - root) * (height * copy_scale(copy, copies, d));
        tint = fract(tint + 0.618034 * hash01(seed));
    }

    var out: VertexOut;
    out.clip = globals.view_proj * vec4<f32>(world, 1.0);
    out.world = world;
    out.normal = blade_normal(across, dir, side);
    out.along = t;
    out.sun = sun_visibility(world);
    if (inst.y != 0u) {
        out.albedo = unpack4x8unorm(inst.y).rgb;
    } else {
        // Ambient occlusion (globals.wgsl): darker to the root and when laid flat.
        out.albedo = blade_albedo(tint, t) * grass_ao(t, blade_upright(b));
    }
    return out;
}

@fragment
fn fs_main(v: VertexOut) -> @location(0) vec4<f32> {
    var n = normalize(v.normal);
    let to_eye = normalize(globals.eye.xyz - v.world);
    // Two-sided: light the side that faces the viewer.
    if (dot(n, to_eye) < 0.0) {
        n = -n;
    }
    // The bodies' shadows (globals.wgsl): the sun's light and glow go.
    let sun = v.sun;
    var c = light_shaded(v.albedo, n, 0.4, sun, 1.0);
    // Translucency: thin blades glow when the sun is behind them.
    let back = pow(max(dot(-to_eye, globals.sun_dir.xyz), 0.0), 4.0);
    c = c + v.albedo * globals.sun_color.rgb * back * 0.6 * v.along * sun;
    if (globals.params.x != 0u) {
        c = v.albedo * (0.6 + 0.4 * max(dot(n, globals.sun_dir.xyz), 0.0));
    }
    return out_color(fog(c, v.world));
}
