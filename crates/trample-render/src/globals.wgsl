// Per-frame values every pass reads (group 0, binding 0). Prepended to every
// other shader of the crate; layout-compatible with `Globals` in globals.rs.

struct Globals {
    view_proj: mat4x4<f32>,
    inv_view_proj: mat4x4<f32>,
    // xyz: eye position, w: time (s).
    eye: vec4<f32>,
    // xyz: direction towards the sun (unit), w: ambient strength.
    sun_dir: vec4<f32>,
    // rgb: sun colour, w: unused.
    sun_color: vec4<f32>,
    // rgb: sky colour overhead.
    sky_zenith: vec4<f32>,
    // rgb: sky colour at the horizon = fog colour.
    sky_horizon: vec4<f32>,
    // x: fog start (m), y: fog end (m), z: geometry_m, w: billboard_m.
    fog: vec4<f32>,
    // x: debug view (0 none, 1 classes), y: segments per blade, z: blade count,
    // w: 1 = encode sRGB in the shader (a non-sRGB target).
    params: vec4<u32>,
    // xz: wind direction (unit), y: steady tip displacement (m), w: gust amplitude (m).
    wind: vec4<f32>,
    // x: gust period (s), y: gust wavelength (m).
    gusts: vec4<f32>,
}

@group(0) @binding(0) var<uniform> globals: Globals;

// Sun (Lambert, wrapped by `wrap` for thin translucent things) + ambient.
fn light(albedo: vec3<f32>, n: vec3<f32>, wrap: f32) -> vec3<f32> {
    let ndl = dot(n, globals.sun_dir.xyz);
    let diffuse = max((ndl + wrap) / (1.0 + wrap), 0.0);
    let sky = mix(globals.sky_horizon.rgb, globals.sky_zenith.rgb, clamp(n.y * 0.5 + 0.5, 0.0, 1.0));
    return albedo * (globals.sun_color.rgb * diffuse + sky * globals.sun_dir.w);
}

// Distance fog towards the horizon colour.
fn fog(color: vec3<f32>, world: vec3<f32>) -> vec3<f32> {
    let d = distance(world, globals.eye.xyz);
    let f = clamp((d - globals.fog.x) / (globals.fog.y - globals.fog.x), 0.0, 1.0);
    return mix(color, globals.sky_horizon.rgb, f * f);
}

// What a fragment shader returns for the linear colour `c`: as is for an
// sRGB target (the hardware encodes it), sRGB-encoded here for any other
// (params.w = 1, `TargetFormat::shader_encodes_srgb`).
fn out_color(c: vec3<f32>) -> vec4<f32> {
    if (globals.params.w == 0u) {
        return vec4<f32>(c, 1.0);
    }
    let x = clamp(c, vec3<f32>(0.0), vec3<f32>(1.0));
    let lo = x * 12.92;
    let hi = 1.055 * pow(x, vec3<f32>(1.0 / 2.4)) - 0.055;
    return vec4<f32>(select(hi, lo, x <= vec3<f32>(0.0031308)), 1.0);
}

// Small integer hash -> [0, 1).
fn hash01(x: u32) -> f32 {
    var h = x * 747796405u + 2891336453u;
    h = ((h >> ((h >> 28u) + 4u)) ^ h) * 277803737u;
    h = (h >> 22u) ^ h;
    return f32(h & 0xffffffu) / 16777216.0;
}

// Wind tip displacement of a blade rooted at `root` (trample::wind::tip_offset,
// its specification): a vertex at fraction f of the height moves f² times this.
fn wind_tip_offset(root: vec3<f32>) -> vec3<f32> {
    let d = vec3<f32>(globals.wind.x, 0.0, globals.wind.z);
    let phase = 6.2831853 * (globals.eye.w / globals.gusts.x - dot(root, d) / globals.gusts.y);
    return d * (globals.wind.y + globals.wind.w * (0.5 + 0.5 * sin(phase)));
}

// `r` (a point relative to its root) moved sideways by `o` (horizontal),
// keeping its distance to the root: the height gives way, never below 0.
fn wind_bend(r: vec3<f32>, o: vec3<f32>) -> vec3<f32> {
    let side = vec3<f32>(r.x + o.x, 0.0, r.z + o.z);
    let h = sqrt(max(dot(r, r) - dot(side, side), 0.0));
    return side + vec3<f32>(0.0, h, 0.0);
}
