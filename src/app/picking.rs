//! Mouse picking for the AGC editor and ball throwing: the guide point under the cursor,
//! over the library's rays (`sward::render::ray`: the world-space ray under a pixel, the
//! pixel of a world point, the first point where a ray meets the terrain), which it
//! re-exports for the window.

use glam::{Vec2, Vec3};

use sward::field::HeightField;
use sward::render::camera::CameraView;
pub use sward::render::ray::{pick_terrain, project, screen_ray, Ray};
use sward::scene::Guide;
use sward::sim::agc::{GuideId, PointId};

/// The guide point under the cursor: each point is drawn at
/// `(x, terrain.height(x, z) + lift, z)`; the one whose projection is nearest `cursor`
/// within `radius_px` wins. On equal distances the later guide / point wins, as it is
/// drawn on top. Points behind the camera cannot be picked.
pub fn pick_point(
    guides: &[Guide],
    terrain: &HeightField,
    view: &CameraView,
    size: (u32, u32),
    cursor: Vec2,
    radius_px: f32,
    lift: f32,
) -> Option<(GuideId, PointId)> {
    if !(cursor.is_finite() && radius_px >= 0.0) {
        return None;
    }
    let lift = if lift.is_finite() { lift } else { 0.0 };
    let mut best: Option<((GuideId, PointId), f32)> = None;
    for (g, guide) in guides.iter().enumerate() {
        for (p, point) in guide.points.iter().enumerate() {
            let (x, z) = point.position;
            if !(x.is_finite() && z.is_finite()) {
                continue;
            }
            let world = Vec3::new(x, terrain.height(x, z) + lift, z);
            let Some(pixel) = project(view, size, world) else {
                continue;
            };
            let distance = pixel.distance(cursor);
            if distance > radius_px {
                continue;
            }
            // `<=`: a later point at the same distance is drawn over the earlier one.
            if best.is_none_or(|(_, d)| distance <= d) {
                best = Some(((g, p), distance));
            }
        }
    }
    best.map(|(id, _)| id)
}

#[cfg(test)]
mod tests {
    use super::*;
    use sward::scene::GuidePoint;

    fn view(eye: Vec3, target: Vec3) -> CameraView {
        CameraView {
            eye,
            target,
            fov_y: 60.0,
            near: 0.1,
            far: 1000.0,
        }
    }

    /// 100 m square of bumps up to ±4 m on a 1 m grid.
    fn hills() -> HeightField {
        let mut field = HeightField::flat(100.0, 101);
        let res = field.resolution;
        for j in 0..res {
            for i in 0..res {
                let p = field.vertex(i, j);
                field.heights[(j * res + i) as usize] =
                    2.5 * (p.x * 0.3).sin() * (p.z * 0.25).cos() + 1.5 * (p.x * 0.07 + 1.0).sin();
            }
        }
        field
    }

    fn guide(points: &[(f32, f32)]) -> Guide {
        Guide {
            started: 0.0,
            strength: 1.0,
            radius: 1.0,
            points: points
                .iter()
                .enumerate()
                .map(|(i, &position)| GuidePoint {
                    position,
                    parent: i.checked_sub(1),
                    strength: None,
                    radius: None,
                })
                .collect(),
        }
    }

    #[test]
    fn screen_ray_and_project_round_trip() {
        let views = [
            view(Vec3::new(0.0, 5.0, 10.0), Vec3::ZERO),
            view(Vec3::new(-20.0, 3.0, 4.0), Vec3::new(10.0, 0.0, -7.0)),
            view(Vec3::new(1.0, 30.0, 1.0), Vec3::new(1.0, 0.0, 1.001)),
            view(Vec3::new(2.0, 1.0, -3.0), Vec3::new(2.0, 4.0, 10.0)),
        ];
        let sizes = [(800, 600), (600, 800), (1920, 1080), (100, 100), (1, 1)];
        for v in &views {
            for &size in &sizes {
                let (w, h) = (size.0 as f32, size.1 as f32);
                let cursors = [
                    Vec2::new(0.5 * w, 0.5 * h),
                    Vec2::ZERO,
                    Vec2::new(w, h),
                    Vec2::new(0.13 * w, 0.77 * h),
                    Vec2::new(0.9 * w, 0.05 * h),
                ];
                for c in cursors {
                    let ray = screen_ray(v, size, c);
                    assert!((ray.dir.length() - 1.0).abs() < 1e-5);
                    // The ray starts on the near plane, in front of the eye.
                    let forward = (v.target - v.eye).normalize();
                    assert!((ray.origin - v.eye).dot(forward) > 0.0);
                    assert!((ray.origin - v.eye).length() < 1.0);
                    for t in [0.5, 3.0, 20.0, 150.0] {
                        let px = project(v, size, ray.at(t)).expect("in front");
                        assert!((px - c).length() < 0.01, "{size:?} {c} t={t}: {px} ({v:?})");
                    }
                }
            }
        }
        // The centre pixel looks along the view direction.
        let v = views[1];
        let ray = screen_ray(&v, (640, 480), Vec2::new(320.0, 240.0));
        assert!((ray.dir - (v.target - v.eye).normalize()).length() < 1e-5);
        // Up in the image is +y in the world for a level camera.
        let top = screen_ray(&v, (640, 480), Vec2::new(320.0, 0.0));
        assert!(top.dir.y > ray.dir.y);
        // Zero-sized windows and bad cursors give a finite ray.
        let r = screen_ray(&v, (0, 0), Vec2::new(f32::NAN, 3.0));
        assert!(r.origin.is_finite() && r.dir.is_finite());
    }

    #[test]
    fn project_rejects_points_behind_the_camera() {
        let v = view(Vec3::new(0.0, 2.0, 0.0), Vec3::new(0.0, 2.0, -1.0));
        assert!(project(&v, (800, 600), Vec3::new(0.0, 2.0, 5.0)).is_none());
        assert!(project(&v, (800, 600), Vec3::new(3.0, 0.0, 0.0)).is_none());
        assert!(project(&v, (800, 600), Vec3::NAN).is_none());
        let centre = project(&v, (800, 600), Vec3::new(0.0, 2.0, -5.0)).unwrap();
        assert!((centre - Vec2::new(400.0, 300.0)).length() < 1e-3);
        // Off-screen but in front: still a position.
        let off = project(&v, (800, 600), Vec3::new(100.0, 2.0, -1.0)).unwrap();
        assert!(off.x > 800.0);
    }

    #[test]
    fn flat_field_hit_is_the_analytic_intersection() {
        let field = HeightField::flat(100.0, 65);
        let v = view(Vec3::new(3.0, 10.0, 25.0), Vec3::new(-2.0, 0.0, 0.0));
        let size = (1024, 768);
        for c in [
            Vec2::new(512.0, 384.0),
            Vec2::new(10.0, 700.0),
            Vec2::new(1000.0, 500.0),
            Vec2::new(300.0, 250.0),
        ] {
            let ray = screen_ray(&v, size, c);
            assert!(ray.dir.y < 0.0);
            let t = -ray.origin.y / ray.dir.y;
            let want = ray.at(t);
            let got = pick_terrain(&ray, &field, 1000.0).expect("hits the ground");
            assert!((got - want).length() < 1e-3, "{got} vs {want}");
            // Too short a reach misses.
            assert!(pick_terrain(&ray, &field, 0.9 * t).is_none());
        }
    }

    #[test]
    fn hilly_field_hit_is_the_first_crossing() {
        let field = hills();
        let spacing = field.spacing();
        let eyes = [
            Vec3::new(0.0, 12.0, 40.0),
            Vec3::new(-45.0, 6.0, -45.0),
            Vec3::new(30.0, 4.5, 0.0),
            Vec3::new(-80.0, 20.0, 10.0), // outside the square
        ];
        let mut hits = 0;
        for eye in eyes {
            let v = view(eye, Vec3::new(0.0, 0.0, 0.0));
            for k in 0..25 {
                let c = Vec2::new(40.0 + 90.0 * (k % 5) as f32, 300.0 + 70.0 * (k / 5) as f32);
                let ray = screen_ray(&v, (500, 700), c);
                let Some(hit) = pick_terrain(&ray, &field, 500.0) else {
                    continue;
                };
                hits += 1;
                assert!(hit.x.abs() <= 50.0 && hit.z.abs() <= 50.0);
                assert!(
                    (hit.y - field.height(hit.x, hit.z)).abs() < 1e-3,
                    "{hit}: ground {}",
                    field.height(hit.x, hit.z)
                );
                // Nothing before the hit is underground (fine sampling, inside the square).
                let t_hit = (hit - ray.origin).length();
                let n = (t_hit / (0.1 * spacing)) as usize;
                for i in 0..n {
                    let t = t_hit * i as f32 / n as f32;
                    let p = ray.at(t);
                    if p.x.abs() <= 50.0 && p.z.abs() <= 50.0 && t < t_hit - 1e-3 {
                        assert!(p.y - field.height(p.x, p.z) > -1e-4, "{p} under ground");
                    }
                }
            }
        }
        assert!(hits > 50, "only {hits} hits");
    }

    #[test]
    fn rays_that_miss_return_none() {
        let field = hills();
        let sky = Ray {
            origin: Vec3::new(0.0, 10.0, 0.0),
            dir: Vec3::new(0.3, 0.5, 0.1).normalize(),
        };
        assert!(pick_terrain(&sky, &field, 1000.0).is_none());
        // Beside the square.
        let beside = Ray {
            origin: Vec3::new(60.0, 10.0, -200.0),
            dir: Vec3::new(0.0, -0.01, 1.0).normalize(),
        };
        assert!(pick_terrain(&beside, &field, 1000.0).is_none());
        // Pointing away from the square.
        let away = Ray {
            origin: Vec3::new(-70.0, 10.0, 0.0),
            dir: Vec3::new(-1.0, -0.2, 0.0).normalize(),
        };
        assert!(pick_terrain(&away, &field, 1000.0).is_none());
        // Level above every hill.
        let level = Ray {
            origin: Vec3::new(-70.0, 10.0, 0.0),
            dir: Vec3::X,
        };
        assert!(pick_terrain(&level, &field, 1000.0).is_none());
        // Degenerate input.
        let bad = Ray {
            origin: Vec3::new(0.0, 10.0, 0.0),
            dir: Vec3::ZERO,
        };
        assert!(pick_terrain(&bad, &field, 1000.0).is_none());
        let nan = Ray {
            origin: Vec3::NAN,
            dir: Vec3::NEG_Y,
        };
        assert!(pick_terrain(&nan, &field, 1000.0).is_none());
        let down = Ray {
            origin: Vec3::new(0.0, 10.0, 0.0),
            dir: Vec3::NEG_Y,
        };
        assert!(pick_terrain(&down, &field, f32::NAN).is_none());
        assert!(pick_terrain(&down, &field, -1.0).is_none());
        // Straight down hits directly below.
        let hit = pick_terrain(&down, &field, 1000.0).unwrap();
        assert!((hit - Vec3::new(0.0, field.height(0.0, 0.0), 0.0)).length() < 1e-3);
    }

    #[test]
    fn pick_point_takes_the_nearest_within_the_radius() {
        let field = hills();
        let v = view(Vec3::new(0.0, 30.0, 30.0), Vec3::ZERO);
        let size = (800, 600);
        let lift = 0.3;
        let guides = vec![
            guide(&[(0.0, 0.0), (5.0, 0.0), (5.0, 5.0)]),
            guide(&[(-8.0, 3.0), (-6.0, -4.0)]),
        ];
        let at =
            |x: f32, z: f32| project(&v, size, Vec3::new(x, field.height(x, z) + lift, z)).unwrap();
        let pick = |c: Vec2, r: f32| pick_point(&guides, &field, &v, size, c, r, lift);
        assert_eq!(pick(at(5.0, 0.0), 10.0), Some((0, 1)));
        assert_eq!(
            pick(at(-6.0, -4.0) + Vec2::new(3.0, -2.0), 10.0),
            Some((1, 1))
        );
        assert_eq!(pick(at(-6.0, -4.0) + Vec2::new(30.0, 0.0), 10.0), None);
        // Between two points: the nearer one.
        let a = at(0.0, 0.0);
        let b = at(5.0, 0.0);
        assert_eq!(pick(a + (b - a) * 0.4, 1000.0), Some((0, 0)));
        assert_eq!(pick(a + (b - a) * 0.6, 1000.0), Some((0, 1)));
        // The radius is respected.
        let c = a + Vec2::new(0.0, 6.0);
        assert_eq!(pick(c, 5.9), None);
        assert_eq!(pick(c, 6.1), Some((0, 0)));
        // The lift matters: the unlifted ground position is a few pixels off.
        assert!(
            (at(0.0, 0.0)
                - project(&v, size, Vec3::new(0.0, field.height(0.0, 0.0), 0.0)).unwrap())
            .length()
                > 1.0
        );
        assert_eq!(pick(Vec2::new(f32::NAN, 0.0), 100.0), None);
        assert_eq!(pick_point(&[], &field, &v, size, a, 100.0, lift), None);
    }

    #[test]
    fn pick_point_ties_go_to_the_later_point() {
        let field = HeightField::flat(50.0, 11);
        let v = view(Vec3::new(0.0, 10.0, 10.0), Vec3::ZERO);
        let size = (640, 480);
        let guides = vec![guide(&[(1.0, 1.0), (1.0, 1.0)]), guide(&[(1.0, 1.0)])];
        let c = project(&v, size, Vec3::new(1.0, 0.5, 1.0)).unwrap();
        assert_eq!(
            pick_point(&guides, &field, &v, size, c, 4.0, 0.5),
            Some((1, 0))
        );
        assert_eq!(
            pick_point(&guides[..1], &field, &v, size, c, 4.0, 0.5),
            Some((0, 1))
        );
    }

    #[test]
    fn pick_point_ignores_points_behind_the_camera() {
        let field = HeightField::flat(50.0, 11);
        // Looking along −z from z = 0: a point at z = +10 on the view axis would land
        // on the screen centre if the sign of w were ignored.
        let v = view(Vec3::new(0.0, 2.0, 0.0), Vec3::new(0.0, 2.0, -1.0));
        let size = (640, 480);
        let behind = vec![guide(&[(0.0, 10.0)])];
        let centre = Vec2::new(320.0, 240.0);
        assert_eq!(
            pick_point(&behind, &field, &v, size, centre, 1e6, 2.0),
            None
        );
        let front = vec![guide(&[(0.0, 10.0), (0.0, -10.0)])];
        assert_eq!(
            pick_point(&front, &field, &v, size, centre, 5.0, 2.0),
            Some((0, 1))
        );
    }
}
