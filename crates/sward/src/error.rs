//! The library's error type: every failure a user can cause ends here, with a message that
//! names what to fix (the file, line and field; the allowed range; what to install).

use std::path::PathBuf;

/// Errors at the library boundary.
#[derive(Debug, thiserror::Error)]
pub enum Error {
    /// A file could not be read.
    #[error("cannot read {path}: {source}")]
    Read {
        /// The file that could not be read.
        path: PathBuf,
        /// The operating system's error.
        #[source]
        source: std::io::Error,
    },
    /// A scene file is malformed or holds a value out of range.
    #[error("{path}:{line}:{column}: {message}")]
    Scene {
        /// The scene file (or a stand-in name such as `<inline>` for scene text).
        path: PathBuf,
        /// Line of the offending value, counted from 1.
        line: usize,
        /// Column of the offending value, counted from 1.
        column: usize,
        /// What is wrong and, for a value out of range, what is allowed.
        message: String,
    },
    /// A `--set PATH=VALUE` argument is malformed, names no field of the scene, or sets a
    /// value the scene file could not hold (`arg` is `PATH=VALUE` as given).
    #[error("--set {arg}: {message}")]
    Set {
        /// The argument as given, `PATH=VALUE`.
        arg: String,
        /// What is wrong and, for a value out of range, what is allowed.
        message: String,
    },
    /// An image named by a scene could not be decoded.
    #[error("{path}: cannot decode image: {message}")]
    Image {
        /// The image file.
        path: PathBuf,
        /// Why it was refused: the decoder's error, or a declared size over the limit.
        message: String,
    },
    /// A mesh named by a scene could not be loaded (unreadable, malformed, no triangles,
    /// non-finite vertices, too large).
    #[error("{path}: cannot load mesh: {message}")]
    Mesh {
        /// The mesh file.
        path: PathBuf,
        /// Why the mesh was refused.
        message: String,
    },
    /// No adapter matched the request.
    #[error("{0}")]
    NoAdapter(String),
    /// The request does not fit the adapter's limits; nothing was allocated.
    #[error("{0}")]
    Limits(String),
    /// The device refused a request (out of memory, validation).
    #[error("GPU error: {0}")]
    Gpu(String),
    /// Writing an output file failed; no partial file was left behind.
    #[error("cannot write {path}: {message}")]
    Write {
        /// The file that was being written.
        path: PathBuf,
        /// Why the write failed.
        message: String,
    },
    /// The window cannot open (no display, the display refused it).
    #[error("{0}")]
    Window(String),
    /// A command-line value is out of range.
    #[error("{0}")]
    Invalid(String),
}

/// Shorthand for results of this crate.
pub type Result<T, E = Error> = std::result::Result<T, E>;
