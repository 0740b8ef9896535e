//! Writing a scene back to a RON file (the window's Save button, after editing AGC guides).
//!
//! Only what differs from the defaults is written (the defaults are `Scene::default()`
//! after validation), so the file shows what the user set instead of burying it among
//! eighty default values: a section with one changed field writes just that field, an
//! optional part that is `None` where the default has one is written as `None`, and lists,
//! enum values (`Noise(..)`, `Path(..)`) and structs whose fields have no defaults are
//! written whole when they differ. Everything left out loads back as the same default.
//!
//! The text is `ron`'s pretty form with the crate's default options: structs as `( .. )`
//! without their type names and optional values written as `Some( .. )`. Both are what the
//! loader reads (it accepts `Some( .. )` although its `implicit_some` extension lets users
//! leave it out), so nothing needs a `#![enable(..)]` header. Before anything is written the
//! text is parsed back with the loader's own [`parse_scene`], so a scene that would not load
//! (a NaN, a value out of range) is refused instead of written.
//!
//! The file is written with `output::write_atomic` (a temporary file beside the target, then a
//! rename): a failed save leaves an existing file as it was and no partial file behind.
//!
//! # Image paths
//!
//! The loader rewrites relative image paths (`terrain.height: Png(path: ..)`,
//! `terrain.density_map`) as the scene file's directory joined with the path. Saving writes
//! a path relative to the saved file's directory when that directory is a leading part of
//! the image path, compared component by component after making both absolute against the
//! working directory (without resolving symlinks). That is exact: the loader joins the
//! directory with the remainder and gets the very same path back, so a scene saved where it
//! was loaded from keeps the relative paths its author wrote (`../maps/h.png` included),
//! and a scene folder stays movable. Any other image path is written absolute. We do not
//! invent `..` steps to reach a sibling directory: `a/link/..` is not always `a` when `link`
//! is a symlink, so such a path could name a different file; an absolute path always names
//! the file the scene was using.

use std::ops::Range as Span;
use std::path::{Component, Path, PathBuf};

use ron::ser::PrettyConfig;

use super::load::{options, parse_scene};
use super::types::{HeightSource, Scene};
use super::validate::locate::{inside_some, mask, struct_fields};
use super::validate::validate;
use crate::error::{Error, Result};
use crate::output::write_atomic;

/// The scene as pretty RON text that [`crate::scene::parse_scene`] reads back into an equal
/// scene, holding only the values that differ from the defaults (see the module docs).
/// Image paths are written as they are (see [`save_scene`] for making them relative).
///
/// # Errors
///
/// [`Error::Invalid`] if `ron` cannot serialise the scene (no scene built from the scene
/// types triggers this; the error exists because the serialiser is fallible).
pub fn scene_to_string(scene: &Scene) -> Result<String> {
    let full = full_text(scene)?;
    let mut default = Scene::default();
    // The default scene is valid; validation only normalises its directions, which is what
    // a loaded scene holds, so that unchanged directions compare equal.
    validate(&mut default, "()", Path::new("defaults.ron"))?;
    let defaults = full_text(&default)?;
    let whole = Part {
        text: &full,
        code: mask(&full),
    };
    let base = Part {
        text: &defaults,
        code: mask(&defaults),
    };
    let all = 0..full.len();
    let mut text =
        diff(&whole, all, &base, 0..defaults.len(), 0, true).unwrap_or_else(|| "()".to_owned());
    text.push('\n');
    Ok(text)
}

/// The scene written with every field, in the form that [`diff`] compares.
fn full_text(scene: &Scene) -> Result<String> {
    let config = PrettyConfig::new()
        .struct_names(false)
        .separate_tuple_members(false);
    ron::ser::to_string_pretty(scene, config)
        .map_err(|e| Error::Invalid(format!("cannot write the scene as RON: {e}")))
}

/// Scene text with every field written, and its mask (see `validate::locate::mask`).
struct Part<'a> {
    text: &'a str,
    code: Vec<u8>,
}

/// The value at `span` of `scene` written as it differs from the one at `base_span` of
/// `base`, or `None` if they are the same. Anonymous structs (also inside `Some(..)`) whose
/// type fills in missing fields recurse, so only their changed fields are written;
/// anything else is written whole. `root` is the scene itself.
fn diff(
    scene: &Part,
    span: Span<usize>,
    base: &Part,
    base_span: Span<usize>,
    depth: usize,
    root: bool,
) -> Option<String> {
    let value = scene.text[span.clone()].trim();
    if value == base.text[base_span.clone()].trim() {
        return None;
    }
    let whole = || Some(value.to_owned());
    if let (Some(inner), Some(base_inner)) = (
        inside_some(&scene.code, trimmed(&scene.code, span.clone())),
        inside_some(&base.code, trimmed(&base.code, base_span.clone())),
    ) {
        return diff(scene, inner, base, base_inner, depth, false).map(|d| format!("Some({d})"));
    }
    let span = trimmed(&scene.code, span);
    let base_span = trimmed(&base.code, base_span);
    if scene.code.get(span.start) != Some(&b'(') || !(root || fills_defaults(base, &base_span)) {
        return whole();
    }
    let (Some(fields), Some(base_fields)) = (
        struct_fields(&scene.code, span.clone()),
        struct_fields(&base.code, base_span),
    ) else {
        return whole();
    };
    let indent = "    ".repeat(depth + 1);
    let mut out = String::from("(\n");
    for (key, value) in fields {
        let Some((_, base_value)) = base_fields.iter().find(|(k, _)| *k == key) else {
            return whole();
        };
        if let Some(d) = diff(scene, value, base, base_value.clone(), depth + 1, false) {
            out.push_str(&format!("{indent}{key}: {d},\n"));
        }
    }
    out.push_str(&"    ".repeat(depth));
    out.push(')');
    Some(out)
}

/// Whether the struct at `span` of the full default text may leave fields out, i.e. its
/// type has `#[serde(default)]`: the defaults with `()` in its place still load.
fn fills_defaults(base: &Part, span: &Span<usize>) -> bool {
    let mut text = base.text.to_owned();
    text.replace_range(span.clone(), "()");
    options().from_str::<Scene>(&text).is_ok()
}

fn trimmed(code: &[u8], span: Span<usize>) -> Span<usize> {
    let (mut start, mut end) = (span.start, span.end);
    while start < end && code[start].is_ascii_whitespace() {
        start += 1;
    }
    while end > start && code[end - 1].is_ascii_whitespace() {
        end -= 1;
    }
    start..end
}

/// Saves `scene` to `path` as pretty RON that [`crate::scene::load_scene`] reads back into an
/// equal scene (image paths become relative to `path`'s directory where that is exact; see
/// the module docs).
///
/// # Errors
///
/// [`Error::Write`] naming `path` if the scene would not load back (its message gives the
/// offending field) or if the file cannot be written (missing directory, a parent that is a
/// file, no permission, disk full). An existing file at `path` is unchanged then.
pub fn save_scene(scene: &Scene, path: &Path) -> Result<()> {
    let write_error = |message: String| Error::Write {
        path: path.to_path_buf(),
        message,
    };
    let dir = match path.parent() {
        Some(d) if !d.as_os_str().is_empty() => d,
        _ => Path::new("."),
    };
    let mut scene = scene.clone();
    relativise_images(&mut scene, dir);
    let text = scene_to_string(&scene)?;
    // Parse it back as the loader will, so that the file on disk always loads. The path only
    // serves as the base for relative images here; nothing is opened.
    parse_scene(&text, path).map_err(|e| {
        let reason = match e {
            Error::Scene { message, .. } => message,
            other => other.to_string(),
        };
        write_error(format!("the scene would not load back: {reason}"))
    })?;
    // `write_atomic` reports a missing directory as a bare "No such file or directory";
    // saying which directory is more useful.
    if !dir.is_dir() {
        return Err(write_error(format!(
            "directory {} does not exist",
            dir.display()
        )));
    }
    write_atomic(path, text.as_bytes())
}

/// Rewrites the scene's image paths relative to `dir` where that is exact.
fn relativise_images(scene: &mut Scene, dir: &Path) {
    if let HeightSource::Png { path, .. } = &mut scene.terrain.height {
        *path = relative_to(path, dir);
    }
    if let Some(map) = &mut scene.terrain.density_map {
        *map = relative_to(map, dir);
    }
    // Mesh files are resolved like images and written back the same way.
    for object in &mut scene.objects {
        object.mesh = relative_to(&object.mesh, dir);
    }
}

/// `image` as the loader should find it from a scene file in `dir`: the part after `dir` if
/// `dir` leads the path, else the absolute path. Falls back to `image` unchanged if the
/// working directory is unknown or the result is not UTF-8 (the scene types hold `String`s).
fn relative_to(image: &str, dir: &Path) -> String {
    let (Ok(abs_image), Ok(abs_dir)) = (std::path::absolute(image), std::path::absolute(dir))
    else {
        return image.to_owned();
    };
    let abs_image = without_cur_dir(&abs_image);
    let abs_dir = without_cur_dir(&abs_dir);
    let chosen = match abs_image.strip_prefix(&abs_dir) {
        Ok(rest) if !rest.as_os_str().is_empty() => rest.to_path_buf(),
        _ => abs_image,
    };
    chosen
        .to_str()
        .map(str::to_owned)
        .unwrap_or_else(|| image.to_owned())
}

/// Drops `.` components, which never change what a path names, so that `/a/./b` and `/a/b`
/// compare equal.
fn without_cur_dir(path: &Path) -> PathBuf {
    path.components()
        .filter(|c| !matches!(c, Component::CurDir))
        .collect()
}

#[cfg(test)]
mod tests {
    use std::sync::atomic::{AtomicUsize, Ordering};

    use super::*;
    use crate::scene::load_scene;

    /// A fresh, empty directory for one test (removed by [`Scratch`]'s drop).
    struct Scratch(PathBuf);

    impl Scratch {
        fn new(name: &str) -> Self {
            static NEXT: AtomicUsize = AtomicUsize::new(0);
            let dir = std::env::temp_dir().join(format!(
                "sward-save-{name}-{}-{}",
                std::process::id(),
                NEXT.fetch_add(1, Ordering::Relaxed)
            ));
            let _ = std::fs::remove_dir_all(&dir);
            std::fs::create_dir_all(&dir).expect("create scratch directory");
            Self(dir)
        }
    }

    impl Drop for Scratch {
        fn drop(&mut self) {
            let _ = std::fs::remove_dir_all(&self.0);
        }
    }

    fn asset(name: &str) -> PathBuf {
        Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("../../assets/scenes")
            .join(name)
    }

    /// Files in `dir`, sorted, so that a test can see that nothing was left behind.
    fn listing(dir: &Path) -> Vec<String> {
        let mut names: Vec<String> = std::fs::read_dir(dir)
            .expect("list directory")
            .map(|e| e.expect("entry").file_name().to_string_lossy().into_owned())
            .collect();
        names.sort();
        names
    }

    #[test]
    fn shipped_scenes_round_trip() {
        let scratch = Scratch::new("round-trip");
        let names = [
            "meadow.ron",
            "agc_branching.ron",
            "nature.ron",
            "helicopter.ron",
            "two_winds.ron",
            "around_a_boulder.ron",
            "prairie.ron",
            "bunny_meadow.ron",
        ];
        for name in names {
            let scene = load_scene(&asset(name)).expect("load shipped scene");
            let out = scratch.0.join(name);
            save_scene(&scene, &out).expect("save");
            let back = load_scene(&out).expect("load saved scene");
            assert_eq!(back, scene, "{name}");
            // Saving again over the first copy gives the same bytes: the form is stable.
            let first = std::fs::read_to_string(&out).expect("read");
            save_scene(&back, &out).expect("save again");
            assert_eq!(std::fs::read_to_string(&out).expect("read"), first);
        }
        assert_eq!(listing(&scratch.0).len(), names.len());
        let scene = load_scene(&asset("agc_branching.ron")).expect("load");
        assert_eq!(scene.wind.guides[0].points.len(), 6);
        let text = scene_to_string(&scene).expect("to string");
        assert_eq!(
            parse_scene(&text, Path::new("x.ron")).expect("parse"),
            scene
        );
    }

    #[test]
    fn image_paths_are_relative_to_the_saved_file_where_exact() {
        let scratch = Scratch::new("images");
        let src = scratch.0.join("src");
        let other = scratch.0.join("other");
        std::fs::create_dir_all(src.join("maps")).expect("mkdir");
        std::fs::create_dir_all(&other).expect("mkdir");
        let original = src.join("scene.ron");
        std::fs::write(
            &original,
            "(terrain: (height: Png(path: \"maps/h.png\", scale: 2.0), density_map: \
             \"../mask.png\"))",
        )
        .expect("write");
        let scene = load_scene(&original).expect("load");

        // Saved where it came from: the relative paths come back as written.
        let same = src.join("copy.ron");
        save_scene(&scene, &same).expect("save");
        let text = std::fs::read_to_string(&same).expect("read");
        assert!(text.contains("path: \"maps/h.png\""), "{text}");
        assert!(
            text.contains("density_map: Some(\"../mask.png\")"),
            "{text}"
        );
        // Only what differs from the defaults: the terrain's two images.
        assert_eq!(
            text,
            "(\n    terrain: (\n        height: Png(\n            path: \"maps/h.png\",\n            \
             scale: 2.0,\n        ),\n        density_map: Some(\"../mask.png\"),\n    ),\n)\n"
        );
        assert_eq!(load_scene(&same).expect("load"), scene);

        // Saved elsewhere: absolute, naming the same files.
        let moved = other.join("moved.ron");
        save_scene(&scene, &moved).expect("save");
        let text = std::fs::read_to_string(&moved).expect("read");
        let abs = src.join("maps/h.png");
        assert!(
            text.contains(&format!("{:?}", abs.to_str().expect("utf-8"))),
            "{text}"
        );
        assert_eq!(load_scene(&moved).expect("load"), scene);
    }

    #[test]
    fn missing_directory_is_an_error_naming_the_path() {
        let scratch = Scratch::new("missing");
        let scene = load_scene(&asset("meadow.ron")).expect("load");
        let path = scratch.0.join("no/such/dir/scene.ron");
        let err = save_scene(&scene, &path).expect_err("must fail");
        assert!(
            matches!(&err, Error::Write { path: p, .. } if *p == path),
            "{err:?}"
        );
        let shown = err.to_string();
        assert!(shown.contains(path.to_str().expect("utf-8")), "{shown}");
        assert!(shown.contains("does not exist"), "{shown}");
        assert!(!path.exists());
        assert!(listing(&scratch.0).is_empty());
    }

    #[test]
    fn failed_save_leaves_existing_content() {
        let scratch = Scratch::new("failed");
        let scene = load_scene(&asset("meadow.ron")).expect("load");

        // The parent is a file: nothing can be created below it, and it keeps its content.
        let blocker = scratch.0.join("plain.txt");
        std::fs::write(&blocker, "old content").expect("write");
        let path = blocker.join("scene.ron");
        let err = save_scene(&scene, &path).expect_err("must fail");
        assert!(
            err.to_string().contains(path.to_str().expect("utf-8")),
            "{err}"
        );
        assert_eq!(
            std::fs::read_to_string(&blocker).expect("read"),
            "old content"
        );

        // A scene that would not load back is refused before the existing file is touched.
        let existing = scratch.0.join("scene.ron");
        std::fs::write(&existing, "// old\n()\n").expect("write");
        let mut bad = scene.clone();
        bad.field.density = f32::NAN;
        let err = save_scene(&bad, &existing).expect_err("must fail");
        let shown = err.to_string();
        assert!(shown.contains("field.density"), "{shown}");
        assert!(shown.contains(existing.to_str().expect("utf-8")), "{shown}");
        assert_eq!(
            std::fs::read_to_string(&existing).expect("read"),
            "// old\n()\n"
        );
        assert_eq!(listing(&scratch.0), ["plain.txt", "scene.ron"]);
    }

    #[test]
    fn only_values_that_differ_from_the_defaults_are_written() {
        let parse = |text: &str| parse_scene(text, Path::new("/s/x.ron")).expect("parse");
        assert_eq!(scene_to_string(&parse("()")).expect("text"), "()\n");
        let scene = parse(
            "(field: (density: 120.0), wind: (directional: (strength: 3.0), global: None), \
             physics: (collisions: false))",
        );
        let text = scene_to_string(&scene).expect("text");
        assert_eq!(
            text,
            "(\n    field: (\n        density: 120.0,\n    ),\n    wind: (\n        \
             directional: Some((\n            strength: 3.0,\n        )),\n    ),\n    \
             physics: (\n        collisions: false,\n    ),\n)\n"
        );
        assert_eq!(parse(&text), scene);
        // MSAA (default 4): off is written, the default is not.
        let scene = parse("(render: (msaa: 1))");
        let text = scene_to_string(&scene).expect("text");
        assert_eq!(text, "(\n    render: (\n        msaa: 1,\n    ),\n)\n");
        assert_eq!(parse(&text).render.msaa, 1);
        assert_eq!(
            scene_to_string(&parse("(render: (msaa: 4))")).expect("text"),
            "()\n"
        );
    }

    #[test]
    fn none_lists_and_enums_round_trip() {
        let parse = |text: &str| parse_scene(text, Path::new("/s/x.ron")).expect("parse");
        let scenes = [
            "(wind: (directional: None, point: (radius: 3.0)))",
            "(terrain: (height: Flat), field: (height: (min: 0.3, max: 0.4)))",
            "(terrain: (height: Noise(seed: 7, amplitude: 2.5, wavelength: 30, octaves: 4)))",
            "(colliders: [(center: (0, 1, 0), radius: 0.5, motion: Path(points: [(0, 0), \
             (1, 1)], speed: 2, looped: true))], wind: (global: (direction: (0, 1), \
             strength: 2), downwash: (position: (0, 3, 0), radius: 2, strength: 5)))",
            "(camera: (eye: (1, 2, 3)), render: (sun_direction: (0, 1, 0)), culling: \
             (distance: true))",
        ];
        for text in scenes {
            let scene = parse(text);
            let saved = scene_to_string(&scene).expect("text");
            assert_eq!(parse(&saved), scene, "{text}\n{saved}");
        }
        let saved = scene_to_string(&parse(scenes[0])).expect("text");
        assert!(saved.contains("directional: None"), "{saved}");
        // The point wind is None by default, so it is written whole.
        assert!(
            saved.contains("radius: 3.0") && saved.contains("strength"),
            "{saved}"
        );
        // A range has no defaults of its own: both ends are written.
        let saved =
            scene_to_string(&parse("(field: (height: (min: 0.35, max: 0.9)))")).expect("text");
        assert!(
            saved.contains("min: 0.35") && saved.contains("max: 0.9"),
            "{saved}"
        );
    }
}
