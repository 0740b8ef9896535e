//! The ranges and checks of the scene's mesh objects (`objects`): a mesh file named (and
//! made relative to the scene file's directory), a finite placement, a scale that keeps
//! the mesh within the world's coordinates and a colour in 0..=1. The file itself is read
//! and checked when the session loads it (`crate::mesh`).

use super::allowed::{Allowed, Rule};
use super::objects::POSITION;
use super::{tuple3, Checker};
use crate::error::Result;
use crate::scene::types::MeshObject;

/// Turns of at most a full circle either way (more says the same with a larger number).
const ANGLE: Allowed = Allowed::closed(-360.0, 360.0, "degrees");
/// From millimetre models to kilometre ones.
const SCALE: Allowed = Allowed::closed(0.001, 1000.0, "");
const COLOR: Allowed = Allowed::closed(0.0, 1.0, "");

/// The rules of every object value.
pub(super) const RULES: &[(&str, Rule)] = &[
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
];

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
    check.vector(&at("translation"), &tuple3(object.translation), POSITION)?;
    check.vector(&at("rotation"), &tuple3(object.rotation), ANGLE)?;
    check.real(&at("scale"), object.scale, SCALE)?;
    check.vector(&at("color"), &tuple3(object.color), COLOR)
}
