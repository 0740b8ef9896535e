//! Sphere packing of a closed mesh (Jahrmann & Wimmer 2017, Section 5.3: complex objects
//! approximated by spheres), computed from the mesh itself:
//!
//! 1. **Voxels.** A grid of cubic voxels over the mesh's box (`resolution` along its longest
//!    side). A voxel is inside when its centre is inside the mesh: rays through the voxel
//!    centres along x, y and z each count crossings with the triangles (parity), and the
//!    majority of the three decides, so that a ray grazing an edge or slipping through a
//!    small hole does not flip a whole line of voxels.
//! 2. **Distances.** The exact Euclidean distance from every inside voxel centre to the
//!    nearest outside voxel centre (Felzenszwalb & Huttenlocher's separable transform). A
//!    sphere at a voxel with radius (distance − ½ voxel) stays inside the voxelised solid.
//! 3. **Greedy packing, largest first.** Repeatedly, the voxel not yet covered whose
//!    inscribed sphere is the largest gets a sphere, and the inside voxels in it are
//!    covered; until `count` spheres, or every inside voxel is covered.
//!
//! [`Packing::coverage`] says how well the spheres cover the mesh: the share of its inside
//! voxels that lie in some sphere. Spheres never reach out of the solid by more than the
//! voxel's half-diagonal (they are inscribed in the voxelised solid), so they do not push
//! grass where there is no mesh.

use glam::Vec3;

use super::Mesh;

/// Voxels along the longest side of the mesh's box when the scene does not say.
pub const DEFAULT_RESOLUTION: u32 = 64;

/// The result of [`pack`], in the mesh's own units.
#[derive(Clone, Debug, PartialEq)]
pub struct Packing {
    /// Centre x, y, z and radius of every sphere, largest first.
    pub spheres: Vec<[f32; 4]>,
    /// Share of the inside voxels that some sphere covers, 0–1.
    pub coverage: f32,
    /// Voxels whose centre is inside the mesh.
    pub inside_voxels: usize,
    /// Side of a voxel.
    pub voxel: f32,
    /// For an animated object, what moves the spheres with its pose (`None`: they stay
    /// where the mesh's rest places them).
    pub rig: Option<Box<SphereRig>>,
}

/// The spheres of an animated object's packing tied to its skeleton: each follows the joint
/// that weighs most on the mesh vertex nearest its centre, so a figure's legs push the
/// grass as they swing.
#[derive(Clone, Debug, PartialEq)]
pub struct SphereRig {
    /// The skinned mesh and its skeleton.
    pub mesh: super::skin::SkinnedMesh,
    /// The animation it plays.
    pub animation: usize,
    /// Per sphere, the joint it follows (an index into `mesh.joints`).
    pub joint_of: Vec<usize>,
}

impl SphereRig {
    /// Ties each sphere of `spheres` (in the mesh's bind space) to a joint of `mesh`.
    pub fn new(mesh: &super::skin::SkinnedMesh, animation: usize, spheres: &[[f32; 4]]) -> Self {
        let joint_of = spheres
            .iter()
            .map(|s| {
                let c = Vec3::new(s[0], s[1], s[2]);
                let nearest = mesh
                    .positions
                    .iter()
                    .enumerate()
                    .min_by(|(_, a), (_, b)| {
                        let da = Vec3::from(**a).distance_squared(c);
                        let db = Vec3::from(**b).distance_squared(c);
                        da.total_cmp(&db)
                    })
                    .map_or(0, |(i, _)| i);
                let (j, w) = (mesh.joint_indices[nearest], mesh.weights[nearest]);
                let k = (0..4).max_by(|&a, &b| w[a].total_cmp(&w[b])).unwrap_or(0);
                usize::from(j[k])
            })
            .collect();
        Self {
            mesh: mesh.clone(),
            animation,
            joint_of,
        }
    }

    /// One sphere per joint of `mesh` around the vertices it moves most (centroid; radius
    /// the root-mean-square distance from it, at least 2 cm), tied to that joint: the
    /// packing of `MeshCollider::Joints`. A joint that moves no vertex most has no sphere.
    pub fn joint_spheres(mesh: &super::skin::SkinnedMesh, animation: usize) -> Packing {
        let mut sums = vec![(Vec3::ZERO, 0usize); mesh.joints.len()];
        let dominant = |v: usize| {
            let (j, w) = (mesh.joint_indices[v], mesh.weights[v]);
            let k = (0..4).max_by(|&a, &b| w[a].total_cmp(&w[b])).unwrap_or(0);
            usize::from(j[k])
        };
        for (v, p) in mesh.positions.iter().enumerate() {
            let s = &mut sums[dominant(v)];
            s.0 += Vec3::from(*p);
            s.1 += 1;
        }
        let mut spread = vec![0.0f32; mesh.joints.len()];
        for (v, p) in mesh.positions.iter().enumerate() {
            let j = dominant(v);
            let c = sums[j].0 / sums[j].1 as f32;
            spread[j] += Vec3::from(*p).distance_squared(c);
        }
        let (mut spheres, mut joint_of) = (Vec::new(), Vec::new());
        for (j, (sum, n)) in sums.iter().enumerate() {
            if *n == 0 {
                continue;
            }
            let c = *sum / *n as f32;
            let r = (spread[j] / *n as f32).sqrt().max(0.02);
            spheres.push([c.x, c.y, c.z, r]);
            joint_of.push(j);
        }
        Packing {
            spheres,
            coverage: 1.0,
            inside_voxels: 0,
            voxel: 0.0,
            rig: Some(Box::new(SphereRig {
                mesh: mesh.clone(),
                animation,
                joint_of,
            })),
        }
    }

    /// The spheres at `time`, in the mesh's space (each moved by its joint's skinning
    /// matrix; radii unchanged: a skeleton's joints do not scale).
    pub fn posed(&self, spheres: &[[f32; 4]], time: f32) -> Vec<[f32; 4]> {
        let joints = self.mesh.joint_matrices(Some(self.animation), time);
        spheres
            .iter()
            .zip(&self.joint_of)
            .map(|(s, &j)| {
                let m = joints.get(j).copied().unwrap_or(glam::Mat4::IDENTITY);
                let c = m.transform_point3(Vec3::new(s[0], s[1], s[2]));
                [c.x, c.y, c.z, s[3]]
            })
            .collect()
    }
}

/// The voxel grid of a mesh: inside flags, x fastest.
struct Voxels {
    dims: [usize; 3],
    origin: Vec3,
    size: f32,
    inside: Vec<bool>,
}

impl Voxels {
    fn index(&self, x: usize, y: usize, z: usize) -> usize {
        (z * self.dims[1] + y) * self.dims[0] + x
    }

    fn centre(&self, x: usize, y: usize, z: usize) -> Vec3 {
        self.origin + (Vec3::new(x as f32, y as f32, z as f32) + 0.5) * self.size
    }
}

/// Crossings of the lines along `axis` through every voxel centre with the triangles:
/// for each line (the two other coordinates), the sorted positions along `axis` where it
/// crosses the surface. Each triangle only visits the lines inside its projected box.
fn crossings(mesh: &Mesh, grid: &Voxels, axis: usize) -> Vec<Vec<f32>> {
    let (a, b) = ((axis + 1) % 3, (axis + 2) % 3);
    let (na, nb) = (grid.dims[a], grid.dims[b]);
    let mut lines = vec![Vec::new(); na * nb];
    let p = |i: u32| Vec3::from(mesh.positions[i as usize]);
    for t in mesh.indices.chunks_exact(3) {
        let (p0, p1, p2) = (p(t[0]), p(t[1]), p(t[2]));
        let lo = p0.min(p1).min(p2);
        let hi = p0.max(p1).max(p2);
        // Line (ia, ib) runs through origin + (i + ½) · size on the two other axes.
        let range = |k: usize, n: usize| {
            let first = ((lo[k] - grid.origin[k]) / grid.size - 0.5).ceil().max(0.0) as usize;
            let last = ((hi[k] - grid.origin[k]) / grid.size - 0.5).floor();
            let last = if last < 0.0 {
                0
            } else {
                (last as usize + 1).min(n)
            };
            first..last
        };
        for ib in range(b, nb) {
            for ia in range(a, na) {
                let qa = grid.origin[a] + (ia as f32 + 0.5) * grid.size;
                let qb = grid.origin[b] + (ib as f32 + 0.5) * grid.size;
                if let Some(at) = line_hit([p0, p1, p2], a, b, axis, qa, qb) {
                    lines[ib * na + ia].push(at);
                }
            }
        }
    }
    for line in &mut lines {
        line.sort_by(f32::total_cmp);
    }
    lines
}

/// Where the line {coordinate a = qa, coordinate b = qb} crosses the triangle, as its
/// coordinate along `axis`; a point exactly on an edge counts for the triangle on one side
/// only (half-open edge rule), so a line through a shared edge crosses once.
fn line_hit(t: [Vec3; 3], a: usize, b: usize, axis: usize, qa: f32, qb: f32) -> Option<f32> {
    let (x0, y0) = (t[0][a] - qa, t[0][b] - qb);
    let (x1, y1) = (t[1][a] - qa, t[1][b] - qb);
    let (x2, y2) = (t[2][a] - qa, t[2][b] - qb);
    // Signed areas of the sub-triangles around the line's point, in f64 for a stable sign.
    let e = |xa: f32, ya: f32, xb: f32, yb: f32| {
        f64::from(xa) * f64::from(yb) - f64::from(ya) * f64::from(xb)
    };
    let (w0, w1, w2) = (e(x1, y1, x2, y2), e(x2, y2, x0, y0), e(x0, y0, x1, y1));
    let all_pos = w0 >= 0.0 && w1 >= 0.0 && w2 >= 0.0;
    let all_neg = w0 <= 0.0 && w1 <= 0.0 && w2 <= 0.0;
    let sum = w0 + w1 + w2;
    if !(all_pos || all_neg) || sum == 0.0 {
        return None;
    }
    // Half-open rule: a zero weight counts only on one side of its edge.
    for (w, (xa, ya, xb, yb)) in [
        (w0, (x1, y1, x2, y2)),
        (w1, (x2, y2, x0, y0)),
        (w2, (x0, y0, x1, y1)),
    ] {
        if w == 0.0 {
            let (dx, dy) = (xb - xa, yb - ya);
            let owner = if sum > 0.0 {
                dy > 0.0 || (dy == 0.0 && dx < 0.0)
            } else {
                dy < 0.0 || (dy == 0.0 && dx > 0.0)
            };
            if !owner {
                return None;
            }
        }
    }
    let at = (w0 * f64::from(t[0][axis]) + w1 * f64::from(t[1][axis]) + w2 * f64::from(t[2][axis]))
        / sum;
    Some(at as f32)
}

/// The voxels of `mesh` at `resolution` voxels along its longest side.
fn voxelise(mesh: &Mesh, resolution: u32) -> Voxels {
    let (lo, hi) = mesh.bounds();
    let extent = (hi - lo).max(Vec3::splat(1e-6));
    let size = extent.max_element() / resolution.max(1) as f32;
    // One empty voxel of margin on every side, so the outside is never empty.
    let dims = [0, 1, 2].map(|k| (extent[k] / size).ceil() as usize + 2);
    let origin = lo - Vec3::splat(size);
    let mut grid = Voxels {
        dims,
        origin,
        size,
        inside: vec![false; dims[0] * dims[1] * dims[2]],
    };
    let mut votes = vec![0u8; grid.inside.len()];
    for axis in 0..3 {
        let lines = crossings(mesh, &grid, axis);
        let (a, b) = ((axis + 1) % 3, (axis + 2) % 3);
        let na = dims[a];
        for (line_index, hits) in lines.iter().enumerate() {
            let (ia, ib) = (line_index % na, line_index / na);
            let mut crossed = 0;
            for k in 0..dims[axis] {
                let along = origin[axis] + (k as f32 + 0.5) * size;
                while crossed < hits.len() && hits[crossed] < along {
                    crossed += 1;
                }
                if crossed % 2 == 1 {
                    let mut c = [0usize; 3];
                    c[axis] = k;
                    c[a] = ia;
                    c[b] = ib;
                    votes[grid.index(c[0], c[1], c[2])] += 1;
                }
            }
        }
    }
    for (inside, v) in grid.inside.iter_mut().zip(votes) {
        *inside = v >= 2;
    }
    grid
}

/// One pass of the 1D squared distance transform (lower envelope of parabolas) over `f`,
/// in voxel units.
fn edt_1d(f: &[f64], out: &mut [f64]) {
    let n = f.len();
    let mut v = vec![0usize; n];
    let mut z = vec![0f64; n + 1];
    let mut k = 0usize;
    z[0] = f64::NEG_INFINITY;
    z[1] = f64::INFINITY;
    let inf = f64::INFINITY;
    for q in 1..n {
        if f[q] == inf {
            continue;
        }
        loop {
            let p = v[k];
            if f[p] == inf {
                // The envelope so far is empty: start it here.
                v[k] = q;
                z[k] = f64::NEG_INFINITY;
                z[k + 1] = f64::INFINITY;
                break;
            }
            let s = ((f[q] + (q * q) as f64) - (f[p] + (p * p) as f64)) / (2.0 * (q - p) as f64);
            if s <= z[k] && k > 0 {
                k -= 1;
                continue;
            }
            if s <= z[k] {
                v[k] = q;
                z[k + 1] = f64::INFINITY;
                break;
            }
            k += 1;
            v[k] = q;
            z[k] = s;
            z[k + 1] = f64::INFINITY;
            break;
        }
    }
    k = 0;
    for (q, o) in out.iter_mut().enumerate() {
        while z[k + 1] < q as f64 {
            k += 1;
        }
        let p = v[k];
        *o = if f[p] == inf {
            inf
        } else {
            (q as f64 - p as f64).powi(2) + f[p]
        };
    }
}

/// Squared distance (in voxels²) from every voxel centre to the nearest outside one (0
/// outside).
fn distance_squared(grid: &Voxels) -> Vec<f64> {
    let [nx, ny, nz] = grid.dims;
    let mut d: Vec<f64> = grid
        .inside
        .iter()
        .map(|&i| if i { f64::INFINITY } else { 0.0 })
        .collect();
    let mut line = Vec::new();
    let mut out = Vec::new();
    // x, then y, then z lines.
    for (axis, n) in [(0usize, nx), (1, ny), (2, nz)] {
        line.resize(n, 0.0);
        out.resize(n, 0.0);
        let (o1, o2) = match axis {
            0 => (ny, nz),
            1 => (nx, nz),
            _ => (nx, ny),
        };
        for b in 0..o2 {
            for a in 0..o1 {
                let at = |k: usize| match axis {
                    0 => grid.index(k, a, b),
                    1 => grid.index(a, k, b),
                    _ => grid.index(a, b, k),
                };
                for (k, l) in line.iter_mut().enumerate() {
                    *l = d[at(k)];
                }
                edt_1d(&line, &mut out);
                for (k, o) in out.iter().enumerate() {
                    d[at(k)] = *o;
                }
            }
        }
    }
    d
}

/// Packs at most `count` spheres into `mesh` on a grid of `resolution` voxels along the
/// box's longest side (see the module docs).
pub fn pack(mesh: &Mesh, count: usize, resolution: u32) -> Packing {
    let grid = voxelise(mesh, resolution);
    let d2 = distance_squared(&grid);
    let inside_voxels = grid.inside.iter().filter(|&&i| i).count();
    // Largest inscribed radius first (ties by index, so the result is deterministic).
    let mut order: Vec<usize> = (0..grid.inside.len()).filter(|&i| grid.inside[i]).collect();
    order.sort_by(|&a, &b| d2[b].total_cmp(&d2[a]).then(a.cmp(&b)));
    let mut covered = vec![false; grid.inside.len()];
    let mut covered_count = 0usize;
    let mut spheres = Vec::with_capacity(count);
    let [nx, ny, nz] = grid.dims;
    for &v in &order {
        if spheres.len() >= count || covered_count == inside_voxels {
            break;
        }
        if covered[v] {
            continue;
        }
        let (x, y, z) = (v % nx, (v / nx) % ny, v / (nx * ny));
        // In voxels: the distance to the nearest outside centre, less half a voxel.
        let r_vox = (d2[v].sqrt() - 0.5).max(0.5);
        let centre = grid.centre(x, y, z);
        spheres.push([centre.x, centre.y, centre.z, r_vox as f32 * grid.size]);
        let reach = r_vox.ceil() as usize;
        let span = |c: usize, n: usize| c.saturating_sub(reach)..(c + reach + 1).min(n);
        for zz in span(z, nz) {
            for yy in span(y, ny) {
                for xx in span(x, nx) {
                    let i = grid.index(xx, yy, zz);
                    let dist2 = (xx as f64 - x as f64).powi(2)
                        + (yy as f64 - y as f64).powi(2)
                        + (zz as f64 - z as f64).powi(2);
                    if grid.inside[i] && !covered[i] && dist2 <= r_vox * r_vox {
                        covered[i] = true;
                        covered_count += 1;
                    }
                }
            }
        }
    }
    Packing {
        spheres,
        coverage: if inside_voxels == 0 {
            0.0
        } else {
            covered_count as f32 / inside_voxels as f32
        },
        inside_voxels,
        voxel: grid.size,
        rig: None,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A closed UV sphere of radius `r` at the origin.
    fn ball(r: f32, rings: u32, segments: u32) -> Mesh {
        let mut positions = vec![[0.0, r, 0.0]];
        for i in 1..rings {
            let theta = std::f32::consts::PI * i as f32 / rings as f32;
            for j in 0..segments {
                let phi = std::f32::consts::TAU * j as f32 / segments as f32;
                positions.push([
                    r * theta.sin() * phi.cos(),
                    r * theta.cos(),
                    r * theta.sin() * phi.sin(),
                ]);
            }
        }
        positions.push([0.0, -r, 0.0]);
        let bottom = positions.len() as u32 - 1;
        let at = |i: u32, j: u32| 1 + (i - 1) * segments + j % segments;
        let mut indices = Vec::new();
        for j in 0..segments {
            indices.extend([0, at(1, j + 1), at(1, j)]);
            indices.extend([bottom, at(rings - 1, j), at(rings - 1, j + 1)]);
        }
        for i in 1..rings - 1 {
            for j in 0..segments {
                indices.extend([at(i, j), at(i, j + 1), at(i + 1, j)]);
                indices.extend([at(i, j + 1), at(i + 1, j + 1), at(i + 1, j)]);
            }
        }
        Mesh {
            normals: positions.clone(),
            positions,
            indices,
            degenerate: 0,
        }
    }

    /// An axis-aligned box mesh from `lo` to `hi`.
    fn cuboid(lo: Vec3, hi: Vec3) -> Mesh {
        let c = |x: bool, y: bool, z: bool| {
            [
                if x { hi.x } else { lo.x },
                if y { hi.y } else { lo.y },
                if z { hi.z } else { lo.z },
            ]
        };
        let positions: Vec<[f32; 3]> = (0..8)
            .map(|i| c(i & 1 != 0, i & 2 != 0, i & 4 != 0))
            .collect();
        let quads = [
            [0, 2, 3, 1],
            [4, 5, 7, 6],
            [0, 1, 5, 4],
            [2, 6, 7, 3],
            [0, 4, 6, 2],
            [1, 3, 7, 5],
        ];
        let indices = quads
            .iter()
            .flat_map(|q| [q[0], q[1], q[2], q[0], q[2], q[3]])
            .collect();
        Mesh {
            normals: positions.clone(),
            positions,
            indices,
            degenerate: 0,
        }
    }

    #[test]
    fn the_voxels_of_a_ball_fill_its_volume() {
        let grid = voxelise(&ball(1.0, 24, 48), 40);
        let inside = grid.inside.iter().filter(|&&i| i).count() as f32;
        let volume = inside * grid.size.powi(3);
        let exact = 4.0 / 3.0 * std::f32::consts::PI;
        println!("ball voxel volume {volume:.3} against {exact:.3}");
        // The polygonal ball is a little smaller than the round one.
        assert!((volume - exact).abs() < 0.06 * exact, "{volume}");
    }

    #[test]
    fn one_sphere_fills_a_ball() {
        let p = pack(&ball(2.0, 24, 48), 1, 48);
        let [x, y, z, r] = p.spheres[0];
        println!("one sphere in a ball of 2: centre ({x:.3}, {y:.3}, {z:.3}), radius {r:.3}");
        assert!(Vec3::new(x, y, z).length() < 1.5 * p.voxel);
        assert!(r > 2.0 - 3.0 * p.voxel && r < 2.0, "radius {r}");
        assert!(p.coverage > 0.8, "coverage {}", p.coverage);
    }

    #[test]
    fn more_spheres_cover_more_and_stay_inside_a_box() {
        let (lo, hi) = (Vec3::new(-2.0, 0.0, -0.5), Vec3::new(2.0, 1.0, 0.5));
        let mesh = cuboid(lo, hi);
        let mut last = 0.0;
        for count in [1, 8, 64, 512] {
            let p = pack(&mesh, count, 48);
            println!(
                "box 4 × 1 × 1, {count} spheres: coverage {:.3} of {} voxels",
                p.coverage, p.inside_voxels
            );
            assert!(p.spheres.len() <= count);
            assert!(p.coverage >= last, "coverage fell: {} < {last}", p.coverage);
            last = p.coverage;
            for s in &p.spheres {
                let c = Vec3::new(s[0], s[1], s[2]);
                // Distance from the centre to the box's nearest face.
                let to_face = (c - lo).min(hi - c).min_element();
                assert!(
                    s[3] <= to_face + 0.75 * p.voxel,
                    "sphere {s:?} reaches out of the box ({to_face})"
                );
            }
            // Largest first.
            assert!(p.spheres.windows(2).all(|w| w[0][3] >= w[1][3]));
        }
        assert!(last > 0.9, "512 spheres cover {last}");
    }

    #[test]
    fn packing_is_deterministic() {
        let mesh = ball(1.0, 12, 24);
        assert_eq!(pack(&mesh, 50, 32), pack(&mesh, 50, 32));
    }

    #[test]
    fn the_bunny_is_covered_by_a_thousand_spheres() {
        let path = concat!(env!("CARGO_MANIFEST_DIR"), "/../../assets/models/bunny.obj");
        let mesh = super::super::load(std::path::Path::new(path)).expect("bunny");
        let p = pack(&mesh, 1000, DEFAULT_RESOLUTION);
        println!(
            "bunny: {} spheres, coverage {:.3} of {} inside voxels of {:.4}",
            p.spheres.len(),
            p.coverage,
            p.inside_voxels,
            p.voxel
        );
        assert_eq!(p.spheres.len(), 1000);
        assert!(p.coverage > 0.85, "coverage {}", p.coverage);
    }
}
