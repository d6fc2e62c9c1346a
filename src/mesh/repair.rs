//! The repairs loading makes to what other tools write: what each one is, how it is counted and
//! reported, and the topological repairs themselves (degenerate faces collapsed or removed,
//! non-manifold edges and vertices split, non-orientable surfaces cut open, orientation made
//! consistent and outward; folded one-rings are unfolded in [`super::unfold`]).
//!
//! Every repair is one [`Repair`] in [`super::LoadReport::repairs`]: its kind, how many
//! elements it touched and the first of them in the input's own numbering (the face as the
//! file numbers its polygons, the vertex as the file numbers its vertices). Loading prints each
//! as one `warning:` line; with [`super::LoadOptions::strict`] the first repair needed is an
//! error naming the element instead ([`Error::RepairRefused`]).

use glam::DVec3;
use serde::Serialize;

use super::topology::NO_TWIN;
use crate::error::{Error, Result};

/// What a repair did.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum RepairKind {
    /// Polygons that are not planar or not convex split into triangles (quads by the diagonal
    /// that gives the better pair, larger polygons by ear clipping in their best-fit plane).
    /// Planar convex polygons are split too, but every split of those gives the same flat
    /// surface, so that is not a repair.
    PolygonTriangulated,
    /// Degenerate faces (zero area: a repeated corner, also one made by welding, or collinear
    /// corners) removed by collapsing their degenerate edge.
    DegenerateFaceCollapsed,
    /// Degenerate faces removed leaving a boundary, where collapsing their edge would make the
    /// mesh non-manifold or turn a neighbour over.
    DegenerateFaceRemoved,
    /// Faces on the same three vertices as an earlier face removed.
    DuplicateFaceRemoved,
    /// Edges shared by more than two faces split so that each has at most two.
    NonManifoldEdgeSplit,
    /// Vertices whose faces form several fans split into one vertex per fan.
    NonManifoldVertexSplit,
    /// Edges cut open where the surface cannot be oriented (a Möbius strip, faces tangled by
    /// repeated copies): the orientation flood fill reached both faces of the edge and needs
    /// them to run it the same way, so they no longer share it; it becomes two boundary edges.
    NonOrientableEdgeCut,
    /// Edges of one-rings that fold over themselves flipped (the edge replaced by the other
    /// diagonal of its two faces) where that unfolds the ring ([`super::unfold`]).
    FoldedRingEdgeFlipped,
    /// Faces flipped to agree with the orientation of their connected component.
    FacesReoriented,
    /// Connected components turned inside out as a whole, so that they face outward.
    ComponentTurnedOutward,
}

/// An element of the input mesh, in the input's own numbering.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Element {
    /// A face (polygon) as the file numbers it, 0-based.
    Face(usize),
    /// A vertex as the file numbers it, 0-based.
    Vertex(usize),
    /// An edge between two vertices, numbered as the file numbers them.
    Edge(usize, usize),
}

impl std::fmt::Display for Element {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Element::Face(face) => write!(f, "face {face}"),
            Element::Vertex(vertex) => write!(f, "vertex {vertex}"),
            Element::Edge(a, b) => write!(f, "edge ({a}, {b})"),
        }
    }
}

/// One repair loading made: its kind, how many elements it touched, the first of them.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Repair {
    /// What was done.
    pub kind: RepairKind,
    /// How many faces, edges, vertices or components it touched.
    pub count: usize,
    /// The first of them, in the input's numbering.
    pub first: Element,
    /// What was wrong with the first one and what was done to it, in words.
    pub detail: String,
}

impl Repair {
    /// The repair as one warning line (without the `warning:` prefix): the summary and the
    /// first element with its detail.
    pub fn message(&self) -> String {
        format!(
            "{} (first: {}: {})",
            self.summary(),
            self.first,
            self.detail
        )
    }

    /// What was done and how often, in words.
    pub fn summary(&self) -> String {
        let n = self.count;
        match self.kind {
            RepairKind::PolygonTriangulated => format!(
                "triangulated {n} non-planar or non-convex faces (quads by the diagonal giving \
                 the better triangles, larger ones by ear clipping in their best-fit plane)"
            ),
            RepairKind::DegenerateFaceCollapsed => {
                format!("collapsed {n} degenerate faces (zero area) into an edge or a vertex")
            }
            RepairKind::DegenerateFaceRemoved => format!(
                "removed {n} degenerate faces (zero area), leaving a boundary where collapsing \
                 them would make the mesh non-manifold"
            ),
            RepairKind::DuplicateFaceRemoved => {
                format!("removed {n} duplicate faces (same three vertices as an earlier face)")
            }
            RepairKind::NonManifoldEdgeSplit => format!(
                "split {n} non-manifold edges so that each has at most two faces, pairing faces \
                 that agree in orientation, already share a fan at the edge's ends and are \
                 closest in dihedral angle"
            ),
            RepairKind::NonManifoldVertexSplit => format!(
                "split {n} non-manifold vertices into one vertex per fan (the surface touches \
                 itself there)"
            ),
            RepairKind::NonOrientableEdgeCut => format!(
                "cut open {n} edges where the surface is not orientable (their two faces no \
                 longer share them: each becomes two boundary edges)"
            ),
            RepairKind::FoldedRingEdgeFlipped => format!(
                "flipped {n} edges of one-rings whose faces fold over themselves (each replaced \
                 by the other diagonal of its two faces, so that one normal sees the whole ring \
                 from the front; no vertex moves)"
            ),
            RepairKind::FacesReoriented => {
                format!("re-oriented {n} faces for a consistent orientation of their component")
            }
            RepairKind::ComponentTurnedOutward => {
                format!("turned {n} inside-out components outward (all their faces flipped)")
            }
        }
    }
}

/// The repairs of one load, in the order they were made; in strict mode the first one needed
/// is an error instead.
#[derive(Debug, Default)]
pub(super) struct Repairs {
    strict: bool,
    pub(super) list: Vec<Repair>,
}

impl Repairs {
    /// An empty list; `strict` refuses every repair.
    pub(super) fn new(strict: bool) -> Repairs {
        Repairs {
            strict,
            list: Vec::new(),
        }
    }

    /// Records a repair of `count > 0` elements (nothing for 0); in strict mode returns
    /// [`Error::RepairRefused`] naming the first element instead.
    pub(super) fn record(
        &mut self,
        kind: RepairKind,
        count: usize,
        first: Element,
        detail: String,
    ) -> Result<()> {
        if count == 0 {
            return Ok(());
        }
        let repair = Repair {
            kind,
            count,
            first,
            detail,
        };
        if self.strict {
            return Err(Error::RepairRefused {
                element: first.to_string(),
                problem: repair.detail.clone(),
                repair: repair.summary(),
            });
        }
        self.list.push(repair);
        Ok(())
    }
}

/// `2·area / longest edge²` of the triangle `p` (about the sine of its smallest angle), the
/// scale-free measure of how degenerate it is.
pub(super) fn area_ratio(p: [DVec3; 3]) -> f64 {
    let longest_squared = (p[1] - p[0])
        .length_squared()
        .max((p[2] - p[1]).length_squared())
        .max((p[0] - p[2]).length_squared());
    let twice_area = (p[1] - p[0]).cross(p[2] - p[0]).length();
    if longest_squared > 0.0 {
        twice_area / longest_squared
    } else {
        0.0
    }
}

/// The edge to collapse in a degenerate triangle with distinct corners: from the corner
/// opposite the longest edge (the one lying on, or nearest to, that edge) to the nearer end of
/// that edge. Returns (corner that goes, corner it goes to) as positions in the face.
///
/// For a needle (two corners nearly coincident) this is the short edge; for a cap (a corner
/// on the opposite edge) it moves that corner along the edge by the least distance, so the
/// neighbours change least.
pub(super) fn collapse_edge(p: [DVec3; 3]) -> (usize, usize) {
    // Edge k runs from corner k to corner k+1, opposite corner k+2.
    let longest = (0..3)
        .max_by(|&i, &j| {
            let li = (p[(i + 1) % 3] - p[i]).length_squared();
            let lj = (p[(j + 1) % 3] - p[j]).length_squared();
            li.total_cmp(&lj).then(j.cmp(&i))
        })
        .unwrap_or(0);
    let (a, b, c) = (longest, (longest + 1) % 3, (longest + 2) % 3);
    if p[c].distance_squared(p[a]) <= p[c].distance_squared(p[b]) {
        (c, a)
    } else {
        (c, b)
    }
}

/// Faces per vertex, kept up to date as vertices are merged.
struct VertexFaces {
    faces: Vec<Vec<u32>>,
}

impl VertexFaces {
    fn new(faces: &[[u32; 3]], vertex_count: usize) -> VertexFaces {
        let mut lists = vec![Vec::new(); vertex_count];
        for (f, face) in faces.iter().enumerate() {
            for &v in face {
                if !lists[v as usize].contains(&(f as u32)) {
                    lists[v as usize].push(f as u32);
                }
            }
        }
        VertexFaces { faces: lists }
    }
}

/// What [`collapse_degenerate`] did.
pub(super) struct Collapse {
    /// Faces removed, by index (the degenerate ones and those their collapse emptied).
    pub(super) removed: Vec<bool>,
    /// Degenerate faces collapsed, in order.
    pub(super) collapsed: Vec<usize>,
    /// Degenerate faces removed leaving a boundary, in order.
    pub(super) dropped: Vec<usize>,
    /// For the first collapsed face, the edge collapsed (vertex that went, vertex kept).
    pub(super) first_edge: Option<(u32, u32)>,
}

/// Removes the faces whose `area_ratio` (on `positions`) is at most `threshold` and whose
/// corners are distinct: by collapsing the edge [`collapse_edge`] picks (every face using the
/// vertex that goes uses the one kept instead) where the edge's two ends have no common
/// neighbour but the faces on the edge (the link condition, which keeps the mesh manifold),
/// at most two faces share the edge, and no other face around the vertex turns over or
/// becomes degenerate; otherwise by removing the face alone, which leaves a boundary.
pub(super) fn collapse_degenerate(
    positions: &[DVec3],
    faces: &mut [[u32; 3]],
    threshold: f64,
) -> Collapse {
    let mut out = Collapse {
        removed: vec![false; faces.len()],
        collapsed: Vec::new(),
        dropped: Vec::new(),
        first_edge: None,
    };
    let degenerate = |face: [u32; 3]| area_ratio(face.map(|v| positions[v as usize])) <= threshold;
    if !faces.iter().any(|&face| degenerate(face)) {
        return out;
    }
    let mut adjacency = VertexFaces::new(faces, positions.len());
    for f in 0..faces.len() {
        if out.removed[f] || !degenerate(faces[f]) {
            continue;
        }
        let face = faces[f];
        let (go, keep) = collapse_edge(face.map(|v| positions[v as usize]));
        let (gone, kept) = (face[go], face[keep]);
        if collapse_allowed(
            positions,
            faces,
            &adjacency,
            &out.removed,
            gone,
            kept,
            threshold,
        ) {
            let moved = std::mem::take(&mut adjacency.faces[gone as usize]);
            for &g in &moved {
                let g = g as usize;
                for v in faces[g].iter_mut() {
                    if *v == gone {
                        *v = kept;
                    }
                }
                if faces[g].contains(&gone) || faces[g].iter().filter(|&&v| v == kept).count() > 1 {
                    out.removed[g] = true;
                } else if !adjacency.faces[kept as usize].contains(&(g as u32)) {
                    adjacency.faces[kept as usize].push(g as u32);
                }
            }
            if out.first_edge.is_none() {
                out.first_edge = Some((gone, kept));
            }
            out.collapsed.push(f);
        } else {
            out.removed[f] = true;
            out.dropped.push(f);
        }
    }
    out
}

/// The link condition and the no-fold test for collapsing `gone` into `kept`.
fn collapse_allowed(
    positions: &[DVec3],
    faces: &[[u32; 3]],
    adjacency: &VertexFaces,
    removed: &[bool],
    gone: u32,
    kept: u32,
    threshold: f64,
) -> bool {
    let live = |v: u32| {
        adjacency.faces[v as usize]
            .iter()
            .copied()
            .filter(|&g| !removed[g as usize])
    };
    let shared: Vec<u32> = live(gone)
        .filter(|&g| faces[g as usize].contains(&kept))
        .collect();
    if shared.is_empty() || shared.len() > 2 {
        return false;
    }
    // The vertices opposite the edge in its faces are the only common neighbours allowed.
    let opposite: Vec<u32> = shared
        .iter()
        .flat_map(|&g| faces[g as usize])
        .filter(|&v| v != gone && v != kept)
        .collect();
    let neighbours = |v: u32| -> Vec<u32> {
        let mut list: Vec<u32> = live(v)
            .flat_map(|g| faces[g as usize])
            .filter(|&w| w != v)
            .collect();
        list.sort_unstable();
        list.dedup();
        list
    };
    let kept_neighbours = neighbours(kept);
    for w in neighbours(gone) {
        if w != kept && kept_neighbours.binary_search(&w).is_ok() && !opposite.contains(&w) {
            return false;
        }
    }
    // No face that stays turns over or becomes degenerate.
    for g in live(gone) {
        let face = faces[g as usize];
        if face.contains(&kept) {
            continue;
        }
        let before = face.map(|v| positions[v as usize]);
        let after = face.map(|v| positions[if v == gone { kept } else { v } as usize]);
        let normal = |p: [DVec3; 3]| (p[1] - p[0]).cross(p[2] - p[0]);
        if area_ratio(after) <= threshold
            || (area_ratio(before) > threshold && normal(before).dot(normal(after)) <= 0.0)
        {
            return false;
        }
    }
    true
}

/// Pairs the half-edges of an edge shared by more than two faces: repeatedly the two that
/// run it in opposite directions (agree in orientation), then those that already belong to
/// one fan at more of the edge's ends (so a pair closes a fan instead of joining two, and a
/// face that is alone in its fan at an end is the one left over), then those whose normals
/// are closest (closest in dihedral angle); if some remain, pairs running it the same way
/// (one of them is flipped later). Each half-edge is `(half-edge, runs from the smaller
/// vertex)`; `normal` gives a half-edge's face normal, `fans` its face's fan at the smaller
/// and at the larger vertex (corners joined through the mesh's two-face edges). Returns the
/// pairs; unpaired half-edges become boundary edges, and their ends, when alone in their
/// fans, are split off later, so that no two edges join the same two vertices.
pub(super) fn pair_fan(
    half_edges: &[(u32, bool)],
    normal: &dyn Fn(u32) -> DVec3,
    fans: &dyn Fn(u32) -> (u32, u32),
) -> Vec<(u32, u32)> {
    let mut candidates: Vec<(bool, u8, f64, usize, usize)> = Vec::new();
    for i in 0..half_edges.len() {
        for j in i + 1..half_edges.len() {
            let same = half_edges[i].1 == half_edges[j].1;
            let (ni, nj) = (normal(half_edges[i].0), normal(half_edges[j].0));
            let nj = if same { -nj } else { nj };
            let angle = ni.cross(nj).length().atan2(ni.dot(nj));
            let (fi, fj) = (fans(half_edges[i].0), fans(half_edges[j].0));
            let apart = u8::from(fi.0 != fj.0) + u8::from(fi.1 != fj.1);
            candidates.push((same, apart, angle, i, j));
        }
    }
    candidates.sort_by(|x, y| {
        x.0.cmp(&y.0)
            .then(x.1.cmp(&y.1))
            .then(x.2.total_cmp(&y.2))
            .then((x.3, x.4).cmp(&(y.3, y.4)))
    });
    let mut taken = vec![false; half_edges.len()];
    let mut pairs = Vec::new();
    for (_, _, _, i, j) in candidates {
        if !taken[i] && !taken[j] {
            taken[i] = true;
            taken[j] = true;
            pairs.push((half_edges[i].0, half_edges[j].0));
        }
    }
    pairs
}

/// The consistent orientation of every connected component, found by a flood fill over the
/// twinned edges (see [`orient_cutting`]).
pub(super) struct Orientation {
    /// Per face, whether it is flipped to agree with the first face of its component.
    pub(super) flip: Vec<bool>,
    /// The faces of each connected component, in increasing order, components in order of
    /// their first face.
    pub(super) components: Vec<Vec<u32>>,
    /// The edges cut open, each as its two former half-edges (first that of the face the
    /// fill reached the edge from), in increasing order of that half-edge (face order).
    pub(super) cut: Vec<(u32, u32)>,
}

/// Orients every connected component consistently: a breadth-first flood fill from each
/// component's first face decides for every face whether it flips, so that every twinned edge
/// is run in opposite directions by its two faces (`same_direction[he]`: the two faces of
/// half-edge `he` run it the same way as written). An edge reached from a face whose
/// neighbour across it is already decided, and decided the other way, closes a one-sided loop
/// of faces (the surface is not orientable there): it is cut open, its two half-edges lose
/// their twins in `twin`. The cut edges are the fill's conflicting edges, so the choice is
/// deterministic; after the cut every remaining twinned edge agrees with the flips.
pub(super) fn orient_cutting(twin: &mut [u32], same_direction: &[bool]) -> Orientation {
    const UNSEEN: u8 = 2;
    let face_count = twin.len() / 3;
    let mut flip = vec![UNSEEN; face_count];
    let mut components = Vec::new();
    let mut cut = Vec::new();
    let mut queue = std::collections::VecDeque::new();
    for start in 0..face_count {
        if flip[start] != UNSEEN {
            continue;
        }
        let mut members = vec![start as u32];
        flip[start] = 0;
        queue.push_back(start);
        while let Some(f) = queue.pop_front() {
            for he in 3 * f..3 * f + 3 {
                let t = twin[he];
                if t == NO_TWIN {
                    continue;
                }
                let g = t as usize / 3;
                let wanted = flip[f] ^ u8::from(same_direction[he]);
                if flip[g] == UNSEEN {
                    flip[g] = wanted;
                    members.push(g as u32);
                    queue.push_back(g);
                } else if flip[g] != wanted {
                    twin[he] = NO_TWIN;
                    twin[t as usize] = NO_TWIN;
                    cut.push((he as u32, t));
                }
            }
        }
        members.sort_unstable();
        components.push(members);
    }
    cut.sort_unstable();
    Orientation {
        flip: flip.iter().map(|&state| state == 1).collect(),
        components,
        cut,
    }
}

/// Groups the corners of every vertex into fans (corners joined through twinned edges) and
/// gives every fan but the first its own new vertex, appended after `vertex_count`. Returns,
/// for each new vertex, the vertex it was split from, and for each split vertex (in order)
/// its number of fans.
pub(super) fn split_fans(
    faces: &mut [[u32; 3]],
    twin: &[u32],
    vertex_count: usize,
) -> (Vec<u32>, Vec<(u32, usize)>) {
    let corners = 3 * faces.len();
    let mut parent: Vec<u32> = (0..corners as u32).collect();
    fn root(parent: &mut [u32], mut x: u32) -> u32 {
        while parent[x as usize] != x {
            parent[x as usize] = parent[parent[x as usize] as usize];
            x = parent[x as usize];
        }
        x
    }
    let corner_of = |faces: &[[u32; 3]], face: usize, v: u32| -> Option<u32> {
        faces[face]
            .iter()
            .position(|&w| w == v)
            .map(|c| (3 * face + c) as u32)
    };
    for he in 0..corners {
        let t = twin[he];
        if t == NO_TWIN || (t as usize) < he {
            continue;
        }
        let (f, g) = (he / 3, t as usize / 3);
        for v in [faces[f][he % 3], faces[f][(he + 1) % 3]] {
            if let (Some(a), Some(b)) = (corner_of(faces, f, v), corner_of(faces, g, v)) {
                let (ra, rb) = (root(&mut parent, a), root(&mut parent, b));
                parent[ra.max(rb) as usize] = ra.min(rb);
            }
        }
    }
    // The fan of each corner, and the first fan seen at each vertex keeps the vertex.
    let mut first_root = vec![u32::MAX; vertex_count];
    let mut new_vertex_of_root: std::collections::HashMap<u32, u32> = Default::default();
    let mut split_from = Vec::new();
    let mut fans_at: Vec<usize> = vec![1; vertex_count];
    for corner in 0..corners {
        let v = faces[corner / 3][corner % 3];
        let r = root(&mut parent, corner as u32);
        if first_root[v as usize] == u32::MAX {
            first_root[v as usize] = r;
        } else if first_root[v as usize] != r {
            let next = (vertex_count + split_from.len()) as u32;
            let new = *new_vertex_of_root.entry(r).or_insert_with(|| {
                split_from.push(v);
                fans_at[v as usize] += 1;
                next
            });
            faces[corner / 3][corner % 3] = new;
        }
    }
    let mut split: Vec<(u32, usize)> = (0..vertex_count as u32)
        .filter(|&v| fans_at[v as usize] > 1)
        .map(|v| (v, fans_at[v as usize]))
        .collect();
    // In order of the first face that made the split, so the first named is the first found.
    split.sort_by_key(|&(v, _)| split_from.iter().position(|&s| s == v));
    (split_from, split)
}

#[cfg(test)]
mod tests {
    use glam::DVec3;

    use super::{area_ratio, collapse_edge};

    #[test]
    fn a_cap_collapses_its_corner_into_the_nearer_end() {
        // Corner 2 lies on edge (0, 1), 0.3 from corner 1 and 0.7 from corner 0.
        let p = [DVec3::ZERO, DVec3::X, DVec3::new(0.7, 0.0, 0.0)];
        assert_eq!(collapse_edge(p), (2, 1));
        // Nearer to corner 0, and with the corners listed in another order.
        let p = [DVec3::new(0.2, 0.0, 0.0), DVec3::X, DVec3::ZERO];
        assert_eq!(collapse_edge(p), (0, 2));
        let p = [DVec3::X, DVec3::new(0.9, 0.0, 0.0), DVec3::ZERO];
        assert_eq!(collapse_edge(p), (1, 0));
    }

    #[test]
    fn a_needle_collapses_its_short_edge() {
        let p = [DVec3::ZERO, DVec3::X, DVec3::new(1e-17, 0.0, 0.0)];
        assert_eq!(collapse_edge(p), (2, 0));
        assert_eq!(area_ratio(p), 0.0);
    }
}
