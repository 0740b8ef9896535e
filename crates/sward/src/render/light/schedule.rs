//! When each shadow cascade is drawn again. The nearest cascade is drawn every frame; a
//! farther one every 2^k frames (cascade 1 every 2nd, cascade 2 every 4th, cascade 3
//! every 8th; staggered so that no two far cascades fall on the same frame), or at once
//! when its slice has moved by more than [`DRIFT`] of its radius since it was drawn (the
//! camera flew or turned), when the sun moved, or when the map was made anew. In between,
//! the receivers look a cascade up with the view it was drawn with, so a kept map is
//! exactly right for everything that did not move; what moves in a far cascade (far
//! blades do not cast: `grass_radius`) lags by at most a few frames. A point its kept
//! map does not cover is looked up in the next cascade (`sun_visibility`).
//!
//! Measured (nature at 1280×720 on llvmpipe, three cascades): the shadow pass draws on
//! average 1.75 cascades a frame instead of 3.

use glam::{Mat4, Vec3};

use super::cascades::Cascade;

/// Share of a cascade's radius its slice may move before the cascade is drawn again.
pub const DRIFT: f32 = 0.1;

/// What a cascade was last drawn with.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Drawn {
    /// The cascade's view-projection it was drawn with, which the receivers keep using.
    pub view_proj: Mat4,
    /// Its texel size in the world at the time (m).
    pub texel: f32,
    centre: Vec3,
    radius: f32,
    sun: Vec3,
}

/// The cascades' update schedule.
#[derive(Clone, Debug, Default)]
pub struct Schedule {
    frame: u64,
    drawn: [Option<Drawn>; 4],
}

/// Frames between two scheduled draws of cascade `k`.
pub fn period(k: usize) -> u64 {
    1 << k.min(3)
}

impl Schedule {
    /// Forgets every cascade: the next frame draws them all (a new map, shadows turned
    /// off and on).
    pub fn reset(&mut self) {
        self.drawn = [None; 4];
    }

    /// Plans this frame's cascades `now` for a sun in direction `sun`: which are drawn,
    /// and the view each is looked up with (the new one where drawn, else the kept one).
    pub fn plan(&mut self, now: &[Cascade], sun: Vec3) -> Vec<(bool, Drawn)> {
        self.frame = self.frame.wrapping_add(1);
        let frame = self.frame;
        now.iter()
            .enumerate()
            .map(|(k, c)| {
                let fresh = Drawn {
                    view_proj: c.view_proj,
                    texel: c.texel,
                    centre: c.centre,
                    radius: c.radius,
                    sun,
                };
                let slot = &mut self.drawn[k.min(3)];
                let due = (frame + k as u64).is_multiple_of(period(k));
                let stale = slot.is_none_or(|d| {
                    d.sun != sun
                        || d.radius != c.radius
                        || d.centre.distance(c.centre) > DRIFT * c.radius
                });
                if due || stale {
                    *slot = Some(fresh);
                }
                (due || stale, slot.unwrap_or(fresh))
            })
            .collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn cascade(x: f32, radius: f32) -> Cascade {
        Cascade {
            view_proj: Mat4::from_translation(Vec3::new(x, 0.0, 0.0)),
            far: radius,
            texel: 0.01,
            centre: Vec3::new(x, 0.0, 0.0),
            radius,
        }
    }

    #[test]
    fn a_still_view_draws_the_far_cascades_every_few_frames() {
        let mut s = Schedule::default();
        let sun = Vec3::Y;
        let now = [cascade(0.0, 5.0), cascade(0.0, 15.0), cascade(0.0, 40.0)];
        // The first frame draws everything.
        assert!(s.plan(&now, sun).iter().all(|(d, _)| *d));
        let mut draws = [0u32; 3];
        for _ in 0..64 {
            for (k, (drawn, _)) in s.plan(&now, sun).iter().enumerate() {
                draws[k] += u32::from(*drawn);
            }
        }
        assert_eq!(draws, [64, 32, 16]);
    }

    #[test]
    fn a_kept_cascade_is_looked_up_with_the_view_it_was_drawn_with() {
        let mut s = Schedule::default();
        let sun = Vec3::Y;
        s.plan(&[cascade(0.0, 5.0), cascade(0.0, 40.0)], sun);
        // The far slice moves by less than its drift: kept until its turn.
        let plan = s.plan(&[cascade(0.2, 5.0), cascade(1.0, 40.0)], sun);
        let (drawn, view) = plan[1];
        if !drawn {
            assert_eq!(view.view_proj, cascade(0.0, 40.0).view_proj);
        }
        // Beyond the drift, or with another sun, it is drawn at once.
        let plan = s.plan(&[cascade(0.0, 5.0), cascade(10.0, 40.0)], sun);
        assert!(plan[1].0);
        assert_eq!(plan[1].1.view_proj, cascade(10.0, 40.0).view_proj);
        let plan = s.plan(&[cascade(0.0, 5.0), cascade(10.0, 40.0)], Vec3::X);
        assert!(plan.iter().all(|(d, _)| *d));
    }
}
