//! The evaluation Newton needs, and nothing more: position and first derivatives of a patch at
//! `(u, v)`, by de Casteljau down to the linear level on a stack copy of the net (no
//! allocation, no second derivatives). Falls back to [`Patch::jet`] for degrees above
//! [`MAX_STACK_DEGREE`] and for non-polynomial patch kinds.

use glam::DVec3;

use crate::bezier::triangle::{index, point_count};
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
    b[..point_count(d)].copy_from_slice(net.points());
    // One de Casteljau step from degree m to m−1 in place: the new b(i,j,k) lands where the
    // old b(i+1,j,k) was, which no later (smaller i) row still needs.
    for m in (2..=d).rev() {
        for i in (0..m).rev() {
            for j in (0..m - i).rev() {
                b[index(m - 1, i, j)] = w.x * b[index(m, i + 1, j)]
                    + w.y * b[index(m, i, j + 1)]
                    + w.z * b[index(m, i, j)];
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::bezier::TriangleBezier;
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
}
