//! Species and clumps (issue 15, point 5): the shares, each species' ranges, clumps whose
//! members share a species and face together, and a render that shows the species'
//! colours. The GPU tile kernel against its twin is in `tests/twin_tiles.rs`.

mod common;

use sward::field::clumps::{clump_of, species_of, FieldTraits};
use sward::scene::{Clumps, Range, Scene, Shape, Species};
use sward::session::Session;

fn species() -> Vec<Species> {
    vec![
        Species {
            share: 0.55,
            height: Range::new(0.3, 0.5),
            color: (0.1, 0.4, 0.05),
            ..Default::default()
        },
        Species {
            share: 0.3,
            height: Range::new(0.8, 1.0),
            stiffness: Range::new(3.0, 4.0),
            color: (0.6, 0.5, 0.1),
            shape: Shape::Quadratic,
            ..Default::default()
        },
        Species {
            share: 0.15,
            height: Range::new(0.1, 0.15),
            width: Range::new(0.06, 0.08),
            color: (0.05, 0.2, 0.05),
            shape: Shape::Dandelion,
            ..Default::default()
        },
    ]
}

fn scene(clumps: bool) -> Scene {
    let mut s = common::still_scene();
    s.terrain.size = 10.0;
    s.field.density = 400.0;
    s.field.species = species();
    s.field.clumps = clumps.then(Clumps::default);
    s
}

/// Each species takes its share of the blades (within 2 points), and every blade's
/// height, width and stiffness lie in its species' ranges.
#[test]
fn shares_and_ranges_hold() {
    for clumps in [false, true] {
        let session = Session::new(scene(clumps), None, None).expect("field");
        let traits = FieldTraits::from_field(&session.scene.field);
        let sp = species();
        let mut counts = [0usize; 3];
        for b in &session.field.blades {
            let k = species_of(&traits, b.v0_dir[0], b.v0_dir[2]);
            counts[k] += 1;
            let s = &sp[k];
            let inside = |r: Range, x: f32| x >= r.min - 1e-5 && x <= r.max + 1e-5;
            assert!(
                inside(s.height, b.v1_height[3]),
                "species {k} height {}",
                b.v1_height[3]
            );
            assert!(inside(s.width, b.v2_width[3]), "species {k} width");
            assert!(
                inside(s.stiffness, b.up_stiffness[3]),
                "species {k} stiffness"
            );
        }
        let n = session.field.blades.len() as f32;
        // Clumps draw a species per clump: ~280 clumps here, so the shares vary more.
        let slack = if clumps { 0.08 } else { 0.02 };
        for (k, s) in sp.iter().enumerate() {
            let share = counts[k] as f32 / n;
            println!(
                "clumps {clumps}: species {k}: {share:.3} of {n} blades (share {})",
                s.share
            );
            assert!(
                (share - s.share).abs() < slack,
                "species {k}: {share} against {}",
                s.share
            );
        }
    }
}

/// A clump is one species and its blades face its direction (within (1 − align)·π); the
/// field is patchy: neighbouring blades share a species far more often than they would by
/// chance (Σ share²).
#[test]
fn clumps_share_species_and_facing() {
    let session = Session::new(scene(true), None, None).expect("field");
    let traits = FieldTraits::from_field(&session.scene.field);
    let align = Clumps::default().align;
    let mut by_clump = std::collections::HashMap::new();
    for b in &session.field.blades {
        let (x, z) = (b.v0_dir[0], b.v0_dir[2]);
        let c = clump_of(&traits, x, z);
        let k = species_of(&traits, x, z);
        assert_eq!(
            *by_clump.entry(c.hash).or_insert(k),
            k,
            "a clump of two species"
        );
        let off = (b.v0_dir[3] - c.angle).abs();
        assert!(
            off <= (1.0 - align) * std::f32::consts::PI + 1e-4,
            "facing {off} off the clump"
        );
    }
    assert!(by_clump.len() > 100, "{} clumps", by_clump.len());
    // Neighbours: consecutive blades of a sorted patch are close together.
    let blades = &session.field.blades;
    let mut same = 0;
    let mut pairs = 0;
    for w in blades.windows(2) {
        let d = ((w[0].v0_dir[0] - w[1].v0_dir[0]).powi(2)
            + (w[0].v0_dir[2] - w[1].v0_dir[2]).powi(2))
        .sqrt();
        if d < 0.1 {
            pairs += 1;
            same += usize::from(
                species_of(&traits, w[0].v0_dir[0], w[0].v0_dir[2])
                    == species_of(&traits, w[1].v0_dir[0], w[1].v0_dir[2]),
            );
        }
    }
    let chance: f32 = species().iter().map(|s| s.share * s.share).sum();
    let observed = same as f32 / pairs.max(1) as f32;
    println!("neighbours within 10 cm of one species: {observed:.2} ({pairs} pairs; by chance {chance:.2})");
    assert!(pairs > 1000);
    assert!(observed > chance + 0.3, "{observed} against {chance}");
}

/// The species' colours reach the picture: the straw species' yellow appears in the mixed
/// field and not in a field of the first species alone.
#[test]
fn species_colours_are_drawn() {
    let render = |s: Scene| {
        let mut s = s;
        s.camera.eye = (0.0, 1.6, 3.5);
        s.camera.target = (0.0, 0.2, 0.0);
        common::render_frame(s, (128, 80))
    };
    let straw = |img: &image::RgbaImage| {
        img.pixels()
            .filter(|p| {
                p[0] as f32 > 0.8 * p[1] as f32 && p[1] as f32 > 1.5 * p[2] as f32 && p[1] > 60
            })
            .count()
    };
    let mixed = render(scene(true));
    let mut one = scene(true);
    one.field.species.truncate(1);
    let plain = render(one);
    let (a, b) = (straw(&mixed), straw(&plain));
    println!("straw-coloured pixels: {a} mixed, {b} with one species");
    assert!(a > 200 && a > 5 * b.max(1), "{a} against {b}");
}
