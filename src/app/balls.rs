//! Balls that roll over the terrain: the ones the user throws into the meadow and one
//! steered "character" ball. Their centres, radii and velocities are the sphere colliders
//! the grass reacts to (responsive-grass paper, Section 5.2), and the character is the
//! moving object the prairie thesis has the plants follow.
//!
//! The physics is deliberately small: point masses with a radius, semi-implicit Euler in
//! sub-steps of at most 1/240 s, contact with the height field along the vertical, a
//! restitution with a rest threshold (so balls settle instead of jittering), rolling
//! resistance, and walls at the edges of the terrain square. Contact is written so that it
//! never creates energy; together with the integrator's own slight loss this keeps balls
//! from gaining speed on their own, however long they roll.

use glam::{Vec2, Vec3};

use sward::field::HeightField;

/// Longest physics sub-step in seconds.
pub const MAX_SUBSTEP: f32 = 1.0 / 240.0;
/// Longest frame integrated per call: a hitch must not cost hundreds of sub-steps.
pub const MAX_DT: f32 = 0.25;
/// Inward speed (m/s) below which a contact does not bounce.
pub const BOUNCE_THRESHOLD: f32 = 0.5;
/// Acceleration of the steered character on the ground, m/s².
pub const CHARACTER_ACCELERATION: f32 = 10.0;
/// Top speed steering can give the character, m/s.
pub const CHARACTER_TOP_SPEED: f32 = 6.0;
/// Fastest accepted throw, m/s: keeps ½v² far from overflowing f32.
pub const MAX_THROW_SPEED: f32 = 1000.0;
/// The character counts as on the ground within this gap (m), so that it can still be
/// steered on the sub-step after a contact lifted it exactly onto the surface.
const GROUND_GAP: f32 = 0.02;
/// A ball whose bottom is within this gap (m) of the ground is in contact before it
/// moves: after a push-out the gap is zero up to rounding.
const CONTACT_GAP: f32 = 1e-4;

/// One ball.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Ball {
    pub center: Vec3,
    pub velocity: Vec3,
    pub radius: f32,
}

/// All balls of the window app.
#[derive(Clone, Debug, PartialEq)]
pub struct Balls {
    /// Thrown balls, oldest first.
    pub thrown: Vec<Ball>,
    /// The steered ball, if spawned.
    pub character: Option<Ball>,
    /// Rolling resistance coefficient: tangential deceleration is `friction · g` (times
    /// the normal's vertical part on a slope, where the ground carries less weight).
    pub friction: f32,
    /// Fraction of the inward speed kept after a bounce.
    pub restitution: f32,
    /// Most thrown balls kept; older ones are dropped.
    pub max_thrown: usize,
}

impl Default for Balls {
    fn default() -> Self {
        Self::new()
    }
}

impl Balls {
    /// No balls, no character, default coefficients.
    pub fn new() -> Self {
        Self {
            thrown: Vec::new(),
            character: None,
            friction: 0.25,
            restitution: 0.3,
            max_thrown: 64,
        }
    }

    /// Throws a ball from `origin` along `dir` (normalised here) at `speed` m/s. The
    /// oldest balls go beyond `max_thrown`. Non-finite or degenerate input throws nothing.
    pub fn throw(&mut self, origin: Vec3, dir: Vec3, speed: f32, radius: f32) {
        let Some(dir) = dir.try_normalize() else {
            return;
        };
        if !(origin.is_finite() && speed.is_finite() && radius.is_finite() && radius > 0.0) {
            return;
        }
        self.thrown.push(Ball {
            center: origin,
            velocity: dir * speed.clamp(0.0, MAX_THROW_SPEED),
            radius,
        });
        if self.thrown.len() > self.max_thrown {
            let excess = self.thrown.len() - self.max_thrown;
            self.thrown.drain(..excess);
        }
    }

    /// Puts the character at rest on the ground at `(x, z)` (moved inside the walls),
    /// replacing any previous one. Non-finite input changes nothing.
    pub fn spawn_character(&mut self, at: (f32, f32), radius: f32, terrain: &HeightField) {
        if !(at.0.is_finite() && at.1.is_finite() && radius.is_finite() && radius > 0.0) {
            return;
        }
        let limit = wall_limit(terrain, radius);
        let (x, z) = (at.0.clamp(-limit, limit), at.1.clamp(-limit, limit));
        let center = Vec3::new(x, terrain.height(x, z) + radius, z);
        if center.is_finite() {
            self.character = Some(Ball {
                center,
                velocity: Vec3::ZERO,
                radius,
            });
        }
    }

    /// Advances every ball by `dt` seconds (at most [`MAX_DT`]) under `gravity` m/s²
    /// pointing −y. `steer` (x/z, length clamped to 1) accelerates the character while it
    /// touches the ground. Non-finite `dt` or `gravity` do nothing; a non-finite `steer`
    /// counts as no steering; negative gravity is treated as zero.
    pub fn step(&mut self, dt: f32, gravity: f32, terrain: &HeightField, steer: Vec2) {
        if !(dt.is_finite() && dt > 0.0 && gravity.is_finite()) {
            return;
        }
        let dt = dt.min(MAX_DT);
        let g = gravity.max(0.0);
        let steer = if steer.is_finite() {
            steer.clamp_length_max(1.0)
        } else {
            Vec2::ZERO
        };
        let world = World {
            terrain,
            g,
            friction: if self.friction.is_finite() {
                self.friction.max(0.0)
            } else {
                0.0
            },
            restitution: if self.restitution.is_finite() {
                self.restitution.clamp(0.0, 1.0)
            } else {
                0.0
            },
        };
        let substeps = (dt / MAX_SUBSTEP).ceil().max(1.0) as usize;
        let h = dt / substeps as f32;
        for _ in 0..substeps {
            if let Some(ball) = &mut self.character {
                world.substep(ball, h, steer);
            }
            for ball in &mut self.thrown {
                world.substep(ball, h, Vec2::ZERO);
            }
        }
    }

    /// `(centre, radius, velocity)` of every ball, the character first.
    pub fn spheres(&self) -> Vec<(Vec3, f32, Vec3)> {
        self.character
            .iter()
            .chain(&self.thrown)
            .map(|b| (b.center, b.radius, b.velocity))
            .collect()
    }

    /// Removes the thrown balls; the character stays.
    pub fn clear(&mut self) {
        self.thrown.clear();
    }
}

/// Half-width of the square the centre of a ball of radius `r` may occupy.
fn wall_limit(terrain: &HeightField, r: f32) -> f32 {
    let limit = 0.5 * terrain.size - r;
    if limit.is_finite() {
        limit.max(0.0)
    } else {
        0.0
    }
}

/// The parameters of one step, sanitised.
struct World<'a> {
    terrain: &'a HeightField,
    g: f32,
    friction: f32,
    restitution: f32,
}

impl World<'_> {
    /// Height of the bottom of the ball above the ground under its centre.
    fn gap(&self, ball: &Ball) -> f32 {
        ball.center.y - ball.radius - self.terrain.height(ball.center.x, ball.center.z)
    }

    /// One sub-step of length `h` for one ball. A ball whose state would turn non-finite
    /// keeps its previous position and stops.
    fn substep(&self, ball: &mut Ball, h: f32, steer: Vec2) {
        let before = *ball;

        if steer != Vec2::ZERO && self.gap(ball) <= GROUND_GAP {
            steer_velocity(&mut ball.velocity, steer, h);
        }
        // Contact may not leave the ball with more energy than it has here.
        let energy = 0.5 * ball.velocity.length_squared() + self.g * ball.center.y;

        ball.velocity.y -= self.g * h;
        // A ball touching the ground gets its contact response before it moves, so that
        // on a slope it moves along the surface in the same sub-step in which the slope
        // accelerates it (responding only after the move would let it gain speed one
        // sub-step before losing height).
        let mut touched = false;
        let mut rolled = false;
        if self.gap(ball) <= CONTACT_GAP {
            touched = true;
            rolled = self.respond(ball, h);
        }

        ball.center += ball.velocity * h;

        // Walls: clamp into the square and send the ball back.
        let limit = wall_limit(self.terrain, ball.radius);
        for axis in [0, 2] {
            let c = ball.center[axis];
            if c.abs() > limit {
                ball.center[axis] = c.clamp(-limit, limit);
                let v = ball.velocity[axis];
                if v * c > 0.0 {
                    ball.velocity[axis] = -self.restitution * v;
                }
            }
        }

        // Into the ground (a landing, or rolling into a rise): out along the vertical.
        let ground = self.terrain.height(ball.center.x, ball.center.z);
        if ball.center.y - ball.radius < ground {
            ball.center.y = ground + ball.radius;
            touched = true;
            // Rolling resistance acts once per sub-step.
            self.respond(ball, if rolled { 0.0 } else { h });
        }

        if touched {
            // Lifting the ball out of the ground raises its potential energy, and a
            // bounce after the gravity kick returns a little more speed than the ball
            // arrived with: take both from the kinetic energy.
            let allowed = energy - self.g * ball.center.y;
            let kinetic = 0.5 * ball.velocity.length_squared();
            if kinetic > allowed {
                ball.velocity *= if allowed > 0.0 {
                    (allowed / kinetic).sqrt()
                } else {
                    0.0
                };
            }
        }

        if !(ball.center.is_finite() && ball.velocity.is_finite()) {
            *ball = Ball {
                velocity: Vec3::ZERO,
                ..before
            };
        }
    }

    /// Contact response with the ground under the ball's centre: removes (or, above
    /// [`BOUNCE_THRESHOLD`], reflects with restitution) the velocity into the surface,
    /// and when the ball presses on the ground, applies `resistance_dt` seconds of rolling
    /// resistance, which slows its tangential motion without reversing it. The slope's pull downhill needs nothing
    /// extra: it is gravity minus the removed normal part. Returns whether the ball was
    /// pressing on the ground.
    fn respond(&self, ball: &mut Ball, resistance_dt: f32) -> bool {
        let n = self.terrain.normal(ball.center.x, ball.center.z);
        let vn = ball.velocity.dot(n);
        if vn >= 0.0 {
            return false; // leaving the surface: no contact force
        }
        let bounce = if -vn < BOUNCE_THRESHOLD {
            0.0
        } else {
            self.restitution
        };
        ball.velocity -= (1.0 + bounce) * vn * n;
        if resistance_dt > 0.0 {
            let vn = ball.velocity.dot(n);
            let tangential = ball.velocity - vn * n;
            let speed = tangential.length();
            if speed > 0.0 {
                // The ground carries g·n.y of the weight on a slope.
                let slowed =
                    (speed - self.friction * self.g * n.y.max(0.0) * resistance_dt).max(0.0);
                ball.velocity = vn * n + tangential * (slowed / speed);
            }
        }
        true
    }
}

/// Applies the character's steering for one sub-step: [`CHARACTER_ACCELERATION`] along
/// `steer` in the horizontal plane, but never pushing the horizontal speed above
/// [`CHARACTER_TOP_SPEED`] (or above the current speed, if a slope made it faster).
fn steer_velocity(velocity: &mut Vec3, steer: Vec2, h: f32) {
    let old = Vec2::new(velocity.x, velocity.z);
    let mut new = old + steer * CHARACTER_ACCELERATION * h;
    let old_speed = old.length();
    let new_speed = new.length();
    let cap = old_speed.max(CHARACTER_TOP_SPEED);
    if new_speed > cap {
        new *= cap / new_speed;
    }
    velocity.x = new.x;
    velocity.z = new.y;
}

#[cfg(test)]
mod tests {
    use super::*;

    const DT: f32 = 1.0 / 60.0;
    const G: f32 = 9.81;

    /// A 60 m square of hills up to about ±3 m.
    fn hills() -> HeightField {
        let mut field = HeightField::flat(60.0, 121);
        let res = field.resolution;
        for j in 0..res {
            for i in 0..res {
                let p = field.vertex(i, j);
                field.heights[(j * res + i) as usize] =
                    2.0 * (p.x * 0.2).sin() * (p.z * 0.15).cos() + 1.0 * (p.z * 0.1).sin();
            }
        }
        field
    }

    /// A plane falling towards +x with the given slope (height = −slope·x).
    fn ramp(slope: f32) -> HeightField {
        let mut field = HeightField::flat(100.0, 11);
        let res = field.resolution;
        for j in 0..res {
            for i in 0..res {
                let p = field.vertex(i, j);
                field.heights[(j * res + i) as usize] = -slope * p.x;
            }
        }
        field
    }

    fn energy(balls: &Balls) -> f32 {
        balls
            .spheres()
            .iter()
            .map(|&(c, _, v)| 0.5 * v.length_squared() + G * c.y)
            .sum()
    }

    fn gap(ball: &Ball, terrain: &HeightField) -> f32 {
        ball.center.y - ball.radius - terrain.height(ball.center.x, ball.center.z)
    }

    #[test]
    fn thrown_ball_on_flat_ground_comes_to_rest() {
        let flat = HeightField::flat(80.0, 17);
        let mut balls = Balls::new();
        balls.throw(Vec3::new(0.0, 2.0, 0.0), Vec3::new(1.0, 0.5, 0.3), 8.0, 0.3);
        let mut touched = false;
        for _ in 0..(20.0 / DT) as usize {
            balls.step(DT, G, &flat, Vec2::ZERO);
            let b = balls.thrown[0];
            assert!(gap(&b, &flat) > -1e-3, "below ground: {b:?}");
            touched |= gap(&b, &flat) < 1e-3;
        }
        let b = balls.thrown[0];
        assert!(touched);
        assert!(b.velocity.length() < 1e-3, "still moving: {b:?}");
        assert!(gap(&b, &flat).abs() < 1e-3);
        // It went somewhere along the throw.
        assert!(b.center.x > 5.0 && b.center.z > 1.0);
    }

    #[test]
    fn ball_on_a_slope_rolls_downhill() {
        let slope = ramp(0.5);
        let mut balls = Balls::new();
        balls.throw(Vec3::new(0.0, 0.2, 3.0), Vec3::X, 0.0, 0.2);
        let mut last_x = 0.0;
        for step in 0..60 {
            balls.step(DT, G, &slope, Vec2::ZERO);
            let b = balls.thrown[0];
            assert!(b.center.x >= last_x - 1e-6, "step {step}: went uphill");
            assert!(gap(&b, &slope) > -1e-3);
            last_x = b.center.x;
        }
        let b = balls.thrown[0];
        // Downhill acceleration g(sinθ − μ·cosθ) ≈ 2.2 m/s² along the slope.
        assert!(b.center.x > 0.7, "{b:?}");
        assert!((b.center.z - 3.0).abs() < 1e-3);
        assert!(b.velocity.x > 1.5 && b.velocity.y < 0.0, "{b:?}");
        assert!(gap(&b, &slope).abs() < 1e-2);

        // Where rolling resistance beats the slope, the ball stays put.
        let gentle = ramp(0.1);
        let mut balls = Balls::new();
        balls.spawn_character((0.0, 0.0), 0.3, &gentle);
        for _ in 0..120 {
            balls.step(DT, G, &gentle, Vec2::ZERO);
        }
        assert!(balls.character.unwrap().velocity.length() < 1e-3);
    }

    #[test]
    fn energy_never_increases() {
        let field = hills();
        for (restitution, friction) in [(1.0, 0.0), (0.3, 0.25), (0.8, 0.05), (0.0, 0.0)] {
            let mut balls = Balls::new();
            balls.restitution = restitution;
            balls.friction = friction;
            for k in 0..12 {
                let a = k as f32 * 0.7;
                balls.throw(
                    Vec3::new(-10.0 + k as f32, 5.0, 4.0 - k as f32 * 0.5),
                    Vec3::new(a.cos(), 0.3 - 0.1 * k as f32, a.sin()),
                    4.0 + k as f32,
                    0.25,
                );
            }
            let start = energy(&balls);
            let mut prev = start;
            for step in 0..(15.0 / DT) as usize {
                balls.step(DT, G, &field, Vec2::ZERO);
                let e = energy(&balls);
                assert!(
                    e <= prev + 1e-3,
                    "e={restitution} μ={friction} step {step}: {prev} -> {e}"
                );
                for b in &balls.thrown {
                    assert!(gap(b, &field) > -1e-3);
                }
                prev = e;
            }
            assert!(prev <= start);
            if friction > 0.0 {
                assert!(prev < start - 1.0, "friction removed nothing");
            }
        }
    }

    #[test]
    fn walls_keep_balls_inside() {
        let field = HeightField::flat(10.0, 11);
        let mut balls = Balls::new();
        balls.restitution = 1.0;
        balls.friction = 0.0;
        for k in 0..16 {
            let a = k as f32 * 0.4;
            balls.throw(
                Vec3::new(0.0, 1.0, 0.0),
                Vec3::new(a.cos(), 0.2, a.sin()),
                30.0,
                0.5,
            );
        }
        // One thrown from outside the square comes in.
        balls.throw(Vec3::new(20.0, 1.0, -30.0), Vec3::X, 5.0, 0.5);
        let limit = 5.0 - 0.5;
        for _ in 0..600 {
            balls.step(DT, G, &field, Vec2::ZERO);
            for b in &balls.thrown {
                assert!(b.center.x.abs() <= limit + 1e-4 && b.center.z.abs() <= limit + 1e-4);
            }
        }
        // Without friction and with full restitution they are still moving.
        assert!(balls.thrown[0].velocity.length() > 10.0);
    }

    #[test]
    fn max_thrown_drops_the_oldest() {
        let mut balls = Balls::new();
        for k in 0..70 {
            balls.throw(Vec3::new(k as f32, 1.0, 0.0), Vec3::Y, 1.0, 0.1);
        }
        assert_eq!(balls.thrown.len(), 64);
        assert_eq!(balls.thrown[0].center.x, 6.0);
        assert_eq!(balls.thrown[63].center.x, 69.0);
        balls.max_thrown = 3;
        balls.throw(Vec3::ZERO, Vec3::Y, 1.0, 0.1);
        assert_eq!(balls.thrown.len(), 3);
        assert_eq!(balls.thrown[2].center, Vec3::ZERO);
    }

    #[test]
    fn steering_moves_the_character_and_caps_its_speed() {
        let flat = HeightField::flat(200.0, 11);
        let mut balls = Balls::new();
        balls.spawn_character((0.0, 0.0), 0.4, &flat);
        let c = balls.character.unwrap();
        assert_eq!(c.center, Vec3::new(0.0, 0.4, 0.0));
        let steer = Vec2::new(0.6, -0.8);
        for _ in 0..30 {
            balls.step(DT, G, &flat, steer);
        }
        let c = balls.character.unwrap();
        let moved = Vec2::new(c.center.x, c.center.z);
        assert!(moved.length() > 0.5);
        assert!(moved.normalize().dot(steer) > 0.999, "{moved}");
        assert!(Vec2::new(c.velocity.x, c.velocity.z).normalize().dot(steer) > 0.999);
        // Net acceleration 10 − μg ≈ 7.5 m/s² for 0.5 s.
        assert!((c.velocity.length() - 3.77).abs() < 0.1, "{c:?}");
        for _ in 0..300 {
            balls.step(DT, G, &flat, steer * 3.0); // over-long steer is clamped
            let v = balls.character.unwrap().velocity.length();
            assert!(v <= CHARACTER_TOP_SPEED + 1e-3, "{v}");
        }
        assert!(balls.character.unwrap().velocity.length() > 5.5);
        // Steering does nothing in the air.
        let mut air = Balls::new();
        air.character = Some(Ball {
            center: Vec3::new(0.0, 50.0, 0.0),
            velocity: Vec3::ZERO,
            radius: 0.4,
        });
        air.step(0.1, G, &flat, Vec2::X);
        assert_eq!(air.character.unwrap().velocity.x, 0.0);
    }

    #[test]
    fn clear_keeps_the_character_and_spheres_list_it_first() {
        let field = hills();
        let mut balls = Balls::new();
        balls.throw(Vec3::new(1.0, 5.0, 1.0), Vec3::X, 2.0, 0.2);
        balls.spawn_character((3.0, -2.0), 0.5, &field);
        let c = balls.character.unwrap();
        assert!((c.center.y - field.height(3.0, -2.0) - 0.5).abs() < 1e-6);
        let spheres = balls.spheres();
        assert_eq!(spheres.len(), 2);
        assert_eq!(spheres[0], (c.center, 0.5, Vec3::ZERO));
        balls.clear();
        assert!(balls.thrown.is_empty());
        assert_eq!(balls.character, Some(c));
        assert_eq!(balls.spheres().len(), 1);
        // Spawning outside the square puts it inside the walls.
        balls.spawn_character((1e6, -1e6), 0.5, &field);
        let c = balls.character.unwrap();
        assert_eq!((c.center.x, c.center.z), (29.5, -29.5));
    }

    #[test]
    fn non_finite_input_is_ignored() {
        let field = hills();
        let mut balls = Balls::new();
        balls.throw(Vec3::NAN, Vec3::X, 1.0, 0.2);
        balls.throw(Vec3::ZERO, Vec3::ZERO, 1.0, 0.2);
        balls.throw(Vec3::ZERO, Vec3::new(f32::INFINITY, 0.0, 0.0), 1.0, 0.2);
        balls.throw(Vec3::ZERO, Vec3::X, f32::NAN, 0.2);
        balls.throw(Vec3::ZERO, Vec3::X, 1.0, -0.2);
        balls.spawn_character((f32::NAN, 0.0), 0.3, &field);
        assert!(balls.thrown.is_empty() && balls.character.is_none());
        balls.throw(Vec3::new(0.0, 4.0, 0.0), Vec3::X, f32::MAX, 0.2);
        balls.spawn_character((0.0, 0.0), 0.3, &field);
        let before = balls.clone();
        balls.step(f32::NAN, G, &field, Vec2::ZERO);
        balls.step(DT, f32::INFINITY, &field, Vec2::ZERO);
        balls.step(-1.0, G, &field, Vec2::ZERO);
        assert_eq!(balls, before);
        for _ in 0..120 {
            balls.step(DT, G, &field, Vec2::new(f32::NAN, 1.0));
            balls.step(f32::INFINITY, G, &field, Vec2::X);
        }
        for (c, r, v) in balls.spheres() {
            assert!(c.is_finite() && r.is_finite() && v.is_finite());
        }
    }
}
