//! Grass placed on meshes and sphere packings (issue 14, points 2, 3a and the tests it
//! lists), on the CPU (the placement is the CPU's; the update of surface blades is compared
//! with its twin in `tests/surface_grass.rs`):
//! - the blades per m² within 10 % of the requested density in every region of a sphere
//!   mesh and on both sides of a mesh with triangles 10,000 times apart in area;
//! - every root within 1 mm of the surface, every up vector within 5° of the normal
//!   interpolated at the root;
//! - the paper's invariants for surface blades after the update: the curve's length equals
//!   the height, no tip below the blade's own ground plane, the rest pose a fixed point;
//! - every packed sphere's centre inside the mesh (by a ray-parity test against its
//!   triangles, independent of the packer's voxels), the covered share reported and bounded.

mod common;

use std::path::Path;

use glam::{Mat4, Vec3};
use sward::field::surface::surface_field;
use sward::mesh::Mesh;
use sward::scene::Field;
use sward::sim::layout::Blade;

use common::shapes::icosphere;

/// A 2 m × 1 m flat strip (normal +y) whose left half is one pair of triangles and whose
/// right half is 100 × 100 little squares: its triangles differ 10,000 times in area.
fn uneven_strip() -> Mesh {
    let mut positions = vec![
        [0.0, 0.0, 0.0],
        [1.0, 0.0, 0.0],
        [1.0, 0.0, 1.0],
        [0.0, 0.0, 1.0],
    ];
    let mut indices = vec![0, 2, 1, 0, 3, 2];
    let n = 100;
    for j in 0..=n {
        for i in 0..=n {
            positions.push([1.0 + i as f32 / n as f32, 0.0, j as f32 / n as f32]);
        }
    }
    let at = |i: u32, j: u32| 4 + j * (n + 1) + i;
    for j in 0..n {
        for i in 0..n {
            let (a, b, c, d) = (at(i, j), at(i + 1, j), at(i + 1, j + 1), at(i, j + 1));
            indices.extend([a, c, b, a, d, c]);
        }
    }
    let normals = vec![[0.0, 1.0, 0.0]; positions.len()];
    Mesh {
        positions,
        normals,
        indices,
        degenerate: 0,
    }
}

fn grass(density: f32) -> Field {
    Field {
        density,
        ..Field::default()
    }
}

fn v(a: [f32; 4]) -> Vec3 {
    Vec3::new(a[0], a[1], a[2])
}

/// The point of triangle abc nearest p and its barycentric weights (brute force over a
/// fine grid of the triangle would be slower; this is the textbook region test).
fn nearest_on(p: Vec3, a: Vec3, b: Vec3, c: Vec3) -> (Vec3, [f32; 3]) {
    let n = (b - a).cross(c - a);
    let q = p - n * ((p - a).dot(n) / n.length_squared());
    let bary = |q: Vec3| {
        let wa = (c - b).cross(q - b).dot(n) / n.length_squared();
        let wb = (a - c).cross(q - c).dot(n) / n.length_squared();
        [wa, wb, 1.0 - wa - wb]
    };
    let w = bary(q);
    if w.iter().all(|&x| x >= 0.0) {
        return (q, w);
    }
    // Outside: the nearest point of the three edges.
    let seg = |s: Vec3, e: Vec3| {
        let t = ((p - s).dot(e - s) / (e - s).length_squared()).clamp(0.0, 1.0);
        s + (e - s) * t
    };
    let best = [seg(a, b), seg(b, c), seg(c, a)]
        .into_iter()
        .min_by(|x, y| x.distance(p).total_cmp(&y.distance(p)))
        .expect("three edges");
    (best, bary(best))
}

/// For each blade: the distance of its root from the mesh and the angle (degrees) between
/// its up vector and the normal interpolated at the nearest surface point.
fn root_errors(mesh: &Mesh, blades: &[Blade]) -> (f32, f32) {
    let p: Vec<Vec3> = mesh.positions.iter().map(|&x| Vec3::from(x)).collect();
    let nrm: Vec<Vec3> = mesh.normals.iter().map(|&x| Vec3::from(x)).collect();
    let tris: Vec<[usize; 3]> = mesh
        .indices
        .chunks_exact(3)
        .map(|t| [t[0] as usize, t[1] as usize, t[2] as usize])
        .collect();
    let (mut worst_d, mut worst_a) = (0.0f32, 0.0f32);
    for b in blades {
        let root = v(b.v0_dir);
        let up = v(b.up_stiffness);
        let mut best = (f32::INFINITY, Vec3::ZERO);
        for t in &tris {
            let [a, bb, c] = t.map(|i| p[i]);
            // A cheap reject: no point of the triangle is nearer than this bound.
            let centre = (a + bb + c) / 3.0;
            let reach = a
                .distance(centre)
                .max(bb.distance(centre))
                .max(c.distance(centre));
            if root.distance(centre) - reach > best.0 {
                continue;
            }
            let (q, w) = nearest_on(root, a, bb, c);
            let d = q.distance(root);
            if d < best.0 {
                let n = (nrm[t[0]] * w[0] + nrm[t[1]] * w[1] + nrm[t[2]] * w[2]).normalize();
                best = (d, n);
            }
        }
        worst_d = worst_d.max(best.0);
        worst_a = worst_a.max(up.dot(best.1).clamp(-1.0, 1.0).acos().to_degrees());
    }
    (worst_d, worst_a)
}

#[test]
fn a_sphere_mesh_gets_the_density_everywhere_roots_on_it_and_up_along_its_normal() {
    let mesh = icosphere(3);
    let density = 2000.0;
    let (blades, _) = surface_field(&mesh, Mat4::IDENTITY, &grass(density), 64);
    let area: f64 = sward::field::surface::surface_area(&mesh, Mat4::IDENTITY);
    // Eight octants of equal area (up to the mesh's facets): blades per m² in each.
    let mut per = [0usize; 8];
    for b in &blades {
        let r = v(b.v0_dir);
        per[usize::from(r.x > 0.0) + 2 * usize::from(r.y > 0.0) + 4 * usize::from(r.z > 0.0)] += 1;
    }
    let densities: Vec<f64> = per.iter().map(|&n| n as f64 / (area / 8.0)).collect();
    println!(
        "sphere: {} blades on {area:.3} m², per octant {densities:.0?} per m² (asked {density})",
        blades.len()
    );
    for d in &densities {
        assert!(
            (d - f64::from(density)).abs() < 0.1 * f64::from(density),
            "an octant has {d:.0} blades per m², asked {density}"
        );
    }
    let (dist, angle) = root_errors(&mesh, &blades);
    println!("sphere: roots at most {dist:.2e} m from the surface, up at most {angle:.2}° off");
    assert!(dist < 1e-3, "a root is {dist} m from the surface");
    assert!(
        angle < 5.0,
        "an up vector is {angle}° from the interpolated normal"
    );
}

#[test]
fn triangles_of_very_different_sizes_get_the_same_density() {
    let mesh = uneven_strip();
    let density = 3000.0;
    let (blades, _) = surface_field(&mesh, Mat4::IDENTITY, &grass(density), 64);
    let big = blades.iter().filter(|b| b.v0_dir[0] < 1.0).count();
    let small = blades.len() - big;
    println!("uneven strip: {big} blades on the two big triangles, {small} on the 20,000 small ones (1 m² each side)");
    for n in [big, small] {
        assert!(
            (n as f32 - density).abs() < 0.1 * density,
            "{n} blades on 1 m², asked {density}"
        );
    }
    let (dist, angle) = root_errors(&mesh, &blades);
    assert!(dist < 1e-3 && angle < 5.0, "{dist} m, {angle}°");
}

#[test]
fn surface_blades_keep_the_papers_invariants_through_the_update() {
    use sward::scene::{MeshObject, Scene};
    use sward::session::Session;
    // A grassy sphere a metre above the ground, under gravity and wind: blades point every
    // way, so the up vector is nowhere the terrain's.
    let path = common::shapes::write_obj(&icosphere(2), "placement-sphere");
    let mut scene: Scene = common::still_scene();
    scene.physics.gravity_acceleration = 9.81;
    scene.objects = vec![MeshObject {
        mesh: path.display().to_string(),
        translation: (0.0, 2.0, 0.0),
        grass: Some(Field {
            density: 300.0,
            ..Field::default()
        }),
        ..Default::default()
    }];
    let gpu = common::gpu();
    let session = Session::new(scene.clone(), Some(4096), Some(&gpu)).expect("field");
    let surface: Vec<&Blade> = session
        .field
        .blades
        .iter()
        .filter(|b| b.v0_dir[1] > 0.5)
        .collect();
    assert!(surface.len() > 3000, "{} surface blades", surface.len());
    // The rest pose is a fixed point: with no force a step leaves every blade where it is.
    let mut still = scene;
    still.physics.gravity_acceleration = 0.0;
    let rest_session = Session::new(still, Some(4096), Some(&gpu)).expect("field");
    let rest = common::stepped(&gpu, &rest_session, 5, 1.0 / 30.0)
        .buffers
        .read(&gpu)
        .expect("read")
        .0;
    let drift = rest
        .iter()
        .zip(&rest_session.field.blades)
        .map(|(a, b)| v(a.v2_width).distance(v(b.v2_width)))
        .fold(0.0f32, f32::max);
    // Under gravity, 60 steps.
    let after = common::stepped(&gpu, &session, 60, 1.0 / 30.0)
        .buffers
        .read(&gpu)
        .expect("read")
        .0;
    let (mut worst_len, mut lowest, mut hanging) = (0.0f32, f32::INFINITY, 0);
    for b in after.iter().filter(|b| b.v0_dir[1] > 0.5) {
        let (v0, v1, v2, up, h) = (
            v(b.v0_dir),
            v(b.v1_height),
            v(b.v2_width),
            v(b.up_stiffness),
            b.v1_height[3],
        );
        // Eq. 12's length estimate of the quadratic Bézier curve.
        let len = (2.0 * v0.distance(v2) + v0.distance(v1) + v1.distance(v2)) / 3.0;
        worst_len = worst_len.max((len - h).abs() / h);
        let above = (v2 - v0).dot(up) / h;
        lowest = lowest.min(above);
        hanging += usize::from(v2.y < v0.y);
    }
    println!(
        "surface blades: rest-pose drift {drift:.2e} m, length error at most {:.2e} of the \
         height, lowest tip {lowest:.3} heights above its ground plane, {hanging} tips below \
         their roots",
        worst_len
    );
    assert!(drift < 1e-5, "the rest pose moved by {drift} m");
    assert!(
        worst_len < 1e-3,
        "a curve's length is off by {worst_len} of its height"
    );
    assert!(
        lowest >= -1e-4,
        "a tip is below its blade's ground plane ({lowest})"
    );
    assert!(
        hanging > 500,
        "gravity must make blades under the sphere hang ({hanging})"
    );
}

/// Whether p is inside the closed mesh: a ray along a fixed, irrational direction crosses
/// its triangles an odd number of times (Möller–Trumbore).
fn inside(mesh: &Mesh, p: Vec3) -> bool {
    let dir = Vec3::new(0.5773, 0.5774, 0.5775).normalize();
    let pos: Vec<Vec3> = mesh.positions.iter().map(|&x| Vec3::from(x)).collect();
    let mut crossings = 0;
    for t in mesh.indices.chunks_exact(3) {
        let [a, b, c] = [t[0], t[1], t[2]].map(|i| pos[i as usize]);
        let (e1, e2) = (b - a, c - a);
        let h = dir.cross(e2);
        let det = e1.dot(h);
        if det.abs() < 1e-12 {
            continue;
        }
        let s = p - a;
        let u = s.dot(h) / det;
        let q = s.cross(e1);
        let w = dir.dot(q) / det;
        if u < 0.0 || w < 0.0 || u + w > 1.0 {
            continue;
        }
        if e2.dot(q) / det > 0.0 {
            crossings += 1;
        }
    }
    crossings % 2 == 1
}

#[test]
fn every_packed_sphere_lies_inside_the_mesh_and_the_cover_is_reported() {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("assets/models/bunny.obj");
    let bunny = sward::mesh::load(&path).expect("bunny");
    let ball = icosphere(3);
    for (name, mesh, count) in [("bunny", &bunny, 400usize), ("sphere", &ball, 50)] {
        let p = sward::mesh::pack::pack(mesh, count, 64);
        let outside = p
            .spheres
            .iter()
            .filter(|s| !inside(mesh, Vec3::new(s[0], s[1], s[2])))
            .count();
        println!(
            "{name}: {} spheres cover {:.1} % of the inside voxels; {outside} centres outside",
            p.spheres.len(),
            p.coverage * 100.0
        );
        assert_eq!(outside, 0, "{name}: packed sphere centres outside the mesh");
        assert!(
            p.coverage > 0.5 && p.coverage <= 1.0,
            "{name}: cover {}",
            p.coverage
        );
    }
}
