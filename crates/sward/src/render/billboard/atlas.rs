//! The billboard atlas: strips of sward's own blades rendered once at start-up into a
//! texture array (one layer per variant) with a full mip chain. Each layer is the grass of
//! one card seen from the side, at the card's real size: blades of the field's widths and
//! heights, drawn with the blades' geometry (quadratic Bézier, the triangle-tip shape of
//! `grass.wgsl`, leaning by the field's bend range) and colours (the grass shader's fresh /
//! deep / dry mix per blade, lighter towards the tip, darker at the base), as many as cover
//! the card's base about one and a half times, rasterised on the CPU with 4×4
//! supersampling. The texture's width follows the card's aspect so that texels are about
//! square and a blade is a texel or two wide, never a smeared wedge. The lighting is the
//! blades' own, applied by the billboard shader, so the cards and the far ground read as
//! one: each blade faces one of [`FACINGS`] directions relative to the eye, and a second
//! layer of weights says which ([`Layer::facing`]), so the shader lights each blade of the
//! strip as the blades' shading lights a blade turned that way (`far_grass.wgsl`): the
//! cards keep the contrast between sunlit and translucent blades.

use glam::{Vec2, Vec3};

use crate::field::hash32;
use crate::scene::types::Field;

/// Texel rows of one layer; its width follows the card's aspect ([`layer_size`]).
pub const HEIGHT: u32 = 64;
/// Widest layer (texels).
pub const MAX_WIDTH: u32 = 1024;
/// Strips in the atlas.
pub const VARIANTS: u32 = 4;
/// Blades drawn in one strip: enough to cover the card's base this many times over.
const BASE_COVER: f32 = 1.6;
const MIN_BLADES: u32 = 40;
const MAX_BLADES: u32 = 4000;
/// Supersamples per texel side.
const SS: u32 = 4;
/// Blade facings the strips' blades take (`far_grass_facings` lights each).
pub const FACINGS: usize = 4;

/// One layer's linear RGB and coverage, row-major (row 0 at the top: the tips).
#[derive(Clone, Debug, PartialEq)]
pub struct Layer {
    /// Texels per row ([`layer_size`]: a power of two from [`HEIGHT`] to [`MAX_WIDTH`]).
    pub width: u32,
    /// Texel rows ([`HEIGHT`]).
    pub height: u32,
    /// Per texel, linear RGB in `xyz` and coverage (0 bare to 1 fully covered) in `w`;
    /// `width · height` entries.
    pub rgba: Vec<[f32; 4]>,
    /// Per texel, the share of its covered supersamples whose blade has each facing (sum 1
    /// where covered, 0 where not).
    pub facing: Vec<[f32; FACINGS]>,
}

/// Texels of a layer for a card of `card` (width, height in metres): [`HEIGHT`] rows and
/// about square texels, the width a power of two between `HEIGHT` and [`MAX_WIDTH`].
pub fn layer_size(card: (f32, f32)) -> (u32, u32) {
    let aspect = if card.1 > 0.0 && card.0.is_finite() {
        (card.0 / card.1).clamp(1.0, (MAX_WIDTH / HEIGHT) as f32)
    } else {
        1.0
    };
    let w = (HEIGHT as f32 * aspect).round() as u32;
    (w.next_power_of_two().clamp(HEIGHT, MAX_WIDTH), HEIGHT)
}

/// The grass shader's albedo for a blade's random tint at height `v` (0 root, 1 tip),
/// with its height shading: the same mix as `grass.wgsl` `fs_main`.
pub(crate) fn albedo(tint: [f32; 2], v: f32) -> [f32; 3] {
    let fresh = [0.10, 0.34, 0.05];
    let dry = [0.32, 0.40, 0.09];
    let deep = [0.05, 0.22, 0.04];
    // A tuft seen from afar: the grass shader's height shading, softened (the far ground's
    // colour, which the atlas is scaled to match, averages it the same way).
    let ao = 0.65 + 0.35 * v.powf(0.7);
    std::array::from_fn(|k| {
        let a = fresh[k] + (deep[k] - fresh[k]) * tint[1] * 0.7;
        let a = a + (dry[k] - a) * tint[0] * tint[0] * 0.8;
        let lit = a * 0.75 + (a * 1.1 + [0.015, 0.02, 0.0][k] - a * 0.75) * v;
        lit * ao
    })
}

fn unit(h: u32) -> f32 {
    (h >> 8) as f32 / 16_777_216.0
}

/// Renders variant `variant` of the strip of `field`'s grass on a card of `card` (width,
/// height in metres; heights relative to the card: the tallest blade of the field's range
/// reaches 0.95 of it).
pub fn render_layer(field: &Field, card: (f32, f32), variant: u32) -> Layer {
    let (width, height) = layer_size(card);
    let (w, h) = ((width * SS) as usize, (height * SS) as usize);
    let mut color = vec![[0.0f32; 3]; w * h];
    let mut cover = vec![false; w * h];
    let mut face = vec![0u8; w * h];
    let max_h = field.height.max.max(1e-3);
    let tau = 0.45;
    let card_w = card.0.max(1e-3);
    // The card's aspect in texture units (x in card widths, y in card heights).
    let aspect = card_w / card.1.max(1e-3);
    let mean_width = (0.5 * (field.width.min + field.width.max)).max(1e-4);
    let blades = ((BASE_COVER * card_w / mean_width).round() as u32).clamp(MIN_BLADES, MAX_BLADES);
    for b in 0..blades {
        let key = hash32(variant.wrapping_mul(0x9E37_79B9) ^ hash32(b + 1));
        let r = |k: u32| unit(hash32(key.wrapping_add(k.wrapping_mul(0x85EB_CA6B))));
        let root = 0.03 + 0.94 * r(0);
        let height =
            (field.height.min + (field.height.max - field.height.min) * r(1)) / max_h * 0.95;
        let bend = (field.bend.min + (field.bend.max - field.bend.min) * r(2)).to_radians()
            * if r(3) < 0.5 { -1.0 } else { 1.0 };
        // The blade's real width in card widths, at least a supersample.
        let blade_w = field.width.min + (field.width.max - field.width.min) * r(4);
        let width = (blade_w / card_w).max(1.0 / w as f32);
        let tint = [r(5), r(6)];
        let facing = ((r(9) * FACINGS as f32) as usize).min(FACINGS - 1) as u8;
        // The curve: root, a middle control point straight up, the tip leaning by `bend`
        // (x in card widths, y in card heights).
        let p0 = Vec2::new(root, 0.0);
        let p1 = Vec2::new(root, height * 0.6);
        let p2 = p0 + Vec2::new(bend.sin() / aspect, bend.cos()) * height;
        let rows = (height * h as f32).ceil().max(1.0) as usize;
        for row in 0..=rows {
            let v = row as f32 / rows as f32;
            let a = p0.lerp(p1, v);
            let c = a.lerp(p1.lerp(p2, v), v);
            // The triangle-tip shape: full width up to tau, then tapering to the tip.
            let half = 0.5 * width * (1.0 - ((v - tau).max(0.0) / (1.0 - tau)));
            let y = ((1.0 - c.y) * h as f32) as i64;
            if y < 0 || y >= h as i64 {
                continue;
            }
            let x0 = ((c.x - half) * w as f32).floor() as i64;
            let x1 = ((c.x + half) * w as f32).ceil() as i64;
            let col = albedo(tint, v);
            for x in x0.max(0)..x1.min(w as i64) {
                let i = y as usize * w + x as usize;
                color[i] = col;
                cover[i] = true;
                face[i] = facing;
            }
        }
        // A flower among the blades (`field.flowers`): its head, a disc of its kind's
        // petal colour around its centre colour, at the tip.
        if let Some(f) = field.flowers.as_ref().filter(|f| !f.kinds.is_empty()) {
            if r(7) < f.fraction {
                let kind = &f.kinds[(r(8) * f.kinds.len() as f32) as usize % f.kinds.len()];
                let radius = (f.head_size / card_w).max(1.5 / w as f32);
                let (cx, cy) = (p2.x * w as f32, (1.0 - p2.y) * h as f32);
                let rx = radius * w as f32;
                // The head seen from the side: an ellipse half as tall as wide.
                let ry = 0.5 * rx * aspect * h as f32 / w as f32;
                for y in (cy - ry).floor() as i64..=(cy + ry).ceil() as i64 {
                    for x in (cx - rx).floor() as i64..=(cx + rx).ceil() as i64 {
                        if x < 0 || y < 0 || x >= w as i64 || y >= h as i64 {
                            continue;
                        }
                        let (dx, dy) = ((x as f32 - cx) / rx, (y as f32 - cy) / ry.max(1e-3));
                        let d = (dx * dx + dy * dy).sqrt();
                        if d <= 1.0 {
                            let c = if d < 0.3 { kind.centre } else { kind.petals };
                            let i = y as usize * w + x as usize;
                            color[i] = [c.0, c.1, c.2];
                            cover[i] = true;
                            face[i] = facing;
                        }
                    }
                }
            }
        }
    }
    // Down to texels: the mean colour of the covered supersamples, and the coverage.
    let mut rgba = vec![[0.0f32; 4]; (width * height) as usize];
    let mut facings = vec![[0.0f32; FACINGS]; (width * height) as usize];
    for ty in 0..height as usize {
        for tx in 0..width as usize {
            let (mut sum, mut n) = ([0.0f32; 3], 0u32);
            let mut faces = [0.0f32; FACINGS];
            for sy in 0..SS as usize {
                for sx in 0..SS as usize {
                    let i = (ty * SS as usize + sy) * w + tx * SS as usize + sx;
                    if cover[i] {
                        for k in 0..3 {
                            sum[k] += color[i][k];
                        }
                        faces[face[i] as usize] += 1.0;
                        n += 1;
                    }
                }
            }
            let a = n as f32 / (SS * SS) as f32;
            let c = if n > 0 {
                sum.map(|s| s / n as f32)
            } else {
                [0.0; 3]
            };
            rgba[ty * width as usize + tx] = [c[0], c[1], c[2], a];
            facings[ty * width as usize + tx] = faces.map(|f| f / n.max(1) as f32);
        }
    }
    Layer {
        width,
        height,
        rgba,
        facing: facings,
    }
}

/// The next mip level of a `w × h` level: the box filter of each 2×2 block, the colour
/// weighted by coverage (so empty texels do not darken the edges).
pub fn downsample(level: &[[f32; 4]], w: u32, h: u32) -> Vec<[f32; 4]> {
    let (nw, nh) = ((w / 2).max(1), (h / 2).max(1));
    let mut out = vec![[0.0f32; 4]; (nw * nh) as usize];
    for y in 0..nh {
        for x in 0..nw {
            let mut sum = [0.0f32; 4];
            for (dx, dy) in [(0, 0), (1, 0), (0, 1), (1, 1)] {
                let sx = (2 * x + dx).min(w - 1);
                let sy = (2 * y + dy).min(h - 1);
                let t = level[(sy * w + sx) as usize];
                for k in 0..3 {
                    sum[k] += t[k] * t[3];
                }
                sum[3] += t[3];
            }
            let a = sum[3] / 4.0;
            let c: [f32; 3] = if sum[3] > 0.0 {
                std::array::from_fn(|k| sum[k] / sum[3])
            } else {
                [0.0; 3]
            };
            out[(y * nw + x) as usize] = [c[0], c[1], c[2], a];
        }
    }
    out
}

/// The facing weights' mip chain: each level the box filter of the one before, weighted
/// by the colour's coverage as [`downsample`] weighs the colour (level 0 first, down to
/// 1 × 1, as [`mip_chain`]).
pub fn facing_chain(layer: &Layer) -> Vec<Vec<[f32; FACINGS]>> {
    let colour = mip_chain(layer);
    let mut levels = vec![layer.facing.clone()];
    let (mut w, mut h) = (layer.width, layer.height);
    while w > 1 || h > 1 {
        let (prev, cover) = (levels.last().unwrap(), &colour[levels.len() - 1]);
        let (nw, nh) = ((w / 2).max(1), (h / 2).max(1));
        let mut out = vec![[0.0f32; FACINGS]; (nw * nh) as usize];
        for y in 0..nh {
            for x in 0..nw {
                let (mut sum, mut a) = ([0.0f32; FACINGS], 0.0f32);
                for (dx, dy) in [(0, 0), (1, 0), (0, 1), (1, 1)] {
                    let i = ((2 * y + dy).min(h - 1) * w + (2 * x + dx).min(w - 1)) as usize;
                    let c = cover[i][3];
                    for k in 0..FACINGS {
                        sum[k] += prev[i][k] * c;
                    }
                    a += c;
                }
                if a > 0.0 {
                    out[(y * nw + x) as usize] = sum.map(|v| v / a);
                }
            }
        }
        levels.push(out);
        (w, h) = (nw, nh);
    }
    levels
}

/// The facing weights of one mip level as linear RGBA8.
pub fn encode_facing(level: &[[f32; FACINGS]]) -> Vec<u8> {
    level
        .iter()
        .flat_map(|t| t.map(|v| (v.clamp(0.0, 1.0) * 255.0).round() as u8))
        .collect()
}

/// Every layer's mip chain: level 0 first, down to 1 × 1.
pub fn mip_chain(layer: &Layer) -> Vec<Vec<[f32; 4]>> {
    let mut levels = vec![layer.rgba.clone()];
    let (mut w, mut h) = (layer.width, layer.height);
    while w > 1 || h > 1 {
        let next = downsample(levels.last().unwrap(), w, h);
        w = (w / 2).max(1);
        h = (h / 2).max(1);
        levels.push(next);
    }
    levels
}

/// Row bands of a layer's height profile (twin of `PROFILE_ROWS`, `card_profile.wgsl`).
pub const PROFILE_ROWS: usize = 8;

/// One row band of a layer's height profile (`ProfileRow` in `card_profile.wgsl`): the
/// coverage-weighted mean colour of its texels (rgb, w unused) and the same with each
/// texel weighted by each facing's weight too (the colour that facing's sun lights).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
pub struct ProfileRow {
    /// The band's mean colour (linear rgb; w unused).
    pub colour: [f32; 4],
    /// The band's mean colour times each facing's weight (linear rgb; w unused).
    pub facing: [[f32; 4]; FACINGS],
}

/// A layer's height profile: the mean its cards' texels are moved from by the contrast
/// gain, [`PROFILE_ROWS`] bands of rows from the top (`card_profile.wgsl` says why). A
/// band no blade reaches takes the nearest covered band's, so that no mean is black.
pub fn profile(layer: &Layer) -> [ProfileRow; PROFILE_ROWS] {
    let (w, h) = (layer.width as usize, layer.height as usize);
    let mut rows = [ProfileRow::default(); PROFILE_ROWS];
    let mut weights = [0.0f32; PROFILE_ROWS];
    for y in 0..h {
        let band = y * PROFILE_ROWS / h.max(1);
        for x in 0..w {
            let (t, f) = (layer.rgba[y * w + x], layer.facing[y * w + x]);
            weights[band] += t[3];
            for k in 0..3 {
                rows[band].colour[k] += t[3] * t[k];
                for (j, weight) in f.iter().enumerate() {
                    rows[band].facing[j][k] += t[3] * weight * t[k];
                }
            }
        }
    }
    let covered: Vec<usize> = (0..PROFILE_ROWS).filter(|&b| weights[b] > 1e-6).collect();
    let mut out = rows;
    for (b, row) in out.iter_mut().enumerate() {
        let Some(&from) = covered.iter().min_by_key(|&&c| c.abs_diff(b)) else {
            break;
        };
        let scale = 1.0 / weights[from];
        row.colour = rows[from].colour.map(|v| v * scale);
        row.facing = rows[from].facing.map(|c| c.map(|v| v * scale));
    }
    out
}

/// A row band's mean luminance lit by `light` (the sky's part) and the sun's part of
/// each facing (twin of `profile_luma`).
pub fn profile_luma(row: &ProfileRow, light: Vec3, sun: [Vec3; FACINGS]) -> f32 {
    let rgb = |c: [f32; 4]| Vec3::new(c[0], c[1], c[2]);
    let c = sun
        .iter()
        .zip(&row.facing)
        .fold(rgb(row.colour) * light, |c, (s, f)| c + rgb(*f) * *s);
    c.dot(crate::render::far_gain::LUMA)
}

/// A profile's mean at height `y` of the strip (0 the top row, 1 the bottom) from its
/// bands' means: linear between the bands' centres, the end bands' own past them (twin of
/// `profile_at`).
pub fn profile_at(means: &[f32; PROFILE_ROWS], y: f32) -> f32 {
    let last = (PROFILE_ROWS - 1) as f32;
    let s = (y * PROFILE_ROWS as f32 - 0.5).clamp(0.0, last);
    let i = (s as usize).min(PROFILE_ROWS - 2);
    means[i] + (means[i + 1] - means[i]) * (s - i as f32)
}

/// The luminance the texel (x, y) of level `level` of a layer's mip `chain` (level 0
/// `width` × `height`) is shown with under contrast gain `k`, under white light and no
/// sun (the move in `billboard.wgsl`'s `fs_main`): moved from its layer's profile
/// (`means`, [`profile_luma`] of each band) at the texel's centre by
/// `far_gain::contrast_luma`.
pub fn shown_luma(
    means: &[f32; PROFILE_ROWS],
    chain: &[Vec<[f32; 4]>],
    (width, height): (u32, u32),
    level: usize,
    (x, y): (u32, u32),
    k: f32,
) -> f32 {
    let (w, h) = ((width >> level).max(1), (height >> level).max(1));
    let t = chain[level][(y * w + x) as usize];
    let l = crate::render::far_gain::LUMA.dot(Vec3::new(t[0], t[1], t[2]));
    let m = profile_at(means, (y as f32 + 0.5) / h as f32);
    crate::render::far_gain::contrast_luma(l, m, k)
}

/// Linear to sRGB-encoded 8 bits (the atlas is an sRGB texture).
fn srgb8(v: f32) -> u8 {
    let v = v.clamp(0.0, 1.0);
    let s = if v <= 0.003_130_8 {
        v * 12.92
    } else {
        1.055 * v.powf(1.0 / 2.4) - 0.055
    };
    (s * 255.0).round() as u8
}

/// The texels of one mip level as sRGB RGBA8 (alpha linear).
pub fn encode(level: &[[f32; 4]]) -> Vec<u8> {
    level
        .iter()
        .flat_map(|t| {
            [
                srgb8(t[0]),
                srgb8(t[1]),
                srgb8(t[2]),
                (t[3].clamp(0.0, 1.0) * 255.0).round() as u8,
            ]
        })
        .collect()
}

/// The coverage-weighted mean linear colour of the atlas (what the cards average to).
pub fn mean_color(layers: &[Layer]) -> [f32; 3] {
    let mut sum = [0.0f64; 3];
    let mut weight = 0.0f64;
    for l in layers {
        for t in &l.rgba {
            for k in 0..3 {
                sum[k] += f64::from(t[k] * t[3]);
            }
            weight += f64::from(t[3]);
        }
    }
    if weight <= 0.0 {
        return [0.0; 3];
    }
    sum.map(|s| (s / weight) as f32)
}

/// Scales every layer's colours per channel so that their coverage-weighted mean is `target`.
pub fn match_mean(layers: &mut [Layer], target: [f32; 3]) {
    let mean = mean_color(layers);
    let gain: [f32; 3] = std::array::from_fn(|k| {
        if mean[k] > 1e-6 {
            (target[k] / mean[k]).clamp(0.25, 4.0)
        } else {
            1.0
        }
    });
    for layer in layers {
        for t in &mut layer.rgba {
            for k in 0..3 {
                t[k] *= gain[k];
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The far level includes the flowers: a field with flowers puts its kinds' petal
    /// colours into the tufts, a field without none.
    /// A layer's height profile: each band the coverage-weighted mean of its rows (the
    /// facings' parts adding up to it), and the bands no blade reaches the nearest
    /// covered band's, never black.
    #[test]
    fn the_height_profile_is_each_bands_mean() {
        let (width, height) = (4u32, 32u32);
        let mut rgba = vec![[0.0f32; 4]; (width * height) as usize];
        let mut facing = vec![[0.0f32; FACINGS]; rgba.len()];
        // Nothing in the top 12 rows; below, a colour rising with the row, half the
        // texels half covered and lit by facing 1, the others by facing 3.
        for y in 12..height {
            for x in 0..width {
                let i = (y * width + x) as usize;
                let v = y as f32 / height as f32;
                rgba[i] = [v, 0.5 * v + x as f32 * 0.01, 0.1, if x % 2 == 0 { 1.0 } else { 0.5 }];
                facing[i][if x % 2 == 0 { 1 } else { 3 }] = 1.0;
            }
        }
        let layer = Layer {
            width,
            height,
            rgba,
            facing,
        };
        let profile = profile(&layer);
        let band_rows = (height as usize) / PROFILE_ROWS;
        for (b, row) in profile.iter().enumerate() {
            // The band it stands for: its own, or the first covered one (rows 12-15).
            let from = b.max(3);
            let (mut sum, mut w) = ([0.0f32; 3], 0.0f32);
            for y in from * band_rows..(from + 1) * band_rows {
                for x in 0..width as usize {
                    let t = layer.rgba[y * width as usize + x];
                    for k in 0..3 {
                        sum[k] += t[3] * t[k];
                    }
                    w += t[3];
                }
            }
            for k in 0..3 {
                let want = sum[k] / w;
                assert!((row.colour[k] - want).abs() < 1e-6, "band {b}: {row:?}");
                let parts: f32 = row.facing.iter().map(|f| f[k]).sum();
                assert!((parts - want).abs() < 1e-6, "band {b}: {row:?}");
                assert_eq!(row.facing[0][k], 0.0);
            }
            assert!(row.colour[0] > 0.0, "band {b} is black");
        }
        // Lit: the sky's light on the colour, each facing's sun on its part.
        let lit = profile_luma(&profile[5], Vec3::ONE, [Vec3::ZERO, Vec3::splat(2.0), Vec3::ZERO, Vec3::ZERO]);
        let c = profile[5].colour;
        let f = profile[5].facing[1];
        let want = crate::render::far_gain::LUMA.dot(Vec3::new(c[0] + 2.0 * f[0], c[1] + 2.0 * f[1], c[2] + 2.0 * f[2]));
        assert!((lit - want).abs() < 1e-6);
        // Between the bands' centres the mean is linear, past the end ones flat.
        let means: [f32; PROFILE_ROWS] = std::array::from_fn(|i| i as f32);
        assert_eq!(profile_at(&means, 0.0), 0.0);
        assert_eq!(profile_at(&means, 1.0), 7.0);
        assert!((profile_at(&means, 0.5) - 3.5).abs() < 1e-6);
        assert!((profile_at(&means, 3.5 / 8.0) - 3.0).abs() < 1e-6);
    }

    #[test]
    fn flowers_reach_the_atlas() {
        let purple = |field: &Field| {
            (0..VARIANTS)
                .map(|v| render_layer(field, (1.0, 0.6), v))
                .map(|l| {
                    l.rgba
                        .iter()
                        .filter(|p| p[3] > 0.5 && p[2] > p[1] + 0.1 && p[0] > p[1])
                        .count()
                })
                .sum::<usize>()
        };
        let mut field = Field::default();
        assert_eq!(purple(&field), 0);
        field.flowers = Some(crate::scene::Flowers {
            fraction: 0.3,
            kinds: vec![crate::scene::FlowerKind {
                petals: (0.55, 0.3, 0.8),
                ..Default::default()
            }],
            ..Default::default()
        });
        let n = purple(&field);
        assert!(n > 10, "{n} purple texels");
    }

    /// Every covered texel's facings add up to one, every facing is used about as often,
    /// and the mip chain keeps them adding up to one where there is coverage.
    #[test]
    fn facings_cover_the_strip_and_survive_the_mips() {
        let layer = render_layer(&Field::default(), (2.0, 0.6), 1);
        let mut total = [0.0f64; FACINGS];
        for (f, c) in layer.facing.iter().zip(&layer.rgba) {
            let sum: f32 = f.iter().sum();
            if c[3] > 0.0 {
                assert!((sum - 1.0).abs() < 1e-5, "{f:?}");
            } else {
                assert_eq!(sum, 0.0);
            }
            for k in 0..FACINGS {
                total[k] += f64::from(f[k] * c[3]);
            }
        }
        let all: f64 = total.iter().sum();
        for t in total {
            assert!((t / all - 0.25).abs() < 0.08, "{total:?}");
        }
        let chain = facing_chain(&layer);
        let colour = mip_chain(&layer);
        assert_eq!(chain.len(), colour.len());
        for (f, c) in chain[2].iter().zip(&colour[2]) {
            if c[3] > 0.0 {
                let sum: f32 = f.iter().sum();
                assert!((sum - 1.0).abs() < 1e-4, "{f:?}");
            }
        }
    }
}
