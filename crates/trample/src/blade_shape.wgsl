// How a blade looks when drawn (DESIGN §8), shared by every renderer of the
// field: trample-render's blades.wgsl and billboards.wgsl and bevy_trample's
// blades.wgsl include this one file (trample::blade_shape::WGSL), so a
// change here changes them all. No bindings: plain functions of their
// arguments. Their CPU specifications: `trample::wind::tip_offset` (wind).

// Small integer hash -> [0, 1).
fn hash01(x: u32) -> f32 {
    var h = x * 747796405u + 2891336453u;
    h = ((h >> ((h >> 28u) + 4u)) ^ h) * 277803737u;
    h = (h >> 22u) ^ h;
    return f32(h & 0xffffffu) / 16777216.0;
}

// Wind tip displacement of a blade rooted at `root` at `time` seconds
// (trample::wind::tip_offset, its specification): a vertex at fraction f
// of the height moves f² times this. `wind`: xz unit direction, y steady
// tip displacement (m), w gust amplitude (m); `gusts`: x period (s), y
// wavelength (m).
fn wind_tip_offset_at(root: vec3<f32>, wind: vec4<f32>, gusts: vec4<f32>, time: f32) -> vec3<f32> {
    let d = vec3<f32>(wind.x, 0.0, wind.z);
    let phase = 6.2831853 * (time / gusts.x - dot(root, d) / gusts.y);
    return d * (wind.y + wind.w * (0.5 + 0.5 * sin(phase)));
}

// `r` (a point relative to its root) moved sideways by `o` (horizontal),
// keeping its distance to the root: the height gives way, never below 0.
fn wind_bend(r: vec3<f32>, o: vec3<f32>) -> vec3<f32> {
    let side = vec3<f32>(r.x + o.x, 0.0, r.z + o.z);
    let h = sqrt(max(dot(r, r) - dot(side, side), 0.0));
    return side + vec3<f32>(0.0, h, 0.0);
}

// Vertex `p` (k of n) of a blade rooted at `root` as the wind bends it:
// it moves (k/n)² of the tip's offset `tip` sideways and keeps its
// distance to the root, so the blade bends rather than stretches. Calm
// (`tip` zero): `p` unchanged.
fn blade_wind_vertex(root: vec3<f32>, p: vec3<f32>, k: u32, n: u32, tip: vec3<f32>) -> vec3<f32> {
    let f = f32(k) / f32(n);
    let o = tip * (f * f);
    if (dot(o, o) == 0.0) {
        return p;
    }
    return root + wind_bend(p - root, o);
}

// Unit direction across blade `b`'s flat side at a vertex whose tangent is
// `dir`: a fixed random facing per blade, kept perpendicular to the tangent.
fn blade_across(b: u32, dir: vec3<f32>) -> vec3<f32> {
    let a = hash01(b) * 6.2831853;
    var across = vec3<f32>(cos(a), 0.0, sin(a));
    across = across - dir * dot(across, dir);
    if (dot(across, across) < 1e-6) {
        across = vec3<f32>(1.0, 0.0, 0.0);
    }
    return normalize(across);
}

// Width of a blade `root_width` wide at its root, at fraction `t` of its
// length (0 root, 1 tip): tapered to a point.
fn blade_width(root_width: f32, t: f32) -> f32 {
    return root_width * (1.0 - t * t);
}

// Normal of the bent strip at a vertex with tangent `dir`, facing `across`,
// on side `side` (-0.5 or 0.5): rounded a little across the width.
fn blade_normal(across: vec3<f32>, dir: vec3<f32>, side: f32) -> vec3<f32> {
    return normalize(cross(across, dir)) + across * side * 0.6;
}

// Colour (linear) at fraction `t` along a blade of tint `tint` in [0, 1):
// a root-to-tip gradient varied per blade by its tint.
fn blade_albedo(tint: f32, t: f32) -> vec3<f32> {
    let root = vec3<f32>(0.025, 0.06, 0.012);
    let tip = mix(vec3<f32>(0.16, 0.30, 0.035), vec3<f32>(0.30, 0.34, 0.07), tint);
    return mix(root, tip, smoothstep(0.0, 1.0, t));
}

// Horizontal unit axis of quad `quad` (0 or 1) of the crossed billboard of
// the cell with random seed `seed`: a random turn per cell, the two quads
// at right angles.
fn billboard_axis(seed: u32, quad: u32) -> vec3<f32> {
    let a = hash01(seed) * 1.5707963 + f32(quad) * 1.5707963;
    return vec3<f32>(cos(a), 0.0, sin(a));
}

// A billboard's top edge `top` (from its base) as the wind leans it: moved
// like a blade tip by `tip` (wind_tip_offset_at at the base), its length
// kept. Calm (`tip` zero): `top` unchanged.
fn billboard_top_in_wind(top: vec3<f32>, tip: vec3<f32>) -> vec3<f32> {
    if (dot(tip, tip) > 0.0) {
        return wind_bend(top, tip);
    }
    return top;
}

// Blend bands between levels of detail (ours, DESIGN §8: no ring round the
// camera). `near_band` and `far_band` (m) are the widths
// `LodParams::blend_bands` gives; 0 is the paper's hard switch.
//
// How far the billboards have faded in at distance `d` (m) from the eye:
// 0 up to `geometry_m`, 1 past the near band (1 everywhere without one).
// The blades of Billboard-LOD cells in the near band are drawn too, a
// share 1 - billboard_fade_in_at of them (`blade_fade_at`): the drawn
// density is kept across the change of level.
fn billboard_fade_in_at(d: f32, geometry_m: f32, near_band: f32) -> f32 {
    if (near_band <= 0.0) {
        return 1.0;
    }
    return clamp((d - geometry_m) / near_band, 0.0, 1.0);
}

// How much of the billboards is left at distance `d` (m): 1 up to the far
// band, 0 at `billboard_m`, where the ground shows alone.
fn billboard_fade_out_at(d: f32, billboard_m: f32, far_band: f32) -> f32 {
    if (far_band <= 0.0) {
        return 1.0;
    }
    return clamp((billboard_m - d) / far_band, 0.0, 1.0);
}

// Height scale of a blade (or drawn copy) whose own random value is `h` in
// [0, 1), rooted `d` m from the eye: 1 nearer than `geometry_m`; in the
// near band the blades with the lowest `h` shrink to their root first, so
// that about 1 - billboard_fade_in_at(d) of them stand, each shrinking
// over a short range (no blade pops).
const BLEND_SOFTNESS: f32 = 0.3;

fn blade_fade_at(h: f32, d: f32, geometry_m: f32, near_band: f32) -> f32 {
    if (near_band <= 0.0) {
        return 1.0;
    }
    let f = billboard_fade_in_at(d, geometry_m, near_band);
    return clamp((h + BLEND_SOFTNESS - (1.0 + BLEND_SOFTNESS) * f) / BLEND_SOFTNESS, 0.0, 1.0);
}

// Render density beyond the simulation's (ours, DESIGN §8: near the camera
// more blades are drawn than simulated). Each simulated blade is drawn
// `copies` times; copy 0 is the simulated blade, copy j > 0 its bent shape
// (so it follows the deformation: a track, the wind) moved by a fixed
// random offset within the blade spacing, with its own facing, height and
// tint. Copies thin out with the root's distance d from the eye: copy j is
// drawn to reach_j = near · (1 − (j − 1) / copies) and shrinks to its root
// over the last fifth of that, so nothing pops; `near` =
// `copy_reach_m(...)` keeps the drawn density back to the simulated one
// well before cells change level (the copies would vanish with their
// blades there).
const NEAR_OF_GEOMETRY: f32 = 0.6;

// How far from the eye the copies reach (m), for an asked reach
// `near_density_m` and the level-of-detail distance `geometry_m`.
fn copy_reach_m(near_density_m: f32, geometry_m: f32) -> f32 {
    return min(near_density_m, NEAR_OF_GEOMETRY * geometry_m);
}

// Copy `copy`'s own seed of blade `b` (its facing, offset, height, tint);
// copy 0, the simulated blade, keeps the blade's.
fn copy_seed(b: u32, copy: u32) -> u32 {
    return select(b, b * 7919u + copy * 104729u, copy != 0u);
}

// How much of copy `copy` (≥ 1) of `copies` shows at distance `d` (m):
// 1 near, 0 past its reach, linear between.
fn copy_scale_at(copy: u32, copies: u32, d: f32, near: f32) -> f32 {
    let reach = near * (1.0 - f32(copy - 1u) / f32(copies));
    return clamp((reach - d) / max(0.2 * reach, 1e-3), 0.0, 1.0);
}

// Where copy `copy` (≥ 1, seed `seed`) draws the vertex `world` of the
// blade rooted at `root`: moved by the copy's offset within `spacing` (m,
// the blade spacing), scaled by its height and `copy_scale_at` (`near`,
// m: `copy_reach_m`) about its root, `eye` the viewpoint.
fn copy_vertex(root: vec3<f32>, world: vec3<f32>, seed: u32, copy: u32, copies: u32, spacing: f32, near: f32, eye: vec3<f32>) -> vec3<f32> {
    let offset = vec3<f32>(hash01(seed ^ 0x68e31da4u) - 0.5, 0.0, hash01(seed ^ 0xb5297a4du) - 0.5) * spacing;
    let d = distance(root.xz + offset.xz, eye.xz);
    let height = 0.8 + 0.35 * hash01(seed ^ 0x1b56c4e9u);
    return root + offset + (world - root) * (height * copy_scale_at(copy, copies, d, near));
}

// A copy's tint, from its blade's `tint` and its own seed.
fn copy_tint(tint: f32, seed: u32) -> f32 {
    return fract(tint + 0.618034 * hash01(seed));
}

// Ambient occlusion of grass (ours, DESIGN §8): 1 at the tip of a standing
// blade, darker towards the root (`along`: 0 at the root, 1 at the tip: the
// neighbours hide the sky and the sun there) and for a flattened blade
// (`upright`: the sine of its root-to-tip elevation, 1 standing, 0 lying:
// laid blades shade each other, so a track reads even in the shade).
// Scaled by `strength` (0 = none, 1 = down to 45 % at a standing blade's
// root, 70 % of the light for a lying one).
fn grass_ao_at(along: f32, upright: f32, strength: f32) -> f32 {
    let low = 1.0 - clamp(along, 0.0, 1.0);
    let occlusion = 0.55 * low * low + 0.3 * (1.0 - clamp(upright, 0.0, 1.0));
    return 1.0 - strength * occlusion;
}
