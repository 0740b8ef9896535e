//! Image comparison with the snapshot test's measure: the mean per-channel difference and
//! the share of pixels whose worst channel differs by more than a threshold. The snapshot
//! test and `sward bench` (culled against unculled frames) use the same tolerances.

/// Largest mean per-channel difference (0–255 scale) a matching render may have.
pub const MEAN_TOLERANCE: f64 = 2.0;
/// A pixel fails when some channel differs by more than this.
pub const PIXEL_TOLERANCE: u8 = 48;
/// Largest share of failing pixels a matching render may have.
pub const MAX_FAILING: f64 = 0.01;

/// How two images of the same size differ.
#[derive(Clone, Debug)]
pub struct ImageDiff {
    /// Mean per-channel difference over RGB, 0–255.
    pub mean: f64,
    /// Share of pixels with a channel off by more than `PIXEL_TOLERANCE`.
    pub failing: f64,
    /// The worst channel difference per pixel, ×4, in red (for looking at).
    pub image: image::RgbaImage,
}

impl ImageDiff {
    /// Whether the difference stays within the snapshot tolerances.
    pub fn within_tolerance(&self) -> bool {
        self.mean <= MEAN_TOLERANCE && self.failing <= MAX_FAILING
    }
}

/// Compares `a` against `b`; `None` when their sizes differ.
pub fn compare(a: &image::RgbaImage, b: &image::RgbaImage) -> Option<ImageDiff> {
    if a.dimensions() != b.dimensions() {
        return None;
    }
    let mut sum = 0u64;
    let mut failing = 0usize;
    let mut image = image::RgbaImage::new(a.width(), a.height());
    for (x, y, pa) in a.enumerate_pixels() {
        let pb = b.get_pixel(x, y);
        let d = [0, 1, 2].map(|c| pa[c].abs_diff(pb[c]));
        sum += d.iter().map(|&v| u64::from(v)).sum::<u64>();
        let worst = d.into_iter().max().unwrap_or(0);
        if worst > PIXEL_TOLERANCE {
            failing += 1;
        }
        image.put_pixel(x, y, image::Rgba([worst.saturating_mul(4), 0, 0, 255]));
    }
    let pixels = (f64::from(a.width()) * f64::from(a.height())).max(1.0);
    Some(ImageDiff {
        mean: sum as f64 / (pixels * 3.0),
        failing: failing as f64 / pixels,
        image,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn identical_images_do_not_differ_and_one_bright_pixel_is_counted() {
        let a = image::RgbaImage::from_pixel(10, 10, image::Rgba([10, 20, 30, 255]));
        let same = compare(&a, &a).expect("same size");
        assert_eq!(same.mean, 0.0);
        assert_eq!(same.failing, 0.0);
        assert!(same.within_tolerance());
        let mut b = a.clone();
        b.put_pixel(3, 4, image::Rgba([210, 20, 30, 255]));
        let d = compare(&a, &b).expect("same size");
        assert!((d.mean - 200.0 / 300.0).abs() < 1e-9);
        assert!((d.failing - 0.01).abs() < 1e-12);
        assert_eq!(d.image.get_pixel(3, 4)[0], 255);
        assert!(compare(&a, &image::RgbaImage::new(5, 5)).is_none());
    }
}
