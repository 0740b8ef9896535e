// Hierarchical depth pyramid ("Hi-Z") for occlusion culling, built by
// `render::hiz::DepthPyramid`. Depth runs 0 (near) to 1 (far), so every texel keeps the MAX
// (farthest) depth of the pixels it covers: a blade nearer than that texel somewhere is
// possibly visible, one behind it everywhere is hidden. CPU twin: `reference::hiz`.
//
// Level 0 is the depth buffer itself: the cull reads it directly, so it is not copied
// (writing a copy of every pixel cost about 4 ms of a 1280x720 pyramid on llvmpipe). The
// pyramid texture holds levels 1 and up. `reduce_depth` writes level 1 from the depth
// buffer (a storage texture cannot be a depth format, and textureLoad on r32float is core);
// `downsample` writes level k from level k-1, one dispatch per level.
//
// With MSAA the 3D passes draw into a multisampled depth buffer: `copy_depth2_ms` writes a
// level 0 of its own, the FARTHEST of each pixel's samples (so a blade hidden by the texel
// is hidden behind every sample of it, and occlusion stays conservative), and level 1 from
// it in the same dispatch; `copy_depth_ms` writes level 0 alone for a 1 x 1 target.
// `dump_samples` copies every sample into a buffer (multisampled textures cannot be copied
// out): the test of that reduction compares level 0 with the CPU max over the dumped
// samples.

@group(0) @binding(0) var depth: texture_depth_2d;
@group(0) @binding(1) var src: texture_2d<f32>;
@group(0) @binding(2) var dst: texture_storage_2d<r32float, write>;
@group(0) @binding(3) var depth_ms: texture_depth_multisampled_2d;
@group(0) @binding(4) var<storage, read_write> samples_out: array<f32>;
// Level 1, written by the multisampled copy with level 0.
@group(0) @binding(5) var dst1: texture_storage_2d<r32float, write>;

// The texels of level 0 under texel `p` of level 1: 2 x 2, and for the last column/row of
// an odd-sized level 0 the extra one too (as `downsample` reads them). Returns [start, end).
fn footprint(p: vec2<u32>, size1: vec2<u32>, size0: vec2<u32>) -> vec4<u32> {
    let start = p * 2u;
    var end = min(start + vec2<u32>(2u), size0);
    if p.x == size1.x - 1u {
        end.x = size0.x;
    }
    if p.y == size1.y - 1u {
        end.y = size0.y;
    }
    return vec4<u32>(start, end);
}

// Level 1 from the depth buffer (level 0): one invocation per texel of level 1 (`dst`
// here) keeps the farthest of the depth texels under it.
@compute @workgroup_size(8, 8)
fn reduce_depth(@builtin(global_invocation_id) gid: vec3<u32>) {
    let size1 = textureDimensions(dst);
    if gid.x >= size1.x || gid.y >= size1.y {
        return;
    }
    let f = footprint(gid.xy, size1, textureDimensions(depth));
    var far = 0.0;
    for (var y = f.y; y < f.w; y++) {
        for (var x = f.x; x < f.z; x++) {
            far = max(far, textureLoad(depth, vec2<i32>(vec2<u32>(x, y)), 0));
        }
    }
    textureStore(dst, vec2<i32>(gid.xy), vec4<f32>(far, 0.0, 0.0, 0.0));
}

// Level 0 (the farthest sample of each pixel, into `dst`) and level 1 (into `dst1`) in
// one pass: one invocation per texel of level 1 writes the level-0 texels under it and
// their farthest, so level 0 is not read back by a second pass.
@compute @workgroup_size(8, 8)
fn copy_depth2_ms(@builtin(global_invocation_id) gid: vec3<u32>) {
    let size1 = textureDimensions(dst1);
    if gid.x >= size1.x || gid.y >= size1.y {
        return;
    }
    let f = footprint(gid.xy, size1, textureDimensions(dst));
    var far = 0.0;
    for (var y = f.y; y < f.w; y++) {
        for (var x = f.x; x < f.z; x++) {
            let p = vec2<i32>(vec2<u32>(x, y));
            var d = 0.0;
            for (var s = 0u; s < textureNumSamples(depth_ms); s++) {
                d = max(d, textureLoad(depth_ms, p, i32(s)));
            }
            textureStore(dst, p, vec4<f32>(d, 0.0, 0.0, 0.0));
            far = max(far, d);
        }
    }
    textureStore(dst1, vec2<i32>(gid.xy), vec4<f32>(far, 0.0, 0.0, 0.0));
}

@compute @workgroup_size(8, 8)
fn copy_depth_ms(@builtin(global_invocation_id) gid: vec3<u32>) {
    let size = textureDimensions(dst);
    if gid.x >= size.x || gid.y >= size.y {
        return;
    }
    var far = 0.0;
    for (var s = 0u; s < textureNumSamples(depth_ms); s++) {
        far = max(far, textureLoad(depth_ms, vec2<i32>(gid.xy), i32(s)));
    }
    textureStore(dst, vec2<i32>(gid.xy), vec4<f32>(far, 0.0, 0.0, 0.0));
}

// Pixel (x, y) of a single-sample depth goes to samples_out[y * width + x].
@compute @workgroup_size(8, 8)
fn dump_depth(@builtin(global_invocation_id) gid: vec3<u32>) {
    let size = textureDimensions(depth);
    if gid.x >= size.x || gid.y >= size.y {
        return;
    }
    samples_out[gid.y * size.x + gid.x] = textureLoad(depth, vec2<i32>(gid.xy), 0);
}

// Sample s of pixel (x, y) goes to samples_out[(y * width + x) * samples + s].
@compute @workgroup_size(8, 8)
fn dump_samples(@builtin(global_invocation_id) gid: vec3<u32>) {
    let size = textureDimensions(depth_ms);
    if gid.x >= size.x || gid.y >= size.y {
        return;
    }
    let n = textureNumSamples(depth_ms);
    let base = (gid.y * size.x + gid.x) * n;
    for (var s = 0u; s < n; s++) {
        samples_out[base + s] = textureLoad(depth_ms, vec2<i32>(gid.xy), i32(s));
    }
}

@compute @workgroup_size(8, 8)
fn downsample(@builtin(global_invocation_id) gid: vec3<u32>) {
    let size = textureDimensions(dst);
    if gid.x >= size.x || gid.y >= size.y {
        return;
    }
    let src_size = textureDimensions(src);
    // The 2x2 texels below, and for the last column/row of an odd-sized level the extra
    // one too (3 wide): mip sizes round down, so without it that column would be dropped
    // and the pyramid would no longer be conservative. A 1-texel-wide source (the other
    // axis still halving) gives a 1-wide footprint.
    let start = gid.xy * 2u;
    var end = min(start + vec2<u32>(2u), src_size);
    if gid.x == size.x - 1u {
        end.x = src_size.x;
    }
    if gid.y == size.y - 1u {
        end.y = src_size.y;
    }
    var far = 0.0;
    for (var y = start.y; y < end.y; y++) {
        for (var x = start.x; x < end.x; x++) {
            far = max(far, textureLoad(src, vec2<i32>(vec2<u32>(x, y)), 0).x);
        }
    }
    textureStore(dst, vec2<i32>(gid.xy), vec4<f32>(far, 0.0, 0.0, 0.0));
}
