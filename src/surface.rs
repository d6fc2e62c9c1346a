//! The common output of every scheme: a [`Surface`] is a list of [`Patch`]es, each of which
//! knows the mesh face it belongs to, which piece of that face it is, and which sub-triangle of
//! the face's domain it covers.
//!
//! A patch is a map `S(u, v)` over the unit triangle `u, v ≥ 0, u + v ≤ 1`, read as the
//! barycentric point `(1−u−v, u, v)` of the patch's own domain (so corner 0 is `(u,v) = (0,0)`,
//! corner 1 is `(1,0)`, corner 2 is `(0,1)`). Its `domain` gives the face-barycentric
//! coordinates of those three corners. From the domains alone the surface finds which patch
//! edges meet ([`Surface::joints`]) and which patch corners sit on mesh vertices
//! ([`Surface::vertex_corners`]); metrics, export and the renderer need nothing else.
//!
//! Patch kinds are a closed enum ([`PatchGeometry`]) so that hot loops dispatch statically.

use std::collections::HashMap;

use glam::{DMat3, DVec2, DVec3};

use crate::bezier::TriangleBezier;
use crate::blend::BlendPatch;
use crate::geom::{Aabb, Jet};
use crate::tolerance::{DIVISION_GUARD, DOMAIN_ZERO};

/// The geometry of one patch. Polynomial patches are Bézier triangles; non-polynomial
/// (blended) patch kinds are added as further variants.
#[derive(Clone, Debug, PartialEq)]
pub enum PatchGeometry {
    /// A triangular Bézier patch of any degree.
    Bezier(TriangleBezier),
    /// Three Bézier sub-surfaces blended with rational weights (Nielson, Fang–Mann); boxed,
    /// so that the far more common Bézier patches do not carry its size.
    Blend(Box<BlendPatch>),
}

/// One piece of a surface.
#[derive(Clone, Debug, PartialEq)]
pub struct Patch {
    /// The mesh face this patch belongs to.
    pub face: u32,
    /// Which piece of the face it is (scheme-specific numbering, e.g. HB00: 0..3 = S¹, S², S³, Sᵐ).
    pub piece: u8,
    /// Face-barycentric coordinates (weights of `faces[face][0..3]`) of the patch corners 0, 1, 2.
    pub domain: [DVec3; 3],
    /// The map itself.
    pub geometry: PatchGeometry,
}

/// Subdivisions per patch edge of the grid on which a patch is sampled for its regularity
/// and folds (`(n+1)(n+2)/2 = 45` points, corners and edges included).
pub(crate) const PATCH_GRID: usize = 8;

impl Patch {
    /// Samples of the [`PATCH_GRID`] where the patch turns over its mesh face: the normal
    /// `Su × Sv` points against the face's normal `face_normal`. A patch is parametrised with
    /// the orientation of its face (the export contract, docs/guide/contracts.md), so a surface
    /// that follows its mesh has none; a fold is where the surface doubles back over the face.
    /// Samples whose normal `Su × Sv` is zero to the rounding of the derivatives
    /// ([`Patch::derivative_rounding`]: a singular point, as where a patch corner's two edges
    /// are in line) have no orientation and are not counted. A Bézier patch whose normal's Bézier
    /// form proves it faces along `face_normal` everywhere ([`TriangleBezier::faces_along`])
    /// has none and is not sampled.
    pub(crate) fn fold_samples(&self, face_normal: DVec3) -> usize {
        if let PatchGeometry::Bezier(net) = &self.geometry
            && net.faces_along(face_normal)
        {
            return 0;
        }
        self.sampled_fold_samples(face_normal)
    }

    /// [`Patch::fold_samples`] by evaluating the grid.
    fn sampled_fold_samples(&self, face_normal: DVec3) -> usize {
        let n = PATCH_GRID;
        let unit = face_normal.normalize_or_zero();
        let delta = self.derivative_rounding();
        (0..=n)
            .flat_map(|i| (0..=n - i).map(move |j| (i, j)))
            .filter(|&(i, j)| {
                let (u, v) = (i as f64 / n as f64, j as f64 / n as f64);
                let jet = self.jet(u, v);
                // Su × Sv is known to δ(|Su| + |Sv|): below that it is no direction at all.
                let normal = jet.cross();
                normal.length() > delta * (jet.du.length() + jet.dv.length())
                    && normal.dot(unit) < 0.0
            })
            .count()
    }

    /// How far rounding may move the patch's first derivatives (absolute, in its units): its
    /// control points are stored as f64 offsets up to `R` in magnitude from the patch's origin
    /// ([`Patch::offset_magnitude`]), each within half an ulp of the construction's exact
    /// value, and de Casteljau's evaluation adds a rounding of that size per level; the
    /// derivative of a degree-`d` net multiplies the differences of its points by `d`. So
    /// `δ = 2·d·ε·R` (`ε = 2⁻⁵²`), an estimate of the rounding of the stored surface and its
    /// evaluation, not a rigorous bound (the metrics tests check it against pieces of one
    /// polynomial). A blend is taken at its sub-surfaces' degree.
    pub fn derivative_rounding(&self) -> f64 {
        let degree = match &self.geometry {
            PatchGeometry::Bezier(b) => b.degree(),
            PatchGeometry::Blend(b) => b.degree(),
        };
        2.0 * degree as f64 * f64::EPSILON * self.offset_magnitude()
    }

    /// Bit `e` set when edge `e` of the patch (corner e → e+1) lies on an edge of its mesh
    /// face: both corners' face-barycentric coordinates share a zero.
    pub fn face_edge_mask(&self) -> u8 {
        let mut mask = 0;
        for e in 0..3 {
            let (a, b) = (self.domain[e], self.domain[(e + 1) % 3]);
            if (0..3).any(|c| a[c].abs() < DOMAIN_ZERO && b[c].abs() < DOMAIN_ZERO) {
                mask |= 1 << e;
            }
        }
        mask
    }

    /// Point at `(u, v)`.
    pub fn eval(&self, u: f64, v: f64) -> DVec3 {
        match &self.geometry {
            PatchGeometry::Bezier(b) => b.eval(DVec3::new(1.0 - u - v, u, v)),
            PatchGeometry::Blend(b) => b.eval(u, v),
        }
    }

    /// Position and first and second derivatives at `(u, v)`.
    pub fn jet(&self, u: f64, v: f64) -> Jet {
        match &self.geometry {
            PatchGeometry::Bezier(b) => b.jet(u, v),
            PatchGeometry::Blend(b) => b.jet(u, v),
        }
    }

    /// All partial derivatives up to `max_order` at `(u, v)`, in the order of
    /// [`TriangleBezier::partials`]; `None` for patch kinds that provide only the second-order
    /// [`Patch::jet`].
    pub fn partials(&self, u: f64, v: f64, max_order: usize) -> Option<Vec<DVec3>> {
        match &self.geometry {
            PatchGeometry::Bezier(b) => Some(b.partials(u, v, max_order)),
            PatchGeometry::Blend(b) => b.partials(u, v, max_order),
        }
    }

    /// A box that contains the image of the sub-triangle of the `(u, v)` domain with corners
    /// `tri` (conservative: it may be larger than the image, never smaller).
    pub fn bounds(&self, tri: [DVec2; 3]) -> Aabb {
        let bary = tri.map(|c| DVec3::new(1.0 - c.x - c.y, c.x, c.y));
        match &self.geometry {
            PatchGeometry::Bezier(b) => b.sub_triangle_bounds(bary),
            PatchGeometry::Blend(b) => b.sub_triangle_bounds(bary),
        }
    }

    /// Every control point of the patch (of all sub-surfaces for a blend).
    pub fn control_points(&self) -> impl Iterator<Item = DVec3> + '_ {
        let nets: &[TriangleBezier] = match &self.geometry {
            PatchGeometry::Bezier(b) => std::slice::from_ref(b),
            PatchGeometry::Blend(b) => b.sub_surfaces(),
        };
        nets.iter().flat_map(|n| n.control_points())
    }

    /// The patch with every control point mapped by `f` (an affine map keeps every patch
    /// kind exact: Bézier nets and blended sub-surfaces transform point by point); domain and
    /// parametrisation unchanged.
    pub fn mapped(&self, f: impl Fn(DVec3) -> DVec3) -> Patch {
        let geometry = match &self.geometry {
            PatchGeometry::Bezier(b) => PatchGeometry::Bezier(b.map_points(&f)),
            PatchGeometry::Blend(b) => PatchGeometry::Blend(Box::new(BlendPatch::new(
                b.family(),
                b.sub_surfaces().each_ref().map(|n| n.map_points(&f)),
            ))),
        };
        Patch { geometry, ..*self }
    }

    /// The patch with every control point multiplied by `factor` (the surface scaled about
    /// the origin; domain and parametrisation unchanged): each net's origin and offsets
    /// scaled ([`TriangleBezier::scaled`]), exact for a power of two.
    pub fn scaled(&self, factor: f64) -> Patch {
        let geometry = match &self.geometry {
            PatchGeometry::Bezier(b) => PatchGeometry::Bezier(b.scaled(factor)),
            PatchGeometry::Blend(b) => PatchGeometry::Blend(Box::new(BlendPatch::new(
                b.family(),
                b.sub_surfaces().each_ref().map(|n| n.scaled(factor)),
            ))),
        };
        Patch { geometry, ..*self }
    }

    /// The largest coordinate magnitude of the stored offsets of its nets
    /// ([`TriangleBezier::offset_magnitude`]): the scale the patch is rounded at.
    pub fn offset_magnitude(&self) -> f64 {
        let nets: &[TriangleBezier] = match &self.geometry {
            PatchGeometry::Bezier(b) => std::slice::from_ref(b),
            PatchGeometry::Blend(b) => b.sub_surfaces(),
        };
        nets.iter()
            .map(TriangleBezier::offset_magnitude)
            .fold(0.0, f64::max)
    }

    /// Bounds of the whole patch.
    pub fn full_bounds(&self) -> Aabb {
        match &self.geometry {
            PatchGeometry::Bezier(b) => b.control_bounds(),
            PatchGeometry::Blend(b) => b.control_bounds(),
        }
    }

    /// Patch parameters `(u, v)` of the face-barycentric point `bary` (affine in `bary`; a
    /// point outside the patch gets a negative weight). `None` for a degenerate domain.
    pub fn uv_of(&self, bary: DVec3) -> Option<DVec2> {
        let l = self.domain_inverse()? * bary;
        Some(DVec2::new(l.y, l.z))
    }

    /// The `(u, v)` direction of a face-barycentric direction `dir` (components summing to 0).
    pub fn uv_direction(&self, dir: DVec3) -> Option<DVec2> {
        self.uv_of(dir)
    }

    /// Inverse of the map from patch barycentric weights to face-barycentric coordinates.
    fn domain_inverse(&self) -> Option<DMat3> {
        let m = DMat3::from_cols(self.domain[0], self.domain[1], self.domain[2]);
        (m.determinant().abs() > DIVISION_GUARD).then(|| m.inverse())
    }

    /// Polynomial degree, if the patch is polynomial.
    pub fn degree(&self) -> Option<usize> {
        match &self.geometry {
            PatchGeometry::Bezier(b) => Some(b.degree()),
            PatchGeometry::Blend(_) => None,
        }
    }

    /// The Bézier form, if the patch is polynomial.
    pub fn as_bezier(&self) -> Option<&TriangleBezier> {
        match &self.geometry {
            PatchGeometry::Bezier(b) => Some(b),
            PatchGeometry::Blend(_) => None,
        }
    }

    /// The blend, if the patch is a blended (non-polynomial) patch.
    pub fn as_blend(&self) -> Option<&BlendPatch> {
        match &self.geometry {
            PatchGeometry::Blend(b) => Some(b),
            PatchGeometry::Bezier(_) => None,
        }
    }
}

/// The domain of a patch that covers its whole mesh face, corners on the face's corners
/// (face-barycentric coordinates, see [`Patch::domain`]).
pub const WHOLE_FACE: [DVec3; 3] = [DVec3::X, DVec3::Y, DVec3::Z];

/// The corners of the unit `(u, v)` triangle, in corner order.
pub const UV_CORNERS: [DVec2; 3] = [DVec2::ZERO, DVec2::X, DVec2::Y];

/// The `(u, v)` point at fraction `s` along edge `edge` of a patch (edge e runs from corner e
/// to corner (e+1) mod 3).
pub fn edge_uv(edge: usize, s: f64) -> DVec2 {
    let (a, b) = (UV_CORNERS[edge % 3], UV_CORNERS[(edge + 1) % 3]);
    a + (b - a) * s
}

/// Number of samples taken along every joint by the metrics and the edge-samples export.
///
/// They sit at fractions `s = i/16` for `i = 1..15` plus `s = 1/1024` and `s = 1 − 1/1024`
/// near (not at) the two ends: a corner where several patches meet is where a
/// parametrisation may be singular (`Su × Sv = 0`), and there the normal is undefined rather
/// than discontinuous. All fractions are dyadic, so `s` and `1 − s` are exact and both sides
/// of a joint are evaluated at exactly the same domain point.
pub const JOINT_SAMPLES: usize = 17;

/// Distance (as a fraction of the edge) of the first and last sample from the edge's ends.
pub const END_OFFSET: f64 = 1.0 / 1024.0;

/// The fractions along an edge at which a joint is sampled, in increasing order.
pub fn joint_fractions() -> [f64; JOINT_SAMPLES] {
    let mut s = [0.0; JOINT_SAMPLES];
    for (i, slot) in s.iter_mut().enumerate() {
        *slot = match i {
            0 => END_OFFSET,
            i if i == JOINT_SAMPLES - 1 => 1.0 - END_OFFSET,
            i => i as f64 / (JOINT_SAMPLES - 1) as f64,
        };
    }
    s
}

/// One edge of one patch.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct PatchEdge {
    /// Patch index in [`Surface::patches`].
    pub patch: u32,
    /// Edge 0, 1 or 2 (from corner e to corner e+1).
    pub edge: u8,
}

/// Two patch edges that cover the same curve of the domain.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Joint {
    /// One side.
    pub a: PatchEdge,
    /// The other side.
    pub b: PatchEdge,
    /// True if `b` runs in the opposite direction (fraction s on `a` is 1 − s on `b`).
    pub reversed: bool,
    /// True if the two patches belong to different mesh faces.
    pub between_faces: bool,
}

/// A patch corner that sits on a mesh vertex.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct VertexCorner {
    /// The mesh vertex.
    pub vertex: u32,
    /// The patch.
    pub patch: u32,
    /// Its corner (0, 1, 2).
    pub corner: u8,
}

/// A local frame of a mesh: its bounding-box centre moved to the origin and its
/// bounding-box diagonal scaled by a power of two into `[1, 2)`. Schemes build and metrics
/// measure in it, so that no figure depends on where the mesh is or on its size: the
/// coordinates keep their full precision however far from the origin the mesh lies (a mesh
/// at 1e15 has coordinates of ulp 0.125 in the user's frame, of ulp 2^-52 here), and the
/// power-of-two scale is exact.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LocalFrame {
    /// The user's point at the frame's origin.
    pub centre: DVec3,
    /// Local lengths per user length (a power of two).
    pub scale: f64,
}

impl LocalFrame {
    /// The frame of `points`: their bounding-box centre and the power of two that brings
    /// their diagonal into `[1, 2)` (scale 1 for a single point or an empty set).
    pub fn of_points(points: &[DVec3]) -> LocalFrame {
        let bounds = Aabb::from_points(points);
        let d = bounds.diagonal();
        let finite = d > 0.0 && d.is_finite();
        LocalFrame {
            centre: if points.is_empty() {
                DVec3::ZERO
            } else {
                bounds.center()
            },
            scale: if finite {
                (-d.log2().floor()).exp2()
            } else {
                1.0
            },
        }
    }

    /// The local coordinates of the user's point `p`.
    pub fn to_local(&self, p: DVec3) -> DVec3 {
        (p - self.centre) * self.scale
    }

    /// The user's coordinates of the local point `q`.
    pub fn to_user(&self, q: DVec3) -> DVec3 {
        q / self.scale + self.centre
    }
}

/// The surface a scheme builds from a mesh.
#[derive(Clone, Debug)]
pub struct Surface {
    /// Registered scheme name.
    pub scheme: String,
    /// The scheme's parameters with defaults filled in, as `name → value`.
    pub params: Vec<(String, String)>,
    /// The patches.
    pub patches: Vec<Patch>,
    /// What the construction changed or could not do at particular mesh elements (e.g. a
    /// vertex normal moved so that the surface does not fold), one line each naming the first
    /// element; the commands print them as `warning:` lines.
    pub warnings: Vec<String>,
    /// The face pairs `(f, g)`, `f < g`, sorted, across the edges the construction made sharp
    /// where its smooth surface would fold, at spikes of the mesh and round the faces that
    /// still folded (`Mesh::with_spike_edges`): the surface is G0 across them, and the
    /// metrics count them with the mesh's own sharp edges. Empty on most meshes.
    pub spike_face_pairs: Vec<(u32, u32)>,
}

/// A point of a mesh's domain, independent of the face it is written in.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
enum DomainKey {
    Vertex(u32),
    /// On edge (a, b) with a < b, at fraction t from a (quantised).
    Edge(u32, u32, i64),
    /// Inside a face, at quantised barycentric (b1, b2).
    Interior(u32, i64, i64),
}

/// Domain coordinates are exact simple fractions (0, 1/2, 1/3, …); quantising them to 1e-9
/// identifies equal points written in different faces without tolerance games.
fn quantise(x: f64) -> i64 {
    (x * 1e9).round() as i64
}

fn domain_key(face_vertices: [u32; 3], face: u32, bary: DVec3) -> DomainKey {
    let w = bary.to_array();
    let q = w.map(quantise);
    let one = quantise(1.0);
    if let Some(c) = (0..3).find(|&c| q[c] == one) {
        return DomainKey::Vertex(face_vertices[c]);
    }
    if let Some(c) = (0..3).find(|&c| q[c] == 0) {
        let (i, j) = ((c + 1) % 3, (c + 2) % 3);
        let (va, vb) = (face_vertices[i], face_vertices[j]);
        return if va < vb {
            DomainKey::Edge(va, vb, q[j])
        } else {
            DomainKey::Edge(vb, va, q[i])
        };
    }
    DomainKey::Interior(face, q[1], q[2])
}

impl Surface {
    /// The same surface with every control point mapped by `f` (an affine map keeps every
    /// patch kind exact: Bézier nets and blended sub-surfaces transform point by point).
    pub fn mapped(&self, f: impl Fn(DVec3) -> DVec3) -> Surface {
        Surface {
            scheme: self.scheme.clone(),
            warnings: self.warnings.clone(),
            spike_face_pairs: self.spike_face_pairs.clone(),
            params: self.params.clone(),
            patches: self.patches.iter().map(|patch| patch.mapped(&f)).collect(),
        }
    }

    /// [`Surface::mapped`] consuming the surface: Bézier nets are mapped in place, so a large
    /// surface is never held twice (blends, whose sub-surfaces are rebuilt, are mapped anew).
    pub fn into_mapped(mut self, f: impl Fn(DVec3) -> DVec3) -> Surface {
        for patch in &mut self.patches {
            match &mut patch.geometry {
                PatchGeometry::Bezier(net) => net.map_points_in_place(&f),
                PatchGeometry::Blend(_) => *patch = patch.mapped(&f),
            }
        }
        self
    }

    /// Bounding box of all patches (control-net bounds: contains the surface).
    pub fn bounds(&self) -> Aabb {
        self.patches
            .iter()
            .fold(Aabb::EMPTY, |b, p| b.union(p.full_bounds()))
    }

    /// The index of the first patch with a NaN or infinite control point.
    pub fn first_non_finite_patch(&self) -> Option<usize> {
        self.patches
            .iter()
            .position(|p| !p.control_points().all(|q| q.is_finite()))
    }

    /// The surface scaled about the origin by `factor` (see [`Patch::scaled`]).
    pub fn scaled(&self, factor: f64) -> Surface {
        Surface {
            scheme: self.scheme.clone(),
            warnings: self.warnings.clone(),
            spike_face_pairs: self.spike_face_pairs.clone(),
            params: self.params.clone(),
            patches: self.patches.iter().map(|p| p.scaled(factor)).collect(),
        }
    }

    /// Every pair of patch edges that cover the same domain curve, found from the patch
    /// domains and the mesh faces. Patch edges with no partner (mesh boundary) are left out.
    ///
    /// `edge_ids` names the mesh edge of every half-edge `3·face + edge` by a number shared by
    /// exactly its two half-edges (`Mesh::edge_ids`), so that patch edges along a mesh edge
    /// pair only across that edge even where two edges join the same two vertices; `None`
    /// identifies mesh edges by their two vertices, which is right where no two edges do.
    pub fn joints(&self, faces: &[[u32; 3]], edge_ids: Option<&[u32]>) -> Vec<Joint> {
        let mut open: HashMap<(Option<u32>, DomainKey, DomainKey), PatchEdge> = HashMap::new();
        let mut joints = Vec::new();
        for (pi, patch) in self.patches.iter().enumerate() {
            let fv = faces[patch.face as usize];
            let keys = patch.domain.map(|b| domain_key(fv, patch.face, b));
            for e in 0..3 {
                let here = PatchEdge {
                    patch: pi as u32,
                    edge: e as u8,
                };
                let (b0, b1) = (patch.domain[e], patch.domain[(e + 1) % 3]);
                // Face edge c (corner c to c + 1) carries the patch edge when both its ends
                // have no weight on the opposite corner.
                let carrier = edge_ids.and_then(|ids| {
                    (0..3)
                        .find(|&c| {
                            let opposite = (c + 2) % 3;
                            quantise(b0[opposite]) == 0 && quantise(b1[opposite]) == 0
                        })
                        .map(|c| ids[3 * patch.face as usize + c])
                });
                let (k0, k1) = (keys[e], keys[(e + 1) % 3]);
                if let Some(other) = open.remove(&(carrier, k1, k0)) {
                    joints.push(self.joint(other, here, true));
                } else if let Some(other) = open.remove(&(carrier, k0, k1)) {
                    joints.push(self.joint(other, here, false));
                } else {
                    open.insert((carrier, k0, k1), here);
                }
            }
        }
        joints
    }

    fn joint(&self, a: PatchEdge, b: PatchEdge, reversed: bool) -> Joint {
        Joint {
            a,
            b,
            reversed,
            between_faces: self.patches[a.patch as usize].face
                != self.patches[b.patch as usize].face,
        }
    }

    /// The patch of face `face` whose domain contains the face-barycentric point `bary`, with
    /// the patch parameters `(u, v)` of that point (the first such patch in patch order; points
    /// on a shared patch edge belong to both). `face_patches` lists the patch indices of each
    /// face ([`Surface::patches_by_face`]).
    pub fn locate(
        &self,
        face_patches: &[Vec<u32>],
        face: u32,
        bary: DVec3,
    ) -> Option<(u32, DVec2)> {
        const INSIDE: f64 = -1e-12;
        face_patches.get(face as usize)?.iter().find_map(|&pi| {
            let patch = &self.patches[pi as usize];
            let uv = patch.uv_of(bary)?;
            (uv.x >= INSIDE && uv.y >= INSIDE && 1.0 - uv.x - uv.y >= INSIDE).then_some((pi, uv))
        })
    }

    /// The patch indices of each mesh face (`face_count` lists).
    pub fn patches_by_face(&self, face_count: usize) -> Vec<Vec<u32>> {
        let mut out = vec![Vec::new(); face_count];
        for (i, p) in self.patches.iter().enumerate() {
            if let Some(list) = out.get_mut(p.face as usize) {
                list.push(i as u32);
            }
        }
        out
    }

    /// Every patch corner that lies on a mesh vertex.
    pub fn vertex_corners(&self, faces: &[[u32; 3]]) -> Vec<VertexCorner> {
        let mut out = Vec::new();
        for (pi, patch) in self.patches.iter().enumerate() {
            let fv = faces[patch.face as usize];
            for (c, b) in patch.domain.iter().enumerate() {
                if let DomainKey::Vertex(v) = domain_key(fv, patch.face, *b) {
                    out.push(VertexCorner {
                        vertex: v,
                        patch: pi as u32,
                        corner: c as u8,
                    });
                }
            }
        }
        out
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn flat_patch(face: u32, domain: [DVec3; 3]) -> Patch {
        Patch {
            face,
            piece: 0,
            domain,
            geometry: PatchGeometry::Bezier(TriangleBezier::new(
                1,
                vec![DVec3::ZERO, DVec3::X, DVec3::Y],
            )),
        }
    }

    /// The proof that a patch faces along its face's normal never hides a fold sample: on
    /// the hb, loop94 and pn surfaces of the scanned bunnies (folds included: the papers'
    /// surfaces of `bunny-irregular` fold) and on nets of every degree 1–7 with their
    /// points jittered more and more, wherever `faces_along` holds the 45-point grid finds
    /// no sample turned over; and it holds on most patches of a smooth surface, so the grid
    /// is rarely sampled.
    #[test]
    fn a_patch_proved_to_face_along_its_normal_has_no_fold_sample() {
        use crate::testing::Rng;
        let mut checked = Vec::new();
        for scene in ["bunny", "bunny-irregular"] {
            let mesh = crate::testing::scene(scene);
            for scheme in ["hb", "loop94", "pn"] {
                let surface = crate::schemes::build(scheme, &mesh, &[]).expect("surface");
                let proved = surface
                    .patches
                    .iter()
                    .filter(|p| {
                        let normal = mesh.face_normal(p.face);
                        let proved = p.as_bezier().expect("bezier").faces_along(normal);
                        if proved {
                            assert_eq!(p.sampled_fold_samples(normal), 0, "{scene} {scheme}");
                        }
                        proved
                    })
                    .count();
                checked.push((scene, scheme, proved, surface.patches.len()));
            }
        }
        for &(scene, scheme, proved, all) in &checked {
            assert!(
                proved * 10 >= all * 9,
                "{scene} {scheme}: {proved} of {all} proved"
            );
        }
        let mut rng = Rng::new(7);
        let (mut proved, mut folding) = (0, 0);
        for degree in 1..=7 {
            for case in 0..400 {
                let jitter = 0.02 * f64::from(case % 20);
                let net = TriangleBezier::from_fn(degree, |i, j, _| {
                    let (x, y) = (
                        j as f64 / degree as f64,
                        (degree - i - j) as f64 / degree as f64,
                    );
                    DVec3::new(x, y, 0.3 * x * y)
                        + DVec3::new(
                            rng.range(-1.0, 1.0),
                            rng.range(-1.0, 1.0),
                            rng.range(-1.0, 1.0),
                        ) * jitter
                });
                let patch = Patch {
                    face: 0,
                    piece: 0,
                    domain: [DVec3::X, DVec3::Y, DVec3::Z],
                    geometry: PatchGeometry::Bezier(net),
                };
                let normal = DVec3::Z;
                let samples = patch.sampled_fold_samples(normal);
                folding += usize::from(samples > 0);
                if patch.as_bezier().expect("bezier").faces_along(normal) {
                    proved += 1;
                    assert_eq!(samples, 0, "degree {degree}, case {case}");
                }
            }
        }
        assert!(
            proved > 500 && folding > 500,
            "{proved} proved, {folding} folding"
        );
    }

    /// Two faces (0,1,2) and (2,1,3) share edge (1,2), written in opposite directions; a
    /// 2-split of face 0 at the midpoint of edge (1,2) gives a joint inside the face.
    #[test]
    fn joints_are_found_from_domains() {
        let faces = [[0, 1, 2], [2, 1, 3]];
        let (e0, e1, e2) = (DVec3::X, DVec3::Y, DVec3::Z);
        let mid12 = DVec3::new(0.0, 0.5, 0.5);
        let surface = Surface {
            scheme: "test".into(),
            warnings: Vec::new(),
            spike_face_pairs: Vec::new(),
            params: vec![],
            patches: vec![
                flat_patch(0, [e0, e1, mid12]),
                flat_patch(0, [e0, mid12, e2]),
                flat_patch(1, [e0, e1, e2]),
            ],
        };
        let joints = surface.joints(&faces, None);
        // Inside face 0: edge (corner 2 → 0) of patch 0 with edge (0 → 1) of patch 1.
        let inside: Vec<_> = joints.iter().filter(|j| !j.between_faces).collect();
        assert_eq!(inside.len(), 1, "{joints:?}");
        assert!(inside[0].reversed);
        // Face 1 edge (2 → 1) is covered by two half edges of face 0: no full-edge partner, so
        // the halves stay unmatched (schemes must split both sides alike).
        assert_eq!(joints.len(), 1, "{joints:?}");
        let corners = surface.vertex_corners(&faces);
        assert_eq!(corners.len(), 2 + 2 + 3);
    }

    /// Faces 0 and 2 share their edge 0 (vertices 0 and 1); face 1 runs between the same two
    /// vertices along a boundary edge of its own. By vertices alone face 1 is paired with face
    /// 0, the first face open there; the edge numbers pair faces 0 and 2.
    #[test]
    fn joints_follow_the_edge_numbers_where_two_edges_join_the_same_vertices() {
        let faces = [[0, 1, 2], [0, 1, 4], [1, 0, 3]];
        let whole = [DVec3::X, DVec3::Y, DVec3::Z];
        let surface = Surface {
            scheme: "test".into(),
            warnings: Vec::new(),
            spike_face_pairs: Vec::new(),
            params: vec![],
            patches: (0..3).map(|f| flat_patch(f, whole)).collect(),
        };
        let faces_of = |joints: Vec<Joint>| -> Vec<(u32, u32, bool)> {
            joints
                .iter()
                .map(|j| {
                    let (f, g) = (
                        surface.patches[j.a.patch as usize].face,
                        surface.patches[j.b.patch as usize].face,
                    );
                    (f, g, j.reversed)
                })
                .collect()
        };
        assert_eq!(faces_of(surface.joints(&faces, None)), [(0, 1, false)]);
        let edge_ids = [0, 1, 2, 3, 4, 5, 0, 7, 8];
        assert_eq!(
            faces_of(surface.joints(&faces, Some(&edge_ids))),
            [(0, 2, true)]
        );
    }
}
