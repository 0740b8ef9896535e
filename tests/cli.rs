//! The command line against bad input: each case must end with a clear message on stderr, a
//! non-zero exit code, no panic and no output file (not even a partial one).

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

fn sward(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_sward"))
        .args(args)
        .env(
            "SWARD_ADAPTER",
            std::env::var("SWARD_ADAPTER").unwrap_or_else(|_| "software".into()),
        )
        .env("RUST_BACKTRACE", "0")
        .output()
        .expect("run sward")
}

struct Tmp(PathBuf);

impl Tmp {
    fn new(name: &str) -> Self {
        let dir = std::env::temp_dir().join(format!("sward-cli-{}-{name}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(&dir).expect("temp dir");
        Tmp(dir)
    }
    fn file(&self, name: &str, text: &str) -> PathBuf {
        let p = self.0.join(name);
        std::fs::write(&p, text).expect("write");
        p
    }
    fn path(&self, name: &str) -> PathBuf {
        self.0.join(name)
    }
    /// Nothing but the inputs is left in the directory.
    fn assert_only(&self, inputs: &[&str]) {
        for e in std::fs::read_dir(&self.0).expect("read dir") {
            let name = e.expect("entry").file_name().to_string_lossy().into_owned();
            assert!(
                inputs.contains(&name.as_str()),
                "unexpected output file {name}"
            );
        }
    }
}

impl Drop for Tmp {
    fn drop(&mut self) {
        let _ = std::fs::remove_dir_all(&self.0);
    }
}

/// Runs a failing command and returns its stderr after the common checks.
fn fails(args: &[&str]) -> String {
    let out = sward(args);
    let stderr = String::from_utf8_lossy(&out.stderr).into_owned();
    assert!(!out.status.success(), "expected failure for {args:?}");
    assert!(!stderr.contains("panicked"), "panic for {args:?}: {stderr}");
    assert!(
        stderr.contains("error:"),
        "no error message for {args:?}: {stderr}"
    );
    stderr
}

fn render_args<'a>(scene: &'a str, out: &'a str) -> Vec<&'a str> {
    vec![
        "render", "--scene", scene, "--size", "32x32", "--frames", "1", "--out", out,
    ]
}

#[test]
fn missing_scene_file_is_named() {
    let t = Tmp::new("missing");
    let out = t.path("out.png");
    let missing = t.path("nope.ron");
    let err = fails(&render_args(
        missing.to_str().unwrap(),
        out.to_str().unwrap(),
    ));
    assert!(err.contains("nope.ron"), "{err}");
    t.assert_only(&[]);
}

#[test]
fn malformed_ron_reports_the_line() {
    let t = Tmp::new("malformed");
    let scene = t.file("bad.ron", "(\n    field: (\n        density: 10.0,\n        height: (min: 0.2 max: 0.5),\n    ),\n)\n");
    let out = t.path("out.png");
    let err = fails(&render_args(scene.to_str().unwrap(), out.to_str().unwrap()));
    assert!(
        err.contains("bad.ron:4:"),
        "error must name file and line 4: {err}"
    );
    t.assert_only(&["bad.ron"]);
}

#[test]
fn unknown_field_is_rejected_by_name() {
    let t = Tmp::new("unknown");
    let scene = t.file(
        "typo.ron",
        "(\n    field: (\n        densty: 10.0,\n    ),\n)\n",
    );
    let out = t.path("out.png");
    let err = fails(&render_args(scene.to_str().unwrap(), out.to_str().unwrap()));
    assert!(
        err.contains("densty") && err.contains("typo.ron:3:"),
        "{err}"
    );
    t.assert_only(&["typo.ron"]);
}

#[test]
fn negative_density_names_field_line_and_range() {
    let t = Tmp::new("negative");
    let scene = t.file(
        "neg.ron",
        "(\n    terrain: (size: 4.0),\n    field: (\n        density: -3.0,\n    ),\n)\n",
    );
    let dump = t.path("dump.json");
    let err = fails(&[
        "simulate",
        "--scene",
        scene.to_str().unwrap(),
        "--steps",
        "1",
        "--dump",
        dump.to_str().unwrap(),
    ]);
    assert!(
        err.contains("field.density") && err.contains("neg.ron:4:") && err.contains("allowed"),
        "{err}"
    );
    t.assert_only(&["neg.ron"]);
}

#[test]
fn blade_count_beyond_the_adapter_is_refused_before_allocating() {
    let t = Tmp::new("toomany");
    // 10,000 blades/m² on 4 km × 4 km is 1.6e11 blades: no adapter holds that in one buffer.
    let scene = t.file(
        "huge.ron",
        "(\n    terrain: (size: 4000.0),\n    field: (density: 10000.0),\n)\n",
    );
    let out = t.path("out.png");
    let err = fails(&render_args(scene.to_str().unwrap(), out.to_str().unwrap()));
    assert!(err.contains("blades") && err.contains("at most"), "{err}");
    t.assert_only(&["huge.ron"]);
    // The same through --blades.
    let dump = t.path("dump.json");
    let err = fails(&[
        "simulate",
        "--blades",
        "40000000",
        "--steps",
        "1",
        "--dump",
        dump.to_str().unwrap(),
    ]);
    assert!(err.contains("blades") && err.contains("at most"), "{err}");
    let err = fails(&[
        "simulate",
        "--blades",
        "999999999999",
        "--steps",
        "1",
        "--dump",
        dump.to_str().unwrap(),
    ]);
    assert!(err.contains("out of range"), "{err}");
    t.assert_only(&["huge.ron"]);
}

#[test]
fn bad_size_and_dt_are_out_of_range() {
    let t = Tmp::new("size");
    let out = t.path("out.png");
    let err = fails(&["render", "--size", "0x10", "--out", out.to_str().unwrap()]);
    assert!(err.contains("out of range"), "{err}");
    let err = fails(&[
        "render",
        "--dt=-1",
        "--size",
        "8x8",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert!(err.contains("--dt") && err.contains("allowed"), "{err}");
    t.assert_only(&[]);
}

#[test]
fn unwritable_output_directory_fails_up_front() {
    let out = Path::new("/nonexistent-dir-sward/out.png");
    let err = fails(&[
        "render",
        "--size",
        "8x8",
        "--frames",
        "1",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert!(err.contains("does not exist"), "{err}");
}

#[test]
fn simulate_writes_the_documented_json() {
    let t = Tmp::new("json");
    let dump = t.path("dump.json");
    let out = sward(&[
        "simulate",
        "--blades",
        "256",
        "--steps",
        "5",
        "--dump",
        dump.to_str().unwrap(),
    ]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let v: serde_json::Value =
        serde_json::from_slice(&std::fs::read(&dump).expect("dump")).expect("json");
    let initial = v["initial"].as_array().expect("initial");
    let last = v["final"].as_array().expect("final");
    assert_eq!(initial.len(), 256);
    assert_eq!(last.len(), 256);
    for key in ["v0", "v1", "v2", "up"] {
        assert_eq!(last[0][key].as_array().expect(key).len(), 3);
    }
    for key in ["height", "width", "stiffness", "eta"] {
        assert!(last[0][key].is_number(), "{key}");
    }
    // The wind and gravity moved the tips.
    assert_ne!(initial[0]["v2"], last[0]["v2"]);
    t.assert_only(&["dump.json"]);
}

#[test]
fn dump_wind_writes_the_documented_grid() {
    let t = Tmp::new("wind");
    let dump = t.path("dump.json");
    let wind = t.path("wind.json");
    let scene = concat!(env!("CARGO_MANIFEST_DIR"), "/assets/scenes/two_winds.ron");
    let out = sward(&[
        "simulate",
        "--scene",
        scene,
        "--steps",
        "5",
        "--wind-resolution",
        "32",
        "--pressure-iterations",
        "10",
        "--dump",
        dump.to_str().unwrap(),
        "--dump-wind",
        wind.to_str().unwrap(),
    ]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let v: serde_json::Value =
        serde_json::from_slice(&std::fs::read(&wind).expect("wind dump")).expect("json");
    assert_eq!(v["width"], 32);
    assert_eq!(v["height"], 32);
    assert!(v["cell_size"].as_f64().expect("cell_size") > 0.0);
    assert_eq!(v["origin"].as_array().expect("origin").len(), 2);
    assert_eq!(v["grid"], "staggered");
    let list = |key: &str| -> Vec<f64> {
        v[key]
            .as_array()
            .unwrap_or_else(|| panic!("{key} is a list"))
            .iter()
            .map(|x| x.as_f64().expect("a number"))
            .collect()
    };
    let (u, w, solid, pressure) = (list("u"), list("v"), list("solid"), list("pressure"));
    assert_eq!(u.len(), 33 * 32);
    assert_eq!(w.len(), 32 * 33);
    assert_eq!(solid.len(), 32 * 32);
    assert_eq!(pressure.len(), 32 * 32);
    assert!(solid.iter().all(|&s| s == 0.0 || s == 1.0));
    // The documented layout gives the divergence: what the projection left of it is small
    // next to the flow's own scale, |u| / h.
    let h = v["cell_size"].as_f64().expect("cell_size");
    let mut sum = 0.0;
    for j in 0..32 {
        for i in 0..32 {
            if solid[j * 32 + i] == 0.0 {
                let d =
                    (u[j * 33 + i + 1] - u[j * 33 + i] + w[(j + 1) * 32 + i] - w[j * 32 + i]) / h;
                sum += d * d;
            }
        }
    }
    let rms = (sum / 1024.0).sqrt();
    let peak = u.iter().chain(&w).fold(0.0f64, |m, x| m.max(x.abs()));
    println!("dumped wind: rms divergence {rms:.2e} 1/s, peak {peak:.2} m/s, h {h} m");
    assert!(
        rms < 1e-2 * peak / h,
        "rms divergence {rms} for a peak of {peak} m/s"
    );
    let moving = u.iter().filter(|x| x.abs() > 1e-3).count();
    assert!(moving > 10, "the guides must move the air ({moving} cells)");
    let err = fails(&[
        "simulate",
        "--steps",
        "1",
        "--dump",
        dump.to_str().unwrap(),
        "--dump-wind",
        wind.to_str().unwrap(),
        "--wind-resolution",
        "4096",
    ]);
    assert!(err.contains("out of range"), "{err}");
}

#[test]
fn dump_wind_of_a_3d_grid_writes_layers_and_w() {
    let t = Tmp::new("wind3d");
    let dump = t.path("dump.json");
    let wind = t.path("wind.json");
    let scene = concat!(env!("CARGO_MANIFEST_DIR"), "/assets/scenes/two_winds.ron");
    let out = sward(&[
        "simulate",
        "--scene",
        scene,
        "--steps",
        "5",
        "--wind-resolution",
        "16",
        "--set",
        "wind.fluid.layers=3",
        "--set",
        "wind.fluid.layer_height=0.5",
        "--set",
        "wind.fluid.pressure_solver=Multigrid",
        "--set",
        "wind.fluid.multigrid_cycles=4",
        "--dump",
        dump.to_str().unwrap(),
        "--dump-wind",
        wind.to_str().unwrap(),
    ]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let v: serde_json::Value =
        serde_json::from_slice(&std::fs::read(&wind).expect("wind dump")).expect("json");
    assert_eq!(v["layers"], 3);
    assert_eq!(v["layer_height"], 0.5);
    let list = |key: &str| -> Vec<f64> {
        v[key]
            .as_array()
            .unwrap_or_else(|| panic!("{key} is a list"))
            .iter()
            .map(|x| x.as_f64().expect("a number"))
            .collect()
    };
    let (u, vv, w, solid) = (list("u"), list("v"), list("w"), list("solid"));
    let (n, layers) = (16usize, 3usize);
    assert_eq!(u.len(), 17 * 16 * layers);
    assert_eq!(vv.len(), 16 * 17 * layers);
    assert_eq!(w.len(), 16 * 16 * (layers + 1));
    assert_eq!(solid.len(), 16 * 16 * layers);
    assert_eq!(list("pressure").len(), 16 * 16 * layers);
    // The ground and the top are closed.
    assert!(w[..n * n]
        .iter()
        .chain(&w[n * n * layers..])
        .all(|&x| x == 0.0));
    // The documented layout gives the 3D divergence.
    let (h, dy) = (v["cell_size"].as_f64().expect("h"), 0.5);
    let (lu, plane) = (n * (n + 1), n * n);
    let mut sum = 0.0;
    for k in 0..layers {
        for j in 0..n {
            for i in 0..n {
                let du = u[k * lu + j * (n + 1) + i + 1] - u[k * lu + j * (n + 1) + i];
                let dv = vv[k * lu + (j + 1) * n + i] - vv[k * lu + j * n + i];
                let dw = w[(k + 1) * plane + j * n + i] - w[k * plane + j * n + i];
                let d = (du + dv) / h + dw / dy;
                sum += d * d;
            }
        }
    }
    let rms = (sum / (plane * layers) as f64).sqrt();
    let peak = u.iter().chain(&vv).fold(0.0f64, |m, x| m.max(x.abs()));
    println!("dumped 3D wind: rms divergence {rms:.2e} 1/s, peak {peak:.2} m/s");
    assert!(peak > 1e-3, "the guides must move the air ({peak})");
    assert!(
        rms < 1e-3 * peak / h,
        "rms divergence {rms} for a peak of {peak} m/s"
    );
}

/// The events of a Chrome trace file that `--trace` wrote: (name, duration in µs) of every
/// complete event, after checking the JSON is a trace.
fn trace_events(path: &Path) -> Vec<(String, f64)> {
    let text = std::fs::read_to_string(path).expect("trace written");
    let json: serde_json::Value = serde_json::from_str(&text).expect("trace is JSON");
    let events = json["traceEvents"].as_array().expect("traceEvents array");
    events
        .iter()
        .filter(|e| e["ph"] == "X")
        .map(|e| {
            assert!(e["ts"].as_f64().is_some(), "{e}");
            (
                e["name"].as_str().expect("name").to_owned(),
                e["dur"].as_f64().expect("dur"),
            )
        })
        .collect()
}

#[test]
fn trace_holds_every_frame_s_passes() {
    let t = Tmp::new("trace");
    let (png, trace) = (t.path("f.png"), t.path("t.json"));
    let out = sward(&[
        "render",
        "--size",
        "64x64",
        "--frames",
        "2",
        "--out",
        png.to_str().unwrap(),
        "--trace",
        trace.to_str().unwrap(),
    ]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let events = trace_events(&trace);
    for pass in ["occluders", "pyramid", "patches", "update", "cull", "draw"] {
        let n = events.iter().filter(|(name, _)| name == pass).count();
        assert_eq!(n, 2, "{pass}: one event per frame: {events:?}");
    }
    assert!(events.iter().all(|(_, d)| *d >= 0.0), "{events:?}");
    assert!(
        events.iter().any(|(name, d)| name == "draw" && *d > 0.0),
        "the draw takes time: {events:?}"
    );

    // The flight writes its measured frames (the warm-up left out).
    let flight = t.path("flight.json");
    let out = sward(&[
        "bench",
        "--flight",
        "--scene",
        Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("tests/scenes/bench_small.ron")
            .to_str()
            .unwrap(),
        "--frames",
        "2",
        "--warmup",
        "1",
        "--size",
        "32x32",
        "--trace",
        flight.to_str().unwrap(),
    ]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let events = trace_events(&flight);
    assert_eq!(
        events.iter().filter(|(n, _)| n == "cull").count(),
        2,
        "{events:?}"
    );
}

/// `sward figure` writes the walking figure that `assets/models/walker.gltf` is, loadable as
/// a skinned mesh; a target that is not a regular file is refused and left alone.
#[test]
fn figure_writes_the_walker() {
    let dir = std::env::temp_dir().join(format!("sward-cli-figure-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let out = dir.join("walker.gltf");
    let o = sward(&["figure", "--out", out.to_str().unwrap()]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let m = sward::mesh::skin::SkinnedMesh::load(&out).expect("the walker loads");
    assert_eq!(m.joints.len(), 9);
    assert_eq!(m.animations[0].name, "walk");
    // The shipped asset is this command's output.
    let shipped = std::fs::read_to_string(
        std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("assets/models/walker.gltf"),
    )
    .unwrap();
    assert_eq!(std::fs::read_to_string(&out).unwrap(), shipped);
    let e = fails(&["figure", "--out", dir.to_str().unwrap()]);
    assert!(
        e.contains("not a regular file") || e.contains("directory"),
        "{e}"
    );
}

/// A scene whose animated object's skin is bad fails with the mesh file and what is wrong:
/// the walker with its skin cut to eight joints while its right arm still names joint 8.
#[test]
fn a_bad_skin_is_named_from_the_command_line() {
    let tmp = Tmp::new("bad-skin");
    let walker = std::fs::read_to_string(
        Path::new(env!("CARGO_MANIFEST_DIR")).join("assets/models/walker.gltf"),
    )
    .unwrap();
    let mut doc: serde_json::Value = serde_json::from_str(&walker).unwrap();
    doc["skins"][0]["joints"].as_array_mut().unwrap().pop();
    tmp.file("cut.gltf", &doc.to_string());
    let scene = tmp.file(
        "scene.ron",
        "(terrain: (size: 8.0, height: Flat), field: (density: 10.0), \
         objects: [(mesh: \"cut.gltf\", animation: Some(\"walk\"))])",
    );
    let out = tmp.path("out.png");
    let e = fails(&render_args(scene.to_str().unwrap(), out.to_str().unwrap()));
    assert!(e.contains("cut.gltf"), "{e}");
    assert!(
        e.contains("names joint 8, but the skin has 8 joints"),
        "{e}"
    );
    tmp.assert_only(&["cut.gltf", "scene.ron"]);
}
