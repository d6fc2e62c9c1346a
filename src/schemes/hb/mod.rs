//! Hahmann–Bonneau 2000, *Triangular G¹ interpolation by 4-splitting domain triangles* \[HB00\]:
//! a piecewise quintic G¹ surface with one macro-patch of four Bézier triangles per mesh face.
//!
//! The construction runs in three local passes, each parallel over its elements:
//! 1. per vertex ([`vertex`]): boundary-curve control points `b0, b1, b2` of every edge leaving
//!    the vertex (eqs. 9–15), the twists (eq. 17) and `v⁰, v¹` of the cross-boundary function
//!    (eqs. 19–23) — from the one-ring alone;
//! 2. per edge: the curve midpoint `b3 = (b2 + b̃2)/2` (eq. 16), `v²`, chosen so that `V` is C¹
//!    at the midpoint (HB00 §7, the choice of §9), and `Ψ(½)`: by default the harmonic mean of
//!    the ends' `Ψ(0)`, not eq. 20's arithmetic mean, so that `V` need not bend without bound
//!    beside a vertex of high valence (`psi`, [`PsiRule`]);
//! 3. per face ([`mod@macro_patch`]): the four quintic nets (eqs. 24–33 and the fill of Fig. 13).
//!
//! Open meshes follow [`boundary`]; sharp edges (`--crease-angle`) [`crease`]: each sector of
//! a vertex is built as an open fan, the curve of a sharp edge is shared by its two faces and
//! each of them has its own `V` ([`vertex::HalfEdgeData::minus`]), so the surface is G⁰ across
//! sharp edges and G¹ elsewhere.
//!
//! `V` changes sign with the edge direction: seen from the other end `w` of an edge `v → w`,
//! `Ψ̃(1−u) = Ψ(u)` and `Φ̃(1−u) = 1 − Φ(u)`, so (eq. 18) `Ṽ(1−u) = −V(u)`. Hence, with `v¹` and
//! `ṽ¹` computed at either end, C¹ continuity of `V` at `u = ½` gives `v² = (v¹ − ṽ¹)/2 = −ṽ²`.
//! (HB00 §9 writes `v² = ½v¹ + ½v¹_k` in a per-end sign convention.)
//!
//! Shape parameters: α = 1 interpolates the vertices. HB00 §6 leaves β, γ1, γ2 free per vertex;
//! by default (`auto`) [`vertex::adaptive_shape`] chooses them at each vertex from its one-ring,
//! so that the boundary curves start like the circular arcs with the normal curvature the mesh
//! implies. The former global default β = 1/3, (γ0, γ1, γ2) = (−1, 2, 0) has linear precision on
//! regular meshes and no network undulation on the icosahedron, but γ2 = 0 puts `b2` on the
//! tangent line and the twists in the tangent plane, so every mesh vertex is a flat point
//! (|H| = 0; measured on the unit icosphere of 80 faces: normal error 0.063 rad, distance
//! 1.1e-2, against 0.0106 rad and 1.8e-3 with the per-vertex default, whose |H| at the vertices
//! is 1.000 — results/defaults.md). With γ auto, each edge's `b2` also gets a normal height
//! that starts its boundary curve with the normal curvature of one second fundamental form per
//! vertex, fitted to those the mesh implies along the edges (eq. 15 alone gives one curvature
//! for all directions; `vertex::edge_heights`). The tangent plane at a vertex is by default
//! normal to Max's vertex normal (`plane=max`, [`vertex::PlaneRule`]), exact for one-rings on a
//! sphere; `plane=fourier` is eq. 12's plane of the ring's first Fourier sums, exact on
//! symmetric rings and affine invariant. On sphere-320 / torus-576 these bring the distance from
//! 3.7e-3 / 3.1e-3 to 9.1e-4 / 8.2e-4 (piper 1.0e-3 / 9.1e-4). Numbers for β or the γ set them
//! at every vertex (Fig. 14: β = 0.1, γ = (−3.7, 4.6, 0.1), `plane=fourier`). The six free points default to the thin-plate
//! minimiser (`free=energy`, as in the paper's colour plate); `free=zero-twist` is the cheap
//! alternative.

pub(crate) mod boundary;
pub(crate) mod crease;
pub(crate) mod energy;
pub(crate) mod macro_patch;
pub(crate) mod vertex;

use rayon::prelude::*;

use crate::schemes::vertex_rings::{FaceFrame, HB_SWERVE, HalfEdgeTable, MeshSectors, PsiRule};

use glam::DVec3;

use crate::bezier::TriangleBezier;
use crate::error::{Error, Result};
use crate::mesh::Mesh;
use crate::schemes::{ParamSpec, Params, SchemeSpec};
use crate::surface::{Patch, PatchGeometry, Surface};
use macro_patch::{FreeRule, HalfEdgeCurve, macro_patch, piece_domains};
use vertex::{HalfEdgeData, PlaneRule, ShapeRule};

/// Registry entry.
pub(crate) const SPEC: SchemeSpec = SchemeSpec {
    name: "hb",
    summary: "Hahmann-Bonneau 2000: quintic G1 interpolant, 4 Bezier triangles per face (HB00)",
    params: &[
        ParamSpec {
            name: "alpha",
            default: "1",
            help: "α of eq. 9: 1 interpolates the vertices, < 1 pulls towards the ring centroid",
        },
        ParamSpec {
            name: "beta",
            default: "auto",
            help: "β of eq. 12 (> 0): tangent length, the same at every vertex; auto = per vertex, fitted to circular arcs (1/3 on planar regular rings)",
        },
        ParamSpec {
            name: "gamma0",
            default: "auto",
            help: "γ0 of eq. 15 (weight of b0 in b2); auto = per vertex, from the curvature the one-ring implies, and each edge's b2 raised to the normal curvature of the second fundamental form fitted to the ring",
        },
        ParamSpec {
            name: "gamma1",
            default: "auto",
            help: "γ1 of eq. 15 (weight of b1 in b2); auto = per vertex",
        },
        ParamSpec {
            name: "gamma2",
            default: "auto",
            help: "γ2 of eq. 15 (weight of Loop's point d); auto = 1 − γ0 − γ1, or per vertex if γ0, γ1 are auto too",
        },
        ParamSpec {
            name: "plane",
            default: "max",
            help: "tangent plane at a vertex: max (normal by Max's weights, exact for rings on a sphere) | fourier (eq. 12, plane of the ring's first Fourier sums)",
        },
        ParamSpec {
            name: "free",
            default: "energy",
            help: "six free points per face: energy (thin-plate minimiser) | zero-twist",
        },
        ParamSpec {
            name: "psi",
            default: "harmonic",
            help: "Ψ along an edge: harmonic (Ψ(½) the harmonic mean of its ends: no fold at vertices of high valence) | linear (eq. 20)",
        },
    ],
    needs_closed_mesh: false,
    bytes_per_face: 3800.0,
    sharp_edges: crate::schemes::SharpEdgeSupport::Builds,
    build,
};

/// Reads and checks the shape parameters: `auto` (the default of β, γ0, γ1) leaves the value
/// to [`vertex::adaptive_shape`] at each vertex; numbers set it for every vertex.
fn shape_params(params: &Params) -> Result<(ShapeRule, FreeRule)> {
    let alpha = params.number("alpha")?;
    let beta = if params.text("beta") == "auto" {
        None
    } else {
        Some(params.positive_number("beta", "tangents vanish or flip")?)
    };
    let number = |name: &str| -> Result<Option<f64>> {
        if params.text(name) == "auto" {
            Ok(None)
        } else {
            params.number(name).map(Some)
        }
    };
    let gamma = match (number("gamma0")?, number("gamma1")?, number("gamma2")?) {
        (None, None, None) => None,
        (Some(g0), Some(g1), None) => Some([g0, g1, 1.0 - g0 - g1]),
        (Some(g0), None, Some(g2)) => Some([g0, 1.0 - g0 - g2, g2]),
        (None, Some(g1), Some(g2)) => Some([1.0 - g1 - g2, g1, g2]),
        (Some(g0), Some(g1), Some(g2)) => {
            if (g0 + g1 + g2 - 1.0).abs() > 1e-9 {
                return Err(Error::BadParam {
                    name: "gamma2".into(),
                    reason: format!(
                        "γ0 + γ1 + γ2 must be 1 (eq. 15), got {g0} + {g1} + {g2} = {}",
                        g0 + g1 + g2
                    ),
                });
            }
            Some([g0, g1, g2])
        }
        _ => {
            return Err(Error::BadParam {
                name: "gamma0".into(),
                reason: "set two of gamma0, gamma1, gamma2 (eq. 15: they sum to 1), or none for \
                         the per-vertex choice"
                    .into(),
            });
        }
    };
    let free = match params.choice("free", &["energy", "zero-twist"])? {
        "zero-twist" => FreeRule::ZeroTwist,
        _ => FreeRule::Energy,
    };
    let plane = match params.choice("plane", &["max", "fourier"])? {
        "fourier" => PlaneRule::Fourier,
        _ => PlaneRule::Max,
    };
    let psi = match params.choice("psi", &["harmonic", "linear"])? {
        "linear" => PsiRule::Linear,
        _ => PsiRule::Harmonic,
    };
    Ok((
        ShapeRule {
            alpha,
            beta,
            gamma,
            plane,
            swerve: HB_SWERVE,
            psi,
        },
        free,
    ))
}

/// Pass 1 for the whole mesh, parallel over vertices; on an open mesh the boundary vertices
/// follow [`boundary`], and the vertices that sharp edges cut into sectors [`crease`].
fn half_edge_table(mesh: &Mesh, rule: &ShapeRule) -> Result<HalfEdgeTable<HalfEdgeData>> {
    if mesh.is_closed() && mesh.sharp_edges().is_empty() {
        return Ok(HalfEdgeTable::build(mesh, |v, ring, valences, out| {
            let steps: Vec<f64> = valences
                .iter()
                .map(|&n| 2.0 * std::f64::consts::PI / n as f64)
                .collect();
            rule.half_edges(v, ring, &steps, &steps, out)
        }));
    }
    let sectors = MeshSectors::for_scheme(mesh, SPEC.name)?;
    Ok(boundary::open_half_edge_table(mesh, &sectors, rule))
}

/// Pass 2 for the edge `X → Y` with its reverse `Y → X`, for the face on the "+" side of
/// `X → Y` (`minus = false`, the "−" side of `Y → X`) or on its "−" side: the midpoint
/// (eq. 16), `v²` (C¹ `V`, see the module doc) and `Ψ(½)` (eq. 29, by `psi`) complete the
/// pass-1 data of `X`. `[x, y]` are `X` and `Y` in the face's frame ([`FaceFrame`]): the
/// curve's points (offsets from their vertex in the table) are placed in that frame.
fn curve(
    here: &HalfEdgeData,
    there: &HalfEdgeData,
    minus: bool,
    psi: PsiRule,
    [x, y]: [DVec3; 2],
) -> HalfEdgeCurve {
    let (near, far) = (here.side(minus), there.side(!minus));
    HalfEdgeCurve {
        b: [
            x + here.b[0],
            x + here.b[1],
            x + here.b[2],
            0.5 * ((x + here.b[2]) + (y + there.b[2])),
        ],
        v: [near.v0, near.v1, 0.5 * (near.v1 - far.v1)],
        phi0: near.phi0,
        psi: [near.psi0, psi.middle(near.psi0, far.psi0)],
    }
}

/// The two half-edge curves leaving each corner of face `f`: `(X→Y, X→Z)` for `X = a_k`
/// (the face lies on the "+" side of `X → Y` and on the "−" side of `X → Z`), `Ψ` by `psi`,
/// in the face's `frame`.
fn face_corner_curves(
    table: &HalfEdgeTable<HalfEdgeData>,
    face: [u32; 3],
    f: usize,
    psi: PsiRule,
    frame: &FaceFrame,
) -> [(HalfEdgeCurve, HalfEdgeCurve); 3] {
    let corner = |k: usize| frame.corners[k % 3];
    let mut k = 0;
    table.corner_edges(face, f).map(|[xy, yx, xz, zx]| {
        let (x, y, z) = (corner(k), corner(k + 1), corner(k + 2));
        k += 1;
        (
            curve(table.get(xy), table.get(yx), false, psi, [x, y]),
            curve(table.get(xz), table.get(zx), true, psi, [x, z]),
        )
    })
}

/// Builds the HB00 surface: 4 quintic patches per face, pieces 0–2 at the face corners, 3 in the
/// middle.
///
/// With β chosen per vertex, the boundary curves may first swerve off their edges by
/// [`LOOSE_SWERVE`]; the corners of every face whose macro-patch then folds over it
/// ([`Patch::fold_samples`]) are rebuilt with the tighter [`HB_SWERVE`], until no face with a
/// loose corner folds. Tight caps everywhere would shorten the tangents at every vertex of a
/// scan, not only where a fold asks for it, and curve its patches more than their faces need
/// (measured on a 3.7k-face scanned bunny: 97k BVH leaves at 0.03 everywhere, 35k with this
/// rule, both with 0 folds).
fn build(mesh: &Mesh, params: &Params) -> Result<Surface> {
    let (shape, free) = shape_params(params)?;
    let (patches, _) = macro_patches(mesh, &shape, free, LOOSE_SWERVE)?;
    let mut surface = params.surface(SPEC.name, patches);
    surface.warnings = crate::schemes::vertex_rings::plane_warnings(mesh, SPEC.name, |v, ring| {
        shape.plane.ring_fourier(v, ring)
    });
    Ok(surface)
}

/// The patches of [`build`], four per face, with the swerve cap `loose` where no face folds
/// under it, and which vertices took the tight cap [`HB_SWERVE`] instead.
fn macro_patches(
    mesh: &Mesh,
    shape: &ShapeRule,
    free: FreeRule,
    loose: f64,
) -> Result<(Vec<Patch>, Vec<bool>)> {
    let adaptive = shape.beta.is_none();
    let first = ShapeRule {
        swerve: if adaptive { loose } else { HB_SWERVE },
        ..*shape
    };
    let mut table = half_edge_table(mesh, &first)?;
    let domains = piece_domains();
    // Filled in place, four patches per face, so that the construction's peak memory is the
    // surface itself (collecting per-face arrays first and flattening them doubled it).
    let empty = Patch {
        face: 0,
        piece: 0,
        domain: domains[0],
        geometry: PatchGeometry::Bezier(TriangleBezier::new(0, vec![DVec3::ZERO])),
    };
    let mut patches = vec![empty; 4 * mesh.face_count()];
    // Builds the macro-patches of the faces `selected` (all when `None`).
    let fill =
        |patches: &mut [Patch], table: &HalfEdgeTable<HalfEdgeData>, selected: Option<&[bool]>| {
            patches
                .par_chunks_mut(4)
                .enumerate()
                .filter(|(f, _)| selected.is_none_or(|s| s[*f]))
                .for_each(|(f, out)| {
                    let face = mesh.faces()[f];
                    let frame = FaceFrame::of(mesh.positions(), face);
                    let nets =
                        macro_patch(&face_corner_curves(table, face, f, shape.psi, &frame), free);
                    for (piece, slot) in out.iter_mut().enumerate() {
                        *slot = Patch {
                            face: f as u32,
                            piece: piece as u8,
                            domain: domains[piece],
                            geometry: PatchGeometry::Bezier(TriangleBezier::with_origin(
                                5,
                                frame.origin,
                                nets[piece].to_vec(),
                            )),
                        };
                    }
                });
        };
    fill(&mut patches, &table, None);
    let mut tight = vec![false; mesh.vertex_count()];
    if adaptive {
        let mut tight_table = None;
        let mut changed: Option<Vec<bool>> = None;
        loop {
            let newly: Vec<u32> = folding_faces(mesh, &patches, changed.as_deref())
                .into_iter()
                .flat_map(|f| mesh.faces()[f])
                .filter(|&v| !std::mem::replace(&mut tight[v as usize], true))
                .collect();
            if newly.is_empty() {
                break;
            }
            let tight_table = match &mut tight_table {
                Some(table) => table,
                empty => empty.insert(half_edge_table(
                    mesh,
                    &ShapeRule {
                        swerve: HB_SWERVE,
                        ..*shape
                    },
                )?),
            };
            table.adopt(tight_table, &newly);
            // The faces around a re-capped vertex change; no others do.
            let mut around = vec![false; mesh.face_count()];
            for &v in &newly {
                for &f in mesh.ring_faces(v) {
                    around[f as usize] = true;
                }
            }
            fill(&mut patches, &table, Some(&around));
            changed = Some(around);
        }
    }
    Ok((patches, tight))
}

/// The swerve cap of a per-vertex β at vertices whose faces do not fold under it (see
/// [`build`]): long tangents, nearly flat patches.
const LOOSE_SWERVE: f64 = 0.1;

/// The faces among `selected` (all when `None`) with a patch that folds over them
/// ([`Patch::fold_samples`]), in order.
fn folding_faces(mesh: &Mesh, patches: &[Patch], selected: Option<&[bool]>) -> Vec<usize> {
    let positions = mesh.positions();
    (0..mesh.face_count())
        .into_par_iter()
        .filter(|&f| selected.is_none_or(|s| s[f]))
        .filter(|&f| {
            let p = mesh.faces()[f].map(|v| positions[v as usize]);
            let normal = (p[1] - p[0]).cross(p[2] - p[0]);
            patches[4 * f..4 * f + 4]
                .iter()
                .any(|patch| patch.fold_samples(normal) > 0)
        })
        .collect()
}

#[cfg(test)]
mod tests;

/// Test-only items: used by the unit tests of this and other modules, compiled only for them.
#[cfg(test)]
pub(crate) mod test_support {
    use super::*;

    /// Largest disagreement between the two ways of computing the points two edges share at a
    /// corner piece (twist compatibility, eq. 19), over all face corners; for tests and diagnostics.
    pub(crate) fn max_corner_mismatch(mesh: &Mesh, params: &Params) -> Result<f64> {
        let (shape, _) = shape_params(params)?;
        let table = half_edge_table(mesh, &shape)?;
        Ok(mesh
            .faces()
            .iter()
            .enumerate()
            .flat_map(|(f, face)| {
                let frame = FaceFrame::of(mesh.positions(), *face);
                face_corner_curves(&table, *face, f, shape.psi, &frame)
            })
            .map(|(to_y, to_z)| macro_patch::test_support::corner_mismatch(&to_y, &to_z))
            .fold(0.0, f64::max))
    }
}
