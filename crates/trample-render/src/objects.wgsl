// Objects: flat-shaded triangles posed by a model matrix, with a checker in
// the object's own frame so rolling shows.

struct Object {
    model: mat4x4<f32>,
    // rgb: base colour (linear), w: checker cells per metre (0 = none).
    color: vec4<f32>,
}

@group(1) @binding(0) var<uniform> object: Object;

struct VertexIn {
    @location(0) position: vec3<f32>,
    @location(1) normal: vec3<f32>,
}

struct VertexOut {
    @builtin(position) clip: vec4<f32>,
    @location(0) world: vec3<f32>,
    @location(1) normal: vec3<f32>,
    @location(2) local: vec3<f32>,
}

@vertex
fn vs_main(v: VertexIn) -> VertexOut {
    let world = object.model * vec4<f32>(v.position, 1.0);
    var out: VertexOut;
    out.clip = globals.view_proj * world;
    out.world = world.xyz;
    // Rigid motion (rotation + translation, no scale): the normal turns with the model.
    out.normal = (object.model * vec4<f32>(v.normal, 0.0)).xyz;
    out.local = v.position;
    return out;
}

@fragment
fn fs_main(v: VertexOut) -> @location(0) vec4<f32> {
    var albedo = object.color.rgb;
    if (object.color.w > 0.0) {
        let q = floor(v.local * object.color.w);
        if (i32(q.x + q.y + q.z) % 2 != 0) {
            albedo = albedo * 0.25;
        }
    }
    let n = normalize(v.normal);
    // Bodies shadow each other and themselves (shadows.rs).
    let sun = sun_visibility(v.world);
    var c = light_shaded(albedo, n, 0.0, sun, 1.0);
    // A little specular so the object reads as solid.
    let h = normalize(globals.sun_dir.xyz + normalize(globals.eye.xyz - v.world));
    c = c + globals.sun_color.rgb * pow(max(dot(n, h), 0.0), 40.0) * 0.25 * sun;
    return out_color(fog(c, v.world));
}
