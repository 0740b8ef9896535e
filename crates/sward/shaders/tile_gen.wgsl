// Tile generation (issue 12): the blades of the tiles entering the blade radius, written
// into their pool slots, then the boxes of their patches. `gen_blades` runs one invocation
// per blade (x: blade groups of a tile, y: job); `gen_boxes` one workgroup per patch of
// each job (x: patch, y: job), and also empties the patches of slots being freed. The CPU
// twin is `field::tiles::generate_tile` (src/field/tiles/generate.rs).
//!include common.wgsl
//!include terrain_height.wgsl
//!include blade_pose.wgsl
//!include clumps.wgsl
//!include trails.wgsl

struct GenParams {
    // Patch side in quanta (1/1024 m), patches per tile side, blades per patch, per tile.
    grid: vec4<u32>,
    // Seed key, tuft blades per pid, tuft radius in quanta, tufts per pid.
    key: vec4<u32>,
    // Height min, span; width min, span (m).
    sizes: vec4<f32>,
    // Stiffness min, span; bend min, span (radians).
    attrs: vec4<f32>,
    // Density map width, height, FLAG_* bits, jobs that generate (the first ones).
    map: vec4<u32>,
    // Half the terrain side (bounded grass), density map side, unused x2.
    extent: vec4<f32>,
    // Tiles along the side of the tuft layout's period, unused x3.
    tufts: vec4<u32>,
}

// x: slot, y, z: tile coordinates, w: 1 = generate the tile, 0 = free the slot.
struct Job {
    slot: u32,
    tx: i32,
    tz: i32,
    generate: u32,
}

@group(0) @binding(3) var<uniform> gen: GenParams;
@group(0) @binding(4) var<storage, read> density: array<f32>;
@group(0) @binding(5) var<storage, read> jobs: array<Job>;
@group(0) @binding(6) var<storage, read_write> blades: array<Blade>;
@group(0) @binding(7) var<storage, read_write> states: array<BladeState>;
@group(0) @binding(8) var<storage, read_write> patches: array<PatchBox>;
@group(0) @binding(9) var<storage, read_write> seen: array<u32>;
// The field's species and clumps (the same buffer as `gen`, from byte 256).
@group(0) @binding(10) var<uniform> traits: FieldTraits;
// The tuft centres of one period of tiles (`field::tiles::TuftLayout`): offsets in quanta
// from their patch's corner, `key.w` per patch, patches row-major over the period.
@group(0) @binding(11) var<storage, read> tuft_offsets: array<vec2<u32>>;
// The trail map (`trails.wgsl`): a tile coming back takes its trail from its page.
@group(0) @binding(12) var<storage, read> trails: array<u32>;

fn trail_word(i: u32) -> u32 {
    return trails[i];
}

const FLAG_DENSITY: u32 = 1u;
const FLAG_BOUNDED: u32 = 2u;
const TUFT_BLADES: u32 = 16u;
const MIN_HEIGHT: f32 = 1e-3;
const GOLDEN: u32 = 0x9E3779B9u;
const UNIT: f32 = 1.0 / 16777216.0;
const QUANTUM: f32 = 1.0 / 1024.0;
const EMPTY_PATCH: f32 = 1.0;

fn tile_key(key: u32, tx: i32, tz: i32) -> u32 {
    return hash32(key ^ hash32(bitcast<u32>(tx) ^ rotl17(hash32(bitcast<u32>(tz)))));
}

// The blade's k-th draw.
fn draw(h0: u32, k: u32) -> u32 {
    return hash32(h0 + k * GOLDEN);
}

fn unit(h0: u32, k: u32) -> f32 {
    return f32(draw(h0, k) >> 8u) * UNIT;
}

// Twin of `grid::to_grid`.
fn to_grid(coord: f32, size: f32, samples: u32) -> f32 {
    if samples < 2u || size <= 0.0 {
        return 0.0;
    }
    let last = f32(samples - 1u);
    return clamp((coord / size + 0.5) * last, 0.0, last);
}

// Twin of `DensityMap::sample` (bilinear, edge values continue).
fn density_at(x: f32, z: f32) -> f32 {
    let w = gen.map.x;
    let h = gen.map.y;
    let u = to_grid(x, gen.extent.y, w);
    let v = to_grid(z, gen.extent.y, h);
    let i0 = min(u32(floor(u)), w - 1u);
    let j0 = min(u32(floor(v)), h - 1u);
    let i1 = min(i0 + 1u, w - 1u);
    let j1 = min(j0 + 1u, h - 1u);
    let tx = u - f32(i0);
    let tz = v - f32(j0);
    let a = density[j0 * w + i0];
    let b = density[j0 * w + i1];
    let c = density[j1 * w + i0];
    let d = density[j1 * w + i1];
    let top = a + (b - a) * tx;
    let bottom = c + (d - c) * tx;
    return clamp(top + (bottom - top) * tz, 0.0, 1.0);
}

// The centre (quanta) of tuft `t` of patch (px, pz) of tile (tx, tz): a Poisson-disk
// layout of a period of tiles, the same spacing across every tile border. The twin of
// `TuftLayout::centre`.
fn tuft_centre(tx: i32, tz: i32, px: u32, pz: u32, t: u32) -> vec2<i32> {
    let p = i32(gen.tufts.x);
    let mx = u32(((tx % p) + p) % p);
    let mz = u32(((tz % p) + p) % p);
    let grid = gen.grid.y;
    let side = gen.tufts.x * grid;
    let index = (mz * grid + pz) * side + mx * grid + px;
    let o = tuft_offsets[index * gen.key.w + t];
    let tile_q = i32(gen.grid.x * grid);
    let base = vec2<i32>(tx * tile_q + i32(px * gen.grid.x), tz * tile_q + i32(pz * gen.grid.x));
    return base + vec2<i32>(o);
}

// Blade `i` of tile (tx, tz): the twin of `draw_blade`. Height 0 marks a removed blade.
fn make_blade(tx: i32, tz: i32, i: u32) -> Blade {
    var out: Blade;
    out.v0_dir = vec4<f32>(0.0);
    out.v1_height = vec4<f32>(0.0);
    out.v2_width = vec4<f32>(0.0);
    out.up_stiffness = vec4<f32>(0.0);
    let patch_q = gen.grid.x;
    let grid = gen.grid.y;
    let ps = gen.grid.z;
    let tkey = tile_key(gen.key.x, tx, tz);
    let pid = i / ps;
    let j = i % ps;
    let px = pid % grid;
    let pz = pid / grid;
    let tile_q = i32(patch_q * grid);
    let base_x = tx * tile_q + i32(px * patch_q);
    let base_z = tz * tile_q + i32(pz * patch_q);
    let h0 = hash32(tkey ^ hash32(i));
    var xq: i32;
    var zq: i32;
    if j < gen.key.y {
        let centre = tuft_centre(tx, tz, px, pz, j / TUFT_BLADES);
        let radius_q = gen.key.z;
        let span = 2u * radius_q + 1u;
        let s = i32(draw(h0, 2u) >> 24u);
        let ox = (i32(draw(h0, 0u) % span) - i32(radius_q)) * s / 256;
        let oz = (i32(draw(h0, 1u) % span) - i32(radius_q)) * s / 256;
        xq = centre.x + ox;
        zq = centre.y + oz;
    } else {
        xq = base_x + i32(draw(h0, 0u) % patch_q);
        zq = base_z + i32(draw(h0, 1u) % patch_q);
    }
    let x = f32(xq) * QUANTUM;
    let z = f32(zq) * QUANTUM;
    if (gen.map.z & FLAG_BOUNDED) != 0u {
        let half = gen.extent.x;
        if abs(x) > half || abs(z) > half {
            return out;
        }
    }
    if (gen.map.z & FLAG_DENSITY) != 0u {
        if unit(h0, 8u) >= density_at(x, z) {
            return out;
        }
    }
    // The species' ranges and the clump's facing and lean.
    let t = blade_traits(x, z, f32(draw(h0, 3u) >> 8u) * (TAU * UNIT), gen.attrs.z + gen.attrs.w * unit(h0, 7u), vec3<f32>(unit(h0, 4u), unit(h0, 5u), unit(h0, 6u)));
    let angle = t.angle;
    let height = max(t.height, MIN_HEIGHT);
    let width = t.width;
    let stiffness = t.stiffness;
    let bend = t.bend;
    let ground = terrain_height(vec2<f32>(x, z));
    let v0 = vec3<f32>(x, ground.x, z);
    let up = normalize(vec3<f32>(-ground.y, 1.0, -ground.z));
    let front = blade_frame(up, angle)[1];
    let pose = rest_pose(v0, up, front, height, bend);
    out.v0_dir = vec4<f32>(v0, angle);
    out.v1_height = vec4<f32>(pose[0], height);
    out.v2_width = vec4<f32>(pose[1], width);
    out.up_stiffness = vec4<f32>(up, stiffness);
    return out;
}

// The pose of a blade bent by a trail: leaning towards its rest tip moved by `bend` times
// its height, at the tip distance where the validated curve has the blade's length (as
// `rest_pose`: a fixed point of the validation, so the update takes it as it is). The
// twin of `trails::bent_pose`.
fn trail_pose(v0: vec3<f32>, up: vec3<f32>, rest: vec3<f32>, bend: vec2<f32>, height: f32) -> array<vec3<f32>, 2> {
    let dir = rest + vec3<f32>(bend.x, 0.0, bend.y) * height - v0;
    let along = dot(dir, up);
    let across = dir - up * along;
    let side = length(across);
    if side < 1e-6 * height {
        return validate(v0, rest, up, height);
    }
    return rest_pose(v0, up, across / side, height, atan2(side, along));
}

@compute @workgroup_size(64)
fn gen_blades(
    @builtin(workgroup_id) wid: vec3<u32>,
    @builtin(local_invocation_index) lid: u32,
) {
    let job = jobs[wid.y];
    let i = wid.x * 64u + lid;
    if wid.y >= gen.map.w || job.generate == 0u || i >= gen.grid.w {
        return;
    }
    var blade = make_blade(job.tx, job.tz, i);
    let at = job.slot * gen.grid.w + i;
    let rest = blade.v2_width.xyz;
    // The trail left here before (the twin of `trails::restore`): the eta left now and the
    // tip moved by the bend, validated to the blade's length.
    var eta = 0.0;
    let height = blade.v1_height.w;
    let trail = trail_at(blade.v0_dir.x, blade.v0_dir.z);
    if trail.x > 0.0 && height > 0.0 {
        let pose = trail_pose(blade.v0_dir.xyz, blade.up_stiffness.xyz, rest, trail.yz, height);
        if trail_finite3(pose[0]) && trail_finite3(pose[1]) {
            blade.v1_height = vec4<f32>(pose[0], height);
            blade.v2_width = vec4<f32>(pose[1], blade.v2_width.w);
            eta = trail.x;
        }
    }
    blades[at] = blade;
    states[at].rest_eta = vec4<f32>(rest, eta);
    // A new tile's blades count as seen (SEEN_YES): drawn early in their first frame, so
    // that they cast their shadows then (the casters are the early lists: a blade left to
    // the late test would cast nothing until its second frame); the late test rechecks
    // them against the grass drawn early.
    seen[at] = SEEN_YES;
}

var<workgroup> lo: array<vec3<f32>, 64>;
var<workgroup> hi: array<vec3<f32>, 64>;
var<workgroup> tall: array<f32, 64>;
var<workgroup> lean: array<f32, 64>;

// The box of one pid of a generated tile (the twin of `tiles::patch_box`), or an empty box
// for every pid of a freed slot.
@compute @workgroup_size(64)
fn gen_boxes(
    @builtin(workgroup_id) wid: vec3<u32>,
    @builtin(local_invocation_index) lid: u32,
) {
    let job = jobs[wid.y];
    let per_tile = gen.grid.y * gen.grid.y;
    let pid = job.slot * per_tile + wid.x;
    let ps = gen.grid.z;
    var mn = vec3<f32>(3.0e38);
    var mx = vec3<f32>(-3.0e38);
    var t = 0.0;
    var up_y = 1.0;
    if job.generate != 0u {
        for (var k = lid; k < ps; k += 64u) {
            let b = blades[pid * ps + k];
            if b.v1_height.w > 0.0 {
                mn = min(mn, b.v0_dir.xyz);
                mx = max(mx, b.v0_dir.xyz);
                t = max(t, b.v1_height.w);
                up_y = min(up_y, b.up_stiffness.y);
            }
        }
    }
    lo[lid] = mn;
    hi[lid] = mx;
    tall[lid] = t;
    lean[lid] = up_y;
    workgroupBarrier();
    for (var stride = 32u; stride > 0u; stride >>= 1u) {
        if lid < stride {
            lo[lid] = min(lo[lid], lo[lid + stride]);
            hi[lid] = max(hi[lid], hi[lid + stride]);
            tall[lid] = max(tall[lid], tall[lid + stride]);
            lean[lid] = min(lean[lid], lean[lid + stride]);
        }
        workgroupBarrier();
    }
    if lid == 0u {
        let tallest = tall[0];
        if tallest > 0.0 {
            // max.w: the smallest up.y, which bounds the patch's distance test.
            patches[pid].min = vec4<f32>(lo[0] - tallest, 0.0);
            patches[pid].max = vec4<f32>(hi[0] + tallest, lean[0]);
        } else {
            patches[pid].min = vec4<f32>(0.0, 0.0, 0.0, EMPTY_PATCH);
            patches[pid].max = vec4<f32>(0.0);
        }
    }
}
