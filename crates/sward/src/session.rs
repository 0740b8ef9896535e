//! Builds what a run needs from a scene: the terrain, the field of blades and (through
//! `Renderer`) the GPU resources — checking the blade count against the adapter first, so
//! that a request too large fails with a message before anything is allocated.

use crate::error::{Error, Result};
use crate::field::tiles::{TileLayout, MAX_POOL_BLADES};
use crate::field::{flat_field, generate, DensityMap, GeneratedField, HeightField};
use crate::gpu::Gpu;
use crate::mesh::pack::Packing;
use crate::scene::Scene;
use crate::sim::layout::Blade;

/// Largest `--blades` value accepted on the command line.
pub const MAX_BLADES: usize = 50_000_000;

/// A scene with its terrain and generated field.
pub struct Session {
    /// The scene, validated; with `--blades` its terrain is the flat square the blades
    /// stand on.
    pub scene: Scene,
    /// The ground's height field, built from `scene.terrain`.
    pub terrain: HeightField,
    /// The whole field, or for a streamed scene only the grass grown on mesh objects (the
    /// renderer's pool, filled on the GPU tile by tile around the camera, comes before it).
    pub field: GeneratedField,
    /// For a streamed scene, the grass grown on mesh objects as `field` held it at load
    /// (`fill_tiles_cpu` replaces `field` with the pool followed by this).
    object_grass: GeneratedField,
    /// How a streamed scene is cut into tiles (`field.tile_size > 0`).
    pub tiles: Option<TileLayout>,
    /// The meshes of `scene.objects`, in order, read and checked.
    pub meshes: Vec<crate::mesh::Mesh>,
    /// The skinned mesh and the index of the animation it plays, of each object with an
    /// `animation` (`None` for the others), in order.
    pub skins: Vec<Option<(crate::mesh::skin::SkinnedMesh, usize)>>,
    /// The sphere packing of each object whose `collider` asks for one (in its mesh's
    /// units; `None` for the others), computed once at load.
    pub packings: Vec<Option<Packing>>,
}

/// Grows the grass of every object that has some (`objects[i].grass`) on its surface at
/// rest and appends its patches to `field`.
fn grow_on_objects(
    scene: &Scene,
    meshes: &[crate::mesh::Mesh],
    field: &mut GeneratedField,
) -> Result<()> {
    let patch_size = field.patch_size as usize;
    for (i, (object, mesh)) in scene.objects.iter().zip(meshes).enumerate() {
        let Some(grass) = &object.grass else { continue };
        // Checked before a single blade is made: the area times the density.
        let area = crate::field::surface::surface_area(mesh, object.transform());
        if !area.is_finite() {
            return Err(scene.error_at(
                &format!("objects[{i}].scale"),
                format!(
                    "objects[{i}]: the surface area of {:?} at scale {} overflows (the mesh's \
                     coordinates are too large): lower objects[{i}].scale or use a mesh in \
                     smaller units",
                    object.mesh, object.scale
                ),
            ));
        }
        let wanted = f64::from(grass.density) * area;
        if wanted + field.blades.len() as f64 > MAX_BLADES as f64 {
            return Err(scene.error_at(
                &format!("objects[{i}].grass.density"),
                format!(
                    "objects[{i}].grass.density = {}: {wanted:.0} blades on the {area:.1} m² of \
                     {:?} (with the field's {}) are more than {MAX_BLADES}; lower \
                     objects[{i}].grass.density or objects[{i}].scale",
                    grass.density,
                    object.mesh,
                    field.blades.len()
                ),
            ));
        }
        let (blades, patches) =
            crate::field::surface::surface_field(mesh, object.transform(), grass, patch_size);
        log::info!(
            "objects[{i}] ({}): {} blades of grass in {} patches on its surface",
            object.mesh,
            blades.len(),
            patches.len()
        );
        let states: Vec<_> = blades.iter().map(crate::field::rest_state).collect();
        // The grass of a moving object travels with it (`sim::carry`).
        if object.motion != crate::scene::Motion::Static {
            field.carried.add(
                i,
                object.transform(),
                crate::sim::carry::Grown {
                    blades: &blades,
                    states: &states,
                    boxes: &patches,
                    first_blade: field.blades.len(),
                    first_patch: field.patches.len(),
                    patch_size,
                },
            );
        }
        field.states.extend(states);
        field.blades.extend(blades);
        field.patches.extend(patches);
    }
    Ok(())
}

/// Packs every object whose collider asks for spheres, and logs how well they cover it.
fn pack_objects(scene: &Scene, meshes: &[crate::mesh::Mesh]) -> Vec<Option<Packing>> {
    scene
        .objects
        .iter()
        .zip(meshes)
        .enumerate()
        .map(|(i, (object, mesh))| match object.collider.packing() {
            None => None,
            Some(p) => {
                let packing = crate::mesh::pack::pack(mesh, p.count as usize, p.resolution);
                log::info!(
                    "objects[{i}] ({}): {} spheres cover {:.1} % of the mesh's {} inside \
                     voxels",
                    object.mesh,
                    packing.spheres.len(),
                    packing.coverage * 100.0,
                    packing.inside_voxels
                );
                Some(packing)
            }
        })
        .collect()
}

/// Ties the packings of animated objects to their skeletons (`mesh::pack::SphereRig`);
/// an object whose collider is `Joints` gets one sphere per joint.
fn rig_packings(
    scene: &Scene,
    packings: Vec<Option<crate::mesh::pack::Packing>>,
    skins: &Skins,
) -> Vec<Option<crate::mesh::pack::Packing>> {
    packings
        .into_iter()
        .zip(skins)
        .zip(&scene.objects)
        .map(|((packing, skin), object)| {
            if let (crate::scene::MeshCollider::Joints, Some((mesh, animation))) =
                (&object.collider, skin)
            {
                return Some(crate::mesh::pack::SphereRig::joint_spheres(
                    mesh, *animation,
                ));
            }
            let mut packing = packing?;
            if let Some((mesh, animation)) = skin {
                packing.rig = Some(Box::new(crate::mesh::pack::SphereRig::new(
                    mesh,
                    *animation,
                    &packing.spheres,
                )));
            }
            Some(packing)
        })
        .collect()
}

/// An animated object's mesh is its skinned mesh at the bind pose (what its packing, its
/// grass and its first frame use).
type Skins = Vec<Option<(crate::mesh::skin::SkinnedMesh, usize)>>;

/// Reads every object's mesh (errors name the scene line of its `mesh`) and checks that
/// each fits the adapter's vertex and index buffers, before anything is allocated.
fn load_meshes(scene: &Scene, gpu: Option<&Gpu>) -> Result<(Vec<crate::mesh::Mesh>, Skins)> {
    let mut meshes = Vec::with_capacity(scene.objects.len());
    let mut skins = Vec::with_capacity(scene.objects.len());
    for (i, object) in scene.objects.iter().enumerate() {
        let field = format!("objects[{i}].mesh");
        let path = std::path::Path::new(&object.mesh);
        let mesh = match &object.animation {
            None => {
                skins.push(None);
                crate::mesh::load(path).map_err(|e| scene.image_error(&field, e))?
            }
            Some(name) => {
                let skinned = crate::mesh::skin::SkinnedMesh::load(path)
                    .map_err(|e| scene.image_error(&field, e))?;
                let Some(k) = skinned.animations.iter().position(|a| &a.name == name) else {
                    let names: Vec<&str> =
                        skinned.animations.iter().map(|a| a.name.as_str()).collect();
                    let at = format!("objects[{i}].animation");
                    return Err(scene.image_error(
                        &at,
                        Error::Invalid(format!(
                            "{at} = {name:?}: {} has no animation of that name (it has \
                             {names:?})",
                            object.mesh
                        )),
                    ));
                };
                let mesh = crate::mesh::Mesh {
                    positions: skinned.positions.clone(),
                    normals: skinned.normals.clone(),
                    indices: skinned.indices.clone(),
                    degenerate: 0,
                };
                skins.push(Some((skinned, k)));
                mesh
            }
        };
        if let Some(gpu) = gpu {
            let limits = gpu.device.limits();
            let vertex_bytes = mesh.positions.len() as u64 * 24;
            let index_bytes = mesh.indices.len() as u64 * 4;
            let max = limits.max_buffer_size;
            if vertex_bytes.max(index_bytes) > max {
                return Err(Error::Limits(format!(
                    "{field} = {:?}: {} triangles need a {}-byte buffer, but {} holds at \
                     most {max} bytes in one buffer; use a simpler mesh",
                    object.mesh,
                    mesh.triangles(),
                    vertex_bytes.max(index_bytes),
                    gpu.info.name
                )));
            }
        }
        meshes.push(mesh);
    }
    Ok((meshes, skins))
}

/// The number of blades a scene asks for (before rounding to whole patches).
pub fn requested_blades(scene: &Scene) -> f64 {
    scene.field.density as f64 * (scene.terrain.size as f64).powi(2)
}

/// Checks that `count` blades fit the adapter's buffers.
pub fn check_blade_count(gpu: &Gpu, count: f64) -> Result<()> {
    let bytes = (count.max(0.0) * std::mem::size_of::<Blade>() as f64).ceil();
    gpu.check_storage(
        &format!("a field of {count:.0} blades"),
        bytes.min(u64::MAX as f64) as u64,
    )
}

impl Session {
    /// For a streamed scene, fills `field` with the pool the GPU holds at the start (the
    /// tiles around the scene's camera, from the generation's CPU twin), so that the CPU
    /// simulation and the dumps have blades to work on. Nothing for other scenes.
    pub fn fill_tiles_cpu(&mut self) -> Result<()> {
        let Some(layout) = &self.tiles else {
            return Ok(());
        };
        let density = DensityMap::from_scene(&self.scene.terrain)
            .map_err(|e| self.scene.image_error("terrain.density_map", e))?;
        let eye = glam::Vec3::from(self.scene.camera.eye);
        let mut pool = crate::field::tiles::generate_pool(
            layout,
            &self.scene.field,
            &self.terrain,
            density.as_ref(),
            eye.x,
            eye.z,
        );
        // The grass grown on mesh objects follows the pool, as in the GPU's buffers.
        let objects = &self.object_grass;
        pool.carried = objects
            .carried
            .shifted(pool.blades.len(), pool.patches.len());
        pool.blades.extend_from_slice(&objects.blades);
        pool.states.extend_from_slice(&objects.states);
        pool.patches.extend_from_slice(&objects.patches);
        self.field = pool;
        Ok(())
    }

    /// One line on the field for the command line: its blades and patches, or for a
    /// streamed field its tiles and pool.
    pub fn describe_field(&self) -> String {
        match &self.tiles {
            Some(l) => format!(
                "field: streamed in tiles of {:.2} m ({} patches of {} blades, {:.0} blades/m²); \
                 pool of {} tiles = {} blades within {} m of the camera",
                l.tile_size(),
                l.patches_per_tile(),
                l.patch_size,
                l.density(),
                l.slots,
                l.pool_blades(),
                l.radius
            ),
            None => format!(
                "field: {} blades in {} patches of {}",
                self.field.blades.len(),
                self.field.patches.len(),
                self.field.patch_size
            ),
        }
    }

    /// Generates the field of `scene`, or with `blades = Some(n)` about `n` blades on a flat
    /// square (tests and checks). `gpu`, when given, vets the count before generation.
    pub fn new(scene: Scene, blades: Option<usize>, gpu: Option<&Gpu>) -> Result<Self> {
        if let Some(n) = blades {
            if n == 0 || n > MAX_BLADES {
                return Err(Error::Invalid(format!(
                    "--blades {n} is out of range: allowed 1..={MAX_BLADES}"
                )));
            }
        }
        let tiles = blades
            .is_none()
            .then(|| TileLayout::from_scene(&scene.field, &scene.terrain, &scene.culling))
            .flatten();
        if let Some(layout) = &tiles {
            check_pool(&scene, layout, gpu)?;
        }
        let count = match (blades, &tiles) {
            (Some(n), _) => n as f64,
            // A streamed field holds the pool whatever the terrain's size.
            (None, Some(layout)) => layout.pool_blades() as f64,
            (None, None) => requested_blades(&scene),
        };
        // Without an adapter (the CPU twin) the field still has to fit in memory and be
        // generated in reasonable time: the same bound as `--blades`.
        if blades.is_none() && count > MAX_BLADES as f64 {
            return Err(scene.error_at(
                "field.density",
                format!(
                    "the scene asks for {count:.0} blades (field.density {} blades/m² × \
                     terrain.size {} m squared); allowed at most {MAX_BLADES}: lower \
                     field.density or terrain.size",
                    scene.field.density, scene.terrain.size
                ),
            ));
        }
        if let Some(gpu) = gpu {
            check_blade_count(gpu, count).map_err(|e| match blades {
                // Counted from the scene: at the line of its density.
                None => scene.error_at("field.density", e.to_string()),
                Some(_) => e,
            })?;
        }
        match blades {
            Some(n) => {
                let (terrain, field) = flat_field(n, &scene.field);
                let mut scene = scene;
                scene.terrain.size = terrain.size;
                scene.terrain.height = crate::scene::HeightSource::Flat;
                // `--blades N` is a whole field of N blades, never a streamed one.
                scene.field.tile_size = 0.0;
                let (meshes, skins) = load_meshes(&scene, gpu)?;
                let packings = rig_packings(&scene, pack_objects(&scene, &meshes), &skins);
                let mut field = field;
                grow_on_objects(&scene, &meshes, &mut field)?;
                if let Some(gpu) = gpu {
                    check_blade_count(gpu, field.blades.len() as f64)?;
                }
                Ok(Self {
                    scene,
                    terrain,
                    field,
                    object_grass: GeneratedField::default(),
                    tiles: None,
                    meshes,
                    skins,
                    packings,
                })
            }
            None => {
                // Image errors name the scene line (or --set) that names the image.
                let terrain = HeightField::from_scene(&scene.terrain)
                    .map_err(|e| scene.image_error("terrain.height.path", e))?;
                let density = DensityMap::from_scene(&scene.terrain)
                    .map_err(|e| scene.image_error("terrain.density_map", e))?;
                let field = match &tiles {
                    Some(layout) => GeneratedField {
                        patch_size: layout.patch_size,
                        ..Default::default()
                    },
                    None => generate(&scene.field, &terrain, density.as_ref()),
                };
                let (meshes, skins) = load_meshes(&scene, gpu)?;
                let packings = rig_packings(&scene, pack_objects(&scene, &meshes), &skins);
                let mut field = field;
                grow_on_objects(&scene, &meshes, &mut field)?;
                if let Some(gpu) = gpu {
                    let pool = tiles.as_ref().map_or(0, |l| l.pool_blades());
                    check_blade_count(gpu, (pool + field.blades.len() as u64) as f64)?;
                }
                let object_grass = if tiles.is_some() {
                    field.clone()
                } else {
                    GeneratedField::default()
                };
                Ok(Self {
                    scene,
                    terrain,
                    field,
                    object_grass,
                    tiles,
                    meshes,
                    skins,
                    packings,
                })
            }
        }
    }
}

/// Checks that a streamed field's pool (the tiles a disk of the blade radius touches) stays
/// within `MAX_POOL_BLADES` and the adapter, before anything is allocated.
fn check_pool(scene: &Scene, layout: &TileLayout, gpu: Option<&Gpu>) -> Result<()> {
    let pool = layout.pool_blades();
    if pool > MAX_POOL_BLADES {
        return Err(scene.error_at(
            "culling.max_distance",
            format!(
                "the streamed field needs a pool of {pool} blades ({} tiles of {} blades \
                 within culling.max_distance = {} m at field.density {} blades/m²); allowed at \
                 most {MAX_POOL_BLADES}: lower culling.max_distance or field.density",
                layout.slots,
                layout.blades_per_tile(),
                scene.culling.max_distance,
                scene.field.density
            ),
        ));
    }
    if let Some(gpu) = gpu {
        check_blade_count(gpu, pool as f64)?;
    }
    Ok(())
}

/// The scene's image errors, raised when the session loads its images (moved here from
/// `scene::origin`: they build a session, a layer above the scene).
#[cfg(test)]
mod image_error_tests {
    use crate::field::grid::tests::png_declaring;
    use crate::scene::{load_scene, load_scene_with_sets, Scene};
    use crate::session::Session;

    /// The error of building the session of `scene` (its terrain and density map).
    fn session_error(scene: Scene) -> String {
        match Session::new(scene, None, None) {
            Err(e) => e.to_string(),
            Ok(_) => panic!("the session should fail"),
        }
    }

    #[test]
    fn image_errors_name_the_scene_line_field_and_image() {
        let dir = std::env::temp_dir().join(format!("sward-origin-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let dir = std::path::absolute(&dir).unwrap();
        std::fs::write(dir.join("huge.png"), png_declaring(100_000, 100_000)).unwrap();
        std::fs::write(dir.join("garbage.png"), b"not a png").unwrap();
        let scene_file = dir.join("scene.ron");
        let load = |density_map: &str| {
            let text = format!(
                "(\n  terrain: (\n    size: 2.0, resolution: 3, height: Flat,\n    \
                 density_map: \"{density_map}\",\n  ),\n  field: (density: 1.0),\n)\n"
            );
            std::fs::write(&scene_file, text).unwrap();
            load_scene(&scene_file).unwrap()
        };
        let at = scene_file.display();
        let image = |name: &str| dir.join(name).display().to_string();

        assert_eq!(
            session_error(load("huge.png")),
            format!(
                "{at}:4:5: terrain.density_map = \"huge.png\": cannot decode {}: declares \
                 100000x100000 pixels; allowed at most 16384x16384",
                image("huge.png")
            )
        );
        let garbage = session_error(load("garbage.png"));
        assert!(
            garbage.starts_with(&format!(
                "{at}:4:5: terrain.density_map = \"garbage.png\": cannot decode {}: ",
                image("garbage.png")
            )),
            "{garbage}"
        );
        let missing = session_error(load("missing.png"));
        assert!(
            missing.starts_with(&format!(
                "{at}:4:5: terrain.density_map = \"missing.png\": cannot read {}: ",
                image("missing.png")
            )),
            "{missing}"
        );

        // The height map, and an image named by --set.
        std::fs::write(&scene_file, "(terrain: (size: 2.0, resolution: 3, height: Png(path: \"huge.png\", scale: 1.0)), field: (density: 1.0))").unwrap();
        let m = session_error(load_scene(&scene_file).unwrap());
        assert!(
            m.starts_with(&format!(
                "{at}:1:50: terrain.height.path = \"huge.png\": cannot decode"
            )),
            "{m}"
        );
        let sets = ["terrain.height=Png(path: \"garbage.png\", scale: 1.0)".to_owned()];
        let m = session_error(load_scene_with_sets(&scene_file, &sets).unwrap());
        assert!(
            m.starts_with(&format!(
                "--set {}: terrain.height = Png(path: \"garbage.png\", scale: 1.0): cannot decode {}",
                sets[0],
                image("garbage.png")
            )),
            "{m}"
        );

        // A scene built in code has no origin: the image error names the image.
        let mut scene = Scene::default();
        scene.terrain.size = 2.0;
        scene.terrain.density_map = Some(image("huge.png"));
        let m = session_error(scene);
        assert!(m.starts_with(&image("huge.png")), "{m}");
        let _ = std::fs::remove_dir_all(&dir);
    }
}
