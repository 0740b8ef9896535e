//! Scene files: what `sward render` / `sward simulate` draw and simulate, written in
//! [RON](https://github.com/ron-rs/ron).
//!
//! Every field has a default, so a scene states only what it changes; `()` is a valid scene.
//! A scene is loaded in two steps, and both report errors as `path:line:column: message`
//! ([`crate::Error::Scene`]) so that the user knows where to look:
//!
//! 1. parsing ([`parse_scene`]): syntax errors, unknown fields (a typo such as `densty` is
//!    rejected, not silently ignored) and wrong types, at the position RON reports;
//! 2. validation: every number must be finite and in its documented range (the ranges are
//!    listed in the `validate` module and repeated in each error message). Validation also
//!    normalises direction vectors and resolves relative image paths against the scene
//!    file's directory, so that later stages can use the values as they are.
//!
//! Scripts can change fields without editing the file: [`parse_scene_with_sets`] /
//! [`load_scene_with_sets`] apply `PATH=VALUE` arguments (`field.density=40`), validated
//! like the file.
//!
//! `Some(...)` around optional values may be omitted (RON's `implicit_some` extension is
//! on), e.g. `wind: (directional: (strength: 3.0), point: None)`.
//!
//! ```ron
//! (
//!     terrain: (size: 60.0, height: Noise(seed: 3, amplitude: 4.0, wavelength: 25.0, octaves: 5)),
//!     field: (density: 120.0, height: (min: 0.3, max: 0.9), shape: Quadratic),
//!     colliders: [(center: (0.0, 0.5, 0.0), radius: 0.5, motion: Path(points: [(-10.0, 0.0), (10.0, 0.0)], speed: 2.0, looped: false))],
//!     camera: (eye: (-9.0, 4.0, 13.0), target: (0.0, 0.0, 0.0)),
//! )
//! ```

pub mod limits;
mod load;
mod origin;
pub mod save;
mod set;
pub mod types;
mod validate;

pub use load::{load_scene, parse_scene};
pub use origin::Origin;
pub use set::{load_scene_with_sets, parse_scene_with_sets};
pub use types::*;
pub use validate::{field_rules, FieldRule, RuleKind};
