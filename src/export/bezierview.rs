//! BezierView (SurfLab, University of Florida) `.bv` files: one record per patch, type 3
//! (triangular Bézier patch):
//!
//! ```text
//! 3 <degree>
//! x y z          ← (d+1)(d+2)/2 control points, one per line
//! ```
//!
//! BezierView indexes a triangular net by rows of its third barycentric index: the point
//! with multi-index `(i, j, k)` is number `Σ_{m<k} (d+1−m) + j`, i.e. row k = 0 first (the
//! d+1 points of the edge opposite corner 2), j increasing along each row; for a cubic
//!
//! ```text
//!       9
//!      7 8
//!     4 5 6
//!    0 1 2 3
//! ```
//!
//! smoothlab writes its `b(i,j,k)` into BezierView's `(i,j,k)` slot (same roles of the three
//! barycentric coordinates), so the file lists `for k in 0..=d, for j in 0..=d−k: b(d−j−k, j, k)`:
//! `b(d,0,0), b(d−1,1,0), …, b(0,d,0)`, then the next row, …, `b(0,0,d)` last. The surface and
//! its parametrisation, hence its orientation, are the same as in smoothlab.

use std::fmt::Write;

use crate::bezier::TriangleBezier;
use crate::error::{Error, Result};
use crate::surface::Surface;

/// BezierView's record type for a triangular Bézier patch.
pub(crate) const TRIANGLE_RECORD: u32 = 3;

/// The control points of `b` in BezierView's order.
pub(crate) fn bezierview_order(b: &TriangleBezier) -> impl Iterator<Item = glam::DVec3> + '_ {
    let d = b.degree();
    (0..=d).flat_map(move |k| (0..=d - k).map(move |j| b.point(d - j - k, j)))
}

/// The `.bv` text of `surface`. Fails on a patch with no Bézier form, naming it and its face
/// as `input_face` numbers it.
pub(crate) fn to_bv(surface: &Surface, input_face: &dyn Fn(u32) -> usize) -> Result<String> {
    let mut out = String::new();
    for (index, patch) in surface.patches.iter().enumerate() {
        let bezier = patch.as_bezier().ok_or_else(|| {
            Error::Invalid(format!(
                "patch {index} (face {}, piece {}) is not polynomial; .bv needs Bézier patches",
                input_face(patch.face),
                patch.piece
            ))
        })?;
        // Writing into a String cannot fail.
        let _ = writeln!(out, "{TRIANGLE_RECORD} {}", bezier.degree());
        for p in bezierview_order(bezier) {
            let _ = writeln!(out, "{} {} {}", p.x, p.y, p.z);
        }
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::surface::{Patch, PatchGeometry};
    use glam::DVec3;

    /// A cubic whose point b(i,j,k) encodes its multi-index as (i, j, k).
    fn labelled_cubic() -> TriangleBezier {
        TriangleBezier::from_fn(3, |i, j, k| DVec3::new(i as f64, j as f64, k as f64))
    }

    /// BezierView's index of (i, j, k): Σ_{m<k} (d+1−m) + j (its `b2i_i`).
    fn bezierview_index(d: usize, j: usize, k: usize) -> usize {
        (0..k).map(|m| d + 1 - m).sum::<usize>() + j
    }

    #[test]
    fn points_are_in_bezierview_row_order() {
        let b = labelled_cubic();
        let written: Vec<DVec3> = bezierview_order(&b).collect();
        assert_eq!(written.len(), 10);
        for (n, p) in written.iter().enumerate() {
            let (i, j, k) = (p.x as usize, p.y as usize, p.z as usize);
            assert_eq!(i + j + k, 3);
            assert_eq!(bezierview_index(3, j, k), n, "point {n} is b({i},{j},{k})");
        }
        assert_eq!(written[0], DVec3::new(3.0, 0.0, 0.0));
        assert_eq!(written[3], DVec3::new(0.0, 3.0, 0.0));
        assert_eq!(written[9], DVec3::new(0.0, 0.0, 3.0));
    }

    #[test]
    fn records_have_header_and_points() {
        let patch = |b| Patch {
            face: 0,
            piece: 0,
            domain: crate::surface::WHOLE_FACE,
            geometry: PatchGeometry::Bezier(b),
        };
        let linear = TriangleBezier::new(1, vec![DVec3::ZERO, DVec3::X, DVec3::Y]);
        let surface = Surface {
            scheme: "test".into(),
            warnings: Vec::new(),
            spike_face_pairs: Vec::new(),
            params: vec![],
            patches: vec![patch(labelled_cubic()), patch(linear)],
        };
        let text = to_bv(&surface, &|t| t as usize).expect("polynomial patches");
        let lines: Vec<&str> = text.lines().collect();
        assert_eq!(lines.len(), 1 + 10 + 1 + 3);
        assert_eq!(lines[0], "3 3");
        assert_eq!(lines[1], "3 0 0");
        assert_eq!(lines[2], "2 1 0");
        assert_eq!(lines[10], "0 0 3");
        assert_eq!(lines[11], "3 1");
        assert_eq!(lines[12..], ["0 0 0", "1 0 0", "0 1 0"]);
    }
}
