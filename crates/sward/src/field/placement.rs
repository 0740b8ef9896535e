//! Where blades grow and what each one looks like (paper, Section 4, "Grass distribution"):
//! a fraction of the blades grows in tufts around Poisson-disk centres, the rest are
//! single blades placed uniformly at random — the paper keeps singles free of Poisson
//! sampling on purpose, because random clumping looks natural. A density map thins both
//! by rejection. Every blade starts in its rest pose on the terrain surface.

use glam::{Vec2, Vec3};

use super::blade::{blade_frame, rest_pose};
use super::blade::{Blade, BladeState};
use super::density::DensityMap;
use super::poisson::poisson_disk;
use super::rng::Rng;
use super::terrain::HeightField;
use crate::scene::types::Field;

/// RNG streams: one per consumer, so that e.g. a different tuft fraction does not change
/// the attributes drawn for the blades.
const STREAM_CENTRES: u64 = 1;
const STREAM_TUFTS: u64 = 2;
const STREAM_SINGLES: u64 = 3;
const STREAM_TRIM: u64 = 4;
const STREAM_ATTRIBUTES: u64 = 5;

/// Candidate blades per tuft visit: 8 to 24, mean 16.
const TUFT_MIN: usize = 8;
const TUFT_MAX: usize = 24;
const TUFT_MEAN: usize = (TUFT_MIN + TUFT_MAX) / 2;
/// Minimum distance between tuft centres, in tuft radii.
pub const TUFT_SPACING: f32 = 2.5;
/// Bridson's algorithm fills a rectangle with about 0.62·area/r² points; aiming at
/// 0.55·area/r² per needed centre leaves ~10 % spare centres, so that the shuffled centres
/// in use are spread over the whole square.
const POISSON_FILL: f32 = 0.55;
/// Candidate draws allowed per wanted blade before a density map that rejects nearly
/// everything gives up (a black map must not loop forever).
const ATTEMPTS_PER_BLADE: usize = 64;
const ATTEMPTS_SLACK: usize = 1024;
/// Shortest blade generated: the validation divides by the height.
const MIN_HEIGHT: f32 = 1e-3;

/// Blade root positions (x, z) and the tuft centres used.
#[derive(Clone, Debug, Default)]
pub struct Placement {
    pub roots: Vec<Vec2>,
    /// Only the tests look at the centres (to check the Poisson-disk spacing).
    #[cfg_attr(not(test), allow(dead_code))]
    pub tuft_centres: Vec<Vec2>,
}

/// Keeps candidates where the density map allows grass, with probability equal to the
/// map's value there.
struct Acceptor<'a> {
    density: Option<&'a DensityMap>,
}

impl Acceptor<'_> {
    fn accept(&self, p: Vec2, rng: &mut Rng) -> bool {
        match self.density {
            None => true,
            // `f32()` is in [0, 1): a white pixel (1.0) always accepts, a black one never.
            Some(map) => rng.f32() < map.sample(p.x, p.y),
        }
    }
}

/// Places up to `target` blade roots on the square of side `size` centred on the origin.
/// Fewer come back only when a density map rejects too many candidates.
pub fn place_roots(
    size: f32,
    target: usize,
    field: &Field,
    density: Option<&DensityMap>,
) -> Placement {
    if target == 0 || density.is_some_and(|map| map.max() <= 0.0) {
        return Placement::default();
    }
    let acceptor = Acceptor { density };
    let half = 0.5 * size;
    let fraction = if field.tuft_fraction.is_finite() {
        field.tuft_fraction.clamp(0.0, 1.0)
    } else {
        0.0
    };
    let tuft_target = (fraction * target as f32).round() as usize;
    let mut placement = Placement::default();
    if tuft_target > 0 && field.tuft_radius > 0.0 && field.tuft_radius.is_finite() {
        placement = place_tufts(size, tuft_target.min(target), field, &acceptor);
    }
    // Singles make up whatever the tufts did not place, so that a density map that
    // starves the tufts still gets the requested count where it can.
    let single_target = target - placement.roots.len();
    let mut rng = Rng::new(field.seed, STREAM_SINGLES);
    let cap = single_target * ATTEMPTS_PER_BLADE + ATTEMPTS_SLACK;
    let mut placed = 0;
    for _ in 0..cap {
        if placed == single_target {
            break;
        }
        let p = Vec2::new(rng.range_f32(-half, half), rng.range_f32(-half, half));
        if acceptor.accept(p, &mut rng) {
            placement.roots.push(p);
            placed += 1;
        }
    }
    placement
}

/// Tufts: Poisson-disk centres (at least `TUFT_SPACING` radii apart), each visited for
/// 8–24 candidate blades within the tuft radius, denser towards the centre.
fn place_tufts(size: f32, target: usize, field: &Field, acceptor: &Acceptor) -> Placement {
    let radius = field.tuft_radius;
    let half = 0.5 * size;
    // Centres at least one radius inside the edge keep whole tufts on the terrain.
    let inset = if size > 2.0 * radius {
        half - radius
    } else {
        0.0
    };
    let (lo, hi) = (Vec2::splat(-inset), Vec2::splat(inset));
    let wanted_centres = target.div_ceil(TUFT_MEAN).max(1);
    let area = (2.0 * inset).powi(2);
    // When far fewer tufts are wanted than fit at the minimum spacing, spread them wider:
    // the spacing stays a minimum, and Bridson's cost stays proportional to the tufts used.
    let spacing = (TUFT_SPACING * radius).max((POISSON_FILL * area / wanted_centres as f32).sqrt());
    let mut centres = poisson_disk(lo, hi, spacing, &mut Rng::new(field.seed, STREAM_CENTRES));
    let mut rng = Rng::new(field.seed, STREAM_TUFTS);
    if centres.is_empty() {
        return Placement::default();
    }
    rng.shuffle(&mut centres);

    let mut roots = Vec::with_capacity(target);
    let mut used = 0;
    let cap = target * ATTEMPTS_PER_BLADE + ATTEMPTS_SLACK;
    let mut attempts = 0;
    // Cycling through the centres again (growing the tufts) only happens when the field is
    // so dense that the tufts cannot all fit at the minimum spacing.
    'visits: for visit in 0.. {
        let centre = centres[visit % centres.len()];
        used = used.max((visit % centres.len()) + 1);
        let blades = TUFT_MIN + rng.below(TUFT_MAX - TUFT_MIN + 1);
        for _ in 0..blades {
            if roots.len() == target || attempts == cap {
                break 'visits;
            }
            attempts += 1;
            // Radius linear in u (not √u): the density falls off as 1/r from the centre.
            let r = radius * rng.f32();
            let angle = rng.f32() * std::f32::consts::TAU;
            let p = (centre + r * Vec2::new(angle.cos(), angle.sin()))
                .clamp(-Vec2::splat(half), Vec2::splat(half));
            if acceptor.accept(p, &mut rng) {
                roots.push(p);
            }
        }
    }
    centres.truncate(used);
    Placement {
        roots,
        tuft_centres: centres,
    }
}

/// Drops roots at random until their count is a multiple of `multiple` (only needed when a
/// density map left the field short of its target).
pub fn trim_to_multiple(roots: &mut Vec<Vec2>, multiple: usize, seed: u64) {
    let keep = roots.len() / multiple * multiple;
    if keep < roots.len() {
        // Shuffle first: the tail holds the singles, dropping it would thin them only.
        Rng::new(seed, STREAM_TRIM).shuffle(roots);
        roots.truncate(keep);
    }
}

/// A blade's random draws, taken in root order from one stream before the (costly, and
/// parallel) rest-pose solve, so that the result does not depend on the thread count.
struct BladeDraw {
    root: Vec2,
    angle: f32,
    height: f32,
    width: f32,
    stiffness: f32,
    bend: f32,
}

/// Blades smaller than this many per thread are not worth a thread.
const BLADES_PER_THREAD: usize = 8192;

/// Blades at the given roots, with random attributes from their species' ranges (the
/// field's own without species) and their clump's facing and lean, each in its rest pose
/// on the terrain.
pub fn make_blades(roots: &[Vec2], terrain: &HeightField, field: &Field) -> Vec<Blade> {
    let mut rng = Rng::new(field.seed, STREAM_ATTRIBUTES);
    let traits = super::clumps::FieldTraits::from_field(field);
    let draws: Vec<BladeDraw> = roots
        .iter()
        .map(|&root| {
            let angle = rng.f32() * std::f32::consts::TAU;
            let sizes = [rng.f32(), rng.f32(), rng.f32()];
            let bend = field.bend.lerp(rng.f32()).to_radians();
            // The species' ranges and the clump's facing and lean.
            let (angle, height, width, stiffness, bend) =
                super::clumps::blade_traits(&traits, root.x, root.y, angle, bend, sizes);
            BladeDraw {
                root,
                angle,
                height: height.max(MIN_HEIGHT),
                width,
                stiffness,
                bend,
            }
        })
        .collect();
    let mut blades = vec![Blade::default(); draws.len()];
    // The rest pose is a 40-step bisection per blade: millions of blades take seconds on
    // one core, so the poses are solved in parallel (each blade independently).
    let threads = std::thread::available_parallelism()
        .map_or(1, |n| n.get())
        .min(draws.len().div_ceil(BLADES_PER_THREAD))
        .max(1);
    let chunk = draws.len().div_ceil(threads).max(1);
    std::thread::scope(|scope| {
        for (out, draws) in blades.chunks_mut(chunk).zip(draws.chunks(chunk)) {
            scope.spawn(move || {
                for (blade, draw) in out.iter_mut().zip(draws) {
                    *blade = pose_blade(draw, terrain);
                }
            });
        }
    });
    blades
}

/// One blade rooted on the terrain, growing along the terrain normal, in its rest pose.
fn pose_blade(draw: &BladeDraw, terrain: &HeightField) -> Blade {
    let Vec2 { x, y: z } = draw.root;
    let v0 = Vec3::new(x, terrain.height(x, z), z);
    let up = terrain.normal(x, z);
    let (_, front) = blade_frame(up, draw.angle);
    let (v1, v2) = rest_pose(v0, up, front, draw.height, draw.bend);
    Blade {
        v0_dir: [v0.x, v0.y, v0.z, draw.angle],
        v1_height: [v1.x, v1.y, v1.z, draw.height],
        v2_width: [v2.x, v2.y, v2.z, draw.width],
        up_stiffness: [up.x, up.y, up.z, draw.stiffness],
    }
}

/// The simulation state of a blade at rest: its rest tip is its current tip, η = 0.
pub fn rest_state(blade: &Blade) -> BladeState {
    let v2 = blade.v2_width;
    BladeState {
        rest_eta: [v2[0], v2[1], v2[2], 0.0],
    }
}
