//! The plane parametrization `x = ∪ x_i` of Construction 2.1 [UP §4]: 4n planar patches of
//! degree d around a vertex of valence n, regular and injective.
//!
//! Net (UP Fig. 4.1): sector `s` of the planar net spans the angles `(2s−1)π/n … (2s+1)π/n`;
//! with `W_s = (cos((2s−1)π/n), sin((2s−1)π/n))`, the vertex at ring `ρ`, position `t` is
//! `ρ W_s + t (W_{s+1} − W_s)`: ring ρ is the regular n-gon of circumradius ρ divided into ρ
//! steps per side, so each sector is an affine image of a lattice wedge. The coalesced rings
//! sit at the origin. For half-box splines (odd k) the dual points are the centroids of the
//! triangles of the Fig. 4.1 net of order k + 1 (UP §4: "we take the dual net of the control
//! net in Figure 4.1"), so only the n-gon's own dual points (k = 3) sit at the origin:
//! coalescing all `(k−1)/2` dual rings would make the planar ring patch flat to third order
//! along its inner boundary (Jacobian 0, measured). The surface's control net is coalesced
//! the same way ([`crate::schemes::gk::regular::ControlNet`]), so its ring matches this one.
//!
//! The 3n ring patches `x_{n+1..4n}` are the (half-)box-spline patches of this net over the
//! ring-2 triangles of each sector chart (`Δ(1,0)`, `∇(1,0)`, `Δ(1,1)`). The inner patch
//! `x_s` over `Δ(0,0)` takes its rows `0..=k` (counted from the edge `w_s w_{s+1}`) from the
//! polynomial of the ring patch over `∇(1,0)` continued across their common edge, hence a C^k
//! join [UP §4: "the outer rings are determined by the C^0-, C^1- and C^2-transition"]. The
//! rows `k+1..=d` are free; they are set by shrinking row k towards the origin: the point at
//! row `r`, fraction `τ` along the row, is `(d − r)/(d − k)` times row k (piecewise linearly
//! interpolated) at `τ`. On the edges `v w_s` this puts the free points evenly between the
//! origin and the row-k point, which lies on the ray of `w_s` by the mirror symmetry of the
//! net, so neighbouring inner patches share their edge (C^0) and the corner `b(d,0,0)` is the
//! origin. For k = 2 the single free point is `b = ½ b_row2 = (¼c₁ + c₃/12, (s₁ + s₃)/12)`
//! (UP prints `c₃/6`, which is not on the ray of `w_1` for n ≠ 6 and would break C^0).

use glam::{DMat2, DVec2, DVec3};

use crate::bezier::TriangleBezier;
use crate::schemes::gk::box_spline::{ControlSite, GridTriangle, grid_distance};
use crate::schemes::gk::sector::{SectorPoint, classify, sector_patch};

/// The ring triangles of a sector chart, in the order `x_{n+3s−2}, x_{n+3s−1}, x_{n+3s}`.
pub(crate) const RING_TRIANGLES: [GridTriangle; 3] = [
    GridTriangle {
        i: 1,
        j: 0,
        up: true,
    },
    GridTriangle {
        i: 1,
        j: 0,
        up: false,
    },
    GridTriangle {
        i: 1,
        j: 1,
        up: true,
    },
];

/// The planar net vertex of a sector point (before coalescing).
pub(crate) fn planar_vertex(point: SectorPoint, n: usize) -> DVec2 {
    match point {
        SectorPoint::Centre => DVec2::ZERO,
        SectorPoint::Net { ring, sector, t } => {
            let w = |s: usize| {
                let angle = (2.0 * s as f64 - 1.0) * std::f64::consts::PI / n as f64;
                DVec2::new(angle.cos(), angle.sin())
            };
            let (a, b) = (w(sector), w(sector + 1));
            ring as f64 * a + t as f64 * (b - a)
        }
    }
}

/// The planar control point at a site of the chart of sector 0: net vertices with rings
/// `≤ coalesced` at the origin (`k/2 − 1` rings for even k, UP Fig. 4.1; for odd k the
/// Fig. 4.1 net of order k + 1, i.e. `(k−1)/2` rings, whose triangle centroids are the dual
/// points). `None` for a point opposite the sector outside the coalesced rings.
fn planar_site(site: ControlSite, n: usize, k: usize) -> Option<DVec3> {
    let coalesced = if k.is_multiple_of(2) {
        k / 2 - 1
    } else {
        (k - 1) / 2
    };
    let vertex = |p: [i32; 2]| -> Option<DVec2> {
        let ring = grid_distance(p, [0, 0]) as usize;
        match classify(p, 0, n) {
            _ if ring <= coalesced => Some(DVec2::ZERO),
            SectorPoint::Centre => None,
            point => Some(planar_vertex(point, n)),
        }
    };
    let v = match site {
        ControlSite::Vertex(p) => vertex(p)?,
        ControlSite::Face(f) => {
            let [a, b, c] = f.corners().map(vertex);
            (a? + b? + c?) / 3.0
        }
    };
    Some(DVec3::new(v.x, v.y, 0.0))
}

/// One sector of the plane parametrization: the inner patch and the three ring patches.
#[derive(Clone, Debug)]
pub(crate) struct PlaneSector {
    /// `x_s` over `Δ(0,0)` (corners v, w_s, w_{s+1}).
    pub inner: TriangleBezier,
    /// The ring patches over [`RING_TRIANGLES`].
    pub ring: [TriangleBezier; 3],
}

/// The plane parametrization of sector 0 for valence `n` and order `k`; the other sectors
/// are its rotations by `2πs/n` ([`rotate`]).
pub(crate) fn plane_sector(n: usize, k: usize) -> PlaneSector {
    let patch = |t| {
        sector_patch(k, t, |site| planar_site(site, n, k))
            .expect("the ring patches' subnets reach only coalesced points opposite the sector")
    };
    let ring = RING_TRIANGLES.map(patch);
    let continuation = continue_into_inner(&ring[1]);
    PlaneSector {
        inner: shrink_free_rows(&continuation, k),
        ring,
    }
}

/// The polynomial of the ring patch over `∇(1,0)` (corners (1,0), (2,1), (1,1)) written over
/// the inner triangle `Δ(0,0)`, whose corners (0,0), (1,0), (1,1) have the barycentric
/// coordinates (1, −1, 1), (1, 0, 0), (0, 0, 1) there (blossoming, Farin CAGD §17.8).
pub(crate) fn continue_into_inner(ring_a: &TriangleBezier) -> TriangleBezier {
    ring_a.subdivide([DVec3::new(1.0, -1.0, 1.0), DVec3::X, DVec3::Z])
}

/// Replaces rows `k+1..=d` (counted from the edge opposite corner 0) by row k shrunk towards
/// the origin (see the module doc).
pub(crate) fn shrink_free_rows(patch: &TriangleBezier, k: usize) -> TriangleBezier {
    let d = patch.degree();
    let row_k = |tau: f64| {
        // Row k: points (k, d−k−l, l), l = 0..=d−k, at parameter l/(d−k).
        let span = (d - k) as f64;
        let x = tau * span;
        let l0 = (x.floor() as usize).min(d - k);
        let l1 = (l0 + 1).min(d - k);
        let f = x - l0 as f64;
        let p = |l: usize| patch.point(k, d - k - l);
        p(l0) * (1.0 - f) + p(l1) * f
    };
    TriangleBezier::from_fn(d, |i, j, l| {
        if i <= k {
            patch.point(i, j)
        } else if i == d {
            DVec3::ZERO
        } else {
            let tau = l as f64 / (d - i) as f64;
            row_k(tau) * ((d - i) as f64 / (d - k) as f64)
        }
    })
}

/// A planar patch rotated about the origin by `angle`.
pub(crate) fn rotate(patch: &TriangleBezier, angle: f64) -> TriangleBezier {
    let m = DMat2::from_angle(angle);
    patch.map_points(|p| {
        let q = m * DVec2::new(p.x, p.y);
        DVec3::new(q.x, q.y, p.z)
    })
}

#[cfg(test)]
mod tests {
    use std::f64::consts::PI;

    use super::*;
    use crate::schemes::gk::jets::lattice_jump;

    fn close(a: DVec3, b: DVec2) -> bool {
        (a.x - b.x).abs() < 1e-14 && (a.y - b.y).abs() < 1e-14 && a.z == 0.0
    }

    /// UP Figs. 4.2 and 4.3 (k = 2), with c_i = cos(iπ/n), s_i = sin(iπ/n): the corners of
    /// the ring (Loop limit points of the planar net), row 0 and row 2 of the inner patch,
    /// and the free point b (re-derived, see the module doc).
    #[test]
    fn k2_matches_figs_4_2_and_4_3() {
        for n in 3..=12 {
            let f = |i: f64| ((i * PI / n as f64).cos(), (i * PI / n as f64).sin());
            let ((c1, s1), (c3, s3)) = (f(1.0), f(3.0));
            let x = plane_sector(n, 2);
            let w1_limit = DVec2::new(c1 + c3 / 6.0, 2.0 / 3.0 * s1 + s3 / 6.0);
            let mirror = |p: DVec2| DVec2::new(p.x, -p.y);
            // ∇(1,0) = (1,0),(2,1),(1,1): its corner 2 is w_1; Δ(1,1) corner 2 is 2 w_1.
            assert!(close(x.ring[1].point(0, 0), w1_limit), "n = {n}");
            let outer = DVec2::new(2.0 * c1 + c3 / 6.0, 5.0 / 3.0 * s1 + s3 / 6.0);
            assert!(close(x.ring[2].point(0, 0), outer), "n = {n}");
            // Inner patch x_1 (v, w_0, w_1): b(i, j, l) with i the row from the outer edge.
            let inner = &x.inner;
            let expected = [
                ((0, 4), mirror(w1_limit)),
                (
                    (0, 3),
                    DVec2::new(c1 + c3 / 24.0, -(5.0 / 12.0 * s1 + s3 / 24.0)),
                ),
                ((0, 2), DVec2::new(c1, 0.0)),
                (
                    (0, 1),
                    DVec2::new(c1 + c3 / 24.0, 5.0 / 12.0 * s1 + s3 / 24.0),
                ),
                ((0, 0), w1_limit),
                ((2, 2), DVec2::new(0.5 * c1 + c3 / 6.0, -(s1 + s3) / 6.0)),
                ((2, 1), DVec2::new(0.5 * c1 + c3 / 12.0, 0.0)),
                ((2, 0), DVec2::new(0.5 * c1 + c3 / 6.0, (s1 + s3) / 6.0)),
                ((3, 0), DVec2::new(0.25 * c1 + c3 / 12.0, (s1 + s3) / 12.0)),
                ((4, 0), DVec2::ZERO),
            ];
            for ((i, j), p) in expected {
                assert!(
                    close(inner.point(i, j), p),
                    "n = {n}, b({i},{j}): {}",
                    inner.point(i, j)
                );
            }
        }
    }

    /// All 4n patches of every sector, rotated into place: (inner, ring) per sector.
    fn all_patches(n: usize, k: usize) -> Vec<(TriangleBezier, [TriangleBezier; 3])> {
        let x = plane_sector(n, k);
        (0..n)
            .map(|s| {
                let angle = 2.0 * PI * s as f64 / n as f64;
                (
                    rotate(&x.inner, angle),
                    x.ring.clone().map(|p| rotate(&p, angle)),
                )
            })
            .collect()
    }

    /// Joints: inner–ring and ring–ring C^k (in the lattice), inner–inner C^0 [UP Fig. 2.5].
    #[test]
    fn joints_are_c_k_and_inner_patches_c_0() {
        for k in 1..=4 {
            for n in 3..=12 {
                let x = plane_sector(n, k);
                let next = rotate(&x.ring[0], 2.0 * PI / n as f64);
                let joints = [
                    (&x.inner, 1, &x.ring[1], 2),
                    (&x.ring[0], 2, &x.ring[1], 0),
                    (&x.ring[1], 1, &x.ring[2], 0),
                    (&x.ring[2], 2, &next, 0),
                ];
                for (a, ea, b, eb) in joints {
                    for order in 0..=k {
                        let jump = lattice_jump(a, ea, b, eb, order);
                        assert!(
                            jump < 1e-13,
                            "k {k} n {n} edge {ea} order {order}: {jump:e}"
                        );
                    }
                }
                // x_1's edge v → w_1 (corner 0 → 2) is x_2's edge v → w_1 (corner 0 → 1).
                let d = x.inner.degree();
                let turned = rotate(&x.inner, 2.0 * PI / n as f64);
                for i in 0..=d {
                    let (p, q) = (x.inner.point(i, 0), turned.point(i, d - i));
                    assert!((p - q).length() < 1e-14, "k {k} n {n} edge point {i}");
                }
            }
        }
    }

    /// Regular: the Jacobian determinant is positive on a dense grid of every patch. Injective:
    /// additionally the outer boundary winds once around the origin with increasing angle,
    /// so the locally injective map of the disk is one-to-one (degree argument).
    #[test]
    fn plane_parametrization_is_regular_and_injective() {
        for k in 1..=4 {
            for n in 3..=12 {
                let patches = all_patches(n, k);
                let mut worst = f64::MAX;
                for (inner, ring) in &patches {
                    for p in std::iter::once(inner).chain(ring) {
                        let steps = 24;
                        for a in 0..=steps {
                            for b in 0..=steps - a {
                                let (u, v) = (a as f64 / steps as f64, b as f64 / steps as f64);
                                let jet = p.jet(u, v);
                                worst = worst.min(jet.du.x * jet.dv.y - jet.du.y * jet.dv.x);
                            }
                        }
                    }
                }
                assert!(worst > 0.0, "k {k} n {n}: Jacobian {worst}");
                // Outer boundary: edge 1 of Δ(1,0) and of Δ(1,1), sector by sector.
                let mut angles = Vec::new();
                for (_, ring) in &patches {
                    for p in [&ring[0], &ring[2]] {
                        for step in 0..32 {
                            let s = step as f64 / 32.0;
                            let q = p.eval(DVec3::new(0.0, 1.0 - s, s));
                            angles.push(q.y.atan2(q.x));
                        }
                    }
                }
                let mut turned = 0.0;
                for (i, a) in angles.iter().enumerate() {
                    let mut step = angles[(i + 1) % angles.len()] - a;
                    if step < -PI {
                        step += 2.0 * PI;
                    }
                    assert!(step > 0.0, "k {k} n {n}: boundary turns back at {i}");
                    turned += step;
                }
                assert!(
                    (turned - 2.0 * PI).abs() < 1e-12,
                    "k {k} n {n}: winds {turned}"
                );
                eprintln!("k {k} n {n}: min Jacobian {worst:.3e}");
            }
        }
    }
}
