// The broad phase's uniform (broad_phase.wgsl), also read by propagation's
// `seed` (propagation.wgsl): prepended to both sources.
// Layout-compatible with `GpuBroadParams` in broad_phase.rs.
struct BroadParams {
    // patches, patches per chunk (all but the last), chunks, patches along x
    counts: vec4<u32>,
    // blades per patch, max workgroups per dimension, mask words per patch, unused
    dispatch: vec4<u32>,
}
