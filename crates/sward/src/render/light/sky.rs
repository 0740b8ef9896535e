//! Preetham, Shirley & Smits 1999, "A Practical Analytic Model for Daylight": the CPU side
//! of the sky (its coefficients for the light uniform, the sun's colour through the air, the
//! sky's ambient irradiance) and the CPU twin of `sky_radiance` in `shaders/light.wgsl`.
//!
//! Luminance is in scene units: the model's kcd/m² times [`SKY_SCALE`], so that the noon
//! zenith of a clear sky (about 10 kcd/m²) reads 0.4, beside a sun of about 1.

// The constants are written as published (and as the WGSL twin has them), not rounded
// to f32's precision.
#![allow(clippy::excessive_precision)]

use glam::Vec3;

/// Scene radiance per kcd/m² of the model's luminance.
pub const SKY_SCALE: f32 = 0.04;
/// The sun disk's angular radius (radians): a little over the real 0.27° so that it covers
/// a pixel in small images.
pub const SUN_DISK_RADIUS: f32 = 0.0105;
/// The disk's radiance over the sun's irradiance-scaled radiance (saturates to white).
pub const SUN_DISK_GAIN: f32 = 40.0;
/// The share of the model's sky irradiance that lights the scene (the ambient term). With
/// the whole of it, a clear noon sky (turbidity 3) lit a horizontal surface with 0.42 of
/// the noon sun's irradiance on a surface facing it; clear-sky measurements put diffuse
/// horizontal over direct normal irradiance near 0.15–0.25 at a high sun (Preetham's zenith
/// luminance runs high for clear skies, about 12.8 kcd/m² at 68° where 3–8 is measured).
/// Half of it gives 0.21, and shadows on the grass as dark as a clear day's.
pub const SKY_LIGHT: f32 = 0.5;
/// The noon sun's radiance (air mass 1) in scene units.
const SUN_SCALE: f32 = 1.0;

/// The Perez coefficients A..E for (Y, x, y) at turbidity `t` (Preetham et al., Appendix A.2).
pub fn perez_coefficients(t: f32) -> [Vec3; 5] {
    [
        Vec3::new(
            0.1787 * t - 1.4630,
            -0.0193 * t - 0.2592,
            -0.0167 * t - 0.2608,
        ),
        Vec3::new(
            -0.3554 * t + 0.4275,
            -0.0665 * t + 0.0008,
            -0.0950 * t + 0.0092,
        ),
        Vec3::new(
            -0.0227 * t + 5.3251,
            -0.0004 * t + 0.2125,
            -0.0079 * t + 0.2102,
        ),
        Vec3::new(
            0.1206 * t - 2.5771,
            -0.0641 * t - 0.8989,
            -0.0441 * t - 1.6537,
        ),
        Vec3::new(
            -0.0670 * t + 0.3703,
            -0.0033 * t + 0.0452,
            -0.0109 * t + 0.0529,
        ),
    ]
}

/// The zenith's luminance (kcd/m²) and chromaticity x, y for turbidity `t` and the sun's
/// zenith angle `theta_s` (radians, clamped to the horizon: the model ends there).
pub fn zenith(t: f32, theta_s: f32) -> Vec3 {
    let th = theta_s.clamp(0.0, std::f32::consts::FRAC_PI_2);
    let chi = (4.0 / 9.0 - t / 120.0) * (std::f32::consts::PI - 2.0 * th);
    let big_y = (4.0453 * t - 4.9710) * chi.tan() - 0.2155 * t + 2.4192;
    let (t2, th2, th3) = (t * t, th * th, th * th * th);
    let x = t2 * (0.00166 * th3 - 0.00375 * th2 + 0.00209 * th)
        + t * (-0.02903 * th3 + 0.06377 * th2 - 0.03202 * th + 0.00394)
        + (0.11693 * th3 - 0.21196 * th2 + 0.06052 * th + 0.25886);
    let y = t2 * (0.00275 * th3 - 0.00610 * th2 + 0.00317 * th)
        + t * (-0.04214 * th3 + 0.08970 * th2 - 0.04153 * th + 0.00516)
        + (0.15346 * th3 - 0.26756 * th2 + 0.06670 * th + 0.26688);
    Vec3::new(big_y.max(0.0), x, y)
}

/// Perez's distribution for (Y, x, y) at once (the twin of `perez3`).
pub fn perez3(c: &[Vec3; 5], cos_theta: f32, gamma: f32, cos_gamma: f32) -> Vec3 {
    let [a, b, cc, d, e] = *c;
    let first = Vec3::ONE + a * (b / cos_theta.max(0.01)).exp();
    let second = Vec3::ONE + cc * (d * gamma).exp() + e * cos_gamma * cos_gamma;
    first * second
}

/// CIE xyY to linear sRGB (the twin of `xyy_to_rgb`).
pub fn xyy_to_rgb(x: f32, y: f32, big_y: f32) -> Vec3 {
    let yy = y.max(1e-4);
    let xyz = Vec3::new(x * big_y / yy, big_y, (1.0 - x - y) * big_y / yy);
    Vec3::new(
        Vec3::new(3.2404542, -1.5371385, -0.4985314).dot(xyz),
        Vec3::new(-0.9692660, 1.8760108, 0.0415560).dot(xyz),
        Vec3::new(0.0556434, -0.2040259, 1.0572252).dot(xyz),
    )
    .max(Vec3::ZERO)
}

/// The sky of one sun position and turbidity, ready to evaluate: what the light uniform
/// carries.
#[derive(Clone, Copy, Debug)]
pub struct PreethamSky {
    /// Unit direction towards the sun (may be below the horizon).
    pub sun: Vec3,
    /// The Perez coefficients A..E for (Y, x, y) at the sky's turbidity
    /// ([`perez_coefficients`]).
    pub coefficients: [Vec3; 5],
    /// The zenith's (Y in scene units, x, y), each over its F(0, theta_s).
    pub zenith: Vec3,
}

impl PreethamSky {
    /// The sky for a sun in direction `sun` (normalised) and turbidity `t`. Below the
    /// horizon the model is held at a sun on the horizon and dimmed through twilight.
    pub fn new(sun: Vec3, t: f32) -> Self {
        let coefficients = perez_coefficients(t);
        let theta_s = sun.y.clamp(-1.0, 1.0).acos();
        let th = theta_s.min(std::f32::consts::FRAC_PI_2);
        let z = zenith(t, th);
        let f0 = perez3(&coefficients, 1.0, th, th.cos());
        let twilight = smoothstep(-0.12, 0.02, sun.y);
        let zenith = Vec3::new(z.x * SKY_SCALE * twilight / f0.x, z.y / f0.y, z.z / f0.z);
        Self {
            sun,
            coefficients,
            zenith,
        }
    }

    /// The sky's radiance along `dir` (normalised), without the sun disk: the twin of
    /// `sky_radiance` for the Preetham model; `ground` is the colour below the horizon.
    pub fn radiance(&self, dir: Vec3, ground: Vec3) -> Vec3 {
        let h = dir.y.clamp(-1.0, 1.0);
        let up = Vec3::new(dir.x, h.max(0.0), dir.z);
        let view = if up.length_squared() < 1e-8 {
            Vec3::X
        } else {
            up.normalize()
        };
        let cos_gamma = view.dot(self.sun).clamp(-1.0, 1.0);
        let f = perez3(
            &self.coefficients,
            view.y.max(0.0),
            cos_gamma.acos(),
            cos_gamma,
        );
        let yxy = self.zenith * f;
        let c = xyy_to_rgb(yxy.y, yxy.z, yxy.x);
        if h < 0.0 {
            c.lerp(ground, (-h * 3.0).min(1.0))
        } else {
            c
        }
    }

    /// The sky's irradiance on a horizontal surface over π (so that a white Lambertian
    /// surface in the open reflects this radiance): the upper hemisphere integrated with
    /// the midpoint rule, 16 rings × 32 azimuths.
    pub fn ambient(&self) -> Vec3 {
        let (rings, sectors) = (16, 32);
        let mut sum = Vec3::ZERO;
        let d_theta = std::f32::consts::FRAC_PI_2 / rings as f32;
        let d_phi = std::f32::consts::TAU / sectors as f32;
        for i in 0..rings {
            let theta = (i as f32 + 0.5) * d_theta;
            for j in 0..sectors {
                let phi = (j as f32 + 0.5) * d_phi;
                let dir = Vec3::new(
                    theta.sin() * phi.cos(),
                    theta.cos(),
                    theta.sin() * phi.sin(),
                );
                // L cos(theta) dω, dω = sin(theta) dθ dφ.
                sum += self.radiance(dir, Vec3::ZERO) * theta.cos() * theta.sin() * d_theta * d_phi;
            }
        }
        sum / std::f32::consts::PI
    }
}

/// The sun's radiance reaching the ground, in scene units: the extraterrestrial sun (white)
/// through the Rayleigh and aerosol optical depths of the air mass along the sun's path
/// (Preetham et al., Appendix A.1: Rayleigh τ = 0.008735 λ^-4.08, Ångström aerosols
/// β = 0.04608 T − 0.04586, α = 1.3, λ in µm, at 680, 550 and 440 nm), with the air mass of
/// Kasten & Young 1989. Zero once the sun is below the horizon.
pub fn sun_radiance(sun: Vec3, t: f32) -> Vec3 {
    let elevation = sun.y.clamp(-1.0, 1.0).asin().to_degrees();
    if elevation <= -1.0 {
        return Vec3::ZERO;
    }
    let zenith_deg = 90.0 - elevation.max(0.0);
    let mass =
        1.0 / (zenith_deg.to_radians().cos() + 0.50572 * (96.07995 - zenith_deg).powf(-1.6364));
    let beta = 0.04608 * t - 0.04586;
    let lambda = Vec3::new(0.68, 0.55, 0.44);
    let tau = |l: f32| 0.008735 * l.powf(-4.08) + beta * l.powf(-1.3);
    let depth = Vec3::new(tau(lambda.x), tau(lambda.y), tau(lambda.z));
    // White-balanced to the noon sun (air mass 1), as a camera set to daylight sees it:
    // white overhead, warmer as the path through the air lengthens, red at sunset.
    let through = (-depth * (mass - 1.0)).exp();
    // The sun sets over a degree: its disk slips below the horizon.
    through * SUN_SCALE * smoothstep(-1.0, 0.5, elevation)
}

/// The `Gradient` sky (sward before issue 16): the twin of its branch of `sky_radiance`.
pub fn gradient_radiance(dir: Vec3, sun: Vec3) -> Vec3 {
    let h = dir.y.clamp(-1.0, 1.0);
    let zenith = Vec3::new(0.22, 0.42, 0.78);
    let horizon = Vec3::new(0.70, 0.80, 0.90);
    let mut c = horizon.lerp(zenith, h.max(0.0).powf(0.55));
    if h < 0.0 {
        c = horizon.lerp(Vec3::new(0.45, 0.50, 0.45), (-h * 3.0).min(1.0));
    }
    let s = dir.dot(sun).max(0.0);
    c + Vec3::new(1.0, 0.85, 0.6) * (s.powf(600.0) * 4.0 + s.powf(12.0) * 0.25)
}

pub(crate) fn smoothstep(e0: f32, e1: f32, x: f32) -> f32 {
    let t = ((x - e0) / (e1 - e0)).clamp(0.0, 1.0);
    t * t * (3.0 - 2.0 * t)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn noon_sky_is_blue_at_the_zenith_and_bright_at_the_horizon() {
        let sun = Vec3::new(0.0, 0.866, 0.5);
        let sky = PreethamSky::new(sun, 3.0);
        let zenith = sky.radiance(Vec3::Y, Vec3::ZERO);
        assert!(zenith.z > zenith.x, "zenith {zenith}");
        let lum = |c: Vec3| c.dot(Vec3::new(0.2126, 0.7152, 0.0722));
        // Preetham's zenith at turbidity 3 and 30° is about 10.4 kcd/m².
        assert!(
            (lum(zenith) - 10.4 * SKY_SCALE).abs() < 0.05,
            "{}",
            lum(zenith)
        );
        // Towards the sun's azimuth the horizon is brighter than the zenith; away from it,
        // 120° from the sun, darker (the circumsolar term fades).
        let towards = sky.radiance(Vec3::new(0.0, 0.02, 1.0).normalize(), Vec3::ZERO);
        let away = sky.radiance(Vec3::new(0.0, 0.02, -1.0).normalize(), Vec3::ZERO);
        assert!(lum(towards) > lum(zenith), "{towards} vs {zenith}");
        assert!(lum(away) < lum(towards), "{away} vs {towards}");
    }

    #[test]
    fn evening_sun_is_red_and_dimmer() {
        let noon = sun_radiance(Vec3::Y, 3.0);
        let low = sun_radiance(Vec3::new(0.0, 0.05, 1.0).normalize(), 3.0);
        // Kasten & Young's air mass overhead is 0.9997, not quite 1.
        assert!((noon - Vec3::ONE).abs().max_element() < 1e-3, "{noon}");
        assert!(low.x / low.z > 2.0 * noon.x / noon.z, "{low} {noon}");
        assert!(low.y < noon.y);
        assert_eq!(
            sun_radiance(Vec3::new(0.0, -0.2, 1.0).normalize(), 3.0),
            Vec3::ZERO
        );
    }

    #[test]
    fn ambient_is_the_hemisphere_integral() {
        // A uniform sky of radiance L gives irradiance πL: ambient() = L.
        let sky = PreethamSky::new(Vec3::new(0.0, 0.7, 0.7).normalize(), 3.0);
        let a = sky.ambient();
        assert!(a.min_element() > 0.05 && a.max_element() < 1.0, "{a}");
        assert!(a.z > a.x, "a clear sky's light is blue: {a}");
    }
}
