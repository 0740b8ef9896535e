// The far levels' light gain measured over a frame of one sample per pixel
// (far_gain_common.wgsl).
//!include far_gain_common.wgsl

@group(0) @binding(6) var depth_tex: texture_depth_2d;

fn frame_depth(p: vec2<u32>) -> f32 {
    return textureLoad(depth_tex, p, 0);
}
