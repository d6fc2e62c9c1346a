//! The bounds that say "equal up to rounding", named once with the reason for each value.
//!
//! A figure the construction makes exactly zero (a G¹ normal jump, a vertex interpolation
//! error, a G0 gap) is never exactly zero in f64: it is the rounding of a few dozen operations
//! on coordinates of size about the mesh's diagonal. These bounds sit a few decades above that
//! rounding and many decades below any genuine defect (a real G¹ break is ≥ 1e-4 rad on every
//! mesh smoothlab is measured on), so a test or a report comparison that uses them can fail only
//! for a real change. Scheme-specific thresholds (e.g. the blend's corner radius, the Piper
//! solve's dependent-row bound) stay with the code they belong to.

/// Vertex interpolation and G0 gaps, relative to the bounding-box diagonal: ~4500 ulps, the
/// rounding of evaluating a degree-≤14 net (de Casteljau, `O(d²)` operations per point).
pub const POSITION_REL: f64 = 1e-12;

/// Normal jumps across a joint the construction makes G¹ (rad): the angle between two normals
/// each computed from cross products of derivatives whose relative rounding is ~1e-13 after
/// the derivative scaling by the degree; the 1e-9 bound leaves four decades for ill-shaped
/// patches (skinny 4-split pieces, valence-16 vertices).
pub const NORMAL_RAD: f64 = 1e-9;

/// Curvature jumps (relative to the larger curvature) of joints the construction makes G²:
/// curvature needs second derivatives divided by the squared speed, so its rounding is about
/// the square root of the normal's in the worst patches measured.
pub const CURVATURE_REL: f64 = 1e-6;

/// A face-barycentric coordinate of a patch domain that is zero: domain corners are simple
/// fractions (0, 1/2, 1/3, …) computed in a few operations, so a coordinate on a face edge is
/// within a few ulps of 0 and any other is at least ~1e-3 away.
pub const DOMAIN_ZERO: f64 = 1e-12;

/// Guard against dividing by an exact zero or an underflowed value: any quantity a geometric
/// computation divides by passes it unless it is (numerically) nothing at all. Near-singular
/// systems are judged by scale-relative bounds beside their solvers, not by this.
pub const DIVISION_GUARD: f64 = 1e-300;

/// Asserts `|a − b| ≤ tol` (all `f64`), printing both values, the difference and the bound
/// (and an optional message) when it fails.
#[macro_export]
macro_rules! assert_near {
    ($a:expr, $b:expr, $tol:expr $(,)?) => {
        $crate::assert_near!($a, $b, $tol, "")
    };
    ($a:expr, $b:expr, $tol:expr, $($msg:tt)+) => {{
        let (a, b, tol): (f64, f64, f64) = ($a, $b, $tol);
        assert!(
            (a - b).abs() <= tol,
            "|{} − {}| = {:e} > {:e}: {} = {:e}, {} = {:e} {}",
            stringify!($a),
            stringify!($b),
            (a - b).abs(),
            tol,
            stringify!($a),
            a,
            stringify!($b),
            b,
            format_args!($($msg)+)
        );
    }};
}

#[cfg(test)]
mod tests {
    #[test]
    fn assert_near_passes_within_and_fails_beyond_the_bound() {
        crate::assert_near!(1.0, 1.0 + 1e-13, super::POSITION_REL);
        let beyond = std::panic::catch_unwind(|| crate::assert_near!(1.0, 1.1, 1e-3, "on {}", "x"));
        let message = *beyond
            .expect_err("0.1 > 1e-3")
            .downcast::<String>()
            .expect("text");
        assert!(
            message.contains("> 1e-3") && message.contains("on x"),
            "{message}"
        );
    }
}
