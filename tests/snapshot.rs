//! Snapshot tests: 256 × 144 renders after 30 frames against committed references: the
//! meadow of `tests/scenes/snapshot.ron` (`tests/snapshots/meadow_256x144.png`) and the
//! grassy planet of `assets/scenes/planet.ron` without MSAA (`planet_256x144.png`), and the
//! meadow at noon and at evening (`meadow_noon_256x144.png`, `meadow_evening_256x144.png`). Passes when the mean
//! per-channel difference is under `MEAN_TOLERANCE` and at most `MAX_FAILING` of the pixels
//! differ by more than `PIXEL_TOLERANCE` in some channel (`sward::compare`). On failure it writes `-actual`
//! and `-diff` PNGs beside the reference. `UPDATE_SNAPSHOTS=1` rewrites the reference.

mod common;

use std::path::{Path, PathBuf};

use sward::commands::{render, RenderOptions};
use sward::compare::{compare, MAX_FAILING, MEAN_TOLERANCE};
use sward::gpu::AdapterChoice;

fn dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("tests")
}

#[test]
fn meadow_render_matches_reference() {
    matches_reference(&dir().join("scenes/snapshot.ron"), &[], "meadow_256x144");
}

/// The meadow at noon and at evening (issue 16): the sun by the time of day, its shadows,
/// Preetham's sky and the fog it colours.
#[test]
fn meadow_at_noon_matches_reference() {
    let sets = ["light.time_of_day=Some(12.0)", "light.north=200"];
    matches_reference(
        &dir().join("scenes/snapshot.ron"),
        &sets,
        "meadow_noon_256x144",
    );
}

#[test]
fn meadow_at_evening_matches_reference() {
    let sets = ["light.time_of_day=Some(19.0)", "light.north=200"];
    matches_reference(
        &dir().join("scenes/snapshot.ron"),
        &sets,
        "meadow_evening_256x144",
    );
}

#[test]
fn grassy_planet_render_matches_reference() {
    let scene = Path::new(env!("CARGO_MANIFEST_DIR")).join("assets/scenes/planet.ron");
    matches_reference(&scene, &["render.msaa=1"], "planet_256x144");
}

/// Renders `scene` (with the `--set` overrides `sets`) and compares it with
/// `tests/snapshots/{name}.png`.
fn matches_reference(scene: &Path, sets: &[&str], name: &str) {
    let out =
        std::env::temp_dir().join(format!("sward-snapshot-{name}-{}.png", std::process::id()));
    let adapter: AdapterChoice = std::env::var("SWARD_ADAPTER")
        .unwrap_or_else(|_| "software".into())
        .parse()
        .expect("infallible");
    render(&RenderOptions {
        scene: Some(scene.to_path_buf()),
        sets: sets.iter().map(|s| s.to_string()).collect(),
        size: (256, 144),
        frames: 30,
        dt: 1.0 / 30.0,
        out: out.clone(),
        timings: false,
        trace: None,
        adapter,
        wind_overlay: false,
        pressure_iterations: None,
        wind_resolution: None,
    })
    .expect("render");
    let actual = image::open(&out).expect("rendered png").to_rgba8();
    let _ = std::fs::remove_file(&out);
    let reference_path = dir().join(format!("snapshots/{name}.png"));
    if std::env::var("UPDATE_SNAPSHOTS").is_ok_and(|v| v == "1") {
        actual.save(&reference_path).expect("write reference");
    }
    let reference = image::open(&reference_path)
        .expect("committed reference png")
        .to_rgba8();
    assert_eq!(actual.dimensions(), reference.dimensions());

    let d = compare(&actual, &reference).expect("same size");
    let (mean, failing_fraction, diff) = (d.mean, d.failing, d.image);
    println!("snapshot {name}: mean difference {mean:.3} (max {MEAN_TOLERANCE}), failing pixels {:.3} % (max {:.1} %)", failing_fraction * 100.0, MAX_FAILING * 100.0);
    if mean > MEAN_TOLERANCE || failing_fraction > MAX_FAILING {
        actual
            .save(dir().join(format!("snapshots/{name}-actual.png")))
            .expect("write actual");
        diff.save(dir().join(format!("snapshots/{name}-diff.png")))
            .expect("write diff");
        panic!("render differs from the reference: mean {mean:.3}, failing {:.3} % (see tests/snapshots/*-actual.png, *-diff.png)", failing_fraction * 100.0);
    }
}
