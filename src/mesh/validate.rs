//! The loading pipeline shared by every mesh source: index and coordinate checks, welding,
//! degenerate / duplicate / non-manifold checks and consistent orientation. It ends by handing
//! the oriented faces to [`Topology::build`].

use glam::DVec3;

use super::normals::{self, CornerNormals};
use super::repair::{
    Element, Orientation, RepairKind, Repairs, collapse_degenerate, orient_cutting, pair_fan,
    split_fans,
};
use super::sharp;
use super::topology::{NO_TWIN, Topology};
use super::unfold;
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

/// The faces being repaired, with what each one remembers: its input face, its corners
/// before welding and the file's normal per corner.
struct FaceList {
    faces: Vec<[u32; 3]>,
    origin: Vec<u32>,
    input: Vec<[u32; 3]>,
    normal_corners: Option<Vec<u32>>,
}

impl FaceList {
    /// Keeps the faces whose `keep` flag is set, in order.
    fn retain(&mut self, keep: &[bool]) {
        let kept = |f: &usize| keep[*f];
        let pick = |list: &[[u32; 3]]| -> Vec<[u32; 3]> {
            (0..list.len()).filter(kept).map(|f| list[f]).collect()
        };
        self.faces = pick(&self.faces);
        self.input = pick(&self.input);
        self.origin = (0..self.origin.len())
            .filter(kept)
            .map(|f| self.origin[f])
            .collect();
        if let Some(corners) = &mut self.normal_corners {
            *corners = (0..keep.len())
                .filter(kept)
                .flat_map(|f| [corners[3 * f], corners[3 * f + 1], corners[3 * f + 2]])
                .collect();
        }
    }
}

/// What a file says about its surface besides positions and faces.
pub(super) struct FileMarks<'a> {
    /// The file's normals per face corner, or why there are none.
    pub(super) corner_normals: std::result::Result<CornerNormals, String>,
    /// Edges the file marks sharp (smoothing groups, differing per-corner normals), as input
    /// vertex pairs.
    pub(super) sharp: &'a [[u32; 2]],
}

impl FileMarks<'_> {
    /// No normals (for the reason `why`) and no sharp edges.
    pub(super) fn none(why: &str) -> FileMarks<'static> {
        FileMarks {
            corner_normals: Err(why.to_string()),
            sharp: &[],
        }
    }
}

/// Validates and repairs `faces` over `positions` and builds the mesh (see the module docs of
/// `mesh` for the steps). `origin` is each triangle's input face (the polygon it was cut
/// from); `labels` renames input vertices in errors; `marks` are the file's normals and sharp
/// edges; `repairs` holds the repairs made so far.
pub(super) fn assemble(
    positions: Vec<DVec3>,
    faces: Vec<[u32; 3]>,
    origin: Vec<u32>,
    labels: Option<&[u32]>,
    marks: FileMarks<'_>,
    options: &LoadOptions,
    mut repairs: Repairs,
) -> Result<(Mesh, LoadReport)> {
    let FileMarks {
        corner_normals,
        sharp: file_sharp,
    } = marks;
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
    let input_faces = faces.clone();
    let welding = weld(&positions, &used, bounds, faces, relative_tolerance, &|v| {
        names_in.input(v)
    })?;
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
    let tolerance = welding.tolerance;
    let mut list = FaceList {
        faces: welding.faces,
        origin,
        input: input_faces,
        normal_corners: corner_normals.as_ref().ok().map(|n| n.corner.clone()),
    };
    let input_positions = positions;
    let mut representative = welding.representative;
    let mut positions = welding.positions;
    let scale = normalising_scale(&bounds);
    let weld = WeldNames {
        positions: &input_positions,
        names: &names_in,
        tolerance,
    };

    // Degenerate faces: a repeated corner (as written, or made by welding), then duplicates,
    // then zero area with distinct corners.
    let repeated: Vec<bool> = list
        .faces
        .iter()
        .map(|&[a, b, c]| a == b || b == c || c == a)
        .collect();
    if let Some(first) = repeated.iter().position(|&r| r) {
        let detail = match &welding.first_collapse {
            Some(collapse) if collapse.face == first => format!(
                "{}; the face is removed",
                weld.note(collapse.a, collapse.b, collapse.distance)
            ),
            _ => "a corner is repeated; the face is removed".to_string(),
        };
        repairs.record(
            RepairKind::DegenerateFaceCollapsed,
            repeated.iter().filter(|&&r| r).count(),
            Element::Face(list.origin[first] as usize),
            detail,
        )?;
        list.retain(&repeated.iter().map(|r| !r).collect::<Vec<_>>());
    }
    let duplicates = find_duplicates(&list.faces);
    if let Some(&(face, first)) = duplicates.first() {
        let mut detail = format!("repeats face {}", list.origin[first] as usize);
        if let Some((a, b)) = weld.merged_between(&list, face, first) {
            let distance = input_positions[a].distance(input_positions[b]);
            detail += &format!(" after {}", weld.note_input(a, b, distance));
        }
        detail += "; the later face is removed";
        repairs.record(
            RepairKind::DuplicateFaceRemoved,
            duplicates.len(),
            Element::Face(list.origin[face] as usize),
            detail,
        )?;
        let mut keep = vec![true; list.faces.len()];
        for &(face, _) in &duplicates {
            keep[face] = false;
        }
        list.retain(&keep);
    }
    let scaled: Vec<DVec3> = positions.iter().map(|&p| p * scale).collect();
    let collapse = collapse_degenerate(&scaled, &mut list.faces, DEGENERATE_AREA_RATIO);
    if let Some(&first) = collapse.collapsed.first() {
        let detail = match collapse.first_edge {
            Some((gone, kept)) => format!(
                "zero area; its vertex {} is merged into vertex {}, the nearer end of the \
                 opposite edge",
                input_name(&names_in, &representative, gone),
                input_name(&names_in, &representative, kept)
            ),
            None => "zero area".to_string(),
        };
        repairs.record(
            RepairKind::DegenerateFaceCollapsed,
            collapse.collapsed.len(),
            Element::Face(list.origin[first] as usize),
            detail,
        )?;
    }
    if let Some(&first) = collapse.dropped.first() {
        repairs.record(
            RepairKind::DegenerateFaceRemoved,
            collapse.dropped.len(),
            Element::Face(list.origin[first] as usize),
            "zero area, and collapsing it would make the mesh non-manifold or turn a \
             neighbour over; the face is removed, leaving a hole"
                .to_string(),
        )?;
    }
    if collapse.removed.contains(&true) {
        list.retain(&collapse.removed.iter().map(|r| !r).collect::<Vec<_>>());
        let dropped = drop_unused(&mut positions, &mut representative, &mut list.faces);
        if dropped > 0 {
            report.warnings.push(format!(
                "dropped {dropped} vertices that repairs left used by no face"
            ));
        }
    }
    if list.faces.is_empty() {
        return Err(Error::Invalid(format!(
            "no face is left after the repairs: {}",
            repairs
                .list
                .iter()
                .map(|r| r.message())
                .collect::<Vec<_>>()
                .join("; ")
        )));
    }

    // Non-manifold edges, then vertices.
    let (mut twin, same_direction, split_edges) = link_half_edges(&list.faces, &positions);
    if let Some(&(a, b, count)) = split_edges.first() {
        repairs.record(
            RepairKind::NonManifoldEdgeSplit,
            split_edges.len(),
            Element::Edge(
                input_name(&names_in, &representative, a),
                input_name(&names_in, &representative, b),
            ),
            format!("shared by {count} faces; they are paired, the others split off"),
        )?;
    }
    let (split_from, split_vertices) = split_fans(&mut list.faces, &twin, positions.len());
    if let Some(&(v, fans)) = split_vertices.first() {
        repairs.record(
            RepairKind::NonManifoldVertexSplit,
            split_vertices.len(),
            Element::Vertex(input_name(&names_in, &representative, v)),
            format!("its faces form {fans} separate fans; each fan gets its own vertex"),
        )?;
    }
    for &v in &split_from {
        positions.push(positions[v as usize]);
        representative.push(representative[v as usize]);
    }
    // Consistent orientation, cutting the surface open where it is one-sided; a cut leaves
    // the fans of its ends apart, and those are split as above.
    let orientation = orient_cutting(&mut twin, &same_direction);
    if let Some(&(he, other)) = orientation.cut.first() {
        let (f, e) = (he as usize / 3, he as usize % 3);
        let (a, b) = (list.faces[f][e], list.faces[f][(e + 1) % 3]);
        let first = Element::Edge(
            input_name(&names_in, &representative, a),
            input_name(&names_in, &representative, b),
        );
        let (split_from, _) = split_fans(&mut list.faces, &twin, positions.len());
        repairs.record(
            RepairKind::NonOrientableEdgeCut,
            orientation.cut.len(),
            first,
            format!(
                "the mesh is not orientable: no consistent orientation across this edge of \
                 faces {} and {}; the edge is cut open ({} vertices of the cuts duplicated)",
                list.origin[f],
                list.origin[other as usize / 3],
                split_from.len()
            ),
        )?;
        for &v in &split_from {
            positions.push(positions[v as usize]);
            representative.push(representative[v as usize]);
        }
    }
    let names = VertexNames {
        representative: &representative,
        labels,
    };
    let mut faces = list.faces;
    // The file's normals are matched to vertices before any face is flipped, while faces
    // still list their corners in file order.
    let corner_normals = corner_normals.map(|normals| CornerNormals {
        corner: list.normal_corners.unwrap_or_default(),
        normals: normals.normals,
    });
    let obj_normals =
        normals::per_vertex_from_corners(corner_normals, &faces, positions.len(), &|v| {
            names.welded(v)
        });
    let twin = unfold_folded_rings(
        &mut faces,
        twin,
        &orientation.flip,
        &positions,
        &names,
        &mut repairs,
    )?;
    let flipped = orientation_flips(
        &faces,
        &twin,
        orientation,
        &positions,
        &list.origin,
        &mut repairs,
    )?;
    let twin = apply_flips(&mut faces, twin, &flipped);
    report.reoriented_faces = flipped.iter().filter(|&&f| f).count();
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
    report.repairs = repairs.list;
    for (i, repair) in report.repairs.iter().enumerate() {
        report.warnings.insert(i, repair.message());
    }
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
    let vertex_origin = (0..positions.len() as u32)
        .map(|v| names.welded(v) as u32)
        .collect();
    Ok((
        Mesh {
            positions,
            faces,
            face_origin: list.origin,
            vertex_origin,
            repairs: report.repairs.clone(),
            obj_normals,
            topology,
            sharp,
        },
        report,
    ))
}

/// The input number of mesh vertex `v` (before the final numbering).
fn input_name(names: &VertexNames, representative: &[u32], v: u32) -> usize {
    names.input(representative[v as usize] as usize)
}

/// How repairs caused by welding name the weld.
struct WeldNames<'a> {
    /// The input positions.
    positions: &'a [DVec3],
    names: &'a VertexNames<'a>,
    /// The weld tolerance as a distance.
    tolerance: f64,
}

impl WeldNames<'_> {
    /// "welding merged vertices a and b …" for vertices already named as the input does.
    fn note(&self, a: usize, b: usize, distance: f64) -> String {
        format!(
            "welding merged its corners {a} and {b} ({distance:.3e} apart, within the weld \
             tolerance {:.3e}; a smaller --weld-tolerance keeps them apart)",
            self.tolerance
        )
    }
    /// [`WeldNames::note`] for input vertex indices.
    fn note_input(&self, a: usize, b: usize, distance: f64) -> String {
        format!(
            "welding merged vertex {} into vertex {} ({distance:.3e} apart, within the weld \
             tolerance {:.3e}; a smaller --weld-tolerance keeps them apart)",
            self.names.input(a),
            self.names.input(b),
            self.tolerance
        )
    }
    /// For faces `face` and `first` on the same welded vertices, two input vertices at
    /// different positions that welding merged to make them so (input indices), if any.
    fn merged_between(&self, list: &FaceList, face: usize, first: usize) -> Option<(usize, usize)> {
        for c in 0..3 {
            let welded = list.faces[face][c];
            let d = list.faces[first].iter().position(|&w| w == welded)?;
            let (a, b) = (list.input[face][c] as usize, list.input[first][d] as usize);
            if a != b && self.positions[a] != self.positions[b] {
                return Some((a, b));
            }
        }
        None
    }
}

/// Removes vertices used by no face, keeping the order of the others; returns how many.
fn drop_unused(
    positions: &mut Vec<DVec3>,
    representative: &mut Vec<u32>,
    faces: &mut [[u32; 3]],
) -> usize {
    let mut used = vec![false; positions.len()];
    for &v in faces.iter().flatten() {
        used[v as usize] = true;
    }
    let mut renumber = vec![u32::MAX; positions.len()];
    let mut next = 0u32;
    for v in 0..positions.len() {
        if used[v] {
            renumber[v] = next;
            positions[next as usize] = positions[v];
            representative[next as usize] = representative[v];
            next += 1;
        }
    }
    let dropped = positions.len() - next as usize;
    positions.truncate(next as usize);
    representative.truncate(next as usize);
    for v in faces.iter_mut().flatten() {
        *v = renumber[*v as usize];
    }
    dropped
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

/// The faces on the same three vertices (in any order or orientation) as an earlier face:
/// `(face, earlier face)` in order of the later face.
fn find_duplicates(faces: &[[u32; 3]]) -> Vec<(usize, usize)> {
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
    let mut out = Vec::new();
    let mut start = 0;
    while start < keyed.len() {
        let end = start
            + keyed[start..]
                .iter()
                .take_while(|k| k.0 == keyed[start].0)
                .count();
        for k in &keyed[start + 1..end] {
            out.push((k.1 as usize, keyed[start].1 as usize));
        }
        start = end;
    }
    out.sort_unstable();
    out
}

/// Twins, directions and the split edges (see [`link_half_edges`]).
type Linked = (Vec<u32>, Vec<bool>, Vec<(u32, u32, usize)>);

/// Pairs the half-edges (3·face + corner, running from corner to the next) of each undirected
/// edge. Returns each half-edge's twin (or [`NO_TWIN`]), whether it runs the same way as its
/// twin (which an oriented mesh never does), and the edges shared by more than two faces as
/// `(a, b, faces)`: those are split ([`pair_fan`] picks the pairs, within the fans the faces'
/// corners already form through the two-face edges where it can; the others become boundary
/// edges). O(F log F) by sorting edge keys.
fn link_half_edges(faces: &[[u32; 3]], positions: &[DVec3]) -> Linked {
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
    let mut split = Vec::new();
    let mut link = |h0: u32, h1: u32| {
        twin[h0 as usize] = h1;
        twin[h1 as usize] = h0;
        let same = from(h0 as usize) == from(h1 as usize);
        same_direction[h0 as usize] = same;
        same_direction[h1 as usize] = same;
    };
    let normal = |he: u32| {
        let p = faces[he as usize / 3].map(|v| positions[v as usize]);
        (p[1] - p[0]).cross(p[2] - p[0]).normalize_or_zero()
    };
    // The fans of the corners through the two-face edges alone, so that the faces of an edge
    // shared by more than two are paired within the fans they already belong to.
    let mut fan: Vec<u32> = (0..half_edge_count as u32).collect();
    fn root(fan: &mut [u32], mut x: u32) -> u32 {
        while fan[x as usize] != x {
            fan[x as usize] = fan[fan[x as usize] as usize];
            x = fan[x as usize];
        }
        x
    }
    let corner_of = |he: usize, v: u32| {
        let face = he / 3;
        (0..3)
            .find(|&c| faces[face][c] == v)
            .map_or(he as u32, |c| (3 * face + c) as u32)
    };
    let mut groups: Vec<(usize, usize)> = Vec::new();
    let mut start = 0;
    while start < keyed.len() {
        let key = keyed[start].0;
        let end = start + keyed[start..].iter().take_while(|k| k.0 == key).count();
        if end - start == 2 {
            let (h0, h1) = (keyed[start].1 as usize, keyed[start + 1].1 as usize);
            for v in [from(h0), to(h0)] {
                let (r0, r1) = (
                    root(&mut fan, corner_of(h0, v)),
                    root(&mut fan, corner_of(h1, v)),
                );
                fan[r0.max(r1) as usize] = r0.min(r1);
            }
        }
        groups.push((start, end));
        start = end;
    }
    for (start, end) in groups {
        match end - start {
            1 => {}
            2 => link(keyed[start].1, keyed[start + 1].1),
            count => {
                let key = keyed[start].0;
                let (a, b) = ((key >> 32) as u32, key as u32);
                let half_edges: Vec<(u32, bool)> = keyed[start..end]
                    .iter()
                    .map(|&(_, he)| (he, from(he as usize) == a))
                    .collect();
                let fans: Vec<(u32, (u32, u32))> = half_edges
                    .iter()
                    .map(|&(he, _)| {
                        let he = he as usize;
                        let mut at = |v| root(&mut fan, corner_of(he, v));
                        (he as u32, (at(a), at(b)))
                    })
                    .collect();
                let fans_of = |he: u32| {
                    fans.iter()
                        .find(|&&(h, _)| h == he)
                        .map_or((he, he), |&(_, f)| f)
                };
                for (h0, h1) in pair_fan(&half_edges, &normal, &fans_of) {
                    link(h0, h1);
                }
                split.push((a, b, count));
            }
        }
    }
    (twin, same_direction, split)
}

/// Decides which faces to flip: those `orientation` flips so that every interior edge is run
/// in opposite directions by its two faces ([`orient_cutting`]), then each component as a
/// whole so that it faces outward: a closed one by the sign of its enclosed volume, an open
/// one (or a closed one enclosing no volume) as the larger part of its face area was written.
/// Records the faces flipped as repairs: whole components turned outward, and faces
/// re-oriented to agree with the rest of their component.
fn orientation_flips(
    faces: &[[u32; 3]],
    twin: &[u32],
    orientation: Orientation,
    positions: &[DVec3],
    origin: &[u32],
    repairs: &mut Repairs,
) -> Result<Vec<bool>> {
    let Orientation {
        flip: mut flipped,
        components,
        ..
    } = orientation;
    // Faces of components turned as a whole, reported as a component, not face by face.
    let mut turned_whole = vec![false; faces.len()];
    // Measured about each component's first vertex, in unit-size coordinates.
    let scale = normalising_scale(&Aabb::from_points(positions));
    let (mut turned, mut first_turned) = (0, None);
    for faces_of in &components {
        let closed = faces_of
            .iter()
            .all(|&f| (0..3).all(|e| twin[3 * f as usize + e] != NO_TWIN));
        let centre = positions[faces[faces_of[0] as usize][0] as usize];
        let (mut volume, mut area, mut area_flipped) = (0.0, 0.0, 0.0);
        for &f in faces_of.iter() {
            let [a, b, c] = faces[f as usize].map(|v| (positions[v as usize] - centre) * scale);
            let sign = if flipped[f as usize] { -1.0 } else { 1.0 };
            volume += sign * a.dot(b.cross(c));
            let face_area = (b - a).cross(c - a).length();
            area += face_area;
            if flipped[f as usize] {
                area_flipped += face_area;
            }
        }
        // A volume below rounding of the area sum (a flat double sheet) decides nothing.
        let by_volume = closed && volume.abs() > 1e-9 * area.max(f64::MIN_POSITIVE);
        let turn = if by_volume {
            volume < 0.0
        } else {
            area_flipped > 0.5 * area
        };
        if turn {
            for &f in faces_of.iter() {
                flipped[f as usize] = !flipped[f as usize];
            }
        }
        if faces_of.iter().all(|&f| flipped[f as usize]) {
            turned += 1;
            first_turned.get_or_insert((faces_of[0], faces_of.len(), by_volume));
            for &f in faces_of.iter() {
                turned_whole[f as usize] = true;
            }
        }
    }
    if let Some((face, count, by_volume)) = first_turned {
        let why = if by_volume {
            "its enclosed volume was negative"
        } else {
            "more than half of its face area faced the other way"
        };
        repairs.record(
            RepairKind::ComponentTurnedOutward,
            turned,
            Element::Face(origin[face as usize] as usize),
            format!("the component of {count} faces containing it was inside out ({why})"),
        )?;
    }
    let reoriented: Vec<usize> = (0..faces.len())
        .filter(|&f| flipped[f] && !turned_whole[f])
        .collect();
    if let Some(&first) = reoriented.first() {
        repairs.record(
            RepairKind::FacesReoriented,
            reoriented.len(),
            Element::Face(origin[first] as usize),
            "it is oriented against its neighbours (each component is oriented outward: by its \
             enclosed volume when closed, else as most of its face area was written)"
                .to_string(),
        )?;
    }
    Ok(flipped)
}

/// Unfolds the one-rings that fold over themselves where flipping an edge does
/// ([`unfold::unfold_rings`]), recording the flips as a repair. Works on the faces as the
/// component-consistency flips `flip` orient them (whether a ring folds does not depend on
/// which way its component faces), and returns them as written again, so that the outward
/// decision that follows sees the unfolded surface.
fn unfold_folded_rings(
    faces: &mut [[u32; 3]],
    twin: Vec<u32>,
    flip: &[bool],
    positions: &[DVec3],
    names: &VertexNames,
    repairs: &mut Repairs,
) -> Result<Vec<u32>> {
    let mut twin = apply_flips(faces, twin, flip);
    let flips = unfold::unfold_rings(positions, faces, &mut twin);
    if let Some(first) = flips.first() {
        let [a, b] = first.removed;
        let [c, d] = first.added;
        repairs.record(
            RepairKind::FoldedRingEdgeFlipped,
            flips.len(),
            Element::Edge(names.welded(a), names.welded(b)),
            format!(
                "the faces around vertex {} fold over themselves (no normal sees them all from \
                 the front side); the edge is replaced by the other diagonal of its two faces, \
                 ({}, {})",
                names.welded(first.vertex),
                names.welded(c),
                names.welded(d)
            ),
        )?;
    }
    // Swapping two corners is its own inverse, and so is the renumbering of the twins.
    Ok(apply_flips(faces, twin, flip))
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
    use crate::mesh::{Element, LoadOptions, LoadReport, Mesh, RepairKind};

    fn load((positions, faces): (Vec<DVec3>, Vec<[u32; 3]>)) -> crate::Result<(Mesh, LoadReport)> {
        Mesh::from_triangles(positions, faces)
    }

    /// Loads with `--strict` and returns the refusal's message, which must name `element`.
    fn strict_refusal((positions, faces): generate::Triangles, element: &str) -> String {
        let options = LoadOptions {
            strict: true,
            ..Default::default()
        };
        match Mesh::from_triangles_with(positions, faces, &options) {
            Err(error @ Error::RepairRefused { .. }) => {
                let message = error.to_string();
                assert!(message.starts_with(&format!("{element}: ")), "{message}");
                message
            }
            Err(other) => panic!("expected a refused repair of {element}, got {other}"),
            Ok(_) => panic!("expected a refused repair of {element}, got a mesh"),
        }
    }

    /// The repairs of a load as (kind, count, first element).
    fn repairs(report: &LoadReport) -> Vec<(RepairKind, usize, Element)> {
        let listed: Vec<_> = report
            .repairs
            .iter()
            .map(|r| (r.kind, r.count, r.first))
            .collect();
        // Each repair is also one warning line naming its first element.
        for (repair, warning) in report.repairs.iter().zip(&report.warnings) {
            assert_eq!(&repair.message(), warning);
            assert!(
                warning.contains(&format!("(first: {}: ", repair.first)),
                "{warning}"
            );
        }
        listed
    }

    /// The signed volume of a closed mesh (positive when its faces face outward).
    fn volume(mesh: &Mesh) -> f64 {
        mesh.faces()
            .iter()
            .map(|f| {
                let [a, b, c] = f.map(|v| mesh.positions()[v as usize]);
                a.dot(b.cross(c)) / 6.0
            })
            .sum()
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
    fn a_repeated_corner_is_collapsed_and_refused_when_strict() {
        let (positions, mut faces) = generate::tetrahedron();
        faces[3] = [faces[3][0], faces[3][1], faces[3][0]];
        let (mesh, report) = load((positions.clone(), faces.clone())).unwrap();
        assert_eq!(
            repairs(&report),
            [(RepairKind::DegenerateFaceCollapsed, 1, Element::Face(3))]
        );
        assert_eq!(mesh.face_count(), 3);
        let message = strict_refusal((positions, faces), "face 3");
        assert!(message.contains("a corner is repeated"), "{message}");
    }

    #[test]
    fn corners_that_weld_together_make_a_degenerate_face() {
        // Vertex 3 is a copy of vertex 0, so face 1 has a repeated corner after welding.
        let positions = vec![DVec3::ZERO, DVec3::X, DVec3::Y, DVec3::ZERO];
        let faces = vec![[0, 1, 2], [3, 2, 0]];
        let (mesh, report) = load((positions.clone(), faces.clone())).unwrap();
        assert_eq!(
            repairs(&report),
            [(RepairKind::DegenerateFaceCollapsed, 1, Element::Face(1))]
        );
        assert_eq!(mesh.faces(), &[[0, 1, 2]]);
        strict_refusal((positions, faces), "face 1");
    }

    #[test]
    fn a_collinear_face_is_collapsed() {
        let (mesh, report) = load(bad::collinear_face()).unwrap();
        assert_eq!(
            repairs(&report),
            [(RepairKind::DegenerateFaceCollapsed, 1, Element::Face(1))]
        );
        assert_eq!(mesh.faces(), &[[0, 1, 2]]);
        assert_eq!(mesh.input_face(0), 0);
        strict_refusal(bad::collinear_face(), "face 1");
    }

    #[test]
    fn a_cap_collapses_its_corner_into_the_nearer_end_of_the_opposite_edge() {
        // A flat open patch. Face 1, (b, a, c), is a cap: c lies on edge (a, b), 0.6 from b
        // and 1.4 from a. Below the edge, c's fan is (c, a, d1), (c, d1, d2), (b, c, d2).
        let (a, b, c, t, d1, d2) = (0, 1, 2, 3, 4, 5);
        let positions = vec![
            DVec3::ZERO,
            DVec3::new(2.0, 0.0, 0.0),
            DVec3::new(1.4, 0.0, 0.0),
            DVec3::new(1.0, 1.0, 0.0),
            DVec3::new(0.5, -1.0, 0.0),
            DVec3::new(1.5, -1.0, 0.0),
        ];
        let faces = vec![[a, b, t], [b, a, c], [c, a, d1], [c, d1, d2], [b, c, d2]];
        let (mesh, report) = load((positions, faces)).unwrap();
        assert_eq!(
            repairs(&report),
            [(RepairKind::DegenerateFaceCollapsed, 1, Element::Face(1))]
        );
        assert!(
            report.warnings[0].contains("vertex 2 is merged into vertex 1"),
            "{:?}",
            report.warnings
        );
        // c went to b: the face (b, c, d2) collapsed with the cap, c's other faces now use b
        // (vertex 2 is gone, so d1 and d2 are 3 and 4 now).
        assert_eq!(mesh.faces(), &[[0, 1, 2], [1, 0, 3], [1, 3, 4]]);
        assert_eq!(
            (0..3).map(|t| mesh.input_face(t)).collect::<Vec<_>>(),
            [0, 2, 3]
        );
        assert_eq!(mesh.positions()[1], DVec3::new(2.0, 0.0, 0.0));
    }

    #[test]
    fn degenerate_threshold_is_relative_to_the_longest_edge() {
        // |cross| / longest² is 2e-14 and 0.5e-14: just above and just below the threshold,
        // at scales where an absolute threshold would misjudge both, down to and up to the
        // ends of the supported range. Two faces, so that one is left when the thin one goes.
        for scale in [1e6, 1e-20, 1e20, 1e-59, 1e59] {
            for (height, degenerate) in [(2e-14, false), (0.5e-14, true)] {
                let positions = vec![
                    DVec3::ZERO,
                    DVec3::X * scale,
                    DVec3::new(0.5, height, 0.0) * scale,
                    DVec3::new(0.5, -1.0, 0.0) * scale,
                ];
                let faces = vec![[0, 1, 2], [1, 0, 3]];
                let (_, report) = load((positions.clone(), faces.clone())).unwrap();
                assert_eq!(
                    !report.repairs.is_empty(),
                    degenerate,
                    "height {height} at scale {scale}: {:?}",
                    report.warnings
                );
                if degenerate {
                    strict_refusal((positions, faces), "face 0");
                }
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
    fn a_duplicate_face_is_removed_naming_both_faces() {
        let (mesh, report) = load(bad::tetrahedron_with_duplicate_face()).unwrap();
        assert_eq!(
            repairs(&report),
            [(RepairKind::DuplicateFaceRemoved, 1, Element::Face(4))]
        );
        assert!(
            report.warnings[0].contains("repeats face 0"),
            "{:?}",
            report.warnings
        );
        assert_eq!(mesh.faces(), &generate::tetrahedron().1[..]);
        strict_refusal(bad::tetrahedron_with_duplicate_face(), "face 4");
    }

    #[test]
    fn three_faces_on_an_edge_are_split_off() {
        let (mesh, report) = load(bad::book()).unwrap();
        // The three pages run the edge the same way, 120° apart: two are paired (one of them
        // flipped), the third is split off, which leaves the edge's ends with two fans each.
        let listed = repairs(&report);
        assert_eq!(
            listed[..2],
            [
                (RepairKind::NonManifoldEdgeSplit, 1, Element::Edge(0, 1)),
                (RepairKind::NonManifoldVertexSplit, 2, Element::Vertex(0)),
            ]
        );
        assert_eq!((listed[2].0, listed[2].1), (RepairKind::FacesReoriented, 1));
        assert_eq!((mesh.face_count(), mesh.vertex_count()), (3, 7));
        let paired = (0..3)
            .filter(|&f| (0..3).any(|e| mesh.neighbor(f, e).is_some()))
            .count();
        assert_eq!(paired, 2);
        let message = strict_refusal(bad::book(), "edge (0, 1)");
        assert!(message.contains("shared by 3 faces"), "{message}");
    }

    #[test]
    fn non_manifold_edges_pair_the_faces_closest_in_dihedral_angle() {
        // Four faces on the edge (0, 1) along z, their third corners at 0°, 10°, 180° and 190°
        // about it; the faces at 0° and 180° agree in orientation and continue each other
        // flat, as do those at 10° and 190°.
        let mut positions = vec![DVec3::ZERO, DVec3::Z];
        let mut faces = Vec::new();
        for (degrees, forward) in [(0.0f64, true), (10.0, false), (180.0, false), (190.0, true)] {
            let (s, c) = degrees.to_radians().sin_cos();
            let v = positions.len() as u32;
            positions.push(DVec3::new(c, s, 0.5));
            faces.push(if forward { [0, 1, v] } else { [1, 0, v] });
        }
        let (mesh, report) = load((positions, faces)).unwrap();
        assert_eq!(report.repairs[0].kind, RepairKind::NonManifoldEdgeSplit);
        let across = |f: u32| {
            (0..3)
                .filter_map(|e| mesh.neighbor(f, e))
                .map(|(g, _)| g)
                .collect::<Vec<_>>()
        };
        assert_eq!((across(0), across(1)), (vec![2], vec![3]));
        assert_eq!(report.reoriented_faces, 0);
    }

    #[test]
    fn a_fin_is_split_off_so_that_no_two_edges_join_the_same_vertices() {
        // The fin on the octahedron's edge (0, 4) is closer in dihedral angle to one of the
        // octahedron's faces there, but those two faces already share a fan at both ends: they
        // are paired, and the fin, alone in its fans, is split off with its own two corners.
        let (positions, faces) = bad::octahedron_with_fin();
        let (mesh, report) = load((positions.clone(), faces)).unwrap();
        let listed = repairs(&report);
        assert_eq!(
            listed[..2],
            [
                (RepairKind::NonManifoldEdgeSplit, 1, Element::Edge(0, 4)),
                (RepairKind::NonManifoldVertexSplit, 2, Element::Vertex(0)),
            ]
        );
        assert_eq!(
            (mesh.face_count(), mesh.vertex_count()),
            (9, positions.len() + 2)
        );
        let mut pairs: Vec<(u32, u32)> = mesh.edges().iter().map(|e| (e.a, e.b)).collect();
        let count = pairs.len();
        pairs.sort_unstable();
        pairs.dedup();
        assert_eq!(pairs.len(), count, "two edges join the same two vertices");
        // The octahedron is closed again; the fin is the only boundary.
        let boundary = mesh.edges().iter().filter(|e| e.faces.1.is_none()).count();
        assert_eq!(boundary, 3);
    }

    #[test]
    fn a_bow_tie_vertex_is_split_into_one_vertex_per_fan() {
        let (mesh, report) = load(bad::bow_tie()).unwrap();
        assert_eq!(
            repairs(&report),
            [(RepairKind::NonManifoldVertexSplit, 1, Element::Vertex(0))]
        );
        assert!(
            report.warnings[0].contains("2 separate fans"),
            "{:?}",
            report.warnings
        );
        assert_eq!(mesh.vertex_count(), 6);
        assert_eq!(mesh.positions()[5], mesh.positions()[0]);
        assert_eq!(mesh.faces(), &[[0, 1, 4], [5, 2, 3]]);
        strict_refusal(bad::bow_tie(), "vertex 0");
    }

    #[test]
    fn two_closed_fans_at_one_vertex_are_split() {
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
        let (mesh, report) = load((all_positions.clone(), all_faces.clone())).unwrap();
        // The point reflection turns the second tetrahedron inside out.
        assert_eq!(
            repairs(&report),
            [
                (RepairKind::NonManifoldVertexSplit, 1, Element::Vertex(0)),
                (RepairKind::ComponentTurnedOutward, 1, Element::Face(4)),
            ]
        );
        assert!(mesh.is_closed());
        assert_eq!(mesh.euler_characteristic(), 4);
        assert!(volume(&mesh) > 0.0);
        strict_refusal((all_positions, all_faces), "vertex 0");
    }

    #[test]
    fn repairs_name_vertices_by_input_index_after_dropping_and_welding() {
        // The bow-tie behind an unused vertex and a welded copy of its centre: the centre is
        // input vertex 1 (its copy, input 7, is welded into it).
        let (positions, _) = bad::bow_tie();
        let mut shifted = vec![DVec3::splat(9.0)];
        shifted.extend(&positions);
        shifted.extend([DVec3::splat(8.0), positions[0]]);
        let faces = vec![[1, 2, 5], [7, 3, 4]];
        let (_, report) = load((shifted.clone(), faces.clone())).unwrap();
        assert_eq!(
            repairs(&report),
            [(RepairKind::NonManifoldVertexSplit, 1, Element::Vertex(1))]
        );
        strict_refusal((shifted, faces), "vertex 1");
    }

    /// Checks that every twinned edge of `mesh` is run in opposite directions by its faces.
    fn assert_consistently_oriented(mesh: &Mesh) {
        for f in 0..mesh.face_count() as u32 {
            for e in 0..3 {
                if let Some((g, k)) = mesh.neighbor(f, e) {
                    let (face, other) = (mesh.faces()[f as usize], mesh.faces()[g as usize]);
                    assert_eq!(
                        (face[e], face[(e + 1) % 3]),
                        (other[(k + 1) % 3], other[k]),
                        "faces {f} and {g}"
                    );
                }
            }
        }
    }

    #[test]
    fn a_mobius_strip_is_cut_open_across_one_edge() {
        for segments in [3, 8, 15] {
            let (positions, faces) = bad::mobius_strip(segments);
            let (mesh, report) = load((positions.clone(), faces.clone())).unwrap();
            // The cut, then the faces on one side of it flipped to agree with the other.
            let listed = repairs(&report);
            assert_eq!(
                listed.iter().map(|r| (r.0, r.1)).next(),
                Some((RepairKind::NonOrientableEdgeCut, 1)),
                "{segments}: {:?}",
                report.warnings
            );
            assert!(
                listed[1..]
                    .iter()
                    .all(|r| r.0 == RepairKind::FacesReoriented),
                "{segments}: {:?}",
                report.warnings
            );
            let Element::Edge(a, b) = listed[0].2 else {
                panic!("{segments}: the cut names {}", listed[0].2);
            };
            assert!(
                faces
                    .iter()
                    .any(|f| f.contains(&(a as u32)) && f.contains(&(b as u32))),
                "{segments}: ({a}, {b}) is no edge of the input"
            );
            assert!(
                report.warnings[0].contains("2 vertices of the cuts duplicated"),
                "{:?}",
                report.warnings
            );
            // One edge of 2n interior ones cut: its two ends (on the strip's two sides) are
            // duplicated, and the strip becomes a disk with every face kept, consistently
            // oriented, over the same corner positions.
            assert_eq!(mesh.face_count(), faces.len(), "{segments}");
            assert_eq!(mesh.vertex_count(), positions.len() + 2, "{segments}");
            assert_eq!(mesh.euler_characteristic(), 1, "{segments}");
            let interior = mesh.edges().iter().filter(|e| e.faces.1.is_some()).count();
            assert_eq!(interior, 2 * segments as usize - 1, "{segments}");
            assert_consistently_oriented(&mesh);
            for (t, face) in mesh.faces().iter().enumerate() {
                let mut corners = face.map(|v| mesh.positions()[v as usize].to_array());
                let mut input =
                    faces[mesh.input_face(t as u32)].map(|v| positions[v as usize].to_array());
                corners.sort_by(|p, q| p.partial_cmp(q).unwrap());
                input.sort_by(|p, q| p.partial_cmp(q).unwrap());
                assert_eq!(corners, input, "{segments}: face {t}");
            }
            let message = strict_refusal((positions, faces), &format!("edge ({a}, {b})"));
            assert!(message.contains("not orientable"), "{message}");
        }
    }

    #[test]
    fn a_folded_ring_is_unfolded_by_an_edge_flip_and_refused_when_strict() {
        let (mesh, report) = load(bad::test_support::folded_dart()).unwrap();
        let listed = repairs(&report);
        assert!(
            listed.contains(&(RepairKind::FoldedRingEdgeFlipped, 1, Element::Edge(0, 1))),
            "{:?}",
            report.warnings
        );
        assert!(
            report.warnings.iter().any(|w| w.contains(
                "the faces around vertex 0 fold over themselves (no normal sees them all from \
                 the front side); the edge is replaced by the other diagonal of its two faces, \
                 (2, 3)"
            )),
            "{:?}",
            report.warnings
        );
        assert!(mesh.is_closed());
        assert!(volume(&mesh) > 0.0, "outward after the flip");
        let flat_top = |f: &[u32; 3]| f.iter().all(|&v| v < 4);
        let mut top: Vec<[u32; 3]> = mesh.faces().iter().copied().filter(flat_top).collect();
        for f in &mut top {
            f.sort_unstable();
        }
        top.sort_unstable();
        assert_eq!(
            top,
            vec![[0, 2, 3], [1, 2, 3]],
            "the top is cut along (2, 3)"
        );
        strict_refusal(bad::test_support::folded_dart(), "edge (0, 1)");
    }

    #[test]
    fn flipped_face_is_reoriented_with_a_warning() {
        let (mesh, report) = load(bad::octahedron_with_flipped_face()).unwrap();
        assert_eq!(report.reoriented_faces, 1);
        assert_eq!(
            repairs(&report),
            [(RepairKind::FacesReoriented, 1, Element::Face(3))]
        );
        assert_eq!(report.warnings.len(), 1, "{:?}", report.warnings);
        assert_eq!(mesh.faces(), &generate::octahedron().1[..]);
        strict_refusal(bad::octahedron_with_flipped_face(), "face 3");
    }

    #[test]
    fn every_component_is_oriented_outward_whichever_face_is_flipped() {
        // Component 1: an octahedron whose face 0 is flipped (agreeing with face 0 would turn
        // it inside out). Component 2: a shifted tetrahedron with one flipped face.
        // Component 3: an icosahedron written inside out, every face clockwise.
        let (mut positions, mut faces) = generate::octahedron();
        faces[0].swap(1, 2);
        let (tetra_positions, tetra_faces) = generate::tetrahedron();
        let base = positions.len() as u32;
        positions.extend(tetra_positions.iter().map(|&p| p + DVec3::X * 5.0));
        faces.extend(tetra_faces.iter().map(|f| f.map(|v| v + base)));
        let last = faces.len() - 1;
        faces[last].swap(1, 2);
        let (ico_positions, ico_faces) = generate::icosahedron();
        let base = positions.len() as u32;
        positions.extend(ico_positions.iter().map(|&p| p - DVec3::X * 5.0));
        faces.extend(
            ico_faces
                .iter()
                .map(|f| [f[0] + base, f[2] + base, f[1] + base]),
        );
        let (mesh, report) = load((positions, faces)).unwrap();
        assert_eq!(
            repairs(&report),
            [
                (RepairKind::ComponentTurnedOutward, 1, Element::Face(12)),
                (RepairKind::FacesReoriented, 2, Element::Face(0)),
            ]
        );
        assert_eq!(report.reoriented_faces, 22);
        assert_eq!(mesh.faces()[..8], generate::octahedron().1[..]);
        assert_eq!(mesh.faces()[last], tetra_faces[3].map(|v| v + 6));
        // Every face of every component faces outward, away from its component's centre.
        for (range, centre) in [
            (0..8, DVec3::ZERO),
            (
                8..12,
                DVec3::X * 5.0 + tetra_positions.iter().sum::<DVec3>() / 4.0,
            ),
            (12..32, -DVec3::X * 5.0),
        ] {
            for face in &mesh.faces()[range] {
                let [a, b, c] = face.map(|v| mesh.positions()[v as usize] - centre);
                assert!((b - a).cross(c - a).dot(a + b + c) > 0.0);
            }
        }
    }

    #[test]
    fn an_open_component_keeps_the_orientation_of_most_of_its_area() {
        // A disk with its last face (a small part of the area) flipped, and the same disk with
        // every face but that one flipped: both end as the larger part was written.
        let (positions, faces) = generate::disk(3);
        let mut one_flipped = faces.clone();
        let last = faces.len() - 1;
        one_flipped[last].swap(1, 2);
        let (mesh, report) = load((positions.clone(), one_flipped.clone())).unwrap();
        assert_eq!(
            repairs(&report),
            [(RepairKind::FacesReoriented, 1, Element::Face(last))]
        );
        assert_eq!(mesh.faces(), &faces[..]);
        let all_but_one: Vec<[u32; 3]> = one_flipped.iter().map(|f| [f[0], f[2], f[1]]).collect();
        let (mesh, report) = load((positions, all_but_one.clone())).unwrap();
        assert_eq!(
            repairs(&report),
            [(RepairKind::FacesReoriented, 1, Element::Face(last))]
        );
        assert_eq!(mesh.faces()[0], all_but_one[0]);
    }
}
