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
