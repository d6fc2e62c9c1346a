//! The loading pipeline shared by every mesh source: index and coordinate checks, welding,
//! degenerate / duplicate / non-manifold checks and consistent orientation. It ends by handing
//! the oriented faces to [`Topology::build`].

use glam::DVec3;

use super::normals::{self, CornerNormals};
use super::sharp;
use super::topology::{NO_TWIN, Topology};
use super::weld::{check_weld_tolerance, weld};
use super::{LoadOptions, LoadReport, Mesh};
use crate::error::{Error, Result};
use crate::geom::Aabb;

/// A face is degenerate when `|(b−a)×(c−a)| <= DEGENERATE_AREA_RATIO · (longest edge)²`.
///
/// The ratio is scale-free: `|(b−a)×(c−a)| / longest²` is about the sine of the face's smallest
/// angle, so faces with an angle below ~1e-14 rad (a few ulps of a unit-size coordinate) are
/// rejected. Such faces have no usable normal or tangent plane and break every scheme.
pub const DEGENERATE_AREA_RATIO: f64 = 1e-14;

/// The smallest supported bounding-box diagonal of a mesh.
///
/// Validation itself is scale-free (it works on coordinates normalised by a power of two near
/// the diagonal), but the schemes, metrics and renderer compute with the mesh's own
/// coordinates, where squared normals and fundamental-form determinants are fourth powers of
/// lengths: at spans down to 1e-60 they stay above 1e-240, far from f64's underflow (1e-308).
pub const MIN_COORDINATE_SPAN: f64 = 1e-60;

/// The largest supported coordinate magnitude (fourth powers of lengths stay below 1e241, far
/// from f64's overflow at 1.8e308; see [`MIN_COORDINATE_SPAN`]).
pub const MAX_COORDINATE_MAGNITUDE: f64 = 1e60;

/// How loading names a vertex in errors: as the input numbered it.
struct VertexNames<'a> {
    /// For each welded vertex, the first input vertex merged into it.
    representative: &'a [u32],
    /// Input index → the caller's own number (an OBJ file's `v` order); identity when None.
    labels: Option<&'a [u32]>,
}

impl VertexNames<'_> {
    fn input(&self, input: usize) -> usize {
        self.labels
            .and_then(|labels| labels.get(input))
            .map_or(input, |&label| label as usize)
    }
    fn welded(&self, v: u32) -> usize {
        self.input(self.representative[v as usize] as usize)
    }
}

/// Validates `faces` over `positions` and builds the mesh (see the module docs of `mesh` for
/// the steps). `labels` renames input vertices in errors; `corner_normals` are the file's
/// normals per face corner, or why there are none.
pub(super) fn assemble(
    positions: Vec<DVec3>,
    faces: Vec<[u32; 3]>,
    labels: Option<&[u32]>,
    corner_normals: std::result::Result<CornerNormals, String>,
    file_sharp: &[[u32; 2]],
    options: &LoadOptions,
) -> Result<(Mesh, LoadReport)> {
    let relative_tolerance =
        check_weld_tolerance(options.weld_tolerance).map_err(Error::Invalid)?;
    if faces.is_empty() {
        return Err(Error::EmptyMesh);
    }
    // Half-edges are numbered 3·face + corner in u32, with u32::MAX reserved.
    if faces.len() >= (u32::MAX / 3) as usize {
        return Err(Error::Invalid(format!(
            "the mesh has {} faces; at most {} are supported",
            faces.len(),
            u32::MAX / 3 - 1
        )));
    }
    let mut report = LoadReport::default();
    let names_in = VertexNames {
        representative: &[],
        labels,
    };
    check_indices(&positions, &faces)?;
    if let Some(v) = positions.iter().position(|p| !p.is_finite()) {
        return Err(Error::NonFiniteVertex {
            vertex: names_in.input(v),
        });
    }

    let mut used = vec![false; positions.len()];
    for &v in faces.iter().flatten() {
        used[v as usize] = true;
    }
    let bounds = check_range(&positions, &used, &names_in)?;
    let welding = weld(&positions, &used, bounds, faces, relative_tolerance, &|v| {
        names_in.input(v)
    })?;
    let mut faces = welding.faces;
    report.welded = welding.welded;
    report.welded_near = welding.welded_near;
    report.weld_max_distance = welding.max_distance;
    if welding.welded_near > 0 {
        report.warnings.push(format!(
            "welded {} vertices to a vertex less than the weld tolerance {:.1e} away ({:e} of \
             the bounding-box diagonal); largest distance merged {:.3e}",
            welding.welded_near, welding.tolerance, relative_tolerance, welding.max_distance
        ));
    }
    if welding.unused > 0 {
        report.warnings.push(format!(
            "dropped {} vertices used by no face",
            welding.unused
        ));
    }
    let names = VertexNames {
        representative: &welding.representative,
        labels,
    };
    let positions = welding.positions;

    check_degenerate(&positions, &faces, normalising_scale(&bounds))?;
    check_duplicates(&faces)?;
    let (twin, same_direction) = link_half_edges(&faces, &names)?;
    // The file's normals are matched to vertices before any face is flipped, while faces
    // still list their corners in file order.
    let obj_normals =
        normals::per_vertex_from_corners(corner_normals, &faces, positions.len(), &|v| {
            names.welded(v)
        });
    let flipped = orientation_flips(&faces, &twin, &same_direction, &names)?;
    let twin = apply_flips(&mut faces, twin, &flipped);
    let reoriented: Vec<usize> = (0..faces.len()).filter(|&f| flipped[f]).collect();
    if let Some(&first) = reoriented.first() {
        report.reoriented_faces = reoriented.len();
        report.warnings.push(format!(
            "re-oriented {} faces to agree with their neighbours (first: face {first})",
            reoriented.len()
        ));
    }
    let topology = Topology::build(&faces, twin, positions.len(), |v| names.welded(v))?;
    let file_sharp: Vec<[u32; 2]> = file_sharp
        .iter()
        .map(|pair| pair.map(|v| welding.remap[v as usize]))
        .filter(|&[a, b]| a != b && a != u32::MAX && b != u32::MAX)
        .map(|[a, b]| [a.min(b), a.max(b)])
        .collect();
    let file_sharp = {
        let mut pairs = file_sharp;
        pairs.sort_unstable();
        pairs.dedup();
        pairs
    };
    let sharp = sharp::detect(
        &positions,
        &faces,
        &topology.twin,
        &file_sharp,
        options.crease_angle,
    );
    report.sharp_edges = sharp.count();
    if options.crease_angle.is_none() && !file_sharp.is_empty() {
        let [a, b] = file_sharp[0];
        report.warnings.push(format!(
            "the file marks {} edges sharp (smoothing groups or per-corner normals; first: \
             vertices {} and {}), ignored without --crease-angle (180 keeps only those)",
            file_sharp.len(),
            names.welded(a),
            names.welded(b)
        ));
    }
    Ok((
        Mesh {
            positions,
            faces,
            obj_normals,
            topology,
            sharp,
        },
        report,
    ))
}

fn check_indices(positions: &[DVec3], faces: &[[u32; 3]]) -> Result<()> {
    for (f, face) in faces.iter().enumerate() {
        if let Some(&v) = face.iter().find(|&&v| v as usize >= positions.len()) {
            return Err(Error::VertexIndexOutOfRange {
                face: f,
                vertex: v as usize,
                count: positions.len(),
            });
        }
    }
    Ok(())
}

/// The bounding box of the used vertices, after checking that their coordinates are within
/// [`MAX_COORDINATE_MAGNITUDE`] and span at least [`MIN_COORDINATE_SPAN`] (a zero span, all
/// vertices at one point, is left to the degenerate check, which names a face).
fn check_range(positions: &[DVec3], used: &[bool], names: &VertexNames) -> Result<Aabb> {
    let used_positions = || {
        positions
            .iter()
            .zip(used)
            .filter(|(_, u)| **u)
            .map(|(p, _)| p)
    };
    let bounds = Aabb::from_points(used_positions());
    let (vertex, largest) = used_positions()
        .map(|p| p.abs().max_element())
        .enumerate()
        .fold(
            (0, 0.0),
            |best, (i, m)| if m > best.1 { (i, m) } else { best },
        );
    // Measured in units of the largest magnitude, so that huge coordinates do not overflow.
    let span = if largest > 0.0 {
        let half_extent = (0.5 / largest) * bounds.max - (0.5 / largest) * bounds.min;
        2.0 * largest * half_extent.length()
    } else {
        0.0
    };
    if largest > MAX_COORDINATE_MAGNITUDE || (span > 0.0 && span < MIN_COORDINATE_SPAN) {
        let input = (0..positions.len())
            .filter(|&v| used[v])
            .nth(vertex)
            .unwrap_or(0);
        return Err(Error::CoordinateRange {
            span,
            largest,
            vertex: names.input(input),
            min_span: MIN_COORDINATE_SPAN,
            max_magnitude: MAX_COORDINATE_MAGNITUDE,
        });
    }
    Ok(bounds)
}

/// The power of two nearest to 1 / (diagonal of `bounds`), or 1 for an empty diagonal:
/// multiplying by it maps the mesh to unit size exactly (no rounding), so geometric checks
/// on the scaled coordinates neither overflow nor underflow and give the same verdict for the
/// mesh scaled by any power of two.
fn normalising_scale(bounds: &Aabb) -> f64 {
    let span = (bounds.max - bounds.min).length();
    if span > 0.0 {
        2f64.powi(-(span.log2().round() as i32))
    } else {
        1.0
    }
}

/// Rejects faces with a repeated corner or (numerically) zero area, see
/// [`DEGENERATE_AREA_RATIO`]. Areas are computed on the coordinates times `scale` (see
/// [`normalising_scale`]).
fn check_degenerate(positions: &[DVec3], faces: &[[u32; 3]], scale: f64) -> Result<()> {
    for (f, &[a, b, c]) in faces.iter().enumerate() {
        let repeated = a == b || b == c || c == a;
        let [pa, pb, pc] = [a, b, c].map(|v| positions[v as usize] * scale);
        let longest_squared = (pb - pa)
            .length_squared()
            .max((pc - pb).length_squared())
            .max((pa - pc).length_squared());
        let twice_area = (pb - pa).cross(pc - pa).length();
        let has_area = twice_area > DEGENERATE_AREA_RATIO * longest_squared;
        if repeated || !has_area {
            return Err(Error::DegenerateFace { face: f });
        }
    }
    Ok(())
}

/// Rejects two faces on the same three vertices, in any order or orientation.
fn check_duplicates(faces: &[[u32; 3]]) -> Result<()> {
    let mut keyed: Vec<([u32; 3], u32)> = faces
        .iter()
        .enumerate()
        .map(|(f, face)| {
            let mut key = *face;
            key.sort_unstable();
            (key, f as u32)
        })
        .collect();
    keyed.sort_unstable();
    match keyed.windows(2).find(|pair| pair[0].0 == pair[1].0) {
        Some(pair) => Err(Error::DuplicateFace {
            face: pair[1].1 as usize,
            first: pair[0].1 as usize,
        }),
        None => Ok(()),
    }
}

/// Pairs the half-edges (3·face + corner, running from corner to the next) of each undirected
/// edge. Returns each half-edge's twin (or [`NO_TWIN`]) and whether it runs the same way as its
/// twin (which an oriented mesh never does). O(F log F) by sorting edge keys.
fn link_half_edges(faces: &[[u32; 3]], names: &VertexNames) -> Result<(Vec<u32>, Vec<bool>)> {
    let half_edge_count = 3 * faces.len();
    let from = |he: usize| faces[he / 3][he % 3];
    let to = |he: usize| faces[he / 3][(he + 1) % 3];
    let mut keyed: Vec<(u64, u32)> = (0..half_edge_count)
        .map(|he| {
            let (a, b) = (from(he), to(he));
            let key = (u64::from(a.min(b)) << 32) | u64::from(a.max(b));
            (key, he as u32)
        })
        .collect();
    keyed.sort_unstable();
    let mut twin = vec![NO_TWIN; half_edge_count];
    let mut same_direction = vec![false; half_edge_count];
    let mut start = 0;
    while start < keyed.len() {
        let key = keyed[start].0;
        let end = start + keyed[start..].iter().take_while(|k| k.0 == key).count();
        match end - start {
            1 => {}
            2 => {
                let (h0, h1) = (keyed[start].1, keyed[start + 1].1);
                twin[h0 as usize] = h1;
                twin[h1 as usize] = h0;
                let same = from(h0 as usize) == from(h1 as usize);
                same_direction[h0 as usize] = same;
                same_direction[h1 as usize] = same;
            }
            count => {
                return Err(Error::NonManifoldEdge {
                    a: names.welded((key >> 32) as u32),
                    b: names.welded(key as u32),
                    faces: count,
                });
            }
        }
        start = end;
    }
    Ok((twin, same_direction))
}

/// Decides which faces to flip so that every interior edge is run in opposite directions by
/// its two faces: a flood fill over each connected component, keeping the component's
/// lowest-numbered face as it is. A component that needs a face both flipped and kept is not
/// orientable (a Möbius strip).
fn orientation_flips(
    faces: &[[u32; 3]],
    twin: &[u32],
    same_direction: &[bool],
    names: &VertexNames,
) -> Result<Vec<bool>> {
    const UNSEEN: u8 = 2;
    let mut flip = vec![UNSEEN; faces.len()];
    let mut stack = Vec::new();
    for start in 0..faces.len() {
        if flip[start] != UNSEEN {
            continue;
        }
        flip[start] = 0;
        stack.push(start);
        while let Some(f) = stack.pop() {
            for e in 0..3 {
                let he = 3 * f + e;
                let t = twin[he];
                if t == NO_TWIN {
                    continue;
                }
                let g = t as usize / 3;
                let wanted = flip[f] ^ u8::from(same_direction[he]);
                if flip[g] == UNSEEN {
                    flip[g] = wanted;
                    stack.push(g);
                } else if flip[g] != wanted {
                    return Err(Error::NonOrientable {
                        a: names.welded(faces[f][e]),
                        b: names.welded(faces[f][(e + 1) % 3]),
                    });
                }
            }
        }
    }
    Ok(flip.into_iter().map(|state| state == 1).collect())
}

/// Flips the chosen faces by swapping their last two corners and renumbers the twins: a face
/// (a, b, c) becomes (a, c, b), whose edges 0, 1, 2 are the old edges 2, 1, 0 reversed.
fn apply_flips(faces: &mut [[u32; 3]], twin: Vec<u32>, flipped: &[bool]) -> Vec<u32> {
    if !flipped.contains(&true) {
        return twin;
    }
    let renumber = |he: u32| -> u32 {
        let (f, e) = (he / 3, he % 3);
        if flipped[f as usize] {
            3 * f + (2 - e)
        } else {
            he
        }
    };
    for (face, &flip) in faces.iter_mut().zip(flipped) {
        if flip {
            face.swap(1, 2);
        }
    }
    let mut renumbered = vec![NO_TWIN; twin.len()];
    for (he, &t) in twin.iter().enumerate() {
        if t != NO_TWIN {
            renumbered[renumber(he as u32) as usize] = renumber(t);
        }
    }
    renumbered
}

#[cfg(test)]
mod tests {

    use glam::DVec3;

    use crate::error::Error;
    use crate::mesh::generate::{self, bad};
    use crate::mesh::{LoadReport, Mesh};

    fn load((positions, faces): (Vec<DVec3>, Vec<[u32; 3]>)) -> crate::Result<(Mesh, LoadReport)> {
        Mesh::from_triangles(positions, faces)
    }

    #[test]
    fn clean_input_keeps_its_numbering_and_reports_nothing() {
        let (positions, faces) = generate::icosahedron();
        let (mesh, report) = load((positions.clone(), faces.clone())).unwrap();
        assert_eq!(mesh.positions(), &positions[..]);
        assert_eq!(mesh.faces(), &faces[..]);
        assert_eq!(report, LoadReport::default());
    }

    #[test]
    fn empty_mesh_is_rejected() {
        let error = load((vec![DVec3::ZERO], vec![])).unwrap_err();
        assert!(matches!(error, Error::EmptyMesh), "{error}");
    }

    #[test]
    fn out_of_range_vertex_names_face_and_index() {
        let (positions, mut faces) = generate::tetrahedron();
        faces[2][1] = 9;
        let error = load((positions, faces)).unwrap_err();
        assert!(
            matches!(
                error,
                Error::VertexIndexOutOfRange {
                    face: 2,
                    vertex: 9,
                    count: 4
                }
            ),
            "{error}"
        );
    }

    #[test]
    fn non_finite_coordinates_name_the_vertex() {
        for bad_value in [f64::NAN, f64::INFINITY, f64::NEG_INFINITY] {
            let (mut positions, faces) = generate::octahedron();
            positions[4].y = bad_value;
            let error = load((positions, faces)).unwrap_err();
            assert!(
                matches!(error, Error::NonFiniteVertex { vertex: 4 }),
                "{bad_value}: {error}"
            );
        }
    }

    #[test]
    fn repeated_corner_is_degenerate() {
        let (positions, mut faces) = generate::tetrahedron();
        faces[3] = [faces[3][0], faces[3][1], faces[3][0]];
        let error = load((positions, faces)).unwrap_err();
        assert!(
            matches!(error, Error::DegenerateFace { face: 3 }),
            "{error}"
        );
    }

    #[test]
    fn corners_that_weld_together_make_a_degenerate_face() {
        // Vertex 3 is a copy of vertex 0, so face 1 has a repeated corner after welding.
        let positions = vec![DVec3::ZERO, DVec3::X, DVec3::Y, DVec3::ZERO];
        let error = load((positions, vec![[0, 1, 2], [3, 2, 0]])).unwrap_err();
        assert!(
            matches!(error, Error::DegenerateFace { face: 1 }),
            "{error}"
        );
    }

    #[test]
    fn collinear_face_is_degenerate() {
        let error = load(bad::collinear_face()).unwrap_err();
        assert!(
            matches!(error, Error::DegenerateFace { face: 1 }),
            "{error}"
        );
    }

    #[test]
    fn degenerate_threshold_is_relative_to_the_longest_edge() {
        // |cross| / longest² is 2e-14 and 0.5e-14: just above and just below the threshold,
        // at scales where an absolute threshold would misjudge both, down to and up to the
        // ends of the supported range.
        for scale in [1e6, 1e-20, 1e20, 1e-59, 1e59] {
            for (height, degenerate) in [(2e-14, false), (0.5e-14, true)] {
                let positions = vec![
                    DVec3::ZERO,
                    DVec3::X * scale,
                    DVec3::new(0.5, height, 0.0) * scale,
                ];
                let result = load((positions, vec![[0, 1, 2]]));
                assert_eq!(
                    matches!(result, Err(Error::DegenerateFace { face: 0 })),
                    degenerate,
                    "height {height} at scale {scale}"
                );
            }
        }
    }

    fn scaled((positions, faces): generate::Triangles, scale: f64) -> generate::Triangles {
        (positions.iter().map(|&p| p * scale).collect(), faces)
    }

    #[test]
    fn scaled_meshes_validate_like_the_unscaled_ones() {
        for (name, triangles) in [
            ("octahedron", generate::octahedron()),
            ("deformed icosahedron", generate::deformed_icosahedron()),
            ("genus2", generate::genus2()),
            ("seamed torus", bad::seamed_torus(12, 8)),
        ] {
            let (mesh, report) = load(triangles.clone()).unwrap();
            let normals = mesh
                .vertex_normals(crate::mesh::NormalSource::Estimate)
                .unwrap();
            for scale in [1e-20, 1e20, 1e-50, 1e50, 2f64.powi(-190), 2f64.powi(190)] {
                let (scaled_mesh, scaled_report) = load(scaled(triangles.clone(), scale)).unwrap();
                let label = format!("{name} x {scale:e}");
                assert_eq!(scaled_mesh.faces(), mesh.faces(), "{label}");
                assert_eq!(scaled_report.welded, report.welded, "{label}");
                assert_eq!(scaled_report.welded_near, report.welded_near, "{label}");
                let scaled_normals = scaled_mesh
                    .vertex_normals(crate::mesh::NormalSource::Estimate)
                    .unwrap();
                for (a, b) in normals.iter().zip(&scaled_normals) {
                    assert!(a.distance(*b) < 1e-15, "{label}: {a} vs {b}");
                }
            }
        }
    }

    #[test]
    fn coordinates_out_of_range_name_the_range() {
        for scale in [1e-100, 1e-61, 1e61, 1e100, 1e154, 1e300] {
            let error = load(scaled(generate::octahedron(), scale)).unwrap_err();
            let Error::CoordinateRange {
                span,
                largest,
                vertex,
                ..
            } = error
            else {
                panic!("x {scale:e}: expected CoordinateRange, got {error}");
            };
            assert_eq!((largest, vertex), (scale, 0), "x {scale:e}");
            // The diagonal of the octahedron's box is 2√3, computed without overflow.
            assert!(
                (span / (2.0 * 3f64.sqrt() * scale) - 1.0).abs() < 1e-15,
                "x {scale:e}: span {span:e}"
            );
            let message = error.to_string();
            assert!(
                message.starts_with("coordinates span ")
                    && message.contains("at least 1e-60")
                    && message.contains("up to 1e60"),
                "{message}"
            );
        }
        // Coordinates far from the origin are refused even when the mesh itself is small.
        let (positions, faces) = generate::tetrahedron();
        let far: Vec<DVec3> = positions.iter().map(|&p| p + DVec3::Z * 1e70).collect();
        let error = load((far, faces)).unwrap_err();
        assert!(matches!(error, Error::CoordinateRange { .. }), "{error}");
    }

    #[test]
    fn unused_vertices_do_not_count_towards_the_range() {
        let (mut positions, faces) = generate::octahedron();
        positions.push(DVec3::splat(1e200));
        let (mesh, report) = load((positions, faces)).unwrap();
        assert_eq!(mesh.vertex_count(), 6);
        assert_eq!(report.warnings, ["dropped 1 vertices used by no face"]);
    }

    #[test]
    fn duplicate_face_names_both_faces() {
        let error = load(bad::tetrahedron_with_duplicate_face()).unwrap_err();
        assert!(
            matches!(error, Error::DuplicateFace { face: 4, first: 0 }),
            "{error}"
        );
    }

    #[test]
    fn three_faces_on_an_edge_are_non_manifold() {
        let error = load(bad::book()).unwrap_err();
        assert!(
            matches!(
                error,
                Error::NonManifoldEdge {
                    a: 0,
                    b: 1,
                    faces: 3
                }
            ),
            "{error}"
        );
    }

    #[test]
    fn bow_tie_is_a_non_manifold_vertex() {
        let error = load(bad::bow_tie()).unwrap_err();
        assert!(
            matches!(error, Error::NonManifoldVertex { vertex: 0, fans: 2 }),
            "{error}"
        );
    }

    #[test]
    fn two_closed_fans_at_one_vertex_are_non_manifold() {
        // Two tetrahedra touching at one vertex (input vertex 0 of both).
        let (positions, faces) = generate::tetrahedron();
        let mut all_positions = positions.clone();
        all_positions.extend(positions[1..].iter().map(|&p| 2.0 * positions[0] - p));
        let mut all_faces = faces.clone();
        all_faces.extend(
            faces
                .iter()
                .map(|f| f.map(|v| if v == 0 { 0 } else { v + 3 })),
        );
        let error = load((all_positions, all_faces)).unwrap_err();
        assert!(
            matches!(error, Error::NonManifoldVertex { vertex: 0, fans: 2 }),
            "{error}"
        );
    }

    #[test]
    fn errors_name_vertices_by_input_index_after_dropping_and_welding() {
        // The bow-tie behind an unused vertex and a welded copy of its centre: the centre is
        // input vertex 1 (its copy, input 7, is welded into it).
        let (positions, _) = bad::bow_tie();
        let mut shifted = vec![DVec3::splat(9.0)];
        shifted.extend(&positions);
        shifted.extend([DVec3::splat(8.0), positions[0]]);
        let faces = vec![[1, 2, 5], [7, 3, 4]];
        let error = load((shifted, faces)).unwrap_err();
        assert!(
            matches!(error, Error::NonManifoldVertex { vertex: 1, fans: 2 }),
            "{error}"
        );
    }

    #[test]
    fn mobius_strip_is_not_orientable() {
        for segments in [3, 8, 15] {
            let error = load(bad::mobius_strip(segments)).unwrap_err();
            assert!(matches!(error, Error::NonOrientable { .. }), "{error}");
        }
    }

    #[test]
    fn flipped_face_is_reoriented_with_a_warning() {
        let (mesh, report) = load(bad::octahedron_with_flipped_face()).unwrap();
        assert_eq!(report.reoriented_faces, 1);
        assert_eq!(report.warnings.len(), 1, "{:?}", report.warnings);
        assert!(
            report.warnings[0].contains("face 3"),
            "{:?}",
            report.warnings
        );
        assert_eq!(mesh.faces(), &generate::octahedron().1[..]);
    }

    #[test]
    fn orientation_follows_the_first_face_of_each_component() {
        // Component 1: an octahedron whose face 0 is flipped, so the other seven flip to agree.
        // Component 2: a shifted tetrahedron with one flipped face.
        let (mut positions, mut faces) = generate::octahedron();
        faces[0].swap(1, 2);
        let (tetra_positions, tetra_faces) = generate::tetrahedron();
        let base = positions.len() as u32;
        positions.extend(tetra_positions.iter().map(|&p| p + DVec3::X * 5.0));
        faces.extend(tetra_faces.iter().map(|f| f.map(|v| v + base)));
        let last = faces.len() - 1;
        faces[last].swap(1, 2);
        let expected_first = faces[0];
        let (mesh, report) = load((positions, faces)).unwrap();
        assert_eq!(report.reoriented_faces, 8);
        assert_eq!(mesh.faces()[0], expected_first);
        assert_eq!(mesh.faces()[last], tetra_faces[3].map(|v| v + base));
        // The octahedron is now inside out, consistently: every face normal points inwards.
        for face in &mesh.faces()[..8] {
            let [a, b, c] = face.map(|v| mesh.positions()[v as usize]);
            assert!((b - a).cross(c - a).dot(a + b + c) < 0.0);
        }
    }
}
