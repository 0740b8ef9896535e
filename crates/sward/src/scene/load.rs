//! Reading a scene: file → text → [`Scene`] → validated [`Scene`].
//!
//! Parsing is left entirely to `ron` + serde (the types reject unknown fields); this module
//! only turns `ron`'s spanned errors into [`Error::Scene`] so that every failure reads as
//! `path:line:column: message`, and then runs the validation pass.

use std::path::Path;

use ron::error::{Error as RonError, SpannedError};
use ron::{extensions::Extensions, Options};

use super::types::Scene;
use super::validate::allowed_for;
use super::validate::locate::{field_at, field_value, offset_of};
use crate::error::Result;

/// Reads, parses and validates the scene file at `path`.
///
/// Relative image paths in the scene (`terrain.height: Png(path: ..)`,
/// `terrain.density_map`) are resolved against the directory of `path`.
///
/// # Errors
///
/// [`crate::Error::Read`] naming `path` if the file cannot be read (missing, unreadable, not
/// UTF-8); [`crate::Error::Scene`] with line and column for a syntax error, an unknown field, a
/// wrong type or a value out of range.
pub fn load_scene(path: &Path) -> Result<Scene> {
    let text = crate::input::read_text(path)?;
    parse_scene(&text, path)
}

/// Parses and validates scene `text`; `path` is the file the text came from.
///
/// `path` is used in error messages and as the base for relative image paths (its parent
/// directory); it is never opened. For text that comes from no file, pass a path in the
/// directory that relative image paths should refer to, e.g. `Path::new("<inline>")` for
/// the working directory.
///
/// ```
/// use std::path::Path;
///
/// let scene = sward::scene::parse_scene("(field: (density: 200.0))", Path::new("a.ron")).unwrap();
/// assert_eq!(scene.field.density, 200.0);
/// ```
///
/// # Errors
///
/// [`crate::Error::Scene`] with line and column for a syntax error, an unknown field, a
/// wrong type or a value out of range.
pub fn parse_scene(text: &str, path: &Path) -> Result<Scene> {
    // The same path as with `--set` arguments, with none.
    super::parse_scene_with_sets(text, path, &[])
}

/// The message for `ron`'s error `e` in `text`: when it is about a value (a wrong type, an
/// integer out of bounds, an unknown variant), it names the field the value belongs to,
/// quotes the value and gives the field's allowed range, e.g.
/// `terrain.resolution = 1e3 is not a valid value (Invalid digit 'e' for base 10 integers):
/// allowed 2 <= resolution <= 4097 vertices per side`. Syntax errors and unknown fields
/// (whose message already names the field) keep `ron`'s message.
pub(crate) fn parse_error_message(text: &str, e: &SpannedError) -> String {
    let said = e.code.to_string();
    let offset = offset_of(text, e.position.line, e.position.col);
    let missing = matches!(e.code, RonError::MissingStructField { .. });
    let field = field_at(text, offset, !missing);
    if field.is_empty() {
        return said;
    }
    let span = field_value(text, &field).unwrap_or(offset..offset);
    let mut value = shorten(text[span.clone()].trim());
    let mut said = said;
    match &e.code {
        // `model: 1`: ron suggests its raw-identifier syntax (`r#1`), which is no variant
        // either; the allowed names below are what helps.
        RonError::InvalidIdentifier(_) | RonError::SuggestRawIdentifier(_) => {
            said = "not a name".to_owned();
        }
        RonError::MissingStructField { .. } | RonError::DuplicateStructField { .. } => {
            return match allowed_for(&field) {
                Some(allowed) => format!("{field}: {said}: allowed {allowed}"),
                None => format!("{field}: {said}"),
            };
        }
        code if !is_value_error(code) => {
            // `resolution: 3.5` is a syntax error to `ron` (an integer, then `.5` where a
            // comma belongs), but to the user a malformed value: the error falls inside the
            // value's first token.
            let token_end = text[span.start..]
                .find(|c: char| c.is_whitespace() || matches!(c, ',' | ')' | ']' | '}'))
                .map_or(text.len(), |n| span.start + n);
            if !(span.start < offset && offset < token_end) {
                return said;
            }
            value = text[span.start..token_end].to_owned();
            said = format!("unexpected `{}`", &text[offset..token_end]);
        }
        _ => {}
    }
    let shown = if value.is_empty() {
        format!("{field} is not a valid value ({said})")
    } else {
        format!("{field} = {value} is not a valid value ({said})")
    };
    match allowed_for(&field) {
        Some(allowed) => format!("{shown}: allowed {allowed}"),
        None => shown,
    }
}

/// Whether `ron` raised `code` because of what a value is (its type or its digits) rather
/// than because of the syntax around it.
fn is_value_error(code: &RonError) -> bool {
    matches!(
        code,
        RonError::Message(_)
            | RonError::ExpectedArray
            | RonError::ExpectedBoolean
            | RonError::ExpectedChar
            | RonError::ExpectedFloat
            | RonError::FloatUnderscore
            | RonError::ExpectedInteger
            | RonError::ExpectedOption
            | RonError::ExpectedMap
            | RonError::ExpectedDifferentStructName { .. }
            | RonError::ExpectedStructLike
            | RonError::ExpectedNamedStructLike(_)
            | RonError::ExpectedUnit
            | RonError::ExpectedString
            | RonError::ExpectedIdentifier
            | RonError::IntegerOutOfBounds
            | RonError::InvalidIntegerDigit { .. }
            | RonError::UnderscoreAtBeginning
            | RonError::InvalidValueForType { .. }
            | RonError::ExpectedDifferentLength { .. }
            | RonError::NoSuchEnumVariant { .. }
            | RonError::InvalidIdentifier(_)
            | RonError::SuggestRawIdentifier(_)
    )
}

/// A value as quoted in a message: on one line, and cut short if it is long.
fn shorten(value: &str) -> String {
    let one_line: Vec<&str> = value.split_whitespace().collect();
    let one_line = one_line.join(" ");
    if one_line.chars().count() <= 60 {
        return one_line;
    }
    let cut: String = one_line.chars().take(57).collect();
    format!("{cut}...")
}

/// `ron` options for scene files. `implicit_some` lets users write `directional: (..)`
/// instead of `directional: Some((..))`; the explicit form still parses.
pub(crate) fn options() -> Options {
    Options::default().with_default_extension(Extensions::IMPLICIT_SOME)
}

#[cfg(test)]
mod tests {
    use std::path::PathBuf;

    use super::*;
    use crate::error::Error;
    use crate::scene::validate::validate;
    use crate::scene::{DirectionalWind, HeightSource, Motion};

    fn parse(text: &str) -> Result<Scene> {
        parse_scene(text, Path::new("/scenes/test.ron"))
    }

    /// The scene error's (line, column, message), panicking on any other outcome.
    fn scene_error(text: &str) -> (usize, usize, String) {
        match parse(text) {
            Err(Error::Scene {
                path,
                line,
                column,
                message,
            }) => {
                assert_eq!(path, Path::new("/scenes/test.ron"));
                (line, column, message)
            }
            other => panic!("expected a scene error, got {other:?}"),
        }
    }

    /// `Scene::default()` after validation (which normalises its direction vectors).
    fn validated_default() -> Scene {
        let mut scene = Scene::default();
        validate(&mut scene, "()", Path::new("/scenes/test.ron")).unwrap();
        scene
    }

    #[test]
    fn empty_scene_gives_the_defaults() {
        assert_eq!(parse("()").unwrap(), validated_default());
        assert_eq!(parse("Scene()").unwrap(), validated_default());
        assert_eq!(
            parse("\u{feff}// nothing\n()\n").unwrap(),
            validated_default()
        );
    }

    #[test]
    fn default_scene_is_valid_and_only_directions_change() {
        let scene = validated_default();
        let default = Scene::default();
        assert_eq!(scene.terrain, default.terrain);
        assert_eq!(scene.field, default.field);
        assert_eq!(scene.physics, default.physics); // (0, -1, 0) is already unit length
        assert_eq!(scene.camera, default.camera);
        let d = scene.wind.directional.as_ref().unwrap().direction;
        assert!((d.0.hypot(d.1) - 1.0).abs() < 1e-6);
        let s = scene.render.sun_direction;
        assert!((glam::Vec3::from(s).length() - 1.0).abs() < 1e-6);
    }

    #[test]
    fn valid_scene_round_trips() {
        let mut scene = validated_default();
        scene.terrain.height = HeightSource::Flat;
        scene.field.density = 250.5;
        scene.colliders.push(crate::scene::Sphere {
            center: (1.0, 0.5, -2.0),
            radius: 0.75,
            motion: Motion::Path {
                points: vec![(0.0, 0.0), (4.0, 3.0), (-1.0, 2.5)],
                speed: 1.5,
                looped: true,
            },
        });
        scene.wind.point = Some(crate::scene::PointWind::default());
        for opts in [Options::default(), options()] {
            let text = opts
                .to_string_pretty(&scene, ron::ser::PrettyConfig::default())
                .unwrap();
            assert_eq!(parse(&text).unwrap(), scene, "{text}");
        }
    }

    #[test]
    fn hand_written_scene_parses() {
        let text = r#"#![enable(implicit_some)]
(
    terrain: (
        size: 60.0,
        resolution: 257,
        height: Png(path: "hills.png", scale: 5.0),
        density_map: "maps/density.png",
    ),
    field: (density: 120, height: (min: 0.3, max: 0.9), shape: Quadratic, patch_size: 512),
    colliders: [
        (center: (0.0, 0.5, 0.0), radius: 0.5),
        (center: (1.0, 0.5, 0.0), radius: 0.25, motion: Velocity((1.0, 0.0, 0.0))),
    ],
    wind: (directional: Some((direction: (0.0, 2.0), strength: 3.0)), point: None),
    camera: (eye: (0.0, 2.0, 10.0), target: (0.0, 0.0, 0.0), fov_y: 60.0),
)
"#;
        let scene = parse(text).unwrap();
        assert_eq!(scene.terrain.size, 60.0);
        assert_eq!(
            scene.terrain.height,
            HeightSource::Png {
                path: "/scenes/hills.png".into(),
                scale: 5.0
            }
        );
        assert_eq!(
            scene.terrain.density_map.as_deref(),
            Some("/scenes/maps/density.png")
        );
        assert_eq!(scene.field.density, 120.0);
        assert_eq!(scene.colliders.len(), 2);
        assert_eq!(scene.colliders[0].motion, Motion::Static);
        assert_eq!(
            scene.wind.directional,
            Some(DirectionalWind {
                direction: (0.0, 1.0),
                strength: 3.0,
                ..DirectionalWind::default()
            })
        );
        assert_eq!(scene.wind.point, None);
    }

    #[test]
    fn some_may_be_omitted() {
        let scene = parse("(wind: (directional: (strength: 3.0), point: (radius: 2.0)))").unwrap();
        assert_eq!(scene.wind.directional.unwrap().strength, 3.0);
        assert_eq!(scene.wind.point.unwrap().radius, 2.0);
        let scene = parse("(wind: (directional: None))").unwrap();
        assert_eq!(scene.wind.directional, None);
    }

    #[test]
    fn malformed_ron_reports_its_line() {
        // The comma after `density: 3.0` is missing, so `ron` stumbles on line 4.
        let (line, _, message) = scene_error(
            "(\n    field: (\n        density: 3.0\n        tuft_radius: 0.2,\n    ),\n)\n",
        );
        assert_eq!(line, 4, "{message}");
        let (line, _, _) = scene_error("(\n    field: (\n        density: 3.0,\n");
        assert!(line >= 3);
        let (line, column, _) = scene_error("(field: (density: \"lots\"))");
        assert_eq!((line, column > 1), (1, true));
    }

    #[test]
    fn unknown_field_is_rejected_and_named() {
        let (line, _, message) = scene_error("(\n    field: (\n        densty: 3.0,\n    ),\n)\n");
        assert_eq!(line, 3, "{message}");
        assert!(message.contains("`densty`"), "{message}");
        assert!(message.contains("`density`"), "{message}");
        let (line, _, message) = scene_error("(\n  grass: (),\n)");
        assert_eq!(line, 2, "{message}");
        assert!(message.contains("`grass`"), "{message}");
    }

    #[test]
    fn negative_density_names_field_range_and_line() {
        let text = "(\n    terrain: (size: 20.0),\n    field: (\n        seed: 4,\n        density: -3,\n    ),\n)\n";
        let (line, column, message) = scene_error(text);
        assert_eq!(
            message,
            "field.density = -3 is out of range: allowed 0 < density <= 10000 blades/m²"
        );
        assert_eq!((line, column), (5, 9));
        let shown = parse(text).unwrap_err().to_string();
        assert!(
            shown.starts_with("/scenes/test.ron:5:9: field.density"),
            "{shown}"
        );
    }

    #[test]
    fn nan_and_infinity_are_rejected() {
        for value in ["NaN", "inf", "-inf"] {
            let (line, _, message) = scene_error(&format!("(\n  field: (density: {value}),\n)"));
            assert_eq!(line, 2);
            assert!(message.starts_with("field.density = "), "{message}");
            assert!(message.contains("not a finite number"), "{message}");
        }
        let (_, _, message) = scene_error("(camera: (eye: (0.0, NaN, 1.0)))");
        assert!(message.starts_with("camera.eye = (0, NaN, 1)"), "{message}");
    }

    #[test]
    fn missing_file_names_the_path() {
        let path = Path::new("/nonexistent/dir/scene.ron");
        match load_scene(path) {
            Err(Error::Read { path: p, .. }) => assert_eq!(p, path),
            other => panic!("expected a read error, got {other:?}"),
        }
        let shown = load_scene(path).unwrap_err().to_string();
        assert!(shown.contains("/nonexistent/dir/scene.ron"), "{shown}");
    }

    #[test]
    fn load_scene_resolves_images_next_to_the_file() {
        let dir = std::env::temp_dir().join(format!("sward-scene-test-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let path = dir.join("meadow.ron");
        std::fs::write(&path, "(terrain: (density_map: \"mask.png\"))").unwrap();
        let result = load_scene(&path);
        std::fs::remove_dir_all(&dir).unwrap();
        let expected: PathBuf = dir.join("mask.png");
        assert_eq!(
            result.unwrap().terrain.density_map.map(PathBuf::from),
            Some(expected)
        );
    }

    #[test]
    fn parser_errors_name_the_field_and_its_range() {
        let cases = [
            (
                "(\n  terrain: (\n    resolution: 99999999999,\n  ),\n)",
                "/scenes/test.ron:3:28: terrain.resolution = 99999999999 is not a valid value \
                 (Integer is out of bounds): allowed 2 <= resolution <= 4097 vertices per side",
            ),
            (
                "(terrain: (resolution: 1e3))",
                "/scenes/test.ron:1:25: terrain.resolution = 1e3 is not a valid value (Invalid \
                 digit 'e' for base 10 integers): allowed 2 <= resolution <= 4097 vertices per \
                 side",
            ),
            (
                "(terrain: (resolution: -5))",
                "/scenes/test.ron:1:26: terrain.resolution = -5 is not a valid value (Integer is \
                 out of bounds): allowed 2 <= resolution <= 4097 vertices per side",
            ),
            (
                "(terrain: (resolution: 3.5))",
                "/scenes/test.ron:1:25: terrain.resolution = 3.5 is not a valid value \
                 (unexpected `.5`): allowed 2 <= resolution <= 4097 vertices per side",
            ),
            (
                "(field: (density: \"lots\", seed: 2))",
                "/scenes/test.ron:1:19: field.density = \"lots\" is not a valid value (Expected \
                 float): allowed 0 < density <= 10000 blades/m²",
            ),
            (
                "(culling: (distance: 3))",
                "/scenes/test.ron:1:22: culling.distance = 3 is not a valid value (Expected \
                 boolean): allowed true or false",
            ),
            (
                "(field: (seed: -1))",
                "/scenes/test.ron:1:18: field.seed = -1 is not a valid value (Integer is out of \
                 bounds): allowed 0 <= seed <= 18446744073709551615",
            ),
            (
                "(wind: (point: (strength: true)))",
                "/scenes/test.ron:1:27: wind.point.strength = true is not a valid value \
                 (Expected float): allowed 0 <= strength <= 1000 m/s²",
            ),
            (
                "(colliders: [(center: (0, 0), radius: 1)])",
                "/scenes/test.ron:1:28: colliders[0].center = (0, 0) is not a valid value \
                 (Expected a tuple of size 3 but found 2 elements instead): allowed -100000 <= \
                 center <= 100000 m for every component",
            ),
            (
                "(colliders: [(center: (0, 0, 0))])",
                "/scenes/test.ron:1:32: colliders[0]: Unexpected missing field named `radius` in \
                 `Sphere`: allowed (center: (x, y, z), radius: .., motion: ..)",
            ),
            (
                "(field: (height: (min: \"a\", max: 1)))",
                "/scenes/test.ron:1:24: field.height.min = \"a\" is not a valid value (Expected \
                 float): allowed 0.01 <= height.min <= 10 m (and min <= max)",
            ),
        ];
        for (text, expected) in cases {
            assert_eq!(parse(text).unwrap_err().to_string(), expected, "{text}");
        }
        let (_, _, message) = scene_error("(field: (height: (min: 0.5)))");
        assert_eq!(
            message,
            "field.height: Unexpected missing field named `max` in `Range`: allowed (min: .., \
             max: ..) with 0.01 <= each <= 10 m and min <= max"
        );
        let shape = parse("(field: (shape: Round))").unwrap_err().to_string();
        assert!(
            shape.starts_with("/scenes/test.ron:1:22: field.shape = Round is not a valid value"),
            "{shape}"
        );
        assert!(
            shape.ends_with("allowed one of Quad, Triangle, Quadratic, TriangleTip, Dandelion"),
            "{shape}"
        );
        // A syntax error is not about a value: `ron`'s own message.
        let (_, _, message) = scene_error("(field: (density: 3.0 seed: 2))");
        assert_eq!(message, "Expected comma");
    }
}
