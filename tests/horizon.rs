//! The default meadow seen from high up (eye (0, 40, 60), looking at the origin; 160 × 90):
//! the ground runs on past the 32 m square, so no pixel whose view ray meets the ground
//! within two fog distances shows the sky pass's colour, and the far ground reads as grass
//! (green dominates the lower half). A bounded render of the same view is the control:
//! there the sky shows below the horizon, which proves the sky detector sees it.
//!
//! "Sky colour" is the sky pass's colour along each pixel's view ray: a CPU copy of
//! `sky_color` and `tonemap` (shaders/common.wgsl) and the sRGB encoding of the target.

mod common;

use glam::{Vec3, Vec4};
use sward::commands::{render, RenderOptions};
use sward::gpu::AdapterChoice;
use sward::render::camera::CameraView;

const SIZE: (u32, u32) = (160, 90);
const EYE: Vec3 = Vec3::new(0.0, 40.0, 60.0);
/// A pixel within this many 8-bit steps of the sky colour in every channel is "sky".
const SKY_TOLERANCE: f32 = 4.0;

struct View {
    image: image::RgbaImage,
    camera: CameraView,
    sun: Vec3,
    scene: sward::scene::Scene,
    fog: f32,
    /// Height of the ground plane the sky test intersects the view rays with.
    ground_y: f32,
}

fn render_view(unbounded: bool) -> View {
    render_scene("meadow.ron", unbounded, EYE, Vec3::ZERO, 0.0)
}

fn render_scene(file: &str, unbounded: bool, eye: Vec3, look_at: Vec3, ground_y: f32) -> View {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("assets/scenes")
        .join(file);
    let out = std::env::temp_dir().join(format!(
        "sward-horizon-{}-{file}-{unbounded}.png",
        std::process::id()
    ));
    let adapter: AdapterChoice = std::env::var("SWARD_ADAPTER")
        .unwrap_or_else(|_| "software".into())
        .parse()
        .expect("infallible");
    let sets = vec![
        format!("terrain.unbounded={unbounded}"),
        format!("camera.eye=({:?}, {:?}, {:?})", eye.x, eye.y, eye.z),
        format!(
            "camera.target=({:?}, {:?}, {:?})",
            look_at.x, look_at.y, look_at.z
        ),
    ];
    render(&RenderOptions {
        scene: Some(path.clone()),
        sets,
        size: SIZE,
        frames: 2,
        dt: 1.0 / 30.0,
        out: out.clone(),
        timings: false,
        trace: None,
        adapter,
        wind_overlay: false,
        pressure_iterations: None,
        wind_resolution: None,
    })
    .expect("render");
    let image = image::open(&out).expect("rendered png").to_rgba8();
    let _ = std::fs::remove_file(&out);
    let scene = sward::scene::load_scene(&path).expect("scene loads");
    let mut camera = CameraView::from_scene(&scene.camera);
    camera.eye = eye;
    camera.target = look_at;
    View {
        image,
        camera,
        sun: sward::render::light::sun::scene_sun(&scene),
        fog: sward::render::fog_distance(scene.terrain.size, scene.camera.far),
        ground_y,
        scene,
    }
}

/// Pixels whose ray meets the (roughly level) ground within two fog distances, and how
/// many of them show the sky colour.
fn sky_below_horizon(v: &View) -> (usize, usize) {
    let inv = v.camera.view_proj(SIZE.0 as f32 / SIZE.1 as f32).inverse();
    let (mut ground, mut sky) = (0, 0);
    for (x, y, px) in v.image.enumerate_pixels() {
        let ndc_x = (x as f32 + 0.5) / SIZE.0 as f32 * 2.0 - 1.0;
        let ndc_y = 1.0 - (y as f32 + 0.5) / SIZE.1 as f32 * 2.0;
        let far = inv * Vec4::new(ndc_x, ndc_y, 1.0, 1.0);
        let dir = (far.truncate() / far.w - v.camera.eye).normalize();
        if dir.y >= 0.0 || (v.camera.eye.y - v.ground_y) / -dir.y > 2.0 * v.fog {
            continue;
        }
        ground += 1;
        let want = sward::render::light::sky_srgb(&v.scene, v.sun, dir);
        let is_sky = (0..3).all(|c| (f32::from(px[c]) - f32::from(want[c])).abs() <= SKY_TOLERANCE);
        sky += usize::from(is_sky);
    }
    (ground, sky)
}

#[test]
fn high_view_shows_grass_coloured_ground_to_the_horizon() {
    let open = render_view(true);
    let (ground, sky) = sky_below_horizon(&open);
    println!("unbounded: {sky} of {ground} ground pixels are sky");
    assert!(
        ground > (SIZE.0 * SIZE.1 / 2) as usize,
        "{ground} ground pixels"
    );
    assert_eq!(
        sky, 0,
        "{sky} of {ground} pixels below the horizon show the sky"
    );
    // The lower half is grass: green dominates red and blue on average.
    let mut sum = [0f64; 3];
    let mut n = 0f64;
    for (_, y, px) in open.image.enumerate_pixels() {
        if y >= SIZE.1 / 2 {
            for c in 0..3 {
                sum[c] += f64::from(px[c]);
            }
            n += 1.0;
        }
    }
    let [r, g, b] = sum.map(|s| s / n);
    println!("lower half mean rgb {r:.1} {g:.1} {b:.1}");
    assert!(
        g > r * 1.05 && g > b * 1.05,
        "mean rgb {r:.1} {g:.1} {b:.1}"
    );

    // Control: the bounded square leaves sky below the horizon, and the detector sees it.
    let bounded = render_view(false);
    let (ground, sky) = sky_below_horizon(&bounded);
    println!("bounded: {sky} of {ground} ground pixels are sky");
    assert!(
        sky > ground / 4,
        "bounded: only {sky} of {ground} pixels are sky"
    );
}

/// The prairie from 60 m above its hills, looking out over kilometres: no sky below the
/// horizon (the ground runs on to the fog) and no bare ground (the blades near, the
/// grass-coloured ground far: no pixel of the lower half is soil-coloured, red over green).
#[test]
fn the_prairie_from_high_up_is_grass_to_the_horizon() {
    // The ground under the prairie's camera is at about -19 m.
    let v = render_scene(
        "prairie.ron",
        true,
        Vec3::new(-14.0, 40.0, 16.0),
        Vec3::new(300.0, -20.0, -300.0),
        -19.0,
    );
    let (ground, sky) = sky_below_horizon(&v);
    println!("prairie: {sky} of {ground} ground pixels are sky");
    assert!(
        ground > (SIZE.0 * SIZE.1 / 3) as usize,
        "{ground} ground pixels"
    );
    assert_eq!(
        sky, 0,
        "{sky} of {ground} pixels below the horizon show the sky"
    );
    let (mut soil, mut lower) = (0, 0);
    for (_, y, px) in v.image.enumerate_pixels() {
        if y >= SIZE.1 * 2 / 3 {
            lower += 1;
            soil += usize::from(px[0] >= px[1]);
        }
    }
    println!("prairie: {soil} of {lower} lower pixels are soil-coloured");
    assert!(
        soil * 200 < lower,
        "{soil} of {lower} lower pixels are bare ground"
    );
}
