//! The ranges and checks of the `light` section: the sun's time and place, the sky,
//! exposure, the shadow maps and the blade shading terms.

use super::allowed::{Allowed, Integers, Rule};
use super::Checker;
use crate::error::Result;
use crate::scene::types::Light;

const HOURS: Allowed = Allowed::closed(0.0, 24.0, "h");
const LATITUDE: Allowed = Allowed::closed(-89.0, 89.0, "degrees");
const DAY: Integers = Integers::new(1, 366, "");
const NORTH: Allowed = Allowed::closed(-360.0, 360.0, "degrees");
/// Preetham et al. fit their model for turbidities of about 2 to 10; below 1.7 the zenith
/// chromaticity polynomials leave the gamut.
const TURBIDITY: Allowed = Allowed::closed(1.7, 10.0, "");
const EXPOSURE: Allowed = Allowed::closed(-16.0, 16.0, "stops");
const CASCADES: Integers = Integers::new(1, 4, "");
/// Texels per side of a cascade: the adapter's largest 2D texture is checked when the map
/// is allocated.
const RESOLUTION: Integers = Integers::new(64, 8192, "texels");
const SHADOW_DISTANCE: Allowed = Allowed::open_closed(0.0, 10000.0, "m");
const GRASS_RADIUS: Allowed = Allowed::closed(0.0, 1000.0, "m");
const SOFTNESS: Allowed = Allowed::closed(0.0, 8.0, "texels");
const BIAS: Allowed = Allowed::closed(0.0, 16.0, "texels");
const STRENGTH: Allowed = Allowed::closed(0.0, 2.0, "");

/// The rules of every `light` value.
pub(super) const RULES: &[(&str, Rule)] = &[
    ("light.time_of_day", Rule::Real(HOURS)),
    ("light.latitude", Rule::Real(LATITUDE)),
    ("light.day_of_year", Rule::Integer(DAY)),
    ("light.north", Rule::Real(NORTH)),
    ("light.sky", Rule::Choice("one of Preetham, Gradient")),
    ("light.turbidity", Rule::Real(TURBIDITY)),
    ("light.exposure", Rule::Real(EXPOSURE)),
    (
        "light.tone_mapping",
        Rule::Choice("one of Aces, Agx, Clamp"),
    ),
    ("light.shadows.enabled", Rule::Bool),
    ("light.shadows.cascades", Rule::Integer(CASCADES)),
    ("light.shadows.resolution", Rule::Integer(RESOLUTION)),
    ("light.shadows.distance", Rule::Real(SHADOW_DISTANCE)),
    ("light.shadows.grass_radius", Rule::Real(GRASS_RADIUS)),
    ("light.shadows.softness", Rule::Real(SOFTNESS)),
    ("light.shadows.bias", Rule::Real(BIAS)),
    (
        "light.shadows.blade_lookup",
        Rule::Choice("one of PerPixel, PerRow"),
    ),
    ("light.shading.rounded_normal", Rule::Real(STRENGTH)),
    ("light.shading.translucency", Rule::Real(STRENGTH)),
    ("light.shading.specular", Rule::Real(STRENGTH)),
    ("light.shading.ambient_occlusion", Rule::Real(STRENGTH)),
    ("light.shading.color_variation", Rule::Real(STRENGTH)),
    ("light.shading.wind_waves", Rule::Real(STRENGTH)),
];

pub(super) fn light(check: &Checker, light: &Light) -> Result<()> {
    if let Some(hours) = light.time_of_day {
        check.real("light.time_of_day", hours, HOURS)?;
    }
    check.real("light.latitude", light.latitude, LATITUDE)?;
    check.integer("light.day_of_year", light.day_of_year, DAY)?;
    check.real("light.north", light.north, NORTH)?;
    check.real("light.turbidity", light.turbidity, TURBIDITY)?;
    check.real("light.exposure", light.exposure, EXPOSURE)?;
    let s = &light.shadows;
    check.integer("light.shadows.cascades", s.cascades, CASCADES)?;
    check.integer("light.shadows.resolution", s.resolution, RESOLUTION)?;
    check.real("light.shadows.distance", s.distance, SHADOW_DISTANCE)?;
    check.real("light.shadows.grass_radius", s.grass_radius, GRASS_RADIUS)?;
    check.real("light.shadows.softness", s.softness, SOFTNESS)?;
    check.real("light.shadows.bias", s.bias, BIAS)?;
    let names = crate::scene::types::Shading::NAMES;
    for (name, value) in names.iter().zip(light.shading.strengths()) {
        check.real(&format!("light.shading.{name}"), value, STRENGTH)?;
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::super::tests::rejected;

    #[test]
    fn light_values_are_bounded() {
        assert_eq!(
            rejected(|s| s.light.time_of_day = Some(25.0)),
            "light.time_of_day = 25 is out of range: allowed 0 <= time_of_day <= 24 h"
        );
        let m = rejected(|s| s.light.shadows.cascades = 5);
        assert!(m.contains("1 <= cascades <= 4"), "{m}");
        let m = rejected(|s| s.light.shading.specular = f32::NAN);
        assert!(m.contains("light.shading.specular"), "{m}");
        let m = rejected(|s| s.light.turbidity = 1.0);
        assert!(m.contains("1.7 <= turbidity <= 10"), "{m}");
        let m = rejected(|s| s.light.shadows.resolution = 16);
        assert!(m.contains("64 <= resolution <= 8192 texels"), "{m}");
    }
}
