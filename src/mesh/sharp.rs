//! Sharp edges: mesh edges across which a surface is only G0 (a crease of a CAD part), and
//! the smooth sectors they cut the fan of each vertex into.
//!
//! An edge is sharp when the angle between the normals of its two faces (the dihedral angle
//! as a turn, 0 for a flat pair) exceeds the crease angle ([`super::LoadOptions::crease_angle`]),
//! or when the file marks it: an OBJ edge between faces of different smoothing groups (`s`),
//! or whose two faces give one of its vertices different normals (`vn`). Both are honoured only
//! when a crease angle is set; the default keeps the papers' surfaces, which know no sharp
//! edges. Boundary edges are never sharp (they have one face).
//!
//! Around a vertex, the sharp edges cut the fan of faces into **sectors** (smooth pieces of the
//! fan): an interior vertex with k ≥ 2 sharp edges has k sectors, one with a single sharp edge
//! (a *dart*) keeps one sector, a boundary vertex with k sharp edges has k + 1. A vertex with
//! three or more sharp edges is a *corner*. Normal-based schemes take one normal per sector
//! ([`super::Mesh::corner_normals`]) and, along a sharp edge, a boundary curve whose end
//! tangents follow the crease ([`crease_tangent`]), so both sides share it.

use glam::DVec3;

use super::topology::NO_TWIN;

/// The sharp edges of a mesh, as a flag per half-edge (`3·face + edge`, both half-edges of a
/// sharp edge flagged).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct SharpEdges {
    half_edges: Vec<bool>,
    count: usize,
    by_angle: usize,
    from_file: usize,
    at_spikes: usize,
    first: Option<(u32, u32)>,
}

impl SharpEdges {
    /// True if no edge is sharp.
    pub fn is_empty(&self) -> bool {
        self.count == 0
    }
    /// Number of sharp (undirected) edges.
    pub fn count(&self) -> usize {
        self.count
    }
    /// Of those, the edges whose dihedral angle exceeds the crease angle.
    pub fn by_angle(&self) -> usize {
        self.by_angle
    }
    /// Of those, the edges the file marks (and the angle does not).
    pub fn from_file(&self) -> usize {
        self.from_file
    }
    /// Of those, the edges a construction made sharp at a spike of the mesh where its smooth
    /// surface folded ([`super::Mesh::with_spike_edges`]).
    pub fn at_spikes(&self) -> usize {
        self.at_spikes
    }
    /// The first sharp edge (as mesh vertices, smaller first), in half-edge order among those
    /// found while loading, else the first made sharp at a spike.
    pub fn first(&self) -> Option<(u32, u32)> {
        self.first
    }
    /// Marks the edge of half-edges `he` and `twin` (vertices `edge`) sharp at a spike, unless
    /// it is sharp already.
    pub(super) fn mark_at_spike(&mut self, he: usize, twin: usize, edge: (u32, u32)) {
        if self.half_edges[he] {
            return;
        }
        self.half_edges[he] = true;
        self.half_edges[twin] = true;
        self.count += 1;
        self.at_spikes += 1;
        self.first.get_or_insert(edge);
    }
    /// True if half-edge `he` (`3·face + edge`) lies on a sharp edge.
    pub fn is_sharp(&self, he: usize) -> bool {
        self.half_edges.get(he).copied().unwrap_or(false)
    }
}

/// The angle (rad) between the unit normals of two faces, accurate near 0 and π.
pub(crate) fn turn_angle(n0: DVec3, n1: DVec3) -> f64 {
    n0.cross(n1).length().atan2(n0.dot(n1))
}

/// Finds the sharp edges of oriented `faces` with half-edge `twin`s: every interior edge whose
/// faces' normals are more than `crease_angle_deg` degrees apart, and every edge in
/// `file_marked` (vertex pairs in either order). Returns no sharp edge when `crease_angle_deg`
/// is None.
pub(super) fn detect(
    positions: &[DVec3],
    faces: &[[u32; 3]],
    twin: &[u32],
    file_marked: &[[u32; 2]],
    crease_angle_deg: Option<f64>,
) -> SharpEdges {
    let mut sharp = SharpEdges {
        half_edges: vec![false; twin.len()],
        ..SharpEdges::default()
    };
    let Some(degrees) = crease_angle_deg else {
        return sharp;
    };
    let limit = degrees.to_radians();
    // Face normals of the positions normalised by their largest magnitude, so the cross
    // products neither under- nor overflow at any supported scale.
    let largest = positions
        .iter()
        .map(|p| p.abs().max_element())
        .fold(0.0, f64::max);
    let unit = if largest > 0.0 { 1.0 / largest } else { 1.0 };
    let normal = |f: usize| {
        let [a, b, c] = faces[f].map(|v| positions[v as usize] * unit);
        (b - a).cross(c - a).normalize_or_zero()
    };
    let mut marked: Vec<(u32, u32)> = file_marked
        .iter()
        .map(|&[a, b]| (a.min(b), a.max(b)))
        .collect();
    marked.sort_unstable();
    marked.dedup();
    for he in 0..twin.len() {
        let t = twin[he];
        if t == NO_TWIN || (t as usize) < he {
            continue;
        }
        let (f, g) = (he / 3, t as usize / 3);
        let (a, b) = (faces[f][he % 3], faces[f][(he + 1) % 3]);
        let by_angle = turn_angle(normal(f), normal(g)) > limit;
        let by_file = marked.binary_search(&(a.min(b), a.max(b))).is_ok();
        if by_angle || by_file {
            sharp.half_edges[he] = true;
            sharp.half_edges[t as usize] = true;
            sharp.count += 1;
            sharp.first.get_or_insert((a.min(b), a.max(b)));
            if by_angle {
                sharp.by_angle += 1;
            } else {
                sharp.from_file += 1;
            }
        }
    }
    sharp
}

/// The tangent direction (times the edge vector's component along it) with which a boundary
/// curve leaves vertex `a` along a sharp edge `a → b`, given the normals `n0`, `n1` of the two
/// sectors that meet at the edge there: `t (t · e)` with `t = n0 × n1 / |n0 × n1|` the crease
/// direction, which lies in both sectors' tangent planes. Where the two normals are parallel
/// (a dart, whose single sector is on both sides, or a flat sharp edge) it is `e` projected
/// into the plane of `n0 + n1`; where both normals are orthogonal to `e` (the faces' own, at
/// sectors of one face) it is `e`. The result is the same for `(n0, n1)` and `(n1, n0)` bit for
/// bit, so the faces on both sides of the edge build one curve.
pub fn crease_tangent(e: DVec3, n0: DVec3, n1: DVec3) -> DVec3 {
    /// Below this `|n0 × n1|` the crease direction is left to rounding; the common plane
    /// is used instead.
    const PARALLEL: f64 = 1e-9;
    /// Above this `|n · e| / |e|` a unit normal is not orthogonal to the edge.
    const ACROSS: f64 = 1e-12;
    // Two faces' own normals (sectors of one face each) are orthogonal to their common edge,
    // which is then their crease; n0 × n1 would give it only to rounding over |n0 × n1|.
    let length = e.length();
    if n0.dot(e).abs() <= ACROSS * length && n1.dot(e).abs() <= ACROSS * length {
        return e;
    }
    let cross = n0.cross(n1);
    let length = cross.length();
    if length > PARALLEL {
        let t = cross / length;
        t * t.dot(e)
    } else {
        // n0 + n1 is symmetric, and so is its normalisation.
        let n = (n0 + n1).normalize_or_zero();
        e - n * n.dot(e)
    }
}

#[cfg(test)]
mod tests {
    use glam::DVec3;

    use super::crease_tangent;
    use crate::mesh::{LoadOptions, Mesh};

    fn options(degrees: f64) -> LoadOptions {
        LoadOptions {
            crease_angle: Some(degrees),
            ..LoadOptions::default()
        }
    }

    #[test]
    fn a_cube_has_twelve_sharp_edges_above_its_diagonals() {
        let (positions, faces) = crate::mesh::generate::cube();
        let (mesh, _) = Mesh::from_triangles_with(positions.clone(), faces.clone(), &options(40.0))
            .expect("cube");
        // 18 edges: 12 cube edges at 90°, 6 face diagonals at 0°.
        assert_eq!(mesh.sharp_edges().count(), 12);
        assert_eq!(mesh.sharp_edges().by_angle(), 12);
        // Above 90° nothing is sharp; the default marks nothing.
        let (mesh, _) =
            Mesh::from_triangles_with(positions.clone(), faces.clone(), &options(90.5)).unwrap();
        assert!(mesh.sharp_edges().is_empty());
        let (mesh, _) = Mesh::from_triangles(positions, faces).unwrap();
        assert!(mesh.sharp_edges().is_empty());
    }

    #[test]
    fn the_crease_angle_is_a_strict_bound_at_any_scale() {
        let (positions, faces) = crate::mesh::generate::octahedron();
        // Octahedron: every dihedral turn is acos(1/3) = 70.53°.
        for scale in [1e-50, 1.0, 1e50] {
            let scaled: Vec<DVec3> = positions.iter().map(|&p| p * scale).collect();
            let (sharp, _) =
                Mesh::from_triangles_with(scaled.clone(), faces.clone(), &options(70.0)).unwrap();
            assert_eq!(sharp.sharp_edges().count(), 12, "scale {scale}");
            let (smooth, _) =
                Mesh::from_triangles_with(scaled, faces.clone(), &options(71.0)).unwrap();
            assert!(smooth.sharp_edges().is_empty(), "scale {scale}");
        }
    }

    #[test]
    fn sectors_split_fans_at_sharp_edges() {
        let (positions, faces) = crate::mesh::generate::cube();
        let (mesh, _) = Mesh::from_triangles_with(positions, faces, &options(40.0)).unwrap();
        let normals = mesh
            .vertex_normals(crate::mesh::NormalSource::Estimate)
            .unwrap();
        let corner_normals = mesh.corner_normals(&normals);
        // Every cube corner is a corner vertex: 3 sharp edges, 3 sectors, and each face
        // corner gets its own face's normal.
        for (f, corners) in corner_normals.iter().enumerate() {
            for n in corners {
                assert!(
                    (*n - mesh.face_normal(f as u32)).length() < 1e-15,
                    "face {f}: {n}"
                );
            }
        }
        assert_eq!(mesh.sharp_valence(0), 3);
    }

    #[test]
    fn crease_tangents_are_symmetric_and_follow_the_crease() {
        let e = DVec3::new(1.0, 0.3, -0.2);
        let (n0, n1) = (DVec3::Z, DVec3::new(0.0, -1.0, 0.0));
        let t = crease_tangent(e, n0, n1);
        assert_eq!(t, crease_tangent(e, n1, n0));
        assert!((t - DVec3::new(1.0, 0.0, 0.0)).length() < 1e-15, "{t}");
        // A dart: one normal on both sides is the plain projection.
        let n = DVec3::new(0.1, 0.2, 1.0).normalize();
        let p = crease_tangent(e, n, n);
        assert!(p.dot(n).abs() < 1e-15 && (p - (e - n * n.dot(e))).length() < 1e-15);
    }

    /// Two faces' own normals, both orthogonal to their common edge and 1e-7 rad apart: the
    /// crease is the edge itself, exactly, where `n0 × n1` would turn it by rounding over
    /// 1e-7 — and across the edge altogether when the normals' difference lies along it.
    #[test]
    fn the_crease_of_two_faces_own_normals_is_their_edge() {
        let e = DVec3::new(0.8, -0.1, 0.05);
        let side = DVec3::new(0.1, 0.9, 0.2).reject_from(e).normalize();
        let n0 = e.cross(side).normalize();
        let n1 = (n0 + 1e-7 * side).normalize();
        assert!(n0.dot(e).abs() < 1e-15 && n1.dot(e).abs() < 1e-15);
        assert_eq!(crease_tangent(e, n0, n1), e);
        assert_eq!(crease_tangent(e, n1, n0), e);
        // Normals that are not orthogonal to the edge keep the crease of their planes.
        let tilted = (n0 + 1e-3 * e).normalize();
        let t = crease_tangent(e, n0, tilted);
        assert!(t.dot(n0).abs() < 1e-15 && t.dot(tilted).abs() < 1e-15 && t != e);
    }
}
