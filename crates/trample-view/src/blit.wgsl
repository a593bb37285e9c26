// Copies the renderer's frame (RGBA8 sRGB, read as linear colour) onto the
// window's surface, pixel for pixel (both have the window's size).

@group(0) @binding(0) var frame: texture_2d<f32>;

@vertex
fn vs_main(@builtin(vertex_index) i: u32) -> @builtin(position) vec4<f32> {
    // One triangle covering the screen.
    let uv = vec2<f32>(f32((i << 1u) & 2u), f32(i & 2u));
    return vec4<f32>(uv * 2.0 - 1.0, 0.0, 1.0);
}

fn load(pos: vec4<f32>) -> vec4<f32> {
    let size = vec2<i32>(textureDimensions(frame));
    let p = clamp(vec2<i32>(pos.xy), vec2<i32>(0), size - 1);
    return textureLoad(frame, p, 0);
}

// An sRGB surface encodes on store.
@fragment
fn fs_srgb_surface(@builtin(position) pos: vec4<f32>) -> @location(0) vec4<f32> {
    return vec4<f32>(load(pos).rgb, 1.0);
}

// A linear (UNORM) surface: encode to sRGB here.
@fragment
fn fs_linear_surface(@builtin(position) pos: vec4<f32>) -> @location(0) vec4<f32> {
    let c = load(pos).rgb;
    let lo = c * 12.92;
    let hi = 1.055 * pow(c, vec3<f32>(1.0 / 2.4)) - 0.055;
    return vec4<f32>(select(hi, lo, c <= vec3<f32>(0.0031308)), 1.0);
}
