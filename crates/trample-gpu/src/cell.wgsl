// Shared by the per-cell stages (prepended to classify.wgsl,
// billboards.wgsl, transitions.wgsl, slopes.wgsl and follow.wgsl; not a
// stage of its own): the cell state's bits and the cells' rest data.
//
// `cell_state` bits 0–1: level (0 geometry, 1 billboard, 2 texture); bits
// 2–3: the level before this sub-step's change (3: unchanged); bit 4: the
// billboard is bent (away from its rest slope); bit 5 (track everywhere):
// `follow.wgsl` last computed the cell from blades all at rest, so while
// they stay there it has nothing to compute.
//
// `cell_rest`, per cell two entries: (base xyz, billboard height),
// (slope_origin_b xyz, global cell coordinates gx | gz << 16 as the bits
// of a float).

const GEOMETRY: u32 = 0u;
const BILLBOARD: u32 = 1u;
const UNCHANGED: u32 = 3u;
const BENT: u32 = 16u;
const AT_REST: u32 = 32u;

fn level(s: u32) -> u32 {
    return s & 3u;
}

fn changed_from(s: u32) -> u32 {
    return (s >> 2u) & 3u;
}

fn distance2(a: vec3<f32>, b: vec3<f32>) -> f32 {
    let d = a - b;
    return dot3(d, d);
}

fn normalize_or_zero(v: vec3<f32>) -> vec3<f32> {
    let l2 = dot3(v, v);
    if l2 > 0.0 && l2 < 3.0e38 {
        return v * (1.0 / sqrt(l2));
    }
    return vec3<f32>(0.0);
}
