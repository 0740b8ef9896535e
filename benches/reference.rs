//! Criterion benches of the CPU twins: one blade-update step and one cull pass over a flat
//! field of 16,384 blades. These time the reference code, not the GPU (GPU passes are
//! timed with timestamp queries: `sward render --timings`).

use criterion::{criterion_group, criterion_main, Criterion};
use std::hint::black_box;
use sward::field::flat_field;
use sward::render::camera::CameraView;
use sward::scene::Scene;
use sward::sim::params::{cull_params, sim_params, CullInputs};
use sward::sim::reference::{cull_blade, update_all, WindGrid};

fn bench(c: &mut Criterion) {
    let scene = Scene::default();
    let (_, field) = flat_field(16_384, &scene.field);
    let spheres = [[0.0, 0.3, 0.0, 0.5]];
    let params = sim_params(
        &scene.physics,
        &scene.wind,
        scene.terrain.size,
        1.0 / 60.0,
        1.0,
        field.blades.len() as u32,
        1,
    );
    c.bench_function("cpu update 16k blades", |b| {
        let mut blades = field.blades.clone();
        let mut states = field.states.clone();
        let zero = [[0.0f32; 2]];
        let grid = WindGrid { velocity: &zero };
        b.iter(|| {
            update_all(
                black_box(&mut blades),
                &mut states,
                &params,
                &spheres,
                &grid,
            )
        });
    });
    let camera = CameraView::from_scene(&scene.camera);
    let lod = sward::render::mesh::lod_meshes(scene.field.segments);
    let cp = cull_params(
        &scene.culling,
        &CullInputs {
            view_proj: camera.view_proj(16.0 / 9.0),
            camera: camera.eye,
            fov_y: camera.fov_y,
            near: camera.near,
            far: camera.far,
            viewport_height: 720,
            blade_count: field.blades.len() as u32,
            patch_size: field.patch_size,
            patch_count: field.patches.len() as u32,
            lod_segments: lod.segments,
            lod_index_count: lod.index_count,
            lod_first_index: lod.first_index,
            frame: 0,
            hiz: [0; 4],
            sphere_count: 0,
            collisions: false,
        },
    );
    c.bench_function("cpu cull 16k blades", |b| {
        b.iter(|| {
            field
                .blades
                .iter()
                .enumerate()
                .filter(|(i, blade)| {
                    let patch = &field.patches[*i / field.patch_size as usize];
                    matches!(
                        cull_blade(*i as u32, blade, patch, &cp, None),
                        sward::sim::reference::CullOutcome::Drawn(_)
                    )
                })
                .count()
        });
    });
}

criterion_group!(benches, bench);
criterion_main!(benches);
