//! Flowers among the grass (issue 15, point 4; Zhang's thesis §3.3–3.4): their share of the
//! blades, their stems' height and width, heads of every kind drawn in their colours, and
//! stems pressed by a ball like any blade. The GPU tile kernel with flowers against its
//! twin is in `tests/twin_tiles.rs`.

mod common;

use sward::commands::simulate_cpu;
use sward::field::clumps::{flower_kind, is_flower, FieldTraits, STEM_WIDTH};
use sward::scene::{Flowers, Scene};
use sward::session::Session;

fn scene(fraction: f32) -> Scene {
    let mut s = common::still_scene();
    s.terrain.size = 8.0;
    s.field.density = 300.0;
    s.field.height = sward::scene::Range::new(0.2, 0.3);
    s.field.flowers = (fraction > 0.0).then(|| Flowers {
        fraction,
        height: sward::scene::Range::new(0.35, 0.45),
        head_size: 0.05,
        ..Default::default()
    });
    s.camera.eye = (0.0, 1.4, 2.6);
    s.camera.target = (0.0, 0.2, 0.0);
    s
}

#[test]
fn flowers_take_their_share_with_thin_stems_of_their_height() {
    let session = Session::new(scene(0.05), None, None).expect("field");
    let traits = FieldTraits::from_field(&session.scene.field);
    let mut flowers = 0;
    let mut kinds = [0usize; 4];
    for b in &session.field.blades {
        let (x, z) = (b.v0_dir[0], b.v0_dir[2]);
        if is_flower(&traits, x, z) {
            flowers += 1;
            kinds[flower_kind(&traits, x, z)] += 1;
            assert!(
                (0.35..=0.45 + 1e-5).contains(&b.v1_height[3]),
                "stem {}",
                b.v1_height[3]
            );
            assert_eq!(b.v2_width[3], STEM_WIDTH);
        } else {
            assert!(b.v1_height[3] <= 0.3 + 1e-5, "grass {}", b.v1_height[3]);
        }
    }
    let n = session.field.blades.len();
    let share = flowers as f32 / n as f32;
    println!("flowers: {flowers} of {n} blades ({share:.4}, asked 0.05); kinds {kinds:?}");
    assert!((share - 0.05).abs() < 0.01, "{share}");
    for (k, &c) in kinds.iter().take(3).enumerate() {
        assert!(c * 5 > flowers, "kind {k}: {c} of {flowers}");
    }
}

/// The heads show in their kinds' colours: white, yellow and purple pixels appear with
/// flowers, and (almost) none without.
#[test]
fn heads_are_drawn_in_their_colours() {
    let render = |s: Scene| common::render_frame(s, (160, 100));
    let count = |img: &image::RgbaImage| {
        let mut c = [0usize; 3];
        // The lower 60 % of the picture: grass, no sky.
        for (_, y, p) in img.enumerate_pixels() {
            if y < img.height() * 2 / 5 {
                continue;
            }
            let (r, g, b) = (p[0] as i32, p[1] as i32, p[2] as i32);
            if r > 170 && g > 170 && b > 150 {
                c[0] += 1; // white petals
            } else if r > 140 && r >= g && g > b + 60 {
                c[1] += 1; // yellow
            } else if b > g + 20 && r > g {
                c[2] += 1; // purple
            }
        }
        c
    };
    let with = count(&render(scene(0.08)));
    let without = count(&render(scene(0.0)));
    println!("white, yellow, purple pixels: {with:?} with flowers, {without:?} without");
    for k in 0..3 {
        assert!(
            with[k] > 5 && with[k] > 4 * without[k],
            "kind {k}: {with:?} against {without:?}"
        );
    }
}

/// Stems are blades: a ball rolling through the field presses flowers as it presses grass.
#[test]
fn a_ball_presses_the_flowers() {
    let mut s = scene(0.1);
    s.colliders = vec![common::rolling_sphere(-4.0, 0.25, 0.35, 2.0)];
    let session = Session::new(s, None, None).expect("field");
    let traits = FieldTraits::from_field(&session.scene.field);
    let run = simulate_cpu(&session, 90, 1.0 / 30.0);
    let pressed = run
        .blades
        .iter()
        .zip(&run.states)
        .filter(|(b, st)| is_flower(&traits, b.v0_dir[0], b.v0_dir[2]) && st.rest_eta[3] > 0.05)
        .count();
    println!("flowers pressed by the ball: {pressed}");
    assert!(pressed > 10, "{pressed}");
}
