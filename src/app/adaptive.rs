//! "Target frame time": a small controller that adapts first the render resolution of the
//! 3D passes, then distance culling (the paper's Eq. 20, `id mod n < floor(n·(1 −
//! d/d_max))`), so that the window holds a frame time the user asked for.
//!
//! # Control law
//!
//! * The frame times are smoothed exponentially ([`SMOOTHING`]) so that one slow frame
//!   (a shader compile, a window resize) does not trigger a change.
//! * The controller acts at most every [`ACT_EVERY`] frames, and counts from its last
//!   change: by then the smoothed time mostly shows the effect of that change (the old
//!   value's weight is `(1 − SMOOTHING)^ACT_EVERY` ≈ 10 %), so it does not keep cutting
//!   while the last cut is still on its way into the average.
//! * Over `target · `[`OVER`]: cull more. First, where the window allows it
//!   ([`FrameBudget::with_msaa_step`]), multisampling goes off (4× MSAA costs about 3× the
//!   frame on a CPU adapter, and only smooths edges). Then, where allowed
//!   ([`FrameBudget::with_grass_shadow_step`]), the blades stop casting sun shadows (the
//!   terrain, objects and balls still cast): drawing every blade within the shadow radius
//!   once per cascade was a third of the window's frame on llvmpipe, and it costs a shade,
//!   not a blade. Then, where allowed ([`FrameBudget::with_fold_step`]), the blades are
//!   drawn flat, without the fold along their middle axis (the 3D displacement of Eq. 23,
//!   where the scene has it on): the finest level then has half its triangles, and the
//!   window's frame at its settled state took ×0.90 of its time on llvmpipe; the fold is a
//!   shade across the near blades. Then, where allowed ([`FrameBudget::with_lod_step`]),
//!   the blades change to their coarser meshes at [`LOD_COARSEN`] times the scene's pixel heights (fewer
//!   segments for blades a few dozen pixels tall: on llvmpipe the window's draw fell from
//!   about 51 to 39 ms at its settled state, and the pictures are hard to tell apart).
//!   Then, where allowed ([`FrameBudget::with_morph_step`]), the blades change level at
//!   the thresholds without the morph band (`culling.lod_morph`): a CPU adapter runs the
//!   vertex stage on one thread and the morph's two more points on every blade vertex,
//!   morphing or not; a blade now switches meshes in one frame at the thresholds.
//!   Then the render scale of the 3D passes ×
//!   [`SHRINK`] (down to [`MIN_SCALE`]; the window upscales the smaller image and draws
//!   the panel sharp on top): this costs sharpness, never grass. Only then the grass's
//!   reach: `d_max × `[`SHRINK`] (the blade radius), down to [`MIN_DISTANCE`] m, and
//!   only after [`CONFIRM_FRAMES`] frames over the band in a row (one noisy stretch near
//!   the band's top must not cost the user grass nothing gives back). The
//!   number of levels `n` of Eq. 20 is never lowered: fewer levels thin the grass at every
//!   distance, the blades at the camera's feet included, and the grass near the camera is
//!   what the budget must keep. A machine too slow even then stays over its target.
//! * Under `target · `[`UNDER`]: give detail back, in the reverse order. First the levels
//!   go up by one, then `d_max × `[`GROW`], never above the user's values (the *base*),
//!   then the render scale × [`GROW`] up to 1, then the morph, the blades' finer meshes,
//!   their fold, the blades' shadows, and last multisampling: the grass comes back before
//!   the sharpness.
//! * In between: nothing. The dead band (0.75–1.1 of the target) is wider than one step in
//!   either direction (1/0.85 ≈ 1.18 and 1.08, on a cost that grows about like d_max²), so a
//!   step does not carry the time from one edge of the band across the other, and the
//!   controller settles instead of oscillating.
//!
//! The user's culling values at construction (or at [`FrameBudget::rebase`]) are the base:
//! the controller never goes above them, and a fast machine returns to them. If distance
//! culling is off and the budget needs to cull, it switches it on (the status says so) and
//! leaves it on: switching it back off would be a step the gradual control cannot undo.

use sward::scene::Culling;

/// Weight of the newest frame in the smoothed frame time.
pub const SMOOTHING: f32 = 0.25;
/// Frames between two changes, so that the smoothed time shows the last change's effect.
pub const ACT_EVERY: u32 = 8;
/// Cull more when the smoothed time is over `target · OVER`.
pub const OVER: f32 = 1.1;
/// Give detail back when the smoothed time is under `target · UNDER`.
pub const UNDER: f32 = 0.75;
/// Factor on d_max per step when over the target.
pub const SHRINK: f32 = 0.85;
/// Factor on d_max per step when under the target.
pub const GROW: f32 = 1.08;
/// Consecutive frames over the band before the budget cuts the grass's reach (d_max), the
/// step a user notices most: twice [`ACT_EVERY`], so a stretch of slow frames shorter than
/// that (a tile burst, the machine's noise at the band's edge) cuts nothing. Measured on
/// llvmpipe: the window's frame at d_max 15.7 m sits at about 99 ms of its 99 ms band
/// top, and without the confirmation the settled d_max ranged from 9.6 to 18.4 m over
/// nine runs of the same command.
pub const CONFIRM_FRAMES: u32 = 2 * ACT_EVERY;
/// Smallest d_max the budget sets, in metres (or the base, if that is smaller): the grass
/// within this radius stays.
pub const MIN_DISTANCE: f32 = 8.0;
/// Smallest share of `render.billboard_distance` the budget keeps.
pub const MIN_BILLBOARDS: f32 = 0.4;
/// Smallest render scale of the 3D passes the budget sets (a quarter of the pixels).
pub const MIN_SCALE: f32 = 0.5;
/// Factor on the scene's level-of-detail pixel heights (`culling.lod_near_px`,
/// `lod_far_px`) once the budget takes the coarser meshes: a blade changes level at twice
/// the height on screen, as it would at twice the resolution.
pub const LOD_COARSEN: f32 = 2.0;

/// What one [`FrameBudget::observe`] set in the culling block.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Adjustment {
    pub levels: u32,
    pub max_distance: f32,
    /// Render scale of the 3D passes (1 = the window's resolution).
    pub scale: f32,
}

/// Holds a target frame time by adapting distance culling (see the module docs).
#[derive(Clone, Debug)]
pub struct FrameBudget {
    /// Frame time to hold, in milliseconds; `None` turns the budget off (it then changes
    /// nothing).
    pub target_ms: Option<f32>,
    base_levels: u32,
    base_distance: f32,
    smoothed: Option<f32>,
    /// Valid frames since the last change (or since the start / the last rebase).
    frames: u32,
    /// Consecutive frames since the last change whose smoothed time was over the band
    /// (`target · OVER`): the grass's reach is cut only after [`CONFIRM_FRAMES`] of them.
    over_frames: u32,
    /// Whether the budget switched distance culling on.
    switched_on: bool,
    /// The values at the last observe, for the status line.
    levels: u32,
    max_distance: f32,
    /// Render scale of the 3D passes, in [`FrameBudget::scale_floor`, 1].
    scale: f32,
    /// The lowest scale the budget sets: [`MIN_SCALE`], or 1 to keep the resolution.
    scale_floor: f32,
    /// Whether the budget may switch multisampling off, and whether it has.
    msaa_step: bool,
    msaa_off: bool,
    /// Whether the budget may stop the blades casting sun shadows, and whether it has.
    grass_shadow_step: bool,
    grass_shadows_off: bool,
    /// Whether the budget may draw the blades flat (no fold), and whether it does.
    fold_step: bool,
    fold_off: bool,
    /// Whether the budget may draw the blades with coarser meshes, and whether it does.
    lod_step: bool,
    lod_coarse: bool,
    /// Whether the budget may let the blades change level without the morph band, and
    /// whether it does.
    morph_step: bool,
    morph_off: bool,
    /// The share of the billboard radius drawn (1 = the scene's), when the budget may
    /// shorten it (after the resolution, before the blades).
    billboards: Option<f32>,
}

impl FrameBudget {
    /// A budget whose base (ceiling) is `culling`'s current levels and d_max.
    pub fn new(culling: &Culling, target_ms: Option<f32>) -> Self {
        Self {
            target_ms,
            base_levels: culling.distance_levels,
            base_distance: culling.max_distance,
            smoothed: None,
            frames: 0,
            over_frames: 0,
            switched_on: false,
            levels: culling.distance_levels,
            max_distance: culling.max_distance,
            scale: 1.0,
            scale_floor: MIN_SCALE,
            msaa_step: false,
            msaa_off: false,
            grass_shadow_step: false,
            grass_shadows_off: false,
            fold_step: false,
            fold_off: false,
            lod_step: false,
            lod_coarse: false,
            morph_step: false,
            morph_off: false,
            billboards: None,
        }
    }

    /// The same budget allowed to shorten the billboards' radius (down to
    /// [`MIN_BILLBOARDS`] of it) after the resolution and before the blades' radius.
    pub fn with_billboard_step(mut self, allowed: bool) -> Self {
        self.billboards = allowed.then_some(1.0);
        self
    }

    /// The share of `render.billboard_distance` to draw now.
    pub fn billboards(&self) -> f32 {
        self.billboards.unwrap_or(1.0)
    }

    /// The same budget allowed to switch multisampling off first (the window, whose scene
    /// keeps its `render.msaa`: the budget only caps what is drawn).
    pub fn with_msaa_step(mut self, allowed: bool) -> Self {
        self.msaa_step = allowed;
        self
    }

    /// Whether the budget has switched multisampling off.
    pub fn msaa_off(&self) -> bool {
        self.msaa_off
    }

    /// The same budget allowed to stop the blades casting sun shadows, after multisampling
    /// and before the resolution (the window, whose scene keeps its `grass_radius`).
    pub fn with_grass_shadow_step(mut self, allowed: bool) -> Self {
        self.grass_shadow_step = allowed;
        self
    }

    /// Whether the budget has stopped the blades casting sun shadows.
    pub fn grass_shadows_off(&self) -> bool {
        self.grass_shadows_off
    }

    /// The same budget allowed to draw the blades flat (the renderer's `fold`), after the
    /// blades' shadows and before the coarser meshes.
    pub fn with_fold_step(mut self, allowed: bool) -> Self {
        self.fold_step = allowed;
        self
    }

    /// Whether the blades fold along their middle axis now (the scene's
    /// `render.displacement` applies), or the budget draws them flat.
    pub fn fold(&self) -> bool {
        !self.fold_off
    }

    /// The same budget allowed to draw the blades with their coarser meshes (at
    /// [`LOD_COARSEN`] times the scene's level-of-detail heights), after the blades' fold
    /// and before the resolution (the window, whose scene keeps its heights).
    pub fn with_lod_step(mut self, allowed: bool) -> Self {
        self.lod_step = allowed;
        self
    }

    /// The same budget allowed to let the blades change level without morphing (the
    /// renderer's `lod_morph`), after the coarser meshes and before the resolution.
    pub fn with_morph_step(mut self, allowed: bool) -> Self {
        self.morph_step = allowed;
        self
    }

    /// Whether the blades morph between levels now (the scene's `culling.lod_morph`
    /// applies), or the budget has them change level at the thresholds.
    pub fn lod_morph(&self) -> bool {
        !self.morph_off
    }

    /// The factor on the scene's level-of-detail heights now (1, or [`LOD_COARSEN`]).
    pub fn lod_coarsen(&self) -> f32 {
        if self.lod_coarse {
            LOD_COARSEN
        } else {
            1.0
        }
    }

    /// The same budget with the render scale held at or above `floor` (1 keeps the
    /// window's resolution and adapts only the culling).
    pub fn with_scale_floor(mut self, floor: f32) -> Self {
        self.scale_floor = floor.clamp(0.05, 1.0);
        self.scale = self.scale.max(self.scale_floor);
        self
    }

    /// The render scale of the 3D passes the window should use now.
    pub fn scale(&self) -> f32 {
        self.scale
    }

    /// The user edited the culling block by hand: its values become the new base, and the
    /// controller waits [`ACT_EVERY`] frames before it acts on them.
    pub fn rebase(&mut self, culling: &Culling) {
        self.over_frames = 0;
        self.base_levels = culling.distance_levels;
        self.base_distance = culling.max_distance;
        self.levels = culling.distance_levels;
        self.max_distance = culling.max_distance;
        self.switched_on = false;
        self.frames = 0;
    }

    /// The smoothed frame time in milliseconds (0 before the first valid frame).
    pub fn smoothed_ms(&self) -> f32 {
        self.smoothed.unwrap_or(0.0)
    }

    /// The floor of d_max: [`MIN_DISTANCE`], or the base if the user chose less.
    fn distance_floor(&self) -> f32 {
        MIN_DISTANCE.min(self.base_distance)
    }

    /// Takes one frame's time (call once per frame) and, when it is time to act and the
    /// smoothed time is outside the band, changes `culling`'s levels / d_max (and may switch
    /// distance culling on). Returns what it set, or `None` when it changed nothing.
    /// Non-finite or non-positive times are ignored.
    pub fn observe(&mut self, frame_ms: f32, culling: &mut Culling) -> Option<Adjustment> {
        if !(frame_ms.is_finite() && frame_ms > 0.0) {
            return None;
        }
        let smoothed = match self.smoothed {
            Some(s) => s + SMOOTHING * (frame_ms - s),
            None => frame_ms,
        };
        self.smoothed = Some(smoothed);
        self.levels = culling.distance_levels;
        self.max_distance = culling.max_distance;
        let target = self.target_ms.filter(|t| t.is_finite() && *t > 0.0)?;
        self.frames = self.frames.saturating_add(1);
        self.over_frames = if smoothed > target * OVER {
            self.over_frames.saturating_add(1)
        } else {
            0
        };
        if self.frames < ACT_EVERY {
            return None;
        }
        let changed = if smoothed > target * OVER {
            self.cull_more(culling)
        } else if smoothed < target * UNDER {
            self.cull_less(culling)
        } else {
            false
        };
        if !changed {
            return None;
        }
        self.frames = 0;
        self.over_frames = 0;
        self.levels = culling.distance_levels;
        self.max_distance = culling.max_distance;
        Some(Adjustment {
            levels: culling.distance_levels,
            max_distance: culling.max_distance,
            scale: self.scale,
        })
    }

    fn cull_more(&mut self, culling: &mut Culling) -> bool {
        // Smooth edges first, then pixels: both cost sharpness, not a single blade.
        if self.msaa_step && !self.msaa_off {
            self.msaa_off = true;
            return true;
        }
        if self.grass_shadow_step && !self.grass_shadows_off {
            self.grass_shadows_off = true;
            return true;
        }
        if self.fold_step && !self.fold_off {
            self.fold_off = true;
            return true;
        }
        if self.lod_step && !self.lod_coarse {
            self.lod_coarse = true;
            return true;
        }
        if self.morph_step && !self.morph_off {
            self.morph_off = true;
            return true;
        }
        if self.scale > self.scale_floor {
            self.scale = (self.scale * SHRINK).max(self.scale_floor);
            return true;
        }
        if let Some(b) = self.billboards.filter(|b| *b > MIN_BILLBOARDS) {
            self.billboards = Some((b * SHRINK).max(MIN_BILLBOARDS));
            return true;
        }
        if !culling.distance {
            // The cheapest first step: the user's own levels and d_max, now applied.
            culling.distance = true;
            self.switched_on = true;
            return true;
        }
        let floor = self.distance_floor();
        if culling.max_distance > floor && self.over_frames >= CONFIRM_FRAMES {
            culling.max_distance = (culling.max_distance * SHRINK).max(floor);
            return true;
        }
        false
    }

    fn cull_less(&mut self, culling: &mut Culling) -> bool {
        // Grass first (while distance culling thins it), then the resolution.
        if culling.distance {
            if culling.distance_levels < self.base_levels {
                culling.distance_levels += 1;
                return true;
            }
            if culling.max_distance < self.base_distance {
                culling.max_distance = (culling.max_distance * GROW).min(self.base_distance);
                return true;
            }
        }
        if let Some(b) = self.billboards.filter(|b| *b < 1.0) {
            self.billboards = Some((b * GROW).min(1.0));
            return true;
        }
        if self.scale < 1.0 {
            self.scale = (self.scale * GROW).min(1.0);
            return true;
        }
        if self.morph_off {
            self.morph_off = false;
            return true;
        }
        if self.lod_coarse {
            self.lod_coarse = false;
            return true;
        }
        if self.fold_off {
            self.fold_off = false;
            return true;
        }
        if self.grass_shadows_off {
            self.grass_shadows_off = false;
            return true;
        }
        if self.msaa_off {
            self.msaa_off = false;
            return true;
        }
        false
    }

    /// One line for the Stats panel, e.g. `target 100 ms, now 84 ms: d_max 60 -> 31 m,
    /// levels 8 -> 8`, or `off`.
    pub fn status(&self) -> String {
        let Some(target) = self.target_ms else {
            return "off".into();
        };
        let mut line = format!(
            "target {target:.0} ms, now {:.0} ms: d_max {:.0} -> {:.0} m, levels {} -> {}",
            self.smoothed_ms(),
            self.base_distance,
            self.max_distance,
            self.base_levels,
            self.levels,
        );
        if self.switched_on {
            line.push_str(" (distance culling switched on)");
        }
        line.push_str(&format!(", resolution scale {:.2}", self.scale));
        if self.msaa_off {
            line.push_str(", MSAA off");
        }
        if self.grass_shadows_off {
            line.push_str(", blades cast no shadows");
        }
        if self.fold_off {
            line.push_str(", flat blades");
        }
        if self.lod_coarse {
            line.push_str(", coarser blade meshes");
        }
        if self.morph_off {
            line.push_str(", levels without morphing");
        }
        if let Some(b) = self.billboards.filter(|b| *b < 1.0) {
            line.push_str(&format!(
                ", billboards to {:.0} % of their radius",
                b * 100.0
            ));
        }
        line
    }
}

#[cfg(test)]
mod tests;
