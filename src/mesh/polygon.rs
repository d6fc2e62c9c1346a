//! Polygon meshes, the form every file reader produces, and their way into the triangle
//! pipeline: index and coordinate checks per polygon, triangulation of quads and larger
//! polygons, then [`validate::assemble`] as for any triangle list.
//!
//! A polygon with more than three corners is split into a fan of triangles from its first
//! corner when it is planar and strictly convex, where every split gives the same flat surface
//! (see [`PLANARITY_TOLERANCE`] and [`CONVEXITY_TOLERANCE`]). Any other polygon is refused:
//! how a bent or concave polygon is split changes every surface built on it, so that choice
//! stays with the modeller that made the file.

use glam::DVec3;

use super::normals::CornerNormals;
use super::validate::{self, DEGENERATE_AREA_RATIO};
use super::{LoadOptions, LoadReport, Mesh};
use crate::error::{Error, Result};

/// Largest distance of a polygon's corner from the polygon's plane, relative to the polygon's
/// diameter (its largest corner-to-corner distance), for the polygon to count as planar and be
/// triangulated.
///
/// A thousandth of the diameter is far above what writing coordinates with 6 significant
/// digits does to a planar polygon (a few 10⁻⁶ of the coordinates, at most ~10⁻⁴ of a small
/// polygon far from the origin), and far below a visible fold: the two ways of splitting a quad
/// bent by that much differ by a crease of about 0.2°.
pub const PLANARITY_TOLERANCE: f64 = 1e-3;

/// Smallest sine of the turning angle at every corner of a polygon (in the polygon's plane,
/// in the direction of its orientation) for the polygon to count as strictly convex. A corner
/// turning less than that (a straight or reflex corner) would give a fan triangle of about
/// zero area or one outside the polygon.
pub const CONVEXITY_TOLERANCE: f64 = 1e-10;

/// A mesh as a file stores it: positions and polygons of any size, in file order.
#[derive(Clone, Debug, Default, PartialEq)]
pub(super) struct PolygonMesh {
    /// Vertex positions, numbered as the file numbers them.
    pub(super) positions: Vec<DVec3>,
    /// The corners of every polygon, concatenated in file order.
    pub(super) corners: Vec<u32>,
    /// The number of corners of each polygon.
    pub(super) arities: Vec<u32>,
}

impl PolygonMesh {
    /// Appends a polygon.
    pub(super) fn push_polygon(&mut self, corners: &[u32]) {
        self.corners.extend_from_slice(corners);
        self.arities.push(corners.len() as u32);
    }
}

/// Triangles cut from polygons, each remembering where it came from.
struct Triangulation {
    /// The triangles, polygon by polygon, each polygon's as a fan from its first corner.
    faces: Vec<[u32; 3]>,
    /// For each triangle corner (`3·triangle + corner`), its index in [`PolygonMesh::corners`].
    source_corner: Vec<u32>,
    /// For each triangle, the polygon it was cut from.
    polygon: Vec<u32>,
    /// Polygons with more than three corners.
    split: usize,
}

/// Checks, triangulates and assembles a polygon mesh: the one path from every file format to a
/// [`Mesh`]. `labels` renames input vertices in errors (as in [`validate::assemble`]);
/// `corner_normals` index normals per polygon corner ([`PolygonMesh::corners`] order).
///
/// Errors name faces by their polygon's 0-based number in the file, also when they are found
/// on a triangle cut from it. A warning line tells how many polygons were split.
pub(super) fn assemble(
    polygons: PolygonMesh,
    labels: Option<&[u32]>,
    corner_normals: std::result::Result<CornerNormals, String>,
    file_sharp: &[[u32; 2]],
    options: &LoadOptions,
) -> Result<(Mesh, LoadReport)> {
    if polygons.arities.is_empty() {
        return Err(Error::EmptyMesh);
    }
    let label = |v: usize| labels.and_then(|l| l.get(v)).map_or(v, |&l| l as usize);
    let count = polygons.positions.len();
    let mut start = 0;
    for (face, &arity) in polygons.arities.iter().enumerate() {
        let corners = &polygons.corners[start..start + arity as usize];
        if arity < 3 {
            return Err(Error::NotATriangle {
                face,
                corners: arity as usize,
            });
        }
        if let Some(&vertex) = corners.iter().find(|&&v| v as usize >= count) {
            return Err(Error::VertexIndexOutOfRange {
                face,
                vertex: vertex as usize,
                count,
            });
        }
        start += arity as usize;
    }
    if let Some(v) = polygons.positions.iter().position(|p| !p.is_finite()) {
        return Err(Error::NonFiniteVertex { vertex: label(v) });
    }
    let triangulation = triangulate(&polygons, &label)?;
    let corner_normals = corner_normals.map(|normals| CornerNormals {
        corner: triangulation
            .source_corner
            .iter()
            .map(|&c| normals.corner[c as usize])
            .collect(),
        normals: normals.normals,
    });
    let split = triangulation.split;
    let triangle_count = triangulation.faces.len();
    let polygon_of = triangulation.polygon;
    let (mesh, mut report) = validate::assemble(
        polygons.positions,
        triangulation.faces,
        labels,
        corner_normals,
        file_sharp,
        options,
    )
    .map_err(|e| name_polygon(e, &polygon_of))?;
    if split > 0 {
        report.warnings.insert(
            0,
            format!(
                "triangulated {split} faces with more than 3 corners (planar and convex, split \
                 as a fan from their first corner): the mesh has {triangle_count} triangles \
                 from {} faces, numbered as triangles from here on",
                polygon_of.last().map_or(0, |&p| p as usize + 1)
            ),
        );
    }
    Ok((mesh, report))
}

/// Renames the triangle named by a face error to the polygon it was cut from.
fn name_polygon(error: Error, polygon: &[u32]) -> Error {
    let rename = |f: usize| polygon.get(f).map_or(f, |&p| p as usize);
    match error {
        Error::DegenerateFace { face } => Error::DegenerateFace { face: rename(face) },
        Error::DuplicateFace { face, first } => Error::DuplicateFace {
            face: rename(face),
            first: rename(first),
        },
        Error::WeldCollapsesFace {
            face,
            a,
            b,
            distance,
            tolerance,
        } => Error::WeldCollapsesFace {
            face: rename(face),
            a,
            b,
            distance,
            tolerance,
        },
        other => other,
    }
}

/// Splits every polygon into triangles (triangles are kept as they are); refuses polygons that
/// repeat a corner, are not planar or not strictly convex.
fn triangulate(polygons: &PolygonMesh, label: &dyn Fn(usize) -> usize) -> Result<Triangulation> {
    let triangles: usize = polygons.arities.iter().map(|&a| a as usize - 2).sum();
    let mut out = Triangulation {
        faces: Vec::with_capacity(triangles),
        source_corner: Vec::with_capacity(3 * triangles),
        polygon: Vec::with_capacity(triangles),
        split: 0,
    };
    let mut start = 0usize;
    for (face, &arity) in polygons.arities.iter().enumerate() {
        let n = arity as usize;
        let corners = &polygons.corners[start..start + n];
        if n > 3 {
            check_convex_planar(face, corners, &polygons.positions, label)?;
            out.split += 1;
        }
        for k in 1..n - 1 {
            out.faces.push([corners[0], corners[k], corners[k + 1]]);
            out.source_corner
                .extend([start, start + k, start + k + 1].map(|c| c as u32));
            out.polygon.push(face as u32);
        }
        start += n;
    }
    Ok(out)
}

/// Checks that polygon `face` (more than three corners, finite positions) has distinct
/// corners, is planar within [`PLANARITY_TOLERANCE`] and strictly convex within
/// [`CONVEXITY_TOLERANCE`], so that a fan from its first corner covers it exactly.
fn check_convex_planar(
    face: usize,
    corners: &[u32],
    positions: &[DVec3],
    label: &dyn Fn(usize) -> usize,
) -> Result<()> {
    let n = corners.len();
    for (i, v) in corners.iter().enumerate() {
        if corners[i + 1..].contains(v) {
            return Err(Error::DegenerateFace { face });
        }
    }
    // Coordinates relative to the first corner, scaled to about unit size: the tests are
    // scale-free and nothing overflows or underflows.
    let origin = positions[corners[0] as usize];
    let relative: Vec<DVec3> = corners
        .iter()
        .map(|&v| positions[v as usize] - origin)
        .collect();
    let scale = relative
        .iter()
        .map(|d| d.abs().max_element())
        .fold(0.0, f64::max);
    if !scale.is_finite() {
        // Coordinates far out of range: the range check that follows names the vertex.
        return Ok(());
    }
    if scale == 0.0 {
        return Err(Error::DegenerateFace { face });
    }
    let points: Vec<DVec3> = relative.iter().map(|&d| d / scale).collect();
    let mut diameter: f64 = 0.0;
    for (i, p) in points.iter().enumerate() {
        for q in &points[i + 1..] {
            diameter = diameter.max(p.distance(*q));
        }
    }
    // Newell's normal: twice the vector area, exact for planar polygons.
    let centroid = points.iter().sum::<DVec3>() / n as f64;
    let area_vector: DVec3 = (0..n)
        .map(|i| (points[i] - centroid).cross(points[(i + 1) % n] - centroid))
        .sum();
    if area_vector.length() <= 2.0 * DEGENERATE_AREA_RATIO * diameter * diameter {
        return Err(Error::DegenerateFace { face });
    }
    let normal = area_vector.normalize();
    let deviation = points
        .iter()
        .map(|p| (*p - centroid).dot(normal).abs())
        .fold(0.0, f64::max)
        / diameter;
    if deviation > PLANARITY_TOLERANCE {
        return Err(Error::NonPlanarFace {
            face,
            corners: n,
            deviation,
            tolerance: PLANARITY_TOLERANCE,
        });
    }
    // Every corner turns the same way as the polygon, and all turns add up to one full turn
    // (a star polygon turns the same way everywhere but winds more than once).
    let mut turning = 0.0;
    for i in 0..n {
        let incoming = points[i] - points[(i + n - 1) % n];
        let outgoing = points[(i + 1) % n] - points[i];
        let lengths = incoming.length() * outgoing.length();
        if lengths == 0.0 {
            // Two consecutive corners at one position.
            return Err(Error::DegenerateFace { face });
        }
        let sine = incoming.cross(outgoing).dot(normal) / lengths;
        let cosine = incoming.dot(outgoing) / lengths;
        turning += sine.atan2(cosine);
        if sine <= CONVEXITY_TOLERANCE || turning > std::f64::consts::TAU + 1e-6 {
            return Err(Error::NonConvexFace {
                face,
                corners: n,
                corner: i,
                vertex: label(corners[i] as usize),
            });
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use glam::DVec3;

    use super::{PLANARITY_TOLERANCE, PolygonMesh};
    use crate::error::Error;
    use crate::mesh::{LoadOptions, Mesh};

    /// A closed cube of six quads (outward orientation), vertex `i` at the bits of `i`.
    fn cube() -> PolygonMesh {
        let mut mesh = PolygonMesh {
            positions: (0..8)
                .map(|i| DVec3::new((i & 1) as f64, ((i >> 1) & 1) as f64, (i >> 2) as f64))
                .collect(),
            ..Default::default()
        };
        for quad in [
            [0, 2, 3, 1],
            [4, 5, 7, 6],
            [0, 1, 5, 4],
            [2, 6, 7, 3],
            [0, 4, 6, 2],
            [1, 3, 7, 5],
        ] {
            mesh.push_polygon(&quad);
        }
        mesh
    }

    fn load(polygons: PolygonMesh) -> crate::error::Result<(Mesh, crate::mesh::LoadReport)> {
        super::assemble(
            polygons,
            None,
            Err("no normals".to_string()),
            &[],
            &LoadOptions::default(),
        )
    }

    #[test]
    fn quads_are_split_into_fans_with_a_warning() {
        let (mesh, report) = load(cube()).unwrap();
        assert_eq!((mesh.vertex_count(), mesh.face_count()), (8, 12));
        assert!(mesh.is_closed());
        assert_eq!(mesh.euler_characteristic(), 2);
        // The fan of the first quad: (0, 2, 3) and (0, 3, 1).
        assert_eq!(&mesh.faces()[..2], &[[0, 2, 3], [0, 3, 1]]);
        assert!(
            report.warnings[0].starts_with("triangulated 6 faces with more than 3 corners"),
            "{:?}",
            report.warnings
        );
    }

    #[test]
    fn a_convex_hexagon_becomes_four_triangles() {
        let mut polygons = PolygonMesh {
            positions: (0..6)
                .map(|k| {
                    let a = k as f64 * std::f64::consts::TAU / 6.0;
                    DVec3::new(a.cos(), a.sin(), 0.0)
                })
                .collect(),
            ..Default::default()
        };
        polygons.push_polygon(&[0, 1, 2, 3, 4, 5]);
        let (mesh, report) = load(polygons).unwrap();
        assert_eq!(mesh.face_count(), 4);
        assert!(report.warnings[0].contains("triangulated 1 faces"));
    }

    #[test]
    fn a_bent_quad_is_refused_naming_the_face() {
        let mut polygons = cube();
        // Lift one corner of face 1 (z = 1, corners 4 5 7 6) by 5% of the edge.
        polygons.positions[7].z += 0.05;
        match load(polygons).unwrap_err() {
            Error::NonPlanarFace {
                face, deviation, ..
            } => {
                // Faces 1, 3 and 5 all contain vertex 7; face 1 is found first.
                assert_eq!(face, 1);
                assert!(deviation > PLANARITY_TOLERANCE, "{deviation}");
            }
            other => panic!("expected NonPlanarFace, got {other:?}"),
        }
    }

    #[test]
    fn a_quad_bent_within_the_tolerance_is_split() {
        let mut polygons = cube();
        // 1e-6 of the edge: what rounding to 6 digits does.
        polygons.positions[7] += DVec3::splat(1e-6);
        assert!(load(polygons).is_ok());
    }

    #[test]
    fn a_concave_quad_is_refused_naming_face_corner_and_vertex() {
        let mut polygons = PolygonMesh {
            positions: vec![
                DVec3::new(0.0, 0.0, 0.0),
                DVec3::new(2.0, 0.0, 0.0),
                DVec3::new(0.5, 0.5, 0.0),
                DVec3::new(0.0, 2.0, 0.0),
            ],
            ..Default::default()
        };
        polygons.push_polygon(&[0, 1, 2]);
        polygons.push_polygon(&[0, 1, 2, 3]);
        let err = load(polygons).unwrap_err();
        assert!(
            matches!(
                err,
                Error::NonConvexFace {
                    face: 1,
                    corners: 4,
                    corner: 2,
                    vertex: 2
                }
            ),
            "{err:?}"
        );
        assert!(err.to_string().contains("face 1 (4 corners) is not convex"));
    }

    #[test]
    fn a_straight_corner_and_a_star_are_refused() {
        // Corner 1 lies on the edge from corner 0 to corner 2.
        let mut straight = PolygonMesh {
            positions: vec![
                DVec3::new(0.0, 0.0, 0.0),
                DVec3::new(1.0, 0.0, 0.0),
                DVec3::new(2.0, 0.0, 0.0),
                DVec3::new(0.0, 2.0, 0.0),
            ],
            ..Default::default()
        };
        straight.push_polygon(&[0, 1, 2, 3]);
        assert!(matches!(
            load(straight).unwrap_err(),
            Error::NonConvexFace { corner: 1, .. }
        ));
        // A pentagram turns the same way at every corner but winds twice.
        let mut star = PolygonMesh {
            positions: (0..5)
                .map(|k| {
                    let a = (2 * k) as f64 * std::f64::consts::TAU / 5.0;
                    DVec3::new(a.cos(), a.sin(), 0.0)
                })
                .collect(),
            ..Default::default()
        };
        star.push_polygon(&[0, 1, 2, 3, 4]);
        assert!(matches!(
            load(star).unwrap_err(),
            Error::NonConvexFace { face: 0, .. }
        ));
    }

    #[test]
    fn bad_polygons_are_refused_before_triangulation() {
        let mut short = cube();
        short.push_polygon(&[0, 1]);
        assert!(matches!(
            load(short).unwrap_err(),
            Error::NotATriangle {
                face: 6,
                corners: 2
            }
        ));
        let mut out_of_range = cube();
        out_of_range.push_polygon(&[0, 1, 8, 2]);
        assert!(matches!(
            load(out_of_range).unwrap_err(),
            Error::VertexIndexOutOfRange {
                face: 6,
                vertex: 8,
                count: 8
            }
        ));
        let mut nan = cube();
        nan.positions[5].y = f64::NAN;
        assert!(matches!(
            load(nan).unwrap_err(),
            Error::NonFiniteVertex { vertex: 5 }
        ));
        let mut repeated = cube();
        repeated.corners[3] = 0;
        assert!(matches!(
            load(repeated).unwrap_err(),
            Error::DegenerateFace { face: 0 }
        ));
        let mut coincident = cube();
        coincident.positions[3] = coincident.positions[2];
        assert!(matches!(
            load(coincident).unwrap_err(),
            Error::DegenerateFace { face: 0 }
        ));
        assert!(matches!(
            load(PolygonMesh::default()).unwrap_err(),
            Error::EmptyMesh
        ));
    }

    #[test]
    fn errors_on_cut_triangles_name_the_polygon() {
        let mut polygons = cube();
        // A seventh quad repeating the first: its triangles duplicate those of face 0.
        polygons.push_polygon(&[0, 2, 3, 1]);
        match load(polygons).unwrap_err() {
            Error::DuplicateFace { face, first } => assert_eq!((face, first), (6, 0)),
            other => panic!("expected DuplicateFace, got {other:?}"),
        }
    }
}
