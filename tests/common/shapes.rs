//! Meshes the tests build themselves: an icosphere with its true normals, and OBJ files of
//! them in a scratch folder.

use glam::Vec3;
use sward::mesh::Mesh;

/// An icosphere of radius 1 subdivided `levels` times, with its true (radial) normals.
pub fn icosphere(levels: u32) -> Mesh {
    let t = (1.0 + 5f32.sqrt()) / 2.0;
    let mut v: Vec<Vec3> = [
        (-1.0, t, 0.0),
        (1.0, t, 0.0),
        (-1.0, -t, 0.0),
        (1.0, -t, 0.0),
        (0.0, -1.0, t),
        (0.0, 1.0, t),
        (0.0, -1.0, -t),
        (0.0, 1.0, -t),
        (t, 0.0, -1.0),
        (t, 0.0, 1.0),
        (-t, 0.0, -1.0),
        (-t, 0.0, 1.0),
    ]
    .iter()
    .map(|&(x, y, z)| Vec3::new(x, y, z).normalize())
    .collect();
    let mut f: Vec<[u32; 3]> = vec![
        [0, 11, 5],
        [0, 5, 1],
        [0, 1, 7],
        [0, 7, 10],
        [0, 10, 11],
        [1, 5, 9],
        [5, 11, 4],
        [11, 10, 2],
        [10, 7, 6],
        [7, 1, 8],
        [3, 9, 4],
        [3, 4, 2],
        [3, 2, 6],
        [3, 6, 8],
        [3, 8, 9],
        [4, 9, 5],
        [2, 4, 11],
        [6, 2, 10],
        [8, 6, 7],
        [9, 8, 1],
    ];
    for _ in 0..levels {
        let mut mid = std::collections::HashMap::new();
        let mut next = Vec::new();
        for tri in &f {
            let m: Vec<u32> = (0..3)
                .map(|k| {
                    let (a, b) = (tri[k], tri[(k + 1) % 3]);
                    *mid.entry((a.min(b), a.max(b))).or_insert_with(|| {
                        v.push(((v[a as usize] + v[b as usize]) * 0.5).normalize());
                        v.len() as u32 - 1
                    })
                })
                .collect();
            next.push([tri[0], m[0], m[2]]);
            next.push([tri[1], m[1], m[0]]);
            next.push([tri[2], m[2], m[1]]);
            next.push([m[0], m[1], m[2]]);
        }
        f = next;
    }
    Mesh {
        positions: v.iter().map(|p| p.to_array()).collect(),
        normals: v.iter().map(|p| p.to_array()).collect(),
        indices: f.concat(),
        degenerate: 0,
    }
}

/// Writes `mesh` as an OBJ file (positions, normals, triangles) into a scratch folder;
/// returns its path.
pub fn write_obj(mesh: &Mesh, name: &str) -> std::path::PathBuf {
    let dir = std::env::temp_dir().join(format!("sward-{name}-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("scratch");
    let path = dir.join(format!("{name}.obj"));
    let mut text = String::new();
    for (p, n) in mesh.positions.iter().zip(&mesh.normals) {
        text += &format!(
            "v {} {} {}\nvn {} {} {}\n",
            p[0], p[1], p[2], n[0], n[1], n[2]
        );
    }
    for t in mesh.indices.chunks_exact(3) {
        text += &format!(
            "f {0}//{0} {1}//{1} {2}//{2}\n",
            t[0] + 1,
            t[1] + 1,
            t[2] + 1
        );
    }
    // Tests of one binary run in parallel and write the same file: each writes its own
    // and renames it into place, so a reader sees a whole file, never one being rewritten
    // (a truncated OBJ read back as "no triangles" in a fresh-clone CI).
    static NEXT: std::sync::atomic::AtomicU64 = std::sync::atomic::AtomicU64::new(0);
    let n = NEXT.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
    let part = dir.join(format!("{name}.obj.{n}.part"));
    std::fs::write(&part, text).expect("write obj");
    std::fs::rename(&part, &path).expect("rename obj");
    path
}
