//! The `flat` baseline: every mesh face as one degree-1 Bézier patch, i.e. the mesh itself.
//!
//! It is C⁰ and interpolates the vertices; its normal jumps across every edge by the dihedral
//! angle of the mesh, which is what every smooth scheme is compared against.

use crate::bezier::TriangleBezier;
use crate::error::Result;
use crate::mesh::Mesh;
use crate::schemes::{Params, SchemeSpec};
use crate::surface::{Patch, PatchGeometry, Surface, WHOLE_FACE};

/// Registry entry.
pub(crate) const SPEC: SchemeSpec = SchemeSpec {
    name: "flat",
    summary: "the mesh itself: one linear triangle per face (C0 baseline)",
    params: &[],
    needs_closed_mesh: false,
    bytes_per_face: 400.0,
    sharp_edges: crate::schemes::SharpEdgeSupport::Builds,
    build,
};

fn build(mesh: &Mesh, params: &Params) -> Result<Surface> {
    let positions = mesh.positions();
    let patches = mesh
        .faces()
        .iter()
        .enumerate()
        .map(|(f, corners)| Patch {
            face: f as u32,
            piece: 0,
            domain: WHOLE_FACE,
            // Degree 1: b(1,0,0), b(0,1,0), b(0,0,1) are the three corners in face order.
            geometry: PatchGeometry::Bezier(TriangleBezier::new(
                1,
                corners.iter().map(|&v| positions[v as usize]).collect(),
            )),
        })
        .collect();
    Ok(params.surface(SPEC.name, patches))
}

#[cfg(test)]
mod tests {
    use glam::DVec3;

    use super::*;

    /// Regular tetrahedron, written out so that the test does not depend on the generators.
    fn tetrahedron() -> Mesh {
        let positions = vec![
            DVec3::new(1.0, 1.0, 1.0),
            DVec3::new(1.0, -1.0, -1.0),
            DVec3::new(-1.0, 1.0, -1.0),
            DVec3::new(-1.0, -1.0, 1.0),
        ];
        let faces = vec![[0, 1, 2], [0, 3, 1], [0, 2, 3], [1, 3, 2]];
        Mesh::from_triangles(positions, faces)
            .expect("valid tetrahedron")
            .0
    }

    #[test]
    fn patches_are_the_faces() {
        let mesh = tetrahedron();
        let surface = crate::schemes::build("flat", &mesh, &[]).expect("flat builds");
        assert_eq!(surface.patches.len(), mesh.face_count());
        for (patch, face) in surface.patches.iter().zip(mesh.faces()) {
            for (c, &v) in face.iter().enumerate() {
                let uv = crate::surface::UV_CORNERS[c];
                assert_eq!(
                    patch.eval(uv.x, uv.y),
                    mesh.positions()[v as usize],
                    "corner {c} of face {}",
                    patch.face
                );
            }
            // A point inside is the affine combination of the corners.
            let p = patch.eval(0.25, 0.5);
            let expected = 0.25 * mesh.positions()[face[0] as usize]
                + 0.25 * mesh.positions()[face[1] as usize]
                + 0.5 * mesh.positions()[face[2] as usize];
            assert!((p - expected).length() < 1e-15, "{p} vs {expected}");
        }
    }
}
