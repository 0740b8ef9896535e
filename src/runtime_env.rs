//! The process environment sward needs before any thread or GPU library starts.
//!
//! Without a desktop session `XDG_RUNTIME_DIR` is unset, and Mesa's Vulkan device-select
//! layer (an implicit layer the loader enables) asks libwayland for the compositor's GPU
//! whenever the instance enables `VK_KHR_wayland_surface`, which wgpu always does.
//! libwayland then prints `error: XDG_RUNTIME_DIR is invalid or not set in the environment.`
//! on stderr, once per device enumeration. With a valid (empty) runtime directory the
//! connection attempt fails silently, so a clean run prints only what sward says.

/// Points `XDG_RUNTIME_DIR` at a private directory (`<temp>/sward-runtime-<uid>`, mode 0700,
/// created once and reused) when it is unset or invalid (not an absolute path to a
/// directory). Call it first thing in `main`, before any thread exists: it changes the
/// process environment. A no-op elsewhere than on Unix, and when the directory cannot be
/// made safely.
pub fn ensure_runtime_dir() {
    #[cfg(unix)]
    {
        let valid = std::env::var_os("XDG_RUNTIME_DIR").is_some_and(|v| {
            let p = std::path::Path::new(&v);
            p.is_absolute() && p.is_dir()
        });
        if !valid {
            if let Some(dir) = private_dir() {
                std::env::set_var("XDG_RUNTIME_DIR", dir);
            }
        }
    }
}

/// `<temp>/sward-runtime-<uid>`, created with mode 0700, or the existing one if it is a real
/// directory (not a link) owned by this user and closed to others.
#[cfg(unix)]
fn private_dir() -> Option<std::path::PathBuf> {
    use std::os::unix::fs::{DirBuilderExt, MetadataExt, PermissionsExt};
    // The owner of /proc/self is this process's user (no libc call needed).
    let uid = std::fs::metadata("/proc/self").ok()?.uid();
    let dir = std::env::temp_dir().join(format!("sward-runtime-{uid}"));
    match std::fs::DirBuilder::new().mode(0o700).create(&dir) {
        Ok(()) => {}
        Err(e) if e.kind() == std::io::ErrorKind::AlreadyExists => {}
        Err(_) => return None,
    }
    let meta = std::fs::symlink_metadata(&dir).ok()?;
    let private = meta.is_dir() && meta.uid() == uid && meta.permissions().mode() & 0o077 == 0;
    private.then_some(dir)
}

#[cfg(all(test, unix))]
mod tests {
    #[test]
    fn the_private_dir_is_a_0700_directory_of_this_user() {
        use std::os::unix::fs::{MetadataExt, PermissionsExt};
        let dir = super::private_dir().expect("a private runtime dir");
        let meta = std::fs::symlink_metadata(&dir).expect("exists");
        assert!(meta.is_dir());
        assert_eq!(meta.permissions().mode() & 0o777, 0o700);
        assert_eq!(
            meta.uid(),
            std::fs::metadata("/proc/self").expect("proc").uid()
        );
        // Twice gives the same directory.
        assert_eq!(super::private_dir(), Some(dir));
    }
}
