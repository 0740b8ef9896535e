//! Output files, written so that a failed run changes nothing.
//!
//! Every writer of sward (`render --out`, `simulate --dump` / `--dump-wind`, the window's
//! `--screenshot` / `--record` and Save, `bench --images`) goes through this module:
//!
//! - **Checked before the run.** [`Outputs::add`] checks each path before any work starts:
//!   its directory exists, it is not a directory, device, FIFO or socket, it is not one of
//!   the run's inputs (the scene, the replay script) and no two outputs name the same file.
//! - **Never over something that is not a regular file.** A device node, FIFO, socket or
//!   directory at an output path is refused with an error that says what is there; it is
//!   never replaced. A symbolic link is followed: the file it points to is replaced (a link
//!   to nothing creates that file) and the link stays a link.
//! - **All or nothing.** Each output is written to a temporary file beside its target
//!   ([`Outputs::write`]); only when every output of the run is written does
//!   [`Outputs::commit`] rename them into place. If a rename fails part-way, the files
//!   already replaced are put back from hard-link backups. A run that stops before
//!   `commit` (an error, a panic) leaves no temporary file and no changed target.

use std::fs::{File, OpenOptions};
use std::io::Write;
use std::path::{Path, PathBuf};

use crate::error::{Error, Result};

/// How many links [`resolve`] follows before it calls the chain a loop.
const MAX_LINKS: usize = 40;

fn write_error(path: &Path, message: impl Into<String>) -> Error {
    Error::Write {
        path: path.to_path_buf(),
        message: message.into(),
    }
}

/// What kind of thing stands at a path, in words (for errors), when it is not a regular file.
pub(crate) fn not_regular(meta: &std::fs::Metadata) -> Option<&'static str> {
    use std::os::unix::fs::FileTypeExt;
    let t = meta.file_type();
    if t.is_file() {
        None
    } else if t.is_dir() {
        Some("a directory")
    } else if t.is_char_device() {
        Some("a character device")
    } else if t.is_block_device() {
        Some("a block device")
    } else if t.is_fifo() {
        Some("a FIFO (named pipe)")
    } else if t.is_socket() {
        Some("a socket")
    } else {
        Some("not a regular file")
    }
}

/// The file an output path really names: symbolic links are followed (relative link
/// targets against the link's directory), so that the rename replaces the file and keeps
/// the link. The result may not exist yet.
pub fn resolve(path: &Path) -> Result<PathBuf> {
    let mut current = path.to_path_buf();
    for _ in 0..MAX_LINKS {
        match std::fs::symlink_metadata(&current) {
            Ok(meta) if meta.file_type().is_symlink() => {
                let target = std::fs::read_link(&current)
                    .map_err(|e| write_error(path, format!("cannot read the link: {e}")))?;
                current = match current.parent() {
                    Some(dir) if target.is_relative() => dir.join(target),
                    _ => target,
                };
            }
            _ => return Ok(current),
        }
    }
    Err(write_error(
        path,
        format!("more than {MAX_LINKS} symbolic links in a row (a loop?)"),
    ))
}

/// Checks that `path` can take an output: its directory exists and what stands there (after
/// following links) is a regular file or nothing. Returns the resolved path.
pub fn check_writable(path: &Path) -> Result<PathBuf> {
    if path.as_os_str().is_empty() {
        return Err(write_error(path, "the path is empty: name a file"));
    }
    let resolved = resolve(path)?;
    match std::fs::metadata(&resolved) {
        Ok(meta) => {
            if let Some(kind) = not_regular(&meta) {
                let shown = if resolved == path {
                    String::new()
                } else {
                    format!(" (the link points to {})", resolved.display())
                };
                return Err(write_error(
                    path,
                    format!(
                        "it is {kind}{shown}, not a regular file; sward only writes regular \
                         files and never replaces anything else: name a file path"
                    ),
                ));
            }
        }
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => {}
        Err(e) => return Err(write_error(path, e.to_string())),
    }
    if resolved.file_name().is_none() {
        return Err(write_error(path, "the path names no file: name a file"));
    }
    let dir = parent_dir(&resolved);
    if !dir.is_dir() {
        return Err(write_error(
            path,
            format!("directory {} does not exist", dir.display()),
        ));
    }
    Ok(resolved)
}

fn parent_dir(path: &Path) -> &Path {
    path.parent()
        .filter(|p| !p.as_os_str().is_empty())
        .unwrap_or(Path::new("."))
}

/// Whether `a` and `b` name the same file: equal once resolved and made absolute, or the
/// same inode where both exist (hard links, `./x` against `x`).
pub fn same_file(a: &Path, b: &Path) -> bool {
    use std::os::unix::fs::MetadataExt;
    if let (Ok(ma), Ok(mb)) = (std::fs::metadata(a), std::fs::metadata(b)) {
        return ma.dev() == mb.dev() && ma.ino() == mb.ino();
    }
    let absolute = |p: &Path| -> Option<PathBuf> {
        let p = resolve(p).ok()?;
        let dir = std::fs::canonicalize(parent_dir(&p)).ok()?;
        Some(dir.join(p.file_name()?))
    };
    match (absolute(a), absolute(b)) {
        (Some(a), Some(b)) => a == b,
        _ => false,
    }
}

/// One output of a run.
#[derive(Debug)]
struct Planned {
    /// The flag or control that named it (`--dump`, `Save`), for errors.
    what: String,
    /// As the user wrote it (messages use it).
    path: PathBuf,
    /// After following links: what the rename replaces.
    resolved: PathBuf,
    /// The written temporary file, once [`Outputs::write`] ran.
    staged: Option<PathBuf>,
}

/// The outputs of one run: checked before it starts, written to temporary files during it,
/// renamed into place together at its end (see the module docs). Dropping it without
/// [`Outputs::commit`] removes the temporary files and changes no target.
#[derive(Debug, Default)]
pub struct Outputs {
    planned: Vec<Planned>,
    /// The run's inputs, which no output may replace: (what, path).
    inputs: Vec<(String, PathBuf)>,
}

impl Outputs {
    /// An empty set of outputs: nothing planned, no inputs declared.
    pub fn new() -> Self {
        Self::default()
    }

    /// Declares an input of the run (`--scene`, `--replay`): no output may name it.
    pub fn input(&mut self, what: &str, path: &Path) -> Result<()> {
        for p in &self.planned {
            check_not_input(p, what, path)?;
        }
        self.inputs.push((what.to_string(), path.to_path_buf()));
        Ok(())
    }

    /// Checks and declares an output (see [`check_writable`]); `what` names the flag in
    /// errors. Refuses a path that another output or an input of the run already names.
    pub fn add(&mut self, what: &str, path: &Path) -> Result<()> {
        let resolved = check_writable(path).map_err(|e| prefix(e, what))?;
        let planned = Planned {
            what: what.to_string(),
            path: path.to_path_buf(),
            resolved,
            staged: None,
        };
        for other in &self.planned {
            if same_file(&other.resolved, &planned.resolved) {
                return Err(write_error(
                    path,
                    format!(
                        "{what} and {} name the same file; give each output its own path",
                        other.what
                    ),
                ));
            }
        }
        for (input, input_path) in &self.inputs {
            check_not_input(&planned, input, input_path)?;
        }
        self.planned.push(planned);
        Ok(())
    }

    /// Whether `path` was declared.
    pub fn contains(&self, path: &Path) -> bool {
        self.planned.iter().any(|p| p.path == path)
    }

    /// Whether the declared output `path` has been written (staged).
    pub fn is_written(&self, path: &Path) -> bool {
        self.planned
            .iter()
            .any(|p| p.path == path && p.staged.is_some())
    }

    /// Drops a declared output that the run will not make (its temporary file, if any).
    pub fn forget(&mut self, path: &Path) {
        self.planned.retain_mut(|p| {
            if p.path != path {
                return true;
            }
            if let Some(staged) = p.staged.take() {
                let _ = std::fs::remove_file(staged);
            }
            false
        });
    }

    /// Writes `bytes` for the declared output `path` to a temporary file beside its target.
    /// Nothing is replaced until [`Outputs::commit`].
    pub fn write(&mut self, path: &Path, bytes: &[u8]) -> Result<()> {
        let Some(planned) = self.planned.iter_mut().find(|p| p.path == path) else {
            return Err(write_error(
                path,
                "internal error: this output was not declared before the run",
            ));
        };
        if let Some(old) = planned.staged.take() {
            let _ = std::fs::remove_file(old);
        }
        // Checked again: the file system may have changed during a long run.
        planned.resolved = check_writable(path).map_err(|e| prefix(e, &planned.what))?;
        let staged = stage(&planned.resolved, bytes).map_err(|e| write_error(path, e))?;
        planned.staged = Some(staged);
        Ok(())
    }

    /// Encodes `image` as PNG and writes it like [`Outputs::write`].
    pub fn write_png(&mut self, path: &Path, image: &image::RgbaImage) -> Result<()> {
        let bytes = encode_png(path, image)?;
        self.write(path, &bytes)
    }

    /// Renames every written output into place. Fails (and changes nothing) if an output
    /// was declared but never written. A rename that fails part-way puts back the files
    /// already replaced.
    pub fn commit(mut self) -> Result<()> {
        if let Some(p) = self.planned.iter().find(|p| p.staged.is_none()) {
            return Err(write_error(
                &p.path,
                format!("{} was not written, so no output of this run was", p.what),
            ));
        }
        // Last look before anything is replaced: a target that became a device or FIFO
        // during the run is still refused.
        for p in &self.planned {
            check_writable(&p.resolved).map_err(|e| prefix(e, &p.what))?;
        }
        let mut done: Vec<(PathBuf, Option<PathBuf>)> = Vec::new();
        let mut failure = None;
        for p in &mut self.planned {
            let staged = p.staged.take().expect("checked above");
            let backup = backup(&p.resolved);
            match std::fs::rename(&staged, &p.resolved) {
                Ok(()) => done.push((p.resolved.clone(), backup)),
                Err(e) => {
                    let _ = std::fs::remove_file(&staged);
                    if let Some(b) = backup {
                        let _ = std::fs::remove_file(b);
                    }
                    failure = Some(write_error(&p.path, e.to_string()));
                    break;
                }
            }
        }
        if let Some(e) = failure {
            // Undo: every replaced target gets its old file back (or goes, if it was new).
            for (target, backup) in done {
                match backup {
                    Some(b) => {
                        let _ = std::fs::rename(b, &target);
                    }
                    None => {
                        let _ = std::fs::remove_file(&target);
                    }
                }
            }
            return Err(e);
        }
        for (_, backup) in done {
            if let Some(b) = backup {
                let _ = std::fs::remove_file(b);
            }
        }
        Ok(())
    }
}

impl Drop for Outputs {
    fn drop(&mut self) {
        for p in &mut self.planned {
            if let Some(staged) = p.staged.take() {
                let _ = std::fs::remove_file(staged);
            }
        }
    }
}

fn check_not_input(output: &Planned, input: &str, input_path: &Path) -> Result<()> {
    if same_file(&output.resolved, input_path) {
        return Err(write_error(
            &output.path,
            format!(
                "{} names the file that {input} reads; writing it would destroy the input: \
                 choose another path",
                output.what
            ),
        ));
    }
    Ok(())
}

/// Puts the flag in front of a write error's message.
fn prefix(e: Error, what: &str) -> Error {
    match e {
        Error::Write { path, message } if !what.is_empty() => Error::Write {
            path,
            message: format!("{what}: {message}"),
        },
        other => other,
    }
}

/// A hard link to the current target, so that a failed commit can put it back. `None`
/// where the target does not exist (or the file system has no hard links).
fn backup(target: &Path) -> Option<PathBuf> {
    if !target.is_file() {
        return None;
    }
    let link = sibling(target, "bak").ok()?;
    let _ = std::fs::remove_file(&link);
    std::fs::hard_link(target, &link).ok().map(|_| link)
}

/// A fresh hidden name beside `target` (`.name.tmp1234-0`), created exclusively so that an
/// existing file or link of that name is never written through.
fn sibling(target: &Path, kind: &str) -> std::io::Result<PathBuf> {
    let name = target
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_else(|| "output".into());
    let dir = parent_dir(target);
    for n in 0..1000u32 {
        let candidate = dir.join(format!(".{name}.{kind}{}-{n}", std::process::id()));
        if std::fs::symlink_metadata(&candidate).is_err() {
            return Ok(candidate);
        }
    }
    Err(std::io::Error::other(
        "no free temporary name beside the file",
    ))
}

/// Writes `bytes` to a new temporary file beside `target` (with the target's permissions
/// when it exists) and returns its path.
fn stage(target: &Path, bytes: &[u8]) -> std::result::Result<PathBuf, String> {
    let tmp = sibling(target, "tmp").map_err(|e| e.to_string())?;
    let result = (|| {
        let mut f: File = OpenOptions::new().write(true).create_new(true).open(&tmp)?;
        f.write_all(bytes)?;
        if let Ok(meta) = std::fs::metadata(target) {
            f.set_permissions(meta.permissions())?;
        }
        f.sync_all()
    })();
    match result {
        Ok(()) => Ok(tmp),
        Err(e) => {
            let _ = std::fs::remove_file(&tmp);
            Err(e.to_string())
        }
    }
}

/// Writes one output atomically: checked, written to a temporary file, renamed into place.
pub fn write_atomic(path: &Path, bytes: &[u8]) -> Result<()> {
    let mut outputs = Outputs::new();
    outputs.add("", path)?;
    outputs.write(path, bytes)?;
    outputs.commit()
}

fn encode_png(path: &Path, image: &image::RgbaImage) -> Result<Vec<u8>> {
    let mut bytes = Vec::new();
    image
        .write_to(
            &mut std::io::Cursor::new(&mut bytes),
            image::ImageFormat::Png,
        )
        .map_err(|e| write_error(path, e.to_string()))?;
    Ok(bytes)
}

/// Encodes an image as PNG and writes it atomically.
pub fn save_png(path: &Path, image: &image::RgbaImage) -> Result<()> {
    write_atomic(path, &encode_png(path, image)?)
}

#[cfg(test)]
mod tests {
    use super::*;

    struct Dir(PathBuf);
    impl Dir {
        fn new(name: &str) -> Self {
            let d = std::env::temp_dir().join(format!("sward-out-{name}-{}", std::process::id()));
            let _ = std::fs::remove_dir_all(&d);
            std::fs::create_dir_all(&d).unwrap();
            Self(d)
        }
        fn entries(&self) -> Vec<String> {
            let mut v: Vec<String> = std::fs::read_dir(&self.0)
                .unwrap()
                .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
                .collect();
            v.sort();
            v
        }
    }
    impl Drop for Dir {
        fn drop(&mut self) {
            let _ = std::fs::remove_dir_all(&self.0);
        }
    }

    fn mkfifo(path: &Path) {
        let status = std::process::Command::new("mkfifo")
            .arg(path)
            .status()
            .unwrap();
        assert!(status.success());
    }

    #[test]
    fn fifo_directory_and_link_to_fifo_are_refused_and_kept() {
        let d = Dir::new("fifo");
        let fifo = d.0.join("pipe");
        mkfifo(&fifo);
        let e = write_atomic(&fifo, b"x").unwrap_err().to_string();
        assert!(
            e.contains("FIFO") && e.contains("not a regular file"),
            "{e}"
        );
        let e = write_atomic(&d.0, b"x").unwrap_err().to_string();
        assert!(e.contains("a directory"), "{e}");
        let link = d.0.join("link");
        std::os::unix::fs::symlink("pipe", &link).unwrap();
        let e = write_atomic(&link, b"x").unwrap_err().to_string();
        assert!(
            e.contains("FIFO") && e.contains("the link points to"),
            "{e}"
        );
        use std::os::unix::fs::FileTypeExt;
        assert!(std::fs::metadata(&fifo).unwrap().file_type().is_fifo());
        assert!(std::fs::symlink_metadata(&link)
            .unwrap()
            .file_type()
            .is_symlink());
        assert_eq!(d.entries(), ["link", "pipe"]);
    }

    #[test]
    fn a_link_to_a_file_stays_a_link_and_its_file_is_replaced() {
        let d = Dir::new("link");
        std::fs::write(d.0.join("real"), b"old").unwrap();
        let link = d.0.join("link");
        std::os::unix::fs::symlink("real", &link).unwrap();
        write_atomic(&link, b"new").unwrap();
        assert!(std::fs::symlink_metadata(&link)
            .unwrap()
            .file_type()
            .is_symlink());
        assert_eq!(std::fs::read(d.0.join("real")).unwrap(), b"new");
        // A dangling link creates the file it points to.
        let dangling = d.0.join("dangling");
        std::os::unix::fs::symlink("made", &dangling).unwrap();
        write_atomic(&dangling, b"made").unwrap();
        assert_eq!(std::fs::read(d.0.join("made")).unwrap(), b"made");
        assert_eq!(d.entries(), ["dangling", "link", "made", "real"]);
    }

    #[test]
    fn outputs_are_all_or_nothing() {
        let d = Dir::new("all");
        let a = d.0.join("a.json");
        let b = d.0.join("b.json");
        std::fs::write(&a, b"good").unwrap();
        let mut outputs = Outputs::new();
        outputs.add("--dump", &a).unwrap();
        outputs.add("--dump-wind", &b).unwrap();
        outputs.write(&a, b"replaced").unwrap();
        // The run fails before the second output: nothing changes.
        drop(outputs);
        assert_eq!(std::fs::read(&a).unwrap(), b"good");
        assert_eq!(d.entries(), ["a.json"]);
        // A declared but unwritten output fails the commit, and nothing changes.
        let mut outputs = Outputs::new();
        outputs.add("--dump", &a).unwrap();
        outputs.add("--dump-wind", &b).unwrap();
        outputs.write(&a, b"replaced").unwrap();
        assert!(outputs.commit().is_err());
        assert_eq!(std::fs::read(&a).unwrap(), b"good");
        assert_eq!(d.entries(), ["a.json"]);
        // Both written: both land.
        let mut outputs = Outputs::new();
        outputs.add("--dump", &a).unwrap();
        outputs.add("--dump-wind", &b).unwrap();
        outputs.write(&a, b"A").unwrap();
        outputs.write(&b, b"B").unwrap();
        outputs.commit().unwrap();
        assert_eq!(std::fs::read(&a).unwrap(), b"A");
        assert_eq!(std::fs::read(&b).unwrap(), b"B");
        assert_eq!(d.entries(), ["a.json", "b.json"]);
    }

    #[test]
    fn a_failed_rename_puts_back_what_was_replaced() {
        let d = Dir::new("undo");
        let a = d.0.join("a");
        let b = d.0.join("b");
        std::fs::write(&a, b"old").unwrap();
        let mut outputs = Outputs::new();
        outputs.add("first", &a).unwrap();
        outputs.add("second", &b).unwrap();
        outputs.write(&a, b"new").unwrap();
        outputs.write(&b, b"new").unwrap();
        // A directory appears at the second target during the run: the commit refuses it
        // before replacing anything.
        std::fs::create_dir(&b).unwrap();
        let e = outputs.commit().unwrap_err().to_string();
        assert!(e.contains("a directory"), "{e}");
        assert_eq!(std::fs::read(&a).unwrap(), b"old");
        assert_eq!(d.entries(), ["a", "b"]);
    }

    #[test]
    fn the_same_file_twice_or_an_input_is_refused() {
        let d = Dir::new("same");
        let a = d.0.join("a");
        std::fs::write(&a, b"scene").unwrap();
        let mut outputs = Outputs::new();
        outputs.add("--dump", &a).unwrap();
        let e = outputs
            .add("--dump-wind", &d.0.join("./a"))
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("--dump-wind and --dump name the same file"),
            "{e}"
        );
        let mut outputs = Outputs::new();
        outputs.input("--replay", &a).unwrap();
        let e = outputs.add("--record", &a).unwrap_err().to_string();
        assert!(
            e.contains("--record names the file that --replay reads"),
            "{e}"
        );
        // Not yet existing paths compare by name.
        assert!(same_file(&d.0.join("new"), &d.0.join("./new")));
        assert!(!same_file(&d.0.join("new"), &d.0.join("other")));
        assert_eq!(std::fs::read(&a).unwrap(), b"scene");
    }

    #[test]
    fn missing_directory_and_empty_path_are_refused() {
        let e = write_atomic(Path::new("/nonexistent-sward/x.png"), b"x")
            .unwrap_err()
            .to_string();
        assert!(e.contains("does not exist"), "{e}");
        let e = write_atomic(Path::new(""), b"x").unwrap_err().to_string();
        assert!(e.contains("empty"), "{e}");
    }
}
