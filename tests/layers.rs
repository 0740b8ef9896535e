//! The library's layers (issue 28, point 5; `docs/layers.md`): every top-level module of
//! `src/` has a layer, and its code refers (`crate::…`) only to modules of lower layers. A
//! module that reaches up — the scene validating against a limit kept by the renderer, the
//! field building its blades from the simulation's types — fails here, naming the file,
//! the line and both layers. A new top-level module must be given a layer below.

use std::path::{Path, PathBuf};

/// The layers, lowest first: a module may use the modules of the layers before its own.
const LAYERS: &[(&str, &[&str])] = &[
    (
        "foundations",
        &["error", "shaders", "runtime_env", "compare"],
    ),
    ("foundations over errors", &["output", "gpu", "mesh"]),
    ("input", &["input"]),
    ("scene data", &["scene"]),
    ("field", &["field"]),
    ("simulation", &["sim"]),
    ("session", &["session"]),
    ("rendering", &["render"]),
    ("commands", &["commands"]),
    ("application", &["bench", "app"]),
];

fn layer_of(module: &str) -> Option<usize> {
    LAYERS.iter().position(|(_, ms)| ms.contains(&module))
}

/// One upward reference: file, line, the module there, the module it names.
#[derive(Debug, PartialEq)]
struct Violation {
    file: String,
    line: usize,
    from: String,
    to: String,
}

/// The upward references in `source`, a file of top-level module `from`. Comments are left
/// out (a doc may name a module above to say where something is used).
fn violations_in(file: &str, from: &str, source: &str) -> Vec<Violation> {
    let Some(own) = layer_of(from) else {
        return Vec::new();
    };
    let mut out = Vec::new();
    for (n, line) in source.lines().enumerate() {
        let code = line.split("//").next().unwrap_or("");
        let mut rest = code;
        while let Some(at) = rest.find("crate::") {
            rest = &rest[at + "crate::".len()..];
            let name: String = rest
                .chars()
                .take_while(|c| c.is_ascii_alphanumeric() || *c == '_')
                .collect();
            if let Some(layer) = layer_of(&name) {
                if name != from && layer >= own {
                    out.push(Violation {
                        file: file.into(),
                        line: n + 1,
                        from: from.into(),
                        to: name,
                    });
                }
            }
        }
    }
    out
}

fn rust_files(dir: &Path, out: &mut Vec<PathBuf>) {
    for entry in std::fs::read_dir(dir).expect("read src") {
        let path = entry.expect("entry").path();
        if path.is_dir() {
            rust_files(&path, out);
        } else if path.extension().is_some_and(|e| e == "rs") {
            out.push(path);
        }
    }
}

#[test]
fn every_module_refers_only_to_layers_below_it() {
    let src = Path::new(env!("CARGO_MANIFEST_DIR")).join("src");
    let mut files = Vec::new();
    rust_files(&src, &mut files);
    let mut found = Vec::new();
    let mut checked = 0;
    for path in &files {
        let rel = path.strip_prefix(&src).expect("under src");
        let top = rel
            .components()
            .next()
            .and_then(|c| c.as_os_str().to_str())
            .map(|s| s.trim_end_matches(".rs").to_string())
            .expect("a name");
        if top == "lib" || top == "main" {
            continue;
        }
        assert!(
            layer_of(&top).is_some(),
            "src/{top} has no layer: give it one in tests/layers.rs and docs/layers.md"
        );
        let source = std::fs::read_to_string(path).expect("read");
        found.extend(violations_in(&rel.display().to_string(), &top, &source));
        checked += 1;
    }
    assert!(checked > 100, "only {checked} files checked");
    let report: Vec<String> = found
        .iter()
        .map(|v| {
            format!(
                "src/{}:{}: {} ({}) refers to {} ({})",
                v.file,
                v.line,
                v.from,
                LAYERS[layer_of(&v.from).unwrap()].0,
                v.to,
                LAYERS[layer_of(&v.to).unwrap()].0
            )
        })
        .collect();
    assert!(
        found.is_empty(),
        "references to a layer at or above the module's own:\n{}",
        report.join("\n")
    );
}

/// The checker itself: an upward reference in code is found, one in a comment, a module's
/// own path and a lower layer are not.
#[test]
fn the_checker_finds_a_reference_upwards() {
    let source = "use crate::scene::Scene;\n\
                  use crate::field::HeightField; // crate::render in a comment\n\
                  let x = crate::sim::layout::MAX_SPHERES;\n\
                  //! see crate::render::draw\n\
                  use crate::render::msaa::SAMPLE_COUNTS;\n";
    let found = violations_in("field/x.rs", "field", source);
    assert_eq!(
        found,
        vec![
            Violation {
                file: "field/x.rs".into(),
                line: 3,
                from: "field".into(),
                to: "sim".into(),
            },
            Violation {
                file: "field/x.rs".into(),
                line: 5,
                from: "field".into(),
                to: "render".into(),
            },
        ]
    );
    // A module of the same layer as another counts as above it: bench and app are apart.
    assert_eq!(
        violations_in("bench/x.rs", "bench", "crate::app::run();").len(),
        1
    );
    assert!(violations_in("app/x.rs", "app", "crate::render::Renderer").is_empty());
}
