//! Invalid or awkward meshes, each made to trigger one loading error or repair, for tests of
//! the loader and of everything that reports its errors.

use std::f64::consts::{PI, TAU};

use glam::DVec3;

use super::{Triangles, octahedron, tetrahedron};

/// A Möbius strip of `segments` quads (at least 3), each split in two: one-sided, so
/// [`crate::mesh::Mesh::from_triangles`] fails with `NonOrientable`. Vertices 2i and 2i+1 are
/// the two edges of the strip at angle 2πi/segments; the last quad joins segment
/// `segments − 1` to segment 0 with its sides exchanged.
pub fn mobius_strip(segments: u32) -> Triangles {
    let n = segments.max(3);
    let mut positions = Vec::with_capacity(2 * n as usize);
    for i in 0..n {
        let u = TAU * f64::from(i) / f64::from(n);
        for w in [-0.3, 0.3] {
            // Half a turn of the cross-section over one trip round the centre circle.
            let radial = 1.0 + w * (u / 2.0).cos();
            positions.push(DVec3::new(
                radial * u.cos(),
                radial * u.sin(),
                w * (u / 2.0).sin(),
            ));
        }
    }
    let mut faces = Vec::with_capacity(2 * n as usize);
    for i in 0..n {
        let (a, b) = (2 * i, 2 * i + 1);
        let (c, d) = if i + 1 < n {
            (2 * (i + 1), 2 * (i + 1) + 1)
        } else {
            (1, 0)
        };
        faces.extend([[a, c, d], [a, d, b]]);
    }
    (positions, faces)
}

/// Two triangles that share only vertex 0: a bow-tie, `NonManifoldVertex` at vertex 0 with two
/// fans.
pub fn bow_tie() -> Triangles {
    let positions = vec![
        DVec3::ZERO,
        DVec3::new(1.0, 0.5, 0.0),
        DVec3::new(1.0, -0.5, 0.0),
        DVec3::new(-1.0, -0.5, 0.0),
        DVec3::new(-1.0, 0.5, 0.0),
    ];
    (positions, vec![[0, 1, 4], [0, 2, 3]])
}

/// Three triangles on the edge (0, 1), like pages of a book: `NonManifoldEdge` (0, 1), 3 faces.
pub fn book() -> Triangles {
    let mut positions = vec![DVec3::ZERO, DVec3::Z];
    let mut faces = Vec::new();
    for page in 0..3 {
        let angle = 2.0 * PI / 3.0 * f64::from(page);
        faces.push([0, 1, positions.len() as u32]);
        positions.push(DVec3::new(angle.cos(), angle.sin(), 0.5));
    }
    (positions, faces)
}

/// The [`octahedron`] with face 3 listed clockwise: loading re-orients exactly that face.
pub fn octahedron_with_flipped_face() -> Triangles {
    let (positions, mut faces) = octahedron();
    faces[3].swap(1, 2);
    (positions, faces)
}

/// The [`tetrahedron`] with face 0 listed a second time, in reverse: `DuplicateFace` 4 of 0.
pub fn tetrahedron_with_duplicate_face() -> Triangles {
    let (positions, mut faces) = tetrahedron();
    let [a, b, c] = faces[0];
    faces.push([c, b, a]);
    (positions, faces)
}

/// Two faces, the second with its three corners on the x axis: `DegenerateFace` 1.
pub fn collinear_face() -> Triangles {
    let positions = vec![DVec3::ZERO, DVec3::X, DVec3::Y, DVec3::new(0.5, 0.0, 0.0)];
    (positions, vec![[0, 1, 2], [0, 3, 1]])
}

/// The [`octahedron`] with copies of vertices 0 and 2 appended (as 6 and 7) and used by the
/// odd-numbered faces, plus an unused vertex 8: loading welds 2 vertices, drops 1, and gives
/// back the octahedron exactly.
pub fn octahedron_with_duplicate_vertices() -> Triangles {
    let (mut positions, mut faces) = octahedron();
    positions.extend([positions[0], positions[2], DVec3::new(7.0, 7.0, 7.0)]);
    for face in faces.iter_mut().skip(1).step_by(2) {
        for v in face.iter_mut() {
            match *v {
                0 => *v = 6,
                2 => *v = 7,
                _ => {}
            }
        }
    }
    (positions, faces)
}
