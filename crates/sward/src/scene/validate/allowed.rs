//! What a field may hold, as data: [`Allowed`] intervals of floats, [`Integers`] ranges and
//! the [`Rule`] of every field, each written once as a constant next to the check that uses
//! it and listed in its section's `RULES` table. The table is what parser errors and
//! `--set` errors quote (see [`super::allowed_for`]), so a range is stated in one place.

/// One end of an allowed interval.
#[derive(Clone, Copy, Debug)]
pub(crate) enum Bound {
    Inclusive(f32),
    Exclusive(f32),
}

/// The allowed interval of a float field, with the unit shown in messages. Every interval
/// is finite: an unbounded force or length is how NaN blades got in (a strength of 1e38
/// overflows the first step of the update).
#[derive(Clone, Copy, Debug)]
pub(crate) struct Allowed {
    low: Bound,
    high: Bound,
    unit: &'static str,
}

impl Allowed {
    /// `low <= x <= high`
    pub(crate) const fn closed(low: f32, high: f32, unit: &'static str) -> Self {
        Self {
            low: Bound::Inclusive(low),
            high: Bound::Inclusive(high),
            unit,
        }
    }
    /// `low < x <= high`
    pub(crate) const fn open_closed(low: f32, high: f32, unit: &'static str) -> Self {
        Self {
            low: Bound::Exclusive(low),
            high: Bound::Inclusive(high),
            unit,
        }
    }
    /// `low <= x < high`
    pub(crate) const fn closed_open(low: f32, high: f32, unit: &'static str) -> Self {
        Self {
            low: Bound::Inclusive(low),
            high: Bound::Exclusive(high),
            unit,
        }
    }
    /// `low < x < high`
    pub(crate) const fn open(low: f32, high: f32, unit: &'static str) -> Self {
        Self {
            low: Bound::Exclusive(low),
            high: Bound::Exclusive(high),
            unit,
        }
    }

    /// The interval's two ends as numbers (open or closed alike).
    pub(crate) fn bounds(&self) -> (f32, f32) {
        let value = |b: Bound| match b {
            Bound::Inclusive(v) | Bound::Exclusive(v) => v,
        };
        (value(self.low), value(self.high))
    }

    pub(crate) fn contains(&self, x: f32) -> bool {
        let above_low = match self.low {
            Bound::Inclusive(low) => x >= low,
            Bound::Exclusive(low) => x > low,
        };
        let below_high = match self.high {
            Bound::Inclusive(high) => x <= high,
            Bound::Exclusive(high) => x < high,
        };
        above_low && below_high
    }

    /// E.g. `0 < density <= 10000 blades/m²`.
    pub(crate) fn describe(&self, name: &str) -> String {
        let low = match self.low {
            Bound::Inclusive(v) => format!("{v} <="),
            Bound::Exclusive(v) => format!("{v} <"),
        };
        let high = match self.high {
            Bound::Inclusive(v) => format!("<= {v}"),
            Bound::Exclusive(v) => format!("< {v}"),
        };
        with_unit(format!("{low} {name} {high}"), self.unit)
    }
}

/// The allowed range of an integer field, both ends included.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Integers {
    pub(crate) low: u64,
    pub(crate) high: u64,
    pub(crate) unit: &'static str,
}

impl Integers {
    pub(crate) const fn new(low: u64, high: u64, unit: &'static str) -> Self {
        Self { low, high, unit }
    }

    /// E.g. `2 <= resolution <= 4097 vertices per side`.
    pub(crate) fn describe(&self, name: &str) -> String {
        with_unit(
            format!("{} <= {name} <= {}", self.low, self.high),
            self.unit,
        )
    }
}

/// What one field of the scene may hold.
#[derive(Clone, Copy, Debug)]
pub(crate) enum Rule {
    /// A float in an interval.
    Real(Allowed),
    /// A [`crate::scene::Range`]: both ends in the interval, `min <= max`.
    Range(Allowed),
    /// An unsigned integer in a range.
    Integer(Integers),
    /// A point or velocity: every component in the interval.
    Vector(Allowed),
    /// A direction: finite components, not all zero (normalised on load).
    Direction,
    Bool,
    /// One of the listed enum variants (or a fixed description of the accepted forms).
    Choice(&'static str),
    /// A rule that depends on other fields or is not an interval, described in words.
    Text(&'static str),
}

impl Rule {
    /// The allowed values of the field at `path`, as messages quote them after "allowed".
    pub(crate) fn describe(&self, path: &str) -> String {
        let name = short_name(path);
        match self {
            Rule::Real(a) => a.describe(&name),
            Rule::Range(a) => {
                if name.ends_with(".min") || name.ends_with(".max") {
                    format!("{} (and min <= max)", a.describe(&name))
                } else {
                    format!(
                        "(min: .., max: ..) with {} and min <= max",
                        a.describe("each")
                    )
                }
            }
            Rule::Integer(i) => i.describe(&name),
            Rule::Vector(a) => format!("{} for every component", a.describe(&name)),
            Rule::Direction => {
                "a non-zero direction of finite numbers (normalised on load)".to_owned()
            }
            Rule::Bool => "true or false".to_owned(),
            Rule::Choice(text) | Rule::Text(text) => (*text).to_owned(),
        }
    }
}

fn with_unit(mut text: String, unit: &str) -> String {
    if !unit.is_empty() {
        text.push(' ');
        text.push_str(unit);
    }
    text
}

/// The name a range message uses for a field: its last key (`density`), or the last two
/// for the parts of a [`crate::scene::Range`] (`height.min`), without array indices.
pub(crate) fn short_name(field: &str) -> String {
    let strip = |s: &str| s.split('[').next().unwrap_or(s).to_owned();
    let mut keys = field.rsplit('.');
    let last = strip(keys.next().unwrap_or(field));
    match keys.next() {
        Some(parent) if last == "min" || last == "max" => format!("{}.{last}", strip(parent)),
        _ => last,
    }
}

/// `field` with every array index replaced by `[]` (`colliders[2].radius` →
/// `colliders[].radius`), the form the rule tables use.
pub(crate) fn generic_path(field: &str) -> String {
    let mut out = String::with_capacity(field.len());
    let mut in_index = false;
    for c in field.chars() {
        match c {
            '[' => {
                in_index = true;
                out.push('[');
            }
            ']' => {
                in_index = false;
                out.push(']');
            }
            _ if in_index => {}
            _ => out.push(c),
        }
    }
    out
}

/// `(a, b, c)`, as the vector is written in RON.
pub(crate) fn show(v: &[f32]) -> String {
    let parts: Vec<String> = v.iter().map(f32::to_string).collect();
    format!("({})", parts.join(", "))
}

/// `v` scaled to unit length, or `None` if it is zero (or not finite). Dividing by the
/// largest component first keeps the length from overflowing for huge components or
/// underflowing to zero for tiny ones.
pub(crate) fn unit(v: &[f32]) -> Option<Vec<f32>> {
    let scale = v.iter().fold(0.0f32, |m, c| m.max(c.abs()));
    if !(scale.is_finite() && scale > 0.0) {
        return None;
    }
    let scaled: Vec<f32> = v.iter().map(|c| c / scale).collect();
    let length = scaled.iter().map(|c| c * c).sum::<f32>().sqrt();
    Some(scaled.iter().map(|c| c / length).collect())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn short_names() {
        assert_eq!(short_name("field.density"), "density");
        assert_eq!(short_name("field.height.min"), "height.min");
        assert_eq!(short_name("colliders[3].radius"), "radius");
        assert_eq!(short_name("colliders[3].motion.points[2]"), "points");
        assert_eq!(short_name("size"), "size");
    }

    #[test]
    fn generic_paths_drop_indices() {
        assert_eq!(generic_path("colliders[12].radius"), "colliders[].radius");
        assert_eq!(
            generic_path("wind.guides[0].points[3].strength"),
            "wind.guides[].points[].strength"
        );
        assert_eq!(generic_path("field.density"), "field.density");
    }

    #[test]
    fn descriptions() {
        let a = Allowed::open_closed(0.0, 10000.0, "blades/m²");
        assert_eq!(a.describe("density"), "0 < density <= 10000 blades/m²");
        assert_eq!(
            Rule::Range(Allowed::closed(0.01, 10.0, "m")).describe("field.height.max"),
            "0.01 <= height.max <= 10 m (and min <= max)"
        );
        assert_eq!(
            Rule::Vector(Allowed::closed(-1e5, 1e5, "m")).describe("camera.eye"),
            "-100000 <= eye <= 100000 m for every component"
        );
        assert!(a.contains(10000.0) && !a.contains(0.0) && !a.contains(f32::NAN));
    }
}
