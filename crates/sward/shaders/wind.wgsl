// The analytic wind of Jahrmann & Wimmer (Section 5.1); the twin of
// `reference::analytic_wind`. Included by update.wgsl after common.wgsl.

fn analytic_wind(p: vec3<f32>, time: f32, params: SimParams) -> vec3<f32> {
    var w = vec3<f32>(0.0);
    let dir = params.wind_dir;
    if dir.z != 0.0 {
        let d = dir.xy;
        let k = TAU / params.wind_wave.x;
        let phase = (p.x * d.x + p.z * d.y - time * params.wind_wave.y) * k;
        let along = 1.0 + dir.w * (0.6 * sin(phase) + 0.4 * sin(2.7 * phase + 0.31 * p.x - 0.17 * p.z));
        let across = 0.25 * dir.w * cos(0.5 * phase + 0.23 * (p.x + p.z));
        let side = vec2<f32>(-d.y, d.x);
        let f = (d * along + side * across) * dir.z;
        w += vec3<f32>(f.x, 0.0, f.y);
    }
    let source = params.point_wind;
    if source.w != 0.0 {
        let offset = vec3<f32>(p.x - source.x, 0.0, p.z - source.z);
        let dist = length(offset);
        let radius = params.point_wind_shape.x;
        if dist > 1e-4 && dist < radius {
            let falloff = (1.0 - dist / radius) * (1.0 - dist / radius);
            let pulse = 0.6 + 0.4 * sin(TAU * params.point_wind_shape.y * time - 1.5 * dist);
            w += offset / dist * (source.w * falloff * pulse);
        }
    }
    return w;
}
