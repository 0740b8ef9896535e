//! The canopy as the blades are drawn (issue 27, point 1): where a distant eye's view ray
//! meets the canopy, on which part of its blade, for blades drawn with their own outline
//! or as Eq. 24's quads.
//!
//! The far levels are lit with the blades' light averaged over the blades an eye sees
//! (`far_grass_facings`, far_grass.wgsl), and calibrated on blades measured a little inside
//! their reach (`render::far_gain`). At grazing angles the eye sees the canopy's top, the
//! blades' upper parts: how much of it depends on the outline. A blade that narrows to its
//! tip (the prairie's `TriangleTip`) has little leaf area near the tip, and the eye sees
//! further down, where the blade is darker; Eq. 24 draws a blade narrower than w_min
//! pixels as a quad that keeps its width to the tip. Which of the two the frame draws
//! depends on the blade's width in pixels: in a 480×270 frame the near ring's blades were
//! all quads, in a 1920×1080 frame most kept their outline and read 0.864 of the light
//! model where the 480×270 frame's read 1.013 (red), and the far levels, calibrated on
//! them, read 14 levels dark. So the model knows the outline: a table of the mean v at
//! each depth into the leaf area for a share of quads among the blades (this module, in
//! the light's uniforms), and that share at each point from the blades' width in pixels
//! there (`drawn_quad_share` in far_grass.wgsl).

use crate::scene::{Field, Shape};

/// Depths into the canopy's leaf area the table holds, at `(i / (CANOPY_DEPTHS − 1))²`: the
/// square spaces them finely near the top, where a grazing view looks and where v falls as
/// the square root of the depth for blades that narrow to a point.
pub const CANOPY_DEPTHS: usize = 32;

/// Shares of quads the table holds, evenly from 0 (every blade drawn with its outline) to
/// 1 (every blade a quad, Eq. 24).
pub const CANOPY_SHARES: usize = 4;

/// The table's entries (`LightUniforms::canopy` holds them a vector per depth).
pub const CANOPY_ENTRIES: usize = CANOPY_DEPTHS * CANOPY_SHARES;

/// A blade's drawn width at `v` as a share of its width at the root (the twin of the
/// edges `shape_t` in grass.wgsl puts at u = 0 and u = 1), with tip threshold `tau`. The
/// dandelion's teeth are averaged over a tooth (their swing is finer than a far eye sees).
pub fn shape_width(shape: Shape, tau: f32, v: f32) -> f32 {
    let v = v.clamp(0.0, 1.0);
    match shape {
        Shape::Quad => 1.0,
        Shape::Triangle => 1.0 - v,
        Shape::Quadratic => 1.0 - v * v,
        Shape::TriangleTip => {
            let tau = tau.clamp(0.0, 0.999);
            1.0 - (v - tau).max(0.0) / (1.0 - tau)
        }
        // (1 − v) (0.35 + 0.65 tooth), the tooth's mean 0.5.
        Shape::Dandelion => (1.0 - v) * 0.675,
    }
}

/// The field's blades as the canopy sees them: each species' outline (the field's own
/// when it has none), weighted by its share of the leaf area (share times mean width).
#[derive(Clone, Debug, PartialEq)]
struct Outlines {
    shapes: Vec<(f32, Shape)>,
    tau: f32,
}

impl Outlines {
    fn of(field: &Field) -> Self {
        let mean = |r: crate::scene::Range| 0.5 * (r.min + r.max);
        let mut shapes: Vec<(f32, Shape)> = field
            .species
            .iter()
            .map(|s| (s.share.max(0.0) * mean(s.width).max(0.0), s.shape))
            .filter(|(w, _)| w.is_finite() && *w > 0.0)
            .collect();
        if shapes.is_empty() {
            shapes.push((1.0, field.shape));
        }
        let total: f32 = shapes.iter().map(|(w, _)| w).sum();
        for s in &mut shapes {
            s.0 /= total;
        }
        Self {
            shapes,
            tau: field.tip_threshold,
        }
    }

    /// The drawn width at `v` with a share `quads` of the blades drawn as quads.
    fn width(&self, v: f32, quads: f32) -> f32 {
        let own: f32 = self
            .shapes
            .iter()
            .map(|(w, s)| w * shape_width(*s, self.tau, v))
            .sum();
        own * (1.0 - quads) + quads
    }
}

/// Heights (in tallest blades) the table integrates over, evenly spread in [r, 1].
const TABLE_HEIGHTS: usize = 48;
/// Levels of height the leaf area is summed on, from the ground to the tallest tip.
const TABLE_LEVELS: usize = 192;

/// The mean v at each depth into the leaf area (`CANOPY_DEPTHS` per share of quads,
/// `CANOPY_SHARES` rows), for the field's outlines and blade heights spread evenly from
/// `r` times the tallest to the tallest. A point at height z (in tallest blades) lies on
/// each blade of height h > z at v = z / h, where the blade's leaf area per unit of height
/// is its drawn width there: the leaf area above z and the width-weighted mean v there are
/// summed over the heights, and each depth's z found between the levels.
pub fn canopy_table(field: &Field, r: f32) -> [f32; CANOPY_ENTRIES] {
    outlines_table(&Outlines::of(field), r)
}

/// [`canopy_table`] for the field's `outlines`.
fn outlines_table(outlines: &Outlines, r: f32) -> [f32; CANOPY_ENTRIES] {
    let r = if r.is_finite() { r.clamp(0.0, 1.0) } else { 1.0 };
    let heights: Vec<f32> = (0..TABLE_HEIGHTS)
        .map(|i| r + (1.0 - r) * (i as f32 + 0.5) / TABLE_HEIGHTS as f32)
        .collect();
    let mut table = [0.0; CANOPY_ENTRIES];
    for row in 0..CANOPY_SHARES {
        let quads = row as f32 / (CANOPY_SHARES - 1) as f32;
        // Per level (z from 0 to 1): the leaf area's density and its v-weighted density.
        let mut density = [0.0f32; TABLE_LEVELS + 1];
        let mut v_density = [0.0f32; TABLE_LEVELS + 1];
        for (k, (d, vd)) in density.iter_mut().zip(v_density.iter_mut()).enumerate() {
            let z = k as f32 / TABLE_LEVELS as f32;
            for &h in &heights {
                if h > z {
                    let v = z / h;
                    let w = outlines.width(v, quads);
                    *d += w;
                    *vd += w * v;
                }
            }
        }
        // The leaf area above each level (trapezoids, from the top), as a share of all.
        let mut above = [0.0f32; TABLE_LEVELS + 1];
        for k in (0..TABLE_LEVELS).rev() {
            above[k] = above[k + 1] + 0.5 * (density[k] + density[k + 1]);
        }
        let total = above[0].max(1e-12);
        let mean_v = |k: usize| {
            if density[k] > 1e-9 {
                v_density[k] / density[k]
            } else {
                1.0
            }
        };
        for col in 0..CANOPY_DEPTHS {
            let t = col as f32 / (CANOPY_DEPTHS - 1) as f32;
            let depth = t * t;
            // The first level (from the top) with at least `depth` of the leaf area above.
            let mut k = TABLE_LEVELS;
            while k > 0 && above[k - 1] / total <= depth {
                k -= 1;
            }
            let v = if k == 0 {
                mean_v(0)
            } else {
                // Between levels k − 1 (more above than `depth`) and k.
                let (a0, a1) = (above[k - 1] / total, above[k] / total);
                let f = if a0 > a1 {
                    ((a0 - depth) / (a0 - a1)).clamp(0.0, 1.0)
                } else {
                    0.0
                };
                // The top level holds no leaf area: its v is the tallest tips', 1.
                let top = if k == TABLE_LEVELS { 1.0 } else { mean_v(k) };
                mean_v(k - 1) + (top - mean_v(k - 1)) * f
            };
            table[row * CANOPY_DEPTHS + col] = v.clamp(0.0, 1.0);
        }
    }
    table
}

/// The table as the light's uniforms hold it: one vector per depth, its four components
/// the shares of quads (so that the shader reads whole vectors: a component picked by a
/// computed index made llvmpipe compile the far grass's shaders to code whose memory grew
/// the process by 800 MB).
pub fn packed(table: &[f32; CANOPY_ENTRIES]) -> [[f32; CANOPY_SHARES]; CANOPY_DEPTHS] {
    std::array::from_fn(|col| std::array::from_fn(|row| table[row * CANOPY_DEPTHS + col]))
}

/// The table packed as the light's uniforms hold it ([`packed`] of [`canopy_table`]) for
/// the last field outlines and height spread it was asked for, summed again only when
/// they change. The light's uniforms are rebuilt every frame (`LightPass::prepare`), and
/// the table's sums (4 shares × 193 levels × 48 heights of outline widths, about 37,000)
/// are the same frame after frame unless the field's shapes, tip threshold, species'
/// widths and shares or heights change (the panel, a scene reloaded).
#[derive(Clone, Debug, Default)]
pub struct CanopyCache {
    /// The outlines and the height spread's bits the table was summed for.
    key: Option<(Outlines, u32)>,
    table: [[f32; CANOPY_SHARES]; CANOPY_DEPTHS],
    /// How many times the table was summed (the cache's misses).
    sums: u64,
}

impl CanopyCache {
    /// The packed table for `field` with height spread `r` (as [`canopy_table`] takes it).
    pub fn table(&mut self, field: &Field, r: f32) -> [[f32; CANOPY_SHARES]; CANOPY_DEPTHS] {
        let key = (Outlines::of(field), r.to_bits());
        if self.key.as_ref() != Some(&key) {
            self.table = packed(&outlines_table(&key.0, r));
            self.key = Some(key);
            self.sums += 1;
        }
        self.table
    }

    /// How many times the table was summed since the cache was made.
    pub fn sums(&self) -> u64 {
        self.sums
    }
}

/// Twin of `drawn_canopy_v` (far_grass.wgsl): the mean v at `depth` into the canopy's leaf
/// area (0 at the top, 1 at the ground) with a share `quads` of the blades drawn as quads,
/// interpolated in the table (in the square root of the depth, and in the share).
pub fn drawn_canopy_v(table: &[[f32; CANOPY_SHARES]; CANOPY_DEPTHS], depth: f32, quads: f32) -> f32 {
    let s = depth.clamp(0.0, 1.0).sqrt() * (CANOPY_DEPTHS - 1) as f32;
    let q = quads.clamp(0.0, 1.0) * (CANOPY_SHARES - 1) as f32;
    let s0 = (s as usize).min(CANOPY_DEPTHS - 2);
    let fs = s - s0 as f32;
    // The shares' weights: each row's hat function at q.
    let weigh = |col: &[f32; CANOPY_SHARES]| {
        col.iter()
            .enumerate()
            .map(|(i, v)| v * (1.0 - (q - i as f32).abs()).max(0.0))
            .sum::<f32>()
    };
    let (a, b) = (weigh(&table[s0]), weigh(&table[s0 + 1]));
    a + (b - a) * fs
}

/// The blades' widths (m) the quads' share is taken at (`LightUniforms::canopy_widths`,
/// xy): the quartiles of the field's blade widths, over its species by share.
pub fn width_quartiles(field: &Field) -> [f32; 2] {
    let ranges: Vec<(f32, crate::scene::Range)> = if field.species.is_empty() {
        vec![(1.0, field.width)]
    } else {
        field
            .species
            .iter()
            .map(|s| (s.share.max(0.0), s.width))
            .collect()
    };
    // Each range as 16 evenly spread widths weighing its share; the weighted quartiles.
    let mut samples: Vec<(f32, f32)> = ranges
        .iter()
        .flat_map(|&(share, r)| {
            (0..16).map(move |i| (r.min + (r.max - r.min) * (i as f32 + 0.5) / 16.0, share))
        })
        .filter(|(w, s)| w.is_finite() && s.is_finite() && *s > 0.0)
        .collect();
    if samples.is_empty() {
        return [0.0; 2];
    }
    samples.sort_by(|a, b| a.0.total_cmp(&b.0));
    let total: f32 = samples.iter().map(|s| s.1).sum();
    let quantile = |p: f32| {
        let mut acc = 0.0;
        for &(w, s) in &samples {
            acc += s;
            if acc >= p * total {
                return w;
            }
        }
        samples[samples.len() - 1].0
    };
    [quantile(0.25), quantile(0.75)]
}

/// Twin of Eq. 24's share of quads (`quad_share` in far_grass.wgsl): a blade `wp` pixels
/// wide is drawn `1 − clamp((wp − w_min) / w_span, 0, 1)` of the way to a quad; no span
/// switches the correction off, and every blade keeps its outline.
pub fn quad_share(wp: f32, w_min: f32, w_span: f32) -> f32 {
    if w_span <= 0.0 || !wp.is_finite() {
        return 0.0;
    }
    1.0 - ((wp - w_min) / w_span).clamp(0.0, 1.0)
}

/// The canopy of quads in closed form: the mean v on its blade of the point `depth` into
/// the canopy's leaf area (0 at the top, 1 at the ground), every blade as wide to its tip,
/// the blades' heights spread evenly from `r` times the tallest to the tallest; 1 − depth
/// with one height. A point at height z lies on a blade of height h > z at v = z / h, whose
/// mean over the taller blades is z ln(1/m) / (1 − m), m = max(z, r). (The far model read
/// it until the outlines came in; the table's row of quads is held to it.)
pub fn canopy_v(depth: f32, r: f32) -> f32 {
    if r >= 0.999 {
        return (1.0 - depth).clamp(0.0, 1.0);
    }
    let spread = 1.0 - r;
    let mean_h = 0.5 * (1.0 + r);
    let above = depth.clamp(0.0, 1.0) * mean_h;
    let z = if above <= 0.5 * spread {
        1.0 - (2.0 * spread * above).sqrt()
    } else {
        r - (above - 0.5 * spread)
    };
    let m = z.max(r);
    let inv_h = if 1.0 - m > 1e-4 {
        (1.0 / m).ln() / (1.0 - m)
    } else {
        1.0
    };
    (z * inv_h).clamp(0.0, 1.0)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::{Field, Shape};

    /// `canopy_v` against the canopy it stands for, integrated numerically: blades of
    /// heights spread evenly over [r, 1], each as wide to its tip (a far quad), their leaf
    /// area summed by height; at the height where `depth` of it lies above, the mean v = z/h
    /// over the blades that reach there.
    #[test]
    fn canopy_v_is_the_mean_v_where_the_leaf_area_above_is_depth() {
        for r in [0.2f32, 0.44, 0.7] {
            let heights: Vec<f64> = (0..4000)
                .map(|i| f64::from(r) + (1.0 - f64::from(r)) * (i as f64 + 0.5) / 4000.0)
                .collect();
            let area_above = |z: f64| heights.iter().map(|&h| (h - z).max(0.0)).sum::<f64>();
            let total = area_above(0.0);
            for depth in [0.0f32, 0.05, 0.2, 0.5, 0.8, 1.0] {
                // Bisect for the height with `depth` of the leaf area above it.
                let (mut lo, mut hi) = (0.0f64, 1.0f64);
                for _ in 0..60 {
                    let mid = 0.5 * (lo + hi);
                    if area_above(mid) / total > f64::from(depth) {
                        lo = mid;
                    } else {
                        hi = mid;
                    }
                }
                let z = 0.5 * (lo + hi);
                let taller: Vec<f64> = heights.iter().copied().filter(|&h| h > z).collect();
                let expected = if taller.is_empty() {
                    1.0
                } else {
                    taller.iter().map(|h| z / h).sum::<f64>() / taller.len() as f64
                };
                let got = f64::from(canopy_v(depth, r));
                assert!(
                    (got - expected).abs() < 2e-3,
                    "r {r}, depth {depth}: {got} against {expected}"
                );
            }
        }
        // One height: the old mapping, 1 − depth.
        for depth in [0.0f32, 0.3, 1.0] {
            assert_eq!(canopy_v(depth, 1.0), 1.0 - depth);
        }
    }

    fn field(shape: Shape) -> Field {
        Field {
            shape,
            tip_threshold: 0.45,
            ..Field::default()
        }
    }

    /// The table's row of quads against the closed form (an independent sum: the table
    /// integrates over discrete heights and levels), within the measured 0.01.
    #[test]
    fn the_quads_row_is_the_closed_form() {
        for r in [0.2f32, 0.444, 0.7, 1.0] {
            for shape in [Shape::TriangleTip, Shape::Triangle, Shape::Quad] {
                let table = packed(&canopy_table(&field(shape), r));
                for i in 0..=40 {
                    let depth = (i as f32 / 40.0).powi(2);
                    let got = drawn_canopy_v(&table, depth, 1.0);
                    let want = canopy_v(depth, r);
                    assert!(
                        (got - want).abs() < 0.01,
                        "{shape:?} r {r} depth {depth}: {got} against {want}"
                    );
                }
            }
        }
    }

    /// Blades that narrow to a point: triangles of one height hold the share (1 − z)² of
    /// their leaf area above height z, so depth d lies at z = 1 − √d, where v = z. The table holds it, and every outline's v lies under
    /// the quads' (less leaf area near the tips: the eye sees further down).
    #[test]
    fn outlines_that_narrow_are_seen_further_down() {
        let table = packed(&canopy_table(&field(Shape::Triangle), 1.0));
        for i in 0..=20 {
            let depth = i as f32 / 20.0;
            let got = drawn_canopy_v(&table, depth, 0.0);
            let want = 1.0 - depth.sqrt();
            assert!((got - want).abs() < 0.01, "depth {depth}: {got} against {want}");
        }
        for shape in [Shape::TriangleTip, Shape::Triangle, Shape::Quadratic, Shape::Dandelion] {
            let table = packed(&canopy_table(&field(shape), 0.444));
            for i in 1..20 {
                let depth = (i as f32 / 20.0).powi(2);
                let outline = drawn_canopy_v(&table, depth, 0.0);
                let half = drawn_canopy_v(&table, depth, 0.5);
                let quads = drawn_canopy_v(&table, depth, 1.0);
                assert!(
                    outline <= half + 1e-4 && half <= quads + 1e-4,
                    "{shape:?} depth {depth}: {outline} {half} {quads}"
                );
            }
            // Near the top the difference is the tips' missing leaf area.
            let top = 0.01;
            assert!(
                drawn_canopy_v(&table, top, 0.0) < drawn_canopy_v(&table, top, 1.0) - 0.02,
                "{shape:?}"
            );
        }
    }

    /// Eq. 24's share of quads: every blade under w_min pixels, none past w_min + w_span,
    /// linear between; no span, none (the correction off); a width that is not finite, none.
    #[test]
    fn quad_share_follows_eq_24() {
        assert_eq!(quad_share(0.5, 1.0, 2.0), 1.0);
        assert_eq!(quad_share(2.0, 1.0, 2.0), 0.5);
        assert_eq!(quad_share(3.5, 1.0, 2.0), 0.0);
        assert_eq!(quad_share(0.5, 1.0, 0.0), 0.0);
        assert_eq!(quad_share(f32::NAN, 1.0, 2.0), 0.0);
    }

    /// The widths' quartiles: one range's quarter points; two species by share.
    #[test]
    fn width_quartiles_weigh_the_species() {
        let mut f = field(Shape::TriangleTip);
        f.width = crate::scene::Range { min: 0.02, max: 0.04 };
        let [lo, hi] = width_quartiles(&f);
        assert!((lo - 0.025).abs() < 0.001 && (hi - 0.035).abs() < 0.001, "{lo} {hi}");
        let species = |share, min, max| crate::scene::Species {
            share,
            width: crate::scene::Range { min, max },
            ..Default::default()
        };
        f.species = vec![species(2.0, 0.01, 0.01), species(1.0, 0.05, 0.05)];
        assert_eq!(width_quartiles(&f), [0.01, 0.05]);
        f.species = vec![species(1.0, 0.01, 0.01), species(2.0, 0.05, 0.05)];
        assert_eq!(width_quartiles(&f), [0.01, 0.05]);
        f.species = vec![species(1.0, 0.01, 0.01), species(9.0, 0.05, 0.05)];
        assert_eq!(width_quartiles(&f), [0.05, 0.05]);
    }

    /// The cache gives the table summed for the field it is asked for, and sums again
    /// only when the outlines or the height spread change: not for what the canopy's
    /// outline does not read (the density, the stiffness).
    #[test]
    fn the_cache_sums_again_only_when_the_outlines_change() {
        let mut cache = CanopyCache::default();
        let mut f = field(Shape::TriangleTip);
        let fresh = |f: &Field, r: f32| packed(&canopy_table(f, r));
        assert_eq!(cache.table(&f, 0.44), fresh(&f, 0.44));
        f.density *= 2.0;
        f.stiffness.max += 1.0;
        assert_eq!(cache.table(&f, 0.44), fresh(&f, 0.44));
        assert_eq!(cache.sums(), 1);
        let changes: [&dyn Fn(&mut Field); 3] = [
            &|f| f.tip_threshold = 0.7,
            &|f| f.shape = Shape::Quadratic,
            &|f| {
                f.species = vec![crate::scene::Species {
                    share: 1.0,
                    width: crate::scene::Range { min: 0.02, max: 0.03 },
                    shape: Shape::Triangle,
                    ..Default::default()
                }]
            },
        ];
        for (i, change) in changes.iter().enumerate() {
            let before = cache.table(&f, 0.44);
            change(&mut f);
            let after = cache.table(&f, 0.44);
            assert_eq!(after, fresh(&f, 0.44), "change {i}");
            assert_ne!(after, before, "change {i}");
            assert_eq!(cache.sums(), 2 + i as u64, "change {i}");
        }
        assert_eq!(cache.table(&f, 0.8), fresh(&f, 0.8));
        assert_eq!(cache.sums(), 5);
    }
}
