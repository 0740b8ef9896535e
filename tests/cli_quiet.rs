//! A clean run prints nothing on stderr but what sward means to say: no loader or Mesa WSI
//! noise such as `error: XDG_RUNTIME_DIR is invalid or not set in the environment.` on a
//! machine without a desktop session (`runtime_env::ensure_runtime_dir`).

use std::process::Command;

fn sward() -> Command {
    let mut c = Command::new(env!("CARGO_BIN_EXE_sward"));
    c.env_remove("XDG_RUNTIME_DIR")
        .env_remove("WAYLAND_DISPLAY")
        .env_remove("RUST_LOG")
        .env(
            "SWARD_ADAPTER",
            std::env::var("SWARD_ADAPTER").unwrap_or_else(|_| "software".into()),
        );
    c
}

/// Fails on any stderr line that is not one of sward's own messages.
fn assert_quiet(what: &str, stderr: &str) {
    let ours = ["adapter: ", "field: ", "wrote "];
    for line in stderr.lines() {
        assert!(
            !line.trim_start().to_ascii_lowercase().starts_with("error"),
            "{what}: error line on stderr: {line:?}\n{stderr}"
        );
        assert!(!line.contains("XDG_RUNTIME_DIR"), "{what}: {line:?}");
        assert!(
            ours.iter().any(|p| line.starts_with(p)),
            "{what}: unexpected stderr line {line:?}\n{stderr}"
        );
    }
}

#[test]
fn simulate_without_xdg_runtime_dir_is_quiet() {
    let dir = std::env::temp_dir().join(format!("sward-cli-quiet-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("temp dir");
    let dump = dir.join("dump.json");
    let out = sward()
        .args(["simulate", "--steps", "2", "--blades", "256", "--dump"])
        .arg(&dump)
        .output()
        .expect("run sward");
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "{stderr}");
    assert!(dump.exists());
    assert!(stderr.contains("adapter: "), "{stderr}");
    assert_quiet("simulate", &stderr);
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn render_without_xdg_runtime_dir_is_quiet() {
    let dir = std::env::temp_dir().join(format!("sward-cli-quiet-r-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("temp dir");
    let png = dir.join("frame.png");
    let out = sward()
        .args(["render", "--size", "64x36", "--frames", "1", "--out"])
        .arg(&png)
        .output()
        .expect("run sward");
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "{stderr}");
    assert!(png.exists());
    assert_quiet("render", &stderr);
    let _ = std::fs::remove_dir_all(&dir);
}
