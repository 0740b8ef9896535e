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

/// The update is built for the wind sources the scene has (`WIND_KINDS`: a source it lacks
/// is compiled out, `UpdatePass::prepare` building the pipeline of each combination the
/// first time a frame needs it) and must follow the panel when it switches them live.
/// A field under the fluid alone (driven along x by a global wind), switched to both
/// sources without a rebuild of the solver, must bend along the directional wind's z as
/// well; one that kept the fluid alone must not. Switched from the analytic source (with
/// no analytic wind, at rest) to the fluid through `rebuild_wind`, it must bend along x.
#[test]
fn a_wind_source_switched_live_reaches_the_blades() {
    let gpu = common::gpu();
    let mut scene = common::still_scene();
    scene.physics.gravity_acceleration = 9.81;
    scene.wind.fluid.resolution = 32;
    scene.wind.global = Some(sward::scene::GlobalWind {
        direction: (1.0, 0.0),
        strength: 4.0,
    });
    let dt = 1.0 / 30.0;
    let mean_shift = |session: &Session, r: &sward::render::Renderer| {
        let blades = r.buffers.read(&gpu).expect("read-back").0;
        let initial = &session.field.blades;
        let sum: Vec2 = initial
            .iter()
            .zip(&blades)
            .map(|(a, b)| tip(b) - tip(a))
            .sum();
        sum / initial.len() as f32
    };

    // Fluid -> both, in place: the directional wind blows along z.
    let mut fluid = scene.clone();
    fluid.wind.source = WindSource::Fluid;
    fluid.wind.directional = Some(sward::scene::DirectionalWind {
        direction: (0.0, 1.0),
        strength: 6.0,
        gust: 0.0,
        wavelength: 10.0,
        speed: 1.0,
    });
    let session = Session::new(fluid, Some(2048), Some(&gpu)).expect("field");
    let mut switched = common::stepped(&gpu, &session, 5, dt);
    let mut kept = common::stepped(&gpu, &session, 5, dt);
    switched.scene.wind.source = WindSource::Both;
    for _ in 0..40 {
        switched.step(&gpu, dt);
        kept.step(&gpu, dt);
    }
    let (both, alone) = (mean_shift(&session, &switched), mean_shift(&session, &kept));
    println!("fluid switched to both: {both}; kept the fluid alone: {alone}");
    assert!(
        both.y > 0.05,
        "the directional wind reaches the blades: {both}"
    );
    assert!(alone.y.abs() < 0.2 * both.y, "{alone} against {both}");

    // Analytic (no analytic wind) -> fluid, through the solver's rebuild.
    let mut analytic = scene;
    analytic.wind.source = WindSource::Analytic;
    let session = Session::new(analytic, Some(2048), Some(&gpu)).expect("field");
    let mut switched = common::stepped(&gpu, &session, 5, dt);
    let mut kept = common::stepped(&gpu, &session, 5, dt);
    switched.scene.wind.source = WindSource::Fluid;
    switched.rebuild_wind(&gpu).expect("fluid");
    for _ in 0..40 {
        switched.step(&gpu, dt);
        kept.step(&gpu, dt);
    }
    let (fluid, calm) = (mean_shift(&session, &switched), mean_shift(&session, &kept));
    println!("analytic switched to the fluid: {fluid}; kept analytic: {calm}");
    assert!(fluid.x > 0.05, "the blades bend downwind: {fluid}");
    assert!(calm.length() < 0.2 * fluid.x, "{calm} against {fluid}");
}
