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
}

fn vertex_of(k: u32, b: u32) -> vec3<f32> {
    let l = b - chunk.x;
    // Wind (draw time only, trample::blade_shape): calm leaves the stored vertex.
    let root = pos[l].xyz;
    return blade_wind_vertex(root, pos[k * chunk.y + l].xyz, k, globals.params.y, wind_tip_offset(root));
}
@vertex
fn vs_main(@builtin(vertex_index) vi: u32, @builtin(instance_index) ii: u32) -> VertexOut {
    let inst = instances[chunk.x + ii];
    let b = inst.x;
    let n = globals.params.y;
    let k = vi / 2u;
    let side = f32(vi % 2u) - 0.5;
    let p = vertex_of(k, b);
    // Tangent of the bent shape at vertex k (central difference).
    let dir = normalize(vertex_of(min(k + 1u, n), b) - vertex_of(max(k, 1u) - 1u, b));
    // The blade's flat side faces a fixed random direction, kept perpendicular to the tangent.
    let across = blade_across(b, dir);
    let t = f32(k) / f32(n);
    let world = p + across * side * blade_width(shape[b].x, t);

    var out: VertexOut;
    out.clip = globals.view_proj * vec4<f32>(world, 1.0);
    out.world = world;
    out.normal = blade_normal(across, dir, side);
    out.along = t;
    if (inst.y != 0u) {
        out.albedo = unpack4x8unorm(inst.y).rgb;
    } else {
        out.albedo = blade_albedo(shape[b].y, t);
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
    var c = light(v.albedo, n, 0.4);
    // Translucency: thin blades glow when the sun is behind them.
    let back = pow(max(dot(-to_eye, globals.sun_dir.xyz), 0.0), 4.0);
    c = c + v.albedo * globals.sun_color.rgb * back * 0.6 * v.along;
    if (globals.params.x != 0u) {
        c = v.albedo * (0.6 + 0.4 * max(dot(n, globals.sun_dir.xyz), 0.0));
    }
    return out_color(fog(c, v.world));
}
