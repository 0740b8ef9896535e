// Grass draw: one instance per batch of DRAW_BATCH visible blades (the level's mesh holds a
// batch of blade meshes; the vertex index says which blade of the batch and which vertex of
// it), geometry built in the vertex shader from the blade buffer (Jahrmann & Wimmer Section 6.3): De Casteljau on the Bezier curve (Eq. 21),
// the shape's interpolation parameter (Eq. 22), 3D displacement (Eq. 23) and width
// correction (Eq. 24). The finest level's mesh has 3 columns (u = 0, 0.5, 1), the coarser
// levels' 2 (u = 0, 1; `lod_columns`), and `segments + 1` rows, where each level of detail
// has its own segment count (`CullParams::lod_segments`).
//
// Level changes do not pop: while a blade's projected height falls through the morph band
// above its level's threshold, every vertex slides onto the coarser level's mesh (the
// linear interpolation between the coarser rows around it), so at the threshold the finer
// mesh has the coarser one's shape and the switch moves nothing.
//!include common.wgsl
//!include thinning.wgsl
//!include canopy.wgsl
//!include lod_chord.wgsl
//!include light.wgsl
//!include blade_shade.wgsl
//!include wind.wgsl
//!include wind_sample.wgsl
//!include cwd.wgsl
//!include clumps.wgsl

// Read-only storage, not a uniform: Mesa 22.3's lavapipe recompiles a large shader whose
// branches read a uniform with the uniform's value inlined at every draw and keeps each
// copy until the pipeline is destroyed (about 10 MB a frame); storage is never inlined.
@group(0) @binding(0) var<storage, read> frame: Frame;
@group(0) @binding(1) var<storage, read> blades: array<Blade>;
@group(0) @binding(2) var<storage, read> visible: array<u32>;
@group(0) @binding(3) var<uniform> cull: CullParams;
// x: this draw's level of detail, or FROM_INSTANCE with multi-draw (the level is then the
// instance's region); y: slots per region.
@group(0) @binding(4) var<uniform> draw_level: vec4<u32>;
// The cull's output (also this draw's indirect arguments), for the lists' lengths.
@group(0) @binding(5) var<storage, read> drawn: DrawnBlades;
// The blade models: the update's uniforms (which model, CWD-Sim's parameters, the wind),
// the wind grid (a Cwd blade bends here, from its cell's wind) and the Verlet states
// (a Verlet blade is a cubic through v0, v1, the state's P2 and v2).
@group(0) @binding(6) var<uniform> params: SimParams;
@group(0) @binding(7) var<storage, read> wind_grid: array<vec2<f32>>;
@group(0) @binding(8) var<storage, read> verlet: array<VerletState>;
// The blades' states: η for the trail colour view.
@group(0) @binding(9) var<storage, read> states: array<BladeState>;
// The field's species and clumps: each blade's colour and shape from its root.
@group(0) @binding(10) var<uniform> traits: FieldTraits;

const FROM_INSTANCE: u32 = 0xffffffffu;

// The shadow casters' pipeline (`GrassPipelines::shadow_grass`): the cascade's draw is
// known when the pipeline is built, so the paths it never takes (the finer levels' meshes,
// the morph towards the next level, which evaluates two more blade points per vertex) are
// compiled out; a software rasteriser would run them for every caster vertex.
override CASTER: bool = false;

// Specialisation (render/grass_spec.rs): the scene's switches, given as constants when the
// pipelines are built, so that the paths a scene does not use are compiled away. A CPU
// adapter (llvmpipe) does not jump over an `if`: it runs both sides for the whole SIMD
// batch under a mask, so an unused blade model, blade shape, flower or debug view costs
// every vertex as much as a used one. The defaults keep every path, chosen per blade by
// the uniforms as before; a constant only ever removes a path its uniform would not take.
const ANY: u32 = 0xffffffffu;
// The blade model (MODEL_* of common.wgsl), or ANY: `params.model.x` decides.
override BLADE_MODEL: u32 = 0xffffffffu;
// The blade shape (SHAPE_*), or ANY: the blade's species or `frame.shape.x` decides.
override BLADE_SHAPE: u32 = 0xffffffffu;
// False: the field has one species (every blade's is species 0).
override SPECIES: bool = true;
// False: the field has no clumps (`traits.clumps.x` is 0).
override CLUMPS: bool = true;
// False: the field has no flowers (`traits.flowers.x` is 0).
override FLOWERS: bool = true;
// False: the natural colours only (`frame.debug.x` is 0).
override DEBUG_VIEWS: bool = true;
// Whether blades morph towards the coarser level in the band above each threshold
// (`culling.lod_morph` > 0, `GrassSpec::morph`). A software adapter runs the vertex stage
// on one thread and every branch of it for every vertex: the morph's two more points on
// the curve cost every blade vertex, morphing or not (the window's draw ×0.91 without).
override MORPH: bool = true;
// True: fs_main writes display colour (the scene's exposure and tone curve applied) for a
// host's target (`sward::embed` with `ColorOutput::ToneMapped`); false: linear radiance
// for the tone mapping after the 3D passes.
override DISPLAY_OUTPUT: bool = false;

fn output_color(radiance: vec3<f32>) -> vec4<f32> {
    if DISPLAY_OUTPUT {
        return vec4<f32>(tonemap(radiance), 1.0);
    }
    return vec4<f32>(radiance, 1.0);
}

struct VertexOut {
    // Invariant: the coverage measurement (render/coverage.rs) draws the blades again and
    // needs the same depth to the bit.
    @builtin(position) @invariant clip: vec4<f32>,
    @location(0) world: vec3<f32>,
    @location(1) normal: vec3<f32>,
    @location(2) uv: vec2<f32>,
    // A debug view's colour (w > 0.5; only read with DEBUG_VIEWS).
    @location(3) @interpolate(flat) tint: vec4<f32>,
    // CWD-Sim's Eq. 14 brightness of this vertex (used when frame.debug.y = 1).
    @location(4) shade: f32,
    // The blade's albedo at its root and at its tip (rgb; `blade_albedo`): the colour
    // between them is linear in v, so the fragment interpolates instead of recomputing the
    // species, clump, variation and wave colour of its blade. tip.w: the wave (far flowers).
    @location(5) @interpolate(flat) root: vec4<f32>,
    @location(6) @interpolate(flat) tip: vec4<f32>,
    // Flower heads: x 1 on the head's card (interpolated: the wedge between the stem and the
    // card reads below 0.5), -1 for a far flower drawn as a coloured stem; y, z: the card's
    // coordinates in [-1, 1].
    @location(7) card: vec3<f32>,
    // The flower's petal colour and petal count, and its centre colour.
    @location(8) @interpolate(flat) petals: vec4<f32>,
    @location(9) @interpolate(flat) centre: vec4<f32>,
    // The blade's width direction: the fragment bends the normal along it across the
    // blade (the rounded normal).
    @location(10) side: vec3<f32>,
    // The sky's radiance along the view ray to the blade's root, the colour the fog turns
    // the blade into (`fog_towards`). Once per blade, not per fragment: where the fog is
    // strong the blade is far and spans a sliver of sky, and near the camera, where the
    // sky below the horizon changes fast along a blade, the fog is weak. The same for
    // every vertex of the blade, so a morphing blade's extra vertices match the coarser
    // level's exactly.
    @location(11) @interpolate(flat) sky: vec3<f32>,
    // The sun's visibility through the shadow cascades, looked up per vertex by the lit
    // passes (`vs_lit`): a blade is narrower than a shadow texel, so its vertices along the
    // blade carry the shadow's shape, and the lookup (four filtered comparisons) runs once
    // per vertex instead of once per fragment of the overdrawn grass. 1 in `vs_main`.
    @location(12) sun_lit: f32,
    // The blade's chord (`lod_v`): x the quadratic's `a` its mesh needs (0.5 where the rows
    // follow the curve), y the v the drawn blade starts at.
    @location(13) @interpolate(flat) chord: vec2<f32>,
}

const SHAPE_QUAD: u32 = 0u;
const SHAPE_TRIANGLE: u32 = 1u;
const SHAPE_QUADRATIC: u32 = 2u;
const SHAPE_TRIANGLE_TIP: u32 = 3u;
const SHAPE_DANDELION: u32 = 4u;

// Eq. 22: where between the two edge points c0 and c1 the vertex (u, v) lies.
fn shape_t(shape: u32, u: f32, v: f32, tau: f32, segments: f32) -> f32 {
    switch shape {
        case SHAPE_TRIANGLE: {
            return u + 0.5 * v - u * v;
        }
        case SHAPE_QUADRATIC: {
            return u - u * v * v;
        }
        case SHAPE_TRIANGLE_TIP: {
            return 0.5 + (u - 0.5) * (1.0 - max(v - tau, 0.0) / (1.0 - tau));
        }
        case SHAPE_DANDELION: {
            // A toothed leaf: the width narrows to the tip and swings between teeth. The
            // number of teeth follows the row count so that no tooth falls between rows.
            let teeth = max(floor(segments * 0.5), 1.0);
            let tooth = abs(fract(v * teeth) - 0.5) * 2.0;
            let width = (1.0 - v) * (0.35 + 0.65 * tooth);
            return 0.5 + (u - 0.5) * width;
        }
        default: {
            return u;
        }
    }
}

// A clip-space position in pixels.
fn clip_to_screen(c: vec4<f32>) -> vec2<f32> {
    return (c.xy / max(c.w, 1e-4) * 0.5 + 0.5) * frame.viewport_time.xy;
}

struct BladePoint {
    p: vec3<f32>,
    n: vec3<f32>,
}

// What every point of one blade shares: computed once per vertex and passed to each
// `blade_point` (a morphing vertex evaluates three), so that the frame's trigonometry, the
// shape's species lookup and CWD-Sim's wind sample are not repeated per point.
struct BladeCtx {
    // The width direction and the front (`blade_frame`).
    side: vec3<f32>,
    front: vec3<f32>,
    shape: u32,
    // CWD-Sim's wind at the blade (zero for the other models).
    cwd_wind: vec3<f32>,
    // How many times as wide the thinning draws the blade (`thinning_widen_at`).
    widen: f32,
    // Where the drawn blade starts (its v, `thinned_root_at`): the mesh's rows span v from
    // here to the tip.
    root_v: f32,
    // The width direction in clip space (`frame.view_proj` times (side, 0)). The projection
    // is linear, so a point's two edges, its centre ± the half width along `side`, land at
    // the centre's clip position ± the half width times this: Eq. 24's width in pixels takes
    // one product with the matrix per point instead of two.
    clip_side: vec4<f32>,
}

fn blade_ctx(blade: Blade) -> BladeCtx {
    let axes = blade_frame(blade.up_stiffness.xyz, blade.v0_dir.w);
    // Eq. 20's thinning at the blade's distance (`thinning.wgsl`): its widening and where
    // the drawn blade starts.
    let d = thinning_distance(blade.v0_dir.xyz, blade.up_stiffness.xyz);
    let widen = thinning_widen_at(d, frame.thinning_reach.x, frame.thinning.w);
    let clip_side = frame.view_proj * vec4<f32>(axes[0], 0.0);
    // Seen from above the cards fade out (`canopy_weight`), and nothing stands for the
    // canopy below a cut blade but the far ground's canopy between the blades: the cut goes
    // with the cards (cut, from 19 m up the thinned blades' tips read twice the model).
    // (In 1/4096ths of the blade: a pipeline specialised on the scene, `grass_spec`, rounds
    // the product otherwise, and must draw the very pixels the general one does.)
    let cut = thinned_root_at(d, frame.thinning_reach.x, frame.thinning.w, frame.thinning_reach.y)
        * (1.0 - canopy_weight(blade.v0_dir.xyz, frame.camera_pos.xyz));
    let root_v = round(cut * 4096.0) / 4096.0;
    var ctx = BladeCtx(axes[0], axes[1], blade_shape(blade), vec3<f32>(0.0), widen, root_v, clip_side);
    if blade_model() == MODEL_CWD {
        ctx.cwd_wind = cwd_wind(blade.v0_dir.xyz, blade.v1_height.w);
    }
    return ctx;
}

// The blade model: the specialisation's, else the uniform's.
fn blade_model() -> u32 {
    return select(u32(params.model.x), BLADE_MODEL, BLADE_MODEL != ANY);
}

// The blade's centre line at v and its tangent, by the blade model: Jahrmann's quadratic
// (Eq. 21, De Casteljau), the thesis's cubic (Eq. 5) once the blade has a Verlet state,
// or CWD-Sim's bent straight blade (Eq. 11-13, from the wind of the blade's cell).
fn centre_line(blade: Blade, ctx: BladeCtx, index: u32, v: f32) -> CwdPoint {
    let v0 = blade.v0_dir.xyz;
    let v1 = blade.v1_height.xyz;
    let v2 = blade.v2_width.xyz;
    let model = blade_model();
    if model == MODEL_CWD {
        let up = blade.up_stiffness.xyz;
        let h = blade.v1_height.w;
        return cwd_point(v0, up, ctx.front, h, ctx.cwd_wind, v);
    }
    if model == MODEL_VERLET {
        let s = verlet[index];
        if verlet_owned(s, v0) {
            let p2 = s.p2_dt.xyz;
            let u = 1.0 - v;
            let c = v0 * (u * u * u) + v1 * (3.0 * v * u * u) + p2 * (3.0 * v * v * u) + v2 * (v * v * v);
            let t = 3.0 * (u * u * (v1 - v0) + 2.0 * u * v * (p2 - v1) + v * v * (v2 - p2));
            return CwdPoint(c, t);
        }
    }
    let a = v0 + v * (v1 - v0);
    let b = v1 + v * (v2 - v1);
    return CwdPoint(a + v * (b - a), b - a);
}

// The blade's shape: its species' when the field lists species, else the field's.
fn blade_shape(blade: Blade) -> u32 {
    if BLADE_SHAPE != ANY {
        return BLADE_SHAPE;
    }
    let s = traits.species[species_of(blade.v0_dir.x, blade.v0_dir.z)];
    return select(u32(frame.shape.x), u32(s.attrs.w), s.color.w > 0.5);
}

// The blade's distance from the culling camera across its up axis, as Eq. 20's cull
// measures it.
fn thinning_distance(v0: vec3<f32>, up: vec3<f32>) -> f32 {
    let rel = v0 - frame.thinning.xyz;
    return length(rel - up * dot(rel, up));
}

// The flat blade's normal from Eq. 21's tangent `t` and the width direction `side` (the
// blade's `up` where the tangent vanishes). Only the tangent's direction matters: the
// normal is normalised after the product.
fn flat_normal(t: vec3<f32>, up: vec3<f32>, side: vec3<f32>) -> vec3<f32> {
    let t0 = select(t, up, dot(t, t) < 1e-12);
    return normalize(cross(t0, side));
}

// The vertex at (u, v) of a blade: Eq. 21-24.
fn blade_point(blade: Blade, ctx: BladeCtx, index: u32, u: f32, v: f32, fold: f32) -> BladePoint {
    let widen = ctx.widen;
    let half_width = 0.5 * blade.v2_width.w * widen;
    let up = blade.up_stiffness.xyz;
    // Eq. 21: the curve point c and the tangent t0.
    let centre = centre_line(blade, ctx, index, v);
    let c = centre.p;
    let t1 = ctx.side;
    let c0 = c - half_width * t1;
    let c1 = c + half_width * t1;
    let n = flat_normal(centre.t, up, t1);

    // The dandelion's teeth follow the full mesh's rows at every level.
    var t = shape_t(ctx.shape, u, v, frame.shape.y, frame.shape.z);
    // Eq. 24: thin far blades become quads so their tips do not break into pixel noise.
    // The paper prints t(1 - Phi) + u Phi^2; we blend linearly, which meets the same two
    // limits (Phi = 0: the shape, Phi = 1: the quad) without the dip in between.
    if frame.width_correction.y > 0.0 {
        // The blade's own width, before the thinning widens it: the widened blades stand
        // for the full field's, and keep the shape those would have.
        let centre_clip = frame.view_proj * vec4<f32>(c, 1.0);
        let edge = half_width * ctx.clip_side;
        let wp = length(clip_to_screen(centre_clip + edge) - clip_to_screen(centre_clip - edge)) / widen;
        let phi = 1.0 - min(max((wp - frame.width_correction.x) / frame.width_correction.y, 0.0), 1.0);
        t = t * (1.0 - phi) + u * phi;
    }
    var p = (1.0 - t) * c0 + t * c1;
    // Eq. 23, d = w n (0.5 - |u - 0.5| (1 - v)): the middle axis moves along the normal
    // by half the width at the root, a "v" cross-section with a right angle (the unfolded
    // width grows by √2) that flattens towards the tip.
    // `fold` 1 flattens the fold: the middle axis lies between the edges, as on the
    // coarser levels' two-column meshes (`lod_columns`); the edges do not move.
    if frame.shape.w > 0.5 {
        p += blade.v2_width.w * n * (0.5 - mix(abs(u - 0.5), 0.5, fold) * (1.0 - v));
    }
    // The flat blade's normal: the fragment rounds it across the width.
    return BladePoint(p, n);
}

// Columns of the blade mesh at `level` (twin of `mesh::lod_columns`): the finest level
// keeps the middle axis that the 3D displacement folds the blade along (Eq. 23); the
// coarser levels, a few pixels wide, are flat, with two columns and half the triangles
// (every blade shape is linear across the width, so the middle vertex lies between the
// edges anyway: only the fold is lost).
//
// Without the 3D displacement (`render.displacement: false`, `GrassSpec::fold`) the middle
// column lies between the edges at every level, so the finest level is flat too: half its
// triangles and two thirds of its vertices, the same surface (`mesh::LodMeshes::levels`).
override FOLD: bool = true;

fn lod_columns(level: u32) -> u32 {
    return select(2u, 3u, level == 0u && FOLD);
}

// How far a blade drawn at `level` has morphed towards level + 1: 0 above the morph band,
// 1 at the threshold where the cull pass hands it to the coarser level.
fn morph_factor(level: u32, h_px: f32) -> f32 {
    if level >= 2u || cull.lod.w <= 0.0 {
        return 0.0;
    }
    let threshold = select(cull.lod.z, cull.lod.y, level == 0u);
    return clamp(1.0 - (h_px - threshold) / (threshold * cull.lod.w), 0.0, 1.0);
}

// The quadratic's `a` (`chord_shape`) of a straight segment from `p0` to `p1` standing for
// the centre line through `pm` (its point halfway in v): where `pm` projects onto it.
fn segment_shape(p0: vec3<f32>, pm: vec3<f32>, p1: vec3<f32>) -> f32 {
    let d = p1 - p0;
    let dd = dot(d, d);
    return chord_shape(select(0.5, dot(pm - p0, d) / dd, dd > 1e-12));
}

// The coarsest mesh's chord code (`lod_v`, lod_chord.wgsl) for its `segments` (1 or 2)
// from `root_v` to the tip, each segment's shape taken `share` of the way from the
// identity (the level before it, morphing). The centre line is evaluated once per point
// the segments share.
fn blade_chord_code(blade: Blade, ctx: BladeCtx, index: u32, root_v: f32, segments: u32, share: f32) -> f32 {
    let span = 1.0 - root_v;
    let p0 = centre_line(blade, ctx, index, root_v).p;
    let mid = centre_line(blade, ctx, index, root_v + 0.5 * span).p;
    let p1 = centre_line(blade, ctx, index, 1.0).p;
    if segments <= 1u {
        return chord_code_one(mix(0.5, segment_shape(p0, mid, p1), share));
    }
    let q0 = centre_line(blade, ctx, index, root_v + 0.25 * span).p;
    let q1 = centre_line(blade, ctx, index, root_v + 0.75 * span).p;
    let a0 = mix(0.5, segment_shape(p0, q0, mid), share);
    let a1 = mix(0.5, segment_shape(mid, q1, p1), share);
    return chord_code_two(a0, a1);
}

// The depth-only passes (shadow casters, the coverage measurement): no light bound.
@vertex
fn vs_main(@builtin(vertex_index) batch_vid: u32, @builtin(instance_index) inst: u32) -> VertexOut {
    var out = blade_vertex(batch_vid, inst).out;
    out.sun_lit = 1.0;
    return out;
}

// The lit passes: the blade's vertex, its colours, the sun's visibility at it and the sky
// behind it.
@vertex
fn vs_lit(@builtin(vertex_index) batch_vid: u32, @builtin(instance_index) inst: u32) -> VertexOut {
    let b = blade_vertex(batch_vid, inst);
    var out = b.out;
    let albedo = blade_albedos(b.index, blades[b.index]);
    out.root = vec4<f32>(albedo.root, 0.0);
    out.tip = albedo.tip;
    out.sun_lit = sun_visibility(out.world);
    out.sky = blade_sky(b.root);
    return out;
}

// The sky's radiance along the view ray to a blade's root: the colour the fog turns the
// whole blade into (`VertexOut::sky`).
fn blade_sky(root: vec3<f32>) -> vec3<f32> {
    return sky_radiance(normalize(root - frame.camera_pos.xyz));
}

// A blade's random draws: its colour variation (and the debug views' tint).
fn blade_tint(index: u32) -> vec3<f32> {
    return vec3<f32>(hash01(index), hash01(index ^ 0x9e3779b9u), hash01(index * 3u + 17u));
}

// A blade's albedo at its root and at its tip (`blade_albedo`; tip.w: the shading wave).
struct BladeAlbedo {
    root: vec3<f32>,
    tip: vec4<f32>,
}

// The albedos of blade `index`, made of its random draws, its species' colour, its clump's
// brightness and how far it is bent from its rest pose (the wind's gusts as they run over
// the field). The lit vertex stage and the deferred shading (`grass_deferred.wgsl`) both
// make them here.
fn blade_albedos(index: u32, blade: Blade) -> BladeAlbedo {
    let v0 = blade.v0_dir.xyz;
    var species_color = traits.species[0].color;
    if SPECIES {
        species_color = traits.species[species_of(v0.x, v0.z)].color;
    }
    var clump_light = 1.0;
    if CLUMPS && traits.clumps.x > 0.0 {
        clump_light = 1.0 + traits.clumps.w * (clump_of(v0.x, v0.z).tint - 0.5);
    }
    let base = blade_base_albedo(blade_tint(index), species_color, clump_light);
    let rest_tip = states[index].rest_eta.xyz;
    let gust = length(blade.v2_width.xyz - rest_tip) / max(blade.v1_height.w, 1e-4);
    // Shading waves: a blade the gusts bend away from its rest shows its paler, glossier
    // side, so the gusts read as bright bands running over the field.
    let wave = clamp(gust * 1.5, 0.0, 1.0) * light.shading_b.y;
    return BladeAlbedo(blade_albedo(base, 0.0, wave), vec4<f32>(blade_albedo(base, 1.0, wave), wave));
}

// Eq. 14 (CWD-Sim's self-shadowing) at point p of a blade: its height above the root after
// the deformation (in blade heights) minus the blade's bend times c1 (0 upright, 1 pressed
// flat: how far the tip has sunk from its full height), plus c2, clamped to [m_min, m_max].
fn blade_self_shade(blade: Blade, p: vec3<f32>) -> f32 {
    let v0 = blade.v0_dir.xyz;
    let up = blade.up_stiffness.xyz;
    let h = max(blade.v1_height.w, 1e-4);
    let bend = clamp(1.0 - dot(blade.v2_width.xyz - v0, up) / h, 0.0, 1.0);
    let s = frame.self_shadow;
    return clamp(dot(p - v0, up) / h - bend * s.z + s.w, s.x, s.y);
}

// A blade's vertex and what its colours are made of (the lit passes make them).
struct BladeVertex {
    out: VertexOut,
    // The blade's index in the blade buffer.
    index: u32,
    // Where the blade is rooted.
    root: vec3<f32>,
}

fn blade_vertex(batch_vid: u32, inst: u32) -> BladeVertex {
    var b: BladeVertex;
    // The slot in the visible list: the instance's batch, the blade in the batch.
    var level = draw_level.x;
    // A sun's shadow cascade (frame.debug.z: the grass's shadow radius): every blade as one
    // triangle from its root to its tip (`CASTER_VERTICES`), out to the radius.
    let shadow_pass = CASTER || frame.debug.z > 0.0;
    // Multi-draw: the level is the region the batch lies in (the regions are whole batches,
    // so a batch never straddles two of them). One draw per level binds its region at an
    // offset, and its slots count from 0.
    var region_start = 0u;
    if level == FROM_INSTANCE {
        let region = max(draw_level.y, 1u);
        let first = inst * DRAW_BATCH;
        level = select(select(0u, 1u, first >= region), 2u, first >= 2u * region);
        region_start = level * region;
    }
    let mesh_level = select(level, 2u, shadow_pass);
    // The caster's one row spans the blade, whatever the coarsest level's rows.
    let rows = select(max(cull.lod_segments[mesh_level], 1u), 1u, shadow_pass);
    let cols = lod_columns(mesh_level);
    let per_blade = select(cols * (rows + 1u), CASTER_VERTICES, shadow_pass);
    let in_batch = div_small(batch_vid, per_blade);
    let slot = inst * DRAW_BATCH + in_batch;
    let rel = slot - region_start;
    let vid = batch_vid - in_batch * per_blade;
    // The last batch of a list runs past its end: those slots hold stale indices and draw
    // nothing (a degenerate triangle outside the clip volume).
    let early = drawn.early[level];
    let late_from = late_start(early);
    if rel >= early && (rel < late_from || rel >= late_from + drawn.late[level]) {
        var none: VertexOut;
        none.clip = vec4<f32>(0.0, 0.0, 2.0, 1.0);
        b.out = none;
        return b;
    }
    let index = visible[slot];
    b.index = index;
    let blade = blades[index];
    let v0 = blade.v0_dir.xyz;
    if shadow_pass && distance(v0, frame.camera_pos.xyz) > frame.debug.z {
        var none: VertexOut;
        none.clip = vec4<f32>(0.0, 0.0, 2.0, 1.0);
        b.out = none;
        return b;
    }
    let row = div_small(vid, cols);
    let col = vid - row * cols;
    var u = f32(col) / f32(cols - 1u);
    // A caster's third vertex is the tip, at the middle of the width.
    if shadow_pass && vid == 2u {
        u = 0.5;
    }
    var v = f32(row) / f32(rows);
    // A flower (thesis §3.3): with 3 rows or more, the top two rows are its head, a card
    // facing up at the stem's tip, and the stem takes the rows below; coarser, the stem is
    // drawn with the head's colour at its top.
    let flower = FLOWERS && is_flower(v0.x, v0.z);
    let head = flower && rows >= 3u;
    var card = vec3<f32>(0.0);
    if head {
        v = min(f32(row) / f32(rows - 2u), 1.0);
    } else if flower {
        card.x = -1.0;
    }
    let ctx = blade_ctx(blade);
    // A thinned blade is drawn from `ctx.root_v` up (`thinned_root_at`); a flower keeps its
    // stem whole under its head.
    let root_v = select(ctx.root_v, 0.0, flower);
    v = root_v + (1.0 - root_v) * v;
    var point = blade_point(blade, ctx, index, u, v, 0.0);
    if head && row >= rows - 1u {
        let a = (u - 0.5) * 2.0;
        let b = select(-1.0, 1.0, row == rows);
        let size = traits.flowers.w;
        point.p = point.p + size * (ctx.side * a + ctx.front * b);
        point.n = blade.up_stiffness.xyz;
        card = vec3<f32>(1.0, a, b);
    }

    let h_px = projected_height(v0, blade.v1_height.w, cull);
    let morph = select(morph_factor(level, h_px), 0.0, flower || shadow_pass || !MORPH);
    if MORPH && morph > 0.0 {
        // The coarser rows around this one, in exact integer arithmetic so a row the two
        // levels share is its own target; on a coarser level without the middle axis the
        // target is flat across the width (fold 1), so the middle column unfolds.
        let coarse = max(cull.lod_segments[level + 1u], 1u);
        let fold = select(0.0, 1.0, lod_columns(level + 1u) == 2u);
        let num = row * coarse;
        let below = div_small(num, rows);
        let rem = num - below * rows;
        let v_below = root_v + (1.0 - root_v) * f32(below) / f32(coarse);
        var coarse_point = blade_point(blade, ctx, index, u, v_below, fold);
        if rem != 0u {
            let f = f32(rem) / f32(rows);
            let v_above = root_v + (1.0 - root_v) * f32(below + 1u) / f32(coarse);
            let b = blade_point(blade, ctx, index, u, v_above, fold);
            coarse_point = BladePoint(mix(coarse_point.p, b.p, f), normalize(mix(coarse_point.n, b.n, f)));
        }
        if rem != 0u || (fold > 0.5 && cols == 3u && col == 1u) {
            point.p = mix(point.p, coarse_point.p, morph);
            point.n = normalize(mix(point.n, coarse_point.n, morph));
        }
    }

    var out: VertexOut;
    out.clip = frame.view_proj * vec4<f32>(point.p, 1.0);
    out.world = point.p;
    out.normal = point.n;
    out.uv = vec2<f32>(u, v);
    // The coarsest level's segments are straight, v runs linearly along each (`lod_v`); the
    // level before it goes over to them as it morphs. The finer rows lie on the curve.
    out.chord = vec2<f32>(chord_code_one(0.5), root_v);
    let chord_share = select(select(0.0, morph, level == 1u), 1.0, level >= 2u);
    if !shadow_pass && !flower && chord_share > 0.0 {
        out.chord.x = blade_chord_code(blade, ctx, index, root_v, cull.lod_segments[2], chord_share);
    }
    out.card = card;
    out.side = ctx.side;
    b.root = v0;
    if flower {
        let k = flower_kind(v0.x, v0.z);
        out.petals = traits.flower_kinds[2u * k];
        out.centre = traits.flower_kinds[2u * k + 1u];
    }
    out.shade = blade_self_shade(blade, point.p);
    out.tint = vec4<f32>(blade_tint(index), 0.0);
    // Debug colours: the level of detail (with the morph towards the next), or the patch.
    let mode = select(0u, u32(frame.debug.x), DEBUG_VIEWS);
    if mode == 1u {
        out.tint = vec4<f32>((f32(level) + morph) / 2.0, 0.0, 0.0, 1.0);
    } else if mode == 2u {
        let patch_id = index / max(u32(frame.debug.w), 1u);
        out.tint = vec4<f32>(hash01(patch_id * 7u + 1u), hash01(patch_id * 13u + 5u), hash01(patch_id * 29u + 11u), 2.0);
    } else if mode == 3u {
        // The trail view: η through the same green-to-red ramp as the levels.
        out.tint = vec4<f32>(clamp(states[index].rest_eta.w, 0.0, 1.0), 0.0, 0.0, 1.0);
    }
    b.out = out;
    return b;
}

// A blade's colour before the light: between fresh, deep and dry-ish green by its random
// draws `tint` (or its species' colour a little lighter or darker) and its clump's
// brightness; at variation strength 0 every blade has the mean colour.
fn blade_base_albedo(tint: vec3<f32>, species_color: vec4<f32>, clump_light: f32) -> vec3<f32> {
    let variation = light.shading_b.x;
    let fresh = vec3<f32>(0.10, 0.34, 0.05);
    let dry = vec3<f32>(0.32, 0.40, 0.09);
    let deep = vec3<f32>(0.05, 0.22, 0.04);
    let own = mix(mix(fresh, deep, tint.y * 0.7), dry, tint.x * tint.x * 0.8);
    let mean = mix(mix(fresh, deep, 0.35), dry, 0.27);
    var albedo = mix(mean, own, variation);
    if species_color.w > 0.5 {
        albedo = species_color.rgb * mix(1.0, mix(0.8, 1.2, tint.y), variation);
    }
    return albedo * mix(1.0, clump_light, variation);
}

// The albedo at v along a blade of base colour `base`: lighter towards the tip, where the
// blade is young and thin, and paler by the shading wave `wave`. Linear in v.
fn blade_albedo(base: vec3<f32>, v: f32, wave: f32) -> vec3<f32> {
    let a = mix(base * 0.55, base * 1.25 + vec3<f32>(0.03, 0.04, 0.0), v);
    return mix(a, a * 1.7 + vec3<f32>(0.04, 0.05, 0.02), wave * 0.6);
}

// The flat, lightly shaded colour of the debugging views: a green-to-red ramp over the
// levels of detail, or the patch's random colour.
fn debug_color(tint: vec4<f32>, n: vec3<f32>, sun: vec3<f32>, v: f32) -> vec3<f32> {
    var c = tint.rgb;
    if tint.w < 1.5 {
        let x = tint.r;
        c = vec3<f32>(min(2.0 * x, 1.0), min(2.0 * (1.0 - x), 1.0), 0.1);
    }
    let light = 0.55 + 0.45 * max(dot(n, sun), 0.0);
    return c * light * mix(0.6, 1.0, v);
}

@fragment
fn fs_main(in: VertexOut) -> @location(0) vec4<f32> {
    let sun = frame.sun_dir.xyz;
    let to_eye = normalize(frame.camera_pos.xyz - in.world);
    // Two-sided: light the side that faces the viewer (by the normal itself: the mesh's
    // winding does not say which side of a blade its normal points to).
    var flat_n = normalize(in.normal);
    if dot(flat_n, to_eye) < 0.0 {
        flat_n = -flat_n;
    }
    let v = lod_v(in.uv.y, in.chord);
    if DEBUG_VIEWS && in.tint.w > 0.5 {
        // A debug colour is a display colour: alpha 0 keeps tone mapping off it.
        return vec4<f32>(debug_color(in.tint, flat_n, sun, v), 0.0);
    }
    let lit = in.sun_lit;
    // A flower head: petals around a centre, cut out of the card (a procedural texture:
    // the petal edge swings with the angle, petal_count lobes).
    if FLOWERS && in.card.x > 0.5 {
        let r = length(in.card.yz);
        let theta = atan2(in.card.z, in.card.y);
        let edge = 0.45 + 0.55 * abs(cos(0.5 * in.petals.w * theta));
        if r > edge {
            discard;
        }
        let c = select(in.petals.rgb * mix(0.85, 1.0, r), in.centre.rgb, r < 0.3);
        let head_light = light.ambient.rgb * 0.9 + light.sun.rgb * (abs(dot(flat_n, sun)) * 0.9 * lit);
        return output_color(fog_towards(c * head_light, in.world, in.sky));
    }
    var albedo = mix(in.root.rgb, in.tip.rgb, v);
    if FLOWERS && in.card.x < -0.5 && v > 0.6 {
        // A far flower: its head's colour at the top of the stem.
        albedo = blade_albedo(in.petals.rgb, v, in.tip.w);
    }
    let color = shade_blade(in.world, flat_n, in.side, vec2<f32>(in.uv.x, v), albedo, lit, in.shade);
    return output_color(fog_towards(color, in.world, in.sky));
}
