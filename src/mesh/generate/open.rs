//! Open meshes (with boundaries) for the schemes that take them: a hemisphere, a cylinder open
//! at both ends, half fans whose centre is a boundary vertex of a chosen valence (2 to any) and
//! wheels whose centre is an interior vertex of a chosen valence next to the boundary.

use std::f64::consts::{PI, TAU};

use glam::DVec3;

use super::Triangles;

/// A smooth, non-symmetric height over the plane, so that the open fans are curved in every
/// direction.
fn lift(x: f64, y: f64) -> f64 {
    0.3 * x * x - 0.2 * y * y + 0.15 * x * y + 0.1 * y
}

/// The upper unit hemisphere: the pole, then `rings` rings of `columns` vertices down to the
/// equator (the boundary). Quads between rings are split along alternating diagonals, so the
/// interior vertices have valences 4 to 8 and the boundary vertices 3 and 4; the pole has
/// valence `columns`.
pub fn hemisphere(columns: u32, rings: u32) -> Triangles {
    let (columns, rings) = (columns.max(3), rings.max(1));
    let mut positions = vec![DVec3::Z];
    for r in 1..=rings {
        let polar = 0.5 * PI * r as f64 / rings as f64;
        for c in 0..columns {
            // Every other ring turned by half a column: rings of a sphere, not of a cylinder.
            let azimuth = TAU * (c as f64 + 0.5 * (r % 2) as f64) / columns as f64;
            positions.push(DVec3::new(
                polar.sin() * azimuth.cos(),
                polar.sin() * azimuth.sin(),
                polar.cos(),
            ));
        }
    }
    let at = |r: u32, c: u32| 1 + (r - 1) * columns + c % columns;
    let mut faces: Vec<[u32; 3]> = (0..columns).map(|c| [0, at(1, c), at(1, c + 1)]).collect();
    for r in 1..rings {
        for c in 0..columns {
            let (a, b) = (at(r, c), at(r, c + 1));
            let (d, e) = (at(r + 1, c), at(r + 1, c + 1));
            if (r + c) % 2 == 0 {
                faces.extend([[a, d, e], [a, e, b]]);
            } else {
                faces.extend([[a, d, b], [b, d, e]]);
            }
        }
    }
    (positions, faces)
}

/// A cylinder of radius 1 around the z axis, height 2, open at both ends: `rows` + 1 circles of
/// `columns` vertices, the quads split along alternating diagonals (interior valences 4 and 8,
/// boundary valences 3 and 5). Normals point outwards.
pub fn open_cylinder(columns: u32, rows: u32) -> Triangles {
    let (columns, rows) = (columns.max(3), rows.max(1));
    let mut positions = Vec::new();
    for r in 0..=rows {
        for c in 0..columns {
            let azimuth = TAU * c as f64 / columns as f64;
            let z = -1.0 + 2.0 * r as f64 / rows as f64;
            positions.push(DVec3::new(azimuth.cos(), azimuth.sin(), z));
        }
    }
    let at = |r: u32, c: u32| r * columns + c % columns;
    let mut faces = Vec::new();
    for r in 0..rows {
        for c in 0..columns {
            let (a, b) = (at(r, c), at(r, c + 1));
            let (d, e) = (at(r + 1, c), at(r + 1, c + 1));
            if (r + c) % 2 == 0 {
                faces.extend([[a, b, e], [a, e, d]]);
            } else {
                faces.extend([[a, b, d], [b, e, d]]);
            }
        }
    }
    (positions, faces)
}

/// An open fan whose centre (vertex 0) is a boundary vertex of valence `n` ≥ 2: neighbours at
/// angles `jπ/(n − 1)` with irregular radii for n ≥ 3 (a half disk), one triangle with a 70°
/// corner for n = 2; lifted to a curved surface. The two ends of the fan are corners (boundary
/// vertices of valence 2), the other neighbours boundary vertices of valence 3.
pub fn half_fan(n: u32) -> Triangles {
    let n = n.max(2);
    let spread = if n == 2 { 70f64.to_radians() } else { PI };
    let mut positions = vec![DVec3::new(0.0, 0.0, lift(0.0, 0.0))];
    for j in 0..n {
        let angle = spread * j as f64 / (n - 1) as f64 + 0.1 * (j as f64 * 2.3).sin();
        let radius = 1.0 + 0.2 * (j as f64 * 1.7).cos();
        let (x, y) = (radius * angle.cos(), radius * angle.sin());
        positions.push(DVec3::new(x, y, lift(x, y)));
    }
    let faces = (1..n).map(|j| [0, j, j + 1]).collect();
    (positions, faces)
}

/// An open wheel whose centre (vertex 0) is an interior vertex of valence `m` ≥ 3 with every
/// neighbour on the boundary (boundary valence 3), with irregular angles and radii, lifted to a
/// curved surface.
pub fn wheel(m: u32) -> Triangles {
    let m = m.max(3);
    let mut positions = vec![DVec3::new(0.0, 0.0, lift(0.0, 0.0))];
    for j in 0..m {
        let angle = TAU * j as f64 / m as f64 + 0.15 * (j as f64 * 2.3).sin() / m as f64 * 3.0;
        let radius = 1.0 + 0.2 * (j as f64 * 1.7).cos();
        let (x, y) = (radius * angle.cos(), radius * angle.sin());
        positions.push(DVec3::new(x, y, lift(x, y)));
    }
    let faces = (0..m).map(|j| [0, 1 + j, 1 + (j + 1) % m]).collect();
    (positions, faces)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::Mesh;

    fn load(t: Triangles) -> Mesh {
        Mesh::from_triangles(t.0, t.1).expect("valid open mesh").0
    }

    /// Each generator makes a valid open mesh with the stated valences.
    #[test]
    fn open_meshes_have_the_stated_boundaries_and_valences() {
        let hemisphere = load(hemisphere(8, 4));
        assert!(!hemisphere.is_closed());
        assert_eq!(hemisphere.euler_characteristic(), 1, "a disk");
        let cylinder = load(open_cylinder(8, 3));
        assert_eq!(cylinder.euler_characteristic(), 0, "an annulus");
        for n in 2..=8 {
            let fan = load(half_fan(n));
            assert!(fan.is_boundary_vertex(0));
            assert_eq!(fan.valence(0), n as usize);
            assert_eq!((fan.valence(1), fan.valence(n)), (2, 2), "corners");
        }
        for m in 3..=12 {
            let wheel = load(wheel(m));
            assert!(!wheel.is_boundary_vertex(0));
            assert_eq!(wheel.valence(0), m as usize);
            assert!((1..=m).all(|v| wheel.is_boundary_vertex(v) && wheel.valence(v) == 3));
        }
    }
}
