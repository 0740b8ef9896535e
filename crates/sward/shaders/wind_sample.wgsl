// The wind a blade (or a billboard) feels at a point: the analytic functions and/or the
// fluid grid, as the scene chooses. Expects `params: SimParams` and
// `wind_grid: array<vec2<f32>>` bound by the including shader; shared by `update.wgsl` and
// `billboard.wgsl`, so billboards sway with the same wind the blades read.

const WIND_ANALYTIC: u32 = 1u;
const WIND_FLUID: u32 = 2u;

// The sources a pipeline is built for (`sim::update::UpdatePass`: the scene's), a mask of
// the two above: a source outside it is compiled out. llvmpipe runs the body of a uniform
// test for every blade whether it passes or not, so the fluid grid's two layers of four
// reads each cost a scene with only the analytic wind about a tenth of its update. The
// uniform's mask still chooses among the sources built in.
override WIND_KINDS: u32 = 3u;

fn wind_grid_at(i: i32, j: i32, k: i32, n: i32) -> vec2<f32> {
    return wind_grid[(k * n + clamp(j, 0, n - 1)) * n + clamp(i, 0, n - 1)];
}

// Bilinear between the cell centres of layer k (clamped at the edges), or with per-cell
// grouping the value of the cell the point lies in (CWD-Sim Eq. 1).
fn fluid_layer_velocity(g: vec2<f32>, k: i32, n: i32) -> vec2<f32> {
    if params.fluid_info.z != 0u {
        let c = vec2<i32>(floor(g));
        return wind_grid_at(c.x, c.y, k, n);
    }
    let q = clamp(g - 0.5, vec2<f32>(0.0), vec2<f32>(f32(n - 1)));
    let c = vec2<i32>(floor(q));
    let f = q - vec2<f32>(c);
    let a = mix(wind_grid_at(c.x, c.y, k, n), wind_grid_at(c.x + 1, c.y, k, n), f.x);
    let b = mix(wind_grid_at(c.x, c.y + 1, k, n), wind_grid_at(c.x + 1, c.y + 1, k, n), f.x);
    return mix(a, b, f.y);
}

// Air velocity at a world position `height` metres above the ground: in a 3D grid linear
// between the centres of the two layers around that height (clamped to the lowest and the
// highest; per cell: the layer it lies in). The twin of `reference::sample_grid`.
fn fluid_velocity(p: vec3<f32>, height: f32) -> vec2<f32> {
    let n = i32(params.fluid_info.x);
    let layers = i32(max(params.fluid_info.w, 1u));
    let g = (p.xz - params.fluid_grid.xy) / params.fluid_grid.z;
    if layers == 1 {
        return fluid_layer_velocity(g, 0, n);
    }
    let y = height / params.fluid_layer_height;
    if params.fluid_info.z != 0u {
        return fluid_layer_velocity(g, clamp(i32(floor(y)), 0, layers - 1), n);
    }
    let q = clamp(y - 0.5, 0.0, f32(layers - 1));
    let k = min(i32(floor(q)), layers - 2);
    let t = q - f32(k);
    return mix(fluid_layer_velocity(g, k, n), fluid_layer_velocity(g, k + 1, n), t);
}

// w_i: the analytic functions at p and/or the fluid grid at p, `height` metres above the
// ground (the blade's or the card's height), as the scene chooses.
fn wind_at(p: vec3<f32>, height: f32) -> vec3<f32> {
    var w = vec3<f32>(0.0);
    if (WIND_KINDS & WIND_ANALYTIC) != 0u {
        if (params.fluid_info.y & WIND_ANALYTIC) != 0u {
            w += analytic_wind(p, params.time, params);
        }
    }
    if (WIND_KINDS & WIND_FLUID) != 0u {
        if (params.fluid_info.y & WIND_FLUID) != 0u {
            let v = fluid_velocity(p, height) * params.fluid_grid.w;
            w += vec3<f32>(v.x, 0.0, v.y);
        }
    }
    return w;
}
