//! `sward bench` end to end: the real binary on a small scene, its JSON report checked for
//! structure and counters (never for timings, which depend on the machine), the sweep's
//! blade counts, and bad flags (a clear message naming the flag and its range, exit status
//! 1, no panic). Runs on the adapter `SWARD_ADAPTER` names, the software one by default.

use std::process::{Command, Output};

use serde_json::Value;
use sward::sim::layout::BYTES_PER_BLADE;

const SCENE: &str = "tests/scenes/bench_small.ron";
/// Spheres in `SCENE`.
const SCENE_SPHERES: u64 = 4;

fn adapter() -> String {
    std::env::var("SWARD_ADAPTER").unwrap_or_else(|_| "software".into())
}

fn sward(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_sward"))
        .args(args)
        .current_dir(env!("CARGO_MANIFEST_DIR"))
        .env("SWARD_ADAPTER", adapter())
        .env("RUST_BACKTRACE", "0")
        .output()
        .expect("run sward")
}

/// Runs a bench that must succeed and returns its JSON report.
fn bench_json(args: &[&str]) -> Value {
    let mut all = vec!["bench", "--scene", SCENE, "--json"];
    all.extend_from_slice(args);
    let out = sward(&all);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "sward {all:?} failed: {stderr}");
    serde_json::from_slice(&out.stdout).unwrap_or_else(|e| {
        panic!(
            "stdout is not one JSON object ({e}):\n{}",
            String::from_utf8_lossy(&out.stdout)
        )
    })
}

fn u(v: &Value, path: &[&str]) -> u64 {
    let mut x = v;
    for p in path {
        x = &x[*p];
    }
    x.as_u64()
        .unwrap_or_else(|| panic!("{path:?} is not a count: {x}"))
}

fn f(v: &Value, path: &[&str]) -> f64 {
    let mut x = v;
    for p in path {
        x = &x[*p];
    }
    x.as_f64()
        .unwrap_or_else(|| panic!("{path:?} is not a number: {x}"))
}

#[test]
fn three_configurations_on_the_same_field() {
    let r = bench_json(&["--frames", "6", "--size", "160x90"]);
    assert!(!r["adapter"].as_str().unwrap_or("").is_empty(), "{r}");
    assert!(r["date"].as_str().unwrap_or("").ends_with("UTC"), "{r}");
    assert_eq!(u(&r, &["frames"]), 6);
    assert_eq!(u(&r, &["warmup"]), 5);
    let timestamps = r["timestamps"].as_bool().expect("timestamps flag");
    let configs = r["configurations"].as_array().expect("configurations");
    let names: Vec<&str> = configs
        .iter()
        .map(|c| c["name"].as_str().unwrap())
        .collect();
    assert_eq!(names, ["all features", "collisions off", "culling off"]);

    let total = u(&configs[0], &["blades", "total"]);
    assert!((7_000..=9_000).contains(&total), "about 8k blades: {total}");
    for c in configs {
        let name = c["name"].as_str().unwrap();
        let b = |k: &str| u(c, &["blades", k]);
        assert_eq!(b("total"), total, "{name}: same field in every column");
        assert_eq!(b("drawn") + b("culled"), total, "{name}: drawn + culled");
        let levels = &c["blades"]["drawn_per_level"];
        let per_level: u64 = (0..3).map(|k| levels[k].as_u64().expect("count")).sum();
        assert_eq!(per_level, b("drawn"), "{name}: the levels add up");
        assert!(b("stepped") > 0 && b("stepped") <= total, "{name}: stepped");
        let per_test = b("culled_patch")
            + b("culled_orientation")
            + b("culled_frustum")
            + b("culled_distance")
            + b("culled_occlusion");
        assert_eq!(per_test, b("culled"), "{name}: the tests add up");
        for k in ["fps", "frame_ms", "wall_ms"] {
            let v = f(c, &[k]);
            assert!(v.is_finite() && v > 0.0, "{name}: {k} = {v}");
        }
        // lavapipe has pipeline statistics: every configuration counts one frame's work.
        let w = &c["work"];
        for k in [
            "vertex_invocations",
            "fragment_invocations",
            "compute_invocations",
            "grass_pixels",
        ] {
            assert!(u(w, &[k]) > 0, "{name}: work.{k}: {w}");
        }
        // Forward, each covered pixel is shaded at least once; deferred (this scene has one
        // sample per pixel), once, and the coverage pass counts a pixel twice where two
        // blades meet at the same depth (0.02 % of the pixels, measured).
        let lit = f(w, &["lit_fragments_per_pixel"]);
        assert!(
            lit >= 0.99,
            "{name}: each covered pixel is shaded at least once: {lit}"
        );
        let count = |row: &str, k: &str| w["passes"][row][k].as_u64().unwrap_or(0);
        assert!(
            count("lit grass", "fragment_invocations") > 0
                || count("grass light", "compute_invocations") > 0,
            "{name}: the grass is lit, forward or deferred: {w}"
        );
        // The frame's figures are the passes' sums, the coverage measurement left out.
        let passes = w["passes"].as_object().expect("passes");
        let sum: u64 = passes
            .iter()
            .filter(|(k, _)| k.as_str() != "coverage")
            .map(|(_, p)| u(p, &["vertex_invocations"]))
            .sum();
        assert_eq!(sum, u(w, &["vertex_invocations"]), "{name}");
        if timestamps {
            assert_eq!(c["frame_time_source"], "gpu");
            let parts = [
                "physics",
                "visibility",
                "rendering",
                "shadows",
                "tone_map",
                "billboards",
                "tiles",
                "overlays",
                "far_gain",
                "skinning",
            ];
            for k in parts.iter().chain(&["update", "wind"]) {
                let v = f(c, &["gpu_ms", k]);
                assert!(v.is_finite() && v >= 0.0, "{name}: gpu_ms.{k} = {v}");
            }
            // The frame is every timed pass: the shadows and the tone mapping included.
            let g = &c["gpu_ms"];
            assert!(
                f(g, &["shadows"]) > 0.0,
                "{name}: the meadow casts sun shadows"
            );
            assert!(
                f(g, &["tone_map"]) > 0.0,
                "{name}: every frame is tone-mapped"
            );
            // The far levels' gains are measured every frame they are drawn, and the pass
            // is part of the frame (the bench's frame left it out until 2026-11-29).
            if count("far gain", "compute_invocations") > 0 {
                assert!(
                    f(g, &["far_gain"]) > 0.0,
                    "{name}: the far gain pass ran but is not in the frame"
                );
            }
            let sum: f64 = parts.iter().map(|k| f(g, &[k])).sum();
            assert!((sum - f(c, &["frame_ms"])).abs() < 1e-6 * sum.max(1.0));
        } else {
            assert!(
                c["gpu_ms"].is_null(),
                "{name}: no GPU times without timestamps"
            );
            assert_eq!(c["frame_time_source"], "wall clock");
        }
        let m = &c["memory"];
        assert_eq!(u(m, &["bytes_per_blade"]), BYTES_PER_BLADE as u64);
        assert_eq!(u(m, &["bytes_per_blade"]), 104);
        let measured = f(m, &["measured_bytes_per_blade"]);
        assert!(
            measured >= BYTES_PER_BLADE as f64,
            "{name}: the blade buffers hold at least the layout's bytes: {measured}"
        );
        assert!(u(m, &["blade_bytes"]) > 0 && u(m, &["gpu_bytes"]) >= u(m, &["blade_bytes"]));
        assert!(f(m, &["gpu_mib"]) > 0.0);
    }
    // The scene's camera sees only part of the field: every culling test has work.
    let all = &configs[0];
    assert!(u(all, &["blades", "culled"]) > 0);
    assert!(u(all, &["blades", "drawn"]) > 0);
    let off = &configs[2];
    assert_eq!(
        u(off, &["blades", "culled"]),
        0,
        "culling off culls nothing"
    );
    assert_eq!(u(off, &["blades", "drawn"]), total, "culling off draws all");
    assert_eq!(u(&configs[0], &["colliders"]), SCENE_SPHERES);
    assert_eq!(u(&configs[1], &["colliders"]), 0, "collisions off");
    assert_eq!(u(&configs[2], &["colliders"]), SCENE_SPHERES);

    let ratios = &r["ratios"];
    assert!(f(ratios, &["culling_off_over_all_frame_time"]) > 0.0);
    let culled = f(ratios, &["culled_over_visible_patch_blades"]);
    assert!((0.0..=1.0).contains(&culled), "{culled}");
    if timestamps {
        assert!(
            f(
                ratios,
                &["physics_per_blade_over_rendering_per_drawn_blade"]
            ) >= 0.0
        );
    }
    assert_eq!(
        r["sweep"].as_array().map(Vec::len),
        Some(0),
        "no sweep asked"
    );
}

#[test]
fn sweep_blade_counts_follow_the_request() {
    let r = bench_json(&[
        "--frames",
        "2",
        "--warmup",
        "1",
        "--size",
        "64x36",
        "--sweep",
        "2000,4000",
    ]);
    let points = r["sweep"].as_array().expect("sweep");
    assert_eq!(points.len(), 2);
    let mut last = 0;
    for (p, asked) in points.iter().zip([2000u64, 4000]) {
        assert_eq!(u(p, &["requested"]), asked);
        let blades = u(p, &["blades"]);
        let off = (blades as f64 - asked as f64).abs() / asked as f64;
        assert!(off <= 0.1, "asked {asked}, got {blades}");
        assert!(blades > last, "increasing: {blades} after {last}");
        last = blades;
        assert!(u(p, &["drawn"]) <= blades);
        assert!(f(p, &["frame_ms"]) > 0.0 && f(p, &["fps"]) > 0.0);
        assert!(f(p, &["gpu_mib"]) > 0.0);
    }
}

#[test]
fn table_names_the_configurations_and_the_adapter() {
    let dir = std::env::temp_dir().join(format!("sward_bench_images_{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("temp dir");
    let out = sward(&[
        "bench",
        "--scene",
        SCENE,
        "--frames",
        "1",
        "--warmup",
        "0",
        "--size",
        "64x36",
        "--images",
        dir.to_str().expect("utf-8 temp path"),
    ]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let table = String::from_utf8_lossy(&out.stdout);
    for needle in [
        "adapter:",
        "date:",
        "all features",
        "collisions off",
        "culling off",
        "FPS",
        "wall clock per frame",
        "blades (last frame)",
        "by orientation",
        "physical model",
        "visibility",
        "rendering",
        "collision spheres considered",
        "bytes per blade (layout)",
        "GPU memory of the scene (MiB)",
        "culling off / all features",
        "blades in visible patches",
        "rendering ms per drawn blade",
        "hidden by grass",
        "drawn late",
        "culled vs unculled frame",
    ] {
        assert!(table.contains(needle), "no {needle:?} in:\n{table}");
    }
    // --images: the two frames compared and their difference, at the bench's size.
    for name in ["all.png", "unculled.png", "difference.png"] {
        let image = image::open(dir.join(name)).unwrap_or_else(|e| panic!("{name}: {e}"));
        assert_eq!((image.width(), image.height()), (64, 36), "{name}");
    }
    std::fs::remove_dir_all(&dir).ok();
}

/// A bad invocation: exit status 1, an `error:` line naming `flag` and `range`, no panic,
/// nothing on stdout.
fn refused(args: &[&str], flag: &str, range: &str) {
    let mut all = vec!["bench", "--scene", SCENE];
    all.extend_from_slice(args);
    let out = sward(&all);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(1), "{all:?}: {stderr}");
    assert!(!stderr.contains("panicked"), "{all:?} panicked: {stderr}");
    assert!(stderr.contains("error:"), "{all:?}: {stderr}");
    assert!(
        stderr.contains(flag),
        "{all:?} does not name {flag}: {stderr}"
    );
    assert!(
        stderr.contains(range),
        "{all:?} does not give {range}: {stderr}"
    );
    assert!(out.stdout.is_empty(), "{all:?} printed a report");
}

#[test]
fn bad_flags_are_refused() {
    refused(&["--frames", "0"], "--frames", "1..=100000");
    refused(&["--frames", "lots"], "--frames", "1..=100000");
    refused(&["--frames", "-2"], "--frames", "1..=100000");
    refused(&["--frames", "100001"], "--frames", "1..=100000");
    refused(&["--warmup", "-1"], "--warmup", "0..=10000");
    refused(&["--warmup", "20000"], "--warmup", "0..=10000");
    refused(&["--size", "0x90"], "--size", "1..=16384");
    refused(&["--size", "160"], "--size", "1..=16384");
    refused(&["--size", "160x90x2"], "--size", "1..=16384");
    refused(&["--size", "99999x90"], "--size", "1..=16384");
    let sweep_range = "1..=50000000";
    refused(&["--sweep", ""], "--sweep", sweep_range);
    refused(&["--sweep", "4000,2000"], "--sweep", sweep_range);
    refused(&["--sweep", "2000,2000"], "--sweep", sweep_range);
    refused(&["--sweep", "0,2000"], "--sweep", sweep_range);
    refused(&["--sweep", "2000,,4000"], "--sweep", sweep_range);
    refused(&["--sweep", "2k"], "--sweep", sweep_range);
    refused(&["--sweep", "60000000"], "--sweep", sweep_range);
    refused(
        &["--images", "no/such/folder"],
        "--images",
        "not an existing folder",
    );
}

/// A count the adapter cannot hold is refused before anything is allocated or measured,
/// with the limits message. The count is one blade past what the test adapter's largest
/// storage buffer holds (2,097,153 on lavapipe's 128 MiB).
#[test]
fn sweep_beyond_the_adapter_is_refused_up_front() {
    let choice: sward::gpu::AdapterChoice = adapter().parse().expect("infallible");
    let gpu = sward::gpu::Gpu::new(&choice).expect("tests need a GPU adapter");
    let limits = gpu.device.limits();
    let max_bytes = limits
        .max_storage_buffer_binding_size
        .min(limits.max_buffer_size);
    let too_many = max_bytes / std::mem::size_of::<sward::sim::layout::Blade>() as u64 + 1;
    drop(gpu);
    if too_many > sward::session::MAX_BLADES as u64 {
        // The adapter holds more than --sweep accepts; the range check covers it.
        refused(
            &["--sweep", &too_many.to_string()],
            "--sweep",
            "1..=50000000",
        );
        return;
    }
    let sweep = format!("2000,{too_many}");
    let out = sward(&[
        "bench", "--scene", SCENE, "--frames", "1", "--sweep", &sweep,
    ]);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(1), "{stderr}");
    assert!(!stderr.contains("panicked"), "{stderr}");
    assert!(
        stderr.contains(&format!("--sweep {too_many}")) && stderr.contains("holds at most"),
        "{stderr}"
    );
    assert!(out.stdout.is_empty());
    // Refused before measuring anything: no configuration ran.
    assert!(!stderr.contains("bench: all features"), "{stderr}");
}

#[test]
fn missing_scene_is_named() {
    let out = sward(&[
        "bench",
        "--scene",
        "tests/scenes/no-such-scene.ron",
        "--frames",
        "1",
    ]);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(1), "{stderr}");
    assert!(stderr.contains("no-such-scene.ron"), "{stderr}");
}

/// `bench --flight`: the report's keys, a pop ratio under a bound along a slow flight over
/// the small scene, and every flight frame saved by `--images`.
#[test]
fn a_flight_reports_percentiles_pops_and_saves_its_frames() {
    let dir = std::env::temp_dir().join(format!("sward-flight-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    let frames = 12;
    let v = bench_json(&[
        "--flight",
        "--frames",
        &frames.to_string(),
        "--warmup",
        "2",
        "--size",
        "96x54",
        "--images",
        dir.to_str().unwrap(),
    ]);
    for key in [
        "p50_ms",
        "p95_ms",
        "pop_ratio",
        "blades_drawn",
        "billboards_drawn",
        "tiles_generated",
        "gpu_bytes",
    ] {
        assert!(v.get(key).is_some(), "no {key} in {v}");
    }
    assert!(f(&v, &["p95_ms"]) >= f(&v, &["p50_ms"]) && f(&v, &["p50_ms"]) > 0.0);
    assert!(u(&v, &["blades_drawn"]) > 0);
    assert!(u(&v, &["gpu_bytes"]) > 0);
    let pop = f(&v, &["pop_ratio"]);
    eprintln!("flight pop ratio {pop}");
    // A slow flight with swaying grass and no level switching: no frame differs from the
    // last more than 3x the median change.
    assert!((1.0..3.0).contains(&pop), "pop ratio {pop}");
    // The handover band (blades thinning into cards) changes no more than the other ground
    // (measured 0.99 on the prairie at 640x360; a pop there would raise it).
    let handover = f(&v, &["handover_ratio"]);
    eprintln!("flight handover ratio {handover}");
    assert!(
        handover > 0.0 && handover < 1.5,
        "handover ratio {handover}"
    );
    let mut names: Vec<String> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    names.sort();
    let expected: Vec<String> = (0..frames).map(|i| format!("frame_{i:04}.png")).collect();
    assert_eq!(names, expected);
    let img = image::open(dir.join("frame_0011.png")).unwrap();
    assert_eq!((img.width(), img.height()), (96, 54));
    std::fs::remove_dir_all(&dir).unwrap();
    // A streamed field: tiles of 2 m within 8 m, so that the flight (3.2 m) makes tiles
    // enter and leave; the pool changes without a pop.
    let v = bench_json(&[
        "--flight",
        "--frames",
        "24",
        "--warmup",
        "1",
        "--size",
        "96x54",
        "--set",
        "field.tile_size=2",
        "--set",
        "culling.max_distance=8",
    ]);
    let tiles = u(&v, &["tiles_generated"]);
    let pop = f(&v, &["pop_ratio"]);
    eprintln!("streamed flight: {tiles} tiles generated, pop ratio {pop}");
    assert!(tiles > 0, "{v}");
    assert!(u(&v, &["tiles_resident"]) > 0, "{v}");
    assert!(f(&v, &["tile_gen_ms_per_frame"]) >= 0.0);
    assert!(
        (1.0..3.0).contains(&pop),
        "pop ratio {pop} with tiles streaming"
    );
    // A sweep means a fixed camera: refused with the flight.
    let out = sward(&["bench", "--flight", "--sweep", "1000", "--frames", "1"]);
    assert_eq!(out.status.code(), Some(1));
    assert!(String::from_utf8_lossy(&out.stderr).contains("--sweep and --flight"));
}

#[test]
fn pressure_solvers_run_on_the_same_frames() {
    let out = sward(&[
        "bench",
        "--scene",
        "assets/scenes/two_winds.ron",
        "--json",
        "--pressure-solvers",
        "jacobi,multigrid",
        "--set",
        "wind.fluid.resolution=32",
        "--frames",
        "3",
        "--warmup",
        "2",
    ]);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "{stderr}");
    let v: Value = serde_json::from_slice(&out.stdout).expect("one JSON object");
    assert_eq!(v["resolution"], 32);
    let solvers = v["pressure_solvers"].as_array().expect("pressure_solvers");
    let names: Vec<&str> = solvers
        .iter()
        .map(|s| s["name"].as_str().expect("name"))
        .collect();
    assert_eq!(names, ["jacobi", "multigrid"]);
    for s in solvers {
        let before = s["rms_divergence_before"].as_f64().expect("before");
        let after = s["rms_divergence"].as_f64().expect("after");
        assert!(
            before > 0.0,
            "the guides must make divergence to remove: {s}"
        );
        assert!(after < before, "the solve must remove some: {s}");
        assert!(s["ms"].is_number() || s["ms"].is_null(), "{s}");
    }
    let err = sward(&["bench", "--pressure-solvers", "jacobi,sor"]);
    assert_eq!(err.status.code(), Some(1));
    let text = String::from_utf8_lossy(&err.stderr);
    assert!(
        text.contains("--pressure-solvers entry 2 (\"sor\") is not a solver"),
        "{text}"
    );
}

/// `--models` times the three blade models on the same frames: each steps and draws
/// blades, Verlet takes its 64-byte state on top, and the ratios are to Jahrmann's.
#[test]
fn models_are_timed_side_by_side() {
    let r = bench_json(&[
        "--frames", "2", "--warmup", "1", "--size", "64x36", "--models",
    ]);
    let models = r["models"].as_array().expect("models");
    let names: Vec<&str> = models
        .iter()
        .map(|m| m["model"].as_str().unwrap())
        .collect();
    assert_eq!(names, ["Jahrmann", "Verlet", "Cwd"]);
    for m in models {
        assert!(f(m, &["frame", "wall_ms"]) > 0.0, "{m}");
        assert!(f(m, &["frame", "gpu_ms"]) > 0.0, "{m}");
        assert!(f(m, &["stepped_blades"]) > 0.0, "{m}");
        assert!(f(m, &["drawn_blades"]) > 0.0, "{m}");
        if r["timestamps"].as_bool() == Some(true) {
            assert!(f(m, &["physics_ms"]) > 0.0, "{m}");
            assert!(f(m, &["ns_per_drawn_blade"]) > 0.0, "{m}");
        }
    }
    assert_eq!(
        u(&models[1], &["bytes_per_blade"]),
        u(&models[0], &["bytes_per_blade"]) + 64
    );
    assert_eq!(
        u(&models[2], &["bytes_per_blade"]),
        u(&models[0], &["bytes_per_blade"])
    );
    if r["timestamps"].as_bool() == Some(true) {
        // Each ratio is that model's physics time over Jahrmann's, from the same report.
        for m in &models[1..] {
            let want = f(m, &["physics_ms"]) / f(&models[0], &["physics_ms"]);
            let got = f(m, &["physics_over_jahrmann"]);
            assert!(
                (got - want).abs() <= 1e-3 * want,
                "{got} against {want}: {m}"
            );
        }
    }
    let out = sward(&["bench", "--models", "--colliders", "10", "--scene", SCENE]);
    assert!(!out.status.success());
    assert!(String::from_utf8_lossy(&out.stderr).contains("--models times the blade models alone"));
}

/// `--light` times the light's configurations on the same frames: the frame without
/// shadows is the reference, the shadow pass runs only where shadows are on, the tone
/// mapping runs in every configuration, and `--light` goes with no other mode.
#[test]
fn light_configurations_are_timed_side_by_side() {
    let r = bench_json(&[
        "--frames", "2", "--warmup", "1", "--size", "64x36", "--light",
    ]);
    let configs = r["configs"].as_array().expect("configs");
    let names: Vec<&str> = configs
        .iter()
        .map(|c| c["config"].as_str().unwrap())
        .collect();
    assert_eq!(
        names,
        [
            "no shadows",
            "shadows, no grass casters",
            "shadows",
            "shadows, no blade terms"
        ]
    );
    assert_eq!(
        r["timestamps"].as_bool(),
        Some(true),
        "lavapipe has timestamps"
    );
    assert_eq!(
        f(&configs[0], &["shadows_ms"]),
        0.0,
        "no shadow pass without shadows"
    );
    // Each ratio is that configuration's frame over the one without shadows.
    for c in &configs[1..] {
        let want = f(c, &["frame_ms"]) / f(&configs[0], &["frame_ms"]);
        let got = f(c, &["frame_over_no_shadows"]);
        assert!(
            (got - want).abs() <= 1e-3 * want,
            "{got} against {want}: {c}"
        );
    }
    for c in &configs[1..] {
        assert!(f(c, &["shadows_ms"]) > 0.0, "{c}");
    }
    for c in configs {
        assert!(f(c, &["tonemap_ms"]) > 0.0, "{c}");
        assert!(f(c, &["frame_ms"]) >= f(c, &["draw_ms"]), "{c}");
        assert!(f(c, &["wall_ms"]) > 0.0, "{c}");
    }
    // The shadow cascades are work the counters see: more vertices than without them,
    // and more again with the blades casting.
    let vertices = |k: usize| u(&configs[k]["work"], &["vertex_invocations"]);
    assert!(vertices(1) > vertices(0), "{configs:?}");
    assert!(vertices(2) > vertices(1), "{configs:?}");
    let out = sward(&["bench", "--light", "--models", "--scene", SCENE]);
    assert!(!out.status.success());
    assert!(String::from_utf8_lossy(&out.stderr).contains("--light times the light"));
}

/// `--far-field` compares the scene with its blades drawn further and with its billboards
/// pushed to the horizon: every band of the image in both comparisons, the worst one among
/// them, the reference's blade reach; and it goes with no other mode.
#[test]
fn far_field_compares_the_levels_band_by_band() {
    let r = bench_json(&[
        "--frames",
        "1",
        "--warmup",
        "0",
        "--size",
        "64x40",
        "--far-field",
    ]);
    assert!(f(&r, &["blade_reach"]) >= 50.0);
    let comparisons = r["comparisons"].as_array().expect("comparisons");
    let names: Vec<(&str, &str)> = comparisons
        .iter()
        .map(|c| {
            (
                c["image"].as_str().unwrap(),
                c["reference"].as_str().unwrap(),
            )
        })
        .collect();
    assert_eq!(
        names,
        [
            ("levels", "blades"),
            ("levels", "billboards to the horizon")
        ]
    );
    for c in comparisons {
        let diffs = c["diffs"].as_array().expect("diffs");
        // 40 rows: five bands of eight.
        assert_eq!(diffs.len(), 5, "{c}");
        assert_eq!(c["reference_bands"].as_array().map(Vec::len), Some(5));
        // The worst band is one of them, and no band is further off by luminance alone
        // than the worst is by its larger share of a tolerance.
        let worst = &c["worst"];
        assert!(diffs.contains(worst), "{c}");
        let score =
            |d: &Value| (f(d, &["luminance"]).abs() / 5.0).max(f(d, &["contrast"]).abs() / 0.3);
        assert!(diffs.iter().all(|d| score(d) <= score(worst) + 1e-9), "{c}");
        assert!(u(c, &["within"]) <= 5);
        // Five bands of eight blocks; a band's mean is the mean of its blocks (64 columns
        // split evenly), so no block is less off than the band most off by luminance.
        let blocks = c["blocks_within"].as_array().expect("blocks");
        assert_eq!(blocks[1].as_u64(), Some(40), "{c}");
        assert!(blocks[0].as_u64().unwrap() <= 40);
        let block = f(&c["worst_block"], &["luminance"]).abs();
        let band = diffs
            .iter()
            .map(|d| f(d, &["luminance"]).abs())
            .fold(0.0, f64::max);
        assert!(block + 1e-9 >= band, "{c}");
        assert!(u(&c["worst_block"], &["sector"]) < 8);
        assert!(u(c, &["differing_pixels"]) <= 64 * 40, "{c}");
    }
    // Each band's ground distance: one per band, in metres where the band shows ground
    // (the view looks down onto a field, so some do), null where it is mostly sky.
    let ground = r["band_ground"].as_array().expect("band_ground");
    assert_eq!(ground.len(), 5, "{ground:?}");
    assert!(ground.iter().any(|g| g.is_number()), "{ground:?}");
    for g in ground {
        assert!(
            g.is_null() || g.as_f64().is_some_and(|m| m > 0.0),
            "{ground:?}"
        );
    }
    // Blades to 50 m and no thinning draw another frame than the levels.
    assert!(u(&comparisons[0], &["differing_pixels"]) > 0);
    let out = sward(&["bench", "--far-field", "--light", "--scene", SCENE]);
    assert!(!out.status.success());
    assert!(String::from_utf8_lossy(&out.stderr).contains("--far-field compares the far levels"));
}

/// `--far-field` follows `levels` against `blades` along the run: the worst band after 4
/// frames and at the run's end, where it is the main comparison's; and the frame after 4
/// frames of the longer run is the frame a run of 4 ends on (the renders are deterministic),
/// so its worst band is that run's.
#[test]
fn far_field_follows_the_bands_along_the_run() {
    let run = |frames: &str| {
        bench_json(&[
            "--frames",
            frames,
            "--warmup",
            "0",
            "--size",
            "64x40",
            "--far-field",
        ])
    };
    let long = run("6");
    let series = long["series"].as_array().expect("series");
    let frames: Vec<u64> = series.iter().map(|p| u(p, &["frames"])).collect();
    assert_eq!(frames, [4, 6]);
    let main = &long["comparisons"][0];
    assert_eq!(series[1]["worst"], main["worst"]);
    assert_eq!(series[1]["within"], main["within"]);
    let short = run("4");
    assert_eq!(
        series[0]["worst"], short["comparisons"][0]["worst"],
        "{long}\n{short}"
    );
    assert_eq!(series[0]["within"], short["comparisons"][0]["within"]);
}

/// `--antialiasing` compares no anti-aliasing, 4x MSAA and TAA on the same frames: each
/// with its samples, times, work and flicker; MSAA differs from itself by nothing; and it
/// goes with no other mode and needs pairs of frames.
#[test]
fn antialiasing_compares_none_msaa_and_taa() {
    let r = bench_json(&[
        "--frames",
        "3",
        "--warmup",
        "1",
        "--size",
        "96x54",
        "--antialiasing",
    ]);
    let configs = r["configurations"].as_array().expect("configurations");
    let names: Vec<&str> = configs
        .iter()
        .map(|c| c["name"].as_str().unwrap())
        .collect();
    assert_eq!(names, ["none", "msaa 4x", "taa"]);
    let samples: Vec<u64> = configs.iter().map(|c| u(c, &["samples"])).collect();
    assert_eq!(samples[0], 1);
    assert!(samples[1] > 1, "{samples:?}");
    assert_eq!(samples[2], 1, "TAA draws one sample per pixel");
    for c in configs {
        assert!(f(c, &["wall_ms"]) > 0.0, "{c}");
        assert!(f(c, &["frame_flicker"]) >= 0.0, "{c}");
        assert!(f(c, &["far_flicker"]) >= 0.0, "{c}");
    }
    assert_eq!(f(&configs[1], &["difference_from_msaa"]), 0.0);
    assert!(f(&configs[2], &["taa_ms"]) > 0.0, "the TAA pass is timed");
    assert_eq!(f(&configs[0], &["taa_ms"]), 0.0);
    let out = sward(&["bench", "--antialiasing", "--light", "--scene", SCENE]);
    assert!(!out.status.success());
    assert!(String::from_utf8_lossy(&out.stderr).contains("--antialiasing compares"));
    let out = sward(&["bench", "--antialiasing", "--frames", "1", "--scene", SCENE]);
    assert!(!out.status.success());
    assert!(String::from_utf8_lossy(&out.stderr).contains("at least 2"));
}
