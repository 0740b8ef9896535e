//! The ranges and checks of `terrain` (the ground) and `field` (the blades).

use super::allowed::{Allowed, Integers, Rule};
use super::Checker;
use crate::error::Result;
use crate::scene::types::{Field, HeightSource, Terrain};

const SIZE: Allowed = Allowed::closed(1.0, 10000.0, "m");
const RESOLUTION: Integers = Integers::new(2, 4097, "vertices per side");
const SEED: Integers = Integers::new(0, u64::MAX, "");
const AMPLITUDE: Allowed = Allowed::closed(0.0, 1000.0, "m");
/// Below a centimetre the noise is finer than any grid the terrain can have; the top is
/// ten times the largest terrain.
const WAVELENGTH: Allowed = Allowed::closed(0.01, 100000.0, "m");
const OCTAVES: Integers = Integers::new(1, 12, "");
const SCALE: Allowed = Allowed::closed(0.0, 1000.0, "m");
const DENSITY: Allowed = Allowed::open_closed(0.0, 10000.0, "blades/m²");
/// The update divides by the height (Eq. 11, 13): a blade of 1e-38 m overflows it, so
/// blades are at least a centimetre tall.
const HEIGHT: Allowed = Allowed::closed(0.01, 10.0, "m");
const WIDTH: Allowed = Allowed::open_closed(0.0, 1.0, "m");
const STIFFNESS: Allowed = Allowed::closed(0.0, 1000.0, "1/s");
const BEND: Allowed = Allowed::closed(0.0, 90.0, "degrees");
const FRACTION: Allowed = Allowed::closed(0.0, 1.0, "");
const TUFT_RADIUS: Allowed = Allowed::open_closed(0.0, 10.0, "m");
const TIP_THRESHOLD: Allowed = Allowed::closed_open(0.0, 1.0, "");
const PATCH_SIZE: Integers = Integers::new(64, 65536, "blades");
const PATCH_SIZE_TEXT: &str =
    "a multiple of 64 (the workgroup size) with 64 <= patch_size <= 65536 blades";
const SEGMENTS: Integers = Integers::new(1, 16, "");
const TILE_SIZE: Allowed = Allowed::closed(0.5, 1000.0, "m");
const TILE_SIZE_TEXT: &str = "0 (the whole field generated at start) or 0.5 <= tile_size <= 1000 m";
const SHARE: Allowed = Allowed::open_closed(0.0, 1000.0, "");
const COLOR: Allowed = Allowed::closed(0.0, 1.0, "");
const CLUMP_SIZE: Allowed = Allowed::closed(0.05, 100.0, "m");
const LEAN: Allowed = Allowed::closed(-60.0, 60.0, "degrees");
const HEAD_SIZE: Allowed = Allowed::closed(0.005, 0.5, "m");
const PETALS: Integers = Integers::new(3, 16, "");
const KINDS_TEXT: &str =
    "a list of 1 to 4 kinds: [(petals: (r, g, b), centre: (r, g, b), petal_count: ..), ...]";
const SPECIES_TEXT: &str = "a list of at most 8 species: [(share: .., height: .., width: .., \
     stiffness: .., color: (r, g, b), shape: ..), ...]";

/// The rules of every `terrain` and `field` value.
pub(super) const RULES: &[(&str, Rule)] = &[
    ("terrain.size", Rule::Real(SIZE)),
    ("terrain.resolution", Rule::Integer(RESOLUTION)),
    (
        "terrain.height",
        Rule::Choice(
            "Flat, Noise(seed: .., amplitude: .., wavelength: .., octaves: ..) or \
             Png(path: \"..\", scale: ..)",
        ),
    ),
    ("terrain.height.seed", Rule::Integer(SEED)),
    ("terrain.height.amplitude", Rule::Real(AMPLITUDE)),
    ("terrain.height.wavelength", Rule::Real(WAVELENGTH)),
    ("terrain.height.octaves", Rule::Integer(OCTAVES)),
    ("terrain.height.path", Rule::Text("the path of a PNG file")),
    ("terrain.height.scale", Rule::Real(SCALE)),
    (
        "terrain.density_map",
        Rule::Text("None or the path of a grey PNG file"),
    ),
    ("terrain.unbounded", Rule::Bool),
    ("field.density", Rule::Real(DENSITY)),
    ("field.height", Rule::Range(HEIGHT)),
    ("field.width", Rule::Range(WIDTH)),
    ("field.stiffness", Rule::Range(STIFFNESS)),
    ("field.bend", Rule::Range(BEND)),
    ("field.tuft_fraction", Rule::Real(FRACTION)),
    ("field.tuft_radius", Rule::Real(TUFT_RADIUS)),
    (
        "field.shape",
        Rule::Choice("one of Quad, Triangle, Quadratic, TriangleTip, Dandelion"),
    ),
    ("field.tip_threshold", Rule::Real(TIP_THRESHOLD)),
    ("field.patch_size", Rule::Text(PATCH_SIZE_TEXT)),
    ("field.segments", Rule::Integer(SEGMENTS)),
    ("field.seed", Rule::Integer(SEED)),
    ("field.tile_size", Rule::Text(TILE_SIZE_TEXT)),
    ("field.species", Rule::Text(SPECIES_TEXT)),
    ("field.species[].share", Rule::Real(SHARE)),
    ("field.species[].height", Rule::Range(HEIGHT)),
    ("field.species[].width", Rule::Range(WIDTH)),
    ("field.species[].stiffness", Rule::Range(STIFFNESS)),
    ("field.species[].color", Rule::Vector(COLOR)),
    (
        "field.species[].shape",
        Rule::Choice("one of Quad, Triangle, Quadratic, TriangleTip, Dandelion"),
    ),
    (
        "field.clumps",
        Rule::Text("None or Some((size: .., align: .., lean: .., color_variation: ..))"),
    ),
    ("field.clumps.size", Rule::Real(CLUMP_SIZE)),
    ("field.clumps.align", Rule::Real(FRACTION)),
    ("field.clumps.lean", Rule::Real(LEAN)),
    ("field.clumps.color_variation", Rule::Real(FRACTION)),
    (
        "field.flowers",
        Rule::Text("None or Some((fraction: .., height: .., head_size: .., kinds: [..]))"),
    ),
    ("field.flowers.fraction", Rule::Real(FRACTION)),
    ("field.flowers.height", Rule::Range(HEIGHT)),
    ("field.flowers.head_size", Rule::Real(HEAD_SIZE)),
    ("field.flowers.kinds", Rule::Text(KINDS_TEXT)),
    ("field.flowers.kinds[].petals", Rule::Vector(COLOR)),
    ("field.flowers.kinds[].centre", Rule::Vector(COLOR)),
    ("field.flowers.kinds[].petal_count", Rule::Integer(PETALS)),
];

pub(super) fn terrain(check: &Checker, terrain: &mut Terrain) -> Result<()> {
    check.real("terrain.size", terrain.size, SIZE)?;
    check.integer("terrain.resolution", terrain.resolution, RESOLUTION)?;
    match &mut terrain.height {
        HeightSource::Noise {
            seed: _,
            amplitude,
            wavelength,
            octaves,
        } => {
            check.real("terrain.height.amplitude", *amplitude, AMPLITUDE)?;
            check.real("terrain.height.wavelength", *wavelength, WAVELENGTH)?;
            check.integer("terrain.height.octaves", *octaves, OCTAVES)?;
        }
        HeightSource::Png { path, scale } => {
            check.image_path("terrain.height.path", path)?;
            check.real("terrain.height.scale", *scale, SCALE)?;
        }
        HeightSource::Flat => {}
    }
    if let Some(map) = &mut terrain.density_map {
        check.image_path("terrain.density_map", map)?;
    }
    Ok(())
}

/// Checks a field's values; `prefix` names it in errors (`field`, `objects[2].grass`).
pub(super) fn field(check: &Checker, prefix: &str, field: &Field) -> Result<()> {
    let at = |name: &str| format!("{prefix}.{name}");
    check.real(&at("density"), field.density, DENSITY)?;
    check.range(&at("height"), field.height, HEIGHT)?;
    check.range(&at("width"), field.width, WIDTH)?;
    check.range(&at("stiffness"), field.stiffness, STIFFNESS)?;
    check.range(&at("bend"), field.bend, BEND)?;
    check.real(&at("tuft_fraction"), field.tuft_fraction, FRACTION)?;
    check.real(&at("tuft_radius"), field.tuft_radius, TUFT_RADIUS)?;
    check.real(&at("tip_threshold"), field.tip_threshold, TIP_THRESHOLD)?;
    // Patches are dispatched as whole workgroups of 64 blades, so a patch must fill them.
    let patch = u64::from(field.patch_size);
    if !(PATCH_SIZE.low..=PATCH_SIZE.high).contains(&patch) || !patch.is_multiple_of(64) {
        let name = at("patch_size");
        return Err(check.error(
            &name,
            format!("{name} = {patch} is out of range: allowed {PATCH_SIZE_TEXT}"),
        ));
    }
    check.integer(&at("segments"), field.segments, SEGMENTS)?;
    // Tiles streamed around the camera, or 0 for the whole field at once.
    let tile = field.tile_size;
    if tile != 0.0 && !(tile.is_finite() && TILE_SIZE.contains(tile)) {
        let name = at("tile_size");
        return Err(check.error(
            &name,
            format!("{name} = {tile} is out of range: allowed {TILE_SIZE_TEXT}"),
        ));
    }
    if field.species.len() > crate::scene::limits::MAX_SPECIES {
        let name = at("species");
        return Err(check.error(
            &name,
            format!(
                "{name} has {} species: allowed {SPECIES_TEXT}",
                field.species.len()
            ),
        ));
    }
    for (k, sp) in field.species.iter().enumerate() {
        let at = |name: &str| format!("{prefix}.species[{k}].{name}");
        check.real(&at("share"), sp.share, SHARE)?;
        check.range(&at("height"), sp.height, HEIGHT)?;
        check.range(&at("width"), sp.width, WIDTH)?;
        check.range(&at("stiffness"), sp.stiffness, STIFFNESS)?;
        check.vector(&at("color"), &[sp.color.0, sp.color.1, sp.color.2], COLOR)?;
    }
    if let Some(f) = &field.flowers {
        check.real(&at("flowers.fraction"), f.fraction, FRACTION)?;
        check.range(&at("flowers.height"), f.height, HEIGHT)?;
        check.real(&at("flowers.head_size"), f.head_size, HEAD_SIZE)?;
        let n = f.kinds.len();
        if n == 0 || n > crate::scene::limits::MAX_FLOWER_KINDS {
            let name = at("flowers.kinds");
            return Err(check.error(&name, format!("{name} has {n} kinds: allowed {KINDS_TEXT}")));
        }
        for (k, kind) in f.kinds.iter().enumerate() {
            let at = |name: &str| format!("{prefix}.flowers.kinds[{k}].{name}");
            let (p, c) = (kind.petals, kind.centre);
            check.vector(&at("petals"), &[p.0, p.1, p.2], COLOR)?;
            check.vector(&at("centre"), &[c.0, c.1, c.2], COLOR)?;
            check.integer(&at("petal_count"), kind.petal_count, PETALS)?;
        }
    }
    if let Some(c) = &field.clumps {
        check.real(&at("clumps.size"), c.size, CLUMP_SIZE)?;
        check.real(&at("clumps.align"), c.align, FRACTION)?;
        check.real(&at("clumps.lean"), c.lean, LEAN)?;
        check.real(&at("clumps.color_variation"), c.color_variation, FRACTION)?;
        // The lean adds to the bend: the sum must stay a lean, not a fold.
        let most = field.bend.max + c.lean;
        if most > 90.0 {
            let name = at("clumps.lean");
            return Err(check.error(
                &name,
                format!(
                    "{name} = {} is out of range: bend.max + lean must stay <= 90 degrees \
                     (bend.max is {})",
                    c.lean, field.bend.max
                ),
            ));
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::super::tests::{check, rejected};
    use crate::scene::Scene;

    #[test]
    fn unbounded_is_a_bool_with_a_rule_and_defaults_to_true() {
        assert!(Scene::default().terrain.unbounded);
        assert_eq!(
            super::super::allowed_for("terrain.unbounded").as_deref(),
            Some("true or false")
        );
        for unbounded in [true, false] {
            let mut scene = Scene::default();
            scene.terrain.unbounded = unbounded;
            check(&mut scene).unwrap();
            assert_eq!(scene.terrain.unbounded, unbounded);
        }
        let parsed: Result<Scene, _> = ron::from_str("(terrain: (unbounded: 3))");
        assert!(parsed.is_err());
    }

    #[test]
    fn tile_size_is_zero_or_in_range() {
        for bad in [-1.0, 0.1, 1001.0, f32::NAN, f32::INFINITY] {
            let m = rejected(|s| s.field.tile_size = bad);
            assert!(m.starts_with("field.tile_size = "), "{m}");
            assert!(m.contains("0 (the whole field generated at start)"), "{m}");
        }
        for good in [0.0, 0.5, 12.0, 1000.0] {
            let mut scene = Scene::default();
            scene.field.tile_size = good;
            check(&mut scene).unwrap();
        }
    }

    #[test]
    fn patch_size_must_fill_workgroups() {
        for bad in [0, 32, 100, 65536 + 64] {
            let m = rejected(|s| s.field.patch_size = bad);
            assert!(m.starts_with("field.patch_size = "), "{m}");
            assert!(m.contains("multiple of 64"), "{m}");
        }
        for good in [64, 128, 65536] {
            let mut scene = Scene::default();
            scene.field.patch_size = good;
            check(&mut scene).unwrap();
        }
    }

    #[test]
    fn terrain_ranges_are_finite() {
        let noise = |amplitude, wavelength| crate::scene::HeightSource::Noise {
            seed: 1,
            amplitude,
            wavelength,
            octaves: 3,
        };
        assert_eq!(
            rejected(|s| s.terrain.height = noise(1.0, 1e38)),
            "terrain.height.wavelength = 100000000000000000000000000000000000000 is out of \
             range: allowed 0.01 <= wavelength <= 100000 m"
        );
        assert_eq!(
            rejected(|s| s.terrain.height = noise(1.0, 1e-38)),
            "terrain.height.wavelength = 0.00000000000000000000000000000000000001 is out of \
             range: allowed 0.01 <= wavelength <= 100000 m"
        );
        assert_eq!(
            rejected(|s| s.field.height.min = 1e-38),
            "field.height.min = 0.00000000000000000000000000000000000001 is out of range: \
             allowed 0.01 <= height.min <= 10 m"
        );
        let m = rejected(|s| {
            s.terrain.height = crate::scene::HeightSource::Png {
                path: "h.png".into(),
                scale: 2000.0,
            }
        });
        assert_eq!(
            m,
            "terrain.height.scale = 2000 is out of range: allowed 0 <= scale <= 1000 m"
        );
    }
}
