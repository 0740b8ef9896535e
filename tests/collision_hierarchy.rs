//! Qiu's bounding-volume hierarchy of the colliders (issue 14, point 3b;
//! `physics.collision_hierarchy`), walked per blade in the update:
//! - the GPU walk matches the CPU twin's, at full precision and at a coarse one;
//! - at full precision it presses the grass as the flat lists do (the same spheres, in
//!   another order);
//! - coarser precision (a short `hierarchy_precision_distance`) presses at least as many
//!   blades, with the bounding spheres standing in for the colliders, and never fewer.

mod common;

use glam::Vec3;
use sward::commands::simulate_cpu;
use sward::scene::{MeshCollider, Scene, SpherePacking};
use sward::session::Session;
use sward::sim::layout::{Blade, BladeState};

fn scene(hierarchy: bool, precision: f32) -> Scene {
    let mut scene = common::packed_bunny_scene(0.2, 300);
    scene.physics.collision_hierarchy = hierarchy;
    scene.physics.hierarchy_precision_distance = precision;
    scene
}

fn tip(b: &Blade) -> Vec3 {
    Vec3::new(b.v2_width[0], b.v2_width[1], b.v2_width[2])
}

const STEPS: u32 = 30;

fn run(scene: Scene) -> (Session, Vec<Blade>, Vec<BladeState>) {
    let gpu = common::gpu();
    let session = Session::new(scene, Some(16384), Some(&gpu)).expect("field");
    let r = common::stepped(&gpu, &session, STEPS, 1.0 / 30.0);
    let (blades, states) = r.buffers.read(&gpu).expect("read-back");
    (session, blades, states)
}

fn crushed(states: &[BladeState]) -> usize {
    states.iter().filter(|s| s.rest_eta[3] > 0.0).count()
}

#[test]
fn the_gpu_walk_matches_its_twin_at_every_precision() {
    for precision in [1000.0, 0.5] {
        let (session, gpu_blades, _) = run(scene(true, precision));
        let cpu = simulate_cpu(&session, STEPS, 1.0 / 30.0).blades;
        let err = cpu
            .iter()
            .zip(&gpu_blades)
            .map(|(c, g)| tip(c).distance(tip(g)))
            .fold(0.0f32, f32::max);
        println!("hierarchy walk, precision distance {precision} m: max |gpu - cpu| {err:.2e} m");
        assert!(err < 1e-4, "GPU and CPU differ by {err} m");
    }
}

#[test]
fn the_exact_walk_presses_as_the_lists_do_and_a_coarse_one_no_less() {
    let (_, flat, flat_states) = run(scene(false, 10.0));
    let (_, exact, exact_states) = run(scene(true, 1000.0));
    let (_, coarse, coarse_states) = run(scene(true, 0.5));
    // Inside the packing many spheres overlap: a blade pushed out of one into the next ends
    // where the order of the pushes takes it, so a few blades differ much; the rest agree.
    let apart = flat
        .iter()
        .zip(&exact)
        .filter(|(a, b)| tip(a).distance(tip(b)) > 0.01)
        .count();
    let diff = apart as f32 / flat.len() as f32;
    let (f, e, c) = (
        crushed(&flat_states),
        crushed(&exact_states),
        crushed(&coarse_states),
    );
    let moved = |b: &[Blade]| {
        b.iter()
            .zip(&coarse)
            .map(|(x, y)| tip(x).distance(tip(y)))
            .fold(0.0f32, f32::max)
    };
    println!(
        "blades crushed: lists {f}, exact walk {e}, coarse walk {c}; tips more than 1 cm \
         apart, lists vs exact walk: {apart} ({:.3} %); largest exact vs coarse {:.3} m",
        diff * 100.0,
        moved(&exact)
    );
    assert!(f > 100, "the colliders must press the grass ({f})");
    // The same spheres push the same blades; only the order of the pushes differs.
    assert!(
        (e as f32 - f as f32).abs() <= 0.02 * f as f32,
        "exact walk {e} vs lists {f}"
    );
    assert!(
        diff < 0.01,
        "{apart} blades differ between the exact walk and the lists"
    );
    assert!(c >= e, "the coarse walk pressed fewer blades ({c} < {e})");
    assert!(moved(&exact) > 1e-3, "a coarse walk must change something");
}

#[test]
fn a_bvh_collider_switches_the_walk_on_for_the_scene() {
    let mut with_bvh = scene(false, 1000.0);
    let packing = match &with_bvh.objects[0].collider {
        MeshCollider::Spheres(p) => p.clone(),
        other => panic!("{other:?}"),
    };
    with_bvh.objects[0].collider = MeshCollider::Bvh(packing);
    assert!(with_bvh.collision_hierarchy());
    assert!(!scene(false, 1000.0).collision_hierarchy());
    let (_, a, _) = run(with_bvh);
    let (_, b, _) = run(scene(true, 1000.0));
    assert_eq!(
        a, b,
        "collider: Bvh must walk the hierarchy as the physics switch does"
    );
    // The scene file spells it as the issue does.
    let text = r#"(objects: [(mesh: "bunny.obj", collider: Bvh((count: 50)))])"#;
    let parsed: Scene = ron::from_str(text).expect("parses");
    assert!(matches!(
        parsed.objects[0].collider,
        MeshCollider::Bvh(SpherePacking { count: 50, .. })
    ));
}

/// The broad phase feeds the hierarchy: each stepped patch's list is its cut of the tree
/// (the nodes a walk from the root meets near the patch, down to the level of the patch's
/// coarsest blade), the same on the GPU as in the twin; at full precision it lists the flat
/// lists' spheres, at a coarse one inner nodes.
#[test]
fn the_broad_phase_lists_each_patch_cut_of_the_tree_as_its_twin() {
    use sward::sim::{bvh, reference::patch_nodes, reference::patch_spheres};
    let mut entries = Vec::new();
    for precision in [1000.0, 0.5] {
        let gpu = common::gpu();
        let session = Session::new(scene(true, precision), Some(16384), Some(&gpu)).expect("field");
        let r = common::stepped(&gpu, &session, 3, 1.0 / 30.0);
        let cp = *r.last_cull_params();
        let spheres = r.frame_spheres();
        let nodes = bvh::build(&spheres);
        assert_eq!(
            cp.collide[2] as usize,
            nodes.len(),
            "the cull pass has the tree"
        );
        let lists = r.cull.read_patch_spheres(&gpu, &r.buffers).expect("lists");
        let (mut listed, mut flat, mut inner, mut compared) = (0usize, 0usize, 0usize, 0usize);
        for (p, patch) in session.field.patches.iter().enumerate() {
            let cpu = patch_nodes(patch, &cp, &nodes, false);
            assert_eq!(lists[p], cpu, "patch {p} at precision {precision}");
            // Patches whose lists overflowed (every sphere, or the walk from the root) are
            // left out of the counts.
            let Some(cpu) = cpu else {
                continue;
            };
            let f = patch_spheres(patch, &cp, &spheres);
            compared += 1;
            listed += cpu.len();
            inner += cpu
                .iter()
                .filter(|&&k| !bvh::is_leaf(&nodes[k as usize]))
                .count();
            flat += f.len();
        }
        println!(
            "precision {precision} m: {compared} patches, {listed} list entries ({inner} inner \
             nodes) against {flat} on the flat lists"
        );
        assert!(listed > 0, "the colliders touch some patch");
        entries.push((listed, inner, flat));
    }
    let (exact, coarse) = (entries[0], entries[1]);
    assert_eq!(exact.1, 0, "at full precision only colliders are listed");
    // The same spheres (a node's test is a hair looser than its sphere's, in f32).
    assert!(
        exact.0.abs_diff(exact.2) * 100 <= exact.2,
        "at full precision the lists hold the flat lists' spheres ({} vs {})",
        exact.0,
        exact.2
    );
    assert!(coarse.1 > 0, "a coarse cut lists inner nodes");
}
