//! Figures measured patch by patch: vertex interpolation, regularity and folds.

use glam::DVec3;
use rayon::prelude::*;

use crate::surface::{Patch, Surface, UV_CORNERS};

/// Subdivisions per patch edge of the grid on which regularity and folds are sampled.
pub(crate) const REGULARITY_GRID: usize = crate::surface::PATCH_GRID;

/// Largest `|S(corner) − vertex|` (absolute) over every patch corner that sits on a mesh
/// vertex; `None` if no corner does.
pub(crate) fn interpolation_error(
    surface: &Surface,
    faces: &[[u32; 3]],
    positions: &[DVec3],
) -> Option<f64> {
    surface
        .vertex_corners(faces)
        .iter()
        .map(|vc| {
            let uv = UV_CORNERS[vc.corner as usize];
            let p = surface.patches[vc.patch as usize].eval(uv.x, uv.y);
            (p - positions[vc.vertex as usize]).length()
        })
        .reduce(f64::max)
}

/// Regularity of one patch: `min |Su × Sv| / mean |Su × Sv|` over the sample grid. Scale
/// free (a small patch is not less regular than a big one) and 0 exactly where the
/// parametrisation is singular at a sample; 0 also for a patch that is singular everywhere.
pub(crate) fn patch_regularity(patch: &Patch) -> f64 {
    let n = REGULARITY_GRID;
    let (mut min, mut sum, mut count) = (f64::INFINITY, 0.0, 0usize);
    for i in 0..=n {
        for j in 0..=n - i {
            let (u, v) = (i as f64 / n as f64, j as f64 / n as f64);
            let area = patch.jet(u, v).cross().length();
            min = min.min(area);
            sum += area;
            count += 1;
        }
    }
    let mean = sum / count as f64;
    if mean > 0.0 { min / mean } else { 0.0 }
}

/// The folds of a surface: [`Patch::fold_samples`] over every patch, against the normal
/// `(P1 − P0) × (P2 − P0)` of its face.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub(crate) struct Folds {
    /// Samples where a patch's normal points against its face's normal.
    pub samples: usize,
    /// Patches with at least one such sample.
    pub patches: usize,
}

/// The [`Folds`] of `surface` over the mesh `faces` on `positions`.
pub(crate) fn folds(surface: &Surface, faces: &[[u32; 3]], positions: &[DVec3]) -> Folds {
    let per_patch: Vec<usize> = surface
        .patches
        .par_iter()
        .map(|patch| {
            let p = faces[patch.face as usize].map(|v| positions[v as usize]);
            patch.fold_samples((p[1] - p[0]).cross(p[2] - p[0]))
        })
        .collect();
    Folds {
        samples: per_patch.iter().sum(),
        patches: per_patch.iter().filter(|&&k| k > 0).count(),
    }
}

/// Smallest [`patch_regularity`] over all patches (`None` for an empty surface).
pub(crate) fn min_regularity(surface: &Surface) -> Option<f64> {
    let per_patch: Vec<f64> = surface.patches.par_iter().map(patch_regularity).collect();
    per_patch.into_iter().reduce(f64::min)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::bezier::TriangleBezier;
    use crate::surface::PatchGeometry;

    fn patch(points: Vec<DVec3>, degree: usize) -> Patch {
        Patch {
            face: 0,
            piece: 0,
            domain: crate::surface::WHOLE_FACE,
            geometry: PatchGeometry::Bezier(TriangleBezier::new(degree, points)),
        }
    }

    #[test]
    fn linear_patch_is_perfectly_regular() {
        let p = patch(
            vec![
                DVec3::ZERO,
                DVec3::new(3.0, 0.0, 0.0),
                DVec3::new(1.0, 2.0, 0.5),
            ],
            1,
        );
        // Constant |Su × Sv|: the ratio is one up to the rounding of the mean.
        let r = patch_regularity(&p);
        assert!((r - 1.0).abs() <= 1e-14, "{r}");
    }

    /// A quadratic whose two corner edges at corner 0 are parallel: Su × Sv = 0 at the corner,
    /// which is on the grid.
    #[test]
    fn singular_corner_gives_zero() {
        // b200 = 0, b110 = (1,0,0), b101 = (1,0,0): Su = 2(b110 − b200) and Sv = 2(b101 − b200)
        // are parallel at (u,v) = (0,0).
        let points = vec![
            DVec3::ZERO,               // b(2,0,0)
            DVec3::new(1.0, 0.0, 0.0), // b(1,1,0)
            DVec3::new(1.0, 0.0, 0.0), // b(1,0,1)
            DVec3::new(2.0, 0.0, 0.0), // b(0,2,0)
            DVec3::new(2.0, 1.0, 0.0), // b(0,1,1)
            DVec3::new(2.0, 2.0, 0.0), // b(0,0,2)
        ];
        let p = patch(points, 2);
        assert_eq!(p.jet(0.0, 0.0).cross(), DVec3::ZERO);
        assert_eq!(patch_regularity(&p), 0.0);
    }

    /// The plane quadratic over the face (0,0,0), (1,0,0), (0,1,0) whose edge point
    /// `b(0,1,1)` is at `(x, x, 0)` (the face itself at x = 1/2). Its Jacobian on the far edge
    /// `u + v = 1` is `x` (up to a positive factor), so for x < 0 the patch turns over there.
    fn pulled_quadratic(x: f64) -> Patch {
        let points = vec![
            DVec3::ZERO,               // b(2,0,0)
            DVec3::new(0.5, 0.0, 0.0), // b(1,1,0)
            DVec3::new(0.0, 0.5, 0.0), // b(1,0,1)
            DVec3::new(1.0, 0.0, 0.0), // b(0,2,0)
            DVec3::new(x, x, 0.0),     // b(0,1,1)
            DVec3::new(0.0, 1.0, 0.0), // b(0,0,2)
        ];
        patch(points, 2)
    }

    #[test]
    fn patch_over_its_face_has_no_fold_and_a_turned_patch_has() {
        let up = DVec3::Z;
        assert_eq!(pulled_quadratic(0.5).fold_samples(up), 0);
        assert_eq!(pulled_quadratic(0.1).fold_samples(up), 0);
        // Just past the edge: the 9 samples of the far edge turn over.
        assert_eq!(pulled_quadratic(-0.01).fold_samples(up), 9);
        // Pulled far back: all but the 6 samples nearest corner b(2,0,0).
        assert_eq!(pulled_quadratic(-1.0).fold_samples(up), 39);
        // Seen against the face's normal, the face itself is turned everywhere.
        let grid = (REGULARITY_GRID + 1) * (REGULARITY_GRID + 2) / 2;
        assert_eq!(pulled_quadratic(0.5).fold_samples(-up), grid);
    }
}
