// The sway and bending of a billboard's top: shared by the draw (`billboard.wgsl`) and the
// probe that tests it against the CPU twin (`billboard::top_offset`). Expects `bb`,
// `spheres`, the wind (`wind_sample.wgsl`) and the trail map (`trails.wgsl`).

// How far the top of a card of height `h` rooted at `root` moves: the wind's push (the
// same field the blades feel, scaled by the sway gain), then away from each sphere near
// it and down (Qiu's billboard bending) and along a trail pressed there; at most 0.9 h.
fn top_offset(root: vec3<f32>, h: f32) -> vec3<f32> {
    let top = root + vec3<f32>(0.0, h, 0.0);
    let w = wind_at(top, h);
    var off = vec3<f32>(w.x, 0.0, w.z) * bb.shape.x * h;
    for (var s = 0u; s < bb.info.w; s++) {
        let sphere = spheres[s];
        let reach = sphere.w + h * bb.shape.y;
        let d = top.xz - sphere.xz;
        let dist = length(d);
        if dist < reach && abs(top.y - sphere.y) < sphere.w + h {
            let away = select(vec2<f32>(1.0, 0.0), d / max(dist, 1e-4), dist > 1e-4);
            let push = reach - dist;
            off += vec3<f32>(away.x * push, -0.5 * push, away.y * push);
        }
    }
    // A trail under the card (`trail_at`): its top goes the way the trail's blades were
    // bent and down by half its height, as far as the trail still cripples them (eta up
    // to 1: crippled blades lie where they were pushed).
    let trail = trail_at(root.x, root.z);
    if trail.x > 0.0 {
        let k = min(trail.x, 1.0);
        off += vec3<f32>(trail.y, -0.5, trail.z) * (k * h);
    }
    let len = length(off);
    if len > 0.9 * h {
        off *= 0.9 * h / len;
    }
    return off;
}

