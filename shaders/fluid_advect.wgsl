// Wind step, pass 1 (self-advection, CWD-Sim Eq. 9–10, Stam's `advect` on the staggered
// grid): every face value is carried from where the flow brings it, each component traced
// back from its own face position with a midpoint (RK2) step through `vel` and sampled
// bilinearly on its own lattice; the result is divided by (1 + dissipation · Δt).
//
// `advect` is the semi-Lagrangian step. MacCormack (Selle et al. 2008) runs `forward`
// (the same trace, undamped) into `hat`, `backward` (traced forwards in time through the
// same `vel`) from `hat` into `tilde`, then `correct`: q̂ + (q − q̃) / 2, the estimate of the
// semi-Lagrangian step's error removed, clamped to the four values the forward trace
// interpolated between (so it cannot create new extremes), then damped. Closed walls stay 0.
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

fn sample_vel(axis: u32, pos: vec2<f32>) -> f32 {
    let s = fluid_stencil(axis, pos, i32(params.resolution), params.boundary);
    return fluid_blend(vel[s.index.x], vel[s.index.y], vel[s.index.z], vel[s.index.w], s.f);
}

fn velocity_at(pos: vec2<f32>) -> vec2<f32> {
    return vec2<f32>(sample_vel(0u, pos), sample_vel(1u, pos));
}

// Midpoint trace from `start` over `cells` = ±Δt / h (negative: back in time).
fn trace(start: vec2<f32>, cells: f32) -> vec2<f32> {
    let n = i32(params.resolution);
    let mid = fluid_clamp_pos(start + velocity_at(start) * (0.5 * cells), n, params.boundary);
    return fluid_clamp_pos(start + velocity_at(mid) * cells, n, params.boundary);
}

// The stencil the trace from a face lands in, and whether the face is a closed wall (which
// keeps 0 whatever the trace says).
struct Traced {
    stencil: FluidStencil,
    wall: bool,
}

fn traced(face: FluidFace, cells: f32) -> Traced {
    let n = i32(params.resolution);
    let f = fluid_canonical(face, n, params.boundary);
    let wall = fluid_is_wall(face.axis, face.i, face.j, n, params.boundary);
    let pos = trace(fluid_face_pos(f.axis, f.i, f.j), cells);
    return Traced(fluid_stencil(f.axis, pos, n, params.boundary), wall);
}

fn sample_q(s: FluidStencil) -> f32 {
    return fluid_blend(q[s.index.x], q[s.index.y], q[s.index.z], q[s.index.w], s.f);
}

fn damping() -> f32 {
    return 1.0 + params.dissipation * params.dt;
}

@compute @workgroup_size(8, 8)
fn advect(@builtin(global_invocation_id) gid: vec3<u32>) {
    let face = fluid_face(gid, params.resolution);
    if !face.valid {
        return;
    }
    let n = i32(params.resolution);
    let t = traced(face, -params.dt * params.origin_cell.w);
    let idx = fluid_face_index(face.axis, face.i, face.j, n);
    out[idx] = select(sample_q(t.stencil) / damping(), 0.0, t.wall);
}

@compute @workgroup_size(8, 8)
fn forward(@builtin(global_invocation_id) gid: vec3<u32>) {
    let face = fluid_face(gid, params.resolution);
    if !face.valid {
        return;
    }
    let n = i32(params.resolution);
    let t = traced(face, -params.dt * params.origin_cell.w);
    let idx = fluid_face_index(face.axis, face.i, face.j, n);
    out[idx] = select(sample_q(t.stencil), 0.0, t.wall);
}

@compute @workgroup_size(8, 8)
fn backward(@builtin(global_invocation_id) gid: vec3<u32>) {
    let face = fluid_face(gid, params.resolution);
    if !face.valid {
        return;
    }
    let n = i32(params.resolution);
    let t = traced(face, params.dt * params.origin_cell.w);
    let idx = fluid_face_index(face.axis, face.i, face.j, n);
    out[idx] = select(sample_q(t.stencil), 0.0, t.wall);
}

@compute @workgroup_size(8, 8)
fn correct(@builtin(global_invocation_id) gid: vec3<u32>) {
    let face = fluid_face(gid, params.resolution);
    if !face.valid {
        return;
    }
    let n = i32(params.resolution);
    let idx = fluid_face_index(face.axis, face.i, face.j, n);
    let t = traced(face, -params.dt * params.origin_cell.w);
    if t.wall {
        out[idx] = 0.0;
        return;
    }
    let s = t.stencil;
    let a = q[s.index.x];
    let b = q[s.index.y];
    let d = q[s.index.z];
    let e = q[s.index.w];
    let lo = min(min(a, b), min(d, e));
    let hi = max(max(a, b), max(d, e));
    let v = hat[idx] + 0.5 * (q[idx] - tilde[idx]);
    out[idx] = clamp(v, lo, hi) / damping();
}
