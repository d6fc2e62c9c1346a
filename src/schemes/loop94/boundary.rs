//! Loop's 1994 spline on open meshes: the data of the edges leaving a boundary vertex, the
//! half-ring analogue of [`super::vertex`] — the same rules as HB00's boundary vertices
//! ([`crate::schemes::hb`]'s `boundary.rs`), in Loop's degrees. Loop (and HB00 §3) treat closed
//! meshes only.
//!
//! At a boundary vertex `v` of valence n (neighbours `p_0..p_{n−1}`, edges 0 and n − 1 on the
//! boundary): the angle step `θ = π/(n − 1)` for n ≥ 3, the face angle for a corner (n = 2)
//! ([`crate::schemes::vertex_rings::fan_angle_step`]); tangents
//! `r¹_j = 4(f¹ − f⁰) = 2β (A cos jθ + B sin jθ)` from [`half_ring_tangent_basis`] (on a regular
//! ring, `2β` times the fit is the closed rule `(4β/n) Σ cos(θ(j−i)) p_j`); `f²` Loop's point,
//! the chord midpoint on a boundary edge ([`open_loop_point`]); twists and `V` from
//! [`open_fan_cross_data`] with `V'(0) = 3(v¹ − v⁰)` (the cubic `V` of eq. 4). Interior vertices keep the closed rule, reading their
//! neighbours' orders from the fan so that `Ψ` is linear to the neighbour's `Ψ(0)`.

use glam::DVec3;

use super::vertex::{LoopCross, LoopHalfEdge, LoopShape, RingSteps, half_edges};
use crate::mesh::Mesh;
use crate::schemes::vertex_rings::{
    Fan, HalfEdgeTable, MeshSectors, half_ring_tangent_basis, open_fan_cross_data, open_loop_point,
    swerve_cap,
};

/// The per-vertex pass of Loop's scheme on a mesh that may be open and have sharp edges
/// (`sectors`, [`MeshSectors::new`]): interior vertices by the closed rule of
/// [`half_edges`] (their neighbours' steps and sharp edges read from the [`Fan`]), boundary
/// vertices by [`boundary_half_edges`], vertices cut into sectors by
/// [`super::crease::sector_half_edges`].
pub(crate) fn open_table(
    mesh: &Mesh,
    sectors: &MeshSectors,
    shape: &LoopShape,
) -> HalfEdgeTable<LoopHalfEdge> {
    HalfEdgeTable::build_open(mesh, sectors, |fan, out| {
        if let Some(sectors) = fan.sectors {
            super::crease::sector_half_edges(fan, sectors, shape, out);
        } else if fan.boundary {
            boundary_half_edges(fan, shape, out);
        } else {
            let steps = RingSteps {
                step: fan.ring_step,
                step_minus: fan.ring_step_minus,
                sharp: fan.ring_sharp,
            };
            half_edges(fan.position, fan.ring, &steps, shape, out);
        }
    })
}

/// Fills `out[j]` with the data of edge `v → p_j` at the boundary vertex of `fan` (module doc).
pub(crate) fn boundary_half_edges(fan: &Fan, shape: &LoopShape, out: &mut [LoopHalfEdge]) {
    let (v, ring) = (fan.position, fan.ring);
    let n = ring.len();
    let theta = fan.step;
    let (s, c) = theta.sin_cos();
    let (a, b) = half_ring_tangent_basis(v, ring, theta);
    let LoopShape {
        alpha,
        beta,
        swerve,
        psi,
    } = *shape;
    // β is the upper limit: f¹ − f⁰ = β (A cos jθ + B sin jθ)/2 swerves off no edge.
    let normal = a.cross(b).normalize_or_zero();
    let beta = beta.min(swerve_cap(v, ring, normal, swerve, false, |j| {
        let (sj, cj) = (theta * j as f64).sin_cos();
        0.5 * (cj * a + sj * b)
    }));
    let f0 = alpha * v + (1.0 - alpha) * ring.iter().sum::<DVec3>() / n as f64;
    let mut r1 = Vec::with_capacity(n);
    let mut r2 = Vec::with_capacity(n);
    for (j, slot) in out.iter_mut().enumerate() {
        let (sj, cj) = (theta * j as f64).sin_cos();
        let r1_j = 2.0 * beta * (cj * a + sj * b);
        let f1 = f0 + r1_j / 4.0;
        let f2 = open_loop_point(v, ring, j);
        slot.f = [f0, f1, f2];
        r1.push(r1_j);
        r2.push(12.0 * (f2 - 2.0 * f1 + f0));
    }
    let psi_slope: Vec<f64> = fan
        .ring_step
        .iter()
        .map(|t| psi.slope(s, t.sin()))
        .collect();
    // Φ quadratic with Φ(½) = ½ (eq. 1): Φ'(0) = 1 − 2 cos θ.
    let cross = open_fan_cross_data(&r1, &r2, &psi_slope, (c, s, 1.0 - 2.0 * c));
    for (slot, (v0, v_prime)) in out.iter_mut().zip(cross) {
        slot.set_plus(LoopCross {
            v: [v0, v0 + v_prime / 3.0],
            phi0: c,
            psi0: s,
        });
        slot.beta = beta;
    }
}

#[cfg(test)]
mod tests {
    use glam::DVec3;

    use crate::mesh::{Mesh, generate};
    use crate::metrics::Metrics;
    use crate::schemes::Params;
    use crate::schemes::loop94::test_support::max_consistency_defect;
    use crate::schemes::loop94::{SPEC, build};
    use crate::testing::{mesh, open_test_meshes, params};

    /// G¹ across every interior edge, vertices interpolated, twists and `f²` consistent.
    fn check(name: &str, mesh: &Mesh, p: &Params) {
        let surface = build(mesh, p).expect("loop94 builds on an open mesh");
        assert_eq!(surface.patches.len(), mesh.face_count());
        let m = Metrics::measure(&surface, mesh, 0.0);
        let label = format!("{name} {:?}", p.values());
        let interior_edges = mesh.edges().iter().filter(|e| e.faces.1.is_some()).count();
        assert_eq!(m.joints_between_faces, interior_edges, "{label}");
        assert_eq!(m.singular_samples, 0, "{label}");
        let gap = m.g0_max_rel.unwrap_or(0.0);
        let g1 = m.g1_between_faces_max_rad.unwrap_or(0.0);
        let interpolation = m.interp_max_rel.expect("vertices measured");
        let defect = max_consistency_defect(mesh, p).expect("params") / mesh.bounds().diagonal();
        eprintln!(
            "{label}: gap {gap:.1e}, normal jump {g1:.1e} rad, interpolation \
             {interpolation:.1e}, twist/f² defect {defect:.1e}"
        );
        assert!(gap <= 1e-12, "G0 gap {gap} on {label}");
        assert!(
            g1 <= crate::tolerance::NORMAL_RAD,
            "normal jump {g1} rad on {label}"
        );
        if p.number("alpha").expect("alpha") == 1.0 {
            assert!(
                interpolation <= 1e-12,
                "interpolation {interpolation} on {label}"
            );
        }
        assert!(defect <= 1e-12, "twist/f² defect {defect} on {label}");
    }

    #[test]
    fn g1_and_interpolation_on_open_meshes() {
        for (name, mesh) in open_test_meshes() {
            for pairs in [
                &[][..],
                &[("beta", "0.5")],
                &[("alpha", "0.7"), ("beta", "0.3")],
            ] {
                check(&name, &mesh, &params(&SPEC, pairs));
            }
        }
    }

    /// A planar mesh gives its plane: every control point in the plane z = 0 (exactly).
    #[test]
    fn planar_meshes_give_their_plane() {
        let mut meshes = vec![generate::disk(3)];
        meshes.extend((2..=8).map(generate::half_fan));
        for (positions, faces) in meshes {
            let flat = positions
                .iter()
                .map(|p| DVec3::new(p.x, p.y, 0.0))
                .collect();
            let surface = build(&mesh((flat, faces)), &params(&SPEC, &[])).expect("builds");
            let off = surface
                .patches
                .iter()
                .flat_map(|patch| patch.control_points())
                .map(|x| x.z.abs())
                .fold(0.0, f64::max);
            assert_eq!(off, 0.0, "off the plane z = 0 by {off}");
        }
    }
}
