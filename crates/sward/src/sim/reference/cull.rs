//! CPU twin of the cull (`shaders/cull.wgsl`): the patch step, the blade predicate
//! (Eq. 17–20 and the occlusion tests against the depth pyramid), the two-phase grass
//! occlusion, the levels of detail, the physics list and its broad phase, and the far
//! levels' wave count. Split from `sim::reference` along the update/cull seam; the
//! items are re-exported there.

use glam::{Mat4, Vec2, Vec3, Vec4Swizzles};

use super::super::bvh::{self, BvhNode};
use super::super::layout::{
    Blade, BladeState, CullParams, PatchBox, PATCH_SPHERE_STRIDE, SEEN_CANDIDATE, SEEN_DRAWN_EARLY,
    SEEN_NO, SEEN_YES, TEST_DISTANCE, TEST_FRUSTUM, TEST_OCCLUSION, TEST_ORIENTATION, TEST_PATCH,
    WAVE_QUANTA,
};
use super::{blade_frame, hiz, v4};

/// Why a blade was culled, or the level of detail it is drawn at. The twin of the cull
/// shader's outcome.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum CullOutcome {
    /// Survives every test; drawn at this level of detail (0 nearest; `cull_patch` gives 0
    /// for a visible patch).
    Drawn(u32),
    /// The patch test: the blade's patch box is outside the view frustum.
    Patch,
    /// The orientation test: the blade is seen edge-on (Eq. 17).
    Orientation,
    /// The blade's root, midpoint and tip are all outside the frustum (Eq. 18).
    Frustum,
    /// Thinned by the distance test (Eq. 19–20), alone or with its whole patch.
    Distance,
    /// Hidden in the depth pyramid of the opaque objects, alone or with its whole patch.
    Occlusion,
    /// Nothing there: a blade the tile generation removed (height 0), or an empty patch
    /// (`tiles::EMPTY_PATCH`). Not counted by any test.
    Empty,
}

/// The depth pyramid as the cull reads it: levels row-major, level 0 first
/// (`hiz::build_pyramid`), of a `width` × `height` target.
#[derive(Clone, Copy, Debug)]
pub struct Pyramid<'a> {
    /// Depth per texel of each level, level 0 the depth buffer, each level above the
    /// farthest (largest) depth of the texels it covers.
    pub levels: &'a [Vec<f32>],
    /// Width of level 0 in pixels.
    pub width: u32,
    /// Height of level 0 in pixels.
    pub height: u32,
}

impl Pyramid<'_> {
    fn texel(&self, level: u32, x: i32, y: i32) -> f32 {
        let (w, _) = hiz::level_size(self.width, self.height, level);
        self.levels[level as usize][(y as u32 * w + x as u32) as usize]
    }
}

fn point_in_frustum(view_proj: Mat4, p: Vec3, tolerance: f32) -> bool {
    // Eq. 18
    let c = view_proj * p.extend(1.0);
    let h = c.w + tolerance;
    c.x >= -h && c.x <= h && c.y >= -h && c.y <= h && c.z >= -h && c.z <= h
}

/// Whether the box is at least partly inside the frustum (tested against the six planes
/// of the view-projection matrix, Gribb–Hartmann).
pub fn box_in_frustum(view_proj: Mat4, min: Vec3, max: Vec3) -> bool {
    let m = view_proj.transpose();
    let rows = [m.x_axis, m.y_axis, m.z_axis, m.w_axis];
    let planes = [
        rows[3] + rows[0],
        rows[3] - rows[0],
        rows[3] + rows[1],
        rows[3] - rows[1],
        rows[2],
        rows[3] - rows[2],
    ];
    planes.iter().all(|p| {
        let corner = Vec3::new(
            if p.x >= 0.0 { max.x } else { min.x },
            if p.y >= 0.0 { max.y } else { min.y },
            if p.z >= 0.0 { max.z } else { min.z },
        );
        p.xyz().dot(corner) + p.w >= 0.0
    })
}

/// View distance of a depth-buffer value (perspective, depth 0 at near, 1 at far).
fn occluder_distance(d: f32, params: &CullParams) -> f32 {
    let (n, f) = (params.clip[0], params.clip[1]);
    n * f / (f - d * (f - n)).max(1e-6)
}

/// Whether a point at view distance `z` lies behind the depth `d` by more than `bias` (a
/// fraction of `z`).
fn behind(z: f32, d: f32, bias: f32, params: &CullParams) -> bool {
    z - occluder_distance(d, params) > bias * z
}

fn to_pixel(ndc: Vec2, params: &CullParams) -> (i32, i32) {
    let (w, h) = (params.hiz[0] as f32, params.hiz[1] as f32);
    let px = Vec2::new(ndc.x * 0.5 + 0.5, 0.5 - ndc.y * 0.5) * Vec2::new(w, h);
    (
        (px.x.floor() as i32).clamp(0, params.hiz[0] as i32 - 1),
        (px.y.floor() as i32).clamp(0, params.hiz[1] as i32 - 1),
    )
}

/// A point is occluded when it projects inside the screen, in front of the camera, and
/// behind the depth at its pixel by more than `bias`.
pub fn point_occluded(p: Vec3, bias: f32, params: &CullParams, pyramid: &Pyramid) -> bool {
    let view_proj = Mat4::from_cols_array_2d(&params.view_proj);
    let c = view_proj * p.extend(1.0);
    if c.w <= params.clip[0] {
        return false;
    }
    let ndc = c.xy() / c.w;
    if ndc.x.abs() > 1.0 || ndc.y.abs() > 1.0 {
        return false;
    }
    let (x, y) = to_pixel(ndc, params);
    behind(c.w, pyramid.texel(0, x, y), bias, params)
}

/// The occlusion test of a blade: v0, the curve's midpoint m and v2 all behind the
/// pyramid's depth by more than `bias`. The early pass tests against the opaque objects
/// (`occlusion_bias`); the late pass against the opaque objects and the grass drawn early
/// (`grass_hidden`).
pub fn blade_occluded(blade: &Blade, bias: f32, params: &CullParams, pyramid: &Pyramid) -> bool {
    let v0 = v4(blade.v0_dir).xyz();
    let v2 = v4(blade.v2_width).xyz();
    let m = 0.25 * v0 + 0.5 * v4(blade.v1_height).xyz() + 0.25 * v2;
    point_occluded(v0, bias, params, pyramid)
        && point_occluded(m, bias, params, pyramid)
        && point_occluded(v2, bias, params, pyramid)
}

/// The late pass's test: the blade hidden behind the opaque objects and the grass drawn
/// early, with the grass-occlusion bias (`clip[2]`), for candidates and early blades alike.
pub fn grass_hidden(blade: &Blade, params: &CullParams, pyramid: &Pyramid) -> bool {
    blade_occluded(blade, params.clip[2], params, pyramid)
}

/// What the early blade pass does with grass occlusion on, for a blade whose tests came out
/// as `outcome` and whose seen flag was `seen`: its new flag, and whether it is drawn early
/// (seen last frame). Survivors not seen last frame become candidates for the late pass.
pub fn early_seen(outcome: CullOutcome, seen: u32) -> (u32, bool) {
    match outcome {
        CullOutcome::Drawn(_) if seen == SEEN_YES => (SEEN_DRAWN_EARLY, true),
        CullOutcome::Drawn(_) => (SEEN_CANDIDATE, false),
        _ => (SEEN_NO, false),
    }
}

/// What the late pass does with a blade the early pass left in state `seen`, given whether
/// the pyramid of the opaque objects and the early grass hides it.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Late {
    /// Not the late pass's business (culled early, or in a patch not visited).
    Untouched,
    /// Drawn early; it stays in next frame's early set only if it is not hidden now.
    Rechecked {
        /// Whether it was visible now, so that it is drawn early next frame.
        seen: bool,
    },
    /// A candidate the grass hides: culled by occlusion.
    Hidden,
    /// A candidate nothing hides: drawn late.
    Drawn,
}

/// The late pass's decision for a blade in state `seen` (see [`Late`]).
pub fn late_pass(seen: u32, hidden: bool) -> Late {
    match (seen, hidden) {
        (SEEN_DRAWN_EARLY, h) => Late::Rechecked { seen: !h },
        (SEEN_CANDIDATE, true) => Late::Hidden,
        (SEEN_CANDIDATE, false) => Late::Drawn,
        _ => Late::Untouched,
    }
}

/// The box's screen rectangle against the pyramid level where it spans at most 2 × 2
/// texels: occluded when its nearest corner is behind the farthest depth there.
pub fn box_occluded(min: Vec3, max: Vec3, params: &CullParams, pyramid: &Pyramid) -> bool {
    let view_proj = Mat4::from_cols_array_2d(&params.view_proj);
    let mut lo = Vec2::splat(1e30);
    let mut hi = Vec2::splat(-1e30);
    let mut z_near = 1e30f32;
    for k in 0..8 {
        let corner = Vec3::new(
            if k & 1 != 0 { max.x } else { min.x },
            if k & 2 != 0 { max.y } else { min.y },
            if k & 4 != 0 { max.z } else { min.z },
        );
        let c = view_proj * corner.extend(1.0);
        if c.w <= params.clip[0] {
            return false;
        }
        let ndc = c.xy() / c.w;
        lo = lo.min(ndc);
        hi = hi.max(ndc);
        z_near = z_near.min(c.w);
    }
    if hi.x < -1.0 || lo.x > 1.0 || hi.y < -1.0 || lo.y > 1.0 {
        return false;
    }
    let p0 = to_pixel(Vec2::new(lo.x, hi.y), params);
    let p1 = to_pixel(Vec2::new(hi.x, lo.y), params);
    let top = params.hiz[2] - 1;
    let mut level = 0;
    while level < top
        && ((p1.0 >> level) - (p0.0 >> level) > 1 || (p1.1 >> level) - (p0.1 >> level) > 1)
    {
        level += 1;
    }
    let (lw, lh) = hiz::level_size(params.hiz[0], params.hiz[1], level);
    let a = (
        (p0.0 >> level).min(lw as i32 - 1),
        (p0.1 >> level).min(lh as i32 - 1),
    );
    let b = (
        (p1.0 >> level).min(lw as i32 - 1),
        (p1.1 >> level).min(lh as i32 - 1),
    );
    let mut d = 0.0f32;
    for y in a.1..=b.1 {
        for x in a.0..=b.0 {
            d = d.max(pyramid.texel(level, x, y));
        }
    }
    behind(z_near, d, params.occlusion_bias, params)
}

/// Projected height in pixels of a blade (the level-of-detail measure).
pub fn projected_height(v0: Vec3, height: f32, params: &CullParams) -> f32 {
    let d = v0.distance(v4(params.camera_pos).xyz()).max(1e-3);
    height * params.lod[0] / d
}

/// Level of detail for a projected height: 0 at and above `lod[1]` px, 1 at and above
/// `lod[2]`, else 2.
pub fn lod_level(h_px: f32, params: &CullParams) -> u32 {
    if h_px >= params.lod[1] {
        0
    } else if h_px >= params.lod[2] {
        1
    } else {
        2
    }
}

/// The patch step for one patch: culled by the frustum (`Patch`), by occlusion
/// (`Occlusion`), or visible (`Drawn(0)`: its blades go on to `cull_blade`).
pub fn cull_patch(patch: &PatchBox, params: &CullParams, pyramid: Option<&Pyramid>) -> CullOutcome {
    if patch.min[3] != 0.0 {
        return CullOutcome::Empty;
    }
    if params.tests & TEST_PATCH == 0 {
        return CullOutcome::Drawn(0);
    }
    let view_proj = Mat4::from_cols_array_2d(&params.view_proj);
    let (min, max) = (v4(patch.min).xyz(), v4(patch.max).xyz());
    if !box_in_frustum(view_proj, min, max) {
        return CullOutcome::Patch;
    }
    if params.tests & TEST_DISTANCE != 0 && patch_beyond_distance(patch, params) {
        return CullOutcome::Distance;
    }
    if let Some(p) = pyramid.filter(|_| params.tests & TEST_OCCLUSION != 0) {
        if box_occluded(min, max, params, p) {
            return CullOutcome::Occlusion;
        }
    }
    CullOutcome::Drawn(0)
}

/// Whether every blade of `patch` fails the distance test (Eq. 20) for the camera of
/// `params` (the twin of `patch_beyond_distance` in `cull.wgsl`): a blade's d_proj is
/// |rel × up|, at least `c·H − s·|y|` for an up vector leaning at most to up.y = c
/// (`patch.max[3]`, s = √(1 − c²)), H the horizontal and y the vertical offset of the
/// camera from the root; over the box H is at least the distance to its (x, z) rectangle
/// and |y| at most the height span.
pub fn patch_beyond_distance(patch: &PatchBox, params: &CullParams) -> bool {
    patch_least_distance(patch, params) >= params.max_distance
}

/// The lower bound on the distance test's d_proj over every blade of `patch` that
/// [`patch_beyond_distance`] compares with the reach: `c·H − s·|y|` (the twin of
/// `patch_least_distance` in `cull.wgsl`).
pub fn patch_least_distance(patch: &PatchBox, params: &CullParams) -> f32 {
    let c = v4(params.camera_pos).xyz();
    let (min, max) = (v4(patch.min).xyz(), v4(patch.max).xyz());
    let dx = (min.x - c.x).max(c.x - max.x).max(0.0);
    let dz = (min.z - c.z).max(c.z - max.z).max(0.0);
    let h = (dx * dx + dz * dz).sqrt();
    let y = (c.y - min.y).abs().max((c.y - max.y).abs());
    let cos_up = patch.max[3].clamp(0.0, 1.0);
    let sin_up = (1.0 - cos_up * cos_up).max(0.0).sqrt();
    cos_up * h - sin_up * y
}

/// Whether the patch step puts patch `p` on this frame's update list, and whether at the
/// throttled rate: `None` (skipped this frame), `Some(false)` (every frame), `Some(true)`.
/// A patch beyond the blades' radius ([`patch_beyond_distance`]) and not within
/// `physics_radius` is not stepped at all while the throttle is on.
pub fn patch_update(p: u32, patch: &PatchBox, params: &CullParams) -> Option<bool> {
    if patch.min[3] != 0.0 {
        return None;
    }
    let view_proj = Mat4::from_cols_array_2d(&params.view_proj);
    let (min, max) = (v4(patch.min).xyz(), v4(patch.max).xyz());
    let in_view = box_in_frustum(view_proj, min, max);
    let c = v4(params.camera_pos).xyz();
    let distance = (min - c).max(c - max).max(Vec3::ZERO).length();
    let throttle = params.physics_throttle.max(1);
    let too_far = params.tests & TEST_DISTANCE != 0 && patch_beyond_distance(patch, params);
    let every_frame = (in_view && !too_far) || distance <= params.physics_radius || throttle == 1;
    if every_frame {
        Some(false)
    } else if !too_far && params.frame.wrapping_add(p).is_multiple_of(throttle) {
        Some(true)
    } else {
        None
    }
}

/// The collision broad phase of a stepped patch: the indices of the spheres within one
/// radius of its box, in order (more than `PATCH_SPHERE_STRIDE - 1` go to the GPU's shared
/// pool; only a full pool makes a patch test every sphere). Empty with collisions off.
pub fn patch_spheres(patch: &PatchBox, params: &CullParams, spheres: &[[f32; 4]]) -> Vec<u32> {
    if params.collide[1] == 0 {
        return Vec::new();
    }
    let (min, max) = (v4(patch.min).xyz(), v4(patch.max).xyz());
    spheres
        .iter()
        .take(params.collide[0] as usize)
        .enumerate()
        .filter(|(_, s)| {
            let c = Vec3::new(s[0], s[1], s[2]);
            c.clamp(min, max).distance(c) < 2.0 * s[3]
        })
        .map(|(k, _)| k as u32)
        .collect()
}

/// The collision broad phase of a stepped patch with the colliders' hierarchy
/// (`broad_phase_bvh` in `cull_broad_phase.wgsl`): the nodes a walk from the root meets, in that order,
/// that may touch the box (centre within two radii, as the flat list's test), stopping at
/// the leaves and at the patch's cut level ([`bvh::cut_depth`]); `None` when more than
/// `PATCH_SPHERE_STRIDE - 1` are met (the blades then walk from the root). Empty with
/// collisions off.
pub fn patch_nodes(
    patch: &PatchBox,
    params: &CullParams,
    nodes: &[BvhNode],
    throttled: bool,
) -> Option<Vec<u32>> {
    if params.collide[1] == 0 || nodes.is_empty() {
        return Some(Vec::new());
    }
    let (lo, hi) = (v4(patch.min).xyz(), v4(patch.max).xyz());
    let camera = v4(params.bvh).xyz();
    let cut = bvh::cut_depth(params.collide[3], lo, hi, camera, params.bvh[3], throttled);
    let mut listed = Vec::new();
    let mut stack = vec![0u32];
    while let Some(k) = stack.pop() {
        let node = &nodes[k as usize];
        let c = Vec3::new(node.sphere[0], node.sphere[1], node.sphere[2]);
        if c.clamp(lo, hi).distance(c) >= 2.0 * node.sphere[3] {
            continue;
        }
        if bvh::is_leaf(node) || node.link[3] >= cut {
            listed.push(k);
        } else if stack.len() + 2 <= 32 {
            stack.push(node.link[1]);
            stack.push(node.link[0]);
        }
    }
    (listed.len() < PATCH_SPHERE_STRIDE as usize).then_some(listed)
}

/// The twin of `count_wave` in `shaders/cull.wgsl`: for a blade the cull draws early,
/// `Some` of how far the gusts bend it from its rest, as the blades' shading waves read it
/// (`clamp(1.5 |v2 - rest tip| / h, 0, 1)` in whole 1/1024ths), when it lies from half the
/// blade radius out (everywhere without a distance test); `None` nearer.
pub fn wave_of(blade: &Blade, state: &BladeState, params: &CullParams) -> Option<u32> {
    let v0 = Vec3::from_slice(&blade.v0_dir[..3]);
    let up = Vec3::from_slice(&blade.up_stiffness[..3]);
    let rel = v0 - Vec3::from_slice(&params.camera_pos[..3]);
    let d_proj = (rel - up * rel.dot(up)).length();
    if params.tests & TEST_DISTANCE != 0 && d_proj < 0.5 * params.max_distance {
        return None;
    }
    let v2 = Vec3::from_slice(&blade.v2_width[..3]);
    let rest = Vec3::from_slice(&state.rest_eta[..3]);
    let gust = (v2 - rest).length() / blade.v1_height[3].max(1e-4);
    Some(((gust * 1.5).clamp(0.0, 1.0) * WAVE_QUANTA) as u32)
}

/// The cull predicate for blade `index`: the patch step (frustum and occlusion of its
/// patch box), then Eq. 17–20 and the occlusion of v0 / m / v2; a drawn blade gets its
/// level of detail.
pub fn cull_blade(
    index: u32,
    blade: &Blade,
    patch: &PatchBox,
    params: &CullParams,
    pyramid: Option<&Pyramid>,
) -> CullOutcome {
    let patch_outcome = cull_patch(patch, params, pyramid);
    if patch_outcome != CullOutcome::Drawn(0) {
        return patch_outcome;
    }
    // The classes Eq. 20 culls everywhere in the patch: culled with their chunk.
    if super::thin_order::cull_skips(index, patch, params) {
        return CullOutcome::Distance;
    }
    if blade.v1_height[3] <= 0.0 {
        return CullOutcome::Empty;
    }
    let view_proj = Mat4::from_cols_array_2d(&params.view_proj);
    let v0 = v4(blade.v0_dir).xyz();
    let v1 = v4(blade.v1_height).xyz();
    let v2 = v4(blade.v2_width).xyz();
    let up = v4(blade.up_stiffness).xyz();
    let camera = v4(params.camera_pos).xyz();
    // A flower's stem (`field::clumps::STEM_WIDTH` wide) carries a head that faces up: no
    // side of it is edge-on, so the orientation test spares it.
    let flower = blade.v2_width[3] == crate::field::clumps::STEM_WIDTH;
    if params.tests & TEST_ORIENTATION != 0 && !flower {
        // Eq. 17: the view direction against the blade's width direction.
        let (width_dir, _) = blade_frame(up, blade.v0_dir[3]);
        let view_dir = (v0 - camera).normalize_or_zero();
        if view_dir.dot(width_dir).abs() > params.orientation_threshold {
            return CullOutcome::Orientation;
        }
    }
    let m = 0.25 * v0 + 0.5 * v1 + 0.25 * v2;
    if params.tests & TEST_FRUSTUM != 0 {
        let t = params.frustum_tolerance;
        if !point_in_frustum(view_proj, v0, t)
            && !point_in_frustum(view_proj, m, t)
            && !point_in_frustum(view_proj, v2, t)
        {
            return CullOutcome::Frustum;
        }
    }
    if params.tests & TEST_DISTANCE != 0 {
        // Eq. 19–20, read as the text describes it (the nearest level keeps every blade):
        // kept when `id mod n < floor(n (1 − d/d_max))`, see cull.wgsl.
        let rel = v0 - camera;
        let d_proj = (rel - up * rel.dot(up)).length();
        let n = params.distance_levels.max(1);
        let keep = (n as f32 * (1.0 - d_proj / params.max_distance)).floor();
        if ((index % n) as f32) >= keep {
            return CullOutcome::Distance;
        }
    }
    if let Some(p) = pyramid.filter(|_| params.tests & TEST_OCCLUSION != 0) {
        if blade_occluded(blade, params.occlusion_bias, params, p) {
            return CullOutcome::Occlusion;
        }
    }
    CullOutcome::Drawn(lod_level(
        projected_height(v0, blade.v1_height[3], params),
        params,
    ))
}

/// Where blade `i` stands in the cull's visible lists (`cull_order.wgsl`): by patch (from
/// the last to the first where `from_last`, [`list_from_last`]), then by its position in
/// the patch's class order (the listed chunks' order, then each chunk's lanes). Each
/// level's early list and its late list are sorted by this key, whatever order the GPU ran
/// its workgroups in, so that blades at one depth are drawn in the same order every frame.
pub fn list_order(i: u32, params: &CullParams, from_last: bool) -> (u32, u32) {
    let size = params.patch_size.max(1);
    let patch = i / size;
    let position = if from_last {
        params.patch_count.saturating_sub(1).saturating_sub(patch)
    } else {
        patch
    };
    (
        position,
        super::thin_order::order_position(i % size, size, params.distance_levels),
    )
}

/// Whether the cull lists the patches from the last to the first (twin of
/// `list_from_last`): where the view's direction on the ground (the view-projection's clip
/// w row) points from the last patch's centre towards the first's. The field's patches
/// follow a k-d split of the ground, low side first, so the list runs roughly near to far
/// either way, and the GPU skips shading the blades hidden behind those drawn first.
pub fn list_from_last(params: &CullParams, first: &PatchBox, last: &PatchBox) -> bool {
    if params.patch_count < 2 {
        return false;
    }
    let along_x = (last.max[0] + last.min[0]) - (first.max[0] + first.min[0]);
    let along_z = (last.max[2] + last.min[2]) - (first.max[2] + first.min[2]);
    let m = params.view_proj;
    m[0][3] * along_x + m[2][3] * along_z < 0.0
}

/// The patch bound against the field's own blades (moved here from the field's tests: it
/// checks the cull's twin, a layer above the field).
#[cfg(test)]
mod tests {
    use glam::Vec3;

    use super::patch_beyond_distance;
    use crate::field::generate;
    use crate::field::tests::hills;
    use crate::scene::types::Field;
    use crate::sim::layout::CullParams;

    fn v3(a: [f32; 4]) -> Vec3 {
        Vec3::new(a[0], a[1], a[2])
    }

    #[test]
    fn a_patch_beyond_the_distance_bound_holds_no_blade_the_distance_test_keeps() {
        // Steep hills (2 m over 8 m), blades leaning with the slope; cameras on the ground,
        // above it and high over it, each with a small and a large radius.
        let g = generate(
            &Field {
                density: 60.0,
                patch_size: 256,
                ..Field::default()
            },
            &hills(),
            None,
        );
        let mut beyond = 0;
        let mut kept = 0;
        for (eye, max_distance) in [
            (Vec3::new(-5.0, 1.0, -5.0), 3.0),
            (Vec3::new(0.0, 3.0, 0.0), 2.0),
            (Vec3::new(4.0, 12.0, -2.0), 4.0),
            (Vec3::new(-20.0, 40.0, 15.0), 30.0),
            (Vec3::new(3.0, -1.0, 5.0), 5.0),
        ] {
            let params = CullParams {
                camera_pos: [eye.x, eye.y, eye.z, 1.0],
                max_distance,
                ..Default::default()
            };
            for (patch, b) in g.blades.chunks(g.patch_size as usize).zip(&g.patches) {
                if !patch_beyond_distance(b, &params) {
                    kept += 1;
                    continue;
                }
                beyond += 1;
                for blade in patch {
                    let rel = eye - v3(blade.v0_dir);
                    let up = v3(blade.up_stiffness);
                    let d_proj = (rel - up * rel.dot(up)).length();
                    assert!(
                        d_proj >= max_distance * (1.0 - 1e-5),
                        "a blade at d_proj {d_proj} < {max_distance} in a patch culled whole"
                    );
                }
            }
        }
        // The bound is useful (culls patches) and not everything.
        assert!(beyond > 10 && kept > 10, "beyond {beyond}, kept {kept}");
    }
}
