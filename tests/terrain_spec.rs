//! The lit terrain built for its scene (`TerrainSpec`; issue 26, the frame on a budget):
//! without a density map its lookup is compiled out, and a scene with one still shows it.
//! Seen from above with the blades' reach cut short, the whole view is far ground: where
//! the map is black it must show the soil, not the far grass; a map white everywhere must
//! draw the ground a scene with no map draws (the compiled-out lookup's
//! 1), and a map of two halves two different halves, or that comparison would prove
//! nothing.

mod common;

use sward::scene::{HeightSource, Scene};

const SIZE: (u32, u32) = (96, 96);

fn scene(map: Option<&std::path::Path>) -> Scene {
    let mut s = common::still_scene();
    s.terrain.size = 200.0;
    s.field.density = 1.0;
    s.terrain.resolution = 33;
    s.terrain.height = HeightSource::Flat;
    s.terrain.unbounded = false;
    s.terrain.density_map = map.map(|p| p.to_string_lossy().into_owned());
    // The blades stand within 5 m of the camera, below and behind what it sees: every
    // pixel is the far ground.
    s.culling.max_distance = 5.0;
    s.render.msaa = 1;
    s.camera.eye = (-25.0, 30.0, 0.0);
    s.camera.target = (5.0, 0.0, 0.0);
    s
}

/// Mean (r, g, b) of the pixels in columns `cols` (rows 16..80: clear of the edges).
fn mean(img: &image::RgbaImage, cols: std::ops::Range<u32>) -> [f64; 3] {
    let mut sum = [0.0; 3];
    let mut n = 0.0;
    for y in 16..80 {
        for x in cols.clone() {
            let p = img.get_pixel(x, y);
            for c in 0..3 {
                sum[c] += f64::from(p[c]);
            }
            n += 1.0;
        }
    }
    sum.map(|s| s / n)
}

#[test]
fn the_far_ground_follows_the_density_map_and_a_full_map_draws_what_no_map_draws() {
    let dir = std::env::temp_dir().join(format!("sward-terrain-spec-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let half = dir.join("half.png");
    let white = dir.join("white.png");
    // Black over the square's northern half (z < 0), white over its southern half: the
    // camera looks along +x, so they are the picture's two sides. And all white.
    image::ImageBuffer::from_fn(64, 64, |_, y| image::Luma([if y < 32 { 0u8 } else { 255 }]))
        .save(&half)
        .unwrap();
    image::ImageBuffer::from_fn(64, 64, |_, _| image::Luma([255u8]))
        .save(&white)
        .unwrap();
    let halves = common::render_frame(scene(Some(&half)), SIZE);
    let full = common::render_frame(scene(Some(&white)), SIZE);
    let none = common::render_frame(scene(None), SIZE);
    let _ = std::fs::remove_dir_all(&dir);

    // A map of 1 everywhere is the compiled-out lookup's 1: the same ground. (Not every
    // byte: the map also decides which blades grow, and a few far blade tips differ.)
    let (f, g) = (mean(&full, 0..SIZE.0), mean(&none, 0..SIZE.0));
    for c in 0..3 {
        assert!(
            (f[c] - g[c]).abs() < 0.5,
            "a full map draws other ground than no map: {f:?} vs {g:?}"
        );
    }
    // The lookup is live: one side of the two-halved map draws the ground of no map, the
    // other the soil under the blades instead of the far grass.
    let sides = [8..40, 56..88];
    let gaps: Vec<f64> = sides
        .iter()
        .map(|cols| (mean(&halves, cols.clone())[1] - mean(&none, cols.clone())[1]).abs())
        .collect();
    println!("green against no map, per side: {gaps:?}");
    let (near, far) = (gaps[0].min(gaps[1]), gaps[0].max(gaps[1]));
    assert!(
        near < 1.0,
        "neither side draws the full map's ground: {gaps:?}"
    );
    assert!(
        far > 5.0,
        "the map's bare side draws the far grass: {gaps:?}"
    );
}
