//! The boundary-curve network of a surface — the images of the mesh edges — and how much it
//! undulates [HB00 §3 Fig. 2, §9 Fig. 14].
//!
//! Every mesh edge `a → b` is sampled on the surface of one of its faces, `C(t) = S(a + t(b−a))`
//! in that face's domain, so the measure works for every scheme (polynomial or not). Its bending
//! is read in the *chord plane*: the plane through the chord `b − a` that contains the surface
//! normal at the curve's midpoint. With `m` the unit normal of that plane and
//! `κ(t) = (C' × C'')·m / |C'|³` the signed curvature of the curve in it:
//!
//! * **undulation** `(∫|κ| ds − |∫κ ds|) / 2` — the turning, in radians, against the curve's
//!   overall sense of bending. Zero for a curve that bends one way only; an S or a bump-and-dip
//!   makes it positive. Continuous in the surface, no threshold.
//! * **inflections** — sign changes of `κ` between samples where `|κ|` is significant (at least
//!   `1e-3` of the edge's largest `|κ|` and at least `1e-6 / chord`), so numerically straight
//!   curves count none.
//! * **chord deviation** — largest distance of the curve from the chord segment, relative to the
//!   chord length.
//!
//! Integrals use the midpoint rule with [`NETWORK_SAMPLES`] samples per edge.

use glam::{DVec2, DVec3};
use rayon::prelude::*;
use serde::Serialize;

use crate::mesh::Mesh;
use crate::surface::Surface;

/// Samples per mesh edge.
pub(crate) const NETWORK_SAMPLES: usize = 64;

/// Figures of one boundary curve.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub(crate) struct CurveUndulation {
    /// Turning against the overall bending (rad).
    pub undulation_rad: f64,
    /// Sign changes of the signed curvature.
    pub inflections: usize,
    /// Largest distance from the chord, relative to the chord length.
    pub chord_deviation_rel: f64,
}

/// Figures of the whole network (maxima and totals over the mesh edges).
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize)]
pub struct NetworkUndulation {
    /// Mesh edges measured.
    pub edges: usize,
    /// Largest undulation of one curve (rad).
    pub undulation_max_rad: f64,
    /// Sum of the undulations (rad).
    pub undulation_total_rad: f64,
    /// Largest number of inflections of one curve.
    pub inflections_max: usize,
    /// Curves with at least one inflection.
    pub curves_with_inflections: usize,
    /// Largest chord deviation (relative to the chord).
    pub chord_deviation_max_rel: f64,
}

/// The curve of mesh edge `a → b` sampled on the surface of `face`: positions, first and
/// second derivatives with respect to the edge parameter t.
fn edge_samples(
    surface: &Surface,
    face_patches: &[Vec<u32>],
    mesh: &Mesh,
    face: u32,
    a: u32,
    b: u32,
) -> Option<Vec<(DVec3, DVec3, DVec3)>> {
    let corners = mesh.faces()[face as usize];
    let ca = corners.iter().position(|&v| v == a)?;
    let cb = corners.iter().position(|&v| v == b)?;
    let (ea, eb) = (unit(ca), unit(cb));
    (0..NETWORK_SAMPLES)
        .map(|i| {
            let t = (i as f64 + 0.5) / NETWORK_SAMPLES as f64;
            let (pi, uv) = surface.locate(face_patches, face, ea + t * (eb - ea))?;
            let patch = &surface.patches[pi as usize];
            let w: DVec2 = patch.uv_direction(eb - ea)?;
            let j = patch.jet(uv.x, uv.y);
            let d1 = j.du * w.x + j.dv * w.y;
            let d2 = j.duu * (w.x * w.x) + j.duv * (2.0 * w.x * w.y) + j.dvv * (w.y * w.y);
            Some((j.p, d1, d2))
        })
        .collect()
}

fn unit(c: usize) -> DVec3 {
    let mut e = [0.0; 3];
    e[c] = 1.0;
    DVec3::from_array(e)
}

/// Undulation figures of one sampled curve from `a` to `b` with surface normal `normal` at its
/// middle. `None` if the chord is degenerate or parallel to the normal.
pub(crate) fn curve_undulation(
    samples: &[(DVec3, DVec3, DVec3)],
    a: DVec3,
    b: DVec3,
    normal: DVec3,
) -> Option<CurveUndulation> {
    let chord = b - a;
    let length = chord.length();
    let m = chord.cross(normal).try_normalize()?;
    let dir = chord / length;
    let dt = 1.0 / samples.len() as f64;
    let kappa: Vec<(f64, f64)> = samples
        .iter()
        .map(|(_, d1, d2)| {
            let speed = d1.length();
            (d1.cross(*d2).dot(m) / speed.powi(3), speed * dt)
        })
        .collect();
    let (turning, abs_turning) = kappa.iter().fold((0.0, 0.0), |(t, at), (k, ds)| {
        (t + k * ds, at + k.abs() * ds)
    });
    let largest = kappa.iter().fold(0.0_f64, |m, (k, _)| m.max(k.abs()));
    let significant = (1e-3 * largest).max(1e-6 / length);
    let mut inflections = 0;
    let mut last_sign = 0.0;
    for (k, _) in &kappa {
        if k.abs() >= significant {
            if last_sign * k < 0.0 {
                inflections += 1;
            }
            last_sign = k.signum();
        }
    }
    let deviation = samples
        .iter()
        .map(|(p, _, _)| {
            let s = (*p - a).dot(dir).clamp(0.0, length);
            (*p - (a + s * dir)).length()
        })
        .fold(0.0, f64::max);
    Some(CurveUndulation {
        undulation_rad: 0.5 * (abs_turning - turning.abs()),
        inflections,
        chord_deviation_rel: deviation / length,
    })
}

/// Measures every mesh edge's curve on the surface.
pub fn network_undulation(surface: &Surface, mesh: &Mesh) -> NetworkUndulation {
    let face_patches = surface.patches_by_face(mesh.face_count());
    let per_edge: Vec<Option<CurveUndulation>> = mesh
        .edges()
        .par_iter()
        .map(|e| {
            let face = e.faces.0;
            let corners = mesh.faces()[face as usize];
            let ca = unit(corners.iter().position(|&v| v == e.a)?);
            let cb = unit(corners.iter().position(|&v| v == e.b)?);
            let jet_at = |bary: DVec3| {
                let (pi, uv) = surface.locate(&face_patches, face, bary)?;
                Some(surface.patches[pi as usize].jet(uv.x, uv.y))
            };
            let samples = edge_samples(surface, &face_patches, mesh, face, e.a, e.b)?;
            let normal = jet_at(0.5 * (ca + cb))?.normal();
            curve_undulation(&samples, jet_at(ca)?.p, jet_at(cb)?.p, normal)
        })
        .collect();
    let mut out = NetworkUndulation::default();
    for c in per_edge.iter().flatten() {
        out.edges += 1;
        out.undulation_max_rad = out.undulation_max_rad.max(c.undulation_rad);
        out.undulation_total_rad += c.undulation_rad;
        out.inflections_max = out.inflections_max.max(c.inflections);
        out.curves_with_inflections += usize::from(c.inflections > 0);
        out.chord_deviation_max_rel = out.chord_deviation_max_rel.max(c.chord_deviation_rel);
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Samples of a planar curve y(x) over x ∈ [0, 1] in the plane z = 0 (normal +y at the
    /// middle, so the chord plane is the xy plane).
    fn graph(y: impl Fn(f64) -> (f64, f64, f64)) -> Vec<(DVec3, DVec3, DVec3)> {
        (0..NETWORK_SAMPLES)
            .map(|i| {
                let x = (i as f64 + 0.5) / NETWORK_SAMPLES as f64;
                let (v, d, dd) = y(x);
                (
                    DVec3::new(x, v, 0.0),
                    DVec3::new(1.0, d, 0.0),
                    DVec3::new(0.0, dd, 0.0),
                )
            })
            .collect()
    }

    #[test]
    fn an_arc_does_not_undulate_and_a_wave_does() {
        let arc = graph(|x| (x * (1.0 - x), 1.0 - 2.0 * x, -2.0));
        let c = curve_undulation(&arc, DVec3::ZERO, DVec3::X, DVec3::Y).unwrap();
        assert_eq!(c.inflections, 0);
        assert!(c.undulation_rad < 1e-12, "{}", c.undulation_rad);
        assert!((c.chord_deviation_rel - 0.25).abs() < 1e-3);

        // y = 0.05 sin(3πx): two inflections, turning against the overall sense.
        let k = 3.0 * std::f64::consts::PI;
        let wave = graph(|x| {
            (
                0.05 * (k * x).sin(),
                0.05 * k * (k * x).cos(),
                -0.05 * k * k * (k * x).sin(),
            )
        });
        let w = curve_undulation(&wave, DVec3::ZERO, DVec3::X, DVec3::Y).unwrap();
        assert_eq!(w.inflections, 2);
        assert!(w.undulation_rad > 0.3, "{}", w.undulation_rad);
    }

    #[test]
    fn a_straight_curve_has_no_inflections() {
        let line = graph(|_| (0.0, 0.0, 0.0));
        let c = curve_undulation(&line, DVec3::ZERO, DVec3::X, DVec3::Y).unwrap();
        assert_eq!(c.inflections, 0);
        assert_eq!(c.undulation_rad, 0.0);
        assert_eq!(c.chord_deviation_rel, 0.0);
    }
}
