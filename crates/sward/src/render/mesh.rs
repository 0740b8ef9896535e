//! CPU-built meshes: the terrain grid from the height field, a unit sphere for colliders and
//! the index list of one grass blade (3 columns × `segments + 1` rows).

use bytemuck::{Pod, Zeroable};

use crate::field::HeightField;
use crate::sim::layout::{DRAW_BATCH, LOD_LEVELS};

/// Terrain vertex: position and normal.
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
pub struct TerrainVertex {
    /// World position (m): x, z on the grid centred on the origin, y the terrain height.
    pub position: [f32; 3],
    /// Unit surface normal of the height field at that point.
    pub normal: [f32; 3],
}

/// Vertices and triangle indices of the terrain, one vertex per height sample.
pub fn terrain_mesh(terrain: &HeightField) -> (Vec<TerrainVertex>, Vec<u32>) {
    let n = terrain.resolution.max(2);
    let step = terrain.size / (n - 1) as f32;
    let half = terrain.size * 0.5;
    let mut vertices = Vec::with_capacity((n * n) as usize);
    for j in 0..n {
        for i in 0..n {
            let x = -half + i as f32 * step;
            let z = -half + j as f32 * step;
            let y = terrain.height(x, z);
            vertices.push(TerrainVertex {
                position: [x, y, z],
                normal: terrain.normal(x, z).into(),
            });
        }
    }
    let mut indices = Vec::with_capacity(((n - 1) * (n - 1) * 6) as usize);
    for j in 0..n - 1 {
        for i in 0..n - 1 {
            let a = j * n + i;
            let b = a + 1;
            let c = a + n;
            let d = c + 1;
            indices.extend_from_slice(&[a, c, b, b, c, d]);
        }
    }
    (vertices, indices)
}

/// A unit UV sphere: positions (which are also the normals) and triangle indices.
pub fn sphere_mesh(rings: u32, sectors: u32) -> (Vec<[f32; 3]>, Vec<u32>) {
    let mut vertices = Vec::new();
    for r in 0..=rings {
        let phi = std::f32::consts::PI * r as f32 / rings as f32;
        for s in 0..=sectors {
            let theta = std::f32::consts::TAU * s as f32 / sectors as f32;
            vertices.push([phi.sin() * theta.cos(), phi.cos(), phi.sin() * theta.sin()]);
        }
    }
    let mut indices = Vec::new();
    let row = sectors + 1;
    for r in 0..rings {
        for s in 0..sectors {
            let a = r * row + s;
            let b = a + 1;
            let c = a + row;
            let d = c + 1;
            indices.extend_from_slice(&[a, b, c, b, d, c]);
        }
    }
    (vertices, indices)
}

/// Columns of each level's blade mesh (twin of `lod_columns` in `grass.wgsl`): the finest
/// level keeps the middle axis the 3D displacement folds the blade along (Eq. 23), in two
/// quads per row band; the coarser levels, a few pixels wide, are flat, one quad per band
/// (every blade shape is linear across the width, so only the fold is lost). On llvmpipe
/// the grass draw is bound by the vertices and triangles its one vertex thread handles.
pub const LOD_COLUMNS: [u32; LOD_LEVELS] = [3, 2, 2];

/// Columns of each level's blade mesh for blades that fold (`fold`: the 3D displacement of
/// Eq. 23 on, `GrassSpec::fold`) or not: without the fold the finest level is flat as well.
pub fn lod_columns(fold: bool) -> [u32; LOD_LEVELS] {
    if fold {
        LOD_COLUMNS
    } else {
        [2; LOD_LEVELS]
    }
}

/// Triangle indices of one blade of `columns` (2 or 3) columns: vertex `row * columns +
/// column`, one quad per row band and pair of neighbouring columns.
pub fn blade_indices(segments: u32, columns: u32) -> Vec<u32> {
    let mut indices = Vec::with_capacity((segments * (columns - 1) * 6) as usize);
    for row in 0..segments {
        for col in 0..columns - 1 {
            let a = row * columns + col;
            let b = a + 1;
            let c = a + columns;
            let d = c + 1;
            indices.extend_from_slice(&[a, b, c, b, d, c]);
        }
    }
    indices
}

/// The blade meshes of the levels of detail, one after the other in one index buffer. Each
/// level's mesh is [`DRAW_BATCH`] copies of its blade mesh, copy `b` on vertices
/// `b * vertices_per_blade ..`: one instance draws a batch of blades, and the grass shader
/// splits its vertex index into the blade of the batch and the vertex of the blade.
#[derive(Clone, Debug, PartialEq)]
pub struct LodMeshes {
    /// Segments of each level: the scene's count, about half of it, and one.
    pub segments: [u32; LOD_LEVELS],
    /// Indices of each level's mesh (all [`DRAW_BATCH`] copies of its blade).
    pub index_count: [u32; LOD_LEVELS],
    /// Where each level's indices start in [`LodMeshes::indices`].
    pub first_index: [u32; LOD_LEVELS],
    /// The shadow casters' mesh after the levels: one triangle per blade, its root's two
    /// corners and its tip (3 vertices, [`CASTER_VERTICES`]), as (index count, first).
    pub caster: (u32, u32),
    /// The finest level's flat mesh (two columns) after the casters, for blades that do
    /// not fold, as (index count, first): [`LodMeshes::levels`] draws it in place of the
    /// three-column one.
    pub flat: (u32, u32),
    /// The index buffer: every level's mesh, then the casters' mesh.
    pub indices: Vec<u32>,
}

/// Vertices per blade of the shadow casters' mesh: the root's two corners and the tip.
/// Blades narrow to their tip, so the triangle casts the coarsest level's two-triangle
/// shadow (llvmpipe's shadow pass costs per vertex submitted: a quarter less).
pub const CASTER_VERTICES: u32 = 3;

/// Segments per level of detail for a full mesh of `segments`: every coarser level keeps the
/// root and the tip rows, so all of them lie on the same curve. The coarsest has two
/// segments where the middle level has them (one where it has one): one straight segment
/// cuts the corner of a bent blade's curve, and at a grazing view the prairie's far blades
/// read 3-5 levels brighter than the finest mesh after 32 frames of wind (within 2 with two
/// segments, each mapped onto its half of the curve, `lod_chord`). It costs two vertices
/// and two triangles more per coarse blade.
pub fn lod_segments(segments: u32) -> [u32; LOD_LEVELS] {
    let s = segments.max(1);
    let middle = s.div_ceil(2);
    [s, middle, middle.min(2)]
}

/// Index lists of all levels of detail, concatenated.
pub fn lod_meshes(segments: u32) -> LodMeshes {
    let segments = lod_segments(segments);
    let mut indices = Vec::new();
    let mut index_count = [0; LOD_LEVELS];
    let mut first_index = [0; LOD_LEVELS];
    for (k, &s) in segments.iter().enumerate() {
        first_index[k] = indices.len() as u32;
        indices.extend(batch_indices(s, LOD_COLUMNS[k]));
        index_count[k] = indices.len() as u32 - first_index[k];
    }
    let caster_first = indices.len() as u32;
    for b in 0..DRAW_BATCH {
        indices.extend((0..CASTER_VERTICES).map(|i| i + b * CASTER_VERTICES));
    }
    let caster = (indices.len() as u32 - caster_first, caster_first);
    let flat_first = indices.len() as u32;
    indices.extend(batch_indices(segments[0], lod_columns(false)[0]));
    LodMeshes {
        segments,
        index_count,
        first_index,
        caster,
        flat: (indices.len() as u32 - flat_first, flat_first),
        indices,
    }
}

/// [`DRAW_BATCH`] copies of one blade's indices of `segments` and `columns`, each the one
/// before moved by a blade's vertices.
fn batch_indices(segments: u32, columns: u32) -> Vec<u32> {
    let blade = blade_indices(segments, columns);
    let vertices = (segments + 1) * columns;
    (0..DRAW_BATCH)
        .flat_map(|b| blade.iter().map(move |i| i + b * vertices))
        .collect()
}

impl LodMeshes {
    /// Each level's (index count, first index) for blades that fold or not (`fold`:
    /// `GrassSpec::fold`, the pipelines' `FOLD`): the finest level's flat mesh in place of
    /// its three columns when they do not.
    pub fn levels(&self, fold: bool) -> ([u32; LOD_LEVELS], [u32; LOD_LEVELS]) {
        let (mut count, mut first) = (self.index_count, self.first_index);
        if !fold {
            (count[0], first[0]) = self.flat;
        }
        (count, first)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn blade_indices_cover_every_vertex_of_the_grid() {
        let segments = 5;
        for columns in [2, 3] {
            let idx = blade_indices(segments, columns);
            // Two triangles per row band and pair of neighbouring columns.
            assert_eq!(idx.len(), (segments * (columns - 1) * 6) as usize);
            let max = *idx.iter().max().unwrap();
            assert_eq!(max, (segments + 1) * columns - 1);
            for v in 0..=max {
                assert!(idx.contains(&v), "{columns} columns: vertex {v} unused");
            }
        }
    }

    #[test]
    fn lod_meshes_are_concatenated_and_coarser_each_level() {
        let m = lod_meshes(6);
        let n = DRAW_BATCH;
        assert_eq!(m.segments, [6, 3, 2]);
        // 6 segments of 3 columns, then 3 and 2 of 2 columns (flat).
        assert_eq!(m.index_count, [72 * n, 18 * n, 12 * n]);
        assert_eq!(m.first_index, [0, 72 * n, 90 * n]);
        // The casters' triangles after the levels, one per blade of the batch, then the
        // finest level's flat mesh (6 segments of 2 columns).
        assert_eq!(m.caster, (3 * n, 102 * n));
        assert_eq!(m.flat, (36 * n, 105 * n));
        assert_eq!(m.indices.len() as u32, 141 * n);
        let casters = &m.indices[102 * n as usize..105 * n as usize];
        assert!(casters
            .chunks(3)
            .enumerate()
            .all(|(b, t)| { t == [3 * b as u32, 3 * b as u32 + 1, 3 * b as u32 + 2] }));
        // Vertices per blade: 21, 8, 4 (columns × rows); a batch of blades one after
        // the other, each copy the first one moved by a blade's vertices.
        for (k, columns) in LOD_COLUMNS.into_iter().enumerate() {
            let a = m.first_index[k] as usize;
            let level = &m.indices[a..a + m.index_count[k] as usize];
            let per_blade = (m.segments[k] + 1) * columns;
            assert_eq!(level.iter().max().map(|v| v + 1), Some(per_blade * n));
            let one = level.len() / n as usize;
            for (b, copy) in level.chunks(one).enumerate() {
                for (x, y) in copy.iter().zip(&level[..one]) {
                    assert_eq!(*x, y + b as u32 * per_blade);
                }
            }
        }
        assert_eq!(lod_segments(1), [1, 1, 1]);
        assert_eq!(lod_segments(2), [2, 1, 1]);
        assert_eq!(lod_segments(3), [3, 2, 2]);
        assert_eq!(lod_segments(6), [6, 3, 2]);
    }

    #[test]
    fn blades_that_do_not_fold_draw_a_flat_finest_level() {
        let m = lod_meshes(6);
        let n = DRAW_BATCH as usize;
        assert_eq!(m.levels(true), (m.index_count, m.first_index));
        let (count, first) = m.levels(false);
        assert_eq!(count[1..], m.index_count[1..]);
        assert_eq!(first[1..], m.first_index[1..]);
        assert_eq!((count[0], first[0]), m.flat);
        // Every blade of the batch: the 14 vertices of 7 rows of 2 columns, in 12
        // triangles, each copy the first moved by 14 vertices.
        let flat = &m.indices[first[0] as usize..(first[0] + count[0]) as usize];
        let one = flat.len() / n;
        assert_eq!(one, 36);
        assert_eq!(flat[..one], blade_indices(6, 2)[..]);
        for (b, copy) in flat.chunks(one).enumerate() {
            assert!(copy.iter().zip(&flat[..one]).all(|(x, y)| *x == y + 14 * b as u32));
        }
        assert_eq!(lod_columns(false), [2, 2, 2]);
        assert_eq!(lod_columns(true), LOD_COLUMNS);
    }

    #[test]
    fn sphere_vertices_are_on_the_unit_sphere() {
        let (v, i) = sphere_mesh(8, 12);
        assert!(v
            .iter()
            .all(|p| (glam::Vec3::from(*p).length() - 1.0).abs() < 1e-5));
        assert!(i.iter().all(|&k| (k as usize) < v.len()));
    }
}
