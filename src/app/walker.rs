//! Walk mode (issue 29; the prairie thesis §6): the user steers the scene's animated
//! character. W/S walk it forward and back, A/D turn it, Shift runs; its feet stay on the
//! terrain, and its walk plays at the pace of the ground it covers (the distance walked
//! over its stride, in cycles of the animation), so the feet do not slide and it stands
//! still mid-step when it stops. Each frame the window hands the renderer the walker's
//! [`ObjectPose`]; the camera sits behind it (`CameraMode::Behind`).
//!
//! Pure logic on the CPU (no window, no GPU), unit-tested here; `tests/window.rs` walks the
//! figure of `walk.ron` through the window.

use std::f32::consts::TAU;

use glam::{Vec2, Vec3};

use sward::field::HeightField;
use sward::scene::{ObjectPose, Scene};
use sward::sim::colliders::{animation_time, object_origin, object_transform};

/// Walking speed in m/s (the pace of `walk.ron`'s path).
pub const WALK_SPEED: f32 = 1.4;
/// Speed multiplier while Shift is held.
pub const RUN_FACTOR: f32 = 2.2;
/// Walking backwards is slower than forwards.
pub const BACK_FACTOR: f32 = 0.6;
/// How fast the ground speed follows the keys, m/s².
pub const ACCELERATION: f32 = 5.0;
/// Turning rate with A or D held, rad/s (a quarter turn in a second).
pub const TURN_RATE: f32 = std::f32::consts::FRAC_PI_2;
/// Metres per animation cycle for an object whose scene gives no `stride`.
pub const DEFAULT_STRIDE: f32 = 1.6;
/// Longest frame integrated per call: a hitch must not throw the walker across the map.
pub const MAX_DT: f32 = 0.25;

/// One frame of the walker's controls, from the held keys.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct WalkInput {
    /// W = +1, S = −1.
    pub forward: f32,
    /// D = +1 (turn right), A = −1.
    pub turn: f32,
    /// Shift: run.
    pub fast: bool,
}

/// The steered character's state.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Walker {
    /// Which of the scene's objects walks.
    pub object: usize,
    /// Its origin's (x, z) in metres.
    pub position: Vec2,
    /// Its heading in radians: it faces (sin h, 0, cos h) in the world (its +z turned by
    /// its rotation and its pose's yaw).
    pub heading: f32,
    /// The heading its scene `rotation` alone gives it: the pose's yaw is the rest of the
    /// turn.
    rest_heading: f32,
    /// Ground speed along the heading in m/s (negative: walking back).
    pub speed: f32,
    /// Signed distance walked, in metres, reduced to one stride (the walk's phase).
    pub phase: f32,
    /// Metres walked since it was taken over, forward and back alike.
    pub walked: f32,
    /// Height of its origin above the ground (the object's `translation.y`).
    lift: f32,
    /// Metres per animation cycle.
    stride: f32,
    /// The animation's length in seconds.
    duration: f32,
    /// Largest |x| and |z| (the terrain's walls, as the balls have).
    limit: f32,
}

impl Walker {
    /// Takes over the first animated object of `scene` where it is at `time` (its place,
    /// heading and walk phase carry on without a jump). `duration` gives an object's
    /// animation length. `None` when the scene has no animated object.
    pub fn take(
        scene: &Scene,
        terrain: &HeightField,
        time: f32,
        duration: impl Fn(usize) -> Option<f32>,
    ) -> Option<Self> {
        let (object, o, duration) = scene.objects.iter().enumerate().find_map(|(i, o)| {
            let d = duration(i).filter(|d| *d > 0.0 && d.is_finite())?;
            o.animation.is_some().then_some((i, o, d))
        })?;
        let origin = object_origin(o, terrain, time);
        let stride = if o.stride > 0.0 {
            o.stride
        } else {
            DEFAULT_STRIDE
        };
        let cycles = animation_time(o, duration, time) / duration;
        let w = Self {
            object,
            position: Vec2::new(origin.x, origin.z),
            heading: facing_of(&object_transform(o, terrain, time)),
            rest_heading: facing_of(&o.transform_at(origin)),
            speed: 0.0,
            phase: (cycles * stride).rem_euclid(stride),
            walked: 0.0,
            lift: o.translation.1,
            stride,
            duration,
            limit: (0.5 * terrain.size).max(0.0),
        };
        w.is_finite().then_some(w)
    }

    /// The unit vector the walker faces, on the ground.
    pub fn facing(&self) -> Vec2 {
        let (s, c) = self.heading.sin_cos();
        Vec2::new(s, c)
    }

    /// Advances the walker by `dt` seconds (at most [`MAX_DT`]): turns, speeds up or slows
    /// towards the speed the keys ask for, and walks, staying inside the terrain's walls
    /// (a wall stops it, and its feet with it). Non-finite input does nothing.
    pub fn step(&mut self, input: WalkInput, dt: f32) {
        let before = *self;
        if !dt.is_finite() {
            return;
        }
        let dt = dt.clamp(0.0, MAX_DT);
        let forward = finite_axis(input.forward);
        let turn = finite_axis(input.turn);
        // D turns right: seen from behind, right is the heading decreasing.
        self.heading = (self.heading - turn * TURN_RATE * dt).rem_euclid(TAU);
        let pace = if input.fast { RUN_FACTOR } else { 1.0 };
        let back = if forward < 0.0 { BACK_FACTOR } else { 1.0 };
        let wanted = forward * WALK_SPEED * pace * back;
        let change = (wanted - self.speed).clamp(-ACCELERATION * dt, ACCELERATION * dt);
        self.speed += change;
        let start = self.position;
        let to = start + self.facing() * self.speed * dt;
        self.position = to.clamp(Vec2::splat(-self.limit), Vec2::splat(self.limit));
        // The feet cover what the body covered along its heading (nothing into a wall).
        let walked = (self.position - start).dot(self.facing());
        if self.position != to {
            self.speed = 0.0;
        }
        self.phase = (self.phase + walked).rem_euclid(self.stride);
        self.walked += walked.abs();
        if !self.is_finite() {
            *self = before;
        }
    }

    /// Where the renderer draws the walker: its origin on the terrain under it (plus its
    /// lift), turned to its heading, posed at its walk phase, moving at its ground speed.
    pub fn pose(&self, terrain: &HeightField) -> ObjectPose {
        let (x, z) = (self.position.x, self.position.y);
        let facing = self.facing() * self.speed;
        ObjectPose {
            origin: Vec3::new(x, terrain.height(x, z) + self.lift, z),
            yaw: self.heading - self.rest_heading,
            animation_time: self.phase / self.stride * self.duration,
            velocity: Vec3::new(facing.x, 0.0, facing.y),
        }
    }

    fn is_finite(&self) -> bool {
        self.position.is_finite()
            && self.heading.is_finite()
            && self.rest_heading.is_finite()
            && self.speed.is_finite()
            && self.phase.is_finite()
            && self.walked.is_finite()
    }
}

/// The heading a transform turns an object's +z to, about the vertical (0 along +z, π/2
/// along +x); 0 when it points straight up or down.
fn facing_of(m: &glam::Mat4) -> f32 {
    let f = m.transform_vector3(Vec3::Z);
    let h = f.x.atan2(f.z);
    if h.is_finite() && (f.x != 0.0 || f.z != 0.0) {
        h.rem_euclid(TAU)
    } else {
        0.0
    }
}

fn finite_axis(v: f32) -> f32 {
    if v.is_finite() {
        v.clamp(-1.0, 1.0)
    } else {
        0.0
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use sward::scene::{MeshObject, Motion};

    /// A 100 m square of hills (about ±3 m): the feet must follow them.
    fn terrain() -> HeightField {
        let mut field = HeightField::flat(100.0, 101);
        let res = field.resolution;
        for j in 0..res {
            for i in 0..res {
                let p = field.vertex(i, j);
                field.heights[(j * res + i) as usize] =
                    2.0 * (p.x * 0.2).sin() * (p.z * 0.15).cos() + (p.z * 0.1).sin();
            }
        }
        field
    }

    fn scene_with_walker(motion: Motion) -> Scene {
        Scene {
            objects: vec![
                MeshObject::default(),
                MeshObject {
                    animation: Some("walk".into()),
                    translation: (0.0, 0.05, 0.0),
                    stride: 2.0,
                    motion,
                    ..MeshObject::default()
                },
            ],
            ..Scene::default()
        }
    }

    fn animated(i: usize) -> Option<f32> {
        (i == 1).then_some(1.0)
    }

    #[test]
    fn takes_over_a_path_walker_where_it_is() {
        let terrain = terrain();
        // Walking +x along the path at 1 m/s: after 3 s at (3, 0), facing +x, 1.5 cycles in.
        let s = scene_with_walker(Motion::Path {
            points: vec![(0.0, 0.0), (10.0, 0.0)],
            speed: 1.0,
            looped: false,
        });
        let w = Walker::take(&s, &terrain, 3.0, animated).unwrap();
        assert_eq!(w.object, 1);
        assert!((w.position - Vec2::new(3.0, 0.0)).length() < 1e-4, "{w:?}");
        assert!((w.facing() - Vec2::X).length() < 1e-3, "{:?}", w.facing());
        // The phase carries on: 3 m over a 2 m stride is half a cycle into the second.
        assert!((w.phase - 1.0).abs() < 1e-4, "{}", w.phase);
        let pose = w.pose(&terrain);
        let path = object_transform(&s.objects[1], &terrain, 3.0);
        let mut posed = s.objects[1].clone();
        posed.pose = Some(pose);
        let steered = object_transform(&posed, &terrain, 3.0);
        assert!(
            steered.abs_diff_eq(path, 1e-4),
            "taking over moved it: {steered} vs {path}"
        );
        // No animated object: nothing to take.
        assert!(Walker::take(&s, &terrain, 0.0, |_| None).is_none());
    }

    #[test]
    fn w_walks_forward_at_walking_speed_and_the_walk_keeps_pace() {
        let terrain = terrain();
        let s = scene_with_walker(Motion::Static);
        let mut w = Walker::take(&s, &terrain, 0.0, animated).unwrap();
        let start = w.position;
        let input = WalkInput {
            forward: 1.0,
            ..WalkInput::default()
        };
        let dt = 1.0 / 60.0;
        for _ in 0..(60 * 4) {
            w.step(input, dt);
        }
        assert!((w.speed - WALK_SPEED).abs() < 1e-4, "{}", w.speed);
        // Accelerating for WALK_SPEED / ACCELERATION s costs half that time's distance.
        let expected = WALK_SPEED * 4.0 - 0.5 * WALK_SPEED * WALK_SPEED / ACCELERATION;
        let walked = (w.position - start).dot(Vec2::Y);
        assert!((walked - expected).abs() < 0.03, "{walked} vs {expected}");
        assert!((w.walked - walked).abs() < 1e-3);
        // The phase is the distance over the stride (2 m), in cycles of the 1 s walk.
        let cycles = walked / 2.0;
        let pose = w.pose(&terrain);
        let want = cycles.fract();
        assert!(
            (pose.animation_time - want).abs() < 2e-3,
            "{} vs {want}",
            pose.animation_time
        );
        assert!((pose.velocity - Vec3::Z * WALK_SPEED).length() < 1e-3);
        // Feet on the ground: the origin rides the terrain plus the object's lift.
        let h = terrain.height(w.position.x, w.position.y);
        assert!((pose.origin.y - (h + 0.05)).abs() < 1e-5);
    }

    #[test]
    fn a_and_d_turn_s_walks_back_slower_and_standing_still_holds_the_step() {
        let terrain = terrain();
        let s = scene_with_walker(Motion::Static);
        let mut w = Walker::take(&s, &terrain, 0.0, animated).unwrap();
        let dt = 1.0 / 60.0;
        // D for one second: a quarter turn to the right, from +z to −x.
        for _ in 0..60 {
            w.step(
                WalkInput {
                    turn: 1.0,
                    ..WalkInput::default()
                },
                dt,
            );
        }
        assert!(
            (w.facing() - Vec2::NEG_X).length() < 1e-3,
            "{:?}",
            w.facing()
        );
        for _ in 0..120 {
            w.step(
                WalkInput {
                    forward: -1.0,
                    ..WalkInput::default()
                },
                dt,
            );
        }
        assert!((w.speed + WALK_SPEED * BACK_FACTOR).abs() < 1e-4);
        assert!(w.position.x > 0.5, "walking back from facing −x goes +x");
        // Let go: it stops, and the walk's phase stops with it.
        for _ in 0..60 {
            w.step(WalkInput::default(), dt);
        }
        let phase = w.phase;
        for _ in 0..60 {
            w.step(WalkInput::default(), dt);
        }
        assert_eq!((w.speed, w.phase), (0.0, phase));
    }

    #[test]
    fn a_figure_turned_in_the_scene_walks_the_way_it_faces() {
        let terrain = terrain();
        let mut s = scene_with_walker(Motion::Static);
        // Turned a quarter about y: its +z faces +x.
        s.objects[1].rotation = (0.0, 90.0, 0.0);
        let mut w = Walker::take(&s, &terrain, 0.0, animated).unwrap();
        assert!((w.facing() - Vec2::X).length() < 1e-4, "{:?}", w.facing());
        let start = w.position;
        for _ in 0..60 {
            w.step(
                WalkInput {
                    forward: 1.0,
                    ..WalkInput::default()
                },
                1.0 / 60.0,
            );
        }
        let moved = w.position - start;
        assert!(moved.x > 0.5 && moved.y.abs() < 1e-4, "{moved}");
        // Drawn as it stands: the pose adds no turn to its rotation yet.
        let mut posed = s.objects[1].clone();
        posed.pose = Some(w.pose(&terrain));
        let m = object_transform(&posed, &terrain, 0.0);
        let f = m.transform_vector3(Vec3::Z);
        assert!((f.normalize() - Vec3::X).length() < 1e-4, "{f}");
    }

    #[test]
    fn walls_stop_it_and_bad_input_changes_nothing() {
        let terrain = terrain();
        let s = scene_with_walker(Motion::Static);
        let mut w = Walker::take(&s, &terrain, 0.0, animated).unwrap();
        let run = WalkInput {
            forward: 1.0,
            fast: true,
            ..WalkInput::default()
        };
        for _ in 0..4000 {
            w.step(run, 0.05);
        }
        assert!(
            w.position.y <= 50.0 && w.position.y > 49.0,
            "{:?}",
            w.position
        );
        let held = w;
        w.step(run, f32::NAN);
        w.step(
            WalkInput {
                forward: f32::INFINITY,
                turn: f32::NAN,
                fast: false,
            },
            1e30,
        );
        assert!(w.is_finite());
        assert!(w.position.y <= 50.0 && held.position.y <= 50.0);
    }
}
