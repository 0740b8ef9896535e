//! The far grass seen from above (issue 27, point 2). Upright cards are the canopy seen
//! from the side; from above they read as rows of strokes over a smooth far ground (the
//! prairie from 19 m up, 640 × 360: the levels 12-18 levels darker than blades to 50 m and
//! 56 % flatter). So the far levels hand over by the view's elevation over each point
//! ([`weight`]: from 5.7° to 23.6°): the cards fade out and the far ground takes the texture
//! of the canopy seen from above, rendered here once at start-up from the field's own
//! blades, as the cards' atlas is.
//!
//! A layer is a [`SIDE`]-metre square of ground with the field's blades at its density
//! (heights, widths and bend from the field; roots uniform, leaning any way), each seen in
//! a parallel view from [`VIEW_ELEVATION`] above the ground (the middle of the views that
//! use it) and from an azimuth of its own, projected back onto the ground, so that a texel
//! is the ground point behind which the eye sees that part of a blade. Each texel keeps the blade point nearest the
//! eye, with its albedo along the blade (the atlas's, lighter towards the tip); where no
//! blade is met the eye sees the deep canopy (the blades' roots, in their own shade). The
//! layer wraps (blades crossing an edge come back at the other), and it holds the
//! luminance over its mean: the far ground's light model, calibrated on the blades
//! (`far_gain`), gives the mean, the layer the variation about it. The ground shows one layer per cell of [`SIDE`] metres, turned one
//! of eight ways by a hash of the cell (`canopy.wgsl`), so the pattern does not repeat.

use glam::{Vec2, Vec3};
use wgpu::util::DeviceExt;

use crate::field::hash32;
use crate::gpu::Gpu;
use crate::render::far_gain::LUMA;
use crate::render::light::sky::smoothstep;
use crate::scene::types::Field;

/// The sines of the view's elevation over a point between which the canopy takes over
/// from the cards (5.7° and 23.6°; `CANOPY_ELEVATION`). From 19 m over the prairie, with
/// 10° and 30° the cards still stood in rows from 40 m on: 17 bands of 33 within 5 levels
/// and 30 % of blades to 50 m after 16 frames at 480 × 270, 21 with these; the grazing
/// prairie's far ring lies 3-5° below its eye, and is the same either way.
pub const ELEVATION: (f32, f32) = (0.1, 0.4);
/// The same for the far ground under the cards (1.7° and 9.8°; `CANOPY_GROUND_ELEVATION`).
/// With the cards' own range the ground under cards partly faded was a smooth colour, and
/// from 19 m up the top of the view showed the cards' rows as strokes over it, with gaps of
/// smooth ground between them; from these it shows the canopy's texture there and the
/// rows go. The grazing prairie's far ring (3-5° below its eye) is hidden by its cards:
/// its bands did not change (`sward bench --far-field`, 480 × 270, 32 frames, with and
/// without wind); from 19 m up after 16 frames the worst band stayed +4.8, 33 of 33.
pub const GROUND_ELEVATION: (f32, f32) = (0.03, 0.17);
/// Metres of ground per layer (`CANOPY_SIDE`).
pub const SIDE: f32 = 2.0;
/// Texels per layer side (7.8 mm each: the prairie's blades are 2.5-5 texels wide; the
/// ground samples it three mips sharper than its pixels near the blades, level 0 there).
pub const TEXELS: u32 = 256;
/// Layers (`CANOPY_LAYERS`).
pub const LAYERS: u32 = 4;
/// The stored value is the factor over this (R8Unorm; `CANOPY_SCALE`).
pub const SCALE: f32 = 4.0;
/// The elevation the layers are drawn from (radians: 30°).
pub const VIEW_ELEVATION: f32 = std::f32::consts::FRAC_PI_6;
/// The most blades drawn in one layer (a field of 2,000 blades per m² keeps its look with
/// fewer: the texels are covered many times over).
const MAX_BLADES: u32 = 16_000;
/// The light on a blade's visible face against the mean, least and most (a blade's facing
/// to the sun sets it).
const LIGHT_SPREAD: (f32, f32) = (0.35, 1.65);
/// Texel writes one layer may take (the prairie's take 1.9 million): a bound on the
/// start-up's time whatever the field (10,000 blades per m², 10 m tall, 1 m wide would take
/// 5·10¹⁰).
pub const WORK_BUDGET: usize = 8_000_000;
/// How dark the deep canopy is against a blade's root (its own shade).
const DEEP: f32 = 0.5;

/// How much of the grass at `p` the canopy stands for, seen from `eye` (twin of
/// `canopy_weight`): 0 for a grazing view, 1 looking down.
pub fn weight(p: Vec3, eye: Vec3) -> f32 {
    sine_of_elevation(p, eye).map_or(1.0, weight_at)
}

/// [`weight`] for a view whose elevation has sine `sin_e`.
pub fn weight_at(sin_e: f32) -> f32 {
    smoothstep(ELEVATION.0, ELEVATION.1, sin_e)
}

/// How much of the far ground at `p` shows the canopy seen from above, seen from `eye`
/// (twin of `canopy_ground_weight`): as [`weight`] over [`GROUND_ELEVATION`], so at
/// least [`weight`].
pub fn ground_weight(p: Vec3, eye: Vec3) -> f32 {
    sine_of_elevation(p, eye).map_or(1.0, |s| {
        smoothstep(GROUND_ELEVATION.0, GROUND_ELEVATION.1, s)
    })
}

/// The sine of the view's elevation over `p` from `eye`; `None` with the eye on the point
/// (closer than 1e-6, or not a number): looking straight down.
fn sine_of_elevation(p: Vec3, eye: Vec3) -> Option<f32> {
    let to_eye = eye - p;
    let len = to_eye.length();
    (len > 1e-6).then(|| to_eye.y / len)
}

/// The layer ground point `q` (x, z) shows and how it is turned (twin of
/// `canopy_variant`: bit 0 mirrors u, bit 1 mirrors v, bit 2 swaps them).
pub fn cell_variant(q: Vec2) -> (u32, u32) {
    let cx = (q.x / SIDE).floor() as i32;
    let cz = (q.y / SIDE).floor() as i32;
    let h = hash32((cx as u32) ^ hash32((cz as u32) ^ 0x2c1b_3c6d).rotate_left(17));
    (h % LAYERS, (h >> 8) & 7)
}

/// Turns `v` (a place in a cell, or a gradient with `offset` 0) the way `turn` says (twin
/// of `canopy_turn`: bit 2 swaps the axes, then bit 0 mirrors u, bit 1 mirrors v).
pub fn turn_uv(v: Vec2, turn: u32, offset: f32) -> Vec2 {
    let mut t = if turn & 4 != 0 { Vec2::new(v.y, v.x) } else { v };
    if turn & 1 != 0 {
        t.x = offset - t.x;
    }
    if turn & 2 != 0 {
        t.y = offset - t.y;
    }
    t
}

/// The place of ground point `q` (x, z) in its cell, over [`SIDE`], turned as the cell
/// turns it: where in its layer the far ground samples it.
pub fn cell_uv(q: Vec2) -> Vec2 {
    let f = q / SIDE;
    turn_uv(f - f.floor(), cell_variant(q).1, 1.0)
}

/// Runs the WGSL twins (`canopy_probe.wgsl`) at each (ground point, eye) of `points`: the
/// weight ([`ground_weight`] with `ground`, else [`weight`]), the cell's layer and turn,
/// and [`cell_uv`], as the GPU computes them.
pub fn probe(
    gpu: &Gpu,
    points: &[(Vec3, Vec3)],
    ground: bool,
) -> crate::error::Result<Vec<(f32, u32, u32, Vec2)>> {
    let at: Vec<[f32; 4]> = points.iter().map(|(p, _)| p.extend(0.0).to_array()).collect();
    let w = if ground { 1.0 } else { 0.0 };
    let eyes: Vec<[f32; 4]> = points.iter().map(|(_, e)| e.extend(w).to_array()).collect();
    let out = crate::gpu::run_vec4_probe(
        gpu,
        "sward.canopy_probe",
        "canopy_probe.wgsl",
        &[bytemuck::cast_slice(&at), bytemuck::cast_slice(&eyes)],
        points.len(),
    )?;
    Ok(out
        .iter()
        .map(|v| {
            let c = v[1] as u32;
            (v[0], c / 8, c % 8, Vec2::new(v[2], v[3]))
        })
        .collect())
}

/// One layer of the canopy.
#[derive(Clone, Debug, PartialEq)]
pub struct Layer {
    /// Brightness factors, row-major, [`TEXELS`]² of them: the luminance over the layer's
    /// mean (they average 1, at most [`SCALE`]).
    pub factors: Vec<f32>,
    /// The share of texels where a blade was met.
    pub cover: f32,
    /// Texel writes it took (at most [`WORK_BUDGET`] and one blade's more).
    pub work: usize,
}

/// Layer `layer` of the canopy of `field` seen from above.
pub fn render_layer(field: &Field, layer: u32) -> Layer {
    let n = TEXELS as usize;
    let cell = SIDE / n as f32;
    let mut depth = vec![f32::NEG_INFINITY; n * n];
    let mut lum = vec![0.0f32; n * n];
    let cot = 1.0 / VIEW_ELEVATION.tan();
    let blades = ((field.density.max(0.0) * SIDE * SIDE).round() as u32).clamp(1, MAX_BLADES);
    // Fewer blades than the density (MAX_BLADES): each drawn as wide as they would cover.
    let widen = (field.density.max(0.0) * SIDE * SIDE / blades as f32).max(1.0);
    let unit = |h: u32| (h >> 8) as f32 / 16_777_216.0;
    let mut work = 0usize;
    for b in 0..blades {
        // The layer's budget spent (a field of 10 m blades a metre wide): the blades drawn
        // so far cover it many times over, and the rest, placed at random as they are,
        // would add nothing but time.
        if work >= WORK_BUDGET {
            break;
        }
        let key = hash32(layer.wrapping_mul(0x9E37_79B9) ^ hash32(b + 0x51ed_270b));
        let r = |k: u32| unit(hash32(key.wrapping_add(k.wrapping_mul(0x85EB_CA6B))));
        let root = Vec2::new(r(0), r(1)) * SIDE;
        let height = field.height.min + (field.height.max - field.height.min) * r(2);
        let bend = (field.bend.min + (field.bend.max - field.bend.min) * r(3)).to_radians();
        let width = (field.width.min + (field.width.max - field.width.min) * r(4)).max(1e-4)
            * widen;
        let tint = [r(5), r(6)];
        let phi = r(7) * std::f32::consts::TAU;
        // The light on the blade's face turned to the eye: a blade facing the sun is lit
        // through, one edge-on or turned away is in its own shade (`blade_light`'s
        // spread over the facings, 0.35 to 1.65 of the mean, uniform).
        let facing_light = LIGHT_SPREAD.0 + (LIGHT_SPREAD.1 - LIGHT_SPREAD.0) * r(8);
        // Seen from an azimuth of its own: one view for the whole layer drew every blade
        // long the same way, and with the cells turned the ground showed a patchwork of
        // 2 m squares of strokes; a layer seen straight down (no stretch) read 9-12 levels
        // bright and a third flatter where the view grazes (from 19 m up, 40-80 m away).
        let az = r(9) * std::f32::consts::TAU;
        let look = Vec2::new(az.cos(), az.sin());
        // The blade leans along `dir`; its width lies across it (the blades' own frame).
        let dir = Vec2::new(phi.cos(), phi.sin());
        let across = Vec2::new(-dir.y, dir.x);
        // The curve (as the atlas's): root, a middle point straight up, the tip leaning by
        // `bend`; (ground x, ground z, height).
        let p0 = Vec3::new(root.x, root.y, 0.0);
        let p1 = Vec3::new(root.x, root.y, 0.6 * height);
        let p2 = p0 + Vec3::new(dir.x * bend.sin(), dir.y * bend.sin(), bend.cos()) * height;
        // Steps along the blade: half a texel of the projected length each.
        let reach = height * (1.0 + cot) + bend.sin() * height;
        // At most eight layers long and half a layer wide: past that a blade only wraps
        // over the texels it has drawn.
        let steps = ((reach / (0.5 * cell)).ceil() as usize).clamp(2, 8 * n);
        let half_samples = ((0.5 * width / cell).ceil() as i64).clamp(0, n as i64 / 2);
        work += (steps + 1) * (2 * half_samples as usize + 1);
        for s in 0..=steps {
            let v = s as f32 / steps as f32;
            let c = p0.lerp(p1, v).lerp(p1.lerp(p2, v), v);
            // Projected along the view (`VIEW_ELEVATION` above the ground, from the blade's
            // own azimuth `look`) onto the ground. Of the points behind one ground point the
            // eye sees the highest (their distance along the view is g cos e + height /
            // sin e): the height is the depth.
            let g = Vec2::new(c.x, c.y) - look * (c.z * cot);
            let near = c.z;
            // The triangle-tip shape: full width to 0.45 of the blade, then to a point.
            let half = 0.5 * width * (1.0 - ((v - 0.45).max(0.0) / 0.55));
            let shade = super::billboard::atlas::albedo(tint, v);
            // Lower down, the neighbours shade it (CWD-Sim's self-shadow, Eq. 14, as 0.5 at
            // the root to 1 at the tip).
            let l = LUMA.dot(Vec3::from_array(shade))
                * facing_light
                * (0.5 + 0.5 * v);
            for k in -half_samples..=half_samples {
                let o = k as f32 * cell;
                if o.abs() > half + 0.5 * cell {
                    continue;
                }
                let q = g + across * o;
                let ix = ((q.x / cell).floor() as i64).rem_euclid(n as i64) as usize;
                let iz = ((q.y / cell).floor() as i64).rem_euclid(n as i64) as usize;
                let i = iz * n + ix;
                if near > depth[i] {
                    depth[i] = near;
                    lum[i] = l;
                }
            }
        }
    }
    // The deep canopy where no blade was met: a mean blade's root in its own shade.
    let root = super::billboard::atlas::albedo([0.5, 0.5], 0.0);
    let deep = DEEP * LUMA.dot(Vec3::from_array(root));
    let covered = depth.iter().filter(|&&d| d > f32::NEG_INFINITY).count();
    let lum: Vec<f32> = depth
        .iter()
        .zip(&lum)
        .map(|(&d, &l)| if d > f32::NEG_INFINITY { l } else { deep })
        .collect();
    let mean = lum.iter().map(|&v| f64::from(v)).sum::<f64>() / lum.len() as f64;
    let mean = mean.max(1e-9) as f32;
    Layer {
        factors: lum.iter().map(|&v| (v / mean).min(SCALE)).collect(),
        cover: covered as f32 / lum.len() as f32,
        work,
    }
}

/// The next mip level of a square level of side `side`: the mean of each 2 × 2 block.
pub fn downsample(level: &[f32], side: usize) -> Vec<f32> {
    let h = (side / 2).max(1);
    let mut out = vec![0.0f32; h * h];
    for y in 0..h {
        for x in 0..h {
            let mut sum = 0.0;
            for (dx, dy) in [(0, 0), (1, 0), (0, 1), (1, 1)] {
                sum += level[((2 * y + dy).min(side - 1)) * side + (2 * x + dx).min(side - 1)];
            }
            out[y * h + x] = 0.25 * sum;
        }
    }
    out
}

/// The canopy texture of `field`: [`LAYERS`] layers with full mip chains, each texel the
/// factor over [`SCALE`] (R8Unorm), labelled `sward.terrain.canopy`.
pub fn texture(gpu: &Gpu, field: &Field) -> wgpu::Texture {
    let mips = TEXELS.ilog2() + 1;
    let layers: Vec<Layer> = (0..LAYERS).map(|l| render_layer(field, l)).collect();
    // LayerMajor: every mip of layer 0, then of layer 1, ...
    let mut bytes = Vec::new();
    for layer in &layers {
        let mut level = layer.factors.clone();
        let mut side = TEXELS as usize;
        for m in 0..mips {
            bytes.extend(level.iter().map(|&v| (v / SCALE * 255.0).round().clamp(0.0, 255.0) as u8));
            if m + 1 < mips {
                level = downsample(&level, side);
                side = (side / 2).max(1);
            }
        }
    }
    gpu.device.create_texture_with_data(
        &gpu.queue,
        &wgpu::TextureDescriptor {
            label: Some("sward.terrain.canopy"),
            size: wgpu::Extent3d {
                width: TEXELS,
                height: TEXELS,
                depth_or_array_layers: LAYERS,
            },
            mip_level_count: mips,
            sample_count: 1,
            dimension: wgpu::TextureDimension::D2,
            format: wgpu::TextureFormat::R8Unorm,
            usage: wgpu::TextureUsages::TEXTURE_BINDING,
            view_formats: &[],
        },
        wgpu::util::TextureDataOrder::LayerMajor,
        &bytes,
    )
}

/// Bytes of a canopy texture of `size` (R8, square layers) with its mips.
pub fn texture_bytes(size: wgpu::Extent3d) -> u64 {
    let mut side = u64::from(size.width);
    let mut sum = 0;
    while side > 0 {
        sum += side * side;
        side /= 2;
    }
    sum * u64::from(size.depth_or_array_layers)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn prairie() -> Field {
        let text = include_str!("../../../../assets/scenes/prairie.ron");
        crate::scene::parse_scene(text, std::path::Path::new("prairie.ron"))
            .expect("prairie")
            .field
    }

    fn stats(l: &Layer) -> (f32, f32) {
        let n = l.factors.len() as f64;
        let mean = l.factors.iter().map(|&v| f64::from(v)).sum::<f64>() / n;
        let var = l.factors.iter().map(|&v| (f64::from(v) - mean).powi(2)).sum::<f64>() / n;
        (mean as f32, var.sqrt() as f32)
    }

    /// Measured: the prairie's layers cover 98.8-99.3 % of their texels (the view from 30°
    /// meets a blade almost everywhere, as its leaf area says), average 1 and vary by
    /// 0.48-0.50 about it (the albedo along the blade, the facings' light, the shade low
    /// down).
    #[test]
    fn a_layer_averages_one_and_varies_as_lit_blades_do() {
        let field = prairie();
        for layer in 0..LAYERS {
            let l = render_layer(&field, layer);
            assert_eq!(l.factors.len(), (TEXELS * TEXELS) as usize);
            let (mean, spread) = stats(&l);
            assert!((mean - 1.0).abs() < 0.01, "layer {layer} mean {mean}");
            assert!((0.35..0.65).contains(&spread), "layer {layer} spread {spread}");
            assert!(l.cover > 0.9, "layer {layer} cover {}", l.cover);
            assert!(l.factors.iter().all(|v| v.is_finite() && (0.0..=SCALE).contains(v)));
        }
        // The layers differ (each its own blades), and one layer is the same every time.
        assert_ne!(render_layer(&field, 0), render_layer(&field, 1));
        assert_eq!(render_layer(&field, 2), render_layer(&field, 2));
    }

    /// A sparse field shows its gaps: fewer blades cover less of the ground.
    #[test]
    fn a_sparser_field_covers_less() {
        let dense = prairie();
        let mut sparse = dense.clone();
        sparse.density = 5.0;
        let (d, s) = (render_layer(&dense, 0), render_layer(&sparse, 0));
        assert!(s.cover < 0.5 * d.cover, "cover {} against {}", s.cover, d.cover);
        // Still averaging 1: the light model gives the mean.
        assert!((stats(&s).0 - 1.0).abs() < 0.01);
        // No blades at all: the deep canopy everywhere, one value.
        let mut bare = dense.clone();
        bare.density = 0.0;
        let b = render_layer(&bare, 0);
        assert!(b.factors.iter().all(|v| v.is_finite()));
    }

    /// The largest blades the scene allows, as dense as it allows: the layer is bounded
    /// (`WORK_BUDGET`), still averages 1 and is covered.
    #[test]
    fn the_largest_field_is_drawn_within_the_budget() {
        let mut field = prairie();
        field.density = 10_000.0;
        field.height.min = 10.0;
        field.height.max = 10.0;
        field.width.min = 1.0;
        field.width.max = 1.0;
        field.bend.max = 90.0;
        let l = render_layer(&field, 0);
        let (mean, _) = stats(&l);
        assert!((mean - 1.0).abs() < 0.01, "mean {mean}");
        assert!(l.cover > 0.99, "cover {}", l.cover);
        assert!(l.factors.iter().all(|v| v.is_finite()));
        // One blade at most: eight layers long, half a layer wide.
        let n = TEXELS as usize;
        let blade = (8 * n + 1) * (n + 1);
        assert!(l.work <= WORK_BUDGET + blade, "{} texel writes", l.work);
        // The prairie draws every blade, far within the budget.
        let p = render_layer(&prairie(), 0);
        assert!(p.work < WORK_BUDGET / 2, "the prairie took {}", p.work);
    }

    #[test]
    fn the_weight_goes_from_the_cards_to_the_canopy_with_the_elevation() {
        let p = Vec3::ZERO;
        let at = |deg: f32| {
            let r = deg.to_radians();
            weight(p, Vec3::new(r.cos() * 50.0, r.sin() * 50.0, 0.0))
        };
        assert_eq!(at(3.0), 0.0, "a grazing view keeps its cards");
        assert_eq!(at(5.5), 0.0);
        assert!(at(15.0) > 0.2 && at(15.0) < 0.8, "half way: {}", at(15.0));
        assert_eq!(at(24.0), 1.0, "looking down: the canopy");
        assert_eq!(at(89.0), 1.0);
        let mut last = 0.0;
        for i in 0..=90 {
            let w = at(i as f32);
            assert!(w >= last && w - last < 0.1, "{last} -> {w} at {i}°");
            last = w;
        }
        // The eye on the point itself: looking straight down.
        assert_eq!(weight(p, p), 1.0);
        assert_eq!(weight(p, Vec3::new(f32::NAN, 1.0, 0.0)), 1.0);
    }

    #[test]
    fn cells_take_every_layer_and_turn() {
        let mut seen = [[false; 8]; LAYERS as usize];
        for i in 0..64 {
            for j in 0..64 {
                let q = Vec2::new(i as f32 * SIDE - 60.0, j as f32 * SIDE - 60.0);
                let (layer, turn) = cell_variant(q);
                assert!(layer < LAYERS && turn < 8);
                seen[layer as usize][turn as usize] = true;
                // One cell, one variant.
                assert_eq!(cell_variant(q + Vec2::splat(0.3 * SIDE)), (layer, turn));
            }
        }
        assert!(seen.iter().flatten().all(|&s| s), "{seen:?}");
    }

    #[test]
    fn the_mips_keep_the_mean() {
        let l = render_layer(&prairie(), 0);
        let mut level = l.factors.clone();
        let mut side = TEXELS as usize;
        let mean0 = stats(&l).0;
        while side > 1 {
            level = downsample(&level, side);
            side /= 2;
            let m = level.iter().sum::<f32>() / level.len() as f32;
            assert!((m - mean0).abs() < 1e-3, "mip of side {side}: {m}");
        }
        let bytes = texture_bytes(wgpu::Extent3d {
            width: TEXELS,
            height: TEXELS,
            depth_or_array_layers: LAYERS,
        });
        // 256² + 128² + ... + 1 = (4 · 256² − 1) / 3 per layer.
        assert_eq!(bytes, u64::from((4 * TEXELS * TEXELS - 1) / 3) * u64::from(LAYERS));
    }
}
