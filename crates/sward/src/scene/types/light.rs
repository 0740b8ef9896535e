//! The scene file's light (issue 16): where the sun stands (a direction, or the time of day
//! at a latitude), the analytic sky, exposure and tone mapping, the sun's cascaded shadow
//! maps, and the blade shading terms of the Ghost of Tsushima look, each with a strength
//! (0 switches the term off, 1 is sward's look).

use serde::{Deserialize, Serialize};

/// Light and look of the sunlit meadow.
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
#[serde(default, deny_unknown_fields)]
pub struct Light {
    /// Local solar time in hours (6 = sunrise at the equinox, 12 = noon, 18 = sunset); the
    /// sun's direction follows it, `latitude` and `day_of_year`. `None`: the sun stands at
    /// `render.sun_direction`.
    pub time_of_day: Option<f32>,
    /// Degrees north (negative: south) of the equator.
    pub latitude: f32,
    /// Day of the year, 1 (1 January) to 366: the sun's declination.
    pub day_of_year: u32,
    /// The compass direction of north in the scene, degrees from −z towards +x: turns the
    /// sun's path over the field.
    pub north: f32,
    /// The sky's model: Preetham et al.'s analytic daylight, or the flat gradient of
    /// earlier versions.
    pub sky: SkyModel,
    /// The haze of the Preetham sky (2: very clear, 3: clear, 6: hazy, 10: light fog).
    pub turbidity: f32,
    /// Exposure in stops: the radiance is scaled by 2^exposure before tone mapping.
    pub exposure: f32,
    /// How radiance becomes a display colour.
    pub tone_mapping: ToneMapping,
    /// The sun's cascaded shadow maps.
    pub shadows: Shadows,
    /// The blade shading terms.
    pub shading: Shading,
}

impl Default for Light {
    fn default() -> Self {
        Self {
            time_of_day: None,
            latitude: 45.0,
            day_of_year: 172,
            north: 0.0,
            sky: SkyModel::Preetham,
            turbidity: 3.0,
            exposure: 0.0,
            tone_mapping: ToneMapping::Aces,
            shadows: Shadows::default(),
            shading: Shading::default(),
        }
    }
}

/// The sky's model.
#[derive(Clone, Copy, Debug, Default, Serialize, Deserialize, PartialEq, Eq)]
pub enum SkyModel {
    /// Preetham, Shirley & Smits 1999, "A Practical Analytic Model for Daylight": the
    /// Perez distribution of luminance and chromaticity from the turbidity and the sun's
    /// height, with a sun disk.
    #[default]
    Preetham,
    /// A blue gradient with a glow around the sun (sward before issue 16).
    Gradient,
}

impl SkyModel {
    /// The id the shaders switch on.
    pub fn id(self) -> u32 {
        match self {
            SkyModel::Preetham => 0,
            SkyModel::Gradient => 1,
        }
    }
}

/// The filmic curve from radiance to the display.
#[derive(Clone, Copy, Debug, Default, Serialize, Deserialize, PartialEq, Eq)]
pub enum ToneMapping {
    /// ACES (the RRT + ODT fit of Stephen Hill, in the ACES input colour space).
    #[default]
    Aces,
    /// AgX (Troy Sobotka's, with Benjamin Wrensch's polynomial fit of its base contrast).
    Agx,
    /// No curve: radiance clamped to [0, 1].
    Clamp,
}

impl ToneMapping {
    /// The id the shaders switch on.
    pub fn id(self) -> u32 {
        match self {
            ToneMapping::Aces => 0,
            ToneMapping::Agx => 1,
            ToneMapping::Clamp => 2,
        }
    }
}

/// The sun's cascaded shadow maps: the view split by distance into `cascades`, each with a
/// depth map of `resolution`² texels seen from the sun, snapped to whole texels so that the
/// shadows do not crawl as the camera moves.
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
#[serde(default, deny_unknown_fields)]
pub struct Shadows {
    /// Whether the sun casts shadows (on by default); `false` draws no shadow maps.
    pub enabled: bool,
    /// 1 to 4 cascades.
    pub cascades: u32,
    /// Texels per side of each cascade's map.
    pub resolution: u32,
    /// Shadows end this far from the camera (m); the cascades split it.
    pub distance: f32,
    /// The blades cast shadows out to this distance from the camera (m), with their
    /// coarsest level of detail; 0: the grass casts none.
    pub grass_radius: f32,
    /// Spread of the percentage-closer filter in texels, the shadows' soft edge: its four
    /// bilinear taps sit ±(softness / 2 + 1/4) texels from the point.
    pub softness: f32,
    /// Depth bias in texels of the cascade (against self-shadowing acne).
    pub bias: f32,
    /// Where the deferred grass light looks the sun's shadow up on a blade.
    pub blade_lookup: BladeShadowLookup,
}

/// Where the deferred grass light looks the sun's shadow up on a blade.
#[derive(Clone, Copy, Debug, Default, Serialize, Deserialize, PartialEq, Eq)]
pub enum BladeShadowLookup {
    /// At every pixel of the blade: the shadows of its neighbours fall across it, which a
    /// close view shows.
    #[default]
    PerPixel,
    /// At the blade's rows of vertices, interpolated along it, as the forward pass does: one
    /// lookup per row of each drawn blade instead of one per pixel (on llvmpipe the peer's
    /// 8,192 blades at 1280x720 light in 0.8 of the time), the shadows across a blade lost.
    PerRow,
}

impl Default for Shadows {
    fn default() -> Self {
        Self {
            enabled: true,
            cascades: 3,
            resolution: 1024,
            distance: 80.0,
            grass_radius: 25.0,
            softness: 1.5,
            bias: 1.5,
            blade_lookup: BladeShadowLookup::PerPixel,
        }
    }
}

/// The blade shading terms: each a strength, 0 off, 1 sward's look, up to 2.
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
#[serde(default, deny_unknown_fields)]
pub struct Shading {
    /// The normal bent across the blade's width, so a flat blade reads as curved.
    pub rounded_normal: f32,
    /// Sunlight through the blade when the sun is behind it.
    pub translucency: f32,
    /// The sun's highlight on the blade's waxy surface.
    pub specular: f32,
    /// Darker at the root and where the field is dense.
    pub ambient_occlusion: f32,
    /// Each blade's and each clump's own shade of green.
    pub color_variation: f32,
    /// Bright bands that run over the field with the wind's gusts.
    pub wind_waves: f32,
}

impl Default for Shading {
    fn default() -> Self {
        Self {
            rounded_normal: 1.0,
            translucency: 1.0,
            specular: 1.0,
            ambient_occlusion: 1.0,
            color_variation: 1.0,
            wind_waves: 1.0,
        }
    }
}

impl Shading {
    /// The terms by name, in the order of the panel and the light page's ablation (docs/light.md).
    pub const NAMES: [&'static str; 6] = [
        "rounded_normal",
        "translucency",
        "specular",
        "ambient_occlusion",
        "color_variation",
        "wind_waves",
    ];

    /// The strengths in the order of [`Shading::NAMES`].
    pub fn strengths(&self) -> [f32; 6] {
        [
            self.rounded_normal,
            self.translucency,
            self.specular,
            self.ambient_occlusion,
            self.color_variation,
            self.wind_waves,
        ]
    }

    /// The strength of the term named `name`, for the panel and the ablation.
    pub fn term_mut(&mut self, name: &str) -> Option<&mut f32> {
        Some(match name {
            "rounded_normal" => &mut self.rounded_normal,
            "translucency" => &mut self.translucency,
            "specular" => &mut self.specular,
            "ambient_occlusion" => &mut self.ambient_occlusion,
            "color_variation" => &mut self.color_variation,
            "wind_waves" => &mut self.wind_waves,
            _ => return None,
        })
    }
}
