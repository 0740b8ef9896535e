//! The far grass's texture (`shaders/grass_texture.wgsl`, which the far ground and the
//! billboards' roots are shaded with) against its CPU twin (`render::far_texture`), at
//! points spread over the prairie's 4 km (negative coordinates, lattice corners, far from
//! the origin) and footprints from a millimetre to metres per pixel.

mod common;

use glam::{Vec2, Vec3};
use sward::render::far_texture::{grass_octaves, grass_texture, probe_grass_texture};

/// Largest difference allowed, GPU against CPU: both evaluate the same f32 operations; the
/// smoothstep's cubic and the lattice's fraction differ by rounding only (measured below
/// 1.8e-7).
const TOLERANCE: f32 = 1e-5;

#[test]
fn the_far_grass_texture_matches_its_cpu_twin() {
    let gpu = common::gpu();
    let mut points = Vec::new();
    for k in 0..2000u32 {
        // A low-discrepancy spread over ±2 km, then a few points on lattice corners.
        let x = (k as f32 * 0.618_034).fract() * 4000.0 - 2000.0;
        let z = (k as f32 * 0.754_878).fract() * 4000.0 - 2000.0;
        let footprint = 0.001 * 1.006f32.powi(k as i32 % 1500);
        points.push(Vec3::new(x, z, footprint));
    }
    for corner in [0.0, 1.0, -1.0, 100.0 / 0.35, -3.0 / 7.0] {
        points.push(Vec3::new(corner, -corner, 0.01));
    }
    let gpu_values = probe_grass_texture(&gpu, &points).expect("probe");
    let mut worst = 0.0f32;
    let mut faded = 0;
    for (p, (octaves, texture)) in points.iter().zip(&gpu_values) {
        let cpu_octaves = grass_octaves(Vec2::new(p.x, p.y));
        let cpu_texture = grass_texture(cpu_octaves, p.z);
        worst = worst
            .max((*octaves - cpu_octaves).abs().max_element())
            .max((texture - cpu_texture).abs());
        if cpu_texture == 1.0 {
            faded += 1;
        }
    }
    println!(
        "far texture twin: worst difference {worst:.2e} over {} points ({faded} fully faded)",
        points.len()
    );
    assert!(worst <= TOLERANCE, "{worst}");
    // The footprints cover both ends: some points keep texture, some have lost it all.
    assert!(faded > 100 && faded < points.len() - 100, "{faded}");
}
