// Wind overlay (`sward render --wind-overlay`): the fluid velocity as a translucent colour
// layer draped over the terrain (hue = direction, brightness = speed), small arrows on a
// coarse lattice, and the AGC guide arrows (shaft + head, coloured by strength), all drawn
// over the finished frame without depth test so the grass underneath stays visible.
//!include common.wgsl

struct Overlay {
    // x, z of the grid corner, cell size, speed that maps to full colour.
    grid: vec4<f32>,
    // resolution, glyphs per side, arrow count, unused.
    info: vec4<u32>,
    // terrain size, glyph lift above the ground, guide-arrow lift, max guide strength.
    extra: vec4<f32>,
}

struct Arrow {
    segment: vec4<f32>,
    strength: f32,
    radius: f32,
    // 0 before the AGC sequence reaches the arrow, 1 once it is fully on.
    activation: f32,
    pad: f32,
}

@group(0) @binding(0) var<uniform> frame: Frame;
@group(0) @binding(1) var<uniform> overlay: Overlay;
@group(0) @binding(2) var<storage, read> velocity: array<vec2<f32>>;
@group(0) @binding(3) var<storage, read> arrows: array<Arrow>;
@group(0) @binding(4) var<storage, read> heights: array<f32>;

fn cell(i: i32, j: i32) -> vec2<f32> {
    let n = i32(overlay.info.x);
    return velocity[clamp(j, 0, n - 1) * n + clamp(i, 0, n - 1)];
}

fn sample_velocity(xz: vec2<f32>) -> vec2<f32> {
    let n = f32(overlay.info.x);
    let q = clamp((xz - overlay.grid.xy) / overlay.grid.z - 0.5, vec2<f32>(0.0), vec2<f32>(n - 1.0));
    let c = vec2<i32>(floor(q));
    let f = q - vec2<f32>(c);
    return mix(mix(cell(c.x, c.y), cell(c.x + 1, c.y), f.x), mix(cell(c.x, c.y + 1), cell(c.x + 1, c.y + 1), f.x), f.y);
}

// Ground height from the height field (same grid as the terrain mesh).
fn ground(xz: vec2<f32>) -> f32 {
    let res = arrayLength(&heights);
    let n = i32(round(sqrt(f32(res))));
    let size = overlay.extra.x;
    let q = clamp((xz + 0.5 * size) / size * f32(n - 1), vec2<f32>(0.0), vec2<f32>(f32(n - 1)));
    let c = vec2<i32>(floor(q));
    let f = q - vec2<f32>(c);
    let c1 = min(c + 1, vec2<i32>(n - 1));
    let h00 = heights[c.y * n + c.x];
    let h10 = heights[c.y * n + c1.x];
    let h01 = heights[c1.y * n + c.x];
    let h11 = heights[c1.y * n + c1.x];
    return mix(mix(h00, h10, f.x), mix(h01, h11, f.x), f.y);
}

fn hue(a: f32) -> vec3<f32> {
    let k = vec3<f32>(0.0, 2.0, 4.0);
    return 0.5 + 0.5 * cos(a + k * (TAU / 6.0));
}

struct FieldOut {
    @builtin(position) clip: vec4<f32>,
    @location(0) world: vec3<f32>,
}

struct TerrainIn {
    @location(0) position: vec3<f32>,
    @location(1) normal: vec3<f32>,
}

@vertex
fn vs_field(in: TerrainIn) -> FieldOut {
    var out: FieldOut;
    out.clip = frame.view_proj * vec4<f32>(in.position, 1.0);
    out.world = in.position;
    return out;
}

// Whether (x, z) lies on the wind grid (which may cover only the part of the terrain
// around the camera when it follows the camera).
fn on_grid(xz: vec2<f32>) -> bool {
    let side = overlay.grid.z * f32(overlay.info.x);
    let q = xz - overlay.grid.xy;
    return all(q >= vec2<f32>(0.0)) && all(q <= vec2<f32>(side));
}

@fragment
fn fs_field(in: FieldOut) -> @location(0) vec4<f32> {
    if !on_grid(in.world.xz) {
        discard;
    }
    let v = sample_velocity(in.world.xz);
    let speed = length(v);
    let t = clamp(speed / overlay.grid.w, 0.0, 1.0);
    let color = mix(vec3<f32>(0.05, 0.05, 0.12), hue(atan2(v.y, v.x)), sqrt(t));
    return vec4<f32>(color, 0.25 + 0.3 * t);
}

struct LineOut {
    @builtin(position) clip: vec4<f32>,
    @location(0) color: vec4<f32>,
}

// One arrow as 9 vertices: a shaft quad (6) and a head triangle (3), flat on the ground.
fn arrow_vertex(vid: u32, start: vec2<f32>, end: vec2<f32>, width: f32, lift: f32) -> vec3<f32> {
    let d = end - start;
    let len = max(length(d), 1e-5);
    let dir = d / len;
    let side = vec2<f32>(-dir.y, dir.x);
    let head = min(len * 0.4, width * 4.0);
    let neck = end - dir * head;
    var p: vec2<f32>;
    switch vid {
        case 0u: { p = start - side * width; }
        case 1u: { p = start + side * width; }
        case 2u: { p = neck + side * width; }
        case 3u: { p = start - side * width; }
        case 4u: { p = neck + side * width; }
        case 5u: { p = neck - side * width; }
        case 6u: { p = neck - side * width * 2.6; }
        case 7u: { p = neck + side * width * 2.6; }
        default: { p = end; }
    }
    return vec3<f32>(p.x, ground(p) + lift, p.y);
}

@vertex
fn vs_glyph(@builtin(vertex_index) vid: u32, @builtin(instance_index) inst: u32) -> LineOut {
    // The glyphs cover the wind grid (the terrain square, or the square that follows the
    // camera).
    let n = overlay.info.y;
    let side = overlay.grid.z * f32(overlay.info.x);
    let spacing = side / f32(n);
    let ij = vec2<f32>(f32(inst % n), f32(inst / n)) + 0.5;
    let p = overlay.grid.xy + ij * spacing;
    let v = sample_velocity(p);
    let speed = length(v);
    let t = clamp(speed / overlay.grid.w, 0.0, 1.0);
    var dir = vec2<f32>(1.0, 0.0);
    if speed > 1e-4 {
        dir = v / speed;
    }
    let len = spacing * 0.85 * t;
    let w = arrow_vertex(vid, p - dir * len * 0.5, p + dir * len * 0.5, spacing * 0.06, overlay.extra.y);
    var out: LineOut;
    out.clip = frame.view_proj * vec4<f32>(w, 1.0);
    out.color = vec4<f32>(1.0, 1.0, 1.0, select(0.0, 0.85, speed > 1e-3));
    return out;
}

@vertex
fn vs_guide(@builtin(vertex_index) vid: u32, @builtin(instance_index) inst: u32) -> LineOut {
    let a = arrows[inst];
    let w = arrow_vertex(vid, a.segment.xy, a.segment.zw, max(a.radius * 0.12, 0.04), overlay.extra.z);
    let s = clamp(a.strength / max(overlay.extra.w, 1e-4), 0.0, 1.0);
    var out: LineOut;
    out.clip = frame.view_proj * vec4<f32>(w, 1.0);
    let on = mix(vec3<f32>(1.0, 0.95, 0.2), vec3<f32>(1.0, 0.2, 0.1), s);
    // Arrows the sequence has not switched on yet are grey (as in the window's editor).
    let off = vec3<f32>(0.35, 0.35, 0.38);
    out.color = vec4<f32>(mix(off, on, clamp(a.activation, 0.0, 1.0)), 1.0);
    return out;
}

@fragment
fn fs_line(in: LineOut) -> @location(0) vec4<f32> {
    return in.color;
}
