// The ground: a grid mesh over the terrain with a grass texture generated in
// code (what Texture-LOD cells show, and what shows between blades).

@group(1) @binding(0) var ground: texture_2d<f32>;
@group(1) @binding(1) var ground_sampler: sampler;

struct VertexIn {
    @location(0) position: vec3<f32>,
    @location(1) normal: vec3<f32>,
}

struct VertexOut {
    @builtin(position) clip: vec4<f32>,
    @location(0) world: vec3<f32>,
    @location(1) normal: vec3<f32>,
}

// Metres per repeat of the ground texture (textures::GROUND_TILE_M).
const TILE_M: f32 = 2.0;

@vertex
fn vs_main(v: VertexIn) -> VertexOut {
    var out: VertexOut;
    out.clip = globals.view_proj * vec4<f32>(v.position, 1.0);
    out.world = v.position;
    out.normal = v.normal;
    return out;
}

@fragment
fn fs_main(v: VertexOut) -> @location(0) vec4<f32> {
    let texel = textureSample(ground, ground_sampler, v.world.xz / TILE_M).rgb;
    // Large-scale variation so the tiling does not show.
    let m = 0.85 + 0.15 * sin(v.world.x * 0.21 + sin(v.world.z * 0.17) * 2.0) * cos(v.world.z * 0.13);
    var c = light(texel * m, normalize(v.normal), 0.0);
    if (globals.params.x != 0u) {
        // Debug view: Texture-LOD distance band grey, nearer ground dark.
        let d = distance(v.world, globals.eye.xyz);
        c = select(vec3<f32>(0.05, 0.06, 0.04), vec3<f32>(0.35, 0.35, 0.35), d >= globals.fog.w);
    }
    return out_color(fog(c, v.world));
}
