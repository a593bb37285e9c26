// The sun's shadow map (shadows.rs): the bodies' triangles, posed, seen from
// the sun (globals.light_view_proj), depth only.

struct Object {
    model: mat4x4<f32>,
    color: vec4<f32>,
}

@group(1) @binding(0) var<uniform> object: Object;

@vertex
fn vs_main(@location(0) position: vec3<f32>) -> @builtin(position) vec4<f32> {
    return globals.light_view_proj * (object.model * vec4<f32>(position, 1.0));
}
