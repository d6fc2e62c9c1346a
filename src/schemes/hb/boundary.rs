//! HB00 on open meshes: the data of the edges leaving a boundary vertex. HB00 names boundaries
//! as future work (§10); the rules here are the half-ring analogue of its vertex rules, chosen
//! so that the interior G¹ conditions (eqs. 19, 21, (II_T)) hold unchanged on every interior
//! edge, the macro-patch construction of [`mod@super::macro_patch`] runs as it is, and a planar mesh
//! gives exactly its plane.
//!
//! A boundary vertex `v` of valence n has neighbours `p_0..p_{n−1}` and n − 1 faces
//! `(v, p_j, p_{j+1})`; edges 0 and n − 1 are boundary edges.
//! * **Angle step** ([`crate::schemes::vertex_rings::fan_angle_step`]): `θ = π/(n − 1)` for n ≥ 3 (the fan is read as a half
//!   plane, the boundary is smooth through `v`), `Φ(0) = cos θ`, `Ψ(0) = sin θ` on every edge at
//!   `v`, in place of `2π/n` (eqs. 6, 20). A corner (n = 2: one face, two boundary edges) has no
//!   interior edge and so no G¹ condition at `v`; its step is the face angle.
//! * **Tangents** (eq. 12, half-ring analogue, [`half_ring_tangent_basis`]):
//!   `r¹_j = 3β (A cos jθ + B sin jθ)`, which solves the vertex system (5) on the interior edges;
//!   the tangent plane is that of `A` (the boundary tangent `(p_0 − p_{n−1})/2`) and `B`.
//! * **Second derivatives** (eq. 15): `b2 = γ0 b0 + γ1 b1 + γ2 d_j` with Loop's point
//!   `d_j = (2v + p_{j−1} + 2p_j + p_{j+1})/6` on interior edges and, on a boundary edge, its
//!   curve analogue, the chord midpoint `(v + p_j)/2` (which is what `d_j` equals on a regular
//!   planar ring). `d_j` is symmetric in the edge's two ends, as on closed meshes.
//! * **Twists and `V`** ([`open_fan_cross_data`]): the twist chain (II_T) of an open fan has
//!   one free value, chosen by least squares; `V(0)`, `V'(0)` from (19) and (21) on the side of
//!   each edge that has a face. A boundary edge has no cross-boundary condition, so its `V` only
//!   has to keep the macro-patch C¹ (eq. 16 and `v²` as on interior edges).
//! * **Shape parameters**: α, β, γ as given; `auto` fits them as [`super::vertex::adaptive_shape`]
//!   does at an interior vertex, with the half-ring's tangents and tangent plane.

use glam::DVec3;

use super::vertex::{HalfEdgeData, ShapeParams, ShapeRule, fit_shape};
use crate::mesh::Mesh;
use crate::schemes::vertex_rings::{
    Fan, HalfEdgeTable, MeshSectors, half_ring_tangent_basis, open_fan_cross_data, open_loop_point,
};

/// Pass 1 of HB00 on a mesh that may be open and have sharp edges (`sectors`): interior
/// vertices by the closed rule of [`super::vertex::half_edges`] (their neighbours' steps read
/// from [`Fan::ring_step`], so that `Ψ` is linear to the neighbour's `Ψ(0)`), boundary
/// vertices by [`boundary_half_edges`], vertices cut into sectors by
/// [`super::crease::sector_half_edges`].
pub(crate) fn open_half_edge_table(
    mesh: &Mesh,
    sectors: &MeshSectors,
    rule: &ShapeRule,
) -> HalfEdgeTable<HalfEdgeData> {
    HalfEdgeTable::build_open(mesh, sectors, |fan, out| {
        if let Some(sectors) = fan.sectors {
            super::crease::sector_half_edges(fan, sectors, rule, out);
        } else if fan.boundary {
            boundary_half_edges(fan, rule, out);
        } else {
            rule.half_edges(
                fan.position,
                fan.ring,
                fan.ring_step,
                fan.ring_step_minus,
                out,
            );
        }
    })
}

/// Shape parameters at a boundary vertex for `auto`: the fits of
/// [`super::vertex::adaptive_shape`] (β: tangent speed of circular arcs; γ2: normal curvature of
/// the circles the mesh implies; γ1: no tangential acceleration) over the half-ring's edges,
/// with `unit_tangent[j]` the tangents for β = 1 and `normal` the tangent plane's normal.
fn boundary_shape(
    v: DVec3,
    ring: &[DVec3],
    unit_tangent: &[DVec3],
    normal: DVec3,
    rule: &ShapeRule,
) -> ShapeParams {
    let nf = ring.len() as f64;
    let alpha = rule.alpha;
    let b0 = alpha * v + (1.0 - alpha) * ring.iter().sum::<DVec3>() / nf;
    let fitted = fit_shape(
        v,
        ring,
        b0,
        rule.beta,
        rule.swerve,
        unit_tangent,
        normal,
        false,
        |j| open_loop_point(v, ring, j),
    );
    ShapeParams {
        alpha,
        gamma: rule.gamma.unwrap_or(fitted.gamma),
        ..fitted
    }
}

/// Fills `out[j]` with the data of edge `v → p_j` at the boundary vertex of `fan` (see the
/// module doc): the same quantities as [`super::vertex::half_edges`] computes at an interior vertex.
pub(crate) fn boundary_half_edges(fan: &Fan, rule: &ShapeRule, out: &mut [HalfEdgeData]) {
    let (v, ring) = (fan.position, fan.ring);
    let n = ring.len();
    let theta = fan.step;
    let (s, c) = theta.sin_cos();
    let phi_slope = 1.0 - 2.0 * c;
    let (a, b) = half_ring_tangent_basis(v, ring, theta);
    let unit_tangent: Vec<DVec3> = (0..n)
        .map(|j| {
            let (sj, cj) = (theta * j as f64).sin_cos();
            3.0 * (cj * a + sj * b)
        })
        .collect();
    let normal = a.cross(b).normalize_or_zero();
    let ShapeParams { alpha, beta, gamma } = boundary_shape(v, ring, &unit_tangent, normal, rule);
    let [g0, g1, g2] = gamma;
    let b0 = alpha * v + (1.0 - alpha) * ring.iter().sum::<DVec3>() / n as f64;
    let mut r1 = Vec::with_capacity(n);
    let mut r2 = Vec::with_capacity(n);
    for (j, slot) in out.iter_mut().enumerate() {
        let r1_j = beta * unit_tangent[j];
        let b1 = b0 + r1_j / 6.0;
        let b2 = g0 * b0 + g1 * b1 + g2 * open_loop_point(v, ring, j);
        slot.b = [b0, b1, b2];
        r1.push(r1_j);
        // eq. 14, factor re-derived (see vertex.rs).
        r2.push(24.0 * (b2 - 2.0 * b1 + b0));
    }
    // Ψ from sin θ here to the neighbour's Ψ(0) (eq. 20, by the rule's Ψ(½)).
    let psi_slope: Vec<f64> = fan
        .ring_step
        .iter()
        .map(|t| rule.psi.slope(s, t.sin()))
        .collect();
    let cross = open_fan_cross_data(&r1, &r2, &psi_slope, (c, s, phi_slope));
    for (slot, (v0, v_prime)) in out.iter_mut().zip(cross) {
        slot.v0 = v0;
        // V'(0) = 4(v¹ − v⁰): the quadratic is written in 2u (see vertex.rs).
        slot.v1 = v0 + v_prime / 4.0;
        slot.phi0 = c;
        slot.psi0 = s;
    }
}

#[cfg(test)]
mod tests {
    use glam::{DQuat, DVec3};

    use crate::mesh::{Mesh, generate};
    use crate::metrics::Metrics;
    use crate::schemes::hb::test_support::max_corner_mismatch;
    use crate::schemes::hb::{SPEC, build};
    use crate::schemes::{Params, SchemeSpec};
    use crate::testing::{
        JointFigures, assert_g1_joints, max_smoothness_defect_inside_faces, mesh, open_test_meshes,
        params,
    };
    use crate::tolerance::POSITION_REL;

    /// G¹ across every interior edge, C¹ inside every face, vertices interpolated, twists
    /// compatible at every face corner (boundary corners included).
    fn check(name: &str, mesh: &Mesh, spec: &SchemeSpec, p: &Params) {
        let surface = build(mesh, p).expect("hb builds on an open mesh");
        assert_eq!(surface.patches.len(), 4 * mesh.face_count(), "{name}");
        let m = Metrics::measure(&surface, mesh, 0.0);
        let label = format!("{name} {} {:?}", spec.name, p.values());
        let interior_edges = mesh.edges().iter().filter(|e| e.faces.1.is_some()).count();
        assert_eq!(m.joints_between_faces, 2 * interior_edges, "{label}");
        assert_eq!(m.singular_samples, 0, "{label}");
        let JointFigures {
            gap,
            between,
            inside,
        } = assert_g1_joints(&m, &label);
        let interpolation = m.interp_max_rel.expect("vertices measured");
        let diagonal = mesh.bounds().diagonal();
        let mismatch = max_corner_mismatch(mesh, p).expect("params ok") / diagonal;
        let c1 = max_smoothness_defect_inside_faces(&surface, 1) / diagonal;
        eprintln!(
            "{label}: gap {gap:.1e}, normal jump between faces {between:.1e} rad, inside \
             {inside:.1e} rad, interpolation {interpolation:.1e}, twist mismatch {mismatch:.1e}, \
             C1 defect {c1:.1e}"
        );
        if p.number("alpha").expect("alpha") == 1.0 {
            assert!(
                interpolation <= 1e-12,
                "interpolation {interpolation} on {label}"
            );
        }
        assert!(mismatch <= 1e-12, "twist mismatch {mismatch} on {label}");
        assert!(c1 <= POSITION_REL, "C1 defect inside faces {c1} on {label}");
    }

    #[test]
    fn g1_between_faces_c1_inside_and_interpolation_on_open_meshes() {
        for (name, mesh) in open_test_meshes() {
            for pairs in [
                &[][..],
                &[("free", "zero-twist")][..],
                &[("beta", "0.4"), ("gamma0", "0.2"), ("gamma1", "0.5")][..],
                &[("alpha", "0.8"), ("beta", "0.3")][..],
            ] {
                check(&name, &mesh, &SPEC, &params(&SPEC, pairs));
            }
        }
    }

    /// A planar mesh gives exactly its plane: every control point of every patch lies in the
    /// plane of the mesh (boundary curves included), for the default and fixed parameters, on the
    /// hexagonal disk and on half fans of valences 2..=8, in the plane z = 0 (exactly) and in a
    /// tilted plane (up to rounding).
    #[test]
    fn planar_meshes_give_their_plane() {
        let flat = |(positions, faces): generate::Triangles| {
            let positions: Vec<DVec3> = positions
                .iter()
                .map(|p| DVec3::new(p.x, p.y, 0.0))
                .collect();
            (positions, faces)
        };
        let mut meshes = vec![("disk-3", flat(generate::disk(3)))];
        for n in 2..=8 {
            meshes.push(("half-fan", flat(generate::half_fan(n))));
        }
        let tilt = DQuat::from_axis_angle(DVec3::new(1.0, 2.0, 0.5).normalize(), 0.7);
        let normal = tilt * DVec3::Z;
        for (name, triangles) in meshes {
            let tilted = (
                triangles.0.iter().map(|&p| tilt * p + DVec3::ONE).collect(),
                triangles.1.clone(),
            );
            for pairs in [
                &[][..],
                &[("beta", "0.4"), ("gamma0", "0.2"), ("gamma1", "0.5")],
            ] {
                let p = params(&SPEC, pairs);
                let surface = build(&mesh(triangles.clone()), &p).expect("builds");
                let off = surface
                    .patches
                    .iter()
                    .flat_map(|patch| patch.control_points())
                    .map(|x| x.z.abs())
                    .fold(0.0, f64::max);
                assert_eq!(off, 0.0, "{name} {pairs:?}: off the plane z = 0 by {off}");
                let surface = build(&mesh(tilted.clone()), &p).expect("builds");
                let off = surface
                    .patches
                    .iter()
                    .flat_map(|patch| patch.control_points())
                    .map(|x| (x - DVec3::ONE).dot(normal).abs())
                    .fold(0.0, f64::max);
                assert!(
                    off <= 1e-14,
                    "{name} {pairs:?}: off the tilted plane by {off}"
                );
            }
        }
    }
}
