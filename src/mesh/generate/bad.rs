//! Invalid or awkward meshes, each made to trigger one loading error or repair, for tests of
//! the loader and of everything that reports its errors.

use std::f64::consts::{PI, TAU};

use glam::DVec3;

use super::{Triangles, octahedron, tetrahedron};

/// A Möbius strip of `segments` quads (at least 3), each split in two: one-sided, so
/// [`crate::mesh::Mesh::from_triangles`] cuts it open across one edge
/// (`RepairKind::NonOrientableEdgeCut`). Vertices 2i and 2i+1 are
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

/// The [`octahedron`] with a fin on its edge (+X, +Z) (vertices 0 and 4): a face to (1, −1, 1),
/// in the plane of the face (+X, +Y, +Z) and oriented with it. Loading pairs the fin with that
/// face (they continue each other flat) and leaves the edge's third face, (+X, −Y, +Z), on a
/// boundary edge of its own; the vertices 0 and 4 keep one fan each, so the mesh has two
/// edges, one interior and one boundary, between the same two vertices.
pub fn octahedron_with_fin() -> Triangles {
    let (mut positions, mut faces) = octahedron();
    let (a, b) = (0, 4);
    let face = faces
        .iter()
        .find(|f| f.contains(&a) && f.contains(&b) && f.contains(&2))
        .copied()
        .unwrap_or_default();
    // The face runs the edge from face[c] to face[c + 1]; the fin runs it the other way.
    let c = (0..3)
        .find(|&c| {
            [face[c], face[(c + 1) % 3]]
                .iter()
                .all(|v| [a, b].contains(v))
        })
        .unwrap_or(0);
    let (x, y) = (face[c], face[(c + 1) % 3]);
    let tip = positions.len() as u32;
    positions.push(DVec3::new(1.0, -1.0, 1.0));
    faces.push([y, x, tip]);
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

/// A closed surface sampled the way many exporters write one: on a (columns + 1) × (rows + 1)
/// grid of parameters u = 2π·i/columns, t = j/rows, with `point(u, t)` evaluated at every grid
/// point, so the copies of a seam vertex (u = 0 and u = 2π, or a pole written once per column)
/// differ by rounding (sin 2π ≈ −2.4e-16). Each grid quad gives the triangles (i, j),
/// (i+1, j), (i+1, j+1) and (i, j), (i+1, j+1), (i, j+1); a triangle whose corners coincide
/// up to rounding (at a pole) is left out. Vertex `i·(rows + 1) + j` is grid point (i, j).
pub fn seamed_grid(columns: u32, rows: u32, point: impl Fn(f64, f64) -> DVec3) -> Triangles {
    let vertex = |i: u32, j: u32| i * (rows + 1) + j;
    let positions: Vec<DVec3> = (0..=columns)
        .flat_map(|i| (0..=rows).map(move |j| (i, j)))
        .map(|(i, j)| {
            point(
                TAU * f64::from(i) / f64::from(columns),
                f64::from(j) / f64::from(rows),
            )
        })
        .collect();
    let mut faces = Vec::with_capacity(2 * (columns * rows) as usize);
    for i in 0..columns {
        for j in 0..rows {
            let (p00, p10, p11, p01) = (
                vertex(i, j),
                vertex(i + 1, j),
                vertex(i + 1, j + 1),
                vertex(i, j + 1),
            );
            for face in [[p00, p10, p11], [p00, p11, p01]] {
                let [a, b, c] = face.map(|v| positions[v as usize]);
                let longest = (b - a).length().max((c - b).length()).max((a - c).length());
                if (b - a).cross(c - a).length() > 1e-9 * longest * longest {
                    faces.push(face);
                }
            }
        }
    }
    (positions, faces)
}

/// The torus of major radius 1 and minor radius 0.4 as a [`seamed_grid`] (u around the axis,
/// t around the tube): both seams are written twice, e.g. `1.4 0 0` and
/// `1.4 -3.4e-16 -9.8e-17`. Welded, it is the columns × rows torus, every vertex of valence 6.
pub fn seamed_torus(columns: u32, rows: u32) -> Triangles {
    seamed_grid(columns, rows, |u, t| {
        let v = TAU * t;
        let ring = 1.0 + 0.4 * v.cos();
        DVec3::new(ring * u.cos(), ring * u.sin(), 0.4 * v.sin())
    })
}

/// The unit sphere as a [`seamed_grid`] in longitude u and latitude (south pole at t = 0):
/// the u seam is written twice and each pole once per column (the south pole copies differ by
/// rounding, sin π ≈ 1.2e-16). Welded: columns · (rows − 1) + 2 vertices.
pub fn seamed_sphere(columns: u32, rows: u32) -> Triangles {
    seamed_grid(columns, rows, |u, t| {
        let polar = PI * (1.0 - t);
        DVec3::new(polar.sin() * u.cos(), polar.sin() * u.sin(), polar.cos())
    })
}

/// The closed cylinder of radius 1 about the z axis from z = −1 to 1: its side as a
/// [`seamed_grid`] (the u seam written twice) and two caps, each a fan from its centre (the
/// last two vertices) over the rim vertices, seam copies included. Welded:
/// columns · (rows + 1) + 2 vertices.
pub fn seamed_cylinder(columns: u32, rows: u32) -> Triangles {
    let (mut positions, mut faces) = seamed_grid(columns, rows, |u, t| {
        DVec3::new(u.cos(), u.sin(), 2.0 * t - 1.0)
    });
    let rim = |i: u32, j: u32| i * (rows + 1) + j;
    let (bottom, top) = (positions.len() as u32, positions.len() as u32 + 1);
    positions.extend([DVec3::NEG_Z, DVec3::Z]);
    for i in 0..columns {
        faces.push([bottom, rim(i + 1, 0), rim(i, 0)]);
        faces.push([top, rim(i, rows), rim(i + 1, rows)]);
    }
    (positions, faces)
}

/// Test-only meshes: used by the unit tests of the loader, compiled only for them.
#[cfg(test)]
pub(crate) mod test_support {
    use glam::DVec3;

    use crate::mesh::generate::Triangles;

    /// A closed mesh whose top is a dart in the plane `z = 0` (vertex 2 inside the triangle of
    /// vertices 0, 3, 1) cut along the wrong diagonal: face (0, 1, 2) lies over face (1, 0, 3)
    /// facing the other way, so the one-rings of vertices 0 and 1 fold over themselves; the other
    /// diagonal (2, 3) lies inside the dart. Vertex 4 is the apex below that closes it. Loading
    /// flips the edge (`RepairKind::FoldedRingEdgeFlipped`).
    pub(crate) fn folded_dart() -> Triangles {
        let positions = vec![
            DVec3::new(0.0, 0.0, 0.0),
            DVec3::new(2.0, 0.0, 0.0),
            DVec3::new(1.0, 0.3, 0.0),
            DVec3::new(1.0, 1.0, 0.0),
            DVec3::new(1.0, 0.5, -1.0),
        ];
        let faces = vec![
            [0, 1, 2],
            [1, 0, 3],
            [3, 0, 4],
            [1, 3, 4],
            [2, 1, 4],
            [0, 2, 4],
        ];
        (positions, faces)
    }
}
