//! Every WGSL entry file, with its includes expanded, is parsed and validated by naga —
//! no GPU needed, so a shader error fails here with naga's message and line.

use sward::shaders::{source, ENTRY_FILES};

#[test]
fn every_entry_file_parses_and_validates() {
    let mut checked = 0;
    for name in ENTRY_FILES {
        let src = source(name);
        let module = naga::front::wgsl::parse_str(&src)
            .unwrap_or_else(|e| panic!("{name}: {}", e.emit_to_string(&src)));
        naga::valid::Validator::new(
            naga::valid::ValidationFlags::all(),
            naga::valid::Capabilities::all(),
        )
        .validate(&module)
        .unwrap_or_else(|e| panic!("{name}: {}", e.emit_to_string(&src)));
        assert!(!module.entry_points.is_empty(), "{name} has no entry point");
        checked += 1;
    }
    assert_eq!(checked, ENTRY_FILES.len());
}

#[test]
fn every_shader_file_is_reachable_from_an_entry_file() {
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("crates/sward/shaders");
    let all: String = ENTRY_FILES.iter().map(|n| source(n)).collect();
    for entry in std::fs::read_dir(&dir).expect("shaders/ exists") {
        let path = entry.expect("readable").path();
        let text = std::fs::read_to_string(&path).expect("readable shader");
        // The first non-comment line of each file must appear in some expanded entry.
        let line = text
            .lines()
            .find(|l| !l.trim().is_empty() && !l.trim_start().starts_with("//"))
            .expect("shader has code");
        assert!(
            all.contains(line),
            "{} is not used by any entry file",
            path.display()
        );
    }
}

/// The constants the shaders share with Rust hold the same values (a mismatch would
/// size a struct or a buffer differently on the two sides without any error).
#[test]
fn shared_constants_match_rust() {
    use sward::sim::layout::{
        BVH_NODE_BASE, DRAW_BATCH, MAX_SPHERES, PATCH_SPHERE_STRIDE, SEEN_CANDIDATE,
        SEEN_DRAWN_EARLY, SEEN_NO, SEEN_YES, SPHERES_ALL,
    };
    let value_in = |file: &str, name: &str| -> u64 {
        let src = source(file);
        let line = src
            .lines()
            .find(|l| l.starts_with(&format!("const {name}: u32 = ")))
            .unwrap_or_else(|| panic!("{file} has no const {name}"));
        let text = line
            .split('=')
            .nth(1)
            .expect("a value")
            .trim()
            .trim_end_matches(';')
            .trim_end_matches('u');
        match text.strip_prefix("0x") {
            Some(hex) => u64::from_str_radix(hex, 16).expect("hex"),
            None => text.parse().expect("a number"),
        }
    };
    let value = |name: &str| value_in("common.wgsl", name);
    assert_eq!(value("PATCH_SPHERE_STRIDE"), u64::from(PATCH_SPHERE_STRIDE));
    assert_eq!(value("SPHERES_ALL"), u64::from(SPHERES_ALL));
    assert_eq!(value("DRAW_BATCH"), u64::from(DRAW_BATCH));
    assert_eq!(value("SPHERE_WORDS"), (MAX_SPHERES / 32) as u64);
    assert_eq!(value("BVH_NODE_BASE"), BVH_NODE_BASE as u64);
    // The blades' seen states: the cull's and the tile generation's (a new tile's start).
    for (name, rust) in [
        ("SEEN_NO", SEEN_NO),
        ("SEEN_YES", SEEN_YES),
        ("SEEN_DRAWN_EARLY", SEEN_DRAWN_EARLY),
        ("SEEN_CANDIDATE", SEEN_CANDIDATE),
    ] {
        assert_eq!(value(name), u64::from(rust), "{name}");
    }
    // The deferred light's dispatch sizes: the shading's workgroup and the pixel pass's run.
    use sward::render::deferred::{LIST_RUN, SHADE_GROUP, SUN_INVOCATIONS, SUN_POINTS};
    assert_eq!(
        value_in("grass_vis.wgsl", "SHADE_GROUP"),
        u64::from(SHADE_GROUP)
    );
    assert_eq!(
        value_in("grass_deferred.wgsl", "LIST_RUN"),
        u64::from(LIST_RUN)
    );
    // The sun along the drawn blades: its points per blade and its invocations.
    assert_eq!(
        value_in("grass_vis.wgsl", "SUN_POINTS"),
        u64::from(SUN_POINTS)
    );
    assert_eq!(
        value_in("grass_vis.wgsl", "SUN_INVOCATIONS"),
        u64::from(SUN_INVOCATIONS)
    );
}

/// The flower stem's width is written in three places (the generators' `STEM_WIDTH`, the
/// WGSL twin, and the cull that spares stems from the orientation test): one value.
#[test]
fn flower_stem_width_matches_rust() {
    let rust = sward::field::clumps::STEM_WIDTH;
    assert_eq!(float_in("clumps.wgsl", "STEM_WIDTH"), rust);
    assert_eq!(float_in("cull.wgsl", "FLOWER_STEM_WIDTH"), rust);
}

/// The deferred grass's marker is written in three places (the shading's `BLADE_ALPHA`, its
/// Rust twin, and the far gain's measurement that reads it, which does not include the
/// shading's file): one value.
#[test]
fn blade_alpha_matches_rust() {
    let rust = sward::render::deferred::BLADE_ALPHA;
    assert_eq!(float_in("grass_vis.wgsl", "BLADE_ALPHA"), rust);
    assert_eq!(float_in("far_gain_common.wgsl", "MARKED_ALPHA"), rust);
}

/// The value of `const {name}: f32 = …;` in shader `file`.
fn float_in(file: &str, name: &str) -> f32 {
    let src = source(file);
    let line = src
        .lines()
        .find(|l| l.starts_with(&format!("const {name}: f32 = ")))
        .unwrap_or_else(|| panic!("{file} has no const {name}"));
    line.rsplit('=')
        .next()
        .unwrap()
        .trim()
        .trim_end_matches(';')
        .parse()
        .expect("a number")
}
