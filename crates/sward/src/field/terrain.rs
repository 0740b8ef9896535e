//! The ground: a height function of (x, z) built from the scene's height source, plus the
//! square grid of its heights centred on the origin.
//!
//! * `Noise` and `Flat` are analytic and have no edge: [`HeightField::height`] and
//!   [`HeightField::normal`] evaluate the fBm (rescaled exactly as the grid is) at any
//!   (x, z), inside the square too, so blade roots, picking, balls and the camera stand on
//!   the same surface the terrain's vertex shader draws (`shaders/terrain_height.wgsl` is
//!   the twin). With `terrain.unbounded = false` the function is evaluated at (x, z)
//!   clamped into the square: past the edge the edge heights continue, level outward.
//! * `Png` is a sampled grid and stays bounded in data: bilinear between grid vertices,
//!   central differences for the normal, and past the edge the edge heights continue
//!   (clamped), so an unbounded height-map scene extends its border flat to the horizon.

use std::path::Path;

use glam::Vec3;

use super::grid::{bilinear, load_grey, resample, to_grid};
use super::noise::{fbm_grad, octave_seeds};
use crate::error::{Error, Result};
use crate::scene::types::{HeightSource, Terrain};

/// Largest accepted `terrain.resolution`: 16385² vertices is already 1 GiB of heights.
pub const MAX_RESOLUTION: u32 = 16385;

/// A `resolution × resolution` grid of heights covering x, z in `[-size/2, size/2]`,
/// row-major with x fastest: vertex `(i, j)` is at
/// `x = -size/2 + i·spacing`, `z = -size/2 + j·spacing`, `spacing = size / (resolution − 1)`.
#[derive(Clone, Debug, PartialEq)]
pub struct HeightField {
    /// Side of the square in metres.
    pub size: f32,
    /// Grid vertices per side (at least 2).
    pub resolution: u32,
    /// Height of each vertex in metres, `resolution²` of them, row-major with x fastest.
    pub heights: Vec<f32>,
    /// What lies between and beyond the grid vertices.
    pub surface: Surface,
    /// Whether the analytic surface continues past the square (`terrain.unbounded`).
    pub unbounded: bool,
}

/// How heights between and beyond the grid vertices are found.
#[derive(Clone, Debug, PartialEq)]
pub enum Surface {
    /// Bilinear between grid vertices; outside the square the edge heights continue.
    Grid,
    /// The analytic fBm, equal to the grid at its vertices (up to f32 rounding).
    Noise(NoiseSurface),
}

/// `height(x, z) = (fbm(x, z) − mid) · scale`: the fBm of [`super::fbm`] with the
/// rescaling the grid got (so `amplitude` is the peak-to-peak height inside the square;
/// outside it the hills may reach a little higher or lower). `Flat` is the case of no
/// octaves and scale 0.
#[derive(Clone, Debug, PartialEq)]
pub struct NoiseSurface {
    /// Seed of each octave (`octave_seeds`); empty for the flat plane.
    pub seeds: Vec<u32>,
    /// Wavelength of the first octave in metres.
    pub wavelength: f64,
    /// The fBm value that maps to height 0: the middle of its range over the grid.
    pub mid: f64,
    /// Metres of height per unit of fBm (`amplitude` over the grid's fBm range); 0 for the
    /// flat plane.
    pub scale: f64,
}

impl NoiseSurface {
    /// The flat plane y = 0.
    pub fn flat() -> Self {
        Self {
            seeds: Vec::new(),
            wavelength: 1.0,
            mid: 0.0,
            scale: 0.0,
        }
    }

    /// Height and gradient `(∂h/∂x, ∂h/∂z)` at `(x, z)`.
    pub fn eval(&self, x: f64, z: f64) -> (f64, f64, f64) {
        if self.seeds.is_empty() || self.scale == 0.0 {
            return (0.0, 0.0, 0.0);
        }
        let (h, gx, gz) = fbm_grad(&self.seeds, self.wavelength, x, z);
        (
            (h - self.mid) * self.scale,
            gx * self.scale,
            gz * self.scale,
        )
    }
}

impl HeightField {
    /// A flat field at height 0.
    pub fn flat(size: f32, resolution: u32) -> Self {
        let resolution = resolution.max(2);
        Self {
            size,
            resolution,
            heights: vec![0.0; (resolution as usize).pow(2)],
            surface: Surface::Grid,
            unbounded: true,
        }
    }

    /// Builds the field the scene describes.
    ///
    /// * `Noise`: fBm of value noise, rescaled so that the lowest and highest grid vertex
    ///   are exactly `amplitude` apart, centred on 0 m.
    /// * `Png`: the image (image row 0 at z = −size/2, column 0 at x = −size/2) resampled
    ///   onto the grid, black = 0 m, white = `scale` m.
    /// * `Flat`: 0 m everywhere.
    pub fn from_scene(terrain: &Terrain) -> Result<Self> {
        let size = terrain.size;
        if !(size.is_finite() && size > 0.0) {
            return Err(Error::Invalid(format!(
                "terrain.size must be a positive number of metres, got {size}"
            )));
        }
        let resolution = terrain.resolution;
        if !(2..=MAX_RESOLUTION).contains(&resolution) {
            return Err(Error::Invalid(format!(
                "terrain.resolution must be in 2..={MAX_RESOLUTION}, got {resolution}"
            )));
        }
        let mut surface = Surface::Grid;
        let heights = match &terrain.height {
            HeightSource::Flat => {
                surface = Surface::Noise(NoiseSurface::flat());
                vec![0.0; (resolution as usize).pow(2)]
            }
            &HeightSource::Noise {
                seed,
                amplitude,
                wavelength,
                octaves,
            } => {
                if !(wavelength.is_finite() && wavelength > 0.0) {
                    return Err(Error::Invalid(format!(
                        "terrain noise wavelength must be a positive number of metres, got {wavelength}"
                    )));
                }
                if !amplitude.is_finite() {
                    return Err(Error::Invalid(format!(
                        "terrain noise amplitude must be finite, got {amplitude}"
                    )));
                }
                let (heights, noise) =
                    noise_heights(size, resolution, seed, amplitude, wavelength, octaves);
                surface = Surface::Noise(noise);
                heights
            }
            HeightSource::Png { path, scale } => {
                if !scale.is_finite() {
                    return Err(Error::Invalid(format!(
                        "terrain height map scale must be finite, got {scale}"
                    )));
                }
                let image = load_grey(Path::new(path))?;
                resample(&image, resolution)
                    .into_iter()
                    .map(|luma| luma * scale)
                    .collect()
            }
        };
        Ok(Self {
            size,
            resolution,
            heights,
            surface,
            unbounded: terrain.unbounded,
        })
    }

    /// Where the analytic surface is evaluated for `(x, z)`: the point itself, or clamped
    /// into the square when the terrain is bounded.
    fn analytic_point(&self, x: f32, z: f32) -> (f64, f64) {
        if self.unbounded {
            (f64::from(x), f64::from(z))
        } else {
            let half = 0.5 * self.size;
            (
                f64::from(x.clamp(-half, half)),
                f64::from(z.clamp(-half, half)),
            )
        }
    }

    /// Distance between neighbouring grid vertices.
    pub fn spacing(&self) -> f32 {
        self.size / (self.resolution.max(2) - 1) as f32
    }

    /// The grid vertex `(i, j)` in world space.
    pub fn vertex(&self, i: u32, j: u32) -> Vec3 {
        let s = self.spacing();
        let h = self.heights[(j * self.resolution + i) as usize];
        Vec3::new(
            -0.5 * self.size + i as f32 * s,
            h,
            -0.5 * self.size + j as f32 * s,
        )
    }

    /// Height at `(x, z)`: the analytic surface, or bilinear between grid vertices with the
    /// edge heights continuing outside the square.
    pub fn height(&self, x: f32, z: f32) -> f32 {
        if let Surface::Noise(noise) = &self.surface {
            if x.is_nan() || z.is_nan() {
                return f32::NAN;
            }
            let (px, pz) = self.analytic_point(x, z);
            return noise.eval(px, pz).0 as f32;
        }
        let u = to_grid(x, self.size, self.resolution);
        let v = to_grid(z, self.size, self.resolution);
        bilinear(&self.heights, self.resolution, self.resolution, u, v)
    }

    /// Unit surface normal at `(x, z)`: from the analytic gradient, or for a grid from
    /// central differences one grid spacing apart (one-sided at the edges, where the wider
    /// stencil would leave the square).
    pub fn normal(&self, x: f32, z: f32) -> Vec3 {
        if let Surface::Noise(noise) = &self.surface {
            let (px, pz) = self.analytic_point(x, z);
            let (_, gx, gz) = noise.eval(px, pz);
            // Bounded: level past the edge, like the clamped grid.
            let half = f64::from(0.5 * self.size);
            let gx = if px.abs() < half || self.unbounded {
                gx
            } else {
                0.0
            };
            let gz = if pz.abs() < half || self.unbounded {
                gz
            } else {
                0.0
            };
            return Vec3::new(-gx as f32, 1.0, -gz as f32).normalize();
        }
        let d = self.spacing();
        let half = 0.5 * self.size;
        let (x0, x1) = ((x - d).max(-half), (x + d).min(half));
        let (z0, z1) = ((z - d).max(-half), (z + d).min(half));
        // Outside the square the heights are clamped, so the surface is level there.
        let dx = if x1 > x0 {
            (self.height(x1, z) - self.height(x0, z)) / (x1 - x0)
        } else {
            0.0
        };
        let dz = if z1 > z0 {
            (self.height(x, z1) - self.height(x, z0)) / (z1 - z0)
        } else {
            0.0
        };
        Vec3::new(-dx, 1.0, -dz).normalize()
    }

    /// Bounds that every height inside the square lies within: the grid's own for a grid;
    /// for analytic noise the fBm's range [−1, 1] rescaled (between grid vertices the
    /// function may pass the sampled extremes).
    pub fn height_bounds(&self) -> (f32, f32) {
        let (lo, hi) = self.min_max();
        match &self.surface {
            Surface::Noise(n) if !n.seeds.is_empty() && n.scale != 0.0 => {
                let a = ((-1.0 - n.mid) * n.scale) as f32;
                let b = ((1.0 - n.mid) * n.scale) as f32;
                (lo.min(a.min(b)), hi.max(a.max(b)))
            }
            _ => (lo, hi),
        }
    }

    /// An upper bound of the surface's steepest slope, `|∇h|` (rise over run), anywhere:
    /// for a grid the largest height step between neighbouring vertices along x and along
    /// z over the spacing (bilinear cells slope no more than their edges; outside the square
    /// the edge heights continue), for analytic noise [`crate::field::fbm_max_gradient`] times the
    /// height scale. 0 for flat ground. Where the sun stands higher than this slope
    /// (`tan(elevation) > max_slope`) a ray towards it from anything on or above the ground
    /// rises faster than any hill, so the ground shadows nothing (`render::light`).
    pub fn max_slope(&self) -> f32 {
        if let Surface::Noise(n) = &self.surface {
            if n.seeds.is_empty() || n.scale == 0.0 {
                return 0.0;
            }
            return (super::fbm_max_gradient(n.seeds.len() as u32, n.wavelength) * n.scale.abs())
                as f32;
        }
        let r = self.resolution as usize;
        let (mut dx, mut dz) = (0.0f32, 0.0f32);
        for j in 0..r {
            for i in 0..r {
                let h = self.heights[j * r + i];
                if i + 1 < r {
                    dx = dx.max((self.heights[j * r + i + 1] - h).abs());
                }
                if j + 1 < r {
                    dz = dz.max((self.heights[(j + 1) * r + i] - h).abs());
                }
            }
        }
        dx.hypot(dz) / self.spacing()
    }

    /// Whether the ground may shadow anything under a sun whose direction has height
    /// `sun_y` ([`slope_may_shadow`] of [`Self::max_slope`]).
    pub fn may_shadow(&self, sun_y: f32) -> bool {
        slope_may_shadow(self.max_slope(), sun_y)
    }

    /// Lowest and highest grid height.
    pub fn min_max(&self) -> (f32, f32) {
        self.heights
            .iter()
            .fold((f32::INFINITY, f32::NEG_INFINITY), |(lo, hi), &h| {
                (lo.min(h), hi.max(h))
            })
    }
}

/// Whether ground whose slopes are at most `max_slope` may shadow anything under a sun
/// whose direction has height `sun_y`: only if the sun is no higher than the steepest
/// slope (`tan(elevation) ≤ max_slope`), or below the horizon.
pub fn slope_may_shadow(max_slope: f32, sun_y: f32) -> bool {
    let y = sun_y.clamp(-1.0, 1.0);
    y <= 0.0 || max_slope * (1.0 - y * y).sqrt() >= y
}

/// fBm heights on the grid, rescaled to `amplitude` peak to peak around 0 m. Rescaling to
/// the sampled range (rather than the theoretical ±1 of the fBm) makes `amplitude` the
/// height difference the user actually sees.
fn noise_heights(
    size: f32,
    resolution: u32,
    seed: u64,
    amplitude: f32,
    wavelength: f32,
    octaves: u32,
) -> (Vec<f32>, NoiseSurface) {
    let seeds = octave_seeds(seed, octaves);
    let wavelength = f64::from(wavelength);
    let spacing = f64::from(size) / f64::from(resolution - 1);
    let half = 0.5 * f64::from(size);
    let mut raw = Vec::with_capacity((resolution as usize).pow(2));
    for j in 0..resolution {
        for i in 0..resolution {
            let x = -half + f64::from(i) * spacing;
            let z = -half + f64::from(j) * spacing;
            raw.push(fbm_grad(&seeds, wavelength, x, z).0);
        }
    }
    let (lo, hi) = raw
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), &h| {
            (lo.min(h), hi.max(h))
        });
    let span = hi - lo;
    if span <= 1e-12 {
        return (vec![0.0; raw.len()], NoiseSurface::flat());
    }
    let mid = 0.5 * (lo + hi);
    let scale = f64::from(amplitude) / span;
    let heights = raw
        .into_iter()
        .map(|h| ((h - mid) * scale) as f32)
        .collect();
    (
        heights,
        NoiseSurface {
            seeds,
            wavelength,
            mid,
            scale,
        },
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    fn noise_terrain() -> Terrain {
        Terrain {
            size: 40.0,
            resolution: 129,
            height: HeightSource::Noise {
                seed: 7,
                amplitude: 2.0,
                wavelength: 30.0,
                octaves: 4,
            },
            density_map: None,
            unbounded: true,
        }
    }

    /// `max_slope` bounds the slope everywhere, inside the square and far outside it, and
    /// is not so loose that it stops meaning anything (within 6× of the steepest slope
    /// found); a grid's bound is its steepest cell edge, flat ground has none.
    #[test]
    fn max_slope_bounds_every_slope() {
        let tan = |n: Vec3| n.x.hypot(n.z) / n.y;
        let noise = HeightField::from_scene(&noise_terrain()).unwrap();
        let grid = HeightField {
            surface: Surface::Grid,
            ..noise.clone()
        };
        for (field, outside) in [(&noise, 4000.0), (&grid, 0.0)] {
            let bound = field.max_slope();
            let mut steepest = 0.0f32;
            for k in 0..40_000 {
                let k = k as f32;
                let x = (k * 0.618_034).fract() * 40.0 - 20.0 + outside;
                let z = (k * 0.414_214).fract() * 40.0 - 20.0;
                steepest = steepest.max(tan(field.normal(x, z)));
            }
            assert!(steepest <= bound * 1.0001, "{steepest} > {bound}");
            assert!(steepest > bound / 6.0, "{steepest} vs {bound}");
        }
        assert_eq!(HeightField::flat(10.0, 9).max_slope(), 0.0);
    }

    /// Under a sun higher than `max_slope`, a ray towards it from any point on the ground
    /// (or above it) never passes under the ground again: marched in 5 cm steps over 60 m
    /// from 2,000 points. Under a sun low enough, some rays do, and `may_shadow` says so.
    #[test]
    fn ground_below_the_sun_height_shadows_nothing() {
        let field = HeightField::from_scene(&noise_terrain()).unwrap();
        let slope = field.max_slope();
        let occluded = |sun: Vec3| {
            (0..2000).any(|k| {
                let k = k as f32;
                let x = (k * 0.618_034).fract() * 40.0 - 20.0;
                let z = (k * 0.414_214).fract() * 40.0 - 20.0;
                let p = Vec3::new(x, field.height(x, z) + 1e-4, z);
                (1..1200).any(|s| {
                    let q = p + sun * (s as f32 * 0.05);
                    q.y < field.height(q.x, q.z)
                })
            })
        };
        let high_sun = Vec3::new(0.3, 1.0, 0.2).normalize();
        // The sun just above the bound: no point is shadowed by the ground.
        let just_above = {
            let e = slope.atan() * 1.02;
            Vec3::new(e.cos() * 0.8, e.sin(), e.cos() * 0.6)
        };
        for sun in [just_above, high_sun] {
            assert!(!field.may_shadow(sun.y), "{sun}");
            assert!(!occluded(sun), "{sun} shadowed with max slope {slope}");
        }
        let low = Vec3::new(0.99, 0.05, 0.1).normalize();
        assert!(occluded(low) && field.may_shadow(low.y));
        assert!(HeightField::flat(10.0, 9).may_shadow(-0.1));
        assert!(!HeightField::flat(10.0, 9).may_shadow(0.01));
    }

    #[test]
    fn noise_amplitude_is_peak_to_peak() {
        let field = HeightField::from_scene(&noise_terrain()).unwrap();
        assert_eq!(field.heights.len(), 129 * 129);
        let (lo, hi) = field.min_max();
        assert!((hi - lo - 2.0).abs() < 1e-4, "{lo} {hi}");
        assert!((hi + lo).abs() < 1e-4, "{lo} {hi}");
    }

    #[test]
    fn analytic_heights_match_the_grid_and_stay_in_bounds() {
        let field = HeightField::from_scene(&noise_terrain()).unwrap();
        let (lo, hi) = field.height_bounds();
        for j in (0..129).step_by(8) {
            for i in (0..129).step_by(8) {
                let v = field.vertex(i, j);
                assert!((field.height(v.x, v.z) - v.y).abs() < 1e-5, "{v}");
            }
        }
        // Far outside the square the function goes on (not the edge height) and stays in
        // the fBm's bounds.
        let mut differs = 0;
        for k in 0..200 {
            let (x, z) = (100.0 + k as f32 * 7.3, -5000.0 + k as f32 * 3.1);
            let h = field.height(x, z);
            assert!((lo..=hi).contains(&h), "{h}");
            differs += usize::from((h - field.height(20.0, 0.0)).abs() > 1e-3);
        }
        assert!(differs > 150);
        // Bounded: the edge heights continue, level.
        let mut bounded = noise_terrain();
        bounded.unbounded = false;
        let field = HeightField::from_scene(&bounded).unwrap();
        assert_eq!(field.height(300.0, 5.0), field.height(20.0, 5.0));
        assert_eq!(field.normal(300.0, 5.0).x, 0.0);
    }

    #[test]
    fn noise_is_seeded() {
        let a = HeightField::from_scene(&noise_terrain()).unwrap();
        let b = HeightField::from_scene(&noise_terrain()).unwrap();
        assert_eq!(a, b);
        let mut other = noise_terrain();
        if let HeightSource::Noise { seed, .. } = &mut other.height {
            *seed = 8;
        }
        assert_ne!(a, HeightField::from_scene(&other).unwrap());
    }

    #[test]
    fn noise_hills_are_gentle() {
        // 2 m over a 30 m wavelength: no slope anywhere near a cliff.
        let field = HeightField::from_scene(&noise_terrain()).unwrap();
        for k in 0..400 {
            let x = -20.0 + (k % 20) as f32 * 2.0 + 0.3;
            let z = -20.0 + (k / 20) as f32 * 2.0 + 0.7;
            assert!(field.normal(x, z).y > 0.8, "steep at {x} {z}");
        }
    }

    #[test]
    fn height_is_bilinear_and_clamped() {
        let mut field = HeightField::flat(2.0, 3);
        // Vertices at -1, 0, 1 on both axes; a ramp in x.
        for j in 0..3 {
            for i in 0..3 {
                field.heights[j * 3 + i] = i as f32;
            }
        }
        assert_eq!(field.height(-1.0, 0.0), 0.0);
        assert!((field.height(0.5, 0.3) - 1.5).abs() < 1e-6);
        assert_eq!(field.height(5.0, 5.0), 2.0);
        assert_eq!(field.height(-5.0, 0.0), 0.0);
        assert_eq!(field.vertex(2, 1), Vec3::new(1.0, 2.0, 0.0));
        // Slope 1 in +x: normal (-1, 1, 0)/√2, also at the clamped edges.
        for x in [-1.0, -0.2, 0.0, 0.7, 1.0] {
            let n = field.normal(x, 0.1);
            assert!(
                (n - Vec3::new(-1.0, 1.0, 0.0).normalize()).length() < 1e-5,
                "{n}"
            );
        }
    }

    #[test]
    fn flat_source_is_flat() {
        let terrain = Terrain {
            height: HeightSource::Flat,
            ..noise_terrain()
        };
        let field = HeightField::from_scene(&terrain).unwrap();
        assert_eq!(field.min_max(), (0.0, 0.0));
        assert_eq!(field.normal(3.0, -4.0), Vec3::Y);
    }

    #[test]
    fn bad_values_are_rejected() {
        let mut terrain = noise_terrain();
        terrain.resolution = 1;
        assert!(matches!(
            HeightField::from_scene(&terrain),
            Err(Error::Invalid(_))
        ));
        let mut terrain = noise_terrain();
        terrain.size = 0.0;
        assert!(matches!(
            HeightField::from_scene(&terrain),
            Err(Error::Invalid(_))
        ));
    }

    #[test]
    fn png_heights_follow_luma_and_errors_name_the_path() {
        let dir = std::env::temp_dir().join(format!("sward-field-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        // 16-bit ramp: column 0 black, last column white.
        let path = dir.join("ramp16.png");
        let img = image::ImageBuffer::from_fn(5, 3, |x, _| image::Luma([(x * 65535 / 4) as u16]));
        img.save(&path).unwrap();
        let terrain = Terrain {
            size: 10.0,
            resolution: 9,
            height: HeightSource::Png {
                path: path.to_string_lossy().into_owned(),
                scale: 3.0,
            },
            density_map: None,
            unbounded: true,
        };
        let field = HeightField::from_scene(&terrain).unwrap();
        assert!(field.height(-5.0, 0.0).abs() < 1e-5);
        assert!((field.height(5.0, 2.0) - 3.0).abs() < 1e-4);
        assert!((field.height(0.0, -5.0) - 1.5).abs() < 1e-3);

        // 8-bit input is accepted too.
        let path8 = dir.join("ramp8.png");
        let img8 = image::ImageBuffer::from_fn(2, 2, |x, _| image::Luma([(x * 255) as u8]));
        img8.save(&path8).unwrap();
        let terrain8 = Terrain {
            height: HeightSource::Png {
                path: path8.to_string_lossy().into_owned(),
                scale: 1.0,
            },
            ..terrain.clone()
        };
        let field8 = HeightField::from_scene(&terrain8).unwrap();
        assert!((field8.height(5.0, 0.0) - 1.0).abs() < 1e-5);

        let missing = dir.join("missing.png");
        let terrain_missing = Terrain {
            height: HeightSource::Png {
                path: missing.to_string_lossy().into_owned(),
                scale: 1.0,
            },
            ..terrain.clone()
        };
        let err = HeightField::from_scene(&terrain_missing).unwrap_err();
        assert!(matches!(err, Error::Read { .. }));
        assert!(err.to_string().contains("missing.png"));

        let garbage = dir.join("garbage.png");
        std::fs::write(&garbage, b"not a png").unwrap();
        let terrain_garbage = Terrain {
            height: HeightSource::Png {
                path: garbage.to_string_lossy().into_owned(),
                scale: 1.0,
            },
            ..terrain
        };
        let err = HeightField::from_scene(&terrain_garbage).unwrap_err();
        assert!(matches!(err, Error::Image { .. }));
        assert!(err.to_string().contains("garbage.png"));
        let _ = std::fs::remove_dir_all(&dir);
    }
}
