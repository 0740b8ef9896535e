//! The coarse levels' v along the blade: the CPU twins of `shaders/lod_chord.wgsl`. The
//! coarsest level of detail draws a blade as its chord (one segment from the root row to the
//! tip), where v is linear in length, while on the curve it is not: an upright blade reaches
//! half its height at v = 0.29. Each fragment's v is mapped from the chord's fraction to the
//! curve's v whose point projects there, the curve taken as the quadratic through the
//! chord's ends and the curve's middle, so that a blade shades alike at every level (the
//! coarsest read 13 % brighter than the finest against the far light model). Where the
//! field's blades have three segments or more the coarsest level has two, each mapped so
//! onto its half of the curve (a bent blade's one chord cuts the corner of its curve: 3-5
//! levels brighter at a grazing view after 32 frames of the prairie's wind).

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

/// The chord code of a one-segment mesh of shape `a` (twin of `chord_code_one`): −1 − a.
pub fn code_one(a: f32) -> f32 {
    -1.0 - a.clamp(0.0, 1.0)
}

/// The chord code of a two-segment mesh of shapes `a0` (the root's half) and `a1` (the
/// tip's) (twin of `chord_code_two`): each in 11 bits, `2048 q0 + q1`, exact in an f32.
pub fn code_two(a0: f32, a1: f32) -> f32 {
    let q0 = (a0.clamp(0.0, 1.0) * 2047.0).round();
    let q1 = (a1.clamp(0.0, 1.0) * 2047.0).round();
    q0 * 2048.0 + q1
}

/// A fragment's v from the interpolated `v`, the blade's chord `code` ([`code_one`],
/// [`code_two`]) and the v its drawn part starts at, `root` (twin of `lod_v`): the mesh
/// spans v from the root to 1, in one segment or two halves.
pub fn lod_v(v: f32, code: f32, root: f32) -> f32 {
    let span = 1.0 - root;
    if span <= 1e-4 {
        return v;
    }
    let s = (v - root) / span;
    if code < 0.0 {
        let a = -1.0 - code;
        if (a - 0.5).abs() < 1e-6 {
            return v;
        }
        return root + span * chord_v(s, a);
    }
    let q0 = (code / 2048.0).floor();
    let q1 = code - q0 * 2048.0;
    let half = if s >= 0.5 { 1.0 } else { 0.0 };
    let a = if s >= 0.5 { q1 } else { q0 } / 2047.0;
    root + span * 0.5 * (half + chord_v(2.0 * s - half, a))
}

/// Runs the WGSL twins on the GPU (`lod_chord_probe.wgsl`) at each (s, a, c, root) of
/// `points`: ([`chord_v`] (s, a), [`shape`] (c), [`lod_v`] (s, [`code_one`] (a), root),
/// [`lod_v`] (s, [`code_two`] (a, c), root)) as the GPU computes them.
pub fn probe(gpu: &Gpu, points: &[[f32; 4]]) -> Result<Vec<[f32; 4]>> {
    let out = crate::gpu::run_vec4_probe(
        gpu,
        "sward.lod_chord_probe",
        "lod_chord_probe.wgsl",
        &[bytemuck::cast_slice(points)],
        points.len(),
    )?;
    Ok(out)
}
