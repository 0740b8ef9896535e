//! Seeded 2D value noise and its fractal sum (fBm) for procedural terrain. Value noise
//! rather than gradient noise because the terrain only needs gentle rolling hills: random
//! heights on an integer lattice, blended with a quintic fade so that the surface (and so
//! the normals the blades grow along) has no creases at the lattice lines.

use super::rng::mix64;

/// Lacunarity of the fBm: each octave doubles the frequency ...
const LACUNARITY: f64 = 2.0;
/// ... and halves the amplitude.
const GAIN: f64 = 0.5;

/// The pseudo-random value in `[-1, 1]` at lattice point `(ix, iz)`.
fn lattice(seed: u64, ix: i64, iz: i64) -> f64 {
    let h = mix64(seed ^ mix64((ix as u64) ^ mix64(iz as u64).rotate_left(17)));
    (h >> 11) as f64 * (2.0 / (1u64 << 53) as f64) - 1.0
}

/// Quintic fade 6t⁵ − 15t⁴ + 10t³: zero first and second derivatives at 0 and 1.
fn fade(t: f64) -> f64 {
    t * t * t * (t * (t * 6.0 - 15.0) + 10.0)
}

/// Value noise in `[-1, 1]` with unit lattice spacing.
pub fn value_noise(seed: u64, x: f64, z: f64) -> f64 {
    let (x0, z0) = (x.floor(), z.floor());
    let (ix, iz) = (x0 as i64, z0 as i64);
    let (tx, tz) = (fade(x - x0), fade(z - z0));
    let a = lattice(seed, ix, iz);
    let b = lattice(seed, ix + 1, iz);
    let c = lattice(seed, ix, iz + 1);
    let d = lattice(seed, ix + 1, iz + 1);
    let top = a + (b - a) * tx;
    let bottom = c + (d - c) * tx;
    top + (bottom - top) * tz
}

/// Fractal Brownian motion of value noise in `[-1, 1]`: `octaves` layers, the first with
/// lattice spacing `wavelength`, each next one at twice the frequency and half the weight.
/// The sum is divided by the total weight so the range does not depend on `octaves`.
pub fn fbm(seed: u64, octaves: u32, wavelength: f64, x: f64, z: f64) -> f64 {
    let mut sum = 0.0;
    let mut weight = 0.0;
    let mut amplitude = 1.0;
    let mut frequency = 1.0 / wavelength;
    for octave in 0..octaves {
        // Every octave gets its own lattice values and an irrational offset: otherwise all
        // octaves share lattice lines through the origin and the seams line up into a grid.
        let octave_seed = mix64(seed.wrapping_add(u64::from(octave)));
        let offset = f64::from(octave) * 0.618_033_988_75 + 0.25;
        sum += amplitude * value_noise(octave_seed, x * frequency + offset, z * frequency - offset);
        weight += amplitude;
        amplitude *= GAIN;
        frequency *= LACUNARITY;
    }
    if weight > 0.0 {
        sum / weight
    } else {
        0.0
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn lattice_values_match_at_integer_points_and_stay_in_range() {
        for i in -5..5 {
            for j in -5..5 {
                let v = value_noise(9, f64::from(i), f64::from(j));
                assert_eq!(v, lattice(9, i64::from(i), i64::from(j)));
                assert!((-1.0..=1.0).contains(&v));
            }
        }
    }

    #[test]
    fn noise_is_continuous() {
        // Across a lattice line the value must not jump.
        let step = 1e-6;
        for k in 0..50 {
            let z = f64::from(k) * 0.137;
            let left = value_noise(1, 3.0 - step, z);
            let right = value_noise(1, 3.0 + step, z);
            assert!((left - right).abs() < 1e-4);
        }
    }

    #[test]
    fn fbm_is_seeded_and_bounded() {
        let a = fbm(5, 4, 30.0, 1.5, -2.5);
        assert_eq!(a, fbm(5, 4, 30.0, 1.5, -2.5));
        assert_ne!(a, fbm(6, 4, 30.0, 1.5, -2.5));
        for k in 0..1000 {
            let v = fbm(5, 6, 10.0, f64::from(k) * 0.73, f64::from(k) * -0.31);
            assert!((-1.0..=1.0).contains(&v));
        }
        assert_eq!(fbm(5, 0, 10.0, 1.0, 1.0), 0.0);
    }
}
