//! Property test of the scene's first line of defence: random values — NaN, ±inf, huge,
//! tiny, negative, zero and ordinary — in the numeric fields of a small scene either end in
//! a scene error that names the field and its allowed range, or validate into a scene whose
//! blades stay finite through a few steps of the CPU twin of the update.

use std::collections::BTreeMap;
use std::path::Path;

use proptest::prelude::*;
use sward::commands::simulate_cpu;
use sward::scene::parse_scene;
use sward::session::Session;
use sward::Error;

/// Float fields the test varies (the ones a step of the update or the wind reads, and the
/// rest of the numeric fields for the validation).
const REALS: &[&str] = &[
    "terrain.size",
    "terrain.height.amplitude",
    "terrain.height.wavelength",
    "field.density",
    "field.height.min",
    "field.height.max",
    "field.width.min",
    "field.width.max",
    "field.stiffness.min",
    "field.stiffness.max",
    "field.bend.min",
    "field.bend.max",
    "field.tuft_fraction",
    "field.tuft_radius",
    "field.tip_threshold",
    "wind.directional.strength",
    "wind.directional.gust",
    "wind.directional.wavelength",
    "wind.directional.speed",
    "wind.point.strength",
    "wind.point.radius",
    "wind.point.frequency",
    "wind.fluid.vorticity",
    "wind.fluid.dissipation",
    "wind.fluid.viscosity",
    "wind.fluid.response",
    "wind.global.strength",
    "wind.downwash.radius",
    "wind.downwash.strength",
    "physics.gravity_acceleration",
    "physics.gravity_center_acceleration",
    "physics.gravity_blend",
    "physics.mass",
    "physics.collision_decay",
    "physics.collision_gain",
    "physics.max_collision_strength",
    "physics.stiffness_scale",
    "physics.max_dt",
    "culling.orientation_threshold",
    "culling.frustum_tolerance",
    "culling.max_distance",
    "culling.lod_near_px",
    "culling.lod_far_px",
    "culling.lod_morph",
    "culling.physics_radius",
    "camera.fov_y",
    "camera.near",
    "camera.far",
    "render.width_min_px",
    "render.width_span_px",
    "colliders.radius",
];

/// Vector fields: every component gets a value.
const VECTORS: &[&str] = &[
    "wind.point.position",
    "wind.downwash.position",
    "physics.gravity_center",
    "camera.eye",
    "camera.target",
    "colliders.center",
    "colliders.velocity",
];

/// Unsigned integer fields (the fluid's resolution stays small so that a case is cheap).
const INTEGERS: &[&str] = &[
    "terrain.resolution",
    "terrain.height.octaves",
    "field.segments",
    "field.patch_size",
    "wind.fluid.pressure_iterations",
    "wind.fluid.diffusion_iterations",
    "culling.distance_levels",
    "culling.physics_throttle",
];

/// The small scene every case starts from: 200 blades, every wind on, a moving collider.
fn base() -> BTreeMap<String, String> {
    [
        ("terrain.size", "4.0"),
        ("terrain.resolution", "9"),
        ("field.density", "20.0"),
        ("wind.fluid.resolution", "16"),
        ("wind.fluid.pressure_iterations", "8"),
        ("wind.point.strength", "6.0"),
        ("wind.global.direction", "(1.0, 0.0)"),
        ("wind.global.strength", "2.0"),
        ("wind.downwash.position", "(0.0, 2.0, 0.0)"),
        ("wind.downwash.radius", "2.0"),
        ("wind.downwash.strength", "10.0"),
        ("colliders.center", "(0.0, 0.3, 0.0)"),
        ("colliders.radius", "0.4"),
        ("colliders.velocity", "(0.5, 0.0, 0.0)"),
    ]
    .into_iter()
    .map(|(k, v)| (k.to_owned(), v.to_owned()))
    .collect()
}

fn real() -> impl Strategy<Value = f32> {
    // Ordinary values often enough that many cases validate and reach the update.
    prop_oneof![
        1 => Just(f32::NAN),
        1 => Just(f32::INFINITY),
        1 => Just(f32::NEG_INFINITY),
        1 => Just(1e38f32),
        1 => Just(-1e38f32),
        1 => Just(1e-38f32),
        1 => Just(0.0f32),
        1 => Just(-1.0f32),
        1 => Just(1e6f32),
        8 => 0.0f32..10.0,
        3 => -100.0f32..100.0,
        2 => 0.0f32..1000.0,
    ]
}

/// RON text of an integer value, including ones no unsigned field can hold.
fn integer() -> impl Strategy<Value = String> {
    prop_oneof![
        Just("0".to_owned()),
        Just("-1".to_owned()),
        Just("99999999999".to_owned()),
        Just("64".to_owned()),
        Just("4096".to_owned()),
        (1u32..20).prop_map(|n| n.to_string()),
    ]
}

fn ron_float(x: f32) -> String {
    // `{:?}` writes NaN, inf, -inf and 1e38 as RON reads them.
    format!("{x:?}")
}

/// One case: field → RON value text, on top of [`base`].
fn changes() -> impl Strategy<Value = Vec<(String, String)>> {
    let reals = proptest::sample::select(REALS)
        .prop_flat_map(|f| real().prop_map(move |x| (f.to_owned(), ron_float(x))));
    let vectors = proptest::sample::select(VECTORS).prop_flat_map(|f| {
        (real(), real(), real()).prop_map(move |(x, y, z)| {
            let text = format!("({}, {}, {})", ron_float(x), ron_float(y), ron_float(z));
            (f.to_owned(), text)
        })
    });
    let integers = proptest::sample::select(INTEGERS)
        .prop_flat_map(|f| integer().prop_map(move |v| (f.to_owned(), v)));
    let source = prop_oneof![Just("Analytic"), Just("Fluid"), Just("Both")]
        .prop_map(|s| ("wind.source".to_owned(), s.to_owned()));
    let one = prop_oneof![4 => reals, 2 => vectors, 1 => integers, 1 => source];
    proptest::collection::vec(one, 1..6)
}

/// A tree of sections built from dotted paths, written as RON.
#[derive(Default)]
struct Node {
    value: Option<String>,
    children: BTreeMap<String, Node>,
}

impl Node {
    fn insert(&mut self, path: &str, value: String) {
        match path.split_once('.') {
            Some((head, rest)) => self
                .children
                .entry(head.to_owned())
                .or_default()
                .insert(rest, value),
            None => self.children.entry(path.to_owned()).or_default().value = Some(value),
        }
    }

    fn write(&self, name: &str) -> String {
        if let Some(v) = &self.value {
            return v.clone();
        }
        let fields: Vec<String> = self
            .children
            .iter()
            .map(|(k, c)| format!("{k}: {}", c.write(k)))
            .collect();
        // The terrain's height is an enum: its fields belong to the Noise variant.
        let noise = ["amplitude", "wavelength", "octaves"];
        let variant = if name == "height" && noise.iter().any(|k| self.children.contains_key(*k)) {
            "Noise"
        } else {
            ""
        };
        format!("{variant}({})", fields.join(", "))
    }
}

/// The scene text for `values` (the collider's pseudo-fields become a one-element list).
fn scene_text(values: &BTreeMap<String, String>) -> String {
    let mut root = Node::default();
    let mut collider = Vec::new();
    for (path, value) in values {
        match path.strip_prefix("colliders.") {
            Some("velocity") => collider.push(format!("motion: Velocity({value})")),
            Some(key) => collider.push(format!("{key}: {value}")),
            None => root.insert(path, value.clone()),
        }
    }
    let mut text = root.write("");
    text.insert_str(1, &format!("colliders: [({})], ", collider.join(", ")));
    text
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(256))]

    #[test]
    fn scenes_validate_or_stay_finite(changes in changes()) {
        let mut values = base();
        for (path, value) in changes {
            values.insert(path, value);
        }
        let text = scene_text(&values);
        match parse_scene(&text, Path::new("props.ron")) {
            Err(Error::Scene { message, .. }) => {
                prop_assert!(message.contains("allowed"), "{text}\n{message}");
            }
            Err(other) => prop_assert!(false, "{text}\nnot a scene error: {other}"),
            Ok(scene) => {
                if std::env::var_os("SWARD_PROPS_SHOW").is_some() {
                    eprintln!("valid: {text}");
                }
                let session = Session::new(scene, Some(200), None).expect("session");
                let run = simulate_cpu(&session, 5, 1.0 / 60.0);
                for (i, b) in run.blades.iter().enumerate() {
                    let all = b.v0_dir.iter().chain(&b.v1_height).chain(&b.v2_width);
                    prop_assert!(
                        all.clone().all(|c| c.is_finite()),
                        "{text}\nblade {i} is not finite: {b:?}"
                    );
                }
            }
        }
    }
}

/// The text builder writes what the test means: a check of the harness itself.
#[test]
fn scene_text_builds_the_intended_scene() {
    let mut values = base();
    values.insert("terrain.height.amplitude".into(), "3.0".into());
    values.insert("wind.source".into(), "Fluid".into());
    let text = scene_text(&values);
    let scene = parse_scene(&text, Path::new("props.ron")).expect(&text);
    assert_eq!(scene.wind.source, sward::scene::WindSource::Fluid);
    assert_eq!(scene.colliders.len(), 1);
    assert_eq!(scene.wind.downwash.as_ref().map(|d| d.radius), Some(2.0));
    match scene.terrain.height {
        sward::scene::HeightSource::Noise { amplitude, .. } => assert_eq!(amplitude, 3.0),
        other => panic!("{other:?}"),
    }
}
