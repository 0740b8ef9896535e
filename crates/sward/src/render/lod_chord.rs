//! The coarse levels' v along the blade: the CPU twins of `shaders/lod_chord.wgsl`. The
//! coarsest level of detail draws a blade as its chord (one segment from the root row to the
//! tip), where v is linear in length, while on the curve it is not: an upright blade reaches
//! half its height at v = 0.29. Each fragment's v is mapped from the chord's fraction to the
//! curve's v whose point projects there, the curve taken as the quadratic through the
//! chord's ends and the curve's middle, so that a blade shades alike at every level (the
//! coarsest read 13 % brighter than the finest against the far light model).

use crate::error::Result;
use crate::gpu::Gpu;

/// The quadratic's `a` from the projection `c` of the curve's middle onto the chord, as a
/// share of the chord (twin of `chord_shape`): `2 c − 0.5`, within 0 and 1.
pub fn shape(c: f32) -> f32 {
    (2.0 * c - 0.5).clamp(0.0, 1.0)
}

/// The curve's v at the chord's fraction `s` for the quadratic `a` (twin of `chord_v`):
/// the root in [0, 1] of `(1 − 2a) v² + 2a v − s = 0`; `a` = 0.5 is the identity.
pub fn chord_v(s: f32, a: f32) -> f32 {
    let t = s.clamp(0.0, 1.0);
    let k = a.clamp(0.0, 1.0);
    let den = k + (k * k + (1.0 - 2.0 * k) * t).sqrt();
    if den <= 1e-12 {
        0.0
    } else {
        (t / den).clamp(0.0, 1.0)
    }
}

/// A fragment's v from the interpolated `v` and the blade's (a, root v) (twin of `lod_v`):
/// the chord spans v from the root to 1.
pub fn lod_v(v: f32, a: f32, root: f32) -> f32 {
    let span = 1.0 - root;
    if span <= 1e-4 || (a - 0.5).abs() < 1e-6 {
        return v;
    }
    root + span * chord_v((v - root) / span, a)
}

/// Runs the WGSL twins on the GPU (`lod_chord_probe.wgsl`) at each (s, a, c, root) of
/// `points`: ([`chord_v`] (s, a), [`shape`] (c), [`lod_v`] (s, a, root)) as the GPU
/// computes them.
pub fn probe(gpu: &Gpu, points: &[[f32; 4]]) -> Result<Vec<(f32, f32, f32)>> {
    let out = crate::gpu::run_vec4_probe(
        gpu,
        "sward.lod_chord_probe",
        "lod_chord_probe.wgsl",
        &[bytemuck::cast_slice(points)],
        points.len(),
    )?;
    Ok(out.iter().map(|v| (v[0], v[1], v[2])).collect())
}
