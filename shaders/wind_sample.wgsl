// The wind a blade (or a billboard) feels at a point: the analytic functions and/or the
// fluid grid, as the scene chooses. Expects `params: SimParams` and
// `wind_grid: array<vec2<f32>>` bound by the including shader; shared by `update.wgsl` and
// `billboard.wgsl`, so billboards sway with the same wind the blades read.

const WIND_ANALYTIC: u32 = 1u;
const WIND_FLUID: u32 = 2u;

fn wind_grid_at(i: i32, j: i32, n: i32) -> vec2<f32> {
    return wind_grid[clamp(j, 0, n - 1) * n + clamp(i, 0, n - 1)];
}

// Air velocity at a world position: bilinear between cell centres (clamped at the edges),
// or with per-cell grouping the value of the cell the point lies in (CWD-Sim Eq. 1).
// The twin of `reference::sample_grid`.
fn fluid_velocity(p: vec3<f32>) -> vec2<f32> {
    let n = i32(params.fluid_info.x);
    let g = (p.xz - params.fluid_grid.xy) / params.fluid_grid.z;
    if params.fluid_info.z != 0u {
        let c = vec2<i32>(floor(g));
        return wind_grid_at(c.x, c.y, n);
    }
    let q = clamp(g - 0.5, vec2<f32>(0.0), vec2<f32>(f32(n - 1)));
    let c = vec2<i32>(floor(q));
    let f = q - vec2<f32>(c);
    let a = mix(wind_grid_at(c.x, c.y, n), wind_grid_at(c.x + 1, c.y, n), f.x);
    let b = mix(wind_grid_at(c.x, c.y + 1, n), wind_grid_at(c.x + 1, c.y + 1, n), f.x);
    return mix(a, b, f.y);
}

// w_i(v0): the analytic functions and/or the fluid grid, as the scene chooses.
fn wind_at(p: vec3<f32>) -> vec3<f32> {
    var w = vec3<f32>(0.0);
    if (params.fluid_info.y & WIND_ANALYTIC) != 0u {
        w += analytic_wind(p, params.time, params);
    }
    if (params.fluid_info.y & WIND_FLUID) != 0u {
        let v = fluid_velocity(p) * params.fluid_grid.w;
        w += vec3<f32>(v.x, 0.0, v.y);
    }
    return w;
}
