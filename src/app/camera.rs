//! The interactive camera controller: a fly camera (WASD + QE, right-drag to look), an
//! orbit camera around a point, and a follow camera that orbits a moving object (the
//! steered ball), and a camera behind the walking character (walk mode). It turns one frame of input into a [`CameraView`] for the renderer.
//!
//! The state is yaw/pitch angles rather than a target point so that looking around is a
//! plain addition and the pitch clamp keeps `look_at` away from its singularity. Every
//! mode ends the frame with the eye at least `min_clearance` above the terrain, because a
//! camera under the ground shows nothing but the underside of the field. The controller
//! is pure logic (no window), so it is unit-tested here.

use std::f32::consts::{PI, TAU};

use glam::{Vec2, Vec3};

use sward::field::HeightField;
use sward::render::camera::CameraView;

/// Radians of yaw/pitch per pixel dragged.
pub const LOOK_RADIANS_PER_PIXEL: f32 = 0.004;
/// Speed multiplier while Shift is held.
pub const FAST_FACTOR: f32 = 4.0;
/// Fly speed multiplier per mouse-wheel line.
pub const SPEED_STEP: f32 = 1.2;
/// Fly speed range in m/s.
pub const MIN_SPEED: f32 = 0.5;
pub const MAX_SPEED: f32 = 200.0;
/// Orbit distance multiplier per mouse-wheel line (wheel up = closer).
pub const ZOOM_STEP: f32 = 0.9;
/// Orbit distance range in metres.
pub const MIN_DISTANCE: f32 = 1.0;
pub const MAX_DISTANCE: f32 = 500.0;
/// Time constant of the follow camera's smoothing, in seconds.
pub const FOLLOW_TIME_CONSTANT: f32 = 0.15;
/// Longest frame the controller integrates: a hitch (window drag, breakpoint) must not
/// throw the camera across the map.
pub const MAX_DT: f32 = 0.25;
/// Pitch limit: 89° keeps the view direction away from the world up vector, where the
/// yaw would become meaningless.
pub const MAX_PITCH: f32 = 89.0 * std::f32::consts::PI / 180.0;
/// Default fly speed in m/s.
pub const DEFAULT_SPEED: f32 = 6.0;
/// Default height of the eye above the ground, in metres.
pub const DEFAULT_CLEARANCE: f32 = 0.4;
/// Wheel lines accepted per frame: beyond this the multipliers only saturate the clamps,
/// and a bounded exponent keeps `powf` finite.
const MAX_SCROLL: f32 = 100.0;

/// How the camera reacts to input.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum CameraMode {
    /// Free flight: WASD along the view, QE up and down.
    Fly,
    /// Rotate around `orbit_center`; WASD/QE pan the centre.
    Orbit,
    /// Orbit a moving point (the steered ball); the centre trails it smoothly.
    Follow,
    /// Behind the walking character at `orbit_distance`, turning with it (`track_heading`):
    /// the prairie thesis's camera. Right-drag tilts it, the wheel moves it nearer.
    Behind,
}

/// Time constant with which the camera behind the walker swings round after it turns, in
/// seconds: slower than the walker itself, so a turn reads on screen.
pub const BEHIND_TIME_CONSTANT: f32 = 0.35;
/// Distance and tilt the camera takes behind the walker when walk mode starts.
pub const BEHIND_DISTANCE: f32 = 4.5;
pub const BEHIND_PITCH: f32 = -0.3;

/// One frame of camera input, already mapped from keys and mouse by the window code.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct CameraInput {
    /// W = +1, S = −1.
    pub forward: f32,
    /// D = +1, A = −1.
    pub right: f32,
    /// E = +1, Q = −1.
    pub up: f32,
    /// Shift: move four times faster.
    pub fast: bool,
    /// Pixels dragged with the right button since the last frame (x right, y down).
    pub look: Vec2,
    /// Mouse-wheel lines since the last frame (+ = away from the user / up).
    pub scroll: f32,
}

/// The camera state the window keeps between frames.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CameraController {
    pub mode: CameraMode,
    pub eye: Vec3,
    /// Heading in radians: 0 looks along −z, π/2 along +x.
    pub yaw: f32,
    /// Elevation in radians, positive up, within ±89°.
    pub pitch: f32,
    /// Fly (and pan) speed in m/s.
    pub speed: f32,
    pub orbit_center: Vec3,
    pub orbit_distance: f32,
    /// Vertical field of view in degrees.
    pub fov_y: f32,
    pub near: f32,
    pub far: f32,
    /// Smallest height of the eye above the terrain, in metres.
    pub min_clearance: f32,
    /// The heading the walker faces (its +z towards (sin h, 0, cos h)), which the camera
    /// behind it turns to.
    pub walker_heading: f32,
    /// Radians the view turns left of the followed point in the follow and walk modes, so
    /// that the point shows in the middle of the 3D view beside the panel rather than in the
    /// middle of the window, under the panel (`centre_offset`).
    pub view_offset: f32,
}

impl CameraController {
    /// A fly camera showing exactly what `view` shows.
    pub fn from_view(view: &CameraView) -> Self {
        let eye = if view.eye.is_finite() {
            view.eye
        } else {
            Vec3::ZERO
        };
        let target = if view.target.is_finite() {
            view.target
        } else {
            eye + Vec3::NEG_Z
        };
        let (yaw, pitch) = angles_of(target - eye, 0.0);
        let distance = (target - eye).length();
        let orbit_distance = if distance.is_finite() {
            distance.clamp(MIN_DISTANCE, MAX_DISTANCE)
        } else {
            MIN_DISTANCE
        };
        Self {
            mode: CameraMode::Fly,
            eye,
            yaw,
            pitch,
            speed: DEFAULT_SPEED,
            orbit_center: target,
            orbit_distance,
            fov_y: view.fov_y,
            near: view.near,
            far: view.far,
            min_clearance: DEFAULT_CLEARANCE,
            walker_heading: 0.0,
            view_offset: 0.0,
        }
    }

    /// The view for the renderer: the target is one metre along [`Self::forward`] (turned
    /// by `view_offset` in the follow and walk modes).
    pub fn view(&self) -> CameraView {
        let forward = match self.mode {
            CameraMode::Follow | CameraMode::Behind if self.view_offset.is_finite() => {
                direction(self.yaw - self.view_offset, self.pitch)
            }
            _ => self.forward(),
        };
        CameraView {
            eye: self.eye,
            target: self.eye + forward,
            fov_y: self.fov_y,
            near: self.near,
            far: self.far,
        }
    }

    /// Unit view direction from yaw and pitch.
    pub fn forward(&self) -> Vec3 {
        direction(self.yaw, self.pitch)
    }

    /// Unit horizontal vector to the right of the view (what D moves along).
    pub fn right(&self) -> Vec3 {
        let (sy, cy) = self.yaw.sin_cos();
        Vec3::new(cy, 0.0, sy)
    }

    /// Unit horizontal vector the view faces (what W pans along in orbit mode).
    fn flat_forward(&self) -> Vec3 {
        let (sy, cy) = self.yaw.sin_cos();
        Vec3::new(sy, 0.0, -cy)
    }

    /// Advances the camera by one frame. `follow` is the followed object's centre (only
    /// read in [`CameraMode::Follow`]; with `None` the centre stays where it is).
    pub fn update(
        &mut self,
        input: &CameraInput,
        dt: f32,
        terrain: &HeightField,
        follow: Option<Vec3>,
    ) {
        let before = *self;
        let dt = if dt.is_finite() {
            dt.clamp(0.0, MAX_DT)
        } else {
            0.0
        };

        // Look: drag right turns right, drag down looks down. The yaw is wrapped so that
        // hours of turning do not eat its precision.
        let look = Vec2::new(finite_or_zero(input.look.x), finite_or_zero(input.look.y));
        self.yaw = (self.yaw + look.x * LOOK_RADIANS_PER_PIXEL).rem_euclid(TAU);
        self.pitch = (self.pitch - look.y * LOOK_RADIANS_PER_PIXEL).clamp(-MAX_PITCH, MAX_PITCH);
        if !self.yaw.is_finite() {
            self.yaw = before.yaw;
        }
        if !self.pitch.is_finite() {
            self.pitch = before.pitch;
        }

        let scroll = finite_or_zero(input.scroll).clamp(-MAX_SCROLL, MAX_SCROLL);
        let axes = Vec3::new(axis(input.right), axis(input.up), axis(input.forward));
        let fast = if input.fast { FAST_FACTOR } else { 1.0 };

        match self.mode {
            CameraMode::Fly => {
                self.speed = sanitize_speed(self.speed * SPEED_STEP.powf(scroll));
                // Diagonal key combinations are no faster than a single key.
                let dir = (self.forward() * axes.z + self.right() * axes.x + Vec3::Y * axes.y)
                    .clamp_length_max(1.0);
                self.eye += dir * self.speed * fast * dt;
            }
            CameraMode::Orbit => {
                self.zoom(scroll);
                // Panning on the ground plane: W moves the centre where the camera faces,
                // whatever the pitch, as in map and editor views.
                let dir = (self.flat_forward() * axes.z + self.right() * axes.x + Vec3::Y * axes.y)
                    .clamp_length_max(1.0);
                self.speed = sanitize_speed(self.speed);
                let mut center = self.orbit_center + dir * self.speed * fast * dt;
                // An orbit centre underground is never what the user wants to look at.
                center.y = center.y.max(ground(terrain, center));
                self.orbit_center = center;
                self.eye = self.orbit_center - self.forward() * self.orbit_distance;
            }
            CameraMode::Follow => {
                self.zoom(scroll);
                // WASD is left to the window (it steers the followed ball); the centre
                // trails the object with a frame-rate independent exponential.
                if let Some(target) = follow.filter(|t| t.is_finite()) {
                    let blend = 1.0 - (-dt / FOLLOW_TIME_CONSTANT).exp();
                    self.orbit_center += (target - self.orbit_center) * blend;
                }
                self.eye = self.orbit_center - self.forward() * self.orbit_distance;
            }
            CameraMode::Behind => {
                self.zoom(scroll);
                // WASD walks the character; the camera trails its chest and swings round
                // to its back, both with frame-rate independent exponentials.
                if let Some(target) = follow.filter(|t| t.is_finite()) {
                    let blend = 1.0 - (-dt / FOLLOW_TIME_CONSTANT).exp();
                    self.orbit_center += (target - self.orbit_center) * blend;
                }
                let turn = (yaw_behind(self.walker_heading) - self.yaw + PI).rem_euclid(TAU) - PI;
                let blend = 1.0 - (-dt / BEHIND_TIME_CONSTANT).exp();
                if turn.is_finite() {
                    self.yaw = (self.yaw + turn * blend).rem_euclid(TAU);
                }
                self.eye = self.orbit_center - self.forward() * self.orbit_distance;
            }
        }

        self.keep_above_ground(terrain);
        if !self.is_finite() {
            *self = before;
        }
    }

    /// Switches mode without a jump in the view. Orbit takes `point` as its centre when
    /// given (the eye stays and turns towards it), otherwise the point `orbit_distance`
    /// ahead. Follow needs the followed point and falls back to Fly without one.
    pub fn set_mode(&mut self, mode: CameraMode, point: Option<Vec3>) {
        let point = point.filter(|p| p.is_finite());
        match (mode, point) {
            (CameraMode::Fly, _) => self.mode = CameraMode::Fly,
            (CameraMode::Orbit, None) => {
                self.mode = CameraMode::Orbit;
                self.orbit_distance = sanitize_distance(self.orbit_distance);
                self.orbit_center = self.eye + self.forward() * self.orbit_distance;
            }
            (CameraMode::Orbit | CameraMode::Follow, Some(center)) => {
                self.mode = mode;
                self.aim_at(center);
            }
            (CameraMode::Follow | CameraMode::Behind, None) => self.mode = CameraMode::Fly,
            (CameraMode::Behind, Some(center)) => {
                // Straight behind the walker at once; it swings round with it after.
                self.mode = mode;
                self.yaw = yaw_behind(self.walker_heading);
                self.pitch = BEHIND_PITCH;
                self.orbit_distance = BEHIND_DISTANCE;
                self.orbit_center = center;
                self.eye = center - self.forward() * self.orbit_distance;
            }
        }
    }

    /// Tells the camera which way the walker faces now (read in [`CameraMode::Behind`]).
    /// A non-finite heading is ignored.
    pub fn track_heading(&mut self, heading: f32) {
        if heading.is_finite() {
            self.walker_heading = heading.rem_euclid(TAU);
        }
    }

    /// Makes `center` the orbit centre, keeping the eye (up to the distance clamp) and
    /// turning to face it.
    fn aim_at(&mut self, center: Vec3) {
        let offset = center - self.eye;
        let (yaw, pitch) = angles_of(offset, self.yaw);
        self.yaw = yaw;
        self.pitch = pitch;
        self.orbit_center = center;
        self.orbit_distance = sanitize_distance(offset.length());
        self.eye = center - self.forward() * self.orbit_distance;
    }

    fn zoom(&mut self, scroll: f32) {
        self.orbit_distance = sanitize_distance(self.orbit_distance * ZOOM_STEP.powf(scroll));
    }

    /// Lifts the eye to `min_clearance` above the terrain under it (sampled inside the
    /// square). Orbiting cameras then turn back towards their centre.
    fn keep_above_ground(&mut self, terrain: &HeightField) {
        let clearance = if self.min_clearance.is_finite() {
            self.min_clearance
        } else {
            DEFAULT_CLEARANCE
        };
        let floor = ground(terrain, self.eye) + clearance;
        if !floor.is_finite() || self.eye.y >= floor {
            return;
        }
        self.eye.y = floor;
        if self.mode != CameraMode::Fly {
            let offset = self.orbit_center - self.eye;
            if offset.length() > 1e-4 {
                let (yaw, pitch) = angles_of(offset, self.yaw);
                self.yaw = yaw;
                self.pitch = pitch;
            }
        }
    }

    fn is_finite(&self) -> bool {
        self.eye.is_finite()
            && self.yaw.is_finite()
            && self.pitch.is_finite()
            && self.speed.is_finite()
            && self.orbit_center.is_finite()
            && self.orbit_distance.is_finite()
    }
}

/// Yaw and pitch of a direction; a vertical direction keeps `fallback_yaw`.
fn angles_of(dir: Vec3, fallback_yaw: f32) -> (f32, f32) {
    let dir = dir.normalize_or(Vec3::NEG_Z);
    let pitch = dir.y.clamp(-1.0, 1.0).asin().clamp(-MAX_PITCH, MAX_PITCH);
    let yaw = if dir.x.hypot(dir.z) > 1e-6 {
        dir.x.atan2(-dir.z).rem_euclid(TAU)
    } else {
        fallback_yaw
    };
    (yaw, pitch)
}

/// Terrain height below `p`: the terrain's own height there (an unbounded terrain is a
/// function defined everywhere; a bounded one continues its edge heights), sampled at `p`
/// clamped into the square for a bounded terrain.
fn ground(terrain: &HeightField, p: Vec3) -> f32 {
    let half = 0.5 * terrain.size;
    let half = if half.is_finite() { half.abs() } else { 0.0 };
    if !(p.x.is_finite() && p.z.is_finite()) {
        return f32::NAN;
    }
    if terrain.unbounded {
        return terrain.height(p.x, p.z);
    }
    terrain.height(p.x.clamp(-half, half), p.z.clamp(-half, half))
}

/// The unit direction of a yaw and pitch (yaw 0 along −z, π/2 along +x).
fn direction(yaw: f32, pitch: f32) -> Vec3 {
    let (sy, cy) = yaw.sin_cos();
    let (sp, cp) = pitch.sin_cos();
    Vec3::new(sy * cp, sp, -cy * cp)
}

/// How far left (radians) a view of `size` pixels, whose 3D part starts `left` pixels from
/// the window's left edge, must turn for what it looks at to show in the middle of that
/// part: the angle of the part's centre off the window's centre, at vertical field of view
/// `fov_y` degrees.
pub fn centre_offset(size: (u32, u32), left: u32, fov_y: f32) -> f32 {
    let (w, h) = (size.0.max(1) as f32, size.1.max(1) as f32);
    // The part's centre in normalised x (−1 left, 1 right).
    let centre = left.min(size.0) as f32 / w;
    let half_width = (w / h) * (0.5 * fov_y.to_radians()).tan();
    let angle = (centre * half_width).atan();
    if angle.is_finite() {
        angle
    } else {
        0.0
    }
}

/// The camera yaw that looks along a walker's heading `h` (facing (sin h, 0, cos h)):
/// the camera's forward is (sin yaw, ·, −cos yaw).
pub fn yaw_behind(h: f32) -> f32 {
    (PI - h).rem_euclid(TAU)
}

fn finite_or_zero(v: f32) -> f32 {
    if v.is_finite() {
        v
    } else {
        0.0
    }
}

/// A key axis: finite, within [−1, 1].
fn axis(v: f32) -> f32 {
    finite_or_zero(v).clamp(-1.0, 1.0)
}

fn sanitize_speed(speed: f32) -> f32 {
    if speed.is_finite() {
        speed.clamp(MIN_SPEED, MAX_SPEED)
    } else {
        DEFAULT_SPEED
    }
}

fn sanitize_distance(distance: f32) -> f32 {
    if distance.is_finite() {
        distance.clamp(MIN_DISTANCE, MAX_DISTANCE)
    } else {
        MIN_DISTANCE
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const DT: f32 = 1.0 / 60.0;

    fn view(eye: Vec3, target: Vec3) -> CameraView {
        CameraView {
            eye,
            target,
            fov_y: 60.0,
            near: 0.1,
            far: 1000.0,
        }
    }

    /// 200 m square of rolling hills, up to ±8 m, with slopes up to about 45°.
    fn hills() -> HeightField {
        let mut field = HeightField::flat(200.0, 101);
        let res = field.resolution;
        for j in 0..res {
            for i in 0..res {
                let p = field.vertex(i, j);
                field.heights[(j * res + i) as usize] =
                    5.0 * (p.x * 0.15).sin() * (p.z * 0.11).cos() + 3.0 * (p.z * 0.2).sin();
            }
        }
        field
    }

    fn hold(forward: f32, right: f32, up: f32) -> CameraInput {
        CameraInput {
            forward,
            right,
            up,
            ..Default::default()
        }
    }

    fn run(cam: &mut CameraController, input: &CameraInput, seconds: f32, terrain: &HeightField) {
        let frames = (seconds / DT).round() as usize;
        for _ in 0..frames {
            cam.update(input, DT, terrain, None);
        }
    }

    #[test]
    fn from_view_round_trips_eye_and_direction() {
        let cases = [
            (Vec3::new(0.0, 5.0, 10.0), Vec3::ZERO),
            (Vec3::new(-3.0, 2.0, 1.0), Vec3::new(7.0, 4.0, -2.0)),
            (Vec3::new(1.0, 1.0, 1.0), Vec3::new(1.0, 1.0, 9.0)),
            (Vec3::new(4.0, 30.0, -4.0), Vec3::new(-5.0, 0.0, 3.0)),
        ];
        for (eye, target) in cases {
            let v = view(eye, target);
            let cam = CameraController::from_view(&v);
            let back = cam.view();
            assert!((back.eye - eye).length() < 1e-5, "{eye} -> {}", back.eye);
            let want = (target - eye).normalize();
            let got = (back.target - back.eye).normalize();
            assert!((want - got).length() < 1e-5, "{want} vs {got}");
            assert!((cam.forward().length() - 1.0).abs() < 1e-6);
            assert_eq!(cam.orbit_center, target);
            assert!((cam.orbit_distance - (target - eye).length()).abs() < 1e-4);
            assert_eq!(cam.speed, DEFAULT_SPEED);
            assert_eq!((back.fov_y, back.near, back.far), (60.0, 0.1, 1000.0));
        }
    }

    #[test]
    fn w_for_one_second_moves_speed_metres_along_forward() {
        let flat = HeightField::flat(400.0, 3);
        let mut cam = CameraController::from_view(&view(
            Vec3::new(0.0, 20.0, 0.0),
            Vec3::new(3.0, 18.0, -4.0),
        ));
        let start = cam.eye;
        let forward = cam.forward();
        run(&mut cam, &hold(1.0, 0.0, 0.0), 1.0, &flat);
        let moved = cam.eye - start;
        assert!((moved - forward * cam.speed).length() < 1e-3, "{moved}");

        // Strafing is horizontal, QE is vertical.
        let start = cam.eye;
        run(&mut cam, &hold(0.0, 1.0, 0.0), 1.0, &flat);
        let moved = cam.eye - start;
        assert!(moved.y.abs() < 1e-5 && (moved.length() - cam.speed).abs() < 1e-3);
        assert!(moved.dot(cam.right()) > 0.0);
        let start = cam.eye;
        run(&mut cam, &hold(0.0, 0.0, 1.0), 1.0, &flat);
        assert!((cam.eye - start - Vec3::Y * cam.speed).length() < 1e-3);
    }

    #[test]
    fn shift_moves_four_times_faster() {
        let flat = HeightField::flat(400.0, 3);
        let mut slow = CameraController::from_view(&view(
            Vec3::new(0.0, 20.0, 0.0),
            Vec3::new(0.0, 20.0, -1.0),
        ));
        let mut fast = slow;
        run(&mut slow, &hold(1.0, 0.0, 0.0), 1.0, &flat);
        let input = CameraInput {
            fast: true,
            ..hold(1.0, 0.0, 0.0)
        };
        run(&mut fast, &input, 1.0, &flat);
        let d_slow = slow.eye.z.abs();
        let d_fast = fast.eye.z.abs();
        assert!((d_slow - 6.0).abs() < 1e-3, "{d_slow}");
        assert!((d_fast - 4.0 * d_slow).abs() < 1e-3, "{d_fast}");
    }

    #[test]
    fn wheel_scales_speed_within_limits() {
        let flat = HeightField::flat(100.0, 3);
        let mut cam = CameraController::from_view(&view(
            Vec3::new(0.0, 10.0, 0.0),
            Vec3::new(0.0, 10.0, -1.0),
        ));
        let wheel = |lines| CameraInput {
            scroll: lines,
            ..Default::default()
        };
        cam.update(&wheel(1.0), DT, &flat, None);
        assert!((cam.speed - 7.2).abs() < 1e-4);
        cam.update(&wheel(-2.0), DT, &flat, None);
        assert!((cam.speed - 5.0).abs() < 1e-4);
        for _ in 0..100 {
            cam.update(&wheel(3.0), DT, &flat, None);
        }
        assert_eq!(cam.speed, MAX_SPEED);
        cam.update(&wheel(1e9), DT, &flat, None);
        assert_eq!(cam.speed, MAX_SPEED);
        for _ in 0..100 {
            cam.update(&wheel(-3.0), DT, &flat, None);
        }
        assert_eq!(cam.speed, MIN_SPEED);
        cam.update(&wheel(f32::NEG_INFINITY), DT, &flat, None);
        assert_eq!(cam.speed, MIN_SPEED);
    }

    #[test]
    fn look_rotates_and_pitch_is_clamped() {
        let flat = HeightField::flat(100.0, 3);
        let mut cam = CameraController::from_view(&view(
            Vec3::new(0.0, 10.0, 0.0),
            Vec3::new(0.0, 10.0, -1.0),
        ));
        let drag = |x, y| CameraInput {
            look: Vec2::new(x, y),
            ..Default::default()
        };
        cam.update(&drag(100.0, 0.0), DT, &flat, None);
        assert!((cam.yaw - 0.4).abs() < 1e-5);
        // Dragging right turns right (towards +x from −z).
        assert!(cam.forward().x > 0.3);
        cam.update(&drag(0.0, 100.0), DT, &flat, None);
        assert!((cam.pitch + 0.4).abs() < 1e-5);
        cam.update(&drag(0.0, 1e6), DT, &flat, None);
        assert!((cam.pitch + MAX_PITCH).abs() < 1e-6);
        assert!(cam.forward().y > -1.0 && cam.forward().is_finite());
        cam.update(&drag(0.0, -1e7), DT, &flat, None);
        assert!((cam.pitch - MAX_PITCH).abs() < 1e-6);
        // Huge and non-finite deltas leave a finite, valid state.
        cam.update(&drag(f32::MAX, f32::MIN), DT, &flat, None);
        cam.update(&drag(f32::NAN, f32::INFINITY), DT, &flat, None);
        assert!(cam.yaw.is_finite() && (0.0..TAU).contains(&cam.yaw));
        assert!(cam.pitch.abs() <= MAX_PITCH);
        assert!(cam.view().eye.is_finite() && cam.view().target.is_finite());
        let m = cam.view().view_proj(1.5);
        assert!(m.is_finite());
    }

    #[test]
    fn zero_and_bad_dt_do_not_move_or_poison() {
        let terrain = hills();
        for mode in [CameraMode::Fly, CameraMode::Orbit, CameraMode::Follow] {
            let mut cam = CameraController::from_view(&view(
                Vec3::new(0.0, 30.0, 20.0),
                Vec3::new(0.0, 0.0, 0.0),
            ));
            cam.set_mode(mode, Some(Vec3::ZERO));
            let start = cam;
            for dt in [0.0, -1.0, f32::NAN, f32::NEG_INFINITY] {
                cam.update(&hold(1.0, 1.0, 1.0), dt, &terrain, Some(Vec3::ONE));
            }
            assert_eq!(cam.eye, start.eye);
            // Infinite dt is clamped to MAX_DT, not a jump to infinity.
            cam.update(&hold(1.0, 0.0, 0.0), f32::INFINITY, &terrain, None);
            assert!(cam.eye.is_finite());
            cam.update(
                &hold(f32::NAN, f32::INFINITY, 1e30),
                DT,
                &terrain,
                Some(Vec3::NAN),
            );
            assert!(cam.is_finite(), "{cam:?}");
        }
    }

    #[test]
    fn never_below_terrain_in_any_mode() {
        let terrain = hills();
        for mode in [CameraMode::Fly, CameraMode::Orbit, CameraMode::Follow] {
            let mut cam = CameraController::from_view(&view(
                Vec3::new(10.0, 25.0, 40.0),
                Vec3::new(0.0, 0.0, 0.0),
            ));
            cam.set_mode(mode, Some(Vec3::new(0.0, 2.0, 0.0)));
            assert_eq!(cam.mode, mode);
            // Dive: forward and down, looking down, zooming in, for 10 s; in follow mode
            // the followed point sinks through the ground and moves away.
            let input = CameraInput {
                forward: 1.0,
                right: 0.3,
                up: -1.0,
                fast: true,
                look: Vec2::new(3.0, 4.0),
                scroll: 0.5,
            };
            for frame in 0..600 {
                let t = frame as f32 * DT;
                let follow = Vec3::new(2.0 * t, 2.0 - 3.0 * t, -t);
                cam.update(&input, DT, &terrain, Some(follow));
                let floor = ground(&terrain, cam.eye) + cam.min_clearance;
                assert!(
                    cam.eye.y >= floor - 1e-4,
                    "{mode:?} frame {frame}: eye {} below {floor}",
                    cam.eye
                );
                assert!(cam.is_finite());
            }
        }
    }

    #[test]
    fn orbit_keeps_distance_and_faces_centre() {
        let flat = HeightField::flat(400.0, 3);
        let mut cam = CameraController::from_view(&view(
            Vec3::new(0.0, 10.0, 20.0),
            Vec3::new(0.0, 2.0, 0.0),
        ));
        let before = cam.view();
        cam.set_mode(CameraMode::Orbit, None);
        // Switching is seamless: same eye, same direction.
        assert!((cam.eye - before.eye).length() < 1e-4);
        assert!((cam.forward() - (before.target - before.eye).normalize()).length() < 1e-5);
        let center = cam.orbit_center;
        let distance = cam.orbit_distance;
        assert!((center - Vec3::new(0.0, 2.0, 0.0)).length() < 1e-3);
        // Turning and looking further down (the eye rises, staying clear of the ground).
        let drag = CameraInput {
            look: Vec2::new(7.0, 0.5),
            ..Default::default()
        };
        for _ in 0..120 {
            cam.update(&drag, DT, &flat, None);
            assert!(((cam.eye - center).length() - distance).abs() < 1e-3);
            let to_center = (center - cam.eye).normalize();
            assert!((to_center - cam.forward()).length() < 1e-4);
        }
        // The wheel zooms in by 0.9 per line.
        let zoom = CameraInput {
            scroll: 2.0,
            ..Default::default()
        };
        cam.update(&zoom, DT, &flat, None);
        assert!((cam.orbit_distance - distance * 0.81).abs() < 1e-3);
        assert!(((cam.eye - center).length() - distance * 0.81).abs() < 1e-3);
        // WASD pans the centre at `speed` on the ground plane.
        let mut panned = cam;
        run(&mut panned, &hold(1.0, 0.0, 0.0), 1.0, &flat);
        let moved = panned.orbit_center - cam.orbit_center;
        assert!(moved.y.abs() < 1e-5 && (moved.length() - cam.speed).abs() < 1e-3);
        assert!(((panned.eye - panned.orbit_center).length() - panned.orbit_distance).abs() < 1e-3);
        // Zoom limits.
        for _ in 0..200 {
            cam.update(&zoom, DT, &flat, None);
        }
        assert_eq!(cam.orbit_distance, MIN_DISTANCE);
        let out = CameraInput {
            scroll: -100.0,
            ..Default::default()
        };
        cam.update(&out, DT, &flat, None);
        assert_eq!(cam.orbit_distance, MAX_DISTANCE);
    }

    #[test]
    fn follow_converges_to_a_moving_target() {
        let flat = HeightField::flat(400.0, 3);
        let mut cam =
            CameraController::from_view(&view(Vec3::new(0.0, 8.0, 12.0), Vec3::new(0.0, 0.0, 0.0)));
        let start = Vec3::new(0.0, 0.5, 0.0);
        cam.set_mode(CameraMode::Follow, Some(start));
        assert_eq!(cam.mode, CameraMode::Follow);
        let distance = cam.orbit_distance;
        // A target moving at 3 m/s: the centre trails by about v·τ.
        let velocity = Vec3::new(3.0, 0.0, -1.0);
        let mut target = start;
        for frame in 0..180 {
            target += velocity * DT;
            cam.update(&CameraInput::default(), DT, &flat, Some(target));
            if frame > 90 {
                let lag = (target - cam.orbit_center).length();
                assert!(
                    lag < velocity.length() * FOLLOW_TIME_CONSTANT * 1.1,
                    "lag {lag}"
                );
            }
            assert!(((cam.eye - cam.orbit_center).length() - distance).abs() < 1e-3);
        }
        // Stopped: the centre converges onto it.
        for _ in 0..120 {
            cam.update(&CameraInput::default(), DT, &flat, Some(target));
        }
        assert!((cam.orbit_center - target).length() < 0.01);

        // The smoothing does not depend on the frame rate.
        let mut a = cam;
        let mut b = cam;
        let goal = target + Vec3::new(5.0, 0.0, 0.0);
        for _ in 0..30 {
            a.update(&CameraInput::default(), 1.0 / 120.0, &flat, Some(goal));
        }
        for _ in 0..5 {
            b.update(&CameraInput::default(), 1.0 / 20.0, &flat, Some(goal));
        }
        assert!((a.orbit_center - b.orbit_center).length() < 1e-3);
    }

    #[test]
    fn follow_without_a_target_falls_back_to_fly() {
        let mut cam =
            CameraController::from_view(&view(Vec3::new(0.0, 8.0, 12.0), Vec3::new(0.0, 0.0, 0.0)));
        let before = cam.view();
        cam.set_mode(CameraMode::Follow, None);
        assert_eq!(cam.mode, CameraMode::Fly);
        cam.set_mode(CameraMode::Follow, Some(Vec3::NAN));
        assert_eq!(cam.mode, CameraMode::Fly);
        assert_eq!(cam.view(), before);
        // Orbit around a given point keeps the eye and turns to it.
        let point = Vec3::new(5.0, 0.0, 0.0);
        cam.set_mode(CameraMode::Orbit, Some(point));
        assert_eq!(cam.mode, CameraMode::Orbit);
        assert!((cam.eye - before.eye).length() < 1e-4);
        assert!((cam.forward() - (point - cam.eye).normalize()).length() < 1e-5);
        // Back to fly: nothing moves.
        let orbit_view = cam.view();
        cam.set_mode(CameraMode::Fly, None);
        assert_eq!(cam.view(), orbit_view);
    }

    #[test]
    fn behind_swings_round_to_the_walkers_back_and_shows_it_beside_the_panel() {
        let flat = HeightField::flat(400.0, 3);
        let mut cam =
            CameraController::from_view(&view(Vec3::new(0.0, 8.0, 12.0), Vec3::new(0.0, 0.0, 0.0)));
        let chest = Vec3::new(1.0, 1.2, 2.0);
        // Facing +x: the camera goes straight behind it, at −x, looking along +x.
        cam.track_heading(std::f32::consts::FRAC_PI_2);
        cam.set_mode(CameraMode::Behind, Some(chest));
        assert_eq!(cam.mode, CameraMode::Behind);
        let flat_dir = |c: &CameraController| {
            let f = c.forward();
            Vec2::new(f.x, f.z).normalize()
        };
        assert!(
            (flat_dir(&cam) - Vec2::X).length() < 1e-5,
            "{:?}",
            cam.forward()
        );
        assert!(((cam.eye - chest).length() - BEHIND_DISTANCE).abs() < 1e-3);
        // It turns to face −z (heading π): the camera follows within a few time constants,
        // the short way round, and never ends up in front of it.
        cam.track_heading(std::f32::consts::PI);
        for _ in 0..(3.0 / DT) as usize {
            cam.update(&CameraInput::default(), DT, &flat, Some(chest));
            assert!((cam.eye - chest).dot(Vec3::new(0.0, 0.0, 1.0)) > -0.5);
        }
        assert!(
            (flat_dir(&cam) - Vec2::NEG_Y).length() < 0.02,
            "{:?}",
            flat_dir(&cam)
        );
        // WASD does not move it (they walk the character).
        let before = cam;
        let keys = CameraInput {
            forward: 1.0,
            right: 1.0,
            ..Default::default()
        };
        cam.update(&keys, DT, &flat, Some(chest));
        assert!((cam.eye - before.eye).length() < 1e-4);

        // A panel over the left half of a square 90° view: the chest shows at the middle of
        // the right half (normalised x = 0.5), not at the window's centre (exactly at a
        // level view; the camera's tilt of 0.3 rad moves it by 0.027).
        cam.fov_y = 90.0;
        cam.view_offset = centre_offset((400, 400), 200, 90.0);
        assert!((cam.view_offset - 0.5f32.atan()).abs() < 1e-6);
        let clip = cam.view().view_proj(1.0) * chest.extend(1.0);
        assert!((clip.x / clip.w - 0.5).abs() < 0.04, "{}", clip.x / clip.w);
        cam.pitch = 0.0;
        let clip = cam.view().view_proj(1.0) * (cam.eye + cam.forward()).extend(1.0);
        assert!((clip.x / clip.w - 0.5).abs() < 1e-4, "{}", clip.x / clip.w);
        assert_eq!(centre_offset((400, 400), 0, 90.0), 0.0);
    }
}
