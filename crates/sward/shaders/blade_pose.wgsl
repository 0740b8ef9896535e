// The blade's validated shape (Jahrmann & Wimmer Eq. 9-13) and its rest pose: shared by
// the update (`update.wgsl`) and the tile generation (`tile_gen.wgsl`).

// Eq. 9-13: v2 above the local ground plane, v1 from v2, curve length = height.
fn validate(v0: vec3<f32>, v2_in: vec3<f32>, up: vec3<f32>, height: f32) -> array<vec3<f32>, 2> {
    let v2 = v2_in - up * min(dot(up, v2_in - v0), 0.0);
    let rel = v2 - v0;
    let l_proj = length(rel - up * dot(rel, up));
    let v1 = v0 + up * height * max(1.0 - l_proj / height, 0.05 * max(l_proj / height, 1.0));
    let l0 = length(v2 - v0);
    let l1 = length(v1 - v0) + length(v2 - v1);
    let len = (2.0 * l0 + l1) / 3.0;
    let r = height / len;
    let v1c = v0 + r * (v1 - v0);
    let v2c = v1c + r * (v2 - v1);
    return array<vec3<f32>, 2>(v1c, v2c);
}

// Eq. 12 with n = 2: the length of the curve through v0, v1, v2.
fn curve_length(v0: vec3<f32>, v1: vec3<f32>, v2: vec3<f32>) -> f32 {
    let l0 = length(v2 - v0);
    let l1 = length(v1 - v0) + length(v2 - v1);
    return (2.0 * l0 + l1) / 3.0;
}

// The rest pose of a blade leaning `bend` radians towards its front: the tip on that
// direction where the validated curve length equals the height (bisection on [0, h]), so
// the rest pose is a fixed point of the validation. The twin of `reference::rest_pose`.
fn rest_pose(v0: vec3<f32>, up: vec3<f32>, front: vec3<f32>, height: f32, bend: f32) -> array<vec3<f32>, 2> {
    let dir = up * cos(bend) + front * sin(bend);
    var lo = 0.0;
    var hi = height;
    for (var k = 0u; k < 40u; k++) {
        let mid = 0.5 * (lo + hi);
        let v2 = v0 + dir * mid;
        let rel = v2 - v0;
        let l_proj = length(rel - up * dot(rel, up));
        let v1 = v0 + up * height * max(1.0 - l_proj / height, 0.05 * max(l_proj / height, 1.0));
        if curve_length(v0, v1, v2) < height {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    return validate(v0, v0 + dir * (0.5 * (lo + hi)), up, height);
}
