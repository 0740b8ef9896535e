// Deferred grass shading (issue 26, point 5: the lit shading once per covered pixel;
// `render/deferred.rs`). A software rasteriser shades a fragment for every pixel of each
// 4 x 4 block a blade touches, and blades a pixel or two wide touch many blocks with few
// pixels each: the forward grass ran its lighting about 25 times per covered pixel. Here
// the draw only writes which blade and where on it (the visibility buffer), and the light
// runs once per grass pixel, in compute, which spreads over every core:
//
// 1. `vs_vis` / `fs_vis`: the blades' geometry as the lit pass builds it (`blade_vertex`);
//    each fragment writes (blade index, pack2x16unorm(u, v), its depth's bits, 1).
// 2. `grass_pixels`: one invocation per pixel keeps the pixels whose visibility texel is
//    grass and whose depth is still the grass's (an object or the ground drawn later in
//    front of it changed the depth), appending them to a list; every 256th appended pixel
//    adds a workgroup to the shading's indirect dispatch.
// 3. `shade_pixels`: one invocation per listed pixel rebuilds the blade's point at (u, v)
//    on its curve (Eq. 21-24, as the vertex stage does), its colours and the sun's
//    visibility there, lights it with the forward pass's own `shade_blade` and fog, and
//    writes the scene target.
//
// Used when the grass pipelines are specialised without flowers and debug views, with
// one sample per pixel and filled triangles; otherwise the grass is drawn forward.
//!include grass.wgsl

@group(2) @binding(0) var vis_buffer: texture_2d<u32>;
@group(2) @binding(1) var depth_buffer: texture_depth_2d;
@group(2) @binding(2) var scene_out: texture_storage_2d<rgba16float, write>;
@group(2) @binding(3) var<storage, read_write> pixel_list: PixelList;
// Bound to the pixel pass only: the shading pass reads it as its indirect arguments, which
// a storage binding in the same dispatch may not (it binds a stand-in).
@group(2) @binding(4) var<storage, read_write> shade_args: ShadeArgs;

// The grass pixels, packed (y << 16 | x), and how many; `count` is cleared every frame.
struct PixelList {
    count: atomic<u32>,
    pixels: array<u32>,
}

// The shading's `dispatch_workgroups_indirect` arguments: x (cleared every frame) grows
// by one workgroup per SHADE_GROUP listed pixels; y and z stay 1.
struct ShadeArgs {
    x: atomic<u32>,
    y: u32,
    z: u32,
    pad: u32,
}

// Invocations per workgroup of `shade_pixels` (twin: `deferred::SHADE_GROUP`): 256, the
// most every adapter allows, so a 4K frame's grass needs at most 32,400 workgroups, under
// the 65,535 a dispatch may have along x.
const SHADE_GROUP: u32 = 256u;

struct VisOut {
    // Invariant: the same depth as the lit pass and the coverage measurement.
    @builtin(position) @invariant clip: vec4<f32>,
    @location(0) uv: vec2<f32>,
    @location(1) @interpolate(flat) blade: u32,
}

@vertex
fn vs_vis(@builtin(vertex_index) batch_vid: u32, @builtin(instance_index) inst: u32) -> VisOut {
    let b = blade_vertex(batch_vid, inst);
    var out: VisOut;
    out.clip = b.out.clip;
    out.uv = b.out.uv;
    out.blade = b.index;
    return out;
}

@fragment
fn fs_vis(in: VisOut) -> @location(0) vec4<u32> {
    let uv = clamp(in.uv, vec2<f32>(0.0), vec2<f32>(1.0));
    return vec4<u32>(in.blade, pack2x16unorm(uv), bitcast<u32>(in.clip.z), 1u);
}

@compute @workgroup_size(8, 8)
fn grass_pixels(@builtin(global_invocation_id) gid: vec3<u32>) {
    let size = textureDimensions(vis_buffer);
    if gid.x >= size.x || gid.y >= size.y {
        return;
    }
    let px = vec2<i32>(gid.xy);
    let vis = textureLoad(vis_buffer, px, 0);
    if vis.w == 0u || bitcast<f32>(vis.z) != textureLoad(depth_buffer, px, 0) {
        return;
    }
    let i = atomicAdd(&pixel_list.count, 1u);
    if i % SHADE_GROUP == 0u {
        atomicAdd(&shade_args.x, 1u);
    }
    // Targets are at most 65536 wide (`DeferredTargets::fits`): 16 bits each.
    pixel_list.pixels[i] = (gid.y << 16u) | gid.x;
}

@compute @workgroup_size(256)
fn shade_pixels(@builtin(global_invocation_id) gid: vec3<u32>) {
    if gid.x >= atomicLoad(&pixel_list.count) {
        return;
    }
    let packed = pixel_list.pixels[gid.x];
    let px = vec2<i32>(vec2<u32>(packed & 0xffffu, packed >> 16u));
    let vis = textureLoad(vis_buffer, px, 0);
    let index = vis.x;
    let uv = unpack2x16unorm(vis.y);
    let blade = blades[index];
    let ctx = blade_ctx(blade);
    let point = blade_point(blade, ctx, index, uv.x, uv.y, 0.0);
    // Two-sided, as the forward fragment stage lights it.
    var flat_n = normalize(point.n);
    if dot(flat_n, frame.camera_pos.xyz - point.p) < 0.0 {
        flat_n = -flat_n;
    }
    let albedo = blade_albedos(index, blade);
    let colour = shade_blade(
        point.p,
        flat_n,
        ctx.side,
        uv,
        mix(albedo.root, albedo.tip.rgb, uv.y),
        sun_visibility(point.p),
        blade_self_shade(blade, point.p),
    );
    let v0 = blade.v0_dir.xyz;
    textureStore(scene_out, px, vec4<f32>(fog_towards(colour, point.p, blade_sky(v0)), 1.0));
}
