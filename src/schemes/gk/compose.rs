//! Reparametrization step of Construction 2.1 [UP §2]: a quadratic `q: R² → R³` and the
//! patches `p_i = q ∘ x_i` of degree 2d.
//!
//! Choice of q: UP leaves it open. Here q is the least-squares quadratic through the surface
//! ring `r` read in the plane parametrization, `min Σ |q(x_i(ξ)) − r_i(ξ)|²` over a grid of
//! parameters `ξ` of the 3n ring patches. Then `q ∘ x ≈ r` on the ring, so the adaptation
//! (which blends from `q ∘ x` at the inner boundary of the ring to `r` at its outer boundary)
//! corrects as little as possible, and the hole is filled by the quadratic that best continues
//! the surrounding surface.
//!
//! Composition: with scalar nets `X, Y` of degree d, `q ∘ x = c₀ + c₁X + c₂Y + c₃X² + c₄XY +
//! c₅Y²`, and the product of two Bézier nets of degrees d₁, d₂ is the net of degree d₁ + d₂
//! with `c_γ = Σ_{α+β=γ} (d₁!/α!)(d₂!/β!)/((d₁+d₂)!/γ!) a_α b_β` (Farin, CAGD §17.9).

use glam::{DVec2, DVec3};

use crate::bezier::TriangleBezier;
use crate::bezier::gram::{factorial, multi_indices};
use crate::bezier::triangle::index;
use crate::linalg::invert;

/// A quadratic map `q(x, y) = c₀ + c₁x + c₂y + c₃x² + c₄xy + c₅y²`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Quadratic(pub [DVec3; 6]);

/// The monomials 1, x, y, x², xy, y².
fn monomials(p: DVec2) -> [f64; 6] {
    [1.0, p.x, p.y, p.x * p.x, p.x * p.y, p.y * p.y]
}

impl Quadratic {
    /// The least-squares fit of `samples` (planar point, target point); `None` if the planar
    /// points do not determine a quadratic (they lie on a conic).
    pub(crate) fn fit(samples: &[(DVec2, DVec3)]) -> Option<Quadratic> {
        let rows = samples
            .iter()
            .map(|(p, target)| (monomials(*p).to_vec(), *target));
        let c = least_squares(rows, 6)?;
        Some(Quadratic(std::array::from_fn(|i| c[i])))
    }

    /// The joint least-squares fit of q and a shift `δ` to targets that move with it:
    /// `min Σ |q(p) − (r + β δ)|²` over samples (planar point p, target r, weight β).
    pub(crate) fn fit_with_shift(samples: &[(DVec2, DVec3, f64)]) -> Option<(Quadratic, DVec3)> {
        let rows = samples.iter().map(|(p, target, beta)| {
            let mut basis = monomials(*p).to_vec();
            basis.push(-beta);
            (basis, *target)
        });
        let c = least_squares(rows, 7)?;
        Some((Quadratic(std::array::from_fn(|i| c[i])), c[6]))
    }

    /// `q ∘ x` for a planar patch `x` (its z coordinates are ignored): a patch of degree 2d.
    pub(crate) fn compose(&self, x: &TriangleBezier) -> TriangleBezier {
        let d = x.degree();
        let xs: Vec<f64> = x.control_points().map(|p| p.x).collect();
        let ys: Vec<f64> = x.control_points().map(|p| p.y).collect();
        let [c0, c1, c2, c3, c4, c5] = self.0;
        let linear: Vec<DVec3> = xs
            .iter()
            .zip(&ys)
            .map(|(a, b)| c0 + c1 * *a + c2 * *b)
            .collect();
        let mixed: Vec<DVec3> = xs.iter().zip(&ys).map(|(a, b)| c3 * *a + c4 * *b).collect();
        let square: Vec<DVec3> = ys.iter().map(|b| c5 * *b).collect();
        let ones = vec![1.0; xs.len()];
        let mut net = product(&ones, &linear, d, d);
        for (sum, (a, b)) in net.iter_mut().zip(
            product(&xs, &mixed, d, d)
                .into_iter()
                .zip(product(&ys, &square, d, d)),
        ) {
            *sum += a + b;
        }
        TriangleBezier::new(2 * d, net)
    }
}

/// The least-squares solution of `Σ basis_i c_i ≈ target` over `rows` (by the normal
/// equations; the bases here are small and well scaled), `None` if it is not unique.
fn least_squares(
    rows: impl Iterator<Item = (Vec<f64>, DVec3)>,
    unknowns: usize,
) -> Option<Vec<DVec3>> {
    let mut normal = vec![vec![0.0; unknowns]; unknowns];
    let mut rhs = vec![DVec3::ZERO; unknowns];
    for (basis, target) in rows {
        for (a, ba) in basis.iter().enumerate() {
            for (b, bb) in basis.iter().enumerate() {
                normal[a][b] += ba * bb;
            }
            rhs[a] += *ba * target;
        }
    }
    let inverse = invert(&normal)?;
    Some(
        inverse
            .iter()
            .map(|row| row.iter().zip(&rhs).map(|(w, r)| *w * *r).sum())
            .collect(),
    )
}

/// The product of a scalar net of degree `d1` and a vector net of degree `d2`.
pub(crate) fn product(a: &[f64], b: &[DVec3], d1: usize, d2: usize) -> Vec<DVec3> {
    let d = d1 + d2;
    let multinomial = |n: usize, m: &[usize; 3]| {
        factorial(n) / (factorial(m[0]) * factorial(m[1]) * factorial(m[2]))
    };
    let mut out = vec![DVec3::ZERO; (d + 1) * (d + 2) / 2];
    let low_b = multi_indices(d2);
    for alpha in multi_indices(d1) {
        let wa = multinomial(d1, &alpha) * a[index(d1, alpha[0], alpha[1])];
        if wa == 0.0 {
            continue;
        }
        for beta in &low_b {
            let gamma = [alpha[0] + beta[0], alpha[1] + beta[1], alpha[2] + beta[2]];
            let w = wa * multinomial(d2, beta) / multinomial(d, &gamma);
            out[index(d, gamma[0], gamma[1])] += w * b[index(d2, beta[0], beta[1])];
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    /// `q(p)`.
    fn eval(q: &Quadratic, p: DVec2) -> DVec3 {
        monomials(p).iter().zip(&q.0).map(|(m, c)| *m * *c).sum()
    }

    /// `q ∘ x` evaluated as a net equals q evaluated at x, and the fit reproduces a quadratic.
    #[test]
    fn composition_is_exact_and_fit_reproduces_quadratics() {
        let x = TriangleBezier::from_fn(4, |i, j, l| {
            DVec3::new(
                i as f64 * 0.3 + (j * l) as f64 * 0.1,
                j as f64 - 0.2 * (i * i) as f64,
                0.0,
            )
        });
        let q = Quadratic([
            DVec3::new(1.0, 2.0, 3.0),
            DVec3::new(0.5, -1.0, 0.0),
            DVec3::new(0.0, 0.3, 1.0),
            DVec3::new(0.2, 0.0, -0.4),
            DVec3::new(-0.1, 0.7, 0.0),
            DVec3::new(0.0, 0.0, 0.9),
        ]);
        let p = q.compose(&x);
        assert_eq!(p.degree(), 8);
        let mut samples = Vec::new();
        for a in 0..=6 {
            for b in 0..=6 - a {
                let w = DVec3::new((6 - a - b) as f64, a as f64, b as f64) / 6.0;
                let plane = x.eval(w);
                let expected = eval(&q, DVec2::new(plane.x, plane.y));
                assert!((p.eval(w) - expected).length() < 1e-13);
                samples.push((DVec2::new(plane.x, plane.y), expected));
            }
        }
        let fitted = Quadratic::fit(&samples).expect("samples span the plane");
        for (c, e) in fitted.0.iter().zip(&q.0) {
            assert!((*c - *e).length() < 1e-11, "{c} vs {e}");
        }
    }
}
