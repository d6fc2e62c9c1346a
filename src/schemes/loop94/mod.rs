//! Loop's 1994 sextic G¹ spline, as HB00 §3 summarises it [HB00 eqs. 1–4]: one sextic Bézier
//! triangle per mesh face, quartic boundary curves with `f⁰, f¹, f²` (eq. 2), quadratic `Φ` and
//! constant `ν = μ = ½` (eq. 1), cross-boundary tangents `Φ E' ± Ψ V` with cubic `V` (eqs. 3,
//! 4), and the middle point chosen for quintic precision. `Ψ` is by default quadratic, its
//! middle coefficient the harmonic mean of its ends, not eq. 4's linear `Ψ`, whose `V` has to
//! bend without bound beside a vertex of high valence and folds there (`psi`,
//! [`PsiRule`]; `ΨV` is then quintic, the degree eq. 3 allows).
//!
//! Passes, each parallel: per vertex ([`vertex`]) the data that vertex determines alone; per
//! face ([`patch`]) the three edges from both ends and the sextic. Every patch has degree 6:
//! the lower degrees Loop obtains for faces whose three vertices have equal order (quintic; quartic
//! for order 6) are not used, so that all patches share one form.
//!
//! Defaults: α = 1 interpolates the vertices (the case of HB00 Fig. 2 top, which undulates);
//! β = 0.8, chosen by measured accuracy on the analytic meshes (`cargo run --release --example
//! accuracy -- loop94 beta=B`, results/defaults.md). The boundary curve's second control point
//! is Loop's `f² = d` whatever β (eq. 2), so β trades the curvature at the vertices against the
//! parametrisation: on a regular ring of a sphere the normal curvature of the boundary curves at
//! the vertex is about `κ / β²` (`12 (f² − 2f¹ + f⁰)·N / |4(f¹ − f⁰)|²`); measured `|H|` at the vertices of the unit icosphere (80 faces) is
//! 4.4 with β = 1/2 (the old default, linear precision), 1.7 with β = 0.8, 1.08 with β = 1. On
//! sphere-320 / ellipsoid-320 / torus-576, β = 0.8 gives distances 9.5e-3 / 1.2e-2 / 1.0e-2
//! (β = 1/2: 1.3e-2 / 1.7e-2 / 1.5e-2) and normal errors 0.076 / 0.114 / 0.154 rad (β = 1/2:
//! 0.108 / 0.163 / 0.205) with the smallest mean-curvature error of the values measured
//! (0.25–1.0); larger β shortens the distance further but lowers the regularity on the
//! mixed-valence scene (min |Su×Sv| / mean: 0.43 at β = 1/2, 0.12 at 0.8, 0.02 at 1) and raises
//! the curvature error. Fig. 14's β = 0.1 has short tangents that crease the surface along the
//! edges (regularity 0.04 on the icosahedron).

pub(crate) mod boundary;
pub(crate) mod crease;
pub(crate) mod patch;
pub(crate) mod vertex;

use rayon::prelude::*;

use crate::error::Result;
use crate::mesh::Mesh;
use crate::schemes::vertex_rings::{FaceFrame, HalfEdgeTable, LOOP_SWERVE, MeshSectors, PsiRule};
use crate::schemes::{ParamSpec, Params, SchemeSpec};
use crate::surface::{Patch, PatchGeometry, Surface};
use patch::{edge_curves, sextic};
use vertex::{LoopHalfEdge, LoopShape, RingSteps, half_edges};

/// Registry entry.
pub(crate) const SPEC: SchemeSpec = SchemeSpec {
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
            default: "0.8",
            help: "β of eq. 2 (> 0): tangent magnitude, an upper limit: capped per vertex so that no boundary curve swerves off its edge (docs/folds.md; default chosen by accuracy on analytic meshes; 0.5 gives linear precision)",
        },
        ParamSpec {
            name: "psi",
            default: "harmonic",
            help: "Ψ along an edge: harmonic (quadratic, middle coefficient the harmonic mean of its ends: no fold at vertices of high valence) | linear (eq. 4)",
        },
    ],
    needs_closed_mesh: false,
    bytes_per_face: 1400.0,
    sharp_edges: crate::schemes::SharpEdgeSupport::Builds,
    build,
};

fn shape(params: &Params) -> Result<LoopShape> {
    let alpha = params.number("alpha")?;
    let beta = params.positive_number("beta", "tangents vanish or flip")?;
    let psi = match params.choice("psi", &["harmonic", "linear"])? {
        "linear" => PsiRule::Linear,
        _ => PsiRule::Harmonic,
    };
    Ok(LoopShape {
        alpha,
        beta,
        swerve: LOOP_SWERVE,
        psi,
    })
}

/// The per-vertex pass for the whole mesh, parallel over vertices; on an open mesh the boundary
/// vertices follow [`boundary`], and the vertices that sharp edges cut into sectors [`crease`].
fn table(mesh: &Mesh, shape: &LoopShape) -> Result<HalfEdgeTable<LoopHalfEdge>> {
    if mesh.is_closed() && mesh.sharp_edges().is_empty() {
        return Ok(HalfEdgeTable::build(mesh, |p, ring, valences, out| {
            let step: Vec<f64> = valences
                .iter()
                .map(|&n| 2.0 * std::f64::consts::PI / n as f64)
                .collect();
            let steps = RingSteps {
                step: &step,
                step_minus: &step,
                sharp: &vec![false; ring.len()],
            };
            half_edges(p, ring, &steps, shape, out)
        }));
    }
    let sectors = MeshSectors::for_scheme(mesh, SPEC.name)?;
    Ok(boundary::open_table(mesh, &sectors, shape))
}

/// The three edges `a_k → a_{k+1}` of face `f` as (boundary curve, cross derivative), in the
/// face's `frame`.
fn face_edges(
    table: &HalfEdgeTable<LoopHalfEdge>,
    face: [u32; 3],
    f: usize,
    psi: PsiRule,
    frame: &FaceFrame,
) -> [(crate::bezier::CurveBezier, crate::bezier::CurveBezier); 3] {
    let mut k = 0;
    table.corner_edges(face, f).map(|[xy, yx, _, _]| {
        let ends = [frame.corners[k], frame.corners[(k + 1) % 3]];
        k += 1;
        edge_curves(table.get(xy), table.get(yx), psi, ends)
    })
}

fn build(mesh: &Mesh, params: &Params) -> Result<Surface> {
    let shape = shape(params)?;
    let (table, patches) = table_and_patches(mesh, &shape)?;
    let mut surface = params.surface(SPEC.name, patches);
    surface.warnings = crate::schemes::vertex_rings::plane_warnings(mesh, SPEC.name, |_, ring| {
        crate::schemes::vertex_rings::RingFourier::new(ring)
    });
    surface
        .warnings
        .extend(beta_cap_warning(mesh, &table, shape.beta));
    Ok(surface)
}

/// The per-vertex data of [`build`] and its patches, one per face: the swerve cap everywhere
/// except where [`loosen_where_folding`] drops it.
fn table_and_patches(
    mesh: &Mesh,
    shape: &LoopShape,
) -> Result<(HalfEdgeTable<LoopHalfEdge>, Vec<Patch>)> {
    let mut table = table(mesh, shape)?;
    let mut patches: Vec<Patch> = (0..mesh.face_count())
        .into_par_iter()
        .map(|f| face_patch(mesh, &table, f, shape.psi))
        .collect();
    loosen_where_folding(mesh, shape, &mut table, &mut patches)?;
    Ok((table, patches))
}

/// The sextic patch over face `f` from the per-vertex data `table`, `Ψ` by `psi`.
fn face_patch(mesh: &Mesh, table: &HalfEdgeTable<LoopHalfEdge>, f: usize, psi: PsiRule) -> Patch {
    let face = mesh.faces()[f];
    let frame = FaceFrame::of(mesh.positions(), face);
    let net = sextic(&face_edges(table, face, f, psi, &frame));
    Patch {
        face: f as u32,
        piece: 0,
        domain: [glam::DVec3::X, glam::DVec3::Y, glam::DVec3::Z],
        geometry: PatchGeometry::Bezier(net.placed_at(frame.origin)),
    }
}

/// Rounds of [`loosen_where_folding`].
const LOOSENING_ROUNDS: usize = 4;

/// The swerve cap keeps the boundary curves on their edges, but Loop's middle point is fixed,
/// so on a fan of thin faces the short tangents it leaves bend the curves sharply and fold a
/// patch instead (the ear-clipped caps of the hostile corpus's twelve-gon prism). So the
/// corners of every face whose patch folds over it (`Patch::fold_samples`) are rebuilt without
/// the cap (β then only reaches at most half way along each chord), and kept so if the faces
/// around them then have fewer fold samples; round by round, each vertex tried once.
fn loosen_where_folding(
    mesh: &Mesh,
    shape: &LoopShape,
    table: &mut HalfEdgeTable<LoopHalfEdge>,
    patches: &mut [Patch],
) -> Result<()> {
    let folds = |patches: &[Patch], f: usize| patches[f].fold_samples(mesh.face_normal(f as u32));
    let mut folding: Vec<usize> = (0..mesh.face_count())
        .into_par_iter()
        .filter(|&f| folds(patches, f) > 0)
        .collect();
    if folding.is_empty() {
        return Ok(());
    }
    let capped = self::table(mesh, shape)?;
    let loose = self::table(
        mesh,
        &LoopShape {
            swerve: f64::INFINITY,
            ..*shape
        },
    )?;
    let mut tried = vec![false; mesh.vertex_count()];
    for _ in 0..LOOSENING_ROUNDS {
        let mut newly: Vec<u32> = folding
            .iter()
            .flat_map(|&f| mesh.faces()[f])
            .filter(|&v| !tried[v as usize])
            .collect();
        newly.sort_unstable();
        newly.dedup();
        if newly.is_empty() {
            break;
        }
        for &v in &newly {
            tried[v as usize] = true;
        }
        let mut around: Vec<usize> = newly
            .iter()
            .flat_map(|&v| mesh.ring_faces(v).iter().map(|&f| f as usize))
            .collect();
        around.sort_unstable();
        around.dedup();
        let count = |patches: &[Patch]| around.iter().map(|&f| folds(patches, f)).sum::<usize>();
        let before = count(patches);
        table.adopt(&loose, &newly);
        for &f in &around {
            patches[f] = face_patch(mesh, table, f, shape.psi);
        }
        if count(patches) >= before {
            table.adopt(&capped, &newly);
            for &f in &around {
                patches[f] = face_patch(mesh, table, f, shape.psi);
            }
        }
        folding = around
            .iter()
            .copied()
            .filter(|&f| folds(patches, f) > 0)
            .collect();
    }
    Ok(())
}

/// The warning line for the vertices where β was capped below the parameter `beta` so that no
/// boundary curve swerves off its edge ([`crate::schemes::vertex_rings::swerve_cap`]): their
/// count, the first (in the file's numbering) with its β, and the smallest β used. None when
/// no vertex is capped. A vertex whose every edge is sharp takes β = ½ (`crease.rs`), which is
/// no cap.
fn beta_cap_warning(mesh: &Mesh, table: &HalfEdgeTable<LoopHalfEdge>, beta: f64) -> Option<String> {
    let fully_sharp = crate::schemes::fold_corners::fully_sharp_vertices(mesh);
    let capped: Vec<(u32, f64)> = (0..mesh.vertex_count() as u32)
        .filter(|&v| !fully_sharp[v as usize] || mesh.sharp_valence(v) == 0)
        .filter_map(|v| {
            let used = table.leaving(v).first()?.beta;
            (used < beta).then_some((v, used))
        })
        .collect();
    let &(first, first_beta) = capped.first()?;
    let smallest = capped.iter().map(|c| c.1).fold(f64::INFINITY, f64::min);
    Some(format!(
        "{}: capped β = {beta} at {} vertices so that no boundary curve swerves off its edge \
         (first: vertex {}, β {}; smallest β used {})",
        SPEC.name,
        capped.len(),
        mesh.input_vertex(first),
        short(first_beta),
        short(smallest)
    ))
}

/// A β for a message: three decimals, or three significant digits below 0.01.
fn short(beta: f64) -> String {
    if beta >= 0.01 {
        format!("{beta:.3}")
    } else {
        format!("{beta:.2e}")
    }
}

/// Test-only items: used by the unit tests of this and other modules, compiled only for them.
#[cfg(test)]
pub(crate) mod test_support {
    use super::*;

    /// Largest disagreement of the twist points computed from either edge, and of Loop's middle
    /// boundary point `f²` computed from either end, over all faces (for tests and diagnostics).
    pub(crate) fn max_consistency_defect(mesh: &Mesh, params: &Params) -> Result<f64> {
        let shape = shape(params)?;
        let table = table(mesh, &shape)?;
        Ok(mesh
            .faces()
            .iter()
            .enumerate()
            .map(|(f, face)| {
                let frame = FaceFrame::of(mesh.positions(), *face);
                let twist = patch::test_support::twist_mismatch(&face_edges(
                    &table, *face, f, shape.psi, &frame,
                ));
                // f² from each end, both placed in the face's frame.
                let mut k = 0;
                let f2 = table
                    .corner_edges(*face, f)
                    .map(|[xy, yx, _, _]| {
                        let (x, y) = (frame.corners[k], frame.corners[(k + 1) % 3]);
                        k += 1;
                        ((x + table.get(xy).f[2]) - (y + table.get(yx).f[2])).length()
                    })
                    .into_iter()
                    .fold(0.0, f64::max);
                twist.max(f2)
            })
            .fold(0.0, f64::max))
    }
}

#[cfg(test)]
mod tests {
    use super::test_support::*;
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

    /// The default β = 0.8 on the unit icosphere of 80 faces: measured |H| at the vertices
    /// 1.69–1.72 (β = 1/2: 4.3–4.4; the sphere: 1), normal error 0.141 rad (β = 1/2: 0.205),
    /// radial distance 2.84e-2 (β = 1/2: 4.41e-2).
    #[test]
    fn default_on_the_unit_icosphere() {
        let [distance, normal, h_min, h_max] =
            crate::testing::unit_icosphere_accuracy(|mesh| build(mesh, &params(&SPEC, &[])));
        assert!(
            h_min >= 1.65 && h_max <= 1.75,
            "|H| at the vertices in [{h_min}, {h_max}]"
        );
        assert!(normal <= 0.145, "normal error {normal} rad");
        assert!(distance <= 2.9e-2, "radial distance {distance}");
    }

    /// β above every vertex's swerve cap is capped at each vertex, and one warning says so
    /// with the count, the first vertex and its β, and the smallest β used; β = 0.5 on the
    /// same meshes is capped at fewer vertices, or none and then no warning is given.
    #[test]
    fn a_capped_beta_is_counted_in_one_warning() {
        for (name, mesh) in closed_test_meshes() {
            let (large, _) =
                table_and_patches(&mesh, &shape(&params(&SPEC, &[("beta", "50")])).unwrap())
                    .unwrap();
            let used: Vec<f64> = (0..mesh.vertex_count() as u32)
                .map(|v| large.leaving(v)[0].beta)
                .collect();
            assert!(used.iter().all(|&b| b < 50.0), "{name}: {used:?}");
            let smallest = used.iter().copied().fold(f64::INFINITY, f64::min);
            let surface = build(&mesh, &params(&SPEC, &[("beta", "50")])).unwrap();
            let capped: Vec<&String> = surface
                .warnings
                .iter()
                .filter(|w| w.starts_with("loop94: capped β"))
                .collect();
            let expected = format!(
                "loop94: capped β = 50 at {} vertices so that no boundary curve swerves off its \
                 edge (first: vertex 0, β {}; smallest β used {})",
                mesh.vertex_count(),
                short(used[0]),
                short(smallest)
            );
            assert_eq!(capped, [&expected], "{name}");
            let (half, _) =
                table_and_patches(&mesh, &shape(&params(&SPEC, &[("beta", "0.5")])).unwrap())
                    .unwrap();
            let count = (0..mesh.vertex_count() as u32)
                .filter(|&v| half.leaving(v)[0].beta < 0.5)
                .count();
            let surface = build(&mesh, &params(&SPEC, &[("beta", "0.5")])).unwrap();
            let capped = surface
                .warnings
                .iter()
                .filter(|w| w.starts_with("loop94: capped β"))
                .count();
            assert_eq!(capped, usize::from(count > 0), "{name}: {count} capped");
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

    /// The hostile corpus's twelve-gon prism, its caps ear-clipped into fans of thin faces:
    /// with the swerve cap at every vertex the patches of those fans fold (16 fold samples);
    /// with the corners of folding faces rebuilt without it, none do, and the surface is G1.
    #[test]
    fn corners_of_faces_that_fold_under_the_swerve_cap_are_rebuilt_without_it() {
        let path =
            std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/hostile/ngon-prism.obj");
        let (mesh, _) = Mesh::load_obj(&path).expect("the prism loads");
        let p = params(&SPEC, &[]);
        let shape = shape(&p).unwrap();
        let capped = table(&mesh, &shape).unwrap();
        let capped_folds: usize = (0..mesh.face_count())
            .map(|f| {
                face_patch(&mesh, &capped, f, shape.psi).fold_samples(mesh.face_normal(f as u32))
            })
            .sum();
        assert!(capped_folds > 0);
        check("ngon-prism", &mesh, &p, true);
        let m = Metrics::measure(&build(&mesh, &p).unwrap(), &mesh, 0.0);
        assert_eq!(
            m.folds, 0,
            "{capped_folds} fold samples with the cap everywhere"
        );
    }
}
