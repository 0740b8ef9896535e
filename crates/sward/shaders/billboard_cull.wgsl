// Billboard cull (issue 12, the middle distance): one invocation per cell of the grid
// around the camera places its card (`billboard_place.wgsl`), drops it outside the ring,
// where the density map thins it or outside the view (its centre with a card's margin:
// the test `billboard::count_drawn` makes on the CPU), computes its sway and bending and
// the blades' light on it once (`billboard_sway.wgsl`, `far_grass.wgsl`) and appends the
// survivors to a list that the draw reads, six vertices per card, through an indirect
// draw whose vertex count this pass writes, in the order the cells are visited
// (`mark_cards`, `order_cards`, `cull_cards`). Group 1 is the frame's light (its uniforms).
//
// Why a compute pass: the draw used to place every cell's card in the vertex shader, six
// times per card, for the whole grid (about 40,000 cards, most of them behind the camera
// or outside the ring). A software rasteriser runs vertex shaders on one thread; the
// compute pass runs on all of them and the draw shades only the cards in view.
//!include common.wgsl
//!include light.wgsl
//!include blade_shade.wgsl
//!include far_grass.wgsl
//!include far_gain_math.wgsl
//!include terrain_height.wgsl
//!include wind.wgsl
//!include billboard_place.wgsl

@group(0) @binding(0) var<uniform> frame: Frame;
@group(0) @binding(3) var<uniform> bb: BillboardParams;
@group(0) @binding(6) var<storage, read> spheres: array<vec4<f32>>;
@group(0) @binding(7) var<uniform> params: SimParams;
@group(0) @binding(8) var<storage, read> wind_grid: array<vec2<f32>>;
@group(0) @binding(9) var density_map: texture_2d<f32>;
@group(0) @binding(10) var<storage, read_write> cards: array<DrawnCard>;
@group(0) @binding(11) var<storage, read_write> args: CardDrawArgs;
// The far state: the gusts' bend at the edge of the blades' reach (`CullCounters::wave_sum`,
// `wave_blades`), in word 2 the far field's distance gain, in words 4-7 the far levels'
// measured light gain and in word 11 the cards' contrast gain (far_gain_math.wgsl).
@group(0) @binding(12) var<storage, read> waves: array<u32, FAR_STATE_WORDS>;
// The trail map (`trails.wgsl`): cards over a trail lie down as its blades did.
@group(0) @binding(13) var<storage, read> trails: array<u32>;

fn trail_word(i: u32) -> u32 {
    return trails[i];
}

//!include wind_sample.wgsl
//!include trails.wgsl
//!include billboard_sway.wgsl

// `draw_indirect` arguments (wgpu::util::DrawIndirectArgs): six vertices per card; then,
// per workgroup of the cull, its lanes' kept bits (two words) and its first slot
// (`ORDER_WORDS`), which put the list in the order the cells are visited.
struct CardDrawArgs {
    vertex_count: u32,
    instance_count: u32,
    first_vertex: u32,
    first_instance: u32,
    order: array<u32>,
}

//!include workgroup_scan.wgsl

const ORDER_WORDS: u32 = 3u;

// The density map at (x, z) (1 without one), as the terrain shades it.
fn density_at(xz: vec2<f32>) -> f32 {
    if bb.info.z == 0u {
        return 1.0;
    }
    let dims = vec2<f32>(textureDimensions(density_map));
    let g = (xz / bb.shape.z + 0.5) * (dims - 1.0);
    let t = clamp(vec2<i32>(round(g)), vec2<i32>(0), vec2<i32>(dims) - 1);
    return textureLoad(density_map, t, 0).r;
}

// The cell visited `i`-th (`billboard::visit_order`): within each level, rows along the
// view's main axis from the camera outwards (`bb.levels.w`: bit 0 z downwards, bit 1 x
// downwards, bit 2 x the outer axis), so that the cards are listed, and drawn, nearer
// first and the depth test rejects what they hide before it is shaded.
fn visit_order(i: u32, side: u32) -> u32 {
    let per = side * side;
    let level = i / per;
    let j = i % per;
    let flags = bb.levels.w;
    let x_outer = (flags & 4u) != 0u;
    var x = select(j % side, j / side, x_outer);
    var z = select(j / side, j % side, x_outer);
    if (flags & 1u) != 0u {
        z = side - 1u - z;
    }
    if (flags & 2u) != 0u {
        x = side - 1u - x;
    }
    return level * per + z * side + x;
}

// Cells visited by the cull.
fn cells() -> u32 {
    let side = bb.levels.z;
    return bb.levels.x * side * side;
}

// The card of the cell visited `i`-th as the cull tests it: its cell and placement, its
// height, centre and the centre's clip position (set only past the ring and density
// tests), and whether it is drawn (in the ring, kept by the density map, its centre in
// view with a card's margin; the twin is `billboard::drawn_cells`).
struct CardView {
    cell: u32,
    card: Card,
    height: f32,
    centre: vec3<f32>,
    clip: vec4<f32>,
    kept: bool,
}

fn card_view(i: u32) -> CardView {
    var v: CardView;
    if i >= cells() {
        return v;
    }
    v.cell = visit_order(i, bb.levels.z);
    let c = card_at(v.cell);
    v.card = c;
    if c.fade <= 0.0 || c.accept >= density_at(c.pos.xz) {
        return v;
    }
    v.height = bb.eye_card.w * c.scale;
    v.centre = c.pos + vec3<f32>(0.0, 0.5 * v.height, 0.0);
    v.clip = frame.view_proj * vec4<f32>(v.centre, 1.0);
    let clip = v.clip;
    let margin = 1.0 + bb.eye_card.z * f32(1u << c.level) / max(clip.w, 1e-3);
    v.kept = clip.w > 0.0 && abs(clip.x) <= clip.w * margin && abs(clip.y) <= clip.w * margin
        && clip.z <= clip.w;
    return v;
}

var<workgroup> kept_bits: array<atomic<u32>, 2>;

// The first of three passes that draw the kept cards in the order the cells are visited,
// whatever order the workgroups run in (two crossing cards can lie at exactly one depth at
// a pixel, and the depth test keeps the one drawn last): each workgroup's kept lanes.
@compute @workgroup_size(64)
fn mark_cards(
    @builtin(global_invocation_id) id: vec3<u32>,
    @builtin(workgroup_id) wid: vec3<u32>,
    @builtin(local_invocation_index) lid: u32,
) {
    let kept = card_view(id.x).kept;
    if lid < 2u {
        atomicStore(&kept_bits[lid], 0u);
    }
    workgroupBarrier();
    if kept {
        atomicOr(&kept_bits[lid / 32u], 1u << (lid % 32u));
    }
    workgroupBarrier();
    if lid < 2u {
        args.order[wid.x * ORDER_WORDS + lid] = atomicLoad(&kept_bits[lid]);
    }
}

// Cards `mark_cards` kept in workgroup `g`.
fn kept_in_group(g: u32) -> u32 {
    return countOneBits(args.order[g * ORDER_WORDS]) + countOneBits(args.order[g * ORDER_WORDS + 1u]);
}

// The second: each workgroup's first slot, and the draw's arguments (one workgroup).
@compute @workgroup_size(256)
fn order_cards(@builtin(local_invocation_index) t: u32) {
    let slice = scan_slice(t, (cells() + 63u) / 64u);
    var count = 0u;
    for (var g = slice.x; g < slice.y; g++) {
        count += kept_in_group(g);
    }
    var at = exclusive_scan(t, vec3<u32>(count, 0u, 0u)).x;
    for (var g = slice.x; g < slice.y; g++) {
        args.order[g * ORDER_WORDS + 2u] = at;
        at += kept_in_group(g);
    }
    if t == 0u {
        args.vertex_count = 6u * partial[SCAN_THREADS].x;
        args.instance_count = 1u;
        args.first_vertex = 0u;
        args.first_instance = 0u;
    }
}

// The third: each kept card, lit, at its slot: its workgroup's first slot plus the kept
// lanes before it.
@compute @workgroup_size(64)
fn cull_cards(
    @builtin(global_invocation_id) id: vec3<u32>,
    @builtin(workgroup_id) wid: vec3<u32>,
    @builtin(local_invocation_index) lid: u32,
) {
    let view = card_view(id.x);
    if !view.kept {
        return;
    }
    let words = wid.x * ORDER_WORDS;
    let below = (1u << (lid % 32u)) - 1u;
    var at = args.order[words + 2u] + countOneBits(args.order[words + lid / 32u] & below);
    if lid >= 32u {
        at += countOneBits(args.order[words]);
    }
    let cell = view.cell;
    let c = view.card;
    let h = view.height;
    let centre = view.centre;
    let clip = view.clip;
    var out: DrawnCard;
    out.pos_fade = vec4<f32>(c.pos, c.fade);
    out.top_scale = vec4<f32>(top_offset(c.pos, h), c.scale);
    out.info = vec4<u32>(cell, c.variant, select(0u, 1u, c.mirror > 0.0), c.level);
    // The blades' light averaged over what a distant eye sees of them, once per card (the
    // sun's shadow is looked up by the draw, after the shadow maps are drawn), over the
    // ground's normal: cards and the ground between them read as one on every slope.
    let slope = terrain_height(c.pos.xz);
    let ground_n = normalize(vec3<f32>(-slope.y, 1.0, -slope.z));
    let albedo = max(bb.albedo.rgb, vec3<f32>(1e-4));
    // A trail under the card: its blades show their paler side (`trail_wave`).
    let trail_pale = trail_wave(trail_at(c.pos.x, c.pos.z)) * light.shading_b.y;
    let wave = max(mean_wave(waves[0], waves[1]), trail_pale);
    let l = far_grass_facings(centre, ground_n, albedo, wave);
    // The far ground's patches and clumps at the card's root (`grass_texture`, faded as
    // the ground's are by the metres a pixel spans there: 2 w / (P11 · height) at view
    // depth w), so that cards and the ground between them vary together.
    let m = frame.view_proj;
    let p11 = length(vec3<f32>(m[0][1], m[1][1], m[2][1]));
    let footprint = 2.0 * clip.w / max(p11 * frame.viewport_time.y, 1e-6);
    // Calibrated on the blades the cards stand for (`far_gain`), at the card's distance
    // (`distance_gain`) and in its direction from the camera (`sector_gain`).
    let card_dir = centre - frame.camera_pos.xyz;
    let to_card = length(card_dir);
    let sector = sector_pair(card_dir.xz);
    let patchy = grass_texture(grass_octaves(c.pos.xz), footprint)
        * far_gain(vec4<u32>(waves[4], waves[5], waves[6], waves[7]))
        * distance_gain(to_card, frame.thinning_reach.x, waves[2])
        * sector_gain(sector, waves[SECTOR_WORD + sector.a], waves[SECTOR_WORD + sector.b]);
    // The contrast the blades have where the cards take over from them (a pixel spans a
    // fraction of a blade's height there), handed over to the far ground's (1: the atlas's
    // own) as a pixel grows to span half a card: further out a pixel of blades would show
    // the mean of many, as the far ground does (`CONTRAST_FOOTPRINT`). The texels' mip bias
    // hands over with it.
    let handover = smoothstep(CONTRAST_FOOTPRINT.x, CONTRAST_FOOTPRINT.y, footprint / max(h, 1e-3));
    // w: the contrast the atlas's texels are shown with about its mean (`far_gain`).
    out.light_ambient = vec4<f32>(patchy * l.ambient / albedo, mix(contrast_gain(waves[11]), 1.0, handover));
    for (var j = 0u; j < 4u; j++) {
        out.light_sun[j] = vec4<f32>(patchy * l.sun[j] / albedo, 0.0);
    }
    // w of the first facing: the mip bias of the card's texels.
    out.light_sun[0].w = CARD_SHARPEN * (1.0 - handover);
    cards[at] = out;
}
