//! Tests of `bench`.

use super::*;

#[test]
fn dates() {
    assert_eq!(civil_from_days(0), (1970, 1, 1));
    assert_eq!(civil_from_days(19_723), (2024, 1, 1));
    assert_eq!(civil_from_days(19_782), (2024, 2, 29));
    assert_eq!(civil_from_days(-1), (1969, 12, 31));
    assert_eq!(civil_from_days(11_016), (2000, 2, 29));
}

#[test]
fn thousands_separators() {
    assert_eq!(thousands(0), "0");
    assert_eq!(thousands(999), "999");
    assert_eq!(thousands(1000), "1,000");
    assert_eq!(thousands(397_881), "397,881");
    assert_eq!(thousands(7_000_000), "7,000,000");
}

#[test]
fn flags_are_checked() {
    assert!(parse_count("--frames", "0", 1, MAX_FRAMES).is_err());
    assert!(parse_count("--frames", "-3", 1, MAX_FRAMES).is_err());
    assert_eq!(
        parse_count("--frames", " 20 ", 1, MAX_FRAMES).ok(),
        Some(20)
    );
    assert_eq!(parse_size("1280x720").ok(), Some((1280, 720)));
    for bad in ["0x10", "10x0", "1280", "axb", "20000x10", ""] {
        let e = parse_size(bad).expect_err(bad).to_string();
        assert!(e.contains("--size") && e.contains("1..=16384"), "{e}");
    }
    assert_eq!(
        parse_sweep("1000, 2_000,4000").ok(),
        Some(vec![1000, 2000, 4000])
    );
    for bad in ["", " ", "0", "100,50", "100,100", "1,x", "1,,2", "60000000"] {
        let e = parse_sweep(bad).expect_err(bad).to_string();
        assert!(e.contains("--sweep") && e.contains("1..=50000000"), "{e}");
    }
}

/// A mode that runs alone refuses every other mode flag that is set, and names them all;
/// its own flag does not count against it.
#[test]
fn a_mode_alone_refuses_the_others() {
    let mut o = BenchOptions::parse(
        None,
        "2",
        "64x40",
        "0",
        None,
        false,
        sward::gpu::AdapterChoice::Auto,
    )
    .expect("options");
    o.antialiasing = true;
    assert!(refuse_beside(&o, "--antialiasing", "compares").is_ok());
    o.light = true;
    let e = refuse_beside(&o, "--antialiasing", "compares the anti-aliasing alone")
        .expect_err("--light is set")
        .to_string();
    assert!(
        e.starts_with(
            "--antialiasing compares the anti-aliasing alone: it does not go with --flight, "
        ),
        "{e}"
    );
    assert!(
        e.contains("--light") && e.ends_with(" or --colliders"),
        "{e}"
    );
    assert!(!e.contains("--antialiasing,"), "{e}");
}

#[test]
fn configurations_switch_one_feature() {
    let mut scene = Scene::default();
    scene.culling.orientation = false;
    scene.culling.grass_occlusion = false;
    scene.physics.collisions = false;
    let all = Config::All.apply(&scene);
    let c = &all.culling;
    assert!(all.physics.collisions && c.orientation && c.patches && c.grass_occlusion);
    // The distance test is the scene's choice in both culling columns.
    assert!(!c.distance);
    scene.culling.distance = true;
    let all = Config::All.apply(&scene);
    assert!(all.culling.distance);
    let nc = Config::NoCollisions.apply(&scene);
    assert!(!nc.physics.collisions && nc.culling.frustum && nc.culling.distance);
    let off = Config::NoCulling.apply(&scene);
    let c = &off.culling;
    assert!(off.physics.collisions);
    assert!(!(c.patches || c.orientation || c.frustum || c.distance || c.occlusion));
}

#[test]
fn sweep_scene_hits_the_count() {
    let mut scene = Scene::default();
    scene.terrain.size = 7.3;
    scene.field.patch_size = 1024;
    for n in [100, 2000, 4000, 65_536, 100_000, 397_881, 1_000_000] {
        let (s, total) = sweep_scene(&scene, n);
        assert!(total >= n, "{n}: {total}");
        assert!(
            total as f64 <= (n as f64 * 1.02).max((n + 64) as f64),
            "{n}: {total} with patches of {}",
            s.field.patch_size
        );
        assert!(f64::from(s.field.density) * 7.3f64.powi(2) <= n as f64);
        assert_eq!(s.field.patch_size % 64, 0);
        assert_eq!(s.field.tile_size, 0.0, "a sweep point is a whole field");
    }
    // Even from a streamed scene.
    scene.field.tile_size = 8.0;
    assert_eq!(sweep_scene(&scene, 100_000).0.field.tile_size, 0.0);
}

#[test]
fn without_timestamps_the_table_says_so() {
    let column = |name: &str| ConfigReport {
        name: name.into(),
        fps: 10.0,
        frame_ms: 100.0,
        frame_time_source: "wall clock".into(),
        wall_ms: 100.0,
        blades: BladeCounts {
            total: 1024,
            drawn: 1024,
            ..Default::default()
        },
        gpu_ms: None,
        colliders: 0,
        colliders_considered: 0,
        sphere_tests_per_blade: 0.0,
        blades_reset_nonfinite: 0,
        memory: memory(1024, (90_000, 200_000)),
        work: None,
    };
    let mut configurations: Vec<_> = Config::COLUMNS.iter().map(|c| column(c.name())).collect();
    // Culling off is slower: the ratio is its wall clock over all features' (2.5).
    let off = Config::COLUMNS
        .iter()
        .position(|c| c.name() == "culling off")
        .expect("a culling-off column");
    configurations[off].frame_ms = 250.0;
    configurations[off].wall_ms = 250.0;
    let report = BenchReport {
        adapter: "test adapter".into(),
        date: utc_now(),
        scene: "scene.ron".into(),
        size: [64, 36],
        frames: 3,
        warmup: 0,
        dt: BENCH_DT,
        timestamps: false,
        ratios: ratios(&configurations),
        configurations,
        sweep: Vec::new(),
    };
    assert_eq!(report.ratios.culling_off_over_all_frame_time, Some(2.5));
    assert_eq!(
        report
            .ratios
            .physics_per_blade_over_rendering_per_drawn_blade,
        None
    );
    let table = format_report(&report);
    assert!(table.contains("no timestamp queries"), "{table}");
    assert!(table.contains("frame time, wall clock (ms)"), "{table}");
    assert!(table.contains("n/a"), "{table}");
    assert!(!table.contains("note:"), "{table}");
}

#[test]
fn ratios_follow_the_paper() {
    // Table 1 of the paper, all features and culling off.
    let column = |name: &str, frame_ms: f64, drawn: u64, culled: u64, patch: u64| ConfigReport {
        name: name.into(),
        fps: fps(frame_ms),
        frame_ms,
        frame_time_source: "gpu".into(),
        wall_ms: frame_ms,
        blades: BladeCounts {
            total: 397_881,
            drawn,
            culled: culled + patch,
            culled_patch: patch,
            culled_orientation: culled,
            // The paper steps every blade every frame.
            stepped: 397_881,
            ..Default::default()
        },
        gpu_ms: Some(GpuMs {
            physics: 0.547,
            update: 0.547,
            wind: 0.0,
            visibility: 1.401,
            rendering: 2.057,
            ..Default::default()
        }),
        colliders: 1000,
        colliders_considered: 183,
        sphere_tests_per_blade: 0.0,
        blades_reset_nonfinite: 0,
        memory: Memory::default(),
        work: None,
    };
    let patch = 397_881 - 168_333;
    let r = ratios(&[
        column("all features", 8.13, 43_128, 125_205, patch),
        column("culling off", 12.821, 397_881, 0, 0),
    ]);
    let near = |v: Option<f64>, want: f64| (v.expect("ratio") - want).abs() < 1e-3;
    assert!(near(r.culling_off_over_all_frame_time, 1.577));
    assert!(near(r.culled_over_visible_patch_blades, 0.744));
    assert!(near(
        r.physics_per_blade_over_rendering_per_drawn_blade,
        (0.547 / 397_881.0) / (2.057 / 43_128.0)
    ));
}
