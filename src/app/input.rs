//! What the user is holding and dragging, fed by window events and by replayed scripts alike
//! (both arrive as [`super::replay::Event`]s), and turned into one [`CameraInput`] per frame.

use std::collections::HashSet;

use glam::Vec2;

use super::camera::CameraInput;
use super::replay::{Button, Event, Key};
use super::walker::WalkInput;

/// Held keys and buttons, the cursor, and the look/scroll deltas since the last frame.
#[derive(Debug, Default)]
pub struct InputState {
    held: HashSet<Key>,
    buttons: [bool; 3],
    /// Cursor in physical pixels, origin top-left; None before the first move.
    pub cursor: Option<Vec2>,
    look: Vec2,
    scroll: f32,
}

fn slot(b: Button) -> usize {
    match b {
        Button::Left => 0,
        Button::Right => 1,
        Button::Middle => 2,
    }
}

impl InputState {
    /// Updates the state; returns the cursor movement of a `CursorMoved` (zero otherwise).
    pub fn apply(&mut self, event: Event) -> Vec2 {
        match event {
            Event::CursorMoved(x, y) => {
                let p = Vec2::new(x, y);
                let delta = self.cursor.map_or(Vec2::ZERO, |c| p - c);
                self.cursor = Some(p);
                // Looking is a right-button drag, in fly and orbit modes alike.
                if self.buttons[1] {
                    self.look += delta;
                }
                delta
            }
            Event::Button(b, pressed) => {
                self.buttons[slot(b)] = pressed;
                Vec2::ZERO
            }
            Event::Key(k, true) => {
                self.held.insert(k);
                Vec2::ZERO
            }
            Event::Key(k, false) => {
                self.held.remove(&k);
                Vec2::ZERO
            }
            Event::Scroll(lines) => {
                self.scroll += lines;
                Vec2::ZERO
            }
        }
    }

    pub fn held(&self, key: Key) -> bool {
        self.held.contains(&key)
    }

    pub fn button(&self, b: Button) -> bool {
        self.buttons[slot(b)]
    }

    /// Forgets held keys and buttons (the window lost focus: their releases never come).
    pub fn release_all(&mut self) {
        self.held.clear();
        self.buttons = [false; 3];
    }

    /// Ctrl, by either of its names on the keyboard.
    pub fn ctrl(&self) -> bool {
        self.held(Key::Ctrl)
    }

    /// The arrow keys as a steering vector in screen terms: x right, y forward.
    pub fn steer(&self) -> Vec2 {
        let axis = |pos: Key, neg: Key| self.held(pos) as i32 as f32 - self.held(neg) as i32 as f32;
        Vec2::new(axis(Key::Right, Key::Left), axis(Key::Up, Key::Down))
    }

    /// The walker's controls (walk mode): W/S or ↑/↓ walk, A/D or ←/→ turn, Shift runs;
    /// nothing while Ctrl is down.
    pub fn walk(&self) -> WalkInput {
        if self.ctrl() {
            return WalkInput::default();
        }
        let axis = |pos: Key, neg: Key| self.held(pos) as i32 as f32 - self.held(neg) as i32 as f32;
        WalkInput {
            forward: (axis(Key::W, Key::S) + axis(Key::Up, Key::Down)).clamp(-1.0, 1.0),
            turn: (axis(Key::D, Key::A) + axis(Key::Right, Key::Left)).clamp(-1.0, 1.0),
            fast: self.held(Key::Shift),
        }
    }

    /// The camera's input for this frame; resets the look and scroll deltas. Held keys are
    /// ignored while Ctrl is down (Ctrl+S saves, it does not fly backwards).
    pub fn take_camera(&mut self) -> CameraInput {
        let axis = |pos: Key, neg: Key| self.held(pos) as i32 as f32 - self.held(neg) as i32 as f32;
        let moving = !self.ctrl();
        let input = CameraInput {
            forward: if moving { axis(Key::W, Key::S) } else { 0.0 },
            right: if moving { axis(Key::D, Key::A) } else { 0.0 },
            up: if moving { axis(Key::E, Key::Q) } else { 0.0 },
            fast: self.held(Key::Shift),
            look: self.look,
            scroll: self.scroll,
        };
        self.look = Vec2::ZERO;
        self.scroll = 0.0;
        input
    }

    /// Drops the look and scroll deltas (egui used them).
    pub fn discard_deltas(&mut self) {
        self.look = Vec2::ZERO;
        self.scroll = 0.0;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn right_drag_accumulates_look_and_left_drag_does_not() {
        let mut s = InputState::default();
        s.apply(Event::CursorMoved(10.0, 10.0));
        s.apply(Event::Button(Button::Left, true));
        s.apply(Event::CursorMoved(20.0, 10.0));
        assert_eq!(s.take_camera().look, Vec2::ZERO);
        s.apply(Event::Button(Button::Left, false));
        s.apply(Event::Button(Button::Right, true));
        s.apply(Event::CursorMoved(25.0, 13.0));
        s.apply(Event::CursorMoved(30.0, 12.0));
        assert_eq!(s.take_camera().look, Vec2::new(10.0, 2.0));
        // Taken: the next frame starts from zero.
        assert_eq!(s.take_camera().look, Vec2::ZERO);
    }

    #[test]
    fn keys_map_to_camera_axes_and_ctrl_suppresses_them() {
        let mut s = InputState::default();
        s.apply(Event::Key(Key::W, true));
        s.apply(Event::Key(Key::A, true));
        s.apply(Event::Key(Key::E, true));
        s.apply(Event::Key(Key::Shift, true));
        s.apply(Event::Scroll(2.0));
        let c = s.take_camera();
        assert_eq!((c.forward, c.right, c.up, c.fast), (1.0, -1.0, 1.0, true));
        assert_eq!(c.scroll, 2.0);
        s.apply(Event::Key(Key::Ctrl, true));
        let c = s.take_camera();
        assert_eq!((c.forward, c.right, c.up), (0.0, 0.0, 0.0));
        s.release_all();
        assert!(!s.held(Key::W) && !s.ctrl());
    }

    #[test]
    fn walking_reads_wasd_and_the_arrows_but_not_under_ctrl() {
        let mut s = InputState::default();
        s.apply(Event::Key(Key::W, true));
        s.apply(Event::Key(Key::Left, true));
        s.apply(Event::Key(Key::Shift, true));
        let w = s.walk();
        assert_eq!((w.forward, w.turn, w.fast), (1.0, -1.0, true));
        // W and ↑ together are no faster than one of them.
        s.apply(Event::Key(Key::Up, true));
        assert_eq!(s.walk().forward, 1.0);
        s.apply(Event::Key(Key::Ctrl, true));
        assert_eq!(s.walk(), WalkInput::default());
    }

    #[test]
    fn steering_follows_the_arrow_keys() {
        let mut s = InputState::default();
        s.apply(Event::Key(Key::Up, true));
        s.apply(Event::Key(Key::Left, true));
        assert_eq!(s.steer(), Vec2::new(-1.0, 1.0));
        s.apply(Event::Key(Key::Up, false));
        assert_eq!(s.steer(), Vec2::new(-1.0, 0.0));
    }
}
