//! CPU twin of the depth pyramid (`shaders/hiz.wgsl`, built by
//! [`crate::render::hiz::DepthPyramid`]): level 0 is the depth buffer, each level above
//! keeps the farthest (largest) depth of the texels it covers. `max` is exact, so the GPU
//! must match this bit for bit.

/// Size of level `level` of a `width` x `height` pyramid: halved per level, rounded down,
/// never below 1 (the mip rule of WebGPU).
pub fn level_size(width: u32, height: u32, level: u32) -> (u32, u32) {
    let shrink = |n: u32| n.checked_shr(level).unwrap_or(0).max(1);
    (shrink(width), shrink(height))
}

/// Level 0 of a multisampled depth buffer: the farthest (largest) of each pixel's
/// `samples` samples, which sit at `[(y * width + x) * samples + s]` (what
/// `DepthPyramid::read_depth_samples` returns). `samples = 1` is the identity.
///
/// # Panics
/// If `depth.len()` is not a multiple of `samples`, or `samples` is 0.
pub fn farthest_samples(depth: &[f32], samples: usize) -> Vec<f32> {
    assert!(samples > 0 && depth.len().is_multiple_of(samples));
    depth
        .chunks_exact(samples)
        .map(|s| s.iter().copied().fold(0.0, f32::max))
        .collect()
}

/// Every level, row-major, from `depth` (`width * height` values) down to 1x1.
///
/// Level k's texel (x, y) takes the max over level k-1's texels [2x, 2x+2) x [2y, 2y+2),
/// widened to the end of the row/column for the last texel of an odd-sized level (the
/// texel rounding down drops): so every texel is >= every depth whose pixel it covers.
///
/// # Panics
/// If `depth.len() != width * height`.
pub fn build_pyramid(depth: &[f32], width: u32, height: u32) -> Vec<Vec<f32>> {
    assert_eq!(
        depth.len(),
        width as usize * height as usize,
        "depth is not {width}x{height}"
    );
    let levels = 32 - width.max(height).max(1).leading_zeros();
    let mut pyramid = vec![depth.to_vec()];
    for level in 1..levels {
        let (sw, sh) = level_size(width, height, level - 1);
        let (w, h) = level_size(width, height, level);
        let src = &pyramid[level as usize - 1];
        let mut dst = Vec::with_capacity((w * h) as usize);
        for y in 0..h {
            let y_end = if y == h - 1 { sh } else { (2 * y + 2).min(sh) };
            for x in 0..w {
                let x_end = if x == w - 1 { sw } else { (2 * x + 2).min(sw) };
                let mut far = 0.0f32;
                for sy in 2 * y..y_end {
                    for sx in 2 * x..x_end {
                        far = far.max(src[(sy * sw + sx) as usize]);
                    }
                }
                dst.push(far);
            }
        }
        pyramid.push(dst);
    }
    pyramid
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn farthest_sample_of_each_pixel() {
        let depth = [0.1, 0.9, 0.3, 0.2, 0.5, 0.5, 0.5, 0.5];
        assert_eq!(farthest_samples(&depth, 4), vec![0.9, 0.5]);
        assert_eq!(farthest_samples(&depth, 1), depth.to_vec());
    }

    #[test]
    fn sizes_halve_round_down_and_stop_at_one() {
        assert_eq!(level_size(37, 23, 0), (37, 23));
        assert_eq!(level_size(37, 23, 1), (18, 11));
        assert_eq!(level_size(37, 23, 4), (2, 1));
        assert_eq!(level_size(37, 23, 5), (1, 1));
        assert_eq!(level_size(1, 1, 40), (1, 1));
    }

    #[test]
    fn odd_sizes_fold_the_last_row_and_column_in() {
        // 5x3: level 1 is 2x1, level 2 is 1x1. Level 1's right texel must cover columns
        // 2..5 (3 wide) and both texels rows 0..3 (3 high).
        #[rustfmt::skip]
        let depth = [
            0.1, 0.2, 0.3, 0.4, 0.5,
            0.1, 0.1, 0.1, 0.1, 0.1,
            0.7, 0.1, 0.1, 0.1, 0.9,
        ];
        let p = build_pyramid(&depth, 5, 3);
        assert_eq!(p.len(), 3);
        assert_eq!(p[0], depth);
        // Left: max of columns 0..2, rows 0..3 (0.7 sits in the odd last row).
        // Right: columns 2..5, rows 0..3 (0.9 sits in the odd last row and column).
        assert_eq!(p[1], vec![0.7, 0.9]);
        assert_eq!(p[2], vec![0.9]);
    }

    #[test]
    fn every_level_covers_the_depths_below_it() {
        let (w, h) = (13u32, 7u32);
        let depth: Vec<f32> = (0..w * h)
            .map(|i| ((i * 37) % 101) as f32 / 100.0)
            .collect();
        let p = build_pyramid(&depth, w, h);
        let top = depth.iter().copied().fold(0.0, f32::max);
        assert_eq!(p.last().unwrap(), &vec![top]);
        for (k, level) in p.iter().enumerate() {
            let (lw, lh) = level_size(w, h, k as u32);
            assert_eq!(level.len(), (lw * lh) as usize);
            for y in 0..h {
                for x in 0..w {
                    let tx = (x >> k).min(lw - 1);
                    let ty = (y >> k).min(lh - 1);
                    assert!(level[(ty * lw + tx) as usize] >= depth[(y * w + x) as usize]);
                }
            }
        }
    }
}
