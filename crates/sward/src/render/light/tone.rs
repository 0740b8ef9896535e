//! Exposure and the filmic tone mappers: the CPU twins of `aces`, `agx` and `tonemap` in
//! `shaders/light.wgsl` (linear radiance in, linear display colour out; the sRGB target
//! encodes it).

// The constants are written as published (and as the WGSL twin has them), not rounded
// to f32's precision.
#![allow(clippy::excessive_precision)]

use glam::Vec3;

use crate::scene::ToneMapping;

/// The exposure multiplier at 0 stops for each mapper, so that the meadow's mid-tones land
/// near where sward's earlier curve put them: Hill's ACES fit maps 0.18 to 0.105 where
/// that curve gave 0.24, so it gets 1.8×; AgX maps 0.18 to about 0.2 already.
pub fn base_exposure(mapper: ToneMapping) -> f32 {
    match mapper {
        ToneMapping::Aces => 1.8,
        ToneMapping::Agx | ToneMapping::Clamp => 1.0,
    }
}

/// The multiplier radiance is scaled by before the curve: the mapper's base times 2^EV.
pub fn exposure_multiplier(mapper: ToneMapping, stops: f32) -> f32 {
    base_exposure(mapper) * stops.exp2()
}

fn rows(m: [[f32; 3]; 3], v: Vec3) -> Vec3 {
    // m holds the columns the shader multiplies by the components.
    Vec3::from(m[0]) * v.x + Vec3::from(m[1]) * v.y + Vec3::from(m[2]) * v.z
}

/// Stephen Hill's ACES RRT + ODT fit.
pub fn aces(c: Vec3) -> Vec3 {
    let input = [
        [0.59719, 0.07600, 0.02840],
        [0.35458, 0.90834, 0.13383],
        [0.04823, 0.01566, 0.83777],
    ];
    let output = [
        [1.60475, -0.10208, -0.00327],
        [-0.53108, 1.10813, -0.07276],
        [-0.07367, -0.00605, 1.07602],
    ];
    let v = rows(input, c);
    let a = v * (v + 0.0245786) - 0.000090537;
    let b = v * (0.983729 * v + 0.4329510) + 0.238081;
    rows(output, a / b).clamp(Vec3::ZERO, Vec3::ONE)
}

/// AgX with Benjamin Wrensch's polynomial fit of the base contrast, linearised.
pub fn agx(c: Vec3) -> Vec3 {
    let inset = [
        [0.842479062253094, 0.0423282422610123, 0.0423756549057051],
        [0.0784335999999992, 0.878468636469772, 0.0784336],
        [0.0792237451477643, 0.0791661274605434, 0.879142973793104],
    ];
    let outset = [
        [1.19687900512017, -0.0528968517574562, -0.0529716355144438],
        [-0.0980208811401368, 1.15190312990417, -0.0980434501171241],
        [-0.0990297440797205, -0.0989611768448433, 1.15107367264116],
    ];
    let (lo, hi) = (-12.47393f32, 4.026069f32);
    let v = rows(inset, c);
    let v = Vec3::new(v.x.max(1e-10), v.y.max(1e-10), v.z.max(1e-10));
    let v = Vec3::new(v.x.log2(), v.y.log2(), v.z.log2()).clamp(Vec3::splat(lo), Vec3::splat(hi));
    let v = (v - lo) / (hi - lo);
    let x2 = v * v;
    let x4 = x2 * x2;
    let v =
        15.5 * x4 * x2 - 40.14 * x4 * v + 31.96 * x4 - 6.868 * x2 * v + 0.4298 * x2 + 0.1191 * v
            - 0.00232;
    let v = rows(outset, v).clamp(Vec3::ZERO, Vec3::ONE);
    Vec3::new(v.x.powf(2.2), v.y.powf(2.2), v.z.powf(2.2))
}

/// Exposure (the multiplier of [`exposure_multiplier`]) and the mapper: the twin of
/// `tonemap`.
pub fn tonemap(c: Vec3, mapper: ToneMapping, multiplier: f32) -> Vec3 {
    let x = c.max(Vec3::ZERO) * multiplier;
    match mapper {
        ToneMapping::Aces => aces(x),
        ToneMapping::Agx => agx(x),
        ToneMapping::Clamp => x.clamp(Vec3::ZERO, Vec3::ONE),
    }
}

/// The sRGB transfer function (what the sRGB target applies), to 8 bits.
pub fn srgb8(linear: f32) -> u8 {
    let c = linear.clamp(0.0, 1.0);
    let s = if c <= 0.0031308 {
        12.92 * c
    } else {
        1.055 * c.powf(1.0 / 2.4) - 0.055
    };
    (s * 255.0).round() as u8
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn mappers_are_monotonic_and_bounded() {
        for mapper in [ToneMapping::Aces, ToneMapping::Agx] {
            let mut last = -1.0;
            for i in 0..200 {
                let x = (i as f32 * 0.1 - 10.0).exp2();
                let y = tonemap(Vec3::splat(x), mapper, 1.0).y;
                assert!(
                    y >= last - 1e-6 && (0.0..=1.0).contains(&y),
                    "{mapper:?} {x} {y}"
                );
                last = y;
            }
            assert!(last > 0.9, "{mapper:?} saturates near white: {last}");
        }
        // Mid grey after the base exposure sits near 0.2 for both.
        for mapper in [ToneMapping::Aces, ToneMapping::Agx] {
            let m = exposure_multiplier(mapper, 0.0);
            let g = tonemap(Vec3::splat(0.18), mapper, m).y;
            assert!((0.12..0.3).contains(&g), "{mapper:?}: {g}");
        }
    }
}
