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
