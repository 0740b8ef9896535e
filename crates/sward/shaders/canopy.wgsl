// The far grass seen from above (issue 27, point 2): past the blades, a grazing eye sees
// the canopy from the side, which the billboards' upright cards show; an eye looking down
// on it sees the blades' tops and the gaps between them, which upright cards seen from
// above do not (they read as rows of strokes over a smooth ground). So the far levels hand
// over by the view's elevation at each point: the cards fade out (`card_at`), and the far
// ground takes the texture of the canopy seen from above (`render::far_canopy`: layers of
// sward's own blades rasterised at start-up, mean 1), each cell of the ground showing one
// layer turned one of eight ways, so that nothing repeats. No bindings: the texture is the
// caller's. Twin: `render::far_canopy`.

// The sine of the view's elevation over a point at which the canopy starts to take over
// from the cards, and at which it has (5.7° and 23.6°; `far_canopy::ELEVATION` says why):
// the prairie's grazing views (the far ring 3-5° below the eye) keep their cards; from
// 19 m up the ring is 30-45° below.
const CANOPY_ELEVATION: vec2<f32> = vec2<f32>(0.1, 0.4);
// The same for the far ground under the cards (1.7° and 9.8°; `far_canopy::GROUND_ELEVATION`
// says why): lower, so that where the cards fade or their rows open gaps between them the
// ground shows the canopy's texture, not a smooth colour.
const CANOPY_GROUND_ELEVATION: vec2<f32> = vec2<f32>(0.03, 0.17);
// The side of a canopy cell (m): one layer of the texture, turned by a hash of the cell.
const CANOPY_SIDE: f32 = 2.0;
// Layers of the canopy texture.
const CANOPY_LAYERS: u32 = 4u;
// The texture holds the brightness factor over this (R8Unorm: factors 0 to 4).
const CANOPY_SCALE: f32 = 4.0;

// The mip bias of the cards' texels near the blades, and of the canopy's (`billboard.wgsl`'s
// `fs_main` says why).
const CARD_SHARPEN: f32 = -3.0;
// A pixel's height over the blades' (or a card's) at which the cards and the canopy start
// to hand their contrast and sharpness over to the far ground's, and at which they have
// (`billboard_cull.wgsl`).
const CONTRAST_FOOTPRINT: vec2<f32> = vec2<f32>(0.3, 1.0);

// A handover by the view's elevation over `p` seen from `eye`: 0 below the sine
// `range.x`, 1 above `range.y` (and with the eye on the point).
fn elevation_weight(p: vec3<f32>, eye: vec3<f32>, range: vec2<f32>) -> f32 {
    let to_eye = eye - p;
    let len = length(to_eye);
    if !(len > 1e-6) {
        return 1.0;
    }
    return smoothstep(range.x, range.y, to_eye.y / len);
}

// How much of the grass at `p` the canopy seen from above stands for, seen from `eye`: 0
// for a grazing view (the cards), 1 looking down (twin: `far_canopy::weight`).
fn canopy_weight(p: vec3<f32>, eye: vec3<f32>) -> f32 {
    return elevation_weight(p, eye, CANOPY_ELEVATION);
}

// How much of the far ground at `p` shows the canopy seen from above, seen from `eye`
// (twin: `far_canopy::ground_weight`): at least `canopy_weight`, from a lower elevation.
fn canopy_ground_weight(p: vec3<f32>, eye: vec3<f32>) -> f32 {
    return elevation_weight(p, eye, CANOPY_GROUND_ELEVATION);
}

// The cell of ground point `q` (x, z): which layer it shows (x) and how it is turned (y:
// bit 0 mirrors u, bit 1 mirrors v, bit 2 swaps them). Twin: `far_canopy::cell_variant`.
fn canopy_variant(q: vec2<f32>) -> vec2<u32> {
    let c = vec2<i32>(floor(q / CANOPY_SIDE));
    let h = hash32(bitcast<u32>(c.x) ^ rotl17(hash32(bitcast<u32>(c.y) ^ 0x2c1b3c6du)));
    return vec2<u32>(h % CANOPY_LAYERS, (h >> 8u) & 7u);
}

// Turns `v` (a texture coordinate's offset or gradient) the way `turn` says.
fn canopy_turn(v: vec2<f32>, turn: u32, offset: f32) -> vec2<f32> {
    var t = v;
    if (turn & 4u) != 0u {
        t = t.yx;
    }
    if (turn & 1u) != 0u {
        t.x = offset - t.x;
    }
    if (turn & 2u) != 0u {
        t.y = offset - t.y;
    }
    return t;
}

// The canopy's brightness factor at ground point `q`, whose change across a pixel is
// `dx`, `dy` (m), sharpened by `bias` mip levels: the texture's gradients are given (the
// cells' turns would make the hardware's jump at every cell's edge, and blur a line there).
fn canopy_factor(tex: texture_2d_array<f32>, s: sampler, q: vec2<f32>, dx: vec2<f32>, dy: vec2<f32>, bias: f32) -> f32 {
    let cell = canopy_variant(q);
    let uv = canopy_turn(fract(q / CANOPY_SIDE), cell.y, 1.0);
    let k = exp2(bias) / CANOPY_SIDE;
    let gx = canopy_turn(dx * k, cell.y, 0.0);
    let gy = canopy_turn(dy * k, cell.y, 0.0);
    return textureSampleGrad(tex, s, uv, cell.x, gx, gy).r * CANOPY_SCALE;
}
