// The ground: a grid mesh over the terrain with a grass texture generated in
// code (what Texture-LOD cells show, and what shows between blades).

@group(1) @binding(0) var ground: texture_2d<f32>;
@group(1) @binding(1) var ground_sampler: sampler;
// Per cell (FieldLayout::cell_index order): how flattened its blades are, 0–1.
@group(1) @binding(2) var<storage, read> flatness: array<f32>;

// Where each cell is (terrain.rs `TrackGrid`).
struct TrackGrid {
    origin: vec2<f32>,
    cell_size: f32,
    // How much a fully flattened cell darkens the ground.
    darkening: f32,
    grid: vec2<u32>,
    patches_x: u32,
    cells_per_patch: u32,
    // rgb: the ground's tint at ground-texture level (terrain.rs
    // `far_tint`), and what the billboards' ambient occlusion at full
    // strength takes off it.
    far_tint: vec4<f32>,
    far_occlusion: vec4<f32>,
}
@group(1) @binding(3) var<uniform> track: TrackGrid;

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

// Flatness of cell (gx, gz) (FieldLayout::cell_index); 0 outside the field.
fn cell_flatness(g: vec2<i32>) -> f32 {
    if (any(g < vec2<i32>(0)) || any(vec2<u32>(g) >= track.grid)) {
        return 0.0;
    }
    let c = vec2<u32>(g);
    let n = track.cells_per_patch;
    let p = (c.y / n) * track.patches_x + c.x / n;
    return flatness[p * n * n + (c.y % n) * n + c.x % n];
}

// Flatness at world (x, z), bilinear between cell centres: the track the
// cells' blades make, seen on the ground at every level of detail.
fn flatness_at(xz: vec2<f32>) -> f32 {
    let f = (xz - track.origin) / track.cell_size - 0.5;
    let g = vec2<i32>(floor(f));
    let t = f - floor(f);
    let a = mix(cell_flatness(g), cell_flatness(g + vec2<i32>(1, 0)), t.x);
    let b = mix(cell_flatness(g + vec2<i32>(0, 1)), cell_flatness(g + vec2<i32>(1, 1)), t.x);
    return clamp(mix(a, b, t.y), 0.0, 1.0);
}

// 1 over the field's cells, 0 outside.
fn in_field(xz: vec2<f32>) -> f32 {
    let g = (xz - track.origin) / track.cell_size;
    return select(0.0, 1.0, all(g >= vec2<f32>(0.0)) && all(g < vec2<f32>(track.grid)));
}

@fragment
fn fs_main(v: VertexOut) -> @location(0) vec4<f32> {
    let texel = textureSample(ground, ground_sampler, v.world.xz / TILE_M).rgb;
    // Large-scale variation so the tiling does not show.
    let m = 0.85 + 0.15 * sin(v.world.x * 0.21 + sin(v.world.z * 0.17) * 2.0) * cos(v.world.z * 0.13);
    // Flattened grass: darker and browner (blades laid on the ground
    // shade it and show their duller undersides). The square root makes a
    // half-flattened patch read clearly as a track, continuously from 0.
    // Faded in across the billboard band (geometry_m to billboard_m): the
    // blades and billboards show the track themselves nearer, and a darker
    // ground under them would change as cells change level (popping).
    let d = distance(v.world, globals.eye.xyz);
    let far = smoothstep(globals.fog.z, globals.fog.w, d);
    let flat = sqrt(flatness_at(v.world.xz)) * track.darkening * far;
    // At ground-texture level the ground stands for the grass: tinted to
    // the billboards' mean colour, faded in across the billboard band
    // (under the billboards), so no ring shows where they end.
    let tint = track.far_tint.rgb - globals.shadow.y * track.far_occlusion.rgb;
    let grass = texel * m * mix(vec3<f32>(1.0), tint, far);
    let albedo = mix(grass, grass * vec3<f32>(0.5, 0.45, 0.3), flat);
    // The bodies' shadows; among the geometric blades the ground is as dark
    // as their roots (ambient occlusion, faded out with them).
    let ao = mix(grass_ao(0.0, 1.0), 1.0, max(far, 1.0 - in_field(v.world.xz)));
    var c = light_shaded(albedo, normalize(v.normal), 0.0, sun_visibility(v.world), ao);
    if (globals.params.x != 0u) {
        // Debug view: Texture-LOD distance band grey, nearer ground dark.
        let d = distance(v.world, globals.eye.xyz);
        c = select(vec3<f32>(0.05, 0.06, 0.04), vec3<f32>(0.35, 0.35, 0.35), d >= globals.fog.w);
    }
    return out_color(fog(c, v.world));
}
