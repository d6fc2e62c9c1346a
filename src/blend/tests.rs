//! Tests of [`BlendPatch`]: exact derivatives, corners, edges and bounds.

use super::*;
use crate::testing::Rng;
use glam::DVec2;

const FAMILIES: [WeightFamily; 5] = [
    WeightFamily::Nielson { power: 1 },
    WeightFamily::Nielson { power: 2 },
    WeightFamily::FangMann { t: 1 },
    WeightFamily::FangMann { t: 2 },
    WeightFamily::FangMann { t: 3 },
];

fn random_point(rng: &mut Rng) -> DVec3 {
    DVec3::new(rng.next_f64(), rng.next_f64(), rng.next_f64()) - 0.5
}

/// Three random cubics; the two sub-surfaces through each corner share that corner point
/// (as both families require), the third is free there.
fn random_blend(family: WeightFamily, seed: u64) -> BlendPatch {
    let mut rng = Rng::new(seed);
    let vertices = [DVec3::X, DVec3::Y, DVec3::Z];
    let subs = std::array::from_fn(|owner| {
        TriangleBezier::from_fn(3, |i, j, k| {
            let corner = [i, j, k].iter().position(|&n| n == 3);
            let jitter = 0.2 * random_point(&mut rng);
            match corner {
                Some(c) if c != owner => vertices[c],
                _ => {
                    (i as f64 * vertices[0] + j as f64 * vertices[1] + k as f64 * vertices[2]) / 3.0
                        + jitter
                }
            }
        })
    });
    BlendPatch::new(family, subs)
}

fn random_uv(rng: &mut Rng) -> (f64, f64) {
    let (u, v) = (rng.next_f64(), rng.next_f64());
    if u + v > 1.0 {
        (1.0 - u, 1.0 - v)
    } else {
        (u, v)
    }
}

/// Fourth-order central difference of `f` at 0 with step `h`.
fn derivative(f: impl Fn(f64) -> DVec3, h: f64) -> DVec3 {
    (-f(2.0 * h) + 8.0 * f(h) - 8.0 * f(-h) + f(-2.0 * h)) / (12.0 * h)
}

/// First derivatives against differences of `eval`, second derivatives against differences
/// of the jet's own first derivatives (fourth-order stencils with a step of 1/1000 of the
/// distance to the nearest edge, where the weights vary on the scale of that distance).
#[test]
fn jet_matches_differences_of_eval() {
    for (n, family) in FAMILIES.into_iter().enumerate() {
        let patch = random_blend(family, 17 + n as u64);
        let mut rng = Rng::new(3);
        for _ in 0..50 {
            let (u, v) = random_uv(&mut rng);
            if u < 0.05 || v < 0.05 || u + v > 0.95 {
                continue;
            }
            let h = 1e-3 * u.min(v).min(1.0 - u - v);
            let jet = patch.jet(u, v);
            let du = derivative(|d| patch.eval(u + d, v), h);
            let dv = derivative(|d| patch.eval(u, v + d), h);
            let duu = derivative(|d| patch.jet(u + d, v).du, h);
            let duv = derivative(|d| patch.jet(u, v + d).du, h);
            let dvv = derivative(|d| patch.jet(u, v + d).dv, h);
            let label = format!("{family:?} at ({u}, {v})");
            assert!((jet.p - patch.eval(u, v)).length() <= 1e-15, "{label}");
            for (name, got, want) in [
                ("du", jet.du, du),
                ("dv", jet.dv, dv),
                ("duu", jet.duu, duu),
                ("duv", jet.duv, duv),
                ("dvv", jet.dvv, dvv),
            ] {
                let err = (got - want).length() / want.length().max(1.0);
                assert!(err <= 1e-8, "{label}: {name} {got} vs {want} ({err:e})");
            }
        }
    }
}

/// A blend of three copies of one surface is that surface, derivatives included.
#[test]
fn blend_of_one_surface_is_that_surface() {
    let one = random_blend(WeightFamily::FangMann { t: 1 }, 5).sub_surfaces()[0].clone();
    for family in FAMILIES {
        let patch = BlendPatch::new(family, [one.clone(), one.clone(), one.clone()]);
        for (u, v) in [
            (0.2, 0.3),
            (0.0, 0.5),
            (1.0, 0.0),
            (1e-12, 1e-13),
            (0.4, 0.6),
        ] {
            let (a, b) = (patch.jet(u, v), one.jet(u, v));
            for (x, y) in [(a.p, b.p), (a.du, b.du), (a.dv, b.dv), (a.duu, b.duu)] {
                assert!(
                    (x - y).length() <= 1e-14,
                    "{family:?} ({u},{v}): {x} vs {y}"
                );
            }
        }
    }
}

/// On the edge b_i = 0 the blend is S_i; for Fang–Mann its derivatives are S_i's too up to
/// order t (first and second order for t ≥ 2). The fractions are dyadic so that the points
/// are exactly on the edge (`1 − u − v` exact): off it by one rounding, the (t+1)-th weight
/// derivative, which grows like `1/s^{t+1}` towards a corner, would show.
#[test]
fn edges_belong_to_their_owner() {
    for (n, family) in FAMILIES.into_iter().enumerate() {
        let patch = random_blend(family, 40 + n as u64);
        for s in [1.0 / 1024.0, 0.125, 0.5, 0.875, 1023.0 / 1024.0] {
            for owner in 0..3 {
                let uv = crate::surface::edge_uv((owner + 1) % 3, s);
                let (blend, sub) = (
                    patch.jet(uv.x, uv.y),
                    patch.sub_surfaces()[owner].jet(uv.x, uv.y),
                );
                let label = format!("{family:?} edge of {owner} at {s}");
                assert!((blend.p - sub.p).length() <= 1e-15, "{label}");
                if let WeightFamily::FangMann { t } = family {
                    assert!((blend.du - sub.du).length() <= 1e-14, "{label}");
                    assert!((blend.dv - sub.dv).length() <= 1e-14, "{label}");
                    if t >= 2 {
                        let err = (blend.duu - sub.duu)
                            .length()
                            .max((blend.duv - sub.duv).length())
                            .max((blend.dvv - sub.dvv).length());
                        // The owner's weight is one on the edge, but its second derivatives
                        // are sums of products whose terms grow like s^-2 (1e6 at s = 1/1024)
                        // and cancel: rounding of eps · 1e6.
                        assert!(err <= 1e-9, "{label}: second derivatives off by {err}");
                    }
                }
            }
        }
    }
}

/// Corners evaluate to the shared vertex, and nothing is NaN or infinite on the way there.
#[test]
fn corners_are_the_vertices_and_finite() {
    let vertices = [DVec3::X, DVec3::Y, DVec3::Z];
    let uv = crate::surface::UV_CORNERS;
    for (n, family) in FAMILIES.into_iter().enumerate() {
        let patch = random_blend(family, 70 + n as u64);
        for c in 0..3 {
            assert_eq!(
                patch.eval(uv[c].x, uv[c].y),
                vertices[c],
                "{family:?} corner {c}"
            );
            assert_eq!(
                patch.jet(uv[c].x, uv[c].y).p,
                vertices[c],
                "{family:?} corner {c}"
            );
            let centre = DVec2::splat(1.0 / 3.0);
            for e in 1..=300 {
                let r = 10f64.powf(-(e as f64));
                for towards in [centre, uv[(c + 1) % 3], uv[(c + 2) % 3]] {
                    let at = uv[c] + (towards - uv[c]) * r;
                    let jet = patch.jet(at.x, at.y);
                    let all = [jet.p, jet.du, jet.dv, jet.duu, jet.duv, jet.dvv];
                    assert!(
                        all.iter().all(|x| x.is_finite()),
                        "{family:?} corner {c}, r = {r:e}: {jet:?}"
                    );
                    assert!(patch.eval(at.x, at.y).is_finite());
                }
            }
        }
    }
}

/// The blend over random sub-triangles stays inside the bounds.
#[test]
fn bounds_contain_the_blend() {
    let mut rng = Rng::new(11);
    for (n, family) in FAMILIES.into_iter().enumerate() {
        let patch = random_blend(family, 90 + n as u64);
        let full = patch.control_bounds();
        for _ in 0..30 {
            let corners: [DVec2; 3] = std::array::from_fn(|_| {
                let (u, v) = random_uv(&mut rng);
                DVec2::new(u, v)
            });
            let bary = corners.map(|c| DVec3::new(1.0 - c.x - c.y, c.x, c.y));
            let bounds = patch.sub_triangle_bounds(bary);
            for _ in 0..40 {
                let (a, b) = random_uv(&mut rng);
                let at = corners[0] + a * (corners[1] - corners[0]) + b * (corners[2] - corners[0]);
                let p = patch.eval(at.x, at.y);
                assert!(
                    bounds.contains(p, 0.0),
                    "{family:?}: {p} outside {bounds:?}"
                );
                assert!(full.contains(p, 0.0));
            }
        }
    }
}

/// The Newton fast path gives the jet's position and tangents.
#[test]
fn point_and_tangents_match_the_jet() {
    let mut rng = Rng::new(8);
    for (n, family) in FAMILIES.into_iter().enumerate() {
        let patch = random_blend(family, 120 + n as u64);
        for _ in 0..100 {
            let (u, v) = random_uv(&mut rng);
            let jet = patch.jet(u, v);
            let (p, du, dv) = patch.point_and_tangents(u, v);
            let err = (p - jet.p)
                .length()
                .max((du - jet.du).length())
                .max((dv - jet.dv).length());
            assert!(
                err <= 1e-13 * (1.0 + jet.du.length()),
                "{family:?} ({u},{v}): {err:e}"
            );
        }
    }
}

/// The blend's partials agree with its jet up to order two, and its third-order partials
/// with differences of the jet's second derivatives.
#[test]
fn partials_match_the_jet() {
    let mut rng = Rng::new(21);
    for (n, family) in FAMILIES.into_iter().enumerate() {
        let patch = random_blend(family, 150 + n as u64);
        for _ in 0..30 {
            let (u, v) = random_uv(&mut rng);
            if u < 0.05 || v < 0.05 || u + v > 0.95 {
                continue;
            }
            let all = patch.partials(u, v, 5).expect("away from the corners");
            assert_eq!(all.len(), 21);
            let jet = patch.jet(u, v);
            let label = format!("{family:?} at ({u}, {v})");
            for (k, want) in [jet.p, jet.du, jet.dv, jet.duu, jet.duv, jet.dvv]
                .iter()
                .enumerate()
            {
                let err = (all[k] - *want).length() / want.length().max(1.0);
                assert!(err <= 1e-12, "{label}: partial {k} {} vs {want}", all[k]);
            }
            let h = 1e-3 * u.min(v).min(1.0 - u - v);
            let duuu = derivative(|d| patch.jet(u + d, v).duu, h);
            let dvvv = derivative(|d| patch.jet(u, v + d).dvv, h);
            for (got, want) in [(all[6], duuu), (all[9], dvvv)] {
                let err = (got - want).length() / want.length().max(1.0);
                assert!(err <= 1e-6, "{label}: third order {got} vs {want}");
            }
        }
    }
}
