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
    JointFigures, assert_g1_joints, closed_test_meshes, max_smoothness_defect_inside_faces, mesh,
    open_bunny, open_test_meshes, params, unit_icosphere_accuracy,
};
