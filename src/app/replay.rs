//! Recorded input scripts: `sward --record FILE` writes the keys, buttons, cursor moves and
//! scrolls of a session with the frame each arrived on, and `sward --replay FILE` feeds
//! them back frame by frame, so that an interactive session (flying, editing arrows,
//! throwing balls) can be repeated exactly, e.g. under Xvfb in a test.
//!
//! A script is a RON list of steps; frames never decrease, and several steps may share a
//! frame (they are delivered in file order):
//!
//! ```ron
//! [
//!     (frame: 3, event: Key(Tab, true)),
//!     (frame: 5, event: CursorMoved(640.0, 360.0)),
//!     (frame: 6, event: Button(Left, true)),
//!     (frame: 9, event: Button(Left, false)),
//!     (frame: 10, event: Scroll(2.0)),
//! ]
//! ```
//!
//! Only the keys the window reacts to exist ([`Key`]); recording drops the others, so a
//! script never holds an event that replay could not deliver. Cursor positions are in
//! physical pixels of the window, scroll in lines (positive = away from the user).
//!
//! Errors read as `path:line:column: message` ([`Error::Scene`], the same form as scene
//! files): syntax errors and unknown names where `ron` reports them, out-of-order frames
//! and non-finite numbers at the offending step.

use std::path::Path;

use serde::{Deserialize, Serialize};

use sward::error::{Error, Result};
use sward::output::write_atomic;

/// The keys the window reacts to (camera flight, editor shortcuts, panels).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
pub enum Key {
    W,
    A,
    S,
    D,
    Q,
    E,
    Shift,
    Alt,
    Ctrl,
    Space,
    Up,
    Down,
    Left,
    Right,
    Tab,
    Delete,
    Escape,
    Enter,
    Z,
    Y,
    O,
    F,
    G,
    C,
    H,
    F1,
}

/// Mouse buttons.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
pub enum Button {
    Left,
    Right,
    Middle,
}

/// One input event. `bool`s are `true` for press, `false` for release.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub enum Event {
    /// Cursor position in physical pixels from the window's top-left corner.
    CursorMoved(f32, f32),
    Button(Button, bool),
    Key(Key, bool),
    /// Wheel movement in lines; positive scrolls up / away from the user.
    Scroll(f32),
}

/// An event and the frame (counted from 0 at start-up) it is delivered on.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Step {
    pub frame: u64,
    pub event: Event,
}

/// A whole script: steps in delivery order, frames non-decreasing.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Script {
    pub steps: Vec<Step>,
}

impl Script {
    /// Reads and checks the script at `path`.
    ///
    /// # Errors
    ///
    /// [`Error::Read`] naming `path` if it cannot be read; [`Error::Scene`] with the line and
    /// column of a syntax error, an unknown key or event, a frame smaller than the step
    /// before, or a non-finite coordinate or scroll.
    pub fn load(path: &Path) -> Result<Script> {
        let text = sward::input::read_text(path)?;
        Self::parse(&text, path)
    }

    /// Parses and checks script `text`; `path` names the file in errors and is not opened.
    ///
    /// # Errors
    ///
    /// As [`Script::load`], without the read error.
    pub fn parse(text: &str, path: &Path) -> Result<Script> {
        // Editors on Windows may save a byte-order mark, which `ron` rejects at 1:1.
        let text = text.strip_prefix('\u{feff}').unwrap_or(text);
        let steps: Vec<Step> =
            ron::Options::default()
                .from_str(text)
                .map_err(|e| Error::Scene {
                    path: path.to_path_buf(),
                    line: e.position.line,
                    column: e.position.col,
                    message: name_step(text, (e.position.line, e.position.col), &e.code),
                })?;
        let script = Script { steps };
        if let Some((index, message)) = script.first_problem() {
            // serde keeps no positions for values, so find the step in the text; the list
            // parsed, so the scan finds every element (1:1 is only a fallback).
            let (line, column) = step_positions(text).get(index).copied().unwrap_or((1, 1));
            return Err(Error::Scene {
                path: path.to_path_buf(),
                line,
                column,
                message,
            });
        }
        Ok(script)
    }

    /// The first step that breaks the rules, with a message naming the field.
    fn first_problem(&self) -> Option<(usize, String)> {
        for (i, step) in self.steps.iter().enumerate() {
            if i > 0 {
                let before = self.steps[i - 1].frame;
                if step.frame < before {
                    return Some((
                        i,
                        format!(
                            "steps[{i}].frame = {} is less than steps[{}].frame = {before}: \
                             frames must not decrease",
                            step.frame,
                            i - 1
                        ),
                    ));
                }
            }
            if !finite(&step.event) {
                return Some((
                    i,
                    format!(
                        "steps[{i}].event = {:?} is not finite: cursor coordinates and scroll \
                         must be finite numbers",
                        step.event
                    ),
                ));
            }
        }
        None
    }

    /// Writes the script as RON, one step per line, atomically (temporary file + rename).
    ///
    /// # Errors
    ///
    /// [`Error::Write`] naming `path` if it cannot be written; an existing file is unchanged
    /// then.
    pub fn save(&self, path: &Path) -> Result<()> {
        write_atomic(path, self.to_text(path)?.as_bytes())
    }

    /// The script as RON, one step per line (what [`Script::save`] writes); `path` names
    /// the file in errors.
    pub fn to_text(&self, path: &Path) -> Result<String> {
        let config = ron::ser::PrettyConfig::new()
            .struct_names(false)
            .compact_structs(true);
        let mut text =
            ron::ser::to_string_pretty(&self.steps, config).map_err(|e| Error::Write {
                path: path.to_path_buf(),
                message: format!("cannot write the script as RON: {e}"),
            })?;
        text.push('\n');
        Ok(text)
    }

    /// The frame of the last step (0 for an empty script): replay can stop after it.
    pub fn last_frame(&self) -> u64 {
        self.steps.last().map_or(0, |s| s.frame)
    }
}

/// What each field of a step allows, for parser errors.
const FRAME_ALLOWED: &str = "allowed a whole frame number 0..=18446744073709551615, not \
                             less than the step before";
const EVENT_ALLOWED: &str = "allowed CursorMoved(x, y), Button(Left|Right|Middle, true|false), \
                             Key(KEY, true|false) or Scroll(lines), with finite numbers";

/// A parser error's message with the step and the field it is in, and what that field
/// allows: `steps[1].frame: Integer is out of bounds: allowed …`. Errors outside every step
/// (a missing `[`) keep the parser's words.
fn name_step(text: &str, at: (usize, usize), code: &impl std::fmt::Display) -> String {
    let starts = step_positions(text);
    let Some(index) = starts.iter().rposition(|&p| p <= at) else {
        return format!("{code}: a script is a list of steps, [(frame: N, event: …), …]");
    };
    // The field is the last key written between the step's start and the error.
    let chars: Vec<(usize, usize, char)> = {
        let (mut line, mut column) = (1usize, 0usize);
        text.chars()
            .map(|c| {
                let here = if c == '\n' {
                    let h = (line, column + 1);
                    line += 1;
                    column = 0;
                    h
                } else {
                    column += 1;
                    (line, column)
                };
                (here.0, here.1, c)
            })
            .collect()
    };
    let inside: String = chars
        .iter()
        .filter(|&&(l, c, _)| (l, c) >= starts[index] && (l, c) <= at)
        .map(|&(_, _, ch)| ch)
        .collect();
    let frame = inside.rfind("frame");
    let event = inside.rfind("event");
    let message = code.to_string();
    // Unknown and missing keys are about the step as a whole.
    let whole_step = message.contains("field named");
    match (frame, event) {
        (Some(f), e) if e.is_none_or(|e| f > e) && !whole_step => {
            format!("steps[{index}].frame: {message}: {FRAME_ALLOWED}")
        }
        (_, Some(_)) if !whole_step => {
            format!("steps[{index}].event: {message}: {EVENT_ALLOWED}")
        }
        _ => format!(
            "steps[{index}]: {message}: a step is (frame: N, event: E); frame {FRAME_ALLOWED}; \
             event {EVENT_ALLOWED}"
        ),
    }
}

fn finite(event: &Event) -> bool {
    match *event {
        Event::CursorMoved(x, y) => x.is_finite() && y.is_finite(),
        Event::Scroll(s) => s.is_finite(),
        Event::Button(..) | Event::Key(..) => true,
    }
}

/// The 1-based (line, column) where each element of the top-level RON list in `text`
/// begins (column in characters, as `ron` counts). Comments, strings and `#![..]`
/// attributes are skipped; only nesting depth matters, so any element syntax works.
fn step_positions(text: &str) -> Vec<(usize, usize)> {
    let mut positions = Vec::new();
    let (mut line, mut column) = (1usize, 0usize);
    let mut depth = 0usize;
    let mut in_attribute = false;
    let mut in_list = false;
    let mut expecting = false;
    let mut chars = text.chars().peekable();
    // Advances the position over one character.
    let step = |c: char, line: &mut usize, column: &mut usize| {
        if c == '\n' {
            *line += 1;
            *column = 0;
        } else {
            *column += 1;
        }
    };
    while let Some(c) = chars.next() {
        step(c, &mut line, &mut column);
        match c {
            '/' if chars.peek() == Some(&'/') => {
                // Line comment: up to (not including) the newline.
                while let Some(&n) = chars.peek() {
                    if n == '\n' {
                        break;
                    }
                    step(n, &mut line, &mut column);
                    chars.next();
                }
            }
            '/' if chars.peek() == Some(&'*') => {
                // Block comment; RON nests them.
                let mut nesting = 0usize;
                let mut prev = c;
                for n in chars.by_ref() {
                    step(n, &mut line, &mut column);
                    if prev == '/' && n == '*' {
                        nesting += 1;
                        prev = ' ';
                        continue;
                    }
                    if prev == '*' && n == '/' {
                        nesting -= 1;
                        if nesting == 0 {
                            break;
                        }
                        prev = ' ';
                        continue;
                    }
                    prev = n;
                }
            }
            '"' => {
                if depth == 1 && in_list && expecting {
                    positions.push((line, column));
                    expecting = false;
                }
                let mut escaped = false;
                for n in chars.by_ref() {
                    step(n, &mut line, &mut column);
                    match n {
                        '\\' if !escaped => escaped = true,
                        '"' if !escaped => break,
                        _ => escaped = false,
                    }
                }
            }
            '#' if depth == 0 => in_attribute = true,
            c if c.is_whitespace() => {}
            '(' | '[' | '{' => {
                if depth == 1 && in_list && expecting {
                    positions.push((line, column));
                    expecting = false;
                }
                if depth == 0 && c == '[' && !in_attribute {
                    in_list = true;
                    expecting = true;
                }
                depth += 1;
            }
            ')' | ']' | '}' => {
                depth = depth.saturating_sub(1);
                if depth == 0 {
                    if in_attribute {
                        in_attribute = false;
                    } else if in_list {
                        break;
                    }
                }
            }
            ',' if depth == 1 && in_list => expecting = true,
            _ => {
                if depth == 1 && in_list && expecting {
                    positions.push((line, column));
                    expecting = false;
                }
            }
        }
    }
    positions
}

/// Delivers a script's events frame by frame.
#[derive(Clone, Debug)]
pub struct Player {
    script: Script,
    /// Index of the next step not yet delivered.
    next: usize,
}

impl Player {
    pub fn new(script: Script) -> Self {
        Self { script, next: 0 }
    }

    /// Every step with `step.frame <= frame` not yet returned, in script order. A frame the
    /// caller skipped (a slow frame counts once) delivers its steps on the next call, so no
    /// event is lost or repeated.
    pub fn due(&mut self, frame: u64) -> Vec<Event> {
        let steps = &self.script.steps[self.next..];
        let count = steps.iter().take_while(|s| s.frame <= frame).count();
        self.next += count;
        steps[..count].iter().map(|s| s.event).collect()
    }

    /// Whether every step has been delivered.
    pub fn finished(&self) -> bool {
        self.next >= self.script.steps.len()
    }

    /// The script being played.
    pub fn script(&self) -> &Script {
        &self.script
    }
}

/// Collects a session's events into a [`Script`].
#[derive(Clone, Debug, Default)]
pub struct Recorder {
    steps: Vec<Step>,
}

impl Recorder {
    pub fn new() -> Self {
        Self::default()
    }

    /// Records `event` on `frame`. A cursor move directly after another in the same frame
    /// replaces it: only where the cursor was when the frame ran matters, and a fast mouse
    /// sends dozens per frame. So that the recording always loads again, a frame smaller
    /// than the last recorded one is raised to it, and a non-finite coordinate or scroll is
    /// dropped.
    pub fn push(&mut self, frame: u64, event: Event) {
        if !finite(&event) {
            return;
        }
        let frame = frame.max(self.steps.last().map_or(0, |s| s.frame));
        if let (Event::CursorMoved(..), Some(last)) = (event, self.steps.last_mut()) {
            if last.frame == frame && matches!(last.event, Event::CursorMoved(..)) {
                last.event = event;
                return;
            }
        }
        self.steps.push(Step { frame, event });
    }

    /// The steps recorded so far.
    pub fn script(&self) -> Script {
        Script {
            steps: self.steps.clone(),
        }
    }
}

/// The script key for a physical key, `None` for keys the window ignores. Both Shift, Alt
/// and Ctrl keys map to one modifier each; the keypad's Enter is Enter.
pub fn key_from_winit(code: winit::keyboard::KeyCode) -> Option<Key> {
    use winit::keyboard::KeyCode as K;
    Some(match code {
        K::KeyW => Key::W,
        K::KeyA => Key::A,
        K::KeyS => Key::S,
        K::KeyD => Key::D,
        K::KeyQ => Key::Q,
        K::KeyE => Key::E,
        K::ShiftLeft | K::ShiftRight => Key::Shift,
        K::AltLeft | K::AltRight => Key::Alt,
        K::ControlLeft | K::ControlRight => Key::Ctrl,
        K::Space => Key::Space,
        K::ArrowUp => Key::Up,
        K::ArrowDown => Key::Down,
        K::ArrowLeft => Key::Left,
        K::ArrowRight => Key::Right,
        K::Tab => Key::Tab,
        K::Delete => Key::Delete,
        K::Escape => Key::Escape,
        K::Enter | K::NumpadEnter => Key::Enter,
        K::KeyZ => Key::Z,
        K::KeyY => Key::Y,
        K::KeyO => Key::O,
        K::KeyF => Key::F,
        K::KeyG => Key::G,
        K::KeyC => Key::C,
        K::KeyH => Key::H,
        K::F1 => Key::F1,
        _ => return None,
    })
}

impl Key {
    /// The egui key, for feeding replayed keys to egui. Modifiers are not keys in egui (they
    /// travel as `egui::Modifiers` with every event), so Shift, Alt and Ctrl give `None`.
    pub fn to_egui(self) -> Option<egui::Key> {
        use egui::Key as E;
        Some(match self {
            Key::W => E::W,
            Key::A => E::A,
            Key::S => E::S,
            Key::D => E::D,
            Key::Q => E::Q,
            Key::E => E::E,
            Key::Shift | Key::Alt | Key::Ctrl => return None,
            Key::Space => E::Space,
            Key::Up => E::ArrowUp,
            Key::Down => E::ArrowDown,
            Key::Left => E::ArrowLeft,
            Key::Right => E::ArrowRight,
            Key::Tab => E::Tab,
            Key::Delete => E::Delete,
            Key::Escape => E::Escape,
            Key::Enter => E::Enter,
            Key::Z => E::Z,
            Key::Y => E::Y,
            Key::O => E::O,
            Key::F => E::F,
            Key::G => E::G,
            Key::C => E::C,
            Key::H => E::H,
            Key::F1 => E::F1,
        })
    }
}

impl Button {
    /// The egui pointer button (egui names them by role: left = primary).
    pub fn to_egui(self) -> egui::PointerButton {
        match self {
            Button::Left => egui::PointerButton::Primary,
            Button::Right => egui::PointerButton::Secondary,
            Button::Middle => egui::PointerButton::Middle,
        }
    }

    /// The script button for a winit button, `None` for the extra buttons the window ignores.
    pub fn from_winit(button: winit::event::MouseButton) -> Option<Button> {
        use winit::event::MouseButton as M;
        match button {
            M::Left => Some(Button::Left),
            M::Right => Some(Button::Right),
            M::Middle => Some(Button::Middle),
            M::Back | M::Forward | M::Other(_) => None,
        }
    }
}

#[cfg(test)]
mod tests {
    use std::path::PathBuf;

    use super::*;

    const EXAMPLE: &str = "[
    (frame: 3, event: Key(Tab, true)),
    (frame: 5, event: CursorMoved(640.0, 360.0)),
    (frame: 6, event: Button(Left, true)),
    (frame: 9, event: Button(Left, false)),
    (frame: 10, event: Scroll(2.0)),
]
";

    fn parse(text: &str) -> Result<Script> {
        Script::parse(text, Path::new("/scripts/test.ron"))
    }

    /// The (line, column, message) of a script error, panicking on anything else.
    fn script_error(text: &str) -> (usize, usize, String) {
        match parse(text) {
            Err(Error::Scene {
                path,
                line,
                column,
                message,
            }) => {
                assert_eq!(path, Path::new("/scripts/test.ron"));
                (line, column, message)
            }
            other => panic!("expected a script error, got {other:?}"),
        }
    }

    fn example() -> Script {
        Script {
            steps: vec![
                Step {
                    frame: 3,
                    event: Event::Key(Key::Tab, true),
                },
                Step {
                    frame: 5,
                    event: Event::CursorMoved(640.0, 360.0),
                },
                Step {
                    frame: 6,
                    event: Event::Button(Button::Left, true),
                },
                Step {
                    frame: 9,
                    event: Event::Button(Button::Left, false),
                },
                Step {
                    frame: 10,
                    event: Event::Scroll(2.0),
                },
            ],
        }
    }

    #[test]
    fn example_parses() {
        let script = parse(EXAMPLE).expect("parse");
        assert_eq!(script, example());
        assert_eq!(script.last_frame(), 10);
        assert_eq!(parse("[]").expect("empty").last_frame(), 0);
        // Comments, a byte-order mark, a trailing-comma-free list and struct names are fine.
        let text = "\u{feff}// recorded\n[ /* one */ Step(frame: 1, event: Scroll(-1.5)) ]";
        assert_eq!(
            parse(text).expect("parse").steps[0].event,
            Event::Scroll(-1.5)
        );
    }

    #[test]
    fn bad_scripts_name_the_line() {
        // An unknown key: ron reports where the name is.
        let text = EXAMPLE.replace("Key(Tab, true)", "Key(Tabb, true)");
        let (line, _, message) = script_error(&text);
        assert_eq!(line, 2, "{message}");
        assert!(message.contains("Tabb"), "{message}");

        // A frame smaller than the one before: the offending step's line and column.
        let text = EXAMPLE.replace("frame: 9,", "frame: 4,");
        let (line, column, message) = script_error(&text);
        assert_eq!((line, column), (5, 5), "{message}");
        assert_eq!(
            message,
            "steps[3].frame = 4 is less than steps[2].frame = 6: frames must not decrease"
        );
        let shown = parse(&text).expect_err("bad").to_string();
        assert!(
            shown.starts_with("/scripts/test.ron:5:5: steps[3].frame"),
            "{shown}"
        );

        // NaN and infinity, including steps split over lines and after comments.
        let text = EXAMPLE.replace("CursorMoved(640.0, 360.0)", "CursorMoved(NaN, 360.0)");
        let (line, _, message) = script_error(&text);
        assert_eq!(line, 3, "{message}");
        assert!(
            message.starts_with("steps[1].event = CursorMoved(NaN, 360.0)"),
            "{message}"
        );
        let text = "[\n  // a comment with ( and [\n  (frame: 0, event: Key(W, true)),\n  (\n    \
                    frame: 1,\n    event: Scroll(inf),\n  ),\n]";
        let (line, column, message) = script_error(text);
        assert_eq!((line, column), (4, 3), "{message}");
        assert!(message.contains("steps[1].event"), "{message}");

        // Unknown fields and syntax errors come from ron with their line.
        let (line, _, message) = script_error("[\n (frame: 1, event: Scroll(1.0), extra: 2),\n]");
        assert_eq!(line, 2, "{message}");
        let (line, _, _) = script_error("[\n (frame: 1, event: Scroll(1.0))\n (frame: 2)\n]");
        assert_eq!(line, 3);
    }

    #[test]
    fn positions_skip_attributes_strings_and_comments() {
        let text = "#![enable(implicit_some)]\n[ /* ( [ */ (a: \"(\"), \"x,\", (b: [1, 2]),\n1]";
        assert_eq!(step_positions(text), [(2, 13), (2, 23), (2, 29), (3, 1)]);
    }

    #[test]
    fn save_load_round_trip() {
        let dir = std::env::temp_dir().join(format!("sward-replay-{}", std::process::id()));
        std::fs::create_dir_all(&dir).expect("mkdir");
        let path: PathBuf = dir.join("session.ron");
        let mut script = example();
        script.steps.push(Step {
            frame: 10,
            event: Event::CursorMoved(-3.25, 1e-3),
        });
        script.save(&path).expect("save");
        let text = std::fs::read_to_string(&path).expect("read");
        let back = Script::load(&path);
        let missing = Script::load(&dir.join("missing.ron"));
        let unwritable = example().save(&dir.join("no/such/dir.ron"));
        std::fs::remove_dir_all(&dir).expect("clean up");
        assert_eq!(back.expect("load"), script, "{text}");
        // One step per line, the form of the module docs.
        assert!(text.starts_with(&EXAMPLE[..EXAMPLE.len() - 3]), "{text}");
        assert!(matches!(missing, Err(Error::Read { .. })));
        assert!(matches!(unwritable, Err(Error::Write { .. })));
    }

    #[test]
    fn player_delivers_each_event_once_in_order() {
        let mut script = example();
        // Three events on frame 6.
        script.steps.insert(
            3,
            Step {
                frame: 6,
                event: Event::Key(Key::Alt, true),
            },
        );
        script.steps.insert(
            4,
            Step {
                frame: 6,
                event: Event::Key(Key::Alt, false),
            },
        );
        let all: Vec<Event> = script.steps.iter().map(|s| s.event).collect();
        let mut player = Player::new(script);
        let mut seen = Vec::new();
        let mut per_frame = Vec::new();
        for frame in 0..=4 {
            let due = player.due(frame);
            per_frame.push(due.len());
            seen.extend(due);
        }
        assert_eq!(per_frame, [0, 0, 0, 1, 0]);
        assert!(player.due(4).is_empty(), "nothing twice");
        // Frame 5 skipped: its step arrives with frame 6's three.
        let due = player.due(6);
        assert_eq!(due.len(), 4);
        seen.extend(due);
        assert!(!player.finished());
        seen.extend(player.due(100));
        assert!(player.finished());
        assert!(player.due(101).is_empty());
        assert_eq!(seen, all);
    }

    #[test]
    fn recorder_collapses_moves_within_a_frame() {
        let mut r = Recorder::new();
        r.push(1, Event::CursorMoved(1.0, 1.0));
        r.push(1, Event::CursorMoved(2.0, 2.0));
        r.push(1, Event::CursorMoved(3.0, 3.0));
        r.push(1, Event::Button(Button::Left, true));
        r.push(1, Event::CursorMoved(4.0, 4.0));
        r.push(2, Event::CursorMoved(5.0, 5.0));
        r.push(2, Event::CursorMoved(6.0, 6.0));
        r.push(2, Event::Scroll(f32::NAN)); // dropped: it would not load again
        r.push(1, Event::Key(Key::W, true)); // late: raised to frame 2
        let steps = r.script().steps;
        let events: Vec<(u64, Event)> = steps.iter().map(|s| (s.frame, s.event)).collect();
        assert_eq!(
            events,
            [
                (1, Event::CursorMoved(3.0, 3.0)),
                (1, Event::Button(Button::Left, true)),
                (1, Event::CursorMoved(4.0, 4.0)),
                (2, Event::CursorMoved(6.0, 6.0)),
                (2, Event::Key(Key::W, true)),
            ]
        );
        assert!(r.script().first_problem().is_none());
    }

    #[test]
    fn keys_and_buttons_map_to_winit_and_egui() {
        use winit::keyboard::KeyCode;
        assert_eq!(key_from_winit(KeyCode::KeyW), Some(Key::W));
        assert_eq!(key_from_winit(KeyCode::ShiftRight), Some(Key::Shift));
        assert_eq!(key_from_winit(KeyCode::ControlLeft), Some(Key::Ctrl));
        assert_eq!(key_from_winit(KeyCode::ArrowLeft), Some(Key::Left));
        assert_eq!(key_from_winit(KeyCode::NumpadEnter), Some(Key::Enter));
        assert_eq!(key_from_winit(KeyCode::KeyX), None);
        assert_eq!(Key::Up.to_egui(), Some(egui::Key::ArrowUp));
        assert_eq!(Key::F1.to_egui(), Some(egui::Key::F1));
        assert_eq!(Key::Alt.to_egui(), None);
        assert_eq!(Button::Left.to_egui(), egui::PointerButton::Primary);
        assert_eq!(
            Button::from_winit(winit::event::MouseButton::Right),
            Some(Button::Right)
        );
        assert_eq!(Button::from_winit(winit::event::MouseButton::Back), None);
        // Every script key that is not a modifier reaches egui, and comes from some winit key.
        let all = [
            Key::W,
            Key::A,
            Key::S,
            Key::D,
            Key::Q,
            Key::E,
            Key::Shift,
            Key::Alt,
            Key::Ctrl,
            Key::Space,
            Key::Up,
            Key::Down,
            Key::Left,
            Key::Right,
            Key::Tab,
            Key::Delete,
            Key::Escape,
            Key::Enter,
            Key::Z,
            Key::Y,
            Key::O,
            Key::F,
            Key::G,
            Key::C,
            Key::H,
            Key::F1,
        ];
        let modifiers = [Key::Shift, Key::Alt, Key::Ctrl];
        for k in all {
            assert_eq!(k.to_egui().is_none(), modifiers.contains(&k), "{k:?}");
        }
        let winit_keys = [
            KeyCode::KeyW,
            KeyCode::KeyA,
            KeyCode::KeyS,
            KeyCode::KeyD,
            KeyCode::KeyQ,
            KeyCode::KeyE,
            KeyCode::ShiftLeft,
            KeyCode::AltLeft,
            KeyCode::ControlRight,
            KeyCode::Space,
            KeyCode::ArrowUp,
            KeyCode::ArrowDown,
            KeyCode::ArrowLeft,
            KeyCode::ArrowRight,
            KeyCode::Tab,
            KeyCode::Delete,
            KeyCode::Escape,
            KeyCode::Enter,
            KeyCode::KeyZ,
            KeyCode::KeyY,
            KeyCode::KeyO,
            KeyCode::KeyF,
            KeyCode::KeyG,
            KeyCode::KeyC,
            KeyCode::KeyH,
            KeyCode::F1,
        ];
        let mapped: Vec<Option<Key>> = winit_keys.into_iter().map(key_from_winit).collect();
        assert_eq!(mapped, all.map(Some));
    }
}
