//! Where a loaded scene came from (its file, its text and its `--set` arguments), kept in
//! [`Scene::origin`] so that a problem found after loading — an image named by the scene
//! that is missing or does not decode — is reported like any scene error: at the line that
//! names the image (or the `--set` argument that did), with the field and the image, e.g.
//! `scene.ron:4:9: terrain.density_map = "mask.png": cannot decode /abs/mask.png: ..`.

use std::path::{Path, PathBuf};
use std::sync::Arc;

use super::types::Scene;
use super::validate::locate::{field_value, locate};
use super::validate::SetField;
use crate::error::Error;

/// The source of a loaded scene. Not part of what the scene is: two scenes with the same
/// values are equal wherever they came from, and saving never writes it.
#[derive(Clone, Debug, Default)]
pub struct Origin(Option<Arc<Source>>);

#[derive(Debug)]
struct Source {
    path: PathBuf,
    text: String,
    sets: Vec<SetField>,
}

impl PartialEq for Origin {
    fn eq(&self, _: &Self) -> bool {
        true
    }
}

impl Origin {
    /// The scene came from `text` of the file `path`, with `sets` applied.
    pub(crate) fn new(path: &Path, text: &str, sets: Vec<SetField>) -> Self {
        Self(Some(Arc::new(Source {
            path: path.to_path_buf(),
            text: text.to_owned(),
            sets,
        })))
    }
}

impl Scene {
    /// An error about the value of `field` found after the scene was loaded (a count the
    /// adapter cannot hold, an area that overflows): at the line of the scene file that
    /// writes the field (or the `--set` argument that set it), with `message`. A scene
    /// built in code has no file: the message alone.
    pub fn error_at(&self, field: &str, message: String) -> Error {
        let Some(source) = &self.origin.0 else {
            return Error::Invalid(message);
        };
        let inside = |outer: &str, inner: &str| {
            inner == outer
                || inner
                    .strip_prefix(outer)
                    .is_some_and(|rest| rest.starts_with('.') || rest.starts_with('['))
        };
        let set = source
            .sets
            .iter()
            .rev()
            .find(|s| inside(&s.path, field) || inside(field, &s.path));
        source.located(set, field, message)
    }

    /// `error`, from opening the image that the scene's `field` names (e.g.
    /// `terrain.density_map`), as a scene error that names the scene file's line (or the
    /// `--set` argument), the field, the image as written and the image's absolute path.
    /// Other errors, and any error for a scene built in code, pass through unchanged.
    pub fn image_error(&self, field: &str, error: Error) -> Error {
        let Some(source) = &self.origin.0 else {
            return error;
        };
        let (image, problem) = match &error {
            Error::Image { path, message } => (path, format!("cannot decode {{}}: {message}")),
            Error::Read { path, source } => (path, format!("cannot read {{}}: {source}")),
            Error::Mesh { path, message } => (path, format!("cannot load mesh {{}}: {message}")),
            _ => return error,
        };
        let absolute = std::path::absolute(image).unwrap_or_else(|_| image.clone());
        let problem = problem.replace("{}", &absolute.display().to_string());
        // A --set of the field or of a part around it (`terrain.height=Png(..)`) named it.
        let set = source.sets.iter().rev().find(|s| {
            field == s.path
                || field
                    .strip_prefix(s.path.as_str())
                    .is_some_and(|rest| rest.starts_with('.') || rest.starts_with('['))
        });
        let (named, written) = match set {
            Some(set) => (
                set.path.as_str(),
                set.arg.split_once('=').map(|(_, v)| v.trim().to_owned()),
            ),
            None => (
                field,
                field_value(&source.text, field).map(|span| source.text[span].to_owned()),
            ),
        };
        let message = match written {
            Some(written) => format!("{named} = {written}: {problem}"),
            None => format!("{named}: {problem}"),
        };
        source.located(set, field, message)
    }
}

impl Source {
    /// `message` blamed on the `--set` argument `set`, else on the line of the scene text
    /// that writes `field`.
    fn located(&self, set: Option<&SetField>, field: &str, message: String) -> Error {
        if let Some(set) = set {
            return Error::Set {
                arg: set.arg.clone(),
                message,
            };
        }
        let (line, column) = locate(&self.text, field);
        Error::Scene {
            path: self.path.clone(),
            line,
            column,
            message,
        }
    }
}
