// The octahedral map of the unit sphere onto [0, 1]², both ways (the deferred light's sky
// table, `grass_deferred.wgsl`; its probe, `octahedral_probe.wgsl`). No bindings.

// The octahedral map of the sphere onto [0, 1]² (the upper hemisphere inside the diamond
// |x| + |y| ≤ 1/2 around the centre, the lower folded into the corners): cheap both ways
// and without a seam at the horizon, where the fog looks.
fn octahedral_uv(d: vec3<f32>) -> vec2<f32> {
    let p = d / (abs(d.x) + abs(d.y) + abs(d.z));
    var xz = p.xz;
    if p.y < 0.0 {
        xz = (1.0 - abs(p.zx)) * select(vec2<f32>(-1.0), vec2<f32>(1.0), p.xz >= vec2<f32>(0.0));
    }
    return xz * 0.5 + 0.5;
}

// The unit direction at `uv` of the octahedral map (twin: `deferred::octahedral_direction`).
fn octahedral_direction(uv: vec2<f32>) -> vec3<f32> {
    let f = uv * 2.0 - 1.0;
    var d = vec3<f32>(f.x, 1.0 - abs(f.x) - abs(f.y), f.y);
    let t = max(-d.y, 0.0);
    d.x += select(t, -t, d.x >= 0.0);
    d.z += select(t, -t, d.z >= 0.0);
    return normalize(d);
}
