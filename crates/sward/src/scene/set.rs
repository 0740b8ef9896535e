//! `--set PATH=VALUE`: change fields of a scene from the command line without editing it,
//! validated exactly like the file (the same messages, with the field and its range).
//!
//! `PATH` is a field path as validation messages write it (`field.density`,
//! `wind.guides[0].strength`, `terrain.height.amplitude`); `VALUE` is RON (`40`, `false`,
//! `(1.0, 2.0, 3.0)`, `Flat`, `Noise(amplitude: 3.0)`, `None`).
//!
//! How: the file is parsed by serde alone, written back as RON with every field, and each
//! value is spliced into that text at its field's span (found by the same text scan that
//! locates errors) and parsed again, so a value is read by exactly the parser and types
//! that read the file. A field under an optional part that is `None` (`wind.point.strength`
//! when the file has no point wind) first fills that part with its defaults. Validation
//! runs once at the end, knowing which fields were set: their errors name the argument
//! (`--set field.density=-3: field.density = -3 is out of range: ..`), the file's own
//! values keep `path:line:column`. Relative image paths resolve against the scene file's
//! directory, once, as for values written in the file.

use std::ops::Range as Span;
use std::path::Path;

use ron::ser::PrettyConfig;

use super::load::{options, parse_error_message};
use super::origin::Origin;
use super::types::{Downwash, GlobalWind, PointWind, Scene};
use super::validate::locate::{
    inside_some, list_elements, mask, split_index, struct_fields, value_span,
};
use super::validate::{validate_with_sets, SetField};
use crate::error::{Error, Result};

/// Reads the scene file at `path` and applies `sets` (each `PATH=VALUE`), then validates.
///
/// # Errors
///
/// As [`crate::scene::load_scene`], and [`Error::Set`] for a malformed argument, a path
/// that names no field, or a value that does not parse or is out of range.
pub fn load_scene_with_sets(path: &Path, sets: &[String]) -> Result<Scene> {
    let text = crate::input::read_text(path)?;
    parse_scene_with_sets(&text, path, sets)
}

/// Parses scene `text` (from the file `path`, see [`crate::scene::parse_scene`]), applies
/// `sets` in order (each `PATH=VALUE`; a later one wins) and validates the result.
///
/// ```
/// use std::path::Path;
///
/// let sets = ["field.density=40".to_owned(), "culling.distance=true".to_owned()];
/// let scene = sward::scene::parse_scene_with_sets("()", Path::new("a.ron"), &sets).unwrap();
/// assert_eq!(scene.field.density, 40.0);
/// assert!(scene.culling.distance);
///
/// let bad = ["field.density=-3".to_owned()];
/// let err = sward::scene::parse_scene_with_sets("()", Path::new("a.ron"), &bad).unwrap_err();
/// assert_eq!(
///     err.to_string(),
///     "--set field.density=-3: field.density = -3 is out of range: allowed 0 < density <= \
///      10000 blades/m²"
/// );
/// ```
///
/// # Errors
///
/// [`Error::Scene`] for the file's own syntax errors and values (with line and column);
/// [`Error::Set`] naming the argument for a malformed argument, an unknown field (with the
/// allowed keys), an index past the end of a list, or a value that does not parse or is
/// out of range (with the field and its allowed range).
pub fn parse_scene_with_sets(text: &str, path: &Path, sets: &[String]) -> Result<Scene> {
    let text = text.strip_prefix('\u{feff}').unwrap_or(text);
    let mut scene: Scene = options().from_str(text).map_err(|e| Error::Scene {
        path: path.to_path_buf(),
        line: e.position.line,
        column: e.position.col,
        message: parse_error_message(text, &e),
    })?;
    let mut fields = Vec::with_capacity(sets.len());
    for arg in sets {
        let (field, value) = split_arg(arg)?;
        scene = apply(&scene, arg, &field, value)?;
        fields.push(SetField {
            path: field,
            arg: arg.clone(),
        });
    }
    validate_with_sets(&mut scene, text, path, &fields)?;
    scene.origin = Origin::new(path, text, fields);
    Ok(scene)
}

/// `PATH=VALUE` split at the first `=`, the path checked for its form.
fn split_arg(arg: &str) -> Result<(String, &str)> {
    let fail = |message: String| Error::Set {
        arg: arg.to_owned(),
        message,
    };
    let Some((field, value)) = arg.split_once('=') else {
        return Err(fail(
            "expected PATH=VALUE, e.g. field.density=40 or wind.guides[0].strength=3".into(),
        ));
    };
    let field = field.trim();
    if field.is_empty() {
        return Err(fail(
            "the field path before `=` is empty: expected PATH=VALUE, e.g. field.density=40".into(),
        ));
    }
    if value.trim().is_empty() {
        return Err(fail(format!(
            "the value after `=` is empty: give {field} a RON value"
        )));
    }
    let well_formed = field.split('.').all(|segment| {
        let (name, index) = split_index(segment);
        let bracket = segment.contains('[');
        !name.is_empty()
            && name.bytes().all(|b| b.is_ascii_alphanumeric() || b == b'_')
            && (!bracket || (index.is_some() && segment.ends_with(']')))
    });
    if !well_formed {
        return Err(fail(format!(
            "`{field}` is not a field path: expected keys separated by `.`, with [i] for list \
             elements, e.g. colliders[0].radius"
        )));
    }
    Ok((field.to_owned(), value.trim()))
}

/// `scene` with the field at `field` replaced by the RON `value`; `arg` names the argument
/// in errors.
fn apply(scene: &Scene, arg: &str, field: &str, value: &str) -> Result<Scene> {
    let fail = |message: String| Error::Set {
        arg: arg.to_owned(),
        message,
    };
    single_value(value).map_err(&fail)?;
    let mut text = full_text(scene).map_err(&fail)?;
    // Each pass either finds the field or fills one `None` on the way and looks again.
    let span = loop {
        match find(&text, field).map_err(&fail)? {
            Found::Value(span) => break span,
            Found::NoneAt(prefix, span) => {
                let Some(default) = default_of(&prefix) else {
                    let rest = &field[prefix.len()..];
                    return Err(fail(format!(
                        "{prefix} is None, which has no field `{}`: set {prefix} itself",
                        rest.trim_start_matches('.')
                    )));
                };
                text.replace_range(span, &format!("Some({default})"));
            }
        }
    };
    text.replace_range(span, value);
    options().from_str(&text).map_err(|e| {
        let message = parse_error_message(&text, &e);
        fail(message)
    })
}

/// What [`find`] found.
enum Found {
    /// The span of the field's value.
    Value(Span<usize>),
    /// An optional part on the way (its path and span) is `None`.
    NoneAt(String, Span<usize>),
}

/// The span of `field`'s value in `text`, a scene written with every field.
fn find(text: &str, field: &str) -> std::result::Result<Found, String> {
    let code = mask(text);
    let mut region = 0..code.len();
    let mut prefix = String::new();
    for segment in field.split('.') {
        let (name, index) = split_index(segment);
        region = trim(&code, region);
        if &code[region.clone()] == b"None" {
            return Ok(Found::NoneAt(prefix, region));
        }
        let inner = inside_some(&code, region.clone()).unwrap_or(region.clone());
        let Some(fields) = struct_fields(&code, inner.clone()) else {
            let shown = one_line(&text[inner]);
            return Err(format!(
                "{prefix} is {shown}, which has no field `{name}`: set {prefix} itself"
            ));
        };
        let Some((_, value)) = fields.iter().find(|(key, _)| key == name) else {
            let keys: Vec<String> = fields.iter().map(|(k, _)| format!("`{k}`")).collect();
            let within = if prefix.is_empty() {
                "the scene".to_owned()
            } else {
                format!("`{prefix}`")
            };
            return Err(format!(
                "unknown field `{name}` in {within}, expected one of {}",
                keys.join(", ")
            ));
        };
        if !prefix.is_empty() {
            prefix.push('.');
        }
        prefix.push_str(name);
        region = value.clone();
        if let Some(index) = index {
            let Some(elements) = list_elements(&code, trim(&code, region.clone())) else {
                return Err(format!(
                    "{prefix} is not a list: `{prefix}[{index}]` names nothing"
                ));
            };
            let count = elements.len();
            let Some(element) = elements.get(index) else {
                let allowed = match count {
                    0 => "it is empty".to_owned(),
                    1 => "it has 1 element, allowed index 0".to_owned(),
                    n => format!("it has {n} elements, allowed 0 <= index <= {}", n - 1),
                };
                return Err(format!(
                    "{prefix}[{index}]: index {index} is out of range: {allowed} (set \
                     {prefix} to a longer list first)"
                ));
            };
            prefix.push_str(&format!("[{index}]"));
            region = element.clone();
        }
    }
    Ok(Found::Value(trim(&code, region)))
}

/// The RON text of the defaults of the optional part at `path`, for filling it in.
fn default_of(path: &str) -> Option<String> {
    let text = match path {
        "wind.directional" => ron::to_string(&Scene::default().wind.directional),
        "wind.point" => ron::to_string(&PointWind::default()),
        "wind.global" => ron::to_string(&GlobalWind::default()),
        "wind.downwash" => ron::to_string(&Downwash::default()),
        _ => return None,
    };
    let text = text.ok()?;
    // `Scene::default().wind.directional` is itself an `Option`.
    Some(
        text.strip_prefix("Some(")
            .and_then(|t| t.strip_suffix(')'))
            .map_or(text.clone(), str::to_owned),
    )
}

/// `scene` as RON with every field written (the form [`find`] searches).
fn full_text(scene: &Scene) -> std::result::Result<String, String> {
    let config = PrettyConfig::new().struct_names(false);
    ron::ser::to_string_pretty(scene, config).map_err(|e| format!("cannot write the scene: {e}"))
}

/// Checks that `value` is one RON value: no comment (it would swallow what follows it in
/// the text it is spliced into), balanced brackets and no top-level comma (which would
/// smuggle in other fields).
fn single_value(value: &str) -> std::result::Result<(), String> {
    let code = mask(value);
    // The mask blanks comments and string contents but keeps a string's quotes, so a `/`
    // that was blanked outside quotes began a comment.
    let mut in_string = false;
    let mut comment = false;
    for (i, &b) in code.iter().enumerate() {
        if b == b'"' {
            in_string = !in_string;
        } else if !in_string && b == b' ' && value.as_bytes()[i] == b'/' {
            comment = true;
        }
    }
    if comment {
        return Err(format!("`{value}` holds a comment: give only the value"));
    }
    let mut depth = 0i32;
    for &b in &code {
        match b {
            b'(' | b'[' | b'{' => depth += 1,
            b')' | b']' | b'}' => depth -= 1,
            _ => {}
        }
        if depth < 0 {
            break;
        }
    }
    let span = value_span(&code, 0, code.len());
    let rest = &code[span.end..];
    if depth != 0 || rest.iter().any(|b| !b.is_ascii_whitespace()) {
        return Err(format!(
            "`{value}` is not a single RON value (unbalanced brackets or a `,` outside them)"
        ));
    }
    Ok(())
}

/// `span` without leading and trailing whitespace.
fn trim(code: &[u8], span: Span<usize>) -> Span<usize> {
    let mut start = span.start;
    let mut end = span.end;
    while start < end && code[start].is_ascii_whitespace() {
        start += 1;
    }
    while end > start && code[end - 1].is_ascii_whitespace() {
        end -= 1;
    }
    start..end
}

fn one_line(text: &str) -> String {
    text.split_whitespace().collect::<Vec<_>>().join(" ")
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::{parse_scene, HeightSource, Motion};

    const PATH: &str = "/scenes/test.ron";

    fn set(text: &str, sets: &[&str]) -> Result<Scene> {
        let sets: Vec<String> = sets.iter().map(|s| (*s).to_owned()).collect();
        parse_scene_with_sets(text, Path::new(PATH), &sets)
    }

    fn error(text: &str, sets: &[&str]) -> String {
        set(text, sets).unwrap_err().to_string()
    }

    #[test]
    fn sets_replace_values_and_keep_the_rest() {
        let file = "(field: (density: 120, seed: 4), culling: (distance: true))";
        let scene = set(file, &["culling.distance=false", "field.density=40"]).unwrap();
        let mut expected = parse_scene(file, Path::new(PATH)).unwrap();
        expected.culling.distance = false;
        expected.field.density = 40.0;
        assert_eq!(scene, expected);
        // A later --set of the same field wins; no --set is the file as it is.
        let scene = set(file, &["field.density=40", "field.density=41"]).unwrap();
        assert_eq!(scene.field.density, 41.0);
        assert_eq!(
            set(file, &[]).unwrap(),
            parse_scene(file, Path::new(PATH)).unwrap()
        );
    }

    #[test]
    fn sets_fields_the_file_omits_and_whole_values() {
        let scene = set(
            "()",
            &[
                "camera.eye=(1.0, 2.0, 3.0)",
                "terrain.height=Noise(amplitude: 3.0)",
                "field.shape=Quad",
                "wind.directional=None",
            ],
        )
        .unwrap();
        assert_eq!(scene.camera.eye, (1.0, 2.0, 3.0));
        assert_eq!(
            scene.terrain.height,
            HeightSource::Noise {
                seed: 7,
                amplitude: 3.0,
                wavelength: 30.0,
                octaves: 4
            }
        );
        assert_eq!(scene.field.shape, crate::scene::Shape::Quad);
        assert_eq!(scene.wind.directional, None);
        let scene = set("()", &["terrain.height=Flat"]).unwrap();
        assert_eq!(scene.terrain.height, HeightSource::Flat);
        let scene = set("()", &["terrain.height.amplitude=5"]).unwrap();
        let HeightSource::Noise { amplitude, .. } = scene.terrain.height else {
            panic!("noise")
        };
        assert_eq!(amplitude, 5.0);
    }

    #[test]
    fn sets_fill_a_none_with_defaults() {
        let scene = set("(wind: (point: None))", &["wind.point.strength=2"]).unwrap();
        assert_eq!(
            scene.wind.point,
            Some(PointWind {
                strength: 2.0,
                ..PointWind::default()
            })
        );
        let scene = set("()", &["wind.global.strength=3", "wind.downwash.radius=2"]).unwrap();
        assert_eq!(scene.wind.global.unwrap().strength, 3.0);
        assert_eq!(scene.wind.downwash.unwrap().radius, 2.0);
        let scene = set("(wind: (directional: None))", &["wind.directional.gust=1"]).unwrap();
        assert_eq!(scene.wind.directional.unwrap().gust, 1.0);
    }

    #[test]
    fn sets_reach_list_elements() {
        let file = "(colliders: [(center: (0, 1, 0), radius: 1), (center: (2, 1, 0), radius: 1)])";
        let scene = set(
            file,
            &[
                "colliders[1].radius=0.5",
                "colliders[0].motion=Velocity((1, 0, 0))",
            ],
        )
        .unwrap();
        assert_eq!(scene.colliders[1].radius, 0.5);
        assert_eq!(scene.colliders[0].motion, Motion::Velocity((1.0, 0.0, 0.0)));
        let scene = set(
            "()",
            &[
                "colliders=[(center: (0, 1, 0), radius: 1)]",
                "colliders[0].radius=2",
            ],
        )
        .unwrap();
        assert_eq!(scene.colliders[0].radius, 2.0);
    }

    #[test]
    fn set_errors_name_the_argument_field_and_range() {
        assert_eq!(
            error("(field: (seed: 4))", &["field.density=-3"]),
            "--set field.density=-3: field.density = -3 is out of range: allowed 0 < density \
             <= 10000 blades/m²"
        );
        assert_eq!(
            error("()", &["field.density=lots"]),
            "--set field.density=lots: field.density = lots is not a valid value (Expected \
             float): allowed 0 < density <= 10000 blades/m²"
        );
        assert_eq!(
            error("()", &["terrain.resolution=99999999999"]),
            "--set terrain.resolution=99999999999: terrain.resolution = 99999999999 is not a \
             valid value (Integer is out of bounds): allowed 2 <= resolution <= 4097 vertices \
             per side"
        );
        assert_eq!(
            error("()", &["wind.point.strength=1e38"]),
            "--set wind.point.strength=1e38: wind.point.strength = \
             100000000000000000000000000000000000000 is out of range: allowed 0 <= strength \
             <= 1000 m/s²"
        );
        assert_eq!(
            error("()", &["render.msaa=3"]),
            "--set render.msaa=3: render.msaa = 3 is not a sample count: allowed one of 1, \
             2, 4, 8 samples"
        );
        assert_eq!(
            error("()", &["render.msaa=-1"]),
            "--set render.msaa=-1: render.msaa = -1 is not a valid value (Integer is out of \
             bounds): allowed one of 1, 2, 4, 8 samples"
        );
        // A range whose other end was set: the argument is named.
        let m = error("()", &["field.height.min=0.9"]);
        assert!(
            m.starts_with("--set field.height.min=0.9: field.height: min = 0.9 is greater"),
            "{m}"
        );
    }

    #[test]
    fn file_errors_keep_their_line_with_sets() {
        let text = "(\n  field: (density: -3),\n)";
        assert_eq!(
            error(text, &["culling.distance=false"]),
            "/scenes/test.ron:2:11: field.density = -3 is out of range: allowed 0 < density \
             <= 10000 blades/m²"
        );
        assert_eq!(
            error("(\n  field: (density: 3 seed: 1))", &["field.density=4"]),
            "/scenes/test.ron:2:22: Expected comma"
        );
    }

    #[test]
    fn unknown_fields_and_indices_are_explained() {
        let m = error("()", &["field.densty=3"]);
        assert!(
            m.starts_with(
                "--set field.densty=3: unknown field `densty` in `field`, expected one of \
                 `density`, `height`,"
            ),
            "{m}"
        );
        let m = error("()", &["grass=3"]);
        assert!(m.contains("unknown field `grass` in the scene, expected one of `terrain`"));
        assert_eq!(
            error("()", &["colliders[0].radius=2"]),
            "--set colliders[0].radius=2: colliders[0]: index 0 is out of range: it is empty \
             (set colliders to a longer list first)"
        );
        let m = error(
            "(colliders: [(center: (0, 1, 0), radius: 1)])",
            &["colliders[3].radius=2"],
        );
        assert!(m.contains("index 3 is out of range: it has 1 element, allowed index 0"));
        let m = error("(terrain: (height: Flat))", &["terrain.height.amplitude=3"]);
        assert_eq!(
            m,
            "--set terrain.height.amplitude=3: terrain.height is Flat, which has no field \
             `amplitude`: set terrain.height itself"
        );
        let m = error("()", &["terrain.density_map.x=3"]);
        assert!(
            m.contains("terrain.density_map is None, which has no field `x`"),
            "{m}"
        );
        let m = error("()", &["field.density.x=3"]);
        assert!(
            m.contains("field.density is 80.0, which has no field `x`"),
            "{m}"
        );
    }

    #[test]
    fn malformed_arguments_are_rejected() {
        assert_eq!(
            error("()", &["field.density"]),
            "--set field.density: expected PATH=VALUE, e.g. field.density=40 or \
             wind.guides[0].strength=3"
        );
        assert!(error("()", &["=3"]).contains("the field path before `=` is empty"));
        assert!(error("()", &["field.density="]).contains("the value after `=` is empty"));
        assert!(error("()", &["field..density=3"]).contains("is not a field path"));
        assert!(error("()", &["colliders[x].radius=3"]).contains("is not a field path"));
        // A value that would smuggle in another field or comment out the rest.
        let m = error("()", &["field.density=1, seed: 3"]);
        assert!(m.contains("is not a single RON value"), "{m}");
        let m = error("()", &["field.density=1 // x"]);
        assert!(m.contains("holds a comment"), "{m}");
        let m = error("()", &["field.height=(min: 1"]);
        assert!(m.contains("is not a single RON value"), "{m}");
        // A string with a comma or slashes is one value.
        let scene = set("()", &["terrain.density_map=\"a,b//c.png\""]).unwrap();
        assert_eq!(
            scene.terrain.density_map.as_deref(),
            Some("/scenes/a,b//c.png")
        );
    }

    #[test]
    fn image_paths_resolve_once_against_the_scene_directory() {
        let scene = set(
            "(terrain: (height: Png(path: \"h.png\", scale: 1)))",
            &["terrain.density_map=\"maps/d.png\"", "terrain.size=20"],
        )
        .unwrap();
        assert_eq!(
            scene.terrain.density_map.as_deref(),
            Some("/scenes/maps/d.png")
        );
        let HeightSource::Png { path, .. } = &scene.terrain.height else {
            panic!("png")
        };
        assert_eq!(path, "/scenes/h.png");
    }
}
