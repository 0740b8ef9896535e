//! The grass pipelines' specialisation: the scene's switches (blade model, blade shape,
//! species, clumps, flowers, debug views, the sky model) given to `grass.wgsl` as
//! pipeline-overridable constants, so that the paths a scene does not use are compiled out.
//! The sky model also specialises the sky pass (`pipelines::sky_pipeline`).
//!
//! Why: a CPU adapter (llvmpipe) does not jump over an `if`. It runs both sides for the
//! whole SIMD batch under a mask, so every blade model, shape, flower head and debug colour
//! cost every grass vertex and fragment whether the scene used it or not. Folded to
//! constants, the nature frame's grass draw and shadow casters lose that work (the commit
//! that added this module gives the figures).
//!
//! A constant only ever removes a path its uniform would not take: the shader still reads
//! the uniforms where the constant says "any" (the defaults), so a pipeline built without
//! constants draws exactly as before, and a specialised one draws the same picture.

use crate::field::clumps::FieldTraits;
use crate::scene::Scene;

/// `ANY` in `grass.wgsl`: the uniform decides.
const ANY: u32 = u32::MAX;

/// The constants one set of grass pipelines is built with.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct GrassSpec {
    /// The blade model's id (`BladeModel::id`), or `None`: any, read from the uniform.
    pub model: Option<u32>,
    /// The one blade shape of every blade (`Shape::id`), or `None`: per species.
    pub shape: Option<u32>,
    /// Whether the field has more than one species.
    pub species: bool,
    /// Whether the field has clumps.
    pub clumps: bool,
    /// Whether the field has flowers.
    pub flowers: bool,
    /// Whether a debug colour view (levels, patches, trails) may be on.
    pub debug_views: bool,
    /// The sky model's id (`SkyModel::id`: light.wgsl's `SKY_MODEL`), or `None`: any.
    pub sky: Option<u32>,
    /// Whether the deferred light looks the sun up along each blade at its rows
    /// (`BladeShadowLookup::PerRow`) instead of per pixel: the deferred modules'
    /// `SUN_PER_PIXEL` (`deferred::DeferredPipelines`), not one of grass.wgsl's.
    pub sun_per_row: bool,
    /// Whether the blades morph between levels of detail (`culling.lod_morph` > 0 and
    /// the renderer's `lod_morph`): grass.wgsl's `MORPH`.
    pub morph: bool,
    /// Whether the blades fold along their middle axis (`render.displacement`, Eq. 23):
    /// grass.wgsl's `FOLD`. Without it the finest level's mesh is flat, two columns
    /// (`mesh::LodMeshes::levels`).
    pub fold: bool,
}

impl GrassSpec {
    /// Every path kept: what a pipeline without constants does.
    pub const GENERAL: GrassSpec = GrassSpec {
        model: None,
        shape: None,
        species: true,
        clumps: true,
        flowers: true,
        debug_views: true,
        sky: None,
        sun_per_row: false,
        morph: true,
        fold: true,
    };

    /// The specialisation for drawing `scene`'s field, whose species, clumps and flowers
    /// are `traits` (the draw's uniform, made once with the renderer), with the scene's
    /// model, shape and colour view as they are now (the panel changes them live).
    pub fn of(scene: &Scene, traits: &FieldTraits) -> Self {
        let species = traits.info[0].max(1);
        let own_colour = |k: usize| traits.species[k].color[3] > 0.5;
        // `blade_shape` in grass.wgsl: a species with its own colour has its own shape,
        // else the field's shape of the frame uniform.
        let shape_of = |k: usize| {
            if own_colour(k) {
                traits.species[k].attrs[3] as u32
            } else {
                scene.field.shape.id()
            }
        };
        let first = shape_of(0);
        let shape = (1..species as usize)
            .all(|k| shape_of(k) == first)
            .then_some(first);
        GrassSpec {
            model: Some(scene.physics.model.id()),
            shape,
            species: species > 1,
            clumps: traits.has_clumps(),
            flowers: traits.flowers[0] > 0.0,
            debug_views: scene.render.color_mode.id() != 0,
            sky: Some(scene.light.sky.id()),
            sun_per_row: scene.light.shadows.blade_lookup == crate::scene::BladeShadowLookup::PerRow,
            morph: scene.culling.lod_morph > 0.0,
            fold: scene.render.displacement,
        }
    }

    /// The pipeline constants (`override`s of `grass.wgsl`) for this specialisation.
    pub fn constants(&self) -> [(&'static str, f64); 9] {
        let flag = |b: bool| if b { 1.0 } else { 0.0 };
        [
            ("BLADE_MODEL", self.model.unwrap_or(ANY) as f64),
            ("BLADE_SHAPE", self.shape.unwrap_or(ANY) as f64),
            ("SPECIES", flag(self.species)),
            ("CLUMPS", flag(self.clumps)),
            ("FLOWERS", flag(self.flowers)),
            ("DEBUG_VIEWS", flag(self.debug_views)),
            self.sky_constant(),
            ("MORPH", flag(self.morph)),
            ("FOLD", flag(self.fold)),
        ]
    }

    /// light.wgsl's `SKY_MODEL` for this specialisation: the grass pipelines' and the sky
    /// pass's (`pipelines::sky_pipeline`).
    pub fn sky_constant(&self) -> (&'static str, f64) {
        ("SKY_MODEL", self.sky.unwrap_or(ANY) as f64)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::{BladeModel, ColorMode, Shape};

    fn meadow() -> Scene {
        Scene::default()
    }

    #[test]
    fn a_plain_field_folds_every_switch() {
        let scene = meadow();
        let traits = FieldTraits::from_field(&scene.field);
        let spec = GrassSpec::of(&scene, &traits);
        assert_eq!(spec.model, Some(scene.physics.model.id()));
        assert_eq!(spec.shape, Some(scene.field.shape.id()));
        assert_eq!(
            (spec.species, spec.flowers, spec.debug_views),
            (false, scene.field.flowers.is_some(), false)
        );
    }

    #[test]
    fn the_scene_as_it_is_now_decides_model_shape_and_view() {
        let mut scene = meadow();
        let traits = FieldTraits::from_field(&scene.field);
        scene.physics.model = BladeModel::Cwd;
        scene.field.shape = Shape::Dandelion;
        scene.render.color_mode = ColorMode::Trail;
        let spec = GrassSpec::of(&scene, &traits);
        assert_eq!(spec.model, Some(2));
        assert_eq!(spec.shape, Some(4));
        assert!(spec.debug_views);
    }

    #[test]
    fn species_of_different_shapes_keep_the_shape_per_blade() {
        let scene = crate::scene::parse_scene(
            "(field: (species: [(share: 1.0, shape: Quad, color: (0.1, 0.3, 0.1)), \
             (share: 1.0, shape: Triangle, color: (0.2, 0.3, 0.1))]))",
            std::path::Path::new("species.ron"),
        )
        .expect("scene parses");
        let traits = FieldTraits::from_field(&scene.field);
        let spec = GrassSpec::of(&scene, &traits);
        assert!(spec.species);
        assert_eq!(spec.shape, None);
        assert_eq!(spec.constants()[1], ("BLADE_SHAPE", u32::MAX as f64));
    }

    #[test]
    fn the_general_spec_keeps_every_path() {
        for (name, value) in GrassSpec::GENERAL.constants() {
            let kept = match name {
                "BLADE_MODEL" | "BLADE_SHAPE" | "SKY_MODEL" => value == u32::MAX as f64,
                _ => value == 1.0,
            };
            assert!(kept, "{name} = {value}");
        }
    }
}
