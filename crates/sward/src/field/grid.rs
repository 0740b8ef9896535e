//! Shared plumbing of the height field and the density map: loading a grey PNG as floats
//! in `[0, 1]` and bilinear lookup in a row-major grid that spans the terrain square
//! corner to corner (the first and last sample sit on the square's edges).

use std::path::Path;

use crate::error::{Error, Result};

/// A grey image as row-major floats in `[0, 1]`, x (columns) fastest.
pub struct GreyImage {
    pub width: u32,
    pub height: u32,
    pub values: Vec<f32>,
}

/// Largest width and height of an image the terrain or the density map reads: 16384²
/// 16-bit samples are already 512 MiB, and a field never needs more detail than that.
pub const MAX_IMAGE_SIDE: u32 = 16384;

/// Loads any PNG (any bit depth, colour converted to luma) at 16 bits, so that 16-bit
/// height maps keep their precision and 8-bit ones lose nothing.
///
/// The header's size is checked before anything is decoded, so that a small file that
/// declares a huge image is refused with its size (`declares 100000x100000 pixels; allowed
/// at most 16384x16384`) instead of an allocation failure or a bare "memory limit".
pub fn load_grey(path: &Path) -> Result<GreyImage> {
    // Reading and decoding apart so that a missing file is `Error::Read` (with the OS
    // reason) and a corrupt one is `Error::Image`, both naming the path.
    let bytes = crate::input::read_bytes(path, crate::input::MAX_IMAGE_BYTES)?;
    let image_error = |message: String| Error::Image {
        path: path.to_path_buf(),
        message,
    };
    let reader =
        || image::ImageReader::with_format(std::io::Cursor::new(&bytes), image::ImageFormat::Png);
    let (width, height) = reader()
        .into_dimensions()
        .map_err(|e| image_error(e.to_string()))?;
    if width > MAX_IMAGE_SIDE || height > MAX_IMAGE_SIDE {
        return Err(image_error(format!(
            "declares {width}x{height} pixels; allowed at most {MAX_IMAGE_SIDE}x{MAX_IMAGE_SIDE}"
        )));
    }
    let mut limits = image::Limits::default();
    limits.max_image_width = Some(MAX_IMAGE_SIDE);
    limits.max_image_height = Some(MAX_IMAGE_SIDE);
    // The largest allowed image decoded as 16-bit RGBA, the widest form a PNG decodes to.
    limits.max_alloc = Some(u64::from(MAX_IMAGE_SIDE).pow(2) * 8);
    let mut decoder = reader();
    decoder.limits(limits);
    let image = decoder
        .decode()
        .map_err(|e| image_error(e.to_string()))?
        .to_luma16();
    let (width, height) = image.dimensions();
    let values = image
        .into_raw()
        .into_iter()
        .map(|l| f32::from(l) / f32::from(u16::MAX))
        .collect();
    Ok(GreyImage {
        width,
        height,
        values,
    })
}

/// Maps a world coordinate in `[-size/2, size/2]` to a continuous grid index in
/// `[0, samples - 1]`, clamped so that lookups outside the square repeat the edge.
pub fn to_grid(coord: f32, size: f32, samples: u32) -> f32 {
    if samples < 2 || size <= 0.0 {
        return 0.0;
    }
    let last = (samples - 1) as f32;
    ((coord / size + 0.5) * last).clamp(0.0, last)
}

/// Bilinear lookup at continuous grid index `(u, v)` (already clamped to the grid).
pub fn bilinear(values: &[f32], width: u32, height: u32, u: f32, v: f32) -> f32 {
    let (w, h) = (width as usize, height as usize);
    let i0 = (u.floor() as usize).min(w - 1);
    let j0 = (v.floor() as usize).min(h - 1);
    let i1 = (i0 + 1).min(w - 1);
    let j1 = (j0 + 1).min(h - 1);
    let (tx, tz) = (u - i0 as f32, v - j0 as f32);
    let a = values[j0 * w + i0];
    let b = values[j0 * w + i1];
    let c = values[j1 * w + i0];
    let d = values[j1 * w + i1];
    let top = a + (b - a) * tx;
    let bottom = c + (d - c) * tx;
    top + (bottom - top) * tz
}

/// Resamples `image` bilinearly onto a `resolution × resolution` grid over the same square.
pub fn resample(image: &GreyImage, resolution: u32) -> Vec<f32> {
    let n = resolution as usize;
    let mut out = Vec::with_capacity(n * n);
    // Grid vertex i covers the same fraction of the square as image column u: both put
    // their first and last samples on the edges.
    let scale_u = if resolution > 1 {
        (image.width.saturating_sub(1)) as f32 / (resolution - 1) as f32
    } else {
        0.0
    };
    let scale_v = if resolution > 1 {
        (image.height.saturating_sub(1)) as f32 / (resolution - 1) as f32
    } else {
        0.0
    };
    for j in 0..resolution {
        for i in 0..resolution {
            let u = i as f32 * scale_u;
            let v = j as f32 * scale_v;
            out.push(bilinear(&image.values, image.width, image.height, u, v));
        }
    }
    out
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;

    #[test]
    fn bilinear_interpolates_and_hits_samples() {
        let values = [0.0, 1.0, 2.0, 3.0];
        assert_eq!(bilinear(&values, 2, 2, 0.0, 0.0), 0.0);
        assert_eq!(bilinear(&values, 2, 2, 1.0, 1.0), 3.0);
        assert!((bilinear(&values, 2, 2, 0.5, 0.5) - 1.5).abs() < 1e-6);
        assert!((bilinear(&values, 2, 2, 1.0, 0.5) - 2.0).abs() < 1e-6);
    }

    #[test]
    fn grid_coordinates_span_the_square() {
        assert_eq!(to_grid(-5.0, 10.0, 11), 0.0);
        assert_eq!(to_grid(5.0, 10.0, 11), 10.0);
        assert_eq!(to_grid(0.0, 10.0, 11), 5.0);
        assert_eq!(to_grid(99.0, 10.0, 11), 10.0);
        assert_eq!(to_grid(-99.0, 10.0, 11), 0.0);
    }

    #[test]
    fn resampling_keeps_corners() {
        let image = GreyImage {
            width: 3,
            height: 2,
            values: vec![0.0, 0.5, 1.0, 0.25, 0.5, 0.75],
        };
        let grid = resample(&image, 5);
        assert_eq!(grid[0], 0.0);
        assert_eq!(grid[4], 1.0);
        assert_eq!(grid[20], 0.25);
        assert_eq!(grid[24], 0.75);
    }

    /// A 1×1 grey PNG whose header says `width` × `height` (with a correct CRC), so that
    /// only the header check can refuse it.
    pub(crate) fn png_declaring(width: u32, height: u32) -> Vec<u8> {
        let mut bytes = Vec::new();
        image::ImageBuffer::from_pixel(1, 1, image::Luma([128u8]))
            .write_to(
                &mut std::io::Cursor::new(&mut bytes),
                image::ImageFormat::Png,
            )
            .expect("encode");
        // Signature (8), IHDR length (4), "IHDR" (4), width, height, ..., CRC at 29.
        bytes[16..20].copy_from_slice(&width.to_be_bytes());
        bytes[20..24].copy_from_slice(&height.to_be_bytes());
        let crc = crc32(&bytes[12..29]);
        bytes[29..33].copy_from_slice(&crc.to_be_bytes());
        bytes
    }

    /// The CRC-32 of PNG chunks (ISO 3309), bit by bit.
    fn crc32(data: &[u8]) -> u32 {
        let mut crc = 0xFFFF_FFFFu32;
        for &b in data {
            crc ^= u32::from(b);
            for _ in 0..8 {
                crc = if crc & 1 != 0 {
                    (crc >> 1) ^ 0xEDB8_8320
                } else {
                    crc >> 1
                };
            }
        }
        !crc
    }

    #[test]
    fn huge_declared_size_is_refused_before_decoding() {
        let dir = std::env::temp_dir().join(format!("sward-grid-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let huge = dir.join("huge.png");
        std::fs::write(&huge, png_declaring(100_000, 100_000)).unwrap();
        let err = load_grey(&huge).err().expect("refused");
        assert_eq!(
            err.to_string(),
            format!(
                "{}: cannot decode image: declares 100000x100000 pixels; allowed at most \
                 16384x16384",
                huge.display()
            )
        );
        // The same crafted header at a legal size decodes: the CRC is right.
        let small = dir.join("small.png");
        std::fs::write(&small, png_declaring(1, 1)).unwrap();
        assert_eq!(load_grey(&small).unwrap().values.len(), 1);
        let _ = std::fs::remove_dir_all(&dir);
    }
}
