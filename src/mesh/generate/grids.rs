//! Meshes laid out on grids: the regular torus, the genus-2 plate and the open hexagonal disk.

use std::collections::HashMap;

use glam::DVec3;

use super::{Triangles, analytic};

/// The regular torus used as a scene: 12 segments around the axis, 8 around the tube, major
/// radius 1, minor radius 0.4; every vertex has valence 6. See [`analytic::torus`].
pub fn torus() -> Triangles {
    let sampled = analytic::torus(12, 8, 1.0, 0.4);
    (sampled.positions, sampled.faces)
}

/// A closed genus-2 surface: a plate with two square holes. A grid of 8 × 5 unit squares with
/// squares (2, 2) and (5, 2) removed is triangulated on the top (z = +0.18) and again on the
/// bottom (z = −0.18), and the two copies share the vertices of the outer rim and of the hole
/// rims, which lie in z = 0 (grid spacing 0.25, centred on the origin). Diagonals are chosen so
/// that no edge joins two rim vertices across a square, so top and bottom never share a
/// face or an interior edge. V − E + F = 74 − 228 + 152 = −2.
pub fn genus2() -> Triangles {
    const NX: u32 = 8;
    const NY: u32 = 5;
    const HOLES: [(u32, u32); 2] = [(2, 2), (5, 2)];
    const SPACING: f64 = 0.25;
    const THICKNESS: f64 = 0.18;
    let grid = |i: u32, j: u32| j * (NX + 1) + i;
    let is_hole = |i: u32, j: u32| HOLES.contains(&(i, j));
    let on_rim = |i: u32, j: u32| {
        let outer = i == 0 || j == 0 || i == NX || j == NY;
        let hole = HOLES
            .iter()
            .any(|&(hi, hj)| (hi..=hi + 1).contains(&i) && (hj..=hj + 1).contains(&j));
        outer || hole
    };
    let xy = |i: u32, j: u32| {
        DVec3::new(
            (f64::from(i) - f64::from(NX) / 2.0) * SPACING,
            (f64::from(j) - f64::from(NY) / 2.0) * SPACING,
            0.0,
        )
    };
    let mut positions = Vec::new();
    for j in 0..=NY {
        for i in 0..=NX {
            let lift = if on_rim(i, j) { 0.0 } else { THICKNESS };
            positions.push(xy(i, j) + DVec3::Z * lift);
        }
    }
    // Bottom copies of the off-rim vertices.
    let mut bottom: HashMap<u32, u32> = HashMap::new();
    for j in 0..=NY {
        for i in 0..=NX {
            if !on_rim(i, j) {
                bottom.insert(grid(i, j), positions.len() as u32);
                positions.push(xy(i, j) - DVec3::Z * THICKNESS);
            }
        }
    }
    let below = |v: u32| bottom.get(&v).copied().unwrap_or(v);
    let mut top_faces = Vec::new();
    for j in 0..NY {
        for i in 0..NX {
            if is_hole(i, j) {
                continue;
            }
            let (p00, p10, p11, p01) = (
                grid(i, j),
                grid(i + 1, j),
                grid(i + 1, j + 1),
                grid(i, j + 1),
            );
            if on_rim(i, j) && on_rim(i + 1, j + 1) {
                top_faces.extend([[p00, p10, p01], [p10, p11, p01]]);
            } else {
                top_faces.extend([[p00, p10, p11], [p00, p11, p01]]);
            }
        }
    }
    let mut faces = top_faces.clone();
    faces.extend(
        top_faces
            .iter()
            .map(|&[a, b, c]| [below(a), below(c), below(b)]),
    );
    (positions, faces)
}

/// An open mesh: the hexagonal patch of the triangular lattice with `rings` rings around the
/// centre (3·rings² + 3·rings + 1 vertices, 6·rings² faces), scaled to radius 1 and lifted to
/// the dome z = 0.3 (1 − x² − y²). Interior vertices have valence 6, rim vertices 3 or 4.
pub fn disk(rings: u32) -> Triangles {
    let k = rings.max(1) as i64;
    let mut index = HashMap::new();
    let mut positions = Vec::new();
    for q in -k..=k {
        for r in -k..=k {
            if (q + r).abs() <= k {
                let x = (q as f64 + 0.5 * r as f64) / k as f64;
                let y = (0.75f64.sqrt() * r as f64) / k as f64;
                index.insert((q, r), positions.len() as u32);
                positions.push(DVec3::new(x, y, 0.3 * (1.0 - x * x - y * y)));
            }
        }
    }
    let mut faces = Vec::new();
    for q in -k..=k {
        for r in -k..=k {
            let corner = |dq: i64, dr: i64| index.get(&(q + dq, r + dr)).copied();
            if let (Some(a), Some(b), Some(c)) = (corner(0, 0), corner(1, 0), corner(0, 1)) {
                faces.push([a, b, c]);
            }
            if let (Some(a), Some(b), Some(c)) = (corner(1, 0), corner(1, 1), corner(0, 1)) {
                faces.push([a, b, c]);
            }
        }
    }
    (positions, faces)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::Mesh;

    #[test]
    fn genus2_counts_and_rims() {
        let (positions, faces) = genus2();
        assert_eq!((positions.len(), faces.len()), (74, 152));
        let (mesh, _) = Mesh::from_triangles(positions.clone(), faces).unwrap();
        assert_eq!(mesh.euler_characteristic(), -2);
        // Top and bottom are mirror images: every lifted vertex has a partner below.
        let above = positions.iter().filter(|p| p.z > 0.0).count();
        let below = positions.iter().filter(|p| p.z < 0.0).count();
        assert_eq!((above, below), (20, 20));
    }

    #[test]
    fn disk_counts_and_boundary() {
        for rings in 1..=4u32 {
            let (positions, faces) = disk(rings);
            let k = rings as usize;
            assert_eq!(positions.len(), 3 * k * k + 3 * k + 1);
            assert_eq!(faces.len(), 6 * k * k);
            let (mesh, _) = Mesh::from_triangles(positions, faces).unwrap();
            let rim = (0..mesh.vertex_count() as u32)
                .filter(|&v| mesh.is_boundary_vertex(v))
                .count();
            assert_eq!(rim, 6 * k);
            // Counter-clockwise seen from above: face normals point up.
            for f in 0..mesh.face_count() as u32 {
                assert!(mesh.face_normal(f).z > 0.0);
            }
        }
    }

    #[test]
    fn torus_scene_is_the_12_by_8_grid() {
        let (positions, faces) = torus();
        assert_eq!((positions.len(), faces.len()), (96, 192));
    }
}
