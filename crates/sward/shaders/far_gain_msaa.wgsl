// The far levels' light gain measured over a multisampled frame (far_gain_common.wgsl):
// each pixel's first sample's depth, beside the resolved radiance.
//!include far_gain_common.wgsl

@group(0) @binding(6) var depth_tex: texture_depth_multisampled_2d;

fn frame_depth(p: vec2<u32>) -> f32 {
    return textureLoad(depth_tex, p, 0);
}
