//! Test support shared by the unit tests, the end-to-end tests in `tests/` and the benchmarks:
//! one seeded generator ([`Rng`]), the meshes the schemes are measured on ([`schemes`]) and
//! small surfaces with known geometry that do not depend on a scheme ([`surfaces`]).
//!
//! Not part of the library's interface: its functions panic on failure, as tests want.

pub mod rng;
pub mod schemes;
pub mod surfaces;

pub use rng::Rng;
pub use schemes::{
    JointFigures, assert_g1_joints, closed_test_meshes, creased,
    max_smoothness_defect_inside_faces, mesh, open_bunny, open_test_meshes, params, scene,
    sharp_vertex_kinds, the_warning, unit_icosphere_accuracy,
};

/// The command layer's functions that end-to-end tests and benchmarks call directly.
pub mod app {
    pub use crate::app::figure::render_figure;
    pub use crate::app::figure::spec::FigureSpec;
    pub use crate::app::gallery::{GalleryOptions, render_gallery_with};
    pub use crate::app::render::{RenderArgs, render_command};
    pub use crate::app::scene::SceneFile;
    pub use crate::app::turntable::{Animation, render_animation};
    pub use crate::app::{run_metrics, run_metrics_streaming};
}

/// The benchmark report and results page (`smoothlab report`), for the tests that check
/// what it writes.
pub mod report {
    pub use crate::report::{
        Report, TIMING_KEYS, TIMING_RUNS, analytic, benchmark_meshes, history, page, plots,
        provenance, read, schemes_covered, summary_line, trends, write,
    };
}

/// The renderer's internals that tests and benchmarks drive directly: the BVH, the tessellated
/// reference tracer, the samplers.
pub mod render {
    pub use crate::render::bvh::{PatchBvh, SubdivisionCriterion};
    pub use crate::render::job::estimate_leaves;
    pub use crate::render::sampler::{sphere_direction, uniform};
    pub use crate::render::tessellate::TessellatedTracer;
}

/// The label text of figures and legends.
pub mod text {
    pub use crate::text::*;
}
