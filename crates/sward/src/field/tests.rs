//! Tests of the whole generation: determinism, patch sizes and shapes, blades on the
//! terrain in their rest pose, tuft spacing, and density maps.

use glam::{Vec2, Vec3};

use super::placement::{place_roots, TUFT_SPACING};
use super::*;
use crate::field::blade::curve_length;
use crate::scene::types::{HeightSource, Terrain};

/// Steep noise hills (2 m over 8 m on a 12 m square), shared with the cull twin's tests.
pub(crate) fn hills() -> HeightField {
    HeightField::from_scene(&Terrain {
        size: 12.0,
        resolution: 65,
        height: HeightSource::Noise {
            seed: 3,
            amplitude: 2.0,
            wavelength: 8.0,
            octaves: 4,
        },
        density_map: None,
        unbounded: true,
    })
    .unwrap()
}

fn small_field() -> Field {
    Field {
        density: 60.0,
        patch_size: 256,
        ..Field::default()
    }
}

fn v3(a: [f32; 4]) -> Vec3 {
    Vec3::new(a[0], a[1], a[2])
}

#[test]
fn same_seed_same_field_other_seed_other_field() {
    let terrain = hills();
    let a = generate(&small_field(), &terrain, None);
    let b = generate(&small_field(), &terrain, None);
    assert!(!a.blades.is_empty());
    // Bit-identical, not just equal as floats.
    assert_eq!(
        bytemuck::cast_slice::<_, u8>(&a.blades),
        bytemuck::cast_slice::<_, u8>(&b.blades)
    );
    assert_eq!(
        bytemuck::cast_slice::<_, u8>(&a.states),
        bytemuck::cast_slice::<_, u8>(&b.states)
    );
    assert_eq!(
        bytemuck::cast_slice::<_, u8>(&a.patches),
        bytemuck::cast_slice::<_, u8>(&b.patches)
    );
    let c = generate(
        &Field {
            seed: 2,
            ..small_field()
        },
        &terrain,
        None,
    );
    assert_ne!(a.blades, c.blades);
}

#[test]
fn count_is_density_times_area_rounded_up_to_whole_patches() {
    let terrain = hills();
    let field = small_field();
    let g = generate(&field, &terrain, None);
    let wanted = (60.0f64 * 144.0).ceil() as usize;
    assert_eq!(g.patch_size, 256);
    assert_eq!(g.blades.len(), wanted.div_ceil(256) * 256);
    assert_eq!(g.blades.len(), g.patches.len() * 256);
    assert_eq!(g.states.len(), g.blades.len());
    // Non-multiple patch sizes are rounded up to whole workgroups.
    let g = generate(
        &Field {
            patch_size: 100,
            ..field
        },
        &terrain,
        None,
    );
    assert_eq!(g.patch_size, 128);
    assert_eq!(g.blades.len() % 128, 0);
}

#[test]
fn blades_stand_on_the_terrain_along_its_normal_in_the_rest_pose() {
    let terrain = hills();
    let field = Field {
        bend: crate::scene::types::Range::new(0.0, 60.0),
        ..small_field()
    };
    let g = generate(&field, &terrain, None);
    let half = 0.5 * terrain.size;
    for (blade, state) in g.blades.iter().zip(&g.states) {
        let v0 = v3(blade.v0_dir);
        let v1 = v3(blade.v1_height);
        let v2 = v3(blade.v2_width);
        let up = v3(blade.up_stiffness);
        let h = blade.v1_height[3];
        assert!(v0.x.abs() <= half && v0.z.abs() <= half);
        assert!((v0.y - terrain.height(v0.x, v0.z)).abs() < 1e-4);
        assert!((up.length() - 1.0).abs() < 1e-5);
        assert!((up - terrain.normal(v0.x, v0.z)).length() < 1e-6);
        let angle = blade.v0_dir[3];
        assert!((0.0..std::f32::consts::TAU).contains(&angle));
        assert!((field.height.min..=field.height.max).contains(&h));
        assert!((field.width.min..=field.width.max).contains(&blade.v2_width[3]));
        assert!((field.stiffness.min..=field.stiffness.max).contains(&blade.up_stiffness[3]));
        let length = curve_length(v0, v1, v2);
        assert!((length - h).abs() <= 1e-3 * h, "length {length} height {h}");
        // The tip leans at most the bend range away from up, and stays above ground.
        let lean = (v2 - v0)
            .normalize()
            .dot(up)
            .clamp(-1.0, 1.0)
            .acos()
            .to_degrees();
        assert!(lean <= 60.0 + 0.5, "lean {lean}");
        assert_eq!(state.rest_eta, [v2.x, v2.y, v2.z, 0.0]);
    }
}

#[test]
fn patch_boxes_hold_every_pose() {
    let g = generate(&small_field(), &hills(), None);
    for (patch, b) in g.blades.chunks(g.patch_size as usize).zip(&g.patches) {
        assert_eq!(b.min[3], 0.0);
        // max.w: the smallest up.y of the patch's blades.
        let up_y = patch
            .iter()
            .map(|b| b.up_stiffness[1])
            .fold(1.0f32, f32::min);
        assert_eq!(b.max[3], up_y);
        assert!(up_y > 0.0 && up_y <= 1.0);
        for blade in patch {
            let v0 = v3(blade.v0_dir);
            let h = blade.v1_height[3];
            // Any point within h of the root (every reachable tip) is inside the box.
            for k in 0..3 {
                assert!(v0[k] - h >= b.min[k] - 1e-6 && v0[k] + h <= b.max[k] + 1e-6);
            }
        }
    }
}

#[test]
fn patches_are_compact() {
    let terrain = HeightField::flat(20.0, 2);
    let g = generate(
        &Field {
            density: 40.0,
            ..small_field()
        },
        &terrain,
        None,
    );
    let n = g.patches.len();
    assert!(n >= 8, "{n} patches");
    let grow = 2.0 * Field::default().height.max;
    // Box area without the growth by the blade height, over the ideal share of the square.
    let mean_area = g
        .patches
        .iter()
        .map(|b| ((b.max[0] - b.min[0] - grow).max(0.0)) * ((b.max[2] - b.min[2] - grow).max(0.0)))
        .sum::<f32>()
        / n as f32;
    let ideal = 400.0 / n as f32;
    assert!(mean_area < 3.0 * ideal, "mean {mean_area} ideal {ideal}");
    // The roots of a patch hardly overlap other patches' boxes: the boxes tile the square.
    let total: f32 = g
        .patches
        .iter()
        .map(|b| (b.max[0] - b.min[0] - grow) * (b.max[2] - b.min[2] - grow))
        .sum();
    assert!(total < 1.3 * 400.0, "boxes cover {total} m²");
}

#[test]
fn morton_order_keeps_neighbours_close() {
    let g = generate(&small_field(), &hills(), None);
    for (patch, b) in g.blades.chunks(g.patch_size as usize).zip(&g.patches) {
        let diagonal = Vec2::new(b.max[0] - b.min[0], b.max[2] - b.min[2]).length();
        let steps: f32 = patch
            .windows(2)
            .map(|w| {
                Vec2::new(
                    w[0].v0_dir[0] - w[1].v0_dir[0],
                    w[0].v0_dir[2] - w[1].v0_dir[2],
                )
                .length()
            })
            .sum();
        let mean = steps / (patch.len() - 1) as f32;
        assert!(
            mean < 0.1 * diagonal,
            "mean step {mean}, diagonal {diagonal}"
        );
    }
}

#[test]
fn tuft_centres_respect_the_minimum_distance() {
    let field = Field {
        tuft_fraction: 1.0,
        tuft_radius: 0.2,
        ..small_field()
    };
    let placement = place_roots(12.0, 20_000, &field, None);
    assert_eq!(placement.roots.len(), 20_000);
    let centres = &placement.tuft_centres;
    assert!(centres.len() > 100);
    let min_distance = TUFT_SPACING * field.tuft_radius;
    for (i, a) in centres.iter().enumerate() {
        for b in &centres[i + 1..] {
            assert!(a.distance(*b) >= min_distance * (1.0 - 1e-5));
        }
    }
    // Every tuft blade lies within the radius of some centre (centres are at least
    // 2.5 radii apart, so the nearest centre is the one it belongs to).
    for p in &placement.roots {
        let near = centres
            .iter()
            .map(|c| c.distance(*p))
            .fold(f32::INFINITY, f32::min);
        assert!(near <= field.tuft_radius * (1.0 + 1e-5));
    }
}

#[test]
fn tufts_and_singles_mix() {
    let field = Field {
        tuft_fraction: 0.5,
        ..small_field()
    };
    let placement = place_roots(12.0, 10_000, &field, None);
    assert_eq!(placement.roots.len(), 10_000);
    let tuft_blades = placement
        .roots
        .iter()
        .filter(|p| {
            placement
                .tuft_centres
                .iter()
                .any(|c| c.distance(**p) <= field.tuft_radius)
        })
        .count();
    // Half are tuft blades; a few singles land inside tufts by chance.
    assert!((4_900..6_500).contains(&tuft_blades), "{tuft_blades}");
}

#[test]
fn black_density_map_gives_an_empty_field() {
    let terrain = hills();
    let black = DensityMap::from_values(terrain.size, 4, 4, vec![0.0; 16]).unwrap();
    let g = generate(&small_field(), &terrain, Some(&black));
    assert!(g.blades.is_empty() && g.states.is_empty() && g.patches.is_empty());
    assert_eq!(g.patch_size, 256);
}

#[test]
fn nearly_black_density_map_gives_up_with_whole_patches() {
    // A small white square in a large black map: most candidates are rejected, the attempt
    // cap ends sampling, and the field comes back short but in whole patches.
    let terrain = hills();
    let mut values = vec![0.0; 100 * 100];
    for j in 48..52 {
        for i in 48..52 {
            values[j * 100 + i] = 1.0;
        }
    }
    let map = DensityMap::from_values(terrain.size, 100, 100, values).unwrap();
    let g = generate(&small_field(), &terrain, Some(&map));
    let full = generate(&small_field(), &terrain, None).blades.len();
    assert_eq!(g.blades.len() % 256, 0);
    assert_eq!(g.blades.len(), g.patches.len() * 256);
    assert!(
        !g.blades.is_empty() && g.blades.len() < full,
        "{} of {full}",
        g.blades.len()
    );
    // Every blade grows where the map is not black.
    assert!(g
        .blades
        .iter()
        .all(|b| map.sample(b.v0_dir[0], b.v0_dir[2]) > 0.0));
}

#[test]
fn density_map_shapes_the_field() {
    // Left half black, right half white: the count is kept, all blades on the right.
    let terrain = hills();
    let map = DensityMap::from_values(terrain.size, 2, 1, vec![0.0, 1.0]).unwrap();
    let g = generate(&small_field(), &terrain, Some(&map));
    let plain = generate(&small_field(), &terrain, None);
    assert_eq!(g.blades.len(), plain.blades.len());
    let left = g.blades.iter().filter(|b| b.v0_dir[0] < 0.0).count();
    let right = g.blades.len() - left;
    assert!(right > 3 * left, "left {left} right {right}");
}

#[test]
fn zero_density_gives_zero_blades() {
    let g = generate(
        &Field {
            density: 0.0,
            ..small_field()
        },
        &hills(),
        None,
    );
    assert!(g.blades.is_empty() && g.patches.is_empty());
}

#[test]
fn flat_field_sizes() {
    let field = Field::default();
    let (terrain, g) = flat_field(10_000, &field);
    assert_eq!(g.patch_size, 1024);
    assert_eq!(g.blades.len(), 10_240);
    assert!((g.blades.len() as f32 / terrain.size.powi(2) - field.density).abs() < 1e-2);
    assert!(g
        .blades
        .iter()
        .all(|b| b.v0_dir[1] == 0.0 && b.up_stiffness[..3] == [0.0, 1.0, 0.0]));

    let (_, small) = flat_field(100, &field);
    assert_eq!(small.patch_size, 128);
    assert_eq!(small.blades.len(), 128);
    assert_eq!(small.patches.len(), 1);

    let (_, exact) = flat_field(64, &field);
    assert_eq!((exact.patch_size, exact.blades.len()), (64, 64));

    let (_, none) = flat_field(0, &field);
    assert!(none.blades.is_empty());
}
