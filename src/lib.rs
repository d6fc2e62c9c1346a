//! smoothlab: smooth surfaces from triangle meshes with the classical schemes of the
//! literature, ray-traced exactly and measured.
//!
//! Data flow (see ARCHITECTURE.md): [`mesh::Mesh`] → [`schemes::build`] → [`surface::Surface`] →
//! metrics, export, render.

pub mod app;
pub mod bezier;
pub mod blend;
pub mod budget;
pub mod error;
pub mod export;
pub mod files;
pub mod geom;
pub mod linalg;
pub mod mesh;
pub mod metrics;
pub mod render;
pub mod report;
pub mod schemes;
pub mod surface;
#[doc(hidden)]
pub mod testing;
pub mod tolerance;

pub use error::{Error, Result};
