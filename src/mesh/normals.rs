//! Vertex normals: estimated from the faces (angle-weighted, [Thürmer & Wüthrich 1998]) or taken
//! from an OBJ file, where they must give one direction per vertex.

use glam::DVec3;

use crate::error::{Error, Result};

/// Two file normals at one vertex count as the same direction up to this angle (radians).
pub const OBJ_NORMAL_ANGLE_TOLERANCE: f64 = 1e-6;

/// An OBJ file's normals, per corner of each face in file order.
#[derive(Clone, Debug)]
pub(super) struct CornerNormals {
    /// The file's `vn` records.
    pub(super) normals: Vec<DVec3>,
    /// For corner `c` of face `f`, `normals[corner[3·f + c]]`.
    pub(super) corner: Vec<u32>,
}

/// The file's normals as one unit vector per vertex, or why there are none.
#[derive(Clone, Debug)]
pub(super) enum ObjNormals {
    /// One unit normal per vertex (mesh numbering).
    PerVertex(Vec<DVec3>),
    /// The reason `normals=obj` cannot be honoured.
    Unusable(String),
}

impl ObjNormals {
    /// The normals, or [`Error::MissingNormals`] with the reason.
    pub(super) fn per_vertex(&self) -> Result<Vec<DVec3>> {
        match self {
            ObjNormals::PerVertex(normals) => Ok(normals.clone()),
            ObjNormals::Unusable(reason) => Err(Error::MissingNormals {
                reason: reason.clone(),
            }),
        }
    }
}

/// Angle between two non-zero vectors, accurate near 0 and π (atan2 of sine and cosine).
pub(super) fn angle_between(a: DVec3, b: DVec3) -> f64 {
    a.cross(b).length().atan2(a.dot(b))
}

/// Gathers the file's per-corner normals into one normal per vertex. `faces` are the welded
/// faces with their corners still in file order; `name` gives a vertex's input number for the
/// reason text.
pub(super) fn per_vertex_from_corners(
    corner_normals: std::result::Result<CornerNormals, String>,
    faces: &[[u32; 3]],
    vertex_count: usize,
    name: &dyn Fn(u32) -> usize,
) -> ObjNormals {
    let corner_normals = match corner_normals {
        Ok(corner_normals) => corner_normals,
        Err(reason) => return ObjNormals::Unusable(reason),
    };
    // (normal, face it was first seen in) per vertex
    let mut first_seen: Vec<Option<(DVec3, usize)>> = vec![None; vertex_count];
    for (f, face) in faces.iter().enumerate() {
        for (c, &v) in face.iter().enumerate() {
            let normal = corner_normals
                .corner
                .get(3 * f + c)
                .and_then(|&n| corner_normals.normals.get(n as usize));
            let Some(&normal) = normal else {
                return ObjNormals::Unusable(format!(
                    "corner {c} of face {f} (vertex {}) has no normal",
                    name(v)
                ));
            };
            let length = normal.length();
            if !(length.is_finite() && length > 0.0) {
                return ObjNormals::Unusable(format!(
                    "vertex {} has a zero or non-finite normal in face {f}",
                    name(v)
                ));
            }
            let unit = normal / length;
            match first_seen[v as usize] {
                None => first_seen[v as usize] = Some((unit, f)),
                Some((earlier, earlier_face)) => {
                    let angle = angle_between(earlier, unit);
                    if angle > OBJ_NORMAL_ANGLE_TOLERANCE {
                        return ObjNormals::Unusable(format!(
                            "vertex {} has contradictory normals: {angle:.3e} rad apart in faces \
                             {earlier_face} and {f}",
                            name(v)
                        ));
                    }
                }
            }
        }
    }
    // Every vertex is used by a face (unused ones were dropped), so each has a normal.
    let normals = first_seen
        .into_iter()
        .map(|seen| seen.map_or(DVec3::ZERO, |(normal, _)| normal))
        .collect();
    ObjNormals::PerVertex(normals)
}

/// Angle-weighted vertex normals [Thürmer & Wüthrich 1998]: each face's unit normal weighted by
/// the face's angle at the vertex, summed, normalised. Unlike area or uniform weights, the
/// result does not change when a face is split, so it depends on the surface rather than on
/// how it was triangulated.
pub(super) fn angle_weighted(positions: &[DVec3], faces: &[[u32; 3]]) -> Result<Vec<DVec3>> {
    let mut sums = vec![DVec3::ZERO; positions.len()];
    let mut total_angle = vec![0.0; positions.len()];
    for face in faces {
        let p = face.map(|v| positions[v as usize]);
        let normal = (p[1] - p[0]).cross(p[2] - p[0]).normalize();
        for c in 0..3 {
            let angle = angle_between(p[(c + 1) % 3] - p[c], p[(c + 2) % 3] - p[c]);
            sums[face[c] as usize] += angle * normal;
            total_angle[face[c] as usize] += angle;
        }
    }
    sums.iter()
        .zip(&total_angle)
        .enumerate()
        .map(|(v, (&sum, &total))| {
            let length = sum.length();
            // The sum is at most the total angle long; a far shorter sum means the faces around
            // v point in cancelling directions and no normal is meaningful.
            if length > 1e-12 * total {
                Ok(sum / length)
            } else {
                Err(Error::UndefinedNormal { vertex: v })
            }
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use glam::DVec3;

    use super::{angle_between, angle_weighted};
    use crate::error::Error;
    use crate::mesh::generate::{self, analytic};
    use crate::mesh::{Mesh, NormalSource};

    fn max_angle_error(surface: &analytic::SampledSurface) -> f64 {
        let (mesh, _) =
            Mesh::from_triangles(surface.positions.clone(), surface.faces.clone()).unwrap();
        let estimated = mesh.vertex_normals(NormalSource::Estimate).unwrap();
        estimated
            .iter()
            .zip(&surface.normals)
            .map(|(&n, &exact)| {
                assert!((n.length() - 1.0).abs() < 1e-15, "not unit length: {n}");
                angle_between(n, exact)
            })
            .fold(0.0, f64::max)
    }

    #[test]
    fn symmetric_solids_get_their_exact_normals() {
        // Every vertex of a regular solid sees the same faces at the same angles around the
        // radial direction, so the angle-weighted normal is exactly radial.
        for (positions, faces) in [
            generate::tetrahedron(),
            generate::octahedron(),
            generate::icosahedron(),
        ] {
            let (mesh, _) = Mesh::from_triangles(positions.clone(), faces).unwrap();
            let normals = mesh.vertex_normals(NormalSource::Estimate).unwrap();
            for (n, p) in normals.iter().zip(&positions) {
                assert!(angle_between(*n, *p) < 1e-9, "{n} vs {p}");
            }
        }
    }

    /// Ratios of successive errors, each step halving the edge length.
    fn ratios(errors: &[f64]) -> Vec<f64> {
        errors.windows(2).map(|pair| pair[1] / pair[0]).collect()
    }

    #[test]
    fn sphere_and_ellipsoid_normals_converge_at_first_order() {
        // Angle-weighted normals are only first-order accurate on irregular neighbourhoods
        // (second order needs the point symmetry of a regular grid, see the torus test), and
        // the projected icosphere is irregular from level 2 on. Measured max angle errors,
        // levels 2..5: sphere 1.04e-2, 5.21e-3, 2.61e-3, 1.30e-3 (ratio 0.50); ellipsoid
        // (1, 0.8, 1.3) 2.29e-2, 9.40e-3, 4.33e-3, 2.11e-3 (ratios 0.41–0.49). Level 1 is exact on
        // the sphere by symmetry (1.4e-16).
        let sphere: Vec<f64> = (2..=5)
            .map(|level| max_angle_error(&analytic::sphere(level)))
            .collect();
        let ellipsoid: Vec<f64> = (2..=5)
            .map(|level| max_angle_error(&analytic::ellipsoid(DVec3::new(1.0, 0.8, 1.3), level)))
            .collect();
        println!("sphere {sphere:?}, ellipsoid {ellipsoid:?}");
        assert!(max_angle_error(&analytic::sphere(1)) < 1e-12);
        for ratio in ratios(&sphere).into_iter().chain(ratios(&ellipsoid)) {
            assert!(ratio < 0.55, "{sphere:?} {ellipsoid:?}");
        }
        assert!(sphere[3] < 1.4e-3, "{sphere:?}");
    }

    #[test]
    fn torus_grid_normals_converge_at_second_order() {
        // On the regular (u, v) grid every vertex sees its ring with point symmetry, and the
        // error falls by 4 per halving: measured 2.16e-2, 5.44e-3, 1.36e-3, 3.41e-4 rad.
        let errors: Vec<f64> = [12, 24, 48, 96]
            .iter()
            .map(|&n| max_angle_error(&analytic::torus(2 * n, n, 1.0, 0.4)))
            .collect();
        println!("torus {errors:?}");
        for ratio in ratios(&errors) {
            assert!(ratio < 0.26, "{errors:?}");
        }
    }

    #[test]
    fn cancelling_face_normals_have_no_normal() {
        // Two faces folded onto each other (vertex 3 at vertex 2's place): their normals are
        // opposite with equal angles at vertex 0, which the loader would never let through
        // but the estimator must not turn into NaN.
        let positions = [DVec3::ZERO, DVec3::X, DVec3::Y, DVec3::Y];
        let error = angle_weighted(&positions, &[[0, 1, 2], [1, 0, 3]]).unwrap_err();
        assert!(
            matches!(error, Error::UndefinedNormal { vertex: 0 }),
            "{error}"
        );
    }

    #[test]
    fn meshes_not_read_from_obj_have_no_obj_normals() {
        let (positions, faces) = generate::octahedron();
        let (mesh, _) = Mesh::from_triangles(positions, faces).unwrap();
        let error = mesh.vertex_normals(NormalSource::Obj).unwrap_err();
        assert!(
            matches!(&error, Error::MissingNormals { reason } if reason.contains("not read from an OBJ")),
            "{error}"
        );
    }
}
