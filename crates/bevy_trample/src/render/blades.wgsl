// The meadow in Bevy's renderer (DESIGN §8): geometric blades pulled from
// the blade vertex buffer (the core's layout, Eq. 1: vertex k of blade b at
// pos[k * blades + b]) and crossed billboards for Billboard-LOD cells (Eq. 8's
// top edge), both lit by Bevy's PBR lighting (its lights and their shadows,
// ambient light, fog, tonemapping) in Bevy's opaque pass. The blade's shape,
// wind and colour, the blend bands between levels of detail and the drawn
// copies near the camera are trample::blade_shape, the WGSL trample-render
// uses too.

#import bevy_pbr::mesh_view_bindings::view
#import bevy_pbr::pbr_types
#import bevy_pbr::pbr_functions
#import bevy_pbr::mesh_types::MESH_FLAGS_SHADOW_RECEIVER_BIT
#import trample::blade_shape::{hash01, wind_tip_offset_at, billboard_axis, billboard_top_in_wind, blade_wind_vertex, blade_across, blade_width, blade_normal, blade_albedo, billboard_fade_in_at, billboard_fade_out_at, blade_fade_at, copy_reach_m, copy_seed, copy_vertex, copy_tint, grass_ao_at}

struct Params {
    // xz: wind direction (unit), y: steady tip displacement (m), w: gust (m).
    wind: vec4<f32>,
    // x: gust period (s), y: gust wavelength (m).
    gusts: vec4<f32>,
    // x: blades, y: segments per blade, z: blades per cell, w: drawn
    // copies per simulated blade (render density, >= 1).
    counts: vec4<u32>,
    // x: simulated time (s), y: blade spacing (m), z: the copies' reach (m),
    // w: ambient-occlusion strength.
    time: vec4<f32>,
    // xyz: the eye that decides the levels of detail; w: 1 when `cells`
    // holds the GPU path's blade list of (blade, colour) pairs.
    eye: vec4<f32>,
    // x: geometry_m, y: billboard_m, z: near blend band, w: far blend band (m).
    lod: vec4<f32>,
}

struct Billboard {
    // xyz: base centre, w: half width (m).
    base: vec4<f32>,
    // xyz: base -> top edge (normalize(slope) * height), w: unused.
    top: vec4<f32>,
    // y: the cell (its random seed).
    extra: vec4<u32>,
}

@group(2) @binding(0) var<storage, read> pos: array<vec4<f32>>;
// x: width (m), y: tint in [0, 1).
@group(2) @binding(1) var<storage, read> shape: array<vec2<f32>>;
// Cells drawn as blades (their blades are the instances); on the GPU path
// the blades listed, (blade, colour) pairs.
@group(2) @binding(2) var<storage, read> cells: array<u32>;
@group(2) @binding(3) var<uniform> params: Params;
@group(2) @binding(4) var<storage, read> billboards: array<Billboard>;
// The blades' chunk: x its first blade (and, on the GPU path, its first
// listed blade), y its blades (`pos` holds them: vertex k of the chunk's
// blade l at pos[k * y + l]). The CPU path draws one chunk, (0, blades).
@group(2) @binding(5) var<uniform> chunk: vec4<u32>;

struct VertexOut {
    @builtin(position) clip: vec4<f32>,
    @location(0) world: vec3<f32>,
    @location(1) normal: vec3<f32>,
    @location(2) albedo: vec3<f32>,
    // Billboards: across the quad (0..1) and up it (0 base, 1 top).
    @location(3) uv: vec2<f32>,
    @location(4) @interpolate(flat) seed: u32,
    // Billboards: the share of their strands drawn (blend bands).
    @location(5) @interpolate(flat) presence: f32,
}

fn wind_tip(root: vec3<f32>) -> vec3<f32> {
    return wind_tip_offset_at(root, params.wind, params.gusts, params.time.x);
}

// Vertex k of the chunk's blade l, as drawn in the wind.
fn vertex_of(k: u32, l: u32) -> vec3<f32> {
    let root = pos[l].xyz;
    return blade_wind_vertex(root, pos[k * chunk.y + l].xyz, k, params.counts.y, wind_tip(root));
}

// A world point in the view's clip space (a camera's, or a light's in the
// shadow pipelines).
fn clip_of(world: vec3<f32>) -> vec4<f32> {
    var clip = view.clip_from_world * vec4<f32>(world, 1.0);
#ifdef SHADOW_CLAMP_ORTHO
    // A directional light's shadow view on a device without unclipped
    // depth: grass nearer to the light than the cascade's near plane
    // (reverse Z: depth above 1) is kept, at the near plane.
    clip.z = min(clip.z, clip.w);
#endif
    return clip;
}

// Two triangles a quad: corners (0,0) (1,0) (0,1), (0,1) (1,0) (1,1).
fn corner_of(vi: u32) -> vec2<u32> {
    let c = array<u32, 6>(0u, 1u, 2u, 2u, 1u, 3u)[vi % 6u];
    return vec2<u32>(c & 1u, c >> 1u);
}

// Instance ii is copy ii % copies of listed blade ii / copies (the cells'
// blades in order); copy 0 is the simulated blade.
@vertex
fn blade_vertex(@builtin(vertex_index) vi: u32, @builtin(instance_index) ii: u32) -> VertexOut {
    let per_cell = params.counts.z;
    let copies = max(params.counts.w, 1u);
    let listed = ii / copies;
    let copy = ii % copies;
    // The CPU path lists cells; the GPU path (eye.w = 1) lists blades as
    // (blade, colour) pairs, a chunk's from its first blade on.
    var b = cells[listed / per_cell] * per_cell + listed % per_cell;
    if (params.eye.w == 1.0) {
        b = cells[2u * (chunk.x + listed)];
    }
    // The blade within the chunk's vertices.
    let l = b - chunk.x;
    let n = params.counts.y;
    let c = corner_of(vi);
    let k = vi / 6u + c.y;
    let side = f32(c.x) - 0.5;
    let root = pos[l].xyz;
    let p = vertex_of(k, l);
    // Tangent of the bent shape at vertex k (central difference).
    let dir = normalize(vertex_of(min(k + 1u, n), l) - vertex_of(max(k, 1u) - 1u, l));
    let seed = copy_seed(b, copy);
    let across = blade_across(seed, dir);
    let t = f32(k) / f32(n);
    var world = p + across * side * blade_width(shape[b].x, t);
    var tint = shape[b].y;
    // The near blend band (Billboard-LOD cells' blades): a growing share
    // shrinks to the root with distance as the billboards fade in.
    let eye = params.eye.xyz;
    let fade = blade_fade_at(hash01(seed ^ 0x2c1b3c6du), distance(root, eye), params.lod.x, params.lod.z);
    world = root + (world - root) * fade;
    if (copy != 0u) {
        let near = copy_reach_m(params.time.z, params.lod.x);
        world = copy_vertex(root, world, seed, copy, copies, params.time.y, near, eye);
        tint = copy_tint(tint, seed);
    }

    var out: VertexOut;
    out.clip = clip_of(world);
    out.world = world;
    out.normal = blade_normal(across, dir, side);
    // Ambient occlusion: darker to the root and when laid flat (the
    // stored blade's root-to-tip elevation, without the drawn wind).
    let chord = pos[n * chunk.y + l].xyz - root;
    let upright = chord.y / max(length(chord), 1e-6);
    out.albedo = blade_albedo(tint, t) * grass_ao_at(t, upright, params.time.w);
    out.uv = vec2<f32>(f32(c.x), t);
    out.seed = seed;
    out.presence = 1.0;
    return out;
}

@vertex
fn billboard_vertex(@builtin(vertex_index) vi: u32, @builtin(instance_index) ii: u32) -> VertexOut {
    let bb = billboards[ii];
    let quad = vi / 6u;
    let c = corner_of(vi);
    let x = f32(c.x);
    let y = f32(c.y);
    let seed = bb.extra.y;
    let axis = billboard_axis(seed, quad);
    // Wind (draw time only): the top edge moves like a blade tip.
    let top = billboard_top_in_wind(bb.top.xyz, wind_tip(bb.base.xyz));
    let world = bb.base.xyz + axis * (x * 2.0 - 1.0) * bb.base.w + top * y;

    var out: VertexOut;
    out.clip = clip_of(world);
    out.world = world;
    // Lit as the blades look from afar, so that the levels meet without a
    // step in brightness (check_meadow's ring step, measured on lavapipe:
    // 17 as drawn here, 15 without the ambient occlusion; 35 with the
    // normal bent up by 1.2, tints in the
    // upper half and the base as dark as a blade's root, a yellow-green
    // wash past the blades): the quad's normal bent up a little (0 left
    // the billboards half as bright as the blades, 0.5 a tenth brighter),
    // the blades' whole range of tints, and the base lighter than a
    // blade's root (the nearest billboards' bases show in the blend band).
    out.normal = normalize(cross(axis, top)) + vec3<f32>(0.0, 0.3, 0.0);
    // Ambient occlusion along the height and as the cell lies flatter.
    let upright = bb.top.y / max(length(bb.top.xyz), 1e-6);
    let ao = grass_ao_at(y, 1.0, params.time.w) * grass_ao_at(1.0, upright, params.time.w);
    out.albedo = blade_albedo(hash01(seed ^ 0x51u), 0.3 + 0.7 * y) * ao;
    out.uv = vec2<f32>(x, y);
    out.seed = seed ^ (quad * 0x9e37u);
    // Blend bands: faded in past geometry_m, out towards billboard_m.
    let d = distance(bb.base.xyz, params.eye.xyz);
    out.presence = billboard_fade_in_at(d, params.lod.x, params.lod.z)
        * billboard_fade_out_at(d, params.lod.y, params.lod.w);
    return out;
}

// Bevy's lighting of a two-sided grass surface.
fn lit(v: VertexOut) -> vec4<f32> {
    var pbr = pbr_types::pbr_input_new();
    pbr.material.base_color = vec4<f32>(v.albedo, 1.0);
    pbr.material.perceptual_roughness = 0.85;
    pbr.material.reflectance = vec3<f32>(0.2);
    pbr.material.flags = pbr.material.flags | pbr_types::STANDARD_MATERIAL_FLAGS_FOG_ENABLED_BIT;
    pbr.frag_coord = v.clip;
    pbr.world_position = vec4<f32>(v.world, 1.0);
    pbr.is_orthographic = view.clip_from_view[3].w == 1.0;
    pbr.V = pbr_functions::calculate_view(pbr.world_position, pbr.is_orthographic);
    var n = normalize(v.normal);
    // Two-sided: light the side that faces the viewer.
    if (dot(n, pbr.V) < 0.0) {
        n = -n;
    }
    pbr.world_normal = n;
    pbr.N = n;
    pbr.flags = MESH_FLAGS_SHADOW_RECEIVER_BIT;
    let c = pbr_functions::apply_pbr_lighting(pbr);
    return pbr_functions::main_pass_post_lighting_processing(pbr, c);
}

@fragment
fn blade_fragment(v: VertexOut) -> @location(0) vec4<f32> {
    return lit(v);
}

// A clump of blades cut out of the quad: `STRANDS` tapered strands of
// random heights across it.
const STRANDS: f32 = 7.0;

// Whether the billboard's point `v` lies on one of its drawn strands.
fn on_a_strand(v: VertexOut) -> bool {
    let s = v.uv.x * STRANDS;
    let strand = u32(floor(s));
    let h = 0.55 + 0.45 * hash01(v.seed * 31u + strand);
    let across = abs(fract(s) - 0.5) * 2.0;
    // Each strand tapers to a point at its height.
    if (v.uv.y > h * (1.0 - across * across) || across > 0.8) {
        return false;
    }
    // Blend bands: a share `presence` of the strands shows (a dithered
    // fade that keeps the drawn density as the blades thin out or the
    // ground takes over).
    return hash01(strand * 0x9e3779b9u ^ v.seed * 0x85ebca6bu) < v.presence;
}

@fragment
fn billboard_fragment(v: VertexOut) -> @location(0) vec4<f32> {
    if (!on_a_strand(v)) {
        discard;
    }
    return lit(v);
}

// The billboards in a light's shadow map: the strands the camera sees,
// depth only (the quad's cut-out, not the whole quad).
@fragment
fn billboard_shadow_fragment(v: VertexOut) {
    if (!on_a_strand(v)) {
        discard;
    }
}
