//! The flat collision broad phase (`broad_phase` in `cull.wgsl`): each stepped patch lists
//! the spheres within one radius of its box, in index order, as its twin
//! `reference::patch_spheres` does, whatever the list's length: a list longer than the
//! patch's own slots goes to the shared pool, where before it made the patch test every
//! sphere. The colliders' tree only skips the patches that no sphere is near. With the
//! long lists the update still steps the blades as the CPU twin that tests every sphere,
//! but for the rare tip that a push carries beyond the list's reach.

mod common;

use glam::Vec3;
use sward::commands::simulate_cpu;
use sward::scene::Scene;
use sward::session::Session;
use sward::sim::layout::PATCH_SPHERE_STRIDE;
use sward::sim::reference::{patch_spheres, patch_update};

/// A packed bunny of 1,000 spheres on still grass, plus a ball: the patches under the bunny
/// are near far more spheres than their slots hold. The flat lists, not the hierarchy.
fn scene() -> Scene {
    let mut scene = common::packed_bunny_scene(0.35, 1000);
    scene.physics.collision_hierarchy = false;
    scene
}

const STEPS: u32 = 12;

#[test]
fn long_lists_go_to_the_pool_and_match_the_twin() {
    let gpu = common::gpu();
    let session = Session::new(scene(), Some(16384), Some(&gpu)).expect("field");
    let r = common::stepped(&gpu, &session, STEPS, 1.0 / 30.0);
    let cp = *r.last_cull_params();
    assert!(cp.collide[2] > 0, "the flat broad phase has the tree");
    let spheres = r.frame_spheres();
    assert!(spheres.len() > 1000, "{} spheres", spheres.len());
    let lists = r
        .cull
        .read_patch_spheres(&gpu, &r.buffers)
        .expect("patch spheres");
    let counters = r.cull.read_counters(&gpu).expect("counters");
    let (mut stepped, mut pooled, mut pool_entries, mut empty, mut longest) = (0, 0, 0, 0, 0);
    let mut pairs = 0u32;
    for (p, patch) in session.field.patches.iter().enumerate() {
        if patch_update(p as u32, patch, &cp).is_none() {
            continue;
        }
        stepped += 1;
        let cpu = patch_spheres(patch, &cp, &spheres);
        assert_eq!(lists[p].as_ref(), Some(&cpu), "patch {p}: broad-phase list");
        pairs += cpu.len() as u32;
        longest = longest.max(cpu.len());
        if cpu.is_empty() {
            empty += 1;
        }
        if cpu.len() >= PATCH_SPHERE_STRIDE as usize {
            pooled += 1;
            pool_entries += cpu.len() as u32;
        }
    }
    println!(
        "{stepped} stepped patches: {empty} near no sphere, {pooled} lists in the pool \
         ({pool_entries} entries), longest {longest}"
    );
    assert!(
        pooled > 0,
        "no list outgrew the patch's slots: the pool is not tested"
    );
    assert!(
        empty > 0,
        "every patch is near a sphere: the tree's skip is not tested"
    );
    assert_eq!(counters.pool_used, pool_entries, "pool entries taken");
    assert_eq!(counters.patch_sphere_pairs, pairs, "patch-sphere pairs");
    // Every listed sphere, and no other, is marked as considered.
    let mut used = vec![false; spheres.len()];
    for (p, patch) in session.field.patches.iter().enumerate() {
        if patch_update(p as u32, patch, &cp).is_some() {
            for s in patch_spheres(patch, &cp, &spheres) {
                used[s as usize] = true;
            }
        }
    }
    let considered = used.iter().filter(|&&u| u).count() as u32;
    assert_eq!(counters.spheres_considered(), considered);
}

#[test]
fn blades_under_a_packing_step_as_the_twin_that_tests_every_sphere() {
    let gpu = common::gpu();
    let session = Session::new(scene(), Some(16384), Some(&gpu)).expect("field");
    let r = common::stepped(&gpu, &session, STEPS, 1.0 / 30.0);
    let (blades, states) = r.buffers.read(&gpu).expect("read-back");
    let cpu = simulate_cpu(&session, STEPS, 1.0 / 30.0);
    let tip =
        |b: &sward::sim::layout::Blade| Vec3::new(b.v2_width[0], b.v2_width[1], b.v2_width[2]);
    let err = cpu
        .blades
        .iter()
        .zip(&blades)
        .map(|(c, g)| tip(c).distance(tip(g)))
        .fold(0.0f32, f32::max);
    let crushed = states.iter().filter(|s| s.rest_eta[3] > 0.0).count();
    let apart = |d: f32| {
        cpu.blades
            .iter()
            .zip(&blades)
            .filter(|(c, g)| tip(c).distance(tip(g)) > d)
            .count()
    };
    println!(
        "{crushed} blades crushed; max |gpu - cpu| tip {err:.2e} m; apart by > 1e-6: {}, > 1e-5: {}, > 1e-4: {}",
        apart(1e-6),
        apart(1e-5),
        apart(1e-4)
    );
    assert!(
        crushed > 100,
        "the packing presses the grass ({crushed} blades)"
    );
    // The lists hold the spheres within two radii of the patch box; a push can carry a tip
    // a little beyond that, into a sphere off the list that the twin (every sphere) meets.
    // Measured: 3 of 16,384 tips more than 1e-6 m apart, one by 1.4e-4 m; with every sphere
    // tested (the pool emptied) the largest gap is 1.5e-6 m.
    assert!(err < 1e-3, "GPU and CPU differ by {err} m");
    assert!(
        apart(1e-5) * 1000 <= blades.len(),
        "{} tips more than 1e-5 m from the twin's",
        apart(1e-5)
    );
}
