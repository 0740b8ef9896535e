//! Snapshot test: a 256 × 144 render of `tests/scenes/snapshot.ron` after 30 frames against
//! the committed reference `tests/snapshots/meadow_256x144.png`. Passes when the mean
//! per-channel difference is under `MEAN_THRESHOLD` and at most `MAX_FAILING` of the pixels
//! differ by more than `PIXEL_THRESHOLD` in some channel. On failure it writes `-actual`
//! and `-diff` PNGs beside the reference. `UPDATE_SNAPSHOTS=1` rewrites the reference.

mod common;

use std::path::{Path, PathBuf};

use sward::commands::{render, RenderOptions};
use sward::gpu::AdapterChoice;

const MEAN_THRESHOLD: f64 = 2.0;
const PIXEL_THRESHOLD: u8 = 48;
const MAX_FAILING: f64 = 0.01;

fn dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("tests")
}

#[test]
fn meadow_render_matches_reference() {
    let out = std::env::temp_dir().join(format!("sward-snapshot-{}.png", std::process::id()));
    let adapter: AdapterChoice = std::env::var("SWARD_ADAPTER")
        .unwrap_or_else(|_| "software".into())
        .parse()
        .expect("infallible");
    render(&RenderOptions {
        scene: Some(dir().join("scenes/snapshot.ron")),
        size: (256, 144),
        frames: 30,
        dt: 1.0 / 30.0,
        out: out.clone(),
        timings: false,
        adapter,
        wind_overlay: false,
        pressure_iterations: None,
        wind_resolution: None,
    })
    .expect("render");
    let actual = image::open(&out).expect("rendered png").to_rgba8();
    let _ = std::fs::remove_file(&out);
    let reference_path = dir().join("snapshots/meadow_256x144.png");
    if std::env::var("UPDATE_SNAPSHOTS").is_ok_and(|v| v == "1") {
        actual.save(&reference_path).expect("write reference");
    }
    let reference = image::open(&reference_path)
        .expect("committed reference png")
        .to_rgba8();
    assert_eq!(actual.dimensions(), reference.dimensions());

    let mut sum = 0u64;
    let mut failing = 0usize;
    let mut diff = image::RgbaImage::new(actual.width(), actual.height());
    for (x, y, a) in actual.enumerate_pixels() {
        let r = reference.get_pixel(x, y);
        let d: Vec<u8> = (0..3).map(|c| a[c].abs_diff(r[c])).collect();
        sum += d.iter().map(|&v| v as u64).sum::<u64>();
        let worst = *d.iter().max().expect("3 channels");
        if worst > PIXEL_THRESHOLD {
            failing += 1;
        }
        diff.put_pixel(x, y, image::Rgba([worst.saturating_mul(4), 0, 0, 255]));
    }
    let pixels = (actual.width() * actual.height()) as f64;
    let mean = sum as f64 / (pixels * 3.0);
    let failing_fraction = failing as f64 / pixels;
    println!("snapshot: mean difference {mean:.3} (max {MEAN_THRESHOLD}), failing pixels {:.3} % (max {:.1} %)", failing_fraction * 100.0, MAX_FAILING * 100.0);
    if mean > MEAN_THRESHOLD || failing_fraction > MAX_FAILING {
        actual
            .save(dir().join("snapshots/meadow_256x144-actual.png"))
            .expect("write actual");
        diff.save(dir().join("snapshots/meadow_256x144-diff.png"))
            .expect("write diff");
        panic!("render differs from the reference: mean {mean:.3}, failing {:.3} % (see tests/snapshots/*-actual.png, *-diff.png)", failing_fraction * 100.0);
    }
}
