//! Polygon meshes, the form every file reader produces, and their way into the triangle
//! pipeline: index and coordinate checks per polygon, triangulation of quads and larger
//! polygons, then [`validate::assemble`] as for any triangle list.
//!
//! Every polygon with more than three corners is split into triangles, each remembering its
//! polygon (the input face): a quad by the diagonal whose two triangles have the larger
//! smallest angle, a larger polygon by ear clipping in its best-fit plane, always clipping the
//! ear with the largest smallest angle. A planar, strictly convex polygon (see
//! [`PLANARITY_TOLERANCE`] and [`CONVEXITY_TOLERANCE`]) gives the same flat surface however it
//! is split, so only a warning says how many were split; any other polygon is a repair
//! ([`RepairKind::PolygonTriangulated`]), refused under `--strict`.

use glam::DVec3;

use super::normals::CornerNormals;
use super::repair::{Element, RepairKind, Repairs};
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
    /// The triangles, polygon by polygon.
    faces: Vec<[u32; 3]>,
    /// For each triangle corner (`3·triangle + corner`), its index in [`PolygonMesh::corners`].
    source_corner: Vec<u32>,
    /// For each triangle, the polygon it was cut from.
    polygon: Vec<u32>,
    /// Planar convex polygons with more than three corners.
    split: usize,
    /// Other polygons with more than three corners: (polygon, what is wrong with it).
    repaired: Vec<(usize, String)>,
}

/// Checks, triangulates and assembles a polygon mesh: the one path from every file format to a
/// [`Mesh`]. `labels` renames input vertices in errors (as in [`validate::assemble`]);
/// `corner_normals` index normals per polygon corner ([`PolygonMesh::corners`] order).
///
/// Errors and repairs name faces by their polygon's 0-based number in the file, also when they
/// are found on a triangle cut from it. A warning line tells how many planar convex polygons
/// were split.
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
    let triangulation = triangulate(&polygons, &label);
    let mut repairs = Repairs::new(options.strict);
    if let Some((first, problem)) = triangulation.repaired.first() {
        repairs.record(
            RepairKind::PolygonTriangulated,
            triangulation.repaired.len(),
            Element::Face(*first),
            problem.clone(),
        )?;
    }
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
    let polygon_count = polygons.arities.len();
    let (mesh, mut report) = validate::assemble(
        polygons.positions,
        triangulation.faces,
        triangulation.polygon,
        labels,
        validate::FileMarks {
            corner_normals,
            sharp: file_sharp,
        },
        options,
        repairs,
    )?;
    if split > 0 {
        report.warnings.insert(
            0,
            format!(
                "triangulated {split} faces with more than 3 corners (planar and convex): the \
                 mesh has {triangle_count} triangles from {polygon_count} faces; faces are \
                 named as the file numbers them, and face_id in EXR images is the file's face"
            ),
        );
    }
    Ok((mesh, report))
}

/// Splits every polygon into triangles (triangles are kept as they are), noting which ones
/// are not planar convex polygons.
fn triangulate(polygons: &PolygonMesh, label: &dyn Fn(usize) -> usize) -> Triangulation {
    let triangles: usize = polygons.arities.iter().map(|&a| a as usize - 2).sum();
    let mut out = Triangulation {
        faces: Vec::with_capacity(triangles),
        source_corner: Vec::with_capacity(3 * triangles),
        polygon: Vec::with_capacity(triangles),
        split: 0,
        repaired: Vec::new(),
    };
    let mut start = 0usize;
    let mut local = Vec::new();
    for (face, &arity) in polygons.arities.iter().enumerate() {
        let n = arity as usize;
        let corners = &polygons.corners[start..start + n];
        local.clear();
        if n == 3 {
            local.push([0, 1, 2]);
        } else {
            let points: Vec<DVec3> = corners
                .iter()
                .map(|&v| polygons.positions[v as usize])
                .collect();
            let shape = PolygonShape::of(&points);
            match shape.problem(corners, label) {
                None => out.split += 1,
                Some(problem) => out.repaired.push((face, problem)),
            }
            if n == 4 {
                local.extend(split_quad(&shape.points, shape.normal));
            } else {
                ear_clip(&shape.points, shape.normal, &mut local);
            }
        }
        for t in &local {
            out.faces.push(t.map(|k| corners[k]));
            out.source_corner.extend(t.map(|k| (start + k) as u32));
            out.polygon.push(face as u32);
        }
        start += n;
    }
    out
}

/// A polygon's corners in unit-size coordinates about its first corner, with its plane.
struct PolygonShape {
    /// Corner positions relative to the first corner, scaled to about unit size (so the
    /// measures are scale-free and nothing overflows or underflows).
    points: Vec<DVec3>,
    /// Unit normal of the best-fit plane (Newell's), zero for a polygon of no area.
    normal: DVec3,
    /// Largest corner-to-corner distance.
    diameter: f64,
    /// Length of Newell's vector (twice the area for a planar polygon).
    area_vector: f64,
}

impl PolygonShape {
    fn of(positions: &[DVec3]) -> PolygonShape {
        let origin = positions[0];
        let relative: Vec<DVec3> = positions.iter().map(|&p| p - origin).collect();
        let scale = relative
            .iter()
            .map(|d| d.abs().max_element())
            .fold(0.0, f64::max);
        let points: Vec<DVec3> = if scale > 0.0 && scale.is_finite() {
            relative.iter().map(|&d| d / scale).collect()
        } else {
            relative
        };
        let n = points.len();
        let mut diameter: f64 = 0.0;
        for (i, p) in points.iter().enumerate() {
            for q in &points[i + 1..] {
                diameter = diameter.max(p.distance(*q));
            }
        }
        // Newell's normal: twice the vector area, exact for planar polygons and the normal of
        // the least-squares plane's orientation for bent ones.
        let centroid = points.iter().sum::<DVec3>() / n as f64;
        let area_vector: DVec3 = (0..n)
            .map(|i| (points[i] - centroid).cross(points[(i + 1) % n] - centroid))
            .sum();
        PolygonShape {
            normal: area_vector.normalize_or_zero(),
            area_vector: area_vector.length(),
            points,
            diameter,
        }
    }

    /// Why splitting this polygon (more than three corners) is a repair — not planar within
    /// [`PLANARITY_TOLERANCE`], not strictly convex within [`CONVEXITY_TOLERANCE`], a
    /// repeated corner or no area — or None for a planar, strictly convex polygon.
    fn problem(&self, corners: &[u32], label: &dyn Fn(usize) -> usize) -> Option<String> {
        let n = corners.len();
        let points = &self.points;
        for (i, v) in corners.iter().enumerate() {
            if corners[i + 1..].contains(v) {
                return Some(format!(
                    "its corner {i} (vertex {}) is repeated",
                    label(*v as usize)
                ));
            }
        }
        let diameter = self.diameter;
        if self.area_vector.is_nan()
            || self.area_vector <= 2.0 * DEGENERATE_AREA_RATIO * diameter * diameter
        {
            return Some("it has no area".to_string());
        }
        let centroid = points.iter().sum::<DVec3>() / n as f64;
        let deviation = points
            .iter()
            .map(|p| (*p - centroid).dot(self.normal).abs())
            .fold(0.0, f64::max)
            / diameter;
        if deviation > PLANARITY_TOLERANCE {
            return Some(format!(
                "it has {n} corners and is not planar: a corner lies {deviation:.3e} of its \
                 diameter off its plane, above the tolerance {PLANARITY_TOLERANCE:.0e}"
            ));
        }
        // Every corner turns the same way as the polygon, and all turns add up to one full
        // turn (a star polygon turns the same way everywhere but winds more than once).
        let mut turning = 0.0;
        for i in 0..n {
            let incoming = points[i] - points[(i + n - 1) % n];
            let outgoing = points[(i + 1) % n] - points[i];
            let lengths = incoming.length() * outgoing.length();
            let sine = if lengths > 0.0 {
                incoming.cross(outgoing).dot(self.normal) / lengths
            } else {
                0.0
            };
            let cosine = if lengths > 0.0 {
                incoming.dot(outgoing) / lengths
            } else {
                1.0
            };
            turning += sine.atan2(cosine);
            if sine <= CONVEXITY_TOLERANCE || turning > std::f64::consts::TAU + 1e-6 {
                return Some(format!(
                    "it has {n} corners and is not convex: it turns the wrong way or winds \
                     more than once at corner {i} (vertex {})",
                    label(corners[i] as usize)
                ));
            }
        }
        None
    }
}

/// The smallest angle of the triangle `p` (radians; 0 for a degenerate one).
fn smallest_angle(p: [DVec3; 3]) -> f64 {
    (0..3)
        .map(|i| {
            let (u, v) = (p[(i + 1) % 3] - p[i], p[(i + 2) % 3] - p[i]);
            u.cross(v).length().atan2(u.dot(v))
        })
        .fold(f64::INFINITY, f64::min)
}

/// Whether the triangle `p` faces the side of `normal` (its corners turn counter-clockwise
/// seen from there).
fn faces_along(p: [DVec3; 3], normal: DVec3) -> bool {
    (p[1] - p[0]).cross(p[2] - p[0]).dot(normal) > 0.0
}

/// The two triangles of a quad (corners 0..3): by the diagonal (0, 2) or (1, 3) whose
/// triangles both face the quad's normal (the diagonal inside the quad, for a concave one)
/// and have the larger smallest angle; (0, 2) on a tie, which a square is.
fn split_quad(points: &[DVec3], normal: DVec3) -> [[usize; 3]; 2] {
    let options = [[[0, 1, 2], [0, 2, 3]], [[1, 2, 3], [1, 3, 0]]];
    let score = |pair: &[[usize; 3]; 2]| {
        let tri = |t: [usize; 3]| t.map(|k| points[k]);
        let inside = pair.iter().all(|&t| faces_along(tri(t), normal));
        let angle = smallest_angle(tri(pair[0])).min(smallest_angle(tri(pair[1])));
        (inside, angle)
    };
    let (first, second) = (score(&options[0]), score(&options[1]));
    // Prefer (1, 3) only when it is inside and the other is not, or clearly better: 1e-12
    // rad is far above the rounding of the angles and far below any visible difference.
    let better = match (first.0, second.0) {
        (false, true) => true,
        (true, false) => false,
        _ => second.1 > first.1 + 1e-12,
    };
    options[usize::from(better)]
}

/// Ear clipping in the plane of `normal`: repeatedly cuts off the ear (a convex corner whose
/// triangle holds no other corner) with the largest smallest angle, so a polygon of n corners
/// gives n − 2 triangles facing the polygon's side. Each cut changes the ears of its two
/// neighbours only, so they alone are tested again: O(n²) for n corners. When no corner is an
/// ear (a polygon that crosses itself, or one bent too far for its plane), the convex corner
/// with the best triangle is cut, else any corner with the best triangle, so the loop always
/// ends.
fn ear_clip(points: &[DVec3], normal: DVec3, out: &mut Vec<[usize; 3]>) {
    // Coordinates in the plane: u, v orthonormal to the normal.
    let normal = if normal == DVec3::ZERO {
        DVec3::Z
    } else {
        normal
    };
    let u = normal.any_orthonormal_vector();
    let v = normal.cross(u);
    let flat: Vec<(f64, f64)> = points.iter().map(|p| (p.dot(u), p.dot(v))).collect();
    let cross = |a: usize, b: usize, c: usize| {
        let (ax, ay) = flat[a];
        let (bx, by) = flat[b];
        let (cx, cy) = flat[c];
        (bx - ax) * (cy - ay) - (by - ay) * (cx - ax)
    };
    let n = points.len();
    // A doubly linked ring of the corners left.
    let mut prev: Vec<usize> = (0..n).map(|i| (i + n - 1) % n).collect();
    let mut next: Vec<usize> = (0..n).map(|i| (i + 1) % n).collect();
    let mut alive = vec![true; n];
    // (is an ear, is convex, smallest angle) per corner.
    let judge = |b: usize, prev: &[usize], next: &[usize], alive: &[bool]| {
        let (a, c) = (prev[b], next[b]);
        let convex = cross(a, b, c) > 0.0;
        let ear = convex
            && (0..n).all(|w| {
                !alive[w]
                    || w == a
                    || w == b
                    || w == c
                    || !(cross(a, b, w) >= 0.0 && cross(b, c, w) >= 0.0 && cross(c, a, w) >= 0.0)
            });
        (
            ear,
            convex,
            smallest_angle([points[a], points[b], points[c]]),
        )
    };
    let mut quality: Vec<(bool, bool, f64)> =
        (0..n).map(|b| judge(b, &prev, &next, &alive)).collect();
    for _ in 0..n - 3 {
        let mut best = None;
        for b in (0..n).filter(|&b| alive[b]) {
            if best.is_none_or(|best: usize| quality[b] > quality[best]) {
                best = Some(b);
            }
        }
        let Some(b) = best else { break };
        let (a, c) = (prev[b], next[b]);
        out.push([a, b, c]);
        alive[b] = false;
        next[a] = c;
        prev[c] = a;
        quality[a] = judge(a, &prev, &next, &alive);
        quality[c] = judge(c, &prev, &next, &alive);
    }
    let last = (0..n).find(|&b| alive[b]).unwrap_or(0);
    out.push([prev[last], last, next[last]]);
}

#[cfg(test)]
mod tests {
    use glam::DVec3;

    use super::PolygonMesh;
    use crate::error::Error;
    use crate::mesh::{Element, LoadOptions, Mesh, RepairKind};

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

    /// Polygons given as corner lists go through the pipeline of the files: the cube of
    /// quads is the same mesh either way, and a bad corner count or index names the polygon.
    #[test]
    fn polygons_given_as_lists_load_as_a_file_would() {
        let cube = cube();
        let (from_file, file_report) = load(cube.clone()).expect("the cube loads");
        let (given, report) = Mesh::from_polygons_with(
            cube.positions.clone(),
            cube.corners.clone(),
            cube.arities.clone(),
            &LoadOptions::default(),
        )
        .expect("the cube loads");
        assert_eq!(given.faces(), from_file.faces());
        assert_eq!(given.positions(), from_file.positions());
        assert_eq!(given.face_origins(), from_file.face_origins());
        assert_eq!(report.warnings, file_report.warnings);
        assert_eq!(given.face_count(), 12);
        let short = Mesh::from_polygons_with(
            cube.positions.clone(),
            cube.corners.clone(),
            vec![4; 5],
            &LoadOptions::default(),
        )
        .expect_err("20 corners counted, 24 given");
        assert!(short.to_string().contains("add up to 20"), "{short}");
        let mut corners = cube.corners.clone();
        corners[9] = 8;
        let out = Mesh::from_polygons_with(
            cube.positions,
            corners,
            cube.arities,
            &LoadOptions::default(),
        )
        .expect_err("vertex 8 does not exist");
        assert!(
            matches!(
                out,
                Error::VertexIndexOutOfRange {
                    face: 2,
                    vertex: 8,
                    count: 8
                }
            ),
            "{out}"
        );
    }

    /// The refusal of `--strict`, which must name `element`.
    fn strict_refusal(polygons: PolygonMesh, element: &str) -> String {
        let options = LoadOptions {
            strict: true,
            ..Default::default()
        };
        match super::assemble(polygons, None, Err("no normals".to_string()), &[], &options) {
            Err(error @ Error::RepairRefused { .. }) => {
                let message = error.to_string();
                assert!(message.starts_with(&format!("{element}: ")), "{message}");
                message
            }
            Err(other) => panic!("expected a refused repair of {element}, got {other}"),
            Ok(_) => panic!("expected a refused repair of {element}, got a mesh"),
        }
    }

    /// The (kind, count, first element) of every repair.
    fn repairs(report: &crate::mesh::LoadReport) -> Vec<(RepairKind, usize, Element)> {
        report
            .repairs
            .iter()
            .map(|r| (r.kind, r.count, r.first))
            .collect()
    }

    #[test]
    fn planar_convex_quads_are_split_with_a_warning_and_no_repair() {
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
    fn a_bent_quad_is_split_as_a_repair_and_refused_when_strict() {
        let mut polygons = cube();
        // Lift one corner of face 1 (z = 1, corners 4 5 7 6) by 5% of the edge.
        polygons.positions[7].z += 0.05;
        let (mesh, report) = load(polygons.clone()).unwrap();
        // Faces 1, 3 and 5 all contain vertex 7, but only face 1 is bent: the lift stays in
        // the planes of the other two.
        assert_eq!(
            repairs(&report),
            [(RepairKind::PolygonTriangulated, 1, Element::Face(1))]
        );
        assert_eq!(mesh.face_count(), 12);
        assert!(mesh.is_closed());
        // Triangles name the quads they were cut from.
        assert_eq!(
            (0..12).map(|t| mesh.input_face(t)).collect::<Vec<_>>(),
            [0, 0, 1, 1, 2, 2, 3, 3, 4, 4, 5, 5]
        );
        let message = strict_refusal(polygons, "face 1");
        assert!(message.contains("4 corners and is not planar"), "{message}");
    }

    #[test]
    fn a_bent_quad_is_split_by_the_diagonal_giving_the_better_triangles() {
        // A long thin quad, bent: the diagonal (0, 2) gives a sliver pair, (1, 3) a fair one.
        let mut polygons = PolygonMesh {
            positions: vec![
                DVec3::new(0.0, 0.0, 0.0),
                DVec3::new(4.0, 0.0, 0.0),
                DVec3::new(4.2, 1.0, 0.2),
                DVec3::new(0.2, 1.0, 0.0),
            ],
            ..Default::default()
        };
        polygons.push_polygon(&[1, 2, 3, 0]);
        let (mesh, _) = load(polygons).unwrap();
        // Written from corner 1, so (0, 2) of the polygon is the mesh's (1, 3).
        assert_eq!(mesh.faces(), &[[1, 2, 3], [1, 3, 0]]);
    }

    #[test]
    fn a_quad_bent_within_the_tolerance_is_split_without_a_repair() {
        let mut polygons = cube();
        // 1e-6 of the edge: what rounding to 6 digits does.
        polygons.positions[7] += DVec3::splat(1e-6);
        let (_, report) = load(polygons).unwrap();
        assert!(report.repairs.is_empty(), "{:?}", report.warnings);
    }

    #[test]
    fn a_concave_quad_is_split_inside_and_refused_when_strict() {
        // An arrowhead: corner 2 is reflex, so only the diagonal (0, 2) lies inside.
        let mut polygons = PolygonMesh {
            positions: vec![
                DVec3::new(0.0, 0.0, 0.0),
                DVec3::new(2.0, 0.0, 0.0),
                DVec3::new(0.5, 0.5, 0.0),
                DVec3::new(0.0, 2.0, 0.0),
            ],
            ..Default::default()
        };
        polygons.push_polygon(&[0, 1, 2, 3]);
        let (mesh, report) = load(polygons.clone()).unwrap();
        assert_eq!(mesh.faces(), &[[0, 1, 2], [0, 2, 3]]);
        assert_eq!(
            repairs(&report),
            [(RepairKind::PolygonTriangulated, 1, Element::Face(0))]
        );
        let message = strict_refusal(polygons, "face 0");
        assert!(
            message.contains("is not convex") && message.contains("corner 2 (vertex 2)"),
            "{message}"
        );
    }

    #[test]
    fn concave_n_gons_are_ear_clipped_inside_the_polygon() {
        // An L-shaped hexagon and a comb-shaped 12-gon in a tilted plane, far from the origin.
        let tilt = |x: f64, y: f64| DVec3::new(1e8 + x, 1e8 + y * 0.8, 1e8 + y * 0.6);
        for outline in [
            vec![
                (0.0, 0.0),
                (2.0, 0.0),
                (2.0, 1.0),
                (1.0, 1.0),
                (1.0, 2.0),
                (0.0, 2.0),
            ],
            vec![
                (0.0, 0.0),
                (5.0, 0.0),
                (5.0, 3.0),
                (4.0, 3.0),
                (4.0, 1.0),
                (3.0, 1.0),
                (3.0, 3.0),
                (2.0, 3.0),
                (2.0, 1.0),
                (1.0, 1.0),
                (1.0, 3.0),
                (0.0, 3.0),
            ],
        ] {
            let n = outline.len();
            let mut polygons = PolygonMesh {
                positions: outline.iter().map(|&(x, y)| tilt(x, y)).collect(),
                ..Default::default()
            };
            polygons.push_polygon(&(0..n as u32).collect::<Vec<_>>());
            let area: f64 = (0..n)
                .map(|i| {
                    let (a, b) = (outline[i], outline[(i + 1) % n]);
                    0.5 * (a.0 * b.1 - a.1 * b.0)
                })
                .sum();
            let (mesh, report) = load(polygons).unwrap();
            assert_eq!(mesh.face_count(), n - 2);
            assert_eq!(report.repairs[0].kind, RepairKind::PolygonTriangulated);
            // The triangles all face the polygon's side and cover exactly its area.
            let normal = DVec3::new(0.0, -0.6, 0.8);
            let mut covered = 0.0;
            for t in 0..mesh.face_count() as u32 {
                assert!(
                    mesh.face_normal(t).dot(normal) > 1.0 - 1e-9,
                    "{n}-gon face {t}"
                );
                let [a, b, c] = mesh.faces()[t as usize].map(|v| mesh.positions()[v as usize]);
                covered += 0.5 * (b - a).cross(c - a).length();
            }
            assert!(
                (covered - area).abs() < 1e-6 * area,
                "{n}-gon: {covered} vs {area}"
            );
        }
    }

    #[test]
    fn a_straight_corner_avoids_a_sliver_and_a_star_is_still_split() {
        // Corner 1 lies on the edge from corner 0 to corner 2: the diagonal (1, 3) avoids the
        // zero-area triangle (0, 1, 2).
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
        let (mesh, report) = load(straight.clone()).unwrap();
        assert_eq!(mesh.faces(), &[[1, 2, 3], [1, 3, 0]]);
        assert_eq!(
            repairs(&report),
            [(RepairKind::PolygonTriangulated, 1, Element::Face(0))]
        );
        strict_refusal(straight, "face 0");
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
        let (mesh, report) = load(star.clone()).unwrap();
        assert_eq!(mesh.face_count(), 3);
        assert_eq!(report.repairs[0].kind, RepairKind::PolygonTriangulated);
        let message = strict_refusal(star, "face 0");
        assert!(message.contains("winds more than once"), "{message}");
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
        // A repeated corner and two corners at one position are repairs.
        let mut repeated = cube();
        repeated.corners[3] = 0;
        let message = strict_refusal(repeated.clone(), "face 0");
        assert!(message.contains("is repeated"), "{message}");
        assert!(load(repeated).is_ok());
        let mut coincident = cube();
        coincident.positions[3] = coincident.positions[2];
        strict_refusal(coincident.clone(), "face 0");
        assert!(load(coincident).is_ok());
        assert!(matches!(
            load(PolygonMesh::default()).unwrap_err(),
            Error::EmptyMesh
        ));
    }

    #[test]
    fn repairs_on_cut_triangles_name_the_polygon() {
        let mut polygons = cube();
        // A seventh quad repeating the first: its triangles duplicate those of face 0.
        polygons.push_polygon(&[0, 2, 3, 1]);
        let (mesh, report) = load(polygons.clone()).unwrap();
        assert_eq!(
            repairs(&report),
            [(RepairKind::DuplicateFaceRemoved, 2, Element::Face(6))]
        );
        assert!(
            report.warnings[1].contains("(first: face 6: repeats face 0"),
            "{:?}",
            report.warnings
        );
        assert_eq!(mesh.face_count(), 12);
        strict_refusal(polygons, "face 6");
    }
}
