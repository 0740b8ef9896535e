// The far levels' light gain by the direction of view (issue 27, point 1), the arithmetic
// shared by the measuring pass (far_gain_common.wgsl), the cards (billboard_cull.wgsl), the
// far ground (terrain.wgsl) and the probe. The blades' light changes with the direction
// they are seen from (against the sun, along the wind: the prairie's reference reads about
// 25 levels brighter on the right of its view than on the left at 28-45 m), and the cards
// and the far ground, lit with one gain, show a third of that. So the horizon is cut into
// SECTORS of azimuth around the camera, and each keeps a multiplier of the light gain: what
// the far ring in that direction needs to show the near ring's blades in the same
// direction, over what the whole ring needs. A sector's value holds at its centre and
// goes linearly to its neighbours' (a point's weights, `sector_pair`), both in what a pixel
// adds to the sums and in what a card or the ground is lit with, so that the gain has no
// step across the view. Directions of the world, not of the screen: turning the camera
// keeps what each direction measured.
// Needs `finite3` (far_gain_math.wgsl) and TAU (common.wgsl).

// Sectors around the camera (22.5° each: four across the prairie's 85° view).
const SECTORS: u32 = 16u;
// Sums per sector in a frame's measurement (far ring, near ring).
const SECTOR_SUMS: u32 = 32u;
// The far state's first sector word, and its words in all.
const SECTOR_WORD: u32 = 12u;
const FAR_STATE_WORDS: u32 = 28u;
// The range a sector's multiplier is kept in: it carries how the light changes with the
// direction of view, not the light (the gain's).
const SECTOR_MIN: f32 = 0.6;
const SECTOR_MAX: f32 = 1.6;
// The share of the measured sectors' mean response added to each one's in its move: a
// sector at the edge of the view answers its few pixels weakly, and moved by its shortfall
// over that alone it swung with their noise (the prairie's right edge from 1.6 to 1.05 in
// the first 64 frames); the well-seen sectors move a fifth slower.
const SECTOR_DAMPING: f32 = 0.25;
// The fewest pixels (weights) a sector's far ring needs to be measured, and its near
// ring to give its own blades' ratio (else the whole ring's).
const SECTOR_MIN_SAMPLES: f32 = 8.0;

// The two sectors whose centres a horizontal direction lies between, and the weight of
// the second (the first's is 1 − t).
struct SectorPair {
    a: u32,
    b: u32,
    t: f32,
}

// The sectors of the horizontal direction `d` (from the camera to the point; any length):
// sector k's centre is at azimuth (k + 0.5) TAU / SECTORS from +x towards +z. A point
// straight below the camera, or a direction that is not finite, takes sector 0 whole.
fn sector_pair(d: vec2<f32>) -> SectorPair {
    if !finite3(vec3<f32>(d, 0.0)) || dot(d, d) < 1e-12 {
        return SectorPair(0u, 1u, 0.0);
    }
    let u = atan2(d.y, d.x) / TAU * f32(SECTORS) - 0.5;
    let f = floor(u);
    // u lies in [-SECTORS / 2 - 0.5, SECTORS / 2 - 0.5]: shifted by 2 SECTORS it is whole.
    let a = u32(i32(f) + 2 * i32(SECTORS)) % SECTORS;
    return SectorPair(a, (a + 1u) % SECTORS, clamp(u - f, 0.0, 1.0));
}

// A sector's multiplier from its state word: 1 until measured.
fn sector_value(word: u32) -> f32 {
    let m = bitcast<f32>(word);
    return select(1.0, m, m > 0.0 && finite3(vec3<f32>(m, 0.0, 0.0)));
}

// The multiplier at a direction's `pair`, from its two sectors' state words.
fn sector_gain(pair: SectorPair, a: u32, b: u32) -> f32 {
    return mix(sector_value(a), sector_value(b), pair.t);
}

// What the blades show against the model in a sector's near ring, from its sums (shown
// and model luminance over the pixels standing on a blade, their count, every pixel of the
// ring), as `blades_ratio`: `fallback` where too few were measured.
fn sector_ratio(near: vec4<f32>, fallback: f32) -> f32 {
    let few = near.z < SECTOR_MIN_SAMPLES || near.z < BLADES_STANDING * near.w;
    if few || near.x <= 1e-6 || near.y <= 1e-6 {
        return fallback;
    }
    return clamp(near.x / near.y, BLADES_MIN, BLADES_MAX);
}

// The sectors' multipliers after a frame's sums. `sums[2k]`: sector k's far ring, each
// pixel weighed by its weight for the sector (w, `sector_pair`): the shown luminance
// without the fog and the model's, both weighed by 1 − f; the response of the first to the
// sector's multiplier (the sum of w² × shown / the multiplier the pixel was lit with); the
// weights. `sums[2k + 1]`: its near ring (`sector_ratio`'s). `previous` the multipliers
// (0: not measured), `n` and `blend` as `next_gain`'s.
// Each sector wants its far pixels to show its model times its blades' ratio over the whole
// ring's need (the light gain brings the whole ring there), and is moved towards that by
// its own response (damped by SECTOR_DAMPING), one step of Jacobi's method on the
// interpolated field (a sector at the edge of the view shares its pixels with the next one
// and answers them weakly: moved by its own shown over its value it crept). The responses' sum of the moves is zero, so the
// moved multipliers are only scaled back where a clamp broke it: the gain and the
// multipliers do not drift against each other. A frame that is not finite keeps them all.
fn next_sectors(sums: array<vec4<f32>, SECTOR_SUMS>, previous: array<f32, SECTORS>, n: f32, blend: f32) -> array<f32, SECTORS> {
    var near = vec4<f32>(0.0);
    var shown = 0.0;
    for (var k = 0u; k < SECTORS; k++) {
        shown += sums[2u * k].x;
        near += sums[2u * k + 1u];
    }
    let whole = sector_ratio(near, 1.0);
    var wanted = 0.0;
    for (var k = 0u; k < SECTORS; k++) {
        wanted += sums[2u * k].y * sector_ratio(sums[2u * k + 1u], whole);
    }
    let need = wanted / shown;
    if !finite3(vec3<f32>(need, shown, near.x)) || shown <= 1e-6 || need <= 1e-6 {
        return previous;
    }
    let step = max(1.0 / (n + 1.0), blend);
    // The damping: SECTOR_DAMPING of the measured sectors' mean response, added to each
    // one's own (`next_sectors`'s comment).
    var responses = 0.0;
    var measured = 0.0;
    for (var k = 0u; k < SECTORS; k++) {
        let f = sums[2u * k];
        if f.w >= SECTOR_MIN_SAMPLES && f.x > 1e-6 && f.y > 1e-6 && f.z > 1e-6 {
            responses += f.z;
            measured += 1.0;
        }
    }
    let damping = SECTOR_DAMPING * responses / max(measured, 1.0);
    var next = previous;
    var before = 0.0;
    var after = 0.0;
    var moved = 0u;
    var finite = true;
    for (var k = 0u; k < SECTORS; k++) {
        let f = sums[2u * k];
        if f.w < SECTOR_MIN_SAMPLES || f.x <= 1e-6 || f.y <= 1e-6 || f.z <= 1e-6 {
            continue;
        }
        let old = sector_value(bitcast<u32>(previous[k]));
        let want = f.y * sector_ratio(sums[2u * k + 1u], whole) / need;
        let aim = clamp(old + (want - f.x) / (f.z + damping), SECTOR_MIN, SECTOR_MAX);
        finite = finite && finite3(vec3<f32>(old + (want - f.x) / (f.z + damping), f.z, want));
        next[k] = mix(old, aim, step);
        moved |= 1u << k;
        before += f.z * old;
        after += f.z * next[k];
    }
    if !finite || after <= 0.0 {
        return previous;
    }
    let scale = before / after;
    for (var k = 0u; k < SECTORS; k++) {
        if (moved & (1u << k)) != 0u {
            next[k] = clamp(next[k] * scale, SECTOR_MIN, SECTOR_MAX);
        }
    }
    return next;
}
