//! Where the sun stands: from the scene's time of day, latitude and day of the year (the
//! textbook solar position: Cooper's declination, the hour angle of local solar time), or
//! the fixed `render.sun_direction`.

use glam::Vec3;

use crate::scene::Scene;

/// The sun's declination (radians) on `day` of the year (Cooper 1969).
pub fn declination(day: u32) -> f32 {
    (23.44f32).to_radians() * (std::f32::consts::TAU * (284.0 + day as f32) / 365.0).sin()
}

/// The direction towards the sun at local solar time `hours` (12 = noon), `latitude` degrees
/// north, on `day` of the year, in a scene whose north is `north` degrees from −z towards +x
/// (east is then +x for north 0). Below the horizon the direction points down.
pub fn sun_at(hours: f32, latitude: f32, day: u32, north: f32) -> Vec3 {
    let phi = latitude.to_radians();
    let delta = declination(day);
    let h = (15.0 * (hours - 12.0)).to_radians();
    // The sun in a local frame: x east, y up, z north.
    let up = phi.sin() * delta.sin() + phi.cos() * delta.cos() * h.cos();
    let east = -delta.cos() * h.sin();
    let north_c = phi.cos() * delta.sin() - phi.sin() * delta.cos() * h.cos();
    let n = north.to_radians();
    let north_dir = Vec3::new(n.sin(), 0.0, -n.cos());
    let east_dir = Vec3::new(n.cos(), 0.0, n.sin());
    (east_dir * east + north_dir * north_c + Vec3::Y * up).normalize_or(Vec3::Y)
}

/// The scene's sun: [`sun_at`] when `light.time_of_day` is set, else `render.sun_direction`.
pub fn scene_sun(scene: &Scene) -> Vec3 {
    let l = &scene.light;
    match l.time_of_day {
        Some(hours) => sun_at(hours, l.latitude, l.day_of_year, l.north),
        None => Vec3::from(scene.render.sun_direction).normalize_or(Vec3::Y),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_sun_rises_in_the_east_and_culminates_in_the_south() {
        // Equinox (day 80: declination ~0) at 45° N.
        let dawn = sun_at(6.0, 45.0, 80, 0.0);
        assert!(dawn.y.abs() < 0.03 && dawn.x > 0.99, "{dawn}");
        let noon = sun_at(12.0, 45.0, 80, 0.0);
        assert!((noon.y - 45f32.to_radians().cos()).abs() < 0.02, "{noon}");
        // South is +z with north at -z.
        assert!(noon.z > 0.6 && noon.x.abs() < 1e-4, "{noon}");
        let evening = sun_at(17.0, 45.0, 80, 0.0);
        assert!(
            evening.x < -0.5 && evening.y > 0.0 && evening.y < 0.25,
            "{evening}"
        );
        let night = sun_at(0.0, 45.0, 80, 0.0);
        assert!(night.y < -0.6, "{night}");
    }

    #[test]
    fn midsummer_noon_is_higher_than_midwinter() {
        let summer = sun_at(12.0, 45.0, 172, 0.0).y;
        let winter = sun_at(12.0, 45.0, 355, 0.0).y;
        assert!((summer.asin().to_degrees() - 68.4).abs() < 0.6, "{summer}");
        assert!((winter.asin().to_degrees() - 21.6).abs() < 0.6, "{winter}");
    }
}
