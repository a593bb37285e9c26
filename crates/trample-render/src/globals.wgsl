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
    // x: gust period (s), y: gust wavelength (m), z: drawn copies per
    // simulated blade, w: their reach (m).
    gusts: vec4<f32>,
    // Blend bands between levels of detail (m): x past geometry_m (blades
    // thin out, billboards fade in), y before billboard_m (billboards thin
    // out over the ground).
    blend: vec4<f32>,
    // World -> the sun's shadow-map clip space (shadows.rs).
    light_view_proj: mat4x4<f32>,
    // x: shadow strength (0 = off), y: ambient-occlusion strength,
    // z: depth bias of the shadow test (clip depth), w: unused.
    shadow: vec4<f32>,
}

@group(0) @binding(0) var<uniform> globals: Globals;
// The sun's shadow map (shadows.rs): depth of the nearest body seen from
// the sun; a 1x1 map, never sampled, when shadows are off.
@group(0) @binding(1) var shadow_map: texture_depth_2d;
@group(0) @binding(2) var shadow_sampler: sampler_comparison;

// Sun (Lambert, wrapped by `wrap` for thin translucent things) + ambient.
fn light(albedo: vec3<f32>, n: vec3<f32>, wrap: f32) -> vec3<f32> {
    return light_shaded(albedo, n, wrap, 1.0, 1.0);
}

// `light` with the sun scaled by `sun` (its visibility: `sun_visibility`)
// and everything by `ao` (ambient occlusion: `grass_ao`). In a shadow only
// the sky's ambient is left.
fn light_shaded(albedo: vec3<f32>, n: vec3<f32>, wrap: f32, sun: f32, ao: f32) -> vec3<f32> {
    let ndl = dot(n, globals.sun_dir.xyz);
    let diffuse = max((ndl + wrap) / (1.0 + wrap), 0.0) * sun;
    let sky = mix(globals.sky_horizon.rgb, globals.sky_zenith.rgb, clamp(n.y * 0.5 + 0.5, 0.0, 1.0));
    return albedo * (globals.sun_color.rgb * diffuse + sky * globals.sun_dir.w) * ao;
}

// How much of the sun reaches `world`: 1 in the light, 1 - shadow strength
// in a body's shadow; 1 outside the map or with shadows off. One tap of
// the linear comparison sampler: 2x2 PCF, bilinear between the texels'
// tests (four taps cost llvmpipe a third more render time on the default
// scene: it runs both sides of a branch).
fn sun_visibility(world: vec3<f32>) -> f32 {
    if (globals.shadow.x <= 0.0) {
        return 1.0;
    }
    let p = globals.light_view_proj * vec4<f32>(world, 1.0);
    let uv = vec2<f32>(p.x * 0.5 + 0.5, 0.5 - p.y * 0.5);
    if (any(uv <= vec2<f32>(0.0)) || any(uv >= vec2<f32>(1.0)) || p.z >= 1.0) {
        return 1.0;
    }
    let lit = textureSampleCompareLevel(shadow_map, shadow_sampler, uv, p.z - globals.shadow.z);
    return 1.0 - globals.shadow.x * (1.0 - lit);
}

// Ambient occlusion of grass: the shared `grass_ao_at` (trample::blade_shape)
// at this frame's strength (globals.shadow.y).
fn grass_ao(along: f32, upright: f32) -> f32 {
    return grass_ao_at(along, upright, globals.shadow.y);
}

// Blend bands between levels of detail (issue 15 item 1): the shared
// functions of trample::blade_shape with this frame's distances and bands
// (globals.fog.zw, globals.blend.xy).
fn billboard_fade_in(d: f32) -> f32 {
    return billboard_fade_in_at(d, globals.fog.z, globals.blend.x);
}

fn billboard_fade_out(d: f32) -> f32 {
    return billboard_fade_out_at(d, globals.fog.w, globals.blend.y);
}

fn blade_fade(h: f32, d: f32) -> f32 {
    return blade_fade_at(h, d, globals.fog.z, globals.blend.x);
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

// Wind tip displacement of a blade rooted at `root` now: the shared
// `wind_tip_offset_at` (trample::blade_shape, prepended) with this frame's
// wind and time.
fn wind_tip_offset(root: vec3<f32>) -> vec3<f32> {
    return wind_tip_offset_at(root, globals.wind, globals.gusts, globals.eye.w);
}
