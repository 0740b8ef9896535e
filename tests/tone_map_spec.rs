//! The tone-mapping pass built for the scene's curve alone (issue 26: the frame on a
//! budget) draws the same picture as the general pass with every curve compiled in: the
//! curve folded into a constant removes only the branches the uniform would not take.
//! Each curve renders a few frames both ways and every byte is compared; the curves
//! themselves must give different pictures, or the comparison would prove nothing.

mod common;

use sward::scene::{Scene, ToneMapping};

const SIZE: (u32, u32) = (128, 72);
const FRAMES: usize = 2;

fn render(mapper: ToneMapping, specialise: bool) -> image::RgbaImage {
    let mut scene = Scene::default();
    scene.terrain.size = 6.0;
    scene.render.msaa = 1;
    scene.light.tone_mapping = mapper;
    common::render_frames(scene, SIZE, FRAMES, |r| r.specialise_tone_map(specialise)).0
}

fn differing(a: &image::RgbaImage, b: &image::RgbaImage) -> usize {
    a.pixels().zip(b.pixels()).filter(|(p, q)| p != q).count()
}

#[test]
fn every_tone_mapper_draws_the_same_specialised() {
    let mut pictures = Vec::new();
    for mapper in [ToneMapping::Aces, ToneMapping::Agx, ToneMapping::Clamp] {
        let general = render(mapper, false);
        let special = render(mapper, true);
        let n = differing(&general, &special);
        println!("{mapper:?}: {n} pixels differ");
        assert_eq!(n, 0, "{mapper:?}: specialising changed the picture");
        pictures.push(special);
    }
    let total = (SIZE.0 * SIZE.1) as usize;
    for (i, j) in [(0, 1), (0, 2), (1, 2)] {
        let n = differing(&pictures[i], &pictures[j]);
        assert!(
            n > total / 2,
            "curves {i} and {j} differ in {n} pixels only"
        );
    }
}
