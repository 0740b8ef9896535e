//! Every field of the scene with the values validation allows, as public data read from the
//! sections' `RULES` tables: what a property test (or a tool) needs to vary each field
//! without listing them by hand, so a field added with its rule is covered at once.

use super::allowed::{Allowed, Rule};

/// One field (a dotted path; `[]` stands for any element of a list) and what it may hold.
#[derive(Clone, Debug, PartialEq)]
pub struct FieldRule {
    /// The field's dotted path in a scene, e.g. `field.height` or `colliders[].radius`.
    pub path: &'static str,
    /// What the field may hold.
    pub kind: RuleKind,
}

/// The values a field may hold. Float bounds are given as numbers; whether an end is
/// included is the validation's business (a test probes both sides of each).
#[derive(Clone, Debug, PartialEq)]
pub enum RuleKind {
    /// A float in `low ..= high` (an end may be open).
    Real {
        /// Lower end of the interval.
        low: f32,
        /// Upper end of the interval.
        high: f32,
    },
    /// A `(min: .., max: ..)` range with both ends in `low ..= high` and `min <= max`.
    Range {
        /// Lowest value either end of the range may take.
        low: f32,
        /// Highest value either end of the range may take.
        high: f32,
    },
    /// An unsigned integer in `low ..= high`.
    Integer {
        /// Smallest allowed value (inclusive).
        low: u64,
        /// Largest allowed value (inclusive).
        high: u64,
    },
    /// A point or velocity `(x, y, z)` with every component in `low ..= high`.
    Vector {
        /// Lower end of every component's interval.
        low: f32,
        /// Upper end of every component's interval.
        high: f32,
    },
    /// A direction: finite components, not all zero.
    Direction,
    /// `true` or `false`.
    Bool,
    /// One of these variants or values, as written in a scene (`Jahrmann`, `4`); variants
    /// with fields are left out.
    Choice(Vec<String>),
    /// A structured value or a rule across fields, described in words.
    Other(&'static str),
}

fn bounds(a: &Allowed) -> (f32, f32) {
    a.bounds()
}

/// The bare names in a choice's description: `"one of A, B or C"` gives A, B and C; a
/// variant written with its fields (`Cwd(min: ..)`) and words after a value (`samples`)
/// are left out.
fn choices(text: &str) -> Vec<String> {
    let text = text.trim_start_matches("one of ");
    text.split(", ")
        .flat_map(|part| part.split(" or "))
        .filter_map(|part| {
            let word = part.split_whitespace().next()?;
            let bare = word.chars().all(|c| c.is_ascii_alphanumeric() || c == '_');
            (bare && !part.contains('(')).then(|| word.to_owned())
        })
        .collect()
}

/// Every field with a rule, in the order of the sections' tables.
pub fn field_rules() -> Vec<FieldRule> {
    super::all_rules()
        .map(|(path, rule)| FieldRule {
            path,
            kind: match rule {
                Rule::Real(a) => {
                    let (low, high) = bounds(&a);
                    RuleKind::Real { low, high }
                }
                Rule::Range(a) => {
                    let (low, high) = bounds(&a);
                    RuleKind::Range { low, high }
                }
                Rule::Vector(a) => {
                    let (low, high) = bounds(&a);
                    RuleKind::Vector { low, high }
                }
                Rule::Integer(i) => RuleKind::Integer {
                    low: i.low,
                    high: i.high,
                },
                Rule::Direction => RuleKind::Direction,
                Rule::Bool => RuleKind::Bool,
                Rule::Choice(text) => RuleKind::Choice(choices(text)),
                Rule::Text(text) => RuleKind::Other(text),
            },
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn choices_are_read_from_their_descriptions() {
        assert_eq!(
            choices("Jahrmann, Verlet or Cwd"),
            ["Jahrmann", "Verlet", "Cwd"]
        );
        assert_eq!(
            choices("one of Preetham, Gradient"),
            ["Preetham", "Gradient"]
        );
        assert_eq!(
            choices("Height, Cwd(min: .., max: .., c1: .., c2: ..) or Off"),
            ["Height", "Off"]
        );
        let rules = field_rules();
        let model = rules
            .iter()
            .find(|r| r.path == "physics.model")
            .expect("model");
        assert_eq!(
            model.kind,
            RuleKind::Choice(vec!["Jahrmann".into(), "Verlet".into(), "Cwd".into()])
        );
        assert!(rules.len() > 150, "{}", rules.len());
    }
}
