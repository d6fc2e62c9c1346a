//! Figures measured patch by patch: vertex interpolation and regularity.

use glam::DVec3;
use rayon::prelude::*;

use crate::surface::{Patch, Surface, UV_CORNERS};

/// Subdivisions per patch edge of the grid on which regularity is sampled
/// (`(n+1)(n+2)/2 = 45` points, corners and edges included).
pub const REGULARITY_GRID: usize = 8;

/// Largest `|S(corner) − vertex|` (absolute) over every patch corner that sits on a mesh
/// vertex; `None` if no corner does.
pub fn interpolation_error(
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
pub fn patch_regularity(patch: &Patch) -> f64 {
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

/// Smallest [`patch_regularity`] over all patches (`None` for an empty surface).
pub fn min_regularity(surface: &Surface) -> Option<f64> {
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
}
