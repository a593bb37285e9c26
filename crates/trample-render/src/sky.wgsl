// Sky: a full-screen triangle behind everything; zenith-to-horizon gradient
// and a sun disc, from view rays rebuilt with the inverse view-projection.

struct VertexOut {
    @builtin(position) clip: vec4<f32>,
    @location(0) ndc: vec2<f32>,
}

@vertex
fn vs_main(@builtin(vertex_index) vi: u32) -> VertexOut {
    let xy = vec2<f32>(f32((vi << 1u) & 2u), f32(vi & 2u)) * 2.0 - 1.0;
    var out: VertexOut;
    // Depth 1: the far plane.
    out.clip = vec4<f32>(xy, 1.0, 1.0);
    out.ndc = xy;
    return out;
}

@fragment
fn fs_main(v: VertexOut) -> @location(0) vec4<f32> {
    let far = globals.inv_view_proj * vec4<f32>(v.ndc, 1.0, 1.0);
    let near = globals.inv_view_proj * vec4<f32>(v.ndc, 0.0, 1.0);
    let dir = normalize(far.xyz / far.w - near.xyz / near.w);
    let up = clamp(dir.y, 0.0, 1.0);
    var c = mix(globals.sky_horizon.rgb, globals.sky_zenith.rgb, pow(up, 0.6));
    let sun = max(dot(dir, globals.sun_dir.xyz), 0.0);
    c = c + globals.sun_color.rgb * (pow(sun, 800.0) * 4.0 + pow(sun, 12.0) * 0.15);
    return out_color(c);
}
