//! What Loop's 1994 scheme computes around one mesh vertex `p` from its one-ring alone
//! [HB00 §3, eqs. 1–4]: the first two control points `f⁰, f¹` of every quartic boundary curve
//! leaving `p` and Loop's symmetric middle point `f²` (eq. 2), the twists of the patches at `p`,
//! and the first two control points `v⁰, v¹` of the cubic cross-boundary function `V_i` (eq. 4).
//!
//! Notation as in [`crate::schemes::hb::vertex`]: `p` of order n, neighbours `p_i` with
//! `(p, p_i, p_{i+1})` a face, `θ = 2π/n`. With a quartic boundary curve over `[0, 1]`,
//! `r¹_i = 4(f¹ − f⁰) = (4β/n) Σ cos(θ(j−i)) p_j` and `r²_i = 12(f² − 2f¹ + f⁰)`; `Φ` is quadratic
//! with `Φ(0) = cos θ` and `Φ'(0) = 2(½ − cos θ)` (eq. 1), so (II_T) reads
//! `½(t_i + t_{i−1}) = Φ'(0) r¹_i + Φ(0) r²_i`, solved as in HB00 §6 through the preimages
//! `f̃¹_i = f⁰ + (β/n) Σ [cos + tan(θ/2) sin](θ(j−i)) p_j` and `f̃²_i = (p + p_i + p_{i+1})/3`.
//!
//! The OCR of eq. 4 is damaged (the κ_i factor and the `v¹` row); `v¹` is re-derived here from the
//! twist condition (21): `t_i = Φ'(0) r¹_i + Φ(0) r²_i + Ψ'(0) V(0) + Ψ(0) V'(0)` with
//! `V'(0) = 3(v¹ − v⁰)`; the tests check (19), (21) and (II_T) numerically.

use glam::DVec3;

use crate::schemes::vertex_rings::{PsiRule, RingFourier, front_facing_plane, swerve_cap};
use crate::schemes::vertex_rings::{phi0, psi0};

/// Loop's shape parameters α and β (eq. 2).
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct LoopShape {
    /// α: 1 interpolates the vertices, smaller values approximate (pull `f⁰` to the centroid).
    pub alpha: f64,
    /// β: tangent magnitude (an upper limit, see `swerve`).
    pub beta: f64,
    /// How far a boundary curve may swerve off its edge ([`swerve_cap`]): β is capped per
    /// vertex by it; `LOOP_SWERVE` by default, infinite where the cap made a face fold
    /// (`super::build`).
    pub swerve: f64,
    /// How `Ψ` runs along each edge: linear (eq. 4), or quadratic with its middle Bernstein
    /// coefficient the harmonic mean of the ends ([`PsiRule`]; `ΨV` stays quintic).
    pub psi: PsiRule,
}

/// Data of the directed edge `p → p_i` that `p` determines alone.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub(crate) struct LoopHalfEdge {
    /// `f⁰, f¹, f²` of the quartic boundary curve (eq. 2); `f²` is symmetric in both ends.
    pub f: [DVec3; 3],
    /// `v⁰ = V_i(0)`, `v¹` of the cubic `V_i` (eq. 4).
    pub v: [DVec3; 2],
    /// `Φ_i(0) = cos(2π/n)` (eq. 1).
    pub phi0: f64,
    /// `Ψ_i(0) = sin(2π/n)` (eq. 4).
    pub psi0: f64,
    /// The β used at the edge's first vertex: the parameter, or the swerve cap where that is
    /// lower (the same for every edge leaving the vertex).
    pub beta: f64,
    /// On a sharp edge, the cross-boundary data of the face on the "−" side
    /// (`(p, p_{i−1}, p_i)`); `v`, `phi0` and `psi0` are then those of the "+" side
    /// (`(p, p_i, p_{i+1})`). `None` elsewhere: both sides share them.
    pub minus: Option<LoopCross>,
}

/// The cross-boundary data of one side of a directed edge ([`LoopHalfEdge`]).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub(crate) struct LoopCross {
    /// `v⁰`, `v¹` of the cubic `V` (eq. 4).
    pub v: [DVec3; 2],
    /// `Φ(0)` (eq. 1).
    pub phi0: f64,
    /// `Ψ(0)` (eq. 4).
    pub psi0: f64,
}

impl LoopHalfEdge {
    /// The cross-boundary data of the face on the "−" side (`minus`) or the "+" side.
    pub(crate) fn side(&self, minus: bool) -> LoopCross {
        match (minus, self.minus) {
            (true, Some(side)) => side,
            _ => LoopCross {
                v: self.v,
                phi0: self.phi0,
                psi0: self.psi0,
            },
        }
    }

    /// Sets the cross-boundary data of the "+" side.
    pub(crate) fn set_plus(&mut self, side: LoopCross) {
        self.v = side.v;
        self.phi0 = side.phi0;
        self.psi0 = side.psi0;
    }
}

/// The neighbours of an interior vertex as its closed rule reads them: `step[i]` the angle
/// step at `ring[i]` of the face on the "+" side of edge `p → ring[i]` (`2π` over its order
/// when it is not cut into sectors), `step_minus[i]` of the face on the "−" side, and
/// `sharp[i]` whether the edge is sharp ([`crate::schemes::vertex_rings::Fan`]).
pub(crate) struct RingSteps<'a> {
    /// Angle step at `ring[i]` of the face on the "+" side of edge `i`.
    pub step: &'a [f64],
    /// Angle step at `ring[i]` of the face on the "−" side of edge `i`.
    pub step_minus: &'a [f64],
    /// Whether edge `i` is sharp.
    pub sharp: &'a [bool],
}

/// Fills `out[i]` with the data of edge `p → ring[i]` (eqs. 1–4).
///
/// A sharp edge (a dart's, or one whose far end is cut into sectors) has the chord midpoint
/// as `f²`, as the far end's crease rule has ([`super::crease`]), and the face on each side
/// its own `V`: (21) on the "+" side gives `V'_+(0)` from the twist `t_i` as everywhere, and
/// on the "−" side `t_{i−1} = R_i − Ψ'_−(0) V(0) − Ψ(0) V'_−(0)` (`R_i = Φ'(0) r¹_i + Φ(0) r²_i`)
/// gives `V'_−(0)` from `t_{i−1}`, so that both faces keep their twists (II_T no longer ties
/// them: the edge is only G⁰).
pub(crate) fn half_edges(
    p: DVec3,
    ring: &[DVec3],
    steps: &RingSteps,
    shape: &LoopShape,
    out: &mut [LoopHalfEdge],
) {
    let n = ring.len();
    let nf = n as f64;
    let (fourier, _) = front_facing_plane(p, ring, RingFourier::new(ring));
    let (c, s) = (phi0(n), psi0(n));
    let (phi_0, phi_1) = (c, 1.0 - 2.0 * c);
    let LoopShape {
        alpha,
        beta,
        swerve,
        psi,
    } = *shape;
    // β is the upper limit: f¹ − f⁰ = β cos_sum(i)/n swerves off no edge.
    let beta = beta.min(swerve_cap(p, ring, fourier.normal(), swerve, true, |i| {
        fourier.cos_sum(i) / nf
    }));
    let f0 = alpha * p + (1.0 - alpha) * fourier.mean();
    let r1 = |i: usize| (4.0 * beta / nf) * fourier.cos_sum(i % n);
    // The twist of face (p, p_i, p_{i+1}) [HB00 §6].
    let twist = |i: usize| {
        let f1_pre = f0 + (beta / nf) * fourier.twist_preimage_sum(i);
        let f2_pre = (p + ring[i] + ring[(i + 1) % n]) / 3.0;
        (12.0 * phi_0 - 4.0 * phi_1) * f0
            + (4.0 * phi_1 - 24.0 * phi_0) * f1_pre
            + 12.0 * phi_0 * f2_pre
    };
    for i in 0..n {
        let (prev, next) = (ring[(i + n - 1) % n], ring[(i + 1) % n]);
        let r1_i = r1(i);
        let f1 = f0 + r1_i / 4.0;
        let f2 = if steps.sharp[i] {
            0.5 * (p + ring[i])
        } else {
            (2.0 * p + prev + 2.0 * ring[i] + next) / 6.0
        };
        let r2_i = 12.0 * (f2 - 2.0 * f1 + f0);
        let along = phi_1 * r1_i + phi_0 * r2_i;
        // (19): r¹_{i+1} = Φ(0) r¹_i + Ψ(0) V(0).
        let v0 = (r1(i + 1) - c * r1_i) / s;
        // Ψ'(0): sin(2π/n_i) − sin(2π/n) when Ψ is linear over [0, 1] (eq. 4).
        let psi_1 = psi.slope(s, steps.step[i].sin());
        let v_prime = (twist(i) - along - psi_1 * v0) / s;
        let minus = steps.sharp[i].then(|| {
            let psi_1 = psi.slope(s, steps.step_minus[i].sin());
            let v_prime = (along - psi_1 * v0 - twist((i + n - 1) % n)) / s;
            LoopCross {
                v: [v0, v0 + v_prime / 3.0],
                phi0: c,
                psi0: s,
            }
        });
        out[i] = LoopHalfEdge {
            f: [f0, f1, f2],
            v: [v0, v0 + v_prime / 3.0],
            phi0: c,
            psi0: s,
            beta,
            minus,
        };
    }
}

#[cfg(test)]
mod tests {
    use std::f64::consts::PI;

    use super::*;
    use crate::schemes::vertex_rings::LOOP_SWERVE;

    fn ring(n: usize) -> Vec<DVec3> {
        (0..n)
            .map(|j| {
                let a = 2.0 * PI * j as f64 / n as f64 + 0.2 * (j as f64 * 1.7).sin();
                DVec3::new(
                    a.cos() * (1.0 + 0.1 * j as f64 % 0.3),
                    a.sin(),
                    0.3 * (j as f64).cos(),
                )
            })
            .collect()
    }

    /// (19), (21) and (II_T) hold for orders 3..16, 40 and 64, with `Ψ` linear and with the
    /// harmonic middle coefficient.
    #[test]
    fn twists_and_cross_boundary_data_satisfy_the_g1_conditions_at_the_vertex() {
        for n in (3..=16).chain([40, 64]) {
            for shape in [PsiRule::Linear, PsiRule::Harmonic]
                .into_iter()
                .flat_map(|psi| {
                    [
                        LoopShape {
                            alpha: 1.0,
                            beta: 0.1,
                            swerve: LOOP_SWERVE,
                            psi,
                        },
                        LoopShape {
                            alpha: 0.4,
                            beta: 0.7,
                            swerve: LOOP_SWERVE,
                            psi,
                        },
                    ]
                })
            {
                let p = ring(n);
                let valences: Vec<usize> = (0..n).map(|i| 3 + (i * 7 + n) % 11).collect();
                let step: Vec<f64> = valences.iter().map(|&m| 2.0 * PI / m as f64).collect();
                let steps = RingSteps {
                    step: &step,
                    step_minus: &step,
                    sharp: &vec![false; n],
                };
                let mut he = vec![LoopHalfEdge::default(); n];
                half_edges(DVec3::new(0.0, 0.1, 0.2), &p, &steps, &shape, &mut he);
                let (phi_0, phi_1) = (phi0(n), 1.0 - 2.0 * phi0(n));
                let r1 = |i: usize| 4.0 * (he[i % n].f[1] - he[i % n].f[0]);
                let r2 = |i: usize| 12.0 * (he[i].f[2] - 2.0 * he[i].f[1] + he[i].f[0]);
                // Ψ'(0) from Ψ(0) = sin(2π/n) and the middle coefficient of the quadratic Ψ.
                let twist = |i: usize| {
                    let psi_1 = 2.0 * (shape.psi.middle(psi0(n), psi0(valences[i])) - psi0(n));
                    phi_1 * r1(i)
                        + phi_0 * r2(i)
                        + psi_1 * he[i].v[0]
                        + psi0(n) * 3.0 * (he[i].v[1] - he[i].v[0])
                };
                for (i, h) in he.iter().enumerate() {
                    let eq19 = r1(i + 1) - (phi_0 * r1(i) + psi0(n) * h.v[0]);
                    assert!(eq19.length() < 1e-13, "eq. 19, n={n} i={i}");
                    let lhs = 0.5 * (twist(i) + twist((i + n - 1) % n));
                    let rhs = phi_1 * r1(i) + phi_0 * r2(i);
                    assert!(
                        (lhs - rhs).length() < 1e-11 * (1.0 + rhs.length()),
                        "(II_T) n={n} i={i}: {lhs} vs {rhs}"
                    );
                }
            }
        }
    }
}
