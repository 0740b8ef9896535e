//! Checks that blade data is sound before it leaves the program: `sward simulate` refuses to
//! write a dump holding a non-finite number, and says which blade and which field.
//! (The update itself never keeps a non-finite state: see `reference::state_sound`.)

use std::path::Path;

use super::layout::{Blade, BladeState};
use crate::error::{Error, Result};

/// The first non-finite value among a blade's fields: (field name, value).
pub fn first_non_finite(blade: &Blade, state: &BladeState) -> Option<(&'static str, f32)> {
    let fields: [(&'static str, &[f32]); 10] = [
        ("v0", &blade.v0_dir[..3]),
        ("direction", &blade.v0_dir[3..]),
        ("v1", &blade.v1_height[..3]),
        ("height", &blade.v1_height[3..]),
        ("v2", &blade.v2_width[..3]),
        ("width", &blade.v2_width[3..]),
        ("up", &blade.up_stiffness[..3]),
        ("stiffness", &blade.up_stiffness[3..]),
        ("rest tip", &state.rest_eta[..3]),
        ("eta", &state.rest_eta[3..]),
    ];
    fields
        .iter()
        .find_map(|(name, values)| values.iter().find(|v| !v.is_finite()).map(|&v| (*name, v)))
}

/// Fails with the first blade holding a non-finite number: `set` names the blades ("initial",
/// "final") in the message.
pub fn check_finite(set: &str, blades: &[Blade], states: &[BladeState]) -> Result<()> {
    for (i, (b, s)) in blades.iter().zip(states).enumerate() {
        if let Some((field, value)) = first_non_finite(b, s) {
            return Err(Error::Invalid(format!(
                "{set} blade {i} has a non-finite {field} ({value}); JSON cannot hold it"
            )));
        }
    }
    Ok(())
}

/// What `sward simulate` checks before writing `path`: every number of the initial and the
/// final blades finite. The error names the file, the blade and the field.
pub fn check_dump(
    path: &Path,
    initial: (&[Blade], &[BladeState]),
    last: (&[Blade], &[BladeState]),
) -> Result<()> {
    check_finite("initial", initial.0, initial.1)
        .and_then(|()| check_finite("final", last.0, last.1))
        .map_err(|e| Error::Write {
            path: path.to_path_buf(),
            message: format!("refusing to write a dump with non-finite numbers: {e}"),
        })
}

/// The line `sward simulate` prints on stderr when the update reset blades.
pub fn resets_line(resets: u64) -> Option<String> {
    (resets > 0).then(|| format!("reset {resets} non-finite blades"))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn blade() -> (Blade, BladeState) {
        (
            Blade {
                v0_dir: [0.0, 0.0, 0.0, 1.0],
                v1_height: [0.0, 0.5, 0.0, 0.5],
                v2_width: [0.0, 0.5, 0.0, 0.02],
                up_stiffness: [0.0, 1.0, 0.0, 1.0],
            },
            BladeState {
                rest_eta: [0.0, 0.5, 0.0, 0.0],
            },
        )
    }

    #[test]
    fn a_finite_dump_passes() {
        let (b, s) = blade();
        check_dump(Path::new("x.json"), (&[b], &[s]), (&[b, b], &[s, s])).expect("finite");
    }

    #[test]
    fn a_dump_with_nan_names_the_blade_and_field() {
        let (b, s) = blade();
        let mut bad = b;
        bad.v2_width[1] = f32::NAN;
        let err = check_dump(Path::new("x.json"), (&[b], &[s]), (&[b, bad], &[s, s]))
            .expect_err("NaN");
        let text = err.to_string();
        assert!(text.contains("x.json"), "{text}");
        assert!(text.contains("final blade 1"), "{text}");
        assert!(text.contains("non-finite v2"), "{text}");
        let mut s2 = s;
        s2.rest_eta[3] = f32::INFINITY;
        let text = check_finite("initial", &[b], &[s2])
            .expect_err("inf")
            .to_string();
        assert!(text.contains("initial blade 0 has a non-finite eta (inf)"), "{text}");
    }

    #[test]
    fn the_resets_line_only_when_something_was_reset() {
        assert_eq!(resets_line(0), None);
        assert_eq!(resets_line(3).as_deref(), Some("reset 3 non-finite blades"));
    }
}
