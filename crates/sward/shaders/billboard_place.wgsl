// Billboard placement (issue 12, the middle distance): one card per cell of nested grids
// around the camera (level k's cells 2^k base cells wide, covering Chebyshev distances of
// `levels.y` to twice that in its cells: the prairie thesis's levels by grid distance),
// placed by a hash of the cell and its level (no per-card state), kept in the ring between
// the blades' fade and the billboard radius, faded in where the blades thin out (Eq. 20)
// and out towards the billboard radius. The twin of `billboard::place_card`.
// Expects `bb: BillboardParams` and the terrain's height function (terrain_height.wgsl).
//!include canopy.wgsl

struct BillboardParams {
    // x, z of the camera's cell; grid cells per side; cell side in quanta (1/1024 m).
    cells: vec4<i32>,
    // Fade-in start and end (m): the blades' thinning band; fade-out start and end.
    fade: vec4<f32>,
    // Camera x, z (m); card width and height per cell (m).
    eye_card: vec4<f32>,
    // x: field seed key, y: atlas variants, z: 1 = density map bound, w: sphere count.
    info: vec4<u32>,
    // x: sway gain (m of top offset per m/s² of wind), y: bend radius factor, z: terrain
    // size (m, the density map's square), w: the camera's height (m, world y).
    shape: vec4<f32>,
    // The atlas's mean albedo (rgb: the far ground's grass colour), unused.
    albedo: vec4<f32>,
    // Levels, a level's inner half-size in its cells, cells per side of a level's index
    // space, the order the cull visits a level's cells in (`billboard::visit_flags`).
    levels: vec4<u32>,
}

struct Card {
    // Root on the terrain.
    pos: vec3<f32>,
    // 0 outside the ring or its level (not drawn), else the fade factor in (0, 1].
    fade: f32,
    // Its level: the card is 2^level base cards wide.
    level: u32,
    variant: u32,
    // Card size factor (0.8 to 1.2) and a random mirror (+1 or -1).
    scale: f32,
    mirror: f32,
    // A value in [0, 1) for the density map's acceptance test.
    accept: f32,
}

// A card the cull kept, as the draw reads it (`billboard::DrawnCard` in Rust).
struct DrawnCard {
    // Root on the terrain; fade in (0, 1].
    pos_fade: vec4<f32>,
    // Offset of the card's top (sway and bending); size factor.
    top_scale: vec4<f32>,
    // Cell index, atlas variant, 1 = mirrored, level.
    info: vec4<u32>,
    // The light on the card per unit of the atlas's mean albedo (`far_grass_facings` over
    // `albedo`): the sky's part, and the sun's part when the sun is not shadowed for each
    // of the atlas's blade facings (rgb).
    light_ambient: vec4<f32>,
    light_sun: array<vec4<f32>, 4>,
}

const BB_QUANTUM: f32 = 1.0 / 1024.0;
const BB_UNIT: f32 = 1.0 / 16777216.0;

fn bb_hash(key: u32, level: u32, cx: i32, cz: i32) -> u32 {
    return hash32(key ^ hash32(level * 0x2545F491u) ^ hash32(bitcast<u32>(cx) ^ rotl17(hash32(bitcast<u32>(cz) ^ 0x68e31da4u))));
}

// Card `i`: level i / side², cell i % side² of that level's index space (the children of
// the cells within `levels.y − 1` of the camera's cell one level up).
fn card_at(i: u32) -> Card {
    var c: Card;
    let side = max(bb.levels.z, 1u);
    let level = min(i / (side * side), 31u);
    let j = i % (side * side);
    let half = i32(bb.levels.y);
    // The camera's cell at this level and at the next (arithmetic shifts floor).
    let c0 = vec2<i32>(bb.cells.x >> level, bb.cells.y >> level);
    let parent = vec2<i32>(bb.cells.x >> (level + 1u), bb.cells.y >> (level + 1u));
    let cx = (parent.x - (half - 1)) * 2 + i32(j % side);
    let cz = (parent.y - (half - 1)) * 2 + i32(j / side);
    // Level 0 keeps every cell; the others leave the hole the level inside fills.
    let inside = level > 0u && max(abs(cx - c0.x), abs(cz - c0.y)) < half;
    let cell_q = bb.cells.w << level;
    let h = bb_hash(bb.info.x, level, cx, cz);
    let h1 = hash32(h + 0x9E3779B9u);
    let h2 = hash32(h + 0x3C6EF372u);
    let h3 = hash32(h + 0xDAA66D2Bu);
    let xq = cx * cell_q + i32(h % u32(cell_q));
    let zq = cz * cell_q + i32(h1 % u32(cell_q));
    let x = f32(xq) * BB_QUANTUM;
    let z = f32(zq) * BB_QUANTUM;
    c.variant = h2 % max(bb.info.y, 1u);
    c.scale = 0.8 + 0.4 * f32(h3 >> 8u) * BB_UNIT;
    c.mirror = select(-1.0, 1.0, (h2 & 0x100u) != 0u);
    c.accept = f32(hash32(h3) >> 8u) * BB_UNIT;
    let d = length(vec2<f32>(x, z) - bb.eye_card.xy);
    var fade = 0.0;
    c.level = level;
    if d >= bb.fade.x && d <= bb.fade.w && !inside {
        fade = smoothstep(bb.fade.x, bb.fade.y, d) * (1.0 - smoothstep(bb.fade.z, bb.fade.w, d));
    }
    c.pos = vec3<f32>(x, terrain_height(vec2<f32>(x, z)).x, z);
    // Seen from above, the far ground's canopy stands for the grass instead (canopy.wgsl).
    if fade > 0.0 {
        fade *= 1.0 - canopy_weight(c.pos, vec3<f32>(bb.eye_card.x, bb.shape.w, bb.eye_card.y));
    }
    c.fade = fade;
    return c;
}
