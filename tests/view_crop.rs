//! The window draws its 3D view only beside its panel (`Renderer::view_crop`,
//! `render::camera::crop_x`): the part it draws must be the same part of the whole view,
//! pixel for pixel but for what the culling decides differently at the part's edge, and
//! the blades under the panel must not be drawn.

mod common;

use sward::render::camera::crop_x;
use sward::session::Session;

const FULL: (u32, u32) = (256, 144);
/// The panel's width in pixels: the part drawn is x in [LEFT, 256).
const LEFT: u32 = 96;
const FRAMES: usize = 3;

#[test]
fn the_cropped_view_is_the_same_part_of_the_whole_view() {
    let gpu = common::gpu();
    let mut scene = sward::scene::Scene::default();
    scene.render.msaa = 1;
    let session = Session::new(scene, None, Some(&gpu)).expect("field");
    let (mut whole, target) = common::draw_frames(&gpu, &session, FULL, FRAMES, false, |_| {});
    let whole_image = target.read_image(&gpu).expect("image");
    let whole_drawn = whole.stats(&gpu).expect("stats").counters.drawn();

    let part = (FULL.0 - LEFT, FULL.1);
    let x0 = 2.0 * LEFT as f32 / FULL.0 as f32 - 1.0;
    let aspect = FULL.0 as f32 / FULL.1 as f32;
    let (mut cropped, target) = common::draw_frames(&gpu, &session, part, FRAMES, false, |r| {
        r.display_aspect = Some(aspect);
        r.view_crop = crop_x(x0);
    });
    let part_image = target.read_image(&gpu).expect("image");
    let part_drawn = cropped.stats(&gpu).expect("stats").counters.drawn();

    let mut sum = 0u64;
    let mut far_off = 0usize;
    for (x, y, p) in part_image.enumerate_pixels() {
        let w = whole_image.get_pixel(x + LEFT, y);
        let d: u32 = (0..3).map(|c| u32::from(p[c].abs_diff(w[c]))).sum();
        sum += u64::from(d);
        far_off += usize::from(d > 3 * 64);
    }
    let pixels = (part.0 * part.1) as f64;
    let mean = sum as f64 / (3.0 * pixels);
    println!(
        "cropped view: mean difference {mean:.3}, {far_off} pixels far off; blades drawn {part_drawn} \
         of the whole view's {whole_drawn}"
    );
    // Measured 0.047 levels and 1 pixel: the depth pyramid is built over other pixels, so
    // a few blades at the occlusion test's margin go the other way (22,615 blades drawn
    // of the whole view's 35,272).
    assert!(mean < 1.0, "mean difference {mean:.3}");
    assert!(
        (far_off as f64) < 0.005 * pixels,
        "{far_off} pixels far off"
    );
    // The blades under the panel are not drawn: the frustum is the part's.
    assert!(
        part_drawn < whole_drawn * 9 / 10,
        "{part_drawn} drawn of {whole_drawn}"
    );
    assert!(
        part_drawn > whole_drawn / 4,
        "{part_drawn} of {whole_drawn}"
    );
}
