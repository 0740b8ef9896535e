//! The scene's `render` block: the look of the blades (displacement, width correction,
//! colour view, self-shadow), the billboards' reach and the anti-aliasing (MSAA, TAA).

use serde::{Deserialize, Serialize};

/// Lighting and look.
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
#[serde(default, deny_unknown_fields)]
pub struct Render {
    /// Direction towards the sun (normalised on load).
    pub sun_direction: (f32, f32, f32),
    /// 3D displacement of the middle axis (Eq. 23).
    pub displacement: bool,
    /// Width correction (Eq. 24): w_min and w_span in pixels; w_span = 0 switches it off.
    pub width_min_px: f32,
    /// w_span of Eq. 24 in pixels, 0 to 1024 px (w_min's range too); 0 switches the
    /// correction off.
    pub width_span_px: f32,
    /// What the blade colour shows.
    pub color_mode: ColorMode,
    /// Draw the grass as lines (needs the adapter's line polygon mode).
    pub wireframe: bool,
    /// How the blades darken towards the ground, where their neighbours shade them.
    pub self_shadow: SelfShadow,
    /// Billboards of grass from the blades' radius out to this distance (m); 0: none.
    pub billboard_distance: f32,
    /// Samples per pixel of the 3D passes (MSAA): 1 (off, or TAA with `taa`), 2, 4 or 8.
    /// Thin, moving blades shimmer without anti-aliasing. 4 by default: every WebGPU
    /// adapter supports 4× for the formats used, and the far levels are calibrated on
    /// the blades at 4× (with one sample the far blades' band reads darker); where the
    /// adapter lacks the count asked for, the largest count below it is used (with a
    /// warning).
    pub msaa: u32,
    /// Light the grass once per pixel, after the draw (a visibility buffer and a compute
    /// pass; `render::deferred`), where it can: one sample per pixel, filled triangles, no
    /// flower heads or debug colour view. Otherwise, or false, it is lit as it is drawn.
    pub deferred_grass: bool,
    /// Temporal anti-aliasing (`render::taa`) for frames of one sample per pixel
    /// (`msaa: 1`): the projection is jittered by a sub-pixel offset every frame and each
    /// pixel is blended with the last frames' result found through its motion (the
    /// blade's own for grass), clamped to its neighbourhood. On the software adapter it
    /// costs about a sixth of what 4× MSAA does and flickers half as much (`sward bench
    /// --antialiasing`); off by default (see `msaa`).
    pub taa: bool,
}

/// Self-shadowing among the blades, without shadow maps.
#[derive(Clone, Copy, Debug, Default, Serialize, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub enum SelfShadow {
    /// sward's own: each blade darker towards its base along its length.
    #[default]
    Height,
    /// CWD-Sim's Eq. 14 (Choi & Sung 2024, §3.4): a vertex's brightness is its height above
    /// the root after the deformation, in blade heights, minus the blade's bend (0 upright,
    /// 1 pressed flat) times `c1`, plus `c2`, clamped to [`min`, `max`]: a blade pressed
    /// down by the wind or a ball sinks into the shade of the others.
    Cwd {
        /// Darkest brightness a vertex can get, 0 to 2.
        min: f32,
        /// Brightest a vertex can get, from `min` to 2.
        max: f32,
        /// How much the blade's bend darkens it, 0 to 10.
        c1: f32,
        /// Brightness added to every vertex, -2 to 2.
        c2: f32,
    },
    /// No self-shadow (Figure 7 (a) of the paper).
    Off,
}

impl SelfShadow {
    /// CWD-Sim's shading with the parameters sward ships (dark at the base, full light at
    /// an upright tip).
    pub const CWD: SelfShadow = SelfShadow::Cwd {
        min: 0.3,
        max: 1.0,
        c1: 0.7,
        c2: 0.25,
    };

    /// The mode id the grass shader switches on and the four parameters.
    pub fn uniforms(self) -> (f32, [f32; 4]) {
        match self {
            SelfShadow::Height => (0.0, [0.0; 4]),
            SelfShadow::Cwd { min, max, c1, c2 } => (1.0, [min, max, c1, c2]),
            SelfShadow::Off => (2.0, [0.0; 4]),
        }
    }
}

/// What the blades' colour shows: their natural colour, or a debugging view.
#[derive(Clone, Copy, Debug, Default, Serialize, Deserialize, PartialEq, Eq)]
pub enum ColorMode {
    /// The blades' own colour, lit (the default).
    #[default]
    Natural,
    /// The level of detail each blade is drawn at, with its morph towards the next (green
    /// full mesh, yellow middle, red one segment).
    Lod,
    /// One colour per patch (the unit of patch culling).
    Patch,
    /// The collision strength η of each blade (Eq. 2): green untouched, through yellow to
    /// red at η >= 1 (a full trail), so that trails and their width can be seen.
    Trail,
}

impl ColorMode {
    /// The id the grass shader switches on.
    pub fn id(self) -> u32 {
        match self {
            ColorMode::Natural => 0,
            ColorMode::Lod => 1,
            ColorMode::Patch => 2,
            ColorMode::Trail => 3,
        }
    }
}

impl Default for Render {
    fn default() -> Self {
        Self {
            sun_direction: (-0.45, 0.75, -0.5),
            displacement: true,
            width_min_px: 1.0,
            width_span_px: 2.0,
            color_mode: ColorMode::Natural,
            wireframe: false,
            self_shadow: SelfShadow::Height,
            billboard_distance: 0.0,
            msaa: 4,
            deferred_grass: true,
            taa: false,
        }
    }
}
