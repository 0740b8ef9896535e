//! Property test of the scene's first line of defence, over every field validation has a
//! rule for: the fields and their allowed values are read from the rules themselves
//! (`sward::scene::field_rules`, the sections' `RULES` tables), so a field added with its
//! rule is varied here without editing this file. Random values — the ends of each range,
//! just outside them, NaN, ±inf, huge, tiny, every variant of an enum — are set on a small
//! scene that has every section (species, clumps, flowers, a guide, a collider, a mesh
//! object, the 3D wind, light, propagation). Each case either ends in an error that names
//! what is allowed, or loads into a scene whose blades run five steps of the CPU twin with
//! **no** blade reset: a reset there means validation let through a value that drives the
//! update to NaN.

use std::path::Path;

use proptest::prelude::*;
use sward::commands::simulate_cpu;
use sward::scene::{field_rules, parse_scene_with_sets, RuleKind};
use sward::session::Session;
use sward::Error;

/// The small scene every case starts from: every section present so that every rule's
/// field exists (lists hold one element, reached as `[0]`).
fn base(alt: bool) -> String {
    let planet = std::path::absolute("assets/models/planet.obj").expect("path");
    // The other variants of the enums whose fields have rules: a collider and a downwash
    // on paths, CWD-Sim's self-shadow with its parameters, a height map.
    let (collider_motion, downwash_motion, self_shadow, height) = if alt {
        (
            "Path(points: [(-2.0, 0.0), (2.0, 1.0)], speed: 1.0, looped: true)",
            "Path(points: [(-1.0, 0.0), (1.0, 0.0)], speed: 2.0, looped: false)",
            "Cwd(min: 0.5, max: 1.0, c1: 2.0, c2: 0.5)",
            format!("Png(path: \"{}\", scale: 0.5)", height_map().display()),
        )
    } else {
        (
            "Velocity((0.5, 0.0, 0.0))",
            "Static",
            "Height",
            "Noise(seed: 1, amplitude: 0.5, wavelength: 8.0, octaves: 2)".to_owned(),
        )
    };
    format!(
        r#"(
    terrain: (size: 6.0, resolution: 9, height: {height}),
    field: (
        density: 20.0,
        species: [(share: 1.0, height: (min: 0.3, max: 0.6), width: (min: 0.02, max: 0.03), stiffness: (min: 7.0, max: 11.0), color: (0.1, 0.4, 0.1), shape: Quadratic)],
        clumps: Some((size: 0.6, align: 0.7, lean: 12.0, color_variation: 0.3)),
        flowers: Some((fraction: 0.05, height: (min: 0.3, max: 0.5), head_size: 0.03, kinds: [(petals: (0.9, 0.9, 0.8), centre: (0.9, 0.6, 0.1), petal_count: 6)])),
    ),
    colliders: [(center: (0.0, 0.3, 0.0), radius: 0.4, motion: {collider_motion})],
    objects: [(mesh: "{planet}", translation: (1.0, 0.4, 0.0), scale: 0.3, collider: Spheres((count: 16, resolution: 8)), motion: Path(points: [(-2.0, 0.0), (2.0, 0.0)], speed: 1.0, looped: true), rolls: true)],
    wind: (
        source: Both,
        point: Some((position: (0.0, 0.5, 0.0), strength: 6.0, radius: 2.0, frequency: 1.0)),
        global: Some((direction: (1.0, 0.0), strength: 2.0)),
        downwash: Some((position: (0.0, 2.0, 0.0), radius: 2.0, strength: 10.0, motion: {downwash_motion})),
        fluid: (resolution: 16, pressure_iterations: 8, layers: 2),
        guides: [(strength: 6.0, radius: 1.0, points: [(position: (-2.0, 0.0)), (position: (2.0, 0.0), parent: Some(0))])],
    ),
    physics: (propagation: Some(())),
    camera: (follow: Some(())),
    render: (self_shadow: {self_shadow}),
)"#,
        planet = planet.display()
    )
}

/// A 4 × 4 grey PNG height map, written once per test process.
fn height_map() -> std::path::PathBuf {
    let path = std::env::temp_dir().join(format!("sward-props-{}.png", std::process::id()));
    if !path.exists() {
        let image = image::GrayImage::from_fn(4, 4, |x, y| image::Luma([(x * 40 + y * 20) as u8]));
        image.save(&path).expect("height map");
    }
    path
}

/// Fields inside a variant that wraps a struct (`Spheres((count: ..))`), which `--set`
/// replaces whole: the value is set through the variant.
const WRAPPED: &[(&str, &str)] = &[
    (
        "objects[].collider.count",
        "objects[0].collider=Spheres((count: {}, resolution: 8))",
    ),
    (
        "objects[].collider.resolution",
        "objects[0].collider=Spheres((count: 16, resolution: {}))",
    ),
];

/// Fields that hold an `(x, z)` pair rather than an `(x, y, z)` triple.
fn planar(path: &str) -> bool {
    path.ends_with("points[]")
        || path == "wind.directional.direction"
        || path == "wind.global.direction"
}

/// The `--set` argument that gives `path` (a rule's path) the value text `value`.
fn assignment(path: &str, value: &str) -> String {
    match WRAPPED.iter().find(|(p, _)| *p == path) {
        Some((_, template)) => template.replace("{}", value),
        None => format!("{}={value}", path.replace("[]", "[0]")),
    }
}

/// In-range values of these fields stay small: each case runs the CPU twin, and a 2048²
/// wind grid or 1000 solver iterations would make a case take minutes. Their ends and
/// what lies outside are still tried (refused before anything is allocated).
const CHEAP: &[(&str, u64)] = &[
    ("terrain.resolution", 33),
    ("wind.fluid.resolution", 32),
    ("wind.fluid.layers", 4),
    ("wind.fluid.pressure_iterations", 40),
    ("wind.fluid.multigrid_cycles", 4),
    ("wind.fluid.diffusion_iterations", 20),
    ("objects[].collider.count", 64),
    ("objects[].collider.resolution", 16),
    ("physics.propagation.generations", 4),
];

/// Probes of a float interval: its ends, points inside, just outside, and non-numbers.
fn real(low: f32, high: f32) -> impl Strategy<Value = f32> {
    let span = (high - low).max(1e-6);
    prop_oneof![
        2 => Just(low),
        2 => Just(high),
        1 => Just(low + 1e-3 * span),
        1 => Just(high - 1e-3 * span),
        6 => (0.0f32..=1.0).prop_map(move |t| low + t * span),
        1 => Just(low - 1e-3 * span - 1e-3),
        1 => Just(high + 1e-3 * span + 1e-3),
        1 => Just(f32::NAN),
        1 => Just(f32::INFINITY),
        1 => Just(-1e38f32),
        1 => Just(1e-38f32),
        1 => Just(0.0f32),
    ]
}

fn ron_float(x: f32) -> String {
    // `{:?}` writes NaN, inf, -inf and 1e38 as RON reads them.
    format!("{x:?}")
}

/// `--set PATH=VALUE` texts for one field of each kind.
fn value_for(path: &'static str, kind: RuleKind) -> Option<BoxedStrategy<String>> {
    let cheap = CHEAP.iter().find(|(p, _)| *p == path).map(|(_, m)| *m);
    Some(match kind {
        RuleKind::Real { low, high } => real(low, high).prop_map(ron_float).boxed(),
        RuleKind::Range { low, high } => (real(low, high), real(low, high))
            .prop_map(|(a, b)| format!("(min: {}, max: {})", ron_float(a), ron_float(b)))
            .boxed(),
        RuleKind::Vector { low, high } if planar(path) => (real(low, high), real(low, high))
            .prop_map(|(x, z)| format!("({}, {})", ron_float(x), ron_float(z)))
            .boxed(),
        RuleKind::Vector { low, high } => (real(low, high), real(low, high), real(low, high))
            .prop_map(|(x, y, z)| format!("({}, {}, {})", ron_float(x), ron_float(y), ron_float(z)))
            .boxed(),
        RuleKind::Direction if planar(path) => (real(-2.0, 2.0), real(-2.0, 2.0))
            .prop_map(|(x, z)| format!("({}, {})", ron_float(x), ron_float(z)))
            .boxed(),
        RuleKind::Integer { low, high } => {
            let top = cheap.map_or(high, |c| c.clamp(low, high));
            prop_oneof![
                2 => Just(low),
                1 => Just(high),
                4 => low..=top,
                1 => Just(high.saturating_add(1)),
                1 => Just(low.saturating_sub(1)),
            ]
            .prop_map(|v| v.to_string())
            .boxed()
        }
        RuleKind::Direction => (real(-2.0, 2.0), real(-2.0, 2.0), real(-2.0, 2.0))
            .prop_map(|(x, y, z)| format!("({}, {}, {})", ron_float(x), ron_float(y), ron_float(z)))
            .boxed(),
        RuleKind::Bool => prop_oneof![Just("true".to_owned()), Just("false".to_owned())].boxed(),
        RuleKind::Choice(names) if !names.is_empty() => {
            let mut options = names;
            options.push("NotAVariant".to_owned());
            proptest::sample::select(options).boxed()
        }
        RuleKind::Choice(_) | RuleKind::Other(_) => return None,
    })
}

/// One case: the base scene (or its other variants) and 1 to 5 fields with a value each,
/// as `--set` arguments.
fn changes() -> impl Strategy<Value = (bool, Vec<String>)> {
    let strategies: Vec<BoxedStrategy<String>> = field_rules()
        .into_iter()
        .filter_map(|r| {
            let path = r.path;
            value_for(path, r.kind).map(|v| v.prop_map(move |v| assignment(path, &v)).boxed())
        })
        .collect();
    let count = strategies.len();
    let one = (0..count).prop_flat_map(move |k| strategies[k].clone());
    (any::<bool>(), proptest::collection::vec(one, 1..6))
}

/// Whether an error says what is allowed (a range, the variants, the accepted forms).
fn names_what_is_allowed(e: &Error) -> bool {
    let m = e.to_string();
    m.contains("allowed") || m.contains("at most") || m.contains("must")
        // A field of the variant the other base has: `--set` says to set the enum itself.
        || m.contains("which has no field")
        // A field of the other height source: the parser lists the fields there are.
        || m.contains("expected one of")
}

/// How a case ended (every ending that is not a failure).
enum Outcome {
    Refused,
    RefusedAfterLoading,
    Stepped,
}

fn check_case(alt: bool, sets: &[String]) -> Result<Outcome, TestCaseError> {
    let text = base(alt);
    let shown = || format!("--set {}", sets.join(" --set "));
    match parse_scene_with_sets(&text, Path::new("props.ron"), sets) {
        Err(e @ (Error::Scene { .. } | Error::Set { .. })) => {
            prop_assert!(names_what_is_allowed(&e), "{}\n{e}", shown());
            Ok(Outcome::Refused)
        }
        Err(other) => Err(TestCaseError::fail(format!(
            "{}\nnot a scene error: {other}",
            shown()
        ))),
        Ok(scene) => match Session::new(scene, Some(200), None) {
            // Found after loading (a count or an area too large): a clear error too.
            Err(e) => {
                prop_assert!(names_what_is_allowed(&e), "{}\n{e}", shown());
                Ok(Outcome::RefusedAfterLoading)
            }
            Ok(session) => {
                let run = simulate_cpu(&session, 5, 1.0 / 60.0);
                prop_assert_eq!(
                    run.blades_reset_nonfinite,
                    0,
                    "{}\nvalidation let through a scene whose update went non-finite",
                    shown()
                );
                for (i, b) in run.blades.iter().enumerate() {
                    let all = b.v0_dir.iter().chain(&b.v1_height).chain(&b.v2_width);
                    prop_assert!(
                        all.clone().all(|c| c.is_finite()),
                        "{}\nblade {i} is not finite: {b:?}",
                        shown()
                    );
                }
                Ok(Outcome::Stepped)
            }
        },
    }
}

/// Cases run, and how each ended.
#[derive(Default, Debug)]
struct Outcomes {
    refused: usize,
    refused_after_loading: usize,
    stepped: usize,
}

#[test]
fn scenes_validate_or_stay_finite() {
    let outcomes = std::sync::Mutex::new(Outcomes::default());
    // SWARD_PROPS_CASES runs more cases by hand (CI runs 256).
    let cases = std::env::var("SWARD_PROPS_CASES")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(256);
    let config = ProptestConfig {
        cases,
        failure_persistence: None,
        ..ProptestConfig::default()
    };
    let mut runner = proptest::test_runner::TestRunner::new(config);
    let result = runner.run(&changes(), |(alt, sets)| {
        let outcome = check_case(alt, &sets)?;
        let mut o = outcomes.lock().expect("outcomes");
        match outcome {
            Outcome::Refused => o.refused += 1,
            Outcome::RefusedAfterLoading => o.refused_after_loading += 1,
            Outcome::Stepped => o.stepped += 1,
        }
        Ok(())
    });
    if let Err(e) = result {
        panic!("{e}");
    }
    let o = outcomes.into_inner().expect("outcomes");
    eprintln!("{o:?}");
    // Enough cases get through validation to the update for its check to mean something.
    assert!(o.stepped >= cases as usize / 5, "{o:?}");
}

/// The harness reaches what it means to: the base scene loads and steps, and every field
/// the rules name can be set on it to a value inside its range, so no generated case is
/// lost to a path that does not exist.
#[test]
fn every_ruled_field_is_reachable_on_the_base_scene() {
    for alt in [false, true] {
        let scene = parse_scene_with_sets(&base(alt), Path::new("props.ron"), &[]).expect("base");
        assert_eq!(scene.field.species.len(), 1);
        assert!(scene.field.flowers.is_some() && scene.physics.propagation.is_some());
        assert_eq!(scene.objects.len(), 1);
        let session = Session::new(scene, Some(200), None).expect("session");
        assert_eq!(
            simulate_cpu(&session, 5, 1.0 / 60.0).blades_reset_nonfinite,
            0
        );
    }
    let mut unreachable = Vec::new();
    let mut varied = 0;
    for rule in field_rules() {
        let mid = |low: f32, high: f32| ron_float(0.5 * (low + high));
        let inside = match &rule.kind {
            RuleKind::Real { low, high } => mid(*low, *high),
            RuleKind::Range { low, high } => {
                format!("(min: {0}, max: {0})", mid(*low, *high))
            }
            RuleKind::Vector { low, high } if planar(rule.path) => {
                format!("({0}, {0})", mid(*low, *high))
            }
            RuleKind::Vector { low, high } => format!("({0}, {0}, {0})", mid(*low, *high)),
            RuleKind::Direction if planar(rule.path) => "(1.0, 0.5)".to_owned(),
            RuleKind::Direction => "(1.0, 0.5, 0.0)".to_owned(),
            RuleKind::Integer { low, .. } => low.to_string(),
            RuleKind::Bool => "true".to_owned(),
            RuleKind::Choice(names) if !names.is_empty() => names[0].clone(),
            _ => continue,
        };
        varied += 1;
        let set = assignment(rule.path, &inside);
        // Reachable when one of the two bases takes it.
        let errors: Vec<String> = [false, true]
            .into_iter()
            .filter_map(|alt| {
                parse_scene_with_sets(
                    &base(alt),
                    Path::new("props.ron"),
                    std::slice::from_ref(&set),
                )
                .err()
                .map(|e| e.to_string())
            })
            .collect();
        if errors.len() == 2 && errors.iter().all(|m| !m.contains("allowed")) {
            unreachable.push(format!("{set}: {}", errors[0]));
        }
    }
    eprintln!("{varied} fields varied");
    assert!(varied > 150, "{varied}");
    assert!(unreachable.is_empty(), "{unreachable:#?}");
}
