//! Hahmann–Bonneau 2000: piecewise quintic G¹ interpolant, 4 Bézier triangles per face.

use crate::error::Result;
use crate::mesh::Mesh;
use crate::schemes::{ParamSpec, Params, SchemeSpec};
use crate::surface::Surface;

/// Registry entry.
pub const SPEC: SchemeSpec = SchemeSpec {
    name: "hb",
    summary: "Hahmann-Bonneau 2000 quintic G1 interpolant, 4-split (HB00)",
    params: &[ParamSpec {
        name: "alpha",
        default: "1",
        help: "interpolation parameter α of eq. 9 (1 = interpolate the vertices)",
    }],
    needs_closed_mesh: true,
    build,
};

fn build(_mesh: &Mesh, _params: &Params) -> Result<Surface> {
    todo!()
}
