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

/// Rows of one band of the far-field comparison (issue 27, point 1).
pub const BAND_ROWS: u32 = 8;
/// Side of the square blocks whose luminance spread is a band's local contrast.
pub const BAND_BLOCK: u32 = 8;
/// Largest difference of a band's mean luminance (0–255) for the levels to read as one.
pub const BAND_LUMINANCE_TOLERANCE: f64 = 5.0;
/// Largest relative difference of a band's local contrast.
pub const BAND_CONTRAST_TOLERANCE: f64 = 0.3;

/// One band of rows of an image: its mean luminance and local contrast.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct Band {
    /// First row.
    pub top: u32,
    /// Mean Rec. 709 luminance of the 8-bit values, 0–255.
    pub luminance: f64,
    /// Mean over the band's `BAND_BLOCK`-wide blocks of the luminance's standard deviation.
    pub contrast: f64,
}

fn luma(p: &image::Rgba<u8>) -> f64 {
    0.2126 * f64::from(p[0]) + 0.7152 * f64::from(p[1]) + 0.0722 * f64::from(p[2])
}

/// The whole bands of `BAND_ROWS` rows of `img`, top to bottom.
pub fn bands(img: &image::RgbaImage) -> Vec<Band> {
    let (w, h) = img.dimensions();
    (0..h / BAND_ROWS)
        .map(|b| {
            let top = b * BAND_ROWS;
            let mut sum = 0.0;
            let mut spread = 0.0;
            let blocks = (w / BAND_BLOCK).max(1);
            for k in 0..blocks {
                let (mut s, mut s2, mut n) = (0.0, 0.0, 0.0);
                for y in top..top + BAND_ROWS {
                    for x in k * BAND_BLOCK..((k + 1) * BAND_BLOCK).min(w) {
                        let l = luma(img.get_pixel(x, y));
                        s += l;
                        s2 += l * l;
                        n += 1.0;
                    }
                }
                sum += s;
                let mean = s / f64::max(n, 1.0);
                spread += (s2 / f64::max(n, 1.0) - mean * mean).max(0.0).sqrt();
            }
            Band {
                top,
                luminance: sum / f64::from((w * BAND_ROWS).max(1)),
                contrast: spread / f64::from(blocks),
            }
        })
        .collect()
}

/// How one band of an image differs from the same band of a reference.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct BandDiff {
    /// First row of the band, in pixels from the top of the image.
    pub top: u32,
    /// The image's mean luminance minus the reference's (0–255).
    pub luminance: f64,
    /// The image's local contrast over the reference's, minus 1.
    pub contrast: f64,
}

impl BandDiff {
    /// Whether the band reads as the reference's (issue 27's 5 levels and 30 %).
    pub fn within_tolerance(&self) -> bool {
        self.luminance.abs() <= BAND_LUMINANCE_TOLERANCE
            && self.contrast.abs() <= BAND_CONTRAST_TOLERANCE
    }
}

/// `Some` when the two images have the same size (the comparisons' precondition).
fn same_size(img: &image::RgbaImage, reference: &image::RgbaImage) -> Option<()> {
    (img.dimensions() == reference.dimensions()).then_some(())
}

/// Pixels of `img` whose colour differs from `reference`'s at all; `None` when the sizes
/// differ. Zero says a comparison of the two measured nothing (the configurations drew
/// the same frame: a far ground hidden behind hills draws the same whether the cards
/// reach it or not).
pub fn differing_pixels(img: &image::RgbaImage, reference: &image::RgbaImage) -> Option<usize> {
    same_size(img, reference)?;
    Some(
        img.pixels()
            .zip(reference.pixels())
            .filter(|(a, b)| a.0[..3] != b.0[..3])
            .count(),
    )
}

/// The bands of `img` against those of `reference` whose top row lies in `rows`;
/// `None` when the sizes differ.
pub fn compare_bands(
    img: &image::RgbaImage,
    reference: &image::RgbaImage,
    rows: std::ops::Range<u32>,
) -> Option<Vec<BandDiff>> {
    same_size(img, reference)?;
    Some(diff_bands(&bands(img), &bands(reference), rows))
}

/// The bands `img` (of an image, [`bands`]) against `reference` (of an image of the same
/// size) whose top row lies in `rows`: what [`compare_bands`] gives for the two images,
/// from their bands alone (a run can keep the bands of many frames, not their images).
pub fn diff_bands(img: &[Band], reference: &[Band], rows: std::ops::Range<u32>) -> Vec<BandDiff> {
    img.iter()
        .zip(reference)
        .filter(|(a, _)| rows.contains(&a.top))
        .map(|(a, b)| BandDiff {
            top: a.top,
            luminance: a.luminance - b.luminance,
            // Two flat bands (the sky) have the same contrast.
            contrast: if a.contrast < 1e-6 && b.contrast < 1e-6 {
                0.0
            } else {
                a.contrast / b.contrast.max(1e-6) - 1.0
            },
        })
        .collect()
}

/// The band that differs most: by luminance over its tolerance, or by contrast over its.
pub fn worst_band(diffs: &[BandDiff]) -> Option<BandDiff> {
    let score = |d: &BandDiff| {
        (d.luminance.abs() / BAND_LUMINANCE_TOLERANCE)
            .max(d.contrast.abs() / BAND_CONTRAST_TOLERANCE)
    };
    diffs
        .iter()
        .copied()
        .max_by(|a, b| score(a).total_cmp(&score(b)))
}

/// Blocks across a band for [`compare_blocks`]: each an eighth of the width.
pub const BAND_SECTORS: u32 = 8;

/// How one block (a band's rows across an eighth of the width) of an image differs from
/// the same block of a reference in mean luminance (0–255). The bands' means can hide a
/// field that reads brighter on one side of the view and darker on the other (the far
/// levels against the blades they replace: the sun and the wind light the grass by the
/// direction it is seen in).
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct BlockDiff {
    /// First row of the block's band.
    pub top: u32,
    /// Which eighth of the width, from the left.
    pub sector: u32,
    /// The image's mean luminance minus the reference's.
    pub luminance: f64,
}

fn block_means(img: &image::RgbaImage, top: u32) -> [f64; BAND_SECTORS as usize] {
    let (w, h) = img.dimensions();
    let mut out = [0.0; BAND_SECTORS as usize];
    for (k, m) in out.iter_mut().enumerate() {
        let (x0, x1) = (k as u32 * w / BAND_SECTORS, (k as u32 + 1) * w / BAND_SECTORS);
        let (mut sum, mut n) = (0.0, 0.0);
        for y in top..(top + BAND_ROWS).min(h) {
            for x in x0..x1 {
                sum += luma(img.get_pixel(x, y));
                n += 1.0;
            }
        }
        *m = sum / f64::max(n, 1.0);
    }
    out
}

/// Every block of the whole bands of `img` against `reference` whose top row lies in
/// `rows`, band by band from the top, left to right; `None` when the sizes differ.
pub fn compare_blocks(
    img: &image::RgbaImage,
    reference: &image::RgbaImage,
    rows: std::ops::Range<u32>,
) -> Option<Vec<BlockDiff>> {
    same_size(img, reference)?;
    let bands = img.height() / BAND_ROWS;
    let mut out = Vec::new();
    for b in 0..bands {
        let top = b * BAND_ROWS;
        if !rows.contains(&top) {
            continue;
        }
        let (a, r) = (block_means(img, top), block_means(reference, top));
        for (k, (x, y)) in a.iter().zip(&r).enumerate() {
            out.push(BlockDiff {
                top,
                sector: k as u32,
                luminance: x - y,
            });
        }
    }
    Some(out)
}

/// The block whose luminance differs most.
pub fn worst_block(diffs: &[BlockDiff]) -> Option<BlockDiff> {
    diffs
        .iter()
        .copied()
        .max_by(|a, b| a.luminance.abs().total_cmp(&b.luminance.abs()))
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

    #[test]
    fn differing_pixels_counts_colour_not_alpha() {
        let a = image::RgbaImage::from_pixel(6, 4, image::Rgba([10, 20, 30, 255]));
        let mut b = a.clone();
        b.put_pixel(0, 0, image::Rgba([10, 20, 30, 0]));
        assert_eq!(differing_pixels(&a, &b), Some(0));
        b.put_pixel(5, 3, image::Rgba([10, 21, 30, 255]));
        b.put_pixel(2, 1, image::Rgba([11, 20, 30, 255]));
        assert_eq!(differing_pixels(&a, &b), Some(2));
        assert_eq!(differing_pixels(&a, &image::RgbaImage::new(4, 6)), None);
    }

    #[test]
    fn bands_measure_mean_luminance_and_block_contrast() {
        // 16 x 16: the top band flat grey 100; the bottom band a checkerboard of 0 and 200
        // (mean 100, every block's spread 100).
        let img = image::RgbaImage::from_fn(16, 16, |x, y| {
            let v = if y < 8 {
                100
            } else if (x + y) % 2 == 0 {
                0
            } else {
                200
            };
            image::Rgba([v, v, v, 255])
        });
        let b = bands(&img);
        assert_eq!(b.len(), 2);
        assert!((b[0].luminance - 100.0).abs() < 1e-9 && b[0].contrast < 1e-9);
        assert!((b[1].luminance - 100.0).abs() < 1e-9);
        assert!((b[1].contrast - 100.0).abs() < 1e-9);
        // Against a reference darker by 6 levels with half the contrast: both off.
        let reference = image::RgbaImage::from_fn(16, 16, |x, y| {
            let v = if y < 8 {
                94
            } else if (x + y) % 2 == 0 {
                44
            } else {
                144
            };
            image::Rgba([v, v, v, 255])
        });
        let d = compare_bands(&img, &reference, 0..16).expect("same size");
        assert!((d[0].luminance - 6.0).abs() < 1e-9 && !d[0].within_tolerance());
        assert!((d[1].contrast - 1.0).abs() < 1e-9 && !d[1].within_tolerance());
        assert_eq!(worst_band(&d).map(|w| w.top), Some(8));
        assert_eq!(
            compare_bands(&img, &reference, 8..16).expect("same").len(),
            1
        );
    }

    #[test]
    fn blocks_find_a_side_the_band_mean_hides() {
        // 32 x 16: the image's left half 10 levels above the reference, its right half 10
        // below; the bands' means agree.
        let reference = image::RgbaImage::from_pixel(32, 16, image::Rgba([100, 100, 100, 255]));
        let img = image::RgbaImage::from_fn(32, 16, |x, _| {
            let v = if x < 16 { 110 } else { 90 };
            image::Rgba([v, v, v, 255])
        });
        let bands = compare_bands(&img, &reference, 0..16).expect("same size");
        assert!(bands.iter().all(|d| d.luminance.abs() < 1e-9));
        let blocks = compare_blocks(&img, &reference, 0..16).expect("same size");
        assert_eq!(blocks.len(), 2 * BAND_SECTORS as usize);
        for d in &blocks {
            let want = if d.sector < BAND_SECTORS / 2 { 10.0 } else { -10.0 };
            assert!((d.luminance - want).abs() < 1e-9, "{d:?}");
        }
        assert_eq!(worst_block(&blocks).map(|w| w.luminance.abs()), Some(10.0));
        assert_eq!(compare_blocks(&img, &reference, 8..16).expect("same").len(), 8);
        assert!(compare_blocks(&img, &image::RgbaImage::new(4, 4), 0..4).is_none());
        assert!(worst_block(&[]).is_none());
    }
}
