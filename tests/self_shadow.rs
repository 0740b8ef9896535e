//! CWD-Sim's self-shadow (Eq. 14, `render.self_shadow: Cwd(..)`) in real renders of the same
//! still field: clamped to a brightness of 1 everywhere (c2 = 2) it is exactly the unshaded
//! image (`Off`); pinned to 0.5 (m_min = m_max = 0.5) the grass is darker; the shipped
//! parameters darken the grass between those two, and a field pressed flat by gravity (a
//! large bend) is darker under Eq. 14 than the same field upright, which the unshaded mode
//! does not show.

mod common;

use sward::render::camera::CameraView;
use sward::render::target::Target;
use sward::scene::{Range, SelfShadow};
use sward::session::Session;

const SIZE: (u32, u32) = (96, 64);

fn render(shadow: SelfShadow, bend: f32) -> image::RgbaImage {
    let mut s = common::still_scene();
    s.terrain.size = 6.0;
    s.field.density = 60.0;
    s.field.patch_size = 256;
    s.field.bend = Range::new(bend, bend);
    s.render.self_shadow = shadow;
    s.camera.eye = (0.0, 1.2, -3.5);
    s.camera.target = (0.0, 0.0, 0.0);
    let gpu = common::gpu();
    let session = Session::new(s, None, Some(&gpu)).expect("session");
    let mut r = common::world(&gpu, &session);
    let target = Target::new(&gpu, SIZE.0, SIZE.1).expect("target");
    let camera = CameraView::from_scene(&session.scene.camera);
    sward::commands::world_frame(&gpu, &mut r, 1.0 / 60.0, camera, &target).expect("frame");
    gpu.check_errors().expect("no GPU error");
    target.read_image(&gpu).expect("image")
}

/// Mean green of the lower two thirds (the grass).
fn green(image: &image::RgbaImage) -> f64 {
    let rows = SIZE.1 / 3..SIZE.1;
    let mut sum = 0.0;
    let mut n = 0.0;
    for y in rows {
        for x in 0..SIZE.0 {
            sum += f64::from(image.get_pixel(x, y)[1]);
            n += 1.0;
        }
    }
    sum / n
}

#[test]
fn eq14_clamps_darkens_and_follows_the_bend() {
    let off = render(SelfShadow::Off, 10.0);
    let full = render(
        SelfShadow::Cwd {
            min: 0.3,
            max: 1.0,
            c1: 0.7,
            c2: 2.0,
        },
        10.0,
    );
    assert!(
        off == full,
        "brightness clamped to 1 must equal no self-shadow"
    );
    let half = render(
        SelfShadow::Cwd {
            min: 0.5,
            max: 0.5,
            c1: 0.7,
            c2: 0.25,
        },
        10.0,
    );
    let cwd = render(SelfShadow::CWD, 10.0);
    let (g_off, g_half, g_cwd) = (green(&off), green(&half), green(&cwd));
    println!("green: off {g_off:.1}, Eq. 14 {g_cwd:.1}, pinned to 0.5 {g_half:.1}");
    assert!(g_half < g_off - 5.0, "{g_half} vs {g_off}");
    assert!(g_cwd < g_off - 2.0 && g_cwd > g_half - 30.0, "{g_cwd}");
    // Bent blades sink into the shade under Eq. 14; unshaded, bending changes far less.
    let cwd_bent = green(&render(SelfShadow::CWD, 70.0));
    let off_bent = green(&render(SelfShadow::Off, 70.0));
    println!("bent 70°: Eq. 14 {cwd_bent:.1}, off {off_bent:.1}");
    let cwd_drop = g_cwd - cwd_bent;
    let off_drop = g_off - off_bent;
    assert!(
        cwd_drop > off_drop + 3.0,
        "Eq. 14 drop {cwd_drop:.1} vs off {off_drop:.1}"
    );
}
