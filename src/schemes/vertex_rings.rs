//! Machinery shared by the vertex-local G¹ schemes (HB00, Loop94): data computed for every
//! directed edge `v → p_i` from the one-ring of `v` alone, stored in one flat table, the index
//! arithmetic from a face corner to its directed edges and their reverses, and the discrete
//! Fourier sums of a one-ring that both schemes build their tangents from [HB00 eqs. 12, 17].

use std::f64::consts::PI;

use glam::DVec3;
use rayon::prelude::*;

use crate::mesh::Mesh;
use crate::mesh::front_facing::{FrontFacing, front_facing_by, min_cosine};

/// How the scalar `Ψ` of the cross-boundary derivative `Φ E' ± Ψ V` runs along an edge from
/// `Ψ(0) = sin(2π/n)` at one end to `Ψ(1) = sin(2π/n_i)` at the other [HB00 eqs. 18, 20].
///
/// Along the edge the product `ΨV` is what the surface sees, and `V'(0)` is solved from it
/// (eq. 22: `Ψ(0) V'(0) = … − Ψ'(0) V(0)`), so `V` bends by about `Ψ'(0)/Ψ(0)` per unit of
/// the edge to keep `ΨV` on course. Linear `Ψ` makes that ratio `sin(2π/n_i)/sin(2π/n) − 1`,
/// unbounded as the valence `n` grows (or as the angle step of a sector narrows, whose `Ψ(0)`
/// is the sine of that step): at a pole of valence 64 beside valence 6 it is 7.8, the
/// quadratic `V` cannot follow `1/Ψ`, and `ΨV` turns over in the middle of the edge (the
/// surface folds over both faces; measured on a bipyramid of valence 40 and a UV sphere of 64
/// segments). HB00's 4-split needs `Ψ` only continuous at the edge midpoint (§7: `Ψ` and `V`
/// "continuous and piecewise polynomial of degree 1 and 2"; §8.3: C¹ inside the macro-patch
/// follows from continuity at `u = ½`), so `Ψ(½)` is free.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum PsiRule {
    /// HB00 eq. 20 and Loop94 eq. 4: linear over the edge, `Ψ(½)` the mean of its ends.
    Linear,
    /// `Ψ(½)` the harmonic mean `2ab/(a + b)` of the ends: for hb linear on each half of the
    /// edge, for loop94 the quadratic with that middle Bernstein coefficient (Loop94's `ΨV`
    /// may be quintic, eq. 3, and is a quartic with `Ψ` linear). Either way
    /// `|Ψ'(0)/Ψ(0)| = 2|a − b|/(a + b) < 2` at both ends for any valences, and `Ψ` is
    /// [`PsiRule::Linear`]'s where the two ends have the same valence.
    Harmonic,
}

impl PsiRule {
    /// `Ψ(½)` of an edge whose ends have `Ψ(0) = near` and `Ψ(1) = far` (for a quadratic `Ψ`,
    /// its middle Bernstein coefficient).
    pub(crate) fn middle(self, near: f64, far: f64) -> f64 {
        match self {
            PsiRule::Linear => 0.5 * (near + far),
            PsiRule::Harmonic if near == far => near,
            PsiRule::Harmonic => 2.0 * near * far / (near + far),
        }
    }

    /// `Ψ'(0)` at the `near` end, per unit of the edge parameter `u ∈ [0, 1]` (eq. 22's `Ψ¹`).
    pub(crate) fn slope(self, near: f64, far: f64) -> f64 {
        match self {
            PsiRule::Linear => far - near,
            PsiRule::Harmonic => 2.0 * (self.middle(near, far) - near),
        }
    }

    /// `Ψ'(0)` towards `far_a` minus `Ψ'(0)` towards `far_b`, both from `near`.
    pub(crate) fn slope_difference(self, near: f64, far_a: f64, far_b: f64) -> f64 {
        match self {
            PsiRule::Linear => far_a - far_b,
            PsiRule::Harmonic => self.slope(near, far_a) - self.slope(near, far_b),
        }
    }
}

/// `Φ_i(0) = cos(2π/n)` [HB00 eq. 6].
pub(crate) fn phi0(n: usize) -> f64 {
    (2.0 * PI / n as f64).cos()
}

/// `Ψ_i(0) = sin(2π/n)` [HB00 eq. 20].
pub(crate) fn psi0(n: usize) -> f64 {
    (2.0 * PI / n as f64).sin()
}

/// Discrete Fourier sums of a one-ring `p_0..p_{n−1}` with `θ = 2π/n`:
/// `C = Σ cos(θj) p_j`, `S = Σ sin(θj) p_j`, so that every rotated sum is O(1).
#[derive(Clone, Copy, Debug)]
pub(crate) struct RingFourier {
    theta: f64,
    cos_part: DVec3,
    sin_part: DVec3,
    mean: DVec3,
}

impl RingFourier {
    /// The sums of `ring`.
    pub(crate) fn new(ring: &[DVec3]) -> RingFourier {
        let theta = 2.0 * PI / ring.len() as f64;
        let (mut cos_part, mut sin_part, mut mean) = (DVec3::ZERO, DVec3::ZERO, DVec3::ZERO);
        for (j, p) in ring.iter().enumerate() {
            let (s, c) = (theta * j as f64).sin_cos();
            cos_part += c * *p;
            sin_part += s * *p;
            mean += *p;
        }
        RingFourier {
            theta,
            cos_part,
            sin_part,
            mean: mean / ring.len() as f64,
        }
    }

    /// The same sums with their components along the unit `normal` removed: the ring's first
    /// harmonic seen in the plane with that normal (the centroid is kept).
    pub(crate) fn in_plane(self, normal: DVec3) -> RingFourier {
        RingFourier {
            cos_part: self.cos_part.reject_from_normalized(normal),
            sin_part: self.sin_part.reject_from_normalized(normal),
            ..self
        }
    }

    /// Unit normal of the plane of the first harmonic, `C × S` (zero if they are parallel).
    pub(crate) fn normal(&self) -> DVec3 {
        self.cos_part.cross(self.sin_part).normalize_or_zero()
    }

    /// Centroid of the ring.
    pub(crate) fn mean(&self) -> DVec3 {
        self.mean
    }

    /// `Σ_j cos(θ(j−i)) p_j` (the first-order Fourier component seen from edge i).
    pub(crate) fn cos_sum(&self, i: usize) -> DVec3 {
        let (s, c) = (self.theta * i as f64).sin_cos();
        c * self.cos_part + s * self.sin_part
    }

    /// `Σ_j sin(θ(j−i)) p_j`.
    pub(crate) fn sin_sum(&self, i: usize) -> DVec3 {
        let (s, c) = (self.theta * i as f64).sin_cos();
        c * self.sin_part - s * self.cos_part
    }

    /// `Σ_j [cos(θ(j−i)) + tan(θ/2) sin(θ(j−i))] p_j`: the preimage under the twist matrix
    /// `T` of (II_T) (`½(x_i + x_{i−1})`) of the cosine sums [HB00 §6, b̃¹].
    pub(crate) fn twist_preimage_sum(&self, i: usize) -> DVec3 {
        self.cos_sum(i) + (self.theta / 2.0).tan() * self.sin_sum(i)
    }
}

impl RingFourier {
    /// The same ring with its first harmonic replaced by `cos_part`, `sin_part` (centroid and
    /// angle step kept).
    fn with_harmonic(self, cos_part: DVec3, sin_part: DVec3) -> RingFourier {
        RingFourier {
            cos_part,
            sin_part,
            ..self
        }
    }

    /// The closest rotation-and-scale of the ring's first harmonic in the plane with the unit
    /// `normal`: with `C`, `S` projected into the plane and written in an orthonormal frame
    /// `(e1, e2 = normal × e1)`, the harmonic `C e^{iθj}`-part `z = ½((C1 + S2) + i(C2 − S1))`
    /// (the conformal part of the linear map `(cos, sin) ↦ C cos + S sin`). The result has
    /// `C ⊥ S`, `|C| = |S|` and `C × S` along `+normal` (unless it vanishes): tangents evenly
    /// spaced by the angle step, turning the right way round the normal.
    fn conformal_in(self, normal: DVec3) -> RingFourier {
        let e1 = normal.any_orthonormal_vector();
        let e2 = normal.cross(e1);
        let (c, s) = (self.cos_part, self.sin_part);
        let a = 0.5 * (c.dot(e1) + s.dot(e2));
        let b = 0.5 * (c.dot(e2) - s.dot(e1));
        self.with_harmonic(a * e1 + b * e2, a * e2 - b * e1)
    }
}

/// The margin a moved tangent plane keeps from every face around its vertex: the plane's
/// normal `N` is tilted until `N · n_f ≥ 0.1` for the unit normal `n_f` of each face (about
/// 5.7° off the face's plane), the largest decade below that the one-ring admits otherwise
/// ([`front_facing_by`]). A face seen this close to edge-on is projected into the plane as a
/// corner of tiny but right-handed angle.
pub(crate) const PLANE_MARGIN: f64 = 0.1;

/// A plane is moved only when a face around the vertex sees its normal from behind or
/// edge-on: `N · n_f < 1e-3` ([`crate::mesh::front_facing::FRONT_MARGIN`]). A clean mesh,
/// whose faces all see their vertices' planes from the front, keeps every plane bit for bit.
pub(crate) const PLANE_TRIGGER: f64 = crate::mesh::front_facing::FRONT_MARGIN;

/// Above this tilt (rad) the ring's first harmonic projected into the moved plane is no
/// guide to the tangents (it was computed for a plane far from this one, and its projection
/// can turn the wrong way round): it is replaced by its closest rotation-and-scale
/// ([`RingFourier`]'s conformal part). Below it, likewise whenever the projection would not
/// turn the right way round by a sine of at least [`PLANE_MIN_SINE`].
pub(crate) const LARGE_TILT: f64 = 0.35;

/// The smallest sine between the projected harmonic's `C` and `S` (turning the right way
/// round the moved plane's normal) kept as it is; below, the conformal fit is used.
pub(crate) const PLANE_MIN_SINE: f64 = 0.2;

/// What [`front_facing_plane`] did with a vertex's tangent plane.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) enum PlaneMove {
    /// Every face sees the plane from the front: kept bit for bit.
    Kept,
    /// Tilted by `angle` (rad) to the closest plane the faces see from the front; `conformal`
    /// when the harmonic was replaced by its rotation-and-scale fit.
    Tilted {
        /// Angle between the old and the new normal.
        angle: f64,
        /// The harmonic was replaced by its closest rotation-and-scale.
        conformal: bool,
    },
    /// No plane is seen from the front by every face (the one-ring folds over itself): the
    /// plane is kept, and the surface folds at this vertex.
    Folded,
}

/// The unit normals of the faces `(v, ring[i], ring[i+1])` of a closed one-ring (zero for a
/// face of zero area, which is then skipped).
fn ring_face_normals(v: DVec3, ring: &[DVec3]) -> Vec<DVec3> {
    let n = ring.len();
    (0..n)
        .filter_map(|i| (ring[i] - v).cross(ring[(i + 1) % n] - v).try_normalize())
        .collect()
}

/// A vertex's tangent plane made front-facing (HB00 §6 and Loop94 take the plane of the ring's
/// first Fourier sums, which slivers and pinched rings can turn away from a face): `fourier`'s
/// plane (normal `C × S`) is kept when every face `(v, ring[i], ring[i+1])` sees it from the
/// front ([`PLANE_TRIGGER`]); otherwise its normal is tilted to the closest one that every face
/// sees from the front by [`PLANE_MARGIN`], and the harmonic is projected into the new plane
/// — or, when the tilt exceeds [`LARGE_TILT`] or the projection would turn the wrong way,
/// replaced by its closest rotation-and-scale in the new plane. The G¹ conditions at the
/// vertex (eqs. 19, (II_T)) hold for any harmonic, so this changes shape, not continuity.
pub(crate) fn front_facing_plane(
    v: DVec3,
    ring: &[DVec3],
    fourier: RingFourier,
) -> (RingFourier, PlaneMove) {
    let normal = fourier.normal();
    let faces = ring_face_normals(v, ring);
    if faces.is_empty() || normal == DVec3::ZERO || min_cosine(normal, &faces) >= PLANE_TRIGGER {
        return (fourier, PlaneMove::Kept);
    }
    let FrontFacing::Moved {
        normal: tilted,
        angle,
        ..
    } = front_facing_by(normal, &faces, PLANE_MARGIN)
    else {
        return (fourier, PlaneMove::Folded);
    };
    let projected = fourier.in_plane(tilted);
    let (c, s) = (projected.cos_part, projected.sin_part);
    let sine = c.cross(s).dot(tilted) / (c.length() * s.length()).max(f64::MIN_POSITIVE);
    // A NaN sine (a vanishing projection) takes the fit too.
    let conformal = angle > LARGE_TILT || sine.is_nan() || sine < PLANE_MIN_SINE;
    let moved = if conformal {
        fourier.conformal_in(tilted)
    } else {
        projected
    };
    (moved, PlaneMove::Tilted { angle, conformal })
}

/// How far a boundary curve's first control point may swerve sideways at HB00 vertices
/// ([`swerve_cap`]): `b¹ − b⁰` strays from its chord's direction by at most 0.03 of the chord
/// times the sine of the angle of the face it swerves into. HB00's tangents are evenly spaced
/// around the vertex (eq. 12) while a scanned ring's edges are not; a curve that leaves its
/// edge towards a thin face crosses that face's far edge and the macro-patch turns over it.
/// Measured on the two bunny scenes (fold samples on the regularity grid of 12, hb): 81 / 691
/// with a cap of 0.1 chord whatever the face, 23 / 123 with 0.1 times the face's sine, 14 / 9
/// with 0.03, 14 / 6 with 0.02 (examples/fold_sites.rs). hb applies it only at the corners of
/// faces that fold under a cap of 0.1 (`hb::build`): as many folds, a third of the BVH leaves.
pub(crate) const HB_SWERVE: f64 = 0.03;

/// The same bound at Loop94 vertices. Loop's middle point `f²` is fixed (eq. 2), so a shorter
/// tangent raises the curvature at the vertex instead of straightening the curve, and short
/// tangents fold too: fold samples on the two bunny scenes 11 / 40 at 0.1, 11 / 31 at 0.05,
/// 13 / 54 at 0.03, 27 / 280 at 0.01.
pub(crate) const LOOP_SWERVE: f64 = 0.05;

/// ... and reach at most this fraction of the chord along it (the edge's midpoint, where the
/// curves from the two ends meet).
pub(crate) const REACH: f64 = 0.5;

/// The largest β at a vertex `v` for which no boundary curve leaving it swerves: with
/// `step(i)` the first control point's offset `b¹_i − b⁰` per unit β (HB00 eq. 11: `r¹_i / 6`;
/// Loop94: `r¹_i / 4`, both `cos_sum(i) / n` at an interior vertex) and the chord `p_i − v`
/// projected into the tangent plane with unit `normal` (length `ℓ_i`), β keeps the component
/// of `β step(i)` across the chord within `swerve ℓ_i sin α_i` (`α_i` the angle, in the plane,
/// between the chord and the neighbouring chord it swerves towards: the face it swerves into)
/// and along it within [`REACH`]` ℓ_i`. A tangent that points along its chord gives no bound
/// from the first, so on regular and symmetric rings only the reach bounds β (at 1 for a
/// regular planar ring). `closed`: the ring goes all round `v` (else it is a half-ring whose
/// first and last chords are boundary edges, with no face beyond them). `f64::INFINITY` when
/// nothing bounds it. Everything is measured in the
/// tangent plane, so the cap commutes with similarities of the mesh.
pub(crate) fn swerve_cap(
    v: DVec3,
    ring: &[DVec3],
    normal: DVec3,
    swerve: f64,
    closed: bool,
    step: impl Fn(usize) -> DVec3,
) -> f64 {
    let n = ring.len();
    let chords: Vec<DVec3> = ring
        .iter()
        .map(|p| (*p - v).reject_from_normalized(normal))
        .collect();
    let mut cap = f64::INFINITY;
    for (i, chord) in chords.iter().enumerate() {
        let length = chord.length();
        let Some(dir) = chord.try_normalize() else {
            continue;
        };
        let offset = step(i).reject_from_normalized(normal);
        let along = offset.dot(dir);
        let side = offset - along * dir;
        let across = side.length();
        if across > 0.0 {
            // The neighbouring chord the curve swerves towards, and the face between them.
            // On an open fan, the side past a boundary edge has no face: no bound but the chord.
            let towards = if dir.cross(side).dot(normal) > 0.0 {
                (closed || i + 1 < n).then(|| chords[(i + 1) % n])
            } else {
                (closed || i > 0).then(|| chords[(i + n - 1) % n])
            };
            let width = towards.map_or(1.0, |t| dir.cross(t.normalize_or_zero()).length().min(1.0));
            cap = cap.min(swerve * width * length / across);
        }
        if along > 0.0 {
            cap = cap.min(REACH * length / along);
        }
    }
    cap
}

/// The warnings of [`front_facing_plane`] over a whole mesh, for the scheme `scheme` whose
/// default plane at an interior vertex with one-ring `ring` is that of `plane(v, ring)`: one
/// line counting the tilted planes (first vertex, its angle, the largest, how many took the
/// rotation-and-scale fit), one counting the vertices whose faces fold over themselves.
/// Boundary vertices keep their half-ring planes and vertices cut into sectors by sharp edges
/// their sectors' planes ([`Sector`]); neither is counted.
pub(crate) fn plane_warnings(
    mesh: &Mesh,
    scheme: &str,
    plane: impl Fn(DVec3, &[DVec3]) -> RingFourier + Sync,
) -> Vec<String> {
    let positions = mesh.positions();
    let moves: Vec<(u32, PlaneMove)> = (0..mesh.vertex_count() as u32)
        .into_par_iter()
        .filter(|&v| {
            !mesh.is_boundary_vertex(v) && mesh.valence(v) >= 3 && mesh.sharp_valence(v) < 2
        })
        .filter_map(|v| {
            let at = positions[v as usize];
            let ring: Vec<DVec3> = mesh
                .one_ring(v)
                .iter()
                .map(|&p| positions[p as usize])
                .collect();
            match front_facing_plane(at, &ring, plane(at, &ring)).1 {
                PlaneMove::Kept => None,
                other => Some((v, other)),
            }
        })
        .collect();
    let mut warnings = Vec::new();
    let tilted: Vec<(u32, f64, bool)> = moves
        .iter()
        .filter_map(|(v, m)| match m {
            PlaneMove::Tilted { angle, conformal } => Some((*v, *angle, *conformal)),
            _ => None,
        })
        .collect();
    if let Some(&(v, angle, _)) = tilted.first() {
        let largest = tilted.iter().map(|t| t.1).fold(0.0, f64::max);
        let conformal = tilted.iter().filter(|t| t.2).count();
        warnings.push(format!(
            "{scheme}: tilted {} vertex tangent planes that a face around them saw from behind \
             or edge-on (first: vertex {}, by {:.2}°; largest {:.2}°; {conformal} of them with \
             the ring's tangents refitted in the new plane), so that the surface does not fold \
             there",
            tilted.len(),
            mesh.input_vertex(v),
            angle.to_degrees(),
            largest.to_degrees()
        ));
    }
    let folded: Vec<u32> = moves
        .iter()
        .filter(|(_, m)| *m == PlaneMove::Folded)
        .map(|(v, _)| *v)
        .collect();
    if let Some(&v) = folded.first() {
        warnings.push(format!(
            "{scheme}: the faces around {} vertices fold over themselves (first: vertex {}): no \
             tangent plane sees them all from the front, so a surface there folds or parts \
             along sharp edges (the metrics count any fold in `folds`); repair the mesh at that \
             vertex",
            folded.len(),
            mesh.input_vertex(v)
        ));
    }
    warnings
}

/// A face's own frame: the origin at its first corner, where the patches of the face are
/// stored ([`crate::bezier::TriangleBezier::with_origin`]), and its corners relative to it,
/// which the per-vertex data of a [`HalfEdgeTable`] (offsets from their vertex) are added to.
/// Every point of the face's construction is then a sum of terms of the face's size.
#[derive(Clone, Copy, Debug)]
pub(crate) struct FaceFrame {
    /// The position of the face's first corner.
    pub origin: DVec3,
    /// The corners' positions minus `origin` (the first is zero).
    pub corners: [DVec3; 3],
}

impl FaceFrame {
    /// The frame of `face` over `positions`.
    pub(crate) fn of(positions: &[DVec3], face: [u32; 3]) -> FaceFrame {
        let origin = positions[face[0] as usize];
        FaceFrame {
            origin,
            corners: face.map(|v| positions[v as usize] - origin),
        }
    }
}

/// Per-directed-edge data of a mesh, computed vertex by vertex, each vertex in its own frame:
/// the vertex at the origin and its one-ring relative to it, so that points of the data are
/// offsets from their vertex, with the precision of the ring's size wherever the vertex lies
/// (a consumer adds the vertex, relative to a point near it: [`FaceFrame`]).
pub(crate) struct HalfEdgeTable<T> {
    /// `offsets[v] + i` is the edge `v → one_ring(v)[i]`.
    offsets: Vec<usize>,
    data: Vec<T>,
    /// `corner_ring[3f + k]`: position of `faces[f][k+1]` in the one-ring of `faces[f][k]`.
    corner_ring: Vec<u32>,
}

impl<T: Clone + Default + Send + Sync> HalfEdgeTable<T> {
    /// Runs `per_vertex(v, ring positions, ring valences, out)` for every vertex in parallel,
    /// `v` at the origin and the ring relative to it (see [`HalfEdgeTable`]); `out[i]` is the
    /// entry of edge `v → ring[i]`.
    pub(crate) fn build(
        mesh: &Mesh,
        per_vertex: impl Fn(DVec3, &[DVec3], &[usize], &mut [T]) + Sync,
    ) -> HalfEdgeTable<T> {
        let positions = mesh.positions();
        Self::build_indexed(
            mesh,
            |(ring_points, ring_valence): &mut (Vec<DVec3>, Vec<usize>), v, out| {
                let ring = mesh.one_ring(v as u32);
                ring_points.clear();
                ring_points.extend(ring.iter().map(|&p| positions[p as usize] - positions[v]));
                ring_valence.clear();
                ring_valence.extend(ring.iter().map(|&p| mesh.valence(p)));
                per_vertex(DVec3::ZERO, ring_points, ring_valence, out);
            },
        )
    }

    /// As [`HalfEdgeTable::build`] for a mesh that may have boundaries and sharp edges
    /// (`sectors`, [`MeshSectors::new`]): `per_vertex` gets each vertex's [`Fan`] (boundary
    /// flag, angle steps of the vertex and its neighbours, sectors), in the vertex's own frame.
    pub(crate) fn build_open(
        mesh: &Mesh,
        sectors: &MeshSectors,
        per_vertex: impl Fn(&Fan, &mut [T]) + Sync,
    ) -> HalfEdgeTable<T> {
        let positions = mesh.positions();
        let faces = mesh.faces();
        let steps: Vec<f64> = (0..mesh.vertex_count() as u32)
            .map(|v| fan_angle_step(mesh, v))
            .collect();
        Self::build_indexed(mesh, |_: &mut (), v, out| {
            let ring = mesh.one_ring(v as u32);
            let ring_faces = mesh.ring_faces(v as u32);
            let (n, nf) = (ring.len(), ring_faces.len());
            let boundary = mesh.is_boundary_vertex(v as u32);
            // The step at ring[j] in fan face `face` (modulo the faces).
            let far_step = |j: usize, face: usize| {
                let f = ring_faces[face % nf] as usize;
                let k = faces[f].iter().position(|&x| x == ring[j]).unwrap_or(0);
                sectors.corner_step[3 * f + k]
            };
            let ring_points: Vec<DVec3> = ring
                .iter()
                .map(|&p| positions[p as usize] - positions[v])
                .collect();
            let ring_step: Vec<f64> = (0..n)
                .map(|j| far_step(j, if j < nf { j } else { j - 1 }))
                .collect();
            let ring_step_minus: Vec<f64> = (0..n)
                .map(|j| far_step(j, if boundary && j == 0 { 0 } else { j + nf - 1 }))
                .collect();
            let mut ring_sharp = vec![false; n];
            mesh.sharp_cuts(v as u32).for_each(|j| ring_sharp[j] = true);
            let fan = Fan {
                position: DVec3::ZERO,
                boundary,
                step: steps[v],
                ring: &ring_points,
                ring_step: &ring_step,
                ring_step_minus: &ring_step_minus,
                ring_sharp: &ring_sharp,
                sectors: sectors.by_vertex[v].as_deref(),
            };
            per_vertex(&fan, out);
        })
    }

    /// The table's layout, filled by `fill(scratch, v, out)` for every vertex in parallel
    /// (`scratch`: buffers reused within a thread).
    fn build_indexed<S: Default + Send>(
        mesh: &Mesh,
        fill: impl Fn(&mut S, usize, &mut [T]) + Sync,
    ) -> HalfEdgeTable<T> {
        let nv = mesh.vertex_count();
        let mut offsets = Vec::with_capacity(nv + 1);
        let mut total = 0;
        for v in 0..nv {
            offsets.push(total);
            total += mesh.valence(v as u32);
        }
        offsets.push(total);
        let mut data = vec![T::default(); total];
        let mut slices: Vec<&mut [T]> = Vec::with_capacity(nv);
        let mut rest = data.as_mut_slice();
        for v in 0..nv {
            let (head, tail) = rest.split_at_mut(offsets[v + 1] - offsets[v]);
            slices.push(head);
            rest = tail;
        }
        slices
            .into_par_iter()
            .enumerate()
            .for_each_init(S::default, |scratch, (v, out)| fill(scratch, v, out));
        // (v, ring[j], ring[j+1]) is ring_faces(v)[j].
        let faces = mesh.faces();
        let mut corner_ring = vec![0u32; 3 * faces.len()];
        for v in 0..nv as u32 {
            for (j, &f) in mesh.ring_faces(v).iter().enumerate() {
                let k = faces[f as usize].iter().position(|&x| x == v).unwrap_or(0);
                corner_ring[3 * f as usize + k] = j as u32;
            }
        }
        HalfEdgeTable {
            offsets,
            data,
            corner_ring,
        }
    }
}

impl<T> HalfEdgeTable<T> {
    /// The entry of directed edge `h`.
    pub(crate) fn get(&self, h: usize) -> &T {
        &self.data[h]
    }
    /// The entries of the directed edges leaving vertex `v`, in the order of its one-ring.
    pub fn leaving(&self, v: u32) -> &[T] {
        &self.data[self.offsets[v as usize]..self.offsets[v as usize + 1]]
    }

    /// Takes the entries of the edges leaving each vertex of `vertices` from `other`, a table
    /// of the same mesh: per-vertex data computed under another rule at those vertices only.
    pub(crate) fn adopt(&mut self, other: &HalfEdgeTable<T>, vertices: &[u32])
    where
        T: Clone,
    {
        for &v in vertices {
            let range = self.offsets[v as usize]..self.offsets[v as usize + 1];
            self.data[range.clone()].clone_from_slice(&other.data[range]);
        }
    }

    /// Index of the directed edge from `faces[f][k]` to the corner `step` (1 or 2) after it.
    pub(crate) fn directed(&self, face: [u32; 3], f: usize, k: usize, step: usize) -> usize {
        let x = face[k] as usize;
        let n = self.offsets[x + 1] - self.offsets[x];
        // Face (X, Y, Z) is (v, ring[j], ring[j+1]) around X with j = corner_ring.
        let j = self.corner_ring[3 * f + k] as usize;
        self.offsets[x] + (j + step - 1) % n
    }

    /// For each corner `X = a_k` of face `f`: the directed edges `[X→Y, Y→X, X→Z, Z→X]`
    /// (`Y = a_{k+1}`, `Z = a_{k+2}`).
    pub(crate) fn corner_edges(&self, face: [u32; 3], f: usize) -> [[usize; 4]; 3] {
        let forward: [usize; 3] = std::array::from_fn(|k| self.directed(face, f, k, 1));
        let backward: [usize; 3] = std::array::from_fn(|k| self.directed(face, f, k, 2));
        // X→Y reversed is a_{k+1} → a_k = backward[k+1]; X→Z reversed is forward[k+2].
        std::array::from_fn(|k| {
            [
                forward[k],
                backward[(k + 1) % 3],
                backward[k],
                forward[(k + 2) % 3],
            ]
        })
    }
}

/// The angle step `θ` of the fan around vertex `v` on a mesh that may be open: `2π/n` at an
/// interior vertex of valence n (the `θ` of [`phi0`], [`psi0`]); at a boundary vertex of
/// valence n ≥ 3, whose n − 1 faces are taken to span a half plane (a boundary that is smooth
/// through `v`), `π/(n − 1)`, written `2π/(2(n − 1))` so that it is bit for bit the step of an
/// interior vertex of order `2(n − 1)` ([`fan_order`]); at a boundary vertex of valence 2 (a
/// corner: one face, two boundary edges), the angle of that face at `v`.
pub(crate) fn fan_angle_step(mesh: &Mesh, v: u32) -> f64 {
    let n = mesh.valence(v);
    if !mesh.is_boundary_vertex(v) || n >= 3 {
        2.0 * PI / fan_order(mesh, v) as f64
    } else {
        let positions = mesh.positions();
        let ring = mesh.one_ring(v);
        let at = positions[v as usize];
        let (a, b) = (
            positions[ring[0] as usize] - at,
            positions[ring[1] as usize] - at,
        );
        a.angle_between(b)
    }
}

/// The order whose `θ = 2π/order` a vertex's fan uses ([`fan_angle_step`]): the valence at an
/// interior vertex, `2(n − 1)` at a boundary vertex of valence n (a half fan); 0 for a corner
/// (valence 2 on the boundary), whose step is its face angle and no order.
pub(crate) fn fan_order(mesh: &Mesh, v: u32) -> usize {
    let n = mesh.valence(v);
    match (mesh.is_boundary_vertex(v), n) {
        (false, _) => n,
        (true, 2) => 0,
        (true, _) => 2 * (n - 1),
    }
}

/// The fan of one vertex of a mesh that may be open, as [`HalfEdgeTable::build_open`] hands it
/// to the per-vertex rule.
pub(crate) struct Fan<'a> {
    /// Position of the vertex (the origin in [`HalfEdgeTable::build_open`], which hands out
    /// every fan in its vertex's own frame).
    pub position: DVec3,
    /// True on the boundary: `(v, ring[0])` and `(v, ring[n−1])` are boundary edges and
    /// `(v, ring[j], ring[j+1])`, `j < n − 1`, the faces.
    pub boundary: bool,
    /// The vertex's angle step ([`fan_angle_step`]).
    pub step: f64,
    /// Positions of the one-ring (`Mesh::one_ring` order).
    pub ring: &'a [DVec3],
    /// The angle step at neighbour `ring[j]` of the face on the "+" side of edge `v → ring[j]`
    /// (`(v, ring[j], ring[j+1])`; on a boundary edge, of its one face): [`fan_angle_step`] of
    /// the neighbour, or the step of its [`Sector`] holding that face.
    pub ring_step: &'a [f64],
    /// The same for the face on the "−" side (`(v, ring[j−1], ring[j])`); it differs from
    /// `ring_step` only across a sharp edge whose far end is cut into sectors.
    pub ring_step_minus: &'a [f64],
    /// Whether edge `v → ring[j]` is sharp ([`Mesh::sharp_cuts`]).
    pub ring_sharp: &'a [bool],
    /// The vertex's sectors when sharp edges cut its fan into two or more ([`fan_sectors`]).
    pub sectors: Option<&'a [Sector]>,
}

impl Fan<'_> {
    /// `Ψ'(0)` over each edge of `sector` (its edges `0..=faces`), `Ψ` running by `rule` from
    /// `sin θ` of the sector's step here to the far end's `Ψ(0)` on the sector's side of
    /// the edge ([`Fan::ring_step`] inside and at the first edge, [`Fan::ring_step_minus`]
    /// at the last) [HB00 eq. 20, open-fan analogue].
    pub(crate) fn sector_psi_slope(&self, sector: &Sector, rule: PsiRule) -> Vec<f64> {
        let n = self.ring.len();
        let s = sector.step.sin();
        (0..=sector.faces)
            .map(|j| {
                let edge = (sector.first + j) % n;
                let far = if j < sector.faces {
                    self.ring_step[edge]
                } else {
                    self.ring_step_minus[edge]
                };
                rule.slope(s, far.sin())
            })
            .collect()
    }
}

/// Sectors are told apart from a crease tangent of zero length by this fraction of the
/// edge: below it the edge runs (nearly) along the normal of a sector it bounds.
pub(crate) const MIN_CREASE_TANGENT: f64 = 1e-9;

/// Below this sine of the angle between two sectors' normals they have no crease line of
/// their own (the threshold of [`crate::mesh::crease_tangent`]).
const CREASE_LINE_SINE: f64 = 1e-9;

/// Below this `|sin ω|` of a sector of two or more faces spanning `ω` (near a half or a full
/// turn, or none), the harmonic `A cos jθ + B sin jθ` through its two end tangents would need
/// a `B` far longer than either: the vertex's end tangents then all take one length.
const END_SPAN_SINE: f64 = 0.25;

/// Below this `sin θ` of its angle step a sector of two or more faces is refused (its end
/// tangents leave its faces no angle, or a half turn each).
const MIN_STEP_SINE: f64 = 1e-3;

/// One sector of a vertex's fan (the faces between two consecutive sharp or boundary edges,
/// see [`crate::mesh::SharpEdges`]) read as a fan of its own, with the tangents of its edges.
///
/// Its edges are the fan edges `first..=first + faces` (indices modulo the ring length) and
/// its faces the fan faces `first..first + faces`. Both end edges are sharp or boundary
/// edges; their tangents (the derivatives at `v` of the edges' boundary curves) are fixed
/// before any sector is looked at, so the two sectors of a sharp edge share it bit for bit:
/// along the crease direction ([`crate::mesh::crease_tangent`] of the normals of the two
/// sectors; on a boundary edge the edge projected into its sector's plane), each as long as
/// its edge projected on that direction. The edges inside the sector get the tangents
/// `r¹_j = A cos jθ + B sin jθ` (`A` the first end tangent) with the step `θ = ω / faces`, `ω`
/// the angle from the first end tangent to the last one turning round the sector's normal
/// `N` in (0, 2π], and `B` the one that meets the last end tangent `E`,
/// `(E − A cos ω) / sin ω`: they solve the vertex system `r¹_{j+1} + r¹_{j−1} = 2 cos θ r¹_j`
/// [HB00 eq. 5] on the sector's inner edges. Where a sector's `sin ω` is small (a crease
/// through the vertex, ω = π) that `B` does not exist or is far too long, and every end
/// tangent at the vertex takes one length `L`, the mean of the projected edges: then
/// `B = L N × d` (`d` the unit of `A`), or fitted to the inner chords through a crease. A
/// sector of one face has no inner edge; its step is the face's angle at `v` (as at a corner
/// of an open mesh, [`fan_angle_step`]), and its end tangents are its edges' own, so that a
/// face whose corners have every edge sharp has its straight edges as boundary curves.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct Sector {
    /// Fan position of the first edge.
    pub first: usize,
    /// Number of faces (at least 1).
    pub faces: usize,
    /// Unit normal of the sector's tangent plane (orthogonal to the first end tangent).
    pub normal: DVec3,
    /// The angle step `θ`: `Φ(0) = cos θ`, `Ψ(0) = sin θ` on every edge of the sector.
    pub step: f64,
    /// `r¹_j` of the edges `j = 0..=faces`; the first and last are the end tangents.
    pub tangents: Vec<DVec3>,
}

/// The angle from unit `a` to unit `b` turning round the unit `normal`, in (0, 2π].
fn turn_from(a: DVec3, b: DVec3, normal: DVec3) -> f64 {
    let angle = a.cross(b).dot(normal).atan2(a.dot(b));
    if angle > 0.0 { angle } else { angle + 2.0 * PI }
}

/// The sectors of vertex `v` when sharp edges cut its fan into two or more (an interior
/// vertex with two or more sharp edges, a boundary vertex with one or more), with
/// `corner_normals` the normal of every face corner ([`Mesh::corner_normals`]); `None` when
/// the fan is one sector (no sharp edge, or a dart: one sharp edge at an interior vertex),
/// which the closed and half-ring rules build. Fails, naming the edge, when an end edge runs
/// along the normal of a sector it bounds (its tangent would vanish), a sector's faces
/// cancel in its normal, or a sector of two or more faces has an angle step whose sine is
/// below `MIN_STEP_SINE`.
pub(crate) fn fan_sectors(
    mesh: &Mesh,
    v: u32,
    corner_normals: &[[DVec3; 3]],
) -> std::result::Result<Option<Vec<Sector>>, (u32, u32)> {
    let closed = !mesh.is_boundary_vertex(v);
    let mut starts: Vec<usize> = mesh.sharp_cuts(v).collect();
    if starts.is_empty() || (closed && starts.len() == 1) {
        return Ok(None);
    }
    let ring = mesh.one_ring(v);
    let ring_faces = mesh.ring_faces(v);
    let (n, nf) = (ring.len(), ring_faces.len());
    let positions = mesh.positions();
    let at = positions[v as usize];
    let chord = |j: usize| positions[ring[j % n] as usize] - at;
    let face_normal = |j: usize| {
        let f = ring_faces[j % nf] as usize;
        let c = mesh.faces()[f].iter().position(|&x| x == v).unwrap_or(0);
        corner_normals[f][c]
    };
    if !closed {
        starts.insert(0, 0);
    }
    // (first edge, faces) of every sector, in fan order.
    let bounds: Vec<(usize, usize)> = (0..starts.len())
        .map(|s| {
            let end = match starts.get(s + 1) {
                Some(&next) => next,
                None if closed => starts[0] + n,
                None => n - 1,
            };
            (starts[s], end - starts[s])
        })
        .collect();
    // The end tangents' directions and projected lengths, by fan position.
    let mut ends: Vec<Option<(DVec3, f64)>> = vec![None; n];
    let mut end_edges: Vec<usize> = starts.clone();
    if !closed {
        end_edges.push(n - 1);
    }
    for &j in &end_edges {
        let boundary = !closed && (j == 0 || j == n - 1);
        let tangent = if boundary {
            let normal = face_normal(if j == 0 { 0 } else { nf - 1 });
            crate::mesh::crease_tangent(chord(j), normal, normal)
        } else {
            crate::mesh::crease_tangent(chord(j), face_normal(j + nf - 1), face_normal(j))
        };
        let length = tangent.length();
        // NaN lengths fail too.
        if length.is_nan() || length <= MIN_CREASE_TANGENT * chord(j).length() {
            return Err((v, ring[j]));
        }
        ends[j] = Some((tangent / length, length));
    }
    // A crease through an interior vertex (two sharp edges, one crease direction for both)
    // passes through it: its two tangents are opposite, pointing from the second neighbour
    // to the first along the crease (else both could point to one side, a cusp that leaves
    // one sector no angle at all).
    // Sectors whose normals are parallel (a hairpin's, `Mesh::corner_normals`) share their
    // tangent plane and no crease line: each end tangent is its edge projected into it.
    let through = closed
        && end_edges.len() == 2
        && face_normal(end_edges[0])
            .cross(face_normal(end_edges[1]))
            .length()
            > CREASE_LINE_SINE;
    if through {
        let (a, b) = (end_edges[0], end_edges[1]);
        if let (Some((da, la)), Some((_, lb))) = (ends[a], ends[b]) {
            let through = if da.dot(chord(a) - chord(b)) < 0.0 {
                -da
            } else {
                da
            };
            ends[a] = Some((through, la));
            ends[b] = Some((-through, lb));
        }
    }
    let mean = end_edges
        .iter()
        .filter_map(|&j| ends[j])
        .map(|e| e.1)
        .sum::<f64>()
        / end_edges.len() as f64;
    // Every sector's first end direction, normal and span ω (the turn to its last end).
    let frames = bounds
        .iter()
        .map(|&(first, faces)| {
            let d = ends[first].map_or(DVec3::ZERO, |e| e.0);
            let normal = face_normal(first)
                .reject_from_normalized(d)
                .normalize_or_zero();
            if normal == DVec3::ZERO {
                return Err((v, ring[first % n]));
            }
            let last = ends[(first + faces) % n].map_or(DVec3::ZERO, |e| e.0);
            Ok((d, normal, turn_from(d, last, normal)))
        })
        .collect::<std::result::Result<Vec<_>, _>>()?;
    // End tangents keep their edges' own lengths wherever every sector's harmonic can meet
    // both its ends (its span is not near 0, π or 2π); otherwise all take the mean length.
    let own_lengths = !through
        && bounds
            .iter()
            .zip(&frames)
            .all(|(&(_, faces), &(_, _, span))| faces == 1 || span.sin().abs() >= END_SPAN_SINE);
    let end_tangent = |j: usize| {
        ends[j % n].map_or(
            DVec3::ZERO,
            |(d, length)| {
                if own_lengths { length * d } else { mean * d }
            },
        )
    };
    let sectors = bounds
        .into_iter()
        .zip(frames)
        .map(
            |((first, faces), (d, normal, span))| -> std::result::Result<Sector, (u32, u32)> {
                let step = if faces == 1 {
                    chord(first).angle_between(chord(first + 1))
                } else {
                    span / faces as f64
                };
                // A sector whose end tangents leave its faces (nearly) no angle, or a half turn
                // each, has no harmonic (`sin θ` divides the cross-boundary data): a ring folded
                // at a repaired seam, whose crease lines run (nearly) parallel.
                if faces > 1 && step.sin() < MIN_STEP_SINE {
                    return Err((v, ring[first % n]));
                }
                let (start, end) = (end_tangent(first), end_tangent(first + faces));
                // r¹_j = A cos jθ + B sin jθ with A the first end tangent. Through a crease (both
                // end tangents on one line, ω = π) B is free: fitted to the inner chords as on a
                // half ring; with ends of their own lengths it meets the last end; else it is the
                // quarter turn of A round the normal.
                let side = if through {
                    let inner: Vec<DVec3> = (0..=faces).map(|j| at + chord(first + j)).collect();
                    sine_part(at, &inner, step, mean * d)
                } else if own_lengths && faces > 1 {
                    (end - start * span.cos()) / span.sin()
                } else {
                    mean * normal.cross(d)
                };
                let mut tangents: Vec<DVec3> = (0..=faces)
                    .map(|j| {
                        let (sj, cj) = (step * j as f64).sin_cos();
                        cj * start + sj * side
                    })
                    .collect();
                tangents[0] = start;
                tangents[faces] = end;
                Ok(Sector {
                    first,
                    faces,
                    normal,
                    step,
                    tangents,
                })
            },
        )
        .collect::<std::result::Result<Vec<_>, _>>()?;
    Ok(Some(sectors))
}

/// The sectors of every vertex of a mesh ([`fan_sectors`]) and the angle step at every face
/// corner: the step of the corner's sector, or [`fan_angle_step`] of a vertex whose fan is
/// one sector.
pub(crate) struct MeshSectors {
    /// Per vertex, its sectors (`None`: one sector).
    pub by_vertex: Vec<Option<Vec<Sector>>>,
    /// `corner_step[3f + k]`: the angle step of vertex `faces[f][k]` in face `f`.
    pub corner_step: Vec<f64>,
}

impl MeshSectors {
    /// The sectors of `mesh` ([`fan_sectors`]): none without sharp edges. Fails as
    /// [`fan_sectors`] does, with every edge at fault, in vertex order.
    pub(crate) fn new(mesh: &Mesh) -> std::result::Result<MeshSectors, Vec<(u32, u32)>> {
        if mesh.sharp_edges().is_empty() {
            return Ok(MeshSectors::plain(mesh));
        }
        let nv = mesh.vertex_count();
        // Only the corners of vertices cut into several sectors are read, and their normals
        // come from their faces, not from these vertex normals.
        let corner_normals = mesh.corner_normals(&vec![DVec3::ZERO; nv]);
        let by_vertex: Vec<_> = (0..nv as u32)
            .into_par_iter()
            .map(|v| fan_sectors(mesh, v, &corner_normals))
            .collect();
        let faults: Vec<(u32, u32)> = by_vertex.iter().filter_map(|s| s.clone().err()).collect();
        if !faults.is_empty() {
            return Err(faults);
        }
        let by_vertex = by_vertex.into_iter().map(|s| s.unwrap_or(None)).collect();
        Ok(MeshSectors::from_sectors(mesh, by_vertex))
    }

    /// [`MeshSectors::new`] for `scheme`, failing with the error that names the edge at fault.
    pub(crate) fn for_scheme(mesh: &Mesh, scheme: &str) -> crate::error::Result<MeshSectors> {
        MeshSectors::new(mesh).map_err(|faults| crate::error::Error::DegenerateEdge {
            scheme: scheme.into(),
            a: faults[0].0 as usize,
            b: faults[0].1 as usize,
            reason: "the sharp edge runs along the normal of a sector it bounds, the faces of \
                     that sector cancel in its normal, or its end tangents leave its faces no \
                     angle"
                .into(),
            also: faults[1..]
                .iter()
                .map(|&(a, b)| (a as usize, b as usize))
                .collect(),
        })
    }

    /// One sector per vertex (sharp edges ignored), for the schemes that refuse them.
    pub(crate) fn plain(mesh: &Mesh) -> MeshSectors {
        MeshSectors::from_sectors(mesh, vec![None; mesh.vertex_count()])
    }

    /// The corner steps of the sectors `by_vertex`.
    fn from_sectors(mesh: &Mesh, by_vertex: Vec<Option<Vec<Sector>>>) -> MeshSectors {
        let faces = mesh.faces();
        let mut corner_step = vec![0.0; 3 * faces.len()];
        for v in 0..mesh.vertex_count() as u32 {
            let ring_faces = mesh.ring_faces(v);
            let mut set = |j: usize, step: f64| {
                let f = ring_faces[j % ring_faces.len()] as usize;
                let k = faces[f].iter().position(|&x| x == v).unwrap_or(0);
                corner_step[3 * f + k] = step;
            };
            match &by_vertex[v as usize] {
                None => {
                    let step = fan_angle_step(mesh, v);
                    (0..ring_faces.len()).for_each(|j| set(j, step));
                }
                Some(sectors) => {
                    for s in sectors {
                        (s.first..s.first + s.faces).for_each(|j| set(j, s.step));
                    }
                }
            }
        }
        MeshSectors {
            by_vertex,
            corner_step,
        }
    }
}

/// Tangent basis `(A, B)` of a boundary vertex from its half-ring [HB00 eq. 12, half-ring
/// analogue]: the tangents of the edges are `r¹_j ∝ A cos(jθ) + B sin(jθ)`, the general
/// solution of the vertex system `r¹_{j+1} + r¹_{j−1} = 2 cos θ r¹_j` (HB00 eq. 5) on the
/// n − 2 interior edges of an open fan. For n ≥ 3 (`θ = π/(n−1)`) the boundary tangent is
/// fixed by the two boundary neighbours, `A = (p_0 − p_{n−1})/2` (so `r¹_{n−1} = −r¹_0`: the
/// boundary curve is smooth through the vertex), and `B` is the least-squares fit of the
/// chords `p_j − v` of the interior edges by `A cos(jθ) + B sin(jθ)`. For a corner (n = 2, θ the
/// face angle) both chords are met exactly. On a planar regular half-ring `p_j = v + ρ(cos jθ,
/// sin jθ)` the fit is exact, which gives linear precision with β = 1/3 as at interior vertices.
pub(crate) fn half_ring_tangent_basis(v: DVec3, ring: &[DVec3], theta: f64) -> (DVec3, DVec3) {
    let n = ring.len();
    let (s, c) = theta.sin_cos();
    if n == 2 {
        let a = ring[0] - v;
        return (a, (ring[1] - v - c * a) / s);
    }
    let a = 0.5 * (ring[0] - ring[n - 1]);
    (a, sine_part(v, ring, theta, a))
}

/// The least-squares `B` of [`half_ring_tangent_basis`] for a given `A`: the fit of the inner
/// chords `p_j − v` (`0 < j < n − 1`) by `A cos(jθ) + B sin(jθ)`; zero without inner chords.
fn sine_part(v: DVec3, ring: &[DVec3], theta: f64, a: DVec3) -> DVec3 {
    let n = ring.len();
    let (mut num, mut den) = (DVec3::ZERO, 0.0);
    for (j, p) in ring.iter().enumerate().take(n - 1).skip(1) {
        let (sj, cj) = (theta * j as f64).sin_cos();
        num += sj * (*p - v - cj * a);
        den += sj * sj;
    }
    if den > 0.0 { num / den } else { DVec3::ZERO }
}

/// Loop's point of edge `v → p_j` at a boundary vertex with half-ring `ring` [HB00 eqs. 2, 15]:
/// `d_j = (2v + p_{j−1} + 2p_j + p_{j+1})/6` on an interior edge (the same as at an interior
/// vertex, and the same from the edge's other end); on a boundary edge, whose second face is
/// missing, its curve analogue, the chord midpoint `(v + p_j)/2` — what `d_j` is on a regular
/// planar ring, and again symmetric in the two ends.
pub(crate) fn open_loop_point(v: DVec3, ring: &[DVec3], j: usize) -> DVec3 {
    let n = ring.len();
    if j == 0 || j == n - 1 {
        0.5 * (v + ring[j])
    } else {
        (2.0 * v + ring[j - 1] + 2.0 * ring[j] + ring[j + 1]) / 6.0
    }
}

/// Cross-boundary data at a boundary vertex from its tangents and second derivatives
/// [HB00 eqs. 19, 21, (II_T), open-fan analogue]. Inputs per edge j (`r1[j]`, `r2[j]`: first
/// and second derivative of the boundary curve at `v`; `psi_slope[j] = Ψ'(0)` over the whole
/// edge), `c = Φ(0)`, `s = Ψ(0)` and `phi_slope = Φ'(0)`; the tangents must solve the vertex
/// system on the interior edges ([`half_ring_tangent_basis`]). Returns per edge `(V(0), V'(0))`.
///
/// Face j lies between edges j and j + 1: it is the "+" side of edge j and the "−" side of
/// edge j + 1. The twist `t_j` of face j must satisfy (II_T), `t_j + t_{j−1} = 2 R_j` with
/// `R_j = Φ'(0) r¹_j + Φ(0) r²_j`, on every interior edge 1 ≤ j ≤ n − 2. Unlike the closed ring,
/// the chain is open and always solvable, with one free value: the solution with `t_0 = 0`
/// is `σ_j`, and `t_j = σ_j + (−1)^j t_0`. `t_0` is the least-squares choice closest to the
/// smooth estimate `τ_j = ½(R_j + R_{j+1})` (what (II_T) gives when neighbouring twists are
/// equal). Then (19) and (21) are solved for `V(0)` and `V'(0)` on the side of the edge that has
/// a face — the "+" side except on the last boundary edge.
pub(crate) fn open_fan_cross_data(
    r1: &[DVec3],
    r2: &[DVec3],
    psi_slope: &[f64],
    (c, s, phi_slope): (f64, f64, f64),
) -> Vec<(DVec3, DVec3)> {
    let n = r1.len();
    let r: Vec<DVec3> = (0..n).map(|j| phi_slope * r1[j] + c * r2[j]).collect();
    let faces = n - 1;
    let mut sigma = vec![DVec3::ZERO; faces];
    for j in 1..faces {
        sigma[j] = 2.0 * r[j] - sigma[j - 1];
    }
    let mut t0 = DVec3::ZERO;
    for j in 0..faces {
        let sign = if j.is_multiple_of(2) { 1.0 } else { -1.0 };
        t0 += sign * (0.5 * (r[j] + r[j + 1]) - sigma[j]);
    }
    t0 /= faces as f64;
    let twist = |j: usize| sigma[j] + if j.is_multiple_of(2) { t0 } else { -t0 };
    (0..n)
        .map(|j| {
            if j < faces {
                // "+" side, face j: (19) r¹_{j+1} = Φ r¹_j + Ψ V(0); (21) t_j = R_j + Ψ' V(0) + Ψ V'(0).
                let v0 = (r1[j + 1] - c * r1[j]) / s;
                (v0, (twist(j) - r[j] - psi_slope[j] * v0) / s)
            } else {
                // "−" side, face j − 1: r¹_{j−1} = Φ r¹_j − Ψ V(0); t_{j−1} = R_j − Ψ' V(0) − Ψ V'(0).
                let v0 = (c * r1[j] - r1[j - 1]) / s;
                (v0, (r[j] - psi_slope[j] * v0 - twist(j - 1)) / s)
            }
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::generate;

    /// Vertices of high valence beside ordinary ones — bipyramid poles of valence 40 and 64, a
    /// hemisphere's pole of 64 (open), the centre of a cylinder's cap of 48 — for both schemes
    /// whose cross-boundary derivative is `Φ E' ± Ψ V`, their own surfaces (no sharp edges
    /// made). With `Ψ` linear (HB00 eq. 20, Loop94 eq. 4: `psi=linear`) `ΨV` turns over in the
    /// middle of the edges beside the pole and the surface folds over both faces (measured: hb
    /// 1,440 / 5,888 / 2,880 / 2,496 samples, loop94 640 / 1,536 / 736 / 960); with the
    /// harmonic `Ψ(½)` it folds nowhere, interpolates the vertices and is G¹ between faces
    /// (and, for hb, between the pieces of each face).
    #[test]
    fn vertices_of_high_valence_fold_nowhere_with_the_harmonic_psi() {
        use crate::metrics::Metrics;
        use crate::testing::{mesh, params};
        use crate::tolerance::NORMAL_RAD;
        let meshes = [
            ("bipyramid-40", generate::valence_fan(40).expect("valence")),
            ("bipyramid-64", generate::valence_fan(64).expect("valence")),
            ("hemisphere-64", generate::hemisphere(64, 16)),
            ("capped-cylinder-48", generate::capped_cylinder_with(48, 2)),
        ];
        for (name, triangles) in meshes {
            let mesh = mesh(triangles);
            for spec in [crate::schemes::hb::SPEC, crate::schemes::loop94::SPEC] {
                let label = format!("{name} {}", spec.name);
                let measure = |psi: &str| {
                    let surface =
                        (spec.build)(&mesh, &params(&spec, &[("psi", psi)])).expect("builds");
                    Metrics::measure(&surface, &mesh, 0.0)
                };
                let linear = measure("linear").folds;
                assert!(linear > 0, "{label}: Ψ linear no longer folds");
                let m = measure("harmonic");
                assert_eq!(m.folds, 0, "{label}");
                assert_eq!(m.singular_samples, 0, "{label}");
                let g1 = m.g1_between_faces_max_rad.expect("joints between faces");
                assert!(g1 <= NORMAL_RAD, "{label}: G1 {g1} rad");
                let inside = m.g1_inside_faces_max_rad.unwrap_or(0.0);
                assert!(inside <= NORMAL_RAD, "{label}: inside {inside} rad");
                let interpolation = m.interp_max_rel.expect("vertices measured");
                assert!(interpolation <= 1e-12, "{label}: {interpolation}");
                eprintln!("{label}: {linear} fold samples with Ψ linear, 0 harmonic, G1 {g1:.1e}");
            }
        }
    }

    /// The rotated sums equal the direct sums, and the twist preimage satisfies
    /// ½(x_i + x_{i−1}) = cos-sum_i.
    #[test]
    fn fourier_sums_and_twist_preimage() {
        for n in 3..=12 {
            let ring: Vec<DVec3> = (0..n)
                .map(|j| DVec3::new(j as f64 * 0.37, (j * j) as f64 * 0.11, 1.0 / (j + 1) as f64))
                .collect();
            let f = RingFourier::new(&ring);
            let theta = 2.0 * PI / n as f64;
            for i in 0..n {
                let direct_cos: DVec3 = (0..n)
                    .map(|j| (theta * (j as f64 - i as f64)).cos() * ring[j])
                    .sum();
                let direct_sin: DVec3 = (0..n)
                    .map(|j| (theta * (j as f64 - i as f64)).sin() * ring[j])
                    .sum();
                assert!((f.cos_sum(i) - direct_cos).length() < 1e-13);
                assert!((f.sin_sum(i) - direct_sin).length() < 1e-13);
                let avg = 0.5 * (f.twist_preimage_sum(i) + f.twist_preimage_sum((i + n - 1) % n));
                assert!((avg - f.cos_sum(i)).length() < 1e-13, "n={n} i={i}");
            }
        }
    }

    /// Every corner's directed edges start and end at the right vertices.
    #[test]
    fn corner_edges_connect_the_face_corners() {
        let mesh = crate::testing::mesh(generate::mixed_valence());
        let table = HalfEdgeTable::<(u32, u32)>::build(&mesh, |_, _, _, _| {});
        // Rebuild the (from, to) pairs from the layout of the table.
        let mut ends = Vec::new();
        for v in 0..mesh.vertex_count() as u32 {
            ends.extend(mesh.one_ring(v).iter().map(|&w| (v, w)));
        }
        for (fi, face) in mesh.faces().iter().enumerate() {
            for (k, e) in table.corner_edges(*face, fi).iter().enumerate() {
                let (x, y, z) = (face[k], face[(k + 1) % 3], face[(k + 2) % 3]);
                assert_eq!(
                    [ends[e[0]], ends[e[1]], ends[e[2]], ends[e[3]]],
                    [(x, y), (y, x), (x, z), (z, x)]
                );
            }
        }
    }

    /// On the L-block with its 90° edges sharp (corners, a reflex sector at the inner corner
    /// of the L, creases through vertices): every sector's tangents solve the vertex system
    /// `r_{j+1} + r_{j−1} = 2 cos θ r_j` on its inner edges and reach its last end tangent,
    /// all in the plane of its faces; the sectors' steps add up to their faces' angles.
    #[test]
    fn sector_tangents_solve_the_vertex_system_and_meet_both_ends() {
        let (positions, faces) = generate::l_block();
        let options = crate::mesh::LoadOptions {
            crease_angle: Some(40.0),
            ..Default::default()
        };
        let (mesh, _) = Mesh::from_triangles_with(positions, faces, &options).expect("L-block");
        let sectors = MeshSectors::new(&mesh).expect("sectors");
        let (mut reflex, mut count) = (0, 0);
        for (v, fan) in sectors.by_vertex.iter().enumerate() {
            let ring = mesh.one_ring(v as u32);
            let at = mesh.positions()[v];
            for sector in fan.iter().flatten() {
                count += 1;
                let r = &sector.tangents;
                let m = sector.faces;
                let scale = r[0].length();
                let c = sector.step.cos();
                let (s, c_m) = (sector.step * m as f64).sin_cos();
                let recurrence = r[0] * c_m + (r[1] - c * r[0]) / sector.step.sin() * s;
                assert!((recurrence - r[m]).length() <= 1e-14 * scale, "vertex {v}");
                for j in 1..m {
                    let residual = r[j + 1] + r[j - 1] - 2.0 * c * r[j];
                    assert!(residual.length() <= 1e-14 * scale, "vertex {v}, edge {j}");
                }
                let chord = |j: usize| {
                    mesh.positions()[ring[(sector.first + j) % ring.len()] as usize] - at
                };
                let angles: f64 = (0..m).map(|j| chord(j).angle_between(chord(j + 1))).sum();
                assert!(
                    (sector.step * m as f64 - angles).abs() <= 1e-14,
                    "vertex {v}"
                );
                for t in r {
                    assert!(t.dot(sector.normal).abs() <= 1e-15 * scale, "vertex {v}");
                }
                reflex += usize::from(angles > PI + 0.1);
            }
        }
        assert!(count > 0 && reflex > 0, "{count} sectors, {reflex} reflex");
    }

    /// Crease tangents keep their edges' own lengths: on the scanned bunny with every edge
    /// sharp each face is a sector of its own and its end tangents are its edges (so its
    /// boundary curves are its straight edges); at 35° the sectors of several faces meet end
    /// tangents of different lengths and still solve the vertex system on their inner edges.
    #[test]
    fn crease_tangents_are_as_long_as_their_edges() {
        let bunny = crate::testing::scene("bunny");
        let all = crate::testing::creased(&bunny, 0.01);
        let sectors = MeshSectors::new(&all).expect("sectors");
        let mut ends = 0;
        for (v, fan) in sectors.by_vertex.iter().enumerate() {
            let ring = all.one_ring(v as u32);
            let at = all.positions()[v];
            for sector in fan.iter().flatten().filter(|s| s.faces == 1) {
                for j in [0, 1] {
                    let chord =
                        all.positions()[ring[(sector.first + j) % ring.len()] as usize] - at;
                    // The crease direction n₀ × n₁ of faces 0.01° apart carries rounding
                    // of 1e-16 / sin 0.01° in its direction, none to first order in length.
                    let t = sector.tangents[j];
                    let angle = t.cross(chord).length() / (t.length() * chord.length());
                    let length = t.length() / chord.length() - 1.0;
                    assert!(
                        angle <= 1e-9 && length.abs() <= 1e-14,
                        "vertex {v}: {angle} {length}"
                    );
                    ends += 1;
                }
            }
        }
        assert!(ends > 5000, "{ends}");
        let creased = crate::testing::creased(&bunny, 35.0);
        let sectors = MeshSectors::new(&creased).expect("sectors");
        let mut unequal = 0;
        for fan in sectors.by_vertex.iter().flatten() {
            for sector in fan.iter().filter(|s| s.faces > 1) {
                let (r, m) = (&sector.tangents, sector.faces);
                let scale = r[0].length().max(r[m].length());
                let c = sector.step.cos();
                for j in 1..m {
                    let residual = r[j + 1] + r[j - 1] - 2.0 * c * r[j];
                    assert!(residual.length() <= 1e-13 * scale, "edge {j}: {residual}");
                }
                unequal += usize::from((r[0].length() / r[m].length() - 1.0).abs() > 0.05);
            }
        }
        assert!(unequal > 10, "{unequal}");
    }

    /// A regular ring of `n` points on the unit circle in the plane z = `height`.
    fn regular_ring(n: usize, height: f64) -> Vec<DVec3> {
        (0..n)
            .map(|j| {
                let a = 2.0 * PI * j as f64 / n as f64;
                DVec3::new(a.cos(), a.sin(), height)
            })
            .collect()
    }

    /// A plane every face sees from the front is returned as it came, bit for bit.
    #[test]
    fn a_front_facing_plane_is_kept_bit_for_bit() {
        for n in 3..=12 {
            let ring = regular_ring(n, -0.3);
            let fourier = RingFourier::new(&ring);
            let (kept, how) = front_facing_plane(DVec3::ZERO, &ring, fourier);
            assert_eq!(how, PlaneMove::Kept, "n = {n}");
            for i in 0..n {
                assert_eq!(kept.cos_sum(i), fourier.cos_sum(i), "n = {n}");
                assert_eq!(kept.sin_sum(i), fourier.sin_sum(i), "n = {n}");
            }
        }
    }

    /// The apex of a leaning cone: the ring's plane (z = 0) is seen from behind by the faces
    /// next to the side the apex leans over. The plane is tilted until every face sees it from
    /// the front by the margin, and its tangents still turn the right way round it.
    #[test]
    fn a_plane_seen_from_behind_is_tilted_to_the_front_of_every_face() {
        for n in [5, 6, 9] {
            let ring = regular_ring(n, 0.0);
            let v = DVec3::new(1.2, 0.0, 1.0);
            let fourier = RingFourier::new(&ring);
            let faces = ring_face_normals(v, &ring);
            assert!(
                min_cosine(fourier.normal(), &faces) < 0.0,
                "n = {n}: the premise, a face behind the ring's plane"
            );
            let (moved, how) = front_facing_plane(v, &ring, fourier);
            let PlaneMove::Tilted { angle, .. } = how else {
                panic!("n = {n}: {how:?}");
            };
            let normal = moved.normal();
            let worst = min_cosine(normal, &faces);
            assert!(
                worst >= PLANE_MARGIN * (1.0 - 1e-9),
                "n = {n}: smallest cosine {worst}"
            );
            // The tilt is the closest admissible one: one face sits on the margin.
            assert!(worst <= PLANE_MARGIN * (1.0 + 1e-9), "n = {n}: {worst}");
            let turned = normal.angle_between(fourier.normal());
            assert!(
                (turned - angle).abs() <= 1e-12,
                "n = {n}: {turned} vs {angle}"
            );
            for i in 0..n {
                let (a, b) = (moved.cos_sum(i), moved.cos_sum(i + 1));
                assert!(
                    a.dot(normal).abs() <= 1e-12 * a.length(),
                    "n = {n}: in the plane"
                );
                assert!(
                    a.cross(b).dot(normal) > 0.0,
                    "n = {n}, i = {i}: tangents turn"
                );
            }
        }
    }

    /// A ring whose faces fold over themselves (a flattened ring with faces on both sides of
    /// the sheet) has no front-facing plane: it is kept and reported.
    #[test]
    fn a_ring_folded_over_itself_keeps_its_plane_and_says_so() {
        // The ring of (1, 0, 0) on the octahedron flattened onto z = 0: two faces above the
        // sheet, two below, and every direction is behind one of them.
        let ring = [DVec3::Y, 1e-9 * DVec3::Z, -DVec3::Y, -1e-9 * DVec3::Z];
        let fourier = RingFourier::new(&ring);
        let (kept, how) = front_facing_plane(DVec3::X, &ring, fourier);
        assert_eq!(how, PlaneMove::Folded);
        assert_eq!(kept.cos_sum(0), fourier.cos_sum(0));
    }

    /// On a regular planar ring only the reach bounds β: at 1 (the first control point at the
    /// midpoint). Tangents swerving off their chords are capped so that the largest swerve is
    /// exactly `swerve · ℓ · sin α` on one edge and within it on every other.
    #[test]
    fn the_swerve_cap_bounds_the_sideways_and_forward_reach() {
        for n in 3..=12 {
            let ring = regular_ring(n, 0.0);
            let fourier = RingFourier::new(&ring);
            let step = |i: usize| fourier.cos_sum(i) / n as f64;
            let cap = swerve_cap(DVec3::ZERO, &ring, DVec3::Z, HB_SWERVE, true, step);
            assert!((cap - 1.0).abs() <= 1e-12, "n = {n}: {cap}");
        }
        // Uneven angles: tangents evenly spaced, chords not.
        let angles = [0.0f64, 0.3, 1.9, 2.4, 4.0];
        let ring: Vec<DVec3> = angles
            .iter()
            .map(|a| DVec3::new(a.cos(), a.sin(), 0.0))
            .collect();
        let fourier = RingFourier::new(&ring);
        let step = |i: usize| fourier.cos_sum(i) / 5.0;
        let cap = swerve_cap(DVec3::ZERO, &ring, DVec3::Z, HB_SWERVE, true, step);
        assert!(cap < 1.0, "{cap}");
        let mut tightest = 0.0f64;
        for i in 0..5 {
            let (dir, offset) = (ring[i].normalize(), cap * step(i));
            let side = offset - offset.dot(dir) * dir;
            let towards = if dir.cross(side).z > 0.0 {
                ring[(i + 1) % 5]
            } else {
                ring[(i + 4) % 5]
            };
            let width = dir.cross(towards.normalize()).length();
            let used = side.length() / (HB_SWERVE * width);
            assert!(used <= 1.0 + 1e-12, "edge {i}: {used}");
            assert!(offset.dot(dir) <= REACH * (1.0 + 1e-12), "edge {i}");
            tightest = tightest.max(used.max(offset.dot(dir) / REACH));
        }
        assert!((tightest - 1.0).abs() <= 1e-12, "{tightest}");
    }

    /// The one-ring of vertex 186 of `scenes/bunny.obj` at `--crease-angle 40`: its two sharp
    /// edges (faces turning 49° and 41°) bound a one-face sector of 22°, so the crease turns
    /// back at the vertex (a hairpin). Along a crease line through the vertex both sectors
    /// had to turn through a half turn, and the narrow one turned over its face (hb: 53 fold
    /// samples; pn, piper, fang-mann: 1; nielson refused the face). In the plane of the two
    /// edges (`Mesh::corner_normals`) each end tangent runs along its edge, and no scheme
    /// that keeps sharp edges folds there.
    #[test]
    fn a_crease_turning_back_at_a_vertex_keeps_its_tangents_along_its_edges() {
        let positions = [
            [0.564848, 4.449239, 2.996237],
            [-1.445746, 4.220657, 2.82683],
            [-1.467146, 3.332216, 2.890235],
            [-1.193949, 5.011701, 2.421187],
            [-0.622917, 4.153759, 2.970865],
            [-0.818595, 3.2323, 3.006937],
            [-0.452823, 4.818734, 2.690475],
            [-0.622947, 3.605525, 3.185263],
            [-0.172094, 4.083799, 3.141708],
        ]
        .map(DVec3::from_array)
        .to_vec();
        let faces = vec![
            [2, 4, 1],
            [4, 3, 1],
            [5, 4, 2],
            [6, 3, 4],
            [0, 4, 8],
            [0, 6, 4],
            [7, 8, 4],
            [4, 5, 7],
        ];
        let options = crate::mesh::LoadOptions::default().with_crease_angle(Some(40.0));
        let (mesh, _) = Mesh::from_triangles_with(positions, faces, &options).unwrap();
        let centre = 4;
        assert_eq!(mesh.sharp_valence(centre), 2);
        assert!(!mesh.is_boundary_vertex(centre));

        let sectors = MeshSectors::new(&mesh).unwrap();
        let fan = sectors.by_vertex[centre as usize].as_ref().unwrap();
        assert_eq!(fan.len(), 2);
        assert!(fan[0].normal.cross(fan[1].normal).length() <= 1e-15);
        let at = mesh.positions()[centre as usize];
        let ring = mesh.one_ring(centre);
        for sector in fan {
            for (j, t) in [
                (0, sector.tangents[0]),
                (sector.faces, sector.tangents[sector.faces]),
            ] {
                let chord = mesh.positions()[ring[(sector.first + j) % ring.len()] as usize] - at;
                let angle = chord.angle_between(t);
                assert!(
                    angle <= 1e-12,
                    "end tangent {j} off its edge by {angle} rad"
                );
            }
        }

        for scheme in ["hb", "loop94", "pn", "piper", "nielson", "fang-mann"] {
            let surface = crate::schemes::build(scheme, &mesh, &[])
                .unwrap_or_else(|e| panic!("{scheme}: {e}"));
            let m = crate::metrics::Metrics::measure(&surface, &mesh, 0.0);
            assert_eq!(m.folds, 0, "{scheme}");
            assert!(m.sharp_joints >= 2, "{scheme}");
            if scheme != "pn" {
                let g1 = m.g1_max_rad.unwrap();
                assert!(g1 <= 1e-9, "{scheme}: G1 {g1} rad");
            }
        }
    }
}
