// The terrain's height function: the GPU twin of `HeightField::height` / `normal`
// (src/field/terrain.rs, src/field/noise.rs). Included by the terrain draw and by the
// probe kernel that tests it against the CPU. Binds group 0, bindings 1 (parameters) and
// 2 (the height grid of a Png terrain; a dummy otherwise).
//!include common.wgsl

struct TerrainParams {
    // The camera's view-projection for positions relative to the eye.
    view_proj_relative: mat4x4<f32>,
    // x: mode (0 analytic fBm, 1 grid), y: octaves, z: 1 = unbounded, w: clipmap levels.
    info: vec4<u32>,
    // x: wavelength m, y: mid, z: scale m, w: terrain size m.
    noise: vec4<f32>,
    // The 32-bit lattice seed of each octave (up to 12).
    seeds: array<vec4<u32>, 3>,
    // x: grid resolution, y: cells per ring side, z: morph band in cells, w: 1 = blades
    // grow past the square (a streamed field on an unbounded terrain).
    grid: vec4<u32>,
    // x: soil-to-grass blend start m, y: blend end m, z: 1 = density map bound, w: the
    // camera's far plane m.
    blend: vec4<f32>,
    // rgb: the grass's mean albedo (see `clipmap::FAR_GRASS_ALBEDO`), w: the tallest blade
    // (m; the canopy's sharpness, terrain.wgsl).
    grass_albedo: vec4<f32>,
    // Per level: xy the level's centre (world x, z), z its cell size m, w: unused.
    levels: array<vec4<f32>, 16>,
}

// Read-only storage, not a uniform: lavapipe (Mesa 22.3) would recompile the terrain
// draw with this uniform inlined at every draw and keep every copy (see grass.wgsl).
@group(0) @binding(1) var<storage, read> terrain: TerrainParams;
@group(0) @binding(2) var<storage, read> terrain_grid: array<f32>;

// The value in [-1, 1] at a lattice point: the twin of `noise::lattice`.
fn lattice(seed: u32, ix: i32, iz: i32) -> f32 {
    let h = hash32(seed ^ hash32(bitcast<u32>(ix) ^ rotl17(hash32(bitcast<u32>(iz)))));
    return f32(h >> 8u) * (2.0 / 16777216.0) - 1.0;
}

fn fade(t: vec2<f32>) -> vec2<f32> {
    return t * t * t * (t * (t * 6.0 - 15.0) + 10.0);
}

fn fade_derivative(t: vec2<f32>) -> vec2<f32> {
    return 30.0 * t * t * (t - 1.0) * (t - 1.0);
}

// Value noise and its gradient: x value, yz d/dx, d/dz.
fn value_noise_grad(seed: u32, p: vec2<f32>) -> vec3<f32> {
    let p0 = floor(p);
    let i = vec2<i32>(p0);
    let f = p - p0;
    let t = fade(f);
    let a = lattice(seed, i.x, i.y);
    let b = lattice(seed, i.x + 1, i.y);
    let c = lattice(seed, i.x, i.y + 1);
    let d = lattice(seed, i.x + 1, i.y + 1);
    let top = a + (b - a) * t.x;
    let bottom = c + (d - c) * t.x;
    let df = fade_derivative(f);
    return vec3<f32>(
        top + (bottom - top) * t.y,
        ((b - a) + (a - b - c + d) * t.y) * df.x,
        (bottom - top) * df.y,
    );
}

// Twin of `noise::fbm_grad`, rescaled like `NoiseSurface::eval`: height and gradient.
fn fbm_height(xz: vec2<f32>) -> vec3<f32> {
    let octaves = min(terrain.info.y, 12u);
    var sum = vec3<f32>(0.0);
    var weight = 0.0;
    var amplitude = 1.0;
    var frequency = 1.0 / terrain.noise.x;
    for (var o = 0u; o < octaves; o += 1u) {
        let offset = f32(o) * 0.61803398875 + 0.25;
        let seed = terrain.seeds[o / 4u][o % 4u];
        let n = value_noise_grad(seed, xz * frequency + vec2<f32>(offset, -offset));
        sum += amplitude * vec3<f32>(n.x, n.yz * frequency);
        weight += amplitude;
        amplitude *= 0.5;
        frequency *= 2.0;
    }
    if weight <= 0.0 || terrain.noise.z == 0.0 {
        return vec3<f32>(0.0);
    }
    let s = sum / weight;
    return vec3<f32>((s.x - terrain.noise.y) * terrain.noise.z, s.yz * terrain.noise.z);
}

fn grid_at(i: u32, j: u32) -> f32 {
    return terrain_grid[j * terrain.grid.x + i];
}

// Twin of the grid path of `HeightField::height` (bilinear, edge heights continue) and its
// normal (central differences one spacing apart, one-sided at the edge).
fn grid_value(xz: vec2<f32>) -> f32 {
    let n = terrain.grid.x;
    let last = f32(n - 1u);
    let g = clamp((xz / terrain.noise.w + 0.5) * last, vec2<f32>(0.0), vec2<f32>(last));
    let i0 = min(u32(floor(g.x)), n - 1u);
    let j0 = min(u32(floor(g.y)), n - 1u);
    let i1 = min(i0 + 1u, n - 1u);
    let j1 = min(j0 + 1u, n - 1u);
    let t = g - vec2<f32>(f32(i0), f32(j0));
    let top = mix(grid_at(i0, j0), grid_at(i1, j0), t.x);
    let bottom = mix(grid_at(i0, j1), grid_at(i1, j1), t.x);
    return top + (bottom - top) * t.y;
}

fn grid_height(xz: vec2<f32>) -> vec3<f32> {
    let d = terrain.noise.w / f32(max(terrain.grid.x, 2u) - 1u);
    let half = 0.5 * terrain.noise.w;
    let lo = max(xz - d, vec2<f32>(-half));
    let hi = min(xz + d, vec2<f32>(half));
    var g = vec2<f32>(0.0);
    if hi.x > lo.x {
        g.x = (grid_value(vec2<f32>(hi.x, xz.y)) - grid_value(vec2<f32>(lo.x, xz.y))) / (hi.x - lo.x);
    }
    if hi.y > lo.y {
        g.y = (grid_value(vec2<f32>(xz.x, hi.y)) - grid_value(vec2<f32>(xz.x, lo.y))) / (hi.y - lo.y);
    }
    return vec3<f32>(grid_value(xz), g);
}

// Height and gradient (d/dx, d/dz) of the ground at world (x, z): what the CPU's
// `HeightField::height` and `normal` give there.
fn terrain_height(xz: vec2<f32>) -> vec3<f32> {
    if terrain.info.x == 1u {
        return grid_height(xz);
    }
    if terrain.info.z == 0u {
        let half = 0.5 * terrain.noise.w;
        let c = clamp(xz, vec2<f32>(-half), vec2<f32>(half));
        var h = fbm_height(c);
        // Bounded: level past the edge, like the CPU.
        if abs(c.x) >= half {
            h.y = 0.0;
        }
        if abs(c.y) >= half {
            h.z = 0.0;
        }
        return h;
    }
    return fbm_height(xz);
}
