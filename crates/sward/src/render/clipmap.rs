//! The terrain as a geometry clipmap (Losasso & Hoppe 2004, with the vertex morph of
//! Strugar's CDLOD): nested square levels of [`RING_CELLS`] cells per side around the
//! camera, each level's cells twice as large as the one inside it, out to the far plane
//! and past it until the fog has turned the ground into sky. Heights are not stored: the
//! vertex shader evaluates the terrain's height function (`shaders/terrain_height.wgsl`,
//! the twin of [`HeightField::height`]) at each vertex, so the ground has no edge and costs
//! the same memory wherever the camera flies.
//!
//! Why a clipmap and not a chunked quadtree: the terrain is a function, not data to page
//! in, so there is nothing to stream per chunk; a clipmap is a fixed index buffer drawn
//! once per level with no CPU-side tree walk, no chunk pool and no per-chunk draw calls,
//! and its detail falls off with distance uniformly in every direction, which is what a
//! ground seen from a walking or flying camera needs.
//!
//! Layout: level `k` has cell size `c_k = c_0·2^k` and is centred on the camera's (x, z)
//! rounded to a multiple of `2·c_k`, so its vertices are a superset of level `k+1`'s.
//! Level 0 is a full grid; every other level leaves out the `RING_CELLS/2` square of cells
//! that the level inside it covers. Where that hole sits in a level depends on how the
//! two centres round (one of 3×3 offsets), so the index buffer holds the full grid plus the
//! nine hole variants and each level draws the one it needs. Cracks: near its outer edge a
//! level's odd vertices slide onto their even neighbours ([`MORPH_CELLS`] wide band, by
//! Chebyshev distance from the camera), reaching them one cell inside the edge, so the
//! outer edge is exactly the coarser level's edge (same (x, z), same function).
//!
//! Precision: level centres are multiples of `c_0`, a power of two, so vertex (x, z) are
//! exact in f32 out to about 4000 km at `c_0` = 0.25 m; the noise is evaluated at those
//! world coordinates (lattice coordinates in f32 keep about 1e-4 of a cell at 10 km).
//! The terrain is drawn camera-relative: the vertex shader subtracts the eye from the
//! world position (exact for nearby vertices) and applies a view-projection built for a
//! camera at the origin, so no large translation cancels inside the matrix product.
//!
//! Past the far plane the vertex shader squeezes depth into a thin band just in front of
//! the sky (still growing with distance, so far hills keep their order), so the ground
//! runs on to the horizon instead of ending in a clipped edge.

use glam::{Vec2, Vec3};

use crate::field::{HeightField, Surface};

/// Cells per side of every level (a multiple of 8, so the hole and the morph band fit).
/// A cell covers about the same share of the screen at every level, and this sets it: at
/// 64 a cell seen at a grazing angle was a few pixels tall, and llvmpipe shades every
/// 4 × 4 block a triangle touches, so the ground was shaded about 2.9 times per pixel and
/// each of its 36,000 vertices (evaluated again for the depth pass and every shadow cascade)
/// cost the single-threaded vertex stage. 32 quarters the vertices and halves the
/// rasterised triangles; the hills' smooth heights show no facet at either (nature and the
/// prairie at 1280x720 and 960x540 differ by a mean 0.02 % and 0.003 %).
pub const RING_CELLS: u32 = 32;
/// Width of the morph band in cells: inside the ring, which is `RING_CELLS/4 − 1` cells
/// wide at its narrowest (the hole's offset takes one).
pub const MORPH_CELLS: u32 = 4;
/// Most levels drawn: 32 cells of 0.25 m doubled 15 times is 131 km across.
pub const MAX_LEVELS: usize = 16;
/// The ground is drawn out to this many fog distances (and at least to the far plane):
/// `1 − e^−6`, the fog is 99.75 % sky colour there.
pub const FOG_REACH: f32 = 6.0;
/// Index-buffer variants: the full grid, then the nine hole offsets.
pub const VARIANTS: usize = 10;

/// Uniforms of the terrain height function and clipmap; the twin of WGSL `TerrainParams`.
#[repr(C)]
#[derive(Clone, Copy, Debug, bytemuck::Pod, bytemuck::Zeroable, PartialEq)]
pub struct TerrainUniforms {
    /// The camera's view-projection for positions relative to the eye.
    pub view_proj_relative: [[f32; 4]; 4],
    /// x: mode (0 analytic fBm, 1 grid), y: octaves, z: 1 = unbounded, w: levels.
    pub info: [u32; 4],
    /// x: wavelength m, y: mid, z: scale m, w: terrain size m.
    pub noise: [f32; 4],
    /// 32-bit lattice seed of each octave.
    pub seeds: [[u32; 4]; 3],
    /// x: grid resolution, y: cells per ring side, z: morph band cells.
    pub grid: [u32; 4],
    /// x: soil-to-grass blend start m, y: end m, z: 1 = density map bound, w: far plane m.
    pub blend: [f32; 4],
    /// rgb: the grass's mean albedo; w: the tallest blade (m).
    pub grass_albedo: [f32; 4],
    /// Per level: centre x, z, cell size.
    pub levels: [[f32; 4]; MAX_LEVELS],
}

const _: () = assert!(std::mem::size_of::<TerrainUniforms>() == 448);

/// The mean albedo of the grass as `shaders/grass.wgsl` colours it, averaged over the
/// per-blade random tints (uniform in [0, 1)) and over the upper three quarters of the
/// blade that a distant view sees (v from 0.25 to 1): the colour the far ground takes.
pub fn far_grass_albedo() -> Vec3 {
    let fresh = Vec3::new(0.10, 0.34, 0.05);
    let dry = Vec3::new(0.32, 0.40, 0.09);
    let deep = Vec3::new(0.05, 0.22, 0.04);
    // E[tint.y] = 1/2, E[tint.x²] = 1/3; the mixes are linear in them.
    let base = fresh.lerp(deep, 0.5 * 0.7).lerp(dry, 0.8 / 3.0);
    // mix(a·0.55, a·1.25 + c, v) averaged over v in [0.25, 1]: v̄ = 0.625.
    let v = 0.625;
    (base * 0.55).lerp(base * 1.25 + Vec3::new(0.03, 0.04, 0.0), v)
}

/// The far ground's colour for `field`: the mean of its species' colours by share (each
/// with the along-the-blade shading of [`far_grass_albedo`]; sward's own palette for a
/// field without species), with its flowers' petals mixed in by the share of the ground
/// their heads cover seen from above (blades per m² × fraction × π r², at most a half).
pub fn far_albedo(field: &crate::scene::Field) -> Vec3 {
    let shade = |a: Vec3| (a * 0.55).lerp(a * 1.25 + Vec3::new(0.03, 0.04, 0.0), 0.625);
    let mut albedo = if field.species.is_empty() {
        far_grass_albedo()
    } else {
        let total: f32 = field.species.iter().map(|s| s.share).sum();
        field
            .species
            .iter()
            .map(|s| shade(Vec3::from(s.color)) * (s.share / total.max(1e-6)))
            .sum()
    };
    if let Some(f) = field.flowers.as_ref().filter(|f| !f.kinds.is_empty()) {
        let petals: Vec3 =
            f.kinds.iter().map(|k| Vec3::from(k.petals)).sum::<Vec3>() / f.kinds.len() as f32;
        let cover = (field.density * f.fraction * std::f32::consts::PI * f.head_size * f.head_size)
            .clamp(0.0, 0.5);
        albedo = albedo.lerp(petals, cover);
    }
    albedo
}

/// Distances over which the ground turns from soil to grass colour: from a quarter of the
/// culling distance to the culling distance. Blades thin out with distance (distance
/// culling, Jahrmann & Wimmer Section 4.3) and go sub-pixel; the ground takes over the
/// colour they had, and past the culling distance, where no blade is drawn, it is fully
/// grass-coloured (times the density map: bare soil where the map says no grass).
pub fn grass_blend(max_distance: f32) -> (f32, f32) {
    let end = if max_distance.is_finite() && max_distance > 0.0 {
        max_distance
    } else {
        60.0
    };
    (0.25 * end, end)
}

/// Finest cell size: the power of two at or below the grid spacing, within 1/16..4 m.
pub fn finest_cell(terrain: &HeightField) -> f32 {
    let s = terrain.spacing().clamp(1.0 / 16.0, 4.0);
    2f32.powi(s.log2().floor() as i32)
}

/// Levels needed to reach `reach` metres from the camera in every direction.
pub fn level_count(cell0: f32, reach: f32) -> u32 {
    let mut levels = 1;
    // A level reaches at least (RING_CELLS/2 − 1) cells from the camera.
    while (levels as usize) < MAX_LEVELS
        && (RING_CELLS / 2 - 1) as f32 * cell0 * 2f32.powi(levels as i32 - 1) < reach
    {
        levels += 1;
    }
    levels
}

/// Centre of level `k` of a camera at `eye` (x, z): the eye rounded to a multiple of
/// `2·c_k`.
pub fn level_centre(cell0: f32, k: u32, eye: Vec2) -> Vec2 {
    let step = f64::from(cell0) * 2f64.powi(k as i32 + 1);
    let snap = |v: f32| ((f64::from(v) / step).round() * step) as f32;
    Vec2::new(snap(eye.x), snap(eye.y))
}

/// Which index-buffer variant level `k` draws: 0 (full) for level 0, else the offset of
/// the hole, the centre of level `k − 1` minus this level's centre in cells, each in −1..=1.
pub fn variant(uniforms: &TerrainUniforms, k: usize) -> usize {
    if k == 0 {
        return 0;
    }
    let (inner, outer) = (uniforms.levels[k - 1], uniforms.levels[k]);
    let d = |a: f32, b: f32| (((a - b) / outer[2]).round() as i32).clamp(-1, 1);
    let dx = d(inner[0], outer[0]);
    let dz = d(inner[1], outer[1]);
    1 + (dx + 1) as usize + 3 * (dz + 1) as usize
}

/// The index buffer of every variant, concatenated, and each variant's (first, count).
/// Vertex `j·(RING_CELLS + 1) + i` is grid vertex (i, j); the vertex shader places it.
pub fn ring_indices() -> (Vec<u32>, [(u32, u32); VARIANTS]) {
    let n = RING_CELLS;
    let mut indices = Vec::new();
    let mut ranges = [(0, 0); VARIANTS];
    for (v, range) in ranges.iter_mut().enumerate() {
        let first = indices.len() as u32;
        // The hole: cells n/4 + d .. 3n/4 + d on each axis.
        let hole = (v > 0).then(|| {
            let (dx, dz) = ((v - 1) % 3, (v - 1) / 3);
            let lo = |d: usize| (n / 4) as i64 + d as i64 - 1;
            (lo(dx), lo(dz))
        });
        for j in 0..n {
            for i in 0..n {
                if let Some((hx, hz)) = hole {
                    let inside = |c: u32, lo: i64| (lo..lo + (n / 2) as i64).contains(&(c as i64));
                    if inside(i, hx) && inside(j, hz) {
                        continue;
                    }
                }
                let a = j * (n + 1) + i;
                let b = a + 1;
                let c = a + n + 1;
                let d = c + 1;
                indices.extend_from_slice(&[a, c, b, b, c, d]);
            }
        }
        *range = (first, indices.len() as u32 - first);
    }
    (indices, ranges)
}

/// The terrain uniforms for a camera at `eye` whose far plane is `far` and fog distance
/// `fog`; `density` says whether a density map is bound.
pub fn terrain_uniforms(
    terrain: &HeightField,
    density: bool,
    blend: (f32, f32),
    eye: Vec3,
    far: f32,
    fog: f32,
) -> TerrainUniforms {
    let mut u = TerrainUniforms {
        view_proj_relative: glam::Mat4::IDENTITY.to_cols_array_2d(),
        info: [0, 0, terrain.unbounded as u32, 1],
        noise: [1.0, 0.0, 0.0, terrain.size],
        seeds: [[0; 4]; 3],
        grid: [terrain.resolution, RING_CELLS, MORPH_CELLS, 0],
        blend: [blend.0, blend.1, if density { 1.0 } else { 0.0 }, 0.0],
        grass_albedo: far_grass_albedo().extend(0.0).into(),
        levels: [[0.0; 4]; MAX_LEVELS],
    };
    match &terrain.surface {
        Surface::Grid => u.info[0] = 1,
        Surface::Noise(noise) => {
            let octaves = noise.seeds.len().min(12);
            u.info[1] = octaves as u32;
            u.noise[0] = noise.wavelength as f32;
            u.noise[1] = noise.mid as f32;
            u.noise[2] = noise.scale as f32;
            for (o, &seed) in noise.seeds.iter().take(octaves).enumerate() {
                u.seeds[o / 4][o % 4] = seed;
            }
        }
    }
    let cell0 = finest_cell(terrain);
    let far = if far.is_finite() {
        far.max(1.0)
    } else {
        1000.0
    };
    u.blend[3] = far;
    let reach = if terrain.unbounded {
        far.max(FOG_REACH * fog.max(0.0)).min(1e6)
    } else {
        // Bounded: the square seen from wherever the camera is.
        let corner = Vec2::splat(0.5 * terrain.size);
        let eye_xz = Vec2::new(eye.x, eye.z).abs();
        let eye_xz = if eye_xz.is_finite() {
            eye_xz
        } else {
            Vec2::ZERO
        };
        (eye_xz + corner).length().min(far * 4.0)
    };
    let levels = level_count(cell0, reach);
    u.info[3] = levels;
    let eye_xz = Vec2::new(eye.x, eye.z);
    let eye_xz = if eye_xz.is_finite() {
        eye_xz
    } else {
        Vec2::ZERO
    };
    for k in 0..levels {
        let c = level_centre(cell0, k, eye_xz);
        u.levels[k as usize] = [c.x, c.y, cell0 * 2f32.powi(k as i32), 0.0];
    }
    u
}

/// CPU twin of the vertex shader's `clipmap_xz`: where vertex `vid` of level `level` lies
/// for a camera at `eye` (x, z).
pub fn vertex_xz(u: &TerrainUniforms, vid: u32, level: usize, eye: Vec2) -> Vec2 {
    let n = u.grid[1];
    let (i, j) = (vid % (n + 1), vid / (n + 1));
    let l = u.levels[level];
    let cell = l[2];
    let local = Vec2::new(i as f32 - (n / 2) as f32, j as f32 - (n / 2) as f32);
    let mut xz = Vec2::new(l[0], l[1]) + local * cell;
    let d = (xz.x - eye.x).abs().max((xz.y - eye.y).abs()) / cell;
    let band = u.grid[2] as f32;
    let outer = (n / 2) as f32 - 1.0;
    let morph = ((d - (outer - band)) / band).clamp(0.0, 1.0);
    xz -= Vec2::new((i % 2) as f32, (j % 2) as f32) * morph * cell;
    if u.info[2] == 0 {
        let half = 0.5 * u.noise[3];
        xz = xz.clamp(Vec2::splat(-half), Vec2::splat(half));
    }
    xz
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::types::{HeightSource, Terrain};

    fn meadow(unbounded: bool) -> HeightField {
        HeightField::from_scene(&Terrain {
            size: 32.0,
            resolution: 129,
            height: HeightSource::Noise {
                seed: 7,
                amplitude: 2.5,
                wavelength: 28.0,
                octaves: 4,
            },
            density_map: None,
            unbounded,
        })
        .unwrap()
    }

    #[test]
    fn variants_leave_out_a_half_size_hole() {
        let (indices, ranges) = ring_indices();
        let n = RING_CELLS;
        assert_eq!(ranges[0], (0, n * n * 6));
        for r in &ranges[1..] {
            assert_eq!(r.1, (n * n - n * n / 4) * 6);
        }
        let last = ranges[VARIANTS - 1];
        assert_eq!(indices.len() as u32, last.0 + last.1);
        assert!(indices.iter().all(|&i| i < (n + 1) * (n + 1)));
    }

    #[test]
    fn levels_reach_past_the_far_plane_and_the_fog() {
        let t = meadow(true);
        assert_eq!(finest_cell(&t), 0.25);
        let u = terrain_uniforms(
            &t,
            false,
            (15.0, 60.0),
            Vec3::new(3.3, 5.0, -7.1),
            300.0,
            128.0,
        );
        let levels = u.info[3] as usize;
        let last = u.levels[levels - 1];
        let reach = (RING_CELLS / 2 - 1) as f32 * last[2];
        assert!(reach >= FOG_REACH * 128.0, "{reach}");
        assert!(levels <= MAX_LEVELS);
        // Level 0 covers the camera.
        assert!((u.levels[0][0] - 3.3).abs() <= 0.5 && (u.levels[0][1] + 7.1).abs() <= 0.5);
    }

    /// Every level's outer edge, after the morph, is made of the next level's vertices, and
    /// that level's hole is exactly this level's square: no T-junction, no gap, no overlap.
    #[test]
    fn level_edges_meet_the_next_level_without_cracks() {
        let t = meadow(true);
        let n = RING_CELLS;
        for eye in [
            Vec3::new(0.0, 3.0, 0.0),
            Vec3::new(0.37, 3.0, -0.81),
            Vec3::new(-1234.6, 30.0, 9876.2),
            Vec3::new(10000.13, 2.0, -10000.9),
        ] {
            let e = Vec2::new(eye.x, eye.z);
            let u = terrain_uniforms(&t, false, (15.0, 60.0), eye, 300.0, 128.0);
            let levels = u.info[3] as usize;
            for k in 0..levels - 1 {
                let coarse = u.levels[k + 1];
                let fine = u.levels[k];
                // The hole of level k+1, from its variant, in world units.
                let v = variant(&u, k + 1);
                let (dx, dz) = ((v - 1) % 3, (v - 1) / 3);
                let lo = |c: f32, d: usize| {
                    c + ((n / 4) as f32 + d as f32 - 1.0 - (n / 2) as f32) * coarse[2]
                };
                let (hx, hz) = (lo(coarse[0], dx), lo(coarse[1], dz));
                let half = (n / 2) as f32 * fine[2];
                assert_eq!(hx, fine[0] - half, "level {k} x");
                assert_eq!(hz, fine[1] - half, "level {k} z");
                for vid in 0..(n + 1) * (n + 1) {
                    let (i, j) = (vid % (n + 1), vid / (n + 1));
                    if !(i == 0 || j == 0 || i == n || j == n) {
                        continue;
                    }
                    let p = vertex_xz(&u, vid, k, e);
                    // On a coarse vertex: a multiple of the coarse cell from its centre.
                    let gx = (p.x - coarse[0]) / coarse[2];
                    let gz = (p.y - coarse[1]) / coarse[2];
                    assert_eq!(gx, gx.round(), "level {k} vertex {i},{j} at {p}");
                    assert_eq!(gz, gz.round(), "level {k} vertex {i},{j} at {p}");
                }
            }
        }
    }

    #[test]
    fn bounded_terrain_collapses_onto_the_square() {
        let t = meadow(false);
        let eye = Vec3::new(40.0, 10.0, 5.0);
        let u = terrain_uniforms(&t, false, (15.0, 60.0), eye, 300.0, 128.0);
        for k in 0..u.info[3] as usize {
            for vid in (0..(RING_CELLS + 1).pow(2)).step_by(7) {
                let p = vertex_xz(&u, vid, k, Vec2::new(eye.x, eye.z));
                assert!(p.x.abs() <= 16.0 && p.y.abs() <= 16.0);
            }
        }
        // The levels reach the far corner of the square from the eye.
        let last = u.levels[u.info[3] as usize - 1];
        let reach = (RING_CELLS / 2 - 1) as f32 * last[2];
        assert!(reach >= Vec2::new(56.0, 21.0).length(), "{reach}");
    }

    /// The closed form against a Monte-Carlo average of `grass.wgsl`'s albedo over random
    /// tints and blade heights v in [0.25, 1].
    #[test]
    fn far_albedo_is_the_grass_mean() {
        let fresh = Vec3::new(0.10, 0.34, 0.05);
        let dry = Vec3::new(0.32, 0.40, 0.09);
        let deep = Vec3::new(0.05, 0.22, 0.04);
        let mut rng = crate::field::hash32(1);
        let mut next = || {
            rng = crate::field::hash32(rng);
            rng as f32 / 4294967296.0
        };
        let samples = 200_000;
        let mut sum = Vec3::ZERO;
        for _ in 0..samples {
            let (tx, ty, v) = (next(), next(), 0.25 + 0.75 * next());
            let a = fresh.lerp(deep, ty * 0.7).lerp(dry, tx * tx * 0.8);
            sum += (a * 0.55).lerp(a * 1.25 + Vec3::new(0.03, 0.04, 0.0), v);
        }
        let mean = sum / samples as f32;
        let closed = far_grass_albedo();
        assert!(
            (mean - closed).abs().max_element() < 2e-3,
            "{mean} {closed}"
        );
        // Green dominates.
        assert!(closed.y > closed.x && closed.y > closed.z);
    }

    /// The far colour follows the field: its own palette without species, the species'
    /// colours by share, and the flowers' petals by the ground their heads cover.
    #[test]
    fn far_colour_includes_species_and_flowers() {
        let mut field = crate::scene::Field::default();
        assert_eq!(far_albedo(&field), far_grass_albedo());
        field.species = vec![crate::scene::Species {
            color: (0.5, 0.4, 0.1),
            ..Default::default()
        }];
        let straw = far_albedo(&field);
        assert!(straw.x > far_grass_albedo().x * 1.5, "{straw}");
        field.flowers = Some(crate::scene::Flowers {
            fraction: 0.2,
            head_size: 0.05,
            kinds: vec![crate::scene::FlowerKind {
                petals: (0.6, 0.2, 0.9),
                ..Default::default()
            }],
            ..Default::default()
        });
        // 80 blades/m² × 0.2 × π 0.05² ≈ 0.126 of the ground is petals.
        let flowered = far_albedo(&field);
        let expected = straw.lerp(
            Vec3::new(0.6, 0.2, 0.9),
            80.0 * 0.2 * std::f32::consts::PI * 0.0025,
        );
        assert!(
            (flowered - expected).abs().max_element() < 1e-5,
            "{flowered} {expected}"
        );
    }
}
