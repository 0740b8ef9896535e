//! Twins of the grid helpers of `shaders/fluid_common.wgsl`: face indexing on the staggered
//! grid (n² cells per layer, `layers` layers), the border rules of each quantity, and the
//! trilinear face stencil. Same names without the `fluid_` prefix; `axis` 0 is u (faces
//! normal to x), 1 is v (normal to z), 2 is w (the horizontal planes, up).

use glam::{IVec3, Vec2, Vec3};

use crate::scene::Boundary;

/// `fluid_face_index`: u(i, j, k) at k U + j (n + 1) + i (U = n (n + 1)), then v(i, j, k) at
/// L U + k U + j n + i, then w(i, j, k) at 2 L U + k n² + j n + i.
pub fn face_index(axis: u32, i: i32, j: i32, k: i32, n: i32, layers: i32) -> usize {
    let per_layer = n * (n + 1);
    (match axis {
        0 => k * per_layer + j * (n + 1) + i,
        1 => layers * per_layer + k * per_layer + j * n + i,
        _ => 2 * layers * per_layer + k * n * n + j * n + i,
    }) as usize
}

/// `fluid_canonical`: on a periodic grid, the last face of an axis is computed as the first.
pub fn canonical(axis: u32, i: i32, j: i32, n: i32, boundary: Boundary) -> (i32, i32) {
    if boundary == Boundary::Periodic {
        if axis == 0 && i == n {
            return (0, j);
        }
        if axis == 1 && j == n {
            return (i, 0);
        }
    }
    (i, j)
}

/// `fluid_is_wall`: a border face of a closed grid, the ground or the top.
pub fn is_wall(axis: u32, i: i32, j: i32, k: i32, n: i32, layers: i32, boundary: Boundary) -> bool {
    if axis == 2 {
        return k == 0 || k == layers;
    }
    if boundary != Boundary::Closed {
        return false;
    }
    if axis == 0 {
        i == 0 || i == n
    } else {
        j == 0 || j == n
    }
}

/// `fluid_face_ref`: wrapped in x, z when periodic, else the nearest stored face of the axis.
pub fn face_ref(
    axis: u32,
    i: i32,
    j: i32,
    k: i32,
    n: i32,
    layers: i32,
    boundary: Boundary,
) -> usize {
    let nk = if axis == 2 { layers } else { layers - 1 };
    let kk = k.clamp(0, nk);
    if boundary == Boundary::Periodic {
        return face_index(axis, i.rem_euclid(n), j.rem_euclid(n), kk, n, layers);
    }
    let ni = if axis == 0 { n } else { n - 1 };
    let nj = if axis == 1 { n } else { n - 1 };
    face_index(axis, i.clamp(0, ni), j.clamp(0, nj), kk, n, layers)
}

/// `fluid_face_cells`: the cells below and above a face along its axis.
pub fn face_cells(axis: u32, i: i32, j: i32, k: i32) -> [IVec3; 2] {
    match axis {
        0 => [IVec3::new(i - 1, j, k), IVec3::new(i, j, k)],
        1 => [IVec3::new(i, j - 1, k), IVec3::new(i, j, k)],
        _ => [IVec3::new(i, j, k - 1), IVec3::new(i, j, k)],
    }
}

/// `fluid_cell_ref`: the cell index, wrapped in x, z when periodic; `None` below the ground,
/// above the top and outside other grids.
pub fn cell_ref(c: IVec3, n: i32, layers: i32, boundary: Boundary) -> Option<usize> {
    if c.z < 0 || c.z >= layers {
        return None;
    }
    if boundary == Boundary::Periodic {
        return Some((c.z * n * n + c.y.rem_euclid(n) * n + c.x.rem_euclid(n)) as usize);
    }
    if c.x < 0 || c.x >= n || c.y < 0 || c.y >= n {
        return None;
    }
    Some((c.z * n * n + c.y * n + c.x) as usize)
}

/// `fluid_face_pos`: where a face lies, in cell units (x, z, height) from the grid corner.
pub fn face_pos(axis: u32, i: i32, j: i32, k: i32) -> Vec3 {
    let (i, j, k) = (i as f32, j as f32, k as f32);
    match axis {
        0 => Vec3::new(i, j + 0.5, k + 0.5),
        1 => Vec3::new(i + 0.5, j, k + 0.5),
        _ => Vec3::new(i + 0.5, j + 0.5, k),
    }
}

/// `fluid_stencil`: the eight faces of `axis` around `pos` (a, b, d, e in layer k, then in
/// k + 1) and the weights.
pub fn stencil(
    axis: u32,
    pos: Vec3,
    n: i32,
    layers: i32,
    boundary: Boundary,
) -> ([usize; 8], Vec3) {
    let g = match axis {
        0 => pos - Vec3::new(0.0, 0.5, 0.5),
        1 => pos - Vec3::new(0.5, 0.0, 0.5),
        _ => pos - Vec3::new(0.5, 0.5, 0.0),
    };
    let c = g.floor();
    let (i, j, k) = (c.x as i32, c.y as i32, c.z as i32);
    let r = |i, j, k| face_ref(axis, i, j, k, n, layers, boundary);
    let index = [
        r(i, j, k),
        r(i + 1, j, k),
        r(i, j + 1, k),
        r(i + 1, j + 1, k),
        r(i, j, k + 1),
        r(i + 1, j, k + 1),
        r(i, j + 1, k + 1),
        r(i + 1, j + 1, k + 1),
    ];
    (index, g - c)
}

/// `fluid_blend`: the bilinear blend in the shader's operation order.
pub fn blend(a: f32, b: f32, d: f32, e: f32, f: Vec2) -> f32 {
    let bottom = a + (b - a) * f.x;
    let top = d + (e - d) * f.x;
    bottom + (top - bottom) * f.y
}

/// `fluid_blend3`: bilinear in each layer, then linear between them.
pub fn blend3(v: [f32; 8], f: Vec3) -> f32 {
    let lo = blend(v[0], v[1], v[2], v[3], Vec2::new(f.x, f.y));
    let hi = blend(v[4], v[5], v[6], v[7], Vec2::new(f.x, f.y));
    lo + (hi - lo) * f.z
}

/// `fluid_clamp_pos`: back-traced points stay on closed and open grids, and between the
/// ground and the top.
pub fn clamp_pos(pos: Vec3, n: i32, layers: i32, boundary: Boundary) -> Vec3 {
    let y = pos.z.clamp(0.0, layers as f32);
    if boundary == Boundary::Periodic {
        return Vec3::new(pos.x, pos.y, y);
    }
    let xz = Vec2::new(pos.x, pos.y)
        .max(Vec2::ZERO)
        .min(Vec2::splat(n as f32));
    Vec3::new(xz.x, xz.y, y)
}

/// `fluid_velocity_ref`: the cell to read the cell-centred velocity of (i, j) from, and the
/// sign to multiply it by (closed: mirrored across the wall; open: the edge cell; periodic:
/// wrapped).
pub fn velocity_ref(i: i32, j: i32, n: i32, boundary: Boundary) -> (i32, i32, Vec2) {
    if boundary == Boundary::Periodic {
        return (i.rem_euclid(n), j.rem_euclid(n), Vec2::ONE);
    }
    let mut sign = Vec2::ONE;
    if boundary == Boundary::Closed {
        if i < 0 || i >= n {
            sign.x = -1.0;
        }
        if j < 0 || j >= n {
            sign.y = -1.0;
        }
    }
    (i.clamp(0, n - 1), j.clamp(0, n - 1), sign)
}

/// `fluid_scalar_index`: wrapped when periodic, else the nearest edge cell, in layer k.
pub fn scalar_index(i: i32, j: i32, k: i32, n: i32, boundary: Boundary) -> usize {
    let base = k * n * n;
    if boundary == Boundary::Periodic {
        return (base + j.rem_euclid(n) * n + i.rem_euclid(n)) as usize;
    }
    (base + j.clamp(0, n - 1) * n + i.clamp(0, n - 1)) as usize
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn faces_are_numbered_u_then_v_then_w() {
        let n = 4;
        assert_eq!(face_index(0, 0, 0, 0, n, 1), 0);
        assert_eq!(face_index(0, 4, 3, 0, n, 1), 19);
        assert_eq!(face_index(1, 0, 0, 0, n, 1), 20);
        assert_eq!(face_index(1, 3, 4, 0, n, 1), 39);
        assert_eq!(face_index(2, 0, 0, 0, n, 1), 40);
        // Two layers: u of layer 1 after u of layer 0, v after all u, w after all v.
        assert_eq!(face_index(0, 0, 0, 1, n, 2), 20);
        assert_eq!(face_index(1, 0, 0, 0, n, 2), 40);
        assert_eq!(face_index(1, 0, 0, 1, n, 2), 60);
        assert_eq!(face_index(2, 1, 0, 2, n, 2), 80 + 32 + 1);
    }

    #[test]
    fn borders_clamp_or_wrap_each_lattice() {
        let n = 4;
        // u has n + 1 columns and n rows; clamping keeps the last column.
        assert_eq!(
            face_ref(0, 7, -2, 0, n, 1, Boundary::Open),
            face_index(0, 4, 0, 0, n, 1)
        );
        assert_eq!(
            face_ref(1, 9, 9, 0, n, 1, Boundary::Closed),
            face_index(1, 3, 4, 0, n, 1)
        );
        // Periodic: column n is column 0 again; layers clamp (no wrap in height).
        assert_eq!(
            face_ref(0, 4, 5, 3, n, 2, Boundary::Periodic),
            face_index(0, 0, 1, 1, n, 2)
        );
        assert_eq!(
            face_ref(2, 1, 1, 5, n, 2, Boundary::Periodic),
            face_index(2, 1, 1, 2, n, 2)
        );
        assert_eq!(canonical(1, 2, 4, n, Boundary::Periodic), (2, 0));
        assert_eq!(canonical(1, 2, 4, n, Boundary::Open), (2, 4));
        assert!(is_wall(0, 4, 1, 0, n, 1, Boundary::Closed));
        assert!(!is_wall(1, 4, 1, 0, n, 1, Boundary::Closed));
        assert!(!is_wall(0, 0, 1, 0, n, 1, Boundary::Open));
        // The ground and the top are walls on every grid.
        assert!(is_wall(2, 1, 1, 0, n, 3, Boundary::Periodic));
        assert!(is_wall(2, 1, 1, 3, n, 3, Boundary::Open));
        assert!(!is_wall(2, 1, 1, 2, n, 3, Boundary::Open));
        assert_eq!(cell_ref(IVec3::new(-1, 0, 0), n, 1, Boundary::Open), None);
        assert_eq!(
            cell_ref(IVec3::new(-1, 0, 0), n, 1, Boundary::Periodic),
            Some(3)
        );
        assert_eq!(
            cell_ref(IVec3::new(0, 0, 2), n, 2, Boundary::Periodic),
            None
        );
    }

    #[test]
    fn stencil_at_a_face_reads_that_face() {
        let n = 8;
        let (idx, f) = stencil(0, face_pos(0, 3, 5, 0), n, 1, Boundary::Open);
        assert_eq!(idx[0], face_index(0, 3, 5, 0, n, 1));
        assert_eq!(f, Vec3::ZERO);
        let (idx, f) = stencil(
            1,
            face_pos(1, 2, 7, 0) + Vec3::new(0.25, 0.5, 0.0),
            n,
            1,
            Boundary::Open,
        );
        assert_eq!(
            idx[..4],
            [
                face_index(1, 2, 7, 0, n, 1),
                face_index(1, 3, 7, 0, n, 1),
                face_index(1, 2, 8, 0, n, 1),
                face_index(1, 3, 8, 0, n, 1)
            ]
        );
        // One layer: the upper four are the lower four again.
        assert_eq!(idx[..4], idx[4..]);
        assert_eq!(f, Vec3::new(0.25, 0.5, 0.0));
        // A w face between layers 1 and 2 of a 3-layer grid, a quarter layer up.
        let (idx, f) = stencil(
            2,
            face_pos(2, 1, 1, 1) + Vec3::new(0.0, 0.0, 0.25),
            n,
            3,
            Boundary::Open,
        );
        assert_eq!(idx[0], face_index(2, 1, 1, 1, n, 3));
        assert_eq!(idx[4], face_index(2, 1, 1, 2, n, 3));
        assert_eq!(f, Vec3::new(0.0, 0.0, 0.25));
    }

    #[test]
    fn closed_border_mirrors_the_normal_component() {
        let n = 8;
        assert_eq!(velocity_ref(3, 4, n, Boundary::Closed), (3, 4, Vec2::ONE));
        assert_eq!(
            velocity_ref(-1, 2, n, Boundary::Closed),
            (0, 2, Vec2::new(-1.0, 1.0))
        );
        assert_eq!(
            velocity_ref(5, 8, n, Boundary::Closed),
            (5, 7, Vec2::new(1.0, -1.0))
        );
        assert_eq!(velocity_ref(-1, 2, n, Boundary::Open), (0, 2, Vec2::ONE));
        assert_eq!(
            velocity_ref(8, -1, n, Boundary::Periodic),
            (0, 7, Vec2::ONE)
        );
        assert_eq!(scalar_index(-1, 8, 0, n, Boundary::Periodic), 7);
        assert_eq!(scalar_index(8, 3, 0, n, Boundary::Closed), 31);
        assert_eq!(scalar_index(8, 3, 1, n, Boundary::Closed), 95);
    }
}
