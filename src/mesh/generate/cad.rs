//! CAD-like parts: flat faces meeting at 90° creases, the meshes sharp edges are for
//! ([`crate::mesh::SharpEdges`]): an L-block and a capped cylinder. Both are closed, outward,
//! with interior vertices on their flat faces, so a surface that keeps flat faces flat is
//! tested away from the creases too.

use std::collections::HashMap;
use std::f64::consts::TAU;

use glam::{DVec3, IVec3};

use super::Triangles;

/// An L-shaped prism: the L of the unit squares (0,0), (1,0), (0,1) in the xy-plane, extruded
/// over z ∈ [0, 1], each unit edge cut into `n` pieces (`n` ≥ 1; [`l_block`] uses 2). Its
/// creases are all 90°: 17 convex edges and one concave edge (x = y = 1), with corner vertices
/// (three creases) at all of their ends.
pub fn l_block_with(n: u32) -> Triangles {
    let n = n.max(1) as i32;
    let filled = |cell: IVec3| {
        let unit = cell.div_euclid(IVec3::splat(n));
        unit.z == 0 && matches!((unit.x, unit.y), (0, 0) | (1, 0) | (0, 1))
    };
    voxel_surface(IVec3::new(2 * n, 2 * n, n), filled, 1.0 / f64::from(n))
}

/// The L-block of `scenes/l-block.obj`: [`l_block_with`] at `n = 2` (112 triangles).
pub fn l_block() -> Triangles {
    l_block_with(2)
}

/// The boundary of the cells `filled` of the grid `0 ≤ cell < size` (cubes of edge `h`): one
/// quad per face between a filled and an empty cell, split along alternating diagonals into two
/// counter-clockwise (outward) triangles, vertices shared.
fn voxel_surface(size: IVec3, filled: impl Fn(IVec3) -> bool, h: f64) -> Triangles {
    let inside = |c: IVec3| c.cmpge(IVec3::ZERO).all() && c.cmplt(size).all() && filled(c);
    let mut index: HashMap<IVec3, u32> = HashMap::new();
    let mut positions = Vec::new();
    let mut vertex = |p: IVec3| {
        *index.entry(p).or_insert_with(|| {
            positions.push(p.as_dvec3() * h);
            positions.len() as u32 - 1
        })
    };
    let mut faces = Vec::new();
    let axes = [IVec3::X, IVec3::Y, IVec3::Z];
    for x in 0..size.x {
        for y in 0..size.y {
            for z in 0..size.z {
                let cell = IVec3::new(x, y, z);
                if !inside(cell) {
                    continue;
                }
                for (k, &axis) in axes.iter().enumerate() {
                    let (u, v) = (axes[(k + 1) % 3], axes[(k + 2) % 3]);
                    for outward in [1, -1] {
                        if inside(cell + outward * axis) {
                            continue;
                        }
                        // The face's corners, counter-clockwise seen from outside.
                        let base = cell + if outward > 0 { axis } else { IVec3::ZERO };
                        let mut quad = [base, base + u, base + u + v, base + v];
                        if outward < 0 {
                            quad.reverse();
                        }
                        let [a, b, c, d] = quad.map(&mut vertex);
                        if (x + y + z) % 2 == 0 {
                            faces.extend([[a, b, c], [a, c, d]]);
                        } else {
                            faces.extend([[a, b, d], [b, c, d]]);
                        }
                    }
                }
            }
        }
    }
    (positions, faces)
}

/// A cylinder of radius 1 over z ∈ [−1, 1] with flat caps: `segments` vertices around, the
/// side cut into `rings` bands, each cap a ring at radius 1/2 and a centre vertex. Adjacent
/// side faces turn by 360°/`segments`; the two rims are 90° creases (every rim vertex has
/// two of them).
pub fn capped_cylinder_with(segments: u32, rings: u32) -> Triangles {
    let (m, rings) = (segments.max(3), rings.max(1));
    let around = |i: u32, radius: f64, z: f64| {
        let angle = TAU * f64::from(i % m) / f64::from(m);
        DVec3::new(radius * angle.cos(), radius * angle.sin(), z)
    };
    let mut positions = Vec::new();
    // Side rings 0..=rings from z = −1 up.
    for r in 0..=rings {
        let z = -1.0 + 2.0 * f64::from(r) / f64::from(rings);
        positions.extend((0..m).map(|i| around(i, 1.0, z)));
    }
    let side = |r: u32, i: u32| r * m + i % m;
    let mut faces = Vec::new();
    for r in 0..rings {
        for i in 0..m {
            let (a, b, c, d) = (
                side(r, i),
                side(r, i + 1),
                side(r + 1, i + 1),
                side(r + 1, i),
            );
            faces.extend([[a, b, c], [a, c, d]]);
        }
    }
    // Caps: an inner ring (offset by half a segment) and a centre.
    for (rim, z, up) in [(0, -1.0, false), (rings, 1.0, true)] {
        let inner = positions.len() as u32;
        positions.extend((0..m).map(|i| {
            let angle = TAU * (f64::from(i) + 0.5) / f64::from(m);
            DVec3::new(0.5 * angle.cos(), 0.5 * angle.sin(), z)
        }));
        let centre = positions.len() as u32;
        positions.push(DVec3::new(0.0, 0.0, z));
        let mut cap = Vec::new();
        for i in 0..m {
            let (o0, o1) = (side(rim, i), side(rim, i + 1));
            let (i0, i1) = (inner + i, inner + (i + 1) % m);
            // Counter-clockwise seen from +z.
            cap.extend([[o0, o1, i0], [i0, o1, i1], [centre, i0, i1]]);
        }
        if !up {
            for face in &mut cap {
                face.swap(1, 2);
            }
        }
        faces.extend(cap);
    }
    (positions, faces)
}

/// The capped cylinder of `scenes/capped-cylinder.obj`: [`capped_cylinder_with`] with 16
/// segments (a 22.5° turn between side faces) and 2 bands.
pub fn capped_cylinder() -> Triangles {
    capped_cylinder_with(16, 2)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::{LoadOptions, Mesh};

    fn load(triangles: Triangles, crease: Option<f64>) -> Mesh {
        let options = LoadOptions {
            crease_angle: crease,
            ..LoadOptions::default()
        };
        let (mesh, report) =
            Mesh::from_triangles_with(triangles.0, triangles.1, &options).expect("valid part");
        assert_eq!(report.reoriented_faces, 0, "generated outward");
        mesh
    }

    fn six_volume(mesh: &Mesh) -> f64 {
        mesh.faces()
            .iter()
            .map(|face| {
                let [a, b, c] = face.map(|v| mesh.positions()[v as usize]);
                a.dot(b.cross(c))
            })
            .sum()
    }

    #[test]
    fn the_l_block_is_a_closed_outward_solid_with_its_creases() {
        for n in [1, 2, 3] {
            let mesh = load(l_block_with(n), Some(40.0));
            assert!(mesh.is_closed());
            assert_eq!(mesh.euler_characteristic(), 2);
            // Volume 3, so six times it is 18.
            assert!((six_volume(&mesh) - 18.0).abs() < 1e-12, "n = {n}");
            // 18 crease lines (6 + 6 on the L's outlines at z = 0 and z = 1, 6 vertical),
            // each cut into n pieces, except the long ones (length 2) into 2n.
            let long = 4; // (0..2) along x at y = 0 and along y at x = 0, top and bottom.
            assert_eq!(
                mesh.sharp_edges().count() as u32,
                n * 18 + n * long,
                "n = {n}"
            );
        }
    }

    #[test]
    fn the_capped_cylinder_has_its_two_rims_as_creases() {
        let mesh = load(capped_cylinder(), Some(40.0));
        assert!(mesh.is_closed());
        assert_eq!(mesh.euler_characteristic(), 2);
        assert!(six_volume(&mesh) > 0.0);
        assert_eq!(mesh.sharp_edges().count(), 32);
        for v in 0..16 {
            assert_eq!(mesh.sharp_valence(v), 2, "rim vertex {v}");
        }
        // Below the side's 22.5° turn the side edges are sharp too.
        let finer = load(capped_cylinder(), Some(20.0));
        assert_eq!(finer.sharp_edges().count(), 32 + 2 * 16);
    }
}
