//! Patch generation (paper, Section 4, "Patch generation"): the blades are split into
//! patches of exactly `patch_size` blades that are as compact as possible (tight boxes
//! cull better), and each patch is sorted so that nearby blades have nearby indices.
//!
//! The balanced clustering is a k-d split: the set is cut across its longer x/z extent at
//! the multiple of `patch_size` nearest the median, recursively, until one patch remains.
//! Inside a patch the blades follow the Morton (Z-order) curve, which keeps neighbours
//! close in both axes, unlike the paper's lexicographic sort which only does so in one.

use super::blade::{Blade, PatchBox};

/// Reorders `blades` into consecutive patches of `patch_size` blades and returns their
/// boxes. `blades.len()` must be a multiple of `patch_size`.
pub fn build_patches(blades: &mut [Blade], patch_size: usize) -> Vec<PatchBox> {
    assert!(patch_size > 0 && blades.len().is_multiple_of(patch_size));
    split(blades, patch_size);
    blades
        .chunks_mut(patch_size)
        .map(|patch| {
            morton_sort(patch);
            patch_box(patch)
        })
        .collect()
}

fn x(b: &Blade) -> f32 {
    b.v0_dir[0]
}

fn z(b: &Blade) -> f32 {
    b.v0_dir[2]
}

/// x/z bounds of the roots: (min x, max x, min z, max z).
fn root_bounds(blades: &[Blade]) -> (f32, f32, f32, f32) {
    blades.iter().fold(
        (
            f32::INFINITY,
            f32::NEG_INFINITY,
            f32::INFINITY,
            f32::NEG_INFINITY,
        ),
        |(x0, x1, z0, z1), b| (x0.min(x(b)), x1.max(x(b)), z0.min(z(b)), z1.max(z(b))),
    )
}

/// Balanced k-d split in place: afterwards every run of `patch_size` blades is one patch.
fn split(blades: &mut [Blade], patch_size: usize) {
    let patches = blades.len() / patch_size;
    if patches <= 1 {
        return;
    }
    let (x0, x1, z0, z1) = root_bounds(blades);
    let key: fn(&Blade) -> f32 = if x1 - x0 >= z1 - z0 { x } else { z };
    // Half the patches on each side (one fewer on the left when odd): the cut sits at the
    // median when it can, else one patch away from it.
    let left = patches / 2 * patch_size;
    blades.select_nth_unstable_by(left, |a, b| key(a).total_cmp(&key(b)));
    let (lo, hi) = blades.split_at_mut(left);
    split(lo, patch_size);
    split(hi, patch_size);
}

/// Spreads the low 16 bits of `v` to the even bits.
fn part1by1(v: u32) -> u32 {
    let mut v = v & 0xFFFF;
    v = (v | (v << 8)) & 0x00FF_00FF;
    v = (v | (v << 4)) & 0x0F0F_0F0F;
    v = (v | (v << 2)) & 0x3333_3333;
    (v | (v << 1)) & 0x5555_5555
}

/// The Morton code of `(qx, qz)`: x on the even bits, z on the odd bits.
pub fn morton(qx: u32, qz: u32) -> u32 {
    part1by1(qx) | (part1by1(qz) << 1)
}

/// Sorts a patch along the Z-order curve of its roots quantised to 16 bits over the
/// patch's own x/z box (so the full 16 bits resolve the patch, whatever its size).
fn morton_sort(patch: &mut [Blade]) {
    let (x0, x1, z0, z1) = root_bounds(patch);
    let quantise = |v: f32, lo: f32, hi: f32| {
        if hi > lo {
            ((v - lo) / (hi - lo) * 65535.0).round().clamp(0.0, 65535.0) as u32
        } else {
            0
        }
    };
    // The index breaks ties, so the order is total and the result deterministic.
    let mut keys: Vec<(u32, u32)> = patch
        .iter()
        .enumerate()
        .map(|(i, b)| {
            (
                morton(quantise(x(b), x0, x1), quantise(z(b), z0, z1)),
                i as u32,
            )
        })
        .collect();
    keys.sort_unstable();
    let sorted: Vec<Blade> = keys.iter().map(|&(_, i)| patch[i as usize]).collect();
    patch.copy_from_slice(&sorted);
}

/// The box of the roots grown by the tallest blade in every direction: a tip never gets
/// further from its root than the blade's height (the curve length is the height), so the
/// box holds every pose the simulation can produce. `max[3]` is the smallest up.y of its
/// blades (how far they lean at most), which bounds their distance test from below.
pub(super) fn patch_box(patch: &[Blade]) -> PatchBox {
    let mut min = [f32::INFINITY; 3];
    let mut max = [f32::NEG_INFINITY; 3];
    let mut tallest = 0.0f32;
    let mut up_y = 1.0f32;
    for b in patch {
        for k in 0..3 {
            min[k] = min[k].min(b.v0_dir[k]);
            max[k] = max[k].max(b.v0_dir[k]);
        }
        tallest = tallest.max(b.v1_height[3]);
        up_y = up_y.min(b.up_stiffness[1]);
    }
    PatchBox {
        min: [min[0] - tallest, min[1] - tallest, min[2] - tallest, 0.0],
        max: [max[0] + tallest, max[1] + tallest, max[2] + tallest, up_y],
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn morton_interleaves() {
        assert_eq!(morton(0, 0), 0);
        assert_eq!(morton(1, 0), 1);
        assert_eq!(morton(0, 1), 2);
        assert_eq!(morton(3, 3), 15);
        assert_eq!(morton(0xFFFF, 0), 0x5555_5555);
        assert_eq!(morton(0xFFFF, 0xFFFF), u32::MAX);
    }

    fn blade_at(x: f32, z: f32, h: f32) -> Blade {
        Blade {
            v0_dir: [x, 0.0, z, 0.0],
            v1_height: [x, h * 0.5, z, h],
            ..Default::default()
        }
    }

    #[test]
    fn grid_splits_into_square_patches() {
        // A 16×16 grid into 4 patches of 64: each patch must be an 8×8 quadrant.
        let mut blades: Vec<Blade> = (0..256)
            .map(|i| blade_at((i % 16) as f32, (i / 16) as f32, 0.5))
            .collect();
        let boxes = build_patches(&mut blades, 64);
        assert_eq!(boxes.len(), 4);
        for (patch, b) in blades.chunks(64).zip(&boxes) {
            let (x0, x1, z0, z1) = root_bounds(patch);
            assert_eq!((x1 - x0, z1 - z0), (7.0, 7.0));
            assert_eq!(b.min, [x0 - 0.5, -0.5, z0 - 0.5, 0.0]);
            assert_eq!(b.max, [x1 + 0.5, 0.5, z1 + 0.5, 0.0]);
            // Z-order starts at the patch's low corner and walks 2×2 blocks.
            assert_eq!((x(&patch[0]), z(&patch[0])), (x0, z0));
            assert_eq!((x(&patch[1]), z(&patch[1])), (x0 + 1.0, z0));
            assert_eq!((x(&patch[2]), z(&patch[2])), (x0, z0 + 1.0));
        }
    }

    #[test]
    fn odd_patch_counts_stay_balanced() {
        let mut blades: Vec<Blade> = (0..(3 * 64))
            .map(|i| blade_at((i % 24) as f32 * 0.1, (i / 24) as f32 * 0.1, 0.3))
            .collect();
        let boxes = build_patches(&mut blades, 64);
        assert_eq!(boxes.len(), 3);
        // Split along x (the longer side): patches cover disjoint x ranges.
        let ranges: Vec<(f32, f32)> = blades
            .chunks(64)
            .map(|p| {
                let (x0, x1, _, _) = root_bounds(p);
                (x0, x1)
            })
            .collect();
        for w in ranges.windows(2) {
            assert!(w[0].1 <= w[1].0 || w[1].1 <= w[0].0, "{ranges:?}");
        }
    }
}
