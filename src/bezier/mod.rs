//! Bézier curves and triangular Bézier patches of any degree, in f64.
//!
//! Conventions used everywhere in smoothlab (and in the JSON export of docs/guide/contracts.md): a triangular
//! patch of degree d has control points `b(i,j,k)`, `i+j+k = d`, stored with i from d down to 0,
//! then j from d−i down to 0. Corner `b(d,0,0)` is at barycentric (1,0,0). The patch is also
//! read as a map of `(u, v)` through the barycentric point `(1−u−v, u, v)`.
//!
//! [`triangle`] holds the patch type, its storage order and its evaluation (point, jet,
//! blossom); [`triangle_forms`] the other Bézier forms of the same patch (sub-triangle,
//! higher degree, boundary curves) and its bounds; [`curve`] the Bézier curves; [`hermite2d`]
//! Farin's 2-D cubic Hermite curves through points with tangents.

pub(crate) mod curve;
pub(crate) mod gram;
pub(crate) mod hermite2d;
pub(crate) mod triangle;
pub(crate) mod triangle_forms;

pub use curve::CurveBezier;
pub use triangle::TriangleBezier;

#[cfg(test)]
pub(crate) mod test_support;
