// Species and clumps as pure functions of a blade's root (issue 15, point 5): shared by
// the tile kernel (`tile_gen.wgsl`: the species' ranges, the clump's facing and lean) and
// the grass draw (`grass.wgsl`: the species' colour and shape, the clump's tint). Expects
// `traits: FieldTraits` bound by the including shader. The twin is `field::clumps`, whose
// module comment has the model.

struct Species {
    // Height min, span; width min, span.
    sizes: vec4<f32>,
    // Stiffness min, span; cumulative share; shape id.
    attrs: vec4<f32>,
    // Linear RGB; w: 1 = this colour, 0 = sward's own palette.
    color: vec4<f32>,
}

struct FieldTraits {
    // Clump spacing (0: none), align, lean (radians), colour variation.
    clumps: vec4<f32>,
    // Species count, seed.
    info: vec4<u32>,
    species: array<Species, 8>,
    // Flowers: share of blades (0: none), stem height min, span, head radius.
    flowers: vec4<f32>,
    // Flowers: kind count.
    flower_info: vec4<u32>,
    // Per kind: petal RGB + petal count, centre RGB.
    flower_kinds: array<vec4<f32>, 8>,
}

const STEM_WIDTH: f32 = 0.006;
const SALT_FLOWER: u32 = 0x7feb352du;
const SALT_KIND: u32 = 0x846ca68bu;

const CLUMP_UNIT: f32 = 1.0 / 16777216.0;
const SALT_ANGLE: u32 = 0x68bc21ebu;
const SALT_TINT: u32 = 0x02e5be93u;
const SALT_SPECIES: u32 = 0x1b873593u;

struct Clump {
    hash: u32,
    angle: f32,
    tint: f32,
}

fn clump_unit(h: u32) -> f32 {
    return f32(h >> 8u) * CLUMP_UNIT;
}

// The clump of the root (x, z): the nearest of the jittered centres of the 3 x 3 cells
// around it (`clumps::clump_of`).
fn clump_of(x: f32, z: f32) -> Clump {
    let size = traits.clumps.x;
    let gx = i32(floor(x / size));
    let gz = i32(floor(z / size));
    var best = 3.4e38;
    var best_hash = 0u;
    for (var dz = -1; dz <= 1; dz++) {
        for (var dx = -1; dx <= 1; dx++) {
            let cx = gx + dx;
            let cz = gz + dz;
            let h = hash32(traits.info.y ^ hash32(bitcast<u32>(cx) ^ rotl17(hash32(bitcast<u32>(cz)))));
            let px = (f32(cx) + clump_unit(h)) * size;
            let pz = (f32(cz) + clump_unit(hash32(h))) * size;
            let d = (px - x) * (px - x) + (pz - z) * (pz - z);
            if d < best {
                best = d;
                best_hash = h;
            }
        }
    }
    return Clump(best_hash, clump_unit(hash32(best_hash ^ SALT_ANGLE)) * TAU, clump_unit(hash32(best_hash ^ SALT_TINT)));
}

// The species of the root (x, z) (`clumps::species_of`).
fn species_of(x: f32, z: f32) -> u32 {
    let n = clamp(traits.info.x, 1u, 8u);
    if n == 1u {
        return 0u;
    }
    var h: u32;
    if traits.clumps.x > 0.0 {
        h = hash32(clump_of(x, z).hash ^ SALT_SPECIES);
    } else {
        h = hash32(traits.info.y ^ hash32(bitcast<u32>(x) ^ rotl17(hash32(bitcast<u32>(z)))));
    }
    let u = clump_unit(h);
    for (var k = 0u; k < n; k++) {
        if u < traits.species[k].attrs.z {
            return k;
        }
    }
    return n - 1u;
}

fn root_hash(x: f32, z: f32, salt: u32) -> u32 {
    return hash32(traits.info.y ^ salt ^ hash32(bitcast<u32>(x) ^ rotl17(hash32(bitcast<u32>(z)))));
}

// Whether the blade rooted at (x, z) is a flower stem (`clumps::is_flower`).
fn is_flower(x: f32, z: f32) -> bool {
    return traits.flowers.x > 0.0 && clump_unit(root_hash(x, z, SALT_FLOWER)) < traits.flowers.x;
}

// The kind of the flower rooted at (x, z) (`clumps::flower_kind`).
fn flower_kind(x: f32, z: f32) -> u32 {
    let n = clamp(traits.flower_info.x, 1u, 4u);
    return root_hash(x, z, SALT_KIND) % n;
}

struct BladeTraits {
    angle: f32,
    height: f32,
    width: f32,
    stiffness: f32,
    bend: f32,
}

// A blade's attributes from its root and its uniform draws (height, width, stiffness):
// the species' ranges, and with clumps the facing turned towards the clump's direction by
// `align` and the bend grown by `lean` (`clumps::blade_traits`).
fn blade_traits(x: f32, z: f32, angle: f32, bend: f32, draws: vec3<f32>) -> BladeTraits {
    let s = traits.species[species_of(x, z)];
    var t = BladeTraits(angle, s.sizes.x + s.sizes.y * draws.x, s.sizes.z + s.sizes.w * draws.y, s.attrs.x + s.attrs.y * draws.z, bend);
    // A flower stem: the flowers' height, thin.
    if is_flower(x, z) {
        t.height = traits.flowers.y + traits.flowers.z * draws.x;
        t.width = STEM_WIDTH;
    }
    if traits.clumps.x > 0.0 {
        let c = clump_of(x, z);
        t.angle = c.angle + (angle - 0.5 * TAU) * (1.0 - traits.clumps.y);
        t.bend = bend + traits.clumps.z;
    }
    return t;
}
