// CWD-Sim's grass deformation (Choi & Sung 2024, §3.3, Eq. 11-13), shared by the pose pass
// (`update_cwd.wgsl`) and the grass vertex shader (`grass.wgsl`), which bends every vertex
// with it. Expects `params: SimParams` and the wind sampling of `wind_sample.wgsl`. The
// twin is `sim::cwd`.
//
// Heights are in blade heights (the paper's model units): a vertex at v (0 root, 1 tip) of
// the straight rest blade has Py = v. Eq. 11 bends it under gravity:
//   P' = (Px, Py - k1 Py², Pz + k2 Py²)            (z: the blade's front)
// Eq. 12 turns the wind V of the blade's cell into a translation growing with P'y²:
//   T = F (Vx P'y², -|V| P'y², Vz P'y²)
// Eq. 13 as printed, P'' = M((1 - λ) T + λ P'), would shrink a windless blade to λ of its
// height; sward reads it as P'' = M(P' + (1 - λ) T): λ = 1 is rigid, λ = 0 gives the wind
// its full translation. A vertex never goes below the root's ground plane (the paper's
// equations can push it there in a strong wind).

struct CwdPoint {
    p: vec3<f32>,
    // d p / d v: the blade's tangent, unnormalised.
    t: vec3<f32>,
}

// The point where the wind of a Cwd blade rooted at `v0` is read: the centre of its cell
// (the fluid grid's cells when the fluid is on, else cells of `model.z` metres from the
// origin), so that every blade of a cell shares one force, as in the paper.
fn cwd_sample_point(v0: vec3<f32>) -> vec3<f32> {
    var origin = vec2<f32>(0.0);
    var size = params.model.z;
    if (params.fluid_info.y & WIND_FLUID) != 0u {
        origin = params.fluid_grid.xy;
        size = params.fluid_grid.z;
    }
    let cell = floor((v0.xz - origin) / size);
    let c = origin + (cell + 0.5) * size;
    return vec3<f32>(c.x, v0.y, c.y);
}

// The wind a Cwd blade feels (Eq. 12's V): the wind at its cell's centre.
fn cwd_wind(v0: vec3<f32>, height: f32) -> vec3<f32> {
    return wind_at(cwd_sample_point(v0), height);
}

// The point at v along a Cwd blade rooted at v0 (up, front: its frame) in the wind `wind`.
fn cwd_point(v0: vec3<f32>, up: vec3<f32>, front: vec3<f32>, height: f32, wind: vec3<f32>, v: f32) -> CwdPoint {
    let k1 = params.cwd.x;
    let k2 = params.cwd.y;
    let s = (1.0 - params.cwd.z) * params.cwd.w;
    let w = wind - up * dot(wind, up);
    let speed = length(w);
    // Eq. 11.
    let q = v - k1 * v * v;
    let dq = 1.0 - 2.0 * k1 * v;
    let z = k2 * v * v;
    let dz = 2.0 * k2 * v;
    // Eq. 12-13: the height sinks by (1 - λ) F |V| P'y², the point moves with the wind.
    var y = q - s * speed * q * q;
    var dy = dq - 2.0 * s * speed * q * dq;
    if y < 0.0 {
        y = 0.0;
        dy = 0.0;
    }
    let p = v0 + height * (up * y + front * z + w * (s * q * q));
    let t = height * (up * dy + front * dz + w * (2.0 * s * q * dq));
    return CwdPoint(p, t);
}
