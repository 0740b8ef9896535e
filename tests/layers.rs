//! The layers (issue 28, points 1 and 5; `docs/layers.md`): every top-level module of the
//! library (`crates/sward/src/`) and of the application (`src/`) has a layer, and its code
//! refers (`crate::…`) only to modules of lower layers. A module that reaches up — the
//! scene validating against a limit kept by the renderer, the field building its blades
//! from the simulation's types — fails here, naming the file, the line and both layers. A
//! new top-level module must be given a layer below. The library's manifest must not
//! bring in what only the application needs (window, panel, command line, logger,
//! executor).

use std::path::{Path, PathBuf};

/// A crate's layers, lowest first: a module may use the modules of the layers before its
/// own.
type Layers = &'static [(&'static str, &'static [&'static str])];

/// The library `sward`.
const LIBRARY: Layers = &[
    ("foundations", &["error", "shaders", "compare"]),
    ("foundations over errors", &["output", "gpu", "mesh"]),
    ("input", &["input"]),
    ("scene data", &["scene"]),
    ("field", &["field"]),
    ("simulation", &["sim"]),
    ("session", &["session"]),
    ("rendering", &["render"]),
    ("embedding", &["embed"]),
    ("commands", &["commands"]),
];

/// The application `sward-app` (the library is below all of it).
const APPLICATION: Layers = &[
    ("start-up", &["runtime_env"]),
    ("application", &["bench", "app"]),
];

/// What the library must not depend on: the application's window, panel, command line,
/// logger and executor.
const NOT_IN_THE_LIBRARY: &[&str] = &[
    "winit",
    "egui",
    "egui-wgpu",
    "egui-winit",
    "clap",
    "env_logger",
    "pollster",
];

fn layer_of(layers: Layers, module: &str) -> Option<usize> {
    layers.iter().position(|(_, ms)| ms.contains(&module))
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
fn violations_in(layers: Layers, file: &str, from: &str, source: &str) -> Vec<Violation> {
    let Some(own) = layer_of(layers, from) else {
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
            if let Some(layer) = layer_of(layers, &name) {
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

/// Checks the crate whose sources are `src` against `layers`; returns the files checked.
fn check_crate(src: &Path, layers: Layers) -> usize {
    let mut files = Vec::new();
    rust_files(src, &mut files);
    let mut found = Vec::new();
    let mut checked = 0;
    for path in &files {
        let rel = path.strip_prefix(src).expect("under src");
        let top = rel
            .components()
            .next()
            .and_then(|c| c.as_os_str().to_str())
            .map(|s| s.trim_end_matches(".rs").to_string())
            .expect("a name");
        // The crate roots, and the binary's test of its guide (`doc_commands`, a test
        // module of `main`), stand above every layer.
        if top == "lib" || top == "main" || top == "doc_commands" {
            continue;
        }
        assert!(
            layer_of(layers, &top).is_some(),
            "{}/{top} has no layer: give it one in tests/layers.rs and docs/layers.md",
            src.display()
        );
        let source = std::fs::read_to_string(path).expect("read");
        found.extend(violations_in(
            layers,
            &rel.display().to_string(),
            &top,
            &source,
        ));
        checked += 1;
    }
    let report: Vec<String> = found
        .iter()
        .map(|v| {
            format!(
                "{}/{}:{}: {} ({}) refers to {} ({})",
                src.display(),
                v.file,
                v.line,
                v.from,
                layers[layer_of(layers, &v.from).unwrap()].0,
                v.to,
                layers[layer_of(layers, &v.to).unwrap()].0
            )
        })
        .collect();
    assert!(
        found.is_empty(),
        "references to a layer at or above the module's own:\n{}",
        report.join("\n")
    );
    checked
}

fn root() -> &'static Path {
    Path::new(env!("CARGO_MANIFEST_DIR"))
}

#[test]
fn every_module_refers_only_to_layers_below_it() {
    let library = check_crate(&root().join("crates/sward/src"), LIBRARY);
    assert!(library > 100, "only {library} library files checked");
    let application = check_crate(&root().join("src"), APPLICATION);
    assert!(
        application > 20,
        "only {application} application files checked"
    );
}

/// The names of the `[dependencies]` table of a Cargo manifest (not the dev- or build-
/// dependencies).
fn normal_dependencies(manifest: &str) -> Vec<String> {
    let mut out = Vec::new();
    let mut inside = false;
    for line in manifest.lines() {
        let line = line.trim();
        if line.starts_with('[') {
            inside = line == "[dependencies]";
        } else if inside && !line.starts_with('#') {
            if let Some((name, _)) = line.split_once('=') {
                out.push(name.trim().to_string());
            }
        }
    }
    out
}

#[test]
fn the_library_depends_on_no_window_panel_or_command_line() {
    let manifest =
        std::fs::read_to_string(root().join("crates/sward/Cargo.toml")).expect("manifest");
    let deps = normal_dependencies(&manifest);
    assert!(deps.iter().any(|d| d == "wgpu"), "read {deps:?}");
    let bad: Vec<&String> = deps
        .iter()
        .filter(|d| NOT_IN_THE_LIBRARY.contains(&d.as_str()))
        .collect();
    assert!(
        bad.is_empty(),
        "crates/sward/Cargo.toml depends on {bad:?}, which are the application's"
    );
    // The reader itself: a table after [dependencies] ends it.
    let sample = "[dependencies]\nwgpu = \"30\"\n[dev-dependencies]\nclap = \"4\"\n";
    assert_eq!(normal_dependencies(sample), vec!["wgpu".to_string()]);
}

/// A host's view of the library (issue 28, point 4): without the `internals` feature, which
/// no default turns on, the only public modules are the embedding API, the scene types and
/// the error; every other top-level module is declared through `internal!`, crate-private.
#[test]
fn a_host_sees_only_the_embedding_api_the_scene_and_the_error() {
    let lib = std::fs::read_to_string(root().join("crates/sward/src/lib.rs")).expect("lib.rs");
    let public: Vec<&str> = lib
        .lines()
        .filter_map(|l| l.trim().strip_prefix("pub mod "))
        .map(|m| m.trim_end_matches(';'))
        .filter(|m| !m.starts_with('$'))
        .collect();
    assert_eq!(public, ["embed", "error", "scene"]);
    let internal = lib
        .lines()
        .find_map(|l| l.trim().strip_prefix("internal!("))
        .expect("the internal modules");
    let declared = std::fs::read_dir(root().join("crates/sward/src"))
        .expect("src")
        .filter_map(|e| {
            let name = e.ok()?.file_name().into_string().ok()?;
            let module = name.trim_end_matches(".rs").to_string();
            (module != "lib").then_some(module)
        })
        .filter(|m| !public.contains(&m.as_str()))
        .collect::<Vec<_>>();
    for module in &declared {
        assert!(
            internal.contains(module.as_str()),
            "{module} is neither public nor declared internal"
        );
    }
    let manifest =
        std::fs::read_to_string(root().join("crates/sward/Cargo.toml")).expect("manifest");
    assert!(
        manifest.contains("internals = []"),
        "the feature, off by default"
    );
    assert!(!manifest.contains("default ="), "no default features");
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
    let found = violations_in(LIBRARY, "field/x.rs", "field", source);
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
        violations_in(APPLICATION, "bench/x.rs", "bench", "crate::app::run();").len(),
        1
    );
    assert!(violations_in(APPLICATION, "app/x.rs", "app", "crate::runtime_env::x()").is_empty());
}
