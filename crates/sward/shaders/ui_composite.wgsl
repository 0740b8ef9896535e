// The window's panel, drawn once into a cache texture by egui and composited over each
// frame (`app::ui_cache`): one full-screen triangle, scissored to what egui drew, that
// copies the cache's premultiplied texels over the frame (the pipeline blends One,
// OneMinusSrcAlpha, as egui's own does). The cache has the window's format and size, so a
// pixel is read at its own position and nothing is filtered.

@group(0) @binding(0) var cache: texture_2d<f32>;

@vertex
fn vs_composite(@builtin(vertex_index) vid: u32) -> @builtin(position) vec4<f32> {
    let xy = vec2<f32>(f32((vid << 1u) & 2u), f32(vid & 2u)) * 2.0 - 1.0;
    return vec4<f32>(xy, 0.0, 1.0);
}

@fragment
fn fs_composite(@builtin(position) pixel: vec4<f32>) -> @location(0) vec4<f32> {
    return textureLoad(cache, vec2<i32>(pixel.xy), 0);
}
