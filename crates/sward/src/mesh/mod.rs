//! Triangle meshes from files: OBJ through `tobj` and glTF 2.0 / GLB through `gltf` (both
//! well-kept readers of their formats). Every mesh is checked before anything reaches the
//! GPU: a readable file, at least one triangle, finite vertices, indices in range and at
//! most [`MAX_TRIANGLES`]; degenerate triangles (zero area) are dropped and counted. The
//! normals are area-weighted vertex normals, so any mesh is lit smoothly whether or not
//! its file carries normals.

use std::path::Path;

use glam::Vec3;

use crate::error::{Error, Result};

pub mod figure;
pub mod pack;
pub mod skin;

/// Most triangles a mesh may hold (10 M: 120 MB of indices, far past any grass prop).
pub const MAX_TRIANGLES: usize = 10_000_000;

/// A triangle mesh in its file's units.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Mesh {
    /// Vertex positions, in the file's units.
    pub positions: Vec<[f32; 3]>,
    /// Unit vertex normals, area-weighted, one per position.
    pub normals: Vec<[f32; 3]>,
    /// Three per triangle, counter-clockwise seen from outside.
    pub indices: Vec<u32>,
    /// Triangles of the file left out because their area is zero.
    pub degenerate: usize,
}

impl Mesh {
    /// Number of triangles (a third of `indices`).
    pub fn triangles(&self) -> usize {
        self.indices.len() / 3
    }

    /// The smallest box holding every vertex.
    pub fn bounds(&self) -> (Vec3, Vec3) {
        self.positions.iter().fold(
            (Vec3::splat(f32::INFINITY), Vec3::splat(f32::NEG_INFINITY)),
            |(lo, hi), p| (lo.min(Vec3::from(*p)), hi.max(Vec3::from(*p))),
        )
    }
}

fn fail(path: &Path, message: impl Into<String>) -> Error {
    Error::Mesh {
        path: path.to_path_buf(),
        message: message.into(),
    }
}

/// Reads and checks the mesh at `path` (`.obj`, `.gltf` or `.glb`).
pub fn load(path: &Path) -> Result<Mesh> {
    let ext = path
        .extension()
        .and_then(|e| e.to_str())
        .map(str::to_ascii_lowercase);
    if !path.is_file() {
        let source = std::fs::metadata(path)
            .err()
            .unwrap_or_else(|| std::io::Error::other("not a regular file"));
        return Err(Error::Read {
            path: path.to_path_buf(),
            source,
        });
    }
    let (positions, indices) = match ext.as_deref() {
        Some("obj") => read_obj(path)?,
        Some("gltf" | "glb") => read_gltf(path)?,
        _ => return Err(fail(path, "not a .obj, .gltf or .glb file")),
    };
    build(path, positions, indices)
}

fn read_obj(path: &Path) -> Result<(Vec<[f32; 3]>, Vec<u32>)> {
    let options = tobj::LoadOptions {
        triangulate: true,
        single_index: true,
        ..Default::default()
    };
    let (models, _) = tobj::load_obj(path, &options).map_err(|e| {
        // tobj says what kind of line it could not parse, not which: find it.
        let text = std::fs::read_to_string(path).unwrap_or_default();
        match first_bad_obj_line(&text) {
            Some((line, content)) => fail(path, format!("line {line} ({content:?}): {e}")),
            None => fail(path, e.to_string()),
        }
    })?;
    let mut positions = Vec::new();
    let mut indices = Vec::new();
    for m in models {
        let base = positions.len() as u64;
        for p in m.mesh.positions.chunks_exact(3) {
            positions.push([p[0], p[1], p[2]]);
        }
        for &i in &m.mesh.indices {
            let i = base + u64::from(i);
            indices.push(u32::try_from(i).map_err(|_| fail(path, "more than 4 G vertices"))?);
        }
    }
    Ok((positions, indices))
}

/// The first `v` or `f` line of an OBJ text whose numbers do not parse (1-based line
/// number and its text).
fn first_bad_obj_line(text: &str) -> Option<(usize, String)> {
    for (k, line) in text.lines().enumerate() {
        let mut words = line.split_whitespace();
        let bad = match words.next() {
            Some("v") => {
                let n: Vec<_> = words.map(str::parse::<f32>).collect();
                n.len() < 3 || n.iter().any(|r| r.is_err())
            }
            Some("f") => {
                let n: Vec<_> = words
                    .map(|w| w.split('/').next().unwrap_or("").parse::<i64>())
                    .collect();
                n.len() < 3 || n.iter().any(|r| r.is_err())
            }
            _ => false,
        };
        if bad {
            return Some((k + 1, line.trim().chars().take(60).collect()));
        }
    }
    None
}

fn read_gltf(path: &Path) -> Result<(Vec<[f32; 3]>, Vec<u32>)> {
    let gltf::Gltf {
        document: doc,
        blob,
    } = gltf::Gltf::open(path).map_err(|e| fail(path, e.to_string()))?;
    let base = path.parent().unwrap_or_else(|| Path::new("."));
    let buffers = read_gltf_buffers(path, base, &doc, blob)?;
    let roots = gltf_roots(path, &doc)?;
    // The node graph is a forest (checked above), so the walk visits each node once; the
    // triangles are counted before any is expanded.
    let mut placed = Vec::new();
    let mut stack: Vec<(gltf::Node, glam::Mat4)> = roots
        .into_iter()
        .map(|n| (n, glam::Mat4::IDENTITY))
        .collect();
    let mut triangles = 0usize;
    while let Some((node, parent)) = stack.pop() {
        let m = parent * glam::Mat4::from_cols_array_2d(&node.transform().matrix());
        stack.extend(node.children().map(|c| (c, m)));
        let Some(mesh) = node.mesh() else { continue };
        for prim in mesh.primitives() {
            if prim.mode() != gltf::mesh::Mode::Triangles {
                continue;
            }
            let Some(pos) = prim.get(&gltf::Semantic::Positions) else {
                continue;
            };
            // An accessor past the end of its data is named before anything is read.
            let reader = prim.reader(|b| buffers.get(b.index()).map(|d| &d[..]));
            let past_end = |attribute: &str, accessor: usize| {
                fail(
                    path,
                    format!(
                        "mesh {} primitive {}: accessor {accessor} ({attribute}) runs past \
                         the end of its buffer view or buffer",
                        mesh.index(),
                        prim.index()
                    ),
                )
            };
            if reader.read_positions().is_none() {
                return Err(past_end("POSITION", pos.index()));
            }
            if let (Some(a), None) = (prim.indices(), reader.read_indices()) {
                return Err(past_end("indices", a.index()));
            }
            let count = prim.indices().map_or(pos.count(), |a| a.count());
            triangles = triangles.saturating_add(count / 3);
            if triangles > MAX_TRIANGLES {
                return Err(fail(
                    path,
                    format!(
                        "the scene's meshes, placed by their nodes, hold more than \
                         {MAX_TRIANGLES} triangles (the most allowed)"
                    ),
                ));
            }
            placed.push((m, mesh.index(), prim.index()));
        }
    }
    let mut positions = Vec::new();
    let mut indices = Vec::new();
    for (m, mesh_index, prim_index) in placed {
        let Some(prim) = doc
            .meshes()
            .nth(mesh_index)
            .and_then(|mesh| mesh.primitives().nth(prim_index))
        else {
            continue;
        };
        let reader = prim.reader(|b| buffers.get(b.index()).map(|d| &d[..]));
        // Checked readable in the walk above.
        let Some(ps) = reader.read_positions() else {
            continue;
        };
        let base =
            u32::try_from(positions.len()).map_err(|_| fail(path, "more than 4 G vertices"))?;
        let count = ps.len() as u32;
        positions.extend(ps.map(|p| m.transform_point3(p.into()).to_array()));
        match reader.read_indices() {
            Some(ix) => indices.extend(ix.into_u32().map(|i| base + i.min(count))),
            None => indices.extend(base..base + count - count % 3),
        }
    }
    Ok((positions, indices))
}

/// The document's buffers: the GLB's binary chunk, embedded data and external files, each
/// external file checked first so that a missing one is named (not the `.gltf`).
pub(super) fn read_gltf_buffers(
    path: &Path,
    base: &Path,
    doc: &gltf::Document,
    blob: Option<Vec<u8>>,
) -> Result<Vec<Vec<u8>>> {
    for buffer in doc.buffers() {
        if let gltf::buffer::Source::Uri(uri) = buffer.source() {
            if uri.starts_with("data:") {
                continue;
            }
            if uri.contains("://") {
                return Err(fail(
                    path,
                    format!(
                        "buffer {} is at {uri:?}: only files beside the .gltf can be read",
                        buffer.index()
                    ),
                ));
            }
            let file = base.join(percent_decode(uri));
            if let Err(source) = std::fs::metadata(&file).and_then(|m| {
                if m.is_file() {
                    Ok(())
                } else {
                    Err(std::io::Error::other("not a regular file"))
                }
            }) {
                return Err(Error::Read { path: file, source })
                    .map_err(|e| fail(path, format!("buffer {}: {e}", buffer.index())));
            }
        }
    }
    let data =
        gltf::import_buffers(doc, Some(base), blob).map_err(|e| fail(path, e.to_string()))?;
    Ok(data.into_iter().map(|d| d.0).collect())
}

/// `%XX` escapes of a glTF URI decoded (file names with spaces are written `%20`).
fn percent_decode(uri: &str) -> String {
    let bytes = uri.as_bytes();
    let mut out = Vec::with_capacity(bytes.len());
    let mut k = 0;
    while k < bytes.len() {
        let hex = |b: u8| (b as char).to_digit(16);
        match (
            bytes[k],
            bytes.get(k + 1).copied().and_then(hex),
            bytes.get(k + 2).copied().and_then(hex),
        ) {
            (b'%', Some(h), Some(l)) => {
                out.push((h * 16 + l) as u8);
                k += 3;
            }
            (b, _, _) => {
                out.push(b);
                k += 1;
            }
        }
    }
    String::from_utf8_lossy(&out).into_owned()
}

/// The nodes a walk starts from (the default scene's, else the first scene's, else every
/// node without a parent), after checking that the node graph is a forest: no node is the
/// child of two nodes or its own ancestor. glTF requires this, and a file that breaks it
/// would otherwise make the walk loop or expand without bound.
pub(super) fn gltf_roots<'a>(path: &Path, doc: &'a gltf::Document) -> Result<Vec<gltf::Node<'a>>> {
    let n = doc.nodes().len();
    let mut parent: Vec<Option<usize>> = vec![None; n];
    for node in doc.nodes() {
        for child in node.children() {
            let c = child.index();
            if let Some(p) = parent[c] {
                return Err(fail(
                    path,
                    format!(
                        "node {c} is a child of both node {p} and node {}: the node graph \
                         must be a tree",
                        node.index()
                    ),
                ));
            }
            parent[c] = Some(node.index());
        }
    }
    // With one parent each, a cycle is a chain of parents that comes back to its start.
    for start in 0..n {
        let mut at = start;
        for _ in 0..=n {
            match parent[at] {
                Some(p) if p == start => {
                    return Err(fail(
                        path,
                        format!("node {start} is its own ancestor: the node graph must be a tree"),
                    ))
                }
                Some(p) => at = p,
                None => break,
            }
        }
    }
    let scene = doc.default_scene().or_else(|| doc.scenes().next());
    Ok(match scene {
        Some(s) => {
            let mut seen = vec![false; n];
            let mut roots = Vec::new();
            for node in s.nodes() {
                if parent[node.index()].is_some() {
                    return Err(fail(
                        path,
                        format!(
                            "scene {} lists node {} as a root, but it is a child of node {}",
                            s.index(),
                            node.index(),
                            parent[node.index()].unwrap_or_default()
                        ),
                    ));
                }
                if !std::mem::replace(&mut seen[node.index()], true) {
                    roots.push(node);
                }
            }
            roots
        }
        None => doc
            .nodes()
            .filter(|n| parent[n.index()].is_none())
            .collect(),
    })
}

/// Checks the raw mesh and computes its normals.
fn build(path: &Path, positions: Vec<[f32; 3]>, raw: Vec<u32>) -> Result<Mesh> {
    if let Some(k) = positions
        .iter()
        .position(|p| p.iter().any(|c| !c.is_finite()))
    {
        return Err(fail(
            path,
            format!(
                "vertex {} is not finite ({:?}): every coordinate must be a number",
                k + 1,
                positions[k]
            ),
        ));
    }
    if raw.len() / 3 > MAX_TRIANGLES {
        return Err(fail(
            path,
            format!(
                "{} triangles: at most {MAX_TRIANGLES} are allowed",
                raw.len() / 3
            ),
        ));
    }
    let n = positions.len();
    let mut indices = Vec::with_capacity(raw.len());
    let mut degenerate = 0;
    for (t, tri) in raw.chunks_exact(3).enumerate() {
        if let Some(&bad) = tri.iter().find(|&&i| i as usize >= n) {
            return Err(fail(
                path,
                format!(
                    "triangle {} names vertex {} of {n}",
                    t + 1,
                    bad as usize + 1
                ),
            ));
        }
        let [a, b, c] = [tri[0], tri[1], tri[2]].map(|i| Vec3::from(positions[i as usize]));
        if (b - a).cross(c - a).length_squared() <= f32::MIN_POSITIVE {
            degenerate += 1;
            continue;
        }
        indices.extend_from_slice(tri);
    }
    if indices.is_empty() {
        let message = if degenerate > 0 {
            format!("all {degenerate} triangles have zero area")
        } else {
            "no triangles".to_string()
        };
        return Err(fail(path, message));
    }
    let mut normals = vec![Vec3::ZERO; n];
    for tri in indices.chunks_exact(3) {
        let [a, b, c] = [tri[0], tri[1], tri[2]].map(|i| Vec3::from(positions[i as usize]));
        // Unnormalised: the cross product's length weighs each face by its area.
        let face = (b - a).cross(c - a);
        for &i in tri {
            normals[i as usize] += face;
        }
    }
    Ok(Mesh {
        positions,
        normals: normals
            .iter()
            .map(|v| v.try_normalize().unwrap_or(Vec3::Y).to_array())
            .collect(),
        indices,
        degenerate,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn write(name: &str, text: &str) -> std::path::PathBuf {
        let dir = std::env::temp_dir().join(format!("sward-mesh-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let p = dir.join(name);
        std::fs::write(&p, text).unwrap();
        p
    }

    #[test]
    fn the_shipped_bunny_loads_with_smooth_normals() {
        let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../assets/models/bunny.obj");
        let m = load(&path).unwrap();
        assert_eq!(m.positions.len(), 1839);
        assert!(m.triangles() + m.degenerate == 3674 && m.triangles() > 3600);
        for n in &m.normals {
            assert!((Vec3::from(*n).length() - 1.0).abs() < 1e-4);
        }
        let (lo, hi) = m.bounds();
        assert!(lo.y > -0.01 && hi.y > 9.0, "{lo} {hi}");
        // Closed and outward: the normals of the top vertices point up.
        let top = m
            .positions
            .iter()
            .zip(&m.normals)
            .max_by(|a, b| a.0[1].total_cmp(&b.0[1]))
            .unwrap();
        assert!(top.1[1] > 0.5, "top normal {:?}", top.1);
    }

    #[test]
    fn bad_meshes_are_refused_with_what_is_wrong() {
        let err = |name: &str, text: &str| load(&write(name, text)).unwrap_err().to_string();
        let e = err("bad.obj", "v 0 0 0\nv 1 0 0\nv 0 x 1\nf 1 2 3\n");
        assert!(
            e.contains("bad.obj: cannot load mesh: line 3 (\"v 0 x 1\")"),
            "{e}"
        );
        let e = err("none.obj", "v 0 0 0\nv 1 0 0\n");
        assert!(
            e.contains("none.obj: cannot load mesh: no triangles"),
            "{e}"
        );
        let e = err("flat.obj", "v 0 0 0\nv 1 0 0\nv 2 0 0\nf 1 2 3\n");
        assert!(e.contains("all 1 triangles have zero area"), "{e}");
        let e = err("nan.obj", "v 0 0 0\nv 1 0 0\nv 0 NaN 1\nf 1 2 3\n");
        assert!(e.contains("vertex 3 is not finite"), "{e}");
        let e = err("mesh.stl", "solid");
        assert!(e.contains("not a .obj, .gltf or .glb file"), "{e}");
        let e = load(Path::new("/nonexistent/rock.obj"))
            .unwrap_err()
            .to_string();
        assert!(e.contains("cannot read /nonexistent/rock.obj"), "{e}");
        let e = err("broken.glb", "glTF not really");
        assert!(e.contains("broken.glb: cannot load mesh:"), "{e}");
    }

    #[test]
    fn a_gltf_triangle_loads() {
        // A minimal glTF 2.0 file: one triangle, positions in an embedded base64 buffer.
        let positions: Vec<f32> = vec![0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0, 0.0];
        let bytes: Vec<u8> = positions.iter().flat_map(|f| f.to_le_bytes()).collect();
        let b64 = super::figure::base64(&bytes);
        let text = format!(
            r#"{{"asset":{{"version":"2.0"}},"scene":0,"scenes":[{{"nodes":[0]}}],
            "nodes":[{{"mesh":0,"translation":[0,0,2]}}],
            "meshes":[{{"primitives":[{{"attributes":{{"POSITION":0}}}}]}}],
            "accessors":[{{"bufferView":0,"componentType":5126,"count":3,"type":"VEC3",
              "min":[0,0,0],"max":[1,1,0]}}],
            "bufferViews":[{{"buffer":0,"byteLength":36}}],
            "buffers":[{{"byteLength":36,"uri":"data:application/octet-stream;base64,{b64}"}}]}}"#
        );
        let m = load(&write("tri.gltf", &text)).unwrap();
        assert_eq!(m.triangles(), 1);
        // The node's translation is applied.
        assert_eq!(m.positions[1], [1.0, 0.0, 2.0]);
        assert_eq!(m.normals[0], [0.0, 0.0, 1.0]);
    }
}
