//! smoothlab: smooth surfaces from triangle meshes with the classical schemes of the
//! literature, ray-traced exactly and measured.
//!
//! Data flow (see ARCHITECTURE.md): [`mesh::Mesh`] → [`schemes::build`] → [`surface::Surface`] →
//! [`metrics::Metrics`], [`export`], [`render::RenderJob::render`].
//!
//! ```
//! use smoothlab::mesh::{Mesh, generate};
//! use smoothlab::metrics::Metrics;
//!
//! let (positions, faces) = generate::icosahedron();
//! let (mesh, _report) = Mesh::from_triangles(positions, faces)?;
//! let surface = smoothlab::schemes::build("hb", &mesh, &[])?;
//! let metrics = Metrics::measure(&surface, &mesh, 0.0);
//! assert!(metrics.g1_max_rad.unwrap() < smoothlab::tolerance::NORMAL_RAD);
//! # Ok::<(), smoothlab::Error>(())
//! ```
//!
//! The `examples/` folder renders a zebra image from code the same way.

// Module docs describe the internals for maintainers and link to them; `cargo doc
// --document-private-items` renders those links.
#![allow(rustdoc::private_intra_doc_links)]

// The public API is the facade below: the modules a library user names (`mesh`, `schemes`,
// `surface`, `metrics`, `render`, `export`, `tolerance`) and the re-exports at this root;
// everything else is the crate's own (ARCHITECTURE.md, "Public API"; tests/public_api.rs).
mod app;
mod bezier;
mod blend;
mod budget;
mod error;
pub mod export;
mod files;
mod geom;
mod linalg;
pub mod mesh;
pub mod metrics;
mod progress;
pub mod render;
mod report;
pub mod schemes;
pub mod surface;
#[doc(hidden)]
pub mod testing;
mod text;
pub mod tolerance;

pub use bezier::{CurveBezier, TriangleBezier};
pub use error::{Error, Problem, Result};
pub use geom::Aabb;
pub use mesh::{LoadOptions, LoadReport, Mesh};
pub use metrics::Metrics;
pub use render::{Frame, RenderJob};
pub use surface::{Patch, Surface};

/// The command layer's entry for the `smoothlab` binary (`main.rs` parses a command line into
/// these arguments, calls one function per command and prints its [`cli::Output`]); not a
/// library interface.
#[doc(hidden)]
pub mod cli {
    pub use crate::app::commands::*;
    pub use crate::app::render::RenderArgs;
    pub use crate::app::view::{ViewArgs, ViewReport};
    pub use crate::app::{Output, clean_up_on_signals, limit_threads};
    pub use crate::progress::set_quiet;
}

/// A render job from scene keys: the scene file of the README's Contracts as a value
/// ([`SceneFile::parse`] of its TOML text), validated once into a [`render::RenderJob`] by
/// [`SceneFile::job`] with the errors naming the key at fault. The `render` command and the
/// Python package (`python/`) both make their jobs through it.
pub use app::scene::SceneFile;
