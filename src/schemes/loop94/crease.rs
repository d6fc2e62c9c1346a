//! Loop's 1994 spline with sharp edges: the data of the edges leaving a vertex that sharp edges
//! cut into sectors ([`Sector`]). Loop (and HB00 §3) know no sharp edges; as for HB00
//! ([`crate::schemes::hb`]'s `crease.rs`), each sector is read as an open fan of its own, so
//! that the half-ring rules of [`super::boundary`] carry over in Loop's degrees.
//!
//! * **Boundary curves along sharp edges.** Both faces of a sharp edge share its quartic: at
//!   `v` its control points come from data the two sectors agree on bit for bit — the vertex
//!   point `f⁰`, the crease tangent `T` of the edge ([`Sector::tangents`]) times `2β` (as
//!   `r¹ = 2β (A cos jθ + B sin jθ)` at a boundary vertex), and `f²` the chord midpoint (what
//!   Loop's point is on a boundary edge, [`open_loop_point`]; a dart's closed rule takes it
//!   too, [`super::vertex::half_edges`]). β is one per vertex, the smallest swerve cap of its
//!   sectors, so that every sector sees the same `f¹`; at a vertex whose every face is a
//!   sector of its own it is ½, and each curve is then its straight edge, parametrised in
//!   proportion to length (`f¹ = v + e/4`, `f² = v + e/2`).
//! * **Inside a sector.** Its edges get `r¹_j = 2β` times the sector's tangents (they solve
//!   the vertex system, eq. 5, with `Φ(0) = cos θ`, `Ψ(0) = sin θ`, θ the sector's step),
//!   inner edges Loop's point `f²`, and the twists and `V` come from [`open_fan_cross_data`]
//!   over the sector's edges, as at a boundary vertex: (19), (21) and (II_T) hold on every
//!   inner edge, so the surface is G¹ across them, and each face next to a sharp edge gets its
//!   own `V` on its side ([`LoopHalfEdge::minus`]): only G⁰ across the crease.
//! * **Flat sectors stay flat.** With α = 1, every point of a sector whose faces lie in one
//!   plane is an affine combination of points and directions of that plane (the crease
//!   tangents lie in it), and so is the middle point of each sextic ([`super::patch`]).

use glam::DVec3;

use super::vertex::{LoopCross, LoopHalfEdge, LoopShape};
use crate::schemes::vertex_rings::{Fan, Sector, open_fan_cross_data, open_loop_point, swerve_cap};

/// Fills `out[j]` with the data of edge `v → p_j` at the vertex of `fan`, cut into `sectors`
/// (see the module doc).
pub(crate) fn sector_half_edges(
    fan: &Fan,
    sectors: &[Sector],
    shape: &LoopShape,
    out: &mut [LoopHalfEdge],
) {
    let (v, ring) = (fan.position, fan.ring);
    let n = ring.len();
    let LoopShape {
        alpha,
        beta,
        swerve,
        psi,
    } = *shape;
    let f0 = alpha * v + (1.0 - alpha) * ring.iter().sum::<DVec3>() / n as f64;
    let sector_points = |sector: &Sector| -> Vec<DVec3> {
        (0..=sector.faces)
            .map(|j| ring[(sector.first + j) % n])
            .collect()
    };
    // β is the upper limit: f¹ − f⁰ = β T/2 swerves off no edge of any sector. Where every
    // face is a sector of its own, each boundary curve is its straight edge, parametrised in
    // proportion to length with β = ½, so that faces whose corners are all such vertices can
    // be flat triangles (`schemes::fold_corners`).
    let beta = if sectors.iter().all(|sector| sector.faces == 1) {
        0.5
    } else {
        sectors.iter().fold(beta, |beta, sector| {
            let cap = swerve_cap(
                v,
                &sector_points(sector),
                sector.normal,
                swerve,
                false,
                |j| 0.5 * sector.tangents[j],
            );
            beta.min(cap)
        })
    };
    for sector in sectors {
        let m = sector.faces;
        let edge = |j: usize| (sector.first + j) % n;
        let points = sector_points(sector);
        let r1: Vec<DVec3> = sector.tangents.iter().map(|t| 2.0 * beta * *t).collect();
        let f: Vec<[DVec3; 3]> = (0..=m)
            .map(|j| [f0, f0 + r1[j] / 4.0, open_loop_point(v, &points, j)])
            .collect();
        let r2: Vec<DVec3> = f
            .iter()
            .map(|f| 12.0 * (f[2] - 2.0 * f[1] + f[0]))
            .collect();
        let (s, c) = sector.step.sin_cos();
        let psi_slope = fan.sector_psi_slope(sector, psi);
        // Φ quadratic with Φ(½) = ½ (eq. 1): Φ'(0) = 1 − 2 cos θ.
        let cross = open_fan_cross_data(&r1, &r2, &psi_slope, (c, s, 1.0 - 2.0 * c));
        for (j, (v0, v_prime)) in cross.into_iter().enumerate() {
            let side = LoopCross {
                v: [v0, v0 + v_prime / 3.0],
                phi0: c,
                psi0: s,
            };
            let slot = &mut out[edge(j)];
            slot.f = f[j];
            slot.beta = beta;
            // The last edge of a sector is the "−" side of a sharp edge, unless it is the
            // boundary edge n − 1 of a boundary vertex, whose one face that is.
            if j == m && !(fan.boundary && edge(j) == n - 1) {
                slot.minus = Some(side);
            } else {
                slot.set_plus(side);
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use crate::metrics::Metrics;
    use crate::schemes::loop94::test_support::max_consistency_defect;
    use crate::schemes::loop94::{SPEC, build};
    use crate::testing::{
        closed_test_meshes, creased, open_test_meshes, params, sharp_vertex_kinds,
    };
    use crate::tolerance::{NORMAL_RAD, POSITION_REL};

    /// On every closed and open test mesh with the edges above 20° and 35° sharp (corners,
    /// darts, creases ending at boundaries): G0 across the sharp joints, G¹ across every other
    /// joint, twists and `f²` the same from both ends of every edge, the vertices interpolated
    /// — for the default and fixed shape parameters and α < 1. Every kind of vertex is met.
    #[test]
    fn creased_meshes_are_g0_across_sharp_edges_and_g1_elsewhere() {
        let (mut corners, mut darts, mut on_boundary) = (0, 0, 0);
        let meshes = closed_test_meshes().into_iter().chain(open_test_meshes());
        for (name, mesh) in meshes {
            for degrees in [20.0, 35.0] {
                let mesh = creased(&mesh, degrees);
                if mesh.sharp_edges().is_empty() {
                    continue;
                }
                let [c, d, b] = sharp_vertex_kinds(&mesh);
                (corners, darts, on_boundary) = (corners + c, darts + d, on_boundary + b);
                for pairs in [&[][..], &[("beta", "0.4")][..], &[("alpha", "0.8")][..]] {
                    let p = params(&SPEC, pairs);
                    let label = format!("{name} at {degrees}° {pairs:?}");
                    let surface = build(&mesh, &p).unwrap_or_else(|e| panic!("{label}: {e}"));
                    let m = Metrics::measure(&surface, &mesh, 0.0);
                    assert_eq!(m.singular_samples, 0, "{label}");
                    let gap = m.g0_max_rel.expect("joints measured");
                    let g1 = m.g1_between_faces_max_rad.unwrap_or(0.0);
                    let sharp_gap = m.sharp_g0_max_rel.expect("sharp joints");
                    assert!(gap <= POSITION_REL, "{label}: G0 {gap}");
                    assert!(g1 <= NORMAL_RAD, "{label}: G1 {g1} rad");
                    assert!(sharp_gap <= POSITION_REL, "{label}: sharp G0 {sharp_gap}");
                    let diagonal = mesh.bounds().diagonal();
                    let defect = max_consistency_defect(&mesh, &p).expect("builds") / diagonal;
                    assert!(defect <= 1e-12, "{label}: twist/f² defect {defect}");
                    if pairs.iter().all(|(k, _)| *k != "alpha") {
                        let interpolation = m.interp_max_rel.expect("vertices measured");
                        assert!(interpolation <= 1e-12, "{label}: {interpolation}");
                    }
                    if pairs.is_empty() {
                        eprintln!(
                            "{label}: {} sharp joints, G0 {sharp_gap:.1e}, G1 {g1:.1e} rad, \
                             defect {defect:.1e}, folds {}",
                            m.sharp_joints, m.folds
                        );
                    }
                }
            }
        }
        assert!(
            corners > 0 && darts > 0 && on_boundary > 0,
            "corners {corners}, darts {darts}, on the boundary {on_boundary}"
        );
    }
}
