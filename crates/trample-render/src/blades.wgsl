// Geometric blades (DESIGN §8): one instance per blade, a two-sided tapered
// strip of 2·(n+1) vertices pulled from the blade vertex buffer, laid out as
// the core stores it over a chunk of blades: vertex k of blade b at
// pos[k * blades + (b - first)] (Eq. 1). Both paths draw one draw per chunk:
// the CPU path its uploads (one chunk for a field within one binding), the
// GPU path (trample-gpu) straight from its buffers.

// x: width (m), y: tint in [0, 1).
@group(1) @binding(0) var<storage, read> pos: array<vec4<f32>>;
@group(1) @binding(1) var<storage, read> shape: array<vec2<f32>>;
// x: blade index, y: debug colour (RGBA8, 0 = shade normally).
@group(1) @binding(2) var<storage, read> instances: array<vec2<u32>>;
// x: the chunk's first blade, y: its blades, z: its first instance in
// `instances` (the GPU path lists a chunk's blades from its first blade on,
// z = x; the CPU path's list is compact).
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
// Render density beyond the simulation's (issue 15 item 2; the copies are
// trample::blade_shape's `copy_*`, shared with bevy_trample): each
// simulated blade is drawn `copies` times (globals.gusts.z, ≥ 1; instance
// ii is copy ii % copies of listed blade ii / copies), scattered within
// the blade spacing (globals.sky_zenith.w, m), reaching
// copy_reach_m(globals.gusts.w, geometry_m).
fn drawn_copies() -> u32 {
    return max(u32(globals.gusts.z), 1u);
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
    let inst = instances[chunk.z + ii / copies];
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
    let seed = copy_seed(b, copy);
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
        let near = copy_reach_m(globals.gusts.w, globals.fog.z);
        world = copy_vertex(root, world, seed, copy, copies, globals.sky_zenith.w, near, globals.eye.xyz);
        tint = copy_tint(tint, seed);
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
