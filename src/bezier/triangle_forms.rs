//! Other Bézier forms of the same triangular patch: over a sub-triangle of its domain
//! (subdivision through the blossom), at a higher degree (elevation), restricted to a boundary
//! edge (a Bézier curve), the boxes that contain it (convex-hull property), and the Bézier form
//! of its normal's component along a direction (a proof that it does not turn over).
//!
//! Standard facts from Farin, *Curves and Surfaces for CAGD*, ch. 17, as recalled in
//! [Piper87 §3.6–3.7].

use glam::DVec3;

use crate::bezier::CurveBezier;
use crate::bezier::triangle::{
    TriangleBezier, by_coordinate, de_casteljau_step, de_casteljau_step_by_coordinate, index,
    point_count,
};
use crate::geom::Aabb;

/// Nets of up to this many control points (degree 8) are subdivided on stack buffers.
const STACK_POINTS: usize = point_count(8);

impl TriangleBezier {
    /// The same surface over the sub-triangle with barycentric corners `corners` (each a
    /// barycentric point of this patch's domain): the result's corner `b(d,0,0)` is at
    /// `corners[0]`, `b(0,d,0)` at `corners[1]`, `b(0,0,d)` at `corners[2]`.
    ///
    /// `b'(i,j,k) = blossom(c0^i, c1^j, c2^k)` [Piper87 eq. 15; Farin, CAGD §17.8]. The
    /// blossom is evaluated incrementally: the net after `i` steps at `c0` is shared by all
    /// points with that `i`, and the net after `j` further steps at `c1` by all with that `(i,j)`.
    /// For corners inside the domain every step is a convex combination (stable); outside it
    /// is extrapolation and loses accuracy with the distance.
    pub fn subdivide(&self, corners: [DVec3; 3]) -> TriangleBezier {
        let count = point_count(self.degree());
        let mut points = vec![DVec3::ZERO; count];
        let offsets = self.offsets();
        match self.degree() {
            2 => blossom_net_of_degree::<2, 6>(offsets, corners, &mut points),
            3 => blossom_net_of_degree::<3, 10>(offsets, corners, &mut points),
            4 => blossom_net_of_degree::<4, 15>(offsets, corners, &mut points),
            5 => blossom_net_of_degree::<5, 21>(offsets, corners, &mut points),
            6 => blossom_net_of_degree::<6, 28>(offsets, corners, &mut points),
            _ => self.blossom_net_any_degree(corners, &mut points),
        }
        TriangleBezier::with_origin(self.degree(), self.origin(), points)
    }

    /// [`TriangleBezier::subdivide`]'s net into `points`, for any degree.
    fn blossom_net_any_degree(&self, corners: [DVec3; 3], points: &mut [DVec3]) {
        let count = point_count(self.degree());
        if count <= STACK_POINTS {
            let mut after_c0 = [DVec3::ZERO; STACK_POINTS];
            let mut after_c1 = [DVec3::ZERO; STACK_POINTS];
            let mut after_c2 = [DVec3::ZERO; STACK_POINTS];
            self.blossom_net(
                corners,
                [&mut after_c0, &mut after_c1, &mut after_c2],
                points,
            );
        } else {
            let mut buffers = [(); 3].map(|_| vec![DVec3::ZERO; count]);
            let [a, b, c] = &mut buffers;
            self.blossom_net(corners, [a, b, c], points);
        }
    }

    /// The net of [`TriangleBezier::subdivide`] into `points`, with three working nets
    /// (`scratch`, each at least as long as the net): the net after the steps at `c0`, then
    /// at `c1`, then at `c2`.
    fn blossom_net(
        &self,
        [c0, c1, c2]: [DVec3; 3],
        [after_c0, after_c1, after_c2]: [&mut [DVec3]; 3],
        points: &mut [DVec3],
    ) {
        let d = self.degree();
        after_c0[..point_count(d)].copy_from_slice(self.offsets());
        for i in 0..=d {
            if i > 0 {
                de_casteljau_step(after_c0, d - i + 1, c0);
            }
            after_c1[..point_count(d - i)].copy_from_slice(&after_c0[..point_count(d - i)]);
            for j in 0..=d - i {
                if j > 0 {
                    de_casteljau_step(after_c1, d - i - j + 1, c1);
                }
                let k = d - i - j;
                after_c2[..point_count(k)].copy_from_slice(&after_c1[..point_count(k)]);
                for m in (1..=k).rev() {
                    de_casteljau_step(after_c2, m, c2);
                }
                points[index(d, i, j)] = after_c2[0];
            }
        }
    }

    /// The same surface as a patch of degree d+1 [Piper87 §3.6]:
    /// `b'(i) = (i0 b(i−e0) + i1 b(i−e1) + i2 b(i−e2)) / (d+1)`.
    pub fn elevate(&self) -> TriangleBezier {
        let d = self.degree();
        // Weights i/(d+1) rather than a common factor 1/(d+1): at the corners the weight is
        // exactly one, so the elevated net interpolates the corners bit for bit.
        let weight = |n: usize| n as f64 / (d + 1) as f64;
        TriangleBezier::from_fn(d + 1, |i, j, k| {
            let mut sum = DVec3::ZERO;
            if i > 0 {
                sum += weight(i) * self.offset(i - 1, j);
            }
            if j > 0 {
                sum += weight(j) * self.offset(i, j - 1);
            }
            if k > 0 {
                sum += weight(k) * self.offset(i, j);
            }
            sum
        })
        .placed_at(self.origin())
    }

    /// Boundary curve `edge` (0: corner 0 → corner 1, where k = 0; 1: corner 1 → corner 2,
    /// where i = 0; 2: corner 2 → corner 0, where j = 0). On an edge only that edge's control
    /// points contribute [Piper87 §3.4], so they are the curve's control points.
    /// Panics if `edge > 2`.
    pub fn edge_curve(&self, edge: usize) -> CurveBezier {
        let d = self.degree();
        let points = (0..=d)
            .map(|l| match edge {
                0 => self.point(d - l, l),
                1 => self.point(0, d - l),
                2 => self.point(l, 0),
                _ => panic!("a triangle has edges 0, 1, 2, not {edge}"),
            })
            .collect();
        CurveBezier::new(points)
    }

    /// Bounding box of the control points (contains the patch: convex-hull property).
    pub fn control_bounds(&self) -> Aabb {
        self.control_points()
            .fold(Aabb::EMPTY, |b, p| b.union_point(p))
    }

    /// A box that contains the patch over the sub-triangle with barycentric `corners` (inside
    /// the domain), conservative even under the rounding of the subdivision: the control
    /// bounds of [`TriangleBezier::subdivide`], grown by a bound on its floating-point error.
    ///
    /// Each of the `d` de Casteljau steps per sub-net point is a convex combination, adding at
    /// most about three ulps of the largest coordinate magnitude (weights that sum to one only up to
    /// rounding add one more); the margin `8(d+1)·ε·max|b|` covers that with room to spare.
    pub fn sub_triangle_bounds(&self, corners: [DVec3; 3]) -> Aabb {
        let bounds = self.subdivide(corners).control_bounds();
        let magnitude = self
            .control_points()
            .fold(0.0_f64, |m, p| m.max(p.abs().max_element()));
        let margin = 8.0 * (self.degree() + 1) as f64 * f64::EPSILON * magnitude;
        Aabb {
            min: bounds.min - DVec3::splat(margin),
            max: bounds.max + DVec3::splat(margin),
        }
    }
}

/// The highest degree whose normal component [`TriangleBezier::faces_along`] proves on stack
/// buffers.
const MAX_FACING_DEGREE: usize = 7;

/// `k!` for `k ≤ 2 MAX_FACING_DEGREE − 2`, the largest order [`multinomial`] is asked for.
const FACTORIALS: [f64; 2 * MAX_FACING_DEGREE - 1] = {
    let mut table = [1.0; 2 * MAX_FACING_DEGREE - 1];
    let mut k = 1;
    while k < table.len() {
        table[k] = table[k - 1] * k as f64;
        k += 1;
    }
    table
};

/// `m! / (i! j! (m − i − j)!)`, for `m ≤ 2 MAX_FACING_DEGREE − 2`.
fn multinomial(m: usize, i: usize, j: usize) -> f64 {
    FACTORIALS[m] / (FACTORIALS[i] * FACTORIALS[j] * FACTORIALS[m - i - j])
}

impl TriangleBezier {
    /// True when the patch's normal `∂B/∂u × ∂B/∂v` has a positive component along `n`
    /// everywhere on its domain, by a margin far above rounding: a proof that the patch
    /// nowhere turns over a face of normal `n`. False proves nothing (degree 0 or above
    /// [`MAX_FACING_DEGREE`], or a coefficient too small).
    ///
    /// The partials are Bézier triangles of degree `d − 1` with control points
    /// `a_m = b(m + e₁) − b(m + e₀)`, `c_m = b(m + e₂) − b(m + e₀)` (times `d`), so
    /// `(∂B/∂u × ∂B/∂v) · n` is a Bézier triangle of degree `2d − 2` whose coefficient at `k` is
    /// `d² Σ_{m+l=k} M(m) M(l) / M(k) · det[a_m, c_l, n]` (`M` the multinomials: the product
    /// rule of Bernstein polynomials, Farin, CAGD §17.2); a Bernstein sum lies between its
    /// smallest and largest coefficients.
    pub(crate) fn faces_along(&self, n: DVec3) -> bool {
        let d = self.degree();
        if d == 0 || d > MAX_FACING_DEGREE {
            return false;
        }
        let m = d - 1;
        const FIRST: usize = point_count(MAX_FACING_DEGREE - 1);
        // a_m and c_m × n, each times its multinomial M(m), and the (i, j) of each m.
        let mut a = [DVec3::ZERO; FIRST];
        let mut c_across_n = [DVec3::ZERO; FIRST];
        let mut at = [(0, 0); FIRST];
        let (mut largest_a, mut largest_c) = (0.0_f64, 0.0_f64);
        for i in 0..=m {
            for j in 0..=m - i {
                let p = index(m, i, j);
                let base = self.offset(i + 1, j);
                let (ap, c) = (self.offset(i, j + 1) - base, self.offset(i, j) - base);
                let weight = multinomial(m, i, j);
                a[p] = weight * ap;
                c_across_n[p] = weight * c.cross(n);
                at[p] = (i, j);
                largest_a = largest_a.max(ap.length());
                largest_c = largest_c.max(c.length());
            }
        }
        let count = point_count(m);
        let mut coefficients = [0.0; point_count(2 * MAX_FACING_DEGREE - 2)];
        for p in 0..count {
            let (i, j) = at[p];
            for q in 0..count {
                let (k, l) = at[q];
                coefficients[index(2 * m, i + k, j + l)] += a[p].dot(c_across_n[q]);
            }
        }
        // The sampled normal and these sums each round to a few ulps of this scale.
        let scale = largest_a * largest_c * n.length();
        let margin = 1e-10 * scale;
        scale.is_finite()
            && scale > 0.0
            && (0..=2 * m)
                .flat_map(|i| (0..=2 * m - i).map(move |j| (i, j)))
                .all(|(i, j)| coefficients[index(2 * m, i, j)] > margin * multinomial(2 * m, i, j))
    }
}

/// [`TriangleBezier::subdivide`]'s net for a net of degree `D` (`N` points, `D ≥ 1`): the
/// same de Casteljau steps, in the same order, as the general path (so the same bits), one
/// coordinate at a time ([`de_casteljau_step_by_coordinate`]), with the degree known to the
/// compiler. The BVH build subdivides every patch down to its leaves through here.
fn blossom_net_of_degree<const D: usize, const N: usize>(
    offsets: &[DVec3],
    [c0, c1, c2]: [DVec3; 3],
    points: &mut [DVec3],
) {
    let step = de_casteljau_step_by_coordinate::<N>;
    let mut after_c0 = by_coordinate::<N>(offsets);
    for i in 0..=D {
        if i > 0 {
            step(&mut after_c0, D - i + 1, c0);
        }
        let mut after_c1 = after_c0;
        for j in 0..=D - i {
            if j > 0 {
                step(&mut after_c1, D - i - j + 1, c1);
            }
            let mut after_c2 = after_c1;
            for m in (1..=D - i - j).rev() {
                step(&mut after_c2, m, c2);
            }
            let [x, y, z] = &after_c2;
            points[index(D, i, j)] = DVec3::new(x[0], y[0], z[0]);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::bezier::test_support::{rel_err, scale_of};
    use crate::testing::Rng;

    /// 1..=7 as specified, plus 0 and degrees on the heap path of the evaluator.
    const DEGREES: [usize; 10] = [0, 1, 2, 3, 4, 5, 6, 7, 9, 11];

    /// Checks that `sub` over the unit domain is `patch` over the sub-triangle `corners`, at
    /// random points and the corners.
    fn assert_reproduces(
        patch: &TriangleBezier,
        sub: &TriangleBezier,
        corners: [DVec3; 3],
        rng: &mut Rng,
    ) {
        let scale = scale_of(patch.offsets());
        let mut samples: Vec<DVec3> = (0..10).map(|_| rng.bary_inside()).collect();
        samples.extend([DVec3::X, DVec3::Y, DVec3::Z]);
        for s in samples {
            let in_parent = s.x * corners[0] + s.y * corners[1] + s.z * corners[2];
            let err = rel_err(sub.eval(s), patch.eval(in_parent), scale);
            assert!(
                err <= 1e-12,
                "d={} corners {corners:?} at {s}: rel err {err:e}",
                patch.degree()
            );
        }
    }

    #[test]
    fn subdivide_reproduces_the_surface_over_the_sub_triangle() {
        let mut rng = Rng::new(10);
        for d in DEGREES {
            let patch = rng.triangle(d, 1.0);
            for _ in 0..6 {
                let corners = [rng.bary_inside(), rng.bary_inside(), rng.bary_inside()];
                let sub = patch.subdivide(corners);
                assert_eq!(sub.degree(), d);
                assert_reproduces(&patch, &sub, corners, &mut rng);
            }
        }
    }

    #[test]
    fn subdivide_over_the_whole_domain_is_exact() {
        let mut rng = Rng::new(11);
        for d in DEGREES {
            let patch = rng.triangle(d, 0.0);
            assert_eq!(
                patch.subdivide([DVec3::X, DVec3::Y, DVec3::Z]),
                patch,
                "d={d}"
            );
            // Rotating the corners relabels the control points: with corners (e2, e0, e1),
            // b'(i,j,k) = b[e2^i, e0^j, e1^k] = b(j,k,i).
            let rotated = patch.subdivide([DVec3::Z, DVec3::X, DVec3::Y]);
            for i in 0..=d {
                for j in 0..=d - i {
                    let k = d - i - j;
                    assert_eq!(
                        rotated.point(i, j),
                        patch.point(j, k),
                        "d={d} b({i},{j},{k})"
                    );
                }
            }
        }
    }

    /// The four triangles of the midpoint split (three corner triangles and the reversed middle
    /// one) reproduce the patch, and their nets stay inside the parent's control box.
    #[test]
    fn four_split_reproduces_the_surface() {
        let mut rng = Rng::new(12);
        let (e0, e1, e2) = (DVec3::X, DVec3::Y, DVec3::Z);
        let (m01, m12, m20) = ((e0 + e1) / 2.0, (e1 + e2) / 2.0, (e2 + e0) / 2.0);
        let pieces = [
            [e0, m01, m20],
            [m01, e1, m12],
            [m20, m12, e2],
            [m12, m20, m01],
        ];
        for d in DEGREES {
            let patch = rng.triangle(d, 3.0);
            let parent_box = patch.control_bounds();
            let tol = 1e-14 * scale_of(patch.offsets());
            for corners in pieces {
                let sub = patch.subdivide(corners);
                assert_reproduces(&patch, &sub, corners, &mut rng);
                for p in sub.offsets() {
                    assert!(
                        parent_box.contains(*p, tol),
                        "d={d}: {p} outside the parent hull box"
                    );
                }
            }
        }
    }

    #[test]
    fn elevation_reproduces_the_surface() {
        let mut rng = Rng::new(13);
        for d in DEGREES {
            let patch = rng.triangle(d, 1.0);
            let elevated = patch.elevate();
            let twice = elevated.elevate();
            assert_eq!(elevated.degree(), d + 1);
            assert_eq!(twice.degree(), d + 2);
            let scale = scale_of(patch.offsets());
            let derivative_scale = scale * ((d + 2) * (d + 2)) as f64;
            for _ in 0..10 {
                let w = rng.bary_inside();
                for (name, other) in [("once", &elevated), ("twice", &twice)] {
                    let err = rel_err(other.eval(w), patch.eval(w), scale);
                    assert!(err <= 1e-12, "d={d} {name}: rel err {err:e}");
                    let (a, b) = (other.jet(w.y, w.z), patch.jet(w.y, w.z));
                    for (x, y) in [
                        (a.du, b.du),
                        (a.dv, b.dv),
                        (a.duu, b.duu),
                        (a.duv, b.duv),
                        (a.dvv, b.dvv),
                    ] {
                        let err = rel_err(x, y, derivative_scale);
                        assert!(err <= 1e-11, "d={d} {name} derivative: rel err {err:e}");
                    }
                }
            }
            // Corners are interpolated exactly.
            let e = d + 1;
            assert_eq!(elevated.point(e, 0), patch.point(d, 0));
            assert_eq!(elevated.point(0, e), patch.point(0, d));
            assert_eq!(elevated.point(0, 0), patch.point(0, 0));
        }
    }

    #[test]
    fn edge_curves_match_the_patch_along_its_edges() {
        let mut rng = Rng::new(14);
        for d in DEGREES {
            let patch = rng.triangle(d, 1.0);
            let scale = scale_of(patch.offsets());
            for edge in 0..3 {
                let curve = patch.edge_curve(edge);
                assert_eq!(curve.degree(), d);
                for n in 0..=10 {
                    let t = n as f64 / 10.0;
                    let bary = match edge {
                        0 => DVec3::new(1.0 - t, t, 0.0),
                        1 => DVec3::new(0.0, 1.0 - t, t),
                        _ => DVec3::new(t, 0.0, 1.0 - t),
                    };
                    let err = rel_err(curve.eval(t), patch.eval(bary), scale);
                    assert!(err <= 1e-12, "d={d} edge {edge} t={t}: rel err {err:e}");
                }
            }
        }
    }

    #[test]
    fn control_bounds_contain_the_patch() {
        let mut rng = Rng::new(15);
        for d in DEGREES {
            let patch = rng.triangle(d, 4.0);
            let bounds = patch.control_bounds();
            for _ in 0..200 {
                let p = patch.eval(rng.bary_inside());
                // Zero tolerance: every de Casteljau step is a convex combination.
                assert!(bounds.contains(p, 0.0), "d={d}: {p} outside {bounds:?}");
            }
        }
    }

    /// The padded boxes over small sub-triangles contain the patch there and are much smaller
    /// than the whole patch's box (what makes them useful to the ray tracer's hierarchy).
    #[test]
    fn sub_triangle_bounds_are_conservative_and_tight() {
        let mut rng = Rng::new(16);
        for d in DEGREES {
            let patch = rng.triangle(d, 4.0);
            let whole = patch.control_bounds().diagonal();
            for _ in 0..10 {
                let centre = rng.bary_inside();
                let size = 0.05;
                let corners = [
                    centre,
                    centre + size * DVec3::new(-1.0, 1.0, 0.0),
                    centre + size * DVec3::new(-1.0, 0.0, 1.0),
                ];
                let bounds = patch.sub_triangle_bounds(corners);
                for _ in 0..30 {
                    let s = rng.bary_inside();
                    let p = patch.eval(s.x * corners[0] + s.y * corners[1] + s.z * corners[2]);
                    assert!(bounds.contains(p, 0.0), "d={d}: {p} outside {bounds:?}");
                }
                if d > 0 {
                    let ratio = bounds.diagonal() / whole;
                    assert!(ratio < 0.5, "d={d}: sub box is {ratio} of the whole");
                }
            }
        }
    }
}
