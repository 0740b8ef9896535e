// Wind step, pass 1 (self-advection, CWD-Sim Eq. 9–10, Stam's `advect` on the staggered
// grid): every face value is carried from where the flow brings it, each component traced
// back from its own face position with a midpoint (RK2) step through `vel` and sampled
// trilinearly on its own lattice (bilinearly on a 2D grid); the result is divided by (1 + dissipation · Δt).
//
// `advect` is the semi-Lagrangian step. MacCormack (Selle et al. 2008) runs `forward`
// (the same trace, undamped) into `hat`, `backward` (traced forwards in time through the
// same `vel`) from `hat` into `tilde`, then `correct`: q̂ + (q − q̃) / 2, the estimate of the
// semi-Lagrangian step's error removed, clamped to the values the forward trace
// interpolated between (so it cannot create new extremes), then damped. Walls (closed borders, the ground, the top) stay 0.
// CPU twin: `FluidCpu::advect`.
//!include fluid_common.wgsl

@group(0) @binding(0) var<uniform> params: FluidParams;
// The velocity that carries (the step's starting field).
@group(0) @binding(1) var<storage, read> vel: array<f32>;
// The field being carried.
@group(0) @binding(2) var<storage, read> q: array<f32>;
@group(0) @binding(3) var<storage, read_write> out: array<f32>;
@group(0) @binding(4) var<storage, read> hat: array<f32>;
@group(0) @binding(5) var<storage, read> tilde: array<f32>;

fn dims() -> vec2<i32> {
    return vec2<i32>(i32(params.resolution), i32(params.layers));
}

fn sample_field_vel(axis: u32, pos: vec3<f32>) -> f32 {
    let d = dims();
    let s = fluid_stencil(axis, pos, d.x, d.y, params.boundary);
    let lo = vec4<f32>(vel[s.lower.x], vel[s.lower.y], vel[s.lower.z], vel[s.lower.w]);
    let hi = vec4<f32>(vel[s.upper.x], vel[s.upper.y], vel[s.upper.z], vel[s.upper.w]);
    return fluid_blend3(lo, hi, s.f);
}

fn velocity_at(pos: vec3<f32>) -> vec3<f32> {
    return vec3<f32>(sample_field_vel(0u, pos), sample_field_vel(1u, pos), sample_field_vel(2u, pos));
}

// Midpoint trace from `start` over `cells` = ±Δt / (h, h, dy) (negative: back in time).
fn trace(start: vec3<f32>, cells: vec3<f32>) -> vec3<f32> {
    let d = dims();
    let mid = fluid_clamp_pos(start + velocity_at(start) * (0.5 * cells), d.x, d.y, params.boundary);
    return fluid_clamp_pos(start + velocity_at(mid) * cells, d.x, d.y, params.boundary);
}

// The stencil the trace from a face lands in, and whether the face is a wall (which keeps
// 0 whatever the trace says).
struct Traced {
    stencil: FluidStencil,
    wall: bool,
}

fn traced(face: FluidFace, sign: f32) -> Traced {
    let d = dims();
    let f = fluid_canonical(face, d.x, params.boundary);
    let wall = fluid_is_wall(face.axis, face.i, face.j, face.k, d.x, d.y, params.boundary);
    let cells = vec3<f32>(params.origin_cell.w, params.origin_cell.w, params.layer.y) * (sign * params.dt);
    let pos = trace(fluid_face_pos(f.axis, f.i, f.j, f.k), cells);
    return Traced(fluid_stencil(f.axis, pos, d.x, d.y, params.boundary), wall);
}

fn lower_q(s: FluidStencil) -> vec4<f32> {
    return vec4<f32>(q[s.lower.x], q[s.lower.y], q[s.lower.z], q[s.lower.w]);
}

fn upper_q(s: FluidStencil) -> vec4<f32> {
    return vec4<f32>(q[s.upper.x], q[s.upper.y], q[s.upper.z], q[s.upper.w]);
}

fn sample_q(s: FluidStencil) -> f32 {
    return fluid_blend3(lower_q(s), upper_q(s), s.f);
}

fn damping() -> f32 {
    return 1.0 + params.dissipation * params.dt;
}

fn face_of(gid: vec3<u32>) -> FluidFace {
    return fluid_face(gid, params.resolution, params.layers);
}

fn out_index(face: FluidFace) -> u32 {
    let d = dims();
    return fluid_face_index(face.axis, face.i, face.j, face.k, d.x, d.y);
}

@compute @workgroup_size(8, 8)
fn advect(@builtin(global_invocation_id) gid: vec3<u32>) {
    let face = face_of(gid);
    if !face.valid {
        return;
    }
    let t = traced(face, -1.0);
    out[out_index(face)] = select(sample_q(t.stencil) / damping(), 0.0, t.wall);
}

@compute @workgroup_size(8, 8)
fn forward(@builtin(global_invocation_id) gid: vec3<u32>) {
    let face = face_of(gid);
    if !face.valid {
        return;
    }
    let t = traced(face, -1.0);
    out[out_index(face)] = select(sample_q(t.stencil), 0.0, t.wall);
}

@compute @workgroup_size(8, 8)
fn backward(@builtin(global_invocation_id) gid: vec3<u32>) {
    let face = face_of(gid);
    if !face.valid {
        return;
    }
    let t = traced(face, 1.0);
    out[out_index(face)] = select(sample_q(t.stencil), 0.0, t.wall);
}

@compute @workgroup_size(8, 8)
fn correct(@builtin(global_invocation_id) gid: vec3<u32>) {
    let face = face_of(gid);
    if !face.valid {
        return;
    }
    let idx = out_index(face);
    let t = traced(face, -1.0);
    if t.wall {
        out[idx] = 0.0;
        return;
    }
    let a = lower_q(t.stencil);
    let b = upper_q(t.stencil);
    let lo = min(min(min(a.x, a.y), min(a.z, a.w)), min(min(b.x, b.y), min(b.z, b.w)));
    let hi = max(max(max(a.x, a.y), max(a.z, a.w)), max(max(b.x, b.y), max(b.z, b.w)));
    let v = hat[idx] + 0.5 * (q[idx] - tilde[idx]);
    out[idx] = clamp(v, lo, hi) / damping();
}
