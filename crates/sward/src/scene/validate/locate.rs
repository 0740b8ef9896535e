//! Where a field is written in the scene text, and which field a position is in.
//!
//! serde does not keep positions for values, and a second spanned parse would be far more
//! code for the same result, so this is a small text scan over the RON with comments and
//! string contents masked out: [`locate`] goes from a field path (`colliders[1].radius`)
//! to its line and column, [`value_span`]/[`field_value`] to the bytes of its value (what
//! `--set` replaces), and [`enclosing_path`] the other way, from a parser error's position
//! to the path of the field it is in.

use std::ops::Range as Span;

/// Finds where `field` (a dotted path of keys, with `[i]` for array elements, e.g.
/// `field.height.min` or `colliders[1].motion.speed`) is written in the RON `text`, as a
/// 1-based `(line, column)` (column in characters).
///
/// Each key is searched only inside the value of the key before it, so `field.height` is
/// not confused with `terrain.height`; within that value the least nested occurrence wins
/// (so that `Some((..))` wrappers and enum variants are looked through, but a deeper key of
/// the same name is not taken). Comments and string contents are ignored. When a key is
/// not written (its value is the default) the position of the nearest enclosing key that
/// is written is returned, or `(1, 1)` if there is none.
pub(crate) fn locate(text: &str, field: &str) -> (usize, usize) {
    let code = mask(text);
    let walk = walk(&code, field);
    walk.found
        .map_or((1, 1), |offset| line_column(text, offset))
}

/// Where a walk down a field path got to in the masked text.
pub(crate) struct Walk {
    /// Offset of the deepest key or list element of the path that is written.
    pub(crate) found: Option<usize>,
    /// Span of that key's value (or of that element).
    pub(crate) region: Span<usize>,
    /// How many segments of the path were found (all of them: the field is written).
    pub(crate) segments: usize,
    /// Whether the last segment found lacked its `[i]` element (the list is shorter).
    pub(crate) missing_element: bool,
}

/// Follows `field` down the masked `code` as far as it is written (see [`locate`]).
pub(crate) fn walk(code: &[u8], field: &str) -> Walk {
    let mut walk = Walk {
        found: None,
        region: 0..code.len(),
        segments: 0,
        missing_element: false,
    };
    for segment in field.split('.') {
        let (name, index) = split_index(segment);
        let Some((key, value)) = find_key(code, walk.region.clone(), name) else {
            break;
        };
        walk.found = Some(key);
        walk.region = value_span(code, value, walk.region.end);
        if let Some(index) = index {
            let Some(element) = nth_element(code, walk.region.clone(), index) else {
                walk.missing_element = true;
                break;
            };
            walk.found = Some(element.start);
            walk.region = element;
        }
        walk.segments += 1;
    }
    walk
}

/// `name[3]` → (`name`, Some(3)); `name` → (`name`, None).
pub(crate) fn split_index(segment: &str) -> (&str, Option<usize>) {
    match segment.split_once('[') {
        Some((name, rest)) => (name, rest.trim_end_matches(']').parse::<usize>().ok()),
        None => (segment, None),
    }
}

/// The byte span of the value of `field` in `text`, if the field is written there.
pub(crate) fn field_value(text: &str, field: &str) -> Option<Span<usize>> {
    let code = mask(text);
    let walk = walk(&code, field);
    (walk.segments == field.split('.').count()).then_some(walk.region)
}

/// The path of the field (`colliders[1].motion.speed`) whose value contains byte `offset`
/// of `text`, or `""` outside every field. Wrappers without keys (`Some(..)`, an enum
/// variant's parentheses, a tuple) add nothing to the path, as in validation messages.
pub(crate) fn enclosing_path(text: &str, offset: usize) -> String {
    /// One open bracket: the key whose value is being read in it, or the list index.
    struct Frame {
        list: bool,
        key: Option<String>,
        index: usize,
    }
    let code = mask(text);
    let end = offset.min(code.len());
    let mut frames: Vec<Frame> = Vec::new();
    let mut i = 0;
    while i < end {
        let b = code[i];
        if is_ident(b) && (i == 0 || !is_ident(code[i - 1])) {
            let start = i;
            while i < code.len() && is_ident(code[i]) {
                i += 1;
            }
            let mut j = i;
            while j < code.len() && code[j].is_ascii_whitespace() {
                j += 1;
            }
            if code.get(j) == Some(&b':') && j < end {
                if let Some(frame) = frames.last_mut().filter(|f| !f.list) {
                    frame.key = Some(String::from_utf8_lossy(&code[start..i]).into_owned());
                }
                i = j + 1;
            }
            continue;
        }
        if is_open(b) {
            frames.push(Frame {
                list: b == b'[',
                key: None,
                index: 0,
            });
        } else if is_close(b) {
            frames.pop();
        } else if b == b',' {
            if let Some(frame) = frames.last_mut() {
                // The key's value ended at the comma: what follows belongs to the next key.
                frame.key = None;
                frame.index += 1;
            }
        }
        i += 1;
    }
    let mut path = String::new();
    for frame in &frames {
        if frame.list {
            path.push_str(&format!("[{}]", frame.index));
        } else if let Some(key) = &frame.key {
            if !path.is_empty() {
                path.push('.');
            }
            path.push_str(key);
        }
    }
    path
}

/// The path of the innermost field whose written value contains byte `offset` (see
/// [`enclosing_path`]), counting the end of the value as inside it if `end_inside` (`ron`
/// reports a bad number just after its last digit). A key whose value ended before
/// `offset` (a missing field, reported at the closing bracket of its struct) gives way to
/// the struct around it.
pub(crate) fn field_at(text: &str, offset: usize, end_inside: bool) -> String {
    let mut path = enclosing_path(text, offset);
    while !path.is_empty() {
        if let Some(span) = field_value(text, &path) {
            let end = if end_inside { span.end + 1 } else { span.end };
            if span.start <= offset && offset < end {
                break;
            }
        }
        path = match path.rfind(['.', '[']) {
            Some(cut) => path[..cut].to_owned(),
            None => String::new(),
        };
    }
    path
}

/// The keys and value spans of the struct written at `span` of the masked `code`: an
/// anonymous `(key: value, ..)`, a named one or enum variant `Name(key: value, ..)`. `None`
/// for anything else (a number, a tuple, a list, `Some(..)`: see [`inside_some`]).
pub(crate) fn struct_fields(code: &[u8], span: Span<usize>) -> Option<Vec<(String, Span<usize>)>> {
    let mut i = skip_space(code, span.start, span.end);
    while i < span.end && is_ident(code[i]) {
        i += 1;
    }
    if code.get(i) != Some(&b'(') || span.end == 0 || code[span.end - 1] != b')' {
        return None;
    }
    let inner_end = span.end - 1;
    let mut fields = Vec::new();
    let mut i = i + 1;
    loop {
        i = skip_space(code, i, inner_end);
        if i >= inner_end {
            return Some(fields);
        }
        let start = i;
        while i < inner_end && is_ident(code[i]) {
            i += 1;
        }
        let colon = skip_space(code, i, inner_end);
        if i == start || code.get(colon) != Some(&b':') {
            return None;
        }
        let key = String::from_utf8_lossy(&code[start..i]).into_owned();
        let value = value_span(code, colon + 1, inner_end);
        i = value.end + 1;
        fields.push((key, value));
    }
}

/// The span inside `Some(..)` if `span` of the masked `code` is one.
pub(crate) fn inside_some(code: &[u8], span: Span<usize>) -> Option<Span<usize>> {
    let text = &code[span.clone()];
    if !(text.starts_with(b"Some") && text.ends_with(b")")) {
        return None;
    }
    let open = skip_space(code, span.start + 4, span.end);
    (code.get(open) == Some(&b'(')).then(|| {
        let start = skip_space(code, open + 1, span.end - 1);
        start..value_span(code, start, span.end - 1).end
    })
}

/// The elements of the list written at `span` of the masked `code`, if it is one.
pub(crate) fn list_elements(code: &[u8], span: Span<usize>) -> Option<Vec<Span<usize>>> {
    if code.get(span.start) != Some(&b'[') {
        return None;
    }
    Some(
        (0..)
            .map_while(|n| nth_element(code, span.clone(), n))
            .collect(),
    )
}

fn skip_space(code: &[u8], mut i: usize, end: usize) -> usize {
    while i < end && code[i].is_ascii_whitespace() {
        i += 1;
    }
    i
}

/// The byte offset of 1-based `line` and `column` (in characters) in `text`, as `ron`
/// reports positions; the end of the text if it is past it.
pub(crate) fn offset_of(text: &str, line: usize, column: usize) -> usize {
    let mut offset = 0;
    for (n, l) in text.split_inclusive('\n').enumerate() {
        if n + 1 == line {
            return offset
                + l.char_indices()
                    .nth(column.saturating_sub(1))
                    .map_or(l.len(), |(b, _)| b);
        }
        offset += l.len();
    }
    text.len()
}

/// `text` as bytes with comments and the contents of strings replaced by spaces (newlines
/// kept), so that brackets, commas and keys inside them are not seen. Byte offsets are
/// unchanged.
pub(crate) fn mask(text: &str) -> Vec<u8> {
    let bytes = text.as_bytes();
    let mut code = bytes.to_vec();
    let len = bytes.len();
    let at = |i: usize, s: &[u8]| bytes[i..].starts_with(s);
    // A string keeps its quotes so that it still reads as a value (an empty one).
    let mut blank = |span: Span<usize>, quotes: bool| {
        let (first, last) = (span.start, span.end - 1);
        for (i, b) in code[span].iter_mut().enumerate() {
            if quotes && (first + i == first || first + i == last) {
                *b = b'"';
            } else if *b != b'\n' {
                *b = b' ';
            }
        }
    };
    let mut i = 0;
    while i < len {
        let start = i;
        if at(i, b"//") {
            i = bytes[i..]
                .iter()
                .position(|&b| b == b'\n')
                .map_or(len, |n| i + n);
        } else if at(i, b"/*") {
            // RON block comments nest.
            let mut depth = 0usize;
            while i < len {
                if at(i, b"/*") {
                    depth += 1;
                    i += 2;
                } else if at(i, b"*/") {
                    depth -= 1;
                    i += 2;
                    if depth == 0 {
                        break;
                    }
                } else {
                    i += 1;
                }
            }
        } else if bytes[i] == b'"' {
            i += 1;
            while i < len {
                match bytes[i] {
                    b'\\' => i += 2,
                    b'"' => {
                        i += 1;
                        break;
                    }
                    _ => i += 1,
                }
            }
        } else if bytes[i] == b'r' && (i == 0 || !is_ident(bytes[i - 1])) {
            // A raw string r"..." or r#"..."#: no escapes, ends at `"` plus as many `#`.
            let hashes = bytes[i + 1..].iter().take_while(|&&b| b == b'#').count();
            if bytes.get(i + 1 + hashes) != Some(&b'"') {
                i += 1;
                continue;
            }
            let mut close = vec![b'"'];
            close.extend(std::iter::repeat_n(b'#', hashes));
            i += 2 + hashes;
            while i < len && !at(i, &close) {
                i += 1;
            }
            i = (i + close.len()).min(len);
        } else {
            i += 1;
            continue;
        }
        blank(start..i.min(len), bytes[start] != b'/');
    }
    code
}

pub(crate) fn is_ident(b: u8) -> bool {
    b.is_ascii_alphanumeric() || b == b'_'
}

pub(crate) fn is_open(b: u8) -> bool {
    matches!(b, b'(' | b'[' | b'{')
}

pub(crate) fn is_close(b: u8) -> bool {
    matches!(b, b')' | b']' | b'}')
}

/// The least nested occurrence of `name:` as a key in `code[region]`: the offset of the key
/// and the offset just after its colon.
pub(crate) fn find_key(code: &[u8], region: Span<usize>, name: &str) -> Option<(usize, usize)> {
    let name = name.as_bytes();
    let mut depth = 0i32;
    let mut best: Option<(i32, usize, usize)> = None;
    for i in region.clone() {
        let b = code[i];
        if is_open(b) {
            depth += 1;
        } else if is_close(b) {
            depth -= 1;
        }
        if !code[i..region.end].starts_with(name) || (i > 0 && is_ident(code[i - 1])) {
            continue;
        }
        let mut j = i + name.len();
        if j < region.end && is_ident(code[j]) {
            continue;
        }
        while j < region.end && code[j].is_ascii_whitespace() {
            j += 1;
        }
        if j < region.end && code[j] == b':' && best.is_none_or(|(d, ..)| depth < d) {
            best = Some((depth, i, j + 1));
        }
    }
    best.map(|(_, key, value)| (key, value))
}

/// The span of the value that starts at (or after whitespace from) `start`: up to the comma
/// or closing bracket that ends it, at most up to `end`.
pub(crate) fn value_span(code: &[u8], start: usize, end: usize) -> Span<usize> {
    let mut i = start;
    while i < end && code[i].is_ascii_whitespace() {
        i += 1;
    }
    let first = i;
    let mut depth = 0usize;
    while i < end {
        let b = code[i];
        if is_open(b) {
            depth += 1;
        } else if is_close(b) {
            if depth == 0 {
                break;
            }
            depth -= 1;
        } else if b == b',' && depth == 0 {
            break;
        }
        i += 1;
    }
    first..i
}

/// The span of element `n` (0-based) of the first `[...]` list in `code[region]`.
pub(crate) fn nth_element(code: &[u8], region: Span<usize>, n: usize) -> Option<Span<usize>> {
    let open = region.start + code[region.clone()].iter().position(|&b| b == b'[')?;
    let mut depth = 0usize;
    let mut index = 0;
    let mut element: Option<usize> = None;
    for (i, &b) in code.iter().enumerate().take(region.end).skip(open + 1) {
        let ends_element = depth == 0 && (b == b',' || b == b']');
        if element.is_none() && !b.is_ascii_whitespace() && !ends_element {
            element = Some(i);
        }
        if ends_element {
            if let Some(start) = element.take() {
                if index == n {
                    return Some(start..i);
                }
                index += 1;
            }
            if b == b']' {
                return None;
            }
        } else if is_open(b) {
            depth += 1;
        } else if is_close(b) {
            depth = depth.saturating_sub(1);
        }
    }
    None
}

/// The 1-based line and column (in characters) of byte `offset` in `text`.
pub(crate) fn line_column(text: &str, offset: usize) -> (usize, usize) {
    let before = &text.as_bytes()[..offset.min(text.len())];
    let line_start = before
        .iter()
        .rposition(|&b| b == b'\n')
        .map_or(0, |n| n + 1);
    let line = 1 + before.iter().filter(|&&b| b == b'\n').count();
    // Count characters, not bytes: skip UTF-8 continuation bytes.
    let column = 1 + before[line_start..]
        .iter()
        .filter(|&&b| b & 0xC0 != 0x80)
        .count();
    (line, column)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn locate_finds_keys_inside_their_section() {
        let text = "(\n    field: (\n        density: -3,\n    ),\n)";
        assert_eq!(locate(text, "field.density"), (3, 9));
        assert_eq!(locate(text, "field"), (2, 5));

        // `height` is a key of both `terrain` and `field`.
        let text = "(\n terrain: (height: Noise(seed: 1, amplitude: 2, wavelength: 3, octaves: 4)),\n field: (height: (min: 0.1, max: 0.2)),\n)";
        assert_eq!(locate(text, "field.height.min"), (3, 19));
        assert_eq!(locate(text, "field.height.max"), (3, 29));
        assert_eq!(locate(text, "terrain.height.amplitude"), (2, 35));
        assert_eq!(locate(text, "terrain.height"), (2, 12));
    }

    #[test]
    fn locate_falls_back_to_the_enclosing_key() {
        let text = "(\n  terrain: (size: 4.0),\n  field: (\n    seed: 3,\n  ),\n)";
        // `density` took its default: report the `field` section.
        assert_eq!(locate(text, "field.density"), (3, 3));
        // `density` is written only in another section: still the `field` section.
        let text2 = "(\n  field: (),\n  physics: (mass: 1.0),\n)";
        assert_eq!(locate(text2, "field.mass"), (2, 3));
        // No `camera` section at all: the start of the file.
        assert_eq!(locate(text, "camera.near"), (1, 1));
        assert_eq!(locate("", "camera.near"), (1, 1));
    }

    #[test]
    fn locate_ignores_comments_and_strings() {
        let text = "( // field: (density: 1)\n  terrain: (density_map: \"field: (density: 2)\"),\n  /* field: /* nested */ density: 3 */\n  field: (density: 4),\n)";
        assert_eq!(locate(text, "field.density"), (4, 11));
        let text = "(terrain: (density_map: r#\"a\"b field:\"#), field: (density: 4))";
        assert_eq!(locate(text, "field.density"), (1, 51));
    }

    #[test]
    fn locate_finds_list_elements_and_looks_through_some() {
        let text = "(\n  colliders: [\n    (center: (0, 0, 0), radius: 1),\n    (\n      center: (1, 0, 0),\n      radius: -1,\n      motion: Path(points: [(0, 0)], speed: 1, looped: false),\n    ),\n  ],\n  wind: (directional: Some((\n    strength: -1,\n  ))),\n)";
        assert_eq!(locate(text, "colliders[0].radius"), (3, 25));
        assert_eq!(locate(text, "colliders[1].radius"), (6, 7));
        assert_eq!(locate(text, "colliders[1].motion.points"), (7, 20));
        assert_eq!(locate(text, "colliders[1].motion.speed"), (7, 38));
        // The element exists but does not write the key: the element itself.
        assert_eq!(locate(text, "colliders[0].motion"), (3, 5));
        // No such element: the list's key.
        assert_eq!(locate(text, "colliders[2].radius"), (2, 3));
        assert_eq!(locate(text, "wind.directional.strength"), (11, 5));
    }

    #[test]
    fn locate_prefers_the_least_nested_key_and_whole_words() {
        // `max` inside `field.height` must not be taken for `culling.max_distance`'s
        // neighbour, and `max_distance` must not match `max`.
        let text =
            "(culling: (max_distance: 5, distance_levels: 2), field: (height: (max: 1), max: 2))";
        assert_eq!(locate(text, "culling.max"), (1, 2));
        assert_eq!(locate(text, "field.max"), (1, 76));
    }

    #[test]
    fn line_column_counts_characters() {
        let text = "(\n  /* é */ field: ()\n)";
        assert_eq!(locate(text, "field"), (2, 11));
        assert_eq!(line_column("ab\ncd", 0), (1, 1));
        assert_eq!(line_column("ab\ncd", 4), (2, 2));
        assert_eq!(line_column("ab", 99), (1, 3));
    }

    #[test]
    fn enclosing_path_names_the_field_at_an_offset() {
        let text = "(\n  terrain: (resolution: 1e3, size: 4),\n  colliders: [\n    (center: (0, 0, 0)),\n    (radius: \"x\", motion: Velocity((1, NaN, 0))),\n  ],\n  wind: (point: Some((strength: -1))),\n)";
        let at = |needle: &str| enclosing_path(text, text.find(needle).unwrap());
        assert_eq!(at("1e3"), "terrain.resolution");
        assert_eq!(at("4)"), "terrain.size");
        assert_eq!(at("\"x\""), "colliders[1].radius");
        assert_eq!(at("NaN"), "colliders[1].motion");
        assert_eq!(at("-1"), "wind.point.strength");
        assert_eq!(enclosing_path(text, 0), "");
        assert_eq!(enclosing_path(text, 2), "");
    }

    #[test]
    fn field_values_and_offsets() {
        let text = "(\n  field: (density: 40, height: (min: 0.1, max: 0.2)),\n)";
        let span = field_value(text, "field.height.max").unwrap();
        assert_eq!(&text[span], "0.2");
        let span = field_value(text, "field.height").unwrap();
        assert_eq!(&text[span], "(min: 0.1, max: 0.2)");
        assert_eq!(field_value(text, "field.seed"), None);
        assert_eq!(offset_of(text, 2, 3), 4);
        assert_eq!(offset_of(text, 1, 1), 0);
        assert_eq!(offset_of(text, 9, 1), text.len());
        assert_eq!(offset_of("é:x", 1, 2), 2);
    }
}
