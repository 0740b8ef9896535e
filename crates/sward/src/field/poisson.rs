//! Poisson-disk sampling of a rectangle with Bridson's algorithm ("Fast Poisson disk
//! sampling in arbitrary dimensions", SIGGRAPH 2007 sketch): tuft centres must not clump
//! (paper, Section 4), so every pair of points is at least `r` apart while the rectangle
//! is still filled without large holes. Runs in time linear in the number of points.

use glam::Vec2;

use super::rng::Rng;

/// Candidates tried around an active point before it retires (Bridson's k).
const ATTEMPTS: u32 = 30;
const EMPTY: u32 = u32::MAX;

/// Points in `[lo, hi]` (component-wise), pairwise at least `r` apart, in generation
/// order. Returns no points for an empty rectangle or a non-positive `r`.
pub fn poisson_disk(lo: Vec2, hi: Vec2, r: f32, rng: &mut Rng) -> Vec<Vec2> {
    let extent = hi - lo;
    if !(r > 0.0 && extent.x >= 0.0 && extent.y >= 0.0 && extent.is_finite()) {
        return Vec::new();
    }
    // Cells of side r/√2 hold at most one point, so a 5×5 neighbourhood covers every
    // point that could be closer than r.
    let cell = r / std::f32::consts::SQRT_2;
    let cols = (extent.x / cell).floor() as usize + 1;
    let rows = (extent.y / cell).floor() as usize + 1;
    let mut grid = vec![EMPTY; cols * rows];
    let cell_of = |p: Vec2| {
        let c = (((p.x - lo.x) / cell) as usize).min(cols - 1);
        let rr = (((p.y - lo.y) / cell) as usize).min(rows - 1);
        (c, rr)
    };

    let mut points = Vec::new();
    let mut active = Vec::new();
    let first = lo + Vec2::new(rng.f32(), rng.f32()) * extent;
    let (c, rr) = cell_of(first);
    grid[rr * cols + c] = 0;
    points.push(first);
    active.push(0u32);

    let r2 = r * r;
    while !active.is_empty() {
        let slot = rng.below(active.len());
        let centre = points[active[slot] as usize];
        let mut placed = false;
        for _ in 0..ATTEMPTS {
            // Uniform by area in the annulus [r, 2r].
            let radius = (r2 + rng.f32() * 3.0 * r2).sqrt();
            let angle = rng.f32() * std::f32::consts::TAU;
            let p = centre + radius * Vec2::new(angle.cos(), angle.sin());
            if p.x < lo.x || p.y < lo.y || p.x > hi.x || p.y > hi.y {
                continue;
            }
            let (c, rr) = cell_of(p);
            let clear = (rr.saturating_sub(2)..(rr + 3).min(rows)).all(|j| {
                (c.saturating_sub(2)..(c + 3).min(cols)).all(|i| {
                    let k = grid[j * cols + i];
                    k == EMPTY || points[k as usize].distance_squared(p) >= r2
                })
            });
            if clear {
                let index = points.len() as u32;
                grid[rr * cols + c] = index;
                points.push(p);
                active.push(index);
                placed = true;
                break;
            }
        }
        if !placed {
            active.swap_remove(slot);
        }
    }
    points
}

#[cfg(test)]
mod tests {
    use super::*;

    fn min_pair_distance(points: &[Vec2]) -> f32 {
        let mut best = f32::INFINITY;
        for (i, a) in points.iter().enumerate() {
            for b in &points[i + 1..] {
                best = best.min(a.distance(*b));
            }
        }
        best
    }

    #[test]
    fn respects_min_distance_and_fills_the_rectangle() {
        let lo = Vec2::new(-5.0, -3.0);
        let hi = Vec2::new(5.0, 3.0);
        let r = 0.4;
        let points = poisson_disk(lo, hi, r, &mut Rng::new(11, 0));
        assert!(min_pair_distance(&points) >= r * (1.0 - 1e-5));
        assert!(points
            .iter()
            .all(|p| p.x >= lo.x && p.y >= lo.y && p.x <= hi.x && p.y <= hi.y));
        // A maximal set leaves no hole wider than 2r: every probe is within 2r of a point.
        for i in 0..40 {
            for j in 0..24 {
                let probe = lo + Vec2::new(i as f32 * 0.25, j as f32 * 0.25);
                let near = points
                    .iter()
                    .map(|p| p.distance(probe))
                    .fold(f32::INFINITY, f32::min);
                assert!(near <= 2.0 * r, "hole at {probe}");
            }
        }
    }

    #[test]
    fn is_seeded() {
        let a = poisson_disk(Vec2::ZERO, Vec2::ONE, 0.1, &mut Rng::new(1, 0));
        let b = poisson_disk(Vec2::ZERO, Vec2::ONE, 0.1, &mut Rng::new(1, 0));
        let c = poisson_disk(Vec2::ZERO, Vec2::ONE, 0.1, &mut Rng::new(2, 0));
        assert_eq!(a, b);
        assert_ne!(a, c);
    }

    #[test]
    fn degenerate_inputs() {
        assert!(poisson_disk(Vec2::ZERO, Vec2::ONE, 0.0, &mut Rng::new(1, 0)).is_empty());
        assert!(poisson_disk(Vec2::ONE, Vec2::ZERO, 0.1, &mut Rng::new(1, 0)).is_empty());
        assert_eq!(
            poisson_disk(Vec2::ONE, Vec2::ONE, 0.1, &mut Rng::new(1, 0)).len(),
            1
        );
    }
}
