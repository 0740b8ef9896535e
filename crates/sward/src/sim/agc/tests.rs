//! Tests of `agc`.

use std::path::Path;

use super::*;
use crate::scene::{GlobalWind, Sphere};

const SIZE: f32 = 32.0;

fn set() -> GuideSet {
    GuideSet::new(SIZE).unwrap()
}

fn parents_before_children(set: &GuideSet) {
    set.check().unwrap();
    for g in &set.guides {
        assert_eq!(g.points[0].parent, None);
        for (i, p) in g.points.iter().enumerate().skip(1) {
            assert!(p.parent.unwrap() < i, "{g:?}");
        }
    }
}

#[test]
fn branching_gives_one_arrow_per_child() {
    let mut s = set();
    let g = s.add_guide((0.0, 0.0), 5.0, 1.0).unwrap();
    for end in [(3.0, 0.0), (0.0, 3.0), (-3.0, 0.0)] {
        s.add_child(g, 0, end).unwrap();
    }
    let arrows = arrows(&s.guides);
    assert_eq!(arrows.len(), 3);
    for a in &arrows {
        assert_eq!((a.depth, a.start_point, a.start_distance), (0, 0, 0.0));
        assert_eq!((a.strength, a.radius), (5.0, 1.0));
    }
    // A second level hangs off point 2 and starts 3 m from the root.
    let p = s.add_child(g, 2, (0.0, 7.0)).unwrap();
    let a = *arrows_of(&s).last().unwrap();
    assert_eq!((a.end_point, a.depth, a.start_distance), (p, 1, 3.0));
    parents_before_children(&s);
}

fn arrows_of(s: &GuideSet) -> Vec<Arrow> {
    arrows(&s.guides)
}

#[test]
fn deleting_a_point_reattaches_its_children() {
    let mut s = set();
    let g = s.add_guide((0.0, 0.0), 5.0, 1.0).unwrap();
    let a = s.add_child(g, 0, (2.0, 0.0)).unwrap(); // 1
    let b = s.add_child(g, a, (4.0, 0.0)).unwrap(); // 2
    s.add_child(g, a, (2.0, 2.0)).unwrap(); // 3
    s.add_child(g, b, (6.0, 0.0)).unwrap(); // 4
    s.set_strength(g, Some(b), 9.0).unwrap();

    s.delete_point(g, a).unwrap();
    let pts = &s.guides[g].points;
    assert_eq!(pts.len(), 4);
    // The old points 2, 3 hang off the root now; old 4 keeps its parent (old 2 = new 1).
    assert_eq!(pts[1].position, (4.0, 0.0));
    assert_eq!(pts[1].parent, Some(0));
    assert_eq!(pts[1].strength, Some(9.0));
    assert_eq!(pts[2].parent, Some(0));
    assert_eq!((pts[3].position, pts[3].parent), ((6.0, 0.0), Some(1)));
    parents_before_children(&s);
    let arrows = arrows_of(&s);
    assert_eq!(arrows.len(), 3);
    assert_eq!(arrows[2].start_distance, 4.0);
}

#[test]
fn deleting_the_root_deletes_the_guide() {
    let mut s = set();
    let first = s.add_guide((0.0, 0.0), 5.0, 1.0).unwrap();
    s.add_child(first, 0, (1.0, 0.0)).unwrap();
    let second = s.add_guide((5.0, 5.0), 2.0, 1.0).unwrap();
    s.add_child(second, 0, (6.0, 5.0)).unwrap();
    s.delete_point(first, 0).unwrap();
    assert_eq!(s.guides.len(), 1);
    assert_eq!(s.guides[0].points[0].position, (5.0, 5.0));
    let removed = s.delete_guide(0).unwrap();
    assert_eq!(removed.strength, 2.0);
    assert!(s.guides.is_empty());
    assert_eq!(
        s.delete_guide(0),
        Err(AgcError::NoGuide { guide: 0, count: 0 })
    );
}

#[test]
fn invariant_holds_after_a_sequence_of_edits() {
    let mut s = set();
    let g = s.add_guide((-10.0, -10.0), 3.0, 2.0).unwrap();
    // A fixed LCG (Knuth's MMIX constants): reproducible and needs no dependency.
    let mut state = 5u64;
    let mut next = move || {
        state = state
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        state >> 33
    };
    for step in 0..200 {
        let n = s.guides[g].points.len();
        let pick = (next() as usize) % n;
        let pos = (
            (next() % 300) as f32 / 10.0 - 15.0,
            (next() % 300) as f32 / 10.0 - 15.0,
        );
        // Grow more than shrink so that the tree gets deep and bushy.
        match step % 5 {
            0 if pick > 0 => {
                let _ = s.delete_point(g, pick);
            }
            1 => {
                let _ = s.move_point(g, pick, pos);
            }
            _ => {
                let _ = s.add_child(g, pick, pos);
            }
        }
        parents_before_children(&s);
        assert_eq!(arrows_of(&s).len(), s.guides[g].points.len() - 1);
    }
}

#[test]
fn invalid_edits_are_refused_and_change_nothing() {
    let mut s = set();
    assert_eq!(
        s.add_guide((17.0, 0.0), 1.0, 1.0),
        Err(AgcError::OutsideTerrain {
            x: 17.0,
            z: 0.0,
            half: 16.0
        })
    );
    assert!(matches!(
        s.add_guide((0.0, 0.0), 1.0, 0.0),
        Err(AgcError::Radius { .. })
    ));
    assert!(matches!(
        s.add_guide((0.0, 0.0), 1.0, -2.0),
        Err(AgcError::Radius { .. })
    ));
    assert!(matches!(
        s.add_guide((f32::NAN, 0.0), 1.0, 1.0),
        Err(AgcError::NotFinite { .. })
    ));
    assert!(matches!(
        s.add_guide((0.0, 0.0), f32::INFINITY, 1.0),
        Err(AgcError::NotFinite { .. })
    ));
    assert!(s.guides.is_empty());
    assert_eq!(
        s.add_guide((0.0, 20.0), 1.0, 1.0).unwrap_err().to_string(),
        "position (0, 20) is outside the terrain: allowed -16 ..= 16 on x and z"
    );
    assert_eq!(
        s.add_guide((0.0, 0.0), 1.0, 0.0).unwrap_err().to_string(),
        "radius = 0 is out of range: allowed 0 < radius <= 32 m (the terrain size)"
    );

    let g = s.add_guide((0.0, 0.0), 1.0, 1.0).unwrap();
    let p = s.add_child(g, 0, (2.0, 0.0)).unwrap();
    let before = s.clone();
    assert_eq!(
        s.add_child(g, p, (2.0, 0.00005)).unwrap_err().to_string(),
        "point 2 at (2, 0.00005) would be within 0.0001 m of point 1: an arrow needs a \
         length > 0"
    );
    assert!(matches!(
        s.add_child(g, 0, (0.0, -16.5)),
        Err(AgcError::OutsideTerrain { .. })
    ));
    assert!(matches!(
        s.add_child(g, 0, (0.0, f32::NAN)),
        Err(AgcError::NotFinite { .. })
    ));
    assert!(matches!(
        s.add_child(g, 5, (1.0, 1.0)),
        Err(AgcError::NoPoint { .. })
    ));
    // Moving the end onto the root, or the root onto the end.
    assert!(matches!(
        s.move_point(g, p, (0.0, 0.0)),
        Err(AgcError::ZeroLength { .. })
    ));
    assert!(matches!(
        s.move_point(g, 0, (2.0, 0.0)),
        Err(AgcError::ZeroLength { .. })
    ));
    assert_eq!(
        s.set_strength(g, Some(0), 2.0),
        Err(AgcError::RootHasNoArrow)
    );
    assert!(matches!(
        s.set_radius(g, Some(p), 0.0),
        Err(AgcError::Radius { .. })
    ));
    assert!(matches!(
        s.set_radius(g, None, f32::NAN),
        Err(AgcError::NotFinite { .. })
    ));
    assert!(matches!(
        s.set_strength(g, None, -1.0),
        Err(AgcError::Strength { .. })
    ));
    assert_eq!(s, before);

    // Deleting a point whose child lies on its parent would leave a zero-length arrow.
    let q = s.add_child(g, p, (4.0, 0.0)).unwrap();
    s.add_child(g, q, (2.0, 0.0)).unwrap();
    let before = s.clone();
    assert!(matches!(
        s.delete_point(g, q),
        Err(AgcError::ZeroLength { .. })
    ));
    assert_eq!(s, before);
    assert!(GuideSet::new(0.0).is_err());
}

#[test]
fn overrides_apply_to_the_arrow_that_ends_at_the_point() {
    let mut s = set();
    let g = s.add_guide((0.0, 0.0), 4.0, 1.0).unwrap();
    let a = s.add_child(g, 0, (1.0, 0.0)).unwrap();
    let b = s.add_child(g, 0, (0.0, 1.0)).unwrap();
    s.set_strength(g, Some(b), 8.0).unwrap();
    s.set_radius(g, Some(b), 3.0).unwrap();
    s.set_radius(g, None, 2.0).unwrap();
    let arrows = arrows_of(&s);
    assert_eq!((arrows[0].end_point, arrows[0].strength), (a, 4.0));
    assert_eq!(arrows[0].radius, 2.0);
    assert_eq!((arrows[1].strength, arrows[1].radius), (8.0, 3.0));
    s.clear_overrides(g, b).unwrap();
    assert_eq!(arrows_of(&s)[1].radius, 2.0);
}

/// Each guide's sequence starts when the guide does: a guide added at t = 5 s leaves
/// the first guide's arrows on and switches its own on from t = 5 s; a restart at
/// t = 9 s switches the restarted guide's arrows off and on again.
#[test]
fn each_guide_starts_its_sequence_when_it_is_created_or_restarted() {
    let mut s = set();
    let a = s.add_guide((0.0, 0.0), 10.0, 1.0).unwrap();
    s.add_child(a, 0, (3.0, 0.0)).unwrap();
    s.set_clock(5.0);
    let b = s.add_guide((0.0, 5.0), 10.0, 1.0).unwrap();
    s.add_child(b, 0, (3.0, 5.0)).unwrap();
    s.add_child(b, 1, (9.0, 5.0)).unwrap();
    assert_eq!((s.guides[a].started, s.guides[b].started), (0.0, 5.0));
    let arrows = arrows_of(&s);
    assert_eq!(arrows[0].switch_on_time(), 0.0);
    assert_eq!(arrows[1].switch_on_time(), 5.0);
    assert_eq!(arrows[2].switch_on_time(), 5.0 + 3.0 / FRONT_SPEED);
    // At t = 4.9 s only guide a's arrow pushes; at 5 + ramp the new root's arrow too.
    assert_eq!(arrows_at(&s.guides, 4.9).len(), 1);
    assert_eq!(arrows_at(&s.guides, 5.0 + RAMP_TIME).len(), 2);
    assert_eq!(arrows_at(&s.guides, 6.0 + RAMP_TIME).len(), 3);
    // Replay guide b at t = 9 s: its arrows are off again just after, a's stay on.
    s.set_clock(9.0);
    s.restart(Some(b)).unwrap();
    let after = arrows_at(&s.guides, 9.0 + 1e-3);
    assert_eq!(after.len(), 2, "a's arrow and b's root arrow ramping");
    assert!(after[1].strength < 0.01 * 10.0);
    assert_eq!(after[0].strength, 10.0);
    // Replay everything.
    s.set_clock(20.0);
    s.restart(None).unwrap();
    assert!(s.guides.iter().all(|g| g.started == 20.0));
    assert!(arrows_at(&s.guides, 19.9).is_empty());
    assert!(s.restart(Some(7)).is_err());
    // The overlay lists every arrow at full strength with its activation.
    let overlay = overlay_arrows(&s.guides, 19.9);
    assert_eq!(overlay.len(), 3);
    assert!(overlay
        .iter()
        .all(|a| a.strength == 10.0 && a.activation == 0.0));
    let overlay = overlay_arrows(&s.guides, 30.0);
    assert!(overlay.iter().all(|a| a.activation == 1.0));
    // A bad clock counts as 0.
    s.set_clock(f32::NAN);
    let c = s.add_guide((5.0, 5.0), 1.0, 1.0).unwrap();
    assert_eq!(s.guides[c].started, 0.0);
}

#[test]
fn arrows_switch_on_with_the_front_and_ramp_up() {
    let mut s = set();
    let g = s.add_guide((0.0, 0.0), 10.0, 1.0).unwrap();
    s.add_child(g, 0, (3.0, 0.0)).unwrap();
    s.add_child(g, 1, (3.0, 4.0)).unwrap();
    s.add_child(g, 2, (9.0, 4.0)).unwrap();
    let deep = arrows_of(&s)[2];
    assert_eq!((deep.depth, deep.start_distance), (2, 7.0));
    let t_on = 7.0 / FRONT_SPEED;
    assert_eq!(deep.switch_on_time(), t_on);

    // Before the front: only the two upstream arrows are there.
    let early = arrows_at(&s.guides, t_on - 0.01);
    assert_eq!(early.len(), 2);
    assert!(early
        .iter()
        .all(|a| a.segment[0] != 3.0 || a.segment[1] != 4.0));
    assert_eq!(deep.activation(t_on), 0.0);
    // Half-way up the ramp: half strength (smoothstep(0.5) = 0.5), strictly rising.
    let mid = arrows_at(&s.guides, t_on + RAMP_TIME / 2.0);
    assert_eq!(mid.len(), 3);
    assert!((mid[2].strength - 5.0).abs() < 1e-4, "{mid:?}");
    assert!(deep.activation(t_on + 0.1) < deep.activation(t_on + 0.2));
    // After the ramp: full strength, and it stays on.
    for t in [t_on + RAMP_TIME, t_on + RAMP_TIME + 0.01, 100.0] {
        let late = arrows_at(&s.guides, t);
        assert_eq!(late.len(), 3);
        assert_eq!(late[2].segment, [3.0, 4.0, 9.0, 4.0]);
        assert_eq!((late[2].strength, late[2].radius), (10.0, 1.0));
    }
    // Nothing at all at t = 0: even the root's arrows start from zero force.
    assert!(arrows_at(&s.guides, 0.0).is_empty());
}

#[test]
fn too_many_arrows_are_capped() {
    let mut s = GuideSet::new(1000.0).unwrap();
    let g = s.add_guide((0.0, 0.0), 1.0, 1.0).unwrap();
    for i in 0..MAX_ARROWS + 10 {
        s.add_child(g, 0, (1.0 + i as f32, 0.0)).unwrap();
    }
    assert_eq!(arrows_at(&s.guides, 10.0).len(), MAX_ARROWS);
}

#[test]
fn arrows_skip_broken_trees() {
    let guide = Guide {
        started: 0.0,
        strength: 1.0,
        radius: 1.0,
        points: vec![
            point((0.0, 0.0), None),
            point((1.0, 0.0), Some(3)), // parent after the point
            point((2.0, 0.0), Some(1)), // hangs off the broken one
            point((0.0, 1.0), Some(0)),
            point((0.0, 1.0), Some(3)), // zero length
        ],
    };
    let list = arrows(std::slice::from_ref(&guide));
    assert_eq!(list.len(), 1);
    assert_eq!(list[0].end_point, 3);
    assert!(matches!(
        GuideSet::from_guides(vec![guide], SIZE),
        Err(AgcError::Parent { point: 1, .. })
    ));
}

#[test]
fn guides_round_trip_through_a_scene_file() {
    let mut s = set();
    let g = s.add_guide((-4.0, 2.5), 7.5, 1.25).unwrap();
    let a = s.add_child(g, 0, (0.1, 2.5)).unwrap();
    s.add_child(g, a, (3.0, 6.0)).unwrap();
    s.add_child(g, a, (3.0, -1.0 / 3.0)).unwrap();
    s.set_strength(g, Some(a), 12.0).unwrap();
    let h = s.add_guide((10.0, -10.0), 2.0, 0.5).unwrap();
    s.add_child(h, 0, (12.0, -10.0)).unwrap();

    let mut scene = Scene::default();
    scene.terrain.size = SIZE;
    scene.wind.guides = s.guides.clone();
    let text = ron::to_string(&scene).unwrap();
    let loaded = crate::scene::parse_scene(&text, Path::new("<inline>")).unwrap();
    assert_eq!(loaded.wind.guides, s.guides, "{text}");
    let back = GuideSet::from_guides(loaded.wind.guides, loaded.terrain.size).unwrap();
    assert_eq!(back, s);
}

#[test]
fn fluid_forces_collects_every_source() {
    let terrain = HeightField::flat(SIZE, 2);
    let mut scene = Scene::default();
    scene.terrain.size = SIZE;
    scene.wind.global = Some(GlobalWind {
        direction: (3.0, 4.0),
        strength: 2.0,
    });
    scene.wind.downwash = Some(Downwash {
        position: (0.0, 5.0, 0.0),
        radius: 4.0,
        strength: 3.0,
        motion: Motion::Path {
            points: vec![(0.0, 0.0), (10.0, 0.0)],
            speed: 2.0,
            looped: false,
        },
    });
    scene.colliders = vec![
        Sphere {
            center: (1.0, 0.5, 2.0),
            radius: 0.5,
            motion: Motion::Velocity((3.0, 0.0, -1.0)),
        },
        Sphere {
            center: (0.0, 0.5, 0.0),
            radius: 1.0,
            motion: Motion::Path {
                points: vec![(0.0, 0.0), (0.0, 10.0)],
                speed: 4.0,
                looped: false,
            },
        },
    ];
    let mut s = set();
    let g = s.add_guide((0.0, 0.0), 1.0, 1.0).unwrap();
    s.add_child(g, 0, (1.0, 0.0)).unwrap();
    scene.wind.guides = s.guides;

    let f = fluid_forces(&scene, &terrain, 1.5);
    assert!((f.global[0] - 1.2).abs() < 1e-6 && (f.global[1] - 1.6).abs() < 1e-6);
    assert_eq!(f.downwash, [3.0, 0.0, 4.0, 3.0]);
    assert_eq!(f.arrows.len(), 1);
    assert_eq!(f.obstacles.len(), 2);
    let o = f.obstacles[0];
    assert!((o.circle[0] - 5.5).abs() < 1e-4 && (o.circle[1] - 0.5).abs() < 1e-4);
    assert_eq!(o.circle[2], 0.5);
    assert!((o.velocity[0] - 3.0).abs() < 1e-2 && (o.velocity[1] + 1.0).abs() < 1e-2);
    assert_eq!(f.obstacles[1].circle[..3], [0.0, 6.0, 1.0]);
    assert!((f.obstacles[1].velocity[1] - 4.0).abs() < 1e-2);
    // At t = 0 a path collider already moves at its full speed.
    let f0 = fluid_forces(&scene, &terrain, 0.0);
    assert!((f0.obstacles[1].velocity[1] - 4.0).abs() < 1e-2);

    scene.wind.fluid.obstacles = false;
    scene.wind.downwash.as_mut().unwrap().motion = Motion::Velocity((1.0, 0.0, 2.0));
    let f = fluid_forces(&scene, &terrain, 2.0);
    assert!(f.obstacles.is_empty());
    assert_eq!(f.downwash, [2.0, 4.0, 4.0, 3.0]);
    scene.wind.downwash = None;
    scene.wind.global = None;
    let f = fluid_forces(&scene, &terrain, 2.0);
    assert_eq!((f.global, f.downwash), ([0.0; 2], [0.0; 4]));
}
