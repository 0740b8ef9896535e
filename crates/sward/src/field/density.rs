//! The optional density map: a grey PNG stretched over the terrain square (row 0 at
//! z = −size/2, column 0 at x = −size/2), white = full density, black = no grass. Blade
//! placement keeps a candidate position with the probability this map gives there.

use std::path::Path;

use super::grid::{bilinear, load_grey, to_grid, GreyImage};
use crate::error::{Error, Result};
use crate::scene::types::Terrain;

/// Grass density in `[0, 1]` over the terrain square, sampled bilinearly.
#[derive(Clone, Debug, PartialEq)]
pub struct DensityMap {
    size: f32,
    width: u32,
    height: u32,
    values: Vec<f32>,
}

impl DensityMap {
    /// Loads a grey PNG (any bit depth) covering a square of side `size`.
    pub fn load(path: &Path, size: f32) -> Result<Self> {
        let GreyImage {
            width,
            height,
            values,
        } = load_grey(path)?;
        Self::from_values(size, width, height, values)
    }

    /// The scene's density map, if it names one.
    pub fn from_scene(terrain: &Terrain) -> Result<Option<Self>> {
        terrain
            .density_map
            .as_deref()
            .map(|path| Self::load(Path::new(path), terrain.size))
            .transpose()
    }

    /// A map from row-major values (x fastest); values are clamped to `[0, 1]`.
    pub fn from_values(size: f32, width: u32, height: u32, values: Vec<f32>) -> Result<Self> {
        if width == 0 || height == 0 || values.len() != width as usize * height as usize {
            return Err(Error::Invalid(format!(
                "density map needs {width}×{height} values, got {}",
                values.len()
            )));
        }
        // NaN becomes 0 (no grass) rather than poisoning the acceptance test.
        let values = values
            .into_iter()
            .map(|v| if v.is_nan() { 0.0 } else { v.clamp(0.0, 1.0) })
            .collect();
        Ok(Self {
            size,
            width,
            height,
            values,
        })
    }

    /// Density at `(x, z)` in `[0, 1]`; outside the square the edge values continue.
    pub fn sample(&self, x: f32, z: f32) -> f32 {
        let u = to_grid(x, self.size, self.width);
        let v = to_grid(z, self.size, self.height);
        bilinear(&self.values, self.width, self.height, u, v).clamp(0.0, 1.0)
    }

    /// Side of the square the map covers, in metres.
    pub fn size(&self) -> f32 {
        self.size
    }

    /// Width, height and the row-major values (x fastest) in `[0, 1]`.
    pub fn texels(&self) -> (u32, u32, &[f32]) {
        (self.width, self.height, &self.values)
    }

    /// The largest density anywhere: 0 means the map allows no grass at all, which lets
    /// placement skip its rejection loop instead of burning its whole attempt budget.
    pub fn max(&self) -> f32 {
        self.values.iter().fold(0.0, |m: f32, &v| m.max(v))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn samples_bilinearly_over_the_square() {
        let map = DensityMap::from_values(10.0, 2, 2, vec![0.0, 1.0, 0.0, 1.0]).unwrap();
        assert_eq!(map.sample(-5.0, -5.0), 0.0);
        assert_eq!(map.sample(5.0, 5.0), 1.0);
        assert!((map.sample(0.0, 3.0) - 0.5).abs() < 1e-6);
        assert_eq!(map.sample(50.0, 0.0), 1.0);
        assert_eq!(map.max(), 1.0);
    }

    #[test]
    fn values_are_clamped_and_sizes_checked() {
        let map = DensityMap::from_values(1.0, 1, 2, vec![-1.0, 7.0]).unwrap();
        assert_eq!(map.sample(0.0, -0.5), 0.0);
        assert_eq!(map.sample(0.0, 0.5), 1.0);
        assert!(DensityMap::from_values(1.0, 2, 2, vec![0.0]).is_err());
    }

    #[test]
    fn loads_png_and_reports_missing_file() {
        let dir = std::env::temp_dir().join(format!("sward-density-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let path = dir.join("half.png");
        image::ImageBuffer::from_fn(4, 4, |x, _| image::Luma([if x < 2 { 0u8 } else { 255 }]))
            .save(&path)
            .unwrap();
        let map = DensityMap::load(&path, 8.0).unwrap();
        assert_eq!(map.sample(-4.0, 0.0), 0.0);
        assert_eq!(map.sample(4.0, 0.0), 1.0);
        let err = DensityMap::load(&dir.join("nope.png"), 8.0).unwrap_err();
        assert!(err.to_string().contains("nope.png"));
        let _ = std::fs::remove_dir_all(&dir);
    }
}
