//! The terrain's WGSL height function (`shaders/terrain_height.wgsl`, run by the probe
//! kernel) against its CPU twin, `HeightField::height` / `normal`, on a few hundred points
//! inside the square, around it and far away (10 km): heights within 1e-3 m per metre of
//! amplitude (at least 1e-3 m), unit normals within 5e-3 (0.3°) — 2e-2 for 12 octaves of
//! 200 m, whose finest octave (10 cm) is where f32 lattice coordinates 5 km out limit the
//! slope. Analytic noise (unbounded and
//! bounded), a flat plane and a sampled grid (the `Png` path) are all checked.

mod common;

use glam::{Vec2, Vec3};
use sward::field::HeightField;
use sward::render::terrain::probe_heights;
use sward::scene::types::{HeightSource, Terrain};

fn points() -> Vec<Vec2> {
    let mut p = Vec::new();
    for k in 0..300u32 {
        // A spiral out to ~60 m, then far points.
        let t = k as f32 * 0.37;
        let r = k as f32 * 0.2;
        p.push(Vec2::new(r * t.cos(), r * t.sin()));
    }
    for k in 0..60u32 {
        let a = k as f32 * 0.71;
        let r = 500.0 + k as f32 * 160.0;
        p.push(Vec2::new(r * a.cos() + 0.37, r * a.sin() - 0.19));
    }
    p.push(Vec2::new(10000.3, -10000.7));
    p.push(Vec2::new(-9999.9, 9999.4));
    p
}

fn compare(
    gpu: &sward::gpu::Gpu,
    terrain: &HeightField,
    amplitude: f32,
    normal_tol: f32,
    what: &str,
) {
    let pts = points();
    let got = probe_heights(gpu, terrain, &pts).expect("probe");
    assert_eq!(got.len(), pts.len());
    let tol = 1e-3 * amplitude.max(1.0);
    for (p, g) in pts.iter().zip(&got) {
        let h = terrain.height(p.x, p.y);
        assert!(
            (g.x - h).abs() <= tol,
            "{what}: height at {p}: gpu {} cpu {h}",
            g.x
        );
        let n = terrain.normal(p.x, p.y);
        let gn = Vec3::new(-g.y, 1.0, -g.z).normalize();
        assert!(
            (gn - n).length() <= normal_tol,
            "{what}: normal at {p}: gpu {gn} cpu {n}"
        );
    }
}

fn noise(unbounded: bool) -> Terrain {
    Terrain {
        size: 32.0,
        resolution: 129,
        height: HeightSource::Noise {
            seed: 7,
            amplitude: 2.5,
            wavelength: 28.0,
            octaves: 4,
        },
        density_map: None,
        unbounded,
    }
}

#[test]
fn wgsl_heights_match_the_cpu_terrain() {
    let gpu = common::gpu();
    let unbounded = HeightField::from_scene(&noise(true)).unwrap();
    compare(&gpu, &unbounded, 2.5, 5e-3, "unbounded noise");
    let bounded = HeightField::from_scene(&noise(false)).unwrap();
    compare(&gpu, &bounded, 2.5, 5e-3, "bounded noise");
    // Many octaves, short wavelength, tall hills: the fine octaves stress f32.
    let rough = HeightField::from_scene(&Terrain {
        height: HeightSource::Noise {
            seed: 123_456_789_012,
            amplitude: 40.0,
            wavelength: 200.0,
            octaves: 12,
        },
        ..noise(true)
    })
    .unwrap();
    compare(&gpu, &rough, 40.0, 2e-2, "rough noise");
    let flat = HeightField::from_scene(&Terrain {
        height: HeightSource::Flat,
        ..noise(true)
    })
    .unwrap();
    compare(&gpu, &flat, 1.0, 5e-3, "flat");
    // A sampled grid (what a Png becomes): bilinear inside, edge heights outside.
    let mut grid = HeightField::flat(20.0, 21);
    for j in 0..21u32 {
        for i in 0..21u32 {
            let v = grid.vertex(i, j);
            grid.heights[(j * 21 + i) as usize] = 2.0 * (v.x * 0.4).sin() * (v.z * 0.3).cos();
        }
    }
    compare(&gpu, &grid, 2.0, 5e-3, "grid");
}
