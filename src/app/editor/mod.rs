//! The AGC editor's state machine: what clicks, drags, sliders and shortcuts do to the wind
//! guides, with undo and redo. It owns no window and no GPU; the window translates mouse
//! and keys into the calls below (after picking: which guide point, which terrain point is
//! under the cursor) and re-uploads the arrows whenever [`Editor::revision`] changes.
//!
//! Every change goes through [`GuideSet`], so the guides stay valid (on the terrain, no
//! zero-length arrow, values in range, parents before children) whatever the user does. A
//! refused edit changes nothing and leaves its reason in [`Editor::error`] for the panel.
//!
//! Undo works on snapshots of the whole guide list (a few hundred bytes; far simpler than
//! inverse operations, and exact by construction). One user gesture is one undo step: a
//! whole drag, a whole slider drag (consecutive changes of the same property of the same
//! point coalesce), a new guide together with the drag that placed it.

use glam::Vec2;

use sward::scene::Guide;
use sward::sim::agc::{AgcError, GuideId, GuideSet, PointId};

/// A guide point: the guide's index and the point's index in it (0 = the root).
pub type Selection = (GuideId, PointId);

/// Strength (m/s²) of new guides until the user changes it.
pub const DEFAULT_STRENGTH: f32 = 12.0;
/// Radius (m) of new guides until the user changes it.
pub const DEFAULT_RADIUS: f32 = 2.5;
/// Length (m) of the arrow [`Editor::add_child_of_selected`] adds.
pub const CHILD_STEP: f32 = 3.0;
/// Undo steps kept; older ones are dropped so that a long session does not grow without
/// bound.
pub const MAX_HISTORY: usize = 256;

const NOTHING_SELECTED: &str = "nothing is selected: click a guide point first";

/// What a slider edits, for coalescing consecutive changes into one undo step.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Property {
    Strength,
    Radius,
}

/// An undo (or redo) step: the guides as they were, and what was selected then, so that
/// undoing also brings back the selection (undoing a delete selects the point again).
#[derive(Clone, Debug, PartialEq)]
struct Snapshot {
    guides: Vec<Guide>,
    selection: Option<Selection>,
}

/// A point being dragged.
#[derive(Clone, Debug)]
struct Drag {
    target: Selection,
    /// The state before the drag, recorded as an undo step on the first actual move (a
    /// click that does not move records nothing); `None` once recorded, or when the press
    /// itself was an undoable edit (a new guide) that the drag belongs to.
    pending: Option<Snapshot>,
}

/// The editor's state: the guides, the selection, an ongoing drag and the history.
#[derive(Clone, Debug)]
pub struct Editor {
    set: GuideSet,
    selection: Option<Selection>,
    drag: Option<Drag>,
    undo: Vec<Snapshot>,
    redo: Vec<Snapshot>,
    revision: u64,
    /// The slider edit that the last undo step belongs to, if the last change was one.
    slider: Option<(Selection, Property)>,
    /// Strength (m/s²) of new guides.
    pub new_strength: f32,
    /// Radius (m) of new guides.
    pub new_radius: f32,
    /// The last refused edit, for the panel; cleared by the next successful edit.
    pub error: Option<String>,
}

impl Editor {
    /// An editor for `guides` on a terrain of side `terrain_size` metres.
    ///
    /// # Errors
    ///
    /// As [`GuideSet::from_guides`]: a bad terrain size or guides that break its rules.
    pub fn new(guides: Vec<Guide>, terrain_size: f32) -> Result<Self, AgcError> {
        let set = GuideSet::from_guides(guides, terrain_size)?;
        Ok(Self {
            set,
            selection: None,
            drag: None,
            undo: Vec::new(),
            redo: Vec::new(),
            revision: 0,
            slider: None,
            new_strength: DEFAULT_STRENGTH,
            // On a terrain smaller than the default radius, the default would be refused.
            new_radius: DEFAULT_RADIUS.min(terrain_size),
            error: None,
        })
    }

    /// The guides as they are now (to draw, to upload, to save into the scene).
    pub fn guides(&self) -> &[Guide] {
        &self.set.guides
    }

    /// Sets the scene time at which guides added from now on start their sequence.
    pub fn set_clock(&mut self, time: f32) {
        self.set.set_clock(time);
    }

    /// Starts the sequence again now (at the clock): of the selected point's guide, or of
    /// every guide when nothing is selected. Not an undo step: it moves no point.
    pub fn replay_sequence(&mut self) {
        let guide = self.selection.map(|(guide, _)| guide);
        if self.set.restart(guide).is_ok() {
            self.changed();
        }
    }

    /// The guides with their terrain size.
    pub fn guide_set(&self) -> &GuideSet {
        &self.set
    }

    /// Counts the changes of the guides (undo, redo and [`Editor::replace`] included), so
    /// that the window re-uploads the arrows only when this moves.
    pub fn revision(&self) -> u64 {
        self.revision
    }

    /// The selected point, if any. It always exists.
    pub fn selection(&self) -> Option<Selection> {
        self.selection
    }

    /// Selects a point, or nothing with `None`. A point that does not exist is ignored.
    pub fn select(&mut self, s: Option<Selection>) {
        if s.is_some_and(|s| !self.exists(s)) {
            return;
        }
        if s != self.selection {
            self.drag = None;
        }
        self.set_selection(s);
    }

    /// A left-button press in edit mode. `hit` is the guide point under the cursor,
    /// `ground` the terrain point (x, z) under it, `alt` whether Alt is held.
    ///
    /// * Alt, a selection and a ground point: a new arrow from the selected point to the
    ///   ground point (a point may have many children: the flow branches); the new point
    ///   is selected.
    /// * Otherwise a hit point: it is selected and a drag starts.
    /// * Otherwise a ground point: a new guide rooted there with [`Editor::new_strength`]
    ///   and [`Editor::new_radius`]; its root is selected and a drag starts (one undo step
    ///   removes the guide, wherever it was dragged).
    /// * Otherwise (the sky): nothing is selected.
    pub fn press(&mut self, hit: Option<Selection>, ground: Option<Vec2>, alt: bool) {
        // A press without a release (the window lost the release event) ends the old drag.
        self.release();
        let hit = hit.filter(|&s| self.exists(s));
        if alt {
            if let (Some((g, p)), Some(ground)) = (self.selection, ground) {
                if let Some(child) = self.apply(None, |set| set.add_child(g, p, ground.into())) {
                    self.set_selection(Some((g, child)));
                }
                return;
            }
        }
        if let Some(target) = hit {
            self.set_selection(Some(target));
            self.drag = Some(Drag {
                target,
                pending: Some(self.snapshot()),
            });
            return;
        }
        if let Some(ground) = ground {
            let (strength, radius) = (self.new_strength, self.new_radius);
            if let Some(g) = self.apply(None, |set| set.add_guide(ground.into(), strength, radius))
            {
                self.set_selection(Some((g, 0)));
                self.drag = Some(Drag {
                    target: (g, 0),
                    pending: None,
                });
            }
            return;
        }
        self.set_selection(None);
    }

    /// Moves the dragged point to `ground` (clamped onto the terrain, so that dragging past
    /// the edge pins the point to the edge). `None` (the cursor is off the terrain) and a
    /// call without a drag do nothing; a refused move (onto its parent or a child) leaves
    /// the point where it was and sets [`Editor::error`].
    pub fn drag(&mut self, ground: Option<Vec2>) {
        let (Some(drag), Some(ground)) = (&self.drag, ground) else {
            return;
        };
        let (g, p) = drag.target;
        let to = self.clamp(ground);
        if Vec2::from(self.set.guides[g].points[p].position) == to {
            return;
        }
        match self.set.move_point(g, p, to.into()) {
            Ok(()) => {
                if let Some(before) = self.drag.as_mut().and_then(|d| d.pending.take()) {
                    self.record(before);
                }
                self.slider = None;
                self.changed();
            }
            Err(e) => self.error = Some(e.to_string()),
        }
    }

    /// Ends a drag (left button released).
    pub fn release(&mut self) {
        self.drag = None;
    }

    /// Whether a point is being dragged (the window then keeps the camera still).
    pub fn is_dragging(&self) -> bool {
        self.drag.is_some()
    }

    /// Adds a child [`CHILD_STEP`] metres beyond the selected point, continuing the arrow
    /// that ends there (for a root: along its first arrow, or +x if it has none), clamped
    /// onto the terrain; the child is selected.
    pub fn add_child_of_selected(&mut self) {
        let Some((g, p)) = self.selection else {
            self.error = Some(NOTHING_SELECTED.into());
            return;
        };
        self.drag = None;
        let guide = &self.set.guides[g];
        let here = Vec2::from(guide.points[p].position);
        let along = match guide.points[p].parent {
            Some(parent) => here - Vec2::from(guide.points[parent].position),
            None => guide
                .points
                .iter()
                .find(|c| c.parent == Some(p))
                .map_or(Vec2::X, |c| Vec2::from(c.position) - here),
        };
        let to = self.clamp(here + along.try_normalize().unwrap_or(Vec2::X) * CHILD_STEP);
        if let Some(child) = self.apply(None, |set| set.add_child(g, p, to.into())) {
            self.set_selection(Some((g, child)));
        }
    }

    /// The strength the selected arrow pushes with (m/s²): the guide's for a root, else
    /// the override of the arrow ending at the point or, without one, the guide's.
    pub fn strength_of_selected(&self) -> Option<f32> {
        let (g, p) = self.selection?;
        let guide = &self.set.guides[g];
        let point = &guide.points[p];
        Some(match point.parent {
            None => guide.strength,
            Some(_) => point.strength.unwrap_or(guide.strength),
        })
    }

    /// The radius of the selected arrow (m), as [`Editor::strength_of_selected`].
    pub fn radius_of_selected(&self) -> Option<f32> {
        let (g, p) = self.selection?;
        let guide = &self.set.guides[g];
        let point = &guide.points[p];
        Some(match point.parent {
            None => guide.radius,
            Some(_) => point.radius.unwrap_or(guide.radius),
        })
    }

    /// Sets the strength (m/s²): the guide's on a root, else the override of the arrow
    /// ending at the selected point. Consecutive calls on the same point are one undo step.
    /// An out-of-range value sets [`Editor::error`] and changes nothing.
    pub fn set_strength(&mut self, v: f32) {
        self.set_property(Property::Strength, v);
    }

    /// Sets the radius (m), as [`Editor::set_strength`].
    pub fn set_radius(&mut self, v: f32) {
        self.set_property(Property::Radius, v);
    }

    /// Ends a slider gesture: the next change of the same property starts a new undo step
    /// (call it when the slider is released; without it, two separate drags of the same
    /// slider undo together).
    pub fn end_slider_edit(&mut self) {
        self.slider = None;
    }

    fn set_property(&mut self, property: Property, v: f32) {
        let Some(sel @ (g, p)) = self.selection else {
            self.error = Some(NOTHING_SELECTED.into());
            return;
        };
        // The root has no arrow of its own: there the value is the guide's.
        let point = (self.set.guides[g].points[p].parent.is_some()).then_some(p);
        self.apply(Some((sel, property)), |set| match property {
            Property::Strength => set.set_strength(g, point, v),
            Property::Radius => set.set_radius(g, point, v),
        });
    }

    /// Deletes the selection: a root takes its whole guide, any other point its arrow (its
    /// children are re-attached to its parent, see [`GuideSet::delete_point`]). The parent
    /// is selected afterwards (nothing after deleting a guide).
    pub fn delete_selected(&mut self) {
        let Some((g, p)) = self.selection else {
            self.error = Some(NOTHING_SELECTED.into());
            return;
        };
        self.drag = None;
        match self.set.guides[g].points[p].parent {
            None => {
                if self.apply(None, |set| set.delete_guide(g)).is_some() {
                    self.set_selection(None);
                }
            }
            Some(parent) => {
                // The parent's index is smaller than the point's, so the deletion, which
                // shifts only later points, leaves it as it is.
                if self.apply(None, |set| set.delete_point(g, p)).is_some() {
                    self.set_selection(Some((g, parent)));
                }
            }
        }
    }

    /// Undoes the last step; `false` if there is none.
    pub fn undo(&mut self) -> bool {
        let Some(step) = self.undo.pop() else {
            return false;
        };
        let now = self.restore(step);
        self.redo.push(now);
        true
    }

    /// Redoes the last undone step; `false` if there is none.
    pub fn redo(&mut self) -> bool {
        let Some(step) = self.redo.pop() else {
            return false;
        };
        let now = self.restore(step);
        self.undo.push(now);
        true
    }

    pub fn can_undo(&self) -> bool {
        !self.undo.is_empty()
    }

    pub fn can_redo(&self) -> bool {
        !self.redo.is_empty()
    }

    /// Takes new guides (after loading a scene): history, selection and drag are cleared.
    ///
    /// # Errors
    ///
    /// As [`Editor::new`]; the editor is unchanged then (except [`Editor::error`]).
    pub fn replace(&mut self, guides: Vec<Guide>, terrain_size: f32) -> Result<(), AgcError> {
        let set = GuideSet::from_guides(guides, terrain_size).inspect_err(|e| {
            self.error = Some(e.to_string());
        })?;
        self.set = set;
        self.undo.clear();
        self.redo.clear();
        self.selection = None;
        self.drag = None;
        self.slider = None;
        self.changed();
        Ok(())
    }

    fn exists(&self, (g, p): Selection) -> bool {
        self.set
            .guides
            .get(g)
            .is_some_and(|guide| p < guide.points.len())
    }

    fn set_selection(&mut self, s: Option<Selection>) {
        if s != self.selection {
            // A slider gesture belongs to one point.
            self.slider = None;
        }
        self.selection = s;
    }

    fn snapshot(&self) -> Snapshot {
        Snapshot {
            guides: self.set.guides.clone(),
            selection: self.selection,
        }
    }

    /// Puts `step` in place and returns the state it replaced.
    fn restore(&mut self, step: Snapshot) -> Snapshot {
        self.drag = None;
        self.slider = None;
        let now = self.snapshot();
        self.set.guides = step.guides;
        // Snapshots are taken with a valid selection, but stay defensive: a stale one
        // would index out of bounds in the getters.
        self.selection = step.selection.filter(|&s| self.exists(s));
        self.changed();
        now
    }

    /// Pushes an undo step; any new edit makes the redo steps meaningless.
    fn record(&mut self, before: Snapshot) {
        if self.undo.len() >= MAX_HISTORY {
            self.undo.remove(0);
        }
        self.undo.push(before);
        self.redo.clear();
    }

    fn changed(&mut self) {
        self.revision += 1;
        self.error = None;
    }

    /// Runs one edit through the guide set. On success the previous state becomes an undo
    /// step, unless nothing changed or it continues the same slider gesture (`slider`); on
    /// failure the reason goes to [`Editor::error`] and the guides stay as they were.
    fn apply<T>(
        &mut self,
        slider: Option<(Selection, Property)>,
        edit: impl FnOnce(&mut GuideSet) -> Result<T, AgcError>,
    ) -> Option<T> {
        let before = self.snapshot();
        match edit(&mut self.set) {
            Ok(value) => {
                if self.set.guides != before.guides {
                    // A structural edit in the middle of a drag would leave the drag's
                    // pending undo step stale (and its target possibly gone).
                    self.drag = None;
                    if slider.is_none() || slider != self.slider {
                        self.record(before);
                    }
                    self.slider = slider;
                    self.changed();
                } else {
                    self.error = None;
                    if slider != self.slider {
                        self.slider = None;
                    }
                }
                Some(value)
            }
            Err(e) => {
                // `GuideSet` changes nothing on error; restoring costs little and keeps
                // that promise here even if it were broken.
                self.set.guides = before.guides;
                self.error = Some(e.to_string());
                None
            }
        }
    }

    /// `v` pinned onto the terrain square.
    fn clamp(&self, v: Vec2) -> Vec2 {
        let half = self.set.terrain_size() / 2.0;
        v.clamp(Vec2::splat(-half), Vec2::splat(half))
    }
}

#[cfg(test)]
mod tests;
