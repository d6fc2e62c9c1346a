//! Umlauf–Prautzsch triangular G^k splines [UP], `k = 1..4`: the input mesh is a control net
//! (the surface approximates it, like a subdivision surface). Stages:
//!
//! 1. [`box_spline`]: exact Bézier nets of the symmetric three-directional box spline
//!    (`k = 2(m−1)`, degree `3m − 2`) and the half-box splines (`k = 2m − 3`, degree
//!    `3(m−1)`) for one patch of a regular subnet [UP §2, §3].
//! 2. [`refine`]: Loop refinement until irregular vertices are `k + 2` edges apart.
//! 3. [`regular`]: one patch per face with a regular subnet ([`chart`] finds the subnets).
//!
//! Patches and faces: every patch belongs to the input face that contains its refined face
//! (refinement splits each input face regularly), with `domain` the exact face-barycentric
//! corners of that refined face, so [`crate::surface::Surface::joints`] pairs patches across
//! input faces as for any other scheme. `piece` is 0 for (half-)box-spline patches.
//!
//! Faces whose subnet is not regular — those within grid distance `⌈k/2⌉ − 1` of an
//! irregular vertex, i.e. the n-sided holes of the generalized spline surface — have no patch
//! yet: the surface has one hole per irregular vertex (none on an all-valence-6 net).

pub mod box_spline;
pub mod chart;
pub mod jets;
pub mod plane;
pub mod refine;
pub mod regular;
pub mod sector;

use rayon::prelude::*;

use crate::error::{Error, Result};
use crate::mesh::Mesh;
use crate::schemes::{ParamSpec, Params, SchemeSpec};
use crate::surface::{Patch, PatchGeometry, Surface};

/// Registry entry.
pub const SPEC: SchemeSpec = SchemeSpec {
    name: "gk",
    summary: "Umlauf-Prautzsch 2000: C^k (half-)box-spline surface of a refined control net (UP)",
    params: &[ParamSpec {
        name: "k",
        default: "2",
        help: "smoothness order 1..4 (even: box spline of degree 3k/2+1; odd: half-box spline of degree 3(k+1)/2)",
    }],
    needs_closed_mesh: true,
    build,
};

/// The smoothness order parameter, checked to be 1..=4.
pub fn order(params: &Params) -> Result<usize> {
    let k = params.number("k")?;
    if k.fract() != 0.0 || !(1.0..=4.0).contains(&k) {
        return Err(Error::BadParam {
            name: "k".into(),
            reason: format!("must be one of 1, 2, 3, 4, got {k}"),
        });
    }
    Ok(k as usize)
}

fn build(mesh: &Mesh, params: &Params) -> Result<Surface> {
    let k = order(params)?;
    let net = refine::prepare(mesh, k)?;
    let patches = regular::regular_patches(&net.mesh, k)
        .into_par_iter()
        .enumerate()
        .filter_map(|(f, patch)| {
            Some(Patch {
                face: net.origin[f],
                piece: 0,
                domain: net.domain[f],
                geometry: PatchGeometry::Bezier(patch?),
            })
        })
        .collect();
    Ok(Surface {
        scheme: SPEC.name.to_string(),
        params: params.values().to_vec(),
        patches,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::metrics::Metrics;
    use crate::schemes::gk::jets::lattice_jump;
    use crate::schemes::testing::{closed_test_meshes, params};

    /// Faces without a regular subnet around one irregular vertex of valence n: ring 1 for
    /// k = 1, 2 (n faces), rings 1 and 2 for k = 3, 4 (n + 3n faces).
    fn hole_faces(k: usize, n: usize) -> usize {
        if k <= 2 { n } else { 4 * n }
    }

    /// On every closed test mesh and k = 1..4: the holes are exactly those of the irregular
    /// vertices, and every joint of two patches is C^k in the lattice parametrisation
    /// (derivatives of order ≤ k agree to 1e-12 of the bound the nets put on them, see
    /// [`lattice_jump`]; joints that are not C^{k+1} as well exist on every mesh).
    #[test]
    fn regular_surface_is_c_k_with_one_hole_per_irregular_vertex() {
        for (name, mesh) in closed_test_meshes() {
            for k in 1..=4 {
                let p = params(&SPEC, &[("k", &k.to_string())]);
                let surface = build(&mesh, &p).expect("closed meshes build");
                let net = refine::prepare(&mesh, k).unwrap();
                let holes: usize = (0..net.mesh.vertex_count() as u32)
                    .map(|v| net.mesh.valence(v))
                    .filter(|&n| n != 6)
                    .map(|n| hole_faces(k, n))
                    .sum();
                let label = format!("{name} k = {k}");
                assert_eq!(
                    surface.patches.len() + holes,
                    net.mesh.face_count(),
                    "{label}"
                );
                let degree = box_spline::Family::for_order(k).degree();
                assert!(surface.patches.iter().all(|p| p.degree() == Some(degree)));
                let joints = surface.joints(mesh.faces());
                let (mut worst, mut next_min, mut smoother) = (0.0f64, f64::MAX, 0usize);
                for j in &joints {
                    assert!(j.reversed, "{label}: consistently oriented");
                    let a = surface.patches[j.a.patch as usize].as_bezier().unwrap();
                    let b = surface.patches[j.b.patch as usize].as_bezier().unwrap();
                    let (ea, eb) = (j.a.edge as usize, j.b.edge as usize);
                    for order in 0..=k {
                        worst = worst.max(lattice_jump(a, ea, b, eb, order));
                    }
                    let next = lattice_jump(a, ea, b, eb, k + 1);
                    if next < 1e-12 {
                        smoother += 1;
                    } else {
                        next_min = next_min.min(next);
                    }
                }
                eprintln!(
                    "{label}: {} patches, {} joints, worst order-≤k jump {worst:.1e}, \
                     {smoother} joints also C^{}, smallest order-{} jump elsewhere {next_min:.1e}",
                    surface.patches.len(),
                    joints.len(),
                    k + 1,
                    k + 1
                );
                assert!(worst < 1e-12, "{label}: jump {worst:e}");
                assert!(
                    smoother < joints.len(),
                    "{label}: no joint shows order k + 1 fails"
                );
                let m = Metrics::measure(&surface, &mesh, 0.0);
                assert!(m.g0_max_rel.unwrap() < 1e-12, "{label}");
            }
        }
    }

    #[test]
    fn order_outside_one_to_four_is_refused() {
        for bad in ["0", "5", "2.5", "x"] {
            let err = order(&params(&SPEC, &[("k", bad)])).unwrap_err();
            assert!(err.to_string().contains("'k'"), "{bad}: {err}");
        }
    }
}
