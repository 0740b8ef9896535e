//! CPU twin of `shaders/thin_order.wgsl` and of the patch step's update list
//! (`list_chunks` in `cull.wgsl`): the order in which the update steps a patch's blades
//! (by Eq. 20's thinning class) and which chunks of that order it steps this frame.
//!
//! Eq. 20 keeps a blade at distance d when `i mod n < floor(n (1 − d / d_max))`. Stepped in
//! index order, every workgroup of 64 blades holds every class, and a software adapter runs
//! a workgroup whole however many of its lanes return early: the update cost every blade of
//! a patch in view though most far ones are never drawn. In class order the classes that no
//! blade of a patch can keep fill whole chunks, which step at the throttled rate (like the
//! patches out of view) while the others step every frame.

use glam::Vec4Swizzles;

use super::super::layout::{
    CullParams, PatchBox, CHUNK_THINNED, CHUNK_THROTTLED, TEST_DISTANCE, UPDATE_CHUNK,
};
use super::{box_in_frustum, patch_beyond_distance, patch_least_distance, v4};

/// The class (local index mod `n`) of position `pos` in a patch of `size` blades in class
/// order, and its rank within the class. Class r holds `size / n` blades, one more for
/// the first `size mod n` classes.
pub fn order_class(pos: u32, size: u32, n: u32) -> (u32, u32) {
    let n = n.max(1);
    let q = size / n;
    let rem = size % n;
    let big = rem * (q + 1);
    if pos < big {
        (pos / (q + 1), pos % (q + 1))
    } else {
        let t = pos - big;
        let q = q.max(1);
        (rem + t / q, t % q)
    }
}

/// The blade (its index within the patch) at position `pos` of the class order.
pub fn order_blade(pos: u32, size: u32, n: u32) -> u32 {
    let (r, j) = order_class(pos, size, n);
    r + j * n.max(1)
}

/// Whether local classes `lo..=hi` of patch `p` hold one Eq. 20 keeps at `keep` (index
/// classes `0..keep`; local class r is index class `(r + p · size) mod n`).
pub fn chunk_keeps(lo: u32, hi: u32, keep: u32, p: u32, size: u32, n: u32) -> bool {
    let n = n.max(1);
    (lo..=hi).any(|r| (u64::from(r) + u64::from(p) * u64::from(size)) % u64::from(n) < u64::from(keep))
}

/// The most classes Eq. 20 keeps for any blade of `patch`: `floor(n (1 − d / d_max))` at
/// [`patch_least_distance`], less a centimetre against rounding.
pub fn patch_keep(patch: &PatchBox, params: &CullParams) -> u32 {
    let d = (patch_least_distance(patch, params) - 0.01).max(0.0);
    let n = params.distance_levels.max(1);
    let keep = (n as f32 * (1.0 - d / params.max_distance)).floor();
    keep.clamp(0.0, n as f32) as u32
}

/// Whether chunk `k` of patch `p` (positions `64 k .. 64 k + 63` of the class order;
/// patches are whole chunks) holds a class Eq. 20 keeps at `keep`.
pub fn chunk_kept(k: u32, keep: u32, p: u32, size: u32, n: u32) -> bool {
    let lo = order_class(k * UPDATE_CHUNK, size, n).0;
    let hi = order_class(k * UPDATE_CHUNK + UPDATE_CHUNK - 1, size, n).0;
    chunk_keeps(lo, hi, keep, p, size, n)
}

/// Position of blade `local` (its index within the patch) in the class order: its class
/// starts after the blades of the classes before it.
pub fn order_position(local: u32, size: u32, n: u32) -> u32 {
    let n = n.max(1);
    let (q, rem) = (size / n, size % n);
    let r = local % n;
    r * q + r.min(rem) + local / n
}

/// Whether the blade cull leaves blade `index` of a visible `patch` off its list (the
/// patch step culls it by distance with its chunk): with the distance test on, in a whole
/// patch, its chunk of the class order holds no class [`patch_keep`] allows.
pub fn cull_skips(index: u32, patch: &PatchBox, params: &CullParams) -> bool {
    let size = params.patch_size;
    if params.tests & TEST_DISTANCE == 0 || size == 0 {
        return false;
    }
    let p = index / size;
    if u64::from(p + 1) * u64::from(size) > u64::from(params.blade_count) {
        return false;
    }
    let n = params.distance_levels.max(1);
    let k = order_position(index % size, size, n) / UPDATE_CHUNK;
    !chunk_kept(k, patch_keep(patch, params), p, size, n)
}

/// The update list's entries for patch `p` this frame, in the order the patch step writes
/// them: chunk `p · (size / 64) + c` with [`CHUNK_THROTTLED`] for a patch stepped only on
/// its turn, [`CHUNK_THINNED`] for a chunk of classes no blade of a patch in view keeps
/// (stepped on the patch's turn only). Empty when the patch is not stepped.
pub fn update_chunks(p: u32, patch: &PatchBox, params: &CullParams) -> Vec<u32> {
    if patch.min[3] != 0.0 {
        return Vec::new();
    }
    let view_proj = glam::Mat4::from_cols_array_2d(&params.view_proj);
    let (min, max) = (v4(patch.min).xyz(), v4(patch.max).xyz());
    let in_view = box_in_frustum(view_proj, min, max);
    let c = v4(params.camera_pos).xyz();
    let near = (min - c).max(c - max).max(glam::Vec3::ZERO).length() <= params.physics_radius;
    let throttle = params.physics_throttle.max(1);
    let too_far = params.tests & TEST_DISTANCE != 0 && patch_beyond_distance(patch, params);
    let every_frame = (in_view && !too_far) || near || throttle == 1;
    let turn = !too_far && params.frame.wrapping_add(p).is_multiple_of(throttle);
    if !every_frame && !turn {
        return Vec::new();
    }
    let n = params.distance_levels.max(1);
    let thin = every_frame && !near && throttle > 1 && params.tests & TEST_DISTANCE != 0;
    let keep = if thin { patch_keep(patch, params) } else { n };
    let size = params.patch_size;
    let per_patch = size / UPDATE_CHUNK;
    (0..per_patch)
        .filter_map(|k| {
            let kept = chunk_kept(k, keep, p, size, n);
            let entry = p * per_patch + k;
            match (every_frame, kept) {
                (false, _) => Some(entry | CHUNK_THROTTLED),
                (true, true) => Some(entry),
                (true, false) => turn.then_some(entry | CHUNK_THINNED),
            }
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_class_order_is_a_permutation_with_each_class_contiguous() {
        for (size, n) in [(1024, 8), (1024, 15), (64, 64), (64, 100), (256, 1), (192, 7)] {
            let blades: Vec<u32> = (0..size).map(|pos| order_blade(pos, size, n)).collect();
            let mut sorted = blades.clone();
            sorted.sort_unstable();
            assert_eq!(sorted, (0..size).collect::<Vec<_>>(), "size {size}, n {n}");
            // The position of each blade is where the order puts it.
            for (pos, &b) in blades.iter().enumerate() {
                assert_eq!(order_position(b, size, n), pos as u32, "size {size}, n {n}");
            }
            // Classes never decrease along the order, and each holds its blades in order.
            for w in blades.windows(2) {
                let (a, b) = (w[0] % n, w[1] % n);
                assert!(a < b || (a == b && w[0] < w[1]), "size {size}, n {n}: {w:?}");
            }
        }
    }

    #[test]
    fn a_chunk_is_kept_exactly_when_one_of_its_blades_is() {
        // Patches of 1000 blades in 15 classes and of 192 in 7 (local classes are not index
        // classes there), and 1024 in 8: a chunk's class range, read from the order, holds
        // a blade Eq. 20 keeps exactly when some blade of the chunk has `i mod n < keep`.
        for (size, n) in [(1000u32, 15u32), (192, 7), (1024, 8)] {
            for p in 0..9 {
                for keep in 0..=n {
                    for k in 0..size.div_ceil(UPDATE_CHUNK) {
                        let last = (k * UPDATE_CHUNK + UPDATE_CHUNK - 1).min(size - 1);
                        let blades = (k * UPDATE_CHUNK..=last).map(|pos| p * size + order_blade(pos, size, n));
                        let any = blades.clone().any(|i| i % n < keep);
                        let (lo, hi) = (order_class(k * UPDATE_CHUNK, size, n).0, order_class(last, size, n).0);
                        assert_eq!(chunk_keeps(lo, hi, keep, p, size, n), any, "size {size} n {n} p {p} keep {keep} chunk {k}");
                    }
                }
            }
        }
    }

    #[test]
    fn no_blade_in_a_patch_keeps_a_class_beyond_its_bound() {
        // Random boxes, cameras and blades in them (roots anywhere in the box, up vectors
        // at least as upright as the box says): Eq. 20's keep at the blade is at most the
        // patch's bound, so a chunk above the bound never holds a blade that is drawn.
        let mut seed = 0x2545_f491_4f6c_dd1du64;
        let mut rand = move || {
            seed ^= seed << 13;
            seed ^= seed >> 7;
            seed ^= seed << 17;
            (seed >> 40) as f32 / (1u64 << 24) as f32
        };
        let mut params = CullParams {
            distance_levels: 8,
            max_distance: 30.0,
            ..Default::default()
        };
        for k in 0..20_000 {
            let lo = glam::Vec3::new(rand() * 60.0 - 30.0, rand() * 4.0 - 2.0, rand() * 60.0 - 30.0);
            let hi = lo + glam::Vec3::new(rand() * 2.0, rand() * 1.5, rand() * 2.0);
            // Every other patch on flat ground (upright blades), the others tilted.
            let up_y = if k % 2 == 0 { 1.0 } else { 0.6 + 0.4 * rand() };
            let patch = PatchBox { min: [lo.x, lo.y, lo.z, 0.0], max: [hi.x, hi.y, hi.z, up_y] };
            let cam = glam::Vec3::new(rand() * 40.0 - 20.0, rand() * 8.0 - 1.0, rand() * 40.0 - 20.0);
            params.camera_pos = [cam.x, cam.y, cam.z, 1.0];
            let bound = patch_keep(&patch, &params);
            let v0 = lo + (hi - lo) * glam::Vec3::new(rand(), rand(), rand());
            // An up vector with up.y >= the box's smallest.
            let a = rand() * std::f32::consts::TAU;
            let y = up_y + (1.0 - up_y) * rand();
            let s = (1.0 - y * y).max(0.0).sqrt();
            let up = glam::Vec3::new(s * a.cos(), y, s * a.sin());
            let rel = v0 - cam;
            let d = (rel - up * rel.dot(up)).length();
            let keep = (8.0 * (1.0 - d / 30.0)).floor().clamp(0.0, 8.0) as u32;
            assert!(keep <= bound, "blade keeps {keep}, patch bound {bound}: {patch:?} camera {cam}");
            // Upright, the bound is not loose: the box's 2.8 m diagonal is less than one
            // level's 3.75 m, so no blade keeps two classes fewer than the bound.
            if up_y == 1.0 {
                assert!(bound - keep <= 1, "blade keeps {keep}, patch bound {bound}: {patch:?} camera {cam}");
            }
        }
    }
}
