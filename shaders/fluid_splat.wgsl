// Wind step, pass 1 (splat): v += Δt · (global force + Σ arrows + downwash) per cell, then
// cells inside an obstacle circle become solid and take the obstacle's velocity (a moving
// collider drags the air with it; a static one holds it still). The CPU twin is
// `FluidCpu::splat` in src/sim/reference/fluid.rs.
//!include fluid_common.wgsl

@group(0) @binding(0) var<uniform> params: FluidParams;
@group(0) @binding(1) var<storage, read> arrows: array<FluidArrow>;
@group(0) @binding(2) var<storage, read> obstacles: array<FluidObstacle>;
@group(0) @binding(3) var<storage, read> vel_in: array<vec2<f32>>;
@group(0) @binding(4) var<storage, read_write> vel_out: array<vec2<f32>>;
// 0 = fluid, k + 1 = inside obstacle k (read by the later passes).
@group(0) @binding(5) var<storage, read_write> solid: array<u32>;

// AGC arrow (CWD-Sim Section 3.5): a band of half-width r around the segment pushed along
// it, with the smooth (1 − (d/r)²)² falloff so that the band has no visible edge.
fn arrow_force(a: FluidArrow, p: vec2<f32>) -> vec2<f32> {
    let s = a.segment.xy;
    let d = a.segment.zw - s;
    let len2 = dot(d, d);
    if len2 <= 0.0 || a.radius <= 0.0 {
        return vec2<f32>(0.0, 0.0);
    }
    let t = clamp(dot(p - s, d) / len2, 0.0, 1.0);
    let off = p - (s + d * t);
    let dist2 = dot(off, off);
    let r2 = a.radius * a.radius;
    if dist2 >= r2 {
        return vec2<f32>(0.0, 0.0);
    }
    let w = 1.0 - dist2 / r2;
    return d * (a.strength * w * w / sqrt(len2));
}

// Radial outflow: grows linearly from 0 at the centre (no direction there) to `strength`
// at r/2, then fades with a smoothstep to 0 at r.
fn downwash_force(p: vec2<f32>) -> vec2<f32> {
    let r = params.global_downwash.z;
    if r <= 0.0 {
        return vec2<f32>(0.0, 0.0);
    }
    let off = p - params.downwash_pos.xy;
    let dist = sqrt(dot(off, off));
    if dist <= 0.0 || dist >= r {
        return vec2<f32>(0.0, 0.0);
    }
    let half_r = 0.5 * r;
    var profile = dist / half_r;
    if dist > half_r {
        let t = (dist - half_r) / half_r;
        profile = 1.0 - t * t * (3.0 - 2.0 * t);
    }
    return off * (params.global_downwash.w * profile / dist);
}

@compute @workgroup_size(8, 8)
fn main(@builtin(global_invocation_id) gid: vec3<u32>) {
    let n = params.resolution;
    if gid.x >= n || gid.y >= n {
        return;
    }
    let idx = gid.y * n + gid.x;
    let h = params.origin_cell.z;
    let p = params.origin_cell.xy + (vec2<f32>(gid.xy) + 0.5) * h;
    var force = params.global_downwash.xy;
    for (var a = 0u; a < params.arrow_count; a++) {
        force += arrow_force(arrows[a], p);
    }
    force += downwash_force(p);
    var v = vel_in[idx] + force * params.dt;
    var s = 0u;
    for (var o = 0u; o < params.obstacle_count; o++) {
        let ob = obstacles[o];
        let off = p - ob.circle.xy;
        if dot(off, off) < ob.circle.z * ob.circle.z {
            s = o + 1u;
            v = ob.velocity.xy;
            break;
        }
    }
    vel_out[idx] = v;
    solid[idx] = s;
}
