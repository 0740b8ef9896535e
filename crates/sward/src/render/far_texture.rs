//! The far grass's texture (issue 27, point 3; `shaders/grass_texture.wgsl`): the CPU twin
//! of its value noise, octaves and footprint fade, and a probe that runs the WGSL on the
//! GPU at given points so tests can hold the two together. The far ground and the cards'
//! roots are shaded with it; its mean is 1, so it keeps the grass's colour on average.
//! The far ground's trail is probed here too ([`probe_trails`]), for the same reason.

use glam::{Vec2, Vec3};

use crate::error::Result;
use crate::gpu::Gpu;
use super::light::sky::smoothstep;

/// How much each octave (periods 2.9, 0.6 and 0.14 m) moves the light, at most
/// (`GRASS_TEXTURE`).
pub const GRASS_TEXTURE: Vec3 = Vec3::new(0.55, 0.45, 0.3);

/// The octaves' frequencies per metre (`grass_octaves`).
const FREQUENCIES: [f32; 3] = [0.35, 1.7, 7.0];

/// Integer hash to [0, 1) (`hash01` in `common.wgsl`).
pub fn hash01(x: u32) -> f32 {
    let mut h = x.wrapping_mul(747_796_405).wrapping_add(2_891_336_453);
    h = ((h >> ((h >> 28) + 4)) ^ h).wrapping_mul(277_803_737);
    h = (h >> 22) ^ h;
    h as f32 / 4_294_967_296.0
}

/// Smooth value noise on the unit lattice (`value_noise`): WGSL's i32 products wrap, as
/// `wrapping_mul` does.
pub fn value_noise(p: Vec2) -> f32 {
    let i = p.floor();
    let f = p - i;
    let s = f * f * (3.0 - 2.0 * f);
    let corner = |dx: f32, dy: f32| {
        let x = ((i.x + dx) as i32).wrapping_mul(73_856_093);
        let y = ((i.y + dy) as i32).wrapping_mul(19_349_663);
        hash01((x ^ y) as u32)
    };
    let (a, b, c, d) = (
        corner(0.0, 0.0),
        corner(1.0, 0.0),
        corner(0.0, 1.0),
        corner(1.0, 1.0),
    );
    let top = a + (b - a) * s.x;
    let bottom = c + (d - c) * s.x;
    top + (bottom - top) * s.y
}

/// The three octaves at world (x, z) (`grass_octaves`).
pub fn grass_octaves(q: Vec2) -> Vec3 {
    Vec3::from(FREQUENCIES.map(|k| value_noise(q * k)))
}

/// The texture from the octaves at a footprint of `footprint` metres per pixel
/// (`grass_texture`): each octave fades out as its period nears four pixels.
pub fn grass_texture(octaves: Vec3, footprint: f32) -> f32 {
    let keep = Vec3::from(FREQUENCIES.map(|k| 1.0 - smoothstep(2.0, 4.0, footprint * k * 8.0)));
    1.0 + ((octaves - 0.5) * GRASS_TEXTURE).dot(keep)
}

/// The WGSL at `points` (world x, z and the footprint): each point's octaves and texture,
/// read back from the GPU.
pub fn probe_grass_texture(gpu: &Gpu, points: &[Vec3]) -> Result<Vec<(Vec3, f32)>> {
    let flat: Vec<[f32; 4]> = points.iter().map(|p| [p.x, p.y, p.z, 0.0]).collect();
    let values = crate::gpu::run_vec4_probe(
        gpu,
        "sward.grass_texture_probe",
        "grass_texture_probe.wgsl",
        &[bytemuck::cast_slice(&flat)],
        points.len(),
    )?;
    Ok(values
        .iter()
        .map(|v| (Vec3::new(v[0], v[1], v[2]), v[3]))
        .collect())
}

/// The far ground's trail at `points` (world x, z), read back from the GPU: per point the
/// interpolated wave (`trail_wave_smooth`) and the trail at the point (`trail_at`: η, bend
/// x, bend z), from the map `words` (a read-back [`crate::sim::update::BladeBuffers`]
/// trail map, or one written on the CPU).
pub fn probe_trails(gpu: &Gpu, words: &[u32], points: &[glam::Vec2]) -> Result<Vec<(f32, Vec3)>> {
    let flat: Vec<[f32; 4]> = points.iter().map(|p| [p.x, p.y, 0.0, 0.0]).collect();
    let mut map = words.to_vec();
    map.resize(map.len().max(crate::field::trails::HEADER_WORDS as usize), 0);
    let values = crate::gpu::run_vec4_probe(
        gpu,
        "sward.trail_probe",
        "trail_probe.wgsl",
        &[bytemuck::cast_slice(&map), bytemuck::cast_slice(&flat)],
        points.len(),
    )?;
    Ok(values
        .iter()
        .map(|v| (v[0], Vec3::new(v[1], v[2], v[3])))
        .collect())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The texture averages to 1 over many points at every footprint, and a footprint of
    /// many metres per pixel leaves it flat.
    #[test]
    fn the_texture_averages_to_one_and_fades_with_the_footprint() {
        for footprint in [0.001, 0.05, 0.3, 2.0] {
            let n = 40_000;
            let mean = (0..n)
                .map(|k| {
                    let q = Vec2::new((k % 200) as f32 * 0.731, (k / 200) as f32 * 0.917);
                    grass_texture(grass_octaves(q), footprint)
                })
                .sum::<f32>()
                / n as f32;
            assert!(
                (mean - 1.0).abs() < 0.02,
                "footprint {footprint}: mean {mean}"
            );
        }
        let q = Vec2::new(3.3, -7.1);
        assert_eq!(grass_texture(grass_octaves(q), 10.0), 1.0);
        assert_ne!(grass_texture(grass_octaves(q), 0.001), 1.0);
    }
}
