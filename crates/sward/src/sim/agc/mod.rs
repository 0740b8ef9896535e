//! Arrow-Guided wind Control (AGC, CWD-Sim Section 3.5) as plain data: editing the guides,
//! listing their arrows, and collecting everything that pushes the fluid grid in one step
//! ([`fluid_forces`]). Nothing here touches the GPU; the solver uploads what
//! [`fluid_forces`] returns.
//!
//! # The model
//!
//! A guide is a tree of points on the terrain ([`Guide`], [`GuidePoint`], the form the scene
//! file stores). Point 0 is the root, where the flow starts; every other point names its
//! parent, and the edge parent → point is an *arrow* that accelerates the air along its
//! direction, within `radius` metres of the segment, by `strength` m/s². Any point may have
//! several children, so a flow can branch. A point may override the guide's strength or
//! radius for the arrow that ends at it.
//!
//! Points are stored in a list in which every parent comes before its children (so point 0
//! is the root, and one pass in list order sees every parent before its children). The
//! editing API ([`GuideSet`]) keeps that invariant; [`arrows`] ignores points that break
//! it (a validated scene has none).
//!
//! # The timing rule
//!
//! The paper applies the forces "in a sequence based on the direction of the arrow's flow
//! to make it appear continuous". Here that sequence is a front that leaves a guide's root
//! when the guide's sequence starts (`Guide::started`: the scene's start for a loaded
//! guide, the moment of creation for one added in the editor, the click for "replay the
//! sequence") and runs along every branch at [`FRONT_SPEED`] m/s. An arrow switches on when
//! the front reaches its start:
//!
//! `t_on = started + start_distance / FRONT_SPEED`,
//!
//! where `start_distance` is the path length from the root to the arrow's start, and then
//! ramps up over [`RAMP_TIME`] seconds with a smoothstep to its full strength, where it
//! stays:
//!
//! `strength(t) = strength · smoothstep((t − t_on) / RAMP_TIME)`.
//!
//! The ramp avoids a step in the force (which would start a pressure wave the grid shows as
//! a visible jolt); the front makes downstream arrows wait until the air pushed by the
//! upstream ones could plausibly have arrived, so the grass bends in a wave along the guide
//! instead of all at once.

use std::sync::atomic::{AtomicUsize, Ordering};

use glam::Vec2;

use super::colliders::{along_path, position};
use super::wind_layout::{ArrowGpu, FluidForces, ObstacleGpu, MAX_ARROWS, MAX_OBSTACLES};
use crate::field::HeightField;
use crate::scene::{Downwash, Guide, GuidePoint, Motion, Scene};

/// Speed in m/s of the front that switches the arrows on, from the root outwards.
pub const FRONT_SPEED: f32 = 6.0;
/// Seconds an arrow takes to ramp from off to full strength once the front reaches it.
pub const RAMP_TIME: f32 = 0.5;
/// Points closer than this (metres) to their parent would make a zero-length arrow, whose
/// direction is undefined.
pub const MIN_ARROW_LENGTH: f32 = 1e-4;
/// Largest strength (m/s²) of a guide or an arrow, as the scene validation allows.
pub const MAX_STRENGTH: f32 = 1000.0;

/// Index of a guide in [`GuideSet::guides`] (deleting a guide shifts the later ones down).
pub type GuideId = usize;
/// Index of a point in a guide's `points` (deleting a point shifts the later ones down).
pub type PointId = usize;

/// Why an edit of the guides was refused. The guides are unchanged after an error.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum AgcError {
    /// The guide id is not in the set.
    #[error("no guide {guide}: there are {count} guide(s)")]
    NoGuide {
        /// The requested guide id.
        guide: GuideId,
        /// How many guides the set has.
        count: usize,
    },
    /// The guide exists but has no point with that id.
    #[error("guide {guide} has no point {point}: it has {count} point(s)")]
    NoPoint {
        /// The guide that was asked.
        guide: GuideId,
        /// The requested point id.
        point: PointId,
        /// How many points the guide has.
        count: usize,
    },
    /// A value given to an edit (position, strength or radius) is NaN or infinite.
    #[error("{what} = {value} is not a finite number")]
    NotFinite {
        /// Which value it was: `"position.x"`, `"position.z"`, `"strength"` or `"radius"`.
        what: &'static str,
        /// The offending value.
        value: f32,
    },
    /// A position lies beyond the edge of the terrain.
    #[error("position ({x}, {z}) is outside the terrain: allowed -{half} ..= {half} on x and z")]
    OutsideTerrain {
        /// World x of the position in metres.
        x: f32,
        /// World z of the position in metres.
        z: f32,
        /// Half the terrain size in metres: the largest allowed `|x|` and `|z|`.
        half: f32,
    },
    /// A point would lie within [`MIN_ARROW_LENGTH`] of its parent or a child, making a
    /// zero-length arrow.
    #[error(
        "point {point} at ({x}, {z}) would be within {MIN_ARROW_LENGTH} m of point {other}: \
         an arrow needs a length > 0"
    )]
    ZeroLength {
        /// The point that would be too close (a new point: the id it would get; a deletion:
        /// the child being re-attached).
        point: PointId,
        /// The point it would coincide with: its parent or one of its children.
        other: PointId,
        /// World x of the rejected position in metres.
        x: f32,
        /// World z of the rejected position in metres.
        z: f32,
    },
    /// A radius is not in `(0, terrain size]`.
    #[error("radius = {value} is out of range: allowed 0 < radius <= {max} m (the terrain size)")]
    Radius {
        /// The rejected radius in metres.
        value: f32,
        /// The largest allowed radius: the terrain size in metres.
        max: f32,
    },
    /// A strength is not in `[0, MAX_STRENGTH]`.
    #[error("strength = {value} is out of range: allowed 0 <= strength <= {MAX_STRENGTH} m/s²")]
    Strength {
        /// The rejected strength in m/s².
        value: f32,
    },
    /// A strength or radius override was set on the root, which ends no arrow.
    #[error(
        "point 0 is the root: no arrow ends at it, so it has no strength or radius of its own"
    )]
    RootHasNoArrow,
    /// The terrain size given to [`GuideSet::new`] is not finite or not > 0.
    #[error("terrain size = {value} is out of range: allowed a finite size > 0 m")]
    TerrainSize {
        /// The rejected size in metres.
        value: f32,
    },
    /// A guide has an empty point list (no root).
    #[error("guide {guide} has no points: a guide needs at least its root")]
    Empty {
        /// The empty guide.
        guide: GuideId,
    },
    /// A point's parent breaks the parents-before-children rule: the root has a parent, or
    /// another point has none or one with an index not smaller than its own.
    #[error(
        "guide {guide} point {point}: parent {parent:?} is invalid: the root (point 0) has none, \
         every other point names a parent with a smaller index"
    )]
    Parent {
        /// The guide holding the point.
        guide: GuideId,
        /// The point with the bad parent.
        point: PointId,
        /// The parent it names (`None`: no parent).
        parent: Option<usize>,
    },
}

/// The guides of a scene with an editing API that keeps them valid: every position finite
/// and on the terrain, no zero-length arrow, radii in `(0, terrain size]`, strengths in
/// `[0, 1000]`, and points in parents-before-children order with point 0 the root.
///
/// `guides` is public so that it can be moved in and out of `scene.wind.guides`; code that
/// edits it directly should call [`GuideSet::check`] afterwards.
#[derive(Clone, Debug, PartialEq)]
pub struct GuideSet {
    /// The guides, indexed by [`GuideId`].
    pub guides: Vec<Guide>,
    terrain_size: f32,
    /// Scene time in seconds: a guide added now starts its sequence at this time.
    clock: f32,
}

impl GuideSet {
    /// An empty set on a terrain of side `terrain_size` metres (centred on the origin).
    ///
    /// # Errors
    ///
    /// [`AgcError::TerrainSize`] unless the size is finite and > 0.
    pub fn new(terrain_size: f32) -> Result<Self, AgcError> {
        if !(terrain_size.is_finite() && terrain_size > 0.0) {
            return Err(AgcError::TerrainSize {
                value: terrain_size,
            });
        }
        Ok(Self {
            guides: Vec::new(),
            terrain_size,
            clock: 0.0,
        })
    }

    /// Takes existing guides (e.g. a loaded scene's `wind.guides`), checking them.
    ///
    /// # Errors
    ///
    /// As [`GuideSet::new`] and [`GuideSet::check`].
    pub fn from_guides(guides: Vec<Guide>, terrain_size: f32) -> Result<Self, AgcError> {
        let set = Self {
            guides,
            ..Self::new(terrain_size)?
        };
        set.check()?;
        Ok(set)
    }

    /// The terrain's side length in metres.
    pub fn terrain_size(&self) -> f32 {
        self.terrain_size
    }

    /// Sets the scene time (seconds) at which guides added from now on start their
    /// sequence. Non-finite or negative times count as 0.
    pub fn set_clock(&mut self, time: f32) {
        self.clock = if time.is_finite() { time.max(0.0) } else { 0.0 };
    }

    /// Starts the sequence of `guide` (or of every guide with `None`) again at the clock:
    /// its arrows switch off and come on again from the root outwards.
    ///
    /// # Errors
    ///
    /// [`AgcError::NoGuide`] for a guide that does not exist.
    pub fn restart(&mut self, guide: Option<GuideId>) -> Result<(), AgcError> {
        let clock = self.clock;
        match guide {
            Some(g) => self.guide_mut(g)?.started = clock,
            None => self.guides.iter_mut().for_each(|g| g.started = clock),
        }
        Ok(())
    }

    /// Checks every guide against the rules the editing API keeps (see the type's docs).
    ///
    /// # Errors
    ///
    /// The first rule broken.
    pub fn check(&self) -> Result<(), AgcError> {
        for (g, guide) in self.guides.iter().enumerate() {
            self.check_strength(guide.strength)?;
            self.check_radius(guide.radius)?;
            if guide.points.is_empty() {
                return Err(AgcError::Empty { guide: g });
            }
            for (i, p) in guide.points.iter().enumerate() {
                let parent_ok = match p.parent {
                    None => i == 0,
                    Some(parent) => parent < i,
                };
                if !parent_ok {
                    return Err(AgcError::Parent {
                        guide: g,
                        point: i,
                        parent: p.parent,
                    });
                }
                self.check_position(p.position)?;
                if let Some(s) = p.strength {
                    self.check_strength(s)?;
                }
                if let Some(r) = p.radius {
                    self.check_radius(r)?;
                }
                if let Some(parent) = p.parent {
                    check_length(guide, i, parent, p.position)?;
                }
            }
        }
        Ok(())
    }

    /// Adds a guide with only its root at `root` (no arrows yet); returns its id.
    ///
    /// # Errors
    ///
    /// A non-finite or off-terrain root, a strength outside `[0, 1000]`, a radius outside
    /// `(0, terrain size]`.
    pub fn add_guide(
        &mut self,
        root: (f32, f32),
        strength: f32,
        radius: f32,
    ) -> Result<GuideId, AgcError> {
        self.check_position(root)?;
        self.check_strength(strength)?;
        self.check_radius(radius)?;
        self.guides.push(Guide {
            started: self.clock,
            strength,
            radius,
            points: vec![point(root, None)],
        });
        Ok(self.guides.len() - 1)
    }

    /// Adds a point at `position` as a child of `parent_point`, i.e. a new arrow
    /// `parent_point → position`; returns the new point's id. A point may have any number of
    /// children (the flow branches there). The new point goes to the end of the list, so
    /// parents still come before their children.
    ///
    /// # Errors
    ///
    /// No such guide or point, a non-finite or off-terrain position, or a position within
    /// [`MIN_ARROW_LENGTH`] of the parent.
    pub fn add_child(
        &mut self,
        guide: GuideId,
        parent_point: PointId,
        position: (f32, f32),
    ) -> Result<PointId, AgcError> {
        self.point_ref(guide, parent_point)?;
        self.check_position(position)?;
        let g = &mut self.guides[guide];
        let id = g.points.len();
        check_length(g, id, parent_point, position)?;
        g.points.push(point(position, Some(parent_point)));
        Ok(id)
    }

    /// Moves a point (the root moves the start of its arrows; any other point the end of
    /// its own arrow and the start of its children's).
    ///
    /// # Errors
    ///
    /// No such guide or point, a non-finite or off-terrain position, or a position within
    /// [`MIN_ARROW_LENGTH`] of the point's parent or of one of its children.
    pub fn move_point(
        &mut self,
        guide: GuideId,
        point: PointId,
        position: (f32, f32),
    ) -> Result<(), AgcError> {
        self.point_ref(guide, point)?;
        self.check_position(position)?;
        let g = &self.guides[guide];
        if let Some(parent) = g.points[point].parent {
            check_length(g, point, parent, position)?;
        }
        for (c, child) in g.points.iter().enumerate() {
            if child.parent == Some(point) {
                check_length(g, point, c, position)?;
            }
        }
        self.guides[guide].points[point].position = position;
        Ok(())
    }

    /// Deletes a point.
    ///
    /// * The root (point 0): the whole guide goes (a guide cannot exist without the place
    ///   its flow starts from). Later guides' ids shift down by one.
    /// * Any other point: its arrow goes, and its children are re-attached to its parent,
    ///   so that the flow stays connected (parent → child replaces parent → point → child).
    ///   Later points' ids shift down by one and the parent indices are rewritten to match;
    ///   the list stays in parents-before-children order (the new parent already came
    ///   before the deleted point, which came before its children).
    ///
    /// # Errors
    ///
    /// No such guide or point, or [`AgcError::ZeroLength`] if a re-attached child lies on
    /// the deleted point's parent (move it first); nothing is deleted then.
    pub fn delete_point(&mut self, guide: GuideId, point: PointId) -> Result<(), AgcError> {
        self.point_ref(guide, point)?;
        let Some(parent) = self.guides[guide].points[point].parent else {
            self.guides.remove(guide);
            return Ok(());
        };
        let g = &self.guides[guide];
        for (c, child) in g.points.iter().enumerate() {
            if child.parent == Some(point) {
                check_length(g, c, parent, child.position)?;
            }
        }
        let points = &mut self.guides[guide].points;
        points.remove(point);
        for p in points.iter_mut() {
            p.parent = p.parent.map(|q| match q.cmp(&point) {
                std::cmp::Ordering::Less => q,
                std::cmp::Ordering::Equal => parent,
                std::cmp::Ordering::Greater => q - 1,
            });
        }
        Ok(())
    }

    /// Deletes a whole guide and returns it; later guides' ids shift down by one.
    ///
    /// # Errors
    ///
    /// No such guide.
    pub fn delete_guide(&mut self, guide: GuideId) -> Result<Guide, AgcError> {
        self.guide_ref(guide)?;
        Ok(self.guides.remove(guide))
    }

    /// Sets the strength (m/s²) of the whole guide (`point: None`) or overrides it for the
    /// arrow that ends at `point`.
    ///
    /// # Errors
    ///
    /// No such guide or point, the root as `point`, or a strength outside `[0, 1000]`.
    pub fn set_strength(
        &mut self,
        guide: GuideId,
        point: Option<PointId>,
        value: f32,
    ) -> Result<(), AgcError> {
        self.check_strength(value)?;
        match point {
            None => self.guide_mut(guide)?.strength = value,
            Some(p) => self.arrow_end_mut(guide, p)?.strength = Some(value),
        }
        Ok(())
    }

    /// Sets the radius (m) of the whole guide (`point: None`) or overrides it for the arrow
    /// that ends at `point`.
    ///
    /// # Errors
    ///
    /// No such guide or point, the root as `point`, or a radius outside
    /// `(0, terrain size]`.
    pub fn set_radius(
        &mut self,
        guide: GuideId,
        point: Option<PointId>,
        value: f32,
    ) -> Result<(), AgcError> {
        self.check_radius(value)?;
        match point {
            None => self.guide_mut(guide)?.radius = value,
            Some(p) => self.arrow_end_mut(guide, p)?.radius = Some(value),
        }
        Ok(())
    }

    /// Removes the strength and radius overrides of the arrow ending at `point`, so that it
    /// takes the guide's values again.
    ///
    /// # Errors
    ///
    /// No such guide or point.
    pub fn clear_overrides(&mut self, guide: GuideId, point: PointId) -> Result<(), AgcError> {
        self.point_ref(guide, point)?;
        let p = &mut self.guides[guide].points[point];
        p.strength = None;
        p.radius = None;
        Ok(())
    }

    fn guide_ref(&self, guide: GuideId) -> Result<&Guide, AgcError> {
        self.guides.get(guide).ok_or(AgcError::NoGuide {
            guide,
            count: self.guides.len(),
        })
    }

    fn guide_mut(&mut self, guide: GuideId) -> Result<&mut Guide, AgcError> {
        self.guide_ref(guide)?;
        Ok(&mut self.guides[guide])
    }

    fn point_ref(&self, guide: GuideId, point: PointId) -> Result<&GuidePoint, AgcError> {
        let g = self.guide_ref(guide)?;
        g.points.get(point).ok_or(AgcError::NoPoint {
            guide,
            point,
            count: g.points.len(),
        })
    }

    /// The point at the end of an arrow: any point but the root.
    fn arrow_end_mut(
        &mut self,
        guide: GuideId,
        point: PointId,
    ) -> Result<&mut GuidePoint, AgcError> {
        if self.point_ref(guide, point)?.parent.is_none() {
            return Err(AgcError::RootHasNoArrow);
        }
        Ok(&mut self.guides[guide].points[point])
    }

    fn check_position(&self, (x, z): (f32, f32)) -> Result<(), AgcError> {
        finite("position.x", x)?;
        finite("position.z", z)?;
        let half = self.terrain_size / 2.0;
        if x.abs() > half || z.abs() > half {
            return Err(AgcError::OutsideTerrain { x, z, half });
        }
        Ok(())
    }

    fn check_strength(&self, value: f32) -> Result<(), AgcError> {
        finite("strength", value)?;
        if !(0.0..=MAX_STRENGTH).contains(&value) {
            return Err(AgcError::Strength { value });
        }
        Ok(())
    }

    fn check_radius(&self, value: f32) -> Result<(), AgcError> {
        finite("radius", value)?;
        // A band wider than the terrain would push the whole grid: that is what the global
        // wind is for.
        if !(value > 0.0 && value <= self.terrain_size) {
            return Err(AgcError::Radius {
                value,
                max: self.terrain_size,
            });
        }
        Ok(())
    }
}

fn point(position: (f32, f32), parent: Option<PointId>) -> GuidePoint {
    GuidePoint {
        position,
        parent,
        strength: None,
        radius: None,
    }
}

fn finite(what: &'static str, value: f32) -> Result<(), AgcError> {
    if value.is_finite() {
        Ok(())
    } else {
        Err(AgcError::NotFinite { what, value })
    }
}

/// `point` placed at `position` must not lie on `other` (its parent or child).
fn check_length(
    guide: &Guide,
    point: PointId,
    other: PointId,
    position: (f32, f32),
) -> Result<(), AgcError> {
    let distance = Vec2::from(position).distance(Vec2::from(guide.points[other].position));
    if distance < MIN_ARROW_LENGTH {
        return Err(AgcError::ZeroLength {
            point,
            other,
            x: position.0,
            z: position.1,
        });
    }
    Ok(())
}

/// One arrow of a guide: the edge from point `start_point` to point `end_point`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Arrow {
    /// The guide the arrow belongs to.
    pub guide: GuideId,
    /// The point the arrow starts at (the end point's parent).
    pub start_point: PointId,
    /// The point the arrow ends at; its overrides give the arrow's strength and radius.
    pub end_point: PointId,
    /// (x, z) in world metres.
    pub start: Vec2,
    /// (x, z) of the arrow's end in world metres.
    pub end: Vec2,
    /// Full strength in m/s² (the end point's override, else the guide's).
    pub strength: f32,
    /// Half-width of the pushed band in metres (the end point's override, else the guide's).
    pub radius: f32,
    /// Arrows between the root and this arrow's start: 0 for the root's arrows.
    pub depth: u32,
    /// Path length in metres from the root to this arrow's start, along the tree.
    pub start_distance: f32,
    /// Scene time at which the guide's sequence started (`Guide::started`).
    pub sequence_start: f32,
}

impl Arrow {
    /// When the front reaches the arrow's start, in seconds of scene time:
    /// `sequence_start + start_distance / FRONT_SPEED`.
    pub fn switch_on_time(&self) -> f32 {
        self.sequence_start + self.start_distance / FRONT_SPEED
    }

    /// The fraction of full strength at `time` (see the module docs): 0 until
    /// [`Arrow::switch_on_time`], a smoothstep up over [`RAMP_TIME`], then 1.
    pub fn activation(&self, time: f32) -> f32 {
        let x = ((time - self.switch_on_time()) / RAMP_TIME).clamp(0.0, 1.0);
        x * x * (3.0 - 2.0 * x)
    }
}

/// Every arrow of every guide, by guide and then in list order of the end points (so an
/// arrow comes after the arrows upstream of it).
///
/// Points that do not hang off the root by the list-order rule (parent missing, not smaller
/// than the point's index, or itself not reached), arrows shorter than
/// [`MIN_ARROW_LENGTH`] and non-finite ones are skipped: the shader would normalise a zero
/// direction into NaN. A validated scene or a [`GuideSet`] has none of them.
pub fn arrows(guides: &[Guide]) -> Vec<Arrow> {
    let mut out = Vec::new();
    for (g, guide) in guides.iter().enumerate() {
        // (depth of the point, path length from the root) for points reached from the root.
        let mut reached: Vec<Option<(u32, f32)>> = vec![None; guide.points.len()];
        if let Some(root) = guide.points.first() {
            if root.parent.is_none() {
                reached[0] = Some((0, 0.0));
            }
        }
        for (i, p) in guide.points.iter().enumerate().skip(1) {
            let Some(parent) = p.parent.filter(|&q| q < i) else {
                continue;
            };
            let Some((depth, distance)) = reached[parent] else {
                continue;
            };
            let start = Vec2::from(guide.points[parent].position);
            let end = Vec2::from(p.position);
            let length = start.distance(end);
            if !(length.is_finite() && length >= MIN_ARROW_LENGTH) {
                continue;
            }
            reached[i] = Some((depth + 1, distance + length));
            out.push(Arrow {
                guide: g,
                start_point: parent,
                end_point: i,
                start,
                end,
                strength: p.strength.unwrap_or(guide.strength),
                radius: p.radius.unwrap_or(guide.radius),
                depth,
                start_distance: distance,
                sequence_start: if guide.started.is_finite() {
                    guide.started
                } else {
                    0.0
                },
            });
        }
    }
    out
}

/// The arrows switched on at `time` (seconds since the scene started) as the splat pass
/// reads them, strength scaled by [`Arrow::activation`]; arrows not yet on are left out.
/// At most [`MAX_ARROWS`]: the rest (the last in [`arrows`]' order) are dropped with a
/// warning.
pub fn arrows_at(guides: &[Guide], time: f32) -> Vec<ArrowGpu> {
    let on: Vec<ArrowGpu> = arrows(guides)
        .into_iter()
        .filter_map(|a| {
            let ramp = a.activation(time);
            (ramp > 0.0).then_some(ArrowGpu {
                segment: [a.start.x, a.start.y, a.end.x, a.end.y],
                strength: a.strength * ramp,
                radius: a.radius,
                activation: ramp,
                _pad: 0.0,
            })
        })
        .collect();
    truncate_with_warning(on, MAX_ARROWS, "AGC arrows", &ARROWS_WARNED)
}

/// Every arrow at full strength, with how far the sequence has switched it on at `time`
/// (`ArrowGpu::activation`), for the wind overlay: arrows not yet on are drawn grey.
pub fn overlay_arrows(guides: &[Guide], time: f32) -> Vec<ArrowGpu> {
    arrows(guides)
        .into_iter()
        .take(MAX_ARROWS)
        .map(|a| ArrowGpu {
            segment: [a.start.x, a.start.y, a.end.x, a.end.y],
            strength: a.strength,
            radius: a.radius,
            activation: a.activation(time),
            _pad: 0.0,
        })
        .collect()
}

/// Everything that pushes the fluid grid at `time`: the AGC arrows ([`arrows_at`]), the
/// global wind, the downwash and the colliders as obstacles (when
/// `scene.wind.fluid.obstacles`). Collected whatever `scene.wind.source` says; whether the
/// fluid runs at all is the caller's decision.
///
/// * Global: the normalised direction × strength (zero for a zero direction).
/// * Downwash: centre (x, z) at `time` (along its path at `speed · time`, or moved by its
///   velocity, or fixed), radius, strength; radius 0 when there is none.
/// * Obstacles: each collider's footprint, the circle of its radius under its centre (a 2D
///   grid), or its sphere, its centre's height above the ground under it (a 3D grid), with
///   the velocity from a central difference of its position over ±1/120 s. At most
///   [`MAX_OBSTACLES`]; the rest are dropped with a warning.
pub fn fluid_forces(scene: &Scene, terrain: &HeightField, time: f32) -> FluidForces {
    let wind = &scene.wind;
    let global = wind.global.as_ref().map_or([0.0; 2], |g| {
        let d = Vec2::from(g.direction).normalize_or_zero() * g.strength;
        [d.x, d.y]
    });
    let downwash = wind.downwash.as_ref().map_or([0.0; 4], |d| {
        let c = downwash_center(d, time);
        [c.x, c.y, d.radius, d.strength]
    });
    let obstacles = if wind.fluid.obstacles {
        let all = scene
            .colliders
            .iter()
            .map(|s| {
                // Motion starts at t = 0 and a path is clamped before it, so near t = 0 the
                // window is shifted forward (a one-sided difference) rather than halving a
                // moving collider's velocity.
                const H: f32 = 1.0 / 120.0;
                let t0 = (time - H).max(0.0).min(time);
                let t1 = t0 + 2.0 * H;
                let c = position(s, terrain, time);
                let v = (position(s, terrain, t1) - position(s, terrain, t0)) / (t1 - t0);
                ObstacleGpu {
                    circle: [c.x, c.z, s.radius, c.y - terrain.height(c.x, c.z)],
                    velocity: [v.x, v.z, v.y, 0.0],
                }
            })
            .collect();
        truncate_with_warning(all, MAX_OBSTACLES, "obstacles", &OBSTACLES_WARNED)
    } else {
        Vec::new()
    };
    FluidForces {
        arrows: arrows_at(&wind.guides, time),
        obstacles,
        global,
        downwash,
    }
}

/// The downwash's centre (x, z) at `time`.
fn downwash_center(d: &Downwash, time: f32) -> Vec2 {
    let p = Vec2::new(d.position.0, d.position.2);
    match &d.motion {
        Motion::Static => p,
        Motion::Velocity(v) => p + Vec2::new(v.0, v.2) * time,
        Motion::Path {
            points,
            speed,
            looped,
        } => along_path(points, *looped, speed * time),
    }
}

/// The total last warned about, per list: the lists are rebuilt every frame, and one
/// warning per change of the total is enough to explain missing forces without flooding
/// the log at 60 lines a second.
static ARROWS_WARNED: AtomicUsize = AtomicUsize::new(0);
static OBSTACLES_WARNED: AtomicUsize = AtomicUsize::new(0);

fn truncate_with_warning<T>(
    mut items: Vec<T>,
    max: usize,
    what: &str,
    warned: &AtomicUsize,
) -> Vec<T> {
    if items.len() > max {
        if warned.swap(items.len(), Ordering::Relaxed) != items.len() {
            log::warn!(
                "{} {what} but the fluid solver takes at most {max}: the last {} are ignored",
                items.len(),
                items.len() - max
            );
        }
        items.truncate(max);
    }
    items
}

#[cfg(test)]
mod tests;
