// The cards' height profile (issue 27, point 1): the mean their texels are moved from by
// the contrast gain, row band by row band of the strip, lit as the card is. A distant eye
// sees mostly the tops of the cards, lighter than their mean (the atlas's albedo rises
// from root to tip); moved from the card's one mean, the texels that show brightened with
// the gain, and the light gain, which follows that only as fast as it averages, left the
// first frames bright while the contrast gain rose. Moved from their row's mean, the
// texels of any band of rows keep its mean (`render::billboard::atlas::profile`).

// Row bands of a layer's profile (twin of `atlas::PROFILE_ROWS`).
const PROFILE_ROWS: u32 = 8u;

// One row band of a layer: its coverage-weighted mean colour (rgb) and the same weighted
// by each facing's weight (the colour that facing's sun lights).
struct ProfileRow {
    colour: vec4<f32>,
    facing: array<vec4<f32>, 4>,
}

// A row band's mean luminance lit by `light` (the sky's part) and the sun's part of each
// facing (twin of `atlas::profile_luma`).
fn profile_luma(row: ProfileRow, light: vec3<f32>, sun: array<vec3<f32>, 4>) -> f32 {
    var c = row.colour.rgb * light;
    for (var j = 0u; j < 4u; j++) {
        c += row.facing[j].rgb * sun[j];
    }
    return dot(c, LUMA);
}

// The profile's mean at height `y` of the strip (its texture's v: 0 the top row, 1 the
// bottom), given the bands' means (`top` the upper four, `bottom` the lower four): linear
// between the bands' centres, the end bands' own past them (twin of `atlas::profile_at`).
fn profile_at(top: vec4<f32>, bottom: vec4<f32>, y: f32) -> f32 {
    let last = f32(PROFILE_ROWS - 1u);
    let s = clamp(y * f32(PROFILE_ROWS) - 0.5, 0.0, last);
    let i = min(u32(s), PROFILE_ROWS - 2u);
    let a = select(bottom[(i - 4u) & 3u], top[i & 3u], i < 4u);
    let j = i + 1u;
    let b = select(bottom[(j - 4u) & 3u], top[j & 3u], j < 4u);
    return mix(a, b, s - f32(i));
}
