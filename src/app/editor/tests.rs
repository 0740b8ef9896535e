//! Tests of `editor`.

use super::*;
use sward::scene::GuidePoint;

const SIZE: f32 = 32.0;

fn v(x: f32, z: f32) -> Vec2 {
    Vec2::new(x, z)
}

fn empty() -> Editor {
    Editor::new(Vec::new(), SIZE).expect("empty editor")
}

fn pt(position: (f32, f32), parent: Option<usize>) -> GuidePoint {
    GuidePoint {
        position,
        parent,
        strength: None,
        radius: None,
    }
}

/// One guide: 0 → 1 → 2 and 1 → 3.
fn tree() -> Editor {
    let guide = Guide {
        started: 0.0,
        strength: 4.0,
        radius: 1.5,
        points: vec![
            pt((0.0, 0.0), None),
            pt((4.0, 0.0), Some(0)),
            pt((8.0, 2.0), Some(1)),
            pt((8.0, -2.0), Some(1)),
        ],
    };
    Editor::new(vec![guide], SIZE).expect("tree editor")
}

#[test]
fn replaying_the_sequence_restarts_the_selected_guide_or_all() {
    let mut e = tree();
    e.set_clock(3.0);
    let revision = e.revision();
    e.replay_sequence();
    assert_eq!(e.guides()[0].started, 3.0);
    assert_eq!(e.revision(), revision + 1, "the arrows are uploaded again");
    assert!(!e.can_undo(), "a replay moves nothing: no undo step");
    // A new guide starts at the clock.
    e.set_clock(7.5);
    e.press(None, Some(v(-8.0, -8.0)), false);
    e.release();
    assert_eq!(e.guides().len(), 2);
    assert_eq!(e.guides()[1].started, 7.5);
    // With guide 1 selected only guide 1 restarts.
    e.set_clock(9.0);
    e.select(Some((1, 0)));
    e.replay_sequence();
    assert_eq!((e.guides()[0].started, e.guides()[1].started), (3.0, 9.0));
}

fn parents(e: &Editor, g: usize) -> Vec<Option<usize>> {
    e.guides()[g].points.iter().map(|p| p.parent).collect()
}

fn valid(e: &Editor) {
    GuideSet::from_guides(e.guides().to_vec(), SIZE).expect("guides stay valid");
    if let Some(s) = e.selection() {
        assert!(e.exists(s), "selection {s:?} exists");
    }
}

#[test]
fn click_on_the_ground_makes_a_root() {
    let mut e = empty();
    assert_eq!((e.new_strength, e.new_radius), (12.0, 2.5));
    e.press(None, Some(v(1.0, -2.0)), false);
    assert_eq!(e.guides().len(), 1);
    let g = &e.guides()[0];
    assert_eq!((g.strength, g.radius), (12.0, 2.5));
    assert_eq!(g.points, [pt((1.0, -2.0), None)]);
    assert_eq!(e.selection(), Some((0, 0)));
    assert!(e.is_dragging());
    // The drag that follows belongs to the same undo step as the new guide.
    e.drag(Some(v(2.0, -2.0)));
    e.drag(Some(v(3.0, -2.0)));
    e.release();
    assert!(!e.is_dragging());
    assert_eq!(e.guides()[0].points[0].position, (3.0, -2.0));
    assert!(e.undo());
    assert!(e.guides().is_empty());
    assert_eq!(e.selection(), None);
    assert!(!e.can_undo());
    // A click on the sky deselects.
    assert!(e.redo());
    e.select(Some((0, 0)));
    e.press(None, None, false);
    assert_eq!(e.selection(), None);
    assert_eq!(e.guides().len(), 1);
    // New guides take the current defaults.
    e.new_strength = 9.0;
    e.new_radius = 1.0;
    e.press(None, Some(v(-5.0, 5.0)), false);
    e.release();
    assert_eq!((e.guides()[1].strength, e.guides()[1].radius), (9.0, 1.0));
    assert_eq!(e.selection(), Some((1, 0)));
}

#[test]
fn alt_clicks_from_one_point_branch() {
    let mut e = empty();
    e.press(None, Some(v(0.0, 0.0)), false);
    e.release();
    e.press(None, Some(v(5.0, 1.0)), true);
    assert_eq!(e.selection(), Some((0, 1)));
    assert!(!e.is_dragging());
    e.select(Some((0, 0)));
    e.press(None, Some(v(5.0, -1.0)), true);
    assert_eq!(e.selection(), Some((0, 2)));
    assert_eq!(parents(&e, 0), [None, Some(0), Some(0)]);
    // From the new point: a chain.
    e.press(None, Some(v(9.0, -1.0)), true);
    assert_eq!(parents(&e, 0), [None, Some(0), Some(0), Some(2)]);
    assert_eq!(e.guides()[0].points[3].position, (9.0, -1.0));
    // Alt on a point with nothing selected grabs it instead.
    e.select(None);
    e.press(Some((0, 1)), Some(v(5.0, 1.0)), true);
    assert_eq!(e.selection(), Some((0, 1)));
    assert!(e.is_dragging());
    e.release();
    assert_eq!(e.guides()[0].points.len(), 4);
    valid(&e);
}

#[test]
fn drag_moves_the_point_and_one_undo_restores_it() {
    let mut e = tree();
    let before = e.guides().to_vec();
    // A click that does not move records nothing.
    e.press(Some((0, 2)), Some(v(8.0, 2.0)), false);
    e.drag(Some(v(8.0, 2.0)));
    e.release();
    assert!(!e.can_undo());
    assert_eq!(e.revision(), 0);

    e.press(Some((0, 2)), Some(v(8.0, 2.0)), false);
    assert_eq!(e.selection(), Some((0, 2)));
    for i in 1..=10 {
        e.drag(Some(v(8.0 + i as f32 * 0.5, 2.0)));
    }
    // Past the edge: pinned to it.
    e.drag(Some(v(40.0, 2.0)));
    // Off the terrain altogether: ignored.
    e.drag(None);
    e.release();
    assert_eq!(e.guides()[0].points[2].position, (16.0, 2.0));
    assert_eq!(e.revision(), 11);
    e.drag(Some(v(0.0, 9.0))); // no drag any more
    assert_eq!(e.guides()[0].points[2].position, (16.0, 2.0));
    assert!(e.undo());
    assert_eq!(e.guides(), before);
    assert!(!e.can_undo());
    assert_eq!(e.selection(), Some((0, 2)));

    // Dragging a point onto its parent is refused; the next good move clears the error.
    e.press(Some((0, 1)), None, false);
    e.drag(Some(v(0.0, 0.0)));
    assert!(
        e.error.as_deref().is_some_and(|m| m.contains("length")),
        "{:?}",
        e.error
    );
    assert_eq!(e.guides(), before);
    e.drag(Some(v(4.0, 1.0)));
    assert_eq!(e.error, None);
    e.release();
    assert_eq!(e.guides()[0].points[1].position, (4.0, 1.0));
    valid(&e);
}

#[test]
fn slider_changes_coalesce_into_one_undo_step() {
    let mut e = tree();
    e.select(Some((0, 2)));
    assert_eq!(e.strength_of_selected(), Some(4.0));
    for i in 0..10 {
        e.set_strength(5.0 + i as f32);
    }
    assert_eq!(e.guides()[0].points[2].strength, Some(14.0));
    assert_eq!(e.guides()[0].strength, 4.0);
    assert_eq!(e.strength_of_selected(), Some(14.0));
    assert_eq!(e.revision(), 10);
    assert!(e.undo());
    assert!(!e.can_undo(), "one step for the whole slider drag");
    assert_eq!(e.guides()[0].points[2].strength, None);

    // Another property, another point, or an explicit end: new steps.
    e.select(Some((0, 0)));
    e.set_radius(2.0);
    e.set_radius(3.0);
    assert_eq!(e.guides()[0].radius, 3.0);
    assert_eq!(e.radius_of_selected(), Some(3.0));
    e.set_strength(7.0);
    e.end_slider_edit();
    e.set_strength(8.0);
    e.select(Some((0, 1)));
    e.set_strength(8.0);
    assert_eq!(e.undo.len(), 4);
    // The override of point 1 keeps the guide's radius until set.
    assert_eq!(e.radius_of_selected(), Some(3.0));
    // Setting the same value again changes nothing and records nothing.
    let revision = e.revision();
    e.select(Some((0, 0)));
    e.set_strength(8.0);
    assert_eq!((e.revision(), e.undo.len()), (revision, 4));
}

#[test]
fn undo_redo_round_trip() {
    let mut e = tree();
    let mut states = vec![e.guides().to_vec()];
    e.press(None, Some(v(-10.0, -10.0)), false);
    e.release();
    states.push(e.guides().to_vec());
    e.add_child_of_selected();
    states.push(e.guides().to_vec());
    e.select(Some((0, 3)));
    e.set_radius(0.5);
    states.push(e.guides().to_vec());
    e.delete_selected();
    states.push(e.guides().to_vec());
    e.press(Some((0, 2)), None, false);
    e.drag(Some(v(1.0, 9.0)));
    e.release();
    states.push(e.guides().to_vec());

    for expected in states.iter().rev().skip(1) {
        assert!(e.undo());
        assert_eq!(e.guides(), expected.as_slice());
        valid(&e);
    }
    assert!(!e.undo());
    for expected in states.iter().skip(1) {
        assert!(e.redo());
        assert_eq!(e.guides(), expected.as_slice());
        valid(&e);
    }
    assert!(!e.redo());
    // A new edit after an undo drops the redo steps.
    e.undo();
    assert!(e.can_redo());
    e.select(Some((1, 0)));
    e.set_strength(1.0);
    assert!(!e.can_redo());
}

#[test]
fn add_child_continues_the_arrow() {
    let mut e = tree();
    e.select(Some((0, 1)));
    e.add_child_of_selected();
    assert_eq!(e.selection(), Some((0, 4)));
    assert_eq!(e.guides()[0].points[4].position, (7.0, 0.0));
    assert_eq!(e.guides()[0].points[4].parent, Some(1));
    // A root follows its first arrow; a lone root goes along +x.
    e.select(Some((0, 0)));
    e.add_child_of_selected();
    assert_eq!(e.guides()[0].points[5].position, (3.0, 0.0));
    e.press(None, Some(v(-5.0, 5.0)), false);
    e.release();
    e.add_child_of_selected();
    assert_eq!(e.guides()[1].points[1].position, (-2.0, 5.0));
    // At the edge: clamped onto the terrain.
    e.press(None, Some(v(15.0, -10.0)), false);
    e.release();
    e.add_child_of_selected();
    assert_eq!(e.guides()[2].points[1].position, (16.0, -10.0));
    // Pointing straight out of the edge there is no room: refused.
    e.add_child_of_selected();
    assert!(e.error.is_some());
    assert_eq!(e.guides()[2].points.len(), 2);
    valid(&e);
}

#[test]
fn delete_remaps_the_selection() {
    let mut e = tree();
    e.press(None, Some(v(-10.0, 10.0)), false);
    e.release();
    e.press(None, Some(v(-6.0, 10.0)), true);
    assert_eq!(e.selection(), Some((1, 1)));

    // Point 1 of guide 0: its children 2 and 3 hang from the root now, as points 1, 2.
    e.select(Some((0, 1)));
    e.delete_selected();
    assert_eq!(e.selection(), Some((0, 0)));
    assert_eq!(parents(&e, 0), [None, Some(0), Some(0)]);
    assert_eq!(e.guides()[0].points[1].position, (8.0, 2.0));
    valid(&e);

    // A root: the whole guide, later guides shift down, nothing selected.
    e.delete_selected();
    assert_eq!(e.selection(), None);
    assert_eq!(e.guides().len(), 1);
    assert_eq!(e.guides()[0].points[0].position, (-10.0, 10.0));
    e.select(Some((1, 0)));
    assert_eq!(e.selection(), None, "guide 1 is gone");
    e.select(Some((0, 1)));
    assert_eq!(e.selection(), Some((0, 1)));
    e.delete_selected();
    assert_eq!(e.selection(), Some((0, 0)));
    assert_eq!(e.guides()[0].points.len(), 1);

    // Undo brings the points back with the selection they had.
    assert!(e.undo());
    assert_eq!(e.selection(), Some((0, 1)));
    assert!(e.undo());
    assert_eq!(e.selection(), Some((0, 0)));
    assert_eq!(e.guides().len(), 2);
    assert!(e.undo());
    assert_eq!(e.selection(), Some((0, 1)));
    assert_eq!(e.guides()[0].points.len(), 4);
}

#[test]
fn refused_edits_set_the_error_and_keep_the_guides() {
    let mut e = tree();
    let before = e.guides().to_vec();
    let check = |e: &mut Editor, what: &str| {
        assert!(e.error.is_some(), "{what}: error expected");
        assert_eq!(e.guides(), before.as_slice(), "{what}");
        assert_eq!(e.revision(), 0, "{what}");
        assert!(!e.can_undo(), "{what}");
        e.error = None;
    };
    e.set_strength(1.0);
    check(&mut e, "nothing selected");
    e.delete_selected();
    check(&mut e, "delete with nothing selected");
    e.add_child_of_selected();
    check(&mut e, "child with nothing selected");

    e.select(Some((0, 2)));
    e.set_strength(-1.0);
    check(&mut e, "negative strength");
    e.set_strength(f32::NAN);
    check(&mut e, "NaN strength");
    e.set_radius(0.0);
    check(&mut e, "zero radius");
    e.set_radius(SIZE + 1.0);
    check(&mut e, "radius past the terrain");
    e.press(None, Some(v(30.0, 0.0)), true);
    check(&mut e, "child off the terrain");
    e.press(None, Some(v(8.0, 2.0)), true);
    check(&mut e, "zero-length child");
    e.new_strength = 2000.0;
    e.press(None, Some(v(-3.0, 3.0)), false);
    check(&mut e, "strength of a new guide");
    assert!(!e.is_dragging());
    e.new_strength = DEFAULT_STRENGTH;
    e.press(Some((0, 3)), None, false);
    e.drag(Some(v(4.0, 0.0)));
    check(&mut e, "drag onto the parent");
    e.release();

    // Point 3 moved onto the root: deleting point 1 would make a zero-length arrow 0 → 3.

    let mut e2 = tree();
    e2.select(Some((0, 3)));
    e2.press(Some((0, 3)), None, false);
    e2.drag(Some(v(0.0, 0.0)));
    e2.release();
    assert_eq!(e2.error, None);
    let moved = e2.guides().to_vec();
    e2.select(Some((0, 1)));
    e2.delete_selected();
    assert!(e2.error.as_deref().is_some_and(|m| m.contains("length")));
    assert_eq!(e2.guides(), moved.as_slice());
    assert_eq!(e2.selection(), Some((0, 1)));

    // The error stays until the next successful edit.
    e.select(Some((0, 2)));
    e.set_radius(0.0);
    assert!(e.error.is_some());
    e.set_radius(1.0);
    assert_eq!(e.error, None);
    assert!(Editor::new(before.clone(), 0.0).is_err());
    assert!(e.replace(before.clone(), -1.0).is_err());
    assert!(e.error.is_some());
    assert_eq!(e.guides()[0].points[2].radius, Some(1.0), "unchanged");
}

#[test]
fn revision_bumps_on_every_change() {
    let mut e = empty();
    assert_eq!(e.revision(), 0);
    e.press(None, Some(v(0.0, 0.0)), false);
    assert_eq!(e.revision(), 1);
    e.drag(Some(v(1.0, 0.0)));
    assert_eq!(e.revision(), 2);
    e.release();
    e.press(None, Some(v(4.0, 0.0)), true);
    assert_eq!(e.revision(), 3);
    e.set_strength(1.0);
    e.set_strength(2.0);
    assert_eq!(e.revision(), 5);
    e.set_strength(-2.0); // refused
    e.select(Some((0, 0)));
    e.press(Some((0, 0)), None, false); // selection, no change
    e.release();
    assert_eq!(e.revision(), 5);
    e.undo();
    assert_eq!(e.revision(), 6);
    e.redo();
    assert_eq!(e.revision(), 7);
    e.delete_selected();
    assert_eq!(e.revision(), 8);
    let guides = tree().guides().to_vec();
    e.replace(guides.clone(), SIZE).expect("replace");
    assert_eq!(e.revision(), 9);
    assert_eq!(e.guides(), guides.as_slice());
    assert!(!e.can_undo() && !e.can_redo());
    assert_eq!(e.selection(), None);
}

#[test]
fn random_sessions_keep_the_guides_valid_and_undo_to_the_start() {
    for seed in 0..5u64 {
        let start = tree();
        let mut e = start.clone();
        // A fixed LCG: reproducible without a dependency.
        let mut state = seed;
        let mut next = move |n: u64| {
            state = state
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            (state >> 33) % n
        };
        // Fewer operations than MAX_HISTORY, so that undo can always reach the start.
        for _ in 0..200 {
            let selection = if e.guides().is_empty() {
                None
            } else {
                let g = next(e.guides().len() as u64) as usize;
                Some((g, next(e.guides()[g].points.len() as u64) as usize))
            };
            let x = next(400) as f32 / 10.0 - 20.0;
            let z = next(400) as f32 / 10.0 - 20.0;
            let ground = Some(v(x, z));
            match next(9) {
                0 => e.press(selection, ground, false),
                1 => e.press(None, ground, next(2) == 0),
                2 => e.drag(ground),
                3 => e.release(),
                4 => e.add_child_of_selected(),
                5 => e.set_strength(next(1200) as f32 - 100.0),
                6 => e.set_radius(next(40) as f32 * 0.5),
                7 if next(3) == 0 => e.delete_selected(),
                8 => {
                    e.undo();
                }
                _ => e.select(selection),
            }
            valid(&e);
            assert_eq!(e.strength_of_selected().is_some(), e.selection().is_some());
        }
        while e.undo() {}
        assert_eq!(e.guides(), start.guides(), "seed {seed}");
    }
}
