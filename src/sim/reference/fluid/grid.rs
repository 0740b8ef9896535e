//! Twins of the grid helpers of `shaders/fluid_common.wgsl`: face indexing on the staggered
//! grid, the border rules of each quantity, and the bilinear face stencil. Same names
//! without the `fluid_` prefix; `axis` 0 is u (vertical faces), 1 is v (horizontal faces).

use glam::Vec2;

use crate::scene::Boundary;

/// `fluid_face_index`: u(i, j) at j (n + 1) + i, then v(i, j) at n (n + 1) + j n + i.
pub fn face_index(axis: u32, i: i32, j: i32, n: i32) -> usize {
    if axis == 0 {
        (j * (n + 1) + i) as usize
    } else {
        (n * (n + 1) + j * n + i) as usize
    }
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

/// `fluid_is_wall`: a border face of a closed grid.
pub fn is_wall(axis: u32, i: i32, j: i32, n: i32, boundary: Boundary) -> bool {
    if boundary != Boundary::Closed {
        return false;
    }
    if axis == 0 {
        i == 0 || i == n
    } else {
        j == 0 || j == n
    }
}

/// `fluid_face_ref`: wrapped when periodic, else the nearest stored face of the axis.
pub fn face_ref(axis: u32, i: i32, j: i32, n: i32, boundary: Boundary) -> usize {
    if boundary == Boundary::Periodic {
        return face_index(axis, i.rem_euclid(n), j.rem_euclid(n), n);
    }
    let (ni, nj) = if axis == 1 { (n - 1, n) } else { (n, n - 1) };
    face_index(axis, i.clamp(0, ni), j.clamp(0, nj), n)
}

/// `fluid_face_cells`: the cells below and above a face along its axis.
pub fn face_cells(axis: u32, i: i32, j: i32) -> [(i32, i32); 2] {
    if axis == 0 {
        [(i - 1, j), (i, j)]
    } else {
        [(i, j - 1), (i, j)]
    }
}

/// `fluid_cell_ref`: the cell index, wrapped when periodic; `None` outside other grids.
pub fn cell_ref(i: i32, j: i32, n: i32, boundary: Boundary) -> Option<usize> {
    if boundary == Boundary::Periodic {
        return Some((j.rem_euclid(n) * n + i.rem_euclid(n)) as usize);
    }
    if i < 0 || i >= n || j < 0 || j >= n {
        return None;
    }
    Some((j * n + i) as usize)
}

/// `fluid_face_pos`: where a face lies, in cell units from the grid corner.
pub fn face_pos(axis: u32, i: i32, j: i32) -> Vec2 {
    if axis == 0 {
        Vec2::new(i as f32, j as f32 + 0.5)
    } else {
        Vec2::new(i as f32 + 0.5, j as f32)
    }
}

/// `fluid_stencil`: the four faces of `axis` around `pos` (a, b, d, e) and the weights.
pub fn stencil(axis: u32, pos: Vec2, n: i32, boundary: Boundary) -> ([usize; 4], Vec2) {
    let g = if axis == 1 {
        pos - Vec2::new(0.5, 0.0)
    } else {
        pos - Vec2::new(0.0, 0.5)
    };
    let c = g.floor();
    let (i, j) = (c.x as i32, c.y as i32);
    let index = [
        face_ref(axis, i, j, n, boundary),
        face_ref(axis, i + 1, j, n, boundary),
        face_ref(axis, i, j + 1, n, boundary),
        face_ref(axis, i + 1, j + 1, n, boundary),
    ];
    (index, g - c)
}

/// `fluid_blend`: the bilinear blend in the shader's operation order.
pub fn blend(a: f32, b: f32, d: f32, e: f32, f: Vec2) -> f32 {
    let bottom = a + (b - a) * f.x;
    let top = d + (e - d) * f.x;
    bottom + (top - bottom) * f.y
}

/// `fluid_clamp_pos`: back-traced points stay on closed and open grids.
pub fn clamp_pos(pos: Vec2, n: i32, boundary: Boundary) -> Vec2 {
    if boundary == Boundary::Periodic {
        return pos;
    }
    pos.max(Vec2::ZERO).min(Vec2::splat(n as f32))
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

/// `fluid_scalar_index`: wrapped when periodic, else the nearest edge cell.
pub fn scalar_index(i: i32, j: i32, n: i32, boundary: Boundary) -> usize {
    if boundary == Boundary::Periodic {
        return (j.rem_euclid(n) * n + i.rem_euclid(n)) as usize;
    }
    (j.clamp(0, n - 1) * n + i.clamp(0, n - 1)) as usize
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn faces_are_numbered_u_then_v() {
        let n = 4;
        assert_eq!(face_index(0, 0, 0, n), 0);
        assert_eq!(face_index(0, 4, 3, n), 19);
        assert_eq!(face_index(1, 0, 0, n), 20);
        assert_eq!(face_index(1, 3, 4, n), 39);
    }

    #[test]
    fn borders_clamp_or_wrap_each_lattice() {
        let n = 4;
        // u has n + 1 columns and n rows; clamping keeps the last column.
        assert_eq!(
            face_ref(0, 7, -2, n, Boundary::Open),
            face_index(0, 4, 0, n)
        );
        assert_eq!(
            face_ref(1, 9, 9, n, Boundary::Closed),
            face_index(1, 3, 4, n)
        );
        // Periodic: column n is column 0 again.
        assert_eq!(
            face_ref(0, 4, 5, n, Boundary::Periodic),
            face_index(0, 0, 1, n)
        );
        assert_eq!(canonical(1, 2, 4, n, Boundary::Periodic), (2, 0));
        assert_eq!(canonical(1, 2, 4, n, Boundary::Open), (2, 4));
        assert!(is_wall(0, 4, 1, n, Boundary::Closed));
        assert!(!is_wall(1, 4, 1, n, Boundary::Closed));
        assert!(!is_wall(0, 0, 1, n, Boundary::Open));
        assert_eq!(cell_ref(-1, 0, n, Boundary::Open), None);
        assert_eq!(cell_ref(-1, 0, n, Boundary::Periodic), Some(3));
    }

    #[test]
    fn stencil_at_a_face_reads_that_face() {
        let n = 8;
        let (idx, f) = stencil(0, face_pos(0, 3, 5), n, Boundary::Open);
        assert_eq!(idx[0], face_index(0, 3, 5, n));
        assert_eq!(f, Vec2::ZERO);
        let (idx, f) = stencil(
            1,
            face_pos(1, 2, 7) + Vec2::new(0.25, 0.5),
            n,
            Boundary::Open,
        );
        assert_eq!(
            idx,
            [
                face_index(1, 2, 7, n),
                face_index(1, 3, 7, n),
                face_index(1, 2, 8, n),
                face_index(1, 3, 8, n)
            ]
        );
        assert_eq!(f, Vec2::new(0.25, 0.5));
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
        assert_eq!(scalar_index(-1, 8, n, Boundary::Periodic), 7);
        assert_eq!(scalar_index(8, 3, n, Boundary::Closed), 31);
    }
}
