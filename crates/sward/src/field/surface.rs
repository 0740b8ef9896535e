//! Grass on a mesh's surface (issue 14, point 2; Jahrmann & Wimmer grow blades on any 3D
//! model): roots placed by area-weighted sampling of the placed mesh's triangles, seeded,
//! a share of them in tufts; each blade grows along the surface normal interpolated at its
//! root (so blades stand out of slopes, walls and overhangs), with its height, width,
//! stiffness and bend drawn from the object's ranges, in its rest pose. Gravity stays
//! world-down in the update, so blades on steep faces hang as real grass does.
//!
//! The blades are cut into compact patches by a k-d split across their longest extent in
//! x, y and z (a surface folds in 3D, unlike the terrain), so that every culling test,
//! level of detail and occlusion pass runs on them as on the terrain's blades.

use glam::{Mat3, Mat4, Vec3};

use super::blade::{blade_frame, rest_pose};
use super::blade::{Blade, PatchBox};
use super::patches::morton;
use super::rng::Rng;
use crate::mesh::Mesh;
use crate::scene::types::Field;

/// RNG streams of the surface placement.
const STREAM_ROOTS: u64 = 11;
const STREAM_ATTRIBUTES: u64 = 12;

/// Shortest blade (as `placement::MIN_HEIGHT`).
const MIN_HEIGHT: f32 = 1e-3;

/// A placed mesh in world space: positions, unit normals, triangles and their areas.
struct Placed {
    positions: Vec<Vec3>,
    normals: Vec<Vec3>,
    triangles: Vec<[usize; 3]>,
    /// Running sum of the triangle areas (the sampling's cumulative distribution).
    cumulative: Vec<f64>,
}

impl Placed {
    fn new(mesh: &Mesh, model: Mat4) -> Self {
        let normal_matrix = Mat3::from_mat4(model).inverse().transpose();
        let positions: Vec<Vec3> = mesh
            .positions
            .iter()
            .map(|p| model.transform_point3(Vec3::from(*p)))
            .collect();
        let normals = mesh
            .normals
            .iter()
            .map(|n| (normal_matrix * Vec3::from(*n)).normalize_or_zero())
            .collect();
        let triangles: Vec<[usize; 3]> = mesh
            .indices
            .chunks_exact(3)
            .map(|t| [t[0] as usize, t[1] as usize, t[2] as usize])
            .collect();
        let mut total = 0.0f64;
        let cumulative = triangles
            .iter()
            .map(|t| {
                let [a, b, c] = t.map(|i| positions[i]);
                total += f64::from(0.5 * (b - a).cross(c - a).length());
                total
            })
            .collect();
        Self {
            positions,
            normals,
            triangles,
            cumulative,
        }
    }

    fn area(&self) -> f64 {
        self.cumulative.last().copied().unwrap_or(0.0)
    }

    /// A point uniformly distributed over the surface: its position, interpolated normal
    /// (the face normal where the vertex normals cancel) and triangle.
    fn sample(&self, rng: &mut Rng) -> (Vec3, Vec3, usize) {
        let target = f64::from(rng.f32()) * self.area();
        let t = self
            .cumulative
            .partition_point(|&c| c <= target)
            .min(self.triangles.len() - 1);
        let [ia, ib, ic] = self.triangles[t];
        let (a, b, c) = (self.positions[ia], self.positions[ib], self.positions[ic]);
        // Uniform barycentric coordinates (the square-root warp).
        let (r1, r2) = (rng.f32().sqrt(), rng.f32());
        let (wa, wb, wc) = (1.0 - r1, r1 * (1.0 - r2), r1 * r2);
        let p = a * wa + b * wb + c * wc;
        let n = self.normals[ia] * wa + self.normals[ib] * wb + self.normals[ic] * wc;
        let face = (b - a).cross(c - a).normalize_or_zero();
        (p, n.try_normalize().unwrap_or(face), t)
    }

    /// The normal interpolated at point `p` of triangle `t` (barycentric weights of the
    /// vertex normals; the face normal where they cancel), so that a tuft's blades follow a
    /// curved surface as single blades do.
    fn normal_at(&self, t: usize, p: Vec3) -> Vec3 {
        let [ia, ib, ic] = self.triangles[t];
        let [a, b, c] = [ia, ib, ic].map(|i| self.positions[i]);
        let n = (b - a).cross(c - a);
        let face = n.normalize_or_zero();
        let area2 = n.length_squared();
        if area2 <= 0.0 {
            return face;
        }
        let wa = (c - b).cross(p - b).dot(n) / area2;
        let wb = (a - c).cross(p - c).dot(n) / area2;
        let wc = 1.0 - wa - wb;
        let normal = self.normals[ia] * wa + self.normals[ib] * wb + self.normals[ic] * wc;
        normal.try_normalize().unwrap_or(face)
    }

    /// The point of triangle `t` nearest `p` (Ericson, Real-Time Collision Detection 5.1.5).
    fn closest_on(&self, t: usize, p: Vec3) -> Vec3 {
        let [a, b, c] = self.triangles[t].map(|i| self.positions[i]);
        let (ab, ac, ap) = (b - a, c - a, p - a);
        let (d1, d2) = (ab.dot(ap), ac.dot(ap));
        if d1 <= 0.0 && d2 <= 0.0 {
            return a;
        }
        let bp = p - b;
        let (d3, d4) = (ab.dot(bp), ac.dot(bp));
        if d3 >= 0.0 && d4 <= d3 {
            return b;
        }
        let vc = d1 * d4 - d3 * d2;
        if vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0 {
            return a + ab * (d1 / (d1 - d3));
        }
        let cp = p - c;
        let (d5, d6) = (ab.dot(cp), ac.dot(cp));
        if d6 >= 0.0 && d5 <= d6 {
            return c;
        }
        let vb = d5 * d2 - d1 * d6;
        if vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0 {
            return a + ac * (d2 / (d2 - d6));
        }
        let va = d3 * d6 - d5 * d4;
        if va <= 0.0 && (d4 - d3) >= 0.0 && (d5 - d6) >= 0.0 {
            return b + (c - b) * ((d4 - d3) / ((d4 - d3) + (d5 - d6)));
        }
        let denom = 1.0 / (va + vb + vc);
        a + ab * (vb * denom) + ac * (vc * denom)
    }
}

/// The area in m² of `mesh` placed by `model`.
pub fn surface_area(mesh: &Mesh, model: Mat4) -> f64 {
    Placed::new(mesh, model).area()
}

/// The blades of `grass` on `mesh` placed by `model`: density × area blades rounded up to
/// whole patches of `patch_size`, as consecutive patches (see the module docs), with their
/// boxes. Empty when the density or the area is 0.
pub fn surface_field(
    mesh: &Mesh,
    model: Mat4,
    grass: &Field,
    patch_size: usize,
) -> (Vec<Blade>, Vec<PatchBox>) {
    let placed = Placed::new(mesh, model);
    let wanted = f64::from(grass.density) * placed.area();
    if !(wanted.is_finite() && wanted >= 1.0) || placed.triangles.is_empty() || patch_size == 0 {
        return (Vec::new(), Vec::new());
    }
    let count = (wanted.ceil() as usize).div_ceil(patch_size) * patch_size;
    let mut roots = Rng::new(grass.seed, STREAM_ROOTS);
    let mut attributes = Rng::new(grass.seed, STREAM_ATTRIBUTES);
    let mut blades = Vec::with_capacity(count);
    // A tuft: blades around the last single root, in its tangent plane, kept on that
    // root's triangle (a tuft at a triangle's edge crowds towards it rather than leave the
    // surface).
    let mut anchor: Option<(Vec3, Vec3, usize)> = None;
    while blades.len() < count {
        let (root, up) = match anchor {
            Some((centre, normal, t)) if roots.f32() < grass.tuft_fraction => {
                let (side, front) = blade_frame(normal, roots.f32() * std::f32::consts::TAU);
                let r = grass.tuft_radius * roots.f32().sqrt();
                let a = roots.f32() * std::f32::consts::TAU;
                let p = placed.closest_on(t, centre + (side * a.cos() + front * a.sin()) * r);
                (p, placed.normal_at(t, p))
            }
            _ => {
                let s = placed.sample(&mut roots);
                anchor = Some(s);
                (s.0, s.1)
            }
        };
        let angle = attributes.f32() * std::f32::consts::TAU;
        let height = grass.height.lerp(attributes.f32()).max(MIN_HEIGHT);
        let width = grass.width.lerp(attributes.f32());
        let stiffness = grass.stiffness.lerp(attributes.f32());
        let bend = grass.bend.lerp(attributes.f32()).to_radians();
        let (_, front) = blade_frame(up, angle);
        let (v1, v2) = rest_pose(root, up, front, height, bend);
        blades.push(Blade {
            v0_dir: [root.x, root.y, root.z, angle],
            v1_height: [v1.x, v1.y, v1.z, height],
            v2_width: [v2.x, v2.y, v2.z, width],
            up_stiffness: [up.x, up.y, up.z, stiffness],
        });
    }
    let patches = patches_3d(&mut blades, patch_size);
    (blades, patches)
}

fn root(b: &Blade) -> Vec3 {
    Vec3::new(b.v0_dir[0], b.v0_dir[1], b.v0_dir[2])
}

/// Balanced k-d split across the longest of x, y, z, then each patch in Morton order of
/// its x, z (as `patches::build_patches` does on the terrain) and its box.
fn patches_3d(blades: &mut [Blade], patch_size: usize) -> Vec<PatchBox> {
    split(blades, patch_size);
    blades
        .chunks_mut(patch_size)
        .map(|patch| {
            let (lo, hi) = bounds(patch);
            let extent = (hi - lo).max(Vec3::splat(1e-6));
            patch.sort_by_key(|b| {
                let q = (root(b) - lo) / extent * 65535.0;
                morton(q.x as u32, q.z as u32)
            });
            super::patches::patch_box(patch)
        })
        .collect()
}

fn bounds(blades: &[Blade]) -> (Vec3, Vec3) {
    blades.iter().fold(
        (Vec3::splat(f32::INFINITY), Vec3::splat(f32::NEG_INFINITY)),
        |(lo, hi), b| (lo.min(root(b)), hi.max(root(b))),
    )
}

fn split(blades: &mut [Blade], patch_size: usize) {
    let patches = blades.len() / patch_size;
    if patches <= 1 {
        return;
    }
    let (lo, hi) = bounds(blades);
    let e = hi - lo;
    let axis = if e.x >= e.y && e.x >= e.z {
        0
    } else if e.y >= e.z {
        1
    } else {
        2
    };
    let left = patches / 2 * patch_size;
    blades.select_nth_unstable_by(left, |a, b| a.v0_dir[axis].total_cmp(&b.v0_dir[axis]));
    let (l, r) = blades.split_at_mut(left);
    split(l, patch_size);
    split(r, patch_size);
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A cube of side 2 centred on the origin, its faces' normals outward.
    fn cube() -> Mesh {
        let positions: Vec<[f32; 3]> = (0..8)
            .map(|i| {
                [
                    if i & 1 != 0 { 1.0 } else { -1.0 },
                    if i & 2 != 0 { 1.0 } else { -1.0 },
                    if i & 4 != 0 { 1.0 } else { -1.0 },
                ]
            })
            .collect();
        // Each face its own vertices would give flat normals; with shared corners the
        // normals are the corner averages, so the test below checks flat faces through a
        // box of separate faces.
        let quads = [
            [0, 2, 3, 1],
            [4, 5, 7, 6],
            [0, 1, 5, 4],
            [2, 6, 7, 3],
            [0, 4, 6, 2],
            [1, 3, 7, 5],
        ];
        let mut p = Vec::new();
        let mut n = Vec::new();
        let mut indices = Vec::new();
        for q in quads {
            let [a, b, c] = [q[0], q[1], q[2]].map(|i| Vec3::from(positions[i]));
            let normal = (b - a).cross(c - a).normalize();
            let base = p.len() as u32;
            for i in q {
                p.push(positions[i]);
                n.push(normal.to_array());
            }
            indices.extend([base, base + 1, base + 2, base, base + 2, base + 3]);
        }
        Mesh {
            positions: p,
            normals: n,
            indices,
            degenerate: 0,
        }
    }

    fn grass(density: f32) -> Field {
        Field {
            density,
            tuft_fraction: 0.3,
            tuft_radius: 0.05,
            ..Field::default()
        }
    }

    #[test]
    fn blades_cover_each_face_in_proportion_to_its_area_standing_out_of_it() {
        // Stretched along x: the four faces along x are 4 × 2, the two ends 2 × 2.
        let model = Mat4::from_scale(Vec3::new(2.0, 1.0, 1.0));
        let (blades, patches) = surface_field(&cube(), model, &grass(200.0), 64);
        let area = 4.0 * 8.0 + 2.0 * 4.0;
        assert_eq!(
            blades.len(),
            ((200.0f32 * area).ceil() as usize).div_ceil(64) * 64
        );
        assert_eq!(patches.len(), blades.len() / 64);
        let mut per_face = [0usize; 6];
        for b in &blades {
            let p = root(b);
            let up = Vec3::new(b.up_stiffness[0], b.up_stiffness[1], b.up_stiffness[2]);
            // Each root lies on the box (tufts stay on their anchor's triangle).
            let d = Vec3::new(p.x.abs() - 2.0, p.y.abs() - 1.0, p.z.abs() - 1.0);
            assert!(d.max_element().abs() < 1e-4, "root {p} is off the surface");
            // Up is the face's normal.
            let k = up.abs().max_position();
            assert!(up.abs()[k] > 0.999, "up {up} is not a face normal");
            assert!(
                d[k].abs() < 1e-4 && p[k].signum() == up[k].signum(),
                "{p} {up}"
            );
            per_face[k * 2 + usize::from(up[k] > 0.0)] += 1;
        }
        println!("blades per face (−x, +x, −y, +y, −z, +z): {per_face:?}");
        let n = blades.len() as f32;
        for (f, &count) in per_face.iter().enumerate() {
            let share = if f < 2 { 4.0 / area } else { 8.0 / area };
            let expected = share * n;
            assert!(
                (count as f32 - expected).abs() < 0.15 * expected,
                "face {f}: {count} blades, expected about {expected}"
            );
        }
        // Patches are compact: each one's roots span far less than the object (4 × 2 × 2).
        for patch in blades.chunks(64) {
            let (lo, hi) = bounds(patch);
            assert!((hi - lo).length() < 1.5, "a patch spans {}", hi - lo);
        }
    }

    #[test]
    fn placement_is_seeded_and_empty_without_density() {
        let a = surface_field(&cube(), Mat4::IDENTITY, &grass(50.0), 64);
        let b = surface_field(&cube(), Mat4::IDENTITY, &grass(50.0), 64);
        assert_eq!(a, b);
        let mut other = grass(50.0);
        other.seed += 1;
        assert_ne!(a.0, surface_field(&cube(), Mat4::IDENTITY, &other, 64).0);
        assert!(surface_field(&cube(), Mat4::IDENTITY, &grass(0.0), 64)
            .0
            .is_empty());
    }
}
