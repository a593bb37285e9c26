// Billboards of Billboard-LOD cells (DESIGN §8, paper Eq. 8, 12): two crossed
// vertical quads per cell, a bit wider than the cell, alpha-tested grass-clump
// texture; the top edge is `base + normalize(slope) · height`.

struct Billboard {
    // xyz: base centre, w: half width (m).
    base: vec4<f32>,
    // xyz: base → top edge (normalize(slope) · height), w: unused.
    top: vec4<f32>,
    // x: debug colour (RGBA8, 0 = textured), y: per-cell random seed.
    extra: vec4<u32>,
}

@group(1) @binding(0) var<storage, read> billboards: array<Billboard>;
@group(1) @binding(1) var clump: texture_2d<f32>;
@group(1) @binding(2) var clump_sampler: sampler;

struct VertexOut {
    @builtin(position) clip: vec4<f32>,
    @location(0) world: vec3<f32>,
    @location(1) uv: vec2<f32>,
    @location(2) normal: vec3<f32>,
    @location(3) @interpolate(flat) debug: u32,
    @location(4) shade: f32,
    // How much of the billboard shows (blend bands, globals.wgsl), its seed.
    @location(5) @interpolate(flat) presence: f32,
    @location(6) @interpolate(flat) seed: u32,
    // The sun's visibility (globals.wgsl), per vertex as the blades'.
    @location(7) sun: f32,
}

@vertex
fn vs_main(@builtin(vertex_index) vi: u32, @builtin(instance_index) ii: u32) -> VertexOut {
    let bb = billboards[ii];
    let quad = vi / 6u;
    // Two triangles per quad: corners (0,0) (1,0) (0,1), (0,1) (1,0) (1,1).
    let corner = array<u32, 6>(0u, 1u, 2u, 2u, 1u, 3u)[vi % 6u];
    let x = f32(corner & 1u);
    let y = f32(corner >> 1u);
    let seed = bb.extra.y;
    let axis = billboard_axis(seed, quad);
    // Wind (draw time only, trample::blade_shape): the top edge moves like a blade tip.
    let top = billboard_top_in_wind(bb.top.xyz, wind_tip_offset(bb.base.xyz));
    let world = bb.base.xyz + axis * (x * 2.0 - 1.0) * bb.base.w + top * y;

    var out: VertexOut;
    out.clip = globals.view_proj * vec4<f32>(world, 1.0);
    out.world = world;
    // A random half of the clump texture per quad.
    let u0 = hash01(seed ^ (quad * 0x9e37u)) * 0.5;
    out.uv = vec2<f32>(u0 + x * 0.5, 1.0 - y);
    out.normal = normalize(cross(axis, top));
    out.debug = bb.extra.x;
    let d = distance(bb.base.xyz, globals.eye.xyz);
    out.presence = billboard_fade_in(d) * billboard_fade_out(d);
    out.seed = seed * 2u + quad;
    out.sun = sun_visibility(world);
    // Ambient occlusion as the cell lies flatter (globals.wgsl; towards the base: fs_main).
    out.shade = (0.85 + 0.3 * hash01(seed ^ 0x51u)) * grass_ao(1.0, bb.top.y / max(length(bb.top.xyz), 1e-6));
    return out;
}

@fragment
fn fs_main(v: VertexOut) -> @location(0) vec4<f32> {
    let texel = textureSample(clump, clump_sampler, v.uv);
    if (texel.a < 0.5) {
        discard;
    }
    // Blend bands: a share `presence` of the billboard's columns shows
    // (thin vertical strips, like blades: a dithered fade that keeps the
    // drawn density as the blades thin out or the ground takes over).
    let column = u32(floor(v.uv.x * 96.0));
    if (hash01(column * 0x9e3779b9u ^ v.seed * 0x85ebca6bu) >= v.presence) {
        discard;
    }
    var n = normalize(v.normal);
    let to_eye = normalize(globals.eye.xyz - v.world);
    if (dot(n, to_eye) < 0.0) {
        n = -n;
    }
    // Lit like a blade seen side-on: mostly wrapped, so the quad does not flash as it turns.
    n = normalize(n + vec3<f32>(0.0, 1.2, 0.0));
    var c = light_shaded(texel.rgb * v.shade, n, 0.4, v.sun, grass_ao(1.0 - v.uv.y, 1.0));
    if (v.debug != 0u) {
        c = unpack4x8unorm(v.debug).rgb * (0.6 + 0.4 * (1.0 - v.uv.y));
    }
    return out_color(fog(c, v.world));
}
