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
    let p = pos[k * chunk.y + l].xyz;
    // Wind (draw time only): vertex k moves (k/n)² of the tip's offset
    // sideways and keeps its distance to the root, so the blade bends
    // rather than stretches. Calm: the stored vertex, unchanged.
    let root = pos[l].xyz;
    let f = f32(k) / f32(globals.params.y);
    let o = wind_tip_offset(root) * (f * f);
    if (dot(o, o) == 0.0) {
        return p;
    }
    return root + wind_bend(p - root, o);
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
    let a = hash01(b) * 6.2831853;
    var across = vec3<f32>(cos(a), 0.0, sin(a));
    across = across - dir * dot(across, dir);
    if (dot(across, across) < 1e-6) {
        across = vec3<f32>(1.0, 0.0, 0.0);
    }
    across = normalize(across);
    let t = f32(k) / f32(n);
    let w = shape[b].x * (1.0 - t * t);
    let world = p + across * side * w;

    var out: VertexOut;
    out.clip = globals.view_proj * vec4<f32>(world, 1.0);
    out.world = world;
    // Normal of the bent strip, rounded a little across the width.
    out.normal = normalize(cross(across, dir)) + across * side * 0.6;
    out.along = t;
    if (inst.y != 0u) {
        out.albedo = unpack4x8unorm(inst.y).rgb;
    } else {
        // Root-to-tip gradient (linear colour), varied per blade by its tint.
        let tint = shape[b].y;
        let root = vec3<f32>(0.025, 0.06, 0.012);
        let tip = mix(vec3<f32>(0.16, 0.30, 0.035), vec3<f32>(0.30, 0.34, 0.07), tint);
        out.albedo = mix(root, tip, smoothstep(0.0, 1.0, t));
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
