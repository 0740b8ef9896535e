// The coarse levels' v along the blade (issue 27, point 1: the far levels are calibrated on
// blades that look the same at every level of detail). The coarsest level draws a blade as
// one segment, the chord from its root row to its tip, and the rows between are linear in
// v; but on the curve (`centre_line`) v is not linear in length: an upright blade's
// quadratic (v1 over the root, v2 at the tip) reaches half its height at v = 0.29, so the
// chord gave each height a larger v than the blade has there, and with it the paler tip's
// albedo, less self-shadow and a tip's normal. Measured on the prairie without wind at
// 480x270 (the blades' ratio to the far light model at 10-14 m): 0.862 with the finest
// mesh everywhere, 0.979 with the coarsest (+13 %); 0.972, 0.924 and 0.870 with 1, 2 and 3
// segments. So the far blades read brighter than the near ones, and the far levels,
// calibrated on the near ones, 8 % darker than the reference's far blades.
//
// The chord's fraction s is mapped to the curve's v whose point projects onto the chord
// at s, the curve taken as the quadratic through the chord's ends and the curve's middle:
// with its middle projecting at c (0.5 for a straight blade), the projection of the
// quadratic at v is 2 v (1 − v) a + v², a = 2 c − 0.5, so that v solves
// (1 − 2a) v² + 2a v − s = 0.
//
// The coarsest level has two segments where the field's blades have three or more
// (`mesh::lod_segments`), each mapped so onto its half of the curve: a bent blade's chord
// cuts the corner of its curve, and at a grazing view the one-segment blades at 28-45 m
// read 3-5 levels brighter than the finest mesh after 32 frames of the prairie's wind
// (two mapped segments: within 2, with and without wind). A blade's code (`chord.x`) says
// which: −1 − a for one segment, 2048 q0 + q1 for two (each half's a in 11 bits, exact in
// an f32 and carried flat). No bindings; the twins are in `render::lod_chord`.

// The quadratic's `a` from the projection `c` of the curve's middle onto the chord
// (as a share of the chord): within [0, 1], where the projection rises along the blade.
fn chord_shape(c: f32) -> f32 {
    return clamp(2.0 * c - 0.5, 0.0, 1.0);
}

// The curve's v (0 to 1) at the chord's fraction `s` for the quadratic `a`; `a` = 0.5 is
// the identity. The root of (1 − 2a) v² + 2a v − s = 0 in [0, 1], written without the
// division by 1 − 2a.
fn chord_v(s: f32, a: f32) -> f32 {
    let t = clamp(s, 0.0, 1.0);
    let k = clamp(a, 0.0, 1.0);
    let den = k + sqrt(k * k + (1.0 - 2.0 * k) * t);
    return select(clamp(t / den, 0.0, 1.0), 0.0, den <= 1e-12);
}

// The chord code of a one-segment mesh of shape `a`: −1 − a (negative).
fn chord_code_one(a: f32) -> f32 {
    return -1.0 - clamp(a, 0.0, 1.0);
}

// The chord code of a two-segment mesh of shapes `a0` (root half) and `a1` (tip half), in
// 11 bits each (exact in an f32).
fn chord_code_two(a0: f32, a1: f32) -> f32 {
    let q0 = round(clamp(a0, 0.0, 1.0) * 2047.0);
    let q1 = round(clamp(a1, 0.0, 1.0) * 2047.0);
    return q0 * 2048.0 + q1;
}

// A fragment's v on its blade from the interpolated `v` and the blade's `chord` (x: the
// chord code; y: the v the drawn blade starts at, `thinned_root_at`).
fn lod_v(v: f32, chord: vec2<f32>) -> f32 {
    let span = 1.0 - chord.y;
    if span <= 1e-4 {
        return v;
    }
    let s = (v - chord.y) / span;
    if chord.x < 0.0 {
        let a = -1.0 - chord.x;
        if abs(a - 0.5) < 1e-6 {
            return v;
        }
        return chord.y + span * chord_v(s, a);
    }
    let q0 = floor(chord.x / 2048.0);
    let q1 = chord.x - q0 * 2048.0;
    let half = select(0.0, 1.0, s >= 0.5);
    let a = select(q0, q1, s >= 0.5) / 2047.0;
    return chord.y + span * 0.5 * (half + chord_v(2.0 * s - half, a));
}
