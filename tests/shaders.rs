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
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("shaders");
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
