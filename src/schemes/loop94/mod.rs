//! Loop's 1994 sextic G¹ spline, as HB00 §3 summarises it [HB00 eqs. 1–4]: one sextic Bézier
//! triangle per mesh face, quartic boundary curves with `f⁰, f¹, f²` (eq. 2), quadratic `Φ` and
//! constant `ν = μ = ½` (eq. 1), cross-boundary tangents `Φ E' ± Ψ V` with linear `Ψ` and cubic
//! `V` (eqs. 3, 4), and the middle point chosen for quintic precision.
//!
//! Passes, each parallel: per vertex ([`vertex`]) the data that vertex determines alone; per
//! face ([`patch`]) the three edges from both ends and the sextic. Every patch has degree 6:
//! the lower degrees Loop obtains for faces whose three vertices have equal order (quintic; quartic
//! for order 6) are not used, so that all patches share one form.
//!
//! Defaults: α = 1 interpolates the vertices (the case of HB00 Fig. 2 top, which undulates);
//! β = 1/2 gives linear precision on regular meshes (`r¹_i = 2β e_i` for a planar hexagonal ring)
//! and a regular parametrisation (measured min |Su×Sv| / mean: 0.76 on the icosahedron, against
//! 0.04 with Fig. 14's β = 0.1, whose short tangents crease the surface along the edges).

pub(crate) mod patch;
pub(crate) mod vertex;

use rayon::prelude::*;

use crate::error::Result;
use crate::mesh::Mesh;
use crate::schemes::vertex_rings::HalfEdgeTable;
use crate::schemes::{ParamSpec, Params, SchemeSpec};
use crate::surface::{Patch, PatchGeometry, Surface};
use patch::{edge_curves, sextic};
use vertex::{LoopHalfEdge, LoopShape, half_edges};

/// Registry entry.
pub const SPEC: SchemeSpec = SchemeSpec {
    name: "loop94",
    summary: "Loop 1994: sextic G1 spline, one Bezier triangle per face (HB00 sec. 3)",
    params: &[
        ParamSpec {
            name: "alpha",
            default: "1",
            help: "α of eq. 2: 1 interpolates the vertices, < 1 approximates (less undulation)",
        },
        ParamSpec {
            name: "beta",
            default: "0.5",
            help: "β of eq. 2 (> 0): tangent magnitude",
        },
    ],
    needs_closed_mesh: true,
    build,
};

fn shape(params: &Params) -> Result<LoopShape> {
    let alpha = params.number("alpha")?;
    let beta = params.positive_number("beta", "tangents vanish or flip")?;
    Ok(LoopShape { alpha, beta })
}

fn table(mesh: &Mesh, shape: &LoopShape) -> HalfEdgeTable<LoopHalfEdge> {
    HalfEdgeTable::build(mesh, |p, ring, valences, out| {
        half_edges(p, ring, valences, shape, out)
    })
}

/// The three edges `a_k → a_{k+1}` of face `f` as (boundary curve, cross derivative).
fn face_edges(
    table: &HalfEdgeTable<LoopHalfEdge>,
    face: [u32; 3],
    f: usize,
) -> [(crate::bezier::CurveBezier, crate::bezier::CurveBezier); 3] {
    table
        .corner_edges(face, f)
        .map(|[xy, yx, _, _]| edge_curves(table.get(xy), table.get(yx)))
}

fn build(mesh: &Mesh, params: &Params) -> Result<Surface> {
    let shape = shape(params)?;
    let table = table(mesh, &shape);
    let whole_face = [glam::DVec3::X, glam::DVec3::Y, glam::DVec3::Z];
    let patches = mesh
        .faces()
        .par_iter()
        .enumerate()
        .map(|(f, face)| Patch {
            face: f as u32,
            piece: 0,
            domain: whole_face,
            geometry: PatchGeometry::Bezier(sextic(&face_edges(&table, *face, f))),
        })
        .collect();
    Ok(params.surface(SPEC.name, patches))
}

/// Largest disagreement of the twist points computed from either edge, and of Loop's middle
/// boundary point `f²` computed from either end, over all faces (for tests and diagnostics).
pub fn max_consistency_defect(mesh: &Mesh, params: &Params) -> Result<f64> {
    let table = table(mesh, &shape(params)?);
    Ok(mesh
        .faces()
        .iter()
        .enumerate()
        .map(|(f, face)| {
            let twist = patch::twist_mismatch(&face_edges(&table, *face, f));
            let f2 = table
                .corner_edges(*face, f)
                .iter()
                .map(|[xy, yx, _, _]| (table.get(*xy).f[2] - table.get(*yx).f[2]).length())
                .fold(0.0, f64::max);
            twist.max(f2)
        })
        .fold(0.0, f64::max))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::metrics::Metrics;
    use crate::testing::{Rng, closed_test_meshes, params};

    fn check(name: &str, mesh: &Mesh, p: &Params, interpolates: bool) {
        let surface = build(mesh, p).expect("loop94 builds on a closed mesh");
        assert_eq!(surface.patches.len(), mesh.face_count());
        assert!(surface.patches.iter().all(|p| p.degree() == Some(6)));
        let m = Metrics::measure(&surface, mesh, 0.0);
        let label = format!("{name} {:?}", p.values());
        assert_eq!(m.joints, mesh.edges().len(), "{label}: one joint per edge");
        let (gap, g1) = (m.g0_max_rel.unwrap(), m.g1_between_faces_max_rad.unwrap());
        eprintln!("{label}: gap {gap:.1e}, normal jump {g1:.1e} rad");
        assert!(gap <= 1e-12, "G0 gap {gap} on {label}");
        assert!(
            g1 <= crate::tolerance::NORMAL_RAD,
            "normal jump {g1} rad on {label}"
        );
        assert_eq!(m.singular_samples, 0, "{label}");
        if interpolates {
            let e = m.interp_max_rel.unwrap();
            assert!(e <= 1e-12, "interpolation error {e} on {label}");
        }
        let defect = max_consistency_defect(mesh, p).unwrap() / mesh.bounds().diagonal();
        assert!(defect <= 1e-12, "twist/f² defect {defect} on {label}");
    }

    #[test]
    fn g1_and_interpolation_on_closed_meshes() {
        for (name, mesh) in closed_test_meshes() {
            check(&name, &mesh, &params(&SPEC, &[]), true);
            check(&name, &mesh, &params(&SPEC, &[("beta", "0.5")]), true);
        }
    }

    #[test]
    fn g1_with_random_parameters() {
        let mut rng = Rng::new(94);
        for (name, mesh) in closed_test_meshes() {
            let alpha = format!("{}", 0.3 + 0.7 * rng.next_f64());
            let beta = format!("{}", 0.05 + 0.6 * rng.next_f64());
            let p = params(&SPEC, &[("alpha", &alpha), ("beta", &beta)]);
            check(&name, &mesh, &p, false);
        }
    }

    #[test]
    fn non_positive_beta_is_rejected() {
        let err = shape(&params(&SPEC, &[("beta", "0")])).unwrap_err();
        assert!(err.to_string().contains("beta"), "{err}");
    }
}
