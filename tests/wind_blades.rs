//! Grass reads the fluid wind: blades downstream of a single AGC arrow bend along it, blades
//! far from it stay near their rest pose. Both are measured against a run without the guide
//! (same gravity, no other wind): "near rest" means the mean tip shift of the far blades is
//! under a tenth of the downstream blades' mean shift. An incompressible flow always moves
//! some air everywhere (the jet draws air in from the sides), so far blades are not frozen.

mod common;

use glam::Vec2;
use sward::scene::{Guide, GuidePoint, Scene, WindSource};
use sward::session::Session;
use sward::sim::layout::Blade;

fn run(scene: Scene, steps: u32) -> (Vec<Blade>, Vec<Blade>) {
    let gpu = common::gpu();
    let session = Session::new(scene, Some(8192), Some(&gpu)).expect("field");
    let r = common::stepped(&gpu, &session, steps, 1.0 / 30.0);
    (
        session.field.blades.clone(),
        r.buffers.read(&gpu).expect("read-back").0,
    )
}

fn tip(b: &Blade) -> Vec2 {
    Vec2::new(b.v2_width[0], b.v2_width[2])
}

#[test]
fn blades_downstream_of_an_arrow_bend_along_it() {
    let mut scene = common::still_scene();
    scene.physics.gravity_acceleration = 9.81;
    scene.wind.source = WindSource::Fluid;
    scene.wind.fluid.resolution = 64;
    let mut control = scene.clone();
    // The flat field of 8192 blades at density 80 is about 10 m wide, centred on 0.
    scene.wind.guides = vec![Guide {
        started: 0.0,
        strength: 6.0,
        radius: 1.0,
        points: vec![
            GuidePoint {
                position: (-3.0, 0.0),
                parent: None,
                strength: None,
                radius: None,
            },
            GuidePoint {
                position: (1.0, 0.0),
                parent: Some(0),
                strength: None,
                radius: None,
            },
        ],
    }];
    control.wind.guides.clear();
    let steps = 60;
    let (initial, windy) = run(scene, steps);
    let (_, calm) = run(control, steps);

    let mut sum = Vec2::ZERO;
    let mut count = 0;
    let mut far_worst = 0.0f32;
    let mut far_sum = 0.0f32;
    let mut far_count = 0;
    for i in 0..initial.len() {
        let root = Vec2::new(initial[i].v0_dir[0], initial[i].v0_dir[2]);
        let moved = tip(&windy[i]) - tip(&calm[i]);
        if (-1.0..2.5).contains(&root.x) && root.y.abs() < 0.6 {
            sum += moved;
            count += 1;
        }
        if root.y.abs() > 4.0 {
            far_worst = far_worst.max(moved.length() / initial[i].v1_height[3]);
            far_sum += moved.length();
            far_count += 1;
        }
    }
    let mean = sum / count as f32;
    let far_mean = far_sum / far_count.max(1) as f32;
    let cos = mean.normalize_or_zero().dot(Vec2::X);
    println!(
        "downstream: {count} blades, mean tip shift {:.3} m, cosine with the arrow {cos:.3}; {far_count} far blades (|z| > 4 m) move {far_mean:.4} m on average, at most {:.2} % of their height",
        mean.length(),
        far_worst * 100.0
    );
    assert!(count > 50, "too few blades downstream ({count})");
    assert!(
        mean.length() > 0.02,
        "downstream blades barely move ({})",
        mean.length()
    );
    assert!(
        cos > 0.8,
        "downstream blades bend at cos {cos} to the arrow"
    );
    assert!(far_count > 50, "too few far blades ({far_count})");
    assert!(
        far_mean < 0.1 * mean.length(),
        "far blades move {far_mean} m on average, downstream {}",
        mean.length()
    );
}
