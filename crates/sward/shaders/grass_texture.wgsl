// The far grass's texture (issue 27, point 3): value noise and its three octaves, faded by
// the pixel's footprint. No bindings: the terrain, the billboards' cull and the probe that
// checks it against its CPU twin (`render::far_texture`) include it after common.wgsl.

// Smooth value noise on the unit lattice (the ground's soil and the far grass's texture).
fn value_noise(p: vec2<f32>) -> f32 {
    let i = floor(p);
    let f = fract(p);
    let s = f * f * (3.0 - 2.0 * f);
    let h = vec4<f32>(
        hash01(u32(i32(i.x) * 73856093 ^ i32(i.y) * 19349663)),
        hash01(u32(i32(i.x + 1.0) * 73856093 ^ i32(i.y) * 19349663)),
        hash01(u32(i32(i.x) * 73856093 ^ i32(i.y + 1.0) * 19349663)),
        hash01(u32(i32(i.x + 1.0) * 73856093 ^ i32(i.y + 1.0) * 19349663)),
    );
    return mix(mix(h.x, h.y, s.x), mix(h.z, h.w, s.x), s.y);
}

// The far grass's texture (issue 27, point 3): the grass seen from afar is not one colour
// but patches and clumps of lighter and darker tufts. The ground's three noise octaves
// (periods of 2.9, 0.6 and 0.14 m), each centred on its mean (value noise averages 1/2), so
// the texture averages to 1 and the far ground to the colour the billboards average to;
// each octave fades out as its period nears four pixels (`footprint`, per vertex), which
// filters the texture the way a mip chain would (no shimmer, no tiling: the noise is not
// periodic).
const GRASS_TEXTURE: vec3<f32> = vec3<f32>(0.55, 0.45, 0.3);

// The ground's three noise octaves at world (x, z): periods of 2.9, 0.6 and 0.14 m.
fn grass_octaves(q: vec2<f32>) -> vec3<f32> {
    return vec3<f32>(value_noise(q * 0.35), value_noise(q * 1.7), value_noise(q * 7.0));
}

fn grass_texture(octaves: vec3<f32>, footprint: f32) -> f32 {
    let periods = vec3<f32>(1.0 / 0.35, 1.0 / 1.7, 1.0 / 7.0);
    let keep = 1.0 - smoothstep(vec3<f32>(2.0), vec3<f32>(4.0), footprint / periods * 8.0);
    return 1.0 + dot((octaves - 0.5) * GRASS_TEXTURE, keep);
}

