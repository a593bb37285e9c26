// Segment vs oriented box (paper §4.2, ref. [16]; prepended to the stages
// that need it, not a stage itself): `trample::collision::segment_obb`,
// float op for float op (glam's SSE order), touching counts.

// glam's `Vec3A::cross` (no fma): a.y b.z - a.z b.y, ...
fn cross3(a: vec3<f32>, b: vec3<f32>) -> vec3<f32> {
    return vec3<f32>(a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x);
}

// glam's dot3: (x x' + y y') + z z'.
fn dot3(a: vec3<f32>, b: vec3<f32>) -> f32 {
    return (a.x * b.x + a.y * b.y) + a.z * b.z;
}

// `segment_obb::segment_hits_obb_centred`: segment centre ± half against the
// box (centre c, axes u v w, half extents e), the six separating axes.
fn hits_box(centre: vec3<f32>, half: vec3<f32>, bc: vec3<f32>, u: vec3<f32>, v: vec3<f32>, w: vec3<f32>, e: vec3<f32>) -> bool {
    let d = centre - bc;
    let c = vec3<f32>(dot3(u, d), dot3(v, d), dot3(w, d));
    let h = vec3<f32>(dot3(u, half), dot3(v, half), dot3(w, half));
    return hits_box_local(c, h, e);
}

// `segment_obb::hits_centred_local`: segment c ± h in the frame of a box
// centred at the origin with half extents e, the six separating axes.
fn hits_box_local(c: vec3<f32>, h: vec3<f32>, e: vec3<f32>) -> bool {
    let ah = abs(h);
    let faces = abs(c) <= e + ah;
    let cr = abs(cross3(c, h));
    let reach = vec3<f32>(e.y, e.x, e.x) * vec3<f32>(ah.z, ah.z, ah.y)
        + vec3<f32>(e.z, e.z, e.y) * vec3<f32>(ah.y, ah.x, ah.x);
    return all(faces) && all(cr <= reach);
}
