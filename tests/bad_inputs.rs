//! The memory-and-honesty issue's classes of bad input, one test per class, each through
//! the command line with inputs made in a temporary directory: structures that can be
//! cyclic (a glTF node graph), values in range that used to divide by almost zero (a
//! rolling radius), messages that must name what is wrong (file, flag, field, range), and
//! the Verlet dump's two states. Every run is bounded in time: a loop is a failure, not a
//! hung test.

use std::path::PathBuf;
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

/// One triangle, (0,0,0) (1,0,0) (0,1,0), as glTF float32 positions in base64.
const TRIANGLE: &str = "AAAAAAAAAAAAAAAAAACAPwAAAAAAAAAAAAAAAAAAgD8AAAAA";

/// Runs sward with `args`, killed after `seconds`; (success, stderr).
fn sward(args: &[&str], seconds: u64) -> (bool, String) {
    let mut child = Command::new(env!("CARGO_BIN_EXE_sward"))
        .args(args)
        .env(
            "SWARD_ADAPTER",
            std::env::var("SWARD_ADAPTER").unwrap_or_else(|_| "software".into()),
        )
        .env("RUST_BACKTRACE", "0")
        .env_remove("DISPLAY")
        .env_remove("WAYLAND_DISPLAY")
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .expect("run sward");
    let start = Instant::now();
    loop {
        if let Some(status) = child.try_wait().expect("wait") {
            let out = child.wait_with_output().expect("stderr");
            return (
                status.success(),
                String::from_utf8_lossy(&out.stderr).into_owned(),
            );
        }
        if start.elapsed() > Duration::from_secs(seconds) {
            let _ = child.kill();
            panic!("sward {args:?} still running after {seconds} s");
        }
        std::thread::sleep(Duration::from_millis(50));
    }
}

/// A run that must fail cleanly: no panic, an `error:` line; its stderr.
fn fails(args: &[&str]) -> String {
    let (ok, stderr) = sward(args, 120);
    assert!(!ok, "expected failure for {args:?}: {stderr}");
    assert!(!stderr.contains("panicked"), "panic for {args:?}: {stderr}");
    assert!(stderr.contains("error"), "no error for {args:?}: {stderr}");
    stderr
}

struct Tmp(PathBuf);

impl Tmp {
    fn new(name: &str) -> Self {
        let dir = std::env::temp_dir().join(format!("sward-bad-{}-{name}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(&dir).expect("temp dir");
        Tmp(dir)
    }
    fn file(&self, name: &str, text: &str) -> String {
        let path = self.0.join(name);
        std::fs::write(&path, text).expect("write");
        path.to_str().expect("utf-8").to_owned()
    }
    fn s(&self, name: &str) -> String {
        self.0.join(name).to_str().expect("utf-8").to_owned()
    }
}

impl Drop for Tmp {
    fn drop(&mut self) {
        let _ = std::fs::remove_dir_all(&self.0);
    }
}

/// A glTF document with one triangle mesh, the given `nodes` JSON and `buffer` JSON.
fn gltf(nodes: &str, buffer: &str, accessor_count: u32) -> String {
    format!(
        r#"{{"asset":{{"version":"2.0"}},"scene":0,"scenes":[{{"nodes":[0]}}],
        "nodes":{nodes},
        "meshes":[{{"primitives":[{{"attributes":{{"POSITION":0}}}}]}}],
        "accessors":[{{"bufferView":0,"componentType":5126,"count":{accessor_count},"type":"VEC3",
            "min":[0,0,0],"max":[1,1,0]}}],
        "bufferViews":[{{"buffer":0,"byteLength":36}}],
        "buffers":[{buffer}]}}"#
    )
}

fn embedded() -> String {
    format!(r#"{{"byteLength":36,"uri":"data:application/octet-stream;base64,{TRIANGLE}"}}"#)
}

/// A scene with the mesh `file` as a static object over a small field.
fn scene_with_mesh(tmp: &Tmp, file: &str) -> String {
    tmp.file(
        "scene.ron",
        &format!(
            "(terrain: (size: 8.0, resolution: 9), field: (density: 20.0), \
             objects: [(mesh: \"{file}\")])"
        ),
    )
}

#[test]
fn a_gltf_node_graph_that_is_not_a_tree_is_refused() {
    let tmp = Tmp::new("cycle");
    // A node that is its own ancestor: the loader used to walk it until memory ran out.
    tmp.file(
        "cycle.gltf",
        &gltf(
            r#"[{"children":[1]},{"children":[0],"mesh":0}]"#,
            &embedded(),
            3,
        ),
    );
    let scene = scene_with_mesh(&tmp, "cycle.gltf");
    let out = tmp.s("out.png");
    let e = fails(&[
        "render", "--scene", &scene, "--frames", "1", "--size", "32x18", "--out", &out,
    ]);
    assert!(
        e.contains("cycle.gltf") && e.contains("own ancestor"),
        "{e}"
    );
    assert!(!std::path::Path::new(&out).exists());
    // A node with two parents (a DAG that can expand exponentially) is no tree either.
    tmp.file(
        "shared.gltf",
        &gltf(
            r#"[{"children":[1,2]},{"children":[3]},{"children":[3]},{"mesh":0}]"#,
            &embedded(),
            3,
        ),
    );
    let scene = scene_with_mesh(&tmp, "shared.gltf");
    let e = fails(&[
        "render", "--scene", &scene, "--frames", "1", "--size", "32x18", "--out", &out,
    ]);
    assert!(
        e.contains("node 3 is a child of both node 1 and node 2"),
        "{e}"
    );
}

#[test]
fn gltf_errors_name_the_missing_file_and_the_accessor() {
    let tmp = Tmp::new("gltf-msg");
    tmp.file(
        "external.gltf",
        &gltf(
            r#"[{"mesh":0}]"#,
            r#"{"byteLength":36,"uri":"triangle%20data.bin"}"#,
            3,
        ),
    );
    let scene = scene_with_mesh(&tmp, "external.gltf");
    let out = tmp.s("out.png");
    let e = fails(&[
        "render", "--scene", &scene, "--frames", "1", "--size", "32x18", "--out", &out,
    ]);
    assert!(
        e.contains("triangle data.bin"),
        "the missing .bin is named: {e}"
    );
    // An accessor that claims more vertices than its view holds.
    tmp.file("past.gltf", &gltf(r#"[{"mesh":0}]"#, &embedded(), 30));
    let scene = scene_with_mesh(&tmp, "past.gltf");
    let e = fails(&[
        "render", "--scene", &scene, "--frames", "1", "--size", "32x18", "--out", &out,
    ]);
    assert!(e.contains("accessor 0 (POSITION) runs past the end"), "{e}");
}

#[test]
fn a_rolling_radius_near_zero_is_refused_and_a_small_one_stays_finite() {
    let tmp = Tmp::new("roll");
    let scene = |y: &str| {
        tmp.file(
            "roll.ron",
            &format!(
                "(terrain: (size: 8.0, resolution: 9), field: (density: 30.0), \
                 objects: [(mesh: \"{}\", translation: (0.0, {y}, 0.0), scale: 0.3, \
                 collider: Spheres((count: 20)), \
                 motion: Path(points: [(-3.0, 0.0), (3.0, 0.0)], speed: 2.0, looped: true), \
                 rolls: true)])",
                std::path::absolute("assets/models/planet.obj")
                    .expect("path")
                    .display()
            ),
        )
    };
    let dump = tmp.s("dump.json");
    let e = fails(&[
        "simulate",
        "--scene",
        &scene("1e-45"),
        "--steps",
        "3",
        "--dump",
        &dump,
    ]);
    assert!(
        e.contains("objects[0].translation") && e.contains("rolling radius") && e.contains("0.001"),
        "{e}"
    );
    // The smallest allowed radius spins the object fast; nothing becomes NaN.
    let (ok, stderr) = sward(
        &[
            "simulate",
            "--scene",
            &scene("0.001"),
            "--steps",
            "20",
            "--dump",
            &dump,
        ],
        300,
    );
    assert!(ok, "{stderr}");
    assert!(stderr.contains("non-finite state: 0"), "{stderr}");
}

#[test]
fn command_line_errors_name_the_flag_field_and_range() {
    let tmp = Tmp::new("flags");
    let out = tmp.s("out.png");
    // An enum given a number lists its variants, not RON's raw-identifier advice.
    let e = fails(&["render", "--set", "physics.model=1", "--out", &out]);
    assert!(
        e.contains("allowed Jahrmann, Verlet or Cwd") && !e.contains("r#"),
        "{e}"
    );
    // A negative count reaches the range check however it is written.
    for args in [
        ["bench", "--colliders", "-1"],
        ["bench", "--colliders=-1", ""],
    ] {
        let args: Vec<&str> = args.into_iter().filter(|a| !a.is_empty()).collect();
        let e = fails(&args);
        assert!(e.contains("from 1 to 16384"), "{e}");
    }
    let e = fails(&["render", "--frames", "-3", "--out", &out]);
    assert!(e.contains("--frames") && e.contains("1..="), "{e}");
    // A size the adapter cannot hold: refused before allocating, naming --size and the
    // largest size it can hold.
    let e = fails(&["render", "--size", "16384x16384", "--out", &out]);
    assert!(
        e.contains("--size 16384x16384") && e.contains("largest size"),
        "{e}"
    );
    assert!(!e.contains("Out of Memory"), "{e}");
    for mode in [&[][..], &["--light"][..], &["--flight"][..]] {
        let mut args = vec!["bench", "--size", "16384x16384"];
        args.extend(mode);
        let e = fails(&args);
        assert!(
            e.contains("--size 16384x16384") && e.contains("largest size"),
            "{e}"
        );
    }
    // A scene that is not a file names the flag.
    let fifo = tmp.s("fifo");
    assert!(Command::new("mkfifo")
        .arg(&fifo)
        .status()
        .expect("mkfifo")
        .success());
    let e = fails(&["render", "--scene", &fifo, "--out", &out]);
    assert!(
        e.contains("--scene") && e.contains("not a regular file"),
        "{e}"
    );
    // A mesh named by --set is blamed on the --set, not on line 1 of the scene file.
    let e = fails(&[
        "render",
        "--set",
        "objects=[(mesh: \"nope.obj\")]",
        "--out",
        &out,
    ]);
    assert!(
        e.contains("error: --set objects=") && e.contains("nope.obj"),
        "{e}"
    );
    // A wind grid too big for the adapter: the wind's fields, not the blades'.
    let e = fails(&[
        "render",
        "--set",
        "wind.source=Fluid",
        "--set",
        "wind.fluid.resolution=2048",
        "--set",
        "wind.fluid.layers=16",
        "--out",
        &out,
    ]);
    assert!(e.contains("wind.fluid.resolution"), "{e}");
    assert!(
        !e.contains("field.density"),
        "advice that does not apply: {e}"
    );
    // A packing out of range names an assignment --set accepts.
    let bunny = "assets/scenes/bunny_meadow.ron";
    let e = fails(&[
        "render",
        "--scene",
        bunny,
        "--set",
        "objects[0].collider=Spheres((count: 0))",
        "--out",
        &out,
    ]);
    assert!(e.contains("objects[0].collider=Spheres((count:"), "{e}");
    assert!(!std::path::Path::new(&out).exists());
    // A field too large to generate names the scene file's line of its density.
    let many = tmp.file(
        "many.ron",
        "(terrain: (size: 10000.0),\n field: (density: 10000.0, tile_size: 0.0))",
    );
    let e = fails(&["render", "--scene", &many, "--out", &out]);
    assert!(
        e.contains("many.ron:2:") && e.contains("field.density"),
        "{e}"
    );
}

/// The `initial` and `final` blades of a `simulate` dump of 256 blades of the default
/// meadow, two steps, with `sets`.
fn dump(tmp: &Tmp, sets: &[&str]) -> serde_json::Value {
    let path = tmp.s("dump.json");
    let mut args = vec![
        "simulate", "--blades", "256", "--steps", "2", "--dump", &path,
    ];
    for set in sets {
        args.extend(["--set", set]);
    }
    let (ok, stderr) = sward(&args, 300);
    assert!(ok, "{stderr}");
    serde_json::from_str(&std::fs::read_to_string(&path).expect("dump")).expect("json")
}

fn point(v: &serde_json::Value) -> [f64; 3] {
    let a = v.as_array().expect("a point");
    [0, 1, 2].map(|k| a[k].as_f64().expect("a number"))
}

#[test]
fn both_states_of_a_verlet_run_are_verlet_blades() {
    let tmp = Tmp::new("verlet");
    let verlet = dump(&tmp, &["physics.model=Verlet"]);
    assert_eq!(verlet["model"], "Verlet");
    for state in ["initial", "final"] {
        let blades = verlet[state].as_array().expect("blades");
        assert_eq!(blades.len(), 256, "{state}");
        assert!(
            blades.iter().all(|b| b["v3"].is_array()),
            "every {state} blade has the four points of its cubic"
        );
    }
    // Not stepped yet, a Verlet blade is the field's quadratic raised in degree: the same
    // root and tip, and P1 two thirds of the way from the root to the quadratic's v1.
    let jahrmann = dump(&tmp, &[]);
    let quads = jahrmann["initial"].as_array().expect("blades");
    let cubics = verlet["initial"].as_array().expect("blades");
    for (q, c) in quads.iter().zip(cubics) {
        let (q0, q1, q2) = (point(&q["v0"]), point(&q["v1"]), point(&q["v2"]));
        let (c0, c1, c3) = (point(&c["v0"]), point(&c["v1"]), point(&c["v3"]));
        for k in 0..3 {
            assert!((c0[k] - q0[k]).abs() < 1e-5, "root {c0:?} {q0:?}");
            assert!((c3[k] - q2[k]).abs() < 1e-5, "tip {c3:?} {q2:?}");
            let p1 = q0[k] + 2.0 / 3.0 * (q1[k] - q0[k]);
            assert!((c1[k] - p1).abs() < 1e-5, "P1 {c1:?} against {p1}");
        }
    }
}
