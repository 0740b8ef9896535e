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
        let err =
            check_dump(Path::new("x.json"), (&[b], &[s]), (&[b, bad], &[s, s])).expect_err("NaN");
        let text = err.to_string();
        assert!(text.contains("x.json"), "{text}");
        assert!(text.contains("final blade 1"), "{text}");
        assert!(text.contains("non-finite v2"), "{text}");
        let mut s2 = s;
        s2.rest_eta[3] = f32::INFINITY;
        let text = check_finite("initial", &[b], &[s2])
            .expect_err("inf")
            .to_string();
        assert!(
            text.contains("initial blade 0 has a non-finite eta (inf)"),
            "{text}"
        );
    }

    #[test]
    fn an_absurd_but_finite_tip_is_reset_by_the_length_test() {
        use crate::sim::layout::SimParams;
        use crate::sim::reference::{blade_rest_pose, state_sound, update_blade, WindGrid};
        use glam::Vec3;
        let (b, s) = blade();
        // Its squared length overflows: the validation collapses the curve to a point.
        let mut absurd = b;
        absurd.v2_width[2] = 1e38;
        let params = SimParams {
            dt: 1.0 / 30.0,
            stiffness_scale: 1.0,
            max_eta: 2.0,
            ..Default::default()
        };
        let grid = WindGrid {
            velocity: &[[0.0; 2]],
        };
        let mut state = s;
        assert!(update_blade(&mut absurd, &mut state, &params, &[], &grid));
        let (v1, v2) = blade_rest_pose(&b, &s);
        assert_eq!(absurd.v1_height[..3], v1.to_array());
        assert_eq!(absurd.v2_width[..3], v2.to_array());
        assert_eq!(state.rest_eta[3], 0.0);
        // A sound blade stays: the same step from the rest pose resets nothing.
        let (mut sound, mut state) = (b, s);
        assert!(!update_blade(&mut sound, &mut state, &params, &[], &grid));
        // The test itself: a point-sized curve of a 0.5 m blade is absurd.
        let v0 = Vec3::ZERO;
        assert!(!state_sound(v0, v0, v0, 0.5, 0.0));
        assert!(state_sound(v0, Vec3::Y * 0.25, Vec3::Y * 0.5, 0.5, 0.0));
        assert!(!state_sound(
            v0,
            Vec3::Y * 0.25,
            Vec3::Y * 0.5,
            0.5,
            f32::NAN
        ));
    }

    #[test]
    fn the_resets_line_only_when_something_was_reset() {
        assert_eq!(resets_line(0), None);
        assert_eq!(resets_line(3).as_deref(), Some("reset 3 non-finite blades"));
    }
}
