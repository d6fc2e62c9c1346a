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

/// The G0 contract of every joint, relative to the bounding-box diagonal: two sides whose gap
/// exceeds `G0_GAP_REL · diag` do not meet (continuity order −1), and the renderer's root
/// tolerance stays below it so that a hit is never further from the surface than a joint's gap
/// may be.
pub const G0_GAP_REL: f64 = 1e-9;

/// Relative growth of a bound computed in f64 before it is compared with a computed distance
/// (the renderer's certified Newton: disk radii, Taylor remainders, root tolerances), so
/// that rounding in the bound's own computation can never exclude a true root.
pub const BOUND_GROWTH_REL: f64 = 1e-9;

/// Absolute growth added to such a bound (after [`BOUND_GROWTH_REL`]), for bounds that are
/// zero or underflow: distances are in the tracer's unit frame, so 1e-12 is ~4500 ulps of 1.
pub const BOUND_GROWTH_ABS: f64 = 1e-12;

/// A computed bound grown by its rounding: `bound · (1 + BOUND_GROWTH_REL) + BOUND_GROWTH_ABS`,
/// in that order of operations.
#[inline]
pub fn inflate(bound: f64) -> f64 {
    bound * (1.0 + BOUND_GROWTH_REL) + BOUND_GROWTH_ABS
}

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
    fn inflate_is_the_literal_arithmetic() {
        for bound in [0.0, 1e-300, 0.1, 1.0 / 3.0, 7.5, 1e12] {
            let literal = bound * (1.0 + 1e-9) + 1e-12;
            assert_eq!(
                super::inflate(bound).to_bits(),
                literal.to_bits(),
                "{bound}"
            );
        }
        assert!(super::inflate(1.0) > 1.0 && super::inflate(0.0) > 0.0);
    }

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
