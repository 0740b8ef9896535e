// Terrain: a geometry clipmap around the camera (src/render/clipmap.rs). Each instance is
// one level: a grid of `terrain.grid.y` cells per side whose vertex position comes from the
// vertex index, its height and normal from `terrain_height` (the twin of the CPU's
// HeightField). Near its outer edge a level's odd vertices slide onto their even
// neighbours, so the edge it shares with the next, twice as coarse level is the same line
// on both sides: no cracks. Lit by the sun and the sky; the colour blends from soil under
// the near blades to the grass's own mean colour with distance, then into the fog.
//!include common.wgsl
//!include light.wgsl
//!include blade_shade.wgsl
//!include far_grass.wgsl
//!include terrain_height.wgsl
//!include far_gain_math.wgsl
//!include canopy.wgsl

@group(0) @binding(0) var<uniform> frame: Frame;
@group(0) @binding(3) var density_map: texture_2d<f32>;
@group(0) @binding(4) var density_sampler: sampler;
// The far state: the gusts' bend at the edge of the blades' reach (`CullCounters::wave_sum`,
// `wave_blades`), in word 2 the far field's distance gain, in words 4-7 the far levels'
// measured light gain and in word 11 their contrast gain (far_gain_math.wgsl).
@group(0) @binding(5) var<storage, read> waves: array<u32, FAR_STATE_WORDS>;
// The trail map (`trails.wgsl`): a path pressed into the grass shows on the far ground.
@group(0) @binding(6) var<storage, read> trails: array<u32>;
// The canopy seen from above (`render::far_canopy`, canopy.wgsl): brightness factors over
// CANOPY_SCALE, one layer per cell of ground.
@group(0) @binding(7) var canopy_tex: texture_2d_array<f32>;
@group(0) @binding(8) var canopy_sampler: sampler;

// Whether the field has a trail map at all (a streamed field with `physics.trails`): without
// one the lookup is compiled out, as a software rasteriser would run it for every ground
// pixel even where it returns at once.
override TRAILS: bool = true;

// Whether the scene has a density map (`TerrainSpec::density_map`): without one its
// lookup is compiled out, for the same reason.
override DENSITY_MAP: bool = true;

fn trail_word(i: u32) -> u32 {
    return trails[i];
}
//!include trails.wgsl

struct VertexOut {
    // Invariant: the depth prepass and the colour pass must produce the same depth.
    @builtin(position) @invariant clip: vec4<f32>,
    @location(0) world: vec3<f32>,
    @location(1) normal: vec3<f32>,
    // The sky's radiance along the view ray to this vertex, the fog's colour (`vs_lit`).
    @location(2) sky: vec3<f32>,
    // The far grass's light here (`far_grass_light`, `vs_lit`): the sky's part and the
    // sun's part when the sun is not shadowed.
    @location(3) grass_ambient: vec3<f32>,
    @location(4) grass_sun: vec3<f32>,
    // Metres of ground per pixel here, along the view (`vs_lit`): how fine a texture the
    // pixels can show.
    @location(5) footprint: f32,
}

// Past the far plane the ground is not clipped: its depth is squeezed into the last
// FAR_BAND below 1 (the sky's depth), as 1 − FAR_BAND·far/w, which still grows with the
// view depth w, so far hills keep their order (about 160 Depth32 steps from the far plane
// to infinity). Nearer than about 283 m of a 300 m far plane the normal depth is below that
// band, so nothing in range is ordered wrongly against it.
const FAR_BAND: f32 = 1e-5;

// Twin of `clipmap::vertex_xz`: where vertex `vid` of level `level` lies for a camera at
// `eye` (x, z).
fn clipmap_xz(vid: u32, level: u32, eye: vec2<f32>) -> vec2<f32> {
    let n = terrain.grid.y;
    let ij = vec2<u32>(vid % (n + 1u), vid / (n + 1u));
    let l = terrain.levels[level];
    let cell = l.z;
    let local = vec2<f32>(vec2<i32>(ij) - vec2<i32>(i32(n / 2u)));
    var xz = l.xy + local * cell;
    // Morph factor: 0 inside, 1 from one cell inside the outer edge (Chebyshev distance
    // from the camera, in cells); the band is `terrain.grid.z` cells wide.
    let d = max(abs(xz.x - eye.x), abs(xz.y - eye.y)) / cell;
    let band = f32(terrain.grid.z);
    let outer = f32(n / 2u) - 1.0;
    let morph = clamp((d - (outer - band)) / band, 0.0, 1.0);
    xz -= vec2<f32>(ij % vec2<u32>(2u)) * morph * cell;
    if terrain.info.z == 0u {
        let half = 0.5 * terrain.noise.w;
        xz = clamp(xz, vec2<f32>(-half), vec2<f32>(half));
    }
    return xz;
}

// The depth pass (no light bound): the vertex only.
@vertex
fn vs_main(@builtin(vertex_index) vid: u32, @builtin(instance_index) level: u32) -> VertexOut {
    return terrain_vertex(vid, level);
}

// The lit pass: the vertex, the sky behind it and the far grass's light, looked up per
// vertex: the Perez sky and the grass's light change with the view direction and the
// ground's normal only, smoothly across a clipmap cell, and per fragment they would cost
// every ground pixel.
@vertex
fn vs_lit(@builtin(vertex_index) vid: u32, @builtin(instance_index) level: u32) -> VertexOut {
    var out = terrain_vertex(vid, level);
    let to_p = out.world - frame.camera_pos.xyz;
    out.sky = sky_radiance(to_p / max(length(to_p), 1e-4));
    let grass = far_grass_light(out.world, out.normal, terrain.grass_albedo.rgb, mean_wave(waves[0], waves[1]));
    // Calibrated on the blades this light stands for (`far_gain`), at its distance
    // (`distance_gain`) and in its direction from the camera (`sector_gain`).
    let sector = sector_pair(to_p.xz);
    let gain = far_gain(vec4<u32>(waves[4], waves[5], waves[6], waves[7]))
        * distance_gain(length(to_p), frame.thinning_reach.x, waves[2])
        * sector_gain(sector, waves[SECTOR_WORD + sector.a], waves[SECTOR_WORD + sector.b]);
    out.grass_ambient = grass.ambient * gain;
    out.grass_sun = grass.sun * gain;
    // A pixel spans 2 w / (P11 · height) metres across the view at view depth w (P11 the
    // projection's y scale: the length of clip y's row, whatever the camera's rotation),
    // stretched by the grazing angle along the ground.
    let m = terrain.view_proj_relative;
    let p11 = length(vec3<f32>(m[0][1], m[1][1], m[2][1]));
    let across = 2.0 * out.clip.w / max(p11 * frame.viewport_time.y, 1e-6);
    let dist = max(length(to_p), 1e-4);
    out.footprint = across / max(abs(dot(out.normal, to_p)) / dist, 0.05);
    return out;
}

fn terrain_vertex(vid: u32, level: u32) -> VertexOut {
    let xz = clipmap_xz(vid, level, frame.camera_pos.xz);
    let h = terrain_height(xz);
    let world = vec3<f32>(xz.x, h.x, xz.y);
    var out: VertexOut;
    // Camera-relative: world − eye is small and exact near the camera, wherever it flies.
    var clip = terrain.view_proj_relative * vec4<f32>(world - frame.camera_pos.xyz, 1.0);
    let far = terrain.blend.w;
    if clip.w > far && far > 0.0 {
        clip.z = clip.w * (1.0 - FAR_BAND * far / clip.w);
    }
    out.clip = clip;
    out.world = world;
    out.normal = normalize(vec3<f32>(-h.y, 1.0, -h.z));
    return out;
}

// The terrain into a sun's shadow cascade (frame.view_proj is the cascade's): the same
// clipmap around the camera, in world space.
@vertex
fn vs_shadow(@builtin(vertex_index) vid: u32, @builtin(instance_index) level: u32) -> @builtin(position) vec4<f32> {
    let xz = clipmap_xz(vid, level, frame.camera_pos.xz);
    let h = terrain_height(xz);
    return frame.view_proj * vec4<f32>(xz.x, h.x, xz.y, 1.0);
}

// Grass density at world (x, z): the scene's density map stretched over the square, its
// edge continuing outside; 1 without a map.
fn grass_density(xz: vec2<f32>) -> f32 {
    if !DENSITY_MAP {
        return 1.0;
    }
    let dims = vec2<f32>(textureDimensions(density_map));
    let g = (xz / terrain.noise.w + 0.5) * (dims - 1.0);
    return textureSampleLevel(density_map, density_sampler, (g + 0.5) / dims, 0.0).r;
}

@fragment
fn fs_main(in: VertexOut) -> @location(0) vec4<f32> {
    let n = normalize(in.normal);
    let sun = frame.sun_dir.xyz;
    let q = in.world.xz;
    // The ground's change across the pixel, for the canopy's mip (taken here, in uniform
    // control flow).
    let dqx = dpdx(q);
    let dqy = dpdy(q);
    let octaves = grass_octaves(q);
    let patchy = dot(octaves, vec3<f32>(0.6, 0.3, 0.1));
    let soil = vec3<f32>(0.13, 0.11, 0.06);
    let turf = vec3<f32>(0.06, 0.15, 0.03);
    let ground = mix(soil, turf, smoothstep(0.15, 0.55, patchy));
    let lit = sun_visibility(in.world);
    let diffuse = max(dot(n, sun), 0.0) * lit;
    let near = ground * (light.ambient.rgb * (0.5 + 0.5 * n.y) + light.sun.rgb * diffuse * 1.5);
    // The grass seen from afar: the blades' own light averaged over the blades a distant
    // eye sees (`far_grass_light`, per vertex), the sun's part shadowed here.
    var grass = (in.grass_ambient + lit * in.grass_sun) * grass_texture(octaves, in.footprint);
    // Soil shows between the near blades; with distance the blades cover it, and past
    // the culling distance only their colour is left. Outside the square, where no blades
    // grow yet, the ground is grass-coloured at any distance (over a 2 m band at the edge):
    // it stands for the prairie that continues, not for bare earth where the world ends.
    let dist = distance(in.world, frame.camera_pos.xyz);
    // A streamed field (grid.w = 1) grows blades there too: no such band then.
    var outside = smoothstep(0.0, 2.0, max(abs(q.x), abs(q.y)) - 0.5 * terrain.noise.w);
    if terrain.grid.w == 1u {
        outside = 0.0;
    }
    let cover = max(smoothstep(terrain.blend.x, terrain.blend.y, dist), outside) * grass_density(q);
    // Seen from above, the canopy's tops and gaps (canopy.wgsl), from a lower elevation
    // than the cards fade out at (`canopy_ground_weight`), so that the ground between
    // their rows shows them; sharpened and with the cards' contrast gain near the blades,
    // handed over to the
    // texture's own as a pixel grows to span the blades' height (as the cards'). Only
    // where the far grass shows, as the trails below: the soil under the near blades has
    // none of it (the same pixels; the prairie's frame at 1280x720 on llvmpipe did not
    // change measurably, 703/663 against 686/693 ms, alternating).
    let top = canopy_ground_weight(in.world, frame.camera_pos.xyz);
    if top > 0.0 && cover > 0.0 {
        // The pixel's size across the view (the footprint without its stretch along a
        // grazing view, as the cards take theirs: a pixel spans that much of the blades'
        // height).
        let to_eye = frame.camera_pos.xyz - in.world;
        let across = in.footprint * max(dot(n, to_eye) / max(dist, 1e-4), 0.05);
        let handover = smoothstep(CONTRAST_FOOTPRINT.x, CONTRAST_FOOTPRINT.y, across / max(terrain.grass_albedo.w, 1e-3));
        let f = canopy_factor(canopy_tex, canopy_sampler, q, dqx, dqy, CARD_SHARPEN * (1.0 - handover));
        let k = mix(contrast_gain(waves[11]), 1.0, handover);
        grass *= mix(1.0, contrast_luma(f, 1.0, k), top);
    }
    // A trail here: its pressed blades show their paler side, as the billboards' and the
    // blades' do (`blade_albedo`: a → 1.7 a + 0.04 at 0.6 of the wave; at the far albedo,
    // about 0.1, that is 2.1 a, so the grass is 1 + 0.66 w times as bright). Only where
    // the far grass shows: under the blades the map is theirs to show, and its table probe
    // is the dearest read of this shader.
    if TRAILS {
        if cover > 0.0 && light.shading_b.y > 0.0 {
            grass *= 1.0 + 0.66 * trail_wave_smooth(q.x, q.y) * light.shading_b.y;
        }
    }
    var color = mix(near, grass, cover);
    color = fog_towards(color, in.world, in.sky);
    return vec4<f32>(color, 1.0);
}
