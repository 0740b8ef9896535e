// The blades' light (issue 16's shading terms), included after common.wgsl and light.wgsl
// by every pass that lights grass: the forward and deferred grass (`shade_blade`), and the
// levels that stand for blades far away (`far_grass.wgsl`: the billboards and the far
// ground), so that all of them light the grass with the same terms.

// The light a blade's point sends to the eye (before the fog), in two parts: what the sky
// gives (`ambient`) and what the sun gives when nothing shadows the point (`sun`); the
// point's colour is `ambient + lit * sun` for a sun visibility `lit`.
struct BladeLight {
    ambient: vec3<f32>,
    sun: vec3<f32>,
}

// The light a blade's point at `world` sends to the eye (before the fog): `flat_n` its
// normal turned to the viewer, `side` its width direction, (u, v) where it lies on the
// blade, `albedo` its colour there, `self_shade` CWD-Sim's Eq. 14 there, the sun fully
// visible (the sun's part scales with its visibility).
fn blade_light(world: vec3<f32>, flat_n: vec3<f32>, side: vec3<f32>, uv: vec2<f32>, albedo: vec3<f32>, self_shade: f32) -> BladeLight {
    let sun = frame.sun_dir.xyz;
    let to_eye = normalize(frame.camera_pos.xyz - world);
    let terms_a = light.shading_a;
    let terms_b = light.shading_b;
    let v = uv.y;
    // The rounded normal (Ghost of Tsushima): bent along the width direction, outwards at
    // both edges, so that a flat blade reads as curved.
    let n = normalize(flat_n + side * (uv.x - 0.5) * 1.2 * terms_a.x);
    // Ambient occlusion: light through the canopy falls off with the leaf area above the
    // point (Beer-Lambert, terms_b.z m² of leaf per m² of ground), so the root is dark and
    // a dense field darker. CWD-Sim's Eq. 14 replaces it where chosen; `Off` drops it.
    var ao = mix(1.0, max(exp(-0.35 * terms_b.z * (1.0 - v)), 0.12), terms_a.w);
    let shadow_mode = u32(frame.debug.y);
    if shadow_mode == 1u {
        ao = self_shade;
    } else if shadow_mode == 2u {
        ao = 1.0;
    }
    let sun_rgb = light.sun.rgb;
    let diffuse = max(dot(n, sun), 0.0);
    // Translucency: sunlight shining through the blade towards the viewer.
    let behind = max(dot(-flat_n, sun), 0.0);
    let through = behind * pow(max(dot(-to_eye, sun), 0.0), 2.0);
    let trans = (through * 0.9 + behind * 0.25) * terms_a.y;
    // Specular: the waxy blade's highlight, on the rounded normal.
    let h = normalize(sun + to_eye);
    // x^12 by squaring: a software rasteriser's pow is a logarithm and an exponential.
    let s1 = max(dot(n, h), 0.0);
    let s4 = (s1 * s1) * (s1 * s1);
    let spec = s4 * s4 * s4 * 0.22 * mix(0.3, 1.0, v) * terms_a.z;
    return BladeLight(
        albedo * light.ambient.rgb * 0.9 * ao,
        albedo * sun_rgb * (diffuse * 1.6 * mix(0.55, 1.0, ao))
            + albedo * vec3<f32>(1.0, 1.1, 0.4) * sun_rgb * trans * 1.4 * ao
            + sun_rgb * spec,
    );
}

// `blade_light` under a sun of visibility `lit` (1 lit, 0 in shadow). The forward fragment
// stage and the deferred shading both light here.
fn shade_blade(world: vec3<f32>, flat_n: vec3<f32>, side: vec3<f32>, uv: vec2<f32>, albedo: vec3<f32>, lit: f32, self_shade: f32) -> vec3<f32> {
    let l = blade_light(world, flat_n, side, uv, albedo, self_shade);
    return l.ambient + lit * l.sun;
}
