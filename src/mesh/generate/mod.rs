//! Generated test meshes (the files in scenes/ are written from these): platonic solids, a
//! deformed icosahedron, a triangulated cube, meshes with chosen vertex valences, a torus and a
//! genus-2 surface; an open disk; surfaces sampled from analytic shapes with their exact
//! normals ([`analytic`]); and invalid meshes for error tests ([`bad`]).
//!
//! Every function is pure and deterministic, and every closed mesh is oriented with outward
//! normals. [`SCENES`] lists the meshes committed as `scenes/<name>.obj`; a unit test checks
//! that each committed file parses to exactly the mesh generated here. After changing a
//! generator, rewrite the files with
//! `cargo test --lib mesh::generate -- --ignored write_scenes`. [`SCANNED_SCENES`] lists the
//! committed meshes that come from scans (the Stanford bunny) rather than from a generator;
//! their tests check that each loads without repairs, closed, with the stated genus, face
//! count and valences.

pub mod analytic;
pub mod bad;
mod cad;
mod grids;
mod open;
mod scenes;

pub use cad::{capped_cylinder, capped_cylinder_with, l_block, l_block_with};
pub use grids::{disk, genus2, torus};
pub use open::{half_fan, hemisphere, open_cylinder, wheel};
pub use scenes::{SCANNED_SCENES, SCENES, SHARP_SCENES, ScannedMesh, SceneMesh};

use std::f64::consts::TAU;

use glam::DVec3;

use crate::error::{Error, Result};

/// Vertex positions and counter-clockwise faces (outward normals for closed meshes).
pub type Triangles = (Vec<DVec3>, Vec<[u32; 3]>);

/// OBJ text of generated triangles as they are (unwelded, unvalidated), coordinates in
/// Rust's shortest round-trip form, so a test can hand any of them to the command line.
pub fn to_obj((positions, faces): &Triangles) -> String {
    super::obj::write("", positions, faces)
}

/// The golden ratio, which places the icosahedron's vertices.
const PHI: f64 = 1.618_033_988_749_895;

/// Faces of a convex polyhedron whose edges all have length `edge`, inscribed in a sphere about
/// the origin: the vertex triples at mutual distance `edge`, in lexicographic order, each turned
/// to face outward.
fn equilateral_hull(positions: &[DVec3], edge: f64) -> Vec<[u32; 3]> {
    let n = positions.len() as u32;
    let is_edge = |a: u32, b: u32| {
        ((positions[a as usize] - positions[b as usize]).length() - edge).abs() < 1e-9 * edge
    };
    let mut faces = Vec::new();
    for a in 0..n {
        for b in a + 1..n {
            for c in b + 1..n {
                if is_edge(a, b) && is_edge(b, c) && is_edge(c, a) {
                    faces.push(outward([a, b, c], positions));
                }
            }
        }
    }
    faces
}

/// `face`, or its reverse if its normal points towards the origin.
fn outward(face: [u32; 3], positions: &[DVec3]) -> [u32; 3] {
    let [a, b, c] = face.map(|v| positions[v as usize]);
    if (b - a).cross(c - a).dot(a + b + c) >= 0.0 {
        face
    } else {
        [face[0], face[2], face[1]]
    }
}

/// Regular tetrahedron inscribed in the unit sphere.
pub fn tetrahedron() -> Triangles {
    let corners = [
        (1.0, 1.0, 1.0),
        (1.0, -1.0, -1.0),
        (-1.0, 1.0, -1.0),
        (-1.0, -1.0, 1.0),
    ];
    let raw: Vec<DVec3> = corners
        .iter()
        .map(|&(x, y, z)| DVec3::new(x, y, z))
        .collect();
    let faces = equilateral_hull(&raw, 8f64.sqrt());
    (raw.iter().map(|p| p.normalize()).collect(), faces)
}

/// Regular octahedron with vertices ±x, ±y, ±z.
pub fn octahedron() -> Triangles {
    let positions = vec![
        DVec3::X,
        DVec3::NEG_X,
        DVec3::Y,
        DVec3::NEG_Y,
        DVec3::Z,
        DVec3::NEG_Z,
    ];
    let faces = equilateral_hull(&positions, 2f64.sqrt());
    (positions, faces)
}

/// Regular icosahedron inscribed in the unit sphere, vertices at (0, ±1, ±φ), (±1, ±φ, 0),
/// (±φ, 0, ±1) scaled to unit length.
pub fn icosahedron() -> Triangles {
    let mut raw = Vec::with_capacity(12);
    for (s, t) in [(1.0, 1.0), (-1.0, 1.0), (1.0, -1.0), (-1.0, -1.0)] {
        raw.push(DVec3::new(0.0, s, t * PHI));
    }
    for (s, t) in [(1.0, 1.0), (-1.0, 1.0), (1.0, -1.0), (-1.0, -1.0)] {
        raw.push(DVec3::new(s, t * PHI, 0.0));
    }
    for (s, t) in [(1.0, 1.0), (-1.0, 1.0), (1.0, -1.0), (-1.0, -1.0)] {
        raw.push(DVec3::new(t * PHI, 0.0, s));
    }
    let faces = equilateral_hull(&raw, 2.0);
    (raw.iter().map(|p| p.normalize()).collect(), faces)
}

/// The gallery's default mesh: the unit [`icosahedron`] with its axes scaled by
/// (1.0, 0.8, 1.3), then vertex 0 pulled out to 1.25 times its distance from the centre,
/// vertex 5 pulled out to 1.15 times, and vertex 10 pushed in to 0.85 times. No symmetry is
/// left, and the pushed-in vertex makes a concave spot, so every scheme shows its behaviour
/// at saddle-like and stretched vertices.
pub fn deformed_icosahedron() -> Triangles {
    let (mut positions, faces) = icosahedron();
    for p in &mut positions {
        *p *= DVec3::new(1.0, 0.8, 1.3);
    }
    positions[0] *= 1.25;
    positions[5] *= 1.15;
    positions[10] *= 0.85;
    (positions, faces)
}

/// The cube [−1, 1]³ as 12 triangles, one diagonal per side, with vertex valences
/// 3, 4, 4, 4, 5, 5, 5, 6. (Of the 64 diagonal choices, none gives only valences 4, 5 and 6:
/// the 12 diagonal ends would need every corner to take at least one, with one corner taking
/// three; this choice has the widest spread.) Vertex `x + 2y + 4z` is at (2x−1, 2y−1, 2z−1).
pub fn cube() -> Triangles {
    let positions = (0..8)
        .map(|i| {
            let bit = |k: u32| f64::from((i >> k) & 1) * 2.0 - 1.0;
            DVec3::new(bit(0), bit(1), bit(2))
        })
        .collect();
    // Sides as counter-clockwise quads seen from outside, and whether each is split along
    // its 0–2 diagonal (else 1–3).
    let sides: [([u32; 4], bool); 6] = [
        ([0, 2, 3, 1], true),
        ([4, 5, 7, 6], true),
        ([0, 1, 5, 4], true),
        ([2, 6, 7, 3], true),
        ([0, 4, 6, 2], true),
        ([1, 3, 7, 5], false),
    ];
    let mut faces = Vec::with_capacity(12);
    for ([a, b, c, d], diagonal_ac) in sides {
        if diagonal_ac {
            faces.extend([[a, b, c], [a, c, d]]);
        } else {
            faces.extend([[a, b, d], [b, c, d]]);
        }
    }
    (positions, faces)
}

/// An n-gonal bipyramid: a ring of n vertices on the unit circle in z = 0 (valence 4) and
/// apexes at ±z (valence n). Vertex 0 is the top apex, 1 the bottom apex, 2.. the ring.
fn bipyramid(n: u32) -> Triangles {
    let mut positions = vec![DVec3::Z, DVec3::NEG_Z];
    positions.extend((0..n).map(|i| {
        let angle = TAU * f64::from(i) / f64::from(n);
        DVec3::new(angle.cos(), angle.sin(), 0.0)
    }));
    let ring = |i: u32| 2 + i % n;
    let mut faces = Vec::with_capacity(2 * n as usize);
    for i in 0..n {
        faces.push([0, ring(i), ring(i + 1)]);
        faces.push([1, ring(i + 1), ring(i)]);
    }
    (positions, faces)
}

/// A closed mesh with a vertex of valence `n` (both apexes of an n-gonal bipyramid; ring
/// vertices have valence 4). Defined for every n ≥ 3; the experiments use 3..=16.
pub fn valence_fan(n: usize) -> Result<Triangles> {
    match u32::try_from(n) {
        Ok(n) if n >= 3 => Ok(bipyramid(n)),
        _ => Err(Error::BadParam {
            name: "valence".to_string(),
            reason: format!("a vertex fan needs valence at least 3, got {n}"),
        }),
    }
}

/// Replaces each face of `targets` (given by its corners) by three faces around a new vertex
/// at the face centroid, lifted along the face normal by 0.15 × the mean edge length.
/// Panics if a target is not a face (generator bug, not user data).
fn split_faces(mut mesh: Triangles, targets: &[[u32; 3]]) -> Triangles {
    let (positions, faces) = &mut mesh;
    for target in targets {
        let f = faces
            .iter()
            .position(|face| face == target)
            .expect("split target is a face of the generated mesh");
        let [a, b, c] = *target;
        let [pa, pb, pc] = [a, b, c].map(|v| positions[v as usize]);
        let mean_edge = ((pb - pa).length() + (pc - pb).length() + (pa - pc).length()) / 3.0;
        let normal = (pb - pa).cross(pc - pa).normalize();
        let m = positions.len() as u32;
        positions.push((pa + pb + pc) / 3.0 + 0.15 * mean_edge * normal);
        faces[f] = [a, b, m];
        faces.extend([[b, c, m], [c, a, m]]);
    }
    mesh
}

/// A closed mesh whose vertices have valences 3, 4, 5, 6, 8, 15 and 16: a 12-gonal
/// [`valence_fan`] (top apex 0, bottom apex 1, ring vertices r_i = 2 + i) with seven faces
/// split 1-to-3 at a slightly lifted centroid. Splitting (0, r0, r1) makes r0, r1 valence 5;
/// splitting both faces on edge r5–r6 makes them valence 6; splitting the four faces around r9
/// makes r9 valence 8 (and r8, r10 valence 6). The new centre vertices have valence 3, the
/// apexes 16 and 15.
pub fn mixed_valence() -> Triangles {
    let r = |i: u32| 2 + i;
    split_faces(
        bipyramid(12),
        &[
            [0, r(0), r(1)],
            [0, r(5), r(6)],
            [1, r(6), r(5)],
            [0, r(8), r(9)],
            [0, r(9), r(10)],
            [1, r(9), r(8)],
            [1, r(10), r(9)],
        ],
    )
}

#[cfg(test)]
mod tests {
    use glam::DVec3;

    use super::*;
    use crate::mesh::Mesh;

    /// Six times the signed volume enclosed by the faces (positive for outward normals).
    fn signed_volume_6((positions, faces): &Triangles) -> f64 {
        faces
            .iter()
            .map(|f| {
                let [a, b, c] = f.map(|v| positions[v as usize]);
                a.dot(b.cross(c))
            })
            .sum()
    }

    /// True if every face's normal points away from the origin (star-shaped meshes).
    fn faces_point_outward((positions, faces): &Triangles) -> bool {
        faces.iter().all(|f| {
            let [a, b, c] = f.map(|v| positions[v as usize]);
            (b - a).cross(c - a).dot(a + b + c) > 0.0
        })
    }

    #[test]
    fn platonic_solids_have_the_right_counts_and_face_outward() {
        for (solid, vertices, faces) in [
            (tetrahedron(), 4, 4),
            (octahedron(), 6, 8),
            (icosahedron(), 12, 20),
        ] {
            assert_eq!((solid.0.len(), solid.1.len()), (vertices, faces));
            assert!(faces_point_outward(&solid));
            for p in &solid.0 {
                assert!(
                    (p.length() - 1.0).abs() < 1e-15,
                    "{p} is not on the unit sphere"
                );
            }
        }
    }

    #[test]
    fn deformed_icosahedron_follows_its_documented_deformation() {
        let (regular, faces) = icosahedron();
        let (deformed, deformed_faces) = deformed_icosahedron();
        assert_eq!(faces, deformed_faces);
        let pulls = [(0, 1.25), (5, 1.15), (10, 0.85)];
        for (v, (p, q)) in regular.iter().zip(&deformed).enumerate() {
            let pull = pulls.iter().find(|(w, _)| *w == v).map_or(1.0, |&(_, s)| s);
            assert_eq!(*q, *p * DVec3::new(1.0, 0.8, 1.3) * pull, "vertex {v}");
        }
        assert!(signed_volume_6(&(deformed, faces)) > 0.0);
    }

    #[test]
    fn deformed_icosahedron_has_no_mirror_symmetry_left() {
        // The moved vertices are at distances from the centre that no other vertex has, so no
        // symmetry of the mesh can map one of them to another vertex.
        let (positions, _) = deformed_icosahedron();
        let pulled: Vec<f64> = [0, 5, 10].iter().map(|&v| positions[v].length()).collect();
        for (i, &r) in pulled.iter().enumerate() {
            let same = positions
                .iter()
                .enumerate()
                .filter(|(w, p)| *w != [0, 5, 10][i] && (p.length() - r).abs() < 1e-12)
                .count();
            assert_eq!(same, 0, "pulled vertex {i} has a symmetric partner");
        }
    }

    #[test]
    fn cube_is_a_closed_outward_cube() {
        let cube = cube();
        assert_eq!((cube.0.len(), cube.1.len()), (8, 12));
        assert!(faces_point_outward(&cube));
        // Volume of [-1, 1]³ is 8.
        assert!((signed_volume_6(&cube) / 6.0 - 8.0).abs() < 1e-12);
    }

    #[test]
    fn valence_fans_face_outward_and_reject_too_small_valences() {
        for n in 3..=16 {
            assert!(faces_point_outward(&valence_fan(n).unwrap()), "n = {n}");
        }
        for n in [0, 1, 2] {
            assert!(
                matches!(valence_fan(n), Err(Error::BadParam { .. })),
                "n = {n}"
            );
        }
    }

    #[test]
    fn mixed_valence_faces_outward() {
        let mesh = mixed_valence();
        assert_eq!((mesh.0.len(), mesh.1.len()), (21, 38));
        assert!(faces_point_outward(&mesh));
    }

    #[test]
    fn generated_meshes_load_without_repairs() {
        let mut all: Vec<(String, Triangles)> = SCENES
            .iter()
            .map(|s| (s.name.to_string(), (s.build)()))
            .collect();
        all.push(("disk".to_string(), disk(4)));
        for (name, (positions, faces)) in all {
            let (mesh, report) = Mesh::from_triangles(positions.clone(), faces.clone()).unwrap();
            assert_eq!(report, Default::default(), "{name}");
            assert_eq!(mesh.positions(), &positions[..], "{name}");
            assert_eq!(mesh.faces(), &faces[..], "{name}");
        }
    }

    #[test]
    fn closed_scenes_enclose_positive_volume() {
        for scene in &SCENES {
            assert!(signed_volume_6(&(scene.build)()) > 0.0, "{}", scene.name);
        }
    }
}
