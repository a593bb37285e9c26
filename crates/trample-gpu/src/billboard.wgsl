// A billboard's top edge (paper Eq. 8, DESIGN §6; prepended to cells.wgsl
// and draw_lists.wgsl after segment_obb.wgsl and guard.wgsl, not a stage of
// its own).

// `billboard::billboard_top`: the top edge at base + normalize(slope) ·
// height, above the ground guard.
fn billboard_top(base: vec3<f32>, sl: vec3<f32>, height: f32) -> vec3<f32> {
    if !(height > 0.0) {
        return base;
    }
    var dir = vec3<f32>(0.0, 1.0, 0.0);
    let l2 = dot3(sl, sl);
    if l2 > 0.0 && l2 < 3.0e38 {
        dir = sl * (1.0 / sqrt(l2));
    }
    return guarded_end(base, dir, height, vec3<f32>(1.0, 0.0, 0.0));
}
