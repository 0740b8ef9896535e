// The trail map (issue 29, point 4; `field::trails`, its CPU twin): a header, a table
// from tile to page (open addressing, linear probing) and the pages of texels (stamp
// `eta + a t`, bend x, bend z). Every read goes through `trail_word(i)`, which the including
// shader defines: an atomic load in the blade update (which writes the map), a plain load
// in the tile generation, the billboards and the far ground (which only read it). Expects
// `hash32` and `rotl17` (common.wgsl).

const TRAIL_HEADER: u32 = 16u;
const TRAIL_TEXEL_WORDS: u32 = 3u;
const TRAIL_NONE: u32 = 0xffffffffu;
// The header word holding the largest stamp ever written (`trails::MAX_STAMP_WORD`): the
// update raises it with every write, the CPU's header upload leaves it alone.
const TRAIL_MAX_STAMP: u32 = 12u;
// Blades with a smaller eta leave no trail (`trails::MIN_ETA`).
const TRAIL_MIN_ETA: f32 = 0.02;

// Whether every component is finite: a bit test (a compiler may fold `x == x` away).
fn trail_finite3(v: vec3<f32>) -> bool {
    let e = vec3<u32>(0x7f800000u);
    return all((bitcast<vec3<u32>>(v) & e) != e);
}

// floor(a / b) for b > 0.
fn trail_div_floor(a: i32, b: i32) -> i32 {
    let q = a / b;
    return select(q, q - 1, (a % b) != 0 && a < 0);
}

fn trail_quantum(v: f32) -> i32 {
    return i32(clamp(round(v * 1024.0), -2.0e9, 2.0e9));
}

// The tile (x, y) and texel (z) under world point (x, z): the twin of `TrailLayout::locate`.
fn trail_locate(x: f32, z: f32) -> vec3<i32> {
    let t = i32(trail_word(4u));
    let r = trail_word(1u);
    let xq = trail_quantum(x);
    let zq = trail_quantum(z);
    let tx = trail_div_floor(xq, t);
    let tz = trail_div_floor(zq, t);
    let u = u32(xq - tx * t) * r / u32(t);
    let v = u32(zq - tz * t) * r / u32(t);
    return vec3<i32>(tx, tz, i32(v * r + u));
}

// The page holding tile (tx, tz)'s trail, or TRAIL_NONE: the twin of the table's probe.
fn trail_page(tx: i32, tz: i32) -> u32 {
    let cap = trail_word(0u);
    if cap == 0u {
        return TRAIL_NONE;
    }
    // Outside the tiles any page covers: no probe at all (most of the far ground).
    let lo = vec2<i32>(bitcast<i32>(trail_word(8u)), bitcast<i32>(trail_word(9u)));
    let hi = vec2<i32>(bitcast<i32>(trail_word(10u)), bitcast<i32>(trail_word(11u)));
    if tx < lo.x || tz < lo.y || tx > hi.x || tz > hi.y {
        return TRAIL_NONE;
    }
    var s = hash32(bitcast<u32>(tx) ^ rotl17(hash32(bitcast<u32>(tz)))) & (cap - 1u);
    for (var k = 0u; k < cap; k++) {
        let e = TRAIL_HEADER + 4u * s;
        let page = trail_word(e + 2u);
        if page == 0u {
            return TRAIL_NONE;
        }
        if bitcast<i32>(trail_word(e)) == tx && bitcast<i32>(trail_word(e + 1u)) == tz {
            return page - 1u;
        }
        s = (s + 1u) & (cap - 1u);
    }
    return TRAIL_NONE;
}

// The first word of a texel (`TrailLayout::texel_word`), or TRAIL_NONE where no page covers
// the point.
fn trail_texel_at(x: f32, z: f32) -> u32 {
    let at = trail_locate(x, z);
    let page = trail_page(at.x, at.y);
    if page == TRAIL_NONE {
        return TRAIL_NONE;
    }
    let r = trail_word(1u);
    return trail_word(2u) + page * r * r * TRAIL_TEXEL_WORDS + u32(at.z) * TRAIL_TEXEL_WORDS;
}

// Whether any trail is left anywhere: the largest stamp ever written has not decayed away.
// Where nothing was ever pressed (most scenes) every read stops here, before any probe.
fn trail_alive() -> bool {
    let now = bitcast<f32>(trail_word(5u));
    let decay = bitcast<f32>(trail_word(6u));
    return trail_word(0u) != 0u && bitcast<f32>(trail_word(TRAIL_MAX_STAMP)) - decay * now > 0.0;
}

// The trail at world point (x, z) now: (eta left, at most the ceiling; bend x, bend z), or
// zero where there is none.
fn trail_at(x: f32, z: f32) -> vec3<f32> {
    if !trail_alive() {
        return vec3<f32>(0.0);
    }
    let w = trail_texel_at(x, z);
    if w == TRAIL_NONE {
        return vec3<f32>(0.0);
    }
    return trail_texel(w);
}

// The trail held by the texel whose first word is `w`, now (as `trail_at`).
fn trail_texel(w: u32) -> vec3<f32> {
    let now = bitcast<f32>(trail_word(5u));
    let decay = bitcast<f32>(trail_word(6u));
    let eta = min(bitcast<f32>(trail_word(w)) - decay * now, bitcast<f32>(trail_word(7u)));
    if !(eta > 0.0) {
        return vec3<f32>(0.0);
    }
    return vec3<f32>(eta, bitcast<f32>(trail_word(w + 1u)), bitcast<f32>(trail_word(w + 2u)));
}

// The shading wave (before the waves' strength) of the blades a trail `t` (`trail_at`)
// left: bent by |bend| of their height (`blade_albedos`: clamp(1.5 |bend|)), as long as
// the trail cripples them (eta up to 1). What the far levels shade a trail with.
fn trail_wave(t: vec3<f32>) -> f32 {
    return clamp(1.5 * length(t.yz), 0.0, 1.0) * clamp(t.x, 0.0, 1.0);
}

// `trail_wave` at world point (x, z) interpolated bilinearly between the four texel centres
// around it: on the far ground a path's edge is soft rather than a staircase of texels.
// The far ground runs this for every pixel, and a software rasteriser runs both sides of
// every branch and each lane's integer division on its own, so it is written for that:
// one table probe, for the tile of the lower corner, whose texel the others are clamped
// into (along a tile's last texel the interpolation holds that texel's value, 24 cm at the
// default resolution); no integer division (a texel centre is half a texel from any
// border, so the float tile and texel are `trail_locate`'s). The CPU twin is
// `trails::wave_smooth`.
fn trail_wave_smooth(x: f32, z: f32) -> f32 {
    if !trail_alive() {
        return 0.0;
    }
    let r = max(trail_word(1u), 1u);
    let rf = f32(r);
    let texel = f32(trail_word(4u)) / (1024.0 * rf);
    let g = vec2<f32>(x, z) / texel - 0.5;
    let f = fract(g);
    let base = floor(g);
    let tile = floor((base + 0.5) / rf);
    let uv = vec2<u32>(base - tile * rf);
    let page = trail_page(i32(tile.x), i32(tile.y));
    let w = trail_word(2u) + (page * r + uv.y) * r * TRAIL_TEXEL_WORDS;
    let u0 = uv.x * TRAIL_TEXEL_WORDS;
    let u1 = min(uv.x + 1u, r - 1u) * TRAIL_TEXEL_WORDS;
    let next = select(r * TRAIL_TEXEL_WORDS, 0u, uv.y + 1u >= r);
    let a = trail_wave(trail_texel(w + u0));
    let b = trail_wave(trail_texel(w + u1));
    let d = trail_wave(trail_texel(w + next + u0));
    let e = trail_wave(trail_texel(w + next + u1));
    let v = mix(mix(a, b, f.x), mix(d, e, f.x), f.y);
    return select(0.0, v, page != TRAIL_NONE);
}
