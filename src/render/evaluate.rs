//! The evaluation Newton needs, and nothing more: position and first derivatives of a patch at
//! `(u, v)`, by de Casteljau down to the linear level on a stack copy of the net (no
//! allocation, no second derivatives). Falls back to [`Patch::jet`] for degrees above
//! [`MAX_STACK_DEGREE`] and for non-polynomial patch kinds.

use glam::DVec3;

use crate::bezier::triangle::{index, point_count};

use crate::bezier::TriangleBezier;
use crate::surface::Patch;

/// Largest degree evaluated on the stack (28 control points).
pub const MAX_STACK_DEGREE: usize = 6;

/// `S(u, v)`, `∂S/∂u`, `∂S/∂v` at barycentric `(1−u−v, u, v)`.
pub fn point_and_tangents(patch: &Patch, u: f64, v: f64) -> (DVec3, DVec3, DVec3) {
    let Some(net) = patch.as_bezier() else {
        let jet = patch.jet(u, v);
        return (jet.p, jet.du, jet.dv);
    };
    let d = net.degree();
    if d == 0 || d > MAX_STACK_DEGREE {
        let jet = patch.jet(u, v);
        return (jet.p, jet.du, jet.dv);
    }
    let w = DVec3::new(1.0 - u - v, u, v);
    let mut b = [DVec3::ZERO; point_count(MAX_STACK_DEGREE)];
    // In the storage order, the points with first index i form "row" r = d − i, starting at
    // T(r) = r(r+1)/2, with position s = r − j along it. One de Casteljau step maps rows r−1
    // and r of degree m to row r−1 of degree m−1:
    //   b'[T(r−1)+s] = w0 b[T(r−1)+s] + w1 b[T(r)+s] + w2 b[T(r)+s+1],
    // so it runs in place with r ascending and streams through memory. The first step reads
    // the net directly (no copy).
    let src = net.points();
    if d == 1 {
        b[..3].copy_from_slice(src);
    } else {
        for r in 1..=d {
            let (prev, row) = (r * (r - 1) / 2, r * (r + 1) / 2);
            for s in 0..r {
                b[prev + s] = w.x * src[prev + s] + w.y * src[row + s] + w.z * src[row + s + 1];
            }
        }
    }
    for m in (2..d).rev() {
        for r in 1..=m {
            let (prev, row) = (r * (r - 1) / 2, r * (r + 1) / 2);
            for s in 0..r {
                b[prev + s] = w.x * b[prev + s] + w.y * b[row + s] + w.z * b[row + s + 1];
            }
        }
    }
    // The linear level b(1,0,0), b(0,1,0), b(0,0,1): its plane is the tangent plane
    // [Farin, CAGD §17.3].
    let (b100, b010, b001) = (b[index(1, 1, 0)], b[index(1, 0, 1)], b[index(1, 0, 0)]);
    let scale = d as f64;
    (
        w.x * b100 + w.y * b010 + w.z * b001,
        (b010 - b100) * scale,
        (b001 - b100) * scale,
    )
}

/// A bound on the second derivative of a Bézier triangle in any unit `(u, v)` direction over
/// its domain. With δ = δu (e1 − e0) + δv (e2 − e0), `D²S(δ, δ) = d(d−1) Σ B^{d−2}_{ijk}
/// (δu² Q11 + 2 δu δv Q12 + δv² Q22)` where Q are second differences of the control net, so
/// `d(d−1) (max|Q11| + max|Q12| + max|Q22|)` bounds it (2|δu δv| ≤ 1).
pub fn second_derivative_bound(net: &TriangleBezier) -> f64 {
    let d = net.degree();
    if d < 2 {
        return 0.0;
    }
    let (mut q11, mut q12, mut q22) = (0.0_f64, 0.0_f64, 0.0_f64);
    for i in 0..=d - 2 {
        for j in 0..=d - 2 - i {
            // b(i+a, j+b, k+c) with (a, b, c) one of the six second-order offsets.
            let b00 = net.point(i + 2, j);
            let b01 = net.point(i + 1, j + 1);
            let b02 = net.point(i + 1, j);
            let b11 = net.point(i, j + 2);
            let b12 = net.point(i, j + 1);
            let b22 = net.point(i, j);
            q11 = q11.max((b11 - 2.0 * b01 + b00).length());
            q12 = q12.max((b12 - b01 - b02 + b00).length());
            q22 = q22.max((b22 - 2.0 * b02 + b00).length());
        }
    }
    (d * (d - 1)) as f64 * (q11 + q12 + q22)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::surface::PatchGeometry;

    #[test]
    fn matches_the_jet_for_every_stack_degree() {
        for d in 1..=MAX_STACK_DEGREE + 1 {
            let net = TriangleBezier::from_fn(d, |i, j, k| {
                let (i, j, k) = (i as f64, j as f64, k as f64);
                DVec3::new(
                    j + 0.3 * i * k,
                    k - 0.2 * j * j,
                    (i * 1.7 + j * 0.3 - k).sin(),
                )
            });
            let patch = Patch {
                face: 0,
                piece: 0,
                domain: [DVec3::X, DVec3::Y, DVec3::Z],
                geometry: PatchGeometry::Bezier(net),
            };
            for (u, v) in [(0.0, 0.0), (0.2, 0.3), (0.7, 0.1), (0.0, 1.0), (0.33, 0.33)] {
                let jet = patch.jet(u, v);
                let (p, su, sv) = point_and_tangents(&patch, u, v);
                let err = (p - jet.p)
                    .length()
                    .max((su - jet.du).length())
                    .max((sv - jet.dv).length());
                assert!(err <= 1e-13, "degree {d} at ({u}, {v}): {err:e}");
            }
        }
    }

    /// The second-derivative bound holds at sampled points in sampled directions.
    #[test]
    fn second_derivative_bound_holds() {
        let surface = crate::render::fixtures::octahedron_sphere(5, 1.7, 0);
        for patch in &surface.patches {
            let net = patch.as_bezier().expect("Bézier patch");
            let bound = second_derivative_bound(net);
            for k in 0..50u64 {
                let u = crate::render::sampler::uniform(4, k, 0, 0);
                let v = crate::render::sampler::uniform(4, k, 0, 1) * (1.0 - u);
                let jet = patch.jet(u, v);
                let angle = std::f64::consts::TAU * crate::render::sampler::uniform(4, k, 0, 2);
                let (du, dv) = (angle.cos(), angle.sin());
                let d2 = jet.duu * du * du + 2.0 * jet.duv * du * dv + jet.dvv * dv * dv;
                assert!(
                    d2.length() <= bound * (1.0 + 1e-12),
                    "{} > {bound}",
                    d2.length()
                );
            }
        }
    }
}
