//! The ranges and checks of the scene's mesh objects (`objects`): a mesh file named (and
//! made relative to the scene file's directory), a finite placement, a scale that keeps
//! the mesh within the world's coordinates and a colour in 0..=1. The file itself is read
//! and checked when the session loads it (`crate::mesh`).

use super::allowed::{Allowed, Integers, Rule};
use super::objects::{motion, motion_rules, POSITION};
use super::{tuple3, Checker};
use crate::error::Result;
use crate::scene::limits::MAX_SPHERES;
use crate::scene::types::MeshObject;

/// Turns of at most a full circle either way (more says the same with a larger number).
const ANGLE: Allowed = Allowed::closed(-360.0, 360.0, "degrees");
/// From millimetre models to kilometre ones.
const SCALE: Allowed = Allowed::closed(0.001, 1000.0, "");
const COLOR: Allowed = Allowed::closed(0.0, 1.0, "");
/// A rolling object's radius (`translation.y` with `rolls: true` on a path): it turns by
/// the distance over it, so a radius near zero would spin it without bound (a 1e-45 m
/// radius overflows the angle into NaN transforms).
const ROLL_RADIUS: Allowed = Allowed::closed(0.001, 100000.0, "m");
/// Spheres of one packing: all the update pass takes.
const PACKED: Integers = Integers::new(1, MAX_SPHERES as u64, "spheres");
/// Voxels along the box: 8 resolve a blob, 256 (16 M voxels) any prop.
/// Metres per animation cycle: 0 (the scene's clock) up to a giant's 100 m.
const STRIDE: Allowed = Allowed::closed(0.0, 100.0, "m");
const VOXELS: Integers = Integers::new(8, 256, "voxels");

/// The rules of every object value.
pub(super) const RULES: &[(&str, Rule)] = &{
    let m = motion_rules!("objects[].motion");
    [
    (
        "objects",
        Rule::Text("a list of meshes (mesh: \"file.obj\", translation: .., rotation: .., scale: .., color: ..)"),
    ),
    (
        "objects[]",
        Rule::Text("(mesh: \"file.obj\", translation: .., rotation: .., scale: .., color: ..)"),
    ),
    ("objects[].mesh", Rule::Text("a .obj, .gltf or .glb file")),
    ("objects[].translation", Rule::Vector(POSITION)),
    ("objects[].rotation", Rule::Vector(ANGLE)),
    ("objects[].scale", Rule::Real(SCALE)),
    ("objects[].color", Rule::Vector(COLOR)),
    (
        "objects[].collider",
        Rule::Choice(
            "None, Spheres((count: .., resolution: ..)), Bvh((count: .., resolution: ..)) or \
             Joints (with an animation)",
        ),
    ),
    ("objects[].collider.count", Rule::Integer(PACKED)),
    (
        "objects[].grass",
        Rule::Text("None or Some((density: .., height: (min: .., max: ..), ..)), as field"),
    ),
    ("objects[].collider.resolution", Rule::Integer(VOXELS)),
    ("objects[].stride", Rule::Real(STRIDE)),
    (
        "objects[].animation",
        Rule::Text("None or Some(\"name\"): an animation of the object's .gltf or .glb file"),
    ),
    m[0],
    m[1],
    m[2],
    m[3],
    m[4],
]
};

pub(super) fn object(check: &Checker, i: usize, object: &mut MeshObject) -> Result<()> {
    let at = |name: &str| format!("objects[{i}].{name}");
    let name = at("mesh");
    let lower = object.mesh.to_ascii_lowercase();
    if !(lower.ends_with(".obj") || lower.ends_with(".gltf") || lower.ends_with(".glb")) {
        let message = format!(
            "{name} = {:?} is not a mesh file: name a .obj, .gltf or .glb file",
            object.mesh
        );
        return Err(check.error(&name, message));
    }
    check.file_path(&name, &mut object.mesh, "a .obj, .gltf or .glb file")?;
    if object.collider == crate::scene::MeshCollider::Joints && object.animation.is_none() {
        let field = at("collider");
        let message = format!(
            "{field} = Joints needs a skeleton: give the object an animation of its skinned \
             .gltf or .glb (objects[{i}].animation = Some(\"name\"))"
        );
        return Err(check.error(&field, message));
    }
    if object.animation.is_some() && lower.ends_with(".obj") {
        let field = at("animation");
        let message = format!(
            "{field} = {:?} needs a skinned .gltf or .glb mesh, but {name} is an .obj file",
            object.animation
        );
        return Err(check.error(&field, message));
    }
    check.vector(&at("translation"), &tuple3(object.translation), POSITION)?;
    if object.rolls && matches!(object.motion, crate::scene::Motion::Path { .. }) {
        let field = at("translation");
        let y = object.translation.1;
        if !ROLL_RADIUS.contains(y) {
            let message = format!(
                "{field}: y = {y} is the rolling radius of an object with rolls: true and is \
                 out of range: allowed {}",
                ROLL_RADIUS.describe("y")
            );
            return Err(check.error(&field, message));
        }
    }
    check.vector(&at("rotation"), &tuple3(object.rotation), ANGLE)?;
    check.real(&at("scale"), object.scale, SCALE)?;
    check.vector(&at("color"), &tuple3(object.color), COLOR)?;
    if let Some(p) = object.collider.packing() {
        // The packing's numbers live inside the collider's variant, which `--set` replaces
        // whole: the error names the collider, the number and an assignment that works.
        let field = at("collider");
        for (name, value, allowed) in [
            ("count", p.count, PACKED),
            ("resolution", p.resolution, VOXELS),
        ] {
            if !(allowed.low..=allowed.high).contains(&u64::from(value)) {
                let message = format!(
                    "{field}: {name} = {value} is out of range: allowed {} (set the whole \
                     collider, e.g. {field}=Spheres((count: 400, resolution: 64)))",
                    allowed.describe(name)
                );
                return Err(check.error(&field, message));
            }
        }
    }
    motion(check, &at("motion"), &object.motion)
}

/// Spheres the objects' packings add to the colliders.
pub(super) fn packed_spheres(objects: &[MeshObject]) -> usize {
    objects
        .iter()
        .map(|o| o.collider.packing().map_or(0, |p| p.count as usize))
        .sum()
}
