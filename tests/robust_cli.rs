//! The robustness issue's command-line cases, one group per numbered point: outputs that
//! are not regular files, several outputs as one, bounded counts, clear messages. Every
//! special file is made in a temporary directory (never the real /dev).

use std::os::unix::fs::FileTypeExt;
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
        .env_remove("DISPLAY")
        .env_remove("WAYLAND_DISPLAY")
        .env_remove("WAYLAND_SOCKET")
        .output()
        .expect("run sward")
}

/// Runs a command that must fail cleanly; returns its stderr.
fn fails(args: &[&str]) -> String {
    let out = sward(args);
    let stderr = String::from_utf8_lossy(&out.stderr).into_owned();
    assert!(!out.status.success(), "expected failure for {args:?}");
    assert!(!stderr.contains("panicked"), "panic for {args:?}: {stderr}");
    assert!(stderr.contains("error"), "no error for {args:?}: {stderr}");
    stderr
}

struct Tmp(PathBuf);

impl Tmp {
    fn new(name: &str) -> Self {
        let dir = std::env::temp_dir().join(format!("sward-robust-{}-{name}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(&dir).expect("temp dir");
        Tmp(dir)
    }
    fn path(&self, name: &str) -> PathBuf {
        self.0.join(name)
    }
    fn s(&self, name: &str) -> String {
        self.path(name).to_str().expect("utf-8").to_string()
    }
    fn file(&self, name: &str, text: &str) -> String {
        std::fs::write(self.path(name), text).expect("write");
        self.s(name)
    }
    fn fifo(&self, name: &str) -> String {
        let ok = Command::new("mkfifo")
            .arg(self.path(name))
            .status()
            .expect("mkfifo");
        assert!(ok.success());
        self.s(name)
    }
    fn socket(&self, name: &str) -> (String, std::os::unix::net::UnixListener) {
        let l = std::os::unix::net::UnixListener::bind(self.path(name)).expect("socket");
        (self.s(name), l)
    }
    fn link(&self, name: &str, to: &str) -> String {
        std::os::unix::fs::symlink(to, self.path(name)).expect("symlink");
        self.s(name)
    }
    /// The directory's entries, sorted: nothing else (no temporary file) may be left.
    fn entries(&self) -> Vec<String> {
        let mut v: Vec<String> = std::fs::read_dir(&self.0)
            .expect("read dir")
            .map(|e| e.expect("entry").file_name().to_string_lossy().into_owned())
            .collect();
        v.sort();
        v
    }
}

impl Drop for Tmp {
    fn drop(&mut self) {
        let _ = std::fs::remove_dir_all(&self.0);
    }
}

fn is_fifo(p: &Path) -> bool {
    std::fs::symlink_metadata(p)
        .map(|m| m.file_type().is_fifo())
        .unwrap_or(false)
}

/// Point 1: every writer refuses a FIFO, a socket, a directory and a link to a FIFO, says
/// what is there, and leaves it as it was.
#[test]
fn no_writer_replaces_what_is_not_a_regular_file() {
    let t = Tmp::new("special");
    let fifo = t.fifo("fifo");
    let (socket, _listener) = t.socket("socket");
    std::fs::create_dir(t.path("dir")).unwrap();
    let dir = t.s("dir");
    let link = t.link("link", "fifo");
    let good = t.s("good.json");
    let good_png = t.s("good.png");
    let cases: Vec<(&str, String)> = vec![
        ("FIFO", fifo.clone()),
        ("socket", socket.clone()),
        ("directory", dir.clone()),
        ("FIFO", link.clone()),
    ];
    for (kind, target) in &cases {
        let t = target.as_str();
        let runs: Vec<Vec<&str>> = vec![
            vec!["render", "--size", "16x16", "--frames", "1", "--out", t],
            vec!["simulate", "--blades", "64", "--steps", "1", "--dump", t],
            vec![
                "simulate",
                "--blades",
                "64",
                "--steps",
                "1",
                "--dump",
                &good,
                "--dump-wind",
                t,
            ],
            vec!["--exit-after-frames", "1", "--screenshot", t],
            vec!["--exit-after-frames", "1", "--record", t],
            vec!["--exit-after-frames", "1", "--trace", t],
            vec![
                "render", "--size", "16x16", "--frames", "1", "--out", &good_png, "--trace", t,
            ],
            vec!["bench", "--frames", "1", "--size", "16x16", "--trace", t],
            vec![
                "bench", "--flight", "--frames", "2", "--size", "16x16", "--trace", t,
            ],
        ];
        for args in runs {
            let stderr = fails(&args);
            assert!(
                stderr.contains(kind) && stderr.contains("not a regular file"),
                "{args:?}: {stderr}"
            );
        }
    }
    assert!(is_fifo(&t.path("fifo")));
    assert!(t.path("link").is_symlink());
    assert!(std::fs::metadata(t.path("link"))
        .unwrap()
        .file_type()
        .is_fifo());
    assert!(t.path("dir").is_dir());
    assert!(std::fs::metadata(t.path("socket"))
        .unwrap()
        .file_type()
        .is_socket());
    assert_eq!(t.entries(), ["dir", "fifo", "link", "socket"]);
}

/// Point 1: bench --images refuses a FIFO among its three files before measuring, and the
/// panel's Save (the library call behind it) refuses a FIFO too.
#[test]
fn bench_images_and_save_refuse_a_fifo() {
    let t = Tmp::new("bench");
    t.fifo("unculled.png");
    let stderr = fails(&[
        "bench",
        "--frames",
        "1",
        "--warmup",
        "0",
        "--size",
        "16x16",
        "--images",
        &t.s(""),
    ]);
    assert!(
        stderr.contains("unculled.png") && stderr.contains("FIFO"),
        "{stderr}"
    );
    assert!(!stderr.contains("bench: "), "the bench ran: {stderr}");
    let fifo = t.fifo("scene.ron");
    let scene = sward::scene::Scene::default();
    let e = sward::scene::save::save_scene(&scene, Path::new(&fifo))
        .unwrap_err()
        .to_string();
    assert!(e.contains("FIFO"), "{e}");
    assert!(is_fifo(&t.path("scene.ron")));
    assert_eq!(t.entries(), ["scene.ron", "unculled.png"]);
}

/// Point 1: a symbolic link to a regular file is followed; the file is replaced and the
/// link stays a link.
#[test]
fn a_link_to_a_file_keeps_the_link() {
    let t = Tmp::new("link");
    t.file("real.json", "old");
    let link = t.link("dump.json", "real.json");
    let out = sward(&[
        "simulate", "--blades", "64", "--steps", "1", "--dump", &link,
    ]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert!(t.path("dump.json").is_symlink());
    let text = std::fs::read_to_string(t.path("real.json")).unwrap();
    assert!(text.starts_with("{\"initial\""), "{text}");
    // Point 5: simulate always says how many blades it had to reset (none here).
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(
        stderr.contains("blades reset from a non-finite state: 0"),
        "{stderr}"
    );
    assert_eq!(t.entries(), ["dump.json", "real.json"]);
}

/// Point 2: one run, several outputs: a bad second output is found before the run, and the
/// existing first one is untouched; two outputs on one file, or an output over an input,
/// are refused.
#[test]
fn several_outputs_are_all_or_nothing() {
    let t = Tmp::new("all");
    let a = t.file("a.json", "good");
    let bad = t.s("missing/b.json");
    let stderr = fails(&[
        "simulate",
        "--blades",
        "64",
        "--steps",
        "1",
        "--dump",
        &a,
        "--dump-wind",
        &bad,
    ]);
    assert!(
        stderr.contains("--dump-wind") && stderr.contains("does not exist"),
        "{stderr}"
    );
    assert_eq!(std::fs::read_to_string(t.path("a.json")).unwrap(), "good");
    // The second output is fine but the scene has no fluid: still nothing is written.
    let b = t.s("b.json");
    fails(&[
        "simulate",
        "--blades",
        "64",
        "--steps",
        "1",
        "--dump",
        &a,
        "--dump-wind",
        &b,
    ]);
    assert_eq!(std::fs::read_to_string(t.path("a.json")).unwrap(), "good");
    let stderr = fails(&[
        "simulate",
        "--blades",
        "64",
        "--steps",
        "1",
        "--dump",
        &a,
        "--dump-wind",
        &a,
    ]);
    assert!(stderr.contains("name the same file"), "{stderr}");
    let scene = t.file("scene.ron", "()");
    let stderr = fails(&[
        "render", "--scene", &scene, "--size", "16x16", "--frames", "1", "--out", &scene,
    ]);
    assert!(
        stderr.contains("--out names the file that --scene reads"),
        "{stderr}"
    );
    let script = t.file("s.ron", "[(frame: 1, event: Scroll(1.0))]");
    let stderr = fails(&[
        "--replay",
        &script,
        "--record",
        &script,
        "--exit-after-frames",
        "2",
    ]);
    assert!(
        stderr.contains("--record names the file that --replay reads"),
        "{stderr}"
    );
    assert_eq!(
        std::fs::read_to_string(t.path("s.ron")).unwrap(),
        "[(frame: 1, event: Scroll(1.0))]"
    );
    assert_eq!(t.entries(), ["a.json", "s.ron", "scene.ron"]);
}

/// Point 4: counts have a documented range, in --help and in the error.
#[test]
fn counts_are_bounded_and_documented() {
    for (cmd, flag) in [("render", "--frames"), ("simulate", "--steps")] {
        for bad in ["0", "4294967295", "100001", "-1", "1e3"] {
            let arg = format!("{flag}={bad}");
            let mut args = vec![cmd, arg.as_str()];
            if cmd == "simulate" {
                args.extend(["--dump", "/tmp/sward-never-written.json"]);
            }
            let stderr = fails(&args);
            assert!(stderr.contains("allowed 1..=100000"), "{args:?}: {stderr}");
        }
        let help = sward(&[cmd, "--help"]);
        let help = String::from_utf8_lossy(&help.stdout);
        assert!(help.contains("(1..=100000)"), "{help}");
    }
    assert!(!Path::new("/tmp/sward-never-written.json").exists());
    let help = sward(&["--help"]);
    let help = String::from_utf8_lossy(&help.stdout);
    assert!(help.contains("(1..=10000000)"), "{help}");
}

/// Point 6: the window without a display says so, how to get one, that `render` works
/// headless, and names no source file of the build.
#[test]
fn no_display_is_explained() {
    let stderr = fails(&["--exit-after-frames", "1"]);
    assert!(stderr.contains("no display"), "{stderr}");
    assert!(stderr.contains("xvfb-run"), "{stderr}");
    assert!(stderr.contains("sward render"), "{stderr}");
    assert!(!stderr.contains("GPU error"), "{stderr}");
    assert!(!stderr.contains(".rs:"), "{stderr}");
    assert!(!stderr.contains("registry"), "{stderr}");
    // A display that is named but not there.
    let run = Command::new(env!("CARGO_BIN_EXE_sward"))
        .args(["--exit-after-frames", "1"])
        .env("DISPLAY", ":4321")
        .env_remove("WAYLAND_DISPLAY")
        .output()
        .expect("run sward");
    let stderr = String::from_utf8_lossy(&run.stderr);
    assert_eq!(run.status.code(), Some(1), "{stderr}");
    assert!(stderr.contains("cannot connect to the display"), "{stderr}");
    assert!(
        stderr.contains("DISPLAY=:4321") && stderr.contains("xvfb-run"),
        "{stderr}"
    );
    assert!(
        !stderr.contains(".rs:") && !stderr.contains("GPU error"),
        "{stderr}"
    );
}

/// Point 6: replay script errors name the step and the field (found before a window is
/// needed).
#[test]
fn replay_errors_name_the_step_and_field() {
    let t = Tmp::new("replay");
    let cases = [
        (
            "[(frame: 1, event: Scroll(1.0)),\n (frame: -1, event: Scroll(1.0))]",
            "s.ron:2:",
            "steps[1].frame",
        ),
        (
            "[(frame: 1, event: Scroll(\"x\"))]",
            "s.ron:1:",
            "steps[0].event",
        ),
        (
            "[(frame: 1, event: Button(Left, 3))]",
            "s.ron:1:",
            "steps[0].event",
        ),
        (
            "[(frame: 1, evnt: Scroll(1.0))]",
            "s.ron:1:",
            "steps[0]: Unexpected field named `evnt`",
        ),
        (
            "[(frame: 4, event: Scroll(1.0)), (frame: 2, event: Scroll(1.0))]",
            "s.ron:1:",
            "steps[1].frame = 2",
        ),
        (
            "[(frame: 4, event: Scroll(inf))]",
            "s.ron:1:",
            "steps[0].event",
        ),
    ];
    for (text, place, field) in cases {
        let script = t.file("s.ron", text);
        let stderr = fails(&["--replay", &script, "--exit-after-frames", "1"]);
        assert!(stderr.contains(place), "{text}: {stderr}");
        assert!(stderr.contains(field), "{text}: {stderr}");
        assert!(!stderr.contains("no display"), "{text}: {stderr}");
    }
}

/// Point 8: `--set PATH=VALUE` and `--eye` / `--target` on every command, validated like the
/// file (the same message with the field and its range), and they change the run.
#[test]
fn set_eye_and_target_vary_the_scene_from_the_command_line() {
    let t = Tmp::new("set");
    for cmd in [
        vec!["render", "--size", "16x16", "--frames", "1"],
        vec!["simulate", "--blades", "64", "--steps", "1", "--dump"],
        vec!["bench", "--frames", "1", "--warmup", "0", "--size", "16x16"],
        vec!["--exit-after-frames", "1"],
    ] {
        let out = t.s("out.x");
        let mut args = cmd.clone();
        if cmd[0] == "simulate" {
            args.push(&out);
        }
        if cmd[0] == "render" {
            args.extend(["--out", &out]);
        }
        let mut bad = args.clone();
        bad.extend(["--set", "field.density=-3"]);
        let stderr = fails(&bad);
        assert!(
            stderr.contains(
                "--set field.density=-3: field.density = -3 is out of range: allowed 0 < \
                 density <= 10000 blades/m²"
            ),
            "{bad:?}: {stderr}"
        );
        let mut bad = args.clone();
        bad.extend(["--set", "culling.bogus=1"]);
        let stderr = fails(&bad);
        assert!(
            stderr.contains("`bogus`") && stderr.contains("`distance`"),
            "{stderr}"
        );
        let mut bad = args.clone();
        bad.extend(["--eye", "0,1e9,0"]);
        let stderr = fails(&bad);
        assert!(
            stderr.contains("--eye 0,1000000000,0: camera.eye"),
            "{stderr}"
        );
        assert!(stderr.contains("allowed"), "{stderr}");
        let mut bad = args.clone();
        bad.extend(["--target", "1,2"]);
        let stderr = fails(&bad);
        assert!(stderr.contains("X,Y,Z"), "{stderr}");
        assert!(!t.path("out.x").exists());
    }
    // The values reach the run: two renders from two eyes differ, and a --set of the wind
    // changes the simulated blades.
    let render = |eye: &str, name: &str| {
        let path = t.s(name);
        let out = sward(&[
            "render", "--size", "32x32", "--frames", "1", "--out", &path, "--eye", eye, "--target",
            "0,0,0",
        ]);
        assert!(
            out.status.success(),
            "{}",
            String::from_utf8_lossy(&out.stderr)
        );
        std::fs::read(path).unwrap()
    };
    assert_ne!(render("0,3,12", "a.png"), render("9,1.5,2", "b.png"));
    let simulate = |set: &str, name: &str| {
        let path = t.s(name);
        let out = sward(&[
            "simulate",
            "--blades",
            "64",
            "--steps",
            "5",
            "--dump",
            &path,
            "--set",
            set,
            "--set",
            "wind.point=None",
        ]);
        assert!(
            out.status.success(),
            "{}",
            String::from_utf8_lossy(&out.stderr)
        );
        std::fs::read_to_string(path).unwrap()
    };
    assert_ne!(
        simulate("wind.directional.strength=0", "calm.json"),
        simulate("wind.directional.strength=20", "windy.json")
    );
}

/// Point 5: force-like values without a bound used to give NaN blades with exit 0; now each
/// is refused with its field and range, from the file (with its line) and from --set.
#[test]
fn huge_forces_are_refused_with_the_field_and_range() {
    let t = Tmp::new("forces");
    for (field, section, key) in [
        (
            "wind.directional.strength",
            "wind: (directional: (strength: 1e38))",
            "strength",
        ),
        (
            "wind.point.strength",
            "wind: (point: (strength: 1e38))",
            "strength",
        ),
        ("physics.mass", "physics: (mass: 1e38)", "mass"),
        (
            "physics.gravity_acceleration",
            "physics: (gravity_acceleration: 1e38)",
            "gravity_acceleration",
        ),
        (
            "physics.gravity_center_acceleration",
            "physics: (gravity_center_acceleration: 1e38)",
            "gravity_center_acceleration",
        ),
    ] {
        let scene = t.file("s.ron", &format!("(\n  {section},\n)\n"));
        let dump = t.s("d.json");
        let stderr = fails(&[
            "simulate", "--scene", &scene, "--blades", "64", "--dump", &dump,
        ]);
        assert!(stderr.contains("s.ron:2:"), "{field}: {stderr}");
        assert!(stderr.contains(&format!("{field} = ")), "{field}: {stderr}");
        assert!(
            stderr.contains("out of range: allowed"),
            "{field}: {stderr}"
        );
        assert!(stderr.contains(key), "{field}: {stderr}");
        let set = format!("{field}=1e38");
        let stderr = fails(&["simulate", "--blades", "64", "--dump", &dump, "--set", &set]);
        assert!(
            stderr.contains(&format!("--set {set}: {field} = ")),
            "{stderr}"
        );
        assert!(!t.path("d.json").exists());
    }
}

/// Point 6: the parser's own errors name the field and its range; an image's errors name the
/// scene file, the field and the image, and a huge declared size says its size and the limit.
#[test]
fn parser_and_image_errors_name_the_field() {
    let t = Tmp::new("parser");
    let out = t.s("o.png");
    for (text, expect) in [
        ("(\n  terrain: (resolution: 99999999999),\n)", "s.ron:2:"),
        ("(\n  terrain: (resolution: 1e3),\n)", "s.ron:2:"),
        ("(\n  field: (density: \"lots\"),\n)", "s.ron:2:"),
    ] {
        let scene = t.file("s.ron", text);
        let stderr = fails(&["render", "--scene", &scene, "--frames", "1", "--out", &out]);
        assert!(stderr.contains(expect), "{stderr}");
        assert!(stderr.contains("allowed"), "{stderr}");
        assert!(
            stderr.contains("terrain.resolution") || stderr.contains("field.density"),
            "{stderr}"
        );
    }
    // A PNG whose header declares 100000x100000 pixels: a 1x1 image with its IHDR patched.
    let mut png = Vec::new();
    image::GrayImage::new(1, 1)
        .write_to(&mut std::io::Cursor::new(&mut png), image::ImageFormat::Png)
        .unwrap();
    png[16..20].copy_from_slice(&100_000u32.to_be_bytes());
    png[20..24].copy_from_slice(&100_000u32.to_be_bytes());
    let crc = crc32(&png[12..29]);
    png[29..33].copy_from_slice(&crc.to_be_bytes());
    std::fs::write(t.path("huge.png"), &png).unwrap();
    let scene = t.file(
        "s.ron",
        "(\n  terrain: (\n    density_map: \"huge.png\",\n  ),\n)",
    );
    let stderr = fails(&["render", "--scene", &scene, "--frames", "1", "--out", &out]);
    assert!(stderr.contains("s.ron:3:"), "{stderr}");
    assert!(stderr.contains("terrain.density_map"), "{stderr}");
    assert!(stderr.contains("huge.png"), "{stderr}");
    assert!(stderr.contains("100000x100000"), "{stderr}");
    assert!(!stderr.contains("Memory limit exceeded"), "{stderr}");
    assert!(!t.path("o.png").exists());
}

/// CRC-32 (IEEE) as PNG chunks use it.
fn crc32(bytes: &[u8]) -> u32 {
    let mut crc = 0xffff_ffffu32;
    for &b in bytes {
        crc ^= u32::from(b);
        for _ in 0..8 {
            crc = if crc & 1 != 0 {
                (crc >> 1) ^ 0xedb8_8320
            } else {
                crc >> 1
            };
        }
    }
    !crc
}

/// Point 9: an adapter that cannot run sward (OpenGL here, where Mesa's GL driver exists) is
/// refused before anything is built, with what it lacks and what to install; never a panic.
#[test]
fn an_adapter_that_cannot_run_sward_is_refused_clearly() {
    let t = Tmp::new("adapter");
    let out = t.s("o.png");
    for adapter in ["auto", "software", "llvmpipe"] {
        let run = Command::new(env!("CARGO_BIN_EXE_sward"))
            .args(["render", "--size", "16x16", "--frames", "1", "--out", &out])
            .args(["--adapter", adapter])
            .env("WGPU_BACKEND", "gl")
            .env("RUST_BACKTRACE", "0")
            .output()
            .expect("run sward");
        let stderr = String::from_utf8_lossy(&run.stderr);
        assert_eq!(run.status.code(), Some(1), "{adapter}: {stderr}");
        assert!(!stderr.contains("panicked"), "{stderr}");
        assert!(stderr.contains("mesa-vulkan-drivers"), "{stderr}");
        // Where Mesa's OpenGL driver is installed the adapter is listed with its reason.
        if stderr.contains(", Gl,") {
            assert!(
                stderr.contains("OpenGL backend is not supported"),
                "{stderr}"
            );
        }
    }
    let stderr = fails(&[
        "render",
        "--size",
        "16x16",
        "--frames",
        "1",
        "--out",
        &out,
        "--adapter",
        "no-such-gpu",
    ]);
    assert!(
        stderr.contains("\"no-such-gpu\"") && stderr.contains("among:"),
        "{stderr}"
    );
    assert!(!t.path("o.png").exists());
}

/// Runs sward and kills it after `seconds`: a hang fails the test instead of stalling it.
fn sward_within(args: &[&str], seconds: u64) -> Output {
    let mut child = Command::new(env!("CARGO_BIN_EXE_sward"))
        .args(args)
        .env("RUST_BACKTRACE", "0")
        .env_remove("DISPLAY")
        .env_remove("WAYLAND_DISPLAY")
        .stdout(std::process::Stdio::piped())
        .stderr(std::process::Stdio::piped())
        .spawn()
        .expect("run sward");
    let start = std::time::Instant::now();
    while child.try_wait().expect("wait").is_none() {
        if start.elapsed().as_secs() >= seconds {
            let _ = child.kill();
            panic!("sward {args:?} still ran after {seconds} s");
        }
        std::thread::sleep(std::time::Duration::from_millis(50));
    }
    child.wait_with_output().expect("output")
}

/// Point 4's class: no input hangs a run. A FIFO or a directory given as the scene, the
/// replay script or an image is refused at once with what it is.
#[test]
fn inputs_that_are_not_regular_files_are_refused_without_hanging() {
    let t = Tmp::new("inputs");
    let fifo = t.fifo("fifo");
    let out = t.s("o.png");
    let scene = t.file("s.ron", "(terrain: (density_map: \"fifo\"))");
    let dir = t.s("");
    for args in [
        vec!["render", "--scene", &fifo, "--out", &out],
        vec!["render", "--scene", &dir, "--out", &out],
        vec!["simulate", "--scene", &fifo, "--dump", &out],
        vec!["render", "--scene", &scene, "--frames", "1", "--out", &out],
        vec!["--replay", &fifo, "--exit-after-frames", "1"],
    ] {
        let run = sward_within(&args, 30);
        let stderr = String::from_utf8_lossy(&run.stderr);
        assert!(!run.status.success(), "{args:?}: {stderr}");
        assert!(!stderr.contains("panicked"), "{args:?}: {stderr}");
        assert!(stderr.contains("not a regular file"), "{args:?}: {stderr}");
    }
    assert!(!t.path("o.png").exists());
}

/// The CPU twin has no adapter to vet a field against: a scene that asks for more blades
/// than sward generates is refused at once instead of running out of memory.
#[test]
fn a_huge_field_is_refused_on_the_cpu_path_too() {
    let t = Tmp::new("cpu_huge");
    let dump = t.s("d.json");
    let run = sward_within(
        &[
            "simulate",
            "--cpu",
            "--set",
            "terrain.size=10000",
            "--set",
            "field.density=10000",
            "--dump",
            &dump,
        ],
        30,
    );
    let stderr = String::from_utf8_lossy(&run.stderr);
    assert!(!run.status.success(), "{stderr}");
    // The default meadow streams its blades: its pool is what is too large.
    assert!(
        stderr.contains("pool of") && stderr.contains("allowed at most 20000000"),
        "{stderr}"
    );
    assert!(!t.path("d.json").exists());
    // The same request as a whole field.
    let run = sward_within(
        &[
            "simulate",
            "--cpu",
            "--set",
            "terrain.size=10000",
            "--set",
            "field.density=10000",
            "--set",
            "field.tile_size=0",
            "--dump",
            &dump,
        ],
        30,
    );
    let stderr = String::from_utf8_lossy(&run.stderr);
    assert!(!run.status.success(), "{stderr}");
    assert!(
        stderr.contains("1000000000000 blades") && stderr.contains("allowed at most 50000000"),
        "{stderr}"
    );
    assert!(!t.path("d.json").exists());
}
