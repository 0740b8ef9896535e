// Billboard placement (issue 12, the middle distance): one card per cell of a square grid
// of cells around the camera, placed by a hash of the cell (no per-card state), kept in the
// ring between the blades' fade and the billboard radius, faded in where the blades thin
// out (Eq. 20) and out towards the billboard radius. The twin of `billboard::place_card`.
// Expects `bb: BillboardParams` and the terrain's height function (terrain_height.wgsl).

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
    // size (m, the density map's square), w: unused.
    shape: vec4<f32>,
    // The atlas's mean albedo (rgb: the far ground's grass colour), unused.
    albedo: vec4<f32>,
}

struct Card {
    // Root on the terrain.
    pos: vec3<f32>,
    // 0 outside the ring (not drawn), else the fade factor in (0, 1].
    fade: f32,
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
    // Cell index, atlas variant, 1 = mirrored, unused.
    info: vec4<u32>,
    // The light on the card per unit of the atlas's mean albedo (`far_grass_facings` over
    // `albedo`): the sky's part, and the sun's part when the sun is not shadowed for each
    // of the atlas's blade facings (rgb).
    light_ambient: vec4<f32>,
    light_sun: array<vec4<f32>, 4>,
}

const BB_QUANTUM: f32 = 1.0 / 1024.0;
const BB_UNIT: f32 = 1.0 / 16777216.0;

fn bb_hash(key: u32, cx: i32, cz: i32) -> u32 {
    return hash32(key ^ hash32(bitcast<u32>(cx) ^ rotl17(hash32(bitcast<u32>(cz) ^ 0x68e31da4u))));
}

fn card_at(i: u32) -> Card {
    var c: Card;
    let g = u32(bb.cells.z);
    let cx = bb.cells.x - i32(g / 2u) + i32(i % g);
    let cz = bb.cells.y - i32(g / 2u) + i32(i / g);
    let cell_q = bb.cells.w;
    let h = bb_hash(bb.info.x, cx, cz);
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
    if d >= bb.fade.x && d <= bb.fade.w {
        fade = smoothstep(bb.fade.x, bb.fade.y, d) * (1.0 - smoothstep(bb.fade.z, bb.fade.w, d));
    }
    c.fade = fade;
    c.pos = vec3<f32>(x, terrain_height(vec2<f32>(x, z)).x, z);
    return c;
}
