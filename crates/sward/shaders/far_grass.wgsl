// The grass far away (issue 27, point 1): the billboards and the far ground stand for
// blades too small to draw, so they are lit as the blades they replace would be — by the
// blades' own light (`blade_light`, blade_shade.wgsl) averaged over the blades a distant
// eye sees. Included after common.wgsl, light.wgsl and blade_shade.wgsl; the far grass's
// texture is in grass_texture.wgsl.
//!include grass_texture.wgsl
//
// Which blades a distant eye sees: a view ray entering the canopy at elevation e meets
// leaf area `G · LAI / sin e` on its way to the ground (G = 0.5: blades at random angles,
// LAI the canopy's leaf area, `shading_b.z`), so the share of what it sees at depth d
// below the tips (in shares of the canopy's leaf area, `drawn_canopy_v`) falls off as e^(−k d),
// k = G · LAI / sin e (Beer-Lambert). At grazing angles the eye sees the tips, from above the whole blade.
// The light is averaged at the quartiles of that depth, over four blade facings spread
// around the ground's normal, each turned to the viewer as the blades' shading turns them,
// and over both halves of the blade's width (the rounded normal turns them apart).
//
// The facings are upright: a bent blade's normal tilts up on the face turned towards its
// bend and down on the other, and the two-sided shading shows either face, so the tilts
// cancel on average. (A quadrature tilted up by 0.3 left the prairie's cards 12 levels
// darker than its blades at 28-50 m: the translucency is that sensitive to it.)

// How much brighter the blades read against this model per unit of the sine of the view's
// elevation over them (`far_light::ELEVATION_LIFT` has the measurements): the far levels
// are calibrated on blades seen nearer and steeper than themselves.
const FAR_ELEVATION_LIFT: f32 = 0.35;

// The light of the grass around `p` (on the ground of normal `ground_n`) of mean albedo
// `albedo` (the far albedo: blade colours shaded along the blade at its mean, 0.625): the
// sky's part, and the sun's part for each of the four facings (the billboards' atlas
// gives each of its blades one of them).
struct FarGrassFacings {
    ambient: vec3<f32>,
    sun: array<vec3<f32>, 4>,
}

// The mean shading wave of the blades at the edge of the blades' reach, from the cull's
// two words (the sum of clamp(1.5 |v2 − rest tip| / h, 0, 1) in 1/1024ths and the blades
// counted), times the waves' strength: what `blade_albedos` gives a blade, on average.
fn mean_wave(sum: u32, blades: u32) -> f32 {
    if blades == 0u {
        return 0.0;
    }
    return f32(sum) / (1024.0 * f32(blades)) * light.shading_b.y;
}

// The table of the canopy as drawn (`light.canopy`, `render::light::canopy`): CANOPY_DEPTHS
// depths into the leaf area, each a vector over the shares of quads 0, 1/3, 2/3 and 1.
const CANOPY_DEPTHS: u32 = 32u;

// Where on its blade a distant eye's view ray meets the canopy `depth` into its leaf area
// (0 at the top, 1 at the ground: the share of the canopy's leaf area above the point),
// with a share `quads` of the blades drawn as quads (Eq. 24; `drawn_quad_share`): the mean
// v there of the blades that reach it, each weighed by its drawn width at that height.
// The blades' heights spread evenly from `light.shading_b.w` times the tallest to the
// tallest, so the leaf area falls off above the shortest blade's tip; blades that narrow
// to a point have little of it near their tips, and the eye sees further down them than
// into quads, which keep their width to the tip. The CPU sums it for the field's outlines
// (`render::light::canopy::canopy_table`); here it is interpolated in the square root of
// the depth (the table's spacing) and in the share.
fn drawn_canopy_v(depth: f32, quads: f32) -> f32 {
    let s = sqrt(clamp(depth, 0.0, 1.0)) * f32(CANOPY_DEPTHS - 1u);
    let q = clamp(quads, 0.0, 1.0) * 3.0;
    let s0 = min(u32(s), CANOPY_DEPTHS - 2u);
    // Each share's weight: its hat function at q.
    let w = max(vec4<f32>(1.0) - abs(vec4<f32>(q) - vec4<f32>(0.0, 1.0, 2.0, 3.0)), vec4<f32>(0.0));
    return mix(dot(light.canopy[s0], w), dot(light.canopy[s0 + 1u], w), s - f32(s0));
}

// Eq. 24's share of quads among the blades at `p` whose width runs along `side`
// (`grass.wgsl`'s `blade_point` draws a blade `wp` pixels wide 1 − clamp((wp − w_min) /
// w_span, 0, 1) of the way to a quad), averaged over the field's width quartiles
// (`light.canopy_widths`): in a small frame the far blades are all quads, in a large one
// they keep their outline further out. 0 with the correction off (no span).
fn drawn_quad_share(p: vec3<f32>, side: vec3<f32>) -> f32 {
    // No branch on the uniform (the correction off is a select at the end): lavapipe
    // specialises a shader on a uniform that a branch or a loop's bound reads, and compiled
    // the far gain pass again every frame, its memory growing by 3 MB a frame.
    let span = max(frame.width_correction.y, 1e-6);
    let c = frame.view_proj * vec4<f32>(p, 1.0);
    var share = 0.0;
    for (var k = 0u; k < 2u; k++) {
        let e = frame.view_proj * vec4<f32>(side * (0.5 * light.canopy_widths[k]), 0.0);
        let a = ((c.xy + e.xy) / max(c.w + e.w, 1e-4)) * 0.5 * frame.viewport_time.xy;
        let b = ((c.xy - e.xy) / max(c.w - e.w, 1e-4)) * 0.5 * frame.viewport_time.xy;
        let wp = length(a - b);
        share += 0.5 * (1.0 - clamp((wp - frame.width_correction.x) / span, 0.0, 1.0));
    }
    return select(share, 0.0, frame.width_correction.y <= 0.0);
}

// `wave`: the blades' mean shading wave (`mean_wave`): gusts bend them and they show their
// paler side (`blade_albedo`, linear in the wave, so the mean wave gives the mean albedo).
fn far_grass_facings(p: vec3<f32>, ground_n: vec3<f32>, albedo: vec3<f32>, wave: f32) -> FarGrassFacings {
    let to_eye = normalize(frame.camera_pos.xyz - p);
    let sin_e = max(dot(to_eye, ground_n), 0.02);
    let k = max(0.5 * light.shading_b.z / sin_e, 1e-3);
    let span = 1.0 - exp(-k);
    // The ground's tangent towards the eye (any tangent when looking straight down).
    var t0 = to_eye - ground_n * dot(to_eye, ground_n);
    if dot(t0, t0) < 1e-8 {
        t0 = cross(ground_n, vec3<f32>(0.0, 0.0, 1.0));
    }
    t0 = normalize(t0);
    let t1 = cross(ground_n, t0);
    var out: FarGrassFacings;
    out.ambient = vec3<f32>(0.0);
    for (var j = 0u; j < 4u; j++) {
        out.sun[j] = vec3<f32>(0.0);
    }
    // Each facing's blades: the direction their width runs, and the share of them Eq. 24
    // draws as quads here.
    var sides: array<vec3<f32>, 4>;
    var quads: array<f32, 4>;
    for (var j = 0u; j < 4u; j++) {
        let phi = (f32(j) + 0.5) * 0.7853982;
        sides[j] = normalize(cross(ground_n, cos(phi) * t0 + sin(phi) * t1));
        quads[j] = drawn_quad_share(p, sides[j]);
    }
    for (var q = 0u; q < 2u; q++) {
        let depth = -log(1.0 - (0.25 + 0.5 * f32(q)) * span) / k;
        for (var j = 0u; j < 4u; j++) {
            let v = drawn_canopy_v(depth, quads[j]);
            // The blade's albedo along it (`blade_albedo`: 0.55 at the root to 1.25 at the
            // tip) relative to its value at the mean height the far albedo is taken at.
            let still = albedo * ((0.55 + 0.7 * v) / (0.55 + 0.7 * 0.625));
            let a = mix(still, still * 1.7 + vec3<f32>(0.04, 0.05, 0.02), wave * 0.6);
            // CWD-Sim's Eq. 14 for an unbent blade, where the blades' shading uses it.
            let s = frame.self_shadow;
            let self_shade = clamp(v + s.w, s.x, s.y);
            let phi = (f32(j) + 0.5) * 0.7853982;
            let facing = cos(phi) * t0 + sin(phi) * t1;
            var n = facing;
            if dot(n, to_eye) < 0.0 {
                n = -n;
            }
            // Both halves of the width: the rounded normal turns them apart.
            for (var h = 0u; h < 2u; h++) {
                let u = 0.2 + 0.6 * f32(h);
                let l = blade_light(p, n, sides[j], vec2<f32>(u, v), a, self_shade);
                out.ambient += l.ambient;
                out.sun[j] += l.sun;
            }
        }
    }
    let lift = 1.0 + FAR_ELEVATION_LIFT * sin_e;
    out.ambient *= 0.0625 * lift;
    for (var j = 0u; j < 4u; j++) {
        out.sun[j] *= 0.25 * lift;
    }
    return out;
}

// `far_grass_facings` over every facing: the light of the grass around `p`.
fn far_grass_light(p: vec3<f32>, ground_n: vec3<f32>, albedo: vec3<f32>, wave: f32) -> BladeLight {
    let f = far_grass_facings(p, ground_n, albedo, wave);
    return BladeLight(f.ambient, 0.25 * (f.sun[0] + f.sun[1] + f.sun[2] + f.sun[3]));
}
